//! Calibration of the `throw` preset on seven real cuboid dice (`data/cuboid_dice_throws.csv`):
//! the binomial log-likelihood of the measured counts maximised over a grid of release height H,
//! rms spin Ω and horizontal speed v. Calibration, not validation.
//!
//! Run: `cargo experiment cuboid_dice [-- N [H,… [Ω,… [v,…]]]]` (N = 400, as
//! the committed results; the default grid was refined from coarser grids over H 0.5–16,
//! Ω 0–45, v 1–8) → `results/cuboid_dice/`; the README's prose is `experiments/readme/cuboid_dice.md`.

use experiments::harness;
use harness::{fixed, Common, Context, Parser, Result, Results};
use rocking_stones::dynamics::drops::params::{THROW_HEIGHT, THROW_HORIZONTAL_SPEED, THROW_SPIN};
use rocking_stones::plot::wilson_bars;
use rocking_stones::prelude::*;
use rocking_stones::stats::{binomial_log_likelihood, chi_square_homogeneity, chi_square_tail, min_max};
use rocking_stones::stats::{root_mean_square, wilson};
use rocking_stones::study::outcomes::share_on;
use serde_json::json;
use std::fmt::Write as _;
use std::time::Instant;

/// Side y of the square faces of the steel dice (m): not given by the source; 16 mm, a common
/// die. Only the rolling-resistance length depends on it.
const DIE_Y_M: f64 = 0.016;

/// A measured die: x/y, the fraction of rolls on a square face, the rolls.
struct Die {
    x: f64,
    p: f64,
    n: u64,
}

/// A prepared die 1 × 1 × x (square faces ⊥ z) and its R_max in metres.
fn die(x: f64) -> Result<(Stone, f64)> {
    let (mesh, repairs) = generate::cuboid(1.0, 1.0, x).into_solid_boundary()?;
    let a = Analysis::of_solid(mesh, repairs, &Options::default())?;
    let stone = Stone::new(&a, 0.0035)?;
    Ok((stone, 0.5 * (2.0 + x * x).sqrt() * DIE_Y_M))
}

/// The drops (and the count) that end on a square face, and the quasi-static fraction.
fn p_square(stone: &Stone, p: DropParams, n: u64, seed: u64) -> (u64, u64, f64) {
    let (report, _) = run_and_summarize(stone, &RunHeader::of_params("die", seed, n, p, CertificateMode::Facet));
    share_on(&report, |normal| normal.z.abs() > 0.99)
}

fn throw(h: f64, spin: f64, v: f64, r_max_m: f64) -> DropParams {
    let mut p = Preset::Throw.params(Surface::SteelOnWood);
    (p.launch.height, p.launch.spin, p.launch.horizontal_speed) = (h, spin, v);
    Surface::SteelOnWood.scaled(&mut p.sim.contact, r_max_m);
    p
}

/// The binomial log-likelihood of the measured counts under the square-face probabilities `p`.
fn log_likelihood(dice: &[Die], p: &[f64]) -> f64 {
    let observed: Vec<(f64, f64)> = dice.iter().map(|d| ((d.p * d.n as f64).round(), d.n as f64)).collect();
    binomial_log_likelihood(&observed, p, 1e-4)
}

/// At one die: the calibrated throw's p and its 95 % band (lo, hi), the residual (σ), the drop
/// preset's p and the quasi-static one.
type Fit = (f64, f64, f64, f64, f64, f64);

/// Root mean square of `f(row) − measured` over the dice.
fn rms(dice: &[Die], f: impl Fn(usize) -> f64) -> f64 {
    root_mean_square(&dice.iter().enumerate().map(|(k, d)| f(k) - d.p).collect::<Vec<_>>())
}

/// The values of one axis of the grid (an alias, so that clap takes it as one argument).
type Grid = Vec<f64>;

fn grid(s: &str) -> Result<Grid, std::num::ParseFloatError> {
    s.split(',').map(str::parse).collect()
}

