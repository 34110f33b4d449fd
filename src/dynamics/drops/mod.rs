//! Drops and throws: a stone launched above flat ground and run to rest, once or many times.
//!
//! ```text
//! params (launch + engine params, presets) ─▶ launch (release) ─▶ simulate (one drop)
//!                                                              └▶ batch (many in one world)
//!                                                                   ─▶ montecarlo (runs, shards,
//!                                                                      checkpoints, statistics)
//! ```
//!
//! * [`params`] — a drop's launch beside the engine's parameters; the named presets.
//! * [`launch`] — how a drop starts (the release) and how it ends (its outcome).
//! * [`simulate`] — one drop, alone in its world.
//! * [`batch`] — many independent drops in one rapier world (the same outcomes, drop by drop).
//! * [`montecarlo`] — many drops: reproducible streams, shards, checkpoints, statistics.
//! * [`compare`] — two runs of the same releases compared drop by drop (two numerics, two engines).
//! * [`alone`] — one drop stepped by hand: watched after every step, or continued on to its
//!   equilibrium after the rest rule has ended it.
//! * [`audit`] — one drop run to rest while both certificates are asked along the way: when they
//!   decide, whether they were right, and what their margin had to cover.

pub mod alone;
pub mod audit;
pub mod batch;
pub mod compare;
pub mod launch;
pub mod montecarlo;
pub mod params;
pub mod simulate;
