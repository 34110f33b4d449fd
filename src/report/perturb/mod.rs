//! What a person reads of a perturbation run ([`crate::dynamics::pushes`]): the summary, the
//! curve/threshold/trial CSVs and the outcome-curve and threshold plots.

use super::{short_name, write_json, Folder};
use crate::dynamics::pushes::{Family, PerturbReport, Robustness, Trial};
use crate::dynamics::resting::outcome::Threshold;
use crate::dynamics::stone::Class;
use std::path::{Path, PathBuf};

mod plots;
mod pose;

pub use plots::{barrier_markers, panels, plot_curves, plot_thresholds, threshold_points, Panel};
pub use pose::{resting_outline, resting_pose};

fn fmt_threshold(t: &Option<Threshold>) -> String {
    match t {
        None => "-".into(),
        Some(Threshold::Below(x)) => format!("≤{x:.2e}"),
        Some(Threshold::At(x)) => format!("{x:.2e}"),
        Some(Threshold::Above(x)) => format!(">{x:.2e}"),
    }
}

/// A threshold as a table cell of a README: "≤ x", "x" or "> x" (x to 3 significant digits,
/// `1.23e-4`) for [`Threshold::Below`], [`Threshold::At`] and [`Threshold::Above`]; "–" for none.
pub fn threshold_cell(t: &Option<Threshold>) -> String {
    match t {
        None => "–".into(),
        Some(Threshold::Below(x)) => format!("≤ {x:.2e}"),
        Some(Threshold::At(x)) => format!("{x:.2e}"),
        Some(Threshold::Above(x)) => format!("> {x:.2e}"),
    }
}

/// One stable micro-equilibrium of a run of `family` as a row of a README table: the family,
/// "index (facet f)", the static class, "flock (its type)", the basin barrier, ε₅₀ to leave the
/// micro-equilibrium ([`threshold_cell`]) and its ratio to the barrier, the flock barrier, ε₅₀ to
/// leave the flock and its ratio, the smallest ε at which a trial toppled, and where the topples
/// went ("flock (type): count", comma-separated). Energies as `1.23e-4`, ratios to one decimal,
/// "–" where there is none; the class and the flock types capitalised ("Rocking", "Unstable").
pub fn robustness_row(family: Family, e: &Robustness) -> [String; 12] {
    let q = &e.equilibrium;
    let (e2, f1) = (|x: f64| format!("{x:.2e}"), |x: f64| format!("{x:.1}"));
    let opt = |x: Option<f64>, f: &dyn Fn(f64) -> String| x.map_or("–".into(), f);
    let went: Vec<String> =
        e.destinations.iter().map(|d| format!("{} ({}): {}", d.0, capitalised(d.1.name()), d.2)).collect();
    [
        family.name().to_string(),
        format!("{} (facet {})", q.index, q.facet),
        capitalised(q.class.name()),
        format!("{} ({})", q.flock, capitalised(q.flock_kind.name())),
        e2(q.basin_exit.epsilon),
        threshold_cell(&e.eps50_micro),
        opt(e.ratio_micro, &f1),
        e2(q.flock_exit.epsilon),
        threshold_cell(&e.eps50_flock),
        opt(e.ratio_flock, &f1),
        opt(e.first_topple, &e2),
        went.join(", "),
    ]
}

/// `word` with its first letter in upper case.
fn capitalised(word: &str) -> String {
    let mut c = word.chars();
    c.next().map_or(String::new(), |first| first.to_uppercase().chain(c).collect())
}

fn fmt_eps(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2e}")
    } else {
        "∞".into()
    }
}

/// One line that says which contact a resting run used (`dynamics::resting`), its step and cap
/// as multiples of √(R_max/g) and, for a stone of real R_max `r_max_m` metres, in seconds.
pub fn contact_line(p: &crate::dynamics::resting::RestingParams, r_max_m: Option<f64>) -> String {
    use super::names::number;
    let at = super::drops::Scaled { r_max_m };
    let c = &p.sim;
    let damping = if c.contact.angular_damping > 0.0 || c.contact.linear_damping > 0.0 {
        format!(
            "global damping {} angular, {} linear (the damped reference)",
            at.rate(c.contact.angular_damping),
            at.rate(c.contact.linear_damping)
        )
    } else {
        "no global damping".to_string()
    };
    let surface = match p.surface {
        Some(pair) => format!("{pair} ({}), ", pair.stands_for()),
        None => String::new(),
    };
    format!(
        "contact: {surface}friction {}, restitution {}, rolling resistance δ = {:.2e} R_max{} through the contact, \
         {damping}; dt {}, cap {}",
        number(c.contact.friction, 4),
        number(c.contact.restitution, 4),
        c.contact.rolling_resistance,
        r_max_m.map_or(String::new(), |l| format!(" = {} mm", number(c.contact.rolling_resistance * l * 1e3, 3))),
        at.time(c.numerics.dt),
        at.time(c.numerics.max_time)
    )
}

