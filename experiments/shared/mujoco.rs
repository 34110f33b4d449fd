//! The MuJoCo side of the experiments that drop the benchmark bodies in both engines
//! (`drops_vs_mujoco`, `drops_solver_substeps`): the physics matched in both, the project's modes
//! and parameters, MuJoCo's run through `shared/mujoco_drops.py` (its output, its drops
//! classified by the project's rule) and the drop-by-drop comparison of two runs of the same
//! releases (`dynamics::drops::compare`) for a README.

use super::benchmark_bodies::benchmark_bodies;
use super::harness::{fixed, Context, Result};
use nalgebra::UnitQuaternion;
use rocking_stones::dynamics::drops::compare::Agreement;
use rocking_stones::dynamics::drops::launch::outcome_at;
use rocking_stones::dynamics::drops::montecarlo::{height_above_median_max, summarize};
use rocking_stones::prelude::*;
use serde::Deserialize;
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::process::{Command, Stdio};

/// The physics both engines run (scaled frame).
pub const HEIGHT: f64 = 0.5;
pub const FRICTION: f64 = 0.6;
pub const RESTITUTION: f64 = 0.2;
pub const LINEAR_DAMPING: f64 = 0.1;
pub const ANGULAR_DAMPING: f64 = 1.0;
/// The untimed samples for the statistics have this many times N drops per engine (their first N
/// are the timed drops).
pub const SAMPLE_FACTOR: u64 = 10;

pub type Outcomes = BTreeMap<u64, DropOutcome>;

/// The steps MuJoCo runs at: the reference step (the benchmark protocol) and the project's default
/// drop step, `Preset::largest_stable_dt` (1/120 s).
pub fn mj_dts() -> [f64; 2] {
    [REFERENCE_DT, Preset::Drop.largest_stable_dt()]
}

/// "1/240 s" for dt = 1/240 s.
pub fn step_label(dt: f64) -> String {
    format!("1/{:.0} s", 1.0 / dt)
}

/// A mode of the project: stones per world, certificate, and the step it runs ([`REFERENCE_DT`]
/// for the reference modes, the preset's default step for the default numerics).
#[derive(Clone)]
pub struct Mode {
    pub name: String,
    pub short: String,
    pub batch: usize,
    pub cert: CertificateMode,
    pub dt: f64,
}

/// The project's modes: three at the reference step (MuJoCo's step of the benchmark protocol) and
/// the default numerics (flock-certified + batched at [`Preset::largest_stable_dt`]).
pub fn modes() -> [Mode; 4] {
    let mode = |name: String, short: String, batch, cert, dt| Mode { name, short, batch, cert, dt };
    let (b, f, fast) = (DEFAULT_BATCH, CertificateMode::Flock, Preset::Drop.largest_stable_dt());
    [
        mode("plain".into(), "plain".into(), 1, CertificateMode::None, REFERENCE_DT),
        mode("batched".into(), "batched".into(), b, CertificateMode::None, REFERENCE_DT),
        mode("flock-certified + batched".into(), "flock-cert. + batched".into(), b, f, REFERENCE_DT),
        mode(
            format!("flock-certified + batched, default numerics (dt {})", step_label(fast)),
            format!("flock-cert. + batched, default numerics (dt {})", step_label(fast)),
            b,
            f,
            fast,
        ),
    ]
}

/// The project's parameters at step `dt`: the `drop` preset on steel on wood (its numerics:
/// exact landings and sub-stepped impacts, which damp the free flight exactly), with the matched
/// physics overriding it, no rolling resistance or torsional friction (MuJoCo's condim 3 has
/// neither).
pub fn params(dt: f64) -> DropParams {
    let mut p = Preset::Drop.params(Surface::SteelOnWood);
    p.launch.height = HEIGHT;
    let c = &mut p.sim.contact;
    (c.friction, c.restitution, c.linear_damping, c.angular_damping) =
        (FRICTION, RESTITUTION, LINEAR_DAMPING, ANGULAR_DAMPING);
    (c.rolling_resistance, c.torsional_friction) = (0.0, 0.0);
    p.sim.numerics.dt = dt;
    p
}

