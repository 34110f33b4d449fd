//! No silent size: a dynamics command on a mesh whose length unit is neither given nor known
//! says on standard error, before running, what it assumed, and its JSON records it; a size that
//! is not plausible for a stone is warned about; the bundled stone (in millimetres) needs no
//! option.

use std::f64::consts::PI;
use std::path::Path;
use std::process::Command;

/// Run `rocking` with `args`: success, standard output as JSON (null if it is not), standard error.
fn rocking(args: &[&str]) -> (bool, serde_json::Value, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_rocking")).args(args).output().unwrap();
    let json = serde_json::from_slice(&out.stdout).unwrap_or(serde_json::Value::Null);
    (out.status.success(), json, String::from_utf8_lossy(&out.stderr).into_owned())
}

/// A byte-identical copy of the bundled stone named `mystone.ply` in `dir`, and one sine cycle of
/// 0.3 g at 2 Hz (then 0.5 s of rest) as a CSV record.
fn copy_and_record(dir: &Path) -> (String, String) {
    let mesh = dir.join("mystone.ply");
    std::fs::write(&mesh, rocking_stones::bundled::PLY).unwrap();
    let mut csv = String::from("time_s,ax_g\n");
    for k in 0..=200 {
        let t = k as f64 * 0.005;
        csv += &format!("{t},{}\n", if t <= 0.5 { 0.3 * (2.0 * PI * 2.0 * t).sin() } else { 0.0 });
    }
    let rec = dir.join("pulse.csv");
    std::fs::write(&rec, csv).unwrap();
    (mesh.to_str().unwrap().to_string(), rec.to_str().unwrap().to_string())
}

const NOTE: &str = "its length unit is not known; assuming metres (R_max = 178.3 m)";
const HOW: &str = "give --length-unit mm|cm|m|km or --size R_MAX_M.";
const IMPLAUSIBLE: &str = "R_max = 178.3 m is outside the plausible sizes of a stone, a pebble or a field rock \
                           (R_max 2 mm to 20 m)";

#[test]
fn a_copy_of_the_bundled_stone_without_a_unit_is_said_to_be_assumed_in_metres_and_flagged() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, rec) = copy_and_record(dir.path());
    let shake = |extra: &[&str]| {
        let mut args = vec!["shake"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--pose", "facet:3", "--motion", &rec, "--columns", "time_s,ax_g", "--json"]);
        let (ok, j, err) = rocking(&args);
        assert!(ok, "{err}");
        (j, err)
    };
    // The copy, no unit: metres assumed and said, first thing on standard error, with what it
    // implies and how to change it; 178 m is flagged; the JSON records it. The 178 m rock stands.
    let (j, err) = shake(&[&mesh]);
    let first = err.lines().next().unwrap_or("");
    assert!(first.starts_with("note: ") && first.contains(&format!("mystone.ply: {NOTE}")), "{err}");
    assert!(first.contains("rolling resistance") && first.ends_with(HOW), "{err}");
    assert!(err.lines().any(|l| l.starts_with("warning: ") && l.contains(IMPLAUSIBLE)), "{err}");
    assert_eq!(j["size_assumed"], true);
    assert!((j["r_max_m"].as_f64().unwrap() - 178.323).abs() < 1e-3, "{}", j["r_max_m"]);
    assert_eq!(j["overturned"], false);
    // The copy in millimetres: nothing to say, and the very run of the bundled stone, which
    // overturns.
    let (mm, err) = shake(&[&mesh, "--length-unit", "mm"]);
    assert!(!err.contains("note:") && !err.contains("warning:"), "{err}");
    assert_eq!(mm["size_assumed"], false);
    assert!((mm["r_max_m"].as_f64().unwrap() - 0.178323).abs() < 1e-6, "{}", mm["r_max_m"]);
    assert_eq!(mm["overturned"], true);
    // The bundled stone needs no option: its millimetres are known.
    let (bundled, err) = shake(&[]);
    assert!(!err.contains("note:") && !err.contains("warning:"), "{err}");
    assert_eq!(bundled, mm);
    // Given in metres, nothing is assumed but 178 m is still flagged.
    let (m, err) = shake(&[&mesh, "--length-unit", "m"]);
    assert!(!err.contains("note:") && err.contains(IMPLAUSIBLE), "{err}");
    assert_eq!((&m["size_assumed"], &m["overturned"]), (&false.into(), &false.into()));
}

