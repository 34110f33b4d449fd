//! The one run loop of every simulation (drops, pushes, ground shaking, the simulated hand
//! experimenter): step → state → certificate → rest → cap, and the energy certificate of
//! SPEC §6.
//!
//! ```text
//! for each step:   drive (ground motion)  →  rapier step + contact law  →  state
//!                  → observe (tilt, energy)  →  every CERTIFICATE_EVERY steps, while the
//!                  drive is passive: is the final facet/flock already certain?
//!                  → rest: speeds relative to the ground below the thresholds for rest_time
//!                  → cap: max_time (after the drive has ended)
//! ```
//!
//! **Certificate.** A passive body never gains mechanical energy, and z_G ≥ h(down) (the support
//! function), so E/(m g) bounds h(down) for the rest of the motion; when the sublevel component
//! of h that holds the current down direction contains a single stable facet (or a single flock)
//! of the merge tree, the outcome is decided ([`EnergyCertificate`]). The rolling resistance of
//! [`super::world`] only dissipates, so the certificate holds with it. It is never asked while a
//! ground motion drives the stone (that system is not passive), nor while the soft contact is
//! compressed ([`CERTIFICATE_MAX_COMPRESSION`]). Above the merge tree's decision ceiling
//! ([`crate::basins::MergeTree::decision_ceiling`]) nothing can be decided and a check costs O(1);
//! below it, a check is a descent of h (issue 16). Measured in `results/drops_dt/`: between
//! relaxed states with L ≤ R_max, L never rose by more than 10⁻³ R_max for dt from 1/480 to
//! 1/80 s, and the rest compression stayed below 8·10⁻⁴ R_max — together under the margin.
//!
//! **Measured limit.** Rapier's contact solver (4 iterations) does not conserve energy in the hard
//! first impact of a `throw` (≈ 10 m/s of the scaled body, 35 rad/s of spin): L can rise by up to
//! 1.8 R_max there (0.4 at 16 iterations, 0.08 at 64). The certificate can only decide once
//! L ≤ max h = R_max, where later impacts are slower than a drop from 1 R_max, and there no rise
//! beyond the margin is measured (`tests/contact.rs`); an early injection only delays the decision.
//! Certified outcomes equal full settling drop by drop on 400 throws (`tests/throws.rs`) and in
//! the `drop` and `throw` presets of `results/drops_certificate/` (3 bodies × 300 drops each).

use super::params::DropParams;
use super::stone::Stone;
use super::world::{BodyState, Simulation};
use crate::Vec3;
use serde::{Deserialize, Serialize};

/// What a certificate has proved about the end of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Decided {
    /// The run will end on this (stable) facet.
    Facet(u32),
    /// The run will end in this flock.
    Flock(u32),
}

/// A certificate that may end a run early: given the body's state (its body-frame down
/// direction, the height of G and the energy level L = E/(m g) in the scaled frame), what is
/// already certain.
pub trait Certificate: Sync {
    /// The decided outcome, if any.
    fn decided(&self, state: &BodyState) -> Option<Decided>;
}

/// No early termination.
pub struct NoCertificate;
impl Certificate for NoCertificate {
    fn decided(&self, _: &BodyState) -> Option<Decided> {
        None
    }
}

/// How early the energy certificate ends a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CertificateMode {
    /// Simulate every run until it rests (or the time cap).
    None,
    /// Stop once the final facet is certain.
    Facet,
    /// Stop once the final flock is certain.
    Flock,
}

impl CertificateMode {
    /// The user-facing name.
    pub fn name(self) -> &'static str {
        match self {
            CertificateMode::None => "none",
            CertificateMode::Facet => "facet",
            CertificateMode::Flock => "flock",
        }
    }
}

/// Safety margin added to the energy level before asking the merge tree, in units of R_max: the
/// body sinks into the ground by the contact's penetration, so z_G can be below h(d) by that much.
/// Measured with the project's collider: at most 8·10⁻⁴ R_max over 300 drops up to 2 R_max high
/// with restitution 0.6 (the certificate is validated drop by drop against full settling in
/// `tests/drops.rs` and `results/drops_certificate/`). Without it the tree decides wrongly (5
/// facet-level decisions of 6000 drops in `results/certificate_margin/`); a sharper margin would
/// save at most 11 % of the simulated time there at the facet level and 8 % at the flock level.
pub const CERTIFICATE_MARGIN: f64 = 3e-3;

