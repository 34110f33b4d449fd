//! The fit of the two-tolerance hand experimenter ([`HandExperimenter`]) to the hand columns
//! of Table 2, given the count curves of synthetic pebbles standing for each sample.
//!
//! With the two tolerances independent, E(S), σ(S) of every sample depend only on the stable
//! tolerance (ν̃_S, s_S) and E(U), σ(U) only on the unstable one, so the loss
//!
//! χ² = Σ_samples Σ_(E(S), E(U), σ(S), σ(U)) (model − hand)² / (se_hand² + se_model²)
//!
//! (the terms of [`chi2`](super::chi2), the model's moments those of
//! [`Moments::of_distributions`]) splits into a stable and an unstable part, each minimised over
//! its two parameters (log₁₀ ν̃, s): a coarse grid, then Nelder–Mead from its best point. The
//! errors of the four parameters come from the curvature of χ² at the minimum (covariance
//! 2·H⁻¹, inflated by s² = max(1, χ²/dof) as in [`fit_nu`](super::fit_nu())).
//!
//! The minimiser is written here rather than taken from an optimisation crate: the problems are
//! two-dimensional and smooth (the tolerance's normal smooths the step functions), and a
//! 40-line Nelder–Mead keeps a dependency tree out of the library for it.

use super::fit_nu::{chi2_terms, standard_errors, HandSample};
use super::hand::{CountDistribution, HandExperimenter, Tolerance};
use super::{CountCurve, Moments};
use crate::{Error, Result};
use rayon::prelude::*;
use serde::Serialize;

/// The moments a two-tolerance experimenter gives a population of count curves.
pub fn population_moments(curves: &[CountCurve], exp: &HandExperimenter) -> Moments {
    let d: Vec<CountDistribution> = curves.iter().map(|c| exp.counts(c)).collect();
    Moments::of_distributions(&d)
}

/// One count's step function, merged where the count does not change: `(hi, count)`, the count
/// holding for the previous `hi` < ν ≤ `hi` (the last `hi` is ∞).
type Steps = Vec<(f64, f64)>;

fn steps(curve: &CountCurve, f: fn(&crate::hierarchy::Counts) -> usize) -> Steps {
    let mut out: Steps = Vec::new();
    for (k, c) in curve.counts.iter().enumerate() {
        let hi = curve.levels.get(k).copied().unwrap_or(f64::INFINITY);
        let v = f(c) as f64;
        match out.last_mut() {
            Some(last) if last.1 == v => last.0 = hi,
            _ => out.push((hi, v)),
        }
    }
    out
}

/// [E, σ] of one count over a population under one tolerance (the mixture of
/// [`Moments::of_distributions`]).
fn mixture(pop: &[Steps], tol: &Tolerance) -> (f64, f64) {
    let (mut m1, mut m2) = (0.0, 0.0);
    for s in pop {
        let mut below = 0.0;
        for &(hi, v) in s {
            let c = tol.cdf(hi);
            let p = (c - below).max(0.0);
            below = c;
            m1 += p * v;
            m2 += p * v * v;
        }
    }
    let n = pop.len().max(1) as f64;
    let (m1, m2) = (m1 / n, m2 / n);
    (m1, (super::hand::bessel(pop.len()) * (m2 - m1 * m1)).max(0.0).sqrt())
}

/// The fit of one tolerance.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ToleranceFit {
    /// The fitted tolerance.
    pub tolerance: Tolerance,
    /// Standard error of log₁₀ ν̃.
    pub se_log10_median: f64,
    /// Standard error of the spread s (decades).
    pub se_sd_log10: f64,
    /// χ² of this count's terms (E and σ over the samples) at the fit.
    pub chi2: f64,
}

/// Model against hand for one sample.
#[derive(Clone, Debug, Serialize)]
pub struct SampleFit {
    /// Sample id.
    pub id: String,
    /// [E(S), E(U), σ(S), σ(U)] of the hand experiments.
    pub hand: [f64; 4],
    /// The model's moments (n: synthetic pebbles).
    pub model: Moments,
    /// z = (model − hand) / √(se_hand² + se_model²) of each statistic.
    pub z: [f64; 4],
    /// Σ z².
    pub chi2: f64,
}

impl SampleFit {
    /// Model against hand for a sample.
    pub fn of(h: &HandSample, model: Moments) -> SampleFit {
        let terms = chi2_terms(&h.hand, &h.standard_errors(), &model);
        let m = model.as_array();
        let z = std::array::from_fn(|k| (m[k] - h.hand[k]).signum() * terms[k].sqrt());
        SampleFit { id: h.id.clone(), hand: h.hand, model, z, chi2: terms.iter().sum() }
    }
}

