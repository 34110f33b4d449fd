//! Statistics of runs and samples: binomial intervals, goodness of fit, moments, trend lines and
//! grids.

use serde::Serialize;

/// Wilson score interval for k successes in n trials at z (1.96 for 95 %); (0, 1) for n = 0.
pub fn wilson(k: u64, n: u64, z: f64) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let (k, n) = (k as f64, n as f64);
    let p = k / n;
    let denom = 1.0 + z * z / n;
    let centre = (p + z * z / (2.0 * n)) / denom;
    let half = z * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt() / denom;
    ((centre - half).max(0.0), (centre + half).min(1.0))
}

/// P(χ²_dof ≥ `chi2`), the upper tail of the χ² distribution with `dof` degrees of freedom
/// (crate `statrs`); 1 for no degree of freedom (nothing to test), NaN where undefined.
pub fn chi_square_tail(chi2: f64, dof: usize) -> f64 {
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    if dof == 0 {
        return 1.0;
    }
    ChiSquared::new(dof as f64).map(|d| 1.0 - d.cdf(chi2)).unwrap_or(f64::NAN)
}

/// Pearson's χ² of counts against probabilities (categories with expected count < 5 are pooled
/// into one), its degrees of freedom and p-value. Counts in categories of probability 0 make
/// χ² infinite and p = 0 (the model says they cannot happen), never silently dropped.
pub fn chi_square(counts: &[u64], probabilities: &[f64]) -> (f64, usize, f64) {
    let n: u64 = counts.iter().sum();
    let (mut chi2, mut cats) = (0.0, 0usize);
    let (mut pooled_o, mut pooled_e) = (0.0, 0.0);
    for (&o, &p) in counts.iter().zip(probabilities) {
        let e = p * n as f64;
        if e < 5.0 {
            pooled_o += o as f64;
            pooled_e += e;
        } else {
            chi2 += (o as f64 - e).powi(2) / e;
            cats += 1;
        }
    }
    if pooled_e > 0.0 {
        chi2 += (pooled_o - pooled_e).powi(2) / pooled_e;
        cats += 1;
    } else if pooled_o > 0.0 {
        return (f64::INFINITY, cats.max(1), 0.0);
    }
    let dof = cats.saturating_sub(1);
    (chi2, dof, chi_square_tail(chi2, dof))
}

/// Pearson's χ² test of homogeneity of two samples of counts over the same categories (a 2 × k
/// contingency table; categories empty in both samples are dropped): statistic, degrees of
/// freedom k − 1 and p-value. Expected count of cell (s, c): n_s · (a_c + b_c) / (n_a + n_b).
pub fn chi_square_homogeneity(a: &[u64], b: &[u64]) -> (f64, usize, f64) {
    let (na, nb) = (a.iter().sum::<u64>() as f64, b.iter().sum::<u64>() as f64);
    let n = na + nb;
    let (mut chi2, mut cats) = (0.0, 0usize);
    for (&x, &y) in a.iter().zip(b) {
        let col = (x + y) as f64;
        if col == 0.0 {
            continue;
        }
        cats += 1;
        for (o, row) in [(x as f64, na), (y as f64, nb)] {
            let e = row * col / n;
            if e > 0.0 {
                chi2 += (o - e).powi(2) / e;
            }
        }
    }
    let dof = cats.saturating_sub(1);
    (chi2, dof, chi_square_tail(chi2, dof))
}

