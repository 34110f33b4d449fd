//! Fragility curves: P(toppled out of the flock) against the peak ground acceleration, for a
//! stone resting on its stable micro-equilibria (precariously balanced rocks).
//!
//! The motion is one [`Record`] (real time, SI): a sine pulse ([`sine_pulse`]), filtered noise
//! ([`crate::ground_motion::synthetic::filtered_noise`]) or a read record. It is scaled to each
//! PGA of a grid ([`Record::scaled_to_pga`]) and each trial shakes along a uniformly random
//! azimuth relative to the stone (common random numbers across PGAs: trial k has the same azimuth
//! at every PGA). A trial is exactly a field-rock run ([`crate::dynamics::shaking::drive::shake_placed`]) of the
//! stone standing on the micro-equilibrium: the same contact at the stone's real size, the same
//! drive, rest rule and outcome rule. The outcome is classified as for pushes (same
//! micro-equilibrium / another of the same flock / toppled out of the flock), with 95 % Wilson
//! intervals and the PGA₅₀ interpolated linearly.

use crate::dynamics::resting::outcome::{classify, Curve, CurvePoint, Outcome, Threshold};
use crate::dynamics::resting::{grid_trials, RestingParams, SettleCheck};
use crate::dynamics::shaking::drive::{shake_placed, Placed};
use crate::dynamics::shaking::rock::driven;
use crate::dynamics::stone::{StableEquilibrium, Stone};
use crate::ground_motion::{synthetic, Measures, Record};
use crate::monitor::Monitor;
use crate::rng::item_rng;
use crate::{Error, Result};
use rand::RngExt;
use serde::Serialize;

/// One shaking trial.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ShakeTrial {
    /// Position of the start in [`Stone::stable`].
    pub start: usize,
    /// Analysis index of the start equilibrium.
    pub equilibrium: usize,
    /// Peak ground acceleration (g).
    pub pga: f64,
    /// Azimuth of shaking (rad, world frame).
    pub azimuth: f64,
    /// Trial number at this (equilibrium, PGA): its random stream.
    pub trial: u32,
    /// Same, same flock or toppled.
    pub outcome: Outcome,
    /// Final facet.
    pub final_facet: u32,
    /// Final stable micro-equilibrium.
    pub final_equilibrium: Option<usize>,
    /// Final flock.
    pub final_flock: usize,
    /// Came to rest before the time cap.
    pub settled: bool,
    /// The stone stopped above its final stable facet; the quasi-static descent decided.
    pub non_stable_facet: bool,
    /// Largest tilt (rad) of the resting facet's normal away from straight down.
    pub max_tilt: f64,
    /// Simulated time from the start of the motion (s, scaled).
    pub time: f64,
    /// The deepest any hull corner went below the ground after any step or sub-step of the run
    /// (R_max, [`crate::dynamics::engine::world::penetration`]), the stone's settling included.
    pub deepest_penetration: f64,
}

/// The sine pulse of the sweep: `cycles` cycles of a(t) = A sin(2π f t) along x, A = `amplitude_g`
/// (g), f = `frequency_hz` (Hz, real), sampled at `dt` (s, real).
pub fn sine_pulse(amplitude_g: f64, frequency_hz: f64, cycles: f64, dt: f64) -> Result<Record> {
    if !(frequency_hz > 0.0 && frequency_hz.is_finite()) {
        return Err(Error::parameter("frequency_hz", frequency_hz, "a positive frequency (Hz)"));
    }
    synthetic::sine_cycles(amplitude_g, 1.0 / frequency_hz, cycles, dt)
}

/// Frequency (Hz of the scaled 1 m body) of the default sweep pulse: 2/√L Hz for a stone of
/// R_max = L metres (Froude scaling), the 2 Hz pulse of `results/fragility_shaking/`.
pub const DEFAULT_PULSE_FREQUENCY_SCALED: f64 = 2.0;

