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
//! # Field rocks: true size, pose, three components (issue 11)
//!
//! [`run_record`] / [`run_batch`] shake a rock as it stands in the field with a recorded
//! [`crate::ground_motion::Record`] (up to three components, SI, real time):
//!
//! * **Pose** ([`Pose`], [`place`]): as scanned (mesh frame = world frame, +z up, put down under
//!   its lowest point and settled; refused unless it rests on the stable micro-equilibrium of the
//!   quasi-static descent from the as-scanned down direction), a stable micro-equilibrium, or a
//!   quaternion. The record's x axis is turned by the azimuth in the world frame.
//! * **True size, by an exactly equivalent scaled run** (not rapier at true size with
//!   `length_unit`): time t/√L, accelerations unchanged, every dimensional parameter converted
//!   (rolling-resistance length δ/L from the surface pair; dt, contact frequency and rapier's length
//!   unit are the scaled frame's, i.e. dt·√L, f/√L and L at true size) — see [`shake_record`].
//! * **Three components**: the kinematic ground gets the 3D velocity (midpoint rule, exact ground
//!   displacement for piecewise-linear a(t)); rapier's contact solver uses the kinematic body's
//!   velocity, so a vertical ground acceleration a_z changes the effective gravity to g + a_z
//!   (tested: Housner's threshold drops to 0.7 g tan α under a_z = −0.3 g).
//! * **Contact** from the surface pairs of [`super::params::Surface`] at the rock's real size
//!   ([`rock_params`]; rock on concrete by default). The fragility-curve mode above keeps the
//!   legacy contact of [`super::perturb::legacy_contact`] so that its results stay comparable.
//! * **Outcome** ([`RockRun`]): overturned = rests on a stable micro-equilibrium of another flock;
//!   the largest tilt; the residual slide relative to the ground. Rest is judged on positions
//!   ([`rock_loop`]) because a flat scanned base of near-coplanar micro-facets makes the soft
//!   contact jitter.
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

// ---------------------------------------------------------------------------------------------
// Field rocks: a rock at its true size, in a physical pose, under a recorded 3-component motion.
// ---------------------------------------------------------------------------------------------

/// A ground acceleration history in SI, world frame: a(t) = [x, y horizontal, z up] in m/s² at
/// real time t (s), zero outside [0, duration].
pub trait GroundAcceleration: Sync {
    /// Ground acceleration (m/s²) at real time `t` (s).
    fn accel_at(&self, t: f64) -> [f64; 3];
    /// When the motion ends (s).
    fn duration_s(&self) -> f64;
}

impl<F: Fn(f64) -> [f64; 3] + Sync> GroundAcceleration for (F, f64) {
    fn accel_at(&self, t: f64) -> [f64; 3] {
        if t < 0.0 || t > self.1 {
            [0.0; 3]
        } else {
            (self.0)(t)
        }
    }
    fn duration_s(&self) -> f64 {
        self.1
    }
}

/// How the rock stands on the ground before the motion starts.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Pose {
    /// The mesh frame is the world frame (+z up, as field scans are stored): the rock is put
    /// down on a horizontal ground under its lowest point and settles under gravity. It must come
    /// to rest on the stable micro-equilibrium of the quasi-static descent from the as-scanned
    /// down direction −z ([`Stone::rest`]).
    AsScanned,
    /// Exactly at rest on this stable micro-equilibrium (analysis index), as for pushes.
    Facet {
        /// Analysis index of the stable micro-equilibrium.
        id: usize,
    },
    /// The mesh rotated by this unit quaternion (w, x, y, z; mesh → world), put down and settled
    /// as for [`Pose::AsScanned`].
    Quat {
        /// Components w, x, y, z (normalised on use).
        q: [f64; 4],
    },
}

impl std::fmt::Display for Pose {
    /// The command line's spelling (`as-scanned`, `facet:ID`, `quat:w,x,y,z`), which
    /// [`Pose::from_str`](std::str::FromStr) reads back.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Pose::AsScanned => write!(f, "as-scanned"),
            Pose::Facet { id } => write!(f, "facet:{id}"),
            Pose::Quat { q } => write!(f, "quat:{},{},{},{}", q[0], q[1], q[2], q[3]),
        }
    }
}

