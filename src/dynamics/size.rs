//! The real size of a stone: the one place every dynamics command and the Python binding decide
//! it, and say how they did.
//!
//! A mesh's coordinates carry no unit, but a dynamic result does depend on the real size: the
//! contact's rolling-resistance length δ is divided by R_max, and a ground motion's real
//! frequencies meet the stone at √R_max (every other group is Froude-invariant, see
//! [`crate::dynamics::drops::params`]). The static pipeline (equilibria, flocks, ν, basins) does not. So the size
//! is either **given** (a length unit or R_max), **known** (the bundled stone is in millimetres)
//! or **assumed** (the command's default) — and an assumed size is never silent:
//! [`RealSize::assumption`] is the sentence the command line and the Python binding show before
//! running, and [`RealSize::implausibility`] flags a size outside [`PLAUSIBLE_R_MAX_M`] however it
//! was decided.

use crate::{bundled, Error, Result};
use serde::{Deserialize, Serialize};

/// How the real size of a stone is given: the length of its mesh unit, or its R_max directly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Size {
    /// Metres per mesh unit.
    Unit(f64),
    /// R_max in metres.
    RMax(f64),
}

impl Size {
    /// Metres per mesh unit for a stone whose R_max is `r_max` mesh units; a size that is not a
    /// positive finite length is refused.
    pub fn length_unit_m(self, r_max: f64) -> Result<f64> {
        let unit = match self {
            Size::Unit(u) => u,
            Size::RMax(r) => r / r_max,
        };
        match self {
            Size::Unit(u) if !(unit > 0.0 && unit.is_finite()) => {
                return Err(Error::parameter("length_unit", u, "a positive length in metres per mesh unit"))
            }
            Size::RMax(r) if !(unit > 0.0 && unit.is_finite()) => {
                return Err(Error::parameter("size", r, "a positive length in metres (R_max)"))
            }
            _ => {}
        }
        Ok(unit)
    }
}

/// What a command assumes of a mesh whose unit is neither given nor known: metres, the unit of
/// field scans (`perturb`, `shake`, `shake --pose`).
pub const ASSUMED_UNIT: Size = Size::Unit(1.0);

/// What `drop` assumes of a stone whose size is neither given nor known: R_max = 1 cm, the
/// reference size of the drop presets ([`REFERENCE_R_MAX_M`], a die).
pub const ASSUMED_DROP_SIZE: Size = Size::RMax(REFERENCE_R_MAX_M);

/// The size at which a surface's physical rolling-resistance length is turned into δ / R_max by
/// the drop presets when the stone's real size is not given: R_max = 1 cm (a die, a pebble).
pub const REFERENCE_R_MAX_M: f64 = 0.01;

/// Plausible real R_max (m) of a stone, a pebble or a field rock: from 2 mm (a 4 mm granule, the
/// smallest gravel on Wentworth's scale) to 20 m (a 40 m boulder, the size of the largest known
/// glacial erratics). A size outside is flagged ([`RealSize::implausibility`]), not refused: an
/// asteroid model is legitimately km-sized, and a unit slip (metres for millimetres) is not.
pub const PLAUSIBLE_R_MAX_M: [f64; 2] = [2e-3, 20.0];

/// Where a stone's real size came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SizeSource {
    /// Given by the caller: a length unit or R_max.
    Given,
    /// Known without being given: the bundled stone, whose coordinates are millimetres.
    Known,
    /// Neither given nor known: the command's default, stated by [`RealSize::assumption`].
    Assumed,
}

/// A stone's real size, and how it was decided ([`RealSize::resolve`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RealSize {
    /// Metres per mesh unit.
    pub length_unit_m: f64,
    /// R_max in metres: as given when given as R_max, else R_max in mesh units × the unit.
    pub r_max_m: f64,
    /// Given, known or assumed.
    pub source: SizeSource,
    /// The size as it was given, known or assumed (a unit, or R_max).
    pub as_decided: Size,
}

impl RealSize {
    /// The real size of the mesh named `name` (its report name: [`bundled::NAME`] for the bundled
    /// stone) whose R_max is `r_max` mesh units: `given` if any, else the bundled stone's
    /// millimetres, else `assumed` ([`ASSUMED_UNIT`] or [`ASSUMED_DROP_SIZE`]). A given size that
    /// is not a positive finite length is refused.
    pub fn resolve(name: &str, r_max: f64, given: Option<Size>, assumed: Size) -> Result<RealSize> {
        let (as_decided, source) = match given {
            Some(s) => (s, SizeSource::Given),
            None if bundled::is_bundled(name) => (Size::Unit(bundled::LENGTH_UNIT_M), SizeSource::Known),
            None => (assumed, SizeSource::Assumed),
        };
        let length_unit_m = as_decided.length_unit_m(r_max)?;
        let r_max_m = match as_decided {
            Size::RMax(r) => r,
            Size::Unit(u) => r_max * u,
        };
        Ok(RealSize { length_unit_m, r_max_m, source, as_decided })
    }

    /// Was the size assumed (neither given nor known)?
    pub fn assumed(&self) -> bool {
        self.source == SizeSource::Assumed
    }

    /// Is R_max within [`PLAUSIBLE_R_MAX_M`]?
    pub fn plausible(&self) -> bool {
        (PLAUSIBLE_R_MAX_M[0]..=PLAUSIBLE_R_MAX_M[1]).contains(&self.r_max_m)
    }

