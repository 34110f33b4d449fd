//! How good are ensemble probabilities of toppling, and against what truth?
//!
//! **A. Freestanding blocks against Housner and the published fragility form.** Purvance,
//! Anooshehpoor & Brune (2008, Earthquake Engng Struct. Dyn. 37, 791) give the overturning
//! probability of a freestanding block as a function of its slenderness α, its size (through
//! p = √(3g/4R)), PGA and PGV/PGA, in the logistic form P = 1/(1 + e^−η),
//! η = β₀ + β₁ ln PGA + β₂ ln PGV/PGA fitted per block (the form of the project's
//! [`rocking_stones::ground_motion::fragility`]); their 2-D numerical fragilities integrate
//! Housner's rocking equation. Here five blocks (tan α = 0.15, 0.25, 0.4 at R = 1 m; tan α = 0.25
//! at R = 0.5 m and 2 m) are shaken by one-component records — filtered noise of four
//! predominant periods × two seeds, and one-sine pulses of three periods — scaled to
//! PGA/(g tan α) from 0.8 to 4, by an ensemble over an unknown azimuth and an unknown sign.
//! The same members are integrated with Housner's equation
//! ([`rocking_stones::dynamics::shaking::housner::housner_overturns`], the record's component along the
//! rocking plane, a·cos θ). Both are fitted with the published form; the P = 0.5 contours are
//! compared in the dimensionless variables PGA/(g tan α) and p·PGV/PGA, in which Housner's
//! equation under a time-scaled record is exactly self-similar.
//!
//! **B. Scores.** No outcome here is observed: every truth is simulated, and from the
//! ensemble's own uncertainty, drawn exactly as its members are.
//! * Blocks: the truth is Housner's rocking equation (a second model: 2-D, rigid, instantaneous
//!   impacts) for 64 further rocks per case, drawn independently from the same uncertainty
//!   (azimuth, sign) as the 16 forecast members — not the members' own draws. The dynamics of
//!   forecast and truth differ; the uncertainty is the ensemble's own, known exactly.
//! * The scanned quarry stone in its rocking pose (base-contact tolerance 0–2 mm, azimuth
//!   unknown, random sign, the rock-on-concrete ranges of friction, restitution and rolling
//!   resistance): the truth is 32 held-out members of the same simulation, a perfect-model test.
//!   It measures what a probability is worth over a yes/no when the model and the uncertainty
//!   are exactly right, not the simulator's error (part A and the blocks compare it with
//!   Housner's equation) nor how well a real rock's uncertainty is known.
//!
//! The ensemble's P is scored by the Brier score and the log loss beside three yes/no forecasts
//! (0 or 1), so that it is not compared with an extreme member only:
//! * the **nominal member** ([`rocking_stones::dynamics::shaking::Uncertainty::nominal`]): every
//!   uncertain input at a central value — base contact at the middle of its range, the surface
//!   pair's nominal friction, restitution and δ, and for an azimuth over the whole circle and a
//!   random sign, which have no centre, the record as given;
//! * the **as-given run** (what `rocking shake` runs without `--ensemble`): for the quarry stone
//!   the scanned hull as is (tolerance 0, the end of the range with the smallest support
//!   polygon); for the blocks, whose only uncertain inputs are azimuth and sign, the same rock as
//!   the nominal member (azimuth 0: along the rocking plane);
//! * the **best yes/no**: each case's majority truth outcome, a bound no single run reaches.
//!
//! Run: `cargo run --release --example ensemble_fragility` → `results/ensemble_fragility/`.

use plotters::prelude::*;
use rayon::prelude::*;
use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::resting::default_pair;
use rocking_stones::dynamics::shaking::ensemble::draw;
use rocking_stones::dynamics::shaking::housner::{housner_overturns, housner_ratio};
use rocking_stones::dynamics::shaking::{
    rock_params, run_batch, EnsembleSpec, Pose, RecordRun, RockSetup, Uncertainty,
};
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::generate;
use rocking_stones::ground_motion::fragility::FragilitySurface;
use rocking_stones::ground_motion::synthetic::{filtered_noise, one_sine_pulse, Noise};
use rocking_stones::ground_motion::Record;
use rocking_stones::plot::colors::GREY;
use rocking_stones::plot::{draw_legend, legend_height, log_tick, plain, series_color, style, Mark, FONT_FAMILY};
use rocking_stones::GRAVITY as G;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Members of a block's forecast ensemble, and Housner rocks drawn as its truth.
const BLOCK_MEMBERS: u64 = 16;
const BLOCK_TRUTHS: u64 = 64;
/// The quarry stone: forecast members 0..32, held-out truth 32..64.
const STONE_MEMBERS: u64 = 32;
const STONE_TRUTHS: u64 = 32;
/// PGA/(g tan α) of the block runs (capped at 1.2 g).
const X_GRID: [f64; 8] = [0.8, 1.0, 1.25, 1.6, 2.0, 2.5, 3.2, 4.0];
/// Half-depth of the blocks (h = 1): rocking across it needs 1.5 g, above every PGA run, and
/// friction 1.5 keeps them from sliding — the two assumptions of Housner's equation.
const DEPTH: f64 = 1.5;
const FRICTION: f64 = 1.5;
const SEED: u64 = 24;
/// The stream of the blocks' truth draws: members BLOCK_MEMBERS.. of the same seed are
/// independent of the forecast's.
const TRUTH_OFFSET: u64 = 1_000;

/// A freestanding block 2b × 2d × 2h (h = 1 mesh unit), scaled to a semi-diagonal R (m) of its
/// rocking plane.
struct Block {
    tan_alpha: f64,
    r_m: f64,
}

impl Block {
    fn name(&self) -> String {
        format!("tan{:.2}_R{}", self.tan_alpha, self.r_m)
    }
    fn alpha(&self) -> f64 {
        self.tan_alpha.atan()
    }
    /// Housner's p = √(3g/4R) (rad/s).
    fn p(&self) -> f64 {
        (3.0 * G / (4.0 * self.r_m)).sqrt()
    }
}

const BLOCKS: [Block; 5] = [
    Block { tan_alpha: 0.25, r_m: 1.0 },
    Block { tan_alpha: 0.15, r_m: 1.0 },
    Block { tan_alpha: 0.4, r_m: 1.0 },
    Block { tan_alpha: 0.25, r_m: 0.5 },
    Block { tan_alpha: 0.25, r_m: 2.0 },
];

