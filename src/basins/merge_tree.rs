//! The merge tree of the sublevel sets of h and the energy certificate (see the
//! [module docs](super)).

use super::{SupportFlow, NONE};
use crate::equilibria::Equilibria;
use crate::hull::Polyhedron;
use crate::{Point3, Vec3};
use serde::Serialize;

/// One node of the [`MergeTree`].
#[derive(Clone, Debug, Serialize)]
pub struct MergeNode {
    /// h(n_F) for a facet leaf; the weight of the arc that joined the children otherwise.
    pub level: f64,
    /// Index of the node this one merges into (None at the root).
    pub parent: Option<u32>,
    /// The two nodes joined at this node (None for a facet leaf).
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

    /// The level at and above which [`MergeTree::decided`] (`facet_flock` None) or
    /// [`MergeTree::decided_flock`] (`facet_flock` given) decides nothing, from any direction: the
    /// largest, over the stable facets f, of the level of f's lowest ancestor whose stable facets
    /// are not all f (facet level: f's `unique_level`) or not all in f's flock (flock level); ∞
    /// if the whole tree is one facet / one flock. A run whose energy level is at or above it
    /// needs no descent to know that the certificate cannot decide yet (so the check costs
    /// O(1) until then). Tight: just below it, the facet that attains it decides from its
    /// own normal.
    pub fn decision_ceiling(&self, facet_flock: Option<&[Option<usize>]>) -> f64 {
        #[derive(Clone, Copy, PartialEq)]
        enum Key {
            Empty,
            Uniform(usize),
            Mixed,
        }
        let key_of = |f: usize| match facet_flock {
            None => Key::Uniform(f),
            Some(ff) => ff.get(f).copied().flatten().map_or(Key::Mixed, Key::Uniform),
        };
        let nf = self.solo_until.len();
        let mut keys = vec![Key::Empty; self.nodes.len()];
        let mut ceiling = f64::NEG_INFINITY;
        // Children are created before their parents (node order).
        for (x, node) in self.nodes.iter().enumerate() {
            keys[x] = match node.children {
                None if x < nf && node.stable > 0 => key_of(x),
                None => Key::Empty,
                Some([a, b]) => {
                    let (ka, kb) = (keys[a as usize], keys[b as usize]);
                    let k = match (ka, kb) {
                        (Key::Empty, k) | (k, Key::Empty) => k,
                        (Key::Uniform(i), Key::Uniform(j)) if i == j => ka,
                        _ => Key::Mixed,
                    };
                    if k == Key::Mixed && (matches!(ka, Key::Uniform(_)) || matches!(kb, Key::Uniform(_))) {
                        ceiling = ceiling.max(node.level);
                    }
                    k
                }
            };
        }
        // A uniform root: some facet (or flock) is never joined by another.
        if self.nodes.iter().enumerate().any(|(x, n)| n.parent.is_none() && matches!(keys[x], Key::Uniform(_))) {
            return f64::INFINITY;
        }
        ceiling
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
