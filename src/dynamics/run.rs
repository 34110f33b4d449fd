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
//! ground motion drives the stone (that system is not passive).

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

/// A certificate that may end a run early: given the body-frame down direction and the energy
/// level L = E/(m g) in the scaled frame (a height of G over R_max), what is already certain.
pub trait Certificate: Sync {
    /// The decided outcome, if any.
    fn decided(&self, down: &Vec3, level: f64) -> Option<Decided>;
}

/// No early termination.
pub struct NoCertificate;
impl Certificate for NoCertificate {
    fn decided(&self, _: &Vec3, _: f64) -> Option<Decided> {
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
/// `tests/drops.rs` and `results/drops_certificate/`).
pub const CERTIFICATE_MARGIN: f64 = 3e-3;

/// Steps between two certificate checks.
pub const CERTIFICATE_EVERY: u64 = 4;

/// The merge-tree certificate of SPEC §6 on a prepared stone, at the facet or flock level.
pub struct EnergyCertificate<'a> {
    stone: &'a Stone,
    flock_level: bool,
}

impl<'a> EnergyCertificate<'a> {
    /// The certificate of `mode` for `stone` (None for [`CertificateMode::None`]).
    pub fn new(stone: &'a Stone, mode: CertificateMode) -> Option<Self> {
        match mode {
            CertificateMode::None => None,
            _ => Some(EnergyCertificate { stone, flock_level: mode == CertificateMode::Flock }),
        }
    }

    /// The stable facet that is certain at energy level `level` (scaled), if any.
    pub fn facet(&self, down: &Vec3, level: f64) -> Option<u32> {
        self.stone.tree.decided(down, (level + CERTIFICATE_MARGIN) * self.stone.body.r_max)
    }

    /// The flock that is certain at energy level `level` (scaled), if any.
    pub fn flock(&self, down: &Vec3, level: f64) -> Option<usize> {
        let level = (level + CERTIFICATE_MARGIN) * self.stone.body.r_max;
        self.stone.tree.decided_flock(down, level, &self.stone.facet_flock)
    }
}

impl Certificate for EnergyCertificate<'_> {
    fn decided(&self, down: &Vec3, level: f64) -> Option<Decided> {
        if self.flock_level {
            self.flock(down, level).map(|k| Decided::Flock(k as u32))
        } else {
            self.facet(down, level).map(Decided::Facet)
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

/// Run `sim` until rest, a certificate's decision or the time cap, with `drive` and `cert`;
/// `observe` sees the state after every step.
pub fn run(
    sim: &mut Simulation,
    p: &DropParams,
    drive: &mut dyn Drive,
    cert: &dyn Certificate,
    observe: &mut dyn FnMut(&BodyState),
) -> RunEnd {
    let mut rest = RestDetector::new(p);
    let active = drive.active_steps();
    let steps_max = active + (p.max_time / p.dt).ceil() as u64;
    let mut state = sim.state();
    for step in 0..steps_max {
        drive.before_step(sim, step);
        sim.step();
        state = sim.state();
        observe(&state);
        let taken = step + 1;
        if taken <= active {
            continue;
        }
        if taken % CERTIFICATE_EVERY == 0 {
            if let Some(d) = cert.decided(&state.down, state.level) {
                return RunEnd { steps: taken, settled: true, decided: Some(d), state };
            }
        }
        if rest.at_rest(&(state.linvel - drive.ground_velocity()), &state.angvel) {
            return RunEnd { steps: taken, settled: true, decided: None, state };
        }
    }
    RunEnd { steps: steps_max, settled: false, decided: None, state }
}
