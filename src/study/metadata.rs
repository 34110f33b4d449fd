//! The metadata CSV of a field study: one row per pebble (id, sample, free columns), joined on
//! the pebble id; delimiter detection and readable errors.

use crate::{Error, Result};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

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
    /// The metadata file.
    pub path: PathBuf,
    /// Field delimiter detected in the file (`,` `;` or tab).
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

pub(super) fn describe_csv_error(e: &csv::Error) -> String {
    match e.kind() {
        csv::ErrorKind::UnequalLengths { pos, expected_len, len } => {
            format!("line {}: {len} fields where the header has {expected_len}", pos.as_ref().map_or(0, |p| p.line()))
        }
        _ => e.to_string(),
    }
}
