//! Drops per second per core of this project against MuJoCo under the same physics, and the
//! agreement of their outcome statistics, in one run on one core.
//!
//! Both engines drop the three benchmark bodies (`shared/benchmark_bodies.rs`) from rest, lowest
//! point 0.5 R_max above a plane, Haar-uniform orientation, μ 0.6, e 0.2, global damping 0.1 s⁻¹
//! (linear) and 1 s⁻¹ (angular), the same rest rule and 60 s cap, in the scaled frame (R_max =
//! 1 m, mass 1, g = 9.81) with the same hull corners and inertia tensor. The project runs plain,
//! batched and flock-certified + batched at the reference step `REFERENCE_DT` = 1/240 s, and
//! flock-certified + batched with its default numerics (`Preset::largest_stable_dt`, 1/120 s).
//! MuJoCo runs from Python (`shared/mujoco_drops.py`, which documents its settings) at both steps,
//! 1/240 s (the benchmark protocol) and 1/120 s (the project's default step): one model,
//! its contact's damping ratio calibrated on a ball at 1/240 s, only the step changed (an untimed
//! check runs it at 1/120 s with the ratio calibrated again there); it returns each drop's final
//! body-frame down direction, classified here by the project's own rule (`Stone::rest`), so both
//! are counted per flock identically. Both engines drop the same releases (the project's
//! orientation of each drop index, passed to MuJoCo), so the outcomes are compared drop by drop:
//! how many drops end in the same flock, and the Stuart–Maxwell test of marginal homogeneity of
//! the per-flock counts (`stats::stuart_maxwell`, which uses the pairing), on the timed drops and
//! on larger untimed samples: the project at each step against MuJoCo at each step, and MuJoCo
//! at 1/120 s against itself at 1/240 s (is MuJoCo accurate at the longer step?). Two engines
//! that each drew their own orientations would also differ by the sampling of the orientations:
//! numpy's stream that this experiment used before put 0.300 of the box's releases in the
//! quasi-static basins of its 1 × 0.5 sides, whose area is 0.272 (3.4 standard deviations), and
//! that alone made the engines' box statistics look different.
//!
//! Run: `cargo run --release --example drops_vs_mujoco [-- N]` (N = 300 drops per body and mode;
//! `--seed` the releases' seed, default 7) → `results/drops_vs_mujoco/`; the README's prose is
//! `experiments/readme/drops_vs_mujoco.md`. Needs MuJoCo's Python bindings (`pip install mujoco`)
//! in `python3` or in the interpreter named by `ROCKING_PYTHON`.

#![recursion_limit = "256"] // the README's context is one large `json!`

#[path = "shared/benchmark_bodies.rs"]
mod benchmark_bodies;
#[path = "shared/cpu_time.rs"]
mod cpu_time;
#[path = "shared/harness.rs"]
mod harness;
use benchmark_bodies::benchmark_bodies;
use cpu_time::thread_cpu_seconds;
use harness::{fixed, Common, Context, Parser, Result, Results};
use nalgebra::UnitQuaternion;
use rocking_stones::analysis::Options;
use rocking_stones::dynamics::certificate::{certificate, CertificateMode};
use rocking_stones::dynamics::drops::launch::{launch, DropOutcome};
use rocking_stones::dynamics::drops::montecarlo::{
    run_drops_batched, summarize, DropReport, RunHeader, Shard, DEFAULT_BATCH, FORMAT,
};
use rocking_stones::dynamics::drops::params::{DropParams, Preset};
use rocking_stones::dynamics::engine::params::REFERENCE_DT;
use rocking_stones::dynamics::engine::simulation::Simulation;
use rocking_stones::dynamics::stone::{Stone, REST_TOLERANCE};
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::plot::{series_color, Axis, Chart, Mark, RGBColor};
use rocking_stones::rng::item_rng;
use rocking_stones::stats::stuart_maxwell;
use rocking_stones::Vec3;
use serde::Deserialize;
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::Mutex;

/// The physics both engines run (scaled frame).
const HEIGHT: f64 = 0.5;
const FRICTION: f64 = 0.6;
const RESTITUTION: f64 = 0.2;
const LINEAR_DAMPING: f64 = 0.1;
const ANGULAR_DAMPING: f64 = 1.0;
/// The untimed samples for the statistics have this many times N drops per engine (their first N
/// are the timed drops).
const SAMPLE_FACTOR: u64 = 10;
/// Rounds of timing (each: MuJoCo's drops at both steps, then every mode of the project); the
/// fastest round counts.
const REPEATS: usize = 3;
/// Rapier solver iterations (its sub-steps per step) of the untimed convergence check; the
/// project's default is 4 (`DropParams::solver_iterations`), the last is the reference.
const SUBSTEPS: [usize; 5] = [2, 4, 8, 16, 32];
/// MuJoCo's default contact time constant (s), the first number of solref (`mujoco_drops.py`).
const MJ_TIMECONST: f64 = 0.02;

type Outcomes = BTreeMap<u64, DropOutcome>;
const BLACK: RGBColor = RGBColor(0, 0, 0);

/// The project's default drop step, `Preset::largest_stable_dt` (1/120 s).
fn fast_dt() -> f64 {
    Preset::Drop.largest_stable_dt()
}

/// The steps MuJoCo runs at: the reference step (the benchmark protocol) and the project's default step.
fn mj_dts() -> [f64; 2] {
    [REFERENCE_DT, fast_dt()]
}

/// "1/240 s" for dt = 1/240 s.
fn step_label(dt: f64) -> String {
    format!("1/{:.0} s", 1.0 / dt)
}

/// A mode of the project: stones per world, certificate, and the step it runs ([`REFERENCE_DT`]
/// for the reference modes, the preset's default step for the default numerics).
#[derive(Clone)]
struct Mode {
    name: String,
    short: String,
    batch: usize,
    cert: CertificateMode,
    dt: f64,
}

/// The project's modes: three at the reference step (MuJoCo's step of the benchmark protocol) and
/// the default numerics (flock-certified + batched at [`Preset::largest_stable_dt`]).
fn modes() -> [Mode; 4] {
    let mode = |name: String, short: String, batch, cert, dt| Mode { name, short, batch, cert, dt };
    let (b, f, d) = (DEFAULT_BATCH, CertificateMode::Flock, step_label(fast_dt()));
    [
        mode("plain".into(), "plain".into(), 1, CertificateMode::None, REFERENCE_DT),
        mode("batched".into(), "batched".into(), b, CertificateMode::None, REFERENCE_DT),
        mode("flock-certified + batched".into(), "flock-cert. + batched".into(), b, f, REFERENCE_DT),
        mode(
            format!("flock-certified + batched, default numerics (dt {d})"),
            format!("flock-cert. + batched, default numerics (dt {d})"),
            b,
            f,
            fast_dt(),
        ),
    ]
}

