//! Self-intersections of a triangle mesh, decided with exact predicates.
//!
//! Two triangles *cross* when their closed point sets meet anywhere except where the mesh joins
//! them: triangles sharing an edge may meet only along that edge (they cross only when they are
//! coplanar and fold onto each other), triangles sharing one vertex only at that vertex, and
//! triangles sharing nothing not at all (touching counts: a vertex lying on another triangle is a
//! self-contact of the surface).
//!
//! Every decision is a sign of Shewchuk's exact `orient3d` / `orient2d` (crate `robust`), so the
//! answer does not depend on rounding. The reduction used: two triangles meet iff an edge of one
//! meets the other (closed sets). For triangles sharing a vertex `a`, the set meets beyond `a` iff
//! the edge of one opposite `a` meets the other triangle. Segment–triangle tests use the signs of
//! the segment's ends against the triangle's plane and of the three edges against the segment's
//! line; coplanar configurations are projected onto the coordinate plane where the triangle's
//! projection is largest (exact: the projection is an affine bijection of the plane).
//!
//! Zero-area triangles (three distinct collinear vertices) are skipped: their points lie on their
//! longest edge, which a neighbouring triangle of the closed surface carries as well.
//!
//! Candidate pairs come from a uniform grid over the triangles' bounding boxes (cell size twice the
//! mean box extent); a pair is tested only in the cell that holds the lower corner of the
//! intersection of their boxes, so each pair once. Triangles spanning more than
//! [`MAX_CELLS_PER_TRIANGLE`] cells are tested against every other triangle by box instead.
//! Cells are processed in parallel (rayon) and the result is the same for any thread count.

use crate::Point3;
use rayon::prelude::*;
use robust::{orient2d, orient3d, Coord, Coord3D};

/// A triangle that covers more grid cells than this is tested by bounding box against all others.
pub const MAX_CELLS_PER_TRIANGLE: usize = 64;

/// The deepest crossing of a mesh: two crossing triangles (indices into the triangle list,
/// `first < second`), an approximate point where they meet, how deep they cross ([`depth`]), and
/// how many crossing pairs the mesh has in all.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossing {
    /// Index of the first crossing triangle.
    pub first: usize,
    /// Index of the second crossing triangle (`first < second`).
    pub second: usize,
    /// Approximate point where the two triangles meet.
    pub near: Point3,
    /// How deep the two triangles cross.
    pub depth: f64,
    /// Number of crossing triangle pairs in the whole mesh.
    pub pairs: usize,
}

/// How deep two crossing triangles pass through each other: for each triangle, the other's
/// vertices are measured from its plane and the smaller of the extents on the two sides taken
/// (how far the other reaches through it); `depth` is the larger of the two. A hair-thin overlap
/// of a decimated or stitched scan has a depth of a fraction of a facet; a spike of a vertex
/// pulled through the body, the length of the spike beyond the wall it pierces.
pub fn depth(pi: &[Point3; 3], pj: &[Point3; 3]) -> f64 {
    let through = |t: &[Point3; 3], u: &[Point3; 3]| {
        let n = (t[1] - t[0]).cross(&(t[2] - t[0]));
        let n = n / n.norm();
        let d = u.map(|x| n.dot(&(x - t[0])));
        let (lo, hi) = (d.iter().copied().fold(0.0, f64::min), d.iter().copied().fold(0.0, f64::max));
        (-lo).min(hi)
    };
    through(pi, pj).max(through(pj, pi))
}

#[inline]
fn o3(a: &Point3, b: &Point3, c: &Point3, d: &Point3) -> f64 {
    let c3 = |p: &Point3| Coord3D { x: p.x, y: p.y, z: p.z };
    orient3d(c3(a), c3(b), c3(c), c3(d))
}

/// 2-D coordinates after dropping axis `k`.
#[inline]
fn proj(p: &Point3, k: usize) -> Coord<f64> {
    match k {
        0 => Coord { x: p.y, y: p.z },
        1 => Coord { x: p.z, y: p.x },
        _ => Coord { x: p.x, y: p.y },
    }
}