fn analysed(mesh: rocking_stones::mesh::TriMesh, nu: Option<f64>) -> anyhow::Result<Stone> {
    let (mesh, rep) = mesh.into_solid_boundary()?;
    let a = Analysis::of_solid(mesh, rep, &Options::default())?;
    let nu = nu.unwrap_or_else(|| a.macro_nu(&Options::default()).0);
    Ok(Stone::new(&a, nu)?)
}

/// One-component records scaled to PGA 1 g: filtered noise (4 periods × 2 seeds, 20 s at
/// 200 Hz) and one-sine pulses of period 0.5, 1, 2 and 4 s.
fn records() -> anyhow::Result<Vec<Record>> {
    let mut v = Vec::new();
    for period in [0.2, 0.5, 1.0, 2.0] {
        for seed in [1, 2] {
            let noise = Noise { duration: 20.0, period, components: 1, ..Noise::default() };
            let mut r = filtered_noise(&noise, 1.0, seed)?;
            r.name = format!("noise_T{period}_s{seed}");
            v.push(r);
        }
    }
    for tp in [0.5, 1.0, 2.0, 4.0] {
        let mut r = one_sine_pulse(1.0, tp, tp / 1000.0)?;
        r.name = format!("pulse_T{tp}");
        v.push(r);
    }
    Ok(v)
}

/// One record × scale of a rock: the forecast and the outcomes it is scored against.
struct Case {
    rock: String,
    record: String,
    scale: f64,
    pga_g: f64,
    pgv_over_pga_s: f64,
    /// Settled forecast members and those that overturned.
    settled: usize,
    overturned: usize,
    /// Housner's equation on the forecast's own draws (blocks only).
    ode_same_draws: Option<f64>,
    /// The as-given run (no ensemble: tolerance 0, azimuth 0, sign +, nominal contact) overturned.
    as_given: bool,
    /// The nominal member ([`Uncertainty::nominal`]) overturned.
    nominal: bool,
    /// Outcomes of the truth rocks.
    truths: Vec<bool>,
}

impl Case {
    fn p(&self) -> f64 {
        if self.settled > 0 {
            self.overturned as f64 / self.settled as f64
        } else {
            0.5
        }
    }
}

/// The outcome of the run of `runs` on the record and scale of `d`.
fn outcome_of(runs: &[RecordRun], d: &RecordRun) -> bool {
    let same = |r: &&RecordRun| r.record == d.record && r.scale.to_bits() == d.scale.to_bits();
    runs.iter().find(same).expect("every record × scale was run").rock.overturned
}

/// The best any yes/no forecast of a case can do: its truths' majority outcome.
fn majority(c: &Case) -> bool {
    2 * c.truths.iter().filter(|&&y| y).count() >= c.truths.len()
}

/// Brier score, log loss and accuracy of a set of forecasts (one probability per case) against
/// every truth of its case.
#[derive(Clone, Copy, Default)]
struct Score {
    brier: f64,
    log_loss: f64,
    accuracy: f64,
    n: usize,
}

/// Forecasts are kept inside [ε, 1 − ε] for the log loss, ε = 1/(2 n) for an ensemble of n
/// members (half a member: a forecast of 0 or 1 from n draws is no surer than that); the yes/no
/// of a yes/no forecast gets the same ε, else one wrong answer makes its log loss infinite.
fn score(cases: &[&Case], forecast: &dyn Fn(&Case) -> f64, eps: f64) -> Score {
    let mut s = Score::default();
    for c in cases {
        let p = forecast(c);
        let q = p.clamp(eps, 1.0 - eps);
        for &y in &c.truths {
            let y = y as u8 as f64;
            s.brier += (p - y) * (p - y);
            s.log_loss -= y * q.ln() + (1.0 - y) * (1.0 - q).ln();
            s.accuracy += (((p >= 0.5) as u8 as f64) == y) as u8 as f64;
            s.n += 1;
        }
    }
    let n = s.n.max(1) as f64;
    Score { brier: s.brier / n, log_loss: s.log_loss / n, accuracy: s.accuracy / n, n: s.n }
}

/// The lowest Brier score any forecast of these cases can have: each case forecast by its own
/// truth frequency q, Brier q(1 − q).
fn oracle_brier(cases: &[&Case]) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for c in cases {
        let k = c.truths.len();
        let q = c.truths.iter().filter(|&&y| y).count() as f64 / k.max(1) as f64;
        sum += q * (1.0 - q) * k as f64;
        n += k;
    }
    sum / n.max(1) as f64
}

/// What a block run gives: its cases and the two fitted surfaces (simulation, Housner).
struct BlockResult {
    cases: Vec<Case>,
    surface: Option<FragilitySurface>,
    ode_surface: Option<FragilitySurface>,
    runs: usize,
    seconds: f64,
}

fn block_stone(b: &Block) -> anyhow::Result<(Stone, usize)> {
    let s = analysed(generate::cuboid(2.0 * b.tan_alpha, 2.0 * DEPTH, 2.0), Some(0.01))?;
    let bottom = s
        .stable()
        .iter()
        .find(|e| s.body.facet_normals[e.facet as usize].z < -0.999)
        .ok_or_else(|| anyhow::anyhow!("block {}: no stable bottom face", b.name()))?
        .index;
    Ok((s, bottom))
}

/// Housner's equation for block `b` under `record` × `scale` along azimuth `azimuth_deg` with
/// sign `sign`: the record's component in the rocking plane.
fn housner(b: &Block, record: &Record, scale: f64, azimuth_deg: f64, sign: f64) -> bool {
    let k = scale * sign * azimuth_deg.to_radians().cos();
    let accel = |t: f64| k * record.at(t)[0];
    housner_overturns(b.alpha(), b.p(), &accel, record.duration(), housner_ratio(b.tan_alpha, 1.0))
}

