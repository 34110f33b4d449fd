//! How the fragility experiments check probabilistic statements against simulated truth:
//! proper scores of forecast probabilities (Brier score, log loss, accuracy; the oracle's and a
//! perfect ensemble's Brier score), reliability diagrams, and the measured coverage of a
//! fitted surface's 95 % band (with a cluster-robust band beside the model-based one).
//! Included by an experiment with `#[path = "shared/calibration.rs"] mod calibration;`.
#![allow(dead_code)] // each experiment uses the part it needs

use rocking_stones::ground_motion::fragility::{FragilitySurface, Run};
use rocking_stones::plot::{series_color, Axis, Chart, Mark, Marker, RGBColor};
use rocking_stones::stats::wilson;

/// One forecast case: the forecast probability and the outcomes of the truths it is scored
/// against.
pub type Forecast<'a> = (f64, &'a [bool]);

/// Brier score, log loss, accuracy (P ≥ 0.5 taken as yes) and the number of truths of the
/// forecasts `cases`, each scored against every truth of its case. Forecasts are kept inside
/// [ε, 1 − ε] for the log loss (ε = 1/(2 n) for n members: half a member, a forecast of 0 or 1
/// from n draws being no surer than that; a yes/no forecast gets the same ε, else one wrong
/// answer makes its log loss infinite).
pub fn score(cases: &[Forecast], eps: f64) -> ([f64; 3], usize) {
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
    (s.map(|x| x / k.max(1) as f64), k)
}

/// The oracle's Brier score — each case forecast by its own truth frequency q, q(1 − q), the
/// lowest any forecast can score — and the expected Brier score of a perfect ensemble of `n`
/// members drawn from each case's truth distribution, q(1 − q)(1 + 1/n), with q(1 − q)
/// estimated without bias from the case's K truths as q̂(1 − q̂)·K/(K − 1).
pub fn bounds(truths: &[&[bool]], n: u64) -> (f64, f64) {
    let (mut oracle, mut perfect, mut k_all, mut k_perfect) = (0.0, 0.0, 0usize, 0usize);
    for t in truths {
        let k = t.len();
        let q = t.iter().filter(|&&y| y).count() as f64 / k.max(1) as f64;
        (oracle, k_all) = (oracle + q * (1.0 - q) * k as f64, k_all + k);
        if k >= 2 {
            perfect += q * (1.0 - q) * k as f64 / (k as f64 - 1.0) * (1.0 + 1.0 / n as f64) * k as f64;
            k_perfect += k;
        }
    }
    (oracle / k_all.max(1) as f64, perfect / k_perfect.max(1) as f64)
}

/// A reliability diagram of sets of forecasts `(label, cases)`: each set's P in ten bins
/// against its truths' frequency in the bin, a dot per bin of area ∝ its truths (drawn at 60 %
/// opacity on white), beside the diagonal of perfect reliability.
pub fn reliability(title: &str, sets: &[(String, Vec<Forecast>)]) -> Chart {
    let axis = |label: &str| Axis::linear(label, -0.02, 1.02);
    let mut chart = Chart::new(axis("ensemble P (bin mean)"), axis("observed frequency in the truths"))
        .title(title)
        .line_width(&[(0.0, 0.0), (1.0, 1.0)], GREY, 1);
    for (k, (label, cases)) in sets.iter().enumerate() {
        let mut bins = vec![(0.0, 0usize, 0usize); 10];
        for &(p, truths) in cases {
            let bin = &mut bins[((p * 10.0) as usize).min(9)];
            for &y in truths {
                *bin = (bin.0 + p, bin.1 + y as usize, bin.2 + 1);
            }
        }
        let bins: Vec<(f64, f64, usize)> =
            bins.into_iter().filter(|b| b.2 > 0).map(|(s, y, n)| (s / n as f64, y as f64 / n as f64, n)).collect();
        let total: usize = bins.iter().map(|b| b.2).sum();
        let colour = series_color(k + 1);
        let label = format!("{label} ({total} truths; dot area ∝ truths in the bin)");
        chart = chart.legend(Mark::LineDot(colour), label);
        let faded = |c: u8| (0.6 * c as f64 + 0.4 * 255.0) as u8;
        for b in &bins {
            let r = (4.0 + 30.0 * (b.2 as f64 / total as f64).sqrt()) as u32;
            let dot = RGBColor(faded(colour.0), faded(colour.1), faded(colour.2));
            chart = chart.markers_sized(&[(b.0, b.1)], dot, Marker::Dot, r);
        }
        // The line over its dots, which are opaque.
        chart = chart.line(&bins.iter().map(|b| (b.0, b.1)).collect::<Vec<_>>(), colour);
    }
    chart.legend(Mark::Line(GREY), "perfectly reliable")
}

