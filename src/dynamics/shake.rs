//! Toppling under ground shaking: fragility of a resting stone (precariously balanced rocks,
//! SPEC §7), and the rigid-block checks of Housner (1963).
//!
//! The stone starts at rest on a stable micro-equilibrium exactly as in
//! [`crate::dynamics::perturb`]. The ground — a kinematic body carrying the half-space — is then
//! driven horizontally along an azimuth φ by a prescribed acceleration history a(t) (in units of
//! g): a [`Pulse`] of sine cycles, or a [`Record`] read from a CSV of (time, acceleration in g).
//! The acceleration is integrated to the ground velocity with the midpoint rule at every step
//! and the ground is given the mean velocity of the step ([`Simulation::set_ground_velocity`]),
//! so its displacement is exact for a linear a(t). When the motion ends the ground keeps its
//! final velocity — a frame moving uniformly is inertial, so nothing changes for the stone — and
//! the stone is simulated until it rests *relative to the ground* (time cap as for pushes). The
//! outcome is classified as for pushes (same micro-equilibrium / another of the same flock /
//! toppled out of the flock).
//!
//! A fragility curve is P(toppled out of the flock) against the peak ground acceleration (PGA):
//! the motion is scaled to each PGA of a grid, and each trial shakes along a uniformly random
//! azimuth relative to the stone (common random numbers across PGAs: trial k has the same
//! azimuth at every PGA), with 95 % Wilson intervals and the PGA₅₀ interpolated linearly.
//!
//! # Units and the size of a real stone
//!
//! Simulations run in the scaled frame of [`crate::dynamics::drop`]: the stone has R_max = 1 m
//! (R_max the largest distance from G to the hull) and g = 9.81 m/s². Accelerations are in units
//! of g and need no conversion. Times and frequencies are those of this 1 m body; for a real
//! stone of size R_max = L metres, dynamic similarity (Froude scaling: only a/g, t·√(g/L) and
//! the friction and restitution coefficients enter) gives
//!
//! ```text
//! t_real = t_scaled · √(L / 1 m),      f_real = f_scaled / √(L / 1 m).
//! ```
//!
//! So a 2 Hz pulse on the scaled body is a 1 Hz pulse on a 4 m boulder and a 11.5 Hz pulse on a
//! 3 cm pebble. [`TimeScale`] does this conversion; the CLI takes the real size with `--size`.
//!
//! # Housner's rigid block
//!
//! A block of half-width b and half-height h (tan α = b/h, R = √(b² + h²)) on a rigid ground with
//! enough friction:
//!
//! * under a horizontal ground acceleration a it stays in full contact as long as a < g tan α
//!   and starts to tip when a exceeds it ([`ramp_tipping`] measures it with a slowly rising a);
//! * rocking freely, its angular velocity drops at every impact by the factor
//!   r = 1 − (3/2) sin² α (conservation of angular momentum about the impacting corner, with a
//!   perfectly plastic impact at that corner alone) — [`free_rocking`] measures the ratio of the
//!   impact angular velocities of successive half-cycles (see there for how).

use super::perturb::{
    classify, grid_trials, resting_orientation, resting_simulation, CurvePoint, Outcome, PerturbParams, SettleCheck,
    StableEquilibrium, Stone, Threshold, GRAVITY,
};
use super::run::{self as run_loop, Drive, NoCertificate};
use super::world::{convert, Simulation};
use crate::rng::item_rng;
use crate::{Error, Result, Vec3};
use nalgebra::UnitQuaternion;
use rand::RngExt;
use serde::Serialize;
use std::path::Path;

/// Conversion between a real stone of size R_max = `r_max_m` metres and the scaled 1 m body.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TimeScale {
    /// Real R_max of the stone (m).
    pub r_max_m: f64,
}

impl TimeScale {
    /// The scaled body itself (R_max = 1 m).
    pub const UNIT: TimeScale = TimeScale { r_max_m: 1.0 };

