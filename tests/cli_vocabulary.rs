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
        assert!(help.contains("Also spelled --unit"), "{cmd:?}: {help}");
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
    // equilibrium:ID takes the equilibrium's index, facet:F the hull facet's number: the same
    // stone standing the same way, to the byte.
    let shake = |pose: &str| rocking(&["shake", "--pose", pose, "--motion", motion, "--max-time", "0.5"]);
    let (ok, by_id, err) = shake(&format!("equilibrium:{id}"));
    assert!(ok, "{err}");
    assert!(by_id.contains(&format!("settled onto equilibrium {id} ")), "{by_id}");
    let (ok, by_facet, err) = shake(&format!("facet:{facet}"));
    assert!(ok, "{err}");
    assert_eq!(by_id, by_facet);
    // facet:ID named an equilibrium before: not read that way silently. Hull facet `id` holds
    // no stable equilibrium here, so the refusal says so and points to equilibrium:ID.
    let (ok, _, err) = shake(&format!("facet:{id}"));
    assert!(!ok, "facet:{id} ran");
    assert!(err.contains(&format!("hull facet {id} holds no stable micro-equilibrium")), "{err}");
    assert!(err.contains(&format!("write equilibrium:{id} for it (it rests on hull facet {facet})")), "{err}");
    // --equilibrium takes the equilibrium's index; a facet's number is refused, naming the
    // equilibrium on that facet.
    let (ok, _, err) = rocking(&["perturb", "--equilibrium", &facet.to_string()]);
    assert!(!ok && err.contains(&format!("hull facet {facet} holds stable micro-equilibrium {id}")), "{err}");
}

/// Every `--option` a command's help names (in its descriptions) is an option of that command:
/// no help promises what its command refuses.
#[test]
fn no_help_names_an_option_its_command_does_not_take() {
    let mut wrong = Vec::new();
    for cmd in COMMANDS {
        let (ok, help, err) = rocking(&[cmd, &["--help"]].concat());
        assert!(ok, "{cmd:?}: {err}");
        // The options it takes: the flags that start an option line (and their aliases, which
        // clap does not list: none is named in a description).
        let taken: Vec<String> = help
            .lines()
            .filter_map(|l| {
                let t = l.trim_start();
                let t = t.strip_prefix("-").filter(|_| t.len() > 2 && t.as_bytes()[1] != b'-').map_or(t, |_| &t[4..]);
                t.strip_prefix("--").map(|f| f.split([' ', '<', '=', ',', '[']).next().unwrap_or("").to_string())
            })
            .collect();
        // Another command's options, in its own words (`rocking drop --shard …`), and the other
        // spellings of an option ("also spelled --unit") are not this command's promises.
        let own: String = help
            .split('`')
            .enumerate()
            .filter(|(k, part)| k % 2 == 0 || !(part.starts_with("rocking ") || part.contains("--pose")))
            .map(|(_, part)| part)
            .collect::<Vec<_>>()
            .join(" ");
        let own = own.split_whitespace().collect::<Vec<_>>().join(" ").replace("spelled --", "spelled ");
        for word in own.split(|c: char| !(c.is_ascii_alphanumeric() || c == '-')) {
            if let Some(name) = word.strip_prefix("--").filter(|n| !n.is_empty()) {
                if !taken.iter().any(|t| t == name) {
                    wrong.push(format!("rocking {}: --{name}", cmd.join(" ")));
                }
            }
        }
    }
    wrong.dedup();
    assert!(wrong.is_empty(), "options named in a help that the command does not take:\n{}", wrong.join("\n"));
}

