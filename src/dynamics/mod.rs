//! Rigid-body dynamics of a pebble on the ground (rapier3d), SPEC §6.
//!
//! * [`hull_shape`] — the hull as a parry collider with constant-time bounds and hill-climbing
//!   support queries (no per-step cost that grows with the hull size).

pub mod drop;
pub mod hull_shape;
pub mod perturb;
pub mod shake;
