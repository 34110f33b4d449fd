//! `rocking shake`: drive the ground under a resting stone horizontally (sine pulses or a ground
//! motion from a CSV); fragility curves P(topple out of the flock) against peak ground
//! acceleration. With `--pose`: a field rock at its true size under recorded 3-component motion
//! (one record → one result; a folder of records × scale factors → runs.csv and the fragility
//! surface).

use super::perturb::SimArgs;
use anyhow::{bail, Result};
use rocking_stones::dynamics::shaking::journal::{Journal, JournalHeader};
use rocking_stones::dynamics::shaking::{self, RockSetup, ShakeConfig};
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::ground_motion::read::{self, AccelUnit, Columns};
use rocking_stones::ground_motion::Record;
use rocking_stones::report;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

#[derive(clap::Args)]
pub struct Args {
    /// Mesh file (STL, OBJ, PLY). None: the bundled default stone.
    pub mesh: Option<PathBuf>,
    /// Shake the stone resting on these stable micro-equilibria (repeatable). Default: the
    /// deepest regular one and the rocking one with the highest basin barrier.
    #[arg(long = "equilibrium", value_name = "ID", conflicts_with = "pose", value_parser = super::at_least::<usize, 0>)]
    pub equilibria: Vec<usize>,
    /// Sine pulse: amplitude (g), frequency (Hz, real: for the stone at its real size), cycles.
    #[arg(long, value_name = "AMP,FREQ,CYCLES", value_parser = parse_pulse, allow_hyphen_values = true, conflicts_with_all = ["motion", "pose"])]
    pub pulse: Option<[f64; 3]>,
    /// Ground motion: a CSV (columns --columns, unit --accel-unit; real time) or one to three
    /// PEER .AT2 files (x, y, z components; repeat the option).
    #[arg(long, value_name = "FILE", num_args = 1..=3)]
    pub motion: Vec<PathBuf>,
    /// Field rock: how it stands — as-scanned (mesh frame = world frame, +z up; put down and
    /// settled), equilibrium:ID (a stable micro-equilibrium, as `analyze` numbers them),
    /// facet:F (the stable micro-equilibrium on hull facet F, the number `analyze` prints beside
    /// it) or quat:w,x,y,z (the mesh rotated, then put down and settled).
    #[arg(long, value_parser = parse_pose)]
    pub pose: Option<shaking::Pose>,
    /// CSV records: columns `time,ax[,ay[,az]]` by header name or number from 1.
    #[arg(long, default_value = "1,2")]
    pub columns: String,
    /// CSV records: acceleration unit (g, m/s2, gal).
    #[arg(long, default_value = "g")]
    pub accel_unit: String,
    /// The --motion record's known peak ground velocity (m/s), e.g. measured: reported (and
    /// used for PGV/PGA) instead of the PGV of the processed record (mean removed, acausal
    /// Butterworth high-pass of order 5 at 0.08 Hz, integrated).
    #[arg(long, value_name = "M_S", requires = "motion", conflicts_with = "records")]
    pub pgv: Option<f64>,
    /// --records: a CSV of known PGVs, columns `record` (or `motion`, `file`: the record's file
    /// name) and `pgv_m_s`; the records it names report that PGV, the others the processed one.
    #[arg(long, value_name = "FILE", requires = "records")]
    pub pgv_table: Option<PathBuf>,
    /// Polynomial baseline correction of the records (order 0–3) before use.
    #[arg(long, value_name = "ORDER", value_parser = super::at_least::<usize, 0>)]
    pub baseline: Option<usize>,
    /// Field rock: a folder of records (*.csv read with --columns/--accel-unit; each *.AT2 file
    /// is one record along x), each run at every --scales factor, in parallel.
    #[arg(long, value_name = "DIR", conflicts_with = "motion", requires = "pose")]
    pub records: Option<PathBuf>,
    /// Field rock: scale factors (≥ 0) applied to every record, comma-separated (default 1).
    #[arg(long, value_delimiter = ',', default_value = "1", requires = "pose", allow_hyphen_values = true)]
    pub scales: Vec<f64>,
    /// Field rock batch: continue the batch journalled in -o DIR (DIR/runs.jsonl): the runs it
    /// holds are kept, only the others run (records and scale factors may be added).
    #[arg(long, requires_all = ["output", "pose"])]
    pub resume: bool,
    /// Sweep the peak ground acceleration from PGA_MAX/STEPS to PGA_MAX (g), scaling the motion
    /// to each: fragility curves. Without a motion the default is a sweep up to 1 g of 2 sine
    /// cycles at 0.639 cycles per √(R_max/g) (4.7 Hz for the bundled stone, 2 Hz for
    /// R_max = 1 m); with --pulse or --motion and no --pga-max, the motion is run at its own
    /// amplitude only.
    #[arg(long, conflicts_with = "pose")]
    pub pga_max: Option<f64>,
    /// Number of PGAs of the sweep.
    #[arg(long, default_value_t = 20, conflicts_with = "pose", value_parser = super::at_least::<usize, 1>)]
    pub pga_steps: usize,
    /// Azimuth of the motion's x axis, degrees counter-clockwise from the x axis of the stone
    /// as it stands: the mesh's own x axis as scanned, or, standing on an equilibrium, the mesh
    /// turned by the smallest rotation that brings that facet down. One frame for every mode:
    /// without --pose it replaces the random azimuth of each trial; with --pose it is the
    /// records' azimuth (default 0).
    #[arg(long, allow_hyphen_values = true)]
    pub azimuth: Option<f64>,
    /// Trials per equilibrium and PGA.
    #[arg(short = 'n', long, default_value_t = 40, conflicts_with = "pose", value_parser = super::at_least::<u32, 1>)]
    pub trials: u32,
    /// Seed of the random azimuths; with --pose --ensemble, of the members' draws.
    #[arg(long, default_value_t = 1, value_parser = super::at_least::<u64, 0>)]
    pub seed: u64,
    /// Field rock: an ensemble of N members over what is not known: every member
    /// draws the uncertain inputs below uniformly from their ranges; the result is P(overturn)
    /// with its 95 % interval and the inputs it is most sensitive to. Friction, restitution and
    /// rolling resistance range over the surface pair's published ranges unless pinned (--friction,
    /// --restitution, --rolling-resistance-mm) or given (--friction-range, …).
    #[arg(long, value_name = "N", requires = "pose", value_parser = super::at_least::<u64, 1>)]
    pub ensemble: Option<u64>,
    /// Ensemble: base-contact tolerance in mm, T (uniform in [0, T]) or LOW,HIGH: hull corners
    /// within it of the base plane carry load (the collider's base is flattened onto that plane;
    /// mass and pose unchanged).
    #[arg(long, value_name = "T|LOW,HIGH", requires = "ensemble", allow_hyphen_values = true)]
    pub contact_tolerance_mm: Option<String>,
    /// Replaced by --contact-tolerance-mm (in mm instead of the mesh's unit).
    #[arg(long, hide = true, allow_hyphen_values = true)]
    pub contact_tolerance: Option<String>,
    /// Ensemble: azimuth of the records' x axis, degrees: LOW,HIGH, or `unknown` (0–360).
    #[arg(
        long,
        value_name = "LOW,HIGH|unknown",
        requires = "ensemble",
        conflicts_with = "azimuth",
        allow_hyphen_values = true
    )]
    pub azimuth_range: Option<String>,
    /// Ensemble: how the hidden base meets the ground — drawn (the default: every member draws the
    /// region that carries the weight, the three points it stands on, and for a field scan the
    /// depth below its rim; a closed scan's lowest millimetres are read as hidden, see
    /// --base-band-mm) or scanned (every member stands on the scan's own base, a field scan's
    /// flat cap).
    #[arg(long, value_name = "drawn|scanned", default_value = "drawn", requires = "ensemble", value_parser = ["drawn", "scanned"])]
    pub base: String,
    /// Ensemble, field scan: depth range of the base's support below the rim's lowest point, in
    /// mm, LOW,HIGH or one depth, as measured in the field. Default (calibrated): from 0 to 0.6 ×
    /// the depth at which the scan's walls, continued down, would close — at least a tenth of
    /// the rim's footprint radius, at most all of it.
    #[arg(long, value_name = "LOW,HIGH", requires = "ensemble", allow_hyphen_values = true)]
    pub base_depth_mm: Option<String>,
    /// Ensemble, field scan standing as scanned: the rocking points measured in the field, the
    /// three points it stands on, X1,Y1,X2,Y2,X3,Y3 in mm in the scan's frame (every member
    /// stands on them and draws only the base's depth and slope).
    #[arg(long, value_name = "X1,Y1,X2,Y2,X3,Y3", requires = "ensemble", allow_hyphen_values = true)]
    pub rocking_points_mm: Option<String>,
    /// Ensemble, closed scan: height above its lowest point, in mm, up to which the scan's base is
    /// read as hidden (default 2 mm, calibrated; at most 1 % of R_max).
    #[arg(long, value_name = "MM", requires = "ensemble")]
    pub base_band_mm: Option<f64>,
    /// Ensemble: radius of the region that carries the weight, as a multiple of the base
    /// footprint's radius √(area/π) (at most a quarter of G's height above the support),
    /// LOW,HIGH (default 0.1–1, calibrated).
    #[arg(long, value_name = "LOW,HIGH", requires = "ensemble", allow_hyphen_values = true)]
    pub base_region: Option<String>,
    /// Ensemble: the record's sign is unknown (each member flips it with probability ½).
    #[arg(long, requires = "ensemble")]
    pub random_sign: bool,
    /// Ensemble: friction coefficient range LOW,HIGH.
    #[arg(long, value_name = "LOW,HIGH", requires = "ensemble", allow_hyphen_values = true)]
    pub friction_range: Option<String>,
    /// Ensemble: restitution range LOW,HIGH.
    #[arg(long, value_name = "LOW,HIGH", requires = "ensemble", allow_hyphen_values = true)]
    pub restitution_range: Option<String>,
    /// Ensemble: rolling-resistance length range LOW,HIGH in mm.
    #[arg(
        long,
        alias = "rolling-resistance-range",
        value_name = "LOW,HIGH",
        requires = "ensemble",
        allow_hyphen_values = true
    )]
    pub rolling_resistance_range_mm: Option<String>,
    #[command(flatten)]
    pub sim: SimArgs,
    /// Print the report as JSON instead of the summary.
    #[arg(long)]
    pub json: bool,
    /// Write the run's files into this folder. A sweep (no --pose): shake.json, fragility.csv,
    /// trials.csv, fragility.png/.svg, report.html. One record (--pose): runs.csv. An ensemble
    /// (--pose --ensemble): ensemble.json, members.csv, tipping_polar.png, report.html. A batch
    /// (--records, or several --scales): shake_batch.json, runs.jsonl (the journal --resume
    /// reads), runs.csv, fragility_surface.png, tipping_polar.png, report.html, and with
    /// --ensemble probabilities.csv and contours.csv.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

