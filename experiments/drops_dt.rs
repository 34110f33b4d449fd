//! The largest stable time step of the presets (`Preset::largest_stable_dt`), measured:
//! for each
//! dt, on the bundled stone, a ≈500-hull-vertex synthetic pebble and a box 1 × 0.8 × 0.5,
//!
//! * the per-flock statistics of N fully settled drops (batched worlds) against those at the
//!   reference dt = 1/240 s (`REFERENCE_DT`), by Pearson's χ² test of homogeneity (independent seeds per dt, so the
//!   two samples are independent);
//! * on the first M drops, stepped one at a time with an observer: the largest compression of
//!   the soft contact h(down) − z_G (R_max) over the whole run and at rest, and the largest rise
//!   of the energy level L = E/(m g) between two relaxed states once L ≤ R_max (the region where
//!   the certificate decides; it must stay below `run::CERTIFICATE_MARGIN`);
//! * drops that did not settle, settled off their equilibrium, the mean simulated time to rest,
//!   and drops/s (one thread).
//!
//! Run: `cargo run --release --example drops_dt [-- N M]` (N = 400, M = 40: the committed results) → `results/drops_dt/`.

#[path = "shared/benchmark_bodies.rs"]
mod benchmark_bodies;
use benchmark_bodies::benchmark_bodies;
use rocking_stones::analysis::Options;
use rocking_stones::dynamics::certificate::CertificateMode;
use rocking_stones::dynamics::certificate::{CERTIFICATE_MARGIN, CERTIFICATE_MAX_COMPRESSION};
use rocking_stones::dynamics::drops::batch::simulate_batch_observed;
use rocking_stones::dynamics::drops::launch::{launch, DropOutcome};
use rocking_stones::dynamics::drops::montecarlo::{
    run_drops_batched, summarize, DropReport, RunHeader, Shard, DEFAULT_BATCH, FORMAT,
};
use rocking_stones::dynamics::drops::params::{DropParams, Preset};
use rocking_stones::dynamics::engine::run::NoCertificate;
use rocking_stones::dynamics::stone::{Stone, REST_TOLERANCE};
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::plot::FONT_FAMILY;
use rocking_stones::rng::item_rng;
use rocking_stones::stats::chi_square_homogeneity;
use statrs::distribution::{Binomial, DiscreteCDF};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

const DTS: [f64; 7] = [1.0 / 480.0, 1.0 / 240.0, 1.0 / 180.0, 1.0 / 150.0, 1.0 / 120.0, 1.0 / 100.0, 1.0 / 80.0];
const REFERENCE: usize = 1;

/// What the reading's stability point reads of every body, preset and dt (in `DTS` order per
/// body and preset).
#[derive(Default)]
struct Stability {
    drops: u64,
    unsettled: u64,
    compression: f64,
    compression_at_rest: f64,
    rise: f64,
    /// Mean time to rest at 1/80 s over that at 1/240 s, per body and preset.
    time_ratios: Vec<f64>,
    /// Drops/s at 1/120 s over 1/240 s, per body and preset.
    rate_ratios: Vec<f64>,
}

impl Stability {
    fn reading(&self) -> String {
        let range = |v: &[f64]| {
            let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (lo, hi)
        };
        let (t_lo, t_hi) = range(&self.time_ratios);
        let (r_lo, r_hi) = range(&self.rate_ratios);
        let side = |x: f64, bound: f64| if x < bound { "under" } else { "not under" };
        format!(
            "* **Stability.** {} of the {} drops fail to settle (every body, preset and dt); the compression at \
             rest is at most {:.1e} R_max ({} the outcome rule's `REST_TOLERANCE`, {REST_TOLERANCE:.0e}); the \
             compression during the hard first impact of a throw, which reached 0.1 R_max at 1/240 s and 0.2–0.3 \
             R_max at 1/120–1/80 s when rapier found the contacts at its step boundaries, is now at most {:.1e} \
             R_max at any dt (exact landings and sub-stepped impacts, `results/drops_impacts/`). The mean time to \
             rest at 1/80 s is ×{t_lo:.2}–{t_hi:.2} that at 1/240 s over the bodies and presets. The energy rise \
             between relaxed states once L ≤ R_max is at most {:.1e} R_max at any dt, {} the certificate's \
             margin ({CERTIFICATE_MARGIN:.0e}).\n\
             * **The longest stable step** of every preset is therefore the longest `DropParams::check` accepts, \
             1/120 s (`Preset::largest_stable_dt`; the check's cap, four steps per period of the stiffest contact, \
             is kept although 1/80 s passes too). It gives ×{r_lo:.1}–{r_hi:.1} the drops/s of 1/240 s here and is \
             the default of every preset (with free flight; `results/drops_certificate/`); 1/240 s stays the \
             reference it is checked against (`rocking drop --reference`): the throw preset's dice are re-thrown at \
             it in `results/cuboid_dice/`, the same releases compared drop by drop in `results/drops_vs_mujoco/`.\n",
            self.unsettled,
            self.drops,
            self.compression_at_rest,
            side(self.compression_at_rest, REST_TOLERANCE),
            self.compression,
            self.rise,
            side(self.rise, CERTIFICATE_MARGIN),
        )
    }
}

