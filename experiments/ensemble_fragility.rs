//! How good are ensemble probabilities of toppling, and against what truth? Freestanding blocks
//! under an ensemble (unknown azimuth, sign), simulated and by Housner's equation, fitted with the
//! form of Purvance, Anooshehpoor & Brune (2008); the ensemble's P scored beside yes/no forecasts
//! on simulated truths. Prose: `experiments/readme/ensemble_fragility.md`.
//! Run: `cargo experiment ensemble_fragility` → `results/ensemble_fragility/`.

use rocking_stones::dynamics::shaking::ensemble::{draw, Draw};
use rocking_stones::dynamics::shaking::housner::{block_stone, HousnerBlock as Block};
use rocking_stones::dynamics::shaking::{default_poses, rock_params, run_batch, EnsembleSpec, Pose};
use rocking_stones::dynamics::shaking::{RecordRun, RockSetup, Uncertainty};
use rocking_stones::ground_motion::fragility::{FragilitySurface, Run};
use rocking_stones::ground_motion::synthetic::{noise_family, one_sine_pulse, Noise};
use rocking_stones::ground_motion::Record;
use rocking_stones::plot::{colors::GREY, reliability_diagram};
use rocking_stones::prelude::*;
use rocking_stones::stats::{ensemble_brier, forecast_scores, nonnegative_range, oracle_brier};
use serde_json::{json, Value};
use std::time::Instant;

use experiments::{harness, rocks};
use harness::{columns, fixed, Context, Result, Results};
use rocks::row;

/// Members of a block's forecast ensemble, and Housner rocks drawn as its truth.
const BLOCK_MEMBERS: u64 = 16;
const BLOCK_TRUTHS: u64 = 64;
/// The quarry stone: forecast members 0..32, held-out truth 32..64.
const STONE_MEMBERS: u64 = 32;
const STONE_TRUTHS: u64 = 32;
/// PGA/(g tan α) of the block runs (capped at 1.2 g).
const X_GRID: [f64; 8] = [0.8, 1.0, 1.25, 1.6, 2.0, 2.5, 3.2, 4.0];
/// Half-depth of the blocks (h = 1): rocking across it needs 1.5 g, above every PGA run, and
/// friction 1.5 keeps them from sliding — the two assumptions of Housner's equation.
const DEPTH: f64 = 1.5;
const FRICTION: f64 = 1.5;
/// The stream of the blocks' truth draws, independent of the forecast members'.
const TRUTH_OFFSET: u64 = 1_000;
/// p·PGV/PGA: the plot's axis, and the values at which the P = 0.5 contours are compared.
const TAU_AXIS: [f64; 2] = [0.1, 6.0];
const TAU_GRID: [f64; 5] = [0.3, 0.5, 1.0, 2.0, 3.0];
/// The blocks 2b × 2d × 2h (h = 1 mesh unit), scaled to a semi-diagonal R of their rocking plane.
const BLOCKS: [Block; 5] = [
    Block { tan_alpha: 0.25, r_m: 1.0 },
    Block { tan_alpha: 0.15, r_m: 1.0 },
    Block { tan_alpha: 0.4, r_m: 1.0 },
    Block { tan_alpha: 0.25, r_m: 0.5 },
    Block { tan_alpha: 0.25, r_m: 2.0 },
];

fn block_name(b: &Block) -> String {
    format!("tan{:.2}_R{}", b.tan_alpha, b.r_m)
}
/// The range of p·PGV/PGA block `b`'s records cover.
fn taus(b: &Block, r: &BlockResult) -> (f64, f64) {
    nonnegative_range(r.cases.iter().map(|c| b.p() * c.run.motion.pgv_over_pga_s))
}
/// PGA₅₀/(g tan α) of block `b`'s surface `s` at p·PGV/PGA = `tau`.
fn pga50(b: &Block, s: Option<&FragilitySurface>, tau: f64) -> Option<f64> {
    b.dimensionless_pga_at(s?, 0.5, tau)
}

/// One record × scale of a rock: as-given run, forecast members, Housner's P, nominal run, truths.
struct Case {
    rock: String,
    run: RecordRun,
    settled: usize,
    overturned: usize,
    ode: Option<f64>,
    nominal: bool,
    truths: Vec<bool>,
}

