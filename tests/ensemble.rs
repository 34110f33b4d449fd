//! Field-rock ensembles: an ensemble without uncertainty is the single run, bit for
//! bit; members do not depend on threads or ensemble size; the base-contact tolerance changes the
//! rock's support as the quasi-static polar says, and the dynamics follows it.

mod common;

use common::{bottom, stone};
use rocking_stones::dynamics::resting::RestingParams;
use rocking_stones::dynamics::shaking::ensemble::{base_facet, run_ensemble, EnsembleSpec, Uncertainty};
use rocking_stones::dynamics::shaking::housner::ramp_tipping;
use rocking_stones::dynamics::shaking::{rock_params, run_record, sine_pulse, Pose, RockSetup};
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::generate;
use rocking_stones::hull::convex_hull;
use rocking_stones::mesh::TriMesh;
use rocking_stones::tipping::TippingPolar;
use rocking_stones::Point3;

fn spec(uncertainty: Uncertainty, seed: u64, members: u64) -> EnsembleSpec {
    EnsembleSpec { uncertainty, seed, members }
}

fn block_setup(s: &Stone) -> RockSetup {
    RockSetup::new(s, Pose::Equilibrium { id: bottom(s) }, 0.25, Surface::StoneOnStone, 0.3).unwrap()
}

#[test]
fn an_ensemble_without_uncertainty_is_the_single_run_bit_for_bit() {
    let s = stone(generate::cuboid(1.0, 0.6, 2.0));
    let setup = block_setup(&s);
    for (amp, f) in [(0.3, 4.0), (0.9, 2.0)] {
        let record = sine_pulse(amp, f, 1.0, 1e-3).unwrap();
        let single = run_record(&s, &setup, &record, 1.0).unwrap();
        let e = run_ensemble(&s, &setup, &record, 1.0, &spec(Uncertainty::default(), 7, 2), &|| {}).unwrap();
        for m in &e.members {
            assert_eq!(m.run, single.rock, "{amp} g, {f} Hz, member {}", m.draw.member);
        }
        assert_eq!(e.probability.overturned, 2 * single.rock.overturned as usize);
        assert!(e.sensitivity.is_empty());
    }
}

#[test]
fn members_do_not_depend_on_threads_or_ensemble_size() {
    let s = stone(generate::cuboid(1.0, 0.6, 2.0));
    let setup = block_setup(&s);
    let record = sine_pulse(0.6, 2.0, 1.0, 1e-3).unwrap();
    let u = Uncertainty {
        contact_tolerance_m: Some([0.0, 0.01]),
        azimuth_deg: Some([0.0, 360.0]),
        random_sign: true,
        ..Uncertainty::of_surface(Surface::StoneOnStone)
    };
    let run = |threads: usize, n: u64| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| run_ensemble(&s, &setup, &record, 1.0, &spec(u.clone(), 11, n), &|| {}).unwrap())
    };
    let (one, two) = (run(1, 4), run(2, 4));
    assert_eq!(one.members, two.members);
    assert_eq!(run(2, 2).members[..], one.members[..2]);
    // The draws vary every uncertain input and stay in their ranges.
    let d: Vec<_> = one.members.iter().map(|m| m.draw).collect();
    assert!(d.windows(2).all(|w| w[0].friction != w[1].friction && w[0].azimuth_deg != w[1].azimuth_deg));
    assert!(d.iter().all(|d| (0.6..=0.85).contains(&d.friction) && (0.0..=0.01).contains(&d.contact_tolerance_m)));
    assert_eq!(one.sensitivity.len(), 6);
}

/// A 1 m block 2b × 2d × 2h whose bottom face is flat for x ≤ 0.4 b and bevelled up by `rise`
/// (m) at x = b: standing on the flat part, it pivots about x = 0.4 b when pushed towards +x,
/// unless the bevel's corners carry load.
fn bevelled_block(rise: f64) -> Stone {
    let (b, d, h) = (0.5, 0.3, 1.0);
    let mut pts = Vec::new();
    for sy in [-d, d] {
        for (x, z) in [(-b, h), (b, h), (-b, -h), (0.4 * b, -h), (b, -h + rise)] {
            pts.push(Point3::new(x, sy, z));
        }
    }
    let hull = convex_hull(&pts).unwrap();
    stone(TriMesh::new(pts, hull.triangles))
}

