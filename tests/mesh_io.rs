//! Mesh input/output: every real mesh in `data/meshes/` against `SOURCES.md`, round trips
//! through every writer, the awkward-but-valid variants of each format, and one test per kind of
//! malformed input (each checking the error variant, the file name and what is said).

use rocking_stones::mesh::io::{self, load_solid, read, read_bytes};
use rocking_stones::mesh::TriMesh;
use rocking_stones::{Error, Point3};
use std::path::{Path, PathBuf};

mod common;
use common::load_error;

fn meshes() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/meshes")).to_path_buf()
}

/// One row of the table in `SOURCES.md`.
struct Source {
    file: String,
    raw_vertices: usize,
    raw_faces: usize,
    welded: usize,
    volume: String,
}

fn sources() -> Vec<Source> {
    let text = std::fs::read_to_string(meshes().join("SOURCES.md")).unwrap();
    text.lines()
        .filter(|l| l.starts_with("| ") && (l.contains(".ply |") || l.contains(".obj |")))
        .map(|l| {
            let c: Vec<&str> = l.split('|').map(str::trim).collect();
            let (v, f) = c[4].split_once(" / ").unwrap();
            Source {
                file: c[1].to_string(),
                raw_vertices: v.parse().unwrap(),
                raw_faces: f.parse().unwrap(),
                welded: c[5].parse().unwrap(),
                volume: c[6].to_string(),
            }
        })
        .collect()
}

/// `value` equals `printed` (a number printed to 4 significant digits) within half a unit of the
/// 4th significant digit.
fn matches_4_digits(value: f64, printed: &str) -> bool {
    let expected: f64 = printed.parse().unwrap();
    let tol = 0.5 * 10f64.powi(expected.abs().log10().floor() as i32 - 3);
    (value - expected).abs() <= tol * (1.0 + 1e-9)
}

#[test]
fn every_bundled_mesh_loads_with_the_documented_vertex_count_and_volume() {
    let table = sources();
    let mut on_disk: Vec<String> = std::fs::read_dir(meshes())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".ply") || n.ends_with(".obj"))
        .collect();
    on_disk.sort();
    let mut listed: Vec<String> = table.iter().map(|s| s.file.clone()).collect();
    listed.sort();
    assert_eq!(on_disk, listed, "SOURCES.md and the folder disagree");
    assert_eq!(table.len(), 39);
    for s in &table {
        let path = meshes().join(&s.file);
        let raw = read(&path).unwrap();
        assert_eq!((raw.vertices.len(), raw.triangles.len()), (s.raw_vertices, s.raw_faces), "{}", s.file);
        let (mesh, repairs) = load_solid(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(mesh.vertices.len(), s.welded, "{}: welded vertex count", s.file);
        assert_eq!(repairs.welded_vertices + repairs.unreferenced_vertices, s.raw_vertices - s.welded, "{}", s.file);
        let v = mesh.signed_volume();
        assert!(matches_4_digits(v, &s.volume), "{}: volume {v} vs {}", s.file, s.volume);
    }
}

/// SOURCES.md calls the removed vertices of A0 and 67P "duplicates"; they are in fact vertices no
/// face uses (not at the position of any other vertex), while Arrokoth has 68 true duplicates.
#[test]
fn documented_extra_vertices_are_welded_or_dropped() {
    for (file, welded, unreferenced) in [
        ("stone_quarry_ibois_A0_decimated500_bin.ply", 0, 2),
        ("comet_67P_churyumov_gerasimenko_spc_shap5_bin.ply", 0, 1),
        ("kbo_486958_arrokoth_stern2019_bin.ply", 68, 0),
    ] {
        let (_, repairs) = load_solid(&meshes().join(file)).unwrap();
        assert_eq!((repairs.welded_vertices, repairs.unreferenced_vertices), (welded, unreferenced), "{file}");
    }
}

