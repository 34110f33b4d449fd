//! One stone in its own world above the ground, stepped with the contact law
//! ([`crate::dynamics::engine::contact`]) and, where one step cannot resolve an impact, in
//! sub-steps ([`crate::dynamics::engine::impact`]): the world of every push, shaking run and
//! drop with rapier's flight ([`crate::dynamics::engine::run`]).

use crate::dynamics::engine::body::Body;
use crate::dynamics::engine::contact::{step_world, ContactLaw};
use crate::dynamics::engine::convert;
use crate::dynamics::engine::impact::{self, step_substeps};
use crate::dynamics::engine::params::{Flight, RunParams};
use crate::dynamics::engine::world::{body_state, ground_world, insert_stone, normal_impulse, penetration, BodyState};
use crate::Vec3;
use nalgebra::UnitQuaternion;
use rapier3d::prelude::*;

/// A rapier world with the ground and the stone, in the scaled frame. Drops, pushes and ground
/// shaking all run on it ([`crate::dynamics::engine::run`]).
pub struct Simulation<'a> {
    /// The rapier world.
    pub world: PhysicsWorld,
    /// The stone's rigid body.
    pub body_handle: RigidBodyHandle,
    /// The (kinematic) ground's rigid body.
    pub ground_handle: RigidBodyHandle,
    body_collider: ColliderHandle,
    ground_collider: ColliderHandle,
    law: ContactLaw,
    body: &'a Body,
    /// Sub-step impacts ([`Flight::Free`]).
    resolve_impacts: bool,
    /// Read the sub-step bound again after every sub-step ([`crate::dynamics::engine::params::FlightParams::strict_impacts`]).
    strict_impacts: bool,
    /// The run's time step and solver iterations (restored after a sub-stepped step).
    dt: f64,
    iterations: usize,
    /// The deepest any hull corner has been below the ground after any (sub-)step so far (R_max).
    deepest: f64,
}

impl<'a> Simulation<'a> {
    /// The stone with orientation `orientation` (body → world), G at height `z`, and the given
    /// velocities (world frame), above a flat ground.
    pub fn new(
        body: &'a Body,
        p: &RunParams,
        orientation: &UnitQuaternion<f64>,
        z: f64,
        linvel: &Vec3,
        angvel: &Vec3,
    ) -> Self {
        let (mut world, ground_handle, ground_collider) = ground_world(p);
        let (body_handle, body_collider) = insert_stone(&mut world, body, p, orientation, z, linvel, angvel);
        Simulation {
            world,
            body_handle,
            ground_handle,
            body_collider,
            ground_collider,
            law: ContactLaw::of(&p.contact),
            body,
            resolve_impacts: p.flight.mode == Flight::Free,
            strict_impacts: p.flight.strict_impacts,
            dt: p.numerics.dt,
            iterations: p.numerics.solver_iterations,
            deepest: 0.0,
        }
    }

    /// Advance one time step: rapier's step, then the contact's rolling resistance and torsional
    /// friction (module docs). With [`Flight::Free`] (the default numerics), a step that could
    /// bring a hull corner into the (possibly moving) ground by more
    /// than [`impact::IMPACT_APPROACH`] is cut into the sub-steps of [`impact::substeps`], as a
    /// drop's impacts are: pushes, shaking and the rocking checks resolve their impacts the same
    /// way.
    pub fn step(&mut self) {
        let stone = [(self.body_handle, self.body_collider)];
        let n = if self.resolve_impacts {
            let g = &self.world.bodies[self.ground_handle];
            let (ground_v, ground_z) = (convert::vec_back(g.linvel()), g.translation().z as f64);
            let (q, _) = self.pose();
            let s = self.state();
            impact::substeps(self.body, &q, s.z - ground_z, &(s.linvel - ground_v), &s.angvel, self.dt)
        } else {
            1
        };
        if n == 1 {
            step_world(&mut self.world, &self.law, self.body, self.ground_collider, &stone);
            let depth = penetration(&self.world, self.body, self.body_handle, self.ground_collider);
            self.deepest = self.deepest.max(depth);
            return;
        }
        let depth = step_substeps(
            &mut self.world,
            n,
            (self.dt, self.strict_impacts),
            self.iterations,
            &self.law,
            self.body,
            self.ground_collider,
            stone[0],
        );
        self.deepest = self.deepest.max(depth);
        self.world.integration_parameters.dt = self.dt as f32;
        self.world.integration_parameters.num_solver_iterations = self.iterations;
    }