impl std::str::FromStr for Pose {
    type Err = Error;
    fn from_str(s: &str) -> Result<Pose> {
        let bad = || {
            Error::Usage(format!(
                "--pose {s:?}: expected as-scanned, facet:ID (a stable micro-equilibrium) or quat:w,x,y,z"
            ))
        };
        if s == "as-scanned" {
            return Ok(Pose::AsScanned);
        }
        if let Some(id) = s.strip_prefix("facet:") {
            return Ok(Pose::Facet { id: id.trim().parse().map_err(|_| bad())? });
        }
        if let Some(q) = s.strip_prefix("quat:") {
            let v: Vec<f64> = q
                .split(',')
                .map(|x| x.trim().parse::<f64>())
                .collect::<std::result::Result<_, _>>()
                .map_err(|_| bad())?;
            let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            if v.len() != 4 || !(n > 0.0 && n.is_finite()) {
                return Err(Error::Usage(format!(
                    "--pose {s:?}: a quaternion needs four finite numbers, not all zero"
                )));
            }
            return Ok(Pose::Quat { q: [v[0], v[1], v[2], v[3]] });
        }
        Err(bad())
    }
}

/// The length unit of a mesh: how many metres one mesh unit is (`mm`, `cm`, `m`, `km` or a
/// positive number).
pub fn parse_length_unit(s: &str) -> Result<f64> {
    let v = match s {
        "mm" => 1e-3,
        "cm" => 1e-2,
        "m" => 1.0,
        "km" => 1e3,
        _ => s.parse::<f64>().map_err(|_| {
            Error::Usage(format!(
                "--length-unit {s:?}: expected mm, cm, m, km or a positive number of metres per mesh unit"
            ))
        })?,
    };
    if !(v > 0.0 && v.is_finite()) {
        return Err(Error::Usage(format!("--length-unit must be positive, got {s}")));
    }
    Ok(v)
}

/// A rock standing on the ground, settled, ready to be shaken.
pub struct Placed<'a> {
    /// The simulation, with the rock at rest.
    pub sim: Simulation<'a>,
    /// Position in [`Stone::stable`] of the micro-equilibrium it stands on.
    pub start: usize,
    /// Tilt (rad) of the body between where it was put down and where it came to rest.
    pub settling_tilt: f64,
}

/// Rest criterion for placement: the pose's expected micro-equilibrium, else a usage error that
/// says where the rock went instead.
fn refuse_pose(stone: &Stone, pose: &Pose, down: &Vec3, expected: u32, got: u32, settled: bool) -> Error {
    let eq = |f: u32| stone.facet_equilibrium[f as usize].map_or("?".to_string(), |e| e.to_string());
    let off = stone.body.facet_normals[expected as usize].dot(down).clamp(-1.0, 1.0).acos().to_degrees();
    if !settled {
        return Error::Usage(format!(
            "pose {pose}: the rock did not come to rest after it was put down (it is still moving at the time cap)"
        ));
    }
    Error::Usage(format!(
        "pose {pose}: put down on the ground, the rock does not rest on the stable micro-equilibrium under it \
         ({} by the quasi-static descent, whose facet is {off:.2}° from the given down direction) but rolled \
         to {}: the rock does not stand still in this pose (a scan made standing should be within a fraction of a \
         degree of its resting facet); choose --pose facet:ID or a quat: that stands",
        eq(expected),
        eq(got)
    ))
}