#[inline]
fn o2(a: &Point3, b: &Point3, c: &Point3, k: usize) -> f64 {
    orient2d(proj(a, k), proj(b, k), proj(c, k))
}

/// The axis to drop for coplanar tests with triangle `t`: the one with the largest projected
/// area; `None` when all three projections vanish (collinear vertices).
fn drop_axis(t: &[Point3; 3]) -> Option<usize> {
    let areas = [0, 1, 2].map(|k| o2(&t[0], &t[1], &t[2], k).abs());
    let k = (0..3).max_by(|&i, &j| areas[i].total_cmp(&areas[j]))?;
    (areas[k] > 0.0).then_some(k)
}

/// Is `r` (collinear with p, q) on the closed segment pq? Exact: coordinate comparisons.
fn on_segment(p: &Point3, q: &Point3, r: &Point3) -> bool {
    (0..3).all(|i| p[i].min(q[i]) <= r[i] && r[i] <= p[i].max(q[i]))
}

/// Closed 2-D segments pq and rs (in projection `k`) meet; an approximate common point.
fn segments_meet(p: &Point3, q: &Point3, r: &Point3, s: &Point3, k: usize) -> Option<Point3> {
    let (d1, d2) = (o2(p, q, r, k), o2(p, q, s, k));
    let (d3, d4) = (o2(r, s, p, k), o2(r, s, q, k));
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        let t = d3 / (d3 - d4);
        return Some(p + (q - p) * t);
    }
    // Touching or collinear overlaps: an endpoint on the other segment.
    for (x, y, z, d) in [(p, q, r, d1), (p, q, s, d2), (r, s, p, d3), (r, s, q, d4)] {
        if d == 0.0 && on_segment(x, y, z) {
            return Some(*z);
        }
    }
    None
}

/// Closed segment pq meets closed triangle t (non-degenerate, drop axis `k`) when all are coplanar.
fn coplanar_segment_triangle(p: &Point3, q: &Point3, t: &[Point3; 3], k: usize) -> Option<Point3> {
    let sigma = o2(&t[0], &t[1], &t[2], k).signum();
    let inside = |x: &Point3| (0..3).all(|i| o2(&t[i], &t[(i + 1) % 3], x, k) * sigma >= 0.0);
    if inside(p) {
        return Some(*p);
    }
    if inside(q) {
        return Some(*q);
    }
    (0..3).find_map(|i| segments_meet(p, q, &t[i], &t[(i + 1) % 3], k))
}

/// Closed segment pq meets closed non-degenerate triangle t; an approximate common point.
fn segment_triangle(p: &Point3, q: &Point3, t: &[Point3; 3], k: usize) -> Option<Point3> {
    let (op, oq) = (o3(&t[0], &t[1], &t[2], p), o3(&t[0], &t[1], &t[2], q));
    if (op > 0.0 && oq > 0.0) || (op < 0.0 && oq < 0.0) {
        return None;
    }
    if op == 0.0 && oq == 0.0 {
        return coplanar_segment_triangle(p, q, t, k);
    }
    let s = [o3(p, q, &t[0], &t[1]), o3(p, q, &t[1], &t[2]), o3(p, q, &t[2], &t[0])];
    if s.iter().any(|&x| x > 0.0) && s.iter().any(|&x| x < 0.0) {
        return None;
    }
    let u = op / (op - oq);
    Some(p + (q - p) * u)
}

