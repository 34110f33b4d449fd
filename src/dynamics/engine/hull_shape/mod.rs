//! The hull as a parry3d collider shape: [`HullShape`].
//!
//! The type, its construction and its accessors are here; the queries are split by concept
//! into the submodules: `vec64` (f64 arithmetic on the f32 corners), `cube_map` (directions →
//! start vertices of the climb), `support` (support point and support feature: [`SupportMap`],
//! [`PolygonalFeatureMap`]), `reduce` (the support polygons of facets with more than four
//! corners), `mass` (mass properties) and `parry_shape` ([`Shape`], [`RayCast`], [`PointQuery`]).
//!
//! parry's `ConvexPolyhedron` is unfit as the collider of a pebble for two reasons:
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
//!   (compared by |n × d|, well conditioned for the tiny angles between micro-facets), unless the
//!   body touches a stable facet there (next section). Looking only at the facets around v keeps
//!   it O(1) and guarantees that the deepest point is a contact point. The feature ids are the
//!   polyhedron's facet, edge and corner indices.
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
//! # Resting on a stable facet
//!
//! A scanned stone often rests on a stable facet F whose neighbour F′ (sharing an edge) is within
//! 10⁻⁴–10⁻³ rad of it and unstable (G projects outside F′). The soft contact lets the body tilt
//! by that much (a compression of 10⁻⁴ R_max across a micro-facet of 0.1 R_max), so "the facet
//! closest to the direction" flips between F and F′ from one step to the next; each flip renews
//! the loaded contact points (warm starts lost, the load moved to other corners) and kicks the
//! body. Measured on the stones that would not settle at dt = 1/120 s (`results/drops_settling/`):
//! Prometheus, Itokawa, quarry stone A0 and Tempel 1 rocked on such a pair for the whole 60 s cap,
//! the contact facet flipping every second step (Prometheus: facets 1814/1815, 1.0·10⁻³ rad apart,
//! the body tilted 4.8–5.6·10⁻⁴ rad from 1814 — across their bisector).
//!
//! So the contact comes from a stable facet whenever the body touches one: among the facets at the
//! support vertex v, a stable facet all of whose kept corners lie within the touch tolerance
//! (10⁻³ of the bounding radius, the penetration the solver allows) of the support plane is
//! preferred to the closest facet; among several, the closest. The body can rest only on a stable
//! facet, and when it touches one with every corner its load is on those corners; tilted off it by
//! more than the tolerance (rolling), or once the lowest corner is not one of its corners, the
//! closest facet is used as before. Towards a stable facet's own normal its own feature is
//! returned (it touches with tolerance 0 and is the closest), so every stable facet stays a
//! distinct rest. Measured: with this rule (and the rolling resistance of `dynamics::engine::contact` about
//! the contact patch) every one of the 40 meshes of `results/drops_settling/` settles at 1/120 s.
//!
//! *Only the facets at v.* Extending the candidates to the facets at corners tied with v (within
//! 10⁻⁴ of the radius) also caught a stone that pivots between v and a tied neighbour, but on a
//! scanned flat base (hundreds of micro-facets 10⁻⁴ h deep) it handed the contact to the stable
//! facet under G while the load sat on the base's outer corners, and a rock pushed sideways
//! tipped below Housner's threshold (`tests/shake_rock.rs`); so the deepest corner stays a
//! contact point.
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
//!
//! So the hull-on-plane contact already is the support function's: the
//! support vertex by hill climbing, the facet at it closest to the plane's normal (reduced to at
//! most four corners as above), and each corner's signed distance to the plane — no GJK, no
//! generic polyhedron test. Rapier takes the manifold this way without a custom dispatcher. The
//! distances are computed by parry in f32 (rapier's solver is f32 throughout, so f64 distances
//! would be rounded on the way in anyway); what made impacts start deep was not this manifold
//! but *when* it was asked (only at step boundaries), which [`crate::dynamics::engine::flight`] and
//! [`crate::dynamics::engine::impact`] now resolve.
//!
//! [`SupportMap`]: parry3d::shape::SupportMap
//! [`PolygonalFeatureMap`]: parry3d::shape::PolygonalFeatureMap
//! [`Shape`]: parry3d::shape::Shape
//! [`ShapeType::Custom`]: parry3d::shape::ShapeType::Custom
//! [`RayCast`]: parry3d::query::RayCast
//! [`PointQuery`]: parry3d::query::PointQuery

