//! Do drops settle? Every mesh of `data/meshes` and the bundled stone, thrown N times with the
//! default preset and no certificate, at the default step and again at the reference step
//! (`--reference`): settled fractions, times to rest, rests off the stable facet.
//!
//! Run: `cargo experiment drops_settling [-- N]` (N = 200) →
//! `results/drops_settling/`; the README's prose is `experiments/readme/drops_settling.md`.

use rocking_stones::prelude::*;
use rocking_stones::stats::quantile;
use std::{fmt::Write as _, time::Instant};

use experiments::harness;
use harness::{fixed, Result, Results};

fn main() -> Result<()> {
    let (n, common) = harness::count_args(
        "Do throws settle on every mesh, at the default and the reference step?",
        "Throws per mesh",
        200,
    );
    let seed = common.seed_or(1);
    let out = Results::open("drops_settling", &common)?;
    let data = harness::repo().join("data");
    let mut meshes = rocking_stones::study::mesh_files(&data.join("meshes"))?;
    meshes.push(data.join("default_pebble.ply"));
    let p = DropParams::default();
    let mut reference = p.clone();
    Preset::Throw.reference(&mut reference);
    let mut csv = String::from(
        "mesh,hull_facets,stable_facets,flocks,drops,settled,unsettled,settled_fraction,off_equilibrium,mean_time_s,\
         max_time_s,wall_s,reference_settled_fraction,reference_unsettled,reference_unsettled_median_height_above\n",
    );
    // Per mesh: its name, settled fractions (default, reference) and table row.
    let mut rows: Vec<(String, [f64; 2], [String; 8])> = Vec::new();
    let t_all = Instant::now();
    for m in &meshes {
        let name = m.file_name().unwrap_or_default().to_string_lossy().into_owned();
        let Ok(a) = Analysis::of_file(m, &Options::default()).inspect_err(|e| eprintln!("{name}: {e}")) else {
            continue;
        };
        let stone = Stone::new(&a, a.macro_nu(&Options::default()).0)?;
        let header = RunHeader {
            preset: Some("throw on steel-on-wood".into()),
            ..RunHeader::of_params(name.clone(), seed, n, p.clone(), CertificateMode::None)
        };
        let t0 = Instant::now();
        let (r, outcomes) = run_and_summarize(&stone, &header);
        let wall = t0.elapsed().as_secs_f64();
        let (rf, ref_outcomes) = run_and_summarize(&stone, &RunHeader { params: reference.clone(), ..header });
        // How far above its rest on the facet a drop still moving at the cap stands: ≈ 0 for a
        // stone still jiggling on its facet.
        let above: Vec<f64> = ref_outcomes.values().filter(|o| !o.settled).filter_map(|o| o.height_above).collect();
        let h_ref = quantile(&above, 0.5);
        let frac = [r.settled as f64 / r.drops as f64, rf.settled as f64 / rf.drops as f64];
        let max_t = outcomes.values().map(|o| o.time).fold(0.0, f64::max);
        let stable = stone.facet_equilibrium.iter().filter(|e| e.is_some()).count();
        let (facets, flocks, [f0, f1]) = (stone.body.facet_normals.len(), stone.flock_kinds.len(), frac);
        let (drops, settled, unsettled, off, mean) = (r.drops, r.settled, r.unsettled, r.off_equilibrium, r.mean_time);
        let ref_unsettled = rf.unsettled;
        writeln!(
            csv,
            "{name},{facets},{stable},{flocks},{drops},{settled},{unsettled},{f0:.4},{off},{mean:.2},{max_t:.2},{wall:.1},{f1:.4},{ref_unsettled},{h_ref:.2e}"
        )?;
        let h = if rf.unsettled == 0 { "—".to_string() } else { format!("{h_ref:.1e}") };
        eprintln!("{name}: {settled}/{drops} settled, {off} off, {wall:.1} s wall");
        let (off, mean, [s0, s1]) = (off.to_string(), fixed(mean, 2), frac.map(|f| fixed(f, 3)));
        rows.push((name.clone(), frac, [name, s0, unsettled.to_string(), off, mean, s1, ref_unsettled.to_string(), h]));
    }
    let total = t_all.elapsed().as_secs_f64();
    out.write("settling.csv", csv)?;
    // Per step (default, reference): how many meshes reach the 99.5 % target, and the least settled.
    let target = |k: usize| {
        let worst = rows.iter().min_by(|a, b| a.1[k].total_cmp(&b.1[k]));
        serde_json::json!({
            "ok": rows.iter().filter(|r| r.1[k] >= 0.995).count(),
            "worst": fixed(worst.map_or(1.0, |w| w.1[k]), 3),
            "mesh": worst.map_or("", |w| w.0.as_str()),
        })
    };
    let (l, c, s) = (&p.launch, &p.sim.contact, &p.sim);
    out.readme(
        include_str!("readme/drops_settling.md"),
        serde_json::json!({
            "meshes": rows.len(), "n": n,
            "height": l.height.to_string(), "speed": l.horizontal_speed.to_string(), "spin": l.spin.to_string(),
            "mu": c.friction.to_string(), "e": c.restitution.to_string(), "rolling": c.rolling_resistance.to_string(),
            "dt": fixed(s.numerics.dt, 5), "iterations": s.numerics.solver_iterations,
            "cap": s.numerics.max_time.to_string(), "v_rest": s.rest.rest_linear_speed.to_string(),
            "w_rest": s.rest.rest_angular_speed.to_string(), "t_rest": s.rest.rest_time.to_string(),
            "default": target(0), "reference": target(1), "reference_dt": fixed(reference.sim.numerics.dt, 5),
            "wall": fixed(total, 0), "rows": rows.iter().map(|r| &r.2).collect::<Vec<_>>(),
        }),
    )
}