impl Case {
    /// The case of the as-given run `d`, its nominal member among `nominal`.
    fn of(rock: String, d: &RecordRun, nominal: &[RecordRun], forecast: &[&RecordRun], truths: Vec<bool>) -> Case {
        let settled: Vec<_> = forecast.iter().filter(|m| m.rock.settled).collect();

        Case {
            rock,
            run: d.clone(),
            settled: settled.len(),
            overturned: settled.iter().filter(|m| m.rock.overturned).count(),
            ode: None,
            nominal: nominal.iter().find(|r| r.motion.same_as(&d.motion)).expect("a nominal run").rock.overturned,
            truths,
        }
    }
    fn p(&self) -> f64 {
        match self.settled {
            0 => 0.5,
            n => self.overturned as f64 / n as f64,
        }
    }
    fn yes(&self) -> usize {
        self.truths.iter().filter(|&&y| y).count()
    }
}

/// A block's cases, surfaces fitted to the simulation and to Housner's equation, runs, seconds.
struct BlockResult {
    cases: Vec<Case>,
    surface: Option<FragilitySurface>,
    ode_surface: Option<FragilitySurface>,
    runs: usize,
    seconds: f64,
}

fn run_block(b: &Block, records: &[Record], seed: u64) -> Result<BlockResult> {
    let t0 = Instant::now();
    let (stone, k) = block_stone(b.tan_alpha, DEPTH, 1.0, Some(0.01))?;
    let bottom = stone.stable()[k].index;
    // Mesh: h = 1, rocking semi-diagonal √(tan²α + 1) mesh units = R metres.
    let unit = b.r_m / (b.tan_alpha * b.tan_alpha + 1.0).sqrt();
    let mut params = rock_params(Surface::RockOnConcrete, stone.body.r_max * unit)?;
    (params.sim.contact.friction, params.sim.contact.restitution) = (FRICTION, 0.0);
    let setup = RockSetup::with_params(&stone, Pose::Equilibrium { id: bottom }, unit, 0.0, params);
    let uncertainty = Uncertainty { azimuth_deg: Some([0.0, 360.0]), random_sign: true, ..Uncertainty::default() };
    let spec = EnsembleSpec { uncertainty: uncertainty.clone(), seed, members: BLOCK_MEMBERS };
    let scales: Vec<f64> = X_GRID.iter().map(|x| x * b.tan_alpha).filter(|&pga| pga <= 1.2 + 1e-9).collect();
    let batch = |spec: Option<&EnsembleSpec>| run_batch(&stone, &setup, records, &scales, spec, &[], &|_| {});
    let (ensemble, single, nominal) = (batch(Some(&spec))?, batch(None)?, batch(Some(&spec.nominal(&setup)))?);
    let (mut cases, mut ode_points) = (Vec::new(), Vec::new());
    for d in &single.runs {
        let members: Vec<&RecordRun> = ensemble.runs.iter().filter(|r| r.motion.same_as(&d.motion)).collect();
        let record = records.iter().find(|r| r.name == d.motion.record).expect("a record of the batch");
        // Housner's equation on draws: the record's component in the rocking plane.
        let housner = |draws: Vec<Draw>| b.overturns_drawn(record, d.motion.scale, &draws);
        let same = housner(members.iter().map(|m| m.member.expect("an ensemble run")).collect());
        let truths = housner((0..BLOCK_TRUTHS).map(|k| draw(&uncertainty, &setup, seed, TRUTH_OFFSET + k)).collect());
        ode_points.extend(same.iter().map(|&overturned| Run::of(&d.motion, overturned)));
        let ode = Some(same.iter().filter(|&&o| o).count() as f64 / same.len() as f64);
        cases.push(Case { ode, ..Case::of(block_name(b), d, &nominal.runs, &members, truths) });
    }
    let r = BlockResult {
        cases,
        surface: ensemble.surface,
        ode_surface: FragilitySurface::fit(&ode_points).ok(),
        runs: ensemble.runs.len() + single.runs.len() + nominal.runs.len(),
        seconds: t0.elapsed().as_secs_f64(),
    };
    eprintln!("block {}: {} runs in {:.1} s", block_name(b), r.runs, r.seconds);
    Ok(r)
}