/// Per-step observations of one drop alone in its world.
struct Observed {
    compression: f64,
    compression_at_rest: f64,
    energy_rise: f64,
}

fn observe(stone: &Stone, p: &DropParams, seed: u64, i: u64) -> Observed {
    let r = launch(&mut item_rng(seed, i), p);
    let (mut compression, mut low, mut rise) = (0.0f64, f64::INFINITY, 0.0f64);
    let mut last = None;
    // The run's own numerics (exact landings and sub-stepped impacts by default), one stone.
    simulate_batch_observed(stone, p, &NoCertificate, 1, &mut std::iter::once((i, r)), &mut |_| {}, &mut |_, s| {
        let c = stone.body.support(&s.down) - s.z;
        compression = compression.max(c);
        if c <= CERTIFICATE_MAX_COMPRESSION && s.level <= 1.0 {
            low = low.min(s.level);
            rise = rise.max(s.level - low);
        }
        last = Some(c);
    });
    Observed { compression, compression_at_rest: last.unwrap_or(f64::NAN), energy_rise: rise }
}

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let n: u64 = args.next().map_or(400, |s| s.parse().expect("N"));
    let m: u64 = args.next().map_or(40, |s| s.parse().expect("M"));
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let out = root.join("results/drops_dt");
    std::fs::create_dir_all(&out)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let bodies = benchmark_bodies(&root, false)?;
    let mut md = String::new();
    let mut csv = String::from(
        "body,preset,dt,drops,unsettled,off_equilibrium,mean_time_to_rest_s,drops_per_s,chi2_vs_1_240,dof,p_value,\
         max_compression,max_compression_at_rest,max_energy_rise\n",
    );
    writeln!(md, "# The largest stable time step of the presets\n")?;
    writeln!(
        md,
        "Generated by `cargo run --release --example drops_dt -- {n} {m}`: per body, preset and dt, {n} fully \
         settled drops ({DEFAULT_BATCH} per world, one thread; seed 1000 + k for the k-th dt, so the samples are \
         independent) compared per flock with those at dt = 1/240 s (the default) by Pearson's χ² test of \
         homogeneity; and {m} of them stepped one at a time to measure the contact's compression h(down) − z_G \
         (R_max) during the run and at rest, and the largest rise of L = E/(m g) between relaxed states \
         (compression ≤ {CERTIFICATE_MAX_COMPRESSION}) once L ≤ R_max — what the certificate's margin \
         ({CERTIFICATE_MARGIN} R_max) must cover. Surface steel on wood.\n"
    )?;
    writeln!(md, "| body | preset | 1/dt | unsettled | off equilibrium | mean s to rest | drops/s | χ² vs 1/240 (dof) | p | max compression | at rest | max L rise (relaxed, L ≤ 1) |")?;
    writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|---|")?;
    let mut curves: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    // Every homogeneity test against the reference step, and those below 0.05.
    let (mut tests, mut low) = (0u64, Vec::new());
    let mut stability = Stability::default();
    for (name, a) in &bodies {
        let stone = Stone::new(a, a.macro_nu(&Options::default()).0)?;
        for preset in [Preset::Drop, Preset::Throw, Preset::QuasiStatic] {
            let mut counts: Vec<Vec<u64>> = Vec::new();
            let mut rows = Vec::new();
            for (k, &dt) in DTS.iter().enumerate() {
                let mut params = preset.params(Surface::SteelOnWood);
                params.sim.numerics.dt = dt;
                let header = RunHeader {
                    format: FORMAT.into(),
                    mesh: name.clone(),
                    mesh_fingerprint: String::new(),
                    seed: 1000 + k as u64,
                    drops: n,
                    params: params.clone(),
                    certificate: CertificateMode::None,
                    preset: Some(preset.name().into()),
                    center_of_mass: None,
                    shard: Shard::ALL,
                };
                let sink = Mutex::new(|_: &DropOutcome| {});
                let t = std::time::Instant::now();
                let outcomes = pool.install(|| {
                    run_drops_batched(
                        &stone,
                        &header,
                        Shard::ALL,
                        &BTreeMap::new(),
                        &NoCertificate,
                        DEFAULT_BATCH,
                        &sink,
                    )
                });
                let rate = n as f64 / t.elapsed().as_secs_f64();
                let outcomes: BTreeMap<u64, DropOutcome> = outcomes.into_iter().map(|o| (o.index, o)).collect();
                let report = summarize(&stone.model(), &header, &outcomes);
                let mut c = vec![0u64; stone.flock_kinds.len()];
                for f in &report.flocks {
                    c[f.id] = f.count;
                }
                counts.push(c);
                let obs: Vec<Observed> =
                    pool.install(|| (0..m).map(|i| observe(&stone, &params, 1000 + k as u64, i)).collect());
                let max = |f: &dyn Fn(&Observed) -> f64| obs.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
                rows.push((
                    dt,
                    report,
                    rate,
                    max(&|o| o.compression),
                    max(&|o| o.compression_at_rest),
                    max(&|o| o.energy_rise),
                ));
                eprintln!("{name} {preset} 1/dt = {:.0}: {rate:.0} drops/s", 1.0 / dt);
            }
            let mut curve = Vec::new();
            for (k, (dt, report, rate, comp, comp_rest, rise)) in rows.iter().enumerate() {
                let (chi2, dof, p) = chi_square_homogeneity(&counts[k], &counts[REFERENCE]);
                curve.push((1.0 / dt, p));
                if k != REFERENCE {
                    tests += 1;
                    if p < 0.05 {
                        low.push(format!("{name}, {preset}, 1/{:.0} s: {p:.3}", 1.0 / dt));
                    }
                }
                let t = report.mean_time_to_rest.unwrap_or(f64::NAN);
                stability.drops += report.drops;
                stability.unsettled += report.unsettled;
                stability.compression = stability.compression.max(*comp);
                stability.compression_at_rest = stability.compression_at_rest.max(*comp_rest);
                stability.rise = stability.rise.max(*rise);
                writeln!(
                    md,
                    "| {name} | {preset} | {:.0} | {} | {} | {t:.2} | {rate:.0} | {chi2:.1} ({dof}) | {p:.3} | {comp:.1e} | {comp_rest:.1e} | {rise:.1e} |",
                    1.0 / dt,
                    report.unsettled,
                    report.off_equilibrium
                )?;
                writeln!(
                    csv,
                    "\"{name}\",{preset},{dt:.6},{n},{},{},{t:.4},{rate:.1},{chi2:.3},{dof},{p:.4},{comp:.3e},{comp_rest:.3e},{rise:.3e}",
                    report.unsettled, report.off_equilibrium
                )?;
            }
            let at = |dt: f64| rows.iter().find(|r| (r.0 - dt).abs() < 1e-12).expect("a step of DTS");
            let (reference, fastest, longest) = (at(DTS[REFERENCE]), at(1.0 / 120.0), at(1.0 / 80.0));
            let time = |r: &(f64, DropReport, f64, f64, f64, f64)| r.1.mean_time_to_rest.unwrap_or(f64::NAN);
            stability.time_ratios.push(time(longest) / time(reference));
            stability.rate_ratios.push(fastest.2 / reference.2);
            curves.push((format!("{name}, {preset}"), curve));
        }
    }
    writeln!(md, "\n![p-values](p_values.png)\n")?;
    md.push_str(&statistics_reading(tests, &low));
    md.push_str(&stability.reading());
    std::fs::write(out.join("README.md"), md)?;
    std::fs::write(out.join("dt.csv"), csv)?;
    plot(&out.join("p_values.png"), &curves).map_err(|e| anyhow::anyhow!("plot: {e}"))?;
    Ok(())
}

