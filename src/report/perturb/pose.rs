//! A stone drawn resting on one of its stable micro-equilibria, seen from the side: the
//! photographs of the paper's Figure 11, from the hull.

use crate::analysis::Analysis;
use crate::dynamics::stone::{resting_orientation, Stone};
use crate::planar::{Point2, Polygon};
use crate::plot::{Axis, Chart, Marker, RGBColor};
use crate::{Point3, Result, Vec3};

/// The outline of the stone resting on stable micro-equilibrium `i` (position in
/// [`Stone::stable`]) seen along y, in units of R_max: every hull corner p of `analysis` turned
/// into the resting orientation ([`resting_orientation`] of the facet's normal) about G, w =
/// q (p − G)/R_max + (0, 0, R_F/R_max), so that the facet lies on the ground z = 0 with G
/// straight above the contact point at the origin; the convex hull of the (w_x, w_z), closed
/// (its first corner repeated at the end), counter-clockwise. Errors: `i` out of range, or a
/// hull that projects to fewer than three points.
pub fn resting_outline(analysis: &Analysis, stone: &Stone, i: usize) -> Result<Vec<(f64, f64)>> {
    let s = stone.stable().get(i).ok_or_else(|| crate::Error::parameter("equilibrium", i, "a stable one"))?;
    let (g, q) = (analysis.mass.center_of_mass, resting_orientation(&stone.body.facet_normals[s.facet as usize]));
    let seen = |p: &Point3| {
        let w = q * ((p - g) / stone.body.r_max) + Vec3::new(0.0, 0.0, s.r_normalised);
        Point2::new(w.x, w.z)
    };
    Ok(Polygon::convex_hull(&analysis.hull.vertices.iter().map(seen).collect::<Vec<_>>())?.closed_outline())
}

/// A side view of the stone resting on stable micro-equilibrium `i` ([`resting_outline`]),
/// titled `title`: the outline filled in stone colour, the ground line, G and the vertical from
/// the contact point up to it in red, and a note of R_F and the static barriers (basin, flock) in
/// m g R_max; x from −1.2 to 1.2 and z from −0.15 to 2.05 R_max, without grid.
pub fn resting_pose(analysis: &Analysis, stone: &Stone, i: usize, title: String) -> Result<Chart> {
    let outline = resting_outline(analysis, stone, i)?;
    let s = &stone.stable()[i];
    let (black, red, top) = (RGBColor(0, 0, 0), RGBColor(200, 40, 40), (0.0, s.r_normalised));
    let text = format!(
        "G, R = {:.4} R_max; barriers: basin {:.1e}, flock {:.1e} m g R_max",
        s.r_normalised, s.basin_exit.epsilon, s.flock_exit.epsilon
    );
    let (x, z) = (Axis::linear("x / R_max", -1.2, 1.2), Axis::linear("z / R_max", -0.15, 2.05));
    Ok(Chart::new(x.no_grid(), z.no_grid())
        .title(title)
        .polygon(&outline, RGBColor(190, 175, 150), 1.0)
        .line_width(&outline, black, 1)
        .line(&[(-1.2, 0.0), (1.2, 0.0)], black)
        .line_width(&[(0.0, 0.0), top], red, 1)
        .markers_sized(&[top], red, Marker::Dot, 5)
        .text(text, (-1.15, 1.95)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::Options;

    #[test]
    fn a_cube_rests_as_a_square_on_the_ground() {
        // The unit cube: R_max = √3/2, R_F = ½; seen from the side, a square of side 1/R_max
        // standing on z = 0, centred on x = 0.
        let (mesh, repairs) = crate::generate::cuboid(1.0, 1.0, 1.0).into_solid_boundary().unwrap();
        let a = Analysis::of_solid(mesh, repairs, &Options::default()).unwrap();
        let stone = Stone::new(&a, 0.0035).unwrap();
        let side = 2.0 / 3f64.sqrt();
        for i in 0..stone.stable().len() {
            let outline = resting_outline(&a, &stone, i).unwrap();
            assert_eq!(outline.len(), 5, "{outline:?}");
            assert_eq!(outline[0], outline[4]);
            for &(x, z) in &outline {
                assert!((x.abs() - side / 2.0).abs() < 1e-9 && (z.abs() < 1e-9 || (z - side).abs() < 1e-9), "{x} {z}");
            }
        }
        assert!(resting_outline(&a, &stone, 6).is_err());
        assert!(resting_pose(&a, &stone, 0, "cube".into()).is_ok());
    }
}