pub fn header(name: &str, n: u64, m: &Mode, seed: u64) -> RunHeader {
    RunHeader::of_params(name, seed, n, params(m.dt), m.cert).with_preset(Preset::Drop)
}

/// What `shared/mujoco_drops.py` writes.
#[derive(Deserialize)]
pub struct MjOut {
    pub mujoco_version: String,
    pub numpy_version: String,
    pub python_version: String,
    pub integrator: String,
    pub default_integrator: String,
    pub cone: String,
    pub solver: String,
    pub iterations: u32,
    pub tolerance: f64,
    pub solref: [f64; 2],
    pub solimp: Vec<f64>,
    pub ball_restitution: f64,
    pub ball_restitution_speeds: f64,
    pub bodies: Vec<MjBody>,
}

#[derive(Deserialize)]
pub struct MjBody {
    pub placement_error: f64,
    pub mesh_vertices: usize,
    pub flat_restitution: Option<[f64; 2]>,
    pub drops: Vec<MjDrop>,
    pub sample_drops: Vec<MjDrop>,
    pub loop_cpu_s: Vec<f64>,
    pub replay_cpu_s: Vec<f64>,
    pub replay_identical: bool,
    /// Every release's initial down direction in the project's body frame, as MuJoCo placed it.
    pub release_downs: Vec<[f64; 3]>,
}

#[derive(Deserialize)]
pub struct MjDrop {
    pub down: [f64; 3],
    pub steps: u64,
    pub settled: bool,
    /// Warnings MuJoCo raised during the drop (bad qpos/qvel/qacc: an instability, after which it
    /// resets the state).
    #[serde(default)]
    pub warnings: u64,
}

/// MuJoCo's drops at step `dt` classified by the project's rule ([`Stone::rest`] of the final
/// down direction), as outcomes of a plain run, and their summary. A drop that ended with a
/// non-finite down direction or after a MuJoCo warning counts as not settled.
pub fn classify(stone: &Stone, name: &str, drops: &[MjDrop], dt: f64, seed: u64) -> (DropReport, Outcomes) {
    let outcome = |(i, d): (usize, &MjDrop)| {
        let down = Vec3::from(d.down);
        let sane = down.iter().all(|x| x.is_finite()) && down.norm() > 0.5 && d.warnings == 0;
        (i as u64, outcome_at(stone, i as u64, sane.then_some(&down), d.settled, d.steps as f64 * dt))
    };
    let outcomes: Outcomes = drops.iter().enumerate().map(outcome).collect();
    let mode = Mode { dt, ..modes()[0].clone() };
    (summarize(&stone.model(), &header(name, drops.len() as u64, &mode, seed), &outcomes), outcomes)
}

/// The Python interpreter (`ROCKING_PYTHON`, default `python3`), if it can import mujoco.
pub fn python_with_mujoco(experiment: &str) -> Result<String> {
    let python = std::env::var("ROCKING_PYTHON").unwrap_or_else(|_| "python3".into());
    let mut check = Command::new(&python);
    let ok = check.args(["-c", "import mujoco, numpy"]).stdout(Stdio::null()).stderr(Stdio::null()).status();
    anyhow::ensure!(
        ok.is_ok_and(|s| s.success()),
        "{experiment} needs MuJoCo's Python bindings, but `{python} -c 'import mujoco, numpy'` failed.\n\
         Install them with `{python} -m pip install mujoco` (it brings numpy), or point ROCKING_PYTHON at an \
         interpreter that has them, e.g.\n  python3 -m venv target/mujoco-venv && target/mujoco-venv/bin/pip \
         install mujoco\n  ROCKING_PYTHON=target/mujoco-venv/bin/python cargo experiment \
         {experiment}"
    );
    Ok(python)
}

