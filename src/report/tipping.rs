//! What a person reads of the quasi-static tipping of a pose ([`crate::tipping`]): the polar plot
//! of tan α against azimuth, one closed curve per contact tolerance, and a small HTML section.
//!
//! The plot draws r(θ) = max(tan α(θ), 0) (in g) around the origin in Cartesian coordinates,
//! x = r cos θ, y = r sin θ, with equal scales on both axes: azimuth θ is measured from e₁ (to
//! the right, 0°) towards e₂ (up, 90°) of the summary's ground-plane basis, and the point at θ is
//! the ground acceleration that tips the stone over towards θ (the acceleration itself points to
//! θ + 180°). The curve's distance from the origin is then the support function of the support
//! polygon over h, so a broad base gives a large, round curve and its nearest side the dent where
//! the minimum (a dot) lies. Where the stone cannot stand, tan α < 0 on one side; the curve is
//! clamped to the origin there and the legend says so.

use super::html::escape;
use crate::plot::{
    colors, draw_legend, legend_height, plain, render, series_color, style, DrawResult, Mark, FONT_FAMILY,
};
use crate::tipping::TippingSummary;
use crate::Error;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

/// Width of the picture, and side of its square polar chart (px).
const WIDTH: u32 = 800;
/// Height of the title strip (px).
const TITLE_H: u32 = 36;
/// Height of the two lines of notes under the title (px).
const NOTE_H: u32 = 44;
/// Azimuth of the radial lines and their labels (degrees).
const SPOKE_STEP: usize = 30;
/// Azimuth along which the reference circles are labelled (degrees): between two spokes.
const RING_LABEL_AZIMUTH: f64 = 75.0;

/// Draw the tipping polar of `summaries` (one closed curve per contact tolerance, in the colours
/// of [`series_color`]) titled `title` into `path`: PNG, or SVG when `path` ends in `.svg`.
/// Refuses an empty list and curves with values that are not finite (a pose whose G is not
/// above the ground).
pub fn write_polar_plot(summaries: &[TippingSummary], title: &str, path: &Path) -> crate::Result<()> {
    check(summaries)?;
    let height = TITLE_H + NOTE_H + legend_height(summaries.len() as u32) + WIDTH;
    render!(path, (WIDTH, height), |root| draw_polar(&root, summaries, title))
}

/// An empty list or a value that is not finite cannot be drawn.
fn check(summaries: &[TippingSummary]) -> crate::Result<()> {
    if summaries.is_empty() {
        return Err(Error::parameter("summaries", "none", "at least one tipping summary"));
    }
    let mut values = summaries.iter().flat_map(|s| s.curve.iter().map(|p| p[1]).chain([s.minimum_g]));
    match values.find(|v| !v.is_finite()) {
        Some(v) => Err(Error::parameter("summaries", format!("a tan α of {v}"), "finite tan α values")),
        None => Ok(()),
    }
}

/// The HTML section of the tipping polar: a heading, a table (tolerance in mm, minimum tan α in
/// g, its azimuth in degrees, number of support-polygon corners) with one row per summary, and
/// the picture `image_file` (a path or URL relative to the page). Text is escaped as in
/// [`crate::report::html`].
pub fn polar_section_html(summaries: &[TippingSummary], image_file: &str) -> String {
    let mut html = String::from(
        "<section class=\"tipping\">\n<h2>Quasi-static tipping</h2>\n<table>\n<thead><tr><th>tolerance (mm)</th>\
         <th>minimum tan α (g)</th><th>azimuth (°)</th><th>support-polygon corners</th></tr></thead>\n<tbody>\n",
    );
    for s in summaries {
        let minimum = if s.stands { minimum_text(s) } else { format!("{} (cannot stand)", minimum_text(s)) };
        html.push_str(&format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            escape(&tolerance_text(s)),
            escape(&minimum),
            escape(&azimuth_text(s.minimum_azimuth_deg)),
            s.support_polygon_m.len()
        ));
    }
    html.push_str(&format!(
        "</tbody>\n</table>\n<figure><img alt=\"{0}\" src=\"{1}\"><figcaption>{0}</figcaption></figure>\n</section>\n",
        escape("tan α against azimuth θ (from e₁ towards e₂): the ground acceleration, in g, that tips the stone over towards θ"),
        escape(image_file)
    ));
    html
}

