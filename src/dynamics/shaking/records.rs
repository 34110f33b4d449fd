//! Records × scale factors on one field rock, with or without an ensemble over what is
//! not known about it ([`crate::dynamics::shaking::ensemble`]): every run, the fragility surface
//! P(overturn | PGA, PGV/PGA) fitted to the runs that came to rest (the others are counted), and
//! with an ensemble P(overturn) per record × scale and the surface's contours with their bands.

use crate::dynamics::shaking::ensemble::{
    run_member, sensitivities, Draw, EnsembleSpec, FieldRock, Member, Probability, Sensitivity,
};
use crate::dynamics::shaking::rock::{place, scaled_motion, shake_record, RockRun, RockSetup};
use crate::dynamics::stone::Stone;
use crate::ground_motion::fragility::{self, FragilitySurface};
use crate::ground_motion::{Measures, Record, ScaledRecord};
use crate::{Error, Result};
use serde::Serialize;

/// One record × scale factor on a field rock: the record's intensity measures and the outcome.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct RecordRun {
    /// The record × scale factor and its intensity measures.
    #[serde(flatten)]
    pub motion: ScaledRecord,
    /// In an ensemble ([`crate::dynamics::shaking::ensemble`]): the member's inputs; none for the rock as given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub member: Option<Draw>,
    /// Outcome of the run.
    #[serde(flatten)]
    pub rock: RockRun,
}

/// Shake the rock of `setup` with `record` × `scale`: the record is scaled, its PGA/PGV measured
/// ([`Record::measures`], on the record as given: correct its baseline
/// before), resampled without aliasing to the simulation's real step ([`RockSetup::real_dt`]) when
/// it is sampled finer, the rock placed ([`place`]) and shaken ([`shake_record`]).
pub fn run_record(stone: &Stone, setup: &RockSetup, record: &Record, scale: f64) -> Result<RecordRun> {
    let (m, motion) = scaled_motion(record, scale, setup)?;
    let placed = place(stone, &setup.pose, &setup.params)?;
    let rock = shake_record(stone, placed, &setup.params, &motion, setup.azimuth, setup.r_max_m);
    Ok(RecordRun::of(record, scale, &m, None, RockRun { size_assumed: setup.size_assumed, ..rock }))
}

/// Member `member` of the ensemble `ensemble` on `record` × `scale` ([`run_member`]), as a run of
/// a batch.
pub fn run_record_member(
    rock: FieldRock,
    setup: &RockSetup,
    record: &Record,
    scale: f64,
    ensemble: &EnsembleSpec,
    member: u64,
) -> Result<RecordRun> {
    let (m, motion) = scaled_motion(record, scale, setup)?;
    let Member { draw, run } = run_member(rock, setup, &motion, &ensemble.uncertainty, ensemble.seed, member)?;
    Ok(RecordRun::of(record, scale, &m, Some(draw), run))
}

impl RecordRun {
    /// The run of `record` × `scale` (measures `m`) that ended in `rock`.
    fn of(record: &Record, scale: f64, m: &Measures, member: Option<Draw>, rock: RockRun) -> RecordRun {
        RecordRun { motion: ScaledRecord::of(record, scale, m), member, rock }
    }
}

/// Every record × every scale factor on one rock, with the fragility surface fitted to them.
#[derive(Clone, Debug, Serialize)]
pub struct ShakeBatch {
    /// The rock and how it was shaken.
    pub setup: RockSetup,
    /// Settling tilt (degrees) when the rock was put down.
    pub settling_tilt_deg: f64,
    /// Analysis index of the stable micro-equilibrium it stands on.
    pub start_equilibrium: usize,
    /// One run per (record, scale), records in the given order, scales within a record.
    pub runs: Vec<RecordRun>,
    /// P(overturn | PGA, PGV/PGA) fitted to the runs that came to rest ([`crate::ground_motion::fragility`]); runs
    /// still moving at the time cap are left out and counted in `unsettled`.
    pub surface: Option<fragility::FragilitySurface>,
    /// Why the surface could not be fitted (e.g. every run had the same outcome).
    pub surface_error: Option<String>,
    /// Runs still moving at the time cap: classified by the quasi-static descent in `runs`, but
    /// not used in the fit (their outcome is a guess, not an observation).
    pub unsettled: usize,
    /// With an ensemble: what was uncertain, the seed and the members per record × scale.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ensemble: Option<EnsembleSpec>,
    /// With an ensemble: P(overturn) and the sensitivities of every record × scale.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub probabilities: Vec<EnsembleSummary>,
    /// With an ensemble and a fitted surface: the contours P = 0.1, 0.5, 0.9 with their 95 %
    /// bands ([`contours`]).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub contours: Vec<Contour>,
    /// The quasi-static tipping polar of the pose (at tolerance 0, and at the ends of an
    /// ensemble's base-contact range).
    pub tipping: Vec<crate::tipping::TippingSummary>,
    /// With a drawn base: the members' tan α and support depth, smallest, median, largest.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<crate::dynamics::shaking::ensemble::BaseRange>,
}

