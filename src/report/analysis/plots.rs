//! The pictures of one analysis: the log ν – n(ν) staircase and the hull drawn by flocks, and the
//! coloured hull mesh they share.

use crate::analysis::{Analysis, Report};
use crate::equilibria::Kind;
use crate::mesh::TriMesh;
use crate::plot::{colors, draw_legend, legend_height, log_tick, render, style, DrawResult, Mark, FONT_FAMILY};
use crate::report::names::number;
use crate::Point3;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

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
    // the legend has its own strip above the chart: it never covers the staircase
    let (top, rest) = root.split_vertically(36);
    top.draw(&Text::new(format!("n(ν) = N(ν)/N(0) of {name}"), (16, 8), (FONT_FAMILY, style::TITLE)))
        .map_err(|e| format!("{e:?}"))?;
    let (legend, chart_area) = rest.split_vertically(legend_height(2));
    let mut entries = Vec::new();
    if let Some(p) = &r.plateau {
        entries.push((
            Mark::Box(if p.clear { colors::GREEN } else { colors::ORANGE }, 0.25),
            format!(
                "{} plateau: S = {}, U = {}, H = {} over {:.2} decades",
                if p.clear { "clear" } else { "unclear" },
                p.counts.stable,
                p.counts.unstable,
                p.counts.saddle,
                p.decades
            ),
        ));
    }
    entries.push((Mark::Line(colors::BLUE), "n(ν), the staircase of the ν-hierarchy".to_string()));
    let nu = r.r#macro.nu;
    entries.push((
        Mark::Dashed(colors::VERMILLION),
        format!(
            "macro scale ν = {} ({}): S = {}, U = {}, H = {}",
            number(nu, 3),
            r.r#macro.nu_source,
            r.r#macro.stable,
            r.r#macro.unstable,
            r.r#macro.saddle
        ),
    ));
    draw_legend(&legend, &entries)?;
    let mut chart = ChartBuilder::on(&chart_area)
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(60)
        .build_cartesian_2d((lo..hi).log_scale(), 0f64..1.03)
        .map_err(|e| format!("{e:?}"))?;
    chart
        .configure_mesh()
        .x_desc("ν: cancel arcs with |R_i − R_j|/R_max below ν (log scale)")
        .y_desc("n(ν): fraction of micro-equilibria left")
        .x_label_formatter(&|x: &f64| log_tick(*x))
        .y_label_formatter(&|y: &f64| format!("{y:.1}"))
        .label_style((FONT_FAMILY, style::TICK))
        .axis_desc_style((FONT_FAMILY, style::AXIS))
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.12))
        .draw()
        .map_err(|e| format!("{e:?}"))?;
    if let Some(p) = &r.plateau {
        let color = if p.clear { colors::GREEN.mix(0.25) } else { colors::ORANGE.mix(0.25) };
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(p.nu_lo.max(lo), 0.0), (p.nu_hi.min(hi), 1.0)],
                color.filled(),
            )))
            .map_err(|e| format!("{e:?}"))?;
    }
    let mut pts = Vec::new();
    for s in steps {
        let a = s.nu_lo.max(lo);
        let b = if s.nu_hi.is_finite() { s.nu_hi.min(hi) } else { hi };
        pts.push((a, s.n));
        pts.push((b, s.n));
    }
    chart.draw_series(LineSeries::new(pts, colors::BLUE.stroke_width(style::LINE))).map_err(|e| format!("{e:?}"))?;
    chart
        .draw_series(DashedLineSeries::new(
            vec![(nu, 0.0), (nu, 1.0)],
            6,
            4,
            colors::VERMILLION.stroke_width(style::LINE),
        ))
        .map_err(|e| format!("{e:?}"))?;
    Ok(())
}

/// The colour of flock `id` everywhere (hull picture, coloured PLY, 3D view): Paul Tol's
/// colour-blind-safe palette ([`crate::plot::flock_color`]), one distinct colour per flock.
pub fn flock_color(id: usize) -> RGBColor {
    crate::plot::flock_color(id)
}

