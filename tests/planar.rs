//! The planar case against the paper (Table 1, Figure 4 caption) and against theorems: S = U on
//! every polygon, regular n-gons, the hierarchy invariants, and agreement with the 3D code on a
//! prism. Expected numbers come from the paper's formulas or from geometry, never from our own
//! output.

use proptest::prelude::*;
use rocking_stones::equilibria::Equilibria;
use rocking_stones::hierarchy::Kind;
use rocking_stones::hull::{Polyhedron, DEFAULT_COPLANAR_TOL};
use rocking_stones::planar::{
    ellipse_polygon, ellipse_vertices, sides_for_k, EllipseArc, FlockContents, PlanarAnalysis, PlanarEquilibria,
    PlanarSite, Point2, Polygon, Sampling, DEFAULT_DEGENERACY_TOL,
};
use rocking_stones::Point3;
use std::f64::consts::PI;

/// m = ⌊a²/(2(a² − 1))⌋ of Table 1, written out here independently of the library.
fn paper_m(a: f64) -> usize {
    (a * a / (2.0 * (a * a - 1.0))).floor() as usize
}

fn analyse(p: Polygon) -> PlanarAnalysis {
    PlanarAnalysis::new(p, DEFAULT_DEGENERACY_TOL).expect("planar analysis")
}

/// Table 1 and the caption of Figure 4, read at the automatic plateau. The limit is reached
/// for every a here by k = 23 (a = 1.05 is the slowest; k* = 23, 18, 6, 3, 4, 1 for the six a,
/// see results/planar/table1.md);
/// we check k = 200 and k = 1000.
#[test]
fn table1_limit_of_the_arc_length_ellipse() {
    for a in [1.05, 1.1, 1.2, 1.3, 1.5, 2.0] {
        let m = paper_m(a);
        for k in [200, 1000] {
            let an = analyse(ellipse_polygon(a, sides_for_k(k), Sampling::ArcLength).unwrap());
            let r = an.report(None);
            let p = r.plateau.expect("a plateau");
            assert!(p.clear, "a = {a}, k = {k}: plateau not clear: {p:?}");
            assert_eq!((r.macro_counts.stable, r.macro_counts.unstable), (2, 2), "a = {a}, k = {k}: macro counts");
            let c = FlockContents::of(&r.flocks);
            assert_eq!(c.stable_flocks, vec![(2 * m + 1, 2 * m); 2], "a = {a}, k = {k}: stable flocks");
            assert_eq!(c.unstable_flocks, vec![(2 * m, 2 * m + 1); 2], "a = {a}, k = {k}: unstable flocks");
            assert_eq!(r.stable, 8 * m + 2, "a = {a}, k = {k}: total S");
            assert_eq!(r.unstable, 8 * m + 2, "a = {a}, k = {k}: total U");
            // The rocking equilibria are exactly the stable sides of the unstable flocks.
            assert_eq!(r.rocking.len(), 4 * m, "a = {a}, k = {k}: rocking equilibria");
            for x in &r.rocking {
                assert!(x.phi.cos().abs() > 0.99, "a = {a}: rocking side at φ = {} is not near the major axis", x.phi);
            }
        }
    }
}

