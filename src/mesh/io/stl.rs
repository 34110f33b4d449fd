//! STL, ascii and binary.
//!
//! * **Binary**: 80-byte header (free text, may start with `solid`), u32 little-endian triangle
//!   count n, then n records of 50 bytes: normal (3 × f32, ignored), three vertices (3 × 3 × f32),
//!   u16 attribute (ignored). A file is binary iff its length is exactly 84 + 50·n.
//! * **Ascii**: `solid [name]`, then per triangle `facet normal nx ny nz`, `outer loop`,
//!   `vertex x y z` (three times), `endloop`, `endfacet`; finally `endsolid [name]`. Several solids
//!   may follow each other. Normals are ignored; a loop with more than three vertices is
//!   fan-triangulated.
//!
//! STL stores a triangle soup: every triangle gets three new vertices; welding happens later.

use super::{finite_point, lines, normal, parse_err};
use crate::mesh::TriMesh;
use crate::Result;
use std::fmt::Write as _;

/// Size of the binary header plus the triangle count.
const HEAD: usize = 84;
/// Size of one binary triangle record.
const RECORD: usize = 50;

/// True when the file is exactly as long as a binary STL with the triangle count at byte 80 says.
pub(super) fn binary_size_matches(bytes: &[u8]) -> bool {
    bytes.len() >= HEAD && expected_binary_len(bytes) == bytes.len() as u64
}

fn triangle_count(bytes: &[u8]) -> u32 {
    u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]])
}

fn expected_binary_len(bytes: &[u8]) -> u64 {
    HEAD as u64 + RECORD as u64 * u64::from(triangle_count(bytes))
}

/// Parse an STL: binary if the size rule holds, ascii if it is text starting with `solid`,
/// otherwise a binary STL of the wrong size (reported with expected and present byte counts).
pub(super) fn read(bytes: &[u8]) -> Result<TriMesh> {
    if binary_size_matches(bytes) {
        return read_binary(bytes);
    }
    let starts_solid = bytes.trim_ascii_start().starts_with(b"solid");
    if starts_solid && !bytes.contains(&0) {
        return read_ascii(&String::from_utf8_lossy(bytes));
    }
    if bytes.len() < HEAD {
        return Err(parse_err(format!(
            "not an STL: too short for a binary STL ({} bytes, the header and triangle count alone take {HEAD}) \
             and not an ascii STL (does not start with 'solid')",
            bytes.len()
        )));
    }
    let (n, expected) = (triangle_count(bytes), expected_binary_len(bytes));
    let how = if expected > bytes.len() as u64 { "truncated binary STL" } else { "binary STL with trailing data" };
    Err(parse_err(format!(
        "{how}: the header announces {n} triangles, which need {expected} bytes (84 + 50 x {n}), \
         but the file has {} bytes{}",
        bytes.len(),
        if starts_solid { "" } else { " (and it is not an ascii STL: it does not start with 'solid')" }
    )))
}

fn read_binary(bytes: &[u8]) -> Result<TriMesh> {
    let n = triangle_count(bytes) as usize;
    if n == 0 {
        return Err(parse_err("binary STL with 0 triangles: no surface"));
    }
    let mut mesh = TriMesh { vertices: Vec::with_capacity(3 * n), triangles: Vec::with_capacity(n) };
    for (k, record) in bytes[HEAD..].chunks_exact(RECORD).enumerate() {
        let f = |i: usize| f64::from(f32::from_le_bytes(record[4 * i..4 * i + 4].try_into().unwrap()));
        for corner in 0..3 {
            let i = 3 + 3 * corner;
            let p = finite_point(f(i), f(i + 1), f(i + 2)).ok_or_else(|| {
                parse_err(format!(
                    "triangle {k} (at byte {}), corner {corner}: non-finite coordinate ({}, {}, {})",
                    HEAD + k * RECORD,
                    f(i),
                    f(i + 1),
                    f(i + 2)
                ))
            })?;
            mesh.vertices.push(p);
        }
        let v = 3 * k as u32;
        mesh.triangles.push([v, v + 1, v + 2]);
    }
    Ok(mesh)
}

