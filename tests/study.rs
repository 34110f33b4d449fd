//! Field studies, synthetic hand experiments and the fit of ν.

use rocking_stones::analysis::{Analysis, Options, PAPER_NU};
use rocking_stones::generate;
use rocking_stones::hierarchy::Counts;
use rocking_stones::report::study::{DYNAMIC_COLUMNS, HAND_COLUMNS};
use rocking_stones::report::CSV_HEADER;
use rocking_stones::stats::{log_fit, log_grid, sample_sd, GridSize};
use rocking_stones::study::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Small meshes of `data/meshes` (≤ 20 kB each).
const SMALL: [&str; 4] = [
    "stone_quarry_ibois_A0_decimated500_bin.ply",
    "stone_quarry_ibois_E34_decimated500_bin.ply",
    "stone_quarry_ibois_stone0_ascii.ply",
    "asteroid_2_pallas_hanus2017_bin.ply",
];

fn data(rel: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data")).join(rel)
}

fn scans_folder(dir: &Path) -> PathBuf {
    let scans = dir.join("scans");
    std::fs::create_dir_all(&scans).unwrap();
    for f in SMALL {
        std::fs::copy(data(&format!("meshes/{f}")), scans.join(f)).unwrap();
    }
    scans
}

fn rocking(args: &[&str]) -> std::process::Output {
    let out = Command::new(env!("CARGO_BIN_EXE_rocking")).args(args).output().unwrap();
    assert!(
        out.status.success(),
        "rocking {args:?} failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(path).unwrap();
    let header = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r.records().map(|rec| rec.unwrap().iter().map(String::from).collect()).collect();
    (header, rows)
}

fn stem(f: &str) -> String {
    Path::new(f).file_stem().unwrap().to_string_lossy().into_owned()
}

#[test]
fn the_study_reproduces_rocking_analyze_row_for_row_with_either_separator() {
    let dir = tempfile::tempdir().unwrap();
    let scans = scans_folder(dir.path());
    let scans_s = scans.to_str().unwrap();
    let analyze_csv = dir.path().join("analyze.csv");
    rocking(&["analyze", scans_s, "--csv", analyze_csv.to_str().unwrap()]);
    let (a_header, a_rows) = read_csv(&analyze_csv);
    assert_eq!(a_header, CSV_HEADER);
    assert_eq!(a_rows.len(), SMALL.len());
    // Metadata for three of the four scans (the last has none); one id written with its extension.
    for sep in [';', ','] {
        let origin = if sep == ',' { "Lausanne, CH" } else { "Lausanne; CH" };
        let meta = format!(
            "ID{s}sample{s}origin{s}material{s}weight\n{}{s}A{s}\"{origin}\"{s}limestone{s}\"12,5\"\n{}.ply{s}A{s}x{s}limestone{s}3\n{}{s}B{s}y{s}sandstone{s}7\n",
            stem(SMALL[0]),
            stem(SMALL[1]),
            stem(SMALL[2]),
            s = sep
        );
        let meta_path = dir.path().join(format!("meta_{}.csv", if sep == ';' { "semicolon" } else { "comma" }));
        std::fs::write(&meta_path, meta).unwrap();
        let out = dir.path().join(format!("out_{}", sep as u32));
        // The paper's one-ν experimenter (--nu); the default two-tolerance one is in tests/hand.rs.
        rocking(&[
            "study",
            scans_s,
            "--meta",
            meta_path.to_str().unwrap(),
            "--nu",
            "0.0035",
            "-o",
            out.to_str().unwrap(),
        ]);
        let (header, rows) = read_csv(&out.join("pebbles.csv"));
        assert_eq!(&header[..5], ["id", "sample", "origin", "material", "weight"]);
        assert_eq!(&header[5..5 + CSV_HEADER.len()], CSV_HEADER);
        assert_eq!(&header[5 + CSV_HEADER.len()..], HAND_COLUMNS);
        assert_eq!(rows.len(), a_rows.len());
        for (row, a) in rows.iter().zip(&a_rows) {
            // Same numbers, same formatting, same order as `rocking analyze`.
            assert_eq!(&row[5..5 + CSV_HEADER.len()], a.as_slice());
            assert_eq!(row[0], stem(&a[0]));
        }
        let by_id: BTreeMap<&str, &Vec<String>> = rows.iter().map(|r| (r[0].as_str(), r)).collect();
        let first = by_id[stem(SMALL[0]).as_str()];
        assert_eq!(first[1], "A");
        assert_eq!(first[2], origin);
        assert_eq!(first[4], "12,5");
        assert_eq!(by_id[stem(SMALL[1]).as_str()][1], "A");
        assert_eq!(by_id[stem(SMALL[2]).as_str()][3], "sandstone");
        let orphan = by_id[stem(SMALL[3]).as_str()];
        assert!(orphan[1].is_empty() && orphan[2].is_empty(), "a scan without metadata has an empty sample");
        // The fixed-ν columns are G(0.0035) of the same analysis.
        for row in &rows {
            let a = Analysis::of_file(&scans.join(format!("{}.ply", row[0])), &Options::default()).unwrap();
            let c = a.hierarchy.counts_at(PAPER_NU);
            let n = 5 + CSV_HEADER.len();
            assert_eq!(row[n].parse::<f64>().unwrap(), PAPER_NU);
            assert_eq!(row[n + 1..n + 4], [c.stable.to_string(), c.unstable.to_string(), c.saddle.to_string()]);
        }
        let (sh, samples) = read_csv(&out.join("samples.csv"));
        assert_eq!(sh[0], "sample");
        let names: Vec<&str> = samples.iter().map(|r| r[0].as_str()).collect();
        assert_eq!(names, ["", "A", "B"]);
        assert_eq!(samples[1][1], "2");
        assert!(out.join("zingg.png").exists() && out.join("zingg.svg").exists());
    }
}

#[test]
fn metadata_separators_quotes_and_errors() {
    assert_eq!(detect_delimiter("id;sample;origin"), b';');
    assert_eq!(detect_delimiter("id,sample,origin"), b',');
    assert_eq!(detect_delimiter("id;\"a,b,c\""), b';');
    assert_eq!(detect_delimiter("id\tsample"), b'\t');
    assert_eq!(detect_delimiter("id"), b',');
    let p = Path::new("meta.csv");
    let m = Metadata::parse("\u{feff}Id;Sample;weight\np1;A;1,5\n\np2.STL;B;2\n", p).unwrap();
    assert_eq!(m.columns, ["weight"]);
    assert_eq!(m.rows["p1"].values, ["1,5"]);
    assert_eq!(m.rows["p2"].sample, "B");
    let err = |text: &str| Metadata::parse(text, p).unwrap_err().to_string();
    let e = err("id;sample\np1;A\np2;A\np1;B\n");
    assert!(
        e.contains("meta.csv") && e.contains("\"p1\"") && e.contains("twice") && e.contains("lines 2 and 4"),
        "{e}"
    );
    let e = err("name,sample\np1,A\n");
    assert!(e.contains("no `id` column"), "{e}");
    let e = err("id,sample\n,A\n");
    assert!(e.contains("line 2") && e.contains("empty id"), "{e}");
    let e = err("id,sample,weight\np1,A\n");
    assert!(e.contains("line 2") && e.contains("2 fields") && e.contains("3"), "{e}");
    assert!(err("").contains("empty"));
}

#[test]
fn metadata_ids_without_a_scan_and_duplicate_ids_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let scans = dir.path().join("scans");
    std::fs::create_dir_all(&scans).unwrap();
    std::fs::copy(data(&format!("meshes/{}", SMALL[0])), scans.join(SMALL[0])).unwrap();
    let files = mesh_files(&scans).unwrap();
    let meta = Metadata::parse(&format!("id,sample\n{},A\nghost,A\n", stem(SMALL[0])), Path::new("m.csv")).unwrap();
    let e = run_files(&files, Some(&meta), &StudyOptions::default(), &|| {}).unwrap_err().to_string();
    assert!(e.contains("ghost") && e.contains("no scan"), "{e}");
    let opts = StudyOptions { allow_unmatched: true, ..StudyOptions::default() };
    let (study, unmatched) = run_files(&files, Some(&meta), &opts, &|| {}).unwrap();
    assert_eq!(unmatched, ["ghost"]);
    assert_eq!(study.pebbles[0].sample, "A");
    // Two scans with the same id.
    let twin = scans.join(format!("{}.stl", stem(SMALL[0])));
    std::fs::write(&twin, b"solid x\nendsolid x\n").unwrap();
    let files = mesh_files(&scans).unwrap();
    let e = run_files(&files, None, &StudyOptions::default(), &|| {}).unwrap_err().to_string();
    assert!(e.contains("same id"), "{e}");
}

