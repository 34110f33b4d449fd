//! Triangulating a simple planar polygon, with optional points inside it, by the constrained
//! Delaunay triangulation (CDT) of crate `spade`.
//!
//! The CDT of the polygon's vertices and the interior points, with the polygon's edges as
//! constraints, is the Delaunay triangulation as far as the constraints allow: every triangle's
//! circumcircle holds no point visible from inside it. The triangles inside the polygon are those
//! not reached from the unbounded face without crossing a constraint. For a simple polygon of n
//! vertices with k points strictly inside, Euler's formula gives exactly n + 2k − 2 of them;
//! anything else (two edges crossing, a vertex on another edge, a repeated vertex, an "interior"
//! point outside) is refused with [`NotSimple`] naming the first problem found.
//!
//! Coordinates are translated to the polygon's first vertex and divided by its extent before they
//! reach `spade`, whose predicates are exact but which accepts coordinates of magnitude 2⁻¹⁴² to
//! 2²⁰¹ only; the triangulation (indices) is that of the input.

use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

/// Why a polygon could not be triangulated as a simple polygon.
#[derive(Clone, Debug, PartialEq)]
pub struct NotSimple(pub String);

/// Triangulate the simple polygon `outline` (either orientation) and the points `interior`
/// strictly inside it (module docs). Returns triangles as indices into `outline` followed by
/// `interior`, each counter-clockwise in the (u, v) plane.
pub fn triangulate(outline: &[[f64; 2]], interior: &[[f64; 2]]) -> Result<Vec<[u32; 3]>, NotSimple> {
    let n = outline.len();
    if n < 3 {
        return Err(NotSimple(format!("{n} vertices: a polygon has at least three")));
    }
    let all: Vec<[f64; 2]> = outline.iter().chain(interior).copied().collect();
    if let Some(i) = all.iter().position(|p| !(p[0].is_finite() && p[1].is_finite())) {
        return Err(NotSimple(format!("point {i} has a non-finite coordinate")));
    }
    // Repeated points (exactly equal projections): the polygon touches itself there.
    let mut order: Vec<usize> = (0..all.len()).collect();
    order.sort_by(|&a, &b| all[a][0].total_cmp(&all[b][0]).then(all[a][1].total_cmp(&all[b][1])));
    if let Some(w) = order.windows(2).find(|w| all[w[0]] == all[w[1]]) {
        let (a, b) = (w[0].min(w[1]), w[0].max(w[1]));
        return Err(NotSimple(format!(
            "points {a} and {b} project onto the same point ({}, {}): the outline touches itself",
            all[a][0], all[a][1]
        )));
    }
    let o = outline[0];
    let extent = all.iter().map(|p| (p[0] - o[0]).abs().max((p[1] - o[1]).abs())).fold(0.0, f64::max);
    if !(extent > 0.0 && extent.is_finite()) {
        return Err(NotSimple("the polygon has no extent".into()));
    }
    let flush = |x: f64| if x.abs() < 1e-100 { 0.0 } else { x };
    let points: Vec<Point2<f64>> =
        all.iter().map(|p| Point2::new(flush((p[0] - o[0]) / extent), flush((p[1] - o[1]) / extent))).collect();
    let edges: Vec<[usize; 2]> = (0..n).map(|i| [i, (i + 1) % n]).collect();
    let mut conflict = None;
    let cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::try_bulk_load_cdt(points, edges, |e| {
        conflict.get_or_insert(e);
    })
    .map_err(|e| NotSimple(format!("coordinates the triangulation cannot take ({e:?})")))?;
    if let Some([a, b]) = conflict {
        return Err(NotSimple(format!("the edge from vertex {a} to vertex {b} crosses another edge")));
    }
    if cdt.num_vertices() != all.len() {
        return Err(NotSimple("repeated points".into()));
    }
    // Every outline edge is one constraint edge: none was split by a vertex lying on it.
    for i in 0..n {
        let (a, b) = (FixedVertexHandle::from_index(i), FixedVertexHandle::from_index((i + 1) % n));
        if !cdt.get_edge_from_neighbors(a, b).is_some_and(|e| e.is_constraint_edge()) {
            return Err(NotSimple(format!(
                "the edge from vertex {i} to vertex {} passes through another vertex",
                (i + 1) % n
            )));
        }
    }
    if cdt.num_constraints() != n {
        return Err(NotSimple(format!("{} constraint edges for {n} outline edges", cdt.num_constraints())));
    }
    let inside = inside_faces(&cdt);
    let mut triangles = Vec::with_capacity(inside.len());
    for face in cdt.inner_faces() {
        if !inside[face.fix().index()] {
            continue;
        }
        let [a, b, c] = face.vertices().map(|v| v.fix().index() as u32);
        let [pa, pb, pc] = [a, b, c].map(|i| all[i as usize]);
        let ccw = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0]) > 0.0;
        triangles.push(if ccw { [a, b, c] } else { [a, c, b] });
    }
    let expected = n + 2 * interior.len() - 2;
    if triangles.len() != expected {
        return Err(NotSimple(format!(
            "{} triangles inside where a simple polygon of {n} vertices with {} points inside has {expected} (a point lies outside, or the outline winds twice)",
            triangles.len(),
            interior.len()
        )));
    }
    Ok(triangles)
}

