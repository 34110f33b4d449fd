//! The largest stable time step of the presets (`Preset::largest_stable_dt`), measured on the
//! three benchmark bodies: per dt, the per-flock statistics of N drops against the reference
//! dt, and on M of them the contact's compression and energy rise (what is measured:
//! `experiments/readme/drops_dt.md`).
//!
//! Run: `cargo experiment drops_dt [-- N M]` (N = 400, M = 40: the committed
//! results) → `results/drops_dt/`.

use benchmark_bodies::benchmark_bodies;
use experiments::{benchmark_bodies, harness};
use harness::{fixed, Common, Parser, Result, Results};
use rocking_stones::dynamics::certificate::{CompressionWatch, CERTIFICATE_MARGIN, CERTIFICATE_MAX_COMPRESSION};
use rocking_stones::dynamics::drops::alone::simulate_observed;
use rocking_stones::dynamics::stone::REST_TOLERANCE;
use rocking_stones::prelude::*;
use rocking_stones::stats::{binomial_at_least, chi_square_homogeneity};
use serde_json::json;

const DTS: [f64; 7] = [1.0 / 480.0, 1.0 / 240.0, 1.0 / 180.0, 1.0 / 150.0, 1.0 / 120.0, 1.0 / 100.0, 1.0 / 80.0];
const REFERENCE: usize = 1;
/// The steps whose drops/s (the longest stable one) and time to rest (the longest) the reading
/// compares with the reference's.
const FASTEST: usize = 4;
const LONGEST: usize = 6;
const PRESETS: [Preset; 3] = [Preset::Drop, Preset::Throw, Preset::QuasiStatic];

/// The largest compression h(down) − z_G of one drop alone in its world during the run and at
/// its end, and the largest rise of L between relaxed states once L ≤ R_max.
fn observe(stone: &Stone, p: &DropParams, seed: u64, i: u64) -> [f64; 3] {
    let mut watch = CompressionWatch::default();
    // The run's own numerics (exact landings and sub-stepped impacts by default), one stone.
    simulate_observed(stone, p, &launch(&mut item_rng(seed, i), p), i, &mut |s| watch.see(&stone.body, s));
    [watch.compression, watch.last_compression, watch.rise]
}

/// The largest stable time step of the presets.
#[derive(Parser)]
struct Args {
    /// Fully settled drops per body, preset and dt
    #[arg(default_value_t = 400)]
    n: u64,
    /// Drops of those stepped one at a time with an observer
    #[arg(default_value_t = 40)]
    m: u64,
    #[command(flatten)]
    common: Common,
}

