//! Field studies and synthetic hand experiments (paper §1.2, §3, Table 2, Figure 12).
//!
//! The paper models the person who counts the equilibria of a pebble by hand with one number,
//! ν: pairs of equilibria closer than ν·R_max in R are not told apart, so the experimenter counts
//! the equilibria of G(ν), not of G(0). This module turns that into tools:
//!
//! * **Field study** ([`run_files`]): every scan of a folder analysed in parallel by the same
//!   pipeline as `rocking analyze` ([`Analysis::of_file`] → [`Report`]), joined on its id (the file
//!   name without extension) with an optional metadata CSV ([`Metadata`]), one row per pebble
//!   ([`write_pebbles_csv`]: the `rocking analyze` columns unchanged, then S, U, H at a fixed ν,
//!   by default the paper's [`PAPER_NU`]) and one row per sample ([`summarize`],
//!   [`write_samples_csv`]).
//! * **Static synthetic hand experiment**: the counts of G(ν) at a given ν ([`CountCurve`] reads
//!   them for any ν from the recorded hierarchy without recomputation).
//! * **Dynamic synthetic hand experiment** ([`hand_experiment`]): a simulated person who sets the
//!   pebble down in a uniformly random orientation from a small height, `trials` times, and
//!   notes the distinct stable flocks it comes to rest in (drops in rapier3d, ended as soon as
//!   the final flock is certain, [`CertificateMode::Flock`]). Setting a pebble down can only find
//!   stable positions: unstable equilibria (balancing on a tip) cannot be found this way, so the
//!   dynamic experiment gives S only. Rests inside unstable or saddle flocks (rocking
//!   equilibria) are counted apart.
//! * **Synthetic populations** ([`synthetic_sample`]): N pebbles of [`generate::pebble`] whose
//!   axis ratios scatter around a target sample's mean c/b and c/a.
//! * **Fitting ν** ([`fit_nu`]): the ν at which synthetic populations with the axis ratios of the
//!   paper's Table 2 samples reproduce the hand columns E(S), E(U), σ(S), σ(U) best.
//!
//! **Standard deviations.** σ is the *sample* standard deviation (divisor n − 1) throughout. This
//! is the paper's convention for its hand columns, inferred from Table 2: a mean of 50 integer
//! counts is a multiple of 0.02 and the sum of squares Q of integers has the parity of their sum,
//! so for each (E, σ) pair one can ask whether any integer Q reproduces σ to the printed two
//! decimals. For all 44 hand pairs the n − 1 divisor admits such a Q; the population divisor
//! (n) admits none for 28 of them. (The paper's computer columns, 20 pebbles, fit the population
//! divisor better: 5 of the 6 decisive pairs.)

use crate::analysis::{Analysis, Options, Report, PAPER_NU};
use crate::dynamics::params::{DropParams, Preset, Surface};
use crate::dynamics::stone::Stone;
use crate::equilibria::Kind;
use crate::hierarchy::{Counts, Hierarchy};
use crate::montecarlo::{run_report, CertificateMode, RunHeader, FORMAT};
use crate::plot::{init_fonts, FONT_FAMILY};
use crate::rng::{fnv1a_str, item_rng};
use crate::shape::{describe, Zingg};
use crate::solid::MassProperties;
use crate::stats::{log_fit, log_grid, mean, sample_sd, GridSize, LogFit};
use crate::{generate, Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use rand::{Rng, RngExt};
use rand_distr::StandardNormal;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------------------------
// Statistics
// ---------------------------------------------------------------------------------------------

/// E and σ (sample standard deviation) of S and U over a group of pebbles.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Moments {
    pub n: usize,
    pub es: f64,
    pub eu: f64,
    pub sd_s: f64,
    pub sd_u: f64,
}

impl Moments {
    /// Moments of the (S, U) pairs.
    pub fn of(su: &[(f64, f64)]) -> Moments {
        let s: Vec<f64> = su.iter().map(|p| p.0).collect();
        let u: Vec<f64> = su.iter().map(|p| p.1).collect();
        Moments { n: su.len(), es: mean(&s), eu: mean(&u), sd_s: sample_sd(&s), sd_u: sample_sd(&u) }
    }

    /// Moments of the stable and unstable counts.
    pub fn of_counts(c: &[Counts]) -> Moments {
        Moments::of(&c.iter().map(|c| (c.stable as f64, c.unstable as f64)).collect::<Vec<_>>())
    }

    /// [E(S), E(U), σ(S), σ(U)].
    pub fn as_array(&self) -> [f64; 4] {
        [self.es, self.eu, self.sd_s, self.sd_u]
    }
}

// ---------------------------------------------------------------------------------------------
// Counts for any ν
// ---------------------------------------------------------------------------------------------

/// S(ν), U(ν), H(ν) of one stone for every ν, read from its cancellation hierarchy: the counts
/// of G(0) and after every distinct level. `at(ν)` equals [`Hierarchy::counts_at`] (cancellations
/// with level < ν applied), in O(log n).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CountCurve {
    /// Distinct cancellation levels, increasing.
    pub levels: Vec<f64>,
    /// `counts[0]` = G(0); `counts[k]` = after every cancellation with level ≤ `levels[k − 1]`.
    pub counts: Vec<Counts>,
}

impl CountCurve {
    /// Record the curve of a hierarchy.
    pub fn of(h: &Hierarchy) -> CountCurve {
        let mut c = h.counts0();
        let mut levels = Vec::new();
        let mut counts = vec![c];
        let mut i = 0;
        while i < h.cancellations.len() {
            let level = h.cancellations[i].level;
            while i < h.cancellations.len() && h.cancellations[i].level == level {
                for &x in &h.cancellations[i].removed {
                    let slot = match h.nodes[x].kind {
                        Kind::Stable => &mut c.stable,
                        Kind::Unstable => &mut c.unstable,
                        Kind::Saddle => &mut c.saddle,
                    };
                    *slot -= 1;
                }
                i += 1;
            }
            levels.push(level);
            counts.push(c);
        }
        CountCurve { levels, counts }
    }

    /// The counts of G(ν).
    pub fn at(&self, nu: f64) -> Counts {
        self.counts[self.levels.partition_point(|&l| l < nu)]
    }

    /// The counts of G(0): the micro-equilibria.
    pub fn micro(&self) -> Counts {
        self.counts[0]
    }
}

// ---------------------------------------------------------------------------------------------
// Metadata
// ---------------------------------------------------------------------------------------------

/// One metadata row.
#[derive(Clone, Debug, PartialEq)]
pub struct MetaRow {
    /// Line of the row in the file (1-based, the header is line 1).
    pub line: u64,
    /// Value of the `sample` column (empty without one).
    pub sample: String,
    /// Values of the pass-through columns, in [`Metadata::columns`] order.
    pub values: Vec<String>,
}

/// A metadata CSV joined to the scans on `id`.
///
/// Comma-, semicolon- or tab-separated, detected from the header line (the separator that occurs
/// most often outside quotes; a tie goes to the comma), optionally with a UTF-8 byte-order mark,
/// quoted fields allowed. Column names are matched case-insensitively for `id` (required) and
/// `sample` (optional); every other column is passed through unchanged. An id is the scan's file
/// name without its extension; an id written with a mesh extension (`p01.ply`) is accepted too.
/// Errors name the file and line: no `id` column, an empty id, a row with the wrong number of
/// fields, and the same id twice.
#[derive(Clone, Debug)]
pub struct Metadata {
    pub path: PathBuf,
    pub delimiter: u8,
    /// The pass-through columns (all but `id` and `sample`), as named in the header.
    pub columns: Vec<String>,
    /// By id.
    pub rows: BTreeMap<String, MetaRow>,
}

/// The separator of a header line: `;`, `\t` or `,`, whichever occurs most often outside
/// double quotes (ties and none: `,`).
pub fn detect_delimiter(header: &str) -> u8 {
    let mut n = [0usize; 3];
    let mut quoted = false;
    for ch in header.chars() {
        match ch {
            '"' => quoted = !quoted,
            ',' if !quoted => n[0] += 1,
            ';' if !quoted => n[1] += 1,
            '\t' if !quoted => n[2] += 1,
            _ => {}
        }
    }
    if n[1] > n[0] && n[1] >= n[2] {
        b';'
    } else if n[2] > n[0] && n[2] > n[1] {
        b'\t'
    } else {
        b','
    }
}

/// The id of a metadata value or a file name: trimmed, a mesh extension removed.
pub fn id_key(s: &str) -> String {
    let s = s.trim();
    let lower = s.to_ascii_lowercase();
    for ext in [".ply", ".stl", ".obj"] {
        if lower.ends_with(ext) && s.len() > ext.len() {
            return s[..s.len() - ext.len()].to_string();
        }
    }
    s.to_string()
}

