//! Housner (1963) rigid blocks in the engine: the tipping threshold a = g·tan α under a slowly
//! rising horizontal ground acceleration, and the angular-velocity ratio 1 − (3/2) sin² α at
//! each impact of free rocking, against the closed forms, over aspect ratios and the engine's
//! contact settings.
//!
//! Run: `cargo experiment housner_block` → `results/housner_block/`; the README's
//! prose is `experiments/readme/housner_block.md`.

use rocking_stones::dynamics::resting::RestingParams;
use rocking_stones::dynamics::shaking::housner::{block_stone, ramp_lag, ramp_tipping};
use rocking_stones::dynamics::shaking::housner::{free_rocking, housner_ratio, impact_ratios, mean_impact_ratio};
use rocking_stones::prelude::*;
use serde_json::json;

use experiments::harness;
use harness::{columns, fixed, Result, Results};

/// The blocks' slenderness tan α = b/h.
const TAN_ALPHAS: [f64; 6] = [0.15, 0.25, 0.4, 0.5, 0.667, 0.8];
const DEPTH: f64 = 0.3;
/// Tipping ramp rates (g/s); the table and the figure read the slowest.
const RATES: [f64; 3] = [0.1, 0.03, 0.01];
const BLACK: RGBColor = RGBColor(0, 0, 0);

/// The engine's contact settings: name, restitution, contact frequency (Hz), dt (s), and whether
/// the tipping ramps run too (slow at small dt); each with its colour in the figure.
const SETTINGS: [(&str, f64, f64, f64, bool, RGBColor); 5] = [
    ("e=0, 120 Hz, dt=1/240 (project default contacts)", 0.0, 120.0, 1.0 / 240.0, true, RGBColor(200, 60, 40)),
    ("e=0, 30 Hz, dt=1/240 (rapier default contacts)", 0.0, 30.0, 1.0 / 240.0, true, RGBColor(40, 90, 200)),
    ("e=0, 120 Hz, dt=1/960", 0.0, 120.0, 1.0 / 960.0, true, RGBColor(40, 150, 70)),
    ("e=0, 120 Hz, dt=1/3840", 0.0, 120.0, 1.0 / 3840.0, false, RGBColor(230, 150, 30)),
    ("e=0.3 (rock on concrete), 120 Hz, dt=1/240", 0.3, 120.0, 1.0 / 240.0, true, RGBColor(150, 60, 170)),
];

struct Tip {
    tan_a: f64,
    setting: &'static str,
    rate: f64,
    measured: f64,
    lag: f64,
    /// measured − lag, and its relative error against tan α.
    corrected: f64,
    error: f64,
}

struct Decay {
    tan_a: f64,
    setting: &'static str,
    /// (amplitude after, ratio) of every impact.
    impacts: Vec<(f64, f64)>,
    /// Mean ratio of the first (up to 4) impacts whose post-impact amplitude exceeds 0.02 rad.
    mean: Option<f64>,
}