    /// √(L / 1 m): real time per scaled time.
    pub fn factor(&self) -> f64 {
        self.r_max_m.sqrt()
    }
    /// Real time (s) to time of the scaled body.
    pub fn to_scaled_time(&self, t_real: f64) -> f64 {
        t_real / self.factor()
    }
    /// Time of the scaled body to real time (s).
    pub fn to_real_time(&self, t_scaled: f64) -> f64 {
        t_scaled * self.factor()
    }
    /// Real frequency (Hz) to frequency of the scaled body.
    pub fn to_scaled_frequency(&self, f_real: f64) -> f64 {
        f_real * self.factor()
    }
    /// Frequency of the scaled body to real frequency (Hz).
    pub fn to_real_frequency(&self, f_scaled: f64) -> f64 {
        f_scaled / self.factor()
    }
}

/// `cycles` sine cycles a(t) = A sin(2π f t), 0 ≤ t ≤ cycles / f (A in g, f in Hz of the
/// scaled body).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Pulse {
    /// Peak acceleration A (g).
    pub amplitude: f64,
    /// Frequency f (Hz of the scaled body).
    pub frequency: f64,
    /// Number of sine cycles.
    pub cycles: f64,
}

/// A ground-acceleration history sampled at increasing times (s of the scaled body), in g,
/// linearly interpolated, zero outside.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Record {
    /// Name of the record.
    pub name: String,
    /// Sample times (s of the scaled body, increasing).
    pub times: Vec<f64>,
    /// Ground acceleration at each sample time (g).
    pub accel: Vec<f64>,
}

/// A horizontal ground-acceleration history.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "type", rename_all = "lowercase")]
pub enum Motion {
    /// A few sine cycles.
    Pulse(Pulse),
    /// A sampled acceleration history.
    Record(Record),
}

impl Motion {
    /// Ground acceleration (g) at time t (scaled s).
    pub fn accel(&self, t: f64) -> f64 {
        match self {
            Motion::Pulse(p) => {
                if t < 0.0 || t > p.cycles / p.frequency {
                    0.0
                } else {
                    p.amplitude * (2.0 * std::f64::consts::PI * p.frequency * t).sin()
                }
            }
            Motion::Record(r) => {
                let (ts, a) = (&r.times, &r.accel);
                if ts.is_empty() || t < ts[0] || t > ts[ts.len() - 1] {
                    return 0.0;
                }
                let k = ts.partition_point(|&x| x <= t).clamp(1, ts.len() - 1);
                let (t0, t1) = (ts[k - 1], ts[k]);
                let s = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
                a[k - 1] + s * (a[k] - a[k - 1])
            }
        }
    }

    /// When the motion ends (scaled s).
    pub fn duration(&self) -> f64 {
        match self {
            Motion::Pulse(p) => p.cycles / p.frequency,
            Motion::Record(r) => r.times.last().copied().unwrap_or(0.0),
        }
    }

    /// Peak ground acceleration (g).
    pub fn peak(&self) -> f64 {
        match self {
            Motion::Pulse(p) => p.amplitude.abs(),
            Motion::Record(r) => r.accel.iter().fold(0.0, |m, a| m.max(a.abs())),
        }
    }

    /// The same motion scaled to peak ground acceleration `pga` (g).
    pub fn scaled_to(&self, pga: f64) -> Motion {
        match self {
            Motion::Pulse(p) => Motion::Pulse(Pulse { amplitude: pga, ..*p }),
            Motion::Record(r) => {
                let peak = self.peak();
                let k = if peak > 0.0 { pga / peak } else { 0.0 };
                Motion::Record(Record { accel: r.accel.iter().map(|a| a * k).collect(), ..r.clone() })
            }
        }
    }

    /// A short description.
    pub fn describe(&self) -> String {
        match self {
            Motion::Pulse(p) => {
                format!("{} sine cycle(s) of {:.3} Hz (scaled), amplitude {:.3} g", p.cycles, p.frequency, p.amplitude)
            }
            Motion::Record(r) => {
                format!("record {} ({:.2} s scaled, PGA {:.3} g)", r.name, self.duration(), self.peak())
            }
        }
    }

