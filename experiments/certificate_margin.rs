//! What a sharper energy certificate would buy: the certificate of `dynamics::engine::run`
//! asks the merge tree with the energy level L = E/(m g) raised by a fixed margin
//! (`run::CERTIFICATE_MARGIN`, in R_max) and only every `run::CERTIFICATE_EVERY` steps. Here
//! every drop is simulated to rest once (reference numerics, one stone per world, no
//! certificate) with an observer that asks, at every step and for every margin of a sweep from
//! 0 to the default, whether the facet or the flock would be decided. Per body, preset and
//! level this gives, for each margin:
//!
//! * how many drops it decides and how many of those decisions are **wrong** (not the facet or
//!   flock the drop actually rests on): the margin's necessity, measured;
//! * the mean simulated time per drop a run with that margin would need (the decision's step,
//!   or the time to rest where it never decides), checked every step and every
//!   `CERTIFICATE_EVERY` steps: the gain a sharper margin or more frequent checks could give.
//!
//! The contact's compression at rest and the energy rise between relaxed states, which the
//! margin covers, are measured per body and dt in `results/drops_dt/`.
//!
//! Run: `cargo run --release --example certificate_margin [-- N]` (N = 1000 drops per body and
//! preset) → `results/certificate_margin/`.

#[path = "shared/benchmark_bodies.rs"]
mod benchmark_bodies;
use benchmark_bodies::benchmark_bodies;
use rayon::prelude::*;
use rocking_stones::analysis::Options;
use rocking_stones::dynamics::certificate::{
    CertificateMode, EnergyCertificate, CERTIFICATE_MARGIN, CERTIFICATE_MAX_COMPRESSION,
};
use rocking_stones::dynamics::drops::launch::{launch, release_height};
use rocking_stones::dynamics::drops::params::{DropParams, Preset};
use rocking_stones::dynamics::engine::rest::RestKind;
use rocking_stones::dynamics::engine::run::{
    run_to_end as run_one, Certificate, Decided, NoCertificate, Passive, CERTIFICATE_EVERY,
};
use rocking_stones::dynamics::engine::simulation::Simulation;
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::plot::{series_color, FONT_FAMILY};
use rocking_stones::rng::item_rng;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const READING: &str = r"* **Why so little.** Most of the time a certificate needs is the time the stone takes to come
  down from its release energy (of the order of R_max) to the barrier of the basin or flock it
  ends in; the margin only moves the end of that descent. It matters where the barrier itself is
  of the order of the margin: the micro-barriers between the facets of a smooth pebble, where the
  default margin decides nothing at the facet level and a margin of the order of the pebble's
  rest compression (2.7·10⁻⁴ R_max, `results/drops_dt/`) decides most drops — and still saves
  only about a tenth of the simulated time, since the drop must first come down into the facet's
  basin.
* **So the certificate keeps one margin for every stone** (3·10⁻³ R_max, covering the measured
  energy rise between relaxed states, ≤ 10⁻³ R_max at every dt, and the compression at rest,
  ≤ 10⁻³ R_max, with room to spare) and its check every 4 steps: a margin per stone from its
  measured compression would need its own validation on every stone for a gain of a few per
  cent, and checking every step would ask four times as many descents (at every 4 steps the
  certificate is ≈ 4 % of the profile of a certified throw, `results/drops_certificate/`) to save
  at most a step or two per drop.
";

/// The margins swept (R_max), the default last.
const MARGINS: [f64; 6] = [0.0, 1e-4, 3e-4, 1e-3, 2e-3, CERTIFICATE_MARGIN];

/// A margin as the tables print it.
fn show(m: f64) -> String {
    if m == 0.0 {
        "0".into()
    } else {
        format!("{m:.0e}")
    }
}

/// Seed of the drops (the same drops for every margin).
const SEED: u64 = 11;

/// The first step at which one (margin, level) decides, checked every step and every
/// `CERTIFICATE_EVERY` steps, and what it decided.
#[derive(Clone, Copy, Default)]
struct First {
    every_step: Option<(u64, usize)>,
    every_k: Option<(u64, usize)>,
}

/// One drop: its rest (facet, flock), steps to rest, and per level (facet, flock) and margin the
/// first decisions.
struct Observed {
    facet: usize,
    flock: Option<usize>,
    steps: u64,
    first: [[First; MARGINS.len()]; 2],
}

