//! Calibrating the two-tolerance hand experimenter on the paper's Table 2, with the roughness
//! of the synthetic pebbles fitted alongside, and the leave-one-sample-out check.
//!
//! What is fitted to what:
//!
//! * **The tolerances** (ν̃_S, s_S, ν̃_U, s_U) to the hand columns E(S), E(U), σ(S), σ(U) of the
//!   22 samples ([`fit_hand`]), the synthetic pebbles of each sample standing for its 50.
//! * **The roughness** of the synthetic pebbles ([`crate::generate::pebble`]'s amplitude) by a
//!   profile over a grid: at each roughness the populations are generated, the tolerances
//!   fitted, and the total loss is the hand χ² plus the χ² of the synthetic pebbles at the
//!   paper's ν = 0.0035 against the paper's *computer* columns of the five scanned samples
//!   (real scans counted at 0.0035, 20 each). Those columns say how many equilibria real scans
//!   have at a given ν, so they tie the synthetic pebbles' micro-structure to real scans: the
//!   tolerances fitted on synthetic pebbles then mean the same on a real scan. The roughness
//!   estimate is the vertex of the parabola through the lowest grid point and its neighbours;
//!   its interval is where the profile stays within s² = max(1, χ²/dof) of the minimum.
//!
//! Both sets of columns are Table 2's; nothing else is fitted.

use super::fit_hand::{fit_hand, population_moments, HandFit, SampleFit};
use super::fit_nu::{curves_by_sample, fit_nu, FitOptions, HandSample, NuFit};
use super::hand::HandExperimenter;
use super::synthetic::{synthetic_study, PopulationParams, SampleTarget};
use super::CountCurve;
use crate::analysis::PAPER_NU;
use crate::{Error, Result};
use rayon::prelude::*;
use serde::Serialize;

/// The synthetic count curves of every Table 2 sample at one roughness.
#[derive(Clone, Debug)]
pub struct Populations {
    /// The roughness amplitude they were generated with.
    pub roughness: f64,
    /// `curves[i]`: the pebbles standing for sample i.
    pub curves: Vec<Vec<CountCurve>>,
}

/// Generate the populations of `hand` at every roughness of `roughness` (the other population
/// parameters from `params`).
pub fn table2_populations(
    hand: &[HandSample],
    params: &PopulationParams,
    roughness: &[f64],
) -> Result<Vec<Populations>> {
    let targets: Vec<SampleTarget> = hand.iter().map(|h| h.target()).collect();
    roughness
        .iter()
        .map(|&r| {
            let study =
                synthetic_study(&targets, &PopulationParams { roughness: r, ..params.clone() }, PAPER_NU, None)?;
            let by = curves_by_sample(&study);
            let curves = hand.iter().map(|h| by.get(&h.id).cloned().unwrap_or_default()).collect();
            Ok(Populations { roughness: r, curves })
        })
        .collect()
}

/// The fit at one roughness.
#[derive(Clone, Debug, Serialize)]
pub struct RoughnessFit {
    /// The roughness amplitude.
    pub roughness: f64,
    /// The tolerances fitted to the hand columns.
    pub fit: HandFit,
    /// The synthetic pebbles at ν = 0.0035 against the paper's computer columns (scanned
    /// samples only).
    pub computer: Vec<SampleFit>,
    /// Σ χ² of `computer`.
    pub chi2_computer: f64,
    /// Hand χ² + computer χ²: the profile loss.
    pub total: f64,
}

/// The synthetic pebbles counted at the paper's ν against the computer columns.
pub fn computer_fit(hand: &[HandSample], curves: &[Vec<CountCurve>]) -> Vec<SampleFit> {
    let paper = HandExperimenter::one_nu(PAPER_NU);
    hand.iter()
        .zip(curves)
        .filter_map(|(h, c)| {
            let (computer, n) = (h.computer?, h.n_computer?);
            let as_measured = HandSample { hand: computer, n, ..h.clone() };
            Some(SampleFit::of(&as_measured, population_moments(c, &paper)))
        })
        .collect()
}

