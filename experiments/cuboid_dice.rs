//! Calibration of the `throw` preset on real dice: square cuboid steel dice
//! y × y × x thrown by hand, `data/cuboid_dice_throws.csv` (Mathematical Gazette 97,
//! note 97.16, Table 1: seven of its fifteen dice).
//!
//! The throw has three free parameters, the release height H (in R_max), the rms angular speed
//! Ω of its Gaussian spin (rad/s of the body scaled to R_max = 1 m) and its horizontal speed v
//! (m/s, scaled); the contact (steel on wood: μ = 0.4, e = 0.5, δ = 0.2 mm for a die with
//! y = 16 mm) is fixed from published ranges, not fitted. On a grid of (H, Ω, v) every die is
//! thrown `N` times (common random numbers: throw i of every grid point uses stream (seed, i)),
//! and the binomial log-likelihood of the measured counts
//!
//! ```text
//! ln L(H, Ω) = Σ_dice  k ln p(H, Ω) + (n − k) ln(1 − p(H, Ω)),   k = round(p_measured · n)
//! ```
//!
//! is maximised. The Monte Carlo noise of ln L (a misfitting model turns the binomial noise of
//! the simulated p into ln L noise of ±10) is measured by re-running the best point with
//! another seed; the uncertainty of each parameter is the range of grid values whose ln L lies
//! within twice that noise of the best. The best grid point is then re-run
//! with 4N throws per die for the residuals, and the curve p(square) against x/y is drawn for the
//! calibrated throw (with its 95 % Monte Carlo band), the `drop` preset and the quasi-static
//! basins.
//!
//! Calibration, not validation: the seven dice are the data the throw is fitted to.
//!
//! Run: `cargo run --release --example cuboid_dice [-- N [H,… [Ω,… [v,…]]]]` (N = 400, as
//! the committed results; the default grid was refined from coarser grids over H 0.5–16,
//! Ω 0–45, v 1–8) →
//! `results/cuboid_dice/`.

use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::certificate::CertificateMode;
use rocking_stones::dynamics::drops::montecarlo::{run_and_summarize, RunHeader, FORMAT};
use rocking_stones::dynamics::drops::params::{DropParams, Preset, THROW_HEIGHT, THROW_HORIZONTAL_SPEED, THROW_SPIN};
use rocking_stones::dynamics::engine::params::{Flight, REFERENCE_DT};
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::generate;
use rocking_stones::plot::{colors, draw_legend, legend_height, plain, style, Mark, FONT_FAMILY};
use rocking_stones::stats::{chi_square_homogeneity, wilson};
use statrs::distribution::{ChiSquared, ContinuousCDF};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// Side y of the square faces of the steel dice (m): not given by the source; 16 mm, a common
/// die. Only the rolling-resistance length depends on it.
const DIE_Y_M: f64 = 0.016;

struct Die {
    x: f64,
    p: f64,
    n: u64,
}

fn read_dice(path: &Path) -> Vec<Die> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.trim().parse().expect("a number")).collect();
            Die { x: v[0], p: v[1], n: v[2] as u64 }
        })
        .collect()
}

/// A prepared die 1 × 1 × x (square faces ⊥ z).
fn die(x: f64) -> (Stone, f64) {
    let (mesh, repairs) = generate::cuboid(1.0, 1.0, x).into_solid_boundary().expect("a box");
    let a = Analysis::of_solid(mesh, repairs, &Options::default()).expect("a box analyses");
    let stone = Stone::new(&a, 0.0035).expect("a box has stable facets");
    let r_max_m = 0.5 * (2.0 + x * x).sqrt() * DIE_Y_M;
    (stone, r_max_m)
}

