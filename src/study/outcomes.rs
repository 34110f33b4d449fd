//! Measured outcomes of a die or stone thrown by hand, and how a prediction is scored against
//! them.
//!
//! A hand experiment throws an object n times and counts the face it comes to rest on. An
//! outcome has an id and the outward normal(s), in the object's frame, of the hull facet(s) it
//! rests on (a printed shape may give one outcome several nearly parallel facets). One thrown
//! object is a folder ([`ThrownShape::read`]):
//!
//! * one `.obj` mesh of its hull;
//! * `center_of_mass.txt`: the centre of mass, `x y z` in the mesh's frame;
//! * `outcomes.csv`: `outcome, resting_facet_normals, measured_count, n_throws, measured_freq`,
//!   one row per outcome, the normals written `x y z;x y z;…`, every row with the same
//!   `n_throws`, the counts adding up to it, `measured_freq` = count / n to 5·10⁻⁴.
//!
//! A predictor gives each outcome a probability p_i. It is scored by [`score`]:
//!
//! * the total variation distance TV = ½ Σ |p_i − k_i/n| ([`total_variation`]);
//! * the TV that sampling noise alone would give if the predictor were exact: a parametric
//!   bootstrap that redraws the measurement's n throws from p ([`multinomial`]) and, for a
//!   simulated predictor, its own m throws too;
//! * Pearson's χ² of the counts against p (with p = 0 for a measured outcome marked
//!   impossible, p-value 0); for a simulated predictor, the two-sample χ² of homogeneity of the
//!   measured and simulated counts.

use crate::dynamics::drops::montecarlo::DropReport;
use crate::error::{Error, Result};
use crate::rng::item_rng;
use crate::stats::{chi_square, chi_square_homogeneity, mean};
use crate::{Point3, Vec3};
use rand::Rng;
use rand_distr::{Binomial, Distribution};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The measured outcomes of one object: ids, the outward normals of each outcome's facets (unit
/// vectors, object frame), counts, and the number of throws (the counts' sum).
#[derive(Clone, Debug, PartialEq)]
pub struct MeasuredOutcomes {
    /// Outcome ids, in the file's order.
    pub ids: Vec<String>,
    /// Per outcome, the outward normals of the facets it rests on, normalised.
    pub normals: Vec<Vec<Vec3>>,
    /// Per outcome, the throws that ended on it.
    pub counts: Vec<u64>,
    /// The number of throws.
    pub throws: u64,
}

/// A thrown object's folder: its hull mesh, centre of mass and measured outcomes.
#[derive(Clone, Debug, PartialEq)]
pub struct ThrownShape {
    /// The `.obj` mesh of the folder.
    pub mesh: PathBuf,
    /// The centre of mass, in the mesh's frame.
    pub center_of_mass: Point3,
    /// The measured outcomes.
    pub outcomes: MeasuredOutcomes,
}

impl ThrownShape {
    /// Read and check the folder `dir` (see the module documentation for its files).
    pub fn read(dir: &Path) -> Result<ThrownShape> {
        fn io(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
            move |error| Error::Io { path: path.into(), error }
        }
        let is_obj = |p: &PathBuf| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("obj"));
        let entries = std::fs::read_dir(dir).map_err(io(dir))?;
        let objs: Vec<PathBuf> = entries.filter_map(|e| Some(e.ok()?.path())).filter(is_obj).collect();
        let [mesh] = objs.as_slice() else {
            let what = format!("expected one .obj hull in the folder, found {}", objs.len());
            return Err(Error::Study { path: dir.into(), what });
        };
        let com_path = dir.join("center_of_mass.txt");
        let text = std::fs::read_to_string(&com_path).map_err(io(&com_path))?;
        let center_of_mass = Point3::from(
            parse_vec3(text.trim(), "the centre of mass")
                .map_err(|what| Error::Parse { path: com_path.clone(), what })?,
        );
        let outcomes = MeasuredOutcomes::read(&dir.join("outcomes.csv"))?;
        Ok(ThrownShape { mesh: mesh.clone(), center_of_mass, outcomes })
    }
}