fn run_block(b: &Block, records: &[Record]) -> anyhow::Result<BlockResult> {
    let t0 = Instant::now();
    let (stone, bottom) = block_stone(b)?;
    // Mesh: h = 1, rocking semi-diagonal √(tan²α + 1) mesh units = R metres.
    let unit = b.r_m / (b.tan_alpha * b.tan_alpha + 1.0).sqrt();
    let r_max_m = stone.body.r_max * unit;
    let mut params = rock_params(Surface::RockOnConcrete, r_max_m)?;
    params.sim.contact.friction = FRICTION;
    params.sim.contact.restitution = 0.0;
    let setup = RockSetup::with_params(&stone, Pose::Facet { id: bottom }, unit, 0.0, params);
    let uncertainty = Uncertainty { azimuth_deg: Some([0.0, 360.0]), random_sign: true, ..Uncertainty::default() };
    let spec = EnsembleSpec { uncertainty: uncertainty.clone(), seed: SEED, members: BLOCK_MEMBERS };
    let scales: Vec<f64> = X_GRID.iter().map(|x| x * b.tan_alpha).filter(|&pga| pga <= 1.2 + 1e-9).collect();
    let ensemble = run_batch(&stone, &setup, records, &scales, Some(&spec), &[], &|_| {})?;
    let single = run_batch(&stone, &setup, records, &scales, None, &[], &|_| {})?;
    let nominal = run_batch(&stone, &setup, records, &scales, Some(&spec.nominal(&setup)), &[], &|_| {})?;
    let by_record: BTreeMap<&str, &Record> = records.iter().map(|r| (r.name.as_str(), r)).collect();
    let mut cases = Vec::new();
    let mut ode_points = Vec::new();
    for d in &single.runs {
        let members: Vec<&RecordRun> =
            ensemble.runs.iter().filter(|r| r.record == d.record && r.scale.to_bits() == d.scale.to_bits()).collect();
        let record = by_record[d.record.as_str()];
        let same: Vec<bool> = members
            .par_iter()
            .map(|m| {
                let draw = m.member.expect("an ensemble run");
                housner(b, record, d.scale, draw.azimuth_deg, draw.sign)
            })
            .collect();
        let truths: Vec<bool> = (0..BLOCK_TRUTHS)
            .into_par_iter()
            .map(|k| {
                let t = draw(&uncertainty, &setup, SEED, TRUTH_OFFSET + k);
                housner(b, record, d.scale, t.azimuth_deg, t.sign)
            })
            .collect();
        for &o in &same {
            ode_points.push(rocking_stones::ground_motion::fragility::Run {
                pga_g: d.pga_g,
                pgv_over_pga_s: d.pgv_over_pga_s,
                overturned: o,
            });
        }
        let settled: Vec<&&RecordRun> = members.iter().filter(|m| m.rock.settled).collect();
        cases.push(Case {
            rock: b.name(),
            record: d.record.clone(),
            scale: d.scale,
            pga_g: d.pga_g,
            pgv_over_pga_s: d.pgv_over_pga_s,
            settled: settled.len(),
            overturned: settled.iter().filter(|m| m.rock.overturned).count(),
            ode_same_draws: Some(same.iter().filter(|&&o| o).count() as f64 / same.len() as f64),
            as_given: d.rock.overturned,
            nominal: outcome_of(&nominal.runs, d),
            truths,
        });
    }
    Ok(BlockResult {
        cases,
        surface: ensemble.surface,
        ode_surface: FragilitySurface::fit(&ode_points).ok(),
        runs: ensemble.runs.len() + single.runs.len() + nominal.runs.len(),
        seconds: t0.elapsed().as_secs_f64(),
    })
}

/// The quarry stone in its rocking pose at scanned size under two-component filtered noise:
/// forecast members, held-out truth members, the as-given run and the nominal member; and the
/// nominal member's inputs.
fn run_stone() -> anyhow::Result<(Vec<Case>, String, f64, String)> {
    let t0 = Instant::now();
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/meshes/stone_quarry_ibois_AAA_lowres_bin.ply"));
    let a = Analysis::of_file(path, &Options::default())?;
    let (nu, _) = a.macro_nu(&Options::default());
    let stone = Stone::new(&a, nu)?;
    let probe = rock_params(Surface::RockOnConcrete, stone.body.r_max)?;
    let (regular, rocking) = default_pair(&stone, &probe);
    let k = rocking.or(regular).ok_or_else(|| anyhow::anyhow!("the quarry stone has no stable pose"))?;
    let pose = Pose::Facet { id: stone.stable()[k].index };
    let setup = RockSetup::new(&stone, pose, 1.0, Surface::RockOnConcrete, 0.0)?;
    let given = Uncertainty {
        contact_tolerance_m: Some([0.0, 0.002]),
        azimuth_deg: Some([0.0, 360.0]),
        random_sign: true,
        ..Uncertainty::default()
    };
    let uncertainty = Uncertainty::stated(&given, Surface::RockOnConcrete, 1.0, [false; 3]);
    let spec = EnsembleSpec { uncertainty, seed: SEED, members: STONE_MEMBERS + STONE_TRUTHS };
    let mut records = Vec::new();
    for period in [0.2, 0.5, 1.0, 2.0] {
        let noise = Noise { duration: 20.0, period, components: 2, ..Noise::default() };
        let mut r = filtered_noise(&noise, 1.0, 1)?;
        r.name = format!("noise2_T{period}");
        records.push(r);
    }
    let scales = [0.04, 0.06, 0.08, 0.11, 0.15, 0.2];
    let ensemble = run_batch(&stone, &setup, &records, &scales, Some(&spec), &[], &|_| {})?;
    let single = run_batch(&stone, &setup, &records, &scales, None, &[], &|_| {})?;
    let nominal_spec = spec.nominal(&setup);
    let nominal = run_batch(&stone, &setup, &records, &scales, Some(&nominal_spec), &[], &|_| {})?;
    let d = draw(&nominal_spec.uncertainty, &setup, SEED, 0);
    let nominal_inputs = format!(
        "base contact {:.1} mm, μ {}, e {}, δ {:.2} mm",
        1e3 * d.contact_tolerance_m,
        d.friction,
        d.restitution,
        1e3 * d.rolling_resistance_m
    );
    let cases = single
        .runs
        .iter()
        .map(|d| {
            let members: Vec<&RecordRun> = ensemble
                .runs
                .iter()
                .filter(|r| r.record == d.record && r.scale.to_bits() == d.scale.to_bits() && r.rock.settled)
                .collect();
            let (forecast, truth): (Vec<&RecordRun>, Vec<&RecordRun>) =
                members.iter().partition(|r| r.member.expect("an ensemble run").member < STONE_MEMBERS);
            Case {
                rock: "quarry_AAA".into(),
                record: d.record.clone(),
                scale: d.scale,
                pga_g: d.pga_g,
                pgv_over_pga_s: d.pgv_over_pga_s,
                settled: forecast.len(),
                overturned: forecast.iter().filter(|r| r.rock.overturned).count(),
                ode_same_draws: None,
                as_given: d.rock.overturned,
                nominal: outcome_of(&nominal.runs, d),
                truths: truth.iter().map(|r| r.rock.overturned).collect(),
            }
        })
        .collect();
    Ok((cases, format!("{pose}"), t0.elapsed().as_secs_f64(), nominal_inputs))
}

