//! Drops at vanishing energy converge to the quasi-static basin probabilities
//! ([`rocking_stones::basins`]), and move away from them as the drop height and the restitution
//! grow (large faces gain): a box 2 × 1.4 × 1 and a synthetic pebble with micro-facets, per drop
//! height and restitution, then the pebble for increasing damping.
//!
//! Run: `cargo experiment drops_quasistatic_limit` → `results/drops_quasistatic_limit/`;
//! the README's prose is `experiments/readme/drops_quasistatic_limit.md`.

use rocking_stones::dynamics::drops::montecarlo::Fit;
use rocking_stones::dynamics::drops::params::Launch;
use rocking_stones::dynamics::resting::RestingParams;
use rocking_stones::plot::style;
use rocking_stones::prelude::*;
use serde_json::json;

use experiments::harness;
use harness::{cell, fixed, Result, Results};

const DROPS: u64 = 2000;
const HEIGHTS: [f64; 6] = [0.002, 0.01, 0.03, 0.1, 0.3, 1.0];
const RESTITUTIONS: [f64; 3] = [0.0, 0.3, 0.6];
const DAMPINGS: [f64; 5] = [0.3, 1.0, 3.0, 10.0, 30.0];
/// The bodies: name in the tables, name in the figure.
const BODIES: [(&str, &str); 2] = [("box 2x1.4x1", "box 2 × 1.4 × 1"), ("pebble 1:0.72:0.5", "pebble 1 : 0.72 : 0.5")];

struct Row {
    body: usize,
    height: f64,
    restitution: f64,
    report: DropReport,
    seconds: f64,
}

/// `drops` drops of `stone` from rest at `params`, certified per facet: the report and the wall time (s).
fn run(stone: &Stone, mesh: &str, params: DropParams, seed: u64, drops: u64) -> (DropReport, f64) {
    let header = RunHeader::of_params(mesh, seed, drops, params, CertificateMode::Facet);
    let t = std::time::Instant::now();
    let (report, _) = run_and_summarize(stone, &header);
    (report, t.elapsed().as_secs_f64())
}

/// The damped drop from rest at `height` (restitution 0 unless changed).
fn at_rest(height: f64) -> DropParams {
    DropParams { launch: Launch::at_rest(height), sim: RestingParams::damped().sim }
}

