//! Wavefront OBJ (geometry only).
//!
//! Rules: `v x y z [w | r g b]` adds a vertex (extra numbers ignored); `f i j k …` adds a polygon,
//! fan-triangulated, each corner written `i`, `i/t`, `i//n` or `i/t/n`. Indices count from 1; a
//! negative index is relative (−1 is the last vertex defined so far); 0 is invalid. Positive
//! indices may refer to vertices defined later in the file (checked at the end). Comments (`#`),
//! normals, texture coordinates, groups, materials, smoothing, lines and points are ignored, as are
//! other statements. Lines may end in `\n`, `\r\n` or `\r`; a trailing `\` joins the next line.

use super::{fan, finite_point, lines, parse_err};
use crate::mesh::TriMesh;
use crate::Result;
use std::borrow::Cow;
use std::fmt::Write as _;

/// Parse an OBJ file.
pub(super) fn read(bytes: &[u8]) -> Result<TriMesh> {
    if bytes.contains(&0) {
        return Err(parse_err("not an OBJ file: it contains NUL bytes (binary data), OBJ is text"));
    }
    let text = String::from_utf8_lossy(bytes);
    let mut mesh = TriMesh::default();
    let mut face_lines = Vec::new(); // line of each triangle, for index errors
    let mut polygon = Vec::new();
    for (line_no, line) in joined_lines(&text) {
        let at = |what: String| parse_err(format!("line {line_no}: {what} ('{}')", line.trim()));
        let mut words = line.split_ascii_whitespace();
        match words.next() {
            Some("v") => mesh.vertices.push(vertex(words).map_err(at)?),
            Some("f") => {
                polygon.clear();
                for w in words {
                    polygon.push(corner(w, mesh.vertices.len()).map_err(at)?);
                }
                if polygon.len() < 3 {
                    return Err(at(format!("a face with {} vertices (at least 3 are needed)", polygon.len())));
                }
                fan(&polygon, &mut mesh.triangles);
                face_lines.resize(mesh.triangles.len(), line_no);
            }
            _ => {}
        }
    }
    check_indices(&mesh, &face_lines)?;
    if mesh.vertices.is_empty() || mesh.triangles.is_empty() {
        return Err(parse_err(format!(
            "OBJ file with {} vertices ('v' lines) and {} faces ('f' lines): no surface",
            mesh.vertices.len(),
            mesh.triangles.len()
        )));
    }
    Ok(mesh)
}

/// Lines with `\`-continuations joined, numbered by the line where each statement starts.
fn joined_lines(text: &str) -> Vec<(usize, Cow<'_, str>)> {
    let mut out: Vec<(usize, Cow<str>)> = Vec::new();
    let mut continued = false;
    for (n, line) in lines(text) {
        let (body, more) = match line.trim_end().strip_suffix('\\') {
            Some(b) => (b, true),
            None => (line, false),
        };
        match out.last_mut() {
            Some((_, last)) if continued => {
                let joined = last.to_mut();
                joined.push(' ');
                joined.push_str(body);
            }
            _ => out.push((n, Cow::Borrowed(body))),
        }
        continued = more;
    }
    out
}

/// The coordinates after `v`: three finite numbers.
fn vertex<'a>(mut words: impl Iterator<Item = &'a str>) -> std::result::Result<crate::Point3, String> {
    let mut c = [0.0; 3];
    for x in &mut c {
        let w = words.next().ok_or("a vertex needs 3 coordinates")?;
        *x = w.parse().map_err(|_| format!("'{w}' is not a number"))?;
    }
    finite_point(c[0], c[1], c[2]).ok_or_else(|| "non-finite vertex coordinate (NaN or infinity)".to_string())
}

/// A face corner `i[/t[/n]]` as a 0-based vertex index; `defined` vertices exist so far.
fn corner(word: &str, defined: usize) -> std::result::Result<u32, String> {
    let index = word.split('/').next().unwrap_or("");
    let i: i64 = index.parse().map_err(|_| format!("'{word}' is not a vertex index"))?;
    let zero_based = match i {
        0 => return Err("vertex index 0 (OBJ indices count from 1)".into()),
        i if i > 0 => i - 1,
        i => defined as i64 + i,
    };
    if zero_based < 0 {
        return Err(format!("relative index {i} reaches before the first vertex ({defined} defined so far)"));
    }
    u32::try_from(zero_based).map_err(|_| format!("vertex index {i} is too large"))
}

/// Every positive index must name a vertex of the whole file.
fn check_indices(mesh: &TriMesh, face_lines: &[usize]) -> Result<()> {
    let n = mesh.vertices.len();
    match mesh.triangles.iter().zip(face_lines).find(|(t, _)| t.iter().any(|&i| i as usize >= n)) {
        Some((t, line)) => {
            let bad = t.iter().find(|&&i| i as usize >= n).map_or(0, |&i| i + 1);
            Err(parse_err(format!(
                "line {line}: face refers to vertex {bad}, out of range (the file has {n} vertices, numbered from 1)"
            )))
        }
        None => Ok(()),
    }
}

/// OBJ text: `v x y z` (shortest exact f64 form) and `f a b c` (1-based).
pub(super) fn text(mesh: &TriMesh) -> Vec<u8> {
    let mut s = String::from("# written by rocking-stones\n");
    for p in &mesh.vertices {
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
    }
    for [a, b, c] in &mesh.triangles {
        let _ = writeln!(s, "f {} {} {}", a + 1, b + 1, c + 1);
    }
    s.into_bytes()
}
