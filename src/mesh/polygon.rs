//! Triangulating a planar region bounded by simple polygons, with optional points inside it, by
//! the constrained Delaunay triangulation (CDT) of crate `spade`.
//!
//! The region is bounded by closed outlines that neither cross nor touch themselves or each
//! other, and lies on the left of each directed outline edge: counter-clockwise outer boundaries,
//! clockwise holes (several disjoint pieces are allowed). The CDT of the outline vertices and the
//! interior points, with the outline edges as constraints, is the Delaunay triangulation as far as
//! the constraints allow: no triangle's circumcircle holds a point visible from inside it. The
//! region's triangles are those reached from the triangle on the left of an outline edge without
//! crossing a constraint. Refused with [`NotSimple`], naming the first problem: two edges crossing,
//! a vertex on another edge, two points projecting onto one, an outline with its region on the
//! right of an edge or reaching the unbounded face (it winds the other way), an interior point
//! outside the region.
//!
//! Coordinates are translated to the first outline's first vertex and divided by the extent
//! before they reach `spade`, whose predicates are exact but which accepts coordinates of
//! magnitude 2⁻¹⁴² to 2²⁰¹ only; the triangulation (indices) is that of the input.

use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

/// Why a region could not be triangulated.
#[derive(Clone, Debug, PartialEq)]
pub struct NotSimple(pub String);

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// Triangulate the region bounded by `outlines` (module docs) with the points `interior`
/// strictly inside it. Returns triangles as indices into the outlines' vertices, one outline after
/// the other, followed by `interior`; each counter-clockwise in the (u, v) plane.
pub fn triangulate(outlines: &[Vec<[f64; 2]>], interior: &[[f64; 2]]) -> Result<Vec<[u32; 3]>, NotSimple> {
    let mut edges: Vec<[usize; 2]> = Vec::new();
    let mut at = 0;
    for o in outlines {
        if o.len() < 3 {
            return Err(NotSimple(format!("an outline of {} vertices: a polygon has at least three", o.len())));
        }
        edges.extend((0..o.len()).map(|i| [at + i, at + (i + 1) % o.len()]));
        at += o.len();
    }
    let all: Vec<[f64; 2]> = outlines.iter().flatten().chain(interior).copied().collect();
    if all.is_empty() {
        return Err(NotSimple("no outline".into()));
    }
    if let Some(i) = all.iter().position(|p| !(p[0].is_finite() && p[1].is_finite())) {
        return Err(NotSimple(format!("point {i} has a non-finite coordinate")));
    }
    // Repeated points (exactly equal projections): an outline touches itself or another there.
    let mut order: Vec<usize> = (0..all.len()).collect();
    order.sort_by(|&a, &b| all[a][0].total_cmp(&all[b][0]).then(all[a][1].total_cmp(&all[b][1])));
    if let Some(w) = order.windows(2).find(|w| all[w[0]] == all[w[1]]) {
        let (a, b) = (w[0].min(w[1]), w[0].max(w[1]));
        return Err(NotSimple(format!(
            "points {a} and {b} project onto the same point ({}, {}): the outline touches itself",
            all[a][0], all[a][1]
        )));
    }
    let o = all[0];
    let extent = all.iter().map(|p| (p[0] - o[0]).abs().max((p[1] - o[1]).abs())).fold(0.0, f64::max);
    if !(extent > 0.0 && extent.is_finite()) {
        return Err(NotSimple("the outline has no extent".into()));
    }
    let flush = |x: f64| if x.abs() < 1e-100 { 0.0 } else { x };
    let points: Vec<Point2<f64>> =
        all.iter().map(|p| Point2::new(flush((p[0] - o[0]) / extent), flush((p[1] - o[1]) / extent))).collect();
    let mut conflict = None;
    let cdt = Cdt::try_bulk_load_cdt(points, edges.clone(), |e| {
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
    for &[a, b] in &edges {
        let (ha, hb) = (FixedVertexHandle::from_index(a), FixedVertexHandle::from_index(b));
        if !cdt.get_edge_from_neighbors(ha, hb).is_some_and(|e| e.is_constraint_edge()) {
            return Err(NotSimple(format!("the edge from vertex {a} to vertex {b} passes through another vertex")));
        }
    }
    if cdt.num_constraints() != edges.len() {
        return Err(NotSimple(format!("{} constraint edges for {} outline edges", cdt.num_constraints(), edges.len())));
    }
    let inside = region(&cdt, &edges)?;
    let mut triangles = Vec::new();
    for face in cdt.inner_faces() {
        if !inside[face.fix().index()] {
            continue;
        }
        let [a, b, c] = face.vertices().map(|v| v.fix().index() as u32);
        let [pa, pb, pc] = [a, b, c].map(|i| all[i as usize]);
        let ccw = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0]) > 0.0;
        triangles.push(if ccw { [a, b, c] } else { [a, c, b] });
    }
    // Interior points: only region triangles around them.
    for v in cdt.vertices().skip(at) {
        if v.out_edges().any(|e| e.face().as_inner().is_none_or(|f| !inside[f.fix().index()])) {
            return Err(NotSimple(format!("interior point {} lies outside the region", v.fix().index() - at)));
        }
    }
    Ok(triangles)
}

