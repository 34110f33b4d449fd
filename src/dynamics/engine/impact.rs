//! Impacts resolved, not discovered: a stone whose hull could move into the ground by
//! more than [`IMPACT_APPROACH`] within one time step is stepped in sub-steps short enough that
//! it cannot, in a world of its own.
//!
//! # The bound
//!
//! With G at height z_G moving at v and the body turning at ω (world frame, relative to the
//! ground), a hull point x (r = x − G, |r| ≤ 1 R_max) moves down at
//! u(x) = −v_z − (ω × r)_z ≤ −v_z + |ω_⊥| |r|, ω_⊥ the horizontal part of ω. Over a step of
//! length τ, gravity adds ½ g τ² at most (the contact only pushes up, friction is horizontal),
//! and r turns by at most |ω| |r| τ, which changes (ω × r)_z by at most |ω_⊥| |ω| |r| τ. With
//! the velocities of the step's start (what rapier's step sees, module "Why" below), no point of
//! the hull comes down by more than
//!
//! ```text
//! A(τ)    = (max(0, −v_z) + |ω_⊥|) τ + ½ g τ²                                   (any point)
//! D(x, τ) = min( max(0, u(x)) τ + ½ (g + |ω_⊥| |ω| |r|) τ²,
//!                (max(0, −v_z) + |ω_⊥| |r|) τ + ½ g τ² )  ≤  A(τ)              (corner x)
//! ```
//!
//! A corner x of clearance c(x) = z_G + r_z (its height above the ground) ends the step no
//! deeper than [`IMPACT_APPROACH`] if D(x, τ) ≤ c(x) + IMPACT_APPROACH. So a step needs
//! sub-steps iff some corner x has
//!
//! ```text
//! D(x, dt) > c(x) + IMPACT_APPROACH
//! ```
//!
//! ([`substeps`]). Only corners with c(x) < A(dt) − IMPACT_APPROACH can; they form a cap of the
//! hull that is connected in its vertex graph and holds the lowest corner (on a convex polytope
//! every corner but the lowest has a strictly lower neighbour), so they are found by a walk
//! from the lowest corner (hill climbing) over that cap, and none at all when
//! A(dt) ≤ c_min + IMPACT_APPROACH (c_min the lowest corner's clearance: one climb, most steps).
//! A cap of more than [`MAX_CAP`] corners counts as needing sub-steps (the bound on the walk's
//! cost). When a step needs them it is cut into n = ⌈A(dt) / IMPACT_APPROACH⌉ sub-steps of dt/n
//! (at least 2; n read off the state before every step) — in each, no point comes down by more
//! than IMPACT_APPROACH — in a world of its own ([`crate::dynamics::engine::impact::ImpactWorld`]), until one step
//! would do; then it goes back. Outside rapier, in free flight, the landing itself is found
//! exactly ([`crate::dynamics::engine::flight::FreeBody::fly`]).
//!
//! Why per corner: a stone rocking or rolling on the ground has A(dt) > IMPACT_APPROACH at
//! |ω_⊥| > 2.4 rad/s (dt = 1/240 s), but the corners that move fast are far from the ground and
//! those near it move slowly (the contact point's velocity is about zero). The former rule,
//! A(dt) ≤ IMPACT_APPROACH for every point, sent each such step of a batch to a world of its own,
//! one stone at a time; the per-corner rule keeps them in the shared world (measured in
//! `results/drops_certificate`: flock-certified batched drops with free flight ~2× faster).
//!
//! Why the corners that are already contacts are not exempt. Rapier's contacts for this
//! project's hull on the half-space ground ([`crate::dynamics::engine::hull_shape`], "Contact path in rapier") are
//! not all the corners within its prediction distance: parry's `contact_manifold_halfspace_pfm`
//! (parry3d 0.31, `query/contact_manifolds/contact_manifolds_halfspace_pfm.rs`) takes the support
//! feature towards the ground — [`crate::dynamics::engine::hull_shape::HullShape`]'s `local_support_feature`, the
//! facet at the lowest corner whose normal is closest to down, reduced to at most four corners —
//! and keeps those of its corners within the prediction distance
//! ([`crate::dynamics::engine::flight::LANDING_CLEARANCE`], 0.02 R_max), once, at the step's start (rapier 0.36
//! runs its collision detection before the solver). On a scan the neighbours of that facet lie
//! within the prediction distance too and are no contacts. And a contact corner coming down fast
//! is not held out of the ground by the solver's speculative contact within one step (a soft
//! constraint): measured on the cube drops and knocks of `tests/flight.rs`, exempting the
//! manifold's corners from the rule let the deepest compression reach 7.5·10⁻³ R_max (a 1/120 s
//! step), against 2.6·10⁻³ with every corner under the rule and 5.7·10⁻⁴ under the former A rule,
//! and it was not faster. The bound reads the velocities at the step's start; an impulse within
//! the step (at a contact) can turn the stone faster and bring a far corner down faster than D
//! says, as it could under A (whose |ω_⊥| · 1 R_max left more slack for it) — so the bound is
//! checked by measurement, not assumed (`tests/flight.rs`,
//! `no_impact_starts_deeper_than_the_stated_bound`, `knocked_stones_resolve_their_impacts_as_drops_do`).
//!
//! Runs that start at rest — pushes, shaking, field rocks, the rocking checks — are one stone in
//! its own world ([`crate::dynamics::engine::simulation::Simulation`]): there the step is cut in place, by the same
//! [`substeps`] of the stone's motion relative to the ground (which moves when it is shaken).
//! Their flight stays in rapier (a push or a shake rarely throws a stone clear of the ground);
//! the sub-steps bound where its landing starts just the same.
//!
//! Why a world of its own: the stones of a batch share one rapier world and its time step, and a
//! stone's history must not depend on the others ([`crate::dynamics::drops::batch`]). A stone in an impact world
//! is stepped by its own state only, so outcomes stay the same for any batch size and thread
//! count. Moving a body between worlds drops rapier's warm-start impulses of its contacts
//! (the solver starts that step from zero impulses), the same way whatever shares the world.

