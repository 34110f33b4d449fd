//! The convex polygon (a homogeneous plate) with its area centroid G: construction and checks,
//! regular polygons, the convex hull of a point set, and R(φ), the distance from G to the
//! boundary.

use super::{cross, Point2, Rotate, Vec2};
use crate::mesh::TriMesh;
use crate::{Error, Point3, Result};
use serde::Serialize;
use std::f64::consts::PI;

/// A convex polygon (a homogeneous plate) with its area centroid.
#[derive(Clone, Debug, Serialize)]
pub struct Polygon {
    /// Counter-clockwise.
    pub vertices: Vec<Point2>,
    /// G: the area centroid.
    pub centroid: Point2,
    /// Area of the polygon.
    pub area: f64,
    /// D: the diagonal of the bounding box (scale of the tolerances).
    pub size: f64,
}

impl Polygon {
    /// A convex polygon from its vertices in order (either orientation; stored
    /// counter-clockwise). Collinear consecutive vertices are allowed (a degenerate case the
    /// equilibria decide by perturbation); repeated vertices, reflex vertices, self-overlap and
    /// zero area are errors.
    pub fn new(mut vertices: Vec<Point2>) -> Result<Self> {
        let n = vertices.len();
        if n < 3 {
            return Err(Error::degenerate(format!("a polygon needs at least 3 vertices, got {n}")));
        }
        if vertices.iter().any(|p| !p.x.is_finite() || !p.y.is_finite()) {
            return Err(Error::invalid("non-finite polygon vertex"));
        }
        let (mut lo, mut hi) = (vertices[0], vertices[0]);
        for p in &vertices {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let size = (hi - lo).norm();
        let o = vertices[0];
        let (mut a2, mut m) = (0.0, Vec2::zeros());
        for i in 0..n {
            let (p, q) = (vertices[i] - o, vertices[(i + 1) % n] - o);
            let c = cross(&p, &q);
            a2 += c;
            m += (p + q) * c;
        }
        if a2.abs() <= 1e-12 * size * size {
            return Err(Error::degenerate("polygon of zero area"));
        }
        if a2 < 0.0 {
            vertices.reverse();
            return Self::new(vertices);
        }
        let tol = 1e-12;
        let mut turning = 0.0;
        for i in 0..n {
            let e0 = vertices[i] - vertices[(i + n - 1) % n];
            let e1 = vertices[(i + 1) % n] - vertices[i];
            let (l0, l1) = (e0.norm(), e1.norm());
            if l1 <= tol * size {
                return Err(Error::degenerate(format!("vertices {i} and {} coincide", (i + 1) % n)));
            }
            let c = cross(&e0, &e1);
            if c < -tol * l0 * l1 {
                return Err(Error::invalid(format!("polygon is not convex at vertex {i}")));
            }
            turning += c.atan2(e0.dot(&e1));
        }
        if (turning - 2.0 * PI).abs() > 1e-6 {
            return Err(Error::invalid(format!("polygon winds {:.3} times around itself", turning / (2.0 * PI))));
        }
        let centroid = o + m / (3.0 * a2);
        Ok(Polygon { vertices, centroid, area: a2 / 2.0, size })
    }

    /// The regular n-gon of circumradius `radius` centred at the origin, vertex 0 at angle
    /// `phase`.
    pub fn regular(n: usize, radius: f64, phase: f64) -> Result<Self> {
        Self::new(
            (0..n)
                .map(|i| {
                    let t = phase + 2.0 * PI * i as f64 / n as f64;
                    Point2::new(radius * t.cos(), radius * t.sin())
                })
                .collect(),
        )
    }

    /// The convex hull of a point set (Andrew's monotone chain with exact orientation tests;
    /// collinear points dropped).
    pub fn convex_hull(points: &[Point2]) -> Result<Self> {
        let mut p: Vec<Point2> = points.to_vec();
        p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
        p.dedup();
        if p.len() < 3 {
            return Err(Error::degenerate("fewer than 3 distinct points"));
        }
        let orient = |a: &Point2, b: &Point2, c: &Point2| {
            robust::orient2d(
                robust::Coord { x: a.x, y: a.y },
                robust::Coord { x: b.x, y: b.y },
                robust::Coord { x: c.x, y: c.y },
            )
        };
        let mut hull: Vec<Point2> = Vec::with_capacity(2 * p.len());
        for pass in 0..2 {
            let start = hull.len();
            let iter: Box<dyn Iterator<Item = &Point2>> =
                if pass == 0 { Box::new(p.iter()) } else { Box::new(p.iter().rev()) };
            for q in iter {
                while hull.len() >= start + 2 && orient(&hull[hull.len() - 2], &hull[hull.len() - 1], q) <= 0.0 {
                    hull.pop();
                }
                hull.push(*q);
            }
            hull.pop();
        }
        Self::new(hull)
    }

    /// Number of sides (= vertices).
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    /// Always false: a polygon has at least 3 vertices.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// R_max: the largest distance from G to a vertex.
    pub fn r_max(&self) -> f64 {
        self.vertices.iter().map(|p| (p - self.centroid).norm()).fold(0.0, f64::max)
    }

    /// R(φ): distance from G to the boundary along the polar angle φ (measured at G from +x).
    pub fn radius_at(&self, phi: f64) -> f64 {
        let d = Vec2::new(phi.cos(), phi.sin());
        let n = self.len();
        let g = self.centroid;
        for i in 0..n {
            let a = self.vertices[i] - g;
            let b = self.vertices[(i + 1) % n] - g;
            if cross(&a, &d) >= 0.0 && cross(&d, &b) >= 0.0 {
                let e = b - a;
                let den = cross(&d, &e);
                if den > 0.0 {
                    return cross(&a, &e) / den;
                }
            }
        }
        f64::NAN
    }

    /// The polygon rotated about G by `angle` and translated so that G is at `g`.
    pub fn placed(&self, angle: f64, g: Point2) -> Vec<Point2> {
        self.vertices.iter().map(|p| g + (p - self.centroid).rotate_by(angle)).collect()
    }

    /// The outline as a line chart draws it: the vertices as (x, y), counter-clockwise, the first
    /// repeated at the end to close it.
    pub fn closed_outline(&self) -> Vec<(f64, f64)> {
        self.vertices.iter().chain(self.vertices.first()).map(|p| (p.x, p.y)).collect()
    }

    /// The right prism of height `height` over the polygon, a closed triangle mesh: vertex k
    /// (k < n) is polygon vertex k at z = −height/2, vertex n + k the same at z = +height/2; the
    /// bottom fanned from vertex 0 facing −z, the top from vertex n facing +z, side k two
    /// triangles (k, k + 1, n + k + 1) and (k, n + k + 1, n + k), every triangle counter-clockwise
    /// seen from outside. A regular polygon gives a thick coin (a cylinder's prism).
    pub fn prism(&self, height: f64) -> TriMesh {
        let layer = |z: f64| self.vertices.iter().map(move |p| Point3::new(p.x, p.y, z));
        let vertices: Vec<Point3> = layer(-0.5 * height).chain(layer(0.5 * height)).collect();
        let n = self.vertices.len() as u32;
        let mut t = Vec::new();
        for k in 1..n - 1 {
            t.push([0, k + 1, k]); // bottom, facing −z
            t.push([n, n + k, n + k + 1]); // top, facing +z
        }
        for k in 0..n {
            let j = (k + 1) % n;
            t.push([k, j, n + j]);
            t.push([k, n + j, n + k]);
        }
        TriMesh::new(vertices, t)
    }

    /// The rigid motion that rests the plate on the boundary point `contact` on the ground
    /// y = 0: with u = contact − G, a rotation about G by θ = −π/2 − atan2(u_y, u_x) turns u
    /// straight down, then a translation puts G at (0, |u|), so the contact goes to the origin.
    /// Returns the map p ↦ (cos θ d_x − sin θ d_y, |u| + sin θ d_x + cos θ d_y), d = p − G.
    pub fn resting_on(&self, contact: Point2) -> impl Fn(&Point2) -> Point2 + '_ {
        let u = contact - self.centroid;
        let (s, c) = (-PI / 2.0 - u.y.atan2(u.x)).sin_cos();
        let height = u.norm();
        move |p| {
            let d = p - self.centroid;
            Point2::new(c * d.x - s * d.y, height + s * d.x + c * d.y)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resting_on_a_side_puts_the_plate_above_the_ground() {
        // The 2 × 1 rectangle centred at (1, 0.5), rested on the foot of G on its right side.
        let rect = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)].map(|(x, y)| Point2::new(x, y));
        let poly = Polygon::new(rect.to_vec()).unwrap();
        let place = poly.resting_on(Point2::new(2.0, 0.5));
        let (contact, g) = (place(&Point2::new(2.0, 0.5)), place(&poly.centroid));
        assert!(contact.coords.norm() < 1e-15, "{contact}");
        assert!(g.x.abs() < 1e-15 && (g.y - 1.0).abs() < 1e-15, "{g}");
        // The right side lies on the ground, the left one at height 2; distances are kept.
        let v: Vec<Point2> = rect.iter().map(&place).collect();
        for (p, y) in v.iter().zip([2.0, 0.0, 0.0, 2.0]) {
            assert!((p.y - y).abs() < 1e-14, "{p}");
        }
        assert!(((v[0] - v[1]).norm() - 2.0).abs() < 1e-14);
    }