/// The calibration on Table 2.
#[derive(Clone, Debug, Serialize)]
pub struct Table2HandFit {
    /// The fit at every roughness of the grid.
    pub profile: Vec<RoughnessFit>,
    /// Index of the grid roughness with the lowest total: its tolerances are the calibration.
    pub best: usize,
    /// The roughness estimate (parabola vertex; the grid value at an end of the grid).
    pub roughness: f64,
    /// {r : total(r) ≤ min + s²}, linearly interpolated on the grid (grid ends if not crossed).
    pub roughness_interval: (f64, f64),
    /// The roughness minimum is at an end of the grid.
    pub at_edge: bool,
    /// Statistics fitted (hand and computer) and degrees of freedom (terms − 5).
    pub terms: usize,
    /// terms − 5: the four tolerance parameters and the roughness.
    pub dof: usize,
    /// The paper's one-ν experimenter fitted on the same populations at the chosen roughness.
    pub one_nu: NuFit,
    /// [δ_S, δ_U] at the chosen roughness ([`scan_frame_shift`]): how far (decades) the synthetic
    /// pebbles' ν must be moved to count like the real scans of the computer columns.
    pub scan_shift: [f64; 2],
}

impl Table2HandFit {
    /// The fit at the chosen roughness.
    pub fn chosen(&self) -> &RoughnessFit {
        &self.profile[self.best]
    }

    /// The fitted experimenter moved into the real scans' frame: each median divided by
    /// 10^δ of [`Table2HandFit::scan_shift`]. An alternative reading, not the fit: it assumes
    /// the synthetic and the real count curves differ by that one shift at every ν, which
    /// Table 2 (one ν of real scans) cannot check.
    pub fn in_scan_frame(&self) -> HandExperimenter {
        let e = self.chosen().fit.experimenter;
        let shift = |t: super::Tolerance, d: f64| super::Tolerance { median: t.median / 10f64.powf(d), ..t };
        HandExperimenter {
            stable: shift(e.stable, self.scan_shift[0]),
            unstable: shift(e.unstable, self.scan_shift[1]),
        }
    }
}

/// For S and for U, the shift δ (decades, on a grid of 0.025 from −1 to 1) at which the
/// synthetic pebbles counted at ν = 0.0035·10^δ best match the computer columns (real scans at
/// 0.0035): the χ² of that count's E and σ over the scanned samples, least. δ = 0 when the
/// synthetic pebbles count like the scans; δ > 0 when they need a larger ν to.
pub fn scan_frame_shift(hand: &[HandSample], curves: &[Vec<CountCurve>]) -> [f64; 2] {
    let grid: Vec<f64> = (-40..=40).map(|i| i as f64 * 0.025).collect();
    let fits: Vec<Vec<SampleFit>> = grid
        .iter()
        .map(|d| {
            let nu = PAPER_NU * 10f64.powf(*d);
            hand.iter()
                .zip(curves)
                .filter_map(|(h, c)| {
                    let as_measured = HandSample { hand: h.computer?, n: h.n_computer?, ..h.clone() };
                    Some(SampleFit::of(&as_measured, population_moments(c, &HandExperimenter::one_nu(nu))))
                })
                .collect()
        })
        .collect();
    std::array::from_fn(|k| {
        let chi2 = |f: &Vec<SampleFit>| f.iter().map(|s| s.z[k].powi(2) + s.z[k + 2].powi(2)).sum::<f64>();
        let best = (0..grid.len()).min_by(|&a, &b| chi2(&fits[a]).total_cmp(&chi2(&fits[b]))).unwrap_or(40);
        grid[best]
    })
}

/// How a person's counts compare with the real scans' counts at ν = 0.0035, without synthetic
/// pebbles: over the samples with both (Table 2's five scanned samples), the mean of
/// E_hand − E_scans for S and for U, with its standard error √(Σ σ_h²/n_h + σ_c²/n_c) / k.
/// Near zero: on real scans the person counts like the hierarchy at the paper's ν. None without
/// such samples.
pub fn hand_minus_scans(hand: &[HandSample]) -> Option<[(f64, f64); 2]> {
    let both: Vec<(&HandSample, [f64; 4], usize)> =
        hand.iter().filter_map(|h| Some((h, h.computer?, h.n_computer?))).collect();
    if both.is_empty() {
        return None;
    }
    let k = both.len() as f64;
    Some(std::array::from_fn(|i| {
        let diff = both.iter().map(|(h, c, _)| h.hand[i] - c[i]).sum::<f64>() / k;
        let var: f64 =
            both.iter().map(|(h, c, n)| h.hand[i + 2].powi(2) / h.n as f64 + c[i + 2].powi(2) / *n as f64).sum();
        (diff, var.sqrt() / k)
    }))
}