#[test]
fn rhino_ply_with_bare_cr_header_normals_colours_and_material_element() {
    let path = meshes().join("stone_quarry_ibois_073ac15d_rhino_CRheader_bin.ply");
    let raw = read(&path).unwrap();
    assert_eq!((raw.vertices.len(), raw.triangles.len()), (13491, 26978));
    let (mesh, repairs) = load_solid(&path).unwrap();
    assert!(!repairs.flipped);
    assert!(matches_4_digits(mesh.signed_volume(), "0.0004204"));
    // The extents column of SOURCES.md: 0.1048 x 0.07563 x 0.1059.
    let (lo, hi) = mesh.bounding_box().unwrap();
    for (d, printed) in (hi - lo).iter().zip(["0.1048", "0.07563", "0.1059"]) {
        assert!(matches_4_digits(*d, printed), "{d} vs {printed}");
    }
}

// ---------------------------------------------------------------------------------------------
// Test solids

/// Regular icosahedron (edge 2 before scaling), scaled and moved off the origin, outward faces.
fn icosahedron() -> TriMesh {
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v = Vec::new();
    for a in [-1.0, 1.0] {
        for b in [-phi, phi] {
            v.extend([Point3::new(0.0, a, b), Point3::new(a, b, 0.0), Point3::new(b, 0.0, a)]);
        }
    }
    let mut t = Vec::new();
    let is_edge = |i: usize, j: usize| ((v[i] - v[j]).norm() - 2.0).abs() < 1e-9;
    for i in 0..12 {
        for j in i + 1..12 {
            for k in j + 1..12 {
                if is_edge(i, j) && is_edge(j, k) && is_edge(i, k) {
                    let n = (v[j] - v[i]).cross(&(v[k] - v[i]));
                    let outward = n.dot(&v[i].coords) > 0.0;
                    t.push(if outward { [i as u32, j as u32, k as u32] } else { [i as u32, k as u32, j as u32] });
                }
            }
        }
    }
    assert_eq!(t.len(), 20);
    let offset = Point3::new(1.5, -2.25, 0.75);
    TriMesh::new(v.iter().map(|p| offset + p.coords * 0.37).collect(), t)
}

/// Volume of the regular icosahedron with edge `a`.
fn icosahedron_volume(a: f64) -> f64 {
    5.0 * (3.0 + 5f64.sqrt()) / 12.0 * a.powi(3)
}

/// Cube of side `s`: vertex `x + 2y + 4z` at `(x, y, z)·s`; its six quads, counter-clockwise outside.
fn cube_vertices(s: f64) -> Vec<Point3> {
    (0..8).map(|i| Point3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64) * s).collect()
}

const CUBE_QUADS: [[u32; 4]; 6] = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];

fn cube(s: f64) -> TriMesh {
    let t = CUBE_QUADS.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
    TriMesh::new(cube_vertices(s), t)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

// ---------------------------------------------------------------------------------------------
// Round trips

type Writer = fn(&Path, &TriMesh) -> rocking_stones::Result<()>;

#[test]
fn round_trips_through_every_writer_give_the_same_solid() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = icosahedron();
    let volume = mesh.signed_volume();
    assert!(rel(volume, icosahedron_volume(2.0 * 0.37)) < 1e-12);
    let colors: Vec<[u8; 3]> = (0..20).map(|k| [k as u8 * 12, 255 - k as u8, 7]).collect();
    let cases: [(&str, Writer, f64); 6] = [
        ("binary.stl", io::write, 1e-6),
        ("ascii.stl", io::write_ascii_stl, 1e-12),
        ("binary.ply", io::write, 1e-12),
        ("ascii.ply", io::write_ply_ascii, 1e-12),
        ("mesh.obj", io::write, 1e-12),
        (
            "colored.ply",
            |p, m| io::write_colored_ply(p, m, &(0..20).map(|k| [k as u8, 0, 0]).collect::<Vec<_>>()),
            1e-12,
        ),
    ];
    for (name, writer, tol) in cases {
        let path = dir.path().join(name);
        writer(&path, &mesh).unwrap();
        let (back, repairs) = load_solid(&path).unwrap();
        assert_eq!((back.vertices.len(), back.triangles.len()), (12, 20), "{name}");
        assert!(!repairs.flipped, "{name}");
        assert!(rel(back.signed_volume(), volume) < tol, "{name}: {} vs {volume}", back.signed_volume());
        if name.ends_with(".stl") {
            assert_eq!(repairs.welded_vertices, 60 - 12, "{name}: STL is a triangle soup");
        } else {
            assert_eq!(read(&path).unwrap(), mesh, "{name}: PLY and OBJ round trips are exact");
        }
    }
    let path = dir.path().join("colors.ply");
    io::write_colored_ply(&path, &mesh, &colors).unwrap();
    let header = String::from_utf8_lossy(&std::fs::read(&path).unwrap()[..400]).into_owned();
    assert!(header.contains("element face 20\nproperty list uchar int vertex_indices\nproperty uchar red\n"));
    assert_eq!(read(&path).unwrap(), mesh);
}

