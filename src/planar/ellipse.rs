//! Discretised ellipses (see "Discretised ellipses" in the parent module): arc length by
//! Gauss–Legendre quadrature and its inverse, the vertices of the ellipse polygon for each
//! sampling, the smooth ellipse's R(φ), and the k → ∞ flock contents of Table 1.

use super::{PlanarAnalysis, PlanarReport, Point2, Polygon};
use crate::{Error, Result};
use rand::{RngExt, SeedableRng};
use serde::Serialize;
use std::f64::consts::PI;

/// How the ellipse is discretised.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Sampling {
    /// Equal arc-length spacing, vertex 0 at (a, 0) (the paper's convention).
    ArcLength,
    /// Equal steps of the parameter t of (a cos t, sin t), vertex 0 at t = 0.
    Angle,
    /// Independent uniform arc-length positions (seeded Xoshiro256++), sorted.
    Random {
        /// Seed of the generator.
        seed: u64,
    },
}

/// N = 4k − 2, the paper's numbers of sides.
pub fn sides_for_k(k: usize) -> usize {
    4 * k - 2
}

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton iteration on P_n).
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n.div_ceil(2) {
        let mut z = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            // P_n(z) and P_n'(z) by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, z);
            for j in 2..=n {
                let p2 = ((2 * j - 1) as f64 * z * p1 - (j - 1) as f64 * p0) / j as f64;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 1 { z } else { p1 };
            let pn1 = if n == 1 { 1.0 } else { p0 };
            dp = n as f64 * (z * pn - pn1) / (z * z - 1.0);
            let dz = pn / dp;
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        x[i] = -z;
        x[n - 1 - i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
        w[n - 1 - i] = w[i];
    }
    (x, w)
}

/// Arc length on the ellipse (a cos t, sin t): s(t) and its inverse.
#[derive(Clone, Debug)]
pub struct EllipseArc {
    /// Semi-axis a of the ellipse along x (the other semi-axis is 1).
    pub a: f64,
    width: f64,
    cum: Vec<f64>,
    nodes: Vec<f64>,
    weights: Vec<f64>,
}

const PANELS: usize = 256;
const GL_POINTS: usize = 16;

impl EllipseArc {
    /// Tabulate the arc length of the ellipse with semi-axes `a` and 1 (Gauss–Legendre panels).
    pub fn new(a: f64) -> Self {
        let (nodes, weights) = gauss_legendre(GL_POINTS);
        let width = 2.0 * PI / PANELS as f64;
        let mut arc = EllipseArc { a, width, cum: vec![0.0; PANELS + 1], nodes, weights };
        for m in 0..PANELS {
            let lo = m as f64 * width;
            arc.cum[m + 1] = arc.cum[m] + arc.integrate(lo, lo + width);
        }
        arc
    }

    /// |d(a cos t, sin t)/dt|.
    pub fn speed(&self, t: f64) -> f64 {
        (self.a * t.sin()).hypot(t.cos())
    }

    fn integrate(&self, lo: f64, hi: f64) -> f64 {
        let (c, h) = ((lo + hi) / 2.0, (hi - lo) / 2.0);
        h * self.nodes.iter().zip(&self.weights).map(|(x, w)| w * self.speed(c + h * x)).sum::<f64>()
    }

    /// The perimeter L.
    pub fn perimeter(&self) -> f64 {
        self.cum[PANELS]
    }

    /// s(t) for t ∈ [0, 2π].
    pub fn length_to(&self, t: f64) -> f64 {
        let m = ((t / self.width) as usize).min(PANELS - 1);
        let lo = m as f64 * self.width;
        self.cum[m] + self.integrate(lo, t)
    }

    /// The parameter t ∈ [0, 2π] with s(t) = s (safeguarded Newton).
    pub fn param_at(&self, s: f64) -> f64 {
        let l = self.perimeter();
        if s <= 0.0 {
            return 0.0;
        }
        if s >= l {
            return 2.0 * PI;
        }
        let m = self.cum.partition_point(|&c| c <= s) - 1;
        let (mut lo, mut hi) = (m as f64 * self.width, (m + 1) as f64 * self.width);
        let mut t = lo + (s - self.cum[m]) / (self.cum[m + 1] - self.cum[m]) * self.width;
        for _ in 0..60 {
            let f = self.length_to(t) - s;
            if f.abs() <= 1e-15 * l {
                break;
            }
            if f > 0.0 {
                hi = t;
            } else {
                lo = t;
            }
            let newton = t - f / self.speed(t);
            t = if newton > lo && newton < hi { newton } else { (lo + hi) / 2.0 };
        }
        t
    }
}

fn ellipse_point(a: f64, t: f64) -> Point2 {
    Point2::new(a * t.cos(), t.sin())
}

/// The vertices of the ellipse (a cos t, sin t) discretised into `n` sides (see the module
/// docs), counter-clockwise from vertex 0.
pub fn ellipse_vertices(a: f64, n: usize, sampling: Sampling) -> Result<Vec<Point2>> {
    if !(a >= 1.0 && a.is_finite()) {
        return Err(Error::parameter("a", a, "≥ 1 (the semi-axis along x, the major one)"));
    }
    if n < 3 {
        return Err(Error::parameter("sides", n, "at least 3"));
    }
    let arc = EllipseArc::new(a);
    let l = arc.perimeter();
    // The point at fraction num/den of the perimeter (or of 2π in t), built from the first
    // quadrant by exact mirroring.
    let symmetric = |num: usize, den: usize, first_quadrant: &dyn Fn(f64) -> Point2| {
        let p = |m: usize| first_quadrant(m as f64 / den as f64);
        if 4 * num <= den {
            p(num)
        } else if 4 * num <= 2 * den {
            let q = p(den / 2 - num);
            Point2::new(-q.x, q.y)
        } else if 4 * num <= 3 * den {
            let q = p(num - den / 2);
            Point2::new(-q.x, -q.y)
        } else {
            let q = p(den - num);
            Point2::new(q.x, -q.y)
        }
    };
    let v = match sampling {
        Sampling::ArcLength => {
            let f = |frac: f64| ellipse_point(a, arc.param_at(frac * l));
            (0..n).map(|i| symmetric(2 * i, 2 * n, &f)).collect()
        }
        Sampling::Angle => {
            let f = |frac: f64| ellipse_point(a, frac * 2.0 * PI);
            (0..n).map(|i| symmetric(2 * i, 2 * n, &f)).collect()
        }
        Sampling::Random { seed } => {
            let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
            let mut s: Vec<f64> = (0..n).map(|_| rng.random::<f64>() * l).collect();
            s.sort_by(f64::total_cmp);
            s.into_iter().map(|s| ellipse_point(a, arc.param_at(s))).collect()
        }
    };
    Ok(v)
}

/// The ellipse polygon of [`ellipse_vertices`].
pub fn ellipse_polygon(a: f64, n: usize, sampling: Sampling) -> Result<Polygon> {
    Polygon::new(ellipse_vertices(a, n, sampling)?)
}

/// R(φ) of the smooth ellipse (a cos t, sin t) seen from its centre at polar angle φ.
pub fn ellipse_radius(a: f64, phi: f64) -> f64 {
    1.0 / ((phi.cos() / a).powi(2) + phi.sin().powi(2)).sqrt()
}

/// The k → ∞ flock contents of Table 1 (paper §1.1) for the axis ratio 1 : a.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Table1 {
    /// m = ⌊a² / (2(a² − 1))⌋.
    pub m: usize,
    /// (stable, unstable) micro-equilibria in each stable flock: (2m + 1, 2m).
    pub stable_flock: (usize, usize),
    /// (stable, unstable) micro-equilibria in each unstable flock: (2m, 2m + 1).
    pub unstable_flock: (usize, usize),
    /// Total S = 8m + 2.
    pub total_stable: usize,
    /// a²/(2(a² − 1)) is (within 1e-9) an integer: the formula's floor sits on a jump and the
    /// limit is decided by higher-order terms.
    pub on_jump: bool,
}

