//! Fragility of a rocking vs a regular equilibrium under ground shaking (precariously balanced
//! rocks): P(topple out of the flock) against peak ground acceleration for sine pulses of
//! several frequencies and for a recorded-style ground motion read from a CSV.
//!
//! The recorded-style motion is a synthetic accelerogram (Kanai–Tajimi / Clough–Penzien
//! filtered noise, predominant period 0.4 s, 10 s; `ground_motion::synthetic::filtered_noise`),
//! written to `motion.csv` and read back through the same reader as the CLI's `--motion`.
//!
//! Run: `cargo experiment fragility_shaking` → `results/fragility_shaking/`; the
//! README's prose is `experiments/readme/fragility_shaking.md`.

use rocking_stones::dynamics::resting::outcome::Outcome;
use rocking_stones::dynamics::resting::{default_pair, RestingParams};
use rocking_stones::dynamics::shaking::{self, sine_pulse, ShakeConfig};
use rocking_stones::dynamics::stone::Class;
use rocking_stones::ground_motion::read::{read_record, AccelUnit};
use rocking_stones::ground_motion::synthetic::{filtered_noise, Noise};
use rocking_stones::prelude::*;
use rocking_stones::report::shake::{self as report, pga50_cell};
use serde_json::json;

use experiments::{harness, rocks};
use harness::{fixed, Context, Result, Results};

const TRIALS: u32 = 40;
const FREQUENCIES: [f64; 4] = [0.5, 1.0, 2.0, 4.0];
/// R_max of the boulder (m): real and scaled time agree.
const R_MAX_M: f64 = 1.0;
/// The surface pair.
const SURFACE: Surface = Surface::StoneOnStone;

fn main() -> Result<()> {
    let common = harness::common_args("Fragility curves of the rocking and the regular equilibrium of a pebble.");
    let shake_seed = common.seed_or(1963);
    let out = Results::open("fragility_shaking", &common)?;
    let params = RestingParams::on_surface(SURFACE, R_MAX_M)?;
    // The pebble of `fig11_rocking_vs_regular`: the first seed with a convincingly balanced rocking equilibrium.
    let (seed, stone, regular, rocking) = (0..50u64)
        .find_map(|seed| {
            let stone = rocks::of_mesh(generate::pebble([1.0, 0.75, 0.5], 0.02, 600, seed), None).ok()?;
            match default_pair(&stone, &params) {
                (Some(g), Some(k)) if stone.stable()[k].basin_exit.epsilon >= 1e-4 => Some((seed, stone, g, k)),
                _ => None,
            }
        })
        .context("no pebble with a rocking equilibrium")?;
    eprintln!("pebble seed {seed}: regular {regular}, rocking {rocking}");
    let noise = Noise { duration: 10.0, period: 0.4, ..Noise::default() };
    let record = filtered_noise(&noise, 1.0, shake_seed)?;
    let csv = out.path("motion.csv");
    report::write_record(&csv, &record)?;
    let dt = params.sim.numerics.dt * R_MAX_M.sqrt();
    let mut motions = Vec::new();
    for f in FREQUENCIES {
        motions.push((format!("pulse_{f}Hz"), sine_pulse(1.0, f, 2.0, dt)?));
    }
    let mut read_back = read_record(&[csv.as_path()], &"time_s,ax_g,ay_g,az_g".parse()?, AccelUnit::G)?;
    read_back.name = format!("{}, read back from motion.csv", record.name);
    motions.push(("record".into(), read_back));
    let pgas: Vec<f64> = (1..=40).map(|i| 0.025 * i as f64).collect();
    let (mut rows, mut names, mut first) = (Vec::new(), Vec::new(), None);
    for (name, motion) in motions {
        let (trials, seed, azimuth, r_max_m) = (TRIALS, shake_seed, None, R_MAX_M);
        let cfg = ShakeConfig { params: params.clone(), motion, pgas: pgas.clone(), trials, seed, azimuth, r_max_m };
        let t = std::time::Instant::now();
        let r = shaking::sweep_fragility(&stone, &[regular, rocking], &cfg)?;
        eprintln!("{name}: {} trials in {:.1} s", r.trials.len(), t.elapsed().as_secs_f64());
        eprint!("{}", report::summary(&r, "pebble"));
        // Each equilibrium's curve and static uplift, in its class's colours (line, marker).
        let mut lines = Vec::new();
        let mut markers = Vec::new();
        for f in &r.fragility {
            let q = &f.equilibrium;
            let (label, line, marker) = match q.class {
                Class::Regular => ("regular", RGBColor(200, 60, 40), RGBColor(230, 150, 130)),
                Class::Rocking => ("rocking", RGBColor(40, 90, 200), RGBColor(130, 160, 230)),
            };
            let uplift = q.uplift_acceleration;
            lines.push((format!("{label}: eq {} ({} flock {})", q.index, q.flock_kind, q.flock), &f.curve[..], line));
            markers.push((uplift, format!("static uplift, eq {}: {uplift:.3} g", q.index), marker));
            // The trials below the static uplift, and those of them that left the micro-equilibrium.
            let at = stone.position(q.index).context("a stable equilibrium")?;
            let below: Vec<_> = r.trials.iter().filter(|t| t.start == at && t.pga < uplift).collect();
            let left = below.iter().filter(|t| t.outcome != Outcome::Same).count();
            rows.push(json!({
                "motion": name, "index": q.index, "facet": q.facet, "class": q.class.to_string(),
                "uplift": fixed(uplift, 3), "micro": pga50_cell(&f.pga50_micro), "flock": pga50_cell(&f.pga50_flock),
                "first": f.first_topple.map_or("–".into(), |x| fixed(x, 3)), "left": left, "below": below.len(),
            }));
        }
        let title = format!("Fragility: {}", r.motion.name);
        report::plot_fragility(&out.path(&format!("fragility_{name}.png")), &title, &lines, &markers)?;
        report::write_fragility_csv(&out.path(&format!("fragility_{name}.csv")), &r)?;
        first.get_or_insert(r.params);
        names.push(name);
    }
    let contact = first.context("no motion was run")?.sim.contact;
    let units = FREQUENCIES.map(|f| [0.03, 0.1, 2.0, 5.0].map(|l: f64| fixed(f / l.sqrt(), 2)));
    out.readme(include_str!("readme/fragility_shaking.md"),
        json!({
            "seed": seed, "nu": format!("{:.3e}", stone.nu), "trials": TRIALS, "shake_seed": shake_seed,
            "r_max": R_MAX_M.to_string(), "surface": SURFACE.to_string(), "friction": contact.friction.to_string(),
            "restitution": contact.restitution.to_string(), "delta": format!("{:.1e}", contact.rolling_resistance),
            "units": FREQUENCIES.iter().zip(units).map(|(f, u)| json!({"f": f.to_string(), "real": u})).collect::<Vec<_>>(),
            "rows": rows, "names": names,
        }),
    )
}