/// The quarry stone in its rocking pose at scanned size under two-component filtered noise:
/// its cases (forecast members, held-out truth members, the as-given run and the nominal
/// member), its pose, the seconds taken and the nominal member's inputs.
fn run_stone(seed: u64) -> Result<(Vec<Case>, String, f64, String)> {
    let t0 = Instant::now();
    let (_, stone) = rocks::of_file("data/meshes/stone_quarry_ibois_AAA_lowres_bin.ply")?;
    let (regular, rocking) = default_poses(&stone, stone.body.r_max)?;
    let pose = Pose::Equilibrium { id: rocking.or(regular).context("the quarry stone has no stable pose")? };
    let setup = RockSetup::new(&stone, pose, 1.0, Surface::RockOnConcrete, 0.0)?;
    let (contact_tolerance_m, azimuth_deg) = (Some([0.0, 2.0]), Some([0.0, 360.0])); // as stated: in mm
    let given = Uncertainty { contact_tolerance_m, azimuth_deg, random_sign: true, ..Uncertainty::default() };
    let uncertainty = Uncertainty::stated(&given, Surface::RockOnConcrete, [false; 3]);
    let spec = EnsembleSpec { uncertainty, seed, members: STONE_MEMBERS + STONE_TRUTHS };
    let records =
        noise_family(&Noise { components: 2, ..Noise::default() }, 1.0, &[0.2, 0.5, 1.0, 2.0], &[1], |t, _| {
            format!("noise2_T{t}")
        })?;
    let scales = [0.04, 0.06, 0.08, 0.11, 0.15, 0.2];
    let batch = |spec: Option<&EnsembleSpec>| run_batch(&stone, &setup, &records, &scales, spec, &[], &|_| {});
    let nominal_spec = spec.nominal(&setup);
    let (ensemble, single, nominal) = (batch(Some(&spec))?, batch(None)?, batch(Some(&nominal_spec))?);
    let d = draw(&nominal_spec.uncertainty, &setup, seed, 0);
    let (tol, delta) = (1e3 * d.contact_tolerance_m, 1e3 * d.rolling_resistance_m);
    let inputs = format!("base contact {tol:.1} mm, μ {}, e {}, δ {delta:.2} mm", d.friction, d.restitution);
    let cases = single.runs.iter().map(|d| {
        let settled = ensemble.runs.iter().filter(|r| r.motion.same_as(&d.motion) && r.rock.settled);
        let (forecast, truth): (Vec<&RecordRun>, Vec<&RecordRun>) =
            settled.partition(|r| r.member.expect("an ensemble run").member < STONE_MEMBERS);
        let truths = truth.iter().map(|r| r.rock.overturned).collect();
        Case::of("quarry_AAA".into(), d, &nominal.runs, &forecast, truths)
    });
    Ok((cases.collect(), format!("{pose}"), t0.elapsed().as_secs_f64(), inputs))
}

