//! Per-step cost of the pebble collider in rapier3d (the per-step cost cliff): the
//! project's `HullShape` (exact facets, O(1) bounds, hill-climbing support) against parry's
//! `ConvexPolyhedron` (`ColliderBuilder::convex_hull`: bounds and support points scan every hull
//! point), on synthetic pebbles with ~10², 10³, 10⁴ and 3·10⁴ hull corners, same run, same
//! initial conditions, same (solid) mass properties.
//!
//! Scenario per size and collider: the pebble is released just above a half-space ground in a
//! tilted orientation, never allowed to sleep, and stepped at dt = 1/60 s; it rolls and rocks
//! (small hulls come to rest within the run, the smooth large ones keep rolling). The mean wall time of `PhysicsPipeline::step` over the steps after a short
//! warm-up is the figure (fastest of several repeats). The per-call cost of the three shape
//! queries on the hot path (world AABB, support point, support feature) is timed separately.
//!
//! Run: `cargo run --release --example collider_step_cost` → `results/collider_step_cost/`
//! (`step_cost.csv`, `README.md`).

use parry3d::math::{Pose, Real, Rotation, Vector};
use parry3d::shape::{ConvexPolyhedron, PolygonalFeature, PolygonalFeatureMap, Shape, SupportMap};
use rand::{RngExt, SeedableRng};
use rand_distr::StandardNormal;
use rand_xoshiro::Xoshiro256PlusPlus;
use rapier3d::prelude::{
    CCDSolver, ColliderBuilder, ColliderSet, DefaultBroadPhase, ImpulseJointSet, IntegrationParameters, IslandManager,
    MassProperties, MultibodyJointSet, NarrowPhase, PhysicsPipeline, RigidBodyBuilder, RigidBodySet, SharedShape,
    SoftBodySet,
};
use rocking_stones::dynamics::engine::hull_shape::HullShape;
use rocking_stones::generate;
use rocking_stones::hull::{Polyhedron, DEFAULT_COPLANAR_TOL};
use rocking_stones::solid;
use std::fmt::Write as _;
use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

/// Pebble generator point counts, chosen for ~10², 10³, 10⁴ and 3·10⁴ hull corners (all points are
/// corners up to ~10³; the fraction drops for denser samplings of the rough surface).
const TARGETS: [usize; 4] = [100, 1_000, 12_500, 70_000];
const WARMUP_STEPS: usize = 60;
const TIMED_STEPS: usize = 1_500;
const REPEATS: usize = 5;
const QUERY_CALLS: usize = 20_000;

struct Pebble {
    target: usize,
    corners: usize,
    facets: usize,
    parry_faces: usize,
    hull_shape: HullShape,
    parry: ConvexPolyhedron,
    mass: MassProperties,
    build_hull_shape_ms: f64,
    build_parry_ms: f64,
}

fn pebble(target: usize) -> Pebble {
    let mesh = generate::pebble([1.0, 0.7, 0.5], 0.02, target, 1);
    let poly = Polyhedron::new(&mesh.vertices, DEFAULT_COPLANAR_TOL).unwrap();
    let solid = solid::MassProperties::of(&mesh).unwrap();
    let g = solid.center_of_mass;
    let t = Instant::now();
    let hull_shape = HullShape::new(&poly, &g, 1.0).with_solid_mass(&solid);
    let build_hull_shape_ms = t.elapsed().as_secs_f64() * 1e3;
    let t = Instant::now();
    let parry = ConvexPolyhedron::from_convex_hull(hull_shape.points()).expect("parry hull");
    let build_parry_ms = t.elapsed().as_secs_f64() * 1e3;
    Pebble {
        target,
        corners: hull_shape.num_vertices(),
        facets: hull_shape.num_facets(),
        parry_faces: parry.faces().len(),
        mass: hull_shape.mass_properties(1.0),
        hull_shape,
        parry,
        build_hull_shape_ms,
        build_parry_ms,
    }
}

