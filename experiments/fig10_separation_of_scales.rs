//! Paper Figure 10 (separation of scales) on real stones and on a synthetic pebble: micro-
//! equilibria and the Morse–Smale graph G(0) (10A), the log ν – n(ν) staircase with its plateau
//! (10B), the flocks at the plateau's ν (10C), and the rocking equilibria found.
//!
//! Run: `cargo experiment fig10_separation_of_scales` → `results/fig10/`; the
//! README's prose is `experiments/readme/fig10_separation_of_scales.md`.

use rocking_stones::prelude::*;
use rocking_stones::report::analysis::write_files;

use experiments::harness;
use harness::{Result, Results};

fn main() -> Result<()> {
    let common = harness::common_args("Separation of scales on three quarry stones and a synthetic pebble.");
    let out = Results::open("fig10", &common)?;
    let meshes = harness::repo().join("data/meshes");
    let opts = Options::default();
    let mut runs = Vec::new();
    for name in ["E34", "AAA", "E22"] {
        let file = meshes.join(format!("stone_quarry_ibois_{name}_lowres_bin.ply"));
        runs.push((format!("stone {name}_lowres"), Analysis::of_file(&file, &opts)?));
    }
    let (mesh, rep) = generate::pebble([1.0, 0.72, 0.48], 0.02, 6000, 3).into_solid_boundary()?;
    runs.push(("synthetic pebble 1:0.72:0.48, roughness 0.02".into(), Analysis::of_solid(mesh, rep, &opts)?));
    let mut chart = Chart::new(Axis::log("ν (log scale)", 1e-7, 1.0), Axis::linear("n(ν)", 0.0, 1.05))
        .title("Separation of scales: n(ν) = N(ν)/N(0) (paper Fig. 10B)");
    let mut rows = Vec::new();
    for (k, (name, a)) in runs.iter().enumerate() {
        let slug: String = name.chars().map(|c| if c.is_ascii_alphanumeric() { c } else { '_' }).collect();
        let r = a.report(name, &opts);
        write_files(a, &r, &out.path(&slug))?;
        let steps: Vec<_> =
            r.staircase.iter().flat_map(|s| [(s.nu_lo.max(1e-7), s.n), (s.nu_hi.clamp(1e-7, 1.0), s.n)]).collect();
        chart = chart.line(&steps, series_color(k)).legend(Mark::Line(series_color(k)), r.file.clone());
        let plateau = |f: &dyn Fn(&_) -> String| r.plateau.as_ref().map_or("—".into(), f);
        let (mi, ma) = (&r.micro, &r.r#macro);
        rows.push(serde_json::json!({
            "slug": slug, "file": r.file, "rocking": r.rocking.len(),
            "micro": format!("{}/{}/{}", mi.stable, mi.unstable, mi.saddle),
            "macro": format!("{}/{}/{}", ma.stable, ma.unstable, ma.saddle),
            "range": plateau(&|p| format!("{:.2e} – {:.2e}", p.nu_lo, p.nu_hi)),
            "decades": plateau(&|p| format!("{:.2}", p.decades)),
            "clarity": plateau(&|p| format!("{:.2}", p.clarity)),
            "clear": plateau(&|p| p.clear.to_string()),
        }));
    }
    chart.save(&out.path("n_nu_all.png"), (1000, 600))?;
    out.readme(include_str!("readme/fig10_separation_of_scales.md"), serde_json::json!({ "rows": rows }))
}
