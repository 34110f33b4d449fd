//! The rapier world of one run: a flat ground (a half-space on a kinematic body, so that it can
//! be shaken) and the stone, in the scaled frame of [`crate::dynamics::drops::params`], with the contact law of
//! this project — Coulomb friction and restitution from rapier, impacts completed (Coulomb's
//! compression, Newton's restitution) and rolling resistance and torsional friction added here.
//!
//! # Impacts: Coulomb's compression and Newton's restitution at every struck point (`ContactLaw::restitute`)
//!
//! Rapier 0.36 applies restitution once per step, after its solver sub-steps: one Gauss–Seidel
//! sweep over the points of a contact manifold, each driven to e times its approach speed at the
//! step's start (`apply_restitution`), normal impulses only. That falls short twice.
//!
//! - *A face.* One sweep is exact for a single point, not for a face that lands on several: each
//!   point's impulse also lifts the others, and the sweep does not come back to them. A box
//!   1 × 0.8 × 0.5 landing flat on its broad face from 0.01–1 R_max left at 0.72–0.88 e (e = 0.2
//!   and 0.5, dt 1/240 s; down to 0.25 e at some heights), at any of 1–16 solver sub-steps; a
//!   cube, by its symmetry, at 0.96–1.0 e.
//! - *A corner.* A corner struck within a step gets its friction from the solver's sub-steps,
//!   which at the default 4 do not converge on it: what the impact does to the spin depends on
//!   the number of sub-steps (`results/corner_impact/`: between the two closed forms below, a
//!   box's corner sat at 0.72 (e = 0.2) and 0.89 (e = 0.5) of the way at 4 sub-steps, 0.3 and
//!   0.7 at 32), and with it the bundled stone's rare flocks (184 / 76 drops of 6000 in flocks
//!   2 / 3 at 4 sub-steps, 148 / 54 at 32, e = 0.2, `results/drops_vs_mujoco/`).
//!
//! So after rapier's step the law completes the impact of the points that carried load during
//! the step and approached the ground at its start faster than [`STRUCK_SPEED`] (u_i), solved
//! together, in two stages as the impact itself: a *compression* that brings them to rest with
//! Coulomb friction — each sticks unless its whole friction impulse over the step (rapier's share
//! and the law's) reaches μ times its whole normal impulse — and a *restitution* of normal
//! impulses that sends each off at e u_i (Newton's law, with complementarity). For one sticking
//! corner this is, in closed form, P = K⁻¹ u n + (e u / K_nn) n (K = 𝟙/m − \[r\]× I⁻¹ \[r\]×),
//! reached within 1 % at 4 and at 32 sub-steps (`tests/flight.rs`; the whole range 1–32 in
//! `results/corner_impact/`); a flat landing leaves at e times its impact speed whatever the
//! face (`tests/flight.rs`). A point counts as struck by its approach speed at the step's start,
//! as in Box2D; rapier's own rule (`is_bouncy`) is a point that carried no impulse in the step
//! before, so a corner still loaded from the step before gets no bounce from rapier and gets
//! Newton's law here. The completion never makes a point's normal impulse over the step
//! negative, and adds no energy of its own: a pass that would leave the stone with more
//! mechanical energy than the larger of the step's start and rapier's own step is scaled back
//! (`ContactLaw::restitute`). What rapier's step itself adds is not taken back: that is the
//! solver's error, measured, not bounded ([`crate::dynamics::engine::run::CERTIFICATE_MARGIN`]).
//!
//! *Why a restitution without friction.* The other law a rigid body allows, Newton's law with
//! Coulomb friction throughout (the corner leaves at e u n, sticking), was tried first: it too
//! is independent of the sub-steps, but the seven calibration dice end far from their data under
//! it (best rms 0.073 over the calibration grid; the flat die at most 0.79 on its square faces,
//! measured 0.916), and without an energy cap at e = 0.85 the dice never come to rest. With the
//! two stages the calibration fits better than with rapier's own blend (rms 0.039, χ² 28.5,
//! against 0.051 and 46.8: `results/cuboid_dice/`). Real impacts of hard bodies give back part of
//! the tangential compliance energy that a rigid Coulomb contact takes; a restitution without
//! friction is the simplest law that does, and the dice choose it.
//!
//! *What it approximates.* Rapier's friction model puts a manifold's friction at its centroid,
//! not at the points, so a point's own share of rapier's friction is not known: the law takes the
//! stone's horizontal change of momentum over rapier's step (all of it friction, the damping
//! aside) and shares it among the loaded points by their normal impulses — exact for a single
//! point.
//!
//! # Rolling resistance and torsional friction ([`Simulation::step`])
//!
//! Rapier has no rolling resistance: a smooth pebble rocks on its micro-facets for ever, and a
//! global velocity damping (what this project used before) also slows a body in flight. Here a
//! torque acts only through the contact. After every rapier step, with N Δt the total normal
//! impulse the ground gave the stone during the step (from the contact manifolds), n = +z the
//! ground's normal and ω the stone's angular velocity relative to the ground (which does not
//! rotate), split ω = ω_r + ω_s n into rolling (ω_r ⊥ n) and spinning parts. The contact applies
//! the torque impulses
//!
//! ```text
//! J_r = −min(δ_r N Δt, |ω_r| / (ω̂_rᵀ I⁻¹ ω̂_r)) ω̂_r        (rolling resistance, δ_r a length)
//! J_s = −min(δ_t N Δt, |ω_s'| / (nᵀ I⁻¹ n)) sign(ω_s') n     (torsional friction, δ_t a length)
//! ```
//!
//! (ω_s' the spin after J_r), i.e. a couple of magnitude δ N opposing the relative rotation while
//! it rotates (kinetic), and no more than what stops the rotation's component along its own
//! direction within the step (static: it never reverses it).
//!
//! *About the contact, not about G.* The couple acts on a body whose contact point sticks (the
//! ground's friction supplies the reaction), so the body turns about the contact patch: with c
//! the patch's centre (the solver contacts weighted by their normal impulses) and r = G − c,
//! I is the inertia about c, I_c = I_G + m(|r|²𝟙 − r rᵀ), and G follows: Δω = I_c⁻¹ J,
//! Δv_G = Δω × r, which leaves the contact point's velocity unchanged. Applied to the free body
//! instead (Δω = I_G⁻¹ J, Δv = 0, what this law did before) the couple set the contact point
//! slipping by |Δω| |r| after every step, which rapier's friction turned back into rotation the
//! next step: a resting stone rocked in a limit cycle above the rest rule's speeds (measured at
//! dt = 1/120 s on scanned stones, `results/drops_settling/`); a rolling ball's contact point
//! slipped at δ g Δt r/(I/m), now at < 10 % of that (`tests/contact.rs`).
//!
//! Each impulse changes the kinetic energy about the sticking point by
//! ΔT = −j|ω| + ½ j² ω̂ᵀI_c⁻¹ω̂ ≤ −½ j|ω| ≤ 0 for the clamped j. A slipping contact point adds
//! m v_c·(Δω × r), which can be positive: the law computes the change of T and, where the pivot
//! form would add energy, applies the free body's couple (ΔT ≤ 0 by the same bound with I_G). So
//! the couple only dissipates (tested in `tests/contact.rs`): it takes nothing from the energy
//! argument of the certificate in [`crate::dynamics::engine::run`]. A body in flight has N = 0 and feels nothing.
//!
//! # Friction about the normal, stated once
//!
//! Rapier's default friction model (`FrictionModel::Simplified`) solves, per contact manifold,
//! one tangential Coulomb constraint at the centroid c of the contact points and one *twist*
//! constraint about the normal with the Coulomb limit T_c = μ Σᵢ Nᵢ dᵢ (dᵢ = |pᵢ − c|) — on
//! manifolds of two or more points only. For points spread symmetrically about c this is exactly
//! the torque of Coulomb friction at the points of a spinning support (μ Nᵢ dᵢ each): a flat box
//! spinning on a face spins down at μ g r / k² (r the corners' distance from the axis, k the
//! radius of gyration about it), tested against that closed form in `tests/contact.rs`.
//!
//! The contact patch's own torsional friction δ_t N is the torque of a patch of radius ~δ_t/μ
//! that a point contact stands for. The two describe the same physical torque at two scales, so
//! the couple about the normal has the limit
//!
//! ```text
//! T = max(μ Σᵢ Nᵢ dᵢ, δ_t N)
//! ```
//!
//! never their sum: after rapier's step (which applied up to T_c Δt) the law adds the impulse
//! J_s above with δ_t N Δt replaced by (δ_t N Δt − T_c Δt)⁺, recomputing T_c Δt from the
//! manifold's per-point normal impulses and points. A single point (a ball, a corner) has
//! T_c = 0 and gets δ_t N; a broad face has T_c ≫ δ_t N and gets rapier's twist alone (the box
//! test fails if both act); a scan's micro-facet, whose contact points are a micro-facet apart,
//! has a tiny T_c and still gets the patch's δ_t N (`results/drops_settling`). Rapier's centroid
//! c counts speculative points (within the prediction distance, not yet loaded), so a stone
//! pivoting on one loaded corner with a second corner within 0.02 R_max of the ground has
//! T_c = μ N d with d half their distance — the max keeps δ_t N as the floor there too.

