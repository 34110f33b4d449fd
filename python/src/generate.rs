//! `generate`: the synthetic shapes of `rocking generate` as `(vertices, faces)` arrays.

use crate::convert::{point, py_err, rows3};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A synthetic shape as (vertices, faces) arrays, as `rocking generate`: tetrahedron, cube,
/// octahedron, dodecahedron, icosahedron (circumradius 1), box (axes = edge lengths), ellipsoid,
/// noisy-box, pebble (axes = semi-axes; n points, noise, roughness, seed).
#[pyfunction]
#[pyo3(signature = (shape, *, axes = None, n = None, noise = None, roughness = None, seed = 0))]
#[allow(clippy::type_complexity)]
pub(crate) fn generate<'py>(
    py: Python<'py>,
    shape: &str,
    axes: Option<[f64; 3]>,
    n: Option<usize>,
    noise: Option<f64>,
    roughness: Option<f64>,
    seed: u64,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>)> {
    use rocking_stones::generate::{self as g, Params, Shape};
    let shape: Shape = shape.parse().map_err(py_err)?;
    for (what, given) in
        [("axes", axes.is_some()), ("n", n.is_some()), ("noise", noise.is_some()), ("roughness", roughness.is_some())]
    {
        if given && !shape.uses(what) {
            return Err(PyValueError::new_err(format!("{what} does not apply to {shape}")));
        }
    }
    let p = Params {
        axes: axes.unwrap_or([1.0, 0.75, 0.4]),
        n: n.unwrap_or(if shape == Shape::NoisyBox { 10 } else { 2000 }),
        noise: noise.unwrap_or(if shape == Shape::NoisyBox { 0.01 } else { 0.0 }),
        roughness: roughness.unwrap_or(0.05),
        seed,
    };
    let mesh = py.detach(|| g::generate(shape, &p)).map_err(py_err)?;
    let v = rows3(py, mesh.vertices.iter().map(point));
    let flat: Vec<i64> = mesh.triangles.iter().flatten().map(|&i| i as i64).collect();
    let f = Array2::from_shape_vec((flat.len() / 3, 3), flat).expect("m × 3").into_pyarray(py);
    Ok((v, f))
}
