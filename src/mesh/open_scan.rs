//! Open scans: a rock scanned standing on its pedestal (drone photogrammetry, lidar), stored
//! with +z up, whose surface is open where the rock meets the pedestal.
//!
//! What is read, in order:
//!
//! 1. The checks every mesh gets (finite, indices in range, welded, zero-area and duplicate
//!    triangles), then *flaps* trimmed: a triangle with two or three of its edges on the
//!    boundary hangs on the surface by one edge or not at all, and a patch over the opening would
//!    fold onto it; such triangles are removed (repeatedly) and counted. So are separate pieces
//!    each under 1 % of the scan's area (a speck, or a pocket of the underside a cut separated
//!    from the rest); the scan must then be one piece.
//! 2. The boundary loops ([`boundary_loops`]: a 2-manifold with boundary, consistently
//!    oriented, else refused), one connected piece. Its orientation is that of the surface closed
//!    by a fan from each loop's centroid: if that encloses a negative volume, every triangle is
//!    flipped (as [`super::TriMesh::into_solid_boundary`] flips a closed surface).
//! 3. Every loop measured as an [`Opening`]: perimeter L, its least-squares plane
//!    ([`Plane::best_fit`], normal n pointing out of the solid), the area it encloses on that
//!    plane, |n · ½ Σ pᵢ × pᵢ₊₁|, and its flatness, the largest distance of a vertex from the
//!    plane.
//! 4. The rim of the hidden base. With [`RimChoice::Lowest`] its main loop is the longest
//!    opening, which must be at the base: its outward normal within 60° of straight down
//!    (n_z ≤ −[`BASE_FACING`]) and its centre in the lower half of the scan's height; with
//!    [`RimChoice::Near`] it is the opening passing nearest the point given, facing any way.
//!    Every other opening lying on the main loop's plane (all its vertices within the main loop's
//!    flatness plus [`BASE_PLANE_TOLERANCE`] = 1 % of its perimeter of that plane, facing along
//!    its normal within 60°: a rock standing on several feet, a ring of contact) belongs to the
//!    rim too; the rim's plane is then the least-squares plane of all its loops. Of the other
//!    openings, those at most [`GAP_PERIMETER_RATIO`] = 1/3 of the rim's perimeter long are
//!    *gaps* (holes the scan left). Refused, with what to give instead ([`Error::OpenScan`]): a
//!    closed surface ([`ScanProblem::Closed`]: read it as a stone), an open top or side
//!    ([`ScanProblem::OpenTop`]: the longest opening, or another as long as a third of the rim,
//!    not at the base), another opening that long elsewhere ([`ScanProblem::SeveralRims`]).
//! 5. Every gap closed by a patch: the constrained Delaunay triangulation of its loop projected
//!    on its best-fit plane ([`triangulate`]), refused when that projection is not a simple
//!    polygon ([`ScanProblem::NotSimple`]) or when a patch crosses the scan
//!    ([`ScanProblem::Crossing`]). The scan's own self-intersections are checked as those of a
//!    closed stone (shallow and few accepted and counted, others refused).
//!
//! The rim itself is left open: [`super::BaseClosing`] closes it with a base surface.
//! Lengths are in mesh units.

use super::boundary::{boundary_loops, BoundaryLoop};
use super::plane::{perimeter, vector_area, Plane};
use super::polygon::triangulate;
use super::{intersect, Repairs, TriMesh};
use crate::error::ScanProblem;
use crate::{Error, Point3, Result, Vec3};
use serde::Serialize;

/// A loop other than the rim is a gap of the scan (closed and reported) when its perimeter is at
/// most this fraction of the rim's; a longer one makes the rim ambiguous and is refused.
pub const GAP_PERIMETER_RATIO: f64 = 1.0 / 3.0;

/// An opening belongs to the rim when all its vertices lie within the main loop's flatness plus
/// this fraction of its perimeter of the main loop's plane (and it faces along that plane's
/// normal within 60°).
pub const BASE_PLANE_TOLERANCE: f64 = 0.01;

/// Without a point given, the rim must face down: its outward normal's z component at most
/// −`BASE_FACING` (within 60° of straight down: a pedestal may slope).
pub const BASE_FACING: f64 = 0.5;

/// How the rim of the hidden base is chosen among the openings.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
#[serde(tag = "rim", content = "near", rename_all = "kebab-case")]
pub enum RimChoice {
    /// The one opening that is not a gap, which must be at the bottom of the scan (+z up).
    #[default]
    Lowest,
    /// The opening that passes nearest this point (mesh frame), facing any way.
    Near(Point3),
}