    /// Refuse motions that cannot be simulated.
    pub fn check(&self) -> Result<()> {
        match self {
            Motion::Pulse(p) => {
                if !(p.frequency > 0.0 && p.frequency.is_finite()) {
                    return Err(Error::Usage(format!("pulse frequency must be positive, got {}", p.frequency)));
                }
                if !(p.cycles > 0.0 && p.cycles.is_finite()) {
                    return Err(Error::Usage(format!("pulse cycles must be positive, got {}", p.cycles)));
                }
                if !p.amplitude.is_finite() {
                    return Err(Error::Usage("pulse amplitude must be finite".into()));
                }
            }
            Motion::Record(r) => {
                if r.times.len() < 2 || r.times.len() != r.accel.len() {
                    return Err(Error::Usage(format!("{}: a record needs at least two samples", r.name)));
                }
                if r.times.windows(2).any(|w| !(w[1] > w[0])) {
                    return Err(Error::Usage(format!("{}: times must increase", r.name)));
                }
                if r.times.iter().chain(&r.accel).any(|x| !x.is_finite()) {
                    return Err(Error::Usage(format!("{}: every value must be finite", r.name)));
                }
            }
        }
        Ok(())
    }
}

/// Read a ground motion from CSV: two columns, time (s, real) and acceleration (g); an optional
/// header line and lines starting with `#` are skipped; times are converted to the scaled body
/// with `scale`.
pub fn read_record(path: &Path, scale: TimeScale) -> Result<Record> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::Io { path: path.into(), error: e })?;
    let parse = |what: String| Error::Parse { path: path.into(), what };
    let (mut times, mut accel) = (Vec::new(), Vec::new());
    for (k, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let cols: Vec<&str> = line.split([',', ';', '\t', ' ']).filter(|c| !c.is_empty()).collect();
        if cols.len() < 2 {
            return Err(parse(format!("line {}: expected two columns (time, acceleration in g)", k + 1)));
        }
        match (cols[0].parse::<f64>(), cols[1].parse::<f64>()) {
            (Ok(t), Ok(a)) => {
                times.push(scale.to_scaled_time(t));
                accel.push(a);
            }
            _ if times.is_empty() && k == 0 => continue, // header
            _ => return Err(parse(format!("line {}: not two numbers: {line:?}", k + 1))),
        }
    }
    let name = path.file_name().map_or_else(|| path.display().to_string(), |f| f.to_string_lossy().into_owned());
    let r = Record { name, times, accel };
    Motion::Record(r.clone()).check().map_err(|e| parse(e.to_string()))?;
    Ok(r)
}

/// A synthetic "recorded-style" accelerogram: white noise through a Kanai–Tajimi ground filter
/// (natural frequency `f_ground` Hz, damping 0.6, the classic model of soil-filtered bedrock
/// motion), times a Saragoni–Hart-like envelope t² e^(−t/τ) normalised to peak 1 at t = 2τ,
/// duration `duration` s, sampled at 100 Hz, baseline-corrected (the mean acceleration is removed
/// so the ground ends near rest) and scaled to PGA `pga` (g). All in the scaled body's time.
pub fn synthetic_record(name: &str, duration: f64, f_ground: f64, pga: f64, seed: u64) -> Record {
    use rand_distr::{Distribution, StandardNormal};
    let mut rng = item_rng(seed, 0);
    let dt = 0.01;
    let n = (duration / dt).round() as usize + 1;
    let (w, z) = (2.0 * std::f64::consts::PI * f_ground, 0.6);
    let tau = duration / 8.0;
    let (mut x, mut v) = (0.0f64, 0.0f64);
    let mut times = Vec::with_capacity(n);
    let mut accel = Vec::with_capacity(n);
    let sub = 10;
    let h = dt / sub as f64;
    for k in 0..n {
        let t = k as f64 * dt;
        let mut a_out = 0.0;
        for _ in 0..sub {
            let noise: f64 = StandardNormal.sample(&mut rng);
            let u = noise / h.sqrt();
            // Kanai–Tajimi: ẍ + 2ζω ẋ + ω² x = −u; ground acceleration = −(2ζω ẋ + ω² x).
            let acc = -u - 2.0 * z * w * v - w * w * x;
            v += acc * h;
            x += v * h;
            a_out = -(2.0 * z * w * v + w * w * x);
        }
        let env = (t / (2.0 * tau)).powi(2) * (2.0 - t / tau).exp();
        times.push(t);
        accel.push(a_out * env);
    }
    let mean = accel.iter().sum::<f64>() / n as f64;
    accel.iter_mut().for_each(|a| *a -= mean);
    let r = Record { name: name.into(), times, accel };
    match Motion::Record(r).scaled_to(pga) {
        Motion::Record(r) => r,
        Motion::Pulse(_) => unreachable!(),
    }
}

