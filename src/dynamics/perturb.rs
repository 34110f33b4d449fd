//! Perturbation robustness of stable micro-equilibria (paper §3, §4.1 and Figure 11; SPEC §6–7).
//!
//! A stone is put **exactly at rest** on one stable micro-equilibrium — its facet F on the
//! ground (the orientation maps F's outward normal to −z, with no turn about the vertical), G at
//! height R_F above the ground, zero velocity — and left to settle for
//! [`PerturbParams::settle_time`] so that the soft contacts take their load. It is then
//! perturbed with a kinetic energy of dimensionless magnitude
//!
//! ```text
//! ε = kinetic energy / (m g R_max)
//! ```
//!
//! and simulated to rest (the project's [`RestDetector`], with a time cap; a stone still moving
//! at the cap, or at rest on a facet that is not stable, is classified by the quasi-static descent
//! from its last down direction and counted). The outcome is one of
//! [`Outcome::Same`] (back on F), [`Outcome::SameFlock`] (rocked onto another stable
//! micro-equilibrium of F's flock) or [`Outcome::Toppled`] (left the flock), with the final
//! facet, equilibrium and flock ("where to").
//!
//! Before any trial, [`check_rest`] holds the stone on the equilibrium for
//! `settle_time + hold_time` without perturbation. Equilibria whose G is too close to the edge of
//! a tiny facet for the soft contact (see [`PerturbParams::contact_frequency`]) tip off by
//! themselves; they are reported as not staying at rest and get no curve.
//!
//! With [`PerturbParams::certificate`] a trial ends as soon as the merge-tree certificate of
//! [`crate::montecarlo`] (energy level plus its margin) decides the final facet, or a flock other
//! than the start's; on the bundled stone this gives the same outcomes 1.75× faster.
//!
//! # Perturbation families ([`Family`])
//!
//! * **push**: an instantaneous impulse J at a point X of the hull surface, X uniform by area
//!   over the surface minus the resting facet, the direction uniform on the hemisphere pointing
//!   into the body at X. With r = X − G and unit direction u, the kick is Δv = J u / m,
//!   Δω = J I⁻¹(r × u), so its energy is ½ J² (1/m + (r × u)·I⁻¹(r × u)) and J is solved for ε.
//!   The part of a push that points into the ground is absorbed by the contact at once, as a
//!   real push would be: ε is the energy *given*, an upper bound on the energy that moves the
//!   stone.
//! * **spin**: an angular-velocity kick ω about a uniformly random axis through the contact point
//!   P (the stable point, below G), v_G = ω × (G − P): the stone starts to rock about its contact,
//!   with energy ½ ω·I_P ω (I_P the inertia about P).
//!
//! Trial k of equilibrium i uses the random stream [`item_rng`]`(seed, stream)` with
//! stream = (family bit, i, k) (see [`stream_index`]), and the same stream at every ε (common
//! random numbers: trial k pushes at the same point in the same direction at every ε, only
//! harder), so the curves are smooth in ε, and results are independent of threads.
//!
//! # The static barriers beside them
//!
//! A passive body never gains energy, and z_G ≥ h(down) (the support function), so a body with
//! energy level L = z_G + KE/(m g) can only reach the stable facets of its component of the
//! sublevel set {h ≤ L} ([`crate::basins`]). With L = R_F + ε R_max:
//!
//! * **leaving the micro-equilibrium** needs ε > ε_basin = (U_F − R_F)/R_max with U_F
//!   = [`MergeTree::unique_level`] (the lowest level at which F's component holds another
//!   stable facet), the cheapest way out being the stable facet it is joined to there;
//! * **leaving the flock** needs ε > ε_flock = (min over stable facets F' of other flocks of the
//!   merge level of F and F' − R_F)/R_max ([`MergeTree::entry_barrier`]).
//!
//! Both are m g ΔR barriers of the static landscape: h at a saddle minus R_F. The dynamic
//! thresholds ε₅₀ (the ε at which half of the trials leave, interpolated linearly in P against
//! log ε between grid points, [`Threshold`]) sit above them because part of the energy goes
//! into motion that does not climb (spin about the vertical, sliding, the wrong direction) and
//! into impacts. [`BarrierCheck`] verifies that no trial below a static barrier crossed it.
//!
//! # Rocking vs regular, dynamically
//!
//! A stable micro-equilibrium is **dynamically rocking** if it topples out of its flock at small
//! energy: ε₅₀(flock) ≤ ε*, with ε* = the macro-scale ν by default — the energy m g ν R_max is the
//! resolution of the hand experimenter of the paper, who cannot tell micro-equilibria within ν
//! apart; a stone that leaves its flock for less is one that "even a small force" dislodges.
//! It is **dynamically regular** if ε₅₀(flock) > ε*. The static class is the paper's (stable
//! micro-equilibrium in a stable flock = regular, in an unstable or saddle flock = rocking,
//! [`crate::hierarchy::Hierarchy::rocking_at`]); [`Confusion`] compares the two.

use super::params::DropParams;
use super::run::{self as run_loop, Certificate, CertificateMode, Decided, EnergyCertificate, Passive};
pub use super::stone::{resting_orientation, Class, Exit, StableEquilibrium, Stone};
use super::world::Simulation;
pub use super::world::GRAVITY;
use crate::equilibria::Kind;
use crate::plot::{init_fonts, FONT_FAMILY};
use crate::rng::{item_rng, random_unit, Stream};
use crate::stats::wilson;
use crate::{Error, Result, Vec3};
use nalgebra::{Matrix3, UnitQuaternion};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Default natural frequency (Hz) of the contacts of resting runs; see
/// [`PerturbParams::contact_frequency`].
pub const CONTACT_FREQUENCY: f64 = 120.0;

/// How a resting stone is perturbed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Family {
    /// Impulsive push at a random point of the surface in a random inward direction.
    Push,
    /// Angular-velocity kick about a random axis through the contact point.
    Spin,
}

impl Family {
    /// The user-facing name.
    pub fn name(self) -> &'static str {
        match self {
            Family::Push => "push",
            Family::Spin => "spin",
        }
    }
}

impl std::str::FromStr for Family {
    type Err = Error;
    fn from_str(s: &str) -> Result<Family> {
        match s {
            "push" => Ok(Family::Push),
            "spin" => Ok(Family::Spin),
            _ => Err(Error::Usage(format!("unknown perturbation family {s:?}: expected push or spin"))),
        }
    }
}

/// What became of a perturbed stone.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Outcome {
    /// Back on the micro-equilibrium it started from.
    Same,
    /// On another stable micro-equilibrium of the same flock (it rocked).
    SameFlock,
    /// In another flock (it toppled).
    Toppled,
}

