//! PLY (Stanford polygon file), ascii and binary little/big endian.
//!
//! Header rules: the first line is `ply`; header lines end in `\n`, `\r\n` or a bare `\r` (the
//! terminator of the `ply` line is the one expected after `end_header`, so binary data starting
//! with a `\n` byte is not eaten); `format ascii|binary_little_endian|binary_big_endian 1.0`;
//! `comment` and `obj_info` lines are ignored; `element NAME COUNT` is followed by its
//! `property TYPE NAME` and `property list COUNT_TYPE ITEM_TYPE NAME` lines. Scalar types:
//! `char uchar short ushort int uint float double` and the aliases
//! `int8 uint8 int16 uint16 int32 uint32 float32 float64`.
//!
//! What is used: element `vertex` with scalar `x`, `y`, `z` (any type), element `face` with an
//! integer list `vertex_indices` (or `vertex_index`). Every other property and element is read
//! past according to its declared types and ignored. Faces with more than three vertices are
//! fan-triangulated.

use super::{fan, finite_point, lines, parse_err};
use crate::mesh::TriMesh;
use crate::{Point3, Result};
use std::fmt::Write as _;

/// True when the data starts with the `ply` magic line.
pub(super) fn has_magic(bytes: &[u8]) -> bool {
    bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r")
}

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// Decode one value from exactly `self.size()` bytes.
    fn decode(self, b: &[u8], big: bool) -> f64 {
        macro_rules! num {
            ($t:ty) => {{
                let a = b.try_into().unwrap();
                f64::from(if big { <$t>::from_be_bytes(a) } else { <$t>::from_le_bytes(a) })
            }};
        }
        match self {
            Scalar::I8 => f64::from(b[0] as i8),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => num!(i16),
            Scalar::U16 => num!(u16),
            Scalar::I32 => num!(i32),
            Scalar::U32 => num!(u32),
            Scalar::F32 => num!(f32),
            Scalar::F64 => num!(f64),
        }
    }
}

/// A declared property: a scalar, or a list with its count and item types.
#[derive(Clone, Debug)]
struct Property {
    name: String,
    count: Option<Scalar>,
    item: Scalar,
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

/// The parsed header, the byte offset of the body and the number of header lines.
struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    body: usize,
    lines: usize,
}

/// Parse a PLY file.
pub(super) fn read(bytes: &[u8]) -> Result<TriMesh> {
    if !has_magic(bytes) {
        let start = String::from_utf8_lossy(&bytes[..bytes.len().min(16)]).into_owned();
        return Err(parse_err(format!("not a PLY file: it must start with a line 'ply', it starts with {start:?}")));
    }
    let header = header(bytes)?;
    let mut sink = sink_for(&header.elements, bytes.len() / 3)?;
    match header.encoding {
        Encoding::Ascii => read_ascii(&bytes[header.body..], &header, &mut sink)
            .map_err(|e| count_hint(e, &bytes[header.body..], &header))?,
        enc => read_binary(&bytes[header.body..], header.body, &header.elements, enc == Encoding::Big, &mut sink)?,
    }
    Ok(sink.mesh)
}

