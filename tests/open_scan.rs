//! Open scans: boundary loops, the rim of the hidden base, gaps, closing the rim with a base,
//! cutting closed meshes open; each checked against closed forms or an independent identity.

use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::error::ScanProblem;
use rocking_stones::generate;
use rocking_stones::mesh::plane::{perimeter, vector_area};
use rocking_stones::mesh::{
    boundary_loops, cut_base, cut_open, stand_on, BaseClosing, OpenScan, Plane, RimChoice, TriMesh,
};
use rocking_stones::{Error, Point3, Vec3};
use std::f64::consts::PI;

fn problem(e: &Error) -> Option<ScanProblem> {
    match e {
        Error::OpenScan { problem, .. } => Some(*problem),
        _ => None,
    }
}

fn scan(m: &TriMesh) -> OpenScan {
    OpenScan::new(m.clone(), &RimChoice::Lowest).unwrap_or_else(|e| panic!("{e}"))
}

/// The 2 × 1.5 × 1 box centred at 0, cut 0.2 above its bottom (z = −0.3).
fn cut_box() -> TriMesh {
    cut_base(&generate::cuboid(2.0, 1.5, 1.0), 0.2).unwrap()
}

#[test]
fn a_cut_box_has_one_rim_its_cross_section_oriented_into_the_solid() {
    let m = cut_box();
    let loops = boundary_loops(&m).unwrap();
    assert_eq!(loops.len(), 1);
    let pts = loops[0].points(&m);
    assert!(pts.iter().all(|p| p.z == -0.3), "the rim lies exactly on the cut plane");
    assert!((perimeter(&pts) - 7.0).abs() < 1e-12, "{}", perimeter(&pts));
    // The loop runs counter-clockwise seen from inside (above): its vector area is +z, the area.
    let a = vector_area(&pts);
    assert!((a - Vec3::new(0.0, 0.0, 3.0)).norm() < 1e-12, "{a:?}");
    let s = scan(&m);
    let rim = &s.summary().rim;
    assert!((rim.perimeter - 7.0).abs() < 1e-12 && (rim.area - 3.0).abs() < 1e-12, "{rim:?}");
    assert!(rim.flatness < 1e-12 && (rim.normal + Vec3::z()).norm() < 1e-12, "{rim:?}");
    assert!(s.summary().gaps.is_empty() && s.summary().trimmed_triangles == 0);
}

#[test]
fn a_flat_capped_cut_box_is_the_box_less_the_slab_and_is_a_solid_as_it_is() {
    let closing = BaseClosing::new(scan(&cut_box())).unwrap();
    let closed = closing.flat().unwrap();
    assert!((closed.mesh.signed_volume() - 2.0 * 1.5 * 0.8).abs() < 1e-12, "{}", closed.mesh.signed_volume());
    // Watertight, manifold, outward: the closed-mesh checks accept it unchanged.
    let (checked, repairs) = closed.mesh.clone().into_solid_boundary().unwrap();
    assert_eq!(checked, closed.mesh);
    assert_eq!(repairs, Default::default());
    // About 400 grid points inside the 2 × 1.5 rim, none nearer than half a spacing to it.
    let s = closing.spacing();
    assert!((s - (3.0f64 / 400.0).sqrt()).abs() < 1e-12);
    assert!(closing.points().len() > 300 && closing.points().iter().all(|p| p.rim_distance >= s / 2.0));
    let a =
        Analysis::of_closed_scan(closed, closing.scan().summary().clone(), "flat cap", &Options::default()).unwrap();
    let e = &a.equilibria;
    assert_eq!((e.stable, e.unstable, e.saddle), (6, 8, 12), "a box: S + U − H = 2");
    // On the base: the bottom facet and the four sides (their lower corners are rim vertices),
    // the four lower corners, the four lower edges and the four vertical ones.
    let r = a.report("cut box", &Options::default());
    let d = &r.open_scan.as_ref().unwrap().on_hidden_base;
    assert_eq!((d.stable, d.unstable, d.saddle), (5, 4, 8), "{d:?}");
}

