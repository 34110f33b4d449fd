//! A box's corner impact against the closed forms of a rigid body's impact
//! (`dynamics::engine::impulse`), at rapier's solver sub-steps 1–32: where its spin lies between
//! them (the slip fraction φ, `PointImpact::slip_fraction`).
//!
//! Run: `cargo experiment corner_impact` → `results/corner_impact/`.

use nalgebra::UnitQuaternion;
use rocking_stones::dynamics::drops::{batch::simulate_batch, launch::Release};
use rocking_stones::dynamics::engine::{impulse::PointImpact, run::NoCertificate, world::BodyState};
use rocking_stones::dynamics::shaking::housner::block_stone;
use rocking_stones::prelude::*;
use rocking_stones::stats::median_range;

use experiments::harness;
use harness::{fixed, Context, Result, Results};

const SUBSTEPS: [usize; 6] = [1, 2, 4, 8, 16, 32];
const RESTITUTIONS: [f64; 2] = [0.2, 0.5];
const FRICTION: f64 = 0.6;
const HEIGHT: f64 = 0.5;
const ORIENTATIONS: u64 = 40;
/// Least height (R_max) of the second-lowest corner above the lowest at release: the impact is
/// one corner's, as the closed forms assume.
const SECOND_CORNER: f64 = 0.05;

/// The stone's states just before and just after its first impact (the first step that turns it).
fn first_impact(stone: &Stone, q: UnitQuaternion<f64>, e: f64, substeps: usize) -> Result<(BodyState, BodyState)> {
    let mut p = Preset::Drop.params(Surface::SteelOnWood);
    let c = &mut p.sim.contact;
    (c.friction, c.restitution, c.linear_damping, c.angular_damping) = (FRICTION, e, 0.0, 0.0);
    (c.rolling_resistance, c.torsional_friction) = (0.0, 0.0);
    (p.sim.flight.mode, p.sim.numerics.solver_iterations, p.launch.height) = (Flight::Free, substeps, HEIGHT);
    let release = Release { orientation: q, linvel: Vec3::zeros(), angvel: Vec3::zeros() };
    let (mut before, mut after) = (None, None);
    let mut observe = |_, s: &BodyState| match (after.is_none(), s.angvel.norm() > 1e-9) {
        (true, true) => after = Some(*s),
        (true, false) => before = Some(*s),
        _ => {}
    };
    let mut queue = std::iter::once((0, release));
    simulate_batch(stone, &p, &NoCertificate, 1, &mut queue, &mut |_| {}, &mut observe);
    Ok((before.context("no fall before the impact")?, after.context("no impact")?))
}

/// One simulated impact: its restitution, sub-steps, spin error and slip fraction φ.
type Impact = (f64, usize, f64, f64);
/// Per restitution and sub-step count: the spin error's and φ's median, least and largest.
type Row = (f64, usize, [f64; 3], [f64; 3]);

