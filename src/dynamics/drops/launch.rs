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
    /// Drop `index`, settled on its equilibrium on `facet` after `time` s: not certified, never
    /// below the ground. An outcome written by hand, as a run reader is checked against.
    pub fn at_rest(index: u64, facet: u32, time: f64) -> Self {
        DropOutcome {
            index,
            settled: true,
            facet: Some(facet),
            flock: None,
            time,
            certified: false,
            height_above: Some(0.0),
            deepest_penetration: 0.0,
        }
    }

    /// Settled, but stopped above its stable facet by more than the contact tolerance.
    pub fn off_equilibrium(&self) -> bool {
        self.settled && self.height_above.is_some_and(|h| h > crate::dynamics::stone::REST_TOLERANCE)
    }

    /// The flock the drop ended in: the one a flock-level certificate decided, else the flock of
    /// its facet in `facet_flock` (facet index → flock id, as [`Stone::facet_flock`]); None when
    /// neither is known.
    pub fn flock_in(&self, facet_flock: &[Option<usize>]) -> Option<usize> {
        self.flock.map(|k| k as usize).or_else(|| self.facet.and_then(|f| facet_flock[f as usize]))
    }
}

/// The outcome of drop `index` run elsewhere (another engine, another model) that ended after
/// `time` s with down direction `down` (body frame), `settled` if it had come to rest there, as
/// the project's rule reads it: where it rests by [`Stone::rest`] (not certified). None for
/// `down` (an end the caller cannot use, e.g. non-finite) gives a drop not settled, on no facet.
pub fn outcome_at(stone: &Stone, index: u64, down: Option<&Vec3>, settled: bool, time: f64) -> DropOutcome {
    let rest = down.map(|d| stone.rest(d));
    DropOutcome {
        index,
        settled: settled && rest.is_some(),
        facet: rest.as_ref().map(|r| r.facet),
        flock: None,
        time,
        certified: false,
        height_above: rest.as_ref().map(|r| r.height_above),
        deepest_penetration: 0.0,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Analysis, Options};

    #[test]
    fn an_end_elsewhere_rests_where_the_static_theory_puts_it() {
        let (mesh, repairs) = crate::generate::cuboid(1.0, 0.8, 0.5).into_solid_boundary().unwrap();
        let a = Analysis::of_solid(mesh, repairs, &Options::default()).unwrap();
        let stone = Stone::new(&a, a.macro_nu(&Options::default()).0).unwrap();
        // Ending with a face's normal straight down: at rest flat on that face.
        for n in [Vec3::x(), -Vec3::y(), -Vec3::z()] {
            let o = outcome_at(&stone, 3, Some(&n), true, 1.5);
            let facet = o.facet.expect("a facet") as usize;
            assert!((stone.body.facet_normals[facet] - n).norm() < 1e-9, "{n:?}: facet {facet}");
            assert!(o.height_above.is_some_and(|h| h.abs() < 1e-9) && o.settled && !o.off_equilibrium());
            assert_eq!((o.index, o.time, o.certified, o.flock), (3, 1.5, false, None));
        }
        // Tilted θ = 0.2 rad towards +x off the bottom face (within its basin: the box tips over
        // only at atan(0.5 / 0.25)): back on it, off its equilibrium by the support of the tilted
        // direction, that of the corner (0.5, ·, −0.25), less the face's distance 0.25, over
        // R_max = |(0.5, 0.4, 0.25)|.
        let t = 0.2f64;
        let o = outcome_at(&stone, 0, Some(&Vec3::new(t.sin(), 0.0, -t.cos())), true, 1.0);
        assert!((stone.body.facet_normals[o.facet.unwrap() as usize] + Vec3::z()).norm() < 1e-9);
        let rise = (0.5 * t.sin() + 0.25 * t.cos() - 0.25) / 0.4725f64.sqrt();
        assert!((o.height_above.unwrap() - rise).abs() < 1e-9 && o.off_equilibrium(), "{o:?}");
        // An end the caller cannot use: not settled, on no facet.
        let lost = outcome_at(&stone, 1, None, true, 60.0);
        assert!(!lost.settled && lost.facet.is_none() && lost.height_above.is_none());
    }
}
