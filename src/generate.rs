//! Seeded shape generators: Platonic solids, boxes, ellipsoids and pebbles.
//!
//! Every generator returns a closed, outward-oriented (counter-clockwise seen from outside)
//! [`TriMesh`] that [`TriMesh::into_solid_boundary`] accepts unchanged, centred at the origin.
//! Randomness comes from [`Xoshiro256PlusPlus`] seeded with [`SeedableRng::seed_from_u64`]: a
//! named, version-stable generator, so a seed gives the same mesh on every platform and build.
//!
//! **Star-shaped meshes.** Ellipsoids and pebbles are built on a quasi-uniform set of unit
//! directions uₖ (a Fibonacci sphere turned by a seeded uniformly random rotation), triangulated
//! once by the convex hull of the uₖ. Vertex k is then `pₖ = sₖ · D uₖ` with D = diag(a, b, c)
//! and a radial factor sₖ > 0. Because det(pᵢ, pⱼ, pₖ) = sᵢ sⱼ sₖ · abc · det(uᵢ, uⱼ, uₖ) > 0 for
//! every hull triangle, the central projection of the surface onto the sphere stays a bijection:
//! the mesh is a closed, embedded, outward-oriented surface, star-shaped about the origin (not
//! necessarily convex), for any positive factors.

use crate::hull::convex_hull;
use crate::mesh::TriMesh;
use crate::rng::{fibonacci_sphere, random_rotation, random_unit};
use crate::{Error, Point3, Result, Vec3};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::f64::consts::PI;
use std::fmt;
use std::str::FromStr;

/// The five Platonic solids.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Platonic {
    /// Regular tetrahedron (4 triangular faces).
    Tetrahedron,
    /// Cube (6 square faces).
    Cube,
    /// Regular octahedron (8 triangular faces).
    Octahedron,
    /// Regular dodecahedron (12 pentagonal faces).
    Dodecahedron,
    /// Regular icosahedron (20 triangular faces).
    Icosahedron,
}

impl Platonic {
    /// All five, by increasing number of faces.
    pub const ALL: [Platonic; 5] =
        [Platonic::Tetrahedron, Platonic::Cube, Platonic::Octahedron, Platonic::Dodecahedron, Platonic::Icosahedron];

    /// (faces, edges, vertices) of the solid.
    pub fn fev(self) -> (usize, usize, usize) {
        match self {
            Platonic::Tetrahedron => (4, 6, 4),
            Platonic::Cube => (6, 12, 8),
            Platonic::Octahedron => (8, 12, 6),
            Platonic::Dodecahedron => (12, 30, 20),
            Platonic::Icosahedron => (20, 30, 12),
        }
    }

    /// Lowercase name.
    pub fn name(self) -> &'static str {
        match self {
            Platonic::Tetrahedron => "tetrahedron",
            Platonic::Cube => "cube",
            Platonic::Octahedron => "octahedron",
            Platonic::Dodecahedron => "dodecahedron",
            Platonic::Icosahedron => "icosahedron",
        }
    }

    /// The classical exact corners (before scaling to circumradius 1): tetrahedron = alternate
    /// corners of the cube (±1, ±1, ±1); octahedron ±eᵢ; icosahedron the cyclic permutations of
    /// (0, ±1, ±φ); dodecahedron (±1, ±1, ±1) and the cyclic permutations of (0, ±1/φ, ±φ).
    fn corners(self) -> Vec<Vec3> {
        let phi = (1.0 + 5f64.sqrt()) / 2.0;
        let signs = |v: [f64; 3]| -> Vec<Vec3> {
            let mut out = Vec::new();
            for s in 0..8 {
                let f = |k: usize| if s >> k & 1 == 1 { -1.0 } else { 1.0 };
                let p = Vec3::new(v[0] * f(0), v[1] * f(1), v[2] * f(2));
                if !out.contains(&p) {
                    out.push(p); // zero coordinates: drop the duplicate ±0
                }
            }
            out
        };
        let cyclic = |v: [f64; 3]| -> Vec<Vec3> {
            [[v[0], v[1], v[2]], [v[2], v[0], v[1]], [v[1], v[2], v[0]]].into_iter().flat_map(signs).collect()
        };
        match self {
            Platonic::Tetrahedron => signs([1.0, 1.0, 1.0]).into_iter().filter(|p| p.x * p.y * p.z > 0.0).collect(),
            Platonic::Cube => signs([1.0, 1.0, 1.0]),
            Platonic::Octahedron => cyclic([1.0, 0.0, 0.0]),
            Platonic::Icosahedron => cyclic([0.0, 1.0, phi]),
            Platonic::Dodecahedron => {
                let mut v = signs([1.0, 1.0, 1.0]);
                v.extend(cyclic([0.0, 1.0 / phi, phi]));
                v
            }
        }
    }
}

