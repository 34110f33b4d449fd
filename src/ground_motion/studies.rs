//! Repeated studies of a fragility surface ([`super::fragility`]): the runs of an ensemble
//! whose members are shaken by every record × scale, and how often the 95 % bands fitted in
//! repeated studies cover the surface they estimate.

use super::fragility::{FragilitySurface, Run, Target};
use crate::{Error, Result};

/// The runs of the members `members` of an ensemble shaken by every case of `cases`, each case its
/// (PGA in g, PGV/PGA in s), member by member and case by case: `overturned[m][k]` says whether
/// case k overturned member m. With the member of each run: its cluster for
/// [`FragilitySurface::cluster_robust`]. An error if `overturned` lacks a member or a case.
pub fn member_runs(
    cases: &[(f64, f64)],
    overturned: &[Vec<bool>],
    members: std::ops::Range<u64>,
) -> Result<(Vec<Run>, Vec<u64>)> {
    let mut out = (Vec::new(), Vec::new());
    for m in members {
        let outcome = overturned.get(m as usize).filter(|o| o.len() >= cases.len()).ok_or_else(|| {
            Error::Fit(format!("ensemble runs: member {m} has no outcome for each of the {} cases", cases.len()))
        })?;
        for (&(pga_g, pgv_over_pga_s), &overturned) in cases.iter().zip(outcome) {
            out.0.push(Run { pga_g, pgv_over_pga_s, overturned });
            out.1.push(m);
        }
    }
    Ok(out)
}

/// How often fitted bands cover a known surface, counted over repeated studies: for each study s
/// of `0..studies` (run in parallel) `fits(s)` gives the study's fits, one per kind of band in a
/// fixed order (say a fit and its [`FragilitySurface::cluster_robust`] variant). Returns, for
/// each kind k and each target i of `targets`, the number of studies whose fit k covers
/// `truth`'s value of target i ([`Target::covered`]). The error of the first failing study in
/// order, if any; an error too if `truth` has no contour a target asks for, or the studies give
/// different numbers of fits.
pub fn coverage_counts<F>(targets: &[Target], truth: &FragilitySurface, studies: u64, fits: F) -> Result<Vec<Vec<u64>>>
where
    F: Fn(u64) -> Result<Vec<FragilitySurface>> + Sync,
{
    use rayon::prelude::*;
    if let Some(t) = targets.iter().find(|t| matches!(t, Target::Contour(p, r) if truth.pga_at(*p, *r).is_none())) {
        return Err(Error::Fit(format!("a coverage count: the truth has no contour for the target {t}")));
    }
    let covered: Vec<Vec<Vec<bool>>> = (0..studies)
        .into_par_iter()
        .map(|s| Ok(fits(s)?.iter().map(|f| targets.iter().map(|t| t.covered(f, truth)).collect()).collect()))
        .collect::<Result<_>>()?;
    let kinds = covered.first().map_or(0, Vec::len);
    if covered.iter().any(|c| c.len() != kinds) {
        return Err(Error::Fit("a coverage count: the studies gave different numbers of fits".into()));
    }
    let count = |k: usize, i: usize| covered.iter().filter(|c| c[k][i]).count() as u64;
    Ok((0..kinds).map(|k| (0..targets.len()).map(|i| count(k, i)).collect()).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn member_runs_lay_out_members_by_cases_with_their_clusters() {
        let cases = [(0.1, 0.2), (0.3, 0.4)];
        let outcome = vec![vec![false, true], vec![true, true], vec![false, false]];
        let (runs, members) = member_runs(&cases, &outcome, 1..3).unwrap();
        let run = |pga_g, pgv_over_pga_s, overturned| Run { pga_g, pgv_over_pga_s, overturned };
        assert_eq!(runs, [run(0.1, 0.2, true), run(0.3, 0.4, true), run(0.1, 0.2, false), run(0.3, 0.4, false)]);
        assert_eq!(members, [1, 1, 2, 2]);
        assert!(member_runs(&cases, &outcome, 2..4).is_err());
        assert!(member_runs(&[(0.1, 0.2); 3], &outcome, 0..1).is_err());
    }

    #[test]
    fn coverage_counts_each_kind_of_band_on_each_target() {
        // As in the covered-target test below, a fit with variance s² on β₀ alone covers a truth
        // off by 1.9 s on β₀ and misses one off by 2.0 s, at a point and on a contour: band 0 of
        // the even studies (0, 2, 4) covers. Band 1, a fit with no band off by 0.5 s, never does.
        let (beta, s) = ([1.0, 2.0, 0.5], 0.5);
        let fit =
            FragilitySurface { covariance: [[s * s, 0.0, 0.0], [0.0; 3], [0.0; 3]], ..FragilitySurface::exact(beta) };
        let off = |d: f64| [beta[0] + d * s, beta[1], beta[2]];
        let targets = [Target::Point(0.3, 0.1), Target::Contour(0.5, 0.1)];
        let studies = |study: u64| {
            let d = if study % 2 == 0 { 1.9 } else { 2.0 };
            Ok(vec![FragilitySurface { beta: off(d), ..fit }, FragilitySurface::exact(off(0.5))])
        };
        let counts = coverage_counts(&targets, &FragilitySurface::exact(beta), 5, studies).unwrap();
        assert_eq!(counts, vec![vec![3, 3], vec![0, 0]]);
        // A truth with no contour, and studies that disagree on their number of fits, are errors.
        let flat = FragilitySurface::exact([1.0, -1.0, 0.0]);
        assert!(coverage_counts(&targets, &flat, 5, |_| Ok(vec![fit])).is_err());
        let ragged = |study: u64| Ok(vec![fit; 1 + study as usize % 2]);
        assert!(coverage_counts(&targets, &fit, 5, ragged).is_err());
    }
}
