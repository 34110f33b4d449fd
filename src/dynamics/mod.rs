//! Rigid-body dynamics of a stone on the ground (rapier3d), SPEC §6–7. The stages, in the order
//! data flows through them:
//!
//! * [`hull_shape`] — the hull as a parry collider with constant-time bounds and hill-climbing
//!   support queries (no per-step cost that grows with the hull size).
//! * [`stone`] — the one prepared stone (body, merge tree, facet → equilibrium → flock maps) and
//!   the one rule for where a stone came to rest.
//! * [`params`] — launch, contact and numerics; named presets and surface pairs.
//! * [`world`] — the rapier world of one run and the contact law (rolling resistance, torsional
//!   friction).
//! * [`run`] — the one run loop and the energy certificate.
//! * [`batch`] — many independent drops in one rapier world (the same outcomes, drop by drop).
//! * [`flight`] — free flight between contacts outside rapier (`--flight free`).
//! * [`drop`], [`perturb`], [`shake`] — what drives a run: a launch, a push, a ground motion.

pub mod batch;
pub mod drop;
pub mod flight;
pub mod hull_shape;
pub mod params;
pub mod perturb;
pub mod run;
pub mod shake;
pub mod stone;
pub mod world;
