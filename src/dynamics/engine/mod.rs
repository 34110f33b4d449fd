//! The engine: one stone (or a batch of stones) on flat ground in rapier3d, stepped with this
//! project's contact law until it rests.
//!
//! * [`convert`] — nalgebra (f64) ↔ glam (f32), the one boundary with rapier.
//! * [`hull_shape`] — the hull as a parry collider with constant-time bounds and hill-climbing
//!   support queries.
//! * [`world`] — the rapier world of one run.
//! * [`flight`] — free flight between contacts outside rapier, with exact landings.
//! * [`impact`] — sub-stepped impacts: no hull point comes down by more than a stated bound in
//!   one step.
//! * [`run`] — the one run loop and the end rule every run shares.
//! * [`rest`] — when a run has come to rest: by speeds or by positions.

pub mod body;
pub mod contact;
pub mod convert;
pub mod flight;
pub mod hull_shape;
pub mod impact;
pub mod params;
pub mod rest;
pub mod run;
pub mod world;
