//! What the engine needs to run a stone, split by concern as rapier splits its integration
//! parameters: the [`ContactParams`] between stone and ground, the [`Numerics`] of the
//! integration, the [`FlightParams`] of flight and impacts, and the [`RestParams`] that end a
//! run. [`RunParams`] carries the four; a drop adds its launch to them
//! ([`crate::dynamics::drops::params::DropParams`]), a run that starts at rest its settling and
//! contact stiffness ([`crate::dynamics::resting::RestingParams`]).
//!
//! **Units.** Every run is simulated in the stone's scaled frame: lengths in units of R_max (the
//! largest distance from G to a hull corner), mass 1, g = 9.81 m/s². Rigid-body dynamics with
//! Coulomb friction, restitution and a rolling-resistance *length* is invariant under Froude
//! scaling, so only dimensionless groups matter: height / R_max, speed / √(g R_max),
//! spin · √(R_max / g), δ / R_max. A number given here for the scaled body (R_max = 1 m) converts
//! to a real stone of size R_max = L (metres) as
//!
//! ```text
//! length_real = length · L,   speed_real = speed · √L,   spin_real = spin / √L,   time_real = time · √L
//! ```
//!
//! (e.g. a spin of 5 rad/s of the scaled body is 5/√0.01 = 50 rad/s for a die with R_max = 1 cm).
//! [`crate::dynamics::surface::Surface::scaled`] turns a surface pair's physical
//! rolling-resistance length into δ / R_max for a stone of a given size.
//!
//! Every field documents its default: the calibrated throw on steel on wood for a stone of the
//! reference size R_max = 1 cm ([`crate::dynamics::size::REFERENCE_R_MAX_M`]).
//! The serialised form is flat (each group is flattened), as it was before the split: a
//! checkpoint or a report names `dt`, `friction`, `rest_time`… at one level.

use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// The contact between the stone and the ground (the engine's contact law,
/// [`crate::dynamics::engine::contact`]), and the global velocity damping.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactParams {
    /// Coulomb friction coefficient of the contact. Default 0.4 (steel on wood).
    pub friction: f64,
    /// Restitution coefficient of the contact, in [0, 1]. Default 0.5 (steel on wood).
    pub restitution: f64,
    /// Rolling-resistance length δ_r / R_max: the contact's rolling torque is at most δ_r N
    /// ([`crate::dynamics::engine::contact`]). Default 0.02: steel on wood (δ = 0.2 mm) for
    /// R_max = 1 cm.
    pub rolling_resistance: f64,
    /// Torsional-friction length δ_t / R_max: on a single contact point the torque about the
    /// normal is at most δ_t N (on two or more points rapier's Coulomb twist friction acts instead,
    /// never both: [`crate::dynamics::engine::contact`]). Default: equal to `rolling_resistance`.
    pub torsional_friction: f64,
    /// Global linear velocity damping (1/s of the scaled body). Default 0: it would slow a body in
    /// flight; kept for the overdamped quasi-static preset and for comparison with older runs.
    pub linear_damping: f64,
    /// Global angular velocity damping (1/s of the scaled body). Default 0 (see
    /// `linear_damping`).
    pub angular_damping: f64,
}

impl Default for ContactParams {
    fn default() -> Self {
        let d = 2e-4 / crate::dynamics::size::REFERENCE_R_MAX_M;
        ContactParams {
            friction: 0.4,
            restitution: 0.5,
            rolling_resistance: d,
            torsional_friction: d,
            linear_damping: 0.0,
            angular_damping: 0.0,
        }
    }
}

/// The time integration of a run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Numerics {
    /// Time step (s of the scaled body). Default [`MAX_STABLE_DT`] = 1/120 s (the drop presets'
    /// longest stable step), checked against [`REFERENCE_DT`] = 1/240 s (`results/drops_dt/`,
    /// `results/cuboid_dice/`, `results/drops_vs_mujoco/`); runs that start at rest pin 1/240 s.
    pub dt: f64,
    /// Velocity iterations of rapier's contact solver per step. Default 4 (rapier's).
    pub solver_iterations: usize,
    /// Give up after this long (s of the scaled body). Default 60 s: with rolling resistance
    /// instead of global damping, a smooth pebble thrown onto a table rolls for 5–15 s (scaled)
    /// before it rests (measured on a 400-vertex pebble: mean 9 s at δ = 0.02 R_max).
    pub max_time: f64,
}