#[test]
fn binary_stl_whose_header_starts_with_solid() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("solid_header.stl");
    io::write(&path, &cube(2.0)).unwrap();
    let mut bytes = std::fs::read(&path).unwrap();
    bytes[..80].fill(b' ');
    bytes[..26].copy_from_slice(b"solid exported by a tool x");
    assert_eq!(bytes.len(), 84 + 50 * 12);
    let raw = read_bytes(&bytes, &path).unwrap();
    assert_eq!((raw.vertices.len(), raw.triangles.len()), (36, 12));
    let (mesh, _) = raw.into_solid_boundary().unwrap();
    assert_eq!(mesh.vertices.len(), 8);
    assert!(rel(mesh.signed_volume(), 8.0) < 1e-12);
}

#[test]
fn ascii_stl_with_a_bare_solid_line_and_crlf() {
    let mesh = icosahedron();
    let mut text = String::from("solid\r\n");
    for t in &mesh.triangles {
        text.push_str("facet normal 0 0 0\r\n outer loop\r\n");
        for &i in t {
            let p = mesh.vertices[i as usize];
            text.push_str(&format!("  vertex {:e} {:e} {:e}\r\n", p.x, p.y, p.z));
        }
        text.push_str(" endloop\r\nendfacet\r\n");
    }
    text.push_str("endsolid\r\n");
    let raw = read_bytes(text.as_bytes(), Path::new("bare.stl")).unwrap();
    assert_eq!(raw.triangles.len(), 20);
    let (back, _) = raw.into_solid_boundary().unwrap();
    assert_eq!(back.vertices.len(), 12);
    assert!(rel(back.signed_volume(), mesh.signed_volume()) < 1e-12);
}

/// Big-endian binary value helpers.
fn be_f64(out: &mut Vec<u8>, x: f64) {
    out.extend_from_slice(&x.to_be_bytes());
}

#[test]
fn big_endian_ply_with_double_coordinates_vertex_index_quads_and_extra_data() {
    let header = "ply\nformat binary_big_endian 1.0\ncomment extra properties everywhere\nobj_info made by hand\n\
        element vertex 8\nproperty uchar red\nproperty float64 x\nproperty double y\nproperty double z\n\
        property float nx\nelement face 6\nproperty int16 flags\nproperty list uint8 int32 vertex_index\n\
        element material 2\nproperty list ushort float stuff\nproperty double shine\nend_header\n";
    let mut out = header.as_bytes().to_vec();
    for p in cube_vertices(2.0) {
        out.push(200);
        [p.x, p.y, p.z].iter().for_each(|&x| be_f64(&mut out, x));
        out.extend_from_slice(&1.5f32.to_be_bytes());
    }
    for q in CUBE_QUADS {
        out.extend_from_slice(&(-7i16).to_be_bytes());
        out.push(4);
        q.iter().for_each(|&i| out.extend_from_slice(&(i as i32).to_be_bytes()));
    }
    for n in [3u16, 0] {
        out.extend_from_slice(&n.to_be_bytes());
        (0..n).for_each(|_| out.extend_from_slice(&9f32.to_be_bytes()));
        be_f64(&mut out, 0.5);
    }
    let raw = read_bytes(&out, Path::new("be.ply")).unwrap();
    assert_eq!(raw.vertices, cube_vertices(2.0));
    assert_eq!(raw.triangles.len(), 12);
    let (mesh, repairs) = raw.into_solid_boundary().unwrap();
    assert_eq!(repairs, Default::default());
    assert_eq!(mesh.signed_volume(), 8.0);
}

