//! The hidden base of a field rock: every drawn member stands on exactly the support triangle it
//! drew, its tipping threshold is that triangle's closed form, and the draws are reproducible
//! from (seed, member) whatever the thread count.

use rocking_stones::analysis::Options;
use rocking_stones::dynamics::shaking::ensemble::base::{BaseSource, BaseUncertainty, HiddenBase};
use rocking_stones::dynamics::shaking::ensemble::{member_rocks, MemberRock};
use rocking_stones::dynamics::shaking::rock_params;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::generate;
use rocking_stones::mesh::{cut_base, OpenScan, RimChoice};
use rocking_stones::Vec3;

/// A 0.4 × 0.3 × 0.5 m block cut open 20 mm above its bottom, as a field scan sees it.
fn field_block() -> HiddenBase {
    let open = cut_base(&generate::cuboid(0.4, 0.3, 0.5), 0.02).unwrap();
    HiddenBase::of_open_scan(OpenScan::new(open, &RimChoice::Lowest).unwrap(), 1.0).unwrap()
}

fn members(hidden: &HiddenBase, u: &BaseUncertainty, seed: u64, n: u64, threads: usize) -> Vec<MemberRock> {
    let params = rock_params(Surface::RockOnConcrete, 0.35).unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| member_rocks(hidden, u, seed, n, &Options::default(), 1e-3, &params).unwrap())
}

/// The distance from the origin to the line through `a` and `b` (x, y).
fn distance_to_line(a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    (a[0] * dy - a[1] * dx).abs() / dx.hypot(dy)
}

#[test]
fn a_drawn_member_stands_on_its_triangle_and_tips_at_the_triangles_closed_form() {
    let hidden = field_block();
    assert_eq!(hidden.source(), BaseSource::OpenScan);
    let u = BaseUncertainty::calibrated();
    let rocks = members(&hidden, &u, 5, 6, 2);
    let mut thresholds = Vec::new();
    for (m, rock) in rocks.iter().enumerate() {
        let d = &rock.base;
        let [d0, d1] = hidden.depth_range(&u);
        assert!((d0..=d1).contains(&d.depth_m), "member {m}: depth {}", d.depth_m);
        assert!((u.region[0]..=u.region[1]).contains(&d.region) && (u.slope[0]..=u.slope[1]).contains(&d.slope));
        // The hull's corners relative to G (metres): the lowest are the support, and there are
        // exactly three, the drawn triangle moved by G.
        let s = &rock.stone;
        let corners: Vec<Vec3> = s.body.corners.iter().map(|c| c * s.body.r_max).collect();
        let low = corners.iter().map(|c| c.z).fold(f64::INFINITY, f64::min);
        let support: Vec<&Vec3> = corners.iter().filter(|c| c.z - low < 1e-9).collect();
        assert_eq!(support.len(), 3, "member {m}: the rock stands on {} corners", support.len());
        // Quasi-static threshold: the nearest support edge's distance from G's foot over G's
        // height, against the tipping polar's minimum the member reports.
        let xy: Vec<[f64; 2]> = support.iter().map(|c| [c.x, c.y]).collect();
        let nearest = (0..3).map(|i| distance_to_line(xy[i], xy[(i + 1) % 3])).fold(f64::INFINITY, f64::min);
        let closed_form = nearest / -low;
        assert!(
            (d.tan_alpha - closed_form).abs() < 1e-9 * closed_form.max(1.0),
            "member {m}: tan α {} vs the triangle's {closed_form}",
            d.tan_alpha
        );
        // A block 0.4 wide standing on a triangle inside its footprint tips no later than on
        // its whole bottom (b / h, G about 0.24 m up).
        assert!(closed_form > 0.0 && closed_form < 0.15 / 0.2, "member {m}: tan α {closed_form}");
        thresholds.push(closed_form);
    }
    // The threshold is what the base changes: members differ several-fold.
    let (lo, hi) = thresholds.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &t| (l.min(t), h.max(t)));
    assert!(hi > 2.0 * lo, "tan α from {lo} to {hi}");
}

#[test]
fn members_are_the_same_rocks_whatever_the_threads_or_the_ensemble_size() {
    let hidden = field_block();
    let u = BaseUncertainty::calibrated();
    let one = members(&hidden, &u, 9, 4, 1);
    let two = members(&hidden, &u, 9, 4, 2);
    let few = members(&hidden, &u, 9, 2, 2);
    let draws = |r: &[MemberRock]| r.iter().map(|m| m.base).collect::<Vec<_>>();
    assert_eq!(draws(&one), draws(&two));
    assert_eq!(draws(&few)[..], draws(&one)[..2]);
    assert!(one.windows(2).all(|w| w[0].base.support_m != w[1].base.support_m));
    // Another seed, other rocks.
    assert_ne!(draws(&members(&hidden, &u, 10, 2, 2)), draws(&few));
}