    /// For an assumed size, what was assumed for the mesh `name` and what it implies, e.g.
    /// "rock.ply: its length unit is not known; assuming metres (R_max = 178.3 m). The result
    /// depends on the real size (…)". The caller adds how to give it in its own words.
    pub fn assumption(&self, name: &str) -> Option<String> {
        if !self.assumed() {
            return None;
        }
        let what = match self.as_decided {
            Size::Unit(u) => format!(
                "its length unit is not known; assuming {} (R_max = {})",
                unit_name(u),
                format_length(self.r_max_m)
            ),
            Size::RMax(_) => format!(
                "its real size is not known; assuming R_max = {} (the drop presets' reference size)",
                format_length(self.r_max_m)
            ),
        };
        Some(format!(
            "{name}: {what}. The result depends on the real size (the rolling resistance δ/R_max; \
             under shaking, also the real frequencies of the motion)"
        ))
    }

    /// For a size outside [`PLAUSIBLE_R_MAX_M`], the warning that names it and the range, e.g.
    /// "rock.ply: R_max = 178.3 m is outside the plausible sizes of a stone, a pebble or a field
    /// rock (R_max 2 mm to 20 m)".
    pub fn implausibility(&self, name: &str) -> Option<String> {
        if self.plausible() {
            return None;
        }
        Some(format!(
            "{name}: R_max = {} is outside the plausible sizes of a stone, a pebble or a field rock (R_max {} to {}); \
             check its length unit",
            format_length(self.r_max_m),
            format_length(PLAUSIBLE_R_MAX_M[0]),
            format_length(PLAUSIBLE_R_MAX_M[1])
        ))
    }
}

/// The name of a length unit of `u` metres ("metres", "millimetres", or "1 unit = 0.0254 m").
fn unit_name(u: f64) -> String {
    match u {
        1e-3 => "millimetres".into(),
        1e-2 => "centimetres".into(),
        1.0 => "metres".into(),
        1e3 => "kilometres".into(),
        _ => format!("1 unit = {u} m"),
    }
}

/// A length in metres with four significant digits in km, m or mm ("178.3 m", "178.3 mm",
/// "2 mm").
pub fn format_length(m: f64) -> String {
    let (v, unit) = match m.abs() {
        x if x >= 1e3 => (m / 1e3, "km"),
        x if x >= 1.0 => (m, "m"),
        x if x >= 1e-3 || x == 0.0 => (m * 1e3, "mm"),
        _ => (m * 1e6, "µm"),
    };
    if !v.is_finite() {
        return format!("{m} m");
    }
    let digits = (3 - v.abs().log10().floor() as i32).clamp(0, 3) as usize;
    let s = format!("{v:.digits$}");
    let s = if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s };
    format!("{s} {unit}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_read_with_four_digits() {
        assert_eq!(format_length(178.323), "178.3 m");
        assert_eq!(format_length(0.178323), "178.3 mm");
        assert_eq!(format_length(0.01), "10 mm");
        assert_eq!(format_length(2e-3), "2 mm");
        assert_eq!(format_length(20.0), "20 m");
        assert_eq!(format_length(1234.6), "1.235 km");
    }

    #[test]
    fn the_size_is_given_known_or_assumed_and_an_assumed_or_implausible_one_is_said() {
        let bundled = RealSize::resolve(bundled::NAME, 178.323, None, ASSUMED_UNIT).unwrap();
        assert_eq!((bundled.source, bundled.length_unit_m), (SizeSource::Known, 1e-3));
        assert!((bundled.r_max_m - 0.178323).abs() < 1e-12);
        assert_eq!((bundled.assumption(bundled::NAME), bundled.implausibility(bundled::NAME)), (None, None));
        let copy = RealSize::resolve("mystone.ply", 178.323, None, ASSUMED_UNIT).unwrap();
        assert_eq!((copy.source, copy.r_max_m), (SizeSource::Assumed, 178.323));
        let note = copy.assumption("mystone.ply").unwrap();
        assert!(
            note.starts_with("mystone.ply: its length unit is not known; assuming metres (R_max = 178.3 m)"),
            "{note}"
        );
        let warning = copy.implausibility("mystone.ply").unwrap();
        assert!(warning.contains("R_max = 178.3 m") && warning.contains("(R_max 2 mm to 20 m)"), "{warning}");
        let given = RealSize::resolve("mystone.ply", 178.323, Some(Size::Unit(1e-3)), ASSUMED_UNIT).unwrap();
        assert_eq!((given.source, given.assumption("mystone.ply")), (SizeSource::Given, None));
        // A given size is flagged too when it is implausible (the bundled stone in metres).
        let metres = RealSize::resolve(bundled::NAME, 178.323, Some(Size::Unit(1.0)), ASSUMED_UNIT).unwrap();
        assert!(metres.implausibility("x").is_some() && metres.assumption("x").is_none());
        let die = RealSize::resolve("die.stl", 7.0, None, ASSUMED_DROP_SIZE).unwrap();
        assert_eq!((die.r_max_m, die.length_unit_m), (0.01, 0.01 / 7.0));
        assert!(die.assumption("die.stl").unwrap().contains("assuming R_max = 10 mm"));
        // The bounds are the range's, inclusive.
        let at = |r: f64| RealSize::resolve("x", 1.0, Some(Size::RMax(r)), ASSUMED_UNIT).unwrap().plausible();
        assert_eq!([at(1.9e-3), at(2e-3), at(20.0), at(20.1)], [false, true, true, false]);
        assert!(RealSize::resolve("x", 1.0, Some(Size::RMax(-1.0)), ASSUMED_UNIT).is_err());
    }
}
