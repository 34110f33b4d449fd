//! Simulated truth for open scans: real closed stones stood on their poses, shaken as they are
//! (the truth), then cut open 2–20 mm above their base as a field scan sees them and shaken as
//! an ensemble whose members draw the hidden base, beside the same scan closed by a flat cap.
//! The truth is simulated (the closed stone in the same simulator): a consistency check of the
//! hidden base, not a validation. Prose: `experiments/readme/open_scan_truth.md`.
//!
//! Run: `cargo experiment open_scan_truth` → `results/open_scan_truth/`.

use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::shaking::{
    default_poses, field_members, run_batch, BaseUncertainty, EnsembleSpec, FieldRock, Pose, RockSetup, Uncertainty,
};
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::ground_motion::synthetic::{filtered_noise, one_sine_pulse, Noise};
use rocking_stones::ground_motion::Record;
use rocking_stones::mesh::{cut_base, stand_on, TriMesh};
use rocking_stones::prelude::Chart;
use rocking_stones::stats::{forecast_scores, Forecast};
use rocking_stones::tipping::TippingPolar;
use rocking_stones::Point3;
use serde_json::json;

use experiments::harness::{self, fixed, Context, Parser, Result, Results};

/// The stones (file, metres per mesh unit).
const STONES: [(&str, f64); 4] = [
    ("data/default_pebble.ply", 1e-3),
    ("data/meshes/stone_quarry_ibois_stone0_ascii.ply", 1.0),
    ("data/meshes/stone_quarry_ibois_AAA_lowres_bin.ply", 1.0),
    ("data/meshes/stone_quarry_ibois_E22_lowres_bin.ply", 1.0),
];
/// Heights (mm) above the base at which the scans are cut open.
const CUTS_MM: [f64; 4] = [2.0, 5.0, 10.0, 20.0];
/// One-sine pulses: amplitude as a multiple of the pose's tipping threshold g tan α, and
/// frequency as a multiple of the rock's frequency parameter p = √(3g / 4R_max).
const AMPLITUDES: [f64; 6] = [1.5, 2.0, 3.0, 4.0, 6.0, 8.0];
const FREQUENCIES: [f64; 3] = [0.75, 1.5, 3.0];

/// Simulated truth for open scans: closed stones against their cut-open ensembles.
#[derive(Parser)]
struct Args {
    /// Members of each ensemble.
    #[arg(long, default_value_t = 16)]
    members: u64,
    #[command(flatten)]
    common: harness::Common,
}

/// One stone in one pose under one record: the truth and the two forecasts at one cut.
struct Case {
    stone: String,
    pose: &'static str,
    cut_mm: f64,
    record: String,
    truth: bool,
    drawn: f64,
    flat: f64,
}

