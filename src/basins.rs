//! Quasi-static basins of the stable facets on the sphere of down directions, and the merge tree
//! of the support function that decides a drop's final facet early (SPEC §6, "Static reference"
//! and "Certificates from the static theory").
//!
//! # The support function and its flow
//!
//! A resting body is described by its **down direction** d (unit, body frame, from G towards the
//! ground). With w_V = V − G for the hull corners V,
//!
//! ```text
//! h(d) = max_V w_V · d
//! ```
//!
//! is the height of G above the ground when the body touches it with down direction d. The
//! sphere is tiled by the **normal cones** C_V = {d : w_V·d ≥ w_W·d ∀W} of the corners; C_V is a
//! convex spherical polygon whose corners are the outward normals n_F of the facets at V and
//! whose sides are the **arcs** of the edges at V (the arc of edge E = (A, B) joins the normals of
//! its two facets on the great circle ⊥ B − A). Inside C_V, h(d) = |w_V| cos∠(d, u_V) with
//! u_V = w_V/|w_V|, and since h > 0 (G is inside) C_V lies in the open hemisphere around u_V.
//!
//! **Quasi-static rolling** is the gradient descent of h on the sphere ([`SupportFlow::settle`]):
//!
//! * inside C_V the flow runs along the great circle through u_V, away from u_V (a *meridian* of
//!   V); it is followed exactly (the exit angle is a closed-form `atan2`);
//! * at the arc of E = (A, B), with e = B − A: if w_B·e < 0 the flow crosses from C_A into C_B
//!   (w_A·e > 0: from C_B into C_A); otherwise (w_A·e ≤ 0 ≤ w_B·e, i.e. the foot P of the
//!   perpendicular from G to E's line lies on E) both neighbouring flows run into the arc — a
//!   *valley* of h — and the flow slides along it, away from u_P = (P − G)/|P − G|, to one of its
//!   end normals. (The fourth case, a ridge, would need |e|² < 0.) A valley arc containing u_P
//!   carries a saddle of h, h(u_P) = R of the saddle on E (SPEC §2);
//! * at a facet normal n_F, h near n_F is h(n_F) plus the support function of the polygon F − q_F
//!   (q_F the projection of G onto F's plane). It is a minimum iff q_F is inside F (F stable; the
//!   stable set is taken from [`Equilibria`], so degenerate decisions agree with the rest of the
//!   crate). Otherwise the steepest descent leaves towards q_F − c, c the point of F closest to
//!   q_F: along the arc of c's edge (the body tips over that edge) or into the cone of c's
//!   vertex (it tips over that corner).
//!
//! Every step lowers h, so a descent cannot cycle; it is still capped
//! (`4 (E + F) + 64` steps) and reports an error instead of looping. The start corner is found
//! by hill climbing on the corner graph from the nearest of 64 precomputed directions (a linear
//! function has no local maximum on a convex polytope's graph), not by a scan of all corners.
//!
//! # Basin areas, exactly ([`basin_probabilities`])
//!
//! Inside C_V every point of a meridian flows to the same exit point, so the final facet is a
//! function of the meridian's angle around u_V. It can change only across meridians that are
//! **separatrices**: meridians through the corners of C_V, through a point u_P of an arc (a
//! saddle), and — recursively — the continuations upstream of these, traced backwards (towards
//! u_V) through the transverse arcs by which the flow entered C_V, until they reach a maximum
//! u_V or a corner (whose own backward meridians are traced anyway). A label change on a cone's
//! outflow boundary can only be at one of those points, by induction along the flow (h
//! decreases), so the list is complete. Each cone is then cut into **sectors** between
//! consecutive separatrix angles (gaps > π/2 are split further); a sector ∩ C_V is a convex
//! spherical polygon (clipped exactly against two half-spaces through u_V), its area is a sum of
//! spherical triangle excesses (Van Oosterom–Strackee), and its label is the exact descent from
//! its centroid. As a guard, the centroids of both halves must agree with it; if not, the sector
//! is bisected (up to 24 times) and any area still unresolved is added to the stated error.
//!
//! The stated `error` (absolute, per facet; a bound on the sum over facets as well) is
//! `(unresolved + failed area)/4π + |Σ areas/4π − 1| + 1e-12`, the last term covering rounding
//! and the 1e-12 rad snapping of points onto facet normals. On every body tested the unresolved
//! area is 0, and the probabilities agree with brute-force integration of the flow ODE
//! (`tests/basins.rs`) within the Monte Carlo error.
//!
//! # The merge tree and the energy certificate ([`MergeTree`])
//!
//! For a passive body the total energy E never grows, and E ≥ m g z_G ≥ m g h(d) (the body is on
//! or above the ground). So with the **level** L = E/(m g) (a height of G above the ground, in
//! mesh units), the down direction stays for ever in the sublevel set S_L = {h ≤ L}, and, moving
//! continuously, in its current connected component. If that component contains one stable facet,
//! the final facet is decided; if all its stable facets are in one flock, the final flock is.
//!
//! **Components of S_L from arcs alone.** Take the graph whose nodes are the facet normals and
//! whose edges are the arcs, weighted by the largest h on the arc: max(h(n_F₀), h(n_F₁), |P − G|
//! if u_P lies on the arc) (h on an arc is |P − G| cos∠(d, u_P)). Its components at level L (edges
//! of weight ≤ L) are exactly the components of S_L, each represented by the normals in it:
//!
//! 1. *Every component of C_V ∩ S_L contains a corner of C_V, joined to it inside C_V ∩ S_L along
//!    whole arcs.* C_V ∩ S_L is the convex polygon C_V minus the open cap D = {w_V·d > L}, which
//!    is convex. D meets each side of C_V in one interval, so every component of ∂C_V ∖ D contains
//!    a corner; every component K of C_V ∖ D touches ∂C_V (D's complement is connected and not
//!    inside C_V), and in a single component of ∂C_V ∖ D (two would be separated inside C_V by a
//!    path of K, yet joined by a geodesic of the convex set C_V ∩ D that crosses it). That piece of
//!    ∂C_V is a chain of corners and whole arcs, all in S_L.
//! 2. *Crossing between cones keeps to the graph.* A path of S_L passing from C_V to C_W does so
//!    at a point x of their common arc; h on the arc is a cosine around u_P, so its part in S_L
//!    is at most two intervals, each containing an end normal; that normal is a corner of both
//!    C_V and C_W and is joined to x inside both.
//!
//! Hence two normals are in one component of S_L iff a chain of arcs of weight ≤ L joins them,
//! and Kruskal on the arcs (facets as leaves, each internal node at the weight of the arc that
//! joined its two children) is the merge tree of h. (The weight is the arc's *largest* h, as SPEC
//! §6 says; on a ridge edge whose foot lies outside the edge, u_P can lie on the arc and exceed
//! both end values. A smaller weight would only be conservative.) The component of S_L that
//! contains d contains the facet `settle(d)` reaches (the flow does not raise h), so
//! [`MergeTree::decided`] climbs from that leaf to its highest ancestor with level ≤ L.
//! [`MergeTree::entry_barrier`] is the level of the lowest common ancestor. The caller must add
//! its own margin to L for what the simulation breaks (penetration, f32 rounding); a level below
//! h(d) is raised to h(d).

