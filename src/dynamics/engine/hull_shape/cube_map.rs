//! The cube map of directions: each face of the cube [−1, 1]³ cut into `res × res` cells, a
//! direction's cell found from its largest component (O(1)), and the centre direction of a cell.
//! [`crate::dynamics::engine::hull_shape::HullShape`] stores one start vertex of the hill climb per cell.

use parry3d::math::{Real, Vector};

/// Cube-map cell of a direction, `None` for a zero or non-finite direction.
#[inline]
pub(super) fn cube_cell(res: usize, d: Vector) -> Option<usize> {
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
pub(super) fn cube_cell_dir(res: usize, cell: usize) -> Vector {
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
