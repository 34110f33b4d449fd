pub mod analyze;
pub mod drop;
pub mod generate;
pub mod perturb;
pub mod planar;
pub mod shake;
pub mod study;
pub mod study_hand;

use rocking_stones::dynamics::size::{RealSize, Size};
use std::path::{Path, PathBuf};

/// The progress bar of every long command: `n` steps, counted as `what` ("drops", "trials", or
/// "" for files), elapsed time, estimated time left and an optional message.
pub fn progress_bar(n: u64, what: &str) -> indicatif::ProgressBar {
    let what = if what.is_empty() { String::new() } else { format!(" {what}") };
    let bar = indicatif::ProgressBar::new(n);
    bar.set_style(
        indicatif::ProgressStyle::with_template(&format!(
            "{{bar:40}} {{pos}}/{{len}}{what} {{elapsed_precise}} (eta {{eta}}) {{msg}}"
        ))
        .expect("valid template"),
    );
    bar
}

/// The page `report.html` that [`emit`] writes beside a report's files: its title, and the hull
/// of the stone (for runs on one analysed stone), made only when the page is written.
pub struct Page<'a> {
    /// Title of the page (`rocking drop: pebble`).
    pub title: String,
    /// The 3D view of the stone, if the run has one.
    pub hull: Option<Box<dyn Fn() -> rocking_stones::report::html::HullView + 'a>>,
}

impl<'a> Page<'a> {
    /// The page of `rocking <command>` on the mesh `name`, without a 3D view.
    pub fn titled(command: &str, name: &str) -> Self {
        Page { title: format!("rocking {command}: {}", rocking_stones::report::short_name(name)), hull: None }
    }

    /// The page of `rocking <command>` on one analysed stone, with its hull in 3D, flocks at
    /// `nu` ([`hull_view`]).
    pub fn with_hull(command: &str, analysis: &'a rocking_stones::analysis::Analysis, name: &'a str, nu: f64) -> Self {
        Page { hull: Some(Box::new(move || hull_view(analysis, name, nu))), ..Page::titled(command, name) }
    }
}

/// Print a report (JSON or its human `summary`) and, with `-o DIR`, write its files, then (with a
/// `page`) `report.html` showing the summary and the files, and list what was written.
pub fn emit<R: serde::Serialize>(
    report: &R,
    json: bool,
    summary: &str,
    output: Option<&Path>,
    page: Option<Page>,
    write: impl FnOnce(&Path) -> rocking_stones::Result<Vec<PathBuf>>,
) -> anyhow::Result<()> {
    if json {
        println!("{}", serde_json::to_string_pretty(report)?);
    } else {
        print!("{summary}");
    }
    if let Some(dir) = output {
        let mut written = write(dir)?;
        if let Some(page) = page {
            let view = page.hull.map(|h| h());
            rocking_stones::report::html::add_page(dir, &mut written, &page.title, summary, view.as_ref())?;
        }
        for w in written {
            if !json {
                println!("wrote {}", w.display());
            }
        }
    }
    Ok(())
}

/// The real size of the stone `name` whose R_max is `r_max` mesh units: `--size` (R_max in
/// metres) or `--length-unit` if given, else the bundled stone's millimetres, else `assumed`
/// ([`RealSize::resolve`]). What was assumed, and a size that is not plausible for a stone, are
/// said on standard error before anything runs.
pub fn real_size(
    name: &str,
    r_max: f64,
    length_unit: Option<&str>,
    size: Option<f64>,
    assumed: Size,
) -> anyhow::Result<RealSize> {
    let given = match (size, length_unit) {
        (Some(r), _) => Some(Size::RMax(r)),
        (None, Some(u)) => Some(Size::Unit(rocking_stones::dynamics::shaking::parse_length_unit(u)?)),
        (None, None) => None,
    };
    let real = RealSize::resolve(name, r_max, given, assumed)?;
    if let Some(note) = real.assumption(name) {
        eprintln!("note: {note}; give --length-unit mm|cm|m|km or --size R_MAX_M.");
    }
    if let Some(warning) = real.implausibility(name) {
        eprintln!("warning: {warning}.");
    }
    Ok(real)
}

/// The contact overrides of every command that simulates (each defaults to the surface pair's).
#[derive(clap::Args, Clone)]
pub struct ContactArgs {
    /// Coulomb friction coefficient, ≥ 0 (default: the surface pair's).
    #[arg(long)]
    pub friction: Option<f64>,
    /// Restitution coefficient in [0, 1] (default: the surface pair's).
    #[arg(long)]
    pub restitution: Option<f64>,
    /// Rolling-resistance length δ / R_max (torque ≤ δ N at the contact); default: the surface
    /// pair's δ over the stone's real R_max.
    #[arg(long)]
    pub rolling_resistance: Option<f64>,
}

