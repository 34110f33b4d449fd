//! The planar case (paper §1.1, Table 1, Figures 2, 4, 5; SPEC §5): convex polygons, their
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
//! The module is one file on purpose: it is the planar counterpart of the whole 3D pipeline,
//! from the polygon to its flocks.

use crate::hierarchy::{Counts, Flock, Flocks, Hierarchy, Kind, Node, Plateau, Step};
use crate::{Error, Result};
use rand::{RngExt, SeedableRng};
use serde::Serialize;
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::f64::consts::PI;

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

/// A convex polygon (a homogeneous plate) with its area centroid.
#[derive(Clone, Debug, Serialize)]
pub struct Polygon {
    /// Counter-clockwise.
    pub vertices: Vec<Point2>,
    /// G: the area centroid.
    pub centroid: Point2,
    /// Area of the polygon.
    pub area: f64,
    /// D: the diagonal of the bounding box (scale of the tolerances).
    pub size: f64,
}

impl Polygon {
    /// A convex polygon from its vertices in order (either orientation; stored
    /// counter-clockwise). Collinear consecutive vertices are allowed (a degenerate case the
    /// equilibria decide by perturbation); repeated vertices, reflex vertices, self-overlap and
    /// zero area are errors.
    pub fn new(mut vertices: Vec<Point2>) -> Result<Self> {
        let n = vertices.len();
        if n < 3 {
            return Err(Error::degenerate(format!("a polygon needs at least 3 vertices, got {n}")));
        }
        if vertices.iter().any(|p| !p.x.is_finite() || !p.y.is_finite()) {
            return Err(Error::invalid("non-finite polygon vertex"));
        }
        let (mut lo, mut hi) = (vertices[0], vertices[0]);
        for p in &vertices {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let size = (hi - lo).norm();
        let o = vertices[0];
        let (mut a2, mut m) = (0.0, Vec2::zeros());
        for i in 0..n {
            let (p, q) = (vertices[i] - o, vertices[(i + 1) % n] - o);
            let c = cross(&p, &q);
            a2 += c;
            m += (p + q) * c;
        }
        if a2.abs() <= 1e-12 * size * size {
            return Err(Error::degenerate("polygon of zero area"));
        }
        if a2 < 0.0 {
            vertices.reverse();
            return Self::new(vertices);
        }
        let tol = 1e-12;
        let mut turning = 0.0;
        for i in 0..n {
            let e0 = vertices[i] - vertices[(i + n - 1) % n];
            let e1 = vertices[(i + 1) % n] - vertices[i];
            let (l0, l1) = (e0.norm(), e1.norm());
            if l1 <= tol * size {
                return Err(Error::degenerate(format!("vertices {i} and {} coincide", (i + 1) % n)));
            }
            let c = cross(&e0, &e1);
            if c < -tol * l0 * l1 {
                return Err(Error::invalid(format!("polygon is not convex at vertex {i}")));
            }
            turning += c.atan2(e0.dot(&e1));
        }
        if (turning - 2.0 * PI).abs() > 1e-6 {
            return Err(Error::invalid(format!("polygon winds {:.3} times around itself", turning / (2.0 * PI))));
        }
        let centroid = o + m / (3.0 * a2);
        Ok(Polygon { vertices, centroid, area: a2 / 2.0, size })
    }

    /// The regular n-gon of circumradius `radius` centred at the origin, vertex 0 at angle
    /// `phase`.
    pub fn regular(n: usize, radius: f64, phase: f64) -> Result<Self> {
        Self::new(
            (0..n)
                .map(|i| {
                    let t = phase + 2.0 * PI * i as f64 / n as f64;
                    Point2::new(radius * t.cos(), radius * t.sin())
                })
                .collect(),
        )
    }

    /// The convex hull of a point set (Andrew's monotone chain with exact orientation tests;
    /// collinear points dropped).
    pub fn convex_hull(points: &[Point2]) -> Result<Self> {
        let mut p: Vec<Point2> = points.to_vec();
        p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
        p.dedup();
        if p.len() < 3 {
            return Err(Error::degenerate("fewer than 3 distinct points"));
        }
        let orient = |a: &Point2, b: &Point2, c: &Point2| {
            robust::orient2d(
                robust::Coord { x: a.x, y: a.y },
                robust::Coord { x: b.x, y: b.y },
                robust::Coord { x: c.x, y: c.y },
            )
        };
        let mut hull: Vec<Point2> = Vec::with_capacity(2 * p.len());
        for pass in 0..2 {
            let start = hull.len();
            let iter: Box<dyn Iterator<Item = &Point2>> =
                if pass == 0 { Box::new(p.iter()) } else { Box::new(p.iter().rev()) };
            for q in iter {
                while hull.len() >= start + 2 && orient(&hull[hull.len() - 2], &hull[hull.len() - 1], q) <= 0.0 {
                    hull.pop();
                }
                hull.push(*q);
            }
            hull.pop();
        }
        Self::new(hull)
    }

    /// Number of sides (= vertices).
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    /// Always false: a polygon has at least 3 vertices.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// R_max: the largest distance from G to a vertex.
    pub fn r_max(&self) -> f64 {
        self.vertices.iter().map(|p| (p - self.centroid).norm()).fold(0.0, f64::max)
    }

    /// R(φ): distance from G to the boundary along the polar angle φ (measured at G from +x).
    pub fn radius_at(&self, phi: f64) -> f64 {
        let d = Vec2::new(phi.cos(), phi.sin());
        let n = self.len();
        let g = self.centroid;
        for i in 0..n {
            let a = self.vertices[i] - g;
            let b = self.vertices[(i + 1) % n] - g;
            if cross(&a, &d) >= 0.0 && cross(&d, &b) >= 0.0 {
                let e = b - a;
                let den = cross(&d, &e);
                if den > 0.0 {
                    return cross(&a, &e) / den;
                }
            }
        }
        f64::NAN
    }

    /// The polygon rotated about G by `angle` and translated so that G is at `g`.
    pub fn placed(&self, angle: f64, g: Point2) -> Vec<Point2> {
        self.vertices.iter().map(|p| g + (p - self.centroid).rotate_by(angle)).collect()
    }
}

/// Where on the polygon a micro-equilibrium sits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "on", content = "index", rename_all = "lowercase")]
pub enum PlanarSite {
    /// Side i = (V_i, V_{i+1}).
    Side(u32),
    /// Vertex i (an unstable equilibrium).
    Vertex(u32),
}

/// One micro-equilibrium of a polygon.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct PlanarEquilibrium {
    /// Stable (side) or unstable (vertex).
    pub kind: Kind,
    /// Side or vertex where it lies.
    pub site: PlanarSite,
    /// Contact point: the foot of G on the side, or the vertex.
    pub point: Point2,
    /// R = |point − G|.
    pub r: f64,
    /// Polar angle of `point` seen from G, in (−π, π].
    pub phi: f64,
}

