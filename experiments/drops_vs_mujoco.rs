//! Drops per second per core of this project against MuJoCo under the same physics, and the
//! agreement of their outcome statistics, in one run on one core.
//!
//! Both engines drop the three benchmark bodies (`shared/benchmark_bodies.rs`) from rest, lowest
//! point 0.5 R_max above a plane, Haar-uniform orientation, μ 0.6, e 0.2, global damping 0.1 s⁻¹
//! (linear) and 1 s⁻¹ (angular), dt 1/240 s, the same rest rule and 60 s cap, in the scaled frame
//! (R_max = 1 m, mass 1, g = 9.81) with the same hull corners and inertia tensor. The project
//! runs plain, batched, flock-certified + batched and `--fast` flock-certified + batched;
//! MuJoCo runs from Python (`shared/mujoco_drops.py`, which documents its settings) and returns
//! each drop's final body-frame down direction, classified here by the project's own rule
//! (`Stone::rest`), so both are counted per flock identically. The drops are not the same drop by
//! drop (each side draws its own orientations); the per-flock statistics are compared (χ²
//! homogeneity).
//!
//! Run: `cargo run --release --example drops_vs_mujoco [-- N]` (N = 300 drops per body and mode)
//! → `results/drops_vs_mujoco/`. Needs MuJoCo's Python bindings (`pip install mujoco`) in
//! `python3` or in the interpreter named by `ROCKING_PYTHON`.

#[path = "shared/benchmark_bodies.rs"]
mod benchmark_bodies;
#[path = "shared/cpu_time.rs"]
mod cpu_time;
use benchmark_bodies::benchmark_bodies;
use cpu_time::thread_cpu_seconds;
use nalgebra::UnitQuaternion;
use rocking_stones::analysis::Options;
use rocking_stones::dynamics::drop::DropOutcome;
use rocking_stones::dynamics::params::{DropParams, Preset, Surface};
use rocking_stones::dynamics::stone::{Stone, REST_TOLERANCE};
use rocking_stones::dynamics::world::Simulation;
use rocking_stones::montecarlo::{
    certificate, run_batched, summarize, CertificateMode, DropReport, RunHeader, Shard, DEFAULT_BATCH, FORMAT,
};
use rocking_stones::plot::{init_fonts, series_color, FONT_FAMILY};
use rocking_stones::stats::chi_square_homogeneity;
use rocking_stones::Vec3;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;

/// The physics both engines run (scaled frame).
const HEIGHT: f64 = 0.5;
const FRICTION: f64 = 0.6;
const RESTITUTION: f64 = 0.2;
const LINEAR_DAMPING: f64 = 0.1;
const ANGULAR_DAMPING: f64 = 1.0;
const DT: f64 = 1.0 / 240.0;
const SEED: u64 = 7;
/// The untimed samples for the statistics have this many times N drops per engine (their first N
/// are the timed drops).
const SAMPLE_FACTOR: u64 = 10;
/// Rounds of timing (each: MuJoCo's drops, then every mode of the project); the fastest round counts.
const REPEATS: usize = 3;

/// What differs between the two engines, for the README.
const DIFFERENCES: &str = "
**What differs (and is not matched).**

* **Contact.** Both contacts are soft, differently. Rapier's is a velocity-level constraint that
  applies the restitution coefficient at impact, with a soft position correction (springs of 30–60 Hz,
  `dynamics::world`); MuJoCo's is a spring-damper reference acceleration (time constant 0.02 s, the
  `solimp` impedance) whose under-damping *is* the restitution. Matched on a ball (e = 0.2 by rebound
  height), they differ on other impacts: the box landing flat rebounds differently in the two engines
  (above), and the edge and corner impacts of a tumbling stone are not calibrated at all.