#[test]
fn ply_with_bare_cr_header_keeps_a_first_data_byte_that_is_a_newline() {
    let header = ["ply", "format binary_little_endian 1.0", "element vertex 8", "property uint8 flag"]
        .into_iter()
        .chain(["property float x", "property float y", "property float z", "element face 6"])
        .chain(["property list uchar uint vertex_indices", "end_header", ""])
        .collect::<Vec<_>>()
        .join("\r");
    let mut out = header.into_bytes();
    for p in cube_vertices(3.0) {
        out.push(b'\n'); // a data byte equal to '\n' right after "end_header\r"
        [p.x, p.y, p.z].iter().for_each(|&x| out.extend_from_slice(&(x as f32).to_le_bytes()));
    }
    for q in CUBE_QUADS {
        out.push(4);
        q.iter().for_each(|&i| out.extend_from_slice(&i.to_le_bytes()));
    }
    let (mesh, _) = read_bytes(&out, Path::new("cr.ply")).unwrap().into_solid_boundary().unwrap();
    assert_eq!(mesh.vertices, cube_vertices(3.0));
    assert_eq!(mesh.signed_volume(), 27.0);
}

#[test]
fn ascii_ply_with_crlf_comments_and_polygons_spanning_lines() {
    let mut text = String::from(
        "ply\r\nformat ascii 1.0\r\ncomment hi\r\nelement vertex 8\r\nproperty float x\r\nproperty float y\r\n\
         property float z\r\nproperty uchar red\r\nelement face 6\r\nproperty list uchar int vertex_indices\r\n\
         end_header\r\n",
    );
    for p in cube_vertices(1.0) {
        text.push_str(&format!("{} {} {} 255\r\n", p.x, p.y, p.z));
    }
    for q in CUBE_QUADS {
        text.push_str(&format!("4 {} {}\r\n{} {}\r\n", q[0], q[1], q[2], q[3]));
    }
    let (mesh, _) = read_bytes(text.as_bytes(), Path::new("a.ply")).unwrap().into_solid_boundary().unwrap();
    assert_eq!(mesh.signed_volume(), 1.0);
}

#[test]
fn obj_with_quads_negative_indices_and_slash_forms() {
    let mut text = String::from("# cube\nmtllib cube.mtl\no cube\n");
    for p in cube_vertices(2.0) {
        text.push_str(&format!("v {} {} {}\n", p.x, p.y, p.z));
    }
    text.push_str("vt 0 0\nvn 0 0 1\ng faces\nusemtl stone\ns off\n");
    for (k, q) in CUBE_QUADS.iter().enumerate() {
        let r: Vec<i64> = q.iter().map(|&i| i as i64 - 8).collect();
        text.push_str(&match k % 3 {
            0 => format!("f {} {} {} {}\n", r[0], r[1], r[2], r[3]),
            1 => format!("f {}/1 {}/1 {}/1 {}/1\n", r[0], r[1], r[2], r[3]),
            _ => format!("f {}//1 {}/1/1 {}//1 \\\n  {}//1\n", q[0] + 1, r[1], q[2] + 1, r[3]),
        });
    }
    let raw = read_bytes(text.as_bytes(), Path::new("cube.obj")).unwrap();
    assert_eq!(raw.triangles.len(), 12);
    assert_eq!(raw.vertices, cube_vertices(2.0));
    let (mesh, repairs) = raw.into_solid_boundary().unwrap();
    assert_eq!(repairs, Default::default());
    assert_eq!(mesh.signed_volume(), 8.0);
}

#[test]
fn pds_tab_obj_files_read_with_crlf_and_trailing_spaces() {
    let raw = read(&meshes().join("asteroid_4769_castalia_radar_hudson1994_pdstab.obj")).unwrap();
    assert_eq!((raw.vertices.len(), raw.triangles.len()), (2048, 4092));
    assert_eq!(raw.vertices[1], Point3::new(0.734214, 0.0, 0.0));
}

#[test]
fn format_is_detected_by_content_when_the_extension_is_unknown() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = icosahedron();
    for (written, renamed) in [("a.stl", "a.bin"), ("b.ply", "b.mesh"), ("c.obj", "c.txt")] {
        let (src, dst) = (dir.path().join(written), dir.path().join(renamed));
        io::write(&src, &mesh).unwrap();
        std::fs::rename(&src, &dst).unwrap();
        let (back, _) = load_solid(&dst).unwrap();
        assert_eq!(back.vertices.len(), 12, "{renamed}");
    }
}

