//! What identifies a drop run ([`RunHeader`]): mesh and its fingerprint, seed, number of drops,
//! parameters, certificate, shard. Every partial result of the same run carries the same header.

use crate::dynamics::certificate::CertificateMode;
use crate::dynamics::drops::params::DropParams;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};

/// Which drops a process runs: indices `index`, `index + count`, `index + 2 count`, …
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// Which residue class of drop indices this process runs (0 ≤ index < count).
    pub index: u64,
    /// Number of shards the run is split into.
    pub count: u64,
}

impl Shard {
    /// The whole run.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// [`Shard::ALL`] (for serde defaults).
    pub fn all() -> Shard {
        Shard::ALL
    }

    /// Whether drop `i` belongs to this shard.
    pub fn holds(&self, i: u64) -> bool {
        self.count > 0 && i % self.count == self.index
    }

    /// Parse `i/n` (0 ≤ i < n).
    pub fn parse(s: &str) -> Result<Shard> {
        let bad = || Error::parameter("shard", format!("{s:?}"), "i/n with 0 ≤ i < n");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (i.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// The drop indices of this shard among `n`.
    pub fn indices(&self, n: u64) -> impl Iterator<Item = u64> + '_ {
        (self.index..n).step_by(self.count as usize)
    }
}

/// What identifies a run: every partial result of the same run has the same header.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunHeader {
    /// Checkpoint format tag (`FORMAT`).
    pub format: String,
    /// The mesh file as given (for the report only).
    pub mesh: String,
    /// FNV-1a hash of the mesh's vertices and triangles after loading.
    pub mesh_fingerprint: String,
    /// Seed of the random streams of the drops.
    pub seed: u64,
    /// Number of drops in the run.
    pub drops: u64,
    /// Simulation parameters of the drops.
    pub params: DropParams,
    /// Whether and how the energy certificate may end a drop.
    pub certificate: CertificateMode,
    /// The preset and surface the parameters started from (for the report; `params` is what
    /// was run).
    #[serde(default)]
    pub preset: Option<String>,
    /// The surface pair the contact started from (for the summary; absent from files of earlier
    /// versions and runs made from explicit parameters).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<crate::dynamics::surface::Surface>,
    /// The stone's real R_max (m) the run was made for (for the summary's SI values, a merged
    /// run's too; absent from files of earlier versions and runs made from explicit parameters).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub r_max_m: Option<f64>,
    /// A declared centre of mass (mesh units), if the run used one instead of the solid's G.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center_of_mass: Option<[f64; 3]>,
    /// The shard this file holds (the whole run: 0/1).
    #[serde(default = "Shard::all")]
    pub shard: Shard,
}

impl RunHeader {
    /// The header of a whole run (shard 0/1) of `drops` drops of `mesh` (named `mesh_name`) with
    /// `params`, started from `preset` on `surface`, as `rocking drop` and Python's `drop` write
    /// it; a declared centre of mass and a shard are set on the result.
    pub fn new(
        mesh_name: impl Into<String>,
        mesh: &crate::mesh::TriMesh,
        seed: u64,
        drops: u64,
        params: DropParams,
        certificate: CertificateMode,
        preset: (crate::dynamics::drops::params::Preset, crate::dynamics::surface::Surface),
    ) -> RunHeader {
        RunHeader {
            format: FORMAT.into(),
            mesh: mesh_name.into(),
            mesh_fingerprint: fingerprint(mesh),
            seed,
            drops,
            params,
            certificate,
            preset: Some(format!("{} on {}", preset.0, preset.1)),
            surface: Some(preset.1),
            r_max_m: None,
            center_of_mass: None,
            shard: Shard::ALL,
        }
    }

