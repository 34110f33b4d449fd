//! What a person reads of a study ([`crate::study`]): the pebble, sample and comparison CSVs, the
//! samples table, the Zingg diagram, scatter plots with trend lines, the χ²(ν) curves and the
//! Figure 12 plots.

use super::create_dir;
use crate::analysis::PAPER_NU;
use crate::hierarchy::Counts;
use crate::plot::{render, DrawResult, FONT_FAMILY};
use crate::report::hand::{pair_cells, PAIR_COLUMNS};
use crate::shape::Zingg;
use crate::stats::LogFit;
use crate::study::{trends, Comparison, NuFit, SampleSummary, Study};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Columns after the `rocking analyze` ones in the pebble CSV.
pub const HAND_COLUMNS: [&str; 4] = ["hand_nu", "hand_S", "hand_U", "hand_H"];
/// Columns of the dynamic experimenter in the pebble CSV.
pub const DYNAMIC_COLUMNS: [&str; 4] = ["dyn_trials", "dyn_settled", "dyn_S", "dyn_rocking"];

/// The header of the pebble CSV: `id`, `sample`, the metadata columns (prefixed `meta_` where
/// they would clash with another column), the columns of `rocking analyze` (see
/// [`crate::report::CSV_HEADER`]), the hand columns (the counts at the fixed ν, or the
/// two-tolerance experimenter's [`PAIR_COLUMNS`]), and the dynamic columns.
pub fn pebble_header(study: &Study) -> Vec<String> {
    let mut fixed: Vec<String> = ["id", "sample"].iter().map(|s| s.to_string()).collect();
    fixed.extend(crate::report::CSV_HEADER.iter().map(|s| s.to_string()));
    let hand: &[&str] = if study.hand.is_some() { &PAIR_COLUMNS } else { &HAND_COLUMNS };
    fixed.extend(hand.iter().map(|s| s.to_string()));
    if study.dynamic {
        fixed.extend(DYNAMIC_COLUMNS.iter().map(|s| s.to_string()));
    }
    let meta = study.meta_columns.iter().map(|c| {
        if fixed.iter().any(|f| f.eq_ignore_ascii_case(c)) {
            format!("meta_{c}")
        } else {
            c.clone()
        }
    });
    let mut out: Vec<String> = fixed[..2].to_vec();
    out.extend(meta);
    out.extend(fixed[2..].iter().cloned());
    out
}

/// One CSV row per pebble (see [`pebble_header`]). The `rocking analyze` columns are written by
/// [`crate::report::write_batch_csv`] itself, so they are the same, character for character.
pub fn write_pebbles_csv<W: std::io::Write>(study: &Study, w: W) -> crate::Result<()> {
    (|| -> std::result::Result<_, crate::error::BoxError> {
        let mut buf = Vec::new();
        let rows = study
            .pebbles
            .iter()
            .map(|p| (Path::new(p.file.as_str()), p.result.as_ref().map(|c| &c.report).map_err(|e| e.as_str())));
        crate::report::write_batch_csv(&mut buf, rows)?;
        let mut analyze = csv::Reader::from_reader(buf.as_slice());
        let mut out = csv::Writer::from_writer(w);
        out.write_record(pebble_header(study))?;
        for (p, rec) in study.pebbles.iter().zip(analyze.records()) {
            let rec = rec?;
            let mut row = vec![p.id.clone(), p.sample.clone()];
            row.extend(p.meta.iter().cloned());
            row.extend(rec.iter().map(String::from));
            match &p.result {
                Ok(c) => {
                    let k = c.curve.at(study.nu);
                    match study.hand {
                        Some(_) => row.extend(pair_cells(&study.distribution(c))),
                        None => row.extend([
                            format!("{:e}", study.nu),
                            k.stable.to_string(),
                            k.unstable.to_string(),
                            k.saddle.to_string(),
                        ]),
                    }
                    if study.dynamic {
                        match &c.dynamic {
                            Some(d) => row.extend([
                                d.trials.to_string(),
                                d.settled.to_string(),
                                d.stable.to_string(),
                                d.rocking.to_string(),
                            ]),
                            None => row.extend(std::iter::repeat_n(String::new(), DYNAMIC_COLUMNS.len())),
                        }
                    }
                }
                Err(_) => {
                    let hand = if study.hand.is_some() { PAIR_COLUMNS.len() } else { HAND_COLUMNS.len() };
                    let n = hand + if study.dynamic { DYNAMIC_COLUMNS.len() } else { 0 };
                    row.extend(std::iter::repeat_n(String::new(), n));
                }
            }
            out.write_record(row)?;
        }
        out.flush()?;
        Ok(())
    })()
    .map_err(|e| crate::Error::write(crate::error::MEMORY, e))
}

