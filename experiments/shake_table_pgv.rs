//! PGV of real shake-table tests: the velocity of standard strong-motion processing
//! (`ground_motion::processing`, what `Record::measures` reports) and the plain integral of the
//! acceleration as given (what it reported before), each against the PGV the table's
//! displacement transducer measured, over all tests of one scanned rock.
//!
//! The tests are not in the repository (GPL-3.0): give their folder — `tests.csv` and
//! `motions/TestNNN.csv` — as the argument. Without it the experiment says so and writes nothing.
//!
//! Run: `cargo experiment shake_table_pgv -- DIR` → `results/shake_table_pgv/`; the README's
//! prose is `experiments/readme/shake_table_pgv.md`.

use rocking_stones::ground_motion::processing::Processing;
use rocking_stones::ground_motion::read::{read_csv, AccelUnit};
use rocking_stones::prelude::{Axis, Chart, Mark, Marker, RGBColor};
use rocking_stones::stats::{median_range, quantile};
use serde::Deserialize;
use serde_json::json;
use std::path::PathBuf;

use experiments::harness::{self, fixed, Parser, Result, Results};

/// PGV of shake-table tests: processed and plainly integrated against the table's measurement.
#[derive(Parser)]
struct Args {
    /// The folder of the tests: tests.csv and motions/TestNNN.csv (not in the repository).
    dir: Option<PathBuf>,
    #[command(flatten)]
    common: harness::Common,
}

/// One row of tests.csv (other columns ignored).
#[derive(Deserialize)]
struct Test {
    test: u32,
    motion: String,
    pgv_m_s: f64,
}

/// The tests the README quotes one by one.
const QUOTED: [u32; 3] = [11, 100, 200];

/// The median and the 16 % and 84 % quantiles of `x`, three decimals each.
fn spread(x: &[f64]) -> serde_json::Value {
    json!({"median": fixed(median_range(x)[0], 3), "p16": fixed(quantile(x, 0.16), 3), "p84": fixed(quantile(x, 0.84), 3)})
}

fn main() -> Result<()> {
    let args = Args::parse();
    let Some((dir, tests)) = harness::shake_table_tests::<Test>("shake_table_pgv", &args.dir, "tests.csv, motions/")?
    else {
        return Ok(());
    };
    let p = Processing::default();
    let columns = "time_s,ax_g".parse()?;
    let (mut rows, mut points) = (Vec::new(), Vec::new());
    let (mut processed, mut old, mut quoted) = (Vec::new(), Vec::new(), Vec::new());
    let mut by_size: [(Vec<f64>, Vec<f64>); 2] = Default::default();
    for t in &tests {
        let record = read_csv(&dir.join(&t.motion), &columns, AccelUnit::G)?;
        let m = record.measures_processed(&p)?;
        let raw = record.velocity().iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max);
        let (r_new, r_old) = (m.pgv_m_s / t.pgv_m_s, raw / t.pgv_m_s);
        processed.push(r_new);
        old.push(r_old);
        let bin = &mut by_size[usize::from(t.pgv_m_s >= 0.05)];
        bin.0.push(r_new);
        bin.1.push(r_old);
        if QUOTED.contains(&t.test) {
            quoted.push(json!({"test": t.test, "measured": fixed(t.pgv_m_s, 3), "old": fixed(raw, 3), "processed": fixed(m.pgv_m_s, 3)}));
        }
        // Not the ratios: with the PGVs beside them they would carry the measured PGV out of the
        // tests' folder.
        rows.push([t.test.to_string(), fixed(m.pga_g, 4), fixed(raw, 4), fixed(m.pgv_m_s, 4)]);
        points.push((t.pgv_m_s, m.pgv_m_s, raw));
    }
    let out = Results::open("shake_table_pgv", &args.common)?;
    out.csv("pgv.csv", &harness::columns("test,pga_g,pgv_m_s_integrated,pgv_m_s_processed"), &rows)?;
    // The scatter plot's points: (measured, computed).
    let new_pts: Vec<(f64, f64)> = points.iter().map(|p| (p.0, p.1)).collect();
    let old_pts: Vec<(f64, f64)> = points.iter().map(|p| (p.0, p.2)).collect();
    let all = new_pts.iter().chain(&old_pts).flat_map(|&(a, b)| [a, b]).filter(|v| *v > 0.0);
    let (lo, hi) = all.fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    let (lo, hi) = (lo / 1.5, hi * 1.5);
    let (grey, blue) = (RGBColor(170, 170, 170), RGBColor(40, 90, 200));
    Chart::new(
        Axis::log("PGV measured by the table's displacement transducer (m/s)", lo, hi),
        Axis::log("PGV from the table's acceleration (m/s)", lo, hi),
    )
    .title(format!("PGV of {} shake-table tests", tests.len()))
    .markers(&old_pts, grey, Marker::Ring)
    .markers(&new_pts, blue, Marker::Dot)
    .dashed(&[(lo, lo), (hi, hi)], RGBColor(0, 0, 0))
    .legend(Mark::Ring(grey), "integrated as given (before)")
    .legend(Mark::Dot(blue), format!("processed: high-pass {} Hz, order {}, zero phase", p.corner_hz, p.order))
    .legend(Mark::Dashed(RGBColor(0, 0, 0)), "equal")
    .save(&out.path("pgv_scatter.png"), (900, 800))?;
    let size =
        |k: usize| json!({"n": by_size[k].0.len(), "processed": spread(&by_size[k].0), "old": spread(&by_size[k].1)});
    eprintln!("processed/measured {}; integrated/measured {}", spread(&processed), spread(&old));
    out.readme(
        include_str!("readme/shake_table_pgv.md"),
        json!({
            "n": tests.len(), "corner": p.corner_hz, "order": p.order, "pad_s": fixed(1.5 * p.order as f64 / p.corner_hz, 1),
            "processed": spread(&processed), "old": spread(&old), "small": size(0), "large": size(1),
            "within2_new": processed.iter().filter(|r| (0.5..=2.0).contains(*r)).count(),
            "within2_old": old.iter().filter(|r| (0.5..=2.0).contains(*r)).count(),
            "quoted": quoted,
            "max_measured": fixed(tests.iter().map(|t| t.pgv_m_s).fold(0.0, f64::max), 2),
            "max_processed": fixed(new_pts.iter().map(|p| p.1).fold(0.0, f64::max), 2),
        }),
    )
}