fn parse_pulse(s: &str) -> Result<[f64; 3], String> {
    let v: Vec<f64> =
        s.split(',').map(|x| x.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|e| format!("{e}"))?;
    match v.as_slice() {
        [a, f, c] => Ok([*a, *f, *c]),
        _ => Err(format!("expected AMP,FREQ,CYCLES, got {s:?}")),
    }
}

fn parse_pose(s: &str) -> Result<shaking::Pose, String> {
    s.parse().map_err(|e: rocking_stones::Error| e.spelled(&super::flag))
}

pub fn run_shake(args: Args) -> Result<()> {
    if let Some(pose) = args.pose {
        return field(args, pose);
    }
    // clap does not enforce `requires = "pose"` here (pose conflicts with options that have
    // defaults), so the field-rock options are checked by hand: never silently ignored.
    for (given, flag) in
        [(args.ensemble.is_some(), "--ensemble"), (args.records.is_some(), "--records"), (args.resume, "--resume")]
    {
        if given {
            bail!(
                "{flag} is for a field rock: give --pose (as-scanned for a rock standing as it was scanned) and a \
                 record (--motion FILE or --records DIR)"
            );
        }
    }
    let (analysis, stone, name) = args.sim.stone(args.mesh.as_deref())?;
    let size = args.sim.real_size(&stone, &name)?;
    let params = args.sim.params(&size, Surface::StoneOnStone)?;
    let r_max_m = size.r_max_m;
    let real_dt = params.sim.numerics.dt * r_max_m.sqrt();
    let (motion, default_sweep) = match (&args.pulse, args.motion.is_empty()) {
        (Some([a, f, c]), _) => (shaking::sine_pulse(*a, *f, *c, real_dt)?, false),
        (None, false) => (read_records(&args)?.remove(0), false),
        (None, true) => (shaking::default_pulse(r_max_m, params.sim.numerics.dt)?, true),
    };
    let pgas = shaking::pgas_for(&motion, args.pga_max, args.pga_steps, default_sweep)?;
    let starts = match args.equilibria.is_empty() {
        true => shaking::default_starts(&stone, &params)?,
        false => stone.select(&args.equilibria, None)?,
    };
    let cfg = ShakeConfig {
        params,
        motion,
        pgas,
        trials: args.trials,
        seed: args.seed,
        azimuth: args.azimuth.map(f64::to_radians),
        r_max_m,
    };
    cfg.check()?;
    let bar = super::progress_bar(starts.len() as u64 * cfg.pgas.len() as u64 * cfg.trials as u64, "trials");
    let report = shaking::sweep_fragility_monitored(&stone, &starts, &cfg, &|| bar.inc(1))?;
    let report = shaking::ShakeReport { size_assumed: Some(size.assumed()), ..report };
    bar.finish_and_clear();
    let page = super::Page::with_hull("shake", &analysis, &name, stone.nu);
    let summary = report::shake::summary(&report, &name);
    let write = |dir: &Path| report::shake::write_outputs(&report, &name, dir);
    super::emit(&report, args.json, &summary, args.output.as_deref(), Some(page), write)
}

