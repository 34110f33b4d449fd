//! Quasi-static basins of the stable facets on the sphere of down directions, and the merge tree
//! of the support function that decides a drop's final facet early (the static pipeline and the
//! energy certificate, `docs/methods.md`).
//!
//! # The support function and its flow
//!
//! A resting body is described by its **down direction** d (unit, body frame, from G towards the
//! ground). With w_V = V − G for the hull corners V,
//!
//! ```text
//! h(d) = max_V w_V · d
//! ```
//!
//! is the height of G above the ground when the body touches it with down direction d. The
//! sphere is tiled by the **normal cones** C_V = {d : w_V·d ≥ w_W·d ∀W} of the corners; C_V is a
//! convex spherical polygon whose corners are the outward normals n_F of the facets at V and
//! whose sides are the **arcs** of the edges at V (the arc of edge E = (A, B) joins the normals of
//! its two facets on the great circle ⊥ B − A). Inside C_V, h(d) = |w_V| cos∠(d, u_V) with
//! u_V = w_V/|w_V|, and since h > 0 (G is inside) C_V lies in the open hemisphere around u_V.
//!
//! **Quasi-static rolling** is the gradient descent of h on the sphere ([`SupportFlow::settle`]):
//!
//! * inside C_V the flow runs along the great circle through u_V, away from u_V (a *meridian* of
//!   V); it is followed exactly (the exit angle is a closed-form `atan2`);
//! * at the arc of E = (A, B), with e = B − A: if w_B·e < 0 the flow crosses from C_A into C_B
//!   (w_A·e > 0: from C_B into C_A); otherwise (w_A·e ≤ 0 ≤ w_B·e, i.e. the foot P of the
//!   perpendicular from G to E's line lies on E) both neighbouring flows run into the arc — a
//!   *valley* of h — and the flow slides along it, away from u_P = (P − G)/|P − G|, to one of its
//!   end normals. (The fourth case, a ridge, would need |e|² < 0.) A valley arc containing u_P
//!   carries a saddle of h, h(u_P) = R of the saddle on E ([`crate::equilibria`]);
//! * at a facet normal n_F, h near n_F is h(n_F) plus the support function of the polygon F − q_F
//!   (q_F the projection of G onto F's plane). It is a minimum iff q_F is inside F (F stable; the
//!   stable set is taken from [`Equilibria`], so degenerate decisions agree with the rest of the
//!   crate). Otherwise the steepest descent leaves towards q_F − c, c the point of F closest to
//!   q_F: along the arc of c's edge (the body tips over that edge) or into the cone of c's
//!   vertex (it tips over that corner).
//!
//! Every step lowers h, so a descent cannot cycle; it is still capped
//! (`4 (E + F) + 64` steps) and reports an error instead of looping. The start corner is found
//! by hill climbing on the corner graph from the nearest of 64 precomputed directions (a linear
//! function has no local maximum on a convex polytope's graph), not by a scan of all corners.
//!
//! # Basin areas, exactly ([`basin_probabilities`])
//!
//! Inside C_V every point of a meridian flows to the same exit point, so the final facet is a
//! function of the meridian's angle around u_V. It can change only across meridians that are
//! **separatrices**: meridians through the corners of C_V, through a point u_P of an arc (a
//! saddle), and — recursively — the continuations upstream of these, traced backwards (towards
//! u_V) through the transverse arcs by which the flow entered C_V, until they reach a maximum
//! u_V or a corner (whose own backward meridians are traced anyway). A label change on a cone's
//! outflow boundary can only be at one of those points, by induction along the flow (h
//! decreases), so the list is complete. Each cone is then cut into **sectors** between
//! consecutive separatrix angles (gaps > π/2 are split further); a sector ∩ C_V is a convex
//! spherical polygon (clipped exactly against two half-spaces through u_V), its area is a sum of
//! spherical triangle excesses (Van Oosterom–Strackee), and its label is the exact descent from
//! its centroid. As a guard, the centroids of both halves must agree with it; if not, the sector
//! is bisected (up to 24 times) and any area still unresolved is added to the stated error.
//!
//! The stated `error` (absolute, per facet; a bound on the sum over facets as well) is
//! `(unresolved + failed area)/4π + |Σ areas/4π − 1| + 1e-12`, the last term covering rounding
//! and the 1e-12 rad snapping of points onto facet normals. On every body tested the unresolved
//! area is 0, and the probabilities agree with brute-force integration of the flow ODE
//! (`tests/basins.rs`) within the Monte Carlo error.
//!
//! # The merge tree and the energy certificate ([`MergeTree`])
//!
//! For a passive body the total energy E never grows, and E ≥ m g z_G ≥ m g h(d) (the body is on
//! or above the ground). So with the **level** L = E/(m g) (a height of G above the ground, in
//! mesh units), the down direction stays for ever in the sublevel set S_L = {h ≤ L}, and, moving
//! continuously, in its current connected component. If that component contains one stable facet,
//! the final facet is decided; if all its stable facets are in one flock, the final flock is.
//!
//! **Components of S_L from arcs alone.** Take the graph whose nodes are the facet normals and
//! whose edges are the arcs, weighted by the largest h on the arc: max(h(n_F₀), h(n_F₁), |P − G|
//! if u_P lies on the arc) (h on an arc is |P − G| cos∠(d, u_P)). Its components at level L (edges
//! of weight ≤ L) are exactly the components of S_L, each represented by the normals in it:
//!
//! 1. *Every component of C_V ∩ S_L contains a corner of C_V, joined to it inside C_V ∩ S_L along
//!    whole arcs.* C_V ∩ S_L is the convex polygon C_V minus the open cap D = {w_V·d > L}, which
//!    is convex. D meets each side of C_V in one interval, so every component of ∂C_V ∖ D contains
//!    a corner; every component K of C_V ∖ D touches ∂C_V (D's complement is connected and not
//!    inside C_V), and in a single component of ∂C_V ∖ D (two would be separated inside C_V by a
//!    path of K, yet joined by a geodesic of the convex set C_V ∩ D that crosses it). That piece of
//!    ∂C_V is a chain of corners and whole arcs, all in S_L.
//! 2. *Crossing between cones keeps to the graph.* A path of S_L passing from C_V to C_W does so
//!    at a point x of their common arc; h on the arc is a cosine around u_P, so its part in S_L
//!    is at most two intervals, each containing an end normal; that normal is a corner of both
//!    C_V and C_W and is joined to x inside both.
//!
//! Hence two normals are in one component of S_L iff a chain of arcs of weight ≤ L joins them,
//! and Kruskal on the arcs (facets as leaves, each internal node at the weight of the arc that
//! joined its two children) is the merge tree of h. (The weight is the arc's *largest* h, as the
//! certificate needs; on a ridge edge whose foot lies outside the edge, u_P can lie on the arc
//! and exceed both end values. A smaller weight would only be conservative.) The component of
//! S_L that contains d contains the facet `settle(d)` reaches (the flow does not raise h), so
//! [`MergeTree::decided`] climbs from that leaf to its highest ancestor with level ≤ L.
//! [`MergeTree::entry_barrier`] is the level of the lowest common ancestor. The caller must add
//! its own margin to L for what the simulation breaks (penetration, f32 rounding); a level below
//! h(d) is raised to h(d).
//!
//! # Files
//!
//! [`flow`](SupportFlow) (`flow.rs`): the precomputed flow and the descent; `areas.rs`: the basin
//! areas ([`basin_probabilities`]); `merge_tree.rs`: the merge tree ([`MergeTree`]).
//!
//! [`Equilibria`]: crate::equilibria::Equilibria