use crate::equilibria::Equilibria;
use crate::hull::Polyhedron;
use crate::{Error, Point3, Result, Vec3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Angular tolerance (radians) for snapping a point of an arc onto one of its end normals.
const SNAP: f64 = 1e-12;
/// "No edge / no facet".
const NONE: u32 = u32::MAX;
/// Bisections of a sector whose check labels disagree, before its area counts as unresolved.
const MAX_REFINE: u32 = 24;
/// Precomputed start directions of the support-corner hill climb.
const SEEDS: usize = 64;

/// How the flow meets the arc of an edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ArcKind {
    /// Both neighbouring flows run into the arc (foot of G on the edge): it slides along it.
    Valley,
    /// The flow crosses from the cone of `vertices[k]` into the cone of the other end.
    Cross(u8),
}

/// What the flow does at a facet normal.
#[derive(Clone, Copy, Debug)]
enum Leave {
    /// A minimum of h: the body rests on this facet.
    Stable,
    /// Slide along the arc of `edge` to the normal of facet `to`.
    Slide { to: u32 },
    /// Leave into the cone of `vertex` along its meridian.
    Enter { vertex: u32 },
}

/// Where a descent is.
#[derive(Clone, Copy, Debug)]
enum State {
    Cone { v: u32, d: Vec3, skip_edge: u32, skip_facet: u32 },
    Facet(u32),
}

/// The gradient flow of the support function h on the sphere of down directions, with
/// everything precomputed that a descent needs (owned: no borrow of the polyhedron, `Sync`).
#[derive(Clone, Debug)]
pub struct SupportFlow {
    /// w_V = V − G.
    w: Vec<Vec3>,
    /// u_V = w_V / |w_V|.
    u: Vec<Vec3>,
    edge_vertices: Vec<[u32; 2]>,
    edge_facets: Vec<[u32; 2]>,
    arc: Vec<ArcKind>,
    /// P − G for each edge (P the foot of the perpendicular from G to the edge's line).
    foot: Vec<Vec3>,
    vertex_edges: Vec<Vec<u32>>,
    /// The facets around each corner in cyclic order (the corners of its normal cone).
    cones: Vec<Vec<u32>>,
    facet_vertices: Vec<Vec<u32>>,
    facet_edges: Vec<Vec<u32>>,
    normal: Vec<Vec3>,
    /// h(n_F) = distance from G to the facet's plane.
    facet_h: Vec<f64>,
    leave: Vec<Leave>,
    seeds: Vec<(Vec3, u32)>,
    max_steps: usize,
}

/// A unit vector orthogonal to the unit vector `u`, and u × it (a right-handed frame with u).
fn frame(u: &Vec3) -> (Vec3, Vec3) {
    let (x, y, z) = (u.x.abs(), u.y.abs(), u.z.abs());
    let a = if x <= y && x <= z {
        Vec3::x()
    } else if y <= z {
        Vec3::y()
    } else {
        Vec3::z()
    };
    let p1 = (a - u * u.dot(&a)).normalize();
    (p1, u.cross(&p1))
}

impl SupportFlow {
    /// Precompute the flow of h for hull `poly` and centre of mass `g`; the stable facets are
    /// those of `eq` (which must belong to the same hull and G).
    pub fn new(poly: &Polyhedron, g: &Point3, eq: &Equilibria) -> Self {
        let w: Vec<Vec3> = poly.vertices.iter().map(|p| p - g).collect();
        let u: Vec<Vec3> = w.iter().map(|x| x.normalize()).collect();
        let edge_vertices: Vec<[u32; 2]> = poly.edges.iter().map(|e| e.vertices).collect();
        let edge_facets: Vec<[u32; 2]> = poly.edges.iter().map(|e| e.facets).collect();
        let mut arc = Vec::with_capacity(poly.edges.len());
        let mut foot = Vec::with_capacity(poly.edges.len());
        for e in &poly.edges {
            let [a, b] = e.vertices.map(|v| v as usize);
            let along = poly.vertices[b] - poly.vertices[a];
            arc.push(if w[b].dot(&along) < 0.0 {
                ArcKind::Cross(0)
            } else if w[a].dot(&along) > 0.0 {
                ArcKind::Cross(1)
            } else {
                ArcKind::Valley
            });
            let t = along.normalize();
            foot.push(w[a] - t * w[a].dot(&t));
        }
        let normal: Vec<Vec3> = poly.facets.iter().map(|f| f.normal).collect();
        let facet_h: Vec<f64> = poly.facets.iter().map(|f| f.offset - f.normal.dot(&g.coords)).collect();
        let facet_vertices: Vec<Vec<u32>> = poly.facets.iter().map(|f| f.vertices.clone()).collect();
        let facet_edges: Vec<Vec<u32>> = poly.facets.iter().map(|f| f.edges.clone()).collect();
        let cones = (0..poly.vertices.len() as u32).map(|v| cone_facets(poly, v)).collect();
        let mut flow = SupportFlow {
            w,
            u,
            edge_vertices,
            edge_facets,
            arc,
            foot,
            vertex_edges: poly.vertex_edges.clone(),
            cones,
            facet_vertices,
            facet_edges,
            normal,
            facet_h,
            leave: Vec::new(),
            seeds: Vec::new(),
            max_steps: 4 * (poly.edges.len() + poly.facets.len()) + 64,
        };
        flow.leave = (0..poly.facets.len())
            .map(|f| if eq.at_facet.get(f).is_some_and(|s| s.is_some()) { Leave::Stable } else { flow.leave_facet(f) })
            .collect();
        flow.seeds = crate::rng::fibonacci_sphere(SEEDS)
            .into_iter()
            .map(|d| {
                let best = (0..flow.w.len())
                    .max_by(|&a, &b| flow.w[a].dot(&d).total_cmp(&flow.w[b].dot(&d)).then(b.cmp(&a)))
                    .unwrap_or(0);
                (d, best as u32)
            })
            .collect();
        flow
    }

