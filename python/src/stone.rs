//! An analysed stone: the data of the `Analysis` class (its methods are in `analysis`), and the
//! `mesh` argument of every call that needs an analysed stone — an `Analysis` itself (reused, with
//! its ν unless `nu` is given) or any mesh input, analysed as `rocking analyze` does.

use crate::convert::py_err;
use crate::mesh_input::{analyse, options, source};
use pyo3::prelude::*;
use rocking_stones::analysis::{check_nu, Analysis, Options, Report};
use std::sync::Arc;

/// The static analysis of one stone: mass properties, hull, micro-equilibria, the ν-hierarchy,
/// the plateau, macro counts, flocks and rocking equilibria.
#[pyclass(frozen, module = "rocking_stones", name = "Analysis")]
pub(crate) struct PyAnalysis {
    pub(crate) inner: Arc<Analysis>,
    pub(crate) opts: Options,
    pub(crate) name: String,
    pub(crate) report: Report,
}

impl PyAnalysis {
    pub(crate) fn new(a: Analysis, name: String, opts: Options) -> Self {
        let report = a.report(&name, &opts);
        PyAnalysis { inner: Arc::new(a), opts, name, report }
    }
}

/// An analysed stone: the argument itself when it is an [`PyAnalysis`] (with its ν unless `nu`
/// is given), else a fresh analysis with the CLI's default options.
pub(crate) fn analysed(
    py: Python<'_>,
    mesh: Option<&Bound<'_, PyAny>>,
    name: Option<String>,
    nu: Option<f64>,
) -> PyResult<Stone> {
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

pub(crate) struct Stone {
    pub(crate) analysis: Arc<Analysis>,
    pub(crate) name: String,
    pub(crate) opts: Options,
}

impl Stone {
    pub(crate) fn nu(&self) -> f64 {
        self.analysis.macro_nu(&self.opts).0
    }
}