/// One shaking trial.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ShakeTrial {
    /// Position of the start in [`Stone::stable`], and its analysis index.
    pub start: usize,
    /// Analysis index of the start equilibrium.
    pub equilibrium: usize,
    /// Peak ground acceleration (g) and azimuth of shaking (rad, world frame).
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
}

/// Advance `sim` by step number `step` with the ground driven along `dir` by `motion`: the ground
/// velocity `v` (m/s, scaled) is advanced by the midpoint rule and the ground moves with the mean
/// velocity of the step.
fn drive(sim: &mut Simulation, motion: &Motion, dir: &Vec3, dt: f64, step: u64, v: &mut f64) {
    let t = step as f64 * dt;
    let a = motion.accel(t + 0.5 * dt) * GRAVITY;
    let v_new = *v + a * dt;
    sim.set_ground_velocity(&(dir * (0.5 * (*v + v_new))));
    *v = v_new;
    sim.step();
}

/// The ground driven along `dir` by `motion` ([`drive`]), as a [`Drive`] of the run loop.
struct GroundMotion<'m> {
    motion: &'m Motion,
    dir: Vec3,
    dt: f64,
    /// Ground speed along `dir` at the end of the last step.
    v: f64,
    /// Mean ground speed of the last step.
    v_mean: f64,
}

impl Drive for GroundMotion<'_> {
    fn before_step(&mut self, sim: &mut Simulation, step: u64) {
        let t = step as f64 * self.dt;
        let a = self.motion.accel(t + 0.5 * self.dt) * GRAVITY;
        let v_new = self.v + a * self.dt;
        self.v_mean = 0.5 * (self.v + v_new);
        sim.set_ground_velocity(&(self.dir * self.v_mean));
        self.v = v_new;
    }
    fn ground_velocity(&self) -> Vec3 {
        self.dir * self.v
    }
    fn active_steps(&self) -> u64 {
        (self.motion.duration() / self.dt).ceil() as u64
    }
}

/// Shake the ground under a stone resting on `start` with `motion` along azimuth `azimuth`,
/// then let it come to rest relative to the ground.
pub fn shake_trial(
    stone: &Stone,
    start: usize,
    p: &PerturbParams,
    motion: &Motion,
    azimuth: f64,
    k: u32,
) -> ShakeTrial {
    let s = &stone.stable()[start];
    let dt = p.sim.dt;
    let mut sim = resting_simulation(stone, start, p, p.settle_time);
    let dir = Vec3::new(azimuth.cos(), azimuth.sin(), 0.0);
    let n = stone.body.facet_normals[s.facet as usize];
    let mut ground = GroundMotion { motion, dir, dt, v: 0.0, v_mean: 0.0 };
    let mut max_tilt: f64 = 0.0;
    let end = run_loop::run(&mut sim, &p.sim, &mut ground, &NoCertificate, &mut |st| {
        max_tilt = max_tilt.max(n.dot(&st.down).clamp(-1.0, 1.0).acos())
    });
    let rest = stone.rest(&end.state.down);
    ShakeTrial {
        start,
        equilibrium: s.index,
        pga: motion.peak(),
        azimuth,
        trial: k,
        outcome: classify(stone, start, Some(rest.facet), rest.flock),
        final_facet: rest.facet,
        final_equilibrium: Some(rest.equilibrium),
        final_flock: rest.flock,
        settled: end.settled,
        non_stable_facet: !rest.on_equilibrium(),
        max_tilt,
        time: end.steps as f64 * dt,
    }
}