/// Simulation parameters of perturbation and shaking runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PerturbParams {
    /// Contact, damping, time step, time cap and rest thresholds (launch fields unused).
    /// Default: friction 0.6, restitution 0.2, global damping 0.1 s⁻¹ (linear) and 1 s⁻¹
    /// (angular), no rolling resistance — the contact with which the perturbation and shaking
    /// results in `results/` were computed ([`legacy_contact`]).
    pub sim: DropParams,
    /// Settling time (s) on the equilibrium before the perturbation.
    pub settle_time: f64,
    /// Extra time (s) of undisturbed rest in the check that the stone stays on its equilibrium.
    pub hold_time: f64,
    /// Natural frequency (Hz) of rapier's soft contact constraints (rapier's default: 30 Hz
    /// against moving bodies, which the kinematic ground is, 60 Hz against fixed ones; both are
    /// set to this). A stone on a micro-facet a hundredth of R_max wide stands on a spring
    /// foundation whose rotational stiffness must beat the overturning m g R_F θ: at 30 Hz it
    /// does not for the shallowest facets. Measured on the bundled stone (15 stable
    /// micro-equilibria): 8 stay at rest at 30 Hz, 11 at 60 Hz, 14 at 120 and 240 Hz (the last
    /// one's G is 0.0013 R_F from its facet's edge), and only 8 at 480 Hz, where the stiff
    /// contact starts to jitter at dt = 1/240 s.
    pub contact_frequency: f64,
    /// End a trial once the energy certificate decides its outcome (final facet, or a flock
    /// other than the start's). Off by default: the check that no trial crosses a static barrier
    /// is only meaningful without it.
    pub certificate: bool,
}

/// The contact of the perturbation and shaking runs in `results/`: friction 0.6, restitution
/// 0.2, global damping 0.1 s⁻¹ linear and 1 s⁻¹ angular standing in for rolling resistance, dt
/// 1/240 s, cap 20 s.
pub fn legacy_contact() -> DropParams {
    DropParams {
        height: 0.5,
        horizontal_speed: 0.0,
        spin: 0.0,
        spin_distribution: super::params::SpinDistribution::Fixed,
        friction: 0.6,
        restitution: 0.2,
        rolling_resistance: 0.0,
        torsional_friction: 0.0,
        linear_damping: 0.1,
        angular_damping: 1.0,
        max_time: 20.0,
        ..DropParams::default()
    }
}

impl Default for PerturbParams {
    fn default() -> Self {
        PerturbParams {
            sim: legacy_contact(),
            settle_time: 0.25,
            hold_time: 1.0,
            contact_frequency: CONTACT_FREQUENCY,
            certificate: false,
        }
    }
}

impl PerturbParams {
    /// Refuse parameters that cannot describe a run.
    pub fn check(&self) -> Result<()> {
        self.sim.check()?;
        let bad = |what: String| Err(Error::Usage(what));
        if !(self.settle_time >= 0.0 && self.settle_time.is_finite()) {
            return bad(format!("settle time must be ≥ 0, got {}", self.settle_time));
        }
        if !(self.contact_frequency > 0.0 && self.contact_frequency.is_finite()) {
            return bad(format!("contact frequency must be positive, got {}", self.contact_frequency));
        }
        if !(self.hold_time >= 0.0 && self.hold_time.is_finite()) {
            return bad(format!("hold time must be ≥ 0, got {}", self.hold_time));
        }
        Ok(())
    }
}

/// A regular and a rocking stable micro-equilibrium to compare (positions in
/// [`Stone::stable`]): the regular one with the smallest R (the deepest rest of the stone),
/// and the rocking one with the highest barrier out of its basin (the most convincingly
/// balanced rocking position), each among those that stay at rest (checked with `p`). Either
/// may be missing.
pub fn default_pair(stone: &Stone, p: &PerturbParams) -> (Option<usize>, Option<usize>) {
    let stable = stone.stable();
    let pick = |class: Class, key: &dyn Fn(&StableEquilibrium) -> f64| {
        let mut order: Vec<usize> = (0..stable.len()).filter(|&i| stable[i].class == class).collect();
        order.sort_by(|&a, &b| key(&stable[a]).total_cmp(&key(&stable[b])));
        order.into_iter().find(|&i| check_rest(stone, i, p).stays)
    };
    (pick(Class::Regular, &|s| s.r), pick(Class::Rocking, &|s| -s.basin_exit.epsilon))
}

/// Why a stone would not stay on a micro-equilibrium before any perturbation.
#[derive(Clone, Debug, Serialize)]
pub struct SettleCheck {
    /// The stone stayed on its facet, and came to rest, in the settling and holding time.
    pub stays: bool,
    /// Angle (rad) between the facet's normal and the down direction at the end of the check.
    pub tilt: f64,
    /// Sinking of G below R_F at the end of the check (R_max; the contact's penetration).
    pub sink: f64,
    /// Linear speed at the end of the check.
    pub speed: f64,
    /// Angular speed at the end of the check.
    pub angular_speed: f64,
    /// The facet the quasi-static descent from the final down direction reaches.
    pub facet_reached: u32,
}

/// A new simulation with the stone at rest on stable micro-equilibrium `eq` (position in
/// [`Stone::stable`]), after `time` seconds of settling.
pub fn resting_simulation<'a>(stone: &'a Stone, eq: usize, p: &PerturbParams, time: f64) -> Simulation<'a> {
    let s = &stone.stable()[eq];
    let q = resting_orientation(&stone.body.facet_normals[s.facet as usize]);
    let mut sim = Simulation::new(&stone.body, &p.sim, &q, s.r_normalised, &Vec3::zeros(), &Vec3::zeros());
    sim.set_contact_frequency(p.contact_frequency);
    for _ in 0..(time / p.sim.dt).round() as u64 {
        sim.step();
    }
    sim
}

/// Put the stone on `eq`, let it settle and hold, and check that it stays.
pub fn check_rest(stone: &Stone, eq: usize, p: &PerturbParams) -> SettleCheck {
    let s = &stone.stable()[eq];
    let sim = resting_simulation(stone, eq, p, p.settle_time + p.hold_time);
    let st = sim.state();
    let n = stone.body.facet_normals[s.facet as usize];
    let facet_reached = stone.rest(&st.down).facet;
    let (speed, angular_speed) = (st.linvel.norm(), st.angvel.norm());
    SettleCheck {
        stays: facet_reached == s.facet && speed < p.sim.rest_linear_speed && angular_speed < p.sim.rest_angular_speed,
        tilt: n.dot(&st.down).clamp(-1.0, 1.0).acos(),
        sink: s.r_normalised - st.z,
        speed,
        angular_speed,
        facet_reached,
    }
}