fn analyses() -> Vec<(String, Analysis)> {
    let mut out: Vec<(String, Analysis)> = SMALL
        .iter()
        .map(|f| (f.to_string(), Analysis::of_file(&data(&format!("meshes/{f}")), &Options::default()).unwrap()))
        .collect();
    let (m, r) = generate::pebble([1.0, 0.8, 0.6], 0.05, 1500, 4).into_solid_boundary().unwrap();
    out.push(("synthetic pebble".into(), Analysis::of_solid(m, r, &Options::default()).unwrap()));
    out
}

#[test]
fn at_nu_zero_the_counts_are_the_micro_counts_and_they_fall_monotonically_to_one_one() {
    let mut grid = vec![0.0];
    grid.extend(log_grid(1e-8, 1.0, GridSize::PerDecade(8)));
    for (name, a) in analyses() {
        let curve = CountCurve::of(&a.hierarchy);
        let micro =
            Counts { stable: a.equilibria.stable, unstable: a.equilibria.unstable, saddle: a.equilibria.saddle };
        assert_eq!(curve.at(0.0), micro, "{name}");
        assert_eq!(curve.micro(), micro, "{name}");
        let mut prev = micro;
        for &nu in &grid {
            let c = curve.at(nu);
            assert_eq!(c, a.hierarchy.counts_at(nu), "{name} at ν = {nu}");
            assert!(c.stable <= prev.stable && c.unstable <= prev.unstable && c.saddle <= prev.saddle, "{name} ν {nu}");
            assert_eq!(c.stable as i64 + c.unstable as i64 - c.saddle as i64, 2, "{name} ν {nu}");
            prev = c;
        }
        assert_eq!(curve.at(1.0), Counts { stable: 1, unstable: 1, saddle: 0 }, "{name}");
        // Exactly at a level the cancellations of that level are not yet applied (ν > level).
        for &l in &curve.levels {
            assert_eq!(curve.at(l), a.hierarchy.counts_at(l), "{name} at level {l}");
        }
    }
}

