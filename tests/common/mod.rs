//! Helpers shared by the integration tests: stones and their resting faces, drop-run headers,
//! malformed-file errors, the source tree.
#![allow(dead_code)] // each test uses the helpers it needs

use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::certificate::CertificateMode;
use rocking_stones::dynamics::drops::montecarlo::{RunHeader, Shard, FORMAT};
use rocking_stones::dynamics::drops::params::DropParams;
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::mesh::io::load_solid;
use rocking_stones::mesh::TriMesh;
use rocking_stones::Error;
use std::path::{Path, PathBuf};

/// The stone of a closed mesh at its macro ν.
pub fn stone(mesh: TriMesh) -> Stone {
    let (mesh, rep) = mesh.into_solid_boundary().unwrap();
    let a = Analysis::of_solid(mesh, rep, &Options::default()).unwrap();
    let (nu, _) = a.macro_nu(&Options::default());
    Stone::new(&a, nu).unwrap()
}

/// Analysis index of the stable micro-equilibrium of the face with normal −z.
pub fn bottom(s: &Stone) -> usize {
    s.stable().iter().find(|e| s.body.facet_normals[e.facet as usize].z < -0.999).unwrap().index
}

/// The header of a test drop run of mesh "test": `drops` drops of `params` from `seed`, every
/// shard.
pub fn drop_header(
    drops: u64,
    seed: u64,
    params: DropParams,
    certificate: CertificateMode,
    preset: Option<&str>,
) -> RunHeader {
    RunHeader {
        format: FORMAT.into(),
        mesh: "test".into(),
        mesh_fingerprint: "0".into(),
        seed,
        drops,
        params,
        certificate,
        preset: preset.map(Into::into),
        surface: None,
        r_max_m: None,
        center_of_mass: None,
        shard: Shard::ALL,
    }
}

/// Write `bytes` to `name` in a fresh directory and return the error of `load_solid`, checking
/// that its message names the file.
pub fn load_error(name: &str, bytes: &[u8]) -> Error {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    let e = load_solid(&path).expect_err(name);
    assert!(e.to_string().contains(name), "the message must name the file: {e}");
    e
}

/// Every `.rs` file under `dir`, recursively, into `out`.
pub fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}
