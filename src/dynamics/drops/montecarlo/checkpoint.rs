//! Checkpoints: every finished drop appended to a JSON-lines file as the run goes, read back to
//! resume ([`Checkpoint`], [`read_partial`]), checked against the stone ([`check_outcomes`]), and
//! shards merged into one run ([`merge`]).

use crate::dynamics::drops::launch::DropOutcome;
use crate::dynamics::drops::montecarlo::header::{RunHeader, Shard, FORMAT};
use crate::dynamics::engine::params::REFERENCE_DT;
use crate::dynamics::stone::StaticModel;
use crate::{Error, Result};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

/// What to say when a checkpoint's time step is not this run's: drops written before the default
/// step became the presets' longest stable one (1/120 s) ran at [`REFERENCE_DT`].
fn step_hint(checkpoint_dt: f64, run_dt: f64) -> String {
    if checkpoint_dt == run_dt {
        return String::new();
    }
    let reference = if checkpoint_dt == REFERENCE_DT {
        " (1/240 s: the reference step, the default before the drop presets took their longest stable step 1/120 s)"
    } else {
        ""
    };
    format!("; to resume it, run at its time step dt = {checkpoint_dt} s{reference}")
}

/// Append-only JSON-lines checkpoint of a run.
pub struct Checkpoint {
    file: std::io::BufWriter<std::fs::File>,
}

impl Checkpoint {
    /// Open `path` for a run with `header`. A new file gets the header; an existing file is
    /// read back (when `resume`) and must have the same header; without `resume` an existing
    /// file is an error (it would be overwritten).
    pub fn open(path: &Path, header: &RunHeader, resume: bool) -> Result<(Checkpoint, BTreeMap<u64, DropOutcome>)> {
        let io = |e: std::io::Error| Error::Io { path: path.into(), error: e };
        let mut done = BTreeMap::new();
        if path.exists() {
            if !resume {
                return Err(Error::parameter(
                    "resume",
                    "not set",
                    format!("set to continue the checkpoint {}, which exists (or remove that file)", path.display()),
                ));
            }
            let (h, outcomes) = read_partial(path)?;
            let mut differ = header.differences(&h);
            if h.shard != header.shard {
                differ.push(format!(
                    "shard ({}/{} vs {}/{})",
                    header.shard.index, header.shard.count, h.shard.index, h.shard.count
                ));
            }
            if !differ.is_empty() {
                return Err(Error::Checkpoint(format!(
                    "{}: this checkpoint belongs to a different run; it differs in {}{}",
                    path.display(),
                    differ.join(", "),
                    step_hint(h.params.sim.numerics.dt, header.params.sim.numerics.dt)
                )));
            }
            done = outcomes;
            // Cut a line left half-written by an interrupted run before appending to the file.
            let bytes = std::fs::read(path).map_err(io)?;
            let complete = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
            let file = std::fs::OpenOptions::new().write(true).open(path).map_err(io)?;
            file.set_len(complete as u64).map_err(io)?;
            let file = std::fs::OpenOptions::new().append(true).open(path).map_err(io)?;
            return Ok((Checkpoint { file: std::io::BufWriter::new(file) }, done));
        }
        let file = std::fs::File::create(path).map_err(io)?;
        let mut c = Checkpoint { file: std::io::BufWriter::new(file) };
        c.write_line(&serde_json::to_string(header).expect("header serialises")).map_err(io)?;
        Ok((c, done))
    }

    fn write_line(&mut self, line: &str) -> std::io::Result<()> {
        self.file.write_all(line.as_bytes())?;
        self.file.write_all(b"\n")?;
        self.file.flush()
    }

    /// Record one finished drop (flushed at once).
    pub fn record(&mut self, o: &DropOutcome) -> std::io::Result<()> {
        self.write_line(&serde_json::to_string(o).expect("outcome serialises"))
    }
}