/// The fraction of drops (and the count) that end on a square face, and the quasi-static one.
fn p_square(stone: &Stone, p: &DropParams, n: u64, seed: u64) -> (u64, u64, f64) {
    let header = RunHeader {
        format: FORMAT.into(),
        mesh: "die".into(),
        mesh_fingerprint: String::new(),
        seed,
        drops: n,
        params: p.clone(),
        certificate: CertificateMode::Facet,
        preset: None,
        center_of_mass: None,
        shard: rocking_stones::dynamics::drops::montecarlo::Shard::ALL,
    };
    let (report, _) = run_and_summarize(stone, &header);
    let square = |normal: &rocking_stones::Vec3| normal.z.abs() > 0.99;
    let k: u64 = report.facets.iter().filter(|f| square(&f.normal)).map(|f| f.count).sum();
    let qs: f64 = report.facets.iter().filter(|f| square(&f.normal)).map(|f| f.static_probability).sum();
    (k, report.facet_drops, qs)
}

fn throw(h: f64, spin: f64, v: f64, r_max_m: f64) -> DropParams {
    let mut p = Preset::Throw.params(Surface::SteelOnWood);
    (p.launch.height, p.launch.spin, p.launch.horizontal_speed) = (h, spin, v);
    Surface::SteelOnWood.scaled(&mut p.sim.contact, r_max_m);
    p
}

fn log_likelihood(dice: &[Die], p: &[f64]) -> f64 {
    dice.iter()
        .zip(p)
        .map(|(d, &q)| {
            let q = q.clamp(1e-4, 1.0 - 1e-4);
            let k = (d.p * d.n as f64).round();
            k * q.ln() + (d.n as f64 - k) * (1.0 - q).ln()
        })
        .sum()
}

