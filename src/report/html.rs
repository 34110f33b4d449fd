//! `report.html`: one self-contained page per run (`analyze`, `drop`, `perturb`, `shake` with
//! `-o`): the summary, the run's plots (PNG embedded as base64 `data:` URIs) and an interactive
//! 3D view of the convex hull, with no network access when opened.
//!
//! The 3D view is a small hand-written canvas-2D renderer (`assets/report.js`), not a bundled
//! WebGL library: a convex hull needs no z-buffer, because back-face culling of its facets is
//! exact visibility (two front-facing facets of a convex body never overlap on the screen), and
//! a point on the surface (an equilibrium, a Morse–Smale arc segment) is visible exactly when one
//! of the facets it lies on faces the viewer. So the page draws the front facets in any order,
//! then the arcs and marks whose facets face the viewer; the data lists, for each of them, the
//! facets it lies on. ~300 lines of JavaScript replace a 600 kB library and its licence.
//!
//! The page checks itself: after the first draw it counts the canvas pixels that differ from the
//! background (`getImageData`) and writes `data-status="drawn"` and `data-nonblank` on
//! `#status`; `window.onerror` writes any script error into `#errors`. The headless-browser test
//! (`.ci/report_html.sh`) reads both from Chromium's `--dump-dom`.
//!
//! Base64 is the ten lines of [`base64`] (RFC 4648 §4, checked against the RFC's test vectors)
//! rather than a dependency.

use super::names::Unit;
use crate::analysis::{Analysis, Report};
use crate::equilibria::Site;
use serde::Serialize;
use std::path::Path;

const TEMPLATE: &str = include_str!("assets/report.html");
const SCRIPT: &str = include_str!("assets/report.js");

