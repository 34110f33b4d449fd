//! The resting stone under loads: `perturb` (pushes and spins, as `rocking perturb`), `shake`
//! (fragility curves under ground shaking, as `rocking shake`) and `shake_rock` (a field rock at
//! its true size under one recorded motion), with the `DynamicsResult` class and the parameters,
//! real size and starting equilibria they share.

use crate::convert::{columns, py_err, to_json, to_py};
use crate::kwargs::{enum_from_str, with_params};
use crate::long_run::interruptible;
use crate::stone::analysed;
use numpy::PyReadonlyArray2;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rocking_stones::dynamics::size::{RealSize, Size};
use rocking_stones::dynamics::surface::Surface;
use serde::Serialize;
use std::path::PathBuf;

/// A perturbation or shaking run: its report (as the CLI's `--json`) and every trial.
#[pyclass(frozen, module = "rocking_stones", name = "DynamicsResult")]
pub(crate) struct PyDynamicsResult {
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

/// The parameters of a resting run as the CLI makes them (`--contact-model`, `--surface`, the
/// real size), then the keyword overrides in real units (DropParams fields go into `sim`).
/// `preset=` named the contact model before `contact_model=` did: refused, naming it.
fn resting_params(
    what: &str,
    contact_model: Option<&str>,
    preset: Option<&str>,
    surface: Option<&str>,
    default_surface: Surface,
    size: &RealSize,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<rocking_stones::dynamics::resting::RestingParams> {
    use rocking_stones::dynamics::resting::{RestingParams, RestingPreset};
    if let Some(p) = preset {
        return Err(PyValueError::new_err(format!(
            "{what}: preset= is drop's launch protocol; the contact of a resting run is contact_model= \
             ('surface' or 'damped'), got preset={p:?}"
        )));
    }
    let model: RestingPreset = contact_model.unwrap_or("surface").parse().map_err(py_err)?;
    let surface: Surface = surface.map_or(Ok(default_surface), str::parse).map_err(py_err)?;
    let base = RestingParams::of(model, surface, size.r_max_m).map_err(py_err)?;
    let p: RestingParams = with_params(what, &base, params, size)?;
    p.check().map_err(py_err)?;
    Ok(p)
}

/// The real size of the stone `name` whose R_max is `r_max` mesh units, as the CLI's
/// `--length-unit` / `--size`: `size=` (R_max in metres) or `length_unit=` (a name or metres per
/// unit) if given, else the bundled stone's millimetres, else refused (a `ValueError` saying
/// why, [`RealSize::resolve`]); a size that is not plausible for a stone is told with a
/// `UserWarning` before the run.
pub(crate) fn real_size(
    py: Python<'_>,
    name: &str,
    r_max: f64,
    length_unit: Option<&Bound<'_, PyAny>>,
    size: Option<f64>,
) -> PyResult<RealSize> {
    let given = match (length_unit, size) {
        (Some(_), Some(_)) => return Err(PyValueError::new_err("give length_unit= or size=, not both")),
        (None, Some(r)) => Some(Size::RMax(r)),
        (Some(u), None) => Some(Size::Unit(length_unit_m(u)?)),
        (None, None) => None,
    };
    let real = RealSize::resolve(name, r_max, given)
        .map_err(|e| PyValueError::new_err(e.spelled(&|n: &str| format!("{n}="))))?;
    if let Some(warning) = real.implausibility(name) {
        warn(py, &format!("{warning}."))?;
    }
    Ok(real)
}

/// `length_unit=`: "mm", "cm", "m", "km", "in" or metres per mesh unit (a number or its text).
pub(crate) fn length_unit_m(u: &Bound<'_, PyAny>) -> PyResult<f64> {
    use rocking_stones::mesh::unit::LengthUnit;
    let text = match u.extract::<f64>() {
        Ok(x) => x.to_string(),
        Err(_) => u.extract::<String>()?,
    };
    text.parse::<LengthUnit>().map(|u| u.metres).map_err(py_err)
}

/// `certificate=` of `perturb`: "none", "facet", "flock", or a bool (False: none, True: facet).
fn certificate_mode(c: Option<&Bound<'_, PyAny>>) -> PyResult<rocking_stones::dynamics::certificate::CertificateMode> {
    use rocking_stones::dynamics::certificate::CertificateMode;
    let Some(c) = c else { return Ok(CertificateMode::None) };
    if let Ok(b) = c.extract::<bool>() {
        return Ok(if b { CertificateMode::Facet } else { CertificateMode::None });
    }
    enum_from_str("certificate", &c.extract::<String>()?, "'none', 'facet', 'flock'")
}

/// A `UserWarning` with `message`, raised at the caller's line.
pub(crate) fn warn(py: Python<'_>, message: &str) -> PyResult<()> {
    let message = std::ffi::CString::new(message.replace('\0', " ")).expect("no NUL left");
    PyErr::warn(py, &py.get_type::<pyo3::exceptions::PyUserWarning>(), &message, 1)
}

/// Push or spin the stone resting on its stable micro-equilibria, as `rocking perturb`;
/// returns a `DynamicsResult` whose to_dict() is the CLI's --json. contact_model: "surface"
/// (default) or "damped"; surface: the pair (default "stone-on-stone"); length_unit= or size=:
/// the real size (needed for every mesh but the bundled stone; a size outside R_max 2 mm to 20 m
/// is told with a UserWarning). certificate: "none" (default), "facet" (also True) or "flock".
/// **params in real units for the stone's size, as the CLI's options: friction, restitution,
/// rolling_resistance_mm, dt (s), max_time (s), contact_frequency (Hz), settle_time, hold_time,
/// rest_time (s), rest_linear_speed (m/s), rest_angular_speed (rad/s).
#[pyfunction]
#[pyo3(signature = (mesh = None, *, equilibria = None, flock = None, family = "push", trials = 40, seed = 1, eps_min = 1e-5, eps_max = 1.0, eps_steps = 16, epsilon_star = None, certificate = None, contact_model = None, preset = None, surface = None, length_unit = None, size = None, nu = None, name = None, threads = None, progress = None, **params))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn perturb(
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
    certificate: Option<&Bound<'_, PyAny>>,
    contact_model: Option<&str>,
    preset: Option<&str>,
    surface: Option<&str>,
    length_unit: Option<&Bound<'_, PyAny>>,
    size: Option<f64>,
    nu: Option<f64>,
    name: Option<String>,
    threads: Option<usize>,
    progress: Option<&Bound<'_, PyAny>>,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyDynamicsResult> {
    use rocking_stones::dynamics::pushes::{self as pt, PerturbConfig};
    if !(eps_min > 0.0 && eps_max >= eps_min && eps_steps > 0) {
        return Err(PyValueError::new_err("need 0 < eps_min ≤ eps_max and eps_steps ≥ 1"));
    }
    let s = analysed(py, mesh, name, nu)?;
    let stone = py.detach(|| rocking_stones::dynamics::stone::Stone::new(&s.analysis, s.nu())).map_err(py_err)?;
    let real = real_size(py, &s.name, stone.body.r_max, length_unit, size)?;
    let params = resting_params("perturb", contact_model, preset, surface, Surface::StoneOnStone, &real, params)?;
    let certificate = certificate_mode(certificate)?;
    let params = rocking_stones::dynamics::resting::RestingParams { certificate, ..params };
    let cfg = PerturbConfig {
        params,
        family: enum_from_str("family", family, "'push', 'spin'")?,
        epsilons: rocking_stones::stats::log_grid(eps_min, eps_max, rocking_stones::stats::GridSize::Points(eps_steps)),
        trials,
        seed,
        epsilon_star,
    };
    cfg.check().map_err(py_err)?;
    let starts = stone.select(&equilibria.unwrap_or_default(), flock).map_err(py_err)?;
    let progress = progress.map(|f| (f, pt::task_count(starts.len(), &cfg)));
    let report = interruptible(py, threads, progress, |c| pt::perturb_equilibria_monitored(&stone, &starts, &cfg, c))?
        .map_err(py_err)?;
    let report = pt::PerturbReport { r_max_m: Some(real.r_max_m), size_assumed: Some(real.assumed()), ..report };
    dynamics_result("perturb", &report, &report.trials, rocking_stones::report::perturb::summary(&report, &s.name))
}

/// Shake the ground under the resting stone, as `rocking shake`: fragility curves; returns a
/// `DynamicsResult`. pulse=(amplitude in g, frequency in Hz of the real stone, cycles) or
/// motion= a CSV (read with `columns` and `accel_unit`) or one to three .AT2 paths; the default
/// sweeps 2 sine cycles at 0.639 cycles per √(R_max/g) up to 1 g. azimuth: degrees from the x
/// axis of the stone as it stands (the CLI's --azimuth). contact_model, surface, length_unit /
/// size and **params as for `perturb`.
#[pyfunction]
#[pyo3(signature = (mesh = None, *, equilibria = None, pulse = None, motion = None, columns = "1,2", accel_unit = "g", pga_max = None, pga_steps = 20, azimuth = None, trials = 40, seed = 1, contact_model = None, preset = None, surface = None, length_unit = None, size = None, nu = None, name = None, threads = None, progress = None, **params))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn shake(
    py: Python<'_>,
    mesh: Option<&Bound<'_, PyAny>>,
    equilibria: Option<Vec<usize>>,
    pulse: Option<(f64, f64, f64)>,
    motion: Option<&Bound<'_, PyAny>>,
    columns: &str,
    accel_unit: &str,
    pga_max: Option<f64>,
    pga_steps: usize,
    azimuth: Option<f64>,
    trials: u32,
    seed: u64,
    contact_model: Option<&str>,
    preset: Option<&str>,
    surface: Option<&str>,
    length_unit: Option<&Bound<'_, PyAny>>,
    size: Option<f64>,
    nu: Option<f64>,
    name: Option<String>,
    threads: Option<usize>,
    progress: Option<&Bound<'_, PyAny>>,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyDynamicsResult> {
    use rocking_stones::dynamics::shaking::{self as sh, ShakeConfig};
    if pulse.is_some() && motion.is_some() {
        return Err(PyValueError::new_err("give a pulse or a motion, not both"));
    }
    let s = analysed(py, mesh, name, nu)?;
    let stone = py.detach(|| rocking_stones::dynamics::stone::Stone::new(&s.analysis, s.nu())).map_err(py_err)?;
    let real = real_size(py, &s.name, stone.body.r_max, length_unit, size)?;
    let r_max_m = real.r_max_m;
    let params = resting_params("shake", contact_model, preset, surface, Surface::StoneOnStone, &real, params)?;
    let real_dt = params.sim.numerics.dt * r_max_m.sqrt();
    let (motion, default_sweep) = match (pulse, motion) {
        (Some((a, f, c)), _) => (sh::sine_pulse(a, f, c, real_dt).map_err(py_err)?, false),
        (None, Some(m)) => (read_motion_arg(m, columns, accel_unit)?, false),
        (None, None) => (sh::default_pulse(r_max_m, params.sim.numerics.dt).map_err(py_err)?, true),
    };
    let pgas = sh::pgas_for(&motion, pga_max, pga_steps, default_sweep).map_err(py_err)?;
    let cfg = ShakeConfig { params, motion, pgas, trials, seed, azimuth: azimuth.map(f64::to_radians), r_max_m };
    cfg.check().map_err(py_err)?;
    let starts = match equilibria {
        None => py.detach(|| sh::default_starts(&stone, &cfg.params)).map_err(py_err)?,
        Some(ids) => stone.select(&ids, None).map_err(py_err)?,
    };
    let progress = progress.map(|f| (f, (starts.len() * cfg.pgas.len()) as u64 * cfg.trials as u64));
    let report = interruptible(py, threads, progress, |c| sh::sweep_fragility_monitored(&stone, &starts, &cfg, c))?
        .map_err(py_err)?;
    let report = sh::ShakeReport { size_assumed: Some(real.assumed()), ..report };
    dynamics_result("shake", &report, &report.trials, rocking_stones::report::shake::summary(&report, &s.name))
}

