//! The static core against hand calculations, Poincaré–Hopf and invariance.

use nalgebra::{Rotation3, Vector3};
use proptest::prelude::*;
use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::equilibria::{Equilibria, DEFAULT_DEGENERACY_TOL};
use rocking_stones::hull::{Polyhedron, DEFAULT_COPLANAR_TOL};
use rocking_stones::mesh::{io, TriMesh};
use rocking_stones::solid::MassProperties;
use rocking_stones::{Point3, Vec3};
use std::path::{Path, PathBuf};

fn meshes_dir() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/meshes")).to_path_buf()
}

fn counts(eq: &Equilibria) -> (usize, usize, usize) {
    (eq.stable, eq.unstable, eq.saddle)
}

/// Right prism of height 1 over the obtuse triangle A(0,0) B(4,0) C(5,1).
fn obtuse_prism() -> TriMesh {
    let base = [(0.0, 0.0), (4.0, 0.0), (5.0, 1.0)];
    let mut v: Vec<Point3> = base.iter().map(|&(x, y)| Point3::new(x, y, 0.0)).collect();
    v.extend(base.iter().map(|&(x, y)| Point3::new(x, y, 1.0)));
    let t = vec![[0, 2, 1], [3, 4, 5], [0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [2, 0, 3], [2, 3, 5]];
    TriMesh::new(v, t)
}

#[test]
fn obtuse_prism_matches_hand_calculation() {
    // G = (3, 1/3, 1/2). Hand calculation (see the comments):
    // * caps: G projects to (3, 1/3), inside the triangle → 2 stable.
    // * face AB (y = 0): foot x = 3 ∈ (0, 4) → stable. Face CA: foot at 0.41 of CA → stable.
    // * face BC: foot at parameter ((G−B)·(1,1))/2 = −1/3 < 0, outside → not stable. S = 4.
    // * vertices A, C (top and bottom) are maxima; at B, R grows towards C: (C−B)·(B−G) = 2/3 > 0.
    //   U = 4.
    // * saddles: vertical edges at A and C, bottom and top edges AB and CA; BC's foot is outside,
    //   the vertical edge at B fails the cone condition on face BC. H = 6 = S + U − 2.
    let (mesh, _) = obtuse_prism().into_solid_boundary().unwrap();
    let a = Analysis::of_solid(mesh, Default::default(), &Options::default()).unwrap();
    let g = a.mass.center_of_mass;
    assert!((g - Point3::new(3.0, 1.0 / 3.0, 0.5)).norm() < 1e-12);
    assert_eq!(counts(&a.equilibria), (4, 4, 6));
    // The lowest stable point is on face CA: distance from G to the line y = x/5.
    let r_ca = (1.0 / 3.0 - 3.0 / 5.0f64).abs() / (1.0 + 1.0 / 25.0f64).sqrt();
    assert!((a.equilibria.r_min - r_ca.min(1.0 / 3.0)).abs() < 1e-12);
}

#[test]
fn box_with_shifted_g_keeps_all_faces_stable() {
    // For a rectangular box every interior G projects inside every face (|g_y| < b/2 ...), every
    // vertex is a maximum ((W−V)·(V−G) = −L(L/2 ∓ g) < 0) and every edge a saddle: (6, 8, 12)
    // wherever G is inside. The stable R values are the distances to the faces.
    let mesh = rocking_stones::generate::cuboid(2.0, 1.5, 1.0);
    let (mesh, rep) = mesh.into_solid_boundary().unwrap();
    let mut mass = MassProperties::of(&mesh).unwrap();
    mass.center_of_mass = Point3::new(0.6, -0.5, 0.3);
    let a = Analysis::with_center_of_mass(mesh, rep, mass, &Options::default()).unwrap();
    assert_eq!(counts(&a.equilibria), (6, 8, 12));
    let mut r: Vec<f64> = a.equilibria.points[..6].iter().map(|e| e.r).collect();
    r.sort_by(f64::total_cmp);
    let mut expect = vec![0.4, 1.6, 0.25, 1.25, 0.2, 0.8];
    expect.sort_by(f64::total_cmp);
    for (x, y) in r.iter().zip(&expect) {
        assert!((x - y).abs() < 1e-12, "{r:?} vs {expect:?}");
    }
}

#[test]
fn moving_g_towards_c_swaps_the_unstable_side_face() {
    // G = (4.8, 0.9, 0.5) lies inside the prism (between y = x − 4 and y = x/5 at x = 4.8).
    // Foot on AB: x = 4.8 > 4, outside → AB is no longer stable. Foot on BC:
    // ((G−B)·(1,1))/2 = (0.8 + 0.9)/2 = 0.85 ∈ (0,1) → BC is now stable. CA stays stable
    // (its corners are acute), both caps too: S = 4, but a different set of faces.
    let (mesh, rep) = obtuse_prism().into_solid_boundary().unwrap();
    let mut mass = MassProperties::of(&mesh).unwrap();
    mass.center_of_mass = Point3::new(4.8, 0.9, 0.5);
    let a = Analysis::with_center_of_mass(mesh, rep, mass, &Options::default()).unwrap();
    let stable_normals: Vec<Vec3> = a.equilibria.points[..a.equilibria.stable]
        .iter()
        .map(|e| match e.site {
            rocking_stones::equilibria::Site::Facet(f) => a.hull.facets[f as usize].normal,
            _ => unreachable!(),
        })
        .collect();
    let has = |n: Vec3| stable_normals.iter().any(|m| (m - n.normalize()).norm() < 1e-9);
    assert_eq!(stable_normals.len(), 4);
    assert!(!has(Vec3::new(0.0, -1.0, 0.0)), "AB must not be stable");
    assert!(has(Vec3::new(1.0, -1.0, 0.0)), "BC must be stable");
    let (s, u, h) = counts(&a.equilibria);
    assert_eq!(s + u, h + 2);
}

fn real_meshes() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(meshes_dir())
        .expect("data/meshes")
        .map(|e| e.unwrap().path())
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("ply" | "obj" | "stl")))
        .collect();
    v.sort();
    v
}

