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
use rocking_stones::dynamics::certificate::{certificate, CertificateMode};
use rocking_stones::dynamics::drops::launch::launch;
use rocking_stones::dynamics::drops::launch::DropOutcome;
use rocking_stones::dynamics::drops::montecarlo::{
    run_drops_batched, summarize, DropReport, FlockRow, RunHeader, Shard, DEFAULT_BATCH, FORMAT,
};
use rocking_stones::dynamics::drops::params::{DropParams, Preset};
use rocking_stones::dynamics::engine::params::REFERENCE_DT;
use rocking_stones::dynamics::engine::simulation::Simulation;
use rocking_stones::dynamics::stone::{Stone, REST_TOLERANCE};
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::plot::{series_color, FONT_FAMILY};
use rocking_stones::rng::item_rng;
use rocking_stones::stats::stuart_maxwell;
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
const SEED: u64 = 7;
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

/// What differs between the two engines, for the README.
const DIFFERENCES: &str = "
**What differs (and is not matched).**

* **Contact.** Both contacts are soft, differently. Rapier's is a velocity-level constraint that
  applies the restitution coefficient at impact, with a soft position correction (springs of 30–60 Hz,
  `dynamics::engine::contact`); MuJoCo's is a spring-damper reference acceleration (time constant 0.02 s, the
  `solimp` impedance) whose under-damping *is* the restitution, calibrated at 1/240 s and kept at
  1/120 s, where the same damping ratio gives another restitution (above). Matched on a ball at
  1/240 s (e = 0.2 by rebound height), they agree on the box landing flat at that step (above); the
  edge and corner impacts of a tumbling stone are not calibrated at all. On the same releases the
  outcomes of the box and the pebble are statistically the same in both engines, drop by drop; the
  stone's rarest flock (a saddle flock, about 1 % of the drops) is where the two differ most (Outcome
  statistics, and the solver sub-steps section below).
