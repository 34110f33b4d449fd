//! Figure 5 of the paper: a stable, a rocking and an unstable equilibrium of the discretised
//! ellipse, each drawn resting on a ground line with G vertically above the contact point.
//!
//! Writes results/planar/fig5_equilibria.csv, fig5_rocking.png, fig5.md.
//! Run: `cargo run --release --example fig5_rocking_planar`.

use anyhow::{Context, Result};
use plotters::prelude::*;
use rocking_stones::hierarchy::Kind;
use rocking_stones::planar::{
    ellipse_polygon, sides_for_k, FlockContents, PlanarAnalysis, PlanarEquilibrium, PlanarSite, Point2, Sampling,
    DEFAULT_DEGENERACY_TOL,
};
use rocking_stones::plot::{colors, FONT_FAMILY};
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;

const A: f64 = 1.2;
const K: usize = 8;

fn main() -> Result<()> {
    let out = Path::new("results/planar");
    std::fs::create_dir_all(out)?;
    let n = sides_for_k(K);
    let an = PlanarAnalysis::new(ellipse_polygon(A, n, Sampling::ArcLength)?, DEFAULT_DEGENERACY_TOL)?;
    let report = an.report(None);
    let flocks = an.flocks_at(report.nu);
    let eq = &an.equilibria.points;
    let m = eq.len();
    let flock_kind = |i: usize| flocks.flocks[flocks.membership[i]].kind;
    // Depth of the potential well of a stable point: the lower of its two neighbouring maxima
    // (in G(0)) above it, normalised by R_max.
    let depth = |i: usize| {
        let (p, q) = (eq[(i + m - 1) % m].r, eq[(i + 1) % m].r);
        (p.min(q) - eq[i].r) / an.equilibria.r_max
    };
    // The three: the regular stable point at the bottom of a stable flock (smallest R), a
    // rocking one (stable in an unstable flock, the deepest such well), the unstable point at the
    // top of an unstable flock (largest R).
    let regular = (0..m)
        .filter(|&i| eq[i].kind == Kind::Stable && flock_kind(i) == Kind::Stable)
        .min_by(|&a, &b| eq[a].r.total_cmp(&eq[b].r))
        .context("no regular stable point")?;
    let rocking = (0..m)
        .filter(|&i| eq[i].kind == Kind::Stable && flock_kind(i) != Kind::Stable)
        .max_by(|&a, &b| depth(a).total_cmp(&depth(b)).then(b.cmp(&a)))
        .context("no rocking equilibrium: choose a < √2 and k large enough")?;
    let unstable = (0..m)
        .filter(|&i| eq[i].kind == Kind::Unstable)
        .max_by(|&a, &b| eq[a].r.total_cmp(&eq[b].r).then(b.cmp(&a)))
        .context("no unstable point")?;

    let mut w = csv::Writer::from_path(out.join("fig5_equilibria.csv"))?;
    w.write_record([
        "index",
        "kind",
        "site",
        "site_index",
        "phi",
        "R",
        "flock",
        "flock_type",
        "well_depth_over_Rmax",
        "role",
    ])?;
    for (i, e) in eq.iter().enumerate() {
        let role = if i == regular {
            "regular (figure)"
        } else if i == rocking {
            "rocking (figure)"
        } else if i == unstable {
            "unstable (figure)"
        } else if e.kind == Kind::Stable && flock_kind(i) != Kind::Stable {
            "rocking"
        } else {
            ""
        };
        let (site, si) = match e.site {
            PlanarSite::Side(s) => ("side", s),
            PlanarSite::Vertex(v) => ("vertex", v),
        };
        w.write_record([
            i.to_string(),
            format!("{:?}", e.kind).to_lowercase(),
            site.into(),
            si.to_string(),
            format!("{:.8}", e.phi),
            format!("{:.12}", e.r),
            flocks.membership[i].to_string(),
            format!("{:?}", flock_kind(i)).to_lowercase(),
            if e.kind == Kind::Stable { format!("{:.4e}", depth(i)) } else { String::new() },
            role.into(),
        ])?;
    }
    w.flush()?;

    let path = out.join("fig5_rocking.png");
    let items = [
        (regular, "stable (stable flock)", colors::VERMILLION),
        (rocking, "rocking (stable in unstable flock)", colors::ORANGE),
        (unstable, "unstable (unstable flock)", colors::BLUE),
    ];
    rocking_stones::plot::draw_png(&path, (1500, 560), |root| {
        root.fill(&WHITE)?;
        let (head, body) = root.split_vertically(50);
        head.titled(
            &format!("Discretised ellipse 1 : {A}, N = {n}. Dots: vermillion stable, orange rocking, blue unstable"),
            (FONT_FAMILY, 24),
        )?;
        let panels = body.split_evenly((1, 3));
        for (panel, &(i, title, colour)) in panels.iter().zip(&items) {
            draw_resting(panel, &an, &eq[i], title, colour, &an.equilibria.points, &|j| flock_kind(j))?;
        }
        Ok(())
    })?;

    let c = FlockContents::of(&report.flocks);
    let mut md = String::new();
    writeln!(md, "# Figure 5: stable, rocking and unstable equilibrium (planar)\n")?;
    writeln!(
        md,
        "Ellipse 1 : {A} (major axis x), N = 4k − 2 = {n} sides (k = {K}), arc-length sampling. Micro: S = U = {}; \
         flocks at the plateau ν = {:.3e}: stable flocks {:?}, unstable flocks {:?} (stable + unstable micro-equilibria). \
         Rocking equilibria (stable sides in unstable flocks): {}.\n",
        report.stable,
        report.nu,
        c.stable_flocks,
        c.unstable_flocks,
        report.rocking.len()
    )?;
    writeln!(md, "| figure | site | φ (rad) | R | flock type | well depth / R_max |")?;
    writeln!(md, "|---|---|---|---|---|---|")?;
    for &(i, title, _) in &items {
        let d = if eq[i].kind == Kind::Stable { format!("{:.3e}", depth(i)) } else { "— (a maximum)".into() };
        writeln!(md, "| {title} | {:?} | {:.4} | {:.6} | {:?} | {d} |", eq[i].site, eq[i].phi, eq[i].r, flock_kind(i))?;
    }
    writeln!(
        md,
        "\nThe rocking equilibrium is a genuine minimum of R — the stone can rest on it — but its micro-well (to the lower neighbouring maximum) is {:.0}× \
         shallower than the regular one's and it sits on top of the macro-scale peak: a small push rocks it to a \
         neighbouring micro-equilibrium of the same unstable flock, a larger one topples it into a stable flock. \
         Files: `fig5_rocking.png`, `fig5_equilibria.csv` (every micro-equilibrium with its flock and well depth).",
        depth(regular) / depth(rocking)
    )?;
    std::fs::write(out.join("fig5.md"), md)?;
    println!("wrote results/planar/fig5_rocking.png, fig5_equilibria.csv, fig5.md");
    Ok(())
}