fn small_population(seed: u64) -> PopulationParams {
    PopulationParams { spread: 0.06, roughness: 0.1, points: 900, count: 16, seed, calibrate: true }
}

#[test]
fn flatter_synthetic_samples_have_fewer_equilibria_and_the_log_trend_is_reported() {
    let targets: Vec<SampleTarget> = [(0.45, 0.34), (0.55, 0.41), (0.68, 0.52), (0.8, 0.62)]
        .iter()
        .enumerate()
        .map(|(i, &(cb, ca))| SampleTarget { name: format!("s{i}"), c_over_b: cb, c_over_a: ca })
        .collect();
    let nu = 1e-3;
    let study = synthetic_study(&targets, &small_population(3), nu, None).unwrap();
    let summaries = summarize(&study);
    assert_eq!(summaries.len(), 4);
    for (s, t) in summaries.iter().zip(&targets) {
        assert_eq!(s.pebbles, 16);
        // calibrated: the measured mean ratios are close to the targets
        assert!((s.mean_c_over_b - t.c_over_b).abs() < 0.03, "{} c/b {} vs {}", s.sample, s.mean_c_over_b, t.c_over_b);
        assert!((s.mean_c_over_a - t.c_over_a).abs() < 0.03, "{} c/a {} vs {}", s.sample, s.mean_c_over_a, t.c_over_a);
    }
    let (flat, round) = (&summaries[0].hand, &summaries[3].hand);
    assert!(flat.es < round.es, "E(S): flat {} vs round {}", flat.es, round.es);
    assert!(flat.eu < round.eu, "E(U): flat {} vs round {}", flat.eu, round.eu);
    let pts: Vec<(f64, f64)> = summaries.iter().map(|s| (s.mean_c_over_b, s.hand.es)).collect();
    let fit = log_fit(&pts).unwrap();
    println!("synthetic E(S) against c/b at ν = {nu}: {}", fit.describe());
    assert!(fit.slope > 0.0 && (0.0..=1.0).contains(&fit.r2), "{fit:?}");
}

