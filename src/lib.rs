//! # rocking-stones
//!
//! The mechanics of pebbles and rocking stones after Domokos, Sipos & Szabó,
//! *The mechanics of rocking stones: equilibria on separated scales*.
//!
//! Data flows one way, and the module tree follows it:
//!
//! ```text
//! mesh ─▶ solid ─▶ hull ─▶ equilibria ─▶ morse_smale ─▶ hierarchy ─▶ flocks ─▶ basins
//!   ─▶ dynamics (engine ─▶ stone ─▶ drops, resting ─▶ pushes, shaking)
//!   ─▶ study ─▶ report
//! ```
//!
//! Lower layers never import higher ones: `rng`, `stats` and `ground_motion` sit below `dynamics`; `dynamics`
//! imports neither `study` nor `report`; only `report` and `plot` draw.
//!
//! * [`mesh`] — reading/writing scans (STL, OBJ, PLY), welding, closedness/orientation checks.
//! * [`solid`] — volume, centre of mass G and inertia of the solid bounded by the mesh (f64).
//! * [`hull`] — exact convex hull with exactly-coplanar triangles merged into polygonal facets.
//! * [`equilibria`] — micro-equilibria (critical points of R = |x − G| on the hull).
//! * [`shape`] — axes a ≥ b ≥ c, Zingg class, isoperimetric ratio.
//! * [`tipping`] — a pose's support polygon (with a contact tolerance) and its quasi-static
//!   tipping acceleration tan α against azimuth.
//! * [`generate`] — seeded shape generators (Platonic solids, boxes, ellipsoids, pebbles).
//! * [`morse_smale`] — the Morse–Smale graph of R on the hull.
//! * [`hierarchy`] — its cancellation hierarchy, N(ν), the plateau (macro scale), flocks and
//!   rocking equilibria (2D and 3D).
//! * [`planar`] — the planar case: polygons and discretised ellipses.
//! * [`analysis`] — the whole static pipeline and its serialisable result.
//! * [`mutation`] — seeded mutations of mesh files and meshes, and the check that each ends in an
//!   analysis or a named error (the bounded fuzz test and its experiment).
//! * [`basins`] — quasi-static resting probabilities and the energy merge tree.
//! * [`rng`], [`stats`] — per-item random streams, random rotations and directions, the
//!   Fibonacci sphere; Wilson intervals, χ², KL, moments, log fits, log grids.
//! * [`ground_motion`] — recorded and synthetic ground accelerations (CSV, PEER `.AT2`),
//!   resampling, baseline correction, PGA/PGV, and the fragility surface P(overturn | PGA, PGV/PGA)
//!   fitted to shaking runs ([`ground_motion::fragility`]).
//! * [`dynamics`] — rapier3d, by stage: the engine (world, contact law, flight, impacts, the one
//!   run loop), the prepared stone and its rest rule, the energy certificate; drops (one, a
//!   batch, Monte Carlo runs with shards and checkpoints), pushes, ground shaking.
//! * [`study`] — field studies and synthetic hand experiments.
//! * [`prelude`] — the names a program over the library uses most, in one `use`.
//! * [`report`] — everything a person reads: summaries, CSV and JSON files, plots (through
//!   [`plot`], the one place that picks PNG or SVG); computation modules return data.
//!
//! ```
//! use rocking_stones::analysis::{Analysis, Options};
//! use rocking_stones::generate;
//!
//! // A 2 × 1.5 × 1 box: every face is stable, every vertex unstable, every edge a saddle.
//! let (mesh, repairs) = generate::cuboid(2.0, 1.5, 1.0).into_solid_boundary().unwrap();
//! let a = Analysis::of_solid(mesh, repairs, &Options::default()).unwrap();
//! assert_eq!((a.equilibria.stable, a.equilibria.unstable, a.equilibria.saddle), (6, 8, 12));
//! ```

// `!(x > 0.0)` is used on purpose: it is true for NaN, which must be refused too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
#![warn(missing_docs)]

pub mod analysis;
pub mod basins;
pub mod bundled;
pub mod dynamics;
pub mod equilibria;
pub mod error;
pub mod generate;
pub mod ground_motion;
pub mod hierarchy;
pub mod hull;
pub mod mesh;
pub mod monitor;
pub mod morse_smale;
pub mod mutation;
pub mod planar;
pub mod plot;
pub mod prelude;
pub mod report;
pub mod rng;
pub mod shape;
pub mod solid;
pub mod stats;
pub mod study;
pub mod tipping;

pub use error::{Error, Result};

/// 3-vectors of the static geometry (always f64).
pub type Vec3 = nalgebra::Vector3<f64>;

/// Acceleration of gravity (m/s²): the one value of the project — the simulations' gravity (of the
/// scaled body and of a stone at true size alike) and the conversion of records given in g, so
/// that a record of peak 0.3 g pushes a simulated stone with 0.3 of its own weight.
pub const GRAVITY: f64 = 9.81;
/// Points of the static geometry (always f64).
pub type Point3 = nalgebra::Point3<f64>;
