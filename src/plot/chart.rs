//! A chart in the house style, described as data and drawn in one call: the public plotting
//! API of programs outside the library (the experiments), so that none of them sets up a
//! plotters backend, a coordinate system or the fonts and sizes of [`style`](super::style).
//!
//! A [`Chart`] is two [`Axis`] (linear or logarithmic) and layers drawn in the order they were
//! added: lines (solid or dashed), markers (dots, rings, triangles, crosses), error bars,
//! filled boxes, text, and dashed reference lines across the plot. Its legend is drawn in a
//! strip of its own above the plot, so it never covers data; the strip is as tall as the
//! entries need once wrapped to the width. A [`Figure`] puts several charts side by side under
//! one title and one legend.
//!
//! ```no_run
//! use rocking_stones::plot::{colors, Axis, Chart, Mark};
//! let points = vec![(0.0, 0.1), (0.5, 0.4), (1.0, 0.9)];
//! Chart::new(Axis::linear("h / d", 0.0, 1.0), Axis::linear("P(edge)", 0.0, 1.0))
//!     .title("P(edge) against h/d")
//!     .line(&points, colors::BLUE)
//!     .dots(&points, colors::BLUE)
//!     .hline(1.0 / 3.0, colors::GREY)
//!     .legend(Mark::LineDot(colors::BLUE), "simulated")
//!     .save(std::path::Path::new("p_edge.png"), (900, 640))?;
//! # Ok::<(), rocking_stones::Error>(())
//! ```

use super::{draw_legend, layout_legend, log_tick, plain, style, DrawResult, Mark, FONT_FAMILY};
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::rc::Rc;

/// How a tick value is written.
type Formatter = Rc<dyn Fn(f64) -> String>;

/// One axis of a [`Chart`]: its description, range, scale and ticks.
#[derive(Clone)]
pub struct Axis {
    label: String,
    lo: f64,
    hi: f64,
    log: bool,
    ticks: Option<usize>,
    grid: bool,
    format: Option<Formatter>,
    space: Option<u32>,
}

impl Axis {
    /// A linear axis from `lo` to `hi`; ticks written by [`plain`].
    pub fn linear(label: impl Into<String>, lo: f64, hi: f64) -> Self {
        Axis { label: label.into(), lo, hi, log: false, ticks: None, grid: true, format: None, space: None }
    }

    /// A logarithmic axis from `lo` to `hi` (both > 0); ticks written by [`log_tick`].
    pub fn log(label: impl Into<String>, lo: f64, hi: f64) -> Self {
        Axis { log: true, ..Axis::linear(label, lo, hi) }
    }

    /// About `n` ticks instead of plotters' default (0: none).
    pub fn ticks(mut self, n: usize) -> Self {
        self.ticks = Some(n);
        self
    }

    /// No grid lines across the plot at this axis' ticks.
    pub fn no_grid(mut self) -> Self {
        self.grid = false;
        self
    }

    /// Write the ticks with `f` (category names, percentages) instead of the default.
    pub fn format(mut self, f: impl Fn(f64) -> String + 'static) -> Self {
        self.format = Some(Rc::new(f));
        self
    }

    /// `px` pixels beside the plot for this axis' tick labels and description (default 50 for x,
    /// 60 for y): room for long category names.
    pub fn space(mut self, px: u32) -> Self {
        self.space = Some(px);
        self
    }

    fn tick_text(&self, v: f64) -> String {
        // A tick at zero that the range arithmetic left at ±10⁻¹⁷ is written as zero.
        let v = if v.abs() < 1e-9 * (self.hi - self.lo).abs() { 0.0 } else { v };
        match &self.format {
            Some(f) => f(v),
            None if self.log => log_tick(v),
            None => plain(v),
        }
    }
}

/// The shape of a marker layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Marker {
    /// A filled dot.
    Dot,
    /// An open circle.
    Ring,
    /// A filled triangle.
    Triangle,
    /// A cross.
    Cross,
}

