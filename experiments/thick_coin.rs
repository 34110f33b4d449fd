//! The thick coin: a cylinder of height h and diameter d (a prism over a regular
//! 32-gon), P(lands on its edge) against h/d, under the calibrated `throw` and the
//! `quasi-static` preset, beside the quasi-static basin probability and two published
//! predictions:
//!
//! * the quasi-static (solid-angle) coin is fair three ways — P(edge) = 1/3 — at
//!   h/d = 1/(2√2) ≈ 0.354 (the edge's share of the sphere of directions around G);
//! * a vigorously flipped coin that lands where its angular momentum leaves it (Yong &
//!   Mahadevan, Am. J. Phys. 79, 1195 (2011)) is fair at h/d = 1/√3 ≈ 0.577.
//!
//! Neither is a calibration target; they bracket what a physical throw should give.
//!
//! Run: `cargo run --release --example thick_coin [-- N]` (N = 300 per point and preset) →
//! `results/thick_coin/`.

use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::certificate::CertificateMode;
use rocking_stones::dynamics::drops::montecarlo::{run_and_summarize, RunHeader, FORMAT};
use rocking_stones::dynamics::drops::params::{DropParams, Preset};
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::mesh::TriMesh;
use rocking_stones::plot::{colors, draw_legend, legend_height, plain, style, Mark, FONT_FAMILY};
use rocking_stones::stats::wilson;
use rocking_stones::Point3;
use std::fmt::Write as _;
use std::path::Path;

const SIDES: usize = 32;

/// A prism of height `h` over the regular `SIDES`-gon inscribed in a circle of diameter 1.
fn coin(h: f64) -> TriMesh {
    let mut v = Vec::new();
    for z in [-0.5 * h, 0.5 * h] {
        for k in 0..SIDES {
            let t = std::f64::consts::TAU * k as f64 / SIDES as f64;
            v.push(Point3::new(0.5 * t.cos(), 0.5 * t.sin(), z));
        }
    }
    let n = SIDES as u32;
    let mut t = Vec::new();
    for k in 1..n - 1 {
        t.push([0, k + 1, k]); // bottom, facing −z
        t.push([n, n + k, n + k + 1]); // top, facing +z
    }
    for k in 0..n {
        let j = (k + 1) % n;
        t.push([k, j, n + j]);
        t.push([k, n + j, n + k]);
    }
    TriMesh::new(v, t)
}

/// (edge count, drops, quasi-static P(edge)).
fn p_edge(stone: &Stone, p: &DropParams, n: u64) -> (u64, u64, f64) {
    let header = RunHeader {
        format: FORMAT.into(),
        mesh: "coin".into(),
        mesh_fingerprint: String::new(),
        seed: 5,
        drops: n,
        params: p.clone(),
        certificate: CertificateMode::Facet,
        preset: None,
        center_of_mass: None,
        shard: rocking_stones::dynamics::drops::montecarlo::Shard::ALL,
    };
    let (r, _) = run_and_summarize(stone, &header);
    let edge = |f: &&rocking_stones::dynamics::drops::montecarlo::FacetRow| f.normal.z.abs() < 0.5;
    (
        r.facets.iter().filter(edge).map(|f| f.count).sum(),
        r.facet_drops,
        r.facets.iter().filter(edge).map(|f| f.static_probability).sum(),
    )
}

