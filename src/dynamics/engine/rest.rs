//! When a run has come to rest: by speeds ([`SpeedRest`], drops and pushes) or by positions
//! over whole windows ([`PositionRest`], stones shaken where they stand).

use crate::dynamics::engine::params::RunParams;
use crate::dynamics::engine::world::BodyState;
use crate::Vec3;
use serde::{Deserialize, Serialize};

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