/// The geometry of the paper's discretisation: vertices at both ends of the major axis, side
/// midpoints at both ends of the minor axis, equal arc length between vertices.
#[test]
fn arc_length_discretisation() {
    let a: f64 = 1.7;
    let k = 9;
    let n = sides_for_k(k);
    let v = ellipse_vertices(a, n, Sampling::ArcLength).unwrap();
    assert_eq!(v[0], Point2::new(a, 0.0));
    assert!((v[n / 2] - Point2::new(-a, 0.0)).norm() < 1e-15);
    // N/4 = k − 1/2: the side (k − 1, k) is centred on the minor axis end (0, 1).
    let mid = Point2::from((v[k - 1].coords + v[k].coords) / 2.0);
    assert!(mid.x.abs() < 1e-15 && mid.y > 0.9, "{mid:?}");
    // Equal arc lengths, integrated here by composite Simpson on t (independent of the
    // library's Gauss–Legendre).
    let speed = |t: f64| (a * t.sin()).hypot(t.cos());
    let simpson = |lo: f64, hi: f64| {
        let m = 20_000;
        let h = (hi - lo) / m as f64;
        let mut s = speed(lo) + speed(hi);
        for i in 1..m {
            s += speed(lo + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
        }
        s * h / 3.0
    };
    let t = |p: &Point2| {
        let t = p.y.atan2(p.x / a);
        if t < 0.0 {
            t + 2.0 * PI
        } else {
            t
        }
    };
    let total = EllipseArc::new(a).perimeter();
    for i in 0..n {
        let (t0, mut t1) = (t(&v[i]), t(&v[(i + 1) % n]));
        if t1 <= t0 {
            t1 += 2.0 * PI;
        }
        let s = simpson(t0, t1);
        assert!((s - total / n as f64).abs() < 1e-12, "side {i}: arc {s} vs {}", total / n as f64);
    }
}

/// The perimeter against the Gauss–Kummer series π(a + b) Σ C(1/2, j)² h^j, h = ((a−b)/(a+b))².
#[test]
fn perimeter_against_gauss_kummer() {
    for a in [1.0f64, 1.05, 1.5, 2.0, 3.0] {
        let h = ((a - 1.0) / (a + 1.0)).powi(2);
        let (mut sum, mut c, mut hp) = (1.0, 1.0, 1.0);
        for j in 1..200 {
            c *= (0.5 - (j - 1) as f64) / j as f64; // C(1/2, j)
            hp *= h;
            sum += c * c * hp;
        }
        let series = PI * (a + 1.0) * sum;
        let p = EllipseArc::new(a).perimeter();
        assert!((p - series).abs() < 1e-13 * series, "a = {a}: {p} vs {series}");
    }
}

#[test]
fn regular_polygons_have_n_stable_and_n_unstable_points() {
    for n in 3..=60 {
        let p = Polygon::regular(n, 0.3 + n as f64 * 0.1, 0.1 * n as f64).unwrap();
        let e = PlanarEquilibria::new(&p, DEFAULT_DEGENERACY_TOL).unwrap();
        assert_eq!((e.stable, e.unstable), (n, n), "regular {n}-gon");
        assert_eq!(e.degenerate_decisions, 0);
        // Every cancellation ties: G(0) is its own macro scale.
        let an = analyse(p);
        let r = an.report(None);
        assert_eq!((r.macro_counts.stable, r.macro_counts.unstable), (n, n), "regular {n}-gon macro");
    }
}

/// Other samplings give valid polygons with S = U and the same macro structure 2 + 2.
#[test]
fn angle_and_random_samplings() {
    for sampling in [Sampling::Angle, Sampling::Random { seed: 7 }] {
        let an = analyse(ellipse_polygon(1.5, 400, sampling).unwrap());
        let r = an.report(None);
        assert_eq!(r.stable, r.unstable);
        assert_eq!((r.macro_counts.stable, r.macro_counts.unstable), (2, 2), "{sampling:?}");
        assert!(r.plateau.unwrap().clear, "{sampling:?}");
    }
    // The same seed gives the same polygon.
    let a = ellipse_vertices(1.3, 50, Sampling::Random { seed: 3 }).unwrap();
    let b = ellipse_vertices(1.3, 50, Sampling::Random { seed: 3 }).unwrap();
    assert_eq!(a, b);
}

/// A body without separated scales (a polygon inscribed in a circle, random vertices) gets no
/// clear plateau.
#[test]
fn circle_like_polygons_have_no_clear_plateau() {
    let mut clear = 0;
    for seed in 0..20 {
        let p = ellipse_polygon(1.0, 300, Sampling::Random { seed }).unwrap();
        let an = analyse(p);
        let pl = an.hierarchy.plateau().unwrap();
        clear += usize::from(pl.clear);
    }
    assert_eq!(clear, 0, "{clear} of 20 circle-like polygons reported a clear plateau");
}

/// A prism over a polygon: the 3D code sees the polygon's stable sides as stable side facets
/// (same R), its unstable vertices as two unstable vertices each, and S + U − H = 2 with
/// S₃ = S₂ + 2, U₃ = 2U₂, H₃ = U₂ + 2S₂.
#[test]
fn prism_agrees_with_the_3d_code() {
    for (a, k) in [(1.3, 4), (1.1, 6)] {
        let poly = ellipse_polygon(a, sides_for_k(k), Sampling::ArcLength).unwrap();
        let e2 = PlanarEquilibria::new(&poly, DEFAULT_DEGENERACY_TOL).unwrap();
        let h = 0.7;
        let pts: Vec<Point3> =
            poly.vertices.iter().flat_map(|p| [Point3::new(p.x, p.y, 0.0), Point3::new(p.x, p.y, h)]).collect();
        let hull = Polyhedron::new(&pts, DEFAULT_COPLANAR_TOL).unwrap();
        let g = Point3::new(poly.centroid.x, poly.centroid.y, h / 2.0);
        let e3 = Equilibria::new(&hull, &g, 1e-9).unwrap();
        assert_eq!(e3.stable, e2.stable + 2);
        assert_eq!(e3.unstable, 2 * e2.unstable);
        assert_eq!(e3.saddle, e2.unstable + 2 * e2.stable);
        let mut r2: Vec<f64> = e2.points.iter().filter(|p| p.kind == Kind::Stable).map(|p| p.r).collect();
        let mut r3: Vec<f64> = e3
            .points
            .iter()
            .filter(|p| p.kind == Kind::Stable && (p.point.z - h / 2.0).abs() < 1e-9)
            .map(|p| p.r)
            .collect();
        r2.sort_by(f64::total_cmp);
        r3.sort_by(f64::total_cmp);
        assert_eq!(r2.len(), r3.len());
        for (x, y) in r2.iter().zip(&r3) {
            assert!((x - y).abs() < 1e-12, "{x} vs {y}");
        }
    }
}

/// Collinear vertex exactly at the foot of G: decided by the perturbation, reported, S = U.
#[test]
fn degenerate_polygon_is_decided_and_reported() {
    let p = Polygon::new(vec![
        Point2::new(-1.0, -1.0),
        Point2::new(1.0, -1.0),
        Point2::new(1.0, 0.0),
        Point2::new(1.0, 1.0),
        Point2::new(-1.0, 1.0),
    ])
    .unwrap();
    let e = PlanarEquilibria::new(&p, DEFAULT_DEGENERACY_TOL).unwrap();
    assert_eq!((e.stable, e.unstable), (4, 4));
    // both scalars vanish at the collinear vertex (the foot of G): two decisions are degenerate
    assert!(e.degenerate_decisions >= 2);
    assert!(!e.points.iter().any(|q| q.site == PlanarSite::Vertex(2)), "the collinear vertex is not a maximum");
}

#[test]
fn invalid_polygons_are_rejected() {
    let sq = |v: &[(f64, f64)]| Polygon::new(v.iter().map(|&(x, y)| Point2::new(x, y)).collect());
    assert!(sq(&[(0.0, 0.0), (1.0, 0.0)]).is_err(), "two vertices");
    assert!(sq(&[(0.0, 0.0), (1.0, 0.0), (0.2, 0.2), (0.0, 1.0)]).is_err(), "reflex vertex");
    assert!(sq(&[(0.0, 0.0), (1.0, 0.0), (2.0, 0.0)]).is_err(), "zero area");
    assert!(sq(&[(0.0, 0.0), (1.0, 0.0), (1.0, 0.0), (0.0, 1.0)]).is_err(), "repeated vertex");
    // Clockwise input is accepted and stored counter-clockwise.
    let cw = sq(&[(0.0, 0.0), (0.0, 1.0), (1.0, 1.0), (1.0, 0.0)]).unwrap();
    assert!(cw.area > 0.0);
    assert!(ellipse_polygon(0.5, 10, Sampling::ArcLength).is_err(), "a < 1");
}

#[test]
fn cli_json_has_the_documented_fields() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rocking"))
        .args(["planar", "ellipse", "--a", "1.2", "--k", "100", "--json"])
        .output()
        .expect("run rocking");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let m = paper_m(1.2);
    assert_eq!(j["stable"], 8 * m + 2);
    assert_eq!(j["unstable"], 8 * m + 2);
    assert!(j["nu"].as_f64().unwrap() > 0.0);
    assert_eq!(j["plateau"]["clear"], true);
    let flocks = j["flocks"].as_array().unwrap();
    assert_eq!(flocks.len(), 4);
    for f in flocks {
        let (s, u) = (f["stable"].as_u64().unwrap() as usize, f["unstable"].as_u64().unwrap() as usize);
        match f["type"].as_str().unwrap() {
            "stable" => assert_eq!((s, u), (2 * m + 1, 2 * m)),
            "unstable" => assert_eq!((s, u), (2 * m, 2 * m + 1)),
            t => panic!("flock type {t}"),
        }
    }
    assert_eq!(j["rocking"].as_array().unwrap().len(), 4 * m);
}