#[test]
fn a_closed_scan_is_drawn_below_its_band() {
    let mesh = generate::cuboid(0.4, 0.3, 0.5);
    let hidden = HiddenBase::of_closed_scan(&mesh, 0.002, 1.0).unwrap();
    assert_eq!(hidden.source(), BaseSource::ClosedScan { band_m: 0.002 });
    assert!((hidden.rim_height() - (-0.25 + 0.002)).abs() < 1e-12, "{}", hidden.rim_height());
    // A block's walls are vertical (they never close): the support lies at most three bands
    // below the band's rim, its lowest point being seen.
    let u = BaseUncertainty::calibrated();
    assert_eq!(hidden.depth_range(&u), [0.0, 3.0 * 0.002]);
    let rocks = members(&hidden, &u, 1, 3, 2);
    for r in &rocks {
        let d = r.base.depth_m;
        assert!((0.0..=0.006).contains(&d), "depth {d}");
        // G stays at the block's centre to within the band: the support is d below the rim,
        // G (0 for the block) that high above it, less what the drawn base moves it.
        let s = &r.stone;
        let low = s.body.corners.iter().map(|c| c.z * s.body.r_max).fold(f64::INFINITY, f64::min);
        let expected = 0.25 - 0.002 + d;
        assert!((-low - expected).abs() < 0.002, "G {} above the support, {expected} for the block", -low);
    }
}

#[test]
fn the_walls_close_where_a_cone_has_its_apex_and_never_for_a_prism() {
    // An octahedron standing on a vertex, cut 0.1 above it: its walls are planes through the
    // apex, so continued down they close exactly 0.1 below the rim.
    let open = cut_base(&generate::platonic(generate::Platonic::Octahedron), 0.1).unwrap();
    let hidden = HiddenBase::of_open_scan(OpenScan::new(open, &RimChoice::Lowest).unwrap(), 1.0).unwrap();
    let e = hidden.wall_depth().unwrap();
    assert!((e - 0.1).abs() < 1e-9, "the walls close {e} below the rim");
    let u = BaseUncertainty::calibrated();
    // The range is 0 to `walls` × that depth, at least `floor` and at most once the rim's
    // footprint radius (the section is a square of half-diagonal 0.1: area 0.02).
    let rho = (0.02f64 / std::f64::consts::PI).sqrt();
    let [lo, hi] = hidden.depth_range(&u);
    assert!(lo == 0.0 && (hi - (u.walls * e).max(u.floor * rho).min(rho)).abs() < 1e-12, "{lo}–{hi}");
    let deep = BaseUncertainty { walls: 100.0, ..u };
    assert!((hidden.depth_range(&deep)[1] - rho).abs() < 1e-12, "at most the footprint's radius");
    let shallow = BaseUncertainty { walls: 0.01, floor: 0.5, ..u };
    assert!((hidden.depth_range(&shallow)[1] - 0.5 * rho).abs() < 1e-12, "at least the floor");
    // A block's walls are vertical: they never close, and the depth ranges up to the
    // footprint's radius √(A/π) (A = 0.4 × 0.3).
    let block = field_block();
    assert_eq!(block.wall_depth(), None);
    let rho = (0.4f64 * 0.3 / std::f64::consts::PI).sqrt();
    let [lo, hi] = block.depth_range(&u);
    assert!(lo == 0.0 && (hi - rho).abs() < 1e-9, "{lo}–{hi} against ρ = {rho}");
    // A known depth is taken as given.
    let known = BaseUncertainty { depth_m: Some([0.005, 0.01]), ..u };
    assert_eq!(block.depth_range(&known), [0.005, 0.01]);
}

#[test]
fn measured_rocking_points_are_stood_on_by_every_member_and_checked() {
    let hidden = field_block();
    let points = [[-0.1, -0.08], [0.1, -0.08], [0.0, 0.1]];
    let u = BaseUncertainty { rocking_points_m: Some(points), ..BaseUncertainty::calibrated() };
    let rocks = members(&hidden, &u, 3, 4, 2);
    for r in &rocks {
        // The same support in every member, at the grid points nearest the given ones (the
        // grid's spacing is √(A/400) = 17 mm here).
        assert_eq!(r.base.support_m, rocks[0].base.support_m);
        for (s, p) in r.base.support_m.iter().zip(&points) {
            assert!((s[0] - p[0]).hypot(s[1] - p[1]) < 0.017, "{s:?} for {p:?}");
        }
    }
    assert!(rocks.windows(2).any(|w| w[0].base.depth_m != w[1].base.depth_m), "the depth is still drawn");
    // Points that do not surround G's foot (the block's centre): refused, naming them.
    let aside = BaseUncertainty { rocking_points_m: Some([[0.1, 0.05], [0.15, 0.05], [0.12, 0.1]]), ..u };
    let params = rock_params(Surface::RockOnConcrete, 0.35).unwrap();
    let e = member_rocks(&hidden, &aside, 3, 1, &Options::default(), 1e-3, &params).err().unwrap();
    assert!(e.to_string().contains("rocking_points") && e.to_string().contains("G's foot"), "{e}");
}
