//! Per-step cost of the pebble collider in rapier3d: the project's `HullShape` (exact facets, O(1)
//! bounds, hill-climbing support) against parry's `ConvexPolyhedron` (bounds and support points
//! scan every hull point), on synthetic pebbles of ~10² to 3·10⁴ hull corners, same run and
//! initial conditions (the scenario and what is timed: `experiments/readme/collider_step_cost.md`).
//!
//! Run: `cargo experiment collider_step_cost` → `results/collider_step_cost/`.

use parry3d::math::{Pose, Real, Rotation, Vector};
use parry3d::shape::{ConvexPolyhedron, PolygonalFeature, PolygonalFeatureMap, Shape, SupportMap};
use rand::{RngExt, SeedableRng};
use rand_distr::StandardNormal;
use rand_xoshiro::Xoshiro256PlusPlus;
use rapier3d::prelude::{ColliderBuilder, MassProperties, PhysicsWorld, RigidBodyBuilder, SharedShape};
use rocking_stones::dynamics::engine::hull_shape::HullShape;
use rocking_stones::hull::{Polyhedron, DEFAULT_COPLANAR_TOL};
use rocking_stones::prelude::*;
use rocking_stones::solid;
use serde_json::json;
use std::hint::black_box;
use std::time::Instant;

use experiments::harness;
use harness::{fixed, Context, Result, Results};

/// Pebble generator point counts, chosen for ~10², 10³, 10⁴ and 3·10⁴ hull corners (all points are
/// corners up to ~10³; the fraction drops for denser samplings of the rough surface).
const TARGETS: [usize; 4] = [100, 1_000, 12_500, 70_000];
const WARMUP_STEPS: usize = 60;
const TIMED_STEPS: usize = 1_500;
const REPEATS: usize = 5;
const QUERY_CALLS: usize = 20_000;

/// Mean µs per step after the warm-up, for one collider shape, and the body's final speed and
/// angular speed (to tell whether it has settled).
fn step_cost(shape: SharedShape, mass: MassProperties, start: Pose) -> (f64, f32, f32) {
    // Rapier's own world: default integration parameters, no hooks or events.
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, -9.81, 0.0);
    world.colliders.insert(ColliderBuilder::new(SharedShape::halfspace(Vector::Y)).friction(0.6).build());
    let h = world.bodies.insert(RigidBodyBuilder::dynamic().can_sleep(false).pose(start).build());
    let c = ColliderBuilder::new(shape).density(0.0).mass_properties(mass).friction(0.6).restitution(0.0).build();
    world.colliders.insert_with_parent(c, h, &mut world.bodies);
    (0..WARMUP_STEPS).for_each(|_| world.step());
    let t = Instant::now();
    (0..TIMED_STEPS).for_each(|_| world.step());
    let us = t.elapsed().as_secs_f64() * 1e6 / TIMED_STEPS as f64;
    (us, world.bodies[h].linvel().length(), world.bodies[h].angvel().length())
}

/// ns per call of world AABB, support point and support feature.
fn query_costs(shape: &(impl Shape + PolygonalFeatureMap), dirs: &[Vector], poses: &[Pose]) -> [f64; 3] {
    let time = |f: &mut dyn FnMut(usize)| {
        let t = Instant::now();
        for i in 0..QUERY_CALLS {
            f(i);
        }
        t.elapsed().as_secs_f64() * 1e9 / QUERY_CALLS as f64
    };
    let aabb = time(&mut |i| {
        black_box(shape.compute_aabb(black_box(&poses[i % poses.len()])));
    });
    let support = time(&mut |i| {
        black_box(shape.local_support_point(black_box(dirs[i % dirs.len()])));
    });
    let mut feature = PolygonalFeature::default();
    let feat = time(&mut |i| {
        shape.local_support_feature(black_box(dirs[i % dirs.len()]), &mut feature);
        black_box(&feature);
    });
    [aabb, support, feat]
}

/// One collider of one pebble: the hull's sizes, the fastest repeat's µs per step, the final
/// speed and spin, the query costs (ns) and the build time (ms).
struct Row {
    target: usize,
    sizes: [usize; 3],
    collider: &'static str,
    step_us: f64,
    last: (f32, f32),
    queries_ns: [f64; 3],
    build_ms: f64,
}