fn main() -> anyhow::Result<()> {
    let out = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/results/ensemble_fragility"));
    std::fs::create_dir_all(&out)?;
    let records = records()?;
    let mut blocks = Vec::new();
    for b in &BLOCKS {
        let r = run_block(b, &records)?;
        eprintln!("block {}: {} runs in {:.1} s", b.name(), r.runs, r.seconds);
        blocks.push(r);
    }
    let (stone_cases, stone_pose, stone_seconds, nominal_inputs) = run_stone()?;
    eprintln!("quarry stone: {} cases in {stone_seconds:.1} s", stone_cases.len());

    write_cases(&out, &blocks, &stone_cases)?;
    let mut readme = String::new();
    writeln!(
        readme,
        "# Ensemble fragility: blocks against Housner and the published form, and scores\n\n\
         Regenerate: `cargo run --release --example ensemble_fragility` (about {:.0} min on 2 cores).\n",
        (blocks.iter().map(|b| b.seconds).sum::<f64>() + stone_seconds) / 60.0
    )?;
    part_a(&out, &blocks, &records, &mut readme)?;
    part_b(&out, &blocks, &stone_cases, &stone_pose, &nominal_inputs, &mut readme)?;
    std::fs::write(out.join("README.md"), readme)?;
    eprintln!("wrote {}", out.display());
    Ok(())
}

fn write_cases(out: &Path, blocks: &[BlockResult], stone: &[Case]) -> anyhow::Result<()> {
    let mut csv = String::from(
        "rock,record,scale,pga_g,pgv_over_pga_s,members_settled,members_overturned,p_ensemble,p_housner_same_draws,\
         deterministic_overturned,truths,truths_overturned,nominal_overturned\n",
    );
    for c in blocks.iter().flat_map(|b| &b.cases).chain(stone) {
        writeln!(
            csv,
            "{},{},{},{:.5},{:.5},{},{},{:.4},{},{},{},{},{}",
            c.rock,
            c.record,
            c.scale,
            c.pga_g,
            c.pgv_over_pga_s,
            c.settled,
            c.overturned,
            c.p(),
            c.ode_same_draws.map_or(String::new(), |p| format!("{p:.4}")),
            c.as_given,
            c.truths.len(),
            c.truths.iter().filter(|&&y| y).count(),
            c.nominal
        )?;
    }
    std::fs::write(out.join("cases.csv"), csv)?;
    Ok(())
}

/// The p·PGV/PGA axis of the plot.
const TAU_AXIS: [f64; 2] = [0.1, 6.0];

/// p·PGV/PGA values at which the P = 0.5 contours are compared.
const TAU_GRID: [f64; 5] = [0.3, 0.5, 1.0, 2.0, 3.0];

fn part_a(out: &Path, blocks: &[BlockResult], records: &[Record], readme: &mut String) -> anyhow::Result<()> {
    writeln!(
        readme,
        "## A. Freestanding blocks: simulation, Housner's equation and the published form\n\n\
         Blocks 2b × {d2} × 2h (tan α = b/h; the depth {d2} h keeps them rocking in one plane below 1.5 g), \
         friction {FRICTION} (no sliding), restitution 0 (Housner's impact), at real size R (semi-diagonal of the \
         rocking plane). {} one-component records (filtered noise, predominant periods 0.2, 0.5, 1, 2 s × 2 seeds, \
         20 s at 200 Hz; one-sine pulses of period 0.5, 1, 2, 4 s), scaled to PGA/(g tan α) = {X_GRID:?} (PGA ≤ 1.2 g). \
         Ensemble of {BLOCK_MEMBERS} members per record × scale: azimuth unknown (0–360°) and random sign. \
         Housner's equation is integrated for the same members with the record's component a·cos θ in the rocking \
         plane. Both are fitted with the published form P = 1/(1 + exp(−(β₀ + β₁ ln PGA + β₂ ln PGV/PGA))) \
         (Firth-penalised). PGA₅₀ is the P = 0.5 contour, given as PGA₅₀/(g tan α) at p·PGV/PGA = τ.\n\n\
         | block | tan α | R (m) | p (rad/s) | runs | β₁ ± se | β₂ ± se | Housner β₁ | Housner β₂ | PGA₅₀/(g tan α) at τ = {} (sim / Housner) | time (s) |\n\
         |---|---|---|---|---|---|---|---|---|---|---|",
        records.len(),
        TAU_GRID.map(|t| t.to_string()).join(", "),
        d2 = 2.0 * DEPTH,
    )?;
    let mut csv =
        String::from("block,tan_alpha,r_m,p,source,beta0,beta1,beta2,se0,se1,se2,tau,pga50_over_g_tan_alpha\n");
    for (b, r) in BLOCKS.iter().zip(blocks) {
        let fmt_beta = |s: &Option<FragilitySurface>, i: usize, se: bool| {
            s.as_ref().map_or("-".to_string(), |s| {
                if se {
                    format!("{:.2} ± {:.2}", s.beta[i], s.std_err[i])
                } else {
                    format!("{:.2}", s.beta[i])
                }
            })
        };
        let mut cells = Vec::new();
        for &tau in &TAU_GRID {
            let at = |s: &Option<FragilitySurface>| {
                s.as_ref().and_then(|s| s.pga_at(0.5, tau / b.p())).map(|pga| pga / b.tan_alpha)
            };
            let (sim, ode) = (at(&r.surface), at(&r.ode_surface));
            let f = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.2}"));
            cells.push(format!("{} / {}", f(sim), f(ode)));
            for (source, s, x) in [("simulation", &r.surface, sim), ("housner", &r.ode_surface, ode)] {
                if let Some(s) = s {
                    writeln!(
                        csv,
                        "{},{},{},{:.4},{source},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{tau},{}",
                        b.name(),
                        b.tan_alpha,
                        b.r_m,
                        b.p(),
                        s.beta[0],
                        s.beta[1],
                        s.beta[2],
                        s.std_err[0],
                        s.std_err[1],
                        s.std_err[2],
                        x.map_or(String::new(), |v| format!("{v:.4}"))
                    )?;
                }
            }
        }
        writeln!(
            readme,
            "| {} | {} | {} | {:.2} | {} | {} | {} | {} | {} | {} | {:.0} |",
            b.name(),
            b.tan_alpha,
            b.r_m,
            b.p(),
            r.runs,
            fmt_beta(&r.surface, 1, true),
            fmt_beta(&r.surface, 2, true),
            fmt_beta(&r.ode_surface, 1, false),
            fmt_beta(&r.ode_surface, 2, false),
            cells.join(" · "),
            r.seconds
        )?;
    }
    std::fs::write(out.join("surfaces.csv"), csv)?;
    // Member agreement, case by case: ensemble P against Housner on the same draws.
    let all: Vec<&Case> = blocks.iter().flat_map(|b| &b.cases).collect();
    let diffs: Vec<f64> = all.iter().filter_map(|c| c.ode_same_draws.map(|q| (c.p() - q).abs())).collect();
    let mean_diff = diffs.iter().sum::<f64>() / diffs.len().max(1) as f64;
    let agree = diffs.iter().filter(|&&d| d <= 1.0 / BLOCK_MEMBERS as f64 + 1e-12).count();
    writeln!(
        readme,
        "\nCase by case (block × record × scale, {} cases), the simulated ensemble's P against Housner's equation on \
         the same {BLOCK_MEMBERS} draws: mean |ΔP| = {mean_diff:.3}; {agree} cases ({:.0} %) within one member.",
        diffs.len(),
        100.0 * agree as f64 / diffs.len().max(1) as f64
    )?;
    plot_dimensionless(out, blocks)?;
    writeln!(readme, "\n![P = 0.5 contours, dimensionless](dimensionless.png)\n")?;
    reading_a(blocks, readme)
}

