//! The launch of a drop and its outcome: what [`crate::dynamics::drops::simulate`] and the many-drop world of
//! [`crate::dynamics::drops::batch`] share (in its own module so that neither imports the other's).
//!
//! The launch ([`launch`]) draws from the drop's own random stream: a Haar-uniform orientation,
//! an angular velocity (exact or Gaussian, [`crate::dynamics::drops::params::SpinDistribution`]) and a horizontal
//! velocity along a uniformly random azimuth; the lowest hull point starts `height` above the
//! ground. Where the stone came to rest is decided by the static theory ([`Stone::rest`]: the
//! quasi-static descent of the support function from the final down direction), never by the
//! facet whose normal is closest to down.

use crate::dynamics::drops::params::{DropParams, SpinDistribution};
use crate::dynamics::engine::run::{Decided, RunEnd};
use crate::dynamics::stone::Stone;
use crate::rng::{random_rotation, random_unit, Stream};
use crate::Vec3;
use nalgebra::UnitQuaternion;
use rand::RngExt;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

/// What happened to one drop (one line of a checkpoint).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DropOutcome {
    /// Index of the drop in its run (determines its random stream).
    pub index: u64,
    /// Whether the rest criterion was met (or a certificate decided the drop) before `max_time`.
    pub settled: bool,
    /// The stable facet the drop ended on (by [`Stone::rest`]; None when a flock-level
    /// certificate ended the drop before the facet was decided).
    pub facet: Option<u32>,
    /// The flock decided by a flock-level certificate (otherwise read it off `facet`).
    pub flock: Option<u32>,
    /// Simulated time (s, scaled) until rest, until the certificate's decision, or the cap.
    pub time: f64,
    /// The drop was ended early by the energy certificate.
    pub certified: bool,
    /// For a drop that was simulated to its end (rest or cap): how far above its rest on the
    /// facet G stopped, in R_max ([`crate::dynamics::stone::Rest::height_above`]); None when certified.
    #[serde(default)]
    pub height_above: Option<f64>,
    /// The deepest any hull corner went below the ground after any step or sub-step of the drop
    /// (R_max, [`crate::dynamics::engine::world::penetration`]); 0 in checkpoints written before it was measured.
    #[serde(default)]
    pub deepest_penetration: f64,
}

impl DropOutcome {
    /// Settled, but stopped above its stable facet by more than the contact tolerance.
    pub fn off_equilibrium(&self) -> bool {
        self.settled && self.height_above.is_some_and(|h| h > crate::dynamics::stone::REST_TOLERANCE)
    }
}

/// Initial state of a drop: orientation (body → world), velocity and angular velocity (world).
#[derive(Clone, Copy, Debug)]
pub struct Release {
    /// Body → world.
    pub orientation: UnitQuaternion<f64>,
    /// Velocity of G (world frame).
    pub linvel: Vec3,
    /// Angular velocity (world frame).
    pub angvel: Vec3,
}

/// Draw the launch of `p` from a drop's random stream: orientation (4 normals), angular velocity
/// (3 normals), then the azimuth of the horizontal velocity (one uniform).
pub fn launch(rng: &mut Stream, p: &DropParams) -> Release {
    let orientation = random_rotation(rng);
    let angvel = match p.launch.spin_distribution {
        SpinDistribution::Fixed => random_unit(rng) * p.launch.spin,
        SpinDistribution::Gaussian => {
            Vec3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal)) * (p.launch.spin / 3f64.sqrt())
        }
    };
    let azimuth: f64 = rng.random_range(0.0..std::f64::consts::TAU);
    let linvel = Vec3::new(azimuth.cos(), azimuth.sin(), 0.0) * p.launch.horizontal_speed;
    Release { orientation, linvel, angvel }
}

/// Height of G at release: the lowest hull point `p.height` above the ground.
pub fn release_height(stone: &Stone, p: &DropParams, release: &Release) -> f64 {
    let down_body = release.orientation.inverse() * -Vec3::z();
    p.launch.height + stone.body.support(&down_body)
}

/// The outcome of drop `index` from how its run ended: the certificate's decision, or where the
/// stone rests by [`Stone::rest`]. Its `deepest_penetration` is left at 0 for the caller, which
/// stepped the stone, to fill in.
pub fn outcome(stone: &Stone, p: &DropParams, end: &RunEnd, index: u64) -> DropOutcome {
    let time = end.steps as f64 * p.sim.numerics.dt;
    let outcome = |facet, flock, height_above| DropOutcome {
        index,
        settled: end.settled,
        facet,
        flock,
        time,
        certified: end.decided.is_some(),
        height_above,
        deepest_penetration: 0.0,
    };
    match end.decided {
        Some(Decided::Facet(f)) => outcome(Some(f), None, None),
        Some(Decided::Flock(k)) => outcome(None, Some(k), None),
        None => {
            let rest = stone.rest(&end.state.down);
            outcome(Some(rest.facet), None, Some(rest.height_above))
        }
    }
}