    #[test]
    fn a_prism_is_a_closed_solid_of_area_times_height() {
        // The 2 × 1 rectangle centred at the origin, 3 high: volume 6, G at the origin, inertia
        // about z of a 2 × 1 × 3 box: V (2² + 1²)/12 = 2.5.
        let rect = [(-1.0, -0.5), (1.0, -0.5), (1.0, 0.5), (-1.0, 0.5)].map(|(x, y)| Point2::new(x, y));
        let mesh = Polygon::new(rect.to_vec()).unwrap().prism(3.0);
        let poly = Polygon::new(rect.to_vec()).unwrap();
        assert_eq!(poly.closed_outline(), [(-1.0, -0.5), (1.0, -0.5), (1.0, 0.5), (-1.0, 0.5), (-1.0, -0.5)]);
        assert_eq!((mesh.vertices.len(), mesh.triangles.len()), (8, 12));
        assert_eq!((mesh.vertices[1], mesh.vertices[6]), (Point3::new(1.0, -0.5, -1.5), Point3::new(1.0, 0.5, 1.5)));
        let (solid, _) = mesh.into_solid_boundary().unwrap();
        let m = crate::solid::MassProperties::of(&solid).unwrap();
        assert!((m.volume - 6.0).abs() < 1e-12 && m.center_of_mass.coords.norm() < 1e-12, "{m:?}");
        assert!((m.inertia[(2, 2)] - 2.5).abs() < 1e-12, "{}", m.inertia);
        // A regular 32-gon of circumradius ½: the area of the polygon times the height.
        let coin = Polygon::regular(32, 0.5, 0.0).unwrap();
        let m = crate::solid::MassProperties::of(&coin.prism(0.2)).unwrap();
        assert!((m.volume - 0.2 * coin.area).abs() < 1e-12, "{}", m.volume);
    }
}
