//! Two drop runs of the same releases compared drop by drop: two numerics, two engines, or two
//! settings of one, each run on the same drop indices (hence the same random streams, the same
//! releases). Pairing the outcomes makes the comparison far sharper than two independent
//! samples: a drop that ends in the same flock in both runs carries no evidence of a difference.
//!
//! * [`agreement`] — the Stuart–Maxwell test of marginal homogeneity of the paired per-flock
//!   outcomes ([`crate::stats::stuart_maxwell`]), and how many drops end in the same flock.
//! * [`chi_square_shares`] — which flocks drive the difference between two runs' per-flock
//!   counts: each one's share of Pearson's χ² of homogeneity.
//! * [`matching_drops`] — how many drops end alike in both runs: the same outcome record, facet
//!   or flock ([`Match`]).

use crate::dynamics::drops::launch::DropOutcome;
use crate::stats::stuart_maxwell;
use serde::Serialize;
use std::collections::BTreeMap;

/// Two runs of the same releases compared drop by drop, on the drops present and settled in
/// both with a known flock.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Agreement {
    /// Stuart–Maxwell statistic χ² = dᵀ S⁻¹ d of the paired flock table (0 when the runs never
    /// disagree).
    pub chi2: f64,
    /// Its degrees of freedom: the flocks on which the runs disagree at least once, less one.
    pub dof: usize,
    /// Its p-value under marginal homogeneity (1 when the runs never disagree).
    pub p: f64,
    /// Drops of `both` that ended in the same flock in the two runs.
    pub same: usize,
    /// Drops present and settled in both runs, with a known flock in each.
    pub both: usize,
}

/// [`Agreement`] of the runs `a` and `b` (outcomes by drop index) of the same releases: the
/// table n_ij of drops that ended in flock i in `a` and in flock j in `b` (flocks by
/// [`DropOutcome::flock_in`] of `facet_flock`, facet index → flock id), tested by
/// [`stuart_maxwell`]; same = Σ n_ii, both = Σ n_ij. Drops missing from either run, unsettled in
/// either, or without a flock are left out.
pub fn agreement(
    facet_flock: &[Option<usize>],
    a: &BTreeMap<u64, DropOutcome>,
    b: &BTreeMap<u64, DropOutcome>,
) -> Agreement {
    let pairs: Vec<(usize, usize)> = a
        .iter()
        .filter_map(|(i, x)| {
            let y = b.get(i)?;
            (x.settled && y.settled).then_some(())?;
            Some((x.flock_in(facet_flock)?, y.flock_in(facet_flock)?))
        })
        .collect();
    // Flocks no pair reaches would be rows and columns of zeros, which the test leaves out.
    let k = pairs.iter().map(|&(x, y)| x.max(y) + 1).max().unwrap_or(0);
    let mut table = vec![vec![0u64; k]; k];
    for &(x, y) in &pairs {
        table[x][y] += 1;
    }
    let (chi2, dof, p) = stuart_maxwell(&table);
    let same = pairs.iter().filter(|(x, y)| x == y).count();
    Agreement { chi2, dof, p, same, both: pairs.len() }
}

/// Each category's share (%) of Pearson's χ² statistic of homogeneity of the counts `a` and `b`
/// over the same categories (e.g. two runs' per-flock counts): category c contributes
/// Σ_s (o_sc − e_sc)² / e_sc with e_sc = n_s (a_c + b_c) / (n_a + n_b), 0 when empty in both.
/// The shares sum to 100 unless the statistic is 0 (then all are 0).
pub fn chi_square_shares(a: &[u64], b: &[u64]) -> Vec<f64> {
    let (na, nb) = (a.iter().sum::<u64>() as f64, b.iter().sum::<u64>() as f64);
    let chi: Vec<f64> = a
        .iter()
        .zip(b)
        .map(|(&x, &y)| {
            let col = (x + y) as f64;
            let term = |o: f64, row: f64| (o - row * col / (na + nb)).powi(2) / (row * col / (na + nb));
            if col == 0.0 {
                0.0
            } else {
                term(x as f64, na) + term(y as f64, nb)
            }
        })
        .collect();
    let total = chi.iter().sum::<f64>().max(f64::MIN_POSITIVE);
    chi.iter().map(|c| 100.0 * c / total).collect()
}

/// What of two outcomes of the same release [`matching_drops`] compares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Match {
    /// The whole outcome record: facet, flock, times and heights (floats as values).
    Record,
    /// The facet it ended on (none in both counts as the same).
    Facet,
    /// The flock it ended in ([`DropOutcome::flock_in`]; none in both counts as the same).
    Flock,
}

