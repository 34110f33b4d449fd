//! Housner (1963) rigid blocks in the engine: the tipping threshold a = g·tan α under a slowly
//! rising horizontal ground acceleration, and the angular-velocity ratio 1 − (3/2) sin² α at
//! each impact of free rocking, against the closed forms, over aspect ratios and the engine's
//! contact settings.
//!
//! Blocks: `generate::cuboid(2b, 0.6, 2h)` with h = 1, resting on the face with normal −z,
//! shaken / rocking in the x–z plane (tan α = b/h), on the contact of every resting run (rock on
//! concrete at R_max = 1 m) with friction 1 (no sliding below 1 g).
//!
//! Run: `cargo run --release --example housner_block` → `results/housner_block/`.

use plotters::prelude::*;
use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::resting::RestingParams;
use rocking_stones::dynamics::shaking::housner::{free_rocking, housner_ratio, ramp_tipping};
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::generate;
use rocking_stones::plot::FONT_FAMILY;
use rocking_stones::GRAVITY;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The blocks' slenderness tan α = b/h.
const TAN_ALPHAS: [f64; 6] = [0.15, 0.25, 0.4, 0.5, 0.667, 0.8];
const DEPTH: f64 = 0.3;

fn block(b: f64) -> (Stone, usize) {
    let (mesh, rep) = generate::cuboid(2.0 * b, 2.0 * DEPTH, 2.0).into_solid_boundary().unwrap();
    let a = Analysis::of_solid(mesh, rep, &Options::default()).unwrap();
    let s = Stone::new(&a, 0.01).unwrap();
    let start = s.stable().iter().position(|e| s.body.facet_normals[e.facet as usize].z < -0.999).unwrap();
    (s, start)
}

#[derive(Clone)]
struct Setting {
    name: &'static str,
    restitution: f64,
    contact_frequency: f64,
    dt: f64,
    /// Also run the tipping ramps (slow at small dt).
    tipping: bool,
}

/// The contact of every resting run (rock on concrete, a block of R_max = 1 m: rolling resistance
/// δ = 10⁻⁴ R_max through the contact), with friction 1 and the setting's restitution, contact
/// frequency and step.
fn params(s: &Setting) -> RestingParams {
    let mut p = RestingParams::on_surface(Surface::RockOnConcrete, 1.0).expect("a valid size");
    p.sim.contact.friction = 1.0;
    p.sim.contact.restitution = s.restitution;
    p.sim.numerics.dt = s.dt;
    p.contact_frequency = s.contact_frequency;
    p
}

struct Tip {
    tan_a: f64,
    setting: &'static str,
    rate: f64,
    measured: f64,
    lag: f64,
}

struct Decay {
    tan_a: f64,
    setting: &'static str,
    /// (amplitude before, ratio) of every impact.
    impacts: Vec<(f64, f64)>,
}

impl Decay {
    /// Mean ratio of the first (up to 4) impacts whose post-impact amplitude exceeds 0.02 rad.
    fn mean_large(&self) -> Option<f64> {
        let v: Vec<f64> = self.impacts.iter().filter(|i| i.0 > 0.02).take(4).map(|i| i.1).collect();
        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
    }
}

