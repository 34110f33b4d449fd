//! `analyze` and the `Analysis` class: the static analysis of one stone (mass properties, hull,
//! micro-equilibria, the ν-hierarchy, plateau, macro counts, flocks and rocking equilibria) as
//! `rocking analyze` reports it.

use crate::basins::PyBasins;
use crate::convert::{f64s, i64s, kind_name, matrix3, point, py_err, rows3, strs, to_json, to_py};
use crate::mesh_input::{analyse, options, source};
use crate::stone::PyAnalysis;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

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

    /// For an open scan (a field scan, +z up, open where the rock meets its pedestal): what was
    /// found (dict: the rim and its loops, the gaps closed, the base that closed it, the numbers
    /// of micro-equilibria touching that base); None for a closed stone.
    #[getter]
    fn open_scan<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.report.open_scan)
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

/// Analyse a stone as `rocking analyze` does; returns an `Analysis`.
///
/// mesh: a path (STL, OBJ, PLY), a (vertices (n, 3), faces (m, 3)) pair of arrays, an object
///     with .vertices and .faces (trimesh.Trimesh), or None for the bundled scanned stone.
///     In-memory meshes are welded and checked like files; errors name `name` (default
///     "<memory>"). An open scan (+z up, open where the rock meets its pedestal) is closed with a
///     flat cap, and the micro-equilibria touching that hidden base are marked (`open_scan`).
/// nu: fixed ν of the macro scale (default: the automatic plateau, else 0.0035).
/// coplanar_tol: relative tolerance of the facet merge (× bounding-box diagonal); 1e-6 for f32
///     CAD files.
///
/// Raises MeshError (a ValueError) for unusable meshes, FileNotFoundError / OSError for
/// unreadable files, ValueError for bad options, each with the CLI's message.
#[pyfunction]
#[pyo3(signature = (mesh = None, nu = None, coplanar_tol = rocking_stones::hull::DEFAULT_COPLANAR_TOL, name = None))]
pub(crate) fn analyze(
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