/// One thing drawn on a chart, in data coordinates.
#[derive(Clone)]
enum Layer {
    Line {
        points: Vec<(f64, f64)>,
        color: RGBColor,
        width: u32,
        dashed: bool,
    },
    Markers {
        points: Vec<(f64, f64)>,
        color: RGBColor,
        marker: Marker,
        size: u32,
    },
    /// Vertical bars `(x, lo, hi)` when `vertical`, horizontal bars `(y, lo, hi)` otherwise.
    Bars {
        bars: Vec<(f64, f64, f64)>,
        color: RGBColor,
        vertical: bool,
    },
    /// Filled boxes `(x0, y0, x1, y1, colour)` with an opacity.
    Boxes {
        boxes: Vec<(f64, f64, f64, f64, RGBColor)>,
        alpha: f64,
    },
    Text {
        text: String,
        at: (f64, f64),
        color: RGBColor,
    },
    /// A dashed line across the whole plot at `y` (`horizontal`) or `x`.
    /// A filled polygon with an opacity.
    Polygon {
        points: Vec<(f64, f64)>,
        color: RGBColor,
        alpha: f64,
    },
    Rule {
        at: f64,
        color: RGBColor,
        horizontal: bool,
    },
}

/// A chart: two axes, layers drawn in order, a legend, an optional title.
#[derive(Clone)]
pub struct Chart {
    title: Option<String>,
    x: Axis,
    y: Axis,
    layers: Vec<Layer>,
    legend: Vec<(Mark, String)>,
}

impl Chart {
    /// An empty chart over the axes `x` and `y`.
    pub fn new(x: Axis, y: Axis) -> Self {
        Chart { title: None, x, y, layers: Vec::new(), legend: Vec::new() }
    }