fn flock_colors(r: &Report) -> Vec<RGBColor> {
    r.flocks.iter().map(|f| flock_color(f.id)).collect()
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
/// shaded and tinted by their basin's flock (labelled "F3" on the picture), micro-equilibria as
/// marks by kind (● stable, ■ unstable, ◆ saddle) filled with their flock's colour, Morse–Smale
/// arcs as thin lines (drawn on the visible side only, approximately: both ends facing the viewer
/// as seen from G), and a legend under the views for every mark and colour.
pub fn plot_hull(a: &Analysis, r: &Report, path: &Path) -> crate::Result<()> {
    let (w, views) = (1400u32, 580u32);
    let rows = r.flocks.len().div_ceil(FLOCKS_PER_ROW) as u32;
    let h = views + 96 + 26 * rows;
    render!(path, (w, h), |root| draw_hull(&root, a, r, (w, views)))
}

const FLOCKS_PER_ROW: usize = 5;

/// A kind's mark at pixel (x, y), `size` ≈ its radius, filled with `fill`, black outline.
fn kind_mark<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    kind: Kind,
    (x, y): (i32, i32),
    size: i32,
    fill: RGBColor,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| format!("{x:?}");
    let outline = BLACK.stroke_width(1);
    match kind {
        Kind::Stable => {
            area.draw(&Circle::new((x, y), size, fill.filled())).map_err(e)?;
            area.draw(&Circle::new((x, y), size, outline)).map_err(e)?;
        }
        Kind::Unstable => {
            let s = size - 1;
            area.draw(&Rectangle::new([(x - s, y - s), (x + s, y + s)], fill.filled())).map_err(e)?;
            area.draw(&Rectangle::new([(x - s, y - s), (x + s, y + s)], outline)).map_err(e)?;
        }
        Kind::Saddle => {
            let s = size + 1;
            let pts = vec![(x, y - s), (x + s, y), (x, y + s), (x - s, y)];
            area.draw(&Polygon::new(pts.clone(), fill.filled())).map_err(e)?;
            let mut closed = pts;
            closed.push((x, y - s));
            area.draw(&PathElement::new(closed, outline)).map_err(e)?;
        }
    }
    Ok(())
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
    let err = |x: DrawingAreaErrorKind<DB::ErrorType>| format!("{x:?}");
    root.fill(&WHITE).map_err(err)?;
    let (views, legend) = root.split_vertically(h);
    let panels = views.split_evenly((1, 2));
    let axes = a.mass.principal_axes;
    // principal moments ascending: axis 0 = long axis a, axis 2 = short axis c
    let (ex, ez) = (axes.column(0).into_owned(), axes.column(2).into_owned());
    let g = a.mass.center_of_mass;
    let colors = flock_colors(r);
    let basin = a.basins();
    let facet_flock: Vec<Option<usize>> = basin.iter().map(|b| b.map(|s| r.equilibria[s].flock)).collect();
    for (panel, sign) in panels.iter().zip([1.0, -1.0]) {
        let view = ez * sign; // towards the viewer
        let right = ex;
        let up = view.cross(&right);
        let reach = |axis: &crate::Vec3| a.hull.vertices.iter().map(|p| (p - g).dot(axis).abs()).fold(0.0, f64::max);
        let scale = ((w as f64 / 2.0 - 40.0) / (2.0 * reach(&right))).min((h as f64 - 70.0) / (2.0 * reach(&up)));
        let (cx, cy) = (w as f64 / 4.0, h as f64 / 2.0 + 15.0);
        let project = |p: &Point3| -> (i32, i32) {
            let d = p - g;
            ((cx + d.dot(&right) * scale) as i32, (cy - d.dot(&up) * scale) as i32)
        };
        let light = (view * 0.8 + up * 0.4 + right * 0.2).normalize();
        // where to write each flock's label: the area-weighted mean of its visible facets
        let mut label_at = vec![(0.0f64, 0.0f64, 0.0f64); r.flocks.len()];
        for (f, facet) in a.hull.facets.iter().enumerate() {
            let facing = facet.normal.dot(&view);
            if facing <= 0.0 {
                continue;
            }
            let base = facet_flock[f].map_or(RGBColor(170, 170, 170), |k| colors[k]);
            let shade = 0.6 + 0.4 * facet.normal.dot(&light).max(0.0);
            let tint = |c: u8| ((c as f64 * 0.75 + 255.0 * 0.25) * shade).min(255.0) as u8;
            let poly: Vec<(i32, i32)> = facet.vertices.iter().map(|&v| project(&a.hull.vertices[v as usize])).collect();
            if let Some(k) = facet_flock[f] {
                let weight = facet.area * facing;
                let c = poly.iter().fold((0.0, 0.0), |s, p| (s.0 + p.0 as f64, s.1 + p.1 as f64));
                let n = poly.len() as f64;
                label_at[k].0 += weight * c.0 / n;
                label_at[k].1 += weight * c.1 / n;
                label_at[k].2 += weight;
            }
            panel
                .draw(&Polygon::new(poly, RGBColor(tint(base.0), tint(base.1), tint(base.2)).filled()))
                .map_err(err)?;
        }
        // label only the flocks seen over ≥ 3 % of the view (not slivers at the rim)
        let seen: f64 = label_at.iter().map(|l| l.2).sum();
        for (k, (x, y, wsum)) in label_at.iter().enumerate() {
            if *wsum <= 0.03 * seen {
                continue;
            }
            // beside the centre of the flock's facets, not on the mark that is often there
            let (x, y) = ((x / wsum) as i32 + 22, (y / wsum) as i32 - 20);
            let text = format!("F{k}");
            let half = 7 * text.chars().count() as i32 / 2 + 4;
            panel
                .draw(&Rectangle::new([(x - half, y - 10), (x + half, y + 10)], WHITE.mix(0.85).filled()))
                .map_err(err)?;
            panel
                .draw(&Rectangle::new([(x - half, y - 10), (x + half, y + 10)], BLACK.stroke_width(1)))
                .map_err(err)?;
            panel
                .draw(&Text::new(
                    text,
                    (x, y),
                    (FONT_FAMILY, style::LEGEND).into_font().color(&BLACK).pos(plotters::style::text_anchor::Pos::new(
                        plotters::style::text_anchor::HPos::Center,
                        plotters::style::text_anchor::VPos::Center,
                    )),
                ))
                .map_err(err)?;
        }
        let visible = |p: &Point3| (p - g).dot(&view) > 0.0;
        for arc in &a.graph.arcs {
            for seg in arc.path.windows(2) {
                if visible(&seg[0]) && visible(&seg[1]) {
                    panel
                        .draw(&PathElement::new(vec![project(&seg[0]), project(&seg[1])], BLACK.mix(0.6)))
                        .map_err(err)?;
                }
            }
        }
        for e in &r.equilibria {
            if visible(&e.point) {
                kind_mark(panel, e.kind, project(&e.point), 6, colors[e.flock])?;
            }
        }
        let title = format!(
            "{} (looking along {}c, the shortest axis)",
            if sign > 0.0 { "Front" } else { "Back" },
            if sign > 0.0 { "−" } else { "+" },
        );
        panel.draw(&Text::new(title, (12, 10), (FONT_FAMILY, style::PANEL_TITLE))).map_err(err)?;
    }
    // the legend: marks by kind, arcs, then one swatch per flock
    let font = (FONT_FAMILY, style::LEGEND);
    let y0 = 12;
    let mut x = 14;
    let items = [
        (Some(Kind::Stable), format!("stable micro-equilibrium (on a facet), {} in all", r.micro.stable)),
        (Some(Kind::Unstable), format!("unstable (a vertex), {}", r.micro.unstable)),
        (Some(Kind::Saddle), format!("saddle (an edge), {}", r.micro.saddle)),
        (None, "Morse–Smale arc".to_string()),
    ];
    for (kind, text) in items {
        match kind {
            Some(k) => kind_mark(&legend, k, (x + 8, y0 + 8), 6, RGBColor(200, 200, 200))?,
            None => legend.draw(&PathElement::new(vec![(x, y0 + 8), (x + 18, y0 + 8)], BLACK.mix(0.6))).map_err(err)?,
        }
        legend.draw(&Text::new(text.clone(), (x + 26, y0), font)).map_err(err)?;
        x += 26 + 8 * text.chars().count() as i32 + 30;
    }
    legend
        .draw(&Text::new(
            format!(
                "Facets are tinted by the flock their steepest descent drains to; marks are filled with their flock's \
                 colour. Flocks at ν = {} ({} stable, {} unstable, {} saddle):",
                number(r.r#macro.nu, 3),
                r.r#macro.stable,
                r.r#macro.unstable,
                r.r#macro.saddle
            ),
            (14, y0 + 30),
            font,
        ))
        .map_err(err)?;
    let col = (w as i32 - 28) / FLOCKS_PER_ROW as i32;
    for (i, f) in r.flocks.iter().enumerate() {
        let (cx, cy) = (14 + col * (i % FLOCKS_PER_ROW) as i32, y0 + 58 + 26 * (i / FLOCKS_PER_ROW) as i32);
        legend.draw(&Rectangle::new([(cx, cy), (cx + 18, cy + 16)], colors[f.id].filled())).map_err(err)?;
        legend.draw(&Rectangle::new([(cx, cy), (cx + 18, cy + 16)], BLACK.stroke_width(1))).map_err(err)?;
        let text = format!("F{}: {} flock ({} S, {} U, {} H)", f.id, f.kind, f.stable, f.unstable, f.saddle);
        legend.draw(&Text::new(text, (cx + 26, cy), font)).map_err(err)?;
    }
    Ok(())
}
