//! What a person reads of the calibration of the two-tolerance hand experimenter on Table 2
//! ([`crate::study::fit_hand_table2`], [`crate::study::leave_one_sample_out`]): the roughness
//! profile, model against Table 2 sample by sample (with the one-ν experimenter before it), the
//! leave-one-sample-out predictions, as CSV files and plots, and the numbers a README quotes.

use super::hand::{hand_vs_table2, write_sample_fits_csv};
use super::write_csv;
use crate::plot::{colors, Axis, Chart, Mark};
use crate::stats::min_max;
use crate::study::{LeftOut, NuFit, PopulationParams, RoughnessFit, SampleFit, ScanCounts, Table2HandFit};
use crate::study::{TABLE2_EXPERIMENTER, TABLE2_EXPERIMENTER_ON_SCANS, TABLE2_ROUGHNESS};
use plotters::style::RGBColor;
use serde_json::{json, Value};
use std::path::Path;

/// Everything [`write_calibration`] writes.
pub struct Calibration<'a> {
    /// The calibration.
    pub fit: &'a Table2HandFit,
    /// The one-ν fit before (`study fit-nu`'s populations) and its rows.
    pub before: (&'a NuFit, &'a [SampleFit]),
    /// The one-ν experimenter fitted at the chosen roughness, its rows.
    pub one_nu: &'a [SampleFit],
    /// Every sample predicted without it.
    pub loso: &'a [LeftOut],
    /// Real scans: name, the counts at ν = 0.0035 and the distribution of the calibrated
    /// experimenter in the scans' frame ([`TABLE2_EXPERIMENTER_ON_SCANS`]).
    pub scans: &'a [ScanCounts],
    /// The direct route to the scans' frame: the person's counts against the real scans' at
    /// ν = 0.0035 on the samples Table 2 has both for ([`crate::study::hand_minus_scans`]).
    pub direct: Option<[(f64, f64); 2]>,
    /// The synthetic populations' parameters (roughness: see the profile) and roughness grid.
    pub population: (&'a PopulationParams, &'a [f64]),
    /// Seconds to generate the populations, fit the profile and leave each sample out.
    pub seconds: [f64; 3],
}

/// A curve of the roughness profile: its legend, colour and value.
type Curve<'a> = (&'a str, RGBColor, &'a dyn Fn(&RoughnessFit) -> f64);

fn e2(x: f64) -> String {
    format!("{x:.2e}")
}

fn f(x: f64, digits: usize) -> String {
    format!("{x:.digits$}")
}

