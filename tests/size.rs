//! No guessed size: a dynamics command runs a mesh at the size it is given (a length unit or
//! R_max) or knows (the bundled stone, in millimetres), and refuses a mesh without one; a size
//! that is not plausible for a stone is warned about; the JSON records the real R_max.

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

const IMPLAUSIBLE: &str = "R_max = 178.3 m is outside the plausible sizes of a stone, a pebble or a field rock \
                           (R_max 2 mm to 20 m)";

#[test]
fn a_field_rock_runs_at_the_size_it_is_given_and_an_implausible_one_is_flagged() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, rec) = copy_and_record(dir.path());
    let shake = |extra: &[&str]| {
        let mut args = vec!["shake"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--pose", "equilibrium:3", "--motion", &rec, "--columns", "time_s,ax_g", "--json"]);
        rocking(&args)
    };
    // The copy without a unit is refused before anything runs.
    let (ok, j, err) = shake(&[&mesh]);
    assert!(!ok && j.is_null(), "{err}");
    assert!(err.contains("mystone.ply: its length unit is not known"), "{err}");
    // The copy in millimetres: nothing to say, and the very run of the bundled stone, which
    // overturns.
    let (ok, mm, err) = shake(&[&mesh, "--length-unit", "mm"]);
    assert!(ok && !err.contains("warning:"), "{err}");
    assert_eq!(mm["size_assumed"], false);
    assert!((mm["r_max_m"].as_f64().unwrap() - 0.178323).abs() < 1e-6, "{}", mm["r_max_m"]);
    assert_eq!(mm["overturned"], true);
    // The bundled stone needs no option: its millimetres are known.
    let (ok, bundled, err) = shake(&[]);
    assert!(ok && !err.contains("warning:"), "{err}");
    assert_eq!(bundled, mm);
    // Given in metres, the copy is a 178 m rock: flagged, and it stands (the same motion is
    // slow for it).
    let (ok, m, err) = shake(&[&mesh, "--length-unit", "m"]);
    assert!(ok && err.contains(IMPLAUSIBLE), "{err}");
    assert_eq!((&m["size_assumed"], &m["overturned"]), (&false.into(), &false.into()));
    assert!((m["r_max_m"].as_f64().unwrap() - 178.323).abs() < 1e-3);
}

#[test]
fn drop_and_perturb_run_at_the_given_size() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, _) = copy_and_record(dir.path());
    // --size is R_max in metres: steel-on-wood's rolling-resistance length (0.2 mm) over it.
    let (ok, j, err) = rocking(&["drop", &mesh, "-n", "1", "--size", "0.01", "--json"]);
    assert!(ok && !err.contains("warning:"), "{err}");
    assert_eq!((j["size_assumed"].as_bool(), j["r_max_m"].as_f64()), (Some(false), Some(0.01)));
    assert!((j["params"]["rolling_resistance"].as_f64().unwrap() - 0.02).abs() < 1e-12, "{}", j["params"]);
    // The bundled stone is dropped at its known size, silently.
    let (ok, j, err) = rocking(&["drop", "-n", "1", "--json"]);
    assert!(ok && !err.contains("warning:"), "{err}");
    assert!((j["r_max_m"].as_f64().unwrap() - 0.178323).abs() < 1e-6);
    // perturb in metres: flagged as shake is.
    let args = ["perturb", &mesh, "--length-unit", "m", "--equilibrium", "3", "-n", "1", "--eps-steps", "1", "--json"];
    let (ok, j, err) = rocking(&args);
    assert!(ok && err.contains(IMPLAUSIBLE), "{err}");
    assert!((j["r_max_m"].as_f64().unwrap() - 178.323).abs() < 1e-3);
}

#[test]
fn the_study_needs_the_scans_unit_only_for_its_simulated_experimenter() {
    let dir = tempfile::tempdir().unwrap();
    let scans = dir.path().join("scans");
    std::fs::create_dir(&scans).unwrap();
    copy_and_record(&scans);
    std::fs::remove_file(scans.join("pulse.csv")).unwrap();
    let scans = scans.to_str().unwrap();
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let (ok, _, err) = rocking(&["study", scans, "--dynamic", "--trials", "1", "-o", &out("a")]);
    assert!(!ok && err.contains("(the scans): its length unit is not known"), "{err}");
    let (ok, _, err) = rocking(&["study", scans, "--dynamic", "--trials", "1", "--length-unit", "m", "-o", &out("b")]);
    assert!(ok && err.contains(IMPLAUSIBLE), "{err}");
    let (ok, _, err) = rocking(&["study", scans, "--dynamic", "--trials", "1", "--length-unit", "mm", "-o", &out("c")]);
    assert!(ok && !err.contains("warning:"), "{err}");
    // The static study needs no size.
    let (ok, _, err) = rocking(&["study", scans, "-o", &out("d")]);
    assert!(ok, "{err}");
}

#[test]
fn the_help_says_the_size_is_needed_and_where_it_does_not_matter() {
    let help = |cmd: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_rocking")).args([cmd, "--help"]).output().unwrap();
        String::from_utf8_lossy(&out.stdout).split_whitespace().collect::<Vec<_>>().join(" ")
    };
    for cmd in ["drop", "shake", "perturb"] {
        let h = help(cmd);
        assert!(h.contains("Needed for every mesh but the bundled stone (millimetres)"), "{cmd}: {h}");
    }
    assert!(help("analyze").contains("no count, ν, flock or basin depends on the real size"));
}
