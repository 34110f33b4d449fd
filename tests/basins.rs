//! Quasi-static basin probabilities and the merge-tree certificate, checked
//! against symmetry, against a second, independent method (brute-force integration of the
//! flow ODE with h as a plain maximum over all hull corners), against the planar theory, and
//! against random walks that respect the energy bound.

use nalgebra::Rotation3;
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;
use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::basins::{
    basin_probabilities, flock_probabilities, settle, try_settle, MergeTree, QuasiStatic, SupportFlow,
};
use rocking_stones::generate::{cuboid, pebble, platonic, Platonic};
use rocking_stones::mesh::TriMesh;
use rocking_stones::{Point3, Vec3};
use std::f64::consts::PI;
use std::time::Instant;

fn analyse(mesh: TriMesh) -> Analysis {
    let (mesh, rep) = mesh.into_solid_boundary().unwrap();
    Analysis::of_solid(mesh, rep, &Options::default()).unwrap()
}

fn probabilities(a: &Analysis) -> QuasiStatic {
    basin_probabilities(&a.hull, &a.mass.center_of_mass, &a.equilibria)
}

fn stable(a: &Analysis, f: usize) -> bool {
    a.equilibria.at_facet[f].is_some()
}

/// Uniform random unit vectors.
fn random_directions(n: usize, seed: u64) -> Vec<Vec3> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let z: f64 = rng.random_range(-1.0..1.0);
            let phi: f64 = rng.random_range(0.0..2.0 * PI);
            let r = (1.0 - z * z).sqrt();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

/// The second method: h(d) = max over **all** hull corners (no adjacency), and the flow ODE
/// dd/dt = −(∇h − (∇h·d) d) integrated by explicit steps of fixed angle `eta`, until h has not
/// reached a new minimum for 400 steps (the iterate then chatters around a minimum's normal);
/// the facet is the one whose normal is nearest. Nothing of `rocking_stones::basins` is used.
struct Brute {
    w: Vec<[f64; 3]>,
    normals: Vec<Vec3>,
}

impl Brute {
    fn new(a: &Analysis) -> Self {
        let g = a.mass.center_of_mass;
        Brute {
            w: a.hull.vertices.iter().map(|p| [p.x - g.x, p.y - g.y, p.z - g.z]).collect(),
            normals: a.hull.facets.iter().map(|f| f.normal).collect(),
        }
    }

    fn h_and_grad(&self, d: &Vec3) -> (f64, Vec3) {
        let (mut best, mut bi) = (f64::NEG_INFINITY, 0);
        for (i, w) in self.w.iter().enumerate() {
            let v = w[0] * d.x + w[1] * d.y + w[2] * d.z;
            if v > best {
                best = v;
                bi = i;
            }
        }
        (best, Vec3::from(self.w[bi]))
    }

    fn h(&self, d: &Vec3) -> f64 {
        self.h_and_grad(&d.normalize()).0
    }

    fn settle(&self, d0: &Vec3, eta: f64) -> Option<usize> {
        let mut d = d0.normalize();
        let (mut h_min, mut since) = (f64::INFINITY, 0);
        for _ in 0..2_000_000 {
            let (h, w) = self.h_and_grad(&d);
            if h < h_min - 1e-15 {
                h_min = h;
                since = 0;
            } else {
                since += 1;
                if since > 400 {
                    let f = (0..self.normals.len())
                        .max_by(|&i, &j| self.normals[i].dot(&d).total_cmp(&self.normals[j].dot(&d)))
                        .unwrap();
                    return Some(f);
                }
            }
            let grad = w - d * h;
            let gn = grad.norm();
            if gn == 0.0 {
                return None;
            }
            d = (d - grad * (eta / gn)).normalize();
        }
        None
    }
}

