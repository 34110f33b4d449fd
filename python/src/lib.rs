//! `rocking_stones._native`: the Python binding of the `rocking_stones` library (PyO3).
//!
//! The binding is thin on purpose: every number comes from the Rust library, and every
//! `to_dict()` is the very Rust value the CLI prints with `--json`, serialised by serde_json and
//! read back by Python's `json.loads`, so the two agree by construction.
//!
//! * Meshes: a path (read and checked as `rocking analyze` reads it), a `(vertices, faces)` pair,
//!   or any object with `.vertices` and `.faces` (a `trimesh.Trimesh`). In-memory meshes go
//!   through the same [`TriMesh::into_solid_boundary`] (welding, closedness, orientation) and
//!   their errors name `<memory>` or the `name` the caller passes.
//! * Errors: [`Error`] becomes `MeshError` (a `ValueError`) for unusable meshes, `ValueError`
//!   for bad parameters, `OSError` (`FileNotFoundError`) for files that cannot be read — each
//!   with the message the CLI prints after `error: `.
//! * Long runs (drops, perturbations, shaking, studies) run on a worker thread with the GIL
//!   released; the calling thread waits for them and checks for Ctrl-C every 100 ms. Threads:
//!   rayon's global pool (`RAYON_NUM_THREADS`), or `threads=` for one call.

// `!(x > 0.0)` is used on purpose: it is true for NaN, which must be refused too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{
    PyFileNotFoundError, PyKeyboardInterrupt, PyOSError, PyRuntimeError, PyTypeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString, PyTuple};
use rocking_stones::analysis::{check_nu, Analysis, Options, Report, PAPER_NU};
use rocking_stones::dynamics::drop::DropOutcome;
use rocking_stones::dynamics::params::{DropParams, Preset, Surface};
use rocking_stones::dynamics::stone::Stone as Body;
use rocking_stones::mesh::{io, TriMesh};
use rocking_stones::montecarlo::{self, CertificateMode, DropReport, RunHeader, Shard};
use rocking_stones::{Error, Point3};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

pyo3::create_exception!(
    rocking_stones,
    MeshError,
    PyValueError,
    "The mesh is not the boundary of a solid (open, non-manifold, flipped, several shells, flat, \
     NaN, truncated or unparsable file...). The message is the one `rocking` prints."
);

/// The bundled default stone (as `rocking analyze` without a file).
const DEFAULT_PEBBLE: &[u8] = include_bytes!("../../data/default_pebble.ply");
const DEFAULT_NAME: &str = "default_pebble.ply (bundled)";

// ---------------------------------------------------------------------------------------------
// Errors and conversions

/// A library error as the Python exception that carries the CLI's message.
fn py_err(e: Error) -> PyErr {
    let msg = e.to_string();
    match &e {
        Error::Io { error, .. } if error.kind() == std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err(msg),
        Error::Io { .. } => PyOSError::new_err(msg),
        Error::Usage(_) => PyValueError::new_err(msg),
        Error::Parse { .. }
        | Error::InvalidMesh { .. }
        | Error::Degenerate { .. }
        | Error::SelfIntersecting { .. }
        | Error::CentreOutsideHull { .. }
        | Error::Check { .. } => MeshError::new_err(msg),
        Error::Plot { .. } => PyRuntimeError::new_err(msg),
    }
}

/// Any serialisable value as the Python object `json.loads` makes of its JSON.
fn to_py<'py>(py: Python<'py>, v: &impl Serialize) -> PyResult<Bound<'py, PyAny>> {
    let s = serde_json::to_string(v).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (s,))
}

/// JSON text of a report exactly as the CLI prints it with `--json` (without the final newline),
/// or compact.
fn to_json(v: &impl Serialize, pretty: bool) -> PyResult<String> {
    let r = if pretty { serde_json::to_string_pretty(v) } else { serde_json::to_string(v) };
    r.map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

fn f64s<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, v)
}

fn i64s<'py>(py: Python<'py>, v: Vec<i64>) -> Bound<'py, PyArray1<i64>> {
    PyArray1::from_vec(py, v)
}

fn bools<'py>(py: Python<'py>, v: Vec<bool>) -> Bound<'py, PyArray1<bool>> {
    PyArray1::from_vec(py, v)
}

/// A numpy array of Python strings (`dtype='<U…'`).
fn strs<'py>(py: Python<'py>, v: Vec<String>) -> PyResult<Bound<'py, PyAny>> {
    let np = py.import("numpy")?;
    let kw = PyDict::new(py);
    kw.set_item("dtype", "str")?;
    np.call_method("array", (v,), Some(&kw))
}

/// An `(n, 3)` float64 array.
fn rows3<'py>(py: Python<'py>, rows: impl Iterator<Item = [f64; 3]>) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = rows.flatten().collect();
    let n = flat.len() / 3;
    Array2::from_shape_vec((n, 3), flat).expect("n × 3 values").into_pyarray(py)
}

fn point(p: &Point3) -> [f64; 3] {
    [p.x, p.y, p.z]
}

fn matrix3<'py>(py: Python<'py>, m: &nalgebra::Matrix3<f64>) -> Bound<'py, PyArray2<f64>> {
    rows3(py, (0..3).map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]]))
}

/// Optional index as an int64 column entry (-1 for none).
fn opt_index<T: TryInto<i64>>(x: Option<T>) -> i64 {
    x.and_then(|v| v.try_into().ok()).unwrap_or(-1)
}

/// A dict of columns built by the Python helper `rocking_stones._tables.columns` from records.
fn columns<'py>(py: Python<'py>, records: &impl Serialize) -> PyResult<Bound<'py, PyAny>> {
    let rec = to_py(py, records)?;
    py.import("rocking_stones._tables")?.getattr("columns")?.call1((rec,))
}

// ---------------------------------------------------------------------------------------------
// Mesh inputs