/// Put the rock down in `pose` and let it settle under gravity (module docs of the field-rock
/// section: [`shake_record`]).
///
/// * `Facet`: exactly at rest on the facet, settled for `p.settle_time` (as for pushes).
/// * `AsScanned` / `Quat`: the body orientation is the pose, G above the ground by the support
///   function h(d) of the down direction d (the lowest point touches), zero velocity; simulated
///   without motion until it rests ([`run_loop::RestDetector`] of `p.sim`, at most
///   `p.sim.max_time`). It must rest on the micro-equilibrium the quasi-static descent of h from
///   d reaches ([`Stone::rest`]), else the pose is refused.
pub fn place<'a>(stone: &'a Stone, pose: &Pose, p: &PerturbParams) -> Result<Placed<'a>> {
    let q = match *pose {
        Pose::Facet { id } => {
            let start = stone.position(id).ok_or_else(|| {
                let list: Vec<String> = stone.stable().iter().map(|s| s.index.to_string()).collect();
                Error::Usage(format!("facet:{id} is not a stable micro-equilibrium; stable ones: {}", list.join(", ")))
            })?;
            let sim = resting_simulation(stone, start, p, p.settle_time);
            let n = stone.body.facet_normals[stone.stable()[start].facet as usize];
            let settling_tilt = n.dot(&sim.state().down).clamp(-1.0, 1.0).acos();
            return Ok(Placed { sim, start, settling_tilt });
        }
        Pose::AsScanned => UnitQuaternion::identity(),
        Pose::Quat { q } => UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3])),
    };
    let down0 = q.inverse() * -Vec3::z();
    let expected = stone.rest(&down0);
    let z = stone.body.support(&down0);
    let mut sim = Simulation::new(&stone.body, &p.sim, &q, z, &Vec3::zeros(), &Vec3::zeros());
    sim.set_contact_frequency(p.contact_frequency);
    let min_steps = (p.settle_time / p.sim.dt).round() as u64;
    for _ in 0..min_steps {
        sim.step();
    }
    let end = rock_loop(&mut sim, &p.sim, &mut run_loop::Passive, &mut |_| {});
    let rest = stone.rest(&end.state.down);
    if !end.settled || rest.facet != expected.facet {
        return Err(refuse_pose(stone, pose, &down0, expected.facet, rest.facet, end.settled));
    }
    let start = stone.position(rest.equilibrium).expect("a stable micro-equilibrium");
    Ok(Placed { sim, start, settling_tilt: down0.dot(&end.state.down).clamp(-1.0, 1.0).acos() })
}

/// The ground driven by a 3-component acceleration in the scaled frame ([`shake_record`]).
struct GroundMotion3<'m> {
    motion: &'m dyn GroundAcceleration,
    /// Real seconds per scaled second, √(R_max / 1 m).
    time_factor: f64,
    /// cos and sin of the azimuth.
    rot: (f64, f64),
    dt: f64,
    v: Vec3,
    steps: u64,
}

impl GroundMotion3<'_> {
    /// Ground acceleration of the scaled frame at scaled time t: Froude scaling keeps
    /// accelerations (g is the same), so it is the real one at real time t·√L, horizontal part
    /// rotated by the azimuth.
    fn accel(&self, t: f64) -> Vec3 {
        let [x, y, z] = self.motion.accel_at(t * self.time_factor);
        let (c, s) = self.rot;
        Vec3::new(c * x - s * y, s * x + c * y, z)
    }
}

impl Drive for GroundMotion3<'_> {
    fn before_step(&mut self, sim: &mut Simulation, step: u64) {
        let a = self.accel((step as f64 + 0.5) * self.dt);
        let v_new = self.v + a * self.dt;
        sim.set_ground_velocity(&((self.v + v_new) * 0.5));
        self.v = v_new;
    }
    fn ground_velocity(&self) -> Vec3 {
        self.v
    }
    fn active_steps(&self) -> u64 {
        self.steps
    }
}

/// The outcome of one rock under one ground motion ([`shake_record`]), real units.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct RockRun {
    /// Overturned: came to rest on a stable micro-equilibrium of another flock than the one it
    /// stood on ([`Outcome::Toppled`]; a run still moving at the time cap is classified by the
    /// quasi-static descent from its last down direction, and `settled` is false).
    pub overturned: bool,
    /// Same micro-equilibrium, another one of the same flock (it rocked to a neighbour), or
    /// overturned.
    pub outcome: Outcome,
    /// Largest tilt (degrees) of the start facet's normal away from straight down.
    pub max_tilt_deg: f64,
    /// Residual sliding (m): horizontal displacement of G relative to the ground between the start
    /// and the end of the run (includes the travel of an overturn).
    pub slide_m: f64,
    /// Tilt (degrees) of the body while it settled after being put down.
    pub settling_tilt_deg: f64,
    /// Analysis index of the stable micro-equilibrium it stood on, and its flock.
    pub start_equilibrium: usize,
    /// Flock it stood on.
    pub start_flock: usize,
    /// Analysis index of the stable micro-equilibrium it ended on.
    pub final_equilibrium: usize,
    /// Flock it ended in.
    pub final_flock: usize,
    /// Came to rest (relative to the ground) before the time cap.
    pub settled: bool,
    /// Azimuth of the record's x axis in the world frame (degrees).
    pub azimuth_deg: f64,
    /// Real R_max of the rock (m).
    pub r_max_m: f64,
    /// Real time simulated from the start of the motion (s).
    pub time_s: f64,
    /// Steps simulated (placement excluded).
    pub steps: u64,
}

