//! The bundled default stone: a scanned quarry stone (`data/default_pebble.ply`, IBOIS/EPFL, see
//! `data/README.md`), the stone every command runs on when no mesh is given. Its coordinates are
//! millimetres (R_max = 178 mm), so the dynamics run it at its true size by default.

use crate::analysis::{Analysis, Options};
use crate::mesh::io;
use crate::Result;
use std::path::Path;

/// The name reports give it.
pub const NAME: &str = "default_pebble.ply (bundled)";

/// The PLY file.
pub const PLY: &[u8] = include_bytes!("../data/default_pebble.ply");

/// Metres per mesh unit of the bundled stone (millimetres).
pub const LENGTH_UNIT_M: f64 = 1e-3;

/// Is `name` the report name of the bundled stone?
pub fn is_bundled(name: &str) -> bool {
    name == NAME
}

/// Metres per mesh unit of a mesh named `name` when its unit is not given: millimetres for the
/// bundled stone, metres for any other mesh (the unit of field scans).
pub fn default_length_unit_m(name: &str) -> f64 {
    if is_bundled(name) {
        LENGTH_UNIT_M
    } else {
        1.0
    }
}

/// The bundled stone's mesh, checked and oriented as any loaded mesh.
pub fn mesh() -> Result<(crate::mesh::TriMesh, crate::mesh::Repairs)> {
    let mesh = io::read_bytes(PLY, Path::new(NAME))?;
    mesh.into_solid_boundary().map_err(|e| e.with_path(NAME))
}

/// The analysis of the bundled stone with `opts`.
pub fn analysis(opts: &Options) -> Result<Analysis> {
    let (mesh, repairs) = mesh()?;
    Analysis::of_solid(mesh, repairs, opts).map_err(|e| e.with_path(NAME))
}