/// The numbers the reading of part A rests on, computed.
fn reading_a(blocks: &[BlockResult], readme: &mut String) -> anyhow::Result<()> {
    // Contour agreement inside each block's range of p·PGV/PGA, and the coefficients in
    // standard errors of the simulation's fit.
    let (mut worst, mut worst_beta) = (0.0f64, 0.0f64);
    let mut floor = Vec::new();
    for (b, r) in BLOCKS.iter().zip(blocks) {
        let (Some(s), Some(h)) = (&r.surface, &r.ode_surface) else { continue };
        let taus: Vec<f64> = r.cases.iter().map(|c| b.p() * c.pgv_over_pga_s).collect();
        let (lo, hi) = taus.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &t| (l.min(t), h.max(t)));
        for k in 0..=20 {
            let t = lo * (hi / lo).powf(k as f64 / 20.0);
            if let (Some(x), Some(y)) = (s.pga_at(0.5, t / b.p()), h.pga_at(0.5, t / b.p())) {
                worst = worst.max((x / y - 1.0).abs());
            }
        }
        for i in 1..3 {
            worst_beta = worst_beta.max((s.beta[i] - h.beta[i]).abs() / s.std_err[i]);
        }
        // Where the published form's contour crosses the quasi-static threshold g tan α:
        // ln(PGV/PGA) = (−β₀ − β₁ ln tan α) / β₂ (logit 0.5 = 0).
        let cross = b.p() * ((-s.beta[0] - s.beta[1] * b.tan_alpha.ln()) / s.beta[2]).exp();
        // The weakest shaking that overturned any member, in units of g tan α.
        let lowest =
            r.cases.iter().filter(|c| c.overturned > 0).map(|c| c.pga_g / b.tan_alpha).fold(f64::INFINITY, f64::min);
        floor.push(format!(
            "{}: data up to τ = {hi:.2}, crossing at τ = {cross:.1}, lowest overturning PGA {lowest:.2} g tan α",
            b.name()
        ));
    }
    // The dimensionless collapse: spread of PGA₅₀/(g tan α) over the five blocks at a few τ.
    let spread = |tau: f64, ode: bool| {
        let xs: Vec<f64> = BLOCKS
            .iter()
            .zip(blocks)
            .filter_map(|(b, r)| {
                let s = if ode { &r.ode_surface } else { &r.surface };
                s.as_ref()?.pga_at(0.5, tau / b.p()).map(|x| x / b.tan_alpha)
            })
            .collect();
        let (lo, hi) = xs.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
        format!("{lo:.2}–{hi:.2}")
    };
    let beta2: Vec<String> = BLOCKS
        .iter()
        .zip(blocks)
        .filter_map(|(b, r)| r.surface.as_ref().map(|s| format!("{:.2} ({})", s.beta[2], b.name())))
        .collect();
    writeln!(
        readme,
        "### Reading\n\n\
         * **The published form fits.** Purvance, Anooshehpoor & Brune (2008) report the overturning probability of \
         freestanding blocks as a function of α, p, PGA and PGV/PGA, and fit it per block in the logistic form used \
         here. The simulated ensembles follow that form as closely as Housner's equation does (numbers below), and \
         β₂ > 0 for every block — {} — : at a fixed PGA, motion of longer period overturns more, the dependence on \
         PGV/PGA they found.\n\
         * **Dimensionless, but not exactly.** Under a time-scaled record Housner's equation depends only on \
         PGA/(g tan α), p·PGV/PGA and α. Across the five blocks PGA₅₀/(g tan α) spans {} at τ = 0.3, {} at τ = 1 and \
         {} at τ = 3 (simulation; Housner: {}, {}, {}): close near τ = 1, apart by up to a fifth at the ends, and \
         β₂ grows with size. Housner's equation shows the same spread, so the simulator is not the cause: these \
         records are not time-scaled copies of each other, and PGA with PGV/PGA does not say everything about a \
         record.\n\
         * **Where the form and the physics differ: the floor.** The form's contour is a straight line in \
         (ln PGA, ln PGV/PGA) with no floor; extrapolated to longer periods it predicts P = 0.5 below g tan α, where \
         no rigid block even starts to rock (crossings below, each 2–4× beyond the p·PGV/PGA the records reach; no \
         member overturned below 1.25 g tan α on a grid 0.8, 1, 1.25, …). A fragility surface should not be read \
         beyond its records, or should be capped by the quasi-static threshold (the tipping polar's minimum).\n\
         * **What is not compared.** The coefficients of Purvance et al.'s published fits are not in this \
         repository and could not be consulted where this was written; the comparison is with their form and the \
         dependencies they report, and digit by digit with Housner's equation, which their 2-D simulations \
         integrate.\n",
        beta2.join(", "),
        spread(0.3, false),
        spread(1.0, false),
        spread(3.0, false),
        spread(0.3, true),
        spread(1.0, true),
        spread(3.0, true),
    )?;
    writeln!(
        readme,
        "Computed:\n\n\
         * Simulation and Housner's equation, fitted the same way: the P = 0.5 contours differ by at most \
         {:.1} % inside each block's range of p·PGV/PGA; β₁ and β₂ differ by at most {worst_beta:.1} standard errors \
         of the simulation's fit.\n\
         * Where the published form's P = 0.5 contour reaches PGA = g tan α, beyond which it predicts overturning \
         below the quasi-static threshold (no rigid block even starts to rock there):\n  - {}\n",
        100.0 * worst,
        floor.join("\n  - ")
    )?;
    Ok(())
}

