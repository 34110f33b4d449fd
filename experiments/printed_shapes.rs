//! Validation on three 3D-printed dice thrown by hand (binom3, binom4, dragon_d3):
//! `data/printed_shapes/` (Baktash et al., "Putting Rigid Bodies to Rest", ACM TOG
//! 2025, and its data repository `hbaktash/resting-rigid-bodies`).
//!
//! For each die: its hull (OBJ, a normalised frame) is analysed with the printed solid's centre of
//! mass (`center_of_mass.txt`, the same path as `rocking analyze --center-of-mass`:
//! `Options::center_of_mass`); every stable facet is mapped to the measured outcome whose listed
//! normal (any of them) is nearest to the facet's outward normal (both in the mesh frame: the
//! dynamics translate and scale the hull, never rotate it, and normals do not change under
//! either); and the outcome frequencies are predicted by
//!
//! * the quasi-static basins (exact basin areas on the sphere of down directions, no dynamics);
//! * the `throw` preset calibrated on the steel cuboid dice (`results/cuboid_dice/`), on
//!   `Surface::SteelOnWood` at the die's assumed size, with the default numerics it was
//!   calibrated with (exact landings and sub-stepped impacts, the preset's default step 1/120 s);
//! * the same throw with rapier's own flight (`Flight::Rapier`, impacts found at the step
//!   boundaries: the former numerics), to show what the numerics change;
//! * the `drop` preset as the library gives it (released at rest, 1 R_max above the table).
//!
//! Per shape and predictor: the total variation distance TV = ½ Σ |p_pred − p_meas|, Pearson's
//! χ² of the measured counts against the predicted frequencies (`stats::chi_square`), for the
//! simulated predictors the two-sample χ² of homogeneity (which also counts the Monte Carlo
//! noise of the prediction), and the TV that sampling noise alone gives when the predictor is
//! exactly right (parametric bootstrap: the measured N drawn from the predicted frequencies, and,
//! for a simulated predictor, its own N drawn likewise).
//!
//! **Validation only: nothing is fitted to these data.** The throw's parameters are those of
//! the preset; the only choice made here is the dice's real size (see `METRES_PER_UNIT`), which
//! sets the rolling-resistance length δ / R_max, and its effect is shown by re-running the throw
//! at half and twice that size.
//!
//! Run: `cargo run --release --example printed_shapes [-- N [DATA_DIR]]` (N = 2000 throws per
//! shape and predictor, seed 1; DATA_DIR = `data/printed_shapes`) →
//! `results/printed_shapes/`.

use anyhow::{bail, ensure, Context, Result};
use rand_distr::{Binomial, Distribution};
use rocking_stones::analysis::{Analysis, Options};
use rocking_stones::dynamics::certificate::CertificateMode;
use rocking_stones::dynamics::drops::montecarlo::{run_and_summarize, DropReport, RunHeader};
use rocking_stones::dynamics::drops::params::{DropParams, Preset};
use rocking_stones::dynamics::engine::params::Flight;
use rocking_stones::dynamics::stone::Stone;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::plot::colors::GREY;
use rocking_stones::plot::{draw_legend, legend_height, plain, series_color, style, Mark, FONT_FAMILY};
use rocking_stones::rng::item_rng;
use rocking_stones::stats::{chi_square, chi_square_homogeneity, wilson};
use rocking_stones::{Point3, Vec3};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The shapes, in the order of the data's README.
const SHAPES: [&str; 3] = ["binom3", "binom4", "dragon_d3"];

/// Metres per OBJ unit assumed for the printed dice. The OBJs are in a normalised frame
/// (coordinates within ±1, longest extent 1.7–1.9 units), so they are neither in millimetres
/// (a 2 mm die) nor in metres; the source does not give the printed size. A die thrown by hand is
/// a few centimetres long: 1 unit = 2 cm makes the dice 3.3–3.9 cm long with R_max 1.4–2.0 cm,
/// the range of the steel dice the throw was calibrated on (R_max 1.1–1.9 cm).
const METRES_PER_UNIT: f64 = 0.02;

/// Seed of every simulated run (stream i of throw i, the same launches for every predictor).
const SEED: u64 = 1;

/// Bootstrap replicates of the noise-level TV.
const BOOTSTRAP: u64 = 4000;

/// A normal further than this (degrees) from every listed normal is reported as a poor match.
const POOR_MATCH_DEG: f64 = 5.0;

/// One measured outcome of `outcomes.csv`.
struct Outcome {
    id: String,
    /// Outward normals of the hull facets of the outcome (mesh frame), main first.
    normals: Vec<Vec3>,
    count: u64,
}

/// One printed die: its files and measured outcomes.
struct Shape {
    name: &'static str,
    obj: PathBuf,
    com: Point3,
    outcomes: Vec<Outcome>,
    /// Throws of the measurement.
    n: u64,
}

/// The predictors, in the order of every table and picture.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Predictor {
    QuasiStatic,
    Throw,
    ThrowRapier,
    Drop,
}

impl Predictor {
    const ALL: [Predictor; 4] = [Predictor::QuasiStatic, Predictor::Throw, Predictor::ThrowRapier, Predictor::Drop];

    fn key(self) -> &'static str {
        match self {
            Predictor::QuasiStatic => "quasi_static",
            Predictor::Throw => "throw",
            Predictor::ThrowRapier => "throw_rapier_flight",
            Predictor::Drop => "drop",
        }
    }

    fn label(self) -> &'static str {
        match self {
            Predictor::QuasiStatic => "quasi-static basins",
            Predictor::Throw => "throw (calibrated)",
            Predictor::ThrowRapier => "throw, rapier's flight",
            Predictor::Drop => "drop preset",
        }
    }

    /// The parameters of a simulated predictor for a die of R_max = `r_max_m` metres.
    fn params(self, r_max_m: f64) -> Result<Option<(DropParams, Preset)>> {
        let surface = Surface::SteelOnWood;
        Ok(match self {
            Predictor::QuasiStatic => None,
            Predictor::Throw => {
                // Pinned: the numerics the calibration (`results/cuboid_dice/`) was fitted with.
                let mut p = Preset::Throw.params_at_size(surface, r_max_m)?;
                p.sim.flight.mode = Flight::Free;
                Some((p, Preset::Throw))
            }
            Predictor::ThrowRapier => {
                let mut p = Preset::Throw.params_at_size(surface, r_max_m)?;
                p.sim.flight.mode = Flight::Rapier;
                Some((p, Preset::Throw))
            }
            Predictor::Drop => Some((Preset::Drop.params_at_size(surface, r_max_m)?, Preset::Drop)),
        })
    }
}