/// An [`Agreement`] of two runs of the same releases (`dynamics::drops::compare`) for a README:
/// drops in the same flock of those settled in both, χ² (one decimal), its degrees of freedom, p
/// (three decimals).
pub fn agreement_json(c: &Agreement) -> Value {
    let (chi2, p) = (fixed(c.chi2, 1), fixed(c.p, 3));
    json!({"same": c.same, "both": c.both, "chi2": chi2, "dof": c.dof, "p": p})
}

/// MuJoCo at one step, for one body: the timed drops, the larger sample (which holds them), the
/// fastest round's CPU s of the loop and of the stepping alone, the timed drops' steps, and the
/// sample's drops with a MuJoCo warning.
pub struct MjSide {
    pub report: DropReport,
    pub outcomes: Outcomes,
    pub big: DropReport,
    pub big_outcomes: Outcomes,
    pub loop_s: f64,
    pub step_s: f64,
    pub steps: f64,
    pub warned: usize,
}

impl MjSide {
    /// Body `b` of MuJoCo's `runs` at step `dt` (one per round, the first holding the sample),
    /// classified by the project's rule; the fastest round's CPU seconds.
    pub fn of(stone: &Stone, name: &str, runs: &[MjOut], b: usize, dt: f64, seed: u64) -> MjSide {
        let fastest = |f: fn(&MjBody) -> &Vec<f64>| {
            runs.iter().flat_map(|r| f(&r.bodies[b]).iter().copied()).fold(f64::INFINITY, f64::min)
        };
        let mb = &runs[0].bodies[b];
        let ((report, outcomes), (big, big_outcomes)) =
            (classify(stone, name, &mb.drops, dt, seed), classify(stone, name, &mb.sample_drops, dt, seed));
        let (loop_s, step_s) = (fastest(|x| &x.loop_cpu_s), fastest(|x| &x.replay_cpu_s));
        let steps = mb.drops.iter().map(|d| d.steps).sum::<u64>() as f64;
        let warned = mb.sample_drops.iter().filter(|d| d.warnings > 0).count();
        MjSide { report, outcomes, big, big_outcomes, loop_s, step_s, steps, warned }
    }
}

/// The checks of MuJoCo's side for body `b`, from its runs at each step (one a round, the first
/// holding the samples), its classified drops `mj` and the project's plain drops: MuJoCo's
/// releases are the project's (the largest angle between the two engines' initial down
/// directions, body frame, over every drop of the sample, at both steps), its mesh and placement,
/// its replays and rounds bit for bit the same, its warnings, and how far off its facet each
/// engine's drops came to rest.
pub fn mj_checks(bench: &Bench, rounds: &[Vec<MjOut>; 2], b: usize, mj: &[MjSide], plain: &Outcomes) -> Value {
    let downs = || rounds.iter().flat_map(|r| r[0].bodies[b].release_downs.iter().enumerate());
    let release_angle = downs()
        .map(|(i, d)| {
            let (own, d) = (bench.release(i as u64).inverse() * -Vec3::z(), Vec3::from(*d));
            own.cross(&d).norm().atan2(own.dot(&d))
        })
        .fold(0.0f64, f64::max);
    let same_rounds = |s: usize| {
        rounds[s].iter().all(|r| {
            let (x, y) = (&r.bodies[b].drops, &rounds[s][0].bodies[b].drops);
            x.iter().zip(y).all(|(x, y)| x.down == y.down && x.steps == y.steps)
        })
    };
    let e1 = |x: f64| format!("{x:.1e}");
    // Median and largest height above the facet's rest of each run's settled drops.
    let rise = |o: &Outcomes| height_above_median_max(o).map(e1);
    json!({
        "releases": downs().count(), "angle": e1(release_angle), "vertices": rounds[0][0].bodies[b].mesh_vertices,
        "corners": bench.stones[b].body.corners.len(), "placement": e1(rounds[0][0].bodies[b].placement_error),
        "replay": ([0, 1].map(|s| rounds[s].iter().all(|r| r.bodies[b].replay_identical))),
        "rounds": ([0, 1].map(same_rounds)), "warned": [mj[0].warned, mj[1].warned],
        "rises": [rise(&mj[0].outcomes), rise(&mj[1].outcomes)], "plain_rise": rise(plain),
    })
}

