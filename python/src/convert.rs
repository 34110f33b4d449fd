//! Errors and conversions: a library [`Error`] as the Python exception that carries the CLI's
//! message, and Rust values as Python objects (the dicts `json.loads` makes, numpy arrays,
//! columns).

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rocking_stones::{Error, Point3};
use serde::Serialize;

pyo3::create_exception!(
    rocking_stones,
    MeshError,
    PyValueError,
    "The mesh is not the boundary of a solid (non-manifold, flipped, several shells, flat, NaN, \
     truncated or unparsable file...), nor an open scan that can be read (open at its top, several \
     rims...). The message is the one `rocking` prints."
);

/// A library error as the Python exception that carries the CLI's message.
pub(crate) fn py_err(e: Error) -> PyErr {
    let msg = e.to_string();
    match &e {
        Error::Io { error, .. } if error.kind() == std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err(msg),
        Error::Io { .. } | Error::Clock(_) => PyOSError::new_err(msg),
        // A parameter is named by its field name, which is the keyword argument's.
        Error::Parameter { .. }
        | Error::SizeUnknown { .. }
        | Error::Unknown { .. }
        | Error::Motion { .. }
        | Error::Pose { .. }
        | Error::Checkpoint(_)
        | Error::Fit(_)
        | Error::Study { .. } => PyValueError::new_err(msg),
        Error::Parse { .. }
        | Error::InvalidMesh { .. }
        | Error::Degenerate { .. }
        | Error::SelfIntersecting { .. }
        | Error::CentreOutsideHull { .. }
        | Error::OpenScan { .. }
        | Error::Check { .. } => MeshError::new_err(msg),
        Error::Plot { .. } => PyRuntimeError::new_err(msg),
        Error::Cancelled => pyo3::exceptions::PyKeyboardInterrupt::new_err(msg),
    }
}

/// Any serialisable value as the Python object `json.loads` makes of its JSON.
pub(crate) fn to_py<'py>(py: Python<'py>, v: &impl Serialize) -> PyResult<Bound<'py, PyAny>> {
    let s = serde_json::to_string(v).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (s,))
}

/// JSON text of a report exactly as the CLI prints it with `--json` (without the final newline),
/// or compact.
pub(crate) fn to_json(v: &impl Serialize, pretty: bool) -> PyResult<String> {
    let r = if pretty { serde_json::to_string_pretty(v) } else { serde_json::to_string(v) };
    r.map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

pub(crate) fn f64s<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, v)
}

pub(crate) fn i64s<'py>(py: Python<'py>, v: Vec<i64>) -> Bound<'py, PyArray1<i64>> {
    PyArray1::from_vec(py, v)
}

pub(crate) fn bools<'py>(py: Python<'py>, v: Vec<bool>) -> Bound<'py, PyArray1<bool>> {
    PyArray1::from_vec(py, v)
}

/// A numpy array of Python strings (`dtype='<U…'`).
pub(crate) fn strs<'py>(py: Python<'py>, v: Vec<String>) -> PyResult<Bound<'py, PyAny>> {
    let np = py.import("numpy")?;
    let kw = PyDict::new(py);
    kw.set_item("dtype", "str")?;
    np.call_method("array", (v,), Some(&kw))
}

/// An `(n, 3)` float64 array.
pub(crate) fn rows3<'py>(py: Python<'py>, rows: impl Iterator<Item = [f64; 3]>) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = rows.flatten().collect();
    let n = flat.len() / 3;
    Array2::from_shape_vec((n, 3), flat).expect("n × 3 values").into_pyarray(py)
}

pub(crate) fn point(p: &Point3) -> [f64; 3] {
    [p.x, p.y, p.z]
}

pub(crate) fn matrix3<'py>(py: Python<'py>, m: &nalgebra::Matrix3<f64>) -> Bound<'py, PyArray2<f64>> {
    rows3(py, (0..3).map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]]))
}

/// Optional index as an int64 column entry (-1 for none).
pub(crate) fn opt_index<T: TryInto<i64>>(x: Option<T>) -> i64 {
    x.and_then(|v| v.try_into().ok()).unwrap_or(-1)
}

/// A dict of columns built by the Python helper `rocking_stones._tables.columns` from records.
pub(crate) fn columns<'py>(py: Python<'py>, records: &impl Serialize) -> PyResult<Bound<'py, PyAny>> {
    let rec = to_py(py, records)?;
    py.import("rocking_stones._tables")?.getattr("columns")?.call1((rec,))
}

pub(crate) fn kind_name(k: rocking_stones::equilibria::Kind) -> String {
    serde_json::to_value(k).ok().and_then(|v| v.as_str().map(String::from)).unwrap_or_default()
}