* **Friction.** Rapier 0.36's default friction model (`FrictionModel::Simplified`) solves one Coulomb
  constraint (circular cone) per contact patch at its friction centre plus one *twist* constraint with the
  contact points' lever arms; MuJoCo with condim 3 has an elliptic-cone Coulomb constraint at each contact
  point. Both resist the twist of a multi-point patch; neither has rolling resistance or torsional
  friction at a single point (the project's own rolling and torsional laws are switched off here).
* **Numerics.** Rapier: f32, 4 solver iterations. MuJoCo: f64, a Newton solver run to its tolerance
  (up to 100 iterations), the implicitfast integrator (damping implicit, Coriolis forces explicit).
* **Collision.** The project's own hull collider in rapier's pipeline against MuJoCo's convex mesh–plane
  collision on the same corners (same support function, checked above).
* **Drops.** Each engine draws its own orientations (the project its seeded streams, MuJoCo numpy's
  generator): the statistics are compared, not the drops. Classifying a drop (`Stone::rest`, one descent
  of the support function) is inside the project's timing and outside MuJoCo's (done here afterwards).
* **Timing.** Two different clocks of the same machine: the CPU time of the project's one worker thread
  and the CPU time of the Python process (one thread for MuJoCo; numpy's threads are limited to one).
  CPU times on this shared machine move by ± 15 % from run to run (`results/drops_certificate/`), and
  by more while other jobs run; the rounds (above) time both engines under the same load.
";

/// A mode of the project: stones per world, certificate, and the preset's fast numerics.
#[derive(Clone, Copy)]
struct Mode {
    name: &'static str,
    short: &'static str,
    batch: usize,
    cert: CertificateMode,
    fast: bool,
}

const MODES: [Mode; 4] = [
    Mode { name: "plain", short: "plain", batch: 1, cert: CertificateMode::None, fast: false },
    Mode { name: "batched", short: "batched", batch: DEFAULT_BATCH, cert: CertificateMode::None, fast: false },
    Mode {
        name: "flock-certified + batched",
        short: "flock-cert. + batched",
        batch: DEFAULT_BATCH,
        cert: CertificateMode::Flock,
        fast: false,
    },
    Mode {
        name: "flock-certified + batched, --fast (dt 1/120 s)",
        short: "--fast flock-cert. + batched",
        batch: DEFAULT_BATCH,
        cert: CertificateMode::Flock,
        fast: true,
    },
];

/// The project's parameters of mode `m`: the `drop` preset on steel on wood, with the matched
/// physics overriding it, no rolling resistance or torsional friction (MuJoCo's condim 3 has
/// neither), and `Preset::fast` for `--fast` (the default numerics — exact landings and
/// sub-stepped impacts, which damp the free flight exactly — at the longer step 1/120 s).
fn params(m: &Mode) -> DropParams {
    let mut p = Preset::Drop.params(Surface::SteelOnWood);
    p.height = HEIGHT;
    p.friction = FRICTION;
    p.restitution = RESTITUTION;
    p.linear_damping = LINEAR_DAMPING;
    p.angular_damping = ANGULAR_DAMPING;
    p.rolling_resistance = 0.0;
    p.torsional_friction = 0.0;
    p.dt = DT;
    if m.fast {
        Preset::Drop.fast(&mut p);
    }
    p
}

fn header(name: &str, n: u64, m: &Mode) -> RunHeader {
    RunHeader {
        format: FORMAT.into(),
        mesh: name.into(),
        mesh_fingerprint: String::new(),
        seed: SEED,
        drops: n,
        params: params(m),
        certificate: m.cert,
        preset: Some(Preset::Drop.name().into()),
        center_of_mass: None,
        shard: Shard::ALL,
    }
}

struct Run {
    report: DropReport,
    outcomes: BTreeMap<u64, DropOutcome>,
    seconds: f64,
    /// Median and largest h(final down) − R_F of the drops simulated to rest (R_max).
    rise: (f64, f64),
}

/// Median and largest `height_above` (h(final down) − R_F, R_max) of the outcomes that have one:
/// how far off its stable facet's normal a drop ended (0 when flat on it).
fn rise(outcomes: &BTreeMap<u64, DropOutcome>) -> (f64, f64) {
    let mut h: Vec<f64> = outcomes.values().filter(|o| o.settled).filter_map(|o| o.height_above).collect();
    if h.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    h.sort_by(f64::total_cmp);
    (h[h.len() / 2], h[h.len() - 1])
}

/// Every drop of `h` with `batch` stones per world on the current (one-thread) pool, timed by
/// the worker thread's CPU time.
fn timed(stone: &Stone, h: &RunHeader, batch: usize) -> Run {
    let sink = Mutex::new(|_: &DropOutcome| {});
    let cert = certificate(stone, h.certificate);
    let t = thread_cpu_seconds();
    let out = run_batched(stone, h, Shard::ALL, &BTreeMap::new(), cert.as_ref(), batch, &sink);
    let seconds = thread_cpu_seconds() - t;
    let outcomes: BTreeMap<u64, DropOutcome> = out.into_iter().map(|o| (o.index, o)).collect();
    Run { report: summarize(&stone.model(), h, &outcomes), rise: rise(&outcomes), outcomes, seconds }
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
}

#[derive(Deserialize)]
struct MjDrop {
    down: [f64; 3],
    steps: u64,
    settled: bool,
}

/// MuJoCo's drops classified by the project's rule ([`Stone::rest`] of the final down direction),
/// as outcomes of the plain mode, and their summary.
fn classify(stone: &Stone, name: &str, drops: &[MjDrop]) -> (DropReport, BTreeMap<u64, DropOutcome>) {
    let outcomes: BTreeMap<u64, DropOutcome> = drops
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let rest = stone.rest(&Vec3::new(d.down[0], d.down[1], d.down[2]));
            let o = DropOutcome {
                index: i as u64,
                settled: d.settled,
                facet: Some(rest.facet),
                flock: None,
                time: d.steps as f64 * DT,
                certified: false,
                height_above: Some(rest.height_above),
            };
            (i as u64, o)
        })
        .collect();
    (summarize(&stone.model(), &header(name, drops.len() as u64, &MODES[0]), &outcomes), outcomes)
}

