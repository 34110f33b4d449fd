//! Robustness under mutation: 10⁵ seeded mutations of real and synthetic mesh files —
//! half on the bytes of the file (any format), half on the parsed mesh — each read, checked and
//! analysed with panics caught. Every case must end in an answer or a named error; a panic or a
//! failed internal check is a bug and is listed with the case number that reproduces it
//! (`mutation::run_case(&sources, SEED, i, ..)`). Also times the self-intersection check on the
//! largest scan of `data/meshes` and on a synthetic pebble of 10⁶ triangles.
//!
//! Run: `cargo run --release --example fuzz_mutations` → `results/fuzz_mutations/`.

use rayon::prelude::*;
use rocking_stones::analysis::Options;
use rocking_stones::generate;
use rocking_stones::mesh::{intersect, io};
use rocking_stones::mutation;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

const SEED: u64 = 2026;
const CASES: u64 = 100_000;

/// The mutated sources: small scans of `data/meshes` in each stored format, and a small synthetic pebble
/// written as OBJ, binary STL, ascii STL and ascii PLY.
fn sources(meshes: &Path, tmp: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = [
        "stone_quarry_ibois_E34_decimated500_bin.ply",
        "stone_quarry_ibois_A0_decimated500_bin.ply",
        "asteroid_2_pallas_hanus2017_bin.ply",
        "stone_quarry_ibois_stone0_ascii.ply",
        "kbo_486958_arrokoth_stern2019_bin.ply",
    ]
    .iter()
    .map(|n| (n.to_string(), std::fs::read(meshes.join(n)).expect("a mesh of data/meshes")))
    .collect();
    let small = generate::pebble([1.0, 0.7, 0.5], 0.02, 300, 3);
    for name in ["pebble.obj", "pebble.stl"] {
        let p = tmp.join(name);
        io::write(&p, &small).expect("write");
        out.push((name.to_string(), std::fs::read(&p).expect("read back")));
    }
    let p = tmp.join("pebble_ascii.stl");
    io::write_ascii_stl(&p, &small).expect("write");
    out.push(("pebble_ascii.stl".to_string(), std::fs::read(&p).expect("read back")));
    let p = tmp.join("pebble_ascii.ply");
    io::write_ply_ascii(&p, &small).expect("write");
    out.push(("pebble_ascii.ply".to_string(), std::fs::read(&p).expect("read back")));
    out
}

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let meshes = root.join("data/meshes");
    let dir = root.join("results/fuzz_mutations");
    std::fs::create_dir_all(&dir)?;
    let tmp = tempfile::tempdir()?;
    let sources = sources(&meshes, tmp.path());
    let opts = Options::default();

    // `--timing-only`: skip the campaign (for tuning the self-intersection check).
    let n_cases = if std::env::args().any(|a| a == "--timing-only") { 0 } else { CASES };
    // Silence the default panic message: panics are caught and counted.
    std::panic::set_hook(Box::new(|_| {}));
    let t = Instant::now();
    let cases: Vec<(u64, mutation::Case)> =
        (0..n_cases).into_par_iter().map(|i| (i, mutation::run_case(&sources, SEED, i, &opts))).collect();
    let seconds = t.elapsed().as_secs_f64();
    let _ = std::panic::take_hook();

    let mut counts: BTreeMap<(&str, &str, &str), usize> = BTreeMap::new();
    let mut by_outcome: BTreeMap<&str, usize> = BTreeMap::new();
    let mut failures = String::from("case,source,family,mutation,outcome,message\n");
    let mut n_fail = 0;
    for (i, c) in &cases {
        *counts.entry((c.family, c.mutation, c.outcome.label())).or_default() += 1;
        *by_outcome.entry(c.outcome.label()).or_default() += 1;
        if c.outcome.is_failure() {
            n_fail += 1;
            let msg = match &c.outcome {
                mutation::Outcome::Panicked(m) => m.clone(),
                mutation::Outcome::Refused { message, .. } => message.clone(),
                mutation::Outcome::Analysed => String::new(),
            };
            let _ = writeln!(
                failures,
                "{i},{},{},{},{},\"{}\"",
                c.source,
                c.family,
                c.mutation,
                c.outcome.label(),
                msg.replace('"', "'")
            );
        }
    }
    let mut csv = String::from("family,mutation,outcome,cases\n");
    for ((f, m, o), n) in &counts {
        let _ = writeln!(csv, "{f},{m},{o},{n}");
    }
    if n_cases == CASES {
        std::fs::write(dir.join("counts.csv"), csv)?;
        std::fs::write(dir.join("failures.csv"), failures)?;
    }
    let mut outcome_csv = String::from("outcome,cases\n");
    for (o, n) in &by_outcome {
        let _ = writeln!(outcome_csv, "{o},{n}");
    }
    if n_cases == CASES {
        std::fs::write(dir.join("outcomes.csv"), &outcome_csv)?;
    }

    // Self-intersection check timing: the largest scan and a 10⁶-triangle pebble.
    let largest = std::fs::read_dir(&meshes)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("ply" | "obj")))
        .max_by_key(|p| std::fs::metadata(p).map(|m| m.len()).unwrap_or(0))
        .expect("a mesh of data/meshes");
    let mut timing = String::from("mesh,triangles,threads,seconds,crossing_pairs\n");
    let mut rows = Vec::new();
    let (big, _) = io::load_solid(&largest)?;
    let pebble = generate::pebble([1.0, 0.72, 0.48], 0.02, 500_002, 1);
    let (pebble, _) = pebble.into_solid_boundary().map_err(|e| anyhow::anyhow!("{e}"))?;
    for (name, mesh) in
        [(largest.file_name().unwrap().to_string_lossy().into_owned(), &big), ("pebble_1e6".into(), &pebble)]
    {
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
            let best = (0..3)
                .map(|_| {
                    let t = Instant::now();
                    let c = pool.install(|| intersect::find_self_intersection(&mesh.vertices, &mesh.triangles));
                    (t.elapsed().as_secs_f64(), c.map_or(0, |c| c.pairs))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .expect("three runs");
            let _ = writeln!(timing, "{name},{},{threads},{:.4},{}", mesh.triangles.len(), best.0, best.1);
            rows.push((name.clone(), mesh.triangles.len(), threads, best.0, best.1));
        }
    }
    if n_cases == CASES {
        std::fs::write(dir.join("self_intersection_timing.csv"), &timing)?;
    }

    print!("{outcome_csv}");
    print!("{timing}");
    println!("{CASES} cases in {seconds:.1} s, {n_fail} failures (panics or internal checks)");
    if n_cases == CASES {
        write_readme(&dir, &sources, &by_outcome, seconds, n_fail, &rows)?;
    }
    Ok(())
}

