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
//! Run: `cargo run --release --example fig11_rocking_vs_regular` → `results/fig11_rocking_vs_regular/`.

use plotters::prelude::*;
use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::pushes::{self, Family, PerturbConfig, PerturbReport};
use rocking_stones::dynamics::resting::outcome::Threshold;
use rocking_stones::dynamics::resting::{default_pair, RestingParams};
use rocking_stones::dynamics::stone::{resting_orientation, Class, Stone};
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::generate;
use rocking_stones::planar::{self, Point2};
use rocking_stones::plot::FONT_FAMILY;
use rocking_stones::report;
use rocking_stones::stats::{log_grid, GridSize};
use rocking_stones::Vec3;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const TRIALS: u32 = 200;
const SEED: u64 = 2011;
/// R_max of the pebble (m): a 10 cm pebble, the size of the paper's hand experiments.
const R_MAX_M: f64 = 0.05;
/// The surface pair: a pebble on rock.
const SURFACE: Surface = Surface::StoneOnStone;

fn main() -> anyhow::Result<()> {
    let out = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("results/fig11_rocking_vs_regular");
    std::fs::create_dir_all(&out)?;
    let params = RestingParams::on_surface(SURFACE, R_MAX_M)?;
    let mut search = String::new();
    let (seed, analysis, stone, regular, rocking) = (0..50u64)
        .find_map(|seed| {
            let (mesh, rep) = generate::pebble([1.0, 0.75, 0.5], 0.02, 600, seed).into_solid_boundary().ok()?;
            let a = Analysis::of_solid(mesh, rep, &Options::default()).ok()?;
            let (nu, _) = a.macro_nu(&Options::default());
            let stone = Stone::new(&a, nu).ok()?;
            let n_rocking = stone.stable().iter().filter(|s| s.class == Class::Rocking).count();
            let (reg, rock) = default_pair(&stone, &params);
            let ok = rock.is_some_and(|r| stone.stable()[r].basin_exit.epsilon >= 1e-4) && reg.is_some();
            let _ = writeln!(
                search,
                "| {seed} | {} | {} | {n_rocking} | {} |",
                stone.stable().len(),
                stone.flock_kinds.len(),
                rock.map_or("none stays at rest".into(), |r| format!("{:.2e}", stone.stable()[r].basin_exit.epsilon))
            );
            ok.then(|| (seed, a, stone, reg.unwrap(), rock.unwrap()))
        })
        .expect("a pebble with a rocking equilibrium");
    eprintln!("pebble seed {seed}: regular {regular}, rocking {rocking}");
    let mut reports = Vec::new();
    for family in [Family::Push, Family::Spin] {
        let cfg = PerturbConfig {
            params: params.clone(),
            family,
            epsilons: log_grid(1e-6, 1.0, GridSize::Points(19)),
            trials: TRIALS,
            seed: SEED,
            epsilon_star: None,
        };
        let t = std::time::Instant::now();
        let r = pushes::perturb_equilibria(&stone, &[regular, rocking], &cfg);
        eprintln!("{family:?}: {} trials in {:.1} s", r.trials.len(), t.elapsed().as_secs_f64());
        eprint!("{}", report::perturb::summary(&r, "pebble"));
        reports.push(r);
    }
    // Outputs.
    let mut panels = Vec::new();
    for r in &reports {
        for e in &r.equilibria {
            let q = &e.equilibrium;
            panels.push(report::perturb::Panel {
                title: format!(
                    "{}: eq {} (facet {}, {} flock), {}",
                    match q.class {
                        Class::Regular => "regular",
                        Class::Rocking => "ROCKING",
                    },
                    q.index,
                    q.facet,
                    q.flock_kind,
                    r.family.name()
                ),
                curve: &e.curve,
                markers: report::perturb::barrier_markers(q.basin_exit.epsilon, q.flock_exit.epsilon, r.epsilon_star),
                note: None,
            });
        }
    }
    for ext in ["png", "svg"] {
        report::perturb::plot_curves(
            &out.join(format!("fig11_robustness.{ext}")),
            "Regular (left) vs rocking (right) stable micro-equilibrium: outcome against ε = KE/(m g R_max)",
            "ε (log scale)",
            true,
            &panels[..2],
        )?;
    }
    // Both families in one figure: 2 × 2.
    report::perturb::plot_curves(
        &out.join("fig11_robustness_push_and_spin.png"),
        "Regular vs rocking: pushes (top) and spins about the contact (bottom)",
        "ε (log scale)",
        true,
        &[rebuild(&panels[0]), rebuild(&panels[1]), rebuild(&panels[2]), rebuild(&panels[3])],
    )?;
    plot_poses(&out.join("fig11_poses.png"), &stone, &analysis, &[regular, rocking])?;
    let report = analysis.report("pebble", &Options::default());
    rocking_stones::report::plot_hull(&analysis, &report, &out.join("hull_flocks.png"))?;
    for r in &reports {
        report::perturb::write_curves_csv(&out.join(format!("curves_{}.csv", r.family.name())), r)?;
        report::perturb::write_thresholds_csv(&out.join(format!("thresholds_{}.csv", r.family.name())), r)?;
    }
    readme(&out.join("README.md"), seed, &stone, &reports, &search)?;
    Ok(())
}

