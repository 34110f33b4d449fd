//! Validation on three 3D-printed dice thrown by hand (`data/printed_shapes/`); nothing is
//! fitted to these data. The quasi-static basins, the calibrated `throw` and the `drop` preset
//! predict the outcome frequencies, scored by the total variation distance against its noise.
//!
//! Run: `cargo experiment printed_shapes [-- N [DATA_DIR]]` (N = 2000 throws per
//! shape and predictor, seed 1; DATA_DIR = `data/printed_shapes`) → `results/printed_shapes/`;
//! the README's prose is `experiments/readme/printed_shapes.md`.

use anyhow::ensure;
use rocking_stones::plot::{colors::GREY, wilson_bars, BarSlot, OKABE_ITO};
use rocking_stones::prelude::*;
use rocking_stones::stats::{chi_square_homogeneity, mean, wilson};
use rocking_stones::study::outcomes::{by_outcome, frequencies, score, total_variation, ByOutcome, Score, ThrownShape};
use rocking_stones::tipping::TippingPolar;
use serde_json::{json, Value};
use std::{collections::BTreeMap, path::PathBuf, time::Instant};

use experiments::harness;
use harness::{fixed, Common, Context, Parser, Result, Results};

/// The shapes, in the order of the data's README.
const SHAPES: [&str; 3] = ["binom3", "binom4", "dragon_d3"];
/// Metres per OBJ unit assumed for the printed dice. The OBJs are in a normalised frame (longest
/// extent 1.7–1.9 units) and the source does not give the printed size; a die thrown by hand is a
/// few centimetres long, and 1 unit = 2 cm gives R_max 1.4–2.0 cm, the range of the steel dice
/// the throw was calibrated on (1.1–1.9 cm). The size sets δ / R_max only.
const METRES_PER_UNIT: f64 = 0.02;
/// Bootstrap replicates of the noise-level TV.
const BOOTSTRAP: u64 = 4000;
/// A normal further than this (degrees) from every listed normal is reported as a poor match.
const POOR_MATCH_DEG: f64 = 5.0;
/// The predictors (CSV keys, labels), in the order of every table and picture.
const KEYS: [&str; 4] = ["quasi_static", "throw", "throw_rapier_flight", "drop"];
const LABELS: [&str; 4] = ["quasi-static basins", "throw (calibrated)", "throw, rapier's flight", "drop preset"];

/// Simulated throws of the printed dice against their measured outcomes.
#[derive(Parser)]
struct Args {
    /// Throws per shape and predictor
    #[arg(default_value_t = 2000, value_parser = clap::value_parser!(u64).range(1..))]
    n: u64,
    /// The dice's folder [default: data/printed_shapes of the repository]
    data: Option<PathBuf>,
    #[command(flatten)]
    common: Common,
}

/// One printed die: its name and its folder's hull, centre of mass and measured outcomes.
struct Shape {
    name: &'static str,
    die: ThrownShape,
}

/// One predictor on one die: frequencies, simulated counts, their total, the run's unsettled drops
/// and seconds (none: the exact basins), its score, its tv.csv row and its README values.
struct Pred {
    p: Vec<f64>,
    sim: Option<(Vec<u64>, u64, (u64, f64))>,
    score: Score,
    csv: Vec<String>,
    readme: Value,
}

fn f3(x: f64) -> String {
    fixed(x, 3)
}

/// Score the frequencies `p` of predictor `j` (`sim` as in [`Pred`]) against the measurement; the
/// noise TV: a measurement of the same N drawn from `p` (and a simulation's N) from `stream`.
fn judge(shape: &Shape, j: usize, p: Vec<f64>, sim: Option<(Vec<u64>, u64, (u64, f64))>, stream: (u64, u64)) -> Pred {
    let simulated = sim.as_ref().map(|s| &s.0[..]);
    let s = score(&shape.die.outcomes, &p, simulated, BOOTSTRAP, stream.0 ^ (stream.1 << 32));
    let run = sim.as_ref().map(|s| s.2);
    let (opt, e3) = (|x: Option<String>| x.unwrap_or_default(), |x: f64| format!("{x:.3e}"));
    let csv = [shape.name, KEYS[j]]
        .map(String::from)
        .into_iter()
        .chain([s.tv, s.noise_mean, s.noise_q95].map(|x| fixed(x, 4)));
    let csv = csv.chain([fixed(s.chi2, 2), s.dof.to_string(), e3(s.p_value)]);
    let csv = csv
        .chain([s.p_homogeneity.map(e3), run.map(|r| r.0.to_string()), run.map(|r| fixed(r.1, 1))].map(opt))
        .collect();
    let readme = json!({
        "label": LABELS[j], "tv": f3(s.tv), "beyond": s.tv > s.noise_q95, "within": s.tv <= s.noise_q95,
        "noise_mean": f3(s.noise_mean), "noise_q95": f3(s.noise_q95), "impossible": s.impossible,
        "chi2": fixed(s.chi2, 1), "dof": s.dof, "p": p_text(s.p_value), "p_hom": s.p_homogeneity.map_or("—".into(), p_text),
    });
    Pred { score: s, csv, readme, sim, p }
}

