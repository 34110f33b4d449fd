//! The rocks of the shaking experiments: a stone analysed from a mesh or from a mesh file of the
//! repository, and rows of a CSV written with `format!`.

use anyhow::Result;
use rocking_stones::dynamics::shaking::stone_of;
use rocking_stones::mesh::TriMesh;
use rocking_stones::prelude::*;

/// The stone of a closed `mesh`, its flocks at `nu` or at its macro ν.
pub fn of_mesh(mesh: TriMesh, nu: Option<f64>) -> Result<Stone> {
    let (mesh, rep) = mesh.into_solid_boundary()?;
    Ok(stone_of(&Analysis::of_solid(mesh, rep, &Options::default())?, nu)?)
}

/// The analysis of the mesh file `path` (relative to the repository) and its stone at its
/// macro ν.
pub fn of_file(path: &str) -> Result<(Analysis, Stone)> {
    let a = Analysis::of_file(&crate::harness::repo().join(path), &Options::default())?;
    let stone = stone_of(&a, None)?;
    Ok((a, stone))
}

/// A CSV row written with `format!`, split at its commas (no field holds one).
pub fn row(line: String) -> Vec<String> {
    line.split(',').map(String::from).collect()
}
