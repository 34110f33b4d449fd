//! f64 arithmetic on the f32 corners: dot and cross products, differences, signed distances to
//! a line in a facet's plane and an orthonormal basis of that plane. The products of f32 values
//! are exact in f64, so the queries built on them round only in their additions.

use parry3d::math::Vector;

#[inline]
pub(super) fn dot64(p: Vector, d: &[f64; 3]) -> f64 {
    p.x as f64 * d[0] + p.y as f64 * d[1] + p.z as f64 * d[2]
}

#[inline]
pub(super) fn to64(p: Vector) -> [f64; 3] {
    [p.x as f64, p.y as f64, p.z as f64]
}

#[inline]
pub(super) fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
pub(super) fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
pub(super) fn cross3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

#[inline]
pub(super) fn cross2(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

#[inline]
pub(super) fn sub2(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// Signed distance from `t` to the line a→b, positive on its left.
#[inline]
pub(super) fn left_dist(a: [f64; 2], b: [f64; 2], t: [f64; 2]) -> f64 {
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
pub(super) fn plane_basis(n: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let a = if n[0].abs() < 0.6 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
    let e1 = cross3(a, n);
    let l = dot3(e1, e1).sqrt();
    let e1 = [e1[0] / l, e1[1] / l, e1[2] / l];
    (e1, cross3(n, e1))
}
