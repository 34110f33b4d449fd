//! The Morse–Smale graph of a polygon — the cycle of alternating minima and maxima of R in
//! boundary order — and its ν-hierarchy: cheapest adjacent (stable, unstable) pairs cancelled
//! first (see "Morse–Smale graph and hierarchy" in the parent module).

use super::PlanarEquilibria;
use crate::hierarchy::{Hierarchy, Kind, Node};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

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
