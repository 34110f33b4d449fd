//! `rocking perturb`: push or spin a stone resting on its stable micro-equilibria; robustness
//! curves, thresholds against the static barriers, rocking vs regular.

use super::analyze::load_analysis;
use anyhow::{bail, Result};
use rocking_stones::analysis::{check_nu, Analysis, Options};
use rocking_stones::dynamics::certificate::CertificateMode;
use rocking_stones::dynamics::pushes::{self, Family, PerturbConfig};
use rocking_stones::dynamics::resting::{RestingParams, RestingPreset};
use rocking_stones::dynamics::size::RealSize;
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::report;
use rocking_stones::stats::{log_grid, GridSize};
use std::path::{Path, PathBuf};

/// Simulation parameters shared by `rocking perturb` and `rocking shake`: the contact of every
/// run that starts at rest (the surface pair at the stone's real size) and its overrides, in real
/// units for the stone's size.
#[derive(clap::Args, Clone)]
pub struct SimArgs {
    /// Contact model: `surface` (the surface pair of --surface at the stone's real size, with
    /// rolling resistance through the contact: the physics of drops and field rocks) or `damped`
    /// (the overdamped reference of the former results: friction 0.6, restitution 0.2, global
    /// angular damping 0.319 √(g/R_max); ignores --surface and the size).
    #[arg(long, default_value = "surface", value_parser = parse_contact_model)]
    pub contact_model: RestingPreset,
    /// Replaced by --contact-model (`--preset` is `rocking drop`'s launch protocol).
    #[arg(long, hide = true)]
    pub preset: Option<String>,
    /// Surface pair: stone-on-stone, rock-on-concrete, rock-on-steel, steel-on-wood. Default:
    /// stone-on-stone (a stone resting on rock); with `shake --pose`, rock-on-concrete (a field
    /// rock on a shake table's concrete). The summary says which was used.
    #[arg(long, value_parser = parse_surface)]
    pub surface: Option<Surface>,
    #[command(flatten)]
    pub size: super::SizeArgs,
    #[command(flatten)]
    pub contact: super::ContactArgs,
    /// Time step in seconds of real time (default 0.0131 √(R_max/g): 1.76 ms for the bundled
    /// stone, 4.2 ms for R_max = 1 m).
    #[arg(long, value_name = "S")]
    pub dt: Option<f64>,
    /// Time cap per trial after the perturbation or the motion, in seconds of real time (default
    /// 62.6 √(R_max/g): 8.4 s for the bundled stone, 20 s for R_max = 1 m).
    #[arg(long, value_name = "S")]
    pub max_time: Option<f64>,
    /// Rapier's solver sub-steps per time step (default 4; more cost in proportion, as for
    /// `rocking drop`).
    #[arg(long, value_parser = super::at_least::<usize, 1>)]
    pub solver_iterations: Option<usize>,
    /// Natural frequency of the soft contact constraints in Hz for the stone's real size
    /// (default 38.3 cycles per √(R_max/g): 284 Hz for the bundled stone, 120 Hz for R_max = 1 m).
    #[arg(long, value_name = "HZ")]
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
    /// refused ([`super::SizeArgs::real_size`]). Call it once per run.
    pub fn real_size(&self, stone: &Stone, name: &str) -> Result<RealSize> {
        self.size.real_size(name, stone.body.r_max)
    }

    /// The parameters of the run for a stone of real size `size`, the surface defaulting to
    /// `default_surface`, with every override given (in real units) turned into the scaled frame.
    pub fn params(&self, size: &RealSize, default_surface: Surface) -> Result<RestingParams> {
        if self.preset.is_some() {
            bail!("--preset is `rocking drop`'s launch protocol; the contact of perturb and shake is --contact-model surface|damped");
        }
        let surface = self.surface.unwrap_or(default_surface);
        let mut p = RestingParams::of(self.contact_model, surface, size.r_max_m)?;
        let real = |name: &str, v: Option<f64>| super::scaled(size, name, v);
        let sim = &mut p.sim;
        self.contact.apply(&mut sim.contact, size)?;
        sim.numerics.dt = real("dt", self.dt).unwrap_or(sim.numerics.dt);
        sim.numerics.max_time = real("max_time", self.max_time).unwrap_or(sim.numerics.max_time);
        sim.numerics.solver_iterations = self.solver_iterations.unwrap_or(sim.numerics.solver_iterations);
        p.contact_frequency = real("contact_frequency", self.contact_frequency).unwrap_or(p.contact_frequency);
        p.check().map_err(|e| super::in_real_units(e, size))?;
        Ok(p)
    }

    /// The static analysis' options: ν and a known centre of mass as given.
    pub fn options(&self) -> Options {
        Options { nu: self.nu, center_of_mass: self.center_of_mass, ..Options::default() }
    }

    /// Load and analyse the mesh (or the bundled stone) and prepare it.
    pub fn stone(&self, mesh: Option<&Path>) -> Result<(Analysis, Stone, String)> {
        let opts = Options { nu: self.nu.map(check_nu).transpose()?, ..self.options() };
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
    /// End trials early by the energy certificate: once the final facet is certain or the stone
    /// has certainly left its flock (facet; also the bare `--certificate`), only once it has
    /// certainly left its flock (flock), or never (none, the default: the static-barrier check
    /// proves nothing with a certificate).
    #[arg(long, value_name = "MODE", default_value = "none", num_args = 0..=1, default_missing_value = "facet", value_parser = super::drop::parse_certificate)]
    pub certificate: CertificateMode,
    /// Print the report as JSON instead of the summary.
    #[arg(long)]
    pub json: bool,
    /// Write into this folder: perturb.json, curves.csv, thresholds.csv, trials.csv,
    /// robustness.png/.svg and thresholds.png/.svg (when a trial ran) and report.html.
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

fn parse_contact_model(s: &str) -> std::result::Result<RestingPreset, String> {
    s.parse().map_err(|e: rocking_stones::Error| e.spelled(&super::flag))
}

fn parse_surface(s: &str) -> std::result::Result<Surface, String> {
    s.parse().map_err(|e: rocking_stones::Error| e.spelled(&super::flag))
}
