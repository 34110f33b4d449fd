//! The plots of a perturbation run: outcome curves in panels with their barrier markers, and the
//! dynamic thresholds against the static barriers.

use crate::dynamics::pushes::PerturbReport;
use crate::dynamics::resting::outcome::{CurvePoint, Threshold};
use crate::dynamics::stone::Class;
use crate::plot::{colors, draw_legend, legend_height, log_tick, plain, render, style, DrawResult, Mark, FONT_FAMILY};
use plotters::prelude::*;
use std::path::Path;

/// A panel of [`plot_curves`]: a title, the curve, and vertical markers (x, label, colour).
pub struct Panel<'a> {
    /// Title of the panel.
    pub title: String,
    /// Points of the curve (x = ε or PGA).
    pub curve: &'a [CurvePoint],
    /// Vertical markers: x position, label and colour.
    pub markers: Vec<(f64, String, RGBColor)>,
    /// Written in the panel when there is no curve to draw (why not).
    pub note: Option<String>,
}

/// Top of the probability axis (the legend has its own strip, never over the curves).
const TOP: f64 = 1.04;

/// The three outcome curves: name, colour (Okabe–Ito) and which probability.
const SERIES: [(&str, RGBColor, usize); 3] = [
    ("P(same micro-equilibrium)", colors::BLUE, 0),
    ("P(still in the flock)", colors::GREEN, 1),
    ("P(toppled out of the flock)", colors::VERMILLION, 2),
];

/// Outcome probabilities against x (log ε, or PGA) with 95 % intervals, one panel per entry,
/// side by side (up to three per row; four as 2 × 2), one legend for all panels in a strip
/// under the title. A panel without a curve says why (its note). PNG or SVG by extension.
pub fn plot_curves(path: &Path, caption: &str, x_label: &str, log_x: bool, panels: &[Panel]) -> crate::Result<()> {
    let cols = if panels.len() == 4 { 2 } else { panels.len().clamp(1, 3) };
    let rows = panels.len().div_ceil(cols).max(1);
    let (w, h) = (520 * cols as u32, 360 * rows as u32 + 40 + legend_height(legend_lines(cols)));
    render!(path, (w, h), |root| draw_curves(&root, caption, x_label, log_x, panels, rows, cols))
}

fn legend_lines(cols: usize) -> u32 {
    match cols {
        1 => 4,
        2 => 2,
        _ => 2,
    }
}

type Area<DB> = DrawingArea<DB, plotters::coord::Shift>;

