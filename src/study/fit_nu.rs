//! Table 2 and the fit of ν: the ν at which synthetic populations reproduce the hand columns
//! E(S), E(U), σ(S), σ(U) best, and the hand-vs-computed comparison of Figure 12.

use super::field::{summarize, Study};
use super::metadata::describe_csv_error;
use super::synthetic::{synthetic_study, PopulationParams, SampleTarget};
use super::{CountCurve, Moments};
use crate::analysis::PAPER_NU;
use crate::rng::item_rng;
use crate::stats::{log_fit, log_grid, mean, root_mean_square, sample_sd, GridSize, LogFit};
use crate::{Error, Result};
use rand::RngExt;
use rand_distr::StandardNormal;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// One sample of the paper's Table 2 (`data/table2_hand_experiments.csv`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HandSample {
    /// Sample id.
    pub id: String,
    /// Where the sample was collected.
    pub location: String,
    /// Rock type of the sample.
    pub rock_type: String,
    /// Pebbles counted by hand.
    pub n: usize,
    /// [E(S), E(U), σ(S), σ(U)] of the hand experiments.
    pub hand: [f64; 4],
    /// Mean ratio c/b of the sample.
    pub c_over_b: f64,
    /// Mean ratio c/a of the sample.
    pub c_over_a: f64,
    /// The paper's computer experiments at ν = 0.0035 (the 5 scanned samples only).
    pub computer: Option<[f64; 4]>,
    /// Pebbles of the paper's computer experiments (the 5 scanned samples only).
    pub n_computer: Option<usize>,
}

impl HandSample {
    /// The synthetic target with this sample's mean ratios.
    pub fn target(&self) -> SampleTarget {
        SampleTarget { name: self.id.clone(), c_over_b: self.c_over_b, c_over_a: self.c_over_a }
    }

    /// Standard errors of [E(S), E(U), σ(S), σ(U)]: σ/√n for the means, σ/√(2(n − 1)) for the
    /// standard deviations (normal approximation).
    pub fn standard_errors(&self) -> [f64; 4] {
        standard_errors(&self.hand, self.n)
    }

    /// The standard errors of [`HandSample::standard_errors`] for statistics `m` of `n` pebbles.
    pub fn standard_errors_of(m: &[f64; 4], n: usize) -> [f64; 4] {
        standard_errors(m, n)
    }
}

pub(crate) fn standard_errors(m: &[f64; 4], n: usize) -> [f64; 4] {
    let n = n.max(2) as f64;
    [m[2] / n.sqrt(), m[3] / n.sqrt(), m[2] / (2.0 * (n - 1.0)).sqrt(), m[3] / (2.0 * (n - 1.0)).sqrt()]
}

/// The paper's Table 2 as bundled with the project (`data/table2_hand_experiments.csv`, see
/// `data/README.md`), compiled into the library: the table `rocking study fit-nu` fits by default.
pub const TABLE2_CSV: &str = include_str!("../../data/table2_hand_experiments.csv");

/// The name errors give the bundled Table 2.
pub const TABLE2_NAME: &str = "table2_hand_experiments.csv (bundled)";

/// The bundled Table 2 ([`TABLE2_CSV`]), read as [`read_table2`] reads a file.
pub fn bundled_table2() -> Result<Vec<HandSample>> {
    parse_table2(TABLE2_CSV, Path::new(TABLE2_NAME))
}

/// Read Table 2: columns `id, location, n_hand, n_computer, rock_type, mean_b_mm, ES_hand,
/// ES_computer, EU_hand, EU_computer, sS_hand, sS_computer, sU_hand, sU_computer, c_over_b,
/// c_over_a` (computer columns may be empty).
pub fn read_table2(path: &Path) -> Result<Vec<HandSample>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::Io { path: path.into(), error: e })?;
    parse_table2(&text, path)
}

