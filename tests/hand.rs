//! The two-tolerance hand experimenter: its fit recovers known tolerances, `rocking study`
//! writes its most likely pairs and distributions, and (slow, ignored) its calibration on
//! Table 2 is the one the library ships.

use rocking_stones::analysis::{Analysis, Options, PAPER_NU};
use rocking_stones::report::hand::PAIR_COLUMNS;
use rocking_stones::report::CSV_HEADER;
use rocking_stones::study::*;
use std::path::{Path, PathBuf};
use std::process::Command;

fn data(rel: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data")).join(rel)
}

fn rocking(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_rocking")).args(args).output().unwrap();
    assert!(out.status.success(), "rocking {args:?} failed:\n{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(path).unwrap();
    let header = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r.records().map(|rec| rec.unwrap().iter().map(String::from).collect()).collect();
    (header, rows)
}

fn sample(id: &str, m: Moments, cb: f64, ca: f64) -> HandSample {
    HandSample {
        id: id.into(),
        location: String::new(),
        rock_type: String::new(),
        n: m.n,
        hand: m.as_array(),
        c_over_b: cb,
        c_over_a: ca,
        computer: None,
        n_computer: None,
    }
}

#[test]
fn the_fit_recovers_the_tolerances_that_made_the_hand_columns() {
    // Four small synthetic samples; their "hand" columns are the moments a known experimenter
    // gives them, so the fit on the same pebbles must find it again (χ² = 0 there).
    let truth = HandExperimenter {
        stable: Tolerance { median: 2e-3, sd_log10: 0.35 },
        unstable: Tolerance { median: 8e-3, sd_log10: 0.25 },
    };
    let params = PopulationParams { spread: 0.06, roughness: 0.2, points: 600, count: 14, seed: 5, calibrate: false };
    let targets = [(0.45, 0.34), (0.6, 0.45), (0.72, 0.56), (0.8, 0.62)];
    let mut hand = Vec::new();
    let mut pops = Vec::new();
    for (i, &(cb, ca)) in targets.iter().enumerate() {
        let t = SampleTarget { name: format!("h{i}"), c_over_b: cb, c_over_a: ca };
        let curves: Vec<CountCurve> = synthetic_sample(&t, &params, PAPER_NU, None)
            .unwrap()
            .into_iter()
            .map(|p| p.result.unwrap().curve)
            .collect();
        hand.push(sample(&t.name, population_moments(&curves, &truth), cb, ca));
        pops.push(curves);
    }
    let fit = fit_hand(&hand, &pops).unwrap();
    let e = fit.experimenter;
    println!("truth {truth:?}\nfitted {e:?}, χ² = {}", fit.chi2);
    assert!(fit.chi2 < 1e-3, "{}", fit.chi2);
    for (f, t) in [(e.stable, truth.stable), (e.unstable, truth.unstable)] {
        assert!((f.median / t.median).log10().abs() < 0.05, "{f:?} vs {t:?}");
        assert!((f.sd_log10 - t.sd_log10).abs() < 0.05, "{f:?} vs {t:?}");
    }
    assert_eq!((fit.terms, fit.dof, fit.samples.len()), (16, 12, 4));
    // Each sample's z-scores are ≈ 0; a sample whose E(S) is moved by 3 standard errors gets z ≈ 3.
    let mut off = hand[1].clone();
    off.hand[0] += 3.0 * off.standard_errors()[0];
    let z = SampleFit::of(&off, fit.samples[1].model).z[0];
    assert!(z < -2.0 && z > -3.0, "{z}"); // the model's own error widens the denominator
}

#[test]
fn the_study_writes_the_most_likely_pair_its_probability_and_the_distribution() {
    let dir = tempfile::tempdir().unwrap();
    let scans = dir.path().join("scans");
    std::fs::create_dir_all(&scans).unwrap();
    let names = ["stone_quarry_ibois_E34_decimated500_bin.ply", "stone_quarry_ibois_stone0_ascii.ply"];
    for f in names {
        std::fs::copy(data(&format!("meshes/{f}")), scans.join(f)).unwrap();
    }
    let meta = dir.path().join("meta.csv");
    // Named as Table 2 samples so that --table compares them (one pebble each: an illustration).
    std::fs::write(
        &meta,
        "id,sample\nstone_quarry_ibois_E34_decimated500_bin,T1\nstone_quarry_ibois_stone0_ascii,A1\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let table = data("table2_hand_experiments.csv");
    let args = ["study", scans.to_str().unwrap(), "--meta", meta.to_str().unwrap(), "--table"];
    let stdout = rocking(&[&args[..], &[table.to_str().unwrap(), "-o", out.to_str().unwrap()]].concat());
    assert!(stdout.contains("two-tolerance experimenter") && stdout.contains("real scans' frame"), "{stdout}");
    let (header, rows) = read_csv(&out.join("pebbles.csv"));
    let n = 2 + CSV_HEADER.len();
    assert_eq!(&header[n..], PAIR_COLUMNS);
    let hand: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("hand.json")).unwrap()).unwrap();
    for (row, f) in rows.iter().zip(names) {
        let a = Analysis::of_file(&scans.join(f), &Options::default()).unwrap();
        // Real scans: the calibration in the scans' frame.
        let d = TABLE2_EXPERIMENTER_ON_SCANS.counts(&CountCurve::of(&a.hierarchy));
        let best = d.most_likely();
        let cells = [best.stable.to_string(), best.unstable.to_string(), best.saddle.to_string()];
        assert_eq!(row[n..n + 3], cells, "{f}");
        assert_eq!(row[n + 3], format!("{:.4}", best.p));
        let total: f64 = d.pairs().iter().map(|p| p.p).sum();
        assert!((total - 1.0).abs() < 1e-9 && best.p > 0.0 && best.p <= 1.0);
        let j = hand["pebbles"].as_array().unwrap().iter().find(|p| p["id"] == row[0]).unwrap();
        assert_eq!(j["most_likely"]["stable"], best.stable);
    }
    let (h, fits) = read_csv(&out.join("hand_vs_table2.csv"));
    assert_eq!(h[0], "sample");
    assert_eq!(fits.iter().map(|r| r[0].as_str()).collect::<Vec<_>>(), ["T1", "A1"]);
    assert!(out.join("hand_vs_table2.png").exists());
}