fn main() -> Result<()> {
    let common =
        harness::common_args("Ensemble fragility of blocks and of the quarry stone, scored on simulated truths.");
    let seed = common.seed_or(24);
    let out = Results::open("ensemble_fragility", &common)?;
    // One-component records scaled to PGA 1 g: filtered noise (4 periods × 2 seeds), pulses.
    let mut records =
        noise_family(&Noise::default(), 1.0, &[0.2, 0.5, 1.0, 2.0], &[1, 2], |t, s| format!("noise_T{t}_s{s}"))?;
    for tp in [0.5, 1.0, 2.0, 4.0] {
        records.push(Record { name: format!("pulse_T{tp}"), ..one_sine_pulse(1.0, tp, tp / 1000.0)? });
    }
    let blocks = BLOCKS.iter().map(|b| run_block(b, &records, seed)).collect::<Result<Vec<_>>>()?;
    let (stone, stone_pose, stone_seconds, nominal_inputs) = run_stone(seed)?;
    eprintln!("quarry stone: {} cases in {stone_seconds:.1} s", stone.len());
    let header = "rock,record,scale,pga_g,pgv_over_pga_s,members_settled,members_overturned,p_ensemble,\
                  p_housner_same_draws,deterministic_overturned,truths,truths_overturned,nominal_overturned";
    let cases = blocks.iter().flat_map(|b| &b.cases).chain(&stone).map(|c| {
        let (Case { rock, settled, overturned, nominal, .. }, d) = (c, &c.run);
        let (ode, p, n, k) = (c.ode.map_or(String::new(), |p| fixed(p, 4)), c.p(), c.truths.len(), c.yes());
        row(format!(
            "{rock},{},{},{:.5},{:.5},{settled},{overturned},{p:.4},{ode},{},{n},{k},{nominal}",
            d.motion.record, d.motion.scale, d.motion.pga_g, d.motion.pgv_over_pga_s, d.rock.overturned
        ))
    });
    out.csv("cases.csv", &columns(header), cases)?;
    let block_cases: Vec<&Case> = blocks.iter().flat_map(|b| &b.cases).collect();
    let stone_cases: Vec<&Case> = stone.iter().collect();
    let sets = [
        ("blocks", "Housner's equation on independent draws", &block_cases[..], BLOCK_MEMBERS),
        ("quarry stone", "held-out members (perfect model)", &stone_cases[..], STONE_MEMBERS),
    ];
    let mut scores = Vec::new();
    let scored: Vec<Value> = sets.iter().map(|set| score_set(set, &mut scores)).collect();
    let header = ["rocks", "forecast", "brier", "log_loss", "accuracy", "truths", "scored_against", "overturn_share"];
    out.csv("scores.csv", &header, scores)?;
    let reliability = sets.map(|(name, truth, cases, _)| {
        (format!("{name}, truth: {truth}"), cases.iter().map(|c| (c.p(), &c.truths[..])).collect())
    });
    let title = "Reliability: forecast P(overturn) against the truth's frequency";
    reliability_diagram(title, &reliability).save(&out.path("reliability.png"), (760, 700))?;

    let truths = |cases: &[&Case]| cases.iter().map(|c| c.truths.len()).sum::<usize>();
    out.readme(
        include_str!("readme/ensemble_fragility.md"),
        json!({
            "minutes": fixed((blocks.iter().map(|b| b.seconds).sum::<f64>() + stone_seconds) / 60.0, 0),
            "a": part_a(&out, &blocks)?, "sets": scored, "records": records.len(),
            "depth": (2.0 * DEPTH).to_string(), "friction": FRICTION.to_string(),
            "x_grid": format!("{X_GRID:?}"), "taus": TAU_GRID.map(|t| t.to_string()).join(", "),
            "block_members": BLOCK_MEMBERS, "block_truths": BLOCK_TRUTHS, "stone_members": STONE_MEMBERS,
            "stone_truths": STONE_TRUTHS, "block_cases": block_cases.len(), "stone_cases": stone_cases.len(),
            "block_truth_count": truths(&block_cases), "stone_truth_count": truths(&stone_cases),
            "stone_pose": stone_pose, "nominal_inputs": nominal_inputs,
        }),
    )
}