use crate::dynamics::engine::body::Body;
use crate::dynamics::engine::contact::{law_ground_velocity, step_world, ContactLaw};
use crate::dynamics::engine::convert;
use crate::dynamics::engine::hull_shape::HullShape;
use crate::dynamics::engine::params::RunParams;
use crate::dynamics::engine::world::{body_state, ground_world, insert_stone, normal_impulse, penetration, BodyState};
use crate::{Vec3, GRAVITY};
use nalgebra::UnitQuaternion;
use rapier3d::prelude::{ColliderHandle, PhysicsWorld, RigidBodyHandle};

/// Largest distance (R_max) any hull point may come down within one (sub-)step of a stone in
/// contact or about to be: half rapier's contact prediction distance (0.02 R_max).
pub const IMPACT_APPROACH: f64 = 0.01;

/// Most sub-steps of one step: enough for a stone approaching the ground at 400 R_max/s with a
/// 1/120 s step (n = 334) with room to spare; a launch that would need more is stepped with this
/// many, and what that does shows in the measured depth ([`DEPTH_BOUND`]).
pub const MAX_SUBSTEPS: u32 = 4096;

/// The deepest (R_max) a hull corner may go below the ground at any step or sub-step before a
/// run warns: rapier's contact prediction distance ([`crate::dynamics::engine::flight::LANDING_CLEARANCE`]), the
/// depth beyond which the solver no longer sees a corner's contact before it is inside the ground.
/// Not a proof: the depth is measured after every step and sub-step of every run
/// ([`crate::dynamics::engine::world::penetration`]), reported (`deepest_penetration`), and a run whose depth
/// exceeds this bound says so.
pub const DEPTH_BOUND: f64 = crate::dynamics::engine::flight::LANDING_CLEARANCE;

/// Most corners the walk over the cap of corners that could come down too far visits; a larger
/// cap counts as needing sub-steps (module docs).
pub const MAX_CAP: usize = 128;

/// A(τ) of the module docs: how far any hull point of a stone moving at `linvel` and turning at
/// `angvel` (world frame, relative to the ground) can come down in a step of length `tau` (R_max).
pub fn approach(linvel: &Vec3, angvel: &Vec3, tau: f64) -> f64 {
    let omega_perp = (angvel.x * angvel.x + angvel.y * angvel.y).sqrt();
    ((-linvel.z).max(0.0) + omega_perp) * tau + 0.5 * GRAVITY * tau * tau
}