/// Draw the polygon resting on `contact` (G vertically above it), the ground line, G, the
/// vertical through G, and the micro-equilibria coloured by flock type.
fn draw_resting<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    an: &PlanarAnalysis,
    contact: &PlanarEquilibrium,
    title: &str,
    colour: RGBColor,
    eqs: &[PlanarEquilibrium],
    flock_kind: &dyn Fn(usize) -> Kind,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let g = an.polygon.centroid;
    let u = contact.point - g;
    let angle = -PI / 2.0 - u.y.atan2(u.x);
    let g_new = Point2::new(0.0, u.norm());
    let place = |p: &Point2| {
        let d = p - g;
        let (s, c) = angle.sin_cos();
        (g_new.x + c * d.x - s * d.y, g_new.y + s * d.x + c * d.y)
    };
    let mut c = ChartBuilder::on(area)
        .caption(title, (FONT_FAMILY, 20))
        .margin(10)
        .build_cartesian_2d(-1.6..1.6, -0.25..2.55)
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    // Ground.
    c.draw_series(std::iter::once(Rectangle::new([(-1.6, -0.25), (1.6, 0.0)], RGBColor(225, 215, 195).filled())))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    c.draw_series(std::iter::once(PathElement::new(vec![(-1.6, 0.0), (1.6, 0.0)], BLACK.stroke_width(2))))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let mut v: Vec<(f64, f64)> = an.polygon.vertices.iter().map(place).collect();
    c.draw_series(std::iter::once(Polygon::new(v.clone(), RGBColor(200, 200, 200).mix(0.6).filled())))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    v.push(v[0]);
    c.draw_series(std::iter::once(PathElement::new(v, BLACK.stroke_width(2)))).map_err(|e| anyhow::anyhow!("{e}"))?;
    // Micro-equilibria: stable in stable flocks red, rocking orange, unstable blue.
    c.draw_series(eqs.iter().enumerate().map(|(i, p)| {
        let col = match (p.kind, flock_kind(i)) {
            (Kind::Stable, Kind::Stable) => colors::VERMILLION,
            (Kind::Stable, _) => colors::ORANGE,
            _ => colors::BLUE,
        };
        Circle::new(place(&p.point), 4, col.filled())
    }))
    .map_err(|e| anyhow::anyhow!("{e}"))?;
    // Vertical through G and the contact point.
    c.draw_series(std::iter::once(PathElement::new(vec![(0.0, 0.0), (0.0, g_new.y)], BLACK.mix(0.6).stroke_width(1))))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    c.draw_series(std::iter::once(Circle::new((0.0, g_new.y), 6, BLACK.filled())))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    c.draw_series(std::iter::once(Text::new("G", (0.06, g_new.y + 0.08), (FONT_FAMILY, 18))))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    c.draw_series(std::iter::once(Circle::new((0.0, 0.0), 9, colour.stroke_width(3))))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    c.draw_series(std::iter::once(Text::new(format!("R = {:.4}", contact.r), (0.1, -0.15), (FONT_FAMILY, 16))))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(())
}
