//! The hand experimenter with two tolerances, and the distribution of the counts a person
//! reports for one pebble.
//!
//! A person counting equilibria by hand does not tell apart two equilibria whose R differ by less
//! than a height ν·R_max: the paper's experimenter counts the equilibria of G(ν). Finding a stable
//! position (letting go of the pebble and watching it settle) and an unstable one (holding it
//! balanced on a tip) are different acts, so this experimenter counts the stable equilibria of
//! G(ν_S) and the unstable ones of G(ν_U), with its own tolerance for each; the saddles follow
//! from Poincaré–Hopf, H = S + U − 2. Nor is a tolerance one number: it varies from pebble to
//! pebble (how the pebble sits in the hand, how long one tries). Here log₁₀ ν_S and log₁₀ ν_U are
//! independent normals,
//!
//! log₁₀ ν_S ~ N(log₁₀ ν̃_S, s_S²),   log₁₀ ν_U ~ N(log₁₀ ν̃_U, s_U²),
//!
//! ν̃ the median tolerance and s its spread in decades ([`Tolerance`]); s = 0 is the paper's one
//! fixed ν. (Only the marginal statistics of S and U are published, so a correlation between the
//! two tolerances could not be fitted; they are taken as independent.)
//!
//! **Exact distributions.** S(ν) and U(ν) of a pebble are step functions of ν, read from its
//! cancellation hierarchy ([`CountCurve`]): on the k-th interval of levels, L_(k−1) < ν ≤ L_k,
//! the counts are those of G(ν) after the first k distinct levels. So
//!
//! P(S = s) = Σ_(k : S_k = s) [Φ(z(L_k)) − Φ(z(L_(k−1)))],  z(L) = (log₁₀ L − log₁₀ ν̃_S) / s_S,
//!
//! with L_(−1) = 0 and the last L = ∞ (Φ the standard normal distribution function), and likewise
//! U; by independence P(S = s, U = u) = P(S = s)·P(U = u). No sampling: every pair the hierarchy
//! allows gets its probability. The most likely pair is the pair of the most likely S and the
//! most likely U. A fixed tolerance (s = 0) gives probability 1 to the counts of G(ν).

use super::{CountCurve, Moments};
use crate::{Error, Result};
use serde::{Deserialize, Serialize};

/// A tolerance that varies from pebble to pebble: log₁₀ ν ~ N(log₁₀ `median`, `sd_log10`²).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tolerance {
    /// ν̃: the median tolerance (fraction of R_max).
    pub median: f64,
    /// s: the standard deviation of log₁₀ ν between pebbles (decades); 0 for one fixed ν.
    pub sd_log10: f64,
}

impl Tolerance {
    /// One fixed ν (the paper's experimenter).
    pub fn fixed(nu: f64) -> Tolerance {
        Tolerance { median: nu, sd_log10: 0.0 }
    }

    /// A checked tolerance: `median` positive and finite, `sd_log10` ≥ 0 and finite; `what`
    /// names it in the error.
    pub fn new(what: &str, median: f64, sd_log10: f64) -> Result<Tolerance> {
        if !(median > 0.0 && median.is_finite()) {
            return Err(Error::parameter(&format!("{what}_median"), median, "positive and finite"));
        }
        if !(sd_log10 >= 0.0 && sd_log10.is_finite()) {
            return Err(Error::parameter(&format!("{what}_spread"), sd_log10, "≥ 0 and finite (decades)"));
        }
        Ok(Tolerance { median, sd_log10 })
    }

    /// P(ν ≤ x), the distribution function (x ≤ 0: 0; x = ∞: 1). A fixed tolerance: 1 when
    /// ν ≤ x.
    pub fn cdf(&self, x: f64) -> f64 {
        if !(x > 0.0) {
            return 0.0;
        }
        if x == f64::INFINITY {
            return 1.0;
        }
        if self.sd_log10 == 0.0 {
            return if self.median <= x { 1.0 } else { 0.0 };
        }
        normal_cdf((x.log10() - self.median.log10()) / self.sd_log10)
    }

    /// P(lo < ν ≤ hi).
    pub fn mass(&self, lo: f64, hi: f64) -> f64 {
        (self.cdf(hi) - self.cdf(lo)).max(0.0)
    }
}

/// Φ(z) = erfc(−z/√2)/2 (crate `statrs`), accurate in both tails.
fn normal_cdf(z: f64) -> f64 {
    0.5 * statrs::function::erf::erfc(-z / std::f64::consts::SQRT_2)
}

/// The two-tolerance hand experimenter: stable equilibria counted at ν_S, unstable at ν_U.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct HandExperimenter {
    /// The tolerance ν_S at which stable equilibria are told apart.
    pub stable: Tolerance,
    /// The tolerance ν_U at which unstable equilibria are told apart.
    pub unstable: Tolerance,
}