/// A scan as read: a closed stone, or an open scan.
#[derive(Clone, Debug)]
pub enum Scan {
    /// A closed surface, checked as [`super::TriMesh::into_solid_boundary`] checks it.
    Closed(TriMesh, Repairs),
    /// An open scan.
    Open(Box<OpenScan>),
}

/// One opening (boundary loop) of a scan, measured (mesh units).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Opening {
    /// Number of vertices (= edges) of the loop.
    pub vertices: usize,
    /// Length of the loop.
    pub perimeter: f64,
    /// Area the loop encloses on its best-fit plane.
    pub area: f64,
    /// Largest distance of a loop vertex from that plane.
    pub flatness: f64,
    /// The plane's point: the loop's length-weighted centroid.
    pub centre: Point3,
    /// The plane's unit normal, pointing out of the solid (down, for the rim of a rock standing
    /// +z up).
    pub normal: Vec3,
}

/// What was found in an open scan: the rim and the gaps closed (mesh units).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OpenScanSummary {
    /// How the rim was chosen.
    pub chosen: RimChoice,
    /// The rim of the hidden base as a whole: all its loops (their vertices, perimeters and
    /// enclosed areas summed), on their common least-squares plane (centre, outward normal, the
    /// largest distance of a rim vertex from it).
    pub rim: Opening,
    /// The rim's loops one by one (one, unless the rock stands on several feet), longest first.
    pub rim_loops: Vec<Opening>,
    /// The gaps of the scan, each closed by a flat patch, longest first.
    pub gaps: Vec<Opening>,
    /// Triangles hanging on the surface by one edge or none (flaps), or in a separate piece
    /// under 1 % of its area, removed.
    pub trimmed_triangles: usize,
}

/// An open scan with its gaps closed and its rim found (module docs).
#[derive(Clone, Debug)]
pub struct OpenScan {
    mesh: TriMesh,
    repairs: Repairs,
    scan_triangles: usize,
    rim: Vec<BoundaryLoop>,
    rim_plane: Plane,
    summary: OpenScanSummary,
}

impl OpenScan {
    /// Read `mesh` as an open scan (module docs); a closed mesh is [`ScanProblem::Closed`].
    pub fn new(mesh: TriMesh, rim: &RimChoice) -> Result<OpenScan> {
        let (mesh, rep, original) = mesh.prepared()?;
        OpenScan::from_prepared(mesh, rep, &original, rim)
    }