fn main() {
    let n: u64 = std::env::args().nth(1).map_or(300, |s| s.parse().expect("N"));
    let out = Path::new("results/thick_coin");
    std::fs::create_dir_all(out).expect("results folder");
    let ratios = [0.1, 0.2, 0.3, 0.354, 0.45, 0.577, 0.7, 0.85, 1.0];
    let mut rows = Vec::new();
    let mut csv = String::from("h_over_d,quasi_static_basin,throw,throw_lo,throw_hi,quasi_static_preset,qs_lo,qs_hi\n");
    for &hd in &ratios {
        let (mesh, rep) = coin(hd).into_solid_boundary().expect("a closed prism");
        let a = Analysis::of_solid(mesh, rep, &Options::default()).expect("a prism analyses");
        let stone = Stone::new(&a, 0.0035).expect("stable facets");
        let (kt, nt, basin) = p_edge(&stone, &Preset::Throw.params(Surface::SteelOnWood), n);
        let (kq, nq, _) = p_edge(&stone, &Preset::QuasiStatic.params(Surface::SteelOnWood), n);
        let (pt, pq) = (kt as f64 / nt as f64, kq as f64 / nq as f64);
        let (tl, th) = wilson(kt, nt, 1.96);
        let (ql, qh) = wilson(kq, nq, 1.96);
        eprintln!("h/d {hd}: basin {basin:.3}, throw {pt:.3}, quasi-static {pq:.3}");
        let _ = writeln!(csv, "{hd},{basin:.4},{pt:.4},{tl:.4},{th:.4},{pq:.4},{ql:.4},{qh:.4}");
        rows.push((hd, basin, pt, tl, th, pq, ql, qh));
    }
    std::fs::write(out.join("p_edge.csv"), csv).expect("csv");
    plot(out, &rows).expect("plot");
    let cross = |f: &dyn Fn(&Row) -> f64| {
        rows.windows(2).find(|w| f(&w[0]) < 1.0 / 3.0 && f(&w[1]) >= 1.0 / 3.0).map(|w| {
            let (a, b) = (f(&w[0]), f(&w[1]));
            w[0].0 + (1.0 / 3.0 - a) / (b - a) * (w[1].0 - w[0].0)
        })
    };
    let fmt = |x: Option<f64>| x.map_or("not on the grid".to_string(), |v| format!("{v:.3}"));
    let mut md = String::new();
    let _ = writeln!(md, "# The thick coin: P(edge) against h/d\n");
    let _ = writeln!(md, "Regenerate: `cargo run --release --example thick_coin`.\n");
    let _ = writeln!(md, "A prism over a regular {SIDES}-gon (diameter d = 1, height h), {n} drops per point and preset, steel on wood. `p_edge.png`: the quasi-static basin probability (exact), the `quasi-static` preset (damped creep from contact), the calibrated `throw` with 95 % Wilson intervals; dashed: P = 1/3 and vertical lines at the two published fair-coin ratios.\n");
    let _ = writeln!(md, "| h/d where P(edge) = 1/3 | value |\n|---|---|");
    let _ = writeln!(md, "| quasi-static basins (this code) | {} |", fmt(cross(&|r| r.1)));
    let _ = writeln!(md, "| solid-angle closed form | 0.354 |");
    let _ = writeln!(md, "| `quasi-static` preset | {} |", fmt(cross(&|r| r.5)));
    let _ = writeln!(md, "| calibrated `throw` | {} |", fmt(cross(&|r| r.2)));
    let _ = writeln!(md, "| Yong & Mahadevan 2011, vigorous flip | 0.577 |\n");
    let throw_fair = cross(&|r| r.2);
    // Thin coins: does the throw's P(edge) stay up where a round coin's would vanish (rim rolling)?
    let thin: Vec<f64> = rows.iter().filter(|r| r.0 <= 0.36).map(|r| r.2).collect();
    let thin_floor = thin.iter().copied().fold(f64::INFINITY, f64::min);
    let _ = writeln!(
        md,
        "Reading: the `quasi-static` preset follows the exact basins (the overdamped limit, as it must), and their \
         fair ratio matches the solid-angle closed form. The calibrated `throw` — fitted to dice, not to coins — is \
         fair at h/d = {}, against Yong & Mahadevan's vigorous-flip ratio 0.577{}: an independent check of the throw.{}\n",
        fmt(throw_fair),
        throw_fair.map_or(String::new(), |v| format!(" ({:+.0} %)", 100.0 * (v / 0.577 - 1.0))),
        if thin.len() > 1 && thin_floor > 0.05 {
            format!(
                " For thin coins (h/d ≤ 0.35) the throw's P(edge) does not fall towards zero but stays at {:.2}–{:.2}, \
                 most likely because thin coins roll on their rim like wheels and stop upright on one of the {SIDES} \
                 flat side facets, a seat that a polygonal rim offers and a real round rim does not; read the \
                 thin-coin edge landings as a limit of the polygonal model (not checked drop by drop).",
                thin_floor,
                thin.iter().copied().fold(0.0, f64::max)
            )
        } else {
            String::new()
        }
    );
    let _ = writeln!(md, "| h/d | basin | quasi-static preset | throw |\n|---|---|---|---|");
    for r in &rows {
        let _ = writeln!(
            md,
            "| {} | {:.3} | {:.3} [{:.3}, {:.3}] | {:.3} [{:.3}, {:.3}] |",
            r.0, r.1, r.5, r.6, r.7, r.2, r.3, r.4
        );
    }
    std::fs::write(out.join("README.md"), md).expect("README");
}

