//! What a person reads: summaries, CSV files, plots and other files written from the results of
//! the computation modules. Nothing here computes; every function reads a finished result.
//!
//! * [`analysis`] — one static analysis: summary, batch CSV, N(ν) plot, hull pictures.
//! * [`drops`] — drop runs: summary, `drops.json`, bar plots.
//! * [`perturb`] — perturbation runs: summary, curves/thresholds/trials CSV, plots.
//! * [`planar`] — the planar case: the summary of `rocking planar`.
//! * [`shake`] — shaking runs: summary, fragility CSV and plot, ground-motion records.
//! * [`study`] — field studies: pebble/sample/comparison CSVs, tables, Zingg and Figure 12 plots.

pub mod analysis;
pub mod drops;
pub mod perturb;
pub mod planar;
pub mod shake;
pub mod study;

pub use analysis::{
    flock_color, flock_colored_hull, plot_hull, plot_n_nu, summary, write_batch_csv, write_outputs, CSV_HEADER,
};
pub use drops::{bar_plot, drop_summary, write_drop_outputs, Bar};
