//! Paper Figure 12 and Table 2: the hand experiments against synthetic populations of all 22
//! samples, the dynamic experimenter on the 5 scanned samples, and a field study of the scanned
//! quarry stones in `data/meshes`.
//!
//! Run: `cargo experiment fig12_hand_vs_computer` → `results/fig12_hand_vs_computer/`;
//! the README's prose is `experiments/readme/fig12_hand_vs_computer.md`.

use rocking_stones::analysis::PAPER_NU;
use rocking_stones::prelude::*;
use rocking_stones::report;
use rocking_stones::study::{
    self, Comparison, Experimenter, FitOptions, HandSample, Metadata, PopulationParams, StudyOptions,
};
use serde_json::{json, Value};
use std::fs::File;
use std::path::{Path, PathBuf};

use experiments::harness;
use harness::{Result, Results};

/// The roughness amplitudes scanned; the synthetic pebbles use the one with the lowest χ² against
/// the hand columns (the same rule and scan as `table2_fit_nu`, whose README shows how ν̂ depends
/// on it).
const ROUGHNESS_SCAN: [f64; 9] = [0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.6, 0.8];
/// Set-downs per pebble of the dynamic experimenter.
const TRIALS: [u64; 3] = [5, 20, 100];

fn main() -> Result<()> {
    let common = harness::common_args("Hand experiments against synthetic populations and the dynamic experimenter.");
    let root = harness::repo();
    let out = Results::open("fig12_hand_vs_computer", &common)?;
    let hand = study::read_table2(&root.join("data/table2_hand_experiments.csv"))?;
    let base = PopulationParams { seed: common.seed_or(1), ..PopulationParams::default() };
    let quick = FitOptions { bootstrap: 0, ..FitOptions::default() };
    let mut best = (f64::INFINITY, 0.0);
    for r in ROUGHNESS_SCAN {
        let (f, _) = study::fit_table2(&hand, &PopulationParams { roughness: r, ..base.clone() }, &quick)?;
        eprintln!("roughness {r}: ν = {:.3e}, χ² = {:.0}", f.nu, f.chi2_min);
        if f.chi2_min < best.0 {
            best = (f.chi2_min, r);
        }
    }
    let params = PopulationParams { roughness: best.1, ..base };
    let t = std::time::Instant::now();
    let (fit, mut synthetic) = study::fit_table2(&hand, &params, &FitOptions::default())?;
    eprintln!("fit: ν = {:.3e} ({:.1} s)", fit.nu, t.elapsed().as_secs_f64());
    let mut sections = Vec::new();
    for (nu, name, what) in [(fit.nu, "fitted", "the fitted ν"), (PAPER_NU, "paper_nu", "the paper's ν = 0.0035")] {
        let rows = study::compare(&hand, &synthetic, nu);
        report::study::write_comparison_csv(&rows, nu, File::create(out.path(&format!("comparison_{name}.csv")))?)?;
        report::study::plot_fig12(&rows, nu, "synthetic", &out.path(name))?;
        sections.push(comparison(&rows, nu, name, what));
    }
    synthetic.nu = fit.nu;
    let summaries = study::summarize(&synthetic);
    report::study::write_samples_csv(&synthetic, &summaries, File::create(out.path("synthetic_samples.csv"))?)?;
    for ext in ["png", "svg"] {
        let path = out.path(&format!("synthetic_zingg.{ext}"));
        report::study::plot_zingg(&synthetic, "Zingg diagram: synthetic Table 2 populations", &path)?;
    }
    let dynamic = dynamic_experimenter(&out, &hand, &params, fit.nu)?;
    let field = field_study(&out, root)?;
    out.readme(
        include_str!("readme/fig12_hand_vs_computer.md"),
        json!({
            "count": params.count,
            "roughness": params.roughness.to_string(),
            "points": params.points,
            "spread": params.spread.to_string(),
            "seed": params.seed,
            "scan": format!("{ROUGHNESS_SCAN:?}"),
            "nu": format!("{:.2e}", fit.nu),
            "nu_lo": format!("{:.2e}", fit.bootstrap_interval.0),
            "nu_hi": format!("{:.2e}", fit.bootstrap_interval.1),
            "sections": sections,
            "dynamic": dynamic,
            "field": field,
        }),
    )
}

/// The README's numbers of one comparison (hand against synthetic at one ν).
fn comparison(rows: &[Comparison], nu: f64, name: &str, what: &str) -> Value {
    let t = study::trends(rows);
    let describe = |f: Option<rocking_stones::stats::LogFit>| f.map_or("—".into(), |f| f.describe());
    let f2 = |x: f64| format!("{x:.2}");
    let four = |v: [f64; 4]| v.map(f2).join(" ");
    // Synthetic − hand of each moment over the samples: mean and rms.
    let diffs = study::differences(rows).map(|(bias, rms)| json!({"bias": format!("{bias:+.2}"), "rms": f2(rms)}));
    json!({
        "name": name,
        "what": what,
        "nu": format!("{nu:.2e}"),
        "trends": t.relations().map(|(label, h, c)| [label.to_string(), describe(h), describe(c)]),
        "rise": t.hand_es_cb.zip(t.sim_es_cb).map(|(h, c)| json!({
            "hand": f2(h.slope), "sim": f2(c.slope), "hand_r2": f2(h.r2), "sim_r2": f2(c.r2),
        })),
        "diff": diffs,
        "rows": rows.iter().map(|r| [
            r.id.clone(),
            f2(r.hand_c_over_b),
            f2(r.hand_c_over_a),
            four(r.hand),
            four(r.sim.as_array()),
            r.paper_computer.map_or(String::new(), four),
        ]).collect::<Vec<_>>(),
    })
}

