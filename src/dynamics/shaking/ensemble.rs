//! How likely is a field rock to topple: an ensemble of runs over what is not known
//! about the rock, its pose and the record, instead of one yes or no.
//!
//! # The uncertain inputs ([`Uncertainty`])
//!
//! Each is a range [low, high] that every member draws from uniformly and independently, or
//! absent (`None`): then every member keeps the setup's value.
//!
//! * **Base contact** τ (metres): which scanned points of the base carry load. A scan resolves a
//!   few mm, and the ground under a rock is no flatter; a hull corner within τ of the plane of
//!   the facet the rock stands on may touch. The member's collider is the scanned hull with those
//!   corners moved onto that plane ([`crate::dynamics::engine::body::Body::flattened`]): its support
//!   polygon is exactly the quasi-static one of [`crate::tipping::TippingPolar`] at tolerance τ.
//!   The pose, the mass, G and the inertia are the scan's; only where it can be supported
//!   changes. τ = 0 is the scanned hull.
//! * **Azimuth** of the record's x axis (degrees, world frame): `[0, 360]` when unknown.
//! * **Sign** of the record: a one-component record's polarity, or which way a fault pulse
//!   points, is often not known; a member flips every component with probability ½.
//! * **Friction, restitution, rolling resistance** (δ in metres, also the torsional-friction
//!   length as in [`crate::dynamics::surface::Surface::scaled`]): by default the surface pair's
//!   ranges ([`crate::dynamics::surface::Surface::ranges`]).
//!
//! Member m draws its inputs from the stream (seed, m) in a fixed order, all six always drawn, so
//! a member is the same possible rock for every record, scale factor, thread count and ensemble
//! size (common random numbers: member m of a 64-member ensemble is member m of a 16-member one).
//!
//! # What it returns ([`Ensemble`])
//!
//! Every member's inputs and outcome; P(overturn) = k/n over the members that came to rest
//! (those still moving at the time cap are counted apart, as in the fragility fit), with its
//! Wilson 95 % interval; and per uncertain input its association with overturning
//! ([`Sensitivity`]): Spearman's rank correlation with the 0/1 outcome (average ranks for
//! ties), or for an azimuth that ranges over the whole circle Mardia's circular–linear
//! correlation R ∈ [0, 1] (Mardia 1976, Biometrika 63, 403; Fisher 1993, *Statistical analysis of
//! circular data* §6.2.3), since a rank of an angle has no meaning.
//!
//! # The one run to set beside it
//!
//! [`Uncertainty::nominal`]: every uncertain input at a central value (the middle of the base
//! contact's range, the surface pair's nominal contact), not the rock as given, which stands on
//! the scanned hull — the end of the base-contact range that tips most easily. How the ensemble's
//! P scores against both, on simulated truths, is in `results/ensemble_fragility/`.

use crate::dynamics::shaking::rock::{place, shake_record, RockRun, RockSetup};
use crate::dynamics::stone::Stone;
use crate::dynamics::surface::Surface;
use crate::ground_motion::Record;
use crate::monitor::{self, Monitor};
use crate::rng::item_rng;
use crate::stats::wilson;
use crate::tipping::{TippingPolar, TippingSummary};
use crate::{Error, Point3, Result, Vec3};
use rand::RngExt;
use serde::{Deserialize, Serialize};
use std::borrow::Cow;

/// What is not known about a field rock: ranges each member draws from (module docs). `None`:
/// the setup's value, in every member.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Uncertainty {
    /// Base-contact tolerance τ (metres): corners within τ of the base plane carry load.
    pub contact_tolerance_m: Option<[f64; 2]>,
    /// Azimuth of the record's x axis (degrees, world frame); `[0, 360]`: unknown.
    pub azimuth_deg: Option<[f64; 2]>,
    /// Each member flips the record's sign with probability ½.
    pub random_sign: bool,
    /// Coulomb friction coefficient.
    pub friction: Option<[f64; 2]>,
    /// Coefficient of restitution.
    pub restitution: Option<[f64; 2]>,
    /// Rolling-resistance (and torsional-friction) length δ (metres).
    pub rolling_resistance_m: Option<[f64; 2]>,
}