/// Do triangles `i` and `j` (indices `ti`, `tj`, points `pi`, `pj`, drop axes `ki`, `kj`) cross?
fn crossing(ti: &[u32; 3], tj: &[u32; 3], pi: &[Point3; 3], pj: &[Point3; 3], ki: usize, kj: usize) -> Option<Point3> {
    let mut shared = [(0usize, 0usize); 3];
    let mut n_shared = 0;
    for (a, va) in ti.iter().enumerate() {
        if let Some(b) = tj.iter().position(|vb| vb == va) {
            shared[n_shared] = (a, b);
            n_shared += 1;
        }
    }
    match &shared[..n_shared] {
        [] => {
            // Quick rejection: one triangle strictly on one side of the other's plane.
            let side = |t: &[Point3; 3], u: &[Point3; 3]| {
                let o = u.map(|x| o3(&t[0], &t[1], &t[2], &x));
                o.iter().all(|&x| x > 0.0) || o.iter().all(|&x| x < 0.0)
            };
            if side(pi, pj) || side(pj, pi) {
                return None;
            }
            (0..3)
                .find_map(|e| segment_triangle(&pi[e], &pi[(e + 1) % 3], pj, kj))
                .or_else(|| (0..3).find_map(|e| segment_triangle(&pj[e], &pj[(e + 1) % 3], pi, ki)))
        }
        &[(a, b)] => {
            // The edge opposite the shared vertex, of each triangle, against the other triangle.
            let (b1, c1) = (pi[(a + 1) % 3], pi[(a + 2) % 3]);
            let (b2, c2) = (pj[(b + 1) % 3], pj[(b + 2) % 3]);
            segment_triangle(&b1, &c1, pj, kj).or_else(|| segment_triangle(&b2, &c2, pi, ki))
        }
        &[(a0, _), (a1, _)] => {
            // Shared edge: they meet beyond it only if coplanar with both apexes on one side.
            let apex_i = pi[3 - a0 - a1];
            let bj = (0..3).find(|&m| tj[m] != ti[a0] && tj[m] != ti[a1])?;
            let apex_j = pj[bj];
            let (x, y) = (pi[a0], pi[a1]);
            if o3(&x, &y, &apex_i, &apex_j) != 0.0 {
                return None;
            }
            (o2(&x, &y, &apex_i, ki) * o2(&x, &y, &apex_j, ki) > 0.0)
                .then(|| Point3::from((apex_i.coords + apex_j.coords) / 2.0))
        }
        _ => None, // same three vertices: duplicates are refused before this test
    }
}

/// Find crossing triangles of a mesh (see the module docs); `None` if the surface is embedded.
/// The reported pair is the deepest ([`depth`]; ties: the lexicographically smallest pair).
pub fn find_self_intersection(vertices: &[Point3], triangles: &[[u32; 3]]) -> Option<Crossing> {
    find_crossing_with(vertices, triangles, 0)
}

/// As [`find_self_intersection`], counting only the pairs of which at least one triangle has an
/// index ≥ `first_new`: where a patch appended to a surface (triangles `first_new..`) crosses
/// the surface or itself, the surface's own crossings aside. `first_new` = 0 is
/// [`find_self_intersection`].
pub fn find_crossing_with(vertices: &[Point3], triangles: &[[u32; 3]], first_new: usize) -> Option<Crossing> {
    find_counted(vertices, triangles, &|_, j| j >= first_new)
}

