//! The building blocks of a rapier world in the scaled frame of [`crate::dynamics::engine::params`]:
//! a flat ground (a half-space on a kinematic body, so that it can be shaken), a stone inserted
//! into it, and what is read back (its [`BodyState`], how deep it is in the ground, the ground's
//! normal impulse). Rapier supplies Coulomb friction and restitution; the rest of the contact law
//! is [`crate::dynamics::engine::contact`]. One stone's world with its step is
//! [`crate::dynamics::engine::simulation`].

use crate::dynamics::engine::body::Body;
use crate::dynamics::engine::convert;
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