// ---------------------------------------------------------------------------------------------
// Malformed inputs: each error names the file and says what is wrong

/// Like [`load_error`] for a mesh written with [`io::write`].
fn mesh_error(name: &str, mesh: &TriMesh) -> Error {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    io::write(&path, mesh).unwrap();
    load_error(name, &std::fs::read(&path).unwrap())
}

fn assert_parse(e: &Error, phrases: &[&str]) {
    assert!(matches!(e, Error::Parse { .. }), "expected a parse error, got {e:?}");
    for p in phrases {
        assert!(e.to_string().contains(p), "'{p}' missing from: {e}");
    }
}

fn assert_invalid(e: &Error, phrase: &str) {
    assert!(matches!(e, Error::InvalidMesh { .. }), "expected an invalid-mesh error, got {e:?}");
    assert!(e.to_string().contains(phrase), "'{phrase}' missing from: {e}");
}

fn ascii_ply(vertices: &str, faces: &str, nv: usize, nf: usize) -> String {
    format!(
        "ply\nformat ascii 1.0\nelement vertex {nv}\nproperty float x\nproperty float y\nproperty float z\n\
         element face {nf}\nproperty list uchar int vertex_indices\nend_header\n{vertices}{faces}"
    )
}

const TETRA_V: &str = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";

#[test]
fn empty_files_are_refused() {
    for name in ["empty.stl", "empty.ply", "empty.obj", "empty.xyz"] {
        assert_parse(&load_error(name, b""), &["empty file"]);
    }
}

#[test]
fn missing_file_is_an_io_error_naming_it() {
    let e = load_solid(Path::new("/nonexistent/dir/pebble.ply")).unwrap_err();
    assert!(matches!(e, Error::Io { .. }) && e.to_string().contains("pebble.ply"), "{e}");
}

#[test]
fn truncated_binary_stl() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.stl");
    io::write(&path, &cube(1.0)).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let e = load_error("truncated.stl", &bytes[..bytes.len() - 20]);
    assert_parse(&e, &["truncated binary STL", "12 triangles", "684 bytes", "664 bytes"]);
    let e = load_error("stub.stl", &bytes[..50]);
    assert_parse(&e, &["too short", "50 bytes"]);
}

#[test]
fn truncated_binary_ply_names_the_element_and_byte_counts() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.ply");
    io::write(&path, &cube(1.0)).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    // 8 vertices x 24 bytes, then 12 faces x 13 bytes.
    let e = load_error("faces_cut.ply", &bytes[..bytes.len() - 10]);
    let (len, cut) = (bytes.len(), bytes.len() - 10);
    assert_parse(
        &e,
        &["truncated binary PLY", "element 'face' 11 of 12", &format!("{len} bytes"), &format!("{cut} bytes")],
    );
    let cut = bytes.len() - 12 * 13 - 100;
    let e = load_error("vertices_cut.ply", &bytes[..cut]);
    assert_parse(&e, &["truncated binary PLY", "element 'vertex' (8 x 24 bytes", &format!("only {cut} bytes")]);
}

#[test]
fn nan_and_non_numeric_coordinates_are_refused_where_they_are() {
    let faces = "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
    let e = load_error("nan.ply", ascii_ply("0 0 0\n1 0 0\n0 1 0\n0 nan 1\n", faces, 4, 4).as_bytes());
    assert_parse(&e, &["vertex 3", "non-finite", "NaN", "line 13"]);
    let e = load_error("inf.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv inf 0 1\nf 1 2 3\n");
    assert_parse(&e, &["line 4", "non-finite"]);
    let e = load_error("word.obj", b"v 0 0 0\nv 1 zero 0\n");
    assert_parse(&e, &["line 2", "'zero' is not a number"]);
    let e = load_error("word.ply", ascii_ply("0 0 0\n1 0 0\n0 one 0\n0 0 1\n", faces, 4, 4).as_bytes());
    assert_parse(&e, &["line 12", "'one'"]);
    let e = load_error("nan.stl", b"solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex NaN 0 0\n");
    assert_parse(&e, &["line 5", "non-finite"]);
    let dir = tempfile::tempdir().unwrap();
    io::write(&dir.path().join("cube.stl"), &cube(1.0)).unwrap();
    let mut bin = std::fs::read(dir.path().join("cube.stl")).unwrap();
    bin[84 + 50 * 5 + 12..84 + 50 * 5 + 16].copy_from_slice(&f32::NAN.to_le_bytes());
    assert_parse(&load_error("nan_bin.stl", &bin), &["triangle 5", "non-finite"]);
}

