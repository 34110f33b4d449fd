//! The hull as a parry3d collider shape: [`HullShape`].
//!
//! (Over 800 lines on purpose: one type and the five parry traits it must implement together —
//! `Shape`, `SupportMap`, `PolygonalFeatureMap`, `RayCast`, `PointQuery` — with the proofs and
//! measurements that justify each query, and its tests; split, the invariants shared by the
//! precomputation and the queries would be spread over files.)
//!
//! parry's `ConvexPolyhedron` is unfit as the collider of a pebble for two reasons (SPEC §1, §9):
//!
//! 1. it merges neighbouring hull triangles within ~1.5°, destroying the micro-facets this
//!    project is about — a pebble must be able to rest on each of its own facets;
//! 2. every step costs O(hull vertices): rapier recomputes the collider's AABB over all points,
//!    and its support point is a linear scan of all points.
//!
//! [`HullShape`] keeps the project's own [`Polyhedron`] (exactly merged facets, never re-merged:
//! facet `f` and corner `v` of the shape are facet `f` and corner `v` of the polyhedron) in f32 in
//! the body frame, and answers every per-step query in time independent of the hull size:
//!
//! * **Bounds**: the local AABB and bounding sphere are precomputed; the world AABB is the
//!   intersection of the rotated local AABB (its 8 corners) and the box of the bounding sphere, O(1).
//! * **Support point** ([`SupportMap`]): hill climbing on the vertex–edge graph, started from a
//!   precomputed cube map of directions → support vertices (≤ 32 × 32 cells per cube face, so the
//!   start is within a few degrees of the answer and a climb takes a handful of moves).
//!
//!   *Why hill climbing is exact on a convex polytope.* Let f(x) = x·d. The polytope P lies in the
//!   cone v + cone{w − v : w a neighbour of v} of every vertex v. If no neighbour w of v has
//!   f(w) > f(v), every generator of that cone has (w − v)·d ≤ 0, so f ≤ f(v) on the whole cone and
//!   hence on P: v is a global maximiser. So a climb that moves only on *strict* improvement stops
//!   exactly at a global maximiser, and it terminates because f strictly increases. Ties need no
//!   special handling: a vertex tied with the maximum is itself a maximiser, and from a
//!   non-maximiser a strictly better neighbour always exists (a plateau face is never a trap).
//!   Dot products are evaluated in f64 from the f32 corners (the products are exact, only the
//!   two additions round), so the climb agrees with a brute-force argmax evaluated the same way.
//!   The result depends only on the direction (no cache), which keeps rapier deterministic when
//!   one shape is shared by simulations on several threads.
//! * **Support feature** ([`PolygonalFeatureMap`]): always a facet, as for parry's own polyhedra
//!   and cuboids — the facet at the support vertex v whose normal is closest to the direction
//!   (compared by |n × d|, well conditioned for the tiny angles between micro-facets). Looking only
//!   at the facets around v keeps it O(1) and guarantees that the deepest point is a contact
//!   point. The feature ids are the polyhedron's facet, edge and corner indices.
//!
//!   *Why never an edge or a vertex.* The contact points are the feature's corners (those within
//!   the prediction distance), and the corners that are about to touch are what give the solver
//!   its speculative contacts. Measured: a 0.05 × 1 × 0.05 box toppling onto its side with
//!   edge/vertex features (facet only within 1° of the direction) gets contacts on the leading
//!   edge only, overshoots into the ground within a step and locks into an undamped ±3.5° rocking
//!   limit cycle 1.2 cm deep; with facet features it comes to rest exactly like
//!   `ColliderBuilder::cuboid`. The face / edge / vertex classification with an angle tolerance
//!   (default 1°, parry's) is still available as [`HullShape::support_feature_id`], which point
//!   queries report.
//!
//! # Facets with more than four corners
//!
//! A parry `PolygonalFeature` holds at most four vertices (parry's own `ConvexPolyhedron` simply
//! keeps the first four corners of a larger face). The contact points are the feature's vertices
//! (half-space ground) or its clipping with the ground's face (cuboid ground), so the four kept
//! corners are the body's support polygon. They are chosen so that the two things that matter are
//! kept exactly:
//!
//! * **which facets the body can rest on**: a body rests on facet F iff the projection of G (the
//!   local origin) onto F's plane is inside F. The reduced polygon is a quadrilateral of F's
//!   corners that contains this projection (when it is inside F; otherwise F's corner centroid),
//!   chosen to maximise the distance from that point to the quadrilateral's sides — the tipping
//!   margin. It is precomputed per facet.
//! * **no penetration of the lowest point**: when the body tilts so that a corner outside the
//!   precomputed quadrilateral is lower than all of its corners by more than 10⁻⁴ of the bounding
//!   radius, the quadrilateral is rebuilt around that corner in O(corners of the facet):
//!   the triangle of the fan from it that contains the projection of G, plus the fourth corner that
//!   maximises the margin. At rest (tilts at noise level) the precomputed quadrilateral is used, so
//!   contact ids stay the same from step to step and warm starting works.
//!
//! Sides of the reduced polygon that are hull edges carry their edge ids; chords get ids above the
//! hull's edge count.
//!
//! # Contact path in rapier
//!
//! `shape_type()` is [`ShapeType::Custom`] and the shape is not composite, so
//! `DefaultQueryDispatcher::contact_manifolds` takes its default arm and calls
//! `contact_manifold_convex_convex`. There, against a `HalfSpace` ground, the `(HalfSpace, _)` /
//! `(_, HalfSpace)` arms call `contact_manifold_halfspace_pfm` (one support-feature query per
//! update: the feature's vertices within the prediction distance are the contacts); against any
//! other convex shape (e.g. a `Cuboid` ground) the last arm calls `contact_manifold_pfm_pfm`
//! (GJK/EPA on the support maps, then clipping of the two support features).

