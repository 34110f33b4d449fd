//! The shape of the code, checked on the source itself: no source file over 600 lines, the
//! library names no command-line flag, and the product names nothing outside itself. How the
//! modules import each other is `tests/layers.rs`.

use std::path::{Path, PathBuf};

mod common;
use common::rust_files;

#[test]
fn no_source_file_is_over_600_lines() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["src", "python/src"] {
        rust_files(&root.join(dir), &mut files);
    }
    assert!(files.len() > 40, "only {} files found", files.len());
    let long: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let n = std::fs::read_to_string(f).unwrap().lines().count();
            (n > 600).then(|| format!("{} ({n} lines)", f.strip_prefix(root).unwrap().display()))
        })
        .collect();
    assert!(long.is_empty(), "files over 600 lines: {long:?}");
}

/// The experiments are short programs on one harness: none over 400 lines, each on
/// `experiments/shared/harness.rs` (the `experiments` package's library), none drawing with plotters itself (they draw through the
/// library's `plot::Chart`), each README's prose in a template of `experiments/readme/`.
#[test]
fn experiments_are_short_programs_on_the_harness() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    let mut found = Vec::new();
    let mut count = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_none_or(|x| x != "rs") {
            continue;
        }
        count += 1;
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        let text = std::fs::read_to_string(&p).unwrap();
        let lines = text.lines().count();
        if lines > 400 {
            found.push(format!("{name}: {lines} lines"));
        }
        if !text.contains("use experiments::") || !text.contains("harness") {
            found.push(format!("{name}: not on the harness"));
        }
        for drawn in ["plotters::", "ChartBuilder", "draw_png", "draw_svg"] {
            if text.contains(drawn) {
                found.push(format!("{name}: draws with {drawn}"));
            }
        }
        if text.contains("writeln!(md") || text.contains("writeln!(readme") {
            found.push(format!("{name}: writes README prose in Rust"));
        }
    }
    // What the experiments share: one concept a file, held to the library's 600 lines; and the
    // whole room may only shrink (11 811 lines of Rust before the harness, 5 948 after it; 127
    // more for shake_table_pgv, 467 for the two studies of the hidden base, shake_table_sp1 and
    // open_scan_truth, 12 for shake_table_sp1's spread over the draw of the bases).
    let mut total = 0;
    for e in std::fs::read_dir(&dir).unwrap().chain(std::fs::read_dir(dir.join("shared")).unwrap()) {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "rs") {
            let lines = std::fs::read_to_string(&p).unwrap().lines().count();
            total += lines;
            if p.parent().is_some_and(|d| d.ends_with("shared")) && lines > 600 {
                found.push(format!("shared/{}: {lines} lines", p.file_name().unwrap().to_string_lossy()));
            }
        }
    }
    assert!(count >= 30, "only {count} experiments found");
    assert!(found.is_empty(), "experiments off the harness:\n{}", found.join("\n"));
    assert!(total <= 6_554, "experiments/ has grown to {total} lines of Rust (at most 6 554)");
}

/// The library speaks in its own words: no string in it names a command-line flag
/// (`--dt`); parameter errors name the parameter as the library does ([`Error::Parameter`]) and the
/// CLI and Python spell it. `cmd/` and `main.rs` are the command line; `report/` writes its
/// summaries.
#[test]
fn the_library_names_no_command_line_flag() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    let mut found = Vec::new();
    for f in &files {
        let rel = f.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/");
        if rel.starts_with("src/cmd/") || rel == "src/main.rs" || rel.starts_with("src/report/") {
            continue;
        }
        // String literals may run over several lines (`\` continuations): the quote state is
        // carried from line to line, and each line is checked for the part of it inside a string.
        let mut in_string = false;
        for (k, line) in std::fs::read_to_string(f).unwrap().lines().enumerate() {
            let code = line.trim_start();
            if !in_string && (code.starts_with("//") || code.starts_with("#[")) {
                continue;
            }
            let (mut inside, mut escaped) = (String::new(), false);
            for c in line.chars() {
                match c {
                    '\\' if in_string && !escaped => escaped = true,
                    '"' if !escaped => in_string = !in_string,
                    _ => {
                        if in_string {
                            inside.push(c);
                        }
                        escaped = false;
                    }
                }
                if c == '"' {
                    inside.push(' ');
                    escaped = false;
                }
            }
            let named =
                inside.match_indices("--").any(|(i, _)| inside[i + 2..].starts_with(|c: char| c.is_ascii_lowercase()));
            if named {
                found.push(format!("{rel}:{}: {}", k + 1, code));
            }
        }
    }
    assert!(files.len() > 40);
    assert!(found.is_empty(), "flag names in library strings:\n{}", found.join("\n"));
}

