//! Rapier's solver sub-steps (its solver iterations per step, 2 to 32) against MuJoCo, drop by
//! drop, on the releases and physics of `drops_vs_mujoco` (the MuJoCo side both share is
//! `shared/mujoco.rs`); what it shows is in its README's template,
//! `experiments/readme/drops_solver_substeps.md`.
//!
//! Run: `cargo experiment drops_solver_substeps [-- N]` (10 × N releases per body and
//! count, N = 300; `--seed` the releases' seed, default 7) → `results/drops_solver_substeps/`. Needs
//! MuJoCo's Python bindings (`pip install mujoco`) in `python3` or in the interpreter named by
//! `ROCKING_PYTHON`.

use experiments::{harness, mujoco};
use harness::{fixed, Result, Results};
use mujoco::*;
use rocking_stones::dynamics::drops::compare::{agreement, Agreement};
use rocking_stones::dynamics::drops::montecarlo::{run_timed, TimedRun};
use rocking_stones::prelude::*;
use serde_json::{json, Value};

/// Rapier solver iterations (its sub-steps per step) of the convergence check; the project's
/// default is 4 (`DropParams::solver_iterations`), the last is the reference.
const SUBSTEPS: [usize; 5] = [2, 4, 8, 16, 32];

/// The untimed convergence check of one body: its `drops` releases in mode `m` at each of
/// [`SUBSTEPS`] solver iterations, compared drop by drop with MuJoCo's sample `mj` and with the
/// finest.
fn substeps(pool: &rayon::ThreadPool, stone: &Stone, h: RunHeader, m: &Mode, mj: &MjSide) -> Result<Value> {
    let runs: Vec<TimedRun> = SUBSTEPS
        .iter()
        .map(|&k| {
            eprintln!("  {}: {k} solver iterations (untimed)", h.mesh);
            let mut h = h.clone();
            h.params.sim.numerics.solver_iterations = k;
            run_timed(pool, stone, &h, m.batch)
        })
        .collect::<Result<_, _>>()?;
    let finest = &runs[runs.len() - 1];
    let shown: Vec<usize> = (0..stone.flock_kinds.len()).filter(|&k| finest.report.flock_count(k) > 0).collect();
    let versus = |a: &Outcomes, b: &Outcomes| agreement(&stone.facet_flock, a, b);
    let vs: Vec<(Agreement, Agreement)> =
        runs.iter().map(|r| (versus(&r.outcomes, &mj.big_outcomes), versus(&r.outcomes, &finest.outcomes))).collect();
    // Is the default converged, and from how many sub-steps on are the statistics those of the finest?
    let last = SUBSTEPS.len() - 1;
    let default = SUBSTEPS.iter().position(|&k| k == h.params.sim.numerics.solver_iterations).expect("in SUBSTEPS");
    let converged = (0..last).find(|&i| vs[i..last].iter().all(|v| v.1.p >= 0.05)).map(|i| SUBSTEPS[i]);
    Ok(json!({
        "shown": shown,
        "rows": SUBSTEPS.iter().zip(&runs).zip(&vs).map(|((k, r), (a, b))| json!({
            "k": k, "rate": fixed(r.rate(), 0), "mj": agreement_json(a), "fine": agreement_json(b),
            "fr": shown.iter().map(|&f| fixed(r.report.flock_fraction(f), 4)).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "mj": shown.iter().map(|&f| fixed(mj.big.flock_fraction(f), 4)).collect::<Vec<_>>(),
        "default_ok": vs[default].1.p >= 0.05, "p_default": fixed(vs[default].1.p, 3), "converged": converged,
        "agree": SUBSTEPS.iter().zip(&vs).filter(|(_, v)| v.0.p >= 0.05).map(|(k, _)| k).collect::<Vec<_>>(),
    }))
}

fn main() -> Result<()> {
    let (n, common) = harness::count_args(
        "Rapier's solver sub-steps against MuJoCo.",
        "The samples have ten times N releases per body (N as in `drops_vs_mujoco`)",
        300,
    );
    let (seed, mode) = (common.seed_or(7), modes()[2].clone());
    let big = n * SAMPLE_FACTOR;
    let bench = Bench::new("drops_solver_substeps", seed, n, big)?;
    let out = Results::open("drops_solver_substeps", &common)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    // MuJoCo at the reference step, its damping ratio calibrated there (as in `drops_vs_mujoco`).
    eprintln!("MuJoCo at dt {} ({} {})", step_label(REFERENCE_DT), bench.python, bench.script.display());
    let mj = bench.run(big, REFERENCE_DT, None)?;
    let mut bodies = Vec::new();
    for (b, ((name, _), stone)) in bench.bodies.iter().zip(&bench.stones).enumerate() {
        let side = MjSide::of(stone, name, std::slice::from_ref(&mj), b, REFERENCE_DT, seed);
        let sub = substeps(&pool, stone, header(name, big, &mode, seed), &mode, &side)?;
        bodies.push(json!({"name": name, "sub": sub}));
    }
    let context = json!({
        "n": n, "factor": SAMPLE_FACTOR, "r_l": step_label(REFERENCE_DT), "substeps": SUBSTEPS,
        "mjs": mj.settings(), "bodies": bodies,
    });
    out.readme(include_str!("readme/drops_solver_substeps.md"), context)
}
