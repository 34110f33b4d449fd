//! Readers of ground-motion records: CSV with named or numbered columns, and the PEER NGA
//! `.AT2` files seismologists download (one file per component).
//!
//! Both give a [`Record`] in m/s² at a uniform interval. Errors name the file, the line and what
//! is wrong.
//!
//! # CSV
//!
//! A header line is optional; lines starting with `#` and empty lines are skipped; fields are
//! separated by commas, semicolons, tabs or spaces. [`Columns`] says which column is the time
//! (s) and which are the x, y and z accelerations, by header name or by number from 1
//! (`time_s,ax_g` or `1,2,3`). Times must increase; they are shifted to start at 0 (a rock at
//! rest before the record starts is at rest either way). Uniformly spaced times (within 1 % of
//! the median interval, as times printed with few digits are) are taken as they are; irregular
//! times are interpolated linearly onto a grid at the smallest interval.
//!
//! # Known PGVs
//!
//! [`read_known_pgv`] reads a CSV table of records whose PGV is known: a header line, a column
//! `pgv_m_s` (m/s) and a column naming the record's file, `record`, `motion` or `file` (the first
//! of these present), e.g. `record,pgv_m_s` then `quake.csv,0.31`. Only the file name is kept
//! (`motions/Test011.csv` names `Test011.csv`), the name a record read from that file has; other
//! columns are ignored. [`with_known_pgvs`] gives the records of a folder their PGVs.
//!
//! # PEER NGA `.AT2`
//!
//! Four header lines — the database, the event and station, `ACCELERATION TIME SERIES IN UNITS
//! OF G`, and `NPTS=  5590, DT=   .0050 SEC` (NGA-West2) or `5590  0.0050  NPTS, DT` (older NGA
//! files) — then the NPTS accelerations in g, several per line. Components given as several files
//! become x, y, z in that order; they are brought to the smallest of their intervals
//! ([`Record::resampled`]) and the shorter ones padded with zeros.

use super::Record;
use crate::GRAVITY as G;
use crate::{Error, Result};
use std::path::Path;
use std::str::FromStr;

/// Unit of the acceleration columns of a CSV record.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AccelUnit {
    /// Units of g ([`G`] m/s²).
    G,
    /// m/s².
    MetresPerSecond2,
    /// cm/s² (gal).
    Gal,
}

impl AccelUnit {
    /// m/s² per unit.
    pub fn to_m_s2(self) -> f64 {
        match self {
            AccelUnit::G => G,
            AccelUnit::MetresPerSecond2 => 1.0,
            AccelUnit::Gal => 0.01,
        }
    }

    /// The name the command line takes.
    pub fn name(self) -> &'static str {
        match self {
            AccelUnit::G => "g",
            AccelUnit::MetresPerSecond2 => "m/s2",
            AccelUnit::Gal => "gal",
        }
    }
}

impl FromStr for AccelUnit {
    type Err = Error;
    fn from_str(s: &str) -> Result<AccelUnit> {
        match s.trim().to_ascii_lowercase().as_str() {
            "g" => Ok(AccelUnit::G),
            "m/s2" | "m/s^2" | "m/s²" | "mps2" => Ok(AccelUnit::MetresPerSecond2),
            "gal" | "cm/s2" | "cm/s^2" | "cm/s²" => Ok(AccelUnit::Gal),
            other => Err(Error::unknown("acceleration unit", other, &["g", "m/s2", "gal (cm/s2)"])),
        }
    }
}

/// A column of a CSV file: by header name or by number (from 1).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Column {
    /// The column whose header is this name (case and surrounding spaces ignored).
    Name(String),
    /// Column number, from 1.
    Number(usize),
}

/// The columns of a CSV record: time, then one to three accelerations (x, y, z).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Columns {
    /// The time column (s).
    pub time: Column,
    /// The acceleration columns, x then y then z.
    pub accel: Vec<Column>,
}

impl Default for Columns {
    /// Column 1 is the time, column 2 the x acceleration.
    fn default() -> Columns {
        Columns { time: Column::Number(1), accel: vec![Column::Number(2)] }
    }
}

impl FromStr for Columns {
    type Err = Error;
    /// `time,ax[,ay[,az]]`: names or numbers from 1, e.g. `time_s,ax_g` or `1,3`.
    fn from_str(s: &str) -> Result<Columns> {
        let parts: Vec<Column> = s
            .split(',')
            .map(|p| {
                let p = p.trim();
                match p.parse::<usize>() {
                    Ok(0) => Err(Error::parameter("columns", s, "column names or numbers counted from 1")),
                    Ok(k) => Ok(Column::Number(k)),
                    Err(_) if p.is_empty() => {
                        Err(Error::parameter("columns", s, "names or numbers without an empty one"))
                    }
                    Err(_) => Ok(Column::Name(p.to_string())),
                }
            })
            .collect::<Result<_>>()?;
        if !(2..=4).contains(&parts.len()) {
            return Err(Error::parameter(
                "columns",
                s,
                "the time and one to three accelerations (x, y, z), e.g. time_s,ax_g or 1,2,3",
            ));
        }
        Ok(Columns { time: parts[0].clone(), accel: parts[1..].to_vec() })
    }
}

fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(|| path.display().to_string(), |f| f.to_string_lossy().into_owned())
}

fn read_text(path: &Path) -> Result<String> {
    let bytes = std::fs::read(path).map_err(|e| Error::Io { path: path.into(), error: e })?;
    String::from_utf8(bytes).map_err(|e| Error::Parse {
        path: path.into(),
        what: format!("not a text file (invalid UTF-8 at byte {})", e.utf8_error().valid_up_to()),
    })
}

/// Read a CSV record (see the module doc).
pub fn read_csv(path: &Path, columns: &Columns, unit: AccelUnit) -> Result<Record> {
    let text = read_text(path)?;
    let parse = |what: String| Error::Parse { path: path.into(), what };
    let mut header: Option<Vec<String>> = None;
    let mut index: Option<Vec<usize>> = None;
    let (mut times, mut rows): (Vec<f64>, Vec<[f64; 3]>) = (Vec::new(), Vec::new());
    for (k, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line.split([',', ';', '\t', ' ']).filter(|c| !c.is_empty()).collect();
        let numbers: Option<Vec<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        let Some(numbers) = numbers else {
            if header.is_none() && times.is_empty() {
                header = Some(fields.iter().map(|f| f.trim_matches('"').trim().to_ascii_lowercase()).collect());
                continue;
            }
            return Err(parse(format!("line {}: not all numbers: {line:?}", k + 1)));
        };
        let idx = match &index {
            Some(i) => i,
            None => index.insert(resolve(columns, header.as_deref(), fields.len()).map_err(&parse)?),
        };
        let get = |c: usize| {
            numbers
                .get(c)
                .copied()
                .ok_or_else(|| parse(format!("line {}: {} fields, column {} is missing", k + 1, numbers.len(), c + 1)))
        };
        let t = get(idx[0])?;
        let mut a = [0.0; 3];
        for (slot, &c) in a.iter_mut().zip(&idx[1..]) {
            *slot = get(c)? * unit.to_m_s2();
        }
        if !t.is_finite() || a.iter().any(|x| !x.is_finite()) {
            return Err(parse(format!("line {}: not a finite number: {line:?}", k + 1)));
        }
        if let Some(&prev) = times.last() {
            if t <= prev {
                return Err(parse(format!("line {}: time {t} s does not increase (previous {prev} s)", k + 1)));
            }
        }
        times.push(t);
        rows.push(a);
    }
    match (times.len(), &header) {
        (0, None) => return Err(parse("the file is empty: no samples (a record needs at least two)".into())),
        (0, Some(_)) => {
            return Err(parse(
                "the file has a header but no data rows: no samples (a record needs at least two)".into(),
            ))
        }
        (1, _) => return Err(parse("1 sample: a record needs at least two".into())),
        _ => {}
    }
    uniform(&file_name(path), &times, &rows).map_err(|e| parse(e.to_string()))
}

/// Positions (from 0) of the time and acceleration columns.
fn resolve(columns: &Columns, header: Option<&[String]>, fields: usize) -> std::result::Result<Vec<usize>, String> {
    std::iter::once(&columns.time)
        .chain(&columns.accel)
        .map(|c| match c {
            Column::Number(k) if *k <= fields => Ok(k - 1),
            Column::Number(k) => Err(format!("column {k} asked for, but the lines have {fields} fields")),
            Column::Name(name) => {
                let Some(h) = header else {
                    return Err(format!("column {name:?} asked for by name, but the file has no header line"));
                };
                h.iter()
                    .position(|x| x.eq_ignore_ascii_case(name.trim()))
                    .ok_or_else(|| format!("no column {name:?} in the header (columns: {})", h.join(", ")))
            }
        })
        .collect()
}

/// A record at a uniform interval from samples at increasing `times`.
fn uniform(name: &str, times: &[f64], rows: &[[f64; 3]]) -> Result<Record> {
    let mut steps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    let (median, smallest) = (steps[steps.len() / 2], steps[0]);
    if steps.iter().all(|s| (s - median).abs() <= 0.01 * median) {
        return Record::new(name, median, rows.to_vec());
    }
    let duration = times[times.len() - 1] - times[0];
    let n = (duration / smallest).floor() as usize + 1;
    if n > 20 * times.len() {
        return Err(Error::motion(
            name,
            format!(
                "times are irregular (intervals from {smallest} to {} s) and a grid at the smallest would need {n} samples; resample the record first",
                steps[steps.len() - 1]
            ),
        ));
    }
    let accel = (0..n)
        .map(|k| {
            let t = times[0] + k as f64 * smallest;
            let j = times.partition_point(|&x| x <= t).clamp(1, times.len() - 1);
            let s = ((t - times[j - 1]) / (times[j] - times[j - 1])).clamp(0.0, 1.0);
            [0, 1, 2].map(|c| rows[j - 1][c] + s * (rows[j][c] - rows[j - 1][c]))
        })
        .collect();
    Record::new(name, smallest, accel)
}

