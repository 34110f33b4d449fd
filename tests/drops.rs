//! Drop Monte Carlo: the engine against symmetry, determinism across threads and
//! shards, checkpoints, and the energy bound of the static theory.

use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::certificate::CertificateMode;
use rocking_stones::dynamics::certificate::CERTIFICATE_MARGIN;
use rocking_stones::dynamics::drops::launch::{launch, DropOutcome};
use rocking_stones::dynamics::drops::montecarlo::{
    merge, read_partial, run_drops, summarize, Checkpoint, DropRun, RunHeader, Shard,
};
use rocking_stones::dynamics::drops::params::{DropParams, Launch};
use rocking_stones::dynamics::drops::simulate::simulate;
use rocking_stones::dynamics::engine::run::NoCertificate;
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::generate;
use rocking_stones::mesh::TriMesh;
use rocking_stones::rng::item_rng;
use rocking_stones::stats::wilson;
use std::collections::BTreeMap;
use std::sync::Mutex;

mod common;

fn setup(mesh: TriMesh) -> (Analysis, Stone) {
    let (mesh, rep) = mesh.into_solid_boundary().unwrap();
    let a = Analysis::of_solid(mesh, rep, &Options::default()).unwrap();
    let (nu, _) = a.macro_nu(&Options::default());
    let s = Stone::new(&a, nu).unwrap();
    (a, s)
}

/// A drop from rest at `height` (R_max) with the overdamped contact of the damped resting
/// reference.
fn damped_drop(height: f64) -> DropParams {
    DropParams { launch: Launch::at_rest(height), sim: rocking_stones::dynamics::resting::RestingParams::damped().sim }
}

fn header(drops: u64, seed: u64, certificate: CertificateMode) -> RunHeader {
    common::drop_header(drops, seed, damped_drop(0.5), certificate, None)
}

fn run_all(s: &Stone, h: &RunHeader, shard: Shard) -> Vec<DropOutcome> {
    let sink = Mutex::new(|_: &DropOutcome| {});
    let cert = rocking_stones::dynamics::certificate::certificate(s, h.certificate);
    run_drops(s, &RunHeader { shard, ..h.clone() }, &BTreeMap::new(), cert.as_ref(), &sink)
}

#[test]
fn a_cube_lands_on_each_face_with_probability_one_sixth() {
    let (_, s) = setup(generate::cuboid(1.0, 1.0, 1.0));
    let h = header(1200, 11, CertificateMode::None);
    let outcomes: BTreeMap<u64, DropOutcome> = run_all(&s, &h, Shard::ALL).into_iter().map(|o| (o.index, o)).collect();
    let r = summarize(&s.model(), &h, &outcomes);
    assert_eq!(r.settled, 1200, "every cube drop must come to rest");
    assert_eq!(r.off_equilibrium, 0);
    let stable: Vec<_> = r.facets.iter().filter(|f| f.equilibrium.is_some()).collect();
    assert_eq!(stable.len(), 6);
    for f in &stable {
        // 99.9 % Wilson interval (z = 3.29) around each face's share must contain 1/6.
        let (lo, hi) = wilson(f.count, 1200, 3.29);
        assert!(lo <= 1.0 / 6.0 && 1.0 / 6.0 <= hi, "facet {}: {} of 1200", f.facet, f.count);
        assert!((f.static_probability - 1.0 / 6.0).abs() < 1e-3, "static {}", f.static_probability);
    }
    assert!(r.fit_facets.as_ref().unwrap().p_value > 1e-3, "{:?}", r.fit_facets);
}

#[test]
fn outcomes_do_not_depend_on_threads_or_shards() {
    let (_, s) = setup(generate::pebble([1.0, 0.75, 0.5], 0.03, 400, 2));
    let h = header(48, 5, CertificateMode::Facet);
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap().install(|| run_all(&s, &h, Shard::ALL));
    let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap().install(|| run_all(&s, &h, Shard::ALL));
    assert_eq!(one, two);
    let sharded: Vec<_> = (0..3).map(|i| run_all(&s, &h, Shard { index: i, count: 3 })).collect();
    let parts: Vec<_> = sharded.iter().map(|v| (h.clone(), v.iter().map(|o| (o.index, *o)).collect())).collect();
    let (_, merged) = merge(&parts).unwrap();
    assert_eq!(merged.into_values().collect::<Vec<_>>(), one);
}

