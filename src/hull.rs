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

use crate::mesh::{ldexp, scale_point};
use crate::{Error, Point3, Result, Vec3};
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

/// A closed convex triangulation: `triangles[t]` counter-clockwise seen from outside, indices
/// into the input points; `neighbours[t][k]` is the triangle across the edge
/// `(triangles[t][k], triangles[t][(k+1)%3])`.
#[derive(Clone, Debug)]
pub struct HullTriangles {
    /// Triangles as vertex-index triples, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// For each triangle, the triangles across its three edges.
    pub neighbours: Vec<[u32; 3]>,
}

struct Face {
    v: [u32; 3],
    n: [u32; 3],
    alive: bool,
    normal: Vec3,
    outside: Vec<u32>,
}

/// Exact convex hull of a point set. Errors if fewer than 4 points or all points are coplanar.
pub fn convex_hull(points: &[Point3]) -> Result<HullTriangles> {
    let np = points.len();
    if np < 4 {
        return Err(Error::degenerate(format!("{np} points cannot bound a solid")));
    }
    if points.iter().any(|p| !p.coords.iter().all(|x| x.is_finite())) {
        return Err(Error::degenerate("a point has a non-finite coordinate"));
    }
    let simplex = initial_simplex(points)?;
    let mut faces: Vec<Face> = Vec::new();
    let [i0, i1, i2, i3] = simplex;
    // orient(i0,i1,i2,i3) > 0 after initial_simplex: i3 lies on the inner side of (i0,i1,i2).
    for tri in [[i0, i1, i2], [i0, i3, i1], [i1, i3, i2], [i2, i3, i0]] {
        faces.push(new_face(points, tri));
    }
    link_tetrahedron(&mut faces);
    let in_simplex = |i: u32| simplex.contains(&i);
    for i in 0..np as u32 {
        if in_simplex(i) {
            continue;
        }
        let p = &points[i as usize];
        if let Some(f) = (0..4).find(|&f| is_outside(points, &faces[f], p)) {
            faces[f].outside.push(i);
        }
    }
    let mut pending: Vec<u32> = (0..4).filter(|&f| !faces[f as usize].outside.is_empty()).collect();
    // Scratch buffers reused across iterations.
    let mut visible: Vec<u32> = Vec::new();
    let mut mark: Vec<u32> = Vec::new(); // per face: iteration stamp when known visible
    let mut horizon_next: Vec<u32> = vec![u32::MAX; np]; // per vertex: index into horizon
    let mut horizon: Vec<(u32, u32, u32)> = Vec::new(); // (a, b, outer face)
    let mut stamp = 0u32;
    while let Some(f0) = pending.pop() {
        let f0 = f0 as usize;
        if !faces[f0].alive || faces[f0].outside.is_empty() {
            continue;
        }
        stamp += 1;
        // Eye point: the farthest outside point of f0 (approximate distance suffices).
        let (eye_pos, &eye) = {
            let f = &faces[f0];
            let a = points[f.v[0] as usize];
            f.outside
                .iter()
                .enumerate()
                .max_by(|x, y| {
                    let dx = (points[*x.1 as usize] - a).dot(&f.normal);
                    let dy = (points[*y.1 as usize] - a).dot(&f.normal);
                    dx.total_cmp(&dy).then(y.1.cmp(x.1))
                })
                .unwrap()
        };
        faces[f0].outside.swap_remove(eye_pos);
        let p = points[eye as usize];
        // Visible region: connected set of faces strictly below which the eye lies.
        mark.resize(faces.len(), 0);
        visible.clear();
        visible.push(f0 as u32);
        mark[f0] = stamp;
        let mut k = 0;
        while k < visible.len() {
            let f = visible[k] as usize;
            k += 1;
            for g in faces[f].n {
                let g = g as usize;
                if mark[g] != stamp && is_outside(points, &faces[g], &p) {
                    mark[g] = stamp;
                    visible.push(g as u32);
                }
            }
        }
        // Horizon: edges of visible faces whose neighbour is not visible, chained into a loop.
        horizon.clear();
        for &f in &visible {
            let face = &faces[f as usize];
            for e in 0..3 {
                let g = face.n[e];
                if mark[g as usize] != stamp {
                    let (a, b) = (face.v[e], face.v[(e + 1) % 3]);
                    horizon_next[a as usize] = horizon.len() as u32;
                    horizon.push((a, b, g));
                }
            }
        }
        // Order the horizon as a cycle starting anywhere.
        let m = horizon.len();
        let mut ordered = Vec::with_capacity(m);
        let mut h = 0usize;
        for _ in 0..m {
            ordered.push(horizon[h]);
            h = horizon_next[horizon[h].1 as usize] as usize;
        }
        debug_assert_eq!(h, 0, "horizon is not a single cycle");
        // New faces (a, b, eye), one per horizon edge.
        let first_new = faces.len();
        for (j, &(a, b, g)) in ordered.iter().enumerate() {
            let mut face = new_face(points, [a, b, eye]);
            let nxt = first_new + (j + 1) % m;
            let prv = first_new + (j + m - 1) % m;
            face.n = [g, nxt as u32, prv as u32];
            let outer = &mut faces[g as usize];
            let slot = (0..3).find(|&e| outer.v[e] == b && outer.v[(e + 1) % 3] == a).expect("horizon edge");
            outer.n[slot] = (first_new + j) as u32;
            faces.push(face);
        }
        // Hand the visible faces' outside points to the new faces; the rest are now inside.
        let mut orphans = Vec::new();
        for &f in &visible {
            let face = &mut faces[f as usize];
            face.alive = false;
            orphans.append(&mut face.outside);
        }
        for q in orphans {
            let pq = &points[q as usize];
            if let Some(nf) = (first_new..faces.len()).find(|&nf| is_outside(points, &faces[nf], pq)) {
                faces[nf].outside.push(q);
            }
        }
        pending.extend((first_new..faces.len()).filter(|&nf| !faces[nf].outside.is_empty()).map(|nf| nf as u32));
        mark.resize(faces.len(), 0);
    }
    // Compact the alive faces.
    let mut new_id = vec![u32::MAX; faces.len()];
    let mut count = 0;
    for (i, f) in faces.iter().enumerate() {
        if f.alive {
            new_id[i] = count;
            count += 1;
        }
    }
    let alive = faces.iter().filter(|f| f.alive);
    Ok(HullTriangles {
        triangles: alive.clone().map(|f| f.v).collect(),
        neighbours: alive.map(|f| f.n.map(|g| new_id[g as usize])).collect(),
    })
}