/// A readable summary of a run.
pub fn summary(r: &PerturbReport, mesh: &str) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{mesh}: {} perturbations, {} trials per ε on {} ε from {:.1e} to {:.1e}, seed {}",
        r.family.name(),
        r.trials_per_point,
        r.epsilons.len(),
        r.epsilons.first().copied().unwrap_or(f64::NAN),
        r.epsilons.last().copied().unwrap_or(f64::NAN),
        r.seed
    );
    let _ = writeln!(
        s,
        "ε = kinetic energy / (m g R_max); flocks at ν = {:.3e}; dynamic class at ε* = {:.3e}",
        r.nu, r.epsilon_star
    );
    let _ = writeln!(s, "{}", contact_line(&r.params, r.r_max_m));
    s += &super::depth_line(r.deepest_penetration);
    let _ = writeln!(
        s,
        "{:>5} {:>6} {:>6} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}",
        "eq", "facet", "flock", "static", "barrier", "ε50 micro", "barrier", "ε50 flock", "×barrier", "dynamic"
    );
    let _ = writeln!(
        s,
        "{:>5} {:>6} {:>6} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}",
        "", "", "", "class", "basin", "", "flock", "", "flock", "class"
    );
    for e in &r.equilibria {
        let q = &e.equilibrium;
        let cls = |c: Class| match c {
            Class::Regular => "regular",
            Class::Rocking => "rocking",
        };
        let _ = writeln!(
            s,
            "{:>5} {:>6} {:>4}{} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}",
            q.index,
            q.facet,
            q.flock,
            q.flock_kind.letter(),
            cls(q.class),
            fmt_eps(q.basin_exit.epsilon),
            if e.rest.stays { fmt_threshold(&e.eps50_micro) } else { "no rest".into() },
            fmt_eps(q.flock_exit.epsilon),
            fmt_threshold(&e.eps50_flock),
            e.ratio_flock.map_or("-".into(), |x| format!("{x:.1}")),
            e.dynamic_class.map_or("?", cls),
        );
    }
    let _ = writeln!(
        s,
        "  (flock: its number and type, S stable, U unstable, H saddle; static class: regular in a stable flock, \
         rocking in an unstable or saddle one;\n   barrier basin / flock: the static energy barrier ε to leave the \
         micro-equilibrium's basin / its flock (merge tree);\n   ε50: the energy at which half the trials left; \
         ×barrier: ε50 flock / flock barrier; no rest: the stone did not stay\n   on the facet when set down; \
         dynamic class: read at ε* = macro ν)"
    );
    let b = &r.barrier_check;
    let _ = writeln!(
        s,
        "barrier check: {} of {} trials below the basin barrier left it, {} of {} below the flock barrier toppled; \
         smallest ε/barrier among exits {}, among topples {}; largest energy-level rise {:.1e} R_max",
        b.basin_violations,
        b.below_basin,
        b.flock_violations,
        b.below_flock,
        b.smallest_exit_ratio.map_or("-".into(), |x| format!("{x:.2}")),
        b.smallest_topple_ratio.map_or("-".into(), |x| format!("{x:.2}")),
        b.max_level_rise
    );
    let c = &r.confusion;
    let _ = writeln!(
        s,
        "static vs dynamic class: regular→regular {}, regular→rocking {}, rocking→regular {}, rocking→rocking {}, undecided {}",
        c.regular_as_regular, c.regular_as_rocking, c.rocking_as_regular, c.rocking_as_rocking, c.undecided
    );
    s
}