/// Parse the text of a Table 2 CSV (see [`read_table2`]); `path` names it in errors.
pub fn parse_table2(text: &str, path: &Path) -> Result<Vec<HandSample>> {
    let parse = |what: String| Error::Parse { path: path.into(), what };
    let mut r = csv::ReaderBuilder::new().trim(csv::Trim::All).from_reader(text.as_bytes());
    let header: Vec<String> = r.headers().map_err(|e| parse(e.to_string()))?.iter().map(String::from).collect();
    let col = |name: &str| header.iter().position(|h| h == name).ok_or_else(|| parse(format!("no column {name:?}")));
    let c = |n: &str| col(n);
    let (id, loc, rock, n_hand, n_comp) = (c("id")?, c("location")?, c("rock_type")?, c("n_hand")?, c("n_computer")?);
    let hand = [c("ES_hand")?, c("EU_hand")?, c("sS_hand")?, c("sU_hand")?];
    let comp = [c("ES_computer")?, c("EU_computer")?, c("sS_computer")?, c("sU_computer")?];
    let (cb, ca) = (c("c_over_b")?, c("c_over_a")?);
    let mut out = Vec::new();
    for rec in r.records() {
        let rec = rec.map_err(|e| parse(describe_csv_error(&e)))?;
        let line = rec.position().map_or(0, |p| p.line());
        let num = |i: usize| -> Result<f64> {
            rec[i]
                .replace(',', ".")
                .parse::<f64>()
                .map_err(|_| parse(format!("line {line}: {:?} is not a number", &rec[i])))
        };
        let opt = |i: usize| -> Result<Option<f64>> {
            if rec[i].is_empty() {
                Ok(None)
            } else {
                num(i).map(Some)
            }
        };
        let computer = match (opt(comp[0])?, opt(comp[1])?, opt(comp[2])?, opt(comp[3])?) {
            (Some(a), Some(b), Some(c), Some(d)) => Some([a, b, c, d]),
            _ => None,
        };
        out.push(HandSample {
            id: rec[id].to_string(),
            location: rec[loc].to_string(),
            rock_type: rec[rock].to_string(),
            n: num(n_hand)? as usize,
            hand: [num(hand[0])?, num(hand[1])?, num(hand[2])?, num(hand[3])?],
            c_over_b: num(cb)?,
            c_over_a: num(ca)?,
            computer,
            n_computer: opt(n_comp)?.map(|x| x as usize),
        });
    }
    Ok(out)
}

/// The loss of the fit of ν: a χ² over samples i and the four statistics k ∈ {E(S), E(U), σ(S),
/// σ(U)},
///
/// χ²(ν) = Σᵢ Σₖ (simᵢₖ(ν) − handᵢₖ)² / (se_handᵢₖ² + se_simᵢₖ(ν)²),
///
/// with the standard errors of [`HandSample::standard_errors`] for both (the synthetic ones from
/// the synthetic σ and count). A statistic that is not finite (a sample of one pebble) is left
/// out; a zero denominator is replaced by 10⁻⁶.
pub fn chi2(hand: &[HandSample], sim: &[Moments]) -> f64 {
    hand.iter().zip(sim).map(|(h, m)| chi2_terms(&h.hand, &h.standard_errors(), m).iter().sum::<f64>()).sum()
}

pub(crate) fn chi2_terms(hand: &[f64; 4], se_hand: &[f64; 4], m: &Moments) -> [f64; 4] {
    let s = m.as_array();
    let se = standard_errors(&s, m.n);
    let mut out = [0.0; 4];
    for k in 0..4 {
        if s[k].is_finite() {
            let var = (se_hand[k].powi(2) + if se[k].is_finite() { se[k].powi(2) } else { 0.0 }).max(1e-12);
            out[k] = (s[k] - hand[k]).powi(2) / var;
        }
    }
    out
}

