//! `basins` and the `Basins` class: the quasi-static resting probability of every stable facet
//! (the area of its basin on the sphere of down directions / 4π) and of every flock.

use crate::convert::{f64s, i64s, rows3};
use crate::stone::analysed;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rocking_stones::analysis::Analysis;

/// Quasi-static resting probabilities: the basin of every stable facet on the sphere of down
/// directions (area / 4π, exact up to `error`).
#[pyclass(frozen, module = "rocking_stones", name = "Basins")]
pub(crate) struct PyBasins {
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
    pub(crate) fn of(a: &Analysis, nu: f64) -> PyBasins {
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
pub(crate) fn basins(
    py: Python<'_>,
    mesh: Option<&Bound<'_, PyAny>>,
    nu: Option<f64>,
    name: Option<String>,
) -> PyResult<PyBasins> {
    let stone = analysed(py, mesh, name, nu)?;
    let nu = stone.nu();
    Ok(py.detach(move || PyBasins::of(&stone.analysis, nu)))
}