/// Write the curves of a run as CSV (one row per equilibrium and ε).
pub fn write_curves_csv(path: &Path, r: &PerturbReport) -> crate::Result<()> {
    crate::report::write_csv(
        path,
        &[
            "equilibrium",
            "facet",
            "flock",
            "flock_type",
            "static_class",
            "family",
            "epsilon",
            "n",
            "same",
            "same_flock",
            "toppled",
            "unsettled",
            "p_same",
            "p_same_lo",
            "p_same_hi",
            "p_in_flock",
            "p_in_flock_lo",
            "p_in_flock_hi",
            "p_toppled",
            "p_toppled_lo",
            "p_toppled_hi",
            "barrier_basin",
            "barrier_flock",
        ],
        r.equilibria.iter().flat_map(|e| {
            let q = &e.equilibrium;
            e.curve.iter().map(move |c| {
                [
                    q.index.to_string(),
                    q.facet.to_string(),
                    q.flock.to_string(),
                    q.flock_kind.name().to_string(),
                    q.class.name().to_string(),
                    r.family.name().into(),
                    format!("{:.6e}", c.x),
                    c.n.to_string(),
                    c.same.to_string(),
                    c.same_flock.to_string(),
                    c.toppled.to_string(),
                    c.unsettled.to_string(),
                    format!("{:.4}", c.p_same),
                    format!("{:.4}", c.ci_same.0),
                    format!("{:.4}", c.ci_same.1),
                    format!("{:.4}", c.p_in_flock),
                    format!("{:.4}", c.ci_in_flock.0),
                    format!("{:.4}", c.ci_in_flock.1),
                    format!("{:.4}", c.p_toppled),
                    format!("{:.4}", c.ci_toppled.0),
                    format!("{:.4}", c.ci_toppled.1),
                    format!("{:.6e}", q.basin_exit.epsilon),
                    format!("{:.6e}", q.flock_exit.epsilon),
                ]
            })
        }),
    )
}

/// Write one row per equilibrium: static barriers, dynamic thresholds, classes.
pub fn write_thresholds_csv(path: &Path, r: &PerturbReport) -> crate::Result<()> {
    let th = |t: &Option<Threshold>| match t {
        None => (String::new(), String::new()),
        Some(t) => (format!("{:.6e}", t.value()), t.kind_name().into()),
    };
    let opt = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x:.6e}"));
    crate::report::write_csv(
        path,
        &[
            "equilibrium",
            "facet",
            "r_normalised",
            "flock",
            "flock_type",
            "static_class",
            "stays_at_rest",
            "barrier_basin",
            "basin_exit_equilibrium",
            "barrier_flock",
            "flock_exit_flock",
            "eps50_micro",
            "eps50_micro_kind",
            "eps50_flock",
            "eps50_flock_kind",
            "first_leave",
            "first_topple",
            "ratio_micro",
            "ratio_flock",
            "uplift_acceleration_g",
            "dynamic_class",
        ],
        r.equilibria.iter().map(|e| {
            let q = &e.equilibrium;
            let (m, mk) = th(&e.eps50_micro);
            let (f, fk) = th(&e.eps50_flock);
            [
                q.index.to_string(),
                q.facet.to_string(),
                format!("{:.6}", q.r_normalised),
                q.flock.to_string(),
                q.flock_kind.name().to_string(),
                q.class.name().to_string(),
                e.rest.stays.to_string(),
                format!("{:.6e}", q.basin_exit.epsilon),
                q.basin_exit.equilibrium.map_or(String::new(), |x| x.to_string()),
                format!("{:.6e}", q.flock_exit.epsilon),
                q.flock_exit.flock.map_or(String::new(), |x| x.to_string()),
                m,
                mk,
                f,
                fk,
                opt(e.first_leave),
                opt(e.first_topple),
                opt(e.ratio_micro),
                opt(e.ratio_flock),
                format!("{:.6e}", q.uplift_acceleration),
                e.dynamic_class.map_or(String::new(), |c| c.name().to_string()),
            ]
        }),
    )
}