/// Table 1 of the paper for a > 1 (`None` for a ≤ 1: the circle has no limit).
pub fn table1(a: f64) -> Option<Table1> {
    if !(a > 1.0) {
        return None;
    }
    let x = a * a / (2.0 * (a * a - 1.0));
    let m = x.floor() as usize;
    Some(Table1 {
        m,
        stable_flock: (2 * m + 1, 2 * m),
        unstable_flock: (2 * m, 2 * m + 1),
        total_stable: 8 * m + 2,
        on_jump: (x - x.round()).abs() < 1e-9,
    })
}

impl Table1 {
    /// Whether the measured report has exactly the formula's contents: two stable flocks of
    /// (2m + 1, 2m), two unstable flocks of (2m, 2m + 1) and S = 8m + 2 micro-stable points.
    pub fn matches(&self, r: &PlanarReport) -> bool {
        r.flock_contents.stable_flocks == vec![self.stable_flock; 2]
            && r.flock_contents.unstable_flocks == vec![self.unstable_flock; 2]
            && r.stable == self.total_stable
    }
}

/// The convergence of the arc-length discretised ellipse 1 : a with N = 4k − 2 sides to
/// Table 1, for every k from 2 to a largest k.
#[derive(Clone, Debug, Serialize)]
pub struct Table1Scan {
    /// The formula.
    pub table: Table1,
    /// S for k = 2, 3, …, the largest k.
    pub stable: Vec<usize>,
    /// The largest k whose contents differ from the formula (0 if none).
    pub last_mismatch: usize,
    /// How many k differ from the formula.
    pub mismatches: usize,
}

