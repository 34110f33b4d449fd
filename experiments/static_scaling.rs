//! Speed of the static analysis stage by stage (load → check → mass → hull → facets → equilibria
//! → Morse–Smale graph → hierarchy) on synthetic pebbles of 10³ to 10⁶ vertices and on real
//! models, beside parry3d's f32 quickhull (no exact predicates) on the same points.
//!
//! Run: `cargo experiment static_scaling` → `results/static_scaling/`; the README's
//! prose is `experiments/readme/static_scaling.md`.

use rocking_stones::equilibria::{Equilibria, Signs, DEFAULT_DEGENERACY_TOL};
use rocking_stones::hierarchy::cancellation_hierarchy;
use rocking_stones::hull::{convex_hull, Polyhedron, DEFAULT_COPLANAR_TOL};
use rocking_stones::mesh::io;
use rocking_stones::morse_smale::MorseSmaleGraph;
use rocking_stones::plot::style;
use rocking_stones::prelude::*;
use rocking_stones::solid::MassProperties;
use rocking_stones::stats::{log_fit, min_max};
use serde_json::json;
use std::path::Path;
use std::time::Instant;

use experiments::harness;
use harness::{Result, Results};

const STAGES: [&str; 9] = ["read", "check", "mass", "hull", "facets", "equilibria", "graph", "hierarchy", "total"];

struct Row {
    name: String,
    vertices: usize,
    hull_vertices: usize,
    micro: usize,
    seconds: [f64; 9],
    parry_hull: f64,
}

/// One timed pass of the pipeline over a mesh file (no name, no parry3d time yet).
fn pass(path: &Path) -> Result<Row> {
    let mut s = [0.0; 9];
    let mut clock = Instant::now();
    let mut lap = |k: usize| {
        s[k] = clock.elapsed().as_secs_f64();
        clock = Instant::now();
    };
    let mesh = io::read(path)?;
    lap(0);
    let (mesh, _) = mesh.into_solid_boundary()?;
    lap(1);
    let mass = MassProperties::of(&mesh)?;
    lap(2);
    let hull = convex_hull(&mesh.vertices)?;
    lap(3);
    let poly = Polyhedron::from_hull(&mesh.vertices, &hull, DEFAULT_COPLANAR_TOL)?;
    let g = mass.center_of_mass;
    lap(4);
    let (eq, signs) =
        (Equilibria::new(&poly, &g, DEFAULT_DEGENERACY_TOL)?, Signs::new(&poly, &g, DEFAULT_DEGENERACY_TOL));
    lap(5);
    let graph = MorseSmaleGraph::trace(&poly, &eq, &g, &signs)?;
    lap(6);
    let h = cancellation_hierarchy(&eq, &graph)?;
    lap(7);
    let _ = h.plateau();
    s[8] = s[..8].iter().sum();
    let (vertices, hull_vertices, micro) = (mesh.vertices.len(), poly.vertices.len(), eq.points.len());
    Ok(Row { name: String::new(), vertices, hull_vertices, micro, seconds: s, parry_hull: f64::INFINITY })
}

fn parry_hull_seconds(path: &Path) -> Result<f64> {
    let (mesh, _) = io::load_solid(path)?;
    let c = mesh.vertices.iter().map(|p| p.coords).sum::<rocking_stones::Vec3>() / mesh.vertices.len() as f64;
    let pts: Vec<parry3d::math::Vector> = mesh
        .vertices
        .iter()
        .map(|p| parry3d::math::Vector::new((p.x - c.x) as f32, (p.y - c.y) as f32, (p.z - c.z) as f32))
        .collect();
    let t = Instant::now();
    let _ = parry3d::transformation::try_convex_hull(&pts).map(|h| h.1.len()).unwrap_or(0);
    Ok(t.elapsed().as_secs_f64())
}

/// The best of `reps` passes, stage by stage, and of `reps` parry3d hulls.
fn measure(name: &str, path: &Path, reps: usize) -> Result<Row> {
    let mut best = Row { name: name.into(), ..pass(path)? };
    for _ in 1..reps {
        let r = pass(path)?;
        best.seconds.iter_mut().zip(r.seconds).for_each(|(b, s)| *b = b.min(s));
    }
    for _ in 0..reps {
        best.parry_hull = best.parry_hull.min(parry_hull_seconds(path)?);
    }
    eprintln!("{name}: {} vertices, total {:.3} s", best.vertices, best.seconds[8]);
    Ok(best)
}