/// The fragility surface of `runs`, fitted to the runs that came to rest (the others' outcome is
/// the quasi-static descent's guess from where they were at the time cap, not an observation):
/// the surface, or why it could not be fitted, and how many runs were left out.
pub fn fit_surface(runs: &[RecordRun]) -> (Option<fragility::FragilitySurface>, Option<String>, usize) {
    let unsettled = runs.iter().filter(|r| !r.rock.settled).count();
    let points: Vec<fragility::Run> =
        runs.iter().filter(|r| r.rock.settled).map(|r| fragility::Run::of(&r.motion, r.rock.overturned)).collect();
    match fragility::FragilitySurface::fit(&points) {
        Ok(s) => (Some(s), None, unsettled),
        Err(e) => (None, Some(e.to_string()), unsettled),
    }
}

/// Run every record × scale in parallel (rayon; each run is deterministic and independent, so the
/// result does not depend on the thread count), calling `done` with each finished run (from any
/// thread, in completion order: for appending to a file as the runs finish). The pose is checked
/// once before any run. Runs already in `previous` (same record name, scale and member, from an
/// interrupted batch) are taken as they are and not run again: a run is a deterministic function
/// of the rock, the setup, the record, the scale and the member, so the batch is the same as one
/// run in one go. With `ensemble`, every record × scale is run for each of its members
/// ([`crate::dynamics::shaking::ensemble`]), and the surface is fitted to all of them.
pub fn run_batch<'a>(
    rock: impl Into<FieldRock<'a>>,
    setup: &RockSetup,
    records: &[Record],
    scales: &[f64],
    ensemble: Option<&EnsembleSpec>,
    previous: &[RecordRun],
    done: &(dyn Fn(&RecordRun) + Sync),
) -> Result<ShakeBatch> {
    use rayon::prelude::*;
    if records.is_empty() || scales.is_empty() {
        return Err(Error::parameter("scales", "none", "at least one record and one scale factor"));
    }
    if let Some(e) = ensemble {
        e.check()?;
    }
    let rock: FieldRock = rock.into();
    let stone = rock.stone;
    let placed = place(stone, &setup.pose, &setup.params)?;
    let s = &stone.stable()[placed.start];
    let (settling_tilt_deg, start_equilibrium) = (placed.settling_tilt.to_degrees(), s.index);
    drop(placed);
    let members: Vec<Option<u64>> = match ensemble {
        Some(e) => (0..e.members).map(Some).collect(),
        None => vec![None],
    };
    let mut jobs: Vec<(usize, f64, Option<u64>)> = Vec::new();
    for r in 0..records.len() {
        for &k in scales {
            jobs.extend(members.iter().map(|&m| (r, k, m)));
        }
    }
    let runs: Vec<RecordRun> = jobs
        .par_iter()
        .map(|&(r, k, m)| {
            let same = |p: &&RecordRun| {
                p.motion.record == records[r].name
                    && p.motion.scale.to_bits() == k.to_bits()
                    && p.member.map(|d| d.member) == m
            };
            if let Some(p) = previous.iter().find(same) {
                return Ok(p.clone());
            }
            let run = match (ensemble, m) {
                (Some(e), Some(m)) => run_record_member(rock, setup, &records[r], k, e, m)?,
                _ => run_record(stone, setup, &records[r], k)?,
            };
            done(&run);
            Ok(run)
        })
        .collect::<Result<_>>()?;
    let (surface, surface_error, unsettled) = fit_surface(&runs);
    let (probabilities, contours) = match ensemble {
        Some(e) => (summaries(e, &runs), surface.as_ref().map_or_else(Vec::new, |f| contours(f, &runs))),
        None => (Vec::new(), Vec::new()),
    };
    Ok(ShakeBatch {
        setup: setup.clone(),
        settling_tilt_deg,
        start_equilibrium,
        runs,
        surface,
        surface_error,
        unsettled,
        ensemble: ensemble.cloned(),
        probabilities,
        contours,
        tipping: crate::dynamics::shaking::ensemble::quasi_static(
            stone,
            setup,
            &ensemble.map_or_else(Default::default, |e| e.uncertainty.clone()),
        )?,
        base: crate::dynamics::shaking::ensemble::BaseRange::of_draws(rock.members.iter().map(|m| m.base).collect()),
    })
}

/// P(overturn) of one record × scale factor of an ensemble batch.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EnsembleSummary {
    /// Name of the record.
    pub record: String,
    /// Scale factor.
    pub scale: f64,
    /// PGA of the scaled record (g).
    pub pga_g: f64,
    /// PGV/PGA (s).
    pub pgv_over_pga_s: f64,
    /// P(overturn) over its members, with its interval.
    pub probability: Probability,
    /// How strongly each uncertain input goes with overturning.
    pub sensitivity: Vec<Sensitivity>,
}