fn main() -> Result<()> {
    let args = Args::parse();
    let out = Results::open("open_scan_truth", &args.common)?;
    let opts = Options::default();
    let base = BaseUncertainty::calibrated();
    let spec = EnsembleSpec {
        uncertainty: Uncertainty { base: Some(base), ..Uncertainty::default() },
        seed: args.common.seed_or(1),
        members: args.members,
    };
    let t0 = std::time::Instant::now();
    let mut cases = Vec::new();
    let mut refused = Vec::new();
    for (file, unit) in STONES {
        let mesh = rocking_stones::mesh::io::read(&harness::repo().join(file)).with_context(|| file.to_string())?;
        let scanned = Analysis::of_scan(mesh.clone(), &opts)?;
        let stone = Stone::new(&scanned, scanned.macro_nu(&opts).0)?;
        let name = file.rsplit('/').next().unwrap_or(file).trim_end_matches(".ply").to_string();
        let (regular, rocking) = default_poses(&stone, stone.body.r_max * unit)?;
        for (pose, id) in [("regular", regular), ("rocking", rocking)] {
            let Some(id) = id else { continue };
            let facet = stone.stable()[stone.position(id).context("a default pose")?].facet;
            let standing = stand_on(&mesh, &stone.body.facet_normals[facet as usize])?;
            let (truth, records) = truth_of(&standing, unit, &opts)?;
            eprintln!(
                "{name} {pose}: {} of {} records overturn the closed stone",
                truth.iter().filter(|&&t| t).count(),
                truth.len()
            );
            for cut in CUTS_MM {
                // What the tool refuses (a rim it cannot read) is reported, not skipped silently.
                let forecasts = (|| -> rocking_stones::Result<_> {
                    let open = cut_base(&standing, cut * 1e-3 / unit)?;
                    let a = Analysis::of_scan(open, &opts)?;
                    let s = Stone::new(&a, a.macro_nu(&opts).0)?;
                    let setup = RockSetup::new(&s, Pose::AsScanned, unit, Surface::RockOnConcrete, 0.0)?;
                    let rocks = field_members(&a, &opts, &s, &setup, &spec)?;
                    let rock = FieldRock { stone: &s, members: &rocks };
                    let drawn = run_batch(rock, &setup, &records, &[1.0], Some(&spec), &[], &|_| {})?;
                    let flat = run_batch(&s, &setup, &records, &[1.0], None, &[], &|_| {})?;
                    Ok((drawn, flat))
                })();
                let (drawn, flat) = match forecasts {
                    Ok(f) => f,
                    Err(e) => {
                        eprintln!("{name} {pose} cut {cut} mm: refused: {e}");
                        refused.push(json!({ "stone": name, "pose": pose, "cut_mm": cut, "error": e.to_string() }));
                        continue;
                    }
                };
                for ((r, t), f) in records.iter().zip(&truth).zip(&flat.runs) {
                    let p = drawn.probabilities.iter().find(|x| x.record == r.name).context("every record's P")?;
                    cases.push(Case {
                        stone: name.clone(),
                        pose,
                        cut_mm: cut,
                        record: r.name.clone(),
                        truth: *t,
                        drawn: p.probability.p_overturn,
                        flat: if f.rock.overturned { 1.0 } else { 0.0 },
                    });
                }
            }
        }
    }
    let seconds = t0.elapsed().as_secs_f64();
    let cost = cost(&opts, &spec)?;
    eprintln!("cost: {cost}");
    let rows: Vec<Vec<String>> = cases
        .iter()
        .map(|c| {
            vec![
                c.stone.clone(),
                c.pose.to_string(),
                fixed(c.cut_mm, 0),
                c.record.clone(),
                (c.truth as u8).to_string(),
                fixed(c.drawn, 4),
                fixed(c.flat, 0),
            ]
        })
        .collect();
    out.csv("cases.csv", &["stone", "pose", "cut_mm", "record", "truth_overturned", "p_drawn", "p_flat_cap"], &rows)?;
    let truths: Vec<[bool; 1]> = cases.iter().map(|c| [c.truth]).collect();
    let mut scores = Vec::new();
    for cut in CUTS_MM {
        let k: Vec<usize> = (0..cases.len()).filter(|&i| cases[i].cut_mm == cut).collect();
        let n = k.len() as f64;
        let score = |p: &dyn Fn(&Case) -> f64| {
            let f: Vec<Forecast> = k.iter().map(|&i| (p(&cases[i]), &truths[i][..])).collect();
            forecast_scores(&f, 0.5 / args.members as f64)
        };
        let (d, f) = (score(&|c| c.drawn), score(&|c| c.flat));
        // The truth lies outside the members' spread when every member says the other outcome.
        let outside = |p: &dyn Fn(&Case) -> f64| {
            k.iter().filter(|&&i| if cases[i].truth { p(&cases[i]) == 0.0 } else { p(&cases[i]) == 1.0 }).count()
        };
        let mean = |p: &dyn Fn(&Case) -> f64| k.iter().map(|&i| p(&cases[i])).sum::<f64>() / n;
        scores.push(json!({
            "cut_mm": cut, "cases": k.len(),
            "truth_rate": fixed(k.iter().filter(|&&i| cases[i].truth).count() as f64 / n, 3),
            "mean_p_drawn": fixed(mean(&|c| c.drawn), 3), "brier_drawn": fixed(d.brier, 4),
            "outside_drawn": outside(&|c| c.drawn),
            "mean_p_flat": fixed(mean(&|c| c.flat), 3), "brier_flat": fixed(f.brier, 4),
            "outside_flat": outside(&|c| c.flat),
        }));
    }
    let keys = [
        "cut_mm",
        "cases",
        "truth_rate",
        "mean_p_drawn",
        "brier_drawn",
        "outside_drawn",
        "mean_p_flat",
        "brier_flat",
        "outside_flat",
    ];
    let rows: Vec<Vec<String>> =
        scores.iter().map(|s| keys.iter().map(|k| s[k].to_string().trim_matches('"').to_string()).collect()).collect();
    out.csv("scores.csv", &keys, &rows)?;
    let sets: Vec<(String, Vec<Forecast>)> = [("drawn bases", true), ("flat cap", false)]
        .iter()
        .map(|&(label, drawn)| {
            let f = cases.iter().zip(&truths).map(|(c, t)| (if drawn { c.drawn } else { c.flat }, &t[..])).collect();
            (label.to_string(), f)
        })
        .collect();
    let chart: Chart =
        rocking_stones::plot::reliability_diagram("Open scans against the closed stones (simulated truth)", &sets);
    chart.save(&out.path("reliability.png"), (900, 800))?;
    let stones: Vec<&str> = STONES.iter().map(|(f, _)| f.rsplit('/').next().unwrap_or(f)).collect();
    let context = json!({
        "scores": scores, "stones": stones, "members": args.members, "cases": cases.len(),
        "amplitudes": AMPLITUDES, "frequencies": FREQUENCIES, "base": base, "seconds": fixed(seconds, 0),
        "cost": cost, "refused": refused,
    });
    out.write("scores.json", serde_json::to_string_pretty(&context)?)?;
    out.readme(include_str!("readme/open_scan_truth.md"), &context)
}