/// Where a mesh comes from.
enum Source {
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
fn source(mesh: Option<&Bound<'_, PyAny>>, name: Option<String>) -> PyResult<Source> {
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
fn analyse(src: Source, opts: &Options) -> rocking_stones::Result<(Analysis, String)> {
    let in_memory = |mesh: TriMesh, name: &str| -> rocking_stones::Result<Analysis> {
        let (mesh, repairs) = mesh.into_solid_boundary().map_err(|e| e.with_path(name))?;
        Analysis::of_solid(mesh, repairs, opts).map_err(|e| e.with_path(name))
    };
    match src {
        Source::File(p) => Ok((Analysis::of_file(&p, opts)?, p.display().to_string())),
        Source::Memory(mesh, name) => Ok((in_memory(mesh, &name)?, name)),
        Source::Bundled => {
            let mesh = io::read_bytes(DEFAULT_PEBBLE, Path::new(DEFAULT_NAME))?;
            Ok((in_memory(mesh, DEFAULT_NAME)?, DEFAULT_NAME.to_string()))
        }
    }
}

fn options(nu: Option<f64>, coplanar_tol: f64) -> PyResult<Options> {
    if !(coplanar_tol >= 0.0 && coplanar_tol.is_finite()) {
        return Err(PyValueError::new_err(format!("coplanar_tol must be a finite number ≥ 0, got {coplanar_tol}")));
    }
    Ok(Options { nu: nu.map(check_nu).transpose().map_err(py_err)?, coplanar_tol, ..Options::default() })
}

/// An analysed stone: the argument itself when it is an [`PyAnalysis`] (with its ν unless `nu`
/// is given), else a fresh analysis with the CLI's default options.
fn analysed(py: Python<'_>, mesh: Option<&Bound<'_, PyAny>>, name: Option<String>, nu: Option<f64>) -> PyResult<Stone> {
    if let Some(obj) = mesh {
        if let Ok(a) = obj.cast::<PyAnalysis>() {
            let a = a.get();
            let opts = match nu {
                Some(nu) => Options { nu: Some(check_nu(nu).map_err(py_err)?), ..a.opts.clone() },
                None => a.opts.clone(),
            };
            return Ok(Stone { analysis: a.inner.clone(), name: a.name.clone(), opts });
        }
    }
    let opts = options(nu, rocking_stones::hull::DEFAULT_COPLANAR_TOL)?;
    let src = source(mesh, name)?;
    let (a, name) = py.detach(|| analyse(src, &opts)).map_err(py_err)?;
    Ok(Stone { analysis: Arc::new(a), name, opts })
}

struct Stone {
    analysis: Arc<Analysis>,
    name: String,
    opts: Options,
}

impl Stone {
    fn nu(&self) -> f64 {
        self.analysis.macro_nu(&self.opts).0
    }
}

// ---------------------------------------------------------------------------------------------
// Long runs: a worker thread, the GIL released, Ctrl-C honoured

/// Payload of the unwinding that stops a cancelled run (raised with `resume_unwind`, so no panic
/// message is printed).
struct Cancelled;

/// Run `work` on a worker thread (in a pool of `threads` threads if given, else rayon's global
/// pool) while this thread, without the GIL, waits for it and checks for signals every 100 ms,
/// calling `progress(done, total)` then if given. On Ctrl-C (or an exception in `progress`) the
/// run is told to stop (`stopped()` turns true, `tick()` unwinds at the next trial), the worker
/// is joined and the exception is raised.
fn interruptible<T: Send>(
    py: Python<'_>,
    threads: Option<usize>,
    progress: Option<(&Bound<'_, PyAny>, u64)>,
    work: impl FnOnce(&Control) -> T + Send,
) -> PyResult<T> {
    let pool = match threads {
        Some(0) => return Err(PyValueError::new_err("threads must be at least 1")),
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| PyRuntimeError::new_err(format!("cannot start {n} threads: {e}")))?,
        ),
        None => None,
    };
    let control = Control { cancel: AtomicBool::new(false), done: AtomicU64::new(0) };
    let report = |control: &Control| -> PyResult<()> {
        match progress {
            Some((f, total)) => f.call1((control.done.load(Ordering::Relaxed), total)).map(|_| ()),
            None => Ok(()),
        }
    };
    std::thread::scope(|s| {
        let (tx, mut rx) = std::sync::mpsc::channel();
        let (control, pool) = (&control, &pool);
        let worker = s.spawn(move || {
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match pool {
                Some(p) => p.install(|| work(control)),
                None => work(control),
            }));
            let _ = tx.send(());
            r
        });
        loop {
            let (done, back) = py.detach(move || {
                let r = rx.recv_timeout(Duration::from_millis(100));
                (!matches!(r, Err(std::sync::mpsc::RecvTimeoutError::Timeout)), rx)
            });
            rx = back;
            if done {
                break;
            }
            if let Err(e) = py.check_signals().and_then(|_| report(control)) {
                control.cancel.store(true, Ordering::Relaxed);
                let _ = py.detach(move || worker.join());
                return Err(e);
            }
        }
        match py.detach(move || worker.join()) {
            Ok(Ok(v)) => report(control).map(|_| v),
            Ok(Err(payload)) | Err(payload) => {
                if payload.is::<Cancelled>() {
                    Err(PyKeyboardInterrupt::new_err("interrupted"))
                } else {
                    std::panic::resume_unwind(payload)
                }
            }
        }
    })
}

/// What a running computation sees of the caller's Ctrl-C.
struct Control {
    cancel: AtomicBool,
    /// Trials (drops, files) finished, for `progress`.
    done: AtomicU64,
}

