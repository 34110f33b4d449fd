//! Does the energy certificate ever decide wrongly? Every drop of the bundled stone and the 39
//! meshes of `data/meshes`, under three presets and both numerics, simulated to rest without a
//! certificate while both certificates are asked along it (what is measured, and the margin it
//! checks: `experiments/readme/certificate_decisions.md`).
//!
//! Run: `cargo experiment certificate_decisions [-- N]` (N = 300 drops per mesh,
//! preset and numerics) → `results/certificate_decisions/`.

use experiments::harness;
use harness::{Context, Result, Results};
use rayon::prelude::*;
use rocking_stones::dynamics::certificate::{
    DecisionTally, EnergyCertificate, CERTIFICATE_MARGIN, CERTIFICATE_MAX_COMPRESSION,
};
use rocking_stones::dynamics::drops::audit::audit_certificates;
use rocking_stones::dynamics::engine::run::CERTIFICATE_EVERY;
use rocking_stones::prelude::*;
use rocking_stones::study::{mesh_files, pebble_id};
use serde_json::json;
use std::fmt::Write as _;
use std::path::Path;

/// Decisions (facet level, flock level) and the largest later rise of h above L, for a set of drops.
#[derive(Clone, Copy, Default)]
struct Tally {
    drops: u64,
    levels: [DecisionTally; 2],
    asked: u64,
    excess: f64,
}

impl Tally {
    fn add(&mut self, o: &Tally) {
        self.drops += o.drops;
        for l in 0..2 {
            self.levels[l].merge(&o.levels[l]);
        }
        self.asked += o.asked;
        self.excess = self.excess.max(o.excess);
    }
}

fn drops(stone: &Stone, preset: Preset, flight: Flight, seed: u64, indices: std::ops::Range<u64>) -> Result<Tally> {
    let mut p = preset.params(Surface::SteelOnWood);
    p.sim.flight.mode = flight;
    let facet_cert = EnergyCertificate::new(stone, CertificateMode::Facet).context("the facet level")?;
    let flock_cert = EnergyCertificate::new(stone, CertificateMode::Flock).context("the flock level")?;
    let mut tally = Tally::default();
    for i in indices {
        let release = launch(&mut item_rng(seed, i), &p);
        let audit = audit_certificates(stone, &p, [&facet_cert, &flock_cert], &release, i)
            .context("full settling decides the facet")?;
        tally.drops += 1;
        for (l, s) in audit.scores.iter().enumerate() {
            tally.levels[l].add(s);
        }
        (tally.asked, tally.excess) = (tally.asked + audit.asked, tally.excess.max(audit.excess));
    }
    Ok(tally)
}

fn meshes(root: &Path) -> Result<Vec<(String, Analysis)>> {
    let options = Options::default();
    let mut out = vec![("bundled stone".to_string(), rocking_stones::bundled::analysis(&options)?)];
    for f in mesh_files(&root.join("data/meshes"))? {
        out.push((pebble_id(&f), Analysis::of_file(&f, &options)?));
    }
    Ok(out)
}

