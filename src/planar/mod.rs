//! The planar case (paper §1.1, Table 1, Figures 2, 4, 5): convex polygons, their
//! micro-equilibria, the cycle Morse–Smale graph and its ν-hierarchy, and discretised ellipses.
//!
//! # Micro-equilibria
//!
//! A convex polygon (vertices counter-clockwise) carries a homogeneous plate; G is its **area
//! centroid**. R is the distance from G to a boundary point. Everything follows from one family
//! of scalars, computed once per side i = (V_i → V_{i+1}), t the unit direction, as in
//! [`crate::equilibria`]:
//!
//! * `c⁺(i) = (G − V_i)·t` — `> 0` ⇔ the foot of the perpendicular from G to the side's line
//!   lies beyond V_i towards V_{i+1} ⇔ R decreases when leaving V_i along the side;
//! * `c⁻(i) = (G − V_{i+1})·(−t)` — the same seen from V_{i+1}.
//!
//! Side i is **stable** (a minimum of R) ⇔ c⁺(i) > 0 and c⁻(i) > 0 (foot strictly inside the
//! side), R = distance from G to the line. Vertex i is **unstable** (a maximum of R) ⇔ c⁺(i) > 0
//! and c⁻(i − 1) > 0 (both neighbouring sides' feet lie away from the vertex), R = |V_i − G|.
//!
//! **Degenerate cases** (G's foot on a vertex, a side of nearly zero length, collinear
//! vertices): a scalar with |value| ≤ τ = `tol_rel` · D (D the bounding-box diagonal) is decided
//! by simulation of simplicity, as if G were moved by an infinitesimal ε along the fixed generic
//! direction [`perturbation_direction`] d: sign(t·d) (second order, if t·d = 0 exactly: along
//! d rotated by 90°). Each scalar is shared by the side and the vertex that use it, so the result
//! is the critical-point set of the perturbed generic G + εd. Such decisions are counted in
//! [`PlanarEquilibria::degenerate_decisions`]. On a cycle minima and maxima alternate, hence
//! S = U always; a decided sign pattern that would put a minimum at a vertex (impossible for a
//! convex polygon with G inside) is reported as a failed check, never silently fixed.
//!
//! # Morse–Smale graph and hierarchy
//!
//! The critical points in boundary order (vertex i, then side i, for i = 0, 1, …; the same as
//! increasing polar angle around G) form a cycle of alternating minima and maxima; arcs join
//! consecutive ones (with S = U = 1 the two arcs are a double arc). [`hierarchy`] cancels the
//! cheapest adjacent (stable, unstable) pair, weight |ΔR|/R_max, ties broken by (min index,
//! max index), never the last stable or unstable point; the pair's two outer neighbours become
//! adjacent. On a cycle the cheapest-first weights are non-decreasing (the new arc is at least as
//! heavy as the one cancelled), so `level` = `weight`. Plateau, flocks and rocking equilibria are
//! read with the generic rules of [`crate::hierarchy`].
//!
//! # Discretised ellipses
//!
//! The ellipse has semi-axis **a along x** (the major axis, a ≥ 1) and **1 along y**:
//! (a cos t, sin t). [`Sampling::ArcLength`] puts N vertices at equal arc-length spacing L/N,
//! **vertex 0 at (a, 0)**, the end of the major axis. With the paper's N = 4k − 2 each half
//! (t ∈ [0, π]) has 2k − 1 sides, so there is a vertex at both ends of the major axis and the
//! midpoint of a side at both ends of the minor axis. Arc length is computed by composite
//! 16-point Gauss–Legendre quadrature (256 panels, error ≲ 1e-15) and inverted by safeguarded
//! Newton iteration; the vertices of the other three quadrants are exact mirror images of the
//! first quadrant's, so the polygon is exactly symmetric. Options: [`Sampling::Angle`] (uniform
//! in the parameter t, vertex 0 at t = 0) and [`Sampling::Random`] (N independent uniform
//! arc-length positions, seeded Xoshiro256++, sorted).
//!
//! The module is the planar counterpart of the whole 3D pipeline, from the polygon to its
//! flocks, one submodule per step: `polygon` (the plate and its centroid), `equilibria` (its
//! micro-equilibria), `cycle` (the Morse–Smale cycle and its ν-hierarchy), `ellipse`
//! (discretised ellipses and Table 1) and `analysis` (the whole pipeline and its report).

mod analysis;
mod cycle;
mod ellipse;
mod equilibria;
mod polygon;

pub use analysis::{FlockContents, PlanarAnalysis, PlanarReport, RockingSide};
pub use cycle::hierarchy;
pub use ellipse::{
    ellipse_polygon, ellipse_radius, ellipse_vertices, gauss_legendre, sides_for_k, table1, table1_scan, EllipseArc,
    Sampling, Table1, Table1Scan,
};
pub use equilibria::{PlanarEquilibria, PlanarEquilibrium, PlanarSite};
pub use polygon::Polygon;

pub use crate::hierarchy::NuSource;

/// 2-vectors of the planar geometry.
pub type Vec2 = nalgebra::Vector2<f64>;
/// Points of the planar geometry.
pub type Point2 = nalgebra::Point2<f64>;

/// Default relative tolerance of the degenerate predicates (× bounding-box diagonal).
pub const DEFAULT_DEGENERACY_TOL: f64 = crate::equilibria::DEFAULT_DEGENERACY_TOL;

/// The fixed generic direction of the symbolic perturbation of G.
pub fn perturbation_direction() -> Vec2 {
    Vec2::new(0.8090169943749475, 0.5877852522924731).rotate_by(0.123456789)
}

trait Rotate {
    fn rotate_by(self, angle: f64) -> Self;
}

impl Rotate for Vec2 {
    fn rotate_by(self, angle: f64) -> Self {
        let (s, c) = angle.sin_cos();
        Vec2::new(c * self.x - s * self.y, s * self.x + c * self.y)
    }
}

fn cross(a: &Vec2, b: &Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}