/// Steps between two certificate checks (a check every step would save at most 6 ms of
/// simulated time per drop, `results/certificate_margin/`).
pub const CERTIFICATE_EVERY: u64 = 4;

/// The certificate is asked only while the contact is nearly relaxed: G at most this far (R_max)
/// below h(down), i.e. the soft contact compressed by at most 10⁻³ R_max. Rapier's contacts are
/// springs (30–60 Hz): in a hard impact they store energy that L = z_G + KE/(m g) does not count
/// and give it back (measured: up to 1.8 R_max of L on a throw released 5 R_max high with
/// 35 rad/s of spin, at dt = 1/240 s). With the compression bounded, the stored energy is at most
/// ½ (2π·60 Hz)² (10⁻³ R_max)² / g ≈ 7·10⁻⁴ R_max, which [`CERTIFICATE_MARGIN`] covers with the
/// compression itself (tested in `tests/contact.rs`).
pub const CERTIFICATE_MAX_COMPRESSION: f64 = 1e-3;

/// The merge-tree certificate of SPEC §6 on a prepared stone, at the facet or flock level.
pub struct EnergyCertificate<'a> {
    stone: &'a Stone,
    flock_level: bool,
    /// [`crate::basins::MergeTree::decision_ceiling`] (mesh units): at or above this energy
    /// level (with the margin) nothing can be decided, without a descent.
    ceiling: f64,
    /// Added to the energy level before asking the merge tree (R_max).
    margin: f64,
}

impl<'a> EnergyCertificate<'a> {
    /// The certificate of `mode` for `stone` (None for [`CertificateMode::None`]).
    pub fn new(stone: &'a Stone, mode: CertificateMode) -> Option<Self> {
        Self::with_margin(stone, mode, CERTIFICATE_MARGIN)
    }

    /// The certificate of `mode` with another `margin` (R_max) than [`CERTIFICATE_MARGIN`]: for
    /// measuring what the margin does (`experiments/certificate_margin.rs`), not for runs.
    pub fn with_margin(stone: &'a Stone, mode: CertificateMode, margin: f64) -> Option<Self> {
        match mode {
            CertificateMode::None => None,
            _ => {
                let flock_level = mode == CertificateMode::Flock;
                let ceiling = stone.tree.decision_ceiling(flock_level.then_some(&stone.facet_flock[..]));
                Some(EnergyCertificate { stone, flock_level, ceiling, margin })
            }
        }
    }

    /// Whether the contact is relaxed enough for L to bound the energy
    /// ([`CERTIFICATE_MAX_COMPRESSION`]).
    pub fn relaxed(&self, s: &BodyState) -> bool {
        self.stone.body.support(&s.down) - s.z <= CERTIFICATE_MAX_COMPRESSION
    }

    /// The stable facet that is certain in state `s`, if any.
    pub fn facet(&self, s: &BodyState) -> Option<u32> {
        if !self.relaxed(s) {
            return None;
        }
        self.stone.tree.decided(&s.down, (s.level + self.margin) * self.stone.body.r_max)
    }

    /// The flock that is certain in state `s`, if any.
    pub fn flock(&self, s: &BodyState) -> Option<usize> {
        if !self.relaxed(s) {
            return None;
        }
        let level = (s.level + self.margin) * self.stone.body.r_max;
        self.stone.tree.decided_flock(&s.down, level, &self.stone.facet_flock)
    }
}

impl Certificate for EnergyCertificate<'_> {
    fn decided(&self, s: &BodyState) -> Option<Decided> {
        // O(1): too much energy for any decision (exact, see `decision_ceiling`).
        if (s.level + self.margin) * self.stone.body.r_max >= self.ceiling {
            return None;
        }
        if self.flock_level {
            self.flock(s).map(|k| Decided::Flock(k as u32))
        } else {
            self.facet(s).map(Decided::Facet)
        }
    }
}

/// Counts consecutive calm steps (speeds under the rest thresholds) until `rest_time`.
pub struct RestDetector {
    calm: u64,
    needed: u64,
    linear: f64,
    angular: f64,
}