impl ContactArgs {
    /// Set the overrides given on `contact`.
    pub fn apply(&self, contact: &mut rocking_stones::dynamics::engine::params::ContactParams) {
        contact.friction = self.friction.unwrap_or(contact.friction);
        contact.restitution = self.restitution.unwrap_or(contact.restitution);
        contact.rolling_resistance = self.rolling_resistance.unwrap_or(contact.rolling_resistance);
    }

    /// Which of friction, restitution and rolling resistance are given.
    pub fn pinned(&self) -> [bool; 3] {
        [self.friction.is_some(), self.restitution.is_some(), self.rolling_resistance.is_some()]
    }
}

/// A whole number of at least `MIN` (a count, an id, a seed), refused in the option's words: a
/// negative or fractional value names the allowed range instead of a parser's message.
pub fn at_least<T: std::str::FromStr + TryFrom<u64> + PartialOrd, const MIN: u64>(
    s: &str,
) -> std::result::Result<T, String> {
    let min = T::try_from(MIN).map_err(|_| format!("{MIN} is out of range"))?;
    match s.trim().parse::<T>() {
        Ok(v) if v >= min => Ok(v),
        _ => Err(format!("expected a whole number, at least {MIN}, got {s:?}")),
    }
}

/// ν of the macro scale, checked as the library checks it.
pub fn parse_nu(s: &str) -> std::result::Result<f64, String> {
    let v: f64 = s.parse().map_err(|e| format!("{e}"))?;
    rocking_stones::analysis::check_nu(v).map_err(|e| e.spelled(&flag))
}

/// The relative coplanarity tolerance of the facet merge, checked as the library checks it.
pub fn parse_coplanar_tol(s: &str) -> std::result::Result<f64, String> {
    let v: f64 = s.parse().map_err(|e| format!("{e}"))?;
    rocking_stones::analysis::check_coplanar_tol(v).map_err(|e| e.spelled(&flag))
}

/// Parse `x,y,z` (three finite numbers) as a point.
pub fn parse_point(s: &str) -> std::result::Result<rocking_stones::Point3, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| format!("expected x,y,z (three numbers), got {s:?}"))?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(rocking_stones::Point3::new(x, y, z)),
        _ => Err(format!("expected x,y,z (three finite numbers), got {s:?}")),
    }
}

/// The 3D view of `report.html` for a dynamics run on `analysis` with flocks at `nu` (the
/// stone's macro scale), lengths in mesh units (millimetres for the bundled stone).
pub fn hull_view(
    analysis: &rocking_stones::analysis::Analysis,
    name: &str,
    nu: f64,
) -> rocking_stones::report::html::HullView {
    let opts = rocking_stones::analysis::Options { nu: Some(nu), ..Default::default() };
    let r = analysis.report(name, &opts);
    rocking_stones::report::html::hull_view(analysis, &r, &default_unit(name, None))
}

/// The length unit that labels a mesh's lengths: the one given, else millimetres for the bundled
/// stone (it knows its unit), else "mesh units".
pub fn default_unit(name: &str, given: Option<&String>) -> rocking_stones::report::names::Unit {
    let known = rocking_stones::bundled::is_bundled(name).then(|| "mm".to_string());
    rocking_stones::report::names::Unit(given.cloned().or(known))
}

/// The command line's spelling of a library parameter (`max_time` → `--max-time`); the
/// parameters that have no option of their own are named in words.
pub fn flag(name: &str) -> String {
    const NO_OPTION: [&str; 9] = [
        "rest_time",
        "rest_linear_speed",
        "rest_angular_speed",
        "settle_time",
        "hold_time",
        "degeneracy_tol",
        "components",
        "down",
        "grid",
    ];
    // Parameters the command line builds from options of other names.
    let built = match name {
        "epsilons" => Some("the ε grid (--eps-min, --eps-max, --eps-steps)"),
        "pgas" => Some("the PGA grid (--pga-max, --pga-steps)"),
        "frequency_hz" => Some("the frequency of --pulse"),
        "scale" => Some("each of --scales"),
        _ => None,
    };
    if let Some(b) = built {
        b.to_string()
    } else if NO_OPTION.contains(&name) {
        format!("the {} (no option)", name.replace('_', " "))
    } else {
        format!("--{}", name.replace('_', "-"))
    }
}
