//! Mesh inputs: the `mesh` argument (None for the bundled stone, a path, a `(vertices, faces)`
//! pair or an object with `.vertices` and `.faces`) read, checked and analysed exactly as
//! `rocking analyze` does: a closed stone, or an open scan closed by a flat cap
//! ([`Analysis::of_scan`]).

use crate::convert::{py_err, MeshError};
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString, PyTuple};
use rocking_stones::analysis::{check_nu, Analysis, Options};
use rocking_stones::mesh::{io, TriMesh};
use rocking_stones::Point3;
use std::path::{Path, PathBuf};

/// Where a mesh comes from.
pub(crate) enum Source {
    File(PathBuf),
    Memory(TriMesh, String),
    Bundled,
}

/// `(vertices, faces)` arrays as the library's unchecked [`TriMesh`].
fn mesh_from_arrays(vertices: &Bound<'_, PyAny>, faces: &Bound<'_, PyAny>, name: &str) -> PyResult<TriMesh> {
    let py = vertices.py();
    let np = py.import("numpy")?;
    let kw = PyDict::new(py);
    kw.set_item("dtype", "float64")?;
    let v = np.call_method("ascontiguousarray", (vertices,), Some(&kw))?;
    let f = np.call_method1("asarray", (faces,))?;
    let v: PyReadonlyArray2<f64> = v
        .extract()
        .map_err(|_| PyValueError::new_err(format!("{name}: vertices must be an (n, 3) array of numbers")))?;
    let kind: String = f.getattr("dtype")?.getattr("kind")?.extract()?;
    let f_ndim: usize = f.getattr("ndim")?.extract()?;
    let f_empty = f.getattr("size")?.extract::<usize>()? == 0;
    if !(kind == "i" || kind == "u" || (f_empty && f_ndim == 2)) {
        return Err(PyTypeError::new_err(format!(
            "{name}: faces must be an (m, 3) array of integer vertex indices, got dtype kind '{kind}'"
        )));
    }
    let kw = PyDict::new(py);
    kw.set_item("dtype", "int64")?;
    let f = np.call_method("ascontiguousarray", (f,), Some(&kw))?;
    let f: PyReadonlyArray2<i64> = f
        .extract()
        .map_err(|_| PyValueError::new_err(format!("{name}: faces must be an (m, 3) array of vertex indices")))?;
    if v.shape()[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "{name}: vertices must be an (n, 3) array, got shape {:?}",
            v.shape()
        )));
    }
    if f.shape()[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "{name}: faces must be an (m, 3) array of triangles, got shape {:?}",
            f.shape()
        )));
    }
    let vertices: Vec<Point3> = v.as_array().rows().into_iter().map(|r| Point3::new(r[0], r[1], r[2])).collect();
    let mut triangles = Vec::with_capacity(f.shape()[0]);
    for (k, r) in f.as_array().rows().into_iter().enumerate() {
        let t = [r[0], r[1], r[2]];
        if let Some(&bad) = t.iter().find(|&&i| i < 0 || i > u32::MAX as i64) {
            return Err(MeshError::new_err(format!("{name}: triangle {k} refers to vertex {bad}, which cannot exist")));
        }
        triangles.push(t.map(|i| i as u32));
    }
    Ok(TriMesh::new(vertices, triangles))
}

/// Read the `mesh` argument: None (the bundled stone), a path, a `(vertices, faces)` pair, or an
/// object with `.vertices` and `.faces`.
pub(crate) fn source(mesh: Option<&Bound<'_, PyAny>>, name: Option<String>) -> PyResult<Source> {
    let Some(obj) = mesh else { return Ok(Source::Bundled) };
    if obj.is_none() {
        return Ok(Source::Bundled);
    }
    if obj.is_instance_of::<PyString>() || obj.hasattr("__fspath__")? {
        let p: PathBuf = obj.extract()?;
        return Ok(Source::File(p));
    }
    let name = name.unwrap_or_else(|| rocking_stones::error::MEMORY.to_string());
    if let Ok(t) = obj.cast::<PyTuple>() {
        if t.len() == 2 {
            return Ok(Source::Memory(mesh_from_arrays(&t.get_item(0)?, &t.get_item(1)?, &name)?, name));
        }
    }
    if let Ok(l) = obj.cast::<pyo3::types::PyList>() {
        if l.len() == 2 {
            return Ok(Source::Memory(mesh_from_arrays(&l.get_item(0)?, &l.get_item(1)?, &name)?, name));
        }
    }
    if obj.hasattr("vertices")? && obj.hasattr("faces")? {
        let m = mesh_from_arrays(&obj.getattr("vertices")?, &obj.getattr("faces")?, &name)?;
        return Ok(Source::Memory(m, name));
    }
    Err(PyTypeError::new_err(format!(
        "mesh must be a path, a (vertices, faces) pair of arrays or an object with .vertices and .faces \
         (e.g. a trimesh.Trimesh), got {}",
        obj.get_type().name()?
    )))
}

/// Load and check a mesh and run the static analysis, exactly as `rocking analyze` does.
pub(crate) fn analyse(src: Source, opts: &Options) -> rocking_stones::Result<(Analysis, String)> {
    let in_memory = |mesh: TriMesh, name: &str| -> rocking_stones::Result<Analysis> {
        Analysis::of_scan(mesh, opts).map_err(|e| e.with_path(name))
    };
    match src {
        Source::File(p) => Ok((Analysis::of_file(&p, opts)?, p.display().to_string())),
        Source::Memory(mesh, name) => Ok((in_memory(mesh, &name)?, name)),
        Source::Bundled => {
            let mesh = io::read_bytes(rocking_stones::bundled::PLY, Path::new(rocking_stones::bundled::NAME))?;
            Ok((in_memory(mesh, rocking_stones::bundled::NAME)?, rocking_stones::bundled::NAME.to_string()))
        }
    }
}

pub(crate) fn options(nu: Option<f64>, coplanar_tol: f64) -> PyResult<Options> {
    if !(coplanar_tol >= 0.0 && coplanar_tol.is_finite()) {
        return Err(PyValueError::new_err(format!("coplanar_tol must be a finite number ≥ 0, got {coplanar_tol}")));
    }
    Ok(Options { nu: nu.map(check_nu).transpose().map_err(py_err)?, coplanar_tol, ..Options::default() })
}
