//! Rolling resistance and torsional friction ("Rolling resistance and torsional friction" and
//! "Friction about the normal, stated once" in the parent module): the couple applied after each
//! rapier step about the contact patch, and what it reads of the contact manifold.

use crate::dynamics::engine::convert;
use crate::dynamics::engine::world::ContactLaw;
use crate::dynamics::stone::Body;
use crate::Vec3;
use nalgebra::Matrix3;
use rapier3d::prelude::*;

impl ContactLaw {
    /// Apply the torque impulses J_r and J_s of the parent module's docs to the stone `handle` (collider
    /// `stone`) after a rapier step, from the normal impulse the ground (collider `ground`) gave
    /// it during the step: about the contact patch's centre, or about G where that would add
    /// kinetic energy (the parent module's "About the contact, not about G").
    pub fn apply(
        &self,
        world: &mut PhysicsWorld,
        body: &Body,
        handle: RigidBodyHandle,
        stone: ColliderHandle,
        ground: ColliderHandle,
    ) {
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