impl Control {
    /// Has the caller asked to stop?
    fn stopped(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// One more trial finished.
    fn advance(&self) {
        self.done.fetch_add(1, Ordering::Relaxed);
    }

    /// For progress callbacks: count the trial, and stop the run here if the caller asked to.
    fn tick(&self) {
        self.advance();
        if self.stopped() {
            std::panic::resume_unwind(Box::new(Cancelled));
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Parameters from **kwargs

/// `base` with the fields named in `params` replaced: the keyword arguments map to the serde
/// fields of the parameter struct (nested structs are searched too, e.g. `PerturbParams.sim`), so
/// the binding follows the library's structs without a list of its own.
fn with_params<T: Serialize + serde::de::DeserializeOwned>(
    what: &str,
    base: &T,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<T> {
    let mut value = serde_json::to_value(base).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    if let Some(params) = params {
        for (k, v) in params.iter() {
            let key: String = k.extract()?;
            let new = if let Ok(b) = v.extract::<bool>() {
                serde_json::Value::from(b)
            } else if let Ok(text) = v.extract::<String>() {
                serde_json::Value::from(text) // an enum field, e.g. spin_distribution
            } else {
                let x: f64 = v.extract().map_err(|_| {
                    PyTypeError::new_err(format!(
                        "{what}: parameter {key} must be a number (or a name), got {}",
                        v.repr().map_or_else(|_| "?".into(), |r| r.to_string())
                    ))
                })?;
                serde_json::Number::from_f64(x)
                    .map(serde_json::Value::Number)
                    .ok_or_else(|| PyValueError::new_err(format!("{what}: {key} must be finite, got {x}")))?
            };
            if !set_field(&mut value, &key, new) {
                let mut names = Vec::new();
                field_names(&value, &mut names);
                return Err(PyTypeError::new_err(format!(
                    "{what}: unknown parameter {key:?} (parameters: {})",
                    names.join(", ")
                )));
            }
        }
    }
    serde_json::from_value(value).map_err(|e| PyValueError::new_err(format!("{what}: {e}")))
}

fn set_field(v: &mut serde_json::Value, key: &str, new: serde_json::Value) -> bool {
    let Some(map) = v.as_object_mut() else { return false };
    if let Some(slot) = map.get_mut(key) {
        if !slot.is_object() {
            // Keep integers integers (serde refuses 3.0 for a u32).
            *slot = match (slot.is_u64() || slot.is_i64(), new.as_f64()) {
                (true, Some(x)) if x.fract() == 0.0 && x >= 0.0 => serde_json::Value::from(x as u64),
                _ => new,
            };
            return true;
        }
    }
    map.values_mut().any(|child| child.is_object() && set_field(child, key, new.clone()))
}

fn field_names(v: &serde_json::Value, out: &mut Vec<String>) {
    if let Some(map) = v.as_object() {
        for (k, child) in map {
            if child.is_object() {
                field_names(child, out);
            } else {
                out.push(k.clone());
            }
        }
    }
}

/// `preset=`: perturbations and shaking have only their defaults in this version.
fn check_preset(preset: Option<&str>) -> PyResult<()> {
    match preset {
        None | Some("default") => Ok(()),
        Some(p) => Err(PyValueError::new_err(format!(
            "unknown preset {p:?}: perturb and shake have only 'default' (the CLI's contact); set parameters by keyword"
        ))),
    }
}

/// The drop parameters of `rocking drop --preset P --surface S [--size L]` before option
/// overrides (as `cmd::drop::params`; to move into the library so that both call it).
fn preset_params(preset: Preset, surface: Surface, size: Option<f64>) -> PyResult<DropParams> {
    match size {
        Some(size) => preset.params_at_size(surface, size).map_err(py_err),
        None => Ok(preset.params(surface)),
    }
}

/// A lowercase serde enum (certificate mode, family) from its name.
fn enum_from_str<T: serde::de::DeserializeOwned>(what: &str, s: &str, allowed: &str) -> PyResult<T> {
    serde_json::from_value(serde_json::Value::String(s.to_string()))
        .map_err(|_| PyValueError::new_err(format!("{what} must be one of {allowed}, got {s:?}")))
}

// ---------------------------------------------------------------------------------------------
// analyze

/// The static analysis of one stone: mass properties, hull, micro-equilibria, the ν-hierarchy,
/// the plateau, macro counts, flocks and rocking equilibria.
#[pyclass(frozen, module = "rocking_stones", name = "Analysis")]
struct PyAnalysis {
    inner: Arc<Analysis>,
    opts: Options,
    name: String,
    report: Report,
}

impl PyAnalysis {
    fn new(a: Analysis, name: String, opts: Options) -> Self {
        let report = a.report(&name, &opts);
        PyAnalysis { inner: Arc::new(a), opts, name, report }
    }
}

#[pymethods]
impl PyAnalysis {
    /// The name errors and reports use: the path as given, `<memory>` or the caller's `name`.
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    /// Micro-scale counts (S, U, H): stable facets, unstable vertices, saddle edges.
    #[getter]
    fn micro(&self) -> (usize, usize, usize) {
        let m = &self.report.micro;
        (m.stable, m.unstable, m.saddle)
    }

    /// Macro-scale counts (S, U, H) at `nu`.
    #[getter(r#macro)]
    fn macro_counts(&self) -> (usize, usize, usize) {
        let m = &self.report.r#macro;
        (m.stable, m.unstable, m.saddle)
    }

    /// ν of the macro scale (the caller's, the plateau's middle, or the paper's 0.0035).
    #[getter]
    fn nu(&self) -> f64 {
        self.report.r#macro.nu
    }

    /// Where ν came from: "user", "plateau" or "paper-default".
    #[getter]
    fn nu_source<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.report.r#macro.nu_source)
    }

    /// The plateau of n(ν) (dict) or None.
    #[getter]
    fn plateau<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.report.plateau)
    }

    /// The staircase N(ν) as columns: nu_lo, nu_hi, stable, unstable, saddle, n (= N/N(0)).
    #[getter]
    fn staircase<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.report.staircase;
        let d = PyDict::new(py);
        d.set_item("nu_lo", f64s(py, s.iter().map(|x| x.nu_lo).collect()))?;
        d.set_item("nu_hi", f64s(py, s.iter().map(|x| x.nu_hi).collect()))?;
        d.set_item("stable", i64s(py, s.iter().map(|x| x.counts.stable as i64).collect()))?;
        d.set_item("unstable", i64s(py, s.iter().map(|x| x.counts.unstable as i64).collect()))?;
        d.set_item("saddle", i64s(py, s.iter().map(|x| x.counts.saddle as i64).collect()))?;
        d.set_item("n", f64s(py, s.iter().map(|x| x.n).collect()))?;
        Ok(d)
    }

    /// Counts (S, U, H) of the hierarchy at any ν ≥ 0.
    fn counts_at(&self, nu: f64) -> PyResult<(usize, usize, usize)> {
        if !(nu >= 0.0) {
            return Err(PyValueError::new_err(format!("ν must be ≥ 0, got {nu}")));
        }
        let c = self.inner.hierarchy.counts_at(nu);
        Ok((c.stable, c.unstable, c.saddle))
    }

    /// Every micro-equilibrium as columns (one row each, pandas-ready): index, kind, site
    /// ("facet"/"edge"/"vertex"), site_index, x, y, z, r, flock.
    #[getter]
    fn equilibria<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        use rocking_stones::equilibria::Site;
        let e = &self.report.equilibria;
        let d = PyDict::new(py);
        d.set_item("index", i64s(py, e.iter().map(|x| x.index as i64).collect()))?;
        d.set_item("kind", strs(py, e.iter().map(|x| kind_name(x.kind)).collect())?)?;
        let (site, site_index): (Vec<String>, Vec<i64>) = e
            .iter()
            .map(|x| match x.site {
                Site::Facet(i) => ("facet".to_string(), i as i64),
                Site::Edge(i) => ("edge".to_string(), i as i64),
                Site::Vertex(i) => ("vertex".to_string(), i as i64),
            })
            .unzip();
        d.set_item("site", strs(py, site)?)?;
        d.set_item("site_index", i64s(py, site_index))?;
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            d.set_item(*axis, f64s(py, e.iter().map(|x| x.point[k]).collect()))?;
        }
        d.set_item("r", f64s(py, e.iter().map(|x| x.r).collect()))?;
        d.set_item("flock", i64s(py, e.iter().map(|x| x.flock as i64).collect()))?;
        Ok(d)
    }

    /// Contact points of the micro-equilibria, (n, 3), in the order of `equilibria`.
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows3(py, self.report.equilibria.iter().map(|x| point(&x.point)))
    }

    /// The flocks at `nu` (list of dicts: id, type, root, members, stable, unstable, saddle).
    #[getter]
    fn flocks<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.report.flocks)
    }

    /// Rocking equilibria as columns: index, facet, x, y, z, r, r_normalised, flock, flock_type.
    #[getter]
    fn rocking<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let e = &self.report.rocking;
        let d = PyDict::new(py);
        d.set_item("index", i64s(py, e.iter().map(|x| x.index as i64).collect()))?;
        d.set_item("facet", i64s(py, e.iter().map(|x| x.facet as i64).collect()))?;
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            d.set_item(*axis, f64s(py, e.iter().map(|x| x.point[k]).collect()))?;
        }
        d.set_item("r", f64s(py, e.iter().map(|x| x.r).collect()))?;
        d.set_item("r_normalised", f64s(py, e.iter().map(|x| x.r_normalised).collect()))?;
        d.set_item("flock", i64s(py, e.iter().map(|x| x.flock as i64).collect()))?;
        d.set_item("flock_type", strs(py, e.iter().map(|x| kind_name(x.flock_type)).collect())?)?;
        Ok(d)
    }

    /// Shape descriptors (dict): a ≥ b ≥ c, ratios, Zingg class, volume, area, 36πV²/A³.
    #[getter]
    fn shape<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.report.shape)
    }

    /// Volume of the solid (input units³).
    #[getter]
    fn volume(&self) -> f64 {
        self.inner.mass.volume
    }

    /// Surface area of the mesh.
    #[getter]
    fn area(&self) -> f64 {
        self.report.solid.area
    }

    /// Centre of mass G of the homogeneous solid, (3,).
    #[getter]
    fn center_of_mass<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        f64s(py, point(&self.inner.mass.center_of_mass).to_vec())
    }

    /// Inertia tensor about G, density 1, (3, 3) (trimesh's `moment_inertia` convention).
    #[getter]
    fn inertia<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix3(py, &self.inner.mass.inertia)
    }

    /// Principal moments of inertia, ascending, (3,).
    #[getter]
    fn principal_moments<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        f64s(py, self.inner.mass.principal_moments.to_vec())
    }

    /// Principal axes as unit columns, (3, 3), matching `principal_moments`.
    #[getter]
    fn principal_axes<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix3(py, &self.inner.mass.principal_axes)
    }

    /// Hull summary (dict): facets, edges, vertices, triangles, coplanar_tol, volume, area.
    #[getter]
    fn hull<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.report.hull)
    }

    /// Hull vertices, (k, 3).
    #[getter]
    fn hull_vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows3(py, self.inner.hull.vertices.iter().map(point))
    }

    /// Outward unit normals of the hull facets, (f, 3), indexed like facet numbers.
    #[getter]
    fn facet_normals<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows3(py, self.inner.hull.facets.iter().map(|f| [f.normal.x, f.normal.y, f.normal.z]))
    }

    /// Vertices of the checked mesh (welded, unused ones dropped), (n, 3).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows3(py, self.inner.mesh.vertices.iter().map(point))
    }

    /// Triangles of the checked mesh (outward, counter-clockwise), (m, 3) int64.
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        let flat: Vec<i64> = self.inner.mesh.triangles.iter().flatten().map(|&i| i as i64).collect();
        Array2::from_shape_vec((flat.len() / 3, 3), flat).expect("m × 3").into_pyarray(py)
    }

    /// What loading changed (dict): welded_vertices, unreferenced_vertices, degenerate_triangles,
    /// flipped.
    #[getter]
    fn repairs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.report.repairs)
    }

    /// The report as a dict: equal to `json.loads` of `rocking analyze MESH --json`.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.report)
    }

    /// The report as JSON text; `pretty=True` is exactly what `rocking analyze --json` prints.
    #[pyo3(signature = (pretty = true))]
    fn to_json(&self, pretty: bool) -> PyResult<String> {
        to_json(&self.report, pretty)
    }

    /// The human summary `rocking analyze` prints.
    fn summary(&self) -> String {
        rocking_stones::report::summary(&self.report)
    }

    /// The quasi-static resting probabilities of this stone (see `rocking_stones.basins`).
    fn basins(&self, py: Python<'_>) -> PyBasins {
        let a = self.inner.clone();
        let nu = self.report.r#macro.nu;
        py.detach(move || PyBasins::of(&a, nu))
    }

    fn __repr__(&self) -> String {
        let m = &self.report.micro;
        let k = &self.report.r#macro;
        format!(
            "<Analysis {}: micro S={} U={} H={}, macro S={} U={} H={} at nu={:.4e}, {} rocking>",
            self.name,
            m.stable,
            m.unstable,
            m.saddle,
            k.stable,
            k.unstable,
            k.saddle,
            k.nu,
            self.report.rocking.len()
        )
    }
}