/// All micro-equilibria of a polygon, in boundary (= angular) order.
#[derive(Clone, Debug, Serialize)]
pub struct PlanarEquilibria {
    /// Vertex i (if unstable) then side i (if stable), i = 0, 1, …: alternating kinds.
    pub points: Vec<PlanarEquilibrium>,
    /// Number of stable equilibria (sides).
    pub stable: usize,
    /// Number of unstable equilibria (vertices).
    pub unstable: usize,
    /// Largest distance from G to a vertex.
    pub r_max: f64,
    /// Smallest R over the stable points.
    pub r_min: f64,
    /// Number of predicate signs decided by the symbolic perturbation (0 for generic input).
    pub degenerate_decisions: usize,
}

impl PlanarEquilibria {
    /// Classify every side and vertex of `poly` (see the module docs).
    pub fn new(poly: &Polygon, tol_rel: f64) -> Result<Self> {
        let n = poly.len();
        let g = poly.centroid;
        let tau = tol_rel * poly.size;
        let d = perturbation_direction();
        let d2 = d.rotate_by(PI / 2.0);
        let mut degenerate = 0;
        let mut decide = |value: f64, t: Vec2| {
            if value.abs() > tau {
                value > 0.0
            } else {
                degenerate += 1;
                let first = t.dot(&d);
                if first != 0.0 {
                    first > 0.0
                } else {
                    t.dot(&d2) > 0.0
                }
            }
        };
        let mut plus = Vec::with_capacity(n);
        let mut minus = Vec::with_capacity(n);
        let mut dirs = Vec::with_capacity(n);
        for i in 0..n {
            let (a, b) = (poly.vertices[i], poly.vertices[(i + 1) % n]);
            let t = (b - a).normalize();
            plus.push(decide((g - a).dot(&t), t));
            minus.push(decide((g - b).dot(&-t), -t));
            dirs.push(t);
        }
        let mut points = Vec::new();
        let mut stable = 0;
        let mut unstable = 0;
        let polar = |p: &Point2| (p.y - g.y).atan2(p.x - g.x);
        for i in 0..n {
            let before = minus[(i + n - 1) % n];
            if plus[i] && before {
                let v = poly.vertices[i];
                points.push(PlanarEquilibrium {
                    kind: Kind::Unstable,
                    site: PlanarSite::Vertex(i as u32),
                    point: v,
                    r: (v - g).norm(),
                    phi: polar(&v),
                });
                unstable += 1;
            } else if !plus[i] && !before {
                return Err(Error::check(format!(
                    "vertex {i} decided as a minimum of R ({degenerate} degenerate decisions): impossible on a convex polygon"
                )));
            }
            if plus[i] && minus[i] {
                let a = poly.vertices[i];
                let len = (poly.vertices[(i + 1) % n] - a).norm();
                let foot = a + dirs[i] * (g - a).dot(&dirs[i]).clamp(0.0, len);
                points.push(PlanarEquilibrium {
                    kind: Kind::Stable,
                    site: PlanarSite::Side(i as u32),
                    point: foot,
                    r: (foot - g).norm(),
                    phi: polar(&foot),
                });
                stable += 1;
            }
        }
        if stable != unstable || stable == 0 {
            return Err(Error::check(format!("S = {stable} ≠ U = {unstable} ({degenerate} degenerate decisions)")));
        }
        let r_min = points.iter().filter(|p| p.kind == Kind::Stable).map(|p| p.r).fold(f64::INFINITY, f64::min);
        Ok(PlanarEquilibria { points, stable, unstable, r_max: poly.r_max(), r_min, degenerate_decisions: degenerate })
    }
}

