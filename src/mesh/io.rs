//! Reading and writing meshes: STL (ascii/binary), OBJ, PLY (ascii, binary little/big endian).
//!
//! Readers return the mesh exactly as stored (STL: a triangle soup with three new vertices per
//! triangle; polygons fan-triangulated), with no welding and no topological checks: that is
//! [`TriMesh::into_solid_boundary`]'s job, and [`load_solid`] runs both. What the readers do refuse
//! is anything that is not a well-formed file: empty or truncated files, bad magic or headers,
//! non-numeric or non-finite (NaN, ±inf) coordinates, face indices out of range, faces with fewer
//! than three vertices, and files without vertices or faces. Every error names the file and says
//! where (line, vertex, face, element or byte offset) the problem is.
//!
//! Format detection ([`read_bytes`]): by extension (`.stl`, `.ply`, `.obj`, any case); for any
//! other extension by content (`ply` magic, binary STL size rule, `solid` keyword, OBJ `v` lines).

mod obj;
mod ply;
mod stl;

use super::{Repairs, TriMesh};
use crate::error::MEMORY;
use crate::{Error, Point3, Result};
use std::path::Path;

/// Read a mesh file as it is (no welding or checks). Format by extension, else by content.
pub fn read(path: &Path) -> Result<TriMesh> {
    let bytes = std::fs::read(path).map_err(|error| Error::Io { path: path.into(), error })?;
    read_bytes(&bytes, path)
}

/// Parse a mesh held in memory; `name_hint` selects the format by its extension (as [`read`])
/// and is the file name every error reports.
pub fn read_bytes(bytes: &[u8], name_hint: &Path) -> Result<TriMesh> {
    parse(bytes, name_hint).map_err(|e| e.with_path(name_hint))
}

/// Read a mesh and make it the boundary of a solid ([`TriMesh::into_solid_boundary`]: weld,
/// drop unused vertices and zero-area triangles, check closed / manifold / oriented / one shell /
/// non-zero volume, flip a globally inward surface). Every error names the file.
pub fn load_solid(path: &Path) -> Result<(TriMesh, Repairs)> {
    read(path)?.into_solid_boundary().map_err(|e| e.with_path(path))
}

/// Write a mesh; the format follows the extension: `.stl` binary STL, `.ply` binary little-endian
/// PLY with float64 x/y/z and `uchar int vertex_indices`, `.obj` Wavefront OBJ. Any other
/// extension is an [`Error::Io`] naming the file and the extensions it can write.
pub fn write(path: &Path, mesh: &TriMesh) -> Result<()> {
    let bytes = match extension(path).as_deref() {
        Some("stl") => stl::binary(mesh),
        Some("ply") => ply::binary(mesh, None),
        Some("obj") => obj::text(mesh),
        other => {
            let what = other.map_or("no extension".into(), |e| format!("unknown mesh extension '.{e}'"));
            let error =
                std::io::Error::new(std::io::ErrorKind::InvalidInput, format!("{what} (use .stl, .ply or .obj)"));
            return Err(Error::Io { path: path.to_path_buf(), error });
        }
    };
    write_file(path, mesh, bytes)
}

/// Write an ascii STL (`solid` / `facet normal` / `outer loop` / 3 × `vertex` / `endloop` /
/// `endfacet` / `endsolid`), coordinates printed so that they read back bit-exactly in f64.
pub fn write_ascii_stl(path: &Path, mesh: &TriMesh) -> Result<()> {
    write_file(path, mesh, stl::ascii(mesh))
}

/// Write an ascii PLY (`format ascii 1.0`, double x/y/z, `list uchar int vertex_indices`),
/// coordinates printed so that they read back bit-exactly.
pub fn write_ply_ascii(path: &Path, mesh: &TriMesh) -> Result<()> {
    write_file(path, mesh, ply::ascii(mesh))
}

/// Write a binary little-endian PLY with one colour per triangle (face properties `uchar red`,
/// `uchar green`, `uchar blue` after `vertex_indices`), as MeshLab and ParaView display it.
/// `face_colors` must have one entry per triangle, else [`Error::InvalidMesh`].
pub fn write_colored_ply(path: &Path, mesh: &TriMesh, face_colors: &[[u8; 3]]) -> Result<()> {
    if face_colors.len() != mesh.triangles.len() {
        return Err(Error::InvalidMesh {
            path: path.to_path_buf(),
            what: format!(
                "cannot write it: {} face colours given for {} triangles",
                face_colors.len(),
                mesh.triangles.len()
            ),
        });
    }
    write_file(path, mesh, ply::binary(mesh, Some(face_colors)))
}

/// The format a file is parsed as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Stl,
    Ply,
    Obj,
}

fn parse(bytes: &[u8], name: &Path) -> Result<TriMesh> {
    if bytes.is_empty() {
        return Err(parse_err("empty file (0 bytes): no mesh to read"));
    }
    let mesh = match detect(bytes, name)? {
        Format::Stl => stl::read(bytes)?,
        Format::Ply => ply::read(bytes)?,
        Format::Obj => obj::read(bytes)?,
    };
    if mesh.vertices.is_empty() || mesh.triangles.is_empty() {
        return Err(parse_err(format!(
            "no surface: the file has {} vertices and {} faces",
            mesh.vertices.len(),
            mesh.triangles.len()
        )));
    }
    Ok(mesh)
}

