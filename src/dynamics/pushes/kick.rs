//! The two perturbation families of a resting stone ([`Family`]): a push (an impulse at a point
//! of the hull surface) and a spin (an angular velocity about the contact point), each scaled to a
//! given kinetic energy ε m g R_max ([`kick`]).

use crate::dynamics::stone::Stone;
use crate::rng::{random_unit, Stream};
use crate::{Error, Result, Vec3, GRAVITY};
use nalgebra::{Matrix3, UnitQuaternion};
use serde::{Deserialize, Serialize};

/// How a resting stone is perturbed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Family {
    /// Impulsive push at a random point of the surface in a random inward direction.
    Push,
    /// Angular-velocity kick about a random axis through the contact point.
    Spin,
}

impl Family {
    /// The user-facing name.
    pub fn name(self) -> &'static str {
        match self {
            Family::Push => "push",
            Family::Spin => "spin",
        }
    }
}

impl std::str::FromStr for Family {
    type Err = Error;
    fn from_str(s: &str) -> Result<Family> {
        match s {
            "push" => Ok(Family::Push),
            "spin" => Ok(Family::Spin),
            _ => Err(Error::unknown("perturbation family", s, &["push", "spin"])),
        }
    }
}

/// The velocities (world frame) of a perturbation of energy ε·m g R_max (scaled frame: m = 1,
/// R_max = 1) of `family`, for a stone resting on facet `facet` with orientation `q` and G at
/// height `z`; also the point of application of a push (body frame, relative to G).
pub fn kick(
    stone: &Stone,
    facet: u32,
    q: &UnitQuaternion<f64>,
    z: f64,
    family: Family,
    epsilon: f64,
    rng: &mut Stream,
) -> (Vec3, Vec3, Option<Vec3>) {
    let energy = epsilon * GRAVITY;
    let inertia = stone.body.world_inertia(q);
    match family {
        Family::Push => {
            let (x, n) = stone.surface_point(rng, facet);
            let (r, n) = (q * x, q * n);
            let mut u = random_unit(rng);
            if u.dot(&n) > 0.0 {
                u = -u;
            }
            let c = r.cross(&u);
            let inv = inertia.try_inverse().unwrap_or_else(Matrix3::identity);
            let k = 1.0 + c.dot(&(inv * c));
            let j = (2.0 * energy / k).sqrt();
            (u * j, inv * c * j, Some(x))
        }
        Family::Spin => {
            let a = random_unit(rng);
            let r = Vec3::new(0.0, 0.0, z);
            let ip = inertia + (Matrix3::identity() * r.norm_squared() - r * r.transpose());
            let w = a * (2.0 * energy / a.dot(&(ip * a))).sqrt();
            (w.cross(&r), w, None)
        }
    }
}