/// Calibrate the `throw` preset on seven measured cuboid dice.
#[derive(Parser)]
struct Args {
    /// Throws per die and grid point
    #[arg(default_value_t = 400)]
    n: u64,
    /// Release heights H of the grid (R_max), comma-separated
    #[arg(default_value = "2,3,5", value_parser = grid)]
    heights: Grid,
    /// rms spins Ω of the grid (rad/s, scaled), comma-separated
    #[arg(default_value = "15,25,35", value_parser = grid)]
    spins: Grid,
    /// Horizontal speeds v of the grid (m/s, scaled), comma-separated
    #[arg(default_value = "2,4,6", value_parser = grid)]
    speeds: Grid,
    #[command(flatten)]
    common: Common,
}

fn main() -> Result<()> {
    let args = Args::parse();
    let (n, seed) = (args.n, args.common.seed_or(1));
    let out = Results::open("cuboid_dice", &args.common)?;
    let data = harness::repo().join("data/cuboid_dice_throws.csv");
    let rows =
        csv::ReaderBuilder::new().trim(csv::Trim::All).from_path(&data).with_context(|| data.display().to_string())?;
    let dice: Vec<Die> = (rows.into_deserialize::<(f64, f64, u64)>().enumerate())
        .map(|(i, row)| {
            row.map(|(x, p, n)| Die { x, p, n }).with_context(|| format!("{}, record {}", data.display(), i + 1))
        })
        .collect::<Result<_>>()?;
    let stones: Vec<(Stone, f64)> = dice.iter().map(|d| die(d.x)).collect::<Result<_>>()?;
    let t0 = Instant::now();
    let columns: String = dice.iter().map(|d| format!(",p_square_x{}", d.x)).collect();
    let mut grid_csv = format!("height_rmax,spin_rad_s,horizontal_speed_m_s,log_likelihood{columns}\n");
    let (mut grid, mut drops) = (Vec::new(), 0u64);
    for &v in &args.speeds {
        for &h in &args.heights {
            for &w in &args.spins {
                let square = |(s, r): &(Stone, f64)| {
                    let (k, m, _) = p_square(s, throw(h, w, v, *r), n, seed);
                    k as f64 / m as f64
                };
                let p: Vec<f64> = stones.iter().map(square).collect();
                drops += n * stones.len() as u64;
                let ll = log_likelihood(&dice, &p);
                eprintln!("v = {v}, H = {h:>4}, Ω = {w:>4}: ln L = {ll:.1}  ({:.0} s)", t0.elapsed().as_secs_f64());
                let columns: String = p.iter().map(|q| format!(",{q:.4}")).collect();
                writeln!(grid_csv, "{h},{w},{v},{ll:.3}{columns}")?;
                grid.push((h, w, v, ll));
            }
        }
    }
    out.write("grid.csv", grid_csv)?;
    let best = grid.iter().copied().max_by(|a, b| a.3.total_cmp(&b.3)).context("an empty grid")?;
    let grid_time = t0.elapsed().as_secs_f64();

    // Residuals at the best point with 4N throws, and the drop and quasi-static references:
    // per die (throw, its 95 % band, residual in σ, drop preset, quasi-static).
    let mut fit_csv =
        String::from("x_over_y,measured,n_rolls,throw,throw_lo,throw_hi,residual_sigma,drop_preset,quasi_static\n");
    let (mut rows, mut counts, mut residuals, mut chi2) = (Vec::new(), Vec::new(), Vec::new(), 0.0);
    for (d, (s, r)) in dice.iter().zip(&stones) {
        let (k, m, qs) = p_square(s, throw(best.0, best.1, best.2, *r), 4 * n, seed + 1);
        let dp = Preset::Drop.params_at_size(Surface::SteelOnWood, *r)?;
        let (kd, md, _) = p_square(s, dp, 2 * n, seed + 2);
        drops += 6 * n;
        let (q, (lo, hi), pd) = (k as f64 / m as f64, wilson(k, m, 1.96), kd as f64 / md as f64);
        let z = (q - d.p) / ((d.p * (1.0 - d.p) / d.n as f64) + q * (1.0 - q) / m as f64).sqrt();
        chi2 += z * z;
        writeln!(fit_csv, "{},{},{},{q:.4},{lo:.4},{hi:.4},{z:.2},{pd:.4},{qs:.4}", d.x, d.p, d.n)?;
        let f3 = |x: f64| fixed(x, 3);
        let interval = format!("[{lo:.3}, {hi:.3}]");
        residuals.push([
            d.x.to_string(),
            f3(d.p),
            d.n.to_string(),
            f3(q),
            interval,
            format!("{z:+.1}"),
            f3(pd),
            f3(qs),
        ]);
        rows.push((q, lo, hi, z, pd, qs));
        counts.push((k, m));
    }
    out.write("fit.csv", fit_csv)?;

    // Other numerics at the best point: the same 4N throws with rapier's own flight (contacts
    // at the step boundaries, the former numerics, at their step 1/240 s) and with free flight
    // at the reference step the default is checked against (`--reference`), against the counts
    // of the default numerics.
    let default_dt = Preset::Throw.params(Surface::SteelOnWood).sim.numerics.dt;
    let (rms_fit, rms_drop, rms_qs) = (rms(&dice, |k| rows[k].0), rms(&dice, |k| rows[k].4), rms(&dice, |k| rows[k].5));
    let (mut others, mut compared) = (Vec::new(), vec![Vec::new(); dice.len()]);
    for flight in [Flight::Rapier, Flight::Free] {
        let t = Instant::now();
        let mut per_die = Vec::new();
        for (k, (s, r)) in stones.iter().enumerate() {
            let mut p = throw(best.0, best.1, best.2, *r);
            (p.sim.flight.mode, p.sim.numerics.dt) = (flight, REFERENCE_DT);
            let (kk, m, _) = p_square(s, p, 4 * n, seed + 1);
            let (k_ref, m_ref) = counts[k];
            let (x2, _, _) = chi_square_homogeneity(&[k_ref, m_ref - k_ref], &[kk, m - kk]);
            per_die.push((kk as f64 / m as f64, x2));
            compared[k].extend([fixed(kk as f64 / m as f64, 3), fixed(x2, 2)]);
        }
        drops += 28 * n;
        let chi2: f64 = per_die.iter().map(|x| x.1).sum();
        others.push(json!({
            "flight": flight.to_string(), "inv_dt": fixed(1.0 / REFERENCE_DT, 0), "chi2": fixed(chi2, 1),
            "p": fixed(chi_square_tail(chi2, 7), 2), "rms": fixed(rms(&dice, |k| per_die[k].0), 3),
            "seconds": fixed(t.elapsed().as_secs_f64(), 1),
        }));
    }
    let compared: Vec<Vec<String>> = (dice.iter().zip(&rows).zip(compared))
        .map(|((d, r), c)| [d.x.to_string(), fixed(d.p, 3), fixed(r.0, 3)].into_iter().chain(c).collect())
        .collect();
    let ll_fit = log_likelihood(&dice, &rows.iter().map(|r| r.0).collect::<Vec<_>>());
    let noise_band = 2.0 * (best.3 - ll_fit).abs().max(2.0);
    let within = || grid.iter().filter(|g| g.3 >= best.3 - noise_band);
    let span = |pick: fn(&(f64, f64, f64, f64)) -> f64, name: &str, at: f64| {
        let (lo, hi) = min_max(within().map(pick));
        json!({ "name": name, "best": at.to_string(), "lo": lo.to_string(), "hi": hi.to_string() })
    };
    plot(&out, &dice, &rows)?;
    let preset = grid.iter().find(|g| g.0 == THROW_HEIGHT && g.1 == THROW_SPIN && g.2 == THROW_HORIZONTAL_SPEED);
    // The fitted throw for a real die of y = 16 mm (R_max ≈ 1.1–1.9 cm): Froude scaling.
    let r_m = 0.5 * 3f64.sqrt() * DIE_Y_M; // a cube of side y
    let outlier = dice.iter().zip(&rows).find(|(d, _)| (d.x - 0.75).abs() < 1e-9);
    out.readme(include_str!("readme/cuboid_dice.md"),
        json!({
            "n": n, "n4": 4 * n, "n28": 28 * n, "seed": seed, "inv_dt": fixed(1.0 / default_dt, 0),
            "heights": format!("{:?}", args.heights), "spins": format!("{:?}", args.spins),
            "speeds": format!("{:?}", args.speeds),
            "params": [span(|g| g.0, "H (R_max)", best.0), span(|g| g.1, "Ω (rad/s, scaled)", best.1),
                span(|g| g.2, "v (m/s, scaled)", best.2)],
            "best_ll": fixed(best.3, 1), "fit_ll": fixed(ll_fit, 1), "band": fixed(noise_band, 0),
            "flat": within().map(|g| format!("(H {}, Ω {}, v {})", g.0, g.1, g.2)).collect::<Vec<_>>(),
            "preset": {
                "h": THROW_HEIGHT.to_string(), "w": THROW_SPIN.to_string(), "v": THROW_HORIZONTAL_SPEED.to_string(), "is_best": preset == Some(&best),
                "ll": preset.map(|g| fixed(g.3, 1)), "inside": preset.is_some_and(|g| g.3 >= best.3 - noise_band),
            },
            "die": {
                "r": fixed(r_m * 1e3, 1), "h": fixed(best.0 * r_m * 1e3, 0), "v": fixed(best.2 * r_m.sqrt(), 2),
                "w": fixed(best.1 / r_m.sqrt(), 0), "turns": fixed(best.1 / r_m.sqrt() / std::f64::consts::TAU, 0),
                "energy": fixed(0.5 * (2.0 / 9.0) * best.1 * best.1 / 9.81, 1),
            },
            "residuals": residuals, "rms": fixed(rms_fit, 3), "rms_drop": fixed(rms_drop, 3),
            "rms_qs": fixed(rms_qs, 3), "chi2": fixed(chi2, 1),
            "outlier": outlier.map(|(d, r)| json!({ "off": format!("{:+.2}", r.0 - d.p), "z": format!("{:+.1}", r.3) })),
            "others": others, "compared": compared, "drops": drops, "grid_seconds": fixed(grid_time, 0),
            "seconds": fixed(t0.elapsed().as_secs_f64(), 0),
        }),
    )?;
    println!(
        "best H = {}, Ω = {}, v = {} (ln L {:.1}); rms {rms_fit:.3} (drop {rms_drop:.3}, basins {rms_qs:.3})",
        best.0, best.1, best.2, best.3
    );
    Ok(())
}