#[test]
fn a_paraboloid_base_adds_its_closed_form_volume_bulging_or_recessed() {
    // Over the 2 × 1.5 rim, h(u, v) = H (1 − (2u/a)²)(1 − (2v/b)²) vanishes on the rim and adds
    // H a b (2/3)² to the volume. The rim's long axis is e₁ (x), its centre the plane's origin.
    let closing = BaseClosing::new(scan(&cut_box())).unwrap();
    assert!(closing.plane().e1.x.abs() > 1.0 - 1e-12, "{:?}", closing.plane().e1);
    for big_h in [0.2, -0.2] {
        let closed = closing
            .close(|p| big_h * (1.0 - (p.uv[0] / 1.0).powi(2)).max(0.0) * (1.0 - (p.uv[1] / 0.75).powi(2)).max(0.0))
            .unwrap();
        let want = 2.4 + big_h * 3.0 * 4.0 / 9.0;
        let got = closed.mesh.signed_volume();
        // Piecewise-linear interpolation on a grid of spacing 0.087: within 1 % of the bulge.
        assert!((got - want).abs() < 0.01 * (big_h.abs() * 3.0 * 4.0 / 9.0), "H = {big_h}: {got} vs {want}");
        assert!(closed.mesh.clone().into_solid_boundary().is_ok());
    }
}

#[test]
fn a_base_recessed_through_the_rock_or_not_finite_is_refused() {
    let closing = BaseClosing::new(scan(&cut_box())).unwrap();
    let e = closing.close(|_| -1.0).unwrap_err();
    assert_eq!(problem(&e), Some(ScanProblem::Crossing), "{e}");
    assert!(e.to_string().contains("the base crosses"), "{e}");
    let e = closing.close(|_| f64::NAN).unwrap_err();
    assert!(matches!(e, Error::Parameter { ref name, .. } if name == "offset"), "{e}");
}

#[test]
fn a_cut_sphere_has_the_rim_of_radius_sqrt_2rh_minus_h2() {
    // Unit sphere (4000 points on it), cut h = 0.3 above its bottom: rim radius √(2h − h²).
    let sphere = generate::ellipsoid([1.0, 1.0, 1.0], 4000, 0.0, 3);
    let h = 0.3;
    let s = scan(&cut_base(&sphere, h).unwrap());
    let r = (2.0 * h - h * h).sqrt();
    let rim = &s.summary().rim;
    // An inscribed polyhedron: its section lies within the faceting sag (~1e-3) inside the circle.
    assert!((rim.perimeter / (2.0 * PI * r) - 1.0).abs() < 5e-3, "{} vs {}", rim.perimeter, 2.0 * PI * r);
    assert!((rim.area / (PI * r * r) - 1.0).abs() < 1e-2, "{} vs {}", rim.area, PI * r * r);
    assert!((rim.centre - Point3::new(0.0, 0.0, h - 1.0)).norm() < 1e-2, "{:?}", rim.centre);
    // Closed flat: the sphere less its cap of height h, πh²(3 − h)/3.
    let v = BaseClosing::new(s).unwrap().flat().unwrap().mesh.signed_volume();
    let want = 4.0 * PI / 3.0 - PI * h * h * (3.0 - h) / 3.0;
    assert!((v / want - 1.0).abs() < 1e-2, "{v} vs {want}");
}

/// The part of `m` above (`above`) or below the plane z = `z`, closed flat.
fn capped_part(m: &TriMesh, z: f64, above: bool) -> (f64, f64) {
    let n = if above { Vec3::z() } else { -Vec3::z() };
    let part = cut_open(m, &Plane::new(Point3::new(0.0, 0.0, z), n).unwrap()).unwrap();
    let choice = if above { RimChoice::Lowest } else { RimChoice::Near(Point3::new(0.0, 0.0, z)) };
    let s = OpenScan::new(part, &choice).unwrap_or_else(|e| panic!("z = {z}, above {above}: {e}"));
    let area = s.summary().rim.area;
    let closed = BaseClosing::new(s).unwrap().flat().unwrap();
    (closed.mesh.signed_volume(), area)
}