/// A p-value as a person reads it.
fn p_text(p: f64) -> String {
    match p {
        p if p >= 1e-4 => format!("{:.*}", if p >= 0.01 { 2 } else { 4 }, p),
        p if p > 0.0 => format!("{p:.0e}"),
        _ => "0".into(),
    }
}

/// One die: its predictions, its rows of `outcomes.csv` and its part of the README.
fn run_shape(shape: &Shape, (n, seed): (u64, u64), index: usize) -> Result<(Vec<Pred>, Vec<Vec<String>>, Value)> {
    eprintln!("{}", shape.name);
    let (m, opts) =
        (&shape.die.outcomes, Options { center_of_mass: Some(shape.die.center_of_mass), ..Options::default() });
    let analysis = Analysis::of_file(&shape.die.mesh, &opts)?;
    let stone =
        Stone::new(&analysis, analysis.macro_nu(&opts).0).with_context(|| shape.die.mesh.display().to_string())?;
    let report = analysis.report(&shape.die.mesh.display().to_string(), &opts);
    let (r_max, k, facets) = (analysis.equilibria.r_max, m.ids.len(), &report.stable_facets);
    let r_max_m = r_max * METRES_PER_UNIT;
    let angle_deg = |a: &Vec3, b: &Vec3| a.dot(b).clamp(-1.0, 1.0).acos().to_degrees();
    // The tilt (degrees) that brings G's vertical over the nearest edge of facet `f` (toppling).
    let topple_tilt = |f: u32| -> Result<f64> {
        let (normal, g) = (&analysis.hull.facets[f as usize].normal, &analysis.mass.center_of_mass);
        Ok(TippingPolar::new(&analysis.hull.vertices, g, normal, 0.0)?.tipping_tilt_deg())
    };
    let vec3 = |v: &Vec3, d: usize| format!("({:+.d$}, {:+.d$}, {:+.d$})", v.x, v.y, v.z);
    let angles: Vec<(usize, f64)> = facets.iter().map(|s| m.nearest(&s.normal)).collect();
    let tilts: Vec<f64> = facets.iter().map(|s| topple_tilt(s.facet)).collect::<Result<_>>()?;
    let mapped: Vec<_> = facets.iter().zip(&angles).map(|(s, &(k, a))| (s.facet, k, a > POOR_MATCH_DEG)).collect();
    let stable: BTreeMap<u32, usize> = mapped.iter().map(|m| (m.0, m.1)).collect();
    let basin: BTreeMap<u32, f64> = facets.iter().map(|s| (s.facet, s.basin_probability)).collect();
    ensure!((basin.values().sum::<f64>() - 1.0).abs() < 1e-6, "{}: the basins do not add up to 1", shape.name);
    // The runs on steel on wood: the calibrated throw (its calibrated numerics), the same throw with
    // rapier's flight (impacts found at the step boundaries), the drop preset, then the calibrated
    // throw at ½ and 2 × the assumed size (only δ / R_max changes); the same launches in each.
    let (mut runs, mut info) = (vec![basin], vec![]);
    for (j, factor) in [(1, 1.0), (2, 1.0), (3, 1.0), (1, 0.5), (1, 2.0)] {
        let (preset, surface) = (if j == 3 { Preset::Drop } else { Preset::Throw }, Surface::SteelOnWood);
        let mut params = preset.params_at_size(surface, r_max_m * factor)?;
        params.sim.flight.mode = [Flight::Free, Flight::Rapier].get(j - 1).copied().unwrap_or(params.sim.flight.mode);
        let (c, name) = (shape.die.center_of_mass, shape.die.mesh.display().to_string());
        let header = RunHeader::new(name, &analysis.mesh, seed, n, params, CertificateMode::Facet, (preset, surface));
        let t = Instant::now();
        let (r, _) = run_and_summarize(&stone, &RunHeader { center_of_mass: Some([c.x, c.y, c.z]), ..header });
        let seconds = t.elapsed().as_secs_f64();
        let mut counts = BTreeMap::new();
        for row in r.facets.iter().filter(|r| r.count > 0) {
            let hull_normal = analysis.hull.facets[row.facet as usize].normal;
            ensure!(row.normal.dot(&hull_normal) > 1.0 - 1e-9, "{}: facet {}'s frames differ", shape.name, row.facet);
            ensure!(stable.contains_key(&row.facet), "{}: drops rest on unstable facet {}", shape.name, row.facet);
            counts.insert(row.facet, row.count as f64);
        }
        ensure!(r.facet_drops > 0 && counts.values().sum::<f64>() == r.facet_drops as f64, "lost drops");
        eprintln!("  {} at {factor} × size: {seconds:.0} s, {} drops", LABELS[j], r.drops);
        let (l, c, sim) = (&r.params.launch, &r.params.sim.contact, &r.params.sim);
        let plain = [l.height, l.horizontal_speed, l.spin, c.friction, c.restitution].map(|x| x.to_string());
        let run = json!({
            "label": LABELS[j], "drops": [r.drops, r.unsettled, r.off_equilibrium, r.certified], "plain": plain,
            "seconds": fixed(seconds, 0), "delta": fixed(c.rolling_resistance, 4),
            "flight": sim.flight.mode.to_string(), "steps": fixed(1.0 / sim.numerics.dt, 0),
        });
        runs.push(counts);
        info.push((r.unsettled, seconds, run));
    }
    let p_meas = m.frequencies();
    let (mut preds, mut unlisted) = (Vec::new(), Vec::new());
    for (j, weight) in runs.iter().take(4).enumerate() {
        let ByOutcome { p, unlisted: share, listed_only } = by_outcome(&mapped, k, weight);
        let mut counts = vec![0u64; k];
        weight.iter().for_each(|(f, c)| counts[stable[f]] += *c as u64);
        let sim = (j > 0).then(|| (counts.clone(), counts.iter().sum(), (info[j - 1].0, info[j - 1].1)));
        let pred = judge(shape, j, p, sim, (seed, (index * 8 + j) as u64));
        let tv_listed = listed_only.map_or("—".into(), |q| f3(total_variation(&q, &p_meas)));
        unlisted.push(json!({"label": LABELS[j], "share": f3(share), "tv": f3(pred.score.tv), "tv_listed": tv_listed}));
        preds.push(pred);
    }
    // outcomes.csv, long format: one row per outcome and source (the measurement, each predictor).
    let (mut rows, mut freqs) = (Vec::new(), Vec::new());
    for (i, (id, &count)) in m.ids.iter().zip(&m.counts).enumerate() {
        let sources = preds.iter().zip(KEYS).map(|(p, key)| (key, p.sim.as_ref().map(|s| (s.0[i], s.1)), p.p[i]));
        let mut cells = Vec::new();
        for (source, counts, p) in std::iter::once(("measured", Some((count, m.throws)), p_meas[i])).chain(sources) {
            let (c, n) = counts.map_or(Default::default(), |(c, n)| (c.to_string(), n.to_string()));
            let ci = counts.map(|(c, n)| wilson(c, n, 1.96));
            let (lo, hi) = ci.map_or(Default::default(), |(lo, hi)| (fixed(lo, 5), fixed(hi, 5)));
            rows.push(vec![shape.name.into(), id.clone(), source.into(), c, n, fixed(p, 5), lo, hi]);
            let measured = if source == "measured" { format!(" ({count})") } else { String::new() };
            cells.push(ci.map_or(f3(p), |(lo, hi)| format!("{p:.3} [{lo:.3}, {hi:.3}]{measured}")));
        }
        freqs.push(json!({"id": id, "cells": cells}));
    }
    let size_tv = |i: usize| f3(total_variation(&by_outcome(&mapped, k, &runs[i]).p, &p_meas));
    let (a, b) = (&preds[1].sim.as_ref().expect("simulated").0, &preds[2].sim.as_ref().expect("simulated").0);
    let (chi2, _, p) = chi_square_homogeneity(a, b);
    let numerics = [
        f3(total_variation(&frequencies(a, a.iter().sum()), &frequencies(b, b.iter().sum()))),
        fixed(chi2, 1),
        p_text(p),
    ];
    let (lo, hi) = analysis.mesh.bounding_box().context("an empty mesh")?;
    let extent = [0, 1, 2].map(|i| fixed(hi[i] - lo[i], 2));
    let far = |nm: &&Vec3| facets.iter().all(|s| angle_deg(&s.normal, nm) >= POOR_MATCH_DEG);
    let (qs, th) = (&preds[0], &preds[1]);
    let readme = json!({
        "name": shape.name, "n": m.throws, "extent": extent, "r_max": f3(r_max), "r_max_mm": fixed(r_max_m * 1e3, 1),
        "delta": fixed(Surface::SteelOnWood.contact().rolling_resistance_m / r_max_m, 4),
        "hull_facets": analysis.hull.facets.len(), "stable": facets.len(),
        "degenerate": analysis.equilibria.degenerate_decisions,
        "mapped": facets.iter().zip(&angles).zip(&tilts).map(|((s, &(k, angle)), tilt)| json!({
            "facet": s.facet, "normal": vec3(&s.normal, 4), "r": f3(s.r / r_max),
            "tilt": fixed(*tilt, 2), "basin": fixed(s.basin_probability, 4),
            "outcome": m.ids[k], "angle": fixed(angle, 2), "away": fixed(angle, 0), "poor": angle > POOR_MATCH_DEG,
        })).collect::<Vec<_>>(),
        "empty": (0..k).filter(|i| !stable.values().any(|x| x == i)).map(|i| &m.ids[i]).collect::<Vec<_>>(),
        "unmatched": m.ids.iter().zip(&m.normals)
            .flat_map(|(id, ns)| ns.iter().filter(far).map(move |nm| json!({"id": id, "normal": vec3(nm, 3)})))
            .collect::<Vec<_>>(),
        "poor": mapped.iter().any(|m| m.2), "unlisted": unlisted, "freqs": freqs,
        "scores": preds.iter().map(|p| &p.readme).collect::<Vec<_>>(),
        "closer": th.score.tv + 0.5 * th.score.noise_mean < qs.score.tv, "further": qs.score.tv + 0.5 * qs.score.noise_mean < th.score.tv,
        "size": [size_tv(4), f3(th.score.tv), size_tv(5)], "numerics": numerics,
        "runs": info.iter().take(3).map(|i| &i.2).collect::<Vec<_>>(),
    });
    Ok((preds, rows, readme))
}

