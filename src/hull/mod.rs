//! Exact convex hull in f64 and the polyhedron of its facets.
//!
//! * [`convex_hull`] is an incremental (quickhull-ordered) hull whose every visibility decision is
//!   Shewchuk's exact `orient3d` (crate `robust`), so its topology is always a valid, closed,
//!   convex triangulation of the input points, whatever their precision or degeneracy.
//! * [`Polyhedron::new`] merges adjacent hull triangles that are coplanar — the opposite vertex
//!   of each lies within `δ = rel_tol · D` of the other's plane, D the bounding-box diagonal of
//!   the points — into polygonal facets, drops hull points that are not corners (inside a facet
//!   or on an edge between two facets) and builds the facet/edge/vertex adjacency.
//!
//! The default `rel_tol` = [`DEFAULT_COPLANAR_TOL`] = 1e-9 sits far above the rounding of any
//! f64 rigid motion (~1e-16 D) and far below any real micro-facet: it merges *exactly* planar
//! faces (machined, synthetic) and nothing else. It is not parry's ~1.5° merge.
//!
//! One file per step: [`triangles`] builds the exact hull, `facets` groups its triangles into
//! planar facets and finds the corners, [`polyhedron`] assembles the facet/edge/vertex structure.

mod facets;
pub mod polyhedron;
pub mod triangles;

pub use polyhedron::{Edge, Facet, Polyhedron};
pub use triangles::{convex_hull, HullTriangles};

use crate::Point3;
use robust::{orient3d, Coord3D};

/// Default relative coplanarity tolerance (fraction of the bounding-box diagonal).
pub const DEFAULT_COPLANAR_TOL: f64 = 1e-9;

#[inline]
fn c3(p: &Point3) -> Coord3D<f64> {
    Coord3D { x: p.x, y: p.y, z: p.z }
}

/// Exact orientation: negative iff `d` is on the outer side of the counter-clockwise
/// (seen from outside) triangle `a b c`; zero iff the four points are coplanar.
#[inline]
pub fn orient(a: &Point3, b: &Point3, c: &Point3, d: &Point3) -> f64 {
    orient3d(c3(a), c3(b), c3(c), c3(d))
}

/// Steepest-ascent hill climbing on a graph from vertex `v`: move to the neighbour with the
/// largest `score` while it strictly improves. On the vertex–edge graph of a convex polytope and a
/// linear score x·d this ends at a maximiser (a local maximum of a linear function over the
/// vertices of a convex polytope is global); the support-point queries of
/// [`crate::basins::SupportFlow`] and of the collider [`crate::dynamics::engine::hull_shape`] use it.
#[inline]
pub fn hill_climb<I: IntoIterator<Item = u32>>(
    mut v: u32,
    neighbours: impl Fn(u32) -> I,
    score: impl Fn(u32) -> f64,
) -> u32 {
    let mut best = score(v);
    loop {
        let mut next = v;
        for w in neighbours(v) {
            let s = score(w);
            if s > best {
                best = s;
                next = w;
            }
        }
        if next == v {
            return v;
        }
        v = next;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Error;

    fn cube_points() -> Vec<Point3> {
        let mut v = Vec::new();
        for i in 0..8 {
            v.push(Point3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64));
        }
        // interior, face-centre, and edge-midpoint points must not become corners
        v.push(Point3::new(0.5, 0.5, 0.5));
        v.push(Point3::new(0.5, 0.5, 1.0));
        v.push(Point3::new(0.5, 0.0, 0.0));
        v.push(Point3::new(0.25, 0.0, 0.75));
        v
    }

    #[test]
    fn cube_with_coplanar_points_has_six_square_facets() {
        let p = Polyhedron::new(&cube_points(), DEFAULT_COPLANAR_TOL).unwrap();
        assert_eq!((p.vertices.len(), p.edges.len(), p.facets.len()), (8, 12, 6));
        for f in &p.facets {
            assert_eq!(f.vertices.len(), 4);
            assert!((f.area - 1.0).abs() < 1e-12);
        }
        assert!((p.volume() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn flat_input_is_refused() {
        let pts: Vec<Point3> = (0..10).map(|i| Point3::new(i as f64, (i * i) as f64, 0.0)).collect();
        assert!(matches!(convex_hull(&pts), Err(Error::Degenerate { .. })));
    }
}
