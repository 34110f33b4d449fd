//! Figure 2 of the paper: R(φ) of the smooth ellipse (S = U = 2) and of its N = 100
//! arc-length discretisation, with the equilibria marked and the flocks zoomed.
//!
//! Writes results/planar/fig2_r_phi.csv, fig2_equilibria.csv, fig2_r_phi.png, fig2.md (its prose
//! is `experiments/readme/fig2_planar_r_phi.md`).
//! Run: `cargo experiment fig2_planar_r_phi`.

use rocking_stones::hierarchy::Kind;
use rocking_stones::planar::{ellipse_radius, FlockContents, PlanarAnalysis, Sampling};
use rocking_stones::plot::{plain, OKABE_ITO};
use rocking_stones::prelude::*;
use std::f64::consts::PI;

use experiments::harness;
use harness::{Context, Result, Results};

const A: f64 = 1.2;
const N: usize = 100;
const SAMPLES: usize = 4000;

fn main() -> Result<()> {
    let common = harness::common_args("R(φ) of the smooth and the discretised ellipse.");
    let out = Results::open("planar", &common)?;
    let an = PlanarAnalysis::of_ellipse(A, N, Sampling::ArcLength)?;
    let report = an.report(None);
    let flocks = an.flocks_at(report.nu);
    // G of the polygon is the origin up to rounding (the polygon is symmetric).
    anyhow::ensure!(an.polygon.centroid.coords.norm() < 1e-12, "the polygon's centroid is off the origin");

    // φ in [−π/2, 3π/2) so that the two stable flocks (φ = ±π/2) and the unstable ones (0, π)
    // are all away from the ends of the axis.
    let wrap = |phi: f64| if phi < -PI / 2.0 { phi + 2.0 * PI } else { phi };
    let curve: Vec<(f64, f64, f64)> = (0..SAMPLES)
        .map(|i| {
            let phi = -PI / 2.0 + 2.0 * PI * i as f64 / SAMPLES as f64;
            (phi, ellipse_radius(A, phi), an.polygon.radius_at(phi))
        })
        .collect();
    out.csv(
        "fig2_r_phi.csv",
        &["phi", "R_smooth", "R_polygon"],
        curve.iter().map(|(p, s, q)| [format!("{p:.8}"), format!("{s:.12}"), format!("{q:.12}")]),
    )?;
    // Each micro-equilibrium: φ (wrapped), R, its kind, its flock and the flock's kind.
    let eqs: Vec<(f64, f64, Kind, usize, Kind)> = (an.equilibria.points.iter().enumerate())
        .map(|(i, p)| (wrap(p.phi), p.r, p.kind, flocks.membership[i], flocks.kind_of(i)))
        .collect();
    let name = |k: Kind| k.name().to_string();
    out.csv(
        "fig2_equilibria.csv",
        &["phi", "R", "kind", "flock", "flock_type"],
        (eqs.iter()).map(|e| [format!("{:.8}", e.0), format!("{:.12}", e.1), name(e.2), e.3.to_string(), name(e.4)]),
    )?;
    let title_b = format!(
        "B. N = {N} (arc length): S = {}, U = {}, {} flocks",
        report.stable,
        report.unstable,
        report.flocks.len()
    );
    plot(&out, &curve, &eqs, &title_b)?;

    let contents = FlockContents::of(&report.flocks);
    let p = report.plateau.context("n(ν) has no plateau")?;
    let e3 = |x: f64| format!("{x:.3e}");
    out.page(
        "fig2.md",
        include_str!("readme/fig2_planar_r_phi.md"),
        serde_json::json!({
            "a": A.to_string(),
            "n": N,
            "s": report.stable,
            "u": report.unstable,
            "nu_lo": e3(p.nu_lo),
            "nu_hi": e3(p.nu_hi),
            "decades": format!("{:.2}", p.decades),
            "clear": if p.clear { "clear" } else { "not clear" },
            "nu": e3(report.nu),
            "flocks": report.flocks.len(),
            "stable_flocks": format!("{:?}", contents.stable_flocks),
            "unstable_flocks": format!("{:?}", contents.unstable_flocks),
            "rocking": report.rocking.len(),
            "as_measured": contents.stable_flocks.iter().all(|&f| f == (4, 3)),
        }),
    )?;
    println!("wrote results/planar/fig2_r_phi.{{png,csv}}, fig2_equilibria.csv, fig2.md");
    Ok(())
}

