//! Plot helpers shared by the CLI and the experiments (plotters, bundled font).
//!
//! plotters' default font backend needs the system's fontconfig, which a fresh machine may lack;
//! the project bundles DejaVu Sans (`assets/`, free licence) and registers it through the
//! `ab_glyph` backend, so PNG and SVG plots render everywhere.
//!
//! `render!` is the one place that picks the backend (SVG for a `.svg`
//! path, PNG otherwise) and turns plotters' errors into [`crate::Error::Plot`].

mod chart;
mod intervals;
mod reliability;
pub use chart::{Axis, Chart, Figure, Marker};
pub use intervals::wilson_bars;
/// The colour of every series (`RGBColor(r, g, b)`), so that a program drawing through [`Chart`]
/// can name its own colour without depending on plotters.
pub use plotters::style::RGBColor;
pub use reliability::{reliability_bins, reliability_diagram};
mod categories;
pub use categories::BarSlot;

use std::sync::Once;

static FONT: Once = Once::new();
static DEJAVU: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// Register the bundled font as "sans-serif" (idempotent). Call before drawing any text.
pub fn init_fonts() {
    FONT.call_once(|| {
        if plotters::style::register_font("sans-serif", plotters::style::FontStyle::Normal, DEJAVU).is_err() {
            eprintln!("warning: could not register the bundled font; plots will have no text");
        }
    });
}

/// Font family name to use in every plot.
pub const FONT_FAMILY: &str = "sans-serif";

/// What a drawing step returns: plotters' errors (generic over the backend) boxed.
pub type DrawResult = std::result::Result<(), crate::error::BoxError>;

/// Draw into a PNG or an SVG (by the extension of `path`) of `size` pixels: registers the font,
/// makes the root area `$root` of the right backend, evaluates `$body` (a [`DrawResult`]; it is
/// expanded once per backend, so generic drawing functions and plain code both work), presents
/// the file and returns a [`crate::Result`] naming the file on failure.
macro_rules! render {
    ($path:expr, $size:expr, |$root:ident| $body:expr) => {{
        use plotters::prelude::IntoDrawingArea as _;
        $crate::plot::init_fonts();
        let path: &std::path::Path = $path;
        let drawn: $crate::plot::DrawResult = if path.extension().is_some_and(|e| e == "svg") {
            let $root = plotters::prelude::SVGBackend::new(path, $size).into_drawing_area();
            (|| -> $crate::plot::DrawResult {
                $body?;
                $root.present()?;
                Ok(())
            })()
        } else {
            let $root = plotters::prelude::BitMapBackend::new(path, $size).into_drawing_area();
            (|| -> $crate::plot::DrawResult {
                $body?;
                $root.present()?;
                Ok(())
            })()
        };
        drawn.map_err(|e| $crate::Error::Plot { path: path.to_path_buf(), what: e.to_string() })
    }};
}
pub(crate) use render;

/// Draw a PNG picture of `size` pixels into `path` in the house style (the bundled font
/// registered first): `draw` paints the drawing area, which is then written. The one way
/// programs outside the library (the experiments) make a picture; a failure is an
/// [`Error::Plot`](crate::Error::Plot) naming the file.
pub fn draw_png(
    path: &std::path::Path,
    size: (u32, u32),
    draw: impl FnOnce(
        &plotters::prelude::DrawingArea<plotters::prelude::BitMapBackend<'_>, plotters::coord::Shift>,
    ) -> DrawResult,
) -> crate::Result<()> {
    use plotters::prelude::IntoDrawingArea as _;
    init_fonts();
    let root = plotters::prelude::BitMapBackend::new(path, size).into_drawing_area();
    (|| -> DrawResult {
        draw(&root)?;
        root.present()?;
        Ok(())
    })()
    .map_err(|e| crate::Error::Plot { path: path.to_path_buf(), what: e.to_string() })
}