/// The records of the command line (one --motion, or the --records folder), each baseline
/// corrected if asked, with their known PGVs if given.
fn read_records(args: &Args) -> Result<Vec<Record>> {
    let records = read_baselined(args)?;
    if let Some(pgv) = args.pgv {
        let given = |r: Record| r.with_known_pgv(pgv).map_err(|e| anyhow::anyhow!(e.spelled(&super::flag)));
        return records.into_iter().map(given).collect();
    }
    match &args.pgv_table {
        Some(path) => {
            let table = read::read_known_pgv(path)?;
            let (records, named) = read::with_known_pgvs(records, &table, &path.display().to_string())
                .map_err(|e| anyhow::anyhow!(e.spelled(&super::flag)))?;
            eprintln!("{}: known PGV of {named} of {} records", path.display(), records.len());
            Ok(records)
        }
        None => Ok(records),
    }
}

/// The records of the command line, each baseline corrected if asked.
fn read_baselined(args: &Args) -> Result<Vec<Record>> {
    let columns: Columns = args.columns.parse()?;
    let accel_unit: AccelUnit = args.accel_unit.parse()?;
    let records = match (&args.records, args.motion.is_empty()) {
        (Some(dir), _) => read_folder(dir, &columns, accel_unit)?,
        (None, false) => vec![read_motion(&args.motion, &columns, accel_unit)?],
        (None, true) => bail!("with --pose, give a record (--motion FILE, or up to three .AT2 files) or --records DIR"),
    };
    match args.baseline {
        Some(order) => {
            Ok(records.iter().map(|r| r.baseline_corrected(order)).collect::<rocking_stones::Result<_>>()?)
        }
        None => Ok(records),
    }
}