/// Three finite numbers separated by white space, or what is wrong with `text` (`what` names it).
fn parse_vec3(text: &str, what: &str) -> Result<Vec3, String> {
    let v: Vec<f64> =
        text.split_whitespace().map(str::parse).collect::<Result<_, _>>().map_err(|e| format!("{what}: {e}"))?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(Vec3::new(x, y, z)),
        _ => Err(format!("{what}: {text:?} is not three finite numbers")),
    }
}

impl MeasuredOutcomes {
    /// Read and check an `outcomes.csv` (see the module documentation).
    pub fn read(path: &Path) -> Result<MeasuredOutcomes> {
        let parse = |what: String| Error::Parse { path: path.into(), what };
        let mut reader =
            csv::ReaderBuilder::new().trim(csv::Trim::All).from_path(path).map_err(|e| Error::write(path, e))?;
        let (mut out, mut n_all) = (MeasuredOutcomes { ids: vec![], normals: vec![], counts: vec![], throws: 0 }, None);
        for (i, record) in reader.deserialize().enumerate() {
            let at = format!("record {}", i + 1);
            let (id, normals, count, n, freq): (String, String, u64, u64, f64) =
                record.map_err(|e| parse(format!("{at}: {e}")))?;
            let normals =
                normals.split(';').map(|s| parse_vec3(s, &at)).collect::<Result<Vec<_>, _>>().map_err(parse)?;
            if normals.iter().any(|v| (v.norm() - 1.0).abs() >= 1e-3) {
                return Err(parse(format!("{at}: a normal is not a unit vector")));
            }
            if n == 0 || count > n || *n_all.get_or_insert(n) != n {
                return Err(parse(format!("{at}: {count} of {n} throws, after rows of {n_all:?}")));
            }
            if (freq - count as f64 / n as f64).abs() >= 5e-4 {
                return Err(parse(format!("{at}: measured_freq is not count / n")));
            }
            out.ids.push(id);
            out.normals.push(normals.iter().map(|v| v.normalize()).collect());
            out.counts.push(count);
        }
        out.throws = n_all.ok_or_else(|| parse("no outcomes".into()))?;
        if out.counts.iter().sum::<u64>() != out.throws {
            return Err(parse("the counts do not add up to n_throws".into()));
        }
        Ok(out)
    }

    /// The measured frequencies k_i / n.
    pub fn frequencies(&self) -> Vec<f64> {
        frequencies(&self.counts, self.throws)
    }

    /// The outcome whose listed normal is nearest to `normal` (the largest dot product), and the
    /// angle between them in degrees.
    pub fn nearest(&self, normal: &Vec3) -> (usize, f64) {
        let all = self.normals.iter().enumerate().flat_map(|(k, ns)| ns.iter().map(move |m| (k, m)));
        let (k, m) = all.max_by(|a, b| a.1.dot(normal).total_cmp(&b.1.dot(normal))).expect("an outcome");
        (k, m.dot(normal).clamp(-1.0, 1.0).acos().to_degrees())
    }
}

/// The total variation distance ½ Σ |p_i − q_i| of two distributions over the same outcomes.
pub fn total_variation(p: &[f64], q: &[f64]) -> f64 {
    0.5 * p.iter().zip(q).map(|(a, b)| (a - b).abs()).sum::<f64>()
}

/// The frequencies k_i / n of counts `k`.
pub fn frequencies(k: &[u64], n: u64) -> Vec<f64> {
    k.iter().map(|&k| k as f64 / n as f64).collect()
}

/// A multinomial draw of `n` over the probabilities `p` (adding up to 1), as conditional
/// binomials: k_i ~ B(n − Σ_{j<i} k_j, p_i / (1 − Σ_{j<i} p_j)), the last outcome taking what is
/// left.
pub fn multinomial<R: Rng + ?Sized>(rng: &mut R, n: u64, p: &[f64]) -> Vec<u64> {
    let (mut left, mut mass, mut out) = (n, 1.0, Vec::with_capacity(p.len()));
    for (i, &q) in p.iter().enumerate() {
        let last = i + 1 == p.len() || left == 0;
        let k = if last {
            left
        } else {
            Binomial::new(left, (q / mass).clamp(0.0, 1.0)).expect("a probability in [0, 1]").sample(rng)
        };
        (left, mass) = (left - k, mass - q);
        out.push(k);
    }
    out
}