    /// The title above the chart (the figure's title when the chart is saved alone, the panel's
    /// title in a [`Figure`]).
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }

    /// A solid line through `points` in the house line width.
    pub fn line(self, points: &[(f64, f64)], color: RGBColor) -> Self {
        self.line_width(points, color, style::LINE)
    }

    /// A solid line through `points`, `width` pixels wide.
    pub fn line_width(mut self, points: &[(f64, f64)], color: RGBColor, width: u32) -> Self {
        self.layers.push(Layer::Line { points: points.to_vec(), color, width, dashed: false });
        self
    }

    /// A dashed line through `points` in the house line width.
    pub fn dashed(mut self, points: &[(f64, f64)], color: RGBColor) -> Self {
        self.layers.push(Layer::Line { points: points.to_vec(), color, width: style::LINE, dashed: true });
        self
    }

    /// Markers of `marker` shape at `points`, in the house marker size.
    pub fn markers(self, points: &[(f64, f64)], color: RGBColor, marker: Marker) -> Self {
        self.markers_sized(points, color, marker, style::MARKER)
    }

    /// Markers of `marker` shape and radius `size` pixels at `points`.
    pub fn markers_sized(mut self, points: &[(f64, f64)], color: RGBColor, marker: Marker, size: u32) -> Self {
        self.layers.push(Layer::Markers { points: points.to_vec(), color, marker, size });
        self
    }

    /// Filled dots at `points`.
    pub fn dots(self, points: &[(f64, f64)], color: RGBColor) -> Self {
        self.markers(points, color, Marker::Dot)
    }

    /// Open circles at `points`.
    pub fn rings(self, points: &[(f64, f64)], color: RGBColor) -> Self {
        self.markers(points, color, Marker::Ring)
    }

    /// Vertical error bars `(x, lo, hi)`.
    pub fn y_bars(mut self, bars: &[(f64, f64, f64)], color: RGBColor) -> Self {
        self.layers.push(Layer::Bars { bars: bars.to_vec(), color, vertical: true });
        self
    }

    /// Horizontal error bars `(y, lo, hi)`.
    pub fn x_bars(mut self, bars: &[(f64, f64, f64)], color: RGBColor) -> Self {
        self.layers.push(Layer::Bars { bars: bars.to_vec(), color, vertical: false });
        self
    }

    /// Filled boxes `(x0, y0, x1, y1)` in one colour with opacity `alpha` (bars, bands).
    pub fn boxes(self, boxes: &[(f64, f64, f64, f64)], color: RGBColor, alpha: f64) -> Self {
        let boxes: Vec<_> = boxes.iter().map(|&(a, b, c, d)| (a, b, c, d, color)).collect();
        self.colored_boxes(&boxes, alpha)
    }

    /// Filled boxes `(x0, y0, x1, y1, colour)`, each in its own colour, with opacity `alpha`
    /// (maps, per-category bars).
    pub fn colored_boxes(mut self, boxes: &[(f64, f64, f64, f64, RGBColor)], alpha: f64) -> Self {
        self.layers.push(Layer::Boxes { boxes: boxes.to_vec(), alpha });
        self
    }

    /// A filled polygon through `points` with opacity `alpha` (a band between two curves: the
    /// upper curve, then the lower one reversed; a shape's outline).
    pub fn polygon(mut self, points: &[(f64, f64)], color: RGBColor, alpha: f64) -> Self {
        self.layers.push(Layer::Polygon { points: points.to_vec(), color, alpha });
        self
    }

    /// `text` in the legend font with its top-left corner at `at`.
    pub fn text(self, text: impl Into<String>, at: (f64, f64)) -> Self {
        self.text_colored(text, at, BLACK)
    }

    /// `text` in a colour, top-left corner at `at`.
    pub fn text_colored(mut self, text: impl Into<String>, at: (f64, f64), color: RGBColor) -> Self {
        self.layers.push(Layer::Text { text: text.into(), at, color });
        self
    }

    /// A dashed horizontal line across the plot at `y` (a reference value).
    pub fn hline(mut self, y: f64, color: RGBColor) -> Self {
        self.layers.push(Layer::Rule { at: y, color, horizontal: true });
        self
    }

    /// A dashed vertical line across the plot at `x`.
    pub fn vline(mut self, x: f64, color: RGBColor) -> Self {
        self.layers.push(Layer::Rule { at: x, color, horizontal: false });
        self
    }

    /// A legend entry: `mark` and its text.
    pub fn legend(mut self, mark: Mark, text: impl Into<String>) -> Self {
        self.legend.push((mark, text.into()));
        self
    }

    /// Save the chart alone as a PNG or SVG (by the extension of `path`) of `size` pixels, its
    /// title as the figure's title. A failure names the file.
    pub fn save(self, path: &Path, size: (u32, u32)) -> crate::Result<()> {
        Figure { title: None, legend: Vec::new(), cols: 1, panels: vec![self] }.save(path, size)
    }

    /// Draw the chart into `area`, its title in `title_size` pixels.
    fn draw_on<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, title_size: u32) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let area = match &self.title {
            Some(t) => area.titled(t, (FONT_FAMILY, title_size))?,
            None => area.clone(),
        };
        let area = with_legend(&area, &self.legend)?;
        let mut builder = ChartBuilder::on(&area);
        builder.margin(20).x_label_area_size(self.x.space.unwrap_or(50)).y_label_area_size(self.y.space.unwrap_or(60));
        let (x, y) = ((self.x.lo..self.x.hi), (self.y.lo..self.y.hi));
        match (self.x.log, self.y.log) {
            (false, false) => self.paint(builder.build_cartesian_2d(x, y)?),
            (true, false) => self.paint(builder.build_cartesian_2d(x.log_scale(), y)?),
            (false, true) => self.paint(builder.build_cartesian_2d(x, y.log_scale())?),
            (true, true) => self.paint(builder.build_cartesian_2d(x.log_scale(), y.log_scale())?),
        }
    }

    /// Draw the axes and every layer on a chart context of any pair of f64 coordinates.
    fn paint<DB, X, Y>(&self, mut chart: ChartContext<'_, DB, Cartesian2d<X, Y>>) -> DrawResult
    where
        DB: DrawingBackend,
        DB::ErrorType: 'static,
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        let (fx, fy) = (|v: &f64| self.x.tick_text(*v), |v: &f64| self.y.tick_text(*v));
        let mut mesh = chart.configure_mesh();
        mesh.x_desc(self.x.label.as_str())
            .y_desc(self.y.label.as_str())
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .label_style((FONT_FAMILY, style::TICK))
            .axis_desc_style((FONT_FAMILY, style::AXIS));
        if let Some(n) = self.x.ticks {
            mesh.x_labels(n);
        }
        if let Some(n) = self.y.ticks {
            mesh.y_labels(n);
        }
        if !self.x.grid {
            mesh.disable_x_mesh();
        }
        if !self.y.grid {
            mesh.disable_y_mesh();
        }
        mesh.draw()?;
        for layer in &self.layers {
            match layer {
                Layer::Line { points, color, width, dashed: false } => {
                    chart.draw_series(LineSeries::new(points.iter().copied(), color.stroke_width(*width)))?;
                }
                Layer::Line { points, color, width, dashed: true } => {
                    chart.draw_series(DashedLineSeries::new(
                        points.iter().copied(),
                        8,
                        6,
                        color.stroke_width(*width),
                    ))?;
                }
                Layer::Markers { points, color, marker, size } => {
                    let s = *size as i32;
                    for &p in points {
                        match marker {
                            Marker::Dot => chart.plotting_area().draw(&Circle::new(p, s, color.filled()))?,
                            Marker::Ring => chart.plotting_area().draw(&Circle::new(p, s, color.stroke_width(2)))?,
                            Marker::Triangle => {
                                chart.plotting_area().draw(&TriangleMarker::new(p, s + 1, color.filled()))?
                            }
                            Marker::Cross => chart.plotting_area().draw(&Cross::new(p, s, color.stroke_width(2)))?,
                        }
                    }
                }
                Layer::Bars { bars, color, vertical } => {
                    chart.draw_series(bars.iter().map(|&(at, lo, hi)| {
                        let ends = if *vertical { vec![(at, lo), (at, hi)] } else { vec![(lo, at), (hi, at)] };
                        PathElement::new(ends, color.stroke_width(style::LINE))
                    }))?;
                }
                Layer::Boxes { boxes, alpha } => {
                    chart.draw_series(
                        boxes
                            .iter()
                            .map(|&(x0, y0, x1, y1, c)| Rectangle::new([(x0, y0), (x1, y1)], c.mix(*alpha).filled())),
                    )?;
                }
                Layer::Text { text, at, color } => {
                    chart.draw_series(std::iter::once(Text::new(
                        text.clone(),
                        *at,
                        (FONT_FAMILY, style::LEGEND).into_font().color(color),
                    )))?;
                }
                Layer::Polygon { points, color, alpha } => {
                    chart.draw_series(std::iter::once(Polygon::new(points.clone(), color.mix(*alpha).filled())))?;
                }
                Layer::Rule { at, color, horizontal } => {
                    let ends = if *horizontal {
                        vec![(self.x.lo, *at), (self.x.hi, *at)]
                    } else {
                        vec![(*at, self.y.lo), (*at, self.y.hi)]
                    };
                    chart.draw_series(DashedLineSeries::new(ends, 8, 6, color.stroke_width(1)))?;
                }
            }
        }
        Ok(())
    }
}