fn main() -> Result<()> {
    let common = harness::common_args("The per-step cost of `HullShape` against parry's `ConvexPolyhedron`.");
    let out = Results::open("collider_step_cost", &common)?;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(common.seed_or(2024));
    let mut unit = || {
        let mut g = || rng.sample::<f64, _>(StandardNormal) as Real;
        Vector::new(g(), g(), g()).normalize()
    };
    let dirs: Vec<Vector> = (0..4096).map(|_| unit()).collect();
    let poses: Vec<Pose> =
        (0..256).map(|_| Pose::from_parts(unit(), Rotation::from_scaled_axis(unit() * 2.0))).collect();
    // Released tilted: a fixed random orientation, lowest point 1 mm above the ground.
    let rot = Rotation::from_scaled_axis(unit() * 1.3);
    let ms = |t: Instant| t.elapsed().as_secs_f64() * 1e3;
    let mut rows = Vec::new();
    for target in TARGETS {
        let mesh = generate::pebble([1.0, 0.7, 0.5], 0.02, target, 1);
        let poly = Polyhedron::new(&mesh.vertices, DEFAULT_COPLANAR_TOL)?;
        let solid = solid::MassProperties::of(&mesh)?;
        let t = Instant::now();
        let ours = HullShape::new(&poly, &solid.center_of_mass, 1.0).with_solid_mass(&solid);
        let build_ours = ms(t);
        let t = Instant::now();
        let parry = ConvexPolyhedron::from_convex_hull(ours.points()).context("parry hull")?;
        let build_parry = ms(t);
        let sizes = [ours.num_vertices(), ours.num_facets(), parry.faces().len()];
        let down = rot.inverse() * -Vector::Y;
        let start = Pose::from_parts(Vector::new(0.0, ours.local_support_point(down).dot(down) + 1e-3, 0.0), rot);
        let mass = ours.mass_properties(1.0);
        let shapes = [SharedShape::new(ours.clone()), SharedShape::new(parry.clone())];
        let (mut times, mut last) = ([f64::INFINITY; 2], [(0.0, 0.0); 2]);
        // Interleaved repeats, so both colliders see the same machine load (rapier is
        // deterministic: every repeat runs the same trajectory); the fastest counts, since load
        // on a shared machine only ever adds time.
        for _ in 0..REPEATS {
            for (k, shape) in shapes.iter().enumerate() {
                let (us, speed, spin) = step_cost(shape.clone(), mass, start);
                (times[k], last[k]) = (times[k].min(us), (speed, spin));
            }
        }
        let best = |f: &dyn Fn() -> [f64; 3]| {
            (0..REPEATS).map(|_| f()).fold([f64::INFINITY; 3], |a, b| std::array::from_fn(|i| a[i].min(b[i])))
        };
        let queries = [best(&|| query_costs(&ours, &dirs, &poses)), best(&|| query_costs(&parry, &dirs, &poses))];
        let builds = [build_ours, build_parry];
        for (k, collider) in ["HullShape", "ConvexPolyhedron"].into_iter().enumerate() {
            let (step_us, queries_ns, build_ms) = (times[k], queries[k], builds[k]);
            println!("{:>6} corners  {collider:<16} {step_us:>8.2} µs/step, queries {queries_ns:.1?} ns", sizes[0]);
            rows.push(Row { target, sizes, collider, step_us, last: last[k], queries_ns, build_ms });
        }
    }
    let sizes = |r: &Row| r.sizes.map(|n| n.to_string());
    out.csv(
        "step_cost.csv",
        &"target_points,hull_corners,hull_facets,parry_faces,collider,us_per_step,aabb_ns,support_point_ns,\
          support_feature_ns,build_ms,final_speed,final_spin"
            .split(',')
            .collect::<Vec<_>>(),
        rows.iter().map(|r| {
            let mut v = vec![r.target.to_string()];
            v.extend(sizes(r));
            v.extend([r.collider.into(), fixed(r.step_us, 3)]);
            v.extend(r.queries_ns.map(|x| fixed(x, 1)));
            v.extend([fixed(r.build_ms, 2), format!("{:.3e}", r.last.0), format!("{:.3e}", r.last.1)]);
            v
        }),
    )?;
    let (ours, theirs): (Vec<&Row>, Vec<&Row>) = rows.iter().partition(|r| r.collider == "HullShape");
    let (first, last, pfirst, plast) = (ours[0], ours[ours.len() - 1], theirs[0], theirs[theirs.len() - 1]);
    let f2 = |x: f64| fixed(x, 2);
    out.readme(
        include_str!("readme/collider_step_cost.md"),
        json!({
            "timed_steps": TIMED_STEPS, "warmup_steps": WARMUP_STEPS, "repeats": REPEATS,
            "rows": rows.iter().map(|r| json!({
                "sizes": sizes(r), "collider": r.collider, "step_us": f2(r.step_us),
                "queries": r.queries_ns.map(|x| fixed(x, 1)), "build_ms": fixed(r.build_ms, 1),
                "speed": format!("{:.0e}", r.last.0), "spin": format!("{:.0e}", r.last.1),
            })).collect::<Vec<_>>(),
            "ratios": ours.iter().zip(&theirs).map(|(a, b)| json!({
                "corners": a.sizes[0], "theirs_over_ours": f2(b.step_us / a.step_us),
                "ours": f2(a.step_us / ours[0].step_us), "theirs": f2(b.step_us / theirs[0].step_us),
            })).collect::<Vec<_>>(),
            "first": first.sizes[0], "last": last.sizes[0],
            "more": fixed(last.sizes[0] as f64 / first.sizes[0] as f64, 0),
            "ours": [f2(last.step_us / first.step_us), f2(first.step_us), f2(last.step_us)],
            "theirs": [f2(plast.step_us / pfirst.step_us), f2(pfirst.step_us), f2(plast.step_us)],
        }),
    )
}
