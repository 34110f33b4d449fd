//! Field rocks under recorded ground motion: true size, poses, three components,
//! sliding vs rocking, flat scanned bases, and the one-sine-pulse overturning boundary against
//! Housner's rocking equation.

mod common;

use common::{bottom, stone};
use rocking_stones::dynamics::resting::outcome::Outcome;
use rocking_stones::dynamics::resting::RestingParams;
use rocking_stones::dynamics::shaking::housner::housner_overturns;
use rocking_stones::dynamics::shaking::{place, rock_params, shake_record, shake_trial, sine_pulse, Pose, RockRun};
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::generate;
use rocking_stones::ground_motion::Record;
use rocking_stones::hull::convex_hull;
use rocking_stones::mesh::TriMesh;
use rocking_stones::Point3;
use rocking_stones::GRAVITY;
use std::f64::consts::PI;

/// Shake `s` (R_max = `r_max_m` metres) standing on its bottom face with `motion`.
fn shake(s: &Stone, p: &RestingParams, motion: &Record, r_max_m: f64) -> RockRun {
    let placed = place(s, &Pose::Equilibrium { id: bottom(s) }, p).unwrap();
    shake_record(s, placed, p, motion, 0.0, r_max_m)
}

/// The motion `f` (m/s², real time t in s) on 0 ≤ t ≤ `duration`, sampled every millisecond: a
/// record, as every motion is.
fn sampled(f: impl Fn(f64) -> [f64; 3], duration: f64) -> Record {
    let dt = 1e-3;
    let n = (duration / dt).ceil() as usize + 1;
    Record::new(
        "test motion",
        duration / (n - 1) as f64,
        (0..n).map(|k| f(k as f64 * duration / (n - 1) as f64)).collect(),
    )
    .unwrap()
}

/// Housner's conditions on a real surface pair: no sliding, plastic impacts.
fn housner(r_max_m: f64) -> RestingParams {
    let mut p = rock_params(Surface::RockOnConcrete, r_max_m).unwrap();
    p.sim.contact.friction = 1.0;
    p.sim.contact.restitution = 0.0;
    p
}

/// A trial of the fragility sweep is a field-rock run of the stone standing on the same
/// micro-equilibrium (one drive, one contact, one rest rule): the same outcome, tilt and time to
/// the last bit; and a record along x turned by 90° is the same record along y.
#[test]
fn a_sweep_trial_is_the_field_run_of_the_same_stone() {
    let s = stone(generate::cuboid(1.0, 0.6, 2.0));
    let r_max_m = 0.3;
    let p = rock_params(Surface::StoneOnStone, r_max_m).unwrap();
    let start = s.position(bottom(&s)).unwrap();
    for (amp, f) in [(0.4, 4.0), (0.8, 2.0)] {
        let m = sine_pulse(amp, f, 1.0, 1e-3).unwrap();
        let trial = shake_trial(&s, start, &p, &m, amp, r_max_m, 0.0, 0);
        let run = shake(&s, &p, &m, r_max_m);
        assert_eq!(trial.outcome, run.outcome, "{amp} g, {f} Hz");
        assert_eq!(trial.max_tilt.to_degrees().to_bits(), run.max_tilt_deg.to_bits(), "{amp} g");
        assert_eq!(trial.time * r_max_m.sqrt(), run.time_s, "{amp} g");
        let along_y = Record::new("y", m.dt, m.accel.iter().map(|a| [0.0, a[0], 0.0]).collect()).unwrap();
        let turned =
            shake_record(&s, place(&s, &Pose::Equilibrium { id: bottom(&s) }, &p).unwrap(), &p, &m, PI / 2.0, r_max_m);
        let y =
            shake_record(&s, place(&s, &Pose::Equilibrium { id: bottom(&s) }, &p).unwrap(), &p, &along_y, 0.0, r_max_m);
        assert_eq!(turned.outcome, y.outcome);
        assert!((turned.max_tilt_deg - y.max_tilt_deg).abs() <= 1e-6 * y.max_tilt_deg.max(1e-3), "{amp} g");
    }
}

/// A ramp a(t) = rate·g·t along x up to `a_max`·g, held there for as long again (plus a constant
/// vertical ground acceleration `az_g`·g).
fn ramp(rate: f64, a_max: f64, az_g: f64) -> Record {
    sampled(move |t: f64| [(rate * t).min(a_max) * GRAVITY, 0.0, az_g * GRAVITY], 2.0 * a_max / rate)
}