/// `motion=`: a CSV path (read with `columns` and `accel_unit`) or a list of one to three PEER
/// `.AT2` paths (x, y, z), read by the CLI's reader.
fn read_motion_arg(
    m: &Bound<'_, PyAny>,
    columns: &str,
    accel_unit: &str,
) -> PyResult<rocking_stones::ground_motion::Record> {
    use rocking_stones::ground_motion::read::{read_record, AccelUnit, Columns};
    let paths: Vec<PathBuf> = match m.extract::<PathBuf>() {
        Ok(p) => vec![p],
        Err(_) => m.extract::<Vec<PathBuf>>()?,
    };
    let columns: Columns = columns.parse().map_err(py_err)?;
    let unit: AccelUnit = accel_unit.parse().map_err(py_err)?;
    let refs: Vec<&std::path::Path> = paths.iter().map(|p| p.as_path()).collect();
    read_record(&refs, &columns, unit).map_err(py_err)
}

/// A field rock at its true size under one recorded ground motion, as
/// `rocking shake MESH --pose POSE --length-unit UNIT --motion ... --json`: the same dict.
/// The motion is `motion=` a CSV path (read with `columns` and `accel_unit`) or a list of one to
/// three PEER `.AT2` paths (x, y, z), or `accel=` an array of shape (n,) or (n, k ≤ 3) in m/s²
/// (x, y horizontal, z up) sampled every `dt` seconds. `length_unit`: "mm", "cm", "m", "km" or
/// metres per mesh unit (default mm for the bundled stone; m otherwise, assumed with a
/// UserWarning, as the CLI says it). `azimuth`:
/// degrees (world frame) of the record's x axis (default 0); `scale`: factor on the record.
///
/// `ensemble=N` (as `--ensemble N`): N members over what is not known about the rock, each
/// drawing the uncertain inputs uniformly from their ranges, member m from the stream
/// (`seed`, m) (`--seed`, default 1); returns the dict of `--ensemble N --json` instead: `record`,
/// `scale`, `pga_g`, `pgv_m_s`, `pgv_over_pga_s`, `pga_vertical_g`, `seed`, `uncertainty` (the
/// ranges used, in m and degrees), `probability` {members, settled, overturned, p_overturn,
/// interval95 (Wilson 95 %)}, `sensitivity` [{input, measure ("spearman" or
/// "circular-linear"), correlation (None when undefined)}], `tipping` [the quasi-static tipping
/// polar at base-contact tolerance 0 and at the ends of its range] and `members` [{draw, run}]
/// in member order. `uncertainty=` a dict (needs `ensemble=`), every key optional:
/// `contact_tolerance` T (meaning [0, T]) or (low, high) in the mesh's length unit
/// (`--contact-tolerance`); `azimuth` (low, high) degrees or "unknown" ([0, 360],
/// `--azimuth-range`; not with `azimuth=`); `random_sign` bool (`--random-sign`); `friction`,
/// `restitution` (low, high) and `rolling_resistance_mm` (low, high) in mm (`--friction-range`,
/// `--restitution-range`, `--rolling-resistance-range`; one number x means (x, x)). Friction,
/// restitution and rolling resistance not given range over the `surface` pair's published
/// ranges. The members run in parallel; Ctrl-C stops the members not yet started.
#[pyfunction]
#[pyo3(signature = (mesh = None, *, pose, length_unit = None, size = None, motion = None, accel = None, dt = None, columns = "1,2", accel_unit = "g", baseline = None, azimuth = None, surface = "rock-on-concrete", scale = 1.0, ensemble = None, uncertainty = None, seed = 1, nu = None, name = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn shake_rock<'py>(
    py: Python<'py>,
    mesh: Option<&Bound<'py, PyAny>>,
    pose: &str,
    length_unit: Option<&Bound<'py, PyAny>>,
    size: Option<f64>,
    motion: Option<&Bound<'py, PyAny>>,
    accel: Option<&Bound<'py, PyAny>>,
    dt: Option<f64>,
    columns: &str,
    accel_unit: &str,
    baseline: Option<usize>,
    azimuth: Option<f64>,
    surface: &str,
    scale: f64,
    ensemble: Option<u64>,
    uncertainty: Option<&Bound<'py, PyDict>>,
    seed: u64,
    nu: Option<f64>,
    name: Option<String>,
) -> PyResult<Bound<'py, PyAny>> {
    use rocking_stones::dynamics::shaking::{self as sh, EnsembleSpec, Pose, RockSetup, Uncertainty};
    use rocking_stones::ground_motion::Record;
    let pose: Pose = pose.parse().map_err(py_err)?;
    let surface: Surface = surface.parse().map_err(py_err)?;
    let given = match (ensemble, uncertainty) {
        (None, Some(_)) => {
            return Err(PyValueError::new_err("uncertainty= needs ensemble=N (the number of members to draw)"))
        }
        (None, None) => None,
        (Some(_), u) => Some(given_uncertainty(u)?),
    };
    if given.as_ref().is_some_and(|g| g.azimuth_deg.is_some()) && azimuth.is_some() {
        return Err(PyValueError::new_err("give azimuth= or uncertainty[\"azimuth\"], not both"));
    }
    let azimuth = azimuth.unwrap_or(0.0).to_radians();
    let record = match (motion, accel) {
        (Some(_), Some(_)) => return Err(PyValueError::new_err("give motion= (files) or accel= (an array), not both")),
        (None, None) => return Err(PyValueError::new_err("give motion= (a CSV or .AT2 files) or accel= with dt=")),
        (Some(m), None) => read_motion_arg(m, columns, accel_unit)?,
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
    let stone = py.detach(|| rocking_stones::dynamics::stone::Stone::new(&s.analysis, s.nu())).map_err(py_err)?;
    let real = real_size(py, &s.name, stone.body.r_max, length_unit, size)?;
    let pose = pose.resolved(&stone).map_err(py_err)?;
    let sized = |setup: RockSetup| RockSetup { size_assumed: Some(real.assumed()), ..setup };
    let unit = real.length_unit_m;
    if let (Some(members), Some(given)) = (ensemble, given) {
        let setup = sized(RockSetup::new(&stone, pose, unit, surface, azimuth).map_err(py_err)?);
        // As the command line (`ensemble_spec` of `rocking shake`): nothing is pinned, since
        // shake_rock takes no friction / restitution / rolling-resistance override.
        let uncertainty = Uncertainty::stated(&given, surface, [false; 3]);
        let spec = EnsembleSpec { uncertainty, seed, members };
        spec.check().map_err(py_err)?;
        // Every member's own rock when the base is drawn (`rocking shake`'s `--base drawn`).
        let rocks = py.detach(|| sh::field_members(&s.analysis, &s.opts, &stone, &setup, &spec)).map_err(py_err)?;
        let rock = sh::FieldRock { stone: &stone, members: &rocks };
        // Ctrl-C stops the members not yet started (`interruptible`).
        let run = interruptible(py, None, None, |c| sh::run_ensemble(rock, &setup, &record, scale, &spec, c))?;
        return to_py(py, &run.map_err(py_err)?);
    }
    let run = py.detach(|| -> rocking_stones::Result<sh::RecordRun> {
        let setup = sized(RockSetup::new(&stone, pose, unit, surface, azimuth)?);
        sh::run_record(&stone, &setup, &record, scale)
    });
    to_py(py, &run.map_err(py_err)?)
}

