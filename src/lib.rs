//! # rocking-stones
//!
//! The mechanics of pebbles and rocking stones after Domokos, Sipos & Szabó,
//! *The mechanics of rocking stones: equilibria on separated scales*.
//!
//! Data flows one way, and the module tree follows it:
//!
//! ```text
//! mesh ─▶ solid ─▶ hull ─▶ equilibria ─▶ morse_smale ─▶ hierarchy ─▶ flocks ─▶ report
//! ```
//!
//! * [`mesh`] — reading/writing scans (STL, OBJ, PLY), welding, closedness/orientation checks.
//! * [`solid`] — volume, centre of mass G and inertia of the solid bounded by the mesh (f64).
//! * [`hull`] — exact convex hull with exactly-coplanar triangles merged into polygonal facets.
//! * [`equilibria`] — micro-equilibria (critical points of R = |x − G| on the hull), SPEC §2.
//! * [`shape`] — axes a ≥ b ≥ c, Zingg class, isoperimetric ratio.
//! * [`generate`] — seeded shape generators (Platonic solids, boxes, ellipsoids, pebbles).
//! * [`analysis`] — the whole static pipeline and its serialisable result.

// `!(x > 0.0)` is used on purpose: it is true for NaN, which must be refused too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod analysis;
pub mod basins;
pub mod dynamics;
pub mod equilibria;
pub mod error;
pub mod generate;
pub mod hierarchy;
pub mod hull;
pub mod mesh;
pub mod montecarlo;
pub mod morse_smale;
pub mod planar;
pub mod plot;
pub mod report;
pub mod shape;
pub mod solid;
pub mod study;

pub use error::{Error, Result};

/// 3-vectors of the static geometry (always f64).
pub type Vec3 = nalgebra::Vector3<f64>;
/// Points of the static geometry (always f64).
pub type Point3 = nalgebra::Point3<f64>;
