//! The contact law of this project, in one place: after every rapier step ([`step_world`]) it
//! completes the impacts (Coulomb's compression, Newton's restitution) and applies rolling
//! resistance and torsional friction through the contact. Rapier supplies Coulomb friction and
//! the contact's normal force; everything below is what it lacks.
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
//! solver's error, measured, not bounded ([`crate::dynamics::certificate::CERTIFICATE_MARGIN`]).
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
//! # Rolling resistance and torsional friction ([`step_world`])
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

use crate::dynamics::engine::body::Body;
use crate::dynamics::engine::convert;
use crate::dynamics::engine::params::ContactParams;
use crate::{Vec3, GRAVITY};
use nalgebra::{Matrix3, UnitQuaternion};
use rapier3d::prelude::*;

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

/// One time step of a world whose stones (each a `body`, with its rigid body and collider) lie on
/// the ground collider `ground`: rapier's step, then the contact law on each stone. The one
/// place the contact law is applied, for one stone ([`crate::dynamics::engine::simulation::Simulation::step`]) as for a batch
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
    for (k, &(rigid, collider)) in stones.iter().enumerate() {
        let pair = StoneOnGround { rigid, collider, ground };
        if let Some(m) = before.get(k) {
            law.restitute(world, body, pair, m, &ground_velocity);
        }
        if law.resists() {
            law.apply(world, body, pair);
        }
    }
}

/// One stone of a world and the ground under it: the stone's rigid body and collider, the
/// ground's collider.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StoneOnGround {
    rigid: RigidBodyHandle,
    collider: ColliderHandle,
    ground: ColliderHandle,
}