/// Read one record: a CSV, or one to three .AT2 files.
fn read_motion(paths: &[PathBuf], columns: &Columns, unit: AccelUnit) -> Result<Record> {
    let refs: Vec<&std::path::Path> = paths.iter().map(|p| p.as_path()).collect();
    Ok(read::read_record(&refs, columns, unit)?)
}

/// `rocking shake --pose ...`: a field rock at true size under recorded motion.
fn field(args: Args, pose: shaking::Pose) -> Result<()> {
    let records = read_records(&args)?;
    if args.scales.is_empty() || args.scales.iter().any(|k| !(*k >= 0.0 && k.is_finite())) {
        bail!("--scales must be numbers ≥ 0, e.g. 0.5,1,2");
    }
    let (analysis, stone, name) = args.sim.stone(args.mesh.as_deref())?;
    let pose = pose.resolved(&stone)?;
    let azimuth = args.azimuth.unwrap_or(0.0).to_radians();
    let size = args.sim.real_size(&stone, &name)?;
    let params = args.sim.params(&size, Surface::RockOnConcrete)?;
    let setup = RockSetup {
        r_max_m: size.r_max_m,
        size_assumed: Some(size.assumed()),
        ..RockSetup::with_params(&stone, pose, size.length_unit_m, azimuth, params)
    };
    let ensemble = ensemble_spec(&args)?;
    let rocks = match &ensemble {
        Some(e) => shaking::field_members(&analysis, &args.sim.options(), &stone, &setup, e).map_err(|e| {
            anyhow::anyhow!(e.spelled(&|n: &str| base_flag(n).map_or_else(|| super::flag(n), String::from)))
        })?,
        None => Vec::new(),
    };
    let rock = shaking::FieldRock { stone: &stone, members: &rocks };
    if let (Some(e), [record], [scale]) = (&ensemble, &records[..], &args.scales[..]) {
        let bar = super::progress_bar(e.members, "members");
        let run = shaking::run_ensemble(rock, &setup, record, *scale, e, &|| bar.inc(1))?;
        bar.finish_and_clear();
        let page = super::Page::titled("shake --ensemble", &name);
        let summary = report::shake::ensemble_summary(&run, &name);
        let write = |dir: &Path| report::shake::write_ensemble_outputs(&run, &name, dir);
        return super::emit(&run, args.json, &summary, args.output.as_deref(), Some(page), write);
    }
    if records.len() == 1 && args.scales.len() == 1 {
        let run = shaking::run_record(&stone, &setup, &records[0], args.scales[0])?;
        let summary = report::shake::rock_run_summary(&run, &name);
        let write = |dir: &Path| report::shake::write_run_outputs(&run, dir);
        return super::emit(&run, args.json, &summary, args.output.as_deref(), None, write);
    }
    // Many runs: every finished run is appended to DIR/runs.jsonl (the journal `--resume` reads)
    // and DIR/runs.csv as it comes (never lose finished work); runs.csv is rewritten in the
    // batch's order at the end.
    let mesh_id = match &args.mesh {
        Some(p) => format!("{} fnv1a {:016x}", p.display(), rocking_stones::rng::fnv1a(std::fs::read(p)?)),
        None => "bundled stone".to_string(),
    };
    let header = JournalHeader::new(mesh_id, &setup, ensemble.as_ref());
    let (previous, sink) = match &args.output {
        Some(dir) => {
            std::fs::create_dir_all(dir)?;
            let (journal, previous) = Journal::open(&dir.join("runs.jsonl"), &header, args.resume)?;
            let mut w = csv::Writer::from_path(dir.join("runs.csv"))?;
            w.write_record(report::shake::RUN_CSV_HEADER)?;
            for r in &previous {
                w.write_record(report::shake::run_csv_row(r))?;
            }
            w.flush()?;
            (previous, Some(Mutex::new((journal, w))))
        }
        None => (Vec::new(), None),
    };
    if !previous.is_empty() {
        eprintln!("resuming: {} finished run(s) in the journal are kept", previous.len());
    }
    let members = ensemble.as_ref().map_or(1, |e| e.members);
    let bar = super::progress_bar((records.len() * args.scales.len()) as u64 * members, "runs");
    let failed = std::sync::atomic::AtomicBool::new(false);
    let batch = shaking::run_batch(rock, &setup, &records, &args.scales, ensemble.as_ref(), &previous, &|r| {
        if let Some(w) = &sink {
            let mut w = w.lock().unwrap_or_else(|e| e.into_inner());
            let (j, c) = &mut *w;
            let ok = j.record(r).is_ok()
                && c.write_record(report::shake::run_csv_row(r)).and_then(|_| Ok(c.flush()?)).is_ok();
            if !ok {
                failed.store(true, std::sync::atomic::Ordering::Relaxed);
            }
        }
        bar.inc(1);
    })?;
    if failed.into_inner() {
        bail!(
            "writing runs.jsonl / runs.csv failed during the batch; the runs finished before the failure are in them"
        );
    }
    bar.finish_and_clear();
    drop(sink);
    let page = super::Page::titled("shake --pose", &name);
    let summary = report::shake::batch_summary(&batch, &name);
    let write = |dir: &Path| report::shake::write_batch_outputs(&batch, &name, dir);
    super::emit(&batch, args.json, &summary, args.output.as_deref(), Some(page), write)
}