fn main() -> Result<()> {
    let args = Args::parse();
    let (n, m, seed) = (args.n, args.m, args.common.seed_or(1000));
    let out = Results::open("drops_dt", &args.common)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let bodies = benchmark_bodies(harness::repo(), false)?;
    let mut csv = String::from(
        "body,preset,dt,drops,unsettled,off_equilibrium,mean_time_to_rest_s,drops_per_s,chi2_vs_1_240,dof,p_value,\
         max_compression,max_compression_at_rest,max_energy_rise\n",
    );
    let (mut table, mut curves, mut low, mut tests) = (Vec::new(), Vec::new(), Vec::new(), 0u64);
    // Over every body, preset and dt: drops, unsettled, and the largest compression, compression
    // at rest and energy rise; the ratios of the mean time to rest and of the drops/s.
    let (mut drops, mut unsettled, mut worst) = (0, 0, [f64::NEG_INFINITY; 3]);
    let (mut time_ratios, mut rate_ratios) = (Vec::new(), Vec::new());
    for (name, a) in &bodies {
        let stone = Stone::new(a, a.macro_nu(&Options::default()).0)?;
        stone.quasi_static(); // the basin probabilities of the summaries, computed before any clock starts
        for preset in PRESETS {
            let mut runs = Vec::new();
            for (k, &dt) in DTS.iter().enumerate() {
                let mut params = preset.params(Surface::SteelOnWood);
                params.sim.numerics.dt = dt;
                let mut header = RunHeader::of_params(name, seed + k as u64, n, params.clone(), CertificateMode::None);
                header.preset = Some(preset.name().into());
                let t = std::time::Instant::now();
                let (report, _) = pool.install(|| run_and_summarize(&stone, &header));
                let rate = n as f64 / t.elapsed().as_secs_f64();
                let counts = report.flock_counts(stone.flock_kinds.len());
                let obs: Vec<[f64; 3]> =
                    pool.install(|| (0..m).map(|i| observe(&stone, &params, seed + k as u64, i)).collect());
                let obs: [f64; 3] = std::array::from_fn(|j| obs.iter().map(|o| o[j]).fold(f64::NEG_INFINITY, f64::max));
                eprintln!("{name} {preset} 1/dt = {:.0}: {rate:.0} drops/s", 1.0 / dt);
                runs.push((dt, report, rate, obs, counts));
            }
            let mut curve = Vec::new();
            for (k, (dt, report, rate, [comp, comp_rest, rise], counts)) in runs.iter().enumerate() {
                let (chi2, dof, p) = chi_square_homogeneity(counts, &runs[REFERENCE].4);
                curve.push((1.0 / dt, p));
                if k != REFERENCE {
                    tests += 1;
                    if p < 0.05 {
                        low.push(format!("{name}, {preset}, 1/{:.0} s: {p:.3}", 1.0 / dt));
                    }
                }
                let t = report.mean_time_to_rest.unwrap_or(f64::NAN);
                (drops, unsettled) = (drops + report.drops, unsettled + report.unsettled);
                worst = std::array::from_fn(|j| worst[j].max([*comp, *comp_rest, *rise][j]));
                let (off, sci) = (report.off_equilibrium, |x: &f64| format!("{x:.1e}"));
                table.push(json!({
                    "name": name, "preset": preset.to_string(), "steps": format!("{:.0}", 1.0 / dt),
                    "unsettled": report.unsettled, "off": off, "t": fixed(t, 2), "rate": fixed(*rate, 0),
                    "chi2": fixed(chi2, 1), "dof": dof, "p": fixed(p, 3), "obs": [sci(comp), sci(comp_rest), sci(rise)],
                }));
                csv += &format!(
                    "\"{name}\",{preset},{dt:.6},{n},{},{off},{t:.4},{rate:.1},{chi2:.3},{dof},{p:.4},{comp:.3e},\
                     {comp_rest:.3e},{rise:.3e}\n",
                    report.unsettled
                );
            }
            let time = |k: usize| runs[k].1.mean_time_to_rest.unwrap_or(f64::NAN);
            time_ratios.push(time(LONGEST) / time(REFERENCE));
            rate_ratios.push(runs[FASTEST].2 / runs[REFERENCE].2);
            curves.push((format!("{name}, {preset}"), curve));
        }
    }
    out.write("dt.csv", csv)?;
    plot(&out, &curves)?;
    // How many of the tests fall below 0.05, against what chance alone gives (a binomial of
    // `tests` trials at 0.05); the chance of at least k such p-values says something only when
    // some were found.
    let k = low.len() as u64;
    let tail = binomial_at_least(k, tests, 0.05);
    let range = |v: &[f64], d: usize| {
        let (lo, hi) = v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| (lo.min(x), hi.max(x)));
        (fixed(lo, d), fixed(hi, d))
    };
    let ((time_lo, time_hi), (rate_lo, rate_hi)) = (range(&time_ratios, 2), range(&rate_ratios, 1));
    let side = |x: f64, bound: f64| if x < bound { "under" } else { "not under" };
    out.readme(
        include_str!("readme/drops_dt.md"),
        json!({
            "n": n, "m": m, "seed": seed, "batch": DEFAULT_BATCH,
            "max_compression": CERTIFICATE_MAX_COMPRESSION.to_string(), "margin": CERTIFICATE_MARGIN.to_string(),
            "rows": table,
            "stats": {
                "tests": tests, "k": k, "have": if k == 1 { "has" } else { "have" },
                "which": if low.is_empty() { String::new() } else { format!(" ({})", low.join("; ")) },
                "expected": fixed(0.05 * tests as f64, 1), "by_chance": tail >= 0.05,
                "chance": if k > 0 {
                    format!(" (P(≥ {k}) = {tail:.2} for a binomial of {tests} trials at 0.05)")
                } else { String::new() },
            },
            "s": {
                "unsettled": unsettled, "drops": drops, "at_rest": format!("{:.1e}", worst[1]),
                "at_rest_side": side(worst[1], REST_TOLERANCE), "rest_tolerance": format!("{REST_TOLERANCE:.0e}"),
                "compression": format!("{:.1e}", worst[0]), "time_lo": time_lo, "time_hi": time_hi,
                "rise": format!("{:.1e}", worst[2]), "rise_side": side(worst[2], CERTIFICATE_MARGIN),
                "margin": format!("{CERTIFICATE_MARGIN:.0e}"), "rate_lo": rate_lo, "rate_hi": rate_hi,
            },
        }),
    )
}

/// The p-values against 1/dt: colour by body, line width and marker by preset (three presets per
/// body, in curve order); the reference dt itself (p = 1 against itself) is left out.
fn plot(out: &Results, curves: &[(String, Vec<(f64, f64)>)]) -> Result<()> {
    let black = RGBColor(0, 0, 0);
    let mut chart = Chart::new(
        Axis::linear("1/dt (steps per s of the scaled body)", 60.0, 500.0),
        Axis::log("p-value (log scale)", 1e-3, 1.0),
    )
    .title("Per-flock statistics vs dt: χ² homogeneity p-value against 1/dt = 240");
    for (k, (label, c)) in curves.iter().enumerate() {
        let (colour, width) = (series_color(k / 3), [3, 1, 2][k % 3]);
        let pts: Vec<(f64, f64)> =
            c.iter().filter(|&&(x, _)| (x - 240.0).abs() > 1e-6).map(|&(x, p)| (x, p.max(1e-3))).collect();
        let (marker, mark) = [
            (Marker::Dot, Mark::LineDot(colour)),
            (Marker::Triangle, Mark::Triangle(colour)),
            (Marker::Cross, Mark::Cross(colour)),
        ][k % 3];
        chart = chart.line_width(&pts, colour, width).markers(&pts, colour, marker).legend(mark, label.clone());
    }
    chart
        .line_width(&[(60.0, 0.05), (500.0, 0.05)], black, 1)
        .legend(Mark::WideLine(black, 1), "p = 0.05 (the reading's level)")
        .save(&out.path("p_values.png"), (1000, 600))?;
    Ok(())
}