/// The project's parameters at step `dt`: the `drop` preset on steel on wood (its numerics:
/// exact landings and sub-stepped impacts, which damp the free flight exactly), with the matched
/// physics overriding it, no rolling resistance or torsional friction (MuJoCo's condim 3 has
/// neither).
fn params(dt: f64) -> DropParams {
    let mut p = Preset::Drop.params(Surface::SteelOnWood);
    p.launch.height = HEIGHT;
    let c = &mut p.sim.contact;
    (c.friction, c.restitution, c.linear_damping, c.angular_damping) =
        (FRICTION, RESTITUTION, LINEAR_DAMPING, ANGULAR_DAMPING);
    (c.rolling_resistance, c.torsional_friction) = (0.0, 0.0);
    p.sim.numerics.dt = dt;
    p
}

fn header(name: &str, n: u64, m: &Mode, seed: u64) -> RunHeader {
    RunHeader {
        format: FORMAT.into(),
        mesh: name.into(),
        mesh_fingerprint: String::new(),
        seed,
        drops: n,
        params: params(m.dt),
        certificate: m.cert,
        preset: Some(Preset::Drop.name().into()),
        center_of_mass: None,
        shard: Shard::ALL,
    }
}

/// A run of the project: its summary, outcomes by drop index, CPU seconds.
struct Run {
    report: DropReport,
    outcomes: Outcomes,
    seconds: f64,
}

/// Median and largest `height_above` (h(final down) − R_F, R_max) of the settled outcomes: how
/// far off its stable facet's normal a drop ended (0 when flat on it); `{:.1e}` each.
fn rise(outcomes: &Outcomes) -> [String; 2] {
    let mut h: Vec<f64> = outcomes.values().filter(|o| o.settled).filter_map(|o| o.height_above).collect();
    h.sort_by(f64::total_cmp);
    let at = |i: Option<usize>| i.and_then(|i| h.get(i)).map_or(f64::NAN, |x| *x);
    [at(Some(h.len() / 2)), at(h.len().checked_sub(1))].map(|x| format!("{x:.1e}"))
}

/// Every drop of `h` with `batch` stones per world on the one-thread `pool`, timed by the worker
/// thread's CPU time.
fn timed(pool: &rayon::ThreadPool, stone: &Stone, h: &RunHeader, batch: usize) -> Run {
    pool.install(|| {
        let sink = Mutex::new(|_: &DropOutcome| {});
        let cert = certificate(stone, h.certificate);
        let t = thread_cpu_seconds();
        let out = run_drops_batched(stone, h, Shard::ALL, &BTreeMap::new(), cert.as_ref(), batch, &sink);
        let seconds = thread_cpu_seconds() - t;
        let outcomes: Outcomes = out.into_iter().map(|o| (o.index, o)).collect();
        Run { report: summarize(&stone.model(), h, &outcomes), outcomes, seconds }
    })
}

/// What `shared/mujoco_drops.py` writes.
#[derive(Deserialize)]
struct MjOut {
    mujoco_version: String,
    numpy_version: String,
    python_version: String,
    integrator: String,
    default_integrator: String,
    cone: String,
    solver: String,
    iterations: u32,
    tolerance: f64,
    solref: [f64; 2],
    solimp: Vec<f64>,
    ball_restitution: f64,
    ball_restitution_speeds: f64,
    bodies: Vec<MjBody>,
}

#[derive(Deserialize)]
struct MjBody {
    placement_error: f64,
    mesh_vertices: usize,
    flat_restitution: Option<[f64; 2]>,
    drops: Vec<MjDrop>,
    sample_drops: Vec<MjDrop>,
    loop_cpu_s: Vec<f64>,
    replay_cpu_s: Vec<f64>,
    replay_identical: bool,
    /// Every release's initial down direction in the project's body frame, as MuJoCo placed it.
    release_downs: Vec<[f64; 3]>,
}

#[derive(Deserialize)]
struct MjDrop {
    down: [f64; 3],
    steps: u64,
    settled: bool,
    /// Warnings MuJoCo raised during the drop (bad qpos/qvel/qacc: an instability, after which it
    /// resets the state).
    #[serde(default)]
    warnings: u64,
}

/// MuJoCo's drops at step `dt` classified by the project's rule ([`Stone::rest`] of the final
/// down direction), as outcomes of a plain run, and their summary. A drop that ended with a
/// non-finite down direction or after a MuJoCo warning counts as not settled.
fn classify(stone: &Stone, name: &str, drops: &[MjDrop], dt: f64, seed: u64) -> (DropReport, Outcomes) {
    let mut outcomes = Outcomes::new();
    for (i, d) in drops.iter().enumerate() {
        let down = Vec3::from(d.down);
        let sane = down.iter().all(|x| x.is_finite()) && down.norm() > 0.5 && d.warnings == 0;
        let rest = sane.then(|| stone.rest(&down));
        let o = DropOutcome {
            index: i as u64,
            settled: d.settled && sane,
            facet: rest.as_ref().map(|r| r.facet),
            flock: None,
            time: d.steps as f64 * dt,
            certified: false,
            height_above: rest.as_ref().map(|r| r.height_above),
            deepest_penetration: 0.0,
        };
        outcomes.insert(i as u64, o);
    }
    let mode = Mode { dt, ..modes()[0].clone() };
    (summarize(&stone.model(), &header(name, drops.len() as u64, &mode, seed), &outcomes), outcomes)
}

/// The Python interpreter (`ROCKING_PYTHON`, default `python3`), if it can import mujoco.
fn python_with_mujoco() -> Result<String> {
    let python = std::env::var("ROCKING_PYTHON").unwrap_or_else(|_| "python3".into());
    let mut check = Command::new(&python);
    let ok = check.args(["-c", "import mujoco, numpy"]).stdout(Stdio::null()).stderr(Stdio::null()).status();
    anyhow::ensure!(
        ok.is_ok_and(|s| s.success()),
        "drops_vs_mujoco needs MuJoCo's Python bindings, but `{python} -c 'import mujoco, numpy'` failed.\n\
         Install them with `{python} -m pip install mujoco` (it brings numpy), or point ROCKING_PYTHON at an \
         interpreter that has them, e.g.\n  python3 -m venv target/mujoco-venv && target/mujoco-venv/bin/pip \
         install mujoco\n  ROCKING_PYTHON=target/mujoco-venv/bin/python cargo run --release --example \
         drops_vs_mujoco"
    );
    Ok(python)
}

