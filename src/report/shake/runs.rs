//! Field-rock runs under records ([`crate::dynamics::shaking::RecordRun`]): the columns of
//! `runs.csv`, its rows, and the summary of one run.

use crate::dynamics::shaking::{RecordRun, RockRun};
use crate::report::short_name;
use std::path::Path;

/// Columns of `runs.csv`: one row per (record, scale) run of a field rock.
pub const RUN_CSV_HEADER: [&str; 22] = [
    "record",
    "scale",
    "pga_g",
    "pgv_m_s",
    "pgv_over_pga_s",
    "pga_vertical_g",
    "overturned",
    "outcome",
    "max_tilt_deg",
    "slide_m",
    "start_equilibrium",
    "final_equilibrium",
    "final_flock",
    "settled",
    "time_s",
    "member",
    "contact_tolerance_m",
    "azimuth_deg",
    "sign",
    "friction",
    "restitution",
    "rolling_resistance_m",
];

/// The `runs.csv` row of a run (columns [`RUN_CSV_HEADER`]).
pub fn run_csv_row(r: &RecordRun) -> Vec<String> {
    let mut row = vec![
        r.motion.record.clone(),
        format!("{}", r.motion.scale),
        format!("{:.6}", r.motion.pga_g),
        format!("{:.6}", r.motion.pgv_m_s),
        format!("{:.6}", r.motion.pgv_over_pga_s),
        format!("{:.6}", r.motion.pga_vertical_g),
        r.rock.overturned.to_string(),
        r.rock.outcome.name().to_string(),
        format!("{:.4}", r.rock.max_tilt_deg),
        format!("{:.6}", r.rock.slide_m),
        r.rock.start_equilibrium.to_string(),
        r.rock.final_equilibrium.to_string(),
        r.rock.final_flock.to_string(),
        r.rock.settled.to_string(),
        format!("{:.3}", r.rock.time_s),
    ];
    // An ensemble member's inputs; blank for the rock as given.
    let member = r.member.map(|d| {
        [
            d.member.to_string(),
            format!("{:.6}", d.contact_tolerance_m),
            format!("{:.3}", d.azimuth_deg),
            format!("{}", d.sign),
            format!("{:.4}", d.friction),
            format!("{:.4}", d.restitution),
            format!("{:.3e}", d.rolling_resistance_m),
        ]
    });
    row.extend(member.unwrap_or_default());
    row
}

/// Write `runs.csv` (header and one row per run, in the batch's order).
pub fn write_runs_csv(path: &Path, runs: &[RecordRun]) -> crate::Result<()> {
    crate::report::write_csv(path, &RUN_CSV_HEADER, runs.iter().map(run_csv_row))
}

/// Write the files of one field-rock run into `dir`: `runs.csv` with its one row.
pub fn write_run_outputs(run: &RecordRun, dir: &Path) -> crate::Result<Vec<std::path::PathBuf>> {
    let mut out = crate::report::Folder::create(dir)?;
    out.file("runs.csv", |p| write_runs_csv(p, std::slice::from_ref(run)))?;
    Ok(out.written)
}

/// A readable summary of one field-rock run.
pub fn rock_run_summary(r: &RecordRun, mesh: &str) -> String {
    format!(
        "{} (R_max = {:.3} m) under {} × {}: PGA {:.3} g, {} PGV {:.3} m/s, PGV/PGA {:.3} s\n  \
         settled onto equilibrium {} with a tilt of {:.3}°; {} (outcome {}, final equilibrium {}, flock {}), \
         max tilt {:.2}°, slide {:.4} m{}\n  {}\n",
        short_name(mesh),
        r.rock.r_max_m,
        r.motion.record,
        r.motion.scale,
        r.motion.pga_g,
        r.motion.pgv_source.name(),
        r.motion.pgv_m_s,
        r.motion.pgv_over_pga_s,
        r.rock.start_equilibrium,
        r.rock.settling_tilt_deg,
        if r.rock.overturned { "OVERTURNED" } else { "standing" },
        r.rock.outcome,
        r.rock.final_equilibrium,
        r.rock.final_flock,
        r.rock.max_tilt_deg,
        r.rock.slide_m,
        if r.rock.settled { "" } else { " (still moving at the time cap)" },
        field_line(&r.rock, false)
    ) + &crate::report::depth_line(r.rock.deepest_penetration)
}

/// The record's direction and the ground of a field-rock run: "record's x axis at azimuth 30°
/// from the rock's x axis as it stands; on rock-on-concrete (a rock on a shake table's concrete)";
/// `drawn`: each member of an ensemble drew its own azimuth.
pub(crate) fn field_line(r: &RockRun, drawn: bool) -> String {
    let surface = r.surface.map_or(String::new(), |s| format!("; on {s} ({})", s.stands_for()));
    let azimuth = if drawn { "each member's azimuth".to_string() } else { format!("azimuth {}°", r.azimuth_deg) };
    format!("record's x axis at {azimuth} from the rock's x axis as it stands{surface}")
}