/// Locate `end_header` at the start of a line and parse the header lines before it.
fn header(bytes: &[u8]) -> Result<Header> {
    let crlf = bytes.starts_with(b"ply\r\n");
    let bare_cr = !crlf && bytes[3] == b'\r';
    let key = b"end_header";
    let end = (4..bytes.len().saturating_sub(key.len() - 1))
        .find(|&i| matches!(bytes[i - 1], b'\n' | b'\r') && bytes[i..].starts_with(key))
        .ok_or_else(|| parse_err("PLY header has no 'end_header' line (truncated or not a PLY file)"))?;
    let after = end + key.len();
    let rest = &bytes[after..];
    let terminator = if rest.starts_with(b"\r\n") && !bare_cr {
        2
    } else if rest.starts_with(b"\n") || rest.starts_with(b"\r") {
        1
    } else if rest.is_empty() {
        0
    } else {
        return Err(parse_err("PLY header: 'end_header' must be followed by the end of the line"));
    };
    let text = std::str::from_utf8(&bytes[..end])
        .map_err(|_| parse_err("PLY header contains bytes that are not text (UTF-8/ASCII)"))?;
    let mut h = Header { encoding: Encoding::Ascii, elements: vec![], body: after + terminator, lines: 0 };
    let mut format_seen = false;
    for (line_no, line) in lines(text).skip(1) {
        h.lines = line_no;
        let words: Vec<&str> = line.split_ascii_whitespace().collect();
        let at = |what: String| parse_err(format!("PLY header line {line_no} ('{}'): {what}", line.trim()));
        match words.as_slice() {
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", enc, _version] => {
                format_seen = true;
                h.encoding = match *enc {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Little,
                    "binary_big_endian" => Encoding::Big,
                    _ => return Err(at("unknown format (ascii, binary_little_endian, binary_big_endian)".into())),
                }
            }
            ["element", name, count] => {
                let count = count.parse().map_err(|_| at("the element count is not a non-negative integer".into()))?;
                h.elements.push(Element { name: name.to_string(), count, properties: vec![] });
            }
            ["property", ..] => {
                let p = property(&words).map_err(at)?;
                h.elements.last_mut().ok_or_else(|| at("property before any element".into()))?.properties.push(p);
            }
            _ => return Err(at("not a PLY header line".into())),
        }
    }
    h.lines += 1; // the end_header line
    if !format_seen {
        return Err(parse_err("PLY header has no 'format' line"));
    }
    Ok(h)
}

/// `property TYPE NAME` or `property list COUNT_TYPE ITEM_TYPE NAME`.
fn property(words: &[&str]) -> std::result::Result<Property, String> {
    let ty = |w: &str| Scalar::parse(w).ok_or_else(|| format!("unknown property type '{w}'"));
    match words {
        ["property", "list", count, item, name] => {
            let count = ty(count)?;
            if !count.is_integer() {
                return Err(format!("a list count must have an integer type, not '{}'", words[2]));
            }
            Ok(Property { name: name.to_string(), count: Some(count), item: ty(item)? })
        }
        ["property", item, name] => Ok(Property { name: name.to_string(), count: None, item: ty(item)? }),
        _ => Err("expected 'property TYPE NAME' or 'property list COUNT_TYPE ITEM_TYPE NAME'".into()),
    }
}