impl HandExperimenter {
    /// The paper's experimenter: both counts at one fixed ν.
    pub fn one_nu(nu: f64) -> HandExperimenter {
        HandExperimenter { stable: Tolerance::fixed(nu), unstable: Tolerance::fixed(nu) }
    }

    /// The distribution of the counts this experimenter reports for a pebble.
    pub fn counts(&self, curve: &CountCurve) -> CountDistribution {
        CountDistribution::of(curve, self)
    }
}

/// The experimenter calibrated on the paper's Table 2 (`cargo experiment hand_table2`, which
/// prints the fit these numbers are rounded from): stable equilibria told apart at ν_S with
/// median [`TABLE2_EXPERIMENTER`]`.stable.median`, unstable ones at ν_U, each with its spread in
/// decades between pebbles, fitted on synthetic pebbles of roughness [`TABLE2_ROUGHNESS`]: the
/// default experimenter of `rocking study synthetic`; on real scans, see
/// [`TABLE2_EXPERIMENTER_ON_SCANS`].
pub const TABLE2_EXPERIMENTER: HandExperimenter = HandExperimenter {
    stable: Tolerance { median: 3.55e-3, sd_log10: 0.17 },
    unstable: Tolerance { median: 1.52e-2, sd_log10: 0.0 },
};

/// [`TABLE2_EXPERIMENTER`] in the frame of real scans: the experimenter of `rocking study` on a
/// folder of scans (and of Python's `study`). The calibration's tolerances are tolerances of the
/// synthetic pebbles' hierarchies; real scans have fewer unstable equilibria at a given ν
/// (Table 2's computer columns: the synthetic pebbles match the real scans' counts at ν only when
/// counted at ν·10^δ, δ_S = 0.05 and δ_U = 0.65 decades, [`crate::study::scan_frame_shift`]), so
/// each median is divided by its 10^δ ([`crate::study::Table2HandFit::in_scan_frame`]), the
/// spreads kept (rounded from `cargo experiment hand_table2`, which prints both).
///
/// A second route, without synthetic pebbles, agrees: on the five samples Table 2 reports both
/// ways, the person's mean counts equal the real scans' counts at the paper's ν = 0.0035 within
/// their standard errors (`tests/hand.rs`), so on real scans the person's tolerances lie near it.
pub const TABLE2_EXPERIMENTER_ON_SCANS: HandExperimenter = HandExperimenter {
    stable: Tolerance { median: 3.16e-3, sd_log10: 0.17 },
    unstable: Tolerance { median: 3.41e-3, sd_log10: 0.0 },
};

/// The roughness amplitude of the synthetic pebbles ([`crate::generate::pebble`]) with which
/// [`TABLE2_EXPERIMENTER`] was calibrated: the one whose counts at ν = 0.0035 best match the
/// paper's scans (Table 2's computer columns) together with the hand columns.
pub const TABLE2_ROUGHNESS: f64 = 0.3;

/// A count and its probability.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Weighted {
    /// The count.
    pub count: usize,
    /// Its probability.
    pub p: f64,
}

/// One pair (S, U) a person may report, with H = S + U − 2 and its probability.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct HandPair {
    /// S: stable equilibria reported.
    pub stable: usize,
    /// U: unstable equilibria reported.
    pub unstable: usize,
    /// H = S + U − 2 (Poincaré–Hopf).
    pub saddle: usize,
    /// P(S, U).
    pub p: f64,
}

/// P(S) and P(U) of one pebble under a [`HandExperimenter`]: every count the hierarchy allows,
/// in increasing order, with its probability (zero where the tolerance puts no mass on it).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CountDistribution {
    /// P(S = s) for every s of S(ν).
    pub stable: Vec<Weighted>,
    /// P(U = u) for every u of U(ν).
    pub unstable: Vec<Weighted>,
}

impl CountDistribution {
    /// The distribution of the counts of `curve` under `exp` (see the module documentation).
    pub fn of(curve: &CountCurve, exp: &HandExperimenter) -> CountDistribution {
        CountDistribution {
            stable: marginal(curve, &exp.stable, |c| c.stable),
            unstable: marginal(curve, &exp.unstable, |c| c.unstable),
        }
    }

    /// P(S = s, U = u) (0 for a pair the hierarchy does not allow).
    pub fn p(&self, stable: usize, unstable: usize) -> f64 {
        let find = |v: &[Weighted], k: usize| v.iter().find(|w| w.count == k).map_or(0.0, |w| w.p);
        find(&self.stable, stable) * find(&self.unstable, unstable)
    }

