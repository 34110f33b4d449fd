//! Mass properties of the homogeneous solid bounded by a closed, outward-oriented mesh.
//!
//! By the divergence theorem every integral over the solid is a sum over tetrahedra
//! (o, a, b, c) spanned by a reference point o and each triangle. With a, b, c relative to o
//! and det = a·(b×c):
//!
//! * volume            V = Σ det / 6
//! * first moment      ∫x dV = Σ det (a+b+c) / 24
//! * second moment     ∫x xᵀ dV = Σ det [aaᵀ + bbᵀ + ccᵀ + (a+b+c)(a+b+c)ᵀ] / 120
//!
//! The reference point is the vertex mean, and the second pass is taken about G itself, so a
//! scan far from the origin (or in km or mm) keeps full f64 precision. Density is 1: mass = V.

use crate::mesh::{ldexp, scale_point, TriMesh};
use crate::{Error, Point3, Result, Vec3};
use nalgebra::Matrix3;

/// Volume, centre of mass and inertia of a homogeneous solid (density 1, so mass = volume).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MassProperties {
    /// Volume (input units³).
    pub volume: f64,
    /// Centre of mass G of the solid (input frame and units).
    pub center_of_mass: Point3,
    /// Inertia tensor about G, density 1 (input units⁵).
    pub inertia: Matrix3<f64>,
    /// Principal moments, ascending.
    pub principal_moments: [f64; 3],
    /// Principal axes (unit columns), matching `principal_moments`; right-handed.
    pub principal_axes: Matrix3<f64>,
}

fn moments(mesh: &TriMesh, o: &Point3) -> (f64, Vec3, Matrix3<f64>) {
    let (mut v, mut m1, mut m2) = (0.0, Vec3::zeros(), Matrix3::zeros());
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize] - o);
        let det = a.dot(&b.cross(&c));
        let s = a + b + c;
        v += det;
        m1 += s * det;
        m2 += (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose()) * det;
    }
    (v / 6.0, m1 / 24.0, m2 / 120.0)
}

impl MassProperties {
    /// Integrate a closed, outward-oriented mesh (see [`TriMesh::into_solid_boundary`]).
    ///
    /// The integrals run on the mesh scaled by the exact power of two 2^k of
    /// [`TriMesh::unit_exponent`] (largest extent in [1, 2)), and the results are scaled back; so
    /// the products of coordinates (up to the fifth power in the inertia) neither overflow nor
    /// underflow for any finite input, and for ordinary sizes the result is bit for bit that of
    /// integrating in the input units. A quantity whose value in input units exceeds f64 (the
    /// volume of a 10³⁰⁰-unit stone) comes out infinite, one below the subnormal range as 0;
    /// [`MassProperties::scaled_pow2`] of the normalised properties recovers them.
    pub fn of(mesh: &TriMesh) -> Result<Self> {
        let k = mesh.unit_exponent();
        Ok(Self::of_unscaled(&mesh.scaled_pow2(k))?.scaled_pow2(-k))
    }

    /// The same mass properties for the solid scaled by 2^k: volume × 2^3k, G × 2^k, inertia and
    /// principal moments × 2^5k, the same axes (exact while the values stay in f64's normal range).
    pub fn scaled_pow2(&self, k: i32) -> Self {
        MassProperties {
            volume: ldexp(self.volume, 3 * k),
            center_of_mass: scale_point(&self.center_of_mass, k),
            inertia: self.inertia.map(|x| ldexp(x, 5 * k)),
            principal_moments: self.principal_moments.map(|x| ldexp(x, 5 * k)),
            principal_axes: self.principal_axes,
        }
    }

    /// Integrate in the mesh's own coordinates, without normalising (see [`MassProperties::of`]).
    pub fn of_unscaled(mesh: &TriMesh) -> Result<Self> {
        let n = mesh.vertices.len() as f64;
        if n == 0.0 {
            return Err(Error::degenerate("no vertices"));
        }
        let mean = Point3::from(mesh.vertices.iter().map(|p| p.coords).sum::<Vec3>() / n);
        let (v, m1, _) = moments(mesh, &mean);
        if !(v > 0.0) {
            return Err(Error::degenerate(format!("non-positive volume {v:e}")));
        }
        let g = mean + m1 / v;
        // Second pass about G: the first moment vanishes up to rounding, the second is central.
        let (v2, m1g, m2) = moments(mesh, &g);
        let g = g + m1g / v2;
        let inertia = Matrix3::identity() * m2.trace() - m2;
        Ok(Self::with_inertia(v2, g, inertia))
    }