/// Part A: the fitted surfaces (`surfaces.csv`, `dimensionless.png`) and the README's values.
fn part_a(out: &Results, blocks: &[BlockResult]) -> Result<Value> {
    let (mut csv, mut rows, mut floor, mut worst, mut worst_beta) = (vec![], vec![], vec![], 0.0f64, 0.0f64);
    let (black, tau) = (RGBColor(0, 0, 0), Axis::log("p · PGV/PGA", TAU_AXIS[0], TAU_AXIS[1]));
    let mut chart = Chart::new(tau, Axis::log("PGA₅₀ / (g tan α)", 0.8, 8.0).space(70))
        .title("Freestanding blocks: P = 0.5 contour in Housner's dimensionless variables")
        .line(&[(TAU_AXIS[0], 1.0), (TAU_AXIS[1], 1.0)], GREY);
    for (k, (b, r)) in BLOCKS.iter().zip(blocks).enumerate() {
        chart = contours(chart, series_color(k + 1), b, r);
        let beta = |s: &Option<FragilitySurface>, i, se| {
            s.map_or("-".into(), |s| if se { s.coefficient_text(i, 2) } else { fixed(s.beta[i], 2) })
        };
        let mut cells = Vec::new();
        for &tau in &TAU_GRID {
            let (sim, ode) = (pga50(b, r.surface.as_ref(), tau), pga50(b, r.ode_surface.as_ref(), tau));
            let f = |x: Option<f64>| x.map_or("-".to_string(), |v| fixed(v, 2));
            cells.push(format!("{} / {}", f(sim), f(ode)));
            for (source, s, x) in [("simulation", &r.surface, sim), ("housner", &r.ode_surface, ode)] {
                let Some(s) = s else { continue };
                let mut fields =
                    vec![block_name(b), b.tan_alpha.to_string(), b.r_m.to_string(), fixed(b.p(), 4), source.into()];
                fields.extend(s.beta.iter().chain(&s.std_err).map(|&v| fixed(v, 4)));
                fields.extend([tau.to_string(), x.map_or(String::new(), |v| fixed(v, 4))]);
                csv.push(fields);
            }
        }
        rows.push(json!({
            "name": block_name(b), "tan_alpha": b.tan_alpha.to_string(), "r": b.r_m.to_string(), "p": fixed(b.p(), 2),
            "runs": r.runs, "b1": beta(&r.surface, 1, true), "b2": beta(&r.surface, 2, true),
            "h1": beta(&r.ode_surface, 1, false), "h2": beta(&r.ode_surface, 2, false),
            "cells": cells.join(" · "), "seconds": fixed(r.seconds, 0),
        }));
        // Contour agreement inside the records' p·PGV/PGA; β in the simulation's standard errors.
        let (Some(s), Some(h)) = (&r.surface, &r.ode_surface) else { continue };
        let (lo, hi) = taus(b, r);
        let ratios = (0..=20).map(|k| lo * (hi / lo).powf(k as f64 / 20.0) / b.p());
        worst = worst.max(s.contour_gap(h, 0.5, ratios));
        worst_beta = (1..3).map(|i| (s.beta[i] - h.beta[i]).abs() / s.std_err[i]).fold(worst_beta, f64::max);
        // The form's crossing of g tan α, ln(PGV/PGA) = (−β₀ − β₁ ln tan α)/β₂; the weakest overturning.
        let cross = b.p() * s.ratio_at(0.5, b.tan_alpha).unwrap_or(f64::NAN);
        let overturning = r.cases.iter().filter(|c| c.overturned > 0);
        let lowest = overturning.map(|c| c.run.motion.pga_g / b.tan_alpha).fold(f64::INFINITY, f64::min);
        floor.push(format!(
            "{}: data up to τ = {hi:.2}, crossing at τ = {cross:.1}, lowest overturning PGA {lowest:.2} g tan α",
            block_name(b)
        ));
    }
    let header = "block,tan_alpha,r_m,p,source,beta0,beta1,beta2,se0,se1,se2,tau,pga50_over_g_tan_alpha";
    out.csv("surfaces.csv", &columns(header), csv)?;
    chart
        .legend(Mark::Line(black), "solid: simulation (shaded: 95 % band)")
        .legend(Mark::Dashed(black), "Housner's equation, same members")
        .legend(Mark::Line(GREY), "PGA = g tan α (quasi-static threshold)")
        .save(&out.path("dimensionless.png"), (1000, 700))?;
    // Member agreement, case by case: ensemble P against Housner on the same draws.
    let cases = blocks.iter().flat_map(|b| &b.cases);
    let diffs: Vec<f64> = cases.filter_map(|c| c.ode.map(|q| (c.p() - q).abs())).collect();
    let agree = diffs.iter().filter(|&&d| d <= 1.0 / BLOCK_MEMBERS as f64 + 1e-12).count();
    let n = diffs.len().max(1) as f64;
    // The dimensionless collapse: spread of PGA₅₀/(g tan α) over the five blocks at a few τ.
    let spread = |ode: bool| {
        [0.3, 1.0, 3.0].map(|tau| {
            let s = |r: &BlockResult| if ode { r.ode_surface } else { r.surface };
            let (lo, hi) =
                nonnegative_range(BLOCKS.iter().zip(blocks).filter_map(|(b, r)| pga50(b, s(r).as_ref(), tau)));
            format!("{lo:.2}–{hi:.2}")
        })
    };
    let beta2 =
        BLOCKS.iter().zip(blocks).filter_map(|(b, r)| Some(format!("{:.2} ({})", r.surface?.beta[2], block_name(b))));
    Ok(json!({
        "rows": rows, "cases": diffs.len(), "mean_diff": fixed(diffs.iter().sum::<f64>() / n, 3), "agree": agree,
        "agree_pct": fixed(100.0 * agree as f64 / n, 0), "beta2": beta2.collect::<Vec<_>>().join(", "),
        "sim": spread(false), "ode": spread(true), "worst": fixed(100.0 * worst, 1), "worst_beta": fixed(worst_beta, 1),
        "floor": floor,
    }))
}

