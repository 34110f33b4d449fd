//! Robustness under mutation: 10⁵ seeded mutations of real and synthetic mesh files, each read,
//! checked and analysed with panics caught; and the time of the self-intersection check on the
//! largest scan of `data/meshes` and on a synthetic pebble of 10⁶ triangles.
//!
//! Run: `cargo experiment fuzz_mutations [-- --timing-only]` →
//! `results/fuzz_mutations/`; the README's prose is `experiments/readme/fuzz_mutations.md`.

use rayon::prelude::*;
use rocking_stones::mesh::{intersect, io, TriMesh};
use rocking_stones::mutation::{self, Outcome};
use rocking_stones::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use experiments::harness;
use harness::{fixed, Common, Context, Parser, Result, Results};

const CASES: u64 = 100_000;

/// The mutation campaign and the self-intersection timing.
#[derive(Parser)]
struct Args {
    /// Skip the campaign and write nothing: only time the self-intersection check (for tuning it)
    #[arg(long)]
    timing_only: bool,
    #[command(flatten)]
    common: Common,
}

/// The mutated sources: small scans of `data/meshes` in each stored format, and a small synthetic
/// pebble written as OBJ, binary STL, ascii STL and ascii PLY.
fn sources(meshes: &Path, tmp: &Path) -> Result<Vec<(String, Vec<u8>)>> {
    let mut out = Vec::new();
    for name in [
        "stone_quarry_ibois_E34_decimated500_bin.ply",
        "stone_quarry_ibois_A0_decimated500_bin.ply",
        "asteroid_2_pallas_hanus2017_bin.ply",
        "stone_quarry_ibois_stone0_ascii.ply",
        "kbo_486958_arrokoth_stern2019_bin.ply",
    ] {
        out.push((name.to_string(), std::fs::read(meshes.join(name)).with_context(|| format!("reading {name}"))?));
    }
    let small = generate::pebble([1.0, 0.7, 0.5], 0.02, 300, 3);
    type Writer = fn(&Path, &TriMesh) -> rocking_stones::Result<()>;
    let writers: [(&str, Writer); 4] = [
        ("pebble.obj", io::write),
        ("pebble.stl", io::write),
        ("pebble_ascii.stl", io::write_ascii_stl),
        ("pebble_ascii.ply", io::write_ply_ascii),
    ];
    for (name, write) in writers {
        write(&tmp.join(name), &small)?;
        out.push((name.to_string(), std::fs::read(tmp.join(name))?));
    }
    Ok(out)
}

fn main() -> Result<()> {
    let args = Args::parse();
    let seed = args.common.seed_or(2026);
    let out = Results::open("fuzz_mutations", &args.common)?;
    let meshes = harness::repo().join("data/meshes");
    let tmp = tempfile::tempdir()?;
    let sources = sources(&meshes, tmp.path())?;
    let opts = Options::default();
    let n_cases = if args.timing_only { 0 } else { CASES };
    // Silence the default panic message: panics are caught and counted.
    std::panic::set_hook(Box::new(|_| {}));
    let t = Instant::now();
    let cases: Vec<_> =
        (0..n_cases).into_par_iter().map(|i| (i, mutation::run_case(&sources, seed, i, &opts))).collect();
    let seconds = t.elapsed().as_secs_f64();
    let _ = std::panic::take_hook();

    let mut counts: BTreeMap<(&str, &str, &str), usize> = BTreeMap::new();
    let mut by_outcome: BTreeMap<&str, usize> = BTreeMap::new();
    let (mut failures, mut n_fail) = (String::from("case,source,family,mutation,outcome,message\n"), 0);
    for (i, c) in &cases {
        *counts.entry((c.family, c.mutation, c.outcome.label())).or_default() += 1;
        *by_outcome.entry(c.outcome.label()).or_default() += 1;
        if c.outcome.is_failure() {
            n_fail += 1;
            let msg = match &c.outcome {
                Outcome::Panicked(m) | Outcome::Refused { message: m, .. } => m.replace('"', "'"),
                Outcome::Analysed => String::new(),
            };
            let (source, family, mutation, label) = (&c.source, c.family, c.mutation, c.outcome.label());
            failures += &format!("{i},{source},{family},{mutation},{label},\"{msg}\"\n");
        }
    }

    // Self-intersection check timing: the largest scan and a 10⁶-triangle pebble.
    let largest = std::fs::read_dir(&meshes)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("ply" | "obj")))
        .max_by_key(|p| std::fs::metadata(p).map(|m| m.len()).unwrap_or(0))
        .context("no mesh in data/meshes")?;
    let (big, _) = io::load_solid(&largest)?;
    let (pebble, _) = generate::pebble([1.0, 0.72, 0.48], 0.02, 500_002, 1).into_solid_boundary()?;
    let big_name = largest.file_name().context("a file name")?.to_string_lossy().into_owned();
    let (mut timing, mut rows) = (String::from("mesh,triangles,threads,seconds,crossing_pairs\n"), Vec::new());
    for (name, mesh) in [(big_name, &big), ("pebble_1e6".into(), &pebble)] {
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
            let best = (0..3)
                .map(|_| {
                    let t = Instant::now();
                    let c = pool.install(|| intersect::find_self_intersection(&mesh.vertices, &mesh.triangles));
                    (t.elapsed().as_secs_f64(), c.map_or(0, |c| c.pairs))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .context("three runs")?;
            let triangles = mesh.triangles.len();
            timing += &format!("{name},{triangles},{threads},{:.4},{}\n", best.0, best.1);
            rows.push(serde_json::json!({
                "name": name, "triangles": triangles, "threads": threads, "seconds": fixed(best.0, 3), "pairs": best.1,
            }));
        }
    }
    print!("{timing}");
    println!("{n_cases} cases in {seconds:.1} s, {n_fail} failures (panics or internal checks)");
    if args.timing_only {
        return Ok(());
    }
    let counts = counts.iter().map(|((f, m, o), n)| [f.to_string(), m.to_string(), o.to_string(), n.to_string()]);
    out.csv("counts.csv", &["family", "mutation", "outcome", "cases"], counts)?;
    out.write("failures.csv", failures)?;
    out.csv("outcomes.csv", &["outcome", "cases"], by_outcome.iter().map(|(o, n)| [o.to_string(), n.to_string()]))?;
    out.write("self_intersection_timing.csv", timing)?;
    out.readme(include_str!("readme/fuzz_mutations.md"),
        serde_json::json!({
            "cases": CASES, "seed": seed, "seconds": fixed(seconds, 0), "n_fail": n_fail, "timing": rows,
            "sources": sources.iter().map(|(n, _)| n).collect::<Vec<_>>(), "outcomes": by_outcome.iter().collect::<Vec<_>>(),
        }),
    )
}
