//! Category charts in the house style: an axis that names categories at the integers 0, 1, …
//! ([`Axis::categories`]), bars of several series side by side in a group at each category, each
//! where its [`BarSlot`] puts it so that marks drawn over a bar can find it
//! ([`Chart::slot_bars`] for one series, [`Chart::grouped_bars`] for all of them with their
//! legend), and dashed lines of any width on log–log axes.

use super::chart::{Axis, Chart};
use super::{series_color, Mark};
use plotters::style::RGBColor;

impl Axis {
    /// A category axis: `names[k]` written under the integer k, nothing between them, the axis
    /// from −0.5 to n − 0.5 (each category one unit wide), n + 1 ticks and no grid lines.
    pub fn categories(label: impl Into<String>, names: Vec<String>) -> Self {
        let n = names.len();
        let name = move |x: f64| match x.round() {
            k if (x - k).abs() > 1e-6 || k < 0.0 => String::new(),
            k => names.get(k as usize).cloned().unwrap_or_default(),
        };
        Axis::linear(label, -0.5, n as f64 - 0.5).ticks(n + 1).no_grid().format(name)
    }
}

/// Where the bars of one series stand in grouped bars on a [`Axis::categories`] axis: series
/// `slot` of `slots` side by side, the group `width` wide (in category units) and centred on
/// its category; each bar 0.9 of its slot wide, so that neighbouring bars keep a gap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BarSlot {
    /// The series' place in the group, from the left (0-based).
    pub slot: usize,
    /// Series per group.
    pub slots: usize,
    /// Width of a group (category units, < 1 to leave a gap between groups).
    pub width: f64,
}

impl BarSlot {
    /// The left edge of this series' bar at category `k`: k − width/2 + slot · width/slots.
    pub fn left(&self, k: usize) -> f64 {
        k as f64 - self.width / 2.0 + self.slot as f64 * (self.width / self.slots as f64)
    }

    /// The width of a slot: width / slots (the bar is 0.9 of it).
    pub fn slot_width(&self) -> f64 {
        self.width / self.slots as f64
    }

    /// The middle of this series' slot at category `k`: k − width/2 + width/slots · (slot + ½),
    /// where a bar centred in its slot ([`BarSlot::centred`]) stands.
    pub fn slot_centre(&self, k: usize) -> f64 {
        k as f64 - self.width / 2.0 + self.width / self.slots as f64 * (self.slot as f64 + 0.5)
    }

    /// A bar centred in this series' slot at category `k`: `(x − half_width, 0, x + half_width,
    /// value)` at x = [`BarSlot::slot_centre`]; half of 0.9 of the slot width leaves the same gap
    /// on either side.
    pub fn centred(&self, k: usize, half_width: f64, value: f64) -> (f64, f64, f64, f64) {
        let x = self.slot_centre(k);
        (x - half_width, 0.0, x + half_width, value)
    }

    /// The middle of this series' bar at category `k` (where its error bar stands).
    pub fn centre(&self, k: usize) -> f64 {
        self.left(k) + 0.45 * (self.width / self.slots as f64)
    }

    /// The bar `(x0, 0, x1, value)` at category `k`.
    pub fn bar(&self, k: usize, value: f64) -> (f64, f64, f64, f64) {
        self.bar_from(k, 0.0, value)
    }

    /// The bar `(x0, base, x1, value)` at category `k`: from `base` (the bottom of a log axis, say)
    /// up or down to `value`.
    pub fn bar_from(&self, k: usize, base: f64, value: f64) -> (f64, f64, f64, f64) {
        (self.left(k), base, self.left(k) + self.width / self.slots as f64 * 0.9, value)
    }
}

impl Chart {
    /// One series of grouped bars: `values[k]` as a bar from 0 at category k, in the place of
    /// `slot`, filled with `color`.
    pub fn slot_bars(self, values: &[f64], slot: BarSlot, color: RGBColor) -> Self {
        let bars: Vec<_> = values.iter().enumerate().map(|(k, &v)| slot.bar(k, v)).collect();
        self.boxes(&bars, color, 1.0)
    }

    /// Every series of grouped bars, with its legend: `values[k][s]` is the bar of series `s` at
    /// category `k`, from `base` up (or down) to it, in the [`BarSlot`] `s` of `series.len()`
    /// across `width`; series `s` filled with [`series_color`]`(s)`, its legend entry a box of
    /// that colour and `series[s]`. A category with no value for a series has no bar for it.
    pub fn grouped_bars(mut self, values: &[Vec<f64>], series: &[String], base: f64, width: f64) -> Self {
        for (s, label) in series.iter().enumerate() {
            let slot = BarSlot { slot: s, slots: series.len(), width };
            let bar = |(k, v): (usize, &Vec<f64>)| v.get(s).map(|&y| slot.bar_from(k, base, y));
            let boxes: Vec<_> = values.iter().enumerate().filter_map(bar).collect();
            let color = series_color(s);
            self = self.boxes(&boxes, color, 1.0).legend(Mark::Box(color, 1.0), label.clone());
        }
        self
    }