use crate::dynamics::engine::convert;
use crate::dynamics::engine::impact;
use crate::dynamics::engine::params::Flight;
use crate::dynamics::engine::params::RunParams;
use crate::dynamics::stone::Body;
use crate::{Vec3, GRAVITY};
use nalgebra::{Matrix3, UnitQuaternion};
use rapier3d::prelude::*;

mod resistance;

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
            law: ContactLaw::of(p),
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

/// One time step of a world whose stones (each a `body`, with its rigid body and collider) lie on
/// the ground collider `ground`: rapier's step, then the contact law on each stone. The one
/// place the contact law is applied, for one stone ([`Simulation::step`]) as for a batch
/// ([`crate::dynamics::drops::batch`]); a stone meets only the ground, so its law reads nothing of the others.
pub fn step_world(
    world: &mut PhysicsWorld,
    law: &ContactLaw,
    body: &Body,
    ground: ColliderHandle,
    stones: &[(RigidBodyHandle, ColliderHandle)],
) {
    // The stones' motion at the step's start: the approach speeds of Newton's law.
    // (Read only when the law has a restitution to complete.)
    let (before, ground_velocity): (Vec<Motion>, Vec3) = if law.restitution > 0.0 {
        let motions = stones.iter().map(|&(handle, _)| Motion::of(&world.bodies[handle])).collect();
        (motions, law_ground_velocity(world, ground))
    } else {
        (Vec::new(), Vec3::zeros())
    };
    world.step();
    for (k, &(handle, collider)) in stones.iter().enumerate() {
        if let Some(m) = before.get(k) {
            law.restitute(world, body, handle, collider, ground, m, &ground_velocity);
        }
        if law.resists() {
            law.apply(world, body, handle, collider, ground);
        }
    }
}