fn main() -> anyhow::Result<()> {
    let out = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("results/housner_block");
    std::fs::create_dir_all(&out)?;
    let settings = [
        Setting {
            name: "e=0, 120 Hz, dt=1/240 (project default contacts)",
            restitution: 0.0,
            contact_frequency: 120.0,
            dt: 1.0 / 240.0,
            tipping: true,
        },
        Setting {
            name: "e=0, 30 Hz, dt=1/240 (rapier default contacts)",
            restitution: 0.0,
            contact_frequency: 30.0,
            dt: 1.0 / 240.0,
            tipping: true,
        },
        Setting {
            name: "e=0, 120 Hz, dt=1/960",
            restitution: 0.0,
            contact_frequency: 120.0,
            dt: 1.0 / 960.0,
            tipping: true,
        },
        Setting {
            name: "e=0, 120 Hz, dt=1/3840",
            restitution: 0.0,
            contact_frequency: 120.0,
            dt: 1.0 / 3840.0,
            tipping: false,
        },
        Setting {
            name: "e=0.3 (rock on concrete), 120 Hz, dt=1/240",
            restitution: 0.3,
            contact_frequency: 120.0,
            dt: 1.0 / 240.0,
            tipping: true,
        },
    ];
    let mut tips = Vec::new();
    let mut decays = Vec::new();
    for &tan_a in &TAN_ALPHAS {
        let (stone, start) = block(tan_a);
        let r_max = stone.body.r_max;
        let (bs, hs) = (tan_a / r_max, 1.0 / r_max);
        let i_o = 4.0 / 3.0 * (bs * bs + hs * hs);
        for s in &settings {
            let p = params(s);
            for rate in [0.1, 0.03, 0.01] {
                if !s.tipping || (s.restitution > 0.0 && rate != 0.01) {
                    continue;
                }
                let tilt = 1e-3;
                let lag = rate * (6.0 * i_o * tilt / (hs * rate * GRAVITY)).cbrt();
                let measured = ramp_tipping(&stone, start, &p, 0.0, rate, tilt, 2.0 * tan_a).unwrap_or(f64::NAN);
                eprintln!("tan α {tan_a}: {} rate {rate}: {measured:.4} (lag {lag:.4})", s.name);
                tips.push(Tip { tan_a, setting: s.name, rate, measured, lag });
            }
            let alpha = tan_a.atan();
            let cycles = free_rocking(&stone, start, &p, tan_a, 1.0, 0.5 * alpha, 8.0);
            // Impacts until the rocking has died out (amplitude below 10⁻⁵ rad: contact noise).
            let impacts: Vec<(f64, f64)> = cycles
                .windows(2)
                .take_while(|w| w[1].amplitude > 1e-5)
                .map(|w| (w[1].amplitude, w[1].omega0 / w[0].omega0))
                .collect();
            let d = Decay { tan_a, setting: s.name, impacts };
            eprintln!("  decay: mean {:?} vs Housner {:.4}", d.mean_large(), housner_ratio(tan_a, 1.0));
            decays.push(d);
        }
    }
    // CSVs.
    let mut w = csv::Writer::from_path(out.join("tipping.csv"))?;
    w.write_record([
        "tan_alpha",
        "setting",
        "ramp_rate_g_per_s",
        "measured_g",
        "detection_lag_g",
        "corrected_g",
        "relative_error",
    ])?;
    for t in &tips {
        w.write_record([
            t.tan_a.to_string(),
            t.setting.into(),
            t.rate.to_string(),
            format!("{:.5}", t.measured),
            format!("{:.5}", t.lag),
            format!("{:.5}", t.measured - t.lag),
            format!("{:.5}", (t.measured - t.lag) / t.tan_a - 1.0),
        ])?;
    }
    w.flush()?;
    let mut w = csv::Writer::from_path(out.join("rocking_impacts.csv"))?;
    w.write_record(["tan_alpha", "setting", "impact", "amplitude_after_rad", "ratio", "housner"])?;
    for d in &decays {
        for (k, (amp, ratio)) in d.impacts.iter().enumerate() {
            w.write_record([
                d.tan_a.to_string(),
                d.setting.into(),
                (k + 1).to_string(),
                format!("{amp:.6}"),
                format!("{ratio:.5}"),
                format!("{:.5}", housner_ratio(d.tan_a, 1.0)),
            ])?;
        }
    }
    w.flush()?;
    plot(&out.join("housner.png"), &tips, &decays, &settings)?;
    readme(&out.join("README.md"), &tips, &decays, &settings)?;
    Ok(())
}

