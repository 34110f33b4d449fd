//! What a person reads of a shaking run ([`crate::dynamics::shaking`]): the summary, the fragility
//! CSV and plot, and ground-motion records written as CSV.

use super::{short_name, write_json, Folder};
use crate::dynamics::resting::outcome::{CurvePoint, Threshold};
use crate::dynamics::shaking::{MotionInfo, ShakeReport, ShakeTrial};
use crate::dynamics::stone::{Class, StableEquilibrium};
use crate::ground_motion::Record;
use crate::plot::{render, DrawResult, Mark};
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Write a record as CSV: time (s) and the three components in g (`time_s,ax_g,ay_g,az_g`, what
/// `--columns time_s,ax_g,ay_g,az_g --accel-unit g` reads back).
pub fn write_record(path: &Path, r: &Record) -> crate::Result<()> {
    (|| -> std::result::Result<_, crate::error::BoxError> {
        let mut w = csv::Writer::from_path(path)?;
        w.write_record(["time_s", "ax_g", "ay_g", "az_g"])?;
        for (k, a) in r.accel.iter().enumerate() {
            let g = |x: f64| format!("{:.6}", x / crate::GRAVITY);
            w.write_record([format!("{:.5}", k as f64 * r.dt), g(a[0]), g(a[1]), g(a[2])])?;
        }
        w.flush()?;
        Ok(())
    })()
    .map_err(|e| crate::Error::write(path, e))
}

/// One line that says what a motion is: its name, PGA, PGV and duration.
pub fn describe_motion(m: &MotionInfo) -> String {
    format!(
        "{} (PGA {:.3} g, PGV {:.3} m/s, {:.2} s)",
        m.name, m.measures.pga_g, m.measures.pgv_m_s, m.measures.duration_s
    )
}

/// A readable summary of a shaking run.
pub fn summary(r: &ShakeReport, mesh: &str) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(s, "{mesh}: ground shaking, {}, scaled to each PGA", describe_motion(&r.motion));
    let _ = writeln!(
        s,
        "  stone of R_max = {:.3} m; {}",
        r.r_max_m,
        super::perturb::contact_line(&r.params, Some(r.r_max_m))
    );
    s += &super::depth_line(r.deepest_penetration);
    let _ = writeln!(
        s,
        "{} trials per PGA on {} PGAs from {:.3} g to {:.3} g, seed {}; flocks at ν = {:.3e}",
        r.trials_per_point,
        r.pgas.len(),
        r.pgas.first().copied().unwrap_or(f64::NAN),
        r.pgas.last().copied().unwrap_or(f64::NAN),
        r.seed,
        r.nu
    );
    let th = |t: &Option<Threshold>| match t {
        None => "-".to_string(),
        Some(Threshold::Below(x)) => format!("≤{x:.3}"),
        Some(Threshold::At(x)) => format!("{x:.3}"),
        Some(Threshold::Above(x)) => format!(">{x:.3}"),
    };
    let class = |q: &StableEquilibrium| q.class.name().to_string();
    if r.pgas.len() == 1 {
        let _ = writeln!(
            s,
            "{:>5} {:>6} {:>8} {:>10} {:>21} {:>21} {:>21}",
            "eq", "facet", "class", "uplift (g)", "P(same micro)", "P(still in flock)", "P(toppled)"
        );
        let p = |x: f64, ci: (f64, f64)| format!("{x:.2} [{:.2}, {:.2}]", ci.0, ci.1);
        for f in &r.fragility {
            let q = &f.equilibrium;
            match f.curve.first() {
                Some(c) => {
                    let _ = writeln!(
                        s,
                        "{:>5} {:>6} {:>8} {:>10.4} {:>21} {:>21} {:>21}",
                        q.index,
                        q.facet,
                        class(q),
                        q.uplift_acceleration,
                        p(c.p_same, c.ci_same),
                        p(c.p_in_flock, c.ci_in_flock),
                        p(c.p_toppled, c.ci_toppled)
                    );
                }
                None => {
                    let _ = writeln!(
                        s,
                        "{:>5} {:>6} {:>8} {:>10.4}   does not stay at rest",
                        q.index,
                        q.facet,
                        class(q),
                        q.uplift_acceleration
                    );
                }
            }
        }
        return s;
    }
    let _ = writeln!(
        s,
        "{:>5} {:>6} {:>8} {:>10} {:>11} {:>11} {:>12}",
        "eq", "facet", "class", "uplift (g)", "PGA50 micro", "PGA50 flock", "first topple"
    );
    for f in &r.fragility {
        let q = &f.equilibrium;
        let _ = writeln!(
            s,
            "{:>5} {:>6} {:>8} {:>10.4} {:>11} {:>11} {:>12}",
            q.index,
            q.facet,
            class(q),
            q.uplift_acceleration,
            if f.rest.stays { th(&f.pga50_micro) } else { "no rest".into() },
            th(&f.pga50_flock),
            f.first_topple.map_or("-".into(), |x| format!("{x:.3}")),
        );
    }
    s
}