fn main() {
    let n: u64 = std::env::args().nth(1).map_or(400, |s| s.parse().expect("N"));
    let out = Path::new("results/cuboid_dice");
    std::fs::create_dir_all(out).expect("results folder");
    let dice = read_dice(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/cuboid_dice_throws.csv")));
    let stones: Vec<(Stone, f64)> = dice.iter().map(|d| die(d.x)).collect();
    let list = |k: usize, default: &[f64]| -> Vec<f64> {
        std::env::args()
            .nth(k)
            .map_or(default.to_vec(), |s| s.split(',').map(|x| x.parse().expect("a number")).collect())
    };
    let heights = list(2, &[2.0, 3.0, 5.0]);
    let spins = list(3, &[15.0, 25.0, 35.0]);
    let speeds = list(4, &[2.0, 4.0, 6.0]);
    let t0 = Instant::now();
    let mut grid_csv = String::from("height_rmax,spin_rad_s,horizontal_speed_m_s,log_likelihood");
    for x in &dice {
        let _ = write!(grid_csv, ",p_square_x{}", x.x);
    }
    grid_csv.push('\n');
    let mut grid = Vec::new();
    let mut drops = 0u64;
    for &v in &speeds {
        for &h in &heights {
            for &w in &spins {
                let p: Vec<f64> = stones
                    .iter()
                    .map(|(s, r)| {
                        let (k, m, _) = p_square(s, &throw(h, w, v, *r), n, 1);
                        drops += n;
                        k as f64 / m as f64
                    })
                    .collect();
                let ll = log_likelihood(&dice, &p);
                eprintln!("v = {v}, H = {h:>4}, Ω = {w:>4}: ln L = {ll:.1}  ({:.0} s)", t0.elapsed().as_secs_f64());
                let _ = write!(grid_csv, "{h},{w},{v},{ll:.3}");
                for q in &p {
                    let _ = write!(grid_csv, ",{q:.4}");
                }
                grid_csv.push('\n');
                grid.push((h, w, v, ll));
            }
        }
    }
    std::fs::write(out.join("grid.csv"), grid_csv).expect("write grid.csv");
    let best = grid.iter().copied().max_by(|a, b| a.3.total_cmp(&b.3)).expect("a grid");
    let grid_time = t0.elapsed().as_secs_f64();

    // Residuals at the best point with 4N throws, and the drop and quasi-static references.
    let mut fit_csv =
        String::from("x_over_y,measured,n_rolls,throw,throw_lo,throw_hi,residual_sigma,drop_preset,quasi_static\n");
    let mut rows = Vec::new();
    let mut reference_counts = Vec::new();
    let mut chi2 = 0.0;
    for (d, (s, r)) in dice.iter().zip(&stones) {
        let (k, m, qs) = p_square(s, &throw(best.0, best.1, best.2, *r), 4 * n, 2);
        let mut dp = Preset::Drop.params(Surface::SteelOnWood);
        Surface::SteelOnWood.scaled(&mut dp.sim.contact, *r);
        let (kd, md, _) = p_square(s, &dp, 2 * n, 3);
        drops += 6 * n;
        let q = k as f64 / m as f64;
        let (lo, hi) = wilson(k, m, 1.96);
        let sigma = ((d.p * (1.0 - d.p) / d.n as f64) + q * (1.0 - q) / m as f64).sqrt();
        let z = (q - d.p) / sigma;
        chi2 += z * z;
        let pd = kd as f64 / md as f64;
        let _ = writeln!(fit_csv, "{},{},{},{q:.4},{lo:.4},{hi:.4},{z:.2},{pd:.4},{qs:.4}", d.x, d.p, d.n);
        rows.push((d.x, d.p, d.n, q, lo, hi, z, pd, qs));
        reference_counts.push((k, m));
    }
    std::fs::write(out.join("fit.csv"), fit_csv).expect("write fit.csv");

    // Other numerics at the best point: the same 4N throws (seed 2) with rapier's own flight
    // (contacts at the step boundaries, the former numerics, at their step 1/240 s) and
    // with free flight at the reference step
    // the default is checked against (`--reference`), against the counts of the default numerics.
    let others = [(Flight::Rapier, Some(REFERENCE_DT)), (Flight::Free, Some(REFERENCE_DT))];
    let default_dt = Preset::Throw.params(Surface::SteelOnWood).sim.numerics.dt;
    let mut numerics = Vec::new();
    for &(flight, dt) in &others {
        let t = Instant::now();
        let per_die: Vec<(f64, f64)> = dice
            .iter()
            .zip(&stones)
            .zip(&reference_counts)
            .map(|((_, (s, r)), &(k_ref, m_ref))| {
                let mut p = throw(best.0, best.1, best.2, *r);
                p.sim.flight.mode = flight;
                p.sim.numerics.dt = dt.unwrap_or(p.sim.numerics.dt);
                let (k, m, _) = p_square(s, &p, 4 * n, 2);
                let (chi2, _, _) = chi_square_homogeneity(&[k_ref, m_ref - k_ref], &[k, m - k]);
                (k as f64 / m as f64, chi2)
            })
            .collect();
        drops += 28 * n;
        numerics.push((flight, dt.unwrap_or(default_dt), per_die, t.elapsed().as_secs_f64()));
    }
    let ll_fit = log_likelihood(&dice, &rows.iter().map(|r| r.3).collect::<Vec<_>>());
    let noise_band = 2.0 * (best.3 - ll_fit).abs().max(2.0);
    let flat = grid
        .iter()
        .filter(|g| g.3 >= best.3 - noise_band)
        .map(|g| format!("(H {}, Ω {}, v {})", g.0, g.1, g.2))
        .collect::<Vec<_>>()
        .join(", ");
    let range = |pick: fn(&(f64, f64, f64, f64)) -> f64| {
        let within: Vec<f64> = grid.iter().filter(|g| g.3 >= best.3 - noise_band).map(pick).collect();
        (within.iter().copied().fold(f64::INFINITY, f64::min), within.iter().copied().fold(f64::NEG_INFINITY, f64::max))
    };
    let (h_lo, h_hi) = range(|g| g.0);
    let (w_lo, w_hi) = range(|g| g.1);
    let (v_lo, v_hi) = range(|g| g.2);
    let rms = (rows.iter().map(|r| (r.3 - r.1).powi(2)).sum::<f64>() / rows.len() as f64).sqrt();
    let rms_drop = (rows.iter().map(|r| (r.7 - r.1).powi(2)).sum::<f64>() / rows.len() as f64).sqrt();
    let rms_qs = (rows.iter().map(|r| (r.8 - r.1).powi(2)).sum::<f64>() / rows.len() as f64).sqrt();
    plot(out, &rows).expect("plot");
    let elapsed = t0.elapsed().as_secs_f64();

    // The fitted throw for a real die of y = 16 mm (R_max ≈ 1.1–1.9 cm): Froude scaling.
    let r_m = 0.5 * 3f64.sqrt() * DIE_Y_M; // a cube of side y
    let mut md = String::new();
    let _ = writeln!(md, "# Calibrating the `throw` preset on seven measured cuboid dice\n");
    let _ = writeln!(md, "Regenerate: `cargo run --release --example cuboid_dice`.\n");
    let _ = writeln!(
        md,
        "Data: `data/cuboid_dice_throws.csv` (Mathematical Gazette 97, note 97.16, Table 1; steel dice \
         y × y × x rolled by hand, 332–1011 rolls each). **This is a calibration, not a validation**: the \
         free parameters of the throw are fitted to these seven dice.\n"
    );
    let inv_dt = 1.0 / default_dt;
    let _ = writeln!(md, "Model: rapier3d with exact landings and sub-stepped impacts (the default numerics: the depth of every corner measured after every sub-step, and each impact is completed by Coulomb's compression and Newton's restitution, `dynamics::engine::contact`), the die's exact box hull, no global damping, dt 1/{inv_dt:.0} s (the preset's longest stable step, `Preset::largest_stable_dt`); contact steel on wood (μ = 0.4, e = 0.5, rolling resistance δ = 0.2 mm for y = 16 mm), lengths and speeds of the body scaled to R_max = 1 m; fitted: release height H (R_max), the rms Ω of the Gaussian spin (rad/s, scaled) and the horizontal release speed v (m/s, scaled). Grid H {heights:?} × Ω {spins:?} × v {speeds:?}, {n} throws per die and grid point (common random numbers), binomial log-likelihood.\n");
    let _ = writeln!(md, "## Fit\n");
    let _ = writeln!(md, "| parameter | best | range over the grid points within the noise band |\n|---|---|---|");
    let _ = writeln!(md, "| H (R_max) | {} | {h_lo} – {h_hi} |", best.0);
    let _ = writeln!(md, "| Ω (rad/s, scaled) | {} | {w_lo} – {w_hi} |", best.1);
    let _ = writeln!(md, "| v (m/s, scaled) | {} | {v_lo} – {v_hi} |", best.2);
    let _ = writeln!(
        md,
        "\nMonte Carlo noise: the best point's ln L is {:.1} on the grid (seed 1, {n} throws per die) and {:.1} when \
         re-run with seed 2 and {} throws per die (scaled to {n}); with noise of that size the surface is flat across the \
         grid points within {:.0} of the best: {}. That set, not the best point alone, is the calibrated range.\n",
        best.3,
        ll_fit,
        4 * n,
        noise_band,
        flat
    );
    let preset = grid.iter().find(|g| g.0 == THROW_HEIGHT && g.1 == THROW_SPIN && g.2 == THROW_HORIZONTAL_SPEED);
    let _ = writeln!(
        md,
        "The `throw` preset (`dynamics::drops::params`: H {THROW_HEIGHT}, Ω {THROW_SPIN}, v {THROW_HORIZONTAL_SPEED}) {}.\n",
        match preset {
            Some(g) if *g == best => "is the best grid point".to_string(),
            Some(g) if g.3 >= best.3 - noise_band =>
                format!("scores ln L {:.1} on the grid, inside the noise band", g.3),
            Some(g) => format!("scores ln L {:.1} on the grid, **outside the noise band: refit it**", g.3),
            None => "is not a grid point: **add it to the grid or refit it**".to_string(),
        }
    );
    let _ = writeln!(
        md,
        "For a real die (y = 16 mm, R_max = {:.1} mm for a cube) the best throw is released {:.0} mm above the \
         table, {:.2} m/s sideways, with an rms spin of {:.0} rad/s ({:.0} turns/s). Height and sideways speed are \
         those of a die rolled from the hand onto a table. The spin is high for a hand: it carries all the tumbling \
         energy of a real release (fingers, palm, a table that is not flat), which the model has no other way to \
         receive; read it as the rotational energy of the release (≈ {:.1} m g R_max for a cube, I = 2 m R_max²/9), not as a measured spin.\n",
        r_m * 1e3,
        best.0 * r_m * 1e3,
        best.2 * r_m.sqrt(),
        best.1 / r_m.sqrt(),
        best.1 / r_m.sqrt() / std::f64::consts::TAU,
        0.5 * (2.0 / 9.0) * best.1 * best.1 / 9.81
    );
    let _ = writeln!(md, "## Residuals at the best point ({} throws per die)\n", 4 * n);
    let _ = writeln!(md, "| x/y | measured | n | throw | 95 % MC interval | residual (σ) | drop preset | quasi-static |\n|---|---|---|---|---|---|---|---|");
    for r in &rows {
        let _ = writeln!(
            md,
            "| {} | {:.3} | {} | {:.3} | [{:.3}, {:.3}] | {:+.1} | {:.3} | {:.3} |",
            r.0, r.1, r.2, r.3, r.4, r.5, r.6, r.7, r.8
        );
    }
    let _ = writeln!(
        md,
        "\nrms error: calibrated throw **{rms:.3}**, `drop` preset {rms_drop:.3}, quasi-static basins {rms_qs:.3}; \
         χ² of the throw = {chi2:.1} over 7 dice (3 fitted parameters). Before this calibration the default drop \
         (damped quasi-static roll) missed by ≈ 0.17 rms.\n"
    );
    if let Some(r) = rows.iter().find(|r| (r.0 - 0.75).abs() < 1e-9) {
        let _ = writeln!(
            md,
            "The die with x/y = 0.75 is the outlier of every fit ({:+.2}, {:+.1}σ here, and on every grid point of the \
             ridge): no launch of this model matches it and its neighbours at once. Left as it is, not fitted away.\n",
            r.3 - r.1,
            r.6
        );
    }
    let _ = writeln!(
        md,
        "Picture: `p_square.png` — measured points with 95 % Wilson intervals, the calibrated throw with its 95 % \
         Monte Carlo band, the `drop` preset, and the quasi-static basin probability.\n"
    );
    let _ = writeln!(md, "## The same throws with other numerics\n");
    let _ = writeln!(
        md,
        "The best point's {} throws per die again (same seed, same launches), with rapier's own flight (`--flight \
         rapier`: contacts found at the step boundaries, impacts starting up to 0.1–0.2 R_max inside the ground — the \
         former numerics of this calibration, at their step 1/240 s) and with free flight at the reference step the default is \
         checked against (1/240 s, `--reference`). Not a calibration: the parameters are those fitted above; the question \
         is only whether the numerics change the answer. χ² of homogeneity of each die's square/other counts against \
         the default numerics (1 dof each; summed over the 7 dice, 7 dof).\n",
        4 * n
    );
    let _ = write!(md, "| x/y | measured | default (exact landings, 1/{:.0} s) |", 1.0 / default_dt);
    for (flight, dt, ..) in &numerics {
        let _ = write!(md, " {flight} flight, 1/{:.0} s | χ² |", 1.0 / dt);
    }
    let _ = writeln!(md, "\n|---|---|---|{}", "---|---|".repeat(numerics.len()));
    for (k, r) in rows.iter().enumerate() {
        let _ = write!(md, "| {} | {:.3} | {:.3} |", r.0, r.1, r.3);
        for (_, _, per_die, _) in &numerics {
            let _ = write!(md, " {:.3} | {:.2} |", per_die[k].0, per_die[k].1);
        }
        let _ = writeln!(md);
    }
    for (flight, dt, per_die, seconds) in &numerics {
        let chi2: f64 = per_die.iter().map(|x| x.1).sum();
        let p_value = 1.0 - ChiSquared::new(7.0).expect("7 dof").cdf(chi2);
        let rms_other =
            (rows.iter().zip(per_die).map(|(r, x)| (x.0 - r.1).powi(2)).sum::<f64>() / rows.len() as f64).sqrt();
        let _ = writeln!(
            md,
            "\n* {flight} flight at 1/{:.0} s: summed χ² {chi2:.1} (7 dof, p = {p_value:.2}); rms error against the \
             measured dice {rms_other:.3} (default numerics {rms:.3}); {:.1} s for the {} throws.",
            1.0 / dt,
            seconds,
            28 * n
        );
    }
    let _ = writeln!(md);
    let _ =
        writeln!(md, "Cost: {drops} simulated throws, grid {grid_time:.0} s, total {elapsed:.0} s on this machine.");
    std::fs::write(out.join("README.md"), md).expect("write README");
    println!(
        "best H = {}, Ω = {}, v = {} (ln L {:.1}); rms {rms:.3} (drop {rms_drop:.3}, basins {rms_qs:.3})",
        best.0, best.1, best.2, best.3
    );
}

type Row = (f64, f64, u64, f64, f64, f64, f64, f64, f64);

fn plot(out: &Path, rows: &[Row]) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    let path = out.join("p_square.png");
    rocking_stones::plot::draw_png(&path, (900, 640), |root| {
        root.fill(&WHITE)?;
        let root = root.titled("Cuboid dice: P(lands on a square face) against x/y", (FONT_FAMILY, style::TITLE))?;
        let (legend, area) = root.split_vertically(legend_height(2));
        let (throw, drop, basins, measured) = (colors::BLUE, colors::ORANGE, colors::GREEN, BLACK);
        draw_legend(
            &legend,
            &[
                (Mark::LineDot(measured), "measured (hand throws, 95 % Wilson interval)".into()),
                (Mark::Line(throw), "calibrated throw".into()),
                (Mark::Box(throw, 0.25), "its 95 % Monte Carlo band".into()),
                (Mark::Line(drop), "drop preset (from rest, 1 R_max)".into()),
                (Mark::Line(basins), "quasi-static basins (exact)".into()),
            ],
        )
        .map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&area)
            .margin(20)
            .margin_top(10)
            .x_label_area_size(50)
            .y_label_area_size(60)
            .build_cartesian_2d(0.3f64..2.8, 0.0f64..1.0)?;
        chart
            .configure_mesh()
            .x_desc("x / y (long side over square side)")
            .y_desc("P(lands on a square face)")
            .x_label_formatter(&|x| plain(*x))
            .y_label_formatter(&|y| plain(*y))
            .label_style((FONT_FAMILY, style::TICK))
            .axis_desc_style((FONT_FAMILY, style::AXIS))
            .draw()?;
        let band: Vec<(f64, f64)> =
            rows.iter().map(|r| (r.0, r.5)).chain(rows.iter().rev().map(|r| (r.0, r.4))).collect();
        chart.draw_series(std::iter::once(Polygon::new(band, throw.mix(0.25).filled())))?;
        chart.draw_series(LineSeries::new(rows.iter().map(|r| (r.0, r.8)), basins.stroke_width(style::LINE)))?;
        chart.draw_series(LineSeries::new(rows.iter().map(|r| (r.0, r.7)), drop.stroke_width(style::LINE)))?;
        chart.draw_series(LineSeries::new(rows.iter().map(|r| (r.0, r.3)), throw.stroke_width(style::LINE)))?;
        chart.draw_series(rows.iter().map(|r| {
            let (lo, hi) = wilson((r.1 * r.2 as f64).round() as u64, r.2, 1.96);
            PathElement::new(vec![(r.0, lo), (r.0, hi)], measured.stroke_width(style::LINE))
        }))?;
        chart.draw_series(rows.iter().map(|r| Circle::new((r.0, r.1), style::MARKER, measured.filled())))?;
        Ok(())
    })?;
    Ok(())
}
