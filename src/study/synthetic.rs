//! Synthetic populations: pebbles of [`crate::generate::pebble`] whose axis ratios scatter around
//! a target sample's mean c/b and c/a.

use super::experimenter::Experimenter;
use super::field::{Counted, Pebble, Study};
use crate::analysis::{Analysis, Options};
use crate::rng::{fnv1a_str, item_rng};
use crate::shape::describe;
use crate::solid::MassProperties;
use crate::stats::mean;
use crate::{generate, Error, Result};
use rand::{Rng, RngExt};
use rand_distr::StandardNormal;
use rayon::prelude::*;
use serde::Serialize;

/// A target sample: mean axis ratios c/b and c/a (measured as the project measures them, see
/// [`crate::shape`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SampleTarget {
    /// Sample name.
    pub name: String,
    /// Target mean c/b.
    pub c_over_b: f64,
    /// Target mean c/a.
    pub c_over_a: f64,
}

/// How a synthetic population is generated (see [`synthetic_specs`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PopulationParams {
    /// Standard deviation of c/b and of b/a between the pebbles of a sample.
    pub spread: f64,
    /// Roughness amplitude of [`generate::pebble`] (largest relative radial deviation).
    pub roughness: f64,
    /// Points of each pebble (the scan resolution).
    pub points: usize,
    /// Pebbles per sample.
    pub count: usize,
    /// Seed of the generator.
    pub seed: u64,
    /// Correct the generator's mean ratios once so that the *measured* means hit the target.
    pub calibrate: bool,
}

impl Default for PopulationParams {
    fn default() -> Self {
        PopulationParams { spread: 0.08, roughness: 0.05, points: 2000, count: 50, seed: 1, calibrate: true }
    }
}

/// One synthetic pebble to generate.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SyntheticSpec {
    /// Semi-axes 1 ≥ b ≥ c of the underlying ellipsoid.
    pub semi_axes: [f64; 3],
    /// Seed of [`generate::pebble`].
    pub seed: u64,
}

/// Smallest ratio drawn for c/b or b/a.
pub const MIN_RATIO: f64 = 0.15;

/// The pebbles of a synthetic sample. Pebble j draws from [`item_rng`]`(seed ^ fnv1a_str(name), j)`
/// a mesh seed and two standard normals z₁, z₂; its ellipsoid has semi-axes
/// (1, β, β γ) with γ = c/b = clamp(μ_c/b + spread·z₁) and β = b/a = clamp(μ_b/a + spread·z₂),
/// clamped to [0.15, 1], μ_b/a = (c/a)/(c/b) of the target. With `calibrate`, the population is
/// generated and measured once ([`describe`]: principal-axes box, which roughness inflates), the
/// means μ are shifted by target − measured, and the specs are drawn again with the same z.
/// So the population depends only on (target, params), not on other samples.
pub fn synthetic_specs(target: &SampleTarget, params: &PopulationParams) -> Result<Vec<SyntheticSpec>> {
    for (what, x) in [("c_over_b", target.c_over_b), ("c_over_a", target.c_over_a)] {
        if !(x > 0.0 && x <= 1.0) {
            return Err(Error::parameter(what, format!("{x} (target {})", target.name), "in (0, 1]"));
        }
    }
    if target.c_over_a > target.c_over_b {
        return Err(Error::parameter(
            "c_over_a",
            format!("{} (target {})", target.c_over_a, target.name),
            format!("at most c/b = {}, since b ≤ a", target.c_over_b),
        ));
    }
    if !(params.spread >= 0.0 && params.spread.is_finite()) {
        return Err(Error::parameter("spread", params.spread, "≥ 0"));
    }
    let base = params.seed ^ fnv1a_str(&target.name);
    let draws: Vec<(u64, f64, f64)> = (0..params.count as u64)
        .map(|j| {
            let mut rng = item_rng(base, j);
            let seed = rng.next_u64();
            (seed, rng.sample::<f64, _>(StandardNormal), rng.sample::<f64, _>(StandardNormal))
        })
        .collect();
    let specs = |mu_cb: f64, mu_ba: f64| -> Vec<SyntheticSpec> {
        draws
            .iter()
            .map(|&(seed, z1, z2)| {
                let cb = (mu_cb + params.spread * z1).clamp(MIN_RATIO, 1.0);
                let ba = (mu_ba + params.spread * z2).clamp(MIN_RATIO, 1.0);
                SyntheticSpec { semi_axes: [1.0, ba, ba * cb], seed }
            })
            .collect()
    };
    let ba_target = (target.c_over_a / target.c_over_b).min(1.0);
    let first = specs(target.c_over_b, ba_target);
    if !params.calibrate || params.count == 0 {
        return Ok(first);
    }
    let measured: Vec<(f64, f64)> = first
        .par_iter()
        .map(|s| -> Result<(f64, f64)> {
            let (mesh, _) =
                generate::pebble(s.semi_axes, params.roughness, params.points, s.seed).into_solid_boundary()?;
            let d = describe(&mesh, &MassProperties::of(&mesh)?);
            Ok((d.c_over_b, d.b_over_a))
        })
        .collect::<Result<_>>()?;
    let m_cb = mean(&measured.iter().map(|m| m.0).collect::<Vec<_>>());
    let m_ba = mean(&measured.iter().map(|m| m.1).collect::<Vec<_>>());
    Ok(specs(target.c_over_b + (target.c_over_b - m_cb), ba_target + (ba_target - m_ba)))
}