/// The contact tolerance in mm, at most 3 significant digits ("0", "2", "0.5").
fn tolerance_text(s: &TippingSummary) -> String {
    plain(s.tolerance_m * 1000.0)
}

/// The minimum tan α in g, at most 3 significant digits ("0.417").
fn minimum_text(s: &TippingSummary) -> String {
    plain(s.minimum_g)
}

/// An azimuth in whole degrees, in 0…359.
fn azimuth_text(degrees: f64) -> String {
    ((degrees.round() as i64).rem_euclid(360)).to_string()
}

/// The legend entry of one curve: "τ = 2 mm: min 0.213 g at 134°", or why it cannot stand.
fn legend_text(s: &TippingSummary) -> String {
    let (tol, min, az) = (tolerance_text(s), minimum_text(s), azimuth_text(s.minimum_azimuth_deg));
    match s.support_polygon_m.len() {
        _ if s.stands => format!("τ = {tol} mm: min {min} g at {az}°"),
        n @ 0..=2 => {
            format!("τ = {tol} mm: cannot stand (touches at {} only)", if n == 2 { "an edge" } else { "a corner" })
        }
        _ => format!("τ = {tol} mm: cannot stand (min {min} g at {az}°), drawn as 0 where tan α < 0"),
    }
}

/// The reference circles (in g): 3 to 5 multiples of a step 1, 2, 2.5 or 5 × 10ᵏ, the last one
/// at or beyond `r_max` (the largest tan α drawn), so that every curve lies inside it.
fn rings(r_max: f64) -> Vec<f64> {
    let r = if r_max > 0.0 && r_max.is_finite() { r_max } else { 0.1 };
    let raw = r / 5.0;
    let decade = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0].iter().map(|m| m * decade).find(|s| *s >= raw * (1.0 - 1e-12));
    let step = step.unwrap_or(10.0 * decade);
    let n = ((r / step) * (1.0 - 1e-12)).ceil().max(1.0) as usize;
    (1..=n).map(|k| k as f64 * step).collect()
}

/// The point at azimuth `degrees` and radius `r`, in the chart's Cartesian coordinates.
fn at(degrees: f64, r: f64) -> (f64, f64) {
    let t = degrees.to_radians();
    (r * t.cos(), r * t.sin())
}

/// A circle of radius `r` about the origin as a closed polyline (1° steps).
fn circle(r: f64) -> Vec<(f64, f64)> {
    (0..=360).map(|k| at(k as f64, r)).collect()
}

type Polar<'a, DB> =
    ChartContext<'a, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>>;

fn draw_polar<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    summaries: &[TippingSummary],
    title: &str,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| format!("{x:?}");
    root.fill(&WHITE).map_err(e)?;
    let (top, rest) = root.split_vertically(TITLE_H);
    top.draw(&Text::new(title.to_string(), (16, 8), (FONT_FAMILY, style::TITLE))).map_err(e)?;
    let (notes, rest) = rest.split_vertically(NOTE_H);
    draw_notes(&notes)?;
    let (legend, square) = rest.split_vertically(legend_height(summaries.len() as u32));
    draw_legend_rows(&legend, summaries)?;
    let r_max = summaries.iter().flat_map(|s| s.curve.iter().map(|p| p[1])).fold(0.0, f64::max);
    let rings = rings(r_max);
    let outer = rings.last().copied().unwrap_or(0.1);
    let extent = 1.16 * outer;
    let mut chart =
        ChartBuilder::on(&square).margin(8).build_cartesian_2d(-extent..extent, -extent..extent).map_err(e)?;
    draw_grid(&mut chart, &rings)?;
    for (k, s) in summaries.iter().enumerate() {
        draw_curve(&mut chart, s, series_color(k))?;
    }
    draw_ring_labels(&mut chart, &rings)
}