/// The drops of run `a` whose outcome in run `b` of the same releases (the same drop index)
/// matches at `level`, flocks by `facet_flock` (facet index → flock id); drops missing from `b`
/// do not count. Unlike [`agreement`], every drop counts, settled or not.
pub fn matching_drops(
    facet_flock: &[Option<usize>],
    a: &BTreeMap<u64, DropOutcome>,
    b: &BTreeMap<u64, DropOutcome>,
    level: Match,
) -> usize {
    let same = |x: &DropOutcome, y: &DropOutcome| match level {
        Match::Record => x == y,
        Match::Facet => x.facet == y.facet,
        Match::Flock => x.flock_in(facet_flock) == y.flock_in(facet_flock),
    };
    a.iter().filter(|(i, x)| b.get(i).is_some_and(|y| same(x, y))).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Facets 0, 1, 2 in flocks 0, 1, 1; facet 3 in none.
    const FACET_FLOCK: [Option<usize>; 4] = [Some(0), Some(1), Some(1), None];

    fn run(facets: &[(bool, u32)]) -> BTreeMap<u64, DropOutcome> {
        let outcome = |(i, &(settled, facet)): (usize, &(bool, u32))| DropOutcome {
            settled,
            ..DropOutcome::at_rest(i as u64, facet, 1.0)
        };
        facets.iter().enumerate().map(outcome).map(|o| (o.index, o)).collect()
    }

    #[test]
    fn a_run_agrees_with_itself() {
        let a = run(&[(true, 0), (true, 1), (true, 2), (false, 0), (true, 3), (true, 1)]);
        // Four settled drops with a flock (facet 3 has none, drop 3 did not settle).
        let same = Agreement { chi2: 0.0, dof: 0, p: 1.0, same: 4, both: 4 };
        assert_eq!(agreement(&FACET_FLOCK, &a, &a), same);
    }

    #[test]
    fn two_flocks_give_mcnemar() {
        // Paired table [[5, 3], [1, 7]]: McNemar's χ² = (3 − 1)² / (3 + 1) = 1 on 1 dof, whose
        // tail is erfc(1/√2) = 0.317 310 507 9.
        let mut pairs = vec![((true, 0), (true, 0)); 5];
        pairs.extend([((true, 0), (true, 1)); 3]);
        pairs.extend([((true, 1), (true, 0)); 1]);
        // Facets 1 and 2 are both flock 1.
        pairs.extend([((true, 2), (true, 1)); 7]);
        // Left out: unsettled in one run, and a drop missing from the second run.
        pairs.extend([((false, 0), (true, 1)), ((true, 1), (false, 0))]);
        let (mut a, b) =
            (run(&pairs.iter().map(|p| p.0).collect::<Vec<_>>()), run(&pairs.iter().map(|p| p.1).collect::<Vec<_>>()));
        a.insert(99, DropOutcome { index: 99, ..a[&0] });
        let r = agreement(&FACET_FLOCK, &a, &b);
        assert_eq!((r.dof, r.same, r.both), (1, 12, 16));
        assert!((r.chi2 - 1.0).abs() < 1e-12 && (r.p - 0.317_310_507_9).abs() < 1e-6, "{r:?}");
    }

    #[test]
    fn a_certified_flock_counts_as_its_flock() {
        let a = run(&[(true, 0), (true, 1)]);
        let mut b = a.clone();
        // The certificate decided flock 1 for drop 0 (no facet): a disagreement, as for facet 1.
        b.insert(0, DropOutcome { facet: None, flock: Some(1), certified: true, ..a[&0] });
        let r = agreement(&FACET_FLOCK, &a, &b);
        assert_eq!((r.same, r.both, r.dof), (1, 2, 1));
        assert!((r.chi2 - 1.0).abs() < 1e-12); // McNemar (1 − 0)² / (1 + 0)
    }

    #[test]
    fn drops_match_by_record_facet_or_flock() {
        let a = run(&[(true, 0), (true, 1), (true, 2), (false, 3)]);
        let mut b = a.clone();
        // Drop 1 ends on facet 2 (the same flock 1), drop 3 lasts longer, drop 2 is missing.
        b.insert(1, DropOutcome { facet: Some(2), ..a[&1] });
        b.insert(3, DropOutcome { time: 2.0, ..a[&3] });
        b.remove(&2);
        let count = |level| matching_drops(&FACET_FLOCK, &a, &b, level);
        assert_eq!([count(Match::Record), count(Match::Facet), count(Match::Flock)], [1, 2, 3]);
    }

    #[test]
    fn shares_of_a_hand_computed_chi_square() {
        // a = (10, 0, 5), b = (5, 5, 5): expected 7.5, 2.5, 5 in each sample, so the terms are
        // 2 · 2.5²/7.5 = 5/3, 2 · 2.5²/2.5 = 5 and 0 (total 20/3), and the empty category 0.
        let shares = chi_square_shares(&[10, 0, 5, 0], &[5, 5, 5, 0]);
        for (s, want) in shares.iter().zip([25.0, 75.0, 0.0, 0.0]) {
            assert!((s - want).abs() < 1e-12, "{shares:?}");
        }
        // Identical samples: no χ², no share.
        assert_eq!(chi_square_shares(&[3, 4], &[3, 4]), vec![0.0, 0.0]);
    }
}
