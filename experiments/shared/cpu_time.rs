//! CPU time of the calling thread, for `drops_impacts`, which times its drops itself (the timed
//! drop runs of the other experiments are the library's `montecarlo::run_timed`).

/// The library's `montecarlo::thread_cpu_seconds` (Linux's schedstat), which this program needs.
pub fn thread_cpu_seconds() -> f64 {
    rocking_stones::dynamics::drops::montecarlo::thread_cpu_seconds().expect("the thread's CPU time")
}
