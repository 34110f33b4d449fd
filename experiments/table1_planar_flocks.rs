//! Table 1 of the paper: flock contents of the arc-length discretised ellipse 1 : a with
//! N = 4k − 2 sides, measured for a grid of a and k, with the k → ∞ formula beside them; and the
//! smallest k from which the measured contents equal the formula for every k up to K_SCAN.
//!
//! Writes results/planar/table1.csv, table1_convergence.csv, table1_sqrt2.csv,
//! table1_convergence.png and table1.md (its prose is `experiments/readme/table1_planar_flocks.md`).
//! Run: `cargo experiment table1_planar_flocks`.

use rocking_stones::planar::{sides_for_k, table1_scan, PlanarAnalysis, PlanarReport, Sampling, Table1Scan};
use rocking_stones::prelude::*;
use serde_json::json;

use experiments::harness;
use harness::{Result, Results};

const A_GRID: [f64; 8] = [1.02, 1.05, 1.1, 1.2, 1.3, 1.5, 2.0, 3.0];
/// The grid of k; its last, k = 1000, stands for the limit in the README.
const K_GRID: [usize; 11] = [2, 3, 5, 10, 20, 30, 50, 100, 200, 500, 1000];
const K_SCAN: usize = 2000;
const SQRT2_K: [usize; 12] = [5, 10, 50, 100, 200, 300, 400, 500, 600, 700, 1000, 2000];

/// The report of the ellipse 1 : a with N = 4k − 2 sides, discretised in arc length.
fn measure(a: f64, k: usize) -> Result<PlanarReport> {
    Ok(PlanarAnalysis::of_ellipse(a, sides_for_k(k), Sampling::ArcLength)?.report(None))
}

fn fmt_flocks(v: &[(usize, usize)]) -> String {
    v.iter().map(|(s, u)| format!("{s}+{u}")).collect::<Vec<_>>().join(" ")
}

/// One axis ratio: the grid's measurements (with their match) and the scan of every k up to K_SCAN.
struct Ratio {
    a: f64,
    grid: Vec<(usize, bool, PlanarReport)>,
    scan: Table1Scan,
}