/// Sub-steps a stone `body` with orientation `q` (body → world), G at height `z` above the
/// ground, moving at `linvel` and turning at `angvel` (world frame, relative to the ground)
/// needs for a step of length `dt` (1: none): more than one iff some hull corner could come down
/// by more than its clearance plus [`IMPACT_APPROACH`] (module docs). Reads nothing but the
/// stone's own state.
pub fn substeps(body: &Body, q: &UnitQuaternion<f64>, z: f64, linvel: &Vec3, angvel: &Vec3, dt: f64) -> u32 {
    let a = approach(linvel, angvel, dt);
    if !(a.is_finite() && z.is_finite()) {
        return MAX_SUBSTEPS;
    }
    let safe = match body.shape.as_shape::<HullShape>() {
        Some(hull) => corners_stay_clear(body, hull, q, z, linvel, angvel, dt, a),
        // Any other collider: the bound for every point, as if every corner touched.
        None => a <= IMPACT_APPROACH,
    };
    if safe {
        return 1;
    }
    ((a / IMPACT_APPROACH).ceil() as u32).clamp(2, MAX_SUBSTEPS)
}

/// Whether no corner of `hull` can come down by more than its clearance plus
/// [`IMPACT_APPROACH`] in a step of length `tau` (D(x, τ) of the module docs; `a` is A(τ)).
#[allow(clippy::too_many_arguments)]
fn corners_stay_clear(
    body: &Body,
    hull: &HullShape,
    q: &UnitQuaternion<f64>,
    z: f64,
    linvel: &Vec3,
    angvel: &Vec3,
    tau: f64,
    a: f64,
) -> bool {
    let down = q.inverse() * -Vec3::z();
    let clearance = |v: u32| z - body.corners[v as usize].dot(&down);
    let lowest = hull.support_vertex(convert::vec(&down));
    if a <= clearance(lowest) + IMPACT_APPROACH {
        return true;
    }
    // Only corners below this can come down too far; they form a connected cap around `lowest`.
    let reach = a - IMPACT_APPROACH;
    // (ω × r)_z = r_b · (ω_b × down), r_b and ω_b in the body frame.
    let lever = (q.inverse() * angvel).cross(&down);
    let omega_perp = (angvel.x * angvel.x + angvel.y * angvel.y).sqrt();
    let omega = angvel.norm();
    let fall = (-linvel.z).max(0.0);
    let descent = |r: &Vec3| {
        let rn = r.norm();
        let u = -linvel.z - r.dot(&lever);
        let taylor = u.max(0.0) * tau + 0.5 * (GRAVITY + omega_perp * omega * rn) * tau * tau;
        let speed = (fall + omega_perp * rn) * tau + 0.5 * GRAVITY * tau * tau;
        taylor.min(speed)
    };
    let mut seen = [0u32; MAX_CAP];
    let mut len = 1;
    seen[0] = lowest;
    let mut next = 0;
    // `seen[..len]`: corners met; `seen[next..len]` that lie in the cap are still to visit.
    while next < len {
        let v = seen[next];
        next += 1;
        let c = clearance(v);
        if c >= reach {
            continue;
        }
        if descent(&body.corners[v as usize]) > c + IMPACT_APPROACH {
            return false;
        }
        for w in hull.corner_neighbours(v) {
            if !seen[..len].contains(&w) {
                if len == MAX_CAP {
                    return false;
                }
                seen[len] = w;
                len += 1;
            }
        }
    }
    true
}

/// One step of length `dt` of one stone, cut for an impact into `n` sub-steps of `dt / n` with
/// ⌈`iterations` / n⌉ solver sub-steps each ([`crate::dynamics::engine::impact`] says why not all the solver
/// sub-steps in each), each a [`step_world`]. `(dt, strict)`: with `strict`
/// ([`crate::dynamics::engine::params::FlightParams::strict_impacts`]), after every sub-step the bound of [`substeps`] is
/// read again off the stone's new motion (an impulse within the sub-step may have turned it
/// faster than the motion at its start allowed for): where one more sub-step of the current
/// length could bring a corner down by more than [`IMPACT_APPROACH`], the rest of the
/// step is cut finer (at most [`MAX_SUBSTEPS`] sub-steps in all). Leaves the world's step
/// and iterations at the last sub-step's. Returns the deepest [`penetration`] after any of the
/// sub-steps (R_max, ≥ 0).
#[allow(clippy::too_many_arguments)]
pub fn step_substeps(
    world: &mut PhysicsWorld,
    n: u32,
    (dt, strict): (f64, bool),
    iterations: usize,
    law: &ContactLaw,
    body: &Body,
    ground: ColliderHandle,
    stone: (RigidBodyHandle, ColliderHandle),
) -> f64 {
    let (mut left, mut taken, mut tau) = (n, 0u32, dt / n as f64);
    let set = |world: &mut PhysicsWorld, tau: f64, count: u32| {
        world.integration_parameters.dt = tau as f32;
        world.integration_parameters.num_solver_iterations = iterations.div_ceil(count as usize);
    };
    set(world, tau, n);
    let mut deepest: f64 = 0.0;
    while left > 0 {
        step_world(world, law, body, ground, &[stone]);
        (left, taken) = (left - 1, taken + 1);
        deepest = deepest.max(penetration(world, body, stone.0, ground));
        if strict && left > 0 && taken + left < MAX_SUBSTEPS {
            let finer = substeps_now(world, body, stone.0, ground, tau).min(MAX_SUBSTEPS / (taken + left));
            if finer > 1 {
                (left, tau) = (left * finer, tau / finer as f64);
                set(world, tau, taken + left);
            }
        }
    }
    deepest
}