/// [`draw_png`]'s twin for an SVG picture of `size` pixels.
pub fn draw_svg(
    path: &std::path::Path,
    size: (u32, u32),
    draw: impl FnOnce(
        &plotters::prelude::DrawingArea<plotters::prelude::SVGBackend<'_>, plotters::coord::Shift>,
    ) -> DrawResult,
) -> crate::Result<()> {
    use plotters::prelude::IntoDrawingArea as _;
    init_fonts();
    let root = plotters::prelude::SVGBackend::new(path, size).into_drawing_area();
    (|| -> DrawResult {
        draw(&root)?;
        root.present()?;
        Ok(())
    })()
    .map_err(|e| crate::Error::Plot { path: path.to_path_buf(), what: e.to_string() })
}

/// The house style of every plot the project draws (library reports and experiments): one place
/// for font sizes, line widths and colours, so that all figures read alike. Sizes are in pixels
/// of a figure about 900 px wide, which keeps a 1 : 1 scale for a journal column (8–9 cm) at
/// ~250 dpi: text ≥ 14 px ≈ 8 pt there.
pub mod style {
    /// Figure title.
    pub const TITLE: u32 = 20;
    /// Panel title (multi-panel figures).
    pub const PANEL_TITLE: u32 = 16;
    /// Axis descriptions ("ν (log scale)", "probability").
    pub const AXIS: u32 = 16;
    /// Tick labels.
    pub const TICK: u32 = 14;
    /// Legend entries and labels written on a picture.
    pub const LEGEND: u32 = 14;
    /// Data lines.
    pub const LINE: u32 = 2;
    /// Marker radius.
    pub const MARKER: u32 = 4;
}

/// The Okabe–Ito colour-blind-safe qualitative palette (M. Okabe & K. Ito, *Color Universal
/// Design*, 2008; the palette recommended by Wong, *Nature Methods* 8, 441 (2011)): black,
/// orange, sky blue, bluish green, yellow, blue, vermillion, reddish purple.
pub const OKABE_ITO: [RGBColor; 8] = [
    RGBColor(0, 0, 0),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 158, 115),
    RGBColor(240, 228, 66),
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(204, 121, 167),
];

/// Named Okabe–Ito colours for the data series of every plot.
pub mod colors {
    use plotters::style::RGBColor;
    /// Okabe–Ito blue.
    pub const BLUE: RGBColor = RGBColor(0, 114, 178);
    /// Okabe–Ito vermillion.
    pub const VERMILLION: RGBColor = RGBColor(213, 94, 0);
    /// Okabe–Ito bluish green.
    pub const GREEN: RGBColor = RGBColor(0, 158, 115);
    /// Okabe–Ito orange.
    pub const ORANGE: RGBColor = RGBColor(230, 159, 0);
    /// Okabe–Ito sky blue.
    pub const SKY: RGBColor = RGBColor(86, 180, 233);
    /// Okabe–Ito reddish purple.
    pub const PURPLE: RGBColor = RGBColor(204, 121, 167);
    /// Okabe–Ito yellow.
    pub const YELLOW: RGBColor = RGBColor(240, 228, 66);
    /// Neutral grey for reference marks (ε*, plateaus' edges, diagonals).
    pub const GREY: RGBColor = RGBColor(110, 110, 110);
}

/// The colour of data series `k` of a plot (several stones, stages, parameters): Okabe–Ito
/// blue, vermillion, bluish green, orange, reddish purple, sky blue, black, yellow, repeating.
pub fn series_color(k: usize) -> RGBColor {
    const ORDER: [usize; 8] = [5, 6, 3, 1, 7, 2, 0, 4];
    OKABE_ITO[ORDER[k % 8]]
}