    /// Number of facets.
    pub fn facets(&self) -> usize {
        self.normal.len()
    }

    /// Is facet `f` a minimum of h (a stable facet)?
    pub fn is_stable(&self, f: u32) -> bool {
        matches!(self.leave[f as usize], Leave::Stable)
    }

    /// h(n_F): the distance from G to facet `f`'s plane.
    pub fn facet_height(&self, f: u32) -> f64 {
        self.facet_h[f as usize]
    }

    /// The largest h along the arc of edge `e` (the weight of the arc in the merge tree).
    pub fn arc_max(&self, e: u32) -> f64 {
        let [f0, f1] = self.edge_facets[e as usize];
        let mut m = self.facet_h[f0 as usize].max(self.facet_h[f1 as usize]);
        let p = self.foot[e as usize];
        let pn = p.norm();
        if pn > 0.0 {
            let up = p / pn;
            let (n0, n1) = (self.normal[f0 as usize], self.normal[f1 as usize]);
            let axis = n0.cross(&n1);
            if n0.cross(&up).dot(&axis) >= 0.0 && up.cross(&n1).dot(&axis) >= 0.0 && up.dot(&(n0 + n1)) > 0.0 {
                m = m.max(pn);
            }
        }
        m
    }

    fn other(&self, e: u32, v: u32) -> u32 {
        let [a, b] = self.edge_vertices[e as usize];
        if a == v {
            b
        } else {
            a
        }
    }

    /// The corner of the hull touching the ground for down direction `d` (any length): the
    /// maximiser of w_V·d, by hill climbing from the nearest precomputed direction.
    pub fn support_vertex(&self, d: &Vec3) -> u32 {
        let mut v = self.seeds.iter().max_by(|a, b| a.0.dot(d).total_cmp(&b.0.dot(d))).map_or(0, |s| s.1);
        let mut best = self.w[v as usize].dot(d);
        loop {
            let mut next = v;
            for &e in &self.vertex_edges[v as usize] {
                let x = self.other(e, v);
                let val = self.w[x as usize].dot(d);
                if val > best {
                    best = val;
                    next = x;
                }
            }
            if next == v {
                return v;
            }
            v = next;
        }
    }

    /// h(d) for a down direction `d` (normalised here).
    pub fn h(&self, d: &Vec3) -> f64 {
        let d = d.normalize();
        self.w[self.support_vertex(&d) as usize].dot(&d)
    }

    /// The stable facet the quasi-static descent from down direction `d` ends on.
    pub fn settle(&self, d: &Vec3) -> Result<u32> {
        let d = unit(d)?;
        self.descend(self.support_vertex(&d), d, None)
    }

    /// As [`SupportFlow::settle`], also returning h(d).
    pub fn settle_with_height(&self, d: &Vec3) -> Result<(u32, f64)> {
        let d = unit(d)?;
        let v = self.support_vertex(&d);
        Ok((self.descend(v, d, None)?, self.w[v as usize].dot(&d)))
    }

    /// The descent from `d` with its breakpoints (exits from cones, facet normals), ending at
    /// the normal of the stable facet it returns.
    pub fn settle_path(&self, d: &Vec3) -> Result<(u32, Vec<Vec3>)> {
        let d = unit(d)?;
        let mut path = Vec::new();
        let f = self.descend(self.support_vertex(&d), d, Some(&mut path))?;
        Ok((f, path))
    }