/// How ν is fitted.
#[derive(Clone, Debug, Serialize)]
pub struct FitOptions {
    /// The ν grid (increasing, positive).
    pub grid: Vec<f64>,
    /// Bootstrap replicates (0: none).
    pub bootstrap: usize,
    /// Seed of the bootstrap resampling.
    pub seed: u64,
    /// Which of [E(S), E(U), σ(S), σ(U)] enter the loss (default: all four).
    pub statistics: [bool; 4],
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            grid: log_grid(1e-5, 1e-1, GridSize::PerDecade(20)),
            bootstrap: 200,
            seed: 1,
            statistics: [true; 4],
        }
    }
}

/// The result of [`fit_nu`].
#[derive(Clone, Debug, Serialize)]
pub struct NuFit {
    /// The ν grid searched.
    pub grid: Vec<f64>,
    /// χ² at every grid ν.
    pub chi2: Vec<f64>,
    /// Best ν: the vertex of the parabola in log ν through the grid minimum and its neighbours.
    pub nu: f64,
    /// χ² at the best ν.
    pub chi2_min: f64,
    /// Statistics fitted (up to 4 per sample) and degrees of freedom (terms − 1).
    pub terms: usize,
    /// Degrees of freedom (terms − 1).
    pub dof: usize,
    /// The minimum is at an end of the grid (ν is then only bounded on one side).
    pub at_edge: bool,
    /// Scale factor s² = max(1, χ²_min / dof) (errors inflated by s when the model does not
    /// fit within the stated errors).
    pub scale: f64,
    /// {ν : χ²(ν) ≤ χ²_min + s²} (linear interpolation in log ν on the grid), widened to
    /// contain `nu` where the refined minimum falls between grid points above that level.
    pub interval: (f64, f64),
    /// χ² at `nu` itself (not interpolated) split by statistic: [E(S), E(U), σ(S), σ(U)],
    /// summed over the samples (statistics left out of the fit included, for comparison).
    pub chi2_by_statistic: [f64; 4],
    /// Fitted ν of every bootstrap replicate.
    pub bootstrap: Vec<f64>,
    /// 16th and 84th percentiles of the bootstrap ν (the ±1σ range of a normal).
    pub bootstrap_interval: (f64, f64),
    /// Standard deviation of log10 ν over the replicates.
    pub bootstrap_sd_log10: f64,
}

