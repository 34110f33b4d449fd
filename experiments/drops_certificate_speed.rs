//! Drops per second per core for the `drop` and `throw` presets, one drop per rapier
//! world (plain) or many (batched, [`rocking_stones::dynamics::drops::batch`]), with full settling or
//! the energy certificate (facet and flock level), same drops (same seed) in every mode, on the
//! bundled stone, a ≈500-hull-vertex synthetic pebble and a box 1 × 0.8 × 0.5; every mode's
//! outcomes are compared drop by drop with the plain mode's (batched: bit-identical; certified:
//! same facet / flock), and the per-flock statistics of every mode are given against the
//! quasi-static probabilities. A batch-size sweep picks `montecarlo::DEFAULT_BATCH`.
//!
//! Run: `cargo run --release --example drops_certificate_speed [-- N]` (N = 1000 drops per mode;
//! one thread, so the figures are per core) → `results/drops_certificate/`.

#[path = "shared/benchmark_bodies.rs"]
mod benchmark_bodies;
#[path = "shared/cpu_time.rs"]
mod cpu_time;
use benchmark_bodies::benchmark_bodies;
use cpu_time::thread_cpu_seconds;
use rocking_stones::analysis::Options;
use rocking_stones::dynamics::certificate::{certificate, CertificateMode};
use rocking_stones::dynamics::drops::launch::DropOutcome;
use rocking_stones::dynamics::drops::montecarlo::{
    run_drops_batched, summarize, DropReport, RunHeader, Shard, DEFAULT_BATCH, FORMAT,
};
use rocking_stones::dynamics::drops::params::Preset;
use rocking_stones::dynamics::engine::params::{Flight, REFERENCE_DT};
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::plot::{series_color, FONT_FAMILY};
use rocking_stones::stats::chi_square_homogeneity;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// One mode: stones per world (1 = plain), certificate, flight, and whether it runs the
/// preset's default step (its longest stable one, 1/120 s, `Preset::largest_stable_dt`) rather
/// than the reference step [`REFERENCE_DT`] = 1/240 s.
#[derive(Clone, Copy)]
struct Mode {
    name: &'static str,
    batch: usize,
    cert: CertificateMode,
    flight: Flight,
    default_step: bool,
}

