//! Bars of several series side by side over named categories: an axis of categories
//! ([`Axis::categories`]) and grouped bars on it ([`Chart::grouped_bars`]), each bar where
//! [`bar_slot`] puts it, so that marks and labels drawn over a bar can find it.

use super::{series_color, Axis, Chart, Mark};

impl Axis {
    /// A linear axis of categories: `names[k]` written under x = k, from −0.5 to
    /// `names.len()` − 0.5 with one tick a category and no grid lines; nothing is written at a
    /// tick that is not a category.
    pub fn categories(label: impl Into<String>, names: Vec<String>) -> Self {
        let right = names.len() as f64 - 0.5;
        Axis::linear(label, -0.5, right).ticks(names.len() + 1).no_grid().format(move |x| {
            let k = x.round();
            let name = ((x - k).abs() < 1e-6 && k >= 0.0).then(|| names.get(k as usize)).flatten();
            name.cloned().unwrap_or_default()
        })
    }
}

/// Where bar `slot` of `slots` bars stands in group `group`, the group's bars side by side across
/// `width` (category units, 1 between groups) centred on x = group: the left edge
/// x₀ = group − width/2 + slot · w and the slot's width w = width / slots. The bar is
/// x₀ … x₀ + 0.9 w (a gap of 0.1 w before the next).
pub fn bar_slot(group: usize, slot: usize, slots: usize, width: f64) -> (f64, f64) {
    let w = width / slots as f64;
    (group as f64 - width / 2.0 + slot as f64 * w, w)
}

impl Chart {
    /// Grouped bars over an axis of categories: `values[k][s]` is the bar of series `s` in group
    /// `k`, from `base` up (or down) to it, the groups' bars side by side across `width`
    /// ([`bar_slot`]), series `s` in [`series_color`]`(s)` with its legend entry, a box of its
    /// colour and `series[s]`. A group with no value for a series has no bar for it.
    pub fn grouped_bars(mut self, values: &[Vec<f64>], series: &[String], base: f64, width: f64) -> Self {
        for (s, label) in series.iter().enumerate() {
            let bar = |(k, v): (usize, &Vec<f64>)| {
                let (x0, w) = bar_slot(k, s, series.len(), width);
                v.get(s).map(|&y| (x0, base, x0 + w * 0.9, y))
            };
            let boxes: Vec<_> = values.iter().enumerate().filter_map(bar).collect();
            let color = series_color(s);
            self = self.boxes(&boxes, color, 1.0).legend(Mark::Box(color, 1.0), label.clone());
        }
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bars_sit_side_by_side_in_their_group() {
        // Four bars across 0.8 of group 1: slots of 0.2 from 0.6, the third at 1.0.
        let (x0, w) = bar_slot(1, 2, 4, 0.8);
        assert!((x0 - 1.0).abs() < 1e-12 && (w - 0.2).abs() < 1e-12);
        assert_eq!(bar_slot(0, 0, 2, 0.86), (-0.43, 0.43));
    }

    #[test]
    fn a_grouped_bar_chart_names_its_categories_and_series() {
        let names = vec!["granite".to_string(), "basalt".to_string()];
        let series = ["drops".to_string(), "throws".to_string()];
        let path = std::env::temp_dir().join(format!("grouped_bars_{}.svg", std::process::id()));
        Chart::new(Axis::categories("rock", names), Axis::linear("speed-up", 0.0, 3.0))
            .grouped_bars(&[vec![1.0, 2.0], vec![2.5]], &series, 0.0, 0.8)
            .save(&path, (500, 400))
            .unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        // Each category under its tick once, each series in the legend once.
        for text in ["granite", "basalt", "drops", "throws"] {
            assert_eq!(svg.matches(text).count(), 1, "{text}");
        }
        // Three bars (basalt has no throw) beside the two legend boxes, in the series' colours.
        let fill = |c: plotters::style::RGBColor| format!("fill=\"#{:02X}{:02X}{:02X}\"", c.0, c.1, c.2);
        assert_eq!(svg.matches(&fill(series_color(0))).count(), 3);
        assert_eq!(svg.matches(&fill(series_color(1))).count(), 2);
    }
}