impl Uncertainty {
    /// The contact of `surface` uncertain within its ranges ([`Surface::ranges`]); the pose,
    /// azimuth and sign known.
    pub fn of_surface(surface: Surface) -> Uncertainty {
        let r = surface.ranges();
        Uncertainty {
            friction: Some(r.friction),
            restitution: Some(r.restitution),
            rolling_resistance_m: Some(r.rolling_resistance_m),
            ..Uncertainty::default()
        }
    }

    /// The uncertainty a user states (the command line's and Python's): `given` in the user's
    /// units — base-contact tolerance in the mesh's length unit (`length_unit_m` metres each),
    /// azimuth in degrees, δ in mm. Friction, restitution and δ not given range over
    /// `surface`'s ranges ([`Surface::ranges`]) unless `pinned` (the user set that value:
    /// friction, restitution, rolling resistance).
    pub fn stated(given: &Uncertainty, surface: Surface, length_unit_m: f64, pinned: [bool; 3]) -> Uncertainty {
        let r = surface.ranges();
        let or_surface = |x: Option<[f64; 2]>, pinned: bool, default: [f64; 2]| match x {
            Some(x) => Some(x),
            None if pinned => None,
            None => Some(default),
        };
        Uncertainty {
            contact_tolerance_m: given.contact_tolerance_m.map(|t| t.map(|x| x * length_unit_m)),
            azimuth_deg: given.azimuth_deg,
            random_sign: given.random_sign,
            friction: or_surface(given.friction, pinned[0], r.friction),
            restitution: or_surface(given.restitution, pinned[1], r.restitution),
            rolling_resistance_m: or_surface(
                given.rolling_resistance_m.map(|d| d.map(|x| x * 1e-3)),
                pinned[2],
                r.rolling_resistance_m,
            ),
        }
    }

    /// Every range ordered, finite and physical (friction ≥ 0, restitution in [0, 1], lengths
    /// ≥ 0); else a parameter error naming it.
    pub fn check(&self) -> Result<()> {
        let ranges = [
            ("contact_tolerance", self.contact_tolerance_m, 0.0, f64::INFINITY),
            ("azimuth", self.azimuth_deg, f64::NEG_INFINITY, f64::INFINITY),
            ("friction", self.friction, 0.0, f64::INFINITY),
            ("restitution", self.restitution, 0.0, 1.0),
            ("rolling_resistance", self.rolling_resistance_m, 0.0, f64::INFINITY),
        ];
        for (name, range, min, max) in ranges {
            if let Some([lo, hi]) = range {
                if !(lo.is_finite() && hi.is_finite() && lo <= hi && lo >= min && hi <= max) {
                    let expected = format!("a range LOW,HIGH with LOW ≤ HIGH inside [{min}, {max}]");
                    return Err(Error::parameter(name, format!("{lo},{hi}"), expected));
                }
            }
        }
        Ok(())
    }

    /// The nominal member of this uncertainty for the rock of `setup`, as an ensemble whose every
    /// member is that one rock: each uncertain input held at a central value, each range
    /// collapsed to that point ([`draw`] then returns it exactly). The single run to set beside the
    /// ensemble: the rock as given ([`crate::dynamics::shaking::records::run_record`]) stands on the scanned hull
    /// (τ = 0), an end of the base-contact range — the smallest support polygon the range allows,
    /// hence the rock most easily tipped — and so is an extreme member, not a typical one.
    ///
    /// * **Base contact** τ: the middle of its range. Nothing says which end the real base is
    ///   nearer; the middle is the median of the members' uniform draws.
    /// * **Azimuth**: the middle of a range; for the whole circle, the setup's azimuth (the
    ///   record as given). No direction is central on a circle: the middle of 0–360°, 180°, is
    ///   only the record turned round, no more typical than 0°.
    /// * **Sign**: + (the record as given): a sign has no middle.
    /// * **Friction, restitution, rolling resistance**: the setup's value (the surface pair's
    ///   published nominal contact) when it lies inside the range, else the middle of the range.
    ///   The pair's ranges ([`Surface::ranges`]) are the published spread about that value, and
    ///   δ's (½δ to 2δ) is centred on δ in ratio, so its arithmetic middle (1.25 δ) would not be
    ///   its centre; a range a user gives that leaves the value out has only its middle.
    ///
    /// An input that is not uncertain keeps the setup's value, as in every member.
    pub fn nominal(&self, setup: &RockSetup) -> Uncertainty {
        let given = draw(&Uncertainty::default(), setup, 0, 0);
        let middle = |[lo, hi]: [f64; 2]| 0.5 * (lo + hi);
        let central = |range: Option<[f64; 2]>, value: f64| {
            range.map(|[lo, hi]| {
                let x = if (lo..=hi).contains(&value) { value } else { middle([lo, hi]) };
                [x, x]
            })
        };
        Uncertainty {
            contact_tolerance_m: self.contact_tolerance_m.map(|r| [middle(r); 2]),
            azimuth_deg: match self.azimuth_unknown() {
                true => None,
                false => self.azimuth_deg.map(|r| [middle(r); 2]),
            },
            random_sign: false,
            friction: central(self.friction, given.friction),
            restitution: central(self.restitution, given.restitution),
            rolling_resistance_m: central(self.rolling_resistance_m, given.rolling_resistance_m),
        }
    }

