//! What a person reads of a drop run ([`crate::dynamics::drops::montecarlo`]): the summary, `drops.json` and the
//! bar plots of resting flocks and facets against the quasi-static probabilities.

use super::names::number;
use super::{write_json, Folder};
use crate::plot::{render, DrawResult, FONT_FAMILY};
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A readable summary of a drop run whose real size is not known here (merged shards): speeds,
/// spins and times as multiples of √(g R_max), √(g/R_max) and √(R_max/g).
pub fn drop_summary(r: &crate::dynamics::drops::montecarlo::DropReport) -> String {
    drop_summary_sized(r, None)
}

/// The run's speeds, spins and times (kept in the frame scaled to R_max = 1 m, g = 9.81 m/s²) as
/// the dimensionless multiples they are, and, for a stone of real R_max `r_max_m` metres, in SI
/// units of the real stone (Froude scaling, [`crate::dynamics::drops::params`]).
pub struct Scaled {
    /// The real R_max in metres, if known.
    pub r_max_m: Option<f64>,
}

impl Scaled {
    /// A speed of the scaled frame: "1.28 √(g R_max) = 1.69 m/s" (4 m/s at R_max = 1 m, for the
    /// bundled stone).
    pub fn speed(&self, v: f64) -> String {
        let real = self.r_max_m.map(|l| format!(" = {} m/s", number(v * l.sqrt(), 3)));
        format!("{} √(g R_max){}", number(v / crate::GRAVITY.sqrt(), 3), real.unwrap_or_default())
    }

    /// An angular speed of the scaled frame: "7.98 √(g/R_max) = 59.2 rad/s" (25 rad/s at
    /// R_max = 1 m, for the bundled stone).
    pub fn spin(&self, w: f64) -> String {
        let real = self.r_max_m.map(|l| format!(" = {} rad/s", number(w / l.sqrt(), 3)));
        format!("{} √(g/R_max){}", number(w / crate::GRAVITY.sqrt(), 3), real.unwrap_or_default())
    }

    /// A rate (a velocity damping) of the scaled frame, as [`Scaled::spin`] in s⁻¹.
    pub fn rate(&self, c: f64) -> String {
        let real = self.r_max_m.map(|l| format!(" = {} s⁻¹", number(c / l.sqrt(), 3)));
        format!("{} √(g/R_max){}", number(c / crate::GRAVITY.sqrt(), 3), real.unwrap_or_default())
    }

    /// A time of the scaled frame: "0.0261 √(R_max/g) = 0.00352 s" (1/120 s at R_max = 1 m, for
    /// the bundled stone).
    pub fn time(&self, t: f64) -> String {
        let real = self.r_max_m.map(|l| format!(" = {} s", number(t * l.sqrt(), 3)));
        format!("{} √(R_max/g){}", number(t * crate::GRAVITY.sqrt(), 3), real.unwrap_or_default())
    }

    /// A length in units of R_max, in mm too when the real size is known: "0.001122 R_max =
    /// 0.2 mm" (steel on wood's rolling-resistance length, for the bundled stone).
    pub fn length(&self, x: f64) -> String {
        let real = self.r_max_m.map(|l| format!(" = {} mm", number(x * l * 1e3, 3)));
        format!("{} R_max{}", number(x, 4), real.unwrap_or_default())
    }

    /// " for R_max = 178.3 mm" when the real size is known.
    pub fn for_size(&self) -> String {
        self.r_max_m.map_or(String::new(), |l| format!(" for R_max = {}", crate::dynamics::size::format_length(l)))
    }
}