fn read_ascii(text: &str) -> Result<TriMesh> {
    let mut mesh = TriMesh::default();
    let mut loop_start: Option<(usize, usize)> = None; // (line, first vertex of the open loop)
    for (line_no, line) in lines(text) {
        let mut words = line.split_ascii_whitespace();
        let Some(keyword) = words.next() else { continue };
        let at = |what: String| parse_err(format!("line {line_no}: {what}"));
        match keyword {
            "vertex" => mesh.vertices.push(vertex(words, line).map_err(at)?),
            "outer" => loop_start = Some((line_no, mesh.vertices.len())),
            "endloop" => {
                let (_, first) = loop_start.take().ok_or_else(|| at("'endloop' without 'outer loop'".into()))?;
                let count = mesh.vertices.len() - first;
                if count < 3 {
                    return Err(at(format!("a facet with {count} vertices (at least 3 are needed)")));
                }
                let polygon: Vec<u32> = (first as u32..mesh.vertices.len() as u32).collect();
                super::fan(&polygon, &mut mesh.triangles);
            }
            "solid" | "endsolid" | "facet" | "endfacet" => {}
            other => return Err(at(format!("unexpected '{other}' in an ascii STL"))),
        }
    }
    if let Some((line_no, _)) = loop_start {
        return Err(parse_err(format!("line {line_no}: 'outer loop' is never closed by 'endloop' (truncated file?)")));
    }
    if mesh.triangles.is_empty() {
        return Err(parse_err("ascii STL without any facet: no surface"));
    }
    Ok(mesh)
}

/// Parse the three coordinates after `vertex`; they must be finite numbers.
fn vertex<'a>(mut words: impl Iterator<Item = &'a str>, line: &str) -> Result<crate::Point3, String> {
    let mut c = [0.0; 3];
    for x in &mut c {
        let w = words.next().ok_or_else(|| format!("'{}': a vertex needs 3 coordinates", line.trim()))?;
        *x = w.parse().map_err(|_| format!("'{w}' is not a number in '{}'", line.trim()))?;
    }
    finite_point(c[0], c[1], c[2])
        .ok_or_else(|| format!("non-finite vertex coordinate (NaN or infinity) in '{}'", line.trim()))
}

/// Binary STL (f32 coordinates), header `rocking-stones binary STL` (never starting with `solid`).
pub(super) fn binary(mesh: &TriMesh) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEAD + RECORD * mesh.triangles.len());
    let mut header = [b' '; 80];
    let title = b"rocking-stones binary STL";
    header[..title.len()].copy_from_slice(title);
    out.extend_from_slice(&header);
    out.extend_from_slice(&(mesh.triangles.len() as u32).to_le_bytes());
    for t in &mesh.triangles {
        let n = normal(mesh, t);
        let corners = t.iter().map(|&i| mesh.vertices[i as usize].coords);
        for v in std::iter::once(n).chain(corners) {
            v.iter().for_each(|&x| out.extend_from_slice(&(x as f32).to_le_bytes()));
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

/// Ascii STL with f64 coordinates printed exactly (shortest round-trip representation).
pub(super) fn ascii(mesh: &TriMesh) -> Vec<u8> {
    let mut s = String::from("solid rocking-stones\n");
    for t in &mesh.triangles {
        let n = normal(mesh, t);
        let _ = writeln!(s, "  facet normal {} {} {}\n    outer loop", n.x, n.y, n.z);
        for &i in t {
            let p = mesh.vertices[i as usize];
            let _ = writeln!(s, "      vertex {} {} {}", p.x, p.y, p.z);
        }
        s.push_str("    endloop\n  endfacet\n");
    }
    s.push_str("endsolid rocking-stones\n");
    s.into_bytes()
}