fn kind_name(k: rocking_stones::equilibria::Kind) -> String {
    serde_json::to_value(k).ok().and_then(|v| v.as_str().map(String::from)).unwrap_or_default()
}

/// Analyse a stone as `rocking analyze` does; returns an `Analysis`.
///
/// mesh: a path (STL, OBJ, PLY), a (vertices (n, 3), faces (m, 3)) pair of arrays, an object
///     with .vertices and .faces (trimesh.Trimesh), or None for the bundled scanned stone.
///     In-memory meshes are welded and checked like files; errors name `name` (default
///     "<memory>").
/// nu: fixed ν of the macro scale (default: the automatic plateau, else 0.0035).
/// coplanar_tol: relative tolerance of the facet merge (× bounding-box diagonal); 1e-6 for f32
///     CAD files.
///
/// Raises MeshError (a ValueError) for unusable meshes, FileNotFoundError / OSError for
/// unreadable files, ValueError for bad options, each with the CLI's message.
#[pyfunction]
#[pyo3(signature = (mesh = None, nu = None, coplanar_tol = rocking_stones::hull::DEFAULT_COPLANAR_TOL, name = None))]
fn analyze(
    py: Python<'_>,
    mesh: Option<&Bound<'_, PyAny>>,
    nu: Option<f64>,
    coplanar_tol: f64,
    name: Option<String>,
) -> PyResult<PyAnalysis> {
    let opts = options(nu, coplanar_tol)?;
    let src = source(mesh, name)?;
    py.detach(move || {
        let (a, name) = analyse(src, &opts)?;
        Ok(PyAnalysis::new(a, name, opts))
    })
    .map_err(py_err)
}

// ---------------------------------------------------------------------------------------------
// basins

/// Quasi-static resting probabilities: the basin of every stable facet on the sphere of down
/// directions (area / 4π, exact up to `error`).
#[pyclass(frozen, module = "rocking_stones", name = "Basins")]
struct PyBasins {
    facets: Vec<u32>,
    equilibria: Vec<usize>,
    flocks: Vec<usize>,
    normals: Vec<[f64; 3]>,
    probability: Vec<f64>,
    flock_probability: Vec<f64>,
    error: f64,
    method: String,
    nu: f64,
}

impl PyBasins {
    fn of(a: &Analysis, nu: f64) -> PyBasins {
        let eq = &a.equilibria;
        let q = rocking_stones::basins::basin_probabilities(&a.hull, &a.mass.center_of_mass, eq);
        let flocks = a.hierarchy.flocks_at(nu);
        let flock_probability =
            rocking_stones::basins::flock_probabilities(&q, eq, &flocks.membership, flocks.flocks.len());
        let stable: Vec<(u32, usize)> =
            eq.at_facet.iter().enumerate().filter_map(|(f, s)| s.map(|s| (f as u32, s as usize))).collect();
        PyBasins {
            facets: stable.iter().map(|&(f, _)| f).collect(),
            equilibria: stable.iter().map(|&(_, s)| s).collect(),
            flocks: stable.iter().map(|&(_, s)| flocks.membership[s]).collect(),
            normals: stable
                .iter()
                .map(|&(f, _)| {
                    let n = a.hull.facets[f as usize].normal;
                    [n.x, n.y, n.z]
                })
                .collect(),
            probability: stable.iter().map(|&(f, _)| q.facet_probability[f as usize]).collect(),
            flock_probability,
            error: q.error,
            method: q.method,
            nu,
        }
    }
}

#[pymethods]
impl PyBasins {
    /// Hull facet of every stable micro-equilibrium.
    #[getter]
    fn facet<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        i64s(py, self.facets.iter().map(|&f| f as i64).collect())
    }
    /// Index of the stable micro-equilibrium (as in `Analysis.equilibria`).
    #[getter]
    fn equilibrium<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        i64s(py, self.equilibria.iter().map(|&f| f as i64).collect())
    }
    /// Flock of the stable micro-equilibrium at `nu`.
    #[getter]
    fn flock<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        i64s(py, self.flocks.iter().map(|&f| f as i64).collect())
    }
    /// Outward unit normal of the facet, (k, 3): the stone rests with −normal pointing down.
    #[getter]
    fn normal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows3(py, self.normals.iter().copied())
    }
    /// Quasi-static probability of resting on the facet (sums to 1).
    #[getter]
    fn probability<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        f64s(py, self.probability.clone())
    }
    /// Probability of every flock (indexed by flock id at `nu`).
    #[getter]
    fn flock_probability<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        f64s(py, self.flock_probability.clone())
    }
    /// Bound on the absolute error of every probability.
    #[getter]
    fn error(&self) -> f64 {
        self.error
    }
    /// How the probabilities were obtained.
    #[getter]
    fn method(&self) -> &str {
        &self.method
    }
    /// ν at which the flocks were read.
    #[getter]
    fn nu(&self) -> f64 {
        self.nu
    }
    /// Columns (pandas-ready): facet, equilibrium, flock, nx, ny, nz, probability.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("facet", self.facet(py))?;
        d.set_item("equilibrium", self.equilibrium(py))?;
        d.set_item("flock", self.flock(py))?;
        for (k, axis) in ["nx", "ny", "nz"].iter().enumerate() {
            d.set_item(*axis, f64s(py, self.normals.iter().map(|n| n[k]).collect()))?;
        }
        d.set_item("probability", self.probability(py))?;
        Ok(d)
    }
    fn __len__(&self) -> usize {
        self.facets.len()
    }
    fn __repr__(&self) -> String {
        format!("<Basins: {} stable facets, error ≤ {:.1e}>", self.facets.len(), self.error)
    }
}

/// Quasi-static resting probability of every stable facet, with its normal and flock; returns
/// `Basins`. `mesh` as for `analyze`, or an `Analysis`.
#[pyfunction]
#[pyo3(signature = (mesh = None, nu = None, name = None))]
fn basins(
    py: Python<'_>,
    mesh: Option<&Bound<'_, PyAny>>,
    nu: Option<f64>,
    name: Option<String>,
) -> PyResult<PyBasins> {
    let stone = analysed(py, mesh, name, nu)?;
    let nu = stone.nu();
    Ok(py.detach(move || PyBasins::of(&stone.analysis, nu)))
}

// ---------------------------------------------------------------------------------------------
// drop

/// The result of a drop run: the report `rocking drop --json` prints and every drop's outcome.
#[pyclass(frozen, module = "rocking_stones", name = "DropResult")]
struct PyDropResult {
    report: DropReport,
    outcomes: Vec<DropOutcome>,
}