/// Shake a placed rock with `motion` (real time, SI, record x axis turned by `azimuth` rad in the
/// world frame) until it rests relative to the ground.
///
/// # True size (Froude-exact scaled simulation)
///
/// The rock is simulated in the scaled frame of [`super::params`] (R_max = 1, g = 9.81 m/s²) and
/// the motion is converted exactly: with L = `r_max_m`, t_scaled = t/√L, accelerations unchanged,
/// ground velocity / √L, displacement / L. The rigid-body equations with Coulomb friction,
/// Newton restitution and a rolling-resistance *length* δ (given as δ/L by
/// [`super::params::Preset::params_at_size`]) are invariant under this change of units, so the
/// scaled run *is* the run at true size in which the numerical parameters are converted the same
/// way: time step dt·√L, contact natural frequency f/√L, rapier's length unit L (prediction
/// distance, allowed penetration ∝ L). Every dimensional parameter enters through those four
/// groups; the real frequencies of the record meet the real √(g/L) of the rock. Checked against
/// Housner's rocking equation integrated at true size (`tests/shake_rock.rs`,
/// `results/fragility_surface/`).
pub fn shake_record(
    stone: &Stone,
    placed: Placed,
    p: &PerturbParams,
    motion: &dyn GroundAcceleration,
    azimuth: f64,
    r_max_m: f64,
) -> RockRun {
    let Placed { mut sim, start, settling_tilt } = placed;
    let s = &stone.stable()[start];
    let dt = p.sim.dt;
    let time_factor = r_max_m.sqrt();
    let steps = (motion.duration_s() / time_factor / dt).ceil() as u64;
    let mut ground =
        GroundMotion3 { motion, time_factor, rot: (azimuth.cos(), azimuth.sin()), dt, v: Vec3::zeros(), steps };
    let rel = |sim: &Simulation| {
        let b = sim.world.bodies[sim.body_handle].translation();
        let g = sim.world.bodies[sim.ground_handle].translation();
        Vec3::new((b.x - g.x) as f64, (b.y - g.y) as f64, 0.0)
    };
    let x0 = rel(&sim);
    let n = stone.body.facet_normals[s.facet as usize];
    let mut max_tilt: f64 = 0.0;
    let end = rock_loop(&mut sim, &p.sim, &mut ground, &mut |st| {
        max_tilt = max_tilt.max(n.dot(&st.down).clamp(-1.0, 1.0).acos())
    });
    let slide = (rel(&sim) - x0).norm() * r_max_m;
    let rest = stone.rest(&end.state.down);
    let outcome = classify(stone, start, Some(rest.facet), rest.flock);
    RockRun {
        overturned: outcome == Outcome::Toppled,
        outcome,
        max_tilt_deg: max_tilt.to_degrees(),
        slide_m: slide,
        settling_tilt_deg: settling_tilt.to_degrees(),
        start_equilibrium: s.index,
        start_flock: s.flock,
        final_equilibrium: rest.equilibrium,
        final_flock: rest.flock,
        settled: end.settled,
        azimuth_deg: azimuth.to_degrees(),
        r_max_m,
        time_s: end.steps as f64 * dt * time_factor,
        steps: end.steps,
    }
}

/// Shaking parameters of a rock at true size R_max = `r_max_m` on `surface`: the surface pair's
/// friction, restitution and rolling-resistance length ([`super::params::Preset::params_at_size`]
/// with the release-from-rest launch, whose launch fields are unused), the resting runs' contact
/// frequency, dt 1/240 s and a 20 s cap after the motion (scaled).
///
/// The rest of field-rock runs is [`rock_loop`]'s (positions, not speeds), over windows of
/// `rest_time` = 0.5 s.
pub fn rock_params(surface: super::params::Surface, r_max_m: f64) -> Result<PerturbParams> {
    let mut sim = super::params::Preset::Drop.params_at_size(surface, r_max_m)?;
    sim.max_time = 20.0;
    sim.rest_time = 0.5;
    Ok(PerturbParams { sim, ..PerturbParams::default() })
}