#[test]
fn flat_caps_on_both_sides_of_a_cut_give_back_the_whole_volume() {
    // Property: the solid above the cut, closed flat, and the slab below it, closed flat, add up
    // to the closed mesh's volume, and both read the same rim area (two meshes, two
    // triangulations of the cross-section).
    let (stone, _) = rocking_stones::bundled::mesh().unwrap();
    let mut cases: Vec<TriMesh> = (0..4).map(|seed| generate::pebble([1.0, 0.7, 0.45], 0.05, 1500, seed)).collect();
    cases.push(stone);
    for (k, m) in cases.iter().enumerate() {
        let (lo, hi) = m.bounding_box().unwrap();
        for frac in [0.1, 0.25, 0.5] {
            let z = lo.z + frac * (hi.z - lo.z);
            let (v_up, a_up) = capped_part(m, z, true);
            let (v_down, a_down) = capped_part(m, z, false);
            let v = m.signed_volume();
            assert!(((v_up + v_down) / v - 1.0).abs() < 1e-9, "case {k} at {frac}: {v_up} + {v_down} vs {v}");
            assert!((a_up / a_down - 1.0).abs() < 1e-9, "case {k} at {frac}: {a_up} vs {a_down}");
        }
    }
}

#[test]
fn the_bundled_stone_standing_cut_a_few_mm_above_its_base() {
    // Standing on its likeliest stable facet (equilibrium 10), cut 5 mm above the ground: the
    // rim lies on z = 5 mm exactly, faces straight down, and is where the stone was cut.
    let a = rocking_stones::bundled::analysis(&Options::default()).unwrap();
    let rocking_stones::equilibria::Site::Facet(f) = a.equilibria.points[10].site else { panic!("not a facet") };
    let standing = stand_on(&a.mesh, &a.hull.facets[f as usize].normal).unwrap();
    let zmin = standing.vertices.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
    assert_eq!(zmin, 0.0);
    let s = scan(&cut_base(&standing, 5.0).unwrap());
    let rim = &s.summary().rim;
    assert!(rim.flatness < 1e-9 && (rim.centre.z - 5.0).abs() < 1e-9 && rim.normal.z < -1.0 + 1e-12, "{rim:?}");
    assert!(s.rim().iter().flat_map(|l| l.points(s.mesh())).all(|p| p.z == 5.0));
    // Its loops are closed and run counter-clockwise seen from above (into the stone).
    for l in s.rim() {
        assert!(vector_area(&l.points(s.mesh())).z > 0.0);
    }
    assert_eq!(s.summary().rim_loops.len(), s.rim().len());
}

/// Remove the fan of triangles around vertex `v`.
fn punch(m: &mut TriMesh, v: u32) {
    m.triangles.retain(|t| !t.contains(&v));
}

#[test]
fn gaps_are_found_closed_and_reported() {
    let pebble = generate::pebble([1.0, 0.7, 0.45], 0.05, 1500, 1);
    let cut = cut_base(&pebble, 0.25).unwrap();
    let whole = BaseClosing::new(scan(&cut)).unwrap().flat().unwrap().mesh.signed_volume();
    // Two holes high on the pebble: the fans of its top and of its +x end.
    let mut holed = cut.clone();
    let top = (0..holed.vertices.len()).max_by(|&a, &b| holed.vertices[a].z.total_cmp(&holed.vertices[b].z)).unwrap();
    let end = (0..holed.vertices.len()).max_by(|&a, &b| holed.vertices[a].x.total_cmp(&holed.vertices[b].x)).unwrap();
    punch(&mut holed, top as u32);
    punch(&mut holed, end as u32);
    let s = scan(&holed);
    let gaps = &s.summary().gaps;
    assert_eq!(gaps.len(), 2, "{gaps:?}");
    for g in gaps {
        let small = rocking_stones::mesh::open_scan::GAP_PERIMETER_RATIO * s.summary().rim.perimeter;
        assert!(g.vertices >= 3 && g.perimeter > 0.0 && g.perimeter < small, "{g:?}");
    }
    assert!(gaps.iter().any(|g| g.normal.z > 0.9), "the top gap faces up: {gaps:?}");
    let closed = BaseClosing::new(s).unwrap().flat().unwrap();
    assert!(closed.mesh.clone().into_solid_boundary().is_ok());
    // A flat patch over each fan: only the fans' small caps are missing.
    assert!((closed.mesh.signed_volume() / whole - 1.0).abs() < 1e-3, "{} vs {whole}", closed.mesh.signed_volume());
}

