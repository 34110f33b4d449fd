pub mod analyze;
pub mod drop;
pub mod generate;
pub mod perturb;
pub mod planar;
pub mod shake;
pub mod study;
pub mod study_hand;

use rocking_stones::dynamics::size::{dimension, Dimension, RealSize, Size};
use rocking_stones::mesh::unit::LengthUnit;
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

/// How a dynamics command is told the stone's real size (every command that simulates, and
/// `study --dynamic`): a length unit or R_max. The bundled stone knows its size; any other mesh
/// without one is refused ([`rocking_stones::dynamics::size`] says why).
#[derive(clap::Args, Clone, Default)]
pub struct SizeArgs {
    /// The mesh's length unit: mm, cm, m, km, in or a number of metres per unit. The stone's
    /// real size, on which every dynamic result depends (the rolling resistance relative to R_max;
    /// under shaking, the real frequencies of the motion). Needed for every mesh but the bundled
    /// stone (millimetres). Also spelled --unit.
    #[arg(long = "length-unit", alias = "unit", value_name = "UNIT", value_parser = parse_length_unit, conflicts_with = "size")]
    pub length_unit: Option<LengthUnit>,
    /// The stone's real size as R_max in metres (the largest distance from G to the hull),
    /// instead of --length-unit.
    #[arg(long, value_name = "R_MAX_M")]
    pub size: Option<f64>,
}

impl SizeArgs {
    /// The size as given, if it was.
    pub fn given(&self) -> Option<Size> {
        match (self.size, self.length_unit) {
            (Some(r), _) => Some(Size::RMax(r)),
            (None, Some(u)) => Some(Size::Unit(u.metres)),
            (None, None) => None,
        }
    }

    /// The real size of the stone `name` whose R_max is `r_max` mesh units: the one given, else
    /// the bundled stone's, else refused ([`RealSize::resolve`]). A size that is not plausible for
    /// a stone is warned about on standard error before anything runs.
    pub fn real_size(&self, name: &str, r_max: f64) -> anyhow::Result<RealSize> {
        let real = RealSize::resolve(name, r_max, self.given()).map_err(|e| anyhow::anyhow!(e.spelled(&flag)))?;
        if let Some(warning) = real.implausibility(name) {
            eprintln!("warning: {warning}.");
        }
        Ok(real)
    }
}

/// A length unit (`mm`, `cm`, `m`, `km`, `in` or metres per unit), checked as the library checks it.
pub fn parse_length_unit(s: &str) -> std::result::Result<LengthUnit, String> {
    s.parse::<LengthUnit>().map_err(|e| e.spelled(&flag))
}

/// An option given in real SI units for the stone of size `size` (its library name `name`, of a
/// [`dimension`]), as the number the scaled parameters hold.
pub fn scaled(size: &RealSize, name: &str, value: Option<f64>) -> Option<f64> {
    value.map(|v| dimension(name).map_or(v, |d| size.scaled(d, v)))
}

/// An option given in millimetres (a rolling-resistance or torsional-friction length), as the
/// scaled parameter δ / R_max of the stone of size `size`.
pub fn scaled_mm(size: &RealSize, value_mm: Option<f64>) -> Option<f64> {
    value_mm.map(|v| size.scaled(Dimension::Length, v * 1e-3))
}

/// A parameter error of the scaled frame told in the option's real units for the stone of size
/// `size`: `--max-time must be positive and finite, got -2` for `--max-time -2`, not the scaled
/// number the check saw. Other errors as they are.
pub fn in_real_units(e: rocking_stones::Error, size: &RealSize) -> anyhow::Error {
    if let rocking_stones::Error::Parameter { name, value, expected } = &e {
        if let (Some(d), Ok(v)) = (dimension(name), value.parse::<f64>()) {
            let real = size.real(d, v);
            let (real, unit) = match (d, name.as_str()) {
                (Dimension::Length, _) => (real * 1e3, " mm"),
                (Dimension::Time, _) => (real, " s"),
                (Dimension::Speed, _) => (real, " m/s"),
                (Dimension::Rate, "spin" | "rest_angular_speed") => (real, " rad/s"),
                (Dimension::Rate, "contact_frequency") => (real, " Hz"),
                (Dimension::Rate, _) => (real, " 1/s"),
            };
            let number = rocking_stones::report::names::number;
            let scaled = match d {
                Dimension::Time => format!(" = {} √(R_max/g)", number(v * rocking_stones::GRAVITY.sqrt(), 4)),
                _ => String::new(),
            };
            return anyhow::anyhow!("{} must be {expected}, got {}{unit}{scaled}", flag(name), number(real, 6));
        }
    }
    anyhow::anyhow!(e.spelled(&flag))
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
    /// Rolling-resistance length δ in mm: the contact's rolling torque is at most δ times the
    /// normal force (default: the surface pair's, e.g. 0.2 mm steel on wood, 0.1 mm rock on
    /// concrete).
    #[arg(long, value_name = "MM")]
    pub rolling_resistance_mm: Option<f64>,
    /// Replaced by --rolling-resistance-mm (δ in mm instead of δ/R_max).
    #[arg(long, hide = true, allow_hyphen_values = true)]
    pub rolling_resistance: Option<String>,
}

impl ContactArgs {
    /// Set the overrides given on `contact`, for a stone of real size `size`.
    pub fn apply(
        &self,
        contact: &mut rocking_stones::dynamics::engine::params::ContactParams,
        size: &RealSize,
    ) -> anyhow::Result<()> {
        if let Some(v) = &self.rolling_resistance {
            anyhow::bail!(
                "--rolling-resistance (δ/R_max) is now --rolling-resistance-mm, the length δ in mm: {v} R_max is {} mm \
                 for this stone",
                v.parse::<f64>().map_or("?".into(), |x| format!("{}", x * size.r_max_m * 1e3))
            );
        }
        contact.friction = self.friction.unwrap_or(contact.friction);
        contact.restitution = self.restitution.unwrap_or(contact.restitution);
        contact.rolling_resistance = scaled_mm(size, self.rolling_resistance_mm).unwrap_or(contact.rolling_resistance);
        Ok(())
    }

    /// Which of friction, restitution and rolling resistance are given.
    pub fn pinned(&self) -> [bool; 3] {
        [self.friction.is_some(), self.restitution.is_some(), self.rolling_resistance_mm.is_some()]
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
pub fn default_unit(name: &str, given: Option<LengthUnit>) -> rocking_stones::report::names::Unit {
    let known = rocking_stones::bundled::is_bundled(name).then(|| "mm".to_string());
    rocking_stones::report::names::Unit(given.map(|u| u.label()).or(known))
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
    } else if matches!(name, "rolling_resistance" | "torsional_friction") {
        format!("--{}-mm", name.replace('_', "-"))
    } else if NO_OPTION.contains(&name) {
        format!("the {} (no option)", name.replace('_', " "))
    } else {
        format!("--{}", name.replace('_', "-"))
    }
}