fn main() -> Result<()> {
    let common = harness::common_args("Time per stage of the static analysis against the mesh size.");
    let out = Results::open("static_scaling", &common)?;
    let seed = common.seed_or(1);
    let tmp = tempfile::tempdir()?;
    let mut rows = Vec::new();
    for n in [1_000usize, 3_000, 10_000, 30_000, 100_000, 300_000, 1_000_000] {
        let mesh = generate::pebble([1.0, 0.75, 0.5], 0.01, n, seed);
        let path = tmp.path().join(format!("pebble_{n}.ply"));
        io::write(&path, &mesh)?;
        rows.push(measure(&format!("pebble n={n}"), &path, if n >= 300_000 { 1 } else { 3 })?);
    }
    let meshes = harness::repo().join("data/meshes");
    for f in [
        "asteroid_101955_bennu_osirisrex2019_bin.ply",
        "comet_67P_churyumov_gerasimenko_spc_shap5_bin.ply",
        "stone_quarry_ibois_E34_lowres_bin.ply",
    ] {
        let p = meshes.join(f);
        if p.exists() {
            rows.push(measure(f.trim_end_matches(".ply"), &p, 3)?);
        }
    }
    let header: Vec<&str> = ["input", "vertices", "hull_vertices", "micro_equilibria"]
        .into_iter()
        .chain(STAGES)
        .chain(["parry_hull"])
        .collect();
    let counts = |r: &Row| [r.name.clone(), r.vertices.to_string(), r.hull_vertices.to_string(), r.micro.to_string()];
    out.csv(
        "timings.csv",
        &header,
        rows.iter().map(|r| {
            let times = r.seconds.iter().chain([&r.parry_hull]).map(|s| format!("{s:.6}"));
            counts(r).into_iter().chain(times).collect::<Vec<_>>()
        }),
    )?;
    let peb: Vec<&Row> = rows.iter().filter(|r| r.name.starts_with("pebble")).collect();
    plot(&out, &peb)?;
    // Least-squares slope of log(time) against log(n) over the synthetic pebbles.
    let exponent = |k: usize| {
        let pts: Vec<(f64, f64)> = peb.iter().map(|r| (r.vertices as f64, r.seconds[k].ln())).collect();
        log_fit(&pts).map_or(f64::NAN, |f| f.slope)
    };
    let (first, big) = (&rows[0], peb[peb.len() - 1]);
    let per_vertex = |r: &Row| r.seconds[8] / r.vertices as f64;
    out.readme(
        include_str!("readme/static_scaling.md"),
        json!({
            "rows": rows.iter().map(|r| {
                let stages = r.seconds[..8].iter().map(|t| format!("{:.1} ms", t * 1e3));
                let ends = [format!("**{:.3} s**", r.seconds[8]), format!("{:.2}", r.seconds[3] / r.parry_hull)];
                counts(r).into_iter().chain(stages).chain(ends).collect::<Vec<_>>()
            }).collect::<Vec<_>>(),
            "exponents": STAGES.iter().enumerate().map(|(k, st)| {
                let e = exponent(k);
                format!("{st}: {}", if e.is_finite() { format!("n^{e:.2}") } else { "–".into() })
            }).collect::<Vec<_>>(),
            "bennu": rows.iter().find(|r| r.name.contains("bennu")).map(|b| json!({
                "total": format!("{:.3}", b.seconds[8]),
                "ratio": format!("{:.2}", b.seconds[8] / b.parry_hull),
            })),
            "big": big.vertices,
            "first": first.vertices,
            "per_vertex": format!("{:.2}", per_vertex(big) / per_vertex(first)),
        }),
    )
}

/// Time of the stages mass … hierarchy and the total against n (log–log), parry3d's hull dashed.
fn plot(out: &Results, peb: &[&Row]) -> Result<()> {
    let (lo, hi) =
        min_max(peb.iter().flat_map(|r| r.seconds[2..].iter().copied().chain([r.parry_hull])).filter(|&t| t > 0.0));
    let (lo, hi) = (10f64.powf((lo * 0.8).log10().floor()), 10f64.powf((hi * 1.25).log10().ceil()));
    let curve = |f: &dyn Fn(&Row) -> f64| peb.iter().map(|r| (r.vertices as f64, f(r).max(lo))).collect::<Vec<_>>();
    let mut chart =
        Chart::new(Axis::log("mesh vertices (log scale)", 5e2, 2e6), Axis::log("time (s, log scale)", lo, hi))
            .title("Static analysis time per stage (synthetic pebbles, one thread)")
            .dashed(&curve(&|r| r.parry_hull), colors::GREY);
    // stages drawn: mass … hierarchy in the series colours, the total (series colour 6: black) wider.
    for (k, stage) in STAGES.iter().enumerate().skip(2) {
        let (c, width) = (series_color(k - 2), style::LINE + u32::from(k == 8));
        chart = chart.legend(Mark::Line(c), *stage).line_width(&curve(&|r| r.seconds[k]), c, width);
    }
    chart
        .legend(Mark::Dashed(colors::GREY), "parry3d hull (f32 baseline)")
        .save(&out.path("scaling.png"), (900, 640))?;
    Ok(())
}