/// The commands and subcommands whose help is read.
const COMMANDS: [&[&str]; 13] = [
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

/// The file names `-o` promises in a help text (`x.png/.svg` is x.png and x.svg), in `part` of it.
fn promised(part: &str) -> std::collections::BTreeSet<String> {
    let mut out = std::collections::BTreeSet::new();
    for word in part.split(|c: char| c.is_whitespace() || c == ',' || c == ';' || c == '(' || c == ')' || c == ':') {
        let word = word.trim_end_matches('.');
        let Some((stem, exts)) = word.split_once('.') else { continue };
        if stem.is_empty() || !stem.chars().all(|c| c.is_ascii_lowercase() || c == '_') {
            continue;
        }
        for ext in exts.split("/.") {
            if ["json", "jsonl", "csv", "png", "svg", "ply", "html"].contains(&ext) {
                out.insert(format!("{stem}.{ext}"));
            }
        }
    }
    out
}

/// The help text of `-o` of `rocking ARGS`, on one line: its option line and the description
/// lines under it, up to the next option.
fn output_help(args: &[&str]) -> String {
    let (_, help, _) = rocking(&[args, &["--help"]].concat());
    let lines: Vec<&str> = help.lines().collect();
    let start = lines.iter().position(|l| l.trim_start().starts_with("-o, --output")).expect("an -o option");
    let is_option = |l: &str| l.starts_with("  -") && !l.starts_with("   ");
    let end = lines[start + 1..].iter().position(|l| is_option(l)).map_or(lines.len(), |k| start + 1 + k);
    lines[start..end].join(" ").split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The files a run wrote into `dir`.
fn written(dir: &std::path::Path) -> std::collections::BTreeSet<String> {
    std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect()
}

#[test]
fn every_output_folder_holds_the_files_its_help_lists() {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let run = |args: &[&str]| {
        let (ok, _, err) = rocking(args);
        assert!(ok, "{args:?}: {err}");
    };
    run(&["analyze", "-o", &out("analyze")]);
    assert_eq!(written(dir.path().join("analyze").as_path()), promised(&output_help(&["analyze"])));
    run(&["drop", "-n", "4", "-o", &out("drop")]);
    assert_eq!(written(dir.path().join("drop").as_path()), promised(&output_help(&["drop"])));
    let part = out("part.jsonl");
    run(&["drop", "-n", "4", "--checkpoint", &part]);
    run(&["merge", &part, "-o", &out("merge")]);
    assert_eq!(written(dir.path().join("merge").as_path()), promised(&output_help(&["merge"])));
    run(&["perturb", "--equilibrium", "0", "-n", "1", "--eps-steps", "1", "-o", &out("perturb")]);
    assert_eq!(written(dir.path().join("perturb").as_path()), promised(&output_help(&["perturb"])));
    // shake: one sentence of its -o help per kind of run.
    let help = output_help(&["shake"]);
    let sentence = |start: &str| {
        let from = help.find(start).unwrap_or_else(|| panic!("{start:?} in {help}"));
        let rest = &help[from..];
        rest[..rest.find(". ").map_or(rest.len(), |k| k + 1)].to_string()
    };
    let records = dir.path().join("records");
    std::fs::create_dir(&records).unwrap();
    let rows: String =
        (0..=100).map(|i| format!("{:.2},{:.4}\n", i as f64 * 0.01, 0.05 * (i as f64 * 0.3).sin())).collect();
    std::fs::write(records.join("a.csv"), format!("time,ax\n{rows}")).unwrap();
    let motion = records.join("a.csv");
    let motion = motion.to_str().unwrap();
    let records = records.to_str().unwrap();
    run(&["shake", "-n", "1", "--pga-steps", "1", "-o", &out("sweep")]);
    assert_eq!(written(dir.path().join("sweep").as_path()), promised(&sentence("A sweep")));
    run(&["shake", "--pose", "equilibrium:10", "--motion", motion, "-o", &out("one")]);
    assert_eq!(written(dir.path().join("one").as_path()), promised(&sentence("One record")));
    run(&["shake", "--pose", "equilibrium:10", "--motion", motion, "--ensemble", "2", "-o", &out("ensemble")]);
    assert_eq!(written(dir.path().join("ensemble").as_path()), promised(&sentence("An ensemble")));
    run(&["shake", "--pose", "equilibrium:10", "--records", records, "--scales", "0.5,1", "-o", &out("batch")]);
    let batch = sentence("A batch");
    let with_ensemble = promised(&batch[batch.find("with --ensemble").unwrap()..]);
    let plain: std::collections::BTreeSet<String> = promised(&batch).difference(&with_ensemble).cloned().collect();
    assert_eq!(written(dir.path().join("batch").as_path()), plain);
    let args = ["shake", "--pose", "equilibrium:10", "--records", records, "--scales", "0.5,1", "--ensemble", "2"];
    run(&[&args[..], &["-o", &out("batch_ensemble")]].concat());
    assert_eq!(written(dir.path().join("batch_ensemble").as_path()), promised(&batch));
}

/// The same unit-less mesh is refused by every command that simulates, with the same sentence,
/// and runs as the bundled stone once its unit is given — by any of the unit's spellings.
#[test]
fn one_size_rule_for_every_command() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("mystone.ply");
    std::fs::write(&mesh, rocking_stones::bundled::PLY).unwrap();
    let mesh = mesh.to_str().unwrap();
    let scans = dir.path().join("scans");
    std::fs::create_dir(&scans).unwrap();
    std::fs::write(scans.join("mystone.ply"), rocking_stones::bundled::PLY).unwrap();
    let scans = scans.to_str().unwrap();
    let motion = dir.path().join("still.csv");
    std::fs::write(&motion, "time,ax\n0,0\n0.01,0\n0.02,0\n").unwrap();
    let motion = motion.to_str().unwrap();
    let study_out = dir.path().join("study").to_str().unwrap().to_string();
    const SAYS: &str = "its length unit is not known, and the result depends on the stone's real size";
    const HOW: &str = "give --length-unit (mm, cm, m, km, in or metres per mesh unit)";
    const OR_SIZE: &str = " or --size (R_max in metres)";
    for args in [
        &["drop", mesh, "-n", "1"][..],
        &["perturb", mesh, "--equilibrium", "10", "-n", "1", "--eps-steps", "1"],
        &["shake", mesh, "-n", "1", "--pga-steps", "1"],
        &["shake", mesh, "--pose", "equilibrium:10", "--motion", motion],
        &["study", scans, "--dynamic", "--trials", "1", "-o", &study_out],
    ] {
        let (ok, _, err) = rocking(args);
        assert!(!ok, "{args:?} ran");
        assert!(err.contains(SAYS) && err.contains(HOW), "{args:?}: {err}");
        // One stone may be sized by its R_max; a folder of scans of many sizes only by their
        // unit, and `study` has no --size: the message names only what the command takes.
        assert_eq!(err.contains(OR_SIZE), args[0] != "study", "{args:?}: {err}");
    }
    // Given in millimetres (or --unit mm, or as R_max), the copy is the bundled stone.
    let bundled = rocking(&["drop", "-n", "3", "--json"]).1;
    for unit in [&["--length-unit", "mm"][..], &["--unit", "mm"], &["--length-unit", "0.001"]] {
        let (ok, copy, err) = rocking(&[&["drop", mesh, "-n", "3", "--json"][..], unit].concat());
        assert!(ok, "{unit:?}: {err}");
        let strip = |t: &str| t.replace(mesh, "MESH").replace(rocking_stones::bundled::NAME, "MESH");
        assert_eq!(strip(&copy), strip(&bundled), "{unit:?}");
    }
    // One set of unit names: a name outside it is refused by every command alike.
    for cmd in [&["analyze", mesh][..], &["drop", mesh], &["perturb", mesh], &["shake", mesh]] {
        let (ok, _, err) = rocking(&[cmd, &["--length-unit", "meters"]].concat());
        assert!(!ok && err.contains("--length-unit must be mm, cm, m, km, in or a positive number"), "{cmd:?}: {err}");
    }
}

/// Options in real units: the summary prints the default in both forms, and giving back the
/// printed SI value runs with the default (to rounding).
#[test]
fn options_take_the_stone_s_real_units() {
    let params = |args: &[&str]| {
        let (ok, out, err) = rocking(&[args, &["--json"]].concat());
        assert!(ok, "{args:?}: {err}");
        serde_json::from_str::<serde_json::Value>(&out).unwrap()["params"].clone()
    };
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-3 * b.abs();
    let default = params(&["perturb", "--equilibrium", "10", "-n", "1", "--eps-steps", "1"]);
    // 1/240 s of the scaled body is 1.7595 ms for R_max = 178.323 mm; 120 Hz is 284.17 Hz.
    let perturb = ["perturb", "--equilibrium", "10", "-n", "1", "--eps-steps", "1"];
    let options = ["--dt", "0.0017595", "--contact-frequency", "284.17", "--rolling-resistance-mm", "0.1"];
    let given = params(&[&perturb[..], &options].concat());
    assert!(close(given["contact_frequency"].as_f64().unwrap(), default["contact_frequency"].as_f64().unwrap()));
    for key in ["dt", "rolling_resistance", "max_time", "friction"] {
        let (g, d) = (given["sim"][key].as_f64().unwrap(), default["sim"][key].as_f64().unwrap());
        assert!(close(g, d), "{key}: {given} vs {default}");
    }
    let drop = params(&["drop", "-n", "1", "--spin", "59.2", "--horizontal-speed", "1.69", "--max-time", "25.34"]);
    let default = params(&["drop", "-n", "1"]);
    for key in ["spin", "horizontal_speed", "max_time"] {
        assert!(close(drop[key].as_f64().unwrap(), default[key].as_f64().unwrap()), "{key}: {drop} vs {default}");
    }
    // A value out of range is told back in the unit it was given in.
    let (ok, _, err) = rocking(&["perturb", "--max-time", "-2"]);
    assert!(!ok && err.contains("--max-time must be positive and finite, got -2 s"), "{err}");
    // The former spellings whose unit changed say what replaced them.
    let dir = tempfile::tempdir().unwrap();
    let motion = dir.path().join("still.csv");
    std::fs::write(&motion, "time,ax\n0,0\n0.01,0\n0.02,0\n").unwrap();
    let motion = motion.to_str().unwrap();
    for (args, says) in [
        (&["drop", "--rolling-resistance", "0.02"][..], "--rolling-resistance-mm"),
        (&["drop", "--torsional-friction", "0.02"], "--torsional-friction-mm"),
        (
            &["shake", "--pose", "equilibrium:10", "--motion", motion, "--ensemble", "2", "--contact-tolerance", "2"],
            "--contact-tolerance-mm",
        ),
    ] {
        let (ok, _, err) = rocking(args);
        assert!(!ok && err.contains(says), "{args:?}: {err}");
    }
}

/// `--certificate` takes none, facet or flock on drop and perturb alike.
#[test]
fn the_certificate_takes_the_same_values_everywhere() {
    for cmd in [&["drop", "-n", "2"][..], &["perturb", "--equilibrium", "10", "-n", "1", "--eps-steps", "1"]] {
        for mode in ["none", "facet", "flock"] {
            let (ok, _, err) = rocking(&[cmd, &["--certificate", mode]].concat());
            assert!(ok, "{cmd:?} {mode}: {err}");
        }
        let (ok, _, err) = rocking(&[cmd, &["--certificate", "always"]].concat());
        assert!(!ok && err.contains("expected one of none, facet, flock"), "{cmd:?}: {err}");
    }
}

/// A merged run prints what the run it merges prints, SI values included.
#[test]
fn merge_prints_what_drop_prints() {
    let dir = tempfile::tempdir().unwrap();
    let part = |i: usize| dir.path().join(format!("part{i}.jsonl")).to_str().unwrap().to_string();
    for i in 0..2 {
        let shard = format!("{i}/2");
        let (ok, _, err) = rocking(&["drop", "-n", "6", "--shard", &shard, "--checkpoint", &part(i)]);
        assert!(ok, "{err}");
    }
    let (ok, merged, err) = rocking(&["merge", &part(0), &part(1)]);
    assert!(ok, "{err}");
    let (ok, whole, err) = rocking(&["drop", "-n", "6"]);
    assert!(ok, "{err}");
    assert_eq!(merged, whole);
    assert!(merged.contains(" = 1.69 m/s") && merged.contains("for R_max = 178.3 mm"), "{merged}");
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
    let commands = COMMANDS;
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

/// A reader that stops early (`rocking analyze | head -1`) ends the program quietly, without a
/// panic.
#[test]
fn a_closed_pipe_ends_the_program_quietly() {
    use std::io::Read;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_rocking"))
        .args(["analyze", "--json"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 16];
    child.stdout.take().unwrap().read_exact(&mut first).unwrap();
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked") && !err.contains("Broken pipe"), "{err}");
}
