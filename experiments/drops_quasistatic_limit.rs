//! Drops at vanishing energy converge to the quasi-static basin probabilities
//! ([`rocking_stones::basins`]), and move away from them as the drop height and the restitution
//! grow (large faces gain).
//!
//! Bodies: a box 2 × 1.4 × 1 (six faces, unequal basins) and a synthetic pebble with micro-facets.
//! For each drop height (and restitution), N drops with the same seed; per flock and per facet:
//! KL divergence and χ² of the empirical distribution from the static one.
//!
//! Run: `cargo run --release --example drops_quasistatic_limit` → `results/drops_quasistatic_limit/`.

use plotters::prelude::*;
use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::certificate::CertificateMode;
use rocking_stones::dynamics::drops::montecarlo::{run_and_summarize, DropReport, RunHeader, FORMAT};
use rocking_stones::dynamics::drops::params::{DropParams, Launch};
use rocking_stones::dynamics::resting::RestingParams;
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::generate;
use rocking_stones::plot::{draw_legend, legend_height, log_tick, series_color, style, Mark, FONT_FAMILY};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const DROPS: u64 = 2000;
const HEIGHTS: [f64; 6] = [0.002, 0.01, 0.03, 0.1, 0.3, 1.0];
const RESTITUTIONS: [f64; 3] = [0.0, 0.3, 0.6];

struct Row {
    body: String,
    height: f64,
    restitution: f64,
    report: DropReport,
    seconds: f64,
}

fn main() -> anyhow::Result<()> {
    let out = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("results/drops_quasistatic_limit");
    std::fs::create_dir_all(&out)?;
    let bodies = [
        ("box 2x1.4x1", generate::cuboid(2.0, 1.4, 1.0)),
        ("pebble 1:0.72:0.5", generate::pebble([1.0, 0.72, 0.5], 0.02, 1500, 3)),
    ];
    let mut rows = Vec::new();
    for (name, mesh) in bodies {
        let (mesh, rep) = mesh.into_solid_boundary()?;
        let a = Analysis::of_solid(mesh, rep, &Options::default())?;
        let (nu, _) = a.macro_nu(&Options::default());
        let setup = Stone::new(&a, nu)?;
        eprintln!("{name}: quasi-static error ±{:.1e} ({})", setup.quasi_static().error, setup.quasi_static().method);
        for &e in &RESTITUTIONS {
            for &hgt in &HEIGHTS {
                let mut params = DropParams { launch: Launch::at_rest(hgt), sim: RestingParams::damped().sim };
                params.sim.contact.restitution = e;
                let header = RunHeader {
                    format: FORMAT.into(),
                    mesh: name.into(),
                    mesh_fingerprint: String::new(),
                    seed: 2024,
                    drops: DROPS,
                    params,
                    certificate: CertificateMode::Facet,
                    preset: None,
                    center_of_mass: None,
                    shard: rocking_stones::dynamics::drops::montecarlo::Shard::ALL,
                };
                let t = std::time::Instant::now();
                let (report, _) = run_and_summarize(&setup, &header);
                let seconds = t.elapsed().as_secs_f64();
                eprintln!(
                    "  e = {e}, height {hgt}: KL flocks {:.4}, facets {:.4} ({seconds:.1} s)",
                    report.fit_flocks.kl_divergence,
                    report.fit_facets.as_ref().map_or(f64::NAN, |f| f.kl_divergence)
                );
                rows.push(Row { body: name.into(), height: hgt, restitution: e, report, seconds });
            }
        }
    }
    let damping = damping_sweep()?;
    write_csv(&out.join("kl_vs_height.csv"), &rows)?;
    plot(&out.join("kl_vs_height.png"), &rows)?;
    write_box_faces(&out.join("box_faces.csv"), &rows)?;
    summary(&out.join("README.md"), &rows, &damping)?;
    Ok(())
}

/// The pebble at the lowest height and no restitution, for increasing damping (towards the
/// overdamped, quasi-static rolling): (damping, report).
fn damping_sweep() -> anyhow::Result<Vec<(f64, DropReport)>> {
    let (mesh, rep) = generate::pebble([1.0, 0.72, 0.5], 0.02, 1500, 3).into_solid_boundary()?;
    let a = Analysis::of_solid(mesh, rep, &Options::default())?;
    let (nu, _) = a.macro_nu(&Options::default());
    let setup = Stone::new(&a, nu)?;
    let mut out = Vec::new();
    for d in [0.3, 1.0, 3.0, 10.0, 30.0] {
        let mut params = DropParams { launch: Launch::at_rest(0.002), sim: RestingParams::damped().sim };
        let c = &mut params.sim.contact;
        (c.restitution, c.linear_damping, c.angular_damping) = (0.0, d, d);
        params.sim.numerics.max_time = 60.0;
        let header = RunHeader {
            format: FORMAT.into(),
            mesh: "pebble".into(),
            mesh_fingerprint: String::new(),
            seed: 2025,
            drops: 1000,
            params,
            certificate: CertificateMode::Facet,
            preset: None,
            center_of_mass: None,
            shard: rocking_stones::dynamics::drops::montecarlo::Shard::ALL,
        };
        let (report, _) = run_and_summarize(&setup, &header);
        eprintln!(
            "  damping {d}: KL flocks {:.4}, non-stable {}",
            report.fit_flocks.kl_divergence, report.off_equilibrium
        );
        out.push((d, report));
    }
    Ok(out)
}

