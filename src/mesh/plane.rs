//! Planes in space, and the plane that best fits a closed polyline.
//!
//! The best-fit plane of a closed polyline p₀ … pₙ₋₁ (pₙ = p₀) is the least-squares plane of the
//! *curve*, not of its vertices, so that a rim sampled densely on one side and sparsely on the
//! other is not pulled towards the dense side: each vertex is weighted by half the length of its
//! two edges, wᵢ = (|pᵢ − pᵢ₋₁| + |pᵢ₊₁ − pᵢ|)/2, the plane passes through the weighted mean
//! o = Σ wᵢ pᵢ / Σ wᵢ, and its normal is the eigenvector of the smallest eigenvalue of the weighted
//! covariance C = Σ wᵢ (pᵢ − o)(pᵢ − o)ᵀ (which minimises Σ wᵢ (n·(pᵢ − o))²). In the plane, the
//! first axis e₁ is the eigenvector of the largest eigenvalue (the polyline's long direction) and
//! e₂ = n × e₁, so that (e₁, e₂, n) is right-handed: a polygon counter-clockwise in (e₁, e₂) has
//! the normal +n.
//!
//! The normal's sign is the caller's: [`Plane::best_fit`] puts it on the side of a direction it is
//! given, e.g. the polyline's vector area A = ½ Σ pᵢ × pᵢ₊₁ (the Newell normal, whose sign is the
//! polyline's sense of rotation).
//! The area the polyline encloses on the plane is |n·A| (exact for a planar polygon: the area of
//! its projection).

use crate::{Point3, Vec3};

/// An oriented plane with a right-handed frame: the points o + u e₁ + v e₂, normal n = e₁ × e₂.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Plane {
    /// A point of the plane (the origin of its coordinates).
    pub point: Point3,
    /// Unit normal n.
    pub normal: Vec3,
    /// First unit axis in the plane, e₁.
    pub e1: Vec3,
    /// Second unit axis in the plane, e₂ = n × e₁.
    pub e2: Vec3,
}

impl Plane {
    /// The plane through `point` with unit normal direction `normal` (normalised; `None` if it
    /// is zero or not finite), e₁ any unit vector perpendicular to it.
    pub fn new(point: Point3, normal: Vec3) -> Option<Plane> {
        let n = normal.try_normalize(0.0)?;
        if !n.iter().all(|x| x.is_finite()) {
            return None;
        }
        // The coordinate axis least aligned with n, made perpendicular to it.
        let k = (0..3).min_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs())).unwrap_or(0);
        let e1 = (Vec3::ith(k, 1.0) - n * n[k]).normalize();
        Some(Plane { point, normal: n, e1, e2: n.cross(&e1) })
    }

    /// The least-squares plane of the closed polyline `points` (module docs), its normal on the
    /// side of `towards` (n·towards ≥ 0). `None` for fewer than three points, a polyline of zero
    /// length or non-finite arithmetic.
    pub fn best_fit(points: &[Point3], towards: &Vec3) -> Option<Plane> {
        Plane::best_fit_loops(&[points], towards)
    }

    /// The least-squares plane of several closed polylines together, each weighted as in
    /// [`Plane::best_fit`].
    pub fn best_fit_loops(loops: &[&[Point3]], towards: &Vec3) -> Option<Plane> {
        if loops.iter().any(|l| l.len() < 3) || loops.is_empty() {
            return None;
        }
        let weighted: Vec<(Point3, f64)> = loops
            .iter()
            .flat_map(|points| {
                let n = points.len();
                (0..n).map(move |i| {
                    let w =
                        ((points[i] - points[(i + n - 1) % n]).norm() + (points[(i + 1) % n] - points[i]).norm()) / 2.0;
                    (points[i], w)
                })
            })
            .collect();
        let total: f64 = weighted.iter().map(|(_, w)| w).sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let first = weighted[0].0.coords;
        let mean = weighted.iter().map(|(p, w)| (p.coords - first) * *w).sum::<Vec3>() / total + first;
        let mut c = nalgebra::Matrix3::zeros();
        for (p, w) in &weighted {
            let d = p.coords - mean;
            c += d * d.transpose() * *w;
        }
        if !c.iter().all(|x| x.is_finite()) {
            return None;
        }
        let eig = nalgebra::SymmetricEigen::new(c);
        let mut order = [0usize, 1, 2];
        order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
        let mut normal: Vec3 = eig.eigenvectors.column(order[0]).into_owned();
        if normal.dot(towards) < 0.0 {
            normal = -normal;
        }
        let e1: Vec3 = eig.eigenvectors.column(order[2]).into_owned();
        let e1 = (e1 - normal * normal.dot(&e1)).try_normalize(0.0)?;
        let normal = normal.try_normalize(0.0)?;
        Some(Plane { point: Point3::from(mean), normal, e1, e2: normal.cross(&e1) })
    }

    /// Signed distance of `p` from the plane, positive on the side n points to.
    pub fn distance(&self, p: &Point3) -> f64 {
        self.normal.dot(&(p - self.point))
    }

    /// Coordinates (u, v) of the projection of `p` on the plane.
    pub fn coordinates(&self, p: &Point3) -> [f64; 2] {
        let d = p - self.point;
        [self.e1.dot(&d), self.e2.dot(&d)]
    }

    /// The point o + u e₁ + v e₂ + h n.
    pub fn at(&self, u: f64, v: f64, h: f64) -> Point3 {
        self.point + self.e1 * u + self.e2 * v + self.normal * h
    }
}

