//! What a person reads of ground shaking ([`crate::dynamics::shaking`]), one file per kind of run:
//!
//! * [`trials`] — a shaking run of the stable equilibria: summary, fragility CSV and plot, trials.
//! * [`runs`] — field-rock runs under records: `runs.csv` and the one-run summary.
//! * [`ensemble`] — ensembles of a field rock: summary, members, the tipping polar, contour bands.
//! * [`batch`] — a batch of runs: summary, the fragility surface plot and its files.
//!
//! Ground-motion records are written here as CSV.

pub mod batch;
pub mod ensemble;
pub mod runs;
pub mod trials;

pub use batch::{batch_summary, plot_fragility_surface, write_batch_outputs};
pub use ensemble::{ensemble_runs, ensemble_summary, tipping_lines, write_ensemble_outputs};
pub use runs::{rock_run_summary, run_csv_row, write_run_outputs, write_runs_csv, RUN_CSV_HEADER};
pub use trials::{pga50_cell, plot_fragility, summary, write_fragility_csv, write_outputs, write_trials_csv};

use crate::dynamics::shaking::MotionInfo;
use crate::ground_motion::Record;
use std::path::Path;

/// Write a record as CSV: time (s) and the three components in g (`time_s,ax_g,ay_g,az_g`, what
/// `--columns time_s,ax_g,ay_g,az_g --accel-unit g` reads back).
pub fn write_record(path: &Path, r: &Record) -> crate::Result<()> {
    let g = |x: f64| format!("{:.6}", x / crate::GRAVITY);
    let rows = r.accel.iter().enumerate().map(|(k, a)| [format!("{:.5}", k as f64 * r.dt), g(a[0]), g(a[1]), g(a[2])]);
    crate::report::write_csv(path, &["time_s", "ax_g", "ay_g", "az_g"], rows)
}

/// One line that says what a motion is: its name, PGA, PGV (processed or given) and duration.
pub fn describe_motion(m: &MotionInfo) -> String {
    format!(
        "{} (PGA {:.3} g, {} PGV {:.3} m/s, {:.2} s)",
        m.name,
        m.measures.pga_g,
        m.measures.pgv_source.name(),
        m.measures.pgv_m_s,
        m.measures.duration_s
    )
}
