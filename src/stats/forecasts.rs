//! Probabilistic forecasts scored against outcomes: the logistic function, the Brier score, log
//! loss and accuracy, their bounds (an oracle, a perfect ensemble), the AUC of two samples and the
//! binomial log-likelihood of measured counts.

use serde::Serialize;

/// The logistic function 1 / (1 + e^(−η)): the probability of log-odds η.
pub fn logistic(eta: f64) -> f64 {
    1.0 / (1.0 + (-eta).exp())
}

/// One probability forecast and the outcomes it is scored against: the forecast P of "yes",
/// and the yes/no outcomes of the truths of its case.
pub type Forecast<'a> = (f64, &'a [bool]);

/// The proper scores of a set of probability forecasts ([`forecast_scores`]), each a mean over
/// every truth of every case.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ForecastScores {
    /// Brier score: the mean of (P − y)², y = 1 for yes, 0 for no (0 is perfect, 0.25 is P = ½).
    pub brier: f64,
    /// Log loss: the mean of −[y ln q + (1 − y) ln(1 − q)], q = P kept inside [ε, 1 − ε] (nats).
    pub log_loss: f64,
    /// Accuracy: the share of truths the forecast gets right, P ≥ ½ read as yes.
    pub accuracy: f64,
    /// The number of truths scored.
    pub truths: usize,
}

/// The Brier score, log loss and accuracy of the forecasts `cases`, each scored against every
/// truth of its case ([`ForecastScores`]; zeros for no truth). The log loss keeps a forecast
/// inside [ε, 1 − ε], `eps` = ε: an ensemble of n members says no more than ε = 1/(2n) (half a
/// member) by a P of 0 or 1, and a yes/no forecast given the same ε does not make its log loss
/// infinite by one wrong answer.
pub fn forecast_scores(cases: &[Forecast], eps: f64) -> ForecastScores {
    let (mut s, mut k) = ([0.0; 3], 0usize);
    for &(p, truths) in cases {
        let q = p.clamp(eps, 1.0 - eps);
        for y in truths.iter().map(|&y| y as u8 as f64) {
            s[0] += (p - y) * (p - y);
            s[1] -= y * q.ln() + (1.0 - y) * (1.0 - q).ln();
            s[2] += (((p >= 0.5) as u8 as f64) == y) as u8 as f64;
            k += 1;
        }
    }
    let [brier, log_loss, accuracy] = s.map(|x| x / k.max(1) as f64);
    ForecastScores { brier, log_loss, accuracy, truths: k }
}

/// The oracle's Brier score of cases with the outcomes `truths`: each case forecast by its own
/// truth frequency q, which scores q(1 − q) — the lowest any forecast of the case can. The mean
/// over every truth (each case weighted by its K truths); 0 for no truth.
pub fn oracle_brier(truths: &[&[bool]]) -> f64 {
    let (mut oracle, mut k_all) = (0.0, 0usize);
    for t in truths {
        let k = t.len();
        let q = t.iter().filter(|&&y| y).count() as f64 / k.max(1) as f64;
        (oracle, k_all) = (oracle + q * (1.0 - q) * k as f64, k_all + k);
    }
    oracle / k_all.max(1) as f64
}

/// The expected Brier score of a perfect ensemble of `members` members — each drawn from its
/// case's truth distribution, so its P is a binomial frequency of mean q — against the truths:
/// q(1 − q)(1 + 1/n), q(1 − q) estimated without bias from the case's K truths as
/// q̂(1 − q̂)·K/(K − 1). The mean over every truth of the cases with K ≥ 2 (each weighted by K);
/// 0 if there is none.
pub fn ensemble_brier(truths: &[&[bool]], members: u64) -> f64 {
    let (mut perfect, mut k_perfect) = (0.0, 0usize);
    for t in truths {
        let k = t.len();
        let q = t.iter().filter(|&&y| y).count() as f64 / k.max(1) as f64;
        if k >= 2 {
            perfect += q * (1.0 - q) * k as f64 / (k as f64 - 1.0) * (1.0 + 1.0 / members as f64) * k as f64;
            k_perfect += k;
        }
    }
    perfect / k_perfect.max(1) as f64
}

/// The Mann–Whitney probability that a random value of `a` is smaller than a random value of `b`,
/// ties counting ½: (#{aᵢ < bⱼ} + ½ #{aᵢ = bⱼ}) / (|a| |b|), the area under the ROC curve of
/// "smaller means `a`". ½ for no separation, 1 when every `a` is below every `b`; NaN when either
/// sample is empty. Infinite values rank as numbers (∞ = ∞ is a tie).
pub fn mann_whitney_auc(a: &[f64], b: &[f64]) -> f64 {
    let score = |x: f64, y: f64| if x == y { 0.5 } else { f64::from(u8::from(x < y)) };
    let s: f64 = a.iter().flat_map(|&x| b.iter().map(move |&y| score(x, y))).sum();
    let n = (a.len() * b.len()) as f64;
    if n > 0.0 {
        s / n
    } else {
        f64::NAN
    }
}