/// Compare the exact probabilities with the ODE's end facets from `n` random directions.
/// Pointwise: the exact descent and the ODE agree on almost every direction, and re-running the
/// disagreements with a 10× smaller step removes most of them (they sit within a step of a
/// separatrix). In distribution: every facet within 4.5 σ (binomial) + the fraction that still
/// disagrees.
fn second_method(a: &Analysis, q: &QuasiStatic, n: usize, eta: f64, seed: u64, min_agree: f64) {
    let brute = Brute::new(a);
    let flow = SupportFlow::new(&a.hull, &a.mass.center_of_mass, &a.equilibria);
    let dirs = random_directions(n, seed);
    let ends: Vec<(u32, Option<usize>)> =
        dirs.par_iter().map(|d| (flow.settle(d).unwrap(), brute.settle(d, eta))).collect();
    let unsettled = ends.iter().filter(|e| e.1.is_none()).count();
    assert!(unsettled == 0, "{unsettled} ODE runs did not converge");
    let disagree: Vec<usize> = (0..n).filter(|&i| ends[i].0 as usize != ends[i].1.unwrap()).collect();
    let agree = 1.0 - disagree.len() as f64 / n as f64;
    let still: usize =
        disagree.par_iter().filter(|&&i| brute.settle(&dirs[i], eta / 10.0) != Some(ends[i].0 as usize)).count();
    println!(
        "second method: {n} directions, step {eta}: exact descent = ODE on {:.4}; {} disagree, {} still at step {}",
        agree,
        disagree.len(),
        still,
        eta / 10.0
    );
    assert!(agree >= min_agree, "pointwise agreement {agree} < {min_agree}");
    assert!(still * 4 <= disagree.len().max(4), "refining the ODE step did not resolve the disagreements");
    let mut counts = vec![0usize; a.hull.facets.len()];
    for e in &ends {
        counts[e.1.unwrap()] += 1;
    }
    let slack = still as f64 / n as f64;
    let mut worst: f64 = 0.0;
    for (f, (&c, &p)) in counts.iter().zip(&q.facet_probability).enumerate() {
        let emp = c as f64 / n as f64;
        let sigma = (p.max(1.0 / n as f64) * (1.0 - p) / n as f64).sqrt();
        let dev = (emp - p).abs();
        worst = worst.max(dev / (4.5 * sigma + slack + q.error + 1.0 / n as f64));
        assert!(
            dev <= 4.5 * sigma + slack + q.error + 1.0 / n as f64,
            "facet {f}: exact {p:.5} vs ODE {emp:.5} (σ {sigma:.5})"
        );
        if !stable(a, f) {
            assert_eq!(c, 0, "the ODE ended on non-stable facet {f}");
        }
    }
    println!("largest deviation / allowed = {worst:.3}");
}

fn check_partition(a: &Analysis, q: &QuasiStatic) {
    let sum: f64 = q.facet_probability.iter().sum();
    assert!((sum - 1.0).abs() <= 1e-12, "sum {sum}");
    for (f, &p) in q.facet_probability.iter().enumerate() {
        assert!(p >= 0.0);
        if !stable(a, f) {
            assert_eq!(p, 0.0, "non-stable facet {f} has probability {p}");
        }
    }
    assert!(q.error <= 1e-9, "stated error {} ({})", q.error, q.method);
}

#[test]
fn platonic_solids_are_fair_dice() {
    for (p, faces) in
        [(Platonic::Tetrahedron, 4), (Platonic::Cube, 6), (Platonic::Octahedron, 8), (Platonic::Icosahedron, 20)]
    {
        let a = analyse(platonic(p));
        assert_eq!(a.hull.facets.len(), faces);
        let q = probabilities(&a);
        check_partition(&a, &q);
        for &pr in &q.facet_probability {
            assert!((pr - 1.0 / faces as f64).abs() <= q.error.max(1e-12), "{p}: {:?}", q.facet_probability);
        }
        println!("{p}: every face 1/{faces} within {:.1e} ({})", q.error, q.method);
    }
}

#[test]
fn box_matches_the_ode_integration() {
    let a = analyse(cuboid(3.0, 2.0, 1.0));
    let q = probabilities(&a);
    check_partition(&a, &q);
    // Opposite faces are equal by symmetry; larger faces are likelier.
    let by_axis = |k: usize| {
        let f: Vec<usize> = (0..6).filter(|&f| a.hull.facets[f].normal[k].abs() > 0.5).collect();
        assert!((q.facet_probability[f[0]] - q.facet_probability[f[1]]).abs() < 1e-12);
        q.facet_probability[f[0]]
    };
    let (px, py, pz) = (by_axis(0), by_axis(1), by_axis(2));
    println!("box 3×2×1: faces ⊥x {px:.6}, ⊥y {py:.6}, ⊥z {pz:.6} (error {:.1e})", q.error);
    assert!(pz > py && py > px && px > 0.0);
    second_method(&a, &q, 20_000, 5e-4, 1, 0.995);
}