impl Metadata {
    /// Read and check a metadata file.
    pub fn read(path: &Path) -> Result<Metadata> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::Io { path: path.into(), error: e })?;
        Metadata::parse(&text, path)
    }

    /// Parse metadata text (`path` only names it in errors).
    pub fn parse(text: &str, path: &Path) -> Result<Metadata> {
        let parse = |what: String| Error::Parse { path: path.into(), what };
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let header_line =
            text.lines().find(|l| !l.trim().is_empty()).ok_or_else(|| parse("empty metadata file".into()))?;
        let delimiter = detect_delimiter(header_line);
        let mut reader = csv::ReaderBuilder::new()
            .delimiter(delimiter)
            .trim(csv::Trim::All)
            .has_headers(true)
            .from_reader(text.as_bytes());
        let header: Vec<String> =
            reader.headers().map_err(|e| parse(format!("header: {e}")))?.iter().map(|s| s.to_string()).collect();
        let find = |name: &str| header.iter().position(|h| h.eq_ignore_ascii_case(name));
        let id_col = find("id").ok_or_else(|| {
            parse(format!(
                "no `id` column (columns: {}; separator detected: {:?})",
                header.join(", "),
                delimiter as char
            ))
        })?;
        let sample_col = find("sample");
        let pass: Vec<usize> = (0..header.len()).filter(|&i| i != id_col && Some(i) != sample_col).collect();
        let columns = pass.iter().map(|&i| header[i].clone()).collect();
        let mut rows: BTreeMap<String, MetaRow> = BTreeMap::new();
        for record in reader.records() {
            let record = record.map_err(|e| parse(describe_csv_error(&e)))?;
            let line = record.position().map_or(0, |p| p.line());
            if record.iter().all(|f| f.is_empty()) {
                continue;
            }
            let id = id_key(&record[id_col]);
            if id.is_empty() {
                return Err(parse(format!("line {line}: empty id")));
            }
            let row = MetaRow {
                line,
                sample: sample_col.map_or(String::new(), |c| record[c].to_string()),
                values: pass.iter().map(|&i| record[i].to_string()).collect(),
            };
            if let Some(prev) = rows.get(&id) {
                return Err(parse(format!("id {id:?} appears twice (lines {} and {line})", prev.line)));
            }
            rows.insert(id, row);
        }
        Ok(Metadata { path: path.into(), delimiter, columns, rows })
    }

    /// Ids of the metadata that are not among `ids`.
    pub fn unmatched<'a>(&'a self, ids: &BTreeSet<String>) -> Vec<&'a str> {
        self.rows.keys().filter(|k| !ids.contains(*k)).map(|s| s.as_str()).collect()
    }
}

fn describe_csv_error(e: &csv::Error) -> String {
    match e.kind() {
        csv::ErrorKind::UnequalLengths { pos, expected_len, len } => {
            format!("line {}: {len} fields where the header has {expected_len}", pos.as_ref().map_or(0, |p| p.line()))
        }
        _ => e.to_string(),
    }
}

// ---------------------------------------------------------------------------------------------
// Pebbles and studies
// ---------------------------------------------------------------------------------------------

/// The simulated hand experimenter of [`hand_experiment`].
#[derive(Clone, Debug, Serialize)]
pub struct Experimenter {
    /// Times the pebble is set down (a person's budget).
    pub trials: u64,
    /// Drop parameters; `height` (in R_max) is the small height it is let go from.
    pub params: DropParams,
    /// Seed of the experimenter's hands (mixed with each pebble's id).
    pub seed: u64,
}

/// Default budget of the simulated experimenter.
pub const DEFAULT_TRIALS: u64 = 20;
/// Default release height of the simulated experimenter, in R_max: a pebble put down by hand.
pub const DEFAULT_SET_DOWN_HEIGHT: f64 = 0.05;

/// The contact and launch of a pebble set down by hand: the [`Preset::Drop`] protocol (from rest,
/// no spin) on [`Surface::StoneOnStone`], released [`DEFAULT_SET_DOWN_HEIGHT`] above the ground.
pub fn set_down_params() -> DropParams {
    DropParams { height: DEFAULT_SET_DOWN_HEIGHT, ..Preset::Drop.params(Surface::StoneOnStone) }
}

impl Default for Experimenter {
    fn default() -> Self {
        Experimenter {
            trials: DEFAULT_TRIALS,
            params: DropParams { height: DEFAULT_SET_DOWN_HEIGHT, ..set_down_params() },
            seed: 1,
        }
    }
}

/// What the simulated experimenter found on one pebble.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DynamicCounts {
    pub trials: u64,
    /// Trials that came to rest (the others were still moving at the time cap).
    pub settled: u64,
    /// Distinct stable flocks found: the dynamic S.
    pub stable: usize,
    /// Distinct unstable or saddle flocks rested in (rocking equilibria found).
    pub rocking: usize,
    /// Ids of every flock found (flocks of G(ν)).
    pub found: Vec<usize>,
}

/// Set the analysed pebble down `exp.trials` times in uniformly random orientations from
/// `exp.params.height` (in R_max) and count the distinct flocks of G(ν) it rests in. Trial i
/// uses [`item_rng`]`(seed, i)`. A trial settling on a facet that is not stable counts for the
/// flock its steepest descent drains to; a trial still moving at the time cap counts for nothing.
pub fn hand_experiment(a: &Analysis, nu: f64, exp: &Experimenter, seed: u64) -> Result<DynamicCounts> {
    let stone = Stone::new(a, nu)?;
    let header = RunHeader {
        format: FORMAT.into(),
        mesh: String::new(),
        mesh_fingerprint: String::new(),
        seed,
        drops: exp.trials,
        params: exp.params.clone(),
        certificate: CertificateMode::Flock,
        preset: None,
    };
    let (_, outcomes) = run_report(&stone, &header);
    let mut found = BTreeSet::new();
    let mut settled = 0;
    for o in outcomes.values().filter(|o| o.settled) {
        settled += 1;
        // Facets of outcomes are stable facets (the rule of `Stone::rest`).
        let flock = o.flock.map(|k| k as usize).or_else(|| o.facet.and_then(|f| stone.facet_flock[f as usize]));
        if let Some(k) = flock {
            found.insert(k);
        }
    }
    let kinds = &stone.flock_kinds;
    let stable = found.iter().filter(|&&k| kinds[k] == Kind::Stable).count();
    Ok(DynamicCounts {
        trials: exp.trials,
        settled,
        stable,
        rocking: found.len() - stable,
        found: found.into_iter().collect(),
    })
}

/// The counts of one analysed pebble.
#[derive(Clone, Debug)]
pub struct Counted {
    /// What `rocking analyze` reports for it.
    pub report: Report,
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
        Ok(Counted { report: a.report(name, opts), curve: CountCurve::of(&a.hierarchy), dynamic })
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
    pub result: std::result::Result<Counted, String>,
}

/// A study: pebbles, their metadata columns and the fixed ν of the hand columns.
#[derive(Clone, Debug)]
pub struct Study {
    /// ν of the fixed-ν (hand experiment) columns.
    pub nu: f64,
    pub meta_columns: Vec<String>,
    pub pebbles: Vec<Pebble>,
    /// Whether the dynamic experimenter ran.
    pub dynamic: bool,
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
        return Err(Error::Usage(format!("{}: no .stl, .obj or .ply files in this folder", folder.display())));
    }
    Ok(found)
}

/// A pebble's id: its file name without the extension.
pub fn pebble_id(path: &Path) -> String {
    path.file_stem().map_or(String::new(), |s| s.to_string_lossy().into_owned())
}

/// Analyse `files` in parallel (calling `tick` after each) and join them with `meta` on their
/// ids. Errors: two files with the same id; metadata ids without a scan (unless
/// `opts.allow_unmatched`, when they are returned as the second value). A file that fails to
/// load or analyse gets a row with its error, as in `rocking analyze`.
pub fn run_files(
    files: &[PathBuf],
    meta: Option<&Metadata>,
    opts: &StudyOptions,
    tick: &(dyn Fn() + Sync),
) -> Result<(Study, Vec<String>)> {
    let ids: Vec<String> = files.iter().map(|f| pebble_id(f)).collect();
    let mut seen: BTreeMap<&str, &Path> = BTreeMap::new();
    for (id, f) in ids.iter().zip(files) {
        if let Some(prev) = seen.insert(id, f) {
            return Err(Error::Usage(format!(
                "{} and {} have the same id {id:?}: ids (file names without extension) must be unique",
                prev.display(),
                f.display()
            )));
        }
    }
    let mut unmatched = Vec::new();
    if let Some(m) = meta {
        let set: BTreeSet<String> = ids.iter().cloned().collect();
        unmatched = m.unmatched(&set).into_iter().map(String::from).collect();
        if !unmatched.is_empty() && !opts.allow_unmatched {
            let shown: Vec<&str> = unmatched.iter().take(10).map(|s| s.as_str()).collect();
            return Err(Error::Usage(format!(
                "{}: {} id(s) have no scan: {}{} (a scan's id is its file name without extension; \
                 pass --allow-unmatched to only warn)",
                m.path.display(),
                unmatched.len(),
                shown.join(", "),
                if unmatched.len() > 10 { ", …" } else { "" }
            )));
        }
    }
    let ncols = meta.map_or(0, |m| m.columns.len());
    let pebbles: Vec<Pebble> = files
        .par_iter()
        .zip(ids.par_iter())
        .map(|(f, id)| {
            let name = f.display().to_string();
            let seed = opts.experimenter.as_ref().map_or(0, |e| e.seed ^ fnv1a_str(id));
            let result = Analysis::of_file(f, &opts.analysis)
                .and_then(|a| Counted::of(&a, &name, &opts.analysis, opts.nu, opts.experimenter.as_ref(), seed))
                .map_err(|e| e.to_string());
            tick();
            let row = meta.and_then(|m| m.rows.get(id));
            Pebble {
                id: id.clone(),
                sample: row.map_or(String::new(), |r| r.sample.clone()),
                meta: row.map_or_else(|| vec![String::new(); ncols], |r| r.values.clone()),
                file: name,
                result,
            }
        })
        .collect();
    let study = Study {
        nu: opts.nu,
        meta_columns: meta.map_or_else(Vec::new, |m| m.columns.clone()),
        pebbles,
        dynamic: opts.experimenter.is_some(),
    };
    Ok((study, unmatched))
}