/// The ground's velocity (world frame): the body that carries the ground collider.
fn law_ground_velocity(world: &PhysicsWorld, ground: ColliderHandle) -> Vec3 {
    world.colliders[ground].parent().map_or(Vec3::zeros(), |h| convert::vec_back(world.bodies[h].linvel()))
}

/// A stone's pose and velocities at a step's start (world frame).
#[derive(Clone, Copy, Debug)]
struct Motion {
    rotation: UnitQuaternion<f64>,
    linvel: Vec3,
    angvel: Vec3,
    /// Height of G.
    z: f64,
}

impl Motion {
    fn of(rb: &RigidBody) -> Self {
        Motion {
            rotation: convert::quat_back(rb.rotation()),
            linvel: convert::vec_back(rb.linvel()),
            angvel: convert::vec_back(rb.angvel()),
            z: rb.translation().z as f64,
        }
    }
}

/// Most projected Gauss–Seidel sweeps of `ContactLaw::restitute` (4 points converge to 10⁻⁹
/// in a few tens).
const RESTITUTION_SWEEPS: usize = 200;

/// Approach speed (R_max/s, scaled) below which a contact point is resting, not struck, for the
/// restitution of `ContactLaw::restitute`: a bounce from it would rise e² u²/(2g) < 5·10⁻⁴ R_max.
/// A stone at rest starts every step with a normal speed ~10⁻³ at its points (the rest rule's
/// 2·10⁻³), far below it.
pub const STRUCK_SPEED: f64 = 0.1;

