//! Closing an open scan's rim with a base surface: the hidden underside of the rock.
//!
//! The base is a height field over the rim's best-fit plane (o, e₁, e₂, n; n the rim's outward
//! normal, pointing down and out of the rock): a point (u, v) inside the rim's projection
//! becomes o + u e₁ + v e₂ + h(u, v) n, where the caller's offset h is positive for a base bulging
//! below the rim plane, away from the rock, negative for one recessed into it, and should vanish
//! towards the rim (each [`BasePoint`] carries its distance from the rim for that). h ≡ 0 is the
//! flat cap, the nominal closing.
//!
//! The surface is triangulated once ([`BaseClosing::new`]): the rim polygon projected on its
//! plane with the points of a square grid inside it, by a constrained Delaunay triangulation
//! ([`triangulate`]). The grid's spacing is s = √(A / [`BASE_GRID_POINTS`]) for the rim's
//! enclosed area A (about 400 points whatever the rim's size and shape, some twenty across a
//! round base), aligned with the plane's axes, and points nearer than s/2 to the rim are left
//! out so that no sliver triangle hugs it. The rim's vertices keep their 3D positions, so the
//! base is watertight with the scan; only the interior points move with the offset. Every
//! closing ([`BaseClosing::close`]) reuses that triangulation: it places the interior points,
//! checks that the base does not cross the scan (exact predicates,
//! [`intersect::find_patch_crossing`], on the base and the scan triangles within its bounding
//! box; a height field over a plane triangulation cannot cross itself), and returns the closed solid boundary, which [`super::TriMesh::into_solid_boundary`]
//! accepts as it is.

use super::open_scan::OpenScan;
use super::plane::Plane;
use super::polygon::triangulate;
use super::{intersect, Repairs, TriMesh};
use crate::error::ScanProblem;
use crate::{Error, Point3, Result};

/// Number of grid points the base's interior gets (module docs).
pub const BASE_GRID_POINTS: f64 = 400.0;

/// Grid points per base at most, when the rim's bounding box is much larger than its area (a
/// thin sliver of a rim): the spacing grows instead.
const MAX_LATTICE: f64 = 100.0 * BASE_GRID_POINTS;

/// An interior point of the base, as the offset function sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct BasePoint {
    /// Its position on the rim's plane (mesh frame).
    pub point: Point3,
    /// Its coordinates (u, v) in the plane's frame ([`Plane::coordinates`]).
    pub uv: [f64; 2],
    /// Distance from the rim's projection on the plane.
    pub rim_distance: f64,
}

/// An open scan closed by a base: a closed, outward, manifold surface.
#[derive(Clone, Debug)]
pub struct ClosedScan {
    /// The scan, its gaps' patches, then the base's triangles; the scan's vertices, then the
    /// base's interior points.
    pub mesh: TriMesh,
    /// The scan's repairs ([`OpenScan::repairs`]).
    pub repairs: Repairs,
    /// For every vertex: whether it belongs to the base (the rim or an interior point).
    pub on_base: Vec<bool>,
    /// Index of the base's first triangle in `mesh`.
    pub first_base_triangle: usize,
}

/// The triangulated base of an open scan, ready to be closed with any offset (module docs).
#[derive(Clone, Debug)]
pub struct BaseClosing {
    scan: OpenScan,
    points: Vec<BasePoint>,
    triangles: Vec<[u32; 3]>,
    boxes: Vec<(Point3, Point3)>,
    spacing: f64,
}

impl BaseClosing {
    /// Triangulate the base of `scan` (module docs). Refuses a rim that does not project onto
    /// its plane as a simple polygon ([`ScanProblem::NotSimple`]).
    pub fn new(scan: OpenScan) -> Result<BaseClosing> {
        let plane = scan.rim_plane().clone();
        let mesh = scan.mesh();
        // The base runs every rim loop backwards: its region is on the left of the reversed loops.
        let order: Vec<u32> = scan.rim().iter().flat_map(|l| l.vertices.iter().rev().copied()).collect();
        let outlines: Vec<Vec<[f64; 2]>> = scan
            .rim()
            .iter()
            .map(|l| l.vertices.iter().rev().map(|&i| plane.coordinates(&mesh.vertices[i as usize])).collect())
            .collect();
        let (interior, spacing) = grid(&outlines, scan.summary().rim.area);
        let uv: Vec<[f64; 2]> = interior.iter().map(|(p, _)| *p).collect();
        let local = triangulate(&outlines, &uv).map_err(|e| {
            let rim = &scan.summary().rim;
            Error::open_scan(
                ScanProblem::NotSimple,
                format!(
                    "the rim of the hidden base ({} edges in {} loop(s), perimeter {:.4e}) does not project onto its best-fit plane as simple polygons ({}): seen along its normal ({:.2}, {:.2}, {:.2}) it folds over itself; cut the scan flat at its base, or give a point near another rim",
                    rim.vertices,
                    outlines.len(),
                    rim.perimeter,
                    e.0,
                    plane.normal.x,
                    plane.normal.y,
                    plane.normal.z
                ),
            )
        })?;
        let (n, nv) = (order.len() as u32, mesh.vertices.len() as u32);
        let triangles =
            local.into_iter().map(|t| t.map(|i| if i < n { order[i as usize] } else { nv + i - n })).collect();
        let points = interior
            .into_iter()
            .map(|([u, v], d)| BasePoint { point: plane.at(u, v, 0.0), uv: [u, v], rim_distance: d })
            .collect();
        let boxes = intersect::triangle_boxes(&mesh.vertices, &mesh.triangles);
        Ok(BaseClosing { scan, points, triangles, boxes, spacing })
    }

