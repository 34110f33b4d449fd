//! The rigid body of a stone in the scaled frame: the hull as a parry collider
//! ([`crate::dynamics::engine::hull_shape`]), the solid's G at the origin, its inertia, and the
//! support function h(d) the engine, the certificate and the rest rule read.

use crate::hull::Polyhedron;
use crate::{Point3, Result, Vec3};
use nalgebra::{Matrix3, UnitQuaternion};
use rapier3d::prelude::SharedShape;

/// The rigid body of a stone in the scaled frame (body origin at G, lengths / R_max, mass 1).
#[derive(Clone)]
pub struct Body {
    /// Hull corners relative to G, divided by R_max.
    pub corners: Vec<Vec3>,
    /// The collider: the project's own hull ([`crate::dynamics::engine::hull_shape::HullShape`], exact facets,
    /// constant-time bounds), shared by all runs.
    pub shape: SharedShape,
    /// Outward unit normal of every facet (body frame).
    pub facet_normals: Vec<Vec3>,
    /// Inertia about G for unit mass, in the scaled frame.
    pub inertia: Matrix3<f64>,
    /// R_max in input units (the length scale).
    pub r_max: f64,
}

impl Body {
    /// Prepare the body from the hull, G and the solid's inertia tensor about G (density 1,
    /// input units) and volume.
    pub fn new(hull: &Polyhedron, g: &Point3, inertia: &Matrix3<f64>, volume: f64) -> Self {
        let r_max = hull.vertices.iter().map(|p| (p - g).norm()).fold(0.0, f64::max);
        let corners = hull.vertices.iter().map(|p| (p - g) / r_max).collect();
        let shape = SharedShape::new(crate::dynamics::engine::hull_shape::HullShape::new(hull, g, 1.0 / r_max));
        let facet_normals = hull.facets.iter().map(|f| f.normal).collect();
        // I scales as L⁵ and mass as L³: unit mass in the scaled frame gives I / (V R_max²).
        let inertia = inertia / (volume * r_max * r_max);
        Body { corners, shape, facet_normals, inertia, r_max }
    }

    /// Height of G above the ground when the body touches it with down direction `d` (body
    /// frame): the support function h(d) = max (x − G)·d.
    pub fn support(&self, d: &Vec3) -> f64 {
        self.corners.iter().map(|c| c.dot(d)).fold(f64::NEG_INFINITY, f64::max)
    }

    /// h(d) by hill climbing on the collider's vertex graph
    /// ([`crate::dynamics::engine::hull_shape::HullShape::support_vertex`]): O(1) in the hull size, where
    /// [`Body::support`] scans every corner. The climb runs on the collider's f32 corners, so the
    /// corner found may differ from the exact maximiser when two corners are within f32 rounding
    /// (10⁻⁷ R_max) of each other in direction `d`, and so may the value by as much.
    pub fn support_climb(&self, d: &Vec3) -> f64 {
        match self.shape.as_shape::<crate::dynamics::engine::hull_shape::HullShape>() {
            Some(h) => self.corners[h.support_vertex(crate::dynamics::engine::convert::vec(d)) as usize].dot(d),
            None => self.support(d),
        }
    }

    /// The facet whose outward normal is closest to the down direction `d` (body frame). Not an
    /// outcome rule (see [`crate::dynamics::stone::Stone::rest`]); used to measure tilts.
    pub fn facet_towards(&self, d: &Vec3) -> u32 {
        let mut best = (f64::NEG_INFINITY, 0u32);
        for (i, n) in self.facet_normals.iter().enumerate() {
            let c = n.dot(d);
            if c > best.0 {
                best = (c, i as u32);
            }
        }
        best.1
    }

    /// This body with its base flattened: every corner x within `tolerance` (R_max)
    /// of the lowest plane in direction `down` — h(down) − x·down ≤ tolerance — moved along
    /// `down` onto that plane, the collider rebuilt on the new hull. Those corners then carry
    /// load: the support polygon is [`crate::tipping::TippingPolar`]'s at that tolerance. Mass,
    /// G, inertia and R_max are kept (a few mm of surface do not move them), and so are
    /// `facet_normals`, which stay the analysed hull's (the outcome is read by the static
    /// theory of the scanned hull).
    pub fn flattened(&self, down: &Vec3, tolerance: f64) -> Result<Body> {
        let h = self.support(down);
        let points: Vec<Point3> = self
            .corners
            .iter()
            .map(|c| {
                let lift = h - c.dot(down);
                Point3::from(if lift <= tolerance { c + down * lift } else { *c })
            })
            .collect();
        let hull = Polyhedron::new(&points, crate::hull::DEFAULT_COPLANAR_TOL)?;
        let shape =
            SharedShape::new(crate::dynamics::engine::hull_shape::HullShape::new(&hull, &Point3::origin(), 1.0));
        Ok(Body {
            corners: hull.vertices.iter().map(|p| p.coords).collect(),
            shape,
            facet_normals: self.facet_normals.clone(),
            inertia: self.inertia,
            r_max: self.r_max,
        })
    }

    /// Inertia tensor about G in the world frame for body orientation `q` (unit mass, scaled).
    pub fn world_inertia(&self, q: &UnitQuaternion<f64>) -> Matrix3<f64> {
        let r = q.to_rotation_matrix();
        r.matrix() * self.inertia * r.matrix().transpose()
    }
}
