//! The convex polyhedron of a point set: corners, polygonal facets, edges and their adjacency,
//! built from the exact hull and its planar facets.

use super::facets::{boundary_loop, corners, merge_coplanar};
use super::triangles::{convex_hull, HullTriangles};
use crate::mesh::{ldexp, scale_point};
use crate::{Error, Point3, Result, Vec3};

/// A polygonal facet of the hull: a convex polygon with outward unit normal.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Facet {
    /// Corner indices (into [`Polyhedron::vertices`]) counter-clockwise seen from outside.
    pub vertices: Vec<u32>,
    /// Edge indices (into [`Polyhedron::edges`]): `edges[k]` joins `vertices[k]` to `vertices[k+1]`.
    pub edges: Vec<u32>,
    /// Outward unit normal n; the facet lies in the plane n·x = `offset`.
    pub normal: Vec3,
    /// Offset of the facet's plane along the normal (input units).
    pub offset: f64,
    /// Area of the facet (input units²).
    pub area: f64,
    /// The hull triangles (indices into [`Polyhedron::vertices`]) that make up the facet.
    pub triangles: Vec<[u32; 3]>,
}

/// An edge between two facets: `facets[0]` runs it from `vertices[0]` to `vertices[1]` in its
/// counter-clockwise loop (the facet on the left), `facets[1]` runs it backwards.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct Edge {
    /// The two corners joined by the edge (indices into the corners).
    pub vertices: [u32; 2],
    /// The two facets on either side (left, then right, of `vertices[0]`→`vertices[1]`).
    pub facets: [u32; 2],
}

/// The convex polyhedron of a point set: corners, polygonal facets, edges and their adjacency.
/// S + U − H = 2 is checked against its Euler characteristic V − E + F = 2 on construction.
#[derive(Clone, Debug)]
pub struct Polyhedron {
    /// Corners (vertices where ≥ 3 facets meet), in the input frame.
    pub vertices: Vec<Point3>,
    /// For each corner, the index of the input point it came from.
    pub source: Vec<u32>,
    /// The polygonal facets.
    pub facets: Vec<Facet>,
    /// The edges between facets.
    pub edges: Vec<Edge>,
    /// For each corner, the incident edges (unordered).
    pub vertex_edges: Vec<Vec<u32>>,
    /// The absolute coplanarity tolerance δ that was used (input units).
    pub coplanar_tol: f64,
    /// Bounding-box diagonal of the input points (input units).
    pub diameter: f64,
    /// Number of hull triangles before merging.
    pub hull_triangles: usize,
}

impl Polyhedron {
    /// Hull of `points` with exactly-coplanar triangles merged (`rel_tol` × bounding-box diagonal).
    pub fn new(points: &[Point3], rel_tol: f64) -> Result<Self> {
        let hull = convex_hull(points)?;
        Self::from_hull(points, &hull, rel_tol)
    }