/// Fit the tolerances at every roughness of `pops` and choose the roughness (see the module
/// documentation).
pub fn fit_hand_table2(hand: &[HandSample], pops: &[Populations]) -> Result<Table2HandFit> {
    if pops.is_empty() {
        return Err(Error::Fit("hand experimenter: no roughness to fit".into()));
    }
    let profile: Vec<RoughnessFit> = pops
        .par_iter()
        .map(|p| {
            let fit = fit_hand(hand, &p.curves)?;
            let computer = computer_fit(hand, &p.curves);
            let chi2_computer = computer.iter().map(|s| s.chi2).sum();
            Ok(RoughnessFit { roughness: p.roughness, total: fit.chi2 + chi2_computer, fit, computer, chi2_computer })
        })
        .collect::<Result<_>>()?;
    let best = (0..profile.len()).min_by(|&a, &b| profile[a].total.total_cmp(&profile[b].total)).unwrap_or(0);
    let terms = profile[best].fit.terms + 4 * profile[best].computer.len();
    let dof = terms.saturating_sub(5).max(1);
    let (r, loss): (Vec<f64>, Vec<f64>) = profile.iter().map(|p| (p.roughness, p.total)).unzip();
    let (roughness, at_edge) = vertex(&r, &loss, best);
    let scale = (profile[best].total / dof as f64).max(1.0);
    let roughness_interval = crossing(&r, &loss, best, loss[best] + scale);
    let one_opts = FitOptions { bootstrap: 0, ..FitOptions::default() };
    let one_nu = fit_nu(hand, &pops[best].curves, &one_opts)?;
    let scan_shift = scan_frame_shift(hand, &pops[best].curves);
    Ok(Table2HandFit { profile, best, roughness, roughness_interval, at_edge, terms, dof, one_nu, scan_shift })
}

/// The vertex of the parabola through the grid minimum `i` and its neighbours (linear
/// roughness), or the grid value at an end.
fn vertex(x: &[f64], y: &[f64], i: usize) -> (f64, bool) {
    if i == 0 || i + 1 >= x.len() {
        return (x[i], true);
    }
    let (x0, x1, x2, y0, y1, y2) = (x[i - 1], x[i], x[i + 1], y[i - 1], y[i], y[i + 1]);
    let num = (x1 - x0).powi(2) * (y1 - y2) - (x1 - x2).powi(2) * (y1 - y0);
    let den = (x1 - x0) * (y1 - y2) - (x1 - x2) * (y1 - y0);
    if den == 0.0 {
        return (x1, false);
    }
    ((x1 - 0.5 * num / den).clamp(x0, x2), false)
}

/// The range around the minimum `i` where y ≤ `level` (linear interpolation; grid ends if the
/// level is never crossed).
fn crossing(x: &[f64], y: &[f64], i: usize, level: f64) -> (f64, f64) {
    let cross = |j: usize, k: usize| x[j] + (level - y[j]) / (y[k] - y[j]) * (x[k] - x[j]);
    let lo = (1..=i).rev().find(|&j| y[j - 1] > level).map_or(x[0], |j| cross(j, j - 1));
    let hi = (i..x.len() - 1).find(|&j| y[j + 1] > level).map_or(x[x.len() - 1], |j| cross(j, j + 1));
    (lo, hi)
}

/// The paper's one-ν experimenter at `nu` against the hand columns, sample by sample.
pub fn one_nu_fits(hand: &[HandSample], curves: &[Vec<CountCurve>], nu: f64) -> Vec<SampleFit> {
    let one = HandExperimenter::one_nu(nu);
    hand.iter().zip(curves).map(|(h, c)| SampleFit::of(h, population_moments(c, &one))).collect()
}

/// A scan's name, its (S, U) at the paper's ν = 0.0035 and an experimenter's distribution.
pub type ScanCounts = (String, (usize, usize), super::CountDistribution);

/// What `exp` reports for each scan of `files` ([`ScanCounts`]).
pub fn scans_counted(files: &[std::path::PathBuf], exp: &HandExperimenter) -> Result<Vec<ScanCounts>> {
    files
        .iter()
        .map(|f| {
            let a = crate::analysis::Analysis::of_file(f, &crate::analysis::Options::default())?;
            let curve = CountCurve::of(&a.hierarchy);
            let (k, name) = (curve.at(PAPER_NU), f.file_name().unwrap_or_default().to_string_lossy().into_owned());
            Ok((name, (k.stable, k.unstable), exp.counts(&curve)))
        })
        .collect()
}

/// Model against Table 2 for every Table 2 sample that is a sample of the study (by name): the
/// moments of its hand columns ([`super::summarize`]'s `hand`) against the hand columns.
pub fn compare_hand(hand: &[HandSample], study: &super::Study) -> Vec<SampleFit> {
    let summaries = super::summarize(study);
    hand.iter()
        .filter_map(|h| {
            let s = summaries.iter().find(|s| s.sample == h.id && s.pebbles > 0)?;
            Some(SampleFit::of(h, s.hand))
        })
        .collect()
}