/// Paul Tol's colour-blind-safe qualitative palettes (P. Tol, *Colour Schemes*, SRON technical
/// note SRON/EPS/TN/09-002, 2021): the nine "muted" colours, then the eight "light" ones (without
/// their pale grey): up to 17 flocks get distinct colours; beyond that they repeat and the flock
/// number written on the picture tells them apart.
pub const FLOCK_PALETTE: [RGBColor; 17] = [
    RGBColor(51, 34, 136),   // indigo
    RGBColor(221, 204, 119), // sand
    RGBColor(17, 119, 51),   // green
    RGBColor(204, 102, 119), // rose
    RGBColor(136, 204, 238), // cyan
    RGBColor(136, 34, 85),   // wine
    RGBColor(68, 170, 153),  // teal
    RGBColor(153, 153, 51),  // olive
    RGBColor(170, 68, 153),  // purple
    RGBColor(119, 170, 221), // light blue
    RGBColor(238, 136, 102), // orange
    RGBColor(187, 204, 51),  // pear
    RGBColor(255, 170, 187), // pink
    RGBColor(153, 221, 255), // light cyan
    RGBColor(170, 170, 0),   // light olive
    RGBColor(238, 221, 136), // light yellow
    RGBColor(68, 187, 153),  // mint
];

/// The colour of flock number `id` (flocks are numbered 0, 1, … in every report): the same in
/// `hull.png`, `hull_flocks.ply`, the drop bar plots and the 3D view of `report.html`.
pub fn flock_color(id: usize) -> RGBColor {
    FLOCK_PALETTE[id % FLOCK_PALETTE.len()]
}

/// Superscript form of an integer exponent ("−5" → "⁻⁵").
fn superscript(e: i32) -> String {
    e.to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            _ => '⁹',
        })
        .collect()
}

/// A tick label of a log axis, read by a person: the value rounded to 3 significant digits
/// (plotters' ticks carry float noise, 10⁻⁵ arrives as 9.99999e-6), as a plain decimal between
/// 0.001 and 10 000 ("0.001", "0.02", "500"), otherwise as a power of ten ("10⁻⁵", "2×10⁻⁶").
pub fn log_tick(x: f64) -> String {
    if !x.is_finite() || x <= 0.0 {
        return if x == 0.0 { "0".into() } else { String::new() };
    }
    let e = x.log10().floor() as i32;
    let mut m = x / 10f64.powi(e);
    // round the mantissa to 3 significant digits; 9.999… becomes 10 and moves the exponent.
    m = (m * 100.0).round() / 100.0;
    let (m, e) = if m >= 10.0 { (m / 10.0, e + 1) } else { (m, e) };
    if (-3..=4).contains(&e) {
        plain(m * 10f64.powi(e))
    } else if (m - 1.0).abs() < 1e-9 {
        format!("10{}", superscript(e))
    } else {
        format!("{}×10{}", plain(m), superscript(e))
    }
}

