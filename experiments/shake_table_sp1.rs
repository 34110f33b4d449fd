//! One real rock's shake-table tests against the ensemble's P(overturn): the rock scanned closed,
//! and cut open above its base as a field scan sees it. The calibration of the hidden base's
//! defaults (in-sample: the only tests it is scored on are the ones it was tuned on).
//!
//! The tests are not in the repository (GPL-3.0): give their folder (`SP1.ply`, `tests.csv`,
//! `motions/TestNNN.csv`) as the argument; without it the experiment says so, writes nothing.
//!
//! Run: `cargo experiment shake_table_sp1 -- DIR` → `results/shake_table_sp1/`; the README's prose
//! is `experiments/readme/shake_table_sp1.md`.

use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::shaking::{
    field_members, run_batch, BaseUncertainty, EnsembleSpec, FieldRock, Pose, RockSetup, Uncertainty,
};
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::ground_motion::read::{read_csv, AccelUnit};
use rocking_stones::prelude::Chart;
use rocking_stones::stats::{forecast_scores, Forecast};
use serde::Deserialize;
use serde_json::json;
use std::path::PathBuf;

use experiments::harness::{self, fixed, Parser, Result, Results};

/// Shake-table tests of one scanned rock: the ensemble's P(overturn) scored, closed and cut open.
#[derive(Parser)]
struct Args {
    /// The folder of the tests: SP1.ply, tests.csv and motions/TestNNN.csv (not in the repository).
    dir: Option<PathBuf>,
    /// Heights (mm) above the base at which the scan is cut open; 0: the closed scan.
    #[arg(long, default_value = "0,2,5,10,20", value_delimiter = ',')]
    cuts_mm: Vec<f64>,
    /// Members of each ensemble.
    #[arg(long, default_value_t = 16)]
    members: u64,
    /// Every k-th test only (calibration runs on a subset).
    #[arg(long, default_value_t = 1)]
    every: usize,
    /// The bases to run: drawn (every member its own), scanned (the scan's own base, a field
    /// scan's flat cap: the ensemble before), or both.
    #[arg(long, default_value = "drawn,scanned", value_delimiter = ',', value_parser = ["drawn", "scanned"])]
    bases: Vec<String>,
    /// Calibration: the closed scan's band (mm).
    #[arg(long)]
    band_mm: Option<f64>,
    /// Calibration: the field scan's depth range LOW,HIGH (mm).
    #[arg(long, value_delimiter = ',')]
    depth_mm: Option<Vec<f64>>,
    /// Calibration: the region's range LOW,HIGH (× the footprint's radius).
    #[arg(long, value_delimiter = ',')]
    region: Option<Vec<f64>>,
    /// Calibration: the slope range LOW,HIGH of the underside away from its support.
    #[arg(long, value_delimiter = ',')]
    slope: Option<Vec<f64>>,
    /// Calibration: the deepest support as a multiple of the walls' closing depth.
    #[arg(long)]
    walls: Option<f64>,
    /// Calibration: the deepest support at least this multiple of the footprint's radius.
    #[arg(long)]
    floor: Option<f64>,
    /// Calibration: the region's largest radius over G's height.
    #[arg(long)]
    reach: Option<f64>,
    /// Calibration: the azimuth's half range (degrees) around the table's axis.
    #[arg(long)]
    azimuth_spread: Option<f64>,
    /// Calibration: the record's sign unknown (each member flips it with probability ½).
    #[arg(long)]
    random_sign: bool,
    /// Further seeds of the drawn ensembles: how much their scores move with the draw of the
    /// members' bases alone (seed_spread.csv, beside the --seed of the main run).
    #[arg(long, value_delimiter = ',')]
    spread_seeds: Vec<u64>,
    #[command(flatten)]
    common: harness::Common,
}

/// One row of tests.csv (other columns ignored).
#[derive(Deserialize)]
struct Test {
    test: u32,
    motion: String,
    overturned: u8,
}