    /// Whether the azimuth is unknown: it spans the whole circle.
    fn azimuth_unknown(&self) -> bool {
        self.azimuth_deg.is_some_and(|[lo, hi]| hi - lo >= 360.0)
    }
}

/// The inputs of one member (real units): the drawn values, or the setup's where the input is
/// not uncertain.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Draw {
    /// Member index: its random stream is (seed, member).
    pub member: u64,
    /// Base-contact tolerance τ (m).
    pub contact_tolerance_m: f64,
    /// Azimuth of the record's x axis (degrees).
    pub azimuth_deg: f64,
    /// +1 or −1: the record as given or with every component's sign flipped.
    pub sign: f64,
    /// Friction coefficient.
    pub friction: f64,
    /// Restitution.
    pub restitution: f64,
    /// Rolling-resistance length δ (m).
    pub rolling_resistance_m: f64,
}

/// Member `member`'s inputs for `setup` under `u`, from the stream (`seed`, `member`).
pub fn draw(u: &Uncertainty, setup: &RockSetup, seed: u64, member: u64) -> Draw {
    let mut rng = item_rng(seed, member);
    // Six uniforms in a fixed order, whichever inputs are uncertain (module docs).
    let x: [f64; 6] = std::array::from_fn(|_| rng.random_range(0.0..1.0));
    let pick = |range: Option<[f64; 2]>, x: f64, known: f64| range.map_or(known, |[lo, hi]| lo + (hi - lo) * x);
    let sim = &setup.params.sim;
    Draw {
        member,
        contact_tolerance_m: pick(u.contact_tolerance_m, x[0], 0.0),
        azimuth_deg: pick(u.azimuth_deg, x[1], setup.azimuth.to_degrees()),
        sign: if u.random_sign && x[2] < 0.5 { -1.0 } else { 1.0 },
        friction: pick(u.friction, x[3], sim.contact.friction),
        restitution: pick(u.restitution, x[4], sim.contact.restitution),
        rolling_resistance_m: pick(u.rolling_resistance_m, x[5], sim.contact.rolling_resistance * setup.r_max_m),
    }
}

/// One member: its inputs and its run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Member {
    /// The inputs it was run with.
    pub draw: Draw,
    /// Its outcome.
    pub run: RockRun,
}

/// The facet the rock of `setup` stands on before any motion: the pose's facet, or the one the
/// quasi-static descent from its down direction reaches (what [`place`] requires).
pub fn base_facet(stone: &Stone, setup: &RockSetup) -> Result<u32> {
    use crate::dynamics::shaking::rock::Pose;
    let q = match setup.pose {
        Pose::Facet { id } => {
            return stone.stable().iter().find(|s| s.index == id).map(|s| s.facet).ok_or_else(|| {
                Error::Usage(format!(
                    "facet:{id} is not the index of a stable micro-equilibrium{}",
                    stone.facet_hint(id)
                ))
            })
        }
        Pose::AsScanned => nalgebra::UnitQuaternion::identity(),
        Pose::Quat { q } => {
            nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]))
        }
    };
    Ok(stone.rest(&(q.inverse() * -Vec3::z())).facet)
}

