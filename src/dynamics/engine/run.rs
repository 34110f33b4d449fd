//! The one run loop of every simulation (drops, pushes, ground shaking, the simulated hand
//! experimenter): step → state → certificate → rest → cap, and the energy certificate that may
//! end a drop early.
//!
//! ```text
//! for each step:   drive (ground motion)  →  rapier step + contact law  →  state
//!                  → observe (tilt, energy)  →  every CERTIFICATE_EVERY steps, while the
//!                  drive is passive: is the final facet/flock already certain?
//!                  → rest: a RestRule (speeds, or positions over windows)
//!                  → cap: max_time (after the drive has ended)
//! ```
//!
//! **Certificate: an argument whose one gap is measured, not a proof.** A rigid body on a passive
//! contact never gains mechanical energy, and z_G ≥ h(down) (the support function), so E/(m g)
//! bounds h(down) for the rest of the motion; when the sublevel component of h that holds the
//! current down direction contains a single stable facet (or a single flock) of the merge tree,
//! the outcome is decided ([`EnergyCertificate`]). The parts of the contact this project writes
//! only dissipate (the rolling resistance of [`crate::dynamics::engine::world`], and its impact law, which adds no
//! energy beyond what the step's start or rapier's own step had). Rapier's soft-constraint solver
//! is not proven to: what it may give back is covered by a margin ([`CERTIFICATE_MARGIN`]) whose
//! size is measured, not derived. The certificate is never asked while a ground motion drives the
//! stone (that system is not passive), nor while the soft contact is compressed
//! ([`CERTIFICATE_MAX_COMPRESSION`]). Above the merge tree's decision ceiling
//! ([`crate::basins::MergeTree::decision_ceiling`]) nothing can be decided and a check costs O(1);
//! below it, a check is a descent of h.
//!
//! **Measured limit.** With rapier's own flight (`--flight rapier`, impacts found after the stone
//! is already up to 0.2 R_max inside the ground), rapier's contact solver (4 iterations) does not
//! conserve energy in the hard first impact of a throw (≈ 10 m/s of the scaled body, 35 rad/s of
//! spin): L could rise by up to 1.8 R_max there (0.4 at 16 iterations, 0.08 at 64). The certificate can only decide once
//! L ≤ max h = R_max, where later impacts are slower than a drop from 1 R_max, and there no rise
//! beyond the margin is measured (`tests/contact.rs`); an early injection only delays the decision.
//! Certified outcomes equal full settling drop by drop on 400 throws (`tests/throws.rs`) and in
//! the `drop` and `throw` presets of `results/drops_certificate/` (3 bodies × 300 drops each).

use crate::dynamics::engine::params::RunParams;
use crate::dynamics::engine::world::{BodyState, Simulation};
use crate::dynamics::stone::Stone;
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
/// body sinks into the ground by the contact's compression (the certificate is asked only up to
/// [`CERTIFICATE_MAX_COMPRESSION`]), so h(down) can be above z_G, and hence above L, by that
/// much, plus what the solver gives back. **Measured, not proven** — the largest later rise of
/// h(down) above the L read at any state where the certificate may be asked is 1.46·10⁻³ R_max
/// over 72 000 drops at the default step (the bundled stone and 39 scanned meshes, 3 presets,
/// rapier's flight and free flight), so the margin is 2.1 times it, and 0 of 7 940 691 decisions
/// there (103 282 of them the first of their drop) name another facet or flock than full settling
/// reaches (`results/certificate_decisions/`). Without a margin the tree decides wrongly (11 of
/// 11 472 decisions in `results/certificate_margin/`, none from 3·10⁻⁴ on).
pub const CERTIFICATE_MARGIN: f64 = 3e-3;

/// Steps between two certificate checks (a check every step would save at most 6 ms of
/// simulated time per drop, `results/certificate_margin/`).
pub const CERTIFICATE_EVERY: u64 = 4;

