//! Long runs (drops, perturbations, shaking, studies): the work runs on a worker thread with the
//! GIL released while the calling thread waits, checks for Ctrl-C and reports progress every
//! 100 ms; the work sees the caller's Ctrl-C through [`Control`].

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

/// Run `work` on a worker thread (in a pool of `threads` threads if given, else rayon's global
/// pool) while this thread, without the GIL, waits for it and checks for signals every 100 ms,
/// calling `progress(done, total)` then if given. On Ctrl-C (or an exception in `progress`) the
/// run is told to stop (`stopped()` turns true: the library's runs skip the trials they have not
/// started, [`rocking_stones::monitor`]), the worker is joined and the exception is raised.
pub(crate) fn interruptible<T: Send>(
    py: Python<'_>,
    threads: Option<usize>,
    progress: Option<(&Bound<'_, PyAny>, u64)>,
    work: impl FnOnce(&Control) -> T + Send,
) -> PyResult<T> {
    let pool = match threads {
        Some(0) => return Err(PyValueError::new_err("threads must be at least 1")),
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| PyRuntimeError::new_err(format!("cannot start {n} threads: {e}")))?,
        ),
        None => None,
    };
    let control = Control { cancel: AtomicBool::new(false), done: AtomicU64::new(0) };
    let report = |control: &Control| -> PyResult<()> {
        match progress {
            Some((f, total)) => f.call1((control.done.load(Ordering::Relaxed), total)).map(|_| ()),
            None => Ok(()),
        }
    };
    std::thread::scope(|s| {
        let (tx, mut rx) = std::sync::mpsc::channel();
        let (control, pool) = (&control, &pool);
        let worker = s.spawn(move || {
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match pool {
                Some(p) => p.install(|| work(control)),
                None => work(control),
            }));
            let _ = tx.send(());
            r
        });
        loop {
            let (done, back) = py.detach(move || {
                let r = rx.recv_timeout(Duration::from_millis(100));
                (!matches!(r, Err(std::sync::mpsc::RecvTimeoutError::Timeout)), rx)
            });
            rx = back;
            if done {
                break;
            }
            if let Err(e) = py.check_signals().and_then(|_| report(control)) {
                control.cancel.store(true, Ordering::Relaxed);
                let _ = py.detach(move || worker.join());
                return Err(e);
            }
        }
        match py.detach(move || worker.join()) {
            Ok(Ok(v)) => report(control).map(|_| v),
            Ok(Err(payload)) | Err(payload) => std::panic::resume_unwind(payload),
        }
    })
}

/// What a running computation sees of the caller's Ctrl-C.
pub(crate) struct Control {
    cancel: AtomicBool,
    /// Trials (drops, files) finished, for `progress`.
    done: AtomicU64,
}

impl Control {
    /// Has the caller asked to stop?
    pub(crate) fn stopped(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// One more trial finished.
    pub(crate) fn advance(&self) {
        self.done.fetch_add(1, Ordering::Relaxed);
    }
}

/// The caller of a library run: finished trials counted for `progress`, Ctrl-C as a stop.
impl rocking_stones::monitor::Monitor for Control {
    fn finished(&self) {
        self.advance();
    }
    fn stopped(&self) -> bool {
        Control::stopped(self)
    }
}

/// Threads of the long runs by default: `RAYON_NUM_THREADS` if set, else the number of cores.
#[pyfunction]
pub(crate) fn num_threads() -> usize {
    rayon::current_num_threads()
}
