//! What an ensemble's outcome depends on: P(overturn) with its Wilson interval ([`Probability`]),
//! and each uncertain input's rank correlation with the outcome ([`sensitivities`]: Spearman's ρ
//! for a linear input, the circular–linear correlation for the azimuth).

use crate::dynamics::shaking::ensemble::Draw;
use crate::dynamics::shaking::rock::RockRun;
use crate::dynamics::shaking::{Member, Uncertainty};
use crate::stats::wilson;
use serde::{Deserialize, Serialize};

/// How strongly one uncertain input goes with overturning (module docs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sensitivity {
    /// The input (`contact_tolerance`, `azimuth`, `sign`, `friction`, `restitution`,
    /// `rolling_resistance`, and with a drawn base `base_tan_alpha`, the member's static tipping
    /// threshold, and `base_depth`).
    pub input: String,
    /// `spearman` (rank correlation with the 0/1 outcome, in [−1, 1]) or `circular-linear`
    /// (Mardia's R, in [0, 1], for an azimuth over the whole circle).
    pub measure: String,
    /// The correlation; `None` when it is undefined (every member had the same outcome).
    pub correlation: Option<f64>,
}

/// P(overturn) of an ensemble with its interval.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Probability {
    /// Members run.
    pub members: usize,
    /// Members that came to rest before the time cap (the others are left out of P).
    pub settled: usize,
    /// Settled members that overturned.
    pub overturned: usize,
    /// overturned / settled (NaN-free: 0 when none settled, with the interval [0, 1]).
    pub p_overturn: f64,
    /// Wilson 95 % interval of P.
    pub interval95: [f64; 2],
}

impl Probability {
    /// P(overturn) over the settled runs of `runs`.
    pub fn of<'a>(runs: impl IntoIterator<Item = &'a RockRun>) -> Probability {
        let (mut members, mut settled, mut overturned) = (0, 0, 0);
        for r in runs {
            members += 1;
            settled += r.settled as usize;
            overturned += (r.settled && r.overturned) as usize;
        }
        let (lo, hi) = wilson(overturned as u64, settled as u64, 1.96);
        let p = if settled > 0 { overturned as f64 / settled as f64 } else { 0.0 };
        Probability { members, settled, overturned, p_overturn: p, interval95: [lo, hi] }
    }
}

/// The sensitivity of the outcome to every input that is uncertain in `u`, over the settled
/// members.
pub fn sensitivities(u: &Uncertainty, members: &[Member]) -> Vec<Sensitivity> {
    let settled: Vec<&Member> = members.iter().filter(|m| m.run.settled).collect();
    let y: Vec<f64> = settled.iter().map(|m| m.run.overturned as u8 as f64).collect();
    let column = |f: fn(&Draw) -> f64| settled.iter().map(|m| f(&m.draw)).collect::<Vec<f64>>();
    let rank = |input: &str, x: Vec<f64>| Sensitivity {
        input: input.into(),
        measure: "spearman".into(),
        correlation: spearman(&x, &y),
    };
    let mut out = Vec::new();
    if u.contact_tolerance_m.is_some() {
        out.push(rank("contact_tolerance", column(|d| d.contact_tolerance_m)));
    }
    if u.azimuth_unknown() {
        let theta = column(|d| d.azimuth_deg.to_radians());
        let r = circular_linear(&theta, &y);
        out.push(Sensitivity { input: "azimuth".into(), measure: "circular-linear".into(), correlation: r });
    } else if u.azimuth_deg.is_some() {
        out.push(rank("azimuth", column(|d| d.azimuth_deg)));
    }
    if u.random_sign {
        out.push(rank("sign", column(|d| d.sign)));
    }
    if u.friction.is_some() {
        out.push(rank("friction", column(|d| d.friction)));
    }
    if u.restitution.is_some() {
        out.push(rank("restitution", column(|d| d.restitution)));
    }
    if u.rolling_resistance_m.is_some() {
        out.push(rank("rolling_resistance", column(|d| d.rolling_resistance_m)));
    }
    if u.base.is_some() {
        out.push(rank("base_tan_alpha", column(|d| d.base.map_or(f64::NAN, |b| b.tan_alpha))));
        let depth = column(|d| d.base.map_or(f64::NAN, |b| b.depth_m));
        if depth.iter().any(|&x| x != depth[0]) {
            out.push(rank("base_depth", depth));
        }
    }
    out
}

/// Ranks from 1, ties given their average rank.
fn ranks(x: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..x.len()).collect();
    order.sort_by(|&a, &b| x[a].total_cmp(&x[b]));
    let mut r = vec![0.0; x.len()];
    let mut i = 0;
    while i < order.len() {
        let mut j = i;
        while j + 1 < order.len() && x[order[j + 1]] == x[order[i]] {
            j += 1;
        }
        let average = (i + j) as f64 / 2.0 + 1.0;
        for &k in &order[i..=j] {
            r[k] = average;
        }
        i = j + 1;
    }
    r
}

/// Pearson's correlation; `None` when either sample has no spread.
fn pearson(x: &[f64], y: &[f64]) -> Option<f64> {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    (sxx > 0.0 && syy > 0.0).then(|| (sxy / (sxx * syy).sqrt()).clamp(-1.0, 1.0))
}

/// Spearman's rank correlation (Pearson's on average ranks).
pub fn spearman(x: &[f64], y: &[f64]) -> Option<f64> {
    if x.len() != y.len() || x.len() < 2 {
        return None;
    }
    pearson(&ranks(x), &ranks(y))
}

/// Mardia's circular–linear correlation of a linear `y` with angles `theta` (rad):
/// R² = (r_yc² + r_ys² − 2 r_yc r_ys r_cs) / (1 − r_cs²), r the Pearson correlations of y, cos θ
/// and sin θ; R ∈ [0, 1].
pub fn circular_linear(theta: &[f64], y: &[f64]) -> Option<f64> {
    if theta.len() != y.len() || theta.len() < 3 {
        return None;
    }
    let c: Vec<f64> = theta.iter().map(|t| t.cos()).collect();
    let s: Vec<f64> = theta.iter().map(|t| t.sin()).collect();
    let (ryc, rys, rcs) = (pearson(y, &c)?, pearson(y, &s)?, pearson(&c, &s)?);
    let r2 = (ryc * ryc + rys * rys - 2.0 * ryc * rys * rcs) / (1.0 - rcs * rcs);
    r2.is_finite().then(|| r2.clamp(0.0, 1.0).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spearman_and_mardia_match_hand_values() {
        // Perfectly monotone, and with ties: average ranks.
        assert!(
            (spearman(&[1.0, 2.0, 3.0, 4.0], &[0.0, 0.0, 1.0, 1.0]).unwrap() - 0.894_427_190_999_915_9).abs() < 1e-12
        );
        assert_eq!(ranks(&[3.0, 1.0, 3.0, 2.0]), vec![3.5, 1.0, 3.5, 2.0]);
        assert_eq!(spearman(&[1.0, 2.0, 3.0], &[1.0, 1.0, 1.0]), None);
        // y = cos θ exactly: R = 1; y independent of a symmetric set of angles: R = 0.
        let theta: Vec<f64> = (0..36).map(|k| k as f64 * 10f64.to_radians()).collect();
        let y: Vec<f64> = theta.iter().map(|t| t.cos()).collect();
        assert!((circular_linear(&theta, &y).unwrap() - 1.0).abs() < 1e-12);
        let flat: Vec<f64> = theta.iter().enumerate().map(|(k, _)| (k % 2) as f64).collect();
        assert!(circular_linear(&theta, &flat).unwrap() < 0.05);
    }
}
