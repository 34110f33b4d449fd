//! How deep the ground is entered: rapier's own flight, which finds a contact only at the step
//! boundaries, against exact landings and sub-stepped impacts (`--flight free`), per benchmark
//! body, preset and time step, then launches far beyond the presets (what is measured:
//! `experiments/readme/drops_impacts.md`).
//!
//! Run: `cargo experiment drops_impacts [-- N]` (N = 300) → `results/drops_impacts/`.

use benchmark_bodies::benchmark_bodies;
use experiments::{benchmark_bodies, harness};
use harness::{Result, Results};
use rocking_stones::dynamics::drops::{batch::simulate_batch, montecarlo::thread_cpu_seconds};
use rocking_stones::dynamics::engine::impact::{DEPTH_BOUND, IMPACT_APPROACH};
use rocking_stones::dynamics::engine::{flight::CONTACT_CLEARANCE, run::NoCertificate};
use rocking_stones::prelude::*;
use rocking_stones::stats::{chi_square_homogeneity, quantile};
use std::fmt::Write as _;

/// The presets and steps (1/s) of the comparison.
const PRESETS: [Preset; 2] = [Preset::Drop, Preset::Throw];
const STEPS: [f64; 2] = [240.0, 120.0];

/// One body, preset, dt and flight: the largest and 99th-percentile depth over the drops, the
/// drops deeper than the bound, drops/s, settled drops and flock counts.
struct Measured {
    max: f64,
    p99: f64,
    over: usize,
    per_s: f64,
    settled: u64,
    flocks: Vec<u64>,
}

fn measure(stone: &Stone, p: &DropParams, seed: u64, n: u64) -> Result<Measured> {
    let mut deepest = vec![f64::NAN; n as usize];
    let (mut flocks, mut settled) = (vec![0u64; stone.flock_kinds.len()], 0);
    let mut queue = (0..n).map(|i| (i, launch(&mut item_rng(seed, i), p)));
    let clock = thread_cpu_seconds()?;
    let mut finished = |o: DropOutcome| {
        settled += u64::from(o.settled);
        deepest[o.index as usize] = o.deepest_penetration;
        if let Some(k) = o.facet.and_then(|f| stone.facet_flock[f as usize]) {
            flocks[k] += 1;
        }
    };
    simulate_batch(stone, p, &NoCertificate, 1, &mut queue, &mut finished, &mut |_, _| {});
    let per_s = n as f64 / (thread_cpu_seconds()? - clock);
    let over = deepest.iter().filter(|&&d| d > DEPTH_BOUND).count();
    Ok(Measured { max: quantile(&deepest, 1.0), p99: quantile(&deepest, 0.99), over, per_s, settled, flocks })
}