fn plot(path: &Path, tips: &[Tip], decays: &[Decay], settings: &[Setting]) -> anyhow::Result<()> {
    rocking_stones::plot::draw_png(path, (1400, 600), |root| {
        root.fill(&WHITE)?;
        let (left, right) = root.split_horizontally(700);
        let colors = [
            RGBColor(200, 60, 40),
            RGBColor(40, 90, 200),
            RGBColor(40, 150, 70),
            RGBColor(230, 150, 30),
            RGBColor(150, 60, 170),
        ];
        let mut chart = ChartBuilder::on(&left)
            .caption("Tipping under a slow ramp: measured − detection lag vs g·tan α", (FONT_FAMILY, 18))
            .margin(14)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..0.9, 0.0..0.9)?;
        chart
            .configure_mesh()
            .x_desc("tan α = b/h")
            .y_desc("tipping acceleration (g)")
            .label_style((FONT_FAMILY, 13))
            .draw()?;
        chart
            .draw_series(LineSeries::new(vec![(0.0, 0.0), (0.9, 0.9)], BLACK.stroke_width(1)))?
            .label("Housner: a = g tan α")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK));
        for (s, c) in settings.iter().zip(colors).filter(|(s, _)| s.tipping) {
            let pts: Vec<(f64, f64)> = tips
                .iter()
                .filter(|t| t.setting == s.name && t.rate == 0.01)
                .map(|t| (t.tan_a, t.measured - t.lag))
                .collect();
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 5, c.stroke_width(2))))?
                .label(s.name)
                .legend(move |(x, y)| Circle::new((x + 8, y), 5, c.stroke_width(2)));
        }
        chart
            .configure_series_labels()
            .label_font((FONT_FAMILY, 12))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperLeft)
            .draw()?;
        let mut chart = ChartBuilder::on(&right)
            .caption("Free rocking: angular-velocity ratio per impact", (FONT_FAMILY, 18))
            .margin(14)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..42.0, 0.0..1.05)?;
        chart
            .configure_mesh()
            .x_desc("α (degrees)")
            .y_desc("ω after / ω before")
            .label_style((FONT_FAMILY, 13))
            .draw()?;
        let curve: Vec<(f64, f64)> = (0..=84)
            .map(|i| {
                let a = (i as f64 * 0.5).to_radians();
                (i as f64 * 0.5, 1.0 - 1.5 * a.sin().powi(2))
            })
            .collect();
        chart
            .draw_series(LineSeries::new(curve, BLACK.stroke_width(2)))?
            .label("Housner: 1 − 1.5 sin² α")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK.stroke_width(2)));
        for (k, (s, c)) in settings.iter().zip(colors).enumerate() {
            let pts: Vec<(f64, f64)> = decays
                .iter()
                .filter(|d| d.setting == s.name)
                .filter_map(|d| d.mean_large().map(|m| (d.tan_a.atan().to_degrees() + 0.4 * k as f64 - 0.8, m)))
                .collect();
            chart
                .draw_series(pts.iter().map(|&p| TriangleMarker::new(p, 6, c.filled())))?
                .label(s.name)
                .legend(move |(x, y)| TriangleMarker::new((x + 8, y), 6, c.filled()));
        }
        chart
            .configure_series_labels()
            .label_font((FONT_FAMILY, 12))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::LowerLeft)
            .draw()?;
        Ok(())
    })?;
    Ok(())
}

