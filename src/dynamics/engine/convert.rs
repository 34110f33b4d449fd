//! Conversions between the f64 nalgebra geometry of the static pipeline and rapier's f32 glam
//! types: the one boundary between the two (static geometry stays in f64).

use crate::Vec3;
use nalgebra::{Matrix3, UnitQuaternion};
use rapier3d::math::{Matrix, Rotation, Vector};

/// nalgebra → glam vector.
pub fn vec(v: &Vec3) -> Vector {
    Vector::new(v.x as f32, v.y as f32, v.z as f32)
}
/// glam → nalgebra vector.
pub fn vec_back(v: Vector) -> Vec3 {
    Vec3::new(v.x as f64, v.y as f64, v.z as f64)
}
/// nalgebra → glam rotation.
pub fn quat(q: &UnitQuaternion<f64>) -> Rotation {
    Rotation::from_xyzw(q.i as f32, q.j as f32, q.k as f32, q.w as f32).normalize()
}
/// glam → nalgebra rotation.
pub fn quat_back(q: &Rotation) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q.w as f64, q.x as f64, q.y as f64, q.z as f64))
}
/// nalgebra → glam matrix.
pub fn mat(m: &Matrix3<f64>) -> Matrix {
    Matrix::from_cols(
        Vector::new(m[(0, 0)] as f32, m[(1, 0)] as f32, m[(2, 0)] as f32),
        Vector::new(m[(0, 1)] as f32, m[(1, 1)] as f32, m[(2, 1)] as f32),
        Vector::new(m[(0, 2)] as f32, m[(1, 2)] as f32, m[(2, 2)] as f32),
    )
}