impl MjOut {
    /// MuJoCo's settings that do not depend on the step, for a README.
    pub fn settings(&self) -> Value {
        json!({
            "version": self.mujoco_version, "python": self.python_version, "numpy": self.numpy_version,
            "cone": self.cone, "solimp": format!("{:?}", self.solimp), "integrator": self.integrator,
            "default_integrator": self.default_integrator.trim_start_matches("mjINT_").to_lowercase(),
            "solver": self.solver.trim_start_matches("mjSOL_").to_lowercase(), "iterations": self.iterations,
            "tolerance": format!("{:e}", self.tolerance),
        })
    }
}

/// The facet normal (body frame) of the box's flat landing, whose restitution MuJoCo measures.
pub fn box_normal() -> Vec3 {
    -Vec3::z()
}

/// The benchmark bodies, their stones, and MuJoCo's input for them: `n` timed drops and a sample
/// of `big` (the timed ones first), released as the project releases the same drop indices.
pub struct Bench {
    pub bodies: Vec<(String, Analysis)>,
    pub stones: Vec<Stone>,
    /// The project's parameters at the reference step.
    pub reference: DropParams,
    pub seed: u64,
    pub python: String,
    pub script: PathBuf,
    experiment: &'static str,
    input: Value,
}

impl Bench {
    /// The bodies of `experiment` (which names its error message and temporary folder), after
    /// checking that the Python interpreter has MuJoCo.
    pub fn new(experiment: &'static str, seed: u64, n: u64, big: u64) -> Result<Bench> {
        let python = python_with_mujoco(experiment)?;
        let root = crate::harness::repo();
        let bodies = benchmark_bodies(root, true)?;
        let stones: Vec<Stone> =
            bodies.iter().map(|(_, a)| Stone::new(a, a.macro_nu(&Options::default()).0)).collect::<Result<_, _>>()?;
        let (reference, box_normal) = (params(REFERENCE_DT), box_normal());
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
        let script = root.join("experiments/shared/mujoco_drops.py");
        Ok(Bench { bodies, stones, reference, seed, python, script, experiment, input })
    }

    /// The release orientation (body → world) of drop `i`.
    pub fn release(&self, i: u64) -> UnitQuaternion<f64> {
        launch(&mut item_rng(self.seed, i), &self.reference).orientation
    }

    /// One run of MuJoCo at step `dt` (one process, one thread): the timed drops and a sample of
    /// `sample` drops (the timed ones first), with `solref` when given, else the damping ratio
    /// calibrated on the ball at this step.
    pub fn run(&self, sample: u64, dt: f64, solref: Option<[f64; 2]>) -> Result<MjOut> {
        let tmp = std::env::temp_dir().join(format!("{}_{}", self.experiment, std::process::id()));
        std::fs::create_dir_all(&tmp)?;
        let mut input = self.input.clone();
        (input["sample_drops"], input["dt"], input["solref"]) = (json!(sample), json!(dt), json!(solref));
        let (in_path, out_path) = (tmp.join("in.json"), tmp.join("out.json"));
        std::fs::write(&in_path, serde_json::to_string(&input)?)?;
        let one_thread = ["OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"].map(|var| (var, "1"));
        let mut command = Command::new(&self.python);
        command.arg(&self.script).arg(&in_path).arg(&out_path).envs(one_thread);
        let status = command.status().with_context(|| format!("cannot run {}", self.python))?;
        anyhow::ensure!(status.success(), "{} failed ({status})", self.script.display());
        let mj: MjOut = serde_json::from_str(&std::fs::read_to_string(&out_path)?)?;
        std::fs::remove_dir_all(&tmp)?;
        anyhow::ensure!(mj.bodies.len() == self.bodies.len(), "MuJoCo returned {} bodies", mj.bodies.len());
        Ok(mj)
    }
}
