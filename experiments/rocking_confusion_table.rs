//! Rocking vs regular over many stones (paper §4.1): the paper's static class of every stable
//! micro-equilibrium against its dynamic class from pushes and spins (ε₅₀(flock) ≤ ε*), on
//! synthetic pebbles and the real quarry stones of `data/meshes`.
//!
//! Run: `cargo experiment rocking_confusion_table` → `results/rocking_confusion_table/`;
//! the README's prose is `experiments/readme/rocking_confusion_table.md`.

use experiments::harness;
use harness::{fixed, Context, Result, Results};
use rocking_stones::dynamics::pushes::{self, dynamic_class, rocking_auc, Confusion, Family, PerturbConfig};
use rocking_stones::dynamics::pushes::{PerturbReport, Robustness};
use rocking_stones::dynamics::resting::outcome::Threshold;
use rocking_stones::dynamics::resting::RestingParams;
use rocking_stones::dynamics::stone::Class;
use rocking_stones::prelude::*;
use rocking_stones::report::perturb::{plot_thresholds, threshold_points};
use rocking_stones::stats::{five_numbers, log_grid, min_max, GridSize};
use rocking_stones::study;
use serde_json::{json, Value};

const TRIALS: u32 = 30;
/// R_max of the synthetic pebbles (m), as in `fig11_rocking_vs_regular`.
const PEBBLE_R_MAX_M: f64 = 0.05;
/// The surface pair: stones on rock.
const SURFACE: Surface = Surface::StoneOnStone;

struct StoneRun {
    name: String,
    kind: &'static str,
    stone: Stone,
    r_max_m: f64,
    reports: Vec<PerturbReport>,
}

/// The synthetic pebbles and the real quarry stones of `data/meshes`, analysed.
fn inputs() -> Result<Vec<(String, &'static str, Analysis)>> {
    let mut inputs = Vec::new();
    for (axes, rough, seeds) in [
        ([1.0, 0.75, 0.5], 0.02, 0..3u64),
        ([1.0, 0.75, 0.5], 0.04, 0..2),
        ([1.0, 0.6, 0.4], 0.02, 0..2),
        ([1.0, 0.85, 0.7], 0.02, 0..2),
    ] {
        for seed in seeds {
            let (mesh, rep) = generate::pebble(axes, rough, 600, seed).into_solid_boundary()?;
            let name = format!("pebble {}:{}:{} r{} s{seed}", axes[0], axes[1], axes[2], rough);
            inputs.push((name, "synthetic", Analysis::of_solid(mesh, rep, &Options::default())?));
        }
    }
    let meshes = study::mesh_files(&harness::repo().join("data/meshes"))?;
    for p in meshes.iter().filter(|p| study::pebble_id(p).starts_with("stone_")) {
        let name = p.file_name().context("a mesh file name")?.to_string_lossy().into_owned();
        inputs.push((name, "real", Analysis::of_file(p, &Options::default())?));
    }
    Ok(inputs)
}

fn main() -> Result<()> {
    let common = harness::common_args("Static class against dynamic robustness over many stones.");
    let seed = common.seed_or(77);
    let out = Results::open("rocking_confusion_table", &common)?;
    let mut runs = Vec::new();
    for (name, kind, a) in inputs()? {
        let stone = Stone::new(&a, a.macro_nu(&Options::default()).0)?;
        // Real stones at their true size: the files in millimetres (A0, E34) are the ones whose
        // R_max exceeds 10 units, the others are in metres (`meshes/SOURCES.md`).
        let r_max_m = match kind {
            "real" if stone.body.r_max > 10.0 => stone.body.r_max * 1e-3,
            "real" => stone.body.r_max,
            _ => PEBBLE_R_MAX_M,
        };
        let params = RestingParams::on_surface(SURFACE, r_max_m)?;
        let all: Vec<usize> = (0..stone.stable().len()).collect();
        let mut reports = Vec::new();
        for family in [Family::Push, Family::Spin] {
            let epsilons = log_grid(1e-6, 1.0, GridSize::Points(13));
            let cfg =
                PerturbConfig { params: params.clone(), family, epsilons, trials: TRIALS, seed, epsilon_star: None };
            let t = std::time::Instant::now();
            let r = pushes::perturb_equilibria(&stone, &all, &cfg);
            let (n, secs) = (r.trials.len(), t.elapsed().as_secs_f64());
            eprintln!(
                "{name}: {family:?}, {} equilibria, {n} trials in {secs:.1} s; confusion {:?}",
                all.len(),
                r.confusion
            );
            reports.push(r);
        }
        runs.push(StoneRun { name, kind, stone, r_max_m, reports });
    }
    let mut header: Vec<String> = "stone,kind,nu,equilibrium,facet,flock,flock_type,static_class,stays_at_rest,\
                                   barrier_basin,barrier_flock"
        .split(',')
        .map(String::from)
        .collect();
    for f in ["push", "spin"] {
        let columns = ["eps50_micro", "eps50_flock", "eps50_flock_kind", "dynamic_class_nu", "dynamic_class_10nu"];
        header.extend(columns.map(|c| format!("{f}_{c}")));
    }
    out.csv("equilibria.csv", &header.iter().map(String::as_str).collect::<Vec<_>>(), csv_rows(&runs))?;
    for (fi, (family, what)) in [("push", "pushes"), ("spin", "spins")].into_iter().enumerate() {
        let points: Vec<_> = runs.iter().flat_map(|r| threshold_points(&r.reports[fi])).collect();
        let title = format!("All stones, {what}: ε₅₀ vs static barrier");
        plot_thresholds(&out.path(&format!("thresholds_vs_barriers_{family}.png")), &title, &points)?;
    }
    out.readme(include_str!("readme/rocking_confusion_table.md"), context(&runs, seed))
}

