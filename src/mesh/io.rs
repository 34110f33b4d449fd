//! Reading and writing meshes: STL (ascii/binary), OBJ, PLY (ascii, binary little/big endian).
//! (Being written: see the helper's work.)

use super::TriMesh;
use crate::{Error, Result};
use std::path::Path;

/// Read a mesh file as it is (no welding or checks). Format by content and extension.
pub fn read(path: &Path) -> Result<TriMesh> {
    Err(Error::Parse { path: path.into(), what: "mesh reading is not implemented yet".into() })
}

/// Write a mesh; the format follows the extension (.stl binary, .ply binary, .obj).
pub fn write(path: &Path, _mesh: &TriMesh) -> Result<()> {
    Err(Error::Parse { path: path.into(), what: "mesh writing is not implemented yet".into() })
}