/// The velocities (world frame) of a perturbation of energy ε·m g R_max (scaled frame: m = 1,
/// R_max = 1) of `family`, for a stone resting on facet `facet` with orientation `q` and G at
/// height `z`; also the point of application of a push (body frame, relative to G).
pub fn kick(
    stone: &Stone,
    facet: u32,
    q: &UnitQuaternion<f64>,
    z: f64,
    family: Family,
    epsilon: f64,
    rng: &mut Stream,
) -> (Vec3, Vec3, Option<Vec3>) {
    let energy = epsilon * GRAVITY;
    let inertia = stone.body.world_inertia(q);
    match family {
        Family::Push => {
            let (x, n) = stone.surface_point(rng, facet);
            let (r, n) = (q * x, q * n);
            let mut u = random_unit(rng);
            if u.dot(&n) > 0.0 {
                u = -u;
            }
            let c = r.cross(&u);
            let inv = inertia.try_inverse().unwrap_or_else(Matrix3::identity);
            let k = 1.0 + c.dot(&(inv * c));
            let j = (2.0 * energy / k).sqrt();
            (u * j, inv * c * j, Some(x))
        }
        Family::Spin => {
            let a = random_unit(rng);
            let r = Vec3::new(0.0, 0.0, z);
            let ip = inertia + (Matrix3::identity() * r.norm_squared() - r * r.transpose());
            let w = a * (2.0 * energy / a.dot(&(ip * a))).sqrt();
            (w.cross(&r), w, None)
        }
    }
}

/// One perturbation trial.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Trial {
    /// Position of the start equilibrium in [`Stone::stable`].
    pub start: usize,
    /// Its analysis index.
    pub equilibrium: usize,
    /// Push or spin.
    pub family: Family,
    /// Energy of the perturbation (m g R_max).
    pub epsilon: f64,
    /// Trial number at this (equilibrium, ε): its random stream.
    pub trial: u32,
    /// Same, same flock or toppled.
    pub outcome: Outcome,
    /// Final facet (None when a flock-level certificate ended the trial).
    pub final_facet: Option<u32>,
    /// Final stable micro-equilibrium.
    pub final_equilibrium: Option<usize>,
    /// Final flock.
    pub final_flock: usize,
    /// Came to rest (or was decided by the certificate) before the cap.
    pub settled: bool,
    /// Ended by the energy certificate.
    pub certified: bool,
    /// The stone stopped above its final stable facet by more than the contact tolerance
    /// ([`crate::dynamics::stone::Rest::on_equilibrium`]); the quasi-static descent decided.
    pub non_stable_facet: bool,
    /// Simulated time after the perturbation (s).
    pub time: f64,
    /// Largest rise of the energy level above its value just after the kick (R_max): a passive
    /// body has none; the contact solver's penetration correction gives a little.
    pub max_level_rise: f64,
}

/// The random stream of trial `trial` on stable micro-equilibrium `start` for `family`:
/// family in bit 63, `start` in bits 32–62, `trial` in bits 0–31.
pub fn stream_index(family: Family, start: usize, trial: u32) -> u64 {
    let f = match family {
        Family::Push => 0u64,
        Family::Spin => 1u64 << 63,
    };
    f | ((start as u64) << 32) | trial as u64
}

/// Classify a final facet (or flock) relative to the start.
pub fn classify(stone: &Stone, start: usize, facet: Option<u32>, flock: usize) -> Outcome {
    let s = &stone.stable()[start];
    if facet == Some(s.facet) {
        Outcome::Same
    } else if flock == s.flock {
        Outcome::SameFlock
    } else {
        Outcome::Toppled
    }
}

/// The certificate of a trial: the final facet once it is certain, or the flock once a flock
/// other than the start's is certain (a decided start flock leaves same vs same-flock open).
struct TrialCertificate<'a> {
    energy: EnergyCertificate<'a>,
    start_flock: usize,
}

impl Certificate for TrialCertificate<'_> {
    fn decided(&self, down: &Vec3, level: f64) -> Option<Decided> {
        if let Some(f) = self.energy.facet(down, level) {
            return Some(Decided::Facet(f));
        }
        self.energy.flock(down, level).filter(|&k| k != self.start_flock).map(|k| Decided::Flock(k as u32))
    }
}

/// Run one trial: rest on `start`, kick, simulate to rest.
pub fn trial(stone: &Stone, start: usize, p: &PerturbParams, family: Family, epsilon: f64, seed: u64, k: u32) -> Trial {
    let s = &stone.stable()[start];
    let mut rng = item_rng(seed, stream_index(family, start, k));
    let mut sim = resting_simulation(stone, start, p, p.settle_time);
    let (q, z) = sim.pose();
    let (v, w, _) = kick(stone, s.facet, &q, z, family, epsilon, &mut rng);
    sim.set_velocity(&v, &w);
    let level0 = sim.state().level;
    let mut max_rise: f64 = 0.0;
    let energy = EnergyCertificate::new(stone, CertificateMode::Facet).expect("a facet certificate");
    let cert = TrialCertificate { energy, start_flock: s.flock };
    let none = super::run::NoCertificate;
    let cert: &dyn Certificate = if p.certificate { &cert } else { &none };
    let end = run_loop::run(&mut sim, &p.sim, &mut Passive, cert, &mut |st| max_rise = max_rise.max(st.level - level0));
    let flock_of = |f: u32| stone.facet_flock[f as usize].unwrap_or(usize::MAX);
    let (facet, flock, off) = match end.decided {
        Some(Decided::Facet(f)) => (Some(f), flock_of(f), false),
        Some(Decided::Flock(k)) => (None, k as usize, false),
        None => {
            let rest = stone.rest(&end.state.down);
            (Some(rest.facet), rest.flock, !rest.on_equilibrium())
        }
    };
    Trial {
        start,
        equilibrium: s.index,
        family,
        epsilon,
        trial: k,
        outcome: classify(stone, start, facet, flock),
        final_facet: facet,
        final_equilibrium: facet.and_then(|f| stone.facet_equilibrium[f as usize]),
        final_flock: flock,
        settled: end.settled,
        certified: end.decided.is_some(),
        non_stable_facet: off,
        time: end.steps as f64 * p.sim.dt,
        max_level_rise: max_rise,
    }
}

/// The ε (or acceleration) at which a probability first reaches ½ on a grid.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", content = "value", rename_all = "lowercase")]
pub enum Threshold {
    /// Already ≥ ½ at the smallest grid value (the threshold is at most this).
    Below(f64),
    /// Interpolated between the two grid values around the crossing.
    At(f64),
    /// Never reached ½ on the grid (the threshold is above its largest value).
    Above(f64),
}

impl Threshold {
    /// The value (a bound for `Below` / `Above`).
    pub fn value(&self) -> f64 {
        match *self {
            Threshold::Below(x) | Threshold::At(x) | Threshold::Above(x) => x,
        }
    }