    /// A dashed line `width` pixels wide through `points` on log–log axes, drawn as solid
    /// segments (the chart's own dashed lines have the house width): the plot taken as
    /// `x_scale` = (decades, pixels) wide and `y_scale` high, each piece between two points is cut
    /// into n = ⌈length/13 px⌉ equal steps (n ≥ 1), each a dash of 8/13 of its step, geometric in
    /// both coordinates.
    pub fn log_dashed(
        mut self,
        points: &[(f64, f64)],
        color: RGBColor,
        width: u32,
        x_scale: (f64, f64),
        y_scale: (f64, f64),
    ) -> Self {
        let px = |p: (f64, f64)| (p.0.log10() / x_scale.0 * x_scale.1, p.1.log10() / y_scale.0 * y_scale.1);
        for w in points.windows(2) {
            let ((x0, y0), (x1, y1)) = (px(w[0]), px(w[1]));
            let n = ((x1 - x0).hypot(y1 - y0) / 13.0).ceil().max(1.0);
            let at = |t: f64| (w[0].0 * (w[1].0 / w[0].0).powf(t), w[0].1 * (w[1].1 / w[0].1).powf(t));
            for k in 0..n as usize {
                let t = k as f64 / n;
                self = self.line_width(&[at(t), at(t + 8.0 / 13.0 / n)], color, width);
            }
        }
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::Figure;
    use plotters::prelude::{IntoDrawingArea, SVGBackend};

    fn svg_of(chart: Chart) -> String {
        crate::plot::init_fonts();
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, (600, 400)).into_drawing_area();
            Figure::new("t", 1, vec![chart]).draw(&root).expect("draws");
            root.present().expect("presents");
        }
        svg
    }

    #[test]
    fn a_category_axis_names_the_integers_only() {
        let names = vec!["first one".to_string(), "second one".to_string()];
        let y = || Axis::linear("y", 10.0, 20.0);
        let svg = svg_of(Chart::new(Axis::categories("flock", names).ticks(9), y()));
        assert!(svg.contains("first one") && svg.contains("second one"), "a name is missing");
        // The same ticks on a plain axis write 0.5 and 1.5; the category axis leaves them blank.
        let plain = svg_of(Chart::new(Axis::linear("x", -0.5, 1.5).ticks(9), y()));
        assert!(plain.contains("\n0.5\n") && plain.contains("\n1.5\n"));
        assert!(!svg.contains("\n0.5\n") && !svg.contains("\n1.5\n"));
    }

    #[test]
    fn grouped_bars_stand_side_by_side() {
        // Four series in a group 0.8 wide: slots 0.2 wide, bars 0.18 wide.
        let first = BarSlot { slot: 0, slots: 4, width: 0.8 };
        let last = BarSlot { slot: 3, ..first };
        let (x0, y0, x1, y1) = first.bar(2, 0.5);
        assert!((x0 - 1.6).abs() < 1e-12 && (x1 - 1.78).abs() < 1e-12 && y0 == 0.0 && y1 == 0.5);
        assert!((last.left(2) - 2.2).abs() < 1e-12);
        assert!((last.centre(2) - 2.29).abs() < 1e-12);
        assert!((last.slot_width() - 0.2).abs() < 1e-12);
        // Centred in their slots: 2.3 for the last; a bar 0.18 wide around it.
        assert!((last.slot_centre(2) - 2.3).abs() < 1e-12 && (first.slot_centre(2) - 1.7).abs() < 1e-12);
        let (x0, _, x1, _) = last.centred(2, 0.09, 1.0);
        assert!((x0 - 2.21).abs() < 1e-12 && (x1 - 2.39).abs() < 1e-12);
        assert_eq!(BarSlot { slot: 0, slots: 1, width: 0.8 }.slot_centre(0), 0.0);
        // From the bottom of a log axis: the same edges, the base where it is asked.
        assert_eq!(last.bar_from(2, 0.5, 3.0), (last.left(2), 0.5, last.bar(2, 3.0).2, 3.0));
    }

    #[test]
    fn a_grouped_bar_chart_names_its_categories_and_series() {
        let names = vec!["granite".to_string(), "basalt".to_string()];
        let series = ["drops".to_string(), "throws".to_string()];
        let chart = Chart::new(Axis::categories("rock", names), Axis::linear("speed-up", 0.0, 3.0));
        let svg = svg_of(chart.grouped_bars(&[vec![1.0, 2.0], vec![2.5]], &series, 0.0, 0.8));
        // Each category under its tick once, each series in the legend once.
        for text in ["granite", "basalt", "drops", "throws"] {
            assert_eq!(svg.matches(text).count(), 1, "{text}");
        }
        // Three bars (basalt has no throw) beside the two legend boxes, in the series' colours.
        let fill = |c: RGBColor| format!("fill=\"#{:02X}{:02X}{:02X}\"", c.0, c.1, c.2);
        assert_eq!(svg.matches(&fill(series_color(0))).count(), 3);
        assert_eq!(svg.matches(&fill(series_color(1))).count(), 2);
    }

    #[test]
    fn a_log_dashed_line_is_cut_into_dashes_of_13_px() {
        // One decade over 130 px: ten steps, so ten dashes 3 px wide (nothing else is that wide).
        let chart = Chart::new(Axis::log("x", 1.0, 10.0), Axis::log("y", 1.0, 10.0));
        let black = RGBColor(0, 0, 0);
        let svg = svg_of(chart.log_dashed(&[(1.0, 1.0), (10.0, 1.0)], black, 3, (1.0, 130.0), (1.0, 100.0)));
        assert_eq!(svg.matches("stroke-width=\"3\"").count(), 10);
        // 131 px: eleven.
        let chart = Chart::new(Axis::log("x", 1.0, 10.0), Axis::log("y", 1.0, 10.0));
        let svg = svg_of(chart.log_dashed(&[(1.0, 1.0), (10.0, 1.0)], black, 3, (1.0, 131.0), (1.0, 100.0)));
        assert_eq!(svg.matches("stroke-width=\"3\"").count(), 11);
    }
}
