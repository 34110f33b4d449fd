//! Plot helpers shared by the CLI and the experiments (plotters, bundled font).
//!
//! plotters' default font backend needs the system's fontconfig, which a fresh machine may lack;
//! the project bundles DejaVu Sans (`assets/`, free licence) and registers it through the
//! `ab_glyph` backend, so PNG and SVG plots render everywhere.

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
