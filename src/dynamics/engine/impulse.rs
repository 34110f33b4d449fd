//! The closed forms of a rigid body's impact on one point, which the contact law's two stages
//! bracket (`experiments/corner_impact.rs` checks rapier's corner impacts against them).
//!
//! A body of mass 1 (the scaled frame) with world-frame inertia I about G, not turning, falls at
//! speed u onto the ground (normal +z) and touches it at one point r (from G). An impulse P at
//! that point changes v by P and ω by I⁻¹ (r × P), so the contact point's velocity
//! v + ω × r changes by K P with the impact matrix
//!
//! ```text
//! K = 1 − [r]× I⁻¹ [r]×        ([r]× p = r × p; K is symmetric positive definite)
//! ```
//!
//! * *Newton's law with sticking friction* ([`PointImpact::sticking`]): the contact point leaves
//!   at e u straight up, P = K⁻¹ (0, 0, (1 + e) u) (valid while |P_xy| ≤ μ P_z).
//! * *Sticking compression, then a frictionless restitution* ([`PointImpact::frictionless_restitution`]):
//!   K⁻¹ (0, 0, u) stops the point, then a normal impulse λ ẑ with K_zz λ = e u sends it up at e u.

use crate::Vec3;
use nalgebra::Matrix3;

/// A body of mass 1 about to strike the ground at one point: its impact matrix K and what the
/// closed forms give (module docs).
#[derive(Clone, Copy, Debug)]
pub struct PointImpact {
    r: Vec3,
    inertia_inverse: Matrix3<f64>,
    k: Matrix3<f64>,
    k_inverse: Matrix3<f64>,
}

impl PointImpact {
    /// The impact at `r` (world frame, from G) of a body of mass 1 with world-frame inertia
    /// `inertia` about G; None if the inertia or K is singular.
    pub fn new(inertia: &Matrix3<f64>, r: &Vec3) -> Option<Self> {
        let inertia_inverse = inertia.try_inverse()?;
        let k = Matrix3::identity() - r.cross_matrix() * inertia_inverse * r.cross_matrix();
        Some(PointImpact { r: *r, inertia_inverse, k, k_inverse: k.try_inverse()? })
    }

    /// The impact matrix K = 1 − [r]× I⁻¹ [r]×: the change of the contact point's velocity per
    /// unit impulse there.
    pub fn matrix(&self) -> &Matrix3<f64> {
        &self.k
    }

    /// Newton's law with sticking friction at approach speed `u` and restitution `e`: the
    /// impulse K⁻¹ (0, 0, (1 + e) u) after which the contact point moves up at e u, without slip.
    pub fn sticking(&self, e: f64, u: f64) -> Vec3 {
        self.k_inverse * Vec3::new(0.0, 0.0, (1.0 + e) * u)
    }

    /// A sticking compression K⁻¹ (0, 0, u), which stops the contact point, followed by a
    /// frictionless restitution (e u / K_zz) ẑ, after which it moves up at e u (and slides).
    pub fn frictionless_restitution(&self, e: f64, u: f64) -> Vec3 {
        self.k_inverse * Vec3::new(0.0, 0.0, u) + Vec3::z() * (e * u / self.k[(2, 2)])
    }

    /// The spin I⁻¹ (r × P) that the impulse `p` at the contact point gives the body.
    pub fn spin(&self, p: &Vec3) -> Vec3 {
        self.inertia_inverse * self.r.cross(p)
    }

    /// Where a spin `w` after the impact at approach speed `u` and restitution `e` lies between
    /// the two closed forms: the slip fraction φ = (w − ω_N)·(ω_F − ω_N) / |ω_F − ω_N|², ω_N
    /// the spin of Newton's law with sticking friction ([`PointImpact::sticking`]) and ω_F that
    /// of the frictionless restitution ([`PointImpact::frictionless_restitution`]): 0 at ω_N,
    /// 1 at ω_F (w projected on the line through them).
    pub fn slip_fraction(&self, e: f64, u: f64, w: &Vec3) -> f64 {
        let (w_n, w_f) = (self.spin(&self.sticking(e, u)), self.spin(&self.frictionless_restitution(e, u)));
        (w - w_n).dot(&(w_f - w_n)) / (w_f - w_n).norm_squared()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The contact point's velocity after the impulse `p` on a body falling at u, not turning.
    fn point_velocity(i: &PointImpact, u: f64, p: &Vec3) -> Vec3 {
        Vec3::new(0.0, 0.0, -u) + p + i.spin(p).cross(&i.r)
    }

    #[test]
    fn a_point_below_g_bounces_without_spin() {
        // r straight below G: K ẑ = ẑ, so both laws give the impulse (1 + e) u ẑ and no spin.
        let i =
            PointImpact::new(&Matrix3::from_diagonal(&Vec3::new(0.2, 0.3, 0.4)), &Vec3::new(0.0, 0.0, -0.5)).unwrap();
        for p in [i.sticking(0.5, 2.0), i.frictionless_restitution(0.5, 2.0)] {
            assert!((p - Vec3::new(0.0, 0.0, 3.0)).norm() < 1e-12 && i.spin(&p).norm() < 1e-12, "{p:?}");
        }
    }

    #[test]
    fn the_closed_forms_leave_the_point_as_they_say() {
        // An isotropic inertia i: K = (1 + |r|²/i) 1 − r rᵀ / i by [r]×² = r rᵀ − |r|² 1.
        let (inertia, r, e, u) = (0.25, Vec3::new(0.4, -0.3, -0.5), 0.3, 1.7);
        let i = PointImpact::new(&(Matrix3::identity() * inertia), &r).unwrap();
        let k = Matrix3::identity() * (1.0 + r.norm_squared() / inertia) - r * r.transpose() / inertia;
        assert!((i.matrix() - k).norm() < 1e-12);
        // Sticking: the point leaves straight up at e u.
        let v = point_velocity(&i, u, &i.sticking(e, u));
        assert!((v - Vec3::new(0.0, 0.0, e * u)).norm() < 1e-12, "{v:?}");
        // Frictionless restitution: up at e u too, sliding by the normal impulse's K column.
        let lambda = e * u / k[(2, 2)];
        let v = point_velocity(&i, u, &i.frictionless_restitution(e, u));
        let slide = k.column(2).xy() * lambda;
        assert!((v - Vec3::new(slide.x, slide.y, e * u)).norm() < 1e-12, "{v:?}");
    }

    #[test]
    fn the_slip_fraction_places_a_spin_between_the_closed_forms() {
        let (r, e, u) = (Vec3::new(0.4, -0.3, -0.5), 0.3, 1.7);
        let i = PointImpact::new(&Matrix3::from_diagonal(&Vec3::new(0.2, 0.3, 0.4)), &r).unwrap();
        let (w_n, w_f) = (i.spin(&i.sticking(e, u)), i.spin(&i.frictionless_restitution(e, u)));
        assert!((w_f - w_n).norm() > 1e-3);
        assert!(i.slip_fraction(e, u, &w_n).abs() < 1e-12);
        assert!((i.slip_fraction(e, u, &w_f) - 1.0).abs() < 1e-12);
        // A quarter of the way, moved off the line by a perpendicular: still 1/4.
        let off = (w_f - w_n).cross(&Vec3::new(1.0, 2.0, 3.0));
        assert!((i.slip_fraction(e, u, &(w_n + (w_f - w_n) * 0.25 + off)) - 0.25).abs() < 1e-12);
    }
}
