//! Cutting a closed mesh open along a plane, as a field scan sees a rock: what lies below the
//! plane removed, the triangles it crosses clipped exactly at it.
//!
//! With d(x) = n·(x − p) the signed distance from the plane (p, n), a triangle whose vertices all
//! have d ≥ 0 and not all d = 0 is kept as it is, one with all d ≤ 0 is removed, and one with
//! vertices on both sides is clipped to its part d ≥ 0 (Sutherland–Hodgman on the triangle:
//! a triangle or a quadrilateral, split into two triangles). The point where an edge (a, b)
//! crosses the plane is a + t (b − a), t = d(a) / (d(a) − d(b)), computed once per edge and
//! shared by the two triangles of that edge, so the cut surface is watertight and its rim a
//! closed loop of edges lying in the plane. When n is a coordinate axis (a horizontal cut,
//! n = +z) the crossing points get that coordinate of p exactly, so the rim is exactly planar.
//!
//! [`stand_on`] poses a mesh as a rock stands: a given outward direction (a stable facet's
//! normal) turned straight down, the lowest point at z = 0.

use super::plane::Plane;
use super::TriMesh;
use crate::{Error, Point3, Result, Vec3};
use std::collections::HashMap;

/// Remove the part of `mesh` on the side of `plane` opposite its normal, clipping the triangles
/// it crosses at the plane (module docs). The mesh is welded first (a triangle soup would cut
/// into a soup). Refuses a plane that leaves nothing or removes nothing ([`Error::Parameter`]
/// `cut`).
pub fn cut_open(mesh: &TriMesh, plane: &Plane) -> Result<TriMesh> {
    let mut mesh = mesh.clone();
    mesh.weld();
    let n = plane.normal;
    let axis = (0..3).find(|&k| n[k].abs() == 1.0);
    let d: Vec<f64> = mesh.vertices.iter().map(|x| plane.distance(x)).collect();
    if let Some(i) = d.iter().position(|x| !x.is_finite()) {
        return Err(Error::invalid(format!("vertex {i}: its distance from the cutting plane is not finite")));
    }
    let mut vertices = mesh.vertices.clone();
    let mut crossing: HashMap<(u32, u32), u32> = HashMap::new();
    let mut at = |a: u32, b: u32, vertices: &mut Vec<Point3>| -> u32 {
        let key = (a.min(b), a.max(b));
        *crossing.entry(key).or_insert_with(|| {
            let (a, b) = key;
            let (pa, pb) = (vertices[a as usize], vertices[b as usize]);
            let (da, db) = (d[a as usize], d[b as usize]);
            let mut x = pa + (pb - pa) * (da / (da - db));
            if let Some(k) = axis {
                x[k] = plane.point[k];
            }
            vertices.push(x);
            (vertices.len() - 1) as u32
        })
    };
    let mut triangles = Vec::with_capacity(mesh.triangles.len());
    let mut changed = false;
    for t in &mesh.triangles {
        let s = t.map(|i| d[i as usize]);
        if s.iter().all(|&x| x >= 0.0) && s.iter().any(|&x| x > 0.0) {
            triangles.push(*t);
            continue;
        }
        changed = true;
        if s.iter().all(|&x| x <= 0.0) {
            continue;
        }
        let mut poly: Vec<u32> = Vec::with_capacity(4);
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let (da, db) = (s[k], s[(k + 1) % 3]);
            if da >= 0.0 {
                poly.push(a);
            }
            if (da > 0.0 && db < 0.0) || (da < 0.0 && db > 0.0) {
                poly.push(at(a, b, &mut vertices));
            }
        }
        for k in 1..poly.len().saturating_sub(1) {
            let tri = [poly[0], poly[k], poly[k + 1]];
            if tri[0] != tri[1] && tri[1] != tri[2] && tri[2] != tri[0] {
                triangles.push(tri);
            }
        }
    }
    if triangles.is_empty() {
        return Err(Error::parameter(
            "cut",
            format!("the plane through {:?}", plane.point.coords.as_slice()),
            "a plane with part of the mesh above it",
        ));
    }
    if !changed {
        return Err(Error::parameter(
            "cut",
            format!("the plane through {:?}", plane.point.coords.as_slice()),
            "a plane that passes through the mesh",
        ));
    }
    let mut out = TriMesh::new(vertices, triangles);
    out.weld();
    Ok(out)
}

/// Cut `mesh` open `height` above its lowest point: [`cut_open`] at the plane z = z_min +
/// `height`, normal +z (the part below removed). `height` must be positive and below the top.
pub fn cut_base(mesh: &TriMesh, height: f64) -> Result<TriMesh> {
    let (lo, hi) = mesh.bounding_box().ok_or_else(|| Error::invalid("empty mesh: nothing to cut"))?;
    if !(height > 0.0 && lo.z + height < hi.z) {
        return Err(Error::parameter(
            "cut",
            height,
            format!("a height in (0, {}) above the lowest point", hi.z - lo.z),
        ));
    }
    let plane = Plane { point: Point3::new(0.0, 0.0, lo.z + height), normal: Vec3::z(), e1: Vec3::x(), e2: Vec3::y() };
    cut_open(mesh, &plane)
}

/// `mesh` turned so that the unit direction `down` (mesh frame; e.g. the outward normal of the
/// stable facet it rests on) points straight down (−z), then raised so that its lowest point is
/// at z = 0 (x and y as the rotation leaves them). Refuses a zero or non-finite `down`.
pub fn stand_on(mesh: &TriMesh, down: &Vec3) -> Result<TriMesh> {
    let d = down
        .try_normalize(0.0)
        .filter(|d| d.iter().all(|x| x.is_finite()))
        .ok_or_else(|| Error::parameter("down", format!("{:?}", down.as_slice()), "a non-zero finite direction"))?;
    let rotation = nalgebra::Rotation3::rotation_between(&d, &-Vec3::z())
        .unwrap_or_else(|| nalgebra::Rotation3::from_axis_angle(&Vec3::x_axis(), std::f64::consts::PI));
    let turned = mesh.transformed(&rotation, 1.0, &Vec3::zeros());
    let z_min = turned.vertices.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
    Ok(turned.transformed(&nalgebra::Rotation3::identity(), 1.0, &Vec3::new(0.0, 0.0, -z_min)))
}
