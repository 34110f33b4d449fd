//! Drops and throws: a stone launched above flat ground, run to rest, many times.
//!
//! * [`params`] — launch, contact and numerics; the named presets and surface pairs.
//! * [`launch`] — how a drop starts (the release) and how it ends (its outcome).
//! * [`simulate`] — one drop, alone in its world.
//! * [`batch`] — many independent drops in one rapier world (the same outcomes, drop by drop).
//! * [`montecarlo`] — many drops: reproducible streams, shards, checkpoints, statistics.

pub mod batch;
pub mod launch;
pub mod montecarlo;
pub mod params;
pub mod simulate;