/// Housner (1963) at true size: a block of b/h = 0.5 does not tip under a quasi-static horizontal
/// acceleration of 0.9 g tan α and tips under 1.1 g tan α, for a 5 cm and a 5 m block (the
/// real-size contact — rolling-resistance length δ/L — and time scaling change nothing); with the
/// ground accelerating downwards at 0.3 g the effective gravity is 0.7 g and the threshold drops to
/// 0.7 g tan α (the vertical component is carried by the ground's contact).
#[test]
fn housner_threshold_holds_at_true_size_and_with_vertical_motion() {
    let s = stone(generate::cuboid(1.0, 0.6, 2.0));
    let tan_a = 0.5;
    for r_max_m in [0.05, 5.0] {
        let p = housner(r_max_m);
        // Real ramp rates: 0.05 g per scaled second.
        let rate = 0.05 / r_max_m.sqrt();
        let below = shake(&s, &p, &ramp(rate, 0.9 * tan_a, 0.0), r_max_m);
        assert!(below.max_tilt_deg < 0.1, "{r_max_m} m: 0.9 g tan α tilted it {}°", below.max_tilt_deg);
        let above = shake(&s, &p, &ramp(rate, 1.1 * tan_a, 0.0), r_max_m);
        assert!(above.max_tilt_deg > 1.0, "{r_max_m} m: 1.1 g tan α only tilted it {}°", above.max_tilt_deg);
        // Vertical: effective gravity 0.7 g.
        let below = shake(&s, &p, &ramp(rate, 0.63 * tan_a, -0.3), r_max_m);
        assert!(below.max_tilt_deg < 0.1, "{r_max_m} m, a_z = −0.3 g: 0.63 g tan α tilted it {}°", below.max_tilt_deg);
        let above = shake(&s, &p, &ramp(rate, 0.77 * tan_a, -0.3), r_max_m);
        assert!(
            above.max_tilt_deg > 1.0,
            "{r_max_m} m, a_z = −0.3 g: 0.77 g tan α only tilted it {}°",
            above.max_tilt_deg
        );
    }
}

/// A purely vertical motion below 1 g neither tilts nor moves the block sideways, and it rests
/// on the same face after (the ground carries it up and down).
#[test]
fn vertical_motion_below_one_g_leaves_a_block_in_place() {
    let s = stone(generate::cuboid(1.0, 0.6, 2.0));
    let r_max_m = 0.5;
    let p = rock_params(Surface::RockOnConcrete, r_max_m).unwrap();
    let m = sampled(|t: f64| [0.0, 0.0, 0.8 * GRAVITY * (2.0 * PI * 3.0 * t).sin()], 2.0);
    let run = shake(&s, &p, &m, r_max_m);
    assert_eq!(run.outcome, Outcome::Same);
    assert!(run.max_tilt_deg < 0.05, "tilt {}°", run.max_tilt_deg);
    // Measured: 0.9 mm (0.2 % of R_max) of drift from the soft contact's asymmetric corner loads.
    assert!(run.slide_m < 2e-3, "slide {} m", run.slide_m);
}

/// Residual slip of a rigid block on a Coulomb ground (Newmark 1965 sliding block), integrated
/// with a small step: the block follows the ground while |a_g| ≤ μ g, else slides with
/// acceleration ∓μ g until the relative velocity vanishes.
fn newmark_slide(a_g: &dyn Fn(f64) -> f64, duration: f64, mu: f64) -> f64 {
    let (dt, mut t, mut v_rel, mut s) = (1e-5, 0.0, 0.0f64, 0.0);
    let f = mu * GRAVITY;
    while t < duration + 5.0 {
        let a = if t <= duration { a_g(t) } else { 0.0 };
        if v_rel == 0.0 && a.abs() <= f {
            t += dt;
            continue;
        }
        let dir = if v_rel != 0.0 { v_rel.signum() } else { -a.signum() };
        let v_new = v_rel + (-f * dir - a) * dt;
        v_rel = if v_new.signum() != dir && v_rel != 0.0 { 0.0 } else { v_new };
        s += v_rel * dt;
        t += dt;
    }
    s.abs()
}