mod areas;
mod flow;
mod merge_tree;

pub use areas::{basin_probabilities, flock_probabilities, QuasiStatic};
pub use flow::{settle, try_settle};
pub use merge_tree::{MergeNode, MergeTree};

use crate::Vec3;

/// Angular tolerance (radians) for snapping a point of an arc onto one of its end normals.
const SNAP: f64 = 1e-12;
/// "No edge / no facet".
const NONE: u32 = u32::MAX;
/// Bisections of a sector whose check labels disagree, before its area counts as unresolved.
const MAX_REFINE: u32 = 24;
/// Precomputed start directions of the support-corner hill climb.
const SEEDS: usize = 64;

/// How the flow meets the arc of an edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ArcKind {
    /// Both neighbouring flows run into the arc (foot of G on the edge): it slides along it.
    Valley,
    /// The flow crosses from the cone of `vertices[k]` into the cone of the other end.
    Cross(u8),
}

/// What the flow does at a facet normal.
#[derive(Clone, Copy, Debug)]
enum Leave {
    /// A minimum of h: the body rests on this facet.
    Stable,
    /// Slide along the arc of `edge` to the normal of facet `to`.
    Slide { to: u32 },
    /// Leave into the cone of `vertex` along its meridian.
    Enter { vertex: u32 },
}

/// Where a descent is.
#[derive(Clone, Copy, Debug)]
enum State {
    Cone { v: u32, d: Vec3, skip_edge: u32, skip_facet: u32 },
    Facet(u32),
}

/// The gradient flow of the support function h on the sphere of down directions, with
/// everything precomputed that a descent needs (owned: no borrow of the polyhedron, `Sync`).
#[derive(Clone, Debug)]
pub struct SupportFlow {
    /// w_V = V − G.
    w: Vec<Vec3>,
    /// u_V = w_V / |w_V|.
    u: Vec<Vec3>,
    edge_vertices: Vec<[u32; 2]>,
    edge_facets: Vec<[u32; 2]>,
    arc: Vec<ArcKind>,
    /// P − G for each edge (P the foot of the perpendicular from G to the edge's line).
    foot: Vec<Vec3>,
    vertex_edges: Vec<Vec<u32>>,
    /// The facets around each corner in cyclic order (the corners of its normal cone).
    cones: Vec<Vec<u32>>,
    facet_vertices: Vec<Vec<u32>>,
    facet_edges: Vec<Vec<u32>>,
    normal: Vec<Vec3>,
    /// h(n_F) = distance from G to the facet's plane.
    facet_h: Vec<f64>,
    leave: Vec<Leave>,
    seeds: Vec<(Vec3, u32)>,
    max_steps: usize,
}