/// Several [`Chart`]s side by side under one title and one legend.
pub struct Figure {
    title: Option<String>,
    legend: Vec<(Mark, String)>,
    cols: usize,
    panels: Vec<Chart>,
}

impl Figure {
    /// A figure of `panels` in rows of `cols` (≥ 1), under `title`.
    pub fn new(title: impl Into<String>, cols: usize, panels: Vec<Chart>) -> Self {
        Figure { title: Some(title.into()), legend: Vec::new(), cols: cols.max(1), panels }
    }

    /// A legend entry shared by every panel, drawn once under the title.
    pub fn legend(mut self, mark: Mark, text: impl Into<String>) -> Self {
        self.legend.push((mark, text.into()));
        self
    }

    /// Save as a PNG or SVG (by the extension of `path`) of `size` pixels; a failure names the
    /// file.
    pub fn save(&self, path: &Path, size: (u32, u32)) -> crate::Result<()> {
        super::render!(path, size, |root| self.draw(&root))
    }

    /// Draw the figure into `area`.
    pub fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        area.fill(&WHITE)?;
        let area = match &self.title {
            Some(t) => area.titled(t, (FONT_FAMILY, style::TITLE))?,
            None => area.clone(),
        };
        let area = with_legend(&area, &self.legend)?;
        if let [alone] = self.panels.as_slice() {
            return alone.draw_on(&area, if self.title.is_some() { style::PANEL_TITLE } else { style::TITLE });
        }
        let rows = self.panels.len().div_ceil(self.cols);
        let cells = area.split_evenly((rows, self.cols));
        for (panel, cell) in self.panels.iter().zip(cells.iter()) {
            panel.draw_on(cell, style::PANEL_TITLE)?;
        }
        Ok(())
    }
}

