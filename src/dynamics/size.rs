//! The real size of a stone: the one place every dynamics command and the Python binding decide
//! it, and the conversion of options given in real units into the scaled frame the engine runs in.
//!
//! A mesh's coordinates carry no unit, but a dynamic result does depend on the real size: the
//! contact's rolling-resistance length δ is divided by R_max, and a ground motion's real
//! frequencies meet the stone at √R_max (every other group is Froude-invariant, see
//! [`crate::dynamics::engine::params`]). The static pipeline (equilibria, flocks, ν, basins) does
//! not. So the size is either **given** (a length unit, [`crate::mesh::unit`], or R_max) or
//! **known** (the bundled stone is in millimetres); otherwise a dynamic run is refused
//! ([`Error::SizeUnknown`]) rather than run at a guess. No one guess is right: scans of dice and
//! pebbles come in millimetres, field scans in metres, and a die taken for metres rolls as an
//! 8 m boulder with a rolling resistance a thousand times too small for it. Asking costs one
//! option; a wrong guess silently changes the answer. [`RealSize::implausibility`] still flags a
//! size outside [`PLAUSIBLE_R_MAX_M`], however it was decided.
//!
//! Options of the commands are given in real units for the stone's real size (s, m/s, rad/s,
//! Hz, 1/s; rolling resistance in mm): [`RealSize::scaled`] turns them into the numbers of the
//! scaled body (R_max = 1 m, g = 9.81 m/s²) the engine's parameters hold, [`RealSize::real`]
//! back for printing.

use crate::mesh::unit::LengthUnit;
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
        match self {
            Size::Unit(u) => Ok(LengthUnit::metres(u)?.metres),
            Size::RMax(r) if r > 0.0 && r.is_finite() && (r / r_max).is_finite() && r / r_max > 0.0 => Ok(r / r_max),
            Size::RMax(r) => Err(Error::parameter("size", r, "a positive length in metres (R_max)")),
        }
    }
}

/// The size at which a surface's physical rolling-resistance length is turned into δ / R_max by
/// the library's parameter defaults when no size is given to them
/// ([`crate::dynamics::drops::params::Preset::params`]): R_max = 1 cm (a die, a pebble). The
/// commands always pass the stone's real size.
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
    /// millimetres, else refused ([`Error::SizeUnknown`]). A given size that is not a positive
    /// finite length is refused.
    pub fn resolve(name: &str, r_max: f64, given: Option<Size>) -> Result<RealSize> {
        let (as_decided, source) = match given {
            Some(s) => (s, SizeSource::Given),
            None if bundled::is_bundled(name) => (Size::Unit(bundled::LENGTH_UNIT_M), SizeSource::Known),
            None => return Err(Error::SizeUnknown { mesh: name.to_string(), one_stone: true }),
        };
        let length_unit_m = as_decided.length_unit_m(r_max)?;
        let r_max_m = match as_decided {
            Size::RMax(r) => r,
            Size::Unit(u) => r_max * u,
        };
        Ok(RealSize { length_unit_m, r_max_m, source, as_decided })
    }

    /// Was the size assumed? Never: a size is given or known ([`RealSize::resolve`]). Reports
    /// keep their `size_assumed` field (always false) for the readers of earlier files, which
    /// could assume one.
    pub fn assumed(&self) -> bool {
        false
    }

    /// Is R_max within [`PLAUSIBLE_R_MAX_M`]?
    pub fn plausible(&self) -> bool {
        (PLAUSIBLE_R_MAX_M[0]..=PLAUSIBLE_R_MAX_M[1]).contains(&self.r_max_m)
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

    /// `value`, given in real SI units for this stone, as the number the scaled body's parameters
    /// hold (R_max = 1 m, g = 9.81 m/s², [`crate::dynamics::engine::params`]): Froude scaling
    /// with L = R_max in metres,
    ///
    /// ```text
    /// time, speed: x / √L     rate (spin, damping, frequency): x · √L     length: x / L
    /// ```
    pub fn scaled(&self, dimension: Dimension, value: f64) -> f64 {
        let l = self.r_max_m;
        match dimension {
            Dimension::Time | Dimension::Speed => value / l.sqrt(),
            Dimension::Rate => value * l.sqrt(),
            Dimension::Length => value / l,
        }
    }

    /// The inverse of [`RealSize::scaled`]: a scaled parameter in real SI units for this stone.
    pub fn real(&self, dimension: Dimension, scaled: f64) -> f64 {
        let l = self.r_max_m;
        match dimension {
            Dimension::Time | Dimension::Speed => scaled * l.sqrt(),
            Dimension::Rate => scaled / l.sqrt(),
            Dimension::Length => scaled * l,
        }
    }
}