/// Columns after the `rocking analyze` ones in the pebble CSV.
pub const HAND_COLUMNS: [&str; 4] = ["hand_nu", "hand_S", "hand_U", "hand_H"];
/// Columns of the dynamic experimenter in the pebble CSV.
pub const DYNAMIC_COLUMNS: [&str; 4] = ["dyn_trials", "dyn_settled", "dyn_S", "dyn_rocking"];

/// The header of the pebble CSV: `id`, `sample`, the metadata columns (prefixed `meta_` where
/// they would clash with another column), the columns of `rocking analyze` (see
/// [`crate::report::CSV_HEADER`]), the counts at the fixed ν, and the dynamic columns.
pub fn pebble_header(study: &Study) -> Vec<String> {
    let mut fixed: Vec<String> = ["id", "sample"].iter().map(|s| s.to_string()).collect();
    fixed.extend(crate::report::CSV_HEADER.iter().map(|s| s.to_string()));
    fixed.extend(HAND_COLUMNS.iter().map(|s| s.to_string()));
    if study.dynamic {
        fixed.extend(DYNAMIC_COLUMNS.iter().map(|s| s.to_string()));
    }
    let meta = study.meta_columns.iter().map(|c| {
        if fixed.iter().any(|f| f.eq_ignore_ascii_case(c)) {
            format!("meta_{c}")
        } else {
            c.clone()
        }
    });
    let mut out: Vec<String> = fixed[..2].to_vec();
    out.extend(meta);
    out.extend(fixed[2..].iter().cloned());
    out
}

/// One CSV row per pebble (see [`pebble_header`]). The `rocking analyze` columns are written by
/// [`crate::report::write_batch_csv`] itself, so they are the same, character for character.
pub fn write_pebbles_csv<W: std::io::Write>(study: &Study, w: W) -> anyhow::Result<()> {
    let mut buf = Vec::new();
    let rows = study
        .pebbles
        .iter()
        .map(|p| (Path::new(p.file.as_str()), p.result.as_ref().map(|c| &c.report).map_err(|e| e.as_str())));
    crate::report::write_batch_csv(&mut buf, rows)?;
    let mut analyze = csv::Reader::from_reader(buf.as_slice());
    let mut out = csv::Writer::from_writer(w);
    out.write_record(pebble_header(study))?;
    for (p, rec) in study.pebbles.iter().zip(analyze.records()) {
        let rec = rec?;
        let mut row = vec![p.id.clone(), p.sample.clone()];
        row.extend(p.meta.iter().cloned());
        row.extend(rec.iter().map(String::from));
        match &p.result {
            Ok(c) => {
                let k = c.curve.at(study.nu);
                row.extend([
                    format!("{:e}", study.nu),
                    k.stable.to_string(),
                    k.unstable.to_string(),
                    k.saddle.to_string(),
                ]);
                if study.dynamic {
                    match &c.dynamic {
                        Some(d) => row.extend([
                            d.trials.to_string(),
                            d.settled.to_string(),
                            d.stable.to_string(),
                            d.rocking.to_string(),
                        ]),
                        None => row.extend(std::iter::repeat_n(String::new(), DYNAMIC_COLUMNS.len())),
                    }
                }
            }
            Err(_) => {
                let n = HAND_COLUMNS.len() + if study.dynamic { DYNAMIC_COLUMNS.len() } else { 0 };
                row.extend(std::iter::repeat_n(String::new(), n));
            }
        }
        out.write_record(row)?;
    }
    out.flush()?;
    Ok(())
}

/// One sample of a study: sizes, mean axis ratios and the moments of the counts at each scale.
#[derive(Clone, Debug, Serialize)]
pub struct SampleSummary {
    pub sample: String,
    /// Pebbles analysed.
    pub pebbles: usize,
    /// Pebbles whose analysis failed (not in the statistics).
    pub failed: usize,
    pub mean_c_over_b: f64,
    pub mean_c_over_a: f64,
    pub mean_b_over_a: f64,
    /// G(0).
    pub micro: Moments,
    /// Each pebble's macro scale (its automatic plateau, as in `rocking analyze`).
    pub plateau: Moments,
    /// G(ν) at the study's fixed ν.
    pub hand: Moments,
    /// Dynamic experimenter: E and σ of the stable flocks found (U is not observable).
    pub dyn_es: Option<f64>,
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
                hand: counts(&|c| c.curve.at(study.nu)),
                dyn_es: some(mean(&dyn_s)),
                dyn_sd_s: some(sample_sd(&dyn_s)),
                dyn_rocking: some(mean(&dyn_r)),
            }
        })
        .collect()
}

/// A number for a CSV cell: empty for NaN.
fn cell(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.6}")
    } else {
        String::new()
    }
}

/// One CSV row per sample: `sample, pebbles, failed, mean_c_over_b, mean_c_over_a,
/// mean_b_over_a`, then `E_S, E_U, sd_S, sd_U` for the micro scale (`micro_`), each pebble's
/// plateau (`plateau_`) and the fixed ν (`hand_`, with `hand_nu`), then the dynamic
/// experimenter (`dyn_E_S, dyn_sd_S, dyn_rocking`) if it ran. σ is the sample standard deviation
/// (n − 1), as in the paper's Table 2.
pub fn write_samples_csv<W: std::io::Write>(study: &Study, summaries: &[SampleSummary], w: W) -> anyhow::Result<()> {
    let mut out = csv::Writer::from_writer(w);
    let mut header: Vec<String> =
        ["sample", "pebbles", "failed", "mean_c_over_b", "mean_c_over_a", "mean_b_over_a"].map(String::from).to_vec();
    for scale in ["micro", "plateau", "hand"] {
        if scale == "hand" {
            header.push("hand_nu".into());
        }
        for m in ["E_S", "E_U", "sd_S", "sd_U"] {
            header.push(format!("{scale}_{m}"));
        }
    }
    if study.dynamic {
        header.extend(["dyn_E_S", "dyn_sd_S", "dyn_rocking"].map(String::from));
    }
    out.write_record(&header)?;
    for s in summaries {
        let mut row = vec![
            s.sample.clone(),
            s.pebbles.to_string(),
            s.failed.to_string(),
            cell(s.mean_c_over_b),
            cell(s.mean_c_over_a),
        ];
        row.push(cell(s.mean_b_over_a));
        for (scale, m) in [("micro", &s.micro), ("plateau", &s.plateau), ("hand", &s.hand)] {
            if scale == "hand" {
                row.push(format!("{:e}", study.nu));
            }
            row.extend(m.as_array().map(cell));
        }
        if study.dynamic {
            row.extend([s.dyn_es, s.dyn_sd_s, s.dyn_rocking].map(|x| x.map_or(String::new(), cell)));
        }
        out.write_record(row)?;
    }
    out.flush()?;
    Ok(())
}

/// The plain-text table of the sample summaries printed by `rocking study`.
pub fn samples_table(study: &Study, summaries: &[SampleSummary]) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<12} {:>4} {:>6} {:>6}  {:>13}  {:>13}  {:>20}{}",
        "sample",
        "n",
        "c/b",
        "c/a",
        "micro E(S,U)",
        "plateau E(S,U)",
        format!("ν={:.2e} E(S,U) σ(S,U)", study.nu),
        if study.dynamic { "  dynamic E(S) σ(S)" } else { "" }
    );
    for m in summaries {
        let name = if m.sample.is_empty() { "(none)" } else { &m.sample };
        let _ = write!(
            s,
            "{:<12} {:>4} {:>6.3} {:>6.3}  {:>6.2} {:>6.2}  {:>6.2} {:>6.2}  {:>4.2} {:>4.2} {:>4.2} {:>4.2}",
            name,
            m.pebbles,
            m.mean_c_over_b,
            m.mean_c_over_a,
            m.micro.es,
            m.micro.eu,
            m.plateau.es,
            m.plateau.eu,
            m.hand.es,
            m.hand.eu,
            m.hand.sd_s,
            m.hand.sd_u
        );
        if let (Some(e), Some(sd)) = (m.dyn_es, m.dyn_sd_s) {
            let _ = write!(s, "  {e:>8.2} {sd:>5.2}");
        }
        let _ = writeln!(s, "{}", if m.failed > 0 { format!("  ({} failed)", m.failed) } else { String::new() });
    }
    s
}

