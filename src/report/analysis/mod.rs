//! What a person reads: the human summary, the batch CSV, and the pictures and coloured mesh of
//! one analysis. Everything here reads [`Report`] / [`Analysis`]; nothing is recomputed.

use super::names::{number, plural, Unit};
use super::{write_json, Folder};
use crate::analysis::{Analysis, Report};
use crate::equilibria::Kind;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

mod plots;

pub use plots::{flock_color, flock_colored_hull, plot_hull, plot_n_nu};

/// A short, readable summary of a report, lengths in "mesh units" (see [`summary_in`]).
pub fn summary(r: &Report) -> String {
    summary_in(r, &Unit::default())
}

/// A short, readable summary of a report whose mesh coordinates are in `unit`: volume, area,
/// G, axes and points labelled with it, numbers as plain decimals.
pub fn summary_in(r: &Report, unit: &Unit) -> String {
    let mut s = String::new();
    let g = r.solid.center_of_mass;
    let n = |x: f64| number(x, 6);
    let _ = writeln!(s, "{}", r.file);
    let _ = writeln!(
        s,
        "  mesh     {} vertices, {} triangles{}",
        r.mesh.vertices,
        r.mesh.triangles,
        repairs_note(&r.repairs)
    );
    if let Some(o) = &r.open_scan {
        s.push_str(&open_scan_lines(o, unit));
    }
    let _ = writeln!(
        s,
        "  solid    volume {} {}, area {} {}, G = ({}, {}, {}) {}",
        n(r.solid.volume),
        unit.volume(),
        n(r.solid.area),
        unit.area(),
        n(g.x),
        n(g.y),
        n(g.z),
        unit.length()
    );
    let sh = &r.shape;
    let _ = writeln!(
        s,
        "  shape    axes a {} ≥ b {} ≥ c {} {}; c/b {:.3}, b/a {:.3}, c/a {:.3}; Zingg class {}; 36πV²/A³ = {:.3}",
        number(sh.a, 5),
        number(sh.b, 5),
        number(sh.c, 5),
        unit.length(),
        sh.c_over_b,
        sh.b_over_a,
        sh.c_over_a,
        sh.zingg,
        sh.isoperimetric_ratio
    );
    let _ = writeln!(
        s,
        "  hull     {} facets, {} edges, {} vertices ({} triangles before merging exactly coplanar ones)",
        r.hull.facets, r.hull.edges, r.hull.vertices, r.hull.triangles
    );
    let m = &r.micro;
    let _ = writeln!(
        s,
        "  micro    S = {}  U = {}  H = {}   (S + U − H = {}){}",
        m.stable,
        m.unstable,
        m.saddle,
        m.stable as i64 + m.unstable as i64 - m.saddle as i64,
        if m.degenerate_decisions > 0 {
            format!("; {} degenerate predicate(s) decided by symbolic perturbation", m.degenerate_decisions)
        } else {
            String::new()
        }
    );
    match &r.plateau {
        Some(p) => {
            let _ = writeln!(
                s,
                "  plateau  ν ∈ [{}, {}), {} decades, {} (clarity {}): S = {}  U = {}  H = {}",
                number(p.nu_lo, 4),
                number(p.nu_hi, 4),
                if p.decades.is_finite() { format!("{:.2}", p.decades) } else { "∞".into() },
                if p.clear { "clear" } else { "NOT clear — micro and macro scales are not well separated" },
                if p.clarity.is_finite() { format!("{:.2}", p.clarity) } else { "∞".into() },
                p.counts.stable,
                p.counts.unstable,
                p.counts.saddle
            );
        }
        None => {
            let _ = writeln!(s, "  plateau  none (no cancellation: the micro-equilibria are already the macro ones)");
        }
    }
    let mc = &r.r#macro;
    let _ = writeln!(
        s,
        "  macro    ν = {} ({}): S = {}  U = {}  H = {}",
        number(mc.nu, 5),
        mc.nu_source,
        mc.stable,
        mc.unstable,
        mc.saddle
    );
    let count = |k: Kind| r.flocks.iter().filter(|f| f.kind == k).count();
    let _ = writeln!(
        s,
        "  flocks   {} stable, {} unstable, {} saddle",
        count(Kind::Stable),
        count(Kind::Unstable),
        count(Kind::Saddle)
    );
    if r.rocking.is_empty() {
        let _ = writeln!(s, "  rocking  none: every stable micro-equilibrium lies in a stable flock");
    } else {
        let on_base = r.rocking.iter().filter(|q| q.hidden_base).count();
        let _ = writeln!(
            s,
            "  rocking  {} (stable micro-equilibria inside unstable/saddle flocks; --equilibrium ID and \
             --pose equilibrium:ID take the equilibrium, --pose facet:F the hull facet){}:",
            plural(r.rocking.len() as u64, "rocking equilibrium", "rocking equilibria"),
            if r.open_scan.is_some() { format!("; {on_base} on the hidden base") } else { String::new() }
        );
        for q in r.rocking.iter().take(10) {
            let _ = writeln!(
                s,
                "           equilibrium {:>5} (facet {:>6})  R/R_max = {:.5}  in {} flock {}  at ({}, {}, {}) {}{}",
                q.index,
                q.facet,
                q.r_normalised,
                q.flock_type,
                q.flock,
                n(q.point.x),
                n(q.point.y),
                n(q.point.z),
                unit.length(),
                if q.hidden_base { "  [on the hidden base]" } else { "" }
            );
        }
        if r.rocking.len() > 10 {
            let _ = writeln!(s, "           … {} more in --json", r.rocking.len() - 10);
        }
    }
    s
}