impl RestDetector {
    /// The criterion of `p`.
    pub fn new(p: &DropParams) -> Self {
        RestDetector {
            calm: 0,
            needed: (p.rest_time / p.dt).ceil() as u64,
            linear: p.rest_linear_speed,
            angular: p.rest_angular_speed,
        }
    }

    /// Feed the velocities relative to the ground; true once the body has been calm long enough.
    pub fn at_rest(&mut self, linvel: &Vec3, angvel: &Vec3) -> bool {
        if linvel.norm() < self.linear && angvel.norm() < self.angular {
            self.calm += 1;
        } else {
            self.calm = 0;
        }
        self.calm >= self.needed
    }
}

/// What drives a run besides gravity.
pub trait Drive {
    /// Prepare step number `step` (from 0): e.g. set the ground's velocity.
    fn before_step(&mut self, sim: &mut Simulation, step: u64);
    /// The ground's velocity (world frame) during the last step.
    fn ground_velocity(&self) -> Vec3;
    /// Steps during which the drive acts: no rest and no certificate before it has ended, and
    /// the time cap counts from its end.
    fn active_steps(&self) -> u64;
}

/// Nothing but gravity and the contact: drops and pushes.
pub struct Passive;
impl Drive for Passive {
    fn before_step(&mut self, _: &mut Simulation, _: u64) {}
    fn ground_velocity(&self) -> Vec3 {
        Vec3::zeros()
    }
    fn active_steps(&self) -> u64 {
        0
    }
}

/// How a run ended.
#[derive(Clone, Copy, Debug)]
pub struct RunEnd {
    /// Steps taken.
    pub steps: u64,
    /// The body rested (or a certificate decided) before the cap.
    pub settled: bool,
    /// What a certificate decided, if it ended the run.
    pub decided: Option<Decided>,
    /// The last state.
    pub state: BodyState,
}

/// The end rule of a run, step by step: no decision while the drive acts, then the certificate
/// every [`CERTIFICATE_EVERY`] steps, the rest criterion, and the time cap counted from the
/// drive's end. Shared by [`run`] and the many-body world of [`super::batch`], so that a drop
/// ends on the same step in both.
pub struct Progress {
    rest: RestDetector,
    active: u64,
    steps_max: u64,
    taken: u64,
}

impl Progress {
    /// The rule of `p` for a drive that acts during `active` steps.
    pub fn new(p: &DropParams, active: u64) -> Self {
        Progress { rest: RestDetector::new(p), active, steps_max: active + (p.max_time / p.dt).ceil() as u64, taken: 0 }
    }

    /// Steps taken so far.
    pub fn taken(&self) -> u64 {
        self.taken
    }

    /// The time cap is reached.
    pub fn capped(&self) -> bool {
        self.taken >= self.steps_max
    }

    /// Account for one more step that ended in `state`, the ground moving at `ground_velocity`:
    /// the end of the run if it ends here (decided, at rest, or at the cap).
    pub fn after_step(&mut self, state: &BodyState, ground_velocity: &Vec3, cert: &dyn Certificate) -> Option<RunEnd> {
        self.taken += 1;
        let taken = self.taken;
        if taken > self.active {
            if taken % CERTIFICATE_EVERY == 0 {
                if let Some(d) = cert.decided(state) {
                    return Some(RunEnd { steps: taken, settled: true, decided: Some(d), state: *state });
                }
            }
            if self.rest.at_rest(&(state.linvel - ground_velocity), &state.angvel) {
                return Some(RunEnd { steps: taken, settled: true, decided: None, state: *state });
            }
        }
        self.capped().then_some(RunEnd { steps: taken, settled: false, decided: None, state: *state })
    }
}

/// Run `sim` until rest, a certificate's decision or the time cap, with `drive` and `cert`;
/// `observe` sees the state after every step.
pub fn run(
    sim: &mut Simulation,
    p: &DropParams,
    drive: &mut dyn Drive,
    cert: &dyn Certificate,
    observe: &mut dyn FnMut(&BodyState),
) -> RunEnd {
    let mut progress = Progress::new(p, drive.active_steps());
    let mut state = sim.state();
    while !progress.capped() {
        drive.before_step(sim, progress.taken());
        sim.step();
        state = sim.state();
        observe(&state);
        if let Some(end) = progress.after_step(&state, &drive.ground_velocity(), cert) {
            return end;
        }
    }
    RunEnd { steps: progress.taken(), settled: false, decided: None, state }
}
