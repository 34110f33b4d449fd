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

use super::{Hierarchy, Kind};
use serde::Serialize;

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

impl Flocks {
    /// The type of the flock of node `node` (a stable node in an unstable or saddle flock is a
    /// rocking equilibrium).
    pub fn kind_of(&self, node: usize) -> Kind {
        self.flocks[self.membership[node]].kind
    }
}

impl Hierarchy {
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

    /// The rocking equilibria at ν: stable nodes whose flock is not a stable flock (sorted).
    pub fn rocking_at(&self, nu: f64) -> Vec<usize> {
        let f = self.flocks_at(nu);
        (0..self.nodes.len()).filter(|&i| self.nodes[i].kind == Kind::Stable && f.kind_of(i) != Kind::Stable).collect()
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
