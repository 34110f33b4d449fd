//! `rocking shake`: drive the ground under a resting stone horizontally (sine pulses or a ground
//! motion from a CSV); fragility curves P(topple out of the flock) against peak ground
//! acceleration.

use super::perturb::{select, SimArgs};
use anyhow::{bail, Result};
use rocking_stones::dynamics::perturb::default_pair;
use rocking_stones::dynamics::shake::{self, Motion, Pulse, ShakeConfig, TimeScale};
use rocking_stones::report;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Mesh file (STL, OBJ, PLY). None: the bundled default stone.
    pub mesh: Option<PathBuf>,
    /// Shake the stone resting on these stable micro-equilibria (repeatable). Default: the
    /// deepest regular one and the rocking one with the highest basin barrier.
    #[arg(long = "equilibrium", value_name = "ID")]
    pub equilibria: Vec<usize>,
    /// Sine pulse: amplitude (g), frequency (Hz, for a stone of --size metres), cycles.
    #[arg(long, value_name = "AMP,FREQ,CYCLES", value_parser = parse_pulse, conflicts_with = "motion")]
    pub pulse: Option<[f64; 3]>,
    /// Ground motion: CSV of time (s, for a stone of --size metres) and acceleration (g).
    #[arg(long, value_name = "FILE.csv")]
    pub motion: Option<PathBuf>,
    /// Sweep the peak ground acceleration from PGA_MAX/STEPS to PGA_MAX (g), scaling the motion
    /// to each: fragility curves. Without a motion the default is a sweep of a 2-cycle pulse of
    /// 2 Hz (scaled) up to 1 g; with --pulse or --motion and no --pga-max, the motion is run at
    /// its own amplitude only.
    #[arg(long)]
    pub pga_max: Option<f64>,
    #[arg(long, default_value_t = 20)]
    pub pga_steps: usize,
    /// Size of the real stone, R_max in metres: frequencies and record times are real and are
    /// converted to the scaled 1 m body (f_scaled = f_real·√size).
    #[arg(long, default_value_t = 1.0)]
    pub size: f64,
    /// Shake along this azimuth (degrees, in the frame of the resting stone) instead of a
    /// random azimuth per trial.
    #[arg(long)]
    pub azimuth: Option<f64>,
    /// Trials per equilibrium and PGA.
    #[arg(short = 'n', long, default_value_t = 40)]
    pub trials: u32,
    /// Seed of the random azimuths.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[command(flatten)]
    pub sim: SimArgs,
    #[arg(long)]
    pub json: bool,
    /// Write shake.json, fragility.csv, trials.csv, fragility.png/.svg and report.html into this folder.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

fn parse_pulse(s: &str) -> Result<[f64; 3], String> {
    let v: Vec<f64> =
        s.split(',').map(|x| x.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|e| format!("{e}"))?;
    match v.as_slice() {
        [a, f, c] => Ok([*a, *f, *c]),
        _ => Err(format!("expected AMP,FREQ,CYCLES, got {s:?}")),
    }
}

pub fn run(args: Args) -> Result<()> {
    let params = args.sim.params()?;
    if !(args.size > 0.0 && args.size.is_finite()) {
        bail!("--size must be positive");
    }
    let scale = TimeScale { r_max_m: args.size };
    let (motion, default_sweep) = match (&args.pulse, &args.motion) {
        (Some([a, f, c]), _) => {
            (Motion::Pulse(Pulse { amplitude: *a, frequency: scale.to_scaled_frequency(*f), cycles: *c }), false)
        }
        (None, Some(path)) => (Motion::Record(shake::read_record(path, scale)?), false),
        (None, None) => (Motion::Pulse(Pulse { amplitude: 1.0, frequency: 2.0, cycles: 2.0 }), true),
    };
    let pga_max = args.pga_max.or(default_sweep.then_some(1.0));
    let pgas = match pga_max {
        Some(m) => {
            if m.is_nan() || m <= 0.0 || args.pga_steps == 0 {
                bail!("need --pga-max > 0 and --pga-steps ≥ 1");
            }
            (1..=args.pga_steps).map(|i| m * i as f64 / args.pga_steps as f64).collect()
        }
        None => vec![motion.peak()],
    };
    let (analysis, stone, name) = args.sim.stone(args.mesh.as_deref())?;
    let starts = if args.equilibria.is_empty() {
        let (regular, rocking) = default_pair(&stone, &params);
        let v: Vec<usize> = regular.into_iter().chain(rocking).collect();
        if v.is_empty() {
            bail!("no stable micro-equilibrium of this stone stays at rest in the simulation");
        }
        v
    } else {
        select(&stone, &args.equilibria, None)?
    };
    let cfg = ShakeConfig {
        params,
        motion,
        pgas,
        trials: args.trials,
        seed: args.seed,
        azimuth: args.azimuth.map(f64::to_radians),
        scale,
    };
    cfg.check()?;
    let bar = super::progress_bar(starts.len() as u64 * cfg.pgas.len() as u64 * cfg.trials as u64, "trials");
    let report = shake::run_with(&stone, &starts, &cfg, &|| bar.inc(1));
    bar.finish_and_clear();
    super::emit(
        &report,
        args.json,
        || report::shake::summary(&report, &name),
        args.output.as_deref(),
        |dir| {
            let mut w = report::shake::write_outputs(&report, &name, dir)?;
            let view = super::hull_view(&analysis, &name, stone.nu);
            let title = format!("rocking shake: {}", report::short_name(&name));
            report::html::add_page(dir, &mut w, &title, &report::shake::summary(&report, &name), Some(&view))?;
            Ok(w)
        },
    )
}