/// Restitution of a flat landing in rapier (the project's world and contact, no damping) at step
/// `dt`: the body dropped from rest with its facet of outward normal `normal` (body frame) facing
/// down, `HEIGHT` above the ground; e = √(rebound height / drop height) of G above its height at
/// rest on the facet, as the Python side measures MuJoCo's. The rebound is found by the velocity
/// (from the step where G first moves up to the step where it moves down again), not by the
/// contact impulse, which a sub-stepped impact (`dynamics::engine::impact`) leaves at zero after the step.
fn rapier_flat_restitution(stone: &Stone, normal: &Vec3, dt: f64) -> f64 {
    let mut p = params(dt);
    (p.sim.contact.linear_damping, p.sim.contact.angular_damping) = (0.0, 0.0);
    let q = UnitQuaternion::rotation_between(normal, &-Vec3::z()).unwrap_or_else(UnitQuaternion::identity);
    let h = stone.body.support(normal);
    let mut sim = Simulation::new(&stone.body, &p.sim, &q, HEIGHT + h, &Vec3::zeros(), &Vec3::zeros());
    let (mut rising, mut apex) = (false, f64::NEG_INFINITY);
    for _ in 0..(10.0 / p.sim.numerics.dt) as usize {
        sim.step();
        let s = sim.state();
        rising |= s.linvel.z > 0.0;
        if rising {
            if s.linvel.z <= 0.0 {
                return ((apex - h).max(0.0) / HEIGHT).sqrt();
            }
            apex = apex.max(s.z);
        }
    }
    0.0
}

/// Per-flock counts of a report, by flock id.
fn counts(stone: &Stone, r: &DropReport) -> Vec<u64> {
    (0..stone.flock_kinds.len()).map(|k| r.flocks.iter().find(|f| f.id == k).map_or(0, |f| f.count)).collect()
}

/// The fraction of a report's settled drops in flock `k`.
fn fraction(r: &DropReport, k: usize) -> f64 {
    r.flocks.iter().find(|f| f.id == k).map_or(0.0, |f| f.fraction)
}

/// Flock `k`'s fraction of a report with its 95 % interval, "—" if it has no such flock.
fn cell(r: &DropReport, k: usize) -> String {
    let f = r.flocks.iter().find(|g| g.id == k);
    f.map_or("—".into(), |g| format!("{:.3} [{:.3}, {:.3}]", g.fraction, g.ci95.0, g.ci95.1))
}

/// Each category's share (%) of Pearson's χ² statistic of homogeneity of the counts `a` and `b`.
fn chi_shares(a: &[u64], b: &[u64]) -> Vec<f64> {
    let (na, nb) = (a.iter().sum::<u64>() as f64, b.iter().sum::<u64>() as f64);
    let chi: Vec<f64> = a
        .iter()
        .zip(b)
        .map(|(&x, &y)| {
            let col = (x + y) as f64;
            let term = |o: f64, row: f64| (o - row * col / (na + nb)).powi(2) / (row * col / (na + nb));
            if col == 0.0 {
                0.0
            } else {
                term(x as f64, na) + term(y as f64, nb)
            }
        })
        .collect();
    let total = chi.iter().sum::<f64>().max(f64::MIN_POSITIVE);
    chi.iter().map(|c| 100.0 * c / total).collect()
}

/// Two runs of the same releases compared drop by drop: the Stuart–Maxwell test of marginal
/// homogeneity of their per-flock counts (`stats::stuart_maxwell`, which uses the pairing), and
/// how many of the drops settled in both end in the same flock.
struct Chi {
    chi2: f64,
    dof: usize,
    p: f64,
    same: usize,
    both: usize,
}

impl Chi {
    fn json(&self) -> Value {
        let (chi2, p) = (fixed(self.chi2, 1), fixed(self.p, 3));
        json!({"same": self.same, "both": self.both, "chi2": chi2, "dof": self.dof, "p": p})
    }
}

/// The flock a drop ended in (the certificate's, or that of its rest facet).
fn flock_of(stone: &Stone, o: &DropOutcome) -> Option<usize> {
    o.flock.map(|k| k as usize).or_else(|| o.facet.and_then(|f| stone.facet_flock[f as usize]))
}

/// [`Chi`] of the runs `a` and `b` (outcomes by drop index) on the drops settled in both.
fn drop_by_drop(stone: &Stone, a: &Outcomes, b: &Outcomes) -> Chi {
    let k = stone.flock_kinds.len();
    let mut table = vec![vec![0u64; k]; k];
    let (mut same, mut both) = (0, 0);
    for (i, x) in a {
        let Some(y) = b.get(i) else { continue };
        if let (true, true, Some(fx), Some(fy)) = (x.settled, y.settled, flock_of(stone, x), flock_of(stone, y)) {
            table[fx][fy] += 1;
            both += 1;
            same += usize::from(fx == fy);
        }
    }
    let (chi2, dof, p) = stuart_maxwell(&table);
    Chi { chi2, dof, p, same, both }
}