    /// Merge a hull triangulation into polygonal facets.
    pub fn from_hull(points: &[Point3], hull: &HullTriangles, rel_tol: f64) -> Result<Self> {
        let (lo, hi) = points.iter().fold((points[0], points[0]), |(l, h), p| (l.inf(p), h.sup(p)));
        let diameter = (hi - lo).norm();
        let delta = rel_tol * diameter;
        let tris = &hull.triangles;
        let nt = tris.len();
        let tri_n: Vec<Vec3> = tris
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| points[i as usize]);
                (b - a).cross(&(c - a))
            })
            .collect();
        let facet_of = merge_coplanar(points, hull, &tri_n, delta);
        let nf = facet_of.iter().map(|&f| f + 1).max().unwrap_or(0);
        if nf < 4 {
            return Err(Error::degenerate(format!(
                "all points lie within {delta:.3e} of one plane (coplanar tolerance): a flat object has no interior"
            )));
        }
        let np = points.len();
        // Boundary loop of every facet, from the triangles' edges whose neighbour is elsewhere.
        let mut boundary: Vec<Vec<(u32, u32)>> = vec![Vec::new(); nf as usize];
        let mut facet_normal = vec![Vec3::zeros(); nf as usize];
        for t in 0..nt {
            let f = facet_of[t] as usize;
            facet_normal[f] += tri_n[t];
            for e in 0..3 {
                if facet_of[hull.neighbours[t][e] as usize] as usize != f {
                    boundary[f].push((tris[t][e], tris[t][(e + 1) % 3]));
                }
            }
        }
        let mut loops = Vec::with_capacity(nf as usize);
        let mut next_of = vec![u32::MAX; np];
        for b in &boundary {
            loops.push(boundary_loop(b, &mut next_of)?);
        }
        let is_corner = corners(np, tris, &facet_of, &loops);
        let mut corner_id = vec![u32::MAX; np];
        let mut vertices = Vec::new();
        let mut source = Vec::new();
        for v in 0..np {
            if is_corner[v] {
                corner_id[v] = vertices.len() as u32;
                vertices.push(points[v]);
                source.push(v as u32);
            }
        }
        let mut facets = Vec::with_capacity(nf as usize);
        let mut half_edges: std::collections::HashMap<(u32, u32), (u32, u32)> = std::collections::HashMap::new(); // (a,b) -> (facet, slot in facet loop)
        for (f, loop_pts) in loops.iter().enumerate() {
            let corners: Vec<u32> =
                loop_pts.iter().filter(|&&v| is_corner[v as usize]).map(|&v| corner_id[v as usize]).collect();
            debug_assert!(corners.len() >= 3, "corners() promotes until every facet has three");
            let n = facet_normal[f].normalize();
            let offset =
                corners.iter().map(|&c| n.dot(&vertices[c as usize].coords)).sum::<f64>() / corners.len() as f64;
            let area = facet_normal[f].norm() / 2.0;
            for k in 0..corners.len() {
                half_edges.insert((corners[k], corners[(k + 1) % corners.len()]), (f as u32, k as u32));
            }
            // Triangles of the facet with non-corner points fanned away: keep them in point ids
            // remapped to corners where possible (non-corner points are dropped by re-fanning).
            let tri_c: Vec<[u32; 3]> =
                (1..corners.len() - 1).map(|k| [corners[0], corners[k], corners[k + 1]]).collect();
            facets.push(Facet { vertices: corners, edges: Vec::new(), normal: n, offset, area, triangles: tri_c });
        }
        // Edges: pair each half-edge with its twin.
        let mut edges = Vec::new();
        let mut vertex_edges = vec![Vec::new(); vertices.len()];
        let mut keys: Vec<_> = half_edges.keys().copied().filter(|&(a, b)| a < b).collect();
        keys.sort_unstable();
        for (a, b) in keys {
            let (f0, k0) = half_edges[&(a, b)];
            let Some(&(f1, k1)) = half_edges.get(&(b, a)) else {
                return Err(Error::check("a hull edge has no twin"));
            };
            let id = edges.len() as u32;
            edges.push(Edge { vertices: [a, b], facets: [f0, f1] });
            facets[f0 as usize].edges.push(u32::MAX);
            facets[f1 as usize].edges.push(u32::MAX);
            let _ = (k0, k1);
            vertex_edges[a as usize].push(id);
            vertex_edges[b as usize].push(id);
        }
        // Fill facet edge slots in loop order.
        for f in &mut facets {
            f.edges.clear();
        }
        for (id, e) in edges.iter().enumerate() {
            let [a, b] = e.vertices;
            let (f0, k0) = half_edges[&(a, b)];
            let (f1, k1) = half_edges[&(b, a)];
            for (f, k) in [(f0, k0), (f1, k1)] {
                let fe = &mut facets[f as usize].edges;
                if fe.len() <= k as usize {
                    fe.resize(k as usize + 1, u32::MAX);
                }
                fe[k as usize] = id as u32;
            }
        }
        let poly = Polyhedron {
            vertices,
            source,
            facets,
            edges,
            vertex_edges,
            coplanar_tol: delta,
            diameter,
            hull_triangles: nt,
        };
        let chi = poly.vertices.len() as i64 - poly.edges.len() as i64 + poly.facets.len() as i64;
        if chi != 2 {
            return Err(Error::check(format!("hull Euler characteristic V − E + F = {chi}, not 2")));
        }
        Ok(poly)
    }

    /// The same polyhedron scaled by 2^k: corners, facet offsets, areas, δ and the diameter
    /// (exact in f64's normal range; the combinatorics and normals do not change).
    pub fn scaled_pow2(mut self, k: i32) -> Self {
        self.vertices.iter_mut().for_each(|p| *p = scale_point(p, k));
        for f in &mut self.facets {
            f.offset = ldexp(f.offset, k);
            f.area = ldexp(f.area, 2 * k);
        }
        self.coplanar_tol = ldexp(self.coplanar_tol, k);
        self.diameter = ldexp(self.diameter, k);
        self
    }

    /// The other end of edge `e` seen from corner `v`.
    pub fn other_end(&self, e: u32, v: u32) -> u32 {
        let [a, b] = self.edges[e as usize].vertices;
        if a == v {
            b
        } else {
            a
        }
    }

    /// Surface area of the hull.
    pub fn area(&self) -> f64 {
        self.facets.iter().map(|f| f.area).sum()
    }

    /// Volume of the hull (by facets, about `o`).
    pub fn volume(&self) -> f64 {
        let o = self.vertices[0];
        self.facets.iter().map(|f| f.area * (f.offset - f.normal.dot(&o.coords))).sum::<f64>() / 3.0
    }
}
