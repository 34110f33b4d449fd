//! What a person reads: the human summary, the batch CSV, and the pictures and coloured mesh of
//! one analysis. Everything here reads [`Report`] / [`Analysis`]; nothing is recomputed.

use super::{write_json, Folder};
use crate::analysis::{Analysis, NuSource, Report};
use crate::equilibria::Kind;
use crate::mesh::TriMesh;
use crate::plot::{render, DrawResult, FONT_FAMILY};
use crate::Point3;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A short, readable summary of a report.
pub fn summary(r: &Report) -> String {
    let mut s = String::new();
    let g = r.solid.center_of_mass;
    let _ = writeln!(s, "{}", r.file);
    let _ = writeln!(
        s,
        "  mesh     {} vertices, {} triangles{}",
        r.mesh.vertices,
        r.mesh.triangles,
        repairs_note(&r.repairs)
    );
    let _ = writeln!(
        s,
        "  solid    volume {:.6e}, area {:.6e}, G = ({:.6e}, {:.6e}, {:.6e})",
        r.solid.volume, r.solid.area, g.x, g.y, g.z
    );
    let sh = &r.shape;
    let _ = writeln!(
        s,
        "  shape    axes a {:.4e} ≥ b {:.4e} ≥ c {:.4e}; c/b {:.3}, b/a {:.3}, c/a {:.3}; Zingg {:?}; 36πV²/A³ = {:.3}",
        sh.a, sh.b, sh.c, sh.c_over_b, sh.b_over_a, sh.c_over_a, sh.zingg, sh.isoperimetric_ratio
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
                "  plateau  ν ∈ [{:.3e}, {:.3e}), {:.2} decades, {} (clarity {:.2}): S = {}  U = {}  H = {}",
                p.nu_lo,
                p.nu_hi,
                p.decades,
                if p.clear { "clear" } else { "NOT clear — micro and macro scales are not well separated" },
                p.clarity,
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
    let source = match mc.nu_source {
        NuSource::User => "set by --nu",
        NuSource::Plateau => "middle of the plateau",
        NuSource::PaperDefault => "no clear plateau: the paper's hand experimenter",
    };
    let _ = writeln!(
        s,
        "  macro    ν = {:.4e} ({source}): S = {}  U = {}  H = {}",
        mc.nu, mc.stable, mc.unstable, mc.saddle
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
        let _ = writeln!(
            s,
            "  rocking  {} rocking equilibria (stable micro-equilibria inside unstable/saddle flocks):",
            r.rocking.len()
        );
        for q in r.rocking.iter().take(10) {
            let _ = writeln!(
                s,
                "           facet {:>6}  R/R_max = {:.5}  in {:?} flock {}  at ({:.4e}, {:.4e}, {:.4e})",
                q.facet, q.r_normalised, q.flock_type, q.flock, q.point.x, q.point.y, q.point.z
            );
        }
        if r.rocking.len() > 10 {
            let _ = writeln!(s, "           … {} more in --json", r.rocking.len() - 10);
        }
    }
    s
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
        format!("{:?}", sh.zingg).to_lowercase(),
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

/// Write `report.json`, `n_nu.png/.svg`, `hull.png` and `hull_flocks.ply` into `dir`.
pub fn write_outputs(a: &Analysis, r: &Report, dir: &Path) -> crate::Result<Vec<PathBuf>> {
    let mut out = Folder::create(dir)?;
    out.file("report.json", |p| write_json(p, r))?;
    for ext in ["png", "svg"] {
        out.file(&format!("n_nu.{ext}"), |p| plot_n_nu(r, p))?;
    }
    out.file("hull.png", |p| plot_hull(a, r, p))?;
    let (mesh, colors) = flock_colored_hull(a, r);
    out.file("hull_flocks.ply", |p| crate::mesh::io::write_colored_ply(p, &mesh, &colors))?;
    Ok(out.written)
}

/// The log ν – n(ν) staircase (paper Figure 10B) with the plateau and the chosen ν marked.
pub fn plot_n_nu(r: &Report, path: &Path) -> crate::Result<()> {
    render!(path, (900, 560), |root| draw_n_nu(&root, r))
}

fn draw_n_nu<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, r: &Report) -> DrawResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| format!("{e:?}"))?;
    let steps = &r.staircase;
    let positive: Vec<f64> =
        steps.iter().flat_map(|s| [s.nu_lo, s.nu_hi]).filter(|v| *v > 0.0 && v.is_finite()).collect();
    let lo = positive.iter().cloned().fold(f64::INFINITY, f64::min).min(r.r#macro.nu).max(1e-12) / 2.0;
    let hi = positive.iter().cloned().fold(0.0, f64::max).max(r.r#macro.nu) * 2.0;
    let name = Path::new(&r.file).file_name().map_or(r.file.clone(), |f| f.to_string_lossy().into_owned());
    let mut chart = ChartBuilder::on(root)
        .caption(format!("n(ν) = N(ν)/N(0), {name}"), (FONT_FAMILY, 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(55)
        .build_cartesian_2d((lo..hi).log_scale(), 0f64..1.05)
        .map_err(|e| format!("{e:?}"))?;
    chart
        .configure_mesh()
        .x_desc("ν (log scale)")
        .y_desc("n(ν)")
        .label_style((FONT_FAMILY, 14))
        .draw()
        .map_err(|e| format!("{e:?}"))?;
    if let Some(p) = &r.plateau {
        let color = if p.clear { RGBColor(200, 235, 200) } else { RGBColor(240, 220, 200) };
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(p.nu_lo.max(lo), 0.0), (p.nu_hi.min(hi), 1.05)],
                color.filled(),
            )))
            .map_err(|e| format!("{e:?}"))?
            .label(format!("plateau S={} U={} H={}", p.counts.stable, p.counts.unstable, p.counts.saddle))
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 15, y + 5)], color.filled()));
    }
    let mut pts = Vec::new();
    for s in steps {
        let a = s.nu_lo.max(lo);
        let b = if s.nu_hi.is_finite() { s.nu_hi.min(hi) } else { hi };
        pts.push((a, s.n));
        pts.push((b, s.n));
    }
    chart
        .draw_series(LineSeries::new(pts, BLUE.stroke_width(2)))
        .map_err(|e| format!("{e:?}"))?
        .label("n(ν)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], BLUE.stroke_width(2)));
    let nu = r.r#macro.nu;
    chart
        .draw_series(LineSeries::new(vec![(nu, 0.0), (nu, 1.05)], RED.stroke_width(1)))
        .map_err(|e| format!("{e:?}"))?
        .label(format!("ν = {nu:.3e}: S={} U={} H={}", r.r#macro.stable, r.r#macro.unstable, r.r#macro.saddle))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], RED));
    chart
        .configure_series_labels()
        .label_font((FONT_FAMILY, 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|e| format!("{e:?}"))?;
    Ok(())
}

/// A colour per flock: reds for stable flocks, blues for unstable, greens for saddle flocks.
pub fn flock_color(kind: Kind, ordinal: usize) -> RGBColor {
    let t = (ordinal as f64 * 0.618_033_988_75).fract();
    let (h, s, l) = match kind {
        Kind::Stable => (0.0 + 0.12 * t, 0.75, 0.45 + 0.2 * t),
        Kind::Unstable => (0.55 + 0.12 * t, 0.7, 0.4 + 0.2 * t),
        Kind::Saddle => (0.25 + 0.1 * t, 0.6, 0.35 + 0.2 * t),
    };
    let c = HSLColor(h, s, l).to_rgba();
    RGBColor(c.0, c.1, c.2)
}

fn flock_colors(r: &Report) -> Vec<RGBColor> {
    let mut seen = [0usize; 3];
    r.flocks
        .iter()
        .map(|f| {
            let k = f.kind as usize;
            seen[k] += 1;
            flock_color(f.kind, seen[k] - 1)
        })
        .collect()
}

/// The hull triangulated by facets, each facet coloured by the flock of the stable
/// micro-equilibrium its steepest descent drains to (its Morse–Smale basin).
pub fn flock_colored_hull(a: &Analysis, r: &Report) -> (TriMesh, Vec<[u8; 3]>) {
    let colors = flock_colors(r);
    let basin = a.basins();
    let mut tris = Vec::new();
    let mut face_colors = Vec::new();
    for (f, facet) in a.hull.facets.iter().enumerate() {
        let c = basin[f].map_or(RGBColor(128, 128, 128), |s| colors[r.equilibria[s].flock]);
        for t in &facet.triangles {
            tris.push(*t);
            face_colors.push([c.0, c.1, c.2]);
        }
    }
    (TriMesh::new(a.hull.vertices.clone(), tris), face_colors)
}

/// Two orthographic views of the hull (along −c and +c, the shortest principal axis), facets
/// shaded and tinted by their basin's flock, micro-equilibria as dots (● stable, ■ unstable,
/// ◆ saddle) in their flock's colour, Morse–Smale arcs as thin lines (drawn on the visible
/// side only, approximately: both ends facing the viewer as seen from G).
pub fn plot_hull(a: &Analysis, r: &Report, path: &Path) -> crate::Result<()> {
    let (w, h) = (1400u32, 720u32);
    render!(path, (w, h), |root| draw_hull(&root, a, r, (w, h)))
}

fn draw_hull<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    a: &Analysis,
    r: &Report,
    (w, h): (u32, u32),
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| format!("{e:?}"))?;
    let panels = root.split_evenly((1, 2));
    let axes = a.mass.principal_axes;
    // principal moments ascending: axis 0 = long axis a, axis 2 = short axis c
    let (ex, ez) = (axes.column(0).into_owned(), axes.column(2).into_owned());
    let g = a.mass.center_of_mass;
    let colors = flock_colors(r);
    let basin = a.basins();
    for (panel, sign) in panels.iter().zip([1.0, -1.0]) {
        let view = ez * sign; // towards the viewer
        let right = ex;
        let up = view.cross(&right);
        let extent = a.hull.vertices.iter().map(|p| (p - g).norm()).fold(0.0, f64::max) * 1.1;
        let scale = (h as f64 - 80.0) / (2.0 * extent);
        let (cx, cy) = (w as f64 / 4.0, h as f64 / 2.0 + 15.0);
        let project = |p: &Point3| -> (i32, i32) {
            let d = p - g;
            ((cx + d.dot(&right) * scale) as i32, (cy - d.dot(&up) * scale) as i32)
        };
        let light = (view * 0.8 + up * 0.4 + right * 0.2).normalize();
        for (f, facet) in a.hull.facets.iter().enumerate() {
            if facet.normal.dot(&view) <= 0.0 {
                continue;
            }
            let base = basin[f].map_or(RGBColor(160, 160, 160), |s| colors[r.equilibria[s].flock]);
            let shade = 0.35 + 0.65 * facet.normal.dot(&light).max(0.0);
            let tint = |c: u8| ((c as f64 * 0.55 + 255.0 * 0.45) * shade).min(255.0) as u8;
            let poly: Vec<(i32, i32)> = facet.vertices.iter().map(|&v| project(&a.hull.vertices[v as usize])).collect();
            panel
                .draw(&Polygon::new(poly, RGBColor(tint(base.0), tint(base.1), tint(base.2)).filled()))
                .map_err(|e| format!("{e:?}"))?;
        }
        let visible = |p: &Point3| (p - g).dot(&view) > 0.0;
        for arc in &a.graph.arcs {
            for seg in arc.path.windows(2) {
                if visible(&seg[0]) && visible(&seg[1]) {
                    panel
                        .draw(&PathElement::new(vec![project(&seg[0]), project(&seg[1])], BLACK.mix(0.55)))
                        .map_err(|e| format!("{e:?}"))?;
                }
            }
        }
        for e in &r.equilibria {
            if !visible(&e.point) {
                continue;
            }
            let c = colors[e.flock];
            let (x, y) = project(&e.point);
            let el: DynElement<_, _> = match e.kind {
                Kind::Stable => Circle::new((x, y), 5, c.filled()).into_dyn(),
                Kind::Unstable => Rectangle::new([(x - 4, y - 4), (x + 4, y + 4)], c.filled()).into_dyn(),
                Kind::Saddle => {
                    Polygon::new(vec![(x, y - 5), (x + 5, y), (x, y + 5), (x - 5, y)], c.filled()).into_dyn()
                }
            };
            panel.draw(&el).map_err(|e| format!("{e:?}"))?;
        }
        let title = format!(
            "{} side (view along {}c): micro S={} U={} H={}, macro S={} U={} H={}",
            if sign > 0.0 { "front" } else { "back" },
            if sign > 0.0 { "−" } else { "+" },
            r.micro.stable,
            r.micro.unstable,
            r.micro.saddle,
            r.r#macro.stable,
            r.r#macro.unstable,
            r.r#macro.saddle
        );
        panel.draw(&Text::new(title, (10, 10), (FONT_FAMILY, 16))).map_err(|e| format!("{e:?}"))?;
    }
    Ok(())
}
