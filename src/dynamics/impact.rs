//! Impacts resolved, not discovered (issue 25): a stone whose hull could move into the ground by
//! more than [`IMPACT_APPROACH`] within one time step is stepped in sub-steps short enough that
//! it cannot, in a world of its own.
//!
//! # The bound
//!
//! With G at height z_G moving at v and the body turning at ω (world frame), a hull point x
//! (|x − G| ≤ 1 R_max) moves down at −ẋ_z = −v_z − (ω × (x − G))_z ≤ −v_z + |ω_⊥|, ω_⊥ the
//! horizontal part of ω; over a step of length τ, gravity adds ½ g τ² at most (the contact only
//! pushes up). So no point of the hull comes down by more than
//!
//! ```text
//! A(τ) = (max(0, −v_z) + |ω_⊥|) τ + ½ g τ²        (R_max)
//! ```
//!
//! A point that is not yet a contact of rapier's manifold (rapier makes contacts at the step's
//! start only, for the support feature's corners within its prediction distance) can therefore
//! end the step at most A(τ) deep. A stone in the shared world whose A(dt) exceeds
//! [`IMPACT_APPROACH`] is taken out of it into an [`ImpactWorld`] and stepped there in
//! n = ⌈A(dt) / IMPACT_APPROACH⌉ sub-steps of dt/n (n read off the state before every step),
//! until one step would do; then it goes back. Outside rapier, in free flight, the landing
//! itself is found exactly ([`super::flight::FreeBody::fly`]).
//!
//! Why a world of its own: the stones of a batch share one rapier world and its time step, and a
//! stone's history must not depend on the others ([`super::batch`]). A stone in an impact world
//! is stepped by its own state only, so outcomes stay the same for any batch size and thread
//! count. Moving a body between worlds drops rapier's warm-start impulses of its contacts
//! (the solver starts that step from zero impulses), the same way whatever shares the world.

use super::params::DropParams;
use super::stone::Body;
use super::world::{body_state, ground_world, insert_stone, normal_impulse, step_world, BodyState, ContactLaw};
use crate::GRAVITY;
use nalgebra::UnitQuaternion;
use rapier3d::prelude::{ColliderHandle, PhysicsWorld, RigidBodyHandle};

/// Largest distance (R_max) any hull point may come down within one (sub-)step of a stone in
/// contact or about to be: half rapier's contact prediction distance (0.02 R_max).
pub const IMPACT_APPROACH: f64 = 0.01;

/// Most sub-steps of one step (a stone at 60 m/s of the scaled body and 1/120 s would need 50).
pub const MAX_SUBSTEPS: u32 = 64;

/// A(τ) of the module docs: how far any hull point of a stone in state `s` can come down in a
/// step of length `tau` (R_max).
pub fn approach(s: &BodyState, tau: f64) -> f64 {
    let omega_perp = (s.angvel.x * s.angvel.x + s.angvel.y * s.angvel.y).sqrt();
    ((-s.linvel.z).max(0.0) + omega_perp) * tau + 0.5 * GRAVITY * tau * tau
}

/// Sub-steps a stone in state `s` needs for a step of length `dt` (1: none).
pub fn substeps(s: &BodyState, dt: f64) -> u32 {
    let n = (approach(s, dt) / IMPACT_APPROACH).ceil();
    if n.is_finite() {
        (n as u32).clamp(1, MAX_SUBSTEPS)
    } else {
        MAX_SUBSTEPS
    }
}

/// A world with the ground and one stone, stepped in sub-steps (module docs).
pub struct ImpactWorld {
    world: PhysicsWorld,
    handle: RigidBodyHandle,
    collider: ColliderHandle,
    ground: ColliderHandle,
    dt: f64,
    /// The run's solver iterations (rapier's sub-steps of one step).
    iterations: usize,
}

impl ImpactWorld {
    /// The stone with orientation `q`, G at height `z` and velocities `linvel`, `angvel` (world
    /// frame), alone above the ground with the contact and numerics of `p`.
    pub fn new(body: &Body, p: &DropParams, q: &UnitQuaternion<f64>, s: &BodyState) -> Self {
        let (mut world, _, ground) = ground_world(p);
        let (handle, collider) = insert_stone(&mut world, body, p, q, s.z, &s.linvel, &s.angvel);
        ImpactWorld { world, handle, collider, ground, dt: p.dt, iterations: p.solver_iterations }
    }

    /// Put the stone in state `s` with orientation `q` in this world instead of the one it held
    /// (the world, its ground and numerics are kept: building a rapier world is costly).
    pub fn reset(&mut self, body: &Body, p: &DropParams, q: &UnitQuaternion<f64>, s: &BodyState) {
        self.world.remove_body(self.handle);
        (self.handle, self.collider) = insert_stone(&mut self.world, body, p, q, s.z, &s.linvel, &s.angvel);
    }

    /// Advance one step of the run in `n` sub-steps of dt/n, each with the contact law and
    /// ⌈iterations / n⌉ of rapier's solver sub-steps (so a step still has at least the solver
    /// sub-steps of the shared world). Why not all of them in every sub-step: rapier's
    /// restitution is applied once per step, point by point, after the solver's sub-steps, and
    /// it loses accuracy when the impact falls early in a short step — a flat cube landing at
    /// 6.25 m/s with e = 0.3 leaves at 1.77 m/s with 4 solver sub-steps at dt = 1/720 s (plain
    /// rapier; e·v = 1.88) and at 1.86 m/s with one.
    pub fn step(&mut self, n: u32, law: &ContactLaw, body: &Body) {
        self.world.integration_parameters.dt = (self.dt / n as f64) as f32;
        self.world.integration_parameters.num_solver_iterations = self.iterations.div_ceil(n as usize);
        for _ in 0..n {
            step_world(&mut self.world, law, body, self.ground, &[(self.handle, self.collider)]);
        }
    }

    /// The stone's state and orientation.
    pub fn state(&self, body: &Body) -> (BodyState, UnitQuaternion<f64>) {
        let rb = &self.world.bodies[self.handle];
        (body_state(rb, body), super::convert::quat_back(rb.rotation()))
    }

    /// Total normal impulse of the ground in the last sub-step.
    pub fn normal_impulse(&self) -> f64 {
        normal_impulse(&self.world, self.ground, self.collider)
    }
}