// ---------------------------------------------------------------------------------------------
// Synthetic populations
// ---------------------------------------------------------------------------------------------

/// A target sample: mean axis ratios c/b and c/a (measured as the project measures them, see
/// [`crate::shape`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SampleTarget {
    pub name: String,
    pub c_over_b: f64,
    pub c_over_a: f64,
}

/// How a synthetic population is generated (see [`synthetic_specs`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PopulationParams {
    /// Standard deviation of c/b and of b/a between the pebbles of a sample.
    pub spread: f64,
    /// Roughness amplitude of [`generate::pebble`] (largest relative radial deviation).
    pub roughness: f64,
    /// Points of each pebble (the scan resolution).
    pub points: usize,
    /// Pebbles per sample.
    pub count: usize,
    pub seed: u64,
    /// Correct the generator's mean ratios once so that the *measured* means hit the target.
    pub calibrate: bool,
}

impl Default for PopulationParams {
    fn default() -> Self {
        PopulationParams { spread: 0.08, roughness: 0.05, points: 2000, count: 50, seed: 1, calibrate: true }
    }
}

/// One synthetic pebble to generate.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SyntheticSpec {
    /// Semi-axes 1 ≥ b ≥ c of the underlying ellipsoid.
    pub semi_axes: [f64; 3],
    /// Seed of [`generate::pebble`].
    pub seed: u64,
}

/// Smallest ratio drawn for c/b or b/a.
pub const MIN_RATIO: f64 = 0.15;

/// The pebbles of a synthetic sample. Pebble j draws from [`item_rng`]`(seed ^ fnv1a_str(name), j)`
/// a mesh seed and two standard normals z₁, z₂; its ellipsoid has semi-axes
/// (1, β, β γ) with γ = c/b = clamp(μ_c/b + spread·z₁) and β = b/a = clamp(μ_b/a + spread·z₂),
/// clamped to [0.15, 1], μ_b/a = (c/a)/(c/b) of the target. With `calibrate`, the population is
/// generated and measured once ([`describe`]: principal-axes box, which roughness inflates), the
/// means μ are shifted by target − measured, and the specs are drawn again with the same z.
/// So the population depends only on (target, params), not on other samples.
pub fn synthetic_specs(target: &SampleTarget, params: &PopulationParams) -> Result<Vec<SyntheticSpec>> {
    for (what, x) in [("c/b", target.c_over_b), ("c/a", target.c_over_a)] {
        if !(x > 0.0 && x <= 1.0) {
            return Err(Error::Usage(format!("{}: target {what} must be in (0, 1], got {x}", target.name)));
        }
    }
    if target.c_over_a > target.c_over_b {
        return Err(Error::Usage(format!(
            "{}: c/a ({}) cannot exceed c/b ({}) since b ≤ a",
            target.name, target.c_over_a, target.c_over_b
        )));
    }
    if !(params.spread >= 0.0 && params.spread.is_finite()) {
        return Err(Error::Usage(format!("spread must be ≥ 0, got {}", params.spread)));
    }
    let base = params.seed ^ fnv1a_str(&target.name);
    let draws: Vec<(u64, f64, f64)> = (0..params.count as u64)
        .map(|j| {
            let mut rng = item_rng(base, j);
            let seed = rng.next_u64();
            (seed, rng.sample::<f64, _>(StandardNormal), rng.sample::<f64, _>(StandardNormal))
        })
        .collect();
    let specs = |mu_cb: f64, mu_ba: f64| -> Vec<SyntheticSpec> {
        draws
            .iter()
            .map(|&(seed, z1, z2)| {
                let cb = (mu_cb + params.spread * z1).clamp(MIN_RATIO, 1.0);
                let ba = (mu_ba + params.spread * z2).clamp(MIN_RATIO, 1.0);
                SyntheticSpec { semi_axes: [1.0, ba, ba * cb], seed }
            })
            .collect()
    };
    let ba_target = (target.c_over_a / target.c_over_b).min(1.0);
    let first = specs(target.c_over_b, ba_target);
    if !params.calibrate || params.count == 0 {
        return Ok(first);
    }
    let measured: Vec<(f64, f64)> = first
        .par_iter()
        .map(|s| -> Result<(f64, f64)> {
            let (mesh, _) =
                generate::pebble(s.semi_axes, params.roughness, params.points, s.seed).into_solid_boundary()?;
            let d = describe(&mesh, &MassProperties::of(&mesh)?);
            Ok((d.c_over_b, d.b_over_a))
        })
        .collect::<Result<_>>()?;
    let m_cb = mean(&measured.iter().map(|m| m.0).collect::<Vec<_>>());
    let m_ba = mean(&measured.iter().map(|m| m.1).collect::<Vec<_>>());
    Ok(specs(target.c_over_b + (target.c_over_b - m_cb), ba_target + (ba_target - m_ba)))
}

/// The pass-through columns of synthetic pebbles.
pub const SYNTHETIC_COLUMNS: [&str; 8] =
    ["target_c_over_b", "target_c_over_a", "spread", "roughness", "points", "mesh_seed", "semi_b", "semi_c"];

/// Generate and count a synthetic sample (ids `NAME_000`, …, sample `NAME`), in parallel; with
/// an experimenter, also the dynamic counts at `nu`. The mesh of a pebble is
/// `generate::pebble(spec.semi_axes, params.roughness, params.points, spec.seed)`.
pub fn synthetic_sample(
    target: &SampleTarget,
    params: &PopulationParams,
    nu: f64,
    exp: Option<&Experimenter>,
) -> Result<Vec<Pebble>> {
    let specs = synthetic_specs(target, params)?;
    let opts = Options::default();
    Ok(specs
        .par_iter()
        .enumerate()
        .map(|(j, s)| {
            let id = format!("{}_{j:03}", target.name);
            let result = generate::pebble(s.semi_axes, params.roughness, params.points, s.seed)
                .into_solid_boundary()
                .and_then(|(mesh, rep)| Analysis::of_solid(mesh, rep, &opts))
                .and_then(|a| Counted::of(&a, &id, &opts, nu, exp, exp.map_or(0, |e| e.seed ^ s.seed)))
                .map_err(|e| e.to_string());
            Pebble {
                id: id.clone(),
                sample: target.name.clone(),
                meta: vec![
                    format!("{}", target.c_over_b),
                    format!("{}", target.c_over_a),
                    format!("{}", params.spread),
                    format!("{}", params.roughness),
                    params.points.to_string(),
                    s.seed.to_string(),
                    format!("{:.6}", s.semi_axes[1]),
                    format!("{:.6}", s.semi_axes[2]),
                ],
                file: id,
                result,
            }
        })
        .collect())
}

/// A study of synthetic samples (one per target), for the CSV writers and plots.
pub fn synthetic_study(
    targets: &[SampleTarget],
    params: &PopulationParams,
    nu: f64,
    exp: Option<&Experimenter>,
) -> Result<Study> {
    let mut pebbles = Vec::new();
    for t in targets {
        pebbles.extend(synthetic_sample(t, params, nu, exp)?);
    }
    Ok(Study { nu, meta_columns: SYNTHETIC_COLUMNS.map(String::from).to_vec(), pebbles, dynamic: exp.is_some() })
}

// ---------------------------------------------------------------------------------------------
// Table 2 and the fit of ν
// ---------------------------------------------------------------------------------------------

/// One sample of the paper's Table 2 (`data/table2_hand_experiments.csv`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HandSample {
    pub id: String,
    pub location: String,
    pub rock_type: String,
    /// Pebbles counted by hand.
    pub n: usize,
    /// [E(S), E(U), σ(S), σ(U)] of the hand experiments.
    pub hand: [f64; 4],
    pub c_over_b: f64,
    pub c_over_a: f64,
    /// The paper's computer experiments at ν = 0.0035 (the 5 scanned samples only).
    pub computer: Option<[f64; 4]>,
    pub n_computer: Option<usize>,
}

impl HandSample {
    /// The synthetic target with this sample's mean ratios.
    pub fn target(&self) -> SampleTarget {
        SampleTarget { name: self.id.clone(), c_over_b: self.c_over_b, c_over_a: self.c_over_a }
    }

    /// Standard errors of [E(S), E(U), σ(S), σ(U)]: σ/√n for the means, σ/√(2(n − 1)) for the
    /// standard deviations (normal approximation).
    pub fn standard_errors(&self) -> [f64; 4] {
        standard_errors(&self.hand, self.n)
    }
}

