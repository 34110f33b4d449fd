//! Fragility of field rocks under ground motion, and the checks behind it: A. one-sine pulses on a
//! slender block, rapier against Housner's equation; B. fragility surfaces of field rocks; C. the
//! speed of one long record; D. the coverage of the surface's 95 % band over repeated studies.
//!
//! Run: `cargo experiment fragility_surface [-- --synthetic-studies N
//! --ensemble-studies N --reference-members N]` → `results/fragility_surface/`; the README's
//! prose is `experiments/readme/fragility_surface.md`.

use anyhow::Context as _;
use rayon::prelude::*;
use rocking_stones::dynamics::shaking::housner::{block_stone, housner_ratio, HousnerBlock};
use rocking_stones::dynamics::shaking::{default_poses, place, rock_params, run_batch, run_record, shake_record};
use rocking_stones::dynamics::shaking::{Pose, RockSetup};
use rocking_stones::ground_motion::fragility::{FragilitySurface, Target};
use rocking_stones::ground_motion::studies::{coverage_counts, member_runs};
use rocking_stones::ground_motion::synthetic::{filtered_noise, noise_family, one_sine_pulse, Noise};
use rocking_stones::prelude::*;
use rocking_stones::stats::{nonnegative_range, rate_with_wilson};
use rocking_stones::{ground_motion::Record, GRAVITY as G};
use serde_json::{json, Value};
use std::time::Instant;

use experiments::{harness, rocks};
use harness::{cell, columns, fixed, timed, Common, Parser, Result, Results};
use rocks::row;

/// Part A: the ω_p/p grid and the a_p/(g tan α) grid.
const RATIOS: [f64; 7] = [1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0];
const AMP_STEP: f64 = 0.05;
const AMP_MAX: f64 = 8.0;
/// Part B (and D2): filtered noise of two horizontal components, four predominant periods ×
/// three seeds, scaled to PGA 1 g (the scale factors then give the PGA in g).
const PERIODS: [f64; 4] = [0.2, 0.5, 1.0, 2.0];
const SEEDS: [u64; 3] = [1, 2, 3];
const SCALES: [f64; 12] = [0.02, 0.03, 0.05, 0.08, 0.12, 0.2, 0.3, 0.5, 0.8, 1.2, 2.0, 3.0];
/// Part D1: the known surface and the point its band is checked at.
const SYNTH_BETA: [f64; 3] = [4.0, 3.0, 1.5];
const SYNTH_POINT: (f64, f64) = (0.35, 0.1);
/// Part D2: members per study; the block (tan α, R in m) and PGA/(g tan α) of its runs; the
/// contours whose bands are checked (the batch's).
const STUDY_MEMBERS: u64 = 16;
const BLOCK: HousnerBlock = HousnerBlock { tan_alpha: 0.25, r_m: 1.0 };
const BLOCK_X: [f64; 8] = [0.8, 1.0, 1.25, 1.6, 2.0, 2.5, 3.2, 4.0];
const CONTOURS: [f64; 3] = [0.1, 0.5, 0.9];
const QUARRY: &str = "data/meshes/stone_quarry_ibois_AAA_lowres_bin.ply";

/// Fragility of field rocks, one-sine pulses, speed and the coverage of the surface's band.
#[derive(Parser)]
struct Args {
    /// Studies of the known surface (part D1)
    #[arg(long, default_value_t = 4000)]
    synthetic_studies: u64,
    /// Ensemble studies of the block (part D2)
    #[arg(long, default_value_t = 300)]
    ensemble_studies: u64,
    /// Members of the surface the D2 studies estimate (disjoint from the studies')
    #[arg(long, default_value_t = 2048)]
    reference_members: u64,
    #[command(flatten)]
    common: Common,
}

fn main() -> Result<()> {
    let args = Args::parse();
    let out = Results::open("fragility_surface", &args.common)?;
    let quarry = rocks::of_file(QUARRY)?;
    let noise = Noise { components: 2, ..Noise::default() };
    let records = noise_family(&noise, 1.0, &PERIODS, &SEEDS, |t, s| format!("noise_T{t}_s{s}"))?;
    let context = json!({
        "a": part_a(&out)?, "c": part_c(&quarry)?, "b": part_b(&out, &quarry.1, &records)?,
        "d": part_d(&out, &args, &records)?,
        "periods": format!("{PERIODS:?}"), "seeds": format!("{SEEDS:?}"), "scales": format!("{SCALES:?}"),
    });
    out.readme(include_str!("readme/fragility_surface.md"), context)
}