/// The lines of an open scan: what was found, and the base that closed it.
fn open_scan_lines(o: &crate::analysis::OpenScanReport, unit: &Unit) -> String {
    let n = |x: f64| number(x, 4);
    let rim = &o.scan.rim;
    let gaps = match o.scan.gaps.first() {
        None => "no gaps".to_string(),
        Some(g) => format!(
            "{} closed flat (the largest {} {} around, {} {})",
            plural(o.scan.gaps.len() as u64, "scan gap", "scan gaps"),
            n(g.perimeter),
            unit.length(),
            n(g.area),
            unit.area()
        ),
    };
    let trimmed = if o.scan.trimmed_triangles > 0 {
        format!(
            "; {} hanging at the openings or in small separate pieces trimmed",
            plural(o.scan.trimmed_triangles as u64, "triangle", "triangles")
        )
    } else {
        String::new()
    };
    let d = &o.on_hidden_base;
    format!(
        "  open     an open scan: the rim of its hidden base{} is {} {} around, encloses {} {} on its plane and lies within {} {} of it; {gaps}{trimmed}\n  base     hidden, closed by a {} (the nominal base); {} stable, {} unstable and {} saddle micro-equilibria touch it\n",
        if o.scan.rim_loops.len() > 1 { format!(" ({} loops on one plane)", o.scan.rim_loops.len()) } else { String::new() },
        n(rim.perimeter),
        unit.length(),
        n(rim.area),
        unit.area(),
        n(rim.flatness),
        unit.length(),
        o.base,
        d.stable,
        d.unstable,
        d.saddle
    )
}

fn repairs_note(r: &crate::mesh::Repairs) -> String {
    let mut notes = Vec::new();
    if r.welded_vertices > 0 {
        notes.push(format!("{} duplicate vertices welded", r.welded_vertices));
    }
    if r.unreferenced_vertices > 0 {
        notes.push(format!("{} unused vertices dropped", r.unreferenced_vertices));
    }
    if r.degenerate_triangles > 0 {
        notes.push(format!("{} zero-area triangles dropped", r.degenerate_triangles));
    }
    if r.flipped {
        notes.push("orientation was inward and has been flipped".into());
    }
    if notes.is_empty() {
        String::new()
    } else {
        format!(" ({})", notes.join("; "))
    }
}

/// Columns of the batch CSV, one row per mesh.
pub const CSV_HEADER: [&str; 25] = [
    "file",
    "error",
    "volume",
    "area",
    "a",
    "b",
    "c",
    "c_over_b",
    "b_over_a",
    "c_over_a",
    "zingg",
    "isoperimetric_ratio",
    "hull_facets",
    "hull_edges",
    "hull_vertices",
    "micro_S",
    "micro_U",
    "micro_H",
    "nu",
    "nu_source",
    "macro_S",
    "macro_U",
    "macro_H",
    "plateau_decades",
    "rocking",
];

