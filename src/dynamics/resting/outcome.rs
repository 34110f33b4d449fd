//! What became of a stone that started at rest on a stable micro-equilibrium (pushed, spun or
//! shaken), and the statistics of many such runs on a grid of intensities: the outcome classes
//! ([`Outcome`], [`classify`]), one grid point's counts with 95 % Wilson intervals
//! ([`CurvePoint`]) and the intensity at which a probability reaches ½ ([`Threshold`]).
//!
//! The outcome rule is the one of every command: where a run ends is read from the static theory
//! (the stable facet of the quasi-static descent from the final down direction,
//! [`crate::dynamics::stone::Stone::rest`], or a certificate's decision), then compared with the start.

use crate::dynamics::stone::Stone;
use crate::stats::wilson;
use serde::{Deserialize, Serialize};

/// What became of a perturbed stone.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Outcome {
    /// Back on the micro-equilibrium it started from.
    Same,
    /// On another stable micro-equilibrium of the same flock (it rocked).
    SameFlock,
    /// In another flock (it toppled).
    Toppled,
}

/// Classify a final facet (or flock) relative to the start.
pub fn classify(stone: &Stone, start: usize, facet: Option<u32>, flock: usize) -> Outcome {
    let s = &stone.stable()[start];
    if facet == Some(s.facet) {
        Outcome::Same
    } else if flock == s.flock {
        Outcome::SameFlock
    } else {
        Outcome::Toppled
    }
}

/// The ε (or acceleration) at which a probability first reaches ½ on a grid.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", content = "value", rename_all = "lowercase")]
pub enum Threshold {
    /// Already ≥ ½ at the smallest grid value (the threshold is at most this).
    Below(f64),
    /// Interpolated between the two grid values around the crossing.
    At(f64),
    /// Never reached ½ on the grid (the threshold is above its largest value).
    Above(f64),
}

impl Threshold {
    /// The value (a bound for `Below` / `Above`).
    pub fn value(&self) -> f64 {
        match *self {
            Threshold::Below(x) | Threshold::At(x) | Threshold::Above(x) => x,
        }
    }

    /// The kind as a CSV writes it: "below", "at" or "above".
    pub fn kind_name(&self) -> &'static str {
        match self {
            Threshold::Below(_) => "below",
            Threshold::At(_) => "at",
            Threshold::Above(_) => "above",
        }
    }

    /// A threshold as a sortable number: its value where it is at most that (`Below`, `At`),
    /// ∞ where it lies above the grid (`Above`) or there is none; the order in which a smaller
    /// threshold means a less robust equilibrium.
    pub fn rank(t: Option<Threshold>) -> f64 {
        match t {
            Some(Threshold::Below(x) | Threshold::At(x)) => x,
            Some(Threshold::Above(_)) | None => f64::INFINITY,
        }
    }

    /// First crossing of ½ by `p` over the increasing grid `x`, interpolated linearly in p
    /// against log x (`log`) or x.
    pub fn crossing(x: &[f64], p: &[f64], log: bool) -> Option<Threshold> {
        let first = p.iter().position(|&v| v >= 0.5)?;
        if first == 0 {
            return Some(Threshold::Below(x[0]));
        }
        let (x0, x1, p0, p1) = (x[first - 1], x[first], p[first - 1], p[first]);
        let t = if p1 > p0 { (0.5 - p0) / (p1 - p0) } else { 1.0 };
        Some(Threshold::At(if log { (x0.ln() + t * (x1.ln() - x0.ln())).exp() } else { x0 + t * (x1 - x0) }))
    }

    /// As [`Threshold::crossing`], `Above(max x)` if it never crosses (None on an empty grid).
    pub fn of(x: &[f64], p: &[f64], log: bool) -> Option<Threshold> {
        Self::crossing(x, p, log).or_else(|| x.last().map(|&m| Threshold::Above(m)))
    }
}