/// Write every trial as CSV.
pub fn write_trials_csv(path: &Path, trials: &[Trial]) -> crate::Result<()> {
    crate::report::write_csv(
        path,
        &[
            "equilibrium",
            "family",
            "epsilon",
            "trial",
            "outcome",
            "final_facet",
            "final_equilibrium",
            "final_flock",
            "settled",
            "certified",
            "non_stable_facet",
            "time",
            "max_level_rise",
        ],
        trials.iter().map(|t| {
            [
                t.equilibrium.to_string(),
                t.family.name().into(),
                format!("{:.6e}", t.epsilon),
                t.trial.to_string(),
                t.outcome.name().into(),
                t.final_facet.map_or(String::new(), |x| x.to_string()),
                t.final_equilibrium.map_or(String::new(), |x| x.to_string()),
                t.final_flock.to_string(),
                t.settled.to_string(),
                t.certified.to_string(),
                t.non_stable_facet.to_string(),
                format!("{:.4}", t.time),
                format!("{:.3e}", t.max_level_rise),
            ]
        }),
    )
}

/// Write `perturb.json`, `curves.csv`, `thresholds.csv`, `trials.csv` and (if any curve)
/// `robustness.png/.svg` and `thresholds.png/.svg` into `dir`; `name` is the mesh named in captions.
pub fn write_outputs(r: &PerturbReport, name: &str, dir: &Path) -> crate::Result<Vec<PathBuf>> {
    let mut out = Folder::create(dir)?;
    out.file("perturb.json", |p| write_json(p, r))?;
    out.file("curves.csv", |p| write_curves_csv(p, r))?;
    out.file("thresholds.csv", |p| write_thresholds_csv(p, r))?;
    out.file("trials.csv", |p| write_trials_csv(p, &r.trials))?;
    let panels = panels(r);
    if !panels.is_empty() {
        let short = short_name(name);
        let caption = format!("{short}: robustness to {} perturbations (ε = KE / m g R_max)", r.family.name());
        for ext in ["png", "svg"] {
            out.file(&format!("robustness.{ext}"), |p| plot_curves(p, &caption, "ε (log scale)", true, &panels))?;
        }
        let caption = format!("{short}: dynamic thresholds vs static barriers");
        for ext in ["png", "svg"] {
            out.file(&format!("thresholds.{ext}"), |p| plot_thresholds(p, &caption, &threshold_points(r)))?;
        }
    }
    Ok(out.written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn threshold_cells_say_which_side_of_the_grid() {
        assert_eq!(threshold_cell(&Some(Threshold::Below(1e-6))), "≤ 1.00e-6");
        assert_eq!(threshold_cell(&Some(Threshold::At(0.000_123_4))), "1.23e-4");
        assert_eq!(threshold_cell(&Some(Threshold::Above(1.0))), "> 1.00e0");
        assert_eq!(threshold_cell(&None), "–");
    }

    #[test]
    fn a_robustness_row_reads_the_equilibrium_and_its_thresholds() {
        use crate::dynamics::resting::SettleCheck;
        use crate::dynamics::stone::{Exit, StableEquilibrium};
        use crate::equilibria::Kind;
        let exit = |epsilon| Exit { epsilon, facet: None, equilibrium: None, flock: None };
        let equilibrium = StableEquilibrium {
            index: 7,
            facet: 12,
            r: 1.0,
            r_normalised: 0.5,
            flock: 2,
            flock_kind: Kind::Unstable,
            class: Class::Rocking,
            basin_exit: exit(2e-5),
            flock_exit: exit(f64::INFINITY),
            uplift_acceleration: 0.3,
        };
        let rest = SettleCheck { stays: true, tilt: 0.0, sink: 0.0, speed: 0.0, angular_speed: 0.0, facet_reached: 12 };
        let e = Robustness {
            equilibrium,
            rest,
            curve: vec![],
            eps50_micro: Some(Threshold::At(3.1e-4)),
            eps50_flock: Some(Threshold::Above(1.0)),
            first_leave: Some(1e-4),
            first_topple: Some(0.1),
            ratio_micro: Some(15.5),
            ratio_flock: None,
            destinations: vec![(0, Kind::Stable, 3), (4, Kind::Saddle, 1)],
            dynamic_class: None,
        };
        let row = robustness_row(Family::Spin, &e);
        let want = ["spin", "7 (facet 12)", "Rocking", "2 (Unstable)", "2.00e-5", "3.10e-4", "15.5", "inf", "> 1.00e0"];
        assert_eq!(row[..9], want.map(String::from));
        assert_eq!(row[9..], ["–", "1.00e-1", "0 (Stable): 3, 4 (Saddle): 1"].map(String::from));
    }
}