/// A number for a CSV cell: empty for NaN.
fn cell(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.6}")
    } else {
        String::new()
    }
}

/// One CSV row per sample: `sample, pebbles, failed, mean_c_over_b, mean_c_over_a,
/// mean_b_over_a`, then `E_S, E_U, sd_S, sd_U` for the micro scale (`micro_`), each pebble's
/// plateau (`plateau_`) and the hand experimenter (`hand_`; with `hand_nu` for the one-ν one),
/// then the dynamic
/// experimenter (`dyn_E_S, dyn_sd_S, dyn_rocking`) if it ran. σ is the sample standard deviation
/// (n − 1), as in the paper's Table 2.
pub fn write_samples_csv<W: std::io::Write>(study: &Study, summaries: &[SampleSummary], w: W) -> crate::Result<()> {
    (|| -> std::result::Result<_, crate::error::BoxError> {
        let mut out = csv::Writer::from_writer(w);
        let mut header: Vec<String> =
            ["sample", "pebbles", "failed", "mean_c_over_b", "mean_c_over_a", "mean_b_over_a"]
                .map(String::from)
                .to_vec();
        for scale in ["micro", "plateau", "hand"] {
            if scale == "hand" && study.hand.is_none() {
                header.push("hand_nu".into());
            }
            for m in ["E_S", "E_U", "sd_S", "sd_U"] {
                header.push(format!("{scale}_{m}"));
            }
        }
        if study.dynamic {
            header.extend(["dyn_E_S", "dyn_sd_S", "dyn_rocking"].map(String::from));
        }
        out.write_record(&header)?;
        for s in summaries {
            let mut row = vec![
                s.sample.clone(),
                s.pebbles.to_string(),
                s.failed.to_string(),
                cell(s.mean_c_over_b),
                cell(s.mean_c_over_a),
            ];
            row.push(cell(s.mean_b_over_a));
            for (scale, m) in [("micro", &s.micro), ("plateau", &s.plateau), ("hand", &s.hand)] {
                if scale == "hand" && study.hand.is_none() {
                    row.push(format!("{:e}", study.nu));
                }
                row.extend(m.as_array().map(cell));
            }
            if study.dynamic {
                row.extend([s.dyn_es, s.dyn_sd_s, s.dyn_rocking].map(|x| x.map_or(String::new(), cell)));
            }
            out.write_record(row)?;
        }
        out.flush()?;
        Ok(())
    })()
    .map_err(|e| crate::Error::write(crate::error::MEMORY, e))
}

/// The plain-text table of the sample summaries printed by `rocking study`.
pub fn samples_table(study: &Study, summaries: &[SampleSummary]) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<12} {:>4} {:>6} {:>6}  {:>13}  {:>13}  {:>20}{}",
        "sample",
        "n",
        "c/b",
        "c/a",
        "micro E(S,U)",
        "plateau E(S,U)",
        match study.hand {
            Some(_) => "hand E(S,U) σ(S,U)".to_string(),
            None => format!("ν={:.2e} E(S,U) σ(S,U)", study.nu),
        },
        if study.dynamic { "  dynamic E(S) σ(S)" } else { "" }
    );
    for m in summaries {
        let name = if m.sample.is_empty() { "(none)" } else { &m.sample };
        let _ = write!(
            s,
            "{:<12} {:>4} {:>6.3} {:>6.3}  {:>6.2} {:>6.2}  {:>6.2} {:>6.2}  {:>4.2} {:>4.2} {:>4.2} {:>4.2}",
            name,
            m.pebbles,
            m.mean_c_over_b,
            m.mean_c_over_a,
            m.micro.es,
            m.micro.eu,
            m.plateau.es,
            m.plateau.eu,
            m.hand.es,
            m.hand.eu,
            m.hand.sd_s,
            m.hand.sd_u
        );
        if let (Some(e), Some(sd)) = (m.dyn_es, m.dyn_sd_s) {
            let _ = write!(s, "  {e:>8.2} {sd:>5.2}");
        }
        let _ = writeln!(s, "{}", if m.failed > 0 { format!("  ({} failed)", m.failed) } else { String::new() });
    }
    s
}

