//! `rocking drop` and `rocking merge`: Monte Carlo drops of a scan in rapier3d.

use super::analyze::load_analysis;
use anyhow::{bail, Result};
use rocking_stones::analysis::{check_nu, Options};
use rocking_stones::dynamics::certificate::CertificateMode;
use rocking_stones::dynamics::drops::montecarlo::{
    check_outcomes, merge, read_partial, summarize, DropReport, DropRun, RunHeader, Shard,
};
use rocking_stones::dynamics::drops::params::{DropParams, Preset};
use rocking_stones::dynamics::engine::params::Flight;
use rocking_stones::dynamics::size::{RealSize, Size};
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Mesh file (STL, OBJ, PLY). None: the bundled default stone.
    pub mesh: Option<PathBuf>,
    /// Number of drops in the whole run (≥ 1).
    #[arg(short = 'n', long, default_value_t = 1000, value_parser = super::at_least::<u64, 1>)]
    pub drops: u64,
    /// Seed: drop i uses its own stream derived from (seed, i).
    #[arg(long, default_value_t = 1, value_parser = super::at_least::<u64, 0>)]
    pub seed: u64,
    /// Print the report as JSON instead of the summary.
    #[arg(long)]
    pub json: bool,
    /// Launch protocol: throw (a hand throw onto a table, calibrated on measured dice), drop
    /// (released from rest 1 R_max above the ground) or quasi-static (the overdamped limit of the
    /// basins). Every parameter below overrides the preset's value.
    #[arg(long, default_value = "throw", value_parser = parse_preset)]
    pub preset: Preset,
    /// Surface pair setting friction, restitution and rolling resistance: steel-on-wood (the
    /// default: the table the throw is calibrated on, steel dice on wood), stone-on-stone,
    /// rock-on-concrete, rock-on-steel.
    #[arg(long, default_value = "steel-on-wood", value_parser = parse_surface)]
    pub surface: Surface,
    #[command(flatten)]
    pub size: super::SizeArgs,
    /// Release height of the lowest point above the ground, in units of R_max (default: the
    /// preset's: 2 for throw, 1 for drop).
    #[arg(long, value_name = "R_MAX")]
    pub height: Option<f64>,
    /// Horizontal release speed in m/s for the stone's real size (default: the preset's,
    /// 1.28 √(g R_max) for throw: 1.69 m/s for the bundled stone, 0.4 m/s for R_max = 1 cm).
    #[arg(long, value_name = "M_S")]
    pub horizontal_speed: Option<f64>,
    /// Release angular speed in rad/s for the stone's real size, the rms of the presets'
    /// Gaussian law (default: the preset's, 7.98 √(g/R_max) for throw: 59 rad/s for the bundled
    /// stone, 250 rad/s for R_max = 1 cm).
    #[arg(long, value_name = "RAD_S")]
    pub spin: Option<f64>,
    #[command(flatten)]
    pub contact: super::ContactArgs,
    /// Torsional-friction length δ_t in mm: the torque about the normal on a single contact
    /// point is at most δ_t times the normal force (default: the rolling-resistance length).
    #[arg(long, value_name = "MM")]
    pub torsional_friction_mm: Option<f64>,
    /// Replaced by --torsional-friction-mm (δ_t in mm instead of δ_t/R_max).
    #[arg(long, hide = true, allow_hyphen_values = true)]
    pub torsional_friction: Option<String>,
    /// Global linear velocity damping in 1/s (default 0: it would slow a stone in flight; only
    /// the quasi-static preset damps, 3.19 √(g/R_max)).
    #[arg(long, value_name = "PER_S")]
    pub linear_damping: Option<f64>,
    /// Global angular velocity damping in 1/s (default 0, as --linear-damping).
    #[arg(long, value_name = "PER_S")]
    pub angular_damping: Option<f64>,
    /// Time step in seconds of real time, a number or a fraction such as 1/2000 (default: the
    /// preset's longest stable step, 0.0261 √(R_max/g): 3.5 ms for the bundled stone, 0.83 ms for
    /// R_max = 1 cm; --reference halves it).
    #[arg(long, value_name = "S", value_parser = parse_step)]
    pub dt: Option<f64>,
    /// Time cap per drop in seconds of real time (default: the preset's, 188 √(R_max/g): 25 s
    /// for the bundled stone, 6 s for R_max = 1 cm).
    #[arg(long, value_name = "S")]
    pub max_time: Option<f64>,
    /// Rapier's solver sub-steps per time step (default 4). Impacts are completed by the contact
    /// law whatever this is, so the per-flock statistics at 4 are those at 32 on the bundled
    /// stone, a pebble and a box (paired test, results/drops_vs_mujoco/); more cost in
    /// proportion.
    #[arg(long, value_parser = super::at_least::<usize, 1>)]
    pub solver_iterations: Option<usize>,
    /// How the flight between contacts is integrated: free (the default: outside the physics
    /// engine, exactly as a free rigid body, handed to it at the exact instant of touch-down,
    /// and hard impacts sub-stepped so that a corner goes about 0.01 R_max into the ground at
    /// most, measured after every sub-step and warned about beyond 0.02 R_max) or rapier
    /// (every step in the physics engine, contacts found at the step boundaries: the former
    /// numerics, kept to compare).
    #[arg(long, value_parser = parse_flight)]
    pub flight: Option<Flight>,
    /// Strict impacts: read the impact sub-step bound again after every sub-step, so that an
    /// impact that turns the stone faster within a step (a spin about the vertical turned into a
    /// tumble) cannot carry a corner deeper than 0.02 R_max. Off by default: the calibration and
    /// the published results were computed without it, and it moves about one ordinary throw in a
    /// thousand; use it for launches far beyond the presets, or when a run warns of its depth.
    #[arg(long)]
    pub strict_impacts: bool,
    /// The reference numerics: free flight at dt 1/240 s, the step the default 1/120 s (the
    /// preset's longest stable step, measured) is checked against — on the same releases, drop
    /// by drop, the paired test does not tell their per-flock statistics apart on the bundled
    /// stone, a pebble and a box (results/drops_vs_mujoco/), and every throw of the 40 shared
    /// meshes settles at both (results/drops_settling/). 1.5–2.0× the cost (results/drops_dt/). --dt and --flight
    /// still override it.
    #[arg(long, conflicts_with = "fast")]
    pub reference: bool,
    /// The preset's longest stable step with free flight: the default since it was shown equal
    /// to the reference numerics; kept so that older command lines run.
    #[arg(long, hide = true)]
    pub fast: bool,
    /// End drops early by the energy certificate: once the final facet is certain (facet), once
    /// the final flock is (flock), or never (none).
    #[arg(long, default_value = "facet", value_parser = parse_certificate)]
    pub certificate: CertificateMode,
    /// ν at which flocks are read (default: the automatic plateau, else 0.0035).
    #[arg(long, value_parser = super::parse_nu)]
    pub nu: Option<f64>,
    /// A known centre of mass x,y,z (mesh units) instead of the homogeneous solid's G: a
    /// weighted die, a hollow print, a scan of only the hull (inertia taken about it).
    #[arg(long, value_parser = super::parse_point, allow_hyphen_values = true)]
    pub center_of_mass: Option<rocking_stones::Point3>,
    /// Stones simulated together in one physics world (they touch only the ground; every drop's
    /// outcome is the same for any value); 1: each drop alone in its own world.
    #[arg(long, default_value_t = rocking_stones::dynamics::drops::montecarlo::DEFAULT_BATCH, value_parser = parse_batch)]
    pub batch: usize,
    /// Run only shard i of n, given as i/n (drops i, i+n, i+2n, …); combine with `rocking
    /// merge` (default: the whole run).
    #[arg(long, value_name = "I/N", allow_hyphen_values = true)]
    pub shard: Option<String>,
    /// Append every finished drop to this file (JSON lines) as the run goes.
    #[arg(long)]
    pub checkpoint: Option<PathBuf>,
    /// Continue the run recorded in --checkpoint, skipping the drops it already holds.
    #[arg(long, requires = "checkpoint")]
    pub resume: bool,
    /// Write into this folder: drops.json, drops_flocks.png/.svg and drops_facets.png/.svg (bar
    /// plots per flock and per stable facet, against the static probabilities) and report.html.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

