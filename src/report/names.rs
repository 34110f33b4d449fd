//! User-facing names of every enum the CLI, the summaries and `report.html` print, and the
//! small wording helpers they share (plurals, units, plain numbers). Rust's `Debug` names
//! (`ArcLength`, `Random { seed: 1 }`, `PaperDefault`) never reach a person: every summary goes
//! through the [`std::fmt::Display`] impls here (or the types' own `name()`), and
//! `tests/user_strings.rs` checks every value.

use crate::dynamics::certificate::CertificateMode;
use crate::dynamics::drops::params::SpinDistribution;
use crate::dynamics::pushes::Family;
use crate::dynamics::resting::outcome::Outcome;
use crate::dynamics::stone::Class;
use crate::equilibria::Kind;
use crate::hierarchy::NuSource;
use crate::planar::Sampling;
use std::fmt;

impl Kind {
    /// Every kind of micro-equilibrium, in the order stable, unstable, saddle (S, U, H).
    pub const ALL: [Kind; 3] = [Kind::Stable, Kind::Unstable, Kind::Saddle];

    /// The user-facing name: "stable", "unstable", "saddle".
    pub fn name(self) -> &'static str {
        match self {
            Kind::Stable => "stable",
            Kind::Unstable => "unstable",
            Kind::Saddle => "saddle",
        }
    }

    /// The paper's letter: S (stable), U (unstable), H (saddle).
    pub fn letter(self) -> &'static str {
        match self {
            Kind::Stable => "S",
            Kind::Unstable => "U",
            Kind::Saddle => "H",
        }
    }

    /// Where on the hull a micro-equilibrium of this kind sits: a stable facet, an unstable
    /// vertex, a saddle edge.
    pub fn site_name(self) -> &'static str {
        match self {
            Kind::Stable => "facet",
            Kind::Unstable => "vertex",
            Kind::Saddle => "edge",
        }
    }
}

impl fmt::Display for Kind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl NuSource {
    /// Every source of the macro-scale ν.
    pub const ALL: [NuSource; 3] = [NuSource::User, NuSource::Plateau, NuSource::PaperDefault];
}

impl fmt::Display for NuSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            NuSource::User => "set by --nu",
            NuSource::Plateau => "middle of the plateau",
            NuSource::PaperDefault => "no clear plateau: the paper's hand experimenter",
        })
    }
}

impl fmt::Display for Sampling {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Sampling::ArcLength => f.write_str("equal arc lengths"),
            Sampling::Angle => f.write_str("equal parameter angles"),
            Sampling::Random { seed } => write!(f, "random arc-length positions, seed {seed}"),
        }
    }
}

impl Class {
    /// Both static classes.
    pub const ALL: [Class; 2] = [Class::Regular, Class::Rocking];
}

impl fmt::Display for Class {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl Family {
    /// Both perturbation families.
    pub const ALL: [Family; 2] = [Family::Push, Family::Spin];
}

impl fmt::Display for Family {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl Outcome {
    /// Every outcome of a perturbation or shaking trial.
    pub const ALL: [Outcome; 3] = [Outcome::Same, Outcome::SameFlock, Outcome::Toppled];

    /// The user-facing name, as in `trials.csv`: "same", "same-flock", "toppled".
    pub fn name(self) -> &'static str {
        match self {
            Outcome::Same => "same",
            Outcome::SameFlock => "same-flock",
            Outcome::Toppled => "toppled",
        }
    }
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl fmt::Display for CertificateMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl SpinDistribution {
    /// Both spin laws.
    pub const ALL: [SpinDistribution; 2] = [SpinDistribution::Fixed, SpinDistribution::Gaussian];

    /// How `--spin` is read under this law: "exact" or "rms, Gaussian".
    pub fn name(self) -> &'static str {
        match self {
            SpinDistribution::Fixed => "exact",
            SpinDistribution::Gaussian => "rms, Gaussian",
        }
    }
}

impl fmt::Display for SpinDistribution {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// "1 drop", "2 drops": `n` and the singular or plural noun.
pub fn plural(n: impl Into<u64>, one: &str, many: &str) -> String {
    let n = n.into();
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The length unit of a mesh's coordinates, as the user names it (`--unit mm`), or unknown:
/// every summary labels volume (unit³), area (unit²) and lengths (G, R, axes) with it, or says
/// "mesh units".
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Unit(pub Option<String>);

impl Unit {
    /// A unit named by the user (any non-empty word: mm, cm, m, in, km, …).
    pub fn named(name: &str) -> Unit {
        let t = name.trim();
        Unit(if t.is_empty() { None } else { Some(t.to_string()) })
    }

    /// "mm", or "mesh units" when unknown.
    pub fn length(&self) -> String {
        self.0.clone().unwrap_or_else(|| "mesh units".into())
    }

    /// "mm²", or "mesh units²".
    pub fn area(&self) -> String {
        format!("{}²", self.length())
    }

    /// "mm³", or "mesh units³".
    pub fn volume(&self) -> String {
        format!("{}³", self.length())
    }
}

/// A number for a person to read: a plain decimal with `sig` significant digits when its size
/// is between 10⁻³ and 10⁷ ("3648619", "725.97", "0.0035"), else scientific with a ×10ⁿ
/// ("1.2×10⁻⁹"); infinite values as "∞".
pub fn number(x: f64, sig: usize) -> String {
    if x == 0.0 {
        return "0".into();
    }
    if x.is_nan() {
        return "NaN".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "∞".into() } else { "−∞".into() };
    }
    let e = x.abs().log10().floor() as i32;
    if (-3..7).contains(&e) {
        let digits = (sig as i32 - 1 - e).max(0) as usize;
        let s = format!("{x:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let s = format!("{:.*e}", sig.saturating_sub(1), x);
        let (m, ex) = s.split_once('e').unwrap_or((&s, "0"));
        let m = if m.contains('.') { m.trim_end_matches('0').trim_end_matches('.') } else { m };
        let ex: i32 = ex.parse().unwrap_or(0);
        format!("{m}×10{}", superscript(ex))
    }
}

fn superscript(e: i32) -> String {
    const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    e.to_string().chars().map(|c| c.to_digit(10).map_or('⁻', |d| SUP[d as usize])).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_plain_where_people_read_them() {
        assert_eq!(number(3_648_619.4, 7), "3648619");
        assert_eq!(number(725.973_6, 6), "725.974");
        assert_eq!(number(0.0035, 3), "0.0035");
        assert_eq!(number(1.2e-9, 3), "1.2×10⁻⁹");
        assert_eq!(number(3.0e12, 4), "3×10¹²");
        assert_eq!(number(f64::INFINITY, 4), "∞");
        assert_eq!(plural(1u64, "drop", "drops"), "1 drop");
        assert_eq!(plural(0u64, "drop", "drops"), "0 drops");
        assert_eq!(Unit::named("mm").volume(), "mm³");
        assert_eq!(Unit::default().area(), "mesh units²");
    }
}