impl Mode {
    /// The reference numerics (rapier flight, 1/240 s): outcomes comparable drop by drop, bit
    /// for bit, with plain.
    fn reference(&self) -> bool {
        self.flight == Flight::Rapier && !self.default_step
    }
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

const READING: &str = r"
* **Reference numerics** (rapier flight, dt 1/240 s): batched outcomes are bit-identical to
  plain ones drop by drop (the *same outcome* column compares the whole outcome record, floats as
  bits; `tests/batch.rs` checks batch sizes 1, 7, 32 and 1–2 threads); certified outcomes have
  the plain drop's facet / flock in every case.
* **Free flight** (`--flight free`) and the **default numerics** (free flight at the preset's
  longest stable step, 1/120 s for `drop` and `throw`, `Preset::largest_stable_dt`; `--fast` before
  it became the default) integrate differently from
  plain, so a chaotic throw ends elsewhere drop by drop (the *same outcome* column then compares
  the facet or flock only); their per-flock statistics are compared with plain's by Pearson's χ²
  test of homogeneity (the *χ² p* column: no p below 0.05 in this run means no difference this
  sample can resolve — a few per cent of a flock's share).
* **Where the time goes.** Most of a throw's simulated time is flight: the release height and then
  the hops of a spinning body (the bundled stone's throw: 3.7 of its 4.3 s up to the flock
  certificate's decision are spent more than 0.01 R_max above the ground). In rapier a step in
  flight still costs ≈ 1.2 µs per stone (broad phase, the half-space pair, island and integration
  stages) against ≈ 4 µs in contact; free flight takes it to ≈ 0.1 µs. What remains is the contact
  phase (a profile of the flock-certified, batched, free-flight throws of the bundled stone: the
  solver ≈ 35 %, contact generation and the hull's support queries ≈ 20 %, the free flight itself
  ≈ 10 %, the certificate ≈ 4 %). The certificate's gain is the simulated time it saves (the mean
  simulated s column): large where one flock's basin is reached early (the pebble's drop),
  smaller for throws, which slide and roll with translational energy that the energy bound must
  count.
* **Noise.** CPU times move with the load of this shared machine: the two timings of the same
  plain run can differ by 20 % or more (see the plain rows), and before every mode was timed
  twice one run at 1/120 s came out a third slower than in the runs before and after it; with the
  faster of two timings per mode, read a single ratio as ± 15 %.
";

struct ModeRun {
    report: DropReport,
    outcomes: BTreeMap<u64, DropOutcome>,
    seconds: f64,
}

fn header(name: &str, n: u64, preset: Preset, m: &Mode) -> RunHeader {
    let mut params = preset.params(Surface::SteelOnWood);
    params.sim.flight.mode = m.flight;
    if !m.default_step {
        params.sim.numerics.dt = REFERENCE_DT;
    }
    RunHeader {
        format: FORMAT.into(),
        mesh: name.into(),
        mesh_fingerprint: String::new(),
        seed: 7,
        drops: n,
        params,
        certificate: m.cert,
        preset: Some(preset.name().into()),
        center_of_mass: None,
        shard: Shard::ALL,
    }
}

/// Run every drop of `h` with `batch` stones per world on the current (one-thread) pool; the
/// time is the worker thread's CPU time.
fn timed(stone: &Stone, h: &RunHeader, batch: usize) -> ModeRun {
    let sink = Mutex::new(|_: &DropOutcome| {});
    let cert = certificate(stone, h.certificate);
    let t = thread_cpu_seconds();
    let out = run_drops_batched(stone, h, Shard::ALL, &BTreeMap::new(), cert.as_ref(), batch, &sink);
    let seconds = thread_cpu_seconds() - t;
    let outcomes: BTreeMap<u64, DropOutcome> = out.into_iter().map(|o| (o.index, o)).collect();
    ModeRun { report: summarize(&stone.model(), h, &outcomes), outcomes, seconds }
}

fn main() -> anyhow::Result<()> {
    let n: u64 = std::env::args().nth(1).map_or(1000, |s| s.parse().expect("N"));
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let out = root.join("results/drops_certificate");
    std::fs::create_dir_all(&out)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let bodies = benchmark_bodies(&root, true)?;
    let mut s = String::new();
    let mut csv = String::from(
        "body,preset,mode,batch,certificate,flight,dt,drops,seconds,drops_per_s,speedup_vs_plain,mean_sim_time_s,\
         settled,certified,same_outcome_as_plain,chi2_p_flocks_vs_plain,kl_flocks\n",
    );
    writeln!(s, "# Drops per second per core: plain, batched and certified, and agreement with plain\n")?;
    writeln!(
        s,
        "Generated by `cargo run --release --example drops_certificate_speed -- {n}`: {n} drops per preset and mode, \
         seed 7, **one thread** (figures per core), surface steel on wood, the same drops (same seed and index) in \
         every mode. Times are the CPU time of the one worker thread (not wall time, which on this shared machine counts other jobs). *batched*: {DEFAULT_BATCH} stones per rapier world (`montecarlo::DEFAULT_BATCH`). Speed-ups \
         are against the plain mode of the same body and preset measured in the same run. Every mode is timed \
         twice and the faster run is used (the CPU time of a thread still grows with what the other core of this \
         shared machine runs, by up to a third in one run); plain is timed before and after the other modes and both \
         are given. The simulated-time column is the machine-independent measure of what a certificate saves. *same \
         outcome as plain*: for full settling with the reference numerics, the drop's outcome record is \
         bit-identical (facet, time and final height as f64); otherwise the same facet (full settling, facet \
         level) or flock (flock level) as the plain drop.\n"
    )?;
    writeln!(s, "| body | preset | mode | drops/s | speed-up vs plain | mean simulated s per drop | settled | certified | same outcome as plain | χ² p vs plain (flocks) | KL flocks vs static |")?;
    writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|")?;
    let mut flock_tables = String::new();
    let mut bars: Vec<(String, Vec<f64>)> = Vec::new();
    for (name, a) in &bodies {
        let (nu, _) = a.macro_nu(&Options::default());
        let stone = Stone::new(a, nu)?;
        for preset in [Preset::Drop, Preset::Throw] {
            let plain_first = pool.install(|| timed(&stone, &header(name, n, preset, &MODES[0]), 1));
            let mut runs: Vec<ModeRun> = Vec::new();
            for m in &MODES[1..] {
                let once = || pool.install(|| timed(&stone, &header(name, n, preset, m), m.batch));
                let (first, again) = (once(), once());
                let r = if again.seconds < first.seconds { again } else { first };
                eprintln!("{name} {preset} {}: {:.1} drops/s", m.name, n as f64 / r.seconds);
                runs.push(r);
            }
            let plain_again = pool.install(|| timed(&stone, &header(name, n, preset, &MODES[0]), 1));
            let plain_seconds = plain_first.seconds.min(plain_again.seconds);
            eprintln!(
                "{name} {preset} plain: {:.1} / {:.1} drops/s",
                n as f64 / plain_first.seconds,
                n as f64 / plain_again.seconds
            );
            let first_seconds = plain_first.seconds;
            let plain = ModeRun { seconds: plain_seconds, ..plain_first };
            runs.insert(0, plain);
            let plain = &runs[0];
            let flock_of = |x: &DropOutcome| {
                x.flock.map(|k| k as usize).or_else(|| x.facet.and_then(|f| stone.facet_flock[f as usize]))
            };
            let mut speedups = Vec::new();
            for (m, r) in MODES.iter().zip(&runs) {
                let same = r
                    .outcomes
                    .iter()
                    .filter(|(i, o)| {
                        let p = &plain.outcomes[*i];
                        match m.cert {
                            CertificateMode::None if m.reference() => o == &p,
                            CertificateMode::None => o.facet == p.facet,
                            CertificateMode::Facet => o.facet == p.facet,
                            CertificateMode::Flock => flock_of(o) == flock_of(p),
                        }
                    })
                    .count();
                let counts = |run: &ModeRun| -> Vec<u64> {
                    plain
                        .report
                        .flocks
                        .iter()
                        .map(|f| run.report.flocks.iter().find(|g| g.id == f.id).map_or(0, |g| g.count))
                        .collect()
                };
                let (_, _, p_value) = chi_square_homogeneity(&counts(plain), &counts(r));
                let rate = n as f64 / r.seconds;
                let speedup = plain.seconds / r.seconds;
                speedups.push(speedup);
                let rate_cell = if m.batch == 1 && m.cert == CertificateMode::None {
                    format!("{rate:.1} ({:.1} / {:.1})", n as f64 / first_seconds, n as f64 / plain_again.seconds)
                } else {
                    format!("{rate:.1}")
                };
                writeln!(
                    s,
                    "| {name} | {preset} | {} | {rate_cell} | {speedup:.1}× | {:.2} | {} | {} | {same}/{n} | {p_value:.2} | {:.4} |",
                    m.name, r.report.mean_time, r.report.settled, r.report.certified, r.report.fit_flocks.kl_divergence
                )?;
                writeln!(
                    csv,
                    "\"{name}\",{preset},{},{},{},{},{},{n},{:.3},{rate:.2},{speedup:.3},{:.4},{},{},{same},{p_value:.4},{:.5}",
                    m.name,
                    m.batch,
                    m.cert.name(),
                    r.report.params.sim.flight.mode,
                    r.report.params.sim.numerics.dt,
                    r.seconds,
                    r.report.mean_time,
                    r.report.settled,
                    r.report.certified,
                    r.report.fit_flocks.kl_divergence
                )?;
            }
            let short = ["stone", "pebble", "box"][bars.len() / 2];
            bars.push((format!("{short}, {preset}"), speedups));
            writeln!(flock_tables, "\n### {name}, {preset}\n")?;
            write!(flock_tables, "| flock | type | static |")?;
            for m in &MODES {
                write!(flock_tables, " {} |", m.name)?;
            }
            writeln!(flock_tables, "\n|---|---|---|{}", "---|".repeat(MODES.len()))?;
            for f in &plain.report.flocks {
                write!(
                    flock_tables,
                    "| {} | {} | {:.3} |",
                    f.id,
                    format!("{:?}", f.kind).to_lowercase(),
                    f.static_probability
                )?;
                for r in &runs {
                    let cell = r
                        .report
                        .flocks
                        .iter()
                        .find(|g| g.id == f.id)
                        .map_or("—".into(), |g| format!("{:.3} [{:.3}, {:.3}]", g.fraction, g.ci95.0, g.ci95.1));
                    write!(flock_tables, " {cell} |")?;
                }
                writeln!(flock_tables)?;
            }
        }
    }
    // Batch-size sweep on the bundled stone's throws, full settling (the per-step cost only).
    let (name, a) = &bodies[0];
    let stone = Stone::new(a, a.macro_nu(&Options::default()).0)?;
    writeln!(s, "\n## Batch size (bundled stone, throw, full settling, {n} drops, one thread)\n")?;
    writeln!(s, "| stones per world | drops/s | speed-up vs 1 |")?;
    writeln!(s, "|---|---|---|")?;
    let mut base = None;
    for batch in [1, 4, 8, 16, 32, 64, 128] {
        let r = pool.install(|| timed(&stone, &header(name, n, Preset::Throw, &MODES[1]), batch));
        let b = *base.get_or_insert(r.seconds);
        writeln!(s, "| {batch} | {:.1} | {:.2}× |", n as f64 / r.seconds, b / r.seconds)?;
        writeln!(
            csv,
            "\"{name}\",throw,batch sweep,{batch},none,rapier,{:.6},{n},{:.3},{:.2},{:.3},{:.4},{},0,,,",
            REFERENCE_DT,
            r.seconds,
            n as f64 / r.seconds,
            b / r.seconds,
            r.report.mean_time,
            r.report.settled
        )?;
    }
    writeln!(s, "\n![speed-ups](speedup.png)\n")?;
    writeln!(s, "## Reading\n")?;
    for (k, m) in MODES.iter().enumerate().skip(1) {
        let list: Vec<String> = bars.iter().map(|(label, v)| format!("{label} {:.1}×", v[k])).collect();
        writeln!(s, "* **{}** vs plain: {}.", m.name, list.join(", "))?;
    }
    let target = |k: usize| {
        let met = bars.iter().filter(|(_, v)| v[k] >= 7.0).count();
        let lo = bars.iter().map(|(_, v)| v[k]).fold(f64::INFINITY, f64::min);
        let hi = bars.iter().map(|(_, v)| v[k]).fold(0.0, f64::max);
        format!("{met} of {} body × preset cases at ≥ 7× ({lo:.1}–{hi:.1}×)", bars.len())
    };
    writeln!(
        s,
        "\n* **The 7× target** (certified + batched against plain): with the reference numerics, \
         {} — flock-certified + batched + free flight, {}; with the default numerics (1/120 s), {}.",
        target(4),
        target(7),
        target(8)
    )?;
    s.push_str(READING);
    writeln!(s, "\n## Per flock (fraction of drops, 95 % interval; static = quasi-static basin probability)")?;
    s.push_str(&flock_tables);
    std::fs::write(out.join("README.md"), s)?;
    std::fs::write(out.join("speed.csv"), csv)?;
    plot(&out.join("speedup.png"), &bars).map_err(|e| anyhow::anyhow!("plot: {e}"))?;
    Ok(())
}

fn plot(path: &Path, bars: &[(String, Vec<f64>)]) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    rocking_stones::plot::draw_png(path, (1300, 640), |root| {
        root.fill(&WHITE)?;
        let top = bars.iter().flat_map(|(_, v)| v.iter().copied()).fold(1.0, f64::max) * 1.15;
        let mut chart = ChartBuilder::on(root)
            .margin(20)
            .x_label_area_size(60)
            .y_label_area_size(60)
            .caption("Drops per core: speed-up over plain (one drop per world, full settling)", (FONT_FAMILY, 20))
            .build_cartesian_2d(-0.5f64..bars.len() as f64 - 0.5, 0.0f64..top)?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(bars.len() + 1)
            .x_label_formatter(&|x| {
                let k = x.round();
                if (x - k).abs() > 1e-6 || k < 0.0 {
                    return String::new();
                }
                bars.get(k as usize).map_or(String::new(), |b| b.0.clone())
            })
            .y_desc("speed-up (same run, same drops)")
            .label_style((FONT_FAMILY, 13))
            .draw()?;
        let w = 0.84 / PLOTTED.len() as f64;
        for (slot, &s) in PLOTTED.iter().enumerate() {
            let m = &MODES[s];
            let colour = series_color(slot);
            chart
                .draw_series(bars.iter().enumerate().map(|(k, (_, v))| {
                    let x0 = k as f64 - 0.42 + slot as f64 * w;
                    Rectangle::new([(x0, 0.0), (x0 + w * 0.9, v[s])], colour.filled())
                }))?
                .label(m.name)
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 14, y + 5)], colour.filled()));
        }
        chart
            .draw_series(std::iter::once(PathElement::new(vec![(-0.5, 7.0), (bars.len() as f64 - 0.5, 7.0)], BLACK)))?
            .label("target 7×")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], BLACK));
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .label_font((FONT_FAMILY, 13))
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .draw()?;
        Ok(())
    })?;
    Ok(())
}
