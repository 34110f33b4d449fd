//! The ν-hierarchy of a Morse–Smale graph, its scales, flocks and rocking equilibria (paper
//! §2.2.3). Generic: the 3D graph of a hull ([`crate::morse_smale`]) and the planar
//! cycle of a polygon ([`crate::planar`]) both produce a [`Hierarchy`], and every question
//! asked of it — S(ν), U(ν), H(ν), N(ν), the staircase n(ν), the plateau, the flocks — is
//! answered here, once, for both.
//!
//! # The data
//!
//! A [`Hierarchy`] is the original graph G(0) (its critical points, [`Node`], and its arcs)
//! plus the sequence of [`Cancellation`]s chosen by the caller (cheapest valid arc first). Each
//! cancellation removes two nodes and carries its `weight` v = |R_i − R_j| / R_max and its
//! `level`, the running maximum of the weights so far. G(ν) is G(0) with **every cancellation of
//! level < ν applied**; since levels are non-decreasing, G(ν) is a prefix of the sequence, found
//! by binary search, so N(ν) = N(0) − 2·#{level < ν} is instant for any ν. (In 2D, cheapest-first
//! cancellation on a cycle already has non-decreasing weights; in 3D it need not, hence the
//! running maximum.) Invariants, checked by [`Hierarchy::check`]: S + U − H = 2 after every
//! step when the graph has saddles (3D), S = U when it has none (2D); N(ν) non-increasing;
//! never fewer than one stable and one unstable node.
//!
//! # The staircase
//!
//! N(ν) is piecewise constant. [`Hierarchy::staircase`] returns its steps: the first is
//! [0, ν₁] with N(0) (ν₁ the first level), then one step per distinct level L, from L to the
//! next level (the last one to v_max = (R_max − R_min)/R_max, R_min the smallest node R).
//! Because G(ν) applies cancellations with level **strictly** below ν, a step's counts hold for
//! nu_lo < ν ≤ nu_hi (the endpoints are measure zero for every use here).
//!
//! The macro scale is read in [`plateau`], the flocks in [`flocks`]; G(0) and its cancellation
//! sequence are built in [`cancellation`].

mod cancellation;
mod flocks;
mod plateau;
#[cfg(test)]
mod tests;

pub use crate::equilibria::Kind;
pub use cancellation::cancellation_hierarchy;
pub use flocks::{Flock, Flocks};
pub use plateau::{
    macro_nu, MacroScale, NuSource, Plateau, LEVEL_RESOLUTION, PAPER_NU, PLATEAU_MACRO_FRACTION, PLATEAU_MIN_CLARITY,
    PLATEAU_MIN_DECADES,
};
use serde::Serialize;

/// A critical point of R in G(0).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Node {
    /// Stable, unstable or saddle.
    pub kind: Kind,
    /// R: distance from G to the point.
    pub r: f64,
}

/// One cancellation of the hierarchy: two nodes leave the graph.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Cancellation {
    /// v = |R_i − R_j| / R_max of the arc cancelled.
    pub weight: f64,
    /// Running maximum of `weight` over the sequence so far: the ν above which (ν > level) this
    /// cancellation has happened. Non-decreasing.
    pub level: f64,
    /// The two nodes removed (3D: [saddle, extremum]; 2D: [stable, unstable]).
    pub removed: [usize; 2],
}

/// Numbers of stable, unstable and saddle points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Counts {
    /// Number of stable points (S).
    pub stable: usize,
    /// Number of unstable points (U).
    pub unstable: usize,
    /// Number of saddle points (H).
    pub saddle: usize,
}

impl Counts {
    /// N = S + U + H.
    pub fn total(&self) -> usize {
        self.stable + self.unstable + self.saddle
    }

    fn add(&mut self, kind: Kind, delta: isize) {
        let c = match kind {
            Kind::Stable => &mut self.stable,
            Kind::Unstable => &mut self.unstable,
            Kind::Saddle => &mut self.saddle,
        };
        *c = c.checked_add_signed(delta).expect("count went negative");
    }
}

/// One step of the piecewise-constant N(ν): the counts hold for nu_lo < ν ≤ nu_hi (and at ν = 0
/// for the first step).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Step {
    /// Lower end of the ν interval (exclusive).
    pub nu_lo: f64,
    /// Upper end of the ν interval (inclusive).
    pub nu_hi: f64,
    /// Counts of G(ν) on the step.
    pub counts: Counts,
    /// n = N/N(0).
    pub n: f64,
}

/// G(0), the cancellation sequence, and everything that can be read from them.
#[derive(Clone, Debug, Serialize)]
pub struct Hierarchy {
    /// Nodes of G(0): the micro-equilibria.
    pub nodes: Vec<Node>,
    /// Arcs of the original graph G(0) (node pairs; multi-arcs may repeat).
    pub arcs: Vec<(usize, usize)>,
    /// Largest distance from G to a hull vertex / polygon vertex.
    pub r_max: f64,
    /// The cancellation sequence, in the order the cancellations happen.
    pub cancellations: Vec<Cancellation>,
}