/// The P = 0.5 contours of every block, simulation (solid, with its 95 % band shaded) and
/// Housner (dashed), as PGA₅₀/(g tan α) against p·PGV/PGA.
fn plot_dimensionless(out: &Path, blocks: &[BlockResult]) -> anyhow::Result<()> {
    let path = out.join("dimensionless.png");
    rocking_stones::plot::draw_png(&path, (1000, 700), |root| {
        root.fill(&WHITE)?;
        let root = root.titled(
            "Freestanding blocks: P = 0.5 contour in Housner's dimensionless variables",
            (FONT_FAMILY, style::TITLE),
        )?;
        let (legend, area) = root.split_vertically(legend_height(3));
        let mut entries: Vec<(Mark, String)> = BLOCKS
            .iter()
            .enumerate()
            .map(|(k, b)| (Mark::Line(series_color(k + 1)), format!("tan α = {}, R = {} m", b.tan_alpha, b.r_m)))
            .collect();
        entries.push((Mark::Line(BLACK), "solid: simulation (shaded: 95 % band)".into()));
        entries.push((Mark::Dashed(BLACK), "Housner's equation, same members".into()));
        entries.push((Mark::Line(GREY), "PGA = g tan α (quasi-static threshold)".into()));
        draw_legend(&legend, &entries).map_err(|e| anyhow::anyhow!(e))?;
        let mut chart = ChartBuilder::on(&area)
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d((TAU_AXIS[0]..TAU_AXIS[1]).log_scale(), (0.8f64..8.0).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("p · PGV/PGA")
            .y_desc("PGA₅₀ / (g tan α)")
            .x_label_formatter(&|x| log_tick(*x))
            .y_label_formatter(&|y| log_tick(*y))
            .axis_desc_style((FONT_FAMILY, style::AXIS))
            .label_style((FONT_FAMILY, style::TICK))
            .draw()?;
        chart.draw_series(LineSeries::new(
            vec![(TAU_AXIS[0], 1.0), (TAU_AXIS[1], 1.0)],
            GREY.stroke_width(style::LINE),
        ))?;
        for (k, (b, r)) in BLOCKS.iter().zip(blocks).enumerate() {
            let colour = series_color(k + 1);
            // The range of p·PGV/PGA the block's records cover.
            let taus: Vec<f64> = r.cases.iter().map(|c| b.p() * c.pgv_over_pga_s).collect();
            let (lo, hi) = taus.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &t| (l.min(t), h.max(t)));
            let (lo, hi) = (lo.max(TAU_AXIS[0]), hi.min(TAU_AXIS[1]));
            let grid: Vec<f64> = (0..=60).map(|k| lo * (hi / lo).powf(k as f64 / 60.0)).collect();
            let contour = |s: &FragilitySurface| -> Vec<(f64, f64)> {
                grid.iter().filter_map(|&t| s.pga_at(0.5, t / b.p()).map(|p| (t, p / b.tan_alpha))).collect()
            };
            if let Some(s) = &r.surface {
                let band: Vec<(f64, f64, f64)> = grid
                    .iter()
                    .filter_map(|&t| {
                        let [lo, _, hi] = s.pga_band_at(0.5, t / b.p(), 1.96)?;
                        Some((t, lo? / b.tan_alpha, hi? / b.tan_alpha))
                    })
                    .collect();
                let mut poly: Vec<(f64, f64)> = band.iter().map(|&(t, l, _)| (t, l)).collect();
                poly.extend(band.iter().rev().map(|&(t, _, h)| (t, h)));
                if poly.len() > 2 {
                    chart.draw_series(std::iter::once(Polygon::new(poly, colour.mix(0.12).filled())))?;
                }
                chart.draw_series(LineSeries::new(contour(s), colour.stroke_width(3)))?;
            }
            if let Some(s) = &r.ode_surface {
                chart.draw_series(DashedLineSeries::new(contour(s), 6, 4, colour.stroke_width(style::LINE)))?;
            }
        }
        Ok(())
    })?;
    Ok(())
}

/// What each rock's forecasts are scored against, for the tables.
fn truth_label(rocks: &str) -> &'static str {
    match rocks {
        "blocks" => "Housner's equation on independent draws",
        _ => "held-out members (perfect model)",
    }
}

