//! The statistics of a drop run against the static theory ([`summarize`]): per facet and per
//! flock, counts and fractions with Wilson 95 % intervals beside the quasi-static basin
//! probabilities, and Pearson's χ² and the Kullback–Leibler divergence of the empirical
//! distribution from the static one ([`Fit`]).

use crate::dynamics::certificate::CertificateMode;
use crate::dynamics::drops::launch::DropOutcome;
use crate::dynamics::drops::montecarlo::header::RunHeader;
use crate::dynamics::drops::params::DropParams;
use crate::dynamics::stone::StaticModel;
use crate::equilibria::Kind;
use crate::stats::{chi_square, kl_divergence, wilson};
use crate::Vec3;
use serde::Serialize;
use std::collections::BTreeMap;

/// Per-facet row of a drop report.
#[derive(Clone, Debug, Serialize)]
pub struct FacetRow {
    /// Hull facet index.
    pub facet: u32,
    /// Outward unit normal of the facet (mesh frame).
    pub normal: Vec3,
    /// Index of the stable micro-equilibrium on it (None: the facet is not stable).
    pub equilibrium: Option<usize>,
    /// Flock of that equilibrium at ν (None: the facet is not stable).
    pub flock: Option<usize>,
    /// Settled drops that ended on the facet.
    pub count: u64,
    /// Fraction of the settled drops with a determined facet that ended on it.
    pub fraction: f64,
    /// 95 % Wilson interval of `fraction`.
    pub ci95: (f64, f64),
    /// Quasi-static resting probability of the facet (basin area / 4π).
    pub static_probability: f64,
}

/// Per-flock row of a drop report.
#[derive(Clone, Debug, Serialize)]
pub struct FlockRow {
    /// Flock id.
    pub id: usize,
    #[serde(rename = "type")]
    /// Type of the flock (stable, unstable or saddle).
    pub kind: Kind,
    /// Settled drops that ended in the flock.
    pub count: u64,
    /// Fraction of the settled drops with a known flock that ended in it.
    pub fraction: f64,
    /// 95 % Wilson interval of `fraction`.
    pub ci95: (f64, f64),
    /// Quasi-static resting probability of the flock (sum over its facets).
    pub static_probability: f64,
}

/// Goodness of fit of the drops against the static probabilities.
#[derive(Clone, Debug, Serialize)]
pub struct Fit {
    /// Pearson χ² statistic of the counts against the static probabilities.
    pub chi_square: f64,
    /// Degrees of freedom of the χ² test.
    pub dof: usize,
    /// p-value of the χ² test (NaN, `null` in JSON, when it has no degree of freedom: no drop
    /// came to rest, or all fell in one category).
    pub p_value: f64,
    /// Kullback–Leibler divergence D(empirical ‖ static) in nats.
    pub kl_divergence: f64,
}

/// The numbers of a drop run, read by the CLI, the plots and the experiments.
#[derive(Clone, Debug, Serialize)]
pub struct DropReport {
    /// The mesh file as given.
    pub mesh: String,
    /// Seed of the random streams of the drops.
    pub seed: u64,
    /// Drops asked for in the run.
    pub drops_requested: u64,
    /// Drops present in these results (all of them unless partial).
    pub drops: u64,
    /// Drops that came to rest (or were decided by the certificate).
    pub settled: u64,
    /// Drops still moving at the time cap: left out of every count, fraction and fit (a drop that
    /// has not come to rest has no resting position; assigning it the quasi-static descent from
    /// where it was would count a guess as an outcome).
    pub unsettled: u64,
    /// Settled drops that stopped above their stable facet by more than the contact tolerance
    /// ([`crate::dynamics::stone::REST_TOLERANCE`]): held on a slope by friction or rolling
    /// resistance. Their facet is the one the quasi-static descent reaches.
    pub off_equilibrium: u64,
    /// Drops ended by the energy certificate.
    pub certified: u64,
    /// The deepest any hull corner went below the ground after any step or sub-step of any drop
    /// of the run (R_max; [`crate::dynamics::engine::world::penetration`]).
    pub deepest_penetration: f64,
    /// Drops whose deepest penetration exceeded [`crate::dynamics::engine::impact::DEPTH_BOUND`].
    pub drops_beyond_depth_bound: u64,
    /// Mean simulated time per drop (s, scaled frame), whatever ended it.
    pub mean_time: f64,
    /// Mean simulated time to rest of the drops that came to rest without the certificate.
    pub mean_time_to_rest: Option<f64>,
    /// Mean simulated time to the certificate's decision of the certified drops.
    pub mean_time_to_decision: Option<f64>,
    /// Drops whose final facet is determined (settled and not ended by a flock-level
    /// certificate): the per-facet fractions are over these.
    pub facet_drops: u64,
    /// Simulation parameters of the drops.
    pub params: DropParams,
    /// The preset the parameters started from, if any.
    pub preset: Option<String>,
    /// The surface pair the contact started from, if known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<crate::dynamics::surface::Surface>,
    /// Whether and how the energy certificate may end a drop.
    pub certificate: CertificateMode,
    /// Resolution ν of the flocks.
    pub nu: f64,
    /// Facets that were reached or have a positive static probability (empty in flock-certified
    /// mode, where the certificate leaves facets undetermined).
    pub facets: Vec<FacetRow>,
    /// One row per flock.
    pub flocks: Vec<FlockRow>,
    /// χ² / KL of settled drops on stable facets against the static facet probabilities
    /// (None in flock-certificate mode, where facets are not decided).
    pub fit_facets: Option<Fit>,
    /// χ² / KL of the drops by flock against the static flock probabilities.
    pub fit_flocks: Fit,
}