#[test]
fn log_fit_and_sample_standard_deviation() {
    let pts: Vec<(f64, f64)> = [0.3, 0.5, 0.7, 0.9].iter().map(|&x: &f64| (x, 2.0 + 3.0 * x.ln())).collect();
    let f = log_fit(&pts).unwrap();
    assert!((f.slope - 3.0).abs() < 1e-12 && (f.intercept - 2.0).abs() < 1e-12 && (f.r2 - 1.0).abs() < 1e-12);
    assert!(log_fit(&[(1.0, 2.0)]).is_none());
    // n − 1 divisor: var of 1, 2, 3, 4 is 5/3.
    assert!((sample_sd(&[1.0, 2.0, 3.0, 4.0]) - (5.0f64 / 3.0).sqrt()).abs() < 1e-12);
    assert!(sample_sd(&[1.0]).is_nan());
    let m = Moments::of(&[(2.0, 2.0), (3.0, 4.0)]);
    assert_eq!((m.n, m.es, m.eu), (2, 2.5, 3.0));
}

#[test]
fn table2_is_read_with_its_five_scanned_samples() {
    let t = read_table2(&data("table2_hand_experiments.csv")).unwrap();
    assert_eq!(t.len(), 22);
    assert_eq!(t.iter().filter(|h| h.computer.is_some()).count(), 5);
    let t1 = &t[0];
    assert_eq!((t1.id.as_str(), t1.n, t1.hand), ("T1", 50, [3.36, 4.12, 1.10, 1.08]));
    assert_eq!(t1.computer, Some([3.05, 3.68, 1.00, 1.13]));
    assert!(t.iter().all(|h| h.c_over_a <= h.c_over_b));
    // The table compiled into the library (the default of `rocking study fit-nu`) is this file.
    assert_eq!(bundled_table2().unwrap(), t);
}

#[test]
fn synthetic_populations_and_the_experimenter_are_reproducible_from_the_seed() {
    let t = SampleTarget { name: "X".into(), c_over_b: 0.6, c_over_a: 0.45 };
    let p = PopulationParams { count: 4, points: 500, ..small_population(5) };
    assert_eq!(synthetic_specs(&t, &p).unwrap(), synthetic_specs(&t, &p).unwrap());
    assert_ne!(
        synthetic_specs(&t, &p).unwrap(),
        synthetic_specs(&t, &PopulationParams { seed: 6, ..p.clone() }).unwrap()
    );
    // The CLI: same --seed, same bytes (static and dynamic counts).
    let dir = tempfile::tempdir().unwrap();
    let run = |seed: &str, out: &str| {
        let o = dir.path().join(out);
        rocking(&[
            "study",
            "synthetic",
            "--c-over-b",
            "0.6",
            "--c-over-a",
            "0.45",
            "--count",
            "3",
            "--points",
            "500",
            "--roughness",
            "0.05",
            "--seed",
            seed,
            "--dynamic",
            "--trials",
            "4",
            "-o",
            o.to_str().unwrap(),
        ]);
        std::fs::read_to_string(o.join("pebbles.csv")).unwrap()
    };
    let (a, b, c) = (run("7", "a"), run("7", "b"), run("8", "c"));
    assert_eq!(a, b);
    assert_ne!(a, c);
    let (header, rows) = read_csv(&dir.path().join("a/pebbles.csv"));
    assert_eq!(rows.len(), 3);
    assert_eq!(&header[header.len() - 4..], DYNAMIC_COLUMNS);
    assert!(rows.iter().all(|r| r[header.len() - 4] == "4"));
}

#[test]
fn the_dynamic_experimenter_finds_at_most_the_static_stable_flocks() {
    let (m, r) = generate::pebble([1.0, 0.75, 0.55], 0.1, 800, 2).into_solid_boundary().unwrap();
    let a = Analysis::of_solid(m, r, &Options::default()).unwrap();
    let nu = 1e-3;
    let exp = Experimenter { trials: 12, ..Experimenter::default() };
    let d = hand_experiment(&a, nu, &exp, 42).unwrap();
    assert_eq!(d, hand_experiment(&a, nu, &exp, 42).unwrap(), "same seed, same findings");
    let flocks = a.hierarchy.flocks_at(nu);
    assert!(d.settled <= d.trials && d.settled > 0);
    assert!(d.stable >= 1 && d.stable <= a.hierarchy.counts_at(nu).stable, "{d:?}");
    assert_eq!(d.found.len(), d.stable + d.rocking);
    assert!(d.found.iter().all(|&k| k < flocks.flocks.len()));
}