use crate::hull::Polyhedron;
use crate::Point3;
use parry3d::bounding_volume::{Aabb, BoundingSphere};
use parry3d::mass_properties::MassProperties;
use parry3d::math::{Matrix, Pose, Real, Vector};
use parry3d::query::details::{
    local_point_projection_on_support_map, local_ray_intersection_with_support_map_with_params,
};
use parry3d::query::gjk::VoronoiSimplex;
use parry3d::query::{PointProjection, PointQuery, Ray, RayCast, RayIntersection};
use parry3d::shape::{
    FeatureId, PackedFeatureId, PolygonalFeature, PolygonalFeatureMap, Shape, ShapeType, SubShapeId, SupportMap,
    TypedShape,
};

/// Angle (radians) within which [`HullShape::support_feature_id`] reports a facet (normal within
/// it of the direction) or an edge (perpendicular to the direction within it): 1°, parry's value.
pub const DEFAULT_FEATURE_ANGLE: f64 = std::f64::consts::PI / 180.0;

/// A reduced facet polygon is rebuilt around the lowest corner when that corner is lower than the
/// precomputed quadrilateral by more than this fraction of the bounding radius.
const REDUCE_TOL_REL: f64 = 1e-4;
/// Most cells per side of a cube-map face (6 · 32² = 6144 start vertices).
const MAX_CUBE_RES: usize = 32;
/// Facets with more corners try this many fan apexes for their precomputed quadrilateral.
const QUAD_APEXES: usize = 64;
/// `PackedFeatureId` codes have 30 bits.
const FEATURE_CODE_LIMIT: u64 = 1 << 30;

#[derive(Clone, Copy, Debug)]
struct HullEdge {
    vertices: [u32; 2],
    facets: [u32; 2],
    /// Unit direction from `vertices[0]` to `vertices[1]`.
    dir: Vector,
}

/// The support feature of the hull in a direction (see [`HullShape::support_feature_id`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Feature {
    Face(u32),
    Edge(u32),
    Vertex(u32),
}

/// The project's hull as a parry3d [`Shape`]: exact facets, O(1) bounds, hill-climbing support
/// point, and support features that are the hull's own facets (see the module documentation).
#[derive(Clone, Debug)]
pub struct HullShape {
    /// Corners in the body frame, f32: `(x − origin) · scale`.
    points: Vec<Vector>,
    /// Vertex adjacency (CSR): `nbr[nbr_start[v]..nbr_start[v + 1]]` = (neighbour corner, edge).
    nbr_start: Vec<u32>,
    nbr: Vec<(u32, u32)>,
    /// Facets around each corner (CSR).
    vface_start: Vec<u32>,
    vface: Vec<u32>,
    edges: Vec<HullEdge>,
    /// Facet loops (CSR): corners counter-clockwise seen from outside, and `face_edges[k]`
    /// joining corner k to corner k + 1.
    face_start: Vec<u32>,
    face_corners: Vec<u32>,
    face_edges: Vec<u32>,
    /// Outward unit normals, f64 (from the exact hull) and f32.
    normals64: Vec<[f64; 3]>,
    normals: Vec<Vector>,
    /// Per facet with more than four corners: the loop positions of its precomputed support
    /// quadrilateral and the point (body frame) it is built to cover.
    quads: Vec<[u32; 4]>,
    targets: Vec<[f64; 3]>,
    local_aabb: Aabb,
    local_sphere: BoundingSphere,
    /// Cube map of start vertices: `cube_res²` cells per face, faces ordered +x, −x, +y, −y, +z, −z.
    cube_res: usize,
    cube: Vec<u32>,
    feature_angle: f64,
    sin_eps: Real,
    reduce_tol: f64,
    /// The input-frame origin and scale of [`HullShape::new`] (identity after [`HullShape::scaled`]).
    frame_origin: Point3,
    frame_scale: f64,
    /// Volume, centre of mass and inertia about the centre of mass at unit density (f64): the
    /// hull's, or the solid's after [`HullShape::with_solid_mass`].
    unit_volume: f64,
    unit_com: [f64; 3],
    unit_inertia: [[f64; 3]; 3],
}

#[inline]
fn dot64(p: Vector, d: &[f64; 3]) -> f64 {
    p.x as f64 * d[0] + p.y as f64 * d[1] + p.z as f64 * d[2]
}

#[inline]
fn to64(p: Vector) -> [f64; 3] {
    [p.x as f64, p.y as f64, p.z as f64]
}

#[inline]
fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
fn cross3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