    /// Volume, centre and inertia about it, with the principal moments (ascending) and a
    /// right-handed frame of principal axes.
    fn with_inertia(volume: f64, center_of_mass: Point3, inertia: Matrix3<f64>) -> Self {
        let eig = nalgebra::SymmetricEigen::new(inertia);
        let mut order = [0usize, 1, 2];
        order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
        let mut axes = Matrix3::from_columns(&order.map(|i| eig.eigenvectors.column(i).into_owned()));
        if axes.determinant() < 0.0 {
            axes.set_column(2, &(-axes.column(2)));
        }
        MassProperties {
            volume,
            center_of_mass,
            inertia,
            principal_moments: order.map(|i| eig.eigenvalues[i]),
            principal_axes: axes,
        }
    }

    /// The same body with its centre of mass declared at `c` (a weighted die, a hollow print, a
    /// scan of only the hull): the mass (= volume, density 1) is kept, and the inertia is the
    /// homogeneous solid's taken about `c` by the parallel-axis theorem,
    /// I_c = I_G + m (|d|² 1 − d dᵀ), d = c − G. The true distribution of a non-uniform body is
    /// unknown; this keeps its mass and the geometric spread of the solid, the inertia a
    /// rigid-body simulation needs about its centre of mass. `self` must be the homogeneous
    /// solid's own (central) properties.
    pub fn about(&self, c: &Point3) -> Self {
        let d = c - self.center_of_mass;
        let shift = (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * self.volume;
        Self::with_inertia(self.volume, *c, self.inertia + shift)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_declared_centre_shifts_the_inertia_by_the_parallel_axis_theorem() {
        // Unit cube (side 2h = 1, V = 1, I_G = 1/6) declared centred at a corner of its centre
        // cell, d = (0.25, 0, 0): I_xx unchanged, I_yy = I_zz = 1/6 + 0.0625.
        let m = MassProperties::of(&cube(0.5, Vec3::zeros())).unwrap();
        let c = Point3::new(0.25, 0.0, 0.0);
        let s = m.about(&c);
        assert_eq!(s.center_of_mass, c);
        assert!((s.inertia[(0, 0)] - 1.0 / 6.0).abs() < 1e-12);
        assert!((s.inertia[(1, 1)] - (1.0 / 6.0 + 0.0625)).abs() < 1e-12);
        assert!((s.inertia[(2, 2)] - (1.0 / 6.0 + 0.0625)).abs() < 1e-12);
        assert!(s.inertia[(0, 1)].abs() < 1e-12 && s.volume == m.volume);
        // The principal moments follow the shifted tensor: 1/6, 1/6 + 1/16 (twice).
        assert!((s.principal_moments[0] - 1.0 / 6.0).abs() < 1e-12);
        assert!((s.principal_moments[2] - (1.0 / 6.0 + 0.0625)).abs() < 1e-12);
    }

    fn cube(h: f64, c: Vec3) -> TriMesh {
        let v: Vec<Point3> = (0..8)
            .map(|i| {
                Point3::from(
                    c + Vec3::new(
                        if i & 1 > 0 { h } else { -h },
                        if i & 2 > 0 { h } else { -h },
                        if i & 4 > 0 { h } else { -h },
                    ),
                )
            })
            .collect();
        let t = vec![
            [0, 2, 3],
            [0, 3, 1],
            [4, 5, 7],
            [4, 7, 6],
            [0, 1, 5],
            [0, 5, 4],
            [2, 6, 7],
            [2, 7, 3],
            [0, 4, 6],
            [0, 6, 2],
            [1, 3, 7],
            [1, 7, 5],
        ];
        TriMesh::new(v, t)
    }

    #[test]
    fn cube_far_from_origin_keeps_precision() {
        let c = Vec3::new(1e7, -3e6, 2e5);
        let m = MassProperties::of(&cube(0.5, c)).unwrap();
        assert!((m.volume - 1.0).abs() < 1e-9, "{}", m.volume);
        assert!((m.center_of_mass.coords - c).norm() < 1e-8);
        for k in m.principal_moments {
            assert!((k - 1.0 / 6.0).abs() < 1e-9, "{k}");
        }
    }
}