/// The dynamic experimenter on the scanned samples: `dynamic_experimenter.csv` and the README's rows.
fn dynamic_experimenter(
    out: &Results,
    hand: &[HandSample],
    params: &PopulationParams,
    nu: f64,
) -> Result<Vec<[String; 7]>> {
    let scanned: Vec<&HandSample> = hand.iter().filter(|h| h.computer.is_some()).collect();
    let targets: Vec<_> = scanned.iter().map(|h| h.target()).collect();
    let p = PopulationParams { count: 20, ..params.clone() };
    let mut per_trials = Vec::new();
    for trials in TRIALS {
        let exp = Experimenter { trials, ..Experimenter::default() };
        let t = std::time::Instant::now();
        let st = study::synthetic_study(&targets, &p, nu, Some(&exp))?;
        eprintln!("dynamic, {trials} trials: {:.1} s", t.elapsed().as_secs_f64());
        per_trials.push(study::summarize(&st));
    }
    let get = |k: usize, id: &str| per_trials[k].iter().find(|x| x.sample == id).expect("every sample is summarised");
    let f4 = |x: Option<f64>| format!("{:.4}", x.unwrap_or(f64::NAN));
    out.csv(
        "dynamic_experimenter.csv",
        &"sample nu hand_E_S hand_sd_S static_E_S static_sd_S trials dyn_E_S dyn_sd_S dyn_rocking"
            .split(' ')
            .collect::<Vec<_>>(),
        scanned.iter().flat_map(|h| {
            TRIALS.iter().enumerate().map(move |(k, trials)| {
                let g = get(k, &h.id);
                [
                    h.id.clone(),
                    format!("{nu:e}"),
                    format!("{}", h.hand[0]),
                    format!("{}", h.hand[2]),
                    format!("{:.4}", g.hand.es),
                    format!("{:.4}", g.hand.sd_s),
                    trials.to_string(),
                    f4(g.dyn_es),
                    f4(g.dyn_sd_s),
                    f4(g.dyn_rocking),
                ]
            })
        }),
    )?;
    // sample, hand, static, dynamic at each number of trials, rocking found at the most.
    let pm = |m: f64, s: Option<f64>| format!("{m:.2} ± {:.2}", s.unwrap_or(f64::NAN));
    let dynamic = |k: usize, id: &str| pm(get(k, id).dyn_es.unwrap_or(f64::NAN), get(k, id).dyn_sd_s);
    Ok(scanned
        .iter()
        .map(|h| {
            let rocking = format!("{:.2}", get(2, &h.id).dyn_rocking.unwrap_or(f64::NAN));
            let (hand, stat) =
                (pm(h.hand[0], Some(h.hand[2])), pm(get(0, &h.id).hand.es, Some(get(0, &h.id).hand.sd_s)));
            [h.id.clone(), hand, stat, dynamic(0, &h.id), dynamic(1, &h.id), dynamic(2, &h.id), rocking]
        })
        .collect())
}

/// The field study of the scanned quarry stones, in `field_study/`: how many, and the samples' table.
fn field_study(out: &Results, root: &Path) -> Result<Value> {
    let meshes = root.join("data/meshes");
    let files: Vec<PathBuf> =
        study::mesh_files(&meshes)?.into_iter().filter(|f| study::pebble_id(f).starts_with("stone_quarry")).collect();
    let dir = out.path("field_study");
    std::fs::create_dir_all(&dir)?;
    let mut meta = String::from("id;sample;origin;material;source\n");
    for f in &files {
        let id = study::pebble_id(f);
        let sample = if id.contains("lowres") { "IBOIS lowres" } else { "IBOIS other" };
        meta += &format!("{id};{sample};EPFL IBOIS stone scans;limestone;see data/meshes/SOURCES.md\n");
    }
    let meta_path = dir.join("metadata.csv");
    std::fs::write(&meta_path, &meta)?;
    let meta = Metadata::read(&meta_path)?;
    let experimenter = Some(Experimenter::default());
    let opts = StudyOptions { analysis: Options::default(), nu: PAPER_NU, experimenter, allow_unmatched: false };
    let t = std::time::Instant::now();
    let (mut study, _) = study::run_files(&files, Some(&meta), &opts, &|| {})?;
    eprintln!("field study: {:.1} s", t.elapsed().as_secs_f64());
    // Paths in the CSV relative to the repository, as a user running from it would see them.
    study.relative_to(root);
    let summaries = study::summarize(&study);
    report::study::write_pebbles_csv(&study, File::create(dir.join("pebbles.csv"))?)?;
    report::study::write_samples_csv(&study, &summaries, File::create(dir.join("samples.csv"))?)?;
    for ext in ["png", "svg"] {
        report::study::plot_zingg(&study, "Zingg diagram: IBOIS quarry stones", &dir.join(format!("zingg.{ext}")))?;
    }
    Ok(json!({"stones": files.len(), "table": report::study::samples_table(&study, &summaries)}))
}