#[test]
fn a_closed_mesh_an_open_top_and_two_rims_are_refused_naming_what_to_give() {
    let e = OpenScan::new(generate::cuboid(1.0, 1.0, 1.0), &RimChoice::Lowest).unwrap_err();
    assert_eq!(problem(&e), Some(ScanProblem::Closed), "{e}");
    assert!(e.to_string().contains("read it as a closed stone"), "{e}");
    // Cut from the top: open at the top.
    let bowl = cut_open(&generate::cuboid(2.0, 1.5, 1.0), &Plane::new(Point3::new(0.0, 0.0, 0.3), -Vec3::z()).unwrap())
        .unwrap();
    let e = OpenScan::new(bowl, &RimChoice::Lowest).unwrap_err();
    assert_eq!(problem(&e), Some(ScanProblem::OpenTop), "{e}");
    assert!(e.to_string().contains("give a point near the rim"), "{e}");
    // Open at both ends: sideways (an open side), and with a point given, two rims.
    let tube = generate::cuboid(2.0, 1.5, 1.0);
    let tube = cut_open(&tube, &Plane::new(Point3::new(-0.9, 0.0, 0.0), Vec3::x()).unwrap()).unwrap();
    let tube = cut_open(&tube, &Plane::new(Point3::new(0.9, 0.0, 0.0), -Vec3::x()).unwrap()).unwrap();
    let e = OpenScan::new(tube.clone(), &RimChoice::Lowest).unwrap_err();
    assert_eq!(problem(&e), Some(ScanProblem::OpenTop), "{e}");
    let e = OpenScan::new(tube, &RimChoice::Near(Point3::new(-0.9, 0.0, 0.0))).unwrap_err();
    assert_eq!(problem(&e), Some(ScanProblem::SeveralRims), "{e}");
    assert!(e.to_string().contains("several places of comparable size"), "{e}");
}

#[test]
fn non_manifold_boundaries_are_refused_naming_the_place() {
    // Two cut boxes whose rims share a corner, and nothing else: a vertex on two loops. The
    // second is the first halved about its corner (−0.5, −0.5, −0.3), moved onto (0.5, 0.5, −0.3).
    let a = cut_base(&generate::cuboid(1.0, 1.0, 1.0), 0.2).unwrap();
    let (from, to) = (Point3::new(-0.5, -0.5, -0.3), Point3::new(0.5, 0.5, -0.3));
    assert!(a.vertices.contains(&from));
    let mut b = a.clone();
    b.vertices.iter_mut().for_each(|p| *p = to + (*p - from) * 0.5);
    let n = a.vertices.len() as u32;
    b.triangles.iter_mut().for_each(|t| *t = t.map(|i| i + n));
    let both = TriMesh::new([a.vertices.clone(), b.vertices].concat(), [a.triangles.clone(), b.triangles].concat());
    let e = OpenScan::new(both, &RimChoice::Lowest).unwrap_err();
    assert!(matches!(e, Error::InvalidMesh { .. }) && e.to_string().contains("two boundary loops"), "{e}");
    // An edge of three triangles: the cut box with a fin read as a scan says so, as a closed
    // mesh would.
    let mut fin = a.clone();
    let top = *fin.triangles.iter().find(|t| t.iter().all(|&i| fin.vertices[i as usize].z == 0.5)).unwrap();
    fin.vertices.push(Point3::new(0.0, 0.0, 2.0));
    fin.triangles.push([top[0], top[1], fin.vertices.len() as u32 - 1]);
    let e = Analysis::of_scan(fin, &Options::default()).err().expect("refused");
    assert!(e.to_string().contains("non-manifold"), "{e}");
}

