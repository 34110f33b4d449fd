//! The engine: one stone (or a batch of stones, [`crate::dynamics::drops::batch`]) on flat
//! ground in rapier3d, stepped with this project's contact law until it rests.
//!
//! ```text
//! params ─▶ world (ground, stone) ─▶ contact (after every rapier step) ─▶ impact (sub-steps)
//!        ─▶ simulation (one stone's world) ─▶ run (the loop) ◀─ rest (when it has stopped)
//! flight: the free flight of a drop between contacts, outside rapier
//! ```
//!
//! * [`params`] — what a run takes, by concern: contact, numerics, rest rule, flight.
//! * [`convert`] — nalgebra (f64) ↔ glam (f32), the one boundary with rapier.
//! * [`hull_shape`] — the hull as a parry collider with constant-time bounds and hill-climbing
//!   support queries; [`body`] — the stone's rigid body built on it.
//! * [`world`] — the building blocks of a rapier world: ground, stone, what is read back.
//! * [`contact`] — the one contact law: impacts completed, rolling resistance and torsional
//!   friction through the contact.
//! * [`impact`] — sub-stepped impacts: no hull point comes down by more than a stated bound in
//!   one step; [`impulse`] — the closed forms of an impact on one point.
//! * [`simulation`] — one stone in its own world, stepped.
//! * [`flight`] — free flight between contacts outside rapier, with exact landings.
//! * [`run`] — the one run loop and the end rule every run shares; [`rest`] — when a run has
//!   come to rest, by speeds or by positions.

pub mod body;
pub mod contact;
pub mod convert;
pub mod flight;
pub mod hull_shape;
pub mod impact;
pub mod impulse;
pub mod params;
pub mod rest;
pub mod run;
pub mod simulation;
pub mod world;