/// Sliding instead of rocking (Shenton 1996): a block of b/h = 0.5 under a half-sine of 0.7 g —
/// above its tipping acceleration g tan α — rocks on a high-friction ground but only slides when
/// μ = 0.3 < b/h, because friction transmits at most μ m g < m g tan α; the slip agrees with
/// Newmark's sliding block.
#[test]
fn low_friction_slides_instead_of_rocking() {
    let s = stone(generate::cuboid(1.0, 0.6, 2.0));
    let r_max_m = 0.5;
    let a_g = |t: f64| 0.7 * GRAVITY * (2.0 * PI * 2.0 * t).sin();
    let m = sampled(move |t: f64| [a_g(t), 0.0, 0.0], 0.25);
    let mut p = rock_params(Surface::RockOnConcrete, r_max_m).unwrap();
    p.sim.contact.friction = 0.3;
    let slid = shake(&s, &p, &m, r_max_m);
    let expected = newmark_slide(&a_g, 0.25, 0.3);
    assert!(slid.max_tilt_deg < 0.2, "μ = 0.3: tilted {}°", slid.max_tilt_deg);
    assert!(
        (slid.slide_m / expected - 1.0).abs() < 0.1,
        "μ = 0.3: slid {} m, Newmark's block {expected} m",
        slid.slide_m
    );
    p.sim.contact.friction = 0.8;
    let rocked = shake(&s, &p, &m, r_max_m);
    assert!(rocked.max_tilt_deg > 0.5, "μ = 0.8: tilted only {}°", rocked.max_tilt_deg);
}

/// A box 2b × 2d × 2h whose bottom face is an n × n grid of points pushed down by up to
/// `noise`·h (seeded): the flat base of a scan, many near-coplanar facets, triangulated by the
/// convex hull.
fn scanned_box(b: f64, d: f64, h: f64, n: usize, noise: f64, seed: u64) -> TriMesh {
    let mut pts: Vec<Point3> = Vec::new();
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            pts.push(Point3::new(sx * b, sy * d, h));
        }
    }
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut uniform = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for i in 0..=n {
        for j in 0..=n {
            let (x, y) = (-b + 2.0 * b * i as f64 / n as f64, -d + 2.0 * d * j as f64 / n as f64);
            pts.push(Point3::new(x, y, -h - noise * h * uniform()));
        }
    }
    let hull = convex_hull(&pts).unwrap();
    let mut m = TriMesh::new(pts, hull.triangles);
    m.weld();
    m
}

/// The tipping of a rock under a quasi-static horizontal acceleration does not depend on how its
/// flat base is triangulated: an exact box, and two "scanned" boxes whose base is 20 × 20 grid
/// points pushed down by up to 10⁻⁴ h (hundreds of near-coplanar micro-facets, two different
/// realisations) all stay put at 0.95 g b/h and tip at 1.05 g b/h — Housner's threshold with the
/// base's outer edge as the pivot.
#[test]
fn a_flat_scanned_base_tips_at_housners_threshold_whatever_its_triangulation() {
    let (b, d, h) = (0.5, 0.3, 1.0);
    let tan_a = b / h;
    for (mesh, name) in [
        (generate::cuboid(2.0 * b, 2.0 * d, 2.0 * h), "exact box"),
        (scanned_box(b, d, h, 20, 1e-4, 1), "scan 1"),
        (scanned_box(b, d, h, 20, 1e-4, 2), "scan 2"),
    ] {
        let s = stone(mesh);
        let r_max_m = 0.5;
        let p = housner(r_max_m);
        let facets = s.body.facet_normals.iter().filter(|n| n.z < -0.99).count();
        let placed = place(&s, &Pose::AsScanned, &p).unwrap();
        let run =
            |a_max: f64, placed| shake_record(&s, placed, &p, &ramp(0.05 / r_max_m.sqrt(), a_max, 0.0), 0.0, r_max_m);
        let below = run(0.95 * tan_a, placed);
        assert!(
            below.max_tilt_deg < 0.1,
            "{name} ({facets} base facets): 0.95 g b/h tilted it {}°",
            below.max_tilt_deg
        );
        let above = run(1.05 * tan_a, place(&s, &Pose::AsScanned, &p).unwrap());
        assert!(
            above.max_tilt_deg > 1.0,
            "{name} ({facets} base facets): 1.05 g b/h only tilted it {}°",
            above.max_tilt_deg
        );
    }
}