    /// First crossing of ½ by `p` over the increasing grid `x`, interpolated linearly in p
    /// against log x (`log`) or x.
    pub fn crossing(x: &[f64], p: &[f64], log: bool) -> Option<Threshold> {
        let first = p.iter().position(|&v| v >= 0.5)?;
        if first == 0 {
            return Some(Threshold::Below(x[0]));
        }
        let (x0, x1, p0, p1) = (x[first - 1], x[first], p[first - 1], p[first]);
        let t = if p1 > p0 { (0.5 - p0) / (p1 - p0) } else { 1.0 };
        Some(Threshold::At(if log { (x0.ln() + t * (x1.ln() - x0.ln())).exp() } else { x0 + t * (x1 - x0) }))
    }

    /// As [`Threshold::crossing`], `Above(max x)` if it never crosses (None on an empty grid).
    pub fn of(x: &[f64], p: &[f64], log: bool) -> Option<Threshold> {
        Self::crossing(x, p, log).or_else(|| x.last().map(|&m| Threshold::Above(m)))
    }
}

/// Outcome counts at one grid value, with 95 % Wilson intervals.
#[derive(Clone, Debug, Serialize)]
pub struct CurvePoint {
    /// ε (perturbations) or peak ground acceleration in g (shaking).
    pub x: f64,
    pub n: u64,
    pub same: u64,
    pub same_flock: u64,
    pub toppled: u64,
    /// Trials that hit the time cap (classified from where they were).
    pub unsettled: u64,
    pub p_same: f64,
    pub ci_same: (f64, f64),
    /// P(still in the flock) = P(same) + P(another micro-equilibrium of the flock).
    pub p_in_flock: f64,
    pub ci_in_flock: (f64, f64),
    pub p_toppled: f64,
    pub ci_toppled: (f64, f64),
}

impl CurvePoint {
    /// Count the outcomes of trials at grid value `x`.
    pub fn count(x: f64, outcomes: impl Iterator<Item = (Outcome, bool)>) -> CurvePoint {
        let (mut n, mut same, mut same_flock, mut toppled, mut unsettled) = (0, 0, 0, 0, 0);
        for (o, settled) in outcomes {
            n += 1;
            unsettled += u64::from(!settled);
            match o {
                Outcome::Same => same += 1,
                Outcome::SameFlock => same_flock += 1,
                Outcome::Toppled => toppled += 1,
            }
        }
        let p = |k: u64| if n > 0 { k as f64 / n as f64 } else { f64::NAN };
        CurvePoint {
            x,
            n,
            same,
            same_flock,
            toppled,
            unsettled,
            p_same: p(same),
            ci_same: wilson(same, n, 1.96),
            p_in_flock: p(same + same_flock),
            ci_in_flock: wilson(same + same_flock, n, 1.96),
            p_toppled: p(toppled),
            ci_toppled: wilson(toppled, n, 1.96),
        }
    }
}

/// The robustness of one stable micro-equilibrium.
#[derive(Clone, Debug, Serialize)]
pub struct Robustness {
    pub equilibrium: StableEquilibrium,
    pub rest: SettleCheck,
    /// One point per ε of the grid (empty if the stone does not stay on the equilibrium).
    pub curve: Vec<CurvePoint>,
    /// ε₅₀ to leave the micro-equilibrium (P(same) < ½) and to leave the flock (P(toppled) ≥ ½).
    pub eps50_micro: Option<Threshold>,
    pub eps50_flock: Option<Threshold>,
    /// Smallest ε at which any trial left the micro-equilibrium / the flock.
    pub first_leave: Option<f64>,
    pub first_topple: Option<f64>,
    /// ε₅₀ / static barrier (how far above the barrier the dynamic threshold sits).
    pub ratio_micro: Option<f64>,
    pub ratio_flock: Option<f64>,
    /// Topples by destination flock: (flock, type, count).
    pub destinations: Vec<(usize, Kind, u64)>,
    /// Dynamic class at ε* (None: the grid does not decide it).
    pub dynamic_class: Option<Class>,
}

/// No trial below a static barrier may cross it (SPEC §6: energy never grows).
#[derive(Clone, Debug, Default, Serialize)]
pub struct BarrierCheck {
    /// Trials with ε below the basin barrier, and how many of them left the micro-equilibrium.
    pub below_basin: u64,
    pub basin_violations: u64,
    /// Trials with ε below the flock barrier, and how many of them left the flock.
    pub below_flock: u64,
    pub flock_violations: u64,
    /// Smallest ε / basin barrier among trials that left their micro-equilibrium (≥ 1 if the
    /// static theory holds; the reported numerical margin is how far below 1 it may go).
    pub smallest_exit_ratio: Option<f64>,
    /// Smallest ε / flock barrier among trials that toppled.
    pub smallest_topple_ratio: Option<f64>,
    /// Largest rise of the energy level during a trial (R_max units).
    pub max_level_rise: f64,
}

impl BarrierCheck {
    /// Tally the trials (`barriers[start]` = (basin, flock) barriers in ε).
    pub fn of(trials: &[Trial], stone: &Stone) -> BarrierCheck {
        let mut c = BarrierCheck::default();
        let min = |a: &mut Option<f64>, x: f64| *a = Some(a.map_or(x, |y: f64| y.min(x)));
        for t in trials {
            let s = &stone.stable()[t.start];
            let (b, f) = (s.basin_exit.epsilon, s.flock_exit.epsilon);
            c.max_level_rise = c.max_level_rise.max(t.max_level_rise);
            if t.epsilon < b {
                c.below_basin += 1;
                c.basin_violations += u64::from(t.outcome != Outcome::Same);
            }
            if t.epsilon < f {
                c.below_flock += 1;
                c.flock_violations += u64::from(t.outcome == Outcome::Toppled);
            }
            if t.outcome != Outcome::Same && b.is_finite() {
                min(&mut c.smallest_exit_ratio, t.epsilon / b);
            }
            if t.outcome == Outcome::Toppled && f.is_finite() {
                min(&mut c.smallest_topple_ratio, t.epsilon / f);
            }
        }
        c
    }
}

/// Static class (rows) against dynamic class (columns).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Confusion {
    pub regular_as_regular: u64,
    pub regular_as_rocking: u64,
    pub rocking_as_regular: u64,
    pub rocking_as_rocking: u64,
    /// Equilibria the grid could not classify dynamically (or that do not stay at rest).
    pub undecided: u64,
}

impl Confusion {
    pub fn add(&mut self, stat: Class, dynamic: Option<Class>) {
        match (stat, dynamic) {
            (Class::Regular, Some(Class::Regular)) => self.regular_as_regular += 1,
            (Class::Regular, Some(Class::Rocking)) => self.regular_as_rocking += 1,
            (Class::Rocking, Some(Class::Regular)) => self.rocking_as_regular += 1,
            (Class::Rocking, Some(Class::Rocking)) => self.rocking_as_rocking += 1,
            (_, None) => self.undecided += 1,
        }
    }

