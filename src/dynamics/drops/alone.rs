//! One drop alone, with an observer at every step. [`run_alone`]: in its own rapier world, kept
//! after the run: rapier's flight whatever the parameters say (the world of [`Simulation`]), no
//! certificate and no drive, and the speed rest rule; the world is returned so that the drop can
//! be stepped on past the rest rule's end, until the stone is on its equilibrium
//! ([`go_on_to_equilibrium`]). [`simulate_observed`]: in a batch of one, with the numerics of
//! the run's parameters (their flight included), as [`crate::dynamics::drops::simulate`] runs it.

use crate::dynamics::drops::batch::simulate_batch;
use crate::dynamics::drops::launch::{release_height, DropOutcome, Release};
use crate::dynamics::drops::params::DropParams;
use crate::dynamics::engine::rest::RestKind;
use crate::dynamics::engine::run::{run_to_end, NoCertificate, Passive, RunEnd};
use crate::dynamics::engine::simulation::Simulation;
use crate::dynamics::engine::world::BodyState;
use crate::dynamics::stone::{Rest, Stone};

/// Run the drop `release` of `stone` under `p` in a [`Simulation`] of its own until the speed
/// rule finds it at rest (or the time cap), `observe` seeing the state after every step: the
/// simulation, to go on from the end, and how the run ended.
pub fn run_alone<'a>(
    stone: &'a Stone,
    p: &DropParams,
    release: &Release,
    observe: &mut dyn FnMut(&BodyState),
) -> (Simulation<'a>, RunEnd) {
    let z0 = release_height(stone, p, release);
    let mut sim = Simulation::new(&stone.body, &p.sim, &release.orientation, z0, &release.linvel, &release.angvel);
    let end = run_to_end(&mut sim, &p.sim, &mut Passive, &NoCertificate, RestKind::Speeds, observe);
    (sim, end)
}

/// Step `sim`, a run of `stone` that ended resting as `from` ([`Stone::rest`]), on with nothing
/// but gravity and the contact until the stone is on its equilibrium ([`Rest::on_equilibrium`],
/// read after every step) or for `steps_max` steps: the steps taken and where it rests then
/// (`from` if no step was taken).
pub fn go_on_to_equilibrium(sim: &mut Simulation, stone: &Stone, from: Rest, steps_max: u64) -> (u64, Rest) {
    let mut now = from;
    let steps = sim.step_until(steps_max, &mut |s| {
        now = stone.rest(&s.down);
        now.on_equilibrium()
    });
    (steps, now)
}

/// Simulate drop `index`, released as `release`, of `stone` under `p` to its end without a
/// certificate, in a batch of one ([`simulate_batch`]: the numerics of `p`, its flight included),
/// `observe` seeing the stone's state after every step: the drop's outcome.
pub fn simulate_observed(
    stone: &Stone,
    p: &DropParams,
    release: &Release,
    index: u64,
    observe: &mut dyn FnMut(&BodyState),
) -> Option<DropOutcome> {
    let mut out = None;
    let mut queue = std::iter::once((index, *release));
    simulate_batch(stone, p, &NoCertificate, 1, &mut queue, &mut |o| out = Some(o), &mut |_, s| observe(s));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Analysis, Options};
    use crate::dynamics::drops::{launch::launch, params::Preset, simulate::simulate};
    use crate::dynamics::engine::params::Flight;
    use crate::dynamics::surface::Surface;

    #[test]
    fn a_drop_alone_ends_as_the_simulated_drop_and_is_observed_at_every_step() {
        let (mesh, repairs) = crate::generate::cuboid(1.0, 0.8, 0.5).into_solid_boundary().unwrap();
        let stone = Stone::new(&Analysis::of_solid(mesh, repairs, &Options::default()).unwrap(), 0.0035).unwrap();
        let mut p = Preset::Throw.params(Surface::SteelOnWood);
        p.sim.flight.mode = Flight::Rapier;
        for i in 0..3 {
            let release = launch(&mut crate::rng::item_rng(4, i), &p);
            let mut seen = 0u64;
            let (sim, end) = run_alone(&stone, &p, &release, &mut |_| seen += 1);
            let simulated = simulate(&stone, &p, &release, i, &NoCertificate);
            assert_eq!(seen, end.steps);
            assert!(end.settled && simulated.settled);
            assert_eq!(Some(stone.rest(&end.state.down).facet), simulated.facet, "drop {i}");
            assert!((end.steps as f64 * p.sim.numerics.dt - simulated.time).abs() < 1e-9, "drop {i}");
            assert_eq!(sim.deepest_penetration(), simulated.deepest_penetration);
        }
    }

    #[test]
    fn an_observed_drop_ends_as_the_simulated_drop() {
        let (mesh, repairs) = crate::generate::cuboid(1.0, 0.8, 0.5).into_solid_boundary().unwrap();
        let stone = Stone::new(&Analysis::of_solid(mesh, repairs, &Options::default()).unwrap(), 0.0035).unwrap();
        let p = Preset::Throw.params(Surface::SteelOnWood);
        assert_eq!(p.sim.flight.mode, Flight::Free);
        for i in 0..3 {
            let release = launch(&mut crate::rng::item_rng(6, i), &p);
            let (mut seen, mut last) = (0u64, None);
            let observed = simulate_observed(&stone, &p, &release, i, &mut |s| (seen, last) = (seen + 1, Some(*s)));
            assert_eq!(observed, Some(simulate(&stone, &p, &release, i, &NoCertificate)), "drop {i}");
            // Seen to the end: the last state rests on the outcome's facet.
            assert!(seen > 0);
            assert_eq!(Some(stone.rest(&last.unwrap().down).facet), observed.unwrap().facet);
        }
    }

    #[test]
    fn going_on_stops_on_the_equilibrium() {
        let (mesh, repairs) = crate::generate::cuboid(1.0, 0.8, 0.5).into_solid_boundary().unwrap();
        let stone = Stone::new(&Analysis::of_solid(mesh, repairs, &Options::default()).unwrap(), 0.0035).unwrap();
        let p = Preset::Drop.params(Surface::SteelOnWood);
        let (mut sim, end) = run_alone(&stone, &p, &launch(&mut crate::rng::item_rng(2, 0), &p), &mut |_| {});
        let rest = stone.rest(&end.state.down);
        // No step: where it was. A box at rest on its face is on the equilibrium after one more step.
        assert_eq!(go_on_to_equilibrium(&mut sim, &stone, rest, 0), (0, rest));
        let (steps, now) = go_on_to_equilibrium(&mut sim, &stone, rest, 100);
        assert_eq!((steps, now.facet), (1, rest.facet));
        assert!(now.on_equilibrium());
        // Tipped by a spin it takes more than one step to come back onto a face.
        sim.set_velocity(&crate::Vec3::zeros(), &crate::Vec3::new(0.0, 3.0, 0.0));
        let (steps, now) = go_on_to_equilibrium(&mut sim, &stone, rest, 100_000);
        assert!(steps > 1 && now.on_equilibrium(), "{steps} steps: {now:?}");
    }
}
