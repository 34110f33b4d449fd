//! `rocking planar`: the planar case (paper §1.1): micro-equilibria, hierarchy and flocks of a
//! discretised ellipse or a regular polygon.

use anyhow::Result;
use rocking_stones::planar::{
    ellipse_polygon, sides_for_k, table1, PlanarAnalysis, PlanarReport, Polygon, Sampling, DEFAULT_DEGENERACY_TOL,
};
use rocking_stones::report;
use rocking_stones::report::planar::ShapeInfo;
use serde::Serialize;

#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    pub shape: Shape,
}

#[derive(clap::Subcommand)]
pub enum Shape {
    /// The ellipse with semi-axes a (along x, the major axis) and 1 (along y), discretised into
    /// N = 4k − 2 sides (vertex 0 at (a, 0)).
    Ellipse(EllipseArgs),
    /// The regular n-gon (S = U = n).
    Regular(RegularArgs),
}

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum SamplingArg {
    /// Equal arc-length spacing (the paper's).
    Arclength,
    /// Equal steps of the parameter t of (a cos t, sin t).
    Angle,
    /// Independent uniform arc-length positions (use --seed).
    Random,
}

#[derive(clap::Args)]
pub struct EllipseArgs {
    /// Semi-axis along x (a ≥ 1); the other semi-axis is 1.
    #[arg(long)]
    pub a: f64,
    /// N = 4k − 2 sides.
    #[arg(long, required_unless_present = "sides", conflicts_with = "sides", value_parser = super::at_least::<usize, 1>)]
    pub k: Option<usize>,
    /// Number of sides N directly (instead of --k).
    #[arg(long, value_parser = super::at_least::<usize, 3>)]
    pub sides: Option<usize>,
    /// How the N vertices are placed on the ellipse.
    #[arg(long, value_enum, default_value_t = SamplingArg::Arclength)]
    pub sampling: SamplingArg,
    /// Seed of --sampling random.
    #[arg(long, default_value_t = 1, value_parser = super::at_least::<u64, 0>)]
    pub seed: u64,
    #[command(flatten)]
    pub common: Common,
}

#[derive(clap::Args)]
pub struct RegularArgs {
    /// Number of sides (at least 3).
    #[arg(short = 'n', long = "sides", alias = "n", value_parser = super::at_least::<usize, 3>)]
    pub n: usize,
    #[command(flatten)]
    pub common: Common,
}

#[derive(clap::Args)]
pub struct Common {
    /// Fix ν of the macro scale (default: the automatic plateau if it is clear, else 0.0035).
    #[arg(long)]
    pub nu: Option<f64>,
    /// Print one JSON object instead of the summary.
    #[arg(long)]
    pub json: bool,
    /// Relative tolerance of degenerate predicates (× bounding-box diagonal).
    #[arg(long, default_value_t = DEFAULT_DEGENERACY_TOL)]
    pub degeneracy_tol: f64,
}

#[derive(Serialize)]
struct Output<'a> {
    shape: ShapeInfo,
    #[serde(flatten)]
    report: &'a PlanarReport,
    /// Table 1's k → ∞ limit (ellipse only).
    table1: Option<rocking_stones::planar::Table1>,
}

pub fn run_planar(args: Args) -> Result<()> {
    let (polygon, info, common) = match &args.shape {
        Shape::Ellipse(e) => {
            let sides = match (e.k, e.sides) {
                (Some(k), _) if k >= 1 => sides_for_k(k),
                (Some(k), _) => anyhow::bail!("--k must be ≥ 1, got {k}"),
                (None, Some(n)) if n >= 3 => n,
                (None, Some(n)) => anyhow::bail!("--sides must be at least 3 for a polygon, got {n}"),
                (None, None) => anyhow::bail!("give --k or --sides"),
            };
            let sampling = match e.sampling {
                SamplingArg::Arclength => Sampling::ArcLength,
                SamplingArg::Angle => Sampling::Angle,
                SamplingArg::Random => Sampling::Random { seed: e.seed },
            };
            let p = ellipse_polygon(e.a, sides, sampling)?;
            (p, ShapeInfo::Ellipse { a: e.a, k: e.k, sides, sampling }, &e.common)
        }
        Shape::Regular(r) if r.n < 3 => anyhow::bail!("-n (sides) must be at least 3 for a polygon, got {}", r.n),
        Shape::Regular(r) => (Polygon::regular(r.n, 1.0, 0.0)?, ShapeInfo::Regular { n: r.n }, &r.common),
    };
    if !(common.degeneracy_tol > 0.0 && common.degeneracy_tol.is_finite()) {
        anyhow::bail!("--degeneracy-tol must be a positive finite number, got {}", common.degeneracy_tol);
    }
    if let Some(nu) = common.nu {
        anyhow::ensure!(nu.is_finite() && nu >= 0.0, "--nu must be a non-negative number, got {nu}");
    }
    let analysis = PlanarAnalysis::new(polygon, common.degeneracy_tol)?;
    let report = analysis.report(common.nu);
    let limit = match info {
        ShapeInfo::Ellipse { a, .. } => table1(a),
        ShapeInfo::Regular { .. } => None,
    };
    if common.json {
        println!("{}", serde_json::to_string_pretty(&Output { shape: info, report: &report, table1: limit })?);
    } else {
        print!("{}", report::planar::summary(&info, &report, limit.as_ref()));
    }
    Ok(())
}
