//! # The plateau rule (automatic macro scale)
//!
//! The paper reads the macro scale off "a sudden jump followed by a plateau" of n(ν). The rule:
//!
//! 1. **Candidates** are the steps above the micro scale that reach the macro scale: steps
//!    [lo, hi] starting at a cancellation level (lo ≥ ν₁, lo > 0), ending at most at v_max, and
//!    with hi ≥ [`PLATEAU_MACRO_FRACTION`] · v_max (1 % of the total relief: a plateau is ended by
//!    the cancellation of a macro-equilibrium, not by another micro one). The **terminal** step
//!    (S = U = 1, H = 0, the topological minimum every hierarchy ends in) is not a candidate.
//! 2. The length of a step is log10(hi/lo), in decades; steps between levels equal up to
//!    rounding (relative difference ≤ [`LEVEL_RESOLUTION`]) have length 0.
//! 3. The **plateau** is the longest candidate (ties: the lower one), reported as a [`Plateau`]
//!    with its range, `decades`, counts and `clarity` = decades / decades of the second-longest
//!    candidate (∞ if there is none or it has zero length; serialised as `null`).
//!    `clear` = decades ≥ [`PLATEAU_MIN_DECADES`] (0.5) **and** clarity ≥
//!    [`PLATEAU_MIN_CLARITY`] (2): a long run of constant N, at least twice as long as any other.
//!    Its representative ν is the geometric midpoint [`Plateau::nu`] = √(lo·hi).
//! 4. If no candidate has positive length (G(0) has no micro scale: e.g. an ellipse polygon fine
//!    enough to have exactly its 2 + 2 smooth equilibria, a regular polygon whose cancellations
//!    all tie), **G(0) is its own macro scale**: the plateau is the first step [0, ν₁], with
//!    decades = clarity = ∞, clear, and ν = 0. A hierarchy without any cancellation has no plateau
//!    (`None`).
//!
//! Why not simply "the longest step above ν₁"? The lowest levels are a few extreme order
//! statistics of the micro weights (the flattest spots) and are sparse in log ν: the step between
//! the first two levels, with almost every micro-equilibrium still present, often spans 1–3
//! decades. Measured: on polygons inscribed in a circle with 100–1000 random vertices (the planar
//! sphere-like body) such steps came out as "clear" plateaus for 7–11 of 20 polygons, and on
//! noisy triaxial ellipsoids they beat the real (2, 2, 2) plateau's clarity. Requiring the
//! plateau to end at the macro scale removes them (0 of 20 circle-like polygons with ≥ 100
//! vertices and ≤ 1 % noise; see `tests/planar.rs`), while keeping plateaus that follow only a
//! couple of micro cancellations (a noisy box: 2 micro and 12 macro cancellations). A rule
//! "above the median level" was tried and rejected for that reason. The terminal step is
//! excluded because its length measures only how far the last surviving pair is from v_max, not
//! a separation of scales, and no homogeneous planar body (nor any pebble) has S = U = 1 at the
//! macro scale. Macro-equilibria whose cancellation costs less than 1 % of v_max are read as
//! micro. A body without separated scales gets `clear = false`, and callers must say so rather
//! than read flocks off it as if they were real.
//!

use super::{Counts, Flocks, Hierarchy, Step};
use serde::{Serialize, Serializer};

/// The automatic macro scale: the longest step of N(ν) in log ν above the micro scale (see the
/// module docs for the rule).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Plateau {
    /// Lower end of the plateau's ν interval.
    pub nu_lo: f64,
    /// Upper end of the plateau's ν interval.
    pub nu_hi: f64,
    /// log10(nu_hi / nu_lo) (∞, serialised as null, when G(0) is its own macro scale).
    #[serde(serialize_with = "finite_or_null")]
    pub decades: f64,
    /// Counts of G(ν) on the plateau.
    pub counts: Counts,
    /// decades / decades of the second-longest step (∞, serialised as null, if none).
    #[serde(serialize_with = "finite_or_null")]
    pub clarity: f64,
    /// decades ≥ [`PLATEAU_MIN_DECADES`] and clarity ≥ [`PLATEAU_MIN_CLARITY`].
    pub clear: bool,
}

/// A plateau shorter than this (in decades of ν) is not clear.
pub const PLATEAU_MIN_DECADES: f64 = 0.5;
/// Levels closer than this (relative) are equal up to rounding: a step between them has zero
/// length for the plateau rule (a regular polygon's ties, exact symmetries).
pub const LEVEL_RESOLUTION: f64 = 1e-9;
/// A plateau must reach the macro scale: its upper end is at least this fraction of v_max.
pub const PLATEAU_MACRO_FRACTION: f64 = 0.01;
/// A plateau less than this many times longer than the runner-up is not clear.
pub const PLATEAU_MIN_CLARITY: f64 = 2.0;