/// Write the fragility curves as CSV.
pub fn write_fragility_csv(path: &Path, r: &ShakeReport) -> crate::Result<()> {
    (|| -> std::result::Result<_, crate::error::BoxError> {
        let mut w = csv::Writer::from_path(path)?;
        w.write_record([
            "equilibrium",
            "facet",
            "static_class",
            "pga_g",
            "n",
            "same",
            "same_flock",
            "toppled",
            "unsettled",
            "p_same",
            "p_toppled",
            "p_toppled_lo",
            "p_toppled_hi",
            "uplift_acceleration_g",
        ])?;
        for f in &r.fragility {
            let q = &f.equilibrium;
            for c in &f.curve {
                w.write_record([
                    q.index.to_string(),
                    q.facet.to_string(),
                    q.class.name().to_string(),
                    format!("{:.4}", c.x),
                    c.n.to_string(),
                    c.same.to_string(),
                    c.same_flock.to_string(),
                    c.toppled.to_string(),
                    c.unsettled.to_string(),
                    format!("{:.4}", c.p_same),
                    format!("{:.4}", c.p_toppled),
                    format!("{:.4}", c.ci_toppled.0),
                    format!("{:.4}", c.ci_toppled.1),
                    format!("{:.5}", q.uplift_acceleration),
                ])?;
            }
        }
        w.flush()?;
        Ok(())
    })()
    .map_err(|e| crate::Error::write(path, e))
}

/// Fragility curves P(toppled) against PGA, one line (with 95 % intervals) per
/// `(label, curve, colour)`, and vertical markers.
pub fn plot_fragility(
    path: &Path,
    caption: &str,
    lines: &[(String, &[CurvePoint], plotters::style::RGBColor)],
    markers: &[(f64, String, plotters::style::RGBColor)],
) -> crate::Result<()> {
    render!(path, (900, 600), |root| draw_fragility(&root, caption, lines, markers))
}

#[allow(clippy::type_complexity)]
fn draw_fragility<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    caption: &str,
    lines: &[(String, &[CurvePoint], plotters::style::RGBColor)],
    markers: &[(f64, String, plotters::style::RGBColor)],
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let font = crate::plot::FONT_FAMILY;
    let err = |x: DrawingAreaErrorKind<_>| format!("{x:?}");
    let hi = lines.iter().flat_map(|l| l.1.iter().map(|c| c.x)).fold(0.0, f64::max).max(1e-3) * 1.05;
    root.fill(&WHITE).map_err(err)?;
    let mut chart = ChartBuilder::on(root)
        .caption(caption, (font, crate::plot::style::TITLE))
        .margin(14)
        .x_label_area_size(45)
        .y_label_area_size(55)
        .build_cartesian_2d(0.0..hi, -0.02f64..1.02)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("peak ground acceleration (g)")
        .y_desc("P(toppled out of the flock)")
        .label_style((font, crate::plot::style::TICK))
        .draw()
        .map_err(err)?;
    for (x, label, color) in markers {
        let c = *color;
        chart
            .draw_series(DashedLineSeries::new(vec![(*x, 0.0), (*x, 1.02)], 6, 4, c.stroke_width(2)))
            .map_err(err)?
            .label(label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2)));
    }
    for (label, curve, color) in lines {
        let c = *color;
        let pts: Vec<(f64, f64)> = curve.iter().map(|p| (p.x, p.p_toppled)).collect();
        chart
            .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
            .map_err(err)?
            .label(label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2)));
        chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled()))).map_err(err)?;
        chart
            .draw_series(
                curve
                    .iter()
                    .map(|p| PathElement::new(vec![(p.x, p.ci_toppled.0), (p.x, p.ci_toppled.1)], c.stroke_width(1))),
            )
            .map_err(err)?;
    }
    chart
        .configure_series_labels()
        .label_font((font, crate::plot::style::LEGEND))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerRight)
        .draw()
        .map_err(err)?;
    Ok(())
}