#[derive(PartialEq, Eq, PartialOrd, Ord)]
struct ArcKey {
    weight_bits: u64,
    lo: usize,
    hi: usize,
    /// The arc as (first, next) in the cycle's orientation.
    first: usize,
    next: usize,
}

/// The cancellation hierarchy of the cycle of critical points (see the module docs).
pub fn hierarchy(eq: &PlanarEquilibria) -> Hierarchy {
    let nodes: Vec<Node> = eq.points.iter().map(|p| Node { kind: p.kind, r: p.r }).collect();
    let n = nodes.len();
    let arcs: Vec<(usize, usize)> = (0..n).map(|i| (i, (i + 1) % n)).collect();
    let mut h = Hierarchy { nodes, arcs, r_max: eq.r_max, cancellations: Vec::with_capacity(n / 2) };
    let mut next: Vec<usize> = (0..n).map(|i| (i + 1) % n).collect();
    let mut prev: Vec<usize> = (0..n).map(|i| (i + n - 1) % n).collect();
    let mut alive = vec![true; n];
    let key = |h: &Hierarchy, u: usize, v: usize| {
        // Non-negative weights: the bit pattern orders like the value.
        Reverse(ArcKey { weight_bits: h.weight(u, v).to_bits(), lo: u.min(v), hi: u.max(v), first: u, next: v })
    };
    let mut heap: BinaryHeap<_> = (0..n).map(|i| key(&h, i, next[i])).collect();
    let mut remaining = eq.stable;
    let mut level: f64 = 0.0;
    while remaining > 1 {
        let Some(Reverse(k)) = heap.pop() else { break };
        let (u, v) = (k.first, k.next);
        if !alive[u] || !alive[v] || next[u] != v {
            continue; // stale
        }
        let weight = f64::from_bits(k.weight_bits);
        level = level.max(weight);
        let removed = if h.nodes[u].kind == Kind::Stable { [u, v] } else { [v, u] };
        h.cancellations.push(crate::hierarchy::Cancellation { weight, level, removed });
        alive[u] = false;
        alive[v] = false;
        remaining -= 1;
        let (p, q) = (prev[u], next[v]);
        next[p] = q;
        prev[q] = p;
        heap.push(key(&h, p, q));
    }
    debug_assert!(h.check().is_ok(), "{:?}", h.check());
    h
}