    /// Every pair the hierarchy allows with P > 0, most likely first (ties: fewer S, then fewer
    /// U first).
    pub fn pairs(&self) -> Vec<HandPair> {
        let mut out: Vec<HandPair> = self
            .stable
            .iter()
            .flat_map(|s| self.unstable.iter().map(move |u| pair(s.count, u.count, s.p * u.p)))
            .filter(|p| p.p > 0.0)
            .collect();
        out.sort_by(|a, b| b.p.total_cmp(&a.p).then(a.stable.cmp(&b.stable)).then(a.unstable.cmp(&b.unstable)));
        out
    }

    /// The most likely pair: the most likely S with the most likely U (ties: the smaller count).
    pub fn most_likely(&self) -> HandPair {
        let s = mode(&self.stable);
        let u = mode(&self.unstable);
        pair(s.count, u.count, s.p * u.p)
    }

    /// [E(S), E(S²)].
    pub fn stable_moments(&self) -> [f64; 2] {
        raw_moments(&self.stable)
    }

    /// [E(U), E(U²)].
    pub fn unstable_moments(&self) -> [f64; 2] {
        raw_moments(&self.unstable)
    }
}

fn pair(stable: usize, unstable: usize, p: f64) -> HandPair {
    HandPair { stable, unstable, saddle: (stable + unstable).saturating_sub(2), p }
}

fn mode(v: &[Weighted]) -> Weighted {
    // `v` is in increasing count: keep the first of equal probabilities.
    v.iter().copied().fold(Weighted { count: 0, p: -1.0 }, |best, w| if w.p > best.p { w } else { best })
}

fn raw_moments(v: &[Weighted]) -> [f64; 2] {
    v.iter().fold([0.0, 0.0], |[m1, m2], w| {
        let k = w.count as f64;
        [m1 + w.p * k, m2 + w.p * k * k]
    })
}

/// P(count = k) for every count the curve takes, the k-th interval of levels weighted by the
/// tolerance's mass on it.
fn marginal(curve: &CountCurve, tol: &Tolerance, f: fn(&crate::hierarchy::Counts) -> usize) -> Vec<Weighted> {
    let mut out: Vec<Weighted> = Vec::new();
    let mut lo = 0.0;
    for (k, c) in curve.counts.iter().enumerate() {
        let hi = curve.levels.get(k).copied().unwrap_or(f64::INFINITY);
        let p = tol.mass(lo, hi);
        let count = f(c);
        match out.iter_mut().find(|w| w.count == count) {
            Some(w) => w.p += p,
            None => out.push(Weighted { count, p }),
        }
        lo = hi;
    }
    out.sort_by_key(|w| w.count);
    out
}

impl Moments {
    /// E and σ of S and U over a group of n pebbles each counted once by a person whose
    /// tolerance varies: E(S) = mean of the pebbles' E_i(S), and σ(S)² the expected sample
    /// variance (n − 1) of such counts,
    ///
    /// σ(S)² = n/(n − 1) · [mean_i E_i(S²) − E(S)²]
    ///
    /// (the variance of the mixture, within and between pebbles, with the n − 1 correction);
    /// U likewise. With every distribution certain this is the sample standard deviation of the
    /// counts, [`Moments::of`].
    pub fn of_distributions(d: &[CountDistribution]) -> Moments {
        let n = d.len();
        let avg = |f: &dyn Fn(&CountDistribution) -> [f64; 2]| {
            let sum = d.iter().map(f).fold([0.0, 0.0], |a, m| [a[0] + m[0], a[1] + m[1]]);
            [sum[0] / n as f64, sum[1] / n as f64]
        };
        let (s, u) = (avg(&|x| x.stable_moments()), avg(&|x| x.unstable_moments()));
        let sd = |m: [f64; 2]| (bessel(n) * (m[1] - m[0] * m[0])).max(0.0).sqrt();
        Moments { n, es: s[0], eu: u[0], sd_s: sd(s), sd_u: sd(u) }
    }
}