#[test]
fn face_index_out_of_range_or_too_few_corners() {
    let faces = "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 9\n";
    let e = load_error("range.ply", ascii_ply(TETRA_V, faces, 4, 4).as_bytes());
    assert_parse(&e, &["face 3", "vertex 9", "out of range", "4 vertices"]);
    let e = load_error("range.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\n");
    assert_parse(&e, &["line 5", "vertex 7", "out of range"]);
    let e = load_error("rel.obj", b"v 0 0 0\nv 1 0 0\nf -1 -2 -3\n");
    assert_parse(&e, &["line 3", "relative index -3"]);
    let e = load_error("zero.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    assert_parse(&e, &["line 4", "index 0"]);
    let e = load_error("two.ply", ascii_ply(TETRA_V, "3 0 2 1\n2 0 1\n3 1 2 3\n3 0 3 2\n", 4, 4).as_bytes());
    assert_parse(&e, &["face 1 has 2 vertices", "at least 3"]);
    let e = load_error("two.obj", b"v 0 0 0\nv 1 0 0\nf 1 2\n");
    assert_parse(&e, &["line 3", "face with 2 vertices"]);
}

#[test]
fn bad_magic_headers_and_missing_parts() {
    assert_parse(&load_error("magic.ply", b"plx\nformat ascii 1.0\n"), &["not a PLY file"]);
    assert_parse(&load_error("noend.ply", b"ply\nformat ascii 1.0\nelement vertex 3\n"), &["no 'end_header'"]);
    let bad_count = ascii_ply(TETRA_V, "", 4, 0).replace("element vertex 4", "element vertex four");
    assert_parse(&load_error("count.ply", bad_count.as_bytes()), &["header line 3", "element count"]);
    let bad_type = ascii_ply(TETRA_V, "", 4, 0).replace("property float y", "property real y");
    assert_parse(&load_error("type.ply", bad_type.as_bytes()), &["header line 5", "unknown property type 'real'"]);
    let no_z = ascii_ply(TETRA_V, "", 4, 1).replace("property float z\n", "");
    assert_parse(&load_error("noz.ply", no_z.as_bytes()), &["no scalar property 'z'"]);
    let cloud = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n\
                 end_header\n0 0 0\n";
    assert_parse(&load_error("cloud.ply", cloud.as_bytes()), &["no 'face' element", "zero faces"]);
    assert_parse(&load_error("nofaces.ply", ascii_ply(TETRA_V, "", 4, 0).as_bytes()), &["0 faces"]);
    assert_parse(&load_error("short.ply", ascii_ply(TETRA_V, "3 0 1 2\n", 4, 2).as_bytes()), &["ends early", "face"]);
    assert_parse(&load_error("nofaces.obj", b"v 0 0 0\n"), &["1 vertices", "0 faces"]);
    assert_parse(&load_error("nofacets.stl", b"solid x\nendsolid x\n"), &["without any facet"]);
    assert_parse(&load_error("junk.stl", b"solid x\nfacet normal 0 0 1\nbanana\n"), &["line 3", "'banana'"]);
    assert_parse(&load_error("open_loop.stl", b"solid x\nouter loop\nvertex 0 0 0\n"), &["line 2", "never closed"]);
    assert_parse(&load_error("mystery.xyz", b"hello world"), &["unknown mesh format", "'.xyz'"]);
    assert_parse(&load_error("binary.obj", b"v 0 0 0\0\0"), &["NUL"]);
}

#[test]
fn writer_errors_name_the_file_and_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let named = |e: &Error, file: &str| e.to_string().starts_with(&dir.path().join(file).display().to_string());
    let e = io::write(&dir.path().join("mesh.xyz"), &cube(1.0)).unwrap_err();
    assert!(matches!(e, Error::Io { .. }) && named(&e, "mesh.xyz") && e.to_string().contains("'.xyz'"), "{e}");
    assert!(e.to_string().contains("use .stl, .ply or .obj"), "{e}");
    let e = io::write(&dir.path().join("mesh"), &cube(1.0)).unwrap_err();
    assert!(matches!(e, Error::Io { .. }) && e.to_string().contains("no extension"), "{e}");
    let e = io::write_colored_ply(&dir.path().join("c.ply"), &cube(1.0), &[[0, 0, 0]; 5]).unwrap_err();
    assert!(matches!(e, Error::InvalidMesh { .. }) && named(&e, "c.ply"), "{e}");
    assert!(e.to_string().contains("5 face colours given for 12 triangles"), "{e}");
    let broken = TriMesh::new(cube_vertices(1.0), vec![[0, 1, 8]]);
    let e = io::write(&dir.path().join("b.obj"), &broken).unwrap_err();
    assert!(
        matches!(e, Error::InvalidMesh { .. }) && named(&e, "b.obj") && e.to_string().contains("8 vertices"),
        "{e}"
    );
}