#[test]
fn fit_hand_writes_the_fit_the_model_against_the_table_and_the_left_out_predictions() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fit");
    let args = ["study", "fit-hand", "--count", "4", "--points", "300", "--roughness", "0.2,0.3", "--loso", "-o"];
    let stdout = rocking(&[&args[..], &[out.to_str().unwrap()]].concat());
    assert!(stdout.contains("χ² (hand) =") && stdout.contains("leave one sample out"), "{stdout}");
    let (header, rows) = read_csv(&out.join("samples.csv"));
    assert_eq!((header[0].as_str(), rows.len()), ("sample", 22));
    let fit: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("fit.json")).unwrap()).unwrap();
    assert_eq!(fit["fit"]["profile"].as_array().unwrap().len(), 2);
    assert_eq!(fit["loso"].as_array().unwrap().len(), 22);
    assert!(out.join("hand_vs_table2.png").exists());
}

/// On real scans a person counts near the paper's ν: on the five samples Table 2 reports both
/// ways (the person's counts and the real scans' at ν = 0.0035), the differences of the means,
/// pooled, are within two standard errors of zero for S and U. That is a route to the scans'
/// frame without synthetic pebbles, and [`TABLE2_EXPERIMENTER_ON_SCANS`] (the fit moved by the
/// synthetic pebbles' shift) must agree with it; the fit as made on synthetic pebbles does not
/// (its ν_U would count too few unstable equilibria on a scan), so the frame matters.
#[test]
fn on_real_scans_a_person_counts_near_the_papers_nu() {
    let hand = bundled_table2().unwrap();
    assert_eq!(hand.iter().filter(|h| h.computer.is_some()).count(), 5);
    for (name, (diff, se)) in ["E(S)", "E(U)"].iter().zip(hand_minus_scans(&hand).unwrap()) {
        println!("{name}: hand − scans = {diff:.3} ± {se:.3} (z = {:.2})", diff / se);
        assert!((diff / se).abs() < 2.0, "{name}: z = {}", diff / se);
    }
    let decades = |nu: f64| (nu / PAPER_NU).log10().abs();
    let e = TABLE2_EXPERIMENTER_ON_SCANS;
    assert!(decades(e.stable.median) < 0.1 && decades(e.unstable.median) < 0.1, "{e:?}");
    assert!(e.stable.median < e.unstable.median, "stable positions found at the finer tolerance");
    assert!(decades(TABLE2_EXPERIMENTER.unstable.median) > 0.5);
}

/// The calibration the library ships ([`TABLE2_EXPERIMENTER`], [`TABLE2_ROUGHNESS`], and
/// [`TABLE2_EXPERIMENTER_ON_SCANS`] moved into the scans' frame) is what the fit on Table 2 gives (minutes: run by `cargo experiment hand_table2`, or
/// `cargo test --release --test hand -- --ignored`).
#[test]
#[ignore]
fn the_shipped_calibration_is_the_fit_on_table_2() {
    let hand = bundled_table2().unwrap();
    let grid = [TABLE2_ROUGHNESS - 0.1, TABLE2_ROUGHNESS, TABLE2_ROUGHNESS + 0.1];
    let pops = table2_populations(&hand, &PopulationParams::default(), &grid).unwrap();
    let fit = fit_hand_table2(&hand, &pops).unwrap();
    let e = fit.chosen().fit.experimenter;
    println!("{e:?} at roughness {}", fit.chosen().roughness);
    assert_eq!(fit.chosen().roughness, TABLE2_ROUGHNESS);
    let scans = fit.in_scan_frame();
    for (f, t) in [
        (e.stable, TABLE2_EXPERIMENTER.stable),
        (e.unstable, TABLE2_EXPERIMENTER.unstable),
        (scans.stable, TABLE2_EXPERIMENTER_ON_SCANS.stable),
        (scans.unstable, TABLE2_EXPERIMENTER_ON_SCANS.unstable),
    ] {
        assert!((f.median / t.median).log10().abs() < 0.02, "{f:?} vs {t:?}");
        assert!((f.sd_log10 - t.sd_log10).abs() < 0.01, "{f:?} vs {t:?}");
    }
}