/// `--rocking-points-mm`: six numbers X1,Y1,X2,Y2,X3,Y3 (mm) as three points (m).
fn parse_points(s: &str) -> Result<[[f64; 2]; 3]> {
    let v: Vec<f64> =
        s.split(',').map(|x| x.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| {
            anyhow::anyhow!("--rocking-points-mm: expected six numbers X1,Y1,X2,Y2,X3,Y3 (mm), got {s:?}")
        })?;
    match v[..] {
        [x1, y1, x2, y2, x3, y3] => Ok([[x1, y1], [x2, y2], [x3, y3]].map(|p| p.map(|x| x * 1e-3))),
        _ => bail!("--rocking-points-mm: expected six numbers X1,Y1,X2,Y2,X3,Y3 (mm), got {} number(s)", v.len()),
    }
}

/// A `LOW,HIGH` range (or one number T: [0, T] when `from_zero`, else [T, T]) of option `flag`.
fn parse_range(flag: &str, s: &str, from_zero: bool) -> Result<[f64; 2]> {
    let v: Vec<f64> = s.split(',').map(|x| x.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| {
        anyhow::anyhow!("--{flag}: expected LOW,HIGH (two numbers){}, got {s:?}", if from_zero { " or T" } else { "" })
    })?;
    match v[..] {
        [t] if from_zero => Ok([0.0, t]),
        [t] => Ok([t, t]),
        [lo, hi] => Ok([lo, hi]),
        _ => bail!("--{flag}: expected LOW,HIGH, got {s:?}"),
    }
}