/// A predicted distribution over the outcomes.
struct Prediction {
    predictor: Predictor,
    p: Vec<f64>,
    /// Simulated counts per outcome and their total (None: exact, the quasi-static basins).
    counts: Option<(Vec<u64>, u64)>,
    /// Run diagnostics (simulated predictors only).
    run: Option<RunInfo>,
    /// The share of the prediction on stable facets that match no listed normal (within
    /// `POOR_MATCH_DEG`), counted for their nearest outcome by the rule.
    unlisted: f64,
    /// The prediction with those facets left out (renormalised); None if there are none.
    p_listed_only: Option<Vec<f64>>,
}

struct RunInfo {
    params: DropParams,
    drops: u64,
    unsettled: u64,
    off_equilibrium: u64,
    certified: u64,
    seconds: f64,
}

/// How one predictor fares against one shape's measurement.
struct Score {
    tv: f64,
    chi2: f64,
    dof: usize,
    p_value: f64,
    /// Two-sample χ² of homogeneity (simulated predictors).
    p_homogeneity: Option<f64>,
    /// Mean and 95th percentile of the TV that sampling noise gives when the predictor is exact.
    noise_mean: f64,
    noise_q95: f64,
    /// An outcome was measured that the predictor never gives (χ² cannot be computed).
    impossible: bool,
}

/// A stable facet and the outcome it counts for.
struct Mapped {
    facet: u32,
    normal: Vec3,
    basin: f64,
    outcome: usize,
    angle_deg: f64,
    /// Distance from G to the facet's plane (OBJ units).
    r: f64,
    /// The tilt (degrees) that brings G's vertical over the nearest edge of the facet: how far
    /// the stone can be rocked on it before it topples off.
    tilt_deg: f64,
}

impl Mapped {
    fn poor(&self) -> bool {
        self.angle_deg > POOR_MATCH_DEG
    }
}

/// Everything computed for one shape.
struct ShapeResult {
    shape: Shape,
    r_max_units: f64,
    extent: Vec3,
    r_max_m: f64,
    hull_facets: usize,
    stable: usize,
    /// Equilibrium predicates decided by the symbolic perturbation (degenerate, e.g. G's
    /// vertical through a facet's edge).
    degenerate: usize,
    mapped: Vec<Mapped>,
    predictions: Vec<Prediction>,
    scores: Vec<Score>,
    /// The throw (rapier flight) at ½ and 2 × the assumed size: (factor, frequencies, TV).
    size_check: Vec<(f64, Vec<f64>, f64)>,
    /// Reference against free-flight throws (same launches): TV between them, χ² of homogeneity
    /// and its p-value.
    numerics: (f64, f64, f64),
}

fn parse_vec3(text: &str, what: &str) -> Result<Vec3> {
    let v: Vec<f64> = text
        .split_whitespace()
        .map(|x| x.parse::<f64>().with_context(|| format!("{what}: {x:?} is not a number")))
        .collect::<Result<_>>()?;
    ensure!(v.len() == 3, "{what}: expected three numbers x y z, found {} in {text:?}", v.len());
    ensure!(v.iter().all(|x| x.is_finite()), "{what}: {text:?} is not three finite numbers");
    Ok(Vec3::new(v[0], v[1], v[2]))
}

fn read_text(path: &Path) -> Result<String> {
    std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))
}

/// `outcomes.csv`: `outcome,resting_facet_normals,measured_count,n_throws,measured_freq`.
fn read_outcomes(path: &Path) -> Result<(Vec<Outcome>, u64)> {
    let text = read_text(path)?;
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty());
    let expected = "outcome,resting_facet_normals,measured_count,n_throws,measured_freq";
    match lines.next() {
        Some((_, h)) if h.trim() == expected => {}
        Some((_, h)) => bail!("{}: header {h:?}, expected {expected:?}", path.display()),
        None => bail!("{}: empty file", path.display()),
    }
    let mut outcomes = Vec::new();
    let mut n_all = None;
    for (i, line) in lines {
        let at = || format!("{} line {}", path.display(), i + 1);
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        ensure!(f.len() == 5, "{}: expected 5 comma-separated fields, found {}: {line:?}", at(), f.len());
        let normals = f[1]
            .split(';')
            .map(|s| {
                let v = parse_vec3(s, &at())?;
                ensure!(
                    (v.norm() - 1.0).abs() < 1e-3,
                    "{}: normal {s:?} is not a unit vector (|n| = {})",
                    at(),
                    v.norm()
                );
                Ok(v.normalize())
            })
            .collect::<Result<Vec<_>>>()?;
        let count: u64 = f[2].parse().with_context(|| format!("{}: measured_count {:?}", at(), f[2]))?;
        let n: u64 = f[3].parse().with_context(|| format!("{}: n_throws {:?}", at(), f[3]))?;
        let freq: f64 = f[4].parse().with_context(|| format!("{}: measured_freq {:?}", at(), f[4]))?;
        ensure!(n > 0 && count <= n, "{}: measured_count {count} out of n_throws {n}", at());
        ensure!(
            (freq - count as f64 / n as f64).abs() < 5e-4,
            "{}: measured_freq {freq} is not measured_count / n_throws = {}",
            at(),
            count as f64 / n as f64
        );
        ensure!(*n_all.get_or_insert(n) == n, "{}: n_throws {n} differs from the earlier lines' {n_all:?}", at());
        ensure!(!outcomes.iter().any(|o: &Outcome| o.id == f[0]), "{}: outcome {} listed twice", at(), f[0]);
        outcomes.push(Outcome { id: f[0].to_string(), normals, count });
    }
    let n = n_all.with_context(|| format!("{}: no outcomes", path.display()))?;
    let total: u64 = outcomes.iter().map(|o| o.count).sum();
    ensure!(total == n, "{}: the counts add up to {total}, not to n_throws = {n}", path.display());
    Ok((outcomes, n))
}