/// Read a partial result (checkpoint file): its header and outcomes by index. A truncated last
/// line (an interrupted write) is ignored. Every line is checked against the header before it
/// counts: valid UTF-8 and JSON, a drop index below the run's drop count, in the file's shard, and
/// not seen before; a failure names the file, the line and the field. Facet and flock indices are
/// checked against the stone by [`check_outcomes`].
pub fn read_partial(path: &Path) -> Result<(RunHeader, BTreeMap<u64, DropOutcome>)> {
    let io = |e: std::io::Error| Error::Io { path: path.into(), error: e };
    let parse = |what: String| Error::Parse { path: path.into(), what };
    let bytes = std::fs::read(path).map_err(io)?;
    let mut lines: Vec<&[u8]> = bytes.split(|&b| b == b'\n').collect();
    if lines.last().is_some_and(|l| l.is_empty()) {
        lines.pop();
    }
    let text = |k: usize, l: &[u8]| -> Result<String> {
        String::from_utf8(l.to_vec()).map_err(|e| parse(format!("line {}: not UTF-8 text ({e})", k + 1)))
    };
    let first = lines.first().ok_or_else(|| parse("empty file: not a drop result".into()))?;
    let header: RunHeader =
        serde_json::from_str(&text(0, first)?).map_err(|e| parse(format!("line 1 is not a drop-run header: {e}")))?;
    if header.format != FORMAT {
        return Err(parse(format!("unknown format {:?} (expected {FORMAT:?})", header.format)));
    }
    if header.shard.count == 0 || header.shard.index >= header.shard.count {
        return Err(parse(format!(
            "line 1: field shard: {}/{} is not a shard",
            header.shard.index, header.shard.count
        )));
    }
    let mut outcomes = BTreeMap::new();
    let mut seen: BTreeMap<u64, usize> = BTreeMap::new();
    let last = lines.len();
    for (k, raw) in lines.iter().enumerate().skip(1) {
        let line = k + 1;
        let o = match String::from_utf8(raw.to_vec()).ok().and_then(|t| serde_json::from_str::<DropOutcome>(&t).ok()) {
            Some(o) => o,
            None if k + 1 == last => break, // interrupted while writing the last line
            None => {
                let t = text(k, raw)?;
                let e = serde_json::from_str::<DropOutcome>(&t).err().map_or(String::new(), |e| e.to_string());
                return Err(parse(format!("line {line}: not a drop outcome: {e}")));
            }
        };
        if o.index >= header.drops {
            return Err(parse(format!(
                "line {line}: field index: drop {} is beyond the run's {} drops",
                o.index, header.drops
            )));
        }
        if !header.shard.holds(o.index) {
            return Err(parse(format!(
                "line {line}: field index: drop {} does not belong to shard {}/{}",
                o.index, header.shard.index, header.shard.count
            )));
        }
        if let Some(prev) = seen.insert(o.index, line) {
            return Err(parse(format!("line {line}: field index: drop {} is already on line {prev}", o.index)));
        }
        if !(o.time.is_finite() && o.time >= 0.0) {
            return Err(parse(format!("line {line}: field time: {} is not a simulated time", o.time)));
        }
        outcomes.insert(o.index, o);
    }
    Ok((header, outcomes))
}

/// Check outcomes read from `path` against the stone they are summarised on: every facet a stable
/// facet of its hull, every flock one of its flocks. Errors name the file, the drop and the field.
pub fn check_outcomes(path: &Path, outcomes: &BTreeMap<u64, DropOutcome>, model: &StaticModel) -> Result<()> {
    let bad = |what: String| Err(Error::Parse { path: path.into(), what });
    for o in outcomes.values() {
        if let Some(f) = o.facet {
            match model.facet_equilibrium.get(f as usize) {
                None => {
                    return bad(format!(
                        "drop {}: field facet: {f} is beyond the hull's {} facets",
                        o.index,
                        model.facet_equilibrium.len()
                    ))
                }
                Some(None) => return bad(format!("drop {}: field facet: {f} is not a stable facet", o.index)),
                Some(Some(_)) => {}
            }
        }
        if let Some(k) = o.flock {
            if k as usize >= model.flock_kinds.len() {
                return bad(format!(
                    "drop {}: field flock: {k} is beyond the stone's {} flocks",
                    o.index,
                    model.flock_kinds.len()
                ));
            }
        }
    }
    Ok(())
}

/// Combine partial results of one run. Headers must agree; an index present twice must have
/// the same outcome.
pub fn merge(parts: &[(RunHeader, BTreeMap<u64, DropOutcome>)]) -> Result<(RunHeader, BTreeMap<u64, DropOutcome>)> {
    let (first, _) =
        parts.first().ok_or_else(|| Error::Checkpoint("nothing to merge: no partial results given".into()))?;
    let mut all = BTreeMap::new();
    for (h, outcomes) in parts {
        let differ = first.differences(h);
        if !differ.is_empty() {
            return Err(Error::Checkpoint(format!(
                "partial results of different runs cannot be merged: they differ in {}",
                differ.join(", ")
            )));
        }
        for (i, o) in outcomes {
            if let Some(prev) = all.insert(*i, *o) {
                if prev != *o {
                    return Err(Error::Checkpoint(format!(
                        "drop {i} has two different outcomes in the partial results"
                    )));
                }
            }
        }
    }
    let mut header = first.clone();
    header.shard = Shard::ALL;
    Ok((header, all))
}
