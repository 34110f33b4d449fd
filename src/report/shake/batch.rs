//! A batch of field-rock runs ([`crate::dynamics::shaking::ShakeBatch`]): its summary, the
//! fragility surface plot and the batch's files.

use super::ensemble::{batch_lines, write_batch_ensemble_outputs};
use super::runs::write_runs_csv;
use crate::dynamics::shaking::{RecordRun, ShakeBatch};
use crate::ground_motion::fragility::FragilitySurface;
use crate::ground_motion::processing::Processing;
use crate::ground_motion::PgvSource;
use crate::plot::{render, DrawResult, Mark};
use crate::report::{short_name, write_json, Folder};
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// A readable summary of a batch of runs and its fragility surface.
pub fn batch_summary(b: &ShakeBatch, mesh: &str) -> String {
    let n = b.runs.len();
    let k = b.runs.iter().filter(|r| r.rock.overturned).count();
    let mut s = format!(
        "{} (R_max = {:.3} m), standing on equilibrium {} (settling tilt {:.3}°): {n} runs, {k} overturned\n",
        short_name(mesh),
        b.setup.r_max_m,
        b.start_equilibrium,
        b.settling_tilt_deg
    );
    if let Some(r) = b.runs.first() {
        let drawn = b.ensemble.as_ref().is_some_and(|e| e.uncertainty.azimuth_deg.is_some());
        s += &format!("  {}\n", super::runs::field_line(&r.rock, drawn));
    }
    s += &pgv_line(&b.runs);
    match (&b.surface, &b.surface_error) {
        (Some(f), _) => {
            s += &format!(
                "fragility surface P = 1/(1+exp(−(β0 + β1 ln PGA + β2 ln PGV/PGA))): β = {:.3} ± {:.3}, {:.3} ± {:.3}, {:.3} ± {:.3}\n",
                f.beta[0], f.std_err[0], f.beta[1], f.std_err[1], f.beta[2], f.std_err[2]
            );
            for ratio in [0.05, 0.1, 0.2, 0.5] {
                if let Some(a) = f.pga_at(0.5, ratio) {
                    s += &format!("  P = 0.5 at PGV/PGA = {ratio} s: PGA {a:.3} g\n");
                }
            }
        }
        (None, Some(e)) => s += &format!("{e}\n"),
        (None, None) => {}
    }
    s += &batch_lines(b);
    if let Some(base) = &b.base {
        s += &super::ensemble::base_line(base);
    }
    s += &crate::report::depth_line(b.runs.iter().map(|r| r.rock.deepest_penetration).fold(0.0, f64::max));
    if b.unsettled > 0 {
        s += &format!(
            "{} of {n} runs were still moving at the time cap: classified by the quasi-static descent in runs.csv \
             (settled = false), left out of the fragility surface\n",
            b.unsettled
        );
    }
    s
}

/// Which PGV the runs' PGV/PGA is of: processed, given, or how many of each.
fn pgv_line(runs: &[RecordRun]) -> String {
    let given = runs.iter().filter(|r| r.motion.pgv_source == PgvSource::Given).count();
    match (given, runs.len()) {
        (_, 0) => String::new(),
        (0, _) => format!(
            "PGV of the records: processed (mean removed, acausal Butterworth high-pass at {} Hz, integrated)\n",
            Processing::default().corner_hz
        ),
        (g, n) if g == n => "PGV of the records: given with them\n".to_string(),
        (g, n) => format!("PGV of the records: given for {g} of {n} runs, processed for the others\n"),
    }
}

/// Plot the runs in the (PGA, PGV/PGA) plane on log axes — overturned filled, standing hollow —
/// with the surface's P = 0.1, 0.5, 0.9 contours (the form of Purvance et al. 2008, Fig. 7) and,
/// with `bands`, the 95 % band of the P = 0.5 contour shaded ([`FragilitySurface::pga_band_at`];
/// every contour's band is in `contours.csv`).
pub fn plot_fragility_surface(
    path: &Path,
    caption: &str,
    runs: &[RecordRun],
    surface: Option<&FragilitySurface>,
    bands: bool,
) -> crate::Result<()> {
    render!(path, (900, 650), |root| draw_surface(&root, caption, runs, surface, bands))
}