/// How the ellipse is discretised.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Sampling {
    /// Equal arc-length spacing, vertex 0 at (a, 0) (the paper's convention).
    ArcLength,
    /// Equal steps of the parameter t of (a cos t, sin t), vertex 0 at t = 0.
    Angle,
    /// Independent uniform arc-length positions (seeded Xoshiro256++), sorted.
    Random {
        /// Seed of the generator.
        seed: u64,
    },
}

/// N = 4k − 2, the paper's numbers of sides.
pub fn sides_for_k(k: usize) -> usize {
    4 * k - 2
}

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton iteration on P_n).
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n.div_ceil(2) {
        let mut z = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            // P_n(z) and P_n'(z) by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, z);
            for j in 2..=n {
                let p2 = ((2 * j - 1) as f64 * z * p1 - (j - 1) as f64 * p0) / j as f64;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 1 { z } else { p1 };
            let pn1 = if n == 1 { 1.0 } else { p0 };
            dp = n as f64 * (z * pn - pn1) / (z * z - 1.0);
            let dz = pn / dp;
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        x[i] = -z;
        x[n - 1 - i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
        w[n - 1 - i] = w[i];
    }
    (x, w)
}

/// Arc length on the ellipse (a cos t, sin t): s(t) and its inverse.
#[derive(Clone, Debug)]
pub struct EllipseArc {
    /// Semi-axis a of the ellipse along x (the other semi-axis is 1).
    pub a: f64,
    width: f64,
    cum: Vec<f64>,
    nodes: Vec<f64>,
    weights: Vec<f64>,
}

const PANELS: usize = 256;
const GL_POINTS: usize = 16;

impl EllipseArc {
    /// Tabulate the arc length of the ellipse with semi-axes `a` and 1 (Gauss–Legendre panels).
    pub fn new(a: f64) -> Self {
        let (nodes, weights) = gauss_legendre(GL_POINTS);
        let width = 2.0 * PI / PANELS as f64;
        let mut arc = EllipseArc { a, width, cum: vec![0.0; PANELS + 1], nodes, weights };
        for m in 0..PANELS {
            let lo = m as f64 * width;
            arc.cum[m + 1] = arc.cum[m] + arc.integrate(lo, lo + width);
        }
        arc
    }

    /// |d(a cos t, sin t)/dt|.
    pub fn speed(&self, t: f64) -> f64 {
        (self.a * t.sin()).hypot(t.cos())
    }

    fn integrate(&self, lo: f64, hi: f64) -> f64 {
        let (c, h) = ((lo + hi) / 2.0, (hi - lo) / 2.0);
        h * self.nodes.iter().zip(&self.weights).map(|(x, w)| w * self.speed(c + h * x)).sum::<f64>()
    }

    /// The perimeter L.
    pub fn perimeter(&self) -> f64 {
        self.cum[PANELS]
    }

    /// s(t) for t ∈ [0, 2π].
    pub fn length_to(&self, t: f64) -> f64 {
        let m = ((t / self.width) as usize).min(PANELS - 1);
        let lo = m as f64 * self.width;
        self.cum[m] + self.integrate(lo, t)
    }

    /// The parameter t ∈ [0, 2π] with s(t) = s (safeguarded Newton).
    pub fn param_at(&self, s: f64) -> f64 {
        let l = self.perimeter();
        if s <= 0.0 {
            return 0.0;
        }
        if s >= l {
            return 2.0 * PI;
        }
        let m = self.cum.partition_point(|&c| c <= s) - 1;
        let (mut lo, mut hi) = (m as f64 * self.width, (m + 1) as f64 * self.width);
        let mut t = lo + (s - self.cum[m]) / (self.cum[m + 1] - self.cum[m]) * self.width;
        for _ in 0..60 {
            let f = self.length_to(t) - s;
            if f.abs() <= 1e-15 * l {
                break;
            }
            if f > 0.0 {
                hi = t;
            } else {
                lo = t;
            }
            let newton = t - f / self.speed(t);
            t = if newton > lo && newton < hi { newton } else { (lo + hi) / 2.0 };
        }
        t
    }
}

fn ellipse_point(a: f64, t: f64) -> Point2 {
    Point2::new(a * t.cos(), t.sin())
}

/// The vertices of the ellipse (a cos t, sin t) discretised into `n` sides (see the module
/// docs), counter-clockwise from vertex 0.
pub fn ellipse_vertices(a: f64, n: usize, sampling: Sampling) -> Result<Vec<Point2>> {
    if !(a >= 1.0 && a.is_finite()) {
        return Err(Error::Usage(format!("the semi-axis a must be ≥ 1 (the major axis is x), got {a}")));
    }
    if n < 3 {
        return Err(Error::Usage(format!("an ellipse polygon needs at least 3 sides, got {n}")));
    }
    let arc = EllipseArc::new(a);
    let l = arc.perimeter();
    // The point at fraction num/den of the perimeter (or of 2π in t), built from the first
    // quadrant by exact mirroring.
    let symmetric = |num: usize, den: usize, first_quadrant: &dyn Fn(f64) -> Point2| {
        let p = |m: usize| first_quadrant(m as f64 / den as f64);
        if 4 * num <= den {
            p(num)
        } else if 4 * num <= 2 * den {
            let q = p(den / 2 - num);
            Point2::new(-q.x, q.y)
        } else if 4 * num <= 3 * den {
            let q = p(num - den / 2);
            Point2::new(-q.x, -q.y)
        } else {
            let q = p(den - num);
            Point2::new(q.x, -q.y)
        }
    };
    let v = match sampling {
        Sampling::ArcLength => {
            let f = |frac: f64| ellipse_point(a, arc.param_at(frac * l));
            (0..n).map(|i| symmetric(2 * i, 2 * n, &f)).collect()
        }
        Sampling::Angle => {
            let f = |frac: f64| ellipse_point(a, frac * 2.0 * PI);
            (0..n).map(|i| symmetric(2 * i, 2 * n, &f)).collect()
        }
        Sampling::Random { seed } => {
            let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
            let mut s: Vec<f64> = (0..n).map(|_| rng.random::<f64>() * l).collect();
            s.sort_by(f64::total_cmp);
            s.into_iter().map(|s| ellipse_point(a, arc.param_at(s))).collect()
        }
    };
    Ok(v)
}

/// The ellipse polygon of [`ellipse_vertices`].
pub fn ellipse_polygon(a: f64, n: usize, sampling: Sampling) -> Result<Polygon> {
    Polygon::new(ellipse_vertices(a, n, sampling)?)
}

/// R(φ) of the smooth ellipse (a cos t, sin t) seen from its centre at polar angle φ.
pub fn ellipse_radius(a: f64, phi: f64) -> f64 {
    1.0 / ((phi.cos() / a).powi(2) + phi.sin().powi(2)).sqrt()
}

/// The k → ∞ flock contents of Table 1 (paper §1.1) for the axis ratio 1 : a.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Table1 {
    /// m = ⌊a² / (2(a² − 1))⌋.
    pub m: usize,
    /// (stable, unstable) micro-equilibria in each stable flock: (2m + 1, 2m).
    pub stable_flock: (usize, usize),
    /// (stable, unstable) micro-equilibria in each unstable flock: (2m, 2m + 1).
    pub unstable_flock: (usize, usize),
    /// Total S = 8m + 2.
    pub total_stable: usize,
    /// a²/(2(a² − 1)) is (within 1e-9) an integer: the formula's floor sits on a jump and the
    /// limit is decided by higher-order terms.
    pub on_jump: bool,
}