fn write_csv(path: &Path, rows: &[Row]) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_path(path)?;
    w.write_record([
        "body",
        "restitution",
        "height",
        "drops",
        "settled",
        "certified",
        "kl_flocks",
        "chi2_flocks",
        "p_flocks",
        "kl_facets",
        "chi2_facets",
        "p_facets",
        "seconds",
    ])?;
    for r in rows {
        let f = r.report.fit_facets.as_ref();
        w.write_record([
            r.body.clone(),
            r.restitution.to_string(),
            r.height.to_string(),
            r.report.drops.to_string(),
            r.report.settled.to_string(),
            r.report.certified.to_string(),
            format!("{:.6}", r.report.fit_flocks.kl_divergence),
            format!("{:.3}", r.report.fit_flocks.chi_square),
            format!("{:.4}", r.report.fit_flocks.p_value),
            f.map_or(String::new(), |f| format!("{:.6}", f.kl_divergence)),
            f.map_or(String::new(), |f| format!("{:.3}", f.chi_square)),
            f.map_or(String::new(), |f| format!("{:.4}", f.p_value)),
            format!("{:.2}", r.seconds),
        ])?;
    }
    w.flush()?;
    Ok(())
}

/// Box: the share of drops on each pair of opposite faces against the static share.
fn write_box_faces(path: &Path, rows: &[Row]) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_path(path)?;
    w.write_record(["restitution", "height", "face_area", "fraction", "ci_lo", "ci_hi", "static"])?;
    for r in rows.iter().filter(|r| r.body.starts_with("box")) {
        for f in &r.report.facets {
            // face area of a 2 × 1.4 × 1 box from its normal
            let n = f.normal;
            let area = if n.x.abs() > 0.9 {
                1.4
            } else if n.y.abs() > 0.9 {
                2.0
            } else {
                2.8
            };
            w.write_record([
                r.restitution.to_string(),
                r.height.to_string(),
                area.to_string(),
                format!("{:.5}", f.fraction),
                format!("{:.5}", f.ci95.0),
                format!("{:.5}", f.ci95.1),
                format!("{:.5}", f.static_probability),
            ])?;
        }
    }
    w.flush()?;
    Ok(())
}

