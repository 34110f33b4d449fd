//! The Morse–Smale graph of R on the hull (paper §2.2.2): every saddle's two stable and two
//! unstable ends. Its cancellation hierarchy is built in [`crate::hierarchy`].
//!
//! **Flow on a facet.** On facet F with q_F the projection of G onto F's plane,
//! R² = |x − q_F|² + dist(G, F)², so the gradient flow runs radially away from q_F (ascent) or
//! towards it (descent), along straight lines in the facet.
//!
//! **Flow at an edge.** For edge E between F₀ and F₁ let `s(F,E) > 0` mean that q_F lies on F's
//! side of E (see [`crate::equilibria`]). The sign does not depend on the point of E, so an
//! edge is either a *ridge* (both s > 0: both flows descend away from it, ascend into it) or
//! *transverse* (one s > 0, one s < 0). A *valley* (both s < 0) is impossible when G is
//! inside: in the plane orthogonal to E, G = α r₀ + β r₁ (α, β > 0) with both G·r₀ < 0 and
//! G·r₁ < 0 would need cos²θ > 1. Consequently a descending line crosses every edge it meets,
//! and an ascending line crosses transverse edges and slides up along ridges.
//!
//! **Vertices.** An ascending line that reaches a vertex that is not a maximum leaves along the
//! steepest admissible direction: a ridge edge along which R grows (rate −c(V→W)/R) or the
//! radial ray of a facet that lies inside the facet's corner (rate |V − q_F|/R).
//!
//! **Arcs.** From a saddle on edge E the two ascending lines run along E (a ridge) to its end
//! vertices and on; the two descending lines enter F₀ and F₁ towards q_F. Every saddle gets
//! exactly 2 stable and 2 unstable ends (possibly the same point twice: a double arc).

use crate::equilibria::{Equilibria, Signs, Site};
use crate::hull::Polyhedron;
use crate::{Error, Point3, Result, Vec3};
use serde::Serialize;

/// One integral line from a saddle to an extremum.
#[derive(Clone, Debug, Serialize)]
pub struct Arc {
    /// Index of the saddle in [`Equilibria::points`].
    pub saddle: usize,
    /// Index of the stable or unstable end.
    pub end: usize,
    /// The traced line on the hull surface, from the saddle to the end (input frame).
    pub path: Vec<Point3>,
}

/// The Morse–Smale graph G(0): four arcs per saddle (two descending, two ascending).
#[derive(Clone, Debug, Serialize)]
pub struct MorseSmaleGraph {
    /// The arcs, four per saddle (two descending, two ascending).
    pub arcs: Vec<Arc>,
}

/// The polyhedron, G and the signs of the edge predicates: what the tracer needs.
struct Tracer<'a> {
    poly: &'a Polyhedron,
    eq: &'a Equilibria,
    g: Point3,
    /// q_F: the projection of G onto each facet's plane.
    q: Vec<Point3>,
    side: &'a [[bool; 2]],
    max_steps: usize,
}

/// Where an integral line currently is.
#[derive(Clone, Copy, Debug)]
enum At {
    /// In the interior (or entering from an edge) of a facet.
    Facet {
        facet: u32,
        from_edge: Option<u32>,
    },
    Vertex(u32),
}

impl<'a> Tracer<'a> {
    fn new(poly: &'a Polyhedron, eq: &'a Equilibria, g: Point3, signs: &'a Signs) -> Self {
        let q = poly.facets.iter().map(|f| g - f.normal * (f.normal.dot(&g.coords) - f.offset)).collect();
        Tracer { poly, eq, g, q, side: &signs.side, max_steps: 4 * (poly.edges.len() + poly.vertices.len()) + 16 }
    }

    /// `s(F, E) > 0` for facet `f` of edge `e`.
    fn side_of(&self, e: u32, f: u32) -> bool {
        let ed = &self.poly.edges[e as usize];
        self.side[e as usize][usize::from(ed.facets[0] != f)]
    }