fn random_polygon(points: &[(f64, f64)]) -> Option<Polygon> {
    Polygon::convex_hull(&points.iter().map(|&(x, y)| Point2::new(x, y)).collect::<Vec<_>>()).ok()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// S = U on every convex polygon, and the hierarchy invariants: N(ν) non-increasing,
    /// S = U at every level, G(v_max) has S = U = 1, levels non-decreasing.
    #[test]
    fn random_convex_polygons(points in prop::collection::vec((-1.0f64..1.0, -1.0f64..1.0), 3..80)) {
        let Some(poly) = random_polygon(&points) else { return Ok(()) };
        prop_assume!(poly.area > 1e-6);
        let e = PlanarEquilibria::new(&poly, DEFAULT_DEGENERACY_TOL).unwrap();
        prop_assert_eq!(e.stable, e.unstable);
        prop_assert!(e.stable >= 2, "a homogeneous convex plate has at least 2 stable points");
        let an = analyse(poly);
        let h = &an.hierarchy;
        h.check().unwrap();
        let steps = h.staircase();
        for w in steps.windows(2) {
            prop_assert!(w[0].counts.total() > w[1].counts.total());
            prop_assert!(w[0].nu_hi <= w[1].nu_hi);
        }
        for s in &steps {
            prop_assert_eq!(s.counts.stable, s.counts.unstable);
            prop_assert_eq!(s.counts.saddle, 0);
            let mid = if s.nu_hi > s.nu_lo { (s.nu_lo + s.nu_hi) / 2.0 } else { s.nu_hi };
            if s.nu_hi > s.nu_lo {
                prop_assert_eq!(h.counts_at(mid), s.counts);
            }
        }
        let last = h.counts_at(h.v_max() * (1.0 + 1e-9) + 1e-300);
        prop_assert_eq!((last.stable, last.unstable), (1, 1));
        for c in h.cancellations.windows(2) {
            prop_assert!(c[0].weight <= c[1].weight, "cheapest-first weights on a cycle never decrease");
        }
    }

    /// Inscribed polygons of an ellipse with random vertices: convex, S = U, alternating kinds.
    #[test]
    fn random_ellipse_polygons(a in 1.0f64..4.0, n in 3usize..300, seed in 0u64..1000) {
        let poly = ellipse_polygon(a, n, Sampling::Random { seed });
        prop_assume!(poly.is_ok());
        let e = PlanarEquilibria::new(&poly.unwrap(), DEFAULT_DEGENERACY_TOL).unwrap();
        prop_assert_eq!(e.stable, e.unstable);
        for w in e.points.windows(2) {
            prop_assert!(w[0].kind != w[1].kind, "kinds alternate along the boundary");
        }
    }
}