    pub fn merge(&mut self, o: &Confusion) {
        self.regular_as_regular += o.regular_as_regular;
        self.regular_as_rocking += o.regular_as_rocking;
        self.rocking_as_regular += o.rocking_as_regular;
        self.rocking_as_rocking += o.rocking_as_rocking;
        self.undecided += o.undecided;
    }

    /// Fraction of decided equilibria whose classes agree.
    pub fn agreement(&self) -> f64 {
        let agree = self.regular_as_regular + self.rocking_as_rocking;
        let all = agree + self.regular_as_rocking + self.rocking_as_regular;
        if all == 0 {
            f64::NAN
        } else {
            agree as f64 / all as f64
        }
    }
}

/// What a perturbation run is.
#[derive(Clone, Debug, Serialize)]
pub struct PerturbConfig {
    pub params: PerturbParams,
    pub family: Family,
    /// Increasing grid of ε.
    pub epsilons: Vec<f64>,
    pub trials: u32,
    pub seed: u64,
    /// ε* of the dynamic classification (None: the stone's ν).
    pub epsilon_star: Option<f64>,
}

impl PerturbConfig {
    pub fn check(&self) -> Result<()> {
        self.params.check()?;
        if self.epsilons.is_empty() || self.epsilons.iter().any(|e| !(*e > 0.0 && e.is_finite())) {
            return Err(Error::Usage("the ε grid must hold positive values".into()));
        }
        if self.epsilons.windows(2).any(|w| w[1] <= w[0]) {
            return Err(Error::Usage("the ε grid must be increasing".into()));
        }
        if self.trials == 0 {
            return Err(Error::Usage("at least one trial per ε".into()));
        }
        Ok(())
    }
}

/// The numbers of a perturbation run.
#[derive(Clone, Debug, Serialize)]
pub struct PerturbReport {
    pub family: Family,
    pub seed: u64,
    pub trials_per_point: u32,
    pub epsilons: Vec<f64>,
    pub nu: f64,
    pub epsilon_star: f64,
    pub params: PerturbParams,
    pub equilibria: Vec<Robustness>,
    pub barrier_check: BarrierCheck,
    pub confusion: Confusion,
    /// Every trial (sorted by start, ε, trial).
    #[serde(skip)]
    pub trials: Vec<Trial>,
}

/// Dynamic class from ε₅₀(flock) and ε*.
pub fn dynamic_class(eps50_flock: Option<Threshold>, epsilon_star: f64) -> Option<Class> {
    match eps50_flock? {
        Threshold::Below(x) | Threshold::At(x) if x <= epsilon_star => Some(Class::Rocking),
        Threshold::Below(_) => None,
        Threshold::At(_) => Some(Class::Regular),
        Threshold::Above(x) if x >= epsilon_star => Some(Class::Regular),
        Threshold::Above(_) => None,
    }
}

/// Summarise the trials of one start equilibrium.
pub fn robustness(
    stone: &Stone,
    start: usize,
    rest: SettleCheck,
    epsilons: &[f64],
    trials: &[Trial],
    epsilon_star: f64,
) -> Robustness {
    let eq = stone.stable()[start].clone();
    let curve: Vec<CurvePoint> = if rest.stays {
        epsilons
            .iter()
            .map(|&e| CurvePoint::count(e, trials.iter().filter(|t| t.epsilon == e).map(|t| (t.outcome, t.settled))))
            .collect()
    } else {
        Vec::new()
    };
    let x: Vec<f64> = curve.iter().map(|c| c.x).collect();
    let leave: Vec<f64> = curve.iter().map(|c| 1.0 - c.p_same).collect();
    let topple: Vec<f64> = curve.iter().map(|c| c.p_toppled).collect();
    let eps50_micro = Threshold::of(&x, &leave, true);
    let eps50_flock = Threshold::of(&x, &topple, true);
    let first = |pred: &dyn Fn(&Trial) -> bool| {
        trials
            .iter()
            .filter(|t| pred(t))
            .map(|t| t.epsilon)
            .fold(None, |a: Option<f64>, e| Some(a.map_or(e, |b| b.min(e))))
    };
    let first_leave = first(&|t| t.outcome != Outcome::Same);
    let first_topple = first(&|t| t.outcome == Outcome::Toppled);
    let ratio = |t: Option<Threshold>, b: f64| match t {
        Some(Threshold::At(v)) if b.is_finite() && b > 0.0 => Some(v / b),
        _ => None,
    };
    let mut destinations: Vec<(usize, Kind, u64)> = Vec::new();
    for t in trials.iter().filter(|t| t.outcome == Outcome::Toppled) {
        match destinations.iter_mut().find(|d| d.0 == t.final_flock) {
            Some(d) => d.2 += 1,
            None => destinations.push((
                t.final_flock,
                stone.flock_kinds.get(t.final_flock).copied().unwrap_or(Kind::Stable),
                1,
            )),
        }
    }
    destinations.sort_by_key(|d| d.0);
    Robustness {
        ratio_micro: ratio(eps50_micro, eq.basin_exit.epsilon),
        ratio_flock: ratio(eps50_flock, eq.flock_exit.epsilon),
        dynamic_class: if rest.stays { dynamic_class(eps50_flock, epsilon_star) } else { None },
        equilibrium: eq,
        rest,
        curve,
        eps50_micro,
        eps50_flock,
        first_leave,
        first_topple,
        destinations,
    }
}

/// Run `cfg` on the stable micro-equilibria `starts` (positions in [`Stone::stable`]), in
/// parallel; the result does not depend on the number of threads.
pub fn run(stone: &Stone, starts: &[usize], cfg: &PerturbConfig) -> PerturbReport {
    run_with(stone, starts, cfg, &|| {})
}

/// Number of trials a run of `cfg` on `n` equilibria makes (if all stay at rest).
pub fn task_count(n: usize, cfg: &PerturbConfig) -> u64 {
    n as u64 * cfg.epsilons.len() as u64 * cfg.trials as u64
}

/// [`run`], calling `progress` after every trial (from any thread).
pub fn run_with(stone: &Stone, starts: &[usize], cfg: &PerturbConfig, progress: &(dyn Fn() + Sync)) -> PerturbReport {
    let checks: Vec<SettleCheck> = starts.par_iter().map(|&s| check_rest(stone, s, &cfg.params)).collect();
    let tasks: Vec<(usize, f64, u32)> = starts
        .iter()
        .zip(&checks)
        .filter(|(_, c)| c.stays)
        .flat_map(|(&s, _)| cfg.epsilons.iter().flat_map(move |&e| (0..cfg.trials).map(move |k| (s, e, k))))
        .collect();
    let trials: Vec<Trial> = tasks
        .par_iter()
        .map(|&(s, e, k)| {
            let t = trial(stone, s, &cfg.params, cfg.family, e, cfg.seed, k);
            progress();
            t
        })
        .collect();
    report(stone, starts, checks, trials, cfg)
}