/// Write one CSV row per shaking trial.
pub fn write_trials_csv(path: &Path, trials: &[ShakeTrial]) -> crate::Result<()> {
    (|| -> std::result::Result<_, crate::error::BoxError> {
        let mut w = csv::Writer::from_path(path)?;
        w.write_record([
            "equilibrium",
            "pga_g",
            "azimuth_deg",
            "trial",
            "outcome",
            "final_equilibrium",
            "final_flock",
            "settled",
            "max_tilt_rad",
        ])?;
        for t in trials {
            w.write_record([
                t.equilibrium.to_string(),
                format!("{:.4}", t.pga),
                format!("{:.2}", t.azimuth.to_degrees()),
                t.trial.to_string(),
                t.outcome.name().to_string(),
                t.final_equilibrium.map_or(String::new(), |x| x.to_string()),
                t.final_flock.to_string(),
                t.settled.to_string(),
                format!("{:.5}", t.max_tilt),
            ])?;
        }
        w.flush()?;
        Ok(())
    })()
    .map_err(|e| crate::Error::write(path, e))
}

/// Write `shake.json`, `fragility.csv`, `trials.csv` and (if any curve) `fragility.png/.svg` into
/// `dir`; `name` is the mesh named in the caption.
pub fn write_outputs(r: &ShakeReport, name: &str, dir: &Path) -> crate::Result<Vec<PathBuf>> {
    let mut out = Folder::create(dir)?;
    out.file("shake.json", |p| write_json(p, r))?;
    out.file("fragility.csv", |p| write_fragility_csv(p, r))?;
    out.file("trials.csv", |p| write_trials_csv(p, &r.trials))?;
    let lines: Vec<(String, &[CurvePoint], RGBColor)> = r
        .fragility
        .iter()
        .filter(|f| !f.curve.is_empty())
        .enumerate()
        .map(|(i, f)| {
            let q = &f.equilibrium;
            let class = match q.class {
                Class::Regular => "regular",
                Class::Rocking => "rocking",
            };
            (format!("eq {} ({class}, facet {})", q.index, q.facet), f.curve.as_slice(), crate::plot::series_color(i))
        })
        .collect();
    if !lines.is_empty() {
        let caption = format!("{}: fragility, {}", short_name(name), describe_motion(&r.motion));
        for ext in ["png", "svg"] {
            out.file(&format!("fragility.{ext}"), |p| plot_fragility(p, &caption, &lines, &[]))?;
        }
    }
    Ok(out.written)
}

// --- Field rocks under records --------------------------------------------------------------

use crate::dynamics::shaking::{RecordRun, ShakeBatch};
use crate::ground_motion::fragility::FragilitySurface;

/// Columns of `runs.csv`: one row per (record, scale) run of a field rock.
pub const RUN_CSV_HEADER: [&str; 22] = [
    "record",
    "scale",
    "pga_g",
    "pgv_m_s",
    "pgv_over_pga_s",
    "pga_vertical_g",
    "overturned",
    "outcome",
    "max_tilt_deg",
    "slide_m",
    "start_equilibrium",
    "final_equilibrium",
    "final_flock",
    "settled",
    "time_s",
    "member",
    "contact_tolerance_m",
    "azimuth_deg",
    "sign",
    "friction",
    "restitution",
    "rolling_resistance_m",
];