/// Run member `member` of the ensemble `u` (seed `seed`) on `motion` (already scaled and
/// sampled for the run, [`crate::dynamics::shaking::rock::driven`]): the rock's base contact, contact and the
/// record's azimuth and sign as drawn; where an input is not uncertain, exactly the setup's
/// single run ([`crate::dynamics::shaking::records::run_record`]).
pub fn run_member(
    stone: &Stone,
    setup: &RockSetup,
    motion: &Record,
    u: &Uncertainty,
    seed: u64,
    member: u64,
) -> Result<Member> {
    let d = draw(u, setup, seed, member);
    let mut p = setup.params.clone();
    if u.friction.is_some() {
        p.sim.contact.friction = d.friction;
    }
    if u.restitution.is_some() {
        p.sim.contact.restitution = d.restitution;
    }
    if u.rolling_resistance_m.is_some() {
        p.sim.contact.rolling_resistance = d.rolling_resistance_m / setup.r_max_m;
        p.sim.contact.torsional_friction = d.rolling_resistance_m / setup.r_max_m;
    }
    let rock: Cow<Stone> = match d.contact_tolerance_m > 0.0 {
        true => Cow::Owned(stone.with_base_contact(base_facet(stone, setup)?, d.contact_tolerance_m / setup.r_max_m)?),
        false => Cow::Borrowed(stone),
    };
    let motion: Cow<Record> = if d.sign < 0.0 { Cow::Owned(motion.scaled(-1.0)) } else { Cow::Borrowed(motion) };
    let azimuth = if u.azimuth_deg.is_some() { d.azimuth_deg.to_radians() } else { setup.azimuth };
    let placed = place(&rock, &setup.pose, &p).map_err(|e| Error::Usage(format!("ensemble member {member}: {e}")))?;
    let run = RockRun {
        size_assumed: setup.size_assumed,
        ..shake_record(&rock, placed, &p, &motion, azimuth, setup.r_max_m)
    };
    Ok(Member { draw: d, run })
}

/// How strongly one uncertain input goes with overturning (module docs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sensitivity {
    /// The input (`contact_tolerance`, `azimuth`, `sign`, `friction`, `restitution`,
    /// `rolling_resistance`).
    pub input: String,
    /// `spearman` (rank correlation with the 0/1 outcome, in [−1, 1]) or `circular-linear`
    /// (Mardia's R, in [0, 1], for an azimuth over the whole circle).
    pub measure: String,
    /// The correlation; `None` when it is undefined (every member had the same outcome).
    pub correlation: Option<f64>,
}

/// P(overturn) of an ensemble with its interval.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Probability {
    /// Members run.
    pub members: usize,
    /// Members that came to rest before the time cap (the others are left out of P).
    pub settled: usize,
    /// Settled members that overturned.
    pub overturned: usize,
    /// overturned / settled (NaN-free: 0 when none settled, with the interval [0, 1]).
    pub p_overturn: f64,
    /// Wilson 95 % interval of P.
    pub interval95: [f64; 2],
}

impl Probability {
    /// P(overturn) over the settled runs of `runs`.
    pub fn of<'a>(runs: impl IntoIterator<Item = &'a RockRun>) -> Probability {
        let (mut members, mut settled, mut overturned) = (0, 0, 0);
        for r in runs {
            members += 1;
            settled += r.settled as usize;
            overturned += (r.settled && r.overturned) as usize;
        }
        let (lo, hi) = wilson(overturned as u64, settled as u64, 1.96);
        let p = if settled > 0 { overturned as f64 / settled as f64 } else { 0.0 };
        Probability { members, settled, overturned, p_overturn: p, interval95: [lo, hi] }
    }
}