fn read_shape(data: &Path, name: &'static str) -> Result<Shape> {
    let dir = data.join(name);
    let objs: Vec<PathBuf> = std::fs::read_dir(&dir)
        .with_context(|| format!("cannot list {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("obj")))
        .collect();
    let obj = match objs.as_slice() {
        [one] => one.clone(),
        [] => bail!("{}: no .obj hull in the folder", dir.display()),
        _ => bail!("{}: several .obj files, expected one hull: {objs:?}", dir.display()),
    };
    let com_path = dir.join("center_of_mass.txt");
    let c = parse_vec3(read_text(&com_path)?.trim(), &com_path.display().to_string())?;
    let (outcomes, n) = read_outcomes(&dir.join("outcomes.csv"))?;
    Ok(Shape { name, obj, com: Point3::from(c), outcomes, n })
}

/// The outcome nearest to `normal` (largest dot product with any listed normal) and the angle.
fn nearest_outcome(outcomes: &[Outcome], normal: &Vec3) -> (usize, f64) {
    let (k, dot) = outcomes
        .iter()
        .enumerate()
        .flat_map(|(k, o)| o.normals.iter().map(move |m| (k, m.dot(normal))))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .expect("an outcome");
    (k, dot.clamp(-1.0, 1.0).acos().to_degrees())
}

fn tv(p: &[f64], q: &[f64]) -> f64 {
    0.5 * p.iter().zip(q).map(|(a, b)| (a - b).abs()).sum::<f64>()
}

/// A multinomial draw of `n` over `p` (conditional binomials).
fn multinomial(rng: &mut rocking_stones::rng::Stream, n: u64, p: &[f64]) -> Vec<u64> {
    let (mut left, mut mass) = (n, 1.0);
    let mut out = Vec::with_capacity(p.len());
    for (i, &q) in p.iter().enumerate() {
        let k = if i + 1 == p.len() || left == 0 {
            left
        } else {
            let r = (q / mass).clamp(0.0, 1.0);
            Binomial::new(left, r).expect("a probability").sample(rng)
        };
        out.push(k);
        left -= k;
        mass -= q;
    }
    out
}

/// Mean and 95th percentile of the TV between a measurement of `n_meas` throws and the
/// prediction when the prediction's frequencies `p` are the truth (a simulated prediction of
/// `n_sim` drops is redrawn too).
fn noise_tv(p: &[f64], n_meas: u64, n_sim: Option<u64>, stream: u64) -> (f64, f64) {
    let freq = |c: &[u64], n: u64| c.iter().map(|&k| k as f64 / n as f64).collect::<Vec<_>>();
    let mut tvs: Vec<f64> = (0..BOOTSTRAP)
        .map(|b| {
            let mut rng = item_rng(SEED ^ (stream << 32), b);
            let meas = freq(&multinomial(&mut rng, n_meas, p), n_meas);
            match n_sim {
                Some(m) => tv(&meas, &freq(&multinomial(&mut rng, m, p), m)),
                None => tv(&meas, p),
            }
        })
        .collect();
    tvs.sort_by(f64::total_cmp);
    let mean = tvs.iter().sum::<f64>() / tvs.len() as f64;
    (mean, tvs[((0.95 * tvs.len() as f64) as usize).min(tvs.len() - 1)])
}

fn score(shape: &Shape, pred: &Prediction, stream: u64) -> Score {
    let measured: Vec<u64> = shape.outcomes.iter().map(|o| o.count).collect();
    let p_meas: Vec<f64> = measured.iter().map(|&k| k as f64 / shape.n as f64).collect();
    let impossible = pred.p.iter().zip(&measured).any(|(&p, &k)| p == 0.0 && k > 0);
    let (chi2, dof, p_value) = chi_square(&measured, &pred.p);
    let p_homogeneity = pred.counts.as_ref().map(|(c, _)| chi_square_homogeneity(&measured, c).2);
    let (noise_mean, noise_q95) = noise_tv(&pred.p, shape.n, pred.counts.as_ref().map(|c| c.1), stream);
    Score {
        tv: tv(&pred.p, &p_meas),
        chi2,
        dof,
        p_value: if impossible { 0.0 } else { p_value },
        p_homogeneity,
        noise_mean,
        noise_q95,
        impossible,
    }
}

/// Run `params` on the stone and gather the counts by outcome.
fn simulate(
    stone: &Stone,
    analysis: &Analysis,
    shape: &Shape,
    (params, preset): (DropParams, Preset),
    n: u64,
    facet_outcome: &BTreeMap<u32, usize>,
) -> Result<(BTreeMap<u32, u64>, RunInfo)> {
    let c = shape.com;
    let header = RunHeader {
        center_of_mass: Some([c.x, c.y, c.z]),
        ..RunHeader::new(
            shape.obj.display().to_string(),
            &analysis.mesh,
            SEED,
            n,
            params,
            CertificateMode::Facet,
            (preset, Surface::SteelOnWood),
        )
    };
    let t = Instant::now();
    let (report, _): (DropReport, _) = run_and_summarize(stone, &header);
    let seconds = t.elapsed().as_secs_f64();
    let mut counts = BTreeMap::new();
    for row in report.facets.iter().filter(|r| r.count > 0) {
        let hull_normal = analysis.hull.facets[row.facet as usize].normal;
        ensure!(
            row.normal.dot(&hull_normal) > 1.0 - 1e-9,
            "{}: the drop report's normal of facet {} is not the hull's (frames differ)",
            shape.name,
            row.facet
        );
        ensure!(
            facet_outcome.contains_key(&row.facet),
            "{}: {} drops rest on facet {}, which is not a stable facet",
            shape.name,
            row.count,
            row.facet
        );
        counts.insert(row.facet, row.count);
    }
    let total: u64 = counts.values().sum();
    ensure!(
        total == report.facet_drops && total > 0,
        "{}: {total} counted drops of {}",
        shape.name,
        report.facet_drops
    );
    let info = RunInfo {
        params: report.params.clone(),
        drops: report.drops,
        unsettled: report.unsettled,
        off_equilibrium: report.off_equilibrium,
        certified: report.certified,
        seconds,
    };
    Ok((counts, info))
}

/// A distribution over the stable facets (weights adding up to 1, or counts) gathered by
/// outcome: the frequencies, the share on facets that match no listed normal, and the
/// frequencies without those facets (renormalised) when there are any.
fn by_outcome(mapped: &[Mapped], k: usize, weight: impl Fn(u32) -> f64) -> (Vec<f64>, f64, Option<Vec<f64>>) {
    let total: f64 = mapped.iter().map(|m| weight(m.facet)).sum();
    let mut p = vec![0.0; k];
    let mut listed = vec![0.0; k];
    for m in mapped {
        p[m.outcome] += weight(m.facet) / total;
        if !m.poor() {
            listed[m.outcome] += weight(m.facet);
        }
    }
    let unlisted: f64 = mapped.iter().filter(|m| m.poor()).map(|m| weight(m.facet)).sum::<f64>() / total;
    let listed_total: f64 = listed.iter().sum();
    let listed_only = (mapped.iter().any(Mapped::poor) && listed_total > 0.0)
        .then(|| listed.iter().map(|x| x / listed_total).collect());
    (p, unlisted, listed_only)
}

/// The tilt (degrees) from resting on facet `f` to G's vertical over the facet's nearest edge.
fn topple_tilt(analysis: &Analysis, f: u32) -> f64 {
    let facet = &analysis.hull.facets[f as usize];
    let g = analysis.mass.center_of_mass.coords;
    let n = facet.normal;
    let height = facet.offset - n.dot(&g);
    let foot = g + height * n;
    let corner = |i: usize| analysis.hull.vertices[facet.vertices[i % facet.vertices.len()] as usize].coords;
    let margin = (0..facet.vertices.len())
        .map(|i| {
            let (a, b) = (corner(i), corner(i + 1));
            let inward = n.cross(&(b - a)).normalize();
            (foot - a).dot(&inward)
        })
        .fold(f64::INFINITY, f64::min);
    margin.atan2(height).to_degrees()
}

fn run_shape(shape: Shape, n: u64, index: usize) -> Result<ShapeResult> {
    let opts = Options { center_of_mass: Some(shape.com), ..Options::default() };
    let analysis = Analysis::of_file(&shape.obj, &opts)?;
    let (nu, _) = analysis.macro_nu(&opts);
    let stone = Stone::new(&analysis, nu).with_context(|| format!("{}", shape.obj.display()))?;
    let report = analysis.report(&shape.obj.display().to_string(), &opts);
    let r_max_units = analysis.equilibria.r_max;
    let r_max_m = r_max_units * METRES_PER_UNIT;
    let (lo, hi) = analysis
        .mesh
        .vertices
        .iter()
        .fold((Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)), |(lo, hi), v| {
            (lo.inf(&v.coords), hi.sup(&v.coords))
        });

    // Stable facets → outcomes, by the nearest listed normal (mesh frame).
    let mapped: Vec<Mapped> = report
        .stable_facets
        .iter()
        .map(|s| {
            let (outcome, angle_deg) = nearest_outcome(&shape.outcomes, &s.normal);
            let tilt_deg = topple_tilt(&analysis, s.facet);
            Mapped {
                facet: s.facet,
                normal: s.normal,
                r: s.r,
                basin: s.basin_probability,
                outcome,
                angle_deg,
                tilt_deg,
            }
        })
        .collect();
    let k = shape.outcomes.len();
    let facet_outcome: BTreeMap<u32, usize> = mapped.iter().map(|m| (m.facet, m.outcome)).collect();
    let basin_total: f64 = mapped.iter().map(|m| m.basin).sum();
    ensure!((basin_total - 1.0).abs() < 1e-6, "{}: the basins add up to {basin_total}", shape.name);

    let mut predictions = Vec::new();
    for predictor in Predictor::ALL {
        let prediction = match predictor.params(r_max_m)? {
            None => {
                let basin: BTreeMap<u32, f64> = mapped.iter().map(|m| (m.facet, m.basin)).collect();
                let (p, unlisted, p_listed_only) = by_outcome(&mapped, k, |f| basin[&f]);
                Prediction { predictor, p, counts: None, run: None, unlisted, p_listed_only }
            }
            Some(params) => {
                let (by_facet, info) = simulate(&stone, &analysis, &shape, params, n, &facet_outcome)?;
                eprintln!(
                    "  {} {}: {} drops in {:.0} s ({} unsettled)",
                    shape.name,
                    predictor.label(),
                    info.drops,
                    info.seconds,
                    info.unsettled
                );
                let weight = |f: u32| by_facet.get(&f).copied().unwrap_or(0) as f64;
                let (p, unlisted, p_listed_only) = by_outcome(&mapped, k, weight);
                let mut counts = vec![0u64; k];
                for (f, c) in &by_facet {
                    counts[facet_outcome[f]] += c;
                }
                let total = counts.iter().sum();
                Prediction { predictor, p, counts: Some((counts, total)), run: Some(info), unlisted, p_listed_only }
            }
        };
        predictions.push(prediction);
    }
    let scores: Vec<Score> =
        predictions.iter().enumerate().map(|(k, p)| score(&shape, p, (index * 8 + k) as u64)).collect();

    let counts_of = |p: Predictor| {
        predictions.iter().find(|x| x.predictor == p).and_then(|x| x.counts.as_ref()).map(|c| c.0.clone())
    };
    let numerics = match (counts_of(Predictor::Throw), counts_of(Predictor::ThrowRapier)) {
        (Some(a), Some(b)) => {
            let (chi2, _, p) = chi_square_homogeneity(&a, &b);
            let freq = |c: &[u64]| {
                let t: u64 = c.iter().sum();
                c.iter().map(|&k| k as f64 / t as f64).collect::<Vec<_>>()
            };
            (tv(&freq(&a), &freq(&b)), chi2, p)
        }
        _ => bail!("{}: the throws did not run", shape.name),
    };

    // Size: the throw (rapier flight) at ½ and 2 × the assumed R_max (only δ / R_max changes).
    let mut size_check = Vec::new();
    for factor in [0.5, 2.0] {
        let params = Predictor::Throw.params(r_max_m * factor)?.expect("a simulated predictor");
        let (by_facet, info) = simulate(&stone, &analysis, &shape, params, n, &facet_outcome)?;
        eprintln!("  {} throw at {factor} × size: {:.0} s", shape.name, info.seconds);
        let (p, _, _) = by_outcome(&mapped, k, |f| by_facet.get(&f).copied().unwrap_or(0) as f64);
        let measured: Vec<u64> = shape.outcomes.iter().map(|o| o.count).collect();
        let p_meas: Vec<f64> = measured.iter().map(|&k| k as f64 / shape.n as f64).collect();
        size_check.push((factor, p.clone(), tv(&p, &p_meas)));
    }
    Ok(ShapeResult {
        r_max_units,
        extent: hi - lo,
        r_max_m,
        hull_facets: analysis.hull.facets.len(),
        stable: report.stable_facets.len(),
        degenerate: analysis.equilibria.degenerate_decisions,
        mapped,
        predictions,
        scores,
        size_check,
        numerics,
        shape,
    })
}

fn main() -> Result<()> {
    let n: u64 = match std::env::args().nth(1) {
        Some(s) => s.parse().with_context(|| format!("N (throws per shape and predictor): {s:?} is not a count"))?,
        None => 2000,
    };
    ensure!(n > 0, "N must be at least 1");
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let data = std::env::args().nth(2).map_or_else(|| root.join("data/printed_shapes"), PathBuf::from);
    let out = root.join("results/printed_shapes");
    std::fs::create_dir_all(&out).with_context(|| format!("cannot create {}", out.display()))?;
    let t0 = Instant::now();
    // Every input is read and checked before the first throw.
    let shapes: Vec<Shape> = SHAPES.into_iter().map(|name| read_shape(&data, name)).collect::<Result<_>>()?;
    let mut results = Vec::new();
    for (index, shape) in shapes.into_iter().enumerate() {
        eprintln!("{}", shape.name);
        results.push(run_shape(shape, n, index)?);
    }
    let elapsed = t0.elapsed().as_secs_f64();
    std::fs::write(out.join("outcomes.csv"), outcomes_csv(&results)).context("writing outcomes.csv")?;
    std::fs::write(out.join("tv.csv"), tv_csv(&results)).context("writing tv.csv")?;
    plot(&out.join("tv.png"), &results).map_err(|e| anyhow::anyhow!("tv.png: {e}"))?;
    let command = if n == 2000 {
        "cargo run --release --example printed_shapes".to_string()
    } else {
        format!("cargo run --release --example printed_shapes -- {n}")
    };
    std::fs::write(out.join("README.md"), readme(&results, n, &command, elapsed)).context("writing README.md")?;
    for r in &results {
        let tvs: Vec<String> =
            Predictor::ALL.iter().zip(&r.scores).map(|(p, s)| format!("{} {:.3}", p.key(), s.tv)).collect();
        println!("{}: TV {}", r.shape.name, tvs.join(", "));
    }
    Ok(())
}

/// Long format: one row per shape, outcome and source (the measurement or a predictor).
fn outcomes_csv(results: &[ShapeResult]) -> String {
    let mut csv = String::from("shape,outcome,source,count,n,frequency,ci95_lo,ci95_hi\n");
    for r in results {
        for (k, o) in r.shape.outcomes.iter().enumerate() {
            let (lo, hi) = wilson(o.count, r.shape.n, 1.96);
            let _ = writeln!(
                csv,
                "{},{},measured,{},{},{:.5},{lo:.5},{hi:.5}",
                r.shape.name,
                o.id,
                o.count,
                r.shape.n,
                o.count as f64 / r.shape.n as f64
            );
            for pred in &r.predictions {
                match &pred.counts {
                    Some((c, total)) => {
                        let (lo, hi) = wilson(c[k], *total, 1.96);
                        let _ = writeln!(
                            csv,
                            "{},{},{},{},{total},{:.5},{lo:.5},{hi:.5}",
                            r.shape.name,
                            o.id,
                            pred.predictor.key(),
                            c[k],
                            pred.p[k]
                        );
                    }
                    None => {
                        let _ =
                            writeln!(csv, "{},{},{},,,{:.5},,", r.shape.name, o.id, pred.predictor.key(), pred.p[k]);
                    }
                }
            }
        }
    }
    csv
}

fn tv_csv(results: &[ShapeResult]) -> String {
    let mut csv = String::from(
        "shape,predictor,tv,noise_tv_mean,noise_tv_95,chi_square,dof,p_value,p_homogeneity,unsettled,seconds\n",
    );
    for r in results {
        for (pred, s) in r.predictions.iter().zip(&r.scores) {
            let _ = writeln!(
                csv,
                "{},{},{:.4},{:.4},{:.4},{:.2},{},{:.3e},{},{},{}",
                r.shape.name,
                pred.predictor.key(),
                s.tv,
                s.noise_mean,
                s.noise_q95,
                s.chi2,
                s.dof,
                s.p_value,
                s.p_homogeneity.map_or(String::new(), |p| format!("{p:.3e}")),
                pred.run.as_ref().map_or(String::new(), |i| i.unsettled.to_string()),
                pred.run.as_ref().map_or(String::new(), |i| format!("{:.1}", i.seconds)),
            );
        }
    }
    csv
}

/// A p-value as a person reads it.
fn p_text(p: f64) -> String {
    if p >= 0.01 {
        format!("{p:.2}")
    } else if p >= 1e-4 {
        format!("{p:.4}")
    } else if p > 0.0 {
        format!("{p:.0e}")
    } else {
        "0".into()
    }
}

fn score_of(r: &ShapeResult, p: Predictor) -> &Score {
    &r.scores[Predictor::ALL.iter().position(|&q| q == p).expect("a predictor")]
}

fn readme(results: &[ShapeResult], n: u64, command: &str, elapsed: f64) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "# Printed dice: the throw preset against measured hand throws\n");
    let _ = writeln!(md, "Regenerate: `{command}` ({n} simulated throws per shape and predictor, seed {SEED}).\n");
    let _ = writeln!(
        md,
        "**Validation only, nothing fitted to these data.** The three dice of \
         `data/printed_shapes/` (Baktash et al., *Putting Rigid Bodies to Rest*, ACM TOG 2025; \
         data repository `hbaktash/resting-rigid-bodies`, MIT) were 3D-printed and thrown by hand onto a table \
         329–406 times each. The predictors below are the project's as they are: the quasi-static basins, and \
         the `throw` preset whose launch was calibrated on seven steel cuboid dice (`results/cuboid_dice/`) on \
         the steel-on-wood contact. The measured throw protocol (height, spin, table) is not documented by the \
         source, and the dice are plastic, not steel: the contact is not the dice's own either.\n"
    );
    let _ = writeln!(md, "## Setup\n");
    let _ = writeln!(
        md,
        "* **Centre of mass.** Each hull is analysed with the printed solid's G from `center_of_mass.txt` \
         (`Options::center_of_mass`, what `rocking analyze/drop --center-of-mass` use), not the hull's centroid; \
         the inertia is the homogeneous hull's about that G (`MassProperties::about`)."
    );
    let _ = writeln!(
        md,
        "* **Size.** Only the rolling-resistance length depends on it (δ = 0.2 mm for steel on wood, \
         δ / R_max in the scaled body; the launch is Froude-scaled). The OBJs are in a normalised frame, not in \
         millimetres or metres (coordinates within ±1, longest extent 1.7–1.9 units), and the source does not \
         give the printed size. Assumed: **1 OBJ unit = {:.0} mm**, i.e. dice a few centimetres long, with R_max in \
         the range of the calibration dice (1.1–1.9 cm):\n",
        METRES_PER_UNIT * 1e3
    );
    let _ = writeln!(
        md,
        "  | shape | extent (OBJ units) | R_max (OBJ units) | assumed R_max | δ / R_max |\n  |---|---|---|---|---|"
    );
    for r in results {
        let _ = writeln!(
            md,
            "  | {} | {:.2} × {:.2} × {:.2} | {:.3} | {:.1} mm | {:.4} |",
            r.shape.name,
            r.extent.x,
            r.extent.y,
            r.extent.z,
            r.r_max_units,
            r.r_max_m * 1e3,
            Surface::SteelOnWood.contact().rolling_resistance_m / r.r_max_m
        );
    }
    let _ = writeln!(md, "\n  Its effect is measured at the end (the throw at half and twice this size).");
    let _ = writeln!(
        md,
        "* **Mapping.** As the data's README says: each stable facet of the hull counts for the outcome whose \
         listed normal (any of the outcome's normals, main first) is nearest to the facet's outward normal. Both \
         are in the OBJ's frame: the analysis keeps the input frame (the dynamics translate the hull to G and \
         scale it, never rotate it; the experiment checks that the drop report's normals are the hull's). \
         In the tables below, *tilt to topple* is the angle the die must be rocked on the facet before G's \
         vertical passes over the facet's nearest edge (0° is a facet on the edge of stability), and a *degenerate \
         decision* is an equilibrium predicate that was exactly on its threshold and was decided by the symbolic \
         perturbation of G."
    );
    let _ = writeln!(
        md,
        "* **Predictors.** (a) quasi-static basins: the basin area of each stable facet on the sphere of down \
         directions / 4π (exact, no interval); (b) the `throw` preset on steel-on-wood at the assumed size with \
         the numerics it was calibrated with in `results/cuboid_dice/` (`Flight::Free`: exact landings and \
         sub-stepped impacts, the preset's default dt listed below), energy certificate per facet; (c) the same throw with rapier's own \
         flight (`Flight::Rapier`: impacts found at the step boundaries, the former numerics); (d) the \
         `drop` preset as the library gives it (released at rest, 1 R_max above the table; its flight is the \
         library's default, listed below). Every simulated predictor uses the same launches (seed {SEED}, stream i \
         for throw i). Parameters as run (scaled body, R_max = 1 m; `binom3`'s δ / R_max, the others' in the \
         size table above):\n"
    );
    let _ = writeln!(
        md,
        "| predictor | height (R_max) | horizontal speed (m/s) | spin, rms (rad/s) | μ | e | δ / R_max | flight | dt (s) |\n|---|---|---|---|---|---|---|---|---|"
    );
    if let Some(r) = results.first() {
        for pred in &r.predictions {
            if let Some(i) = &pred.run {
                let p = &i.params;
                let _ = writeln!(
                    md,
                    "| {} | {} | {} | {} | {} | {} | {:.4} | {} | 1/{:.0} |",
                    pred.predictor.label(),
                    p.launch.height,
                    p.launch.horizontal_speed,
                    p.launch.spin,
                    p.sim.contact.friction,
                    p.sim.contact.restitution,
                    p.sim.contact.rolling_resistance,
                    p.sim.flight.mode,
                    1.0 / p.sim.numerics.dt
                );
            }
        }
    }
    let _ = writeln!(md);
    let _ = writeln!(md, "## Stable facets and outcomes\n");
    for r in results {
        let _ = writeln!(
            md,
            "**{}** ({} hull facets, {} stable; {} degenerate equilibrium decision(s)):\n\n| facet | outward normal | R / R_max | tilt to topple | quasi-static basin | → outcome | angle to its nearest listed normal |\n|---|---|---|---|---|---|---|",
            r.shape.name, r.hull_facets, r.stable, r.degenerate
        );
        for m in &r.mapped {
            let _ = writeln!(
                md,
                "| {} | ({:+.4}, {:+.4}, {:+.4}) | {:.3} | {:.2}° | {:.4} | {} | {:.2}°{} |",
                m.facet,
                m.normal.x,
                m.normal.y,
                m.normal.z,
                m.r / r.r_max_units,
                m.tilt_deg,
                m.basin,
                r.shape.outcomes[m.outcome].id,
                m.angle_deg,
                if m.angle_deg > POOR_MATCH_DEG { " (poor match)" } else { "" }
            );
        }
        let empty: Vec<&str> = r
            .shape
            .outcomes
            .iter()
            .enumerate()
            .filter(|(k, _)| !r.mapped.iter().any(|m| m.outcome == *k))
            .map(|(_, o)| o.id.as_str())
            .collect();
        if !empty.is_empty() {
            let _ = writeln!(
                md,
                "\nOutcome(s) {} have no stable facet of this hull: every predictor gives them 0.",
                empty.join(", ")
            );
        }
        let unmatched: Vec<String> = r
            .shape
            .outcomes
            .iter()
            .flat_map(|o| o.normals.iter().map(move |nm| (o, nm)))
            .filter(|(_, nm)| {
                !r.mapped.iter().any(|m| m.normal.dot(nm).clamp(-1.0, 1.0).acos().to_degrees() < POOR_MATCH_DEG)
            })
            .map(|(o, nm)| format!("outcome {} ({:+.3}, {:+.3}, {:+.3})", o.id, nm.x, nm.y, nm.z))
            .collect();
        if !unmatched.is_empty() {
            let _ = writeln!(
                md,
                "\nListed normals with no stable facet within {POOR_MATCH_DEG}°: {} (a facet that is not stable for \
                 this hull and G).",
                unmatched.join("; ")
            );
        }
        let poor: Vec<&Mapped> = r.mapped.iter().filter(|m| m.poor()).collect();
        if !poor.is_empty() {
            let list: Vec<String> = poor
                .iter()
                .map(|m| {
                    format!(
                        "facet {} (→ outcome {}, {:.0}° away)",
                        m.facet, r.shape.outcomes[m.outcome].id, m.angle_deg
                    )
                })
                .collect();
            let _ = writeln!(
                md,
                "\n**Stable, but listed in no outcome:** {}. The rule counts it for its nearest outcome; the printed die \
                 may not rest there (its G, print or the table differ), or the experimenter may have read it otherwise. \
                 Share of each predictor on it, and the TV if it is left out (the rest renormalised):\n",
                list.join(", ")
            );
            let _ =
                writeln!(md, "| predictor | share on unlisted facets | TV (rule) | TV (left out) |\n|---|---|---|---|");
            let p_meas: Vec<f64> = r.shape.outcomes.iter().map(|o| o.count as f64 / r.shape.n as f64).collect();
            for (pred, sc) in r.predictions.iter().zip(&r.scores) {
                let _ = writeln!(
                    md,
                    "| {} | {:.3} | {:.3} | {} |",
                    pred.predictor.label(),
                    pred.unlisted,
                    sc.tv,
                    pred.p_listed_only.as_ref().map_or("—".into(), |q| format!("{:.3}", tv(q, &p_meas)))
                );
            }
        }
        let _ = writeln!(md);
    }
    let _ = writeln!(md, "## Predicted and measured frequencies\n");
    let _ = writeln!(
        md,
        "Measured: count / N with its 95 % Wilson interval. Simulated predictors: the fraction of the {n} throws \
         with its 95 % Monte Carlo (Wilson) interval.\n"
    );
    for r in results {
        let _ = writeln!(md, "**{}** (N = {} measured throws)\n", r.shape.name, r.shape.n);
        let _ = write!(md, "| outcome | measured |");
        for p in Predictor::ALL {
            let _ = write!(md, " {} |", p.label());
        }
        let _ = writeln!(md, "\n|---|---|{}", "---|".repeat(Predictor::ALL.len()));
        for (k, o) in r.shape.outcomes.iter().enumerate() {
            let (lo, hi) = wilson(o.count, r.shape.n, 1.96);
            let _ =
                write!(md, "| {} | {:.3} [{lo:.3}, {hi:.3}] ({}) |", o.id, o.count as f64 / r.shape.n as f64, o.count);
            for pred in &r.predictions {
                match &pred.counts {
                    Some((c, total)) => {
                        let (lo, hi) = wilson(c[k], *total, 1.96);
                        let _ = write!(md, " {:.3} [{lo:.3}, {hi:.3}] |", pred.p[k]);
                    }
                    None => {
                        let _ = write!(md, " {:.3} |", pred.p[k]);
                    }
                }
            }
            let _ = writeln!(md);
        }
        let _ = writeln!(md);
    }
    let _ = writeln!(md, "## Distance to the measurement\n");
    let _ = writeln!(
        md,
        "TV = ½ Σ |p_pred − p_meas| over the outcomes. **Noise TV**: the TV a measurement of the same N would show \
         if the predictor were exactly right (parametric bootstrap, {BOOTSTRAP} replicates: the measured N drawn \
         from the predicted frequencies, and for a simulated predictor its {n} throws redrawn too); mean and 95th \
         percentile. A TV above the 95th percentile is more than sampling noise. χ²: Pearson's χ² of the \
         measured counts against the predicted frequencies (`stats::chi_square`, categories expected below 5 \
         pooled), which takes the prediction as exact; two-sample: the χ² test of homogeneity of the measured \
         and simulated counts, which also counts the Monte Carlo noise.\n"
    );
    let _ = writeln!(md, "| shape | predictor | TV | noise TV: mean | noise TV: 95 % | χ² (dof) | p | p two-sample |\n|---|---|---|---|---|---|---|---|");
    for r in results {
        for (pred, s) in r.predictions.iter().zip(&r.scores) {
            let mark = if s.tv > s.noise_q95 { "**" } else { "" };
            let _ = writeln!(
                md,
                "| {} | {} | {mark}{:.3}{mark} | {:.3} | {:.3} | {} | {} | {} |",
                r.shape.name,
                pred.predictor.label(),
                s.tv,
                s.noise_mean,
                s.noise_q95,
                if s.impossible {
                    "∞ (an outcome measured, never predicted)".to_string()
                } else {
                    format!("{:.1} ({})", s.chi2, s.dof)
                },
                p_text(s.p_value),
                s.p_homogeneity.map_or("—".into(), p_text)
            );
        }
    }
    let _ = writeln!(md, "\nBold: TV beyond the 95th percentile of its noise TV.\n");
    let _ = writeln!(md, "Picture: `tv.png` — per die, the measured frequencies (black, 95 % Wilson intervals) and the four predictors (bars, 95 % Monte Carlo intervals); last panel, the TV of each predictor with the 95th percentile of its noise TV.\n");
    let _ = writeln!(md, "{}", reading(results));
    let _ = writeln!(md, "## Size assumption: the calibrated throw at half and twice the assumed size\n");
    let _ = writeln!(md, "Only δ / R_max changes (× 2 and × ½). Same launches (seed {SEED}, {n} throws).\n");
    let _ = writeln!(md, "| shape | TV at ½ × size (δ/R_max × 2) | TV at the assumed size | TV at 2 × size (δ/R_max × ½) |\n|---|---|---|---|");
    for r in results {
        let at = |f: f64| r.size_check.iter().find(|s| s.0 == f).map_or(f64::NAN, |s| s.2);
        let _ = writeln!(
            md,
            "| {} | {:.3} | {:.3} | {:.3} |",
            r.shape.name,
            at(0.5),
            score_of(r, Predictor::Throw).tv,
            at(2.0)
        );
    }
    let _ = writeln!(md, "\n## Exact landings against rapier's flight\n");
    let _ = writeln!(
        md,
        "The same {n} launches of the throw with exact landings (b) and with rapier's flight (c); χ² of \
         homogeneity of the two samples' outcome counts (the test takes the samples as independent; they share \
         their launches, but a throw is chaotic and the outcomes differ drop by drop).\n"
    );
    let _ = writeln!(md, "| shape | TV between the two | χ² | p |\n|---|---|---|---|");
    for r in results {
        let (d, chi2, p) = r.numerics;
        let _ = writeln!(md, "| {} | {d:.3} | {chi2:.1} | {} |", r.shape.name, p_text(p));
    }
    let _ = writeln!(md, "\n## Runs\n");
    let _ = writeln!(md, "| shape | predictor | drops | unsettled at the time cap | stopped off their facet | ended by the certificate | seconds |\n|---|---|---|---|---|---|---|");
    for r in results {
        for pred in &r.predictions {
            if let Some(i) = &pred.run {
                let _ = writeln!(
                    md,
                    "| {} | {} | {} | {} | {} | {} | {:.0} |",
                    r.shape.name,
                    pred.predictor.label(),
                    i.drops,
                    i.unsettled,
                    i.off_equilibrium,
                    i.certified,
                    i.seconds
                );
            }
        }
    }
    let _ = writeln!(md, "\nTotal {elapsed:.0} s on this machine (2 cores, shared).");
    md
}