#[test]
fn open_mesh_is_refused() {
    let mut m = cube(1.0);
    m.triangles.truncate(10);
    assert_invalid(&mesh_error("open_cube.ply", &m), "the surface is open");
}

#[test]
fn non_manifold_edge_with_three_triangles_is_refused() {
    // Three tetrahedra glued around the edge AB (A = 0, B = 1; C, D, E around it): AB carries
    // exactly three triangles (the three "pages" ABC, ABD, ABE) and no edge is open.
    let v = vec![
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(0.0, 0.0, 1.0),
        Point3::new(1.0, 0.0, 0.5),
        Point3::new(-0.5, 0.8, 0.5),
        Point3::new(-0.5, -0.8, 0.5),
    ];
    let (a, b) = (0, 1);
    let mut t = vec![[a, b, 2], [a, b, 3], [a, b, 4]];
    for (p, q) in [(2, 3), (3, 4), (4, 2)] {
        t.extend([[a, p, q], [b, q, p]]);
    }
    let e = mesh_error("book.obj", &TriMesh::new(v, t));
    assert_invalid(&e, "non-manifold");
    assert!(e.to_string().contains("shared by more than two triangles"), "{e}");
}

#[test]
fn inconsistently_oriented_mesh_is_refused() {
    let mut m = cube(1.0);
    m.triangles[7].swap(1, 2);
    assert_invalid(&mesh_error("one_flipped.stl", &m), "inconsistent orientation");
}

#[test]
fn globally_flipped_cube_loads_flipped_back() {
    let mut m = cube(2.0);
    m.triangles.iter_mut().for_each(|t| t.swap(1, 2));
    assert_eq!(m.signed_volume(), -8.0);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("inside_out.ply");
    io::write(&path, &m).unwrap();
    let (mesh, repairs) = load_solid(&path).unwrap();
    assert!(repairs.flipped);
    assert_eq!(mesh.signed_volume(), 8.0);
}

#[test]
fn flat_double_sided_mesh_is_degenerate() {
    // A square, triangulated along AC on the front and along BD on the back: closed, manifold,
    // consistently oriented, and encloses nothing.
    let v = vec![
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(1.0, 0.0, 0.0),
        Point3::new(1.0, 1.0, 0.0),
        Point3::new(0.0, 1.0, 0.0),
    ];
    let m = TriMesh::new(v, vec![[0, 1, 2], [0, 2, 3], [1, 0, 3], [1, 3, 2]]);
    let e = mesh_error("flat.obj", &m);
    assert!(matches!(e, Error::Degenerate { .. }), "{e:?}");
    assert!(e.to_string().contains("encloses no volume"), "{e}");
}

#[test]
fn errors_from_memory_name_the_hint() {
    let e = read_bytes(b"", Path::new("hint/pebble.stl")).unwrap_err();
    assert!(e.to_string().starts_with("hint/pebble.stl: empty file"), "{e}");
}
