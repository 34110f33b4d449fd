//! Seeded mutations of mesh files and meshes, and the check that every one of them ends in a
//! result or a named error: never a panic, never a failed internal check. Used by the bounded
//! mutation test (`tests/reliability.rs`) and the experiment `experiments/fuzz_mutations.rs`.
//!
//! Byte mutations act on the file as stored (any format): overwrite bytes, truncate, delete or
//! duplicate a range, insert an awkward token (`nan`, `-1`, `1e309`, a huge count, a line break),
//! write an IEEE special (NaN, ±inf, 3.4e38, a subnormal) over an aligned word, or change a digit
//! of the text. Mesh mutations act on the parsed triangles: move a vertex (by 10⁻⁶ to 10 sizes),
//! pull one through the body, swap two vertices, collapse one onto another, scale everything by
//! 10^±300, delete, duplicate or flip a triangle, rewire one corner, or put a NaN in a coordinate.

use crate::analysis::{Analysis, Options};
use crate::mesh::{io, TriMesh};
use crate::{Error, Point3, Vec3};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

/// The end of one case: accepted (analysed), refused with an error of a kind ([`Error::kind`]),
/// or a panic with its message.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// The mutated input was accepted and analysed.
    Analysed,
    /// The input was refused with an error.
    Refused {
        /// The error's kind (`Error::kind`).
        kind: &'static str,
        /// The error's message.
        message: String,
    },
    /// The analysis panicked, with the panic message.
    Panicked(String),
}

impl Outcome {
    /// `analysed`, the error kind, or `panic`.
    pub fn label(&self) -> &'static str {
        match self {
            Outcome::Analysed => "analysed",
            Outcome::Refused { kind, .. } => kind,
            Outcome::Panicked(_) => "panic",
        }
    }

    /// A panic or a failed internal check: what no user input may cause.
    pub fn is_failure(&self) -> bool {
        matches!(self, Outcome::Panicked(_)) || matches!(self, Outcome::Refused { kind: "internal-check", .. })
    }
}

fn outcome(r: std::thread::Result<crate::Result<Analysis>>) -> Outcome {
    match r {
        Ok(Ok(_)) => Outcome::Analysed,
        Ok(Err(e)) => refused(&e),
        Err(p) => Outcome::Panicked(
            p.downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default(),
        ),
    }
}

fn refused(e: &Error) -> Outcome {
    Outcome::Refused { kind: e.kind(), message: e.to_string() }
}

/// Read `bytes` as the file `name`, check it and analyse it, catching panics.
pub fn check_bytes(bytes: &[u8], name: &Path, opts: &Options) -> Outcome {
    outcome(catch_unwind(AssertUnwindSafe(|| {
        let mesh = io::read_bytes(bytes, name)?;
        let (mesh, rep) = mesh.into_solid_boundary().map_err(|e| e.with_path(name))?;
        Analysis::of_solid(mesh, rep, opts).map_err(|e| e.with_path(name))
    })))
}

/// Check and analyse a mesh in memory, catching panics.
pub fn check_mesh(mesh: TriMesh, opts: &Options) -> Outcome {
    outcome(catch_unwind(AssertUnwindSafe(|| {
        let (mesh, rep) = mesh.into_solid_boundary()?;
        Analysis::of_solid(mesh, rep, opts)
    })))
}

/// Names of the byte mutations, in the order [`mutate_bytes`] draws them.
pub const BYTE_MUTATIONS: [&str; 7] =
    ["overwrite", "truncate", "delete-range", "duplicate-range", "insert-token", "ieee-special", "change-digit"];

/// Names of the mesh mutations, in the order [`mutate_mesh`] draws them.
pub const MESH_MUTATIONS: [&str; 11] = [
    "move-vertex",
    "pull-through",
    "swap-vertices",
    "collapse-vertex",
    "scale",
    "delete-triangle",
    "duplicate-triangle",
    "flip-triangle",
    "rewire-corner",
    "nan-coordinate",
    "move-two-vertices",
];