/// Most struck contact points one step resolves together (`ContactLaw::restitute`).
const MAX_STRUCK: usize = 16;

/// One step of length `dt` of one stone, cut for an impact into `n` sub-steps of `dt / n` with
/// ⌈`iterations` / n⌉ solver sub-steps each ([`crate::dynamics::engine::impact`] says why not all the solver
/// sub-steps in each), each a [`step_world`]. `(dt, strict)`: with `strict`
/// ([`crate::dynamics::engine::params::FlightParams::strict_impacts`]), after every sub-step the bound of [`impact::substeps`] is
/// read again off the stone's new motion (an impulse within the sub-step may have turned it
/// faster than the motion at its start allowed for): where one more sub-step of the current
/// length could bring a corner down by more than [`impact::IMPACT_APPROACH`], the rest of the
/// step is cut finer (at most [`impact::MAX_SUBSTEPS`] sub-steps in all). Leaves the world's step
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
        if strict && left > 0 && taken + left < impact::MAX_SUBSTEPS {
            let finer = substeps_now(world, body, stone.0, ground, tau).min(impact::MAX_SUBSTEPS / (taken + left));
            if finer > 1 {
                (left, tau) = (left * finer, tau / finer as f64);
                set(world, tau, taken + left);
            }
        }
    }
    deepest
}