#[inline]
fn cross2(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

#[inline]
fn sub2(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// Signed distance from `t` to the line a→b, positive on its left.
#[inline]
fn left_dist(a: [f64; 2], b: [f64; 2], t: [f64; 2]) -> f64 {
    let e = sub2(b, a);
    let l = (e[0] * e[0] + e[1] * e[1]).sqrt();
    if l > 0.0 {
        cross2(e, sub2(t, a)) / l
    } else {
        f64::NEG_INFINITY
    }
}

/// An orthonormal pair (e1, e2) with e1 × e2 = n, so counter-clockwise seen from outside is
/// counter-clockwise in (e1, e2) coordinates.
fn plane_basis(n: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let a = if n[0].abs() < 0.6 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
    let e1 = cross3(a, n);
    let l = dot3(e1, e1).sqrt();
    let e1 = [e1[0] / l, e1[1] / l, e1[2] / l];
    (e1, cross3(n, e1))
}

/// Cube-map cell of a direction, `None` for a zero or non-finite direction.
#[inline]
fn cube_cell(res: usize, d: Vector) -> Option<usize> {
    let c = [d.x, d.y, d.z];
    let a = [c[0].abs(), c[1].abs(), c[2].abs()];
    let axis = if a[0] >= a[1] && a[0] >= a[2] {
        0
    } else if a[1] >= a[2] {
        1
    } else {
        2
    };
    let m = a[axis];
    if !(m > 0.0 && m.is_finite()) {
        return None;
    }
    let side = (c[axis] < 0.0) as usize;
    let cell = |x: Real| ((((x / m) + 1.0) * 0.5 * res as Real) as usize).min(res - 1);
    Some(((axis * 2 + side) * res + cell(c[(axis + 1) % 3])) * res + cell(c[(axis + 2) % 3]))
}

/// The direction through the centre of a cube-map cell.
fn cube_cell_dir(res: usize, cell: usize) -> Vector {
    let face = cell / (res * res);
    let (iu, iv) = ((cell / res) % res, cell % res);
    let (axis, sign) = (face / 2, if face % 2 == 0 { 1.0 } else { -1.0 });
    let centre = |i: usize| -1.0 + (i as f64 + 0.5) * 2.0 / res as f64;
    let mut c = [0.0f64; 3];
    c[axis] = sign;
    c[(axis + 1) % 3] = centre(iu);
    c[(axis + 2) % 3] = centre(iv);
    Vector::new(c[0] as Real, c[1] as Real, c[2] as Real)
}

impl HullShape {
    /// The hull `poly` as a collider in the body frame: corners stored as f32 `(x − origin)·scale`.
    ///
    /// `origin` should be the solid's centre of mass G, so that the local frame is the body frame
    /// of the rigid body (rapier mass properties) and the reduced support polygons of facets with
    /// more than four corners cover the projection of G (see the module documentation).
    ///
    /// # Panics
    /// If `scale` is not finite and positive.
    pub fn new(poly: &Polyhedron, origin: &Point3, scale: f64) -> HullShape {
        assert!(scale.is_finite() && scale > 0.0, "HullShape::new: scale must be finite and positive, got {scale}");
        let points = poly
            .vertices
            .iter()
            .map(|p| {
                let q = (p - origin) * scale;
                Vector::new(q.x as Real, q.y as Real, q.z as Real)
            })
            .collect();
        let loops = poly.facets.iter().map(|f| (f.vertices.clone(), f.edges.clone())).collect();
        let normals = poly.facets.iter().map(|f| [f.normal.x, f.normal.y, f.normal.z]).collect();
        let edges = poly.edges.iter().map(|e| (e.vertices, e.facets)).collect();
        let mut shape = Self::build(points, loops, normals, edges, DEFAULT_FEATURE_ANGLE);
        shape.frame_origin = *origin;
        shape.frame_scale = scale;
        shape
    }

    /// The same shape reporting the *solid's* mass properties (volume, G and inertia of the
    /// scanned body, SPEC §1, in the input frame as computed by
    /// [`crate::solid::MassProperties::of`]) from [`Shape::mass_properties`], mapped to the body
    /// frame of [`HullShape::new`], instead of those of the hull. A collider built with a density
    /// then gets the right mass, G and inertia without further setting.
    pub fn with_solid_mass(mut self, solid: &crate::solid::MassProperties) -> HullShape {
        let s = self.frame_scale;
        let g = (solid.center_of_mass - self.frame_origin) * s;
        self.unit_volume = solid.volume * s.powi(3);
        self.unit_com = [g.x, g.y, g.z];
        self.unit_inertia = std::array::from_fn(|i| std::array::from_fn(|j| solid.inertia[(i, j)] * s.powi(5)));
        self
    }

    /// The same shape with another feature angle (radians, in (0, π/2)) for
    /// [`HullShape::support_feature_id`]: the largest angle between a facet normal and the
    /// direction for which the facet is reported (and between an edge and the plane perpendicular
    /// to the direction for an edge).
    ///
    /// # Panics
    /// If the angle is not in (0, π/2).
    pub fn with_feature_angle(mut self, radians: f64) -> HullShape {
        assert!(radians > 0.0 && radians < std::f64::consts::FRAC_PI_2, "feature angle {radians} not in (0, π/2)");
        self.feature_angle = radians;
        self.sin_eps = radians.sin() as Real;
        self
    }

    fn build(
        points: Vec<Vector>,
        loops: Vec<(Vec<u32>, Vec<u32>)>,
        normals64: Vec<[f64; 3]>,
        edge_list: Vec<([u32; 2], [u32; 2])>,
        feature_angle: f64,
    ) -> HullShape {
        let nv = points.len();
        // Facet loops.
        let mut face_start = Vec::with_capacity(loops.len() + 1);
        let mut face_corners = Vec::new();
        let mut face_edges = Vec::new();
        face_start.push(0u32);
        for (c, e) in &loops {
            debug_assert_eq!(c.len(), e.len());
            face_corners.extend_from_slice(c);
            face_edges.extend_from_slice(e);
            face_start.push(face_corners.len() as u32);
        }
        let normals = normals64.iter().map(|n| Vector::new(n[0] as Real, n[1] as Real, n[2] as Real)).collect();
        // Edges and vertex adjacency.
        let edges: Vec<HullEdge> = edge_list
            .iter()
            .map(|&(v, f)| {
                let d = sub3(to64(points[v[1] as usize]), to64(points[v[0] as usize]));
                let l = dot3(d, d).sqrt();
                let dir = Vector::new((d[0] / l) as Real, (d[1] / l) as Real, (d[2] / l) as Real);
                HullEdge { vertices: v, facets: f, dir }
            })
            .collect();
        let (nbr_start, nbr) = csr(
            nv,
            edges.iter().enumerate().flat_map(|(id, e)| {
                let [a, b] = e.vertices;
                [(a, (b, id as u32)), (b, (a, id as u32))]
            }),
        );
        let (vface_start, vface) =
            csr(nv, loops.iter().enumerate().flat_map(|(f, (c, _))| c.iter().map(move |&v| (v, f as u32))));
        // Bounds.
        let (lo, hi) = points.iter().fold((points[0], points[0]), |(l, h), &p| (l.min(p), h.max(p)));
        let local_aabb = Aabb::new(lo, hi);
        let centre = local_aabb.center();
        let radius = points.iter().map(|p| (*p - centre).length()).fold(0.0, Real::max);
        let local_sphere = BoundingSphere::new(centre, radius);
        let cube_res = (((nv as f64) / 24.0).sqrt().ceil() as usize).clamp(1, MAX_CUBE_RES);
        let mut shape = HullShape {
            points,
            nbr_start,
            nbr,
            vface_start,
            vface,
            edges,
            face_start,
            face_corners,
            face_edges,
            normals64,
            normals,
            quads: Vec::new(),
            targets: Vec::new(),
            local_aabb,
            local_sphere,
            cube_res,
            cube: Vec::new(),
            feature_angle,
            sin_eps: feature_angle.sin() as Real,
            reduce_tol: REDUCE_TOL_REL * radius as f64,
            frame_origin: Point3::origin(),
            frame_scale: 1.0,
            unit_volume: 0.0,
            unit_com: [0.0; 3],
            unit_inertia: [[0.0; 3]; 3],
        };
        // Cube map: each cell's support vertex, climbing from the previous cell's.
        let mut start = 0u32;
        shape.cube = (0..6 * cube_res * cube_res)
            .map(|cell| {
                start = shape.climb(start, &to64(cube_cell_dir(cube_res, cell)));
                start
            })
            .collect();
        // Reduced support polygons of facets with more than four corners.
        let nf = shape.normals.len();
        shape.targets = (0..nf).map(|f| shape.facet_target(f)).collect();
        shape.quads = (0..nf).map(|f| shape.static_quad(f)).collect();
        shape.compute_unit_mass();
        shape
    }

    /// Number of corners.
    pub fn num_vertices(&self) -> usize {
        self.points.len()
    }

    /// Number of facets.
    pub fn num_facets(&self) -> usize {
        self.normals.len()
    }

    /// Number of edges.
    pub fn num_edges(&self) -> usize {
        self.edges.len()
    }

    /// The corners in the body frame (index = corner index of the polyhedron).
    pub fn points(&self) -> &[Vector] {
        &self.points
    }

    /// Corners of facet `f`, counter-clockwise seen from outside (same as the polyhedron's).
    pub fn facet_corners(&self, f: usize) -> &[u32] {
        &self.face_corners[self.face_start[f] as usize..self.face_start[f + 1] as usize]
    }

    /// Outward unit normal of facet `f`, f32.
    pub fn facet_normal(&self, f: usize) -> Vector {
        self.normals[f]
    }

    /// The feature angle (radians), see [`HullShape::with_feature_angle`].
    pub fn feature_angle(&self) -> f64 {
        self.feature_angle
    }

    /// Corners of facet `f` kept in its support polygon when the body rests on it (all of them for
    /// facets with at most four corners, otherwise the precomputed quadrilateral).
    pub fn facet_support_corners(&self, f: usize) -> Vec<u32> {
        let cs = self.facet_corners(f);
        if cs.len() <= 4 {
            cs.to_vec()
        } else {
            self.quads[f].iter().map(|&i| cs[i as usize]).collect()
        }
    }

    #[inline]
    fn neighbours(&self, v: u32) -> &[(u32, u32)] {
        &self.nbr[self.nbr_start[v as usize] as usize..self.nbr_start[v as usize + 1] as usize]
    }

    #[inline]
    fn faces_at(&self, v: u32) -> &[u32] {
        &self.vface[self.vface_start[v as usize] as usize..self.vface_start[v as usize + 1] as usize]
    }

    #[inline]
    fn facet_edges(&self, f: usize) -> &[u32] {
        &self.face_edges[self.face_start[f] as usize..self.face_start[f + 1] as usize]
    }

    /// Steepest-ascent hill climbing from `v` ([`crate::hull::hill_climb`]).
    #[inline]
    fn climb(&self, v: u32, d: &[f64; 3]) -> u32 {
        crate::hull::hill_climb(
            v,
            |v| self.neighbours(v).iter().map(|&(w, _)| w),
            |w| dot64(self.points[w as usize], d),
        )
    }

    /// Index of a corner maximising x·dir (exact, see the module documentation); corner 0 for a
    /// zero or non-finite direction.
    #[inline]
    pub fn support_vertex(&self, dir: Vector) -> u32 {
        match cube_cell(self.cube_res, dir) {
            Some(cell) => self.climb(self.cube[cell], &to64(dir)),
            None => 0,
        }
    }

    /// The facet at corner `v` whose normal is closest to the unit direction `d` among those with
    /// n·d > 0, and the squared sine of its angle to `d`. Compared by the sine (|n × d|), which is
    /// well conditioned for the small angles between micro-facets, unlike the cosine.
    #[inline]
    fn closest_facet_at_with_sin2(&self, v: u32, d: Vector) -> Option<(u32, Real)> {
        let mut best: Option<(u32, Real)> = None;
        for &f in self.faces_at(v) {
            let n = self.normals[f as usize];
            if n.dot(d) > 0.0 {
                let s2 = n.cross(d).length_squared();
                if best.is_none_or(|b| s2 < b.1) {
                    best = Some((f, s2));
                }
            }
        }
        best
    }

    #[inline]
    fn closest_facet_at(&self, v: u32, d: Vector) -> Option<u32> {
        self.closest_facet_at_with_sin2(v, d).map(|b| b.0)
    }

    /// Support vertex and the support feature towards `dir`.
    fn feature_toward(&self, dir: Vector) -> (u32, Feature) {
        let v = self.support_vertex(dir);
        let d = dir.normalize_or_zero();
        if d == Vector::ZERO {
            return (v, Feature::Vertex(v));
        }
        if let Some((f, s2)) = self.closest_facet_at_with_sin2(v, d) {
            if s2 <= self.sin_eps * self.sin_eps {
                return (v, Feature::Face(f));
            }
        }
        let mut best = (Real::INFINITY, u32::MAX);
        for &(_, e) in self.neighbours(v) {
            let c = self.edges[e as usize].dir.dot(d).abs();
            if c < best.0 {
                best = (c, e);
            }
        }
        if best.1 != u32::MAX && best.0 <= self.sin_eps {
            return (v, Feature::Edge(best.1));
        }
        (v, Feature::Vertex(v))
    }

    /// The facet rapier's contacts come from towards `dir` (the facet of
    /// [`PolygonalFeatureMap::local_support_feature`]): among the facets at the support vertex,
    /// the one whose normal is closest to `dir`. O(1); for a body at rest, `dir` = down in the body
    /// frame gives the facet it rests on.
    pub fn support_facet(&self, dir: Vector) -> u32 {
        let v = self.support_vertex(dir);
        self.closest_facet_at(v, dir.normalize_or_zero()).unwrap_or(self.faces_at(v)[0])
    }

    /// The support feature towards `dir`: `Face(f)` for the facet at the support vertex whose
    /// normal is within the feature angle of `dir` (the closest one), else `Edge(e)` for an edge
    /// at the support vertex perpendicular to `dir` within that angle, else `Vertex(v)`. Indices
    /// are the polyhedron's facet, edge and corner indices.
    pub fn support_feature_id(&self, dir: Vector) -> FeatureId {
        match self.feature_toward(dir).1 {
            Feature::Face(f) => FeatureId::Face(f),
            Feature::Edge(e) => FeatureId::Edge(e),
            Feature::Vertex(v) => FeatureId::Vertex(v),
        }
    }

    /// The point (body frame, f64) the reduced support polygon of facet `f` is built to cover: the
    /// projection of the origin (G) on the facet plane when it lies strictly inside the facet,
    /// else the centroid of the corners.
    fn facet_target(&self, f: usize) -> [f64; 3] {
        let cs = self.facet_corners(f);
        let n = self.normals64[f];
        let pts: Vec<[f64; 3]> = cs.iter().map(|&c| to64(self.points[c as usize])).collect();
        let offset = pts.iter().map(|p| dot3(n, *p)).sum::<f64>() / pts.len() as f64;
        let proj = [n[0] * offset, n[1] * offset, n[2] * offset];
        let (e1, e2) = plane_basis(n);
        let p2 = |p: [f64; 3]| [dot3(p, e1), dot3(p, e2)];
        let t = p2(proj);
        let inside = (0..pts.len()).all(|k| left_dist(p2(pts[k]), p2(pts[(k + 1) % pts.len()]), t) > 0.0);
        if inside {
            proj
        } else {
            let s = pts.iter().fold([0.0; 3], |a, p| [a[0] + p[0], a[1] + p[1], a[2] + p[2]]);
            let k = pts.len() as f64;
            [s[0] / k, s[1] / k, s[2] / k]
        }
    }

    /// The quadrilateral of facet `f`'s corners containing corner `apex` (a loop position) that
    /// covers the facet's target point: the fan triangle from `apex` that contains the target
    /// (deepest inside), plus the corner that maximises the target's distance to the sides.
    /// Returns loop positions in cyclic order and that distance (the margin).
    fn quad_with_apex(&self, f: usize, apex: usize) -> ([u32; 4], f64) {
        let cs = self.facet_corners(f);
        let k = cs.len();
        let (e1, e2) = plane_basis(self.normals64[f]);
        let p2 = |p: [f64; 3]| [dot3(p, e1), dot3(p, e2)];
        let at = |r: usize| p2(to64(self.points[cs[(apex + r) % k] as usize]));
        let t = p2(self.targets[f]);
        let a = at(0);
        let (mut j, mut best) = (1, f64::NEG_INFINITY);
        for r in 1..k - 1 {
            let (b, c) = (at(r), at(r + 1));
            let area = cross2(sub2(b, a), sub2(c, a));
            if area <= 0.0 {
                continue;
            }
            let m = (cross2(sub2(c, b), sub2(t, b))
                .min(cross2(sub2(a, c), sub2(t, c)))
                .min(cross2(sub2(b, a), sub2(t, a))))
                / area;
            if m > best {
                best = m;
                j = r;
            }
        }
        let (mut quad, mut margin) = ([0, j, j + 1, j + 1], f64::NEG_INFINITY);
        for r in 1..k {
            if r == j || r == j + 1 {
                continue;
            }
            let q = if r < j { [0, r, j, j + 1] } else { [0, j, j + 1, r] };
            let m = (0..4).map(|i| left_dist(at(q[i]), at(q[(i + 1) % 4]), t)).fold(f64::INFINITY, f64::min);
            if m > margin {
                margin = m;
                quad = q;
            }
        }
        (quad.map(|r| ((apex + r) % k) as u32), margin)
    }

    /// The precomputed support quadrilateral of facet `f` (loop positions); the identity for
    /// facets with at most four corners.
    fn static_quad(&self, f: usize) -> [u32; 4] {
        let k = self.facet_corners(f).len();
        if k <= 4 {
            return [0, 1, 2, 3];
        }
        let apexes = k.min(QUAD_APEXES);
        let mut best = ([0, 1, 2, 3], f64::NEG_INFINITY);
        for i in 0..apexes {
            let (q, m) = self.quad_with_apex(f, i * k / apexes);
            if m > best.1 {
                best = (q, m);
            }
        }
        best.0
    }

    /// Feature id of the side from loop position `a` to `b` of facet `f` (a hull edge or a chord).
    fn side_id(&self, f: usize, a: u32, b: u32) -> PackedFeatureId {
        let cs = self.facet_corners(f);
        let k = cs.len() as u32;
        if b == (a + 1) % k {
            PackedFeatureId::edge(self.facet_edges(f)[a as usize])
        } else {
            let (u, w) = (cs[a as usize].min(cs[b as usize]) as u64, cs[a as usize].max(cs[b as usize]) as u64);
            let ne = self.edges.len() as u64;
            let code = ne + (u * self.points.len() as u64 + w) % (FEATURE_CODE_LIMIT - ne).max(1);
            PackedFeatureId::edge(code.min(FEATURE_CODE_LIMIT - 1) as u32)
        }
    }

    /// Writes facet `f` (or its reduced quadrilateral) as a polygonal feature; `v` is the support
    /// vertex (a corner of `f`) and `dir` the support direction.
    fn write_face(&self, f: usize, v: u32, dir: Vector, out: &mut PolygonalFeature) {
        let cs = self.facet_corners(f);
        let k = cs.len();
        let mut pos = [0u32, 1, 2, 3];
        let n = if k <= 4 {
            k
        } else {
            pos = self.quads[f];
            if !pos.iter().any(|&i| cs[i as usize] == v) {
                let d = to64(dir);
                let depth = |c: u32| dot64(self.points[c as usize], &d);
                let quad_deepest = pos.iter().map(|&i| depth(cs[i as usize])).fold(f64::NEG_INFINITY, f64::max);
                if depth(v) - quad_deepest > self.reduce_tol * dot3(d, d).sqrt() {
                    let apex = cs.iter().position(|&c| c == v).unwrap_or(0);
                    pos = self.quad_with_apex(f, apex).0;
                }
            }
            4
        };
        for i in 0..4 {
            let p = pos[i.min(n - 1)];
            let c = cs[p as usize];
            out.vertices[i] = self.points[c as usize];
            out.vids[i] = PackedFeatureId::vertex(c);
            out.eids[i] = self.side_id(f, p, pos[(i.min(n - 1) + 1) % n]);
        }
        out.fid = PackedFeatureId::face(f as u32);
        out.num_vertices = n;
    }

    /// Mass properties of the hull at unit density, in f64 from the f32 corners (fan triangles of
    /// the facets, tetrahedra from the local origin).
    fn compute_unit_mass(&mut self) {
        let (mut vol, mut first, mut second) = (0.0, [0.0f64; 3], [[0.0f64; 3]; 3]);
        for f in 0..self.num_facets() {
            let cs = self.facet_corners(f);
            let a = to64(self.points[cs[0] as usize]);
            for w in cs[1..].windows(2) {
                let (b, c) = (to64(self.points[w[0] as usize]), to64(self.points[w[1] as usize]));
                let det = dot3(a, cross3(b, c));
                vol += det / 6.0;
                let s = [a[0] + b[0] + c[0], a[1] + b[1] + c[1], a[2] + b[2] + c[2]];
                for i in 0..3 {
                    first[i] += det / 24.0 * s[i];
                    for j in 0..3 {
                        second[i][j] += det / 120.0 * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
                    }
                }
            }
        }
        let com = [first[0] / vol, first[1] / vol, first[2] / vol];
        let tr = second[0][0] + second[1][1] + second[2][2];
        let c2 = dot3(com, com);
        let mut inertia = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                let id = if i == j { 1.0 } else { 0.0 };
                inertia[i][j] = tr * id - second[i][j] - vol * (c2 * id - com[i] * com[j]);
            }
        }
        self.unit_volume = vol;
        self.unit_com = com;
        self.unit_inertia = inertia;
    }

    /// The hull scaled by a positive factor per axis about the body-frame origin (`None` for a
    /// zero, negative or non-finite factor). Its mass properties are the scaled hull's.
    pub fn scaled(&self, scale: Vector) -> Option<HullShape> {
        if !(scale.min_element() > 0.0 && scale.is_finite()) {
            return None;
        }
        let points = self.points.iter().map(|&p| p * scale).collect();
        let loops =
            (0..self.num_facets()).map(|f| (self.facet_corners(f).to_vec(), self.facet_edges(f).to_vec())).collect();
        let s = to64(scale);
        let normals = self
            .normals64
            .iter()
            .map(|n| {
                let m = [n[0] / s[0], n[1] / s[1], n[2] / s[2]];
                let l = dot3(m, m).sqrt();
                [m[0] / l, m[1] / l, m[2] / l]
            })
            .collect();
        let edges = self.edges.iter().map(|e| (e.vertices, e.facets)).collect();
        Some(Self::build(points, loops, normals, edges, self.feature_angle))
    }
}