#[test]
fn poincare_hopf_on_every_real_mesh() {
    let files = real_meshes();
    assert!(files.len() >= 30, "expected the meshes of data/meshes, found {}", files.len());
    for f in files {
        let a = Analysis::of_file(&f, &Options::default()).unwrap_or_else(|e| panic!("{e}"));
        let (s, u, h) = counts(&a.equilibria);
        assert_eq!(s + u, h + 2, "{}", f.display());
        // The hull encloses the solid: hull volume ≥ solid volume.
        assert!(a.hull.volume() >= a.mass.volume * (1.0 - 1e-12), "{}", f.display());
    }
}

fn sorted_normalised_r(a: &Analysis) -> Vec<f64> {
    let mut r: Vec<f64> = a.equilibria.points.iter().map(|e| e.r / a.equilibria.r_max).collect();
    r.sort_by(f64::total_cmp);
    r
}

#[test]
fn rotation_translation_and_scale_leave_equilibria_unchanged() {
    let path = meshes_dir().join("stone_quarry_ibois_E34_decimated500_bin.ply");
    let (mesh, _) = io::load_solid(&path).unwrap();
    let base = Analysis::of_solid(mesh.clone(), Default::default(), &Options::default()).unwrap();
    let rot = Rotation3::from_euler_angles(0.3, -1.1, 2.2);
    for (scale, shift) in [(1.0, Vec3::new(1e3, -2e3, 5e2)), (1e-6, Vec3::new(3.0, 4.0, -5.0)), (1e3, Vec3::zeros())] {
        let moved = mesh.transformed(&rot, scale, &shift);
        let a = Analysis::of_solid(moved, Default::default(), &Options::default()).unwrap();
        assert_eq!(counts(&a.equilibria), counts(&base.equilibria), "scale {scale}");
        for (x, y) in sorted_normalised_r(&a).iter().zip(sorted_normalised_r(&base)) {
            assert!((x - y).abs() < 1e-9, "scale {scale}: {x} vs {y}");
        }
    }
}

#[test]
fn rotated_platonic_solids_keep_f_v_e() {
    use rocking_stones::generate::{platonic, Platonic};
    let rot = Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(Vector3::new(1.0, 2.0, 3.0)), 0.7);
    for (p, fve) in [
        (Platonic::Tetrahedron, (4, 4, 6)),
        (Platonic::Cube, (6, 8, 12)),
        (Platonic::Octahedron, (8, 6, 12)),
        (Platonic::Dodecahedron, (12, 20, 30)),
        (Platonic::Icosahedron, (20, 12, 30)),
    ] {
        let mesh = platonic(p).transformed(&rot, 1e-3, &Vec3::new(7.0, -3.0, 1.0));
        let (mesh, rep) = mesh.into_solid_boundary().unwrap();
        let a = Analysis::of_solid(mesh, rep, &Options::default()).unwrap();
        assert_eq!(counts(&a.equilibria), fve, "{p:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]
    /// S + U − H = 2 on random hulls with G anywhere strictly inside.
    #[test]
    fn poincare_hopf_on_random_hulls(
        pts in prop::collection::vec((-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), 5..120),
        w in prop::collection::vec(0.01f64..1.0, 5),
        grid in prop::bool::ANY,
    ) {
        // Half the cases on a coarse grid: many exactly coplanar and collinear points, ties.
        let q = |x: f64| if grid { (x * 3.0).round() / 3.0 } else { x };
        let points: Vec<Point3> = pts.iter().map(|&(x, y, z)| Point3::new(q(x), q(y), q(z))).collect();
        let Ok(poly) = Polyhedron::new(&points, DEFAULT_COPLANAR_TOL) else { return Ok(()) };
        let g = poly.vertices.iter().zip(w.iter().cycle()).fold(Vec3::zeros(), |acc, (p, wi)| acc + p.coords * *wi)
            / poly.vertices.iter().zip(w.iter().cycle()).map(|(_, wi)| *wi).sum::<f64>();
        let eq = Equilibria::new(&poly, &Point3::from(g), DEFAULT_DEGENERACY_TOL).unwrap();
        prop_assert_eq!(eq.stable + eq.unstable, eq.saddle + 2);
        prop_assert_eq!(poly.vertices.len() + poly.facets.len(), poly.edges.len() + 2);
    }
}