pub fn parse_preset(s: &str) -> std::result::Result<Preset, String> {
    s.parse().map_err(|e: rocking_stones::Error| e.spelled(&super::flag))
}

pub fn parse_surface(s: &str) -> std::result::Result<Surface, String> {
    s.parse().map_err(|e: rocking_stones::Error| e.spelled(&super::flag))
}

/// A time step given as a number (`0.004`) or a fraction (`1/240`).
pub fn parse_step(s: &str) -> std::result::Result<f64, String> {
    let value = match s.split_once('/') {
        Some((n, d)) => n.trim().parse::<f64>().ok().zip(d.trim().parse::<f64>().ok()).map(|(n, d)| n / d),
        None => s.trim().parse::<f64>().ok(),
    };
    match value {
        Some(v) if v > 0.0 && v.is_finite() => Ok(v),
        _ => Err(format!("--dt must be a positive time step in seconds, as 0.004 or 1/240, got {s:?}")),
    }
}

pub fn parse_batch(s: &str) -> std::result::Result<usize, String> {
    match s.parse::<usize>() {
        Ok(n) if (1..=100_000).contains(&n) => Ok(n),
        _ => Err(format!("--batch must be a whole number of stones from 1 to 100000, got {s:?}")),
    }
}

pub fn parse_flight(s: &str) -> std::result::Result<Flight, String> {
    s.parse().map_err(|e: rocking_stones::Error| e.spelled(&super::flag))
}