/// A panel is not Clone (it borrows); rebuild one with the same content.
fn rebuild<'a>(p: &report::perturb::Panel<'a>) -> report::perturb::Panel<'a> {
    report::perturb::Panel { title: p.title.clone(), curve: p.curve, markers: p.markers.clone(), note: p.note.clone() }
}

/// Side views of the stone resting on each equilibrium (the photos of the paper's Figure 11):
/// the outline of the hull seen along y in its resting orientation, the ground, G and the
/// contact point straight below it.
fn plot_poses(path: &Path, stone: &Stone, a: &Analysis, which: &[usize]) -> anyhow::Result<()> {
    rocking_stones::plot::draw_png(path, (1200, 520), |root| {
        root.fill(&WHITE)?;
        let g = a.mass.center_of_mass;
        let r_max = stone.body.r_max;
        for (area, &i) in root.split_evenly((1, which.len())).iter().zip(which) {
            let s = &stone.stable()[i];
            let q = resting_orientation(&stone.body.facet_normals[s.facet as usize]);
            let pts: Vec<(f64, f64)> = a
                .hull
                .vertices
                .iter()
                .map(|p| {
                    let w = q * ((p - g) / r_max) + Vec3::new(0.0, 0.0, s.r_normalised);
                    (w.x, w.z)
                })
                .collect();
            let outline: Vec<(f64, f64)> =
                planar::Polygon::convex_hull(&pts.iter().map(|&(x, y)| Point2::new(x, y)).collect::<Vec<_>>())?
                    .vertices
                    .iter()
                    .map(|p| (p.x, p.y))
                    .collect();
            let title = format!(
                "{} equilibrium {} (facet {}): {:?} flock {}",
                match s.class {
                    Class::Regular => "regular",
                    Class::Rocking => "rocking",
                },
                s.index,
                s.facet,
                s.flock_kind,
                s.flock
            );
            let mut chart = ChartBuilder::on(area)
                .caption(title, (FONT_FAMILY, 18))
                .margin(15)
                .build_cartesian_2d(-1.2f64..1.2, -0.15f64..2.05)?;
            chart.draw_series(std::iter::once(Polygon::new(outline.clone(), RGBColor(190, 175, 150).filled())))?;
            chart.draw_series(std::iter::once(PathElement::new(
                outline.iter().chain(outline.first()).copied().collect::<Vec<_>>(),
                BLACK.stroke_width(1),
            )))?;
            chart
                .draw_series(std::iter::once(PathElement::new(vec![(-1.2, 0.0), (1.2, 0.0)], BLACK.stroke_width(2))))?;
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(0.0, 0.0), (0.0, s.r_normalised)],
                RGBColor(200, 40, 40).stroke_width(1),
            )))?;
            chart.draw_series(std::iter::once(Circle::new(
                (0.0, s.r_normalised),
                5,
                RGBColor(200, 40, 40).filled(),
            )))?;
            chart.draw_series(std::iter::once(Text::new(
                format!(
                    "G, R = {:.4} R_max; barriers: basin {:.1e}, flock {:.1e} m g R_max",
                    s.r_normalised, s.basin_exit.epsilon, s.flock_exit.epsilon
                ),
                (-1.15, 1.95),
                (FONT_FAMILY, 14),
            )))?;
        }
        Ok(())
    })?;
    Ok(())
}

fn th(t: &Option<Threshold>) -> String {
    match t {
        None => "–".into(),
        Some(Threshold::Below(x)) => format!("≤ {x:.2e}"),
        Some(Threshold::At(x)) => format!("{x:.2e}"),
        Some(Threshold::Above(x)) => format!("> {x:.2e}"),
    }
}