    /// The deepest any hull corner has been below the ground after any step or sub-step of the
    /// run so far, in R_max ([`penetration`]; 0 if it never touched).
    pub fn deepest_penetration(&self) -> f64 {
        self.deepest
    }

    /// Advance `steps` time steps with nothing but gravity and the contact (settling).
    pub fn advance(&mut self, steps: u64) {
        for _ in 0..steps {
            self.step();
        }
    }

    /// Step with nothing but gravity and the contact until `done` holds of the state after a
    /// step, or `steps_max` steps have been taken: the steps taken (0 if `steps_max` is 0; `done`
    /// is not asked of the state before the first step).
    pub fn step_until(&mut self, steps_max: u64, done: &mut dyn FnMut(&BodyState) -> bool) -> u64 {
        for k in 1..=steps_max {
            self.step();
            if done(&self.state()) {
                return k;
            }
        }
        steps_max
    }

    /// Horizontal position of G relative to the ground (scaled frame; the ground moves when it
    /// is shaken).
    pub fn ground_offset(&self) -> Vec3 {
        let b = self.world.bodies[self.body_handle].translation();
        let g = self.world.bodies[self.ground_handle].translation();
        Vec3::new((b.x - g.x) as f64, (b.y - g.y) as f64, 0.0)
    }

    /// Total normal impulse the ground gave the stone during the last step.
    pub fn normal_impulse(&self) -> f64 {
        normal_impulse(&self.world, self.ground_collider, self.body_collider)
    }

    /// Set the ground's velocity (world frame) for the next steps.
    pub fn set_ground_velocity(&mut self, v: &Vec3) {
        self.world.bodies[self.ground_handle].set_linvel(convert::vec(v), true);
    }

    /// Set the stone's velocities (world frame).
    pub fn set_velocity(&mut self, linvel: &Vec3, angvel: &Vec3) {
        let rb = &mut self.world.bodies[self.body_handle];
        rb.set_linvel(convert::vec(linvel), true);
        rb.set_angvel(convert::vec(angvel), true);
    }

    /// The stone's orientation (body → world) and the height of G.
    pub fn pose(&self) -> (UnitQuaternion<f64>, f64) {
        let rb = &self.world.bodies[self.body_handle];
        (convert::quat_back(rb.rotation()), rb.translation().z as f64)
    }

    /// Set the soft contacts' natural frequency (Hz) against moving and fixed bodies.
    pub fn set_contact_frequency(&mut self, hz: f64) {
        let ip = &mut self.world.integration_parameters;
        ip.contact_softness.natural_frequency = hz as f32;
        ip.static_contact_softness.natural_frequency = hz as f32;
    }

    /// The stone's current state.
    pub fn state(&self) -> BodyState {
        body_state(&self.world.bodies[self.body_handle], self.body)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Analysis, Options};
    use crate::dynamics::drops::params::Preset;
    use crate::dynamics::surface::Surface;

    #[test]
    fn stepping_until_stops_where_advancing_as_far_does() {
        let (mesh, rep) = crate::generate::cuboid(1.0, 0.8, 0.5).into_solid_boundary().unwrap();
        let a = Analysis::of_solid(mesh, rep, &Options::default()).unwrap();
        let stone = crate::dynamics::stone::Stone::new(&a, 0.01).unwrap();
        let p = Preset::Drop.params(Surface::SteelOnWood).sim;
        let q = UnitQuaternion::from_euler_angles(0.3, 0.2, 0.1);
        let new = || Simulation::new(&stone.body, &p, &q, 2.0, &Vec3::zeros(), &Vec3::zeros());
        // Falling from rest, G sinks monotonically: stop at the first state below z = 1.9 (in the air: the corners are within 1 R_max of G).
        let (mut sim, mut twin) = (new(), new());
        let k = sim.step_until(1000, &mut |s| s.z < 1.9);
        twin.advance(k - 1);
        assert!(twin.state().z >= 1.9);
        twin.advance(1);
        assert_eq!((sim.state().z, sim.state().linvel), (twin.state().z, twin.state().linvel));
        assert!(sim.state().z < 1.9 && k > 1);
        // A condition never met: every step taken.
        assert_eq!(new().step_until(7, &mut |_| false), 7);
    }
}
