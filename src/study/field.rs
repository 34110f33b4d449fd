//! Field studies: every scan of a folder analysed by the `rocking analyze` pipeline, joined with
//! its metadata, counted at a fixed ν (and by the dynamic experimenter), summarised per sample.

use super::experimenter::{hand_experiment, DynamicCounts, Experimenter};
use super::hand::{CountDistribution, HandExperimenter};
use super::metadata::Metadata;
use super::{CountCurve, Moments};
use crate::analysis::{Analysis, Options, Report, PAPER_NU};
use crate::dynamics::size::{RealSize, Size};
use crate::hierarchy::Counts;
use crate::rng::fnv1a_str;
use crate::stats::{mean, sample_sd};
use crate::{Error, Result};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The counts of one analysed pebble.
#[derive(Clone, Debug)]
pub struct Counted {
    /// What `rocking analyze` reports for it.
    pub report: Report,
    /// Its counts S and U as functions of ν.
    pub curve: CountCurve,
    /// The simulated experimenter's findings at the study's ν, if asked for.
    pub dynamic: Option<DynamicCounts>,
}

impl Counted {
    /// Count an analysed pebble: the report (named `name`), the count curve and, with an
    /// experimenter, the dynamic counts at `nu` (hand seed `seed`).
    pub fn of(
        a: &Analysis,
        name: &str,
        opts: &Options,
        nu: f64,
        exp: Option<&Experimenter>,
        seed: u64,
    ) -> Result<Counted> {
        let dynamic = exp.map(|e| hand_experiment(a, nu, e, seed)).transpose()?;
        Ok(Counted { report: a.report_without_basins(name, opts), curve: CountCurve::of(&a.hierarchy), dynamic })
    }
}

/// One pebble of a study.
#[derive(Clone, Debug)]
pub struct Pebble {
    /// The file name without extension (synthetic: `SAMPLE_###`).
    pub id: String,
    /// Empty when the pebble has no metadata.
    pub sample: String,
    /// The pass-through metadata values (empty strings without metadata).
    pub meta: Vec<String>,
    /// The file as `rocking analyze` names it.
    pub file: String,
    /// Its counts, or why its analysis failed.
    pub result: std::result::Result<Counted, String>,
}

/// A study: pebbles, their metadata columns and the hand experimenter of the hand columns.
#[derive(Clone, Debug)]
pub struct Study {
    /// ν of the fixed-ν (hand experiment) columns: the paper's one-ν experimenter, used when
    /// `hand` is None.
    pub nu: f64,
    /// The two-tolerance hand experimenter of the hand columns (each pebble's distribution of
    /// counts and its most likely pair); None: the counts of G(`nu`).
    pub hand: Option<HandExperimenter>,
    /// Names of the pass-through metadata columns.
    pub meta_columns: Vec<String>,
    /// The pebbles, with their results.
    pub pebbles: Vec<Pebble>,
    /// Whether the dynamic experimenter ran.
    pub dynamic: bool,
}

impl Study {
    /// The counts a person reports for a pebble: the most likely pair of the two-tolerance
    /// experimenter (H = S + U − 2), or the counts of G(ν) without one.
    pub fn reported(&self, c: &Counted) -> Counts {
        match &self.hand {
            Some(e) => {
                let p = e.counts(&c.curve).most_likely();
                Counts { stable: p.stable, unstable: p.unstable, saddle: p.saddle }
            }
            None => c.curve.at(self.nu),
        }
    }

    /// The distribution of a pebble's reported counts: the two-tolerance experimenter's, or
    /// certainty on the counts of G(ν) without one.
    pub fn distribution(&self, c: &Counted) -> CountDistribution {
        self.hand.unwrap_or_else(|| HandExperimenter::one_nu(self.nu)).counts(&c.curve)
    }

    /// For a study whose scans are in units of `length_unit_m` metres, the warning
    /// ([`RealSize::implausibility`]) of each analysed pebble whose real size is not plausible.
    pub fn implausible_sizes(&self, length_unit_m: f64) -> Result<Vec<String>> {
        let mut odd = Vec::new();
        for p in &self.pebbles {
            if let Ok(c) = &p.result {
                let given = Some(Size::Unit(length_unit_m));
                odd.extend(RealSize::resolve(&p.file, c.report.micro.r_max, given)?.implausibility(&p.file));
            }
        }
        Ok(odd)
    }

    /// Name every pebble's file relative to `root`, as a user running from `root` names it: the
    /// folders `root` that lead a file name are removed, in the pebble and in its report.
    pub fn relative_to(&mut self, root: &Path) {
        for p in &mut self.pebbles {
            if let Ok(relative) = Path::new(&p.file).strip_prefix(root) {
                p.file = relative.display().to_string();
            }
            if let Ok(c) = &mut p.result {
                c.report.file = p.file.clone();
            }
        }
    }
}