/// The certificate is asked only while the contact is nearly relaxed: G at most this far (R_max)
/// below h(down), i.e. the contact compressed by at most 10⁻³ R_max. In a hard impact the contact
/// is compressed and L = z_G + KE/(m g) does not count what the compression will give back.
///
/// *What the compression can give back: not bounded by a formula.* Read as a linear spring of
/// rapier's natural frequency f, a compression c would store ½ (2π f)² c² / g per unit weight:
/// 7.2·10⁻³ R_max at f = 60 Hz and c = 10⁻³ R_max (2.9·10⁻² at the 120 Hz of runs that start at
/// rest) — more than the margin. Rapier's contact is not that spring: its soft constraint
/// (TGS-soft, rapier 0.36) pushes a penetration out with a bias velocity that the relaxation pass
/// of every sub-step takes away again, so a compression is restored mostly as height (which L
/// counts once the contact has relaxed). That is an argument about the solver, not a bound; what
/// is left is the solver's own error, and it is measured on the quantity the certificate needs:
/// over the whole future of every state where the certificate may be asked (relaxed,
/// L ≤ 1 R_max), how far the support height h(down) rises above the L read there
/// (`tests/contact.rs` on pebble throws; `results/certificate_decisions/` on 72 000 drops of 40
/// bodies, largest 1.46·10⁻³ R_max, under [`CERTIFICATE_MARGIN`]).
pub const CERTIFICATE_MAX_COMPRESSION: f64 = 1e-3;

/// The merge-tree energy certificate ([`crate::basins`], `docs/methods.md`) on a prepared stone,
/// at the facet or flock level.
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
    /// ([`CERTIFICATE_MAX_COMPRESSION`]). h(down) by hill climbing (O(1) in the hull size, exact
    /// to the collider's f32 rounding, 10⁻⁷ R_max: [`crate::dynamics::stone::Body::support_climb`]).
    pub fn relaxed(&self, s: &BodyState) -> bool {
        self.stone.body.support_climb(&s.down) - s.z <= CERTIFICATE_MAX_COMPRESSION
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

/// What a rest rule reads after a step.
#[derive(Clone, Copy, Debug)]
pub struct RestSample<'s> {
    /// The stone's state.
    pub state: &'s BodyState,
    /// The ground's velocity during the step (world frame).
    pub ground_velocity: Vec3,
    /// Horizontal position of G relative to the ground (scaled frame).
    pub offset: Vec3,
}

/// When a stone is at rest. Two implementations, one per kind of contact history:
///
/// * [`SpeedRest`]: speeds relative to the ground below thresholds, held over a window — the
///   rule of drops and pushes, whose stones end on a facet of the hull after rolling;
/// * [`PositionRest`]: positions that stay put over whole windows — the rule of stones shaken
///   where they stand, whose flat scanned bases make the soft contact jitter (see there).
///
/// Which one a run uses is a [`RestKind`] chosen by the kind of run (drops and pushes: speeds;
/// stones shaken where they stand: positions); both read the same [`RestSample`] and neither is
/// ever asked while a drive acts. Why not by the stone, from whether its hull has a flat base of
/// near-coplanar micro-facets: every hull measured has them — the smallest angle between
/// adjacent facets is 1.2·10⁻⁵–9.9·10⁻⁴ rad on the seven scanned stones of `data/meshes` (the
/// bundled stone 6.9·10⁻⁵) and 9·10⁻⁶–9·10⁻⁵ on synthetic pebbles — so such a rule would give
/// every stone positions, and change every calibrated drop result.
pub trait RestRule: Send {
    /// Account for a step taken after the drive ended; true once the stone is at rest.
    fn at_rest(&mut self, sample: &RestSample) -> bool;
    /// Account for a step taken while the drive acts (no rest is possible then).
    fn driven(&mut self, _sample: &RestSample) {}
}

/// The rest rules of [`RestRule`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RestKind {
    /// [`SpeedRest`].
    Speeds,
    /// [`PositionRest`].
    Positions,
}