mod cube_map;
mod mass;
mod parry_shape;
mod reduce;
mod support;
mod vec64;

use crate::hull::Polyhedron;
use crate::Point3;
use parry3d::bounding_volume::{Aabb, BoundingSphere};
use parry3d::math::{Real, Vector};

use cube_map::cube_cell_dir;
use vec64::{dot3, sub3, to64};

/// Angle (radians) within which [`HullShape::support_feature_id`] reports a facet (normal within
/// it of the direction) or an edge (perpendicular to the direction within it): 1°, parry's value.
pub const DEFAULT_FEATURE_ANGLE: f64 = std::f64::consts::PI / 180.0;

/// A reduced facet polygon is rebuilt around the lowest corner when that corner is lower than the
/// precomputed quadrilateral by more than this fraction of the bounding radius.
const REDUCE_TOL_REL: f64 = 1e-4;
/// A body touches a facet with its whole support polygon when every corner of that polygon is
/// within this fraction of the bounding radius of the support plane: the penetration the contact
/// solver allows (`world::ALLOWED_PENETRATION`, 10⁻³ R_max). See "Resting on a stable facet".
const TOUCH_TOL_REL: f64 = 1e-3;
/// Most cells per side of a cube-map face (6 · 32² = 6144 start vertices).
const MAX_CUBE_RES: usize = 32;

#[derive(Clone, Copy, Debug)]
struct HullEdge {
    vertices: [u32; 2],
    facets: [u32; 2],
    /// Unit direction from `vertices[0]` to `vertices[1]`.
    dir: Vector,
}

/// The project's hull as a parry3d [`Shape`](parry3d::shape::Shape): exact facets, O(1) bounds, hill-climbing support
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
    /// Per facet: whether the origin (G) projects strictly inside it (a stable facet).
    stable: Vec<bool>,
    local_aabb: Aabb,
    local_sphere: BoundingSphere,
    /// Cube map of start vertices: `cube_res²` cells per face, faces ordered +x, −x, +y, −y, +z, −z.
    cube_res: usize,
    cube: Vec<u32>,
    feature_angle: f64,
    sin_eps: Real,
    reduce_tol: f64,
    /// [`TOUCH_TOL_REL`] times the bounding radius.
    touch_tol: f64,
    /// The input-frame origin and scale of [`HullShape::new`] (identity after [`HullShape::scaled`]).
    frame_origin: Point3,
    frame_scale: f64,
    /// Volume, centre of mass and inertia about the centre of mass at unit density (f64): the
    /// hull's, or the solid's after [`HullShape::with_solid_mass`].
    unit_volume: f64,
    unit_com: [f64; 3],
    unit_inertia: [[f64; 3]; 3],
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
            stable: Vec::new(),
            local_aabb,
            local_sphere,
            cube_res,
            cube: Vec::new(),
            feature_angle,
            sin_eps: feature_angle.sin() as Real,
            reduce_tol: REDUCE_TOL_REL * radius as f64,
            touch_tol: TOUCH_TOL_REL * radius as f64,
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
        shape.stable = (0..nf).map(|f| shape.origin_projection_inside(f).is_some()).collect();
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

    /// Whether the origin (G) projects strictly inside facet `f`: the body can rest on it (a
    /// stable facet, [`crate::equilibria`]).
    pub fn rests_on(&self, f: usize) -> bool {
        self.stable[f]
    }

    /// How far (body units) a corner may be from the support plane and still touch it: what
    /// decides whether the body touches a stable facet with its whole support polygon ("Resting
    /// on a stable facet").
    pub fn touch_tolerance(&self) -> f64 {
        self.touch_tol
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate;
    use crate::hull::DEFAULT_COPLANAR_TOL;
    use parry3d::shape::{FeatureId, PolygonalFeature, PolygonalFeatureMap, Shape, SupportMap};

    fn cube() -> HullShape {
        let mesh = generate::cuboid(1.0, 1.0, 1.0);
        let poly = Polyhedron::new(&mesh.vertices, DEFAULT_COPLANAR_TOL).unwrap();
        HullShape::new(&poly, &Point3::origin(), 1.0)
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