/// A readable summary of a drop run on a stone of real R_max `r_max_m` metres if known.
pub fn drop_summary_sized(r: &crate::dynamics::drops::montecarlo::DropReport, r_max_m: Option<f64>) -> String {
    let at = Scaled { r_max_m };
    let mut s = String::new();
    let p = &r.params;
    let plural = |n: u64, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    let _ = writeln!(
        s,
        "{}: {} of {} (seed {}), preset {}{}; {} settled, {} ended by the {} certificate{}",
        r.mesh,
        r.drops,
        plural(r.drops_requested, "drop", "drops"),
        r.seed,
        r.preset.as_deref().unwrap_or("custom"),
        r.surface.map_or(String::new(), |s| format!(" ({})", s.stands_for())),
        r.settled,
        r.certified,
        r.certificate.name(),
        if r.unsettled > 0 { format!(", {} still moving (left out)", r.unsettled) } else { String::new() }
    );
    let _ = writeln!(
        s,
        "  launch: height {} R_max, horizontal speed {}, spin {} ({}){}",
        number(p.launch.height, 4),
        at.speed(p.launch.horizontal_speed),
        at.spin(p.launch.spin),
        match p.launch.spin_distribution {
            crate::dynamics::drops::params::SpinDistribution::Fixed => "exact",
            crate::dynamics::drops::params::SpinDistribution::Gaussian => "rms, Gaussian",
        },
        at.for_size()
    );
    let _ = writeln!(
        s,
        "  contact: friction {}, restitution {}, rolling resistance {}, torsional {} (single contact point), damping {} linear, {} angular; dt {}, flight {}",
        number(p.sim.contact.friction, 4),
        number(p.sim.contact.restitution, 4),
        at.length(p.sim.contact.rolling_resistance),
        at.length(p.sim.contact.torsional_friction),
        at.rate(p.sim.contact.linear_damping),
        at.rate(p.sim.contact.angular_damping),
        at.time(p.sim.numerics.dt),
        p.sim.flight.mode
    );
    let mean = |t: Option<f64>| t.map_or("-".to_string(), |t| at.time(t));
    let _ = writeln!(
        s,
        "  simulated time per drop: {} to rest, {} to the certificate's decision",
        mean(r.mean_time_to_rest),
        mean(r.mean_time_to_decision)
    );
    s += &super::depth_line(r.deepest_penetration);
    if r.drops_beyond_depth_bound > 0 {
        let _ = writeln!(
            s,
            "  ({} of {} went deeper than the bound; with --flight rapier impacts are found only after the stone \
             is inside the ground: keep the default --flight free)",
            r.drops_beyond_depth_bound, r.drops
        );
    }
    if r.unsettled > 0 {
        let _ = writeln!(
            s,
            "  WARNING: {} still moving at the {} cap: left out of every count, fraction and fit below (a drop \
             that has not come to rest has no resting position). Raise --max-time, lower --dt, or add \
             --rolling-resistance.",
            plural(r.unsettled, "drop", "drops"),
            at.time(p.sim.numerics.max_time)
        );
    }
    if r.off_equilibrium > 0 {
        let _ = writeln!(
            s,
            "  note: {} stopped above their stable facet (held by friction or rolling resistance); counted \
             where the quasi-static descent leads",
            plural(r.off_equilibrium, "drop", "drops")
        );
    }
    if r.settled == 0 {
        let _ =
            writeln!(s, "  no drop came to rest: no fractions, nothing to compare with the quasi-static probabilities");
        return s;
    }
    let _ = writeln!(s, "  flocks at ν = {:.4e} (fractions of the {} drops at rest):", r.nu, r.settled);
    let _ = writeln!(
        s,
        "    {:>5} {:<9} {:>7} {:>9} {:>18} {:>9}",
        "flock", "type", "drops", "fraction", "95% interval", "static"
    );
    for f in &r.flocks {
        let _ = writeln!(
            s,
            "    {:>5} {:<9} {:>7} {:>9.4} {:>18} {:>9.4}",
            f.id,
            f.kind.name(),
            f.count,
            f.fraction,
            format!("[{:.4}, {:.4}]", f.ci95.0, f.ci95.1),
            f.static_probability
        );
    }
    let mut facets: Vec<_> = r.facets.iter().collect();
    facets.sort_by(|a, b| b.count.cmp(&a.count).then(b.static_probability.total_cmp(&a.static_probability)));
    if facets.is_empty() {
        let _ = writeln!(
            s,
            "  facets: not determined (the flock certificate stops a drop once its flock is certain; \
             use --certificate facet or none for per-facet counts)"
        );
    } else {
        let _ = writeln!(
            s,
            "  stable facets (the {} most frequent of {}; fractions of the {} drops whose facet is determined):",
            facets.len().min(12),
            facets.len(),
            r.facet_drops
        );
        let _ = writeln!(
            s,
            "    {:>6} {:>5} {:>7} {:>9} {:>18} {:>9}",
            "facet", "flock", "drops", "fraction", "95% interval", "static"
        );
    }
    for f in facets.iter().take(12) {
        let _ = writeln!(
            s,
            "    {:>6} {:>5} {:>7} {:>9.4} {:>18} {:>9.4}{}",
            f.facet,
            f.flock.map_or("-".into(), |k| k.to_string()),
            f.count,
            f.fraction,
            format!("[{:.4}, {:.4}]", f.ci95.0, f.ci95.1),
            f.static_probability,
            if f.equilibrium.is_none() { "  (not a stable facet)" } else { "" }
        );
    }
    let fit = |name: &str, f: &crate::dynamics::drops::montecarlo::Fit| {
        if f.dof == 0 {
            return format!("{name}: no χ² test (every drop in one category), KL = {:.4} nats", f.kl_divergence);
        }
        format!(
            "{name}: χ² = {:.2} ({} dof, p = {:.3}), KL = {:.4} nats",
            f.chi_square, f.dof, f.p_value, f.kl_divergence
        )
    };
    let _ = writeln!(s, "  vs quasi-static: {}", fit("flocks", &r.fit_flocks));
    if let Some(f) = &r.fit_facets {
        let _ = writeln!(s, "                   {}", fit("facets", f));
    }
    s
}

