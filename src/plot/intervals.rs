//! Error bars of counted frequencies, as [`super::Chart::y_bars`] draws them.

use crate::stats::wilson;

/// The 95 % Wilson intervals ([`wilson`], z = 1.96) of `k` successes in `n` trials at each x of
/// `points` = (x, k, n), as (x, lower, upper) bars.
pub fn wilson_bars(points: impl IntoIterator<Item = (f64, u64, u64)>) -> Vec<(f64, f64, f64)> {
    points
        .into_iter()
        .map(|(x, k, n)| {
            let (lo, hi) = wilson(k, n, 1.96);
            (x, lo, hi)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wilson_bars_are_the_intervals_at_their_positions() {
        // 10 of 100 (the textbook interval 0.0552 – 0.1744) at x = 2; no trials: the whole (0, 1).
        let bars = wilson_bars([(2.0, 10, 100), (3.5, 0, 0)]);
        assert_eq!(bars.len(), 2);
        assert!(bars[0].0 == 2.0 && (bars[0].1 - 0.055228).abs() < 1e-5 && (bars[0].2 - 0.174368).abs() < 1e-5);
        assert_eq!(bars[1], (3.5, 0.0, 1.0));
    }
}