    /// The steepest-descent exit from the normal of a facet that is not stable.
    fn leave_facet(&self, f: usize) -> Leave {
        let n = self.normal[f];
        let q = n * self.facet_h[f]; // projection of G onto the plane, relative to G
        let vs = &self.facet_vertices[f];
        let k_n = vs.len();
        let mut min_side = (f64::INFINITY, 0usize);
        let mut closest = (f64::INFINITY, 0usize, 0.0);
        for k in 0..k_n {
            let a = self.w[vs[k] as usize];
            let ab = self.w[vs[(k + 1) % k_n] as usize] - a;
            let inward = n.cross(&ab).normalize();
            let side = (q - a).dot(&inward);
            if side < min_side.0 {
                min_side = (side, k);
            }
            let lambda = ((q - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
            let dist = (q - (a + ab * lambda)).norm_squared();
            if dist < closest.0 {
                closest = (dist, k, lambda);
            }
        }
        let across = |k: usize| {
            let e = self.facet_edges[f][k];
            let [f0, f1] = self.edge_facets[e as usize];
            Leave::Slide { to: if f0 == f as u32 { f1 } else { f0 } }
        };
        if min_side.0 > 0.0 {
            // q is inside F by rounding while `eq` (symbolic perturbation) says F is not stable:
            // tip over the edge G projects closest to.
            return across(min_side.1);
        }
        let (_, k, lambda) = closest;
        if lambda > 1e-12 && lambda < 1.0 - 1e-12 {
            across(k)
        } else {
            Leave::Enter { vertex: if lambda <= 0.5 { vs[k] } else { vs[(k + 1) % k_n] } }
        }
    }

    /// If `x` (a point of the arc of edge `e`) is at, or numerically beyond, one of the arc's
    /// end normals, that facet.
    fn corner_of(&self, e: u32, x: &Vec3) -> Option<u32> {
        let [f0, f1] = self.edge_facets[e as usize];
        let (n0, n1) = (self.normal[f0 as usize], self.normal[f1 as usize]);
        let axis = n0.cross(&n1);
        let (d0, d1) = ((x - n0).norm(), (x - n1).norm());
        let beyond = n0.cross(x).dot(&axis) <= 0.0 || x.cross(&n1).dot(&axis) <= 0.0;
        (beyond || d0 < SNAP || d1 < SNAP).then_some(if d0 <= d1 { f0 } else { f1 })
    }

    /// Descend from `d` in the cone of `v` to a stable facet.
    fn descend(&self, v: u32, d: Vec3, mut path: Option<&mut Vec<Vec3>>) -> Result<u32> {
        let mut state = State::Cone { v, d, skip_edge: NONE, skip_facet: NONE };
        if let Some(p) = path.as_deref_mut() {
            p.push(d);
        }
        for _ in 0..self.max_steps {
            state = match state {
                State::Facet(f) => match self.leave[f as usize] {
                    Leave::Stable => return Ok(f),
                    Leave::Slide { to } => State::Facet(to),
                    Leave::Enter { vertex } => {
                        State::Cone { v: vertex, d: self.normal[f as usize], skip_edge: NONE, skip_facet: f }
                    }
                },
                State::Cone { v, d, skip_edge, skip_facet } => self.cone_step(v, &d, skip_edge, skip_facet)?,
            };
            if let Some(p) = path.as_deref_mut() {
                match state {
                    State::Cone { d, .. } => p.push(d),
                    State::Facet(f) => {
                        if p.last() != Some(&self.normal[f as usize]) {
                            p.push(self.normal[f as usize]);
                        }
                    }
                }
            }
        }
        Err(Error::check(format!("the quasi-static descent did not reach a stable facet in {} steps", self.max_steps)))
    }

    /// Follow the meridian of `v` through `d` (away from u_V) to the boundary of its cone.
    fn cone_step(&self, v: u32, d: &Vec3, skip_edge: u32, skip_facet: u32) -> Result<State> {
        let vi = v as usize;
        let u = self.u[vi];
        let t = d * u.dot(d) - u;
        let tn = t.norm();
        // d = u_V exactly (a maximum): any meridian; take the frame's.
        let t = if tn > 1e-15 { t / tn } else { frame(d).0 };
        let wv = self.w[vi];
        let mut best: Option<(f64, u32)> = None;
        for &e in &self.vertex_edges[vi] {
            if e == skip_edge || self.edge_facets[e as usize].contains(&skip_facet) {
                continue;
            }
            let m = wv - self.w[self.other(e, v) as usize];
            let (a, b) = (m.dot(d), m.dot(&t));
            // first θ > 0 with a cos θ + b sin θ = 0 (the meridian leaves through this arc)
            let theta = if a > 0.0 {
                a.atan2(-b)
            } else if b < 0.0 {
                0.0
            } else {
                continue;
            };
            if best.is_none_or(|(bt, be)| theta < bt || (theta == bt && e < be)) {
                best = Some((theta, e));
            }
        }
        let Some((theta, e)) = best else {
            return Err(Error::check("a quasi-static descent found no exit from a vertex cone"));
        };
        let x = (d * theta.cos() + t * theta.sin()).normalize();
        if let Some(f) = self.corner_of(e, &x) {
            return Ok(State::Facet(f));
        }
        let ei = e as usize;
        match self.arc[ei] {
            ArcKind::Cross(k) if self.edge_vertices[ei][k as usize] == v => {
                Ok(State::Cone { v: self.other(e, v), d: x, skip_edge: e, skip_facet: NONE })
            }
            _ => {
                // Valley: slide along the arc, downhill, to one of its ends.
                let [f0, f1] = self.edge_facets[ei];
                let axis = self.normal[f0 as usize].cross(&self.normal[f1 as usize]);
                let towards_f1 = axis.cross(&x);
                Ok(State::Facet(if wv.dot(&towards_f1) < 0.0 { f1 } else { f0 }))
            }
        }
    }

    /// Trace the meridian of `v` through `x` backwards (towards u_V), and on upstream through
    /// transverse arcs, recording every (cone, point) it passes. `on`: the edges `x` lies on.
    fn trace_back(&self, v: u32, x: Vec3, on: [u32; 2], out: &mut Vec<(u32, Vec3)>) {
        let (mut v, mut x, mut on) = (v, x, on);
        for _ in 0..self.max_steps {
            let vi = v as usize;
            let (u, wv) = (self.u[vi], self.w[vi]);
            // The backward ray enters the cone only if it does not cross the arcs x lies on.
            if on.iter().any(|&e| e != NONE && (wv - self.w[self.other(e, v) as usize]).dot(&u) < 0.0) {
                return;
            }
            out.push((v, x));
            let xu = x.dot(&u);
            if !(xu > 0.0) {
                return;
            }
            // Gnomonic line u + s·y0, s from 1 (at x) down to 0 (at u_V).
            let y0 = x / xu - u;
            let mut best: Option<(f64, u32)> = None;
            for &e in &self.vertex_edges[vi] {
                if on.contains(&e) {
                    continue;
                }
                let m = wv - self.w[self.other(e, v) as usize];
                let (mu, my) = (m.dot(&u), m.dot(&y0));
                if mu >= 0.0 || !(my > 0.0) {
                    continue;
                }
                let s = -mu / my;
                if best.is_none_or(|(bs, be)| s > bs || (s == bs && e < be)) {
                    best = Some((s, e));
                }
            }
            let Some((s, e)) = best else { return }; // reached u_V: V is a maximum of h
            let x1 = (u + y0 * s).normalize();
            if self.corner_of(e, &x1).is_some() {
                return; // a corner: its own backward meridians are traced separately
            }
            match self.arc[e as usize] {
                ArcKind::Cross(k) if self.edge_vertices[e as usize][k as usize] != v => {
                    v = self.other(e, v);
                    x = x1;
                    on = [e, NONE];
                }
                _ => return,
            }
        }
    }

    /// Basin areas of the stable facets (see the module docs).
    pub fn basins(&self) -> QuasiStatic {
        let nv = self.w.len();
        // Sources of separatrices: every corner of every cone, every u_P on its arc.
        let mut sources: Vec<(u32, Vec3, [u32; 2])> = Vec::new();
        for (f, vs) in self.facet_vertices.iter().enumerate() {
            let k_n = vs.len();
            for (k, &v) in vs.iter().enumerate() {
                let on = [self.facet_edges[f][k], self.facet_edges[f][(k + k_n - 1) % k_n]];
                sources.push((v, self.normal[f], on));
            }
        }
        for (e, p) in self.foot.iter().enumerate() {
            let pn = p.norm();
            if !(pn > 0.0) {
                continue;
            }
            let up = p / pn;
            let [f0, f1] = self.edge_facets[e];
            if up.dot(&(self.normal[f0 as usize] + self.normal[f1 as usize])) <= 0.0
                || self.corner_of(e as u32, &up).is_some()
            {
                continue;
            }
            for v in self.edge_vertices[e] {
                sources.push((v, up, [e as u32, NONE]));
            }
        }
        let traced: Vec<Vec<(u32, Vec3)>> = sources
            .par_iter()
            .map(|&(v, x, on)| {
                let mut out = Vec::new();
                self.trace_back(v, x, on, &mut out);
                out
            })
            .collect();
        let frames: Vec<(Vec3, Vec3)> = self.u.iter().map(frame).collect();
        let mut angles: Vec<Vec<f64>> = vec![Vec::new(); nv];
        for (v, x) in traced.into_iter().flatten() {
            if let Some(a) = angle(&frames[v as usize], &x) {
                angles[v as usize].push(a);
            }
        }
        let cones: Vec<ConeResult> =
            angles.into_par_iter().enumerate().map(|(v, a)| self.cone_basins(v as u32, &frames[v], a)).collect();
        let mut area = vec![0.0; self.normal.len()];
        let (mut unresolved, mut failed, mut sectors, mut refined) = (0.0, 0.0, 0usize, 0usize);
        for c in &cones {
            for &(f, a) in &c.areas {
                area[f as usize] += a;
            }
            unresolved += c.unresolved;
            failed += c.failed;
            sectors += c.sectors;
            refined += c.refined;
        }
        let total: f64 = area.iter().sum();
        let sphere = 4.0 * PI;
        let facet_probability = area.iter().map(|a| if total > 0.0 { a / total } else { 0.0 }).collect();
        let error = (unresolved + failed) / sphere + (total / sphere - 1.0).abs() + 1e-12;
        QuasiStatic {
            facet_probability,
            error,
            method: format!(
                "exact: normal cones of the hull corners cut along separatrix meridians into {sectors} spherical \
                 sectors, each labelled by an exact quasi-static descent ({refined} sectors re-bisected by the \
                 consistency check, unresolved area {:.1e} of 4π, failed descents {:.1e} of 4π, total area 4π·{:.15})",
                unresolved / sphere,
                failed / sphere,
                total / sphere
            ),
        }
    }

    /// The sectors of the cone of `v` between consecutive separatrix angles `angles`.
    fn cone_basins(&self, v: u32, fr: &(Vec3, Vec3), mut angles: Vec<f64>) -> ConeResult {
        let corners: Vec<Vec3> = self.cones[v as usize].iter().map(|&f| self.normal[f as usize]).collect();
        angles.extend(corners.iter().filter_map(|c| angle(fr, c)));
        angles.sort_by(f64::total_cmp);
        angles.dedup_by(|a, b| (*a - *b).abs() < 1e-15);
        if angles.is_empty() {
            angles.push(0.0);
        }
        // No gap above π/2 (the wedge clip needs < π).
        let mut all = Vec::with_capacity(angles.len() + 4);
        for (i, &a) in angles.iter().enumerate() {
            let next = if i + 1 < angles.len() { angles[i + 1] } else { angles[0] + 2.0 * PI };
            all.push(a);
            let pieces = ((next - a) / (0.5 * PI)).ceil().max(1.0) as usize;
            for j in 1..pieces {
                all.push(a + (next - a) * j as f64 / pieces as f64);
            }
        }
        let mut res = ConeResult::default();
        let cone = Cone { v, corners: &corners, fr };
        for i in 0..all.len() {
            let next = if i + 1 < all.len() { all[i + 1] } else { all[0] + 2.0 * PI };
            self.sector(&cone, all[i], next, 0, None, &mut res);
        }
        res
    }

    /// Label the sector [a1, a2] of a cone (with a consistency check and bisection).
    fn sector(&self, cone: &Cone, a1: f64, a2: f64, depth: u32, known: Option<u32>, res: &mut ConeResult) {
        let Some((area, centre)) = cone.piece(a1, a2) else { return };
        res.sectors += usize::from(depth == 0);
        let label = match known {
            Some(l) => Some(l),
            None => self.descend(cone.v, centre, None).ok(),
        };
        let mid = 0.5 * (a1 + a2);
        let half = |lo: f64, hi: f64| cone.piece(lo, hi).map(|(_, c)| self.descend(cone.v, c, None).ok());
        let (left, right) = (half(a1, mid), half(mid, a2));
        // A half that is empty agrees; a half whose descent failed does not.
        let agrees = |h: &Option<Option<u32>>| h.is_none_or(|l| l.is_some() && l == label);
        if let Some(l) = label.filter(|_| agrees(&left) && agrees(&right)) {
            res.areas.push((l, area));
        } else if depth < MAX_REFINE && mid > a1 && mid < a2 {
            res.refined += usize::from(depth == 0);
            self.sector(cone, a1, mid, depth + 1, left.flatten(), res);
            self.sector(cone, mid, a2, depth + 1, right.flatten(), res);
        } else if let Some(l) = label {
            res.areas.push((l, area));
            res.unresolved += area;
        } else {
            res.failed += area;
        }
    }
}

/// `d` normalised, or an error for a zero or non-finite vector.
fn unit(d: &Vec3) -> Result<Vec3> {
    let n = d.norm();
    if n > 0.0 && n.is_finite() {
        Ok(d / n)
    } else {
        Err(Error::Usage(format!("a down direction must be a finite non-zero vector, not {d:?}")))
    }
}

/// Angle of `x` around u in the frame (p1, p2); `None` at u itself.
fn angle(fr: &(Vec3, Vec3), x: &Vec3) -> Option<f64> {
    let (c, s) = (x.dot(&fr.0), x.dot(&fr.1));
    (c.hypot(s) > 1e-15).then(|| s.atan2(c))
}

/// The facets around corner `v` in cyclic order.
fn cone_facets(poly: &Polyhedron, v: u32) -> Vec<u32> {
    let edges = &poly.vertex_edges[v as usize];
    let Some(&e0) = edges.first() else { return Vec::new() };
    let start = poly.edges[e0 as usize].facets[0];
    let mut out = Vec::with_capacity(edges.len());
    let mut f = start;
    for _ in 0..edges.len() {
        out.push(f);
        let facet = &poly.facets[f as usize];
        let n = facet.vertices.len();
        let Some(k) = facet.vertices.iter().position(|&x| x == v) else { break };
        let ed = &poly.edges[facet.edges[(k + n - 1) % n] as usize];
        f = if ed.facets[0] == f { ed.facets[1] } else { ed.facets[0] };
        if f == start {
            break;
        }
    }
    out
}

/// Per-cone output of [`SupportFlow::basins`].
#[derive(Default)]
struct ConeResult {
    areas: Vec<(u32, f64)>,
    unresolved: f64,
    failed: f64,
    sectors: usize,
    refined: usize,
}

/// A vertex cone as a convex spherical polygon, with the frame around u_V.
struct Cone<'a> {
    v: u32,
    corners: &'a [Vec3],
    fr: &'a (Vec3, Vec3),
}

impl Cone<'_> {
    /// Area and centroid direction of the cone ∩ the wedge of angles [a1, a2] (a2 − a1 < π).
    fn piece(&self, a1: f64, a2: f64) -> Option<(f64, Vec3)> {
        let (p1, p2) = *self.fr;
        // n(α)·x = ρ sin(φ − α) ≥ 0 ⇔ φ ∈ [α, α + π]
        let n = |a: f64| p2 * a.cos() - p1 * a.sin();
        let mut poly = clip(self.corners, &n(a1));
        poly = clip(&poly, &-n(a2));
        if poly.len() < 3 {
            return None;
        }
        let area = spherical_area(&poly);
        let centre = poly.iter().sum::<Vec3>().normalize();
        (area > 0.0 && centre.iter().all(|c| c.is_finite())).then_some((area, centre))
    }
}

