//! The support polygons of facets with more than four corners (see "Facets with more than four
//! corners" in the parent module): the point each facet's quadrilateral must cover, the
//! quadrilateral of largest tipping margin, its rebuild around a lower corner when the body tilts,
//! and the feature ids of its sides.

use crate::dynamics::engine::hull_shape::vec64::{cross2, dot3, dot64, left_dist, plane_basis, sub2, to64};
use crate::dynamics::engine::hull_shape::HullShape;
use parry3d::math::Vector;
use parry3d::shape::{PackedFeatureId, PolygonalFeature};

/// Facets with more corners try this many fan apexes for their precomputed quadrilateral.
const QUAD_APEXES: usize = 64;
/// `PackedFeatureId` codes have 30 bits.
const FEATURE_CODE_LIMIT: u64 = 1 << 30;

impl HullShape {
    /// The point (body frame, f64) the reduced support polygon of facet `f` is built to cover: the
    /// projection of the origin (G) on the facet plane when it lies strictly inside the facet,
    /// else the centroid of the corners.
    pub(super) fn facet_target(&self, f: usize) -> [f64; 3] {
        self.origin_projection_inside(f).unwrap_or_else(|| {
            let cs = self.facet_corners(f);
            let s = cs
                .iter()
                .map(|&c| to64(self.points[c as usize]))
                .fold([0.0; 3], |a, p| [a[0] + p[0], a[1] + p[1], a[2] + p[2]]);
            let k = cs.len() as f64;
            [s[0] / k, s[1] / k, s[2] / k]
        })
    }

    /// The projection of the origin (G) on facet `f`'s plane (body frame, f64) if it lies strictly
    /// inside the facet: then the body can rest on `f` (a stable facet).
    pub(super) fn origin_projection_inside(&self, f: usize) -> Option<[f64; 3]> {
        let cs = self.facet_corners(f);
        let n = self.normals64[f];
        let pts: Vec<[f64; 3]> = cs.iter().map(|&c| to64(self.points[c as usize])).collect();
        let offset = pts.iter().map(|p| dot3(n, *p)).sum::<f64>() / pts.len() as f64;
        let proj = [n[0] * offset, n[1] * offset, n[2] * offset];
        let (e1, e2) = plane_basis(n);
        let p2 = |p: [f64; 3]| [dot3(p, e1), dot3(p, e2)];
        let t = p2(proj);
        let inside = (0..pts.len()).all(|k| left_dist(p2(pts[k]), p2(pts[(k + 1) % pts.len()]), t) > 0.0);
        inside.then_some(proj)
    }

    /// The quadrilateral of facet `f`'s corners containing corner `apex` (a loop position) that
    /// covers the facet's target point: the fan triangle from `apex` that contains the target
    /// (deepest inside), plus the corner that maximises the target's distance to the sides.
    /// Returns loop positions in cyclic order and that distance (the margin).
    fn quad_with_apex(&self, f: usize, apex: usize) -> ([u32; 4], f64) {
        let cs = self.facet_corners(f);
        let k = cs.len();
        let (e1, e2) = plane_basis(self.normals64[f]);
        let p2 = |p: [f64; 3]| [dot3(p, e1), dot3(p, e2)];
        let at = |r: usize| p2(to64(self.points[cs[(apex + r) % k] as usize]));
        let t = p2(self.targets[f]);
        let a = at(0);
        let (mut j, mut best) = (1, f64::NEG_INFINITY);
        for r in 1..k - 1 {
            let (b, c) = (at(r), at(r + 1));
            let area = cross2(sub2(b, a), sub2(c, a));
            if area <= 0.0 {
                continue;
            }
            let m = (cross2(sub2(c, b), sub2(t, b))
                .min(cross2(sub2(a, c), sub2(t, c)))
                .min(cross2(sub2(b, a), sub2(t, a))))
                / area;
            if m > best {
                best = m;
                j = r;
            }
        }
        let (mut quad, mut margin) = ([0, j, j + 1, j + 1], f64::NEG_INFINITY);
        for r in 1..k {
            if r == j || r == j + 1 {
                continue;
            }
            let q = if r < j { [0, r, j, j + 1] } else { [0, j, j + 1, r] };
            let m = (0..4).map(|i| left_dist(at(q[i]), at(q[(i + 1) % 4]), t)).fold(f64::INFINITY, f64::min);
            if m > margin {
                margin = m;
                quad = q;
            }
        }
        (quad.map(|r| ((apex + r) % k) as u32), margin)
    }

    /// The precomputed support quadrilateral of facet `f` (loop positions); the identity for
    /// facets with at most four corners.
    pub(super) fn static_quad(&self, f: usize) -> [u32; 4] {
        let k = self.facet_corners(f).len();
        if k <= 4 {
            return [0, 1, 2, 3];
        }
        let apexes = k.min(QUAD_APEXES);
        let mut best = ([0, 1, 2, 3], f64::NEG_INFINITY);
        for i in 0..apexes {
            let (q, m) = self.quad_with_apex(f, i * k / apexes);
            if m > best.1 {
                best = (q, m);
            }
        }
        best.0
    }

    /// Feature id of the side from loop position `a` to `b` of facet `f` (a hull edge or a chord).
    fn side_id(&self, f: usize, a: u32, b: u32) -> PackedFeatureId {
        let cs = self.facet_corners(f);
        let k = cs.len() as u32;
        if b == (a + 1) % k {
            PackedFeatureId::edge(self.facet_edges(f)[a as usize])
        } else {
            let (u, w) = (cs[a as usize].min(cs[b as usize]) as u64, cs[a as usize].max(cs[b as usize]) as u64);
            let ne = self.edges.len() as u64;
            let code = ne + (u * self.points.len() as u64 + w) % (FEATURE_CODE_LIMIT - ne).max(1);
            PackedFeatureId::edge(code.min(FEATURE_CODE_LIMIT - 1) as u32)
        }
    }

    /// Writes facet `f` (or its reduced quadrilateral) as a polygonal feature; `v` is the support
    /// vertex (a corner of `f`) and `dir` the support direction.
    pub(super) fn write_face(&self, f: usize, v: u32, dir: Vector, out: &mut PolygonalFeature) {
        let cs = self.facet_corners(f);
        let k = cs.len();
        let mut pos = [0u32, 1, 2, 3];
        let n = if k <= 4 {
            k
        } else {
            pos = self.quads[f];
            if !pos.iter().any(|&i| cs[i as usize] == v) {
                let d = to64(dir);
                let depth = |c: u32| dot64(self.points[c as usize], &d);
                let quad_deepest = pos.iter().map(|&i| depth(cs[i as usize])).fold(f64::NEG_INFINITY, f64::max);
                if depth(v) - quad_deepest > self.reduce_tol * dot3(d, d).sqrt() {
                    let apex = cs.iter().position(|&c| c == v).unwrap_or(0);
                    pos = self.quad_with_apex(f, apex).0;
                }
            }
            4
        };
        for i in 0..4 {
            let p = pos[i.min(n - 1)];
            let c = cs[p as usize];
            out.vertices[i] = self.points[c as usize];
            out.vids[i] = PackedFeatureId::vertex(c);
            out.eids[i] = self.side_id(f, p, pos[(i.min(n - 1) + 1) % n]);
        }
        out.fid = PackedFeatureId::face(f as u32);
        out.num_vertices = n;
    }
}