/// How a predictor's probabilities agree with the measured outcomes ([`score`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Score {
    /// TV between the prediction and the measured frequencies.
    pub tv: f64,
    /// Mean TV of the sampling noise alone (the predictor taken as exact).
    pub noise_mean: f64,
    /// 95th percentile of that TV: a TV above it is more than noise.
    pub noise_q95: f64,
    /// Pearson's χ² of the counts against the prediction, its degrees of freedom and p-value
    /// (0 when the prediction is impossible).
    pub chi2: f64,
    /// Degrees of freedom of `chi2`.
    pub dof: usize,
    /// p-value of `chi2`.
    pub p_value: f64,
    /// Whether an outcome was measured that the prediction gives probability 0.
    pub impossible: bool,
    /// For a simulated predictor, the p-value of the χ² of homogeneity of the measured and the
    /// simulated counts.
    pub p_homogeneity: Option<f64>,
}

/// Score the probabilities `p` against `measured`. `simulated`: the counts of a simulated
/// predictor (whose frequencies `p` are), so that the noise level includes its own sampling;
/// `bootstrap` replicates of the noise TV, replicate b drawn from `item_rng(seed, b)`.
pub fn score(measured: &MeasuredOutcomes, p: &[f64], simulated: Option<&[u64]>, bootstrap: u64, seed: u64) -> Score {
    let n = measured.throws;
    let mut tvs: Vec<f64> = (0..bootstrap)
        .map(|b| {
            let mut rng = item_rng(seed, b);
            let meas = frequencies(&multinomial(&mut rng, n, p), n);
            simulated.map_or(total_variation(&meas, p), |sim| {
                let m = sim.iter().sum();
                total_variation(&meas, &frequencies(&multinomial(&mut rng, m, p), m))
            })
        })
        .collect();
    tvs.sort_by(f64::total_cmp);
    let noise_q95 = tvs[((0.95 * tvs.len() as f64) as usize).min(tvs.len() - 1)];
    let impossible = p.iter().zip(&measured.counts).any(|(&p, &k)| p == 0.0 && k > 0);
    let (chi2, dof, p_value) = chi_square(&measured.counts, p);
    Score {
        tv: total_variation(p, &measured.frequencies()),
        noise_mean: mean(&tvs),
        noise_q95,
        chi2,
        dof,
        p_value: if impossible { 0.0 } else { p_value },
        impossible,
        p_homogeneity: simulated.map(|c| chi_square_homogeneity(&measured.counts, c).2),
    }
}

/// A predictor's weights over the stable facets of a hull gathered by measured outcome
/// ([`by_outcome`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ByOutcome {
    /// The frequency of each outcome: the weights of its facets over the total weight.
    pub p: Vec<f64>,
    /// The share of the weight on facets that match no listed normal well.
    pub unlisted: f64,
    /// The frequencies without those facets (the rest renormalised), when there are any and
    /// some weight is left.
    pub listed_only: Option<Vec<f64>>,
}

/// Gather the weights `w` (probabilities or counts, by facet; a facet absent from `w` weighs 0)
/// of the stable facets `mapped` = (facet, its outcome among `k`, whether it matches no listed
/// normal well — see [`MeasuredOutcomes::nearest`]) by outcome.
pub fn by_outcome(mapped: &[(u32, usize, bool)], k: usize, w: &BTreeMap<u32, f64>) -> ByOutcome {
    let w = |f: u32| w.get(&f).copied().unwrap_or(0.0);
    let total: f64 = mapped.iter().map(|m| w(m.0)).sum();
    let (mut p, mut listed) = (vec![0.0; k], vec![0.0; k]);
    for &(f, outcome, poor) in mapped {
        p[outcome] += w(f) / total;
        listed[outcome] += if poor { 0.0 } else { w(f) };
    }
    let unlisted: f64 = mapped.iter().filter(|m| m.2).map(|m| w(m.0)).sum::<f64>() / total;
    let listed_total: f64 = listed.iter().sum();
    let listed_only = mapped.iter().any(|m| m.2) && listed_total > 0.0;
    ByOutcome { p, unlisted, listed_only: listed_only.then(|| listed.iter().map(|x| x / listed_total).collect()) }
}