fn main() -> Result<()> {
    let (n, common) = harness::count_args(
        "How deep drops enter the ground with rapier's flight and with exact landings.",
        "Drops per body, preset, step and flight (a third of them per launch beyond the presets)",
        300,
    );
    let (seed, beyond_seed) = (common.seed_or(1), common.seed_or(3));
    let out = Results::open("drops_impacts", &common)?;
    let mut csv =
        String::from("body,preset,steps_per_s,flight,drops,settled,max_depth,p99_depth,drops_per_s,chi2_p_vs_rapier\n");
    let (mut table, mut extreme) = (String::new(), String::new());
    let mut bars = Vec::new();
    let (mut worst_free, mut least_rapier) = (0.0f64, f64::INFINITY);
    let (mut worst_extreme, mut worst_default, mut beyond_default) = (0.0f64, 0.0f64, 0usize);
    let bodies = benchmark_bodies(harness::repo(), false)?;
    // Beyond the presets: the benchmark bodies and the box of `rocking generate box`.
    let generated = generate::cuboid(1.0, 0.75, 0.4).into_solid_boundary()?;
    let generated = Analysis::of_solid(generated.0, generated.1, &Options::default())?;
    let beyond = bodies.iter().map(|(n, a)| (n.as_str(), a)).chain([("box 1 × 0.75 × 0.4", &generated)]);
    for (name, a) in beyond {
        let stone = Stone::new(a, 0.0035)?;
        // At the default step with free flight: a drop spun at 400 rad/s and a throw at
        // 200 R_max/s sideways (N/3 drops each), default and strict impacts.
        for (label, preset, spin, speed) in [
            ("drop, spin 400 rad/s", Preset::Drop, Some(400.0), None),
            ("throw, 200 R_max/s", Preset::Throw, None, Some(200.0)),
        ] {
            for (strict, numerics) in [(false, "default"), (true, "strict")] {
                let mut p = preset.params(Surface::SteelOnWood);
                (p.launch.spin, p.launch.horizontal_speed) =
                    (spin.unwrap_or(p.launch.spin), speed.unwrap_or(p.launch.horizontal_speed));
                p.sim.flight.strict_impacts = strict;
                let drops = (n / 3).max(1);
                let Measured { max, p99, over, settled, .. } = measure(&stone, &p, beyond_seed, drops)?;
                if strict {
                    worst_extreme = worst_extreme.max(max);
                } else {
                    (worst_default, beyond_default) = (worst_default.max(max), beyond_default + over);
                }
                writeln!(
                    extreme,
                    "| {name} | {label} | {numerics} | {drops} | {max:.1e} | {p99:.1e} | {over} | {settled} |"
                )?;
                println!("{name} {label} strict {strict}: deepest {max:.2e}");
            }
        }
    }
    for (name, a) in &bodies {
        let stone = Stone::new(a, 0.0035)?;
        for preset in PRESETS {
            for inv_dt in STEPS {
                let [r, f] = [Flight::Rapier, Flight::Free].map(|flight| {
                    let mut p = preset.params(Surface::SteelOnWood);
                    (p.sim.numerics.dt, p.sim.flight.mode) = (1.0 / inv_dt, flight);
                    measure(&stone, &p, seed, n)
                });
                let [r, f] = [r?, f?];
                let (_, _, p) = chi_square_homogeneity(&r.flocks, &f.flocks);
                let preset = preset.name();
                for (m, flight) in [(&r, Flight::Rapier), (&f, Flight::Free)] {
                    let (flight, settled, max, p99, per_s) = (flight.name(), m.settled, m.max, m.p99, m.per_s);
                    writeln!(csv, "{name},{preset},{inv_dt},{flight},{n},{settled},{max:e},{p99:e},{per_s:.1},{p:.3}")?;
                }
                let (rmax, r99, fmax, f99) = (r.max, r.p99, f.max, f.p99);
                worst_free = worst_free.max(fmax);
                if preset == Preset::Throw.name() {
                    least_rapier = least_rapier.min(rmax);
                }
                let (rs, fs, rn, fn_) = (r.per_s, f.per_s, r.settled, f.settled);
                writeln!(
                    table,
                    "| {name} | {preset} | 1/{inv_dt} | {rmax:.1e} | {r99:.1e} | {fmax:.1e} | {f99:.1e} | {rs:.0} | {fs:.0} | {rn}/{fn_} | {p:.2} |"
                )?;
                bars.push((rmax, fmax));
                println!("{name} {preset} 1/{inv_dt}: rapier {rmax:.2e}, exact {fmax:.2e}, p {p:.2}");
            }
        }
    }
    out.write("impacts.csv", csv)?;
    plot(&out, &bodies.iter().map(|b| b.0.as_str()).collect::<Vec<_>>(), &bars)?;
    let under = |d: f64| if d <= DEPTH_BOUND { "under" } else { "over" };
    out.readme(
        include_str!("readme/drops_impacts.md"),
        serde_json::json!({
            "n": n, "seed": seed, "beyond_seed": beyond_seed, "landing": CONTACT_CLEARANCE.to_string(),
            "approach": IMPACT_APPROACH.to_string(), "bound": DEPTH_BOUND.to_string(),
            "table": table, "extreme": extreme,
            "worst_free": format!("{worst_free:.2e}"), "worst_free_under": under(worst_free),
            "worst_default": format!("{worst_default:.2e}"), "beyond_default": beyond_default,
            "worst_extreme": format!("{worst_extreme:.2e}"), "holds": under(worst_extreme),
            "least_rapier": format!("{least_rapier:.2}"),
            "worst_rapier": format!("{:.2}", bars.iter().map(|b| b.0).fold(0.0, f64::max)),
        }),
    )
}

/// The largest depth per configuration, one panel per body: per preset and step, rapier's flight
/// beside free flight.
fn plot(out: &Results, bodies: &[&str], bars: &[(f64, f64)]) -> Result<()> {
    let (rapier, exact, hi) = (series_color(0), series_color(1), bars.len() as f64 / 3.0 - 0.5);
    let panels = bodies.iter().zip(bars.chunks(4)).map(|(body, bars)| {
        let steps = PRESETS.iter().flat_map(|_| STEPS.map(|s| format!("1/{s}")));
        let x = Axis::categories("time step (s)", steps.collect()).ticks(4);
        let at = |lo: f64, d: &mut dyn Iterator<Item = f64>| -> Vec<_> {
            d.enumerate().map(|(k, d)| (k as f64 + lo, 5e-5, k as f64 + lo + 0.38, d.max(5e-5))).collect()
        };
        let mut chart = Chart::new(x, Axis::log("depth, largest over the drops (R_max, log scale)", 5e-5, 1.0))
            .title(*body)
            .boxes(&at(-0.4, &mut bars.iter().map(|b| b.0)), rapier, 1.0)
            .boxes(&at(0.02, &mut bars.iter().map(|b| b.1)), exact, 1.0)
            .line_width(&[(-0.5, DEPTH_BOUND), (hi, DEPTH_BOUND)], colors::GREY, 2);
        for (k, preset) in PRESETS.iter().enumerate() {
            chart = chart.text(preset.name(), (2.0 * k as f64 + 0.25, 0.7));
        }
        chart
    });
    Figure::new(
        "Deepest hull corner below the ground, at any step or sub-step, per configuration",
        3,
        panels.collect(),
    )
    .legend(Mark::Box(rapier, 1.0), "rapier's flight (contacts at the step boundaries)")
    .legend(Mark::Box(exact, 1.0), "exact landings + sub-stepped impacts (flight = free)")
    .legend(Mark::WideLine(colors::GREY, 2), format!("depth at which a run warns, {DEPTH_BOUND} R_max"))
    .save(&out.path("impacts.png"), (1100, 760))?;
    Ok(())
}