/// Largest change of the down direction (rad) over a rest window for a field rock at rest.
pub const ROCK_REST_ANGLE: f64 = 1e-3;
/// Largest horizontal displacement of G relative to the ground (R_max) over a rest window.
pub const ROCK_REST_DISPLACEMENT: f64 = 1e-3;

/// The run loop of field rocks: [`run_loop::run`] with a rest criterion on *positions*.
///
/// A flat scanned base is many near-coplanar micro-facets, and a rock standing on it never comes
/// to rest by the speed thresholds of drops (2·10⁻³ m/s, 5·10⁻³ rad/s, scaled): the soft
/// contact switches between micro-facets in a limit cycle of ~10⁻⁵ rad of tilt at up to
/// 2·10⁻² m/s and rad/s (measured on a block whose base is a 20 × 20 grid pushed down by up to
/// 10⁻⁴ h, at any contact frequency 30–120 Hz and dt 1/240 s). Here the rock is at rest once,
/// over a whole window of `rest_time` after the motion has ended, its down direction stayed
/// within [`ROCK_REST_ANGLE`] and G within [`ROCK_REST_DISPLACEMENT`] (relative to the ground) of
/// where they were at the window's start. A rock that still rocks by more than 0.06° is never at
/// rest; where it rests is decided by the quasi-static descent ([`Stone::rest`]). No certificate:
/// a driven system is not passive.
pub fn rock_loop(
    sim: &mut Simulation,
    p: &super::params::DropParams,
    drive: &mut dyn Drive,
    observe: &mut dyn FnMut(&super::world::BodyState),
) -> run_loop::RunEnd {
    let active = drive.active_steps();
    let window = ((p.rest_time / p.dt).ceil() as u64).max(1);
    let steps_max = active + (p.max_time / p.dt).ceil() as u64;
    let rel = |sim: &Simulation| {
        let b = sim.world.bodies[sim.body_handle].translation();
        let g = sim.world.bodies[sim.ground_handle].translation();
        Vec3::new((b.x - g.x) as f64, (b.y - g.y) as f64, 0.0)
    };
    let mut state = sim.state();
    let mut reference = (state.down, rel(sim));
    let mut calm = true;
    for step in 0..steps_max {
        drive.before_step(sim, step);
        sim.step();
        state = sim.state();
        observe(&state);
        let taken = step + 1;
        if taken <= active {
            reference = (state.down, rel(sim));
            continue;
        }
        let moved = state.down.dot(&reference.0).clamp(-1.0, 1.0).acos() > ROCK_REST_ANGLE
            || (rel(sim) - reference.1).norm() > ROCK_REST_DISPLACEMENT;
        calm &= !moved;
        if (taken - active) % window == 0 {
            if calm {
                return run_loop::RunEnd { steps: taken, settled: true, decided: None, state };
            }
            reference = (state.down, rel(sim));
            calm = true;
        }
    }
    run_loop::RunEnd { steps: steps_max, settled: false, decided: None, state }
}

impl GroundAcceleration for crate::ground_motion::Record {
    fn accel_at(&self, t: f64) -> [f64; 3] {
        self.at(t)
    }
    fn duration_s(&self) -> f64 {
        self.duration()
    }
}

/// A field rock and how it is shaken: everything of a run but the record.
#[derive(Clone, Debug, Serialize)]
pub struct RockSetup {
    /// The pose it stands in.
    pub pose: Pose,
    /// Metres per mesh unit.
    pub length_unit_m: f64,
    /// Real R_max of the rock (m): the body's R_max (mesh units) times `length_unit_m`.
    pub r_max_m: f64,
    /// Azimuth (rad, world frame) of the records' x axis.
    pub azimuth: f64,
    /// Simulation parameters (scaled frame, see [`shake_record`]).
    pub params: PerturbParams,
}

impl RockSetup {
    /// The setup of `stone` in `pose` with mesh unit `length_unit_m` metres on `surface`.
    pub fn new(
        stone: &Stone,
        pose: Pose,
        length_unit_m: f64,
        surface: super::params::Surface,
        azimuth: f64,
    ) -> Result<RockSetup> {
        let r_max_m = stone.body.r_max * length_unit_m;
        Ok(RockSetup { pose, length_unit_m, r_max_m, azimuth, params: rock_params(surface, r_max_m)? })
    }

