pub mod analyze;
pub mod drop;
pub mod generate;
pub mod perturb;
pub mod planar;
pub mod shake;
pub mod study;

use std::path::{Path, PathBuf};

/// Print a report (JSON or its human summary) and, with `-o DIR`, write its files and list them.
pub fn emit<R: serde::Serialize>(
    report: &R,
    json: bool,
    summary: impl FnOnce() -> String,
    output: Option<&Path>,
    write: impl FnOnce(&Path) -> anyhow::Result<Vec<PathBuf>>,
) -> anyhow::Result<()> {
    if json {
        println!("{}", serde_json::to_string_pretty(report)?);
    } else {
        print!("{}", summary());
    }
    if let Some(dir) = output {
        for w in write(dir)? {
            if !json {
                println!("wrote {}", w.display());
            }
        }
    }
    Ok(())
}
