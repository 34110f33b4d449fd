//! The rocks of the shaking experiments: a stone analysed from a mesh or from a mesh file of the
//! repository, a stone's default poses on rock on concrete, and the small formatting of their
//! fragility fits. Included by an experiment with `#[path = "shared/rocks.rs"] mod rocks;`.
#![allow(dead_code)] // each experiment uses the part it needs

use anyhow::Result;
use rocking_stones::dynamics::resting::default_pair;
use rocking_stones::dynamics::shaking::rock_params;
use rocking_stones::ground_motion::fragility::FragilitySurface;
use rocking_stones::mesh::TriMesh;
use rocking_stones::prelude::*;
use std::path::Path;

/// The stone of `a` with its flocks at `nu`, or at its macro ν.
fn stone_of(a: &Analysis, nu: Option<f64>) -> Result<Stone> {
    let nu = nu.unwrap_or_else(|| a.macro_nu(&Options::default()).0);
    Ok(Stone::new(a, nu)?)
}

/// The stone of a closed `mesh`, its flocks at `nu` or at its macro ν.
pub fn of_mesh(mesh: TriMesh, nu: Option<f64>) -> Result<Stone> {
    let (mesh, rep) = mesh.into_solid_boundary()?;
    stone_of(&Analysis::of_solid(mesh, rep, &Options::default())?, nu)
}

/// The analysis of the mesh file `path` (relative to the repository) and its stone at its
/// macro ν.
pub fn of_file(path: &str) -> Result<(Analysis, Stone)> {
    let a = Analysis::of_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join(path), &Options::default())?;
    let stone = stone_of(&a, None)?;
    Ok((a, stone))
}

/// The regular and the rocking default pose (equilibrium indices, [`default_pair`]) of `s` as
/// a rock of R_max `r_max_m` on concrete.
pub fn default_poses(s: &Stone, r_max_m: f64) -> Result<(Option<usize>, Option<usize>)> {
    let (regular, rocking) = default_pair(s, &rock_params(Surface::RockOnConcrete, r_max_m)?);
    let id = |k: Option<usize>| k.map(|k| s.stable()[k].index);
    Ok((id(regular), id(rocking)))
}

/// Coefficient `i` of a fit with its standard error, "β ± se" to 2 decimals.
pub fn beta_se(s: &FragilitySurface, i: usize) -> String {
    format!("{:.2} ± {:.2}", s.beta[i], s.std_err[i])
}

/// The smallest and the largest of non-negative `xs` (∞ and 0 if there are none).
pub fn range(xs: impl IntoIterator<Item = f64>) -> (f64, f64) {
    xs.into_iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), x| (lo.min(x), hi.max(x)))
}

/// A CSV row written with `format!`, split at its commas (no field holds one).
pub fn row(line: String) -> Vec<String> {
    line.split(',').map(String::from).collect()
}
