//! A shaking run of a stone's stable equilibria ([`crate::dynamics::shaking::ShakeReport`]): the
//! summary, the fragility curves as CSV and plot, and one row per trial.

use super::describe_motion;
use crate::dynamics::resting::outcome::{CurvePoint, Threshold};
use crate::dynamics::shaking::{ShakeReport, ShakeTrial};
use crate::dynamics::stone::{Class, StableEquilibrium};
use crate::plot::{render, DrawResult};
use crate::report::{short_name, write_json, Folder};
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// A readable summary of a shaking run.
pub fn summary(r: &ShakeReport, mesh: &str) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(s, "{mesh}: ground shaking, {}, scaled to each PGA", describe_motion(&r.motion));
    let _ = writeln!(
        s,
        "  stone of R_max = {:.3} m; {}",
        r.r_max_m,
        crate::report::perturb::contact_line(&r.params, Some(r.r_max_m))
    );
    s += &crate::report::depth_line(r.deepest_penetration);
    let azimuth = match r.azimuth_deg {
        Some(a) => format!("all along azimuth {a}° from the stone's x axis as it stands"),
        None => "each along a random azimuth".to_string(),
    };
    let _ = writeln!(
        s,
        "{} trials per PGA on {} PGAs from {:.3} g to {:.3} g ({azimuth}), seed {}; flocks at ν = {:.3e}",
        r.trials_per_point,
        r.pgas.len(),
        r.pgas.first().copied().unwrap_or(f64::NAN),
        r.pgas.last().copied().unwrap_or(f64::NAN),
        r.seed,
        r.nu
    );
    let th = |t: &Option<Threshold>| match t {
        None => "-".to_string(),
        Some(Threshold::Below(x)) => format!("≤{x:.3}"),
        Some(Threshold::At(x)) => format!("{x:.3}"),
        Some(Threshold::Above(x)) => format!(">{x:.3}"),
    };
    let class = |q: &StableEquilibrium| q.class.name().to_string();
    if r.pgas.len() == 1 {
        let _ = writeln!(
            s,
            "{:>5} {:>6} {:>8} {:>10} {:>21} {:>21} {:>21}",
            "eq", "facet", "class", "uplift (g)", "P(same micro)", "P(still in flock)", "P(toppled)"
        );
        let p = |x: f64, ci: (f64, f64)| format!("{x:.2} [{:.2}, {:.2}]", ci.0, ci.1);
        for f in &r.fragility {
            let q = &f.equilibrium;
            match f.curve.first() {
                Some(c) => {
                    let _ = writeln!(
                        s,
                        "{:>5} {:>6} {:>8} {:>10.4} {:>21} {:>21} {:>21}",
                        q.index,
                        q.facet,
                        class(q),
                        q.uplift_acceleration,
                        p(c.p_same, c.ci_same),
                        p(c.p_in_flock, c.ci_in_flock),
                        p(c.p_toppled, c.ci_toppled)
                    );
                }
                None => {
                    let _ = writeln!(
                        s,
                        "{:>5} {:>6} {:>8} {:>10.4}   does not stay at rest",
                        q.index,
                        q.facet,
                        class(q),
                        q.uplift_acceleration
                    );
                }
            }
        }
        return s;
    }
    let _ = writeln!(
        s,
        "{:>5} {:>6} {:>8} {:>10} {:>11} {:>11} {:>12}",
        "eq", "facet", "class", "uplift (g)", "PGA50 micro", "PGA50 flock", "first topple"
    );
    for f in &r.fragility {
        let q = &f.equilibrium;
        let _ = writeln!(
            s,
            "{:>5} {:>6} {:>8} {:>10.4} {:>11} {:>11} {:>12}",
            q.index,
            q.facet,
            class(q),
            q.uplift_acceleration,
            if f.rest.stays { th(&f.pga50_micro) } else { "no rest".into() },
            th(&f.pga50_flock),
            f.first_topple.map_or("-".into(), |x| format!("{x:.3}")),
        );
    }
    s
}

/// Write the fragility curves as CSV.
pub fn write_fragility_csv(path: &Path, r: &ShakeReport) -> crate::Result<()> {
    crate::report::write_csv(
        path,
        &[
            "equilibrium",
            "facet",
            "static_class",
            "pga_g",
            "n",
            "same",
            "same_flock",
            "toppled",
            "unsettled",
            "p_same",
            "p_toppled",
            "p_toppled_lo",
            "p_toppled_hi",
            "uplift_acceleration_g",
        ],
        r.fragility.iter().flat_map(|f| {
            let q = &f.equilibrium;
            f.curve.iter().map(move |c| {
                [
                    q.index.to_string(),
                    q.facet.to_string(),
                    q.class.name().to_string(),
                    format!("{:.4}", c.x),
                    c.n.to_string(),
                    c.same.to_string(),
                    c.same_flock.to_string(),
                    c.toppled.to_string(),
                    c.unsettled.to_string(),
                    format!("{:.4}", c.p_same),
                    format!("{:.4}", c.p_toppled),
                    format!("{:.4}", c.ci_toppled.0),
                    format!("{:.4}", c.ci_toppled.1),
                    format!("{:.5}", q.uplift_acceleration),
                ]
            })
        }),
    )
}