#[test]
fn a_rim_that_folds_over_itself_seen_from_below_is_refused() {
    // A unit cube open at the bottom, with a fan of triangles hanging from its y = 0 rim edge and
    // reaching below the cube past y = 1: seen along the rim's normal, the rim crosses itself.
    let v: Vec<Point3> = (0..8).map(|i| Point3::new((i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2) as f64)).collect();
    let mut t = vec![
        [4, 5, 7],
        [4, 7, 6],
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
    ];
    let extra = [(0.5, 0.6, -0.4), (0.1, 1.3, -0.5), (0.5, 1.4, -0.5), (0.9, 1.3, -0.5)];
    let mut v = v;
    v.extend(extra.iter().map(|&(x, y, z)| Point3::new(x, y, z)));
    let (x, a, c, b) = (8, 9, 10, 11);
    t.extend([[1, 0, x], [0, a, x], [a, c, x], [c, b, x], [b, 1, x]]);
    // Seen along its normal it winds both ways: it does not even face down; given by a point.
    let e = OpenScan::new(TriMesh::new(v.clone(), t.clone()), &RimChoice::Lowest).unwrap_err();
    assert_eq!(problem(&e), Some(ScanProblem::OpenTop), "{e}");
    let near = RimChoice::Near(Point3::new(0.5, 0.5, 0.0));
    let s = OpenScan::new(TriMesh::new(v, t), &near).unwrap_or_else(|e| panic!("{e}"));
    let e = BaseClosing::new(s).unwrap_err();
    assert_eq!(problem(&e), Some(ScanProblem::NotSimple), "{e}");
    assert!(e.to_string().contains("simple polygon"), "{e}");
}

#[test]
fn broken_open_scans_end_in_an_answer_or_a_named_error_never_a_panic() {
    let cut = cut_base(&generate::pebble([1.0, 0.7, 0.45], 0.05, 600, 2), 0.1).unwrap();
    let mut outcomes = std::collections::BTreeMap::new();
    for seed in 0..60u64 {
        let mut m = cut.clone();
        let nt = m.triangles.len() as u64;
        let pick = |k: u64| ((seed * 7919 + k * 104_729) % nt) as usize;
        match seed % 5 {
            0 => (0..1 + seed % 4).for_each(|k| {
                let i = pick(k) % m.triangles.len();
                m.triangles.remove(i);
            }),
            1 => m.triangles[pick(0)].swap(1, 2),
            2 => {
                m = m.transformed(
                    &nalgebra::Rotation3::identity(),
                    if seed % 2 == 0 { 1e300 } else { 1e-300 },
                    &Vec3::zeros(),
                )
            }
            3 => m.vertices[m.triangles[pick(0)][0] as usize].z -= 5.0 * (seed as f64 - 30.0) / 30.0,
            _ => m = m.transformed(&nalgebra::Rotation3::from_euler_angles(seed as f64, 1.0, 0.3), 1.0, &Vec3::zeros()),
        }
        let r = std::panic::catch_unwind(|| Analysis::of_scan(m, &Options::default()).map(|_| ()));
        let label = match r {
            Ok(Ok(())) => "analysed".to_string(),
            Ok(Err(e)) => {
                assert_ne!(e.kind(), "internal-check", "seed {seed}: {e}");
                e.kind().to_string()
            }
            Err(_) => panic!("seed {seed} panicked"),
        };
        *outcomes.entry(label).or_insert(0) += 1;
    }
    assert!(outcomes.get("analysed").copied().unwrap_or(0) >= 10, "{outcomes:?}");
}

#[test]
fn closed_meshes_read_as_scans_report_exactly_as_before() {
    // The same report, byte for byte, through the scan reader and through the closed path.
    let (mesh, repairs) = rocking_stones::bundled::mesh().unwrap();
    let opts = Options::default();
    let old = Analysis::of_solid(mesh.clone(), repairs, &opts).unwrap().report("x", &opts);
    let raw =
        rocking_stones::mesh::io::read_bytes(rocking_stones::bundled::PLY, std::path::Path::new("x.ply")).unwrap();
    let new = Analysis::of_scan(raw, &opts).unwrap().report("x", &opts);
    let (old, new) = (serde_json::to_string(&old).unwrap(), serde_json::to_string(&new).unwrap());
    assert_eq!(old, new);
    assert!(!new.contains("hidden_base") && !new.contains("open_scan"));
}