#[pymethods]
impl PyDropResult {
    #[getter]
    fn drops(&self) -> u64 {
        self.report.drops
    }
    #[getter]
    fn seed(&self) -> u64 {
        self.report.seed
    }
    /// Drops that came to rest (or were decided by the certificate).
    #[getter]
    fn settled(&self) -> u64 {
        self.report.settled
    }
    /// Drops still moving at the time cap.
    #[getter]
    fn unsettled(&self) -> u64 {
        self.report.unsettled
    }
    /// Drops ended early by the energy certificate.
    #[getter]
    fn certified(&self) -> u64 {
        self.report.certified
    }
    /// Settled drops that did not end on a stable micro-equilibrium.
    #[getter]
    fn off_equilibrium(&self) -> u64 {
        self.report.off_equilibrium
    }
    /// Mean simulated time per drop (s, scaled 1 m body).
    #[getter]
    fn mean_time(&self) -> f64 {
        self.report.mean_time
    }
    /// ν at which flocks were read.
    #[getter]
    fn nu(&self) -> f64 {
        self.report.nu
    }
    /// Per facet (reached or with positive static probability) as columns: facet, nx, ny, nz,
    /// equilibrium, flock (-1: not a stable facet), count, fraction, ci95_lo, ci95_hi,
    /// static_probability.
    #[getter]
    fn facets<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let f = &self.report.facets;
        let d = PyDict::new(py);
        d.set_item("facet", i64s(py, f.iter().map(|x| x.facet as i64).collect()))?;
        for (k, axis) in ["nx", "ny", "nz"].iter().enumerate() {
            d.set_item(*axis, f64s(py, f.iter().map(|x| x.normal[k]).collect()))?;
        }
        d.set_item("equilibrium", i64s(py, f.iter().map(|x| opt_index(x.equilibrium)).collect()))?;
        d.set_item("flock", i64s(py, f.iter().map(|x| opt_index(x.flock)).collect()))?;
        d.set_item("count", i64s(py, f.iter().map(|x| x.count as i64).collect()))?;
        d.set_item("fraction", f64s(py, f.iter().map(|x| x.fraction).collect()))?;
        d.set_item("ci95_lo", f64s(py, f.iter().map(|x| x.ci95.0).collect()))?;
        d.set_item("ci95_hi", f64s(py, f.iter().map(|x| x.ci95.1).collect()))?;
        d.set_item("static_probability", f64s(py, f.iter().map(|x| x.static_probability).collect()))?;
        Ok(d)
    }
    /// Per flock as columns: id, type, count, fraction, ci95_lo, ci95_hi, static_probability.
    #[getter]
    fn flocks<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let f = &self.report.flocks;
        let d = PyDict::new(py);
        d.set_item("id", i64s(py, f.iter().map(|x| x.id as i64).collect()))?;
        d.set_item("type", strs(py, f.iter().map(|x| kind_name(x.kind)).collect())?)?;
        d.set_item("count", i64s(py, f.iter().map(|x| x.count as i64).collect()))?;
        d.set_item("fraction", f64s(py, f.iter().map(|x| x.fraction).collect()))?;
        d.set_item("ci95_lo", f64s(py, f.iter().map(|x| x.ci95.0).collect()))?;
        d.set_item("ci95_hi", f64s(py, f.iter().map(|x| x.ci95.1).collect()))?;
        d.set_item("static_probability", f64s(py, f.iter().map(|x| x.static_probability).collect()))?;
        Ok(d)
    }
    /// Every drop as columns: index, settled, facet, flock (-1: none), time, certified.
    #[getter]
    fn outcomes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let o = &self.outcomes;
        let d = PyDict::new(py);
        d.set_item("index", i64s(py, o.iter().map(|x| x.index as i64).collect()))?;
        d.set_item("settled", bools(py, o.iter().map(|x| x.settled).collect()))?;
        d.set_item("facet", i64s(py, o.iter().map(|x| opt_index(x.facet)).collect()))?;
        d.set_item("flock", i64s(py, o.iter().map(|x| opt_index(x.flock)).collect()))?;
        d.set_item("time", f64s(py, o.iter().map(|x| x.time).collect()))?;
        d.set_item("certified", bools(py, o.iter().map(|x| x.certified).collect()))?;
        Ok(d)
    }
    /// χ² and KL of the facet counts against the static probabilities (dict, or None in flock
    /// certificate mode).
    #[getter]
    fn fit_facets<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.report.fit_facets)
    }
    /// χ² and KL of the flock counts.
    #[getter]
    fn fit_flocks<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.report.fit_flocks)
    }
    /// The report as a dict: equal to `json.loads` of `rocking drop MESH -n N --seed S --json`.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.report)
    }
    /// The report as JSON text (`pretty=True`: as `rocking drop --json` prints it).
    #[pyo3(signature = (pretty = true))]
    fn to_json(&self, pretty: bool) -> PyResult<String> {
        to_json(&self.report, pretty)
    }
    /// The human summary `rocking drop` prints.
    fn summary(&self) -> String {
        rocking_stones::report::drop_summary(&self.report)
    }
    fn __repr__(&self) -> String {
        format!(
            "<DropResult {}: {} drops, seed {}, {} settled, {} certified>",
            self.report.mesh, self.report.drops, self.report.seed, self.report.settled, self.report.certified
        )
    }
}

// The one place the binding calls the Monte Carlo loop (to adapt when the dynamics API changes):
// drops run in chunks through `montecarlo::run` (drop i depends only on (seed, i), so chunks give
// exactly the outcomes of one run) and the caller's Ctrl-C is checked between chunks.
/// Drop the stone `n` times from uniformly random orientations in rapier3d, as
/// `rocking drop MESH -n N --seed S`; returns a `DropResult` whose to_dict() is the CLI's --json.
///
/// preset: "quasi-static", "drop" or "throw" (the CLI's default); surface: "steel-on-wood" (the
/// default), "stone-on-stone", "rock-on-concrete", "rock-on-steel"; size: R_max of the real
/// stone in metres (scales the contact as --size does).
/// **params override single parameters, as the CLI's options: height, horizontal_speed, spin,
/// spin_distribution, friction, restitution, rolling_resistance, torsional_friction,
/// linear_damping, angular_damping, dt, solver_iterations, max_time, rest_linear_speed,
/// rest_angular_speed, rest_time, flight ("rapier", the reference, or "free": the flight between
/// contacts integrated outside rapier, the CLI's --flight).
/// certificate: "none", "facet" or "flock" (energy certificate that ends decided drops early).
/// fast: the CLI's --fast (free flight at the preset's longest stable time step; **params still
/// override it).
/// threads: threads of this run (default:
/// RAYON_NUM_THREADS or all cores). progress: callable(done, total), called about every 0.1 s
/// (e.g. to update a tqdm bar). Releases the GIL; Ctrl-C raises KeyboardInterrupt.
#[pyfunction]
#[pyo3(signature = (mesh = None, n = 1000, seed = 1, *, preset = "throw", surface = "steel-on-wood", size = None, certificate = "facet", fast = false, nu = None, name = None, threads = None, progress = None, **params))]
#[pyo3(name = "drop")]
#[allow(clippy::too_many_arguments)]
fn drop_stone(
    py: Python<'_>,
    mesh: Option<&Bound<'_, PyAny>>,
    n: u64,
    seed: u64,
    preset: &str,
    surface: &str,
    size: Option<f64>,
    certificate: &str,
    fast: bool,
    nu: Option<f64>,
    name: Option<String>,
    threads: Option<usize>,
    progress: Option<&Bound<'_, PyAny>>,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyDropResult> {
    if n == 0 {
        return Err(PyValueError::new_err("n must be at least 1"));
    }
    let preset: Preset = preset.parse().map_err(py_err)?;
    let surface: Surface = surface.parse().map_err(py_err)?;
    let mut base = preset_params(preset, surface, size)?;
    if fast {
        preset.fast(&mut base);
    }
    let p: DropParams = with_params("drop", &base, params)?;
    p.check().map_err(py_err)?;
    let certificate: CertificateMode = enum_from_str("certificate", certificate, "'none', 'facet', 'flock'")?;
    let stone = analysed(py, mesh, name, nu)?;
    let body = py.detach(|| Body::new(&stone.analysis, stone.nu())).map_err(py_err)?;
    let header = RunHeader {
        format: montecarlo::FORMAT.into(),
        mesh: stone.name.clone(),
        mesh_fingerprint: montecarlo::fingerprint(&stone.analysis.mesh),
        seed,
        drops: n,
        params: p,
        certificate,
        preset: Some(format!("{preset} on {surface}")),
        center_of_mass: None,
        shard: rocking_stones::montecarlo::Shard::ALL,
    };
    let progress = progress.map(|f| (f, n));
    let outcomes = interruptible(py, threads, progress, |control| -> Result<BTreeMap<u64, DropOutcome>, Cancelled> {
        let cert = montecarlo::certificate(&body, header.certificate);
        let sink = std::sync::Mutex::new(|_: &DropOutcome| control.advance());
        let mut done = BTreeMap::new();
        // Chunks of about a quarter of a second, so that Ctrl-C is answered quickly.
        let mut chunk = rayon::current_num_threads() as u64;
        while (done.len() as u64) < n {
            if control.stopped() {
                return Err(Cancelled);
            }
            let start = Instant::now();
            let before = done.len() as u64;
            let upto = (before + chunk).min(n);
            let part = RunHeader { drops: upto, ..header.clone() };
            for o in montecarlo::run(&body, &part, Shard::ALL, &done, cert.as_ref(), &sink) {
                done.insert(o.index, o);
            }
            let per_drop = start.elapsed().as_secs_f64() / (upto - before) as f64;
            let threads = rayon::current_num_threads() as u64;
            chunk = ((0.25 / per_drop.max(1e-6)) as u64).clamp(threads, 64 * threads.max(4));
        }
        Ok(done)
    })?
    .map_err(|_| PyKeyboardInterrupt::new_err("interrupted"))?;
    let report = montecarlo::summarize(&body.model(), &header, &outcomes);
    Ok(PyDropResult { report, outcomes: outcomes.into_values().collect() })
}

