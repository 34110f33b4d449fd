//! The two-tolerance hand experimenter in `rocking study`: its flag (`--tolerances`), the files
//! it writes (hand.json, the model against Table 2 with z-scores and its plot) and `rocking
//! study fit-hand` (library: `rocking_stones::study::{hand, fit_hand_table2}`).

use anyhow::{Context, Result};
use rocking_stones::report::hand::{hand_json, hand_vs_table2, write_sample_fits_csv};
use rocking_stones::study::{self, HandExperimenter, HandSample, PopulationParams, Study, Tolerance};
use std::path::{Path, PathBuf};

/// The hand experimenter's flag, shared by `study FOLDER` and `study synthetic`.
#[derive(clap::Args, Clone)]
pub struct HandArgs {
    /// The two-tolerance hand experimenter (the default, unless --nu gives the paper's one-ν
    /// one): NU_S,SD_S,NU_U,SD_U, the median tolerance at which stable equilibria are told
    /// apart and its spread between pebbles (standard deviation of log10 ν, decades), then the
    /// same for unstable ones. Default: the calibration on the paper's Table 2 (see `study
    /// fit-hand`): on a folder of real scans in the scans' frame (ν_S = 3.16e-3 ×/÷ 10^0.17,
    /// ν_U = 3.41e-3), on synthetic pebbles as fitted on them (3.55e-3 ×/÷ 10^0.17, 1.52e-2).
    #[arg(long, value_name = "NU_S,SD_S,NU_U,SD_U", conflicts_with = "nu")]
    pub tolerances: Option<String>,
}

impl HandArgs {
    /// The experimenter: None with a one-ν `nu`, else the given tolerances or `calibrated`
    /// (the calibration in the frame of the pebbles counted: real scans or synthetic pebbles).
    pub fn experimenter(&self, nu: Option<f64>, calibrated: HandExperimenter) -> Result<Option<HandExperimenter>> {
        if nu.is_some() {
            return Ok(None);
        }
        let Some(text) = &self.tolerances else { return Ok(Some(calibrated)) };
        let x: Vec<f64> = text
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .ok()
            .filter(|x: &Vec<f64>| x.len() == 4)
            .with_context(|| format!("--tolerances must be four numbers NU_S,SD_S,NU_U,SD_U, got {text:?}"))?;
        let spell = |e: rocking_stones::Error| anyhow::anyhow!("--tolerances: {}", e.spelled(&|n| n.replace('_', " ")));
        Ok(Some(HandExperimenter {
            stable: Tolerance::new("stable", x[0], x[1]).map_err(spell)?,
            unstable: Tolerance::new("unstable", x[2], x[3]).map_err(spell)?,
        }))
    }
}

/// Say which experimenter counts the hand columns.
pub fn describe(study: &Study) -> String {
    match study.hand {
        Some(e) => format!(
            "hand columns: the two-tolerance experimenter{}, stable at ν_S = {:.2e} ×/÷ 10^{:.2}, unstable at ν_U = \
             {:.2e} ×/÷ 10^{:.2} (median, spread between pebbles); hand_S, hand_U: the most likely pair, hand_p its \
             probability, hand_pairs the distribution (also hand.json)",
            match e {
                e if e == study::TABLE2_EXPERIMENTER_ON_SCANS => " calibrated on Table 2, in the real scans' frame",
                e if e == study::TABLE2_EXPERIMENTER => " calibrated on Table 2, on synthetic pebbles",
                _ => "",
            },
            e.stable.median,
            e.stable.sd_log10,
            e.unstable.median,
            e.unstable.sd_log10
        ),
        None => format!("hand columns: the paper's one-ν experimenter, the counts of G(ν) at ν = {:.2e}", study.nu),
    }
}

/// Write hand.json and, with Table 2 samples among the study's, hand_vs_table2.csv/.png/.svg.
/// Returns what it wrote.
pub fn write_hand(study: &Study, table: Option<&[HandSample]>, dir: &Path) -> Result<Vec<PathBuf>> {
    let mut wrote = Vec::new();
    let p = dir.join("hand.json");
    std::fs::write(&p, hand_json(study)?).with_context(|| format!("{}: cannot write", p.display()))?;
    wrote.push(p);
    let Some(table) = table else { return Ok(wrote) };
    let rows = study::compare_hand(table, study);
    if rows.is_empty() {
        eprintln!("warning: no sample of the study is named as a sample of the table; no comparison written");
        return Ok(wrote);
    }
    let p = dir.join("hand_vs_table2.csv");
    write_sample_fits_csv(&rows, std::fs::File::create(&p).with_context(|| format!("{}: cannot create", p.display()))?)
        .map_err(|e| e.with_path(&p))?;
    wrote.push(p);
    let label = match study.hand {
        Some(_) => "model: two-tolerance hand experimenter".to_string(),
        None => format!("model: counts at ν = {:.2e}", study.nu),
    };
    let n = table.first().map_or(50, |h| h.n);
    for ext in ["png", "svg"] {
        let p = dir.join(format!("hand_vs_table2.{ext}"));
        hand_vs_table2("Hand counts: model against the table, per sample", n, &[(label.clone(), &rows[..])])
            .save(&p, (1500, 1000))?;
        wrote.push(p);
    }
    let chi2: f64 = rows.iter().map(|r| r.chi2).sum();
    println!(
        "against the table: χ² = {chi2:.1} over {} samples × 4 statistics (z-scores in hand_vs_table2.csv)",
        rows.len()
    );
    Ok(wrote)
}