/// The certificates asked at every step: per margin, the facet and the flock level.
type Certificates<'a> = Vec<[EnergyCertificate<'a>; 2]>;

fn certificates(stone: &Stone) -> Certificates<'_> {
    let at = |mode, m| EnergyCertificate::with_margin(stone, mode, m).expect("a certificate");
    MARGINS.iter().map(|&m| [at(CertificateMode::Facet, m), at(CertificateMode::Flock, m)]).collect()
}

fn observe(stone: &Stone, certs: &Certificates, p: &DropParams, i: u64) -> Observed {
    let r = launch(&mut item_rng(SEED, i), p);
    let z0 = release_height(stone, p, &r);
    let mut sim = Simulation::new(&stone.body, &p.sim, &r.orientation, z0, &r.linvel, &r.angvel);
    let mut first = [[First::default(); MARGINS.len()]; 2];
    let mut step = 0u64;
    let end = run_one(&mut sim, &p.sim, &mut Passive, &NoCertificate, RestKind::Speeds, &mut |s| {
        step += 1;
        for (k, pair) in certs.iter().enumerate() {
            for (lvl, cert) in pair.iter().enumerate() {
                let f = &mut first[lvl][k];
                if f.every_k.is_some() {
                    continue;
                }
                let d = match cert.decided(s) {
                    Some(Decided::Facet(f)) => f as usize,
                    Some(Decided::Flock(k)) => k as usize,
                    None => continue,
                };
                f.every_step.get_or_insert((step, d));
                if step % CERTIFICATE_EVERY == 0 {
                    f.every_k = Some((step, d));
                }
            }
        }
    });
    let rest = stone.rest(&end.state.down);
    Observed {
        facet: rest.facet as usize,
        flock: stone.facet_flock.get(rest.facet as usize).copied().flatten(),
        steps: end.steps,
        first,
    }
}

/// One row: a margin's decisions on one body, preset and level.
struct Row {
    decided: usize,
    wrong: usize,
    mean_time_every_step: f64,
    mean_time_every_k: f64,
}

/// What sharper margins and more frequent checks save on one body, preset and level.
struct Saving {
    level: usize,
    /// Mean simulated time per drop at the sharpest margin without a wrong decision (every
    /// step), ÷ the default certificate's.
    best: f64,
    /// Seconds per drop saved by checking every step at the default margin.
    every_step_gain: f64,
    wrong_at_zero: usize,
    decided_at_zero: usize,
    largest_wrong_margin: Option<f64>,
}

fn summarise(obs: &[Observed], lvl: usize, k: usize, dt: f64) -> Row {
    let (mut decided, mut wrong, mut t1, mut tk) = (0, 0, 0.0, 0.0);
    for o in obs {
        let truth = if lvl == 0 { Some(o.facet) } else { o.flock };
        let f = o.first[lvl][k];
        if let Some((_, d)) = f.every_step {
            decided += 1;
            wrong += usize::from(Some(d) != truth);
        }
        t1 += f.every_step.map_or(o.steps, |(s, _)| s) as f64 * dt;
        tk += f.every_k.map_or(o.steps, |(s, _)| s) as f64 * dt;
    }
    let n = obs.len() as f64;
    Row { decided, wrong, mean_time_every_step: t1 / n, mean_time_every_k: tk / n }
}

