//! Many drops in one rapier world (batched drops): every drop's outcome is bit-identical to the same
//! drop alone in its world, for any batch size and thread count, with and without the certificate.

use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::certificate::{certificate, CertificateMode};
use rocking_stones::dynamics::drops::launch::{launch, DropOutcome};
use rocking_stones::dynamics::drops::montecarlo::{run_drops_batched, RunHeader, Shard, FORMAT};
use rocking_stones::dynamics::drops::params::Preset;
use rocking_stones::dynamics::drops::simulate::simulate;
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::generate;
use rocking_stones::rng::item_rng;
use std::collections::BTreeMap;
use std::sync::Mutex;

fn stone(mesh: rocking_stones::mesh::TriMesh) -> Stone {
    let (mesh, rep) = mesh.into_solid_boundary().unwrap();
    let a = Analysis::of_solid(mesh, rep, &Options::default()).unwrap();
    let (nu, _) = a.macro_nu(&Options::default());
    Stone::new(&a, nu).unwrap()
}

fn header(drops: u64, preset: Preset, certificate: CertificateMode) -> RunHeader {
    RunHeader {
        format: FORMAT.into(),
        mesh: "test".into(),
        mesh_fingerprint: "0".into(),
        seed: 5,
        drops,
        params: preset.params(Surface::SteelOnWood),
        certificate,
        preset: Some(preset.name().into()),
        surface: Some(Surface::SteelOnWood),
        r_max_m: None,
        center_of_mass: None,
        shard: Shard::ALL,
    }
}

/// Outcomes with their floats as bit patterns, so that equality is bit-identity.
fn bits(o: &DropOutcome) -> (u64, bool, Option<u32>, Option<u32>, u64, bool, Option<u64>) {
    (o.index, o.settled, o.facet, o.flock, o.time.to_bits(), o.certified, o.height_above.map(f64::to_bits))
}

fn batched(s: &Stone, h: &RunHeader, batch: usize, threads: usize, shard: Shard) -> Vec<DropOutcome> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    let cert = certificate(s, h.certificate);
    let finished = Mutex::new(Vec::new());
    let out = {
        let sink = Mutex::new(|o: &DropOutcome| finished.lock().unwrap().push(o.index));
        pool.install(|| {
            run_drops_batched(s, &RunHeader { shard, ..h.clone() }, &BTreeMap::new(), cert.as_ref(), batch, &sink)
        })
    };
    // Every drop is reported to the checkpoint exactly once.
    let mut seen = finished.into_inner().unwrap();
    seen.sort();
    assert_eq!(seen, out.iter().map(|o| o.index).collect::<Vec<_>>());
    out
}

fn alone(s: &Stone, h: &RunHeader) -> Vec<DropOutcome> {
    let cert = certificate(s, h.certificate);
    (0..h.drops)
        .map(|i| simulate(s, &h.params, &launch(&mut item_rng(h.seed, i), &h.params), i, cert.as_ref()))
        .collect()
}

#[test]
fn batched_drops_are_bit_identical_to_drops_alone_for_any_batch_and_thread_count() {
    let cases = [
        (stone(generate::cuboid(1.0, 0.8, 0.5)), Preset::Throw, CertificateMode::None),
        (stone(generate::cuboid(1.0, 0.8, 0.5)), Preset::Drop, CertificateMode::Facet),
        (stone(generate::pebble([1.0, 0.72, 0.5], 0.02, 120, 3)), Preset::Drop, CertificateMode::Flock),
    ];
    for (s, preset, mode) in &cases {
        let h = header(40, *preset, *mode);
        let reference: Vec<_> = alone(s, &h).iter().map(bits).collect();
        // The drops really differ (the test could not pass with one repeated outcome).
        let times: std::collections::BTreeSet<u64> = reference.iter().map(|r| r.4).collect();
        assert!(times.len() > 10, "{preset} {mode:?}: only {} distinct times", times.len());
        for batch in [1, 7, 32] {
            for threads in [1, 2] {
                let got: Vec<_> = batched(s, &h, batch, threads, Shard::ALL).iter().map(bits).collect();
                assert_eq!(got, reference, "{preset} {mode:?}: batch {batch}, {threads} threads");
            }
        }
        // Shards of a batched run hold the same drops.
        let mut sharded: Vec<_> =
            (0..3).flat_map(|k| batched(s, &h, 7, 2, Shard { index: k, count: 3 })).map(|o| bits(&o)).collect();
        sharded.sort();
        assert_eq!(sharded, reference, "{preset} {mode:?}: shards of a batch-7 run");
    }
}