/// The reading of the results, with the numbers of this run.
fn reading(results: &[ShapeResult]) -> String {
    let mut md = String::from("## Reading\n\n");
    for r in results {
        let qs = score_of(r, Predictor::QuasiStatic);
        let th = score_of(r, Predictor::Throw);
        let fr = score_of(r, Predictor::ThrowRapier);
        let dr = score_of(r, Predictor::Drop);
        let verdict = |s: &Score| {
            if s.tv <= s.noise_q95 {
                "within noise"
            } else {
                "beyond noise"
            }
        };
        let _ = writeln!(
            md,
            "* **{}**: TV quasi-static {:.3} ({}), calibrated throw {:.3} ({}), rapier's flight {:.3} ({}), drop {:.3} ({}); \
             the calibrated throw is {} the quasi-static basins here.",
            r.shape.name,
            qs.tv,
            verdict(qs),
            th.tv,
            verdict(th),
            fr.tv,
            verdict(fr),
            dr.tv,
            verdict(dr),
            if th.tv + 0.5 * th.noise_mean < qs.tv {
                "closer to the measurement than"
            } else if qs.tv + 0.5 * qs.noise_mean < th.tv {
                "further from the measurement than"
            } else {
                "about as close to the measurement as"
            }
        );
    }
    let mean = |p: Predictor| results.iter().map(|r| score_of(r, p).tv).sum::<f64>() / results.len() as f64;
    let means: Vec<String> = Predictor::ALL.iter().map(|&p| format!("{} {:.3}", p.label(), mean(p))).collect();
    let _ = writeln!(
        md,
        "\n(\"About as close\": the two TVs differ by less than half the mean noise TV.) Mean TV over the three dice: \
         {}.\n",
        means.join(", ")
    );
    md.push_str(READING);
    md
}