fn new_face(points: &[Point3], v: [u32; 3]) -> Face {
    let [a, b, c] = v.map(|i| points[i as usize]);
    let normal = (b - a).cross(&(c - a));
    let len = normal.norm();
    Face {
        v,
        n: [u32::MAX; 3],
        alive: true,
        normal: if len > 0.0 { normal / len } else { normal },
        outside: Vec::new(),
    }
}

#[inline]
fn is_outside(points: &[Point3], f: &Face, p: &Point3) -> bool {
    let [a, b, c] = f.v.map(|i| &points[i as usize]);
    orient(a, b, c, p) < 0.0
}

fn link_tetrahedron(faces: &mut [Face]) {
    for f in 0..faces.len() {
        for e in 0..3 {
            let (a, b) = (faces[f].v[e], faces[f].v[(e + 1) % 3]);
            let g = (0..faces.len())
                .find(|&g| g != f && (0..3).any(|k| faces[g].v[k] == b && faces[g].v[(k + 1) % 3] == a))
                .expect("tetrahedron is closed");
            faces[f].n[e] = g as u32;
        }
    }
}

/// Four affinely independent points, ordered so that the fourth lies inside the first three's
/// counter-clockwise triangle (orient > 0).
fn initial_simplex(points: &[Point3]) -> Result<[u32; 4]> {
    let (lo, hi) = points.iter().fold((points[0], points[0]), |(l, h), p| (l.inf(p), h.sup(p)));
    let axis = (hi - lo).imax();
    let i0 = (0..points.len()).min_by(|&i, &j| points[i][axis].total_cmp(&points[j][axis])).unwrap();
    let i1 = (0..points.len()).max_by(|&i, &j| points[i][axis].total_cmp(&points[j][axis])).unwrap();
    if points[i0] == points[i1] {
        return Err(Error::degenerate("all points coincide"));
    }
    let (a, b) = (points[i0], points[i1]);
    let line = |p: &Point3| (p - a).cross(&(b - a)).norm_squared();
    let i2 = (0..points.len()).max_by(|&i, &j| line(&points[i]).total_cmp(&line(&points[j]))).unwrap();
    if line(&points[i2]) == 0.0 {
        return Err(Error::degenerate("all points are collinear"));
    }
    let c = points[i2];
    let i3 = (0..points.len())
        .max_by(|&i, &j| orient(&a, &b, &c, &points[i]).abs().total_cmp(&orient(&a, &b, &c, &points[j]).abs()))
        .unwrap();
    let o = orient(&a, &b, &c, &points[i3]);
    if o == 0.0 {
        return Err(Error::degenerate("all points are coplanar (a flat object has no interior)"));
    }
    let s = [i0 as u32, i1 as u32, i2 as u32, i3 as u32];
    Ok(if o > 0.0 { s } else { [s[1], s[0], s[2], s[3]] })
}

/// Group hull triangles into planar facets. Adjacent triangles are candidates when the
/// opposite vertex of one lies within δ of the other's plane (either way round, so that a sliver
/// — three nearly collinear hull points — joins its neighbour); candidates are merged
/// most-coplanar first, and a merge is accepted only if every vertex of one group lies within δ
/// of the plane of the other group's largest triangle (its anchor; the merged group keeps the
/// larger anchor). So a facet is planar within δ as a whole, never a chain of slightly bent
/// pairs. Returns the facet id of every triangle (ids in order of first triangle).
fn merge_coplanar(points: &[Point3], hull: &HullTriangles, tri_n: &[Vec3], delta: f64) -> Vec<u32> {
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
fn boundary_loop(boundary: &[(u32, u32)], next_of: &mut [u32]) -> Result<Vec<u32>> {
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
fn corners(np: usize, tris: &[[u32; 3]], facet_of: &[u32], loops: &[Vec<u32>]) -> Vec<bool> {
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