#[test]
fn the_base_contact_tolerance_moves_the_pivot_as_the_tipping_polar_says() {
    let rise = 0.002;
    let s = bevelled_block(rise);
    let mut p: RestingParams = rock_params(Surface::RockOnConcrete, s.body.r_max).unwrap();
    (p.sim.contact.friction, p.sim.contact.restitution) = (1.0, 0.0);
    let setup = RockSetup::with_params(&s, Pose::Equilibrium { id: bottom(&s) }, 1.0, 0.0, p.clone());
    let facet = base_facet(&s, &setup).unwrap();
    let down = s.body.facet_normals[facet as usize];
    let corners: Vec<Point3> = s.body.corners.iter().map(|c| Point3::from(c * s.body.r_max)).collect();
    for (tolerance, pivot) in [(0.0, 0.4 * 0.5), (2.0 * rise, 0.5)] {
        // Quasi-static: the polar's tan α towards ±x (the y sides, d/h = 0.3, are not in play)
        // is the pivot's over G's height.
        let polar = TippingPolar::new(&corners, &Point3::origin(), &down, tolerance).unwrap();
        let [e1, e2] = polar.basis;
        let x = e2.x.atan2(e1.x);
        let tan_x = polar.acceleration(x).min(polar.acceleration(x + std::f64::consts::PI));
        assert!((tan_x - pivot / polar.height).abs() < 0.01, "τ = {tolerance}: {tan_x} vs {}", pivot / polar.height);
        // Dynamic: a slow ramp of ground acceleration tips the flattened rock at that tan α
        // (within the detector's lag and 2 %), in the weaker of the two directions along x.
        let rock = s.with_base_contact(facet, tolerance / s.body.r_max).unwrap();
        let start = rock.position(bottom(&rock)).unwrap();
        let tip = |azimuth: f64| ramp_tipping(&rock, start, &p, azimuth, 0.01, 1e-3, 1.5).unwrap();
        let weaker = tip(0.0).min(tip(std::f64::consts::PI));
        eprintln!("τ = {tolerance} m: polar tan α {tan_x:.4}, ramp tipped at {weaker:.4} g");
        assert!((weaker / tan_x - 1.0).abs() < 0.03, "τ = {tolerance}: tipped at {weaker} g, polar {tan_x} g");
    }
}

#[test]
fn an_ensemble_batch_fits_every_member_and_resumes_by_member() {
    use rocking_stones::dynamics::shaking::run_batch;
    let s = stone(generate::cuboid(1.0, 0.6, 2.0));
    let setup = block_setup(&s);
    let record = sine_pulse(1.0, 2.0, 1.0, 1e-3).unwrap();
    let e = spec(Uncertainty { azimuth_deg: Some([0.0, 360.0]), ..Uncertainty::default() }, 3, 3);
    let scales = [0.2, 0.5, 1.0];
    let all = run_batch(&s, &setup, std::slice::from_ref(&record), &scales, Some(&e), &[], &|_| {}).unwrap();
    assert_eq!(all.runs.len(), 9);
    assert!(all.runs.iter().all(|r| r.member.is_some()));
    assert_eq!(all.probabilities.len(), 3);
    assert_eq!(all.probabilities.iter().map(|p| p.probability.members).sum::<usize>(), 9);
    assert_eq!(all.tipping.len(), 1);
    // A member is the same possible rock at every scale: its draw does not depend on the scale.
    assert_eq!(all.runs[0].member, all.runs[3].member);
    // Resuming from the first four runs (a killed batch) runs the other five, and the batch is the same.
    let ran = std::sync::atomic::AtomicUsize::new(0);
    let resumed = run_batch(&s, &setup, std::slice::from_ref(&record), &scales, Some(&e), &all.runs[..4], &|_| {
        ran.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    })
    .unwrap();
    assert_eq!(ran.into_inner(), 5);
    assert_eq!(resumed.runs, all.runs);
}

#[test]
fn a_stopped_ensemble_skips_the_members_left_and_says_so() {
    use rocking_stones::monitor::Monitor;
    use std::sync::atomic::{AtomicU64, Ordering};
    struct StopAfterOne(AtomicU64);
    impl Monitor for StopAfterOne {
        fn finished(&self) {
            self.0.fetch_add(1, Ordering::Relaxed);
        }
        fn stopped(&self) -> bool {
            self.0.load(Ordering::Relaxed) >= 1
        }
    }
    let s = stone(generate::cuboid(1.0, 0.6, 2.0));
    let setup = block_setup(&s);
    let record = sine_pulse(0.3, 4.0, 1.0, 1e-3).unwrap();
    let m = StopAfterOne(AtomicU64::new(0));
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let r = pool.install(|| run_ensemble(&s, &setup, &record, 1.0, &spec(Uncertainty::default(), 1, 8), &m));
    assert!(matches!(r, Err(rocking_stones::Error::Cancelled)), "{:?}", r.map(|e| e.probability));
    assert_eq!(m.0.into_inner(), 1, "one member ran, the seven left were skipped");
}
