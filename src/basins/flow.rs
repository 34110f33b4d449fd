//! The gradient flow of the support function h on the sphere of down directions: its
//! precomputation and the quasi-static descent (see the [module docs](super)).

use super::{ArcKind, Leave, State, SupportFlow, NONE, SEEDS, SNAP};
use crate::equilibria::Equilibria;
use crate::hull::Polyhedron;
use crate::{Error, Point3, Result, Vec3};

/// A unit vector orthogonal to the unit vector `u`, and u × it (a right-handed frame with u).
pub(super) fn frame(u: &Vec3) -> (Vec3, Vec3) {
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
        let v = self.seeds.iter().max_by(|a, b| a.0.dot(d).total_cmp(&b.0.dot(d))).map_or(0, |s| s.1);
        crate::hull::hill_climb(
            v,
            |v| self.vertex_edges[v as usize].iter().map(move |&e| self.other(e, v)),
            |x| self.w[x as usize].dot(d),
        )
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
    pub(super) fn corner_of(&self, e: u32, x: &Vec3) -> Option<u32> {
        let [f0, f1] = self.edge_facets[e as usize];
        let (n0, n1) = (self.normal[f0 as usize], self.normal[f1 as usize]);
        let axis = n0.cross(&n1);
        let (d0, d1) = ((x - n0).norm(), (x - n1).norm());
        let beyond = n0.cross(x).dot(&axis) <= 0.0 || x.cross(&n1).dot(&axis) <= 0.0;
        (beyond || d0 < SNAP || d1 < SNAP).then_some(if d0 <= d1 { f0 } else { f1 })
    }

    /// Descend from `d` in the cone of `v` to a stable facet.
    pub(super) fn descend(&self, v: u32, d: Vec3, mut path: Option<&mut Vec<Vec3>>) -> Result<u32> {
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
    pub(super) fn trace_back(&self, v: u32, x: Vec3, on: [u32; 2], out: &mut Vec<(u32, Vec3)>) {
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
}

/// `d` normalised, or an error for a zero or non-finite vector.
fn unit(d: &Vec3) -> Result<Vec3> {
    let n = d.norm();
    if n > 0.0 && n.is_finite() {
        Ok(d / n)
    } else {
        Err(Error::parameter("down", format!("{d:?}"), "a finite non-zero vector"))
    }
}

/// Angle of `x` around u in the frame (p1, p2); `None` at u itself.
pub(super) fn angle(fr: &(Vec3, Vec3), x: &Vec3) -> Option<f64> {
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

/// The final stable facet of the quasi-static descent from down direction `d`. Builds the
/// equilibria (default degeneracy tolerance) and the flow on each call; for many directions build
/// a [`SupportFlow`] (or a [`MergeTree`](super::MergeTree)) once.
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