#[test]
fn the_bundled_open_scan_is_read_and_its_base_marked() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/open_scan_E34.ply");
    let a = Analysis::of_file(&path, &Options::default()).unwrap();
    let r = a.report("open scan", &Options::default());
    let o = r.open_scan.as_ref().expect("an open scan");
    assert_eq!(o.base, "flat cap");
    assert!((o.scan.rim.centre.z - 5.0).abs() < 1e-9 && o.scan.rim.flatness < 1e-9, "{:?}", o.scan.rim);
    let marked = r.equilibria.iter().filter(|e| e.hidden_base).count();
    assert_eq!(marked, o.on_hidden_base.stable + o.on_hidden_base.unstable + o.on_hidden_base.saddle);
    assert!(o.on_hidden_base.stable >= 1, "it stands on its base: {:?}", o.on_hidden_base);
    let json = serde_json::to_value(&r).unwrap();
    assert!(json["open_scan"]["rim"]["perimeter"].as_f64().unwrap() > 0.0);
    // The figures data/README.md quotes: two feet 216 mm apart, 755 mm of rim around 11 907 mm².
    assert_eq!(o.scan.rim_loops.len(), 2);
    assert_eq!((o.scan.rim.perimeter.round(), o.scan.rim.area.round()), (755.0, 11907.0));
    let apart = (o.scan.rim_loops[0].centre - o.scan.rim_loops[1].centre).norm();
    assert_eq!(apart.round(), 216.0);
    // It stands on the stable facet of the bundled stone with the largest basin (37 %).
    let stone = rocking_stones::bundled::analysis(&Options::default()).unwrap().report("s", &Options::default());
    let likeliest =
        stone.stable_facets.iter().max_by(|a, b| a.basin_probability.total_cmp(&b.basin_probability)).unwrap();
    assert_eq!((likeliest.equilibrium, (likeliest.basin_probability * 100.0).round()), (10, 37.0));
}

fn rocking(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_rocking")).args(args).output().expect("run rocking")
}