/// Fit ν: `pops[i]` are the count curves of the synthetic pebbles standing for `hand[i]`. The
/// loss is [`chi2`] on `opts.grid`. Uncertainty two ways: the Δχ² = s² interval ([`NuFit::scale`])
/// and a bootstrap in which each replicate resamples the synthetic pebbles of every sample with
/// replacement and draws the hand statistics from normals of their standard errors, then refits.
pub fn fit_nu(hand: &[HandSample], pops: &[Vec<CountCurve>], opts: &FitOptions) -> Result<NuFit> {
    if hand.len() != pops.len() || hand.is_empty() {
        return Err(Error::Fit(format!("ν: {} hand samples but {} synthetic populations", hand.len(), pops.len())));
    }
    if opts.grid.len() < 3 || opts.grid.windows(2).any(|w| !(w[0] > 0.0 && w[1] > w[0])) {
        return Err(Error::parameter("grid", format!("{:?}", opts.grid), "at least 3 increasing positive values of ν"));
    }
    // table[i][j][g] = (S, U) of pebble j of sample i at grid ν g.
    let table: Vec<Vec<Vec<(f64, f64)>>> = pops
        .iter()
        .map(|pop| {
            pop.iter()
                .map(|c| {
                    opts.grid
                        .iter()
                        .map(|&nu| {
                            let k = c.at(nu);
                            (k.stable as f64, k.unstable as f64)
                        })
                        .collect()
                })
                .collect()
        })
        .collect();
    let se_hand: Vec<[f64; 4]> = hand.iter().map(|h| h.standard_errors()).collect();
    let used = opts.statistics;
    if !used.iter().any(|&u| u) {
        return Err(Error::Fit("ν: no statistic selected".into()));
    }
    let masked = |t: [f64; 4]| -> f64 { (0..4).filter(|&k| used[k]).map(|k| t[k]).sum() };
    let curve = |picks: &[Vec<usize>], targets: &[[f64; 4]]| -> Vec<f64> {
        (0..opts.grid.len())
            .map(|g| {
                (0..hand.len())
                    .map(|i| {
                        let su: Vec<(f64, f64)> = picks[i].iter().map(|&j| table[i][j][g]).collect();
                        masked(chi2_terms(&targets[i], &se_hand[i], &Moments::of(&su)))
                    })
                    .sum()
            })
            .collect()
    };
    let all: Vec<Vec<usize>> = pops.iter().map(|p| (0..p.len()).collect()).collect();
    let targets: Vec<[f64; 4]> = hand.iter().map(|h| h.hand).collect();
    let chi2 = curve(&all, &targets);
    let (nu, at_edge, chi2_min) = refine(&opts.grid, &chi2);
    let terms = used.iter().filter(|&&u| u).count() * hand.len();
    let dof = terms.saturating_sub(1).max(1);
    let scale = (chi2_min / dof as f64).max(1.0);
    let (lo, hi) = crossing_interval(&opts.grid, &chi2, chi2_min + scale);
    let interval = (lo.min(nu), hi.max(nu));
    let mut chi2_by_statistic = [0.0; 4];
    for ((h, se), pop) in hand.iter().zip(&se_hand).zip(pops) {
        let m = Moments::of_counts(&pop.iter().map(|c| c.at(nu)).collect::<Vec<_>>());
        for (acc, t) in chi2_by_statistic.iter_mut().zip(chi2_terms(&h.hand, se, &m)) {
            *acc += t;
        }
    }
    let bootstrap: Vec<f64> = (0..opts.bootstrap as u64)
        .into_par_iter()
        .map(|b| {
            let mut rng = item_rng(opts.seed ^ 0xb007_5742, b);
            let picks: Vec<Vec<usize>> =
                pops.iter().map(|p| (0..p.len()).map(|_| rng.random_range(0..p.len().max(1))).collect()).collect();
            let t: Vec<[f64; 4]> = hand
                .iter()
                .zip(&se_hand)
                .map(|(h, se)| {
                    let mut z = || rng.sample::<f64, _>(StandardNormal);
                    [
                        h.hand[0] + z() * se[0],
                        h.hand[1] + z() * se[1],
                        (h.hand[2] + z() * se[2]).max(0.0),
                        (h.hand[3] + z() * se[3]).max(0.0),
                    ]
                })
                .collect();
            refine(&opts.grid, &curve(&picks, &t)).0
        })
        .collect();
    let (bootstrap_interval, bootstrap_sd_log10) = if bootstrap.is_empty() {
        ((f64::NAN, f64::NAN), f64::NAN)
    } else {
        let mut sorted = bootstrap.clone();
        sorted.sort_by(|a, b| a.total_cmp(b));
        let q = |p: f64| sorted[((p * (sorted.len() - 1) as f64).round() as usize).min(sorted.len() - 1)];
        ((q(0.16), q(0.84)), sample_sd(&bootstrap.iter().map(|x| x.log10()).collect::<Vec<_>>()))
    };
    Ok(NuFit {
        grid: opts.grid.clone(),
        chi2,
        nu,
        chi2_min,
        terms,
        dof,
        at_edge,
        scale,
        interval,
        chi2_by_statistic,
        bootstrap,
        bootstrap_interval,
        bootstrap_sd_log10,
    })
}