fn perr<E: std::fmt::Debug>(e: E) -> String {
    format!("plot: {e:?}")
}

/// The {S, U} class of a pebble at ν, as in the paper's classification (Domokos et al. 2010).
pub fn class_label(c: Counts) -> String {
    format!("{{{},{}}}", c.stable, c.unstable)
}

/// Classes with their own colour in [`plot_zingg`]; the rarer ones are grey.
pub const ZINGG_CLASSES: usize = 9;

/// Zingg diagram (x = b/a, y = c/b, class boundaries at 2/3) of the study, each pebble coloured
/// by its macro class {S, U} at the study's ν (the [`ZINGG_CLASSES`] most frequent classes; the
/// others grey).
pub fn plot_zingg(study: &Study, title: &str, path: &Path) -> crate::Result<()> {
    let mut classes: BTreeMap<(usize, usize), Vec<(f64, f64)>> = BTreeMap::new();
    for p in &study.pebbles {
        if let Ok(c) = &p.result {
            let k = study.reported(c);
            classes.entry((k.stable, k.unstable)).or_default().push((c.report.shape.b_over_a, c.report.shape.c_over_b));
        }
    }
    let scale = match study.hand {
        Some(_) => "the hand experimenter's most likely {S,U}".to_string(),
        None => format!("class {{S,U}} at ν = {:.2e}", study.nu),
    };
    render!(path, (760, 720), |root| draw_zingg(&root, title, &scale, &classes))
}

fn draw_zingg<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    scale: &str,
    classes: &BTreeMap<(usize, usize), Vec<(f64, f64)>>,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(perr)?;
    let mut chart = ChartBuilder::on(root)
        .caption(format!("{title} ({scale})"), (FONT_FAMILY, 18))
        .margin(14)
        .x_label_area_size(45)
        .y_label_area_size(55)
        .build_cartesian_2d(0f64..1.0, 0f64..1.0)
        .map_err(perr)?;
    chart
        .configure_mesh()
        .x_desc("b/a")
        .y_desc("c/b")
        .label_style((FONT_FAMILY, 14))
        .light_line_style(WHITE)
        .draw()
        .map_err(perr)?;
    let t = crate::shape::ZINGG_THRESHOLD;
    for line in [vec![(t, 0.0), (t, 1.0)], vec![(0.0, t), (1.0, t)]] {
        chart.draw_series(LineSeries::new(line, BLACK.mix(0.6).stroke_width(1))).map_err(perr)?;
    }
    // The most frequent classes get their own colour, the rest one grey "other" series.
    let mut by_count: Vec<((usize, usize), usize)> = classes.iter().map(|(k, v)| (*k, v.len())).collect();
    by_count.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let shown: BTreeSet<(usize, usize)> = by_count.iter().take(ZINGG_CLASSES).map(|(k, _)| *k).collect();
    let other: Vec<(f64, f64)> =
        classes.iter().filter(|(k, _)| !shown.contains(k)).flat_map(|(_, v)| v.iter().copied()).collect();
    if !other.is_empty() {
        let grey = RGBColor(150, 150, 150);
        let n_other = classes.len() - shown.len();
        chart
            .draw_series(other.iter().map(|&(x, y)| Circle::new((x, y), 3, grey.filled())))
            .map_err(perr)?
            .label(format!("{n_other} other classes (n = {})", other.len()))
            .legend(move |(x, y)| Circle::new((x + 6, y), 3, grey.filled()));
    }
    for (k, ((s, u), pts)) in classes.iter().filter(|(k, _)| shown.contains(k)).enumerate() {
        let color = crate::plot::series_color(k);
        chart
            .draw_series(pts.iter().map(|&(x, y)| Circle::new((x, y), 4, color.filled())))
            .map_err(perr)?
            .label(format!("{} (n = {})", class_label(Counts { stable: *s, unstable: *u, saddle: 0 }), pts.len()))
            .legend(move |(x, y)| Circle::new((x + 6, y), 4, color.filled()));
    }
    for (z, (x, y)) in [
        (Zingg::Rod, (0.02, 0.99)),
        (Zingg::Spheroid, (t + 0.01, 0.99)),
        (Zingg::Blade, (0.02, t - 0.01)),
        (Zingg::Disc, (t + 0.01, t - 0.01)),
    ] {
        chart.draw_series(std::iter::once(Text::new(z.name(), (x, y), (FONT_FAMILY, 15)))).map_err(perr)?;
    }
    chart
        .configure_series_labels()
        .label_font((FONT_FAMILY, 13))
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerLeft)
        .draw()
        .map_err(perr)?;
    Ok(())
}

