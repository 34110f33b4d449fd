//! One vocabulary on the command line: the old spellings of an option still run and give the
//! same output as the new, a negative number reaches the option's own check (which says the
//! allowed range), the ids the summaries print are the ids the options take, and every option of
//! every command is described.

use std::process::Command;

/// Run `rocking` with `args`: success, standard output, standard error.
fn rocking(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_rocking")).args(args).output().expect("run rocking");
    (out.status.success(), String::from_utf8_lossy(&out.stdout).into(), String::from_utf8_lossy(&out.stderr).into())
}

#[test]
fn the_old_spelling_of_the_length_unit_gives_the_same_summary() {
    let (ok_new, new, err) = rocking(&["analyze", "--length-unit", "cm"]);
    assert!(ok_new, "{err}");
    let (ok_old, old, err) = rocking(&["analyze", "--unit", "cm"]);
    assert!(ok_old, "{err}");
    assert_eq!(new, old);
    assert!(new.contains("cm³"), "{new}");
    // `drop` and `study` take --length-unit too (drop also --size); they are checked where
    // they run (tests/size.rs). Here: the option exists on every command that takes a unit.
    for cmd in [&["analyze"][..], &["drop"], &["perturb"], &["shake"], &["study"]] {
        let (_, help, _) = rocking(&[cmd, &["--help"]].concat());
        assert!(help.contains("--length-unit <UNIT>"), "{cmd:?}: {help}");
    }
}

#[test]
fn a_negative_number_reaches_the_option_s_own_check() {
    for cmd in [
        &["analyze"][..],
        &["drop"],
        &["merge", "missing.jsonl"],
        &["perturb"],
        &["shake"],
        &["study", "."],
        &["study", "synthetic"],
    ] {
        for nu in [&["--nu", "-0.5"][..], &["--nu=-0.5"]] {
            let (ok, _, err) = rocking(&[cmd, nu].concat());
            assert!(!ok, "{cmd:?} {nu:?} ran");
            assert!(err.contains("--nu must be in (0, 1], got -0.5"), "{cmd:?} {nu:?}: {err}");
            assert!(!err.contains("unexpected argument"), "{cmd:?} {nu:?}: {err}");
        }
    }
    // Other numbers, whole numbers and comma-separated values with a minus sign.
    for (args, says) in [
        (&["drop", "--friction", "-0.5"][..], "--friction must be ≥ 0 and finite, got -0.5"),
        (&["drop", "-n", "-3"], "expected a whole number, at least 1, got \"-3\""),
        (&["drop", "--shard", "-1/2"], "--shard must be i/n with 0 ≤ i < n"),
        (&["planar", "regular", "-n", "-3"], "expected a whole number, at least 3, got \"-3\""),
        (&["planar", "ellipse", "--a", "2", "--k", "3", "--degeneracy-tol", "-1"], "--degeneracy-tol must be"),
        (&["perturb", "--epsilon-star", "-0.5"], "--epsilon-star must be a positive energy"),
        (&["perturb", "--max-time", "-2"], "--max-time must be positive and finite, got -2"),
        (&["perturb", "--center-of-mass", "-1e6,0,0"], "is not inside the convex hull"),
        (&["shake", "--pulse", "-0.5,2"], "expected AMP,FREQ,CYCLES"),
        (&["shake", "--equilibrium", "-1"], "expected a whole number, at least 0, got \"-1\""),
        (&["study", "synthetic", "--spread", "-0.5"], "--spread must be a finite number ≥ 0"),
        (&["generate", "cube", "-o", "x.stl", "--seed", "-1"], "expected a whole number, at least 0"),
    ] {
        let (ok, _, err) = rocking(args);
        assert!(!ok && err.contains(says), "{args:?}: {err}");
        assert!(!err.contains("unexpected argument"), "{args:?}: {err}");
    }
}

#[test]
fn the_equilibrium_analyze_prints_is_the_one_shake_takes() {
    let (ok, text, err) = rocking(&["analyze"]);
    assert!(ok, "{err}");
    // "equilibrium     0 (facet    174)  R/R_max = …": the first rocking equilibrium.
    let line = text.lines().find(|l| l.trim_start().starts_with("equilibrium ")).expect(&text);
    let words: Vec<&str> =
        line.split(|c: char| c.is_whitespace() || c == '(' || c == ')').filter(|w| !w.is_empty()).collect();
    assert_eq!((words[0], words[2]), ("equilibrium", "facet"), "{line}");
    let (id, facet): (usize, usize) = (words[1].parse().unwrap(), words[3].parse().unwrap());
    assert_ne!(id, facet, "the bundled stone's ids must differ for this test to tell them apart: {line}");
    let dir = tempfile::tempdir().unwrap();
    let motion = dir.path().join("still.csv");
    let rows: String = (0..=50).map(|i| format!("{:.2},0\n", i as f64 * 0.01)).collect();
    std::fs::write(&motion, format!("time,ax\n{rows}")).unwrap();
    let motion = motion.to_str().unwrap();
    let pose = format!("facet:{id}");
    let (ok, out, err) = rocking(&["shake", "--pose", &pose, "--motion", motion, "--max-time", "0.5"]);
    assert!(ok, "{pose}: {err}");
    assert!(out.contains(&format!("settled onto equilibrium {id} ")), "{out}");
    // The hull facet's number is refused, and the refusal names the equilibrium on it.
    let pose = format!("facet:{facet}");
    let (ok, _, err) = rocking(&["shake", "--pose", &pose, "--motion", motion]);
    assert!(!ok, "{pose} ran");
    assert!(err.contains(&format!("hull facet {facet} holds stable micro-equilibrium {id}")), "{err}");
    let (ok, _, err) = rocking(&["perturb", "--equilibrium", &facet.to_string()]);
    assert!(!ok && err.contains(&format!("hull facet {facet} holds stable micro-equilibrium {id}")), "{err}");
}