fn main() -> Result<()> {
    let common = harness::common_args("Drops at vanishing energy against the quasi-static basins.");
    let (seed, damping_seed) = (common.seed_or(2024), common.seed_or(2024) + 1);
    let out = Results::open("drops_quasistatic_limit", &common)?;
    let meshes = [generate::cuboid(2.0, 1.4, 1.0), generate::pebble([1.0, 0.72, 0.5], 0.02, 1500, 3)];
    let mut rows = Vec::new();
    let mut stones = Vec::new();
    for (body, mesh) in meshes.into_iter().enumerate() {
        let (mesh, rep) = mesh.into_solid_boundary()?;
        let a = Analysis::of_solid(mesh, rep, &Options::default())?;
        let stone = Stone::new(&a, a.macro_nu(&Options::default()).0)?;
        let (name, qs) = (BODIES[body].0, stone.quasi_static());
        eprintln!("{name}: quasi-static error ±{:.1e} ({})", qs.error, qs.method);
        for &restitution in &RESTITUTIONS {
            for &height in &HEIGHTS {
                let mut params = at_rest(height);
                params.sim.contact.restitution = restitution;
                let (report, seconds) = run(&stone, name, params, seed, DROPS);
                eprintln!(
                    "  e = {restitution}, height {height}: KL flocks {:.4}, facets {:.4} ({seconds:.1} s)",
                    report.fit_flocks.kl_divergence,
                    report.fit_facets.as_ref().map_or(f64::NAN, |f| f.kl_divergence)
                );
                rows.push(Row { body, height, restitution, report, seconds });
            }
        }
        stones.push(stone);
    }
    // The pebble at the lowest height and no restitution, for increasing damping.
    let damping: Vec<(f64, DropReport)> = DAMPINGS
        .map(|d| {
            let mut params = at_rest(0.002);
            let c = &mut params.sim.contact;
            (c.restitution, c.linear_damping, c.angular_damping) = (0.0, d, d);
            params.sim.numerics.max_time = 60.0;
            let (report, _) = run(&stones[1], "pebble", params, damping_seed, 1000);
            eprintln!(
                "  damping {d}: KL flocks {:.4}, non-stable {}",
                report.fit_flocks.kl_divergence, report.off_equilibrium
            );
            (d, report)
        })
        .into();
    out.csv(
        "kl_vs_height.csv",
        &"body,restitution,height,drops,settled,certified,kl_flocks,chi2_flocks,p_flocks,kl_facets,chi2_facets,\
          p_facets,seconds"
            .split(',')
            .collect::<Vec<_>>(),
        rows.iter().map(|r| {
            let (f, facets) = (&r.report.fit_flocks, r.report.fit_facets.as_ref());
            let fit = |f: &Fit| [fixed(f.kl_divergence, 6), fixed(f.chi_square, 3), fixed(f.p_value, 4)];
            let (body, counts) = (BODIES[r.body].0.into(), [r.report.drops, r.report.settled, r.report.certified]);
            [body, r.restitution.to_string(), r.height.to_string()]
                .into_iter()
                .chain(counts.map(|n| n.to_string()))
                .chain(fit(f))
                .chain(facets.map(fit).unwrap_or_default())
                .chain([fixed(r.seconds, 2)])
        }),
    )?;
    // Box: the share of drops on each face against the static share, with the face's area
    // (a 2 × 1.4 × 1 box, from its normal).
    out.csv(
        "box_faces.csv",
        &["restitution", "height", "face_area", "fraction", "ci_lo", "ci_hi", "static"],
        rows.iter().filter(|r| r.body == 0).flat_map(|r| {
            r.report.facets.iter().map(|f| {
                // The box's 2 × 1.4 × 1 without its extent along the face's normal (x, y or z).
                let area = [1.4, 2.0, 2.8][f.normal.iamax()];
                [r.restitution.to_string(), r.height.to_string(), f64::to_string(&area)]
                    .into_iter()
                    .chain([f.fraction, f.ci95.0, f.ci95.1, f.static_probability].map(|x| fixed(x, 5)))
            })
        }),
    )?;
    plot(&out, &rows)?;
    let cell4 = |x: f64| cell(x, 4, false);
    let facets_kl = |r: &DropReport| r.fit_facets.as_ref().map_or("–".into(), |f| cell4(f.kl_divergence));
    out.readme(
        include_str!("readme/drops_quasistatic_limit.md"),
        json!({
            "drops": DROPS, "seed": seed, "damping_seed": damping_seed,
            "rows": rows.iter().map(|r| json!({
                "body": BODIES[r.body].0, "restitution": r.restitution.to_string(), "height": r.height.to_string(),
                "settled": r.report.settled, "kl": cell4(r.report.fit_flocks.kl_divergence),
                "chi2": fixed(r.report.fit_flocks.chi_square, 1), "p": fixed(r.report.fit_flocks.p_value, 3),
                "kl_facets": facets_kl(&r.report), "seconds": fixed(r.seconds, 1),
            })).collect::<Vec<_>>(),
            "damping": damping.iter().map(|(d, r)| json!({
                "damping": d.to_string(), "settled": r.settled, "off": r.off_equilibrium, "moving": r.unsettled,
                "kl": cell4(r.fit_flocks.kl_divergence), "kl_facets": facets_kl(r),
            })).collect::<Vec<_>>(),
        }),
    )
}

/// KL of the flock shares against drop height: the box solid with dots, the pebble dashed with
/// rings, one colour per restitution; wider lines first, so curves that coincide (the pebble's)
/// stay visible side by side.
fn plot(out: &Results, rows: &[Row]) -> Result<()> {
    let mut chart = Chart::new(
        Axis::log("drop height / R_max (log scale)", 1e-3, 2.0),
        Axis::log("KL(drops ‖ static), nats (log scale)", 3e-4, 0.2).space(70),
    )
    .title("Drops vs quasi-static basins: KL divergence of the flock shares against drop height");
    for (body, (_, label)) in BODIES.iter().enumerate() {
        for (k, &e) in RESTITUTIONS.iter().enumerate() {
            let (c, width) = (series_color(k), style::LINE + 2 - k as u32);
            let pts: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.body == body && r.restitution == e)
                .map(|r| (r.height, r.report.fit_flocks.kl_divergence.max(3e-4)))
                .collect();
            let label = format!("{label}, restitution {e}");
            chart = if body == 0 {
                chart.line_width(&pts, c, width).dots(&pts, c).legend(Mark::LineDot(c), label)
            } else {
                // The plot: 3.3 decades over ~900 px wide, 2.8 decades over ~500 px high.
                let dashed = chart.log_dashed(&pts, c, width, (3.3, 900.0), (2.8, 500.0));
                dashed.rings(&pts, c).legend(Mark::Dashed(c), label)
            };
        }
    }
    chart.save(&out.path("kl_vs_height.png"), (1000, 640))?;
    Ok(())
}
