//! CPU time of the calling thread, for experiments that time themselves on a shared machine, and
//! drop runs timed by it (`drops_certificate_speed`, `drops_vs_mujoco`, `drops_solver_substeps`).
#![allow(dead_code)] // `drops_impacts` uses the clock alone

use rocking_stones::dynamics::certificate::certificate;
use rocking_stones::dynamics::drops::montecarlo::{run_drops_batched, summarize};
use rocking_stones::prelude::*;
use std::collections::BTreeMap;
use std::sync::Mutex;

/// CPU time of the calling thread (s), from Linux's /proc/thread-self/schedstat: on a shared
/// machine, wall time counts the other jobs' time slices, CPU time does not.
pub fn thread_cpu_seconds() -> f64 {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").expect("Linux schedstat");
    s.split_whitespace().next().and_then(|ns| ns.parse::<f64>().ok()).expect("CPU ns") * 1e-9
}

/// A timed drop run: its summary, its outcomes by drop index, and the CPU seconds of its drops.
pub struct Run {
    pub report: DropReport,
    pub outcomes: BTreeMap<u64, DropOutcome>,
    pub seconds: f64,
}

/// Every drop of `h` with `batch` stones per world on the one-thread `pool`, timed by the worker
/// thread's CPU time (the drops alone: not the certificate's construction, nor the summary).
pub fn timed(pool: &rayon::ThreadPool, stone: &Stone, h: &RunHeader, batch: usize) -> Run {
    pool.install(|| {
        let sink = Mutex::new(|_: &DropOutcome| {});
        let cert = certificate(stone, h.certificate);
        let t = thread_cpu_seconds();
        let out = run_drops_batched(stone, h, &BTreeMap::new(), cert.as_ref(), batch, &sink);
        let seconds = thread_cpu_seconds() - t;
        let outcomes: BTreeMap<u64, DropOutcome> = out.into_iter().map(|o| (o.index, o)).collect();
        Run { report: summarize(&stone.model(), h, &outcomes), outcomes, seconds }
    })
}
