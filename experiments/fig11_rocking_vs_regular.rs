//! Paper Figure 11, dynamically: a synthetic pebble with a rocking equilibrium, one regular and
//! one rocking stable micro-equilibrium side by side, and how each responds to pushes and spins
//! of growing energy ε = KE / (m g R_max).
//!
//! The pebble: the first seed of `generate::pebble([1, 0.75, 0.5], roughness 0.02, 600 points)`
//! whose hierarchy (at the automatic macro ν) has a rocking equilibrium that stays at rest in the
//! simulation with a basin barrier of at least 10⁻⁴ m g R_max (a convincingly balanced one, not
//! a marginal dip). The regular equilibrium is the stone's deepest (smallest R), the rocking
//! one the rocking equilibrium with the highest basin barrier ([`default_pair`]).
//!
//! Run: `cargo run --release --example fig11_rocking_vs_regular` → `results/fig11_rocking_vs_regular/`;
//! the README's prose is `experiments/readme/fig11_rocking_vs_regular.md`.

use rocking_stones::dynamics::pushes::{self, Family, PerturbConfig};
use rocking_stones::dynamics::resting::outcome::Threshold;
use rocking_stones::dynamics::resting::{default_pair, RestingParams};
use rocking_stones::dynamics::stone::{resting_orientation, Class};
use rocking_stones::planar::{self, Point2};
use rocking_stones::prelude::*;
use rocking_stones::report;
use rocking_stones::stats::{log_grid, GridSize};
use serde_json::json;

#[path = "shared/harness.rs"]
mod harness;
use harness::{Context, Result, Results};

const TRIALS: u32 = 200;
/// R_max of the pebble (m): a 10 cm pebble, the size of the paper's hand experiments.
const R_MAX_M: f64 = 0.05;
/// The surface pair: a pebble on rock.
const SURFACE: Surface = Surface::StoneOnStone;