    fn other_facet(&self, e: u32, f: u32) -> u32 {
        let ed = &self.poly.edges[e as usize];
        if ed.facets[0] == f {
            ed.facets[1]
        } else {
            ed.facets[0]
        }
    }

    /// Follow the ray `x + t·u` (t > 0, u in facet f's plane) to the boundary of f, skipping
    /// the edge it came from. Returns the exit edge, the exit point and the parameter λ∈[0,1]
    /// of that point along the edge (from `vertices[0]`).
    fn exit(&self, f: u32, x: &Point3, u: &Vec3, skip: Option<u32>) -> Option<(u32, Point3, f64)> {
        let facet = &self.poly.facets[f as usize];
        let n = facet.vertices.len();
        let mut best: Option<(f64, u32)> = None;
        for k in 0..n {
            let e = facet.edges[k];
            if Some(e) == skip {
                continue;
            }
            let a = self.poly.vertices[facet.vertices[k] as usize];
            let b = self.poly.vertices[facet.vertices[(k + 1) % n] as usize];
            let m = facet.normal.cross(&(b - a)); // inward in-plane normal (unnormalised)
            let um = u.dot(&m);
            if um >= 0.0 {
                continue;
            }
            let t = ((x - a).dot(&m) / -um).max(0.0);
            if best.is_none_or(|(bt, _)| t < bt) {
                best = Some((t, e));
            }
        }
        let (t, e) = best?;
        let y = x + u * t;
        let [a, b] = self.poly.edges[e as usize].vertices.map(|v| self.poly.vertices[v as usize]);
        let lambda = ((y - a).dot(&(b - a)) / (b - a).norm_squared()).clamp(0.0, 1.0);
        Some((e, a + (b - a) * lambda, lambda))
    }

    /// Snap a point on edge e at parameter λ to an end vertex when it is (numerically) there.
    fn snap(&self, e: u32, lambda: f64) -> Option<u32> {
        let ed = &self.poly.edges[e as usize];
        let [a, b] = ed.vertices.map(|v| self.poly.vertices[v as usize]);
        let tol = 1e-12 * self.poly.diameter / (b - a).norm();
        if lambda <= tol {
            Some(ed.vertices[0])
        } else if lambda >= 1.0 - tol {
            Some(ed.vertices[1])
        } else {
            None
        }
    }

    /// Does the ray from corner v of facet f in direction u lie strictly inside f's corner?
    fn inside_corner(&self, f: u32, v: u32, u: &Vec3) -> bool {
        let facet = &self.poly.facets[f as usize];
        let n = facet.vertices.len();
        let k = facet.vertices.iter().position(|&w| w == v).expect("vertex of facet");
        let p = self.poly.vertices[v as usize];
        let next = self.poly.vertices[facet.vertices[(k + 1) % n] as usize];
        let prev = self.poly.vertices[facet.vertices[(k + n - 1) % n] as usize];
        // inward normals of the two edges at the corner
        let m_out = facet.normal.cross(&(next - p));
        let m_in = facet.normal.cross(&(p - prev));
        u.dot(&m_out) > 0.0 && u.dot(&m_in) > 0.0
    }

    /// Facets around vertex v (from its edges).
    fn facets_at(&self, v: u32) -> Vec<u32> {
        let mut fs: Vec<u32> =
            self.poly.vertex_edges[v as usize].iter().flat_map(|&e| self.poly.edges[e as usize].facets).collect();
        fs.sort_unstable();
        fs.dedup();
        fs
    }