/// One series of a scatter plot.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Marker colour.
    pub color: RGBColor,
    /// Filled or hollow markers.
    pub filled: bool,
    /// The (x, y) points.
    pub points: Vec<(f64, f64)>,
    /// Draw this trend line (its equation and R² go into the legend).
    pub trend: Option<LogFit>,
}

/// A scatter plot of `series` with their logarithmic trend lines; `diagonal` adds y = x.
pub fn scatter_plot(
    path: &Path,
    title: &str,
    labels: (&str, &str),
    series: &[Series],
    diagonal: bool,
) -> crate::Result<()> {
    render!(path, (980, 640), |root| draw_scatter(&root, title, labels, series, diagonal))
}

fn draw_scatter<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    labels: (&str, &str),
    series: &[Series],
    diagonal: bool,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(perr)?;
    let pts = || series.iter().flat_map(|s| s.points.iter()).filter(|p| p.0.is_finite() && p.1.is_finite());
    let (mut x0, mut x1) = pts().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (mut y0, mut y1) = pts().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.1), b.max(p.1)));
    if !x0.is_finite() {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    if diagonal {
        (x0, y0) = (x0.min(y0), x0.min(y0));
        (x1, y1) = (x1.max(y1), x1.max(y1));
    }
    let (dx, dy) = ((x1 - x0).max(1e-3) * 0.08, (y1 - y0).max(1e-3) * 0.1);
    let (x0, x1, y0, y1) = (x0 - dx, x1 + dx, y0 - dy, y1 + dy);
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT_FAMILY, 19))
        .margin(14)
        .x_label_area_size(45)
        .y_label_area_size(55)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(perr)?;
    chart.configure_mesh().x_desc(labels.0).y_desc(labels.1).label_style((FONT_FAMILY, 14)).draw().map_err(perr)?;
    if diagonal {
        chart
            .draw_series(LineSeries::new(vec![(x0, x0), (x1, x1)], BLACK.mix(0.5)))
            .map_err(perr)?
            .label("y = x")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK.mix(0.5)));
    }
    for s in series {
        let color = s.color;
        let style = if s.filled { color.filled() } else { color.stroke_width(2) };
        let good = s.points.iter().filter(|p| p.0.is_finite() && p.1.is_finite());
        chart
            .draw_series(good.map(|&(x, y)| Circle::new((x, y), 4, style)))
            .map_err(perr)?
            .label(s.label.clone())
            .legend(move |(x, y)| Circle::new((x + 6, y), 4, style));
        if let Some(t) = s.trend {
            let (lo, hi) = s.points.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| (a.min(p.0), b.max(p.0)));
            if lo > 0.0 && hi > lo {
                let line: Vec<(f64, f64)> =
                    (0..=60).map(|k| lo + (hi - lo) * k as f64 / 60.0).map(|x| (x, t.eval(x))).collect();
                chart
                    .draw_series(LineSeries::new(line, color.stroke_width(2)))
                    .map_err(perr)?
                    .label(format!("  {}", t.describe()))
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2)));
            }
        }
    }
    chart
        .configure_series_labels()
        .label_font((FONT_FAMILY, 12))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .map_err(perr)?;
    Ok(())
}

/// χ²(ν) curves (log ν axis, log χ² axis) with the fitted ν of each and the paper's 0.0035.
pub fn plot_loss(path: &Path, title: &str, fits: &[(String, &NuFit)]) -> crate::Result<()> {
    render!(path, (980, 620), |root| draw_loss(&root, title, fits))
}

