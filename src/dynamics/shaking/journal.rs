//! The journal of a batch of records × scale factors on a field rock: every finished run is
//! appended to a JSON-lines file as it comes and flushed, so that a batch that is killed loses no
//! finished run, and `resume` continues it. The first line is the batch's [`JournalHeader`];
//! every other line one [`RecordRun`]. A last line cut off by a kill is dropped and its run done
//! again.

use crate::dynamics::shaking::ensemble::EnsembleSpec;
use crate::dynamics::shaking::records::RecordRun;
use crate::dynamics::shaking::rock::RockSetup;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Format tag of the first line of a batch journal.
pub const JOURNAL_FORMAT: &str = "rocking-shake-runs/1";

/// What identifies a batch: the mesh, the rock's setup and the ensemble. A journal continues only
/// the batch of its own header (records and scale factors may be added).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JournalHeader {
    /// [`JOURNAL_FORMAT`].
    pub format: String,
    /// The mesh: its path and a hash of its bytes, or the bundled stone.
    pub mesh: String,
    /// The rock, its pose, size, contact and azimuth.
    pub setup: RockSetup,
    /// The ensemble run for every record × scale factor, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ensemble: Option<EnsembleSpec>,
}

impl JournalHeader {
    /// The header of a batch on `mesh` with `setup` and `ensemble`.
    pub fn new(mesh: impl Into<String>, setup: &RockSetup, ensemble: Option<&EnsembleSpec>) -> Self {
        JournalHeader {
            format: JOURNAL_FORMAT.into(),
            mesh: mesh.into(),
            setup: setup.clone(),
            ensemble: ensemble.cloned(),
        }
    }
}

/// An open journal, appended to as runs finish.
pub struct Journal {
    file: std::fs::File,
}

impl Journal {
    /// Open the journal `path` of the batch `header`: a new file gets the header; with `resume`
    /// an existing one must be of the same batch and its finished runs are returned (a last line
    /// cut off by a kill is dropped); without `resume` an existing journal is refused (it would be
    /// overwritten).
    pub fn open(path: &Path, header: &JournalHeader, resume: bool) -> Result<(Journal, Vec<RecordRun>)> {
        let io = |error: std::io::Error| Error::Io { path: path.into(), error };
        if !resume && path.exists() {
            return Err(Error::parameter(
                "resume",
                "not set",
                format!("set to continue the batch journal {}, which exists (or remove it)", path.display()),
            ));
        }
        let (runs, valid) = if resume { read_journal(path, header)? } else { (Vec::new(), 0) };
        let mut file = std::fs::OpenOptions::new().create(true).append(true).open(path).map_err(io)?;
        file.set_len(valid).map_err(io)?;
        if valid == 0 {
            // Written as a JSON value (keys sorted), as every journal has been.
            let line =
                serde_json::to_value(header).and_then(|v| serde_json::to_string(&v)).map_err(|e| io(e.into()))?;
            writeln!(file, "{line}").map_err(io)?;
        }
        Ok((Journal { file }, runs))
    }

    /// Append one finished run (flushed at once).
    pub fn record(&mut self, run: &RecordRun) -> std::io::Result<()> {
        let line = serde_json::to_string(run).map_err(std::io::Error::other)?;
        writeln!(self.file, "{line}")?;
        self.file.flush()
    }
}

/// The runs of the journal `path` after checking that its header is `header`'s, and the length in
/// bytes of its complete lines. A missing or empty file holds nothing.
fn read_journal(path: &Path, header: &JournalHeader) -> Result<(Vec<RecordRun>, u64)> {
    let parse = |what: String| Error::Parse { path: PathBuf::from(path), what };
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok((Vec::new(), 0)),
        Err(error) => return Err(Error::Io { path: path.into(), error }),
    };
    let Some(first) = text.split_inclusive('\n').next().filter(|l| l.ends_with('\n')) else {
        return Ok((Vec::new(), 0));
    };
    let found: JournalHeader =
        serde_json::from_str(first).map_err(|e| parse(format!("line 1 is not a batch journal header: {e}")))?;
    if &found != header {
        return Err(parse(
            "this journal is of another batch (its mesh, pose, size, surface, azimuth, ensemble or simulation \
             parameters differ); use another output folder"
                .into(),
        ));
    }
    let (mut runs, mut valid) = (Vec::new(), first.len() as u64);
    for (k, line) in text.split_inclusive('\n').enumerate().skip(1) {
        if !line.ends_with('\n') {
            break; // the last line, cut off while it was being written (a kill): run it again
        }
        let run = serde_json::from_str::<RecordRun>(line)
            .map_err(|e| parse(format!("line {}: not a finished run: {e}", k + 1)))?;
        runs.push(run);
        valid += line.len() as u64;
    }
    Ok((runs, valid))
}
