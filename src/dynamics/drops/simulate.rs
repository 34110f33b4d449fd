//! One drop or throw of a stone onto flat ground, from release to rest (drops, `docs/methods.md`).
//!
//! The launch and the outcome rule are [`crate::dynamics::drops::launch`]'s; the run itself is the one loop of
//! [`crate::dynamics::engine::run`] (speed rest rule, [`RestKind::Speeds`]), or a batch of one
//! ([`crate::dynamics::drops::batch`]) when the flight between contacts leaves rapier.
//! [`flat_restitution`] measures the coefficient of restitution a flat landing has in the engine,
//! for calibrating another engine's contact against it.

use crate::dynamics::drops::launch::{outcome, release_height, DropOutcome, Release};
use crate::dynamics::drops::params::DropParams;
use crate::dynamics::engine::params::RunParams;
use crate::dynamics::engine::rest::RestKind;
use crate::dynamics::engine::run::{run_to_end, Certificate, Passive};
use crate::dynamics::engine::simulation::Simulation;
use crate::dynamics::stone::Stone;
use crate::Vec3;
use nalgebra::UnitQuaternion;

/// Simulate one drop to rest (or to the certificate, or to the time cap), alone in its world
/// (with [`crate::dynamics::engine::params::Flight::Free`]: a batch of one, [`crate::dynamics::drops::batch`], where the flight is).
pub fn simulate(stone: &Stone, p: &DropParams, release: &Release, index: u64, cert: &dyn Certificate) -> DropOutcome {
    if crate::dynamics::engine::flight::applies(&p.sim) {
        let mut out = None;
        crate::dynamics::drops::batch::simulate_batch(
            stone,
            p,
            cert,
            1,
            &mut std::iter::once((index, *release)),
            &mut |o| out = Some(o),
            &mut |_, _| {},
        );
        return out.expect("a batch of one drop finishes it");
    }
    let z0 = release_height(stone, p, release);
    let mut sim = Simulation::new(&stone.body, &p.sim, &release.orientation, z0, &release.linvel, &release.angvel);
    let end = run_to_end(&mut sim, &p.sim, &mut Passive, cert, RestKind::Speeds, &mut |_| {});
    DropOutcome { deepest_penetration: sim.deepest_penetration(), ..outcome(stone, p, &end, index) }
}

/// The coefficient of restitution of a flat landing in the engine under `p` (its contact and step;
/// damping switched off, so that the rebound measures the contact alone): the stone dropped from
/// rest with its facet of outward normal `normal` (body frame) facing down, its lowest point
/// `height` (R_max) above the ground; e = √(rebound height / drop height) of G above its height
/// at rest on the facet. The rebound is found by the velocity (from the step where G first moves
/// up to the step where it moves down again), not by the contact impulse, which a sub-stepped
/// impact ([`crate::dynamics::engine::impact`]) leaves at zero after the step. 0 when G does not
/// rise again within 10 s.
pub fn flat_restitution(stone: &Stone, p: &RunParams, normal: &Vec3, height: f64) -> f64 {
    let mut p = p.clone();
    (p.contact.linear_damping, p.contact.angular_damping) = (0.0, 0.0);
    let q = UnitQuaternion::rotation_between(normal, &-Vec3::z()).unwrap_or_else(UnitQuaternion::identity);
    let h = stone.body.support(normal);
    let mut sim = Simulation::new(&stone.body, &p, &q, height + h, &Vec3::zeros(), &Vec3::zeros());
    let (mut rising, mut apex) = (false, f64::NEG_INFINITY);
    for _ in 0..(10.0 / p.numerics.dt) as usize {
        sim.step();
        let s = sim.state();
        rising |= s.linvel.z > 0.0;
        if rising {
            if s.linvel.z <= 0.0 {
                return ((apex - h).max(0.0) / height).sqrt();
            }
            apex = apex.max(s.z);
        }
    }
    0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Analysis, Options};
    use crate::dynamics::drops::params::Preset;
    use crate::dynamics::surface::Surface;

    #[test]
    fn a_flat_landing_rebounds_with_the_contact_restitution() {
        let (mesh, repairs) = crate::generate::cuboid(1.0, 0.8, 0.5).into_solid_boundary().unwrap();
        let a = Analysis::of_solid(mesh, repairs, &Options::default()).unwrap();
        let stone = Stone::new(&a, a.macro_nu(&Options::default()).0).unwrap();
        let mut p = Preset::Drop.params(Surface::SteelOnWood).sim;
        // Newton's law at the impact: the rebound speed is e times the impact speed, so G rises
        // back to e² of its drop height, whatever the damping of the preset.
        let measured = [0.2, 0.5, 0.8].map(|e| {
            p.contact.restitution = e;
            (e, flat_restitution(&stone, &p, &-Vec3::z(), 0.5))
        });
        assert!(measured.iter().all(|(e, m)| (m - e).abs() < 0.02), "{measured:?}");
    }
}