/// One set's scores ([`forecast_scores`], ε = 1/(2n)): `scores.csv` rows to `csv`, README values.
fn score_set(&(name, truth, cases, n): &(&str, &str, &[&Case], u64), csv: &mut Vec<Vec<String>>) -> Value {
    type Forecast = fn(&Case) -> f64; // a case's probability of overturning
    let forecasts: [(String, Forecast); 5] = [
        (format!("ensemble P ({n} members)"), |c| c.p()),
        ("Housner on the forecast's draws".into(), |c| c.ode.unwrap_or(0.5)),
        ("nominal member (yes/no)".into(), |c| c.nominal as u8 as f64),
        ("as-given run (yes/no)".into(), |c| c.run.rock.overturned as u8 as f64),
        // The best any yes/no forecast of a case can do: its truths' majority outcome.
        ("best yes/no (majority truth; a bound)".into(), |c| (2 * c.yes() >= c.truths.len()) as u8 as f64),
    ];
    let mut scores = Vec::new();
    for (label, f) in forecasts.iter().filter(|(l, _)| name == "blocks" || !l.starts_with("Housner")) {
        let each: Vec<_> = cases.iter().map(|c| (f(c), &c.truths[..])).collect();
        let s = forecast_scores(&each, 0.5 / n as f64);
        let (s, k) = ([s.brier, s.log_loss, s.accuracy], s.truths);
        // Its mean P: the share of cases a yes/no says overturn.
        let share = cases.iter().map(|c| f(c)).sum::<f64>() / cases.len() as f64;
        csv.push(row(format!("{name},{label},{:.5},{:.5},{:.4},{k},{truth},{share:.4}", s[0], s[1], s[2])));
        scores.push((label.clone(), s, share));
    }
    let truths: Vec<&[bool]> = cases.iter().map(|c| &c.truths[..]).collect();
    let (oracle, perfect) = (oracle_brier(&truths), ensemble_brier(&truths, n));
    let truth_share = cases.iter().map(|c| c.yes()).sum::<usize>() as f64 / truths.concat().len() as f64;
    csv.push(row(format!("{name},perfect {n}-member ensemble (expected),{perfect:.5},,,,{truth},")));
    csv.push(row(format!("{name},oracle,{oracle:.5},,,,{truth},{truth_share:.4}")));
    let row = |(l, s, share): &(String, [f64; 3], f64)| {
        [l.clone(), fixed(s[0], 4), fixed(s[1], 4), fixed(s[2], 3), fixed(100.0 * share, 1)]
    };
    let [(_, ens, p), .., (_, nominal, nominal_yes), (_, given, given_yes), (_, best, _)] = &scores[..] else {
        unreachable!("four or five forecasts")
    };
    let (pct, f2, f3) = (|x: f64, d| fixed(100.0 * x, d), |x| fixed(x, 2), |x| fixed(x, 3));
    json!({
        "name": name, "truth": truth, "n": n, "rows": scores.iter().map(row).collect::<Vec<_>>(),
        "perfect": f3(perfect), "perfect4": fixed(perfect, 4),
        "oracle": f3(oracle), "oracle4": fixed(oracle, 4), "truth_share": pct(truth_share, 1),
        "brier": [f3(ens[0]), f3(nominal[0]), f3(given[0]), f3(best[0])], "skill": f2(1.0 - ens[0] / nominal[0]),
        "log_loss": [f2(ens[1]), f2(nominal[1]), f2(given[1])], "nominal_yes": pct(*nominal_yes, 0),
        "given_yes": pct(*given_yes, 0), "mean_p": pct(*p, 1), "off": format!("{:+.4}", ens[0] - perfect),
    })
}

/// Block `b`'s P = 0.5 contours drawn on `chart` in `colour`: the simulation's solid with its
/// 95 % band shaded, Housner's dashed, both over the p·PGV/PGA its records cover.
fn contours(mut chart: Chart, colour: RGBColor, b: &Block, r: &BlockResult) -> Chart {
    chart = chart.legend(Mark::Line(colour), format!("tan α = {}, R = {} m", b.tan_alpha, b.r_m));
    let (lo, hi) = taus(b, r);
    let (lo, hi) = (lo.max(TAU_AXIS[0]), hi.min(TAU_AXIS[1]));
    let grid: Vec<f64> = (0..=60).map(|k| lo * (hi / lo).powf(k as f64 / 60.0)).collect();
    let contour = |s: &FragilitySurface| -> Vec<(f64, f64)> {
        grid.iter().filter_map(|&t| Some((t, pga50(b, Some(s), t)?))).collect()
    };
    if let Some(s) = &r.surface {
        let poly = b.dimensionless_band(s, 0.5, &grid, 1.96);
        if poly.len() > 2 {
            chart = chart.polygon(&poly, colour, 0.12);
        }
        chart = chart.line_width(&contour(s), colour, 3);
    }
    if let Some(s) = &r.ode_surface {
        chart = chart.dashed(&contour(s), colour);
    }
    chart
}