/// The keys of `shake_rock`'s `uncertainty=` dict.
const UNCERTAINTY_KEYS: [&str; 11] = [
    "contact_tolerance_mm",
    "azimuth",
    "random_sign",
    "friction",
    "restitution",
    "rolling_resistance_mm",
    "base",
    "base_depth_mm",
    "base_band_mm",
    "base_region",
    "rocking_points_mm",
];

/// `uncertainty=` of `shake_rock` as the command line's `given` uncertainty (user units: the
/// mesh's length unit, degrees, mm), each range checked and named by its key.
fn given_uncertainty(d: Option<&Bound<'_, PyDict>>) -> PyResult<rocking_stones::dynamics::shaking::Uncertainty> {
    use pyo3::types::PyBool;
    use rocking_stones::dynamics::shaking::BaseUncertainty;
    let mut given = rocking_stones::dynamics::shaking::Uncertainty {
        base: Some(BaseUncertainty::calibrated()),
        ..Default::default()
    };
    let Some(d) = d else { return Ok(given) };
    let repr = |v: &Bound<'_, PyAny>| v.repr().map_or_else(|_| "?".into(), |r| r.to_string());
    // A pair (low, high), or one number x: [0, x] when `from_zero`, else [x, x] (`parse_range`).
    let range = |key: &str, v: &Bound<'_, PyAny>, from_zero: bool| -> PyResult<[f64; 2]> {
        let bad = || {
            let one = if from_zero { " or a number T (meaning (0, T))" } else { " or one number" };
            PyValueError::new_err(format!("uncertainty[{key:?}] must be a pair (low, high){one}, got {}", repr(v)))
        };
        if v.is_instance_of::<PyBool>() {
            return Err(bad());
        }
        if let Ok(x) = v.extract::<f64>() {
            return Ok(if from_zero { [0.0, x] } else { [x, x] });
        }
        match v.extract::<Vec<f64>>() {
            Ok(x) if x.len() == 2 => Ok([x[0], x[1]]),
            _ => Err(bad()),
        }
    };
    for (k, v) in d.iter() {
        let key: String = k
            .extract()
            .map_err(|_| PyValueError::new_err(format!("uncertainty= keys must be strings, got {}", repr(&k))))?;
        match key.as_str() {
            "contact_tolerance_mm" => given.contact_tolerance_m = Some(range(&key, &v, true)?),
            "contact_tolerance" => {
                return Err(PyValueError::new_err(
                    "uncertainty[\"contact_tolerance\"] (in the mesh's unit) is now uncertainty[\"contact_tolerance_mm\"], in mm",
                ))
            }
            "azimuth" => {
                given.azimuth_deg = Some(match v.extract::<String>() {
                    Ok(s) if s == "unknown" => [0.0, 360.0],
                    Ok(s) => {
                        return Err(PyValueError::new_err(format!(
                            "uncertainty[\"azimuth\"] must be a pair (low, high) of degrees or \"unknown\", got {s:?}"
                        )))
                    }
                    Err(_) => range(&key, &v, false)?,
                })
            }
            "random_sign" => {
                given.random_sign = v.extract::<bool>().map_err(|_| {
                    PyValueError::new_err(format!(
                        "uncertainty[\"random_sign\"] must be True or False, got {}",
                        repr(&v)
                    ))
                })?
            }
            "friction" => given.friction = Some(range(&key, &v, false)?),
            "restitution" => given.restitution = Some(range(&key, &v, false)?),
            "rolling_resistance_mm" => given.rolling_resistance_m = Some(range(&key, &v, false)?),
            "base" => match v.extract::<String>().ok().as_deref() {
                Some("drawn") => given.base = given.base.or(Some(BaseUncertainty::calibrated())),
                Some("scanned") => given.base = None,
                _ => {
                    return Err(PyValueError::new_err(format!(
                        "uncertainty[\"base\"] must be \"drawn\" or \"scanned\", got {}",
                        repr(&v)
                    )))
                }
            },
            "base_depth_mm" | "base_band_mm" | "base_region" | "rocking_points_mm" => {
                let Some(b) = given.base.as_mut() else {
                    return Err(PyValueError::new_err(format!("uncertainty[{key:?}] needs the base drawn, not scanned")));
                };
                match key.as_str() {
                    "base_depth_mm" => b.depth_m = Some(range(&key, &v, true)?.map(|x| x * 1e-3)),
                    "base_band_mm" => b.band_m = v.extract::<f64>()? * 1e-3,
                    "rocking_points_mm" => {
                        let p: [[f64; 2]; 3] = v.extract().map_err(|_| {
                            PyValueError::new_err(format!("uncertainty[{key:?}]: three points (x, y) in mm"))
                        })?;
                        b.rocking_points_m = Some(p.map(|q| q.map(|x| x * 1e-3)));
                    }
                    _ => b.region = range(&key, &v, false)?,
                }
            }
            _ => {
                return Err(PyValueError::new_err(format!(
                    "uncertainty: unknown key {key:?} (keys: {})",
                    UNCERTAINTY_KEYS.join(", ")
                )))
            }
        }
    }
    // The ranges in the user's units (scaling by a positive unit keeps them valid), named by key.
    given.check().map_err(|e| {
        PyValueError::new_err(e.spelled(&|name| {
            let key = match name {
                "rolling_resistance" => "rolling_resistance_mm",
                "contact_tolerance" => "contact_tolerance_mm",
                "base_depth" => "base_depth_mm",
                "base_band" => "base_band_mm",
                other => other,
            };
            format!("uncertainty[{key:?}]")
        }))
    })?;
    Ok(given)
}
