//! Figure 5 of the paper: a stable, a rocking and an unstable equilibrium of the discretised
//! ellipse, each drawn resting on a ground line with G vertically above the contact point.
//!
//! Run: `cargo experiment fig5_rocking_planar` → `results/planar/`
//! (fig5_equilibria.csv, fig5_rocking.png, fig5.md); the README's prose is
//! `experiments/readme/fig5_rocking_planar.md`.

use rocking_stones::hierarchy::Kind;
use rocking_stones::planar::{sides_for_k, FlockContents, PlanarAnalysis, PlanarSite, Point2, Sampling};
use rocking_stones::prelude::*;

use experiments::harness;
use harness::{Context, Result, Results};

const A: f64 = 1.2;
const K: usize = 8;
const BLACK: RGBColor = RGBColor(0, 0, 0);

fn main() -> Result<()> {
    let common = harness::common_args("A stable, a rocking and an unstable equilibrium of the discretised ellipse.");
    let out = Results::open("planar", &common)?;
    let n = sides_for_k(K);
    let an = PlanarAnalysis::of_ellipse(A, n, Sampling::ArcLength)?;
    let report = an.report(None);
    let flocks = an.flocks_at(report.nu);
    let eq = &an.equilibria.points;
    let m = eq.len();
    // Depth of the potential well of a stable point (over R_max; only stable points have one).
    let depth = |i: usize| an.equilibria.well_depth(i).unwrap_or(f64::NAN);
    // The three: the regular stable point at the bottom of a stable flock (smallest R), a
    // rocking one (stable in an unstable flock, the deepest such well), the unstable point at the
    // top of an unstable flock (largest R).
    let pick = |keep: &dyn Fn(usize) -> bool, key: &dyn Fn(usize) -> f64| {
        (0..m).filter(|&i| keep(i)).max_by(|&a, &b| key(a).total_cmp(&key(b)).then(b.cmp(&a)))
    };
    let rocks = |i: usize| eq[i].kind == Kind::Stable && flocks.kind_of(i) != Kind::Stable;
    let regular =
        pick(&|i| eq[i].kind == Kind::Stable && !rocks(i), &|i| -eq[i].r).context("no regular stable point")?;
    let rocking = pick(&rocks, &depth).context("no rocking equilibrium: choose a < √2 and k large enough")?;
    let unstable = pick(&|i| eq[i].kind == Kind::Unstable, &|i| eq[i].r).context("no unstable point")?;

    let mut csv = String::from("index,kind,site,site_index,phi,R,flock,flock_type,well_depth_over_Rmax,role\n");
    for (i, e) in eq.iter().enumerate() {
        let role = match i {
            _ if i == regular => "regular (figure)",
            _ if i == rocking => "rocking (figure)",
            _ if i == unstable => "unstable (figure)",
            _ if rocks(i) => "rocking",
            _ => "",
        };
        let (site, si) = match e.site {
            PlanarSite::Side(s) => ("side", s),
            PlanarSite::Vertex(v) => ("vertex", v),
        };
        let d = if e.kind == Kind::Stable { format!("{:.4e}", depth(i)) } else { String::new() };
        let (kind, flock, fk) = (e.kind.name(), flocks.membership[i], flocks.kind_of(i).name());
        csv += &format!("{i},{kind},{site},{si},{:.8},{:.12},{flock},{fk},{d},{role}\n", e.phi, e.r);
    }
    out.write("fig5_equilibria.csv", csv)?;

    // Each one drawn resting on its contact point (G vertically above it) on the ground, with G,
    // the vertical through G, and the micro-equilibria: stable in stable flocks vermillion,
    // rocking orange, unstable blue.
    let bare = |lo, hi| Axis::linear("", lo, hi).ticks(0).no_grid().space(0);
    let dot = |j: usize| match (eq[j].kind, rocks(j)) {
        (Kind::Stable, false) => colors::VERMILLION,
        (Kind::Stable, true) => colors::ORANGE,
        _ => colors::BLUE,
    };
    let resting = |i: usize, title: &str| {
        let rest = an.polygon.resting_on(eq[i].point);
        let place = |p: &Point2| (rest(p).x, rest(p).y);
        let gy = rest(&an.polygon.centroid).y;
        let mut v: Vec<(f64, f64)> = an.polygon.vertices.iter().map(place).collect();
        let mut chart = Chart::new(bare(-1.6, 1.6), bare(-0.25, 2.55))
            .title(title)
            .boxes(&[(-1.6, -0.25, 1.6, 0.0)], RGBColor(225, 215, 195), 1.0) // the ground
            .line_width(&[(-1.6, 0.0), (1.6, 0.0)], BLACK, 2)
            .polygon(&v, RGBColor(200, 200, 200), 0.6);
        v.push(v[0]);
        chart = chart.line_width(&v, BLACK, 2);
        for (j, p) in eq.iter().enumerate() {
            chart = chart.dots(&[place(&p.point)], dot(j));
        }
        chart
            .line_width(&[(0.0, 0.0), (0.0, gy)], colors::GREY, 1)
            .markers_sized(&[(0.0, gy)], BLACK, Marker::Dot, 6)
            .text("G", (0.06, gy + 0.08))
            .markers_sized(&[(0.0, 0.0)], dot(i), Marker::Ring, 9)
            .text(format!("R = {:.4}", eq[i].r), (0.1, -0.15))
    };
    let (mut panels, mut rows) = (Vec::new(), Vec::new());
    for (i, title) in [
        (regular, "stable (stable flock)"),
        (rocking, "rocking (stable in unstable flock)"),
        (unstable, "unstable (unstable flock)"),
    ] {
        panels.push(resting(i, title));
        let d = if eq[i].kind == Kind::Stable { format!("{:.3e}", depth(i)) } else { "— (a maximum)".into() };
        rows.push(serde_json::json!({
            "title": title, "site": format!("{:?}", eq[i].site), "phi": format!("{:.4}", eq[i].phi),
            "r": format!("{:.6}", eq[i].r), "flock": format!("{:?}", flocks.kind_of(i)), "depth": d,
        }));
    }
    let title = format!("Discretised ellipse 1 : {A}, N = {n}. Dots: vermillion stable, orange rocking, blue unstable");
    Figure::new(title, 3, panels).save(&out.path("fig5_rocking.png"), (1500, 560))?;
    let c = FlockContents::of(&report.flocks);
    out.page(
        "fig5.md",
        include_str!("readme/fig5_rocking_planar.md"),
        serde_json::json!({
            "a": A.to_string(), "n": n, "k": K, "s": report.stable, "nu": format!("{:.3e}", report.nu),
            "stable_flocks": format!("{:?}", c.stable_flocks), "unstable_flocks": format!("{:?}", c.unstable_flocks),
            "rocking": report.rocking.len(), "rows": rows, "ratio": format!("{:.0}", depth(regular) / depth(rocking)),
        }),
    )
}