/// Table 1 of the paper for a > 1 (`None` for a ≤ 1: the circle has no limit).
pub fn table1(a: f64) -> Option<Table1> {
    if !(a > 1.0) {
        return None;
    }
    let x = a * a / (2.0 * (a * a - 1.0));
    let m = x.floor() as usize;
    Some(Table1 {
        m,
        stable_flock: (2 * m + 1, 2 * m),
        unstable_flock: (2 * m, 2 * m + 1),
        total_stable: 8 * m + 2,
        on_jump: (x - x.round()).abs() < 1e-9,
    })
}

pub use crate::hierarchy::NuSource;

/// Polygon, micro-equilibria and hierarchy, in memory.
#[derive(Clone, Debug)]
pub struct PlanarAnalysis {
    /// The polygon.
    pub polygon: Polygon,
    /// Its micro-equilibria.
    pub equilibria: PlanarEquilibria,
    /// Cancellation hierarchy of the micro-equilibria over ν.
    pub hierarchy: Hierarchy,
}

/// The flock contents of a polygon with a stable/unstable macro pattern (e.g. the ellipse):
/// the (stable, unstable) counts of every stable and every unstable flock, in flock order.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct FlockContents {
    /// (stable, unstable) counts of every stable flock.
    pub stable_flocks: Vec<(usize, usize)>,
    /// (stable, unstable) counts of every unstable flock.
    pub unstable_flocks: Vec<(usize, usize)>,
}