/// Write `drops.json` and bar plots `drops_flocks.png/.svg`, `drops_facets.png/.svg` into `dir`.
pub fn write_drop_outputs(
    r: &crate::dynamics::drops::montecarlo::DropReport,
    dir: &Path,
) -> crate::Result<Vec<PathBuf>> {
    let mut out = Folder::create(dir)?;
    out.file("drops.json", |p| write_json(p, r))?;
    let flocks: Vec<Bar> = r
        .flocks
        .iter()
        .map(|f| Bar {
            label: format!("F{} {}", f.id, f.kind),
            fraction: f.fraction,
            ci: f.ci95,
            reference: f.static_probability,
        })
        .collect();
    let caption = format!("Resting flock: drops (n = {}) vs quasi-static", r.settled);
    for ext in ["png", "svg"] {
        out.file(&format!("drops_flocks.{ext}"), |p| bar_plot(p, &caption, &flocks))?;
    }
    let mut facets: Vec<_> = r.facets.iter().collect();
    facets.sort_by(|a, b| b.static_probability.total_cmp(&a.static_probability).then(b.count.cmp(&a.count)));
    let bars: Vec<Bar> = facets
        .iter()
        .take(30)
        .map(|f| Bar { label: f.facet.to_string(), fraction: f.fraction, ci: f.ci95, reference: f.static_probability })
        .collect();
    for ext in ["png", "svg"] {
        out.file(&format!("drops_facets.{ext}"), |p| {
            bar_plot(p, "Resting facet (micro-equilibrium): drops vs quasi-static", &bars)
        })?;
    }
    Ok(out.written)
}

/// One category of a bar plot: empirical fraction with its interval, and a reference value.
pub struct Bar {
    /// Category name on the x axis.
    pub label: String,
    /// Empirical fraction.
    pub fraction: f64,
    /// 95 % interval of the fraction.
    pub ci: (f64, f64),
    /// Reference (static) probability drawn beside it.
    pub reference: f64,
}

/// Bars of empirical fractions with 95 % intervals beside reference (static) probabilities.
pub fn bar_plot(path: &Path, title: &str, bars: &[Bar]) -> crate::Result<()> {
    let (w, h) = (1000u32, 560u32);
    render!(path, (w, h), |root| draw_bars(&root, title, bars))
}

fn draw_bars<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    bars: &[Bar],
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| format!("{x:?}");
    root.fill(&WHITE).map_err(e)?;
    let top = bars.iter().map(|b| b.ci.1.max(b.reference)).fold(0.0, f64::max).max(0.05) * 1.15;
    let n = bars.len().max(1);
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT_FAMILY, crate::plot::style::TITLE))
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(60)
        .build_cartesian_2d(-0.5f64..n as f64 - 0.5, 0f64..top)
        .map_err(e)?;
    let labels: Vec<String> = bars.iter().map(|b| b.label.clone()).collect();
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(n.min(30))
        .x_label_formatter(&|x| {
            let i = x.round();
            if (x - i).abs() < 1e-6 && i >= 0.0 {
                labels.get(i as usize).cloned().unwrap_or_default()
            } else {
                String::new()
            }
        })
        .y_desc("probability")
        .label_style((FONT_FAMILY, crate::plot::style::TICK))
        .draw()
        .map_err(e)?;
    let drops = crate::plot::colors::BLUE;
    let stat = crate::plot::colors::ORANGE;
    chart
        .draw_series(
            bars.iter()
                .enumerate()
                .map(|(i, b)| Rectangle::new([(i as f64 - 0.38, 0.0), (i as f64 - 0.02, b.fraction)], drops.filled())),
        )
        .map_err(e)?
        .label("drops (95% Wilson interval)")
        .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], drops.filled()));
    chart
        .draw_series(bars.iter().enumerate().map(|(i, b)| {
            PathElement::new(vec![(i as f64 - 0.2, b.ci.0), (i as f64 - 0.2, b.ci.1)], BLACK.stroke_width(2))
        }))
        .map_err(e)?;
    chart
        .draw_series(
            bars.iter()
                .enumerate()
                .map(|(i, b)| Rectangle::new([(i as f64 + 0.02, 0.0), (i as f64 + 0.38, b.reference)], stat.filled())),
        )
        .map_err(e)?
        .label("quasi-static (basin area / 4π)")
        .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], stat.filled()));
    chart
        .configure_series_labels()
        .label_font((FONT_FAMILY, crate::plot::style::LEGEND))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(e)?;
    Ok(())
}