/// The result of [`fit_hand`].
#[derive(Clone, Debug, Serialize)]
pub struct HandFit {
    /// The fitted experimenter.
    pub experimenter: HandExperimenter,
    /// The stable tolerance's fit.
    pub stable: ToleranceFit,
    /// The unstable tolerance's fit.
    pub unstable: ToleranceFit,
    /// χ² over the hand terms.
    pub chi2: f64,
    /// Hand statistics fitted.
    pub terms: usize,
    /// terms − 4 (the four tolerance parameters).
    pub dof: usize,
    /// Model against hand, sample by sample.
    pub samples: Vec<SampleFit>,
}

/// Fit the two tolerances: `pops[i]` are the count curves of the synthetic pebbles standing for
/// `hand[i]` (see the module documentation).
pub fn fit_hand(hand: &[HandSample], pops: &[Vec<CountCurve>]) -> Result<HandFit> {
    if hand.len() != pops.len() || hand.is_empty() || pops.iter().any(|p| p.is_empty()) {
        return Err(Error::Fit(format!(
            "hand experimenter: {} hand samples but {} synthetic populations (each needs a pebble)",
            hand.len(),
            pops.len()
        )));
    }
    let fits: Vec<ToleranceFit> = [0usize, 1]
        .par_iter()
        .map(|&kind| {
            let f: fn(&crate::hierarchy::Counts) -> usize = if kind == 0 { |c| c.stable } else { |c| c.unstable };
            let pops: Vec<Vec<Steps>> = pops.iter().map(|p| p.iter().map(|c| steps(c, f)).collect()).collect();
            fit_one(hand, &pops, kind)
        })
        .collect();
    let (stable, unstable) = (fits[0], fits[1]);
    let experimenter = HandExperimenter { stable: stable.tolerance, unstable: unstable.tolerance };
    let samples: Vec<SampleFit> =
        hand.iter().zip(pops).map(|(h, p)| SampleFit::of(h, population_moments(p, &experimenter))).collect();
    let terms = 4 * hand.len();
    Ok(HandFit {
        experimenter,
        stable,
        unstable,
        chi2: samples.iter().map(|s| s.chi2).sum(),
        terms,
        dof: terms.saturating_sub(4).max(1),
        samples,
    })
}

/// χ² of one count's terms (kind 0: E(S), σ(S); 1: E(U), σ(U)) at (log₁₀ ν̃, s).
fn kind_chi2(hand: &[HandSample], pops: &[Vec<Steps>], kind: usize, x: [f64; 2]) -> f64 {
    let tol = Tolerance { median: 10f64.powf(x[0]), sd_log10: x[1].abs() };
    hand.iter()
        .zip(pops)
        .map(|(h, pop)| {
            let (e, sd) = mixture(pop, &tol);
            let se_h = h.standard_errors();
            let se_m = standard_errors(&[e, e, sd, sd], pop.len());
            let t = |i: usize, m: f64, se_m: f64| (m - h.hand[i]).powi(2) / (se_h[i].powi(2) + se_m.powi(2)).max(1e-12);
            t(kind, e, se_m[0]) + t(kind + 2, sd, se_m[2])
        })
        .sum()
}

fn fit_one(hand: &[HandSample], pops: &[Vec<Steps>], kind: usize) -> ToleranceFit {
    let f = |x: [f64; 2]| kind_chi2(hand, pops, kind, x);
    // Coarse grid: log₁₀ ν̃ from −5 to −0.5 by 0.25, s from 0 to 1.5 by 0.25.
    let mut best = ([-3.0, 0.5], f64::INFINITY);
    for i in 0..=18 {
        for j in 0..=6 {
            let x = [-5.0 + 0.25 * i as f64, 0.25 * j as f64];
            let v = f(x);
            if v < best.1 {
                best = (x, v);
            }
        }
    }
    let (x, chi2) = nelder_mead(&f, best.0, [0.1, 0.1], 400);
    let x = [x[0], x[1].abs()];
    let dof = (2 * hand.len()).saturating_sub(2).max(1);
    let scale = (chi2 / dof as f64).max(1.0);
    let se = curvature_errors(&f, x, scale);
    ToleranceFit {
        tolerance: Tolerance { median: 10f64.powf(x[0]), sd_log10: x[1] },
        se_log10_median: se[0],
        se_sd_log10: se[1],
        chi2,
    }
}

/// Standard errors from the curvature of χ² at `x`: covariance 2·H⁻¹·`scale` (H by central
/// differences, step 0.02). NaN where H is not positive definite.
fn curvature_errors(f: &dyn Fn([f64; 2]) -> f64, x: [f64; 2], scale: f64) -> [f64; 2] {
    let h = 0.02;
    let at = |a: f64, b: f64| f([x[0] + a, x[1] + b]);
    let f0 = at(0.0, 0.0);
    let h00 = (at(h, 0.0) - 2.0 * f0 + at(-h, 0.0)) / (h * h);
    let h11 = (at(0.0, h) - 2.0 * f0 + at(0.0, -h)) / (h * h);
    let h01 = (at(h, h) - at(h, -h) - at(-h, h) + at(-h, -h)) / (4.0 * h * h);
    let det = h00 * h11 - h01 * h01;
    if !(h00 > 0.0 && det > 0.0) {
        return [f64::NAN; 2];
    }
    [(2.0 * scale * h11 / det).sqrt(), (2.0 * scale * h00 / det).sqrt()]
}

