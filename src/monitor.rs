//! What a long run (perturbations, shaking, field studies) tells its caller, and hears from it:
//! one call after every finished item (a progress bar), and whether to stop (Ctrl-C in Python).
//! A stopped run skips the items it has not started and returns [`Error::Cancelled`]; it never
//! unwinds through the thread pool.

use crate::{Error, Result};

/// A long run's caller.
pub trait Monitor: Sync {
    /// One more item (a trial, a file) finished.
    fn finished(&self);
    /// Whether the caller asks the run to stop. Default: never.
    fn stopped(&self) -> bool {
        false
    }
}

/// A closure is a monitor that is told of every finished item and never stops the run.
impl<F: Fn() + Sync> Monitor for F {
    fn finished(&self) {
        self()
    }
}

/// `item()` unless the caller has asked to stop (then None), telling the monitor when it
/// finished.
pub fn item<T>(monitor: &dyn Monitor, item: impl FnOnce() -> T) -> Option<T> {
    if monitor.stopped() {
        return None;
    }
    let t = item();
    monitor.finished();
    Some(t)
}

/// The items of a run whose every item went through [`item`]: all of them, or
/// [`Error::Cancelled`] if the caller stopped the run.
pub fn all<T>(items: Vec<Option<T>>) -> Result<Vec<T>> {
    items.into_iter().collect::<Option<Vec<T>>>().ok_or(Error::Cancelled)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicU64, Ordering};

    struct StopAfter(AtomicU64, u64);
    impl Monitor for StopAfter {
        fn finished(&self) {
            self.0.fetch_add(1, Ordering::Relaxed);
        }
        fn stopped(&self) -> bool {
            self.0.load(Ordering::Relaxed) >= self.1
        }
    }

    #[test]
    fn a_stopped_run_skips_what_is_left_and_says_so() {
        let m = StopAfter(AtomicU64::new(0), 3);
        let items: Vec<Option<u32>> = (0..10).map(|k| item(&m, || k)).collect();
        assert_eq!(items.iter().flatten().count(), 3);
        assert!(matches!(all(items), Err(Error::Cancelled)));
        let count = AtomicU64::new(0);
        let tick = || {
            count.fetch_add(1, Ordering::Relaxed);
        };
        let items: Vec<Option<u32>> = (0..10).map(|k| item(&tick, || k)).collect();
        assert_eq!(all(items).unwrap(), (0..10).collect::<Vec<_>>());
        assert_eq!(count.load(Ordering::Relaxed), 10);
    }
}
