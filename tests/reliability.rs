//! Reliability: every reproducer of a damaged or hostile input ends in a named error or in the
//! unchanged answer; scale does not change counts or ν; batch runs report failures in their exit code; a
//! bounded mutation campaign over the bundled meshes finds no panic and no failed internal check.

use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::generate;
use rocking_stones::mesh::io::{self, load_solid};
use rocking_stones::mesh::{intersect, TriMesh, SHALLOW_CROSSING_DEPTH};
use rocking_stones::mutation;
use rocking_stones::solid::MassProperties;
use rocking_stones::{Error, Point3, Vec3};
use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::load_error;

fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn meshes() -> PathBuf {
    repo().join("data/meshes")
}

fn default_pebble() -> TriMesh {
    io::read(&repo().join("data/default_pebble.ply")).expect("bundled pebble")
}

/// A small synthetic pebble (closed, embedded), 2000 vertices.
fn pebble() -> TriMesh {
    generate::pebble([1.0, 0.72, 0.48], 0.02, 2000, 7)
}

fn write(dir: &Path, name: &str, mesh: &TriMesh) -> PathBuf {
    let p = dir.join(name);
    io::write(&p, mesh).unwrap();
    p
}

// ---------------------------------------------------------------------------------------------
// Self-intersecting surfaces

/// The vertex farthest from the vertex mean, pulled through the body to the other side.
fn pulled_through(mut m: TriMesh) -> TriMesh {
    let c = Point3::from(m.vertices.iter().map(|p| p.coords).sum::<Vec3>() / m.vertices.len() as f64);
    let (far, _) = m.vertices.iter().enumerate().max_by(|a, b| (a.1 - c).norm().total_cmp(&(b.1 - c).norm())).unwrap();
    m.vertices[far] = c + (c - m.vertices[far]) * 1.5;
    m
}

#[test]
fn obj_with_a_vertex_pulled_through_the_body_is_self_intersecting() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "pulled.obj", &pulled_through(pebble()));
    let e = load_solid(&path).unwrap_err();
    let Error::SelfIntersecting { first, second, pairs, near, relative_depth, .. } = &e else {
        panic!("expected SelfIntersecting, got {e:?}")
    };
    assert!(first < second && *pairs >= 1, "{e}");
    assert!(*relative_depth > 0.1, "a spike through the body is deep: {e}");
    assert!(near.is_some());
    let msg = e.to_string();
    assert!(msg.contains("pulled.obj") && msg.contains(&format!("triangles {first} and {second}")), "{msg}");
    // The same mesh analysed without the check: G's position is a named error or an answer, never
    // the internal Poincaré–Hopf check.
    let mut raw = io::read(&path).unwrap();
    raw.weld();
    if let Err(Error::Check { what, .. }) = Analysis::of_solid(raw, Default::default(), &Options::default()) {
        panic!("internal check reached: {what}");
    }
}

#[test]
fn ply_whose_header_swaps_x_and_nz_is_self_intersecting() {
    // The bundled stone written as an ascii PLY with vertex normals, then the header's `x` and
    // `nz` names swapped: the reader takes the normals' z for x.
    let m = default_pebble();
    let (m, _) = m.into_solid_boundary().unwrap();
    let mut normals = vec![Vec3::zeros(); m.vertices.len()];
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| m.vertices[i as usize]);
        let n = (b - a).cross(&(c - a));
        t.iter().for_each(|&i| normals[i as usize] += n);
    }
    let mut text = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float nz\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float x\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        m.vertices.len(),
        m.triangles.len()
    );
    for (p, n) in m.vertices.iter().zip(&normals) {
        let n = n.normalize();
        text += &format!("{} {} {} {} {} {}\n", p.x, p.y, p.z, n.x, n.y, n.z);
    }
    for t in &m.triangles {
        text += &format!("3 {} {} {}\n", t[0], t[1], t[2]);
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("swapped.ply");
    std::fs::write(&path, text).unwrap();
    let e = load_solid(&path).unwrap_err();
    assert!(matches!(e, Error::SelfIntersecting { .. }), "expected SelfIntersecting, got {e:?}");
    assert!(e.to_string().starts_with(&format!("{}: the surface intersects itself", path.display())), "{e}");
}