pub fn parse_certificate(s: &str) -> std::result::Result<CertificateMode, String> {
    s.parse().map_err(|e: rocking_stones::Error| e.spelled(&super::flag))
}

#[derive(clap::Args)]
pub struct MergeArgs {
    /// Partial results (checkpoint files of `rocking drop --shard ... --checkpoint ...`).
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// The mesh, if it is not at the path recorded in the results.
    #[arg(long)]
    pub mesh: Option<PathBuf>,
    /// ν at which flocks are read (as in `rocking drop`; default: the automatic plateau, else
    /// 0.0035).
    #[arg(long, value_parser = super::parse_nu)]
    pub nu: Option<f64>,
    /// Print the merged report as JSON instead of the summary.
    #[arg(long)]
    pub json: bool,
    /// Write the merged run's files into this folder, as `rocking drop` writes them: drops.json,
    /// drops_flocks.png/.svg, drops_facets.png/.svg and report.html.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

/// The parameters of the run for a stone of real size `size`: the preset's, with every option
/// given in real units turned into the scaled frame.
fn params(a: &Args, size: &RealSize) -> Result<DropParams> {
    let mut p = a.preset.params_for(a.surface, Some(size.r_max_m))?;
    if a.reference {
        a.preset.reference(&mut p);
    }
    if let Some(v) = &a.torsional_friction {
        bail!("--torsional-friction (δ_t/R_max) is now --torsional-friction-mm, the length δ_t in mm (got {v})");
    }
    let set = |field: &mut f64, v: Option<f64>| {
        if let Some(v) = v {
            *field = v;
        }
    };
    let real = |name: &str, v: Option<f64>| super::scaled(size, name, v);
    set(&mut p.launch.height, a.height);
    set(&mut p.launch.horizontal_speed, real("horizontal_speed", a.horizontal_speed));
    set(&mut p.launch.spin, real("spin", a.spin));
    a.contact.apply(&mut p.sim.contact, size)?;
    set(&mut p.sim.contact.torsional_friction, super::scaled_mm(size, a.torsional_friction_mm));
    set(&mut p.sim.contact.linear_damping, real("linear_damping", a.linear_damping));
    set(&mut p.sim.contact.angular_damping, real("angular_damping", a.angular_damping));
    set(&mut p.sim.numerics.dt, real("dt", a.dt));
    set(&mut p.sim.numerics.max_time, real("max_time", a.max_time));
    p.sim.numerics.solver_iterations = a.solver_iterations.unwrap_or(p.sim.numerics.solver_iterations);
    if let Some(flight) = a.flight {
        p.sim.flight.mode = flight;
    }
    p.sim.flight.strict_impacts = a.strict_impacts;
    p.check().map_err(|e| super::in_real_units(e, size))?;
    Ok(p)
}

pub fn run_drop(args: Args) -> Result<()> {
    if args.drops == 0 {
        bail!("-n/--drops must be at least 1");
    }
    let opts =
        Options { nu: args.nu.map(check_nu).transpose()?, center_of_mass: args.center_of_mass, ..Options::default() };
    let (analysis, name) = load_analysis(args.mesh.as_deref(), &opts)?;
    let (nu, _) = analysis.macro_nu(&opts);
    let stone = Stone::new(&analysis, nu)?;
    let size = args.size.real_size(&name, stone.body.r_max)?;
    let p = params(&args, &size)?;
    let shard = args.shard.as_deref().map(Shard::parse).transpose()?.unwrap_or(Shard::ALL);
    let header = RunHeader {
        center_of_mass: args.center_of_mass.map(|c| [c.x, c.y, c.z]),
        r_max_m: Some(size.r_max_m),
        shard,
        ..RunHeader::new(name, &analysis.mesh, args.seed, args.drops, p, args.certificate, (args.preset, args.surface))
    };
    let run = match &args.checkpoint {
        Some(path) => DropRun::checkpointed(&stone, &header, path, args.resume)?,
        None => DropRun::new(&stone, &header),
    };
    let bar = super::progress_bar(run.pending(), "drops");
    let all = run.run(args.batch, &|| bar.inc(1)).map_err(|e| match e {
        e @ rocking_stones::Error::Io { .. } => {
            anyhow::Error::new(e).context("writing the checkpoint failed; finished drops up to the failure are in it")
        }
        e => e.into(),
    })?;
    bar.finish_and_clear();
    let model = stone.model();
    let report = summarize(&model, &header, &all);
    emit(&report, Some(&size), args.json, args.output.as_deref(), &analysis, nu)
}

pub fn run_merge(args: MergeArgs) -> Result<()> {
    let parts = args.parts.iter().map(|p| read_partial(p)).collect::<rocking_stones::Result<Vec<_>>>()?;
    let (header, outcomes) = merge(&parts)?;
    let missing_shards: Vec<String> = {
        let count = parts[0].0.shard.count;
        (0..count)
            .filter(|i| !parts.iter().any(|(h, _)| h.shard.index == *i && h.shard.count == count))
            .map(|i| format!("{i}/{count}"))
            .collect()
    };
    let opts = Options {
        nu: args.nu.map(check_nu).transpose()?,
        center_of_mass: header.center_of_mass.map(|[x, y, z]| rocking_stones::Point3::new(x, y, z)),
        ..Options::default()
    };
    let mesh = match &args.mesh {
        Some(m) => Some(m.clone()),
        None if super::analyze::is_bundled(&header.mesh) => None,
        None => Some(PathBuf::from(&header.mesh)),
    };
    let (analysis, _) = load_analysis(mesh.as_deref(), &opts)?;
    let fp = rocking_stones::dynamics::drops::montecarlo::fingerprint(&analysis.mesh);
    if fp != header.mesh_fingerprint {
        anyhow::bail!(
            "the mesh does not match the one the drops were run on (fingerprint {fp} vs {})",
            header.mesh_fingerprint
        );
    }
    let (nu, _) = analysis.macro_nu(&opts);
    let stone = Stone::new(&analysis, nu)?;
    let model = stone.model();
    for (path, (_, part)) in args.parts.iter().zip(&parts) {
        check_outcomes(path, part, &model)?;
    }
    let missing = header.drops - outcomes.len() as u64;
    if missing > 0 {
        let shards = if missing_shards.is_empty() {
            String::new()
        } else {
            format!(" (shards {} absent)", missing_shards.join(", "))
        };
        eprintln!("note: {missing} of {} drops are not in these partial results{shards}", header.drops);
    }
    // The size the shards were run at, recorded in their header (none in files of earlier
    // versions: the summary then gives scaled values only).
    let size = header.r_max_m.map(|r| RealSize::resolve(&header.mesh, stone.body.r_max, Some(Size::RMax(r))));
    let size = size.transpose()?;
    emit(&summarize(&model, &header, &outcomes), size.as_ref(), args.json, args.output.as_deref(), &analysis, nu)
}

/// The JSON of a drop run: the report, and the stone's real size with whether it was assumed
/// (none for merged shards, whose size is in their parameters' rolling resistance).
#[derive(serde::Serialize)]
struct Sized<'a> {
    #[serde(flatten)]
    report: &'a DropReport,
    #[serde(skip_serializing_if = "Option::is_none")]
    r_max_m: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    size_assumed: Option<bool>,
}

fn emit(
    report: &DropReport,
    size: Option<&RealSize>,
    json: bool,
    output: Option<&std::path::Path>,
    analysis: &rocking_stones::analysis::Analysis,
    nu: f64,
) -> Result<()> {
    use rocking_stones::report;
    let sized = Sized { report, r_max_m: size.map(|s| s.r_max_m), size_assumed: size.map(RealSize::assumed) };
    let summary = report::drop_summary_sized(report, sized.r_max_m);
    let page = super::Page::with_hull("drop", analysis, &report.mesh, nu);
    super::emit(&sized, json, &summary, output, Some(page), |dir| report::write_drop_outputs(report, dir))
}