/// The known PGVs of a CSV table (see the module doc): (record file name, PGV in m/s) per row,
/// in the file's order. Refuses a table without the columns, a PGV that is not a positive
/// number, a name given twice (naming the file and the line) and a table without rows.
pub fn read_known_pgv(path: &Path) -> Result<Vec<(String, f64)>> {
    let text = read_text(path)?;
    let parse = |what: String| Error::Parse { path: path.into(), what };
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let line = |r: &csv::StringRecord| r.position().map_or(0, |p| p.line());
    let mut rows = reader.records().map(|r| r.map_err(|e| parse(e.to_string())));
    let Some(header) = rows.next().transpose()? else {
        return Err(parse("empty: a header line with `pgv_m_s` and `record` (or `motion`, `file`) is needed".into()));
    };
    let names: Vec<String> = header.iter().map(|h| h.to_ascii_lowercase()).collect();
    let find = |n: &str| names.iter().position(|h| h == n);
    let (Some(pgv_col), Some(name_col)) = (find("pgv_m_s"), ["record", "motion", "file"].iter().find_map(|n| find(n)))
    else {
        return Err(parse(format!(
            "line {}: the header needs columns `pgv_m_s` and `record` (or `motion`, `file`), has: {}",
            line(&header),
            names.join(", ")
        )));
    };
    let mut out: Vec<(String, f64)> = Vec::new();
    for row in rows {
        let row = row?;
        let k = line(&row);
        let (Some(name), Some(pgv)) = (row.get(name_col), row.get(pgv_col)) else {
            return Err(parse(format!("line {k}: {} fields, the record or the PGV is missing", row.len())));
        };
        let pgv: f64 = match pgv.parse() {
            Ok(v) if v > 0.0 && f64::is_finite(v) => v,
            _ => return Err(parse(format!("line {k}: PGV {pgv:?} is not a positive number (m/s)"))),
        };
        let name = file_name(Path::new(name));
        if out.iter().any(|(n, _)| *n == name) {
            return Err(parse(format!("line {k}: record {name:?} is given twice")));
        }
        out.push((name, pgv));
    }
    if out.is_empty() {
        return Err(parse("no rows: the table gives no PGV".into()));
    }
    Ok(out)
}

/// `records` with the PGVs of `table` ([`read_known_pgv`]) for those it names (by record name,
/// the file name); the others keep the processed PGV. Refuses a table that names none of the
/// records (a table of other records, most likely), naming `table_name`; returns how many it
/// named.
pub fn with_known_pgvs(
    records: Vec<Record>,
    table: &[(String, f64)],
    table_name: &str,
) -> Result<(Vec<Record>, usize)> {
    let mut named = 0;
    let records: Vec<Record> = records
        .into_iter()
        .map(|r| match table.iter().find(|(n, _)| *n == r.name) {
            Some((_, pgv)) => {
                named += 1;
                r.with_known_pgv(*pgv)
            }
            None => Ok(r),
        })
        .collect::<Result<_>>()?;
    if named == 0 && !records.is_empty() {
        let first = table.iter().take(3).map(|(n, _)| n.as_str()).collect::<Vec<_>>().join(", ");
        return Err(Error::parameter(
            "pgv_table",
            table_name,
            format!("a table naming some of the records by file name (it names {first}…)"),
        ));
    }
    Ok((records, named))
}

/// One component of a PEER NGA `.AT2` file: its interval (s) and accelerations (g).
pub fn read_at2_component(path: &Path) -> Result<(f64, Vec<f64>)> {
    let text = read_text(path)?;
    let parse = |what: String| Error::Parse { path: path.into(), what };
    let lines: Vec<&str> = text.lines().collect();
    if lines.len() < 4 {
        return Err(parse("not a PEER .AT2 file: fewer than the four header lines".into()));
    }
    let units = lines[2].to_ascii_uppercase();
    if !units.contains("ACCELERATION") || !units.contains("UNITS OF G") {
        return Err(parse(format!(
            "line 3: expected 'ACCELERATION TIME SERIES IN UNITS OF G', got {:?} (velocity and displacement files, .VT2/.DT2, are not ground accelerations)",
            lines[2].trim()
        )));
    }
    let (npts, dt) = at2_counts(lines[3]).map_err(|w| parse(format!("line 4: {w}: {:?}", lines[3].trim())))?;
    let mut values = Vec::with_capacity(npts);
    for (k, line) in lines.iter().enumerate().skip(4) {
        for field in line.split_whitespace() {
            let x: f64 = field.parse().map_err(|_| parse(format!("line {}: not a number: {field:?}", k + 1)))?;
            if !x.is_finite() {
                return Err(parse(format!("line {}: not a finite number: {field:?}", k + 1)));
            }
            values.push(x);
        }
    }
    if values.len() != npts {
        return Err(parse(format!("the header says NPTS = {npts}, the file holds {} values", values.len())));
    }
    Ok((dt, values))
}