impl Default for Numerics {
    fn default() -> Self {
        Numerics { dt: MAX_STABLE_DT, solver_iterations: 4, max_time: 60.0 }
    }
}

/// When a run has come to rest: its speeds (or, for runs on a moving ground, its positions) stay
/// below these for `rest_time` ([`crate::dynamics::engine::rest`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RestParams {
    /// Rest: linear speed below this (m/s, scaled) … Default 2·10⁻³.
    pub rest_linear_speed: f64,
    /// … and angular speed below this (rad/s, scaled) … Default 5·10⁻³.
    pub rest_angular_speed: f64,
    /// … for this long (s, scaled). Default 0.25 s.
    pub rest_time: f64,
}

impl Default for RestParams {
    fn default() -> Self {
        RestParams { rest_linear_speed: 2e-3, rest_angular_speed: 5e-3, rest_time: 0.25 }
    }
}

/// How the flight between contacts is integrated, and how impacts start.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FlightParams {
    /// How a drop's flight between contacts is integrated, and how its impacts start. Default
    /// [`Flight::Free`]: exact landings and sub-stepped impacts
    /// ([`crate::dynamics::engine::impact`]), at which the throw is calibrated
    /// (`results/cuboid_dice/`). A checkpoint written before the field existed ran with
    /// [`Flight::Rapier`], which is what it reads as.
    #[serde(rename = "flight", default = "Flight::rapier")]
    pub mode: Flight,
    /// Strict impacts: read the sub-step bound of [`crate::dynamics::engine::impact`] again after
    /// every impact sub-step and cut the rest of the step finer where an impulse within the
    /// sub-step has turned the stone faster than the motion at the step's start allowed for (an
    /// impact can turn a spin about the vertical into a tumble). Default false: the count is read
    /// at the step's start, as the calibration and every result in `results/` were computed; with
    /// it, a box spun at 400 rad/s stays within [`crate::dynamics::engine::impact::DEPTH_BOUND`]
    /// (0.033 R_max deep without it, `tests/flight.rs`), and about one ordinary throw in a
    /// thousand ends elsewhere.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub strict_impacts: bool,
}

/// Everything the engine needs of a run: contact, numerics, rest rule, flight (each group's
/// fields serialised at one level).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunParams {
    /// The contact between the stone and the ground.
    #[serde(flatten)]
    pub contact: ContactParams,
    /// The time integration.
    #[serde(flatten)]
    pub numerics: Numerics,
    /// When the run has come to rest.
    #[serde(flatten)]
    pub rest: RestParams,
    /// Flight between contacts and impacts.
    #[serde(flatten)]
    pub flight: FlightParams,
}

impl RunParams {
    /// Refuse parameters that cannot describe a run, naming the parameter (its field name,
    /// [`Error::Parameter`]) and the value.
    pub fn check(&self) -> Result<()> {
        let (c, n, r) = (&self.contact, &self.numerics, &self.rest);
        let positive = [("dt", n.dt), ("max_time", n.max_time), ("rest_time", r.rest_time)];
        if let Some((name, v)) = positive.iter().find(|(_, v)| !(*v > 0.0 && v.is_finite())) {
            return Err(Error::parameter(name, v, "positive and finite"));
        }
        let non_negative = [
            ("friction", c.friction),
            ("rolling_resistance", c.rolling_resistance),
            ("torsional_friction", c.torsional_friction),
            ("linear_damping", c.linear_damping),
            ("angular_damping", c.angular_damping),
            ("rest_linear_speed", r.rest_linear_speed),
            ("rest_angular_speed", r.rest_angular_speed),
        ];
        if let Some((name, v)) = non_negative.iter().find(|(_, v)| !(*v >= 0.0 && v.is_finite())) {
            return Err(Error::parameter(name, v, "≥ 0 and finite"));
        }
        if !(0.0..=1.0).contains(&c.restitution) {
            return Err(Error::parameter("restitution", c.restitution, "in [0, 1]"));
        }
        if n.solver_iterations == 0 || n.solver_iterations > 1000 {
            return Err(Error::parameter("solver_iterations", n.solver_iterations, "in 1..=1000"));
        }
        if n.dt > n.max_time {
            return Err(Error::parameter(
                "dt",
                n.dt,
                format!("at most the time cap max_time ({:.4} √(R_max/g))", n.max_time * crate::GRAVITY.sqrt()),
            ));
        }
        // Contact stability: rapier's soft contacts (30–60 Hz) need several steps per
        // oscillation, and a body must not fall through more than a fraction of itself per step.
        if n.dt > MAX_STABLE_DT {
            return Err(Error::parameter(
                "dt",
                n.dt,
                format!(
                    "at most {:.4} √(R_max/g) for the contact solver (the soft contacts oscillate at 30–60 Hz of the \
                     scaled body and need ≥ 4 steps per period; the drop presets take this longest step, runs from \
                     rest half of it)",
                    MAX_STABLE_DT * crate::GRAVITY.sqrt()
                ),
            ));
        }
        if n.max_time / n.dt > 1e8 {
            return Err(Error::parameter(
                "max_time",
                n.max_time,
                format!("at most 10⁸ steps of dt = {:.4e} √(R_max/g)", n.dt * crate::GRAVITY.sqrt()),
            ));
        }
        Ok(())
    }
}

