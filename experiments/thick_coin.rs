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
//! `results/thick_coin/`; the README's prose is `experiments/readme/thick_coin.md`.

use rocking_stones::mesh::TriMesh;
use rocking_stones::prelude::*;
use rocking_stones::stats::wilson;

#[path = "shared/harness.rs"]
mod harness;
use harness::{fixed, Result, Results};

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
fn p_edge(stone: &Stone, p: DropParams, n: u64, seed: u64) -> (u64, u64, f64) {
    let (r, _) = run_and_summarize(stone, &RunHeader::of_params("coin", seed, n, p, CertificateMode::Facet));
    let edge = || r.facets.iter().filter(|f| f.normal.z.abs() < 0.5);
    (edge().map(|f| f.count).sum(), r.facet_drops, edge().map(|f| f.static_probability).sum())
}

/// One h/d: the basin probability, then each preset's P(edge) with its 95 % Wilson interval.
struct Row {
    hd: f64,
    basin: f64,
    throw: (f64, f64, f64),
    qs: (f64, f64, f64),
}

fn main() -> Result<()> {
    let (n, common) = harness::count_args("P(edge) of the thick coin against h/d.", "Drops per point and preset", 300);
    let seed = common.seed_or(5);
    let out = Results::open("thick_coin", &common)?;
    let ratios = [0.1, 0.2, 0.3, 0.354, 0.45, 0.577, 0.7, 0.85, 1.0];
    let mut rows = Vec::new();
    for &hd in &ratios {
        let (mesh, rep) = coin(hd).into_solid_boundary()?;
        let a = Analysis::of_solid(mesh, rep, &Options::default())?;
        let stone = Stone::new(&a, 0.0035)?;
        let share = |preset: Preset| {
            let (k, n, basin) = p_edge(&stone, preset.params(Surface::SteelOnWood), n, seed);
            let (lo, hi) = wilson(k, n, 1.96);
            ((k as f64 / n as f64, lo, hi), basin)
        };
        let ((throw, basin), (qs, _)) = (share(Preset::Throw), share(Preset::QuasiStatic));
        eprintln!("h/d {hd}: basin {basin:.3}, throw {:.3}, quasi-static {:.3}", throw.0, qs.0);
        rows.push(Row { hd, basin, throw, qs });
    }
    let f4 = |x: f64| fixed(x, 4);
    out.csv(
        "p_edge.csv",
        &["h_over_d", "quasi_static_basin", "throw", "throw_lo", "throw_hi", "quasi_static_preset", "qs_lo", "qs_hi"],
        rows.iter().map(|r| {
            let (t, q) = (r.throw, r.qs);
            std::iter::once(r.hd.to_string()).chain([r.basin, t.0, t.1, t.2, q.0, q.1, q.2].map(f4))
        }),
    )?;
    plot(&out, &rows)?;
    // h/d where a curve crosses P = 1/3, interpolated linearly between grid points.
    let cross = |f: &dyn Fn(&Row) -> f64| {
        rows.windows(2).find(|w| f(&w[0]) < 1.0 / 3.0 && f(&w[1]) >= 1.0 / 3.0).map(|w| {
            let (a, b) = (f(&w[0]), f(&w[1]));
            w[0].hd + (1.0 / 3.0 - a) / (b - a) * (w[1].hd - w[0].hd)
        })
    };
    let fmt = |x: Option<f64>| x.map_or("not on the grid".to_string(), |v| format!("{v:.3}"));
    let throw_fair = cross(&|r| r.throw.0);
    // Thin coins: does the throw's P(edge) stay up where a round coin's would vanish (rim rolling)?
    let thin: Vec<f64> = rows.iter().filter(|r| r.hd <= 0.36).map(|r| r.throw.0).collect();
    let (thin_lo, thin_hi) =
        (thin.iter().copied().fold(f64::INFINITY, f64::min), thin.iter().copied().fold(0.0, f64::max));
    let f3 = |x: f64| fixed(x, 3);
    out.readme(include_str!("readme/thick_coin.md"),
        serde_json::json!({
            "sides": SIDES,
            "n": n,
            "fair": {
                "basin": fmt(cross(&|r| r.basin)),
                "quasi_static": fmt(cross(&|r| r.qs.0)),
                "throw": fmt(throw_fair),
            },
            "throw_vs_flip": throw_fair.map_or(String::new(), |v| format!(" ({:+.0} %)", 100.0 * (v / 0.577 - 1.0))),
            "thin": (thin.len() > 1 && thin_lo > 0.05).then(|| serde_json::json!({"lo": fixed(thin_lo, 2), "hi": fixed(thin_hi, 2)})),
            "rows": rows.iter().map(|r| serde_json::json!({
                "hd": r.hd.to_string(), "basin": f3(r.basin),
                "qs": f3(r.qs.0), "qs_lo": f3(r.qs.1), "qs_hi": f3(r.qs.2),
                "throw": f3(r.throw.0), "throw_lo": f3(r.throw.1), "throw_hi": f3(r.throw.2),
            })).collect::<Vec<_>>(),
        }),
    )
}

fn plot(out: &Results, rows: &[Row]) -> Result<()> {
    let (basin, qs, throw, grey) = (colors::GREEN, colors::ORANGE, colors::BLUE, colors::GREY);
    let curve = |f: fn(&Row) -> f64| rows.iter().map(|r| (r.hd, f(r))).collect::<Vec<_>>();
    let mut chart =
        Chart::new(Axis::linear("h / d (coin height over diameter)", 0.0, 1.05), Axis::linear("P(edge)", 0.0, 1.0))
            .title("Thick coin: P(lands on its edge) against h/d")
            .legend(Mark::Line(basin), "quasi-static basins (exact)")
            .legend(Mark::Line(qs), "quasi-static preset (simulated)")
            .legend(Mark::LineDot(throw), "throw preset, 95 % Wilson intervals")
            .legend(Mark::Dashed(grey), "P = 1/3 and the published fair-coin ratios")
            .hline(1.0 / 3.0, grey);
    for (x, label) in [(0.354, "solid angle 1/(2√2)"), (0.577, "Yong & Mahadevan 1/√3")] {
        chart = chart.vline(x, grey).text(label, (x + 0.01, 0.97));
    }
    chart
        .line(&curve(|r| r.basin), basin)
        .line(&curve(|r| r.qs.0), qs)
        .line(&curve(|r| r.throw.0), throw)
        .dots(&curve(|r| r.throw.0), throw)
        .y_bars(&rows.iter().map(|r| (r.hd, r.throw.1, r.throw.2)).collect::<Vec<_>>(), throw)
        .save(&out.path("p_edge.png"), (900, 640))?;
    Ok(())
}