/// The runs of stones of `kind` (all if `None`).
fn of_kind<'a>(runs: &'a [StoneRun], kind: Option<&'a str>) -> impl Iterator<Item = &'a StoneRun> {
    runs.iter().filter(move |r| kind.is_none_or(|k| r.kind == k))
}

/// The equilibria of family `family` of the runs of stones of `kind` (all if `None`).
fn equilibria<'a>(runs: &'a [StoneRun], family: usize, kind: Option<&'a str>) -> impl Iterator<Item = &'a Robustness> {
    of_kind(runs, kind).flat_map(move |r| &r.reports[family].equilibria)
}

fn confusion(runs: &[StoneRun], family: usize, factor: f64, kind: Option<&str>) -> Confusion {
    let mut c = Confusion::default();
    for r in of_kind(runs, kind) {
        c.merge(&Confusion::of(&r.reports[family].equilibria, r.reports[family].epsilon_star * factor));
    }
    c
}

/// One row per equilibrium: its static barriers and, per family, ε₅₀ and the dynamic classes.
fn csv_rows(runs: &[StoneRun]) -> Vec<Vec<String>> {
    let e4 = |x: f64| format!("{x:.4e}");
    let th = |t: &Option<Threshold>| t.map_or(String::new(), |t| e4(t.value()));
    let kind = |t: &Option<Threshold>| t.map_or("", |t| t.kind_name()).to_string();
    let mut rows = Vec::new();
    for r in runs {
        for (ep, es) in r.reports[0].equilibria.iter().zip(&r.reports[1].equilibria) {
            let (q, stays) = (&ep.equilibrium, ep.rest.stays);
            let class = |e: &Robustness, f: f64| match dynamic_class(e.eps50_flock, r.stone.nu * f) {
                Some(c) if stays => c.name().to_string(),
                _ => String::new(),
            };
            let mut row = vec![r.name.clone(), r.kind.into(), e4(r.stone.nu), q.index.to_string()];
            row.extend([q.facet.to_string(), q.flock.to_string(), q.flock_kind.to_string(), q.class.to_string()]);
            row.extend([stays.to_string(), e4(q.basin_exit.epsilon), e4(q.flock_exit.epsilon)]);
            for e in [ep, es] {
                let f = e.eps50_flock;
                row.extend([th(&e.eps50_micro), th(&f), kind(&f), class(e, 1.0), class(e, 10.0)]);
            }
            rows.push(row);
        }
    }
    rows
}

