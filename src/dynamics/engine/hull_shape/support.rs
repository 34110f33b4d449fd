//! Support point and support feature of [`HullShape`]: steepest-ascent hill climbing on the
//! vertex–edge graph from the cube map's start vertex (exact on a convex polytope, see the parent
//! module), and the facet at the support vertex whose normal is closest to the direction.

use crate::dynamics::engine::hull_shape::cube_map::cube_cell;
use crate::dynamics::engine::hull_shape::vec64::{dot64, to64};
use crate::dynamics::engine::hull_shape::HullShape;
use parry3d::math::{Real, Vector};
use parry3d::shape::{FeatureId, PolygonalFeature, PolygonalFeatureMap, SupportMap};

/// The support feature of the hull in a direction (see [`HullShape::support_feature_id`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Feature {
    Face(u32),
    Edge(u32),
    Vertex(u32),
}

impl HullShape {
    /// Steepest-ascent hill climbing from `v` ([`crate::hull::hill_climb`]).
    #[inline]
    pub(super) fn climb(&self, v: u32, d: &[f64; 3]) -> u32 {
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

    /// The facet the contact comes from at the support vertex `v` towards the unit direction `d`
    /// ("Resting on a stable facet" in the parent module): among the facets at `v` with n·d > 0,
    /// the stable one closest to `d` that the body touches with its whole support polygon (every
    /// kept corner within the touch tolerance of the support plane); failing one, the facet whose
    /// normal is closest to `d`. O(facets at `v` · 4).
    #[inline]
    fn contact_facet(&self, v: u32, d: Vector) -> Option<u32> {
        let d64 = to64(d);
        let floor = dot64(self.points[v as usize], &d64) - self.touch_tol;
        let touches = |f: u32| {
            let cs = self.facet_corners(f as usize);
            let kept = |i: usize| if cs.len() <= 4 { cs[i] } else { cs[self.quads[f as usize][i] as usize] };
            (0..cs.len().min(4)).all(|i| dot64(self.points[kept(i) as usize], &d64) >= floor)
        };
        let resting = self
            .faces_at(v)
            .iter()
            .filter(|&&f| self.stable[f as usize] && self.normals[f as usize].dot(d) > 0.0 && touches(f))
            .map(|&f| (f, self.normals[f as usize].cross(d).length_squared()))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        resting.or_else(|| self.closest_facet_at_with_sin2(v, d)).map(|b| b.0)
    }

    /// The corners joined to corner `v` by a hull edge.
    pub fn corner_neighbours(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.neighbours(v).iter().map(|&(w, _)| w)
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
    /// [`PolygonalFeatureMap::local_support_feature`]): among the facets at the support vertex, a
    /// stable one the body touches with its whole support polygon, else the one whose normal is
    /// closest to `dir`. O(1); for a body at rest, `dir` = down in the body frame gives the facet
    /// it rests on.
    pub fn support_facet(&self, dir: Vector) -> u32 {
        let v = self.support_vertex(dir);
        self.contact_facet(v, dir.normalize_or_zero()).unwrap_or(self.faces_at(v)[0])
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
        let f = self.contact_facet(v, dir.normalize_or_zero()).unwrap_or(self.faces_at(v)[0]);
        self.write_face(f as usize, v, dir, out);
    }
}