/// NPTS and DT from the fourth header line, in either layout.
fn at2_counts(line: &str) -> std::result::Result<(usize, f64), String> {
    let upper = line.to_ascii_uppercase();
    let number_after = |key: &str| -> Option<&str> {
        let at = upper.find(key)? + key.len();
        let rest = line[at..].trim_start_matches([' ', '=']);
        rest.split([',', ' ']).find(|s| !s.is_empty())
    };
    let (n, dt) = if upper.contains("NPTS=") || upper.contains("NPTS =") {
        (number_after("NPTS").ok_or("no NPTS value")?, number_after("DT").ok_or("no DT value")?)
    } else {
        let mut it = line.split([',', ' ', '\t']).filter(|s| !s.is_empty());
        (it.next().ok_or("no NPTS value")?, it.next().ok_or("no DT value")?)
    };
    let n: usize = n.parse().map_err(|_| format!("NPTS is not a count ({n:?})"))?;
    let dt: f64 = dt.parse().map_err(|_| format!("DT is not a number ({dt:?})"))?;
    if n < 2 {
        return Err(format!("NPTS = {n}: a record needs at least two samples"));
    }
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(format!("DT = {dt} s must be positive"));
    }
    Ok((n, dt))
}

/// A record from one to three `.AT2` files: x, y, z in that order (see the module doc).
pub fn read_at2(paths: &[&Path]) -> Result<Record> {
    if !(1..=3).contains(&paths.len()) {
        return Err(Error::parameter(
            "motion",
            format!("{} files", paths.len()),
            "one to three .AT2 files (x, y, z components)",
        ));
    }
    let parts: Vec<(f64, Vec<f64>)> = paths.iter().map(|p| read_at2_component(p)).collect::<Result<_>>()?;
    let name = paths.iter().map(|p| file_name(p)).collect::<Vec<_>>().join("+");
    let dt = parts.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
    let mut columns: Vec<Vec<f64>> = Vec::new();
    for (path, (dt_c, values)) in paths.iter().zip(&parts) {
        let one = Record::new(file_name(path), *dt_c, values.iter().map(|a| [a * G, 0.0, 0.0]).collect())?;
        let one = if (dt_c - dt).abs() > 1e-12 * dt { one.resampled(dt)? } else { one };
        columns.push(one.accel.iter().map(|a| a[0]).collect());
    }
    let n = columns.iter().map(Vec::len).max().unwrap_or(0);
    let accel =
        (0..n).map(|k| [0, 1, 2].map(|c| columns.get(c).and_then(|col| col.get(k)).copied().unwrap_or(0.0))).collect();
    Record::new(name, dt, accel)
}

/// Write the x, y and z accelerations (in g) of `record` as PEER `.AT2` text (five values per
/// line, the NGA-West2 header): the inverse of [`read_at2_component`], for tests and for users
/// who convert their own records.
pub fn at2_text(record: &Record, component: usize, event: &str) -> String {
    let mut s = String::from("PEER NGA STRONG MOTION DATABASE RECORD\n");
    s += &format!("{event}\nACCELERATION TIME SERIES IN UNITS OF G\n");
    s += &format!("NPTS= {:7}, DT= {:.6} SEC\n", record.accel.len(), record.dt);
    for chunk in record.accel.chunks(5) {
        let line: Vec<String> = chunk.iter().map(|a| format!("{:16.8E}", a[component] / G)).collect();
        s += &line.join("");
        s.push('\n');
    }
    s
}

/// A record from files as the command line names them: one to three `.AT2` files (x, y, z), or
/// one CSV file read with `columns` and `unit`.
pub fn read_record(paths: &[&Path], columns: &Columns, unit: AccelUnit) -> Result<Record> {
    let at2 = |p: &&Path| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("at2"));
    if !paths.is_empty() && paths.iter().all(at2) {
        return read_at2(paths);
    }
    match paths {
        [one] => read_csv(one, columns, unit),
        _ => Err(Error::parameter("motion", "a mix of files", "one CSV record or one to three .AT2 files (x, y, z)")),
    }
}