/// The physical dimension of a run parameter given in real units ([`RealSize::scaled`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// Seconds: time step, time caps, rest and settling windows.
    Time,
    /// Metres per second.
    Speed,
    /// Per second: spin (rad/s), damping rates (1/s), frequencies (Hz).
    Rate,
    /// Metres: the rolling-resistance and torsional-friction lengths.
    Length,
}

/// The dimension of the run parameter `name` (a field of the parameter structs:
/// [`crate::dynamics::engine::params`], [`crate::dynamics::drops::params`],
/// [`crate::dynamics::resting::RestingParams`]); None for a dimensionless one (friction,
/// restitution, solver iterations, heights in R_max…).
pub fn dimension(name: &str) -> Option<Dimension> {
    match name {
        "dt" | "max_time" | "rest_time" | "settle_time" | "hold_time" => Some(Dimension::Time),
        "horizontal_speed" | "rest_linear_speed" => Some(Dimension::Speed),
        "spin" | "rest_angular_speed" | "linear_damping" | "angular_damping" | "contact_frequency" => {
            Some(Dimension::Rate)
        }
        "rolling_resistance" | "torsional_friction" => Some(Dimension::Length),
        _ => None,
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
    fn the_size_is_given_or_known_and_a_mesh_without_one_is_refused() {
        let bundled = RealSize::resolve(bundled::NAME, 178.323, None).unwrap();
        assert_eq!((bundled.source, bundled.length_unit_m), (SizeSource::Known, 1e-3));
        assert!((bundled.r_max_m - 0.178323).abs() < 1e-12);
        assert_eq!(bundled.implausibility(bundled::NAME), None);
        match RealSize::resolve("mystone.ply", 178.323, None).unwrap_err() {
            e @ Error::SizeUnknown { .. } => {
                let text = e.to_string();
                assert!(text.starts_with("mystone.ply: its length unit is not known"), "{text}");
                assert!(text.contains("give length_unit (mm, cm, m, km, in") && text.contains("or size"), "{text}");
                let keywords = e.spelled(&|n: &str| format!("{n}="));
                assert!(
                    keywords.contains("give length_unit= (mm") && keywords.contains("or size= (R_max"),
                    "{keywords}"
                );
            }
            e => panic!("{e}"),
        }
        let given = RealSize::resolve("mystone.ply", 178.323, Some(Size::Unit(1e-3))).unwrap();
        assert_eq!((given.source, given.assumed()), (SizeSource::Given, false));
        // A given size is flagged when it is implausible (the bundled stone in metres).
        let metres = RealSize::resolve(bundled::NAME, 178.323, Some(Size::Unit(1.0))).unwrap();
        let warning = metres.implausibility("x").unwrap();
        assert!(warning.contains("R_max = 178.3 m") && warning.contains("(R_max 2 mm to 20 m)"), "{warning}");
        let die = RealSize::resolve("die.stl", 7.0, Some(Size::RMax(0.01))).unwrap();
        assert_eq!((die.r_max_m, die.length_unit_m), (0.01, 0.01 / 7.0));
        // The bounds are the range's, inclusive.
        let at = |r: f64| RealSize::resolve("x", 1.0, Some(Size::RMax(r))).unwrap().plausible();
        assert_eq!([at(1.9e-3), at(2e-3), at(20.0), at(20.1)], [false, true, true, false]);
        assert!(RealSize::resolve("x", 1.0, Some(Size::RMax(-1.0))).is_err());
        assert!(RealSize::resolve("x", 1.0, Some(Size::Unit(0.0))).is_err());
    }

    #[test]
    fn real_units_scale_as_froude_says_and_back() {
        // A die of R_max = 1 cm: a spin of 5 rad/s of the scaled body is 50 rad/s, 1/120 s of it
        // 0.833 ms, 1 m/s of it 0.1 m/s, δ = 0.2 mm is 0.02 R_max.
        let die = RealSize::resolve("die.stl", 1.0, Some(Size::RMax(0.01))).unwrap();
        assert!((die.scaled(Dimension::Rate, 50.0) - 5.0).abs() < 1e-12);
        assert!((die.scaled(Dimension::Time, 1.0 / 1200.0) - 1.0 / 120.0).abs() < 1e-15);
        assert!((die.scaled(Dimension::Speed, 0.1) - 1.0).abs() < 1e-12);
        assert!((die.scaled(Dimension::Length, 2e-4) - 0.02).abs() < 1e-15);
        for d in [Dimension::Time, Dimension::Speed, Dimension::Rate, Dimension::Length] {
            assert!((die.real(d, die.scaled(d, 0.37)) - 0.37).abs() < 1e-15, "{d:?}");
        }
        assert_eq!(dimension("dt"), Some(Dimension::Time));
        assert_eq!(dimension("contact_frequency"), Some(Dimension::Rate));
        assert_eq!(dimension("rolling_resistance"), Some(Dimension::Length));
        assert_eq!((dimension("friction"), dimension("height")), (None, None));
    }
}