fn draw_curves<DB: DrawingBackend>(
    root: &Area<DB>,
    caption: &str,
    x_label: &str,
    log_x: bool,
    panels: &[Panel],
    rows: usize,
    cols: usize,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| format!("{x:?}");
    root.fill(&WHITE).map_err(e)?;
    let root = root.titled(caption, (FONT_FAMILY, style::TITLE)).map_err(e)?;
    let (legend, grid) = root.split_vertically(legend_height(legend_lines(cols)));
    let mut entries: Vec<(Mark, String)> =
        SERIES.iter().map(|(name, c, _)| (Mark::LineDot(*c), format!("{name}, 95 % interval"))).collect();
    for p in panels {
        for (_, label, c) in &p.markers {
            if !entries.iter().any(|(_, l)| l == label) {
                entries.push((Mark::Dashed(*c), label.clone()));
            }
        }
    }
    draw_legend(&legend, &entries)?;
    for (panel, area) in panels.iter().zip(grid.split_evenly((rows, cols))) {
        let xs: Vec<f64> = panel
            .curve
            .iter()
            .map(|c| c.x)
            .chain(panel.markers.iter().map(|m| m.0))
            .filter(|x| x.is_finite() && (!log_x || *x > 0.0))
            .collect();
        let (mut lo, mut hi) =
            (xs.iter().cloned().fold(f64::INFINITY, f64::min), xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max));
        if !lo.is_finite() {
            (lo, hi) = (1e-3, 1.0);
        }
        let pick = |c: &CurvePoint, k: usize| match k {
            0 => (c.p_same, c.ci_same),
            1 => (c.p_in_flock, c.ci_in_flock),
            _ => (c.p_toppled, c.ci_toppled),
        };
        macro_rules! body {
            ($chart:ident) => {{
                $chart
                    .configure_mesh()
                    .x_desc(x_label)
                    .y_desc("probability")
                    .x_labels(8)
                    .x_label_formatter(&|x: &f64| if log_x { log_tick(*x) } else { plain(*x) })
                    .y_label_formatter(&|y: &f64| format!("{y:.1}"))
                    .label_style((FONT_FAMILY, style::TICK))
                    .axis_desc_style((FONT_FAMILY, style::TICK))
                    .light_line_style(WHITE.mix(0.0))
                    .bold_line_style(BLACK.mix(0.1))
                    .draw()
                    .map_err(e)?;
                for (x, _, color) in &panel.markers {
                    if !x.is_finite() || (log_x && *x <= 0.0) {
                        continue;
                    }
                    $chart
                        .draw_series(DashedLineSeries::new(
                            vec![(*x, 0.0), (*x, 1.0)],
                            6,
                            4,
                            color.stroke_width(style::LINE),
                        ))
                        .map_err(e)?;
                }
                for (_, color, k) in SERIES {
                    let pts: Vec<(f64, f64)> = panel.curve.iter().map(|c| (c.x, pick(c, k).0)).collect();
                    $chart.draw_series(LineSeries::new(pts.clone(), color.stroke_width(style::LINE))).map_err(e)?;
                    $chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled()))).map_err(e)?;
                    $chart
                        .draw_series(panel.curve.iter().map(|c| {
                            let (_, ci) = pick(c, k);
                            PathElement::new(vec![(c.x, ci.0), (c.x, ci.1)], color.stroke_width(1))
                        }))
                        .map_err(e)?;
                }
                if let Some(note) = &panel.note {
                    for (i, line) in note.lines().enumerate() {
                        area.draw(&Text::new(
                            line.to_string(),
                            (84, 110 + 20 * i as i32),
                            (FONT_FAMILY, style::LEGEND),
                        ))
                        .map_err(e)?;
                    }
                }
            }};
        }
        if log_x {
            let mut chart = ChartBuilder::on(&area)
                .caption(&panel.title, (FONT_FAMILY, style::PANEL_TITLE))
                .margin(10)
                .x_label_area_size(40)
                .y_label_area_size(50)
                .build_cartesian_2d((lo / 1.5..hi * 1.5).log_scale(), -0.02f64..TOP)
                .map_err(e)?;
            body!(chart);
        } else {
            let pad = 0.05 * (hi - lo).max(1e-9);
            let mut chart = ChartBuilder::on(&area)
                .caption(&panel.title, (FONT_FAMILY, style::PANEL_TITLE))
                .margin(10)
                .x_label_area_size(40)
                .y_label_area_size(50)
                .build_cartesian_2d((lo - pad).max(0.0)..hi + pad, -0.02f64..TOP)
                .map_err(e)?;
            body!(chart);
        }
    }
    Ok(())
}

/// The panels of a perturbation report: static barriers and ε* as markers.
pub fn panels(r: &PerturbReport) -> Vec<Panel<'_>> {
    r.equilibria
        .iter()
        .map(|e| {
            let q = &e.equilibrium;
            Panel {
                title: format!("eq {} (facet {}): {} in {} flock {}", q.index, q.facet, q.class, q.flock_kind, q.flock),
                curve: &e.curve,
                markers: barrier_markers(q.basin_exit.epsilon, q.flock_exit.epsilon, r.epsilon_star),
                note: e.curve.is_empty().then(|| {
                    "No curve: set down at rest on this facet, the\nstone did not stay there (it rolled off in the\n\
                     rest check), so it was never perturbed."
                        .to_string()
                }),
            }
        })
        .collect()
}

/// The vertical markers of a robustness panel, in the house colours: the static basin barrier
/// (orange), the flock barrier (reddish purple) and ε* of the macro ν (grey).
pub fn barrier_markers(basin: f64, flock: f64, epsilon_star: f64) -> Vec<(f64, String, RGBColor)> {
    vec![
        (basin, "static barrier to leave the basin (micro-equilibrium)".into(), colors::ORANGE),
        (flock, "static barrier to leave the flock".into(), colors::PURPLE),
        (epsilon_star, "ε* = macro ν (dynamic class read here)".into(), colors::GREY),
    ]
}