// ---------------------------------------------------------------------------------------------
// perturb and shake

/// A perturbation or shaking run: its report (as the CLI's `--json`) and every trial.
#[pyclass(frozen, module = "rocking_stones", name = "DynamicsResult")]
struct PyDynamicsResult {
    kind: &'static str,
    json: serde_json::Value,
    trials: serde_json::Value,
    summary: String,
}

#[pymethods]
impl PyDynamicsResult {
    /// The report as a dict: equal to `json.loads` of the CLI's `--json` output.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.json)
    }
    /// The report as JSON text.
    #[pyo3(signature = (pretty = true))]
    fn to_json(&self, pretty: bool) -> PyResult<String> {
        to_json(&self.json, pretty)
    }
    /// Every trial as columns (pandas-ready; nested values flattened with `_`, points and
    /// intervals split into `_x/_y/_z` and `_lo/_hi`, missing numbers as NaN).
    #[getter]
    fn trials<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        columns(py, &self.trials)
    }
    /// The human summary the CLI prints.
    fn summary(&self) -> String {
        self.summary.clone()
    }
    fn __getitem__<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        match self.json.get(key) {
            Some(v) => to_py(py, v),
            None => Err(pyo3::exceptions::PyKeyError::new_err(key.to_string())),
        }
    }
    fn __repr__(&self) -> String {
        format!("<{} result: {} trials>", self.kind, self.trials.as_array().map_or(0, |t| t.len()))
    }
}

fn dynamics_result(
    kind: &'static str,
    report: &impl Serialize,
    trials: &impl Serialize,
    summary: String,
) -> PyResult<PyDynamicsResult> {
    let e = |e: serde_json::Error| PyRuntimeError::new_err(e.to_string());
    Ok(PyDynamicsResult {
        kind,
        json: serde_json::to_value(report).map_err(e)?,
        trials: serde_json::to_value(trials).map_err(e)?,
        summary,
    })
}