    /// [`OpenScan::new`] after the checks every reading shares; `original` numbers the
    /// triangles as in the input, for messages.
    pub(super) fn from_prepared(
        mut mesh: TriMesh,
        mut rep: Repairs,
        original: &[usize],
        choice: &RimChoice,
    ) -> Result<OpenScan> {
        let mut original = original.to_vec();
        let trimmed = trim_flaps(&mut mesh, &mut original) + drop_fragments(&mut mesh, &mut original);
        if mesh.triangles.is_empty() {
            return Err(Error::invalid(
                "the surface is open and encloses nothing: every triangle hangs on the others by one edge or none",
            ));
        }
        if trimmed > 0 {
            mesh.weld();
        }
        let mut loops = boundary_loops(&mesh)?;
        if loops.is_empty() {
            return Err(Error::open_scan(
                ScanProblem::Closed,
                "the surface is closed (every edge joins two triangles): not an open scan; read it as a closed stone",
            ));
        }
        let pieces = mesh.pieces();
        if pieces > 1 {
            return Err(Error::invalid(format!(
                "the scan has {pieces} separate pieces; a scanned rock is one connected surface"
            )));
        }
        let k = mesh.unit_exponent();
        let unit = mesh.scaled_pow2(k);
        let v = volume_closed_by_fans(&unit, &loops);
        let d = unit.diameter();
        if !(v.abs() > 1e-12 * d * d * d) {
            return Err(Error::degenerate("the scan, closed over its openings, encloses no volume: flat or collapsed"));
        }
        if v < 0.0 {
            rep.flipped = true;
            mesh.triangles.iter_mut().for_each(|t| t.swap(1, 2));
            loops = boundary_loops(&mesh)?;
        }
        let measured: Vec<(Opening, Plane)> =
            loops.iter().enumerate().map(|(i, l)| measure(&mesh, l, i)).collect::<Result<_>>()?;
        let openings: Vec<&Opening> = measured.iter().map(|(o, _)| o).collect();
        let base = choose_rim(&mesh, &loops, &openings, choice)?;
        // The scan's own crossings, as a closed stone's.
        unit.check_crossings(k, &mut rep, &original)?;
        let scan_triangles = mesh.triangles.len();
        let boxes = intersect::triangle_boxes(&mesh.vertices, &mesh.triangles);
        let mut gaps = Vec::new();
        for (i, (l, (opening, plane))) in loops.iter().zip(&measured).enumerate() {
            if base.contains(&i) {
                continue;
            }
            // The patch runs the loop backwards: its region is on the left of the reversed loop.
            let outline: Vec<[f64; 2]> = l.points(&mesh).iter().rev().map(|p| plane.coordinates(p)).collect();
            let m = l.len() as u32;
            let patch: Vec<[u32; 3]> = triangulate(&[outline], &[])
                .map_err(|e| {
                    Error::open_scan(
                        ScanProblem::NotSimple,
                        format!(
                            "a gap of the scan ({}) cannot be closed flat: seen along its normal it is not a simple polygon ({}); fill it in the scan",
                            describe(opening),
                            e.0
                        ),
                    )
                })?
                .into_iter()
                .map(|t| t.map(|j| l.vertices[(m - 1 - j) as usize]))
                .collect();
            if let Some(c) =
                intersect::find_patch_crossing(&mesh.vertices, &mesh.triangles[..scan_triangles], &boxes, &patch)
            {
                return Err(Error::open_scan(
                    ScanProblem::Crossing,
                    format!(
                        "the flat patch closing a gap of the scan ({}) crosses the scan near ({}, {}, {}); fill that gap in the scan",
                        describe(opening),
                        c.near.x,
                        c.near.y,
                        c.near.z
                    ),
                ));
            }
            mesh.triangles.extend(patch);
            gaps.push(opening.clone());
        }
        gaps.sort_by(|a, b| b.perimeter.total_cmp(&a.perimeter));
        let rim: Vec<BoundaryLoop> = base.iter().map(|&i| loops[i].clone()).collect();
        let (rim_opening, rim_plane) = measure_together(&mesh, &rim)?;
        let mut rim_loops: Vec<Opening> = base.iter().map(|&i| measured[i].0.clone()).collect();
        rim_loops.sort_by(|a, b| b.perimeter.total_cmp(&a.perimeter));
        let summary =
            OpenScanSummary { chosen: choice.clone(), rim: rim_opening, rim_loops, gaps, trimmed_triangles: trimmed };
        Ok(OpenScan { mesh, repairs: rep, scan_triangles, rim, rim_plane, summary })
    }

    /// The scan (welded, outward) with its gaps closed: open at the rim only. Its triangles
    /// `0..scan_triangles()` are the scan's, the rest the gaps' patches.
    pub fn mesh(&self) -> &TriMesh {
        &self.mesh
    }

    /// What reading the scan repaired (welded vertices, dropped triangles, a flip, shallow
    /// crossings).
    pub fn repairs(&self) -> &Repairs {
        &self.repairs
    }

    /// Number of the scan's own triangles (those before the gaps' patches).
    pub fn scan_triangles(&self) -> usize {
        self.scan_triangles
    }

    /// The rim's loops (the main one first): vertex indices into [`OpenScan::mesh`], in the
    /// direction the scan's triangles run them (counter-clockwise seen from inside the rock).
    pub fn rim(&self) -> &[BoundaryLoop] {
        &self.rim
    }

    /// The rim's best-fit plane, its normal pointing out of the solid.
    pub fn rim_plane(&self) -> &Plane {
        &self.rim_plane
    }

    /// What was found: rim, gaps, trimmed flaps.
    pub fn summary(&self) -> &OpenScanSummary {
        &self.summary
    }
}

/// Remove, repeatedly, triangles with two or three edges on the boundary; `original` follows.
fn trim_flaps(mesh: &mut TriMesh, original: &mut Vec<usize>) -> usize {
    let mut trimmed = 0;
    loop {
        let uses = mesh.edge_uses();
        let free = |t: &[u32; 3]| {
            (0..3)
                .filter(|&k| {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    uses.get(&(a.min(b), a.max(b))).is_some_and(|&(f, r)| f + r == 1)
                })
                .count()
        };
        let keep: Vec<bool> = mesh.triangles.iter().map(|t| free(t) < 2).collect();
        let removed = keep.iter().filter(|k| !**k).count();
        if removed == 0 {
            return trimmed;
        }
        trimmed += removed;
        let mut it = keep.iter();
        mesh.triangles.retain(|_| *it.next().unwrap_or(&true));
        let mut it = keep.iter();
        original.retain(|_| *it.next().unwrap_or(&true));
    }
}

