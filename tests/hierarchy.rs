//! Property tests of the generic ν-hierarchy queries on random Morse functions on a cycle (the
//! planar Morse–Smale graph): counts, staircase, plateau and the flock rule, the latter checked
//! against a brute-force bottleneck (minimax) path computation.

use proptest::prelude::*;
use rocking_stones::hierarchy::{Hierarchy, Kind};
use rocking_stones::planar::{hierarchy, PlanarEquilibria, PlanarEquilibrium, PlanarSite, Point2};

/// A random Morse function on a cycle: 2n critical points, minima at even positions.
fn cycle(rs: &[(f64, f64)]) -> Hierarchy {
    let mut points = Vec::new();
    for (i, &(lo, hi)) in rs.iter().enumerate() {
        for (kind, r) in [(Kind::Unstable, 1.0 + hi), (Kind::Stable, 1.0 - lo)] {
            points.push(PlanarEquilibrium {
                kind,
                site: if kind == Kind::Stable { PlanarSite::Side(i as u32) } else { PlanarSite::Vertex(i as u32) },
                point: Point2::origin(),
                r,
                phi: 0.0,
            });
        }
    }
    let r_max = points.iter().map(|p| p.r).fold(0.0, f64::max);
    let r_min = points.iter().map(|p| p.r).fold(f64::INFINITY, f64::min);
    let eq = PlanarEquilibria { points, stable: rs.len(), unstable: rs.len(), r_max, r_min, degenerate_decisions: 0 };
    hierarchy(&eq)
}

/// Bottleneck distance from `s` to every node over the original arcs (Dijkstra-like, minimax).
fn bottleneck_from(h: &Hierarchy, s: usize) -> Vec<f64> {
    let n = h.nodes.len();
    let mut d = vec![f64::INFINITY; n];
    let mut done = vec![false; n];
    d[s] = 0.0;
    for _ in 0..n {
        let u = (0..n).filter(|&i| !done[i]).min_by(|&a, &b| d[a].total_cmp(&d[b])).unwrap();
        done[u] = true;
        for &(a, b) in &h.arcs {
            let v = if a == u {
                b
            } else if b == u {
                a
            } else {
                continue;
            };
            let w = d[u].max(h.weight(a, b));
            if w < d[v] {
                d[v] = w;
            }
        }
    }
    d
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn queries_are_consistent(rs in prop::collection::vec((0.0f64..0.5, 0.0f64..0.5), 1..40), probe in 0.0f64..1.0) {
        let h = cycle(&rs);
        h.check().unwrap();
        let n0 = h.nodes.len();
        // counts_at, total_at, alive_at agree at every level and between levels.
        let mut nus: Vec<f64> = h.cancellations.iter().flat_map(|c| [c.level, c.level * (1.0 + 1e-12) + 1e-300]).collect();
        nus.push(0.0);
        nus.push(probe * h.v_max());
        for &nu in &nus {
            let c = h.counts_at(nu);
            let alive = h.alive_at(nu);
            prop_assert_eq!(c.total(), h.total_at(nu));
            prop_assert_eq!(alive.iter().filter(|&&x| x).count(), c.total());
            prop_assert_eq!(c.stable, c.unstable);
            prop_assert!((h.n_at(nu) - c.total() as f64 / n0 as f64).abs() < 1e-15);
        }
        // The staircase tiles [0, v_max] and N strictly decreases from step to step.
        let st = h.staircase();
        prop_assert_eq!(st[0].nu_lo, 0.0);
        prop_assert_eq!(st[0].counts.total(), n0);
        for w in st.windows(2) {
            prop_assert_eq!(w[0].nu_hi, w[1].nu_lo);
            prop_assert!(w[0].counts.total() > w[1].counts.total());
        }
        prop_assert_eq!(st.last().unwrap().counts.total(), 2);
        if let Some(p) = h.plateau() {
            prop_assert!(p.nu_lo <= p.nu_hi);
            prop_assert!(p.clarity >= 1.0 || p.clarity.is_infinite());
            let nu = p.nu();
            if p.nu_hi > p.nu_lo {
                prop_assert_eq!(h.counts_at(nu), p.counts);
            }
        }
    }

    /// The flock rule: a partition, one survivor per flock of that survivor's kind, and every
    /// node in the flock of a survivor at minimal bottleneck distance.
    #[test]
    fn flocks_are_bottleneck_assignments(rs in prop::collection::vec((0.0f64..0.5, 0.0f64..0.5), 1..25), probe in 0.0f64..1.0) {
        let h = cycle(&rs);
        let nu = probe * h.v_max();
        let alive = h.alive_at(nu);
        let f = h.flocks_at(nu);
        let survivors: Vec<usize> = (0..h.nodes.len()).filter(|&i| alive[i]).collect();
        prop_assert_eq!(f.flocks.len(), survivors.len());
        let mut seen = vec![0; h.nodes.len()];
        for (id, fl) in f.flocks.iter().enumerate() {
            prop_assert_eq!(fl.id, id);
            prop_assert_eq!(fl.root, survivors[id]);
            prop_assert_eq!(fl.kind, h.nodes[fl.root].kind);
            prop_assert!(fl.members.contains(&fl.root));
            prop_assert_eq!(fl.members.iter().filter(|&&m| alive[m]).count(), 1);
            prop_assert_eq!(fl.stable + fl.unstable + fl.saddle, fl.members.len());
            for &m in &fl.members {
                seen[m] += 1;
                prop_assert_eq!(f.membership[m], id);
            }
        }
        prop_assert!(seen.iter().all(|&s| s == 1), "flocks partition the nodes");
        let dist: Vec<Vec<f64>> = survivors.iter().map(|&s| bottleneck_from(&h, s)).collect();
        for i in 0..h.nodes.len() {
            let best = dist.iter().map(|d| d[i]).fold(f64::INFINITY, f64::min);
            let own = dist[f.membership[i]][i];
            prop_assert!(own <= best, "node {} assigned at bottleneck {} but {} is possible", i, own, best);
        }
        for i in h.rocking_at(nu) {
            prop_assert_eq!(h.nodes[i].kind, Kind::Stable);
            prop_assert!(f.flocks[f.membership[i]].kind != Kind::Stable);
        }
    }
}