/// The `runs.csv` row of a run (columns [`RUN_CSV_HEADER`]).
pub fn run_csv_row(r: &RecordRun) -> Vec<String> {
    let mut row = vec![
        r.record.clone(),
        format!("{}", r.scale),
        format!("{:.6}", r.pga_g),
        format!("{:.6}", r.pgv_m_s),
        format!("{:.6}", r.pgv_over_pga_s),
        format!("{:.6}", r.pga_vertical_g),
        r.rock.overturned.to_string(),
        r.rock.outcome.name().to_string(),
        format!("{:.4}", r.rock.max_tilt_deg),
        format!("{:.6}", r.rock.slide_m),
        r.rock.start_equilibrium.to_string(),
        r.rock.final_equilibrium.to_string(),
        r.rock.final_flock.to_string(),
        r.rock.settled.to_string(),
        format!("{:.3}", r.rock.time_s),
    ];
    // An ensemble member's inputs; blank for the rock as given.
    let member = r.member.map(|d| {
        [
            d.member.to_string(),
            format!("{:.6}", d.contact_tolerance_m),
            format!("{:.3}", d.azimuth_deg),
            format!("{}", d.sign),
            format!("{:.4}", d.friction),
            format!("{:.4}", d.restitution),
            format!("{:.3e}", d.rolling_resistance_m),
        ]
    });
    row.extend(member.unwrap_or_default());
    row
}

/// Write `runs.csv` (header and one row per run, in the batch's order).
pub fn write_runs_csv(path: &Path, runs: &[RecordRun]) -> crate::Result<()> {
    (|| -> std::result::Result<_, crate::error::BoxError> {
        let mut w = csv::Writer::from_path(path)?;
        w.write_record(RUN_CSV_HEADER)?;
        for r in runs {
            w.write_record(run_csv_row(r))?;
        }
        w.flush()?;
        Ok(())
    })()
    .map_err(|e| crate::Error::write(path, e))
}

/// A readable summary of one field-rock run.
pub fn rock_run_summary(r: &RecordRun, mesh: &str) -> String {
    format!(
        "{} (R_max = {:.3} m) under {} × {}: PGA {:.3} g, PGV {:.3} m/s, PGV/PGA {:.3} s\n  \
         settled onto equilibrium {} with a tilt of {:.3}°; {} (outcome {}, final equilibrium {}, flock {}), \
         max tilt {:.2}°, slide {:.4} m{}\n",
        short_name(mesh),
        r.rock.r_max_m,
        r.record,
        r.scale,
        r.pga_g,
        r.pgv_m_s,
        r.pgv_over_pga_s,
        r.rock.start_equilibrium,
        r.rock.settling_tilt_deg,
        if r.rock.overturned { "OVERTURNED" } else { "standing" },
        r.rock.outcome,
        r.rock.final_equilibrium,
        r.rock.final_flock,
        r.rock.max_tilt_deg,
        r.rock.slide_m,
        if r.rock.settled { "" } else { " (still moving at the time cap)" }
    ) + &super::depth_line(r.rock.deepest_penetration)
}

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
        (None, Some(e)) => s += &format!("no fragility surface: {e}\n"),
        (None, None) => {}
    }
    s += &super::ensemble::batch_lines(b);
    s += &super::depth_line(b.runs.iter().map(|r| r.rock.deepest_penetration).fold(0.0, f64::max));
    if b.unsettled > 0 {
        s += &format!(
            "{} of {n} runs were still moving at the time cap: classified by the quasi-static descent in runs.csv \
             (settled = false), left out of the fragility surface\n",
            b.unsettled
        );
    }
    s
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
    let pts: Vec<&RecordRun> = runs.iter().filter(|r| r.pga_g > 0.0 && r.pgv_over_pga_s > 0.0).collect();
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
    for r in &pts {
        x0 = x0.min(r.pga_g);
        x1 = x1.max(r.pga_g);
        y0 = y0.min(r.pgv_over_pga_s);
        y1 = y1.max(r.pgv_over_pga_s);
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
            pts.iter().filter(|r| r.rock.overturned).map(|r| Circle::new((r.pga_g, r.pgv_over_pga_s), 4, red.filled())),
        )
        .map_err(err)?;
    chart
        .draw_series(
            pts.iter()
                .filter(|r| !r.rock.overturned)
                .map(|r| Circle::new((r.pga_g, r.pgv_over_pga_s), 4, blue.stroke_width(2))),
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
    super::ensemble::write_batch_ensemble_outputs(b, name, &mut out)?;
    Ok(out.written)
}
