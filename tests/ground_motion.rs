//! Ground-motion records: the CSV and PEER `.AT2` readers agree with each other and with the
//! record they were written from; bad files are refused with the file, the line and the reason.
//! Every record here is written by the test itself (no third-party records are shipped).

use rocking_stones::ground_motion::read::{at2_text, read_at2, read_csv, AccelUnit, Columns};
use rocking_stones::ground_motion::synthetic::{filtered_noise, one_sine_pulse, Noise};
use rocking_stones::ground_motion::Record;
use rocking_stones::GRAVITY as G;
use std::fs;
use std::path::Path;

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    fs::write(&p, text).unwrap();
    p
}

/// The record as CSV with a header: time_s, ax_g, ay_g, az_g, values printed as `.AT2` prints
/// them (9 significant digits), so that both files hold the same numbers.
fn csv_text(r: &Record) -> String {
    let mut s = String::from("# written by the test\ntime_s,ax_g,ay_g,az_g\n");
    for (k, a) in r.accel.iter().enumerate() {
        s += &format!("{},{:.8E},{:.8E},{:.8E}\n", k as f64 * r.dt, a[0] / G, a[1] / G, a[2] / G);
    }
    s
}

#[test]
fn at2_and_csv_give_the_same_record() {
    let dir = tempfile::tempdir().unwrap();
    let noise = Noise { duration: 5.0, components: 3, ..Noise::default() };
    let r = filtered_noise(&noise, 0.25, 4).unwrap();
    let csv = write(dir.path(), "quake.csv", &csv_text(&r));
    let files: Vec<_> = (0..3)
        .map(|c| write(dir.path(), &format!("quake_{c}.AT2"), &at2_text(&r, c, "Test event, 2026, station X")))
        .collect();
    let paths: Vec<&Path> = files.iter().map(|p| p.as_path()).collect();
    let from_at2 = read_at2(&paths).unwrap();
    let from_csv = read_csv(&csv, &"time_s,ax_g,ay_g,az_g".parse().unwrap(), AccelUnit::G).unwrap();
    assert_eq!(from_at2.accel, from_csv.accel, "same numbers, same record");
    assert!((from_at2.dt - r.dt).abs() < 1e-15 && (from_csv.dt - r.dt).abs() < 1e-12);
    // 9 significant digits: the records agree with the original to 10⁻⁸ relative.
    let peak = r.measures().pga_m_s2;
    for (a, b) in from_csv.accel.iter().zip(&r.accel) {
        for c in 0..3 {
            assert!((a[c] - b[c]).abs() < 1e-8 * peak);
        }
    }
    let (m1, m2) = (from_csv.measures(), r.measures());
    assert!((m1.pga_g - m2.pga_g).abs() < 1e-8 && (m1.pgv_m_s - m2.pgv_m_s).abs() < 1e-8);
    assert_eq!(from_at2.name, "quake_0.AT2+quake_1.AT2+quake_2.AT2");
}

#[test]
fn csv_columns_by_name_number_and_unit() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "r.csv", "t;up;east\n0.0;1;0.5\n0.01;2;-0.5\n0.02;3;0.25\n");
    let by_name = read_csv(&p, &"T,East".parse().unwrap(), AccelUnit::G).unwrap();
    assert_eq!(by_name.accel.iter().map(|a| a[0]).collect::<Vec<_>>(), vec![0.5 * G, -0.5 * G, 0.25 * G]);
    let by_number = read_csv(&p, &"1,3,3,2".parse().unwrap(), AccelUnit::MetresPerSecond2).unwrap();
    assert_eq!(by_number.accel[1], [-0.5, -0.5, 2.0]);
    let gal = read_csv(&p, &Columns::default(), AccelUnit::Gal).unwrap();
    assert_eq!(gal.accel[2], [0.03, 0.0, 0.0]);
    assert!((gal.dt - 0.01).abs() < 1e-15);
}

#[test]
fn irregular_times_are_interpolated_onto_a_grid() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "r.csv", "1.0,0\n1.1,1\n1.3,3\n1.4,4\n");
    let r = read_csv(&p, &Columns::default(), AccelUnit::MetresPerSecond2).unwrap();
    assert!((r.dt - 0.1).abs() < 1e-12);
    let xs: Vec<f64> = r.accel.iter().map(|a| a[0]).collect();
    assert_eq!(xs.len(), 5);
    for (k, x) in xs.iter().enumerate() {
        assert!((x - k as f64).abs() < 1e-9, "{xs:?}");
    }
}