/// [`impact::substeps`] for a step of length `tau` from the current motion of the stone `handle`
/// (relative to the ground collider `ground`, which may move).
fn substeps_now(world: &PhysicsWorld, body: &Body, handle: RigidBodyHandle, ground: ColliderHandle, tau: f64) -> u32 {
    let rb = &world.bodies[handle];
    let q = convert::quat_back(rb.rotation());
    let ground_z = world.colliders[ground].translation().z as f64;
    let ground_v = law_ground_velocity(world, ground);
    let v = convert::vec_back(rb.linvel()) - ground_v;
    impact::substeps(body, &q, rb.translation().z as f64 - ground_z, &v, &convert::vec_back(rb.angvel()), tau)
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

/// A point struck in a step (`ContactLaw::restitute`), with what the compression adds at it.
#[derive(Clone, Copy, Debug, Default)]
struct Struck {
    /// The point in the body frame (G at the origin).
    local: Vec3,
    /// Its lever r from G (world frame, at the step's end).
    lever: Vec3,
    /// The normal speed it must leave at: e u.
    target: f64,
    /// The normal impulse rapier gave it during the step, λ.
    impulse: f64,
    /// Its friction coefficient μ.
    friction: f64,
    /// Its share F of the friction impulse rapier gave the stone during the step (horizontal).
    rapier_friction: Vec3,
    /// K_ii⁻¹.
    block_inverse: Matrix3<f64>,
    /// The impulse the compression has added so far, ΔP (world frame).
    added: Vec3,
}

impl Struck {
    /// `p` (an added impulse ΔP) projected on the point's cone: Δλ ≥ −λ and
    /// |F + ΔP_t| ≤ μ (λ + Δλ) — the point's whole friction over the step within Coulomb's limit
    /// of its whole normal impulse.
    fn cone(&self, mut p: Vec3) -> Vec3 {
        p.z = p.z.max(-self.impulse);
        let limit = self.friction * (self.impulse + p.z);
        let (fx, fy) = (self.rapier_friction.x + p.x, self.rapier_friction.y + p.y);
        let total = fx.hypot(fy);
        if total > limit {
            let scale = limit / total;
            p.x = fx * scale - self.rapier_friction.x;
            p.y = fy * scale - self.rapier_friction.y;
        }
        p
    }
}

/// The contact's restitution, rolling resistance and torsional friction (module docs), lengths
/// in R_max.
#[derive(Clone, Copy, Debug)]
pub struct ContactLaw {
    /// Coefficient of restitution e (Newton's law at every struck point, after a compression with
    /// Coulomb friction: `Self::restitute`).
    pub restitution: f64,
    /// δ_r / R_max.
    pub rolling_resistance: f64,
    /// δ_t / R_max.
    pub torsional_friction: f64,
}

impl ContactLaw {
    /// The law of `p`.
    pub fn of(p: &RunParams) -> Self {
        ContactLaw {
            restitution: p.contact.restitution,
            rolling_resistance: p.contact.rolling_resistance,
            torsional_friction: p.contact.torsional_friction,
        }
    }

    /// Whether the contact resists rolling or spinning ([`Self::apply`]).
    pub fn resists(&self) -> bool {
        self.rolling_resistance > 0.0 || self.torsional_friction > 0.0
    }

    /// The impact at every struck point, solved together (module docs, "Impacts"): after
    /// rapier's step, the points of the stone's contact with the ground that carried load during
    /// the step and approached it at its start faster than [`STRUCK_SPEED`] (u_i, from the motion
    /// `before`) are brought to rest with Coulomb friction (*compression*), then leave at
    /// Newton's e u_i by normal impulses (*restitution*):
    ///
    /// ```text
    /// compression:  v_i = 0 unless a cone binds,  Δλ_i ≥ −λ_i,  |F_i + ΔP_i,t| ≤ μ (λ_i + Δλ_i)
    /// restitution:  v_i·n ≥ e u_i,  δλ_i ≥ −(λ_i + Δλ_i),  (v_i·n − e u_i)(λ_i + Δλ_i + δλ_i) = 0
    /// v_i = v_i⁰ + Σ_j K_ij P_j,    K_ij = 𝟙/m − [r_i]× I⁻¹ [r_j]×
    /// ```
    ///
    /// (ΔP_i = Δλ_i n + ΔP_i,t the compression's added impulse at point i, δλ_i n the
    /// restitution's, λ_i the normal impulse rapier gave it during the step and F_i its share of
    /// rapier's friction impulse, n the ground's normal, r_i its lever from G, all relative to the
    /// ground), each by projected Gauss–Seidel sweeps to convergence (3 × 3 blocks K_ii in the
    /// compression, K_ii's normal entry in the restitution). The completion adds no energy of its
    /// own: if the two stages together would leave the stone with more mechanical energy than the
    /// larger of its energy at the step's start and after rapier's step, their change of velocity
    /// is scaled back to that larger one (measured: 27 of 20 000 passes on thrown dice, by at most
    /// 1.4·10⁻³ R_max). Energy that rapier's step itself added (after it exceeds the start) is
    /// kept, not taken back.
    #[allow(clippy::too_many_arguments)]
    fn restitute(
        &self,
        world: &mut PhysicsWorld,
        body: &Body,
        handle: RigidBodyHandle,
        stone: ColliderHandle,
        ground: ColliderHandle,
        before: &Motion,
        ground_velocity: &Vec3,
    ) {
        // No point of the hull (|r| ≤ 1 R_max) approaches faster than this: nothing to strike.
        let rel = before.linvel - ground_velocity;
        let omega_perp = (before.angvel.x * before.angvel.x + before.angvel.y * before.angvel.y).sqrt();
        if -rel.z + omega_perp <= STRUCK_SPEED {
            return;
        }
        let Some(pair) = world.narrow_phase.contact_pair(ground, stone) else { return };
        let stone_is_first = pair.collider1 == stone;
        let n = Vec3::z();
        let mut struck = [Struck::default(); MAX_STRUCK];
        let mut len = 0;
        let mut loads = 0.0;
        for m in pair.manifolds() {
            for sc in &m.data.solver_contacts {
                let id = (sc.contact_id[0] & !NEW_CONTACT_BIT) as usize;
                let tracked = &m.points[id];
                let impulse = tracked.data.impulse as f64;
                loads += impulse.max(0.0);
                let local = convert::vec_back(if stone_is_first { tracked.local_p1 } else { tracked.local_p2 });
                let r = before.rotation * local;
                let u = -(before.linvel + before.angvel.cross(&r) - ground_velocity).dot(&n);
                if impulse > 0.0 && u > STRUCK_SPEED && len < MAX_STRUCK {
                    let friction = m.data.friction as f64;
                    struck[len] =
                        Struck { local, target: self.restitution * u, impulse, friction, ..Struck::default() };
                    len += 1;
                }
            }
        }
        if len == 0 {
            return;
        }
        let rb = &world.bodies[handle];
        let q = convert::quat_back(rb.rotation());
        let z = rb.translation().z as f64;
        let (v_rapier, w_rapier) = (convert::vec_back(rb.linvel()), convert::vec_back(rb.angvel()));
        let (mut v, mut w) = (v_rapier, w_rapier);
        let inertia = body.world_inertia(&q);
        let inv: Matrix3<f64> = inertia.try_inverse().unwrap_or_else(Matrix3::identity);
        // The friction impulse rapier gave the stone during the step: its horizontal change of
        // momentum (m = 1; gravity is vertical; the velocity damping, c dt ≤ 10⁻³ of the velocity,
        // is neglected), shared among the loaded points by their normal impulses.
        let friction = Vec3::new(v.x - before.linvel.x, v.y - before.linvel.y, 0.0);
        // Levers and the inverse blocks K_ii⁻¹ (m = 1 in the scaled frame), once: the sweeps only
        // change the velocities.
        for s in &mut struck[..len] {
            s.rapier_friction = friction * (s.impulse / loads);
            s.lever = q * s.local;
            let cross = s.lever.cross_matrix();
            s.block_inverse =
                (Matrix3::identity() - cross * inv * cross).try_inverse().unwrap_or_else(Matrix3::identity);
        }
        // Compression: the struck points brought to rest, within their friction cones.
        for _ in 0..RESTITUTION_SWEEPS {
            let mut change: f64 = 0.0;
            for s in &mut struck[..len] {
                let velocity = v + w.cross(&s.lever) - ground_velocity;
                let next = s.cone(s.added - s.block_inverse * velocity);
                let d = next - s.added;
                s.added = next;
                v += d;
                w += inv * s.lever.cross(&d);
                change = change.max(d.norm());
            }
            if change <= 1e-9 {
                break;
            }
        }
        // Restitution: normal impulses to e u_i.
        let arm: [Vec3; MAX_STRUCK] = std::array::from_fn(|k| struck[k].lever.cross(&n));
        let k_diag: [f64; MAX_STRUCK] = std::array::from_fn(|k| 1.0 + arm[k].dot(&(inv * arm[k])));
        let mut bounce = [0.0; MAX_STRUCK];
        for _ in 0..RESTITUTION_SWEEPS {
            let mut change: f64 = 0.0;
            for k in 0..len {
                let s = &struck[k];
                let speed = (v + w.cross(&s.lever) - ground_velocity).dot(&n);
                let next = (bounce[k] + (s.target - speed) / k_diag[k]).max(-(s.impulse + s.added.z));
                let d = next - bounce[k];
                bounce[k] = next;
                v += n * d;
                w += inv * (arm[k] * d);
                change = change.max(d.abs());
            }
            if change <= 1e-9 {
                break;
            }
        }
        // No energy from the impact (doc above).
        let energy = |v: &Vec3, w: &Vec3, inertia: &Matrix3<f64>, z: f64| {
            0.5 * v.norm_squared() + 0.5 * w.dot(&(inertia * w)) + GRAVITY * z
        };
        let start = energy(&before.linvel, &before.angvel, &body.world_inertia(&before.rotation), before.z);
        let after_rapier = energy(&v_rapier, &w_rapier, &inertia, z);
        let cap = start.max(after_rapier);
        if energy(&v, &w, &inertia, z) > cap {
            let (dv, dw) = (v - v_rapier, w - w_rapier);
            // E(s) = E(rapier) + a s + b s² for the change scaled by s: the largest s ≤ 1 within the cap.
            let a = v_rapier.dot(&dv) + w_rapier.dot(&(inertia * dw));
            let b = 0.5 * dv.norm_squared() + 0.5 * dw.dot(&(inertia * dw));
            let room = cap - after_rapier;
            let s = if b > 0.0 {
                ((-a + (a * a + 4.0 * b * room).max(0.0).sqrt()) / (2.0 * b)).clamp(0.0, 1.0)
            } else {
                0.0
            };
            v = v_rapier + dv * s;
            w = w_rapier + dw * s;
        }
        let rb = &mut world.bodies[handle];
        rb.set_linvel(convert::vec(&v), true);
        rb.set_angvel(convert::vec(&w), true);
    }
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