fn main() -> Result<()> {
    let args = Args::parse();
    let (n, seed) = (args.n, args.common.seed_or(1));
    let data = args.data.unwrap_or_else(|| harness::repo().join("data/printed_shapes"));
    let out = Results::open("printed_shapes", &args.common)?;
    let t0 = Instant::now();
    // Every input is read and checked before the first throw.
    let shapes: Vec<Shape> = SHAPES
        .into_iter()
        .map(|name| Ok(Shape { name, die: ThrownShape::read(&data.join(name))? }))
        .collect::<Result<_>>()?;
    let results: Vec<_> = shapes.iter().enumerate().map(|(i, s)| run_shape(s, (n, seed), i)).collect::<Result<_>>()?;
    let preds: Vec<&Vec<Pred>> = results.iter().map(|r| &r.0).collect();
    let elapsed = t0.elapsed().as_secs_f64();
    let rows = results.iter().flat_map(|r| r.1.iter());
    out.csv("outcomes.csv", &["shape", "outcome", "source", "count", "n", "frequency", "ci95_lo", "ci95_hi"], rows)?;
    let header = ["shape", "predictor", "tv", "noise_tv_mean", "noise_tv_95", "chi_square", "dof", "p_value"];
    let tv_rows = preds.iter().flat_map(|p| p.iter().map(|p| &p.csv));
    out.csv("tv.csv", &[&header[..], &["p_homogeneity", "unsettled", "seconds"]].concat(), tv_rows)?;
    plot(&out, &shapes, &preds)?;
    let mean_tv = |j: usize| f3(mean(&preds.iter().map(|p| p[j].score.tv).collect::<Vec<_>>()));
    let means: Vec<_> = LABELS.iter().enumerate().map(|(j, label)| json!({"label": label, "tv": mean_tv(j)})).collect();
    let context = json!({
        "n": n, "seed": seed, "mm_per_unit": fixed(METRES_PER_UNIT * 1e3, 0), "poor_deg": POOR_MATCH_DEG.to_string(),
        "bootstrap": BOOTSTRAP, "elapsed": fixed(elapsed, 0), "means": means,
        "shapes": results.iter().map(|r| &r.2).collect::<Vec<_>>(),
    });
    out.readme(include_str!("readme/printed_shapes.md"), context)
}

