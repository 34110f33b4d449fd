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

pub mod base;
pub mod sensitivity;
mod triangle;
pub mod uncertainty;

pub use base::{BaseDraw, BaseSource, BaseUncertainty, HiddenBase};
pub use sensitivity::{circular_linear, sensitivities, spearman, Probability, Sensitivity};
pub use uncertainty::{draw, Draw, Uncertainty};

use crate::dynamics::shaking::rock::{place, shake_record, RockRun, RockSetup};
use crate::dynamics::stone::Stone;
use crate::ground_motion::{Record, ScaledRecord};
use crate::monitor::{self, Monitor};
use crate::tipping::{TippingPolar, TippingSummary};
use crate::{Error, Point3, Result, Vec3};
use serde::{Deserialize, Serialize};
use std::borrow::Cow;

/// One member: its inputs and its run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Member {
    /// The inputs it was run with.
    pub draw: Draw,
    /// Its outcome.
    pub run: RockRun,
}

/// The rock an ensemble or a batch runs: the scan's stone and, when its base is uncertain, every
/// member's own rock with its drawn base ([`member_rocks`]; member m is `members[m]`). A stone
/// alone (`&stone` into it) is a rock whose base is the scan's.
#[derive(Clone, Copy)]
pub struct FieldRock<'a> {
    /// The rock as scanned (the nominal closing of an open scan).
    pub stone: &'a Stone,
    /// Each member's own rock; empty when the base is not uncertain.
    pub members: &'a [MemberRock],
}

impl<'a> From<&'a Stone> for FieldRock<'a> {
    fn from(stone: &'a Stone) -> Self {
        FieldRock { stone, members: &[] }
    }
}

/// A member's own rock: its closed solid's stone, standing as the hidden base's frame stands
/// ([`Pose::AsScanned`]), and what its base drew.
#[derive(Clone)]
pub struct MemberRock {
    /// The member's stone (flocks at the scan's ν).
    pub stone: Stone,
    /// Its base.
    pub base: BaseDraw,
}

/// Every member's rock of an ensemble of `members` members (seed `seed`) drawing its base from
/// `u` on `hidden` ([`HiddenBase::member`]), its solids analysed with `opts` and flocks read at
/// `nu`, each put down with the runs' parameters `params` to check it stands, in parallel
/// (independent of the thread count).
pub fn member_rocks(
    hidden: &HiddenBase,
    u: &BaseUncertainty,
    seed: u64,
    members: u64,
    opts: &crate::analysis::Options,
    nu: f64,
    params: &crate::dynamics::resting::RestingParams,
) -> Result<Vec<MemberRock>> {
    use rayon::prelude::*;
    (0..members)
        .into_par_iter()
        .map(|m| hidden.member(u, seed, m, opts, nu, params).map(|(stone, base)| MemberRock { stone, base }))
        .collect()
}

/// Every member's own rock of the ensemble `spec` of the rock of `setup` (its stone `stone`, the
/// static analysis `analysis` of its scan with the options `opts`), as the command line and the
/// Python binding draw them: none when the base is not uncertain, else the scan's hidden base
/// ([`HiddenBase::of_scan`], a known centre of mass carried into its frame) closed anew by every
/// member ([`member_rocks`]).
pub fn field_members(
    analysis: &crate::analysis::Analysis,
    opts: &crate::analysis::Options,
    stone: &Stone,
    setup: &RockSetup,
    spec: &EnsembleSpec,
) -> Result<Vec<MemberRock>> {
    let Some(b) = spec.uncertainty.base else { return Ok(Vec::new()) };
    let band_m = b.band_for(setup.r_max_m);
    let hidden = HiddenBase::of_scan(analysis.scan_mesh(), &setup.pose, stone, band_m, setup.length_unit_m, &opts.rim)?;
    member_rocks(&hidden, &b, spec.seed, spec.members, &hidden.options(opts), stone.nu, &setup.params)
}

/// The facet the rock of `setup` stands on before any motion: the pose's facet, or the one the
/// quasi-static descent from its down direction reaches (what [`place`] requires).
pub fn base_facet(stone: &Stone, setup: &RockSetup) -> Result<u32> {
    facet_under(stone, &setup.pose)
}

/// The facet `stone` stands on in `pose` ([`base_facet`]).
fn facet_under(stone: &Stone, pose: &crate::dynamics::shaking::rock::Pose) -> Result<u32> {
    use crate::dynamics::shaking::rock::Pose;
    match pose.resolved(stone)? {
        Pose::Equilibrium { id } => {
            Ok(stone.stable()[stone.position(id).expect("a resolved pose names a stable micro-equilibrium")].facet)
        }
        pose => {
            let q = pose.orientation().ok_or_else(|| Error::check(format!("pose {pose} did not resolve")))?;
            Ok(stone.rest(&(q.inverse() * -Vec3::z())).facet)
        }
    }
}

