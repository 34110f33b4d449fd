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
//!
//! One module per concept: `convert` (errors and conversions), `mesh_input` (the `mesh`
//! argument), `stone` (an analysed stone: the `Analysis` class's data), `long_run` (worker thread, GIL released, Ctrl-C), `kwargs` (parameters from
//! `**kwargs`), then one per command: `analysis`, `basins`, `drops`, `dynamics` (perturb, shake,
//! shake_rock), `study` and `generate`.
//!
//! [`TriMesh::into_solid_boundary`]: rocking_stones::mesh::TriMesh::into_solid_boundary
//! [`Error`]: rocking_stones::Error

// `!(x > 0.0)` is used on purpose: it is true for NaN, which must be refused too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod analysis;
mod basins;
mod convert;
mod drops;
mod dynamics;
mod generate;
mod kwargs;
mod long_run;
mod mesh_input;
mod stone;
mod study;

use convert::MeshError;
use pyo3::prelude::*;
use rocking_stones::analysis::PAPER_NU;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("MeshError", m.py().get_type::<MeshError>())?;
    m.add("DEFAULT_COPLANAR_TOL", rocking_stones::hull::DEFAULT_COPLANAR_TOL)?;
    m.add("PAPER_NU", PAPER_NU)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<stone::PyAnalysis>()?;
    m.add_class::<basins::PyBasins>()?;
    m.add_class::<drops::PyDropResult>()?;
    m.add_class::<dynamics::PyDynamicsResult>()?;
    m.add_class::<study::PyStudy>()?;
    m.add_function(wrap_pyfunction!(analysis::analyze, m)?)?;
    m.add_function(wrap_pyfunction!(basins::basins, m)?)?;
    m.add_function(wrap_pyfunction!(drops::drop_stone, m)?)?;
    m.add_function(wrap_pyfunction!(dynamics::perturb, m)?)?;
    m.add_function(wrap_pyfunction!(dynamics::shake, m)?)?;
    m.add_function(wrap_pyfunction!(dynamics::shake_rock, m)?)?;
    m.add_function(wrap_pyfunction!(study::study, m)?)?;
    m.add_function(wrap_pyfunction!(generate::generate, m)?)?;
    m.add_function(wrap_pyfunction!(long_run::num_threads, m)?)?;
    Ok(())
}