fn part_a(out: &Results) -> Result<Value> {
    let (b, d, h) = (0.25, 0.3, 1.0);
    let (stone, k) = block_stone(b, d, h, None)?;
    let r_max_m = stone.body.r_max; // length unit: metres
    let block = HousnerBlock { tan_alpha: b / h, r_m: (b * b + h * h).sqrt() };
    let (big_r, alpha, p, r) = (block.r_m, block.tan_alpha.atan(), block.p(), housner_ratio(b, h));
    let bottom = stone.stable()[k].index;
    let concrete = rock_params(Surface::RockOnConcrete, r_max_m)?;
    let mut ideal = concrete.clone();
    (ideal.sim.contact.friction, ideal.sim.contact.restitution) = (1.0, 0.0);
    let sim = |q, ap: f64, wp: f64| -> Result<bool> {
        let placed = place(&stone, &Pose::Equilibrium { id: bottom }, q)?;
        // The pulse as every motion is, a record: sampled 2000 times per period.
        let tp = 2.0 * std::f64::consts::PI / wp;
        let run = shake_record(&stone, placed, q, &one_sine_pulse(ap / G, tp, tp / 2000.0)?, 0.0, r_max_m);
        Ok(run.overturned || run.final_equilibrium != bottom)
    };
    let amps: Vec<f64> = (0..).map(|k| 1.0 + AMP_STEP * k as f64).take_while(|a| *a <= AMP_MAX + 1e-9).collect();
    let t0 = Instant::now();
    let jobs: Vec<(f64, f64)> = RATIOS.iter().flat_map(|&x| amps.iter().map(move |&a| (x, a))).collect();
    // Each pulse: whether Housner's equation, rapier with Housner's contact (e = 0, μ = 1) and
    // rapier with rock on concrete overturn the block.
    let rows: Vec<(f64, f64, [bool; 3])> = jobs
        .par_iter()
        .map(|&(ratio, amp)| {
            let (wp, ap) = (ratio * p, amp * G * alpha.tan());
            let accel = move |t: f64| ap * (wp * t).sin();
            let ode = block.overturns(&accel, 2.0 * std::f64::consts::PI / wp);
            Ok((ratio, amp, [ode, sim(&ideal, ap, wp)?, sim(&concrete, ap, wp)?]))
        })
        .collect::<Result<_>>()?;
    eprintln!("part A: {} runs in {:.1} s", rows.len(), t0.elapsed().as_secs_f64());
    out.csv(
        "one_sine_pulse.csv",
        &columns(
            "omega_p_over_p,ap_over_g_tan_alpha,ode_overturns,rapier_ideal_overturns,rapier_rock_on_concrete_overturns",
        ),
        rows.iter()
            .map(|(x, a, o)| [x.to_string(), fixed(*a, 3), o[0].to_string(), o[1].to_string(), o[2].to_string()]),
    )?;
    // The minimum overturning a_p/(g tan α) of each ω_p/p (∞: none up to AMP_MAX).
    let min_of = |ratio: f64, i: usize| {
        rows.iter().filter(|x| x.0 == ratio && x.2[i]).map(|x| x.1).fold(f64::INFINITY, f64::min)
    };
    let minima: Vec<[f64; 4]> = RATIOS.iter().map(|&x| [x, min_of(x, 0), min_of(x, 1), min_of(x, 2)]).collect();
    // The overturning region in (ω_p/p, a_p/(g tan α)): the ODE's left of each ω_p/p, rapier's right.
    let (grey, red, blue) = (RGBColor(120, 120, 120), RGBColor(255, 0, 0), RGBColor(0, 0, 255));
    let boxes = |i: usize, dx: f64| -> Vec<(f64, f64, f64, f64)> {
        let (half, rows) = (AMP_STEP / 2.0, rows.iter().filter(|x| x.2[i]));
        rows.map(|&(x, a, _)| (x + dx.min(0.0), a - half, x + dx.max(0.0), a + half)).collect()
    };
    let min_line: Vec<(f64, f64)> = minima.iter().filter(|m| m[3].is_finite()).map(|m| (m[0], m[3])).collect();
    Chart::new(Axis::linear("ω_p / p", 0.5, 8.5), Axis::linear("a_p / (g tan α)", 0.8, AMP_MAX + 0.2))
        .title("One-sine pulse, block b/h = 0.25: overturning region")
        .boxes(&boxes(0, -0.12), grey, 1.0)
        .boxes(&boxes(1, 0.12), red, 0.7)
        .line(&min_line, blue)
        .legend(Mark::Box(grey, 1.0), "Housner ODE overturns (left)")
        .legend(Mark::Box(red, 0.7), "rapier (e = 0, μ = 1) overturns (right)")
        .legend(Mark::Line(blue), "rapier, rock on concrete: minimum")
        .save(&out.path("one_sine_pulse.png"), (900, 600))?;
    let rows: Vec<[String; 5]> = minima
        .iter()
        .map(|&[x, o, i, c]| {
            let ratio = if o.is_finite() && i.is_finite() { fixed(i / o, 3) } else { "–".to_string() };
            [x.to_string(), cell(o, 2, false), cell(i, 2, false), cell(c, 2, false), ratio]
        })
        .collect();
    Ok(json!({
        "b_h": fixed(b / h, 2), "alpha": fixed(alpha, 3), "big_r": fixed(big_r, 3), "p": fixed(p, 3), "r": fixed(r, 3),
        "amp_max": AMP_MAX.to_string(), "amp_step": AMP_STEP.to_string(), "rows": rows,
    }))
}