/// The pass-through columns of synthetic pebbles.
pub const SYNTHETIC_COLUMNS: [&str; 8] =
    ["target_c_over_b", "target_c_over_a", "spread", "roughness", "points", "mesh_seed", "semi_b", "semi_c"];

/// Generate and count a synthetic sample (ids `NAME_000`, …, sample `NAME`), in parallel; with
/// an experimenter, also the dynamic counts at `nu`. The mesh of a pebble is
/// `generate::pebble(spec.semi_axes, params.roughness, params.points, spec.seed)`.
pub fn synthetic_sample(
    target: &SampleTarget,
    params: &PopulationParams,
    nu: f64,
    exp: Option<&Experimenter>,
) -> Result<Vec<Pebble>> {
    let specs = synthetic_specs(target, params)?;
    let opts = Options::default();
    Ok(specs
        .par_iter()
        .enumerate()
        .map(|(j, s)| {
            let id = format!("{}_{j:03}", target.name);
            let result = generate::pebble(s.semi_axes, params.roughness, params.points, s.seed)
                .into_solid_boundary()
                .and_then(|(mesh, rep)| Analysis::of_solid(mesh, rep, &opts))
                .and_then(|a| Counted::of(&a, &id, &opts, nu, exp, exp.map_or(0, |e| e.seed ^ s.seed)))
                .map_err(|e| e.to_string());
            Pebble {
                id: id.clone(),
                sample: target.name.clone(),
                meta: vec![
                    format!("{}", target.c_over_b),
                    format!("{}", target.c_over_a),
                    format!("{}", params.spread),
                    format!("{}", params.roughness),
                    params.points.to_string(),
                    s.seed.to_string(),
                    format!("{:.6}", s.semi_axes[1]),
                    format!("{:.6}", s.semi_axes[2]),
                ],
                file: id,
                result,
            }
        })
        .collect())
}

/// A study of synthetic samples (one per target), for the CSV writers and plots.
pub fn synthetic_study(
    targets: &[SampleTarget],
    params: &PopulationParams,
    nu: f64,
    exp: Option<&Experimenter>,
) -> Result<Study> {
    let mut pebbles = Vec::new();
    for t in targets {
        pebbles.extend(synthetic_sample(t, params, nu, exp)?);
    }
    Ok(Study {
        nu,
        hand: None,
        meta_columns: SYNTHETIC_COLUMNS.map(String::from).to_vec(),
        pebbles,
        dynamic: exp.is_some(),
    })
}