/// `--pose as-scanned` of a box standing on its base settles with a negligible tilt onto its
/// bottom face; a box put down on an edge (turned 30° about y) is refused, naming where it went.
#[test]
fn as_scanned_pose_settles_or_is_refused() {
    let s = stone(generate::cuboid(1.0, 0.6, 2.0));
    let p = rock_params(Surface::RockOnConcrete, 1.0).unwrap();
    let placed = place(&s, &Pose::AsScanned, &p).unwrap();
    assert_eq!(s.stable()[placed.start].index, bottom(&s));
    assert!(placed.settling_tilt < 1e-3, "settling tilt {} rad", placed.settling_tilt);
    // Turned 10° about y: it falls back onto the bottom face (the descent under it) — accepted.
    let c = (5f64.to_radians()).cos();
    let sn = (5f64.to_radians()).sin();
    let placed = place(&s, &Pose::Quat { q: [c, 0.0, sn, 0.0] }, &p).unwrap();
    assert_eq!(s.stable()[placed.start].index, bottom(&s));
    assert!((placed.settling_tilt.to_degrees() - 10.0).abs() < 0.5, "{}", placed.settling_tilt.to_degrees());
    assert!("quat:0,0,0,0".parse::<Pose>().is_err());
    assert!("facet:x".parse::<Pose>().is_err());
    assert_eq!("equilibrium:3".parse::<Pose>().unwrap(), Pose::Equilibrium { id: 3 });
    assert_eq!("facet:3".parse::<Pose>().unwrap(), Pose::HullFacet { facet: 3 });
}

/// The one-sine pulse (Zhang & Makris 2001 "type A", a_g = a_p sin ω_p t for one period) on a
/// slender block (b/h = 0.25, R = 1.03 m at true size): the smallest a_p/(g tan α) on a 0.05 grid
/// that overturns it, from rapier and from Housner's rocking equation integrated above, agree
/// within 5 % at ω_p/p = 2 and 4 (measured: equal at 2, +2.8 % at 4; the full spectrum is in
/// `results/fragility_surface/`).
#[test]
fn one_sine_pulse_overturning_boundary_matches_housners_equation() {
    let (b, d, h) = (0.25, 0.3, 1.0);
    let s = stone(generate::cuboid(2.0 * b, 2.0 * d, 2.0 * h));
    let r_max_m = s.body.r_max;
    let big_r = (b * b + h * h).sqrt();
    let p = (3.0 * GRAVITY / (4.0 * big_r)).sqrt();
    let alpha = (b / h).atan();
    let r = 1.0 - 1.5 * alpha.sin().powi(2);
    let q = housner(r_max_m);
    for ratio in [2.0, 4.0] {
        let wp = ratio * p;
        let first = |f: &dyn Fn(f64) -> bool| (0..40).map(|k| 1.0 + 0.05 * k as f64).find(|&a| f(a));
        let ode = first(&|amp| {
            let ap = amp * GRAVITY * alpha.tan();
            housner_overturns(alpha, p, &move |t: f64| ap * (wp * t).sin(), 2.0 * PI / wp, r)
        })
        .expect("the ODE overturns below 3 g tan α");
        let sim = first(&|amp| {
            let ap = amp * GRAVITY * alpha.tan();
            let run = shake(&s, &q, &sampled(move |t: f64| [ap * (wp * t).sin(), 0.0, 0.0], 2.0 * PI / wp), r_max_m);
            run.overturned
        })
        .expect("rapier overturns below 3 g tan α");
        assert!((sim / ode - 1.0).abs() < 0.05, "ω_p/p = {ratio}: rapier {sim}, Housner ODE {ode}");
    }
}

/// A three-component record written as three PEER `.AT2` files and as one CSV (time, ax, ay, az
/// in g, the same nine digits) gives the identical run: same measures, same outcome, same tilt
/// and slide to the last bit.
#[test]
fn a_record_as_at2_and_as_csv_gives_identical_runs() {
    use rocking_stones::dynamics::shaking::{run_record, RockSetup};
    use rocking_stones::ground_motion::read::{at2_text, read_at2, read_csv, AccelUnit};
    use rocking_stones::ground_motion::synthetic::{filtered_noise, Noise};
    let dir = tempfile::tempdir().unwrap();
    // dt = 2⁻⁶ s: sample times are exact in binary and in six decimals (the AT2 header), so the
    // CSV's times give the AT2's DT exactly.
    let noise = Noise { duration: 6.0, period: 0.5, dt: 1.0 / 64.0, components: 3, ..Noise::default() };
    let rec = filtered_noise(&noise, 0.4, 7).unwrap();
    let mut paths = Vec::new();
    for c in 0..3 {
        let p = dir.path().join(format!("rec_{c}.AT2"));
        std::fs::write(&p, at2_text(&rec, c, "test record")).unwrap();
        paths.push(p);
    }
    let mut csv = String::from("time_s,ax_g,ay_g,az_g\n");
    for (k, a) in rec.accel.iter().enumerate() {
        let g = |x: f64| format!("{:.8E}", x / rocking_stones::GRAVITY);
        csv += &format!("{},{},{},{}\n", k as f64 * rec.dt, g(a[0]), g(a[1]), g(a[2]));
    }
    let csv_path = dir.path().join("rec.csv");
    std::fs::write(&csv_path, csv).unwrap();
    let from_at2 = read_at2(&paths.iter().map(|p| p.as_path()).collect::<Vec<_>>()).unwrap();
    let from_csv = read_csv(&csv_path, &"time_s,ax_g,ay_g,az_g".parse().unwrap(), AccelUnit::G).unwrap();
    assert_eq!(from_at2.dt, from_csv.dt);
    assert_eq!(from_at2.accel, from_csv.accel);
    let s = stone(generate::cuboid(1.0, 0.6, 2.0));
    let setup = RockSetup::new(&s, Pose::Equilibrium { id: bottom(&s) }, 0.4, Surface::RockOnConcrete, 0.3).unwrap();
    let a = run_record(&s, &setup, &from_at2, 1.5).unwrap();
    let b = run_record(&s, &setup, &from_csv, 1.5).unwrap();
    assert!(a.rock.max_tilt_deg > 0.1, "the record should rock the block ({}°)", a.rock.max_tilt_deg);
    assert_eq!((a.motion.pga_g, a.motion.pgv_m_s, &a.rock), (b.motion.pga_g, b.motion.pgv_m_s, &b.rock));
}