#[test]
fn at2_older_header_and_different_intervals() {
    let dir = tempfile::tempdir().unwrap();
    let pulse = one_sine_pulse(0.5, 0.4, 0.005).unwrap();
    let fine = at2_text(&pulse, 0, "event");
    let old = fine.replacen(
        &format!("NPTS= {:7}, DT= {:.6} SEC", pulse.accel.len(), pulse.dt),
        &format!("  {}   {:.4}   NPTS, DT", pulse.accel.len(), pulse.dt),
        1,
    );
    assert_ne!(old, fine);
    let a = write(dir.path(), "new.AT2", &fine);
    let b = write(dir.path(), "old.AT2", &old);
    assert_eq!(read_at2(&[&a]).unwrap().accel, read_at2(&[&b]).unwrap().accel);
    // A second component at twice the interval is brought to the first one's.
    let coarse = pulse.resampled(0.01).unwrap();
    let c = write(dir.path(), "coarse.AT2", &at2_text(&coarse, 0, "event"));
    let both = read_at2(&[&a, &c]).unwrap();
    assert!((both.dt - 0.005).abs() < 1e-12);
    assert_eq!(both.accel.len(), pulse.accel.len());
    let m = both.measures();
    // x and y in phase: the resultant peaks near √2 · 0.5 g (the low-pass ringing adds < 0.1 %).
    assert!((m.pga_g / (0.5 * 2f64.sqrt()) - 1.0).abs() < 1e-3, "{m:?}");
}

#[test]
fn bad_records_name_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let msg = |p: &Path| read_csv(p, &Columns::default(), AccelUnit::G).unwrap_err().to_string();
    let e = msg(&write(dir.path(), "back.csv", "0,0\n0.01,1\n0.005,2\n"));
    assert!(e.contains("back.csv") && e.contains("line 3") && e.contains("does not increase"), "{e}");
    let e = msg(&write(dir.path(), "text.csv", "time,a\n0,0\n0.01,x\n"));
    assert!(e.contains("text.csv") && e.contains("line 3"), "{e}");
    let e = msg(&write(dir.path(), "one.csv", "0,1\n"));
    assert!(e.contains("at least two"), "{e}");
    let e = read_csv(&write(dir.path(), "h.csv", "time,a\n0,0\n1,1\n"), &"time,az".parse().unwrap(), AccelUnit::G)
        .unwrap_err()
        .to_string();
    assert!(e.contains("no column \"az\"") && e.contains("time, a"), "{e}");
    let e = msg(&dir.path().join("missing.csv"));
    assert!(e.contains("missing.csv"), "{e}");
    assert!("time".parse::<Columns>().is_err() && "0,1".parse::<Columns>().is_err());
    assert!("furlongs".parse::<AccelUnit>().is_err());

    let pulse = one_sine_pulse(0.5, 0.4, 0.01).unwrap();
    let good = at2_text(&pulse, 0, "event");
    let short = good.rsplit_once('\n').unwrap().0.rsplit_once('\n').unwrap().0.to_string();
    let e = read_at2(&[&write(dir.path(), "short.AT2", &short)]).unwrap_err().to_string();
    assert!(e.contains("short.AT2") && e.contains("NPTS"), "{e}");
    let vel = good.replace("ACCELERATION TIME SERIES IN UNITS OF G", "VELOCITY TIME SERIES IN UNITS OF CM/S");
    let e = read_at2(&[&write(dir.path(), "v.VT2", &vel)]).unwrap_err().to_string();
    assert!(e.contains("v.VT2") && e.contains("line 3"), "{e}");
    let mut lines: Vec<String> = good.lines().map(String::from).collect();
    lines[5] = lines[5].replacen('E', "X", 1);
    let e = read_at2(&[&write(dir.path(), "nan.AT2", &lines.join("\n"))]).unwrap_err().to_string();
    assert!(e.contains("nan.AT2") && e.contains("not a number"), "{e}");
}