/// The random stream of shaking trial `trial` on `start` (bit 62 set: never a push stream).
pub fn shake_stream(start: usize, trial: u32) -> u64 {
    (1u64 << 62) | ((start as u64) << 32) | trial as u64
}

/// What a fragility run is.
#[derive(Clone, Debug, Serialize)]
pub struct ShakeConfig {
    /// Simulation parameters.
    pub params: PerturbParams,
    /// The motion's shape (its amplitude is replaced by each PGA of the grid).
    pub motion: Motion,
    /// Increasing grid of peak ground accelerations (g).
    pub pgas: Vec<f64>,
    /// Number of trials per equilibrium and PGA.
    pub trials: u32,
    /// Seed of the random streams of the trials.
    pub seed: u64,
    /// Shake along this azimuth (rad) instead of a random one per trial.
    pub azimuth: Option<f64>,
    /// Real size of the stone, for reporting times and frequencies.
    pub scale: TimeScale,
}

impl ShakeConfig {
    /// Refuse invalid parameters or motion, a bad PGA grid, zero trials or a non-positive size.
    pub fn check(&self) -> Result<()> {
        self.params.check()?;
        self.motion.check()?;
        if self.pgas.is_empty() || self.pgas.iter().any(|a| !(*a >= 0.0 && a.is_finite())) {
            return Err(Error::Usage("the PGA grid must hold values ≥ 0".into()));
        }
        if self.pgas.windows(2).any(|w| w[1] <= w[0]) {
            return Err(Error::Usage("the PGA grid must be increasing".into()));
        }
        if self.trials == 0 {
            return Err(Error::Usage("at least one trial per PGA".into()));
        }
        if !(self.scale.r_max_m > 0.0 && self.scale.r_max_m.is_finite()) {
            return Err(Error::Usage(format!("the size must be positive, got {}", self.scale.r_max_m)));
        }
        Ok(())
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
    /// PGA₅₀ to leave the micro-equilibrium and to topple out of the flock.
    pub pga50_micro: Option<Threshold>,
    /// PGA₅₀ to topple out of the flock.
    pub pga50_flock: Option<Threshold>,
    /// Smallest PGA at which any trial toppled.
    pub first_topple: Option<f64>,
}

/// The numbers of a shaking run.
#[derive(Clone, Debug, Serialize)]
pub struct ShakeReport {
    /// The motion's shape (amplitude replaced by each PGA).
    pub motion: Motion,
    /// Seed of the random streams of the trials.
    pub seed: u64,
    /// Number of trials per equilibrium and PGA.
    pub trials_per_point: u32,
    /// Increasing grid of peak ground accelerations (g).
    pub pgas: Vec<f64>,
    /// Resolution ν of the flocks.
    pub nu: f64,
    /// Simulation parameters.
    pub params: PerturbParams,
    /// Real size of the stone, for reporting times and frequencies.
    pub scale: TimeScale,
    /// Fragility of each stable micro-equilibrium.
    pub fragility: Vec<Fragility>,
    #[serde(skip)]
    /// Every trial.
    pub trials: Vec<ShakeTrial>,
}

/// Run a fragility study on the stable micro-equilibria `starts`, in parallel (independent of
/// the number of threads).
pub fn run(stone: &Stone, starts: &[usize], cfg: &ShakeConfig) -> ShakeReport {
    run_with(stone, starts, cfg, &|| {})
}

/// [`run`], calling `progress` after every trial (from any thread).
pub fn run_with(stone: &Stone, starts: &[usize], cfg: &ShakeConfig, progress: &(dyn Fn() + Sync)) -> ShakeReport {
    let (checks, trials) = grid_trials(stone, starts, &cfg.params, cfg.pgas.len(), cfg.trials, |s, i, k| {
        let azimuth = cfg.azimuth.unwrap_or_else(|| {
            let mut rng = item_rng(cfg.seed, shake_stream(s, k));
            rng.random_range(0.0..2.0 * std::f64::consts::PI)
        });
        let motion = cfg.motion.scaled_to(cfg.pgas[i]);
        let mut t = shake_trial(stone, s, &cfg.params, &motion, azimuth, k);
        t.pga = cfg.pgas[i];
        progress();
        t
    });
    let fragility = starts
        .iter()
        .zip(checks)
        .map(|(&s, rest)| {
            let mine: Vec<&ShakeTrial> = trials.iter().filter(|t| t.start == s).collect();
            let curve: Vec<CurvePoint> = if rest.stays {
                cfg.pgas
                    .iter()
                    .map(|&a| CurvePoint::count(a, mine.iter().filter(|t| t.pga == a).map(|t| (t.outcome, t.settled))))
                    .collect()
            } else {
                Vec::new()
            };
            let x: Vec<f64> = curve.iter().map(|c| c.x).collect();
            let leave: Vec<f64> = curve.iter().map(|c| 1.0 - c.p_same).collect();
            let topple: Vec<f64> = curve.iter().map(|c| c.p_toppled).collect();
            Fragility {
                equilibrium: stone.stable()[s].clone(),
                rest,
                pga50_micro: Threshold::of(&x, &leave, false),
                pga50_flock: Threshold::of(&x, &topple, false),
                first_topple: mine
                    .iter()
                    .filter(|t| t.outcome == Outcome::Toppled)
                    .map(|t| t.pga)
                    .fold(None, |a: Option<f64>, x| Some(a.map_or(x, |y| y.min(x)))),
                curve,
            }
        })
        .collect();
    ShakeReport {
        motion: cfg.motion.clone(),
        seed: cfg.seed,
        trials_per_point: cfg.trials,
        pgas: cfg.pgas.clone(),
        nu: stone.nu,
        params: cfg.params.clone(),
        scale: cfg.scale,
        fragility,
        trials,
    }
}

/// Housner's ramp: the stone at rest on `start`, the ground accelerating along `azimuth` with
/// a(t) = `rate`·t (g per scaled second) up to `a_max` (g). Returns the ground acceleration
/// (g) at which the resting facet's tilt first exceeds `tilt` (rad), or None.
///
/// The detection lags the true onset: past the threshold a_c the overturning moment grows
/// like m h (a − a_c), so the tilt grows like (t − t_c)³ and the reading is late by about
/// (6 I_O tilt / (m h g rate))^(1/3)·rate (in g); keep `rate` and `tilt` small.
pub fn ramp_tipping(
    stone: &Stone,
    start: usize,
    p: &PerturbParams,
    azimuth: f64,
    rate: f64,
    tilt: f64,
    a_max: f64,
) -> Option<f64> {
    let s = &stone.stable()[start];
    let dt = p.sim.dt;
    let mut sim = resting_simulation(stone, start, p, p.settle_time);
    let dir = Vec3::new(azimuth.cos(), azimuth.sin(), 0.0);
    let n = stone.body.facet_normals[s.facet as usize];
    // The tilt of the settled, unloaded stone is the reference.
    let tilt0 = n.dot(&sim.state().down).clamp(-1.0, 1.0).acos();
    let ramp = Motion::Record(Record { name: "ramp".into(), times: vec![0.0, a_max / rate], accel: vec![0.0, a_max] });
    let steps = (a_max / rate / dt).ceil() as u64;
    let mut v = 0.0;
    for step in 0..steps {
        drive(&mut sim, &ramp, &dir, dt, step, &mut v);
        let st = sim.state();
        if n.dot(&st.down).clamp(-1.0, 1.0).acos() - tilt0 > tilt {
            return Some(ramp.accel((step + 1) as f64 * dt));
        }
    }
    None
}

/// One free-rocking half-cycle of a block (between two impacts).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct HalfCycle {
    /// Start and end time (s, scaled).
    pub t0: f64,
    /// End time (s, scaled).
    pub t1: f64,
    /// Largest |θ| in the half-cycle (rad).
    pub amplitude: f64,
    /// Angular velocity the block has at θ = 0 on the corner it rocks on in this half-cycle:
    /// the median over the half-cycle's samples (|θ| ≥ 0.2 amplitude) of
    /// √(ω² + (2 m g R / I_O)(cos(α − |θ|) − cos α)), which is constant for a rigid rotation about
    /// the corner (energy conservation), so it measures the impact velocities without reading
    /// the few steps the soft contact takes to turn the block over.
    pub omega0: f64,
}