/// Options of a field study.
#[derive(Clone, Debug)]
pub struct StudyOptions {
    /// Options of the static analysis; `nu: None` gives the automatic plateau in the macro
    /// columns, as `rocking analyze` without `--nu`.
    pub analysis: Options,
    /// ν of the fixed-ν columns.
    pub nu: f64,
    /// Run the simulated experimenter too.
    pub experimenter: Option<Experimenter>,
    /// Metadata ids without a scan are a warning (returned) instead of an error.
    pub allow_unmatched: bool,
}

impl Default for StudyOptions {
    fn default() -> Self {
        StudyOptions { analysis: Options::default(), nu: PAPER_NU, experimenter: None, allow_unmatched: false }
    }
}

/// Does the file name end in a mesh extension (`stl`, `obj`, `ply`, any case)?
pub fn is_mesh_file(p: &Path) -> bool {
    let ext = p.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase());
    matches!(ext.as_deref(), Some("stl" | "obj" | "ply"))
}

/// The mesh files of a folder, sorted, as `rocking analyze FOLDER` lists them.
pub fn mesh_files(folder: &Path) -> Result<Vec<PathBuf>> {
    let io = |e| Error::Io { path: folder.into(), error: e };
    let mut found: Vec<PathBuf> = std::fs::read_dir(folder)
        .map_err(io)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|f| f.is_file() && is_mesh_file(f))
        .collect();
    found.sort();
    if found.is_empty() {
        return Err(Error::Study {
            path: folder.to_path_buf(),
            what: "no .stl, .obj or .ply files in this folder".into(),
        });
    }
    Ok(found)
}

/// A pebble's id: its file name without the extension.
pub fn pebble_id(path: &Path) -> String {
    path.file_stem().map_or(String::new(), |s| s.to_string_lossy().into_owned())
}

/// Analyse `files` in parallel (telling `monitor` of each; [`Error::Cancelled`] if it stops) and join them with `meta` on their
/// ids. Errors: two files with the same id; metadata ids without a scan (unless
/// `opts.allow_unmatched`, when they are returned as the second value). A file that fails to
/// load or analyse gets a row with its error, as in `rocking analyze`.
pub fn run_files(
    files: &[PathBuf],
    meta: Option<&Metadata>,
    opts: &StudyOptions,
    monitor: &dyn crate::monitor::Monitor,
) -> Result<(Study, Vec<String>)> {
    let ids: Vec<String> = files.iter().map(|f| pebble_id(f)).collect();
    let mut seen: BTreeMap<&str, &Path> = BTreeMap::new();
    for (id, f) in ids.iter().zip(files) {
        if let Some(prev) = seen.insert(id, f) {
            return Err(Error::Study {
                path: f.clone(),
                what: format!(
                    "has the same id {id:?} as {}: ids (file names without extension) must be unique",
                    prev.display()
                ),
            });
        }
    }
    let mut unmatched = Vec::new();
    if let Some(m) = meta {
        let set: BTreeSet<String> = ids.iter().cloned().collect();
        unmatched = m.unmatched(&set).into_iter().map(String::from).collect();
        if !unmatched.is_empty() && !opts.allow_unmatched {
            let shown: Vec<&str> = unmatched.iter().take(10).map(|s| s.as_str()).collect();
            return Err(Error::Study {
                path: m.path.clone(),
                what: format!(
                    "{} id(s) have no scan: {}{} (a scan's id is its file name without extension; \
                 allow unmatched ids to only warn of them)",
                    unmatched.len(),
                    shown.join(", "),
                    if unmatched.len() > 10 { ", …" } else { "" }
                ),
            });
        }
    }
    let ncols = meta.map_or(0, |m| m.columns.len());
    let pebbles: Vec<Option<Pebble>> = files
        .par_iter()
        .zip(ids.par_iter())
        .map(|(f, id)| {
            crate::monitor::item(monitor, || {
                let name = f.display().to_string();
                let seed = opts.experimenter.as_ref().map_or(0, |e| e.seed ^ fnv1a_str(id));
                let result = Analysis::of_file(f, &opts.analysis)
                    .and_then(|a| Counted::of(&a, &name, &opts.analysis, opts.nu, opts.experimenter.as_ref(), seed))
                    .map_err(|e| e.to_string());
                let row = meta.and_then(|m| m.rows.get(id));
                Pebble {
                    id: id.clone(),
                    sample: row.map_or(String::new(), |r| r.sample.clone()),
                    meta: row.map_or_else(|| vec![String::new(); ncols], |r| r.values.clone()),
                    file: name,
                    result,
                }
            })
        })
        .collect::<Vec<_>>();
    let pebbles = crate::monitor::all(pebbles)?;
    let study = Study {
        nu: opts.nu,
        hand: None,
        meta_columns: meta.map_or_else(Vec::new, |m| m.columns.clone()),
        pebbles,
        dynamic: opts.experimenter.is_some(),
    };
    Ok((study, unmatched))
}