fn standard_errors(m: &[f64; 4], n: usize) -> [f64; 4] {
    let n = n.max(2) as f64;
    [m[2] / n.sqrt(), m[3] / n.sqrt(), m[2] / (2.0 * (n - 1.0)).sqrt(), m[3] / (2.0 * (n - 1.0)).sqrt()]
}

/// Read Table 2: columns `id, location, n_hand, n_computer, rock_type, mean_b_mm, ES_hand,
/// ES_computer, EU_hand, EU_computer, sS_hand, sS_computer, sU_hand, sU_computer, c_over_b,
/// c_over_a` (computer columns may be empty).
pub fn read_table2(path: &Path) -> Result<Vec<HandSample>> {
    let parse = |what: String| Error::Parse { path: path.into(), what };
    let text = std::fs::read_to_string(path).map_err(|e| Error::Io { path: path.into(), error: e })?;
    let mut r = csv::ReaderBuilder::new().trim(csv::Trim::All).from_reader(text.as_bytes());
    let header: Vec<String> = r.headers().map_err(|e| parse(e.to_string()))?.iter().map(String::from).collect();
    let col = |name: &str| header.iter().position(|h| h == name).ok_or_else(|| parse(format!("no column {name:?}")));
    let c = |n: &str| col(n);
    let (id, loc, rock, n_hand, n_comp) = (c("id")?, c("location")?, c("rock_type")?, c("n_hand")?, c("n_computer")?);
    let hand = [c("ES_hand")?, c("EU_hand")?, c("sS_hand")?, c("sU_hand")?];
    let comp = [c("ES_computer")?, c("EU_computer")?, c("sS_computer")?, c("sU_computer")?];
    let (cb, ca) = (c("c_over_b")?, c("c_over_a")?);
    let mut out = Vec::new();
    for rec in r.records() {
        let rec = rec.map_err(|e| parse(describe_csv_error(&e)))?;
        let line = rec.position().map_or(0, |p| p.line());
        let num = |i: usize| -> Result<f64> {
            rec[i]
                .replace(',', ".")
                .parse::<f64>()
                .map_err(|_| parse(format!("line {line}: {:?} is not a number", &rec[i])))
        };
        let opt = |i: usize| -> Result<Option<f64>> {
            if rec[i].is_empty() {
                Ok(None)
            } else {
                num(i).map(Some)
            }
        };
        let computer = match (opt(comp[0])?, opt(comp[1])?, opt(comp[2])?, opt(comp[3])?) {
            (Some(a), Some(b), Some(c), Some(d)) => Some([a, b, c, d]),
            _ => None,
        };
        out.push(HandSample {
            id: rec[id].to_string(),
            location: rec[loc].to_string(),
            rock_type: rec[rock].to_string(),
            n: num(n_hand)? as usize,
            hand: [num(hand[0])?, num(hand[1])?, num(hand[2])?, num(hand[3])?],
            c_over_b: num(cb)?,
            c_over_a: num(ca)?,
            computer,
            n_computer: opt(n_comp)?.map(|x| x as usize),
        });
    }
    Ok(out)
}

/// The loss of the fit of ν: a χ² over samples i and the four statistics k ∈ {E(S), E(U), σ(S),
/// σ(U)},
///
/// χ²(ν) = Σᵢ Σₖ (simᵢₖ(ν) − handᵢₖ)² / (se_handᵢₖ² + se_simᵢₖ(ν)²),
///
/// with the standard errors of [`HandSample::standard_errors`] for both (the synthetic ones from
/// the synthetic σ and count). A statistic that is not finite (a sample of one pebble) is left
/// out; a zero denominator is replaced by 10⁻⁶.
pub fn chi2(hand: &[HandSample], sim: &[Moments]) -> f64 {
    hand.iter().zip(sim).map(|(h, m)| chi2_terms(&h.hand, &h.standard_errors(), m).iter().sum::<f64>()).sum()
}

fn chi2_terms(hand: &[f64; 4], se_hand: &[f64; 4], m: &Moments) -> [f64; 4] {
    let s = m.as_array();
    let se = standard_errors(&s, m.n);
    let mut out = [0.0; 4];
    for k in 0..4 {
        if s[k].is_finite() {
            let var = (se_hand[k].powi(2) + if se[k].is_finite() { se[k].powi(2) } else { 0.0 }).max(1e-12);
            out[k] = (s[k] - hand[k]).powi(2) / var;
        }
    }
    out
}

/// How ν is fitted.
#[derive(Clone, Debug, Serialize)]
pub struct FitOptions {
    /// The ν grid (increasing, positive).
    pub grid: Vec<f64>,
    /// Bootstrap replicates (0: none).
    pub bootstrap: usize,
    pub seed: u64,
    /// Which of [E(S), E(U), σ(S), σ(U)] enter the loss (default: all four).
    pub statistics: [bool; 4],
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            grid: log_grid(1e-5, 1e-1, GridSize::PerDecade(20)),
            bootstrap: 200,
            seed: 1,
            statistics: [true; 4],
        }
    }
}

/// The result of [`fit_nu`].
#[derive(Clone, Debug, Serialize)]
pub struct NuFit {
    pub grid: Vec<f64>,
    /// χ² at every grid ν.
    pub chi2: Vec<f64>,
    /// Best ν: the vertex of the parabola in log ν through the grid minimum and its neighbours.
    pub nu: f64,
    pub chi2_min: f64,
    /// Statistics fitted (up to 4 per sample) and degrees of freedom (terms − 1).
    pub terms: usize,
    pub dof: usize,
    /// The minimum is at an end of the grid (ν is then only bounded on one side).
    pub at_edge: bool,
    /// Scale factor s² = max(1, χ²_min / dof) (errors inflated by s when the model does not
    /// fit within the stated errors).
    pub scale: f64,
    /// {ν : χ²(ν) ≤ χ²_min + s²} (linear interpolation in log ν on the grid), widened to
    /// contain `nu` where the refined minimum falls between grid points above that level.
    pub interval: (f64, f64),
    /// χ² at `nu` itself (not interpolated) split by statistic: [E(S), E(U), σ(S), σ(U)],
    /// summed over the samples (statistics left out of the fit included, for comparison).
    pub chi2_by_statistic: [f64; 4],
    /// Fitted ν of every bootstrap replicate.
    pub bootstrap: Vec<f64>,
    /// 16th and 84th percentiles of the bootstrap ν (the ±1σ range of a normal).
    pub bootstrap_interval: (f64, f64),
    /// Standard deviation of log10 ν over the replicates.
    pub bootstrap_sd_log10: f64,
}