fn draw_loss<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, title: &str, fits: &[(String, &NuFit)]) -> DrawResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(perr)?;
    let xs = || fits.iter().flat_map(|f| f.1.grid.iter().copied());
    let ys = || fits.iter().flat_map(|f| f.1.chi2.iter().copied()).filter(|y| *y > 0.0 && y.is_finite());
    let (x0, x1) = (xs().fold(f64::INFINITY, f64::min), xs().fold(0.0, f64::max));
    let (y0, y1) = (ys().fold(f64::INFINITY, f64::min).max(1e-3), ys().fold(0.0, f64::max).max(1.0));
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT_FAMILY, 19))
        .margin(14)
        .x_label_area_size(45)
        .y_label_area_size(65)
        .build_cartesian_2d((x0..x1).log_scale(), (y0 / 1.5..y1 * 1.5).log_scale())
        .map_err(perr)?;
    chart
        .configure_mesh()
        .x_desc("ν (log scale)")
        .y_desc("χ² (log scale)")
        .x_label_formatter(&|x: &f64| crate::plot::log_tick(*x))
        .y_label_formatter(&|y: &f64| crate::plot::log_tick(*y))
        .label_style((FONT_FAMILY, 14))
        .draw()
        .map_err(perr)?;
    chart
        .draw_series(LineSeries::new(vec![(PAPER_NU, y0 / 1.5), (PAPER_NU, y1 * 1.5)], BLACK.stroke_width(1)))
        .map_err(perr)?
        .label("paper: ν = 0.0035")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK));
    for (k, (label, f)) in fits.iter().enumerate() {
        let color = crate::plot::series_color(k);
        let pts: Vec<(f64, f64)> = f.grid.iter().zip(&f.chi2).map(|(x, y)| (*x, y.max(y0))).collect();
        chart
            .draw_series(LineSeries::new(pts, color.stroke_width(2)))
            .map_err(perr)?
            .label(format!("{label}: ν = {:.2e}", f.nu))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2)));
        chart.draw_series(std::iter::once(Circle::new((f.nu, f.chi2_min.max(y0)), 5, color.filled()))).map_err(perr)?;
    }
    chart
        .configure_series_labels()
        .label_font((FONT_FAMILY, 12))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(perr)?;
    Ok(())
}

/// Colours of the Figure 12 plots: hand (purple, yellow as in the paper) and computed (red, blue).
pub const HAND_S: RGBColor = RGBColor(128, 60, 160);
/// Hand experiments, unstable (yellow).
pub const HAND_U: RGBColor = RGBColor(215, 170, 0);
/// Computed, stable (red).
pub const COMPUTED_S: RGBColor = RGBColor(210, 40, 40);
/// Computed, unstable (blue).
pub const COMPUTED_U: RGBColor = RGBColor(40, 90, 210);

/// Write a comparison as CSV.
pub fn write_comparison_csv<W: std::io::Write>(rows: &[Comparison], nu: f64, w: W) -> crate::Result<()> {
    (|| -> std::result::Result<_, crate::error::BoxError> {
        let mut out = csv::Writer::from_writer(w);
        out.write_record([
            "id",
            "nu",
            "hand_c_over_b",
            "hand_c_over_a",
            "sim_c_over_b",
            "sim_c_over_a",
            "hand_E_S",
            "hand_E_U",
            "hand_sd_S",
            "hand_sd_U",
            "sim_E_S",
            "sim_E_U",
            "sim_sd_S",
            "sim_sd_U",
            "sim_n",
            "paper_E_S",
            "paper_E_U",
            "paper_sd_S",
            "paper_sd_U",
        ])?;
        for r in rows {
            let mut row = vec![r.id.clone(), format!("{nu:e}")];
            row.extend([r.hand_c_over_b, r.hand_c_over_a, r.sim_c_over_b, r.sim_c_over_a].map(cell));
            row.extend(r.hand.map(cell));
            row.extend(r.sim.as_array().map(cell));
            row.push(r.sim.n.to_string());
            row.extend(r.paper_computer.map_or([f64::NAN; 4], |p| p).map(cell));
            out.write_record(row)?;
        }
        out.flush()?;
        Ok(())
    })()
    .map_err(|e| crate::Error::write(crate::error::MEMORY, e))
}