/// The Stuart–Maxwell test of marginal homogeneity of a paired sample (Stuart 1955, Maxwell
/// 1970): `table[i][j]` counts the items classified i by the first method and j by the second
/// (e.g. the flock of one release in two engines). With the marginal differences
/// d_i = n_i· − n_·i and their covariance S_ii = n_i· + n_·i − 2 n_ii, S_ij = −(n_ij + n_ji),
/// the statistic χ² = dᵀ S⁻¹ d over k − 1 of the k categories is χ² with k − 1 degrees of
/// freedom under homogeneity (dropping any one category gives the same value, since Σ d_i = 0).
/// Categories on which the two methods never disagree (S_ii = 0, hence d_i = 0) carry no
/// information and are left out of k. For two categories it is McNemar's (b − c)² / (b + c).
/// Unlike [`chi_square_homogeneity`], which takes its two samples as independent and is
/// conservative for a paired one, this test uses the pairing: items classified alike by both
/// methods cancel. Returns (χ², dof, p); (0, 0, 1) when the methods never disagree.
pub fn stuart_maxwell(table: &[Vec<u64>]) -> (f64, usize, f64) {
    let k = table.len();
    let n = |i: usize, j: usize| table[i][j] as f64;
    let row = |i: usize| (0..k).map(|j| n(i, j)).sum::<f64>();
    let col = |i: usize| (0..k).map(|j| n(j, i)).sum::<f64>();
    let informative: Vec<usize> = (0..k).filter(|&i| row(i) + col(i) - 2.0 * n(i, i) > 0.0).collect();
    let Some((_, kept)) = informative.split_last() else { return (0.0, 0, 1.0) };
    let m = kept.len();
    if m == 0 {
        return (0.0, 0, 1.0);
    }
    let d = nalgebra::DVector::from_fn(m, |a, _| row(kept[a]) - col(kept[a]));
    let s = nalgebra::DMatrix::from_fn(m, m, |a, b| {
        let (i, j) = (kept[a], kept[b]);
        if i == j {
            row(i) + col(i) - 2.0 * n(i, i)
        } else {
            -(n(i, j) + n(j, i))
        }
    });
    let chi2 = match s.cholesky() {
        Some(c) => d.dot(&c.solve(&d)),
        None => return (f64::INFINITY, m, 0.0),
    };
    let p = chi_square_tail(chi2, m);
    (chi2, m, p)
}

/// Kullback–Leibler divergence D(empirical ‖ static) in nats (categories with zero counts
/// contribute 0; a count where the static probability is 0 gives ∞).
pub fn kl_divergence(counts: &[u64], probabilities: &[f64]) -> f64 {
    let n: u64 = counts.iter().sum();
    counts
        .iter()
        .zip(probabilities)
        .filter(|(&o, _)| o > 0)
        .map(|(&o, &p)| {
            let q = o as f64 / n as f64;
            if p > 0.0 {
                q * (q / p).ln()
            } else {
                f64::INFINITY
            }
        })
        .sum()
}

/// Arithmetic mean (NaN for no data).
pub fn mean(x: &[f64]) -> f64 {
    if x.is_empty() {
        f64::NAN
    } else {
        x.iter().sum::<f64>() / x.len() as f64
    }
}

/// Sample standard deviation, divisor n − 1 (the paper's convention for Table 2, see
/// [`crate::study`]); NaN for fewer than two values.
pub fn sample_sd(x: &[f64]) -> f64 {
    if x.len() < 2 {
        return f64::NAN;
    }
    let m = mean(x);
    (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (x.len() - 1) as f64).sqrt()
}

/// A logarithmic trend line y = intercept + slope · ln x (least squares), as the trend lines of
/// the paper's Figure 12, with its coefficient of determination R².
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LogFit {
    /// a of y = a + b ln x.
    pub intercept: f64,
    /// b of y = a + b ln x.
    pub slope: f64,
    /// 1 − SS_res / SS_tot.
    pub r2: f64,
    /// Points used.
    pub n: usize,
}

impl LogFit {
    /// The trend at x.
    pub fn eval(&self, x: f64) -> f64 {
        self.intercept + self.slope * x.ln()
    }

    /// `y = 2.31 ln x + 4.12 (R² = 0.78, n = 22)`.
    pub fn describe(&self) -> String {
        let sign = if self.intercept < 0.0 { '−' } else { '+' };
        format!("y = {:.3} ln x {} {:.3} (R² = {:.3}, n = {})", self.slope, sign, self.intercept.abs(), self.r2, self.n)
    }
}