/// The closed stone `mesh` standing as it stands (+z up, mesh units of `unit` m): its records
/// (one-sine pulses around its tipping threshold, [`AMPLITUDES`] × [`FREQUENCIES`]) and whether
/// each overturns it.
fn truth_of(mesh: &TriMesh, unit: f64, opts: &Options) -> Result<(Vec<bool>, Vec<Record>)> {
    let a = Analysis::of_scan(mesh.clone(), opts)?;
    let s = Stone::new(&a, a.macro_nu(opts).0)?;
    let setup = RockSetup::new(&s, Pose::AsScanned, unit, Surface::RockOnConcrete, 0.0)?;
    let corners: Vec<Point3> = s.body.corners.iter().map(|c| Point3::from(c * s.body.r_max)).collect();
    let tan_alpha = TippingPolar::new(&corners, &Point3::origin(), &-rocking_stones::Vec3::z(), 0.0)?.minimum().0;
    let p = (3.0 * 9.81 / (4.0 * setup.r_max_m)).sqrt();
    let mut records = Vec::new();
    for x in AMPLITUDES {
        for k in FREQUENCIES {
            let tp = std::f64::consts::TAU / (k * p);
            let r = one_sine_pulse(x * tan_alpha, tp, 1e-3)?;
            records.push(Record { name: format!("a{x}_f{k}"), ..r });
        }
    }
    let batch = run_batch(&s, &setup, &records, &[1.0], None, &[], &|_| {})?;
    Ok((batch.runs.iter().map(|r| r.rock.overturned).collect(), records))
}

/// What an open-scan ensemble costs beside a closed one, both timed here: the bundled open scan
/// (`data/open_scan_E34.ply`) with 32 members drawing their bases, and the bundled closed stone
/// standing on the same facet with 16 members on its scanned base, under one 60 s record of
/// filtered noise at 0.3 g (wall-clock seconds on this machine's threads; drawing the members
/// counted in).
fn cost(opts: &Options, spec: &EnsembleSpec) -> Result<serde_json::Value> {
    let record = filtered_noise(&Noise { duration: 60.0, ..Noise::default() }, 0.3, 7)?;
    let time = |mesh: TriMesh, members: u64, drawn: bool| -> Result<(f64, f64)> {
        let t = std::time::Instant::now();
        let a = Analysis::of_scan(mesh, opts)?;
        let s = Stone::new(&a, a.macro_nu(opts).0)?;
        let setup = RockSetup::new(&s, Pose::AsScanned, 1e-3, Surface::RockOnConcrete, 0.0)?;
        let uncertainty = Uncertainty {
            base: drawn.then_some(BaseUncertainty::calibrated()),
            ..Uncertainty::stated(&Uncertainty::default(), Surface::RockOnConcrete, [false; 3])
        };
        let e = EnsembleSpec { uncertainty, seed: spec.seed, members };
        let rocks = field_members(&a, opts, &s, &setup, &e)?;
        let drawn_s = t.elapsed().as_secs_f64();
        let rock = FieldRock { stone: &s, members: &rocks };
        let run = rocking_stones::dynamics::shaking::ensemble::run_ensemble(rock, &setup, &record, 1.0, &e, &|| {})?;
        anyhow::ensure!(run.members.len() == members as usize, "every member ran");
        Ok((t.elapsed().as_secs_f64(), drawn_s))
    };
    // The closed stone standing on the open scan's facet: the open scan cut from it.
    let read = |file: &str| rocking_stones::mesh::io::read(&harness::repo().join(file));
    let standing = {
        let mesh = read("data/default_pebble.ply")?;
        let a = Analysis::of_scan(mesh.clone(), opts)?;
        let s = Stone::new(&a, a.macro_nu(opts).0)?;
        let facet = s.stable()[s.position(10).context("equilibrium 10")?].facet;
        stand_on(&mesh, &s.body.facet_normals[facet as usize])?
    };
    let (closed_s, _) = time(standing, 16, false)?;
    let (open_s, drawing_s) = time(read("data/open_scan_E34.ply")?, 32, true)?;
    Ok(json!({
        "closed_16_s": fixed(closed_s, 2), "open_32_s": fixed(open_s, 2), "drawing_s": fixed(drawing_s, 2),
        "ratio": fixed(open_s / closed_s, 2), "threads": rayon::current_num_threads(),
    }))
}
