//! Speed of the static analysis: load → check → mass → hull → facets →
//! equilibria → Morse–Smale graph → hierarchy, on synthetic pebbles from 10³ to 10⁶ vertices
//! and on the 98k-vertex Bennu model. The hull is also timed against parry3d's quickhull on the
//! same points (f32, no exact predicates) as an in-run baseline; figures are reported as times
//! and as ratios to that baseline and to the smallest input.
//!
//! Run: `cargo run --release --example static_scaling` → `results/static_scaling/`.

use plotters::prelude::*;
use rocking_stones::equilibria::{Equilibria, Signs, DEFAULT_DEGENERACY_TOL};
use rocking_stones::generate;
use rocking_stones::hierarchy::cancellation_hierarchy;
use rocking_stones::hierarchy::Hierarchy;
use rocking_stones::hull::{convex_hull, Polyhedron, DEFAULT_COPLANAR_TOL};
use rocking_stones::mesh::io;
use rocking_stones::morse_smale::MorseSmaleGraph;
use rocking_stones::plot::{colors, draw_legend, legend_height, log_tick, series_color, style, Mark, FONT_FAMILY};
use rocking_stones::solid::MassProperties;
use rocking_stones::stats::log_fit;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

const STAGES: [&str; 9] = ["read", "check", "mass", "hull", "facets", "equilibria", "graph", "hierarchy", "total"];

struct Row {
    name: String,
    vertices: usize,
    hull_vertices: usize,
    micro: usize,
    seconds: [f64; 9],
    parry_hull: f64,
}

fn time<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let t = Instant::now();
    let x = f();
    (x, t.elapsed().as_secs_f64())
}

/// One timed pass of the pipeline over a mesh file.
fn pass(path: &Path) -> ([f64; 9], usize, usize, usize) {
    let mut s = [0.0; 9];
    let (mesh, t) = time(|| io::read(path).unwrap());
    s[0] = t;
    let ((mesh, _), t) = time(|| mesh.into_solid_boundary().unwrap());
    s[1] = t;
    let (mass, t) = time(|| MassProperties::of(&mesh).unwrap());
    s[2] = t;
    let (hull, t) = time(|| convex_hull(&mesh.vertices).unwrap());
    s[3] = t;
    let (poly, t) = time(|| Polyhedron::from_hull(&mesh.vertices, &hull, DEFAULT_COPLANAR_TOL).unwrap());
    s[4] = t;
    let g = mass.center_of_mass;
    let ((eq, signs), t) = time(|| {
        (Equilibria::new(&poly, &g, DEFAULT_DEGENERACY_TOL).unwrap(), Signs::new(&poly, &g, DEFAULT_DEGENERACY_TOL))
    });
    s[5] = t;
    let (graph, t) = time(|| MorseSmaleGraph::trace(&poly, &eq, &g, &signs).unwrap());
    s[6] = t;
    let (h, t): (Hierarchy, f64) = time(|| cancellation_hierarchy(&eq, &graph).unwrap());
    s[7] = t;
    let _ = h.plateau();
    s[8] = s[..8].iter().sum();
    (s, mesh.vertices.len(), poly.vertices.len(), eq.points.len())
}

fn parry_hull_seconds(path: &Path) -> f64 {
    let (mesh, _) = io::load_solid(path).unwrap();
    let c = mesh.vertices.iter().map(|p| p.coords).sum::<rocking_stones::Vec3>() / mesh.vertices.len() as f64;
    let pts: Vec<parry3d::math::Vector> = mesh
        .vertices
        .iter()
        .map(|p| parry3d::math::Vector::new((p.x - c.x) as f32, (p.y - c.y) as f32, (p.z - c.z) as f32))
        .collect();
    let (_, t) = time(|| parry3d::transformation::try_convex_hull(&pts).map(|h| h.1.len()).unwrap_or(0));
    t
}