#[test]
fn rough_pebbles_match_the_ode_integration() {
    // The brief's pebble (786 hull corners, 1568 facets, S = 5) and one with more micro-minima
    // (500 corners, S = 13).
    for (n, seed, ode_seed) in [(800, 11, 2), (500, 1, 3)] {
        let a = analyse(pebble([1.0, 0.7, 0.5], 0.03, n, seed));
        let q = probabilities(&a);
        check_partition(&a, &q);
        let s = a.equilibria.stable;
        println!(
            "pebble: {} hull corners, {} facets, S = {s}, largest basin {:.4}, smallest {:.2e}",
            a.hull.vertices.len(),
            a.hull.facets.len(),
            q.facet_probability.iter().cloned().fold(0.0, f64::max),
            q.facet_probability.iter().cloned().filter(|&p| p > 0.0).fold(1.0, f64::min)
        );
        assert!(s > 2, "expected micro-equilibria on a rough pebble");
        assert!(q.facet_probability.iter().filter(|&&p| p > 0.0).count() == s, "every stable facet has a basin");
        second_method(&a, &q, 3000, 1e-3, ode_seed, 0.97);
    }
}

#[test]
fn settle_agrees_with_the_free_function_and_handles_exact_normals() {
    let a = analyse(pebble([1.0, 0.8, 0.6], 0.02, 300, 5));
    let g = a.mass.center_of_mass;
    let flow = SupportFlow::new(&a.hull, &g, &a.equilibria);
    for d in random_directions(50, 9) {
        assert_eq!(settle(&a.hull, &g, &d), flow.settle(&d).unwrap());
        let (f, path) = flow.settle_path(&d).unwrap();
        let hs: Vec<f64> = path.iter().map(|p| flow.h(p)).collect();
        assert!(hs.windows(2).all(|w| w[1] <= w[0] * (1.0 + 1e-12)), "h rose along a descent: {hs:?}");
        assert!((path.last().unwrap() - a.hull.facets[f as usize].normal).norm() < 1e-12);
    }
    for (f, facet) in a.hull.facets.iter().enumerate() {
        if stable(&a, f) {
            assert_eq!(flow.settle(&facet.normal).unwrap(), f as u32);
        } else {
            assert_ne!(flow.settle(&facet.normal).unwrap(), f as u32);
        }
    }
    assert!(flow.settle(&Vec3::zeros()).is_err());
    assert!(try_settle(&a.hull, &g, &Vec3::new(f64::NAN, 0.0, 1.0)).is_err());
}

#[test]
fn invariant_under_rotation_scaling_and_translation() {
    let base = pebble([1.0, 0.75, 0.55], 0.02, 400, 3);
    let a = analyse(base.clone());
    let q = probabilities(&a);
    let rot = Rotation3::from_euler_angles(0.3, -1.1, 2.2);
    let b = analyse(base.transformed(&rot, 1000.0, &Vec3::new(5e3, -2e3, 7e2)));
    let qb = probabilities(&b);
    assert_eq!(a.hull.facets.len(), b.hull.facets.len());
    for (f, facet) in a.hull.facets.iter().enumerate() {
        let n = rot * facet.normal;
        let fb = (0..b.hull.facets.len())
            .max_by(|&i, &j| b.hull.facets[i].normal.dot(&n).total_cmp(&b.hull.facets[j].normal.dot(&n)))
            .unwrap();
        assert!((b.hull.facets[fb].normal - n).norm() < 1e-9);
        assert!(
            (q.facet_probability[f] - qb.facet_probability[fb]).abs() < 1e-9,
            "facet {f}: {} vs {}",
            q.facet_probability[f],
            qb.facet_probability[fb]
        );
    }
}