/// The ensemble of the command line: the surface pair's contact ranges unless pinned or given,
/// the base-contact tolerance and δ from mm to metres, the azimuth range or `unknown`.
fn ensemble_spec(args: &Args) -> Result<Option<shaking::EnsembleSpec>> {
    let Some(members) = args.ensemble else { return Ok(None) };
    if let Some(t) = &args.contact_tolerance {
        bail!("--contact-tolerance (in the mesh's unit) is now --contact-tolerance-mm, in mm (got {t})");
    }
    let range = |flag: &str, s: &Option<String>| s.as_deref().map(|s| parse_range(flag, s, false)).transpose();
    let given = shaking::Uncertainty {
        contact_tolerance_m: args
            .contact_tolerance_mm
            .as_deref()
            .map(|s| parse_range("contact-tolerance-mm", s, true))
            .transpose()?,
        azimuth_deg: match args.azimuth_range.as_deref() {
            Some("unknown") => Some([0.0, 360.0]),
            s => s
                .map(|s| parse_range("azimuth-range", s, false).map_err(|e| anyhow::anyhow!("{e}, or unknown")))
                .transpose()?,
        },
        random_sign: args.random_sign,
        friction: range("friction-range", &args.friction_range)?,
        restitution: range("restitution-range", &args.restitution_range)?,
        rolling_resistance_m: range("rolling-resistance-range-mm", &args.rolling_resistance_range_mm)?,
        base: match args.base.as_str() {
            "scanned" => None,
            _ => {
                let calibrated = shaking::BaseUncertainty::calibrated();
                let mm = |r: [f64; 2]| r.map(|x| x * 1e-3);
                Some(shaking::BaseUncertainty {
                    rocking_points_m: args.rocking_points_mm.as_deref().map(parse_points).transpose()?,
                    depth_m: range("base-depth-mm", &args.base_depth_mm)?.map(mm),
                    band_m: args.base_band_mm.map_or(calibrated.band_m, |b| b * 1e-3),
                    region: range("base-region", &args.base_region)?.unwrap_or(calibrated.region),
                    ..calibrated
                })
            }
        },
    };
    // Check the ranges as given (mm), named by their flags.
    let flag = |n: &str| match n {
        "contact_tolerance" => "--contact-tolerance-mm".to_string(),
        "rolling_resistance" => "--rolling-resistance-range-mm".to_string(),
        other => base_flag(other).map_or_else(|| format!("--{}-range", other.replace('_', "-")), String::from),
    };
    given.check().map_err(|e| anyhow::anyhow!(e.spelled(&flag)))?;
    let surface = args.sim.surface.unwrap_or(Surface::RockOnConcrete);
    let pinned = args.sim.contact.pinned();
    let uncertainty = shaking::Uncertainty::stated(&given, surface, pinned);
    let spec = shaking::EnsembleSpec { uncertainty, seed: args.seed, members };
    spec.check().map_err(|e| anyhow::anyhow!(e.spelled(&super::flag)))?;
    Ok(Some(spec))
}

/// The flag of a hidden-base parameter of the library, None for any other parameter.
fn base_flag(name: &str) -> Option<&'static str> {
    match name {
        "base_depth" => Some("--base-depth-mm"),
        "base_band" => Some("--base-band-mm"),
        "base_region" => Some("--base-region"),
        "rocking_points" => Some("--rocking-points-mm"),
        _ => None,
    }
}

/// Every record of a folder, by file name: `*.csv` and `*.AT2` (one record along x per file).
fn read_folder(dir: &std::path::Path, columns: &Columns, unit: AccelUnit) -> Result<Vec<Record>> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| anyhow::anyhow!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv") || e.eq_ignore_ascii_case("at2")))
        .collect();
    paths.sort();
    if paths.is_empty() {
        bail!("{}: no *.csv or *.AT2 record in this folder", dir.display());
    }
    paths.iter().map(|p| read_motion(std::slice::from_ref(p), columns, unit)).collect()
}