/// One flock of a table that sets drop runs of one stone side by side, as the experiments'
/// READMEs print it (serialised with `static` for the probability).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FlockCells {
    /// The flock's id.
    pub id: usize,
    /// Its type ([`crate::equilibria::Kind::name`]: stable, unstable, saddle).
    pub kind: &'static str,
    /// Its quasi-static probability, with the table's decimals.
    #[serde(rename = "static")]
    pub static_probability: String,
    /// Per run, its fraction with the 95 % interval
    /// ([`crate::dynamics::drops::montecarlo::DropReport::flock_fraction_with_ci`], "—" where the
    /// run has no row for it).
    pub cells: Vec<String>,
}

/// The rows of a table of drop runs of one stone side by side: one [`FlockCells`] per flock of
/// the first report (its rows, in its order), with a cell per report, every number with `digits`
/// decimals; no rows without a report.
pub fn flock_cells(reports: &[&crate::dynamics::drops::montecarlo::DropReport], digits: usize) -> Vec<FlockCells> {
    let Some(first) = reports.first() else { return Vec::new() };
    let row = |f: &crate::dynamics::drops::montecarlo::FlockRow| FlockCells {
        id: f.id,
        kind: f.kind.name(),
        static_probability: format!("{:.digits$}", f.static_probability),
        cells: reports.iter().map(|r| r.flock_fraction_with_ci(f.id, digits)).collect(),
    };
    first.flocks.iter().map(row).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::certificate::CertificateMode;
    use crate::dynamics::drops::launch::DropOutcome;
    use crate::dynamics::drops::montecarlo::{summarize, RunHeader};
    use crate::dynamics::drops::params::Preset;
    use crate::dynamics::stone::StaticModel;
    use crate::dynamics::surface::Surface;
    use crate::equilibria::Kind;
    use crate::Vec3;

    #[test]
    fn a_flock_table_has_the_first_runs_flocks_and_a_cell_per_run() {
        // Two stable facets in flocks 0 and 1 (static 0.7, 0.3) and a saddle flock 2 no drop reaches.
        let model = StaticModel {
            facet_normals: vec![Vec3::x(), Vec3::y()],
            facet_equilibrium: vec![Some(0), Some(1)],
            facet_flock: vec![Some(0), Some(1)],
            flock_kinds: vec![Kind::Stable, Kind::Stable, Kind::Saddle],
            facet_probability: vec![0.7, 0.3],
            nu: 0.0,
        };
        let run = |facets: &[u32]| {
            let drop = |(i, &facet): (usize, &u32)| DropOutcome::at_rest(i as u64, facet, 1.0);
            let outcomes = facets.iter().enumerate().map(drop).map(|o| (o.index, o)).collect();
            let header = RunHeader::of_params(
                "t",
                1,
                facets.len() as u64,
                Preset::Drop.params(Surface::SteelOnWood),
                CertificateMode::None,
            );
            summarize(&model, &header, &outcomes)
        };
        // All four drops in flock 0 in the first run; one in four in the second.
        let (a, b) = (run(&[0, 0, 0, 0]), run(&[0, 1, 1, 1]));
        let rows = flock_cells(&[&a, &b], 2);
        // Wilson at z = 1.96: 4 of 4 → [0.51, 1.00], 0 of 4 → [0.00, 0.49], 1 of 4 → [0.05, 0.70].
        let want = |id, p: &str, cells: [&str; 2]| FlockCells {
            id,
            kind: "stable",
            static_probability: p.into(),
            cells: cells.map(String::from).to_vec(),
        };
        assert_eq!(
            rows,
            vec![
                want(0, "0.70", ["1.00 [0.51, 1.00]", "0.25 [0.05, 0.70]"]),
                want(1, "0.30", ["0.00 [0.00, 0.49]", "0.75 [0.30, 0.95]"]),
            ]
        );
        assert!(flock_cells(&[], 2).is_empty());
    }
}