fn main() -> Result<()> {
    let common = harness::common_args("A regular and a rocking equilibrium of one pebble under pushes and spins.");
    let out = Results::open("fig11_rocking_vs_regular", &common)?;
    let trial_seed = common.seed_or(2011);
    let params = RestingParams::on_surface(SURFACE, R_MAX_M)?;
    let mut search = Vec::new();
    let (seed, analysis, stone, regular, rocking) = (0..50u64)
        .find_map(|seed| {
            let (mesh, rep) = generate::pebble([1.0, 0.75, 0.5], 0.02, 600, seed).into_solid_boundary().ok()?;
            let a = Analysis::of_solid(mesh, rep, &Options::default()).ok()?;
            let stone = Stone::new(&a, a.macro_nu(&Options::default()).0).ok()?;
            let (reg, rock) = default_pair(&stone, &params);
            let best = rock.map(|r| stone.stable()[r].basin_exit.epsilon);
            search.push(json!({
                "seed": seed,
                "stable": stone.stable().len(),
                "flocks": stone.flock_kinds.len(),
                "rocking": stone.stable().iter().filter(|s| s.class == Class::Rocking).count(),
                "best": best.map_or("none stays at rest".into(), |e| format!("{e:.2e}")),
            }));
            (best.is_some_and(|e| e >= 1e-4) && reg.is_some()).then(|| (seed, a, stone, reg.unwrap(), rock.unwrap()))
        })
        .context("no pebble with a rocking equilibrium")?;
    eprintln!("pebble seed {seed}: regular {regular}, rocking {rocking}");
    let mut reports = Vec::new();
    for family in [Family::Push, Family::Spin] {
        let epsilons = log_grid(1e-6, 1.0, GridSize::Points(19));
        let cfg = PerturbConfig {
            params: params.clone(),
            family,
            epsilons,
            trials: TRIALS,
            seed: trial_seed,
            epsilon_star: None,
        };
        let t = std::time::Instant::now();
        let r = pushes::perturb_equilibria(&stone, &[regular, rocking], &cfg);
        eprintln!("{family:?}: {} trials in {:.1} s", r.trials.len(), t.elapsed().as_secs_f64());
        eprint!("{}", report::perturb::summary(&r, "pebble"));
        reports.push(r);
    }
    // The panels: pushes then spins, each the regular then the rocking equilibrium.
    let class = |c: Class, loud: bool| match c {
        Class::Regular => "regular",
        Class::Rocking if loud => "ROCKING",
        Class::Rocking => "rocking",
    };
    let panels: Vec<_> = (reports.iter())
        .flat_map(|r| r.equilibria.iter().map(move |e| (r, e)))
        .map(|(r, e)| {
            let q = &e.equilibrium;
            report::perturb::Panel {
                title: format!(
                    "{}: eq {} (facet {}, {} flock), {}",
                    class(q.class, true),
                    q.index,
                    q.facet,
                    q.flock_kind,
                    r.family.name()
                ),
                curve: &e.curve,
                markers: report::perturb::barrier_markers(q.basin_exit.epsilon, q.flock_exit.epsilon, r.epsilon_star),
                note: None,
            }
        })
        .collect();
    let eps = "ε (log scale)";
    for ext in ["png", "svg"] {
        let title = "Regular (left) vs rocking (right) stable micro-equilibrium: outcome against ε = KE/(m g R_max)";
        report::perturb::plot_curves(&out.path(&format!("fig11_robustness.{ext}")), title, eps, true, &panels[..2])?;
    }
    let title = "Regular vs rocking: pushes (top) and spins about the contact (bottom)";
    report::perturb::plot_curves(&out.path("fig11_robustness_push_and_spin.png"), title, eps, true, &panels)?;

    // Side views of the stone resting on each equilibrium (the photos of the paper's Figure 11):
    // the outline of the hull seen along y in its resting orientation, the ground, G and the
    // contact point straight below it.
    let (g, red) = (analysis.mass.center_of_mass, RGBColor(200, 40, 40));
    let mut poses = Vec::new();
    for i in [regular, rocking] {
        let s = &stone.stable()[i];
        let q = resting_orientation(&stone.body.facet_normals[s.facet as usize]);
        let seen = |p: &rocking_stones::Point3| {
            let w = q * ((p - g) / stone.body.r_max) + Vec3::new(0.0, 0.0, s.r_normalised);
            Point2::new(w.x, w.z)
        };
        let hull = planar::Polygon::convex_hull(&analysis.hull.vertices.iter().map(seen).collect::<Vec<_>>())?;
        let outline: Vec<(f64, f64)> = hull.vertices.iter().chain(hull.vertices.first()).map(|p| (p.x, p.y)).collect();
        let (black, top) = (RGBColor(0, 0, 0), (0.0, s.r_normalised));
        let title = format!(
            "{} equilibrium {} (facet {}): {:?} flock {}",
            class(s.class, false),
            s.index,
            s.facet,
            s.flock_kind,
            s.flock
        );
        let text = format!(
            "G, R = {:.4} R_max; barriers: basin {:.1e}, flock {:.1e} m g R_max",
            s.r_normalised, s.basin_exit.epsilon, s.flock_exit.epsilon
        );
        poses.push(
            Chart::new(
                Axis::linear("x / R_max", -1.2, 1.2).no_grid(),
                Axis::linear("z / R_max", -0.15, 2.05).no_grid(),
            )
            .title(title)
            .polygon(&outline, RGBColor(190, 175, 150), 1.0)
            .line_width(&outline, black, 1)
            .line(&[(-1.2, 0.0), (1.2, 0.0)], black)
            .line_width(&[(0.0, 0.0), top], red, 1)
            .markers_sized(&[top], red, Marker::Dot, 5)
            .text(text, (-1.15, 1.95)),
        );
    }
    let title = "The pebble resting on its regular and its rocking equilibrium (side view)";
    Figure::new(title, 2, poses).save(&out.path("fig11_poses.png"), (1200, 520))?;
    let report = analysis.report("pebble", &Options::default());
    report::plot_hull(&analysis, &report, &out.path("hull_flocks.png"))?;
    for r in &reports {
        report::perturb::write_curves_csv(&out.path(&format!("curves_{}.csv", r.family.name())), r)?;
        report::perturb::write_thresholds_csv(&out.path(&format!("thresholds_{}.csv", r.family.name())), r)?;
    }

    let th = |t: &Option<Threshold>| match t {
        None => "–".into(),
        Some(Threshold::Below(x)) => format!("≤ {x:.2e}"),
        Some(Threshold::At(x)) => format!("{x:.2e}"),
        Some(Threshold::Above(x)) => format!("> {x:.2e}"),
    };
    let opt = |x: Option<f64>, f: fn(f64) -> String| x.map_or("–".into(), f);
    let (e2, f1) = (|x: f64| format!("{x:.2e}"), |x: f64| format!("{x:.1}"));
    let p = &reports[0].params.sim;
    out.readme(
        include_str!("readme/fig11_rocking_vs_regular.md"),
        json!({
            "seed": seed,
            "nu": format!("{:.3e}", stone.nu),
            "flocks": stone.flock_kinds.len(),
            "search": search,
            "trials": TRIALS,
            "trial_seed": trial_seed,
            "r_max": R_MAX_M.to_string(),
            "surface": SURFACE.to_string(),
            "friction": p.contact.friction.to_string(),
            "restitution": p.contact.restitution.to_string(),
            "rolling": format!("{:.1e}", p.contact.rolling_resistance),
            "rest_time": p.rest.rest_time.to_string(),
            "max_time": p.numerics.max_time.to_string(),
            "rows": reports.iter().flat_map(|r| r.equilibria.iter().map(move |e| (r, e))).map(|(r, e)| {
                let q = &e.equilibrium;
                let went: Vec<_> = e.destinations.iter().map(|d| format!("{} ({:?}): {}", d.0, d.1, d.2)).collect();
                [
                    r.family.name().to_string(),
                    format!("{} (facet {})", q.index, q.facet),
                    format!("{:?}", q.class),
                    format!("{} ({:?})", q.flock, q.flock_kind),
                    e2(q.basin_exit.epsilon),
                    th(&e.eps50_micro),
                    opt(e.ratio_micro, f1),
                    e2(q.flock_exit.epsilon),
                    th(&e.eps50_flock),
                    opt(e.ratio_flock, f1),
                    opt(e.first_topple, e2),
                    went.join(", "),
                ]
            }).collect::<Vec<_>>(),
            "checks": reports.iter().map(|r| {
                let b = &r.barrier_check;
                json!({
                    "family": r.family.name(),
                    "check": b,
                    "smallest": opt(b.smallest_exit_ratio, |x| format!("{x:.2}")),
                    "rise": format!("{:.1e}", b.max_level_rise),
                })
            }).collect::<Vec<_>>(),
        }),
    )
}