    /// Real time step of the simulation (s): dt·√(R_max / 1 m).
    pub fn real_dt(&self) -> f64 {
        self.params.sim.dt * self.r_max_m.sqrt()
    }
}

/// One record × scale factor on a field rock: the record's intensity measures and the outcome.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct RecordRun {
    /// Name of the record.
    pub record: String,
    /// Scale factor applied to the record.
    pub scale: f64,
    /// Peak horizontal ground acceleration of the scaled record (g).
    pub pga_g: f64,
    /// Peak horizontal ground velocity of the scaled record (m/s).
    pub pgv_m_s: f64,
    /// PGV/PGA (s).
    pub pgv_over_pga_s: f64,
    /// Peak vertical ground acceleration (g).
    pub pga_vertical_g: f64,
    /// Outcome of the run.
    #[serde(flatten)]
    pub rock: RockRun,
}

/// Shake the rock of `setup` with `record` × `scale`: the record is scaled, its PGA/PGV measured
/// ([`crate::ground_motion::Record::measures`], on the record as given: correct its baseline
/// before), resampled without aliasing to the simulation's real step ([`RockSetup::real_dt`]) when
/// it is sampled finer, the rock placed ([`place`]) and shaken ([`shake_record`]).
pub fn run_record(
    stone: &Stone,
    setup: &RockSetup,
    record: &crate::ground_motion::Record,
    scale: f64,
) -> Result<RecordRun> {
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(Error::Usage(format!("scale factors must be ≥ 0, got {scale}")));
    }
    let scaled = record.scaled(scale);
    let m = scaled.measures();
    let dt = setup.real_dt();
    let driven = if scaled.dt < dt { scaled.resampled(dt)? } else { scaled };
    let placed = place(stone, &setup.pose, &setup.params)?;
    let rock = shake_record(stone, placed, &setup.params, &driven, setup.azimuth, setup.r_max_m);
    Ok(RecordRun {
        record: record.name.clone(),
        scale,
        pga_g: m.pga_g,
        pgv_m_s: m.pgv_m_s,
        pgv_over_pga_s: m.pgv_over_pga_s,
        pga_vertical_g: m.pga_vertical_g,
        rock,
    })
}

/// Every record × every scale factor on one rock, with the fragility surface fitted to them.
#[derive(Clone, Debug, Serialize)]
pub struct ShakeBatch {
    /// The rock and how it was shaken.
    pub setup: RockSetup,
    /// Settling tilt (degrees) when the rock was put down.
    pub settling_tilt_deg: f64,
    /// Analysis index of the stable micro-equilibrium it stands on.
    pub start_equilibrium: usize,
    /// One run per (record, scale), records in the given order, scales within a record.
    pub runs: Vec<RecordRun>,
    /// P(overturn | PGA, PGV/PGA) fitted to the runs ([`crate::ground_motion::surface`]).
    pub surface: Option<crate::ground_motion::surface::FragilitySurface>,
    /// Why the surface could not be fitted (e.g. every run had the same outcome).
    pub surface_error: Option<String>,
}

/// Run every record × scale in parallel (rayon; each run is deterministic and independent, so the
/// result does not depend on the thread count), calling `done` with each finished run (from any
/// thread, in completion order: for appending to a file as the runs finish). The pose is checked
/// once before any run. Runs already in `previous` (same record name and scale, from an
/// interrupted batch) are taken as they are and not run again: a run is a deterministic function
/// of the rock, the setup, the record and the scale, so the batch is the same as one run in one go.
pub fn run_batch(
    stone: &Stone,
    setup: &RockSetup,
    records: &[crate::ground_motion::Record],
    scales: &[f64],
    previous: &[RecordRun],
    done: &(dyn Fn(&RecordRun) + Sync),
) -> Result<ShakeBatch> {
    use rayon::prelude::*;
    if records.is_empty() || scales.is_empty() {
        return Err(Error::Usage("a batch needs at least one record and one scale factor".into()));
    }
    let placed = place(stone, &setup.pose, &setup.params)?;
    let s = &stone.stable()[placed.start];
    let (settling_tilt_deg, start_equilibrium) = (placed.settling_tilt.to_degrees(), s.index);
    drop(placed);
    let jobs: Vec<(usize, f64)> = (0..records.len()).flat_map(|r| scales.iter().map(move |&k| (r, k))).collect();
    let runs: Vec<RecordRun> = jobs
        .par_iter()
        .map(|&(r, k)| {
            let same = |p: &&RecordRun| p.record == records[r].name && p.scale.to_bits() == k.to_bits();
            if let Some(p) = previous.iter().find(same) {
                return Ok(p.clone());
            }
            let run = run_record(stone, setup, &records[r], k)?;
            done(&run);
            Ok(run)
        })
        .collect::<Result<_>>()?;
    let points: Vec<crate::ground_motion::surface::Run> = runs
        .iter()
        .map(|r| crate::ground_motion::surface::Run {
            pga_g: r.pga_g,
            pgv_over_pga_s: r.pgv_over_pga_s,
            overturned: r.rock.overturned,
        })
        .collect();
    let (surface, surface_error) = match crate::ground_motion::surface::FragilitySurface::fit(&points) {
        Ok(s) => (Some(s), None),
        Err(e) => (None, Some(e.to_string())),
    };
    Ok(ShakeBatch { setup: setup.clone(), settling_tilt_deg, start_equilibrium, runs, surface, surface_error })
}