fn plot(path: &Path, rows: &[Row]) -> anyhow::Result<()> {
    rocking_stones::plot::draw_png(path, (1000, 640), |root| {
        root.fill(&WHITE)?;
        let root = root.titled(
            "Drops vs quasi-static basins: KL divergence of the flock shares against drop height",
            (FONT_FAMILY, style::TITLE),
        )?;
        let (legend, area) = root.split_vertically(legend_height(2));
        let bodies = [("box 2x1.4x1", "box 2 × 1.4 × 1"), ("pebble 1:0.72:0.5", "pebble 1 : 0.72 : 0.5")];
        let mut entries = Vec::new();
        for (b, (_, label)) in bodies.iter().enumerate() {
            for (k, &e) in RESTITUTIONS.iter().enumerate() {
                let c = series_color(k);
                let mark = if b == 0 { Mark::LineDot(c) } else { Mark::Dashed(c) };
                entries.push((mark, format!("{label}, restitution {e}")));
            }
        }
        draw_legend(&legend, &entries).map_err(|e| anyhow::anyhow!(e.to_string()))?;
        let mut chart = ChartBuilder::on(&area)
            .margin(20)
            .margin_top(10)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d((1e-3f64..2.0).log_scale(), (3e-4f64..0.2).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("drop height / R_max (log scale)")
            .y_desc("KL(drops ‖ static), nats (log scale)")
            .x_label_formatter(&|x: &f64| log_tick(*x))
            .y_label_formatter(&|y: &f64| log_tick(*y))
            .label_style((FONT_FAMILY, style::TICK))
            .axis_desc_style((FONT_FAMILY, style::AXIS))
            .draw()?;
        for (b, (body, _)) in bodies.iter().enumerate() {
            for (k, &e) in RESTITUTIONS.iter().enumerate() {
                let color = series_color(k);
                // wider lines first, so curves that coincide (the pebble's) stay visible side by side.
                let width = style::LINE + 2 - k as u32;
                let pts: Vec<(f64, f64)> = rows
                    .iter()
                    .filter(|r| r.body == *body && r.restitution == e)
                    .map(|r| (r.height, r.report.fit_flocks.kl_divergence.max(3e-4)))
                    .collect();
                if b == 0 {
                    chart.draw_series(LineSeries::new(pts.clone(), color.stroke_width(width)))?;
                    chart.draw_series(pts.iter().map(|&p| Circle::new(p, style::MARKER, color.filled())))?;
                } else {
                    chart.draw_series(DashedLineSeries::new(pts.clone(), 8, 5, color.stroke_width(width)))?;
                    chart.draw_series(pts.iter().map(|&p| Circle::new(p, style::MARKER, color.stroke_width(2))))?;
                }
            }
        }
        Ok(())
    })?;
    Ok(())
}

/// A table cell of 4 decimals, "∞" or "–" where the number is infinite or undefined.
fn num4(x: f64) -> String {
    if x.is_nan() {
        "–".into()
    } else if x.is_infinite() {
        if x > 0.0 { "∞" } else { "−∞" }.into()
    } else {
        format!("{x:.4}")
    }
}

fn summary(path: &Path, rows: &[Row], damping: &[(f64, DropReport)]) -> anyhow::Result<()> {
    let mut s = String::new();
    writeln!(s, "# Drops at vanishing energy vs the quasi-static basins\n")?;
    writeln!(s, "Regenerate: `cargo run --release --example drops_quasistatic_limit`.\n")?;
    writeln!(
        s,
        "![KL against drop height](kl_vs_height.png)\n\nIn the picture the three pebble curves coincide at most \
         heights (the flock shares hardly depend on the restitution); wider lines are drawn first.\n"
    )?;
    writeln!(s, "{DROPS} drops per row, seed 2024,")?;
    writeln!(
        s,
        "no spin, friction 0.6, default damping, facet-level energy certificate. KL = D(drops ‖ static) over flocks."
    )?;
    writeln!(
        s,
        "The expected KL of a perfect model from sampling noise alone is about (k − 1)/(2N) for k categories.\n"
    )?;
    writeln!(s, "| body | restitution | height / R_max | settled | KL flocks | χ² flocks (p) | KL facets | s |")?;
    writeln!(s, "|---|---|---|---|---|---|---|---|")?;
    for r in rows {
        writeln!(
            s,
            "| {} | {} | {} | {} | {} | {:.1} ({:.3}) | {} | {:.1} |",
            r.body,
            r.restitution,
            r.height,
            r.report.settled,
            num4(r.report.fit_flocks.kl_divergence),
            r.report.fit_flocks.chi_square,
            r.report.fit_flocks.p_value,
            r.report.fit_facets.as_ref().map_or("–".into(), |f| num4(f.kl_divergence)),
            r.seconds
        )?;
    }
    writeln!(
        s,
        "\n`box_faces.csv`: per face of the box, drop share vs static share (large faces gain as the energy grows)."
    )?;
    writeln!(
        s,
        "\n## Towards overdamped rolling (pebble, height 0.002 R_max, restitution 0, 1000 drops, seed 2025)\n"
    )?;
    writeln!(s, "| damping (1/s, linear = angular) | settled | off equilibrium | still moving at 60 s | KL flocks | KL facets |")?;
    writeln!(s, "|---|---|---|---|---|---|")?;
    for (d, r) in damping {
        writeln!(
            s,
            "| {d} | {} | {} | {} | {} | {} |",
            r.settled,
            r.off_equilibrium,
            r.unsettled,
            num4(r.fit_flocks.kl_divergence),
            r.fit_facets.as_ref().map_or("–".into(), |f| num4(f.kl_divergence))
        )?;
    }
    s.push_str(READING);
    std::fs::write(path, s)?;
    Ok(())
}

const READING: &str = "
## Reading

* **Box** (each stable flock is one facet): at every height up to 0.3 R_max and every restitution
  the drop shares agree with the quasi-static basin probabilities within sampling noise
  (KL ≈ (k − 1)/(2N) = 0.00125 for N = 2000, k = 6). At 1 R_max with restitution 0.6 the drops
  bounce and tumble and the large faces gain: 0.660 of the drops end on the two 2 × 1.4 faces
  against 0.519 static (`box_faces.csv`).
* **Pebble, flocks**: close to the static flock probabilities at every height (KL 0.006–0.008
  against a noise level of ≈ 0.0008: a small but significant bias), and closer with more damping
  (0.0035–0.0036 at 1–30 1/s, the table above).
* **Pebble, micro-facets**: at the default damping (1 1/s) the drops do **not** converge to the
  micro-level basins as the drop height goes to 0 (KL ≈ 0.2 over the stable facets). A vanishing
  drop height does not make the motion quasi-static: the potential energy released while the
  pebble rolls from its release orientation to rest is of the order of the macro barriers, far
  above the micro barriers inside a flock, so the pebble rocks across them and ends on the deeper
  micro-facets — the micro-scale rocking of the paper. Quasi-static rolling is the overdamped
  limit, and the damping sweep shows the convergence: at 10 1/s the micro-facet KL falls to 0.008
  (from 0.20–0.28 at 0.3–3 1/s) and stays there at 30 1/s. (Formerly the outcome was the
  facet closest to the resting normal, and at 30 1/s a quarter of the bodies, stopped by the speed
  thresholds while still creeping, counted on non-stable facets; the quasi-static descent that now
  reads the outcome sends them to their basin's equilibrium: 1 of 1000 off equilibrium.)
";
