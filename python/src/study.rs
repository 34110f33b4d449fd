//! `study` and the `Study` class: a field study over a folder of scans, as `rocking study`, with
//! its `pebbles.csv` and `samples.csv` as text and as rows, and each pebble's distribution of
//! the hand counts (`hand.json`).

use crate::convert::{py_err, to_py};
use crate::long_run::interruptible;
use crate::mesh_input::options;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rocking_stones::analysis::{check_nu, Report, PAPER_NU};
use std::path::PathBuf;

/// A field study: one row per scan with the columns of `pebbles.csv`.
#[pyclass(frozen, module = "rocking_stones", name = "Study")]
pub(crate) struct PyStudy {
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
    /// ν of the one-ν hand columns; None when the two-tolerance experimenter counts them.
    #[getter]
    fn nu(&self) -> Option<f64> {
        self.study.hand.is_none().then_some(self.study.nu)
    }
    /// The two-tolerance hand experimenter (dict of its stable and unstable tolerances: median
    /// and sd_log10), None for the one-ν one.
    #[getter]
    fn experimenter<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.study.hand)
    }
    /// Every analysed pebble's distribution of the hand counts, as `hand.json`: a dict with
    /// `experimenter` and `pebbles` (id, sample, file, most_likely {stable, unstable, saddle, p},
    /// distribution {stable: [{count, p}], unstable: [...]}).
    fn hand<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = rocking_stones::report::hand::hand_json(&self.study).map_err(py_err)?;
        py.import("json")?.getattr("loads")?.call1((text,))
    }
    /// `hand.json` exactly as `rocking study` writes it.
    fn hand_json(&self) -> PyResult<String> {
        rocking_stones::report::hand::hand_json(&self.study).map_err(py_err)
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
        let hand = match self.study.hand {
            Some(_) => "two tolerances".to_string(),
            None => format!("nu = {}", self.study.nu),
        };
        format!("<Study: {} pebbles, {} failed, {hand}>", self.study.pebbles.len(), failed)
    }
}

/// A field study over a folder of scans, as `rocking study FOLDER --meta META`; returns a
/// `Study` with one row per pebble (the columns of pebbles.csv). The hand columns are the
/// two-tolerance hand experimenter's most likely pair (`tolerances=(nu_s, sd_s, nu_u, sd_u)`,
/// default the calibration on Table 2 in the real scans' frame, as `rocking study FOLDER`), or with
/// `nu=` the paper's one-ν counts. dynamic=True adds the
/// simulated hand experimenter (`trials` set-downs from `height` R_max per pebble), each pebble
/// set down at its real size, given by `length_unit=` (the scans' unit: "mm", "cm", "m", "km",
/// "in" or metres per unit), which it needs.
#[pyfunction]
#[pyo3(signature = (folder, meta = None, *, nu = None, tolerances = None, coplanar_tol = rocking_stones::hull::DEFAULT_COPLANAR_TOL, allow_unmatched = false, dynamic = false, length_unit = None, trials = rocking_stones::study::DEFAULT_TRIALS, height = rocking_stones::study::DEFAULT_SET_DOWN_HEIGHT, seed = 1, threads = None, progress = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn study(
    py: Python<'_>,
    folder: PathBuf,
    meta: Option<PathBuf>,
    nu: Option<f64>,
    tolerances: Option<(f64, f64, f64, f64)>,
    coplanar_tol: f64,
    allow_unmatched: bool,
    dynamic: bool,
    length_unit: Option<&Bound<'_, PyAny>>,
    trials: u64,
    height: f64,
    seed: u64,
    threads: Option<usize>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyStudy> {
    use rocking_stones::study::{self as st, Experimenter, HandExperimenter, Metadata, StudyOptions, Tolerance};
    let hand = match (nu, tolerances) {
        (Some(_), Some(_)) => return Err(PyValueError::new_err("give nu= (one ν) or tolerances= (two), not both")),
        (Some(_), None) => None,
        (None, None) => Some(st::TABLE2_EXPERIMENTER_ON_SCANS),
        (None, Some((a, b, c, d))) => Some(HandExperimenter {
            stable: Tolerance::new("stable", a, b).map_err(py_err)?,
            unstable: Tolerance::new("unstable", c, d).map_err(py_err)?,
        }),
    };
    let nu = check_nu(nu.unwrap_or(PAPER_NU)).map_err(py_err)?;
    if !folder.is_dir() {
        return Err(PyValueError::new_err(format!("{}: not a folder", folder.display())));
    }
    let experimenter = if dynamic {
        let mut params = st::set_down_params();
        params.launch.height = height;
        params.check().map_err(py_err)?;
        if trials == 0 {
            return Err(PyValueError::new_err("trials must be at least 1"));
        }
        let length_unit_m = match length_unit {
            Some(u) => Some(crate::dynamics::length_unit_m(u)?),
            None => {
                let e = rocking_stones::Error::SizeUnknown {
                    mesh: format!("{} (the scans)", folder.display()),
                    one_stone: false,
                };
                return Err(PyValueError::new_err(e.spelled(&|n: &str| format!("{n}="))));
            }
        };
        Some(Experimenter { trials, params, seed, length_unit_m })
    } else if length_unit.is_some() {
        return Err(PyValueError::new_err(
            "length_unit= sets the size of the dynamic experimenter: it needs dynamic=True",
        ));
    } else {
        None
    };
    let files = st::mesh_files(&folder).map_err(py_err)?;
    let meta = meta.as_deref().map(Metadata::read).transpose().map_err(py_err)?;
    let opts = StudyOptions { analysis: options(None, coplanar_tol)?, nu, experimenter, allow_unmatched };
    let (mut study, _unmatched) = interruptible(py, threads, progress.map(|f| (f, files.len() as u64)), |c| {
        st::run_files(&files, meta.as_ref(), &opts, c)
    })?
    .map_err(py_err)?;
    study.hand = hand;
    if let Some(u) = opts.experimenter.as_ref().and_then(|e| e.length_unit_m) {
        let odd = study.implausible_sizes(u).map_err(py_err)?;
        if let Some(first) = odd.first() {
            let more = if odd.len() > 1 { format!(" (and {} more pebbles)", odd.len() - 1) } else { String::new() };
            crate::dynamics::warn(py, &format!("{first}{more}."))?;
        }
    }
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