/// The deepest crossing among the pairs (i, j), i < j, for which `count(i, j)` holds.
fn find_counted(
    vertices: &[Point3],
    triangles: &[[u32; 3]],
    count: &(dyn Fn(usize, usize) -> bool + Sync),
) -> Option<Crossing> {
    let nt = triangles.len();
    let pts: Vec<[Point3; 3]> = triangles.iter().map(|t| t.map(|i| vertices[i as usize])).collect();
    let axis: Vec<Option<usize>> = pts.par_iter().map(drop_axis).collect();
    let boxes: Vec<(Point3, Point3)> =
        pts.iter().map(|p| (p[0].inf(&p[1]).inf(&p[2]), p[0].sup(&p[1]).sup(&p[2]))).collect();
    let live: Vec<usize> = (0..nt).filter(|&t| axis[t].is_some()).collect();
    if live.len() < 2 {
        return None;
    }
    let (glo, ghi) =
        live.iter().fold((boxes[live[0]].0, boxes[live[0]].1), |(l, h), &t| (l.inf(&boxes[t].0), h.sup(&boxes[t].1)));
    let mean_extent = live.iter().map(|&t| (boxes[t].1 - boxes[t].0).amax()).sum::<f64>() / live.len() as f64;
    let span = (ghi - glo).amax();
    // Cell size: twice the mean box extent, but at most 2^20 cells per axis.
    let h = (2.0 * mean_extent).max(span / (1u64 << 20) as f64);
    if !(h > 0.0 && h.is_finite()) {
        return None;
    }
    let cells_per_axis = ((span / h).floor() as u64 + 1).min(1 << 20);
    let cell = |x: f64, i: usize| (((x - glo[i]) / h).floor().max(0.0) as u64).min(cells_per_axis - 1);
    let cell3 = |p: &Point3| [cell(p.x, 0), cell(p.y, 1), cell(p.z, 2)];
    let key = |c: [u64; 3]| (c[0] << 42) | (c[1] << 21) | c[2];
    let ranges: Vec<([u64; 3], [u64; 3])> = boxes.iter().map(|(l, h)| (cell3(l), cell3(h))).collect();
    let n_cells = |t: usize| {
        let (l, h) = ranges[t];
        (0..3).map(|i| (h[i] - l[i] + 1) as usize).product::<usize>()
    };
    let (big, small): (Vec<usize>, Vec<usize>) = live.iter().partition(|&&t| n_cells(t) > MAX_CELLS_PER_TRIANGLE);
    let mut entries: Vec<(u64, u32)> = small
        .par_iter()
        .flat_map_iter(|&t| {
            let (l, h) = ranges[t];
            (l[0]..=h[0]).flat_map(move |x| {
                (l[1]..=h[1]).flat_map(move |y| (l[2]..=h[2]).map(move |z| (key([x, y, z]), t as u32)))
            })
        })
        .collect();
    entries.par_sort_unstable();
    let mut starts: Vec<usize> = (0..entries.len()).filter(|&k| k == 0 || entries[k].0 != entries[k - 1].0).collect();
    starts.push(entries.len());
    let overlap = |i: usize, j: usize| {
        let (a, b) = (&boxes[i], &boxes[j]);
        (0..3).all(|k| a.0[k] <= b.1[k] && b.0[k] <= a.1[k])
    };
    let test = |i: usize, j: usize| -> Option<(usize, usize, Point3)> {
        let (i, j) = (i.min(j), i.max(j));
        if !count(i, j) {
            return None;
        }
        let (ki, kj) = (axis[i]?, axis[j]?);
        crossing(&triangles[i], &triangles[j], &pts[i], &pts[j], ki, kj).map(|p| (i, j, p))
    };
    let in_cells: Vec<(usize, usize, Point3)> = starts
        .par_windows(2)
        .flat_map_iter(|w| {
            let group = &entries[w[0]..w[1]];
            let here = group[0].0;
            let mut found = Vec::new();
            for (a, &(_, i)) in group.iter().enumerate() {
                for &(_, j) in &group[a + 1..] {
                    let (i, j) = (i as usize, j as usize);
                    if !overlap(i, j) {
                        continue;
                    }
                    let corner = boxes[i].0.sup(&boxes[j].0);
                    if key(cell3(&corner)) != here {
                        continue;
                    }
                    found.extend(test(i, j));
                }
            }
            found
        })
        .collect();
    let is_big = {
        let mut v = vec![false; nt];
        big.iter().for_each(|&t| v[t] = true);
        v
    };
    let is_big = &is_big;
    let with_big: Vec<(usize, usize, Point3)> = big
        .par_iter()
        .flat_map_iter(|&b| {
            live.iter()
                .filter(move |&&t| t != b && !(is_big[t] && t < b) && overlap(b, t))
                .filter_map(move |&t| test(b, t))
                .collect::<Vec<_>>()
        })
        .collect();
    let pairs = in_cells.len() + with_big.len();
    in_cells
        .into_iter()
        .chain(with_big)
        .map(|(i, j, near)| (i, j, near, depth(&pts[i], &pts[j])))
        .max_by(|x, y| x.3.total_cmp(&y.3).then((y.0, y.1).cmp(&(x.0, x.1))))
        .map(|(first, second, near, depth)| Crossing { first, second, near, depth, pairs })
}

/// Axis-aligned bounding box of every triangle.
pub fn triangle_boxes(vertices: &[Point3], triangles: &[[u32; 3]]) -> Vec<(Point3, Point3)> {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            (a.inf(&b).inf(&c), a.sup(&b).sup(&c))
        })
        .collect()
}

