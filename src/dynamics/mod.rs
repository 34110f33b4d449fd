//! Rigid-body dynamics of a stone on the ground (rapier3d); `docs/methods.md` describes the
//! methods.
//!
//! * [`engine`] — the world, the contact law, free flight, impact sub-steps, the one run loop.
//! * [`stone`] — the one prepared stone and the one rule for where a stone came to rest.
//! * [`size`] — the real size of a stone: given, known or assumed.
//! * [`drops`] — drops and throws, one or many.
//! * [`resting`] — runs that start at rest on a stable micro-equilibrium.
//! * [`pushes`] — pushes and spins of a resting stone.
//! * [`shaking`] — the ground shaken under a resting stone.

pub mod certificate;
pub mod drops;
pub mod engine;
pub mod pushes;
pub mod resting;
pub mod shaking;
pub mod size;
pub mod stone;
pub mod surface;