fn main() -> Result<()> {
    let common =
        harness::common_args("Where a box's corner impact lies between the closed forms, at solver sub-steps 1–32.");
    let seed = common.seed_or(3);
    let out = Results::open("corner_impact", &common)?;
    let (stone, _) = block_stone(0.5, 0.4, 0.25, None)?; // a box 1 × 0.8 × 0.5
    let launch_params = Preset::Drop.params(Surface::SteelOnWood);
    let mut impacts: Vec<Impact> = Vec::new();
    let (mut sticking, mut sliding, mut two_corners) = (0, 0, 0);
    'orientations: for i in 0..ORIENTATIONS {
        let q = launch(&mut item_rng(seed, i), &launch_params).orientation;
        let down = q.inverse() * -Vec3::z();
        // A single corner strikes: the next corner down is at least SECOND_CORNER above it.
        let mut corners = stone.body.corners.clone();
        corners.sort_by(|a, b| b.dot(&down).total_cmp(&a.dot(&down)));
        if corners[0].dot(&down) - corners[1].dot(&down) < SECOND_CORNER {
            two_corners += 1;
            continue;
        }
        let impact = PointImpact::new(&stone.body.world_inertia(&q), &(q * corners[0])).context("a singular impact")?;
        for e in RESTITUTIONS {
            let mut rows = Vec::new();
            for substeps in SUBSTEPS {
                // The closed forms need only the approach speed, read off the last state before it.
                let (before, after) = first_impact(&stone, q, e, substeps)?;
                let u = -before.linvel.z;
                let newton = impact.sticking(e, u);
                if newton.xy().norm() > FRICTION * newton.z {
                    sliding += 1;
                    continue 'orientations;
                }
                let (w_n, slip) = (impact.spin(&newton), impact.slip_fraction(e, u, &after.angvel));
                rows.push((e, substeps, (after.angvel - w_n).norm() / w_n.norm(), slip));
            }
            // An orientation that slides at the second e keeps its rows of the first.
            impacts.extend(rows);
        }
        sticking += 1;
    }
    out.csv(
        "impacts.csv",
        &["restitution", "substeps", "spin_error", "slip_fraction"],
        impacts.iter().map(|m| [m.0.to_string(), m.1.to_string(), fixed(m.2, 6), fixed(m.3, 6)]),
    )?;
    let rows: Vec<Row> = (RESTITUTIONS.iter())
        .flat_map(|&e| SUBSTEPS.map(|k| (e, k)))
        .map(|(e, k)| {
            let of = impacts.iter().filter(|m| m.0 == e && m.1 == k);
            let (errors, slips): (Vec<f64>, Vec<f64>) = of.map(|m| (m.2, m.3)).unzip();
            (e, k, median_range(&errors), median_range(&slips))
        })
        .collect();
    plot(&out, &rows)?;
    let at = |k: usize| RESTITUTIONS.map(|e| rows.iter().find(|r| (r.0, r.1) == (e, k)).map(|r| r.3[0]));
    let phi = RESTITUTIONS.map(|e| {
        let [_, lo, hi] = median_range(&rows.iter().filter(|r| r.0 == e).map(|r| r.3[0]).collect::<Vec<_>>());
        serde_json::json!({"lo": fixed(lo, 2), "hi": fixed(hi, 2)})
    });
    let f2 = |x: Option<f64>| x.map(|x| fixed(x, 2));
    out.readme(
        include_str!("readme/corner_impact.md"),
        serde_json::json!({
            "height": HEIGHT.to_string(), "orientations": sticking + sliding + two_corners, "seed": seed,
            "two_corners": two_corners, "second_corner": SECOND_CORNER.to_string(), "friction": FRICTION.to_string(),
            "inv_dt": fixed(1.0 / launch_params.sim.numerics.dt, 0), "sticking": sticking, "sliding": sliding,
            "rows": rows.iter().map(|r| [
                r.0.to_string(), r.1.to_string(), fixed(r.2[0], 3), fixed(r.2[2], 3),
                fixed(r.3[0], 2), fixed(r.3[1], 2), fixed(r.3[2], 2),
            ]).collect::<Vec<_>>(),
            "phi": phi, "at4": at(4).map(f2), "at32": at(32).map(f2),
        }),
    )
}

fn plot(out: &Results, rows: &[Row]) -> Result<()> {
    let lo = rows.iter().map(|r| r.3[1]).fold(0.0, f64::min) - 0.05;
    let hi = rows.iter().map(|r| r.3[2]).fold(1.0, f64::max) + 0.05;
    let mut chart = Chart::new(
        Axis::log("rapier solver sub-steps per step (default 4)", 0.8, 40.0).format(|x| format!("{x:.0}")).no_grid(),
        Axis::linear("φ: 0 Newton + sticking friction, 1 frictionless restitution", lo, hi),
    )
    .title("Corner impact of a box: where the contact's spin lies (φ)")
    .hline(0.0, colors::GREY);
    for (e, color) in RESTITUTIONS.iter().zip([colors::VERMILLION, colors::BLUE]) {
        let of = || rows.iter().filter(|r| r.0 == *e);
        chart = chart
            .y_bars(&of().map(|r| (r.1 as f64, r.3[1], r.3[2])).collect::<Vec<_>>(), color)
            .line_width(&of().map(|r| (r.1 as f64, r.3[0])).collect::<Vec<_>>(), color, 3)
            .legend(Mark::WideLine(color, 3), format!("e = {e}: median and range"));
    }
    chart.save(&out.path("slip.png"), (900, 560))?;
    Ok(())
}