/// The reading's first point: how many of the `tests` homogeneity tests fall below 0.05 (`low`),
/// against what chance alone gives (a binomial of `tests` trials at 0.05).
fn statistics_reading(tests: u64, low: &[String]) -> String {
    let k = low.len() as u64;
    let chance = Binomial::new(0.05, tests).expect("a binomial");
    let tail = if k == 0 { 1.0 } else { chance.sf(k - 1) };
    let which = if low.is_empty() { String::new() } else { format!(" ({})", low.join("; ")) };
    let verdict = if tail >= 0.05 {
        "no dt from 1/480 to 1/80 s changes the per-flock statistics of any body or preset detectably at this \
         sample size"
    } else {
        "**more than chance gives**: read the rows below 0.05 as a change of the statistics with dt"
    };
    format!(
        "## Reading\n\n* **Statistics.** Of the {tests} homogeneity tests against 1/240 s (every body, preset and dt), \
         {k} {have} p < 0.05{which}, where chance alone gives {:.1} on average{chance}: {verdict}. The test's power \
         is that of independent samples of this size: differences of a few per cent in a flock's share would pass.\n",
        0.05 * tests as f64,
        have = if k == 1 { "has" } else { "have" },
        // The chance of at least k such p-values says something only when some were found.
        chance = if k > 0 { format!(" (P(≥ {k}) = {tail:.2} for a binomial of {tests} trials at 0.05)") } else { String::new() },
    )
}