impl FlockContents {
    /// Collect the contents of `flocks` by type.
    pub fn of(flocks: &[Flock]) -> Self {
        let mut c = FlockContents::default();
        for f in flocks {
            match f.kind {
                Kind::Stable => c.stable_flocks.push((f.stable, f.unstable)),
                _ => c.unstable_flocks.push((f.stable, f.unstable)),
            }
        }
        c
    }

    /// The common (stable, unstable) content of all stable flocks and of all unstable flocks,
    /// if every flock of a type has the same content.
    pub fn uniform(&self) -> Option<((usize, usize), (usize, usize))> {
        let same = |v: &[(usize, usize)]| v.first().filter(|f| v.iter().all(|x| x == *f)).copied();
        Some((same(&self.stable_flocks)?, same(&self.unstable_flocks)?))
    }
}

/// A rocking equilibrium of a polygon: a stable side in an unstable flock.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct RockingSide {
    /// Index into the micro-equilibria.
    pub index: usize,
    /// The stable side.
    pub side: u32,
    /// Contact point: the foot of G on the side.
    pub point: Point2,
    /// R = distance from G to the contact point.
    pub r: f64,
    /// Polar angle of the contact point seen from G, in (−π, π].
    pub phi: f64,
    /// Index of the (unstable) flock containing it.
    pub flock: usize,
}

/// The serialisable result of a planar analysis.
#[derive(Clone, Debug, Serialize)]
pub struct PlanarReport {
    /// Number of sides of the polygon.
    pub sides: usize,
    /// Area of the polygon.
    pub area: f64,
    /// G: the area centroid.
    pub centroid: Point2,
    /// Micro-equilibria.
    pub stable: usize,
    /// Number of unstable micro-equilibria (vertices).
    pub unstable: usize,
    /// R_min: smallest distance from G to a stable side.
    pub r_min: f64,
    /// R_max: largest distance from G to a vertex.
    pub r_max: f64,
    /// v_max = (R_max − R_min)/R_max: the largest cancellation level.
    pub v_max: f64,
    /// Number of signs decided within the tolerance τ = `tol_rel` · D.
    pub degenerate_decisions: usize,
    /// The macro scale used for flocks.
    pub nu: f64,
    /// Where ν came from.
    pub nu_source: NuSource,
    /// The longest step of n(ν), if any.
    pub plateau: Option<Plateau>,
    /// S(ν), U(ν).
    #[serde(rename = "macro")]
    pub macro_counts: Counts,
    /// Flocks at ν.
    pub flocks: Vec<Flock>,
    /// (stable, unstable) contents of the flocks by type.
    pub flock_contents: FlockContents,
    /// Stable sides in unstable flocks.
    pub rocking: Vec<RockingSide>,
    /// Every micro-equilibrium.
    pub micro: Vec<PlanarEquilibrium>,
    /// Staircase of the counts against ν.
    pub staircase: Vec<Step>,
}