/// One sample of a study: sizes, mean axis ratios and the moments of the counts at each scale.
#[derive(Clone, Debug, Serialize)]
pub struct SampleSummary {
    /// Sample name.
    pub sample: String,
    /// Pebbles analysed.
    pub pebbles: usize,
    /// Pebbles whose analysis failed (not in the statistics).
    pub failed: usize,
    /// Mean c/b over the analysed pebbles.
    pub mean_c_over_b: f64,
    /// Mean c/a over the analysed pebbles.
    pub mean_c_over_a: f64,
    /// Mean b/a over the analysed pebbles.
    pub mean_b_over_a: f64,
    /// G(0).
    pub micro: Moments,
    /// Each pebble's macro scale (its automatic plateau, as in `rocking analyze`).
    pub plateau: Moments,
    /// The hand experimenter's counts: E and σ of the mixture of the pebbles' distributions
    /// ([`Moments::of_distributions`]); for the one-ν experimenter, of G(ν) at the study's ν.
    pub hand: Moments,
    /// Dynamic experimenter: E and σ of the stable flocks found (U is not observable).
    pub dyn_es: Option<f64>,
    /// σ of the stable flocks found by the dynamic experimenter.
    pub dyn_sd_s: Option<f64>,
    /// Mean number of distinct rocking positions (unstable/saddle flocks) found.
    pub dyn_rocking: Option<f64>,
}

/// Per-sample summaries, samples in name order (pebbles without a sample form the group "").
pub fn summarize(study: &Study) -> Vec<SampleSummary> {
    let mut groups: BTreeMap<&str, Vec<&Pebble>> = BTreeMap::new();
    for p in &study.pebbles {
        groups.entry(p.sample.as_str()).or_default().push(p);
    }
    groups
        .into_iter()
        .map(|(name, ps)| {
            let ok: Vec<&Counted> = ps.iter().filter_map(|p| p.result.as_ref().ok()).collect();
            let shape = |f: fn(&Counted) -> f64| mean(&ok.iter().map(|c| f(c)).collect::<Vec<_>>());
            let counts =
                |f: &dyn Fn(&Counted) -> Counts| Moments::of_counts(&ok.iter().map(|c| f(c)).collect::<Vec<_>>());
            let dynamic: Vec<&DynamicCounts> = ok.iter().filter_map(|c| c.dynamic.as_ref()).collect();
            let dyn_s: Vec<f64> = dynamic.iter().map(|d| d.stable as f64).collect();
            let dyn_r: Vec<f64> = dynamic.iter().map(|d| d.rocking as f64).collect();
            let some = |x: f64| (!dynamic.is_empty()).then_some(x);
            SampleSummary {
                sample: name.to_string(),
                pebbles: ok.len(),
                failed: ps.len() - ok.len(),
                mean_c_over_b: shape(|c| c.report.shape.c_over_b),
                mean_c_over_a: shape(|c| c.report.shape.c_over_a),
                mean_b_over_a: shape(|c| c.report.shape.b_over_a),
                micro: counts(&|c| c.curve.micro()),
                plateau: counts(&|c| c.report.macro_counts()),
                hand: match study.hand {
                    Some(_) => Moments::of_distributions(&ok.iter().map(|c| study.distribution(c)).collect::<Vec<_>>()),
                    None => counts(&|c| c.curve.at(study.nu)),
                },
                dyn_es: some(mean(&dyn_s)),
                dyn_sd_s: some(sample_sd(&dyn_s)),
                dyn_rocking: some(mean(&dyn_r)),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_are_named_relative_to_the_root() {
        let (mesh, repairs) = crate::generate::cuboid(1.0, 2.0, 3.0).into_solid_boundary().unwrap();
        let a = Analysis::of_solid(mesh, repairs, &Options::default()).unwrap();
        let pebble = |file: &str, result| Pebble {
            id: "p".into(),
            sample: String::new(),
            meta: vec![],
            file: file.into(),
            result,
        };
        let counted = Counted::of(&a, "field/scans/a.ply", &Options::default(), PAPER_NU, None, 0).unwrap();
        let pebbles = vec![
            pebble("field/scans/a.ply", Ok(counted)),
            pebble("field/scans/b.ply", Err("unreadable".into())),
            pebble("elsewhere/field/c.ply", Err("unreadable".into())),
        ];
        let mut study = Study { nu: PAPER_NU, hand: None, meta_columns: vec![], pebbles, dynamic: false };
        study.relative_to(Path::new("field"));
        let files: Vec<&str> = study.pebbles.iter().map(|p| p.file.as_str()).collect();
        assert_eq!(files, ["scans/a.ply", "scans/b.ply", "elsewhere/field/c.ply"]);
        assert_eq!(study.pebbles[0].result.as_ref().unwrap().report.file, "scans/a.ply");
    }
}