fn measure(name: &str, path: &Path, reps: usize) -> Row {
    let mut best = [f64::INFINITY; 9];
    let mut info = (0, 0, 0);
    for _ in 0..reps {
        let (s, v, hv, m) = pass(path);
        for k in 0..9 {
            best[k] = best[k].min(s[k]);
        }
        info = (v, hv, m);
    }
    let parry = (0..reps).map(|_| parry_hull_seconds(path)).fold(f64::INFINITY, f64::min);
    eprintln!("{name}: {} vertices, total {:.3} s", info.0, best[8]);
    Row { name: name.into(), vertices: info.0, hull_vertices: info.1, micro: info.2, seconds: best, parry_hull: parry }
}

fn main() -> anyhow::Result<()> {
    let out = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("results/static_scaling");
    std::fs::create_dir_all(&out)?;
    let tmp = tempfile::tempdir()?;
    let mut rows = Vec::new();
    for n in [1_000usize, 3_000, 10_000, 30_000, 100_000, 300_000, 1_000_000] {
        let mesh = generate::pebble([1.0, 0.75, 0.5], 0.01, n, 1);
        let path = tmp.path().join(format!("pebble_{n}.ply"));
        io::write(&path, &mesh)?;
        let reps = if n >= 300_000 { 1 } else { 3 };
        rows.push(measure(&format!("pebble n={n}"), &path, reps));
    }
    let meshes = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/meshes");
    for f in [
        "asteroid_101955_bennu_osirisrex2019_bin.ply",
        "comet_67P_churyumov_gerasimenko_spc_shap5_bin.ply",
        "stone_quarry_ibois_E34_lowres_bin.ply",
    ] {
        let p = meshes.join(f);
        if p.exists() {
            rows.push(measure(f.trim_end_matches(".ply"), &p, 3));
        }
    }
    write_csv(&out.join("timings.csv"), &rows)?;
    plot(&out.join("scaling.png"), &rows)?;
    write_summary(&out.join("README.md"), &rows)?;
    Ok(())
}

fn write_csv(path: &Path, rows: &[Row]) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_path(path)?;
    let mut header = vec!["input", "vertices", "hull_vertices", "micro_equilibria"];
    header.extend(STAGES.iter().copied());
    header.push("parry_hull");
    w.write_record(&header)?;
    for r in rows {
        let mut rec = vec![r.name.clone(), r.vertices.to_string(), r.hull_vertices.to_string(), r.micro.to_string()];
        rec.extend(r.seconds.iter().map(|s| format!("{s:.6}")));
        rec.push(format!("{:.6}", r.parry_hull));
        w.write_record(&rec)?;
    }
    w.flush()?;
    Ok(())
}

/// Least-squares slope of log(time) against log(n) over the synthetic pebbles.
fn exponent(rows: &[Row], stage: usize) -> f64 {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.name.starts_with("pebble"))
        .map(|r| (r.vertices as f64, r.seconds[stage].ln()))
        .collect();
    log_fit(&pts).map_or(f64::NAN, |f| f.slope)
}

