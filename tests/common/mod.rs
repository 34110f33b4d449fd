//! Helpers shared by the integration tests of standing and shaken stones.

use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::mesh::TriMesh;

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