/// Write profile.csv, samples.csv, computer.csv, samples_one_nu_before.csv, loso.csv,
/// hand_vs_table2, roughness_profile and loso plots (PNG and SVG) into `dir`; return the
/// numbers a README quotes (fields named as in the experiment's template).
pub fn write_calibration(dir: &Path, c: &Calibration) -> crate::Result<Value> {
    let (fit, best) = (c.fit, c.fit.chosen());
    let header = [
        "roughness",
        "nu_S",
        "sd_S",
        "se_log10_nu_S",
        "se_sd_S",
        "nu_U",
        "sd_U",
        "se_log10_nu_U",
        "se_sd_U",
        "chi2_hand",
        "chi2_computer",
        "total",
    ];
    let rows = fit.profile.iter().map(|p| {
        let (s, u) = (p.fit.stable, p.fit.unstable);
        let mut row = vec![p.roughness.to_string()];
        for t in [s, u] {
            row.extend([
                e2(t.tolerance.median),
                f(t.tolerance.sd_log10, 3),
                f(t.se_log10_median, 3),
                f(t.se_sd_log10, 3),
            ]);
        }
        row.extend([f(p.fit.chi2, 1), f(p.chi2_computer, 1), f(p.total, 1)]);
        row
    });
    write_csv(&dir.join("profile.csv"), &header, rows)?;
    for (name, rows) in
        [("samples", &best.fit.samples[..]), ("computer", &best.computer), ("samples_one_nu_before", c.before.1)]
    {
        let p = dir.join(format!("{name}.csv"));
        let file = std::fs::File::create(&p).map_err(|e| crate::Error::Io { path: p.clone(), error: e })?;
        write_sample_fits_csv(rows, file).map_err(|e| e.with_path(&p))?;
    }
    let (before, exp) = (c.before.0, best.fit.experimenter);
    let models = [
        (format!("two tolerances (χ² = {:.0})", best.fit.chi2), &best.fit.samples[..]),
        (
            format!("one ν = {} at roughness {} (χ² = {:.0})", e2(fit.one_nu.nu), best.roughness, fit.one_nu.chi2_min),
            c.one_nu,
        ),
        (format!("before: one ν = {} at roughness 0.05 (χ² = {:.0})", e2(before.nu), before.chi2_min), c.before.1),
    ];
    let title = format!("Hand experimenter against Table 2 (synthetic pebbles, roughness {})", best.roughness);
    let predicted: Vec<SampleFit> = c.loso.iter().map(|l| l.prediction.clone()).collect();
    let loso_models = [
        ("leave-one-sample-out prediction".to_string(), &predicted[..]),
        ("in-sample fit".to_string(), &best.fit.samples[..]),
    ];
    let pts = |g: &dyn Fn(&RoughnessFit) -> f64| -> Vec<(f64, f64)> {
        fit.profile.iter().map(|p| (p.roughness, g(p))).collect()
    };
    let top = fit.profile.iter().map(|p| p.total).fold(0.0, f64::max) * 1.1;
    let mut profile = Chart::new(
        Axis::linear("roughness amplitude of the synthetic pebbles", 0.0, 0.55),
        Axis::linear("χ²", 0.0, top),
    )
    .title("Profile of the calibration over the roughness");
    let curves: [Curve; 3] = [
        ("total (hand + computer columns)", colors::GREEN, &|p| p.total),
        ("hand columns (22 samples × 4, tolerances fitted)", colors::BLUE, &|p| p.fit.chi2),
        ("computer columns (5 scanned samples × 4, ν = 0.0035)", colors::VERMILLION, &|p| p.chi2_computer),
    ];
    for (label, colour, g) in curves {
        profile = profile.legend(Mark::LineDot(colour), label).line(&pts(g), colour).dots(&pts(g), colour);
    }
    let profile = profile.vline(fit.roughness, colors::GREY);
    for ext in ["png", "svg"] {
        hand_vs_table2(&title, 50, &models).save(&dir.join(format!("hand_vs_table2.{ext}")), (1500, 1000))?;
        let loso_title = "Each sample predicted by the experimenter fitted on the other 21";
        hand_vs_table2(loso_title, 50, &loso_models).save(&dir.join(format!("loso.{ext}")), (1500, 1000))?;
        profile.clone().save(&dir.join(format!("roughness_profile.{ext}")), (1000, 650))?;
    }
    let header = [
        "sample",
        "roughness",
        "nu_S",
        "sd_S",
        "nu_U",
        "sd_U",
        "hand_E_S",
        "hand_E_U",
        "hand_sd_S",
        "hand_sd_U",
        "pred_E_S",
        "pred_E_U",
        "pred_sd_S",
        "pred_sd_U",
        "z_E_S",
        "z_E_U",
        "z_sd_S",
        "z_sd_U",
        "chi2",
        "chi2_in_sample",
    ];
    let rows = c.loso.iter().zip(&best.fit.samples).map(|(l, inside)| {
        let (e, p) = (l.experimenter, &l.prediction);
        let mut row = vec![p.id.clone(), l.roughness.to_string()];
        row.extend([e2(e.stable.median), f(e.stable.sd_log10, 3), e2(e.unstable.median), f(e.unstable.sd_log10, 3)]);
        row.extend(p.hand.iter().chain(&p.model.as_array()).map(|x| f(*x, 3)));
        row.extend(p.z.iter().map(|z| f(*z, 2)));
        row.extend([f(p.chi2, 2), f(inside.chi2, 2)]);
        row
    });
    write_csv(&dir.join("loso.csv"), &header, rows)?;

    let zs: Vec<f64> = c.loso.iter().flat_map(|l| l.prediction.z).collect();
    let within = |k: f64| zs.iter().filter(|z| z.abs() <= k).count();
    let loso_chi2: f64 = c.loso.iter().map(|l| l.prediction.chi2).sum();
    let span = |g: &dyn Fn(&LeftOut) -> f64, show: &dyn Fn(f64) -> String| {
        let (lo, hi) = min_max(c.loso.iter().map(g));
        format!("{} – {}", show(lo), show(hi))
    };
    let mut worst: Vec<&SampleFit> = best.fit.samples.iter().collect();
    worst.sort_by(|a, b| b.chi2.total_cmp(&a.chi2));
    let worst: Vec<Value> =
        worst.iter().take(6).map(|s| json!({"id": s.id, "chi2": f(s.chi2, 0), "z": s.z.map(|z| f(z, 1))})).collect();
    let near: Vec<&SampleFit> = best.fit.samples.iter().filter(|s| s.chi2 <= 12.0).collect();
    let near_chi2: f64 = near.iter().map(|s| s.chi2).sum();
    let near_dof = (4 * near.len()).saturating_sub(4).max(1);
    let reduced = |x: f64, dof: usize| f(x / dof as f64, 2);
    let real: Vec<Value> = c
        .scans
        .iter()
        .map(|(name, (s, u), d)| {
            let m = d.most_likely();
            json!({"cells": [name, format!("{{{s},{u}}}"), format!("{{{},{}}}", m.stable, m.unstable), f(m.p, 2),
                f(d.stable_moments()[0], 2), f(d.unstable_moments()[0], 2)]})
        })
        .collect();
    let tol = |t: crate::study::ToleranceFit| {
        json!([
            e2(t.tolerance.median),
            f(t.tolerance.sd_log10, 2),
            f(t.se_log10_median, 2),
            f(t.se_sd_log10, 2),
            f(t.chi2, 0)
        ])
    };
    let (pop, grid, cal, on_scans) =
        (c.population.0, c.population.1, TABLE2_EXPERIMENTER, TABLE2_EXPERIMENTER_ON_SCANS);
    let direct = c.direct.map(|d| d.map(|(x, se)| [f(x, 3), f(se, 3), f(x / se, 2)]));
    Ok(json!({
        "grid": grid.iter().map(|r| r.to_string()).collect::<Vec<_>>().join(", "), "count": pop.count,
        "points": pop.points, "spread": pop.spread, "seed": pop.seed, "seconds": c.seconds.map(|s| f(s, 0)),
        "cal": [e2(cal.stable.median), f(cal.stable.sd_log10, 2), e2(cal.unstable.median), f(cal.unstable.sd_log10, 2),
            TABLE2_ROUGHNESS.to_string()],
        "r": best.roughness.to_string(), "r_hat": f(fit.roughness, 3), "at_edge": fit.at_edge,
        "r_interval": [f(fit.roughness_interval.0, 3), f(fit.roughness_interval.1, 3)],
        "stable": tol(best.fit.stable), "unstable": tol(best.fit.unstable), "finer": exp.stable.median < exp.unstable.median,
        "chi2": f(best.fit.chi2, 0), "dof": best.fit.dof, "reduced": reduced(best.fit.chi2, best.fit.dof),
        "chi2_computer": f(best.chi2_computer, 0), "total": f(best.total, 0), "total_dof": fit.dof,
        "total_reduced": reduced(best.total, fit.dof),
        "before": [e2(before.nu), f(before.chi2_min, 0), before.dof.to_string(), reduced(before.chi2_min, before.dof)],
        "one_nu": [e2(fit.one_nu.nu), f(fit.one_nu.chi2_min, 0), reduced(fit.one_nu.chi2_min, fit.one_nu.dof)],
        "worst": worst, "near": [near.len().to_string(), f(near_chi2, 0), near_dof.to_string(), reduced(near_chi2, near_dof)],
        "loso": [f(loso_chi2, 0), reduced(loso_chi2, zs.len()), within(1.0).to_string(), within(2.0).to_string(),
            zs.len().to_string(), reduced(loso_chi2, c.loso.len())],
        "loso_span": [span(&|l| l.roughness, &|x| x.to_string()), span(&|l| l.experimenter.stable.median, &e2),
            span(&|l| l.experimenter.unstable.median, &e2)],
        "real": real,
        "shift": fit.scan_shift.map(|d| f(d, 3)),
        "scan_frame": [e2(fit.in_scan_frame().stable.median), e2(fit.in_scan_frame().unstable.median)],
        "on_scans": [e2(on_scans.stable.median), f(on_scans.stable.sd_log10, 2), e2(on_scans.unstable.median),
            f(on_scans.unstable.sd_log10, 2)],
        "direct": direct,
    }))
}
