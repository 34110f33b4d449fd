//! Intervals of a measured rate: the Wilson score interval of k successes in n trials.

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

/// A measured rate: k of n, as (k/n, low, high) with the Wilson score interval ([`wilson`]) at
/// z (1.96 for 95 %); (NaN, 0, 1) for n = 0.
pub fn rate_with_wilson(k: u64, n: u64, z: f64) -> (f64, f64, f64) {
    let (lo, hi) = wilson(k, n, z);
    (k as f64 / n as f64, lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn a_rate_is_its_fraction_inside_its_wilson_interval() {
        // 8 of 10 at z = 2: centre (0.8 + 0.2)/1.4 = 5/7, half-width 2·√(0.016 + 0.01)/1.4.
        let (rate, lo, hi) = rate_with_wilson(8, 10, 2.0);
        let half = 2.0 * 0.026f64.sqrt() / 1.4;
        assert_eq!(rate, 0.8);
        assert!((lo - (5.0 / 7.0 - half)).abs() < 1e-12 && (hi - (5.0 / 7.0 + half)).abs() < 1e-12);
        assert!(lo < rate && rate < hi);
        let (none, lo, hi) = rate_with_wilson(0, 0, 1.96);
        assert!(none.is_nan() && (lo, hi) == (0.0, 1.0));
    }
}
