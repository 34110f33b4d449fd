//! Drops per second per core for the `drop` and `throw` presets on the bundled stone, a
//! ≈500-hull-vertex synthetic pebble and a box 1 × 0.8 × 0.5: plain, batched, certified (facet and
//! flock level) and with free flight, the same drops in every mode compared drop by drop with
//! plain, and the batch-size sweep that picks `montecarlo::DEFAULT_BATCH`; the README's prose is
//! `experiments/readme/drops_certificate_speed.md`.
//!
//! Run: `cargo experiment drops_certificate_speed [-- N]` (N = 1000 drops per mode;
//! one thread, so the figures are per core) → `results/drops_certificate/`.

use benchmark_bodies::benchmark_bodies;
use experiments::{benchmark_bodies, harness};
use harness::{fixed, Result, Results};
use rocking_stones::dynamics::drops::compare::{matching_drops, Match};
use rocking_stones::dynamics::drops::montecarlo::{run_timed, TimedRun};
use rocking_stones::prelude::*;
use rocking_stones::report::drops::flock_cells;
use rocking_stones::stats::chi_square_homogeneity;
use serde_json::json;
use std::fmt::Write as _;

/// One mode: stones per world (1 = plain), certificate, flight, and whether it runs the
/// preset's default step (its longest stable one, 1/120 s, `Preset::largest_stable_dt`) rather
/// than the reference step [`REFERENCE_DT`] = 1/240 s.
struct Mode {
    name: &'static str,
    batch: usize,
    cert: CertificateMode,
    flight: Flight,
    default_step: bool,
}

const fn mode(name: &'static str, batch: usize, cert: CertificateMode, flight: Flight) -> Mode {
    Mode { name, batch, cert, flight, default_step: false }
}

const MODES: [Mode; 9] = [
    mode("plain", 1, CertificateMode::None, Flight::Rapier),
    mode("batched", DEFAULT_BATCH, CertificateMode::None, Flight::Rapier),
    mode("flock-certified", 1, CertificateMode::Flock, Flight::Rapier),
    mode("facet-certified + batched", DEFAULT_BATCH, CertificateMode::Facet, Flight::Rapier),
    mode("flock-certified + batched", DEFAULT_BATCH, CertificateMode::Flock, Flight::Rapier),
    mode("batched + free flight", DEFAULT_BATCH, CertificateMode::None, Flight::Free),
    mode("facet-certified + batched + free flight", DEFAULT_BATCH, CertificateMode::Facet, Flight::Free),
    mode("flock-certified + batched + free flight", DEFAULT_BATCH, CertificateMode::Flock, Flight::Free),
    Mode {
        name: "flock-certified + batched, default numerics (free flight, dt 1/120 s)",
        batch: DEFAULT_BATCH,
        cert: CertificateMode::Flock,
        flight: Flight::Free,
        default_step: true,
    },
];

/// The modes drawn in `speedup.png` (plain is 1 by definition; the facet certificate and full
/// settling with free flight are in the table).
const PLOTTED: [usize; 5] = [1, 2, 4, 7, 8];

fn header(name: &str, n: u64, seed: u64, preset: Preset, m: &Mode) -> RunHeader {
    let mut params = preset.params(Surface::SteelOnWood);
    params.sim.flight.mode = m.flight;
    if !m.default_step {
        params.sim.numerics.dt = REFERENCE_DT;
    }
    RunHeader::of_params(name, seed, n, params, m.cert).with_preset(preset)
}

