//! Do drops settle? Every mesh of `data/meshes` and the bundled stone, thrown N times
//! with the default preset (the calibrated `throw` on steel on wood) and **no certificate**: how
//! many come to rest before the time cap, how long it takes, how many stop off their stable
//! facet, and where the quasi-static descent puts them (no drop can land on a non-stable facet:
//! outcomes are read by the static theory). The default step is the preset's longest stable one
//! (1/120 s, measured on three bodies in `results/drops_dt/`); the same throws again at the
//! reference step 1/240 s (`--reference`, `Preset::reference`) show that the longer step does not
//! leave a mesh unsettled that the shorter one settles.
//!
//! Run: `cargo run --release --example drops_settling [-- N]` (N = 200) →
//! `results/drops_settling/`.

use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::certificate::CertificateMode;
use rocking_stones::dynamics::drops::launch::DropOutcome;
use rocking_stones::dynamics::drops::montecarlo::{run_and_summarize, RunHeader, FORMAT};
use rocking_stones::dynamics::drops::params::{DropParams, Preset};
use rocking_stones::dynamics::stone::Stone;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

fn main() {
    let n: u64 = std::env::args().nth(1).map_or(200, |s| s.parse().expect("N"));
    let out = Path::new("results/drops_settling");
    std::fs::create_dir_all(out).expect("results folder");
    let mut meshes: Vec<PathBuf> = std::fs::read_dir("data/meshes")
        .expect("data/meshes")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| rocking_stones::study::is_mesh_file(p))
        .collect();
    meshes.sort();
    meshes.push(PathBuf::from("data/default_pebble.ply"));
    let p = DropParams::default();
    let mut reference = p.clone();
    Preset::Throw.reference(&mut reference);
    let mut csv = String::from(
        "mesh,hull_facets,stable_facets,flocks,drops,settled,unsettled,settled_fraction,off_equilibrium,mean_time_s,max_time_s,wall_s,\
         reference_settled_fraction,reference_unsettled,reference_unsettled_median_height_above\n",
    );
    let mut worst = (1.0f64, String::new());
    let mut worst_ref = (1.0f64, String::new());
    let mut rows = Vec::new();
    let t_all = Instant::now();
    for m in &meshes {
        let name = m.file_name().unwrap().to_string_lossy().into_owned();
        let a = match Analysis::of_file(m, &Options::default()) {
            Ok(a) => a,
            Err(e) => {
                eprintln!("{name}: {e}");
                continue;
            }
        };
        let (nu, _) = a.macro_nu(&Options::default());
        let stone = Stone::new(&a, nu).expect("stone");
        let header = RunHeader {
            format: FORMAT.into(),
            mesh: name.clone(),
            mesh_fingerprint: String::new(),
            seed: 1,
            drops: n,
            params: p.clone(),
            certificate: CertificateMode::None,
            preset: Some("throw on steel-on-wood".into()),
            center_of_mass: None,
            shard: rocking_stones::dynamics::drops::montecarlo::Shard::ALL,
        };
        let t0 = Instant::now();
        let (r, outcomes) = run_and_summarize(&stone, &header);
        let wall = t0.elapsed().as_secs_f64();
        let (rf, ref_outcomes) = run_and_summarize(&stone, &RunHeader { params: reference.clone(), ..header.clone() });
        let frac_ref = rf.settled as f64 / rf.drops as f64;
        let h_ref = unsettled_height(ref_outcomes.values());
        if frac_ref < worst_ref.0 || worst_ref.1.is_empty() {
            worst_ref = (frac_ref, name.clone());
        }
        let frac = r.settled as f64 / r.drops as f64;
        let max_t = outcomes.values().map(|o| o.time).fold(0.0, f64::max);
        let stable = stone.facet_equilibrium.iter().filter(|e| e.is_some()).count();
        let _ = writeln!(
            csv,
            "{name},{},{stable},{},{},{},{},{frac:.4},{},{:.2},{max_t:.2},{wall:.1},{frac_ref:.4},{},{h_ref:.2e}",
            stone.body.facet_normals.len(),
            stone.flock_kinds.len(),
            r.drops,
            r.settled,
            r.unsettled,
            r.off_equilibrium,
            r.mean_time,
            rf.unsettled
        );
        eprintln!(
            "{name}: {}/{} settled, {} off, mean {:.2} s, {wall:.1} s wall",
            r.settled, r.drops, r.off_equilibrium, r.mean_time
        );
        if frac < worst.0 || worst.1.is_empty() {
            worst = (frac, name.clone());
        }
        rows.push((name, frac, r.unsettled, r.off_equilibrium, r.mean_time, frac_ref, rf.unsettled, h_ref));
    }
    std::fs::write(out.join("settling.csv"), csv).expect("write csv");
    let below = rows.iter().filter(|r| r.1 < 0.995).count();
    let below_ref = rows.iter().filter(|r| r.5 < 0.995).count();
    let mut md = String::new();
    let _ = writeln!(md, "# Do drops settle? {} meshes × {n} throws, certificate off\n", rows.len());
    let _ = writeln!(md, "Regenerate: `cargo run --release --example drops_settling`.\n");
    let _ = writeln!(
        md,
        "Preset: the default `throw` on steel on wood (height {} R_max, horizontal speed {} m/s, Gaussian spin {} rad/s rms, \
         μ {}, e {}, rolling resistance {} R_max, no global damping), dt = {:.5} s, {} solver iterations, cap {} s \
         (scaled to R_max = 1 m). Rest: speeds below {} m/s and {} rad/s for {} s.\n",
        p.launch.height,
        p.launch.horizontal_speed,
        p.launch.spin,
        p.sim.contact.friction,
        p.sim.contact.restitution,
        p.sim.contact.rolling_resistance,
        p.sim.numerics.dt,
        p.sim.numerics.solver_iterations,
        p.sim.numerics.max_time,
        p.sim.rest.rest_linear_speed,
        p.sim.rest.rest_angular_speed,
        p.sim.rest.rest_time
    );
    let _ = writeln!(
        md,
        "**{} of {} meshes reach the 99.5 % target**; the lowest settled fraction is {:.3} ({}). Total wall time {:.0} s.\n",
        rows.len() - below,
        rows.len(),
        worst.0,
        worst.1,
        t_all.elapsed().as_secs_f64()
    );
    let _ = writeln!(
        md,
        "**With `--reference`** (the same throws at the reference step dt = {:.5} s): {} of {} meshes reach \
         the target; the lowest settled fraction is {:.3} ({}). The last column is how far above its rest on the facet the \
         quasi-static descent reaches a drop still moving at the cap stands (median per mesh, R_max): near 0 for \
         a stone jiggling on its facet with speeds above the rest rule's {} m/s and {} rad/s, large for one still \
         rolling.\n",
        reference.sim.numerics.dt,
        rows.len() - below_ref,
        rows.len(),
        worst_ref.0,
        worst_ref.1,
        p.sim.rest.rest_linear_speed,
        p.sim.rest.rest_angular_speed,
    );
    let _ = writeln!(
        md,
        "| mesh | settled | unsettled | off equilibrium | mean time (s) | `--reference`: settled | `--reference`: unsettled | \
         `--reference` unsettled: height above the facet |\n|---|---|---|---|---|---|---|---|"
    );
    for r in &rows {
        let h = if r.6 == 0 { "—".to_string() } else { format!("{:.1e}", r.7) };
        let _ = writeln!(md, "| {} | {:.3} | {} | {} | {:.2} | {:.3} | {} | {h} |", r.0, r.1, r.2, r.3, r.4, r.5, r.6);
    }
    let _ = writeln!(
        md,
        "\n*Off equilibrium*: at rest, but G more than 10⁻³ R_max above its rest on the stable facet the quasi-static \
         descent reaches (held on a slope by friction or rolling resistance); counted at that facet. Every outcome is a \
         stable facet by construction (the descent of the support function), so no drop is counted on a non-stable facet."
    );
    std::fs::write(out.join("README.md"), md).expect("write README");
}

/// Median height of G above its rest on the facet (R_max) at the cap, over the drops that did not
/// settle (NaN when every drop settled): ≈ 0 for a stone still jiggling on its facet.
fn unsettled_height<'a>(outcomes: impl Iterator<Item = &'a DropOutcome>) -> f64 {
    let mut h: Vec<f64> = outcomes.filter(|o| !o.settled).filter_map(|o| o.height_above).collect();
    h.sort_by(f64::total_cmp);
    h.get(h.len() / 2).copied().unwrap_or(f64::NAN)
}