/// Assemble the report of a run from its rest checks and trials.
pub fn report(
    stone: &Stone,
    starts: &[usize],
    checks: Vec<SettleCheck>,
    trials: Vec<Trial>,
    cfg: &PerturbConfig,
) -> PerturbReport {
    let epsilon_star = cfg.epsilon_star.unwrap_or(stone.nu);
    let mut confusion = Confusion::default();
    let equilibria: Vec<Robustness> = starts
        .iter()
        .zip(checks)
        .map(|(&s, c)| {
            let mine: Vec<Trial> = trials.iter().filter(|t| t.start == s).copied().collect();
            let r = robustness(stone, s, c, &cfg.epsilons, &mine, epsilon_star);
            confusion.add(r.equilibrium.class, r.dynamic_class);
            r
        })
        .collect();
    PerturbReport {
        family: cfg.family,
        seed: cfg.seed,
        trials_per_point: cfg.trials,
        epsilons: cfg.epsilons.clone(),
        nu: stone.nu,
        epsilon_star,
        params: cfg.params.clone(),
        equilibria,
        barrier_check: BarrierCheck::of(&trials, stone),
        confusion,
        trials,
    }
}

fn fmt_threshold(t: &Option<Threshold>) -> String {
    match t {
        None => "-".into(),
        Some(Threshold::Below(x)) => format!("≤{x:.2e}"),
        Some(Threshold::At(x)) => format!("{x:.2e}"),
        Some(Threshold::Above(x)) => format!(">{x:.2e}"),
    }
}

fn fmt_eps(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2e}")
    } else {
        "∞".into()
    }
}

/// A readable summary of a run.
pub fn summary(r: &PerturbReport, mesh: &str) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{mesh}: {} perturbations, {} trials per ε on {} ε from {:.1e} to {:.1e}, seed {}",
        r.family.name(),
        r.trials_per_point,
        r.epsilons.len(),
        r.epsilons.first().copied().unwrap_or(f64::NAN),
        r.epsilons.last().copied().unwrap_or(f64::NAN),
        r.seed
    );
    let _ = writeln!(
        s,
        "ε = kinetic energy / (m g R_max); flocks at ν = {:.3e}; dynamic class at ε* = {:.3e}",
        r.nu, r.epsilon_star
    );
    let _ = writeln!(
        s,
        "{:>5} {:>6} {:>6} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}",
        "eq", "facet", "flock", "static", "barrier", "ε50 micro", "barrier", "ε50 flock", "×barrier", "dynamic"
    );
    let _ = writeln!(
        s,
        "{:>5} {:>6} {:>6} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}",
        "", "", "", "class", "basin", "", "flock", "", "flock", "class"
    );
    for e in &r.equilibria {
        let q = &e.equilibrium;
        let cls = |c: Class| match c {
            Class::Regular => "regular",
            Class::Rocking => "rocking",
        };
        let _ = writeln!(
            s,
            "{:>5} {:>6} {:>4}{} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}",
            q.index,
            q.facet,
            q.flock,
            match q.flock_kind {
                Kind::Stable => "S",
                Kind::Unstable => "U",
                Kind::Saddle => "H",
            },
            cls(q.class),
            fmt_eps(q.basin_exit.epsilon),
            if e.rest.stays { fmt_threshold(&e.eps50_micro) } else { "no rest".into() },
            fmt_eps(q.flock_exit.epsilon),
            fmt_threshold(&e.eps50_flock),
            e.ratio_flock.map_or("-".into(), |x| format!("{x:.1}")),
            e.dynamic_class.map_or("?", cls),
        );
    }
    let b = &r.barrier_check;
    let _ = writeln!(
        s,
        "barrier check: {} of {} trials below the basin barrier left it, {} of {} below the flock barrier toppled; \
         smallest ε/barrier among exits {}, among topples {}; largest energy-level rise {:.1e} R_max",
        b.basin_violations,
        b.below_basin,
        b.flock_violations,
        b.below_flock,
        b.smallest_exit_ratio.map_or("-".into(), |x| format!("{x:.2}")),
        b.smallest_topple_ratio.map_or("-".into(), |x| format!("{x:.2}")),
        b.max_level_rise
    );
    let c = &r.confusion;
    let _ = writeln!(
        s,
        "static vs dynamic class: regular→regular {}, regular→rocking {}, rocking→regular {}, rocking→rocking {}, undecided {}",
        c.regular_as_regular, c.regular_as_rocking, c.rocking_as_regular, c.rocking_as_rocking, c.undecided
    );
    s
}

/// Write the curves of a run as CSV (one row per equilibrium and ε).
pub fn write_curves_csv(path: &Path, r: &PerturbReport) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_path(path)?;
    w.write_record([
        "equilibrium",
        "facet",
        "flock",
        "flock_type",
        "static_class",
        "family",
        "epsilon",
        "n",
        "same",
        "same_flock",
        "toppled",
        "unsettled",
        "p_same",
        "p_same_lo",
        "p_same_hi",
        "p_in_flock",
        "p_in_flock_lo",
        "p_in_flock_hi",
        "p_toppled",
        "p_toppled_lo",
        "p_toppled_hi",
        "barrier_basin",
        "barrier_flock",
    ])?;
    for e in &r.equilibria {
        let q = &e.equilibrium;
        for c in &e.curve {
            w.write_record([
                q.index.to_string(),
                q.facet.to_string(),
                q.flock.to_string(),
                format!("{:?}", q.flock_kind).to_lowercase(),
                format!("{:?}", q.class).to_lowercase(),
                r.family.name().into(),
                format!("{:.6e}", c.x),
                c.n.to_string(),
                c.same.to_string(),
                c.same_flock.to_string(),
                c.toppled.to_string(),
                c.unsettled.to_string(),
                format!("{:.4}", c.p_same),
                format!("{:.4}", c.ci_same.0),
                format!("{:.4}", c.ci_same.1),
                format!("{:.4}", c.p_in_flock),
                format!("{:.4}", c.ci_in_flock.0),
                format!("{:.4}", c.ci_in_flock.1),
                format!("{:.4}", c.p_toppled),
                format!("{:.4}", c.ci_toppled.0),
                format!("{:.4}", c.ci_toppled.1),
                format!("{:.6e}", q.basin_exit.epsilon),
                format!("{:.6e}", q.flock_exit.epsilon),
            ])?;
        }
    }
    w.flush()?;
    Ok(())
}

