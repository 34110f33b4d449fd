//! Where do stones come to rest under each launch preset? The bundled
//! quarry stone and the scanned asteroid Castalia, N drops under `quasi-static`, `drop` and the
//! calibrated `throw` (flock certificate), the flock distributions side by side with the
//! quasi-static basin probabilities, with χ² and KL against them.
//!
//! Run: `cargo run --release --example presets_flocks [-- N]` (N = 1000) →
//! `results/presets_flocks/`.

use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::certificate::CertificateMode;
use rocking_stones::dynamics::drops::montecarlo::{run_and_summarize, DropReport, RunHeader, FORMAT};
use rocking_stones::dynamics::drops::params::Preset;
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::plot::{colors, draw_legend, legend_height, plain, style, Mark, FONT_FAMILY};
use std::fmt::Write as _;
use std::path::Path;

fn main() {
    let n: u64 = std::env::args().nth(1).map_or(1000, |s| s.parse().expect("N"));
    let out = Path::new("results/presets_flocks");
    std::fs::create_dir_all(out).expect("results folder");
    let meshes = [
        ("bundled stone E34", "data/default_pebble.ply", Surface::StoneOnStone),
        ("asteroid Castalia", "data/meshes/asteroid_4769_castalia_radar_hudson1994_pdstab.obj", Surface::StoneOnStone),
    ];
    let mut md = String::from(
        "# Flock distributions under the three launch presets\n\nRegenerate: `cargo run --release --example presets_flocks`.\n\n",
    );
    let _ = writeln!(
        md,
        "{n} drops per preset (seed 1, flock certificate), surface stone on stone, flocks at the automatic macro ν. \
         `static` is the quasi-static basin probability of the flock (exact). Bars: `<mesh>_flocks.png` (with 95 % intervals of the simulated fractions).\n"
    );
    let mut csv = String::from("mesh,flock,type,static,quasi_static,drop,throw\n");
    for (name, path, surface) in meshes {
        let a = Analysis::of_file(Path::new(path), &Options::default()).expect(path);
        let (nu, _) = a.macro_nu(&Options::default());
        let stone = Stone::new(&a, nu).expect("stone");
        let reports: Vec<DropReport> = Preset::ALL
            .iter()
            .map(|&preset| {
                let header = RunHeader {
                    format: FORMAT.into(),
                    mesh: name.into(),
                    mesh_fingerprint: String::new(),
                    seed: 1,
                    drops: n,
                    params: preset.params(surface),
                    certificate: CertificateMode::Flock,
                    preset: Some(preset.name().into()),
                    center_of_mass: None,
                    shard: rocking_stones::dynamics::drops::montecarlo::Shard::ALL,
                };
                let t = std::time::Instant::now();
                let r = run_and_summarize(&stone, &header).0;
                eprintln!("{name} {preset}: {:.1} s", t.elapsed().as_secs_f64());
                r
            })
            .collect();
        let _ = writeln!(md, "## {name} (ν = {nu:.3e}, {} flocks)\n", reports[0].flocks.len());
        let _ = writeln!(md, "| flock | type | static | quasi-static | drop | throw |\n|---|---|---|---|---|---|");
        for f in &reports[0].flocks {
            let cell = |r: &DropReport| {
                r.flocks
                    .iter()
                    .find(|g| g.id == f.id)
                    .map_or("0".into(), |g| format!("{:.3} [{:.3}, {:.3}]", g.fraction, g.ci95.0, g.ci95.1))
            };
            let frac = |r: &DropReport| r.flocks.iter().find(|g| g.id == f.id).map_or(0.0, |g| g.fraction);
            let kind = format!("{:?}", f.kind).to_lowercase();
            let _ = writeln!(
                md,
                "| {} | {kind} | {:.3} | {} | {} | {} |",
                f.id,
                f.static_probability,
                cell(&reports[0]),
                cell(&reports[1]),
                cell(&reports[2])
            );
            let _ = writeln!(
                csv,
                "{name},{},{kind},{:.4},{:.4},{:.4},{:.4}",
                f.id,
                f.static_probability,
                frac(&reports[0]),
                frac(&reports[1]),
                frac(&reports[2])
            );
        }
        let _ = writeln!(
            md,
            "\n| preset | χ² (dof, p) | KL (nats) | settled | mean simulated s to decision |\n|---|---|---|---|---|"
        );
        for (preset, r) in Preset::ALL.iter().zip(&reports) {
            let f = &r.fit_flocks;
            let _ = writeln!(
                md,
                "| {preset} | {:.1} ({}, {:.3}) | {:.4} | {}/{} | {} |",
                f.chi_square,
                f.dof,
                f.p_value,
                f.kl_divergence,
                r.settled,
                r.drops,
                r.mean_time_to_decision.map_or("–".into(), |t| format!("{t:.2}"))
            );
        }
        md.push('\n');
        let slug: String = name.chars().map(|c| if c.is_ascii_alphanumeric() { c } else { '_' }).collect();
        plot(&out.join(format!("{slug}_flocks.png")), name, &reports).expect("plot");
    }
    std::fs::write(out.join("flocks.csv"), csv).expect("csv");
    std::fs::write(out.join("README.md"), md).expect("README");
}