/// The minimum of a loss on a grid, refined by the parabola in log ν through the lowest point
/// and its two neighbours: (ν, at an end of the grid, loss there).
fn refine(grid: &[f64], loss: &[f64]) -> (f64, bool, f64) {
    let i = (0..loss.len()).min_by(|&a, &b| loss[a].total_cmp(&loss[b])).unwrap_or(0);
    if i == 0 || i + 1 == loss.len() {
        return (grid[i], true, loss[i]);
    }
    let (x0, x1, x2) = (grid[i - 1].ln(), grid[i].ln(), grid[i + 1].ln());
    let (y0, y1, y2) = (loss[i - 1], loss[i], loss[i + 1]);
    let denom = (x0 - x1) * (x0 - x2) * (x1 - x2);
    let a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / denom;
    let b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / denom;
    if !(a > 0.0) {
        return (grid[i], false, loss[i]);
    }
    let x = (-b / (2.0 * a)).clamp(x0, x2);
    let c = y1 - a * x1 * x1 - b * x1;
    (x.exp(), false, (a * x * x + b * x + c).min(y1))
}

/// The range of ν around the minimum where the loss stays ≤ `level` (grid ends if never
/// crossed).
fn crossing_interval(grid: &[f64], loss: &[f64], level: f64) -> (f64, f64) {
    let i = (0..loss.len()).min_by(|&a, &b| loss[a].total_cmp(&loss[b])).unwrap_or(0);
    let cross = |j: usize, k: usize| {
        // loss[j] ≤ level < loss[k]: interpolate in log ν
        let t = ((level - loss[j]) / (loss[k] - loss[j])).clamp(0.0, 1.0);
        (grid[j].ln() + t * (grid[k].ln() - grid[j].ln())).exp()
    };
    let mut lo = grid[0];
    for j in (1..=i).rev() {
        if loss[j - 1] > level {
            lo = cross(j, j - 1);
            break;
        }
    }
    let mut hi = grid[grid.len() - 1];
    for j in i..grid.len() - 1 {
        if loss[j + 1] > level {
            hi = cross(j, j + 1);
            break;
        }
    }
    (lo, hi)
}

/// The count curves of the pebbles of a study, grouped by sample name.
pub fn curves_by_sample(study: &Study) -> BTreeMap<String, Vec<CountCurve>> {
    let mut out: BTreeMap<String, Vec<CountCurve>> = BTreeMap::new();
    for p in &study.pebbles {
        if let Ok(c) = &p.result {
            out.entry(p.sample.clone()).or_default().push(c.curve.clone());
        }
    }
    out
}

/// Generate the synthetic populations of `hand` with `params` and fit ν. Returns the fit and the
/// study (to read the synthetic statistics at any ν).
pub fn fit_table2(hand: &[HandSample], params: &PopulationParams, opts: &FitOptions) -> Result<(NuFit, Study)> {
    let targets: Vec<SampleTarget> = hand.iter().map(|h| h.target()).collect();
    let study = synthetic_study(&targets, params, PAPER_NU, None)?;
    let by = curves_by_sample(&study);
    let pops: Vec<Vec<CountCurve>> = hand.iter().map(|h| by.get(&h.id).cloned().unwrap_or_default()).collect();
    Ok((fit_nu(hand, &pops, opts)?, study))
}

/// Moments of every sample of a study at `nu`, by sample name.
pub fn moments_at(study: &Study, nu: f64) -> BTreeMap<String, Moments> {
    curves_by_sample(study)
        .into_iter()
        .map(|(k, curves)| (k, Moments::of_counts(&curves.iter().map(|c| c.at(nu)).collect::<Vec<_>>())))
        .collect()
}

/// One row of a hand-vs-computed comparison.
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    /// Sample id.
    pub id: String,
    /// Mean ratios: Table 2's (hand) and the synthetic pebbles' measured ones.
    pub hand_c_over_b: f64,
    /// Mean c/a of Table 2 (hand).
    pub hand_c_over_a: f64,
    /// Measured mean c/b of the synthetic pebbles.
    pub sim_c_over_b: f64,
    /// Measured mean c/a of the synthetic pebbles.
    pub sim_c_over_a: f64,
    /// [E(S), E(U), σ(S), σ(U)] of the hand experiments (Table 2).
    pub hand: [f64; 4],
    /// E and σ of S and U of the synthetic pebbles at ν.
    pub sim: Moments,
    /// The paper's computer experiments (5 scanned samples).
    pub paper_computer: Option<[f64; 4]>,
}

