//! Fragility of a rocking vs a regular equilibrium under ground shaking (precariously balanced
//! rocks): P(topple out of the flock) against peak ground acceleration for sine pulses of
//! several frequencies and for a recorded-style ground motion read from a CSV.
//!
//! The pebble and its two equilibria are those of `fig11_rocking_vs_regular` (the first seed of
//! `generate::pebble([1, 0.75, 0.5], 0.02, 600, seed)` with a convincingly balanced rocking
//! equilibrium; `default_pair`), here a boulder of R_max = 1 m on rock (`Surface::StoneOnStone`:
//! the contact of every resting run at its real size). Each trial shakes along a uniformly random
//! azimuth. The recorded-style motion is a synthetic accelerogram (Kanai–Tajimi / Clough–Penzien
//! filtered noise, predominant period 0.4 s, 10 s; `ground_motion::synthetic::filtered_noise`),
//! written to `motion.csv` and read back through the same reader as the CLI's `--motion`.
//!
//! Run: `cargo run --release --example fragility_shaking` → `results/fragility_shaking/`.

use plotters::style::RGBColor;
use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::resting::outcome::{CurvePoint, Threshold};
use rocking_stones::dynamics::resting::{default_pair, RestingParams};
use rocking_stones::dynamics::shaking::{self, sine_pulse, ShakeConfig, ShakeReport};
use rocking_stones::dynamics::stone::{Class, Stone};
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::generate;
use rocking_stones::ground_motion::read::{read_record, AccelUnit};
use rocking_stones::ground_motion::synthetic::{filtered_noise, Noise};
use rocking_stones::ground_motion::Record;
use rocking_stones::report;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const TRIALS: u32 = 40;
const SEED: u64 = 1963;
const FREQUENCIES: [f64; 4] = [0.5, 1.0, 2.0, 4.0];
/// R_max of the boulder (m): real and scaled time agree.
const R_MAX_M: f64 = 1.0;
/// The surface pair.
const SURFACE: Surface = Surface::StoneOnStone;

fn main() -> anyhow::Result<()> {
    let out = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("results/fragility_shaking");
    std::fs::create_dir_all(&out)?;
    let params = RestingParams::on_surface(SURFACE, R_MAX_M)?;
    let (seed, stone, regular, rocking) = (0..50u64)
        .find_map(|seed| {
            let (mesh, rep) = generate::pebble([1.0, 0.75, 0.5], 0.02, 600, seed).into_solid_boundary().ok()?;
            let a = Analysis::of_solid(mesh, rep, &Options::default()).ok()?;
            let (nu, _) = a.macro_nu(&Options::default());
            let stone = Stone::new(&a, nu).ok()?;
            let (reg, rock) = default_pair(&stone, &params);
            let ok = rock.is_some_and(|r| stone.stable()[r].basin_exit.epsilon >= 1e-4) && reg.is_some();
            ok.then(|| (seed, stone, reg.unwrap(), rock.unwrap()))
        })
        .expect("a pebble with a rocking equilibrium");
    eprintln!("pebble seed {seed}: regular {regular}, rocking {rocking}");
    let noise = Noise { duration: 10.0, period: 0.4, ..Noise::default() };
    let record = filtered_noise(&noise, 1.0, SEED)?;
    let csv = out.join("motion.csv");
    report::shake::write_record(&csv, &record)?;
    let dt = params.sim.numerics.dt * R_MAX_M.sqrt();
    let mut motions: Vec<(String, Record)> = FREQUENCIES
        .iter()
        .map(|&f| Ok((format!("pulse_{f}Hz"), sine_pulse(1.0, f, 2.0, dt)?)))
        .collect::<rocking_stones::Result<_>>()?;
    let columns = "time_s,ax_g,ay_g,az_g".parse()?;
    let mut read_back = read_record(&[csv.as_path()], &columns, AccelUnit::G)?;
    read_back.name = format!("{}, read back from motion.csv", record.name);
    motions.push(("record".into(), read_back));
    let pgas: Vec<f64> = (1..=40).map(|i| 0.025 * i as f64).collect();
    let mut runs: Vec<(String, ShakeReport)> = Vec::new();
    for (name, motion) in motions {
        let cfg = ShakeConfig {
            params: params.clone(),
            motion,
            pgas: pgas.clone(),
            trials: TRIALS,
            seed: SEED,
            azimuth: None,
            r_max_m: R_MAX_M,
        };
        let t = std::time::Instant::now();
        let r = shaking::sweep_fragility(&stone, &[regular, rocking], &cfg)?;
        eprintln!("{name}: {} trials in {:.1} s", r.trials.len(), t.elapsed().as_secs_f64());
        eprint!("{}", report::shake::summary(&r, "pebble"));
        let lines: Vec<(String, &[CurvePoint], RGBColor)> = r
            .fragility
            .iter()
            .map(|f| {
                let q = &f.equilibrium;
                let (label, color) = match q.class {
                    Class::Regular => ("regular", RGBColor(200, 60, 40)),
                    Class::Rocking => ("rocking", RGBColor(40, 90, 200)),
                };
                (format!("{label}: eq {} ({} flock {})", q.index, q.flock_kind, q.flock), f.curve.as_slice(), color)
            })
            .collect();
        let markers: Vec<(f64, String, RGBColor)> = r
            .fragility
            .iter()
            .map(|f| {
                let q = &f.equilibrium;
                let color = match q.class {
                    Class::Regular => RGBColor(230, 150, 130),
                    Class::Rocking => RGBColor(130, 160, 230),
                };
                (q.uplift_acceleration, format!("static uplift, eq {}: {:.3} g", q.index, q.uplift_acceleration), color)
            })
            .collect();
        report::shake::plot_fragility(
            &out.join(format!("fragility_{name}.png")),
            &format!("Fragility: {}", r.motion.name),
            &lines,
            &markers,
        )?;
        report::shake::write_fragility_csv(&out.join(format!("fragility_{name}.csv")), &r)?;
        runs.push((name, r));
    }
    readme(&out.join("README.md"), seed, &stone, &runs)?;
    Ok(())
}

