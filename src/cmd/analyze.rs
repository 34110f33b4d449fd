//! `rocking analyze`: the static analysis of one scan (summary or JSON) or of many (CSV).

use anyhow::{Context, Result};
use rayon::prelude::*;
use rocking_stones::analysis::{Analysis, Options, Report};
use rocking_stones::bundled;
use rocking_stones::mesh::RimChoice;
use rocking_stones::report;
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// Mesh files (STL, OBJ, PLY) or folders of them. None: the bundled default pebble.
    pub paths: Vec<PathBuf>,
    /// Print one JSON object (one file) instead of the human summary; with several files, JSON
    /// lines: one compact object per file, in order (`{"file", "error", "kind"}` for a failure).
    #[arg(long)]
    pub json: bool,
    /// Fix ν of the macro scale (default: the automatic plateau; the paper's hand experimenter
    /// is 0.0035).
    #[arg(long, value_parser = super::parse_nu)]
    pub nu: Option<f64>,
    /// A known centre of mass x,y,z (mesh units) instead of the homogeneous solid's G: a
    /// weighted die, a hollow print, a scan of only the hull (inertia taken about it).
    #[arg(long, value_parser = super::parse_point, allow_hyphen_values = true)]
    pub center_of_mass: Option<rocking_stones::Point3>,
    /// Relative coplanarity tolerance of the facet merge (× bounding-box diagonal), in (0, 1e-3].
    #[arg(long, default_value_t = rocking_stones::hull::DEFAULT_COPLANAR_TOL, value_parser = super::parse_coplanar_tol)]
    pub coplanar_tol: f64,
    /// Write into this folder: report.json, n_nu.png/.svg (n(ν)), hull.png/.svg (the hull by
    /// flock), hull_flocks.ply (flock-coloured, for MeshLab or ParaView) and report.html (the
    /// summary, the plots and an interactive 3D view of the hull).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Length unit of the mesh coordinates (mm, cm, m, km, in or a number of metres per unit):
    /// labels volume (unit³), area (unit²), G, axes and R in the summary and report.html.
    /// Default: "mesh units" ("mm" for the bundled stone). A label only: no count, ν, flock or
    /// basin depends on the real size (the dynamics commands do, and need it). Also spelled
    /// --unit.
    #[arg(long = "length-unit", alias = "unit", value_name = "UNIT", value_parser = super::parse_length_unit)]
    pub length_unit: Option<rocking_stones::mesh::unit::LengthUnit>,
    /// CSV file for a batch (several files or a folder); default: standard output.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// An open scan (a field scan, +z up, open where the rock meets its pedestal): the rim of
    /// its hidden base is the opening passing nearest this point x,y,z (mesh units) instead of
    /// the one opening at the bottom of the scan.
    #[arg(long, value_parser = super::parse_point, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub rim_near: Option<rocking_stones::Point3>,
}

