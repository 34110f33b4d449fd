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
//! * **Timing.** A run timed by the CPU time of the one thread that runs it ([`run_timed`]):
//!   drops per second per core on a machine shared with other jobs.

pub mod checkpoint;
pub mod header;
pub mod summary;
pub mod timed;

pub use checkpoint::{check_outcomes, merge, read_partial, Checkpoint};
pub use header::{fingerprint, RunHeader, Shard, FORMAT};
pub use summary::{height_above_median_max, summarize, DropReport, FacetRow, Fit, FlockRow};
pub use timed::{run_timed, thread_cpu_seconds, TimedRun};

use crate::dynamics::certificate::certificate;
use crate::dynamics::drops::batch::simulate_batch;
use crate::dynamics::drops::launch::{launch, DropOutcome};
use crate::dynamics::drops::simulate::simulate;
use crate::dynamics::engine::run::Certificate;
use crate::dynamics::stone::Stone;
use crate::monitor::Monitor;
use crate::rng::item_rng;
use crate::{Error, Result};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Stones per rapier world in [`run_drops`] (`rocking drop --batch`), chosen from the batch-size sweep
/// of `results/drops_certificate/`: the gain over one world per drop levels off from about 16
/// stones per world (1.6–2.3× on throws) and falls beyond 64.
pub const DEFAULT_BATCH: usize = 32;

/// Run the drops of the header's shard ([`RunHeader::shard`]) that are not in `done`, in
/// parallel, [`DEFAULT_BATCH`] stones per world, calling `on_done` (under a lock) as each
/// finishes. Returns the new outcomes sorted by index.
pub fn run_drops(
    stone: &Stone,
    header: &RunHeader,
    done: &BTreeMap<u64, DropOutcome>,
    cert: &dyn Certificate,
    on_done: &Mutex<dyn FnMut(&DropOutcome) + Send + '_>,
) -> Vec<DropOutcome> {
    run_drops_batched(stone, header, done, cert, DEFAULT_BATCH, on_done)
}

/// [`run_drops`] with `batch` stones per rapier world ([`crate::dynamics::drops::batch`]); 1: every drop
/// alone in its own world ([`simulate`]). Every drop's outcome is the same for any batch size
/// and thread count (`tests/batch.rs`). One world per thread takes the pending drops from a
/// shared queue.
pub fn run_drops_batched(
    stone: &Stone,
    header: &RunHeader,
    done: &BTreeMap<u64, DropOutcome>,
    cert: &dyn Certificate,
    batch: usize,
    on_done: &Mutex<dyn FnMut(&DropOutcome) + Send + '_>,
) -> Vec<DropOutcome> {
    run_pending(stone, header, done, cert, batch, on_done, &|| false)
}

/// [`run_drops_batched`], starting no drop once `stopped()` is true (the drops already in a world
/// run to their end).
fn run_pending(
    stone: &Stone,
    header: &RunHeader,
    done: &BTreeMap<u64, DropOutcome>,
    cert: &dyn Certificate,
    batch: usize,
    on_done: &Mutex<dyn FnMut(&DropOutcome) + Send + '_>,
    stopped: &(dyn Fn() -> bool + Sync),
) -> Vec<DropOutcome> {
    let todo: Vec<u64> = header.shard.indices(header.drops).filter(|i| !done.contains_key(i)).collect();
    let release = |i: u64| launch(&mut item_rng(header.seed, i), &header.params);
    let record = |o: &DropOutcome| (on_done.lock().expect("no panic while holding the lock"))(o);
    let mut out: Vec<DropOutcome> = if batch <= 1 {
        todo.par_iter()
            .filter_map(|&i| {
                if stopped() {
                    return None;
                }
                let o = simulate(stone, &header.params, &release(i), i, cert);
                record(&o);
                Some(o)
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
                let mut queue = std::iter::from_fn(|| {
                    if stopped() {
                        return None;
                    }
                    todo.get(next.fetch_add(1, Ordering::Relaxed))
                })
                .map(|&i| (i, release(i)));
                let mut finished = |o: DropOutcome| {
                    record(&o);
                    outcomes.push(o);
                };
                simulate_batch(stone, &header.params, cert, batch, &mut queue, &mut finished, &mut |_, _| {});
                outcomes
            })
            .collect();
        per_world.into_iter().flatten().collect()
    };
    out.sort_by_key(|o| o.index);
    out
}