const GREY: RGBColor = rocking_stones::plot::colors::GREY;

/// Measured coverage: k of n, with its Wilson 95 % interval.
pub fn rate(k: u64, n: u64) -> (f64, f64, f64) {
    let (lo, hi) = wilson(k, n, 1.96);
    (k as f64 / n as f64, lo, hi)
}

pub fn logistic(eta: f64) -> f64 {
    1.0 / (1.0 + (-eta).exp())
}

/// The covariance of a fit with its runs grouped in clusters (an ensemble's members): the
/// sandwich I⁻¹ (Σ_c s_c s_cᵀ) I⁻¹ · C/(C − 1), s_c the score Σ x (y − p) of cluster c's runs,
/// I the Fisher information (Liang & Zeger 1986, with the small-sample factor C/(C − 1)).
pub fn clustered(fit: &FragilitySurface, runs: &[Run], cluster: &[u64]) -> FragilitySurface {
    use nalgebra::{Matrix3, Vector3};
    let b = Vector3::from(fit.beta);
    let inv_info = Matrix3::from_fn(|i, j| fit.covariance[i][j]);
    let mut scores: std::collections::BTreeMap<u64, Vector3<f64>> = Default::default();
    for (r, &c) in runs.iter().zip(cluster) {
        let x = Vector3::new(1.0, r.pga_g.ln(), r.pgv_over_pga_s.ln());
        *scores.entry(c).or_insert_with(Vector3::zeros) += x * (r.overturned as u8 as f64 - logistic(x.dot(&b)));
    }
    let n = scores.len() as f64;
    let meat: Matrix3<f64> = scores.values().map(|s| s * s.transpose()).sum::<Matrix3<f64>>() * (n / (n - 1.0));
    let v = inv_info * meat * inv_info;
    FragilitySurface {
        covariance: std::array::from_fn(|i| std::array::from_fn(|j| v[(i, j)])),
        std_err: std::array::from_fn(|i| v[(i, i)].sqrt()),
        ..*fit
    }
}

/// What a band is checked on: P at a point (PGA, PGV/PGA), or the PGA of a contour P = p at a
/// PGV/PGA.
#[derive(Clone, Copy)]
pub enum Target {
    Point(f64, f64),
    Contour(f64, f64),
}

impl Target {
    /// The target's name, and its columns of a coverage CSV: what, p, PGA (g), PGV/PGA (s).
    pub fn name(&self) -> (String, String) {
        match *self {
            Target::Point(pga, r) => {
                (format!("P at PGA {pga:.3} g and PGV/PGA {r:.3} s"), format!("P at a point,,{pga:.4},{r:.4}"))
            }
            Target::Contour(p, r) => {
                (format!("PGA of P = {p} at PGV/PGA {r:.3} s"), format!("PGA of a contour,{p},,{r:.4}"))
            }
        }
    }

    /// Whether the 95 % band of `fit` contains `truth`'s value. A contour band's edge that does
    /// not reach p ([`FragilitySurface::pga_band_at`]) leaves that side open.
    pub fn covered(&self, fit: &FragilitySurface, truth: &FragilitySurface) -> bool {
        match *self {
            Target::Point(pga, r) => {
                let [lo, _, hi] = fit.band(pga, r, 1.96);
                (lo..=hi).contains(&truth.probability(pga, r))
            }
            Target::Contour(p, r) => {
                let x = truth.pga_at(p, r).expect("the truth rises with PGA");
                match fit.pga_band_at(p, r, 1.96) {
                    Some([lo, _, hi]) => lo.is_none_or(|a| a <= x) && hi.is_none_or(|b| x <= b),
                    None => false,
                }
            }
        }
    }
}