fn main() -> anyhow::Result<()> {
    let n: u64 = std::env::args().nth(1).map_or(1000, |s| s.parse().expect("N"));
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let out = root.join("results/certificate_margin");
    std::fs::create_dir_all(&out)?;
    let bodies = benchmark_bodies(&root, false)?;
    let mut md = String::new();
    let mut csv = String::from(
        "body,preset,level,margin_rmax,drops,decided,wrong,mean_time_every_step_s,mean_time_every_k_s,mean_time_to_rest_s\n",
    );
    writeln!(md, "# What a sharper certificate would buy: the margin and the check interval\n")?;
    writeln!(
        md,
        "Generated by `cargo run --release --example certificate_margin -- {n}`: per body and preset, {n} drops \
         (seed {SEED}, the default numerics: exact landings and sub-stepped impacts at dt 1/{:.0} s, one stone per world, surface steel on wood) \
         simulated to rest once, with the merge tree asked at every step whether the stable facet (facet level) or \
         the flock (flock level) is decided at the energy level L + margin, for each margin (R_max) — only while the \
         contact is relaxed (compression ≤ {CERTIFICATE_MAX_COMPRESSION} R_max), as the certificate does. \
         *decided*: drops decided before rest; *wrong*: decisions that are not where the drop rests; *mean s per \
         drop*: the decision's time, or the time to rest where it never decides — what a run with that margin \
         would simulate, with a check every step or every {CERTIFICATE_EVERY} steps (the default). The default \
         margin is {CERTIFICATE_MARGIN} R_max.\n",
        1.0 / Preset::Drop.params(Surface::SteelOnWood).sim.numerics.dt
    )?;
    writeln!(
        md,
        "| body | preset | level | margin (R_max) | decided | wrong | mean s per drop, every step | every {CERTIFICATE_EVERY} steps | vs default margin | full settling |"
    )?;
    writeln!(md, "|---|---|---|---|---|---|---|---|---|---|")?;
    let mut curves: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let mut stats: Vec<Saving> = Vec::new();
    for (name, a) in &bodies {
        let stone = Stone::new(a, a.macro_nu(&Options::default()).0)?;
        let certs = certificates(&stone);
        for preset in [Preset::Drop, Preset::Throw] {
            let p = preset.params(Surface::SteelOnWood);
            let obs: Vec<Observed> = (0..n).into_par_iter().map(|i| observe(&stone, &certs, &p, i)).collect();
            let rest = obs.iter().map(|o| o.steps as f64 * p.sim.numerics.dt).sum::<f64>() / n as f64;
            eprintln!("{name} {preset}: {n} drops observed");
            for (lvl, level) in ["facet", "flock"].into_iter().enumerate() {
                let rows: Vec<Row> = (0..MARGINS.len()).map(|k| summarise(&obs, lvl, k, p.sim.numerics.dt)).collect();
                let default = rows.last().expect("the default margin").mean_time_every_k;
                for (k, row) in rows.iter().enumerate() {
                    let m = MARGINS[k];
                    writeln!(
                        md,
                        "| {name} | {preset} | {level} | {} | {} | {} | {:.3} | {:.3} | {:.2}× | {rest:.3} |",
                        show(m),
                        row.decided,
                        row.wrong,
                        row.mean_time_every_step,
                        row.mean_time_every_k,
                        row.mean_time_every_k / default
                    )?;
                    writeln!(
                        csv,
                        "\"{name}\",{preset},{level},{m:e},{n},{},{},{:.5},{:.5},{rest:.5}",
                        row.decided, row.wrong, row.mean_time_every_step, row.mean_time_every_k
                    )?;
                }
                // The sharpest margin that decided nothing wrongly: what it saves against the default.
                let safe = (0..rows.len()).find(|&k| rows[k..].iter().all(|r| r.wrong == 0)).unwrap_or(rows.len() - 1);
                stats.push(Saving {
                    level: lvl,
                    best: rows[safe].mean_time_every_step / default,
                    every_step_gain: default - rows.last().expect("the default margin").mean_time_every_step,
                    wrong_at_zero: rows[0].wrong,
                    decided_at_zero: rows[0].decided,
                    largest_wrong_margin: rows
                        .iter()
                        .enumerate()
                        .rev()
                        .find(|(_, r)| r.wrong > 0)
                        .map(|(k, _)| MARGINS[k]),
                });
                curves.push((
                    format!("{name}, {preset}, {level}"),
                    rows.iter().enumerate().map(|(k, r)| (MARGINS[k], r.mean_time_every_k / default)).collect(),
                ));
            }
        }
    }
    writeln!(md, "\n![mean simulated time per drop against the margin](margin.png)\n")?;
    writeln!(md, "## Reading\n")?;
    let wrong_at_zero: usize = stats.iter().map(|s| s.wrong_at_zero).sum();
    let decided_at_zero: usize = stats.iter().map(|s| s.decided_at_zero).sum();
    let largest_wrong = stats.iter().filter_map(|s| s.largest_wrong_margin).reduce(f64::max);
    let wrong_margins = match largest_wrong {
        Some(w) => {
            let safe = MARGINS.iter().copied().find(|&m| m > w).unwrap_or(CERTIFICATE_MARGIN);
            format!(
                "The largest margin with a wrong decision in this sample is {} R_max, none from {} on",
                show(w),
                show(safe)
            )
        }
        None => "No margin of the sweep decides wrongly in this sample".into(),
    };
    writeln!(
        md,
        "* **Wrong decisions.** With no margin the merge tree decides {wrong_at_zero} of its {decided_at_zero} \
         decisions (both levels, all bodies and presets) wrongly: the contact's compression and the energy the \
         solver injects let the stone cross a barrier just above L. {wrong_margins}; the default, \
         {CERTIFICATE_MARGIN}, covers the worst cases measured over all dt in `results/drops_dt/` (energy rise \
         ≤ 10⁻³, compression at rest ≤ 10⁻³ R_max), which a sample of drops does not bound."
    )?;
    for (lvl, level) in ["Facet", "Flock"].into_iter().enumerate() {
        let of: Vec<&Saving> = stats.iter().filter(|s| s.level == lvl).collect();
        let lo = of.iter().map(|s| s.best).fold(f64::INFINITY, f64::min);
        let hi = of.iter().map(|s| s.best).fold(0.0, f64::max);
        writeln!(
            md,
            "* **{level} level:** the sharpest margin of the sweep without a wrong decision, checked every step, \
             simulates {lo:.2}–{hi:.2}× the mean time per drop of the default certificate; checking every step \
             instead of every {CERTIFICATE_EVERY} saves at most {:.3} s per drop.",
            of.iter().map(|s| s.every_step_gain).fold(0.0, f64::max)
        )?;
    }
    md.push_str(READING);
    std::fs::write(out.join("README.md"), md)?;
    std::fs::write(out.join("margin.csv"), csv)?;
    plot(&out.join("margin.png"), &curves).map_err(|e| anyhow::anyhow!("plot: {e}"))?;
    Ok(())
}

