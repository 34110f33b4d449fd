//! What the experiments share: the harness every one runs on ([`harness`]: command line, results
//! folder, CSV, README from a template) and the pieces several of them use — the rocks of the
//! shaking studies ([`rocks`]), the benchmark bodies of drop throughput ([`benchmark_bodies`]),
//! and the MuJoCo side of the engine comparisons ([`mujoco`]).

pub mod benchmark_bodies;
pub mod harness;
pub mod mujoco;
pub mod rocks;