/// Find vertex x/y/z and the face index list (types checked) and prepare to collect them;
/// `capacity` bounds the vertex storage reserved up front (a header may lie about counts).
fn sink_for(elements: &[Element], capacity: usize) -> Result<Sink> {
    let find = |name: &str| elements.iter().find(|e| e.name == name);
    let vertex = find("vertex").ok_or_else(|| parse_err("PLY header has no 'vertex' element"))?;
    let face = find("face")
        .ok_or_else(|| parse_err("PLY header has no 'face' element: a point cloud, not a surface (zero faces)"))?;
    let mut xyz = [0; 3];
    for (slot, axis) in xyz.iter_mut().zip(["x", "y", "z"]) {
        *slot = vertex
            .properties
            .iter()
            .position(|p| p.name == axis && p.count.is_none())
            .ok_or_else(|| parse_err(format!("PLY element 'vertex' has no scalar property '{axis}'")))?;
    }
    let indices = face
        .properties
        .iter()
        .position(|p| p.count.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index"))
        .ok_or_else(|| parse_err("PLY element 'face' has no list property 'vertex_indices' or 'vertex_index'"))?;
    if !face.properties[indices].item.is_integer() {
        return Err(parse_err("PLY face indices must have an integer type"));
    }
    if vertex.count > u32::MAX as usize {
        return Err(parse_err(format!("PLY file with {} vertices: more than 2^32 are not supported", vertex.count)));
    }
    if vertex.count == 0 || face.count == 0 {
        return Err(parse_err(format!("PLY file with {} vertices and {} faces: no surface", vertex.count, face.count)));
    }
    Ok(Sink {
        mesh: TriMesh { vertices: Vec::with_capacity(vertex.count.min(capacity)), triangles: Vec::new() },
        xyz,
        indices,
        vertex_count: vertex.count,
        values: [0.0; 3],
        polygon: Vec::new(),
    })
}

/// Collects vertices and triangles while the body is read; checks every value as it arrives.
struct Sink {
    mesh: TriMesh,
    xyz: [usize; 3],
    indices: usize,
    vertex_count: usize,
    values: [f64; 3],
    polygon: Vec<u32>,
}

impl Sink {
    /// A scalar property of the current vertex.
    fn vertex_value(&mut self, property: usize, value: f64) {
        if let Some(axis) = self.xyz.iter().position(|&p| p == property) {
            self.values[axis] = value;
        }
    }

    fn end_vertex(&mut self, index: usize) -> std::result::Result<(), String> {
        let [x, y, z] = self.values;
        let p: Point3 = finite_point(x, y, z)
            .ok_or_else(|| format!("vertex {index} has a non-finite coordinate ({x}, {y}, {z}): NaN or infinity"))?;
        self.mesh.vertices.push(p);
        Ok(())
    }

    /// Check one face's indices (in range, at least 3) and fan-triangulate it.
    fn face(&mut self, index: usize, values: &[f64]) -> std::result::Result<(), String> {
        if values.len() < 3 {
            return Err(format!("face {index} has {} vertices (at least 3 are needed)", values.len()));
        }
        self.polygon.clear();
        for &v in values {
            if !(v >= 0.0 && v < self.vertex_count as f64 && v.fract() == 0.0) {
                return Err(format!(
                    "face {index} refers to vertex {v}, out of range (there are {} vertices, numbered from 0)",
                    self.vertex_count
                ));
            }
            self.polygon.push(v as u32);
        }
        fan(&self.polygon, &mut self.mesh.triangles);
        Ok(())
    }
}

/// Read the binary body: every element in header order, its instances property by property.
/// `offset` is the body's position in the file (for messages).
fn read_binary(body: &[u8], offset: usize, elements: &[Element], big: bool, sink: &mut Sink) -> Result<()> {
    let mut pos = 0;
    let mut list = Vec::new();
    for e in elements {
        if let Some(stride) = fixed_size(e) {
            let need = e.count.checked_mul(stride).and_then(|s| s.checked_add(pos)).unwrap_or(usize::MAX);
            if need > body.len() {
                return Err(parse_err(format!(
                    "truncated binary PLY: element '{}' ({} x {stride} bytes from byte {}) needs the file to have \
                     {} bytes, but it has only {} bytes",
                    e.name,
                    e.count,
                    offset + pos,
                    offset.saturating_add(need),
                    offset + body.len()
                )));
            }
        }
        let role = Role::of(e);
        for i in 0..e.count {
            let short = |need: usize| {
                parse_err(format!(
                    "truncated binary PLY: element '{}' {i} of {} needs at least {} bytes of file, \
                     but the file has only {} bytes",
                    e.name,
                    e.count,
                    offset.saturating_add(need),
                    offset + body.len()
                ))
            };
            for (k, p) in e.properties.iter().enumerate() {
                let n = match p.count {
                    None => 1,
                    Some(c) => {
                        let b = body.get(pos..pos + c.size()).ok_or_else(|| short(pos + c.size()))?;
                        pos += c.size();
                        list_length(c.decode(b, big), e, i).map_err(parse_err)?
                    }
                };
                let need = n.checked_mul(p.item.size()).and_then(|s| s.checked_add(pos)).unwrap_or(usize::MAX);
                let bytes = body.get(pos..need).ok_or_else(|| short(need))?;
                pos = need;
                if role == Role::Other || (role == Role::Face && k != sink.indices) {
                    continue;
                }
                list.clear();
                list.extend(bytes.chunks_exact(p.item.size()).map(|b| p.item.decode(b, big)));
                deliver(sink, role, i, k, &list).map_err(parse_err)?;
            }
            if role == Role::Vertex {
                sink.end_vertex(i).map_err(parse_err)?;
            }
        }
    }
    Ok(())
}

/// Bytes per instance of an element without list properties.
fn fixed_size(e: &Element) -> Option<usize> {
    e.properties.iter().map(|p| p.count.is_none().then_some(p.item.size())).sum()
}

/// A list length read from the file: a non-negative integer.
fn list_length(n: f64, e: &Element, i: usize) -> std::result::Result<usize, String> {
    if n >= 0.0 {
        Ok(n as usize)
    } else {
        Err(format!("{} {i}: negative list length {n}", e.name))
    }
}

/// Which of the used elements an element is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    Vertex,
    Face,
    Other,
}

