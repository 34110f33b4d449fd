//! Rigid-body dynamics of a stone on the ground (rapier3d); `docs/methods.md` describes the
//! methods. The stages, in the order data flows through them:
//!
//! * [`convert`] — nalgebra (f64) ↔ glam (f32), the one boundary with rapier.
//! * [`hull_shape`] — the hull as a parry collider with constant-time bounds and hill-climbing
//!   support queries (no per-step cost that grows with the hull size).
//! * [`stone`] — the one prepared stone (body, merge tree, facet → equilibrium → flock maps) and
//!   the one rule for where a stone came to rest.
//! * [`params`] — launch, contact and numerics; named presets and surface pairs.
//! * [`resting`] — a stone put at rest on a stable micro-equilibrium, and the contact of every
//!   run that starts at rest (the surface pair at the stone's real size).
//! * [`size`] — the real size of a stone: given, known (the bundled stone) or assumed, and
//!   said when assumed or implausible.
//! * [`world`] — the rapier world of one run and the contact law (rolling resistance, torsional
//!   friction).
//! * [`run`] — the one run loop, its two rest rules and the energy certificate.
//! * [`launch`] and [`outcome`] — how a drop starts and ends; what became of a stone that
//!   started at rest, and the statistics of its curves.
//! * [`batch`] — many independent drops in one rapier world (the same outcomes, drop by drop).
//! * [`flight`] — free flight between contacts outside rapier (`--flight free`), with exact
//!   landings.
//! * [`impact`] — sub-stepped impacts: no hull point comes down by more than a stated bound in
//!   one step (`--flight free`).
//! * [`drop`](mod@drop), [`perturb`], [`shake`] — what drives a run: a launch, a push, a ground motion.
//! * [`housner`] — Housner's rigid block, the reference the shaking runs are checked against.

pub mod batch;
pub mod convert;
pub mod drop;
pub mod flight;
pub mod housner;
pub mod hull_shape;
pub mod impact;
pub mod launch;
pub mod outcome;
pub mod params;
pub mod perturb;
pub mod resting;
pub mod run;
pub mod shake;
pub mod size;
pub mod stone;
pub mod world;