impl Hierarchy {
    /// |r_a − r_b| / r_max.
    pub fn weight(&self, a: usize, b: usize) -> f64 {
        (self.nodes[a].r - self.nodes[b].r).abs() / self.r_max
    }

    /// R_min: the smallest R over the nodes (a stable point).
    pub fn r_min(&self) -> f64 {
        self.nodes.iter().map(|n| n.r).fold(f64::INFINITY, f64::min)
    }

    /// v_max = (R_max − R_min) / R_max: no arc weight exceeds it.
    pub fn v_max(&self) -> f64 {
        (self.r_max - self.r_min()) / self.r_max
    }

    /// Number of cancellations applied in G(ν): those with level < ν (binary search).
    pub fn applied(&self, nu: f64) -> usize {
        self.cancellations.partition_point(|c| c.level < nu)
    }

    /// Counts of G(0).
    pub fn counts0(&self) -> Counts {
        let mut c = Counts::default();
        for n in &self.nodes {
            c.add(n.kind, 1);
        }
        c
    }

    /// Which nodes of G(0) are alive in G(ν).
    pub fn alive_at(&self, nu: f64) -> Vec<bool> {
        let mut alive = vec![true; self.nodes.len()];
        for c in &self.cancellations[..self.applied(nu)] {
            alive[c.removed[0]] = false;
            alive[c.removed[1]] = false;
        }
        alive
    }

    /// N(ν) = S + U + H of G(ν), in O(log n).
    pub fn total_at(&self, nu: f64) -> usize {
        self.nodes.len() - 2 * self.applied(nu)
    }

    /// n(ν) = N(ν) / N(0).
    pub fn n_at(&self, nu: f64) -> f64 {
        self.total_at(nu) as f64 / self.nodes.len() as f64
    }

    /// S(ν), U(ν), H(ν).
    pub fn counts_at(&self, nu: f64) -> Counts {
        let mut c = self.counts0();
        for cancel in &self.cancellations[..self.applied(nu)] {
            for &i in &cancel.removed {
                c.add(self.nodes[i].kind, -1);
            }
        }
        c
    }

    /// The steps of the piecewise-constant N(ν), from ν = 0 to v_max (see the module docs).
    pub fn staircase(&self) -> Vec<Step> {
        let n0 = self.nodes.len().max(1) as f64;
        let v_max = self.v_max();
        let mut counts = self.counts0();
        let mut steps = Vec::new();
        let mut lo = 0.0;
        let mut i = 0;
        while i < self.cancellations.len() {
            let level = self.cancellations[i].level;
            steps.push(Step { nu_lo: lo, nu_hi: level, counts, n: counts.total() as f64 / n0 });
            while i < self.cancellations.len() && self.cancellations[i].level == level {
                for &x in &self.cancellations[i].removed {
                    counts.add(self.nodes[x].kind, -1);
                }
                i += 1;
            }
            lo = level;
        }
        steps.push(Step { nu_lo: lo, nu_hi: v_max.max(lo), counts, n: counts.total() as f64 / n0 });
        steps
    }

    /// Verify the invariants of the module docs; the first violation is the error.
    pub fn check(&self) -> crate::Result<()> {
        let err = |s: String| Err(crate::Error::check(s));
        let n = self.nodes.len();
        if let Some(&(a, b)) = self.arcs.iter().find(|&&(a, b)| a >= n || b >= n) {
            return err(format!("arc ({a}, {b}) names a node beyond {n}"));
        }
        if !(self.r_max > 0.0) {
            return err(format!("r_max = {} is not positive", self.r_max));
        }
        let mut c = self.counts0();
        let planar = c.saddle == 0;
        let balanced = |c: &Counts| {
            if planar {
                c.stable == c.unstable
            } else {
                c.stable + c.unstable == c.saddle + 2
            }
        };
        if !balanced(&c) {
            return err(format!("G(0) unbalanced: {c:?}"));
        }
        let mut alive = vec![true; n];
        let mut level: f64 = 0.0;
        for (k, x) in self.cancellations.iter().enumerate() {
            level = level.max(x.weight);
            if x.level != level {
                return err(format!("cancellation {k}: level {} is not the running maximum {level}", x.level));
            }
            for &i in &x.removed {
                if i >= n || !alive[i] {
                    return err(format!("cancellation {k}: node {i} is not alive"));
                }
                alive[i] = false;
                c.add(self.nodes[i].kind, -1);
            }
            if !balanced(&c) || c.stable == 0 || c.unstable == 0 {
                return err(format!("after cancellation {k}: {c:?}"));
            }
        }
        Ok(())
    }
}