/// Fit ν: `pops[i]` are the count curves of the synthetic pebbles standing for `hand[i]`. The
/// loss is [`chi2`] on `opts.grid`. Uncertainty two ways: the Δχ² = s² interval ([`NuFit::scale`])
/// and a bootstrap in which each replicate resamples the synthetic pebbles of every sample with
/// replacement and draws the hand statistics from normals of their standard errors, then refits.
pub fn fit_nu(hand: &[HandSample], pops: &[Vec<CountCurve>], opts: &FitOptions) -> Result<NuFit> {
    if hand.len() != pops.len() || hand.is_empty() {
        return Err(Error::Usage(format!("{} hand samples but {} synthetic populations", hand.len(), pops.len())));
    }
    if opts.grid.len() < 3 || opts.grid.windows(2).any(|w| !(w[0] > 0.0 && w[1] > w[0])) {
        return Err(Error::Usage("the ν grid needs at least 3 increasing positive values".into()));
    }
    // table[i][j][g] = (S, U) of pebble j of sample i at grid ν g.
    let table: Vec<Vec<Vec<(f64, f64)>>> = pops
        .iter()
        .map(|pop| {
            pop.iter()
                .map(|c| {
                    opts.grid
                        .iter()
                        .map(|&nu| {
                            let k = c.at(nu);
                            (k.stable as f64, k.unstable as f64)
                        })
                        .collect()
                })
                .collect()
        })
        .collect();
    let se_hand: Vec<[f64; 4]> = hand.iter().map(|h| h.standard_errors()).collect();
    let used = opts.statistics;
    if !used.iter().any(|&u| u) {
        return Err(Error::Usage("no statistic selected for the fit of ν".into()));
    }
    let masked = |t: [f64; 4]| -> f64 { (0..4).filter(|&k| used[k]).map(|k| t[k]).sum() };
    let curve = |picks: &[Vec<usize>], targets: &[[f64; 4]]| -> Vec<f64> {
        (0..opts.grid.len())
            .map(|g| {
                (0..hand.len())
                    .map(|i| {
                        let su: Vec<(f64, f64)> = picks[i].iter().map(|&j| table[i][j][g]).collect();
                        masked(chi2_terms(&targets[i], &se_hand[i], &Moments::of(&su)))
                    })
                    .sum()
            })
            .collect()
    };
    let all: Vec<Vec<usize>> = pops.iter().map(|p| (0..p.len()).collect()).collect();
    let targets: Vec<[f64; 4]> = hand.iter().map(|h| h.hand).collect();
    let chi2 = curve(&all, &targets);
    let (nu, at_edge, chi2_min) = refine(&opts.grid, &chi2);
    let terms = used.iter().filter(|&&u| u).count() * hand.len();
    let dof = terms.saturating_sub(1).max(1);
    let scale = (chi2_min / dof as f64).max(1.0);
    let (lo, hi) = crossing_interval(&opts.grid, &chi2, chi2_min + scale);
    let interval = (lo.min(nu), hi.max(nu));
    let mut chi2_by_statistic = [0.0; 4];
    for ((h, se), pop) in hand.iter().zip(&se_hand).zip(pops) {
        let m = Moments::of_counts(&pop.iter().map(|c| c.at(nu)).collect::<Vec<_>>());
        for (acc, t) in chi2_by_statistic.iter_mut().zip(chi2_terms(&h.hand, se, &m)) {
            *acc += t;
        }
    }
    let bootstrap: Vec<f64> = (0..opts.bootstrap as u64)
        .into_par_iter()
        .map(|b| {
            let mut rng = item_rng(opts.seed ^ 0xb007_5742, b);
            let picks: Vec<Vec<usize>> =
                pops.iter().map(|p| (0..p.len()).map(|_| rng.random_range(0..p.len().max(1))).collect()).collect();
            let t: Vec<[f64; 4]> = hand
                .iter()
                .zip(&se_hand)
                .map(|(h, se)| {
                    let mut z = || rng.sample::<f64, _>(StandardNormal);
                    [
                        h.hand[0] + z() * se[0],
                        h.hand[1] + z() * se[1],
                        (h.hand[2] + z() * se[2]).max(0.0),
                        (h.hand[3] + z() * se[3]).max(0.0),
                    ]
                })
                .collect();
            refine(&opts.grid, &curve(&picks, &t)).0
        })
        .collect();
    let (bootstrap_interval, bootstrap_sd_log10) = if bootstrap.is_empty() {
        ((f64::NAN, f64::NAN), f64::NAN)
    } else {
        let mut sorted = bootstrap.clone();
        sorted.sort_by(|a, b| a.total_cmp(b));
        let q = |p: f64| sorted[((p * (sorted.len() - 1) as f64).round() as usize).min(sorted.len() - 1)];
        ((q(0.16), q(0.84)), sample_sd(&bootstrap.iter().map(|x| x.log10()).collect::<Vec<_>>()))
    };
    Ok(NuFit {
        grid: opts.grid.clone(),
        chi2,
        nu,
        chi2_min,
        terms,
        dof,
        at_edge,
        scale,
        interval,
        chi2_by_statistic,
        bootstrap,
        bootstrap_interval,
        bootstrap_sd_log10,
    })
}

/// The minimum of a loss on a grid, refined by the parabola in log ν through the lowest point
/// and its two neighbours: (ν, at an end of the grid, loss there).
fn refine(grid: &[f64], loss: &[f64]) -> (f64, bool, f64) {
    let i = (0..loss.len()).min_by(|&a, &b| loss[a].total_cmp(&loss[b])).unwrap_or(0);
    if i == 0 || i + 1 == loss.len() {
        return (grid[i], true, loss[i]);
    }
    let (x0, x1, x2) = (grid[i - 1].ln(), grid[i].ln(), grid[i + 1].ln());
    let (y0, y1, y2) = (loss[i - 1], loss[i], loss[i + 1]);
    let denom = (x0 - x1) * (x0 - x2) * (x1 - x2);
    let a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / denom;
    let b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / denom;
    if !(a > 0.0) {
        return (grid[i], false, loss[i]);
    }
    let x = (-b / (2.0 * a)).clamp(x0, x2);
    let c = y1 - a * x1 * x1 - b * x1;
    (x.exp(), false, (a * x * x + b * x + c).min(y1))
}

/// The range of ν around the minimum where the loss stays ≤ `level` (grid ends if never
/// crossed).
fn crossing_interval(grid: &[f64], loss: &[f64], level: f64) -> (f64, f64) {
    let i = (0..loss.len()).min_by(|&a, &b| loss[a].total_cmp(&loss[b])).unwrap_or(0);
    let cross = |j: usize, k: usize| {
        // loss[j] ≤ level < loss[k]: interpolate in log ν
        let t = ((level - loss[j]) / (loss[k] - loss[j])).clamp(0.0, 1.0);
        (grid[j].ln() + t * (grid[k].ln() - grid[j].ln())).exp()
    };
    let mut lo = grid[0];
    for j in (1..=i).rev() {
        if loss[j - 1] > level {
            lo = cross(j, j - 1);
            break;
        }
    }
    let mut hi = grid[grid.len() - 1];
    for j in i..grid.len() - 1 {
        if loss[j + 1] > level {
            hi = cross(j, j + 1);
            break;
        }
    }
    (lo, hi)
}

/// The count curves of the pebbles of a study, grouped by sample name.
pub fn curves_by_sample(study: &Study) -> BTreeMap<String, Vec<CountCurve>> {
    let mut out: BTreeMap<String, Vec<CountCurve>> = BTreeMap::new();
    for p in &study.pebbles {
        if let Ok(c) = &p.result {
            out.entry(p.sample.clone()).or_default().push(c.curve.clone());
        }
    }
    out
}

/// Generate the synthetic populations of `hand` with `params` and fit ν. Returns the fit and the
/// study (to read the synthetic statistics at any ν).
pub fn fit_table2(hand: &[HandSample], params: &PopulationParams, opts: &FitOptions) -> Result<(NuFit, Study)> {
    let targets: Vec<SampleTarget> = hand.iter().map(|h| h.target()).collect();
    let study = synthetic_study(&targets, params, PAPER_NU, None)?;
    let by = curves_by_sample(&study);
    let pops: Vec<Vec<CountCurve>> = hand.iter().map(|h| by.get(&h.id).cloned().unwrap_or_default()).collect();
    Ok((fit_nu(hand, &pops, opts)?, study))
}

/// Moments of every sample of a study at `nu`, by sample name.
pub fn moments_at(study: &Study, nu: f64) -> BTreeMap<String, Moments> {
    curves_by_sample(study)
        .into_iter()
        .map(|(k, curves)| (k, Moments::of_counts(&curves.iter().map(|c| c.at(nu)).collect::<Vec<_>>())))
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Plots
// ---------------------------------------------------------------------------------------------

/// Draw into a PNG or an SVG (by the extension of `path`) of the given size.
macro_rules! render {
    ($path:expr, $size:expr, |$root:ident| $body:expr) => {{
        init_fonts();
        let path: &Path = $path;
        if path.extension().is_some_and(|e| e == "svg") {
            let $root = SVGBackend::new(path, $size).into_drawing_area();
            $body?;
            $root.present().map_err(|e| anyhow::anyhow!("{}: {e:?}", path.display()))?;
        } else {
            let $root = BitMapBackend::new(path, $size).into_drawing_area();
            $body?;
            $root.present().map_err(|e| anyhow::anyhow!("{}: {e:?}", path.display()))?;
        }
        anyhow::Ok(())
    }};
}

fn perr<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow::anyhow!("plot: {e:?}")
}

/// The {S, U} class of a pebble at ν, as in the paper's classification (Domokos et al. 2010).
pub fn class_label(c: Counts) -> String {
    format!("{{{},{}}}", c.stable, c.unstable)
}

/// Classes with their own colour in [`plot_zingg`]; the rarer ones are grey.
pub const ZINGG_CLASSES: usize = 9;

/// Zingg diagram (x = b/a, y = c/b, class boundaries at 2/3) of the study, each pebble coloured
/// by its macro class {S, U} at the study's ν (the [`ZINGG_CLASSES`] most frequent classes; the
/// others grey).
pub fn plot_zingg(study: &Study, title: &str, path: &Path) -> anyhow::Result<()> {
    let mut classes: BTreeMap<(usize, usize), Vec<(f64, f64)>> = BTreeMap::new();
    for p in &study.pebbles {
        if let Ok(c) = &p.result {
            let k = c.curve.at(study.nu);
            classes.entry((k.stable, k.unstable)).or_default().push((c.report.shape.b_over_a, c.report.shape.c_over_b));
        }
    }
    render!(path, (760, 720), |root| draw_zingg(&root, title, study.nu, &classes))
}