/// The longest time step (s, scaled) a run accepts: 1/120 s, four steps per period of the
/// stiffest default contact (30 Hz). Measured: at 1/120 s the cube still lands 1/6 on each face;
/// at dt = 1 s 4 of 5 drops never settle.
pub const MAX_STABLE_DT: f64 = 1.0 / 120.0;

/// The reference time step (s, scaled): the step the drop presets' default
/// ([`crate::dynamics::drops::params::Preset::largest_stable_dt`]) and every longer one are
/// checked against (`results/drops_dt/`, `results/drops_settling/`), `rocking drop
/// --reference`'s, and the step of runs that start at rest
/// ([`crate::dynamics::resting::RESTING_DT`]).
pub const REFERENCE_DT: f64 = 1.0 / 240.0;

/// How the flight of a dropped stone between contacts is integrated
/// ([`crate::dynamics::engine::flight`]), and with it how impacts start
/// ([`crate::dynamics::engine::impact`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Flight {
    /// Every step in rapier's pipeline, in the air as on the ground: contacts are found only at
    /// the step boundaries, so an impact can start 0.1–0.2 R_max inside the ground in a throw
    /// (`results/drops_impacts/`). The former reference numerics, kept to compare.
    Rapier,
    /// The default. Out of rapier while the stone is clear of the ground: G on its parabola and
    /// the rotation by Euler's equations ([`crate::dynamics::engine::flight`]), handed to rapier
    /// at the exact instant its lowest point comes within
    /// [`crate::dynamics::engine::flight::CONTACT_CLEARANCE`] of the ground; in contact, a step
    /// that could bring a hull point down by more than
    /// [`crate::dynamics::engine::impact::IMPACT_APPROACH`] is sub-stepped
    /// ([`crate::dynamics::engine::impact`]). How deep impacts go is measured after every step and
    /// sub-step and reported by every run (`results/drops_impacts/`). Runs that start at rest
    /// (pushes, shaking) sub-step their impacts the same way and keep their flight in rapier.
    /// Global damping (`linear_damping`, `angular_damping`) acts in free flight too, exactly
    /// ([`crate::dynamics::engine::flight::Damping`]).
    #[default]
    Free,
}

impl Flight {
    /// Every mode.
    pub const ALL: [Flight; 2] = [Flight::Rapier, Flight::Free];

    /// [`Flight::Rapier`]: what a checkpoint written before the field existed ran with.
    pub fn rapier() -> Flight {
        Flight::Rapier
    }

    /// The user-facing name (as `--flight` takes it).
    pub fn name(self) -> &'static str {
        match self {
            Flight::Rapier => "rapier",
            Flight::Free => "free",
        }
    }
}

impl fmt::Display for Flight {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Flight {
    type Err = Error;
    fn from_str(s: &str) -> Result<Flight> {
        Flight::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| Error::unknown("flight mode", s, &["rapier", "free"]))
    }
}
