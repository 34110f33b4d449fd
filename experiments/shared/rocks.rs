//! The rocks and records of the shaking experiments: a stone analysed from a mesh or from a
//! mesh file of the repository, a block's resting bottom face, a stone's default poses on rock
//! on concrete, a freestanding block under Housner's rocking equation, families of
//! filtered-noise records, and the small formatting of their fragility fits. Included by an
//! experiment with `#[path = "shared/rocks.rs"] mod rocks;`.
#![allow(dead_code)] // each experiment uses the part it needs

use anyhow::{Context, Result};
use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::resting::default_pair;
use rocking_stones::dynamics::shaking::housner::{housner_overturns, housner_ratio};
use rocking_stones::dynamics::shaking::rock_params;
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::ground_motion::fragility::FragilitySurface;
use rocking_stones::ground_motion::synthetic::{filtered_noise, Noise};
use rocking_stones::ground_motion::Record;
use rocking_stones::mesh::TriMesh;
use rocking_stones::GRAVITY as G;
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

/// The stable equilibrium (its index) of a block resting on its bottom face (normal −z).
pub fn bottom_face(s: &Stone) -> Result<usize> {
    let bottom = s.stable().iter().find(|e| s.body.facet_normals[e.facet as usize].z < -0.999);
    Ok(bottom.context("the block has no stable bottom face")?.index)
}

/// The regular and the rocking default pose (equilibrium indices, [`default_pair`]) of `s` as
/// a rock of R_max `r_max_m` on concrete.
pub fn default_poses(s: &Stone, r_max_m: f64) -> Result<(Option<usize>, Option<usize>)> {
    let (regular, rocking) = default_pair(s, &rock_params(Surface::RockOnConcrete, r_max_m)?);
    let id = |k: Option<usize>| k.map(|k| s.stable()[k].index);
    Ok((id(regular), id(rocking)))
}

/// A freestanding rectangular block for Housner's rocking equation: its slenderness tan α = b/h
/// and the semi-diagonal R (m) of its rocking plane.
pub struct Block {
    pub tan_alpha: f64,
    pub r_m: f64,
}

impl Block {
    /// Housner's frequency parameter p = √(3g/4R) (rad/s).
    pub fn p(&self) -> f64 {
        (3.0 * G / (4.0 * self.r_m)).sqrt()
    }

    /// Whether Housner's equation, with Housner's impact ratio, overturns the block under the
    /// ground acceleration `accel(t)` in its rocking plane (m/s²) within `duration` s.
    pub fn overturns(&self, accel: &dyn Fn(f64) -> f64, duration: f64) -> bool {
        housner_overturns(self.tan_alpha.atan(), self.p(), accel, duration, housner_ratio(self.tan_alpha, 1.0))
    }
}

/// Filtered noise (Kanai–Tajimi–Clough–Penzien with an envelope, 20 s at 200 Hz) of
/// `components` components scaled to PGA 1 g, one record per predominant period × seed (the
/// seeds inner), named by `name(period, seed)`.
pub fn noise_records(
    periods: &[f64],
    seeds: &[u64],
    components: usize,
    name: impl Fn(f64, u64) -> String,
) -> Result<Vec<Record>> {
    let mut records = Vec::new();
    for &period in periods {
        for &seed in seeds {
            let noise = Noise { duration: 20.0, period, components, ..Noise::default() };
            let mut r = filtered_noise(&noise, 1.0, seed)?;
            r.name = name(period, seed);
            records.push(r);
        }
    }
    Ok(records)
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
