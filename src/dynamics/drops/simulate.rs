//! One drop or throw of a stone onto flat ground, from release to rest (drops, `docs/methods.md`).
//!
//! The launch and the outcome rule are [`crate::dynamics::drops::launch`]'s; the run itself is the one loop of
//! [`crate::dynamics::engine::run`] (speed rest rule, [`RestKind::Speeds`]), or a batch of one
//! ([`crate::dynamics::drops::batch`]) when the flight between contacts leaves rapier.

use crate::dynamics::drops::launch::{outcome, release_height, DropOutcome, Release};
use crate::dynamics::drops::params::DropParams;
use crate::dynamics::engine::rest::RestKind;
use crate::dynamics::engine::run::{run_to_end, Certificate, Passive};
use crate::dynamics::engine::simulation::Simulation;
use crate::dynamics::stone::Stone;

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
