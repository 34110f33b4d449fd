//! Mass properties of [`HullShape`] at unit density: the hull's own (fan tetrahedra from the
//! local origin, in f64 from the f32 corners), or the scanned solid's mapped to the body frame.

use crate::dynamics::engine::hull_shape::vec64::{cross3, dot3, to64};
use crate::dynamics::engine::hull_shape::HullShape;

impl HullShape {
    /// The same shape reporting the *solid's* mass properties (volume, G and inertia of the
    /// scanned body, in the input frame as computed by
    /// [`crate::solid::MassProperties::of`]) from [`Shape::mass_properties`], mapped to the body
    /// frame of [`HullShape::new`], instead of those of the hull. A collider built with a density
    /// then gets the right mass, G and inertia without further setting.
    ///
    /// [`Shape::mass_properties`]: parry3d::shape::Shape::mass_properties
    pub fn with_solid_mass(mut self, solid: &crate::solid::MassProperties) -> HullShape {
        let s = self.frame_scale;
        let g = (solid.center_of_mass - self.frame_origin) * s;
        self.unit_volume = solid.volume * s.powi(3);
        self.unit_com = [g.x, g.y, g.z];
        self.unit_inertia = std::array::from_fn(|i| std::array::from_fn(|j| solid.inertia[(i, j)] * s.powi(5)));
        self
    }

    /// Mass properties of the hull at unit density, in f64 from the f32 corners (fan triangles of
    /// the facets, tetrahedra from the local origin).
    pub(super) fn compute_unit_mass(&mut self) {
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
}