/// The hand experimenter's ν of the paper (§3): the macro scale when n(ν) has no clear plateau.
pub const PAPER_NU: f64 = 0.0035;

/// Where the macro-scale ν came from.
#[derive(Clone, Copy, Debug, Serialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum NuSource {
    /// Given by the user (`--nu`).
    User,
    /// The midpoint (in log ν) of a clear plateau of n(ν).
    Plateau,
    /// No clear plateau: the paper's hand-experiment value [`PAPER_NU`].
    PaperDefault,
}

/// A hierarchy read at its macro scale ([`Hierarchy::macro_scale`]).
#[derive(Clone, Debug)]
pub struct MacroScale {
    /// The macro-scale ν.
    pub nu: f64,
    /// Where ν came from.
    pub source: NuSource,
    /// The longest step of n(ν), if any.
    pub plateau: Option<Plateau>,
    /// S(ν), U(ν), H(ν).
    pub counts: Counts,
    /// The flocks at ν.
    pub flocks: Flocks,
    /// The rocking equilibria at ν ([`Hierarchy::rocking_at`]).
    pub rocking: Vec<usize>,
}

/// The macro-scale ν, one rule for the 3D and the planar case: the user's, else the midpoint of
/// a clear `plateau`, else [`PAPER_NU`] (an unclear plateau's own ν is not a macro scale).
pub fn macro_nu(user: Option<f64>, plateau: Option<Plateau>) -> (f64, NuSource) {
    match (user, plateau) {
        (Some(nu), _) => (nu, NuSource::User),
        (None, Some(p)) if p.clear => (p.nu(), NuSource::Plateau),
        (None, _) => (PAPER_NU, NuSource::PaperDefault),
    }
}

fn finite_or_null<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    if x.is_finite() {
        s.serialize_f64(*x)
    } else {
        s.serialize_none()
    }
}

impl Plateau {
    /// The representative ν of the plateau: its geometric midpoint √(lo·hi).
    pub fn nu(&self) -> f64 {
        (self.nu_lo * self.nu_hi).sqrt()
    }
}

impl Hierarchy {
    /// The automatic macro scale (see the module docs for the rule), `None` without any
    /// cancellation.
    pub fn plateau(&self) -> Option<Plateau> {
        let steps = self.staircase();
        if steps.len() < 2 {
            return None;
        }
        let terminal = |s: &Step| s.counts.stable == 1 && s.counts.unstable == 1 && s.counts.saddle == 0;
        let nu_macro = PLATEAU_MACRO_FRACTION * self.v_max();
        let candidates: Vec<(Step, f64)> = steps
            .iter()
            .skip(1)
            .filter(|s| s.nu_lo > 0.0 && s.nu_hi >= nu_macro && !terminal(s))
            .map(|s| (*s, if s.nu_hi > s.nu_lo * (1.0 + LEVEL_RESOLUTION) { (s.nu_hi / s.nu_lo).log10() } else { 0.0 }))
            .collect();
        let mut best: Option<usize> = None;
        for (i, (_, d)) in candidates.iter().enumerate() {
            if best.is_none_or(|b| *d > candidates[b].1) {
                best = Some(i);
            }
        }
        let Some(b) = best.filter(|&b| candidates[b].1 > 0.0) else {
            // Nothing between the first level and the topological minimum: G(0) is its own
            // macro scale.
            let s = steps[0];
            return Some(Plateau {
                nu_lo: s.nu_lo,
                nu_hi: s.nu_hi,
                decades: f64::INFINITY,
                counts: s.counts,
                clarity: f64::INFINITY,
                clear: true,
            });
        };
        let (step, decades) = candidates[b];
        let second = candidates.iter().enumerate().filter(|(i, _)| *i != b).map(|(_, c)| c.1).fold(0.0, f64::max);
        let clarity = if second > 0.0 { decades / second } else { f64::INFINITY };
        Some(Plateau {
            nu_lo: step.nu_lo,
            nu_hi: step.nu_hi,
            decades,
            counts: step.counts,
            clarity,
            clear: decades >= PLATEAU_MIN_DECADES && clarity >= PLATEAU_MIN_CLARITY,
        })
    }

    /// The hierarchy read at its macro scale: ν by [`macro_nu`] (`user` first), and the plateau,
    /// counts, flocks and rocking equilibria there — what the 3D and the planar reports show.
    pub fn macro_scale(&self, user: Option<f64>) -> MacroScale {
        let plateau = self.plateau();
        let (nu, source) = macro_nu(user, plateau);
        MacroScale {
            nu,
            source,
            plateau,
            counts: self.counts_at(nu),
            flocks: self.flocks_at(nu),
            rocking: self.rocking_at(nu),
        }
    }
}