/// [`substeps`] for a step of length `tau` from the current motion of the stone `handle`
/// (relative to the ground collider `ground`, which may move).
fn substeps_now(world: &PhysicsWorld, body: &Body, handle: RigidBodyHandle, ground: ColliderHandle, tau: f64) -> u32 {
    let rb = &world.bodies[handle];
    let q = convert::quat_back(rb.rotation());
    let ground_z = world.colliders[ground].translation().z as f64;
    let ground_v = law_ground_velocity(world, ground);
    let v = convert::vec_back(rb.linvel()) - ground_v;
    substeps(body, &q, rb.translation().z as f64 - ground_z, &v, &convert::vec_back(rb.angvel()), tau)
}

/// A world with the ground and one stone, stepped in sub-steps ([`crate::dynamics::engine::impact`]): where a
/// stone of a batch goes for its impacts.
pub struct ImpactWorld {
    world: PhysicsWorld,
    handle: RigidBodyHandle,
    collider: ColliderHandle,
    ground: ColliderHandle,
    dt: f64,
    /// The run's solver iterations (rapier's sub-steps of one step).
    iterations: usize,
    /// [`crate::dynamics::engine::params::FlightParams::strict_impacts`].
    strict: bool,
}

impl ImpactWorld {
    /// The stone with orientation `q`, G at height `z` and velocities `linvel`, `angvel` (world
    /// frame), alone above the ground with the contact and numerics of `p`.
    pub fn new(body: &Body, p: &RunParams, q: &UnitQuaternion<f64>, s: &BodyState) -> Self {
        let (mut world, _, ground) = ground_world(p);
        let (handle, collider) = insert_stone(&mut world, body, p, q, s.z, &s.linvel, &s.angvel);
        ImpactWorld {
            world,
            handle,
            collider,
            ground,
            dt: p.numerics.dt,
            iterations: p.numerics.solver_iterations,
            strict: p.flight.strict_impacts,
        }
    }

    /// Put the stone in state `s` with orientation `q` in this world instead of the one it held
    /// (the world, its ground and numerics are kept: building a rapier world is costly).
    pub fn reset(&mut self, body: &Body, p: &RunParams, q: &UnitQuaternion<f64>, s: &BodyState) {
        self.world.remove_body(self.handle);
        (self.handle, self.collider) = insert_stone(&mut self.world, body, p, q, s.z, &s.linvel, &s.angvel);
    }

    /// Advance one step of the run in `n` sub-steps of dt/n, each with the contact law and
    /// ⌈iterations / n⌉ of rapier's solver sub-steps (so a step still has at least the solver
    /// sub-steps of the shared world). Why not all of them in every sub-step: rapier's
    /// restitution is applied once per step, point by point, after the solver's sub-steps, and
    /// it loses accuracy when the impact falls early in a short step — a flat cube landing at
    /// 6.25 m/s with e = 0.3 leaves at 1.77 m/s with 4 solver sub-steps at dt = 1/720 s (plain
    /// rapier, before the contact law completed its restitution, [`ContactLaw`]; e·v = 1.88) and
    /// at 1.86 m/s with one.
    /// Returns the deepest [`penetration`] after any of the sub-steps (R_max).
    pub fn step(&mut self, n: u32, law: &ContactLaw, body: &Body) -> f64 {
        let stone = (self.handle, self.collider);
        step_substeps(&mut self.world, n, (self.dt, self.strict), self.iterations, law, body, self.ground, stone)
    }

    /// The stone's state and orientation.
    pub fn state(&self, body: &Body) -> (BodyState, UnitQuaternion<f64>) {
        let rb = &self.world.bodies[self.handle];
        (body_state(rb, body), convert::quat_back(rb.rotation()))
    }

    /// Total normal impulse of the ground in the last sub-step.
    pub fn normal_impulse(&self) -> f64 {
        normal_impulse(&self.world, self.ground, self.collider)
    }
}