type Row = (f64, f64, f64, f64, f64, f64, f64, f64);

fn plot(out: &Path, rows: &[Row]) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    let path = out.join("p_edge.png");
    rocking_stones::plot::draw_png(&path, (900, 640), |root| {
        root.fill(&WHITE)?;
        let root = root.titled("Thick coin: P(lands on its edge) against h/d", (FONT_FAMILY, style::TITLE))?;
        let (legend, area) = root.split_vertically(legend_height(2));
        let (basin, qs, throw, grey) = (colors::GREEN, colors::ORANGE, colors::BLUE, colors::GREY);
        draw_legend(
            &legend,
            &[
                (Mark::Line(basin), "quasi-static basins (exact)".into()),
                (Mark::Line(qs), "quasi-static preset (simulated)".into()),
                (Mark::LineDot(throw), "throw preset, 95 % Wilson intervals".into()),
                (Mark::Dashed(grey), "P = 1/3 and the published fair-coin ratios".into()),
            ],
        )
        .map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&area)
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0f64..1.05, 0.0f64..1.0)?;
        chart
            .configure_mesh()
            .x_desc("h / d (coin height over diameter)")
            .y_desc("P(edge)")
            .x_label_formatter(&|x| plain(*x))
            .y_label_formatter(&|y| plain(*y))
            .label_style((FONT_FAMILY, style::TICK))
            .axis_desc_style((FONT_FAMILY, style::AXIS))
            .draw()?;
        let dashed = |a: (f64, f64), b: (f64, f64)| {
            (0..40).filter(|k| k % 2 == 0).map(move |k| {
                let (s, t) = (k as f64 / 40.0, (k + 1) as f64 / 40.0);
                PathElement::new(
                    vec![
                        (a.0 + s * (b.0 - a.0), a.1 + s * (b.1 - a.1)),
                        (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)),
                    ],
                    grey.stroke_width(1),
                )
            })
        };
        for (x, label) in [(0.354, "solid angle 1/(2√2)"), (0.577, "Yong & Mahadevan 1/√3")] {
            chart.draw_series(dashed((x, 0.0), (x, 1.0)))?;
            chart.draw_series(std::iter::once(Text::new(label, (x + 0.01, 0.97), (FONT_FAMILY, style::LEGEND))))?;
        }
        chart.draw_series(dashed((0.0, 1.0 / 3.0), (1.05, 1.0 / 3.0)))?;
        chart.draw_series(LineSeries::new(rows.iter().map(|r| (r.0, r.1)), basin.stroke_width(style::LINE)))?;
        chart.draw_series(LineSeries::new(rows.iter().map(|r| (r.0, r.5)), qs.stroke_width(style::LINE)))?;
        chart.draw_series(LineSeries::new(rows.iter().map(|r| (r.0, r.2)), throw.stroke_width(style::LINE)))?;
        chart.draw_series(rows.iter().map(|r| Circle::new((r.0, r.2), style::MARKER, throw.filled())))?;
        chart.draw_series(
            rows.iter().map(|r| PathElement::new(vec![(r.0, r.3), (r.0, r.4)], throw.stroke_width(style::LINE))),
        )?;
        Ok(())
    })?;
    Ok(())
}
