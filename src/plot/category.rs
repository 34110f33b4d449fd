//! Category axes and bars side by side: outcomes, dice or runs named along an axis, with several
//! bars (one per predictor or series) at each name.

use super::chart::Axis;

impl Axis {
    /// A category axis: `names` written at the integer positions 0, 1, …, n − 1 (the range runs
    /// from −½ to n − ½), nothing written between them, no grid.
    pub fn categories(label: impl Into<String>, names: Vec<String>) -> Self {
        let axis = Axis::linear(label, -0.5, names.len() as f64 - 0.5).ticks(4 * names.len() + 1).no_grid();
        axis.format(move |x| category_name(&names, x))
    }
}

/// The name of the category at position `x` of a category axis: `names[x]` where x is an index
/// (to 10⁻⁶), empty elsewhere.
fn category_name(names: &[String], x: f64) -> String {
    let at_index = (x - x.round()).abs() < 1e-6 && x > -0.5;
    names.get(x.round() as usize).filter(|_| at_index).cloned().unwrap_or_default()
}

/// The centre of bar `slot` of `slots` bars side by side at category `i` of a category axis: the
/// group spans 0.8 around i, each bar its 0.8 / `slots` share, x = i − 0.4 + 0.8 / slots ·
/// (slot + ½).
pub fn bar_centre(i: usize, slots: usize, slot: usize) -> f64 {
    i as f64 - 0.4 + 0.8 / slots as f64 * (slot as f64 + 0.5)
}

/// The box (x − w, 0, x + w, y) of a bar of height `y` centred at `x` with half-width `w`, as
/// [`super::Chart::boxes`] takes it.
pub fn bar(x: f64, w: f64, y: f64) -> (f64, f64, f64, f64) {
    (x - w, 0.0, x + w, y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::{Chart, Figure};
    use plotters::prelude::*;

    #[test]
    fn categories_are_named_at_their_indices_only() {
        let names: Vec<String> = ["one", "two", "three"].map(String::from).to_vec();
        assert_eq!(category_name(&names, 2.0), "three");
        assert_eq!(category_name(&names, 1.000_000_1), "two");
        assert_eq!(category_name(&names, 0.25), "");
        assert_eq!(category_name(&names, -0.5), "");
        assert_eq!(category_name(&names, 3.0), "");
        // Drawn: each name once on the axis.
        let chart = Chart::new(Axis::categories("outcome", names), Axis::linear("p", 0.0, 1.0));
        super::super::init_fonts();
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, (500, 300)).into_drawing_area();
            Figure::new("categories", 1, vec![chart]).draw(&root).expect("draws");
            root.present().expect("presents");
        }
        for name in ["\none\n", "\ntwo\n", "\nthree\n"] {
            assert_eq!(svg.matches(name).count(), 1, "{name:?}");
        }
    }

    #[test]
    fn bars_side_by_side_fill_their_group() {
        // Four bars at category 2: centres 1.7, 1.9, 2.1, 2.3, spaced 0.2, the group 1.6 … 2.4.
        let centres: Vec<f64> = (0..4).map(|s| bar_centre(2, 4, s)).collect();
        for (c, want) in centres.iter().zip([1.7, 1.9, 2.1, 2.3]) {
            assert!((c - want).abs() < 1e-12, "{centres:?}");
        }
        assert_eq!(bar_centre(0, 1, 0), 0.0);
        assert_eq!(bar(2.0, 0.1, 0.5), (1.9, 0.0, 2.1, 0.5));
    }
}