/// The options of `rocking ARGS --help` that have no description.
fn undescribed(args: &[&str]) -> (Vec<String>, usize) {
    let (ok, help, err) = rocking(&[args, &["--help"]].concat());
    assert!(ok, "{args:?}: {err}");
    let lines: Vec<&str> = help.lines().collect();
    let indent = |l: &str| l.len() - l.trim_start().len();
    let (mut missing, mut options) = (Vec::new(), 0);
    for (k, line) in lines.iter().enumerate() {
        let t = line.trim_start();
        let is_option = indent(line) == 2 || (indent(line) == 6 && t.starts_with("--"));
        if !(is_option && t.starts_with('-')) {
            continue;
        }
        options += 1;
        // The flag and its value name, then (short layout) the description on the same line.
        let spec_end = t.find("  ").unwrap_or(t.len());
        let same_line = t[spec_end..].trim();
        let next = lines.get(k + 1).copied().unwrap_or("");
        let next_line = indent(next) > indent(line)
            && !next.trim().is_empty()
            && !next.trim_start().starts_with("Possible values")
            && !next.trim_start().starts_with('[');
        if same_line.is_empty() && !next_line {
            missing.push(t[..spec_end].to_string());
        }
    }
    (missing, options)
}

#[test]
fn every_option_of_every_command_is_described() {
    let commands: [&[&str]; 13] = [
        &[],
        &["analyze"],
        &["generate"],
        &["planar"],
        &["planar", "ellipse"],
        &["planar", "regular"],
        &["drop"],
        &["merge"],
        &["perturb"],
        &["shake"],
        &["study"],
        &["study", "synthetic"],
        &["study", "fit-nu"],
    ];
    let mut all = Vec::new();
    let mut counted = 0;
    for cmd in commands {
        let (missing, options) = undescribed(cmd);
        counted += options;
        all.extend(missing.into_iter().map(|m| format!("rocking {}: {m}", cmd.join(" "))));
    }
    assert!(counted > 150, "only {counted} options read: the help layout was not understood");
    assert!(all.is_empty(), "options without a description:\n{}", all.join("\n"));
}

#[test]
fn no_help_speaks_of_the_scaled_body() {
    for cmd in ["drop", "perturb", "shake"] {
        let (_, help, _) = rocking(&[cmd, "--help"]);
        let flat = help.split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(!flat.contains("scaled body") && !flat.contains("scaled 1 m body"), "{cmd}: {flat}");
        assert!(!flat.contains("(s, scaled)") && !flat.contains("Hz, scaled"), "{cmd}: {flat}");
    }
}

#[test]
fn the_drop_summary_gives_the_launch_as_multiples_and_for_the_real_stone() {
    // The throw preset (4 m/s, 25 rad/s rms, dt 1/120 s at R_max = 1 m) on the bundled stone,
    // R_max = 178.3 mm: speeds × √0.1783, spins ÷ √0.1783, times × √0.1783; multiples of
    // √(g R_max), √(g/R_max), √(R_max/g) with g = 9.81 m/s².
    let (ok, out, err) = rocking(&["drop", "-n", "1", "--batch", "1"]);
    assert!(ok, "{err}");
    assert!(
        out.contains(
            "launch: height 2 R_max, horizontal speed 1.28 √(g R_max) = 1.69 m/s, spin 7.98 √(g/R_max) = 59.2 rad/s \
             (rms, Gaussian) for R_max = 178.3 mm"
        ),
        "{out}"
    );
    assert!(out.contains("dt 0.0261 √(R_max/g) = 0.00352 s"), "{out}");
    // No number printed with all its binary digits.
    assert!(out.contains("rolling resistance 0.001122 R_max"), "{out}");
    assert!(!out.split(|c: char| !(c.is_ascii_digit() || c == '.')).any(|w| w.len() > 12), "{out}");
}
