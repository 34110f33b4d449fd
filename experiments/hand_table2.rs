//! The two-tolerance hand experimenter calibrated on Table 2 (before: one ν; after), left one
//! sample out, and on the bundled real scans. `cargo experiment hand_table2` →
//! `results/hand_table2/`; the README's prose is `experiments/readme/hand_table2.md`.

use rocking_stones::report::hand_calibration::{write_calibration, Calibration};
use rocking_stones::study::{self, FitOptions, PopulationParams, TABLE2_EXPERIMENTER_ON_SCANS};

use experiments::harness;
use harness::{Result, Results};

/// The roughness grid of the profile (the first, 0.05, is `study fit-nu`'s default: the "before").
const ROUGHNESS: [f64; 9] = [0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.5];

fn main() -> Result<()> {
    let common = harness::common_args("The two-tolerance hand experimenter calibrated on Table 2, and its LOSO check.");
    let out = Results::open("hand_table2", &common)?;
    let hand = study::read_table2(&harness::repo().join("data/table2_hand_experiments.csv"))?;
    let params = PopulationParams { seed: common.seed_or(1), ..PopulationParams::default() };
    let (pops, gen_s) = harness::timed(|| study::table2_populations(&hand, &params, &ROUGHNESS));
    let pops = pops?;
    let (fit, fit_s) = harness::timed(|| study::fit_hand_table2(&hand, &pops));
    let fit = fit?;
    let before = study::fit_nu(&hand, &pops[0].curves, &FitOptions { bootstrap: 0, ..FitOptions::default() })?;
    let before_rows = study::one_nu_fits(&hand, &pops[0].curves, before.nu);
    let one_nu = study::one_nu_fits(&hand, &pops[fit.best].curves, fit.one_nu.nu);
    let (loso, loso_s) = harness::timed(|| study::leave_one_sample_out(&hand, &pops));
    let mut files = study::mesh_files(&harness::repo().join("data/meshes"))?;
    files.retain(|p| p.file_name().is_some_and(|n| n.to_string_lossy().starts_with("stone_")));
    files.insert(0, harness::repo().join("data/default_pebble.ply"));
    let scans = study::scans_counted(&files, &TABLE2_EXPERIMENTER_ON_SCANS)?;
    let (population, seconds) = ((&params, &ROUGHNESS[..]), [gen_s, fit_s, loso_s]);
    let (loso, before, direct) = (loso?, (&before, &before_rows[..]), study::hand_minus_scans(&hand));
    let c = Calibration { fit: &fit, before, one_nu: &one_nu, loso: &loso, scans: &scans, direct, population, seconds };
    out.readme(include_str!("readme/hand_table2.md"), write_calibration(&out.path(""), &c)?)
}