#[test]
fn drop_and_perturb_state_the_size_they_assume() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, _) = copy_and_record(dir.path());
    // drop assumes R_max = 1 cm (the presets' reference size, plausible): said, not flagged.
    let (ok, j, err) = rocking(&["drop", &mesh, "-n", "1", "--json"]);
    assert!(ok, "{err}");
    let first = err.lines().next().unwrap_or("");
    assert!(
        first.starts_with("note: ")
            && first.contains("mystone.ply: its real size is not known; assuming R_max = 10 mm"),
        "{err}"
    );
    assert!(first.ends_with(HOW) && !err.contains("warning:"), "{err}");
    assert_eq!((j["size_assumed"].as_bool(), j["r_max_m"].as_f64()), (Some(true), Some(0.01)));
    // steel-on-wood's rolling-resistance length (0.2 mm) over R_max.
    assert!((j["params"]["rolling_resistance"].as_f64().unwrap() - 0.02).abs() < 1e-12, "{}", j["params"]);
    // The bundled stone is dropped at its known size, silently.
    let (ok, j, err) = rocking(&["drop", "-n", "1", "--json"]);
    assert!(ok && !err.contains("note:") && !err.contains("warning:"), "{err}");
    assert_eq!(j["size_assumed"], false);
    assert!((j["r_max_m"].as_f64().unwrap() - 0.178323).abs() < 1e-6);
    // --size is a given size.
    let (ok, j, err) = rocking(&["drop", &mesh, "-n", "1", "--size", "0.05", "--json"]);
    assert!(ok && !err.contains("note:"), "{err}");
    assert_eq!((j["size_assumed"].as_bool(), j["r_max_m"].as_f64()), (Some(false), Some(0.05)));
    // perturb assumes metres, as shake.
    let args = ["perturb", &mesh, "--equilibrium", "3", "-n", "1", "--eps-steps", "1", "--json"];
    let (ok, j, err) = rocking(&args);
    assert!(ok && err.contains(NOTE) && err.contains(IMPLAUSIBLE), "{err}");
    assert_eq!(j["size_assumed"], true);
    assert!((j["r_max_m"].as_f64().unwrap() - 178.323).abs() < 1e-3);
}

#[test]
fn the_study_says_the_size_its_experimenter_sets_pebbles_down_at() {
    let dir = tempfile::tempdir().unwrap();
    let scans = dir.path().join("scans");
    std::fs::create_dir(&scans).unwrap();
    copy_and_record(&scans);
    std::fs::remove_file(scans.join("pulse.csv")).unwrap();
    let scans = scans.to_str().unwrap();
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let (ok, _, err) = rocking(&["study", scans, "--dynamic", "--trials", "1", "-o", &out("a")]);
    assert!(ok, "{err}");
    assert!(err.contains("the scans' length unit is not known") && err.contains("R_max = 10 mm"), "{err}");
    let (ok, _, err) = rocking(&["study", scans, "--dynamic", "--trials", "1", "--length-unit", "m", "-o", &out("b")]);
    assert!(ok && !err.contains("note:") && err.contains(IMPLAUSIBLE), "{err}");
    let (ok, _, err) = rocking(&["study", scans, "--dynamic", "--trials", "1", "--length-unit", "mm", "-o", &out("c")]);
    assert!(ok && !err.contains("note:") && !err.contains("warning:"), "{err}");
    // The static study needs no size.
    let (ok, _, err) = rocking(&["study", scans, "-o", &out("d")]);
    assert!(ok && !err.contains("note:"), "{err}");
}

#[test]
fn the_help_says_what_the_size_defaults_to_and_where_it_does_not_matter() {
    let help = |cmd: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_rocking")).args([cmd, "--help"]).output().unwrap();
        String::from_utf8_lossy(&out.stdout).split_whitespace().collect::<Vec<_>>().join(" ")
    };
    for cmd in ["shake", "perturb"] {
        let h = help(cmd);
        assert!(h.contains("m is assumed, and the command says so before running"), "{cmd}: {h}");
    }
    assert!(help("drop").contains("R_max = 1 cm (the presets' reference size, a die) is assumed"));
    assert!(help("analyze").contains("no count, ν, flock or basin depends on the real size"));
}
