//! The thick coin: P(lands on its edge) against h/d of a prism over a regular 32-gon, under the
//! calibrated `throw` and the `quasi-static` preset, beside the quasi-static basins and two
//! published fair-coin ratios, neither a calibration target: the solid-angle coin, fair at
//! h/d = 1/(2√2) (the edge's share of the directions around G), and the vigorously flipped coin of
//! Yong & Mahadevan (Am. J. Phys. 79, 1195 (2011)), fair at 1/√3.
//!
//! Run: `cargo experiment thick_coin [-- N]` (N = 300 per point and preset) →
//! `results/thick_coin/`; the README's prose is `experiments/readme/thick_coin.md`.

use rocking_stones::planar::Polygon;
use rocking_stones::prelude::*;
use rocking_stones::stats::{min_max, upward_crossing, wilson};
use rocking_stones::study::outcomes::share_on;

use experiments::harness;
use harness::{fixed, Result, Results};

const SIDES: usize = 32;

/// (edge count, drops, quasi-static P(edge)).
fn p_edge(stone: &Stone, p: DropParams, n: u64, seed: u64) -> (u64, u64, f64) {
    let (r, _) = run_and_summarize(stone, &RunHeader::of_params("coin", seed, n, p, CertificateMode::Facet));
    share_on(&r, |normal| normal.z.abs() < 0.5)
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
        // A prism of height h/d over the regular `SIDES`-gon inscribed in a circle of diameter 1.
        let (mesh, rep) = Polygon::regular(SIDES, 0.5, 0.0)?.prism(hd).into_solid_boundary()?;
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
    let cross =
        |f: &dyn Fn(&Row) -> f64| upward_crossing(&rows.iter().map(|r| (r.hd, f(r))).collect::<Vec<_>>(), 1.0 / 3.0);
    let fmt = |x: Option<f64>| x.map_or("not on the grid".to_string(), |v| format!("{v:.3}"));
    let throw_fair = cross(&|r| r.throw.0);
    // Thin coins: does the throw's P(edge) stay up where a round coin's would vanish (rim rolling)?
    let thin: Vec<f64> = rows.iter().filter(|r| r.hd <= 0.36).map(|r| r.throw.0).collect();
    let (thin_lo, thin_hi) = min_max(thin.iter().copied());
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
