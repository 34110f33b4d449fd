//! The Morse–Smale graph and the ν-hierarchy against known macro structures.

use nalgebra::Rotation3;
use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::equilibria::Kind;
use rocking_stones::generate;
use rocking_stones::mesh::TriMesh;
use rocking_stones::Vec3;

fn analyse(mesh: TriMesh) -> Analysis {
    let (mesh, rep) = mesh.into_solid_boundary().expect("generated meshes are closed");
    Analysis::of_solid(mesh, rep, &Options::default()).expect("analysis")
}

fn plateau_counts(a: &Analysis) -> (usize, usize, usize, bool) {
    let p = a.hierarchy.plateau().expect("a plateau");
    (p.counts.stable, p.counts.unstable, p.counts.saddle, p.clear)
}

#[test]
fn noisy_triaxial_ellipsoids_have_two_two_two_on_the_plateau() {
    for (n, seed) in [(1500, 1), (3000, 2), (6000, 3)] {
        let a = analyse(generate::ellipsoid([1.0, 0.7, 0.45], n, 0.01, seed));
        let micro = a.equilibria.stable + a.equilibria.unstable + a.equilibria.saddle;
        assert!(micro > 6, "n = {n}: expected many micro-equilibria, got {micro}");
        assert_eq!(plateau_counts(&a), (2, 2, 2, true), "n = {n}, seed = {seed}");
    }
}

#[test]
fn noisy_box_has_six_eight_twelve_on_the_plateau() {
    // Radial noise on flat faces adds micro-equilibria mostly near the corners (the hull of a
    // noisy plane is a few large facets, so each face keeps one stable point).
    let a = analyse(generate::noisy_cuboid(2.0, 1.4, 1.0, 12, 0.005, 7));
    let micro = a.equilibria.stable + a.equilibria.unstable + a.equilibria.saddle;
    assert!(micro > 26, "the noise must add micro-equilibria, got {micro}");
    assert_eq!(plateau_counts(&a), (6, 8, 12, true));
}

#[test]
fn sphere_like_body_has_no_clear_plateau() {
    let a = analyse(generate::ellipsoid([1.0, 1.0, 1.0], 3000, 0.01, 5));
    let p = a.hierarchy.plateau();
    assert!(p.is_none_or(|p| !p.clear), "{p:?}");
}

#[test]
fn every_saddle_has_two_stable_and_two_unstable_ends() {
    let a = analyse(generate::pebble([1.0, 0.75, 0.5], 0.02, 3000, 11));
    let eq = &a.equilibria;
    let mut ends = vec![(0, 0); eq.points.len()];
    for arc in &a.graph.arcs {
        assert_eq!(eq.points[arc.saddle].kind, Kind::Saddle);
        match eq.points[arc.end].kind {
            Kind::Stable => ends[arc.saddle].0 += 1,
            Kind::Unstable => ends[arc.saddle].1 += 1,
            Kind::Saddle => panic!("an arc ends at a saddle"),
        }
    }
    for (i, p) in eq.points.iter().enumerate() {
        if p.kind == Kind::Saddle {
            assert_eq!(ends[i], (2, 2), "saddle {i}");
        }
    }
    assert_eq!(a.graph.arcs.len(), 4 * eq.saddle);
}

#[test]
fn traced_arcs_follow_the_gradient() {
    let a = analyse(generate::pebble([1.0, 0.8, 0.6], 0.02, 2500, 4));
    let g = a.mass.center_of_mass;
    let tol = 1e-9 * a.hull.diameter;
    for arc in &a.graph.arcs {
        let r: Vec<f64> = arc.path.iter().map(|p| (p - g).norm()).collect();
        let ascending = a.equilibria.points[arc.end].kind == Kind::Unstable;
        for w in r.windows(2) {
            if ascending {
                assert!(w[1] >= w[0] - tol, "ascending arc goes down: {r:?}");
            } else {
                assert!(w[1] <= w[0] + tol, "descending arc goes up: {r:?}");
            }
        }
        let start = arc.path.first().unwrap();
        let end = arc.path.last().unwrap();
        assert!((start - a.equilibria.points[arc.saddle].point).norm() <= tol);
        assert!((end - a.equilibria.points[arc.end].point).norm() <= tol);
    }
}

#[test]
fn hierarchy_invariants_hold_at_every_level() {
    for seed in 0..4 {
        let a = analyse(generate::pebble([1.0, 0.7, 0.5], 0.03, 1500, seed));
        let h = &a.hierarchy;
        let steps = h.staircase();
        let mut last_n = usize::MAX;
        for s in &steps {
            let c = s.counts;
            assert_eq!(c.stable + c.unstable, c.saddle + 2, "seed {seed}: {c:?}");
            assert!(c.total() <= last_n);
            last_n = c.total();
        }
        let top = h.counts_at(2.0);
        assert_eq!((top.stable, top.unstable, top.saddle), (1, 1, 0), "seed {seed}");
    }
}

#[test]
fn hierarchy_is_invariant_under_similarity() {
    let mesh = generate::pebble([1.0, 0.8, 0.55], 0.02, 2000, 9);
    let base = analyse(mesh.clone());
    let rot = Rotation3::from_euler_angles(1.0, 0.4, -2.0);
    let moved = analyse(mesh.transformed(&rot, 2.5e4, &Vec3::new(-3e5, 1e5, 7e4)));
    let levels = |a: &Analysis| a.hierarchy.cancellations.iter().map(|c| c.level).collect::<Vec<_>>();
    let (l0, l1) = (levels(&base), levels(&moved));
    assert_eq!(l0.len(), l1.len());
    for (x, y) in l0.iter().zip(&l1) {
        assert!((x - y).abs() < 1e-9, "{x} vs {y}");
    }
    assert_eq!(base.hierarchy.plateau().map(|p| p.counts), moved.hierarchy.plateau().map(|p| p.counts));
}