fn draw_zingg<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    nu: f64,
    classes: &BTreeMap<(usize, usize), Vec<(f64, f64)>>,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(perr)?;
    let mut chart = ChartBuilder::on(root)
        .caption(format!("{title} (class {{S,U}} at ν = {nu:.2e})"), (FONT_FAMILY, 18))
        .margin(14)
        .x_label_area_size(45)
        .y_label_area_size(55)
        .build_cartesian_2d(0f64..1.0, 0f64..1.0)
        .map_err(perr)?;
    chart
        .configure_mesh()
        .x_desc("b/a")
        .y_desc("c/b")
        .label_style((FONT_FAMILY, 14))
        .light_line_style(WHITE)
        .draw()
        .map_err(perr)?;
    let t = crate::shape::ZINGG_THRESHOLD;
    for line in [vec![(t, 0.0), (t, 1.0)], vec![(0.0, t), (1.0, t)]] {
        chart.draw_series(LineSeries::new(line, BLACK.mix(0.6).stroke_width(1))).map_err(perr)?;
    }
    // The most frequent classes get their own colour, the rest one grey "other" series.
    let mut by_count: Vec<((usize, usize), usize)> = classes.iter().map(|(k, v)| (*k, v.len())).collect();
    by_count.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let shown: BTreeSet<(usize, usize)> = by_count.iter().take(ZINGG_CLASSES).map(|(k, _)| *k).collect();
    let other: Vec<(f64, f64)> =
        classes.iter().filter(|(k, _)| !shown.contains(k)).flat_map(|(_, v)| v.iter().copied()).collect();
    if !other.is_empty() {
        let grey = RGBColor(150, 150, 150);
        let n_other = classes.len() - shown.len();
        chart
            .draw_series(other.iter().map(|&(x, y)| Circle::new((x, y), 3, grey.filled())))
            .map_err(perr)?
            .label(format!("{n_other} other classes (n = {})", other.len()))
            .legend(move |(x, y)| Circle::new((x + 6, y), 3, grey.filled()));
    }
    for (k, ((s, u), pts)) in classes.iter().filter(|(k, _)| shown.contains(k)).enumerate() {
        let color = Palette99::pick(k).to_rgba();
        chart
            .draw_series(pts.iter().map(|&(x, y)| Circle::new((x, y), 4, color.filled())))
            .map_err(perr)?
            .label(format!("{} (n = {})", class_label(Counts { stable: *s, unstable: *u, saddle: 0 }), pts.len()))
            .legend(move |(x, y)| Circle::new((x + 6, y), 4, color.filled()));
    }
    for (z, (x, y)) in [
        (Zingg::Rod, (0.02, 0.99)),
        (Zingg::Spheroid, (t + 0.01, 0.99)),
        (Zingg::Blade, (0.02, t - 0.01)),
        (Zingg::Disc, (t + 0.01, t - 0.01)),
    ] {
        chart.draw_series(std::iter::once(Text::new(z.name(), (x, y), (FONT_FAMILY, 15)))).map_err(perr)?;
    }
    chart
        .configure_series_labels()
        .label_font((FONT_FAMILY, 13))
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerLeft)
        .draw()
        .map_err(perr)?;
    Ok(())
}

/// One series of a scatter plot.
#[derive(Clone, Debug)]
pub struct Series {
    pub label: String,
    pub color: RGBColor,
    /// Filled or hollow markers.
    pub filled: bool,
    pub points: Vec<(f64, f64)>,
    /// Draw this trend line (its equation and R² go into the legend).
    pub trend: Option<LogFit>,
}

/// A scatter plot of `series` with their logarithmic trend lines; `diagonal` adds y = x.
pub fn scatter_plot(
    path: &Path,
    title: &str,
    labels: (&str, &str),
    series: &[Series],
    diagonal: bool,
) -> anyhow::Result<()> {
    render!(path, (980, 640), |root| draw_scatter(&root, title, labels, series, diagonal))
}

fn draw_scatter<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    labels: (&str, &str),
    series: &[Series],
    diagonal: bool,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(perr)?;
    let pts = || series.iter().flat_map(|s| s.points.iter()).filter(|p| p.0.is_finite() && p.1.is_finite());
    let (mut x0, mut x1) = pts().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (mut y0, mut y1) = pts().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.1), b.max(p.1)));
    if !x0.is_finite() {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    if diagonal {
        (x0, y0) = (x0.min(y0), x0.min(y0));
        (x1, y1) = (x1.max(y1), x1.max(y1));
    }
    let (dx, dy) = ((x1 - x0).max(1e-3) * 0.08, (y1 - y0).max(1e-3) * 0.1);
    let (x0, x1, y0, y1) = (x0 - dx, x1 + dx, y0 - dy, y1 + dy);
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT_FAMILY, 19))
        .margin(14)
        .x_label_area_size(45)
        .y_label_area_size(55)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(perr)?;
    chart.configure_mesh().x_desc(labels.0).y_desc(labels.1).label_style((FONT_FAMILY, 14)).draw().map_err(perr)?;
    if diagonal {
        chart
            .draw_series(LineSeries::new(vec![(x0, x0), (x1, x1)], BLACK.mix(0.5)))
            .map_err(perr)?
            .label("y = x")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK.mix(0.5)));
    }
    for s in series {
        let color = s.color;
        let style = if s.filled { color.filled() } else { color.stroke_width(2) };
        let good = s.points.iter().filter(|p| p.0.is_finite() && p.1.is_finite());
        chart
            .draw_series(good.map(|&(x, y)| Circle::new((x, y), 4, style)))
            .map_err(perr)?
            .label(s.label.clone())
            .legend(move |(x, y)| Circle::new((x + 6, y), 4, style));
        if let Some(t) = s.trend {
            let (lo, hi) = s.points.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| (a.min(p.0), b.max(p.0)));
            if lo > 0.0 && hi > lo {
                let line: Vec<(f64, f64)> =
                    (0..=60).map(|k| lo + (hi - lo) * k as f64 / 60.0).map(|x| (x, t.eval(x))).collect();
                chart
                    .draw_series(LineSeries::new(line, color.stroke_width(2)))
                    .map_err(perr)?
                    .label(format!("  {}", t.describe()))
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2)));
            }
        }
    }
    chart
        .configure_series_labels()
        .label_font((FONT_FAMILY, 12))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .map_err(perr)?;
    Ok(())
}

/// χ²(ν) curves (log ν axis, log χ² axis) with the fitted ν of each and the paper's 0.0035.
pub fn plot_loss(path: &Path, title: &str, fits: &[(String, &NuFit)]) -> anyhow::Result<()> {
    render!(path, (980, 620), |root| draw_loss(&root, title, fits))
}

fn draw_loss<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    fits: &[(String, &NuFit)],
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(perr)?;
    let xs = || fits.iter().flat_map(|f| f.1.grid.iter().copied());
    let ys = || fits.iter().flat_map(|f| f.1.chi2.iter().copied()).filter(|y| *y > 0.0 && y.is_finite());
    let (x0, x1) = (xs().fold(f64::INFINITY, f64::min), xs().fold(0.0, f64::max));
    let (y0, y1) = (ys().fold(f64::INFINITY, f64::min).max(1e-3), ys().fold(0.0, f64::max).max(1.0));
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT_FAMILY, 19))
        .margin(14)
        .x_label_area_size(45)
        .y_label_area_size(65)
        .build_cartesian_2d((x0..x1).log_scale(), (y0 / 1.5..y1 * 1.5).log_scale())
        .map_err(perr)?;
    chart
        .configure_mesh()
        .x_desc("ν (log scale)")
        .y_desc("χ² (log scale)")
        .label_style((FONT_FAMILY, 14))
        .draw()
        .map_err(perr)?;
    chart
        .draw_series(LineSeries::new(vec![(PAPER_NU, y0 / 1.5), (PAPER_NU, y1 * 1.5)], BLACK.stroke_width(1)))
        .map_err(perr)?
        .label("paper: ν = 0.0035")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK));
    for (k, (label, f)) in fits.iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        let pts: Vec<(f64, f64)> = f.grid.iter().zip(&f.chi2).map(|(x, y)| (*x, y.max(y0))).collect();
        chart
            .draw_series(LineSeries::new(pts, color.stroke_width(2)))
            .map_err(perr)?
            .label(format!("{label}: ν = {:.2e}", f.nu))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2)));
        chart.draw_series(std::iter::once(Circle::new((f.nu, f.chi2_min.max(y0)), 5, color.filled()))).map_err(perr)?;
    }
    chart
        .configure_series_labels()
        .label_font((FONT_FAMILY, 12))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(perr)?;
    Ok(())
}

/// Colours of the Figure 12 plots: hand (purple, yellow as in the paper) and computed (red, blue).
pub const HAND_S: RGBColor = RGBColor(128, 60, 160);
pub const HAND_U: RGBColor = RGBColor(215, 170, 0);
pub const COMPUTED_S: RGBColor = RGBColor(210, 40, 40);
pub const COMPUTED_U: RGBColor = RGBColor(40, 90, 210);

/// One row of a hand-vs-computed comparison.
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    pub id: String,
    /// Mean ratios: Table 2's (hand) and the synthetic pebbles' measured ones.
    pub hand_c_over_b: f64,
    pub hand_c_over_a: f64,
    pub sim_c_over_b: f64,
    pub sim_c_over_a: f64,
    pub hand: [f64; 4],
    pub sim: Moments,
    /// The paper's computer experiments (5 scanned samples).
    pub paper_computer: Option<[f64; 4]>,
}