/// Clip a convex spherical polygon (unit vectors, minor arcs) to the hemisphere m·x ≥ 0.
fn clip(poly: &[Vec3], m: &Vec3) -> Vec<Vec3> {
    let n = poly.len();
    let mut out = Vec::with_capacity(n + 2);
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        let (dp, dq) = (m.dot(&p), m.dot(&q));
        if dp >= 0.0 {
            out.push(p);
        }
        if (dp >= 0.0) != (dq >= 0.0) {
            let x = q * dp - p * dq;
            let x = if dp >= 0.0 { x } else { -x };
            let len = x.norm();
            if len > 0.0 {
                out.push(x / len);
            }
        }
    }
    out
}

/// Area of a convex spherical polygon: fan of triangles, each by Van Oosterom–Strackee.
fn spherical_area(poly: &[Vec3]) -> f64 {
    let a = poly[0];
    let mut s = 0.0;
    for k in 1..poly.len() - 1 {
        let (b, c) = (poly[k], poly[k + 1]);
        s += 2.0 * a.dot(&b.cross(&c)).atan2(1.0 + a.dot(&b) + b.dot(&c) + c.dot(&a));
    }
    s.abs()
}

/// The quasi-static resting probabilities: basin areas of the stable facets / 4π.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct QuasiStatic {
    /// Per hull facet; 0 for facets that are not stable; sums to 1.
    pub facet_probability: Vec<f64>,
    /// Bound on the absolute error of every entry (and of their sum), see the module docs.
    pub error: f64,
    /// How the numbers were obtained.
    pub method: String,
}