fn plot(path: &Path, title: &str, reports: &[DropReport]) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    let flocks = &reports[0].flocks;
    rocking_stones::plot::draw_png(path, (900, 560), |root| {
        root.fill(&WHITE)?;
        let root = root.titled(&format!("{title}: resting flocks by launch preset"), (FONT_FAMILY, style::TITLE))?;
        let (legend, area) = root.split_vertically(legend_height(1));
        let colours = [colors::GREEN, colors::ORANGE, colors::SKY, colors::BLUE];
        let labels = ["quasi-static basins (exact)", "quasi-static", "drop", "throw"];
        let mut entries: Vec<(Mark, String)> =
            colours.iter().zip(labels).map(|(&c, l)| (Mark::Box(c, 1.0), l.to_string())).collect();
        entries.push((Mark::Line(BLACK), "95 % interval".into()));
        draw_legend(&legend, &entries).map_err(|e| e.to_string())?;
        let top = flocks
            .iter()
            .map(|f| f.static_probability)
            .chain(reports.iter().flat_map(|r| r.flocks.iter().map(|g| g.ci95.1)))
            .fold(0.0, f64::max);
        let mut chart = ChartBuilder::on(&area)
            .margin(20)
            .margin_top(10)
            .x_label_area_size(50)
            .y_label_area_size(60)
            .build_cartesian_2d(-0.5f64..flocks.len() as f64 - 0.5, 0.0f64..(top * 1.1).min(1.0))?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(flocks.len() + 1)
            .x_label_formatter(&|x| {
                // A label under each group of bars (centred on the integers), none between them.
                let k = x.round();
                if (x - k).abs() > 1e-6 || k < 0.0 {
                    return String::new();
                }
                flocks
                    .get(k as usize)
                    .map_or(String::new(), |f| format!("{} {}", f.id, format!("{:?}", f.kind).to_lowercase()))
            })
            .y_label_formatter(&|y| plain(*y))
            .x_desc("flock (number, type)")
            .y_desc("fraction of drops")
            .label_style((FONT_FAMILY, style::TICK))
            .axis_desc_style((FONT_FAMILY, style::AXIS))
            .draw()?;
        let w = 0.8 / 4.0;
        for (s, &colour) in colours.iter().enumerate() {
            let group =
                |k: usize| reports.get(s.wrapping_sub(1)).and_then(|r| r.flocks.iter().find(|g| g.id == flocks[k].id));
            let value = |k: usize| -> f64 {
                if s == 0 {
                    flocks[k].static_probability
                } else {
                    group(k).map_or(0.0, |g| g.fraction)
                }
            };
            chart.draw_series((0..flocks.len()).map(|k| {
                let x0 = k as f64 - 0.4 + s as f64 * w;
                Rectangle::new([(x0, 0.0), (x0 + w * 0.9, value(k))], colour.filled())
            }))?;
            if s > 0 {
                chart.draw_series((0..flocks.len()).filter_map(|k| {
                    let g = group(k)?;
                    let x = k as f64 - 0.4 + (s as f64 + 0.45) * w;
                    Some(PathElement::new(vec![(x, g.ci95.0), (x, g.ci95.1)], BLACK.stroke_width(1)))
                }))?;
            }
        }
        Ok(())
    })?;
    Ok(())
}