/// The faces of the region: flooded from the face on the left of every outline edge, never
/// across a constraint; refused if it reaches the unbounded face or the right of an outline edge.
fn region(cdt: &Cdt, edges: &[[usize; 2]]) -> Result<Vec<bool>, NotSimple> {
    let mut inside = vec![false; cdt.all_faces().len()];
    let mut stack = Vec::new();
    let wrong = |a: usize, b: usize| {
        NotSimple(format!("the outline winds the other way at the edge from vertex {a} to vertex {b}"))
    };
    for &[a, b] in edges {
        let e = cdt
            .get_edge_from_neighbors(FixedVertexHandle::from_index(a), FixedVertexHandle::from_index(b))
            .ok_or_else(|| wrong(a, b))?;
        let f = e.face().as_inner().ok_or_else(|| wrong(a, b))?;
        if !inside[f.fix().index()] {
            inside[f.fix().index()] = true;
            stack.push(f);
        }
    }
    while let Some(f) = stack.pop() {
        for e in f.adjacent_edges() {
            if e.is_constraint_edge() {
                continue;
            }
            let Some(g) = e.rev().face().as_inner() else {
                return Err(NotSimple("the region reaches the unbounded face: an outline winds the other way".into()));
            };
            if !inside[g.fix().index()] {
                inside[g.fix().index()] = true;
                stack.push(g);
            }
        }
    }
    for &[a, b] in edges {
        let e = cdt.get_edge_from_neighbors(FixedVertexHandle::from_index(a), FixedVertexHandle::from_index(b));
        if e.and_then(|e| e.rev().face().as_inner()).is_some_and(|f| inside[f.fix().index()]) {
            return Err(wrong(a, b));
        }
    }
    Ok(inside)
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
        // Counter-clockwise L of area 3, with two points inside: 6 + 4 − 2 = 8 triangles, all
        // counter-clockwise, covering the area exactly.
        let outline = vec![[2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0], [0.0, 0.0]];
        let interior = [[0.5, 0.5], [0.5, 1.5]];
        let t = triangulate(std::slice::from_ref(&outline), &interior).unwrap();
        assert_eq!(t.len(), 8);
        let pts: Vec<[f64; 2]> = outline.iter().chain(&interior).copied().collect();
        assert!((area(&pts, &t) - 3.0).abs() < 1e-12);
        // The reflex corner (1, 1) is not cut across: no triangle joins (1, 2) to (2, 0).
        assert!(!t.iter().any(|t| t.contains(&0) && t.contains(&3)));
        // Clockwise, the same outline bounds the outside: refused.
        let cw: Vec<[f64; 2]> = outline.iter().rev().copied().collect();
        assert!(triangulate(&[cw], &[]).unwrap_err().0.contains("other way"));
    }

    #[test]
    fn a_square_with_a_square_hole_and_a_separate_triangle() {
        // Outer 4 × 4 counter-clockwise, hole 2 × 2 clockwise, and a triangle beside: area 12.5.
        let outer = vec![[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]];
        let hole = vec![[1.0, 1.0], [1.0, 3.0], [3.0, 3.0], [3.0, 1.0]];
        let tri = vec![[5.0, 0.0], [6.0, 0.0], [5.0, 1.0]];
        let t = triangulate(&[outer.clone(), hole.clone(), tri.clone()], &[[0.5, 2.0]]).unwrap();
        let pts: Vec<[f64; 2]> = outer.iter().chain(&hole).chain(&tri).chain(&[[0.5, 2.0]]).copied().collect();
        assert!((area(&pts, &t) - 12.5).abs() < 1e-12, "{}", area(&pts, &t));
        // Euler: 11 outline vertices, 1 point inside, 2 pieces, 1 hole: 11 + 2 − 4 + 2 = 11.
        assert_eq!(t.len(), 11);
        assert!(triangulate(&[outer, hole], &[[2.0, 2.0]]).unwrap_err().0.contains("outside"));
    }

    #[test]
    fn crossing_touching_and_outside_points_are_refused() {
        let bow = vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(triangulate(&[bow], &[]).unwrap_err().0.contains("crosses"), "bow tie");
        let touching = vec![[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [3.0, 4.0], [2.0, 0.0], [1.0, 4.0], [0.0, 4.0]];
        let e = triangulate(&[touching], &[]).unwrap_err().0;
        assert!(e.contains("passes through another vertex"), "a vertex on another edge: {e}");
        let repeated = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [1.0, 0.0]];
        assert!(triangulate(&[repeated], &[]).unwrap_err().0.contains("same point"));
        let square = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert!(triangulate(std::slice::from_ref(&square), &[[2.0, 0.5]]).unwrap_err().0.contains("outside"));
        assert_eq!(triangulate(&[square], &[[0.5, 0.5]]).unwrap().len(), 4);
    }
}