/// A number as a plain decimal with at most 3 significant digits and no trailing zeros
/// ("0.0035", "12.5", "300").
pub fn plain(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{x:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The mark of a legend entry drawn by [`draw_legend`].
#[derive(Clone, Copy, Debug)]
pub enum Mark {
    /// A solid line in a colour.
    Line(RGBColor),
    /// A dashed line in a colour.
    Dashed(RGBColor),
    /// A filled box (areas, bars) in a colour with an opacity.
    Box(RGBColor, f64),
    /// A dot with a short line (points joined by lines, with error bars).
    LineDot(RGBColor),
    /// A filled dot (scattered points).
    Dot(RGBColor),
    /// An open circle (scattered points of a second kind).
    Ring(RGBColor),
    /// A filled triangle (scattered points of a third kind).
    Triangle(RGBColor),
    /// A cross (scattered points of a fourth kind).
    Cross(RGBColor),
    /// A solid line of a given width in pixels (a series drawn wider than the others).
    WideLine(RGBColor, u32),
}

/// Where each legend entry goes in `area` (its top-left pixel), wrapping left to right, and
/// how many lines the entries take.
pub(crate) fn layout_legend<DB: plotters::prelude::DrawingBackend>(
    area: &plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
    entries: &[(Mark, String)],
) -> std::result::Result<(Vec<(i32, i32)>, u32), crate::error::BoxError>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let width = area.dim_in_pixel().0 as i32;
    let font = (FONT_FAMILY, style::LEGEND);
    let (mut x, mut y, mut lines) = (16, 6, 1);
    let mut at = Vec::with_capacity(entries.len());
    for (_, text) in entries {
        let text_w = area.estimate_text_size(text, &font.into_text_style(area))?.0 as i32;
        let item_w = 30 + text_w + 26;
        if x + item_w > width && x > 16 {
            x = 16;
            y += 24;
            lines += 1;
        }
        at.push((x, y));
        x += item_w;
    }
    Ok((at, lines))
}

/// Draw a legend in its own strip `area` (outside every chart, so it never covers data): the
/// entries left to right, wrapping to new lines, each a mark and its text in the house font.
/// Returns nothing but plotters' errors as text.
pub fn draw_legend<DB: plotters::prelude::DrawingBackend>(
    area: &plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
    entries: &[(Mark, String)],
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let err = |x: DrawingAreaErrorKind<DB::ErrorType>| format!("{x:?}");
    let font = (FONT_FAMILY, style::LEGEND);
    let (at, _) = layout_legend(area, entries)?;
    for ((mark, text), (x, y)) in entries.iter().zip(at) {
        let my = y + 9;
        match *mark {
            Mark::Line(c) => {
                area.draw(&PathElement::new(vec![(x, my), (x + 22, my)], c.stroke_width(style::LINE))).map_err(err)?
            }
            Mark::Dashed(c) => {
                for k in 0..3 {
                    area.draw(&PathElement::new(
                        vec![(x + 8 * k, my), (x + 8 * k + 5, my)],
                        c.stroke_width(style::LINE),
                    ))
                    .map_err(err)?
                }
            }
            Mark::Box(c, alpha) => {
                area.draw(&Rectangle::new([(x, my - 7), (x + 22, my + 7)], c.mix(alpha).filled())).map_err(err)?
            }
            Mark::LineDot(c) => {
                area.draw(&PathElement::new(vec![(x, my), (x + 22, my)], c.stroke_width(style::LINE))).map_err(err)?;
                area.draw(&Circle::new((x + 11, my), 4, c.filled())).map_err(err)?;
            }
            Mark::Dot(c) => area.draw(&Circle::new((x + 11, my), 4, c.filled())).map_err(err)?,
            Mark::Ring(c) => area.draw(&Circle::new((x + 11, my), 4, c.stroke_width(2))).map_err(err)?,
            Mark::Triangle(c) => area.draw(&TriangleMarker::new((x + 11, my), 5, c.filled())).map_err(err)?,
            Mark::Cross(c) => area.draw(&Cross::new((x + 11, my), 4, c.stroke_width(2))).map_err(err)?,
            Mark::WideLine(c, w) => {
                area.draw(&PathElement::new(vec![(x, my), (x + 22, my)], c.stroke_width(w))).map_err(err)?
            }
        }
        area.draw(&Text::new(text.clone(), (x + 30, y), font)).map_err(err)?;
    }
    Ok(())
}

/// The height in pixels of a legend strip of `lines` lines.
pub fn legend_height(lines: u32) -> u32 {
    12 + 24 * lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_ticks_are_clean() {
        assert_eq!(log_tick(9.999_999_999_999_99e-6), "10⁻⁵");
        assert_eq!(log_tick(1e-5), "10⁻⁵");
        assert_eq!(log_tick(2e-7), "2×10⁻⁷");
        assert_eq!(log_tick(0.001), "0.001");
        assert_eq!(log_tick(0.009_999_999_999), "0.01");
        assert_eq!(log_tick(0.05), "0.05");
        assert_eq!(log_tick(1.0), "1");
        assert_eq!(log_tick(500.0), "500");
        assert_eq!(log_tick(1e6), "10⁶");
        assert_eq!(plain(0.0035), "0.0035");
        assert_eq!(plain(12.5), "12.5");
    }

    #[test]
    fn flock_colours_are_distinct_up_to_the_palette_size() {
        for i in 0..FLOCK_PALETTE.len() {
            for j in 0..i {
                assert_ne!(flock_color(i), flock_color(j), "flocks {i} and {j}");
            }
        }
        assert_eq!(flock_color(FLOCK_PALETTE.len()), flock_color(0));
    }
}
