//! Fuzz the .stl reader and, when it parses, the solid checks and the static analysis: any input
//! must end in a mesh, an answer or a named error; a panic or a failed internal check is a bug.
#![no_main]

use libfuzzer_sys::fuzz_target;
use rocking_stones::analysis::Options;
use rocking_stones::mutation::check_bytes;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let outcome = check_bytes(data, Path::new("fuzz.stl"), &Options::default());
    assert!(!outcome.is_failure(), "{outcome:?}");
});