impl DropReport {
    /// The row of flock `id`; None when the report has none (no drop settled in it and its
    /// static probability is 0).
    pub fn flock(&self, id: usize) -> Option<&FlockRow> {
        self.flocks.iter().find(|f| f.id == id)
    }

    /// The fraction of the settled drops (with a known flock) that ended in flock `id`; 0 when
    /// the report has no row for it.
    pub fn flock_fraction(&self, id: usize) -> f64 {
        self.flock(id).map_or(0.0, |f| f.fraction)
    }

    /// The settled drops that ended in flock `id`; 0 when the report has no row for it.
    pub fn flock_count(&self, id: usize) -> u64 {
        self.flock(id).map_or(0, |f| f.count)
    }

    /// The per-flock counts of flocks 0..`flocks` (by id), as the stone's `flock_kinds.len()`
    /// numbers them: the sample that two runs' homogeneity tests compare.
    pub fn flock_counts(&self, flocks: usize) -> Vec<u64> {
        (0..flocks).map(|k| self.flock_count(k)).collect()
    }

    /// The flocks' fractions and quasi-static probabilities summed over groups of flocks (flocks a
    /// symmetry of the stone makes equivalent, e.g. the two opposite faces of a box): entry g is
    /// (Σ fraction, Σ static probability) over the report's flocks f with `group(f)` = g, for
    /// g < `groups`; a flock whose group is not below `groups` is left out.
    pub fn pooled_flocks(&self, groups: usize, group: impl Fn(usize) -> usize) -> Vec<(f64, f64)> {
        let mut pooled = vec![(0.0, 0.0); groups];
        for f in &self.flocks {
            if let Some(p) = pooled.get_mut(group(f.id)) {
                *p = (p.0 + f.fraction, p.1 + f.static_probability);
            }
        }
        pooled
    }

    /// Flock `id`'s fraction with its 95 % interval as tables print it
    /// ([`FlockRow::fraction_with_ci`], `digits` decimals); "—" when the report has no row for it.
    pub fn flock_fraction_with_ci(&self, id: usize, digits: usize) -> String {
        self.flock(id).map_or("—".into(), |f| f.fraction_with_ci(digits))
    }
}

/// How far off their stable facet's normal the settled drops of a run came to rest: the median
/// (of an even count, the upper of the two middle values) and the largest
/// [`DropOutcome::height_above`] (R_max; 0 for a drop flat on its facet) of the settled outcomes
/// that have one; NaN for each when none has.
pub fn height_above_median_max(outcomes: &BTreeMap<u64, DropOutcome>) -> [f64; 2] {
    let mut h: Vec<f64> = outcomes.values().filter(|o| o.settled).filter_map(|o| o.height_above).collect();
    h.sort_by(f64::total_cmp);
    let at = |i: Option<usize>| i.and_then(|i| h.get(i)).map_or(f64::NAN, |x| *x);
    [at(Some(h.len() / 2)), at(h.len().checked_sub(1))]
}

impl FlockRow {
    /// "fraction [low, high]" of the flock's fraction and its 95 % interval, each with `digits`
    /// decimals, as tables print it.
    pub fn fraction_with_ci(&self, digits: usize) -> String {
        let (f, (lo, hi)) = (self.fraction, self.ci95);
        format!("{f:.digits$} [{lo:.digits$}, {hi:.digits$}]")
    }
}

