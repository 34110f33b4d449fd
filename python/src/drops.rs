//! `drop` and the `DropResult` class: Monte Carlo drops in rapier3d, run as `rocking drop` runs
//! them; the caller's Ctrl-C stops the run before its next drop.

use crate::convert::{bools, f64s, i64s, kind_name, opt_index, py_err, strs, to_json, to_py};
use crate::dynamics::real_size;
use crate::kwargs::{enum_from_str, with_params};
use crate::long_run::interruptible;
use crate::stone::analysed;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rocking_stones::dynamics::certificate::CertificateMode;
use rocking_stones::dynamics::drops::launch::DropOutcome;
use rocking_stones::dynamics::drops::montecarlo::{self, DropReport, DropRun, RunHeader, DEFAULT_BATCH};
use rocking_stones::dynamics::drops::params::{DropParams, Preset};
use rocking_stones::dynamics::size::RealSize;
use rocking_stones::dynamics::stone::Stone as Body;
use rocking_stones::dynamics::surface::Surface;

/// The result of a drop run: the report `rocking drop --json` prints and every drop's outcome.
#[pyclass(frozen, module = "rocking_stones", name = "DropResult")]
pub(crate) struct PyDropResult {
    report: DropReport,
    outcomes: Vec<DropOutcome>,
    size: RealSize,
}

/// The JSON of `rocking drop --json`: the report, the stone's real size and whether it was
/// assumed.
#[derive(serde::Serialize)]
struct Sized<'a> {
    #[serde(flatten)]
    report: &'a DropReport,
    r_max_m: f64,
    size_assumed: bool,
}