/// n/(n − 1), NaN for fewer than 2 (no sample variance).
pub(crate) fn bessel(n: usize) -> f64 {
    if n < 2 {
        f64::NAN
    } else {
        n as f64 / (n - 1) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hierarchy::Counts;

    /// S: 5 below 10⁻³, 3 up to 10⁻², then 2; U: 6, 4 (from 10⁻³), 2 (from 10⁻¹).
    fn curve() -> CountCurve {
        let c = |stable, unstable| Counts { stable, unstable, saddle: stable + unstable - 2 };
        CountCurve { levels: vec![1e-3, 1e-2, 1e-1], counts: vec![c(5, 6), c(3, 4), c(2, 4), c(2, 2)] }
    }

    #[test]
    fn a_fixed_tolerance_gives_the_counts_of_g_nu() {
        let k = curve();
        for nu in [1e-4, 1e-3, 2e-3, 1e-2, 0.05, 0.5] {
            let d = HandExperimenter::one_nu(nu).counts(&k);
            let best = d.most_likely();
            let c = k.at(nu);
            assert_eq!(
                (best.stable, best.unstable, best.saddle, best.p),
                (c.stable, c.unstable, c.saddle, 1.0),
                "{nu}"
            );
            assert_eq!(d.pairs().len(), 1);
        }
    }

    #[test]
    fn the_probabilities_are_normal_masses_of_the_level_intervals() {
        // ν̃_S = 10⁻², s = 1 decade: P(S=5) = Φ(−1), P(S=3) = Φ(0) − Φ(−1), P(S=2) = 1/2 (to the
        // 10⁻¹¹ of statrs' erfc).
        let phi_m1 = 0.158_655_253_931_457_05;
        let exp = HandExperimenter {
            stable: Tolerance { median: 1e-2, sd_log10: 1.0 },
            unstable: Tolerance { median: 1e-1, sd_log10: 0.5 },
        };
        let d = exp.counts(&curve());
        let s: Vec<(usize, f64)> = d.stable.iter().map(|w| (w.count, w.p)).collect();
        for ((k, p), (k0, p0)) in s.iter().zip([(2, 0.5), (3, 0.5 - phi_m1), (5, phi_m1)]) {
            assert_eq!(*k, k0);
            assert!((p - p0).abs() < 1e-9, "P(S = {k}) = {p}, expected {p0}");
        }
        // U: 6 below 10⁻³ (z = −4), 4 up to 10⁻¹ (z = 0), 2 above: 1/2 each up to Φ(−4).
        let pu = |k| d.unstable.iter().find(|w| w.count == k).unwrap().p;
        assert!((pu(2) - 0.5).abs() < 1e-12 && (pu(6) - 3.167_124_183_311_992e-5).abs() < 1e-12);
        let total: f64 = d.pairs().iter().map(|p| p.p).sum();
        assert!((total - 1.0).abs() < 1e-12);
        // Most likely: S = 2 (1/2 against 0.34), U: 2 and 4 tie at 1/2 − Φ(−4)/2…: U = 2 has 1/2.
        let best = d.most_likely();
        assert_eq!((best.stable, best.unstable, best.saddle), (2, 2, 2));
        assert!((best.p - 0.25).abs() < 1e-12);
        assert!((d.p(3, 4) - (0.5 - phi_m1) * pu(4)).abs() < 1e-9);
        assert_eq!(d.p(4, 4), 0.0);
        // Moments: E(S) = 2·½ + 3·(½ − Φ(−1)) + 5·Φ(−1).
        let es = 1.0 + 3.0 * (0.5 - phi_m1) + 5.0 * phi_m1;
        assert!((d.stable_moments()[0] - es).abs() < 1e-9);
    }

    #[test]
    fn the_moments_of_a_group_are_those_of_the_mixture() {
        // Pebbles at fixed tolerances: the moments are those of their counts (n − 1 for σ).
        let k = curve();
        let d: Vec<CountDistribution> =
            [1e-4, 0.5, 5e-3].iter().map(|&nu| HandExperimenter::one_nu(nu).counts(&k)).collect();
        let m = Moments::of_distributions(&d);
        let of = Moments::of(&[(5.0, 6.0), (2.0, 2.0), (3.0, 4.0)]);
        for (a, b) in m.as_array().iter().zip(of.as_array()) {
            assert!((a - b).abs() < 1e-12, "{m:?} {of:?}");
        }
        // One pebble whose tolerance is either side of a level with probability ½ each (and
        // 10⁻⁸⁸ beyond the next, 20 spreads away): S is 5
        // or 3 (E = 4, mixture variance 1); with a certain pebble of S = 2 beside it, E(S) = 3
        // and σ(S)² = 2/1 · (mean of E_i(S²) − 9) = 2 · ((17 + 4)/2 − 9) = 3.
        let half = HandExperimenter::one_nu(1.0);
        let mut d = vec![half.counts(&k), HandExperimenter::one_nu(0.5).counts(&k)];
        d[0] = HandExperimenter { stable: Tolerance { median: 1e-3, sd_log10: 0.05 }, ..half }.counts(&k);
        let m = Moments::of_distributions(&d);
        assert!((m.es - 3.0).abs() < 1e-12 && (m.sd_s - 3f64.sqrt()).abs() < 1e-12, "{m:?}");
    }

    #[test]
    fn bad_tolerances_are_parameter_errors() {
        assert!(Tolerance::new("nu_s", 0.0, 0.3).is_err());
        assert!(Tolerance::new("nu_s", 1e-3, -0.1).is_err());
        assert!(Tolerance::new("nu_s", 1e-3, f64::NAN).is_err());
        assert_eq!(Tolerance::new("nu_s", 1e-3, 0.2).unwrap(), Tolerance { median: 1e-3, sd_log10: 0.2 });
    }
}