/// Planar reference: for a polygon with G at its area centroid, the basin of a stable side under
/// the flow of the planar support function on the circle is the arc between the two maxima (the
/// directions of the unstable vertices) around its normal.
fn planar_basins(poly: &[[f64; 2]]) -> Vec<f64> {
    let n = poly.len();
    let (mut cx, mut cy, mut area) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        let c = p[0] * q[1] - q[0] * p[1];
        area += c / 2.0;
        cx += (p[0] + q[0]) * c / 6.0;
        cy += (p[1] + q[1]) * c / 6.0;
    }
    let g = [cx / area, cy / area];
    let ang = |v: [f64; 2]| v[1].atan2(v[0]);
    // Outward normal angle of side i (from vertex i to i+1, counter-clockwise polygon).
    let side_normal = |i: usize| {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        ang([q[1] - p[1], p[0] - q[0]])
    };
    let wrap = |x: f64| x.rem_euclid(2.0 * PI);
    let mut maxima = Vec::new();
    for (i, v) in poly.iter().enumerate() {
        let dir = ang([v[0] - g[0], v[1] - g[1]]);
        // Vertex i's normal cone: from the normal of side i−1 to that of side i.
        let lo = side_normal((i + n - 1) % n);
        let hi = side_normal(i);
        if wrap(dir - lo) < wrap(hi - lo) {
            maxima.push(wrap(dir));
        }
    }
    maxima.sort_by(f64::total_cmp);
    (0..n)
        .map(|i| {
            let a = wrap(side_normal(i));
            let k = maxima.iter().position(|&m| m > a).unwrap_or(0);
            let prev = maxima[(k + maxima.len() - 1) % maxima.len()];
            let next = maxima[k];
            let (p, q) = (poly[i], poly[(i + 1) % n]);
            // Stable side iff the foot of G lies inside it.
            let t = ((g[0] - p[0]) * (q[0] - p[0]) + (g[1] - p[1]) * (q[1] - p[1]))
                / ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2));
            if t > 0.0 && t < 1.0 {
                wrap(next - prev) / (2.0 * PI)
            } else {
                0.0
            }
        })
        .collect()
}

#[test]
fn long_prism_approaches_the_planar_basins() {
    // An irregular convex hexagon (counter-clockwise) with an obtuse corner that makes a side
    // unstable.
    let poly = [[0.0, 0.0], [2.0, -0.3], [3.2, 0.4], [3.4, 1.3], [1.5, 1.9], [-0.4, 0.9]];
    let planar = planar_basins(&poly);
    println!("planar basins: {planar:?}");
    let mut errs = Vec::new();
    for length in [10.0, 40.0] {
        let mut v: Vec<Point3> = poly.iter().map(|p| Point3::new(p[0], p[1], -length / 2.0)).collect();
        v.extend(poly.iter().map(|p| Point3::new(p[0], p[1], length / 2.0)));
        let hull = rocking_stones::hull::convex_hull(&v).unwrap();
        let a = analyse(TriMesh::new(v, hull.triangles));
        let q = probabilities(&a);
        check_partition(&a, &q);
        let mut err: f64 = 0.0;
        for (i, &p2) in planar.iter().enumerate() {
            let (p, r) = (poly[i], poly[(i + 1) % poly.len()]);
            let n = Vec3::new(r[1] - p[1], p[0] - r[0], 0.0).normalize();
            let f = (0..a.hull.facets.len()).find(|&f| (a.hull.facets[f].normal - n).norm() < 1e-9).unwrap();
            err = err.max((q.facet_probability[f] - p2).abs());
        }
        println!("prism of length {length}: largest |P(side) − planar| = {err:.5}");
        errs.push(err);
    }
    assert!(errs[1] < 0.01 && errs[1] < errs[0], "{errs:?}");
}