fn th(t: &Option<Threshold>) -> String {
    match t {
        None => "–".into(),
        Some(Threshold::Below(x)) => format!("≤ {x:.3}"),
        Some(Threshold::At(x)) => format!("{x:.3}"),
        Some(Threshold::Above(x)) => format!("> {x:.3}"),
    }
}

fn readme(path: &Path, seed: u64, stone: &Stone, runs: &[(String, ShakeReport)]) -> anyhow::Result<()> {
    let mut s = String::new();
    let params = &runs[0].1.params;
    writeln!(s, "# Fragility under ground shaking: rocking vs regular equilibrium\n")?;
    writeln!(s, "Regenerate: `cargo run --release --example fragility_shaking`.\n")?;
    writeln!(
        s,
        "Pebble `generate::pebble([1, 0.75, 0.5], 0.02, 600, seed {seed})` (the one of `fig11_rocking_vs_regular`), \
         flocks at ν = {:.3e}. The ground is driven horizontally along a uniformly random azimuth per trial \
         (trial k has the same azimuth at every PGA), {TRIALS} trials per PGA, PGA from 0.025 g to 1 g in steps of \
         0.025 g, seed {SEED}. The stone is a boulder of R_max = {R_MAX_M} m on rock: the contact of every resting \
         run ({SURFACE}: friction {}, restitution {}, rolling resistance δ = {:.1e} R_max through the contact, no \
         global damping; 120 Hz contacts, dt 1/240 s scaled), rest by positions over 0.5 s windows. Outcome after \
         the motion, once the stone rests relative to the ground: same micro-equilibrium, another of its flock, or \
         toppled out of the flock (plotted).\n",
        stone.nu, params.sim.contact.friction, params.sim.contact.restitution, params.sim.contact.rolling_resistance,
    )?;
    writeln!(
        s,
        "**Units.** Accelerations are in g and hold for any size. Times and frequencies scale with √(R_max/1 m) \
         (Froude similarity; only the rolling-resistance length δ/R_max breaks it, and it is 10⁻⁴ here): a pulse \
         of f Hz on this 1 m boulder is f/√L Hz for a stone of R_max = L m.\n"
    )?;
    writeln!(s, "| scaled (1 m) | 3 cm pebble | 10 cm cobble | 2 m boulder | 5 m rock |\n|---|---|---|---|---|")?;
    for f in [0.5, 1.0, 2.0, 4.0] {
        let real = |l: f64| f / l.sqrt();
        writeln!(
            s,
            "| {f} Hz | {:.2} Hz | {:.2} Hz | {:.2} Hz | {:.2} Hz |",
            real(0.03),
            real(0.1),
            real(2.0),
            real(5.0)
        )?;
    }
    writeln!(s, "\n| motion | equilibrium | class | static uplift (g) | PGA₅₀ leave micro | PGA₅₀ topple | first topple (g) | trials below uplift: left micro / n |")?;
    writeln!(s, "|---|---|---|---|---|---|---|---|")?;
    for (name, r) in runs {
        for f in &r.fragility {
            let q = &f.equilibrium;
            let below: Vec<_> = r
                .trials
                .iter()
                .filter(|t| t.start == f.equilibrium_position(stone) && t.pga < q.uplift_acceleration)
                .collect();
            let left =
                below.iter().filter(|t| t.outcome != rocking_stones::dynamics::resting::outcome::Outcome::Same).count();
            writeln!(
                s,
                "| {name} | {} (facet {}) | {} | {:.3} | {} | {} | {} | {left} / {} |",
                q.index,
                q.facet,
                q.class,
                q.uplift_acceleration,
                th(&f.pga50_micro),
                th(&f.pga50_flock),
                f.first_topple.map_or("–".into(), |x| format!("{x:.3}")),
                below.len()
            )?;
        }
    }
    writeln!(s)?;
    for (name, _) in runs {
        writeln!(s, "![{name}](fragility_{name}.png)\n")?;
    }
    writeln!(
        s,
        "Static uplift: the quasi-static horizontal acceleration that lifts the stone off its resting facet in the \
         most fragile direction, (distance from the stable point to the nearest side of the facet) / R_F — Housner's \
         tan α for a block. Below it a rigid stone on a rigid ground does not move at all.\n\nFiles: \
         `fragility_<motion>.csv` (per PGA: counts, P(topple) with 95 % Wilson intervals), `motion.csv` (the \
         accelerogram: time in s, acceleration in g; scaled to each PGA)."
    )?;
    std::fs::write(path, s)?;
    Ok(())
}

trait Position {
    fn equilibrium_position(&self, stone: &Stone) -> usize;
}

impl Position for shaking::Fragility {
    fn equilibrium_position(&self, stone: &Stone) -> usize {
        stone.position(self.equilibrium.index).expect("a stable equilibrium")
    }
}