/// Run member `member` of the ensemble `u` (seed `seed`) on `motion` (already scaled and
/// sampled for the run, [`crate::dynamics::shaking::rock::driven`]): the rock's base contact, contact and the
/// record's azimuth and sign as drawn; where an input is not uncertain, exactly the setup's
/// single run ([`crate::dynamics::shaking::records::run_record`]).
pub fn run_member<'a>(
    rock: impl Into<FieldRock<'a>>,
    setup: &RockSetup,
    motion: &Record,
    u: &Uncertainty,
    seed: u64,
    member: u64,
) -> Result<Member> {
    let field: FieldRock = rock.into();
    let own = field.members.get(member as usize);
    if u.base.is_some() && own.is_none() {
        return Err(Error::check(format!(
            "ensemble member {member}: the base is uncertain but no rock was drawn for it"
        )));
    }
    let d = Draw { base: own.map(|r| r.base), ..draw(u, setup, seed, member) };
    // A member's own rock stands as the hidden base's frame stands, with its own real size.
    let (stone, pose, r_max_m) = match own {
        Some(r) => {
            (&r.stone, crate::dynamics::shaking::rock::Pose::AsScanned, r.stone.body.r_max * setup.length_unit_m)
        }
        None => (field.stone, setup.pose, setup.r_max_m),
    };
    let mut p = setup.params.clone();
    if r_max_m != setup.r_max_m {
        p.sim.contact.rolling_resistance *= setup.r_max_m / r_max_m;
        p.sim.contact.torsional_friction *= setup.r_max_m / r_max_m;
    }
    if u.friction.is_some() {
        p.sim.contact.friction = d.friction;
    }
    if u.restitution.is_some() {
        p.sim.contact.restitution = d.restitution;
    }
    if u.rolling_resistance_m.is_some() {
        p.sim.contact.rolling_resistance = d.rolling_resistance_m / r_max_m;
        p.sim.contact.torsional_friction = d.rolling_resistance_m / r_max_m;
    }
    let rock: Cow<Stone> = match d.contact_tolerance_m > 0.0 {
        true => Cow::Owned(stone.with_base_contact(facet_under(stone, &pose)?, d.contact_tolerance_m / r_max_m)?),
        false => Cow::Borrowed(stone),
    };
    let motion: Cow<Record> = if d.sign < 0.0 { Cow::Owned(motion.scaled(-1.0)) } else { Cow::Borrowed(motion) };
    let azimuth = if u.azimuth_deg.is_some() { d.azimuth_deg.to_radians() } else { setup.azimuth };
    let placed = place(&rock, &pose, &p).map_err(|e| match e {
        Error::Pose { pose, what } => Error::Pose { pose, what: format!("ensemble member {member}: {what}") },
        e => e,
    })?;
    let run =
        RockRun { size_assumed: setup.size_assumed, ..shake_record(&rock, placed, &p, &motion, azimuth, r_max_m) };
    Ok(Member { draw: d, run })
}

/// One record × scale factor under an ensemble.
#[derive(Clone, Debug, Serialize)]
pub struct Ensemble {
    /// The record × scale factor and its intensity measures.
    #[serde(flatten)]
    pub motion: ScaledRecord,
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
    /// With a drawn base: the members' quasi-static tipping thresholds and depths.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub base: Option<BaseRange>,
    /// Every member, in member order.
    pub members: Vec<Member>,
}

/// Run the members of the ensemble `e` of the rock of `setup` under `record` × `scale`, in
/// parallel (rayon; each member is independent and deterministic, so the result does not depend
/// on the thread count); `monitor` hears of each finished member and may stop the run
/// ([`crate::monitor`]: the members not started are skipped, [`Error::Cancelled`]).
pub fn run_ensemble<'a>(
    rock: impl Into<FieldRock<'a>>,
    setup: &RockSetup,
    record: &Record,
    scale: f64,
    e: &EnsembleSpec,
    monitor: &dyn Monitor,
) -> Result<Ensemble> {
    use rayon::prelude::*;
    e.check()?;
    let field: FieldRock = rock.into();
    let (u, seed, n) = (&e.uncertainty, e.seed, e.members);
    let (m, motion) = crate::dynamics::shaking::rock::scaled_motion(record, scale, setup)?;
    let members: Vec<Option<Result<Member>>> = (0..n)
        .into_par_iter()
        .map(|k| monitor::item(monitor, || run_member(field, setup, &motion, u, seed, k)))
        .collect();
    let members: Vec<Member> = monitor::all(members)?.into_iter().collect::<Result<_>>()?;
    Ok(Ensemble {
        motion: ScaledRecord::of(record, scale, &m),
        size_assumed: setup.size_assumed,
        seed,
        uncertainty: u.clone(),
        probability: Probability::of(members.iter().map(|m| &m.run)),
        sensitivity: sensitivities(u, &members),
        tipping: quasi_static(field.stone, setup, u)?,
        base: BaseRange::of(&members),
        members,
    })
}

/// The quasi-static tipping threshold over an ensemble's drawn bases: what field practice quotes
/// from the rocking points, as a range over the members.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BaseRange {
    /// Members with a drawn base.
    pub members: usize,
    /// tan α (g) of the members: smallest, median, largest.
    pub tan_alpha: [f64; 3],
    /// Depth (m) of the members' supports below the rim: smallest, median, largest.
    pub depth_m: [f64; 3],
}

impl BaseRange {
    /// The range over `members`' drawn bases; None when none was drawn.
    pub fn of(members: &[Member]) -> Option<BaseRange> {
        BaseRange::of_draws(members.iter().filter_map(|m| m.draw.base).collect())
    }

    /// The range over the drawn bases `bases`; None when there are none.
    pub fn of_draws(bases: Vec<BaseDraw>) -> Option<BaseRange> {
        if bases.is_empty() {
            return None;
        }
        let three = |mut x: Vec<f64>| {
            x.sort_by(f64::total_cmp);
            [x[0], crate::stats::quantile(&x, 0.5), x[x.len() - 1]]
        };
        Some(BaseRange {
            members: bases.len(),
            tan_alpha: three(bases.iter().map(|b| b.tan_alpha).collect()),
            depth_m: three(bases.iter().map(|b| b.depth_m).collect()),
        })
    }
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
    use crate::dynamics::surface::Surface;

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