fn readme(path: &Path, seed: u64, stone: &Stone, reports: &[PerturbReport], search: &str) -> anyhow::Result<()> {
    let mut s = String::new();
    writeln!(s, "# Figure 11, dynamically: a regular and a rocking equilibrium of one pebble\n")?;
    writeln!(s, "Regenerate: `cargo run --release --example fig11_rocking_vs_regular`.\n")?;
    writeln!(
        s,
        "Pebble: `generate::pebble([1, 0.75, 0.5], roughness 0.02, n = 600, seed {seed})`, flocks at the automatic \
         macro ν = {:.3e} ({} flocks). Seed search (first seed with a rocking equilibrium that stays at rest in the \
         simulation and has a basin barrier ≥ 10⁻⁴):\n",
        stone.nu,
        stone.flock_kinds.len()
    )?;
    writeln!(
        s,
        "| seed | stable micro | flocks | rocking | best rocking basin barrier |\n|---|---|---|---|---|\n{search}"
    )?;
    writeln!(
        s,
        "Each point: {TRIALS} trials (seed {SEED}; trial k pushes at the same point in the same direction at every ε), \
         95 % Wilson intervals; ε = kinetic energy given / (m g R_max). Static barriers from the merge tree of the \
         support function (m g ΔR, ΔR = saddle height − R_F): the lowest energy at which the stone could leave the \
         basin of its micro-equilibrium, and its flock.\n"
    )?;
    let p = &reports[0].params.sim;
    writeln!(
        s,
        "Contact: the one of every resting run — a pebble of R_max = {R_MAX_M} m on rock ({SURFACE}: friction {}, \
         restitution {}, rolling resistance and torsional friction δ = 0.1 mm = {:.1e} R_max through the contact, no \
         global damping), 120 Hz contacts, dt 1/240 s (scaled), rest by speeds held {} s, cap {} s after the push.\n",
        p.contact.friction, p.contact.restitution, p.contact.rolling_resistance, p.rest.rest_time, p.numerics.max_time
    )?;
    writeln!(s, "![robustness](fig11_robustness.png)\n\n![poses](fig11_poses.png)\n")?;
    writeln!(
        s,
        "| family | equilibrium | class | flock | basin barrier | ε₅₀ leave micro | ×barrier | flock barrier | ε₅₀ topple | ×barrier | first topple | topples went to |"
    )?;
    writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|")?;
    for r in reports {
        for e in &r.equilibria {
            let q = &e.equilibrium;
            writeln!(
                s,
                "| {} | {} (facet {}) | {:?} | {} ({:?}) | {:.2e} | {} | {} | {:.2e} | {} | {} | {} | {} |",
                r.family.name(),
                q.index,
                q.facet,
                q.class,
                q.flock,
                q.flock_kind,
                q.basin_exit.epsilon,
                th(&e.eps50_micro),
                e.ratio_micro.map_or("–".into(), |x| format!("{x:.1}")),
                q.flock_exit.epsilon,
                th(&e.eps50_flock),
                e.ratio_flock.map_or("–".into(), |x| format!("{x:.1}")),
                e.first_topple.map_or("–".into(), |x| format!("{x:.2e}")),
                e.destinations.iter().map(|d| format!("{} ({:?}): {}", d.0, d.1, d.2)).collect::<Vec<_>>().join(", "),
            )?;
        }
    }
    writeln!(s)?;
    for r in reports {
        let b = &r.barrier_check;
        writeln!(
            s,
            "Barrier check ({}): {} trials below the basin barrier, {} left it; {} below the flock barrier, {} toppled; \
             smallest ε / basin barrier among trials that left: {}; largest rise of the energy level during a trial \
             {:.1e} R_max.",
            r.family.name(),
            b.below_basin,
            b.basin_violations,
            b.below_flock,
            b.flock_violations,
            b.smallest_exit_ratio.map_or("–".into(), |x| format!("{x:.2}")),
            b.max_level_rise
        )?;
    }
    writeln!(
        s,
        "\nFiles: `curves_{{push,spin}}.csv` (per ε: counts and probabilities with intervals), \
         `thresholds_{{push,spin}}.csv`, `fig11_robustness.{{png,svg}}` (pushes), \
         `fig11_robustness_push_and_spin.png`, `fig11_poses.png` (the stone resting on each), \
         `hull_flocks.png` (facets by flock, micro-equilibria as dots)."
    )?;
    std::fs::write(path, s)?;
    Ok(())
}