fn main() -> Result<()> {
    let common = harness::common_args("Housner's rigid block in the engine: tipping thresholds and impact ratios.");
    let out = Results::open("housner_block", &common)?;
    let (mut tips, mut decays) = (Vec::new(), Vec::new());
    for &tan_a in &TAN_ALPHAS {
        let (stone, start) = block_stone(tan_a, DEPTH, 1.0, Some(0.01))?;
        let (bs, hs) = (tan_a / stone.body.r_max, 1.0 / stone.body.r_max);
        for &(setting, restitution, frequency, dt, tipping, _) in &SETTINGS {
            // The contact of every resting run (rock on concrete, a block of R_max = 1 m: rolling
            // resistance δ = 10⁻⁴ R_max through the contact), friction 1, the setting's rest.
            let mut p = RestingParams::on_surface(Surface::RockOnConcrete, 1.0)?;
            (p.sim.contact.friction, p.sim.contact.restitution) = (1.0, restitution);
            (p.sim.numerics.dt, p.contact_frequency) = (dt, frequency);
            for rate in RATES {
                if !tipping || (restitution > 0.0 && rate != 0.01) {
                    continue;
                }
                let tilt = 1e-3;
                let lag = ramp_lag(bs, hs, rate, tilt);
                let measured = ramp_tipping(&stone, start, &p, 0.0, rate, tilt, 2.0 * tan_a).unwrap_or(f64::NAN);
                eprintln!("tan α {tan_a}: {setting} rate {rate}: {measured:.4} (lag {lag:.4})");
                let (corrected, error) = (measured - lag, (measured - lag) / tan_a - 1.0);
                tips.push(Tip { tan_a, setting, rate, measured, lag, corrected, error });
            }
            let cycles = free_rocking(&stone, start, &p, tan_a, 1.0, 0.5 * tan_a.atan(), 8.0);
            // Impacts until the rocking has died out (amplitude below 10⁻⁵ rad: contact noise).
            let impacts = impact_ratios(&cycles, 1e-5);
            let mean = mean_impact_ratio(&impacts, 0.02, 4);
            eprintln!("  decay: mean {mean:?} vs Housner {:.4}", housner_ratio(tan_a, 1.0));
            decays.push(Decay { tan_a, setting, impacts, mean });
        }
    }
    let f5 = |x: f64| fixed(x, 5);
    out.csv(
        "tipping.csv",
        &columns("tan_alpha,setting,ramp_rate_g_per_s,measured_g,detection_lag_g,corrected_g,relative_error"),
        tips.iter().map(|t| {
            [t.tan_a.to_string(), t.setting.into(), t.rate.to_string()]
                .into_iter()
                .chain([t.measured, t.lag, t.corrected, t.error].map(f5))
        }),
    )?;
    out.csv(
        "rocking_impacts.csv",
        &["tan_alpha", "setting", "impact", "amplitude_after_rad", "ratio", "housner"],
        decays.iter().flat_map(|d| {
            d.impacts.iter().enumerate().map(|(k, &(amp, ratio))| {
                [d.tan_a.to_string(), d.setting.into(), (k + 1).to_string(), fixed(amp, 6), f5(ratio)]
                    .into_iter()
                    .chain([f5(housner_ratio(d.tan_a, 1.0))])
            })
        }),
    )?;
    plot(&out, &tips, &decays)?;
    let slow: Vec<&Tip> = tips.iter().filter(|t| t.rate == 0.01).collect();
    let f4 = |x: f64| fixed(x, 4);
    out.readme(
        include_str!("readme/housner_block.md"),
        json!({
            "tips": slow.iter().map(|t| json!({
                "tan_a": t.tan_a.to_string(), "setting": t.setting, "measured": f4(t.measured),
                "lag": f4(t.lag), "corrected": f4(t.corrected), "error": format!("{:+.2}", 100.0 * t.error),
            })).collect::<Vec<_>>(),
            "max_error": fixed(100.0 * slow.iter().map(|t| t.error.abs()).fold(0.0, f64::max), 2),
            "settings": SETTINGS.map(|s| s.0),
            "rocking": TAN_ALPHAS.map(|t| {
                let housner = housner_ratio(t, 1.0);
                let cell = |s: &str| {
                    let d = decays.iter().find(|d| d.tan_a == t && d.setting == s);
                    d.and_then(|d| d.mean)
                        .map_or("–".into(), |m| format!("{m:.4} ({:+.1} %)", 100.0 * (m / housner - 1.0)))
                };
                json!({
                    "tan_a": t.to_string(), "alpha": fixed(t.atan().to_degrees(), 1), "housner": f4(housner),
                    "cells": SETTINGS.map(|s| cell(s.0)),
                })
            }),
        }),
    )
}

fn plot(out: &Results, tips: &[Tip], decays: &[Decay]) -> Result<()> {
    let mut tipping =
        Chart::new(Axis::linear("tan α = b/h", 0.0, 0.9), Axis::linear("tipping acceleration (g)", 0.0, 0.9))
            .title("Tipping under a slow ramp: measured − detection lag vs g·tan α")
            .line_width(&[(0.0, 0.0), (0.9, 0.9)], BLACK, 1)
            .legend(Mark::WideLine(BLACK, 1), "Housner: a = g tan α");
    let curve: Vec<(f64, f64)> =
        (0..=84).map(|i| i as f64 * 0.5).map(|a| (a, 1.0 - 1.5 * a.to_radians().sin().powi(2))).collect();
    let mut rocking = Chart::new(Axis::linear("α (degrees)", 0.0, 42.0), Axis::linear("ω after / ω before", 0.0, 1.05))
        .title("Free rocking: angular-velocity ratio per impact")
        .line(&curve, BLACK)
        .legend(Mark::Line(BLACK), "Housner: 1 − 1.5 sin² α");
    for (k, &(name, .., tip, c)) in SETTINGS.iter().enumerate() {
        if tip {
            let pts: Vec<_> =
                tips.iter().filter(|t| t.setting == name && t.rate == 0.01).map(|t| (t.tan_a, t.corrected)).collect();
            tipping = tipping.markers_sized(&pts, c, Marker::Ring, 5).legend(Mark::Ring(c), name);
        }
        // The settings side by side around each α, so that equal ratios stay visible.
        let pts: Vec<_> = decays
            .iter()
            .filter(|d| d.setting == name)
            .filter_map(|d| d.mean.map(|m| (d.tan_a.atan().to_degrees() + 0.4 * k as f64 - 0.8, m)))
            .collect();
        rocking = rocking.markers_sized(&pts, c, Marker::Triangle, 5).legend(Mark::Triangle(c), name);
    }
    Figure::new("Housner's rigid block in the engine", 2, vec![tipping, rocking])
        .save(&out.path("housner.png"), (1400, 700))?;
    Ok(())
}
