//! Exact basin areas of the stable facets: separatrices, sectors, spherical polygons (see the
//! [module docs](super)).

use super::flow::{angle, frame};
use super::{SupportFlow, MAX_REFINE, NONE};
use crate::equilibria::Equilibria;
use crate::hull::Polyhedron;
use crate::{Point3, Vec3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

impl SupportFlow {
    /// Basin areas of the stable facets (see the module docs).
    pub fn basins(&self) -> QuasiStatic {
        let nv = self.w.len();
        // Sources of separatrices: every corner of every cone, every u_P on its arc.
        let mut sources: Vec<(u32, Vec3, [u32; 2])> = Vec::new();
        for (f, vs) in self.facet_vertices.iter().enumerate() {
            let k_n = vs.len();
            for (k, &v) in vs.iter().enumerate() {
                let on = [self.facet_edges[f][k], self.facet_edges[f][(k + k_n - 1) % k_n]];
                sources.push((v, self.normal[f], on));
            }
        }
        for (e, p) in self.foot.iter().enumerate() {
            let pn = p.norm();
            if !(pn > 0.0) {
                continue;
            }
            let up = p / pn;
            let [f0, f1] = self.edge_facets[e];
            if up.dot(&(self.normal[f0 as usize] + self.normal[f1 as usize])) <= 0.0
                || self.corner_of(e as u32, &up).is_some()
            {
                continue;
            }
            for v in self.edge_vertices[e] {
                sources.push((v, up, [e as u32, NONE]));
            }
        }
        let traced: Vec<Vec<(u32, Vec3)>> = sources
            .par_iter()
            .map(|&(v, x, on)| {
                let mut out = Vec::new();
                self.trace_back(v, x, on, &mut out);
                out
            })
            .collect();
        let frames: Vec<(Vec3, Vec3)> = self.u.iter().map(frame).collect();
        let mut angles: Vec<Vec<f64>> = vec![Vec::new(); nv];
        for (v, x) in traced.into_iter().flatten() {
            if let Some(a) = angle(&frames[v as usize], &x) {
                angles[v as usize].push(a);
            }
        }
        let cones: Vec<ConeResult> =
            angles.into_par_iter().enumerate().map(|(v, a)| self.cone_basins(v as u32, &frames[v], a)).collect();
        let mut area = vec![0.0; self.normal.len()];
        let (mut unresolved, mut failed, mut sectors, mut refined) = (0.0, 0.0, 0usize, 0usize);
        for c in &cones {
            for &(f, a) in &c.areas {
                area[f as usize] += a;
            }
            unresolved += c.unresolved;
            failed += c.failed;
            sectors += c.sectors;
            refined += c.refined;
        }
        let total: f64 = area.iter().sum();
        let sphere = 4.0 * PI;
        let facet_probability = area.iter().map(|a| if total > 0.0 { a / total } else { 0.0 }).collect();
        let error = (unresolved + failed) / sphere + (total / sphere - 1.0).abs() + 1e-12;
        QuasiStatic {
            facet_probability,
            error,
            method: format!(
                "exact: normal cones of the hull corners cut along separatrix meridians into {sectors} spherical \
                 sectors, each labelled by an exact quasi-static descent ({refined} sectors re-bisected by the \
                 consistency check, unresolved area {:.1e} of 4π, failed descents {:.1e} of 4π, total area 4π·{:.15})",
                unresolved / sphere,
                failed / sphere,
                total / sphere
            ),
        }
    }

    /// The sectors of the cone of `v` between consecutive separatrix angles `angles`.
    fn cone_basins(&self, v: u32, fr: &(Vec3, Vec3), mut angles: Vec<f64>) -> ConeResult {
        let corners: Vec<Vec3> = self.cones[v as usize].iter().map(|&f| self.normal[f as usize]).collect();
        angles.extend(corners.iter().filter_map(|c| angle(fr, c)));
        angles.sort_by(f64::total_cmp);
        angles.dedup_by(|a, b| (*a - *b).abs() < 1e-15);
        if angles.is_empty() {
            angles.push(0.0);
        }
        // No gap above π/2 (the wedge clip needs < π).
        let mut all = Vec::with_capacity(angles.len() + 4);
        for (i, &a) in angles.iter().enumerate() {
            let next = if i + 1 < angles.len() { angles[i + 1] } else { angles[0] + 2.0 * PI };
            all.push(a);
            let pieces = ((next - a) / (0.5 * PI)).ceil().max(1.0) as usize;
            for j in 1..pieces {
                all.push(a + (next - a) * j as f64 / pieces as f64);
            }
        }
        let mut res = ConeResult::default();
        let cone = Cone { v, corners: &corners, fr };
        for i in 0..all.len() {
            let next = if i + 1 < all.len() { all[i + 1] } else { all[0] + 2.0 * PI };
            self.sector(&cone, all[i], next, 0, None, &mut res);
        }
        res
    }

    /// Label the sector [a1, a2] of a cone (with a consistency check and bisection).
    fn sector(&self, cone: &Cone, a1: f64, a2: f64, depth: u32, known: Option<u32>, res: &mut ConeResult) {
        let Some((area, centre)) = cone.piece(a1, a2) else { return };
        res.sectors += usize::from(depth == 0);
        let label = match known {
            Some(l) => Some(l),
            None => self.descend(cone.v, centre, None).ok(),
        };
        let mid = 0.5 * (a1 + a2);
        let half = |lo: f64, hi: f64| cone.piece(lo, hi).map(|(_, c)| self.descend(cone.v, c, None).ok());
        let (left, right) = (half(a1, mid), half(mid, a2));
        // A half that is empty agrees; a half whose descent failed does not.
        let agrees = |h: &Option<Option<u32>>| h.is_none_or(|l| l.is_some() && l == label);
        if let Some(l) = label.filter(|_| agrees(&left) && agrees(&right)) {
            res.areas.push((l, area));
        } else if depth < MAX_REFINE && mid > a1 && mid < a2 {
            res.refined += usize::from(depth == 0);
            self.sector(cone, a1, mid, depth + 1, left.flatten(), res);
            self.sector(cone, mid, a2, depth + 1, right.flatten(), res);
        } else if let Some(l) = label {
            res.areas.push((l, area));
            res.unresolved += area;
        } else {
            res.failed += area;
        }
    }
}

/// Per-cone output of [`SupportFlow::basins`].
#[derive(Default)]
struct ConeResult {
    areas: Vec<(u32, f64)>,
    unresolved: f64,
    failed: f64,
    sectors: usize,
    refined: usize,
}

/// A vertex cone as a convex spherical polygon, with the frame around u_V.
struct Cone<'a> {
    v: u32,
    corners: &'a [Vec3],
    fr: &'a (Vec3, Vec3),
}