#[test]
fn flock_probabilities_sum_the_facets() {
    let a = analyse(pebble([1.0, 0.7, 0.5], 0.03, 500, 4));
    let q = probabilities(&a);
    let nu = a.hierarchy.plateau().map_or(0.0035, |p| p.nu());
    let flocks = a.hierarchy.flocks_at(nu);
    let per = flock_probabilities(&q, &a.equilibria, &flocks.membership, flocks.flocks.len());
    assert!((per.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    for (k, fl) in flocks.flocks.iter().enumerate() {
        let expect: f64 = fl
            .members
            .iter()
            .filter_map(|&i| match a.equilibria.points[i].site {
                rocking_stones::equilibria::Site::Facet(f) => Some(q.facet_probability[f as usize]),
                _ => None,
            })
            .sum();
        assert!((per[k] - expect).abs() < 1e-14);
    }
}

/// A random walk of small steps that never leaves {h ≤ level} (h by the plain maximum): any
/// motion a passive body with energy `level` could make, regardless of dynamics.
fn energy_walk(brute: &Brute, d0: Vec3, level: f64, steps: usize, step: f64, rng: &mut Xoshiro256PlusPlus) -> Vec3 {
    let mut d = d0;
    for _ in 0..steps {
        let r = Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        let next = (d + r * step).normalize();
        if brute.h(&next) <= level {
            d = next;
        }
    }
    d
}

#[test]
fn merge_tree_levels_and_certificates() {
    let a = analyse(pebble([1.0, 0.7, 0.5], 0.03, 500, 4));
    let g = a.mass.center_of_mass;
    let t = MergeTree::new(&a.hull, &g, &a.equilibria);
    let brute = Brute::new(&a);
    let nf = a.hull.facets.len() as u32;
    let stable: Vec<u32> = (0..nf).filter(|&f| stable(&a, f as usize)).collect();
    assert!(stable.len() > 1);
    let h_max = a.hull.vertices.iter().map(|p| (p - g).norm()).fold(0.0, f64::max);
    // The root holds every facet, at a level below max h.
    let root = t.nodes().iter().position(|n| n.parent.is_none()).unwrap();
    assert_eq!(t.nodes().iter().filter(|n| n.parent.is_none()).count(), 1);
    assert_eq!(t.stable_below(root as u32).len(), stable.len());
    assert!(t.nodes()[root].level <= h_max);
    for d in random_directions(100, 21) {
        assert_eq!(t.decided(&d, h_max * 1.0001), None);
        assert_eq!(t.decided(&d, f64::NAN), None);
    }
    for &f in &stable {
        let n = a.hull.facets[f as usize].normal;
        let hf = t.flow().facet_height(f);
        assert!((t.entry_barrier(f, f) - hf).abs() < 1e-15);
        assert!((hf - brute.h(&n)).abs() < 1e-12);
        let solo = t.unique_level(f);
        assert!(solo > hf);
        assert_eq!(t.decided(&n, hf + 0.5 * (solo - hf)), Some(f));
        assert_eq!(t.decided(&n, solo), None);
        assert_eq!(t.decided(&n, hf - 1.0), Some(f), "a level below h(d) is raised to h(d)");
    }
    // Barriers: symmetric, ≥ both facet heights, ultrametric.
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(8);
    for _ in 0..2000 {
        let [x, y, z] = [0; 3].map(|_| rng.random_range(0..nf));
        let (bxy, byx) = (t.entry_barrier(x, y), t.entry_barrier(y, x));
        assert_eq!(bxy, byx);
        assert!(bxy >= t.flow().facet_height(x) && bxy >= t.flow().facet_height(y));
        assert!(t.entry_barrier(x, z) <= bxy.max(t.entry_barrier(y, z)));
    }
    // Merge levels never decrease towards the root; the unique level is the barrier to the
    // nearest other stable facet.
    for n in t.nodes() {
        if let Some(p) = n.parent {
            assert!(t.nodes()[p as usize].level >= n.level);
        }
    }
    for &f in &stable {
        let nearest = stable.iter().filter(|&&s| s != f).map(|&s| t.entry_barrier(f, s)).fold(f64::INFINITY, f64::min);
        assert_eq!(nearest, t.unique_level(f));
    }
    // Soundness against energy-bounded random walks: whenever the tree decides, a walk inside
    // {h ≤ level} followed by the ODE descent ends on the decided facet. Starts near each stable
    // facet, at levels between h(d) and the facet's unique level (and a little above it).
    let (mut decided, mut undecided) = (0, 0);
    for &f in &stable {
        let n = a.hull.facets[f as usize].normal;
        println!("stable facet {f}: h = {:.5}, unique up to {:.5}", t.flow().facet_height(f), t.unique_level(f));
        for (i, r) in random_directions(12, 33 + f as u64).into_iter().enumerate() {
            let d = (n + r * 0.05).normalize();
            let hd = brute.h(&d);
            let f0 = t.flow().settle(&d).unwrap();
            let level = hd + (t.unique_level(f0) - hd).max(0.0) * [0.3, 0.9, 0.999, 1.2][i % 4];
            match t.decided(&d, level) {
                Some(f1) => {
                    decided += 1;
                    assert_eq!(f1, f0);
                    let end = energy_walk(&brute, d, level, 3000, 0.02, &mut rng);
                    assert_eq!(
                        brute.settle(&end, 1e-3),
                        Some(f1 as usize),
                        "a walk at level {level} escaped facet {f1}"
                    );
                }
                None => undecided += 1,
            }
        }
    }
    println!("certificates near stable facets: {decided} decided, {undecided} undecided");
    assert!(decided > 0);
}

#[test]
fn box_certificates_hold_against_energy_bounded_walks() {
    // A 3 × 2 × 1 box: faces at h = 1.5, 1, 0.5; saddles at the edge midpoints,
    // |P − G| = √(1.5² + 1²), √(1.5² + 0.5²), √(1 + 0.5²).
    let a = analyse(cuboid(3.0, 2.0, 1.0));
    let t = MergeTree::new(&a.hull, &a.mass.center_of_mass, &a.equilibria);
    let brute = Brute::new(&a);
    let face = |k: usize| (0..6u32).find(|&f| a.hull.facets[f as usize].normal[k] > 0.5).unwrap();
    let (fx, fy, fz) = (face(0), face(1), face(2));
    let (sxy, sxz, syz) = ((1.5f64.powi(2) + 1.0).sqrt(), (1.5f64.powi(2) + 0.25).sqrt(), 1.25f64.sqrt());
    assert!((t.entry_barrier(fz, fy) - syz).abs() < 1e-12);
    assert!((t.entry_barrier(fy, fx) - sxy.min(sxz.max(syz))).abs() < 1e-12);
    assert!((t.unique_level(fz) - syz).abs() < 1e-12);
    assert!((t.unique_level(fx) - sxz).abs() < 1e-12);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
    let (mut decided, mut undecided) = (0, 0);
    for (i, d) in random_directions(500, 34).into_iter().enumerate() {
        let hd = brute.h(&d);
        let level = hd * [1.0, 1.01, 1.03, 1.1][i % 4];
        match t.decided(&d, level) {
            Some(f) => {
                decided += 1;
                let end = energy_walk(&brute, d, level, 3000, 0.02, &mut rng);
                assert_eq!(brute.settle(&end, 1e-3), Some(f as usize), "a walk at level {level} escaped facet {f}");
            }
            None => undecided += 1,
        }
    }
    println!("box certificates on random starts: {decided} decided, {undecided} undecided");
    assert!(decided > 20 && undecided > 20, "{decided} decided, {undecided} undecided");
}

#[test]
fn flock_certificate_and_barriers_across_flocks() {
    let a = analyse(pebble([1.0, 0.7, 0.5], 0.03, 500, 4));
    let g = a.mass.center_of_mass;
    let t = MergeTree::new(&a.hull, &g, &a.equilibria);
    let brute = Brute::new(&a);
    let nu = a.hierarchy.plateau().map_or(0.0035, |p| p.nu());
    let flocks = a.hierarchy.flocks_at(nu);
    let facet_flock: Vec<Option<usize>> =
        a.equilibria.at_facet.iter().map(|s| s.map(|s| flocks.membership[s as usize])).collect();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(44);
    let (mut facet_level, mut flock_level) = (0, 0);
    for (i, d) in random_directions(60, 55).into_iter().enumerate() {
        let hd = brute.h(&d);
        let level = hd * (1.0 + [0.0, 0.01, 0.03, 0.1][i % 4]);
        if t.decided(&d, level).is_some() {
            facet_level += 1;
            assert!(t.decided_flock(&d, level, &facet_flock).is_some(), "a decided facet decides its flock");
        }
        if let Some(k) = t.decided_flock(&d, level, &facet_flock) {
            flock_level += 1;
            let end = energy_walk(&brute, d, level, 3000, 0.02, &mut rng);
            let f = brute.settle(&end, 1e-3).unwrap();
            assert_eq!(facet_flock[f], Some(k), "a walk at level {level} left flock {k}");
        }
    }
    println!("of 60 random starts: {facet_level} decided at facet level, {flock_level} at flock level");
    assert!(flock_level >= facet_level);
}

#[test]
fn decision_ceiling_is_exact_and_tight() {
    // Above the ceiling nothing decides (from any direction), just below it the facet
    // that attains it decides from its own normal; at facet and at flock level.
    let a = analyse(pebble([1.0, 0.7, 0.5], 0.03, 300, 4));
    let g = a.mass.center_of_mass;
    let t = MergeTree::new(&a.hull, &g, &a.equilibria);
    let flocks = a.hierarchy.flocks_at(a.hierarchy.plateau().map_or(0.0035, |p| p.nu()));
    let facet_flock: Vec<Option<usize>> =
        a.equilibria.at_facet.iter().map(|s| s.map(|s| flocks.membership[s as usize])).collect();
    let stable: Vec<usize> = (0..a.hull.facets.len()).filter(|&f| stable(&a, f)).collect();
    assert!(stable.len() >= 2 && flocks.flocks.len() >= 2);
    let facet_ceiling = t.decision_ceiling(None);
    let flock_ceiling = t.decision_ceiling(Some(&facet_flock));
    // The facet ceiling is the largest unique level (a second, independent formula).
    let largest_unique = stable.iter().map(|&f| t.unique_level(f as u32)).fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(facet_ceiling, largest_unique);
    assert!(flock_ceiling >= facet_ceiling && flock_ceiling.is_finite(), "{flock_ceiling} {facet_ceiling}");
    for d in random_directions(300, 9).iter().chain(stable.iter().map(|&f| &a.hull.facets[f].normal)) {
        for up in [0.0, 1e-9, 0.1] {
            assert_eq!(t.decided(d, facet_ceiling * (1.0 + up)), None);
            assert_eq!(t.decided_flock(d, flock_ceiling * (1.0 + up), &facet_flock), None);
        }
    }
    let below = |c: f64| c * (1.0 - 1e-9);
    let facet_tight = stable.iter().any(|&f| t.decided(&a.hull.facets[f].normal, below(facet_ceiling)).is_some());
    let flock_tight =
        stable.iter().any(|&f| t.decided_flock(&a.hull.facets[f].normal, below(flock_ceiling), &facet_flock).is_some());
    assert!(facet_tight && flock_tight);
}

/// Release-mode timing on a pebble with ≈ 500 hull corners:
/// `cargo test --release --test basins -- --ignored --nocapture`.
#[test]
#[ignore]
fn timing_500_corner_pebble() {
    for (n, seed) in [(500, 1), (500, 2), (800, 11), (2000, 3)] {
        let a = analyse(pebble([1.0, 0.7, 0.5], 0.03, n, seed));
        let t0 = Instant::now();
        let q = probabilities(&a);
        let dt = t0.elapsed();
        let t1 = Instant::now();
        let tree = MergeTree::new(&a.hull, &a.mass.center_of_mass, &a.equilibria);
        let dt_tree = t1.elapsed();
        let dirs = random_directions(100_000, 1);
        let t2 = Instant::now();
        let k = dirs.iter().filter(|d| tree.decided(d, tree.flow().h(d) * 1.01).is_some()).count();
        let per = t2.elapsed().as_secs_f64() / dirs.len() as f64;
        println!(
            "pebble n={n}: {} hull corners, {} facets, S = {}: basins {:.3} s (error {:.1e}; {}), tree {:.4} s, \
             decided() {:.2} µs/call ({k} of 100000 decided at 1.01 h)",
            a.hull.vertices.len(),
            a.hull.facets.len(),
            a.equilibria.stable,
            dt.as_secs_f64(),
            q.error,
            q.method,
            dt_tree.as_secs_f64(),
            per * 1e6
        );
    }
}

/// Every real mesh of `data/meshes` (release): exact basins with nothing unresolved, and the time taken.
/// `cargo test --release --test basins -- --ignored --nocapture real_meshes`.
#[test]
#[ignore]
fn real_meshes_basins() {
    let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/meshes"));
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "ply" || x == "obj" || x == "stl"))
        .collect();
    paths.sort();
    for p in paths {
        let Ok(a) = Analysis::of_file(&p, &Options::default()) else {
            println!("{}: not analysable", p.display());
            continue;
        };
        let t0 = Instant::now();
        let q = probabilities(&a);
        let dt = t0.elapsed().as_secs_f64();
        println!(
            "{}: {} corners, S = {}, basins {dt:.3} s, error {:.1e}",
            p.file_name().unwrap().to_string_lossy(),
            a.hull.vertices.len(),
            a.equilibria.stable,
            q.error
        );
        check_partition(&a, &q);
    }
}
