//! Paper Figure 11, dynamically: a regular and a rocking stable micro-equilibrium of one synthetic
//! pebble under pushes and spins of growing energy ε = KE / (m g R_max). The regular one is the
//! stone's deepest (smallest R), the rocking one the rocking equilibrium with the highest basin
//! barrier ([`default_pair`]).
//!
//! Run: `cargo experiment fig11_rocking_vs_regular` → `results/fig11_rocking_vs_regular/`;
//! the README's prose is `experiments/readme/fig11_rocking_vs_regular.md`.

use rocking_stones::dynamics::pushes::{self, Family, PerturbConfig};
use rocking_stones::dynamics::resting::{default_pair, RestingParams};
use rocking_stones::dynamics::stone::Class;
use rocking_stones::prelude::*;
use rocking_stones::report;
use rocking_stones::stats::{log_grid, GridSize};
use serde_json::json;

use experiments::harness;
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
    let loud = |c: Class| if c == Class::Rocking { "ROCKING" } else { c.name() };
    let panels: Vec<_> = (reports.iter())
        .flat_map(|r| r.equilibria.iter().map(move |e| (r, e)))
        .map(|(r, e)| {
            let q = &e.equilibrium;
            report::perturb::Panel {
                title: format!(
                    "{}: eq {} (facet {}, {} flock), {}",
                    loud(q.class),
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

    // Side views of the stone resting on each equilibrium (the photos of the paper's Figure 11).
    let mut poses = Vec::new();
    for i in [regular, rocking] {
        let s = &stone.stable()[i];
        let title = format!(
            "{} equilibrium {} (facet {}): {:?} flock {}",
            s.class.name(),
            s.index,
            s.facet,
            s.flock_kind,
            s.flock
        );
        poses.push(report::perturb::resting_pose(&analysis, &stone, i, title)?);
    }
    let title = "The pebble resting on its regular and its rocking equilibrium (side view)";
    Figure::new(title, 2, poses).save(&out.path("fig11_poses.png"), (1200, 520))?;
    let report = analysis.report("pebble", &Options::default());
    report::plot_hull(&analysis, &report, &out.path("hull_flocks.png"))?;
    for r in &reports {
        report::perturb::write_curves_csv(&out.path(&format!("curves_{}.csv", r.family.name())), r)?;
        report::perturb::write_thresholds_csv(&out.path(&format!("thresholds_{}.csv", r.family.name())), r)?;
    }

    let opt = |x: Option<f64>, f: fn(f64) -> String| x.map_or("–".into(), f);
    let rows = reports.iter().flat_map(|r| r.equilibria.iter().map(|e| report::perturb::robustness_row(r.family, e)));
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
            "rows": rows.collect::<Vec<_>>(),
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