/// Write one row per equilibrium: static barriers, dynamic thresholds, classes.
pub fn write_thresholds_csv(path: &Path, r: &PerturbReport) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_path(path)?;
    w.write_record([
        "equilibrium",
        "facet",
        "r_normalised",
        "flock",
        "flock_type",
        "static_class",
        "stays_at_rest",
        "barrier_basin",
        "basin_exit_equilibrium",
        "barrier_flock",
        "flock_exit_flock",
        "eps50_micro",
        "eps50_micro_kind",
        "eps50_flock",
        "eps50_flock_kind",
        "first_leave",
        "first_topple",
        "ratio_micro",
        "ratio_flock",
        "uplift_acceleration_g",
        "dynamic_class",
    ])?;
    let th = |t: &Option<Threshold>| match t {
        None => (String::new(), String::new()),
        Some(t) => (
            format!("{:.6e}", t.value()),
            match t {
                Threshold::Below(_) => "below",
                Threshold::At(_) => "at",
                Threshold::Above(_) => "above",
            }
            .into(),
        ),
    };
    let opt = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x:.6e}"));
    for e in &r.equilibria {
        let q = &e.equilibrium;
        let (m, mk) = th(&e.eps50_micro);
        let (f, fk) = th(&e.eps50_flock);
        w.write_record([
            q.index.to_string(),
            q.facet.to_string(),
            format!("{:.6}", q.r_normalised),
            q.flock.to_string(),
            format!("{:?}", q.flock_kind).to_lowercase(),
            format!("{:?}", q.class).to_lowercase(),
            e.rest.stays.to_string(),
            format!("{:.6e}", q.basin_exit.epsilon),
            q.basin_exit.equilibrium.map_or(String::new(), |x| x.to_string()),
            format!("{:.6e}", q.flock_exit.epsilon),
            q.flock_exit.flock.map_or(String::new(), |x| x.to_string()),
            m,
            mk,
            f,
            fk,
            opt(e.first_leave),
            opt(e.first_topple),
            opt(e.ratio_micro),
            opt(e.ratio_flock),
            format!("{:.6e}", q.uplift_acceleration),
            e.dynamic_class.map_or(String::new(), |c| format!("{c:?}").to_lowercase()),
        ])?;
    }
    w.flush()?;
    Ok(())
}

/// Write every trial as CSV.
pub fn write_trials_csv(path: &Path, trials: &[Trial]) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_path(path)?;
    w.write_record([
        "equilibrium",
        "family",
        "epsilon",
        "trial",
        "outcome",
        "final_facet",
        "final_equilibrium",
        "final_flock",
        "settled",
        "certified",
        "non_stable_facet",
        "time",
        "max_level_rise",
    ])?;
    for t in trials {
        w.write_record([
            t.equilibrium.to_string(),
            t.family.name().into(),
            format!("{:.6e}", t.epsilon),
            t.trial.to_string(),
            match t.outcome {
                Outcome::Same => "same",
                Outcome::SameFlock => "same-flock",
                Outcome::Toppled => "toppled",
            }
            .into(),
            t.final_facet.map_or(String::new(), |x| x.to_string()),
            t.final_equilibrium.map_or(String::new(), |x| x.to_string()),
            t.final_flock.to_string(),
            t.settled.to_string(),
            t.certified.to_string(),
            t.non_stable_facet.to_string(),
            format!("{:.4}", t.time),
            format!("{:.3e}", t.max_level_rise),
        ])?;
    }
    w.flush()?;
    Ok(())
}

/// A panel of [`plot_curves`]: a title, the curve, and vertical markers (x, label, colour).
pub struct Panel<'a> {
    pub title: String,
    pub curve: &'a [CurvePoint],
    pub markers: Vec<(f64, String, RGBColor)>,
}

use plotters::prelude::*;

/// Top of the probability axis: room above 1 for the legend.
const TOP: f64 = 1.55;

/// Outcome probabilities against x (log ε, or PGA) with 95 % intervals, one panel per entry,
/// side by side (up to three per row; four as 2 × 2). PNG or SVG by extension.
pub fn plot_curves(path: &Path, caption: &str, x_label: &str, log_x: bool, panels: &[Panel]) -> anyhow::Result<()> {
    init_fonts();
    let cols = if panels.len() == 4 { 2 } else { panels.len().clamp(1, 3) };
    let rows = panels.len().div_ceil(cols).max(1);
    let (w, h) = (560 * cols as u32, 420 * rows as u32 + 40);
    if path.extension().is_some_and(|e| e == "svg") {
        let root = SVGBackend::new(path, (w, h)).into_drawing_area();
        draw_curves(&root, caption, x_label, log_x, panels, rows, cols)?;
        root.present()?;
    } else {
        let root = BitMapBackend::new(path, (w, h)).into_drawing_area();
        draw_curves(&root, caption, x_label, log_x, panels, rows, cols)?;
        root.present()?;
    }
    Ok(())
}

type Area<DB> = DrawingArea<DB, plotters::coord::Shift>;

fn draw_curves<DB: DrawingBackend>(
    root: &Area<DB>,
    caption: &str,
    x_label: &str,
    log_x: bool,
    panels: &[Panel],
    rows: usize,
    cols: usize,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| anyhow::anyhow!("{x:?}");
    root.fill(&WHITE).map_err(e)?;
    let root = root.titled(caption, (FONT_FAMILY, 22)).map_err(e)?;
    for (panel, area) in panels.iter().zip(root.split_evenly((rows, cols))) {
        let xs: Vec<f64> = panel
            .curve
            .iter()
            .map(|c| c.x)
            .chain(panel.markers.iter().map(|m| m.0))
            .filter(|x| x.is_finite() && (!log_x || *x > 0.0))
            .collect();
        let (mut lo, mut hi) =
            (xs.iter().cloned().fold(f64::INFINITY, f64::min), xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max));
        if !lo.is_finite() {
            (lo, hi) = (1e-3, 1.0);
        }
        let series = [
            ("P(same micro-equilibrium)", RGBColor(40, 90, 200), 0usize),
            ("P(still in the flock)", RGBColor(40, 160, 80), 1),
            ("P(toppled out of the flock)", RGBColor(210, 50, 40), 2),
        ];
        let pick = |c: &CurvePoint, k: usize| match k {
            0 => (c.p_same, c.ci_same),
            1 => (c.p_in_flock, c.ci_in_flock),
            _ => (c.p_toppled, c.ci_toppled),
        };
        macro_rules! body {
            ($chart:ident) => {{
                $chart
                    .configure_mesh()
                    .x_desc(x_label)
                    .y_desc("probability")
                    .x_labels(8)
                    .x_label_formatter(&|x: &f64| if log_x { format!("{x:.0e}") } else { format!("{x:.2}") })
                    .y_label_formatter(&|y: &f64| if *y > 1.001 { String::new() } else { format!("{y:.1}") })
                    .label_style((FONT_FAMILY, 13))
                    .draw()
                    .map_err(e)?;
                for (x, label, color) in &panel.markers {
                    if !x.is_finite() || (log_x && *x <= 0.0) {
                        continue;
                    }
                    let c = *color;
                    $chart
                        .draw_series(DashedLineSeries::new(vec![(*x, 0.0), (*x, 1.02)], 6, 4, c.stroke_width(2)))
                        .map_err(e)?
                        .label(label.clone())
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2)));
                }
                for (name, color, k) in series {
                    let pts: Vec<(f64, f64)> = panel.curve.iter().map(|c| (c.x, pick(c, k).0)).collect();
                    $chart
                        .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
                        .map_err(e)?
                        .label(name)
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2)));
                    $chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled()))).map_err(e)?;
                    $chart
                        .draw_series(panel.curve.iter().map(|c| {
                            let (_, ci) = pick(c, k);
                            PathElement::new(vec![(c.x, ci.0), (c.x, ci.1)], color.stroke_width(1))
                        }))
                        .map_err(e)?;
                }
                $chart
                    .configure_series_labels()
                    .label_font((FONT_FAMILY, 12))
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .position(SeriesLabelPosition::UpperLeft)
                    .draw()
                    .map_err(e)?;
            }};
        }
        if log_x {
            let mut chart = ChartBuilder::on(&area)
                .caption(&panel.title, (FONT_FAMILY, 16))
                .margin(10)
                .x_label_area_size(40)
                .y_label_area_size(50)
                .build_cartesian_2d((lo / 1.5..hi * 1.5).log_scale(), -0.02f64..TOP)
                .map_err(e)?;
            body!(chart);
        } else {
            let pad = 0.05 * (hi - lo).max(1e-9);
            let mut chart = ChartBuilder::on(&area)
                .caption(&panel.title, (FONT_FAMILY, 16))
                .margin(10)
                .x_label_area_size(40)
                .y_label_area_size(50)
                .build_cartesian_2d((lo - pad).max(0.0)..hi + pad, -0.02f64..TOP)
                .map_err(e)?;
            body!(chart);
        }
    }
    Ok(())
}

