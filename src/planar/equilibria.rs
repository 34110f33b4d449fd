//! The micro-equilibria of a polygon (see "Micro-equilibria" in the parent module): stable
//! sides and unstable vertices, read from the signs of c⁺ and c⁻, degenerate signs decided by
//! the symbolic perturbation of G.

use super::{perturbation_direction, Point2, Polygon, Rotate, Vec2};
use crate::hierarchy::Kind;
use crate::{Error, Result};
use serde::Serialize;
use std::f64::consts::PI;

/// Where on the polygon a micro-equilibrium sits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "on", content = "index", rename_all = "lowercase")]
pub enum PlanarSite {
    /// Side i = (V_i, V_{i+1}).
    Side(u32),
    /// Vertex i (an unstable equilibrium).
    Vertex(u32),
}

/// One micro-equilibrium of a polygon.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct PlanarEquilibrium {
    /// Stable (side) or unstable (vertex).
    pub kind: Kind,
    /// Side or vertex where it lies.
    pub site: PlanarSite,
    /// Contact point: the foot of G on the side, or the vertex.
    pub point: Point2,
    /// R = |point − G|.
    pub r: f64,
    /// Polar angle of `point` seen from G, in (−π, π].
    pub phi: f64,
}

/// All micro-equilibria of a polygon, in boundary (= angular) order.
#[derive(Clone, Debug, Serialize)]
pub struct PlanarEquilibria {
    /// Vertex i (if unstable) then side i (if stable), i = 0, 1, …: alternating kinds.
    pub points: Vec<PlanarEquilibrium>,
    /// Number of stable equilibria (sides).
    pub stable: usize,
    /// Number of unstable equilibria (vertices).
    pub unstable: usize,
    /// Largest distance from G to a vertex.
    pub r_max: f64,
    /// Smallest R over the stable points.
    pub r_min: f64,
    /// Number of predicate signs decided by the symbolic perturbation (0 for generic input).
    pub degenerate_decisions: usize,
}

impl PlanarEquilibria {
    /// Classify every side and vertex of `poly` (see the module docs).
    pub fn new(poly: &Polygon, tol_rel: f64) -> Result<Self> {
        let n = poly.len();
        let g = poly.centroid;
        let tau = tol_rel * poly.size;
        let d = perturbation_direction();
        let d2 = d.rotate_by(PI / 2.0);
        let mut degenerate = 0;
        let mut decide = |value: f64, t: Vec2| {
            if value.abs() > tau {
                value > 0.0
            } else {
                degenerate += 1;
                let first = t.dot(&d);
                if first != 0.0 {
                    first > 0.0
                } else {
                    t.dot(&d2) > 0.0
                }
            }
        };
        let mut plus = Vec::with_capacity(n);
        let mut minus = Vec::with_capacity(n);
        let mut dirs = Vec::with_capacity(n);
        for i in 0..n {
            let (a, b) = (poly.vertices[i], poly.vertices[(i + 1) % n]);
            let t = (b - a).normalize();
            plus.push(decide((g - a).dot(&t), t));
            minus.push(decide((g - b).dot(&-t), -t));
            dirs.push(t);
        }
        let mut points = Vec::new();
        let mut stable = 0;
        let mut unstable = 0;
        let mut at = |kind, site, point: Point2| {
            let r = (point - g).norm();
            points.push(PlanarEquilibrium { kind, site, point, r, phi: (point.y - g.y).atan2(point.x - g.x) });
        };
        for i in 0..n {
            let before = minus[(i + n - 1) % n];
            if plus[i] && before {
                at(Kind::Unstable, PlanarSite::Vertex(i as u32), poly.vertices[i]);
                unstable += 1;
            } else if !plus[i] && !before {
                return Err(Error::check(format!(
                    "vertex {i} decided as a minimum of R ({degenerate} degenerate decisions): impossible on a convex polygon"
                )));
            }
            if plus[i] && minus[i] {
                let a = poly.vertices[i];
                let len = (poly.vertices[(i + 1) % n] - a).norm();
                at(Kind::Stable, PlanarSite::Side(i as u32), a + dirs[i] * (g - a).dot(&dirs[i]).clamp(0.0, len));
                stable += 1;
            }
        }
        if stable != unstable || stable == 0 {
            return Err(Error::check(format!("S = {stable} ≠ U = {unstable} ({degenerate} degenerate decisions)")));
        }
        let r_min = points.iter().filter(|p| p.kind == Kind::Stable).map(|p| p.r).fold(f64::INFINITY, f64::min);
        Ok(PlanarEquilibria { points, stable, unstable, r_max: poly.r_max(), r_min, degenerate_decisions: degenerate })
    }

    /// The depth of the potential well of the stable point `i` (`None` for an unstable one):
    /// the rise of R from it to the lower of its two neighbouring maxima on the cycle,
    /// normalised by R_max, (min(R_{i−1}, R_{i+1}) − R_i) / R_max.
    pub fn well_depth(&self, i: usize) -> Option<f64> {
        let (eq, m) = (&self.points, self.points.len());
        if eq[i].kind != Kind::Stable {
            return None;
        }
        let (p, q) = (eq[(i + m - 1) % m].r, eq[(i + 1) % m].r);
        Some((p.min(q) - eq[i].r) / self.r_max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planar::DEFAULT_DEGENERACY_TOL;

    #[test]
    fn square() {
        let sq = Polygon::regular(4, 1.0, 0.3).unwrap();
        let e = PlanarEquilibria::new(&sq, DEFAULT_DEGENERACY_TOL).unwrap();
        assert_eq!((e.stable, e.unstable, e.degenerate_decisions), (4, 4, 0));
    }

    #[test]
    fn well_depths_of_a_rectangle() {
        // The 2 × 1 rectangle: long sides at R = 1/2, short sides at R = 1, corners at √5/2.
        let rect = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)].map(|(x, y)| Point2::new(x, y));
        let e = PlanarEquilibria::new(&Polygon::new(rect.to_vec()).unwrap(), DEFAULT_DEGENERACY_TOL).unwrap();
        let corner = 5f64.sqrt() / 2.0;
        for (i, p) in e.points.iter().enumerate() {
            match (p.site, e.well_depth(i)) {
                (PlanarSite::Vertex(_), d) => assert_eq!(d, None),
                (PlanarSite::Side(s), Some(d)) => {
                    let r = if s % 2 == 0 { 0.5 } else { 1.0 };
                    assert!((d - (corner - r) / corner).abs() < 1e-15, "side {s}: {d}");
                }
                other => panic!("{other:?}"),
            }
        }
    }
}