/// The default sweep motion for a stone of real size `r_max_m` metres: 2 cycles of a 1 g sine at
/// [`DEFAULT_PULSE_FREQUENCY_SCALED`] / √L Hz, sampled at the simulation's real step
/// `dt_scaled`·√L (so it is driven as sampled).
pub fn default_pulse(r_max_m: f64, dt_scaled: f64) -> Result<Record> {
    let f = DEFAULT_PULSE_FREQUENCY_SCALED / r_max_m.sqrt();
    sine_pulse(1.0, f, 2.0, dt_scaled * r_max_m.sqrt())
}

/// The PGA grid of a sweep: `steps` values from `pga_max`/`steps` to `pga_max` (g).
pub fn pga_grid(pga_max: f64, steps: usize) -> Result<Vec<f64>> {
    if !(pga_max > 0.0 && pga_max.is_finite()) {
        return Err(Error::parameter("pga_max", pga_max, "a positive acceleration in g"));
    }
    if steps == 0 {
        return Err(Error::parameter("pga_steps", steps, "at least 1"));
    }
    Ok((1..=steps).map(|i| pga_max * i as f64 / steps as f64).collect())
}

/// The PGA grid of a run of `motion`: a sweep up to `pga_max` in `steps` when given, else up to
/// 1 g for the default pulse (`default_sweep`), else the motion at its own amplitude only.
pub fn pgas_for(motion: &Record, pga_max: Option<f64>, steps: usize, default_sweep: bool) -> Result<Vec<f64>> {
    match pga_max.or(default_sweep.then_some(1.0)) {
        Some(m) => pga_grid(m, steps),
        None => Ok(vec![motion.measures().pga_g]),
    }
}

/// The stable micro-equilibria a sweep shakes by default: the deepest regular one and the
/// rocking one with the highest basin barrier that stay at rest
/// ([`crate::dynamics::resting::default_pair`]); an error if none does.
pub fn default_starts(stone: &Stone, p: &RestingParams) -> Result<Vec<usize>> {
    let (regular, rocking) = crate::dynamics::resting::default_pair(stone, p);
    let v: Vec<usize> = regular.into_iter().chain(rocking).collect();
    if v.is_empty() {
        return Err(Error::Pose {
            pose: "on any stable equilibrium".into(),
            what: "no stable micro-equilibrium of this stone stays at rest in the simulation".into(),
        });
    }
    Ok(v)
}

/// Shake the ground under a stone resting on `start` with `record` (real time, already at its
/// peak ground acceleration `pga` (g) and sampled for the run, see [`driven`]) along `azimuth`,
/// then let it come to rest relative to the ground.
#[allow(clippy::too_many_arguments)]
pub fn shake_trial(
    stone: &Stone,
    start: usize,
    p: &RestingParams,
    record: &Record,
    pga: f64,
    r_max_m: f64,
    azimuth: f64,
    k: u32,
) -> ShakeTrial {
    let run = shake_placed(stone, Placed::on(stone, start, p), p, record, azimuth, r_max_m);
    let rest = stone.rest(&run.end.state.down);
    ShakeTrial {
        start,
        equilibrium: stone.stable()[start].index,
        pga,
        azimuth,
        trial: k,
        outcome: classify(stone, start, Some(rest.facet), rest.flock),
        final_facet: rest.facet,
        final_equilibrium: Some(rest.equilibrium),
        final_flock: rest.flock,
        settled: run.end.settled,
        non_stable_facet: !rest.on_equilibrium(),
        max_tilt: run.max_tilt,
        time: run.end.steps as f64 * p.sim.numerics.dt,
        deepest_penetration: run.deepest_penetration,
    }
}

/// The random stream of shaking trial `trial` on `start` (bit 62 set: never a push stream).
pub fn shake_stream(start: usize, trial: u32) -> u64 {
    (1u64 << 62) | ((start as u64) << 32) | trial as u64
}