/// How to read the picture, two lines under the title.
fn draw_notes<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| format!("{x:?}");
    let font = (FONT_FAMILY, style::LEGEND).into_font().color(&colors::GREY);
    let lines = [
        "r(θ) = tan α(θ): the ground acceleration (g) that tips the stone over towards azimuth θ",
        "(the acceleration points to θ + 180°); θ from e₁ (0°, right) towards e₂ (90°, up).",
    ];
    for (i, line) in lines.iter().enumerate() {
        area.draw(&Text::new(line.to_string(), (16, 2 + 20 * i as i32), font.clone())).map_err(e)?;
    }
    Ok(())
}

/// One legend row per curve (a table of the minima, easier to read than wrapped entries).
fn draw_legend_rows<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, summaries: &[TippingSummary]) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let mut rest = area.clone();
    for (k, s) in summaries.iter().enumerate() {
        let (row, below) = rest.split_vertically(24);
        draw_legend(&row, &[(Mark::LineDot(series_color(k)), legend_text(s))])?;
        rest = below;
    }
    Ok(())
}

/// Reference circles (labelled by [`draw_ring_labels`]) and radial lines every 30°, labelled in
/// degrees.
fn draw_grid<DB: DrawingBackend>(chart: &mut Polar<'_, DB>, rings: &[f64]) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| format!("{x:?}");
    let outer = rings.last().copied().unwrap_or(0.1);
    let line = colors::GREY.mix(0.35).stroke_width(1);
    chart.draw_series(rings.iter().map(|&r| PathElement::new(circle(r), line))).map_err(e)?;
    chart
        .draw_series(
            (0..360).step_by(SPOKE_STEP).map(|d| PathElement::new(vec![(0.0, 0.0), at(d as f64, outer)], line)),
        )
        .map_err(e)?;
    let centred = (FONT_FAMILY, style::TICK).into_font().color(&BLACK).pos(Pos::new(HPos::Center, VPos::Center));
    chart
        .draw_series(
            (0..360)
                .step_by(SPOKE_STEP)
                .map(|d| Text::new(format!("{d}°"), at(d as f64, 1.09 * outer), centred.clone())),
        )
        .map_err(e)?;
    Ok(())
}

/// The labels of the reference circles ("0.2 g") along azimuth [`RING_LABEL_AZIMUTH`], each on
/// a light backdrop so that it stays readable where a curve crosses it (drawn after the curves).
fn draw_ring_labels<DB: DrawingBackend>(chart: &mut Polar<'_, DB>, rings: &[f64]) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| format!("{x:?}");
    let font = (FONT_FAMILY, style::TICK).into_font().color(&colors::GREY);
    for &r in rings {
        let text = format!("{} g", plain(r));
        let (w, h) = chart.plotting_area().estimate_text_size(&text, &font).map_err(e)?;
        let (w, h) = (w as i32, h as i32);
        let label = EmptyElement::at(at(RING_LABEL_AZIMUTH, r))
            + Rectangle::new([(2, -h - 4), (w + 7, -1)], WHITE.mix(0.8).filled())
            + Text::new(text, (4, -h - 3), font.clone());
        chart.plotting_area().draw(&label).map_err(e)?;
    }
    Ok(())
}