    /// Steepest descent from vertex v: the facet whose ray towards q_F is inside its corner
    /// and steepest; `None` if there is none (a degenerate vertex).
    fn descend_from_vertex(&self, v: u32) -> Option<(u32, Vec3)> {
        let p = self.poly.vertices[v as usize];
        self.facets_at(v)
            .into_iter()
            .filter_map(|f| {
                let d = self.q[f as usize] - p;
                let len = d.norm();
                (len > 0.0 && self.inside_corner(f, v, &d)).then(|| (len, f, d / len))
            })
            .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)))
            .map(|(_, f, u)| (f, u))
    }

    /// Trace the descending line that leaves edge `e0` into facet `f0` at `start`.
    fn descend(&self, start: Point3, f0: u32, e0: Option<u32>) -> Result<(usize, Vec<Point3>)> {
        let mut path = vec![start];
        let mut at = At::Facet { facet: f0, from_edge: e0 };
        let mut x = start;
        for _ in 0..self.max_steps {
            let (f, from_edge) = match at {
                At::Facet { facet, from_edge } => (facet, from_edge),
                At::Vertex(v) => match self.descend_from_vertex(v) {
                    Some((f, _)) => (f, None),
                    None => return Err(Error::check("a descending line is stuck at a vertex")),
                },
            };
            if let Some(s) = self.eq.at_facet[f as usize] {
                path.push(self.q[f as usize]);
                return Ok((s as usize, path));
            }
            let u = (self.q[f as usize] - x).normalize();
            let skip = from_edge;
            let Some((e, y, lambda)) = self.exit(f, &x, &u, skip) else {
                return Err(Error::check("a descending line found no exit from a non-stable facet"));
            };
            path.push(y);
            x = y;
            at = match self.snap(e, lambda) {
                Some(v) => {
                    x = self.poly.vertices[v as usize];
                    At::Vertex(v)
                }
                None => At::Facet { facet: self.other_facet(e, f), from_edge: Some(e) },
            };
        }
        Err(Error::check("a descending line did not reach a stable point"))
    }

    /// Steepest ascent from vertex v (not a maximum): a ridge edge or a facet ray.
    fn ascend_from_vertex(&self, v: u32) -> Option<AscentStep> {
        let p = self.poly.vertices[v as usize];
        let rel = p - self.g;
        let mut best: Option<(f64, AscentStep)> = None;
        let mut consider = |rate: f64, step: AscentStep| {
            if rate > 0.0 && best.as_ref().is_none_or(|(r, _)| rate > *r) {
                best = Some((rate, step));
            }
        };
        for &e in &self.poly.vertex_edges[v as usize] {
            let w = self.poly.other_end(e, v);
            let t = (self.poly.vertices[w as usize] - p).normalize();
            let ridge = self.side[e as usize][0] && self.side[e as usize][1];
            if ridge {
                consider(rel.dot(&t), AscentStep::Edge(w));
            }
        }
        for f in self.facets_at(v) {
            let d = p - self.q[f as usize];
            let len = d.norm();
            if len > 0.0 && self.inside_corner(f, v, &d) {
                consider(len, AscentStep::Facet(f, d / len));
            }
        }
        best.map(|(_, s)| s).or_else(|| {
            // Degenerate fallback: the steepest edge along which R grows at all.
            self.poly.vertex_edges[v as usize]
                .iter()
                .map(|&e| (e, self.poly.other_end(e, v)))
                .map(|(e, w)| (rel.dot(&(self.poly.vertices[w as usize] - p).normalize()), e, w))
                .filter(|x| x.0 > 0.0)
                .max_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, _, w)| AscentStep::Edge(w))
        })
    }

    /// Trace the ascending line that leaves the saddle on edge `e` towards its end `towards`.
    fn ascend(&self, start: Point3, towards: u32) -> Result<(usize, Vec<Point3>)> {
        let mut path = vec![start];
        let mut v = towards;
        for _ in 0..self.max_steps {
            path.push(self.poly.vertices[v as usize]);
            if let Some(u) = self.eq.at_vertex[v as usize] {
                return Ok((u as usize, path));
            }
            match self.ascend_from_vertex(v) {
                Some(AscentStep::Edge(w)) => v = w,
                Some(AscentStep::Facet(f, u)) => {
                    v = self.ascend_in_facet(&mut path, self.poly.vertices[v as usize], f, u, None)?
                }
                None => return Err(Error::check("an ascending line is stuck at a vertex that is not a maximum")),
            }
        }
        Err(Error::check("an ascending line did not reach an unstable point"))
    }

    /// Ascend through facets from `x` in facet `f` along `u` until the line reaches a vertex
    /// (by sliding along a ridge, or by hitting it); returns that vertex.
    fn ascend_in_facet(
        &self,
        path: &mut Vec<Point3>,
        mut x: Point3,
        mut f: u32,
        mut u: Vec3,
        mut from: Option<u32>,
    ) -> Result<u32> {
        for _ in 0..self.max_steps {
            let Some((e, y, lambda)) = self.exit(f, &x, &u, from) else {
                return Err(Error::check("an ascending line found no exit from a facet"));
            };
            if let Some(v) = self.snap(e, lambda) {
                return Ok(v);
            }
            path.push(y);
            let g2 = self.other_facet(e, f);
            if self.side_of(e, g2) {
                // Ridge: slide up along the edge, away from the foot of G on its line.
                let ed = &self.poly.edges[e as usize];
                let [a, b] = ed.vertices.map(|v| self.poly.vertices[v as usize]);
                let foot = (self.g - a).dot(&(b - a)) / (b - a).norm_squared();
                return Ok(if lambda > foot { ed.vertices[1] } else { ed.vertices[0] });
            }
            // Transverse: cross into the neighbour and head away from its q.
            let d = y - self.q[g2 as usize];
            u = d.normalize();
            x = y;
            f = g2;
            from = Some(e);
        }
        Err(Error::check("an ascending line crossed too many facets"))
    }
}