fn write_readme(
    dir: &Path,
    sources: &[(String, Vec<u8>)],
    by_outcome: &BTreeMap<&str, usize>,
    seconds: f64,
    n_fail: usize,
    timing: &[(String, usize, usize, f64, usize)],
) -> anyhow::Result<PathBuf> {
    let mut s = String::new();
    let _ = writeln!(s, "# Mutation campaign and self-intersection timing\n");
    let _ = writeln!(
        s,
        "`cargo run --release --example fuzz_mutations`: {CASES} seeded cases (seed {SEED}) over {} source files \
         ({}); even cases mutate the file's bytes, odd ones the parsed mesh (`rocking_stones::mutation`). \
         Each case is read, checked and analysed with panics caught; {seconds:.0} s on this machine (2 threads).\n",
        sources.len(),
        sources.iter().map(|(n, _)| format!("`{n}`")).collect::<Vec<_>>().join(", ")
    );
    let _ = writeln!(s, "| outcome | cases |\n|---|---|");
    for (o, n) in by_outcome {
        let _ = writeln!(s, "| {o} | {n} |");
    }
    let _ = writeln!(
        s,
        "\n**Panics or failed internal checks: {n_fail}** (`failures.csv` lists them with the case number; \
         `mutation::run_case(&sources, {SEED}, i, ..)` replays case i). `counts.csv` splits the outcomes by mutation.\n"
    );
    let _ = writeln!(s, "## Self-intersection check (best of 3)\n\n| mesh | triangles | threads | seconds | crossing pairs |\n|---|---|---|---|---|");
    for (name, nt, th, sec, pairs) in timing {
        let _ = writeln!(s, "| {name} | {nt} | {th} | {sec:.3} | {pairs} |");
    }
    let path = dir.join("README.md");
    std::fs::write(&path, s)?;
    Ok(path)
}
