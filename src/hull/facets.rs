//! Hull triangles grouped into planar facets (within the coplanarity tolerance δ), each facet's
//! boundary loop, and the corners: hull points where at least three facets meet.

use super::orient;
use super::triangles::HullTriangles;
use crate::{Error, Point3, Result, Vec3};

/// Group hull triangles into planar facets. Adjacent triangles are candidates when the
/// opposite vertex of one lies within δ of the other's plane (either way round, so that a sliver
/// — three nearly collinear hull points — joins its neighbour); candidates are merged
/// most-coplanar first, and a merge is accepted only if every vertex of one group lies within δ
/// of the plane of the other group's largest triangle (its anchor; the merged group keeps the
/// larger anchor). So a facet is planar within δ as a whole, never a chain of slightly bent
/// pairs. Returns the facet id of every triangle (ids in order of first triangle).
pub(super) fn merge_coplanar(points: &[Point3], hull: &HullTriangles, tri_n: &[Vec3], delta: f64) -> Vec<u32> {
    let tris = &hull.triangles;
    let nt = tris.len();
    let height = |t: usize, d: u32| {
        let [a, b, c] = tris[t].map(|i| &points[i as usize]);
        let n = tri_n[t].norm();
        if n > 0.0 {
            orient(a, b, c, &points[d as usize]).abs() / n
        } else {
            f64::INFINITY
        }
    };
    let mut candidates = Vec::new();
    for t in 0..nt {
        for e in 0..3 {
            let u = hull.neighbours[t][e] as usize;
            if u < t {
                continue;
            }
            let opp_u = *tris[u].iter().find(|v| !tris[t].contains(v)).expect("distinct triangles");
            let h = height(t, opp_u).min(height(u, tris[t][(e + 2) % 3]));
            if h <= delta {
                candidates.push((h, t as u32, u as u32));
            }
        }
    }
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
    let mut dsu = Dsu((0..nt as u32).collect());
    let mut members: Vec<Vec<u32>> = (0..nt as u32).map(|t| vec![t]).collect();
    let anchor: Vec<u32> = (0..nt as u32).collect();
    let area = |t: u32| tri_n[t as usize].norm();
    for (_, t, u) in candidates {
        let (rt, ru) = (dsu.find(t), dsu.find(u));
        if rt == ru {
            continue;
        }
        let (keep, other) = if area(anchor[rt as usize]) >= area(anchor[ru as usize]) { (rt, ru) } else { (ru, rt) };
        let at = anchor[keep as usize] as usize;
        let a = points[tris[at][0] as usize];
        let n = tri_n[at].normalize();
        let planar = members[other as usize]
            .iter()
            .all(|&m| tris[m as usize].iter().all(|&v| n.dot(&(points[v as usize] - a)).abs() <= delta));
        if planar {
            dsu.0[other as usize] = keep;
            let moved = std::mem::take(&mut members[other as usize]);
            members[keep as usize].extend(moved);
        }
    }
    let mut facet_of = vec![u32::MAX; nt];
    let mut root_id = vec![u32::MAX; nt];
    let mut nf = 0u32;
    for (t, slot) in facet_of.iter_mut().enumerate() {
        let r = dsu.find(t as u32) as usize;
        if root_id[r] == u32::MAX {
            root_id[r] = nf;
            nf += 1;
        }
        *slot = root_id[r];
    }
    facet_of
}

/// Chain a facet's boundary half-edges into its counter-clockwise loop of hull points.
pub(super) fn boundary_loop(boundary: &[(u32, u32)], next_of: &mut [u32]) -> Result<Vec<u32>> {
    for &(a, b) in boundary {
        next_of[a as usize] = b;
    }
    let start = boundary[0].0;
    let mut loop_pts = vec![start];
    let mut cur = next_of[start as usize];
    while cur != start {
        loop_pts.push(cur);
        cur = next_of[cur as usize];
        if loop_pts.len() > boundary.len() {
            return Err(Error::degenerate(
                "merging nearly coplanar hull triangles gave a facet whose boundary is not a simple loop: the coplanar tolerance is too large for this shape (use a smaller coplanar tolerance)",
            ));
        }
    }
    if loop_pts.len() != boundary.len() {
        return Err(Error::degenerate(
            "merging nearly coplanar hull triangles gave a facet with a hole or a pinched boundary: the coplanar tolerance is too large for this shape (use a smaller coplanar tolerance)",
        ));
    }
    Ok(loop_pts)
}

/// Corners: hull points where three or more facets meet. A point with two facets lies on their
/// common edge and one with a single facet inside it; both are dropped. Should a facet then have
/// fewer than three corners (possible only when the tolerance merged nearly coplanar triangles,
/// bending the facets' common boundary), its two-facet points are kept as corners too, so every
/// facet stays a polygon.
pub(super) fn corners(np: usize, tris: &[[u32; 3]], facet_of: &[u32], loops: &[Vec<u32>]) -> Vec<bool> {
    let mut first_facet = vec![u32::MAX; np];
    let mut second_facet = vec![u32::MAX; np];
    let mut is_corner = vec![false; np];
    for (t, tri) in tris.iter().enumerate() {
        let f = facet_of[t];
        for &v in tri {
            let v = v as usize;
            if first_facet[v] == u32::MAX || first_facet[v] == f {
                first_facet[v] = f;
            } else if second_facet[v] == u32::MAX || second_facet[v] == f {
                second_facet[v] = f;
            } else {
                is_corner[v] = true;
            }
        }
    }
    for l in loops {
        if l.iter().filter(|&&v| is_corner[v as usize]).count() < 3 {
            l.iter().for_each(|&v| is_corner[v as usize] = true);
        }
    }
    is_corner
}

struct Dsu(Vec<u32>);
impl Dsu {
    fn find(&mut self, mut x: u32) -> u32 {
        while self.0[x as usize] != x {
            let p = self.0[self.0[x as usize] as usize];
            self.0[x as usize] = p;
            x = p;
        }
        x
    }
}