/// The summaries of every record × scale of an ensemble batch's `runs`, in their order.
pub fn summaries(e: &EnsembleSpec, runs: &[RecordRun]) -> Vec<EnsembleSummary> {
    let mut out: Vec<EnsembleSummary> = Vec::new();
    for group in runs.chunk_by(|a, b| a.motion.same_as(&b.motion)) {
        let members: Vec<Member> =
            group.iter().filter_map(|r| r.member.map(|draw| Member { draw, run: r.rock.clone() })).collect();
        out.push(EnsembleSummary {
            record: group[0].motion.record.clone(),
            scale: group[0].motion.scale,
            pga_g: group[0].motion.pga_g,
            pgv_over_pga_s: group[0].motion.pgv_over_pga_s,
            probability: Probability::of(group.iter().map(|r| &r.rock)),
            sensitivity: sensitivities(&e.uncertainty, &members),
        });
    }
    out
}

/// A point of a contour P(overturn) = p of a fitted surface, with its 95 % band
/// ([`FragilitySurface::pga_band_at`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Contour {
    /// The probability of the contour.
    pub p: f64,
    /// PGV/PGA (s).
    pub pgv_over_pga_s: f64,
    /// PGA (g) on the contour; none when the surface does not rise with PGA.
    pub pga_g: Option<f64>,
    /// PGA where the band's upper edge reaches p (the band's low side), and where its lower
    /// edge does (high side), g; none where an edge does not reach p within e^±6 of the contour.
    pub band95: [Option<f64>; 2],
}

/// The contours P = 0.1, 0.5 and 0.9 of `surface` at nine PGV/PGA log-spaced over the range of
/// `runs`.
pub fn contours(surface: &FragilitySurface, runs: &[RecordRun]) -> Vec<Contour> {
    let ratios = runs.iter().map(|r| r.motion.pgv_over_pga_s).filter(|r| *r > 0.0 && r.is_finite());
    let (lo, hi) = crate::stats::nonnegative_range(ratios);
    if !(lo <= hi) {
        return Vec::new();
    }
    let mut out = Vec::new();
    for p in [0.1, 0.5, 0.9] {
        for k in 0..9 {
            let ratio = lo * (hi / lo).powf(k as f64 / 8.0);
            let band = surface.pga_band_at(p, ratio, 1.96);
            out.push(Contour {
                p,
                pgv_over_pga_s: ratio,
                pga_g: surface.pga_at(p, ratio),
                band95: band.map_or([None, None], |[a, _, b]| [a, b]),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::resting::outcome::Outcome;

    fn run(pga_g: f64, ratio: f64, overturned: bool, settled: bool) -> RecordRun {
        RecordRun {
            motion: ScaledRecord {
                record: format!("r{pga_g}-{ratio}"),
                scale: 1.0,
                pga_g,
                pgv_m_s: pga_g * ratio * 9.81,
                pgv_over_pga_s: ratio,
                pga_vertical_g: 0.0,
                pgv_source: Default::default(),
            },
            member: None,
            rock: RockRun {
                overturned,
                outcome: if overturned { Outcome::Toppled } else { Outcome::Same },
                max_tilt_deg: 0.0,
                slide_m: 0.0,
                settling_tilt_deg: 0.0,
                start_equilibrium: 0,
                start_flock: 0,
                final_equilibrium: 0,
                final_flock: 0,
                settled,
                azimuth_deg: 0.0,
                surface: None,
                r_max_m: 1.0,
                size_assumed: None,
                time_s: 1.0,
                steps: 1,
                deepest_penetration: 0.0,
            },
        }
    }

    /// Runs still moving at the cap do not enter the fit: adding unsettled runs that claim the
    /// opposite outcome changes nothing but the count.
    #[test]
    fn the_fragility_fit_uses_settled_runs_only() {
        let mut settled = Vec::new();
        for (i, a) in [0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0].iter().enumerate() {
            for (j, t) in [0.05, 0.1, 0.2].iter().enumerate() {
                settled.push(run(*a, *t, a * t.sqrt() > 0.1 || (i + j) % 5 == 0, true));
            }
        }
        let (alone, _, none) = fit_surface(&settled);
        assert_eq!(none, 0);
        let mut all = settled.clone();
        all.extend([run(0.1, 0.05, true, false), run(1.0, 0.2, false, false), run(0.12, 0.06, true, false)]);
        let (with, _, three) = fit_surface(&all);
        assert_eq!(three, 3);
        assert_eq!(alone.unwrap().beta, with.unwrap().beta);
        // The same runs counted as settled would move the fit: the check is not vacuous.
        let counted: Vec<RecordRun> = all
            .iter()
            .cloned()
            .map(|mut r| {
                r.rock.settled = true;
                r
            })
            .collect();
        assert_ne!(fit_surface(&settled).0.unwrap().beta, fit_surface(&counted).0.unwrap().beta);
    }
}