fn main() -> Result<()> {
    let (n, common) = harness::count_args(
        "Drops per second per core, plain, batched and certified.",
        "Drops per body, preset and mode",
        1000,
    );
    let seed = common.seed_or(7);
    let out = Results::open("drops_certificate", &common)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let bodies = benchmark_bodies(harness::repo(), true)?;
    let mut csv = String::from(
        "body,preset,mode,batch,certificate,flight,dt,drops,seconds,drops_per_s,speedup_vs_plain,mean_sim_time_s,\
         settled,certified,same_outcome_as_plain,chi2_p_flocks_vs_plain,kl_flocks\n",
    );
    let (mut rows, mut flocks, mut bars) = (Vec::new(), Vec::new(), Vec::<(String, Vec<f64>)>::new());
    for (name, a) in &bodies {
        let stone = Stone::new(a, a.macro_nu(&Options::default()).0)?;
        for preset in [Preset::Drop, Preset::Throw] {
            let run = |m: &Mode| run_timed(&pool, &stone, &header(name, n, seed, preset, m), m.batch);
            // Plain is timed before and after the other modes, each other mode twice; the faster
            // run counts.
            let plain_first = run(&MODES[0])?;
            let mut runs = vec![];
            for m in &MODES[1..] {
                let r = run(m)?.faster(run(m)?);
                eprintln!("{name} {preset} {}: {:.1} drops/s", m.name, r.rate());
                runs.push(r);
            }
            let plain_again = run(&MODES[0])?;
            let (first_rate, again_rate) = (plain_first.rate(), plain_again.rate());
            eprintln!("{name} {preset} plain: {first_rate:.1} / {again_rate:.1} drops/s");
            runs.insert(0, plain_first.faster(plain_again));
            let plain = &runs[0];
            let counts =
                |r: &TimedRun| -> Vec<u64> { plain.report.flocks.iter().map(|f| r.report.flock_count(f.id)).collect() };
            let mut speedups = Vec::new();
            for (m, r) in MODES.iter().zip(&runs) {
                let level = match m.cert {
                    // the reference numerics: bit for bit
                    CertificateMode::None if m.flight == Flight::Rapier && !m.default_step => Match::Record,
                    CertificateMode::None | CertificateMode::Facet => Match::Facet,
                    CertificateMode::Flock => Match::Flock,
                };
                let same = matching_drops(&stone.facet_flock, &r.outcomes, &plain.outcomes, level);
                let (_, _, p_value) = chi_square_homogeneity(&counts(plain), &counts(r));
                let (rate, speedup, rep) = (r.rate(), plain.seconds / r.seconds, &r.report);
                speedups.push(speedup);
                let plain_rates = format!(" ({first_rate:.1} / {again_rate:.1})");
                rows.push(json!({
                    "body": name, "preset": preset.to_string(), "mode": m.name,
                    "rate": format!("{rate:.1}{}", if m.batch == 1 && m.cert == CertificateMode::None { plain_rates } else { String::new() }),
                    "speedup": fixed(speedup, 1), "mean_time": fixed(rep.mean_time, 2), "settled": rep.settled,
                    "certified": rep.certified, "same": same, "p": fixed(p_value, 2),
                    "kl": fixed(rep.fit_flocks.kl_divergence, 4),
                }));
                writeln!(
                    csv,
                    "\"{name}\",{preset},\"{}\",{},{},{},{},{n},{:.3},{rate:.2},{speedup:.3},{:.4},{},{},{same},{p_value:.4},{:.5}",
                    m.name,
                    m.batch,
                    m.cert.name(),
                    rep.params.sim.flight.mode,
                    rep.params.sim.numerics.dt,
                    r.seconds,
                    rep.mean_time,
                    rep.settled,
                    rep.certified,
                    rep.fit_flocks.kl_divergence
                )?;
            }
            bars.push((format!("{}, {preset}", ["stone", "pebble", "box"][bars.len() / 2]), speedups));
            let table = flock_cells(&runs.iter().map(|r| &r.report).collect::<Vec<_>>(), 3);
            flocks.push(json!({ "body": name, "preset": preset.to_string(), "rows": table }));
        }
    }
    // Batch-size sweep on the bundled stone's throws, full settling (the per-step cost only).
    let (name, a) = &bodies[0];
    let stone = Stone::new(a, a.macro_nu(&Options::default()).0)?;
    let mut sweep = Vec::new();
    let mut base = None;
    for batch in [1, 4, 8, 16, 32, 64, 128] {
        let r = run_timed(&pool, &stone, &header(name, n, seed, Preset::Throw, &MODES[1]), batch)?;
        let b = *base.get_or_insert(r.seconds);
        let (rate, speedup) = (r.rate(), b / r.seconds);
        sweep.push(json!({ "batch": batch, "rate": fixed(rate, 1), "speedup": fixed(speedup, 2) }));
        writeln!(
            csv,
            "\"{name}\",throw,batch sweep,{batch},none,rapier,{REFERENCE_DT:.6},{n},{:.3},{rate:.2},{speedup:.3},{:.4},{},0,,,",
            r.seconds, r.report.mean_time, r.report.settled
        )?;
    }
    let speedups: Vec<_> = (MODES.iter().enumerate().skip(1))
        .map(|(k, m)| {
            let cases: Vec<_> = bars.iter().map(|(label, v)| format!("{label} {:.1}×", v[k])).collect();
            json!({ "mode": m.name, "cases": cases })
        })
        .collect();
    // The 7× target: flock-certified + batched, with free flight, and with the default numerics.
    let targets: Vec<_> = [4, 7, 8]
        .into_iter()
        .map(|k| {
            let of = || bars.iter().map(|(_, v)| v[k]);
            json!({
                "met": of().filter(|&s| s >= 7.0).count(), "cases": bars.len(),
                "lo": fixed(of().fold(f64::INFINITY, f64::min), 1), "hi": fixed(of().fold(0.0, f64::max), 1),
            })
        })
        .collect();
    out.readme(
        include_str!("readme/drops_certificate_speed.md"),
        json!({
            "n": n, "seed": seed, "batch": DEFAULT_BATCH, "rows": rows, "sweep": sweep, "speedups": speedups,
            "targets": targets, "modes": MODES.iter().map(|m| m.name).collect::<Vec<_>>(), "flocks": flocks,
        }),
    )?;
    out.write("speed.csv", csv)?;
    plot(&out, &bars)
}

/// The speed-ups of the plotted modes, one group of bars per body and preset.
fn plot(out: &Results, bars: &[(String, Vec<f64>)]) -> Result<()> {
    const BLACK: RGBColor = RGBColor(0, 0, 0);
    let top = bars.iter().flat_map(|(_, v)| v.iter().copied()).fold(1.0, f64::max) * 1.15;
    let (names, right) = (bars.iter().map(|b| b.0.clone()).collect(), bars.len() as f64 - 0.5);
    let plotted: Vec<Vec<f64>> = bars.iter().map(|(_, v)| PLOTTED.map(|s| v[s]).to_vec()).collect();
    Chart::new(Axis::categories("", names), Axis::linear("speed-up (same run, same drops)", 0.0, top))
        .title("Drops per core: speed-up over plain (one drop per world, full settling)")
        .grouped_bars(&plotted, &PLOTTED.map(|s| MODES[s].name.to_string()), 0.0, 0.84)
        .line_width(&[(-0.5, 7.0), (right, 7.0)], BLACK, 1)
        .legend(Mark::Line(BLACK), "target 7×")
        .save(&out.path("speedup.png"), (1300, 640))?;
    Ok(())
}