/// What a fragility run is.
#[derive(Clone, Debug)]
pub struct ShakeConfig {
    /// Simulation parameters.
    pub params: RestingParams,
    /// The motion's shape (real time, SI); it is scaled to each PGA of the grid.
    pub motion: Record,
    /// Increasing grid of peak ground accelerations (g).
    pub pgas: Vec<f64>,
    /// Number of trials per equilibrium and PGA.
    pub trials: u32,
    /// Seed of the random streams of the trials.
    pub seed: u64,
    /// Shake along this azimuth (rad) instead of a random one per trial.
    pub azimuth: Option<f64>,
    /// Real size of the stone, R_max in metres.
    pub r_max_m: f64,
}

impl ShakeConfig {
    /// Refuse invalid parameters, a motion without horizontal acceleration, a bad PGA grid, zero
    /// trials or a non-positive size.
    pub fn check(&self) -> Result<()> {
        self.params.check()?;
        if !(self.motion.measures().pga_g > 0.0) {
            return Err(Error::motion(&self.motion.name, "the motion has no horizontal acceleration"));
        }
        if self.pgas.is_empty() || self.pgas.iter().any(|a| !(*a >= 0.0 && a.is_finite())) {
            return Err(Error::parameter("pgas", format!("{:?}", self.pgas), "a non-empty grid of PGAs ≥ 0"));
        }
        if self.pgas.windows(2).any(|w| w[1] <= w[0]) {
            return Err(Error::parameter("pgas", format!("{:?}", self.pgas), "an increasing grid"));
        }
        if self.trials == 0 {
            return Err(Error::parameter("trials", 0, "at least 1 per PGA"));
        }
        if !(self.r_max_m > 0.0 && self.r_max_m.is_finite()) {
            return Err(Error::parameter("size", format!("{} m", self.r_max_m), "positive"));
        }
        Ok(())
    }
}

/// The motion of a run, as reported: its name and intensity measures at its own amplitude.
#[derive(Clone, Debug, Serialize)]
pub struct MotionInfo {
    /// Name (file name or description).
    pub name: String,
    /// Sampling interval (s, real).
    pub dt_s: f64,
    /// PGA, PGV, PGV/PGA and duration of the motion as given.
    pub measures: Measures,
}

impl MotionInfo {
    /// The description of `r`.
    pub fn of(r: &Record) -> MotionInfo {
        MotionInfo { name: r.name.clone(), dt_s: r.dt, measures: r.measures() }
    }
}

/// The fragility of one stable micro-equilibrium.
#[derive(Clone, Debug, Serialize)]
pub struct Fragility {
    /// The stable micro-equilibrium and its static description.
    pub equilibrium: StableEquilibrium,
    /// Whether the unshaken stone stays at rest on it.
    pub rest: SettleCheck,
    /// One point per PGA (x = PGA in g).
    pub curve: Vec<CurvePoint>,
    /// PGA₅₀ to leave the micro-equilibrium.
    pub pga50_micro: Option<Threshold>,
    /// PGA₅₀ to topple out of the flock.
    pub pga50_flock: Option<Threshold>,
    /// Smallest PGA at which any trial toppled.
    pub first_topple: Option<f64>,
}

/// The numbers of a shaking run.
#[derive(Clone, Debug, Serialize)]
pub struct ShakeReport {
    /// The motion's shape (scaled to each PGA).
    pub motion: MotionInfo,
    /// Seed of the random streams of the trials.
    pub seed: u64,
    /// Number of trials per equilibrium and PGA.
    pub trials_per_point: u32,
    /// Increasing grid of peak ground accelerations (g).
    pub pgas: Vec<f64>,
    /// Resolution ν of the flocks.
    pub nu: f64,
    /// Simulation parameters.
    pub params: RestingParams,
    /// Real size of the stone, R_max in metres.
    pub r_max_m: f64,
    /// Whether that size was assumed, the mesh's unit being neither given nor known: set by the
    /// command line and the Python binding ([`crate::dynamics::size::RealSize::resolve`]);
    /// absent when the caller gave R_max as a number.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub size_assumed: Option<bool>,
    /// The azimuth every trial shook along (degrees from the x axis of the stone as it stands:
    /// the mesh turned by the smallest rotation that brings the facet down); absent: a random
    /// azimuth per trial.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub azimuth_deg: Option<f64>,
    /// Fragility of each stable micro-equilibrium.
    pub fragility: Vec<Fragility>,
    /// The deepest any hull corner went below the ground after any step or sub-step of any trial
    /// (R_max, [`crate::dynamics::engine::world::penetration`]).
    pub deepest_penetration: f64,
    /// Every trial.
    #[serde(skip)]
    pub trials: Vec<ShakeTrial>,
}

