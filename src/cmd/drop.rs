//! `rocking drop` and `rocking merge`: Monte Carlo drops of a scan in rapier3d.

use super::analyze::load_analysis;
use anyhow::{Context, Result};
use rocking_stones::analysis::{check_nu, Options};
use rocking_stones::dynamics::drop::{DropOutcome, DropParams};
use rocking_stones::montecarlo::{
    merge, read_partial, run, summarize, CertificateMode, Checkpoint, DropReport, DropSetup, RunHeader, Shard, FORMAT,
};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Mutex;

#[derive(clap::Args)]
pub struct Args {
    /// Mesh file (STL, OBJ, PLY). None: the bundled default stone.
    pub mesh: Option<PathBuf>,
    /// Number of drops in the whole run.
    #[arg(short = 'n', long, default_value_t = 1000)]
    pub drops: u64,
    /// Seed: drop i uses its own stream derived from (seed, i).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// Drop height of the lowest point, in units of R_max.
    #[arg(long, default_value_t = DropParams::default().height)]
    pub height: f64,
    /// Initial angular speed (rad/s of the body scaled to R_max = 1 m).
    #[arg(long, default_value_t = DropParams::default().spin)]
    pub spin: f64,
    #[arg(long, default_value_t = DropParams::default().friction)]
    pub friction: f64,
    #[arg(long, default_value_t = DropParams::default().restitution)]
    pub restitution: f64,
    /// Linear velocity damping (1/s).
    #[arg(long, default_value_t = DropParams::default().linear_damping)]
    pub linear_damping: f64,
    /// Angular velocity damping (1/s): stands in for rolling resistance.
    #[arg(long, default_value_t = DropParams::default().angular_damping)]
    pub angular_damping: f64,
    /// Time step (s).
    #[arg(long, default_value_t = DropParams::default().dt)]
    pub dt: f64,
    /// Time cap per drop (s).
    #[arg(long, default_value_t = DropParams::default().max_time)]
    pub max_time: f64,
    /// End drops early once the energy certificate decides the facet (or the flock).
    #[arg(long, value_enum, default_value_t = CertificateMode::Facet)]
    pub certificate: CertificateMode,
    /// ν at which flocks are read (default: the automatic plateau, else 0.0035).
    #[arg(long)]
    pub nu: Option<f64>,
    /// Run only shard i of n (drops i, i+n, i+2n, …); combine with `rocking merge`.
    #[arg(long)]
    pub shard: Option<String>,
    /// Append every finished drop to this file (JSON lines) as the run goes.
    #[arg(long)]
    pub checkpoint: Option<PathBuf>,
    /// Continue the run recorded in --checkpoint, skipping the drops it already holds.
    #[arg(long, requires = "checkpoint")]
    pub resume: bool,
    /// Write report.json and the bar plots (per flock, per facet) into this folder.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

#[derive(clap::Args)]
pub struct MergeArgs {
    /// Partial results (checkpoint files of `rocking drop --shard ... --checkpoint ...`).
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// The mesh, if it is not at the path recorded in the results.
    #[arg(long)]
    pub mesh: Option<PathBuf>,
    /// ν at which flocks are read (as in `rocking drop`).
    #[arg(long)]
    pub nu: Option<f64>,
    #[arg(long)]
    pub json: bool,
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

fn params(a: &Args) -> Result<DropParams> {
    let p = DropParams {
        height: a.height,
        spin: a.spin,
        friction: a.friction,
        restitution: a.restitution,
        linear_damping: a.linear_damping,
        angular_damping: a.angular_damping,
        dt: a.dt,
        max_time: a.max_time,
        ..DropParams::default()
    };
    p.check().map_err(anyhow::Error::msg)?;
    Ok(p)
}

pub fn run_drop(args: Args) -> Result<()> {
    let p = params(&args)?;
    let opts = Options { nu: args.nu.map(check_nu).transpose()?, ..Options::default() };
    let (analysis, name) = load_analysis(args.mesh.as_deref(), &opts)?;
    let (nu, _) = analysis.macro_nu(&opts);
    let setup = DropSetup::new(&analysis, nu)?;
    let shard = args.shard.as_deref().map(Shard::parse).transpose()?.unwrap_or(Shard::ALL);
    let header = RunHeader {
        format: FORMAT.into(),
        mesh: name,
        mesh_fingerprint: rocking_stones::montecarlo::fingerprint(&analysis.mesh),
        seed: args.seed,
        drops: args.drops,
        params: p,
        certificate: args.certificate,
    };
    let (mut checkpoint, done) = match &args.checkpoint {
        Some(path) => {
            let (c, d) = Checkpoint::open(path, &header, args.resume)?;
            (Some(c), d)
        }
        None => (None, BTreeMap::new()),
    };
    let todo = shard.indices(header.drops).filter(|i| !done.contains_key(i)).count() as u64;
    let bar = super::progress_bar(todo, "drops");
    let mut write_error: Option<std::io::Error> = None;
    let new = {
        let sink = Mutex::new(|o: &DropOutcome| {
            if let Some(c) = checkpoint.as_mut() {
                if let Err(e) = c.record(o) {
                    write_error.get_or_insert(e);
                }
            }
            bar.inc(1);
        });
        let cert = setup.certificate(args.certificate);
        run(&setup.body, &header, shard, &done, cert.as_ref(), &sink)
    };
    bar.finish_and_clear();
    if let Some(e) = write_error {
        return Err(e).context("writing the checkpoint failed; finished drops up to the failure are in it");
    }
    let mut all = done;
    all.extend(new.into_iter().map(|o| (o.index, o)));
    let report = summarize(&setup.model, &header, &all);
    emit(&report, args.json, args.output.as_deref())
}

pub fn run_merge(args: MergeArgs) -> Result<()> {
    let parts = args.parts.iter().map(|p| read_partial(p)).collect::<rocking_stones::Result<Vec<_>>>()?;
    let (header, outcomes) = merge(&parts)?;
    let opts = Options { nu: args.nu.map(check_nu).transpose()?, ..Options::default() };
    let mesh = match &args.mesh {
        Some(m) => Some(m.clone()),
        None if super::analyze::is_bundled(&header.mesh) => None,
        None => Some(PathBuf::from(&header.mesh)),
    };
    let (analysis, _) = load_analysis(mesh.as_deref(), &opts)?;
    let fp = rocking_stones::montecarlo::fingerprint(&analysis.mesh);
    if fp != header.mesh_fingerprint {
        anyhow::bail!(
            "the mesh does not match the one the drops were run on (fingerprint {fp} vs {})",
            header.mesh_fingerprint
        );
    }
    let (nu, _) = analysis.macro_nu(&opts);
    let setup = DropSetup::new(&analysis, nu)?;
    let missing = header.drops - outcomes.len() as u64;
    if missing > 0 {
        eprintln!("note: {missing} of {} drops are not in these partial results", header.drops);
    }
    emit(&summarize(&setup.model, &header, &outcomes), args.json, args.output.as_deref())
}

fn emit(report: &DropReport, json: bool, output: Option<&std::path::Path>) -> Result<()> {
    super::emit(
        report,
        json,
        || rocking_stones::report::drop_summary(report),
        output,
        |dir| Ok(rocking_stones::report::write_drop_outputs(report, dir)?),
    )
}
