//! What a sharper energy certificate would buy: drops of the three benchmark bodies simulated to
//! rest once while the certificates of a sweep of margins are asked at every step (what is
//! measured: `experiments/readme/certificate_margin.md`).
//!
//! Run: `cargo experiment certificate_margin [-- N]` (N = 1000 drops per body and
//! preset) → `results/certificate_margin/`.

use benchmark_bodies::benchmark_bodies;
use experiments::{benchmark_bodies, harness};
use harness::{fixed, Context, Result, Results};
use rayon::prelude::*;
use rocking_stones::dynamics::certificate::{
    EnergyCertificate, FirstDecision, CERTIFICATE_MARGIN, CERTIFICATE_MAX_COMPRESSION,
};
use rocking_stones::dynamics::drops::alone::run_alone;
use rocking_stones::dynamics::engine::run::CERTIFICATE_EVERY;
use rocking_stones::prelude::*;

/// The margins swept (R_max), the default last.
const MARGINS: [f64; 6] = [0.0, 1e-4, 3e-4, 1e-3, 2e-3, CERTIFICATE_MARGIN];

/// A margin as the tables print it.
fn show(m: f64) -> String {
    if m == 0.0 {
        "0".into()
    } else {
        format!("{m:.0e}")
    }
}

/// One drop: its rest (facet, flock), steps to rest, and per level (facet, flock) and margin the
/// first decisions.
struct Observed {
    truth: [Option<u32>; 2],
    steps: u64,
    first: [[FirstDecision; MARGINS.len()]; 2],
}

/// The certificates asked at every step: per margin, the facet and the flock level.
type Certificates<'a> = Vec<[EnergyCertificate<'a>; 2]>;

fn certificates(stone: &Stone) -> Result<Certificates<'_>> {
    let at = |mode, m| EnergyCertificate::with_margin(stone, mode, m).context("a certificate");
    MARGINS.iter().map(|&m| Ok([at(CertificateMode::Facet, m)?, at(CertificateMode::Flock, m)?])).collect()
}

fn observe(stone: &Stone, certs: &Certificates, p: &DropParams, seed: u64, i: u64) -> Observed {
    let mut first = [[FirstDecision::default(); MARGINS.len()]; 2];
    let mut step = 0u64;
    let (_, end) = run_alone(stone, p, &launch(&mut item_rng(seed, i), p), &mut |s| {
        step += 1;
        for (k, pair) in certs.iter().enumerate() {
            for (lvl, cert) in pair.iter().enumerate() {
                first[lvl][k].ask(cert, step, s);
            }
        }
    });
    let facet = stone.rest(&end.state.down).facet;
    Observed { truth: [Some(facet), stone.flock_of(facet).map(|k| k as u32)], steps: end.steps, first }
}

/// One row: a margin's decisions on one body, preset and level (mean simulated s per drop
/// with a check every step and every `CERTIFICATE_EVERY` steps).
struct Row {
    decided: usize,
    wrong: usize,
    every_step: f64,
    every_k: f64,
}

fn summarise(obs: &[Observed], lvl: usize, k: usize, dt: f64) -> Row {
    let mean = |at: fn(&FirstDecision) -> Option<(u64, u32)>| {
        obs.iter().map(|o| at(&o.first[lvl][k]).map_or(o.steps, |(s, _)| s) as f64 * dt).sum::<f64>() / obs.len() as f64
    };
    let decided = || obs.iter().filter_map(|o| o.first[lvl][k].every_step.map(|(_, d)| Some(d) != o.truth[lvl]));
    Row {
        decided: decided().count(),
        wrong: decided().filter(|&w| w).count(),
        every_step: mean(|f| f.every_step),
        every_k: mean(|f| f.every_k),
    }
}