/// Mean µs per step after the warm-up, for one collider shape, and the body's final speed and
/// angular speed (to tell whether it has settled).
fn step_cost(shape: SharedShape, mass: MassProperties, start: Pose) -> (f64, f32, f32) {
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    colliders.insert(ColliderBuilder::new(SharedShape::halfspace(Vector::Y)).friction(0.6).build());
    let h = bodies.insert(RigidBodyBuilder::dynamic().can_sleep(false).pose(start).build());
    let c = ColliderBuilder::new(shape).density(0.0).mass_properties(mass).friction(0.6).restitution(0.0).build();
    colliders.insert_with_parent(c, h, &mut bodies);
    let mut pipeline = PhysicsPipeline::new();
    let params = IntegrationParameters::default();
    let (mut islands, mut broad, mut narrow) = (IslandManager::new(), DefaultBroadPhase::new(), NarrowPhase::new());
    let (mut impulse_joints, mut multibody_joints) = (ImpulseJointSet::new(), MultibodyJointSet::new());
    let (mut soft_bodies, mut ccd) = (SoftBodySet::new(), CCDSolver::new());
    let mut step = |n: usize| {
        for _ in 0..n {
            pipeline.step(
                Vector::new(0.0, -9.81, 0.0),
                &params,
                &mut islands,
                &mut broad,
                &mut narrow,
                &mut bodies,
                &mut colliders,
                &mut impulse_joints,
                &mut multibody_joints,
                &mut soft_bodies,
                &mut ccd,
                &(),
                &(),
            );
        }
    };
    step(WARMUP_STEPS);
    let t = Instant::now();
    step(TIMED_STEPS);
    let us = t.elapsed().as_secs_f64() * 1e6 / TIMED_STEPS as f64;
    (us, bodies[h].linvel().length(), bodies[h].angvel().length())
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

/// The fastest repeat: on a shared machine, load only ever adds time.
fn fastest(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

struct Row {
    p_target: usize,
    corners: usize,
    facets: usize,
    parry_faces: usize,
    collider: &'static str,
    step_us: f64,
    final_speed: f32,
    final_spin: f32,
    queries_ns: [f64; 3],
    build_ms: f64,
}

fn main() -> anyhow::Result<()> {
    let out = Path::new("results/collider_step_cost");
    std::fs::create_dir_all(out)?;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(2024);
    let mut unit = || {
        let mut g = || rng.sample::<f64, _>(StandardNormal) as Real;
        Vector::new(g(), g(), g()).normalize()
    };
    let dirs: Vec<Vector> = (0..4096).map(|_| unit()).collect();
    let poses: Vec<Pose> =
        (0..256).map(|_| Pose::from_parts(unit(), Rotation::from_scaled_axis(unit() * 2.0))).collect();
    // Released tilted: a fixed random orientation, lowest point 1 mm above the ground.
    let rot = Rotation::from_scaled_axis(unit() * 1.3);

    let mut rows = Vec::new();
    for target in TARGETS {
        let p = pebble(target);
        let down = rot.inverse() * -Vector::Y;
        let depth = p.hull_shape.local_support_point(down).dot(down);
        let start = Pose::from_parts(Vector::new(0.0, depth + 1e-3, 0.0), rot);
        let shapes: [(&'static str, SharedShape, f64); 2] = [
            ("HullShape", SharedShape::new(p.hull_shape.clone()), p.build_hull_shape_ms),
            ("ConvexPolyhedron", SharedShape::new(p.parry.clone()), p.build_parry_ms),
        ];
        let mut times: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
        let mut finals = [(0.0, 0.0); 2];
        // Interleaved repeats, so both colliders see the same machine load (rapier is
        // deterministic: every repeat runs the same trajectory).
        for _ in 0..REPEATS {
            for (k, (_, shape, _)) in shapes.iter().enumerate() {
                let (us, speed, spin) = step_cost(shape.clone(), p.mass, start);
                times[k].push(us);
                finals[k] = (speed, spin);
            }
        }
        let best = |f: &dyn Fn() -> [f64; 3]| {
            (0..REPEATS).map(|_| f()).fold([f64::INFINITY; 3], |a, b| std::array::from_fn(|i| a[i].min(b[i])))
        };
        let queries =
            [best(&|| query_costs(&p.hull_shape, &dirs, &poses)), best(&|| query_costs(&p.parry, &dirs, &poses))];
        for (k, (name, _, build)) in shapes.iter().enumerate() {
            let row = Row {
                p_target: p.target,
                corners: p.corners,
                facets: p.facets,
                parry_faces: p.parry_faces,
                collider: name,
                step_us: fastest(&times[k]),
                final_speed: finals[k].0,
                final_spin: finals[k].1,
                queries_ns: queries[k],
                build_ms: *build,
            };
            println!(
                "{:>6} corners  {:<16} {:>8.2} µs/step  aabb {:>8.1} ns  support {:>8.1} ns  feature {:>8.1} ns",
                row.corners, row.collider, row.step_us, row.queries_ns[0], row.queries_ns[1], row.queries_ns[2]
            );
            rows.push(row);
        }
    }

    let mut csv = csv::Writer::from_path(out.join("step_cost.csv"))?;
    csv.write_record([
        "target_points",
        "hull_corners",
        "hull_facets",
        "parry_faces",
        "collider",
        "us_per_step",
        "aabb_ns",
        "support_point_ns",
        "support_feature_ns",
        "build_ms",
        "final_speed",
        "final_spin",
    ])?;
    for r in &rows {
        csv.write_record([
            r.p_target.to_string(),
            r.corners.to_string(),
            r.facets.to_string(),
            r.parry_faces.to_string(),
            r.collider.to_string(),
            format!("{:.3}", r.step_us),
            format!("{:.1}", r.queries_ns[0]),
            format!("{:.1}", r.queries_ns[1]),
            format!("{:.1}", r.queries_ns[2]),
            format!("{:.2}", r.build_ms),
            format!("{:.3e}", r.final_speed),
            format!("{:.3e}", r.final_spin),
        ])?;
    }
    csv.flush()?;

    let mut md = String::new();
    writeln!(md, "# Per-step cost of the pebble collider: `HullShape` vs parry `ConvexPolyhedron`\n")?;
    writeln!(
        md,
        "Generated by `cargo run --release --example collider_step_cost` (`experiments/collider_step_cost.rs`); \
         raw numbers in `step_cost.csv`.\n"
    )?;
    writeln!(
        md,
        "Synthetic pebbles `generate::pebble([1.0, 0.7, 0.5], 0.02, n, 1)`, collider about the solid's G with the \
         solid's mass properties (collider density 0). Each is released tilted, 1 mm above a half-space ground, \
         never allowed to sleep, dt = 1/60 s: it rolls and rocks (the smooth large hulls are still rolling at the end, \
         see the last column; rapier has no rolling resistance). `µs/step` is the mean wall time of \
         `PhysicsPipeline::step` over {TIMED_STEPS} steps after {WARMUP_STEPS} warm-up steps, fastest of {REPEATS} \
         interleaved repeats; the query columns are ns per call (fastest of {REPEATS}) of the shape queries on the hot path (world AABB \
         for a random pose, support point and support feature for random directions). `build ms` is \
         `HullShape::new` from the project's `Polyhedron` (hull already computed) and \
         `ConvexPolyhedron::from_convex_hull` including parry's own hull. Same run, same initial \
         conditions for both colliders. Wall-clock figures on a shared, loaded 2-core machine: single figures \
         vary by up to ±40 % between runs; the trend over hull sizes is the result.\n"
    )?;
    writeln!(
        md,
        "| hull corners | our facets | parry faces | collider | µs/step | AABB ns | support point ns | support feature ns | build ms | final speed, spin |"
    )?;
    writeln!(md, "|---:|---:|---:|---|---:|---:|---:|---:|---:|---|")?;
    for r in &rows {
        writeln!(
            md,
            "| {} | {} | {} | {} | {:.2} | {:.1} | {:.1} | {:.1} | {:.1} | {:.0e} m/s, {:.0e} rad/s |",
            r.corners,
            r.facets,
            r.parry_faces,
            r.collider,
            r.step_us,
            r.queries_ns[0],
            r.queries_ns[1],
            r.queries_ns[2],
            r.build_ms,
            r.final_speed,
            r.final_spin
        )?;
    }
    let ours: Vec<&Row> = rows.iter().filter(|r| r.collider == "HullShape").collect();
    let theirs: Vec<&Row> = rows.iter().filter(|r| r.collider == "ConvexPolyhedron").collect();
    writeln!(md, "\n## Ratios\n")?;
    writeln!(md, "| hull corners | ConvexPolyhedron / HullShape per step | HullShape vs smallest | ConvexPolyhedron vs smallest |")?;
    writeln!(md, "|---:|---:|---:|---:|")?;
    for (a, b) in ours.iter().zip(&theirs) {
        writeln!(
            md,
            "| {} | {:.2}× | {:.2}× | {:.2}× |",
            a.corners,
            b.step_us / a.step_us,
            a.step_us / ours[0].step_us,
            b.step_us / theirs[0].step_us
        )?;
    }
    let (first, last) = (ours[0], ours[ours.len() - 1]);
    let (pfirst, plast) = (theirs[0], theirs[theirs.len() - 1]);
    writeln!(md, "\n## Reading\n")?;
    writeln!(
        md,
        "* From {} to {} hull corners ({:.0}× more), `HullShape`'s step time changes by {:.2}× ({:.2} → {:.2} µs), \
         `ConvexPolyhedron`'s by {:.2}× ({:.2} → {:.2} µs).",
        first.corners,
        last.corners,
        last.corners as f64 / first.corners as f64,
        last.step_us / first.step_us,
        first.step_us,
        last.step_us,
        plast.step_us / pfirst.step_us,
        pfirst.step_us,
        plast.step_us
    )?;
    writeln!(
        md,
        "* The shape queries explain it: parry's world AABB and support point scan all points (O(n)), its support \
         feature scans all faces; `HullShape` transforms a precomputed local box (O(1)) and hill-climbs from a cube-map \
         start (a few neighbour scans), its feature is a facet at the support vertex."
    )?;
    writeln!(
        md,
        "* parry merges neighbouring triangles within ~1.5°: its face count is far below the exact facet count \
         (the micro-facets this project studies are gone), so its contact features are not our facets."
    )?;
    writeln!(
        md,
        "* The trajectories are not identical (different contact features, and `HullShape` never merges facets), \
         so part of the per-step difference at small sizes is solver work, not shape queries; how long a body \
         moves before it settles also changes the mean (steps at rest are cheaper: rapier recycles contacts)."
    )?;
    writeln!(
        md,
        "* The query timings use random directions and poses (cold caches for large hulls); in a simulation \
         successive queries are coherent, so the hill climb starts and stays in cache."
    )?;
    std::fs::write(out.join("README.md"), md)?;
    println!("wrote {}", out.display());
    Ok(())
}
