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
//! # The plateau rule (automatic macro scale)
//!
//! The paper reads the macro scale off "a sudden jump followed by a plateau" of n(ν). The rule:
//!
//! 1. **Candidates** are the steps above the micro scale that reach the macro scale: steps
//!    [lo, hi] starting at a cancellation level (lo ≥ ν₁, lo > 0), ending at most at v_max, and
//!    with hi ≥ [`PLATEAU_MACRO_FRACTION`] · v_max (1 % of the total relief: a plateau is ended by
//!    the cancellation of a macro-equilibrium, not by another micro one). The **terminal** step
//!    (S = U = 1, H = 0, the topological minimum every hierarchy ends in) is not a candidate.
//! 2. The length of a step is log10(hi/lo), in decades; steps between levels equal up to
//!    rounding (relative difference ≤ [`LEVEL_RESOLUTION`]) have length 0.
//! 3. The **plateau** is the longest candidate (ties: the lower one), reported as a [`Plateau`]
//!    with its range, `decades`, counts and `clarity` = decades / decades of the second-longest
//!    candidate (∞ if there is none or it has zero length; serialised as `null`).
//!    `clear` = decades ≥ [`PLATEAU_MIN_DECADES`] (0.5) **and** clarity ≥
//!    [`PLATEAU_MIN_CLARITY`] (2): a long run of constant N, at least twice as long as any other.
//!    Its representative ν is the geometric midpoint [`Plateau::nu`] = √(lo·hi).
//! 4. If no candidate has positive length (G(0) has no micro scale: e.g. an ellipse polygon fine
//!    enough to have exactly its 2 + 2 smooth equilibria, a regular polygon whose cancellations
//!    all tie), **G(0) is its own macro scale**: the plateau is the first step [0, ν₁], with
//!    decades = clarity = ∞, clear, and ν = 0. A hierarchy without any cancellation has no plateau
//!    (`None`).
//!
//! Why not simply "the longest step above ν₁"? The lowest levels are a few extreme order
//! statistics of the micro weights (the flattest spots) and are sparse in log ν: the step between
//! the first two levels, with almost every micro-equilibrium still present, often spans 1–3
//! decades. Measured: on polygons inscribed in a circle with 100–1000 random vertices (the planar
//! sphere-like body) such steps came out as "clear" plateaus for 7–11 of 20 polygons, and on
//! noisy triaxial ellipsoids they beat the real (2, 2, 2) plateau's clarity. Requiring the
//! plateau to end at the macro scale removes them (0 of 20 circle-like polygons with ≥ 100
//! vertices and ≤ 1 % noise; see `tests/planar.rs`), while keeping plateaus that follow only a
//! couple of micro cancellations (a noisy box: 2 micro and 12 macro cancellations). A rule
//! "above the median level" was tried and rejected for that reason. The terminal step is
//! excluded because its length measures only how far the last surviving pair is from v_max, not
//! a separation of scales, and no homogeneous planar body (nor any pebble) has S = U = 1 at the
//! macro scale. Macro-equilibria whose cancellation costs less than 1 % of v_max are read as
//! micro. A body without separated scales gets `clear = false`, and callers must say so rather
//! than read flocks off it as if they were real.
//!
//! # The flock rule
//!
//! At a given ν, the survivors (alive nodes of G(ν)) are the macro-equilibria. Every node of
//! G(0) is assigned to exactly one survivor by a multi-source **bottleneck (minimax)
//! assignment over the original arcs**: process the arcs of G(0) in increasing weight (ties by
//! (min index, max index)), uniting their endpoints' components (union–find), but never merging
//! two components that both already contain a survivor. When all arcs are processed every
//! component contains exactly one survivor (G(0) is connected: any component without one would
//! have been merged through the arc that leaves it), and that survivor's kind is the flock's type
//! (stable, unstable or saddle flock). Equivalently, a node belongs to the survivor it reaches by
//! the path whose largest potential step |ΔR|/R_max is smallest.
//!
//! Rationale: a cancelled micro-equilibrium belongs to the macro-equilibrium it reaches by the
//! gentlest route. A shallow stable dip near a macro peak is therefore in the *unstable* flock
//! (a **rocking** equilibrium, [`Hierarchy::rocking_at`]), which a rule following which node
//! absorbed which in the cancellation sequence would miss (the dip may be cancelled against a
//! neighbour that is itself cancelled later towards a valley). Edge cases: at ν = 0 every node is
//! a survivor and its own flock; above the last level there is one stable and one unstable flock
//! (plus no saddle); ties in weight are broken by index, so the result is deterministic. Flock
//! ids are given in the order of their survivor's (root's) node index.