/// One sample predicted by the experimenter fitted on the other samples.
#[derive(Clone, Debug, Serialize)]
pub struct LeftOut {
    /// The roughness chosen without the sample.
    pub roughness: f64,
    /// The tolerances fitted without the sample.
    pub experimenter: HandExperimenter,
    /// The prediction against the sample's hand columns.
    pub prediction: SampleFit,
}

/// Leave one sample out: for every sample, the whole calibration (tolerances and roughness)
/// on the other samples' hand and computer columns, then its hand columns predicted.
pub fn leave_one_sample_out(hand: &[HandSample], pops: &[Populations]) -> Result<Vec<LeftOut>> {
    (0..hand.len())
        .into_par_iter()
        .map(|i| {
            let keep = |v: &[Vec<CountCurve>]| -> Vec<Vec<CountCurve>> {
                v.iter().enumerate().filter(|(j, _)| *j != i).map(|(_, c)| c.clone()).collect()
            };
            let others: Vec<HandSample> =
                hand.iter().enumerate().filter(|(j, _)| *j != i).map(|(_, h)| h.clone()).collect();
            let fits: Vec<(f64, HandFit)> = pops
                .iter()
                .map(|p| {
                    let curves = keep(&p.curves);
                    let fit = fit_hand(&others, &curves)?;
                    let computer: f64 = computer_fit(&others, &curves).iter().map(|s| s.chi2).sum();
                    Ok((fit.chi2 + computer, fit))
                })
                .collect::<Result<_>>()?;
            let k = (0..fits.len()).min_by(|&a, &b| fits[a].0.total_cmp(&fits[b].0)).unwrap_or(0);
            let experimenter = fits[k].1.experimenter;
            let prediction = SampleFit::of(&hand[i], population_moments(&pops[k].curves[i], &experimenter));
            Ok(LeftOut { roughness: pops[k].roughness, experimenter, prediction })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_vertex_and_the_crossing_of_a_parabola() {
        // y = 10 (x − 0.27)² · 100 + 50 on a grid: vertex 0.27; y ≤ 60 for |x − 0.27| ≤ 0.1.
        let x = [0.1, 0.2, 0.3, 0.4, 0.5];
        let y: Vec<f64> = x.iter().map(|&v: &f64| 1000.0 * (v - 0.27).powi(2) + 50.0).collect();
        let (v, edge) = vertex(&x, &y, 2);
        assert!((v - 0.27).abs() < 1e-12 && !edge, "{v}");
        let (lo, hi) = crossing(&x, &y, 2, 60.0);
        // Linear interpolation between grid points: lo between 0.1 and 0.2, hi between 0.3 and 0.4.
        assert!(lo > 0.1 && lo < 0.2 && hi > 0.3 && hi < 0.4, "{lo} {hi}");
        assert_eq!(vertex(&x, &y, 0), (0.1, true));
    }

    #[test]
    fn hand_minus_scans_by_hand() {
        let sample = |hand: [f64; 4], computer: Option<[f64; 4]>| HandSample {
            id: "x".into(),
            location: String::new(),
            rock_type: String::new(),
            n: 50,
            hand,
            c_over_b: 0.7,
            c_over_a: 0.5,
            computer,
            n_computer: computer.map(|_| 20),
        };
        let h = [
            sample([3.0, 4.0, 1.0, 2.0], Some([2.5, 4.5, 2.0, 1.0])),
            sample([2.0, 3.0, 1.0, 1.0], Some([2.5, 3.0, 1.0, 1.0])),
            sample([9.0, 9.0, 1.0, 1.0], None),
        ];
        // S: (0.5 − 0.5)/2 = 0, √(1/50 + 4/20 + 1/50 + 1/20)/2 = √0.29/2; U: (−0.5 + 0)/2.
        let [s, u] = hand_minus_scans(&h).unwrap();
        assert!(s.0.abs() < 1e-12 && (s.1 - 0.29f64.sqrt() / 2.0).abs() < 1e-12, "{s:?}");
        assert!(
            (u.0 + 0.25).abs() < 1e-12
                && (u.1 - (4.0 / 50.0 + 1.0 / 20.0 + 1.0 / 50.0 + 1.0 / 20.0f64).sqrt() / 2.0).abs() < 1e-12
        );
        assert_eq!(hand_minus_scans(&h[2..]), None);
    }
}