/// Least-squares y = a + b ln x over the points with x > 0 and finite y; `None` with fewer than
/// two such points or all x equal.
pub fn log_fit(points: &[(f64, f64)]) -> Option<LogFit> {
    let p: Vec<(f64, f64)> =
        points.iter().filter(|(x, y)| *x > 0.0 && x.is_finite() && y.is_finite()).map(|(x, y)| (x.ln(), *y)).collect();
    if p.len() < 2 {
        return None;
    }
    let n = p.len() as f64;
    let (mx, my) = (p.iter().map(|q| q.0).sum::<f64>() / n, p.iter().map(|q| q.1).sum::<f64>() / n);
    let sxx: f64 = p.iter().map(|q| (q.0 - mx).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = p.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum();
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let ss_tot: f64 = p.iter().map(|q| (q.1 - my).powi(2)).sum();
    let ss_res: f64 = p.iter().map(|q| (q.1 - intercept - slope * q.0).powi(2)).sum();
    let r2 = if ss_tot > 0.0 { 1.0 - ss_res / ss_tot } else { 1.0 };
    Some(LogFit { intercept, slope, r2, n: p.len() })
}

/// How many points a [`log_grid`] has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GridSize {
    /// Exactly this many points (both ends included).
    Points(usize),
    /// This many points per decade (rounded to a whole number of steps, at least one).
    PerDecade(usize),
}

/// A log-spaced grid from `lo` to `hi`, both included.
pub fn log_grid(lo: f64, hi: f64, size: GridSize) -> Vec<f64> {
    match size {
        GridSize::Points(0) => vec![],
        GridSize::Points(1) => vec![lo],
        GridSize::Points(n) => {
            (0..n).map(|i| if i + 1 == n { hi } else { lo * (hi / lo).powf(i as f64 / (n - 1) as f64) }).collect()
        }
        GridSize::PerDecade(per_decade) => {
            let decades = (hi / lo).log10();
            let steps = (decades * per_decade as f64).round().max(1.0) as usize;
            (0..=steps).map(|k| lo * 10f64.powf(decades * k as f64 / steps as f64)).collect()
        }
    }
}

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

/// The smallest and the largest of `values` (NaN values ignored, as [`f64::min`] and
/// [`f64::max`] do); (∞, −∞) when there is none.
pub fn min_max(values: impl IntoIterator<Item = f64>) -> (f64, f64) {
    values.into_iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)))
}

