//! Shape descriptors field users expect (axes, Zingg class, isoperimetric ratio).
//!
//! * **Axes a ≥ b ≥ c** are the extents (max − min) of the mesh vertices projected onto the three
//!   principal axes of inertia of the solid, sorted in decreasing order: the edge lengths of the
//!   *principal-axes bounding box*, the computer analogue of the calliper axes a sedimentologist
//!   measures by hand (longest, intermediate, shortest, mutually perpendicular). They are full
//!   lengths (not semi-axes), in input units, and invariant under rigid motions. When principal
//!   moments are equal (symmetric solids: cube, square prism, solid of revolution), the inertia
//!   leaves the axes free within their eigenspace; there the smallest box is taken (see
//!   [`principal_extents`]), so a cube is 1 × 1 × 1, not a box around a tilted cube.
//! * **Zingg class** (Zingg 1935) from b/a and c/b with both thresholds at 2/3; see [`Zingg`].
//! * **Isoperimetric ratio** Q = 36π V² / A³ ∈ (0, 1], V the solid's volume and A the surface
//!   area of the mesh; Q = 1 exactly for a sphere and only for it (cube: π/6 ≈ 0.524).

use crate::mesh::TriMesh;
use crate::solid::MassProperties;
use crate::Vec3;
use serde::Serialize;
use std::fmt;

/// The threshold of both Zingg ratios b/a and c/b.
pub const ZINGG_THRESHOLD: f64 = 2.0 / 3.0;

/// Zingg (1935) shape class from the axis ratios, thresholds 2/3 on b/a and c/b.
/// A ratio equal to 2/3 counts as "not above" (the ≤ side).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Zingg {
    /// Oblate (tabular): b/a > 2/3, c/b ≤ 2/3.
    Disc,
    /// Equant: b/a > 2/3, c/b > 2/3.
    Spheroid,
    /// Flat and elongated: b/a ≤ 2/3, c/b ≤ 2/3.
    Blade,
    /// Prolate: b/a ≤ 2/3, c/b > 2/3.
    Rod,
}

impl Zingg {
    /// The class of a stone with the given ratios b/a and c/b (each in (0, 1]).
    pub fn classify(b_over_a: f64, c_over_b: f64) -> Zingg {
        match (b_over_a > ZINGG_THRESHOLD, c_over_b > ZINGG_THRESHOLD) {
            (true, false) => Zingg::Disc,
            (true, true) => Zingg::Spheroid,
            (false, false) => Zingg::Blade,
            (false, true) => Zingg::Rod,
        }
    }

    /// Lowercase name, as serialised.
    pub fn name(self) -> &'static str {
        match self {
            Zingg::Disc => "disc",
            Zingg::Spheroid => "spheroid",
            Zingg::Blade => "blade",
            Zingg::Rod => "rod",
        }
    }
}

impl fmt::Display for Zingg {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Size and shape of one stone (see the module docs for the definitions).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ShapeDescriptors {
    /// Longest principal-axes bounding-box edge (input units).
    pub a: f64,
    /// Intermediate principal-axes bounding-box edge.
    pub b: f64,
    /// Shortest principal-axes bounding-box edge.
    pub c: f64,
    /// Flatness ratio c/b.
    pub c_over_b: f64,
    /// Elongation ratio b/a.
    pub b_over_a: f64,
    /// Ratio c/a.
    pub c_over_a: f64,
    /// Zingg class from b/a and c/b.
    pub zingg: Zingg,
    /// Volume of the solid (input units³), from the mass properties.
    pub volume: f64,
    /// Surface area of the mesh (input units²).
    pub area: f64,
    /// 36π V² / A³: 1 for a sphere, smaller for every other shape.
    pub isoperimetric_ratio: f64,
}

/// Relative tolerance under which two principal moments count as equal (exact symmetry up to
/// rounding): the inertia then leaves the axes in their common eigenspace undetermined.
pub const EQUAL_MOMENTS_TOL: f64 = 1e-8;

/// Largest hull facets tried as box faces when all three principal moments are equal.
const ISOTROPIC_CANDIDATES: usize = 64;

/// Extents (max − min) of the vertices along the three axes of the box frame, unsorted.
///
/// The frame is the principal axes of inertia. Where moments are equal (within
/// [`EQUAL_MOMENTS_TOL`] of the largest) the inertia does not fix the axes and the eigenvectors
/// are arbitrary; the frame is then chosen to make the box smallest, so that symmetric solids
/// (cube, square prism, cylinder) get their natural box:
///
/// * two equal moments: the distinct axis e is kept and, in the plane ⟂ e, the minimum-area
///   rectangle of the projected points (one side on an edge of their 2-D hull);
/// * three equal moments: the minimum-volume box with a face on one of the 64 largest hull
///   facets, each with its minimum-area rectangle.
pub fn principal_extents(mesh: &TriMesh, mass: &MassProperties) -> [f64; 3] {
    let g = mass.center_of_mass;
    let rel: Vec<Vec3> = mesh.vertices.iter().map(|p| p - g).collect();
    extents(&rel, &box_frame(&rel, mass))
}

/// Extents (max − min) of `points` along each of `axes`.
fn extents(points: &[Vec3], axes: &[Vec3; 3]) -> [f64; 3] {
    axes.map(|e| {
        let (lo, hi) = points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
            let x = e.dot(p);
            (l.min(x), h.max(x))
        });
        (hi - lo).max(0.0)
    })
}