/// Part B: the fragility surfaces of the bundled stone (as a 0.5 m boulder, both default poses)
/// and the quarry stone (at its scanned size, rocking pose), rock on concrete, azimuth 0.
fn part_b(out: &Results, quarry: &Stone, records: &[Record]) -> Result<Value> {
    let (_, pebble) = rocks::of_file("data/default_pebble.ply")?;
    let unit = 0.5 / pebble.body.r_max;
    let (regular, rocking) = default_poses(&pebble, 0.5)?;
    let (q_regular, q_rocking) = default_poses(quarry, quarry.body.r_max)?;
    let cases = [
        ("bundled_regular", &pebble, regular, unit),
        ("bundled_rocking", &pebble, rocking, unit),
        ("quarry_AAA", quarry, q_rocking.or(q_regular), 1.0),
    ];
    let mut rows = Vec::new();
    for (name, stone, id, unit) in cases {
        let Some(id) = id else { continue };
        let (t0, pose) = (Instant::now(), Pose::Equilibrium { id });
        let setup = RockSetup::new(stone, pose, unit, Surface::RockOnConcrete, 0.0)?;
        let batch = run_batch(stone, &setup, records, &SCALES, None, &[], &|_| {})?;
        let secs = t0.elapsed().as_secs_f64();
        rocking_stones::report::shake::write_batch_outputs(&batch, name, &out.path(name))?;
        let k = stone.position(batch.start_equilibrium).context("the batch starts at a stable equilibrium")?;
        let overturned = batch.runs.iter().filter(|r| r.rock.overturned).count();
        let s = batch.surface.as_ref();
        let beta = (0..3).map(|i| s.map_or("-".into(), |s| s.coefficient_text(i, 2))).collect::<Vec<_>>().join(" | ");
        let pga50 = |ratio| s.and_then(|s| s.pga_at(0.5, ratio)).map_or("-".to_string(), |v| fixed(v, 3));
        rows.push(json!({
            "name": name, "r_max": fixed(setup.r_max_m, 3), "pose": pose.to_string(),
            "class": stone.stable()[k].class.to_string(), "runs": batch.runs.len(), "overturned": overturned,
            "beta": beta, "p05": pga50(0.05), "p2": pga50(0.2), "secs": fixed(secs, 1),
        }));
        eprintln!("{name}: {} runs, {overturned} overturned, {secs:.1} s", batch.runs.len());
    }
    Ok(json!({ "runs": records.len() * SCALES.len(), "rows": rows }))
}