/// Housner's rocking equation for a rigid rectangular block (Housner 1963; the form integrated by
/// Makris & Roussos 2000 and Zhang & Makris 2001), integrated independently of rapier — the
/// reference the rapier block is checked against (`tests/shake_rock.rs`,
/// `experiments/fragility_surface.rs`). `alpha` = atan(b/h), `p` = √(3g/4R) (rad/s), `accel` the
/// ground acceleration ü_g(t) (m/s²) for 0 ≤ t ≤ `duration` (s), `r` the impact ratio. Returns
/// whether the block overturns:
///
/// θ̈ = −p² [sin(α sgn θ − θ) + (ü_g/g) cos(α sgn θ − θ)],   p² = 3g/(4R),
///
/// rocking starts when |ü_g| > g tan α (θ takes the sign of −ü_g), at every impact (θ crossing 0)
/// the angular velocity is multiplied by r = 1 − (3/2) sin² α, and the block returns to rest when
/// an impact leaves it slower than 10⁻⁶ p while |ü_g| ≤ g tan α. It overturns when |θ| passes
/// π/2, or passes α after the ground motion has ended (gravity alone then tips it over).
/// RK4 with 4000 steps per 2π/p.
pub fn housner_overturns(alpha: f64, p: f64, accel: &dyn Fn(f64) -> f64, duration: f64, r: f64) -> bool {
    let g = GRAVITY;
    let h = 2.0 * std::f64::consts::PI / p / 4000.0;
    let rhs = |t: f64, th: f64, side: f64| {
        let a = if t <= duration { accel(t) } else { 0.0 };
        -p * p * ((alpha * side - th).sin() + a / g * (alpha * side - th).cos())
    };
    let (mut t, mut th, mut w, mut side, mut resting) = (0.0f64, 0.0f64, 0.0f64, 1.0f64, true);
    let t_end = duration + 40.0 / p;
    while t < t_end {
        let a = if t <= duration { accel(t) } else { 0.0 };
        if resting {
            if a.abs() > g * alpha.tan() {
                resting = false;
                side = -a.signum();
            } else {
                t += h;
                continue;
            }
        }
        // RK4 on (θ, ω) on the current corner.
        let k1 = (w, rhs(t, th, side));
        let k2 = (w + 0.5 * h * k1.1, rhs(t + 0.5 * h, th + 0.5 * h * k1.0, side));
        let k3 = (w + 0.5 * h * k2.1, rhs(t + 0.5 * h, th + 0.5 * h * k2.0, side));
        let k4 = (w + h * k3.1, rhs(t + h, th + h * k3.0, side));
        let th_new = th + h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        let w_new = w + h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        t += h;
        if th_new * side < 0.0 {
            // Impact: onto the other corner, angular velocity × r.
            th = 0.0;
            w = r * w_new;
            side = -side;
            let a = if t <= duration { accel(t) } else { 0.0 };
            if w.abs() < 1e-6 * p && a.abs() <= g * alpha.tan() {
                resting = true;
                w = 0.0;
            }
            continue;
        }
        th = th_new;
        w = w_new;
        if th.abs() > std::f64::consts::FRAC_PI_2 || (t > duration && th.abs() > alpha) {
            return true;
        }
    }
    false
}