#[test]
fn a_table_of_known_pgvs_names_records_by_file_name() {
    use rocking_stones::ground_motion::read::{read_known_pgv, with_known_pgvs};
    use rocking_stones::ground_motion::PgvSource;
    let dir = tempfile::tempdir().unwrap();
    let p =
        write(dir.path(), "pgv.csv", "# measured\nmotion, note ,PGV_m_s\nmotions/a.csv,first,0.3\n\nb.csv,\"x\",0.2\n");
    let table = read_known_pgv(&p).unwrap();
    assert_eq!(table, vec![("a.csv".to_string(), 0.3), ("b.csv".to_string(), 0.2)]);
    let pulse = one_sine_pulse(0.2, 0.5, 0.005).unwrap();
    let named = |n: &str| Record { name: n.into(), known_pgv_m_s: None, ..pulse.clone() };
    let (records, n) = with_known_pgvs(vec![named("a.csv"), named("c.csv")], &table, "pgv.csv").unwrap();
    assert_eq!(n, 1);
    let (a, c) = (records[0].measures(), records[1].measures());
    assert_eq!((a.pgv_m_s, a.pgv_source), (0.3, PgvSource::Given));
    assert_eq!(c.pgv_source, PgvSource::Processed);
    // A table of other records is refused, naming itself.
    let e = with_known_pgvs(vec![named("c.csv")], &table, "pgv.csv").unwrap_err().to_string();
    assert!(e.contains("pgv.csv") && e.contains("a.csv"), "{e}");
    // Bad tables name the file, the line and what is wrong.
    let msg = |name: &str, text: &str| read_known_pgv(&write(dir.path(), name, text)).unwrap_err().to_string();
    let e = msg("cols.csv", "record,pga_g\na.csv,0.3\n");
    assert!(e.contains("cols.csv") && e.contains("pgv_m_s") && e.contains("record, pga_g"), "{e}");
    let e = msg("neg.csv", "record,pgv_m_s\na.csv,0.3\nb.csv,-0.1\n");
    assert!(e.contains("neg.csv") && e.contains("line 3") && e.contains("-0.1"), "{e}");
    let e = msg("twice.csv", "file,pgv_m_s\nx/a.csv,0.3\ny/a.csv,0.2\n");
    assert!(e.contains("line 3") && e.contains("twice"), "{e}");
    let e = msg("short.csv", "record,pgv_m_s\na.csv\n");
    assert!(e.contains("line 2") && e.contains("missing"), "{e}");
    assert!(msg("empty.csv", "# nothing\n").contains("empty"));
    assert!(msg("header.csv", "record,pgv_m_s\n").contains("no rows"));
}

/// `rocking shake` on the bundled stone (standing on its rocking pose) under one second of a
/// 2 Hz sine of 0.25 g: the PGV printed is the processed one — the closed form 2 a_p/ω_p less
/// the high-pass's T f_c (π/10)/sin(π/10) (`ground_motion::processing`) — unless `--pgv` gives
/// it; a folder of records takes known PGVs from `--pgv-table`.
#[test]
fn the_shake_command_says_which_pgv_it_used() {
    use std::f64::consts::PI;
    use std::process::Command;
    let dir = tempfile::tempdir().unwrap();
    let mut csv = String::from("time_s,ax_g\n");
    for k in 0..2000 {
        let t = k as f64 / 200.0;
        csv += &format!("{t:.3},{:.6}\n", if t < 1.0 { 0.25 * (2.0 * PI * 2.0 * t).sin() } else { 0.0 });
    }
    let recs = dir.path().join("records");
    fs::create_dir(&recs).unwrap();
    let rec = write(&recs, "pulse.csv", &csv);
    write(&recs, "other.csv", &csv);
    let run = |extra: &[&str]| {
        let base = ["shake", "--pose", "equilibrium:3", "--columns", "time_s,ax_g", "--json"];
        Command::new(env!("CARGO_BIN_EXE_rocking")).args(base).args(extra).output().unwrap()
    };
    let json = |out: std::process::Output| -> serde_json::Value {
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let rec_s = rec.to_str().unwrap();
    let closed = 2.0 * 0.25 * G / (2.0 * PI * 2.0);
    let j = json(run(&["--motion", rec_s]));
    let processed = closed * (1.0 - 1.0 * 0.08 * (PI / 10.0) / (PI / 10.0).sin());
    assert!((j["pgv_m_s"].as_f64().unwrap() / processed - 1.0).abs() < 0.01, "{} vs {processed}", j["pgv_m_s"]);
    assert_eq!(j["pgv_source"], "processed");
    let j = json(run(&["--motion", rec_s, "--pgv", "0.39"]));
    assert_eq!((j["pgv_m_s"].as_f64(), &j["pgv_source"]), (Some(0.39), &serde_json::json!("given")));
    assert!((j["pgv_over_pga_s"].as_f64().unwrap() - 0.39 / (0.25 * G)).abs() < 1e-3, "{j}");
    let out = run(&["--motion", rec_s, "--pgv", "-1"]);
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("--pgv"));
    // A folder: the table names one record of two.
    let table = write(dir.path(), "pgv.csv", "record,pgv_m_s\npulse.csv,0.5\nelsewhere.csv,0.1\n");
    let j = json(run(&["--records", recs.to_str().unwrap(), "--pgv-table", table.to_str().unwrap()]));
    let runs = j["runs"].as_array().unwrap();
    let of = |name: &str| runs.iter().find(|r| r["record"] == name).unwrap().clone();
    assert_eq!((of("pulse.csv")["pgv_m_s"].as_f64(), &of("pulse.csv")["pgv_source"]), (Some(0.5), &"given".into()));
    assert_eq!(of("other.csv")["pgv_source"], "processed");
    assert!((of("other.csv")["pgv_m_s"].as_f64().unwrap() / processed - 1.0).abs() < 0.01);
}