    /// The open scan.
    pub fn scan(&self) -> &OpenScan {
        &self.scan
    }

    /// The base's interior points, in the order of the closed mesh's vertices after the scan's.
    pub fn points(&self) -> &[BasePoint] {
        &self.points
    }

    /// The grid spacing s (mesh units).
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// The rim's plane: the frame of the offset.
    pub fn plane(&self) -> &Plane {
        self.scan.rim_plane()
    }

    /// The flat cap: [`BaseClosing::close`] with h ≡ 0.
    pub fn flat(&self) -> Result<ClosedScan> {
        self.close(|_| 0.0)
    }

    /// Close the rim with the base h = `offset(point)` along the rim plane's outward normal
    /// (module docs). Refuses a non-finite offset ([`Error::Parameter`] `offset`) and a base that
    /// crosses the scan ([`ScanProblem::Crossing`]).
    pub fn close(&self, offset: impl Fn(&BasePoint) -> f64) -> Result<ClosedScan> {
        let scan = self.scan.mesh();
        let normal = self.plane().normal;
        let nv = scan.vertices.len();
        let mut vertices = Vec::with_capacity(nv + self.points.len());
        vertices.extend_from_slice(&scan.vertices);
        for b in &self.points {
            let h = offset(b);
            if !h.is_finite() {
                return Err(Error::parameter(
                    "offset",
                    h,
                    format!(
                        "a finite height at every point of the base (here at ({}, {}, {}))",
                        b.point.x, b.point.y, b.point.z
                    ),
                ));
            }
            vertices.push(b.point + normal * h);
        }
        if let Some(c) = intersect::find_patch_crossing(&vertices, &scan.triangles, &self.boxes, &self.triangles) {
            return Err(Error::open_scan(
                ScanProblem::Crossing,
                format!(
                    "the base crosses the scan's triangle {} near ({}, {}, {}) ({} crossing pair(s), {:.3e} deep): recessed deeper than the rock allows",
                    c.first, c.near.x, c.near.y, c.near.z, c.pairs, c.depth
                ),
            ));
        }
        let first_base_triangle = scan.triangles.len();
        let mut triangles = Vec::with_capacity(first_base_triangle + self.triangles.len());
        triangles.extend_from_slice(&scan.triangles);
        triangles.extend_from_slice(&self.triangles);
        let mut on_base = vec![false; vertices.len()];
        self.scan.rim().iter().flat_map(|l| &l.vertices).for_each(|&i| on_base[i as usize] = true);
        on_base[nv..].iter_mut().for_each(|b| *b = true);
        let mesh = TriMesh::new(vertices, triangles);
        Ok(ClosedScan { mesh, repairs: self.scan.repairs().clone(), on_base, first_base_triangle })
    }
}

/// The grid points strictly inside the region bounded by `outlines`, at least s/2 from them,
/// with their distances from them, and the spacing s = √(`area` / [`BASE_GRID_POINTS`]) (module
/// docs). Cost: (grid points in the bounding box) × (outline vertices), once per scan.
fn grid(outlines: &[Vec<[f64; 2]>], area: f64) -> (Vec<([f64; 2], f64)>, f64) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in outlines.iter().flatten() {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let (w, h) = (hi[0] - lo[0], hi[1] - lo[1]);
    let s = (area / BASE_GRID_POINTS).sqrt().max((w * h / MAX_LATTICE).sqrt());
    if !(s > 0.0 && s.is_finite()) {
        return (Vec::new(), 0.0);
    }
    let (nx, ny) = ((w / s).floor() as i64, (h / s).floor() as i64);
    // Centred on the box: the same margin on both sides.
    let (u0, v0) = (lo[0] + (w - nx as f64 * s) / 2.0, lo[1] + (h - ny as f64 * s) / 2.0);
    let edges: Vec<([f64; 2], [f64; 2])> =
        outlines.iter().flat_map(|o| (0..o.len()).map(move |i| (o[i], o[(i + 1) % o.len()]))).collect();
    let mut out = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            let p = [u0 + i as f64 * s, v0 + j as f64 * s];
            let d = edges.iter().map(|(a, b)| segment_distance(&p, a, b)).fold(f64::INFINITY, f64::min);
            if d >= s / 2.0 && inside(&p, &edges) {
                out.push((p, d));
            }
        }
    }
    (out, s)
}

/// Even-odd rule: a ray from `p` towards +u crosses the edges an odd number of times.
fn inside(p: &[f64; 2], edges: &[([f64; 2], [f64; 2])]) -> bool {
    let mut odd = false;
    for (a, b) in edges {
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            odd ^= x > p[0];
        }
    }
    odd
}

/// Distance from `p` to the segment ab.
fn segment_distance(p: &[f64; 2], a: &[f64; 2], b: &[f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 { (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0) } else { 0.0 };
    ((p[0] - a[0] - t * dx).powi(2) + (p[1] - a[1] - t * dy).powi(2)).sqrt()
}