/// Part C: time per run of a 60 s, 800 Hz, three-component record on the 1 872-vertex quarry
/// stone (one thread), at its true size and as a 1 m rock.
fn part_c((a, stone): &(Analysis, Stone)) -> Result<Value> {
    let (regular, _) = default_poses(stone, stone.body.r_max)?;
    let pose = Pose::Equilibrium { id: regular.context("the quarry stone has no regular pose")? };
    let noise = Noise { duration: 60.0, period: 0.5, dt: 1.0 / 800.0, components: 3, ..Noise::default() };
    let (rec, t_make) = timed(|| filtered_noise(&noise, 0.1, 11));
    let rec = rec?;
    let mut rows = Vec::new();
    for unit in [1.0, 1.0 / stone.body.r_max] {
        let setup = RockSetup::new(stone, pose, unit, Surface::RockOnConcrete, 0.0)?;
        let (resampled, t_res) = timed(|| rec.resampled(setup.real_dt()));
        let (run, t_run) = timed(|| run_record(stone, &setup, &resampled?, 1.0));
        let run = run?;
        let steps = run.rock.steps;
        eprintln!("speed: R_max {:.3} m: {steps} steps in {t_run:.3} s", setup.r_max_m);
        let (r, dt, per_step) = (setup.r_max_m, setup.real_dt(), fixed(1e6 * t_run / steps as f64, 1));
        rows.push([fixed(r, 3), fixed(dt, 5), steps.to_string(), fixed(t_res, 3), fixed(t_run, 3), per_step]);
    }
    Ok(json!({
        "samples": rec.accel.len(), "t_make": fixed(t_make, 2), "vertices": a.mesh.vertices.len(),
        "corners": stone.body.corners.len(), "rows": rows,
    }))
}

/// A target's columns of a coverage CSV: what, p, PGA (g), PGV/PGA (s).
fn target_columns(target: &Target) -> String {
    match *target {
        Target::Point(pga, r) => format!("P at a point,,{pga:.4},{r:.4}"),
        Target::Contour(p, r) => format!("PGA of a contour,{p},,{r:.4}"),
    }
}

const PRODUCT: &str = "model-based (the product's)";
const ROBUST: &str = "cluster-robust (members as clusters)";