/// Draw `entries` as a legend strip at the top of `area` (nothing if there are none) and
/// return the rest of the area.
fn with_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[(Mark, String)],
) -> Result<DrawingArea<DB, Shift>, crate::error::BoxError>
where
    DB::ErrorType: 'static,
{
    if entries.is_empty() {
        return Ok(area.clone());
    }
    let (_, lines) = layout_legend(area, entries)?;
    let (strip, rest) = area.split_vertically(super::legend_height(lines));
    draw_legend(&strip, entries)?;
    Ok(rest)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::colors;

    #[test]
    fn a_tick_at_zero_left_at_rounding_noise_reads_zero() {
        let axis = Axis::linear("x", -0.3, 0.3);
        assert_eq!(axis.tick_text(-2.78e-17), "0");
        assert_eq!(axis.tick_text(0.1), "0.1");
        // Small but real values are kept.
        assert_eq!(Axis::linear("x", 0.0, 1e-6).tick_text(2e-7), "0.0000002");
    }

    fn svg_of(figure: &Figure, size: (u32, u32)) -> String {
        super::super::init_fonts();
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
            figure.draw(&root).expect("draws");
            root.present().expect("presents");
        }
        svg
    }

    #[test]
    fn a_chart_draws_its_title_axes_series_and_legend() {
        let pts = [(1.0, 0.2), (10.0, 0.5), (100.0, 0.9)];
        let chart = Chart::new(Axis::log("ν (log scale)", 1.0, 100.0), Axis::linear("probability", 0.0, 1.0))
            .title("a test chart")
            .line(&pts, colors::VERMILLION)
            .dots(&pts, colors::BLUE)
            .hline(0.5, colors::GREY)
            .polygon(&[(2.0, 0.1), (3.0, 0.1), (3.0, 0.3)], colors::PURPLE, 1.0)
            .legend(Mark::Line(colors::VERMILLION), "model");
        let svg = svg_of(&Figure { title: None, legend: vec![], cols: 1, panels: vec![chart] }, (600, 400));
        for needle in ["a test chart", "ν (log scale)", "probability", "model", "#D55E00", "#0072B2", "#CC79A7"] {
            assert!(svg.contains(needle), "{needle} missing from the SVG");
        }
        // the log axis writes its ticks as a person reads them
        assert!(svg.contains("\n10\n") && svg.contains("\n100\n"), "log ticks missing");
        assert!(!svg.contains("#009E73"), "a colour that was never drawn appears");
    }

    #[test]
    fn a_figure_draws_every_panel_and_the_legend_grows_with_its_entries() {
        let panel = |t: &str| Chart::new(Axis::linear("x", 0.0, 1.0), Axis::linear("y", 0.0, 1.0)).title(t);
        let fig = Figure::new("two panels", 2, vec![panel("left panel"), panel("right panel")])
            .legend(Mark::Dot(colors::GREEN), "shared");
        let svg = svg_of(&fig, (800, 400));
        for needle in ["two panels", "left panel", "right panel", "shared", "#009E73"] {
            assert!(svg.contains(needle), "{needle} missing from the SVG");
        }
        let mut svg = String::new();
        let root = SVGBackend::with_string(&mut svg, (300, 200)).into_drawing_area();
        let long: Vec<(Mark, String)> =
            (0..6).map(|k| (Mark::Dot(colors::BLUE), format!("entry number {k}"))).collect();
        let (_, one) = layout_legend(&root, &long[..1]).unwrap();
        let (_, many) = layout_legend(&root, &long).unwrap();
        assert_eq!(one, 1);
        assert!(many >= 3, "six long entries in 300 px take {many} lines");
    }
}