enum AscentStep {
    /// Slide along a ridge edge to the given vertex.
    Edge(u32),
    /// Leave into a facet along a direction.
    Facet(u32, Vec3),
}

impl MorseSmaleGraph {
    /// Trace the four arcs of every saddle.
    pub fn trace(poly: &Polyhedron, eq: &Equilibria, g: &Point3, signs: &Signs) -> Result<Self> {
        let tracer = Tracer::new(poly, eq, *g, signs);
        let mut arcs = Vec::with_capacity(4 * eq.saddle);
        for (i, p) in eq.points.iter().enumerate() {
            let Site::Edge(e) = p.site else { continue };
            let ed = &poly.edges[e as usize];
            for f in ed.facets {
                let (end, path) = tracer.descend(p.point, f, Some(e))?;
                arcs.push(Arc { saddle: i, end, path });
            }
            for v in ed.vertices {
                let (end, path) = tracer.ascend(p.point, v)?;
                arcs.push(Arc { saddle: i, end, path });
            }
        }
        Ok(MorseSmaleGraph { arcs })
    }

    /// The stable micro-equilibrium each facet drains to: steepest descent from the facet's
    /// vertex centroid (its Morse–Smale cell, used to colour the hull by flock).
    pub fn facet_basins(poly: &Polyhedron, eq: &Equilibria, g: &Point3, signs: &Signs) -> Vec<Option<usize>> {
        let tracer = Tracer::new(poly, eq, *g, signs);
        poly.facets
            .iter()
            .enumerate()
            .map(|(f, facet)| {
                let c = facet.vertices.iter().map(|&v| poly.vertices[v as usize].coords).sum::<Vec3>()
                    / facet.vertices.len() as f64;
                tracer.descend(Point3::from(c), f as u32, None).ok().map(|(s, _)| s)
            })
            .collect()
    }

    /// The arcs' ends of saddle `h` (`[stable, stable, unstable, unstable]` by arc order).
    pub fn ends(&self) -> Vec<(usize, usize)> {
        self.arcs.iter().map(|a| (a.saddle, a.end)).collect()
    }
}