#[cfg(test)]
mod tests {
    use super::areas::{clip, spherical_area};
    use super::*;
    use crate::equilibria::Equilibria;
    use crate::generate::{cuboid, platonic, Platonic};
    use crate::hull::Polyhedron;
    use crate::hull::DEFAULT_COPLANAR_TOL;
    use crate::mesh::TriMesh;
    use crate::solid::MassProperties;
    use crate::Point3;
    use std::f64::consts::PI;

    fn setup(mesh: TriMesh) -> (Polyhedron, Point3, Equilibria) {
        let (mesh, _) = mesh.into_solid_boundary().unwrap();
        let g = MassProperties::of(&mesh).unwrap().center_of_mass;
        let poly = Polyhedron::new(&mesh.vertices, DEFAULT_COPLANAR_TOL).unwrap();
        let eq = Equilibria::new(&poly, &g, crate::equilibria::DEFAULT_DEGENERACY_TOL).unwrap();
        (poly, g, eq)
    }

    fn facet_towards(poly: &Polyhedron, d: Vec3) -> u32 {
        (0..poly.facets.len())
            .max_by(|&a, &b| poly.facets[a].normal.dot(&d).total_cmp(&poly.facets[b].normal.dot(&d)))
            .unwrap() as u32
    }

    #[test]
    fn box_edges_are_valleys_and_descent_ends_on_the_dominant_face() {
        let (poly, g, eq) = setup(cuboid(2.0, 1.5, 1.0));
        let flow = SupportFlow::new(&poly, &g, &eq);
        assert!(flow.arc.iter().all(|&k| k == ArcKind::Valley), "G at the centre: every foot at an edge midpoint");
        // Near a face normal the descent ends on that face; on an exact normal too.
        for d in [Vec3::x(), -Vec3::y(), Vec3::z(), Vec3::new(1.0, 0.1, -0.05), Vec3::new(0.05, -0.1, 1.0)] {
            assert_eq!(flow.settle(&d).unwrap(), facet_towards(&poly, d), "{d:?}");
        }
        // h decreases along the path, which ends at the facet's normal.
        let (f, path) = flow.settle_path(&Vec3::new(0.9, 0.8, 0.7)).unwrap();
        let hs: Vec<f64> = path.iter().map(|p| flow.h(p)).collect();
        assert!(hs.windows(2).all(|w| w[1] <= w[0] + 1e-12), "{hs:?}");
        assert!((path.last().unwrap() - poly.facets[f as usize].normal).norm() < 1e-12);
    }

    #[test]
    fn support_vertex_hill_climb_matches_a_scan() {
        let (poly, g, eq) = setup(platonic(Platonic::Icosahedron));
        let flow = SupportFlow::new(&poly, &g, &eq);
        for d in crate::rng::fibonacci_sphere(200) {
            let scan = (0..poly.vertices.len()).map(|v| (poly.vertices[v] - g).dot(&d)).fold(f64::MIN, f64::max);
            assert!((flow.w[flow.support_vertex(&d) as usize].dot(&d) - scan).abs() < 1e-14);
        }
    }

    #[test]
    fn clipping_and_areas_of_the_octant() {
        let oct = [Vec3::x(), Vec3::y(), Vec3::z()];
        assert!((spherical_area(&oct) - PI / 2.0).abs() < 1e-15);
        let half = clip(&oct, &Vec3::new(1.0, -1.0, 0.0).normalize());
        assert!((spherical_area(&half) - PI / 4.0).abs() < 1e-15);
        assert!(clip(&oct, &-Vec3::x()).len() < 3 || spherical_area(&clip(&oct, &-Vec3::x())) < 1e-15);
    }

    #[test]
    fn cube_sectors_split_at_corners_and_saddles() {
        let (poly, g, eq) = setup(cuboid(2.0, 2.0, 2.0));
        let q = basin_probabilities(&poly, &g, &eq);
        for p in &q.facet_probability {
            assert!((p - 1.0 / 6.0).abs() < 1e-12, "{:?}", q.facet_probability);
        }
        assert!(q.error < 1e-11, "{}", q.error);
        assert!(q.method.contains("48 spherical sectors"), "{}", q.method);
    }

    #[test]
    fn merge_tree_of_the_cube() {
        let (poly, g, eq) = setup(cuboid(2.0, 2.0, 2.0));
        let t = MergeTree::new(&poly, &g, &eq);
        // Arcs peak at the saddles: h = √2 (edge midpoints); faces at h = 1.
        for f in 0..6 {
            assert!((t.entry_barrier(f, f) - 1.0).abs() < 1e-12);
            assert!((t.unique_level(f) - 2f64.sqrt()).abs() < 1e-12);
            let n = poly.facets[f as usize].normal;
            assert_eq!(t.decided(&n, 1.2), Some(f));
            assert_eq!(t.decided(&n, 1.5), None);
        }
        assert_eq!(t.nodes().len(), 11);
        assert_eq!(t.stable_below(10).len(), 6);
    }
}