/// Inner faces (by index) not reachable from the unbounded face without crossing a constraint.
fn inside_faces(cdt: &ConstrainedDelaunayTriangulation<Point2<f64>>) -> Vec<bool> {
    let nf = cdt.all_faces().len();
    let mut outside = vec![false; nf];
    let mut stack: Vec<usize> = Vec::new();
    let faces: Vec<_> = cdt.inner_faces().collect();
    let mut by_index = vec![None; nf];
    for (k, f) in faces.iter().enumerate() {
        by_index[f.fix().index()] = Some(k);
    }
    // Faces across a non-constraint edge from the unbounded face are outside.
    for f in &faces {
        let i = f.fix().index();
        let open = f.adjacent_edges().iter().any(|e| !e.is_constraint_edge() && e.rev().face().is_outer());
        if open && !outside[i] {
            outside[i] = true;
            stack.push(i);
        }
    }
    while let Some(i) = stack.pop() {
        let Some(k) = by_index[i] else { continue };
        for e in faces[k].adjacent_edges() {
            if e.is_constraint_edge() {
                continue;
            }
            if let Some(g) = e.rev().face().as_inner() {
                let j = g.fix().index();
                if !outside[j] {
                    outside[j] = true;
                    stack.push(j);
                }
            }
        }
    }
    let mut inside = vec![false; nf];
    for f in &faces {
        let i = f.fix().index();
        inside[i] = !outside[i];
    }
    inside
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(p: &[[f64; 2]], t: &[[u32; 3]]) -> f64 {
        t.iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| p[i as usize]);
                ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / 2.0
            })
            .sum()
    }

    #[test]
    fn an_l_shape_with_inner_points_is_covered_exactly() {
        // Clockwise L of area 3, with two points inside: 6 + 4 − 2 = 8 triangles, all
        // counter-clockwise, covering the area exactly.
        let outline = [[0.0, 0.0], [0.0, 2.0], [1.0, 2.0], [1.0, 1.0], [2.0, 1.0], [2.0, 0.0]];
        let interior = [[0.5, 0.5], [0.5, 1.5]];
        let t = triangulate(&outline, &interior).unwrap();
        assert_eq!(t.len(), 8);
        let pts: Vec<[f64; 2]> = outline.iter().chain(&interior).copied().collect();
        assert!((area(&pts, &t) - 3.0).abs() < 1e-12);
        // The reflex corner (1, 1) is not cut across: no triangle joins (0, 2)… to (2, 0)… directly.
        assert!(!t.iter().any(|t| t.contains(&1) && t.contains(&5)));
    }

    #[test]
    fn crossing_touching_and_outside_points_are_refused() {
        let bow = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(triangulate(&bow, &[]).unwrap_err().0.contains("crosses"), "bow tie");
        let touching = [[0.0, 0.0], [2.0, 0.0], [1.0, 1.0], [2.0, 2.0], [0.0, 2.0], [1.0, 0.0]];
        assert!(triangulate(&touching, &[]).is_err(), "a vertex on another edge");
        let repeated = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [1.0, 0.0]];
        assert!(triangulate(&repeated, &[]).unwrap_err().0.contains("same point"));
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert!(triangulate(&square, &[[2.0, 0.5]]).unwrap_err().0.contains("outside"));
        assert_eq!(triangulate(&square, &[[0.5, 0.5]]).unwrap().len(), 4);
    }
}