/// `rocking study fit-hand`: calibrate the two-tolerance experimenter on Table 2.
#[derive(clap::Args)]
pub struct FitHandArgs {
    /// A Table 2 CSV (columns as in the paper's Table 2); default: the paper's Table 2, bundled.
    #[arg(long)]
    pub table: Option<PathBuf>,
    /// Roughness amplitudes of the synthetic pebbles to profile (comma-separated); the one whose
    /// fit matches the hand columns and, at ν = 0.0035, the table's computer columns best is
    /// chosen. Each costs one population of every sample.
    #[arg(long, value_delimiter = ',', default_value = "0.2,0.3,0.4")]
    pub roughness: Vec<f64>,
    /// Points per synthetic pebble.
    #[arg(long, default_value_t = 2000, value_parser = super::at_least::<usize, 12>)]
    pub points: usize,
    /// Synthetic pebbles per sample.
    #[arg(long, default_value_t = 50, value_parser = super::at_least::<usize, 2>)]
    pub count: usize,
    /// Seed of the synthetic pebbles.
    #[arg(long, default_value_t = 1, value_parser = super::at_least::<u64, 0>)]
    pub seed: u64,
    /// Also leave each sample out, refit on the others and predict it (loso.csv).
    #[arg(long)]
    pub loso: bool,
    /// Output folder.
    #[arg(short, long, default_value = "study_fit_hand")]
    pub output: PathBuf,
}

pub fn fit_hand(args: FitHandArgs) -> Result<()> {
    if let Some(r) = args.roughness.iter().find(|r| !(0.0..1.0).contains(*r)) {
        anyhow::bail!("--roughness must be in [0, 1), got {r}");
    }
    let hand = match &args.table {
        Some(path) => study::read_table2(path)?,
        None => study::bundled_table2()?,
    };
    let params = PopulationParams { points: args.points, count: args.count, seed: args.seed, ..Default::default() };
    eprintln!("{} samples × {} synthetic pebbles at roughness {:?}", hand.len(), args.count, args.roughness);
    let pops = study::table2_populations(&hand, &params, &args.roughness)?;
    let fit = study::fit_hand_table2(&hand, &pops)?;
    let dir = &args.output;
    std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create folder", dir.display()))?;
    let best = fit.chosen();
    let p = dir.join("samples.csv");
    write_sample_fits_csv(&best.fit.samples, std::fs::File::create(&p)?).map_err(|e| e.with_path(&p))?;
    let one_rows = study::one_nu_fits(&hand, &pops[fit.best].curves, fit.one_nu.nu);
    let models = [
        (format!("two tolerances (χ² = {:.0})", best.fit.chi2), &best.fit.samples[..]),
        (format!("one ν = {:.2e} (χ² = {:.0})", fit.one_nu.nu, fit.one_nu.chi2_min), &one_rows[..]),
    ];
    for ext in ["png", "svg"] {
        hand_vs_table2("Hand experimenter against the table", hand[0].n, &models)
            .save(&dir.join(format!("hand_vs_table2.{ext}")), (1500, 1000))?;
    }
    let loso = if args.loso { Some(study::leave_one_sample_out(&hand, &pops)?) } else { None };
    let json = serde_json::json!({ "population": params, "fit": fit, "loso": loso });
    std::fs::write(dir.join("fit.json"), serde_json::to_string_pretty(&json)?)?;
    let (e, s, u) = (best.fit.experimenter, best.fit.stable, best.fit.unstable);
    println!(
        "roughness {} (vertex {:.3}, interval {:.3} – {:.3}{})",
        best.roughness,
        fit.roughness,
        fit.roughness_interval.0,
        fit.roughness_interval.1,
        if fit.at_edge { ", at an end of the grid" } else { "" }
    );
    println!(
        "ν_S = {:.2e} (log10 ± {:.2}), spread {:.2} ± {:.2} decades; ν_U = {:.2e} (log10 ± {:.2}), spread {:.2} ± {:.2}",
        e.stable.median,
        s.se_log10_median,
        e.stable.sd_log10,
        s.se_sd_log10,
        e.unstable.median,
        u.se_log10_median,
        e.unstable.sd_log10,
        u.se_sd_log10
    );
    println!(
        "χ² (hand) = {:.1} for {} dof ({:.2}); computer columns at ν = 0.0035: {:.1}; one ν at this roughness: ν = {:.2e}, χ² = {:.1}",
        best.fit.chi2,
        best.fit.dof,
        best.fit.chi2 / best.fit.dof as f64,
        best.chi2_computer,
        fit.one_nu.nu,
        fit.one_nu.chi2_min
    );
    let frame = fit.in_scan_frame();
    println!(
        "the computer columns' real scans count like these synthetic pebbles at ν·10^δ, δ_S = {:.3}, δ_U = {:.3} \
         decades: in the scans' frame ν_S = {:.2e}, ν_U = {:.2e}",
        fit.scan_shift[0], fit.scan_shift[1], frame.stable.median, frame.unstable.median
    );
    if let Some(l) = &loso {
        let chi2: f64 = l.iter().map(|x| x.prediction.chi2).sum();
        println!("leave one sample out: χ² = {chi2:.1} over {} predicted statistics", 4 * l.len());
    }
    println!("wrote {}", dir.display());
    Ok(())
}