impl fmt::Display for Platonic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The closed surface of the convex hull of `points` (all of them must be hull vertices).
fn hull_mesh(points: Vec<Point3>) -> TriMesh {
    let hull = convex_hull(&points).expect("generator points span a solid");
    let mut mesh = TriMesh::new(points, hull.triangles);
    mesh.weld(); // drops points the hull did not use (none for the generators' inputs)
    mesh
}

/// A Platonic solid centred at the origin with circumradius 1, triangulated by the convex hull
/// of its exact corners. The dodecahedron's pentagons are split into three triangles each; its
/// corners are coplanar up to f64 rounding (~1e-16), far inside the hull's coplanarity
/// tolerance, so [`crate::hull::Polyhedron`] merges them back into 12 pentagons.
pub fn platonic(p: Platonic) -> TriMesh {
    let corners = p.corners();
    let r = corners[0].norm();
    hull_mesh(corners.iter().map(|c| Point3::from(c / r)).collect())
}

/// A box with full edge lengths a, b, c along x, y, z, centred at the origin (12 triangles).
pub fn cuboid(a: f64, b: f64, c: f64) -> TriMesh {
    let h = Vec3::new(a, b, c) / 2.0;
    let corners = (0..8).map(|s| {
        let f = |k: usize| if s >> k & 1 == 1 { -h[k] } else { h[k] };
        Point3::new(f(0), f(1), f(2))
    });
    hull_mesh(corners.collect())
}

/// `n` quasi-uniform unit directions: the Fibonacci sphere zₖ = 1 − (2k+1)/n,
/// θₖ = k·π(3 − √5) (the golden angle), turned by a seeded uniformly random rotation so that
/// different seeds give different samplings.
pub fn fibonacci_directions(n: usize, rng: &mut Xoshiro256PlusPlus) -> Vec<Vec3> {
    let rot = random_rotation(rng).to_rotation_matrix();
    fibonacci_sphere(n).into_iter().map(|u| rot * u).collect()
}

/// The star-shaped mesh `pₖ = factor[k] · D uₖ` triangulated by the hull of the directions
/// (see the module docs). Every factor must be positive.
fn star_mesh(dirs: &[Vec3], axes: [f64; 3], factor: &[f64]) -> TriMesh {
    let unit: Vec<Point3> = dirs.iter().map(|u| Point3::from(*u)).collect();
    let hull = convex_hull(&unit).expect("Fibonacci directions span the sphere");
    let d = Vec3::from(axes);
    let vertices = dirs.iter().zip(factor).map(|(u, s)| Point3::from(u.component_mul(&d) * *s)).collect();
    let mut mesh = TriMesh::new(vertices, hull.triangles);
    mesh.weld(); // drops directions the hull did not use (none: points on a sphere are extreme)
    mesh
}

/// Uniform draws in [−1, 1].
fn uniform_pm1(rng: &mut Xoshiro256PlusPlus, n: usize) -> Vec<f64> {
    (0..n).map(|_| rng.random_range(-1.0..=1.0)).collect()
}

