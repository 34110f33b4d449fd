//! The length unit of a mesh's coordinates: how many metres one unit is.
//!
//! Mesh formats carry no unit (STL, OBJ and PLY store bare numbers), so the caller says it. One
//! set of names is read everywhere — every command's `--length-unit` and the Python binding's
//! `length_unit=`: `mm`, `cm`, `m`, `km`, `in`, or a positive number of metres per mesh unit
//! (`0.3048` for feet). The static pipeline does not depend on it (it only labels lengths); the
//! dynamics do, through the stone's real size ([`crate::dynamics::size`]).

use crate::{Error, Result};

/// The names a length unit may be given by, with their length in metres.
pub const NAMES: [(&str, f64); 5] = [("mm", 1e-3), ("cm", 1e-2), ("m", 1.0), ("km", 1e3), ("in", 0.0254)];

/// The length of one mesh unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LengthUnit {
    /// Metres per mesh unit (positive, finite).
    pub metres: f64,
}

impl LengthUnit {
    /// A unit of `metres` metres, refused unless positive and finite.
    pub fn metres(metres: f64) -> Result<LengthUnit> {
        if metres > 0.0 && metres.is_finite() {
            Ok(LengthUnit { metres })
        } else {
            Err(Error::parameter("length_unit", metres, expected()))
        }
    }

    /// The unit's short name (`mm`, `in`…) when it has one.
    pub fn name(&self) -> Option<&'static str> {
        NAMES.iter().find(|(_, m)| *m == self.metres).map(|(n, _)| *n)
    }

    /// The label of lengths in this unit: its name (`mm`), else the unit spelled as a length in
    /// parentheses (`(0.3048 m)`), so that an area reads `12 (0.3048 m)²`.
    pub fn label(&self) -> String {
        match self.name() {
            Some(n) => n.to_string(),
            None => format!("({} m)", self.metres),
        }
    }
}

impl std::str::FromStr for LengthUnit {
    type Err = Error;

    /// `mm`, `cm`, `m`, `km`, `in` or a positive number of metres per mesh unit.
    fn from_str(s: &str) -> Result<LengthUnit> {
        let t = s.trim();
        if let Some((_, m)) = NAMES.iter().find(|(n, _)| *n == t) {
            return Ok(LengthUnit { metres: *m });
        }
        match t.parse::<f64>() {
            Ok(v) => LengthUnit::metres(v).map_err(|_| Error::parameter("length_unit", format!("{s:?}"), expected())),
            Err(_) => Err(Error::parameter("length_unit", format!("{s:?}"), expected())),
        }
    }
}

/// What a length unit must be, as the error messages say it.
fn expected() -> String {
    let names: Vec<&str> = NAMES.iter().map(|(n, _)| *n).collect();
    format!("{} or a positive number of metres per mesh unit", names.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_numbers_are_read_and_anything_else_is_refused_with_the_list() {
        let m = |s: &str| s.parse::<LengthUnit>().map(|u| u.metres);
        assert_eq!([m("mm"), m("cm"), m("m"), m("km"), m("in")].map(Result::unwrap), [1e-3, 1e-2, 1.0, 1e3, 0.0254]);
        assert_eq!(m(" 0.3048 ").unwrap(), 0.3048);
        for bad in ["meters", "ft", "-1", "0", "inf", "NaN", ""] {
            let e = m(bad).unwrap_err().to_string();
            assert!(e.starts_with("length_unit must be mm, cm, m, km, in or a positive number"), "{bad}: {e}");
        }
        assert_eq!("mm".parse::<LengthUnit>().unwrap().label(), "mm");
        assert_eq!("0.3048".parse::<LengthUnit>().unwrap().label(), "(0.3048 m)");
        assert_eq!("0.001".parse::<LengthUnit>().unwrap().label(), "mm");
    }
}