fn readme(path: &Path, tips: &[Tip], decays: &[Decay], settings: &[Setting]) -> anyhow::Result<()> {
    let mut s = String::new();
    writeln!(s, "# Housner's rigid block in the engine\n")?;
    writeln!(
        s,
        "Blocks `generate::cuboid(2b, 0.6, 2h)`, h = 1, tan α = b/h, resting on the face with normal −z; friction 1 \
         (sliding needs a > 1 g), on the contact of every resting run (rock on concrete at R_max = 1 m: rolling \
         resistance δ = 10⁻⁴ R_max through the contact, no global damping). Rapier 0.36, the project's `HullShape` collider on a half-space ground \
         (a kinematic body). `cargo run --release --example housner_block`.\n"
    )?;
    writeln!(s, "![housner](housner.png)\n")?;
    writeln!(s, "## Tipping threshold (`housner::ramp_tipping`)\n")?;
    writeln!(
        s,
        "The ground accelerates along x with a(t) = rate·t; the reading is the ground acceleration when the resting \
         face has tilted 10⁻³ rad. Past the threshold a_c the overturning moment is m h (a − a_c), so the tilt grows \
         as m h rate g (t − t_c)³/(6 I_O) and the reading lags by Δa = rate·(6 I_O θ_d/(m h rate g))^(1/3), \
         I_O = (4/3) m (b² + h²) (in the scaled frame). Table: rate 0.01 g/s.\n"
    )?;
    writeln!(s, "| tan α | setting | measured (g) | lag (g) | measured − lag | error |\n|---|---|---|---|---|---|")?;
    for t in tips.iter().filter(|t| t.rate == 0.01) {
        writeln!(
            s,
            "| {} | {} | {:.4} | {:.4} | {:.4} | {:+.2} % |",
            t.tan_a,
            t.setting,
            t.measured,
            t.lag,
            t.measured - t.lag,
            100.0 * ((t.measured - t.lag) / t.tan_a - 1.0)
        )?;
    }
    let errs: Vec<f64> =
        tips.iter().filter(|t| t.rate == 0.01).map(|t| ((t.measured - t.lag) / t.tan_a - 1.0).abs()).collect();
    writeln!(
        s,
        "\nLargest |error| after the lag correction at 0.01 g/s: {:.2} %. Faster ramps (0.03, 0.1 g/s, in \
         `tipping.csv`) read later, as the lag formula says.\n",
        100.0 * errs.iter().cloned().fold(0.0, f64::max)
    )?;
    writeln!(s, "## Free rocking (`housner::free_rocking`)\n")?;
    writeln!(
        s,
        "Released from rest tilted by α/2 about its +x bottom edge. For each half-cycle between zero crossings of the \
         tilt θ the impact angular velocity ω₀ = √(ω² + (2 m g R/I_O)(cos(α − |θ|) − cos α)) — constant during a rigid \
         rotation about the corner — is taken as the median over the half-cycle's samples (|θ| ≥ 0.2 × its amplitude), \
         so the ratio ω₀(after)/ω₀(before) measures the impact without reading the few steps the soft contact takes. \
         Mean of the first (up to) four impacts whose following amplitude exceeds 0.02 rad, against Housner's \
         1 − (3/2) sin² α:\n"
    )?;
    write!(s, "| tan α | α (°) | Housner |")?;
    for st in settings {
        write!(s, " {} |", st.name)?;
    }
    writeln!(s)?;
    writeln!(s, "|---|---|---|{}", "---|".repeat(settings.len()))?;
    for &t in &TAN_ALPHAS {
        write!(s, "| {t} | {:.1} | {:.4} |", t.atan().to_degrees(), housner_ratio(t, 1.0))?;
        for st in settings {
            let d = decays.iter().find(|d| d.tan_a == t && d.setting == st.name);
            match d.and_then(|d| d.mean_large()) {
                Some(m) => write!(s, " {m:.4} ({:+.1} %) |", 100.0 * (m / housner_ratio(t, 1.0) - 1.0))?,
                None => write!(s, " – |")?,
            }
        }
        writeln!(s)?;
    }
    writeln!(
        s,
        "\nReading. Housner's law assumes a perfectly plastic impulse at the new corner alone (the old corner lifts \
         off, no bounce, no slip). With restitution 0 and friction 1 the engine's impacts satisfy the same angular \
         momentum balance about the new corner, and the measured ratios agree with 1 − (3/2) sin² α within about \
         1.5 % for α ≤ 34° at the default dt = 1/240 s, mostly slightly *below* it (a little more dissipative): the \
         soft contact spreads the impact over a few steps while gravity and the old contact still act; at \
         dt = 1/960 s and 1/3840 s the deviation drops below about 1 %: the engine converges to Housner's law as the \
         step shrinks. The squat block (α = 38.7°, Housner 0.415) is the exception at the default step: its \
         impacts are the fastest (normal speed 2bω of the impacting corner) and are resolved over several steps of a \
         soft, heavily damped spring whose compression is partly given back — a pseudo-restitution that Housner's \
         plastic impact lacks — so it comes out 10–14 % *above* Housner at 1/240 s, and within 1 % at 1/960 s and \
         1/3840 s. (Only one impact per run has an amplitude above 0.02 rad there, so its column is a single impact.) \
         Restitution: every point that strikes the ground faster than `world::STRUCK_SPEED` (0.1 R_max/s) is \
         brought to rest with Coulomb friction and then sent off at Newton's e u by normal impulses, all struck \
         points solved together (`world::ContactLaw::restitute`; rapier alone applied restitution once, and only \
         to points new in the step). With rock on concrete's e = 0.3 the impacting corner rebounds, so the block \
         loses more per impact than Housner's plastic impulse (last column): little for the slender blocks, whose \
         corners strike slowly (near or below that speed after the first impact), and more the squatter the \
         block, whose corners strike at up to 2bω (down to 16 % below Housner's ratio at α = 38.7°). Robustness \
         and fragility results therefore depend on the restitution chosen; Housner's law is the e = 0 limit. Small amplitudes (corner lift b·θ comparable to the \
         contact's static compression, ~10⁻⁴ R_max) scatter more (every impact down to an amplitude of 10⁻⁵ rad in \
         `rocking_impacts.csv`)."
    )?;
    std::fs::write(path, s)?;
    Ok(())
}