fn main() -> Result<()> {
    let args = Args::parse();
    let Some((dir, tests)) =
        harness::shake_table_tests::<Test>("shake_table_sp1", &args.dir, "SP1.ply, tests.csv, motions/")?
    else {
        return Ok(());
    };
    let tests: Vec<Test> = tests.into_iter().step_by(args.every.max(1)).collect();
    let columns = "time_s,ax_g".parse()?;
    let records = tests
        .iter()
        .map(|t| read_csv(&dir.join(&t.motion), &columns, AccelUnit::G))
        .collect::<rocking_stones::Result<Vec<_>>>()?;
    let mesh = rocking_stones::mesh::io::read(&dir.join("SP1.ply"))?;
    let calibrated = BaseUncertainty::calibrated();
    let base = BaseUncertainty {
        band_m: args.band_mm.map_or(calibrated.band_m, |b| b * 1e-3),
        depth_m: args.depth_mm.as_ref().map(|d| [d[0] * 1e-3, d[d.len() - 1] * 1e-3]),
        walls: args.walls.unwrap_or(calibrated.walls),
        floor: args.floor.unwrap_or(calibrated.floor),
        region: args.region.as_ref().map_or(calibrated.region, |r| [r[0], r[r.len() - 1]]),
        slope: args.slope.as_ref().map_or(calibrated.slope, |r| [r[0], r[r.len() - 1]]),
        reach: args.reach.unwrap_or(calibrated.reach),
        ..calibrated
    };
    let out = Results::open("shake_table_sp1", &args.common)?;
    let observed: Vec<bool> = tests.iter().map(|t| t.overturned == 1).collect();
    let mut scores = Vec::new();
    let mut per_test: Vec<Vec<String>> = tests.iter().map(|t| vec![t.test.to_string()]).collect();
    let mut sets = Vec::new();
    let runs: Vec<(f64, bool)> =
        args.bases.iter().flat_map(|b| args.cuts_mm.iter().map(move |&c| (c, b == "drawn"))).collect();
    let run = |cut: f64, drawn: bool, seed: u64| -> Result<(Vec<f64>, f64, rocking_stones::stats::ForecastScores)> {
        let scan = if cut > 0.0 { rocking_stones::mesh::cut_base(&mesh, cut * 1e-3)? } else { mesh.clone() };
        let opts = Options::default();
        let analysis = Analysis::of_scan(scan.clone(), &opts)?;
        let stone = Stone::new(&analysis, analysis.macro_nu(&opts).0)?;
        let setup = RockSetup::new(&stone, Pose::AsScanned, 1.0, Surface::RockOnConcrete, 0.0)?;
        let uncertainty = Uncertainty {
            base: drawn.then_some(base),
            random_sign: args.random_sign,
            azimuth_deg: args.azimuth_spread.map(|a| [-a, a]),
            ..Uncertainty::stated(&Uncertainty::default(), Surface::RockOnConcrete, [false; 3])
        };
        let spec = EnsembleSpec { uncertainty, seed, members: args.members };
        let rocks = field_members(&analysis, &opts, &stone, &setup, &spec)?;
        let rock = FieldRock { stone: &stone, members: &rocks };
        let batch = run_batch(rock, &setup, &records, &[1.0], Some(&spec), &[], &|_| {})?;
        let p: Vec<f64> = records
            .iter()
            .map(|r| {
                batch.probabilities.iter().find(|s| s.record == r.name).map_or(f64::NAN, |s| s.probability.p_overturn)
            })
            .collect();
        let truths: Vec<[bool; 1]> = observed.iter().map(|&y| [y]).collect();
        let cases: Vec<Forecast> = p.iter().zip(&truths).map(|(&p, y)| (p, &y[..])).collect();
        let s = forecast_scores(&cases, 0.5 / args.members as f64);
        Ok((p, rocks.iter().map(|r| r.base.depth_m).fold(0.0, f64::max), s))
    };
    let mean = |p: &[f64]| p.iter().sum::<f64>() / p.len() as f64;
    let label = |cut: f64| if cut > 0.0 { format!("cut {cut} mm") } else { "closed".to_string() };
    let mut spread = Vec::new();
    for (cut, drawn) in runs {
        let t0 = std::time::Instant::now();
        let (p, deepest_m, s) = run(cut, drawn, args.common.seed_or(1))?;
        let seconds = t0.elapsed().as_secs_f64();
        if drawn && !args.spread_seeds.is_empty() {
            spread.push(vec![label(cut), args.common.seed_or(1).to_string(), fixed(s.brier, 4), fixed(mean(&p), 3)]);
            for &seed in &args.spread_seeds {
                let (p, _, s) = run(cut, drawn, seed)?;
                spread.push(vec![label(cut), seed.to_string(), fixed(s.brier, 4), fixed(mean(&p), 3)]);
            }
        }
        let zero: Vec<bool> = p.iter().zip(&observed).filter(|(p, _)| **p == 0.0).map(|(_, y)| *y).collect();
        let label = label(cut);
        let row = json!({
            "scan": label, "cut_mm": cut, "base": if drawn { "drawn" } else { "scanned" }, "tests": p.len(), "brier": fixed(s.brier, 4), "log_loss": fixed(s.log_loss, 4),
            "accuracy": fixed(s.accuracy, 3), "mean_p": fixed(mean(&p), 3),
            "observed": fixed(observed.iter().filter(|&&y| y).count() as f64 / p.len() as f64, 3),
            "p_zero": zero.len(), "p_zero_overturned": zero.iter().filter(|&&y| y).count(),
            "deepest_support_mm": fixed(1e3 * deepest_m, 1),
            "seconds": fixed(seconds, 0),
        });
        eprintln!("{row}");
        scores.push(row);
        for (r, p) in per_test.iter_mut().zip(&p) {
            r.push(fixed(*p, 4));
        }
        sets.push((format!("{label}, {}", if drawn { "drawn" } else { "scanned" }), p));
    }
    let header: Vec<String> = std::iter::once("test".to_string())
        .chain(sets.iter().map(|(l, _)| format!("p_{}", l.replace(", ", "_").replace(' ', "_"))))
        .collect();
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    out.csv("p_overturn.csv", &header, &per_test)?;
    let keys =
        harness::columns("scan,cut_mm,base,tests,brier,log_loss,accuracy,mean_p,observed,p_zero,p_zero_overturned");
    let rows: Vec<Vec<String>> =
        scores.iter().map(|s| keys.iter().map(|k| s[k].to_string().trim_matches('"').to_string()).collect()).collect();
    out.csv("scores.csv", &keys, &rows)?;
    let truths: Vec<[bool; 1]> = observed.iter().map(|&y| [y]).collect();
    for (base, file) in [("drawn", "reliability_drawn.png"), ("scanned", "reliability_scanned.png")] {
        let diagram: Vec<(String, Vec<Forecast>)> = sets
            .iter()
            .filter(|(l, _)| l.ends_with(base))
            .map(|(l, p)| (l.clone(), p.iter().zip(&truths).map(|(&p, y)| (p, &y[..])).collect()))
            .collect();
        if diagram.is_empty() {
            continue;
        }
        let title = format!("P(overturn) against the shake table: base {base}");
        let chart: Chart = rocking_stones::plot::reliability_diagram(&title, &diagram);
        chart.save(&out.path(file), (900, 800))?;
    }
    let mut context = json!({
        "base": base, "scores": scores, "tests": tests.len(), "members": args.members, "every": args.every,
        "observed": fixed(observed.iter().filter(|&&y| y).count() as f64 / observed.len() as f64, 3),
    });
    if !spread.is_empty() {
        out.csv("seed_spread.csv", &["scan", "seed", "brier", "mean_p"], &spread)?;
        context["spread"] = json!(spread);
    }
    out.write("scores.json", serde_json::to_string_pretty(&context)?)?;
    out.readme(include_str!("readme/shake_table_sp1.md"), &context)
}
