//! Plane triangles of the hidden base's support: whether a point (G's foot) is held strictly
//! inside one, and how far a point lies from one.

/// (b − a) × (c − a): positive when c lies left of the line from a to b.
fn cross(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The side of each edge of `t` that `p` lies on ([`cross`]).
fn sides(t: &[[f64; 2]; 3], p: [f64; 2]) -> [f64; 3] {
    [cross(t[0], t[1], p), cross(t[1], t[2], p), cross(t[2], t[0], p)]
}

/// `p` strictly inside the triangle `t` (not on an edge): a support that holds G's foot.
pub(super) fn strictly_inside(t: &[[f64; 2]; 3], p: [f64; 2]) -> bool {
    let s = sides(t, p);
    s.iter().all(|&x| x > 0.0) || s.iter().all(|&x| x < 0.0)
}

/// The distance from `p` to the triangle `t` in the plane: 0 inside.
pub(super) fn distance_to_triangle(p: [f64; 2], t: &[[f64; 2]; 3]) -> f64 {
    let s = sides(t, p);
    if s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0) {
        return 0.0;
    }
    (0..3)
        .map(|i| {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let len2 = dx * dx + dy * dy;
            let u = if len2 > 0.0 { (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0) } else { 0.0 };
            ((p[0] - a[0] - u * dx).powi(2) + (p[1] - a[1] - u * dy).powi(2)).sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_on_an_edge_is_not_held() {
        let t = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]];
        assert!(strictly_inside(&t, [0.5, 0.5]));
        assert!(strictly_inside(&[t[0], t[2], t[1]], [0.5, 0.5]), "either orientation");
        assert!(
            !strictly_inside(&t, [1.0, 0.0]) && !strictly_inside(&t, [0.0, 0.0]) && !strictly_inside(&t, [2.0, 2.0])
        );
    }

    #[test]
    fn the_distance_to_a_triangle_is_zero_inside_and_euclidean_outside() {
        let t = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]];
        assert_eq!(distance_to_triangle([0.5, 0.5], &t), 0.0);
        assert!((distance_to_triangle([1.0, -1.0], &t) - 1.0).abs() < 1e-15);
        assert!((distance_to_triangle([-3.0, -4.0], &t) - 5.0).abs() < 1e-15);
        assert!((distance_to_triangle([2.0, 2.0], &t) - 2f64.sqrt()).abs() < 1e-15);
    }
}