pub fn run_analyze(args: Args) -> Result<()> {
    let opts = Options {
        nu: args.nu,
        coplanar_tol: args.coplanar_tol,
        center_of_mass: args.center_of_mass,
        rim: args.rim_near.map_or(RimChoice::Lowest, RimChoice::Near),
        ..Options::default()
    };
    opts.check()?;
    let files = expand(&args.paths)?;
    let is_batch = args.paths.iter().any(|p| p.is_dir()) || files.len() > 1 || args.csv.is_some();
    if is_batch && args.output.is_some() {
        anyhow::bail!(
            "-o/--output writes the plots and files of one stone; for {} files use --csv FILE (or --json for JSON lines)",
            files.len()
        );
    }
    if args.csv.is_some() && args.json {
        anyhow::bail!("--csv and --json choose two different outputs for a batch: give one of them");
    }
    match files.as_slice() {
        [] if args.csv.is_none() => single(None, &args, &opts),
        [] => anyhow::bail!("--csv needs mesh files or folders to analyse"),
        [one] if !is_batch => single(Some(one), &args, &opts),
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
/// and the name to report. An open scan is said on standard error: it is analysed closed by a
/// flat cap.
pub fn load_analysis(path: Option<&Path>, opts: &Options) -> Result<(Analysis, String)> {
    let (analysis, name) = match path {
        Some(p) => (Analysis::of_file(p, opts)?, p.display().to_string()),
        None => (bundled::analysis(opts)?, bundled::NAME.to_string()),
    };
    if let Some(h) = &analysis.hidden_base {
        eprintln!(
            "note: {name} is an open scan: its hidden base is closed by a {} (the nominal base; `shake --pose \
             as-scanned --ensemble N` draws it anew for every member)",
            h.base
        );
    }
    Ok((analysis, name))
}

pub use rocking_stones::bundled::is_bundled;

/// Say on standard error what was accepted although not clean (shallow self-intersections).
fn warn(name: &str, r: &rocking_stones::mesh::Repairs) {
    if r.shallow_crossings > 0 {
        eprintln!(
            "warning: {name}: {} pair(s) of triangles cross each other, at most {:.1e} of the size deep (accepted: below {:.0e}); volume and G are those of the surface as given",
            r.shallow_crossings,
            r.crossing_depth,
            rocking_stones::mesh::SHALLOW_CROSSING_DEPTH
        );
    }
}

fn single(path: Option<&PathBuf>, args: &Args, opts: &Options) -> Result<()> {
    let (analysis, name) = load_analysis(path.map(|p| p.as_path()), opts)?;
    warn(&name, &analysis.repairs);
    let report = analysis.report(&name, opts);
    let unit = super::default_unit(&name, args.length_unit);
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report::summary_in(&report, &unit));
    }
    if let Some(dir) = &args.output {
        let written = report::write_outputs_in(&analysis, &report, &unit, dir)?;
        if !args.json {
            for w in written {
                println!("wrote {}", w.display());
            }
        }
    }
    Ok(())
}

/// One file of a batch: its report, or its error message and kind.
type Outcome = Result<Report, (String, &'static str)>;

fn batch(files: &[PathBuf], args: &Args, opts: &Options) -> Result<()> {
    let bar = indicatif::ProgressBar::new(files.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {elapsed_precise} {msg}")
            .expect("valid template"),
    );
    let results: Vec<(PathBuf, Outcome)> = files
        .par_iter()
        .map(|f| {
            let r = Analysis::of_file(f, opts)
                .map(|a| a.report(&f.display().to_string(), opts))
                .map_err(|e| (e.to_string(), e.kind()));
            bar.inc(1);
            (f.clone(), r)
        })
        .collect();
    bar.finish_and_clear();
    let failed = results.iter().filter(|(_, r)| r.is_err()).count();
    for (_, r) in &results {
        match r {
            Err((e, _)) => eprintln!("error: {e}"),
            Ok(report) => warn(&report.file, &report.repairs),
        }
    }
    if args.json {
        let mut out = std::io::stdout().lock();
        for (f, r) in &results {
            let line = match r {
                Ok(report) => serde_json::to_string(report)?,
                Err((e, kind)) => serde_json::to_string(
                    &serde_json::json!({ "file": f.display().to_string(), "error": e, "kind": kind }),
                )?,
            };
            writeln!(out, "{line}")?;
        }
    } else {
        let rows = results.iter().map(|(f, r)| (f.as_path(), r.as_ref().map_err(|(e, _)| e.as_str())));
        match &args.csv {
            Some(path) => {
                let file = std::fs::File::create(path).with_context(|| format!("{}: cannot create", path.display()))?;
                report::write_batch_csv(file, rows)?;
                eprintln!("wrote {} ({} files, {} failed)", path.display(), results.len(), failed);
            }
            None => report::write_batch_csv(std::io::stdout().lock(), rows)?,
        }
    }
    if failed > 0 {
        anyhow::bail!(
            "{failed} of {} files failed (their errors are above and in the {} output)",
            results.len(),
            if args.json { "JSON lines" } else { "CSV `error` column of the" }
        );
    }
    Ok(())
}

/// Does the file name end in a mesh extension we read?
fn is_mesh_file(p: &Path) -> bool {
    let ext = p.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase());
    matches!(ext.as_deref(), Some("stl" | "obj" | "ply"))
}