/// The untimed convergence check of one body: its `drops` releases in mode `m` at each of
/// [`SUBSTEPS`] solver iterations, compared drop by drop with MuJoCo's outcomes `mj` and with
/// the finest.
fn substeps(pool: &rayon::ThreadPool, stone: &Stone, h: RunHeader, m: &Mode, mj: &Outcomes) -> Value {
    let runs: Vec<Run> = SUBSTEPS
        .iter()
        .map(|&k| {
            eprintln!("  {}: {k} solver iterations (untimed)", h.mesh);
            let mut h = h.clone();
            h.params.sim.numerics.solver_iterations = k;
            timed(pool, stone, &h, m.batch)
        })
        .collect();
    let finest = &runs[runs.len() - 1];
    let shown: Vec<usize> = (0..stone.flock_kinds.len())
        .filter(|&k| finest.report.flocks.iter().any(|f| f.id == k && f.count > 0))
        .collect();
    let mut mj_counts = vec![0u64; stone.flock_kinds.len()];
    for k in mj.values().filter(|o| o.settled).filter_map(|o| flock_of(stone, o)) {
        mj_counts[k] += 1;
    }
    let settled = mj_counts.iter().sum::<u64>().max(1) as f64;
    let vs: Vec<(Chi, Chi)> = runs
        .iter()
        .map(|r| (drop_by_drop(stone, &r.outcomes, mj), drop_by_drop(stone, &r.outcomes, &finest.outcomes)))
        .collect();
    // Is the default converged, and from how many sub-steps on are the statistics those of the finest?
    let last = SUBSTEPS.len() - 1;
    let default = SUBSTEPS.iter().position(|&k| k == 4).expect("the default is in SUBSTEPS");
    let converged = (0..last).find(|&i| vs[i..last].iter().all(|v| v.1.p >= 0.05)).map(|i| SUBSTEPS[i]);
    json!({
        "shown": shown,
        "rows": SUBSTEPS.iter().zip(&runs).zip(&vs).map(|((k, r), (a, b))| json!({
            "k": k, "rate": fixed(h.drops as f64 / r.seconds, 0), "mj": a.json(), "fine": b.json(),
            "fr": shown.iter().map(|&f| fixed(fraction(&r.report, f), 4)).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "mj": shown.iter().map(|&f| fixed(mj_counts[f] as f64 / settled, 4)).collect::<Vec<_>>(),
        "default_ok": vs[default].1.p >= 0.05, "p_default": fixed(vs[default].1.p, 3), "converged": converged,
        "agree": SUBSTEPS.iter().zip(&vs).filter(|(_, v)| v.0.p >= 0.05).map(|(k, _)| k).collect::<Vec<_>>(),
    })
}

/// MuJoCo at one step, for one body: the timed drops, the larger sample (which holds them), the
/// fastest round's CPU s of the loop and of the stepping alone, the timed drops' steps, and the
/// sample's drops with a MuJoCo warning.
struct MjSide {
    report: DropReport,
    outcomes: Outcomes,
    big: DropReport,
    big_outcomes: Outcomes,
    loop_s: f64,
    step_s: f64,
    steps: f64,
    warned: usize,
}

/// Drops per second of the project against MuJoCo.
#[derive(Parser)]
struct Args {
    /// Drops per body and mode (the untimed samples have ten times as many)
    #[arg(default_value_t = 300)]
    n: u64,
    #[command(flatten)]
    common: Common,
}

fn main() -> Result<()> {
    let args = Args::parse();
    let (n, seed, modes, dts) = (args.n, args.common.seed_or(7), modes(), mj_dts());
    let (nd, big) = (n as f64, n * SAMPLE_FACTOR);
    let python = python_with_mujoco()?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = Results::open("drops_vs_mujoco", &args.common)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let bodies = benchmark_bodies(root, true)?;
    let stones: Vec<Stone> =
        bodies.iter().map(|(_, a)| Stone::new(a, a.macro_nu(&Options::default()).0)).collect::<Result<_, _>>()?;
    let box_normal = -Vec3::z();

    // MuJoCo first (one process per step, one thread): the bodies as the project has them.
    let reference = params(REFERENCE_DT);
    let release = |i: u64| launch(&mut item_rng(seed, i), &reference).orientation;
    let (c, num, rest) = (&reference.sim.contact, &reference.sim.numerics, &reference.sim.rest);
    let input = json!({
        "drops": n, "sample_drops": big, "repeats": 1,
        "orientations": (0..big).map(|i| { let q = release(i); [q.w, q.i, q.j, q.k] }).collect::<Vec<_>>(),
        "height": reference.launch.height, "friction": c.friction, "restitution": c.restitution,
        "linear_damping": c.linear_damping, "angular_damping": c.angular_damping, "dt": num.dt,
        "max_time": num.max_time,
        "rest_linear_speed": rest.rest_linear_speed, "rest_angular_speed": rest.rest_angular_speed,
        "rest_time": rest.rest_time,
        "bodies": bodies.iter().zip(&stones).enumerate().map(|(k, ((name, _), s))| json!({
            "name": name,
            "corners": s.body.corners.iter().map(|c| [c.x, c.y, c.z]).collect::<Vec<_>>(),
            "inertia": (0..3).map(|i| [0, 1, 2].map(|j| s.body.inertia[(i, j)])).collect::<Vec<_>>(),
            "flat_normal": (k == 2).then_some([box_normal.x, box_normal.y, box_normal.z]),
        })).collect::<Vec<_>>(),
    });
    let tmp = std::env::temp_dir().join(format!("drops_vs_mujoco_{}", std::process::id()));
    std::fs::create_dir_all(&tmp)?;
    let script = root.join("experiments/shared/mujoco_drops.py");
    // One run of MuJoCo at step `dt` (one process, one thread): `n` timed drops and a sample of
    // `sample` drops (the timed ones first), with `solref` when given, else the damping ratio
    // calibrated on the ball at this step.
    let run_mujoco = |sample: u64, dt: f64, solref: Option<[f64; 2]>| -> Result<MjOut> {
        let mut input = input.clone();
        (input["sample_drops"], input["dt"], input["solref"]) = (json!(sample), json!(dt), json!(solref));
        let (in_path, out_path) = (tmp.join("in.json"), tmp.join("out.json"));
        std::fs::write(&in_path, serde_json::to_string(&input)?)?;
        let mut command = Command::new(&python);
        command.arg(&script).arg(&in_path).arg(&out_path);
        for var in ["OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"] {
            command.env(var, "1");
        }
        let status = command.status().with_context(|| format!("cannot run {python}"))?;
        anyhow::ensure!(status.success(), "{} failed ({status})", script.display());
        let mj: MjOut = serde_json::from_str(&std::fs::read_to_string(&out_path)?)?;
        anyhow::ensure!(mj.bodies.len() == bodies.len(), "MuJoCo returned {} bodies", mj.bodies.len());
        Ok(mj)
    };
    // REPEATS rounds, each MuJoCo's drops at both steps and then every mode of the project, so
    // that both engines are timed under the same load of this shared machine; the fastest round
    // counts for each. MuJoCo at the longer step is the model of the reference step (its solref,
    // calibrated there) with only the step changed, as the project keeps its parameters at its
    // longer step; in the first round, an untimed check runs MuJoCo at the longer step with the
    // damping ratio calibrated again at that step (`recal`).
    let (mut mj_rounds, mut recal) = (Vec::<[MjOut; 2]>::new(), None);
    let mut best: Vec<Vec<Option<Run>>> = bodies.iter().map(|_| modes.iter().map(|_| None).collect()).collect();
    for round in 1..=REPEATS {
        let sample = if round == 1 { big } else { n };
        eprintln!("round {round} of {REPEATS}: MuJoCo at dt {} ({python} {})", step_label(dts[0]), script.display());
        let first = run_mujoco(sample, dts[0], None)?;
        eprintln!("round {round} of {REPEATS}: MuJoCo at dt {} ({python} {})", step_label(dts[1]), script.display());
        mj_rounds.push([run_mujoco(sample, dts[1], Some(first.solref))?, first]);
        mj_rounds.last_mut().expect("pushed").swap(0, 1);
        if round == 1 {
            eprintln!(
                "round 1 of {REPEATS}: MuJoCo at dt {}, damping ratio calibrated at that step (untimed check)",
                step_label(dts[1])
            );
            recal = Some(run_mujoco(n, dts[1], None)?);
        }
        eprintln!("round {round} of {REPEATS}: the project");
        for (b, ((name, _), stone)) in bodies.iter().zip(&stones).enumerate() {
            for (k, m) in modes.iter().enumerate() {
                let r = timed(&pool, stone, &header(name, n, m, seed), m.batch);
                eprintln!("  {name} {}: {:.1} drops/s", m.name, nd / r.seconds);
                if best[b][k].as_ref().is_none_or(|x| r.seconds < x.seconds) {
                    best[b][k] = Some(r);
                }
            }
        }
    }
    std::fs::remove_dir_all(&tmp)?;
    let (mj0, recal) = (&mj_rounds[0], recal.expect("round 1 ran"));
    let mut csv = String::from(
        "body,engine,mode,batch,certificate,dt,drops,cpu_seconds,drops_per_s,ratio_vs_mujoco_loop,\
         ratio_vs_mujoco_stepping,ratio_vs_mujoco_same_dt_loop,ratio_vs_mujoco_same_dt_stepping,cpu_us_per_step,\
         mean_sim_time_s,settled,certified,off_equilibrium,chi2_p_flocks_vs_mujoco,chi2_p_flocks_vs_mujoco_same_dt,\
         kl_flocks_vs_static\n",
    );
    // Per body: the four modes against MuJoCo at the reference step, then the default numerics
    // against MuJoCo at the same step; each (against the loop, against the stepping alone).
    let mut bars: Vec<(&str, Vec<(f64, f64)>)> = Vec::new();
    let (mut flat, mut box_pairs, mut ctx) = (Vec::new(), Value::Null, Vec::new());
    let (mut lead, mut longer, mut negative, mut mj_unsettled) = (Vec::new(), Vec::new(), false, Vec::new());
    let (mut worst, mut all_same, mut totals) = ((f64::INFINITY, ""), true, [0u64; 4]);
    for (b, ((name, _), stone)) in bodies.iter().zip(&stones).enumerate() {
        let short = ["stone", "pebble", "box"][b];
        let fastest = |s: usize, f: fn(&MjBody) -> &Vec<f64>| {
            mj_rounds.iter().flat_map(|r| f(&r[s].bodies[b]).iter().copied()).fold(f64::INFINITY, f64::min)
        };
        // MuJoCo's drops at each step, classified by the project's rule; its fastest round.
        let mj: Vec<MjSide> = (0..2)
            .map(|s| {
                let mb = &mj0[s].bodies[b];
                let ((report, outcomes), (big, big_outcomes)) = (
                    classify(stone, name, &mb.drops, dts[s], seed),
                    classify(stone, name, &mb.sample_drops, dts[s], seed),
                );
                let (loop_s, step_s) = (fastest(s, |x| &x.loop_cpu_s), fastest(s, |x| &x.replay_cpu_s));
                let steps = mb.drops.iter().map(|d| d.steps).sum::<u64>() as f64;
                let warned = mb.sample_drops.iter().filter(|d| d.warnings > 0).count();
                MjSide { report, outcomes, big, big_outcomes, loop_s, step_s, steps, warned }
            })
            .collect();
        let recal_drops = &recal.bodies[b].drops;
        let recal_report = classify(stone, name, recal_drops, dts[1], seed).0;
        let is_box = mj0[0].bodies[b].flat_restitution.is_some();
        if is_box {
            for (s, &dt) in dts.iter().enumerate() {
                let [m, ms] = mj0[s].bodies[b].flat_restitution.unwrap_or([f64::NAN; 2]);
                flat.push((dt, rapier_flat_restitution(stone, &box_normal, dt), m, ms));
            }
        }
        // The project's modes, their fastest round.
        let rows: Vec<Run> = best[b].iter_mut().map(|r| r.take().expect("REPEATS ≥ 1")).collect();
        // MuJoCo's releases are the project's: the largest angle between the two engines' initial
        // down directions (body frame) over every drop of the sample, at both steps.
        let downs = || mj0.iter().flat_map(|r| r.bodies[b].release_downs.iter().enumerate());
        let release_angle = downs()
            .map(|(i, d)| {
                let (own, d) = (release(i as u64).inverse() * -Vec3::z(), Vec3::from(*d));
                own.cross(&d).norm().atan2(own.dot(&d))
            })
            .fold(0.0f64, f64::max);
        let same_rounds = |s: usize| {
            mj_rounds.iter().all(|r| {
                let (x, y) = (&r[s].bodies[b].drops, &mj0[s].bodies[b].drops);
                x.iter().zip(y).all(|(x, y)| x.down == y.down && x.steps == y.steps)
            })
        };
        let e1 = |x: f64| format!("{x:.1e}");
        let checks = json!({
            "releases": downs().count(), "angle": e1(release_angle), "vertices": mj0[0].bodies[b].mesh_vertices,
            "corners": stone.body.corners.len(), "placement": e1(mj0[0].bodies[b].placement_error),
            "replay": ([0, 1].map(|s| mj_rounds.iter().all(|r| r[s].bodies[b].replay_identical))),
            "rounds": ([0, 1].map(same_rounds)), "warned": [mj[0].warned, mj[1].warned],
            "rises": [rise(&mj[0].outcomes), rise(&mj[1].outcomes)], "plain_rise": rise(&rows[0].outcomes),
        });
        // The larger, untimed samples: the batched project at the reference step (drop by drop
        // the plain drops), the default numerics, and MuJoCo at both steps.
        let project = timed(&pool, stone, &header(name, big, &modes[1], seed), DEFAULT_BATCH);
        let fast = timed(&pool, stone, &header(name, big, &modes[3], seed), modes[3].batch);
        // The two steps of one engine start from the same orientations: drops that end in the
        // same flock at both steps.
        let paired = |a: &Outcomes, b: &Outcomes| {
            let same =
                |i, o| b.get(i).is_some_and(|p: &DropOutcome| p.settled && flock_of(stone, p) == flock_of(stone, o));
            a.iter().filter(|(i, o)| o.settled && same(*i, *o)).count()
        };
        let (same_mj, same_project) =
            (paired(&mj[0].big_outcomes, &mj[1].big_outcomes), paired(&project.outcomes, &fast.outcomes));
        let versus = |a: &Outcomes, b: &Outcomes| drop_by_drop(stone, a, b);
        let big_ref = versus(&project.outcomes, &mj[0].big_outcomes);
        let big_mj_steps = versus(&mj[1].big_outcomes, &mj[0].big_outcomes);
        let big_fast_same = versus(&fast.outcomes, &mj[1].big_outcomes);
        let big_fast_ref = versus(&fast.outcomes, &mj[0].big_outcomes);
        let big_steps = versus(&fast.outcomes, &project.outcomes);
        let (pb, fb) = (&project.report, &fast.report);
        let shares = chi_shares(&counts(stone, pb), &counts(stone, &mj[0].big));
        let shares_mj = chi_shares(&counts(stone, &mj[1].big), &counts(stone, &mj[0].big));
        let kind = |k: usize| format!("{:?}", stone.flock_kinds[k]).to_lowercase();
        // The flock with the largest share of χ² between two samples, its fraction in each.
        let widest = |v: &[f64], a: &DropReport, b: &DropReport| {
            let k = (0..v.len()).max_by(|&x, &y| v[x].total_cmp(&v[y])).expect("a flock");
            json!({"k": k, "kind": kind(k), "a": fixed(fraction(a, k), 3), "b": fixed(fraction(b, k), 3)})
        };
        let fast_shares = chi_shares(&counts(stone, fb), &counts(stone, &mj[1].big));
        let sample = json!({
            "unsettled": [pb.unsettled, fb.unsettled, mj[0].big.unsettled, mj[1].big.unsettled],
            "ref": big_ref.json(), "mj_steps": big_mj_steps.json(), "fast_same": big_fast_same.json(),
            "fast_ref": big_fast_ref.json(), "steps": big_steps.json(), "same_mj": same_mj,
            "same_project": same_project,
            "flocks": pb.flocks.iter().map(|f| json!({
                "id": f.id, "kind": kind(f.id), "static": fixed(f.static_probability, 3),
                "cells": [cell(pb, f.id), cell(&mj[0].big, f.id), cell(fb, f.id), cell(&mj[1].big, f.id)],
                "shares": [fixed(shares[f.id], 0), fixed(shares_mj[f.id], 0)],
            })).collect::<Vec<_>>(),
        });
        let sub = substeps(&pool, stone, header(name, big, &modes[2], seed), &modes[2], &mj[0].big_outcomes);
        if is_box {
            // The box: its six flocks are its faces; pool the two faces of each pair (by symmetry the same).
            let axis_of = |k: usize| {
                let f = (0..stone.facet_flock.len()).find(|&f| stone.facet_flock[f] == Some(k)).expect("a facet");
                stone.body.facet_normals[f].iamax()
            };
            let pooled = |r: &DropReport, statics: bool| {
                let mut v = [0.0; 3];
                for f in &r.flocks {
                    v[axis_of(f.id)] += if statics { f.static_probability } else { f.fraction };
                }
                v.map(|x| fixed(x, 3)).join(" / ")
            };
            // MuJoCo − project per face at the reference step, the two faces of each pair side by side.
            let mut diffs = [Vec::new(), Vec::new(), Vec::new()];
            for f in &pb.flocks {
                diffs[axis_of(f.id)].push(format!("{:+.3}", fraction(&mj[0].big, f.id) - f.fraction));
            }
            box_pairs = json!({
                "pooled": [pooled(pb, false), pooled(&mj[0].big, false), pooled(fb, false), pooled(&mj[1].big, false),
                    pooled(pb, true)],
                "diffs": diffs.map(|d| d.join(" / ")),
                "apart": big_ref.p < 0.05 && flat.iter().all(|&(_, r, m, _)| (r - m).abs() > 0.01),
            });
        }
        let (mut ratios, mut table, mut us, mut p_modes, mut same_modes) = (vec![], vec![], vec![], vec![], vec![]);
        let mut p_fast_same = 0.0;
        for (m, r) in modes.iter().zip(&rows) {
            let s = dts.iter().position(|&d| d == m.dt).expect("MuJoCo runs at every mode's step");
            let rate = nd / r.seconds;
            let ratio = |secs: f64| rate / (nd / secs);
            let (rl, rs, sl, ss) = (ratio(mj[0].loop_s), ratio(mj[0].step_s), ratio(mj[s].loop_s), ratio(mj[s].step_s));
            ratios.push((rl, rs));
            let vs_same = versus(&r.outcomes, &mj[s].outcomes);
            let (p, p_same) = (versus(&r.outcomes, &mj[0].outcomes).p, vs_same.p);
            if s == 1 {
                p_fast_same = p_same;
            }
            let us_k = 1e6 * r.seconds / (nd * r.report.mean_time / r.report.params.sim.numerics.dt);
            us.push(us_k);
            p_modes.push(fixed(p, 2));
            if p < worst.0 {
                worst = (p, short);
            }
            let same =
                r.outcomes.iter().filter(|(i, o)| flock_of(stone, o) == flock_of(stone, &rows[0].outcomes[*i])).count();
            same_modes.push(same);
            let rep = &r.report;
            table.push(json!({
                "label": m.name, "dt": step_label(m.dt), "rate": fixed(rate, 1), "rl": fixed(rl, 2), "rs": fixed(rs, 2),
                "sl": fixed(sl, 2), "ss": fixed(ss, 2), "us": fixed(us_k, 2), "t": fixed(rep.mean_time, 2),
                "settled": rep.settled, "certified": rep.certified, "off": rep.off_equilibrium, "same": same,
                "agree": format!("{}/{}", vs_same.same, vs_same.both), "p": fixed(p, 2), "p_same": fixed(p_same, 2),
            }));
            csv +=
                &format!(
                "\"{name}\",project,\"{}\",{},{},{:.6},{n},{:.4},{rate:.2},{rl:.4},{rs:.4},{sl:.4},{ss:.4},{us_k:.3},\
                 {:.4},{},{},{},{p:.4},{p_same:.4},{:.5}\n",
                m.name, m.batch, m.cert.name(), m.dt, r.seconds, rep.mean_time, rep.settled, rep.certified,
                rep.off_equilibrium, rep.fit_flocks.kl_divergence
            );
        }
        // The default numerics against MuJoCo at the same step.
        let ratio = |secs: f64| nd / rows[3].seconds / (nd / secs);
        ratios.push((ratio(mj[1].loop_s), ratio(mj[1].step_s)));
        let p_mj_steps = versus(&mj[1].outcomes, &mj[0].outcomes).p;
        let mut mj_table = Vec::new();
        for (s, side) in mj.iter().enumerate() {
            let p_cell = |d| if s == 0 { String::new() } else { fixed(p_mj_steps, d) };
            for (label, secs) in
                [("mj_step loop + rest check (Python)", side.loop_s), ("stepping alone (replay)", side.step_s)]
            {
                let (us, rep) = (1e6 * secs / side.steps, &side.report);
                mj_table.push(json!({
                    "label": label, "dt": step_label(dts[s]), "rate": fixed(nd / secs, 1), "us": fixed(us, 2),
                    "t": fixed(rep.mean_time, 2), "settled": rep.settled, "off": rep.off_equilibrium, "p": p_cell(2),
                }));
                csv += &format!(
                    "\"{name}\",mujoco,\"{label}\",1,none,{:.6},{n},{secs:.4},{:.2},,,,,{us:.3},{:.4},{},0,{},{},,\
                     {:.5}\n",
                    dts[s],
                    nd / secs,
                    rep.mean_time,
                    rep.settled,
                    rep.off_equilibrium,
                    p_cell(4),
                    rep.fit_flocks.kl_divergence
                );
            }
            if side.big.unsettled > 0 {
                mj_unsettled.push(json!({"short": short, "step": step_label(dts[s]), "big": side.big.unsettled,
                    "drops": side.big.drops, "timed": side.report.unsettled}));
            }
        }
        let step_us = |s: usize| 1e6 * mj[s].step_s / mj[s].steps;
        let loop_us = 1e6 * mj[0].loop_s / mj[0].steps;
        lead.push(us[0] / step_us(0));
        longer.push(mj[0].report.mean_time.total_cmp(&rows[0].report.mean_time));
        negative |= loop_us < step_us(0);
        totals[0] += (mj[0].warned + mj[1].warned) as u64;
        totals[1] += recal_report.unsettled;
        totals[2] += mj[1].report.unsettled;
        totals[3] += pb.unsettled + fb.unsettled;
        let reports: Vec<&DropReport> = rows.iter().map(|r| &r.report).chain(mj.iter().map(|x| &x.report)).collect();
        let t = |s: usize| fixed(mj[s].report.mean_time, 2);
        let (loop_rate, step_rate) = (|s: usize| nd / mj[s].loop_s, |s: usize| nd / mj[s].step_s);
        ctx.push(json!({
            "name": name, "short": short, "rows": table, "mj_rows": mj_table, "checks": checks, "sample": sample,
            "sub": sub,
            "ratios": ratios.iter().map(|r| json!({"l": fixed(r.0, 2), "s": fixed(r.1, 2)})).collect::<Vec<_>>(),
            "us0": fixed(us[0], 2), "us1": fixed(us[1], 2), "t0": fixed(rows[0].report.mean_time, 2),
            "t2": fixed(rows[2].report.mean_time, 2),
            "mj_step_us0": fixed(step_us(0), 2), "mj_step_us1": fixed(step_us(1), 2), "mj_loop_us0": fixed(loop_us, 2),
            "mj_t0": t(0), "mj_t1": t(1), "loop_share": fixed(100.0 * (loop_us / step_us(0) - 1.0), 0),
            "mj_loop_rate0": fixed(loop_rate(0), 1), "mj_loop_rate1": fixed(loop_rate(1), 1),
            "mj_loop_x": fixed(loop_rate(1) / loop_rate(0), 2), "mj_step_rate0": fixed(step_rate(0), 1),
            "mj_step_rate1": fixed(step_rate(1), 1),
            "recal_unsettled": format!("{} of {}", recal_report.unsettled, recal_report.drops),
            "recal_t": fixed(recal_report.mean_time, 2),
            "recal_warned": recal_drops.iter().filter(|d| d.warnings > 0).count(),
            "p_mj_steps": fixed(p_mj_steps, 2), "big_mj_steps_p": fixed(big_mj_steps.p, 3),
            "mj_steps_low": big_mj_steps.p < 0.05,
            "widest_mj_steps": widest(&shares_mj, &mj[1].big, &mj[0].big), "same_mj_big": format!("{same_mj} of {big}"),
            "p_modes": p_modes.join(" / "), "p_fast_same": fixed(p_fast_same, 2),
            "same_flock": [same_modes[1], same_modes[2]],
            "big_ref_same": format!("{} of {}", big_ref.same, big_ref.both),
            "big_ref_p": fixed(big_ref.p, 3), "ref_low": big_ref.p < 0.05, "widest": widest(&shares, pb, &mj[0].big),
            "big_fast_same_p": fixed(big_fast_same.p, 3), "fast_same_low": big_fast_same.p < 0.05,
            "widest_fast_same": widest(&fast_shares, fb, &mj[1].big),
            "big_fast_ref_p": fixed(big_fast_ref.p, 3), "fast_ref_low": big_fast_ref.p < 0.05,
            "big_steps_p": fixed(big_steps.p, 3), "steps_low": big_steps.p < 0.05,
            "same_project_big": format!("{same_project} of {big}"),
            "big_unsettled": format!("{} / {}", pb.unsettled, fb.unsettled),
            "flocks": rows[0].report.flocks.iter().map(|f| json!({"id": f.id, "kind": kind(f.id),
            "static": fixed(f.static_probability, 3),
                "cells": reports.iter().map(|r| cell(r, f.id)).collect::<Vec<_>>()})).collect::<Vec<_>>(),
            "kl": reports.iter().map(|r| fixed(r.fit_flocks.kl_divergence, 4)).collect::<Vec<_>>(),
        }));
        all_same &= same_modes[1] == n as usize && same_modes[2] == n as usize;
        bars.push((short, ratios));
    }
    let range = |k: usize, stepping: bool| {
        let v: Vec<f64> = bars.iter().map(|(_, r)| if stepping { r[k].1 } else { r[k].0 }).collect();
        let (lo, hi) = (v.iter().copied().fold(f64::INFINITY, f64::min), v.iter().copied().fold(0.0, f64::max));
        format!("{lo:.1}–{hi:.1}×")
    };
    let all = |f: fn(f64) -> bool| lead.iter().all(|&q| f(q));
    let lead = [
        (all(|q| (2.0 / 3.0..=1.5).contains(&q)), "same"),
        (all(|q| q < 1.0), "project"),
        (all(|q| q > 1.0), "mujoco"),
    ]
    .iter()
    .find(|c| c.0)
    .map_or("depends", |c| c.1);
    let longer =
        [std::cmp::Ordering::Greater, std::cmp::Ordering::Less].iter().position(|o| longer.iter().all(|x| x == o));
    let (m, m1, r) = (&mj0[0], &mj0[1], &recal);
    out.readme(
        "README.md",
        include_str!("readme/drops_vs_mujoco.md"),
        json!({
            "n": n, "big": big, "factor": SAMPLE_FACTOR, "repeats": REPEATS, "batch": DEFAULT_BATCH, "seed": seed,
            "r_l": step_label(dts[0]), "d_l": step_label(dts[1]), "steps": dts.map(step_label), "substeps": SUBSTEPS,
            "height": HEIGHT.to_string(), "friction": FRICTION.to_string(), "restitution": RESTITUTION.to_string(),
            "linear_damping": LINEAR_DAMPING.to_string(), "angular_damping": ANGULAR_DAMPING.to_string(),
            "timeconst": MJ_TIMECONST.to_string(), "rest_tolerance": REST_TOLERANCE.to_string(),
            "max_time": reference.sim.numerics.max_time.to_string(),
            "mj": {
                "version": m.mujoco_version, "python": m.python_version, "numpy": m.numpy_version, "cone": m.cone,
                "solref0": m.solref[0].to_string(), "solref1": fixed(m.solref[1], 4),
                "mj1_solref0": m1.solref[0].to_string(),
                "mj1_solref1": fixed(m1.solref[1], 4), "e": fixed(m.ball_restitution, 3),
                "e_speeds": fixed(m.ball_restitution_speeds, 3),
                "e1": fixed(m1.ball_restitution, 3), "e1_speeds": fixed(m1.ball_restitution_speeds, 3),
                "recal_solref1": fixed(r.solref[1], 4), "recal_e": fixed(r.ball_restitution, 3),
                "solimp": format!("{:?}", m.solimp),
                "integrator": m.integrator,
                "default_integrator": m.default_integrator.trim_start_matches("mjINT_").to_lowercase(),
                "solver": m.solver.trim_start_matches("mjSOL_").to_lowercase(), "iterations": m.iterations,
                "tolerance": format!("{:e}", m.tolerance), "steps_per_tc": fixed(MJ_TIMECONST / dts[1], 1),
                "depends": (m.ball_restitution - m1.ball_restitution).abs() > 0.02,
            },
            "flat": flat.iter().map(|&(dt, r, m, ms)| json!({"step": step_label(dt), "r": fixed(r, 3),
            "m": fixed(m, 3), "ms": fixed(ms, 3)})).collect::<Vec<_>>(),
            "modes": modes.iter().map(|m| &m.name).collect::<Vec<_>>(), "bodies": ctx, "box": box_pairs,
            "ranges": {"plain": range(0, false), "plain_stepping": range(0, true), "cert": range(2, false),
            "default": range(3, false), "same_step": range(4, false)},
            "lead": lead, "longer": longer, "negative": negative, "mj_unsettled": mj_unsettled, "warned": totals[0],
            "recal_unsettled": totals[1], "mj_timed_unsettled": totals[2] > 0, "project_unsettled": totals[3] > 0,
            "worst": {"p": fixed(worst.0, 2), "short": worst.1}, "all_same": all_same,
        }),
    )?;
    out.write("speed.csv", csv)?;
    plot(&out.path("ratio.png"), &modes, &bars)
}

/// The ratios of each body: one bar per mode against MuJoCo at the reference step, then the
/// default numerics against MuJoCo at the same step (the bar: against MuJoCo's loop; a black
/// mark: against its stepping alone), on a log axis (a ratio and its inverse are as far from 1×).
fn plot(path: &Path, modes: &[Mode], bars: &[(&str, Vec<(f64, f64)>)]) -> Result<()> {
    let (r_l, d_l) = (step_label(REFERENCE_DT), step_label(fast_dt()));
    let mut series: Vec<String> = modes.iter().map(|m| format!("{} ÷ MuJoCo at {r_l}", m.short)).collect();
    series.push(format!("{} ÷ MuJoCo at {d_l}, the same step", modes[3].short));
    let values = || bars.iter().flat_map(|(_, v)| v.iter().flat_map(|r| [r.0, r.1]));
    let (bottom, top, right) =
        (values().fold(0.5, f64::min) * 0.8, values().fold(10.0, f64::max) * 12.0, bars.len() as f64 - 0.5);
    let names: Vec<String> = bars.iter().map(|b| b.0.to_string()).collect();
    let x = Axis::linear("", -0.5, right).no_grid().ticks(bars.len() + 1).format(move |x| {
        let k = x.round();
        let known = ((x - k).abs() < 1e-6 && k >= 0.0).then(|| names.get(k as usize)).flatten();
        known.map_or(String::new(), |b| match b.as_str() {
            "stone" => "bundled stone (581 hull vertices)".into(),
            "pebble" => "synthetic pebble (500 hull vertices)".into(),
            other => format!("{other} 1 × 0.8 × 0.5"),
        })
    });
    let y = Axis::log("drops/s of the project ÷ drops/s of MuJoCo (log scale)", bottom, top)
        .format(|y| format!("{}×", rocking_stones::plot::log_tick(y)))
        .space(70);
    // The reference level 1× first, so that the bars and their labels lie over it.
    let mut chart = Chart::new(x, y)
        .title("Drops per core: this project ÷ MuJoCo, same physics, one core")
        .dashed(&[(-0.5, 1.0), (right, 1.0)], BLACK);
    let w = 0.86 / series.len() as f64;
    let x0 = |k: usize, slot: usize| k as f64 - 0.43 + slot as f64 * w;
    for (slot, label) in series.iter().enumerate() {
        let boxes: Vec<_> = bars
            .iter()
            .enumerate()
            .map(|(k, (_, v))| (x0(k, slot), bottom, x0(k, slot) + w * 0.9, v[slot].0))
            .collect();
        chart = chart
            .boxes(&boxes, series_color(slot), 1.0)
            .legend(Mark::Box(series_color(slot), 1.0), format!("{label} (its mj_step loop + rest check)"));
    }
    for (k, (_, v)) in bars.iter().enumerate() {
        for (slot, &(l, s)) in v.iter().enumerate() {
            // The ratio against MuJoCo's loop above each bar, the mark of the stepping alone across it.
            let label_at = (x0(k, slot) + w * 0.05, l.max(s) * 1.3);
            chart = chart
                .line_width(&[(x0(k, slot), s), (x0(k, slot) + w * 0.9, s)], BLACK, 3)
                .text(format!("{l:.1}×"), label_at);
        }
    }
    chart
        .legend(Mark::WideLine(BLACK, 3), "the same bar against MuJoCo's stepping alone (no Python per step)")
        .legend(Mark::Dashed(BLACK), "1×: as fast as MuJoCo")
        .save(path, (1200, 720))?;
    Ok(())
}