/// Separate pieces of the scan each smaller than [`FRAGMENT`] of its area — a scanned speck, or a
/// pocket of the underside that a cut separated from the rest — removed with their triangles
/// (their number returned); the scan then is one piece. Pieces any larger are left for the reader
/// to refuse: which of two sizeable surfaces is the rock is not the reader's to guess.
fn drop_fragments(mesh: &mut TriMesh, original: &mut Vec<usize>) -> usize {
    let labels = mesh.piece_labels();
    let piece: Vec<u32> = mesh.triangles.iter().map(|t| labels[t[0] as usize]).collect();
    let mut area: std::collections::BTreeMap<u32, f64> = std::collections::BTreeMap::new();
    for (t, &p) in mesh.triangles.iter().zip(&piece) {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        *area.entry(p).or_default() += 0.5 * (b - a).cross(&(c - a)).norm();
    }
    let total: f64 = area.values().sum();
    let Some((&main, _)) = area.iter().max_by(|a, b| a.1.total_cmp(b.1)) else { return 0 };
    if area.len() < 2 || area.iter().any(|(&p, &a)| p != main && a > FRAGMENT * total) {
        return 0;
    }
    let keep: Vec<bool> = piece.iter().map(|&p| p == main).collect();
    let removed = keep.iter().filter(|k| !**k).count();
    let mut it = keep.iter();
    mesh.triangles.retain(|_| *it.next().unwrap_or(&true));
    let mut it = keep.iter();
    original.retain(|_| *it.next().unwrap_or(&true));
    removed
}

/// The largest share of a scan's area a separate piece may have and still be dropped as a
/// fragment ([`drop_fragments`]).
const FRAGMENT: f64 = 0.01;

/// Signed volume of the surface closed by a fan from each loop's vertex centroid over it (the fan
/// runs each loop edge backwards, as any patch does).
fn volume_closed_by_fans(mesh: &TriMesh, loops: &[BoundaryLoop]) -> f64 {
    let o = mesh.vertices[0].coords;
    let det = |a: &Point3, b: &Point3, c: &Point3| (a.coords - o).dot(&(b.coords - o).cross(&(c.coords - o)));
    let mut v: f64 = mesh
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
            det(&a, &b, &c)
        })
        .sum();
    for l in loops {
        let pts = l.points(mesh);
        let c = Point3::from(pts.iter().map(|p| p.coords).sum::<Vec3>() / pts.len() as f64);
        v += (0..pts.len()).map(|i| det(&c, &pts[(i + 1) % pts.len()], &pts[i])).sum::<f64>();
    }
    v / 6.0
}

/// Perimeter, plane (normal out of the solid), enclosed area and flatness of loop `i`.
fn measure(mesh: &TriMesh, l: &BoundaryLoop, i: usize) -> Result<(Opening, Plane)> {
    let pts = l.points(mesh);
    let a = vector_area(&pts);
    // The loop runs counter-clockwise seen from inside: its vector area points into the solid.
    let plane = Plane::best_fit(&pts, &-a)
        .ok_or_else(|| Error::degenerate(format!("opening {i} ({} vertices) has no plane: no extent", pts.len())))?;
    let flatness = pts.iter().map(|p| plane.distance(p).abs()).fold(0.0, f64::max);
    let opening = Opening {
        vertices: pts.len(),
        perimeter: perimeter(&pts),
        area: plane.normal.dot(&a).abs(),
        flatness,
        centre: plane.point,
        normal: plane.normal,
    };
    Ok((opening, plane))
}

/// The rim's loops measured together on their least-squares plane (normal out of the solid).
fn measure_together(mesh: &TriMesh, rim: &[BoundaryLoop]) -> Result<(Opening, Plane)> {
    let pts: Vec<Vec<Point3>> = rim.iter().map(|l| l.points(mesh)).collect();
    let slices: Vec<&[Point3]> = pts.iter().map(|p| p.as_slice()).collect();
    let a: Vec3 = pts.iter().map(|p| vector_area(p)).sum();
    let plane =
        Plane::best_fit_loops(&slices, &-a).ok_or_else(|| Error::degenerate("the rim has no plane: no extent"))?;
    let opening = Opening {
        vertices: pts.iter().map(Vec::len).sum(),
        perimeter: pts.iter().map(|p| perimeter(p)).sum(),
        area: plane.normal.dot(&a).abs(),
        flatness: pts.iter().flatten().map(|p| plane.distance(p).abs()).fold(0.0, f64::max),
        centre: plane.point,
        normal: plane.normal,
    };
    Ok((opening, plane))
}