/// Quasi-static basin probabilities of the stable facets of `poly` (SPEC §6 "Static reference").
pub fn basin_probabilities(poly: &Polyhedron, g: &Point3, eq: &Equilibria) -> QuasiStatic {
    SupportFlow::new(poly, g, eq).basins()
}

/// Sum the facet probabilities per flock: `membership` = flock id per equilibrium index (as
/// [`crate::hierarchy::Flocks::membership`]), `n_flocks` the number of flocks.
pub fn flock_probabilities(q: &QuasiStatic, eq: &Equilibria, membership: &[usize], n_flocks: usize) -> Vec<f64> {
    let mut out = vec![0.0; n_flocks];
    for (f, &p) in q.facet_probability.iter().enumerate() {
        if let Some(Some(i)) = eq.at_facet.get(f) {
            if let Some(&k) = membership.get(*i as usize) {
                if k < n_flocks {
                    out[k] += p;
                }
            }
        }
    }
    out
}

/// The final stable facet of the quasi-static descent from down direction `d`. Builds the
/// equilibria (default degeneracy tolerance) and the flow on each call; for many directions build
/// a [`SupportFlow`] (or a [`MergeTree`]) once.
///
/// # Panics
///
/// If `d` is zero or not finite, if the equilibria of `poly` and `g` violate Poincaré–Hopf (a
/// degenerate input, see [`Equilibria::new`]), or if the descent exceeds its step cap (a bug).
/// [`try_settle`] returns these as errors instead.
pub fn settle(poly: &Polyhedron, g: &Point3, d: &Vec3) -> u32 {
    try_settle(poly, g, d).unwrap_or_else(|e| panic!("quasi-static descent from {d:?}: {e}"))
}

/// [`settle`] with its failures as errors.
pub fn try_settle(poly: &Polyhedron, g: &Point3, d: &Vec3) -> Result<u32> {
    let eq = Equilibria::new(poly, g, crate::equilibria::DEFAULT_DEGENERACY_TOL)?;
    SupportFlow::new(poly, g, &eq).settle(d)
}

/// One node of the [`MergeTree`].
#[derive(Clone, Debug, Serialize)]
pub struct MergeNode {
    /// h(n_F) for a facet leaf; the weight of the arc that joined the children otherwise.
    pub level: f64,
    pub parent: Option<u32>,
    pub children: Option<[u32; 2]>,
    /// Number of stable facets below (or at) this node.
    pub stable: u32,
}

/// The merge tree of the sublevel sets of h (see the module docs): leaves 0..F are the facets,
/// internal nodes follow in order of creation (non-decreasing level).
#[derive(Clone, Debug)]
pub struct MergeTree {
    flow: SupportFlow,
    nodes: Vec<MergeNode>,
    /// Stable facets in depth-first leaf order; node k covers `stable_order[range[k].0..range[k].1]`.
    stable_order: Vec<u32>,
    range: Vec<(u32, u32)>,
    /// Per facet: the level of its lowest ancestor with ≥ 2 stable facets (∞ if none).
    solo_until: Vec<f64>,
    /// Binary-lifting ancestor tables: up[k][x] = 2^k-th ancestor (NONE above the root).
    up: Vec<Vec<u32>>,
    depth: Vec<u32>,
}