fn main() -> Result<()> {
    let (n, common) = harness::count_args(
        "Decisions and simulated time against the certificate's margin.",
        "Drops per body and preset",
        1000,
    );
    let seed = common.seed_or(11);
    let out = Results::open("certificate_margin", &common)?;
    let bodies = benchmark_bodies(harness::repo(), false)?;
    let mut csv = String::from(
        "body,preset,level,margin_rmax,drops,decided,wrong,mean_time_every_step_s,mean_time_every_k_s,mean_time_to_rest_s\n",
    );
    let (mut table, mut curves, mut groups) = (Vec::new(), Vec::new(), Vec::new());
    for (name, a) in &bodies {
        let stone = Stone::new(a, a.macro_nu(&Options::default()).0)?;
        let certs = certificates(&stone)?;
        for preset in [Preset::Drop, Preset::Throw] {
            let p = preset.params(Surface::SteelOnWood);
            let dt = p.sim.numerics.dt;
            let obs: Vec<Observed> = (0..n).into_par_iter().map(|i| observe(&stone, &certs, &p, seed, i)).collect();
            let rest = obs.iter().map(|o| o.steps as f64 * dt).sum::<f64>() / n as f64;
            eprintln!("{name} {preset}: {n} drops observed");
            for (lvl, level) in ["facet", "flock"].into_iter().enumerate() {
                let rows: Vec<Row> = (0..MARGINS.len()).map(|k| summarise(&obs, lvl, k, dt)).collect();
                let default = rows[MARGINS.len() - 1].every_k;
                for (row, &m) in rows.iter().zip(&MARGINS) {
                    table.push(serde_json::json!({
                        "body": name, "preset": preset.to_string(), "level": level, "margin": show(m),
                        "decided": row.decided, "wrong": row.wrong, "every_step": fixed(row.every_step, 3),
                        "every_k": fixed(row.every_k, 3), "ratio": fixed(row.every_k / default, 2),
                        "rest": fixed(rest, 3),
                    }));
                    csv += &format!(
                        "\"{name}\",{preset},{level},{m:e},{n},{},{},{:.5},{:.5},{rest:.5}\n",
                        row.decided, row.wrong, row.every_step, row.every_k
                    );
                }
                curves.push((
                    format!("{name}, {preset}, {level}"),
                    rows.iter().zip(MARGINS).map(|(r, m)| (m, r.every_k / default)).collect(),
                ));
                groups.push((lvl, rows));
            }
        }
    }
    // Per body, preset and level: the mean time per drop at the sharpest margin that decided
    // nothing wrongly (checked every step) ÷ the default certificate's, and the seconds per drop
    // that checking every step saves at the default margin.
    let best = |rows: &[Row]| {
        let safe = (0..rows.len()).find(|&k| rows[k..].iter().all(|r| r.wrong == 0)).unwrap_or(rows.len() - 1);
        rows[safe].every_step / rows[MARGINS.len() - 1].every_k
    };
    let gain = |rows: &[Row]| rows[MARGINS.len() - 1].every_k - rows[MARGINS.len() - 1].every_step;
    let largest_wrong = groups
        .iter()
        .flat_map(|(_, rows)| rows.iter().zip(MARGINS).filter(|(r, _)| r.wrong > 0).map(|(_, m)| m))
        .reduce(f64::max);
    let levels: Vec<_> = ["Facet", "Flock"]
        .into_iter()
        .enumerate()
        .map(|(lvl, level)| {
            let of = || groups.iter().filter(|g| g.0 == lvl).map(|g| &g.1[..]);
            serde_json::json!({
                "name": level,
                "lo": fixed(of().map(best).fold(f64::INFINITY, f64::min), 2),
                "hi": fixed(of().map(best).fold(0.0, f64::max), 2),
                "gain": fixed(of().map(gain).fold(0.0, f64::max), 3),
            })
        })
        .collect();
    out.readme(
        include_str!("readme/certificate_margin.md"),
        serde_json::json!({
            "n": n,
            "seed": seed,
            "inv_dt": fixed(1.0 / Preset::Drop.params(Surface::SteelOnWood).sim.numerics.dt, 0),
            "max_compression": CERTIFICATE_MAX_COMPRESSION.to_string(),
            "every": CERTIFICATE_EVERY,
            "margin": CERTIFICATE_MARGIN.to_string(),
            "rows": table,
            "wrong_at_zero": groups.iter().map(|g| g.1[0].wrong).sum::<usize>(),
            "decided_at_zero": groups.iter().map(|g| g.1[0].decided).sum::<usize>(),
            "largest_wrong": largest_wrong.map(show),
            "safe": largest_wrong.map(|w| show(MARGINS.iter().copied().find(|&m| m > w).unwrap_or(CERTIFICATE_MARGIN))),
            "levels": levels,
        }),
    )?;
    out.write("margin.csv", csv)?;
    plot(&out, &curves)
}

/// The curves: colour by body, line width by level (facet thin, flock thick), dots for drops and
/// triangles for throws.
fn plot(out: &Results, curves: &[(String, Vec<(f64, f64)>)]) -> Result<()> {
    let values = || curves.iter().flat_map(|(_, c)| c.iter().map(|p| p.1));
    let top = values().fold(1.0f64, f64::max) + 0.02;
    let bottom = (values().fold(1.0f64, f64::min) * 20.0).floor() / 20.0 - 0.05;
    let mut chart = Chart::new(
        Axis::linear("margin (R_max)", -1e-4, CERTIFICATE_MARGIN * 1.05).format(|x| format!("{x:.4}")),
        Axis::linear("mean simulated time per drop ÷ at the default margin", bottom, top),
    )
    .title("Mean simulated time per drop vs the certificate's margin (÷ default margin)");
    for (k, (label, c)) in curves.iter().enumerate() {
        let colour = series_color(k / 4);
        let marker = if (k / 2) % 2 == 0 { Marker::Dot } else { Marker::Triangle };
        chart = chart
            .line_width(c, colour, if k % 2 == 0 { 1 } else { 3 })
            .markers(c, colour, marker)
            .legend(Mark::LineDot(colour), label.as_str());
    }
    chart.save(&out.path("margin.png"), (1000, 600))?;
    Ok(())
}
