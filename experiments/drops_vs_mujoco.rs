//! Drops per second per core of this project against MuJoCo under the same physics, and the
//! agreement of their outcome statistics drop by drop on the same releases; what it compares and
//! how is in its README's template, `experiments/readme/drops_vs_mujoco.md`, the MuJoCo side in
//! `shared/mujoco.rs` and `shared/mujoco_drops.py`.
//!
//! Run: `cargo experiment drops_vs_mujoco [-- N]` (N = 300 drops per body and mode;
//! `--seed` the releases' seed, default 7) → `results/drops_vs_mujoco/`. Needs MuJoCo's Python
//! bindings (`pip install mujoco`) in `python3` or in the interpreter named by `ROCKING_PYTHON`.

#![recursion_limit = "256"] // the README's context is one large `json!`

use experiments::{harness, mujoco};
use harness::{fixed, Result, Results};
use mujoco::*;
use rocking_stones::dynamics::drops::compare::{agreement, chi_square_shares, matching_drops, Match};
use rocking_stones::dynamics::drops::montecarlo::{run_timed, TimedRun};
use rocking_stones::dynamics::drops::simulate::flat_restitution;
use rocking_stones::dynamics::stone::REST_TOLERANCE;
use rocking_stones::plot::BarSlot;
use rocking_stones::prelude::*;
use rocking_stones::report::drops::flock_cells;
use serde_json::{json, Value};
use std::path::Path;

/// Rounds of timing (each: MuJoCo's drops at both steps, then every mode of the project); the
/// fastest round counts.
const REPEATS: usize = 3;
/// MuJoCo's default contact time constant (s), the first number of solref (`mujoco_drops.py`).
const MJ_TIMECONST: f64 = 0.02;
const BLACK: RGBColor = RGBColor(0, 0, 0);
/// The bodies' names under their bars in `ratio.png`.
const BAR_NAMES: [&str; 3] =
    ["bundled stone (581 hull vertices)", "synthetic pebble (500 hull vertices)", "box 1 × 0.8 × 0.5"];

