//! `rocking generate`: write a synthetic shape (Platonic solid, box, ellipsoid, noisy box,
//! pebble) to an STL/PLY/OBJ file, or an open scan cut from a closed mesh.

use anyhow::{bail, Context, Result};
use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::equilibria::{Kind, Site};
use rocking_stones::generate::{generate, Params, Shape};
use rocking_stones::mesh::{cut_base, io, stand_on, OpenScan, RimChoice};
use std::path::PathBuf;

/// What to write: a generated shape, or an open scan cut from a mesh.
#[derive(Clone, Copy, Debug)]
pub enum What {
    Shape(Shape),
    OpenScan,
}

fn parse_what(s: &str) -> Result<What, String> {
    if s == "open-scan" {
        return Ok(What::OpenScan);
    }
    s.parse::<Shape>().map(What::Shape).map_err(|e| format!("{e}, or open-scan"))
}

/// Default axes of the box, ellipsoid and pebble: a generic triaxial shape (b/a = 0.75, c/b ≈ 0.53,
/// Zingg disc), clear of the 2/3 thresholds.
const DEFAULT_AXES: [f64; 3] = [1.0, 0.75, 0.4];

#[derive(clap::Args)]
pub struct Args {
    /// tetrahedron | cube | octahedron | dodecahedron | icosahedron (circumradius 1) | box |
    /// ellipsoid | noisy-box | pebble | open-scan (a closed mesh, --from, cut open --cut above its
    /// lowest point, as a field scan sees a rock standing on its pedestal)
    #[arg(value_parser = parse_what)]
    pub shape: What,
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
    /// open-scan: the closed mesh to cut open (STL, OBJ, PLY).
    #[arg(long, value_name = "MESH")]
    pub from: Option<PathBuf>,
    /// open-scan: remove everything below this height above the mesh's lowest point (mesh units),
    /// clipping the triangles there exactly: the rim of the hidden base.
    #[arg(long, value_name = "H")]
    pub cut: Option<f64>,
    /// open-scan: first stand the mesh on this stable micro-equilibrium's facet (its id as
    /// `rocking analyze --json` lists it), turned facet down, lowest point at z = 0. Default: the
    /// mesh as it is, +z up.
    #[arg(long, value_name = "ID")]
    pub stand_on: Option<usize>,
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
fn params(args: &Args, shape: Shape) -> Result<Params> {
    for (flag, given) in
        [("--from", args.from.is_some()), ("--cut", args.cut.is_some()), ("--stand-on", args.stand_on.is_some())]
    {
        if given {
            bail!("{flag} applies to open-scan, not to {shape}");
        }
    }
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
    let shape = match args.shape {
        What::Shape(shape) => shape,
        What::OpenScan => return open_scan(&args),
    };
    let p = params(&args, shape)?;
    let mesh = generate(shape, &p)?;
    io::write(&args.output, &mesh).with_context(|| format!("writing the {shape}"))?;
    println!(
        "wrote {shape} ({} vertices, {} triangles) to {}",
        mesh.vertices.len(),
        mesh.triangles.len(),
        args.output.display()
    );
    Ok(())
}

/// A closed mesh stood on a stable facet (or as it is) and cut open above its lowest point.
fn open_scan(args: &Args) -> Result<()> {
    for (flag, given) in [
        ("--axes", args.axes.is_some()),
        ("-n", args.n.is_some()),
        ("--noise", args.noise.is_some()),
        ("--roughness", args.roughness.is_some()),
    ] {
        if given {
            bail!("{flag} does not apply to open-scan");
        }
    }
    let (Some(from), Some(cut)) = (&args.from, args.cut) else {
        bail!("open-scan needs --from MESH (a closed mesh) and --cut H (the height of the cut above its lowest point, mesh units)");
    };
    let (mesh, repairs) = io::load_solid(from)?;
    let mesh = match args.stand_on {
        None => mesh,
        Some(id) => {
            let a = Analysis::of_solid(mesh.clone(), repairs, &Options::default()).map_err(|e| e.with_path(from))?;
            let facet = match a.equilibria.points.get(id) {
                Some(p) if p.kind == Kind::Stable => match p.site {
                    Site::Facet(f) => f as usize,
                    _ => bail!("--stand-on {id}: not on a facet"),
                },
                _ => bail!(
                    "--stand-on {id}: not a stable micro-equilibrium of {} (rocking analyze --json lists them)",
                    from.display()
                ),
            };
            stand_on(&mesh, &a.hull.facets[facet].normal)?
        }
    };
    let open = cut_base(&mesh, cut).map_err(|e| {
        anyhow::anyhow!("--cut: {}", e.spelled(&|n| if n == "cut" { "--cut".into() } else { n.into() }))
    })?;
    let scan =
        OpenScan::new(open.clone(), &RimChoice::Lowest).context("the cut mesh does not read back as an open scan")?;
    io::write(&args.output, &open).context("writing the open scan")?;
    let rim = &scan.summary().rim;
    println!(
        "wrote an open scan of {} cut {cut} above its lowest point ({} vertices, {} triangles; rim {} long, enclosing {} on its plane) to {}",
        from.display(),
        open.vertices.len(),
        open.triangles.len(),
        rim.perimeter,
        rim.area,
        args.output.display()
    );
    Ok(())
}