/// `PerturbParams` from keyword arguments (DropParams fields go into `sim`).
fn perturb_params(
    what: &str,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<rocking_stones::dynamics::perturb::PerturbParams> {
    let p: rocking_stones::dynamics::perturb::PerturbParams =
        with_params(what, &rocking_stones::dynamics::perturb::PerturbParams::default(), params)?;
    p.check().map_err(py_err)?;
    Ok(p)
}

/// Positions in `stone.stable` of the equilibria asked for (None: all).
fn select_starts(
    stone: &rocking_stones::dynamics::perturb::Stone,
    equilibria: Option<Vec<usize>>,
    flock: Option<usize>,
) -> PyResult<Vec<usize>> {
    let list =
        || stone.stable().iter().map(|s| format!("{} (flock {})", s.index, s.flock)).collect::<Vec<_>>().join(", ");
    if let Some(k) = flock {
        if k >= stone.flock_kinds.len() {
            return Err(PyValueError::new_err(format!(
                "there is no flock {k} (the stone has {} flocks at ν = {:.3e})",
                stone.flock_kinds.len(),
                stone.nu
            )));
        }
        let v: Vec<usize> = (0..stone.stable().len()).filter(|&i| stone.stable()[i].flock == k).collect();
        if v.is_empty() {
            return Err(PyValueError::new_err(format!(
                "flock {k} has no stable micro-equilibrium; stable ones: {}",
                list()
            )));
        }
        return Ok(v);
    }
    match equilibria {
        None => Ok((0..stone.stable().len()).collect()),
        Some(ids) => ids
            .iter()
            .map(|&id| {
                stone.position(id).ok_or_else(|| {
                    PyValueError::new_err(format!("{id} is not a stable micro-equilibrium; stable ones: {}", list()))
                })
            })
            .collect(),
    }
}

/// Push or spin the stone resting on its stable micro-equilibria, as `rocking perturb`;
/// returns a `DynamicsResult` whose to_dict() is the CLI's --json. **params: friction,
/// restitution, linear_damping, angular_damping, dt, max_time, contact_frequency, settle_time,
/// hold_time, rest thresholds. preset: only None / "default" in this version.
#[pyfunction]
#[pyo3(signature = (mesh = None, *, equilibria = None, flock = None, family = "push", trials = 40, seed = 1, eps_min = 1e-5, eps_max = 1.0, eps_steps = 16, epsilon_star = None, certificate = false, preset = None, nu = None, name = None, threads = None, progress = None, **params))]
#[allow(clippy::too_many_arguments)]
fn perturb(
    py: Python<'_>,
    mesh: Option<&Bound<'_, PyAny>>,
    equilibria: Option<Vec<usize>>,
    flock: Option<usize>,
    family: &str,
    trials: u32,
    seed: u64,
    eps_min: f64,
    eps_max: f64,
    eps_steps: usize,
    epsilon_star: Option<f64>,
    certificate: bool,
    preset: Option<&str>,
    nu: Option<f64>,
    name: Option<String>,
    threads: Option<usize>,
    progress: Option<&Bound<'_, PyAny>>,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyDynamicsResult> {
    use rocking_stones::dynamics::perturb::{self as pt, PerturbConfig};
    check_preset(preset)?;
    let params = pt::PerturbParams { certificate, ..perturb_params("perturb", params)? };
    if !(eps_min > 0.0 && eps_max >= eps_min && eps_steps > 0) {
        return Err(PyValueError::new_err("need 0 < eps_min ≤ eps_max and eps_steps ≥ 1"));
    }
    let cfg = PerturbConfig {
        params,
        family: enum_from_str("family", family, "'push', 'spin'")?,
        epsilons: rocking_stones::stats::log_grid(eps_min, eps_max, rocking_stones::stats::GridSize::Points(eps_steps)),
        trials,
        seed,
        epsilon_star,
    };
    cfg.check().map_err(py_err)?;
    let s = analysed(py, mesh, name, nu)?;
    let stone = py.detach(|| pt::Stone::new(&s.analysis, s.nu())).map_err(py_err)?;
    let starts = select_starts(&stone, equilibria, flock)?;
    let progress = progress.map(|f| (f, pt::task_count(starts.len(), &cfg)));
    let report = interruptible(py, threads, progress, |c| pt::run_with(&stone, &starts, &cfg, &|| c.tick()))?;
    dynamics_result("perturb", &report, &report.trials, rocking_stones::report::perturb::summary(&report, &s.name))
}

/// Shake the ground under the resting stone, as `rocking shake`: fragility curves; returns a
/// `DynamicsResult`. pulse=(amplitude in g, frequency in Hz for a stone of `size` metres,
/// cycles) or motion=CSV of time and acceleration; the default sweeps a 2-cycle 2 Hz pulse up to
/// 1 g. **params as for `perturb`.
#[pyfunction]
#[pyo3(signature = (mesh = None, *, equilibria = None, pulse = None, motion = None, pga_max = None, pga_steps = 20, size = 1.0, azimuth = None, trials = 40, seed = 1, preset = None, nu = None, name = None, threads = None, progress = None, **params))]
#[allow(clippy::too_many_arguments)]
fn shake(
    py: Python<'_>,
    mesh: Option<&Bound<'_, PyAny>>,
    equilibria: Option<Vec<usize>>,
    pulse: Option<(f64, f64, f64)>,
    motion: Option<PathBuf>,
    pga_max: Option<f64>,
    pga_steps: usize,
    size: f64,
    azimuth: Option<f64>,
    trials: u32,
    seed: u64,
    preset: Option<&str>,
    nu: Option<f64>,
    name: Option<String>,
    threads: Option<usize>,
    progress: Option<&Bound<'_, PyAny>>,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyDynamicsResult> {
    use rocking_stones::dynamics::perturb::{self as pt, default_pair};
    use rocking_stones::dynamics::shake::{self as sh, Motion, Pulse, ShakeConfig, TimeScale};
    check_preset(preset)?;
    let params = perturb_params("shake", params)?;
    if !(size > 0.0 && size.is_finite()) {
        return Err(PyValueError::new_err("size must be positive"));
    }
    if pulse.is_some() && motion.is_some() {
        return Err(PyValueError::new_err("give a pulse or a motion, not both"));
    }
    let scale = TimeScale { r_max_m: size };
    let (motion, default_sweep) = match (pulse, motion) {
        (Some((a, f, c)), _) => {
            (Motion::Pulse(Pulse { amplitude: a, frequency: scale.to_scaled_frequency(f), cycles: c }), false)
        }
        (None, Some(path)) => (Motion::Record(sh::read_record(&path, scale).map_err(py_err)?), false),
        (None, None) => (Motion::Pulse(Pulse { amplitude: 1.0, frequency: 2.0, cycles: 2.0 }), true),
    };
    let pgas = match pga_max.or(default_sweep.then_some(1.0)) {
        Some(m) => {
            if !(m > 0.0) || pga_steps == 0 {
                return Err(PyValueError::new_err("need pga_max > 0 and pga_steps ≥ 1"));
            }
            (1..=pga_steps).map(|i| m * i as f64 / pga_steps as f64).collect()
        }
        None => vec![motion.peak()],
    };
    let cfg = ShakeConfig { params, motion, pgas, trials, seed, azimuth: azimuth.map(f64::to_radians), scale };
    cfg.check().map_err(py_err)?;
    let s = analysed(py, mesh, name, nu)?;
    let stone = py.detach(|| pt::Stone::new(&s.analysis, s.nu())).map_err(py_err)?;
    let starts = match equilibria {
        None => {
            let (regular, rocking) = py.detach(|| default_pair(&stone, &cfg.params));
            let v: Vec<usize> = regular.into_iter().chain(rocking).collect();
            if v.is_empty() {
                return Err(PyValueError::new_err(
                    "no stable micro-equilibrium of this stone stays at rest in the simulation",
                ));
            }
            v
        }
        Some(ids) => select_starts(&stone, Some(ids), None)?,
    };
    let progress = progress.map(|f| (f, (starts.len() * cfg.pgas.len()) as u64 * cfg.trials as u64));
    let report = interruptible(py, threads, progress, |c| sh::run_with(&stone, &starts, &cfg, &|| c.tick()))?;
    dynamics_result("shake", &report, &report.trials, rocking_stones::report::shake::summary(&report, &s.name))
}

/// A field rock at its true size under one recorded ground motion, as
/// `rocking shake MESH --pose POSE --length-unit UNIT --motion ... --json`: the same dict.
/// The motion is `motion=` a CSV path (read with `columns` and `accel_unit`) or a list of one to
/// three PEER `.AT2` paths (x, y, z), or `accel=` an array of shape (n,) or (n, k ≤ 3) in m/s²
/// (x, y horizontal, z up) sampled every `dt` seconds. `length_unit`: "mm", "cm", "m" (default),
/// "km" or metres per mesh unit.
#[pyfunction]
#[pyo3(signature = (mesh = None, *, pose, length_unit = None, motion = None, accel = None, dt = None, columns = "1,2", accel_unit = "g", baseline = None, azimuth = 0.0, surface = "rock-on-concrete", scale = 1.0, nu = None, name = None))]
#[allow(clippy::too_many_arguments)]
fn shake_rock<'py>(
    py: Python<'py>,
    mesh: Option<&Bound<'py, PyAny>>,
    pose: &str,
    length_unit: Option<&Bound<'py, PyAny>>,
    motion: Option<&Bound<'py, PyAny>>,
    accel: Option<&Bound<'py, PyAny>>,
    dt: Option<f64>,
    columns: &str,
    accel_unit: &str,
    baseline: Option<usize>,
    azimuth: f64,
    surface: &str,
    scale: f64,
    nu: Option<f64>,
    name: Option<String>,
) -> PyResult<Bound<'py, PyAny>> {
    use rocking_stones::dynamics::params::Surface;
    use rocking_stones::dynamics::perturb as pt;
    use rocking_stones::dynamics::shake::{self as sh, Pose, RockSetup};
    use rocking_stones::ground_motion::read::{read_record, AccelUnit, Columns};
    use rocking_stones::ground_motion::Record;
    let pose: Pose = pose.parse().map_err(py_err)?;
    let unit = match length_unit {
        None => 1.0,
        Some(u) => match u.extract::<f64>() {
            Ok(x) => sh::parse_length_unit(&x.to_string()).map_err(py_err)?,
            Err(_) => sh::parse_length_unit(&u.extract::<String>()?).map_err(py_err)?,
        },
    };
    let surface: Surface = surface.parse().map_err(py_err)?;
    let record = match (motion, accel) {
        (Some(_), Some(_)) => return Err(PyValueError::new_err("give motion= (files) or accel= (an array), not both")),
        (None, None) => return Err(PyValueError::new_err("give motion= (a CSV or .AT2 files) or accel= with dt=")),
        (Some(m), None) => {
            let paths: Vec<PathBuf> = match m.extract::<PathBuf>() {
                Ok(p) => vec![p],
                Err(_) => m.extract::<Vec<PathBuf>>()?,
            };
            let columns: Columns = columns.parse().map_err(py_err)?;
            let unit: AccelUnit = accel_unit.parse().map_err(py_err)?;
            let refs: Vec<&std::path::Path> = paths.iter().map(|p| p.as_path()).collect();
            read_record(&refs, &columns, unit).map_err(py_err)?
        }
        (None, Some(a)) => {
            let dt = dt.ok_or_else(|| PyValueError::new_err("accel= needs dt= (seconds between samples)"))?;
            let np = py.import("numpy")?;
            let arr = np.call_method1("asarray", (a, "float64"))?;
            let arr = if arr.getattr("ndim")?.extract::<usize>()? == 1 {
                arr.call_method1("reshape", ((-1i64, 1i64),))?
            } else {
                arr
            };
            let arr: PyReadonlyArray2<f64> = arr.extract()?;
            let view = arr.as_array();
            if view.ncols() == 0 || view.ncols() > 3 {
                return Err(PyValueError::new_err(format!(
                    "accel= must have 1 to 3 columns (x, y, z), got {}",
                    view.ncols()
                )));
            }
            let rows = view.rows().into_iter().map(|r| [0, 1, 2].map(|c| r.get(c).copied().unwrap_or(0.0))).collect();
            Record::new(name.clone().unwrap_or_else(|| "accel".into()), dt, rows).map_err(py_err)?
        }
    };
    let record = match baseline {
        Some(order) => record.baseline_corrected(order).map_err(py_err)?,
        None => record,
    };
    let s = analysed(py, mesh, name, nu)?;
    let stone = py.detach(|| pt::Stone::new(&s.analysis, s.nu())).map_err(py_err)?;
    let run = py.detach(|| -> rocking_stones::Result<sh::RecordRun> {
        let setup = RockSetup::new(&stone, pose, unit, surface, azimuth.to_radians())?;
        sh::run_record(&stone, &setup, &record, scale)
    });
    to_py(py, &run.map_err(py_err)?)
}

