//! Monte Carlo drops: many drops in parallel, reproducible per drop, sharded,
//! checkpointed, merged, and summarised against the static theory.
//!
//! * **Reproducibility.** Drop i of a run with seed s draws everything from its own generator,
//!   Xoshiro256++ seeded with SplitMix64(s, i) ([`item_rng`]); rapier is deterministic for a
//!   given binary and input. So the outcome of drop i does not depend on the thread count, the
//!   order of execution, or how the run is sharded: counts from any sharding merged with
//!   [`merge`] equal those of one big run.
//! * **Batches.** Drops run [`DEFAULT_BATCH`] stones per rapier world
//!   ([`crate::dynamics::drops::batch`]), which amortises rapier's per-step cost; each drop's
//!   outcome is bit-identical to the same drop alone in its world, for any batch size
//!   (`tests/batch.rs`).
//! * **Checkpoints.** A run appends every finished drop to a JSON-lines file (first line: the
//!   [`RunHeader`]) and flushes it, so an interrupted run loses no finished drop; resuming
//!   skips the indices already in the file.
//! * **Statistics.** Wilson score intervals (95 %) per facet and per flock; Pearson's χ² and the
//!   Kullback–Leibler divergence of the empirical distribution from the static one.

pub mod checkpoint;
pub mod header;
pub mod summary;

pub use checkpoint::{check_outcomes, merge, read_partial, Checkpoint};
pub use header::{fingerprint, RunHeader, Shard, FORMAT};
pub use summary::{summarize, DropReport, FacetRow, Fit, FlockRow};

use crate::dynamics::certificate::certificate;
use crate::dynamics::drops::batch::simulate_batch;
use crate::dynamics::drops::launch::{launch, DropOutcome};
use crate::dynamics::drops::simulate::simulate;
use crate::dynamics::engine::run::Certificate;
use crate::dynamics::stone::Stone;
use crate::rng::item_rng;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Stones per rapier world in [`run_drops`] (`rocking drop --batch`), chosen from the batch-size sweep
/// of `results/drops_certificate/`: the gain over one world per drop levels off from about 16
/// stones per world (1.6–2.3× on throws) and falls beyond 64.
pub const DEFAULT_BATCH: usize = 32;

/// Run the drops of `shard` that are not in `done`, in parallel, [`DEFAULT_BATCH`] stones per
/// world, calling `on_done` (under a lock) as each finishes. Returns the new outcomes sorted by
/// index.
pub fn run_drops(
    stone: &Stone,
    header: &RunHeader,
    shard: Shard,
    done: &BTreeMap<u64, DropOutcome>,
    cert: &dyn Certificate,
    on_done: &Mutex<dyn FnMut(&DropOutcome) + Send + '_>,
) -> Vec<DropOutcome> {
    run_drops_batched(stone, header, shard, done, cert, DEFAULT_BATCH, on_done)
}

/// [`run_drops`] with `batch` stones per rapier world ([`crate::dynamics::drops::batch`]); 1: every drop
/// alone in its own world ([`simulate`]). Every drop's outcome is the same for any batch size
/// and thread count (`tests/batch.rs`). One world per thread takes the pending drops from a
/// shared queue.
pub fn run_drops_batched(
    stone: &Stone,
    header: &RunHeader,
    shard: Shard,
    done: &BTreeMap<u64, DropOutcome>,
    cert: &dyn Certificate,
    batch: usize,
    on_done: &Mutex<dyn FnMut(&DropOutcome) + Send + '_>,
) -> Vec<DropOutcome> {
    let todo: Vec<u64> = shard.indices(header.drops).filter(|i| !done.contains_key(i)).collect();
    let release = |i: u64| launch(&mut item_rng(header.seed, i), &header.params);
    let record = |o: &DropOutcome| (on_done.lock().expect("no panic while holding the lock"))(o);
    let mut out: Vec<DropOutcome> = if batch <= 1 {
        todo.par_iter()
            .map(|&i| {
                let o = simulate(stone, &header.params, &release(i), i, cert);
                record(&o);
                o
            })
            .collect()
    } else {
        // One world per thread, each taking the next pending drop as one of its stones comes to
        // rest: a world drains (fewer stones per step) once, at the end of the run, where
        // contiguous chunks drained at the end of every chunk.
        let next = AtomicUsize::new(0);
        let workers = rayon::current_num_threads().min(todo.len().div_ceil(batch)).max(1);
        let per_world: Vec<Vec<DropOutcome>> = (0..workers)
            .into_par_iter()
            .map(|_| {
                let mut outcomes = Vec::new();
                let mut queue =
                    std::iter::from_fn(|| todo.get(next.fetch_add(1, Ordering::Relaxed))).map(|&i| (i, release(i)));
                simulate_batch(stone, &header.params, cert, batch, &mut queue, &mut |o| {
                    record(&o);
                    outcomes.push(o);
                });
                outcomes
            })
            .collect();
        per_world.into_iter().flatten().collect()
    };
    out.sort_by_key(|o| o.index);
    out
}

/// Run every drop of `header` in memory (no checkpoint, no progress) and summarise them; for
/// experiments and tests. Returns the report and the outcomes by index.
pub fn run_and_summarize(stone: &Stone, header: &RunHeader) -> (DropReport, BTreeMap<u64, DropOutcome>) {
    let sink = Mutex::new(|_: &DropOutcome| {});
    let cert = certificate(stone, header.certificate);
    let outcomes: BTreeMap<u64, DropOutcome> =
        run_drops(stone, header, Shard::ALL, &BTreeMap::new(), cert.as_ref(), &sink)
            .into_iter()
            .map(|o| (o.index, o))
            .collect();
    (summarize(&stone.model(), header, &outcomes), outcomes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_indices() {
        let mut all: Vec<u64> =
            (0..3).flat_map(|i| Shard { index: i, count: 3 }.indices(10).collect::<Vec<_>>()).collect();
        all.sort();
        assert_eq!(all, (0..10).collect::<Vec<_>>());
        assert!(Shard::parse("3/3").is_err() && Shard::parse("1/0").is_err() && Shard::parse("x").is_err());
        assert_eq!(Shard::parse("1/4").unwrap(), Shard { index: 1, count: 4 });
    }
}