impl PlanarAnalysis {
    /// Find the equilibria of `polygon` (signs within `tol_rel` · D decided symbolically), build and check the hierarchy.
    pub fn new(polygon: Polygon, tol_rel: f64) -> Result<Self> {
        let equilibria = PlanarEquilibria::new(&polygon, tol_rel)?;
        let hierarchy = hierarchy(&equilibria);
        hierarchy.check()?;
        Ok(PlanarAnalysis { polygon, equilibria, hierarchy })
    }

    /// The ν of the macro scale, by the rule of the 3D case ([`crate::hierarchy::macro_nu`]):
    /// the user's, else the midpoint of a clear plateau, else the paper's ν = 0.0035.
    pub fn macro_nu(&self, user: Option<f64>) -> (f64, NuSource) {
        crate::hierarchy::macro_nu(user, self.hierarchy.plateau())
    }

    /// The flocks at ν.
    pub fn flocks_at(&self, nu: f64) -> Flocks {
        self.hierarchy.flocks_at(nu)
    }

    /// The report at the user's ν, else at the automatic macro scale.
    pub fn report(&self, user_nu: Option<f64>) -> PlanarReport {
        let m = self.hierarchy.macro_scale(user_nu);
        let (nu, nu_source, flocks) = (m.nu, m.source, m.flocks);
        let eq = &self.equilibria;
        let rocking = m
            .rocking
            .into_iter()
            .map(|i| {
                let p = &eq.points[i];
                RockingSide {
                    index: i,
                    side: match p.site {
                        PlanarSite::Side(s) => s,
                        PlanarSite::Vertex(_) => unreachable!("rocking equilibria are stable"),
                    },
                    point: p.point,
                    r: p.r,
                    phi: p.phi,
                    flock: flocks.membership[i],
                }
            })
            .collect();
        PlanarReport {
            sides: self.polygon.len(),
            area: self.polygon.area,
            centroid: self.polygon.centroid,
            stable: eq.stable,
            unstable: eq.unstable,
            r_min: eq.r_min,
            r_max: eq.r_max,
            v_max: self.hierarchy.v_max(),
            degenerate_decisions: eq.degenerate_decisions,
            nu,
            nu_source,
            plateau: m.plateau,
            macro_counts: m.counts,
            flock_contents: FlockContents::of(&flocks.flocks),
            flocks: flocks.flocks,
            rocking,
            micro: eq.points.clone(),
            staircase: self.hierarchy.staircase(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_is_exact_for_polynomials() {
        let (x, w) = gauss_legendre(16);
        assert!((w.iter().sum::<f64>() - 2.0).abs() < 1e-14);
        // ∫ x^30 dx over [−1, 1] = 2/31 (degree 2n − 2 = 30 integrated exactly).
        let i: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(30)).sum();
        assert!((i - 2.0 / 31.0).abs() < 1e-14, "{i}");
    }

    #[test]
    fn arc_length_of_a_circle() {
        let arc = EllipseArc::new(1.0);
        assert!((arc.perimeter() - 2.0 * PI).abs() < 1e-13);
        assert!((arc.param_at(1.0) - 1.0).abs() < 1e-13);
    }

    #[test]
    fn square_and_degenerate_pentagon() {
        let sq = Polygon::regular(4, 1.0, 0.3).unwrap();
        let e = PlanarEquilibria::new(&sq, DEFAULT_DEGENERACY_TOL).unwrap();
        assert_eq!((e.stable, e.unstable, e.degenerate_decisions), (4, 4, 0));
        // A square with a collinear extra vertex at the foot of G on its right side: both
        // scalars at that vertex vanish; the perturbation makes exactly one adjacent half-side
        // stable and the vertex not a maximum.
        let p = Polygon::new(vec![
            Point2::new(-1.0, -1.0),
            Point2::new(1.0, -1.0),
            Point2::new(1.0, 0.0),
            Point2::new(1.0, 1.0),
            Point2::new(-1.0, 1.0),
        ])
        .unwrap();
        let e = PlanarEquilibria::new(&p, DEFAULT_DEGENERACY_TOL).unwrap();
        assert_eq!((e.stable, e.unstable), (4, 4));
        assert!(e.degenerate_decisions >= 2);
    }
}