#[test]
fn an_interrupted_checkpointed_run_resumes_to_the_same_result() {
    let (_, s) = setup(generate::pebble([1.0, 0.7, 0.5], 0.03, 300, 4));
    let h = header(30, 9, CertificateMode::Facet);
    let full = run_all(&s, &h, Shard::ALL);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.jsonl");
    {
        // "Interrupted": only the first shard of two was run before the process died, and the
        // last line was cut in the middle of a write.
        let (c, done) = Checkpoint::open(&path, &h, false).unwrap();
        assert!(done.is_empty());
        let c = Mutex::new(c);
        let sink = Mutex::new(|o: &DropOutcome| c.lock().unwrap().record(o).unwrap());
        let cert = rocking_stones::dynamics::certificate::certificate(&s, h.certificate);
        let first = RunHeader { shard: Shard { index: 0, count: 2 }, ..h.clone() };
        run_drops(&s, &first, &BTreeMap::new(), cert.as_ref(), &sink);
    }
    std::fs::write(&path, std::fs::read_to_string(&path).unwrap() + "{\"index\": 1, \"sett").unwrap();
    assert!(Checkpoint::open(&path, &h, false).is_err(), "an existing checkpoint must not be overwritten");
    let other = header(30, 10, CertificateMode::Facet);
    assert!(Checkpoint::open(&path, &other, true).is_err(), "a checkpoint of another run must be refused");
    // A run at another time step is refused with the checkpoint's step in the message (a run
    // written at the old default 1/240 s is told how to resume).
    let mut longer = h.clone();
    longer.params.sim.numerics.dt = 1.0 / 120.0;
    let err = Checkpoint::open(&path, &longer, true).err().expect("another step is another run").to_string();
    assert!(err.contains("run at its time step") && err.contains("the reference step"), "{err}");
    let (c, done) = Checkpoint::open(&path, &h, true).unwrap();
    assert_eq!(done.len(), 15);
    {
        let c = Mutex::new(c);
        let sink = Mutex::new(|o: &DropOutcome| c.lock().unwrap().record(o).unwrap());
        let cert = rocking_stones::dynamics::certificate::certificate(&s, h.certificate);
        let rest = run_drops(&s, &h, &done, cert.as_ref(), &sink);
        assert_eq!(rest.len(), 15);
    }
    let (_, all) = read_partial(&path).unwrap();
    assert_eq!(all.into_values().collect::<Vec<_>>(), full);
}

/// A monitor that asks to stop once `after` drops have finished.
struct StopAfter(std::sync::atomic::AtomicU64, u64);
impl rocking_stones::monitor::Monitor for StopAfter {
    fn finished(&self) {
        self.0.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }
    fn stopped(&self) -> bool {
        self.0.load(std::sync::atomic::Ordering::Relaxed) >= self.1
    }
}

#[test]
fn a_drop_run_stopped_by_its_caller_keeps_what_it_finished_and_resumes_to_the_same_result() {
    let (_, s) = setup(generate::pebble([1.0, 0.7, 0.5], 0.03, 300, 4));
    let h = header(40, 9, CertificateMode::Facet);
    let full: BTreeMap<u64, DropOutcome> = run_all(&s, &h, Shard::ALL).into_iter().map(|o| (o.index, o)).collect();
    // In memory, as the Python package runs: the same outcomes as the plain runner.
    let counted = StopAfter(Default::default(), u64::MAX);
    assert_eq!(DropRun::new(&s, &h).run(7, &counted).unwrap(), full);
    assert_eq!(counted.0.into_inner(), 40, "the monitor is told of every drop");
    // Stopped after 5 drops: Cancelled, and the checkpoint holds the drops that finished.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.jsonl");
    let run = DropRun::checkpointed(&s, &h, &path, false).unwrap();
    assert_eq!(run.pending(), 40);
    let stop = StopAfter(Default::default(), 5);
    let err = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap().install(|| run.run(4, &stop));
    assert!(matches!(err, Err(rocking_stones::Error::Cancelled)), "{err:?}");
    let (_, kept) = read_partial(&path).unwrap();
    assert!(kept.len() >= 5 && kept.len() < 40, "{} drops kept", kept.len());
    assert!(kept.iter().all(|(i, o)| full[i] == *o));
    // Resumed: the rest runs, and the whole equals one uninterrupted run.
    let run = DropRun::checkpointed(&s, &h, &path, true).unwrap();
    assert_eq!(run.pending(), 40 - kept.len() as u64);
    assert_eq!(run.run(4, &StopAfter(Default::default(), u64::MAX)).unwrap(), full);
    assert_eq!(read_partial(&path).unwrap().1, full);
}

