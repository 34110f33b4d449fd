//! `rocking perturb`: push or spin a stone resting on its stable micro-equilibria; robustness
//! curves, thresholds against the static barriers, rocking vs regular.

use super::analyze::load_analysis;
use anyhow::{bail, Result};
use rocking_stones::analysis::{check_nu, Analysis, Options};
use rocking_stones::dynamics::pushes::{self, Family, PerturbConfig};
use rocking_stones::dynamics::resting::{RestingParams, RestingPreset};
use rocking_stones::dynamics::size::{RealSize, ASSUMED_UNIT};
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::report;
use rocking_stones::stats::{log_grid, GridSize};
use std::path::{Path, PathBuf};

/// Simulation parameters shared by `rocking perturb` and `rocking shake`: the contact of every
/// run that starts at rest (the surface pair at the stone's real size) and its overrides.
#[derive(clap::Args, Clone)]
pub struct SimArgs {
    /// Contact: `surface` (the surface pair of --surface at the stone's real size, with rolling
    /// resistance through the contact: the physics of drops and field rocks) or `damped` (the
    /// overdamped reference of the former results: friction 0.6, restitution 0.2, global
    /// angular damping 1 s⁻¹; ignores --surface and the size).
    #[arg(long, default_value = "surface", value_parser = parse_resting_preset)]
    pub preset: RestingPreset,
    /// Surface pair: stone-on-stone, rock-on-concrete, rock-on-steel, steel-on-wood. Default:
    /// stone-on-stone (a stone on rock); with `shake --pose`, rock-on-concrete (a shake table).
    #[arg(long, value_parser = parse_surface)]
    pub surface: Option<Surface>,
    /// The mesh's length unit (mm, cm, m, km or metres per unit): the stone's real size, on which
    /// the result depends (the rolling resistance δ/R_max; with shaking, the real frequencies of
    /// the motion). Default: mm for the bundled stone (a 30 cm quarry stone, R_max = 178 mm);
    /// for any other mesh m is assumed, and the command says so before running. A size outside
    /// R_max 2 mm to 20 m is warned about.
    #[arg(long, value_name = "UNIT", conflicts_with = "size")]
    pub length_unit: Option<String>,
    /// The stone's real size as R_max in metres (the largest distance from G to the hull),
    /// instead of --length-unit; default as --length-unit's.
    #[arg(long, value_name = "R_MAX_M")]
    pub size: Option<f64>,
    #[command(flatten)]
    pub contact: super::ContactArgs,
    /// Time step T in s at R_max = 1 m: 3.13 T √(R_max/g), T·√(R_max / 1 m) s for the real
    /// stone (default 1/240).
    #[arg(long)]
    pub dt: Option<f64>,
    /// Time cap per trial after the perturbation / the motion, T in s at R_max = 1 m:
    /// 3.13 T √(R_max/g), T·√(R_max / 1 m) s for the real stone (default 20).
    #[arg(long)]
    pub max_time: Option<f64>,
    /// Rapier's solver sub-steps per time step (default 4; more cost in proportion, as for
    /// `rocking drop`).
    #[arg(long, value_parser = super::at_least::<usize, 1>)]
    pub solver_iterations: Option<usize>,
    /// Natural frequency F of the soft contact constraints in Hz at R_max = 1 m:
    /// F/3.13 cycles per √(R_max/g), F/√(R_max / 1 m) Hz for the real stone (default 120).
    #[arg(long)]
    pub contact_frequency: Option<f64>,
    /// ν at which flocks are read (default: the automatic plateau, else 0.0035).
    #[arg(long, value_parser = super::parse_nu)]
    pub nu: Option<f64>,
    /// A known centre of mass x,y,z (mesh units) instead of the homogeneous solid's G: a
    /// weighted die, a hollow print, a scan of only the hull (inertia taken about it).
    #[arg(long, value_parser = super::parse_point, allow_hyphen_values = true)]
    pub center_of_mass: Option<rocking_stones::Point3>,
}

impl SimArgs {
    /// The stone's real size: --size, --length-unit, else the bundled stone's millimetres, else
    /// metres, said on standard error when assumed or implausible ([`super::real_size`]). Call it
    /// once per run.
    pub fn real_size(&self, stone: &Stone, name: &str) -> Result<RealSize> {
        super::real_size(name, stone.body.r_max, self.length_unit.as_deref(), self.size, ASSUMED_UNIT)
    }

    /// The parameters of the run for a stone of real size `size`, the surface defaulting to
    /// `default_surface`, with every override given.
    pub fn params(&self, size: &RealSize, default_surface: Surface) -> Result<RestingParams> {
        let surface = self.surface.unwrap_or(default_surface);
        let mut p = RestingParams::of(self.preset, surface, size.r_max_m)?;
        let sim = &mut p.sim;
        self.contact.apply(&mut sim.contact);
        sim.numerics.dt = self.dt.unwrap_or(sim.numerics.dt);
        sim.numerics.max_time = self.max_time.unwrap_or(sim.numerics.max_time);
        sim.numerics.solver_iterations = self.solver_iterations.unwrap_or(sim.numerics.solver_iterations);
        p.contact_frequency = self.contact_frequency.unwrap_or(p.contact_frequency);
        p.check()?;
        Ok(p)
    }