/// Hand vs synthetic statistics at `nu` for every Table 2 sample present in the study.
pub fn compare(hand: &[HandSample], study: &Study, nu: f64) -> Vec<Comparison> {
    let sims = moments_at(study, nu);
    let summaries = summarize(study);
    hand.iter()
        .filter_map(|h| {
            let sim = *sims.get(&h.id)?;
            let s = summaries.iter().find(|s| s.sample == h.id)?;
            Some(Comparison {
                id: h.id.clone(),
                hand_c_over_b: h.c_over_b,
                hand_c_over_a: h.c_over_a,
                sim_c_over_b: s.mean_c_over_b,
                sim_c_over_a: s.mean_c_over_a,
                hand: h.hand,
                sim,
                paper_computer: h.computer,
            })
        })
        .collect()
}

/// How far the synthetic statistics sit from the hand ones over the samples of a comparison:
/// for each of [E(S), E(U), σ(S), σ(U)] the mean (the bias) and the root mean square of
/// synthetic − hand; NaN for no rows.
pub fn differences(rows: &[Comparison]) -> [(f64, f64); 4] {
    std::array::from_fn(|k| {
        let d: Vec<f64> = rows.iter().map(|r| r.sim.as_array()[k] - r.hand[k]).collect();
        (mean(&d), root_mean_square(&d))
    })
}

/// The trend lines of Figure 12 for hand and computed statistics.
#[derive(Clone, Debug, Serialize)]
pub struct Trends {
    /// E(S) against c/b and c/a (Figure 12A), hand and computed.
    pub hand_es_cb: Option<LogFit>,
    /// E(S) against c/a, hand.
    pub hand_es_ca: Option<LogFit>,
    /// E(S) against c/b, computed.
    pub sim_es_cb: Option<LogFit>,
    /// E(S) against c/a, computed.
    pub sim_es_ca: Option<LogFit>,
    /// E(U) against c/b, hand.
    pub hand_eu_cb: Option<LogFit>,
    /// E(U) against c/a, hand.
    pub hand_eu_ca: Option<LogFit>,
    /// E(U) against c/b, computed.
    pub sim_eu_cb: Option<LogFit>,
    /// E(U) against c/a, computed.
    pub sim_eu_ca: Option<LogFit>,
    /// σ against E (Figure 12B).
    pub hand_sd_s: Option<LogFit>,
    /// σ(U) against E(U), hand.
    pub hand_sd_u: Option<LogFit>,
    /// σ(S) against E(S), computed.
    pub sim_sd_s: Option<LogFit>,
    /// σ(U) against E(U), computed.
    pub sim_sd_u: Option<LogFit>,
}