/// `tv.png`: per die, the measured frequencies (95 % Wilson intervals) and each predictor's bars
/// (95 % Monte Carlo intervals); last panel, the TV of each predictor with its noise level.
fn plot(out: &Results, shapes: &[Shape], preds: &[&Vec<Pred>]) -> Result<()> {
    let black = OKABE_ITO[0];
    // Bar `slot` of `slots` side by side across 0.8 of each category, centred in its slot; a
    // category axis with three blank ticks between names.
    let place = |slots: usize, slot: usize| BarSlot { slot, slots, width: 0.8 };
    let categories = |label: &str, names: Vec<String>| {
        let n = names.len();
        Axis::categories(label, names).ticks(4 * n + 1)
    };
    // 95 % Wilson intervals of `counts` out of `n` at bar `slot` of 5.
    let whiskers = |slot: usize, counts: &[u64], n: u64| {
        wilson_bars(counts.iter().enumerate().map(|(i, &c)| (place(5, slot).slot_centre(i), c, n)))
    };
    let mut panels = Vec::new();
    for (s, preds) in shapes.iter().zip(preds) {
        let (measured, k) = (whiskers(0, &s.die.outcomes.counts, s.die.outcomes.throws), s.die.outcomes.ids.len());
        let top = measured.iter().map(|m| m.2).chain(preds.iter().flat_map(|p| p.p.clone())).fold(0.0, f64::max);
        let y = Axis::linear("frequency", 0.0, ((top * 1.1) * 10.0).ceil() / 10.0);
        let x = categories("outcome (id of outcomes.csv)", s.die.outcomes.ids.clone());
        let mut chart = Chart::new(x, y).title(format!("{} (N = {} hand throws)", s.name, s.die.outcomes.throws));
        for (slot, pred) in preds.iter().enumerate() {
            let boxes: Vec<_> = (0..k).map(|i| place(5, slot + 1).centred(i, 0.072, pred.p[i])).collect();
            chart = chart.boxes(&boxes, series_color(slot), 0.85);
            if let Some((counts, total, _)) = &pred.sim {
                chart = chart.y_bars(&whiskers(slot + 1, counts, *total), GREY);
            }
        }
        let dots: Vec<_> = s
            .die
            .outcomes
            .frequencies()
            .into_iter()
            .enumerate()
            .map(|(i, p)| (place(5, 0).slot_centre(i), p))
            .collect();
        panels.push(chart.y_bars(&measured, black).dots(&dots, black));
    }
    // Last panel: TV per shape and predictor, with the noise level.
    let top = preds.iter().flat_map(|p| p.iter()).map(|p| p.score.tv.max(p.score.noise_q95)).fold(0.0f64, f64::max);
    let y = Axis::linear("TV = ½ Σ |p_pred − p_meas|", 0.0, ((top * 1.15) * 20.0).ceil() / 20.0);
    let mut chart = Chart::new(categories("die", shapes.iter().map(|s| s.name.to_string()).collect()), y)
        .title("total variation distance to the measurement");
    for slot in 0..4 {
        let boxes: Vec<_> =
            preds.iter().enumerate().map(|(i, p)| place(4, slot).centred(i, 0.09, p[slot].score.tv)).collect();
        chart = chart.boxes(&boxes, series_color(slot), 0.85);
        for (i, q) in preds.iter().map(|p| p[slot].score.noise_q95).enumerate() {
            chart = chart
                .line(&[(place(4, slot).slot_centre(i) - 0.1, q), (place(4, slot).slot_centre(i) + 0.1, q)], black);
        }
    }
    panels.push(chart);
    let title = "Printed dice: measured hand throws against the predictors (validation, nothing fitted)";
    let figure = Figure::new(title, 2, panels).legend(Mark::LineDot(black), "measured (95 % Wilson interval)");
    let figure =
        LABELS.iter().enumerate().fold(figure, |f, (k, label)| f.legend(Mark::Box(series_color(k), 0.85), *label));
    Ok(figure
        .legend(Mark::Line(GREY), "thin whiskers: 95 % Monte Carlo interval of a simulated predictor")
        .legend(Mark::Line(black), "last panel: noise level (95th percentile of the TV if the predictor were exact)")
        .save(&out.path("tv.png"), (1200, 980))?)
}