    /// The header of a whole run (shard 0/1) of `drops` drops named `mesh_name` with explicit
    /// `params`, kept in memory: no mesh fingerprint, no preset named (set them on the result
    /// if the run is journalled). The runs of studies and experiments.
    pub fn of_params(
        mesh_name: impl Into<String>,
        seed: u64,
        drops: u64,
        params: DropParams,
        certificate: CertificateMode,
    ) -> RunHeader {
        RunHeader {
            format: FORMAT.into(),
            mesh: mesh_name.into(),
            mesh_fingerprint: String::new(),
            seed,
            drops,
            params,
            certificate,
            preset: None,
            surface: None,
            r_max_m: None,
            center_of_mass: None,
            shard: Shard::ALL,
        }
    }

    /// This header with `preset` named as the one its parameters started from, by its name alone
    /// ([`crate::dynamics::drops::params::Preset::name`], no surface): the runs of experiments
    /// that start from a preset and change some of its parameters.
    pub fn with_preset(self, preset: crate::dynamics::drops::params::Preset) -> RunHeader {
        RunHeader { preset: Some(preset.name().into()), ..self }
    }

    /// The fields (other than the shard) in which `other` differs from this header: empty when
    /// both belong to the same run.
    pub fn differences(&self, other: &RunHeader) -> Vec<String> {
        let mut d = Vec::new();
        let mut field = |name: &str, same: bool, a: String, b: String| {
            if !same {
                d.push(format!("{name} ({a} vs {b})"));
            }
        };
        field("format", self.format == other.format, self.format.clone(), other.format.clone());
        field(
            "mesh fingerprint",
            self.mesh_fingerprint == other.mesh_fingerprint,
            self.mesh_fingerprint.clone(),
            other.mesh_fingerprint.clone(),
        );
        field("seed", self.seed == other.seed, self.seed.to_string(), other.seed.to_string());
        field("drops", self.drops == other.drops, self.drops.to_string(), other.drops.to_string());
        field("parameters", self.params == other.params, params_text(&self.params), params_text(&other.params));
        field(
            "certificate",
            self.certificate == other.certificate,
            self.certificate.name().into(),
            other.certificate.name().into(),
        );
        field(
            "centre of mass",
            self.center_of_mass == other.center_of_mass,
            centre_text(self.center_of_mass),
            centre_text(other.center_of_mass),
        );
        d
    }
}

/// Parameters as a person compares them: their JSON.
fn params_text(p: &DropParams) -> String {
    serde_json::to_string(p).unwrap_or_default()
}

/// A centre of mass as given by `--center-of-mass`, or the homogeneous solid's.
fn centre_text(c: Option<[f64; 3]>) -> String {
    c.map_or("the homogeneous solid's G".into(), |[x, y, z]| format!("({x}, {y}, {z})"))
}

/// Header format tag of checkpoint files (2: launches with horizontal speed and Gaussian spin,
/// rolling resistance, outcomes by the quasi-static descent; 3: exact landings and sub-stepped
/// impacts under `flight = free`, now the default, and torsional friction on single contact
/// points only — a run of format 2 cannot be resumed or merged with the numerics of 3).
pub const FORMAT: &str = "rocking-drops/3";

/// FNV-1a over the bit patterns of the vertices and the triangle indices.
pub fn fingerprint(mesh: &crate::mesh::TriMesh) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |x: u64| {
        for b in x.to_le_bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    };
    mesh.vertices.iter().flat_map(|p| p.coords.iter().copied().collect::<Vec<_>>()).for_each(|x| eat(x.to_bits()));
    mesh.triangles.iter().flatten().for_each(|&i| eat(i as u64));
    format!("{h:016x}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::drops::params::Preset;
    use crate::dynamics::surface::Surface;

    #[test]
    fn a_header_names_the_preset_it_started_from() {
        let params = Preset::Drop.params(Surface::SteelOnWood);
        let header = RunHeader::of_params("pebble", 7, 30, params, CertificateMode::Flock);
        assert_eq!(header.preset, None);
        let named = header.clone().with_preset(Preset::Throw);
        assert_eq!(named.preset.as_deref(), Some("throw"));
        // Nothing else changes: the two are the same run.
        assert!(named.differences(&header).is_empty());
    }
}