/// A PGA₅₀ ([`Threshold`], g) as a table cell: "≤ x" (P already ½ at the grid's least PGA), "x"
/// or "> x" (P never ½ up to its largest), x to 3 decimals; "–" when there is none.
pub fn pga50_cell(t: &Option<Threshold>) -> String {
    match t {
        None => "–".into(),
        Some(Threshold::Below(x)) => format!("≤ {x:.3}"),
        Some(Threshold::At(x)) => format!("{x:.3}"),
        Some(Threshold::Above(x)) => format!("> {x:.3}"),
    }
}

/// Fragility curves P(toppled) against PGA, one line (with 95 % intervals) per
/// `(label, curve, colour)`, and vertical markers.
pub fn plot_fragility(
    path: &Path,
    caption: &str,
    lines: &[(String, &[CurvePoint], plotters::style::RGBColor)],
    markers: &[(f64, String, plotters::style::RGBColor)],
) -> crate::Result<()> {
    render!(path, (900, 600), |root| draw_fragility(&root, caption, lines, markers))
}

#[allow(clippy::type_complexity)]
fn draw_fragility<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    caption: &str,
    lines: &[(String, &[CurvePoint], plotters::style::RGBColor)],
    markers: &[(f64, String, plotters::style::RGBColor)],
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let font = crate::plot::FONT_FAMILY;
    let err = |x: DrawingAreaErrorKind<_>| format!("{x:?}");
    let hi = lines.iter().flat_map(|l| l.1.iter().map(|c| c.x)).fold(0.0, f64::max).max(1e-3) * 1.05;
    root.fill(&WHITE).map_err(err)?;
    let mut chart = ChartBuilder::on(root)
        .caption(caption, (font, crate::plot::style::TITLE))
        .margin(14)
        .x_label_area_size(45)
        .y_label_area_size(55)
        .build_cartesian_2d(0.0..hi, -0.02f64..1.02)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("peak ground acceleration (g)")
        .y_desc("P(toppled out of the flock)")
        .label_style((font, crate::plot::style::TICK))
        .draw()
        .map_err(err)?;
    for (x, label, color) in markers {
        let c = *color;
        chart
            .draw_series(DashedLineSeries::new(vec![(*x, 0.0), (*x, 1.02)], 6, 4, c.stroke_width(2)))
            .map_err(err)?
            .label(label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2)));
    }
    for (label, curve, color) in lines {
        let c = *color;
        let pts: Vec<(f64, f64)> = curve.iter().map(|p| (p.x, p.p_toppled)).collect();
        chart
            .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
            .map_err(err)?
            .label(label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2)));
        chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled()))).map_err(err)?;
        chart
            .draw_series(
                curve
                    .iter()
                    .map(|p| PathElement::new(vec![(p.x, p.ci_toppled.0), (p.x, p.ci_toppled.1)], c.stroke_width(1))),
            )
            .map_err(err)?;
    }
    chart
        .configure_series_labels()
        .label_font((font, crate::plot::style::LEGEND))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerRight)
        .draw()
        .map_err(err)?;
    Ok(())
}

/// Write one CSV row per shaking trial.
pub fn write_trials_csv(path: &Path, trials: &[ShakeTrial]) -> crate::Result<()> {
    crate::report::write_csv(
        path,
        &[
            "equilibrium",
            "pga_g",
            "azimuth_deg",
            "trial",
            "outcome",
            "final_equilibrium",
            "final_flock",
            "settled",
            "max_tilt_rad",
        ],
        trials.iter().map(|t| {
            [
                t.equilibrium.to_string(),
                format!("{:.4}", t.pga),
                format!("{:.2}", t.azimuth.to_degrees()),
                t.trial.to_string(),
                t.outcome.name().to_string(),
                t.final_equilibrium.map_or(String::new(), |x| x.to_string()),
                t.final_flock.to_string(),
                t.settled.to_string(),
                format!("{:.5}", t.max_tilt),
            ]
        }),
    )
}

/// Write `shake.json`, `fragility.csv`, `trials.csv` and (if any curve) `fragility.png/.svg` into
/// `dir`; `name` is the mesh named in the caption.
pub fn write_outputs(r: &ShakeReport, name: &str, dir: &Path) -> crate::Result<Vec<PathBuf>> {
    let mut out = Folder::create(dir)?;
    out.file("shake.json", |p| write_json(p, r))?;
    out.file("fragility.csv", |p| write_fragility_csv(p, r))?;
    out.file("trials.csv", |p| write_trials_csv(p, &r.trials))?;
    let lines: Vec<(String, &[CurvePoint], RGBColor)> = r
        .fragility
        .iter()
        .filter(|f| !f.curve.is_empty())
        .enumerate()
        .map(|(i, f)| {
            let q = &f.equilibrium;
            let class = match q.class {
                Class::Regular => "regular",
                Class::Rocking => "rocking",
            };
            (format!("eq {} ({class}, facet {})", q.index, q.facet), f.curve.as_slice(), crate::plot::series_color(i))
        })
        .collect();
    if !lines.is_empty() {
        let caption = format!("{}: fragility, {}", short_name(name), describe_motion(&r.motion));
        for ext in ["png", "svg"] {
            out.file(&format!("fragility.{ext}"), |p| plot_fragility(p, &caption, &lines, &[]))?;
        }
    }
    Ok(out.written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pga50_cell_says_which_side_of_the_grid_it_is_on() {
        assert_eq!(pga50_cell(&Some(Threshold::Below(0.025))), "≤ 0.025");
        assert_eq!(pga50_cell(&Some(Threshold::At(0.24512))), "0.245");
        assert_eq!(pga50_cell(&Some(Threshold::Above(1.0))), "> 1.000");
        assert_eq!(pga50_cell(&None), "–");
    }
}