/// Run a fragility study on the stable micro-equilibria `starts`, in parallel (independent of
/// the number of threads).
pub fn sweep_fragility(stone: &Stone, starts: &[usize], cfg: &ShakeConfig) -> Result<ShakeReport> {
    sweep_fragility_monitored(stone, starts, cfg, &|| {})
}

/// [`sweep_fragility`], telling `monitor` of every finished trial (from any thread); [`Error::Cancelled`] if
/// it stops the run.
pub fn sweep_fragility_monitored(
    stone: &Stone,
    starts: &[usize],
    cfg: &ShakeConfig,
    monitor: &dyn Monitor,
) -> Result<ShakeReport> {
    cfg.check()?;
    let real_dt = cfg.params.sim.numerics.dt * cfg.r_max_m.sqrt();
    let motions: Vec<Record> =
        cfg.pgas.iter().map(|&a| driven(&cfg.motion.scaled_to_pga(a), real_dt)).collect::<Result<_>>()?;
    let (checks, trials) = grid_trials(stone, starts, &cfg.params, cfg.pgas.len(), cfg.trials, monitor, |s, i, k| {
        let azimuth = cfg.azimuth.unwrap_or_else(|| {
            let mut rng = item_rng(cfg.seed, shake_stream(s, k));
            rng.random_range(0.0..2.0 * std::f64::consts::PI)
        });
        shake_trial(stone, s, &cfg.params, &motions[i], cfg.pgas[i], cfg.r_max_m, azimuth, k)
    })?;
    let fragility = starts.iter().zip(checks).map(|(&s, rest)| fragility(stone, s, rest, &cfg.pgas, &trials)).collect();
    Ok(ShakeReport {
        motion: MotionInfo::of(&cfg.motion),
        seed: cfg.seed,
        trials_per_point: cfg.trials,
        pgas: cfg.pgas.clone(),
        nu: stone.nu,
        params: cfg.params.clone(),
        r_max_m: cfg.r_max_m,
        size_assumed: None,
        azimuth_deg: cfg.azimuth.map(f64::to_degrees),
        fragility,
        deepest_penetration: trials.iter().map(|t| t.deepest_penetration).fold(0.0, f64::max),
        trials,
    })
}

/// The fragility curve of start `s` from the trials.
fn fragility(stone: &Stone, s: usize, rest: SettleCheck, pgas: &[f64], trials: &[ShakeTrial]) -> Fragility {
    let mine: Vec<&ShakeTrial> = trials.iter().filter(|t| t.start == s).collect();
    let outcomes: Vec<(f64, Outcome, bool)> = mine.iter().map(|t| (t.pga, t.outcome, t.settled)).collect();
    let curve = Curve::of(pgas, rest.stays, &outcomes, false);
    Fragility {
        equilibrium: stone.stable()[s].clone(),
        rest,
        pga50_micro: curve.leave50,
        pga50_flock: curve.topple50,
        first_topple: mine
            .iter()
            .filter(|t| t.outcome == Outcome::Toppled)
            .map(|t| t.pga)
            .fold(None, |a: Option<f64>, x| Some(a.map_or(x, |y| y.min(x)))),
        curve: curve.points,
    }
}