impl Role {
    fn of(e: &Element) -> Role {
        match e.name.as_str() {
            "vertex" => Role::Vertex,
            "face" => Role::Face,
            _ => Role::Other,
        }
    }
}

/// Hand property `k` of instance `i` of a used element to the sink.
fn deliver(sink: &mut Sink, role: Role, i: usize, k: usize, values: &[f64]) -> std::result::Result<(), String> {
    match role {
        Role::Vertex => {
            if let [v] = values {
                sink.vertex_value(k, *v);
            }
            Ok(())
        }
        Role::Face if k == sink.indices => sink.face(i, values),
        _ => Ok(()),
    }
}

/// Read the ascii body: whitespace-separated numbers, normally one element instance per line
/// (instances may also span or share lines).
fn read_ascii(body: &[u8], header: &Header, sink: &mut Sink) -> Result<()> {
    let text = std::str::from_utf8(body).map_err(|_| parse_err("ascii PLY body contains bytes that are not text"))?;
    let words = lines(text).flat_map(|(n, l)| l.split_ascii_whitespace().map(move |w| (n + header.lines, w)));
    let mut tokens = Tokens { words, line: header.lines };
    let at = |line: usize, what: String| parse_err(format!("line {line}: {what}"));
    let mut list = Vec::new();
    for e in &header.elements {
        let role = Role::of(e);
        for i in 0..e.count {
            for (k, p) in e.properties.iter().enumerate() {
                let n = match p.count {
                    None => 1,
                    Some(c) => list_length(tokens.next(c, e, i)?, e, i).map_err(|w| at(tokens.line, w))?,
                };
                list.clear();
                for _ in 0..n {
                    list.push(tokens.next(p.item, e, i)?);
                }
                deliver(sink, role, i, k, &list).map_err(|w| at(tokens.line, w))?;
            }
            if role == Role::Vertex {
                sink.end_vertex(i).map_err(|w| at(tokens.line, w))?;
            }
        }
    }
    if let Some((line, w)) = tokens.words.next() {
        return Err(at(
            line,
            format!("'{w}' follows the last element the header declares: the body holds more data than the header's element counts"),
        ));
    }
    Ok(())
}

/// When an ascii body fails to parse and its number of non-empty lines differs from the number
/// of element instances the header declares, say so first: a wrong count in the header makes the
/// reader take face lines for vertices (or the reverse), and the value it then trips over is a
/// consequence, not the cause.
fn count_hint(e: crate::Error, body: &[u8], header: &Header) -> crate::Error {
    use crate::Error;
    let Error::Parse { path, what } = e else { return e };
    let declared: usize = header.elements.iter().map(|e| e.count).sum();
    let text = String::from_utf8_lossy(body);
    let present = lines(&text).filter(|(_, l)| !l.trim().is_empty()).count();
    if present == declared {
        return Error::Parse { path, what };
    }
    let counts: Vec<String> = header.elements.iter().map(|e| format!("{} {}", e.count, e.name)).collect();
    Error::Parse {
        path,
        what: format!(
            "the header's element counts do not match the data: it declares {} ({declared} lines of data) but the body has {present} non-empty lines (reading stopped at: {what})",
            counts.join(", ")
        ),
    }
}