/// The panels of a perturbation report: static barriers and ε* as markers.
pub fn panels(r: &PerturbReport) -> Vec<Panel<'_>> {
    r.equilibria
        .iter()
        .filter(|e| !e.curve.is_empty())
        .map(|e| {
            let q = &e.equilibrium;
            Panel {
                title: format!(
                    "eq {} (facet {}), {:?} in {:?} flock {}",
                    q.index, q.facet, q.class, q.flock_kind, q.flock
                )
                .to_lowercase(),
                curve: &e.curve,
                markers: vec![
                    (q.basin_exit.epsilon, "static barrier: basin".into(), RGBColor(40, 90, 200)),
                    (q.flock_exit.epsilon, "static barrier: flock".into(), RGBColor(210, 50, 40)),
                    (r.epsilon_star, "ε* (macro ν)".into(), RGBColor(120, 120, 120)),
                ],
            }
        })
        .collect()
}

/// Dynamic thresholds against static barriers (log–log), per equilibrium: ε₅₀ to leave the
/// micro-equilibrium against the basin barrier, ε₅₀ to leave the flock against the flock barrier;
/// regular and rocking equilibria in different colours; the diagonal y = x.
pub fn plot_thresholds(path: &Path, caption: &str, points: &[(f64, f64, bool, Class)]) -> anyhow::Result<()> {
    init_fonts();
    let finite: Vec<f64> = points.iter().flat_map(|p| [p.0, p.1]).filter(|x| x.is_finite() && *x > 0.0).collect();
    let lo = finite.iter().cloned().fold(f64::INFINITY, f64::min).min(1e-3) / 2.0;
    let hi = finite.iter().cloned().fold(0.0, f64::max).max(1e-2) * 2.0;
    let root = BitMapBackend::new(path, (820, 700)).into_drawing_area();
    let e = |x: DrawingAreaErrorKind<std::io::Error>| anyhow::anyhow!("{x:?}");
    root.fill(&WHITE).map_err(|x| anyhow::anyhow!("{x:?}"))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(caption, (FONT_FAMILY, 20))
        .margin(14)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d((lo..hi).log_scale(), (lo..hi).log_scale())
        .map_err(|x| anyhow::anyhow!("{x:?}"))?;
    chart
        .configure_mesh()
        .x_desc("static barrier (m g ΔR / (m g R_max))")
        .y_desc("dynamic threshold ε₅₀")
        .x_label_formatter(&|x: &f64| format!("{x:.0e}"))
        .y_label_formatter(&|y: &f64| format!("{y:.0e}"))
        .label_style((FONT_FAMILY, 13))
        .draw()
        .map_err(|x| anyhow::anyhow!("{x:?}"))?;
    let _ = e;
    chart
        .draw_series(LineSeries::new(vec![(lo, lo), (hi, hi)], BLACK.stroke_width(1)))
        .map_err(|x| anyhow::anyhow!("{x:?}"))?
        .label("ε₅₀ = barrier")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK));
    let styles = [
        (false, Class::Regular, "leave micro-eq., regular", RGBColor(200, 60, 40)),
        (false, Class::Rocking, "leave micro-eq., rocking", RGBColor(40, 90, 200)),
        (true, Class::Regular, "leave flock, regular", RGBColor(200, 60, 40)),
        (true, Class::Rocking, "leave flock, rocking", RGBColor(40, 90, 200)),
    ];
    for (flock, class, label, color) in styles {
        let pts: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.2 == flock && p.3 == class && p.0.is_finite() && p.0 > 0.0 && p.1.is_finite() && p.1 > 0.0)
            .map(|p| (p.0, p.1))
            .collect();
        if flock {
            chart
                .draw_series(pts.iter().map(|&p| TriangleMarker::new(p, 6, color.filled())))
                .map_err(|x| anyhow::anyhow!("{x:?}"))?
                .label(label)
                .legend(move |(x, y)| TriangleMarker::new((x + 8, y), 6, color.filled()));
        } else {
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.stroke_width(2))))
                .map_err(|x| anyhow::anyhow!("{x:?}"))?
                .label(label)
                .legend(move |(x, y)| Circle::new((x + 8, y), 4, color.stroke_width(2)));
        }
    }
    chart
        .configure_series_labels()
        .label_font((FONT_FAMILY, 13))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .map_err(|x| anyhow::anyhow!("{x:?}"))?;
    root.present().map_err(|x| anyhow::anyhow!("{x:?}"))?;
    Ok(())
}

/// The (barrier, ε₅₀, is-flock, class) points of a report for [`plot_thresholds`] (only
/// interpolated thresholds).
pub fn threshold_points(r: &PerturbReport) -> Vec<(f64, f64, bool, Class)> {
    let mut pts = Vec::new();
    for e in &r.equilibria {
        let q = &e.equilibrium;
        if let Some(Threshold::At(v)) = e.eps50_micro {
            pts.push((q.basin_exit.epsilon, v, false, q.class));
        }
        if let Some(Threshold::At(v)) = e.eps50_flock {
            pts.push((q.flock_exit.epsilon, v, true, q.class));
        }
    }
    pts
}