/// The ground's velocity (world frame): the body that carries the ground collider.
pub(crate) fn law_ground_velocity(world: &PhysicsWorld, ground: ColliderHandle) -> Vec3 {
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
    /// The law of the contact `c`.
    pub fn of(c: &ContactParams) -> Self {
        ContactLaw {
            restitution: c.restitution,
            rolling_resistance: c.rolling_resistance,
            torsional_friction: c.torsional_friction,
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
    fn restitute(
        &self,
        world: &mut PhysicsWorld,
        body: &Body,
        pair: StoneOnGround,
        before: &Motion,
        ground_velocity: &Vec3,
    ) {
        let StoneOnGround { rigid: handle, collider: stone, ground } = pair;
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

impl ContactLaw {
    /// Apply the torque impulses J_r and J_s of the parent module's docs to the stone `handle` (collider
    /// `stone`) after a rapier step, from the normal impulse the ground (collider `ground`) gave
    /// it during the step: about the contact patch's centre, or about G where that would add
    /// kinetic energy (the parent module's "About the contact, not about G").
    pub(crate) fn apply(&self, world: &mut PhysicsWorld, body: &Body, on: StoneOnGround) {
        let StoneOnGround { rigid: handle, collider: stone, ground } = on;
        // One look-up of the pair for the normal impulse and rapier's twist limit.
        let Some(pair) = world.narrow_phase.contact_pair(ground, stone) else { return };
        let jn = pair.total_impulse_magnitude() as f64;
        if !(jn > 0.0) {
            return;
        }
        let pose = world.colliders[stone].position();
        let torsion = if self.torsional_friction > 0.0 {
            (self.torsional_friction * jn - twist_limit(pair, stone, pose)).max(0.0)
        } else {
            0.0
        };
        let centre = impulse_centre(pair, stone, pose);
        let rb = &world.bodies[handle];
        let q = convert::quat_back(rb.rotation());
        let w = convert::vec_back(rb.angvel());
        let v = convert::vec_back(rb.linvel());
        let inertia = body.world_inertia(&q);
        // About the contact patch: the body pivots on its sticking contact (lever r = G − c;
        // I_c = I_G + m(|r|²𝟙 − r rᵀ) with m = 1, the stone's mass in the scaled frame).
        let r = centre.map_or(Vec3::zeros(), |c| convert::vec_back(rb.translation()) - c);
        let pivot_inertia = inertia + Matrix3::identity() * r.norm_squared() - r * r.transpose();
        let dw = self.couple(&w, &inverse(&pivot_inertia), jn, torsion);
        let dv = dw.cross(&r);
        let gain = v.dot(&dv) + 0.5 * dv.norm_squared() + w.dot(&(inertia * dw)) + 0.5 * dw.dot(&(inertia * dw));
        let (dw, dv) = if gain <= 0.0 {
            (dw, dv)
        } else {
            // A slipping contact that the pivot form would speed up: the free body's couple.
            (self.couple(&w, &inverse(&inertia), jn, torsion), Vec3::zeros())
        };
        let rb = &mut world.bodies[handle];
        rb.set_angvel(convert::vec(&(w + dw)), true);
        rb.set_linvel(convert::vec(&(v + dv)), true);
    }

    /// The change of ω that the rolling-resistance and torsional impulses J_r, J_s of the parent module's
    /// docs give a body of angular velocity `w` and inverse inertia `inv` (about the point it
    /// turns about), for the normal impulse `jn` and the torsional limit `torsion` (already less
    /// rapier's twist).
    fn couple(&self, w: &Vec3, inv: &Matrix3<f64>, jn: f64, torsion: f64) -> Vec3 {
        let n = Vec3::z();
        let mut dw = Vec3::zeros();
        // Rolling: the part of ω in the ground's plane.
        let wr = w - n * w.dot(&n);
        let wr_norm = wr.norm();
        if wr_norm > 0.0 && self.rolling_resistance > 0.0 {
            let u = wr / wr_norm;
            let stop = wr_norm / u.dot(&(inv * u));
            let j = (self.rolling_resistance * jn).min(stop);
            dw -= inv * (u * j);
        }
        // Spinning about the normal, after the rolling impulse: what δ_t N adds above rapier's
        // twist, T = max(T_c, δ_t N) (the parent module's docs).
        let ws = (w + dw).dot(&n);
        if ws != 0.0 && torsion > 0.0 {
            let stop = ws.abs() / n.dot(&(inv * n));
            let j = torsion.min(stop);
            dw -= inv * (n * (j * ws.signum()));
        }
        dw
    }
}

/// `m`⁻¹, or 𝟙 for a singular `m` (never for an inertia tensor).
fn inverse(m: &Matrix3<f64>) -> Matrix3<f64> {
    m.try_inverse().unwrap_or_else(Matrix3::identity)
}

/// Rapier's twist-friction limit T_c Δt = μ Σᵢ Nᵢ Δt · dᵢ over the step just taken (the parent
/// module's docs): per manifold of ≥ 2 solver contacts, the points' total normal impulses times their
/// distances from the manifold's centroid, times its friction coefficient. Zero on a single
/// point, where rapier's twist is off.
fn twist_limit(pair: &ContactPair, stone: ColliderHandle, stone_pose: &Pose) -> f64 {
    let stone_is_first = pair.collider1 == stone;
    let mut limit = 0.0;
    for m in pair.manifolds() {
        let n = m.data.solver_contacts.len();
        if n < 2 {
            continue;
        }
        let centroid = solver_points(m, stone_is_first, stone_pose).map(|(p, _)| p).sum::<Vec3>() / n as f64;
        let moment: f64 = solver_points(m, stone_is_first, stone_pose).map(|(p, jn)| jn * (p - centroid).norm()).sum();
        limit += m.data.friction as f64 * moment;
    }
    limit
}

/// The solver contacts of manifold `m` on the stone (world frame) with the normal impulse rapier
/// gave each in the last step.
fn solver_points<'a>(
    m: &'a ContactManifold,
    stone_is_first: bool,
    stone_pose: &'a Pose,
) -> impl Iterator<Item = (Vec3, f64)> + 'a {
    m.data.solver_contacts.iter().map(move |sc| {
        let tracked = &m.points[(sc.contact_id[0] & !NEW_CONTACT_BIT) as usize];
        let local = if stone_is_first { tracked.local_p1 } else { tracked.local_p2 };
        (convert::vec_back(stone_pose.transform_point(local)), tracked.data.impulse as f64)
    })
}

/// The centre of the contact patch: the solver contacts' centroid weighted by their normal
/// impulses in the last step (world frame); `None` when they carry none.
fn impulse_centre(pair: &ContactPair, stone: ColliderHandle, stone_pose: &Pose) -> Option<Vec3> {
    let stone_is_first = pair.collider1 == stone;
    let (moment, total) = pair
        .manifolds()
        .iter()
        .flat_map(|m| solver_points(m, stone_is_first, stone_pose))
        .filter(|&(_, jn)| jn > 0.0)
        .fold((Vec3::zeros(), 0.0), |(s, t), (p, jn)| (s + p * jn, t + jn));
    (total > 0.0).then(|| moment / total)
}