pub use crate::equilibria::Kind;
use serde::{Serialize, Serializer};

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

/// The automatic macro scale: the longest step of N(ν) in log ν above the micro scale (see the
/// module docs for the rule).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Plateau {
    /// Lower end of the plateau's ν interval.
    pub nu_lo: f64,
    /// Upper end of the plateau's ν interval.
    pub nu_hi: f64,
    /// log10(nu_hi / nu_lo) (∞, serialised as null, when G(0) is its own macro scale).
    #[serde(serialize_with = "finite_or_null")]
    pub decades: f64,
    /// Counts of G(ν) on the plateau.
    pub counts: Counts,
    /// decades / decades of the second-longest step (∞, serialised as null, if none).
    #[serde(serialize_with = "finite_or_null")]
    pub clarity: f64,
    /// decades ≥ [`PLATEAU_MIN_DECADES`] and clarity ≥ [`PLATEAU_MIN_CLARITY`].
    pub clear: bool,
}

/// A plateau shorter than this (in decades of ν) is not clear.
pub const PLATEAU_MIN_DECADES: f64 = 0.5;
/// Levels closer than this (relative) are equal up to rounding: a step between them has zero
/// length for the plateau rule (a regular polygon's ties, exact symmetries).
pub const LEVEL_RESOLUTION: f64 = 1e-9;
/// A plateau must reach the macro scale: its upper end is at least this fraction of v_max.
pub const PLATEAU_MACRO_FRACTION: f64 = 0.01;
/// A plateau less than this many times longer than the runner-up is not clear.
pub const PLATEAU_MIN_CLARITY: f64 = 2.0;

/// The hand experimenter's ν of the paper (§3): the macro scale when n(ν) has no clear plateau.
pub const PAPER_NU: f64 = 0.0035;

/// Where the macro-scale ν came from.
#[derive(Clone, Copy, Debug, Serialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum NuSource {
    /// Given by the user (`--nu`).
    User,
    /// The midpoint (in log ν) of a clear plateau of n(ν).
    Plateau,
    /// No clear plateau: the paper's hand-experiment value [`PAPER_NU`].
    PaperDefault,
}

/// A hierarchy read at its macro scale ([`Hierarchy::macro_scale`]).
#[derive(Clone, Debug)]
pub struct MacroScale {
    /// The macro-scale ν.
    pub nu: f64,
    /// Where ν came from.
    pub source: NuSource,
    /// The longest step of n(ν), if any.
    pub plateau: Option<Plateau>,
    /// S(ν), U(ν), H(ν).
    pub counts: Counts,
    /// The flocks at ν.
    pub flocks: Flocks,
    /// The rocking equilibria at ν ([`Hierarchy::rocking_at`]).
    pub rocking: Vec<usize>,
}

/// The macro-scale ν, one rule for the 3D and the planar case: the user's, else the midpoint of
/// a clear `plateau`, else [`PAPER_NU`] (an unclear plateau's own ν is not a macro scale).
pub fn macro_nu(user: Option<f64>, plateau: Option<Plateau>) -> (f64, NuSource) {
    match (user, plateau) {
        (Some(nu), _) => (nu, NuSource::User),
        (None, Some(p)) if p.clear => (p.nu(), NuSource::Plateau),
        (None, _) => (PAPER_NU, NuSource::PaperDefault),
    }
}

fn finite_or_null<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    if x.is_finite() {
        s.serialize_f64(*x)
    } else {
        s.serialize_none()
    }
}

impl Plateau {
    /// The representative ν of the plateau: its geometric midpoint √(lo·hi).
    pub fn nu(&self) -> f64 {
        (self.nu_lo * self.nu_hi).sqrt()
    }
}

/// One flock: the micro-equilibria assigned to one survivor (macro-equilibrium) of G(ν).
#[derive(Clone, Debug, Serialize)]
pub struct Flock {
    /// Flock id (its index in the flock list, ordered by root).
    pub id: usize,
    /// The type of the flock: the kind of its surviving macro-equilibrium.
    #[serde(rename = "type")]
    pub kind: Kind,
    /// The surviving node (macro-equilibrium).
    pub root: usize,
    /// Every node of the flock (sorted), the root included.
    pub members: Vec<usize>,
    /// Number of stable micro-equilibria in the flock.
    pub stable: usize,
    /// Number of unstable micro-equilibria in the flock.
    pub unstable: usize,
    /// Number of saddle micro-equilibria in the flock.
    pub saddle: usize,
}