    /// Load and analyse the mesh (or the bundled stone) and prepare it.
    pub fn stone(&self, mesh: Option<&Path>) -> Result<(Analysis, Stone, String)> {
        let opts = Options {
            nu: self.nu.map(check_nu).transpose()?,
            center_of_mass: self.center_of_mass,
            ..Options::default()
        };
        let (analysis, name) = load_analysis(mesh, &opts)?;
        let (nu, _) = analysis.macro_nu(&opts);
        let stone = Stone::new(&analysis, nu)?;
        Ok((analysis, stone, name))
    }
}

#[derive(clap::Args)]
pub struct Args {
    /// Mesh file (STL, OBJ, PLY). None: the bundled default stone.
    pub mesh: Option<PathBuf>,
    /// Perturb only these stable micro-equilibria (index as in `rocking analyze --json`;
    /// repeatable). Default: every stable micro-equilibrium.
    #[arg(long = "equilibrium", value_name = "ID", conflicts_with = "flock", value_parser = super::at_least::<usize, 0>)]
    pub equilibria: Vec<usize>,
    /// Perturb the stable micro-equilibria of this flock.
    #[arg(long, value_name = "ID", value_parser = super::at_least::<usize, 0>)]
    pub flock: Option<usize>,
    /// push: impulse at a random surface point in a random inward direction; spin: angular
    /// velocity about a random axis through the contact point.
    #[arg(long, default_value = "push", value_parser = parse_family)]
    pub family: Family,
    /// Trials per equilibrium and ε.
    #[arg(short = 'n', long, default_value_t = 40, value_parser = super::at_least::<u32, 1>)]
    pub trials: u32,
    /// Seed: trial k of equilibrium i uses its own stream (the same at every ε).
    #[arg(long, default_value_t = 1, value_parser = super::at_least::<u64, 0>)]
    pub seed: u64,
    /// Smallest ε = kinetic energy / (m g R_max) of the log grid (dimensionless).
    #[arg(long, default_value_t = 1e-5)]
    pub eps_min: f64,
    /// Largest ε of the grid (dimensionless).
    #[arg(long, default_value_t = 1.0)]
    pub eps_max: f64,
    /// Number of ε values (log-spaced).
    #[arg(long, default_value_t = 16, value_parser = super::at_least::<usize, 1>)]
    pub eps_steps: usize,
    /// ε* of the dynamic rocking/regular classification, dimensionless as ε (default: the
    /// macro-scale ν).
    #[arg(long)]
    pub epsilon_star: Option<f64>,
    /// End trials as soon as the energy certificate decides their outcome (faster; the
    /// static-barrier check then proves nothing).
    #[arg(long)]
    pub certificate: bool,
    /// Print the report as JSON instead of the summary.
    #[arg(long)]
    pub json: bool,
    /// Write perturb.json, CSVs (curves, thresholds, trials), plots and report.html into this folder.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub sim: SimArgs,
}

pub fn run_perturb(args: Args) -> Result<()> {
    if !(args.eps_min > 0.0 && args.eps_max >= args.eps_min && args.eps_steps > 0) {
        bail!("need 0 < --eps-min ≤ --eps-max and --eps-steps ≥ 1");
    }
    if let Some(e) = args.epsilon_star.filter(|e| !(*e > 0.0 && e.is_finite())) {
        bail!("--epsilon-star must be a positive energy ε (kinetic energy / (m g R_max)), got {e}");
    }
    let (analysis, stone, name) = args.sim.stone(args.mesh.as_deref())?;
    let size = args.sim.real_size(&stone, &name)?;
    let params = args.sim.params(&size, Surface::StoneOnStone)?;
    let cfg = PerturbConfig {
        params: RestingParams { certificate: args.certificate, ..params },
        family: args.family,
        epsilons: log_grid(args.eps_min, args.eps_max, GridSize::Points(args.eps_steps)),
        trials: args.trials,
        seed: args.seed,
        epsilon_star: args.epsilon_star,
    };
    cfg.check()?;
    let starts = stone.select(&args.equilibria, args.flock)?;
    let bar = super::progress_bar(pushes::task_count(starts.len(), &cfg), "trials");
    let report = pushes::perturb_equilibria_monitored(&stone, &starts, &cfg, &|| bar.inc(1))?;
    bar.finish_and_clear();
    let report = pushes::PerturbReport { r_max_m: Some(size.r_max_m), size_assumed: Some(size.assumed()), ..report };
    let page = super::Page::with_hull("perturb", &analysis, &name, stone.nu);
    let summary = report::perturb::summary(&report, &name);
    let write = |dir: &Path| report::perturb::write_outputs(&report, &name, dir);
    super::emit(&report, args.json, &summary, args.output.as_deref(), Some(page), write)
}

fn parse_family(s: &str) -> std::result::Result<Family, String> {
    s.parse().map_err(|e: rocking_stones::Error| e.spelled(&super::flag))
}

fn parse_resting_preset(s: &str) -> std::result::Result<RestingPreset, String> {
    s.parse().map_err(|e: rocking_stones::Error| e.spelled(&super::flag))
}

fn parse_surface(s: &str) -> std::result::Result<Surface, String> {
    s.parse().map_err(|e: rocking_stones::Error| e.spelled(&super::flag))
}