/// Outcome counts at one grid value, with 95 % Wilson intervals.
#[derive(Clone, Debug, Serialize)]
pub struct CurvePoint {
    /// ε (perturbations) or peak ground acceleration in g (shaking).
    pub x: f64,
    /// Number of trials.
    pub n: u64,
    /// Trials that came back to the starting micro-equilibrium.
    pub same: u64,
    /// Trials that ended on another micro-equilibrium of the same flock.
    pub same_flock: u64,
    /// Trials that left the flock.
    pub toppled: u64,
    /// Trials that hit the time cap (classified from where they were).
    pub unsettled: u64,
    /// P(same): fraction of trials back on the starting micro-equilibrium.
    pub p_same: f64,
    /// 95 % Wilson interval of `p_same`.
    pub ci_same: (f64, f64),
    /// P(still in the flock) = P(same) + P(another micro-equilibrium of the flock).
    pub p_in_flock: f64,
    /// 95 % Wilson interval of `p_in_flock`.
    pub ci_in_flock: (f64, f64),
    /// P(toppled): fraction of trials that left the flock.
    pub p_toppled: f64,
    /// 95 % Wilson interval of `p_toppled`.
    pub ci_toppled: (f64, f64),
}

impl CurvePoint {
    /// Count the outcomes of trials at grid value `x`.
    pub fn count(x: f64, outcomes: impl Iterator<Item = (Outcome, bool)>) -> CurvePoint {
        let (mut n, mut same, mut same_flock, mut toppled, mut unsettled) = (0, 0, 0, 0, 0);
        for (o, settled) in outcomes {
            n += 1;
            unsettled += u64::from(!settled);
            match o {
                Outcome::Same => same += 1,
                Outcome::SameFlock => same_flock += 1,
                Outcome::Toppled => toppled += 1,
            }
        }
        let p = |k: u64| if n > 0 { k as f64 / n as f64 } else { f64::NAN };
        CurvePoint {
            x,
            n,
            same,
            same_flock,
            toppled,
            unsettled,
            p_same: p(same),
            ci_same: wilson(same, n, 1.96),
            p_in_flock: p(same + same_flock),
            ci_in_flock: wilson(same + same_flock, n, 1.96),
            p_toppled: p(toppled),
            ci_toppled: wilson(toppled, n, 1.96),
        }
    }
}

/// The outcome curve of one start over a grid of intensities, and its two thresholds.
#[derive(Clone, Debug)]
pub struct Curve {
    /// One point per grid value (empty if the stone does not stay at rest on its start).
    pub points: Vec<CurvePoint>,
    /// Where P(left the micro-equilibrium) first reaches ½.
    pub leave50: Option<Threshold>,
    /// Where P(toppled out of the flock) first reaches ½.
    pub topple50: Option<Threshold>,
}

impl Curve {
    /// Count `trials` — (grid value, outcome, settled) — at each value of `grid`, unless the stone
    /// does not stay at rest (`stays` false: no curve); thresholds interpolated in log x (`log`)
    /// or x ([`Threshold::of`]).
    pub fn of(grid: &[f64], stays: bool, trials: &[(f64, Outcome, bool)], log: bool) -> Curve {
        let points: Vec<CurvePoint> = if stays {
            grid.iter().map(|&x| CurvePoint::count(x, trials.iter().filter(|t| t.0 == x).map(|t| (t.1, t.2)))).collect()
        } else {
            Vec::new()
        };
        let x: Vec<f64> = points.iter().map(|c| c.x).collect();
        let leave: Vec<f64> = points.iter().map(|c| 1.0 - c.p_same).collect();
        let topple: Vec<f64> = points.iter().map(|c| c.p_toppled).collect();
        Curve { leave50: Threshold::of(&x, &leave, log), topple50: Threshold::of(&x, &topple, log), points }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thresholds_rank_by_what_they_bound_and_name_their_kind() {
        let (below, at, above) = (Threshold::Below(1e-6), Threshold::At(3e-4), Threshold::Above(1.0));
        assert_eq!([below, at, above].map(|t| t.kind_name()), ["below", "at", "above"]);
        // At most 10⁻⁶ and 3·10⁻⁴ rank as those values; above the grid or never: ∞.
        assert_eq!(
            [Some(below), Some(at), Some(above), None].map(Threshold::rank),
            [1e-6, 3e-4, f64::INFINITY, f64::INFINITY]
        );
    }
}
