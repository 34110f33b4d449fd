//! What a person reads: the human summary, the batch CSV, and the pictures and coloured mesh of
//! one analysis. Everything here reads [`Report`] / [`Analysis`]; nothing is recomputed.

use crate::analysis::{Analysis, NuSource, Report};
use crate::equilibria::Kind;
use crate::mesh::TriMesh;
use crate::plot::{init_fonts, FONT_FAMILY};
use crate::Point3;
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
) -> anyhow::Result<()> {
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
pub fn write_outputs(a: &Analysis, r: &Report, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| anyhow::anyhow!("{}: cannot create folder: {e}", dir.display()))?;
    let mut written = Vec::new();
    let json = dir.join("report.json");
    std::fs::write(&json, serde_json::to_string_pretty(r)?)?;
    written.push(json);
    for ext in ["png", "svg"] {
        let p = dir.join(format!("n_nu.{ext}"));
        plot_n_nu(r, &p)?;
        written.push(p);
    }
    let p = dir.join("hull.png");
    plot_hull(a, r, &p)?;
    written.push(p);
    let p = dir.join("hull_flocks.ply");
    let (mesh, colors) = flock_colored_hull(a, r);
    crate::mesh::io::write_colored_ply(&p, &mesh, &colors)?;
    written.push(p);
    Ok(written)
}

/// The log ν – n(ν) staircase (paper Figure 10B) with the plateau and the chosen ν marked.
pub fn plot_n_nu(r: &Report, path: &Path) -> anyhow::Result<()> {
    init_fonts();
    let is_svg = path.extension().is_some_and(|e| e == "svg");
    if is_svg {
        let root = SVGBackend::new(path, (900, 560)).into_drawing_area();
        draw_n_nu(&root, r)?;
        root.present()?;
    } else {
        let root = BitMapBackend::new(path, (900, 560)).into_drawing_area();
        draw_n_nu(&root, r)?;
        root.present()?;
    }
    Ok(())
}