/// The root mean square √(Σ xᵢ² / n) of `x` (NaN for no data): the rms of differences, residuals
/// or biases.
pub fn root_mean_square(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
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

/// The x at which the piecewise-linear curve through `points` (in order of x) first crosses
/// `level` upwards: the first segment with y₀ < `level` ≤ y₁, interpolated linearly,
/// x₀ + (level − y₀)/(y₁ − y₀) · (x₁ − x₀). None if it never does.
pub fn upward_crossing(points: &[(f64, f64)], level: f64) -> Option<f64> {
    points.windows(2).find(|w| w[0].1 < level && w[1].1 >= level).map(|w| {
        let ((x0, a), (x1, b)) = (w[0], w[1]);
        x0 + (level - a) / (b - a) * (x1 - x0)
    })
}

/// The five-number summary of `x` without interpolation: the smallest value, the order
/// statistics at positions ⌊n/4⌋, ⌊n/2⌋ and ⌊3n/4⌋ of the sorted values (0-based: the lower
/// quartile, the median, the upper quartile) and the largest; None for no data.
pub fn five_numbers(x: &[f64]) -> Option<[f64; 5]> {
    let mut v = x.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some([*v.first()?, v[n / 4], v[n / 2], v[3 * n / 4], v[n - 1]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chi_square_tail_matches_its_closed_forms() {
        // Two degrees of freedom: P(χ² ≥ x) = exp(−x/2); one: erfc(√(x/2)), at x = 3.841 it is 0.05.
        for x in [0.1, 1.0, 4.0, 12.0] {
            assert!((chi_square_tail(x, 2) - (-x / 2.0).exp()).abs() < 1e-12, "{x}");
        }
        assert!((chi_square_tail(3.841_458_820_694_124, 1) - 0.05).abs() < 1e-9);
        assert_eq!(chi_square_tail(7.0, 0), 1.0);
    }

    #[test]
    fn wilson_interval_matches_a_hand_computation() {
        // k = 10, n = 100, z = 1.96: centre (0.1 + 0.019208)/1.038416 = 0.114798,
        // half-width 1.96·√(0.0009 + 0.00009604)/1.038416 = 0.059570 → (0.0552, 0.1744), the
        // textbook Wilson interval for 10/100.
        let (lo, hi) = wilson(10, 100, 1.96);
        assert!((lo - 0.055228).abs() < 1e-5, "{lo}");
        assert!((hi - 0.174368).abs() < 1e-5, "{hi}");
    }

    #[test]
    fn chi_square_of_a_perfect_fit_is_zero_and_p_is_one() {
        let (c, dof, p) = chi_square(&[100, 200, 300], &[1.0 / 6.0, 2.0 / 6.0, 3.0 / 6.0]);
        assert!(c.abs() < 1e-12 && dof == 2 && (p - 1.0).abs() < 1e-12);
        // Counts where the model gives probability 0: impossible, not ignored.
        let (c, _, p) = chi_square(&[50, 50, 3], &[0.5, 0.5, 0.0]);
        assert!(c.is_infinite() && p == 0.0, "{c} {p}");
        // 2 categories, O = (60, 40) vs E = (50, 50): χ² = 4, p = 0.0455.
        let (c, dof, p) = chi_square(&[60, 40], &[0.5, 0.5]);
        assert!((c - 4.0).abs() < 1e-12 && dof == 1 && (p - 0.0455).abs() < 1e-4, "{p}");
    }

    #[test]
    fn homogeneity_of_a_two_by_two_table_is_the_closed_form() {
        // χ² of a 2×2 table = N (ad − bc)² / (row and column products).
        let (a, b, c, d) = (30u64, 70u64, 45u64, 55u64);
        let n = (a + b + c + d) as f64;
        let closed = n * ((a * d) as f64 - (b * c) as f64).powi(2) / ((a + b) * (c + d) * (a + c) * (b + d)) as f64;
        let (chi2, dof, p) = chi_square_homogeneity(&[a, b, 0], &[c, d, 0]);
        assert!((chi2 - closed).abs() < 1e-12 && dof == 1, "{chi2} vs {closed}");
        // χ² = 4.8 on one degree of freedom: p = 0.0285.
        assert!((closed - 4.8).abs() < 1e-12 && (p - 0.0285).abs() < 1e-4, "{closed} {p}");
        assert_eq!(chi_square_homogeneity(&[5, 10], &[10, 20]).0, 0.0);
    }

    #[test]
    fn log_grids_hit_both_ends() {
        let g = log_grid(1e-3, 1.0, GridSize::Points(4));
        assert_eq!(g.len(), 4);
        assert!((g[1] - 1e-2).abs() < 1e-15 && g[3] == 1.0);
        let g = log_grid(1e-4, 1e-2, GridSize::PerDecade(5));
        assert_eq!(g.len(), 11);
        assert!((g[5] / 1e-3 - 1.0).abs() < 1e-12 && (g[10] / 1e-2 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn stuart_maxwell_of_two_categories_is_mcnemar() {
        // McNemar: b = 25 items change 0 → 1, c = 10 change 1 → 0: χ² = (25 − 10)² / 35.
        let (c, dof, p) = stuart_maxwell(&[vec![40, 25], vec![10, 60]]);
        assert!((c - 225.0 / 35.0).abs() < 1e-12 && dof == 1, "{c} {dof}");
        assert!((p - 0.01123).abs() < 1e-4, "{p}");
    }

    #[test]
    fn stuart_maxwell_sees_the_pairing_and_ignores_the_order_of_categories() {
        // A symmetric table has equal marginals: χ² = 0.
        let sym = [vec![50, 3, 4], vec![3, 40, 6], vec![4, 6, 30]];
        assert_eq!(stuart_maxwell(&sym).0, 0.0);
        // Permuting the categories (which one is left out changes) leaves χ² unchanged.
        let t = [vec![50, 9, 1], vec![2, 40, 8], vec![4, 1, 30]];
        let perm = [2usize, 0, 1];
        let tp: Vec<Vec<u64>> = perm.iter().map(|&i| perm.iter().map(|&j| t[i][j]).collect()).collect();
        let (a, b) = (stuart_maxwell(&t), stuart_maxwell(&tp));
        assert!(a.0 > 1.0 && (a.0 - b.0).abs() < 1e-9 * a.0 && a.1 == 2 && b.1 == 2, "{a:?} {b:?}");
        // Not vacuous: the same marginals as independent samples are far from significant, paired
        // they are: 10 items move 0 → 1 and none back, among 1000 that agree.
        let paired = [vec![500, 10], vec![0, 490]];
        let (_, _, p_paired) = stuart_maxwell(&paired);
        let (_, _, p_independent) = chi_square_homogeneity(&[510, 490], &[500, 500]);
        assert!(p_paired < 0.01 && p_independent > 0.5, "{p_paired} {p_independent}");
        // Methods that never disagree: no test.
        assert_eq!(stuart_maxwell(&[vec![5, 0], vec![0, 7]]), (0.0, 0, 1.0));
    }

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
    fn min_max_and_rms_match_hand_values() {
        assert_eq!(min_max([3.0, -1.5, f64::NAN, 2.0]), (-1.5, 3.0));
        assert_eq!(min_max(std::iter::empty()), (f64::INFINITY, f64::NEG_INFINITY));
        // √((9 + 16 + 0 + 1)/4) = √6.5.
        assert!((root_mean_square(&[3.0, -4.0, 0.0, 1.0]) - 6.5f64.sqrt()).abs() < 1e-15);
        assert!(root_mean_square(&[]).is_nan());
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

    #[test]
    fn upward_crossing_interpolates_the_first_rise() {
        // y = 0.1, 0.3, 0.7, 0.2, 0.9 at x = 0 … 4: ½ is crossed upward between x = 1 and 2 at
        // 1 + 0.2/0.4 = 1.5 (the later rise between 3 and 4 is not the first).
        let pts = [(0.0, 0.1), (1.0, 0.3), (2.0, 0.7), (3.0, 0.2), (4.0, 0.9)];
        assert_eq!(upward_crossing(&pts, 0.5), Some(1.5));
        // Already above at the start: the first rise from below counts (3 → 4 for 0.25).
        let x = upward_crossing(&pts[2..], 0.25).unwrap();
        assert!((x - (3.0 + 0.05 / 0.7)).abs() < 1e-12, "{x}");
        assert_eq!(upward_crossing(&pts, 0.95), None);
    }

    #[test]
    fn five_numbers_are_order_statistics() {
        // Sorted 1 … 8: positions 2, 4 and 6 (0-based) hold 3, 5 and 7.
        assert_eq!(five_numbers(&[8.0, 1.0, 5.0, 3.0, 7.0, 2.0, 6.0, 4.0]), Some([1.0, 3.0, 5.0, 7.0, 8.0]));
        assert_eq!(five_numbers(&[2.5]), Some([2.5; 5]));
        assert_eq!(five_numbers(&[]), None);
    }
}
