//! Trend lines and grids: a least-squares line in log–log coordinates, logarithmic grids, and
//! where a sampled curve first rises through a level.

use serde::Serialize;

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

/// The x at which the piecewise-linear curve through `points` (in order of x) first crosses
/// `level` upwards: the first segment with y₀ < `level` ≤ y₁, interpolated linearly,
/// x₀ + (level − y₀)/(y₁ − y₀) · (x₁ − x₀). None if it never does.
pub fn upward_crossing(points: &[(f64, f64)], level: f64) -> Option<f64> {
    points.windows(2).find(|w| w[0].1 < level && w[1].1 >= level).map(|w| {
        let ((x0, a), (x1, b)) = (w[0], w[1]);
        x0 + (level - a) / (b - a) * (x1 - x0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