/// The four panels: the smooth ellipse, the polygon, and zooms on a stable and an unstable flock.
fn plot(out: &Results, curve: &[(f64, f64, f64)], eqs: &[(f64, f64, Kind, usize, Kind)], title_b: &str) -> Result<()> {
    let black = OKABE_ITO[0];
    let dots = |c: Chart, e: &[(f64, f64, Kind, usize, Kind)], size| {
        let colour = |k: Kind| if k == Kind::Stable { colors::VERMILLION } else { colors::BLUE };
        e.iter().fold(c, |c, e| c.markers_sized(&[(e.0, e.1)], colour(e.2), Marker::Dot, size))
    };
    let (phi, r) = (Axis::linear("φ (rad)", -PI / 2.0, 1.5 * PI), Axis::linear("R", 0.95, A + 0.05));
    let (st, un) = (Kind::Stable, Kind::Unstable);
    let smooth_eqs = [(-PI / 2.0, 1.0, st, 0, st), (0.0, A, un, 0, un), (PI / 2.0, 1.0, st, 0, st), (PI, A, un, 0, un)];
    let a = Chart::new(phi.clone(), r.clone())
        .title(format!("A. smooth ellipse 1 : {A}: S = U = 2 (vermillion: stable, blue: unstable)"))
        .line(&curve.iter().map(|p| (p.0, p.1)).collect::<Vec<_>>(), black);
    let b =
        Chart::new(phi, r).title(title_b).line_width(&curve.iter().map(|p| (p.0, p.2)).collect::<Vec<_>>(), black, 1);
    let mut panels = vec![dots(a, &smooth_eqs, 7), dots(b, eqs, 5)];
    // C, D: zooms on a stable flock (φ = π/2) and an unstable flock (φ = 0).
    for (centre, title) in [(PI / 2.0, "C. zoom: stable flock at φ = π/2"), (0.0, "D. zoom: unstable flock at φ = 0")]
    {
        let half = 0.16;
        let inside = |p: f64| (p - centre).abs() <= half;
        let pts: Vec<(f64, f64)> = curve.iter().filter(|p| inside(p.0)).map(|p| (p.0, p.2)).collect();
        let smooth: Vec<(f64, f64)> = curve.iter().filter(|p| inside(p.0)).map(|p| (p.0, p.1)).collect();
        let (lo, hi) =
            pts.iter().chain(&smooth).fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| (l.min(p.1), h.max(p.1)));
        let pad = (hi - lo) * 0.08;
        let near: Vec<_> = eqs.iter().copied().filter(|e| inside(e.0)).collect();
        // Rocking equilibria: stable points in an unstable flock, ringed.
        let rocking: Vec<_> = near.iter().filter(|e| e.2 == st && e.4 != st).map(|e| (e.0, e.1)).collect();
        let c = Chart::new(
            // ticks at 0 come with float noise (−2.8e-17)
            Axis::linear("φ (rad)", centre - half, centre + half)
                .format(|v| plain(if v.abs() < 1e-9 { 0.0 } else { v })),
            Axis::linear("R", lo - pad, hi + pad).format(|v| format!("{v:.4}")),
        )
        .title(title)
        .legend(Mark::Line(colors::GREY), "smooth")
        .legend(Mark::Line(black), format!("N = {N}"))
        .legend(Mark::Ring(colors::ORANGE), "rocking (stable in unstable flock)")
        .line_width(&smooth, colors::GREY, 1)
        .line(&pts, black);
        panels.push(dots(c, &near, 6).markers_sized(&rocking, colors::ORANGE, Marker::Ring, 11));
    }
    Figure::new("Figure 2: R(φ) of the smooth and the discretised ellipse", 2, panels)
        .save(&out.path("fig2_r_phi.png"), (1400, 1000))?;
    Ok(())
}