#[test]
fn certified_drops_end_where_full_settling_ends() {
    let (_, s) = setup(generate::pebble([1.0, 0.72, 0.5], 0.02, 600, 3));
    let plain = run_all(&s, &header(60, 3, CertificateMode::None), Shard::ALL);
    let facet = run_all(&s, &header(60, 3, CertificateMode::Facet), Shard::ALL);
    let flock = run_all(&s, &header(60, 3, CertificateMode::Flock), Shard::ALL);
    let flock_of =
        |o: &DropOutcome| o.flock.map(|k| k as usize).or_else(|| o.facet.and_then(|f| s.facet_flock[f as usize]));
    let settled = plain.iter().filter(|p| p.settled).count();
    assert!(settled >= 58, "only {settled} of 60 plain drops settled");
    for ((p, f), k) in plain.iter().zip(&facet).zip(&flock) {
        if !p.settled {
            continue;
        }
        assert_eq!(f.facet, p.facet, "drop {}: the facet certificate disagrees with full settling", p.index);
        assert!(k.certified, "drop {}: the flock certificate never decided", p.index);
        assert_eq!(flock_of(k), flock_of(p), "drop {}: the flock certificate disagrees with full settling", p.index);
    }
    let time = |v: &[DropOutcome]| v.iter().map(|o| o.time).sum::<f64>();
    // On this pebble every stable flock holds several micro-facets separated by barriers below
    // the certificate's margin, so the facet-level certificate may never fire. Asking it must not
    // change the simulation: a drop it did not decide is the plain drop to the last bit.
    for (p, f) in plain.iter().zip(&facet).filter(|(_, f)| !f.certified) {
        assert_eq!((f.time.to_bits(), f.facet), (p.time.to_bits(), p.facet), "drop {}", p.index);
    }
    assert!(time(&flock) < time(&plain) / 3.0, "flock certificate: {} s vs plain {} s", time(&flock), time(&plain));
}

#[test]
fn no_drop_ends_beyond_the_barrier_its_energy_allows() {
    let (a, s) = setup(generate::pebble([1.0, 0.7, 0.45], 0.04, 500, 8));
    let p = damped_drop(0.05);
    let g = a.mass.center_of_mass;
    let mut crossed = 0;
    for i in 0..40 {
        let mut rng = item_rng(21, i);
        let release = launch(&mut rng, &p);
        let down = release.orientation.inverse() * -rocking_stones::Vec3::z();
        // Initial energy level (input units): the lowest point p.height·R_max above the ground.
        let level = (p.launch.height + s.body.support(&down)) * s.body.r_max;
        let start = rocking_stones::basins::settle(&a.hull, &g, &down);
        let o = simulate(&s, &p, &release, i, &NoCertificate);
        let end = o.facet.unwrap();
        // Every outcome is a stable facet (the quasi-static descent ends on one).
        assert!(s.facet_equilibrium[end as usize].is_some(), "drop {i} ended on facet {end}, not stable");
        let barrier = s.tree.entry_barrier(start, end);
        // The slack is the certificate's margin: what the contact's compression and the solver
        // may add to the energy level.
        assert!(
            barrier <= level + CERTIFICATE_MARGIN * s.body.r_max,
            "drop {i} ended on facet {end} behind a barrier {barrier} above its energy level {level}"
        );
        crossed += usize::from(end != start && barrier > 0.0);
    }
    // Not vacuous: drops do leave the basin they were released over, across a barrier.
    assert!(crossed >= 5, "only {crossed} of 40 drops crossed a barrier");
}