/// An ellipsoid with semi-axes `axes` (along x, y, z) sampled at `n` points: vertex k is
/// `(1 + noise·ξₖ) · D uₖ`, uₖ the seeded Fibonacci directions, D = diag(a, b, c) (so with
/// `noise` = 0 every vertex lies exactly on the ellipsoid and the mesh is convex and inscribed),
/// ξₖ **uniform on [−1, 1]** (bounded, so every factor is ≥ 1 − noise > 0).
///
/// Panics unless the axes are positive, n ≥ [`MIN_POINTS`] and 0 ≤ noise < 1 ([`generate`]
/// checks these and returns an error instead).
pub fn ellipsoid(axes: [f64; 3], n: usize, noise: f64, seed: u64) -> TriMesh {
    check_axes(axes).and(check_n(n)).and(check_unit("noise", noise)).unwrap();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let dirs = fibonacci_directions(n, &mut rng);
    let factor: Vec<f64> = uniform_pm1(&mut rng, n).into_iter().map(|x| 1.0 + noise * x).collect();
    star_mesh(&dirs, axes, &factor)
}

/// A box with full edge lengths a, b, c whose six faces are m × m grids (m = `n_per_face_side`
/// cells along each face edge; grid points shared along the box edges), each vertex p moved
/// radially to `(1 + noise·ξ) p`, ξ uniform on [−1, 1]. On a face with outward normal eᵢ this is
/// a normal displacement of noise·ξ·(half edge along eᵢ) — relative noise, as for [`ellipsoid`] —
/// plus a tangential slip of the same relative size. The grid is star-shaped about the centre,
/// so the surface stays closed and embedded for any noise < 1. Noise 0 gives a flat-faced box.
///
/// Panics unless the edges are positive, m ≥ 1 and 0 ≤ noise < 1.
pub fn noisy_cuboid(a: f64, b: f64, c: f64, n_per_face_side: usize, noise: f64, seed: u64) -> TriMesh {
    let m = n_per_face_side;
    check_axes([a, b, c]).and(check_unit("noise", noise)).unwrap();
    assert!(m >= 1, "a noisy box needs at least one grid cell per face side");
    let (grid, triangles) = cube_grid(m);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let h = Vec3::new(a, b, c) / (2.0 * m as f64);
    let vertices = grid
        .iter()
        .zip(uniform_pm1(&mut rng, grid.len()))
        .map(|(g, x)| {
            let centred = Vec3::new(g[0] as f64, g[1] as f64, g[2] as f64) * 2.0 - Vec3::repeat(m as f64);
            Point3::from(centred.component_mul(&h) * (1.0 + noise * x))
        })
        .collect();
    TriMesh::new(vertices, triangles)
}

/// The surface of the integer cube [0, m]³ as grid points and outward triangles, each grid point
/// listed once (shared by the faces that meet there).
fn cube_grid(m: usize) -> (Vec<[u32; 3]>, Vec<[u32; 3]>) {
    let m = m as u32;
    let mut index = std::collections::HashMap::new();
    let mut points: Vec<[u32; 3]> = Vec::new();
    let mut id = |p: [u32; 3]| -> u32 {
        *index.entry(p).or_insert_with(|| {
            points.push(p);
            points.len() as u32 - 1
        })
    };
    let mut triangles = Vec::new();
    for k in 0..3 {
        for side in [0, m] {
            // Tangent axes (u, v) with eᵤ × eᵥ = ±eₖ: swap on the negative side to face outward.
            let (u, v) = if side == m { ((k + 1) % 3, (k + 2) % 3) } else { ((k + 2) % 3, (k + 1) % 3) };
            let mut at = |i: u32, j: u32| {
                let mut p = [0; 3];
                (p[k], p[u], p[v]) = (side, i, j);
                id(p)
            };
            for i in 0..m {
                for j in 0..m {
                    let (p00, p10, p11, p01) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                    triangles.push([p00, p10, p11]);
                    triangles.push([p00, p11, p01]);
                }
            }
        }
    }
    (points, triangles)
}

