//! Fitting the hand experimenter's ν to the paper's Table 2 with synthetic pebble populations
//! (`study::fit_table2`), and what the fitted ν depends on: the roughness (the best is the base
//! case), the resolution, the spread of the ratios, the seed, the 5 scanned samples alone, the
//! stable columns alone and no ratio calibration.
//!
//! Run: `cargo experiment table2_fit_nu` → `results/table2_fit_nu/`; the README's
//! prose is `experiments/readme/table2_fit_nu.md`.

use rocking_stones::analysis::PAPER_NU;
use rocking_stones::report::nu_fit::{loss_chart, nu_against_roughness, write_fits_csv};
use rocking_stones::stats::{min_max, sample_sd};
use rocking_stones::study::{self, FitOptions, HandSample, NuFit, PopulationParams};
use serde_json::json;

use experiments::harness;
use harness::{cell, fixed, Result, Results};

/// The roughness amplitudes scanned (the generator allows < 1).
const ROUGHNESS: [f64; 9] = [0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.6, 0.8];

/// One fit: its group and case, the population, the hand samples fitted, the fit, its seconds.
struct Run {
    group: &'static str,
    label: String,
    params: PopulationParams,
    samples: usize,
    fit: NuFit,
    seconds: f64,
}

fn main() -> Result<()> {
    let common = harness::common_args("The fit of ν to Table 2 and its sensitivity to the synthetic pebbles.");
    let out = Results::open("table2_fit_nu", &common)?;
    let data = harness::repo().join("data/table2_hand_experiments.csv");
    let hand = study::read_table2(&data)?;
    let scanned: Vec<HandSample> = hand.iter().filter(|h| h.computer.is_some()).cloned().collect();
    let (opts, seed) = (FitOptions::default(), common.seed_or(1));
    let s_only = FitOptions { statistics: [true, false, true, false], ..opts.clone() };
    let base = PopulationParams { spread: 0.08, points: 2000, count: 50, seed, calibrate: true, roughness: 0.0 };
    let fit =
        |(group, label, params, hand, opts): (&'static str, String, PopulationParams, &[HandSample], &FitOptions)| {
            let t = std::time::Instant::now();
            let (fit, _) = study::fit_table2(hand, &params, opts)?;
            let seconds = t.elapsed().as_secs_f64();
            eprintln!("{group:<10} {label:<28} ν = {:.3e}, χ² = {:.0} ({seconds:.1} s)", fit.nu, fit.chi2_min);
            anyhow::Ok(Run { group, label, params, samples: hand.len(), fit, seconds })
        };
    let with = |base: &PopulationParams, f: &dyn Fn(&mut PopulationParams)| {
        let mut p = base.clone();
        f(&mut p);
        p
    };
    let mut runs = ROUGHNESS
        .map(|r| ("roughness", format!("roughness {r}"), with(&base, &|p| p.roughness = r), &hand[..], &opts))
        .into_iter()
        .map(fit)
        .collect::<Result<Vec<_>>>()?;
    // The base case: the roughness with the lowest χ²; the other groups vary one thing about it.
    let best = runs.iter().min_by(|a, b| a.fit.chi2_min.total_cmp(&b.fit.chi2_min)).expect("runs");
    let (r0, b) = (best.params.roughness, best.fit.clone());
    let base = with(&base, &|p| p.roughness = r0);
    let mut specs = Vec::new();
    specs.extend(
        [1000, 4000, 8000].map(|n| ("points", format!("{n} points"), with(&base, &|p| p.points = n), &hand[..])),
    );
    specs.extend([0.04, 0.12].map(|s| ("spread", format!("spread {s}"), with(&base, &|p| p.spread = s), &hand[..])));
    specs.extend([seed + 1, seed + 2].map(|s| ("seed", format!("seed {s}"), with(&base, &|p| p.seed = s), &hand[..])));
    specs.push(("scanned", "5 scanned samples".into(), base.clone(), &scanned));
    specs.push(("scanned", "5 scanned samples, 20 pebbles".into(), with(&base, &|p| p.count = 20), &scanned));
    let mut specs: Vec<_> = specs.into_iter().map(|(g, l, p, h)| (g, l, p, h, &opts)).collect();
    specs.push(("statistics", "E(S), σ(S) only".into(), base.clone(), &hand, &s_only));
    specs.push(("calibrate", "no ratio calibration".into(), with(&base, &|p| p.calibrate = false), &hand, &opts));
    for spec in specs {
        runs.push(fit(spec)?);
    }

    let fits: Vec<_> =
        runs.iter().map(|r| ((r.group, r.label.as_str(), r.samples, r.seconds), &r.params, &r.fit)).collect();
    write_fits_csv(&out.path("fits.csv"), &out.path("loss_curves.csv"), &fits)?;

    let rough: Vec<&Run> = runs.iter().filter(|r| r.group == "roughness").collect();
    for (group, what) in [
        ("roughness", "by roughness amplitude of the synthetic pebbles"),
        ("points", "by resolution (points per synthetic pebble)"),
        ("spread", "by spread of the axis ratios within a sample"),
    ] {
        let mut fits: Vec<(String, &NuFit)> =
            runs.iter().filter(|r| r.group == group).map(|r| (r.label.clone(), &r.fit)).collect();
        if group != "roughness" {
            fits.insert(0, (format!("base ({} points, spread {})", base.points, base.spread), &b));
        }
        let (title, y) =
            (format!("Misfit χ²(ν) to Table 2's hand counts, {what}"), "χ² over 22 samples × 4 statistics (log scale)");
        let chart = loss_chart(&title, y, &fits);
        for ext in ["png", "svg"] {
            chart.clone().save(&out.path(&format!("loss_{group}.{ext}")), (1000, 680))?;
        }
    }
    let chart = nu_against_roughness(&rough.iter().map(|r| (r.params.roughness, &r.fit)).collect::<Vec<_>>());
    for ext in ["png", "svg"] {
        chart.clone().save(&out.path(&format!("nu_vs_roughness.{ext}")), (900, 600))?;
    }

    // Numbers for the discussion, read off the runs.
    let r_paper = rough.windows(2).find_map(|w| {
        let (a, b) = (w[0], w[1]);
        ((a.fit.nu - PAPER_NU) * (b.fit.nu - PAPER_NU) <= 0.0).then(|| {
            let t = (PAPER_NU / a.fit.nu).ln() / (b.fit.nu / a.fit.nu).ln();
            (a.params.roughness.ln() + t * (b.params.roughness / a.params.roughness).ln()).exp()
        })
    });
    let of =
        |g: &str, f: fn(&NuFit) -> f64| runs.iter().filter(|r| r.group == g).map(|r| f(&r.fit)).collect::<Vec<_>>();
    let e2 = |(lo, hi): (f64, f64)| [format!("{lo:.2e}"), format!("{hi:.2e}")];
    let range = |v: Vec<f64>| e2(min_max(v));
    let seeds: Vec<f64> = std::iter::once(b.nu).chain(of("seed", |f| f.nu)).collect();
    let seed_sd = sample_sd(&seeds.iter().map(|x| x.log10()).collect::<Vec<_>>());
    let chis: Vec<f64> = std::iter::once(b.chi2_min).chain(of("seed", |f| f.chi2_min)).collect();
    let with_base = |g: &str| of(g, |f| f.nu).into_iter().chain([b.nu]).collect::<Vec<_>>();
    let chi_r = |r: f64| rough.iter().find(|x| x.params.roughness == r).map_or(f64::NAN, |x| x.fit.chi2_min);
    let end = |r: Option<&&Run>| {
        [cell(r.map_or(f64::NAN, |r| r.fit.nu), 1, true), r.map_or("–".into(), |r| r.params.roughness.to_string())]
    };
    let span = |(lo, hi): (f64, f64)| format!("{} – {}", cell(lo, 2, true), cell(hi, 2, true));
    let runs_table: Vec<_> = runs
        .iter()
        .map(|r| {
            let (f, c) = (&r.fit, r.fit.chi2_by_statistic);
            let case = if r.group == "roughness" { r.label.clone() } else { format!("{} (roughness {r0})", r.label) };
            let nu = format!("{}{}", cell(f.nu, 2, true), if f.at_edge { " (grid end)" } else { "" });
            let (parts, seconds) =
                (c.map(|x| cell(x, 0, false)).join(" / "), format!("{} s", cell(r.seconds, 0, false)));
            json!({"cells": [r.group, case, r.samples.to_string(), nu, span(f.interval), span(f.bootstrap_interval),
            cell(f.chi2_min, 0, false), parts, seconds]})
        })
        .collect();
    let grid = opts.grid.len();
    let s_only = runs.iter().find(|r| r.group == "statistics").map_or(f64::NAN, |r| r.fit.nu);
    let context = json!({
        "grid": [opts.grid.len().to_string(), format!("{:.0e}", opts.grid[0]), format!("{:.0e}", opts.grid[grid - 1])],
        "bootstrap": opts.bootstrap, "r0": r0.to_string(), "points": base.points,
        "spread": base.spread.to_string(), "count": base.count, "seed": seed, "seed_hi": seed + 2,
        "nu": format!("{:.2e}", b.nu), "interval": e2(b.interval), "boot": e2(b.bootstrap_interval),
        "sd_log10": fixed(b.bootstrap_sd_log10, 2), "chi2_min": fixed(b.chi2_min, 0), "terms": b.terms, "dof": b.dof,
        "reduced": fixed(b.chi2_min / b.dof as f64, 1), "by_statistic": b.chi2_by_statistic.map(|x| fixed(x, 0)),
        "runs": runs_table, "nu_1": format!("{:.1e}", b.nu), "scatter": fixed(10f64.powf(seed_sd), 1),
        "seed_range": range(seeds), "seed_sd": fixed(seed_sd, 2),
        "first": end(rough.first()), "last": end(rough.last()),
        "r_paper": r_paper.map_or("— (not crossed)".into(), |r| format!("{r:.2}")),
        "chi_rough": ([0.1, 0.2, 0.4, 0.6, 0.8].map(|r| cell(chi_r(r), 0, false))),
        "chi_sd": cell(sample_sd(&chis), 0, false), "s_only": cell(s_only, 2, true),
        "points_range": range(with_base("points")), "spread_range": range(with_base("spread")),
    });
    out.readme(include_str!("readme/table2_fit_nu.md"), context)
}