#[test]
fn the_fit_recovers_the_nu_of_synthetic_hand_data() {
    let targets = [(0.45, 0.34), (0.6, 0.45), (0.72, 0.56), (0.8, 0.62)];
    let truth = 1.2e-3;
    // "Hand" data: one synthetic population counted at the true ν …
    let params = |seed| PopulationParams { count: 30, points: 700, ..small_population(seed) };
    let hand: Vec<HandSample> = targets
        .iter()
        .enumerate()
        .map(|(i, &(cb, ca))| {
            let t = SampleTarget { name: format!("h{i}"), c_over_b: cb, c_over_a: ca };
            let pop = synthetic_sample(&t, &params(11), truth, None).unwrap();
            let counts: Vec<Counts> = pop.iter().map(|p| p.result.as_ref().unwrap().curve.at(truth)).collect();
            let m = Moments::of_counts(&counts);
            HandSample {
                id: t.name.clone(),
                location: String::new(),
                rock_type: String::new(),
                n: m.n,
                hand: m.as_array().map(|x| x.max(0.05)),
                c_over_b: cb,
                c_over_a: ca,
                computer: None,
                n_computer: None,
            }
        })
        .collect();
    // … fitted with an independent population (another seed).
    let opts = FitOptions {
        grid: log_grid(1e-5, 1e-1, GridSize::PerDecade(16)),
        bootstrap: 40,
        seed: 3,
        ..FitOptions::default()
    };
    let (fit, _) = fit_table2(&hand, &params(12), &opts).unwrap();
    println!(
        "true ν {truth:.2e}, fitted {:.2e}, interval {:?}, bootstrap {:?}",
        fit.nu, fit.interval, fit.bootstrap_interval
    );
    assert!(fit.nu > truth / 2.0 && fit.nu < truth * 2.0, "{fit:?}");
    assert!(fit.interval.0 <= fit.nu && fit.nu <= fit.interval.1);
    assert_eq!(fit.bootstrap.len(), 40);
    assert!(!fit.at_edge);
}

#[test]
fn fit_nu_cli_writes_the_loss_the_comparison_and_the_figure_12_plots() {
    let dir = tempfile::tempdir().unwrap();
    let fit = |table: Option<&Path>, out: &Path| {
        let mut args = vec!["study", "fit-nu"];
        if let Some(t) = table {
            args.extend(["--table", t.to_str().unwrap()]);
        }
        args.extend(["--scanned-only", "--count", "6", "--points", "500", "--bootstrap", "5", "--per-decade", "5"]);
        args.extend(["-o", out.to_str().unwrap()]);
        let o = rocking(&args);
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(stdout.contains("fitted ν ="), "{stdout}");
        let (_, rows) = read_csv(&out.join("comparison_paper_nu.csv"));
        rows.iter().map(|r| r[0].clone()).collect::<Vec<String>>()
    };
    // No --table: the bundled Table 2, whose five scanned samples are fitted.
    let out = dir.path().join("fit");
    assert_eq!(fit(None, &out), ["T1", "A1", "K1", "K3", "K4"]);
    for f in ["loss.csv", "fit.json", "loss.png", "comparison_fitted.csv", "comparison_paper_nu.csv"] {
        assert!(out.join(f).exists(), "{f}");
    }
    for f in ["fig12a_S.png", "fig12a_U.svg", "fig12b.png", "hand_vs_computed.png"] {
        assert!(out.join("fitted").join(f).exists(), "{f}");
    }
    // --table reads another file: the bundled table cut to its first three samples.
    let three: Vec<&str> = TABLE2_CSV.lines().take(4).collect();
    let table = dir.path().join("three.csv");
    std::fs::write(&table, three.join("\n") + "\n").unwrap();
    assert_eq!(fit(Some(&table), &dir.path().join("three")), ["T1", "A1", "K1"]);
}

/// A field study's report skips the quasi-static basins (their exact areas were most of a
/// 2000-point pebble's analysis time) and is otherwise the report of `rocking analyze`.
#[test]
fn a_study_report_is_the_analyze_report_without_the_basins() {
    let (mesh, rep) = generate::pebble([1.0, 0.7, 0.5], 0.05, 2000, 4).into_solid_boundary().unwrap();
    let opts = Options::default();
    let a = Analysis::of_solid(mesh, rep, &opts).unwrap();
    let full = a.report("p", &opts);
    let lean = a.report_without_basins("p", &opts);
    assert!(!full.stable_facets.is_empty() && lean.stable_facets.is_empty());
    let mut full = serde_json::to_value(&full).unwrap();
    full["stable_facets"] = serde_json::json!([]);
    assert_eq!(full, serde_json::to_value(&lean).unwrap());
}