/// The README's values.
fn context(runs: &[StoneRun], seed: u64) -> Value {
    let real = || of_kind(runs, Some("real"));
    let families: Vec<Value> = [(0, "pushes"), (1, "spins about the contact")]
        .into_iter()
        .map(|(fi, name)| {
            let tables = [
                ("all stones, ε* = ν", 1.0, None),
                ("all stones, ε* = 10 ν", 10.0, None),
                ("synthetic pebbles, ε* = ν", 1.0, Some("synthetic")),
                ("real stones, ε* = ν", 1.0, Some("real")),
            ]
            .map(|(title, factor, kind)| {
                let c = confusion(runs, fi, factor, kind);
                json!({ "title": title, "agreement": fixed(100.0 * c.agreement(), 0), "c": c })
            });
            let aucs = [(None, "all"), (Some("synthetic"), "synthetic"), (Some("real"), "real")].map(|(k, label)| {
                let (a, rock, reg) = rocking_auc(equilibria(runs, fi, k));
                json!({ "label": label, "auc": fixed(a, 3), "rock": rock, "reg": reg })
            });
            json!({ "name": name, "tables": tables, "aucs": aucs })
        })
        .collect();
    // The disagreements at ε* = ν (pushes): (stone kind, rocking→regular, flock barrier / ν,
    // ε₅₀(flock) / ν, flock type).
    let mut dis = Vec::new();
    for r in runs {
        for e in r.reports[0].equilibria.iter().filter(|e| e.rest.stays) {
            let (q, nu) = (&e.equilibrium, r.stone.nu);
            if dynamic_class(e.eps50_flock, nu).is_some_and(|d| d != q.class) {
                let eps50 = e.eps50_flock.map_or(f64::NAN, |t| t.value());
                let kind = q.flock_kind.to_string();
                dis.push((r.kind, q.class == Class::Rocking, q.flock_exit.epsilon / nu, eps50 / nu, kind));
            }
        }
    }
    let range = |v: Vec<f64>| {
        let (lo, hi) = min_max(v);
        format!("{lo:.2}–{hi:.2}")
    };
    let mut kinds: Vec<String> = dis.iter().map(|d| d.4.clone()).collect();
    kinds.sort();
    kinds.dedup();
    let rock_reg = dis.iter().filter(|d| d.1).count();
    let disagreements = (!dis.is_empty()).then(|| {
        json!({
            "count": dis.len(), "rock_reg": rock_reg, "reg_rock": dis.len() - rock_reg,
            "real": dis.iter().filter(|d| d.0 == "real").count(), "kinds": kinds.join(", "),
            "barriers": range(dis.iter().map(|d| d.2).collect()), "thresholds": range(dis.iter().map(|d| d.3).collect()),
        })
    });
    let per_stone: Vec<Value> = (runs.iter())
        .map(|r| {
            let (p, stable) = (&r.reports[0], r.stone.stable());
            let of = |class| stable.iter().filter(|e| e.class == class).count();
            let moving = p.equilibria.iter().filter(|e| !e.rest.stays).count();
            let counts = [stable.len(), of(Class::Regular), of(Class::Rocking), moving];
            json!({ "name": r.name, "nu": format!("{:.2e}", r.stone.nu), "counts": counts, "c": p.confusion, "b": p.barrier_check })
        })
        .collect();
    let mut ratios = Vec::new();
    for (fi, family) in [(0, "push"), (1, "spin")] {
        for class in [Class::Regular, Class::Rocking] {
            let v: Vec<f64> = (equilibria(runs, fi, None))
                .filter(|e| e.equilibrium.class == class)
                .filter_map(|e| e.ratio_flock)
                .collect();
            if let Some([lo, q1, median, q3, hi]) = five_numbers(&v).map(|q| q.map(|x| fixed(x, 1))) {
                ratios.push(json!({
                    "family": family, "class": format!("{class:?}"), "n": v.len(), "median": median,
                    "q1": q1, "q3": q3, "lo": lo, "hi": hi,
                }));
            }
        }
    }
    let checks = || runs.iter().flat_map(|r| r.reports.iter().map(|p| &p.barrier_check));
    let smallest = checks().map(|b| b.smallest_exit_ratio.unwrap_or(f64::INFINITY)).fold(f64::INFINITY, f64::min);
    json!({
        "stones": runs.len(), "synthetic": of_kind(runs, Some("synthetic")).count(), "real": real().count(),
        "trials": TRIALS, "seed": seed, "surface": SURFACE.to_string(), "pebble_r": PEBBLE_R_MAX_M.to_string(),
        "r_lo": fixed(real().map(|r| r.r_max_m).fold(f64::INFINITY, f64::min), 3),
        "r_hi": fixed(real().map(|r| r.r_max_m).fold(0.0, f64::max), 3),
        "families": families, "dis": disagreements, "per_stone": per_stone, "ratios": ratios,
        "check": {
            "below": checks().map(|b| b.below_basin).sum::<u64>(), "viol": checks().map(|b| b.basin_violations).sum::<u64>(),
            "fbelow": checks().map(|b| b.below_flock).sum::<u64>(), "fviol": checks().map(|b| b.flock_violations).sum::<u64>(),
            "smallest": format!("{smallest:.2}"), "rise": format!("{:.1e}", checks().map(|b| b.max_level_rise).fold(0.0, f64::max)),
        },
    })
}
