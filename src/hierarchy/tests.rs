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
    let kinds: Vec<Kind> = (0..6).map(|i| f.kind_of(i)).collect();
    use Kind::{Stable, Unstable};
    assert_eq!(kinds, [Stable, Unstable, Unstable, Unstable, Stable, Unstable], "the dip 2 is in 1's unstable flock");
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