fn main() -> Result<()> {
    let common = harness::common_args("Flock contents of the discretised ellipse against Table 1's formula.");
    let out = Results::open("planar", &common)?;
    let mut ratios = Vec::new();
    for a in A_GRID {
        let scan = table1_scan(a, K_SCAN)?;
        let grid = K_GRID.iter().map(|&k| measure(a, k).map(|m| (k, scan.table.matches(&m), m)));
        let grid = grid.collect::<Result<_>>()?;
        eprintln!("a = {a}: k* = {}", scan.k_star());
        ratios.push(Ratio { a, grid, scan });
    }
    let pair = |p: (usize, usize)| format!("{}+{}", p.0, p.1);
    out.csv(
        "table1.csv",
        &("a k sides S U plateau_clear nu stable_flocks(S+U) unstable_flocks(S+U) formula_m formula_stable_flock \
           formula_unstable_flock formula_total_S matches_formula")
            .split_whitespace()
            .collect::<Vec<_>>(),
        ratios.iter().flat_map(|r| {
            r.grid.iter().map(move |(k, ok, m)| {
                [
                    format!("{}", r.a),
                    k.to_string(),
                    sides_for_k(*k).to_string(),
                    m.stable.to_string(),
                    m.unstable.to_string(),
                    m.plateau.is_some_and(|p| p.clear).to_string(),
                    format!("{:.4e}", m.nu),
                    fmt_flocks(&m.flock_contents.stable_flocks),
                    fmt_flocks(&m.flock_contents.unstable_flocks),
                    r.scan.table.m.to_string(),
                    pair(r.scan.table.stable_flock),
                    pair(r.scan.table.unstable_flock),
                    r.scan.table.total_stable.to_string(),
                    ok.to_string(),
                ]
            })
        }),
    )?;
    out.csv(
        "table1_convergence.csv",
        &["a", "m", "formula_total_S", "k_star", "last_mismatch_k", "mismatches_below_k_star"],
        ratios.iter().map(|r| {
            [
                format!("{}", r.a),
                r.scan.table.m.to_string(),
                r.scan.table.total_stable.to_string(),
                r.scan.k_star().to_string(),
                if r.scan.last_mismatch > 0 { r.scan.last_mismatch.to_string() } else { "-".into() },
                r.scan.mismatches.to_string(),
            ]
        }),
    )?;

    // The jump a = √2 (a²/(2(a²−1)) = 1 exactly).
    let sqrt2 = std::f64::consts::SQRT_2;
    // k, S, degenerate decisions, stable and unstable flocks.
    let mut jump = Vec::new();
    for k in SQRT2_K {
        let m = measure(sqrt2, k)?;
        let (stable, unstable) = (&m.flock_contents.stable_flocks, &m.flock_contents.unstable_flocks);
        let d = m.degenerate_decisions;
        jump.push([k.to_string(), m.stable.to_string(), d.to_string(), fmt_flocks(stable), fmt_flocks(unstable)]);
    }
    out.csv(
        "table1_sqrt2.csv",
        &["a", "k", "S", "degenerate_decisions", "stable_flocks(S+U)", "unstable_flocks(S+U)"],
        jump.iter().map(|row| [&[format!("{sqrt2}")], &row[..]].concat()),
    )?;
    plot(&out, &ratios)?;

    out.page(
        "table1.md",
        include_str!("readme/table1_planar_flocks.md"),
        json!({
            "k_scan": K_SCAN,
            "k_grid": K_GRID,
            "ratios": ratios.iter().map(|r| (r, &r.scan.table, &r.grid[K_GRID.len() - 1].2)).map(|(r, t, limit)| json!({
                "limit": [
                    format!("{}", r.a),
                    format!("{:.4}", r.a * r.a / (2.0 * (r.a * r.a - 1.0))),
                    t.m.to_string(),
                    format!("{} / {}", pair(t.stable_flock), fmt_flocks(&limit.flock_contents.stable_flocks)),
                    format!("{} / {}", pair(t.unstable_flock), fmt_flocks(&limit.flock_contents.unstable_flocks)),
                    format!("{} / {}", t.total_stable, limit.stable),
                    r.scan.k_star().to_string(),
                    r.scan.mismatches.to_string(),
                ],
                "a": format!("{}", r.a),
                "cells": r.grid.iter().map(|(_, ok, m)| format!("{}{}", m.stable, if *ok { " ✓" } else { "" })).collect::<Vec<_>>(),
                "s": t.total_stable,
            })).collect::<Vec<_>>(),
            "jump": jump,
        }),
    )?;
    println!("wrote results/planar/table1.{{csv,md}}, table1_convergence.{{csv,png}}, table1_sqrt2.csv");
    Ok(())
}

/// S against k for each a (log–log), each with its limit 8m + 2 dashed in the same colour.
fn plot(out: &Results, ratios: &[Ratio]) -> Result<()> {
    let s_of_k = |r: &Ratio| -> Vec<(f64, f64)> {
        r.scan.stable.iter().enumerate().map(|(i, &s)| ((i + 2) as f64, s as f64)).collect()
    };
    let ymax = ratios.iter().flat_map(|r| r.scan.stable.iter().map(|&s| s as f64)).fold(0.0, f64::max);
    let mut chart = Chart::new(Axis::log("k", 2.0, K_SCAN as f64), Axis::log("S (micro)", 1.0, ymax * 1.2))
        .title("Discretised ellipse: total S against k (N = 4k − 2); dashed: 8⌊a²/(2(a²−1))⌋ + 2");
    for (i, r) in ratios.iter().enumerate() {
        let lim = r.scan.table.total_stable as f64;
        chart = chart
            .legend(Mark::Line(series_color(i)), format!("a = {}", r.a))
            .line(&s_of_k(r), series_color(i))
            .dashed(&[(2.0, lim), (K_SCAN as f64, lim)], series_color(i));
    }
    chart.save(&out.path("table1_convergence.png"), (1000, 680))?;
    Ok(())
}