/// What the numbers above cannot say by themselves.
const READING: &str = "\
**How to read it.** binom4 is the die whose measurement is far from the quasi-static basins (its two end faces came \
up 4 and 10 times in 404 throws against ≈ 27 each by the basins): it is the one that tests the dynamics. dragon_d3 is \
a fair die by design, and a TV within its noise there cannot tell the predictors apart. A throw with spin takes \
probability from narrow, shallow faces and gives it to deep, wide ones; whether the hand throws of the measurement \
did the same differs from die to die, and three dice cannot say whether the print, the hand or the model is at fault \
where they disagree. The numerics row (exact landings against rapier's flight, same launches) shows how much of a \
prediction is the integration of the impacts rather than the physics.

Caveats: the contact is steel on wood (the calibration's), not a plastic print on the authors' table; the throw \
protocol of the measurement is not documented; the binom hulls are the released example meshes, not the exact \
printed files.
";

type PlotResult = std::result::Result<(), Box<dyn std::error::Error>>;

fn plot(path: &Path, results: &[ShapeResult]) -> PlotResult {
    use plotters::prelude::*;
    rocking_stones::plot::draw_png(path, (1200, 980), |root| {
        root.fill(&WHITE)?;
        let root = root.titled(
            "Printed dice: measured hand throws against the predictors (validation, nothing fitted)",
            (FONT_FAMILY, style::TITLE),
        )?;
        let (legend, area) = root.split_vertically(legend_height(2));
        let mut entries = vec![(Mark::LineDot(BLACK), "measured (95 % Wilson interval)".to_string())];
        for (k, p) in Predictor::ALL.iter().enumerate() {
            entries.push((Mark::Box(series_color(k), 0.85), p.label().to_string()));
        }
        entries.push((Mark::Line(GREY), "thin whiskers: 95 % Monte Carlo interval of a simulated predictor".into()));
        entries.push((
            Mark::Line(BLACK),
            "last panel: noise level (95th percentile of the TV if the predictor were exact)".into(),
        ));
        draw_legend(&legend, &entries).map_err(|e| e.to_string())?;
        let panels = area.split_evenly((2, 2));
        let slots = Predictor::ALL.len() + 1;
        let width = 0.8 / slots as f64;
        let offset = |slot: usize| -0.4 + width * (slot as f64 + 0.5);
        for (r, panel) in results.iter().zip(&panels) {
            let k = r.shape.outcomes.len();
            let top = r
                .shape
                .outcomes
                .iter()
                .map(|o| wilson(o.count, r.shape.n, 1.96).1)
                .chain(r.predictions.iter().flat_map(|p| p.p.iter().copied()))
                .fold(0.0f64, f64::max);
            let y_max = ((top * 1.1) * 10.0).ceil() / 10.0;
            let ids: Vec<String> = r.shape.outcomes.iter().map(|o| o.id.clone()).collect();
            let mut chart = ChartBuilder::on(panel)
                .caption(format!("{} (N = {} hand throws)", r.shape.name, r.shape.n), (FONT_FAMILY, style::PANEL_TITLE))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(60)
                .build_cartesian_2d(-0.5f64..(k as f64 - 0.5), 0.0f64..y_max)?;
            chart
                .configure_mesh()
                .disable_x_mesh()
                .x_labels(4 * k + 1)
                .x_label_formatter(&|x| {
                    let i = x.round();
                    if (x - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < ids.len() {
                        ids[i as usize].clone()
                    } else {
                        String::new()
                    }
                })
                .y_label_formatter(&|y| plain(*y))
                .light_line_style(WHITE.mix(0.0))
                .x_desc("outcome (id of outcomes.csv)")
                .y_desc("frequency")
                .label_style((FONT_FAMILY, style::TICK))
                .axis_desc_style((FONT_FAMILY, style::AXIS))
                .draw()?;
            for (slot, pred) in r.predictions.iter().enumerate() {
                let c = series_color(slot);
                let x0 = |i: usize| i as f64 + offset(slot + 1) - 0.45 * width;
                let x1 = |i: usize| i as f64 + offset(slot + 1) + 0.45 * width;
                chart.draw_series(
                    (0..k).map(|i| Rectangle::new([(x0(i), 0.0), (x1(i), pred.p[i])], c.mix(0.85).filled())),
                )?;
                if let Some((counts, total)) = &pred.counts {
                    chart.draw_series((0..k).map(|i| {
                        let (lo, hi) = wilson(counts[i], *total, 1.96);
                        let x = i as f64 + offset(slot + 1);
                        PathElement::new(vec![(x, lo), (x, hi)], GREY.stroke_width(1))
                    }))?;
                }
            }
            chart.draw_series(r.shape.outcomes.iter().enumerate().map(|(i, o)| {
                let (lo, hi) = wilson(o.count, r.shape.n, 1.96);
                let x = i as f64 + offset(0);
                PathElement::new(vec![(x, lo), (x, hi)], BLACK.stroke_width(style::LINE))
            }))?;
            chart.draw_series(r.shape.outcomes.iter().enumerate().map(|(i, o)| {
                Circle::new((i as f64 + offset(0), o.count as f64 / r.shape.n as f64), style::MARKER, BLACK.filled())
            }))?;
        }
        // Last panel: TV per shape and predictor, with the noise level.
        let panel = &panels[3];
        let top = results.iter().flat_map(|r| r.scores.iter().map(|s| s.tv.max(s.noise_q95))).fold(0.0f64, f64::max);
        let y_max = ((top * 1.15) * 20.0).ceil() / 20.0;
        let names: Vec<&str> = results.iter().map(|r| r.shape.name).collect();
        let mut chart = ChartBuilder::on(panel)
            .caption("total variation distance to the measurement", (FONT_FAMILY, style::PANEL_TITLE))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(-0.5f64..(results.len() as f64 - 0.5), 0.0f64..y_max)?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(4 * results.len() + 1)
            .x_label_formatter(&|x| {
                let i = x.round();
                if (x - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < names.len() {
                    names[i as usize].to_string()
                } else {
                    String::new()
                }
            })
            .y_label_formatter(&|y| plain(*y))
            .light_line_style(WHITE.mix(0.0))
            .x_desc("die")
            .y_desc("TV = ½ Σ |p_pred − p_meas|")
            .label_style((FONT_FAMILY, style::TICK))
            .axis_desc_style((FONT_FAMILY, style::AXIS))
            .draw()?;
        let w = 0.8 / Predictor::ALL.len() as f64;
        for slot in 0..Predictor::ALL.len() {
            let c = series_color(slot);
            let x = |i: usize| i as f64 - 0.4 + w * (slot as f64 + 0.5);
            chart.draw_series(results.iter().enumerate().map(|(i, r)| {
                Rectangle::new([(x(i) - 0.45 * w, 0.0), (x(i) + 0.45 * w, r.scores[slot].tv)], c.mix(0.85).filled())
            }))?;
            chart.draw_series(results.iter().enumerate().map(|(i, r)| {
                let q = r.scores[slot].noise_q95;
                PathElement::new(vec![(x(i) - 0.5 * w, q), (x(i) + 0.5 * w, q)], BLACK.stroke_width(style::LINE))
            }))?;
        }
        Ok(())
    })?;
    Ok(())
}