fn part_b(
    out: &Path,
    blocks: &[BlockResult],
    stone: &[Case],
    stone_pose: &str,
    nominal_inputs: &str,
    readme: &mut String,
) -> anyhow::Result<()> {
    let block_cases: Vec<&Case> = blocks.iter().flat_map(|b| &b.cases).collect();
    let stone_cases: Vec<&Case> = stone.iter().collect();
    let truths = |cases: &[&Case]| cases.iter().map(|c| c.truths.len()).sum::<usize>();
    writeln!(
        readme,
        "## B. Scores: ensemble probability against yes/no runs, on simulated truths\n\n\
         No outcome scored here is observed: every truth is simulated, from the ensemble's own uncertainty drawn \
         exactly as its members are. The scores say what a probability gains over a yes/no when that uncertainty \
         is right; they do not say how well a real rock's uncertainty is known.\n\n\
         * **Blocks** ({} cases, {} truths): truth = Housner's rocking equation — a second model (2-D, rigid, \
         instantaneous impacts), not the simulator — for {BLOCK_TRUTHS} further rocks per case, drawn \
         independently of the {BLOCK_MEMBERS} forecast members from the same uncertainty (azimuth 0–360°, random \
         sign). Forecast and truth differ in their dynamics, not in their uncertainty.\n\
         * **Quarry stone**, pose {stone_pose} at scanned size, rock on concrete ({} cases, {} truths): base-contact \
         tolerance 0–2 mm, azimuth unknown, random sign, friction / restitution / rolling resistance over the \
         surface pair's ranges; two-component filtered noise (periods 0.2, 0.5, 1, 2 s) scaled to PGA 0.04–0.2 g; \
         truth = {STONE_TRUTHS} held-out members of the same simulation, forecast = {STONE_MEMBERS} other members: \
         a **perfect-model** test (model and uncertainty exactly the forecast's).\n\n\
         Forecasts: the ensemble's P; and three yes/no forecasts (0 or 1), so that the ensemble is not set beside an \
         extreme member only:\n\n\
         * **nominal member** (`Uncertainty::nominal`): every uncertain input at a central value — base contact \
         at the middle of its range, the surface pair's nominal friction, restitution and δ (inside their \
         ranges), and for the azimuth over the whole circle and the random sign, which have no centre, the record \
         as given (azimuth 0, sign +); for the quarry stone {nominal_inputs};\n\
         * **as-given run** (`rocking shake` without `--ensemble`): the nominal member but for the base contact, \
         tolerance 0 — the scanned hull as is, the end of the range with the smallest support polygon. For the \
         blocks, whose only uncertain inputs are azimuth and sign, it is the nominal member; azimuth 0 is along \
         their rocking plane, the direction that shakes them hardest;\n\
         * **best yes/no**: each case's majority truth outcome, the best any yes/no can score (a bound, not a \
         run).\n\n\
         Brier score: mean (P − y)² over every truth of every case; log loss: mean −[y ln P + (1 − y) ln(1 − P)], \
         P kept inside [1/(2n), 1 − 1/(2n)] for n forecast members, the same ε for the yes/no forecasts; accuracy: \
         P ≥ 0.5 taken as \"overturns\"; 'overturns in': the mean P, or the share of cases a yes/no forecast says \
         overturn, beside the truths' share overturned. The oracle forecasts each case by its own truth \
         frequency, the lowest Brier score possible.\n\n\
         | rocks | scored against | forecast | Brier | log loss | accuracy | overturns in |\n|---|---|---|---|---|---|---|",
        block_cases.len(),
        truths(&block_cases),
        stone_cases.len(),
        truths(&stone_cases),
    )?;
    let mut csv = String::from("rocks,forecast,brier,log_loss,accuracy,truths,scored_against,overturn_share\n");
    let mut reliability = Vec::new();
    let mut summary = Vec::new();
    for (name, cases, n) in [("blocks", &block_cases, BLOCK_MEMBERS), ("quarry stone", &stone_cases, STONE_MEMBERS)] {
        let truth = truth_label(name);
        let eps = 0.5 / n as f64;
        let yes = |f: fn(&Case) -> bool| cases.iter().filter(|c| f(c)).count() as f64 / cases.len() as f64;
        let (nominal_yes, given_yes, best_yes) = (yes(|c| c.nominal), yes(|c| c.as_given), yes(majority));
        let mean_p = cases.iter().map(|c| c.p()).sum::<f64>() / cases.len() as f64;
        let truth_share = cases.iter().flat_map(|c| &c.truths).filter(|&&y| y).count() as f64 / truths(cases) as f64;
        let ens = score(cases, &|c| c.p(), eps);
        let nominal = score(cases, &|c| c.nominal as u8 as f64, eps);
        let given = score(cases, &|c| c.as_given as u8 as f64, eps);
        let best = score(cases, &|c| majority(c) as u8 as f64, eps);
        let mut rows = vec![(format!("ensemble P ({n} members)"), ens, mean_p)];
        if name == "blocks" {
            let housner = score(cases, &|c| c.ode_same_draws.unwrap_or(0.5), eps);
            let share = cases.iter().map(|c| c.ode_same_draws.unwrap_or(0.5)).sum::<f64>() / cases.len() as f64;
            rows.push(("Housner on the forecast's draws".into(), housner, share));
        }
        rows.push(("nominal member (yes/no)".into(), nominal, nominal_yes));
        rows.push(("as-given run (yes/no)".into(), given, given_yes));
        rows.push(("best yes/no (majority truth; a bound)".into(), best, best_yes));
        for (label, s, share) in &rows {
            writeln!(
                readme,
                "| {name} | {truth} | {label} | {:.4} | {:.4} | {:.3} | {:.1} % |",
                s.brier,
                s.log_loss,
                s.accuracy,
                100.0 * share
            )?;
            writeln!(
                csv,
                "{name},{label},{:.5},{:.5},{:.4},{},{truth},{share:.4}",
                s.brier, s.log_loss, s.accuracy, s.n
            )?;
        }
        let oracle = oracle_brier(cases);
        let perfect = perfect_ensemble_brier(cases, n);
        writeln!(readme, "| {name} | {truth} | a perfect {n}-member ensemble (expected) | {perfect:.4} | – | – | – |")?;
        writeln!(
            readme,
            "| {name} | {truth} | oracle (truth frequency) | {oracle:.4} | – | – | {:.1} % |",
            100.0 * truth_share
        )?;
        writeln!(csv, "{name},perfect {n}-member ensemble (expected),{perfect:.5},,,,{truth},")?;
        writeln!(csv, "{name},oracle,{oracle:.5},,,,{truth},{truth_share:.4}")?;
        reliability.push((format!("{name}, truth: {truth}"), reliability_bins(cases)));
        summary.push(format!(
            "**{name}** (scored against {truth}): Brier {:.3} against {:.3} for the nominal member (skill \
             1 − B/B_nominal = {:.2}), {:.3} for the as-given run and {:.3} for the best possible yes/no; log loss \
             {:.2} against {:.2} (nominal) and {:.2} (as given). The nominal member says overturn in {:.0} % of the \
             cases, the as-given run in {:.0} %, the ensemble's mean P is {:.1} % and {:.1} % of the truths \
             overturned. A perfect {n}-member ensemble would be expected to score {perfect:.3} (the ensemble: {:+.4} from \
             it; its {n} members are common to every case, so that difference is one draw of its sampling noise, not \
             an average over independent ones), the oracle {oracle:.3}",
            ens.brier,
            nominal.brier,
            1.0 - ens.brier / nominal.brier,
            given.brier,
            best.brier,
            ens.log_loss,
            nominal.log_loss,
            given.log_loss,
            100.0 * nominal_yes,
            100.0 * given_yes,
            100.0 * mean_p,
            100.0 * truth_share,
            ens.brier - perfect,
        ));
    }
    std::fs::write(out.join("scores.csv"), csv)?;
    let sets: Vec<(&str, Vec<Bin>)> = reliability.iter().map(|(n, b)| (n.as_str(), b.clone())).collect();
    plot_reliability(out, &sets)?;
    writeln!(readme, "\n![Reliability of the ensemble probabilities](reliability.png)\n")?;
    writeln!(
        readme,
        "### Reading\n\n\
         * {}.\n* {}.\n\
         * The as-given quarry stone stands on the scanned hull as is, the least supported rock the contact range \
         allows, and overturns far more often than the truths do; the nominal member stands at the middle of the \
         range. For the blocks the two are the same rock, shaken along its rocking plane at full amplitude: it \
         overturns wherever some azimuths would not. Any yes/no is wrong wherever the truth is uncertain, and \
         confidently so (its log loss is that of a forecast of 1/(2n) or 1 − 1/(2n)); the best-yes/no row is what \
         the luckiest single run could score.\n\
         * What a finite ensemble must lose to the oracle: with n members drawn from the truth's own distribution \
         the expected Brier score is q(1 − q)(1 + 1/n) per case (q the case's overturning probability; the \
         oracle's q̂(1 − q̂) from K truths is q(1 − q)(1 − 1/K) on average), which the 'perfect ensemble' row \
         evaluates on these cases.\n\
         * The reliability curves lie below the diagonal at high P: binning cases by a P that carries sampling \
         noise (standard error up to 1/(2√n): 0.125 at n = 16) selects the cases whose P came out high by chance. \
         The Brier scores, which need no binning, are set beside a perfect ensemble's above.\n",
        summary[0], summary[1]
    )?;
    Ok(())
}

