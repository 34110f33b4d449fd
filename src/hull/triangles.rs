//! The exact convex hull of a point set as a closed triangulation: incremental, quickhull-ordered,
//! every visibility decision an exact `orient3d`.

use super::orient;
use crate::{Error, Point3, Result, Vec3};

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
