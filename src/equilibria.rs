//! Micro-equilibria: the critical points of R(x) = |x − G| on the hull surface (paper
//! §2.2.2).
//!
//! Every predicate is a sign test of one of two families of scalars, each computed **once**:
//!
//! * facet–edge: `s(F, E) = (G − A)·m`, m the unit in-plane normal of facet F at its edge E
//!   pointing into F. `s > 0` ⇔ the projection of G onto F's plane lies on F's side of E.
//! * vertex–edge: `c(V → W) = (G − V)·(W − V)/|W − V|`. `c > 0` ⇔ the foot of the
//!   perpendicular from G to the line VW lies beyond V towards W ⇔ R decreases from V along VW.
//!
//! Then
//!
//! * F is **stable** ⇔ `s(F, E) > 0` for all its edges E (projection strictly inside F),
//!   R = n·x_F − n·G;
//! * E = (A, B) is a **saddle** ⇔ `c(A→B) > 0`, `c(B→A) > 0` (foot strictly inside E) and
//!   `s(F₀, E) > 0`, `s(F₁, E) > 0` (P − G inside the cone of the two normals), R = |P − G|;
//! * V is **unstable** ⇔ `c(V→W) > 0` for every neighbour W, R = |V − G|.
//!
//! **Degenerate cases.** A scalar with |value| ≤ τ = `tol_rel` · D (D the hull diameter) is
//! *degenerate* (G projects onto an edge or vertex, a tie). Its sign is decided by simulation of
//! simplicity: as if G were moved by an infinitesimal ε along a fixed generic direction d, i.e.
//! sign(value + ε ∂value/∂G·d) = sign(m·d) or sign(t·d). Because every scalar is evaluated once
//! and shared by all the predicates that use it, the result is the critical-point set of the
//! perturbed, generic G + εd, and Poincaré–Hopf S + U − H = 2 holds. Every such decision is
//! counted in [`Equilibria::degenerate_decisions`] and reported.

use crate::hull::Polyhedron;
use crate::mesh::{ldexp, scale_point};
use crate::{Error, Point3, Result, Vec3};
use serde::Serialize;

/// Default relative tolerance for degenerate equilibrium predicates (fraction of D).
pub const DEFAULT_DEGENERACY_TOL: f64 = 1e-9;

/// The fixed, generic direction of the symbolic perturbation of G.
pub fn perturbation_direction() -> Vec3 {
    Vec3::new(0.5488135039273248, 0.7151893663724195, 0.6027633760716439).normalize()
}

/// Type of a critical point of R.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// Minimum of R: the stone can rest here.
    Stable,
    /// Saddle of R on an edge.
    Saddle,
    /// Maximum of R at a vertex.
    Unstable,
}

/// Where on the hull a micro-equilibrium sits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "on", content = "index", rename_all = "lowercase")]
pub enum Site {
    /// Stable: on a hull facet (facet index).
    Facet(u32),
    /// Saddle: on a hull edge (edge index).
    Edge(u32),
    /// Unstable: at a hull vertex (vertex index).
    Vertex(u32),
}

/// One micro-equilibrium.
#[derive(Clone, Debug, Serialize)]
pub struct Equilibrium {
    /// Stable, saddle or unstable.
    pub kind: Kind,
    /// Hull facet, edge or vertex where it lies.
    pub site: Site,
    /// The contact point (projection of G, foot on the edge, or the vertex), input frame.
    pub point: Point3,
    /// R = distance from G to `point`.
    pub r: f64,
}

/// All micro-equilibria of a hull for a given G.
#[derive(Clone, Debug, Serialize)]
pub struct Equilibria {
    /// Stable first (by facet), then saddles (by edge), then unstable (by vertex).
    pub points: Vec<Equilibrium>,
    /// Number of stable equilibria (S).
    pub stable: usize,
    /// Number of saddle equilibria (H).
    pub saddle: usize,
    /// Number of unstable equilibria (U).
    pub unstable: usize,
    /// R_max: largest distance from G to a hull vertex (normalises the weights v_ij).
    pub r_max: f64,
    /// R_min: smallest R over the stable points.
    pub r_min: f64,
    /// Number of predicate signs decided by the symbolic perturbation (0 for generic input).
    pub degenerate_decisions: usize,
    /// For each facet / edge / vertex, the index into `points` of its equilibrium, if any.
    #[serde(skip)]
    pub at_facet: Vec<Option<u32>>,
    #[serde(skip)]
    /// For each edge, the index into `points` of its saddle, if any.
    pub at_edge: Vec<Option<u32>>,
    #[serde(skip)]
    /// For each vertex, the index into `points` of its unstable equilibrium, if any.
    pub at_vertex: Vec<Option<u32>>,
}

/// The shared signed scalars of the predicates (see the module docs).
pub struct Signs {
    /// `side[e] = [s(F₀,E) > 0, s(F₁,E) > 0]` for the two facets of edge e.
    pub side: Vec<[bool; 2]>,
    /// `beyond[e] = [c(A→B) > 0, c(B→A) > 0]` for edge e = (A, B).
    pub beyond: Vec<[bool; 2]>,
    /// Number of these signs decided by the symbolic perturbation.
    pub degenerate: usize,
}