impl PyDropResult {
    fn sized(&self) -> Sized<'_> {
        Sized { report: &self.report, r_max_m: self.size.r_max_m, size_assumed: self.size.assumed() }
    }
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
    /// Drops still moving at the time cap (left out of every count and fit).
    #[getter]
    fn unsettled(&self) -> u64 {
        self.report.unsettled
    }
    /// The deepest any hull corner went below the ground at any step or sub-step (R_max).
    #[getter]
    fn deepest_penetration(&self) -> f64 {
        self.report.deepest_penetration
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
        share_columns(&d, f.iter().map(|x| (x.count, x.fraction, x.ci95, x.static_probability)))?;
        Ok(d)
    }
    /// Per flock as columns: id, type, count, fraction, ci95_lo, ci95_hi, static_probability.
    #[getter]
    fn flocks<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let f = &self.report.flocks;
        let d = PyDict::new(py);
        d.set_item("id", i64s(py, f.iter().map(|x| x.id as i64).collect()))?;
        d.set_item("type", strs(py, f.iter().map(|x| kind_name(x.kind)).collect())?)?;
        share_columns(&d, f.iter().map(|x| (x.count, x.fraction, x.ci95, x.static_probability)))?;
        Ok(d)
    }
    /// Every drop as columns: index, settled, facet, flock (-1: none), time, certified,
    /// deepest_penetration (R_max).
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
        d.set_item("deepest_penetration", f64s(py, o.iter().map(|x| x.deepest_penetration).collect()))?;
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
        to_py(py, &self.sized())
    }
    /// The report as JSON text (`pretty=True`: as `rocking drop --json` prints it).
    #[pyo3(signature = (pretty = true))]
    fn to_json(&self, pretty: bool) -> PyResult<String> {
        to_json(&self.sized(), pretty)
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

/// The columns facets and flocks share, from (count, fraction, 95 % interval, static
/// probability) per row: count, fraction, ci95_lo, ci95_hi, static_probability.
fn share_columns(d: &Bound<'_, PyDict>, rows: impl Iterator<Item = (u64, f64, (f64, f64), f64)>) -> PyResult<()> {
    let py = d.py();
    let rows: Vec<_> = rows.collect();
    d.set_item("count", i64s(py, rows.iter().map(|r| r.0 as i64).collect()))?;
    d.set_item("fraction", f64s(py, rows.iter().map(|r| r.1).collect()))?;
    d.set_item("ci95_lo", f64s(py, rows.iter().map(|r| r.2 .0).collect()))?;
    d.set_item("ci95_hi", f64s(py, rows.iter().map(|r| r.2 .1).collect()))?;
    d.set_item("static_probability", f64s(py, rows.iter().map(|r| r.3).collect()))
}

// The drops run as `rocking drop` runs them ([`DropRun`]); the caller's Ctrl-C stops the run
// before its next drop (KeyboardInterrupt).
/// Drop the stone `n` times from uniformly random orientations in rapier3d, as
/// `rocking drop MESH -n N --seed S`; returns a `DropResult` whose to_dict() is the CLI's --json.
///
/// preset: "quasi-static", "drop" or "throw" (the CLI's default); surface: "steel-on-wood" (the
/// default), "stone-on-stone", "rock-on-concrete", "rock-on-steel"; size: R_max of the real
/// stone in metres (scales the contact as --size does), or length_unit: the mesh's unit ("mm",
/// "cm", "m", "km", "in" or metres per unit); needed for every mesh but the bundled stone
/// (R_max = 178 mm); a size outside R_max 2 mm to 20 m is told with a UserWarning.
/// **params override single parameters, as the CLI's options, in real units for the stone's
/// size: height (R_max), horizontal_speed (m/s), spin (rad/s), spin_distribution, friction,
/// restitution, rolling_resistance_mm, torsional_friction_mm (mm), linear_damping,
/// angular_damping (1/s), dt (s), solver_iterations, max_time (s), rest_linear_speed (m/s),
/// rest_angular_speed (rad/s), rest_time (s), flight ("free", the default: exact landings and sub-stepped
/// impacts, or "rapier": contacts found at rapier's step boundaries; the CLI's --flight).
/// certificate: "none", "facet" or "flock" (energy certificate that ends decided drops early).
/// reference: the CLI's --reference (free flight at the reference step 1/240 s, the one the
/// default 1/120 s is checked against; **params still override it). fast: accepted so that
/// older scripts run; the preset's longest stable step is the default.
/// threads: threads of this run (default:
/// RAYON_NUM_THREADS or all cores). progress: callable(done, total), called about every 0.1 s
/// (e.g. to update a tqdm bar). Releases the GIL; Ctrl-C raises KeyboardInterrupt.
#[pyfunction]
#[pyo3(signature = (mesh = None, n = 1000, seed = 1, *, preset = "throw", surface = "steel-on-wood", size = None, length_unit = None, certificate = "facet", reference = false, fast = false, nu = None, name = None, threads = None, progress = None, **params))]
#[pyo3(name = "drop")]
#[allow(clippy::too_many_arguments)]
pub(crate) fn drop_stone(
    py: Python<'_>,
    mesh: Option<&Bound<'_, PyAny>>,
    n: u64,
    seed: u64,
    preset: &str,
    surface: &str,
    size: Option<f64>,
    length_unit: Option<&Bound<'_, PyAny>>,
    certificate: &str,
    reference: bool,
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
    if reference && fast {
        return Err(PyValueError::new_err(
            "reference and fast exclude each other: the reference step is 1/240 s, fast's (the default) 1/120 s",
        ));
    }
    let certificate: CertificateMode = enum_from_str("certificate", certificate, "'none', 'facet', 'flock'")?;
    let stone = analysed(py, mesh, name, nu)?;
    let body = py.detach(|| Body::new(&stone.analysis, stone.nu())).map_err(py_err)?;
    let real = real_size(py, &stone.name, body.body.r_max, length_unit, size)?;
    let mut base = preset.params_for(surface, Some(real.r_max_m)).map_err(py_err)?;
    if reference {
        preset.reference(&mut base);
    }
    let p: DropParams = with_params("drop", &base, params, &real)?;
    p.check().map_err(py_err)?;
    let header = RunHeader {
        r_max_m: Some(real.r_max_m),
        ..RunHeader::new(&stone.name, &stone.analysis.mesh, seed, n, p, certificate, (preset, surface))
    };
    let progress = progress.map(|f| (f, n));
    let outcomes =
        interruptible(py, threads, progress, |control| DropRun::new(&body, &header).run(DEFAULT_BATCH, control))?
            .map_err(py_err)?;
    let report = montecarlo::summarize(&body.model(), &header, &outcomes);
    Ok(PyDropResult { report, outcomes: outcomes.into_values().collect(), size: real })
}