impl Cone<'_> {
    /// Area and centroid direction of the cone ∩ the wedge of angles [a1, a2] (a2 − a1 < π).
    fn piece(&self, a1: f64, a2: f64) -> Option<(f64, Vec3)> {
        let (p1, p2) = *self.fr;
        // n(α)·x = ρ sin(φ − α) ≥ 0 ⇔ φ ∈ [α, α + π]
        let n = |a: f64| p2 * a.cos() - p1 * a.sin();
        let mut poly = clip(self.corners, &n(a1));
        poly = clip(&poly, &-n(a2));
        if poly.len() < 3 {
            return None;
        }
        let area = spherical_area(&poly);
        let centre = poly.iter().sum::<Vec3>().normalize();
        (area > 0.0 && centre.iter().all(|c| c.is_finite())).then_some((area, centre))
    }
}

/// Clip a convex spherical polygon (unit vectors, minor arcs) to the hemisphere m·x ≥ 0.
pub(super) fn clip(poly: &[Vec3], m: &Vec3) -> Vec<Vec3> {
    let n = poly.len();
    let mut out = Vec::with_capacity(n + 2);
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        let (dp, dq) = (m.dot(&p), m.dot(&q));
        if dp >= 0.0 {
            out.push(p);
        }
        if (dp >= 0.0) != (dq >= 0.0) {
            let x = q * dp - p * dq;
            let x = if dp >= 0.0 { x } else { -x };
            let len = x.norm();
            if len > 0.0 {
                out.push(x / len);
            }
        }
    }
    out
}

/// Area of a convex spherical polygon: fan of triangles, each by Van Oosterom–Strackee.
pub(super) fn spherical_area(poly: &[Vec3]) -> f64 {
    let a = poly[0];
    let mut s = 0.0;
    for k in 1..poly.len() - 1 {
        let (b, c) = (poly[k], poly[k + 1]);
        s += 2.0 * a.dot(&b.cross(&c)).atan2(1.0 + a.dot(&b) + b.dot(&c) + c.dot(&a));
    }
    s.abs()
}

/// The quasi-static resting probabilities: basin areas of the stable facets / 4π.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct QuasiStatic {
    /// Per hull facet; 0 for facets that are not stable; sums to 1.
    pub facet_probability: Vec<f64>,
    /// Bound on the absolute error of every entry (and of their sum), see the module docs.
    pub error: f64,
    /// How the numbers were obtained.
    pub method: String,
}

/// Quasi-static basin probabilities of the stable facets of `poly` (the static reference of drops).
pub fn basin_probabilities(poly: &Polyhedron, g: &Point3, eq: &Equilibria) -> QuasiStatic {
    SupportFlow::new(poly, g, eq).basins()
}

/// Sum the facet probabilities per flock: `membership` = flock id per equilibrium index (as
/// [`crate::hierarchy::Flocks::membership`]), `n_flocks` the number of flocks.
pub fn flock_probabilities(q: &QuasiStatic, eq: &Equilibria, membership: &[usize], n_flocks: usize) -> Vec<f64> {
    let mut out = vec![0.0; n_flocks];
    for (f, &p) in q.facet_probability.iter().enumerate() {
        if let Some(Some(i)) = eq.at_facet.get(f) {
            if let Some(&k) = membership.get(*i as usize) {
                if k < n_flocks {
                    out[k] += p;
                }
            }
        }
    }
    out
}