fn draw_surface<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    caption: &str,
    runs: &[RecordRun],
    surface: Option<&FragilitySurface>,
    bands: bool,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let font = crate::plot::FONT_FAMILY;
    let err = |x: DrawingAreaErrorKind<_>| format!("{x:?}");
    let pts: Vec<&RecordRun> = runs.iter().filter(|r| r.motion.pga_g > 0.0 && r.motion.pgv_over_pga_s > 0.0).collect();
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
    for r in &pts {
        x0 = x0.min(r.motion.pga_g);
        x1 = x1.max(r.motion.pga_g);
        y0 = y0.min(r.motion.pgv_over_pga_s);
        y1 = y1.max(r.motion.pgv_over_pga_s);
    }
    if pts.is_empty() {
        (x0, x1, y0, y1) = (0.01, 10.0, 0.01, 1.0);
    }
    let (x0, x1, y0, y1) = (x0 / 1.5, x1 * 1.5, y0 / 1.5, y1 * 1.5);
    root.fill(&WHITE).map_err(err)?;
    let (red, blue) = (crate::plot::colors::VERMILLION, crate::plot::colors::BLUE);
    // The legend in its own strip above the chart: the runs cover the whole plane.
    let titled = root.titled(caption, (font, 19)).map_err(err)?;
    let (legend, area) = titled.split_vertically(crate::plot::legend_height(1));
    let mut entries = vec![(Mark::Dot(red), "overturned".to_string()), (Mark::Ring(blue), "standing".to_string())];
    if surface.is_some() {
        entries.push((Mark::Dashed(BLACK), "P = 0.1 (short dashes)".into()));
        entries.push((Mark::Line(BLACK), "P = 0.5".into()));
        entries.push((Mark::Dashed(BLACK), "P = 0.9 (long dashes)".into()));
    }
    if surface.is_some() && bands {
        entries.push((Mark::Box(BLACK, 0.15), "95 % band of P = 0.5".into()));
    }
    crate::plot::draw_legend(&legend, &entries)?;
    let mut chart = ChartBuilder::on(&area)
        .margin(14)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("PGA (g)")
        .y_desc("PGV / PGA (s)")
        .x_label_formatter(&|x| crate::plot::log_tick(*x))
        .y_label_formatter(&|y| crate::plot::log_tick(*y))
        .label_style((font, 13))
        .draw()
        .map_err(err)?;
    chart
        .draw_series(
            pts.iter()
                .filter(|r| r.rock.overturned)
                .map(|r| Circle::new((r.motion.pga_g, r.motion.pgv_over_pga_s), 4, red.filled())),
        )
        .map_err(err)?;
    chart
        .draw_series(
            pts.iter()
                .filter(|r| !r.rock.overturned)
                .map(|r| Circle::new((r.motion.pga_g, r.motion.pgv_over_pga_s), 4, blue.stroke_width(2))),
        )
        .map_err(err)?;
    if let (Some(f), true) = (surface, bands) {
        // The P = 0.5 contour's band only: the three bands overlap and hide each other.
        let p = 0.5;
        let edge = |k: usize| -> Vec<(f64, f64)> {
            (0..=100)
                .map(|i| y0 * (y1 / y0).powf(i as f64 / 100.0))
                .filter_map(|y| f.pga_band_at(p, y, 1.96).and_then(|b| b[k]).map(|x| (x.clamp(x0, x1), y)))
                .collect()
        };
        let (low, mut high) = (edge(0), edge(2));
        high.reverse();
        let band: Vec<(f64, f64)> = low.into_iter().chain(high).collect();
        if band.len() >= 3 {
            chart.draw_series(std::iter::once(Polygon::new(band, BLACK.mix(0.12).filled()))).map_err(err)?;
        }
    }
    if let Some(f) = surface {
        for (p, dash) in [(0.1, 3), (0.5, 0), (0.9, 8)] {
            let line: Vec<(f64, f64)> = (0..=100)
                .map(|i| y0 * (y1 / y0).powf(i as f64 / 100.0))
                .filter_map(|y| f.pga_at(p, y).map(|x| (x, y)))
                .filter(|(x, _)| *x >= x0 && *x <= x1)
                .collect();
            if line.len() < 2 {
                continue;
            }
            let style = BLACK.stroke_width(if p == 0.5 { 2 } else { 1 });
            if dash == 0 {
                chart.draw_series(LineSeries::new(line, style)).map_err(err)?;
            } else {
                chart.draw_series(DashedLineSeries::new(line, dash, 4, style)).map_err(err)?;
            }
        }
    }
    Ok(())
}

/// Write a batch: `shake_batch.json`, `runs.csv` and `fragility_surface.png`.
pub fn write_batch_outputs(b: &ShakeBatch, name: &str, dir: &Path) -> crate::Result<Vec<PathBuf>> {
    let mut out = Folder::create(dir)?;
    out.file("shake_batch.json", |p| write_json(p, b))?;
    out.file("runs.csv", |p| write_runs_csv(p, &b.runs))?;
    let caption = format!("{}: P(overturn | PGA, PGV/PGA)", short_name(name));
    let bands = b.ensemble.is_some();
    out.file("fragility_surface.png", |p| plot_fragility_surface(p, &caption, &b.runs, b.surface.as_ref(), bands))?;
    write_batch_ensemble_outputs(b, name, &mut out)?;
    Ok(out.written)
}
