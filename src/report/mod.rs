//! What a person reads: summaries, CSV files, plots and other files written from the results of
//! the computation modules. Nothing here computes; every function reads a finished result.
//!
//! * [`analysis`] — one static analysis: summary, batch CSV, N(ν) plot, hull pictures.
//! * [`drops`] — drop runs: summary, `drops.json`, bar plots.
//! * [`perturb`] — perturbation runs: summary, curves/thresholds/trials CSV, plots.
//! * [`planar`] — the planar case: the summary of `rocking planar`.
//! * [`shake`] — shaking runs, field-rock runs, ensembles and batches: summaries, fragility CSV
//!   and plots, the fragility surface, ground-motion records.
//! * [`study`] — field studies: pebble/sample/comparison CSVs, tables, Zingg and Figure 12 plots.
//! * [`nu_fit`] — fits of ν to hand counts: their χ²(ν) curves.
//! * [`hand`], [`hand_calibration`] — the two-tolerance hand experimenter: its pebble columns and
//!   JSON, model against Table 2, and its calibration on Table 2.

pub mod analysis;
pub mod drops;
pub mod hand;
pub mod hand_calibration;
pub mod html;
pub mod names;
pub mod nu_fit;
pub mod perturb;
pub mod planar;
pub mod shake;
pub mod study;
pub mod tipping;

pub use analysis::{
    flock_color, flock_colored_hull, plot_hull, plot_n_nu, summary, summary_in, write_batch_csv, write_outputs,
    write_outputs_in, CSV_HEADER,
};
pub use drops::{bar_plot, drop_summary, drop_summary_sized, write_drop_outputs, Bar, Scaled};

use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The files of an output folder, written one by one and listed in the order written.
pub(crate) struct Folder {
    dir: PathBuf,
    pub written: Vec<PathBuf>,
}

impl Folder {
    /// Create the folder `dir` (and its parents).
    pub fn create(dir: &Path) -> Result<Self> {
        create_dir(dir)?;
        Ok(Folder { dir: dir.to_path_buf(), written: Vec::new() })
    }

    /// Write the file `name` of the folder with `write` and list it.
    pub fn file(&mut self, name: &str, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
        let p = self.dir.join(name);
        write(&p)?;
        self.written.push(p);
        Ok(())
    }
}

/// The line every simulation summary ends its header with: the deepest penetration of the
/// ground measured at any step or sub-step (R_max), against
/// [`crate::dynamics::engine::impact::DEPTH_BOUND`], with a warning and what to change when it was
/// exceeded.
pub fn depth_line(deepest: f64) -> String {
    let bound = crate::dynamics::engine::impact::DEPTH_BOUND;
    if deepest > bound {
        format!(
            "  WARNING: a hull corner went {deepest:.3} R_max into the ground (bound {bound} R_max): an impact was \
             resolved inside the ground and the outcome is less reliable. Add --strict-impacts (drops: the \
             sub-steps re-read after every impact), or lower --dt, the launch speed and spin, or the motion's \
             amplitude.\n"
        )
    } else {
        format!(
            "  deepest penetration of the ground: {deepest:.2e} R_max at any step or sub-step (bound {bound} R_max)\n"
        )
    }
}

/// The file name of a mesh path for captions (the whole string if it has none).
pub fn short_name(name: &str) -> String {
    Path::new(name).file_name().map_or(name.to_string(), |f| f.to_string_lossy().into_owned())
}

/// Create the output folder `dir` (and its parents).
pub(crate) fn create_dir(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|error| Error::Io { path: dir.to_path_buf(), error })
}

/// Write a CSV file at `path`: the `header`, then one record per row of `rows` (each already
/// formatted); a failure (of the file or of a row) is an [`Error::Io`] naming the file.
pub(crate) fn write_csv<R, S>(path: &Path, header: &[&str], rows: impl IntoIterator<Item = R>) -> Result<()>
where
    R: IntoIterator<Item = S>,
    S: AsRef<[u8]>,
{
    (|| -> std::result::Result<_, crate::error::BoxError> {
        let mut w = csv::Writer::from_path(path)?;
        w.write_record(header)?;
        for row in rows {
            w.write_record(row)?;
        }
        w.flush()?;
        Ok(())
    })()
    .map_err(|e| Error::write(path, e))
}

/// Write `value` as pretty JSON to `path`.
pub(crate) fn write_json<T: serde::Serialize + ?Sized>(path: &Path, value: &T) -> Result<()> {
    let text = serde_json::to_string_pretty(value).map_err(|e| Error::write(path, e))?;
    std::fs::write(path, text).map_err(|error| Error::Io { path: path.to_path_buf(), error })
}
