//! The three benchmark bodies of drop throughput, shared by `drops_certificate_speed`,
//! `drops_dt` and `certificate_margin`: the bundled stone, a ≈500-hull-vertex synthetic pebble
//! and a box 1 × 0.8 × 0.5, each analysed with the default options.

use rocking_stones::prelude::*;
use std::path::Path;

/// The benchmark bodies with their names (`long`: with the hull size and proportions, as the
/// throughput tables print them), from the crate root `root`.
pub fn benchmark_bodies(root: &Path, long: bool) -> anyhow::Result<Vec<(String, Analysis)>> {
    let name = |short: &str, long_name: &str| if long { long_name.to_string() } else { short.to_string() };
    let options = Options::default();
    let pebble = generate::pebble([1.0, 0.72, 0.5], 0.02, 500, 3).into_solid_boundary()?;
    let cuboid = generate::cuboid(1.0, 0.8, 0.5).into_solid_boundary()?;
    Ok(vec![
        (
            name("bundled stone", "bundled stone E34 (581 hull vertices)"),
            Analysis::of_file(&root.join("data/default_pebble.ply"), &options)?,
        ),
        (
            name("pebble n = 500", "synthetic pebble 1:0.72:0.5 (n = 500)"),
            Analysis::of_solid(pebble.0, pebble.1, &options)?,
        ),
        (name("box 1 × 0.8 × 0.5", "box 1 × 0.8 × 0.5"), Analysis::of_solid(cuboid.0, cuboid.1, &options)?),
    ])
}