/// The extension decides when it is `.stl`, `.ply` or `.obj`; otherwise the content: `ply` magic,
/// a binary STL whose size is 84 + 50·n, a text starting with `solid`, or a text with `v` lines.
fn detect(bytes: &[u8], name: &Path) -> Result<Format> {
    match extension(name).as_deref() {
        Some("stl") => return Ok(Format::Stl),
        Some("ply") => return Ok(Format::Ply),
        Some("obj") => return Ok(Format::Obj),
        _ => {}
    }
    let text_start = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]);
    if ply::has_magic(bytes) {
        Ok(Format::Ply)
    } else if stl::binary_size_matches(bytes) || text_start.trim_start().starts_with("solid") {
        Ok(Format::Stl)
    } else if !bytes.contains(&0) && lines(&text_start).any(|(_, l)| l.trim_start().starts_with("v ")) {
        Ok(Format::Obj)
    } else {
        let ext = extension(name).map_or("no extension".to_string(), |e| format!("extension '.{e}'"));
        Err(parse_err(format!(
            "unknown mesh format ({ext}, and the content is not PLY, STL or OBJ); use .stl, .ply or .obj"
        )))
    }
}

/// Lower-case extension of a path, if any.
fn extension(path: &Path) -> Option<String> {
    path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase())
}

/// A parse error without a file name yet ([`read_bytes`] adds it).
fn parse_err(what: impl Into<String>) -> Error {
    Error::Parse { path: MEMORY.into(), what: what.into() }
}

/// Lines of a text ending in `\n`, `\r\n` or a bare `\r`, numbered from 1, without terminators.
fn lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut rest = text;
    let mut number = 0;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        number += 1;
        let end = rest.find(['\n', '\r']).unwrap_or(rest.len());
        let (line, after) = rest.split_at(end);
        let terminator = if after.starts_with("\r\n") { 2 } else { after.len().min(1) };
        rest = &after[terminator..];
        Some((number, line))
    })
}

/// A point from three coordinates, `None` if any is NaN or infinite.
fn finite_point(x: f64, y: f64, z: f64) -> Option<Point3> {
    (x.is_finite() && y.is_finite() && z.is_finite()).then(|| Point3::new(x, y, z))
}

/// Fan-triangulate a polygon `p0 p1 … pk` into `(p0, p_i, p_i+1)`; the caller ensures k ≥ 2.
fn fan(polygon: &[u32], out: &mut Vec<[u32; 3]>) {
    out.extend(polygon.windows(2).skip(1).map(|w| [polygon[0], w[0], w[1]]));
}

/// Refuse to write a mesh whose triangles point past its vertices, then write the bytes.
fn write_file(path: &Path, mesh: &TriMesh, bytes: Vec<u8>) -> Result<()> {
    let n = mesh.vertices.len();
    if let Some((k, t)) = mesh.triangles.iter().enumerate().find(|(_, t)| t.iter().any(|&i| i as usize >= n)) {
        return Err(Error::InvalidMesh {
            path: path.to_path_buf(),
            what: format!("cannot write it: triangle {k} refers to vertex {t:?} but the mesh has {n} vertices"),
        });
    }
    std::fs::write(path, bytes).map_err(|error| Error::Io { path: path.into(), error })
}

/// Outward unit normal of a counter-clockwise triangle (zero for a degenerate one).
fn normal(mesh: &TriMesh, t: &[u32; 3]) -> crate::Vec3 {
    let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
    (b - a).cross(&(c - a)).try_normalize(0.0).unwrap_or_else(crate::Vec3::zeros)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_split_on_lf_crlf_and_bare_cr() {
        let got: Vec<_> = lines("a\nb\r\nc\rd").collect();
        assert_eq!(got, vec![(1, "a"), (2, "b"), (3, "c"), (4, "d")]);
        let got: Vec<_> = lines("a\r\r\nb\n").collect();
        assert_eq!(got, vec![(1, "a"), (2, ""), (3, "b")]);
    }

    #[test]
    fn fan_triangulates_polygons() {
        let mut out = vec![];
        fan(&[0, 1, 2, 3, 4], &mut out);
        assert_eq!(out, vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
    }

    #[test]
    fn detection_by_content_when_the_extension_is_unknown() {
        let name = Path::new("x.dat");
        assert_eq!(detect(b"ply\nformat ascii 1.0\n", name).unwrap(), Format::Ply);
        assert_eq!(detect(b"solid\nfacet normal 0 0 1\n", name).unwrap(), Format::Stl);
        assert_eq!(detect(b"# c\nv 0 0 0\n", name).unwrap(), Format::Obj);
        let e = detect(b"hello", name).unwrap_err().to_string();
        assert!(e.contains("unknown mesh format") && e.contains(".dat"), "{e}");
    }
}