/// A batch of records × scales gives the same runs, in the same order, on one and on two threads.
#[test]
fn batches_are_independent_of_the_thread_count() {
    use rocking_stones::dynamics::shaking::{run_batch, RockSetup};
    use rocking_stones::ground_motion::synthetic::{filtered_noise, Noise};
    let s = stone(generate::cuboid(1.0, 0.6, 2.0));
    let recs: Vec<_> = [1u64, 2]
        .iter()
        .map(|&seed| filtered_noise(&Noise { duration: 4.0, components: 2, ..Noise::default() }, 1.0, seed).unwrap())
        .collect();
    let setup = RockSetup::new(&s, Pose::Equilibrium { id: bottom(&s) }, 0.3, Surface::RockOnConcrete, 0.5).unwrap();
    let pool = |n| rayon::ThreadPoolBuilder::new().num_threads(n).build().unwrap();
    let scales = [0.2, 0.45, 0.8];
    let one = pool(1).install(|| run_batch(&s, &setup, &recs, &scales, None, &[], &|_| {})).unwrap();
    let two = pool(2).install(|| run_batch(&s, &setup, &recs, &scales, None, &[], &|_| {})).unwrap();
    assert_eq!(one.runs, two.runs);
    assert_eq!(one.runs.len(), 6);
    assert!(one.runs.iter().any(|r| r.rock.max_tilt_deg > 0.5), "the records should rock the block");
}

/// Housner's impact ratio r = 1 − (3/2) sin² α still holds with the real-size contact: the
/// rolling-resistance length of rock on concrete (0.1 mm) divided by R_max = 5 cm (2·10⁻³ R_max,
/// the largest it gets for a field rock) and by 5 m.
#[test]
fn housners_impact_ratio_holds_at_true_size() {
    use rocking_stones::dynamics::shaking::housner::{free_rocking, housner_ratio};
    let (b, d, h) = (0.5, 0.3, 1.0);
    let s = stone(generate::cuboid(2.0 * b, 2.0 * d, 2.0 * h));
    let start = s.position(bottom(&s)).unwrap();
    let r = housner_ratio(b, h);
    let alpha = (b / h).atan();
    for r_max_m in [0.05, 5.0] {
        let cycles = free_rocking(&s, start, &housner(r_max_m), b, h, 0.5 * alpha, 6.0);
        let ratios: Vec<f64> =
            cycles.windows(2).filter(|w| w[1].amplitude > 0.02).take(4).map(|w| w[1].omega0 / w[0].omega0).collect();
        assert!(ratios.len() >= 2, "{r_max_m} m: only {} impacts", ratios.len());
        let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
        assert!((mean / r - 1.0).abs() < 0.03, "{r_max_m} m: mean ratio {mean:.4} vs Housner {r:.4} ({ratios:?})");
    }
}

