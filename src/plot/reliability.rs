//! Reliability diagrams of probability forecasts: the forecast P, binned, against how often the
//! truths it was scored against came out yes ([`crate::stats::forecast_scores`] scores the same
//! forecasts).

use super::{colors::GREY, series_color, Axis, Chart, Mark, Marker, RGBColor};
use crate::stats::Forecast;

/// The reliability of the forecasts `cases` in ten bins of P ([0, 0.1), …, [0.9, 1], a P of 1
/// in the last): for each bin that holds a truth, (the mean P over its truths, the share of its
/// truths that came out yes, its number of truths), bins in order of P. Each case weighs by its
/// number of truths; a perfectly reliable forecast has its points on the diagonal.
pub fn reliability_bins(cases: &[Forecast]) -> Vec<(f64, f64, usize)> {
    let mut bins = vec![(0.0, 0usize, 0usize); 10];
    for &(p, truths) in cases {
        let bin = &mut bins[((p * 10.0) as usize).min(9)];
        for &y in truths {
            *bin = (bin.0 + p, bin.1 + y as usize, bin.2 + 1);
        }
    }
    bins.into_iter().filter(|b| b.2 > 0).map(|(s, y, n)| (s / n as f64, y as f64 / n as f64, n)).collect()
}

/// A reliability diagram of sets of forecasts `(label, cases)`, titled `title`: each set's
/// [`reliability_bins`] as a line in its series colour over a dot per bin of area ∝ the bin's
/// truths (radius 4 + 30 √(share of the set's truths) px, drawn at 60 % opacity on white),
/// beside the diagonal of perfect reliability; both axes from −0.02 to 1.02.
pub fn reliability_diagram(title: &str, sets: &[(String, Vec<Forecast>)]) -> Chart {
    let axis = |label: &str| Axis::linear(label, -0.02, 1.02);
    let mut chart = Chart::new(axis("ensemble P (bin mean)"), axis("observed frequency in the truths"))
        .title(title)
        .line_width(&[(0.0, 0.0), (1.0, 1.0)], GREY, 1);
    for (k, (label, cases)) in sets.iter().enumerate() {
        let bins = reliability_bins(cases);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reliability_bins_match_a_hand_count() {
        // P = 0.05 against 3 truths (1 yes), P = 0.12 against 1 (yes), P = 1 against 2 (both yes),
        // P = 0.95 against 2 (1 yes), P = 0.5 against none: bin 0 holds 0.05, bin 1 holds 0.12,
        // bin 5 no truth, the last bin holds 0.95 and 1 (4 truths, 3 yes, mean P (2·0.95 + 2)/4).
        let cases = [
            (0.05, &[true, false, false][..]),
            (0.12, &[true][..]),
            (1.0, &[true, true][..]),
            (0.95, &[true, false][..]),
            (0.5, &[][..]),
        ];
        let bins = reliability_bins(&cases);
        assert_eq!(bins.len(), 3, "{bins:?}");
        assert_eq!((bins[0].1, bins[0].2), (1.0 / 3.0, 3));
        assert!((bins[0].0 - 0.05).abs() < 1e-15);
        assert_eq!((bins[1].0, bins[1].1, bins[1].2), (0.12, 1.0, 1));
        assert!((bins[2].0 - 3.9 / 4.0).abs() < 1e-14 && bins[2].1 == 0.75 && bins[2].2 == 4, "{bins:?}");
    }

    #[test]
    fn a_reliability_diagram_draws_its_sets_and_the_diagonal() {
        let cases = [(0.2, &[false, true][..]), (0.7, &[true][..])];
        let chart = reliability_diagram("calibration", &[("forecast A".into(), cases.to_vec())]);
        let path = std::env::temp_dir().join(format!("reliability_diagram_{}.svg", std::process::id()));
        chart.save(&path, (500, 400)).unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        for needle in ["calibration", "forecast A (3 truths", "perfectly reliable"] {
            assert!(svg.contains(needle), "{needle} missing from the SVG");
        }
    }
}