/// One random byte mutation of a file; returns the new bytes and the mutation's name.
pub fn mutate_bytes(bytes: &[u8], rng: &mut Xoshiro256PlusPlus) -> (Vec<u8>, &'static str) {
    let mut b = bytes.to_vec();
    let n = b.len().max(1);
    let which = rng.random_range(0..BYTE_MUTATIONS.len());
    match which {
        0 => {
            for _ in 0..rng.random_range(1..=8) {
                let i = rng.random_range(0..n);
                if i < b.len() {
                    b[i] = rng.random();
                }
            }
        }
        1 => b.truncate(rng.random_range(0..n)),
        2 => {
            let i = rng.random_range(0..n).min(b.len());
            let j = (i + rng.random_range(1..=64)).min(b.len());
            b.drain(i..j);
        }
        3 => {
            let i = rng.random_range(0..n).min(b.len());
            let j = (i + rng.random_range(1..=256)).min(b.len());
            let chunk = b[i..j].to_vec();
            let at = rng.random_range(0..=b.len());
            b.splice(at..at, chunk);
        }
        4 => {
            const TOKENS: [&str; 12] = [
                " nan ",
                " -1 ",
                " 1e309 ",
                " 4294967295 ",
                "\n",
                " 0 ",
                " 3 ",
                "\r",
                " inf ",
                " 1e-320 ",
                "end_header\n",
                " -0 ",
            ];
            let t = TOKENS[rng.random_range(0..TOKENS.len())];
            let at = rng.random_range(0..=b.len());
            b.splice(at..at, t.bytes());
        }
        5 => {
            let specials: [f64; 6] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 3.4e38, 1e-310, 0.0];
            let x = specials[rng.random_range(0..specials.len())];
            if rng.random::<bool>() {
                let at = rng.random_range(0..n) & !3;
                if at + 4 <= b.len() {
                    b[at..at + 4].copy_from_slice(&(x as f32).to_le_bytes());
                }
            } else {
                let at = rng.random_range(0..n) & !7;
                if at + 8 <= b.len() {
                    b[at..at + 8].copy_from_slice(&x.to_le_bytes());
                }
            }
        }
        _ => {
            let digits: Vec<usize> = (0..b.len().min(4096)).filter(|&i| b[i].is_ascii_digit()).collect();
            if !digits.is_empty() {
                let i = digits[rng.random_range(0..digits.len())];
                b[i] = b'0' + rng.random_range(0..10u8);
            }
        }
    }
    (b, BYTE_MUTATIONS[which])
}

/// One random mesh mutation (on the raw, unwelded mesh); returns its name.
pub fn mutate_mesh(mesh: &mut TriMesh, rng: &mut Xoshiro256PlusPlus) -> &'static str {
    let nv = mesh.vertices.len();
    let nt = mesh.triangles.len();
    if nv == 0 || nt == 0 {
        return "none";
    }
    let size = mesh.diameter().max(f64::MIN_POSITIVE);
    let centre = Point3::from(mesh.vertices.iter().map(|p| p.coords).sum::<Vec3>() / nv as f64);
    let v = rng.random_range(0..nv);
    let t = rng.random_range(0..nt);
    let unit = |rng: &mut Xoshiro256PlusPlus| {
        Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0))
    };
    let which = rng.random_range(0..MESH_MUTATIONS.len());
    match which {
        0 => {
            let step = size * 10f64.powf(rng.random_range(-6.0..1.0));
            mesh.vertices[v] += unit(rng) * step;
        }
        1 => {
            let p = mesh.vertices[v];
            mesh.vertices[v] = centre + (centre - p) * rng.random_range(0.5..3.0);
        }
        2 => {
            let w = rng.random_range(0..nv);
            mesh.vertices.swap(v, w);
        }
        3 => {
            let w = mesh.triangles[t][rng.random_range(0..3)] as usize;
            mesh.vertices[v] = mesh.vertices[w];
        }
        4 => {
            let s = 10f64.powf(rng.random_range(-300.0..300.0));
            mesh.vertices.iter_mut().for_each(|p| *p *= s);
        }
        5 => {
            mesh.triangles.remove(t);
        }
        6 => {
            let tri = mesh.triangles[t];
            mesh.triangles.push(tri);
        }
        7 => mesh.triangles[t].swap(1, 2),
        8 => mesh.triangles[t][rng.random_range(0..3)] = rng.random_range(0..nv) as u32,
        9 => mesh.vertices[v][rng.random_range(0..3)] = [f64::NAN, f64::INFINITY, 1e308][rng.random_range(0..3)],
        _ => {
            for _ in 0..2 {
                let v = rng.random_range(0..nv);
                mesh.vertices[v] += unit(rng) * size * 0.3;
            }
        }
    }
    MESH_MUTATIONS[which]
}

/// One case of a mutation campaign.
#[derive(Clone, Debug)]
pub struct Case {
    /// The source file name.
    pub source: String,
    /// `bytes` or `mesh`, and the mutation's name.
    pub family: &'static str,
    /// Name of the mutation applied.
    pub mutation: &'static str,
    /// How the analysis of the mutated input ended.
    pub outcome: Outcome,
}

/// Run case `i` of a campaign over `sources` (name and bytes of each file): the seed of case i is
/// derived from (`seed`, i), so any case can be rerun alone. Even cases mutate bytes, odd cases
/// the parsed mesh (when the source parses).
pub fn run_case(sources: &[(String, Vec<u8>)], seed: u64, i: u64, opts: &Options) -> Case {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ i.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    let (name, bytes) = &sources[rng.random_range(0..sources.len())];
    let path = Path::new(name);
    if i % 2 == 0 {
        let (b, mutation) = mutate_bytes(bytes, &mut rng);
        let outcome = check_bytes(&b, path, opts);
        Case { source: name.clone(), family: "bytes", mutation, outcome }
    } else {
        match io::read_bytes(bytes, path) {
            Ok(mut mesh) => {
                let mutation = mutate_mesh(&mut mesh, &mut rng);
                let outcome = check_mesh(mesh, opts);
                Case { source: name.clone(), family: "mesh", mutation, outcome }
            }
            Err(e) => Case { source: name.clone(), family: "mesh", mutation: "none", outcome: refused(&e) },
        }
    }
}