/// "N edges, perimeter L around (x, y, z), facing (nx, ny, nz)".
fn describe(o: &Opening) -> String {
    format!(
        "{} edges, perimeter {:.4e} around ({:.4e}, {:.4e}, {:.4e}), facing ({:.2}, {:.2}, {:.2})",
        o.vertices, o.perimeter, o.centre.x, o.centre.y, o.centre.z, o.normal.x, o.normal.y, o.normal.z
    )
}

/// Distance from `p` to the closed polyline `pts`.
fn distance_to_loop(p: &Point3, pts: &[Point3]) -> f64 {
    let n = pts.len();
    (0..n)
        .map(|i| {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            let ab = b - a;
            let t = if ab.norm_squared() > 0.0 { ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0) } else { 0.0 };
            (p - (a + ab * t)).norm()
        })
        .fold(f64::INFINITY, f64::min)
}

/// The indices of the rim's loops among the openings, the main one first (module docs, step 4).
fn choose_rim(mesh: &TriMesh, loops: &[BoundaryLoop], o: &[&Opening], choice: &RimChoice) -> Result<Vec<usize>> {
    let (lo, hi) = mesh.bounding_box().unwrap_or_default();
    let at_base = |i: usize| o[i].normal.z <= -BASE_FACING && o[i].centre.z <= (lo.z + hi.z) / 2.0;
    let main = match choice {
        RimChoice::Near(p) => (0..o.len())
            .min_by(|&a, &b| {
                distance_to_loop(p, &loops[a].points(mesh)).total_cmp(&distance_to_loop(p, &loops[b].points(mesh)))
            })
            .unwrap_or(0),
        RimChoice::Lowest => {
            let longest = (0..o.len()).max_by(|&a, &b| o[a].perimeter.total_cmp(&o[b].perimeter)).unwrap_or(0);
            if !at_base(longest) {
                return Err(open_top(o[longest]));
            }
            longest
        }
    };
    let plane = Plane { point: o[main].centre, normal: o[main].normal, e1: Vec3::zeros(), e2: Vec3::zeros() };
    let tolerance = o[main].flatness + BASE_PLANE_TOLERANCE * o[main].perimeter;
    let on_plane = |i: usize| {
        o[i].normal.dot(&plane.normal).abs() >= BASE_FACING
            && loops[i].points(mesh).iter().all(|p| plane.distance(p).abs() <= tolerance)
    };
    let mut rim = vec![main];
    rim.extend((0..o.len()).filter(|&i| i != main && on_plane(i)));
    let length: f64 = rim.iter().map(|&i| o[i].perimeter).sum();
    let large: Vec<usize> =
        (0..o.len()).filter(|&i| !rim.contains(&i) && o[i].perimeter > GAP_PERIMETER_RATIO * length).collect();
    if let Some(&top) = large.iter().find(|&&i| !at_base(i)).filter(|_| *choice == RimChoice::Lowest) {
        return Err(open_top(o[top]));
    }
    if !large.is_empty() {
        let list = std::iter::once(main).chain(large).map(|i| describe(o[i])).collect::<Vec<_>>().join("; ");
        return Err(Error::open_scan(
            ScanProblem::SeveralRims,
            format!(
                "the surface is open in several places of comparable size, not on one plane ({list}): which one is the rim of the hidden base is not clear; give a point near the rim, or close the other openings in the scan (openings shorter than {:.2} of the rim's perimeter are closed as scan gaps)",
                GAP_PERIMETER_RATIO
            ),
        ));
    }
    Ok(rim)
}

fn open_top(o: &Opening) -> Error {
    Error::open_scan(
        ScanProblem::OpenTop,
        format!(
            "the surface is open, but not only at its base: a large opening ({}) is not at the bottom of the scan (it faces up or sideways, or lies in the upper half). An open scan is read standing as the rock stands, +z up, open where it meets its pedestal; turn the scan so, give a point near the rim of its hidden base, or close that opening in the scan",
            describe(o)
        ),
    )
}