impl Signs {
    /// Evaluate every facet–edge and vertex–edge scalar once.
    pub fn new(poly: &Polyhedron, g: &Point3, tol_rel: f64) -> Self {
        let tau = tol_rel * poly.diameter;
        let d = perturbation_direction();
        let mut degenerate = 0;
        let mut decide = |value: f64, gradient_dot_d: f64| {
            if value.abs() > tau {
                value > 0.0
            } else {
                degenerate += 1;
                gradient_dot_d > 0.0
            }
        };
        let mut side = Vec::with_capacity(poly.edges.len());
        let mut beyond = Vec::with_capacity(poly.edges.len());
        for e in &poly.edges {
            let [a, b] = e.vertices.map(|v| poly.vertices[v as usize]);
            let t = (b - a).normalize();
            let m0 = poly.facets[e.facets[0] as usize].normal.cross(&t).normalize();
            let m1 = -poly.facets[e.facets[1] as usize].normal.cross(&t).normalize();
            side.push([decide((g - a).dot(&m0), m0.dot(&d)), decide((g - a).dot(&m1), m1.dot(&d))]);
            beyond.push([decide((g - a).dot(&t), t.dot(&d)), decide((g - b).dot(&-t), -t.dot(&d))]);
        }
        Signs { side, beyond, degenerate }
    }
}

impl Equilibria {
    /// The same equilibria for the hull and G scaled by 2^k: points, R, R_min and R_max × 2^k
    /// (exact in f64's normal range; the classification does not depend on scale).
    pub fn scaled_pow2(mut self, k: i32) -> Self {
        for p in &mut self.points {
            p.point = scale_point(&p.point, k);
            p.r = ldexp(p.r, k);
        }
        self.r_max = ldexp(self.r_max, k);
        self.r_min = ldexp(self.r_min, k);
        self
    }

    /// Classify every facet, edge and vertex of `poly` for centre of mass `g`.
    pub fn new(poly: &Polyhedron, g: &Point3, tol_rel: f64) -> Result<Self> {
        Self::from_signs(poly, g, &Signs::new(poly, g, tol_rel))
    }

    /// Classify from signs already evaluated (shared with the Morse–Smale tracer).
    pub fn from_signs(poly: &Polyhedron, g: &Point3, signs: &Signs) -> Result<Self> {
        let mut points = Vec::new();
        let mut at_facet = vec![None; poly.facets.len()];
        let mut at_edge = vec![None; poly.edges.len()];
        let mut at_vertex = vec![None; poly.vertices.len()];
        // Stable facets: G's projection on the facet side of every edge.
        for (fi, f) in poly.facets.iter().enumerate() {
            let inside = f.edges.iter().all(|&e| {
                let ed = &poly.edges[e as usize];
                signs.side[e as usize][usize::from(ed.facets[0] != fi as u32)]
            });
            if inside {
                let h = f.offset - f.normal.dot(&g.coords);
                at_facet[fi] = Some(points.len() as u32);
                points.push(Equilibrium {
                    kind: Kind::Stable,
                    site: Site::Facet(fi as u32),
                    point: g + f.normal * h,
                    r: h,
                });
            }
        }
        let stable = points.len();
        for (ei, e) in poly.edges.iter().enumerate() {
            let [s0, s1] = signs.side[ei];
            let [c0, c1] = signs.beyond[ei];
            if s0 && s1 && c0 && c1 {
                let [a, b] = e.vertices.map(|v| poly.vertices[v as usize]);
                let t = (b - a).normalize();
                let foot = a + t * (g - a).dot(&t);
                at_edge[ei] = Some(points.len() as u32);
                points.push(Equilibrium {
                    kind: Kind::Saddle,
                    site: Site::Edge(ei as u32),
                    point: foot,
                    r: (foot - g).norm(),
                });
            }
        }
        let saddle = points.len() - stable;
        for (vi, p) in poly.vertices.iter().enumerate() {
            let max = poly.vertex_edges[vi].iter().all(|&e| {
                let ed = &poly.edges[e as usize];
                signs.beyond[e as usize][usize::from(ed.vertices[0] != vi as u32)]
            });
            if max {
                at_vertex[vi] = Some(points.len() as u32);
                points.push(Equilibrium {
                    kind: Kind::Unstable,
                    site: Site::Vertex(vi as u32),
                    point: *p,
                    r: (p - g).norm(),
                });
            }
        }
        let unstable = points.len() - stable - saddle;
        let r_max = poly.vertices.iter().map(|p| (p - g).norm()).fold(0.0, f64::max);
        let r_min = points[..stable].iter().map(|e| e.r).fold(f64::INFINITY, f64::min);
        let eq = Equilibria {
            points,
            stable,
            saddle,
            unstable,
            r_max,
            r_min,
            degenerate_decisions: signs.degenerate,
            at_facet,
            at_edge,
            at_vertex,
        };
        if stable as i64 + unstable as i64 - saddle as i64 != 2 {
            return Err(Error::check(format!(
                "Poincaré–Hopf violated: S + U − H = {stable} + {unstable} − {saddle} ≠ 2 ({} degenerate decisions)",
                signs.degenerate
            )));
        }
        if stable == 0 {
            return Err(Error::check("no stable facet: G is outside the hull"));
        }
        Ok(eq)
    }
}