/// A synthetic pebble: the ellipsoid with semi-axes `axes` and multi-scale radial roughness.
///
/// Vertex k is `(1 + roughness·f(uₖ)) · D uₖ` on `n` seeded Fibonacci directions (see
/// [`ellipsoid`]), with the roughness field
///
/// f(u) = Σₒ 2⁻ᵒ · (1/M) Σⱼ cos(kₒ dₒⱼ·u + φₒⱼ) + 2⁻ᴼ ξ(u),
///
/// octaves o = 0 … O−1 of wavenumber kₒ = 2·2ᵒ (surface wavelength 2π/kₒ on the unit sphere),
/// each a sum of M = 6 plane waves with uniformly random directions dₒⱼ and phases φₒⱼ, so the
/// amplitude halves as the wavelength halves; O is the number of octaves whose wavelength is at
/// least four vertex spacings √(4π/n). The last term is fine per-vertex noise, ξ uniform on
/// [−1, 1], at the amplitude of the next octave. f is then divided by max |f| over the vertices,
/// so the largest relative radial deviation from the ellipsoid is exactly `roughness`.
///
/// Panics unless the axes are positive, n ≥ [`MIN_POINTS`] and 0 ≤ roughness < 1.
pub fn pebble(axes: [f64; 3], roughness: f64, n: usize, seed: u64) -> TriMesh {
    check_axes(axes).and(check_n(n)).and(check_unit("roughness", roughness)).unwrap();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let dirs = fibonacci_directions(n, &mut rng);
    let f = roughness_field(&dirs, &mut rng);
    let peak = f.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let scale = if peak > 0.0 { roughness / peak } else { 0.0 };
    let factor: Vec<f64> = f.iter().map(|x| 1.0 + scale * x).collect();
    star_mesh(&dirs, axes, &factor)
}

/// Plane waves per octave of the pebble roughness.
const WAVES_PER_OCTAVE: usize = 6;

/// The unnormalised multi-scale field f(uₖ) of [`pebble`].
fn roughness_field(dirs: &[Vec3], rng: &mut Xoshiro256PlusPlus) -> Vec<f64> {
    let spacing = (4.0 * PI / dirs.len() as f64).sqrt();
    let mut f = vec![0.0; dirs.len()];
    let mut amplitude = 1.0;
    let mut k = 2.0;
    while 2.0 * PI / k >= 4.0 * spacing {
        for _ in 0..WAVES_PER_OCTAVE {
            let d = random_unit(rng);
            let phase = rng.random_range(0.0..2.0 * PI);
            for (fk, u) in f.iter_mut().zip(dirs) {
                *fk += amplitude / WAVES_PER_OCTAVE as f64 * (k * d.dot(u) + phase).cos();
            }
        }
        amplitude /= 2.0;
        k *= 2.0;
    }
    for (fk, x) in f.iter_mut().zip(uniform_pm1(rng, dirs.len())) {
        *fk += amplitude * x;
    }
    f
}

/// Smallest number of sample points of an ellipsoid or pebble.
pub const MIN_POINTS: usize = 12;

fn check_axes(axes: [f64; 3]) -> Result<()> {
    if axes.iter().all(|x| x.is_finite() && *x > 0.0) {
        Ok(())
    } else {
        Err(Error::parameter("axes", format!("{}, {}, {}", axes[0], axes[1], axes[2]), "positive and finite"))
    }
}

fn check_n(n: usize) -> Result<()> {
    if n >= MIN_POINTS {
        Ok(())
    } else {
        Err(Error::parameter("n", n, format!("at least {MIN_POINTS} points for an ellipsoid or pebble")))
    }
}