fn plot(path: &Path, curves: &[(String, Vec<(f64, f64)>)]) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    rocking_stones::plot::draw_png(path, (1000, 600), |root| {
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(root)
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(60)
            .caption("Per-flock statistics vs dt: χ² homogeneity p-value against 1/dt = 240", (FONT_FAMILY, 20))
            .build_cartesian_2d(60.0f64..500.0, (1e-3f64..1.0).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("1/dt (steps per s of the scaled body)")
            .y_desc("p-value (log scale)")
            .x_label_formatter(&|x| rocking_stones::plot::plain(*x))
            .y_label_formatter(&|y| rocking_stones::plot::log_tick(*y))
            .label_style((FONT_FAMILY, 14))
            .draw()?;
        // Colour by body, line width by preset (three presets per body, in curve order).
        for (k, (label, c)) in curves.iter().enumerate() {
            let colour = rocking_stones::plot::series_color(k / 3).to_rgba();
            let width = [3, 1, 2][k % 3];
            // The reference dt itself (p = 1 against itself) is not a comparison: leave it out.
            let pts: Vec<(f64, f64)> =
                c.iter().filter(|&&(x, _)| (x - 240.0).abs() > 1e-6).map(|&(x, p)| (x, p.max(1e-3))).collect();
            chart.draw_series(LineSeries::new(pts.clone(), colour.stroke_width(width)))?.label(label.clone()).legend(
                move |(x, y)| {
                    let line = PathElement::new(vec![(x - 4, y), (x + 18, y)], colour.stroke_width(width));
                    let marker = match k % 3 {
                        0 => Circle::new((x + 7, y), 4, colour.filled()).into_dyn(),
                        1 => TriangleMarker::new((x + 7, y), 5, colour.filled()).into_dyn(),
                        _ => Cross::new((x + 7, y), 4, colour.stroke_width(2)).into_dyn(),
                    };
                    EmptyElement::at((0, 0)) + line + marker
                },
            );
            match k % 3 {
                0 => chart.draw_series(pts.iter().map(|&p| Circle::new(p, 4, colour.filled())))?,
                1 => chart.draw_series(pts.iter().map(|&p| TriangleMarker::new(p, 5, colour.filled())))?,
                _ => chart.draw_series(pts.iter().map(|&p| Cross::new(p, 4, colour.stroke_width(2))))?,
            };
        }
        chart
            .draw_series(std::iter::once(PathElement::new(vec![(60.0, 0.05), (500.0, 0.05)], BLACK)))?
            .label("p = 0.05 (the reading's level)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], BLACK));
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerRight)
            .label_font((FONT_FAMILY, 13))
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .draw()?;
        Ok(())
    })?;
    Ok(())
}
