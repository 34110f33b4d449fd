//! Goodness of fit and homogeneity of counts: Pearson's χ² against probabilities, the χ² of
//! homogeneity of two samples, the Stuart–Maxwell test of paired outcomes, the KL divergence, and
//! the tails of the χ² and binomial distributions.

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

/// P(X ≥ `k`) for X ~ Binomial(`n`, `p`): the chance of at least k successes in n trials, e.g.
/// of at least k p-values under 0.05 among n tests of true hypotheses by chance alone (crate
/// `statrs`). 1 for k = 0; NaN for a p outside [0, 1].
pub fn binomial_at_least(k: u64, n: u64, p: f64) -> f64 {
    use statrs::distribution::{Binomial, DiscreteCDF};
    match Binomial::new(p, n) {
        Err(_) => f64::NAN,
        Ok(_) if k == 0 => 1.0,
        Ok(b) => b.sf(k - 1),
    }
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
    fn binomial_tail_against_hand_computed_sums() {
        // Three fair coins: P(X ≥ 2) = (3 + 1)/8; at least none is certain, four impossible.
        assert!((binomial_at_least(2, 3, 0.5) - 0.5).abs() < 1e-12);
        assert_eq!(binomial_at_least(0, 3, 0.5), 1.0);
        assert!(binomial_at_least(4, 3, 0.5).abs() < 1e-12);
        // At least one of 10 tests under 0.05 by chance: 1 − 0.95¹⁰.
        assert!((binomial_at_least(1, 10, 0.05) - (1.0 - 0.95f64.powi(10))).abs() < 1e-12);
        assert!(binomial_at_least(1, 10, 1.5).is_nan());
    }
}