fn main() -> Result<()> {
    let (n, common) = harness::count_args(
        "Does the energy certificate ever decide wrongly?",
        "Drops per mesh, preset and numerics",
        300,
    );
    let seed = common.seed_or(17);
    let out = Results::open("certificate_decisions", &common)?;
    let clock = std::time::Instant::now();
    let stones: Vec<(String, Stone)> = (meshes(harness::repo())?.iter())
        .map(|(name, a)| Ok((name.clone(), Stone::new(a, a.macro_nu(&Options::default()).0)?)))
        .collect::<Result<_>>()?;
    println!("{} bodies analysed in {:.0} s", stones.len(), clock.elapsed().as_secs_f64());
    let presets = [Preset::Drop, Preset::Throw, Preset::QuasiStatic];
    let flights = [Flight::Rapier, Flight::Free];
    // Work items: (body, preset, flight, chunk of 25 drops), in parallel; tallies merged in order.
    let chunk = 25u64;
    let mut items = Vec::new();
    for b in 0..stones.len() {
        for pi in 0..presets.len() {
            for fi in 0..flights.len() {
                for c in (0..n).step_by(chunk as usize) {
                    items.push((b, pi, fi, c..(c + chunk).min(n)));
                }
            }
        }
    }
    let tallies: Vec<((usize, usize, usize), Tally)> = items
        .into_par_iter()
        .map(|(b, pi, fi, r)| Ok(((b, pi, fi), drops(&stones[b].1, presets[pi], flights[fi], seed, r)?)))
        .collect::<Result<_>>()?;
    let mut table = vec![vec![vec![Tally::default(); flights.len()]; presets.len()]; stones.len()];
    for ((b, pi, fi), t) in &tallies {
        table[*b][*pi][*fi].add(t);
    }
    let mut csv = String::from("body,preset,flight,drops,facet_decisions,facet_wrong,flock_decisions,flock_wrong,first_facet,first_facet_wrong,first_flock,first_flock_wrong,asked,max_excess\n");
    let mut total = [Tally::default(); 2];
    let mut per_body: Vec<(String, [f64; 2])> = Vec::new();
    for (b, (name, _)) in stones.iter().enumerate() {
        let mut worst = [f64::NEG_INFINITY; 2];
        for (pi, preset) in presets.iter().enumerate() {
            for (fi, flight) in flights.iter().enumerate() {
                let t = &table[b][pi][fi];
                let (d, w) = (t.levels.map(|l| l.decisions), t.levels.map(|l| l.wrong));
                let (f, fw) = (t.levels.map(|l| l.first), t.levels.map(|l| l.first_wrong));
                let counts =
                    [t.drops, d[0], w[0], d[1], w[1], f[0], fw[0], f[1], fw[1], t.asked].map(|x| x.to_string());
                writeln!(csv, "{name},{},{},{},{:e}", preset.name(), flight.name(), counts.join(","), t.excess)?;
                total[fi].add(t);
                worst[fi] = worst[fi].max(t.excess);
            }
        }
        per_body.push((name.clone(), worst));
    }
    out.write("decisions.csv", csv)?;
    let body_max = per_body.iter().map(|(_, b)| b[0].max(b[1]));
    let (body_lo, body_hi) = (body_max.clone().fold(f64::INFINITY, f64::min), body_max.fold(0.0, f64::max));
    plot(&out, &per_body)?;
    let e = |x: f64| format!("{x:.1e}");
    let totals: Vec<_> = (total.iter().zip(flights))
        .map(|(t, flight)| {
            json!({
                "flight": flight.name(), "drops": t.drops, "decisions": t.levels.map(|l| l.decisions),
                "wrong": t.levels.map(|l| l.wrong), "first": t.levels.map(|l| l.first),
                "first_wrong": t.levels.map(|l| l.first_wrong), "asked": t.asked, "excess": e(t.excess),
            })
        })
        .collect();
    let text = harness::render(
        include_str!("readme/certificate_decisions.md"),
        json!({
            "n": n, "seed": seed, "seconds": format!("{:.0}", clock.elapsed().as_secs_f64()),
            "every": CERTIFICATE_EVERY, "max_compression": CERTIFICATE_MAX_COMPRESSION.to_string(),
            "margin": CERTIFICATE_MARGIN.to_string(), "totals": totals,
            "wrong": total.iter().flat_map(|t| t.levels).map(|l| l.wrong).sum::<u64>(),
            "decisions": total.iter().flat_map(|t| t.levels).map(|l| l.decisions).sum::<u64>(),
            "first": total.iter().flat_map(|t| t.levels).map(|l| l.first).sum::<u64>(),
            "excess": e(total.iter().map(|t| t.excess).fold(0.0, f64::max)),
            "body_lo": e(body_lo), "body_hi": e(body_hi), "cover": format!("{:.1}", CERTIFICATE_MARGIN / body_hi),
        }),
    )?;
    out.write("README.md", &text)?;
    println!("{text}");
    Ok(())
}

/// Per body, the largest excess with either numerics, and the margin.
fn plot(out: &Results, per_body: &[(String, [f64; 2])]) -> Result<()> {
    const BLACK: RGBColor = RGBColor(0, 0, 0);
    let (names, top) = (per_body.iter().map(|b| b.0.clone()).collect::<Vec<_>>(), per_body.len() as f64 - 0.5);
    let name = move |y: f64| names.get(y.round() as usize).cloned().unwrap_or_default();
    let mut chart = Chart::new(
        Axis::log("max over states and later times of h(down(t')) − L(t) (R_max, log scale)", 1e-6, 1e-2),
        Axis::linear("", -0.5, top).ticks(per_body.len()).space(330).format(name),
    )
    .title("Largest later rise of h(down) above the certificate's level L, per body (R_max)");
    for (fi, label) in ["rapier's flight", "exact landings (--flight free)"].into_iter().enumerate() {
        let at = |k: usize| k as f64 + if fi == 0 { 0.15 } else { -0.15 };
        let points: Vec<_> = per_body.iter().enumerate().map(|(k, b)| (b.1[fi].max(1e-6), at(k))).collect();
        chart = chart.dots(&points, series_color(fi)).legend(Mark::Dot(series_color(fi)), label);
    }
    chart
        .line_width(&[(CERTIFICATE_MARGIN, -0.5), (CERTIFICATE_MARGIN, top)], BLACK, 2)
        .legend(Mark::Line(BLACK), format!("margin {CERTIFICATE_MARGIN} R_max"))
        .save(&out.path("excess.png"), (1100, 900))?;
    Ok(())
}
