//! What a person reads of fits of ν to hand counts ([`crate::study::fit_nu`]): their χ²(ν)
//! curves side by side, as a chart in the house style.

use crate::analysis::PAPER_NU;
use crate::plot::{colors, log_tick, series_color, style, Axis, Chart, Mark, Marker};
use crate::study::{NuFit, PopulationParams};
use std::fmt::Display;
use std::path::Path;

/// χ²(ν) curves of several fits `fits` (label, fit) on log–log axes (y described by `y_label`),
/// each with its fitted ν̂ marked and named in the legend, the paper's ν = 0.0035 dashed grey:
/// series colours in order ([`series_color`]), the curves beyond the 8th dashed. The axes span
/// the grids and the positive χ² values (the y range widened by 1.3 each way, its bottom at
/// least 10⁻³, its top at least 1); χ² below the bottom is drawn at it. The y ticks are labelled
/// at 1, 2, 3 and 5 × 10ᵏ only ([`sparse_log_tick`]).
pub fn loss_chart(title: &str, y_label: &str, fits: &[(String, &NuFit)]) -> Chart {
    let xs = || fits.iter().flat_map(|f| f.1.grid.iter().copied());
    let ys = || fits.iter().flat_map(|f| f.1.chi2.iter().copied()).filter(|y| *y > 0.0 && y.is_finite());
    let (x0, x1) = (xs().fold(f64::INFINITY, f64::min), xs().fold(0.0, f64::max));
    let (y0, y1) = (ys().fold(f64::INFINITY, f64::min).max(1e-3), ys().fold(0.0, f64::max).max(1.0));
    let (ylo, yhi) = (y0 / 1.3, y1 * 1.3);
    let mut chart = Chart::new(
        Axis::log("ν, merging tolerance (fraction of R_max, log scale)", x0, x1).no_grid(),
        Axis::log(y_label, ylo, yhi).no_grid().format(sparse_log_tick),
    )
    .title(title)
    .legend(Mark::Dashed(colors::GREY), format!("paper: ν = {PAPER_NU}"))
    .dashed(&[(PAPER_NU, ylo), (PAPER_NU, yhi)], colors::GREY);
    for (k, (label, f)) in fits.iter().enumerate() {
        let (color, text) = (series_color(k), format!("{label}: best ν = {}", log_tick(f.nu)));
        let pts: Vec<(f64, f64)> = f.grid.iter().zip(&f.chi2).map(|(x, y)| (*x, y.max(y0))).collect();
        chart = match k < 8 {
            true => chart.legend(Mark::Line(color), text).line(&pts, color),
            false => chart.legend(Mark::Dashed(color), text).dashed(&pts, color),
        };
        chart = chart.markers_sized(&[(f.nu, f.chi2_min.max(y0))], color, Marker::Dot, style::MARKER + 1);
    }
    chart
}

/// Fitted ν (bootstrap 16–84 % bars) against the roughness amplitude of the synthetic pebbles
/// (`fits`: roughness, fit), log–log, with the paper's ν = 0.0035 dashed.
pub fn nu_against_roughness(fits: &[(f64, &NuFit)]) -> Chart {
    let fitted = colors::VERMILLION;
    let nu: Vec<(f64, f64)> = fits.iter().map(|(r, f)| (*r, f.nu)).collect();
    let bars: Vec<_> = fits.iter().map(|(r, f)| (*r, f.bootstrap_interval.0, f.bootstrap_interval.1)).collect();
    Chart::new(
        Axis::log("roughness amplitude (largest relative radial deviation, log scale)", 0.007, 1.0).no_grid(),
        Axis::log("fitted ν (fraction of R_max, log scale)", 5e-5, 5e-2).no_grid(),
    )
    .title("Fitted ν against the roughness of the synthetic pebbles")
    .legend(Mark::LineDot(fitted), "fitted ν (bars: bootstrap 16–84 %)")
    .legend(Mark::Dashed(colors::GREY), format!("paper: ν = {PAPER_NU}"))
    .dashed(&[(0.007, PAPER_NU), (1.0, PAPER_NU)], colors::GREY)
    .line(&nu, fitted)
    .y_bars(&bars, fitted)
    .markers_sized(&nu, fitted, Marker::Dot, style::MARKER + 1)
}