/// The sensitivity of the outcome to every input that is uncertain in `u`, over the settled
/// members.
pub fn sensitivities(u: &Uncertainty, members: &[Member]) -> Vec<Sensitivity> {
    let settled: Vec<&Member> = members.iter().filter(|m| m.run.settled).collect();
    let y: Vec<f64> = settled.iter().map(|m| m.run.overturned as u8 as f64).collect();
    let column = |f: fn(&Draw) -> f64| settled.iter().map(|m| f(&m.draw)).collect::<Vec<f64>>();
    let rank = |input: &str, x: Vec<f64>| Sensitivity {
        input: input.into(),
        measure: "spearman".into(),
        correlation: spearman(&x, &y),
    };
    let mut out = Vec::new();
    if u.contact_tolerance_m.is_some() {
        out.push(rank("contact_tolerance", column(|d| d.contact_tolerance_m)));
    }
    if u.azimuth_unknown() {
        let theta = column(|d| d.azimuth_deg.to_radians());
        let r = circular_linear(&theta, &y);
        out.push(Sensitivity { input: "azimuth".into(), measure: "circular-linear".into(), correlation: r });
    } else if u.azimuth_deg.is_some() {
        out.push(rank("azimuth", column(|d| d.azimuth_deg)));
    }
    if u.random_sign {
        out.push(rank("sign", column(|d| d.sign)));
    }
    if u.friction.is_some() {
        out.push(rank("friction", column(|d| d.friction)));
    }
    if u.restitution.is_some() {
        out.push(rank("restitution", column(|d| d.restitution)));
    }
    if u.rolling_resistance_m.is_some() {
        out.push(rank("rolling_resistance", column(|d| d.rolling_resistance_m)));
    }
    out
}

/// Ranks from 1, ties given their average rank.
fn ranks(x: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..x.len()).collect();
    order.sort_by(|&a, &b| x[a].total_cmp(&x[b]));
    let mut r = vec![0.0; x.len()];
    let mut i = 0;
    while i < order.len() {
        let mut j = i;
        while j + 1 < order.len() && x[order[j + 1]] == x[order[i]] {
            j += 1;
        }
        let average = (i + j) as f64 / 2.0 + 1.0;
        for &k in &order[i..=j] {
            r[k] = average;
        }
        i = j + 1;
    }
    r
}

/// Pearson's correlation; `None` when either sample has no spread.
fn pearson(x: &[f64], y: &[f64]) -> Option<f64> {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    (sxx > 0.0 && syy > 0.0).then(|| (sxy / (sxx * syy).sqrt()).clamp(-1.0, 1.0))
}

/// Spearman's rank correlation (Pearson's on average ranks).
pub fn spearman(x: &[f64], y: &[f64]) -> Option<f64> {
    if x.len() != y.len() || x.len() < 2 {
        return None;
    }
    pearson(&ranks(x), &ranks(y))
}

/// Mardia's circular–linear correlation of a linear `y` with angles `theta` (rad):
/// R² = (r_yc² + r_ys² − 2 r_yc r_ys r_cs) / (1 − r_cs²), r the Pearson correlations of y, cos θ
/// and sin θ; R ∈ [0, 1].
pub fn circular_linear(theta: &[f64], y: &[f64]) -> Option<f64> {
    if theta.len() != y.len() || theta.len() < 3 {
        return None;
    }
    let c: Vec<f64> = theta.iter().map(|t| t.cos()).collect();
    let s: Vec<f64> = theta.iter().map(|t| t.sin()).collect();
    let (ryc, rys, rcs) = (pearson(y, &c)?, pearson(y, &s)?, pearson(&c, &s)?);
    let r2 = (ryc * ryc + rys * rys - 2.0 * ryc * rys * rcs) / (1.0 - rcs * rcs);
    r2.is_finite().then(|| r2.clamp(0.0, 1.0).sqrt())
}

/// One record × scale factor under an ensemble.
#[derive(Clone, Debug, Serialize)]
pub struct Ensemble {
    /// Name of the record.
    pub record: String,
    /// Scale factor applied to it.
    pub scale: f64,
    /// Peak horizontal ground acceleration of the scaled record (g).
    pub pga_g: f64,
    /// Peak horizontal ground velocity (m/s).
    pub pgv_m_s: f64,
    /// PGV/PGA (s).
    pub pgv_over_pga_s: f64,
    /// Peak vertical ground acceleration (g).
    pub pga_vertical_g: f64,
    /// Whether the rock's size was assumed ([`RockSetup::size_assumed`]; each member's run says
    /// its R_max).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub size_assumed: Option<bool>,
    /// Seed of the members' draws.
    pub seed: u64,
    /// What was uncertain.
    pub uncertainty: Uncertainty,
    /// P(overturn) with its interval.
    pub probability: Probability,
    /// How strongly each uncertain input goes with overturning.
    pub sensitivity: Vec<Sensitivity>,
    /// The quasi-static tipping polar of the pose at base-contact tolerance 0 and at the ends of
    /// its range ([`quasi_static`]).
    pub tipping: Vec<TippingSummary>,
    /// Every member, in member order.
    pub members: Vec<Member>,
}

