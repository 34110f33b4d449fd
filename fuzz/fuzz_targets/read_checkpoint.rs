//! Fuzz the drop checkpoint reader `montecarlo::read_partial` as it is (it reads a path, so the
//! input goes through a temporary file): it must return a result or an error, never panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::io::Write;

fuzz_target!(|data: &[u8]| {
    let mut file = tempfile_in_tmp();
    file.1.write_all(data).expect("write the temporary checkpoint");
    drop(file.1);
    let _ = rocking_stones::dynamics::drops::montecarlo::read_partial(&file.0);
    let _ = std::fs::remove_file(&file.0);
});

/// A fresh file in the system's temporary folder, named by process id and a counter.
fn tempfile_in_tmp() -> (std::path::PathBuf, std::fs::File) {
    use std::sync::atomic::{AtomicU64, Ordering};
    static N: AtomicU64 = AtomicU64::new(0);
    let path = std::env::temp_dir().join(format!(
        "rocking_fuzz_checkpoint_{}_{}.jsonl",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    let file = std::fs::File::create(&path).expect("create a temporary checkpoint");
    (path, file)
}