/// The command line of field rocks: one record → one JSON object with the outcome and the record's
/// measures; a folder × scales → runs.csv with one row per run; a missing column is a clear error.
#[test]
fn the_shake_command_runs_a_field_rock() {
    use std::process::Command;
    let dir = tempfile::tempdir().unwrap();
    // A 20 × 12 × 40 cm block, written in centimetres as OBJ.
    let m = generate::cuboid(20.0, 12.0, 40.0);
    let facet = format!("facet:{}", bottom(&stone(m.clone())));
    let mut obj = String::new();
    for v in &m.vertices {
        obj += &format!("v {} {} {}\n", v.x, v.y, v.z);
    }
    for t in &m.triangles {
        obj += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    let mesh = dir.path().join("block.obj");
    std::fs::write(&mesh, obj).unwrap();
    let recs = dir.path().join("records");
    std::fs::create_dir(&recs).unwrap();
    // One sine cycle of 0.3 g at 2 Hz: PGV = 2 a_p / ω_p.
    let mut csv = String::from("time_s,ax_g\n");
    for k in 0..=200 {
        let t = k as f64 * 0.005;
        csv += &format!("{t},{}\n", if t <= 0.5 { 0.3 * (2.0 * PI * 2.0 * t).sin() } else { 0.0 });
    }
    std::fs::write(recs.join("pulse.csv"), &csv).unwrap();
    std::fs::write(recs.join("pulse2.csv"), &csv).unwrap();
    let rec = recs.join("pulse.csv");
    let run = |args: &[&str]| Command::new(env!("CARGO_BIN_EXE_rocking")).args(args).output().unwrap();
    let (mesh_s, rec_s) = (mesh.to_str().unwrap(), rec.to_str().unwrap());
    let base = ["shake", mesh_s, "--pose", "as-scanned", "--length-unit", "cm", "--motion", rec_s];
    let out =
        run(&[&base[..], &["--columns", "time_s,ax_g", "--accel-unit", "g", "--azimuth", "0", "--json"]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["overturned"], serde_json::Value::Bool(false));
    // 0.3 g is below the block's uplift acceleration g·b/h (Housner: half-width b = 10 cm along
    // x, G at h = 20 cm), so it does not rock: it only leans on its soft contacts, by a tilt far
    // below its overturn angle atan(b/h) = 26.6° (measured 9e-4°; 0.55 g rocks it by 0.23°).
    let uplift_g = 0.10 / 0.20;
    assert!(0.3 < uplift_g);
    let tilt = j["max_tilt_deg"].as_f64().unwrap();
    assert!(tilt > 0.0 && tilt < 0.01, "max tilt {tilt}° under a pulse below the uplift acceleration");
    assert!((j["pga_g"].as_f64().unwrap() - 0.3).abs() < 1e-3);
    // PGV is of the processed record: the high-pass (0.08 Hz, order 5) takes T f_c (π/10)/sin(π/10)
    // of a pulse of duration T = 0.5 s from its closed form 2 a_p / ω_p (ground_motion::processing).
    let pgv = 2.0 * 0.3 * GRAVITY / (2.0 * PI * 2.0) * (1.0 - 0.5 * 0.08 * (PI / 10.0) / (PI / 10.0).sin());
    assert!((j["pgv_m_s"].as_f64().unwrap() / pgv - 1.0).abs() < 0.01, "PGV {} vs {pgv}", j["pgv_m_s"]);
    let r_max = (0.1f64 * 0.1 + 0.06 * 0.06 + 0.2 * 0.2).sqrt();
    assert!((j["r_max_m"].as_f64().unwrap() - r_max).abs() < 1e-9);
    // A folder × scales.
    let outdir = dir.path().join("out");
    let out = run(&[
        "shake",
        mesh_s,
        "--pose",
        &facet,
        "--length-unit",
        "cm",
        "--records",
        recs.to_str().unwrap(),
        "--columns",
        "time_s,ax_g",
        "--scales",
        "0.5,1,4",
        "-o",
        outdir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rows = std::fs::read_to_string(outdir.join("runs.csv")).unwrap();
    assert_eq!(rows.lines().count(), 1 + 2 * 3, "{rows}");
    assert!(outdir.join("fragility_surface.png").exists());
    // The journal: a header and one line per run. The same batch again into the same folder is
    // refused (finished work is never overwritten); a batch killed after two runs and one half-
    // written line, resumed with one more scale, keeps the two runs and ends with the runs of
    // one batch run in one go.
    let args = |out: &std::path::Path, scales: &'static str| -> Vec<String> {
        let v = ["shake", mesh_s, "--pose", &facet, "--length-unit", "cm", "--records", recs.to_str().unwrap()];
        let mut v: Vec<String> = v.iter().map(|s| s.to_string()).collect();
        v.extend(["--columns", "time_s,ax_g", "--scales", scales, "-o", out.to_str().unwrap()].map(String::from));
        v
    };
    let run_s = |v: &[String]| run(&v.iter().map(String::as_str).collect::<Vec<_>>());
    let journal = std::fs::read_to_string(outdir.join("runs.jsonl")).unwrap();
    assert_eq!(journal.lines().count(), 1 + 6);
    let again = run_s(&args(&outdir, "0.5,1,4"));
    assert!(!again.status.success() && String::from_utf8_lossy(&again.stderr).contains("--resume"));
    let cut = dir.path().join("cut");
    std::fs::create_dir(&cut).unwrap();
    let lines: Vec<&str> = journal.lines().collect();
    let partial = format!("{}\n{}\n{}\n{}", lines[0], lines[1], lines[2], &lines[3][..lines[3].len() / 2]);
    std::fs::write(cut.join("runs.jsonl"), partial).unwrap();
    let resumed = run_s(&[args(&cut, "0.5,1,4,8"), vec!["--resume".into()]].concat());
    assert!(resumed.status.success(), "{}", String::from_utf8_lossy(&resumed.stderr));
    assert!(String::from_utf8_lossy(&resumed.stderr).contains("2 finished run(s)"));
    let whole = dir.path().join("whole");
    assert!(run_s(&args(&whole, "0.5,1,4,8")).status.success());
    let csv = |d: &std::path::Path| std::fs::read_to_string(d.join("runs.csv")).unwrap();
    assert_eq!(csv(&cut), csv(&whole));
    assert_eq!(csv(&whole).lines().count(), 1 + 2 * 4);
    let journal = std::fs::read_to_string(cut.join("runs.jsonl")).unwrap();
    assert_eq!(journal.lines().count(), 1 + 8, "the cut line is gone, every run once");
    // Another rock's journal is refused.
    let other =
        run_s(&[args(&cut, "0.5"), vec!["--resume".into(), "--surface".into(), "rock-on-steel".into()]].concat());
    assert!(!other.status.success() && String::from_utf8_lossy(&other.stderr).contains("another batch"));
    // Bad column.
    let out = run(&[&base[..], &["--columns", "time_s,nope"]].concat());
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("pulse.csv") && err.contains("nope"), "{err}");
}

/// The pose prints as the command line spells it, and reads back.
#[test]
fn poses_print_as_the_command_line_spells_them() {
    for text in ["as-scanned", "facet:12", "quat:1,0,0.5,0"] {
        let pose: Pose = text.parse().unwrap();
        assert_eq!(pose.to_string(), text);
        assert_eq!(pose.to_string().parse::<Pose>().unwrap(), pose);
    }
    let e = "quat:0,0,0,0".parse::<Pose>().unwrap_err().to_string();
    assert!(e.contains("not all zero"), "{e}");
    assert!("facet:x".parse::<Pose>().is_err() && "upright".parse::<Pose>().is_err());
}

/// The command line says what it does not apply: options of the PGA sweep are refused
/// with a field rock, options of field rocks without one, and --length-unit with --size; the
/// bundled stone knows it is in millimetres (R_max = 178 mm in the JSON of a pushed run).
#[test]
fn options_that_do_not_apply_are_refused() {
    use std::process::Command;
    let run = |args: &[&str]| Command::new(env!("CARGO_BIN_EXE_rocking")).args(args).output().unwrap();
    let refused = |args: &[&str], word: &str| {
        let out = run(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} was accepted");
        assert!(err.contains(word), "{args:?}: {err}");
    };
    refused(&["shake", "--pose", "facet:3", "--trials", "5", "--motion", "x.csv"], "--trials");
    refused(&["shake", "--pose", "facet:3", "--pga-max", "0.5", "--motion", "x.csv"], "--pga-max");
    refused(&["shake", "--pose", "facet:3", "--equilibrium", "3", "--motion", "x.csv"], "--equilibrium");
    refused(&["shake", "--records", "dir"], "--pose");
    refused(&["shake", "--scales", "1,2"], "--pose");
    refused(&["perturb", "--length-unit", "mm", "--size", "0.2"], "--size");
    refused(&["perturb", "--contact-model", "gravel"], "expected one of surface, damped");
    refused(&["perturb", "--preset", "damped"], "--contact-model surface|damped");
    // The library names a parameter by its field; the command line by its flag.
    refused(&["perturb", "--dt", "1"], "error: --dt must be");
    refused(
        &["perturb", "--solver-iterations", "0"],
        "'--solver-iterations <SOLVER_ITERATIONS>': expected a whole number, at least 1",
    );
    refused(
        &["drop", "-n", "1", "--solver-iterations", "0"],
        "'--solver-iterations <SOLVER_ITERATIONS>': expected a whole number, at least 1",
    );
    refused(&["perturb", "--solver-iterations", "2000"], "error: --solver-iterations must be in 1..=1000");
    refused(&["shake", "--length-unit", "yard"], "--length-unit must be mm, cm, m, km, in");
    refused(&["perturb", "--size=-2"], "error: --size must be a positive length");
    refused(&["drop", "-n", "1", "--restitution", "1.5"], "error: --restitution must be in [0, 1], got 1.5");
    // The bundled stone at its true size, on the default surface pair.
    let out = run(&["perturb", "--equilibrium", "3", "-n", "1", "--eps-steps", "1", "--eps-min", "0.5", "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let sim = &j["params"]["sim"];
    assert_eq!(sim["friction"].as_f64(), Some(0.6), "stone on stone");
    let delta = sim["rolling_resistance"].as_f64().unwrap();
    // δ = 0.1 mm over R_max = 178 mm.
    assert!((delta - 1e-4 / 0.178).abs() < 2e-6, "δ/R_max = {delta}");
    assert_eq!(sim["angular_damping"].as_f64(), Some(0.0), "no global damping");
}

/// A ball under a one-sine pulse against its closed form, at two sizes: rolling
/// without slipping on a ground accelerating at a_g, the ball's centre accelerates at (2/7) a_g
/// (m a = F, I α = −F r, a = α r + a_g with I = (2/5) m r²), so at the end of the pulse, when the
/// ground is back at rest after moving D = a_p T²/(2π), the ball has rolled −(5/7) D relative to
/// it. The drive, the contact (rock on concrete, δ/R_max = 10⁻⁴ and 10⁻⁵) and the Froude
/// conversion of real time are all in the comparison. Measured: 0.15 % off at 1 m (δ = 10⁻⁴ R_max
/// slows the rolling), 0.005 % at 10 m.
#[test]
fn a_ball_under_a_pulse_rolls_back_five_sevenths_of_the_ground_motion() {
    use nalgebra::{Matrix3, UnitQuaternion};
    use rapier3d::prelude::SharedShape;
    use rocking_stones::dynamics::engine::body::Body;
    use rocking_stones::dynamics::engine::run::Drive;
    use rocking_stones::dynamics::engine::simulation::Simulation;
    use rocking_stones::dynamics::shaking::GroundDrive;
    use rocking_stones::ground_motion::synthetic::one_sine_pulse;
    use rocking_stones::Vec3;
    let ball = Body {
        corners: vec![Vec3::x(), -Vec3::x(), Vec3::y(), -Vec3::y(), Vec3::z(), -Vec3::z()],
        shape: SharedShape::ball(1.0),
        facet_normals: vec![Vec3::z()],
        inertia: Matrix3::identity() * 0.4,
        r_max: 1.0,
    };
    for r_max_m in [1.0, 10.0] {
        let mut p = rock_params(Surface::RockOnConcrete, r_max_m).unwrap();
        p.sim.contact.friction = 1.0;
        p.sim.contact.restitution = 0.0;
        // 0.2 g, 2 s of the scaled body: no slip needs a_g (2/7) < μ g.
        let tp = 2.0 * r_max_m.sqrt();
        let pulse = one_sine_pulse(0.2, tp, tp / 2000.0).unwrap();
        let d = 0.2 * GRAVITY * tp * tp / (2.0 * PI);
        let mut sim = Simulation::new(&ball, &p.sim, &UnitQuaternion::identity(), 1.0, &Vec3::zeros(), &Vec3::zeros());
        sim.set_contact_frequency(p.contact_frequency);
        sim.advance(60);
        let x0 = sim.ground_offset();
        let mut ground = GroundDrive::new(&pulse, 0.0, r_max_m, p.sim.numerics.dt);
        for step in 0..ground.active_steps() {
            ground.before_step(&mut sim, step);
            sim.step();
        }
        let rolled = (sim.ground_offset() - x0).x * r_max_m;
        eprintln!("R_max = {r_max_m} m: rolled {rolled:.5} m, closed form {:.5} m", -5.0 / 7.0 * d);
        assert!(
            (rolled / (-5.0 / 7.0 * d) - 1.0).abs() < 0.005,
            "R_max = {r_max_m} m: rolled {rolled} m relative to the ground, closed form {} m",
            -5.0 / 7.0 * d
        );
    }
}
