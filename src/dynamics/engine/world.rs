//! The rapier world of one run: a flat ground (a half-space on a kinematic body, so that it can
//! be shaken) and the stone, in the scaled frame of [`crate::dynamics::drops::params`], with the contact law of
//! this project — Coulomb friction and restitution from rapier, impacts completed (Coulomb's
//! compression, Newton's restitution) and rolling resistance and torsional friction added here.
//!
//! The contact law that acts at every step is [`crate::dynamics::engine::contact`]; impacts that
//! one step cannot resolve are sub-stepped by [`crate::dynamics::engine::impact`].

use crate::dynamics::engine::body::Body;
use crate::dynamics::engine::contact::{step_world, ContactLaw};
use crate::dynamics::engine::convert;
use crate::dynamics::engine::impact::{self, step_substeps};
use crate::dynamics::engine::params::Flight;
use crate::dynamics::engine::params::RunParams;
use crate::{Vec3, GRAVITY};
use nalgebra::UnitQuaternion;
use rapier3d::prelude::*;

/// Penetration the contact solver allows, in units of R_max.
pub const ALLOWED_PENETRATION: f64 = 1e-3;

/// The state of the stone that the rest criterion and the certificate read (scaled frame).
#[derive(Clone, Copy, Debug)]
pub struct BodyState {
    /// Down direction in the body frame.
    pub down: Vec3,
    /// Height of G above the ground.
    pub z: f64,
    /// Linear velocity (world frame).
    pub linvel: Vec3,
    /// Angular velocity (world frame).
    pub angvel: Vec3,
    /// Energy level L = E/(m g) = z_G + kinetic energy/(m g): a bound on h(down) for the rest of
    /// a passive motion.
    pub level: f64,
}

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

/// Collision groups: the ground (group 1) meets everything; a stone (group 2) meets only the
/// ground, so that the stones of a [`crate::dynamics::drops::batch`] world never touch each other (one body in a
/// world behaves the same with or without them).
pub fn ground_groups() -> InteractionGroups {
    InteractionGroups::new(Group::GROUP_1, Group::ALL, InteractionTestMode::And)
}

/// See [`ground_groups`].
pub fn stone_groups() -> InteractionGroups {
    InteractionGroups::new(Group::GROUP_2, Group::GROUP_1, InteractionTestMode::And)
}

/// An empty rapier world in the scaled frame with the numerics of `p` (gravity, dt, solver
/// iterations) and a flat kinematic ground (the half-space z ≤ 0): the world, the ground's body
/// and its collider.
pub fn ground_world(p: &RunParams) -> (PhysicsWorld, RigidBodyHandle, ColliderHandle) {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, 0.0, -GRAVITY as f32);
    world.integration_parameters.dt = p.numerics.dt as f32;
    world.integration_parameters.length_unit = 1.0;
    world.integration_parameters.num_solver_iterations = p.numerics.solver_iterations;
    // Rapier's allowed linear error, in R_max (default 0.005). Note: in rapier 0.36.1 it is
    // read only by continuous collision detection; the penetration the certificate's margin
    // must cover is bounded by measurement instead (see `run::CERTIFICATE_MARGIN`).
    world.integration_parameters.normalized_allowed_linear_error = ALLOWED_PENETRATION as f32;
    let ground_handle = world.bodies.insert(RigidBodyBuilder::kinematic_velocity_based().build());
    let ground = ColliderBuilder::new(SharedShape::halfspace(Vector::Z))
        .friction(p.contact.friction as f32)
        .restitution(p.contact.restitution as f32)
        .collision_groups(ground_groups())
        .build();
    let ground_collider = world.colliders.insert_with_parent(ground, ground_handle, &mut world.bodies);
    (world, ground_handle, ground_collider)
}

/// Insert a stone into `world` with orientation `orientation` (body → world), G at height `z`
/// above the ground and the given velocities (world frame): its body and collider.
pub fn insert_stone(
    world: &mut PhysicsWorld,
    body: &Body,
    p: &RunParams,
    orientation: &UnitQuaternion<f64>,
    z: f64,
    linvel: &Vec3,
    angvel: &Vec3,
) -> (RigidBodyHandle, ColliderHandle) {
    let mass = MassProperties::with_inertia_matrix(Vector::ZERO, 1.0, convert::mat(&body.inertia));
    let rb = RigidBodyBuilder::dynamic()
        .pose(Pose::from_parts(Vector::new(0.0, 0.0, z as f32), convert::quat(orientation)))
        .linvel(convert::vec(linvel))
        .angvel(convert::vec(angvel))
        .linear_damping(p.contact.linear_damping as f32)
        .angular_damping(p.contact.angular_damping as f32)
        .additional_mass_properties(mass)
        .gyroscopic_forces_enabled(true)
        .can_sleep(false)
        .build();
    let body_handle = world.bodies.insert(rb);
    let collider = ColliderBuilder::new(body.shape.clone())
        .density(0.0)
        .friction(p.contact.friction as f32)
        .restitution(p.contact.restitution as f32)
        .collision_groups(stone_groups())
        .build();
    let body_collider = world.colliders.insert_with_parent(collider, body_handle, &mut world.bodies);
    (body_handle, body_collider)
}

/// How deep the deepest hull corner of the stone `handle` (a `body`) lies below the ground's
/// plane (the collider `ground`, which may have been moved by a drive), in R_max: h(d) − (z_G −
/// z_ground) with d the body-frame down direction and h the support function of the hull
/// ([`Body::support_climb`], exact to the collider's f32 rounding); 0 when every corner is above
/// the ground. Measured after every step and sub-step of every run: the depth at which an impact
/// or a resting contact is resolved (a figure of the run's numerics, not of the stone).
pub fn penetration(world: &PhysicsWorld, body: &Body, handle: RigidBodyHandle, ground: ColliderHandle) -> f64 {
    let rb = &world.bodies[handle];
    let q = convert::quat_back(rb.rotation());
    let down = q.inverse() * -Vec3::z();
    let ground_z = world.colliders[ground].translation().z as f64;
    (body.support_climb(&down) - (rb.translation().z as f64 - ground_z)).max(0.0)
}

/// Total normal impulse between two colliders during the last step.
pub fn normal_impulse(world: &PhysicsWorld, ground: ColliderHandle, stone: ColliderHandle) -> f64 {
    world.narrow_phase.contact_pair(ground, stone).map_or(0.0, |c| c.total_impulse_magnitude() as f64)
}

/// The state of a stone's rigid body `rb` (scaled frame).
pub fn body_state(rb: &RigidBody, body: &Body) -> BodyState {
    let q = convert::quat_back(rb.rotation());
    let down = q.inverse() * -Vec3::z();
    let linvel = convert::vec_back(rb.linvel());
    let angvel = convert::vec_back(rb.angvel());
    let w_body = q.inverse() * angvel;
    let kinetic = 0.5 * linvel.norm_squared() + 0.5 * w_body.dot(&(body.inertia * w_body));
    let z = rb.translation().z as f64;
    BodyState { down, z, linvel, angvel, level: z + kinetic / GRAVITY }
}