#[test]
fn two_vertices_pushed_into_each_other_are_reported_not_analysed() {
    // An edit that keeps the volume positive and G inside: a vertex pushed through the opposite
    // wall. Before the check this was analysed without a word.
    let (m, _) = pebble().into_solid_boundary().unwrap();
    let mut bad = m.clone();
    let (lo, hi) = m.bounding_box().unwrap();
    // The vertex with the largest z, moved below the lowest point.
    let (top, _) = m.vertices.iter().enumerate().max_by(|a, b| a.1.z.total_cmp(&b.1.z)).unwrap();
    bad.vertices[top].z = lo.z - 0.1 * (hi.z - lo.z);
    let e = bad.into_solid_boundary().unwrap_err();
    assert!(matches!(e, Error::SelfIntersecting { .. }), "{e:?}");
    // The unedited pebble is embedded.
    assert!(intersect::find_self_intersection(&m.vertices, &m.triangles).is_none());
}

#[test]
fn bundled_scans_cross_themselves_only_hair_thin_and_are_accepted_with_a_count() {
    // Every bundled scan still loads; the three that cross themselves (checked independently with
    // exact rational arithmetic) do so far below the refusal depth and are counted in `Repairs`.
    let mut crossing = Vec::new();
    let mut checked = 0;
    let mut names: Vec<PathBuf> = std::fs::read_dir(meshes()).unwrap().map(|e| e.unwrap().path()).collect();
    names.sort();
    for p in names {
        if matches!(p.extension().and_then(|e| e.to_str()), Some("ply" | "obj")) {
            let (m, rep) = load_solid(&p).unwrap_or_else(|e| panic!("{e}"));
            let found = intersect::find_self_intersection(&m.vertices, &m.triangles);
            assert_eq!(found.as_ref().map_or(0, |c| c.pairs), rep.shallow_crossings, "{}", p.display());
            if rep.shallow_crossings > 0 {
                assert!(rep.crossing_depth > 0.0 && rep.crossing_depth <= SHALLOW_CROSSING_DEPTH);
                crossing.push((p.file_name().unwrap().to_string_lossy().into_owned(), rep.shallow_crossings));
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 39);
    assert_eq!(
        crossing,
        [
            ("kbo_486958_arrokoth_stern2019_bin.ply".to_string(), 6),
            ("moon_mars_phobos_thomas_bin.ply".to_string(), 16),
            ("stone_quarry_ibois_A0_decimated500_bin.ply".to_string(), 3)
        ]
    );
}

#[test]
fn centre_of_mass_outside_the_hull_is_its_own_error() {
    let (m, rep) = pebble().into_solid_boundary().unwrap();
    let mut mass = MassProperties::of(&m).unwrap();
    mass.center_of_mass = Point3::new(5.0, 0.0, 0.0);
    let e = match Analysis::with_center_of_mass(m.clone(), rep.clone(), mass.clone(), &Options::default()) {
        Err(e) => e,
        Ok(_) => panic!("G outside was analysed"),
    };
    assert!(matches!(e, Error::CentreOutsideHull { .. }), "{e:?}");
    assert!(
        e.to_string().contains("is not inside the convex hull") && e.to_string().contains("beyond the plane"),
        "{e}"
    );
    // G on a hull vertex: also refused by name, not by the Poincaré–Hopf check.
    let top = m.vertices.iter().copied().max_by(|a, b| a.x.total_cmp(&b.x)).unwrap();
    mass.center_of_mass = top;
    assert!(matches!(
        Analysis::with_center_of_mass(m, rep, mass, &Options::default()),
        Err(Error::CentreOutsideHull { .. })
    ));
}

// ---------------------------------------------------------------------------------------------
// Scale

/// (micro S, U, H), (macro S, U, H), ν, hull facets.
type Summary = ((usize, usize, usize), (usize, usize, usize), f64, usize);

fn summary(a: &Analysis) -> Summary {
    let r = a.report("x", &Options::default());
    (
        (r.micro.stable, r.micro.unstable, r.micro.saddle),
        (r.r#macro.stable, r.r#macro.unstable, r.r#macro.saddle),
        r.r#macro.nu,
        r.hull.facets,
    )
}

fn analyse_scaled(m: &TriMesh, s: f64) -> Analysis {
    let scaled = TriMesh::new(m.vertices.iter().map(|p| p * s).collect(), m.triangles.clone());
    let (mesh, rep) = scaled.into_solid_boundary().unwrap_or_else(|e| panic!("×{s:e}: {e}"));
    Analysis::of_solid(mesh, rep, &Options::default()).unwrap_or_else(|e| panic!("×{s:e}: {e}"))
}

#[test]
fn every_finite_scale_gives_the_same_counts_and_nu() {
    let (m, _) = default_pebble().into_solid_boundary().unwrap();
    let base = analyse_scaled(&m, 1.0);
    let b = summary(&base);
    assert_eq!(b.0, (15, 13, 26), "the README's micro counts of the bundled stone");
    for s in [1e-300, 1e-100, 10f64.powf(-79.5), 1e-79, 1e75, 1e100, 1e300] {
        let a = analyse_scaled(&m, s);
        let got = summary(&a);
        // Multiplying by 10^k rounds every coordinate, so ν may differ in its last bits.
        assert_eq!((got.0, got.1, got.3), (b.0, b.1, b.3), "×{s:e}");
        assert!((got.2 - b.2).abs() <= 1e-9 * b.2, "×{s:e}: ν {} vs {}", got.2, b.2);
        // Lengths come back in input units.
        assert!((a.equilibria.r_max / s - base.equilibria.r_max).abs() <= 1e-9 * base.equilibria.r_max, "×{s:e}");
        assert!((a.shape.c_over_a - base.shape.c_over_a).abs() <= 1e-9, "×{s:e}");
    }
    // Powers of two are exact: everything is bit for bit the same, scaled.
    for k in [-1000, -263, -1, 1, 300, 1000] {
        let s = 2f64.powi(k);
        let a = analyse_scaled(&m, s);
        assert_eq!(summary(&a), b, "×2^{k}");
        assert_eq!(a.equilibria.r_max, base.equilibria.r_max * s, "×2^{k}");
        let rs: Vec<f64> = a.equilibria.points.iter().map(|p| p.r / s).collect();
        let rb: Vec<f64> = base.equilibria.points.iter().map(|p| p.r).collect();
        assert_eq!(rs, rb, "×2^{k}");
    }
}

#[test]
fn quantities_that_overflow_f64_in_input_units_are_infinite_not_wrong() {
    let (m, _) = pebble().into_solid_boundary().unwrap();
    let a = analyse_scaled(&m, 1e300);
    let base = analyse_scaled(&m, 1.0);
    assert!(a.mass.volume.is_infinite() && a.mass.volume > 0.0, "{}", a.mass.volume);
    assert!(a.shape.volume.is_infinite());
    assert!(
        (a.shape.isoperimetric_ratio - base.shape.isoperimetric_ratio).abs() < 1e-9 * base.shape.isoperimetric_ratio
    );
    let g = a.mass.center_of_mass.coords / 1e300 - base.mass.center_of_mass.coords;
    assert!(g.norm() < 1e-9, "G in input units: {:?}", a.mass.center_of_mass);
}

#[test]
fn tiny_stone_gets_the_same_nu_as_the_unscaled_one() {
    // The reported case: at ×10^-79.5 ν came out 3.38e-2 instead of 2.48e-2.
    let (m, _) = default_pebble().into_solid_boundary().unwrap();
    let nu = |s: f64| analyse_scaled(&m, s).report("x", &Options::default()).r#macro.nu;
    let (a, b) = (nu(1.0), nu(10f64.powf(-79.5)));
    assert!((a - b).abs() <= 1e-9 * a, "{a} vs {b}");
}

// ---------------------------------------------------------------------------------------------
// Messages

fn tetra_ply(nv_header: usize, nf_header: usize) -> String {
    format!(
        "ply\nformat ascii 1.0\nelement vertex {nv_header}\nproperty float x\nproperty float y\nproperty float z\n\
         element face {nf_header}\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n"
    )
}

#[test]
fn ply_header_count_larger_or_smaller_than_the_data_says_so() {
    assert!(load_solid_ok(&tetra_ply(4, 4)));
    for (nv, nf) in [(5, 4), (4, 5), (3, 4), (4, 3), (6, 4)] {
        let e = load_error("counts.ply", tetra_ply(nv, nf).as_bytes());
        assert!(matches!(e, Error::Parse { .. }), "{e:?}");
        let msg = e.to_string();
        assert!(
            msg.contains("the header's element counts do not match the data")
                || msg.contains("more data than the header"),
            "{nv} {nf}: {msg}"
        );
    }
}

fn load_solid_ok(text: &str) -> bool {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("ok.ply");
    std::fs::write(&p, text).unwrap();
    load_solid(&p).is_ok()
}

fn tetra() -> TriMesh {
    let v = vec![
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(1.0, 0.0, 0.0),
        Point3::new(0.0, 1.0, 0.0),
        Point3::new(0.0, 0.0, 1.0),
    ];
    TriMesh::new(v, vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
}

#[test]
fn duplicated_triangle_is_called_a_duplicate() {
    let mut m = tetra();
    m.triangles.push([1, 2, 3]);
    let e = m.clone().into_solid_boundary().unwrap_err();
    assert!(matches!(e, Error::InvalidMesh { .. }));
    assert!(e.to_string().contains("duplicate triangle: triangles 2 and 4"), "{e}");
    m.triangles[4] = [1, 3, 2];
    let e = m.into_solid_boundary().unwrap_err();
    assert!(e.to_string().contains("duplicate triangle") && e.to_string().contains("opposite orientations"), "{e}");
}

#[test]
fn fin_triangle_is_reported_as_non_manifold_first() {
    // A triangle sticking out of the edge 1–2 of a tetrahedron: the edge carries three triangles
    // and the fin's two free edges are open; the cause is the extra triangle.
    let mut m = tetra();
    m.vertices.push(Point3::new(1.0, 1.0, -1.0));
    m.triangles.push([1, 2, 4]);
    let e = m.into_solid_boundary().unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("non-manifold: 1 edge(s)") && msg.contains("fin"), "{msg}");
}

// ---------------------------------------------------------------------------------------------
// Command line: exit codes, batch output, option validation

fn rocking(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_rocking")).args(args).output().expect("run rocking")
}

fn batch_folder() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "a_cube.ply", &generate::cuboid(1.0, 1.0, 1.0));
    write(dir.path(), "b_pebble.obj", &pebble());
    let mut open = generate::cuboid(1.0, 2.0, 3.0);
    open.triangles.pop();
    write(dir.path(), "c_open.stl", &open);
    dir
}

#[test]
fn batch_with_a_failed_file_finishes_writes_its_csv_and_exits_non_zero() {
    let dir = batch_folder();
    let csv = dir.path().join("out.csv");
    let out = rocking(&["analyze", dir.path().to_str().unwrap(), "--csv", csv.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("1 of 3 files failed"), "{stderr}");
    let mut r = csv::Reader::from_path(&csv).unwrap();
    let headers = r.headers().unwrap().clone();
    let err_col = headers.iter().position(|h| h == "error").expect("error column");
    let rows: Vec<csv::StringRecord> = r.records().map(|x| x.unwrap()).collect();
    assert_eq!(rows.len(), 3);
    assert!(rows[0][err_col].is_empty() && rows[1][err_col].is_empty());
    assert!(rows[2][err_col].contains("the surface is open"), "{:?}", &rows[2]);
    // Without the broken file the batch succeeds.
    std::fs::remove_file(dir.path().join("c_open.stl")).unwrap();
    let out = rocking(&["analyze", dir.path().to_str().unwrap(), "--csv", csv.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn json_with_several_files_prints_json_lines() {
    let dir = batch_folder();
    let out = rocking(&["analyze", dir.path().to_str().unwrap(), "--json"]);
    assert_eq!(out.status.code(), Some(1));
    let stdout = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<serde_json::Value> = stdout.lines().map(|l| serde_json::from_str(l).expect("a JSON line")).collect();
    assert_eq!(lines.len(), 3);
    assert_eq!(lines[0]["micro"]["stable"], 6, "the cube's 6 faces");
    assert!(lines[1]["micro"]["stable"].as_u64().unwrap() >= 2);
    // A box missing a triangle on a side is read as an open scan, and refused as one: its one
    // opening is not at its base.
    assert_eq!(lines[2]["kind"], "open-scan");
    assert!(lines[2]["error"].as_str().unwrap().contains("c_open.stl"));
}

#[test]
fn nonsense_options_are_refused_with_a_message() {
    let dir = batch_folder();
    let cube = dir.path().join("a_cube.ply");
    let cube = cube.to_str().unwrap();
    for bad in ["nan", "-1", "0", "inf", "0.5"] {
        let out = rocking(&["analyze", cube, &format!("--coplanar-tol={bad}")]);
        assert!(!out.status.success(), "--coplanar-tol {bad} accepted");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("--coplanar-tol must be") && err.contains("finite number in (0, 1e-3]"), "{bad}: {err}");
    }
    for bad in ["nan", "-1", "0", "2"] {
        let out = rocking(&["analyze", cube, &format!("--nu={bad}")]);
        assert!(!out.status.success(), "--nu {bad} accepted");
        assert!(String::from_utf8_lossy(&out.stderr).contains("--nu must be in (0, 1]"));
    }
    let out = rocking(&["analyze", cube, "--coplanar-tol", "1e-6"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let out = rocking(&["analyze", dir.path().to_str().unwrap(), "-o", dir.path().join("plots").to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--csv"));
}

// ---------------------------------------------------------------------------------------------
// Bounded mutation campaign

#[test]
fn thousands_of_mutated_files_end_in_an_answer_or_a_named_error() {
    // The small bundled meshes (binary and ascii PLY), plus an OBJ and an STL of a small pebble.
    let mut sources: Vec<(String, Vec<u8>)> = [
        "stone_quarry_ibois_E34_decimated500_bin.ply",
        "stone_quarry_ibois_A0_decimated500_bin.ply",
        "asteroid_2_pallas_hanus2017_bin.ply",
        "stone_quarry_ibois_stone0_ascii.ply",
    ]
    .iter()
    .map(|n| (n.to_string(), std::fs::read(meshes().join(n)).unwrap()))
    .collect();
    let dir = tempfile::tempdir().unwrap();
    let small = generate::pebble([1.0, 0.7, 0.5], 0.02, 300, 3);
    for name in ["pebble.obj", "pebble.stl"] {
        let p = write(dir.path(), name, &small);
        sources.push((name.to_string(), std::fs::read(p).unwrap()));
    }
    let opts = Options::default();
    let n = 3000;
    let mut by_kind = std::collections::BTreeMap::<&str, usize>::new();
    let prev = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let cases: Vec<mutation::Case> = {
        use rayon::prelude::*;
        (0..n).into_par_iter().map(|i| mutation::run_case(&sources, 13, i, &opts)).collect()
    };
    std::panic::set_hook(prev);
    for c in &cases {
        *by_kind.entry(c.outcome.label()).or_default() += 1;
        assert!(!c.outcome.is_failure(), "{} {} {}: {:?}", c.source, c.family, c.mutation, c.outcome);
    }
    // The campaign must exercise both ends: answers and several kinds of refusal.
    assert!(by_kind.get("analysed").copied().unwrap_or(0) > n as usize / 20, "{by_kind:?}");
    for kind in ["parse", "invalid-mesh", "self-intersecting"] {
        assert!(by_kind.get(kind).copied().unwrap_or(0) > 0, "no {kind}: {by_kind:?}");
    }
}
