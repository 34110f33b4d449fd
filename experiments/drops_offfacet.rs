//! Why quasi-static drops on a smooth pebble "rest" above their facet, and what it does to the
//! outcome: the speed rule ends a damped creep down a gentle slope of the support function before
//! the stone reaches its facet; every such drop is continued (up to 30 s more, same numerics)
//! until it is on its equilibrium — is it the facet it was counted on?
//!
//! Run: `cargo experiment drops_offfacet [-- N]` (N = 400) → `results/drops_offfacet/`;
//! the explanation is in `experiments/readme/drops_offfacet.md`.

use benchmark_bodies::benchmark_bodies;
use experiments::{benchmark_bodies, harness};
use harness::{fixed, Result, Results};
use rocking_stones::dynamics::drops::alone::{go_on_to_equilibrium, run_alone};
use rocking_stones::dynamics::stone::REST_TOLERANCE;
use rocking_stones::prelude::*;
use rocking_stones::stats::quantile;
use std::fmt::Write as _;

fn main() -> Result<()> {
    let (n, common) = harness::count_args(
        "Quasi-static drops that stop above their facet, continued until they are on it.",
        "Drops per body",
        400,
    );
    let seed = common.seed_or(1);
    let out = Results::open("drops_offfacet", &common)?;
    let mut csv = String::from("body,drop,height_above,speed,spin,same_facet,seconds_more,height_after\n");
    let p = Preset::QuasiStatic.params(Surface::SteelOnWood);
    // Per body: its table row, and the heights above the facet when stopped and after going on.
    let (mut rows, mut hist, mut changed, mut medians) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut all_off, mut all_same) = (0usize, 0usize);
    for (name, a) in benchmark_bodies(harness::repo(), false)? {
        let stone = Stone::new(&a, 0.0035)?;
        // Each drop the speed rule ended above its facet: (height above, speed, same facet after
        // going on, seconds more, height after).
        let mut off = Vec::new();
        for i in 0..n {
            let (mut sim, end) = run_alone(&stone, &p, &launch(&mut item_rng(seed, i), &p), &mut |_| {});
            let first = stone.rest(&end.state.down);
            if first.on_equilibrium() {
                continue;
            }
            let (k, now) = go_on_to_equilibrium(&mut sim, &stone, first, (30.0 / p.sim.numerics.dt) as u64);
            let (v, w, more) = (end.state.linvel.norm(), end.state.angvel.norm(), k as f64 * p.sim.numerics.dt);
            let same = now.facet == first.facet;
            writeln!(csv, "{name},{i},{:e},{v:e},{w:e},{same},{more:.3},{:e}", first.height_above, now.height_above)?;
            if !same {
                changed.push(
                    serde_json::json!({"body": name, "drop": i, "height": format!("{:.1e}", first.height_above)}),
                );
            }
            off.push((first.height_above, v, same, more, now.height_above));
        }
        let same = off.iter().filter(|c| c.2).count();
        (all_off, all_same) = (all_off + off.len(), all_same + same);
        let reached: Vec<f64> = off.iter().filter(|c| c.4 <= REST_TOLERANCE).map(|c| c.3).collect();
        let max_h = off.iter().map(|c| c.0).fold(0.0, f64::max);
        let max_v = off.iter().map(|c| c.1).fold(0.0, f64::max);
        let median = quantile(&reached, 0.5);
        medians.extend(Some(median).filter(|m| m.is_finite()));
        let k = off.len();
        let cells = [name.clone(), n.to_string(), k.to_string(), format!("{max_h:.1e}"), format!("{max_v:.1e}")];
        let cells = [&cells[..], &[format!("{same}/{k}"), format!("{}/{k}", reached.len()), fixed(median, 1)]].concat();
        println!("{name}: {k} of {n} above the facet; {same} same facet, {} reached it", reached.len());
        rows.push(cells);
        hist.push((name, off.iter().map(|c| c.0).collect::<Vec<_>>(), off.iter().map(|c| c.4).collect::<Vec<_>>()));
    }
    out.write("offfacet.csv", csv)?;
    plot(&out, &hist)?;
    out.readme(
        include_str!("readme/drops_offfacet.md"),
        serde_json::json!({
            "n": n, "inv_dt": fixed(1.0 / p.sim.numerics.dt, 0), "tolerance": REST_TOLERANCE.to_string(),
            "rows": rows, "all_off": all_off, "all_same": all_same, "moved": all_off - all_same, "drops": 3 * n,
            "changed": changed,
            "median_lo": fixed(medians.iter().copied().fold(f64::INFINITY, f64::min), 1),
            "median_hi": fixed(medians.iter().copied().fold(0.0, f64::max), 1),
        }),
    )
}

/// Per body, the heights above the facet when stopped (dots) and after going on (crosses), on
/// rows of their own, jittered over five lines so that equal heights stay apart.
fn plot(out: &Results, hist: &[(String, Vec<f64>, Vec<f64>)]) -> Result<()> {
    let rows = hist.len() as f64;
    let mut chart = Chart::new(
        Axis::log("h(down) − R_F (R_max, log scale); ≤ 10⁻³ counts as on the facet", 1e-5, 1.0),
        Axis::linear("", -0.5, rows - 0.5).ticks(0).no_grid(),
    )
    .title("Height of G above the counted facet's rest: when the speed rule stopped (●) and after going on (×)")
    .line_width(&[(REST_TOLERANCE, -0.5), (REST_TOLERANCE, rows - 0.5)], colors::GREY, 2);
    for (k, (name, before, after)) in hist.iter().enumerate() {
        let (y, c) = (k as f64, series_color(k));
        let at = |h: &[f64], side: f64| -> Vec<(f64, f64)> {
            h.iter()
                .enumerate()
                .map(|(i, &h)| (h.max(1e-5), y + side * (0.15 + 0.1 * ((i % 5) as f64 / 5.0))))
                .collect()
        };
        chart = chart
            .markers_sized(&at(before, 1.0), c, Marker::Dot, 3)
            .markers(&at(after, -1.0), c, Marker::Cross)
            .text_colored(name.clone(), (1.3e-5, y + 0.45), c);
    }
    chart
        .legend(Mark::Dot(colors::GREY), "when the speed rule stopped the drop")
        .legend(Mark::Cross(colors::GREY), "after going on, up to 30 s more")
        .save(&out.path("offfacet.png"), (1000, 560))?;
    Ok(())
}