/// The expected Brier score of an ensemble of `n` members drawn from each case's truth
/// distribution: q(1 − q)(1 + 1/n) per truth, q estimated without bias from the case's K truths
/// as q̂(1 − q̂)·K/(K − 1).
fn perfect_ensemble_brier(cases: &[&Case], n: u64) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for c in cases {
        let k = c.truths.len();
        if k < 2 {
            continue;
        }
        let q = c.truths.iter().filter(|&&y| y).count() as f64 / k as f64;
        sum += q * (1.0 - q) * k as f64 / (k as f64 - 1.0) * (1.0 + 1.0 / n as f64) * k as f64;
        count += k;
    }
    sum / count.max(1) as f64
}

/// One bin of a reliability diagram: mean forecast, observed truth frequency, truths in it.
type Bin = (f64, f64, usize);

/// Forecast P in ten bins, the non-empty ones.
fn reliability_bins(cases: &[&Case]) -> Vec<Bin> {
    let mut bins = vec![(0.0, 0usize, 0usize); 10];
    for c in cases {
        let p = c.p();
        let k = ((p * 10.0) as usize).min(9);
        for &y in &c.truths {
            bins[k].0 += p;
            bins[k].1 += y as usize;
            bins[k].2 += 1;
        }
    }
    bins.into_iter().filter(|b| b.2 > 0).map(|(s, y, n)| (s / n as f64, y as f64 / n as f64, n)).collect()
}

fn plot_reliability(out: &Path, sets: &[(&str, Vec<Bin>)]) -> anyhow::Result<()> {
    let path = out.join("reliability.png");
    rocking_stones::plot::draw_png(&path, (760, 700), |root| {
        root.fill(&WHITE)?;
        let root = root
            .titled("Reliability: forecast P(overturn) against the truth's frequency", (FONT_FAMILY, style::TITLE))?;
        let (legend, area) = root.split_vertically(legend_height(2));
        let mut entries: Vec<(Mark, String)> = sets
            .iter()
            .enumerate()
            .map(|(k, (name, bins))| {
                let total: usize = bins.iter().map(|b| b.2).sum();
                (Mark::LineDot(series_color(k + 1)), format!("{name} ({total} truths; dot area ∝ truths in the bin)"))
            })
            .collect();
        entries.push((Mark::Line(GREY), "perfectly reliable".into()));
        draw_legend(&legend, &entries).map_err(|e| anyhow::anyhow!(e))?;
        let mut chart = ChartBuilder::on(&area)
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(60)
            .build_cartesian_2d(-0.02f64..1.02, -0.02f64..1.02)?;
        chart
            .configure_mesh()
            .x_desc("ensemble P (bin mean)")
            .y_desc("observed frequency in the truths")
            .x_label_formatter(&|x| plain(*x))
            .y_label_formatter(&|y| plain(*y))
            .axis_desc_style((FONT_FAMILY, style::AXIS))
            .label_style((FONT_FAMILY, style::TICK))
            .draw()?;
        chart.draw_series(LineSeries::new(vec![(0.0, 0.0), (1.0, 1.0)], GREY.stroke_width(1)))?;
        for (k, (_, bins)) in sets.iter().enumerate() {
            let colour = series_color(k + 1);
            let total: usize = bins.iter().map(|b| b.2).sum();
            chart.draw_series(LineSeries::new(bins.iter().map(|b| (b.0, b.1)), colour.stroke_width(style::LINE)))?;
            chart.draw_series(bins.iter().map(|b| {
                let r = (4.0 + 30.0 * (b.2 as f64 / total as f64).sqrt()) as i32;
                Circle::new((b.0, b.1), r, colour.mix(0.6).filled())
            }))?;
        }
        Ok(())
    })?;
    Ok(())
}