fn main() -> Result<()> {
    let (n, common) = harness::count_args(
        "Drops per second of the project against MuJoCo.",
        "Drops per body and mode (the untimed samples have ten times as many)",
        300,
    );
    let (seed, modes, dts) = (common.seed_or(7), modes(), mj_dts());
    let (nd, big) = (n as f64, n * SAMPLE_FACTOR);
    let bench = Bench::new("drops_vs_mujoco", seed, n, big)?;
    let out = Results::open("drops_vs_mujoco", &common)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let (bodies, stones, reference) = (&bench.bodies, &bench.stones, &bench.reference);
    let (python, script) = (&bench.python, bench.script.display());
    // REPEATS rounds, each MuJoCo's drops at both steps and then every mode of the project, so
    // that both engines are timed under the same load of this shared machine; the fastest round
    // counts for each. MuJoCo at the longer step is the model of the reference step (its solref,
    // calibrated there) with only the step changed, as the project keeps its parameters at its
    // longer step; in the first round, an untimed check runs MuJoCo at the longer step with the
    // damping ratio calibrated again at that step (`recal`).
    // MuJoCo's runs at each step, one a round.
    let (mut mj_rounds, mut recal): ([Vec<MjOut>; 2], _) = ([Vec::new(), Vec::new()], None);
    let mut best: Vec<Vec<Option<TimedRun>>> = bodies.iter().map(|_| modes.iter().map(|_| None).collect()).collect();
    for round in 1..=REPEATS {
        let sample = if round == 1 { big } else { n };
        eprintln!("round {round} of {REPEATS}: MuJoCo at dt {} ({python} {})", step_label(dts[0]), script);
        let first = bench.run(sample, dts[0], None)?;
        eprintln!("round {round} of {REPEATS}: MuJoCo at dt {} ({python} {})", step_label(dts[1]), script);
        mj_rounds[1].push(bench.run(sample, dts[1], Some(first.solref))?);
        mj_rounds[0].push(first);
        if round == 1 {
            let d = step_label(dts[1]);
            eprintln!("round 1 of {REPEATS}: MuJoCo at dt {d}, damping ratio calibrated at that step (untimed check)");
            recal = Some(bench.run(n, dts[1], None)?);
        }
        eprintln!("round {round} of {REPEATS}: the project");
        for (b, ((name, _), stone)) in bodies.iter().zip(stones).enumerate() {
            for (k, m) in modes.iter().enumerate() {
                let r = run_timed(&pool, stone, &header(name, n, m, seed), m.batch)?;
                eprintln!("  {name} {}: {:.1} drops/s", m.name, r.rate());
                best[b][k] = Some(if let Some(fastest) = best[b][k].take() { fastest.faster(r) } else { r });
            }
        }
    }
    let (mj0, recal) = ([&mj_rounds[0][0], &mj_rounds[1][0]], recal.expect("round 1 ran"));
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
    for (b, ((name, _), stone)) in bodies.iter().zip(stones).enumerate() {
        let short = ["stone", "pebble", "box"][b];
        // MuJoCo's drops at each step, classified by the project's rule; its fastest round.
        let mj: Vec<MjSide> = (0..2).map(|s| MjSide::of(stone, name, &mj_rounds[s], b, dts[s], seed)).collect();
        let recal_drops = &recal.bodies[b].drops;
        let recal_report = classify(stone, name, recal_drops, dts[1], seed).0;
        let is_box = mj0[0].bodies[b].flat_restitution.is_some();
        if is_box {
            for (s, &dt) in dts.iter().enumerate() {
                let [m, ms] = mj0[s].bodies[b].flat_restitution.unwrap_or([f64::NAN; 2]);
                flat.push((dt, flat_restitution(stone, &params(dt).sim, &box_normal(), HEIGHT), m, ms));
            }
        }
        // The project's modes, their fastest round.
        let rows: Vec<TimedRun> = best[b].iter_mut().map(|r| r.take().expect("REPEATS ≥ 1")).collect();
        let checks = mj_checks(&bench, &mj_rounds, b, &mj, &rows[0].outcomes);
        // The larger, untimed samples: the batched project at the reference step (drop by drop
        // the plain drops), the default numerics, and MuJoCo at both steps.
        let project = run_timed(&pool, stone, &header(name, big, &modes[1], seed), DEFAULT_BATCH)?;
        let fast = run_timed(&pool, stone, &header(name, big, &modes[3], seed), modes[3].batch)?;
        let versus = |a: &Outcomes, b: &Outcomes| agreement(&stone.facet_flock, a, b);
        let big_ref = versus(&project.outcomes, &mj[0].big_outcomes);
        let big_fast_same = versus(&fast.outcomes, &mj[1].big_outcomes);
        let big_fast_ref = versus(&fast.outcomes, &mj[0].big_outcomes);
        // The two steps of one engine start from the same orientations: their `same` counts the
        // drops that end in the same flock at both steps.
        let big_mj_steps = versus(&mj[1].big_outcomes, &mj[0].big_outcomes);
        let big_steps = versus(&fast.outcomes, &project.outcomes);
        let (pb, fb) = (&project.report, &fast.report);
        let counts = |r: &DropReport| r.flock_counts(stone.flock_kinds.len());
        let shares = chi_square_shares(&counts(pb), &counts(&mj[0].big));
        let shares_mj = chi_square_shares(&counts(&mj[1].big), &counts(&mj[0].big));
        let kind = |k: usize| stone.flock_kinds[k].name();
        let cell = |r: &DropReport, k: usize| r.flock_fraction_with_ci(k, 3);
        // The flock with the largest share of χ² between two samples, its fraction in each.
        let widest = |v: &[f64], a: &DropReport, b: &DropReport| {
            let k = (0..v.len()).max_by(|&x, &y| v[x].total_cmp(&v[y])).expect("a flock");
            json!({"k": k, "kind": kind(k), "a": fixed(a.flock_fraction(k), 3), "b": fixed(b.flock_fraction(k), 3)})
        };
        let fast_shares = chi_square_shares(&counts(fb), &counts(&mj[1].big));
        let sample = json!({
            "unsettled": [pb.unsettled, fb.unsettled, mj[0].big.unsettled, mj[1].big.unsettled],
            "ref": agreement_json(&big_ref), "mj_steps": agreement_json(&big_mj_steps),
            "fast_same": agreement_json(&big_fast_same), "fast_ref": agreement_json(&big_fast_ref),
            "steps": agreement_json(&big_steps), "same_mj": big_mj_steps.same, "same_project": big_steps.same,
            "flocks": pb.flocks.iter().map(|f| json!({
                "id": f.id, "kind": kind(f.id), "static": fixed(f.static_probability, 3),
                "cells": [cell(pb, f.id), cell(&mj[0].big, f.id), cell(fb, f.id), cell(&mj[1].big, f.id)],
                "shares": [fixed(shares[f.id], 0), fixed(shares_mj[f.id], 0)],
            })).collect::<Vec<_>>(),
        });
        if is_box {
            // The box: its six flocks are its faces; pool the two faces of each pair (by symmetry the same).
            let axis_of = |k: usize| {
                let f = (0..stone.facet_flock.len()).find(|&f| stone.facet_flock[f] == Some(k)).expect("a facet");
                stone.body.facet_normals[f].iamax()
            };
            let pooled = |r: &DropReport, statics: bool| {
                let sums = r.pooled_flocks(3, axis_of).into_iter().map(|(f, s)| fixed(if statics { s } else { f }, 3));
                sums.collect::<Vec<_>>().join(" / ")
            };
            // MuJoCo − project per face at the reference step, the two faces of each pair side by side.
            let mut diffs = [Vec::new(), Vec::new(), Vec::new()];
            for f in &pb.flocks {
                diffs[axis_of(f.id)].push(format!("{:+.3}", mj[0].big.flock_fraction(f.id) - f.fraction));
            }
            box_pairs = json!({
                "pooled": [pooled(pb, false), pooled(&mj[0].big, false), pooled(fb, false), pooled(&mj[1].big, false),
                    pooled(pb, true)],
                "diffs": diffs.map(|d| d.join(" / ")),
                "apart": big_ref.p < 0.05 && flat.iter().all(|&(_, r, m, _)| (r - m).abs() > 0.01),
            });
        }
        let (mut ratios, mut table, mut p_modes, mut same_modes) = (vec![], vec![], vec![], vec![]);
        for (m, r) in modes.iter().zip(&rows) {
            let s = dts.iter().position(|&d| d == m.dt).expect("MuJoCo runs at every mode's step");
            let rate = r.rate();
            let ratio = |secs: f64| rate / (nd / secs);
            let (rl, rs, sl, ss) = (ratio(mj[0].loop_s), ratio(mj[0].step_s), ratio(mj[s].loop_s), ratio(mj[s].step_s));
            ratios.push((rl, rs));
            let vs_same = versus(&r.outcomes, &mj[s].outcomes);
            let (p, p_same, us_k) = (versus(&r.outcomes, &mj[0].outcomes).p, vs_same.p, r.micros_per_step());
            p_modes.push(fixed(p, 2));
            if p < worst.0 {
                worst = (p, short);
            }
            let same = matching_drops(&stone.facet_flock, &r.outcomes, &rows[0].outcomes, Match::Flock);
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
        let ratio = |secs: f64| rows[3].rate() / (nd / secs);
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
                let (dt, rate, t, kl) = (dts[s], nd / secs, rep.mean_time, rep.fit_flocks.kl_divergence);
                let (settled, off, p) = (rep.settled, rep.off_equilibrium, p_cell(4));
                csv += &format!(
                    "\"{name}\",mujoco,\"{label}\",1,none,{dt:.6},{n},{secs:.4},{rate:.2},,,,,{us:.3},{t:.4},{settled},0,\
                     {off},{p},,{kl:.5}\n"
                );
            }
            if side.big.unsettled > 0 {
                mj_unsettled.push(json!({"short": short, "step": step_label(dts[s]), "big": side.big.unsettled,
                    "drops": side.big.drops, "timed": side.report.unsettled}));
            }
        }
        let step_us = |s: usize| 1e6 * mj[s].step_s / mj[s].steps;
        let loop_us = 1e6 * mj[0].loop_s / mj[0].steps;
        lead.push(rows[0].micros_per_step() / step_us(0));
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
            "ratios": ratios.iter().map(|r| json!({"l": fixed(r.0, 2), "s": fixed(r.1, 2)})).collect::<Vec<_>>(),
            "us0": fixed(rows[0].micros_per_step(), 2), "us1": fixed(rows[1].micros_per_step(), 2),
            "t0": fixed(rows[0].report.mean_time, 2), "t2": fixed(rows[2].report.mean_time, 2),
            "mj_step_us0": fixed(step_us(0), 2), "mj_step_us1": fixed(step_us(1), 2), "mj_loop_us0": fixed(loop_us, 2),
            "mj_t0": t(0), "mj_t1": t(1), "loop_share": fixed(100.0 * (loop_us / step_us(0) - 1.0), 0),
            "mj_loop_rate0": fixed(loop_rate(0), 1), "mj_loop_rate1": fixed(loop_rate(1), 1),
            "mj_loop_x": fixed(loop_rate(1) / loop_rate(0), 2), "mj_step_rate0": fixed(step_rate(0), 1),
            "mj_step_rate1": fixed(step_rate(1), 1),
            "recal_unsettled": format!("{} of {}", recal_report.unsettled, recal_report.drops),
            "recal_t": fixed(recal_report.mean_time, 2),
            "recal_warned": recal_drops.iter().filter(|d| d.warnings > 0).count(),
            "p_mj_steps": fixed(p_mj_steps, 2), "big_mj_steps_p": fixed(big_mj_steps.p, 3),
            "mj_steps_low": big_mj_steps.p < 0.05, "same_mj_big": format!("{} of {big}", big_mj_steps.same),
            "widest_mj_steps": widest(&shares_mj, &mj[1].big, &mj[0].big),
            "p_modes": p_modes.join(" / "), "p_fast_same": fixed(versus(&rows[3].outcomes, &mj[1].outcomes).p, 2),
            "same_flock": [same_modes[1], same_modes[2]],
            "big_ref_same": format!("{} of {}", big_ref.same, big_ref.both),
            "big_ref_p": fixed(big_ref.p, 3), "ref_low": big_ref.p < 0.05, "widest": widest(&shares, pb, &mj[0].big),
            "big_fast_same_p": fixed(big_fast_same.p, 3), "fast_same_low": big_fast_same.p < 0.05,
            "widest_fast_same": widest(&fast_shares, fb, &mj[1].big),
            "big_fast_ref_p": fixed(big_fast_ref.p, 3), "fast_ref_low": big_fast_ref.p < 0.05,
            "big_steps_p": fixed(big_steps.p, 3), "steps_low": big_steps.p < 0.05,
            "same_project_big": format!("{} of {big}", big_steps.same),
            "big_unsettled": format!("{} / {}", pb.unsettled, fb.unsettled),
            "flocks": flock_cells(&reports, 3),
            "kl": reports.iter().map(|r| fixed(r.fit_flocks.kl_divergence, 4)).collect::<Vec<_>>(),
        }));
        all_same &= same_modes[1] == n as usize && same_modes[2] == n as usize;
        bars.push((BAR_NAMES[b], ratios));
    }
    let range = |k: usize, stepping: bool| {
        let v: Vec<f64> = bars.iter().map(|(_, r)| if stepping { r[k].1 } else { r[k].0 }).collect();
        let (lo, hi) = (v.iter().copied().fold(f64::INFINITY, f64::min), v.iter().copied().fold(0.0, f64::max));
        format!("{lo:.1}–{hi:.1}×")
    };
    let all = |f: fn(f64) -> bool| lead.iter().all(|&q| f(q));
    let same = all(|q| (2.0 / 3.0..=1.5).contains(&q));
    let lead = [(same, "same"), (all(|q| q < 1.0), "project"), (all(|q| q > 1.0), "mujoco")];
    let lead = lead.iter().find(|c| c.0).map_or("depends", |c| c.1);
    let longer =
        [std::cmp::Ordering::Greater, std::cmp::Ordering::Less].iter().position(|o| longer.iter().all(|x| x == o));
    let (m, m1, r) = (&mj0[0], &mj0[1], &recal);
    out.readme(
        include_str!("readme/drops_vs_mujoco.md"),
        json!({
            "n": n, "big": big, "factor": SAMPLE_FACTOR, "repeats": REPEATS, "batch": DEFAULT_BATCH, "seed": seed,
            "r_l": step_label(dts[0]), "d_l": step_label(dts[1]), "steps": dts.map(step_label),
            "height": HEIGHT.to_string(), "friction": FRICTION.to_string(), "restitution": RESTITUTION.to_string(),
            "linear_damping": LINEAR_DAMPING.to_string(), "angular_damping": ANGULAR_DAMPING.to_string(),
            "timeconst": MJ_TIMECONST.to_string(), "rest_tolerance": REST_TOLERANCE.to_string(),
            "max_time": reference.sim.numerics.max_time.to_string(),
            "mjs": m.settings(), "mj": {
                "solref0": m.solref[0].to_string(), "solref1": fixed(m.solref[1], 4),
                "mj1_solref0": m1.solref[0].to_string(),
                "mj1_solref1": fixed(m1.solref[1], 4), "e": fixed(m.ball_restitution, 3),
                "e_speeds": fixed(m.ball_restitution_speeds, 3),
                "e1": fixed(m1.ball_restitution, 3), "e1_speeds": fixed(m1.ball_restitution_speeds, 3),
                "recal_solref1": fixed(r.solref[1], 4), "recal_e": fixed(r.ball_restitution, 3),
                "steps_per_tc": fixed(MJ_TIMECONST / dts[1], 1),
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
    let (r_l, d_l, loop_) = (step_label(REFERENCE_DT), step_label(modes[3].dt), "(its mj_step loop + rest check)");
    let mut series: Vec<String> = modes.iter().map(|m| format!("{} ÷ MuJoCo at {r_l} {loop_}", m.short)).collect();
    series.push(format!("{} ÷ MuJoCo at {d_l}, the same step {loop_}", modes[3].short));
    let values = || bars.iter().flat_map(|(_, v)| v.iter().flat_map(|r| [r.0, r.1]));
    let (bottom, top, right) =
        (values().fold(0.5, f64::min) * 0.8, values().fold(10.0, f64::max) * 12.0, bars.len() as f64 - 0.5);
    let y = Axis::log("drops/s of the project ÷ drops/s of MuJoCo (log scale)", bottom, top)
        .format(|y| format!("{}×", rocking_stones::plot::log_tick(y)))
        .space(70);
    let loops: Vec<Vec<f64>> = bars.iter().map(|(_, v)| v.iter().map(|r| r.0).collect()).collect();
    // The reference level 1× first, so that the bars and their labels lie over it.
    let mut chart = Chart::new(Axis::categories("", bars.iter().map(|b| b.0.to_string()).collect()), y)
        .title("Drops per core: this project ÷ MuJoCo, same physics, one core")
        .dashed(&[(-0.5, 1.0), (right, 1.0)], BLACK)
        .grouped_bars(&loops, &series, bottom, 0.86);
    for (k, (_, v)) in bars.iter().enumerate() {
        for (slot, &(l, s)) in v.iter().enumerate() {
            // The ratio against MuJoCo's loop above each bar, the mark of the stepping alone across it.
            let b = BarSlot { slot, slots: series.len(), width: 0.86 };
            let (x0, w) = (b.left(k), b.slot_width());
            chart = chart
                .line_width(&[(x0, s), (x0 + w * 0.9, s)], BLACK, 3)
                .text(format!("{l:.1}×"), (x0 + w * 0.05, l.max(s) * 1.3));
        }
    }
    chart
        .legend(Mark::WideLine(BLACK, 3), "the same bar against MuJoCo's stepping alone (no Python per step)")
        .legend(Mark::Dashed(BLACK), "1×: as fast as MuJoCo")
        .save(path, (1200, 720))?;
    Ok(())
}
