//! Plot helpers shared by the CLI and the experiments (plotters, bundled font).
//!
//! plotters' default font backend needs the system's fontconfig, which a fresh machine may lack;
//! the project bundles DejaVu Sans (`assets/`, free licence) and registers it through the
//! `ab_glyph` backend, so PNG and SVG plots render everywhere.
//!
//! [`render!`](crate::plot::render) is the one place that picks the backend (SVG for a `.svg`
//! path, PNG otherwise) and turns plotters' errors into [`crate::Error::Plot`].

use std::sync::Once;

static FONT: Once = Once::new();
static DEJAVU: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

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
