//! Summaries of a sample: mean, standard deviation, quantiles and order statistics, ranges, the
//! root mean square.

/// Arithmetic mean (NaN for no data).
pub fn mean(x: &[f64]) -> f64 {
    if x.is_empty() {
        f64::NAN
    } else {
        x.iter().sum::<f64>() / x.len() as f64
    }
}

/// Sample standard deviation, divisor n − 1 (the paper's convention for Table 2, see
/// [`crate::study`]); NaN for fewer than two values.
pub fn sample_sd(x: &[f64]) -> f64 {
    if x.len() < 2 {
        return f64::NAN;
    }
    let m = mean(x);
    (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (x.len() - 1) as f64).sqrt()
}

/// The nearest-rank quantile of `x` at `q` ∈ [0, 1]: the value of rank round((n − 1)·q) in `x`
/// sorted by the total order of f64 (no interpolation; NaN sorts last). `q` = 0.5 is the median,
/// the upper of the two middle values for an even n. NaN for no data.
pub fn quantile(x: &[f64], q: f64) -> f64 {
    let mut sorted = x.to_vec();
    sorted.sort_by(f64::total_cmp);
    let rank = ((sorted.len() as f64 - 1.0) * q.clamp(0.0, 1.0)).round();
    if sorted.is_empty() {
        f64::NAN
    } else {
        sorted[rank as usize]
    }
}

/// The median of `x` (the mean of the two middle values for an even count), its smallest and its
/// largest value: [median, min, max]; NaN for an empty `x`.
pub fn median_range(x: &[f64]) -> [f64; 3] {
    if x.is_empty() {
        return [f64::NAN; 3];
    }
    let mut v = x.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    [if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) }, v[0], v[n - 1]]
}

/// The range of non-negative values `xs` (intensity measures, periods, ratios): (the smallest,
/// the largest), the largest at least 0; (∞, 0) for none.
pub fn nonnegative_range(xs: impl IntoIterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = min_max(xs);
    (lo, hi.max(0.0))
}

/// The smallest and the largest of `values` (NaN values ignored, as [`f64::min`] and
/// [`f64::max`] do); (∞, −∞) when there is none.
pub fn min_max(values: impl IntoIterator<Item = f64>) -> (f64, f64) {
    values.into_iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)))
}

/// The root mean square √(Σ xᵢ² / n) of `x` (NaN for no data): the rms of differences, residuals
/// or biases.
pub fn root_mean_square(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

/// The five-number summary of `x` without interpolation: the smallest value, the order
/// statistics at positions ⌊n/4⌋, ⌊n/2⌋ and ⌊3n/4⌋ of the sorted values (0-based: the lower
/// quartile, the median, the upper quartile) and the largest; None for no data.
pub fn five_numbers(x: &[f64]) -> Option<[f64; 5]> {
    let mut v = x.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some([*v.first()?, v[n / 4], v[n / 2], v[3 * n / 4], v[n - 1]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_by_nearest_rank() {
        // Sorted: 1, 2, 3, 4, 10. Ranks round(4q): q = 0.5 → 3, q = 0.9 → rank 4 (3.6 → 4), q = 0.1 → rank 0.
        let x = [4.0, 10.0, 1.0, 3.0, 2.0];
        assert_eq!(quantile(&x, 0.5), 3.0);
        assert_eq!(quantile(&x, 0.9), 10.0);
        assert_eq!(quantile(&x, 0.1), 1.0);
        assert_eq!(quantile(&x, 1.0), 10.0);
        // An even count: the upper middle value (rank round(1.5) = 2 of 1, 2, 3, 4).
        assert_eq!(quantile(&[2.0, 1.0, 4.0, 3.0], 0.5), 3.0);
        assert!(quantile(&[], 0.5).is_nan());
    }

    #[test]
    fn the_median_range_of_odd_and_even_counts() {
        assert_eq!(median_range(&[3.0, -1.0, 7.0]), [3.0, -1.0, 7.0]);
        assert_eq!(median_range(&[4.0, 1.0, 10.0, 2.0]), [3.0, 1.0, 10.0]);
        assert!(median_range(&[]).iter().all(|x| x.is_nan()));
    }

    #[test]
    fn the_range_of_nonnegative_values() {
        assert_eq!(nonnegative_range([0.3, 2.0, 0.05, 1.0]), (0.05, 2.0));
        assert_eq!(nonnegative_range([]), (f64::INFINITY, 0.0));
    }

    #[test]
    fn min_max_and_rms_match_hand_values() {
        assert_eq!(min_max([3.0, -1.5, f64::NAN, 2.0]), (-1.5, 3.0));
        assert_eq!(min_max(std::iter::empty()), (f64::INFINITY, f64::NEG_INFINITY));
        // √((9 + 16 + 0 + 1)/4) = √6.5.
        assert!((root_mean_square(&[3.0, -4.0, 0.0, 1.0]) - 6.5f64.sqrt()).abs() < 1e-15);
        assert!(root_mean_square(&[]).is_nan());
    }

    #[test]
    fn five_numbers_are_order_statistics() {
        // Sorted 1 … 8: positions 2, 4 and 6 (0-based) hold 3, 5 and 7.
        assert_eq!(five_numbers(&[8.0, 1.0, 5.0, 3.0, 7.0, 2.0, 6.0, 4.0]), Some([1.0, 3.0, 5.0, 7.0, 8.0]));
        assert_eq!(five_numbers(&[2.5]), Some([2.5; 5]));
        assert_eq!(five_numbers(&[]), None);
    }
}