// ---------------------------------------------------------------------------------------------
// study

/// A field study: one row per scan with the columns of `pebbles.csv`.
#[pyclass(frozen, module = "rocking_stones", name = "Study")]
struct PyStudy {
    study: rocking_stones::study::Study,
    pebbles_csv: String,
    samples_csv: String,
}

/// CSV text as a list of rows (dicts): empty cells are None, numbers are int or float.
fn csv_rows<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, pyo3::types::PyList>> {
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let header: Vec<String> =
        r.headers().map_err(|e| PyRuntimeError::new_err(e.to_string()))?.iter().map(String::from).collect();
    let rows = pyo3::types::PyList::empty(py);
    for rec in r.records() {
        let rec = rec.map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        let d = PyDict::new(py);
        for (k, cell) in header.iter().zip(rec.iter()) {
            if cell.is_empty() {
                d.set_item(k, py.None())?;
            } else if let Ok(i) = cell.parse::<i64>() {
                d.set_item(k, i)?;
            } else if let Ok(x) = cell.parse::<f64>() {
                d.set_item(k, x)?;
            } else {
                d.set_item(k, cell)?;
            }
        }
        rows.append(d)?;
    }
    Ok(rows)
}

#[pymethods]
impl PyStudy {
    /// One dict per pebble, the columns of `pebbles.csv` (id, sample, metadata, the `rocking
    /// analyze` columns, hand_nu/S/U/H at the study's ν, dynamic columns if asked for).
    #[getter]
    fn rows<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyList>> {
        csv_rows(py, &self.pebbles_csv)
    }
    /// One dict per sample, the columns of `samples.csv`.
    #[getter]
    fn samples<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyList>> {
        csv_rows(py, &self.samples_csv)
    }
    /// The `rocking analyze --json` report of every pebble (None where it failed).
    #[getter]
    fn reports<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let r: Vec<Option<&Report>> =
            self.study.pebbles.iter().map(|p| p.result.as_ref().ok().map(|c| &c.report)).collect();
        to_py(py, &r)
    }
    /// The error of every pebble (None where it was analysed).
    #[getter]
    fn errors(&self) -> Vec<Option<String>> {
        self.study.pebbles.iter().map(|p| p.result.as_ref().err().cloned()).collect()
    }
    /// ν of the fixed-ν (hand) columns.
    #[getter]
    fn nu(&self) -> f64 {
        self.study.nu
    }
    /// `pebbles.csv` exactly as `rocking study` writes it.
    fn pebbles_csv(&self) -> &str {
        &self.pebbles_csv
    }
    /// `samples.csv` exactly as `rocking study` writes it.
    fn samples_csv(&self) -> &str {
        &self.samples_csv
    }
    /// Columns of `rows` (pandas: `pd.DataFrame(study.to_dict())`).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let rows = self.rows(py)?;
        py.import("rocking_stones._tables")?.getattr("columns")?.call1((rows,))
    }
    fn __len__(&self) -> usize {
        self.study.pebbles.len()
    }
    fn __repr__(&self) -> String {
        let failed = self.study.pebbles.iter().filter(|p| p.result.is_err()).count();
        format!("<Study: {} pebbles, {} failed, nu = {}>", self.study.pebbles.len(), failed, self.study.nu)
    }
}

/// A field study over a folder of scans, as `rocking study FOLDER --meta META`; returns a
/// `Study` with one row per pebble (the columns of pebbles.csv). dynamic=True adds the
/// simulated hand experimenter (`trials` set-downs from `height` R_max per pebble).
#[pyfunction]
#[pyo3(signature = (folder, meta = None, *, nu = PAPER_NU, coplanar_tol = rocking_stones::hull::DEFAULT_COPLANAR_TOL, allow_unmatched = false, dynamic = false, trials = rocking_stones::study::DEFAULT_TRIALS, height = rocking_stones::study::DEFAULT_SET_DOWN_HEIGHT, seed = 1, threads = None, progress = None))]
#[allow(clippy::too_many_arguments)]
fn study(
    py: Python<'_>,
    folder: PathBuf,
    meta: Option<PathBuf>,
    nu: f64,
    coplanar_tol: f64,
    allow_unmatched: bool,
    dynamic: bool,
    trials: u64,
    height: f64,
    seed: u64,
    threads: Option<usize>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyStudy> {
    use rocking_stones::study::{self as st, Experimenter, Metadata, StudyOptions};
    let nu = check_nu(nu).map_err(py_err)?;
    if !folder.is_dir() {
        return Err(PyValueError::new_err(format!("{}: not a folder", folder.display())));
    }
    let experimenter = if dynamic {
        let params = DropParams { height, ..st::set_down_params() };
        params.check().map_err(py_err)?;
        if trials == 0 {
            return Err(PyValueError::new_err("trials must be at least 1"));
        }
        Some(Experimenter { trials, params, seed })
    } else {
        None
    };
    let files = st::mesh_files(&folder).map_err(py_err)?;
    let meta = meta.as_deref().map(Metadata::read).transpose().map_err(py_err)?;
    let opts = StudyOptions { analysis: options(None, coplanar_tol)?, nu, experimenter, allow_unmatched };
    let (study, _unmatched) = interruptible(py, threads, progress.map(|f| (f, files.len() as u64)), |c| {
        st::run_files(&files, meta.as_ref(), &opts, &|| c.tick())
    })?
    .map_err(py_err)?;
    fn text<E: std::fmt::Display>(r: Result<(), E>, buf: Vec<u8>) -> PyResult<String> {
        r.map_err(|e| PyRuntimeError::new_err(format!("{e:#}")))?;
        String::from_utf8(buf).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    }
    let mut p = Vec::new();
    let r = rocking_stones::report::study::write_pebbles_csv(&study, &mut p);
    let pebbles_csv = text(r, p)?;
    let mut s = Vec::new();
    let r = rocking_stones::report::study::write_samples_csv(&study, &st::summarize(&study), &mut s);
    let samples_csv = text(r, s)?;
    Ok(PyStudy { study, pebbles_csv, samples_csv })
}

// ---------------------------------------------------------------------------------------------
// generate

/// A synthetic shape as (vertices, faces) arrays, as `rocking generate`: tetrahedron, cube,
/// octahedron, dodecahedron, icosahedron (circumradius 1), box (axes = edge lengths), ellipsoid,
/// noisy-box, pebble (axes = semi-axes; n points, noise, roughness, seed).
#[pyfunction]
#[pyo3(signature = (shape, *, axes = None, n = None, noise = None, roughness = None, seed = 0))]
#[allow(clippy::type_complexity)]
fn generate<'py>(
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

/// Threads of the long runs by default: `RAYON_NUM_THREADS` if set, else the number of cores.
#[pyfunction]
fn num_threads() -> usize {
    rayon::current_num_threads()
}

// ---------------------------------------------------------------------------------------------

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("MeshError", m.py().get_type::<MeshError>())?;
    m.add("DEFAULT_COPLANAR_TOL", rocking_stones::hull::DEFAULT_COPLANAR_TOL)?;
    m.add("PAPER_NU", PAPER_NU)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<PyAnalysis>()?;
    m.add_class::<PyBasins>()?;
    m.add_class::<PyDropResult>()?;
    m.add_class::<PyDynamicsResult>()?;
    m.add_class::<PyStudy>()?;
    m.add_function(wrap_pyfunction!(analyze, m)?)?;
    m.add_function(wrap_pyfunction!(basins, m)?)?;
    m.add_function(wrap_pyfunction!(drop_stone, m)?)?;
    m.add_function(wrap_pyfunction!(perturb, m)?)?;
    m.add_function(wrap_pyfunction!(shake, m)?)?;
    m.add_function(wrap_pyfunction!(shake_rock, m)?)?;
    m.add_function(wrap_pyfunction!(study, m)?)?;
    m.add_function(wrap_pyfunction!(generate, m)?)?;
    m.add_function(wrap_pyfunction!(num_threads, m)?)?;
    Ok(())
}