/// One CSV row per mesh; failures get a row with the error and empty numbers.
pub fn write_batch_csv<'a, W: std::io::Write>(
    w: W,
    rows: impl Iterator<Item = (&'a Path, Result<&'a Report, &'a str>)>,
) -> crate::Result<()> {
    (|| -> std::result::Result<_, crate::error::BoxError> {
        let mut out = csv::Writer::from_writer(w);
        out.write_record(CSV_HEADER)?;
        for (file, r) in rows {
            match r {
                Ok(r) => out.write_record(csv_row(r))?,
                Err(e) => {
                    let mut row = vec![file.display().to_string(), e.to_string()];
                    row.resize(CSV_HEADER.len(), String::new());
                    out.write_record(row)?
                }
            }
        }
        out.flush()?;
        Ok(())
    })()
    .map_err(|e| crate::Error::write(crate::error::MEMORY, e))
}

fn csv_row(r: &Report) -> Vec<String> {
    let sh = &r.shape;
    let mc = &r.r#macro;
    vec![
        r.file.clone(),
        String::new(),
        format!("{:e}", r.solid.volume),
        format!("{:e}", r.solid.area),
        format!("{:e}", sh.a),
        format!("{:e}", sh.b),
        format!("{:e}", sh.c),
        format!("{:.6}", sh.c_over_b),
        format!("{:.6}", sh.b_over_a),
        format!("{:.6}", sh.c_over_a),
        sh.zingg.name().to_string(),
        format!("{:.6}", sh.isoperimetric_ratio),
        r.hull.facets.to_string(),
        r.hull.edges.to_string(),
        r.hull.vertices.to_string(),
        r.micro.stable.to_string(),
        r.micro.unstable.to_string(),
        r.micro.saddle.to_string(),
        format!("{:e}", mc.nu),
        serde_json::to_value(mc.nu_source).map(|v| v.as_str().unwrap_or("").to_string()).unwrap_or_default(),
        mc.stable.to_string(),
        mc.unstable.to_string(),
        mc.saddle.to_string(),
        r.plateau.as_ref().map_or(String::new(), |p| format!("{:.4}", p.decades)),
        r.rocking.len().to_string(),
    ]
}

/// Write `report.json`, `n_nu.png/.svg`, `hull.png/.svg`, `hull_flocks.ply` and `report.html`
/// into `dir`, lengths in mesh units (see [`write_outputs_in`]).
pub fn write_outputs(a: &Analysis, r: &Report, dir: &Path) -> crate::Result<Vec<PathBuf>> {
    write_outputs_in(a, r, &Unit::default(), dir)
}

/// [`write_outputs`] for a mesh whose coordinates are in `unit` (labels of the summary and the
/// 3D view of `report.html`).
pub fn write_outputs_in(a: &Analysis, r: &Report, unit: &Unit, dir: &Path) -> crate::Result<Vec<PathBuf>> {
    let mut written = write_files(a, r, dir)?;
    let title = format!("rocking analyze: {}", super::short_name(&r.file));
    super::html::add_page(dir, &mut written, &title, &summary_in(r, unit), Some(&super::html::hull_view(a, r, unit)))?;
    Ok(written)
}

/// The files of [`write_outputs`] without `report.html` (for experiments that keep many stones'
/// pictures side by side).
pub fn write_files(a: &Analysis, r: &Report, dir: &Path) -> crate::Result<Vec<PathBuf>> {
    let mut out = Folder::create(dir)?;
    out.file("report.json", |p| write_json(p, r))?;
    for ext in ["png", "svg"] {
        out.file(&format!("n_nu.{ext}"), |p| plot_n_nu(r, p))?;
    }
    for ext in ["png", "svg"] {
        out.file(&format!("hull.{ext}"), |p| plot_hull(a, r, p))?;
    }
    let (mesh, colors) = flock_colored_hull(a, r);
    out.file("hull_flocks.ply", |p| crate::mesh::io::write_colored_ply(p, &mesh, &colors))?;
    Ok(out.written)
}