/// The numbers of an ascii body with the line of the last one read.
struct Tokens<I> {
    words: I,
    line: usize,
}

impl<'a, I: Iterator<Item = (usize, &'a str)>> Tokens<I> {
    /// The next number, of type `ty`, for instance `i` of element `e`.
    fn next(&mut self, ty: Scalar, e: &Element, i: usize) -> Result<f64> {
        let (line, w) = self.words.next().ok_or_else(|| {
            parse_err(format!(
                "ascii PLY ends early (after line {}): element '{}' {i} of {} is incomplete",
                self.line, e.name, e.count
            ))
        })?;
        self.line = line;
        ascii_value(w, ty)
            .ok_or_else(|| parse_err(format!("line {line}: '{w}' is not a valid {ty:?} value ({} {i})", e.name)))
    }
}

/// Parse an ascii value of a declared type: integers must be integral (`3` or `3.0`) and within the
/// type's range;
/// floats accept anything Rust parses (NaN and infinity are refused later, for coordinates).
fn ascii_value(word: &str, ty: Scalar) -> Option<f64> {
    if !ty.is_integer() {
        return word.parse().ok();
    }
    let v = match word.parse::<i64>() {
        Ok(v) => v,
        Err(_) => word.parse::<f64>().ok().filter(|v| v.fract() == 0.0 && v.abs() < 1e12)? as i64,
    };
    let (lo, hi) = match ty {
        Scalar::I8 => (i8::MIN as i64, i8::MAX as i64),
        Scalar::U8 => (0, u8::MAX as i64),
        Scalar::I16 => (i16::MIN as i64, i16::MAX as i64),
        Scalar::U16 => (0, u16::MAX as i64),
        Scalar::I32 => (i32::MIN as i64, i32::MAX as i64),
        _ => (0, u32::MAX as i64),
    };
    (lo..=hi).contains(&v).then_some(v as f64)
}

/// Header text of the written files.
fn header_text(mesh: &TriMesh, format: &str, colors: bool) -> String {
    let mut s = format!(
        "ply\nformat {format} 1.0\ncomment written by rocking-stones\nelement vertex {}\n\
         property double x\nproperty double y\nproperty double z\nelement face {}\n\
         property list uchar int vertex_indices\n",
        mesh.vertices.len(),
        mesh.triangles.len()
    );
    if colors {
        s.push_str("property uchar red\nproperty uchar green\nproperty uchar blue\n");
    }
    s.push_str("end_header\n");
    s
}

/// Binary little-endian PLY, double x/y/z, optional per-face uchar red/green/blue.
pub(super) fn binary(mesh: &TriMesh, colors: Option<&[[u8; 3]]>) -> Vec<u8> {
    let mut out = header_text(mesh, "binary_little_endian", colors.is_some()).into_bytes();
    out.reserve(24 * mesh.vertices.len() + 16 * mesh.triangles.len());
    for p in &mesh.vertices {
        p.coords.iter().for_each(|x| out.extend_from_slice(&x.to_le_bytes()));
    }
    for (k, t) in mesh.triangles.iter().enumerate() {
        out.push(3);
        t.iter().for_each(|&i| out.extend_from_slice(&(i as i32).to_le_bytes()));
        if let Some(c) = colors {
            out.extend_from_slice(&c[k]);
        }
    }
    out
}

/// Ascii PLY, coordinates printed in the shortest form that reads back bit-exactly.
pub(super) fn ascii(mesh: &TriMesh) -> Vec<u8> {
    let mut s = header_text(mesh, "ascii", false);
    for p in &mesh.vertices {
        let _ = writeln!(s, "{} {} {}", p.x, p.y, p.z);
    }
    for [a, b, c] in &mesh.triangles {
        let _ = writeln!(s, "3 {a} {b} {c}");
    }
    s.into_bytes()
}