/// Where a patch crosses a surface it is attached to, or itself: [`find_crossing_with`] on the
/// patch and the surface triangles whose boxes (`surface_boxes`, [`triangle_boxes`] of `surface`)
/// meet the patch's bounding box, the only ones it can reach. Only pairs of a surface triangle
/// and a patch triangle are counted: the patches closing an open scan are height fields over a
/// plane triangulation (their projections on the plane do not overlap), which cannot cross
/// themselves. In the result, triangle `i < surface.len()` is surface triangle `i`, and
/// `surface.len() + j` is patch triangle `j`.
pub fn find_patch_crossing(
    vertices: &[Point3],
    surface: &[[u32; 3]],
    surface_boxes: &[(Point3, Point3)],
    patch: &[[u32; 3]],
) -> Option<Crossing> {
    let boxes = triangle_boxes(vertices, patch);
    let (lo, hi) = boxes.iter().copied().reduce(|(l, h), (a, b)| (l.inf(&a), h.sup(&b)))?;
    let near: Vec<usize> = (0..surface.len().min(surface_boxes.len()))
        .filter(|&i| {
            let (a, b) = &surface_boxes[i];
            (0..3).all(|k| a[k] <= hi[k] && lo[k] <= b[k])
        })
        .collect();
    let triangles: Vec<[u32; 3]> = near.iter().map(|&i| surface[i]).chain(patch.iter().copied()).collect();
    let name = |i: usize| if i < near.len() { near[i] } else { surface.len() + i - near.len() };
    find_crossing_with(vertices, &triangles, near.len()).map(|c| Crossing {
        first: name(c.first),
        second: name(c.second),
        ..c
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64, z: f64) -> Point3 {
        Point3::new(x, y, z)
    }

    #[test]
    fn piercing_triangles_cross_and_separated_ones_do_not() {
        let v = vec![
            p(0.0, 0.0, 0.0),
            p(2.0, 0.0, 0.0),
            p(0.0, 2.0, 0.0),
            p(0.5, 0.5, -1.0),
            p(0.5, 0.5, 1.0),
            p(3.0, 3.0, 0.5),
            p(0.5, 0.5, 2.0),
        ];
        let hit = find_self_intersection(&v, &[[0, 1, 2], [3, 4, 5]]).expect("crossing");
        assert_eq!((hit.first, hit.second, hit.pairs), (0, 1, 1));
        // They meet along the segment (0.5, 0.5, 0)–(1, 1, 0).
        let n = hit.near;
        assert!(n.z.abs() < 1e-12 && (n.x - n.y).abs() < 1e-12 && (0.5..=1.0).contains(&n.x), "{n:?}");
        assert!(find_self_intersection(&v, &[[0, 1, 2], [4, 6, 5]]).is_none());
    }

    #[test]
    fn shared_vertex_and_edge_neighbours_only_cross_when_they_really_do() {
        let v = vec![
            p(0.0, 0.0, 0.0),
            p(1.0, 0.0, 0.0),
            p(0.0, 1.0, 0.0),
            p(0.0, 0.0, 1.0),
            p(0.3, 0.3, -1.0),
            p(0.3, 0.3, 1.0),
            p(0.5, -0.5, 0.0),
        ];
        // Tetrahedron faces sharing edges/vertices: fine.
        assert!(find_self_intersection(&v, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]).is_none());
        // Sharing vertex 0, but the second passes through the first's interior.
        assert!(find_self_intersection(&v, &[[0, 1, 2], [0, 4, 5]]).is_some());
        // Sharing edge 0–1, coplanar, folded onto the same side: crossing; on the other side: not.
        assert!(find_self_intersection(&v, &[[0, 1, 2], [1, 0, 5]]).is_none());
        assert!(find_self_intersection(&v, &[[0, 1, 2], [0, 1, 6]]).is_none());
        let fold = vec![p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0), p(0.5, 0.4, 0.0)];
        assert!(find_self_intersection(&fold, &[[0, 1, 2], [1, 0, 3]]).is_some());
    }
}