* **Friction.** Rapier 0.36's default friction model (`FrictionModel::Simplified`) solves one Coulomb
  constraint (circular cone) per contact patch at its friction centre plus one *twist* constraint with the
  contact points' lever arms; MuJoCo with condim 3 has an elliptic-cone Coulomb constraint at each contact
  point. Both resist the twist of a multi-point patch; neither has rolling resistance or torsional
  friction at a single point (the project's own rolling and torsional laws are switched off here).
* **Numerics.** Rapier: f32, 4 solver iterations. MuJoCo: f64, a Newton solver run to its tolerance
  (up to 100 iterations), the implicitfast integrator (damping implicit, Coriolis forces explicit).
* **Collision.** The project's own hull collider in rapier's pipeline against MuJoCo's convex mesh–plane
  collision on the same corners (same support function, checked above).
* **Drops.** The same releases in both engines (the project's seeded stream, passed to MuJoCo): the
  drops are compared one by one, not only their statistics. When each engine drew its own (before),
  numpy's stream for the box put 0.300 of its 3000 releases in the quasi-static basins of the 1 × 0.5
  sides, whose area is 0.272 (3.4 standard deviations of such a sample), and that alone made the
  box's statistics look different from the project's (p = 0.012). Classifying a drop (`Stone::rest`, one descent
  of the support function) is inside the project's timing and outside MuJoCo's (done here afterwards).
* **Timing.** Two different clocks of the same machine: the CPU time of the project's one worker thread
  and the CPU time of the Python process (one thread for MuJoCo; numpy's threads are limited to one).
  CPU times on this shared machine move by ± 15 % from run to run (`results/drops_certificate/`), and
  by more while other jobs run; the rounds (above) time both engines under the same load.
";

/// A mode of the project: stones per world, certificate, and the step it runs.
#[derive(Clone)]
struct Mode {
    name: String,
    short: String,
    batch: usize,
    cert: CertificateMode,
    /// Time step (s, scaled): [`REFERENCE_DT`] for the reference modes, the preset's default step
    /// for the default numerics.
    dt: f64,
}

/// The project's modes: three at the reference step (MuJoCo's step of the benchmark protocol) and
/// the default numerics (flock-certified + batched at [`Preset::largest_stable_dt`]).
fn modes() -> [Mode; 4] {
    let mode =
        |name: &str, short: &str, batch, cert, dt| Mode { name: name.into(), short: short.into(), batch, cert, dt };
    let d = step_label(fast_dt());
    [
        mode("plain", "plain", 1, CertificateMode::None, REFERENCE_DT),
        mode("batched", "batched", DEFAULT_BATCH, CertificateMode::None, REFERENCE_DT),
        mode("flock-certified + batched", "flock-cert. + batched", DEFAULT_BATCH, CertificateMode::Flock, REFERENCE_DT),
        mode(
            &format!("flock-certified + batched, default numerics (dt {d})"),
            &format!("flock-cert. + batched, default numerics (dt {d})"),
            DEFAULT_BATCH,
            CertificateMode::Flock,
            fast_dt(),
        ),
    ]
}

/// The project's parameters of mode `m`: the `drop` preset on steel on wood (its numerics:
/// exact landings and sub-stepped impacts, which damp the free flight exactly), with the matched
/// physics overriding it, no rolling resistance or torsional friction (MuJoCo's condim 3 has
/// neither), at the mode's step.
fn params(m: &Mode) -> DropParams {
    let mut p = Preset::Drop.params(Surface::SteelOnWood);
    p.launch.height = HEIGHT;
    p.sim.contact.friction = FRICTION;
    p.sim.contact.restitution = RESTITUTION;
    p.sim.contact.linear_damping = LINEAR_DAMPING;
    p.sim.contact.angular_damping = ANGULAR_DAMPING;
    p.sim.contact.rolling_resistance = 0.0;
    p.sim.contact.torsional_friction = 0.0;
    p.sim.numerics.dt = m.dt;
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
    let out = run_drops_batched(stone, h, Shard::ALL, &BTreeMap::new(), cert.as_ref(), batch, &sink);
    let seconds = thread_cpu_seconds() - t;
    let outcomes: BTreeMap<u64, DropOutcome> = out.into_iter().map(|o| (o.index, o)).collect();
    Run { report: summarize(&stone.model(), h, &outcomes), rise: rise(&outcomes), outcomes, seconds }
}

/// The untimed convergence check of one body: its `drops` releases in mode `m` at each of
/// [`SUBSTEPS`] solver iterations, compared drop by drop with MuJoCo's outcomes `mj` and with
/// the finest; a markdown table.
fn substep_table(
    stone: &Stone,
    name: &str,
    drops: u64,
    m: &Mode,
    pool: &rayon::ThreadPool,
    mj: &BTreeMap<u64, DropOutcome>,
) -> anyhow::Result<String> {
    let runs: Vec<Run> = SUBSTEPS
        .iter()
        .map(|&k| {
            let mut h = header(name, drops, m);
            h.params.sim.numerics.solver_iterations = k;
            eprintln!("  {name}: {k} solver iterations (untimed)");
            pool.install(|| timed(stone, &h, m.batch))
        })
        .collect();
    let finest = &runs[runs.len() - 1];
    let kinds = stone.flock_kinds.len();
    let shown: Vec<usize> =
        (0..kinds).filter(|&k| finest.report.flocks.iter().any(|f| f.id == k && f.count > 0)).collect();
    let mut t = format!("\n### {name}\n\n| solver iterations | drops/s | same flock as MuJoCo | p vs MuJoCo | same flock as {} | p vs {} |", SUBSTEPS[SUBSTEPS.len() - 1], SUBSTEPS[SUBSTEPS.len() - 1]);
    for k in &shown {
        write!(t, " flock {k} |")?;
    }
    writeln!(t, "\n|{}", "---|".repeat(6 + shown.len()))?;
    let mj_counts = {
        let mut c = vec![0u64; kinds];
        for o in mj.values().filter(|o| o.settled) {
            if let Some(k) = flock_of(stone, o) {
                c[k] += 1;
            }
        }
        c
    };
    // Each run against MuJoCo and against the finest, once: the table and the reading use them.
    let vs: Vec<(Chi, Chi)> = runs
        .iter()
        .map(|r| (drop_by_drop(stone, &r.outcomes, mj), drop_by_drop(stone, &r.outcomes, &finest.outcomes)))
        .collect();
    for ((k, r), &(a, b)) in SUBSTEPS.iter().zip(&runs).zip(&vs) {
        write!(
            t,
            "| {k} | {:.0} | {} of {} | {:.3} | {} of {} | {:.3} |",
            drops as f64 / r.seconds,
            a.same,
            a.both,
            a.p,
            b.same,
            b.both,
            b.p
        )?;
        for &f in &shown {
            write!(t, " {:.4} |", r.report.flocks.iter().find(|g| g.id == f).map_or(0.0, |g| g.fraction))?;
        }
        writeln!(t)?;
    }
    let settled: u64 = mj_counts.iter().sum();
    write!(t, "| MuJoCo {} | | | | | |", step_label(REFERENCE_DT))?;
    for &f in &shown {
        write!(t, " {:.4} |", mj_counts[f] as f64 / settled.max(1) as f64)?;
    }
    writeln!(t)?;
    // Reading: is the default converged, and from how many sub-steps on are the statistics those
    // of the finest?
    let p_finest: Vec<f64> = vs.iter().map(|v| v.1.p).collect();
    let p_mj: Vec<f64> = vs.iter().map(|v| v.0.p).collect();
    let default = SUBSTEPS.iter().position(|&k| k == 4).expect("the default is in SUBSTEPS");
    let converged = (0..SUBSTEPS.len() - 1).find(|&i| p_finest[i..SUBSTEPS.len() - 1].iter().all(|&p| p >= 0.05));
    let agree: Vec<String> =
        SUBSTEPS.iter().zip(&p_mj).filter(|(_, &p)| p >= 0.05).map(|(k, _)| k.to_string()).collect();
    writeln!(
        t,
        "\nAt the default 4 iterations the per-flock statistics {} those at {} (p = {:.3}); {}. Against MuJoCo, p ≥ \
         0.05 at {}.",
        if p_finest[default] >= 0.05 { "are" } else { "are **not**" },
        SUBSTEPS[SUBSTEPS.len() - 1],
        p_finest[default],
        match converged {
            Some(i) =>
                format!("from {} iterations on every p against {} is ≥ 0.05", SUBSTEPS[i], SUBSTEPS[SUBSTEPS.len() - 1]),
            None => "no coarser count reaches them".into(),
        },
        if agree.is_empty() { "no iteration count".into() } else { format!("{} iterations", agree.join(", ")) },
    )?;
    Ok(t)
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
fn classify(stone: &Stone, name: &str, drops: &[MjDrop], dt: f64) -> (DropReport, BTreeMap<u64, DropOutcome>) {
    let outcomes: BTreeMap<u64, DropOutcome> = drops
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let down = Vec3::new(d.down[0], d.down[1], d.down[2]);
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
            (i as u64, o)
        })
        .collect();
    let mode = Mode { dt, ..modes()[0].clone() };
    (summarize(&stone.model(), &header(name, drops.len() as u64, &mode), &outcomes), outcomes)
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

/// Restitution of a flat landing in rapier (the project's world and contact, no damping) at step
/// `dt`: the body dropped from rest with its facet of outward normal `normal` (body frame) facing
/// down, `HEIGHT` above the ground; e = √(rebound height / drop height) of G above its height at
/// rest on the facet, as the Python side measures MuJoCo's. The rebound is found by the velocity
/// (from the step where G first moves up to the step where it moves down again), not by the
/// contact impulse, which a sub-stepped impact (`dynamics::engine::impact`) leaves at zero after the step.
fn rapier_flat_restitution(stone: &Stone, normal: &Vec3, dt: f64) -> f64 {
    let mut p = params(&Mode { dt, ..modes()[0].clone() });
    p.sim.contact.linear_damping = 0.0;
    p.sim.contact.angular_damping = 0.0;
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

/// Each category's share of Pearson's χ² statistic of homogeneity of the counts `a` and `b`.
fn chi_shares(a: &[u64], b: &[u64]) -> Vec<f64> {
    let (na, nb) = (a.iter().sum::<u64>() as f64, b.iter().sum::<u64>() as f64);
    a.iter()
        .zip(b)
        .map(|(&x, &y)| {
            let col = (x + y) as f64;
            if col == 0.0 {
                return 0.0;
            }
            [(x as f64, na), (y as f64, nb)]
                .iter()
                .map(|&(o, row)| (o - row * col / (na + nb)).powi(2) / (row * col / (na + nb)))
                .sum::<f64>()
        })
        .collect()
}

/// Two runs of the same releases compared drop by drop: the Stuart–Maxwell test of marginal
/// homogeneity of their per-flock counts (`stats::stuart_maxwell`, which uses the pairing), and
/// how many of the drops settled in both end in the same flock.
#[derive(Clone, Copy)]
struct Chi {
    chi2: f64,
    dof: usize,
    p: f64,
    same: usize,
    both: usize,
}

/// The flock a drop ended in (the certificate's, or that of its rest facet).
fn flock_of(stone: &Stone, o: &DropOutcome) -> Option<usize> {
    o.flock.map(|k| k as usize).or_else(|| o.facet.and_then(|f| stone.facet_flock[f as usize]))
}

/// [`Chi`] of the runs `a` and `b` (outcomes by drop index) on the drops settled in both.
fn drop_by_drop(stone: &Stone, a: &BTreeMap<u64, DropOutcome>, b: &BTreeMap<u64, DropOutcome>) -> Chi {
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

/// MuJoCo at one step, for one body.
struct MjSide {
    dt: f64,
    report: DropReport,
    outcomes: BTreeMap<u64, DropOutcome>,
    /// Fastest round: CPU s of the loop and of the stepping alone.
    loop_s: f64,
    step_s: f64,
    steps: u64,
    big: DropReport,
    big_outcomes: BTreeMap<u64, DropOutcome>,
    /// Drops with a MuJoCo warning, in the larger sample (which holds the timed drops).
    warned: usize,
}

/// What the reading of the README needs of one body and one MuJoCo step.
struct MjSummary {
    step_us: f64,
    loop_us: f64,
    loop_rate: f64,
    step_rate: f64,
    t: f64,
    unsettled: u64,
    big_unsettled: u64,
    big_drops: u64,
    warned: usize,
}

/// The flock with the largest share of χ² between two samples: id, type, the fraction there in
/// the first and in the second.
type Widest = (usize, String, f64, f64);

/// What the reading of the README needs of one body.
struct Summary {
    short: &'static str,
    /// CPU µs per simulated step of each mode.
    us: Vec<f64>,
    /// Paired p (Stuart–Maxwell, timed drops) of each mode's per-flock counts against MuJoCo's at
    /// 1/240 s.
    p: Vec<f64>,
    /// Drops of each mode that ended in the flock of the same plain drop.
    same_flock: Vec<usize>,
    /// Mean simulated s per drop of each mode.
    t: Vec<f64>,
    /// MuJoCo at each of [`mj_dts`].
    mj: Vec<MjSummary>,
    /// Paired p, timed drops: the default numerics against MuJoCo at the same step; MuJoCo at the
    /// default step against MuJoCo at the reference step.
    p_fast_same: f64,
    p_mj_steps: f64,
    /// Larger samples: the reference project (batched) against MuJoCo at the reference step, and
    /// the flock with the largest share of χ² there.
    big_ref: Chi,
    widest: Widest,
    /// Larger samples: MuJoCo at the default step against MuJoCo at the reference step.
    big_mj_steps: Chi,
    widest_mj_steps: Widest,
    /// Larger samples: the default numerics against MuJoCo at the same step, against MuJoCo at the
    /// reference step, against the project at the reference step.
    big_fast_same: Chi,
    /// The flock with the largest share of χ² between the default numerics and MuJoCo at the
    /// same step (larger samples).
    widest_fast_same: Widest,
    big_fast_ref: Chi,
    big_project_steps: Chi,
    /// Larger samples' unsettled drops: the project's reference (batched) and default numerics.
    big_unsettled: (u64, u64),
    /// Larger samples, paired by their orientations: drops that end in the same flock at both
    /// steps, in MuJoCo and in the project, of this many.
    same_big: (usize, usize, u64),
    /// The untimed check of MuJoCo at the longer step with the damping ratio calibrated there:
    /// drops, drops not at rest at the cap, drops with a warning, mean simulated s per drop.
    recal: (u64, u64, usize, f64),
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
    let modes = modes();
    let python = python_with_mujoco();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let out = root.join("results/drops_vs_mujoco");
    std::fs::create_dir_all(&out)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let bodies = benchmark_bodies(&root, true)?;
    let stones: Vec<Stone> =
        bodies.iter().map(|(_, a)| Stone::new(a, a.macro_nu(&Options::default()).0)).collect::<Result<_, _>>()?;
    let box_normal = -Vec3::z();

    // MuJoCo first (one process per step, one thread): the bodies as the project has them.
    let reference = params(&modes[0]);
    let input = serde_json::json!({
        "drops": n,
        "sample_drops": n * SAMPLE_FACTOR,
        "orientations": (0..n * SAMPLE_FACTOR)
            .map(|i| {
                let q = launch(&mut item_rng(SEED, i), &reference).orientation;
                [q.w, q.i, q.j, q.k]
            })
            .collect::<Vec<_>>(),
        "repeats": 1,
        "height": reference.launch.height,
        "friction": reference.sim.contact.friction,
        "restitution": reference.sim.contact.restitution,
        "linear_damping": reference.sim.contact.linear_damping,
        "angular_damping": reference.sim.contact.angular_damping,
        "dt": reference.sim.numerics.dt,
        "max_time": reference.sim.numerics.max_time,
        "rest_linear_speed": reference.sim.rest.rest_linear_speed,
        "rest_angular_speed": reference.sim.rest.rest_angular_speed,
        "rest_time": reference.sim.rest.rest_time,
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
    // One run of MuJoCo at step `dt` (one process, one thread): `n` timed drops and a sample of
    // `sample` drops (the timed ones first), with `solref` when given, else the damping ratio
    // calibrated on the ball at this step.
    let run_mujoco = |sample: u64, dt: f64, solref: Option<[f64; 2]>| -> anyhow::Result<MjOut> {
        let mut input = input.clone();
        input["sample_drops"] = serde_json::json!(sample);
        input["dt"] = serde_json::json!(dt);
        input["solref"] = serde_json::json!(solref);
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
    // REPEATS rounds, each MuJoCo's drops at both steps and then every mode of the project, so
    // that both engines are timed under the same load of this shared machine; the fastest round
    // counts for each. MuJoCo at the longer step is the model of the reference step (its solref,
    // calibrated there) with only the step changed, as the project keeps its parameters at its
    // longer step; in the first round, an untimed check runs MuJoCo at the longer step with the
    // damping ratio calibrated again at that step (`recalibrated`).
    let mut mj_rounds: Vec<Vec<MjOut>> = Vec::new();
    let mut recalibrated: Option<MjOut> = None;
    let mut best: Vec<Vec<Option<Run>>> = (0..bodies.len()).map(|_| (0..modes.len()).map(|_| None).collect()).collect();
    for round in 0..REPEATS {
        let sample = if round == 0 { n * SAMPLE_FACTOR } else { n };
        let mut this: Vec<MjOut> = Vec::new();
        for dt in mj_dts() {
            eprintln!(
                "round {} of {REPEATS}: MuJoCo at dt {} ({python} {})",
                round + 1,
                step_label(dt),
                script.display()
            );
            let solref = this.first().map(|r| r.solref);
            this.push(run_mujoco(sample, dt, solref)?);
        }
        if round == 0 {
            eprintln!(
                "round 1 of {REPEATS}: MuJoCo at dt {}, damping ratio calibrated at that step (untimed check)",
                step_label(fast_dt())
            );
            recalibrated = Some(run_mujoco(n, fast_dt(), None)?);
        }
        mj_rounds.push(this);
        eprintln!("round {} of {REPEATS}: the project", round + 1);
        for (b, ((name, _), stone)) in bodies.iter().zip(&stones).enumerate() {
            for (k, m) in modes.iter().enumerate() {
                let r = pool.install(|| timed(stone, &header(name, n, m), m.batch));
                eprintln!("  {name} {}: {:.1} drops/s", m.name, n as f64 / r.seconds);
                if best[b][k].as_ref().is_none_or(|x| r.seconds < x.seconds) {
                    best[b][k] = Some(r);
                }
            }
        }
    }
    std::fs::remove_dir_all(&tmp)?;
    // Whether every round gave MuJoCo's round-0 drops, per body and step.
    let same_rounds = |b: usize, s: usize| {
        mj_rounds.iter().all(|r| {
            r[s].bodies[b]
                .drops
                .iter()
                .zip(&mj_rounds[0][s].bodies[b].drops)
                .all(|(x, y)| x.down == y.down && x.steps == y.steps)
        })
    };
    let yes_no = |ok: bool| if ok { "yes" } else { "**no**" };
    let dts = mj_dts();
    let (ref_label, def_label) = (step_label(dts[0]), step_label(dts[1]));

    let mut csv = String::from(
        "body,engine,mode,batch,certificate,dt,drops,cpu_seconds,drops_per_s,ratio_vs_mujoco_loop,\
         ratio_vs_mujoco_stepping,ratio_vs_mujoco_same_dt_loop,ratio_vs_mujoco_same_dt_stepping,cpu_us_per_step,\
         mean_sim_time_s,settled,certified,off_equilibrium,chi2_p_flocks_vs_mujoco,chi2_p_flocks_vs_mujoco_same_dt,\
         kl_flocks_vs_static\n",
    );
    let mut table = String::new();
    let mut flock_tables = String::new();
    // Per body: the four modes against MuJoCo at the reference step, then the default numerics
    // against MuJoCo at the same step; each (against the loop, against the stepping alone).
    let mut bars: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let mut checks = String::new();
    let mut rapier_flat: Vec<(f64, f64, [f64; 2])> = Vec::new();
    let mut summaries: Vec<Summary> = Vec::new();
    let mut sample_tables = String::new();
    let mut substep_tables = String::new();
    let mut box_pairs = String::new();
    for (b, ((name, _), stone)) in bodies.iter().zip(&stones).enumerate() {
        // MuJoCo's drops at each step, classified by the project's rule; its fastest round.
        let mj: Vec<MjSide> = dts
            .iter()
            .enumerate()
            .map(|(s, &dt)| {
                let mb = &mj_rounds[0][s].bodies[b];
                let (report, outcomes) = classify(stone, name, &mb.drops, dt);
                let big = classify(stone, name, &mb.sample_drops, dt);
                let fastest = |f: &dyn Fn(&MjBody) -> &[f64]| {
                    mj_rounds.iter().flat_map(|r| f(&r[s].bodies[b]).iter().copied()).fold(f64::INFINITY, f64::min)
                };
                MjSide {
                    dt,
                    report,
                    outcomes,
                    loop_s: fastest(&|x| &x.loop_cpu_s),
                    step_s: fastest(&|x| &x.replay_cpu_s),
                    steps: mb.drops.iter().map(|d| d.steps).sum(),
                    big: big.0,
                    big_outcomes: big.1,
                    warned: mb.sample_drops.iter().filter(|d| d.warnings > 0).count(),
                }
            })
            .collect();
        let mb0 = &mj_rounds[0][0].bodies[b];
        let recal_drops = &recalibrated.as_ref().expect("round 0 ran").bodies[b].drops;
        let recal = classify(stone, name, recal_drops, fast_dt()).0;
        if mb0.flat_restitution.is_some() {
            for (s, &dt) in dts.iter().enumerate() {
                let mj_e = mj_rounds[0][s].bodies[b].flat_restitution.unwrap_or([f64::NAN; 2]);
                rapier_flat.push((dt, rapier_flat_restitution(stone, &box_normal, dt), mj_e));
            }
        }

        // The project's modes, their fastest round.
        let mut rows: Vec<Row> = Vec::new();
        for (m, r) in modes.iter().zip(best[b].iter_mut()) {
            let r = r.take().expect("REPEATS ≥ 1");
            rows.push(Row {
                label: m.name.clone(),
                rate: n as f64 / r.seconds,
                seconds: r.seconds,
                report: r.report,
                outcomes: r.outcomes,
                rise: r.rise,
            });
        }
        let per_step = |f: &dyn Fn(usize) -> String| {
            dts.iter()
                .enumerate()
                .map(|(s, &dt)| format!("{} at {}", f(s), step_label(dt)))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let rises = per_step(&|s| {
            let r = rise(&mj[s].outcomes);
            format!("median {:.1e}, largest {:.1e} R_max", r.0, r.1)
        });
        // MuJoCo's releases are the project's: the largest angle between the two engines' initial
        // down directions (body frame) over every drop of the sample, at both steps.
        let release_angle = mj_rounds[0]
            .iter()
            .flat_map(|r| r.bodies[b].release_downs.iter().enumerate())
            .map(|(i, d)| {
                let q = launch(&mut item_rng(SEED, i as u64), &reference).orientation;
                let own = q.inverse() * -Vec3::z();
                let (cos, sin) = (own.dot(&Vec3::from(*d)), own.cross(&Vec3::from(*d)).norm());
                sin.atan2(cos)
            })
            .fold(0.0f64, f64::max);
        let releases = mj_rounds[0].iter().map(|r| r.bodies[b].release_downs.len()).sum::<usize>();
        writeln!(
            checks,
            "* {name}: MuJoCo's initial down direction (body frame) is the project's for every one of the {releases} \
             releases (both steps) within {release_angle:.1e} rad; MuJoCo's compiled mesh has {} vertices ({} hull \
             corners given), its support in 7 directions within {:.1e} R_max of the corners'; the replays ended bit for bit where the loop did: \
             {}; every round gave the same drops: {}; drops with a MuJoCo warning (an instability) in the \
             larger samples: {}. How far off its stable facet a drop came to rest, h(final down) − R_F (the rise \
             of G that its tilt implies; 0 flat on the facet, counted on it up to {REST_TOLERANCE}): in MuJoCo \
             {rises}; median {:.1e}, largest {:.1e} in the project's plain drops.",
            mb0.mesh_vertices,
            stone.body.corners.len(),
            mb0.placement_error,
            per_step(&|s| yes_no(mj_rounds.iter().all(|r| r[s].bodies[b].replay_identical)).to_string()),
            per_step(&|s| yes_no(same_rounds(b, s)).to_string()),
            per_step(&|s| mj[s].warned.to_string()),
            rows[0].rise.0,
            rows[0].rise.1,
        )?;
        let nd = n as f64;
        // The larger, untimed samples: the batched project at the reference step (drop by drop
        // the plain drops), the default numerics, and MuJoCo at both steps.
        let big = n * SAMPLE_FACTOR;
        let project_run = pool.install(|| timed(stone, &header(name, big, &modes[1]), DEFAULT_BATCH));
        let fast_run = pool.install(|| timed(stone, &header(name, big, &modes[3]), modes[3].batch));
        let (project_big, fast_big) = (&project_run.report, &fast_run.report);
        // The two steps of one engine start from the same orientations: drops that end in the
        // same flock at both steps.
        let paired = |a: &BTreeMap<u64, DropOutcome>, b: &BTreeMap<u64, DropOutcome>| {
            a.iter()
                .filter(|(i, o)| {
                    o.settled && b.get(i).is_some_and(|p| p.settled && flock_of(stone, p) == flock_of(stone, o))
                })
                .count()
        };
        let same_mj = paired(&mj[0].big_outcomes, &mj[1].big_outcomes);
        let same_project = paired(&project_run.outcomes, &fast_run.outcomes);
        let (pc, dc) = (counts(stone, project_big), counts(stone, fast_big));
        let (m0, m1) = (counts(stone, &mj[0].big), counts(stone, &mj[1].big));
        let big_ref = drop_by_drop(stone, &project_run.outcomes, &mj[0].big_outcomes);
        let big_mj_steps = drop_by_drop(stone, &mj[1].big_outcomes, &mj[0].big_outcomes);
        let big_fast_same = drop_by_drop(stone, &fast_run.outcomes, &mj[1].big_outcomes);
        let big_fast_ref = drop_by_drop(stone, &fast_run.outcomes, &mj[0].big_outcomes);
        let big_project_steps = drop_by_drop(stone, &fast_run.outcomes, &project_run.outcomes);
        let shares = chi_shares(&pc, &m0);
        let shares_mj = chi_shares(&m1, &m0);
        let test = |what: &str, c: &Chi| {
            format!(
                "* {what}: same flock in both {} of {} drops; Stuart–Maxwell χ² = {:.1} ({} dof), p = {:.3}",
                c.same, c.both, c.chi2, c.dof, c.p
            )
        };
        writeln!(
            sample_tables,
            "\n### {name}\n\n{} drops per engine and step; not settled within the {} s cap: project {} at {ref_label} \
             (batched), {} at {def_label} (default numerics); MuJoCo {} at {ref_label}, {} at {def_label}.\n\n{}\n{}\n{}\n{}\n{}\n",
            big,
            reference.sim.numerics.max_time,
            project_big.unsettled,
            fast_big.unsettled,
            mj[0].big.unsettled,
            mj[1].big.unsettled,
            test(&format!("project {ref_label} against MuJoCo {ref_label}"), &big_ref),
            test(&format!("MuJoCo {def_label} against MuJoCo {ref_label}"), &big_mj_steps)
                + &format!(" (the same orientations at both steps: {same_mj} of {big} drops end in the same flock)"),
            test(&format!("project default numerics ({def_label}) against MuJoCo {def_label}"), &big_fast_same),
            test(&format!("project default numerics ({def_label}) against MuJoCo {ref_label}"), &big_fast_ref),
            test(&format!("project default numerics ({def_label}) against project {ref_label}"), &big_project_steps)
                + &format!(" (the same orientations at both steps: {same_project} of {big} drops end in the same flock)"),
        )?;
        writeln!(
            sample_tables,
            "| flock | type | static | project {ref_label} (batched) | MuJoCo {ref_label} | project {def_label} (default \
             numerics) | MuJoCo {def_label} | share of χ², project {ref_label} vs MuJoCo {ref_label} | share of χ², \
             MuJoCo {def_label} vs {ref_label} |\n|---|---|---|---|---|---|---|---|---|"
        )?;
        let cell = |r: &DropReport, id: usize| {
            r.flocks
                .iter()
                .find(|g| g.id == id)
                .map_or("—".into(), |g: &FlockRow| format!("{:.3} [{:.3}, {:.3}]", g.fraction, g.ci95.0, g.ci95.1))
        };
        let share = |v: &[f64], k: usize| 100.0 * v[k] / v.iter().sum::<f64>().max(f64::MIN_POSITIVE);
        for f in &project_big.flocks {
            writeln!(
                sample_tables,
                "| {} | {} | {:.3} | {} | {} | {} | {} | {:.0} % | {:.0} % |",
                f.id,
                format!("{:?}", f.kind).to_lowercase(),
                f.static_probability,
                cell(project_big, f.id),
                cell(&mj[0].big, f.id),
                cell(fast_big, f.id),
                cell(&mj[1].big, f.id),
                share(&shares, f.id),
                share(&shares_mj, f.id),
            )?;
        }
        let fraction = |r: &DropReport, k: usize| r.flocks.iter().find(|f| f.id == k).map_or(0.0, |f| f.fraction);
        substep_tables.push_str(&substep_table(stone, name, big, &modes[2], &pool, &mj[0].big_outcomes)?);
        if mb0.flat_restitution.is_some() {
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
                format!("{:.3} / {:.3} / {:.3}", v[0], v[1], v[2])
            };
            box_pairs = format!(
                " By face pair, the box rests on its 0.8 × 0.5 ends, 1 × 0.5 sides and 1 × 0.8 faces with fractions \
                 {} in the project at {ref_label} and {} in MuJoCo at {ref_label}; {} in the project's default \
                 numerics and {} in MuJoCo at {def_label} (static {}).",
                pooled(project_big, false),
                pooled(&mj[0].big, false),
                pooled(fast_big, false),
                pooled(&mj[1].big, false),
                pooled(project_big, true),
            );
            // MuJoCo − project per face at the reference step, the two faces of each pair side by side.
            let mut diffs = [Vec::new(), Vec::new(), Vec::new()];
            for f in &project_big.flocks {
                diffs[axis_of(f.id)].push(format!("{:+.3}", fraction(&mj[0].big, f.id) - f.fraction));
            }
            write!(
                box_pairs,
                " MuJoCo − project per face at {ref_label}: ends {}, sides {}, faces {}.",
                diffs[0].join(" / "),
                diffs[1].join(" / "),
                diffs[2].join(" / ")
            )?;
            let flat_apart = rapier_flat.iter().all(|&(_, r, [m, _])| (r - m).abs() > 0.01);
            if big_ref.p < 0.05 && flat_apart {
                box_pairs.push_str(
                    " The ball calibration of the restitution does not pin down how a box tumbles: its flat landing \
                     already rebounds differently in the two engines (above).",
                );
            }
        }
        let widest_of = |v: &[f64], a: &DropReport, b: &DropReport| {
            let k = (0..v.len()).max_by(|&x, &y| v[x].total_cmp(&v[y])).expect("a flock");
            (k, format!("{:?}", stone.flock_kinds[k]).to_lowercase(), fraction(a, k), fraction(b, k))
        };
        let widest = widest_of(&shares, project_big, &mj[0].big);
        let widest_mj_steps = widest_of(&shares_mj, &mj[1].big, &mj[0].big);
        let widest_fast_same = widest_of(&chi_shares(&dc, &m1), fast_big, &mj[1].big);

        let mut ratios = Vec::new();
        let (mut us_modes, mut p_modes, mut same_modes) = (Vec::new(), Vec::new(), Vec::new());
        let mut p_fast_same = f64::NAN;
        for (m, r) in modes.iter().zip(&rows) {
            let s = dts.iter().position(|&d| d == m.dt).expect("MuJoCo runs at every mode's step");
            let (rl, rs) = (r.rate / (nd / mj[0].loop_s), r.rate / (nd / mj[0].step_s));
            let (sl, ss) = (r.rate / (nd / mj[s].loop_s), r.rate / (nd / mj[s].step_s));
            ratios.push((rl, rs));
            let vs_same = drop_by_drop(stone, &r.outcomes, &mj[s].outcomes);
            let (p, p_same) = (drop_by_drop(stone, &r.outcomes, &mj[0].outcomes).p, vs_same.p);
            let agree = format!("{}/{}", vs_same.same, vs_same.both);
            if s == 1 {
                p_fast_same = p_same;
            }
            let us = 1e6 * r.seconds / (nd * r.report.mean_time / r.report.params.sim.numerics.dt);
            us_modes.push(us);
            p_modes.push(p);
            let same =
                r.outcomes.iter().filter(|(i, o)| flock_of(stone, o) == flock_of(stone, &rows[0].outcomes[*i])).count();
            same_modes.push(same);
            writeln!(
                table,
                "| {name} | project, {} | {} | {:.1} | **{rl:.2}×** | {rs:.2}× | **{sl:.2}×** ({ss:.2}×) | {us:.2} | \
                 {:.2} | {} | {} | {} | {same}/{n} | {agree} | {p:.2} | {p_same:.2} |",
                r.label,
                step_label(m.dt),
                r.rate,
                r.report.mean_time,
                r.report.settled,
                r.report.certified,
                r.report.off_equilibrium
            )?;
            writeln!(
                csv,
                "\"{name}\",project,\"{}\",{},{},{:.6},{n},{:.4},{:.2},{rl:.4},{rs:.4},{sl:.4},{ss:.4},{us:.3},{:.4},{},{},{},\
                 {p:.4},{p_same:.4},{:.5}",
                r.label,
                m.batch,
                m.cert.name(),
                r.report.params.sim.numerics.dt,
                r.seconds,
                r.rate,
                r.report.mean_time,
                r.report.settled,
                r.report.certified,
                r.report.off_equilibrium,
                r.report.fit_flocks.kl_divergence
            )?;
        }
        // The default numerics against MuJoCo at the same step.
        let d = &rows[3];
        ratios.push((d.rate / (nd / mj[1].loop_s), d.rate / (nd / mj[1].step_s)));
        let p_mj_steps = drop_by_drop(stone, &mj[1].outcomes, &mj[0].outcomes).p;
        for (s, side) in mj.iter().enumerate() {
            let p_cell = if s == 0 { String::new() } else { format!("{p_mj_steps:.2}") };
            for (label, secs) in
                [("mj_step loop + rest check (Python)", side.loop_s), ("stepping alone (replay)", side.step_s)]
            {
                let us = 1e6 * secs / side.steps as f64;
                writeln!(
                    table,
                    "| {name} | MuJoCo, {label} | {} | {:.1} | | | | {us:.2} | {:.2} | {} | — | {} | | | {p_cell} | |",
                    step_label(side.dt),
                    nd / secs,
                    side.report.mean_time,
                    side.report.settled,
                    side.report.off_equilibrium
                )?;
                writeln!(
                    csv,
                    "\"{name}\",mujoco,\"{label}\",1,none,{:.6},{n},{secs:.4},{:.2},,,,,{us:.3},{:.4},{},0,{},{},,{:.5}",
                    side.dt,
                    nd / secs,
                    side.report.mean_time,
                    side.report.settled,
                    side.report.off_equilibrium,
                    if s == 0 { String::new() } else { format!("{p_mj_steps:.4}") },
                    side.report.fit_flocks.kl_divergence
                )?;
            }
        }
        let short = ["stone", "pebble", "box"][bars.len()];
        bars.push((short.into(), ratios));
        summaries.push(Summary {
            short,
            us: us_modes,
            p: p_modes,
            same_flock: same_modes,
            t: rows.iter().map(|r| r.report.mean_time).collect(),
            mj: mj
                .iter()
                .map(|x| MjSummary {
                    step_us: 1e6 * x.step_s / x.steps as f64,
                    loop_us: 1e6 * x.loop_s / x.steps as f64,
                    loop_rate: nd / x.loop_s,
                    step_rate: nd / x.step_s,
                    t: x.report.mean_time,
                    unsettled: x.report.unsettled,
                    big_unsettled: x.big.unsettled,
                    big_drops: x.big.drops,
                    warned: x.warned,
                })
                .collect(),
            p_fast_same,
            p_mj_steps,
            big_ref,
            widest,
            big_mj_steps,
            widest_mj_steps,
            widest_fast_same,
            big_fast_same,
            big_fast_ref,
            big_project_steps,
            big_unsettled: (project_big.unsettled, fast_big.unsettled),
            same_big: (same_mj, same_project, big),
            recal: (
                recal.drops,
                recal.unsettled,
                recal_drops.iter().filter(|d| d.warnings > 0).count(),
                recal.mean_time,
            ),
        });

        writeln!(flock_tables, "\n### {name}\n")?;
        write!(flock_tables, "| flock | type | static |")?;
        for m in &modes {
            write!(flock_tables, " {} |", m.name)?;
        }
        for side in &mj {
            write!(flock_tables, " MuJoCo {} |", step_label(side.dt))?;
        }
        writeln!(flock_tables, "\n|---|---|---|{}", "---|".repeat(modes.len() + mj.len()))?;
        let reports: Vec<&DropReport> = rows.iter().map(|r| &r.report).chain(mj.iter().map(|x| &x.report)).collect();
        for f in &rows[0].report.flocks {
            write!(
                flock_tables,
                "| {} | {} | {:.3} |",
                f.id,
                format!("{:?}", f.kind).to_lowercase(),
                f.static_probability
            )?;
            for r in &reports {
                write!(flock_tables, " {} |", cell(r, f.id))?;
            }
            writeln!(flock_tables)?;
        }
        write!(flock_tables, "| KL vs static | | |")?;
        for r in &reports {
            write!(flock_tables, " {:.4} |", r.fit_flocks.kl_divergence)?;
        }
        writeln!(flock_tables)?;
    }

    let parts = Parts { table, flock_tables, checks, sample_tables, substep_tables, box_pairs };
    let recalibrated = recalibrated.expect("round 0 ran");
    let s = readme(n, &mj_rounds[0], &recalibrated, &modes, &parts, &bars, &summaries, &rapier_flat)?;
    std::fs::write(out.join("README.md"), s)?;
    std::fs::write(out.join("speed.csv"), csv)?;
    plot(&out.join("ratio.png"), &modes, &bars).map_err(|e| anyhow::anyhow!("plot: {e}"))?;
    Ok(())
}

/// The parts of the README written while the bodies run: the speed table, the per-flock tables
/// and the checks.
struct Parts {
    table: String,
    flock_tables: String,
    checks: String,
    sample_tables: String,
    /// The untimed convergence check in rapier's solver sub-steps.
    substep_tables: String,
    /// The box's fractions pooled by face pair.
    box_pairs: String,
}

#[allow(clippy::too_many_arguments)]
fn readme(
    n: u64,
    mj: &[MjOut],
    recal: &MjOut,
    modes: &[Mode],
    parts: &Parts,
    bars: &[(String, Vec<(f64, f64)>)],
    summaries: &[Summary],
    rapier_flat: &[(f64, f64, [f64; 2])],
) -> anyhow::Result<String> {
    let dts = mj_dts();
    let (r_l, d_l) = (step_label(dts[0]), step_label(dts[1]));
    let def = &modes[3];
    let mut s = String::new();
    writeln!(s, "# Drops per second per core: this project against MuJoCo, same physics\n")?;
    writeln!(
        s,
        "Generated by `cargo run --release --example drops_vs_mujoco -- {n}` (MuJoCo {} from Python {}, numpy {}; \
         `experiments/shared/mujoco_drops.py`): {n} drops per body and mode, on **one core** — the project in a \
         one-thread rayon pool, timed by the CPU time of its worker thread; MuJoCo in one Python process, timed by \
         its process CPU time; the two run one after the other, never at the same time, in {REPEATS} rounds (each: \
         MuJoCo's drops at {r_l} and at {d_l}, then every mode of the project, so that both see the same load of \
         this shared machine), and each side's fastest round is used. The project runs plain, batched and \
         flock-certified + batched at the reference step {r_l} (`REFERENCE_DT`, MuJoCo's step in the benchmark \
         protocol), and flock-certified + batched with its **default numerics** at dt {d_l} \
         (`Preset::largest_stable_dt`, what `rocking drop` runs; `--reference` takes {r_l}). MuJoCo runs at both steps: at {r_l} (the benchmark \
         protocol) and at {d_l}, the project's default step. The *ratio* is the project's drops/s over \
         MuJoCo's for the same body. The per-flock statistics are compared on the timed drops and on larger \
         untimed samples ({SAMPLE_FACTOR} × {n} drops per engine, step and body).\n",
        mj[0].mujoco_version, mj[0].python_version, mj[0].numpy_version
    )?;
    writeln!(s, "## The physics matched\n")?;
    writeln!(s, "| | project (rapier3d 0.36) | MuJoCo {} |", mj[0].mujoco_version)?;
    writeln!(s, "|---|---|---|")?;
    let calibration = format!(
        "solref = ({}, {:.4}): **measured e = {:.3} at {r_l}** (by rebound speed over impact speed at the steps where \
         the contact starts and stops: {:.3}). At {d_l} MuJoCo runs the same model, only the step changed (as the \
         project keeps its parameters at its longer step): there the same solref gives the ball **e = {:.3}** ({:.3} \
         by speeds); the damping ratio calibrated at {d_l}, {:.4} (ball e = {:.3}), is used only in an untimed check \
         (Reading)",
        mj[0].solref[0],
        mj[0].solref[1],
        mj[0].ball_restitution,
        mj[0].ball_restitution_speeds,
        mj[1].ball_restitution,
        mj[1].ball_restitution_speeds,
        recal.solref[1],
        recal.ball_restitution,
    );
    writeln!(
        s,
        "| frame | scaled: R_max = 1 m, mass 1, g = 9.81 m/s² | the same |\n\
         | body | the hull corners relative to G (`Stone::body.corners`), the project's collider | a mesh geom on the \
         same corners (MuJoCo collides with their convex hull), rotated into the principal axes of the inertia \
         tensor; the final down direction is rotated back |\n\
         | mass, inertia | 1, `Stone::body.inertia` | `<inertial pos=\"0 0 0\" mass=\"1\" fullinertia=…/>`, the same \
         tensor (diagonal in the principal frame) |\n\
         | release | from rest, lowest point {HEIGHT} R_max above the plane, Haar-uniform orientation (the \
         project's stream, seed {SEED}) | the same releases: the project's orientation of each drop index, carried \
         to the principal frame (the drops are compared one by one) |\n\
         | friction | Coulomb μ = {FRICTION} (rapier, circular cone) | condim 3 (sliding only), μ = {FRICTION} on \
         both geoms, **{} cone** (MuJoCo's default is pyramidal) |\n\
         | restitution | e = {RESTITUTION} (rapier's restitution coefficient, completed by the contact law in the two stages of an impact: the struck points brought to rest with Coulomb friction, then sent off at Newton's e u by normal impulses, `world::ContactLaw::restitute`) | MuJoCo has none: \
         solref = (time constant, damping ratio), the default time constant and the damping ratio found by \
         bisection at {r_l} so that a ball (radius 1 = R_max, mass 1) dropped {HEIGHT} R_max onto the plane \
         rebounds to e² of its drop height: {calibration}; solimp = {:?} (default) |\n\
         | rolling / torsional friction | off (`rolling_resistance = 0`, `torsional_friction = 0`) | none (condim 3) |\n\
         | global damping | {LINEAR_DAMPING} s⁻¹ linear, {ANGULAR_DAMPING} s⁻¹ angular: v ← v / (1 + dt c) each step \
         | dof_damping on the free joint: {LINEAR_DAMPING}·m on the translations and {ANGULAR_DAMPING}·I_i on the \
         principal rotations (the torque −c I ω), treated implicitly by the integrator, which is the same \
         v ← v / (1 + dt c) |\n\
         | numerics | the `drop` preset's (exact landings, sub-stepped impacts), 4 solver iterations; dt = {r_l} \
         (plain, batched, flock-certified + batched) or {d_l} (the default numerics) | opt.timestep = {r_l} or \
         {d_l} (one run each; the contact's time constant {MJ_TIMECONST} s is at least twice either, as MuJoCo \
         asks of a soft contact), **{}** integrator (MuJoCo's default is {}), {} solver ({} iterations, tolerance \
         {:e}), one thread |\n\
         | rest | linear speed < 2·10⁻³ m/s and angular speed < 5·10⁻³ rad/s for 0.25 s of consecutive steps, \
         cap 60 s | the same rule on qvel, checked after every step (⌈0.25 s / dt⌉ steps, cap ⌈60 s / dt⌉) |\n\
         | outcome | `Stone::rest` of the final down direction (the certificate's flock when it decides) | the \
         final down direction returned, `Stone::rest` applied here |\n",
        mj[0].cone,
        mj[0].solimp,
        mj[0].integrator,
        mj[0].default_integrator.trim_start_matches("mjINT_").to_lowercase(),
        mj[0].solver.trim_start_matches("mjSOL_").to_lowercase(),
        mj[0].iterations,
        mj[0].tolerance
    )?;
    if !rapier_flat.is_empty() {
        let list = rapier_flat
            .iter()
            .map(|&(dt, r, [m, ms])| {
                format!("at {}: e = {r:.3} in rapier and {m:.3} in MuJoCo (by speeds {ms:.3})", step_label(dt))
            })
            .collect::<Vec<_>>()
            .join("; ");
        writeln!(
            s,
            "Check of the restitution on a body: the box dropped flat on its 1 × 0.8 face from {HEIGHT} R_max (no \
             damping) rebounds {list}.\n"
        )?;
    }
    writeln!(
        s,
        "**MuJoCo timing.** *mj_step loop + rest check*: per drop, a Python loop of `mujoco.mj_step(m, d)` and the \
         rest test on `d.qvel` (what the project's run loop does in Rust); *stepping alone*: the same drops replayed \
         as one `mj_step(m, d, nstep=steps)` call each (MuJoCo is deterministic: the replay ends bit for bit where \
         the loop did), i.e. MuJoCo's C stepping without the interpreter — a lower bound of what a C program driving \
         MuJoCo would spend. The ratios in bold are against the loop, the others against stepping alone. The \
         columns *vs MuJoCo {r_l}* divide by MuJoCo at {r_l} for every mode (the benchmark protocol); the column *vs \
         MuJoCo at the same dt* divides by MuJoCo at the mode's own step: {r_l} for plain, batched and \
         flock-certified + batched (so the same numbers), **{d_l} for the default numerics** — the comparison at \
         equal steps.\n"
    )?;
    writeln!(s, "## Drops per second per core\n")?;
    writeln!(
        s,
        "| body | engine, mode | dt | drops/s | ratio vs MuJoCo {r_l} loop | ratio vs MuJoCo {r_l} stepping alone | \
         ratio vs MuJoCo at the same dt: loop (stepping alone) | CPU µs per step | mean simulated s per drop | settled \
         | certified | off its facet | same flock as plain | same flock as MuJoCo at the same dt | p vs MuJoCo {r_l} \
         (flocks, paired) | p vs MuJoCo at the same dt |"
    )?;
    writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")?;
    s.push_str(&parts.table);
    writeln!(
        s,
        "\n*off its facet*: settled with G more than {REST_TOLERANCE} R_max above its stable facet's rest (stopped on \
         a slope or an edge). Both engines drop the same releases, so the drops pair up by index: *same flock as \
         MuJoCo* counts the drops settled in both that end in the same flock; *p*: the Stuart–Maxwell test of \
         marginal homogeneity of the per-flock counts of that row against MuJoCo's, drop by drop \
         (`stats::stuart_maxwell`); on MuJoCo's {d_l} rows, against MuJoCo's own at {r_l}.\n"
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
    let list = |k: usize| bars.iter().map(|(b, v)| format!("{b} {:.2}× ({:.2}×)", v[k].0, v[k].1)).collect::<Vec<_>>();
    for (k, m) in modes.iter().enumerate() {
        let protocol = if k == 3 { ", the benchmark protocol" } else { "" };
        writeln!(
            s,
            "* **{}** against MuJoCo's loop at {r_l}{protocol} (in parentheses: against its stepping alone): {}.",
            m.name,
            list(k).join(", ")
        )?;
    }
    writeln!(
        s,
        "* **{}** against MuJoCo's loop at the same step, {d_l} (in parentheses: against its stepping alone): {}.",
        def.name,
        list(4).join(", ")
    )?;
    let per_step_ratio: Vec<f64> = summaries.iter().map(|x| x.us[0] / x.mj[0].step_us).collect();
    let lead = if per_step_ratio.iter().all(|&q| (2.0 / 3.0..=1.5).contains(&q)) {
        "Engine against engine, the two physics engines cost about the same per step."
    } else if per_step_ratio.iter().all(|&q| q < 1.0) {
        "Engine against engine, the project's engine costs less per step."
    } else if per_step_ratio.iter().all(|&q| q > 1.0) {
        "Engine against engine, MuJoCo costs less per step."
    } else {
        "Engine against engine, the cost per step depends on the body."
    };
    let longer = if summaries.iter().all(|x| x.mj[0].t > x.t[0]) {
        "longer in MuJoCo"
    } else if summaries.iter().all(|x| x.mj[0].t < x.t[0]) {
        "shorter in MuJoCo"
    } else {
        "in MuJoCo longer for some bodies and shorter for others"
    };
    writeln!(
        s,
        "\n**{lead}** The plain rows at {r_l} ({} of MuJoCo's loop, {} of its stepping alone) split into a cost per \
         simulated step — {} µs in the project against {} µs of MuJoCo stepping alone ({} µs with the Python loop) — \
         and the simulated time a drop takes to come to rest, {longer} ({} s against {} s; the rest rule and the \
         damping are the same, so the difference is in how the two contacts dissipate). The Python loop adds {} % \
         to MuJoCo's stepping{}.\n",
        range(0, false),
        range(0, true),
        each(&|x| format!("{} {:.2}", x.short, x.us[0])),
        each(&|x| format!("{:.2}", x.mj[0].step_us)),
        each(&|x| format!("{:.2}", x.mj[0].loop_us)),
        each(&|x| format!("{} {:.2}", x.short, x.mj[0].t)),
        each(&|x| format!("{:.2}", x.t[0])),
        each(&|x| format!("{:.0}", 100.0 * (x.mj[0].loop_us / x.mj[0].step_us - 1.0))),
        if summaries.iter().any(|x| x.mj[0].loop_us < x.mj[0].step_us) {
            " (a negative share is the noise of the timing: the loop cannot cost less than the stepping it contains)"
        } else {
            ""
        },
    )?;
    // MuJoCo at the longer step: speed, settling, warnings, and its statistics against its own at
    // the reference step.
    let mj_unsettled: Vec<String> = summaries
        .iter()
        .flat_map(|x| {
            x.mj.iter().zip(dts).filter(|(m, _)| m.big_unsettled > 0).map(move |(m, dt)| {
                format!(
                    "{} at {}: {} of {} (of them {} of the {n} timed)",
                    x.short,
                    step_label(dt),
                    m.big_unsettled,
                    m.big_drops,
                    m.unsettled
                )
            })
        })
        .collect();
    let warned: usize = summaries.iter().flat_map(|x| x.mj.iter().map(|m| m.warned)).sum();
    let settling = if mj_unsettled.is_empty() {
        format!(
            "Every MuJoCo drop came to rest within the 60 s cap at both steps ({} drops per body and step, the \
             timed ones among them)",
            n * SAMPLE_FACTOR
        )
    } else {
        format!("MuJoCo drops not at rest at the 60 s cap: {}", mj_unsettled.join("; "))
    };
    let warnings = if warned == 0 {
        "and MuJoCo raised no warning (no bad qpos, qvel or qacc: no instability) in any drop".to_string()
    } else {
        format!("and MuJoCo raised warnings (an instability, after which it resets the state) in {warned} drops, counted as not settled")
    };
    let recal_unsettled: u64 = summaries.iter().map(|x| x.recal.1).sum();
    let recal_sentence = if recal_unsettled > 0 {
        format!(
            "Calibrating the damping ratio again at {d_l} gives {:.4}, with which the ball rebounds with e = {:.3}, but \
             then drops do not come to rest: in an untimed check of {n} drops per body, {} were still moving at the \
             60 s cap (mean simulated s per drop {}; drops with a MuJoCo warning {}), so that calibration is not used.",
            recal.solref[1],
            recal.ball_restitution,
            each(&|x| format!("{} {} of {}", x.short, x.recal.1, x.recal.0)),
            each(&|x| format!("{} {:.2}", x.short, x.recal.3)),
            each(&|x| format!("{} {}", x.short, x.recal.2)),
        )
    } else {
        format!(
            "Calibrated again at {d_l}, the damping ratio {:.4} (ball e = {:.3}) brings every drop of an untimed check \
             ({n} per body) to rest too (mean simulated s per drop {}); the table keeps the model of {r_l}.",
            recal.solref[1],
            recal.ball_restitution,
            each(&|x| format!("{} {:.2}", x.short, x.recal.3)),
        )
    };
    let mj_differ: Vec<&str> = summaries.iter().filter(|x| x.big_mj_steps.p < 0.05).map(|x| x.short).collect();
    let mj_verdict = if mj_differ.is_empty() {
        format!(
            "No p below 0.05: MuJoCo's per-flock statistics at {d_l} are those it has at {r_l} within what these \
             samples resolve; MuJoCo too keeps its statistics at the longer step, and the comparison at equal steps \
             compares two engines that both do."
        )
    } else {
        format!(
            "Below 0.05 for the {}: there MuJoCo's per-flock statistics at {d_l} differ from its own at {r_l} by more \
             than sampling (the flock with the largest share of χ²: {}), so MuJoCo at {d_l} is a faster but not an \
             equivalent MuJoCo there.",
            mj_differ.join(" and "),
            summaries
                .iter()
                .filter(|x| x.big_mj_steps.p < 0.05)
                .map(|x| format!(
                    "{} flock {} ({}), {:.3} at {d_l} against {:.3} at {r_l}",
                    x.short, x.widest_mj_steps.0, x.widest_mj_steps.1, x.widest_mj_steps.2, x.widest_mj_steps.3
                ))
                .collect::<Vec<_>>()
                .join(", ")
        )
    };
    writeln!(
        s,
        "**MuJoCo at the project's default step, {d_l}.** The same MuJoCo model as at {r_l}, solref ({}, {:.4}), \
         only the step changed; the contact's time constant {MJ_TIMECONST} s is {:.1} steps of {d_l} (MuJoCo asks \
         for at least 2). MuJoCo's restitution {}: the ball that rebounds with e = {:.3} at {r_l} rebounds with \
         e = {:.3} at {d_l}. {recal_sentence} MuJoCo's loop runs {} drops/s at {d_l} against {} at {r_l} (×{}), its \
         stepping alone {} against {}; a step costs {} µs of stepping alone against {} µs at {r_l}, and a drop \
         takes {} simulated s against {}. {settling}, {warnings}. Paired p (Stuart–Maxwell) of its per-flock counts \
         at {d_l} against its own at {r_l}: timed drops {}; larger samples ({SAMPLE_FACTOR} × {n}, \
         [below](#larger-samples-untimed)) {}. {mj_verdict} (Both steps drop the same releases: {} drops end in the \
         same flock at both steps.)\n",
        mj[1].solref[0],
        mj[1].solref[1],
        MJ_TIMECONST / dts[1],
        if (mj[0].ball_restitution - mj[1].ball_restitution).abs() > 0.02 {
            "depends on its step"
        } else {
            "hardly depends on its step"
        },
        mj[0].ball_restitution,
        mj[1].ball_restitution,
        each(&|x| format!("{} {:.1}", x.short, x.mj[1].loop_rate)),
        each(&|x| format!("{:.1}", x.mj[0].loop_rate)),
        each(&|x| format!("{:.2}", x.mj[1].loop_rate / x.mj[0].loop_rate)),
        each(&|x| format!("{} {:.1}", x.short, x.mj[1].step_rate)),
        each(&|x| format!("{:.1}", x.mj[0].step_rate)),
        each(&|x| format!("{} {:.2}", x.short, x.mj[1].step_us)),
        each(&|x| format!("{:.2}", x.mj[0].step_us)),
        each(&|x| format!("{} {:.2}", x.short, x.mj[1].t)),
        each(&|x| format!("{:.2}", x.mj[0].t)),
        each(&|x| format!("{} {:.2}", x.short, x.p_mj_steps)),
        each(&|x| format!("{} {:.3}", x.short, x.big_mj_steps.p)),
        each(&|x| format!("{} {} of {}", x.short, x.same_big.0, x.same_big.2)),
    )?;
    writeln!(
        s,
        "**The large ratios are the project's algorithms, not a faster engine.** Batching ({} per step, against \
         plain's {}) shares a rapier world's fixed cost per step between {DEFAULT_BATCH} stones; the flock \
         certificate ends a drop once its flock is certain, after {} simulated s instead of {}; the default \
         numerics take the step {d_l} instead of {r_l}. Exact landings and sub-stepped impacts (the `drop` preset's \
         numerics, in every mode here) cost little: only a step in which some hull corner could come down by more \
         than its clearance plus 0.01 R_max is cut, in a world of the stone's own, outside the batch \
         (`dynamics::engine::impact`). None of this is specific to rapier: the certificate needs only the body's energy and \
         down direction, which MuJoCo has too; MuJoCo can put many bodies in one model; and MuJoCo too takes the \
         longer step (above). So {} (flock-certified + batched, both engines at {r_l}) and {} (the default numerics \
         against MuJoCo at {r_l}, the benchmark protocol) — **{} against MuJoCo at the same step {d_l}**{} — are what \
         this project's drop pipeline gains over a plain MuJoCo loop (outcome statistics compared below), not a \
         property of the engines.\n",
        each(&|x| format!("{} {:.2} µs", x.short, x.us[1])),
        each(&|x| format!("{:.2}", x.us[0])),
        each(&|x| format!("{} {:.2}", x.short, x.t[2])),
        each(&|x| format!("{:.2}", x.t[0])),
        range(2, false),
        range(3, false),
        range(4, false),
        if summaries.iter().any(|x| x.mj[1].unsettled > 0) {
            format!(
                " (MuJoCo's timed drops at {d_l} that did not come to rest ran to the 60 s cap, which inflates these)"
            )
        } else {
            String::new()
        },
    )?;
    let worst = summaries
        .iter()
        .flat_map(|x| x.p.iter().map(move |&p| (p, x.short)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .expect("a body");
    let drop_by_drop = summaries.iter().all(|x| x.same_flock[1] == n as usize && x.same_flock[2] == n as usize);
    let shared = if drop_by_drop {
        "The batched and flock-certified drops end in the plain drop's flock drop by drop (the *same flock as plain* \
         column), so they share plain's p"
            .to_string()
    } else {
        format!(
            "The batched and flock-certified drops do not all end in the plain drop's flock (the *same flock as plain* \
             column: batched {}, flock-certified {} of {n})",
            each(&|x| format!("{} {}", x.short, x.same_flock[1])),
            each(&|x| format!("{} {}", x.short, x.same_flock[2])),
        )
    };
    let big_differ = |f: &dyn Fn(&Summary) -> f64| -> Vec<&str> {
        summaries.iter().filter(|x| f(x) < 0.05).map(|x| x.short).collect()
    };
    let verdict = |differ: Vec<&str>, what: &str| {
        if differ.is_empty() {
            format!("no p below 0.05 ({what} agree within what these samples resolve)")
        } else {
            format!("below 0.05 for the {} ({what} differ there by more than sampling)", differ.join(" and "))
        }
    };
    write!(
        s,
        "**Outcome statistics.** Both engines drop the same releases, so every comparison is drop by drop (paired \
         p: the Stuart–Maxwell test of marginal homogeneity of the per-flock counts). In the timed runs ({n} drops), \
         p against MuJoCo at {r_l}, plain / batched / flock-certified + batched / default numerics: {}; the lowest \
         is {:.2} ({}). {shared}; the default numerics integrate at another step: against MuJoCo at the same step, \
         {d_l}, their p is {}. The sharper tests are on the larger untimed samples ({SAMPLE_FACTOR} × {n} drops per \
         engine and step, [below](#larger-samples-untimed)). There, the project's batched drops at {r_l} end in \
         MuJoCo's flock at {r_l} in {} of the drops settled in both; p = {}, {}. The flock with the largest share \
         of the homogeneity χ² there: {}. The project's default numerics against MuJoCo at the same step {d_l}: \
         p = {}, {}{}; against MuJoCo at {r_l}: p = {}, {}; against the project's own drops at {r_l}: p = {}, {} \
         ({} drops end in the same flock at both steps).",
        each(&|x| format!("{} {}", x.short, x.p.iter().map(|p| format!("{p:.2}")).collect::<Vec<_>>().join(" / "))),
        worst.0,
        worst.1,
        each(&|x| format!("{} {:.2}", x.short, x.p_fast_same)),
        each(&|x| format!("{} {} of {}", x.short, x.big_ref.same, x.big_ref.both)),
        each(&|x| format!("{} {:.3}", x.short, x.big_ref.p)),
        verdict(big_differ(&|x| x.big_ref.p), "the two engines' per-flock statistics"),
        each(&|x| format!(
            "{} flock {} ({}), project {:.3} against MuJoCo {:.3}",
            x.short, x.widest.0, x.widest.1, x.widest.2, x.widest.3
        )),
        each(&|x| format!("{} {:.3}", x.short, x.big_fast_same.p)),
        verdict(big_differ(&|x| x.big_fast_same.p), "the two engines at equal steps"),
        {
            let w: Vec<String> = summaries
                .iter()
                .filter(|x| x.big_fast_same.p < 0.05)
                .map(|x| {
                    let (k, kind, a, b) = &x.widest_fast_same;
                    format!("{} flock {k} ({kind}), project {a:.3} against MuJoCo {b:.3}", x.short)
                })
                .collect();
            if w.is_empty() {
                String::new()
            } else {
                format!(", the flock with the largest share of χ² there: {}", w.join(", "))
            }
        },
        each(&|x| format!("{} {:.3}", x.short, x.big_fast_ref.p)),
        verdict(big_differ(&|x| x.big_fast_ref.p), "the project's default numerics and MuJoCo at the reference step"),
        each(&|x| format!("{} {:.3}", x.short, x.big_project_steps.p)),
        verdict(big_differ(&|x| x.big_project_steps.p), "the project's two steps"),
        each(&|x| format!("{} {} of {}", x.short, x.same_big.1, x.same_big.2)),
    )?;
    let project_unsettled: u64 = summaries.iter().map(|x| x.big_unsettled.0 + x.big_unsettled.1).sum();
    if project_unsettled > 0 {
        write!(
            s,
            " Project drops not at rest at the cap in the larger samples ({r_l} / {d_l}): {}.",
            each(&|x| format!("{} {} / {}", x.short, x.big_unsettled.0, x.big_unsettled.1))
        )?;
    }
    s.push_str(&parts.box_pairs);
    writeln!(s)?;
    s.push_str(DIFFERENCES);
    writeln!(s, "\n## Checks\n")?;
    s.push_str(&parts.checks);
    writeln!(
        s,
        "\n## Larger samples (untimed)\n\n{SAMPLE_FACTOR} × {n} drops per engine, step and body, the first {n} the \
         timed ones: the project's batched drops at {r_l} (drop by drop its plain drops), its default numerics \
         (flock-certified + batched at {d_l}) and MuJoCo's drops at both steps, per flock (fraction of settled drops, \
         95 % interval; static = quasi-static basin probability), with each flock's share of two χ² statistics of \
         homogeneity (which take the two samples as independent: a description of where they differ; the tests \
         use the pairing)."
    )?;
    s.push_str(&parts.sample_tables);
    writeln!(
        s,
        "\n## Rapier's solver sub-steps (untimed)\n\nThe project's drops at {r_l} (flock-certified + batched) \
         with {} solver iterations (rapier's sub-steps of a step; the default is 4), the same {SAMPLE_FACTOR} × {n} \
         releases, each compared drop by drop with MuJoCo at {r_l} and with the project at {} iterations (paired p: \
         Stuart–Maxwell). Drops/s here are indicative (untimed conditions).",
        SUBSTEPS.map(|k| k.to_string()).join(", "),
        SUBSTEPS[SUBSTEPS.len() - 1],
    )?;
    s.push_str(&parts.substep_tables);
    writeln!(s, "\n## Per flock, timed runs (fraction of settled drops, 95 % interval; static = quasi-static basin probability)")?;
    s.push_str(&parts.flock_tables);
    Ok(s)
}

fn plot(path: &Path, modes: &[Mode], bars: &[(String, Vec<(f64, f64)>)]) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    let dts = mj_dts();
    let (r_l, d_l) = (step_label(dts[0]), step_label(dts[1]));
    // One bar per mode against MuJoCo at the reference step, then the default numerics against
    // MuJoCo at the same step.
    let mut series: Vec<String> = modes.iter().map(|m| format!("{} ÷ MuJoCo at {r_l}", m.short)).collect();
    series.push(format!("{} ÷ MuJoCo at {d_l}, the same step", modes[3].short));
    let slots = series.len();
    rocking_stones::plot::draw_png(path, (1200, 720), |root| {
        root.fill(&WHITE)?;
        let values = || bars.iter().flat_map(|(_, v)| v.iter().flat_map(|r| [r.0, r.1]));
        // Log axis: a ratio and its inverse are as far from 1×; room above the bars for the legend.
        let bottom = values().fold(0.5, f64::min) * 0.8;
        let top = values().fold(10.0, f64::max) * 12.0;
        let mut chart = ChartBuilder::on(root)
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
        // The reference level 1×, drawn first so that the bars and their labels lie over it (10× and
        // 100× are the axis' major grid lines).
        let references = [(1.0, "1×: as fast as MuJoCo")];
        let reference_style = |_: f64| BLACK.stroke_width(2);
        for (level, _) in references {
            chart.draw_series(DashedLineSeries::new(
                vec![(-0.5, level), (bars.len() as f64 - 0.5, level)],
                10,
                6,
                reference_style(level),
            ))?;
        }
        let w = 0.86 / slots as f64;
        let x0 = |k: usize, slot: usize| k as f64 - 0.43 + slot as f64 * w;
        for (slot, label) in series.iter().enumerate() {
            let colour = series_color(slot);
            chart
                .draw_series(bars.iter().enumerate().map(|(k, (_, v))| {
                    Rectangle::new([(x0(k, slot), bottom), (x0(k, slot) + w * 0.9, v[slot].0)], colour.filled())
                }))?
                .label(format!("{label} (its mj_step loop + rest check)"))
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 14, y + 5)], colour.filled()));
        }
        // The ratio against MuJoCo's loop, written above each bar.
        use plotters::style::text_anchor::{HPos, Pos, VPos};
        let label = TextStyle::from((FONT_FAMILY, 12).into_font()).pos(Pos::new(HPos::Center, VPos::Bottom));
        chart.draw_series(bars.iter().enumerate().flat_map(|(k, (_, v))| {
            let label = label.clone();
            (0..slots).map(move |slot| {
                let top = v[slot].0.max(v[slot].1) * 1.04;
                Text::new(format!("{:.1}×", v[slot].0), (x0(k, slot) + w * 0.45, top), label.clone())
            })
        }))?;
        chart
            .draw_series(bars.iter().enumerate().flat_map(|(k, (_, v))| {
                (0..slots).map(move |slot| {
                    PathElement::new(
                        vec![(x0(k, slot), v[slot].1), (x0(k, slot) + w * 0.9, v[slot].1)],
                        BLACK.stroke_width(3),
                    )
                })
            }))?
            .label("the same bar against MuJoCo's stepping alone (no Python per step)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], BLACK.stroke_width(3)));
        // The reference lines' legend entries (the lines themselves are drawn under the bars).
        for (level, label) in references {
            let style = reference_style(level);
            chart
                .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
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
        Ok(())
    })?;
    Ok(())
}