/// The flocks at one ν.
#[derive(Clone, Debug, Serialize)]
pub struct Flocks {
    /// Flock id of every node of G(0).
    pub membership: Vec<usize>,
    /// Ordered by root index (= by id).
    pub flocks: Vec<Flock>,
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

    /// The automatic macro scale (see the module docs for the rule), `None` without any
    /// cancellation.
    pub fn plateau(&self) -> Option<Plateau> {
        let steps = self.staircase();
        if steps.len() < 2 {
            return None;
        }
        let terminal = |s: &Step| s.counts.stable == 1 && s.counts.unstable == 1 && s.counts.saddle == 0;
        let nu_macro = PLATEAU_MACRO_FRACTION * self.v_max();
        let candidates: Vec<(Step, f64)> = steps
            .iter()
            .skip(1)
            .filter(|s| s.nu_lo > 0.0 && s.nu_hi >= nu_macro && !terminal(s))
            .map(|s| (*s, if s.nu_hi > s.nu_lo * (1.0 + LEVEL_RESOLUTION) { (s.nu_hi / s.nu_lo).log10() } else { 0.0 }))
            .collect();
        let mut best: Option<usize> = None;
        for (i, (_, d)) in candidates.iter().enumerate() {
            if best.is_none_or(|b| *d > candidates[b].1) {
                best = Some(i);
            }
        }
        let Some(b) = best.filter(|&b| candidates[b].1 > 0.0) else {
            // Nothing between the first level and the topological minimum: G(0) is its own
            // macro scale.
            let s = steps[0];
            return Some(Plateau {
                nu_lo: s.nu_lo,
                nu_hi: s.nu_hi,
                decades: f64::INFINITY,
                counts: s.counts,
                clarity: f64::INFINITY,
                clear: true,
            });
        };
        let (step, decades) = candidates[b];
        let second = candidates.iter().enumerate().filter(|(i, _)| *i != b).map(|(_, c)| c.1).fold(0.0, f64::max);
        let clarity = if second > 0.0 { decades / second } else { f64::INFINITY };
        Some(Plateau {
            nu_lo: step.nu_lo,
            nu_hi: step.nu_hi,
            decades,
            counts: step.counts,
            clarity,
            clear: decades >= PLATEAU_MIN_DECADES && clarity >= PLATEAU_MIN_CLARITY,
        })
    }

    /// The arcs of G(0) sorted by (weight, min index, max index).
    fn sorted_arcs(&self) -> Vec<(f64, usize, usize)> {
        let mut arcs: Vec<(f64, usize, usize)> =
            self.arcs.iter().map(|&(a, b)| (self.weight(a, b), a.min(b), a.max(b))).collect();
        arcs.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
        arcs
    }

    /// The flocks of G(ν) by the bottleneck assignment (see the module docs).
    pub fn flocks_at(&self, nu: f64) -> Flocks {
        let n = self.nodes.len();
        let alive = self.alive_at(nu);
        let mut uf = UnionFind::new(n);
        // survivor[root of component] = the survivor it contains, if any.
        let mut survivor: Vec<Option<usize>> = (0..n).map(|i| alive[i].then_some(i)).collect();
        for (_, a, b) in self.sorted_arcs() {
            let (ra, rb) = (uf.find(a), uf.find(b));
            if ra == rb || (survivor[ra].is_some() && survivor[rb].is_some()) {
                continue;
            }
            let s = survivor[ra].or(survivor[rb]);
            let r = uf.union(ra, rb);
            survivor[r] = s;
        }
        let roots: Vec<usize> = (0..n).filter(|&i| alive[i]).collect();
        let mut id_of = vec![usize::MAX; n];
        let mut flocks: Vec<Flock> = roots
            .iter()
            .enumerate()
            .map(|(id, &root)| {
                id_of[root] = id;
                Flock { id, kind: self.nodes[root].kind, root, members: Vec::new(), stable: 0, unstable: 0, saddle: 0 }
            })
            .collect();
        let mut membership = vec![0; n];
        for (i, m) in membership.iter_mut().enumerate() {
            let root = survivor[uf.find(i)];
            debug_assert!(root.is_some(), "node {i} is in a component without survivor: G(0) not connected");
            // A disconnected G(0) is a bug upstream; its orphans go to flock 0 rather than panic.
            let id = root.map_or(0, |r| id_of[r]);
            *m = id;
            let f = &mut flocks[id];
            f.members.push(i);
            match self.nodes[i].kind {
                Kind::Stable => f.stable += 1,
                Kind::Unstable => f.unstable += 1,
                Kind::Saddle => f.saddle += 1,
            }
        }
        Flocks { membership, flocks }
    }