#[test]
fn the_cli_regenerates_the_bundled_open_scan_and_analyses_it() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("open.ply");
    let from = root.join("data/default_pebble.ply");
    let args = ["generate", "open-scan", "--from", from.to_str().unwrap(), "--stand-on", "10", "--cut", "5"];
    let r = rocking(&[&args[..], &["-o", out.to_str().unwrap()]].concat());
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    // The command data/README.md gives makes the bundled file, byte for byte.
    assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(root.join("data/open_scan_E34.ply")).unwrap());
    let r = rocking(&["analyze", out.to_str().unwrap(), "--length-unit", "mm"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let text = String::from_utf8_lossy(&r.stdout);
    assert!(text.contains("open     an open scan") && text.contains("closed by a flat cap"), "{text}");
    assert!(String::from_utf8_lossy(&r.stderr).contains("is an open scan"));
    // Options that do not fit are refused by their flags.
    let r = rocking(&[&args[..6], &["--cut=-1", "-o", out.to_str().unwrap()]].concat());
    let e = String::from_utf8_lossy(&r.stderr);
    assert!(!r.status.success() && e.contains("--cut must be a height in (0, "), "{e}");
    let r = rocking(&["generate", "box", "--cut", "1", "-o", out.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&r.stderr).contains("--cut applies to open-scan"));
}

#[test]
fn the_cli_reads_an_open_top_as_a_scan_when_given_a_point_near_its_rim() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bowl.ply");
    let bowl = cut_open(&generate::cuboid(2.0, 1.5, 1.0), &Plane::new(Point3::new(0.0, 0.0, 0.3), -Vec3::z()).unwrap())
        .unwrap();
    rocking_stones::mesh::io::write(&path, &bowl).unwrap();
    let r = rocking(&["analyze", path.to_str().unwrap(), "--json"]);
    assert!(String::from_utf8_lossy(&r.stderr).contains("not at the bottom of the scan"));
    let r = rocking(&["analyze", path.to_str().unwrap(), "--json", "--rim-near", "0,0,0.3"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let json: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    assert_eq!(json["open_scan"]["chosen"]["rim"], "near");
    assert!((json["solid"]["volume"].as_f64().unwrap() - 2.4).abs() < 1e-12, "{}", json["solid"]["volume"]);
    assert_eq!(json["micro"]["stable"], 6);
}

/// The cut box and a second, separate box scaled by `k` beside it.
fn with_second_piece(k: f64) -> TriMesh {
    let mut m = cut_box();
    let other = generate::cuboid(k, k, k);
    let n = m.vertices.len() as u32;
    m.vertices.extend(other.vertices.iter().map(|p| p + Vec3::new(5.0, 0.0, 0.0)));
    m.triangles.extend(other.triangles.iter().map(|t| t.map(|i| i + n)));
    m
}

#[test]
fn a_speck_beside_the_scan_is_dropped_and_counted_a_second_rock_is_refused() {
    // A 0.05 cube: 0.015 of area beside the cut box's 8.6 (0.2 %), a speck.
    let s = scan(&with_second_piece(0.05));
    assert_eq!(s.summary().trimmed_triangles, 12, "the speck's 12 triangles");
    assert!((s.summary().rim.area - 3.0).abs() < 1e-12 && s.summary().rim_loops.len() == 1);
    // A 0.5 cube (1.5 of area, 15 %) is a second surface: refused, naming the pieces.
    let e = OpenScan::new(with_second_piece(0.5), &RimChoice::Lowest).unwrap_err();
    assert!(e.to_string().contains("2 separate pieces"), "{e}");
}

#[test]
fn the_bundled_rocking_field_scan_topples_where_its_flat_cap_would_not() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("open.ply");
    let from = root.join("data/default_pebble.ply");
    let args = ["generate", "open-scan", "--from", from.to_str().unwrap(), "--stand-on", "3", "--cut", "5"];
    let r = rocking(&[&args[..], &["-o", out.to_str().unwrap()]].concat());
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let bundled = root.join("data/open_scan_E34_rocking.ply");
    assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(&bundled).unwrap(), "data/README.md's command");
    // The README's field scan: one 1 Hz sine cycle of 0.2 g.
    let rec = dir.path().join("pulse.csv");
    let rows: String = (0..2000)
        .map(|i| {
            let t = i as f64 / 200.0;
            let a = if t < 1.0 { (2.0 * PI * t).sin() } else { 0.0 };
            format!("{t:.3},{a:.5}\n")
        })
        .collect();
    std::fs::write(&rec, format!("time_s,ax_g\n{rows}")).unwrap();
    // The README's command; `more` adds to it.
    let (scan, rec) = (bundled.to_str().unwrap(), rec.to_str().unwrap());
    let shake = |more: &[&str]| {
        let readme = ["shake", scan, "--length-unit", "mm", "--pose", "as-scanned", "--motion", rec];
        rocking(&[&readme[..], &["--columns", "time_s,ax_g"], more].concat())
    };
    let p = |base: &str| {
        let r = shake(&["--scales", "0.2", "--ensemble", "16", "--base", base, "--json"]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        serde_json::from_slice::<serde_json::Value>(&r.stdout).unwrap()
    };
    let (drawn, flat) = (p("drawn"), p("scanned"));
    // On its flat cap the scan stands on a wide support and no member overturns; the members
    // standing on drawn bases do, some of them (the closed stone it was cut from overturns).
    assert_eq!(flat["probability"]["overturned"], 0, "{}", flat["probability"]);
    let k = drawn["probability"]["overturned"].as_u64().unwrap();
    assert!((2..=14).contains(&k), "{} of 16 drawn members overturned", k);
    let base = &drawn["base"];
    assert_eq!(base["members"], 16);
    let tan = base["tan_alpha"].as_array().unwrap();
    let flat_tan = flat["tipping"][0]["minimum_g"].as_f64().unwrap();
    assert!(tan[2].as_f64().unwrap() < flat_tan, "drawn tan α up to {} against the flat cap's {flat_tan}", tan[2]);
    assert!(flat.get("base").is_none());
    // Rocking points that do not surround G's foot are refused by their flag, in the scan's
    // frame (G's foot is at x = 731 mm).
    let r = shake(&["--ensemble", "2", "--rocking-points-mm", "600,-195,650,-195,620,-160"]);
    let e = String::from_utf8_lossy(&r.stderr);
    assert!(!r.status.success() && e.contains("--rocking-points-mm must be three distinct points"), "{e}");
}
