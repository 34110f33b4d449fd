//! Field-rock ensembles: summaries, the members' table, the tipping polar and the
//! banded fragility contours of [`crate::dynamics::shaking::ensemble`].

use super::runs::write_runs_csv;
use crate::dynamics::shaking::ensemble::BaseRange;
use crate::dynamics::shaking::ensemble::Sensitivity;
use crate::dynamics::shaking::records::{Contour, EnsembleSummary};
use crate::dynamics::shaking::{Ensemble, RecordRun, ShakeBatch};
use crate::report::{short_name, write_json, Folder};
use crate::tipping::TippingSummary;
use std::path::{Path, PathBuf};

/// A readable summary of an ensemble of one field rock under one record.
pub fn ensemble_summary(e: &Ensemble, mesh: &str) -> String {
    let p = &e.probability;
    let mut s = format!(
        "{} under {} × {}: PGA {:.3} g, {} PGV {:.3} m/s, PGV/PGA {:.3} s\n  \
         P(overturn) = {:.3} (95 % interval {:.3}–{:.3}): {} of {} settled members overturned",
        short_name(mesh),
        e.motion.record,
        e.motion.scale,
        e.motion.pga_g,
        e.motion.pgv_source.name(),
        e.motion.pgv_m_s,
        e.motion.pgv_over_pga_s,
        p.p_overturn,
        p.interval95[0],
        p.interval95[1],
        p.overturned,
        p.settled
    );
    if p.settled < p.members {
        s += &format!(" ({} still moving at the time cap, left out)", p.members - p.settled);
    }
    s += "\n";
    if let Some(m) = e.members.first() {
        s += &format!("  {}\n", super::runs::field_line(&m.run, e.uncertainty.azimuth_deg.is_some()));
    }
    s += &sensitivity_lines(&e.sensitivity);
    s += &tipping_lines(&e.tipping);
    if let Some(b) = &e.base {
        s += &base_line(b);
    }
    s
}

/// The drawn bases of an ensemble in one line: the quasi-static tipping threshold tan α over the
/// members (smallest, median, largest) and the support's depth below the rim.
pub fn base_line(b: &BaseRange) -> String {
    let [lo, mid, hi] = b.tan_alpha;
    let depth = match b.depth_m {
        [d0, _, d1] if d0 == d1 => format!("{:.1} mm", 1e3 * d0),
        [d0, d, d1] => format!("{:.1}–{:.1} mm (median {:.1})", 1e3 * d0, 1e3 * d1, 1e3 * d),
    };
    format!(
        "  drawn bases ({} members; the tipping lines above are the scan's own base): quasi-static tipping off the \
         rocking points tan α from {lo:.3} to {hi:.3} (median {mid:.3}); support {depth} below the rim\n",
        b.members
    )
}

/// The members of an ensemble as runs of `runs.csv` (with their inputs).
pub fn ensemble_runs(e: &Ensemble) -> Vec<RecordRun> {
    e.members
        .iter()
        .map(|m| RecordRun { motion: e.motion.clone(), member: Some(m.draw), rock: m.run.clone() })
        .collect()
}

/// One line per uncertain input, the strongest association with overturning first.
fn sensitivity_lines(sens: &[Sensitivity]) -> String {
    let mut sorted: Vec<_> = sens.iter().collect();
    sorted.sort_by(|a, b| {
        b.correlation.map(f64::abs).unwrap_or(-1.0).total_cmp(&a.correlation.map(f64::abs).unwrap_or(-1.0))
    });
    sorted
        .iter()
        .map(|x| match x.correlation {
            Some(c) => format!("  sensitivity to {}: {} {:+.2}\n", x.input, x.measure, c),
            None => format!("  sensitivity to {}: undefined (every member had the same outcome)\n", x.input),
        })
        .collect()
}