fn plot(path: &Path, curves: &[(String, Vec<(f64, f64)>)]) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    rocking_stones::plot::draw_png(path, (1000, 600), |root| {
        root.fill(&WHITE)?;
        let values = || curves.iter().flat_map(|(_, c)| c.iter().map(|p| p.1));
        let top = values().fold(1.0f64, f64::max) + 0.02;
        let bottom = (values().fold(1.0f64, f64::min) * 20.0).floor() / 20.0 - 0.05;
        let mut chart = ChartBuilder::on(root)
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(60)
            .caption("Mean simulated time per drop vs the certificate's margin (÷ default margin)", (FONT_FAMILY, 20))
            .build_cartesian_2d(-1e-4f64..CERTIFICATE_MARGIN * 1.05, bottom..top)?;
        chart
            .configure_mesh()
            .x_desc("margin (R_max)")
            .y_desc("mean simulated time per drop ÷ at the default margin")
            .x_label_formatter(&|x| format!("{x:.4}"))
            .label_style((FONT_FAMILY, 14))
            .draw()?;
        // Colour by body, line width by level; drop and throw share the colour, throws dashed by marker.
        for (k, (label, c)) in curves.iter().enumerate() {
            let colour = series_color(k / 4).to_rgba();
            let width = if k % 2 == 0 { 1 } else { 3 };
            chart.draw_series(LineSeries::new(c.clone(), colour.stroke_width(width)))?.label(label.clone()).legend(
                move |(x, y)| {
                    let line = PathElement::new(vec![(x - 4, y), (x + 18, y)], colour.stroke_width(width));
                    let marker = if (k / 2) % 2 == 0 {
                        Circle::new((x + 7, y), 4, colour.filled()).into_dyn()
                    } else {
                        TriangleMarker::new((x + 7, y), 5, colour.filled()).into_dyn()
                    };
                    EmptyElement::at((0, 0)) + line + marker
                },
            );
            if (k / 2) % 2 == 0 {
                chart.draw_series(c.iter().map(|&p| Circle::new(p, 4, colour.filled())))?;
            } else {
                chart.draw_series(c.iter().map(|&p| TriangleMarker::new(p, 5, colour.filled())))?;
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerRight)
            .label_font((FONT_FAMILY, 12))
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .draw()?;
        Ok(())
    })?;
    Ok(())
}