/// What a drop run predicts for an outcome made of the hull facets whose outward normal (mesh
/// frame) satisfies `on` (the square faces of a die, the rim of a coin): the drops that came to
/// rest on those facets, the drops whose facet was determined (their frequency's denominator,
/// [`DropReport::facet_drops`]) and the facets' quasi-static probability (the sum of their basin
/// areas over 4π).
pub fn share_on(report: &DropReport, on: impl Fn(&Vec3) -> bool) -> (u64, u64, f64) {
    let facets = || report.facets.iter().filter(|f| on(&f.normal));
    (facets().map(|f| f.count).sum(), report.facet_drops, facets().map(|f| f.static_probability).sum())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn measured(counts: Vec<u64>) -> MeasuredOutcomes {
        let k = counts.len();
        let ids = (0..k).map(|i| i.to_string()).collect();
        let normals = (0..k).map(|i| vec![if i == 0 { Vec3::z() } else { -Vec3::z() }]).collect();
        MeasuredOutcomes { ids, normals, throws: counts.iter().sum(), counts }
    }

    #[test]
    fn total_variation_is_half_the_l1_distance() {
        assert_eq!(total_variation(&[0.5, 0.5, 0.0], &[0.2, 0.3, 0.5]), 0.5);
        assert_eq!(total_variation(&[0.25, 0.75], &[0.25, 0.75]), 0.0);
    }

    #[test]
    fn multinomial_draws_keep_n_and_the_means() {
        let p = [0.5, 0.3, 0.2, 0.0];
        let mut sum = [0u64; 4];
        for b in 0..2000 {
            let k = multinomial(&mut item_rng(3, b), 100, &p);
            assert_eq!(k.iter().sum::<u64>(), 100);
            assert_eq!(k[3], 0, "an outcome of probability 0 is never drawn");
            (0..4).for_each(|i| sum[i] += k[i]);
        }
        // Mean count 100 p_i; its standard error over 2000 draws is √(100 p (1 − p) / 2000) ≤ 0.12.
        for i in 0..3 {
            let m = sum[i] as f64 / 2000.0;
            assert!((m - 100.0 * p[i]).abs() < 0.5, "outcome {i}: mean {m}");
        }
    }

    #[test]
    fn the_noise_level_of_an_exact_predictor_matches_its_closed_form() {
        // Two outcomes, p = (½, ½), n = 100: TV = |k/n − ½|, whose mean is E|B(100, ½) − 50| / 100
        // = 100·C(100, 50)/2¹⁰⁰ / 2 / 100 = 0.0398 (the mean absolute deviation of a binomial).
        let m = measured(vec![50, 50]);
        let s = score(&m, &[0.5, 0.5], None, 4000, 11);
        assert_eq!((s.tv, s.chi2, s.p_value, s.impossible), (0.0, 0.0, 1.0, false));
        assert!((s.noise_mean - 0.0398).abs() < 0.002, "noise TV {}", s.noise_mean);
        assert!(s.noise_q95 >= 0.08 && s.noise_q95 <= 0.11, "95th percentile {}", s.noise_q95);
        // A simulated predictor of 100 draws of its own adds its noise: the TV of two such
        // samples is larger.
        let sim = score(&m, &[0.5, 0.5], Some(&[50, 50]), 4000, 11);
        assert!(sim.noise_mean > 1.3 * s.noise_mean && sim.p_homogeneity == Some(1.0));
    }

    #[test]
    fn an_outcome_the_prediction_rules_out_makes_it_impossible() {
        let s = score(&measured(vec![90, 10]), &[1.0, 0.0], None, 10, 1);
        assert!(s.impossible && s.p_value == 0.0);
        assert!((s.tv - 0.1).abs() < 1e-12);
    }

    #[test]
    fn the_nearest_outcome_is_the_one_of_the_closest_normal() {
        let m = measured(vec![1, 1]);
        let (k, angle) = m.nearest(&Vec3::new(0.0, 0.1, -1.0).normalize());
        assert_eq!(k, 1);
        assert!((angle - 0.1f64.atan().to_degrees()).abs() < 1e-9);
    }

    #[test]
    fn reading_checks_the_counts_and_names_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("outcomes.csv");
        let header = "outcome,resting_facet_normals,measured_count,n_throws,measured_freq\n";
        std::fs::write(&path, format!("{header}a,0 0 1,3,4,0.75\nb,0 0 -1;0 0.6 -0.8,1,4,0.25\n")).unwrap();
        let m = MeasuredOutcomes::read(&path).unwrap();
        assert_eq!((m.ids.len(), m.normals[1].len(), m.counts.clone(), m.throws), (2, 2, vec![3, 1], 4));
        for bad in ["a,0 0 1,3,4,0.75\nb,0 0 -1,2,4,0.5\n", "a,0 0 2,3,4,0.75\n", "a,0 0,1,1,1\n"] {
            std::fs::write(&path, format!("{header}{bad}")).unwrap();
            let e = MeasuredOutcomes::read(&path).unwrap_err().to_string();
            assert!(e.contains("outcomes.csv"), "{e}");
        }
    }

    #[test]
    fn facet_weights_gather_by_outcome() {
        // Facets 4 and 7 are outcome 0, facet 9 outcome 1 but a poor match; counts 3, 1, 4 (and a
        // facet 5 outside the map, ignored).
        let mapped = [(4, 0, false), (7, 0, false), (9, 1, true)];
        let w = BTreeMap::from([(4, 3.0), (7, 1.0), (9, 4.0), (5, 10.0)]);
        let g = by_outcome(&mapped, 2, &w);
        assert_eq!((g.p, g.unlisted, g.listed_only), (vec![0.5, 0.5], 0.5, Some(vec![1.0, 0.0])));
        // Every facet well matched: nothing unlisted, no second set of frequencies.
        let g = by_outcome(&[(4, 1, false), (7, 0, false)], 2, &w);
        assert_eq!((g.p, g.unlisted, g.listed_only), (vec![0.25, 0.75], 0.0, None));
    }

    #[test]
    fn a_drop_run_shares_its_drops_between_an_outcome_and_the_rest() {
        use crate::analysis::{Analysis, Options};
        use crate::dynamics::certificate::CertificateMode;
        use crate::dynamics::drops::montecarlo::{run_and_summarize, RunHeader};
        use crate::dynamics::drops::params::Preset;
        use crate::dynamics::stone::Stone;
        use crate::dynamics::surface::Surface;
        // A flat box 1 × 1 × 0.5: its two square faces (normal ±z) and its four sides.
        let (mesh, repairs) = crate::generate::cuboid(1.0, 1.0, 0.5).into_solid_boundary().unwrap();
        let stone = Stone::new(&Analysis::of_solid(mesh, repairs, &Options::default()).unwrap(), 0.0035).unwrap();
        let params = Preset::Drop.params(Surface::SteelOnWood);
        let (report, _) =
            run_and_summarize(&stone, &RunHeader::of_params("box", 1, 40, params, CertificateMode::Facet));
        let (square, n, p_square) = share_on(&report, |v| v.z.abs() > 0.99);
        let (side, n_side, p_side) = share_on(&report, |v| v.z.abs() <= 0.99);
        assert_eq!((square + side, n, n_side), (n, report.facet_drops, report.facet_drops));
        assert!(n > 30 && square > side, "{square} of {n} on the square faces");
        // The basins cover the sphere; the square faces of a flat box hold most of it.
        assert!((p_square + p_side - 1.0).abs() < 1e-9 && p_square > 0.5, "{p_square} {p_side}");
    }
}