/// Hand vs synthetic statistics at `nu` for every Table 2 sample present in the study.
pub fn compare(hand: &[HandSample], study: &Study, nu: f64) -> Vec<Comparison> {
    let sims = moments_at(study, nu);
    let summaries = summarize(study);
    hand.iter()
        .filter_map(|h| {
            let sim = *sims.get(&h.id)?;
            let s = summaries.iter().find(|s| s.sample == h.id)?;
            Some(Comparison {
                id: h.id.clone(),
                hand_c_over_b: h.c_over_b,
                hand_c_over_a: h.c_over_a,
                sim_c_over_b: s.mean_c_over_b,
                sim_c_over_a: s.mean_c_over_a,
                hand: h.hand,
                sim,
                paper_computer: h.computer,
            })
        })
        .collect()
}

/// Write a comparison as CSV.
pub fn write_comparison_csv<W: std::io::Write>(rows: &[Comparison], nu: f64, w: W) -> anyhow::Result<()> {
    let mut out = csv::Writer::from_writer(w);
    out.write_record([
        "id",
        "nu",
        "hand_c_over_b",
        "hand_c_over_a",
        "sim_c_over_b",
        "sim_c_over_a",
        "hand_E_S",
        "hand_E_U",
        "hand_sd_S",
        "hand_sd_U",
        "sim_E_S",
        "sim_E_U",
        "sim_sd_S",
        "sim_sd_U",
        "sim_n",
        "paper_E_S",
        "paper_E_U",
        "paper_sd_S",
        "paper_sd_U",
    ])?;
    for r in rows {
        let mut row = vec![r.id.clone(), format!("{nu:e}")];
        row.extend([r.hand_c_over_b, r.hand_c_over_a, r.sim_c_over_b, r.sim_c_over_a].map(cell));
        row.extend(r.hand.map(cell));
        row.extend(r.sim.as_array().map(cell));
        row.push(r.sim.n.to_string());
        row.extend(r.paper_computer.map_or([f64::NAN; 4], |p| p).map(cell));
        out.write_record(row)?;
    }
    out.flush()?;
    Ok(())
}

/// The trend lines of Figure 12 for hand and computed statistics.
#[derive(Clone, Debug, Serialize)]
pub struct Trends {
    /// E(S) against c/b and c/a (Figure 12A), hand and computed.
    pub hand_es_cb: Option<LogFit>,
    pub hand_es_ca: Option<LogFit>,
    pub sim_es_cb: Option<LogFit>,
    pub sim_es_ca: Option<LogFit>,
    pub hand_eu_cb: Option<LogFit>,
    pub hand_eu_ca: Option<LogFit>,
    pub sim_eu_cb: Option<LogFit>,
    pub sim_eu_ca: Option<LogFit>,
    /// σ against E (Figure 12B).
    pub hand_sd_s: Option<LogFit>,
    pub hand_sd_u: Option<LogFit>,
    pub sim_sd_s: Option<LogFit>,
    pub sim_sd_u: Option<LogFit>,
}

/// Fit the logarithmic trends of a comparison (computed against the synthetic pebbles' measured
/// ratios).
pub fn trends(rows: &[Comparison]) -> Trends {
    let f = |g: &dyn Fn(&Comparison) -> (f64, f64)| log_fit(&rows.iter().map(g).collect::<Vec<_>>());
    Trends {
        hand_es_cb: f(&|r| (r.hand_c_over_b, r.hand[0])),
        hand_es_ca: f(&|r| (r.hand_c_over_a, r.hand[0])),
        sim_es_cb: f(&|r| (r.sim_c_over_b, r.sim.es)),
        sim_es_ca: f(&|r| (r.sim_c_over_a, r.sim.es)),
        hand_eu_cb: f(&|r| (r.hand_c_over_b, r.hand[1])),
        hand_eu_ca: f(&|r| (r.hand_c_over_a, r.hand[1])),
        sim_eu_cb: f(&|r| (r.sim_c_over_b, r.sim.eu)),
        sim_eu_ca: f(&|r| (r.sim_c_over_a, r.sim.eu)),
        hand_sd_s: f(&|r| (r.hand[0], r.hand[2])),
        hand_sd_u: f(&|r| (r.hand[1], r.hand[3])),
        sim_sd_s: f(&|r| (r.sim.es, r.sim.sd_s)),
        sim_sd_u: f(&|r| (r.sim.eu, r.sim.sd_u)),
    }
}

/// Write the Figure 12 plots of a comparison into `dir`: `fig12a_S.png/.svg` (E(S) against c/b
/// and c/a), `fig12a_U.png/.svg` (E(U)), `fig12b.png/.svg` (σ against E) and
/// `hand_vs_computed.png/.svg` (each statistic, computed against hand, with y = x). Returns the
/// files written.
pub fn plot_fig12(rows: &[Comparison], nu: f64, label: &str, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| anyhow::anyhow!("{}: cannot create folder: {e}", dir.display()))?;
    let t = trends(rows);
    let pts = |g: &dyn Fn(&Comparison) -> (f64, f64)| rows.iter().map(g).collect::<Vec<_>>();
    let ser = |label: &str, color: RGBColor, filled: bool, points: Vec<(f64, f64)>, trend: Option<LogFit>| Series {
        label: label.to_string(),
        color,
        filled,
        points,
        trend,
    };
    let light = |c: RGBColor| {
        RGBColor(((c.0 as u16 + 255) / 2) as u8, ((c.1 as u16 + 255) / 2) as u8, ((c.2 as u16 + 255) / 2) as u8)
    };
    let mut written = Vec::new();
    for (which, k, hc, sc) in [("S", 0usize, HAND_S, COMPUTED_S), ("U", 1, HAND_U, COMPUTED_U)] {
        let (h_cb, h_ca, s_cb, s_ca) = if k == 0 {
            (t.hand_es_cb, t.hand_es_ca, t.sim_es_cb, t.sim_es_ca)
        } else {
            (t.hand_eu_cb, t.hand_eu_ca, t.sim_eu_cb, t.sim_eu_ca)
        };
        let series = vec![
            ser(&format!("hand E({which}) vs c/b"), hc, true, pts(&|r| (r.hand_c_over_b, r.hand[k])), h_cb),
            ser(&format!("hand E({which}) vs c/a"), light(hc), true, pts(&|r| (r.hand_c_over_a, r.hand[k])), h_ca),
            ser(
                &format!("{label} E({which}) vs c/b"),
                sc,
                false,
                pts(&|r| (r.sim_c_over_b, r.sim.as_array()[k])),
                s_cb,
            ),
            ser(
                &format!("{label} E({which}) vs c/a"),
                light(sc),
                false,
                pts(&|r| (r.sim_c_over_a, r.sim.as_array()[k])),
                s_ca,
            ),
        ];
        for ext in ["png", "svg"] {
            let p = dir.join(format!("fig12a_{which}.{ext}"));
            scatter_plot(
                &p,
                &format!("Fig. 12A: E({which}) against flatness, hand vs {label} (ν = {nu:.2e})"),
                ("axis ratio (c/b, c/a)", &format!("E({which})")),
                &series,
                false,
            )?;
            written.push(p);
        }
    }
    let series = vec![
        ser("hand σ(S) vs E(S)", HAND_S, true, pts(&|r| (r.hand[0], r.hand[2])), t.hand_sd_s),
        ser("hand σ(U) vs E(U)", HAND_U, true, pts(&|r| (r.hand[1], r.hand[3])), t.hand_sd_u),
        ser(&format!("{label} σ(S) vs E(S)"), COMPUTED_S, false, pts(&|r| (r.sim.es, r.sim.sd_s)), t.sim_sd_s),
        ser(&format!("{label} σ(U) vs E(U)"), COMPUTED_U, false, pts(&|r| (r.sim.eu, r.sim.sd_u)), t.sim_sd_u),
    ];
    for ext in ["png", "svg"] {
        let p = dir.join(format!("fig12b.{ext}"));
        scatter_plot(
            &p,
            &format!("Fig. 12B: standard deviation against mean, hand vs {label} (ν = {nu:.2e})"),
            ("E", "σ (sample, n − 1)"),
            &series,
            false,
        )?;
        written.push(p);
    }
    let names = ["E(S)", "E(U)", "σ(S)", "σ(U)"];
    let colors = [COMPUTED_S, COMPUTED_U, HAND_S, HAND_U];
    let series: Vec<Series> =
        (0..4).map(|k| ser(names[k], colors[k], k < 2, pts(&|r| (r.hand[k], r.sim.as_array()[k])), None)).collect();
    for ext in ["png", "svg"] {
        let p = dir.join(format!("hand_vs_computed.{ext}"));
        scatter_plot(
            &p,
            &format!("Table 2 samples: {label} (ν = {nu:.2e}) against hand"),
            ("hand experiment", label),
            &series,
            true,
        )?;
        written.push(p);
    }
    Ok(written)
}