/// Free rocking of a box resting on its face with normal −z (a [`crate::generate::cuboid`] of
/// full lengths 2b × 2d × 2h along x, y, z, in input units), released from rest tilted by
/// `theta0` (rad) about its +x bottom edge (rotation about y), simulated for `duration` scaled
/// seconds. Returns the half-cycles between zero crossings of θ, the rotation about y.
pub fn free_rocking(
    stone: &Stone,
    start: usize,
    p: &PerturbParams,
    b: f64,
    h: f64,
    theta0: f64,
    duration: f64,
) -> Vec<HalfCycle> {
    let s = &stone.stable()[start];
    let q0 = resting_orientation(&stone.body.facet_normals[s.facet as usize]);
    let q = UnitQuaternion::from_axis_angle(&Vec3::y_axis(), theta0) * q0;
    let down = q.inverse() * -Vec3::z();
    let z = stone.body.support(&down);
    let mut sim = Simulation::new(&stone.body, &p.sim, &q, z, &Vec3::zeros(), &Vec3::zeros());
    sim.set_contact_frequency(p.contact_frequency);
    let dt = p.sim.dt;
    let r_max = stone.body.r_max;
    let (b, h) = (b / r_max, h / r_max);
    let big_r = (b * b + h * h).sqrt();
    let alpha = b.atan2(h);
    // I_O = I_G + m R² for rotation about the bottom edge (unit mass, scaled); I_G from the body.
    let i_o = stone.body.inertia[(1, 1)] + big_r * big_r;
    let k = 2.0 * GRAVITY * big_r / i_o;
    let steps = (duration / dt).ceil() as u64;
    let mut samples: Vec<(f64, f64, f64)> = Vec::with_capacity(steps as usize);
    for step in 1..=steps {
        sim.step();
        let rb = &sim.world.bodies[sim.body_handle];
        let rot = convert::quat_back(rb.rotation()) * q0.inverse();
        let x = rot * Vec3::x();
        let theta = (-x.z).atan2(x.x);
        let omega = convert::vec_back(rb.angvel()).y;
        samples.push((step as f64 * dt, theta, omega));
    }
    let mut cycles = Vec::new();
    let mut begin = 0;
    for i in 1..=samples.len() {
        let end = i == samples.len() || samples[i].1.signum() != samples[i - 1].1.signum();
        if !end {
            continue;
        }
        let part = &samples[begin..i];
        begin = i;
        let amplitude = part.iter().fold(0.0f64, |m, s| m.max(s.1.abs()));
        let mut inv: Vec<f64> = part
            .iter()
            .filter(|s| s.1.abs() >= 0.2 * amplitude)
            .map(|s| (s.2 * s.2 + k * ((alpha - s.1.abs()).cos() - alpha.cos())).max(0.0).sqrt())
            .collect();
        if inv.is_empty() {
            continue;
        }
        inv.sort_by(f64::total_cmp);
        cycles.push(HalfCycle { t0: part[0].0, t1: part[part.len() - 1].0, amplitude, omega0: inv[inv.len() / 2] });
    }
    cycles
}

/// Housner's ratio of angular velocities after / before an impact of a rocking block,
/// 1 − (3/2) sin² α, tan α = b/h.
pub fn housner_ratio(b: f64, h: f64) -> f64 {
    let a = b.atan2(h);
    1.0 - 1.5 * a.sin().powi(2)
}