/// Where `text` names something outside the product: an internal ticket ("issue 25", "issues 2
/// and 3", "Issue #16"), the design document that is not in the repository ("SPEC", as a word),
/// a folder outside the repository the meshes once came from, or a path of the machine it was
/// written on.
fn outside_references(text: &str) -> Vec<String> {
    let word = |c: char| c.is_alphanumeric() || c == '_';
    let mut found = Vec::new();
    let lower = text.to_lowercase();
    for (i, _) in lower.match_indices("issue") {
        if lower[..i].chars().next_back().is_some_and(word) {
            continue;
        }
        let after = &lower[i + "issue".len()..];
        let rest = after.strip_prefix('s').unwrap_or(after);
        if rest.trim_start_matches([' ', '#']).starts_with(|c: char| c.is_ascii_digit()) {
            found.push(lower[i..].chars().take(12).collect());
        }
    }
    for (i, m) in text.match_indices("SPEC") {
        if !text[..i].chars().next_back().is_some_and(word) && !text[i + m.len()..].starts_with(word) {
            found.push(text[i..].chars().take(10).collect());
        }
    }
    for bad in ["../shared", "shared folder", "shared mesh", "/work/"] {
        if lower.contains(bad) {
            found.push(bad.to_string());
        }
    }
    found
}

/// Every text file under `dir` (build outputs, caches and fuzzing corpora left out).
fn text_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if p.is_dir() {
            let skip = ["target", "__pycache__", ".venv", "corpus", "artifacts", "coverage", ".pytest_cache"];
            if !skip.contains(&name.as_str()) {
                text_files(&p, out);
            }
        } else {
            out.push(p);
        }
    }
}

/// The product speaks of itself alone: no line of its code, help texts, tests, experiments or
/// results names an internal ticket, the design document that is not in the repository, a
/// folder outside the repository or a path of the machine it was written on (the README and
/// `docs/` are not scanned here). This file is left out: it has to spell what it looks for.
#[test]
fn the_product_names_no_issue_number_or_outside_document() {
    // The detector itself: it finds what it must and nothing else.
    for bad in
        ["(issue 16)", "Issues 2 and 3", "issue #13's", "SPEC §6", "(SPEC)", "../shared/x.ply", "the shared meshes"]
    {
        assert!(!outside_references(bad).is_empty(), "{bad:?} not found");
    }
    for good in
        ["ASPECTS", "SPECTRA", "the issue's protocol", "tissue 3", "issues of size", "shared/benchmark_bodies.rs"]
    {
        assert!(outside_references(good).is_empty(), "{good:?} found: {:?}", outside_references(good));
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![root.join("CHANGELOG.md")];
    for dir in ["src", "python", "experiments", "tests", "results", ".ci", "fuzz", "examples"] {
        text_files(&root.join(dir), &mut files);
    }
    let me = root.join(file!());
    let mut read = 0;
    let mut found = Vec::new();
    for f in files.iter().filter(|f| **f != me) {
        let Ok(text) = std::fs::read_to_string(f) else { continue };
        read += 1;
        let rel = f.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/");
        for (k, line) in text.lines().enumerate() {
            for hit in outside_references(line) {
                found.push(format!("{rel}:{}: {hit}", k + 1));
            }
        }
    }
    assert!(read > 300, "only {read} text files read");
    assert!(found.is_empty(), "{} outside references:\n{}", found.len(), found.join("\n"));
}