/// One closed curve r(θ) = max(tan α(θ), 0) and a dot at its minimum.
fn draw_curve<DB: DrawingBackend>(chart: &mut Polar<'_, DB>, s: &TippingSummary, color: RGBColor) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| format!("{x:?}");
    let mut points: Vec<(f64, f64)> = s.curve.iter().map(|p| at(p[0], p[1].max(0.0))).collect();
    if let Some(&first) = points.first() {
        points.push(first);
    }
    chart.draw_series(std::iter::once(PathElement::new(points, color.stroke_width(style::LINE)))).map_err(e)?;
    let dot = at(s.minimum_azimuth_deg, s.minimum_g.max(0.0));
    chart
        .draw_series([
            Circle::new(dot, style::MARKER + 2, WHITE.filled()),
            Circle::new(dot, style::MARKER, color.filled()),
        ])
        .map_err(e)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tipping::tipping_polars;
    use crate::{Point3, Vec3};

    /// The summaries of a 0.6 × 1.0 × 2.4 m block (in mm) with one base corner raised by 1.5 mm
    /// and G moved off the centre, at contact tolerances 0 and 2 mm.
    fn block_summaries() -> Vec<TippingSummary> {
        let (a, b, c) = (300.0, 500.0, 1200.0);
        let mut corners: Vec<Point3> = (0..8)
            .map(|s| {
                let f = |k: usize, h: f64| if s >> k & 1 == 1 { -h } else { h };
                Point3::new(f(0, a), f(1, b), f(2, c))
            })
            .collect();
        for p in corners.iter_mut().filter(|p| p.x > 0.0 && p.y > 0.0 && p.z < 0.0) {
            p.z += 1.5;
        }
        let g = Point3::new(-40.0, -60.0, 0.0);
        let polars = tipping_polars(&corners, &g, &-Vec3::z(), &[0.0, 2.0]).unwrap();
        polars.iter().zip([0.0, 0.002]).map(|(p, tol)| p.summary(tol, 1e-3)).collect()
    }

    #[test]
    fn the_polar_plot_is_written_as_png_and_svg() {
        let summaries = block_summaries();
        assert_eq!(summaries[0].support_polygon_m.len(), 3);
        assert_eq!(summaries[1].support_polygon_m.len(), 4);
        let dir = tempfile::tempdir().unwrap();
        for name in ["polar.png", "polar.svg"] {
            let path = dir.path().join(name);
            write_polar_plot(&summaries, "Tipping polar of a block", &path).unwrap();
            let size = std::fs::metadata(&path).unwrap().len();
            assert!(size > 10_000, "{name}: {size} bytes");
        }
        let svg = std::fs::read_to_string(dir.path().join("polar.svg")).unwrap();
        assert!(svg.contains("τ = 2 mm: min"), "legend missing");
        let e = write_polar_plot(&[], "empty", &dir.path().join("empty.png")).unwrap_err();
        assert!(e.to_string().contains("summaries"), "{e}");
    }

    #[test]
    fn the_html_section_lists_each_tolerance_and_its_minimum() {
        let summaries = block_summaries();
        let html = polar_section_html(&summaries, "tipping <polar>.png");
        assert!(html.contains("<h2>Quasi-static tipping</h2>"));
        for s in &summaries {
            assert!(html.contains(&format!("<td>{}</td>", plain(s.minimum_g))), "{html}");
            assert!(html.contains(&format!("<td>{}</td>", azimuth_text(s.minimum_azimuth_deg))), "{html}");
        }
        // 2 mm: the full rectangle, nearest side x = −300 mm from G at x = −40: 260/1200.
        assert!((summaries[1].minimum_g - 260.0 / 1200.0).abs() < 1e-12);
        assert!(html.contains("<td>0.217</td>") && html.contains("<td>2</td>"), "{html}");
        assert!(html.contains("src=\"tipping &lt;polar&gt;.png\""), "{html}");
    }

    #[test]
    fn reference_circles_enclose_the_curves_in_round_steps() {
        assert_eq!(rings(0.42).iter().map(|r| plain(*r)).collect::<Vec<_>>(), ["0.1", "0.2", "0.3", "0.4", "0.5"]);
        for r_max in [0.0, 0.013, 0.1, 0.42, 1.0, 2.7, 35.0] {
            let r = rings(r_max);
            assert!((3..=5).contains(&r.len()), "{r_max}: {r:?}");
            assert!(*r.last().unwrap() >= r_max * (1.0 - 1e-9), "{r_max}: {r:?}");
        }
        assert_eq!(azimuth_text(359.7), "0");
        assert_eq!(azimuth_text(134.4), "134");
    }
}