/// Part D: how often the 95 % band of a fitted surface contains the surface it estimates,
/// counted over repeated simulated studies.
fn part_d(out: &Results, args: &Args, records: &[Record]) -> Result<Value> {
    let (seed, synth_studies, studies_n) = (args.common.seed_or(2008), args.synthetic_studies, args.ensemble_studies);
    let mut rows = Vec::new();
    // D1: a known logistic surface, independent runs.
    let t0 = Instant::now();
    // The design of the unit test of `ground_motion::fragility`: 12 PGA × 8 PGV/PGA cells, 2 runs each.
    let truth = FragilitySurface::exact(SYNTH_BETA);
    let pgas: Vec<f64> = (0..12).map(|i| 0.05 * 1.3f64.powi(i)).collect();
    let ratios: Vec<f64> = (0..8).map(|j| 0.02 * 1.4f64.powi(j)).collect();
    let d1 = [Target::Point(SYNTH_POINT.0, SYNTH_POINT.1), Target::Contour(0.5, SYNTH_POINT.1)];
    let fits = |s| Ok(vec![FragilitySurface::fit(&truth.draw_runs(&pgas, &ratios, 2, seed + s))?]);
    let synth = coverage_counts(&d1, &truth, synth_studies, fits)?;
    rows.extend(d1.iter().zip(&synth[0]).map(|(t, &k)| ("D1 known surface", *t, PRODUCT, synth_studies, k)));
    eprintln!("part D1: {synth_studies} studies in {:.1} s", t0.elapsed().as_secs_f64());

    // D2: ensembles of a block under Housner's equation, members common to every record × scale.
    let tan_alpha = BLOCK.tan_alpha;
    let measures: Vec<_> = records.iter().map(|r| r.measures()).collect();
    let cases: Vec<(usize, f64)> =
        (0..records.len()).flat_map(|r| BLOCK_X.iter().map(move |&x| (r, x * tan_alpha))).collect();
    let members = studies_n * STUDY_MEMBERS + args.reference_members;
    // Member m: the angle of its rocking plane from the records' x axis, and its sign.
    let oriented: Vec<(&Record, f64)> = cases.iter().map(|&(r, scale)| (&records[r], scale)).collect();
    let (outcome, d2_seconds) = timed(|| BLOCK.overturns_oriented(&oriented, members, seed));
    // The runs of members from..to (each case's PGA and PGV/PGA), and the member of each.
    let intensity: Vec<(f64, f64)> =
        cases.iter().map(|&(r, scale)| (measures[r].pga_g * scale, measures[r].pgv_over_pga_s)).collect();
    let runs_of = |from: u64, to: u64| member_runs(&intensity, &outcome, from..to);
    let first = studies_n * STUDY_MEMBERS;
    let reference = FragilitySurface::fit(&runs_of(first, first + args.reference_members)?.0)?;
    // The records' range of PGV/PGA: its ends and its geometric middle.
    let (lo, hi) = nonnegative_range(measures.iter().map(|m| m.pgv_over_pga_s));
    let mid = (lo * hi).sqrt();
    let mut d2 = vec![Target::Point(reference.pga_at(0.5, mid).context("the reference rises with PGA")?, mid)];
    for r in [lo, mid, hi] {
        d2.extend(CONTOURS.iter().map(|&p| Target::Contour(p, r)));
    }
    // Each study's fit, with its model-based band and with its cluster-robust one.
    let studies = coverage_counts(&d2, &reference, studies_n, |s| {
        let (runs, cluster) = runs_of(s * STUDY_MEMBERS, (s + 1) * STUDY_MEMBERS)?;
        let fit = FragilitySurface::fit(&runs)?;
        Ok(vec![fit, fit.cluster_robust(&runs, &cluster)])
    })?;
    for (band, counts) in [PRODUCT, ROBUST].into_iter().zip(&studies) {
        rows.extend(d2.iter().zip(counts).map(|(t, &k)| ("D2 block ensembles", *t, band, studies_n, k)));
    }
    eprintln!("part D2: {members} members × {} cases in {d2_seconds:.0} s", cases.len());
    out.csv(
        "coverage.csv",
        &columns("studies_of,target,p,pga_g,pgv_over_pga_s,band,studies,covered,coverage,low95,high95"),
        rows.iter().map(|&(kind, target, band, n, k)| {
            let (c, lo, hi) = rate_with_wilson(k, n, 1.96);
            row(format!("{kind},{},{band},{n},{k},{c:.4},{lo:.4},{hi:.4}", target_columns(&target)))
        }),
    )?;
    // The reading, computed: the range of each set's rates, and the mean over the D2 targets.
    let rates = |kind: &str, band: &str| -> Vec<(f64, f64, f64)> {
        rows.iter().filter(|x| x.0 == kind && x.2 == band).map(|x| rate_with_wilson(x.4, x.3, 1.96)).collect()
    };
    let span = |kind: &str, band: &str| {
        let r = rates(kind, band);
        let (lo, hi) = nonnegative_range(r.iter().map(|x| x.0));
        let (below, above) = (r.iter().filter(|x| x.2 < 0.95).count(), r.iter().filter(|x| x.1 > 0.95).count());
        json!({ "lo": fixed(lo, 3), "hi": fixed(hi, 3), "n": r.len(), "below": below, "above": above })
    };
    let mean = |band: &str| rates("D2 block ensembles", band).iter().map(|x| x.0).sum::<f64>() / d2.len() as f64;
    let (product, robust) = (mean(PRODUCT), mean(ROBUST));
    let table = rows.iter().map(|&(kind, target, band, n, k)| {
        let (c, lo, hi) = rate_with_wilson(k, n, 1.96);
        [
            kind.into(),
            target.to_string(),
            band.into(),
            n.to_string(),
            k.to_string(),
            fixed(c, 3),
            fixed(lo, 3),
            fixed(hi, 3),
        ]
    });
    Ok(json!({
        "synth_studies": synth_studies, "beta": SYNTH_BETA.map(|b| b.to_string()), "tan_alpha": tan_alpha.to_string(),
        "r_m": BLOCK.r_m.to_string(), "p": fixed(BLOCK.p(), 2), "records": records.len(), "block_x": format!("{BLOCK_X:?}"),
        "members": STUDY_MEMBERS, "studies": studies_n, "seconds": fixed(d2_seconds, 0),
        "reference": args.reference_members, "contours": format!("{CONTOURS:?}"), "rows": table.collect::<Vec<_>>(),
        "d1": span("D1 known surface", PRODUCT), "d2": span("D2 block ensembles", PRODUCT),
        "d2_robust": span("D2 block ensembles", ROBUST), "product": fixed(product, 3), "robust": fixed(robust, 3),
        "robust_smaller": robust < product,
    }))
}
