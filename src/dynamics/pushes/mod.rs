//! Pushes and spins: a stone at rest on a stable micro-equilibrium, kicked with a growing
//! energy, and where it ends.

pub mod perturb;