/// Compressed rows from (row, value) pairs, rows in `0..n`, values in input order.
fn csr<T: Copy>(n: usize, pairs: impl Iterator<Item = (u32, T)> + Clone) -> (Vec<u32>, Vec<T>) {
    let mut start = vec![0u32; n + 1];
    for (r, _) in pairs.clone() {
        start[r as usize + 1] += 1;
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut out: Vec<Option<T>> = vec![None; start[n] as usize];
    for (r, x) in pairs {
        out[fill[r as usize] as usize] = Some(x);
        fill[r as usize] += 1;
    }
    (start, out.into_iter().map(|x| x.expect("every slot filled")).collect())
}

impl SupportMap for HullShape {
    #[inline]
    fn local_support_point(&self, dir: Vector) -> Vector {
        self.points[self.support_vertex(dir) as usize]
    }
}

impl PolygonalFeatureMap for HullShape {
    fn local_support_feature(&self, dir: Vector, out: &mut PolygonalFeature) {
        let v = self.support_vertex(dir);
        let f = self.closest_facet_at(v, dir.normalize_or_zero()).unwrap_or(self.faces_at(v)[0]);
        self.write_face(f as usize, v, dir, out);
    }
}

impl RayCast for HullShape {
    fn cast_local_ray_and_get_normal(
        &self,
        ray: &Ray,
        max_time_of_impact: Real,
        solid: bool,
    ) -> Option<RayIntersection> {
        local_ray_intersection_with_support_map_with_params(
            self,
            &mut VoronoiSimplex::new(),
            ray,
            max_time_of_impact,
            solid,
        )
    }
}

impl PointQuery for HullShape {
    fn project_local_point(&self, point: Vector, solid: bool) -> PointProjection {
        local_point_projection_on_support_map(self, &mut VoronoiSimplex::new(), point, solid)
    }

    fn project_local_point_and_get_feature(&self, point: Vector) -> (PointProjection, FeatureId) {
        let proj = self.project_local_point(point, false);
        let dpt = point - proj.point;
        let dir = if proj.is_inside { -dpt } else { dpt };
        match dir.try_normalize() {
            Some(dir) => (proj, self.support_feature_id(dir)),
            None => (proj, FeatureId::Unknown),
        }
    }
}

impl Shape for HullShape {
    fn compute_local_aabb(&self) -> Aabb {
        self.local_aabb
    }

    fn compute_local_bounding_sphere(&self) -> BoundingSphere {
        self.local_sphere
    }

    fn clone_dyn(&self) -> Box<dyn Shape> {
        Box::new(self.clone())
    }

    fn scale_dyn(&self, scale: Vector, _num_subdivisions: u32) -> Option<Box<dyn Shape>> {
        Some(Box::new(self.scaled(scale)?))
    }

    /// O(1): the rotated local AABB intersected with the box of the bounding sphere.
    fn compute_aabb(&self, position: &Pose) -> Aabb {
        let a = self.local_aabb.transform_by(position);
        let c = position * self.local_sphere.center;
        let r = Vector::splat(self.local_sphere.radius);
        Aabb::new(a.mins.max(c - r), a.maxs.min(c + r))
    }

    fn compute_bounding_sphere(&self, position: &Pose) -> BoundingSphere {
        self.local_sphere.transform_by(position)
    }

    fn mass_properties(&self, density: Real) -> MassProperties {
        let rho = density as f64;
        let i = &self.unit_inertia;
        let col = |j: usize| Vector::new((i[0][j] * rho) as Real, (i[1][j] * rho) as Real, (i[2][j] * rho) as Real);
        let com = Vector::new(self.unit_com[0] as Real, self.unit_com[1] as Real, self.unit_com[2] as Real);
        MassProperties::with_inertia_matrix(
            com,
            (self.unit_volume * rho) as Real,
            Matrix::from_cols(col(0), col(1), col(2)),
        )
    }

    fn shape_type(&self) -> ShapeType {
        ShapeType::Custom
    }

    fn as_typed_shape(&self) -> TypedShape<'_> {
        TypedShape::Custom(self)
    }

    fn ccd_thickness(&self) -> Real {
        self.local_aabb.half_extents().min_element()
    }

    fn ccd_angular_thickness(&self) -> Real {
        std::f64::consts::FRAC_PI_4 as Real
    }

    fn is_convex(&self) -> bool {
        true
    }

    fn as_support_map(&self) -> Option<&dyn SupportMap> {
        Some(self as &dyn SupportMap)
    }

    fn as_polygonal_feature_map(&self) -> Option<(&dyn PolygonalFeatureMap, Real)> {
        Some((self as &dyn PolygonalFeatureMap, 0.0))
    }

    fn feature_normal_at_point(&self, _subshape: SubShapeId, feature: FeatureId, _point: Vector) -> Option<Vector> {
        match feature {
            FeatureId::Face(f) => self.normals.get(f as usize).copied(),
            FeatureId::Edge(e) => {
                let [f0, f1] = self.edges.get(e as usize)?.facets;
                (self.normals[f0 as usize] + self.normals[f1 as usize]).try_normalize()
            }
            FeatureId::Vertex(v) => {
                if v as usize >= self.points.len() {
                    return None;
                }
                self.faces_at(v).iter().map(|&f| self.normals[f as usize]).sum::<Vector>().try_normalize()
            }
            FeatureId::Unknown => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate;
    use crate::hull::DEFAULT_COPLANAR_TOL;

    fn cube() -> HullShape {
        let mesh = generate::cuboid(1.0, 1.0, 1.0);
        let poly = Polyhedron::new(&mesh.vertices, DEFAULT_COPLANAR_TOL).unwrap();
        HullShape::new(&poly, &Point3::origin(), 1.0)
    }

    #[test]
    fn cube_map_cells_round_trip() {
        for res in [1, 2, 5, 32] {
            for cell in 0..6 * res * res {
                assert_eq!(cube_cell(res, cube_cell_dir(res, cell)), Some(cell), "res {res} cell {cell}");
            }
        }
        assert_eq!(cube_cell(4, Vector::ZERO), None);
        assert_eq!(cube_cell(4, Vector::new(Real::NAN, 0.0, 0.0)), None);
    }

    #[test]
    fn csr_keeps_order() {
        let (s, v) = csr(3, [(2u32, 'a'), (0, 'b'), (2, 'c')].into_iter());
        assert_eq!(s, vec![0, 1, 1, 3]);
        assert_eq!(v, vec!['b', 'a', 'c']);
    }

    #[test]
    fn unit_cube_mass_and_bounds() {
        let s = cube();
        assert!((s.unit_volume - 1.0).abs() < 1e-12);
        assert!(s.unit_com.iter().all(|c| c.abs() < 1e-12));
        for i in 0..3 {
            for j in 0..3 {
                let want = if i == j { 1.0 / 6.0 } else { 0.0 };
                assert!((s.unit_inertia[i][j] - want).abs() < 1e-12, "{:?}", s.unit_inertia);
            }
        }
        assert_eq!(s.compute_local_aabb().mins, Vector::splat(-0.5));
        assert!((s.compute_local_bounding_sphere().radius - 0.75f32.sqrt()).abs() < 1e-6);
    }

    #[test]
    fn zero_direction_is_harmless() {
        let s = cube();
        let mut f = PolygonalFeature::default();
        s.local_support_feature(Vector::ZERO, &mut f);
        assert_eq!(f.num_vertices, 4);
        assert_eq!(s.support_feature_id(Vector::ZERO), FeatureId::Vertex(0));
        let _ = s.local_support_point(Vector::new(Real::NAN, 1.0, 0.0));
    }
}