/// One fit of ν for [`write_fits_csv`]: (group, label, samples fitted, seconds), the population,
/// the fit.
pub type FitRow<'a> = ((&'a str, &'a str, usize, f64), &'a PopulationParams, &'a NuFit);

/// Write `fits` (one row per fit: its case, population, ν̂ with its intervals, χ² and its split)
/// and `curves` (group, label, ν, χ² at every grid ν of every fit).
pub fn write_fits_csv(fits_path: &Path, curves_path: &Path, fits: &[FitRow]) -> crate::Result<()> {
    let header = "group,label,samples,roughness,points,spread,count,seed,calibrate,nu,interval_lo,interval_hi,\
        bootstrap_p16,bootstrap_p84,bootstrap_sd_log10,chi2_min,dof,chi2_ES,chi2_EU,chi2_sdS,chi2_sdU,at_edge,seconds";
    let fixed = |x: f64, digits: usize| format!("{x:.digits$}");
    let rows = fits.iter().map(|((group, label, samples, seconds), p, f)| {
        let first: [&dyn Display; 9] =
            [group, label, samples, &p.roughness, &p.points, &p.spread, &p.count, &p.seed, &p.calibrate];
        let e4 = [f.nu, f.interval.0, f.interval.1, f.bootstrap_interval.0, f.bootstrap_interval.1]
            .map(|x| format!("{x:.4e}"));
        let mut row: Vec<String> = first.iter().map(|x| x.to_string()).chain(e4).collect();
        row.extend([fixed(f.bootstrap_sd_log10, 4), fixed(f.chi2_min, 2), f.dof.to_string()]);
        row.extend(f.chi2_by_statistic.map(|x| fixed(x, 2)));
        row.extend([f.at_edge.to_string(), fixed(*seconds, 1)]);
        row
    });
    super::write_csv(fits_path, &header.split(',').collect::<Vec<_>>(), rows)?;
    let curves = fits.iter().flat_map(|((group, label, ..), _, f)| {
        let points = f.grid.iter().zip(&f.chi2);
        points.map(move |(nu, c)| [group.to_string(), label.to_string(), format!("{nu:.4e}"), fixed(*c, 3)])
    });
    super::write_csv(curves_path, &["group", "label", "nu", "chi2"], curves)
}

/// A log-axis tick written as [`log_tick`] does, but only at 1, 2, 3 and 5 × 10ᵏ (to 2 % of the
/// mantissa): the 4 and 6 … 9 × 10ᵏ ticks crowd each other on a log axis and are left blank.
pub fn sparse_log_tick(y: f64) -> String {
    let m = y / 10f64.powf(y.log10().floor());
    let shown = [1.0, 2.0, 3.0, 5.0].iter().any(|d| (m - d).abs() < 0.02) || m > 9.98;
    if shown {
        log_tick(y)
    } else {
        String::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sparse_ticks_keep_one_two_three_and_five() {
        for (y, text) in [(100.0, "100"), (2e5, "2×10⁵"), (300.0, "300"), (0.05, "0.05")] {
            assert_eq!(sparse_log_tick(y), text, "{y}");
        }
        for y in [400.0, 6000.0, 0.7, 8.0, 90.0] {
            assert_eq!(sparse_log_tick(y), "", "{y}");
        }
    }

    #[test]
    fn a_loss_chart_names_every_fit_and_its_best_nu() {
        let fit = |nu: f64| NuFit {
            grid: vec![1e-4, 1e-3, 1e-2],
            chi2: vec![400.0, 90.0, 250.0],
            nu,
            chi2_min: 80.0,
            terms: 8,
            dof: 7,
            at_edge: false,
            scale: 1.0,
            interval: (5e-4, 3e-3),
            chi2_by_statistic: [20.0; 4],
            bootstrap: vec![],
            bootstrap_interval: (5e-4, 3e-3),
            bootstrap_sd_log10: 0.1,
        };
        let (a, b) = (fit(1e-3), fit(2e-3));
        let chart = loss_chart("fits", "χ²", &[("first".into(), &a), ("second".into(), &b)]);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("loss.svg");
        chart.save(&path, (600, 400)).unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        for text in ["first: best ν = 0.001", "second: best ν = 0.002", "paper: ν = 0.0035"] {
            assert!(svg.contains(text), "{text}");
        }
    }
}