/// P(square) against x/y: the measured dice, the calibrated throw and its band, the drop
/// preset and the quasi-static basins.
fn plot(out: &Results, dice: &[Die], rows: &[Fit]) -> Result<()> {
    const BLACK: RGBColor = RGBColor(0, 0, 0);
    let (throw, drop, basins) = (colors::BLUE, colors::ORANGE, colors::GREEN);
    let curve = |f: fn(&Fit) -> f64| -> Vec<(f64, f64)> { dice.iter().zip(rows).map(|(d, r)| (d.x, f(r))).collect() };
    let band: Vec<(f64, f64)> = curve(|r| r.2).into_iter().chain(curve(|r| r.1).into_iter().rev()).collect();
    let measured: Vec<(f64, f64)> = dice.iter().map(|d| (d.x, d.p)).collect();
    let bars = wilson_bars(dice.iter().map(|d| (d.x, (d.p * d.n as f64).round() as u64, d.n)));
    Chart::new(
        Axis::linear("x / y (long side over square side)", 0.3, 2.8),
        Axis::linear("P(lands on a square face)", 0.0, 1.0),
    )
    .title("Cuboid dice: P(lands on a square face) against x/y")
    .polygon(&band, throw, 0.25)
    .line(&curve(|r| r.5), basins)
    .line(&curve(|r| r.4), drop)
    .line(&curve(|r| r.0), throw)
    .y_bars(&bars, BLACK)
    .dots(&measured, BLACK)
    .legend(Mark::LineDot(BLACK), "measured (hand throws, 95 % Wilson interval)")
    .legend(Mark::Line(throw), "calibrated throw")
    .legend(Mark::Box(throw, 0.25), "its 95 % Monte Carlo band")
    .legend(Mark::Line(drop), "drop preset (from rest, 1 R_max)")
    .legend(Mark::Line(basins), "quasi-static basins (exact)")
    .save(&out.path("p_square.png"), (900, 640))?;
    Ok(())
}