    /// The hierarchy read at its macro scale: ν by [`macro_nu`] (`user` first), and the plateau,
    /// counts, flocks and rocking equilibria there — what the 3D and the planar reports show.
    pub fn macro_scale(&self, user: Option<f64>) -> MacroScale {
        let plateau = self.plateau();
        let (nu, source) = macro_nu(user, plateau);
        MacroScale {
            nu,
            source,
            plateau,
            counts: self.counts_at(nu),
            flocks: self.flocks_at(nu),
            rocking: self.rocking_at(nu),
        }
    }

    /// The rocking equilibria at ν: stable nodes whose flock is not a stable flock (sorted).
    pub fn rocking_at(&self, nu: f64) -> Vec<usize> {
        let f = self.flocks_at(nu);
        (0..self.nodes.len())
            .filter(|&i| self.nodes[i].kind == Kind::Stable && f.flocks[f.membership[i]].kind != Kind::Stable)
            .collect()
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

/// Union–find with path halving and union by size.
struct UnionFind {
    parent: Vec<usize>,
    size: Vec<usize>,
}

impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind { parent: (0..n).collect(), size: vec![1; n] }
    }

    fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] != x {
            self.parent[x] = self.parent[self.parent[x]];
            x = self.parent[x];
        }
        x
    }

    /// Unite two roots; returns the new root.
    fn union(&mut self, a: usize, b: usize) -> usize {
        let (big, small) = if self.size[a] >= self.size[b] { (a, b) } else { (b, a) };
        self.parent[small] = big;
        self.size[big] += self.size[small];
        big
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node(kind: Kind, r: f64) -> Node {
        Node { kind, r }
    }

    fn cancel(h: &Hierarchy, seq: &[[usize; 2]]) -> Vec<Cancellation> {
        let mut level: f64 = 0.0;
        seq.iter()
            .map(|&[a, b]| {
                let weight = h.weight(a, b);
                level = level.max(weight);
                Cancellation { weight, level, removed: [a, b] }
            })
            .collect()
    }

    /// A planar cycle 0..6: a valley (0), a peak (1) with a shallow dip (2, 3) beside it, a
    /// second valley (4) and peak (5). R_max = 2, v_max = 0.5.
    fn planar() -> Hierarchy {
        use Kind::*;
        let nodes = vec![
            node(Stable, 1.00),
            node(Unstable, 2.00),
            node(Stable, 1.98),
            node(Unstable, 1.99),
            node(Stable, 1.10),
            node(Unstable, 1.90),
        ];
        let arcs = vec![(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 0)];
        let mut h = Hierarchy { nodes, arcs, r_max: 2.0, cancellations: vec![] };
        // By hand: cheapest (2,3) w = 0.005; then the cycle is 0,1,4,5 with weights
        // 0.5, 0.45, 0.4, 0.45: cancel (4,5) w = 0.4; then S = U = 1, stop.
        h.cancellations = cancel(&h, &[[2, 3], [4, 5]]);
        h
    }

    /// A 3D graph with S = U = H = 2: both saddles join both stable and both unstable points.
    fn spatial() -> Hierarchy {
        use Kind::*;
        let nodes = vec![
            node(Stable, 1.00),
            node(Stable, 1.05),
            node(Saddle, 1.06),
            node(Saddle, 1.50),
            node(Unstable, 2.00),
            node(Unstable, 1.90),
        ];
        let arcs = vec![(2, 0), (2, 1), (2, 4), (2, 5), (3, 0), (3, 1), (3, 4), (3, 5)];
        let mut h = Hierarchy { nodes, arcs, r_max: 2.0, cancellations: vec![] };
        // (2,1) w = 0.005; then saddle 3 has a double arc to 0; cheapest (3,5) w = 0.2.
        h.cancellations = cancel(&h, &[[2, 1], [3, 5]]);
        h
    }

    fn counts(stable: usize, unstable: usize, saddle: usize) -> Counts {
        Counts { stable, unstable, saddle }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12 * (1.0 + a.abs().max(b.abs()))
    }

    #[test]
    fn counts_and_alive() {
        let h = planar();
        h.check().unwrap();
        assert_eq!(h.counts_at(0.0), counts(3, 3, 0));
        assert_eq!(h.counts_at(0.005), counts(3, 3, 0), "level 0.005 is applied only for ν > 0.005");
        assert_eq!(h.counts_at(0.0051), counts(2, 2, 0));
        assert_eq!(h.counts_at(0.39), counts(2, 2, 0));
        assert_eq!(h.counts_at(0.41), counts(1, 1, 0));
        assert_eq!(h.counts_at(10.0), counts(1, 1, 0));
        assert_eq!(h.total_at(0.1), 4);
        assert!(close(h.n_at(0.1), 4.0 / 6.0));
        assert_eq!(h.alive_at(0.1), vec![true, true, false, false, true, true]);
        assert_eq!(h.alive_at(1.0), vec![true, true, false, false, false, false]);
        let s = spatial();
        s.check().unwrap();
        assert_eq!(s.counts_at(0.0), counts(2, 2, 2));
        assert_eq!(s.counts_at(0.1), counts(1, 2, 1));
        assert_eq!(s.counts_at(0.3), counts(1, 1, 0));
    }

    #[test]
    fn staircase_by_hand() {
        let h = planar();
        let st = h.staircase();
        assert_eq!(st.len(), 3);
        let expect = [(0.0, 0.005, 6), (0.005, 0.4, 4), (0.4, 0.5, 2)];
        for (s, (lo, hi, n)) in st.iter().zip(expect) {
            assert!(close(s.nu_lo, lo) && close(s.nu_hi, hi), "{s:?}");
            assert_eq!(s.counts.total(), n);
            assert!(close(s.n, n as f64 / 6.0));
        }
        // Steps tile [0, v_max] and N is non-increasing.
        for w in st.windows(2) {
            assert_eq!(w[0].nu_hi, w[1].nu_lo);
            assert!(w[0].counts.total() >= w[1].counts.total());
        }
    }

    #[test]
    fn plateau_by_hand() {
        // Candidates: [0.005, 0.4] (2, 2); the terminal step [0.4, 0.5] (1, 1) is not one.
        let p = planar().plateau().unwrap();
        assert!(close(p.nu_lo, 0.005) && close(p.nu_hi, 0.4));
        assert!(close(p.decades, 80f64.log10()));
        assert_eq!(p.clarity, f64::INFINITY);
        assert!(p.clear);
        assert_eq!(p.counts, counts(2, 2, 0));
        assert!(close(p.nu(), (0.005f64 * 0.4).sqrt()));
        let q = spatial().plateau().unwrap();
        assert!(close(q.nu_lo, 0.005) && close(q.nu_hi, 0.2));
        assert!(close(q.decades, 40f64.log10()));
        assert_eq!(q.counts, counts(1, 2, 1));
    }

    /// G(0) with nothing to cancel but the final pair: G(0) is its own macro scale.
    #[test]
    fn no_micro_scale() {
        use Kind::*;
        let nodes = vec![node(Stable, 1.0), node(Unstable, 2.0), node(Stable, 1.1), node(Unstable, 1.9)];
        let arcs = vec![(0, 1), (1, 2), (2, 3), (3, 0)];
        let mut h = Hierarchy { nodes, arcs, r_max: 2.0, cancellations: vec![] };
        h.cancellations = cancel(&h, &[[2, 3]]);
        h.check().unwrap();
        let p = h.plateau().unwrap();
        assert_eq!((p.nu_lo, p.counts), (0.0, counts(2, 2, 0)));
        assert!(p.clear && p.decades.is_infinite());
        assert_eq!(p.nu(), 0.0);
        assert_eq!(h.flocks_at(p.nu()).flocks.len(), 4);
    }

    #[test]
    fn no_cancellation_no_plateau() {
        let nodes = vec![node(Kind::Stable, 1.0), node(Kind::Unstable, 2.0)];
        let h = Hierarchy { nodes, arcs: vec![(0, 1), (1, 0)], r_max: 2.0, cancellations: vec![] };
        h.check().unwrap();
        assert!(h.plateau().is_none());
        assert_eq!(h.staircase().len(), 1);
        let f = h.flocks_at(0.3);
        assert_eq!(f.flocks.len(), 2);
    }

    /// Gradual decay (each level twice the previous): no step stands out.
    #[test]
    fn sphere_like_is_not_clear() {
        use Kind::*;
        // Cycle of 10 (dyadic R, exact weights): levels 1, 2, 4, 8 (/256), v_max = 16/256.
        // Candidates [1, 2], [2, 4] and [4, 8] (/256) have exactly equal length; the terminal
        // step [8, 16] is not a candidate.
        let q = |k: f64| 1.0 - k / 256.0;
        let mut nodes = vec![node(Stable, q(16.0)), node(Unstable, q(0.0))];
        for s in [3.0, 4.0, 6.0, 10.0] {
            nodes.push(node(Stable, q(s)));
            nodes.push(node(Unstable, q(2.0)));
        }
        let arcs = (0..10).map(|i| (i, (i + 1) % 10)).collect();
        let mut h = Hierarchy { nodes, arcs, r_max: 1.0, cancellations: vec![] };
        h.cancellations = cancel(&h, &[[2, 3], [4, 5], [6, 7], [8, 9]]);
        h.check().unwrap();
        let levels: Vec<f64> = h.cancellations.iter().map(|c| c.level * 256.0).collect();
        assert_eq!(levels, vec![1.0, 2.0, 4.0, 8.0]);
        let p = h.plateau().unwrap();
        assert_eq!(p.clarity, 1.0, "{p:?}");
        assert!(!p.clear);
        assert_eq!(p.nu_lo, 1.0 / 256.0, "ties go to the lower step: {p:?}");
        assert_eq!(p.counts, counts(4, 4, 0));
    }

    #[test]
    fn flocks_by_hand_planar() {
        let h = planar();
        let f = h.flocks_at(0.05);
        // Survivors 0, 1, 4, 5; (2,3) joins 1 through the arc (1,2) of weight 0.01.
        assert_eq!(f.membership, vec![0, 1, 1, 1, 2, 3]);
        let kinds: Vec<Kind> = f.flocks.iter().map(|x| x.kind).collect();
        assert_eq!(kinds, vec![Kind::Stable, Kind::Unstable, Kind::Stable, Kind::Unstable]);
        assert_eq!(f.flocks[1].members, vec![1, 2, 3]);
        assert_eq!((f.flocks[1].stable, f.flocks[1].unstable), (1, 2));
        assert_eq!(f.flocks[1].root, 1);
        assert_eq!(h.rocking_at(0.05), vec![2], "the dip beside the peak is a rocking equilibrium");
        // ν = 0: every node its own flock, no rocking.
        let f0 = h.flocks_at(0.0);
        assert_eq!(f0.membership, vec![0, 1, 2, 3, 4, 5]);
        assert!(h.rocking_at(0.0).is_empty());
        // Above the last level: one stable (0) and one unstable (1) flock. (4,5) 0.4 joins 4 and
        // 5 (no survivor), then (3,4) 0.445 joins them to 1's flock; (5,0) 0.45 is refused.
        let f1 = h.flocks_at(1.0);
        assert_eq!(f1.flocks.len(), 2);
        assert_eq!(f1.membership, vec![0, 1, 1, 1, 1, 1]);
    }

    #[test]
    fn flocks_by_hand_spatial() {
        let h = spatial();
        let f = h.flocks_at(0.03);
        // Survivors 0 (S), 3 (H), 4 (U), 5 (U). (2,1) 0.005 joins 1,2; (2,0) 0.03 joins them to 0.
        assert_eq!(f.membership, vec![0, 0, 0, 1, 2, 3]);
        assert_eq!((f.flocks[0].stable, f.flocks[0].saddle, f.flocks[0].unstable), (2, 1, 0));
        assert_eq!(f.flocks[1].kind, Kind::Saddle);
        assert!(h.rocking_at(0.03).is_empty());
    }

    #[test]
    fn broken_hierarchies_are_caught() {
        let mut h = planar();
        h.cancellations[1].removed = [4, 2];
        assert!(h.check().is_err(), "node 2 removed twice");
        let mut h = planar();
        h.cancellations[0].level = 0.3;
        assert!(h.check().is_err(), "level not the running maximum");
        let mut h = spatial();
        h.cancellations[0].removed = [2, 3];
        assert!(h.check().is_err(), "two saddles removed: S + U − H ≠ 2");
    }
}
