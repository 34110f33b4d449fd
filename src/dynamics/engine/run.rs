//! The one run loop of every simulation of one stone in its world (pushes, ground shaking,
//! drops with rapier's flight), and the end rule every run shares, the batches of drops too
//! ([`Progress`]): step → state → certificate → rest → cap.
//!
//! ```text
//! for each step:   drive (ground motion)  →  rapier step + contact law  →  state
//!                  → observe (tilt, energy)  →  every CERTIFICATE_EVERY steps, while the
//!                  drive is passive: is the final facet/flock already certain?
//!                  → rest: a RestRule (speeds, or positions over windows)
//!                  → cap: max_time (after the drive has ended)
//! ```
//!
//! A [`Certificate`] may end a run early once its outcome is certain; the energy certificate of
//! the merge tree is [`crate::dynamics::certificate`]. The rest rules are
//! [`crate::dynamics::engine::rest`].

use crate::dynamics::engine::params::RunParams;
use crate::dynamics::engine::rest::{RestKind, RestRule, RestSample};
use crate::dynamics::engine::simulation::Simulation;
use crate::dynamics::engine::world::BodyState;
use crate::Vec3;

/// What a certificate has proved about the end of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Decided {
    /// The run will end on this (stable) facet.
    Facet(u32),
    /// The run will end in this flock.
    Flock(u32),
}

impl Decided {
    /// The facet decided, if the decision is at the facet level.
    pub fn facet(self) -> Option<u32> {
        match self {
            Decided::Facet(f) => Some(f),
            Decided::Flock(_) => None,
        }
    }

    /// The flock decided, if the decision is at the flock level.
    pub fn flock(self) -> Option<u32> {
        match self {
            Decided::Flock(k) => Some(k),
            Decided::Facet(_) => None,
        }
    }

    /// What was decided, at whichever level: the facet's index or the flock's id.
    pub fn id(self) -> u32 {
        match self {
            Decided::Facet(x) | Decided::Flock(x) => x,
        }
    }
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

/// Steps between two certificate checks (a check every step would save at most 6 ms of
/// simulated time per drop, `results/certificate_margin/`).
pub const CERTIFICATE_EVERY: u64 = 4;

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
/// drive's end. Shared by [`run_to_end`] and the many-body world of [`crate::dynamics::drops::batch`], so that a drop
/// ends on the same step in both.
pub struct Progress {
    rest: Box<dyn RestRule>,
    active: u64,
    steps_max: u64,
    taken: u64,
}

impl Progress {
    /// The rule of `p` for a drive that acts during `active` steps, with rest rule `rest`.
    pub fn new(p: &RunParams, active: u64, rest: RestKind) -> Self {
        let steps_max = active + (p.numerics.max_time / p.numerics.dt).ceil() as u64;
        Progress { rest: rest.rule(p), active, steps_max, taken: 0 }
    }

    /// Show the rule the state the run starts from (a rest window's first reference).
    pub fn start(&mut self, sample: &RestSample) {
        self.rest.driven(sample);
    }

    /// Steps taken so far.
    pub fn taken(&self) -> u64 {
        self.taken
    }

    /// The time cap is reached.
    pub fn capped(&self) -> bool {
        self.taken >= self.steps_max
    }

    /// Account for one more step that ended in `sample`: the end of the run if it ends here
    /// (decided, at rest, or at the cap).
    pub fn after_step(&mut self, sample: &RestSample, cert: &dyn Certificate) -> Option<RunEnd> {
        self.taken += 1;
        let (taken, state) = (self.taken, sample.state);
        if taken > self.active {
            if taken % CERTIFICATE_EVERY == 0 {
                if let Some(d) = cert.decided(state) {
                    return Some(RunEnd { steps: taken, settled: true, decided: Some(d), state: *state });
                }
            }
            if self.rest.at_rest(sample) {
                return Some(RunEnd { steps: taken, settled: true, decided: None, state: *state });
            }
        } else {
            self.rest.driven(sample);
        }
        self.capped().then_some(RunEnd { steps: taken, settled: false, decided: None, state: *state })
    }
}

/// Run `sim` until rest (by the rule `rest`), a certificate's decision or the time cap, with
/// `drive` and `cert`; `observe` sees the state after every step. The one run loop of every
/// command; [`crate::dynamics::drops::batch`] runs many stones by the same [`Progress`].
pub fn run_to_end(
    sim: &mut Simulation,
    p: &RunParams,
    drive: &mut dyn Drive,
    cert: &dyn Certificate,
    rest: RestKind,
    observe: &mut dyn FnMut(&BodyState),
) -> RunEnd {
    let mut progress = Progress::new(p, drive.active_steps(), rest);
    let mut state = sim.state();
    progress.start(&RestSample {
        state: &state,
        ground_velocity: drive.ground_velocity(),
        offset: sim.ground_offset(),
    });
    while !progress.capped() {
        drive.before_step(sim, progress.taken());
        sim.step();
        state = sim.state();
        observe(&state);
        let sample =
            RestSample { state: &state, ground_velocity: drive.ground_velocity(), offset: sim.ground_offset() };
        if let Some(end) = progress.after_step(&sample, cert) {
            return end;
        }
    }
    RunEnd { steps: progress.taken(), settled: false, decided: None, state }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_decision_names_its_level() {
        assert_eq!((Decided::Facet(7).facet(), Decided::Facet(7).flock(), Decided::Facet(7).id()), (Some(7), None, 7));
        assert_eq!((Decided::Flock(2).facet(), Decided::Flock(2).flock(), Decided::Flock(2).id()), (None, Some(2), 2));
    }
}
