//! [`HullShape`] as a parry3d [`Shape`]: ray casts and point projections through the support
//! map (GJK), O(1) bounds, the unit-density mass properties, and the normals of features.

use crate::dynamics::engine::hull_shape::HullShape;
use parry3d::bounding_volume::{Aabb, BoundingSphere};
use parry3d::mass_properties::MassProperties;
use parry3d::math::{Matrix, Pose, Real, Vector};
use parry3d::query::details::{
    local_point_projection_on_support_map, local_ray_intersection_with_support_map_with_params,
};
use parry3d::query::gjk::VoronoiSimplex;
use parry3d::query::{PointProjection, PointQuery, Ray, RayCast, RayIntersection};
use parry3d::shape::{FeatureId, PolygonalFeatureMap, Shape, ShapeType, SubShapeId, SupportMap, TypedShape};

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