fn write_summary(path: &Path, rows: &[Row]) -> anyhow::Result<()> {
    let mut s = String::new();
    writeln!(s, "# Static analysis speed\n")?;
    writeln!(s, "Regenerate: `cargo run --release --example static_scaling`.\n")?;
    writeln!(s, "2-core machine, one thread; minimum of 3 runs, 1 run at n ≥ 3·10⁵. ![time per stage](scaling.png)\n")?;
    writeln!(s, "Synthetic pebbles: `generate::pebble([1, 0.75, 0.5], roughness 0.01, n, seed 1)`.\n")?;
    writeln!(s, "| input | vertices | hull vertices | micro-eq. | read | check | mass | hull | facets | equilibria | graph | hierarchy | **total** | hull / parry3d hull |")?;
    writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")?;
    for r in rows {
        write!(s, "| {} | {} | {} | {} |", r.name, r.vertices, r.hull_vertices, r.micro)?;
        for (k, t) in r.seconds.iter().enumerate() {
            if k == 8 {
                write!(s, " **{:.3} s** |", t)?;
            } else {
                write!(s, " {:.1} ms |", t * 1e3)?;
            }
        }
        writeln!(s, " {:.2} |", r.seconds[3] / r.parry_hull)?;
    }
    writeln!(s, "\nScaling exponents (slope of log time vs log n over the synthetic pebbles):\n")?;
    for (k, st) in STAGES.iter().enumerate() {
        let e = exponent(rows, k);
        writeln!(s, "- {st}: {}", if e.is_finite() { format!("n^{e:.2}") } else { "–".into() })?;
    }
    if let Some(b) = rows.iter().find(|r| r.name.contains("bennu")) {
        writeln!(
            s,
            "\nBennu (98 306 vertices): {:.3} s end to end (target: well under 1 s); {:.2}× the time of parry3d's f32 hull alone.",
            b.seconds[8],
            b.seconds[8] / b.parry_hull
        )?;
    }
    let first = &rows[0];
    let big = rows.iter().rfind(|r| r.name.starts_with("pebble")).unwrap();
    writeln!(
        s,
        "\nPer-vertex cost at n = {} is {:.2}× that at n = {} (1.0 = linear).",
        big.vertices,
        (big.seconds[8] / big.vertices as f64) / (first.seconds[8] / first.vertices as f64),
        first.vertices
    )?;
    std::fs::write(path, s)?;
    Ok(())
}

fn plot(path: &Path, rows: &[Row]) -> anyhow::Result<()> {
    rocking_stones::plot::draw_png(path, (900, 640), |root| {
        root.fill(&WHITE)?;
        let root =
            root.titled("Static analysis time per stage (synthetic pebbles, one thread)", (FONT_FAMILY, style::TITLE))?;
        let (legend, area) = root.split_vertically(legend_height(1));
        let peb: Vec<&Row> = rows.iter().filter(|r| r.name.starts_with("pebble")).collect();
        // stages drawn: mass … hierarchy in the series colours, the total in black, parry3d dashed grey.
        let color = |k: usize| if k == 8 { BLACK } else { series_color(k - 2) };
        let mut entries: Vec<(Mark, String)> = (2..9).map(|k| (Mark::Line(color(k)), STAGES[k].to_string())).collect();
        entries.push((Mark::Dashed(colors::GREY), "parry3d hull (f32 baseline)".into()));
        draw_legend(&legend, &entries).map_err(|e| anyhow::anyhow!(e.to_string()))?;
        let all = peb.iter().flat_map(|r| r.seconds[2..].iter().copied().chain([r.parry_hull])).filter(|&t| t > 0.0);
        let (lo, hi) = all.fold((f64::INFINITY, 0.0f64), |(lo, hi), t| (lo.min(t), hi.max(t)));
        let (lo, hi) = (10f64.powf((lo * 0.8).log10().floor()), 10f64.powf((hi * 1.25).log10().ceil()));
        let mut chart = ChartBuilder::on(&area)
            .margin(20)
            .margin_top(10)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d((5e2f64..2e6).log_scale(), (lo..hi).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("mesh vertices (log scale)")
            .y_desc("time (s, log scale)")
            .x_label_formatter(&|x: &f64| log_tick(*x))
            .y_label_formatter(&|y: &f64| log_tick(*y))
            .label_style((FONT_FAMILY, style::TICK))
            .axis_desc_style((FONT_FAMILY, style::AXIS))
            .draw()?;
        chart.draw_series(DashedLineSeries::new(
            peb.iter().map(|r| (r.vertices as f64, r.parry_hull.max(lo))),
            8,
            5,
            colors::GREY.stroke_width(style::LINE),
        ))?;
        for k in 2..9 {
            let width = if k == 8 { style::LINE + 1 } else { style::LINE };
            chart.draw_series(LineSeries::new(
                peb.iter().map(|r| (r.vertices as f64, r.seconds[k].max(lo))),
                color(k).stroke_width(width),
            ))?;
        }
        Ok(())
    })?;
    Ok(())
}