/// Write the Figure 12 plots of a comparison into `dir`: `fig12a_S.png/.svg` (E(S) against c/b
/// and c/a), `fig12a_U.png/.svg` (E(U)), `fig12b.png/.svg` (σ against E) and
/// `hand_vs_computed.png/.svg` (each statistic, computed against hand, with y = x). Returns the
/// files written.
pub fn plot_fig12(rows: &[Comparison], nu: f64, label: &str, dir: &Path) -> crate::Result<Vec<PathBuf>> {
    create_dir(dir)?;
    let t = trends(rows);
    let pts = |g: &dyn Fn(&Comparison) -> (f64, f64)| rows.iter().map(g).collect::<Vec<_>>();
    let ser = |label: &str, color: RGBColor, filled: bool, points: Vec<(f64, f64)>, trend: Option<LogFit>| Series {
        label: label.to_string(),
        color,
        filled,
        points,
        trend,
    };
    let light = |c: RGBColor| {
        RGBColor(((c.0 as u16 + 255) / 2) as u8, ((c.1 as u16 + 255) / 2) as u8, ((c.2 as u16 + 255) / 2) as u8)
    };
    let mut written = Vec::new();
    for (which, k, hc, sc) in [("S", 0usize, HAND_S, COMPUTED_S), ("U", 1, HAND_U, COMPUTED_U)] {
        let (h_cb, h_ca, s_cb, s_ca) = if k == 0 {
            (t.hand_es_cb, t.hand_es_ca, t.sim_es_cb, t.sim_es_ca)
        } else {
            (t.hand_eu_cb, t.hand_eu_ca, t.sim_eu_cb, t.sim_eu_ca)
        };
        let series = vec![
            ser(&format!("hand E({which}) vs c/b"), hc, true, pts(&|r| (r.hand_c_over_b, r.hand[k])), h_cb),
            ser(&format!("hand E({which}) vs c/a"), light(hc), true, pts(&|r| (r.hand_c_over_a, r.hand[k])), h_ca),
            ser(
                &format!("{label} E({which}) vs c/b"),
                sc,
                false,
                pts(&|r| (r.sim_c_over_b, r.sim.as_array()[k])),
                s_cb,
            ),
            ser(
                &format!("{label} E({which}) vs c/a"),
                light(sc),
                false,
                pts(&|r| (r.sim_c_over_a, r.sim.as_array()[k])),
                s_ca,
            ),
        ];
        for ext in ["png", "svg"] {
            let p = dir.join(format!("fig12a_{which}.{ext}"));
            scatter_plot(
                &p,
                &format!("Fig. 12A: E({which}) against flatness, hand vs {label} (ν = {nu:.2e})"),
                ("axis ratio (c/b, c/a)", &format!("E({which})")),
                &series,
                false,
            )?;
            written.push(p);
        }
    }
    let series = vec![
        ser("hand σ(S) vs E(S)", HAND_S, true, pts(&|r| (r.hand[0], r.hand[2])), t.hand_sd_s),
        ser("hand σ(U) vs E(U)", HAND_U, true, pts(&|r| (r.hand[1], r.hand[3])), t.hand_sd_u),
        ser(&format!("{label} σ(S) vs E(S)"), COMPUTED_S, false, pts(&|r| (r.sim.es, r.sim.sd_s)), t.sim_sd_s),
        ser(&format!("{label} σ(U) vs E(U)"), COMPUTED_U, false, pts(&|r| (r.sim.eu, r.sim.sd_u)), t.sim_sd_u),
    ];
    for ext in ["png", "svg"] {
        let p = dir.join(format!("fig12b.{ext}"));
        scatter_plot(
            &p,
            &format!("Fig. 12B: standard deviation against mean, hand vs {label} (ν = {nu:.2e})"),
            ("E", "σ (sample, n − 1)"),
            &series,
            false,
        )?;
        written.push(p);
    }
    let names = ["E(S)", "E(U)", "σ(S)", "σ(U)"];
    let colors = [COMPUTED_S, COMPUTED_U, HAND_S, HAND_U];
    let series: Vec<Series> =
        (0..4).map(|k| ser(names[k], colors[k], k < 2, pts(&|r| (r.hand[k], r.sim.as_array()[k])), None)).collect();
    for ext in ["png", "svg"] {
        let p = dir.join(format!("hand_vs_computed.{ext}"));
        scatter_plot(
            &p,
            &format!("Table 2 samples: {label} (ν = {nu:.2e}) against hand"),
            ("hand experiment", label),
            &series,
            true,
        )?;
        written.push(p);
    }
    Ok(written)
}