/// The vector area ½ Σ pᵢ × pᵢ₊₁ of a closed polyline (the Newell normal times the enclosed area
/// for a planar polygon), computed relative to the first point.
pub fn vector_area(points: &[Point3]) -> Vec3 {
    let Some(o) = points.first() else { return Vec3::zeros() };
    let n = points.len();
    (0..n).map(|i| (points[i] - o).cross(&(points[(i + 1) % n] - o))).sum::<Vec3>() / 2.0
}

/// Length of a closed polyline.
pub fn perimeter(points: &[Point3]) -> f64 {
    let n = points.len();
    (0..n).map(|i| (points[(i + 1) % n] - points[i]).norm()).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tilted_circle_is_fitted_exactly_and_its_area_is_pi_r_squared() {
        // A circle of radius 2 in a tilted plane, sampled unevenly: the fit is the circle's plane
        // and centre, its enclosed area π r² to the polygon's error.
        let n = Vec3::new(1.0, 2.0, 2.0).normalize();
        let plane = Plane::new(Point3::new(1.0, -1.0, 3.0), n).unwrap();
        let angles: Vec<f64> = (0..400).map(|k| std::f64::consts::TAU * (k as f64 / 400.0).powf(1.5)).collect();
        let pts: Vec<Point3> = angles.iter().map(|t| plane.at(2.0 * t.cos(), 2.0 * t.sin(), 0.0)).collect();
        let a = vector_area(&pts);
        let fit = Plane::best_fit(&pts, &a).unwrap();
        assert!((fit.normal - n).norm() < 1e-9, "{:?}", fit.normal);
        assert!(pts.iter().all(|p| fit.distance(p).abs() < 1e-12));
        // The length-weighted mean is the centre (a vertex mean would lean to the dense side).
        assert!((fit.point - plane.point).norm() < 1e-3, "{:?}", fit.point);
        let area = fit.normal.dot(&a).abs();
        assert!((area - std::f64::consts::PI * 4.0).abs() < 2e-3, "{area}");
        assert!((perimeter(&pts) - 4.0 * std::f64::consts::PI).abs() < 1e-3);
        // Right-handed frame.
        assert!((fit.e1.cross(&fit.e2) - fit.normal).norm() < 1e-12);
        let [u, v] = fit.coordinates(&fit.at(0.3, -0.2, 5.0));
        assert!((u - 0.3).abs() < 1e-12 && (v + 0.2).abs() < 1e-12);
    }

    #[test]
    fn degenerate_polylines_have_no_plane() {
        assert!(Plane::best_fit(&[Point3::origin(); 2], &Vec3::z()).is_none());
        assert!(Plane::best_fit(&[Point3::origin(); 5], &Vec3::z()).is_none());
        assert!(Plane::new(Point3::origin(), Vec3::zeros()).is_none());
    }
}