impl RestKind {
    /// The rule of this kind for the thresholds and window of `p`.
    pub fn rule(self, p: &RunParams) -> Box<dyn RestRule> {
        match self {
            RestKind::Speeds => Box::new(SpeedRest::new(p)),
            RestKind::Positions => Box::new(PositionRest::new(p)),
        }
    }
}

/// Rest by speeds: linear and angular speed relative to the ground below
/// `rest_linear_speed` and `rest_angular_speed` for `rest_time` of consecutive steps.
pub struct SpeedRest {
    calm: u64,
    needed: u64,
    linear: f64,
    angular: f64,
}

impl SpeedRest {
    /// The criterion of `p`.
    pub fn new(p: &RunParams) -> Self {
        SpeedRest {
            calm: 0,
            needed: (p.rest.rest_time / p.numerics.dt).ceil() as u64,
            linear: p.rest.rest_linear_speed,
            angular: p.rest.rest_angular_speed,
        }
    }
}

impl RestRule for SpeedRest {
    fn at_rest(&mut self, s: &RestSample) -> bool {
        let linvel = s.state.linvel - s.ground_velocity;
        if linvel.norm() < self.linear && s.state.angvel.norm() < self.angular {
            self.calm += 1;
        } else {
            self.calm = 0;
        }
        self.calm >= self.needed
    }
}

/// Largest change of the down direction (rad) over a rest window of [`PositionRest`].
pub const REST_ANGLE: f64 = 1e-3;
/// Largest horizontal displacement of G relative to the ground (R_max) over a rest window of
/// [`PositionRest`].
pub const REST_DISPLACEMENT: f64 = 1e-3;

/// Rest by positions, over whole windows of `rest_time` after the drive has ended: the stone is
/// at rest once, over one window, its down direction stayed within [`REST_ANGLE`] and G within
/// [`REST_DISPLACEMENT`] (relative to the ground) of where they were at the window's start.
///
/// A flat scanned base is many near-coplanar micro-facets, and a rock standing on it never comes
/// to rest by the speed thresholds of drops (2·10⁻³ m/s, 5·10⁻³ rad/s, scaled): the soft
/// contact switches between micro-facets in a limit cycle of ~10⁻⁵ rad of tilt at up to
/// 2·10⁻² m/s and rad/s (measured on a block whose base is a 20 × 20 grid pushed down by up to
/// 10⁻⁴ h, at any contact frequency 30–120 Hz and dt 1/240 s). A stone that still rocks by more
/// than 0.06° is never at rest; where it rests is decided by the quasi-static descent.
pub struct PositionRest {
    window: u64,
    after: u64,
    reference: Option<(Vec3, Vec3)>,
    calm: bool,
}

impl PositionRest {
    /// The criterion of `p` (window `rest_time`).
    pub fn new(p: &RunParams) -> Self {
        PositionRest {
            window: ((p.rest.rest_time / p.numerics.dt).ceil() as u64).max(1),
            after: 0,
            reference: None,
            calm: true,
        }
    }
}

impl RestRule for PositionRest {
    fn driven(&mut self, s: &RestSample) {
        self.reference = Some((s.state.down, s.offset));
    }

    fn at_rest(&mut self, s: &RestSample) -> bool {
        let (down, offset) = *self.reference.get_or_insert((s.state.down, s.offset));
        let moved = s.state.down.dot(&down).clamp(-1.0, 1.0).acos() > REST_ANGLE
            || (s.offset - offset).norm() > REST_DISPLACEMENT;
        self.calm &= !moved;
        self.after += 1;
        if self.after % self.window == 0 {
            if self.calm {
                return true;
            }
            self.reference = Some((s.state.down, s.offset));
            self.calm = true;
        }
        false
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
/// drive's end. Shared by [`run`] and the many-body world of [`crate::dynamics::drops::batch`], so that a drop
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
pub fn run(
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
