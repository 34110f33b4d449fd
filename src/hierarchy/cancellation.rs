//! The cancellation hierarchy of G(0) (paper §2.2.3): the Morse–Smale graph simplified one
//! arc at a time, cheapest first.

use super::{Cancellation, Hierarchy, Node};
use crate::equilibria::{Equilibria, Kind};
use crate::morse_smale::MorseSmaleGraph;
use crate::{Error, Result};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// The cancellation hierarchy of G(0) (paper §2.2.3).
///
/// Repeatedly cancel the cheapest valid arc (saddle h, extremum e), weight
/// v = |R_h − R_e| / R_max, ties broken by (h, e): valid when h and e are joined by exactly one
/// arc (a double arc may not be cancelled) and e is not the last stable (unstable) point. The
/// other saddles of e are reconnected to h's other extremum of e's kind; the new arcs are
/// ranked as they appear. `level` is the running maximum of the weights, so G(ν) — every
/// cancellation with level < ν applied — is a prefix of the sequence and N(ν) is monotone.
pub fn cancellation_hierarchy(eq: &Equilibria, graph: &MorseSmaleGraph) -> Result<Hierarchy> {
    let nodes: Vec<Node> = eq.points.iter().map(|p| Node { kind: p.kind, r: p.r }).collect();
    let n = nodes.len();
    // ends[h] = [stable a, stable b, unstable a, unstable b]
    let mut ends = vec![[usize::MAX; 4]; n];
    let mut fill = vec![[0usize; 2]; n];
    let mut saddles_of: Vec<Vec<usize>> = vec![Vec::new(); n];
    for a in &graph.arcs {
        let kind = usize::from(nodes[a.end].kind != Kind::Stable);
        let k = &mut fill[a.saddle][kind];
        if *k >= 2 {
            return Err(Error::check(format!("saddle {} has more than two arcs of one kind", a.saddle)));
        }
        ends[a.saddle][2 * kind + *k] = a.end;
        *k += 1;
        saddles_of[a.end].push(a.saddle);
    }
    if let Some(h) = (0..n).find(|&h| nodes[h].kind == Kind::Saddle && ends[h].contains(&usize::MAX)) {
        return Err(Error::check(format!("saddle {h} does not have 2 stable and 2 unstable arc ends")));
    }
    let weight = |a: usize, b: usize| (nodes[a].r - nodes[b].r).abs() / eq.r_max;
    let key = |w: f64, h: usize, e: usize| Reverse((w.to_bits(), h, e));
    let mut heap = BinaryHeap::new();
    for h in (0..n).filter(|&h| nodes[h].kind == Kind::Saddle) {
        for &e in &ends[h] {
            heap.push(key(weight(h, e), h, e));
        }
    }
    let mut alive = vec![true; n];
    let mut remaining = [eq.stable, eq.unstable];
    let mut cancellations = Vec::with_capacity(eq.saddle);
    let mut level: f64 = 0.0;
    while let Some(Reverse((wbits, h, e))) = heap.pop() {
        if !alive[h] || !alive[e] {
            continue;
        }
        let stable = nodes[e].kind == Kind::Stable;
        let pair = if stable { [ends[h][0], ends[h][1]] } else { [ends[h][2], ends[h][3]] };
        let kind_idx = usize::from(!stable);
        if pair[0] == pair[1] || !pair.contains(&e) || remaining[kind_idx] <= 1 {
            continue; // double arc, stale entry, or the last extremum of its kind
        }
        let other = if pair[0] == e { pair[1] } else { pair[0] };
        let w = f64::from_bits(wbits);
        level = level.max(w);
        cancellations.push(Cancellation { weight: w, level, removed: [h, e] });
        alive[h] = false;
        alive[e] = false;
        remaining[kind_idx] -= 1;
        // Detach h from its ends.
        for &x in &ends[h] {
            saddles_of[x].retain(|&s| s != h);
        }
        // Reconnect e's other saddles to `other`.
        let moved = std::mem::take(&mut saddles_of[e]);
        for h2 in moved {
            for slot in ends[h2].iter_mut() {
                if *slot == e {
                    *slot = other;
                    saddles_of[other].push(h2);
                    heap.push(key(weight(h2, other), h2, other));
                }
            }
        }
    }
    let arcs = graph.arcs.iter().map(|a| (a.saddle, a.end)).collect();
    Ok(Hierarchy { nodes, arcs, r_max: eq.r_max, cancellations })
}