/// Summarise the outcomes of a run (or a merged set of partial runs).
pub fn summarize(model: &StaticModel, header: &RunHeader, outcomes: &BTreeMap<u64, DropOutcome>) -> DropReport {
    let nf = model.facet_normals.len();
    let mut facet_counts = vec![0u64; nf];
    let mut flock_counts = vec![0u64; model.flock_kinds.len()];
    let (mut settled, mut unsettled, mut off, mut certified, mut time) = (0, 0, 0, 0, 0.0);
    let (mut rest_time, mut rested, mut decision_time) = (0.0, 0u64, 0.0);
    let (mut deepest, mut beyond) = (0.0f64, 0u64);
    for o in outcomes.values() {
        time += o.time;
        deepest = deepest.max(o.deepest_penetration);
        beyond += u64::from(o.deepest_penetration > crate::dynamics::engine::impact::DEPTH_BOUND);
        certified += u64::from(o.certified);
        if o.certified {
            decision_time += o.time;
        } else if o.settled {
            rest_time += o.time;
            rested += 1;
        }
        if !o.settled {
            unsettled += 1;
            continue;
        }
        settled += 1;
        off += u64::from(o.off_equilibrium());
        if let Some(f) = o.facet {
            facet_counts[f as usize] += 1;
        }
        if let Some(k) = o.flock_in(&model.facet_flock) {
            flock_counts[k] += 1;
        }
    }
    let flock_probability: Vec<f64> = (0..model.flock_kinds.len())
        .map(|k| (0..nf).filter(|&f| model.facet_flock[f] == Some(k)).map(|f| model.facet_probability[f]).sum())
        .collect();
    let n_facet: u64 = facet_counts.iter().sum();
    let facets_determined = header.certificate != CertificateMode::Flock;
    let facets = (0..nf)
        .filter(|&f| facets_determined && (facet_counts[f] > 0 || model.facet_probability[f] > 0.0))
        .map(|f| FacetRow {
            facet: f as u32,
            normal: model.facet_normals[f],
            equilibrium: model.facet_equilibrium[f],
            flock: model.facet_flock[f],
            count: facet_counts[f],
            fraction: if n_facet > 0 { facet_counts[f] as f64 / n_facet as f64 } else { 0.0 },
            ci95: wilson(facet_counts[f], n_facet, 1.96),
            static_probability: model.facet_probability[f],
        })
        .collect();
    let n_flock: u64 = flock_counts.iter().sum();
    let flocks = (0..model.flock_kinds.len())
        .filter(|&k| flock_counts[k] > 0 || flock_probability[k] > 0.0)
        .map(|k| FlockRow {
            id: k,
            kind: model.flock_kinds[k],
            count: flock_counts[k],
            fraction: if n_flock > 0 { flock_counts[k] as f64 / n_flock as f64 } else { 0.0 },
            ci95: wilson(flock_counts[k], n_flock, 1.96),
            static_probability: flock_probability[k],
        })
        .collect();
    // A test with no degrees of freedom (no drop, or one category) has no p-value (null in
    // JSON), and a divergence that rounds below zero is zero.
    let fit = |counts: &[u64], p: &[f64]| {
        let (chi_square, dof, p_value) = chi_square(counts, p);
        let kl = kl_divergence(counts, p);
        Fit {
            chi_square,
            dof,
            p_value: if dof > 0 { p_value } else { f64::NAN },
            kl_divergence: if kl > 0.0 { kl } else { 0.0 },
        }
    };
    let fit_facets = facets_determined.then(|| fit(&facet_counts, &model.facet_probability));
    let mean = |t: f64, n: u64| (n > 0).then(|| t / n as f64);
    DropReport {
        mesh: header.mesh.clone(),
        seed: header.seed,
        drops_requested: header.drops,
        drops: outcomes.len() as u64,
        settled,
        unsettled,
        off_equilibrium: off,
        certified,
        deepest_penetration: deepest,
        drops_beyond_depth_bound: beyond,
        mean_time: if outcomes.is_empty() { 0.0 } else { time / outcomes.len() as f64 },
        mean_time_to_rest: mean(rest_time, rested),
        mean_time_to_decision: mean(decision_time, certified),
        facet_drops: if facets_determined { n_facet } else { 0 },
        params: header.params.clone(),
        preset: header.preset.clone(),
        surface: header.surface,
        certificate: header.certificate,
        nu: model.nu,
        facets,
        flocks,
        fit_facets,
        fit_flocks: fit(&flock_counts, &flock_probability),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::drops::params::Preset;
    use crate::dynamics::surface::Surface;

    /// Three facets: 0 and 1 stable in flocks 0 and 1, 2 not stable; flock 2 unreachable.
    fn model() -> StaticModel {
        StaticModel {
            facet_normals: vec![Vec3::x(), Vec3::y(), Vec3::z()],
            facet_equilibrium: vec![Some(0), Some(1), None],
            facet_flock: vec![Some(0), Some(1), None],
            flock_kinds: vec![Kind::Stable; 3],
            facet_probability: vec![0.6, 0.4, 0.0],
            nu: 0.0,
        }
    }

    fn drop(index: u64, settled: bool, facet: u32) -> DropOutcome {
        DropOutcome { settled, ..DropOutcome::at_rest(index, facet, 1.0) }
    }

    #[test]
    fn a_report_reads_its_flocks_by_id() {
        // Three settled drops on facet 0, one on facet 1, one unsettled (left out).
        let outcomes: BTreeMap<u64, DropOutcome> =
            [(0, true, 0), (1, true, 0), (2, true, 1), (3, true, 0), (4, false, 1)]
                .map(|(i, s, f)| (i, drop(i, s, f)))
                .into();
        let params = Preset::Drop.params(Surface::SteelOnWood);
        let header = RunHeader::of_params("test", 1, 5, params, CertificateMode::None);
        let r = summarize(&model(), &header, &outcomes);
        assert_eq!((r.flock_count(0), r.flock_count(1), r.flock_count(2)), (3, 1, 0));
        assert_eq!((r.flock_fraction(0), r.flock_fraction(1), r.flock_fraction(2)), (0.75, 0.25, 0.0));
        assert!(r.flock(2).is_none() && r.flock(1).is_some_and(|f| f.id == 1));
        assert_eq!(r.flock_counts(3), vec![3, 1, 0]);
        let row = FlockRow { fraction: 0.25, ci95: (0.0456, 0.6994), ..r.flocks[1].clone() };
        assert_eq!(row.fraction_with_ci(3), "0.250 [0.046, 0.699]");
        // Wilson's interval of 3 in 4 at z = 1.96: (0.75 + z²/8 ± z √(3/64 + z²/64)) / (1 + z²/4).
        assert_eq!(r.flock_fraction_with_ci(0, 3), "0.750 [0.301, 0.954]");
        assert_eq!(r.flock_fraction_with_ci(2, 3), "—");
    }

    #[test]
    fn flocks_pool_by_group() {
        // Flocks 0 and 1 (0.75 and 0.25 of the drops, static 0.6 and 0.4); flock 2 has no row.
        let outcomes: BTreeMap<u64, DropOutcome> =
            [(0, 0), (1, 0), (2, 1), (3, 0)].map(|(i, f)| (i, drop(i, true, f))).into();
        let params = Preset::Drop.params(Surface::SteelOnWood);
        let r = summarize(&model(), &RunHeader::of_params("test", 1, 4, params, CertificateMode::None), &outcomes);
        assert_eq!(r.pooled_flocks(2, |_| 1), vec![(0.0, 0.0), (1.0, 1.0)]);
        assert_eq!(r.pooled_flocks(3, |k| 2 - k), vec![(0.0, 0.0), (0.25, 0.4), (0.75, 0.6)]);
        // Flock 1 in group 1, beyond the one group asked for.
        assert_eq!(r.pooled_flocks(1, |k| k), vec![(0.75, 0.6)]);
    }

    #[test]
    fn heights_above_the_facet_of_the_settled_drops() {
        let at =
            |i: u64, settled: bool, h: Option<f64>| (i, DropOutcome { height_above: h, settled, ..drop(i, true, 0) });
        // Settled with heights 0.3, 0.1, 0.2 and 0.4 (the median of four: the upper middle one);
        // unsettled (5.0) and certified (no height) drops are left out.
        let mut o: BTreeMap<u64, DropOutcome> =
            [at(0, true, Some(0.3)), at(1, true, Some(0.1)), at(2, false, Some(5.0)), at(3, true, None)].into();
        o.extend([at(4, true, Some(0.2)), at(5, true, Some(0.4))]);
        assert_eq!(height_above_median_max(&o), [0.3, 0.4]);
        o.remove(&5);
        assert_eq!(height_above_median_max(&o), [0.2, 0.3]);
        assert!(height_above_median_max(&BTreeMap::new()).iter().all(|x| x.is_nan()));
    }
}