impl Table1Scan {
    /// k*: the smallest k from which every scanned k matches the formula (1 if all do).
    pub fn k_star(&self) -> usize {
        self.last_mismatch + 1
    }
}

/// Measure the arc-length discretised ellipse 1 : a (a > 1) at every k in 2..=`k_max` (macro
/// scale chosen automatically) against [`table1`], with [`Table1::matches`].
pub fn table1_scan(a: f64, k_max: usize) -> Result<Table1Scan> {
    let table = table1(a).ok_or_else(|| Error::parameter("a", a, "> 1 (the circle has no limit)"))?;
    let mut scan = Table1Scan { table, stable: Vec::new(), last_mismatch: 0, mismatches: 0 };
    for k in 2..=k_max {
        let r = PlanarAnalysis::of_ellipse(a, sides_for_k(k), Sampling::ArcLength)?.report(None);
        if !table.matches(&r) {
            (scan.last_mismatch, scan.mismatches) = (k, scan.mismatches + 1);
        }
        scan.stable.push(r.stable);
    }
    Ok(scan)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table1_closed_form() {
        // a = 1.2: a²/(2(a² − 1)) = 1.44/0.88 ≈ 1.64, m = 1, S = 10; a = √2 sits on the jump to m = 1.
        let t = table1(1.2).unwrap();
        assert_eq!((t.m, t.stable_flock, t.unstable_flock, t.total_stable, t.on_jump), (1, (3, 2), (2, 3), 10, false));
        assert!(table1(std::f64::consts::SQRT_2).unwrap().on_jump);
        assert_eq!(table1(1.0), None);
    }

    #[test]
    fn fine_ellipse_matches_table1_and_a_hexagon_does_not() {
        let t = table1(1.2).unwrap();
        let report = |k| PlanarAnalysis::of_ellipse(1.2, sides_for_k(k), Sampling::ArcLength).unwrap().report(None);
        assert!(t.matches(&report(50)));
        // The hexagon (k = 2) has at most 3 stable sides, never 8m + 2 = 10.
        assert!(!t.matches(&report(2)));
    }

    #[test]
    fn table1_scan_of_a_wide_ellipse() {
        // a = 2: m = ⌊4/6⌋ = 0, so every N = 4k − 2 polygon should rest only on its two sides at
        // the ends of the minor axis: S = 2 for every k and k* = 1.
        let scan = table1_scan(2.0, 30).unwrap();
        assert_eq!((scan.k_star(), scan.mismatches), (1, 0));
        assert_eq!(scan.stable, vec![2; 29]);
        // a = 1.2 reaches S = 8m + 2 = 10 by k = 30, with the mismatches all below k*.
        let scan = table1_scan(1.2, 30).unwrap();
        assert_eq!(scan.stable.last(), Some(&10));
        assert!(scan.k_star() <= 30 && scan.mismatches < scan.k_star());
        assert!(table1_scan(1.0, 5).is_err());
    }

    #[test]
    fn gauss_legendre_is_exact_for_polynomials() {
        let (x, w) = gauss_legendre(16);
        assert!((w.iter().sum::<f64>() - 2.0).abs() < 1e-14);
        // ∫ x^30 dx over [−1, 1] = 2/31 (degree 2n − 2 = 30 integrated exactly).
        let i: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(30)).sum();
        assert!((i - 2.0 / 31.0).abs() < 1e-14, "{i}");
    }

    #[test]
    fn arc_length_of_a_circle() {
        let arc = EllipseArc::new(1.0);
        assert!((arc.perimeter() - 2.0 * PI).abs() < 1e-13);
        assert!((arc.param_at(1.0) - 1.0).abs() < 1e-13);
    }
}