#[test]
fn damaged_or_foreign_checkpoints_are_refused_naming_file_line_and_field() {
    // Damaged and foreign checkpoints: every line is checked against its run before it counts.
    let (_, s) = setup(generate::cuboid(1.0, 0.8, 0.5));
    let model = s.model();
    let h = header(10, 3, CertificateMode::Facet);
    let stable = (0..model.facet_equilibrium.len() as u32).find(|&f| model.facet_equilibrium[f as usize].is_some());
    let line = |index: u64, facet: u32| serde_json::to_string(&DropOutcome::at_rest(index, facet, 1.0)).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, header: &RunHeader, lines: &[String]| {
        let path = dir.path().join(name);
        let mut text = serde_json::to_string(header).unwrap() + "\n";
        for l in lines {
            text += l;
            text += "\n";
        }
        std::fs::write(&path, text).unwrap();
        path
    };
    let err = |r: rocking_stones::Result<_>| r.err().map(|e: rocking_stones::Error| e.to_string()).unwrap_or_default();
    let f = stable.unwrap();
    // A facet index beyond the hull: an error, not a panic.
    let p = write("facet.jsonl", &h, &[line(0, f), line(1, 9999)]);
    let (_, o) = read_partial(&p).unwrap();
    let e = err(rocking_stones::dynamics::drops::montecarlo::check_outcomes(&p, &o, &model).map(|_| ()));
    assert!(e.contains("facet.jsonl") && e.contains("drop 1") && e.contains("field facet"), "{e}");
    // A drop index beyond the run.
    let p = write("index.jsonl", &h, &[line(0, f), line(45, f), line(2, f)]);
    let e = err(read_partial(&p).map(|_| ()));
    assert!(e.contains("index.jsonl") && e.contains("line 3") && e.contains("field index"), "{e}");
    // The same drop twice.
    let p = write("twice.jsonl", &h, &[line(4, f), line(4, f), line(5, f)]);
    let e = err(read_partial(&p).map(|_| ()));
    assert!(e.contains("line 3") && e.contains("already on line 2"), "{e}");
    // Not UTF-8.
    let p = dir.path().join("bytes.jsonl");
    let mut bytes = (serde_json::to_string(&h).unwrap() + "\n" + &line(0, f) + "\n").into_bytes();
    bytes.extend_from_slice(&[0xff, 0xfe, b'{', b'\n']);
    bytes.extend_from_slice((line(1, f) + "\n").as_bytes());
    std::fs::write(&p, bytes).unwrap();
    let e = err(read_partial(&p).map(|_| ()));
    assert!(e.contains("line 3") && e.contains("UTF-8"), "{e}");
    // Resuming with another shard.
    let mut h0 = h.clone();
    h0.shard = Shard { index: 0, count: 2 };
    let p = write("shard0.jsonl", &h0, &[line(0, f), line(2, f)]);
    let mut h1 = h.clone();
    h1.shard = Shard { index: 1, count: 2 };
    let e = err(Checkpoint::open(&p, &h1, true).map(|_| ()));
    assert!(e.contains("shard (1/2 vs 0/2)"), "{e}");
    // A line of another shard inside a shard's file.
    let p = write("mixed.jsonl", &h0, &[line(0, f), line(1, f)]);
    let e = err(read_partial(&p).map(|_| ()));
    assert!(e.contains("line 3") && e.contains("shard 0/2"), "{e}");
    // Another mesh: the fingerprints are named, not "seed 7 vs seed 7".
    let mut other = h.clone();
    other.mesh_fingerprint = "ffff".into();
    let e = err(merge(&[(h.clone(), BTreeMap::new()), (other, BTreeMap::new())]).map(|_| ()));
    assert!(e.contains("mesh fingerprint (0 vs ffff)"), "{e}");
    // Shards of one run merge.
    let (_, a) = read_partial(&write("a.jsonl", &h0, &[line(0, f), line(2, f)])).unwrap();
    let (hm, m) =
        merge(&[(h0.clone(), a), (h1.clone(), BTreeMap::from([(1, serde_json::from_str(&line(1, f)).unwrap())]))])
            .unwrap();
    assert_eq!((hm.shard, m.len()), (Shard::ALL, 3));
}

#[test]
fn drops_still_moving_at_the_cap_are_left_out_and_said_to_be() {
    // One rule: a drop still moving at the time cap has no resting position and is left out of
    // every count, fraction and fit; the summary says how many, and prints no test on no data.
    let (_, s) = setup(generate::cuboid(1.0, 0.8, 0.5));
    let mut h = header(12, 4, CertificateMode::Facet);
    h.params.sim.numerics.max_time = 0.2; // far too short for any drop from its height to land and rest
    let outcomes: BTreeMap<u64, DropOutcome> = run_all(&s, &h, Shard::ALL).into_iter().map(|o| (o.index, o)).collect();
    let r = summarize(&s.model(), &h, &outcomes);
    assert_eq!((r.settled, r.unsettled), (0, 12));
    assert!(r.flocks.iter().all(|f| f.count == 0) && r.facets.iter().all(|f| f.count == 0));
    assert!(r.fit_flocks.p_value.is_nan() && r.fit_flocks.dof == 0);
    assert!(r.fit_flocks.kl_divergence == 0.0 && r.fit_flocks.kl_divergence.is_sign_positive());
    let text = rocking_stones::report::drop_summary(&r);
    assert!(text.contains("12 still moving (left out)") && text.contains("left out of every count"), "{text}");
    assert!(!text.contains("χ² =") && !text.contains("-0.0"), "{text}");
    // With a longer cap some come to rest, and only those are counted.
    h.params.sim.numerics.max_time = 1.0;
    let outcomes: BTreeMap<u64, DropOutcome> = run_all(&s, &h, Shard::ALL).into_iter().map(|o| (o.index, o)).collect();
    let r = summarize(&s.model(), &h, &outcomes);
    assert!(r.settled > 0 && r.unsettled > 0, "{} settled, {} moving", r.settled, r.unsettled);
    assert_eq!(r.flocks.iter().map(|f| f.count).sum::<u64>(), r.settled);
}