/// The binomial log-likelihood Σ kᵢ ln qᵢ + (nᵢ − kᵢ) ln(1 − qᵢ) of the observed successes
/// `observed` = (kᵢ, nᵢ) under the probabilities `p` (paired in order), each qᵢ = pᵢ kept inside
/// [ε, 1 − ε] (`eps` = ε), so that a model probability of 0 or 1 (a Monte Carlo estimate that
/// saw no success) costs a finite amount. The binomial coefficients, which do not depend on p,
/// are left out.
pub fn binomial_log_likelihood(observed: &[(f64, f64)], p: &[f64], eps: f64) -> f64 {
    let term = |(&(k, n), &q): (&(f64, f64), &f64)| {
        let q = q.clamp(eps, 1.0 - eps);
        k * q.ln() + (n - k) * (1.0 - q).ln()
    };
    observed.iter().zip(p).map(term).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn logistic_is_the_inverse_of_the_log_odds() {
        assert_eq!(logistic(0.0), 0.5);
        for p in [0.01f64, 0.3, 0.9] {
            assert!((logistic((p / (1.0 - p)).ln()) - p).abs() < 1e-12);
        }
        assert!((logistic(2.0) + logistic(-2.0) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn forecast_scores_match_a_hand_computation() {
        // P = 0.8 against (yes, no), P = 0 against (no): Brier (0.04 + 0.64 + 0)/3 = 0.68/3;
        // accuracy 2/3; log loss with ε = 0.1: (−ln 0.8 − ln 0.2 − ln 0.9)/3.
        let cases = [(0.8, &[true, false][..]), (0.0, &[false][..])];
        let s = forecast_scores(&cases, 0.1);
        assert_eq!(s.truths, 3);
        assert!((s.brier - 0.68 / 3.0).abs() < 1e-14, "{s:?}");
        assert!((s.accuracy - 2.0 / 3.0).abs() < 1e-15);
        let ll = -(0.8f64.ln() + 0.2f64.ln() + 0.9f64.ln()) / 3.0;
        assert!((s.log_loss - ll).abs() < 1e-14, "{} vs {ll}", s.log_loss);
        // A sure wrong answer costs ln(1/ε), not infinity.
        let wrong = forecast_scores(&[(1.0, &[false][..])], 0.01);
        assert!((wrong.log_loss - 100f64.ln()).abs() < 1e-12 && wrong.brier == 1.0 && wrong.accuracy == 0.0);
        assert_eq!(forecast_scores(&[], 0.1), ForecastScores { brier: 0.0, log_loss: 0.0, accuracy: 0.0, truths: 0 });
    }

    #[test]
    fn brier_bounds_match_a_hand_computation_and_their_expectation() {
        // Case a: 1 yes of 4 (q = 1/4), case b: 2 of 2 (q = 1), case c: one truth.
        let (a, b, c) = ([true, false, false, false], [true, true], [true]);
        let truths = [&a[..], &b[..], &c[..]];
        // Oracle: (4 · 3/16 + 0 + 0)/7.
        assert!((oracle_brier(&truths) - 0.75 / 7.0).abs() < 1e-15);
        // Perfect ensemble of 3: case a's 3/16 · 4/3 · (1 + 1/3) · 4 over the 6 truths of a and b.
        let expected = 3.0 / 16.0 * 4.0 / 3.0 * (4.0 / 3.0) * 4.0 / 6.0;
        assert!((ensemble_brier(&truths, 3) - expected).abs() < 1e-15);
        // The expectation it estimates: the Brier score of n binomial draws of P against one more
        // draw of the truth, E[(P̂ − y)²] = q(1 − q)(1 + 1/n), here over a binomial enumeration.
        let (q, n) = (0.3f64, 4u64);
        let choose = |k: u64| (1..=k).fold(1.0, |c, i| c * (n - i + 1) as f64 / i as f64);
        let exact: f64 = (0..=n)
            .map(|k| {
                let (pk, pr) = (choose(k) * q.powi(k as i32) * (1.0 - q).powi((n - k) as i32), k as f64 / n as f64);
                pk * (q * (1.0 - pr).powi(2) + (1.0 - q) * pr * pr)
            })
            .sum();
        assert!((exact - q * (1.0 - q) * (1.0 + 1.0 / n as f64)).abs() < 1e-14, "{exact}");
    }

    #[test]
    fn mann_whitney_auc_counts_pairs_and_ties() {
        // a = (1, 3), b = (2, 3, ∞): pairs (1,2) (1,3) (1,∞) (3,∞) are below, (3,3) a tie, (3,2)
        // above: (4 + ½)/6 = 0.75.
        assert_eq!(mann_whitney_auc(&[1.0, 3.0], &[2.0, 3.0, f64::INFINITY]), 0.75);
        assert_eq!(mann_whitney_auc(&[1.0, 2.0], &[5.0]), 1.0);
        assert_eq!(mann_whitney_auc(&[5.0], &[1.0, 2.0]), 0.0);
        assert_eq!(mann_whitney_auc(&[f64::INFINITY], &[f64::INFINITY]), 0.5);
        assert!(mann_whitney_auc(&[], &[1.0]).is_nan());
    }

    #[test]
    fn binomial_log_likelihood_matches_a_hand_computation() {
        // 3 of 10 at p = 0.3: 3 ln 0.3 + 7 ln 0.7 = −6.108643…; 0 of 4 at p = 0 is clamped to
        // ε = 0.01: 4 ln 0.99.
        let ll = binomial_log_likelihood(&[(3.0, 10.0), (0.0, 4.0)], &[0.3, 0.0], 0.01);
        let hand = 3.0 * 0.3f64.ln() + 7.0 * 0.7f64.ln() + 4.0 * 0.99f64.ln();
        assert!((ll - hand).abs() < 1e-14 && (ll - 4.0 * 0.99f64.ln() + 6.108_643).abs() < 1e-6, "{ll}");
        // The maximum over p is at the observed fraction.
        let at = |p: f64| binomial_log_likelihood(&[(3.0, 10.0)], &[p], 1e-9);
        assert!(at(0.3) > at(0.29) && at(0.3) > at(0.31));
    }
}
