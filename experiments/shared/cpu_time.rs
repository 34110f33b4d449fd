//! CPU time of the calling thread, for experiments that time themselves on a shared machine.

/// CPU time of the calling thread (s), from Linux's /proc/thread-self/schedstat: on a shared
/// machine, wall time counts the other jobs' time slices, CPU time does not.
pub fn thread_cpu_seconds() -> f64 {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").expect("Linux schedstat");
    s.split_whitespace().next().and_then(|ns| ns.parse::<f64>().ok()).expect("CPU ns") * 1e-9
}