fn check_unit(what: &str, x: f64) -> Result<()> {
    if (0.0..1.0).contains(&x) {
        Ok(())
    } else {
        Err(Error::parameter(what, x, "in [0, 1) (a relative amplitude; 1 or more can collapse the surface)"))
    }
}

/// The shapes [`generate`] can build, by CLI name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// A Platonic solid, by its name.
    Platonic(Platonic),
    /// `box`: [`cuboid`].
    Box,
    /// `ellipsoid`: [`ellipsoid`].
    Ellipsoid,
    /// `noisy-box`: [`noisy_cuboid`].
    NoisyBox,
    /// `pebble`: [`pebble`].
    Pebble,
}

impl Shape {
    /// Every accepted name.
    pub const NAMES: [&'static str; 9] =
        ["tetrahedron", "cube", "octahedron", "dodecahedron", "icosahedron", "box", "ellipsoid", "noisy-box", "pebble"];

    /// Whether the shape takes the parameter (`"axes"`, `"n"`, `"noise"`, `"roughness"`, `"seed"`).
    pub fn uses(self, param: &str) -> bool {
        match self {
            Shape::Platonic(_) => false,
            Shape::Box => param == "axes",
            Shape::Ellipsoid | Shape::NoisyBox => param != "roughness",
            Shape::Pebble => param != "noise",
        }
    }

    /// The CLI name.
    pub fn name(self) -> &'static str {
        match self {
            Shape::Platonic(p) => p.name(),
            Shape::Box => "box",
            Shape::Ellipsoid => "ellipsoid",
            Shape::NoisyBox => "noisy-box",
            Shape::Pebble => "pebble",
        }
    }
}

impl fmt::Display for Shape {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Shape {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        let mut found = Platonic::ALL.into_iter().map(Shape::Platonic).chain([
            Shape::Box,
            Shape::Ellipsoid,
            Shape::NoisyBox,
            Shape::Pebble,
        ]);
        found
            .find(|shape| shape.name() == s.to_ascii_lowercase())
            .ok_or_else(|| Error::unknown("shape", s, &Shape::NAMES))
    }
}

/// Parameters of [`generate`]. `axes` are full edge lengths for the boxes and semi-axes for the
/// ellipsoid and pebble; `n` is the number of points (ellipsoid, pebble) or grid cells per face
/// side (noisy box). Platonic solids have circumradius 1 and take no parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Full edge lengths (boxes) or semi-axes (ellipsoid, pebble).
    pub axes: [f64; 3],
    /// Number of points (ellipsoid, pebble) or grid cells per face side (noisy box).
    pub n: usize,
    /// Relative radial noise amplitude in [0, 1) (ellipsoid, noisy box).
    pub noise: f64,
    /// Largest relative radial deviation of the pebble from its ellipsoid, in [0, 1).
    pub roughness: f64,
    /// Seed of the random generator.
    pub seed: u64,
}

/// Build `shape` after checking the parameters it uses; bad values give [`Error::Parameter`] naming the parameter.
pub fn generate(shape: Shape, p: &Params) -> Result<TriMesh> {
    if shape.uses("axes") {
        check_axes(p.axes)?;
    }
    Ok(match shape {
        Shape::Platonic(s) => platonic(s),
        Shape::Box => cuboid(p.axes[0], p.axes[1], p.axes[2]),
        Shape::Ellipsoid => {
            check_n(p.n).and(check_unit("noise", p.noise))?;
            ellipsoid(p.axes, p.n, p.noise, p.seed)
        }
        Shape::NoisyBox => {
            check_unit("noise", p.noise)?;
            if p.n == 0 {
                return Err(Error::parameter("n", p.n, "≥ 1 grid cells per face side for a noisy box"));
            }
            noisy_cuboid(p.axes[0], p.axes[1], p.axes[2], p.n, p.noise, p.seed)
        }
        Shape::Pebble => {
            check_n(p.n).and(check_unit("roughness", p.roughness))?;
            pebble(p.axes, p.roughness, p.n, p.seed)
        }
    })
}
