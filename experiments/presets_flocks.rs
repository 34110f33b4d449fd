//! Where do stones come to rest under each launch preset? The bundled
//! quarry stone and the scanned asteroid Castalia, N drops under `quasi-static`, `drop` and the
//! calibrated `throw` (flock certificate), the flock distributions side by side with the
//! quasi-static basin probabilities, with χ² and KL against them.
//!
//! Run: `cargo experiment presets_flocks [-- N]` (N = 1000) →
//! `results/presets_flocks/`; the README's prose is `experiments/readme/presets_flocks.md`.

use rocking_stones::plot::colors::{BLUE, GREEN, ORANGE, SKY};
use rocking_stones::plot::BarSlot;
use rocking_stones::prelude::*;
use serde_json::json;

use experiments::harness;
use harness::{fixed, Result, Results};

fn lower(x: impl std::fmt::Debug) -> String {
    format!("{x:?}").to_lowercase()
}

fn main() -> Result<()> {
    let (n, common) =
        harness::count_args("Flock distributions under the three launch presets.", "Drops per preset", 1000);
    let seed = common.seed_or(1);
    let out = Results::open("presets_flocks", &common)?;
    let root = harness::repo();
    let (mut csv, mut meshes) = (Vec::new(), Vec::new());
    for (name, path) in [
        ("bundled stone E34", "data/default_pebble.ply"),
        ("asteroid Castalia", "data/meshes/asteroid_4769_castalia_radar_hudson1994_pdstab.obj"),
    ] {
        let a = Analysis::of_file(&root.join(path), &Options::default())?;
        let (nu, _) = a.macro_nu(&Options::default());
        let stone = Stone::new(&a, nu)?;
        let (mut reports, mut fits) = (Vec::new(), Vec::new());
        for preset in Preset::ALL {
            let whole =
                RunHeader::of_params(name, seed, n, preset.params(Surface::StoneOnStone), CertificateMode::Flock);
            let header = RunHeader { preset: Some(preset.name().into()), ..whole };
            let t = std::time::Instant::now();
            let r = run_and_summarize(&stone, &header).0;
            eprintln!("{name} {preset}: {:.1} s", t.elapsed().as_secs_f64());
            let f = &r.fit_flocks;
            fits.push(json!({
                "preset": preset.to_string(), "chi": fixed(f.chi_square, 1), "dof": f.dof, "p": fixed(f.p_value, 3),
                "kl": fixed(f.kl_divergence, 4), "settled": r.settled, "drops": r.drops,
                "time": r.mean_time_to_decision.map_or("–".into(), |t| fixed(t, 2)),
            }));
            reports.push(r);
        }
        let mut flocks = Vec::new();
        for f in &reports[0].flocks {
            let mut row = vec![name.into(), f.id.to_string(), lower(f.kind), fixed(f.static_probability, 4)];
            row.extend(reports.iter().map(|r| fixed(r.flock_fraction(f.id), 4)));
            csv.push(row);
            let cells: Vec<_> =
                reports.iter().map(|r| r.flock(f.id).map_or("0".into(), |g| g.fraction_with_ci(3))).collect();
            let p = fixed(f.static_probability, 3);
            flocks.push(json!({ "id": f.id, "kind": lower(f.kind), "static": p, "cells": cells }));
        }
        meshes.push(json!({ "name": name, "nu": format!("{nu:.3e}"), "flocks": flocks, "fits": fits }));
        plot(&out, name, &reports)?;
    }
    out.csv("flocks.csv", &["mesh", "flock", "type", "static", "quasi_static", "drop", "throw"], csv)?;
    out.readme(include_str!("readme/presets_flocks.md"), json!({ "n": n, "seed": seed, "meshes": meshes }))
}

/// Bars per flock: the exact basin probability, then each preset's fraction with its 95 % interval.
fn plot(out: &Results, name: &str, reports: &[DropReport]) -> Result<()> {
    let flocks = &reports[0].flocks;
    let labels: Vec<String> = flocks.iter().map(|f| format!("{} {}", f.id, lower(f.kind))).collect();
    let x = Axis::categories("flock (number, type)", labels);
    let top = flocks
        .iter()
        .map(|f| f.static_probability)
        .chain(reports.iter().flat_map(|r| r.flocks.iter().map(|g| g.ci95.1)))
        .fold(0.0, f64::max);
    let mut chart = Chart::new(x, Axis::linear("fraction of drops", 0.0, (top * 1.1).min(1.0)))
        .title(format!("{name}: resting flocks by launch preset"));
    let series = [("quasi-static basins (exact)", GREEN), ("quasi-static", ORANGE), ("drop", SKY), ("throw", BLUE)];
    for (s, (label, colour)) in series.into_iter().enumerate() {
        let slot = BarSlot { slot: s, slots: series.len(), width: 0.8 };
        let row = |k: usize| reports.get(s.wrapping_sub(1)).and_then(|r| r.flock(flocks[k].id));
        let value = |k: usize| if s == 0 { flocks[k].static_probability } else { row(k).map_or(0.0, |g| g.fraction) };
        let values: Vec<f64> = (0..flocks.len()).map(value).collect();
        let ci: Vec<_> =
            (0..flocks.len()).filter_map(|k| row(k).map(|g| (slot.centre(k), g.ci95.0, g.ci95.1))).collect();
        chart =
            chart.legend(Mark::Box(colour, 1.0), label).slot_bars(&values, slot, colour).y_bars(&ci, RGBColor(0, 0, 0));
    }
    let slug: String = name.chars().map(|c| if c.is_ascii_alphanumeric() { c } else { '_' }).collect();
    chart
        .legend(Mark::Line(RGBColor(0, 0, 0)), "95 % interval")
        .save(&out.path(&format!("{slug}_flocks.png")), (900, 560))?;
    Ok(())
}