impl MergeTree {
    /// Build the flow of h and the merge tree of its sublevel sets.
    pub fn new(poly: &Polyhedron, g: &Point3, eq: &Equilibria) -> Self {
        Self::from_flow(SupportFlow::new(poly, g, eq))
    }

    /// The merge tree of an existing flow.
    pub fn from_flow(flow: SupportFlow) -> Self {
        let nf = flow.facets();
        let mut nodes: Vec<MergeNode> = (0..nf as u32)
            .map(|f| MergeNode {
                level: flow.facet_height(f),
                parent: None,
                children: None,
                stable: u32::from(flow.is_stable(f)),
            })
            .collect();
        let mut arcs: Vec<(f64, u32)> = (0..flow.edge_facets.len() as u32).map(|e| (flow.arc_max(e), e)).collect();
        arcs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut dsu: Vec<u32> = (0..nf as u32).collect();
        let mut top: Vec<u32> = (0..nf as u32).collect();
        let find = |dsu: &mut Vec<u32>, mut x: u32| {
            while dsu[x as usize] != x {
                let p = dsu[dsu[x as usize] as usize];
                dsu[x as usize] = p;
                x = p;
            }
            x
        };
        for (weight, e) in arcs {
            let [f0, f1] = flow.edge_facets[e as usize];
            let (r0, r1) = (find(&mut dsu, f0), find(&mut dsu, f1));
            if r0 == r1 {
                continue;
            }
            let (a, b) = (top[r0 as usize], top[r1 as usize]);
            let id = nodes.len() as u32;
            let level = weight.max(nodes[a as usize].level).max(nodes[b as usize].level);
            let stable = nodes[a as usize].stable + nodes[b as usize].stable;
            nodes.push(MergeNode { level, parent: None, children: Some([a, b]), stable });
            nodes[a as usize].parent = Some(id);
            nodes[b as usize].parent = Some(id);
            dsu[r0 as usize] = r1;
            top[r1 as usize] = id;
        }
        let n = nodes.len();
        // Depth-first leaf order (children before parents in index order, so roots are last).
        let mut stable_order = Vec::new();
        let mut range = vec![(0u32, 0u32); n];
        let mut depth = vec![0u32; n];
        for root in (0..n).rev().filter(|&i| nodes[i].parent.is_none()) {
            let mut stack = vec![(root as u32, false)];
            while let Some((x, done)) = stack.pop() {
                let xi = x as usize;
                if done {
                    range[xi].1 = stable_order.len() as u32;
                    continue;
                }
                range[xi].0 = stable_order.len() as u32;
                stack.push((x, true));
                match nodes[xi].children {
                    Some([a, b]) => {
                        depth[a as usize] = depth[xi] + 1;
                        depth[b as usize] = depth[xi] + 1;
                        stack.push((b, false));
                        stack.push((a, false));
                    }
                    None => {
                        if nodes[xi].stable > 0 {
                            stable_order.push(x);
                        }
                    }
                }
            }
        }
        // first2[x]: level of the lowest ancestor-or-self of x with ≥ 2 stable facets.
        let mut first2 = vec![f64::INFINITY; n];
        for x in (0..n).rev() {
            first2[x] = if nodes[x].stable >= 2 {
                nodes[x].level
            } else {
                nodes[x].parent.map_or(f64::INFINITY, |p| first2[p as usize])
            };
        }
        let solo_until = (0..nf).map(|f| nodes[f].parent.map_or(f64::INFINITY, |p| first2[p as usize])).collect();
        let mut up = vec![nodes.iter().map(|x| x.parent.unwrap_or(NONE)).collect::<Vec<u32>>()];
        while up.len() < 40 && up.last().unwrap().iter().any(|&p| p != NONE) {
            let prev = up.last().unwrap();
            let next = prev.iter().map(|&p| if p == NONE { NONE } else { prev[p as usize] }).collect();
            up.push(next);
        }
        MergeTree { flow, nodes, stable_order, range, solo_until, up, depth }
    }

    /// The flow of h the tree was built from.
    pub fn flow(&self) -> &SupportFlow {
        &self.flow
    }

    /// All nodes: facets 0..F first, then the merges in order.
    pub fn nodes(&self) -> &[MergeNode] {
        &self.nodes
    }

    /// The stable facets below `node`.
    pub fn stable_below(&self, node: u32) -> &[u32] {
        let (a, b) = self.range[node as usize];
        &self.stable_order[a as usize..b as usize]
    }

    /// For a stable facet: the lowest level at which its sublevel component holds another stable
    /// facet (a body resting there with less energy than this can only come back to it); ∞ if
    /// it is the only stable facet.
    pub fn unique_level(&self, facet: u32) -> f64 {
        self.solo_until[facet as usize]
    }

    /// The highest ancestor-or-self of `x` with level ≤ `level`.
    fn ancestor_at(&self, mut x: u32, level: f64) -> u32 {
        for k in (0..self.up.len()).rev() {
            let a = self.up[k][x as usize];
            if a != NONE && self.nodes[a as usize].level <= level {
                x = a;
            }
        }
        x
    }

    /// The descent's facet and the level actually used (raised to h(d) if below it).
    fn start(&self, d: &Vec3, level: f64) -> Option<(u32, f64)> {
        if !level.is_finite() {
            return None;
        }
        let (f, h) = self.flow.settle_with_height(d).ok()?;
        Some((f, level.max(h)))
    }

    /// The final stable facet of a passive body with down direction `d` and energy level
    /// `level` = E/(m g) (kinetic energy/(m g) + height of G above the ground, mesh units), if
    /// the component of {h ≤ level} containing `d` holds exactly one stable facet; else `None`.
    pub fn decided(&self, d: &Vec3, level: f64) -> Option<u32> {
        let (f, l) = self.start(d, level)?;
        (l < self.solo_until[f as usize]).then_some(f)
    }