/// Run the members of the ensemble `e` of the rock of `setup` under `record` × `scale`, in
/// parallel (rayon; each member is independent and deterministic, so the result does not depend
/// on the thread count); `monitor` hears of each finished member and may stop the run
/// ([`crate::monitor`]: the members not started are skipped, [`Error::Cancelled`]).
pub fn run_ensemble(
    stone: &Stone,
    setup: &RockSetup,
    record: &Record,
    scale: f64,
    e: &EnsembleSpec,
    monitor: &dyn Monitor,
) -> Result<Ensemble> {
    use rayon::prelude::*;
    e.check()?;
    let (u, seed, n) = (&e.uncertainty, e.seed, e.members);
    let (m, motion) = crate::dynamics::shaking::rock::scaled_motion(record, scale, setup)?;
    let members: Vec<Option<Result<Member>>> = (0..n)
        .into_par_iter()
        .map(|k| monitor::item(monitor, || run_member(stone, setup, &motion, u, seed, k)))
        .collect();
    let members: Vec<Member> = monitor::all(members)?.into_iter().collect::<Result<_>>()?;
    Ok(Ensemble {
        record: record.name.clone(),
        scale,
        pga_g: m.pga_g,
        pgv_m_s: m.pgv_m_s,
        pgv_over_pga_s: m.pgv_over_pga_s,
        pga_vertical_g: m.pga_vertical_g,
        size_assumed: setup.size_assumed,
        seed,
        uncertainty: u.clone(),
        probability: Probability::of(members.iter().map(|m| &m.run)),
        sensitivity: sensitivities(u, &members),
        tipping: quasi_static(stone, setup, u)?,
        members,
    })
}

/// The quasi-static side of the rock of `setup`: its support polygon and
/// tipping acceleration tan α against azimuth ([`crate::tipping`]) on the facet it stands on
/// ([`base_facet`]), at base-contact tolerance 0 and at each end of `u`'s range.
pub fn quasi_static(stone: &Stone, setup: &RockSetup, u: &Uncertainty) -> Result<Vec<TippingSummary>> {
    let facet = base_facet(stone, setup)?;
    let down = stone.body.facet_normals[facet as usize];
    let corners: Vec<Point3> = stone.body.corners.iter().map(|c| Point3::from(c * stone.body.r_max)).collect();
    let mut tolerances_m = vec![0.0];
    for t in u.contact_tolerance_m.into_iter().flatten() {
        if !tolerances_m.contains(&t) {
            tolerances_m.push(t);
        }
    }
    let unit = setup.length_unit_m;
    tolerances_m
        .iter()
        .map(|&t| Ok(TippingPolar::new(&corners, &Point3::origin(), &down, t / unit)?.summary(t, unit)))
        .collect()
}

/// An ensemble as a batch runs it: what is uncertain, the seed of the draws and the number of
/// members run for every record × scale factor.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EnsembleSpec {
    /// What is uncertain.
    pub uncertainty: Uncertainty,
    /// Seed of the members' draws.
    pub seed: u64,
    /// Members per record × scale factor (≥ 1).
    pub members: u64,
}

impl EnsembleSpec {
    /// The nominal member of this ensemble ([`Uncertainty::nominal`]) as an ensemble of one:
    /// member 0, with the same seed.
    pub fn nominal(&self, setup: &RockSetup) -> EnsembleSpec {
        EnsembleSpec { uncertainty: self.uncertainty.nominal(setup), seed: self.seed, members: 1 }
    }