/// A drop run as the command line and the Python package run it: the drops of the header's
/// shard that its checkpoint (if any) does not hold yet, each appended to the checkpoint as it
/// finishes (an interrupted run loses no finished drop), with a [`Monitor`] told of every drop
/// and asked whether to stop.
pub struct DropRun<'a> {
    stone: &'a Stone,
    header: &'a RunHeader,
    checkpoint: Option<(Checkpoint, PathBuf)>,
    done: BTreeMap<u64, DropOutcome>,
}

impl<'a> DropRun<'a> {
    /// The run of `header` on `stone`, in memory.
    pub fn new(stone: &'a Stone, header: &'a RunHeader) -> Self {
        DropRun { stone, header, checkpoint: None, done: BTreeMap::new() }
    }

    /// The run of `header` on `stone`, journalled in the checkpoint `path` ([`Checkpoint::open`]:
    /// a new file, or with `resume` an existing one of the same run, whose drops are kept after
    /// [`check_outcomes`] has checked them against the stone).
    pub fn checkpointed(stone: &'a Stone, header: &'a RunHeader, path: &Path, resume: bool) -> Result<Self> {
        let (checkpoint, done) = Checkpoint::open(path, header, resume)?;
        check_outcomes(path, &done, &stone.model())?;
        Ok(DropRun { stone, header, checkpoint: Some((checkpoint, path.to_path_buf())), done })
    }

    /// Drops of the shard still to run.
    pub fn pending(&self) -> u64 {
        self.header.shard.indices(self.header.drops).filter(|i| !self.done.contains_key(i)).count() as u64
    }

    /// Run the pending drops, `batch` stones per world ([`run_drops_batched`]), telling `monitor`
    /// of each; every outcome of the shard (kept and new) by index. [`Error::Cancelled`] if the
    /// monitor stopped the run (the checkpoint holds every drop finished until then), an
    /// [`Error::Io`] naming the checkpoint if writing it failed (it holds every drop finished
    /// before the failure).
    pub fn run(self, batch: usize, monitor: &dyn Monitor) -> Result<BTreeMap<u64, DropOutcome>> {
        let DropRun { stone, header, checkpoint, mut done } = self;
        let (mut file, path) = match checkpoint {
            Some((c, p)) => (Some(c), Some(p)),
            None => (None, None),
        };
        let mut write_error: Option<std::io::Error> = None;
        let new = {
            let sink = Mutex::new(|o: &DropOutcome| {
                if let Some(c) = file.as_mut() {
                    if let Err(e) = c.record(o) {
                        write_error.get_or_insert(e);
                    }
                }
                monitor.finished();
            });
            let cert = certificate(stone, header.certificate);
            run_pending(stone, header, &done, cert.as_ref(), batch, &sink, &|| monitor.stopped())
        };
        if let (Some(error), Some(path)) = (write_error, path) {
            return Err(Error::Io { path, error });
        }
        let all = header.shard.indices(header.drops).count();
        done.extend(new.into_iter().map(|o| (o.index, o)));
        if done.len() < all && monitor.stopped() {
            return Err(Error::Cancelled);
        }
        Ok(done)
    }
}

/// Run the drops of `header` (its shard: every drop of a whole run) in memory (no checkpoint,
/// no progress) and summarise them; for experiments and tests. Returns the report and the outcomes by index.
pub fn run_and_summarize(stone: &Stone, header: &RunHeader) -> (DropReport, BTreeMap<u64, DropOutcome>) {
    let sink = Mutex::new(|_: &DropOutcome| {});
    let cert = certificate(stone, header.certificate);
    let outcomes: BTreeMap<u64, DropOutcome> =
        run_drops(stone, header, &BTreeMap::new(), cert.as_ref(), &sink).into_iter().map(|o| (o.index, o)).collect();
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