/// Nelder–Mead minimisation of `f` in two dimensions from `x0` with initial steps `step`, at
/// most `iters` iterations or until the simplex's values agree to 10⁻⁹: (x, f(x)).
fn nelder_mead(f: &dyn Fn([f64; 2]) -> f64, x0: [f64; 2], step: [f64; 2], iters: usize) -> ([f64; 2], f64) {
    let mut s: Vec<([f64; 2], f64)> =
        [x0, [x0[0] + step[0], x0[1]], [x0[0], x0[1] + step[1]]].iter().map(|&x| (x, f(x))).collect();
    let lerp = |a: [f64; 2], b: [f64; 2], t: f64| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
    for _ in 0..iters {
        s.sort_by(|a, b| a.1.total_cmp(&b.1));
        if (s[2].1 - s[0].1).abs() <= 1e-9 * (1.0 + s[0].1.abs()) {
            break;
        }
        let c = lerp(s[0].0, s[1].0, 0.5);
        let r = lerp(c, s[2].0, -1.0);
        let fr = f(r);
        if fr < s[0].1 {
            let e = lerp(c, s[2].0, -2.0);
            let fe = f(e);
            s[2] = if fe < fr { (e, fe) } else { (r, fr) };
        } else if fr < s[1].1 {
            s[2] = (r, fr);
        } else {
            let k = if fr < s[2].1 { lerp(c, r, 0.5) } else { lerp(c, s[2].0, 0.5) };
            let fk = f(k);
            if fk < s[2].1.min(fr) {
                s[2] = (k, fk);
            } else {
                for i in 1..3 {
                    let x = lerp(s[0].0, s[i].0, 0.5);
                    s[i] = (x, f(x));
                }
            }
        }
    }
    s.sort_by(|a, b| a.1.total_cmp(&b.1));
    s[0]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nelder_mead_finds_the_minimum_of_a_quadratic() {
        let f = |x: [f64; 2]| 3.0 * (x[0] - 1.5).powi(2) + (x[1] + 0.5).powi(2) + x[0] * x[1] + 2.0;
        // ∇ = 0: 6(x − 1.5) + y = 0, 2(y + 0.5) + x = 0 → x = 19/11, y = −15/11.
        let (x, _) = nelder_mead(&f, [0.0, 0.0], [0.5, 0.5], 500);
        assert!((x[0] - 19.0 / 11.0).abs() < 1e-4 && (x[1] + 15.0 / 11.0).abs() < 1e-4, "{x:?}");
        // χ² = (x/0.1)² + (y/0.2)²: H = diag(2/σ²), so 2·H⁻¹ = diag(σ²): the Δχ² = 1 errors.
        let g = |x: [f64; 2]| (x[0] / 0.1).powi(2) + (x[1] / 0.2).powi(2);
        let se = curvature_errors(&g, [0.0, 0.0], 1.0);
        assert!((se[0] - 0.1).abs() < 1e-9 && (se[1] - 0.2).abs() < 1e-9, "{se:?}");
    }

    #[test]
    fn the_merged_steps_give_the_moments_of_the_distributions() {
        use crate::hierarchy::Counts;
        let c = |stable, unstable| Counts { stable, unstable, saddle: stable + unstable - 2 };
        let curves = vec![
            CountCurve { levels: vec![1e-3, 1e-2, 1e-1], counts: vec![c(5, 6), c(3, 4), c(3, 3), c(2, 2)] },
            CountCurve { levels: vec![2e-3], counts: vec![c(4, 4), c(2, 2)] },
        ];
        let exp = HandExperimenter {
            stable: Tolerance { median: 3e-3, sd_log10: 0.4 },
            unstable: Tolerance { median: 1e-2, sd_log10: 0.7 },
        };
        let m = population_moments(&curves, &exp);
        let s: Vec<Steps> = curves.iter().map(|c| steps(c, |k| k.stable)).collect();
        assert_eq!(s[0], vec![(1e-3, 5.0), (1e-1, 3.0), (f64::INFINITY, 2.0)]);
        let (e, sd) = mixture(&s, &exp.stable);
        assert!((e - m.es).abs() < 1e-12 && (sd - m.sd_s).abs() < 1e-12);
        let u: Vec<Steps> = curves.iter().map(|c| steps(c, |k| k.unstable)).collect();
        let (e, sd) = mixture(&u, &exp.unstable);
        assert!((e - m.eu).abs() < 1e-12 && (sd - m.sd_u).abs() < 1e-12);
    }
}