    /// The final flock, if every stable facet of the component of {h ≤ level} containing `d` is
    /// in the same flock (`facet_flock` per facet; `None` entries never decide).
    pub fn decided_flock(&self, d: &Vec3, level: f64, facet_flock: &[Option<usize>]) -> Option<usize> {
        let (f, l) = self.start(d, level)?;
        let own = (*facet_flock.get(f as usize)?)?;
        if l < self.solo_until[f as usize] {
            return Some(own);
        }
        let node = self.ancestor_at(f, l);
        self.stable_below(node)
            .iter()
            .all(|&s| facet_flock.get(s as usize).copied().flatten() == Some(own))
            .then_some(own)
    }

    /// The merge level of two facets (their lowest common ancestor): the lowest energy level at
    /// which a body resting near `from_facet` could reach `to_facet`. h(n_F) for F = F; ∞ if
    /// they are never joined.
    pub fn entry_barrier(&self, from_facet: u32, to_facet: u32) -> f64 {
        let (mut a, mut b) = (from_facet, to_facet);
        if self.depth[a as usize] < self.depth[b as usize] {
            std::mem::swap(&mut a, &mut b);
        }
        let diff = self.depth[a as usize] - self.depth[b as usize];
        for k in 0..self.up.len() {
            if diff >> k & 1 == 1 {
                a = self.up[k][a as usize];
            }
        }
        if a != b {
            for k in (0..self.up.len()).rev() {
                let (pa, pb) = (self.up[k][a as usize], self.up[k][b as usize]);
                if pa != pb {
                    a = pa;
                    b = pb;
                }
            }
            a = self.up[0][a as usize];
            b = self.up[0][b as usize];
            if a != b || a == NONE {
                return f64::INFINITY;
            }
        }
        self.nodes[a as usize].level
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::{cuboid, platonic, Platonic};
    use crate::hull::DEFAULT_COPLANAR_TOL;
    use crate::mesh::TriMesh;
    use crate::solid::MassProperties;

    fn setup(mesh: TriMesh) -> (Polyhedron, Point3, Equilibria) {
        let (mesh, _) = mesh.into_solid_boundary().unwrap();
        let g = MassProperties::of(&mesh).unwrap().center_of_mass;
        let poly = Polyhedron::new(&mesh.vertices, DEFAULT_COPLANAR_TOL).unwrap();
        let eq = Equilibria::new(&poly, &g, crate::equilibria::DEFAULT_DEGENERACY_TOL).unwrap();
        (poly, g, eq)
    }

    fn facet_towards(poly: &Polyhedron, d: Vec3) -> u32 {
        (0..poly.facets.len())
            .max_by(|&a, &b| poly.facets[a].normal.dot(&d).total_cmp(&poly.facets[b].normal.dot(&d)))
            .unwrap() as u32
    }

    #[test]
    fn box_edges_are_valleys_and_descent_ends_on_the_dominant_face() {
        let (poly, g, eq) = setup(cuboid(2.0, 1.5, 1.0));
        let flow = SupportFlow::new(&poly, &g, &eq);
        assert!(flow.arc.iter().all(|&k| k == ArcKind::Valley), "G at the centre: every foot at an edge midpoint");
        // Near a face normal the descent ends on that face; on an exact normal too.
        for d in [Vec3::x(), -Vec3::y(), Vec3::z(), Vec3::new(1.0, 0.1, -0.05), Vec3::new(0.05, -0.1, 1.0)] {
            assert_eq!(flow.settle(&d).unwrap(), facet_towards(&poly, d), "{d:?}");
        }
        // h decreases along the path, which ends at the facet's normal.
        let (f, path) = flow.settle_path(&Vec3::new(0.9, 0.8, 0.7)).unwrap();
        let hs: Vec<f64> = path.iter().map(|p| flow.h(p)).collect();
        assert!(hs.windows(2).all(|w| w[1] <= w[0] + 1e-12), "{hs:?}");
        assert!((path.last().unwrap() - poly.facets[f as usize].normal).norm() < 1e-12);
    }

    #[test]
    fn support_vertex_hill_climb_matches_a_scan() {
        let (poly, g, eq) = setup(platonic(Platonic::Icosahedron));
        let flow = SupportFlow::new(&poly, &g, &eq);
        for d in crate::rng::fibonacci_sphere(200) {
            let scan = (0..poly.vertices.len()).map(|v| (poly.vertices[v] - g).dot(&d)).fold(f64::MIN, f64::max);
            assert!((flow.w[flow.support_vertex(&d) as usize].dot(&d) - scan).abs() < 1e-14);
        }
    }

    #[test]
    fn clipping_and_areas_of_the_octant() {
        let oct = [Vec3::x(), Vec3::y(), Vec3::z()];
        assert!((spherical_area(&oct) - PI / 2.0).abs() < 1e-15);
        let half = clip(&oct, &Vec3::new(1.0, -1.0, 0.0).normalize());
        assert!((spherical_area(&half) - PI / 4.0).abs() < 1e-15);
        assert!(clip(&oct, &-Vec3::x()).len() < 3 || spherical_area(&clip(&oct, &-Vec3::x())) < 1e-15);
    }

    #[test]
    fn cube_sectors_split_at_corners_and_saddles() {
        let (poly, g, eq) = setup(cuboid(2.0, 2.0, 2.0));
        let q = basin_probabilities(&poly, &g, &eq);
        for p in &q.facet_probability {
            assert!((p - 1.0 / 6.0).abs() < 1e-12, "{:?}", q.facet_probability);
        }
        assert!(q.error < 1e-11, "{}", q.error);
        assert!(q.method.contains("48 spherical sectors"), "{}", q.method);
    }

    #[test]
    fn merge_tree_of_the_cube() {
        let (poly, g, eq) = setup(cuboid(2.0, 2.0, 2.0));
        let t = MergeTree::new(&poly, &g, &eq);
        // Arcs peak at the saddles: h = √2 (edge midpoints); faces at h = 1.
        for f in 0..6 {
            assert!((t.entry_barrier(f, f) - 1.0).abs() < 1e-12);
            assert!((t.unique_level(f) - 2f64.sqrt()).abs() < 1e-12);
            let n = poly.facets[f as usize].normal;
            assert_eq!(t.decided(&n, 1.2), Some(f));
            assert_eq!(t.decided(&n, 1.5), None);
        }
        assert_eq!(t.nodes().len(), 11);
        assert_eq!(t.stable_below(10).len(), 6);
    }
}