/// Dynamic thresholds against static barriers (log–log), per equilibrium: ε₅₀ to leave the
/// micro-equilibrium against the basin barrier, ε₅₀ to leave the flock against the flock barrier;
/// regular and rocking equilibria in different colours; the diagonal y = x.
pub fn plot_thresholds(path: &Path, caption: &str, points: &[(f64, f64, bool, Class)]) -> crate::Result<()> {
    render!(path, (820, 700), |root| draw_thresholds(&root, caption, points))
}

fn draw_thresholds<DB: DrawingBackend>(root: &Area<DB>, caption: &str, points: &[(f64, f64, bool, Class)]) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let finite: Vec<f64> = points.iter().flat_map(|p| [p.0, p.1]).filter(|x| x.is_finite() && *x > 0.0).collect();
    let lo = finite.iter().cloned().fold(f64::INFINITY, f64::min).min(1e-3) / 2.0;
    let hi = finite.iter().cloned().fold(0.0, f64::max).max(1e-2) * 2.0;
    root.fill(&WHITE).map_err(|x| format!("{x:?}"))?;
    let mut chart = ChartBuilder::on(root)
        .caption(caption, (FONT_FAMILY, style::TITLE))
        .margin(14)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d((lo..hi).log_scale(), (lo..hi).log_scale())
        .map_err(|x| format!("{x:?}"))?;
    chart
        .configure_mesh()
        .x_desc("static barrier (m g ΔR / (m g R_max))")
        .y_desc("dynamic threshold ε₅₀")
        .x_label_formatter(&|x: &f64| log_tick(*x))
        .y_label_formatter(&|y: &f64| log_tick(*y))
        .label_style((FONT_FAMILY, style::TICK))
        .axis_desc_style((FONT_FAMILY, style::AXIS))
        .draw()
        .map_err(|x| format!("{x:?}"))?;
    chart
        .draw_series(LineSeries::new(vec![(lo, lo), (hi, hi)], BLACK.stroke_width(1)))
        .map_err(|x| format!("{x:?}"))?
        .label("ε₅₀ = barrier")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK));
    let styles = [
        (false, Class::Regular, "leave micro-eq., regular", colors::VERMILLION),
        (false, Class::Rocking, "leave micro-eq., rocking", colors::BLUE),
        (true, Class::Regular, "leave flock, regular", colors::VERMILLION),
        (true, Class::Rocking, "leave flock, rocking", colors::BLUE),
    ];
    for (flock, class, label, color) in styles {
        let pts: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.2 == flock && p.3 == class && p.0.is_finite() && p.0 > 0.0 && p.1.is_finite() && p.1 > 0.0)
            .map(|p| (p.0, p.1))
            .collect();
        if flock {
            chart
                .draw_series(pts.iter().map(|&p| TriangleMarker::new(p, 6, color.filled())))
                .map_err(|x| format!("{x:?}"))?
                .label(label)
                .legend(move |(x, y)| TriangleMarker::new((x + 8, y), 6, color.filled()));
        } else {
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.stroke_width(2))))
                .map_err(|x| format!("{x:?}"))?
                .label(label)
                .legend(move |(x, y)| Circle::new((x + 8, y), 4, color.stroke_width(2)));
        }
    }
    chart
        .configure_series_labels()
        .label_font((FONT_FAMILY, style::LEGEND))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        // below the diagonal: no threshold lies there (a stone never leaves below its barrier)
        .position(SeriesLabelPosition::LowerRight)
        .draw()
        .map_err(|x| format!("{x:?}"))?;
    Ok(())
}

/// The (barrier, ε₅₀, is-flock, class) points of a report for [`plot_thresholds`] (only
/// interpolated thresholds).
pub fn threshold_points(r: &PerturbReport) -> Vec<(f64, f64, bool, Class)> {
    let mut pts = Vec::new();
    for e in &r.equilibria {
        let q = &e.equilibrium;
        if let Some(Threshold::At(v)) = e.eps50_micro {
            pts.push((q.basin_exit.epsilon, v, false, q.class));
        }
        if let Some(Threshold::At(v)) = e.eps50_flock {
            pts.push((q.flock_exit.epsilon, v, true, q.class));
        }
    }
    pts
}
