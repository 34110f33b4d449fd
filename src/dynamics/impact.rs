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
//! [`IMPACT_APPROACH`] is taken out of it into an [`super::world::ImpactWorld`] and stepped there in
//! n = ⌈A(dt) / IMPACT_APPROACH⌉ sub-steps of dt/n (n read off the state before every step),
//! until one step would do; then it goes back. Outside rapier, in free flight, the landing
//! itself is found exactly ([`super::flight::FreeBody::fly`]).
//!
//! Runs that start at rest — pushes, shaking, field rocks, the rocking checks — are one stone in
//! its own world ([`super::world::Simulation`]): there the step is cut in place, with A read
//! from the stone's motion relative to the ground (which moves when it is shaken,
//! [`substeps`] of the relative velocity). Their flight stays in rapier (a push or a shake rarely throws a stone
//! clear of the ground); the sub-steps bound where its landing starts just the same.
//!
//! Why a world of its own: the stones of a batch share one rapier world and its time step, and a
//! stone's history must not depend on the others ([`super::batch`]). A stone in an impact world
//! is stepped by its own state only, so outcomes stay the same for any batch size and thread
//! count. Moving a body between worlds drops rapier's warm-start impulses of its contacts
//! (the solver starts that step from zero impulses), the same way whatever shares the world.

use crate::{Vec3, GRAVITY};

/// Largest distance (R_max) any hull point may come down within one (sub-)step of a stone in
/// contact or about to be: half rapier's contact prediction distance (0.02 R_max).
pub const IMPACT_APPROACH: f64 = 0.01;

/// Most sub-steps of one step (a stone at 60 m/s of the scaled body and 1/120 s would need 50).
pub const MAX_SUBSTEPS: u32 = 64;

/// A(τ) of the module docs: how far any hull point of a stone moving at `linvel` and turning at
/// `angvel` (world frame, relative to the ground) can come down in a step of length `tau` (R_max).
pub fn approach(linvel: &Vec3, angvel: &Vec3, tau: f64) -> f64 {
    let omega_perp = (angvel.x * angvel.x + angvel.y * angvel.y).sqrt();
    ((-linvel.z).max(0.0) + omega_perp) * tau + 0.5 * GRAVITY * tau * tau
}

/// Sub-steps a stone moving at `linvel` and turning at `angvel` (world frame, relative to the
/// ground) needs for a step of length `dt` (1: none).
pub fn substeps(linvel: &Vec3, angvel: &Vec3, dt: f64) -> u32 {
    let n = (approach(linvel, angvel, dt) / IMPACT_APPROACH).ceil();
    if n.is_finite() {
        (n as u32).clamp(1, MAX_SUBSTEPS)
    } else {
        MAX_SUBSTEPS
    }
}
