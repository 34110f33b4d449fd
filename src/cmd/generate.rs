//! `rocking generate`: write a synthetic shape (Platonic solid, box, ellipsoid, noisy box,
//! pebble) to an STL/PLY/OBJ file.

use anyhow::{bail, Context, Result};
use rocking_stones::generate::{generate, Params, Shape};
use rocking_stones::mesh::io;
use std::path::PathBuf;

/// Default axes of the box, ellipsoid and pebble: a generic triaxial shape (b/a = 0.75, c/b ≈ 0.53,
/// Zingg disc), clear of the 2/3 thresholds.
const DEFAULT_AXES: [f64; 3] = [1.0, 0.75, 0.4];

#[derive(clap::Args)]
pub struct Args {
    /// tetrahedron | cube | octahedron | dodecahedron | icosahedron (circumradius 1) | box |
    /// ellipsoid | noisy-box | pebble
    pub shape: Shape,
    /// A,B,C: full edge lengths of box and noisy-box, semi-axes of ellipsoid and pebble
    /// [default: 1,0.75,0.4].
    #[arg(long, value_parser = parse_axes, allow_hyphen_values = true)]
    pub axes: Option<[f64; 3]>,
    /// Number of points (ellipsoid, pebble) [default: 2000] or grid cells per face side
    /// (noisy-box) [default: 10].
    #[arg(short, value_parser = super::at_least::<usize, 1>)]
    pub n: Option<usize>,
    /// Relative radial noise amplitude in [0, 1) of ellipsoid [default: 0] and noisy-box
    /// [default: 0.01].
    #[arg(long, allow_hyphen_values = true)]
    pub noise: Option<f64>,
    /// Largest relative radial roughness in [0, 1) of pebble [default: 0.05].
    #[arg(long, allow_hyphen_values = true)]
    pub roughness: Option<f64>,
    /// Seed of the random shapes (ellipsoid, noisy-box, pebble).
    #[arg(long, default_value_t = 0, value_parser = super::at_least::<u64, 0>)]
    pub seed: u64,
    /// Output file; the format follows the extension (.stl, .ply, .obj).
    #[arg(short, long)]
    pub output: PathBuf,
}

fn parse_axes(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [a, b, c] = parts.as_slice() else {
        return Err(format!("expected three comma-separated numbers A,B,C, got '{s}'"));
    };
    let num = |x: &str| x.parse::<f64>().map_err(|e| format!("'{x}' is not a number ({e})"));
    Ok([num(a)?, num(b)?, num(c)?])
}

/// The generator parameters with per-shape defaults; an option the shape does not use is an error.
fn params(args: &Args) -> Result<Params> {
    let shape = args.shape;
    for (name, given) in [
        ("axes", args.axes.is_some()),
        ("n", args.n.is_some()),
        ("noise", args.noise.is_some()),
        ("roughness", args.roughness.is_some()),
    ] {
        if given && !shape.uses(name) {
            let flag = if name == "n" { "-n".to_string() } else { format!("--{name}") };
            bail!("{flag} does not apply to {shape}");
        }
    }
    let default_n = if shape == Shape::NoisyBox { 10 } else { 2000 };
    let default_noise = if shape == Shape::NoisyBox { 0.01 } else { 0.0 };
    Ok(Params {
        axes: args.axes.unwrap_or(DEFAULT_AXES),
        n: args.n.unwrap_or(default_n),
        noise: args.noise.unwrap_or(default_noise),
        roughness: args.roughness.unwrap_or(0.05),
        seed: args.seed,
    })
}

pub fn run_generate(args: Args) -> Result<()> {
    let p = params(&args)?;
    let mesh = generate(args.shape, &p)?;
    io::write(&args.output, &mesh).with_context(|| format!("writing the {}", args.shape))?;
    println!(
        "wrote {} ({} vertices, {} triangles) to {}",
        args.shape,
        mesh.vertices.len(),
        mesh.triangles.len(),
        args.output.display()
    );
    Ok(())
}