impl Trends {
    /// The six relations of Figure 12, named ("E(S) vs c/b", …, "σ(U) vs E(U)"), each with its
    /// hand and its computed trend: E(S) and E(U) against c/b and c/a (12A), σ against E (12B).
    pub fn relations(&self) -> [(&'static str, Option<LogFit>, Option<LogFit>); 6] {
        [
            ("E(S) vs c/b", self.hand_es_cb, self.sim_es_cb),
            ("E(S) vs c/a", self.hand_es_ca, self.sim_es_ca),
            ("E(U) vs c/b", self.hand_eu_cb, self.sim_eu_cb),
            ("E(U) vs c/a", self.hand_eu_ca, self.sim_eu_ca),
            ("σ(S) vs E(S)", self.hand_sd_s, self.sim_sd_s),
            ("σ(U) vs E(U)", self.hand_sd_u, self.sim_sd_u),
        ]
    }
}

/// Fit the logarithmic trends of a comparison (computed against the synthetic pebbles' measured
/// ratios).
pub fn trends(rows: &[Comparison]) -> Trends {
    let f = |g: &dyn Fn(&Comparison) -> (f64, f64)| log_fit(&rows.iter().map(g).collect::<Vec<_>>());
    Trends {
        hand_es_cb: f(&|r| (r.hand_c_over_b, r.hand[0])),
        hand_es_ca: f(&|r| (r.hand_c_over_a, r.hand[0])),
        sim_es_cb: f(&|r| (r.sim_c_over_b, r.sim.es)),
        sim_es_ca: f(&|r| (r.sim_c_over_a, r.sim.es)),
        hand_eu_cb: f(&|r| (r.hand_c_over_b, r.hand[1])),
        hand_eu_ca: f(&|r| (r.hand_c_over_a, r.hand[1])),
        sim_eu_cb: f(&|r| (r.sim_c_over_b, r.sim.eu)),
        sim_eu_ca: f(&|r| (r.sim_c_over_a, r.sim.eu)),
        hand_sd_s: f(&|r| (r.hand[0], r.hand[2])),
        hand_sd_u: f(&|r| (r.hand[1], r.hand[3])),
        sim_sd_s: f(&|r| (r.sim.es, r.sim.sd_s)),
        sim_sd_u: f(&|r| (r.sim.eu, r.sim.sd_u)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn differences_are_the_bias_and_rms_of_synthetic_minus_hand() {
        let row = |hand: [f64; 4], sim: [f64; 4]| Comparison {
            id: "x".into(),
            hand_c_over_b: 0.5,
            hand_c_over_a: 0.4,
            sim_c_over_b: 0.5,
            sim_c_over_a: 0.4,
            hand,
            sim: Moments { n: 10, es: sim[0], eu: sim[1], sd_s: sim[2], sd_u: sim[3] },
            paper_computer: None,
        };
        // E(S) off by +1 and −3: bias −1, rms √5; E(U) off by +2 twice; σ exact.
        let rows = [row([2.0, 3.0, 1.0, 1.0], [3.0, 5.0, 1.0, 1.0]), row([4.0, 3.0, 1.0, 1.0], [1.0, 5.0, 1.0, 1.0])];
        let d = differences(&rows);
        assert_eq!((d[0].0, d[1], d[2], d[3]), (-1.0, (2.0, 2.0), (0.0, 0.0), (0.0, 0.0)));
        assert!((d[0].1 - 5f64.sqrt()).abs() < 1e-15);
        assert!(differences(&[])[0].0.is_nan());
    }

    #[test]
    fn the_relations_pair_each_hand_trend_with_its_computed_one() {
        // Hand E(S) = 1 + 2 ln(c/b) exactly, computed flat; E(U) against c/a likewise.
        let row = |cb: f64, es: f64| Comparison {
            id: "x".into(),
            hand_c_over_b: cb,
            hand_c_over_a: cb / 2.0,
            sim_c_over_b: cb,
            sim_c_over_a: cb / 2.0,
            hand: [es, es, 1.0, 1.0],
            sim: Moments { n: 10, es: 3.0, eu: 3.0, sd_s: 1.0, sd_u: 1.0 },
            paper_computer: None,
        };
        let rows: Vec<Comparison> = [0.3, 0.5, 0.8].iter().map(|&cb: &f64| row(cb, 1.0 + 2.0 * cb.ln())).collect();
        let r = trends(&rows).relations();
        assert_eq!(r.map(|x| x.0)[..3], ["E(S) vs c/b", "E(S) vs c/a", "E(U) vs c/b"]);
        let (hand, sim) = (r[0].1.unwrap(), r[0].2.unwrap());
        assert!((hand.slope - 2.0).abs() < 1e-12 && (hand.intercept - 1.0).abs() < 1e-12, "{hand:?}");
        assert!(sim.slope.abs() < 1e-12 && (sim.intercept - 3.0).abs() < 1e-12, "{sim:?}");
        // E(S) against c/a = c/b / 2: the same slope, intercept 1 + 2 ln 2.
        assert!((r[1].1.unwrap().intercept - (1.0 + 2.0 * 2f64.ln())).abs() < 1e-12);
        assert_eq!(r[5].0, "σ(U) vs E(U)");
    }
}