/// Standard base64 (RFC 4648 §4, with `=` padding) of `bytes`.
pub fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(A[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// The hull as the 3D view draws it: coordinates relative to G in the mesh's units.
#[derive(Clone, Debug, Serialize)]
pub struct HullView {
    /// Hull vertices − G.
    pub vertices: Vec<[f64; 3]>,
    /// Facets: corner indices (counter-clockwise from outside), outward normal, flock of the
    /// basin the facet drains to (`None`: no stable basin).
    pub facets: Vec<FacetView>,
    /// Every micro-equilibrium.
    pub equilibria: Vec<EquilibriumView>,
    /// Morse–Smale arcs: segments (two points − G) with the facets each lies on.
    pub arcs: Vec<SegmentView>,
    /// Flocks: id, type, colour and contents.
    pub flocks: Vec<FlockView>,
    /// Length unit of the mesh ("mm", or "mesh units").
    pub unit: String,
    /// R_max (for R/R_max in tooltips).
    pub r_max: f64,
}

/// One facet of [`HullView`].
#[derive(Clone, Debug, Serialize)]
pub struct FacetView {
    /// Corner indices.
    pub v: Vec<u32>,
    /// Outward unit normal.
    pub n: [f64; 3],
    /// Flock of its basin.
    pub flock: Option<usize>,
}

/// One micro-equilibrium of [`HullView`].
#[derive(Clone, Debug, Serialize)]
pub struct EquilibriumView {
    /// Index in the report's `equilibria`.
    pub index: usize,
    /// "stable", "unstable" or "saddle".
    pub kind: &'static str,
    /// "facet 12", "edge 40", "vertex 7".
    pub site: String,
    /// Point − G.
    pub p: [f64; 3],
    /// Distance from G (mesh units).
    pub r: f64,
    /// Flock id.
    pub flock: usize,
    /// Hull facets it lies on (visible iff one faces the viewer).
    pub on: Vec<u32>,
}

/// One straight piece of a Morse–Smale arc.
#[derive(Clone, Debug, Serialize)]
pub struct SegmentView {
    /// Start − G.
    pub a: [f64; 3],
    /// End − G.
    pub b: [f64; 3],
    /// Hull facets it lies on.
    pub on: Vec<u32>,
}

/// One flock of [`HullView`].
#[derive(Clone, Debug, Serialize)]
pub struct FlockView {
    /// Flock id.
    pub id: usize,
    /// Its type.
    pub kind: &'static str,
    /// "#rrggbb", the colour of the PNG pictures ([`crate::plot::flock_color`]).
    pub color: String,
    /// Stable, unstable, saddle micro-equilibria in it.
    pub counts: [usize; 3],
}

fn arr(p: crate::Vec3) -> [f64; 3] {
    [p.x, p.y, p.z]
}

/// The data of the 3D view of one analysis.
pub fn hull_view(a: &Analysis, r: &Report, unit: &Unit) -> HullView {
    let g = a.mass.center_of_mass;
    let hull = &a.hull;
    let basin = a.basins();
    let facets = hull
        .facets
        .iter()
        .enumerate()
        .map(|(f, facet)| FacetView {
            v: facet.vertices.clone(),
            n: arr(facet.normal),
            flock: basin[f].map(|s| r.equilibria[s].flock),
        })
        .collect();
    let mut vertex_facets = vec![Vec::new(); hull.vertices.len()];
    for (f, facet) in hull.facets.iter().enumerate() {
        for &v in &facet.vertices {
            vertex_facets[v as usize].push(f as u32);
        }
    }
    let equilibria = r
        .equilibria
        .iter()
        .map(|e| {
            let (site, on) = match e.site {
                Site::Facet(f) => (format!("facet {f}"), vec![f]),
                Site::Edge(k) => (format!("edge {k}"), hull.edges[k as usize].facets.to_vec()),
                Site::Vertex(v) => (format!("vertex {v}"), vertex_facets[v as usize].clone()),
            };
            EquilibriumView {
                index: e.index,
                kind: e.kind.name(),
                site,
                p: arr(e.point - g),
                r: e.r,
                flock: e.flock,
                on,
            }
        })
        .collect();
    // A segment of an arc lies on the facets whose planes hold its midpoint (within 10⁻⁷ of the
    // hull's size): one facet inside a facet, two along an edge.
    let tol = 1e-7 * hull.diameter.max(f64::MIN_POSITIVE);
    let mut arcs = Vec::new();
    for arc in &a.graph.arcs {
        for seg in arc.path.windows(2) {
            let m = (seg[0].coords + seg[1].coords) / 2.0;
            let on: Vec<u32> = hull
                .facets
                .iter()
                .enumerate()
                .filter(|(_, f)| (f.normal.dot(&m) - f.offset).abs() <= tol.max(1e-9 * f.offset.abs()))
                .map(|(i, _)| i as u32)
                .collect();
            if (seg[1] - seg[0]).norm() > 0.0 {
                arcs.push(SegmentView { a: arr(seg[0] - g), b: arr(seg[1] - g), on });
            }
        }
    }
    let flocks = r
        .flocks
        .iter()
        .map(|f| {
            let c = crate::plot::flock_color(f.id);
            FlockView {
                id: f.id,
                kind: f.kind.name(),
                color: format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2),
                counts: [f.stable, f.unstable, f.saddle],
            }
        })
        .collect();
    HullView {
        vertices: hull.vertices.iter().map(|p| arr(p - g)).collect(),
        facets,
        equilibria,
        arcs,
        flocks,
        unit: unit.length(),
        r_max: r.micro.r_max,
    }
}

/// Escape text for HTML.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// The page: `title`, the `summary` text (as printed by the CLI), the PNG files `images` (with a
/// caption each; read and embedded), and the 3D view of `hull` (if any).
pub fn page(title: &str, summary: &str, images: &[(&Path, String)], hull: Option<&HullView>) -> crate::Result<String> {
    let mut figures = String::new();
    for (path, caption) in images {
        let bytes = std::fs::read(path).map_err(|error| crate::Error::Io { path: path.to_path_buf(), error })?;
        figures.push_str(&format!(
            "<figure><img alt=\"{0}\" src=\"data:image/png;base64,{1}\"><figcaption>{0}</figcaption></figure>\n",
            escape(caption),
            base64(&bytes)
        ));
    }
    let data = match hull {
        // `</` cannot close the script element inside JSON: escape every `<`.
        Some(h) => {
            serde_json::to_string(h).map_err(|e| crate::Error::write(crate::error::MEMORY, e))?.replace('<', "\\u003c")
        }
        None => "null".into(),
    };
    Ok(TEMPLATE
        .replace("{{TITLE}}", &escape(title))
        .replace("{{SUMMARY}}", &escape(summary))
        .replace("{{FIGURES}}", &figures)
        .replace("{{SCRIPT}}", SCRIPT)
        .replace("{{DATA}}", &data))
}

/// Write `page(...)` to `path`.
pub fn write_page(
    path: &Path,
    title: &str,
    summary: &str,
    images: &[(&Path, String)],
    hull: Option<&HullView>,
) -> crate::Result<()> {
    let text = page(title, summary, images, hull)?;
    std::fs::write(path, text).map_err(|error| crate::Error::Io { path: path.to_path_buf(), error })
}

/// How to read each picture a run writes, one line (the captions of `report.html`).
pub fn caption(file_name: &str) -> String {
    match file_name {
        "n_nu.png" => "n(ν) = N(ν)/N(0): the fraction of micro-equilibria left when the hierarchy cancels pairs up to ν; \
                       the long flat step (shaded) is the plateau, the dashed line the macro scale.",
        "hull.png" => "The hull seen from both sides of its shortest axis: facets tinted by flock (labels F0, F1, …), \
                       marks by kind (● stable, ■ unstable, ◆ saddle), thin lines the Morse–Smale arcs.",
        "robustness.png" => "Per stable micro-equilibrium: how often the pushed stone comes back (blue), stays in its \
                             flock (green) or topples (vermillion) against the energy ε; dashed: static barriers and ε*.",
        "thresholds.png" => "Dynamic threshold ε₅₀ (half the trials leave) against the static barrier: every point lies \
                             above the diagonal, the barrier is a lower bound.",
        "drops_flocks.png" => "Where the dropped stone came to rest, per flock, with 95 % intervals, beside the \
                               quasi-static basin probabilities.",
        "drops_facets.png" => "The same per stable facet (micro-equilibrium).",
        "fragility.png" => "Fragility: the probability that shaking topples the stone against the peak ground acceleration.",
        "fragility_surface.png" => "Every run in the (PGA, PGV/PGA) plane (filled: overturned) with the fitted \
                                    P(overturn) = 0.1, 0.5, 0.9 contours; with an ensemble, each contour's 95 % band.",
        "tipping_polar.png" => "Quasi-static tipping acceleration tan α (in g) against the azimuth of the side the rock \
                                tips about, for each base-contact tolerance; dots: the minimum.",
        other => return other.to_string(),
    }
    .to_string()
}

/// Add `report.html` to an output folder: `title`, `summary`, every PNG already `written` into
/// it (with its [`caption`]) and the 3D view `hull`; the page is appended to `written`.
pub fn add_page(
    dir: &Path,
    written: &mut Vec<std::path::PathBuf>,
    title: &str,
    summary: &str,
    hull: Option<&HullView>,
) -> crate::Result<()> {
    let images: Vec<(&Path, String)> = written
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .map(|p| (p.as_path(), caption(&p.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default())))
        .collect();
    let path = dir.join("report.html");
    write_page(&path, title, summary, &images, hull)?;
    written.push(path);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc_4648_test_vectors() {
        for (plain, coded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(plain.as_bytes()), coded);
        }
    }
}