/// The orthonormal frame of the box (see [`principal_extents`]).
fn box_frame(points: &[Vec3], mass: &MassProperties) -> [Vec3; 3] {
    let axes: [Vec3; 3] = [0, 1, 2].map(|k| mass.principal_axes.column(k).into_owned());
    let [l0, l1, l2] = mass.principal_moments;
    let equal = |x: f64, y: f64| (y - x).abs() <= EQUAL_MOMENTS_TOL * l2.abs();
    match (equal(l0, l1), equal(l1, l2)) {
        (false, false) => axes,
        (true, true) => isotropic_frame(points).unwrap_or(axes),
        (true, false) => frame_about(points, &axes[2]),
        (false, true) => frame_about(points, &axes[0]),
    }
}

/// The frame (e, d, e × d) with d the direction of the minimum-area rectangle of the points
/// projected on the plane ⟂ e (e a unit vector).
fn frame_about(points: &[Vec3], e: &Vec3) -> [Vec3; 3] {
    let u = e.cross(&if e.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() }).normalize();
    let v = e.cross(&u);
    let plane: Vec<[f64; 2]> = points.iter().map(|p| [u.dot(p), v.dot(p)]).collect();
    let [cx, cy] = min_area_rectangle(&convex_hull_2d(plane)).0;
    let d = u * cx + v * cy;
    [*e, d, e.cross(&d)]
}

/// Among the largest hull facets, the face normal whose box (with its minimum-area rectangle)
/// has the least volume; `None` if the points span no solid.
fn isotropic_frame(points: &[Vec3]) -> Option<[Vec3; 3]> {
    let pts: Vec<crate::Point3> = points.iter().map(|p| crate::Point3::from(*p)).collect();
    let poly = crate::hull::Polyhedron::new(&pts, crate::hull::DEFAULT_COPLANAR_TOL).ok()?;
    let corners: Vec<Vec3> = poly.vertices.iter().map(|p| p.coords).collect();
    let mut facets: Vec<_> = poly.facets.iter().collect();
    facets.sort_by(|a, b| b.area.total_cmp(&a.area));
    facets
        .iter()
        .take(ISOTROPIC_CANDIDATES)
        .map(|f| frame_about(&corners, &f.normal))
        .min_by(|a, b| volume(&corners, a).total_cmp(&volume(&corners, b)))
}

fn volume(points: &[Vec3], axes: &[Vec3; 3]) -> f64 {
    extents(points, axes).iter().product()
}

/// Convex hull of planar points (Andrew's monotone chain), counter-clockwise, no repeats.
fn convex_hull_2d(mut p: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross =
        |o: &[f64; 2], a: &[f64; 2], b: &[f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * p.len());
    for pass in [p.clone(), p.into_iter().rev().collect()] {
        let start = hull.len();
        for q in pass {
            while hull.len() >= start + 2 && cross(&hull[hull.len() - 2], &hull[hull.len() - 1], &q) <= 0.0 {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop(); // the last point of each chain starts the other
    }
    hull
}

/// Minimum-area enclosing rectangle of a convex polygon: one of its sides lies on a polygon edge
/// (Freeman & Shapira 1975). Returns (unit direction of that side, area).
fn min_area_rectangle(hull: &[[f64; 2]]) -> ([f64; 2], f64) {
    let mut best = ([1.0, 0.0], f64::INFINITY);
    for k in 0..hull.len() {
        let (a, b) = (hull[k], hull[(k + 1) % hull.len()]);
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        if len == 0.0 {
            continue;
        }
        let d = [(b[0] - a[0]) / len, (b[1] - a[1]) / len];
        let span = |f: &dyn Fn(&[f64; 2]) -> f64| {
            let (lo, hi) = hull.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| (l.min(f(p)), h.max(f(p))));
            hi - lo
        };
        let area = span(&|p| p[0] * d[0] + p[1] * d[1]) * span(&|p| p[1] * d[0] - p[0] * d[1]);
        if area < best.1 {
            best = (d, area);
        }
    }
    best
}

/// Ratio `num / den`, 0 when `den` is 0 (an empty or collapsed mesh).
fn ratio(num: f64, den: f64) -> f64 {
    if den > 0.0 {
        num / den
    } else {
        0.0
    }
}

/// Axes, ratios, Zingg class, volume, area and isoperimetric ratio of a closed mesh whose mass
/// properties are `mass`.
pub fn describe(mesh: &TriMesh, mass: &MassProperties) -> ShapeDescriptors {
    let mut ext = principal_extents(mesh, mass);
    ext.sort_by(|x, y| y.total_cmp(x));
    let [a, b, c] = ext;
    let (b_over_a, c_over_b) = (ratio(b, a), ratio(c, b));
    let area = mesh.area();
    let volume = mass.volume;
    ShapeDescriptors {
        a,
        b,
        c,
        c_over_b,
        b_over_a,
        c_over_a: ratio(c, a),
        zingg: Zingg::classify(b_over_a, c_over_b),
        volume,
        area,
        isoperimetric_ratio: ratio(36.0 * std::f64::consts::PI * volume * volume, area * area * area),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zingg_classes_and_thresholds() {
        assert_eq!(Zingg::classify(0.9, 0.5), Zingg::Disc);
        assert_eq!(Zingg::classify(0.9, 0.9), Zingg::Spheroid);
        assert_eq!(Zingg::classify(0.5, 0.5), Zingg::Blade);
        assert_eq!(Zingg::classify(0.5, 0.9), Zingg::Rod);
        // Exactly 2/3 is on the "≤" side of both thresholds.
        assert_eq!(Zingg::classify(ZINGG_THRESHOLD, ZINGG_THRESHOLD), Zingg::Blade);
        assert_eq!(Zingg::classify(1.0, ZINGG_THRESHOLD), Zingg::Disc);
    }

    #[test]
    fn zingg_serialises_lowercase() {
        assert_eq!(serde_json::to_string(&Zingg::Spheroid).unwrap(), "\"spheroid\"");
        assert_eq!(Zingg::Rod.to_string(), "rod");
    }
}