    /// The ranges are valid and there is at least one member.
    pub fn check(&self) -> Result<()> {
        if self.members == 0 {
            return Err(Error::parameter("ensemble", 0, "at least one member"));
        }
        self.uncertainty.check()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spearman_and_mardia_match_hand_values() {
        // Perfectly monotone, and with ties: average ranks.
        assert!(
            (spearman(&[1.0, 2.0, 3.0, 4.0], &[0.0, 0.0, 1.0, 1.0]).unwrap() - 0.894_427_190_999_915_9).abs() < 1e-12
        );
        assert_eq!(ranks(&[3.0, 1.0, 3.0, 2.0]), vec![3.5, 1.0, 3.5, 2.0]);
        assert_eq!(spearman(&[1.0, 2.0, 3.0], &[1.0, 1.0, 1.0]), None);
        // y = cos θ exactly: R = 1; y independent of a symmetric set of angles: R = 0.
        let theta: Vec<f64> = (0..36).map(|k| k as f64 * 10f64.to_radians()).collect();
        let y: Vec<f64> = theta.iter().map(|t| t.cos()).collect();
        assert!((circular_linear(&theta, &y).unwrap() - 1.0).abs() < 1e-12);
        let flat: Vec<f64> = theta.iter().enumerate().map(|(k, _)| (k % 2) as f64).collect();
        assert!(circular_linear(&theta, &flat).unwrap() < 0.05);
    }

    #[test]
    fn the_nominal_member_is_central_on_every_input() {
        use crate::dynamics::shaking::rock::{rock_params, Pose};
        let r_max_m = 0.13;
        let params = rock_params(Surface::RockOnConcrete, r_max_m).unwrap();
        let setup =
            RockSetup { pose: Pose::AsScanned, length_unit_m: 1.0, r_max_m, azimuth: 0.3, params, size_assumed: None };
        let field = Uncertainty {
            contact_tolerance_m: Some([0.0, 0.002]),
            azimuth_deg: Some([0.0, 360.0]),
            random_sign: true,
            ..Uncertainty::of_surface(Surface::RockOnConcrete)
        };
        let n = field.nominal(&setup);
        n.check().unwrap();
        // Every member of the nominal ensemble is the same rock, whatever its stream.
        let d = draw(&n, &setup, 24, 0);
        assert_eq!(Draw { member: 0, ..draw(&n, &setup, 7, 5) }, d);
        assert_eq!(d.contact_tolerance_m, 0.001);
        assert_eq!((d.azimuth_deg, d.sign), (0.3f64.to_degrees(), 1.0));
        // Rock on concrete: μ 0.6 in [0.5, 0.7], e 0.3 in [0.2, 0.5], δ 0.1 mm in [0.05, 0.2] mm.
        assert_eq!((d.friction, d.restitution), (0.6, 0.3));
        assert!((d.rolling_resistance_m - 1e-4).abs() < 1e-15, "{}", d.rolling_resistance_m);
        // A partial azimuth range and ranges that leave the pair's value out: their middles.
        let user = Uncertainty {
            azimuth_deg: Some([10.0, 50.0]),
            friction: Some([0.3, 0.5]),
            restitution: Some([0.4, 0.6]),
            ..Uncertainty::default()
        };
        let d = draw(&user.nominal(&setup), &setup, 24, 0);
        assert_eq!((d.azimuth_deg, d.friction, d.restitution), (30.0, 0.4, 0.5));
        // Inputs that are not uncertain stay the setup's.
        assert_eq!(
            (d.contact_tolerance_m, d.rolling_resistance_m),
            (0.0, setup.params.sim.contact.rolling_resistance * r_max_m)
        );
    }

    #[test]
    fn ranges_are_checked_with_their_name() {
        let bad = Uncertainty { restitution: Some([0.2, 1.5]), ..Uncertainty::default() };
        match bad.check().unwrap_err() {
            Error::Parameter { name, .. } => assert_eq!(name, "restitution"),
            e => panic!("{e}"),
        }
        let reversed = Uncertainty { friction: Some([0.7, 0.5]), ..Uncertainty::default() };
        assert!(reversed.check().is_err());
        Uncertainty::of_surface(Surface::RockOnConcrete).check().unwrap();
    }
}