/// The ensemble lines of a batch's summary: P(overturn) per record × scale and the contours
/// with their bands (none without an ensemble).
pub fn batch_lines(b: &ShakeBatch) -> String {
    let mut s = String::new();
    if let Some(e) = &b.ensemble {
        s += &format!("ensemble of {} members per record × scale (seed {}):\n", e.members, e.seed);
        for x in &b.probabilities {
            let p = &x.probability;
            s += &format!(
                "  {} × {}: PGA {:.3} g, P(overturn) {:.3} ({:.3}–{:.3})\n",
                x.record, x.scale, x.pga_g, p.p_overturn, p.interval95[0], p.interval95[1]
            );
        }
        for c in b.contours.iter().filter(|c| c.pgv_over_pga_s == b.contours[0].pgv_over_pga_s || c.p == 0.5) {
            let band = |x: Option<f64>| x.map_or("—".to_string(), |a| format!("{a:.3}"));
            s += &format!(
                "  P = {} at PGV/PGA {:.3} s: PGA {} g (95 % band {}–{})\n",
                c.p,
                c.pgv_over_pga_s,
                band(c.pga_g),
                band(c.band95[0]),
                band(c.band95[1])
            );
        }
    }
    s += &tipping_lines(&b.tipping);
    s
}

/// One line per base-contact tolerance of the quasi-static tipping polar.
pub fn tipping_lines(t: &[TippingSummary]) -> String {
    t.iter()
        .map(|x| {
            let corners = x.support_polygon_m.len();
            if x.stands {
                format!(
                    "  quasi-static tipping, contact tolerance {:.1} mm: tan α ≥ {:.3} (at azimuth {:.0}°), \
                     support polygon of {corners} corners\n",
                    1e3 * x.tolerance_m,
                    x.minimum_g,
                    x.minimum_azimuth_deg
                )
            } else {
                format!(
                    "  quasi-static tipping, contact tolerance {:.1} mm: cannot stand on {corners} corner(s)\n",
                    1e3 * x.tolerance_m
                )
            }
        })
        .collect()
}

/// Write an ensemble's `ensemble.json`, `members.csv` (the runs' columns and each member's
/// inputs) and `tipping_polar.png`.
pub fn write_ensemble_outputs(e: &Ensemble, name: &str, dir: &Path) -> crate::Result<Vec<PathBuf>> {
    let mut out = Folder::create(dir)?;
    out.file("ensemble.json", |p| write_json(p, e))?;
    out.file("members.csv", |p| write_runs_csv(p, &ensemble_runs(e)))?;
    let title = format!("{}: quasi-static tipping acceleration", short_name(name));
    out.file("tipping_polar.png", |p| crate::report::tipping::write_polar_plot(&e.tipping, &title, p))?;
    Ok(out.written)
}

/// The ensemble outputs of a batch: `tipping_polar.png`, and with an ensemble
/// `probabilities.csv` (P(overturn) per record × scale) and `contours.csv` (the contours with
/// their 95 % bands).
pub(crate) fn write_batch_ensemble_outputs(b: &ShakeBatch, name: &str, out: &mut Folder) -> crate::Result<()> {
    let title = format!("{}: quasi-static tipping acceleration", short_name(name));
    out.file("tipping_polar.png", |p| crate::report::tipping::write_polar_plot(&b.tipping, &title, p))?;
    if b.ensemble.is_none() {
        return Ok(());
    }
    out.file("probabilities.csv", |p| write_probabilities(p, &b.probabilities))?;
    out.file("contours.csv", |p| write_contours(p, &b.contours))
}

fn write_probabilities(path: &Path, rows: &[EnsembleSummary]) -> crate::Result<()> {
    let mut s = String::from("record,scale,pga_g,pgv_over_pga_s,members,settled,overturned,p_overturn,low95,high95\n");
    for r in rows {
        let p = &r.probability;
        s += &format!(
            "{},{},{:.6},{:.6},{},{},{},{:.4},{:.4},{:.4}\n",
            r.record,
            r.scale,
            r.pga_g,
            r.pgv_over_pga_s,
            p.members,
            p.settled,
            p.overturned,
            p.p_overturn,
            p.interval95[0],
            p.interval95[1]
        );
    }
    std::fs::write(path, s).map_err(|e| crate::Error::write(path, e))
}

fn write_contours(path: &Path, rows: &[Contour]) -> crate::Result<()> {
    let f = |x: Option<f64>| x.map_or(String::new(), |a| format!("{a:.6}"));
    let mut s = String::from("p,pgv_over_pga_s,pga_g,band95_low_g,band95_high_g\n");
    for c in rows {
        s += &format!("{},{:.6},{},{},{}\n", c.p, c.pgv_over_pga_s, f(c.pga_g), f(c.band95[0]), f(c.band95[1]));
    }
    std::fs::write(path, s).map_err(|e| crate::Error::write(path, e))
}
