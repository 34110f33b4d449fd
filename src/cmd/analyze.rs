//! `rocking analyze`: the static analysis of one scan (summary or JSON) or of many (CSV).

use anyhow::{Context, Result};
use rayon::prelude::*;
use rocking_stones::analysis::{check_nu, Analysis, Options, Report};
use rocking_stones::mesh::io;
use rocking_stones::report;
use std::path::{Path, PathBuf};

/// The bundled default pebble (see `data/README.md` for its provenance).
const DEFAULT_PEBBLE: &[u8] = include_bytes!("../../data/default_pebble.ply");
const DEFAULT_NAME: &str = "default_pebble.ply (bundled)";

#[derive(clap::Args)]
pub struct Args {
    /// Mesh files (STL, OBJ, PLY) or folders of them. None: the bundled default pebble.
    pub paths: Vec<PathBuf>,
    /// Print one JSON object (one file) instead of the human summary.
    #[arg(long)]
    pub json: bool,
    /// Fix ν of the macro scale (default: the automatic plateau; the paper's hand experimenter
    /// is 0.0035).
    #[arg(long, value_parser = parse_nu)]
    pub nu: Option<f64>,
    /// Relative coplanarity tolerance of the facet merge (× bounding-box diagonal).
    #[arg(long, default_value_t = rocking_stones::hull::DEFAULT_COPLANAR_TOL)]
    pub coplanar_tol: f64,
    /// Write plots (n(ν), hull picture) and a flock-coloured PLY into this folder.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// CSV file for a batch (several files or a folder); default: standard output.
    #[arg(long)]
    pub csv: Option<PathBuf>,
}

fn parse_nu(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|e| format!("{e}"))?;
    check_nu(v).map_err(|e| e.to_string())
}

pub fn run(args: Args) -> Result<()> {
    let opts = Options { nu: args.nu, coplanar_tol: args.coplanar_tol, ..Options::default() };
    let files = expand(&args.paths)?;
    match files.as_slice() {
        [] => single(None, &args, &opts),
        [one] if !args.paths.iter().any(|p| p.is_dir()) => single(Some(one), &args, &opts),
        many => batch(many, &args, &opts),
    }
}

/// Files named on the command line, with folders expanded to their mesh files (sorted).
fn expand(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(p)
                .with_context(|| format!("{}: cannot list folder", p.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| is_mesh_file(f))
                .collect();
            found.sort();
            if found.is_empty() {
                anyhow::bail!("{}: no .stl, .obj or .ply files in this folder", p.display());
            }
            out.extend(found);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

/// Analyse a mesh file, or the bundled default stone when `path` is None; returns the analysis
/// and the name to report.
pub fn load_analysis(path: Option<&Path>, opts: &Options) -> Result<(Analysis, String)> {
    Ok(match path {
        Some(p) => (Analysis::of_file(p, opts)?, p.display().to_string()),
        None => {
            let mesh = io::read_bytes(DEFAULT_PEBBLE, Path::new(DEFAULT_NAME))?;
            let (mesh, repairs) = mesh.into_solid_boundary().map_err(|e| e.with_path(DEFAULT_NAME))?;
            (Analysis::of_solid(mesh, repairs, opts).map_err(|e| e.with_path(DEFAULT_NAME))?, DEFAULT_NAME.to_string())
        }
    })
}

/// Is this the report name of the bundled default stone?
pub fn is_bundled(name: &str) -> bool {
    name == DEFAULT_NAME
}

fn single(path: Option<&PathBuf>, args: &Args, opts: &Options) -> Result<()> {
    let (analysis, name) = load_analysis(path.map(|p| p.as_path()), opts)?;
    let report = analysis.report(&name, opts);
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report::summary(&report));
    }
    if let Some(dir) = &args.output {
        let written = report::write_outputs(&analysis, &report, dir)?;
        if !args.json {
            for w in written {
                println!("wrote {}", w.display());
            }
        }
    }
    Ok(())
}

fn batch(files: &[PathBuf], args: &Args, opts: &Options) -> Result<()> {
    let bar = indicatif::ProgressBar::new(files.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {elapsed_precise} {msg}")
            .expect("valid template"),
    );
    let results: Vec<(PathBuf, Result<Report, String>)> = files
        .par_iter()
        .map(|f| {
            let r =
                Analysis::of_file(f, opts).map(|a| a.report(&f.display().to_string(), opts)).map_err(|e| e.to_string());
            bar.inc(1);
            (f.clone(), r)
        })
        .collect();
    bar.finish_and_clear();
    let mut failed = 0;
    for (_, r) in &results {
        if let Err(e) = r {
            eprintln!("error: {e}");
            failed += 1;
        }
    }
    let rows = results.iter().map(|(f, r)| (f.as_path(), r.as_ref().map_err(|e| e.as_str())));
    match &args.csv {
        Some(path) => {
            let file = std::fs::File::create(path).with_context(|| format!("{}: cannot create", path.display()))?;
            report::write_batch_csv(file, rows)?;
            eprintln!("wrote {} ({} files, {} failed)", path.display(), results.len(), failed);
        }
        None => report::write_batch_csv(std::io::stdout().lock(), rows)?,
    }
    Ok(())
}

/// Does the file name end in a mesh extension we read?
fn is_mesh_file(p: &Path) -> bool {
    let ext = p.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase());
    matches!(ext.as_deref(), Some("stl" | "obj" | "ply"))
}