/// The Python interpreter (`ROCKING_PYTHON`, default `python3`); exits with a message when it
/// cannot import mujoco.
fn python_with_mujoco() -> String {
    let python = std::env::var("ROCKING_PYTHON").unwrap_or_else(|_| "python3".into());
    let ok = Command::new(&python)
        .args(["-c", "import mujoco, numpy"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !ok {
        eprintln!(
            "drops_vs_mujoco needs MuJoCo's Python bindings, but `{python} -c 'import mujoco, numpy'` failed.\n\
             Install them with `{python} -m pip install mujoco` (it brings numpy), or point ROCKING_PYTHON at an \
             interpreter that has them, e.g.\n  python3 -m venv target/mujoco-venv && target/mujoco-venv/bin/pip \
             install mujoco\n  ROCKING_PYTHON=target/mujoco-venv/bin/python cargo run --release --example \
             drops_vs_mujoco"
        );
        std::process::exit(2);
    }
    python
}

/// Restitution of a flat landing in rapier (the project's world and contact, no damping): the
/// body dropped from rest with its facet of outward normal `normal` (body frame) facing down,
/// `HEIGHT` above the ground; e = √(rebound height / drop height) of G above its height at first
/// touch, as the Python side measures MuJoCo's.
fn rapier_flat_restitution(stone: &Stone, normal: &Vec3) -> f64 {
    let mut p = params(&MODES[0]);
    p.linear_damping = 0.0;
    p.angular_damping = 0.0;
    let q = UnitQuaternion::rotation_between(normal, &-Vec3::z()).unwrap_or_else(UnitQuaternion::identity);
    let h = stone.body.support(normal);
    let mut sim = Simulation::new(&stone.body, &p, &q, HEIGHT + h, &Vec3::zeros(), &Vec3::zeros());
    let (mut touched, mut left, mut apex) = (false, false, f64::NEG_INFINITY);
    for _ in 0..(10.0 / p.dt) as usize {
        sim.step();
        let touching = sim.normal_impulse() > 0.0;
        let s = sim.state();
        if !touched {
            touched = touching;
        } else if !left {
            left = !touching;
        } else if touching || s.linvel.z < 0.0 {
            return ((apex - h).max(0.0) / HEIGHT).sqrt();
        } else {
            apex = apex.max(s.z);
        }
    }
    0.0
}

/// What the reading of the README needs of one body.
struct Summary {
    short: &'static str,
    /// CPU µs per simulated step of each mode.
    us: Vec<f64>,
    /// χ² homogeneity p of each mode's per-flock counts against MuJoCo's.
    p: Vec<f64>,
    mj_step_us: f64,
    mj_loop_us: f64,
    /// Mean simulated s per drop of each mode.
    t: Vec<f64>,
    mj_t: f64,
    /// The flock with the largest share of χ² in the larger samples: id, type, the project's and
    /// MuJoCo's fraction there.
    widest: (usize, String, f64, f64),
    /// χ² homogeneity p of the larger samples.
    p_big: f64,
}

/// One row of the results: a project mode.
struct Row {
    label: String,
    rate: f64,
    seconds: f64,
    report: DropReport,
    outcomes: BTreeMap<u64, DropOutcome>,
    rise: (f64, f64),
}

fn main() -> anyhow::Result<()> {
    let n: u64 = std::env::args().nth(1).map_or(300, |s| s.parse().expect("N: drops per body and mode"));
    let python = python_with_mujoco();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let out = root.join("results/drops_vs_mujoco");
    std::fs::create_dir_all(&out)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let bodies = benchmark_bodies(&root, true)?;
    let stones: Vec<Stone> =
        bodies.iter().map(|(_, a)| Stone::new(a, a.macro_nu(&Options::default()).0)).collect::<Result<_, _>>()?;
    let box_normal = -Vec3::z();

    // MuJoCo first (one process, one thread): the bodies as the project has them.
    let reference = params(&MODES[0]);
    let input = serde_json::json!({
        "drops": n,
        "sample_drops": n * SAMPLE_FACTOR,
        "seed": SEED,
        "repeats": 1,
        "height": reference.height,
        "friction": reference.friction,
        "restitution": reference.restitution,
        "linear_damping": reference.linear_damping,
        "angular_damping": reference.angular_damping,
        "dt": reference.dt,
        "max_time": reference.max_time,
        "rest_linear_speed": reference.rest_linear_speed,
        "rest_angular_speed": reference.rest_angular_speed,
        "rest_time": reference.rest_time,
        "bodies": bodies.iter().zip(&stones).enumerate().map(|(k, ((name, _), s))| serde_json::json!({
            "name": name,
            "corners": s.body.corners.iter().map(|c| [c.x, c.y, c.z]).collect::<Vec<_>>(),
            "inertia": (0..3).map(|i| [s.body.inertia[(i, 0)], s.body.inertia[(i, 1)], s.body.inertia[(i, 2)]])
                .collect::<Vec<_>>(),
            "flat_normal": (k == 2).then_some([box_normal.x, box_normal.y, box_normal.z]),
        })).collect::<Vec<_>>(),
    });
    let tmp = std::env::temp_dir().join(format!("drops_vs_mujoco_{}", std::process::id()));
    std::fs::create_dir_all(&tmp)?;
    let script = root.join("experiments/shared/mujoco_drops.py");
    // One round of MuJoCo (one process, one thread): its timed drops, and in the first round the
    // larger sample for the statistics.
    let run_mujoco = |round: usize| -> anyhow::Result<MjOut> {
        let mut input = input.clone();
        input["sample_drops"] = serde_json::json!(if round == 0 { n * SAMPLE_FACTOR } else { n });
        let (in_path, out_path) = (tmp.join("in.json"), tmp.join("out.json"));
        std::fs::write(&in_path, serde_json::to_string(&input)?)?;
        let status = Command::new(&python)
            .arg(&script)
            .arg(&in_path)
            .arg(&out_path)
            .env("OMP_NUM_THREADS", "1")
            .env("OPENBLAS_NUM_THREADS", "1")
            .env("MKL_NUM_THREADS", "1")
            .status()?;
        anyhow::ensure!(status.success(), "{} failed ({status})", script.display());
        let mj: MjOut = serde_json::from_str(&std::fs::read_to_string(&out_path)?)?;
        anyhow::ensure!(mj.bodies.len() == bodies.len(), "MuJoCo returned {} bodies", mj.bodies.len());
        Ok(mj)
    };
    // REPEATS rounds, each MuJoCo's drops and then every mode of the project, so that both engines
    // are timed under the same load of this shared machine; the fastest round counts for each.
    let mut mj_rounds: Vec<MjOut> = Vec::new();
    let mut best: Vec<Vec<Option<Run>>> = (0..bodies.len()).map(|_| (0..MODES.len()).map(|_| None).collect()).collect();
    for round in 0..REPEATS {
        eprintln!("round {} of {REPEATS}: MuJoCo ({python} {}), then the project", round + 1, script.display());
        mj_rounds.push(run_mujoco(round)?);
        for (b, ((name, _), stone)) in bodies.iter().zip(&stones).enumerate() {
            for (k, m) in MODES.iter().enumerate() {
                let r = pool.install(|| timed(stone, &header(name, n, m), m.batch));
                eprintln!("  {name} {}: {:.1} drops/s", m.name, n as f64 / r.seconds);
                if best[b][k].as_ref().is_none_or(|x| r.seconds < x.seconds) {
                    best[b][k] = Some(r);
                }
            }
        }
    }
    std::fs::remove_dir_all(&tmp)?;
    let same_drops = |b: usize| {
        mj_rounds.iter().all(|r| {
            r.bodies[b]
                .drops
                .iter()
                .zip(&mj_rounds[0].bodies[b].drops)
                .all(|(x, y)| x.down == y.down && x.steps == y.steps)
        })
    };
    let same_rounds: Vec<bool> = (0..bodies.len()).map(same_drops).collect();
    let mj = &mj_rounds[0];

    let mut csv = String::from(
        "body,engine,mode,batch,certificate,dt,drops,cpu_seconds,drops_per_s,ratio_vs_mujoco_loop,\
         ratio_vs_mujoco_stepping,cpu_us_per_step,mean_sim_time_s,settled,certified,off_equilibrium,chi2_p_flocks_vs_mujoco,\
         kl_flocks_vs_static\n",
    );
    let mut table = String::new();
    let mut flock_tables = String::new();
    let mut bars: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let mut checks = String::new();
    let mut rapier_flat = None;
    let mut summaries: Vec<Summary> = Vec::new();
    let mut sample_tables = String::new();
    let mut box_pairs = String::new();
    for (b, (((name, _), stone), mb)) in bodies.iter().zip(&stones).zip(&mj.bodies).enumerate() {
        // MuJoCo's drops, classified by the project's rule; its fastest round.
        let (mj_report, outcomes) = classify(stone, name, &mb.drops);
        let fastest = |f: &dyn Fn(&MjBody) -> &[f64]| {
            mj_rounds.iter().flat_map(|r| f(&r.bodies[b]).iter().copied()).fold(f64::INFINITY, f64::min)
        };
        let (mj_loop, mj_step) = (fastest(&|x| &x.loop_cpu_s), fastest(&|x| &x.replay_cpu_s));
        let mj_rise = rise(&outcomes);
        if mb.flat_restitution.is_some() {
            rapier_flat = Some((rapier_flat_restitution(stone, &box_normal), mb.flat_restitution));
        }

        // The project's modes, their fastest round.
        let mut rows: Vec<Row> = Vec::new();
        for (m, r) in MODES.iter().zip(best[b].iter_mut()) {
            let r = r.take().expect("REPEATS ≥ 1");
            rows.push(Row {
                label: m.name.into(),
                rate: n as f64 / r.seconds,
                seconds: r.seconds,
                report: r.report,
                outcomes: r.outcomes,
                rise: r.rise,
            });
        }
        writeln!(
            checks,
            "* {name}: MuJoCo's compiled mesh has {} vertices ({} hull corners given), its support in 7 \
             directions within {:.1e} R_max of the corners'; the replays ended bit for bit where the loop did: \
             {}; every round gave the same drops: {}. How far off its stable facet a drop came to rest, h(final down) − R_F (the rise of G that \
             its tilt implies; 0 flat on the facet, counted on it up to {REST_TOLERANCE}): median {:.1e}, \
             largest {:.1e} R_max in MuJoCo; median {:.1e}, largest {:.1e} in the project's plain drops.",
            mb.mesh_vertices,
            stone.body.corners.len(),
            mb.placement_error,
            if mj_rounds.iter().all(|r| r.bodies[b].replay_identical) { "yes" } else { "**no**" },
            if same_rounds[b] { "yes" } else { "**no**" },
            mj_rise.0,
            mj_rise.1,
            rows[0].rise.0,
            rows[0].rise.1,
        )?;
        let nd = mb.drops.len() as f64;
        let counts = |r: &DropReport| -> Vec<u64> {
            (0..stone.flock_kinds.len()).map(|k| r.flocks.iter().find(|f| f.id == k).map_or(0, |f| f.count)).collect()
        };
        let mj_counts = counts(&mj_report);
        // The larger, untimed samples: the batched project (drop by drop the plain drops) and MuJoCo.
        let big = n * SAMPLE_FACTOR;
        let project_big = pool.install(|| timed(stone, &header(name, big, &MODES[1]), DEFAULT_BATCH)).report;
        let (mj_big, _) = classify(stone, name, &mb.sample_drops);
        let (pc, mc) = (counts(&project_big), counts(&mj_big));
        let (chi2_big, dof_big, p_big) = chi_square_homogeneity(&pc, &mc);
        let (na, nb) = (pc.iter().sum::<u64>() as f64, mc.iter().sum::<u64>() as f64);
        let contribution = |k: usize| {
            let col = (pc[k] + mc[k]) as f64;
            if col == 0.0 {
                return 0.0;
            }
            [(pc[k] as f64, na), (mc[k] as f64, nb)]
                .iter()
                .map(|&(o, row)| (o - row * col / (na + nb)).powi(2) / (row * col / (na + nb)))
                .sum::<f64>()
        };
        writeln!(
            sample_tables,
            "\n### {name}: {} project drops, {} MuJoCo drops; χ² = {chi2_big:.1} ({dof_big} dof), p = {p_big:.3}\n",
            project_big.drops, mj_big.drops
        )?;
        writeln!(
            sample_tables,
            "| flock | type | static | project | MuJoCo | share of χ² |\n|---|---|---|---|---|---|"
        )?;
        for f in &project_big.flocks {
            let g = mj_big.flocks.iter().find(|g| g.id == f.id);
            let cell = |x: Option<&rocking_stones::montecarlo::FlockRow>| {
                x.map_or("—".into(), |g| format!("{:.3} [{:.3}, {:.3}]", g.fraction, g.ci95.0, g.ci95.1))
            };
            writeln!(
                sample_tables,
                "| {} | {} | {:.3} | {} | {} | {:.0} % |",
                f.id,
                format!("{:?}", f.kind).to_lowercase(),
                f.static_probability,
                cell(Some(f)),
                cell(g),
                100.0 * contribution(f.id) / chi2_big.max(f64::MIN_POSITIVE)
            )?;
        }
        if mb.flat_restitution.is_some() {
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
                v
            };
            let (pp, mp, sp) = (pooled(&project_big, false), pooled(&mj_big, false), pooled(&project_big, true));
            box_pairs = format!(
                " By face pair, the box rests on its 0.8 × 0.5 ends, 1 × 0.5 sides and 1 × 0.8 faces with fractions \
                 {:.3} / {:.3} / {:.3} in the project and {:.3} / {:.3} / {:.3} in MuJoCo (static {:.3} / {:.3} / \
                 {:.3}).",
                pp[0], pp[1], pp[2], mp[0], mp[1], mp[2], sp[0], sp[1], sp[2]
            );
            // MuJoCo − project per face, the two faces of each pair side by side.
            let mut diffs = [Vec::new(), Vec::new(), Vec::new()];
            for f in &project_big.flocks {
                let m = mj_big.flocks.iter().find(|g| g.id == f.id).map_or(0.0, |g| g.fraction);
                diffs[axis_of(f.id)].push(format!("{:+.3}", m - f.fraction));
            }
            write!(
                box_pairs,
                " MuJoCo − project per face: ends {}, sides {}, faces {}.",
                diffs[0].join(" / "),
                diffs[1].join(" / "),
                diffs[2].join(" / ")
            )?;
            if p_big < 0.05 {
                box_pairs.push_str(
                    " The ball calibration of the restitution does not pin down how a box tumbles: its flat landing \
                     already rebounds differently in the two engines (above).",
                );
            }
        }
        let widest =
            (0..stone.flock_kinds.len()).max_by(|&a, &b| contribution(a).total_cmp(&contribution(b))).expect("a flock");
        let mut ratios = Vec::new();
        let (mut us_modes, mut p_modes) = (Vec::new(), Vec::new());
        for (m, r) in MODES.iter().zip(&rows) {
            let (rl, rs) = (r.rate / (nd / mj_loop), r.rate / (nd / mj_step));
            ratios.push((rl, rs));
            let (_, _, p) = chi_square_homogeneity(&counts(&r.report), &mj_counts);
            let us = 1e6 * r.seconds / (n as f64 * r.report.mean_time / r.report.params.dt);
            us_modes.push(us);
            p_modes.push(p);
            let flock_of = |o: &DropOutcome| {
                o.flock.map(|k| k as usize).or_else(|| o.facet.and_then(|f| stone.facet_flock[f as usize]))
            };
            let same = r.outcomes.iter().filter(|(i, o)| flock_of(o) == flock_of(&rows[0].outcomes[*i])).count();
            writeln!(
                table,
                "| {name} | project, {} | {:.1} | **{rl:.2}×** | {rs:.2}× | {us:.2} | {:.2} | {} | {} | {} | {same}/{n} | {p:.2} |",
                r.label, r.rate, r.report.mean_time, r.report.settled, r.report.certified, r.report.off_equilibrium
            )?;
            writeln!(
                csv,
                "\"{name}\",project,\"{}\",{},{},{:.6},{n},{:.4},{:.2},{rl:.4},{rs:.4},{us:.3},{:.4},{},{},{},{p:.4},{:.5}",
                r.label,
                m.batch,
                m.cert.name(),
                r.report.params.dt,
                r.seconds,
                r.rate,
                r.report.mean_time,
                r.report.settled,
                r.report.certified,
                r.report.off_equilibrium,
                r.report.fit_flocks.kl_divergence
            )?;
        }
        let mj_steps: u64 = mb.drops.iter().map(|d| d.steps).sum();
        for (label, secs) in [("mj_step loop + rest check (Python)", mj_loop), ("stepping alone (replay)", mj_step)] {
            let us = 1e6 * secs / mj_steps as f64;
            writeln!(
                table,
                "| {name} | MuJoCo, {label} | {:.1} | | | {us:.2} | {:.2} | {} | — | {} | | |",
                nd / secs,
                mj_report.mean_time,
                mj_report.settled,
                mj_report.off_equilibrium
            )?;
            writeln!(
                csv,
                "\"{name}\",mujoco,\"{label}\",1,none,{DT:.6},{},{secs:.4},{:.2},,,{us:.3},{:.4},{},0,{},,{:.5}",
                mb.drops.len(),
                nd / secs,
                mj_report.mean_time,
                mj_report.settled,
                mj_report.off_equilibrium,
                mj_report.fit_flocks.kl_divergence
            )?;
        }
        let short = ["stone", "pebble", "box"][bars.len()];
        bars.push((short.into(), ratios));
        let fraction = |r: &DropReport, k: usize| r.flocks.iter().find(|f| f.id == k).map_or(0.0, |f| f.fraction);
        summaries.push(Summary {
            short,
            us: us_modes,
            p: p_modes,
            mj_step_us: 1e6 * mj_step / mj_steps as f64,
            mj_loop_us: 1e6 * mj_loop / mj_steps as f64,
            t: rows.iter().map(|r| r.report.mean_time).collect(),
            mj_t: mj_report.mean_time,
            widest: (
                widest,
                format!("{:?}", stone.flock_kinds[widest]).to_lowercase(),
                fraction(&project_big, widest),
                fraction(&mj_big, widest),
            ),
            p_big,
        });

        writeln!(flock_tables, "\n### {name}\n")?;
        write!(flock_tables, "| flock | type | static |")?;
        for m in &MODES {
            write!(flock_tables, " {} |", m.name)?;
        }
        writeln!(flock_tables, " MuJoCo |\n|---|---|---|{}---|", "---|".repeat(MODES.len()))?;
        for f in &rows[0].report.flocks {
            write!(
                flock_tables,
                "| {} | {} | {:.3} |",
                f.id,
                format!("{:?}", f.kind).to_lowercase(),
                f.static_probability
            )?;
            for r in rows.iter().map(|r| &r.report).chain([&mj_report]) {
                let cell = r
                    .flocks
                    .iter()
                    .find(|g| g.id == f.id)
                    .map_or("—".into(), |g| format!("{:.3} [{:.3}, {:.3}]", g.fraction, g.ci95.0, g.ci95.1));
                write!(flock_tables, " {cell} |")?;
            }
            writeln!(flock_tables)?;
        }
        write!(flock_tables, "| KL vs static | | |")?;
        for r in rows.iter().map(|r| &r.report).chain([&mj_report]) {
            write!(flock_tables, " {:.4} |", r.fit_flocks.kl_divergence)?;
        }
        writeln!(flock_tables)?;
    }

    let parts = Parts { table, flock_tables, checks, sample_tables, box_pairs };
    let s = readme(n, mj, &parts, &bars, &summaries, rapier_flat)?;
    std::fs::write(out.join("README.md"), s)?;
    std::fs::write(out.join("speed.csv"), csv)?;
    plot(&out.join("ratio.png"), &bars).map_err(|e| anyhow::anyhow!("plot: {e}"))?;
    Ok(())
}

/// The parts of the README written while the bodies run: the speed table, the per-flock tables
/// and the checks.
struct Parts {
    table: String,
    flock_tables: String,
    checks: String,
    sample_tables: String,
    /// The box's fractions pooled by face pair.
    box_pairs: String,
}

fn readme(
    n: u64,
    mj: &MjOut,
    parts: &Parts,
    bars: &[(String, Vec<(f64, f64)>)],
    summaries: &[Summary],
    rapier_flat: Option<(f64, Option<[f64; 2]>)>,
) -> anyhow::Result<String> {
    let mut s = String::new();
    writeln!(s, "# Drops per second per core: this project against MuJoCo, same physics\n")?;
    writeln!(
        s,
        "Generated by `cargo run --release --example drops_vs_mujoco -- {n}` (MuJoCo {} from Python {}, numpy {}; \
         `experiments/shared/mujoco_drops.py`): {n} drops per body and mode, on **one core** — the project in a \
         one-thread rayon pool, timed by the CPU time of its worker thread; MuJoCo in one Python process, timed by \
         its process CPU time; the two run one after the other, never at the same time, in {REPEATS} rounds (each: \
         MuJoCo's drops, then every mode of the project, so that both see the same load of this shared machine), \
         and each side's fastest round is used. The *ratio* is the project's drops/s over MuJoCo's for the same \
         body. The per-flock statistics are compared on the timed drops and on larger untimed samples \
         ({SAMPLE_FACTOR} × {n} drops per engine and body).\n",
        mj.mujoco_version, mj.python_version, mj.numpy_version
    )?;
    writeln!(s, "## The physics matched\n")?;
    writeln!(s, "| | project (rapier3d 0.36) | MuJoCo {} |", mj.mujoco_version)?;
    writeln!(s, "|---|---|---|")?;
    writeln!(
        s,
        "| frame | scaled: R_max = 1 m, mass 1, g = 9.81 m/s² | the same |\n\
         | body | the hull corners relative to G (`Stone::body.corners`), the project's collider | a mesh geom on the \
         same corners (MuJoCo collides with their convex hull), rotated into the principal axes of the inertia \
         tensor; the final down direction is rotated back |\n\
         | mass, inertia | 1, `Stone::body.inertia` | `<inertial pos=\"0 0 0\" mass=\"1\" fullinertia=…/>`, the same \
         tensor (diagonal in the principal frame) |\n\
         | release | from rest, lowest point {HEIGHT} R_max above the plane, Haar-uniform orientation (the \
         project's stream, seed {SEED}) | the same, orientations from numpy's `default_rng(seed + body)` (the \
         statistics are compared, not drop by drop) |\n\
         | friction | Coulomb μ = {FRICTION} (rapier, circular cone) | condim 3 (sliding only), μ = {FRICTION} on \
         both geoms, **{} cone** (MuJoCo's default is pyramidal) |\n\
         | restitution | e = {RESTITUTION} (rapier's restitution coefficient) | MuJoCo has none: solref = \
         ({}, {:.4}) (time constant, damping ratio), the default time constant and the damping ratio found by \
         bisection so that a ball (radius 1 = R_max, mass 1) dropped {HEIGHT} R_max onto the plane rebounds to \
         e² of its drop height: **measured e = {:.3}** (by rebound speed over impact speed at the steps where the \
         contact starts and stops: {:.3}); solimp = {:?} (default) |\n\
         | rolling / torsional friction | off (`rolling_resistance = 0`, `torsional_friction = 0`) | none (condim 3) |\n\
         | global damping | {LINEAR_DAMPING} s⁻¹ linear, {ANGULAR_DAMPING} s⁻¹ angular: v ← v / (1 + dt c) each step \
         | dof_damping on the free joint: {LINEAR_DAMPING}·m on the translations and {ANGULAR_DAMPING}·I_i on the \
         principal rotations (the torque −c I ω), treated implicitly by the integrator, which is the same \
         v ← v / (1 + dt c) |\n\
         | numerics | dt = 1/240 s, 4 solver iterations (`--fast`: dt 1/120 s) | opt.timestep = 1/240 s, \
         **{}** integrator (MuJoCo's default is {}), {} solver ({} iterations, tolerance {:e}), one thread |\n\
         | rest | linear speed < 2·10⁻³ m/s and angular speed < 5·10⁻³ rad/s for 0.25 s of consecutive steps, \
         cap 60 s | the same rule on qvel, checked after every step |\n\
         | outcome | `Stone::rest` of the final down direction (the certificate's flock when it decides) | the \
         final down direction returned, `Stone::rest` applied here |\n",
        mj.cone,
        mj.solref[0],
        mj.solref[1],
        mj.ball_restitution,
        mj.ball_restitution_speeds,
        mj.solimp,
        mj.integrator,
        mj.default_integrator.trim_start_matches("mjINT_").to_lowercase(),
        mj.solver.trim_start_matches("mjSOL_").to_lowercase(),
        mj.iterations,
        mj.tolerance
    )?;
    if let Some((rapier_e, Some([mj_e, mj_e_speeds]))) = rapier_flat {
        writeln!(
            s,
            "Check of the restitution on a body: the box dropped flat on its 1 × 0.8 face from {HEIGHT} R_max (no \
             damping) rebounds with e = {rapier_e:.3} in rapier and {mj_e:.3} in MuJoCo (by speeds {mj_e_speeds:.3}).\n"
        )?;
    }
    writeln!(s, "**MuJoCo timing.** *mj_step loop + rest check*: per drop, a Python loop of `mujoco.mj_step(m, d)` and the rest test on `d.qvel` (what the project's run loop does in Rust); *stepping alone*: the same drops replayed as one `mj_step(m, d, nstep=steps)` call each (MuJoCo is deterministic: the replay ends bit for bit where the loop did), i.e. MuJoCo's C stepping without the interpreter — a lower bound of what a C program driving MuJoCo would spend. The ratio in bold is against the loop, the second against stepping alone.\n")?;
    writeln!(s, "## Drops per second per core\n")?;
    writeln!(
        s,
        "| body | engine, mode | drops/s | ratio vs MuJoCo loop | ratio vs MuJoCo stepping alone | CPU µs per step | mean simulated s per drop | settled | certified | off its facet | same flock as plain | χ² p vs MuJoCo (flocks) |"
    )?;
    writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|")?;
    s.push_str(&parts.table);
    writeln!(
        s,
        "\n*off its facet*: settled with G more than {REST_TOLERANCE} R_max above its stable facet's rest (stopped on \
         a slope or an edge). *χ² p*: Pearson's test of homogeneity of the per-flock counts of that mode against \
         MuJoCo's (`stats::chi_square_homogeneity`).\n"
    )?;
    writeln!(s, "![ratio](ratio.png)\n")?;
    writeln!(s, "## Reading\n")?;
    let each = |f: &dyn Fn(&Summary) -> String| summaries.iter().map(f).collect::<Vec<_>>().join(", ");
    let range = |k: usize, stepping: bool| {
        let v: Vec<f64> = bars.iter().map(|(_, r)| if stepping { r[k].1 } else { r[k].0 }).collect();
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(0.0, f64::max);
        format!("{lo:.1}–{hi:.1}×")
    };
    for (k, m) in MODES.iter().enumerate() {
        let list: Vec<String> = bars.iter().map(|(b, v)| format!("{b} {:.2}× ({:.2}×)", v[k].0, v[k].1)).collect();
        writeln!(s, "* **{}** against MuJoCo's loop (against its stepping alone): {}.", m.name, list.join(", "))?;
    }
    writeln!(
        s,
        "\n**Engine against engine, the two physics engines cost about the same per step.** The plain rows \
         ({} of MuJoCo's loop, {} of its stepping alone) split into a cost per simulated step — \
         {} µs in the project against {} µs of MuJoCo stepping alone ({} µs with the Python loop) — and \
         the simulated time a drop takes to come to rest, longer in MuJoCo ({} s against {} s; the rest rule \
         and the damping are the same, so the difference is in how the two contacts dissipate). \
         The Python loop adds {} % to MuJoCo's stepping.\n",
        range(0, false),
        range(0, true),
        each(&|x| format!("{} {:.2}", x.short, x.us[0])),
        each(&|x| format!("{:.2}", x.mj_step_us)),
        each(&|x| format!("{:.2}", x.mj_loop_us)),
        each(&|x| format!("{} {:.2}", x.short, x.mj_t)),
        each(&|x| format!("{:.2}", x.t[0])),
        each(&|x| format!("{:.0}", 100.0 * (x.mj_loop_us / x.mj_step_us - 1.0))),
    )?;
    writeln!(
        s,
        "**The large ratios are the project's algorithms, not a faster engine.** Batching ({} per step, \
         against plain's {}) shares a rapier world's fixed cost per step between {DEFAULT_BATCH} stones; the \
         flock certificate ends a drop once its flock is certain, after {} simulated s instead of {}; \
         `--fast` takes twice the step. Exact landings and sub-stepped impacts (the default numerics) cost \
         little here: only a step in which some hull corner could come down by more than its clearance plus \
         0.01 R_max is cut, in a world of the stone's own, outside the batch (`dynamics::impact`). None of this \
         is specific to rapier: the certificate needs only the \
         body's energy and down direction, which MuJoCo has too; MuJoCo can put many bodies in one model; and \
         MuJoCo at dt 1/120 s was not measured here. So {} (flock-certified + batched) and {} (`--fast`) are \
         what this project's drop pipeline gains over a plain MuJoCo loop (outcome statistics compared below), \
         not a property of the engines.\n",
        each(&|x| format!("{} {:.2} µs", x.short, x.us[1])),
        each(&|x| format!("{:.2}", x.us[0])),
        each(&|x| format!("{} {:.2}", x.short, x.t[2])),
        each(&|x| format!("{:.2}", x.t[0])),
        range(2, false),
        range(3, false),
    )?;
    let worst = summaries
        .iter()
        .flat_map(|x| x.p.iter().map(move |&p| (p, x.short)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .expect("a body");
    writeln!(
        s,
        "**Outcome statistics.** In the timed runs ({n} drops per engine), χ² p of the per-flock counts \
         against MuJoCo's, plain / batched / flock-certified + batched / `--fast`: {}; the lowest is {:.2} \
         ({}). The batched and flock-certified drops end in the plain drop's flock drop by drop (the *same \
         flock as plain* column), so they share plain's p; `--fast` integrates differently and is a sample \
         of its own. Each engine draws its own orientations, and at {n} drops a flock of a few per cent has a \
         95 % interval about as wide as its share, so the sharper test is the larger untimed samples \
         ({SAMPLE_FACTOR} × {n} drops per engine, the project's batched drops against MuJoCo's, \
         [below](#larger-samples-untimed)): p = {}. {} The flock with the largest share of χ² there: {}.\n",
        each(&|x| format!("{} {}", x.short, x.p.iter().map(|p| format!("{p:.2}")).collect::<Vec<_>>().join(" / "))),
        worst.0,
        worst.1,
        each(&|x| format!("{} {:.3}", x.short, x.p_big)),
        {
            let differ: Vec<&str> = summaries.iter().filter(|x| x.p_big < 0.05).map(|x| x.short).collect();
            if differ.is_empty() {
                "No p below 0.05: the two engines' per-flock statistics agree within what these samples can \
                 resolve."
                    .to_string()
            } else {
                format!(
                    "Below 0.05 for the {}: there the two engines' per-flock statistics differ by more than \
                     sampling.",
                    differ.join(" and ")
                )
            }
        },
        each(&|x| format!(
            "{} flock {} ({}), project {:.3} against MuJoCo {:.3}",
            x.short, x.widest.0, x.widest.1, x.widest.2, x.widest.3
        )),
    )?;
    if !parts.box_pairs.is_empty() {
        s.truncate(s.trim_end().len());
        writeln!(s, "{}\n", parts.box_pairs)?;
    }
    s.push_str(DIFFERENCES);
    writeln!(s, "\n## Checks\n")?;
    s.push_str(&parts.checks);
    writeln!(
        s,
        "\n## Larger samples (untimed)\n\n{SAMPLE_FACTOR} × {n} drops per engine and body, the first {n} the timed ones: \
         the project's batched drops (drop by drop its plain drops) and MuJoCo's, per flock (fraction of settled \
         drops, 95 % interval; static = quasi-static basin probability), with each flock's share of the χ² \
         statistic of homogeneity."
    )?;
    s.push_str(&parts.sample_tables);
    writeln!(s, "\n## Per flock, timed runs (fraction of settled drops, 95 % interval; static = quasi-static basin probability)")?;
    s.push_str(&parts.flock_tables);
    Ok(s)
}

fn plot(path: &Path, bars: &[(String, Vec<(f64, f64)>)]) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    init_fonts();
    let root = BitMapBackend::new(path, (1100, 640)).into_drawing_area();
    root.fill(&WHITE)?;
    let values = || bars.iter().flat_map(|(_, v)| v.iter().flat_map(|r| [r.0, r.1]));
    // Log axis: a ratio and its inverse are as far from 1×; room above the bars for the legend.
    let bottom = values().fold(0.5, f64::min) * 0.8;
    let top = values().fold(10.0, f64::max) * 7.0;
    let mut chart = ChartBuilder::on(&root)
        .margin(20)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .caption("Drops per core: this project ÷ MuJoCo, same physics, one core", (FONT_FAMILY, 20))
        .build_cartesian_2d(-0.5f64..bars.len() as f64 - 0.5, (bottom..top).log_scale())?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(bars.len() + 1)
        .x_label_formatter(&|x| {
            let k = x.round();
            if (x - k).abs() > 1e-6 || k < 0.0 {
                return String::new();
            }
            bars.get(k as usize).map_or(String::new(), |b| match b.0.as_str() {
                "stone" => "bundled stone (581 hull vertices)".into(),
                "pebble" => "synthetic pebble (500 hull vertices)".into(),
                other => format!("{other} 1 × 0.8 × 0.5"),
            })
        })
        .y_label_formatter(&|y| format!("{y}×"))
        .y_desc("drops/s of the project ÷ drops/s of MuJoCo (log scale)")
        .label_style((FONT_FAMILY, 14))
        .draw()?;
    let w = 0.84 / MODES.len() as f64;
    let x0 = |k: usize, slot: usize| k as f64 - 0.42 + slot as f64 * w;
    for (slot, m) in MODES.iter().enumerate() {
        let colour = series_color(slot);
        chart
            .draw_series(bars.iter().enumerate().map(|(k, (_, v))| {
                Rectangle::new([(x0(k, slot), bottom), (x0(k, slot) + w * 0.9, v[slot].0)], colour.filled())
            }))?
            .label(format!("{} (vs MuJoCo's mj_step loop + rest check)", m.short))
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 14, y + 5)], colour.filled()));
    }
    // The ratio against MuJoCo's loop, written above each bar.
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let label = TextStyle::from((FONT_FAMILY, 12).into_font()).pos(Pos::new(HPos::Center, VPos::Bottom));
    chart.draw_series(bars.iter().enumerate().flat_map(|(k, (_, v))| {
        let label = label.clone();
        (0..MODES.len()).map(move |slot| {
            let top = v[slot].0.max(v[slot].1) * 1.04;
            Text::new(format!("{:.1}×", v[slot].0), (x0(k, slot) + w * 0.45, top), label.clone())
        })
    }))?;
    chart
        .draw_series(bars.iter().enumerate().flat_map(|(k, (_, v))| {
            (0..MODES.len()).map(move |slot| {
                PathElement::new(
                    vec![(x0(k, slot), v[slot].1), (x0(k, slot) + w * 0.9, v[slot].1)],
                    BLACK.stroke_width(3),
                )
            })
        }))?
        .label("the same mode vs MuJoCo's stepping alone (no Python per step)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], BLACK.stroke_width(3)));
    for (level, label) in [(1.0, "1×: as fast as MuJoCo"), (10.0, "10×")] {
        let style = if level == 1.0 { BLACK.stroke_width(2) } else { RGBColor(110, 110, 110).stroke_width(2) };
        chart
            .draw_series(DashedLineSeries::new(vec![(-0.5, level), (bars.len() as f64 - 0.5, level)], 10, 6, style))?
            .label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], style));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font((FONT_FAMILY, 13))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