fn draw_n_nu<DB: DrawingBackend>(root: &DrawingArea<DB, plotters::coord::Shift>, r: &Report) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e:?}"))?;
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
        .map_err(|e| anyhow::anyhow!("{e:?}"))?;
    chart
        .configure_mesh()
        .x_desc("ν (log scale)")
        .y_desc("n(ν)")
        .label_style((FONT_FAMILY, 14))
        .draw()
        .map_err(|e| anyhow::anyhow!("{e:?}"))?;
    if let Some(p) = &r.plateau {
        let color = if p.clear { RGBColor(200, 235, 200) } else { RGBColor(240, 220, 200) };
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(p.nu_lo.max(lo), 0.0), (p.nu_hi.min(hi), 1.05)],
                color.filled(),
            )))
            .map_err(|e| anyhow::anyhow!("{e:?}"))?
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
        .map_err(|e| anyhow::anyhow!("{e:?}"))?
        .label("n(ν)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], BLUE.stroke_width(2)));
    let nu = r.r#macro.nu;
    chart
        .draw_series(LineSeries::new(vec![(nu, 0.0), (nu, 1.05)], RED.stroke_width(1)))
        .map_err(|e| anyhow::anyhow!("{e:?}"))?
        .label(format!("ν = {nu:.3e}: S={} U={} H={}", r.r#macro.stable, r.r#macro.unstable, r.r#macro.saddle))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], RED));
    chart
        .configure_series_labels()
        .label_font((FONT_FAMILY, 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|e| anyhow::anyhow!("{e:?}"))?;
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
pub fn plot_hull(a: &Analysis, r: &Report, path: &Path) -> anyhow::Result<()> {
    init_fonts();
    let (w, h) = (1400u32, 720u32);
    let root = BitMapBackend::new(path, (w, h)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e:?}"))?;
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
                .map_err(|e| anyhow::anyhow!("{e:?}"))?;
        }
        let visible = |p: &Point3| (p - g).dot(&view) > 0.0;
        for arc in &a.graph.arcs {
            for seg in arc.path.windows(2) {
                if visible(&seg[0]) && visible(&seg[1]) {
                    panel
                        .draw(&PathElement::new(vec![project(&seg[0]), project(&seg[1])], BLACK.mix(0.55)))
                        .map_err(|e| anyhow::anyhow!("{e:?}"))?;
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
            panel.draw(&el).map_err(|e| anyhow::anyhow!("{e:?}"))?;
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
        panel.draw(&Text::new(title, (10, 10), (FONT_FAMILY, 16))).map_err(|e| anyhow::anyhow!("{e:?}"))?;
    }
    root.present()?;
    Ok(())
}

/// A readable summary of a drop run.
pub fn drop_summary(r: &crate::montecarlo::DropReport) -> String {
    let mut s = String::new();
    let p = &r.params;
    let plural = |n: u64, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    let _ = writeln!(
        s,
        "{}: {} of {} (seed {}), preset {}; {} settled, {} ended by the {} certificate",
        r.mesh,
        r.drops,
        plural(r.drops_requested, "drop", "drops"),
        r.seed,
        r.preset.as_deref().unwrap_or("custom"),
        r.settled,
        r.certified,
        r.certificate.name()
    );
    let _ = writeln!(
        s,
        "  launch: height {} R_max, horizontal speed {} m/s, spin {} rad/s ({}), scaled to R_max = 1 m",
        p.height,
        p.horizontal_speed,
        p.spin,
        match p.spin_distribution {
            crate::dynamics::params::SpinDistribution::Fixed => "exact",
            crate::dynamics::params::SpinDistribution::Gaussian => "rms, Gaussian",
        }
    );
    let _ = writeln!(
        s,
        "  contact: friction {}, restitution {}, rolling resistance {} R_max, torsional {} R_max, damping {}/{} 1/s; dt {:.5} s",
        p.friction, p.restitution, p.rolling_resistance, p.torsional_friction, p.linear_damping, p.angular_damping, p.dt
    );
    let mean = |t: Option<f64>| t.map_or("-".to_string(), |t| format!("{t:.2} s"));
    let _ = writeln!(
        s,
        "  simulated time per drop: {} to rest, {} to the certificate's decision",
        mean(r.mean_time_to_rest),
        mean(r.mean_time_to_decision)
    );
    if r.unsettled > 0 {
        let _ = writeln!(
            s,
            "  WARNING: {} still moving at the {} s cap (counted where the quasi-static descent from their last \
             position leads). Raise --max-time, lower --dt, or add --rolling-resistance.",
            plural(r.unsettled, "drop", "drops"),
            p.max_time
        );
    }
    if r.off_equilibrium > 0 {
        let _ = writeln!(
            s,
            "  note: {} stopped above their stable facet (held by friction or rolling resistance); counted \
             where the quasi-static descent leads",
            plural(r.off_equilibrium, "drop", "drops")
        );
    }
    let _ = writeln!(s, "  flocks at ν = {:.4e}:", r.nu);
    let _ = writeln!(
        s,
        "    {:>5} {:<9} {:>7} {:>9} {:>18} {:>9}",
        "flock", "type", "drops", "fraction", "95% interval", "static"
    );
    for f in &r.flocks {
        let _ = writeln!(
            s,
            "    {:>5} {:<9} {:>7} {:>9.4} {:>18} {:>9.4}",
            f.id,
            format!("{:?}", f.kind).to_lowercase(),
            f.count,
            f.fraction,
            format!("[{:.4}, {:.4}]", f.ci95.0, f.ci95.1),
            f.static_probability
        );
    }
    let mut facets: Vec<_> = r.facets.iter().collect();
    facets.sort_by(|a, b| b.count.cmp(&a.count).then(b.static_probability.total_cmp(&a.static_probability)));
    if facets.is_empty() {
        let _ = writeln!(
            s,
            "  facets: not determined (the flock certificate stops a drop once its flock is certain; \
             use --certificate facet or none for per-facet counts)"
        );
    } else {
        let _ = writeln!(
            s,
            "  stable facets (the {} most frequent of {}; fractions of the {} drops whose facet is determined):",
            facets.len().min(12),
            facets.len(),
            r.facet_drops
        );
        let _ = writeln!(
            s,
            "    {:>6} {:>5} {:>7} {:>9} {:>18} {:>9}",
            "facet", "flock", "drops", "fraction", "95% interval", "static"
        );
    }
    for f in facets.iter().take(12) {
        let _ = writeln!(
            s,
            "    {:>6} {:>5} {:>7} {:>9.4} {:>18} {:>9.4}{}",
            f.facet,
            f.flock.map_or("-".into(), |k| k.to_string()),
            f.count,
            f.fraction,
            format!("[{:.4}, {:.4}]", f.ci95.0, f.ci95.1),
            f.static_probability,
            if f.equilibrium.is_none() { "  (not a stable facet)" } else { "" }
        );
    }
    let fit = |name: &str, f: &crate::montecarlo::Fit| {
        format!(
            "{name}: χ² = {:.2} ({} dof, p = {:.3}), KL = {:.4} nats",
            f.chi_square, f.dof, f.p_value, f.kl_divergence
        )
    };
    let _ = writeln!(s, "  vs quasi-static: {}", fit("flocks", &r.fit_flocks));
    if let Some(f) = &r.fit_facets {
        let _ = writeln!(s, "                   {}", fit("facets", f));
    }
    s
}

/// Write `drops.json` and bar plots `drops_flocks.png/.svg`, `drops_facets.png` into `dir`.
pub fn write_drop_outputs(r: &crate::montecarlo::DropReport, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| anyhow::anyhow!("{}: cannot create folder: {e}", dir.display()))?;
    let json = dir.join("drops.json");
    std::fs::write(&json, serde_json::to_string_pretty(r)?)?;
    let mut written = vec![json];
    let flocks: Vec<Bar> = r
        .flocks
        .iter()
        .map(|f| Bar {
            label: format!("{} {}", f.id, format!("{:?}", f.kind).to_lowercase()),
            fraction: f.fraction,
            ci: f.ci95,
            reference: f.static_probability,
        })
        .collect();
    for ext in ["png", "svg"] {
        let p = dir.join(format!("drops_flocks.{ext}"));
        bar_plot(&p, &format!("Resting flock: drops (n = {}) vs quasi-static", r.settled), &flocks)?;
        written.push(p);
    }
    let mut facets: Vec<_> = r.facets.iter().collect();
    facets.sort_by(|a, b| b.static_probability.total_cmp(&a.static_probability).then(b.count.cmp(&a.count)));
    let bars: Vec<Bar> = facets
        .iter()
        .take(30)
        .map(|f| Bar { label: f.facet.to_string(), fraction: f.fraction, ci: f.ci95, reference: f.static_probability })
        .collect();
    let p = dir.join("drops_facets.png");
    bar_plot(&p, "Resting facet (micro-equilibrium): drops vs quasi-static", &bars)?;
    written.push(p);
    Ok(written)
}

/// One category of a bar plot: empirical fraction with its interval, and a reference value.
pub struct Bar {
    pub label: String,
    pub fraction: f64,
    pub ci: (f64, f64),
    pub reference: f64,
}

/// Bars of empirical fractions with 95 % intervals beside reference (static) probabilities.
pub fn bar_plot(path: &Path, title: &str, bars: &[Bar]) -> anyhow::Result<()> {
    init_fonts();
    let (w, h) = (1000u32, 560u32);
    if path.extension().is_some_and(|e| e == "svg") {
        let root = SVGBackend::new(path, (w, h)).into_drawing_area();
        draw_bars(&root, title, bars)?;
        root.present()?;
    } else {
        let root = BitMapBackend::new(path, (w, h)).into_drawing_area();
        draw_bars(&root, title, bars)?;
        root.present()?;
    }
    Ok(())
}

fn draw_bars<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    bars: &[Bar],
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| anyhow::anyhow!("{x:?}");
    root.fill(&WHITE).map_err(e)?;
    let top = bars.iter().map(|b| b.ci.1.max(b.reference)).fold(0.0, f64::max).max(0.05) * 1.15;
    let n = bars.len().max(1);
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT_FAMILY, 20))
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(60)
        .build_cartesian_2d(-0.5f64..n as f64 - 0.5, 0f64..top)
        .map_err(e)?;
    let labels: Vec<String> = bars.iter().map(|b| b.label.clone()).collect();
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(n.min(30))
        .x_label_formatter(&|x| {
            let i = x.round();
            if (x - i).abs() < 1e-6 && i >= 0.0 {
                labels.get(i as usize).cloned().unwrap_or_default()
            } else {
                String::new()
            }
        })
        .y_desc("probability")
        .label_style((FONT_FAMILY, 12))
        .draw()
        .map_err(e)?;
    let drops = RGBColor(70, 110, 200);
    let stat = RGBColor(230, 140, 40);
    chart
        .draw_series(
            bars.iter()
                .enumerate()
                .map(|(i, b)| Rectangle::new([(i as f64 - 0.38, 0.0), (i as f64 - 0.02, b.fraction)], drops.filled())),
        )
        .map_err(e)?
        .label("drops (95% Wilson interval)")
        .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], drops.filled()));
    chart
        .draw_series(bars.iter().enumerate().map(|(i, b)| {
            PathElement::new(vec![(i as f64 - 0.2, b.ci.0), (i as f64 - 0.2, b.ci.1)], BLACK.stroke_width(2))
        }))
        .map_err(e)?;
    chart
        .draw_series(
            bars.iter()
                .enumerate()
                .map(|(i, b)| Rectangle::new([(i as f64 + 0.02, 0.0), (i as f64 + 0.38, b.reference)], stat.filled())),
        )
        .map_err(e)?
        .label("quasi-static (basin area / 4π)")
        .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], stat.filled()));
    chart
        .configure_series_labels()
        .label_font((FONT_FAMILY, 13))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(e)?;
    Ok(())
}
