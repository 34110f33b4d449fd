//! Perturbation robustness of stable micro-equilibria (paper §3, §4.1 and Figure 11).
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
//! and simulated to rest (the speed rest rule of drops, [`SpeedRest`](crate::dynamics::engine::rest::SpeedRest),
//! with a time cap; a stone still moving at the cap, or at rest on a facet that is not stable, is
//! classified by the quasi-static descent from its last down direction and counted). The contact
//! is the one of every run that starts at rest ([`crate::dynamics::resting`]: the surface pair at the
//! stone's real size, rolling resistance through the contact, no global damping), the physics of
//! drops and field rocks. The outcome is one of
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
//! [`crate::dynamics::engine::run`] (energy level plus its margin) decides the final facet, or a flock other
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
//!   = [`MergeTree::unique_level`](crate::basins::MergeTree::unique_level) (the lowest level at which F's component holds another
//!   stable facet), the cheapest way out being the stable facet it is joined to there;
//! * **leaving the flock** needs ε > ε_flock = (min over stable facets F' of other flocks of the
//!   merge level of F and F' − R_F)/R_max ([`MergeTree::entry_barrier`](crate::basins::MergeTree::entry_barrier)).
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
//!
//! The outcome classes and curve statistics are [`crate::dynamics::resting::outcome`]'s (shared with shaking); the
//! rest placement, its check and the contact are [`crate::dynamics::resting`]'s.

use crate::dynamics::certificate::{CertificateMode, EnergyCertificate};
use crate::dynamics::engine::rest::RestKind;
use crate::dynamics::engine::run::{run_to_end, Certificate, Decided, Passive};
use crate::dynamics::resting::outcome::{classify, Curve, CurvePoint, Outcome, Threshold};
use crate::dynamics::resting::{grid_trials, resting_simulation, PerturbParams, SettleCheck};
use crate::dynamics::stone::{Class, StableEquilibrium, Stone};
use crate::equilibria::Kind;
use crate::monitor::Monitor;
use crate::rng::{item_rng, random_unit, Stream};
use crate::{Error, Result, Vec3, GRAVITY};
use nalgebra::{Matrix3, UnitQuaternion};
use serde::{Deserialize, Serialize};

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
    /// The deepest any hull corner went below the ground after any step or sub-step of the run
    /// (R_max, [`crate::dynamics::engine::world::penetration`]), the stone's settling included.
    pub deepest_penetration: f64,
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

/// The certificate of a trial: the final facet once it is certain, or the flock once a flock
/// other than the start's is certain (a decided start flock leaves same vs same-flock open).
struct TrialCertificate<'a> {
    energy: EnergyCertificate<'a>,
    start_flock: usize,
}

impl Certificate for TrialCertificate<'_> {
    fn decided(&self, s: &crate::dynamics::engine::world::BodyState) -> Option<Decided> {
        if let Some(f) = self.energy.facet(s) {
            return Some(Decided::Facet(f));
        }
        self.energy.flock(s).filter(|&k| k != self.start_flock).map(|k| Decided::Flock(k as u32))
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
    let none = crate::dynamics::engine::run::NoCertificate;
    let cert: &dyn Certificate = if p.certificate { &cert } else { &none };
    let end = run_to_end(&mut sim, &p.sim, &mut Passive, cert, RestKind::Speeds, &mut |st| {
        max_rise = max_rise.max(st.level - level0)
    });
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
        time: end.steps as f64 * p.sim.numerics.dt,
        max_level_rise: max_rise,
        deepest_penetration: sim.deepest_penetration(),
    }
}

/// The robustness of one stable micro-equilibrium.
#[derive(Clone, Debug, Serialize)]
pub struct Robustness {
    /// The stable micro-equilibrium and its static description.
    pub equilibrium: StableEquilibrium,
    /// Whether the unperturbed stone stays at rest on it.
    pub rest: SettleCheck,
    /// One point per ε of the grid (empty if the stone does not stay on the equilibrium).
    pub curve: Vec<CurvePoint>,
    /// ε₅₀ to leave the micro-equilibrium (P(same) < ½) and to leave the flock (P(toppled) ≥ ½).
    pub eps50_micro: Option<Threshold>,
    /// ε₅₀ to leave the flock (P(toppled) ≥ ½).
    pub eps50_flock: Option<Threshold>,
    /// Smallest ε at which any trial left the micro-equilibrium / the flock.
    pub first_leave: Option<f64>,
    /// Smallest ε at which any trial left the flock.
    pub first_topple: Option<f64>,
    /// ε₅₀ / static barrier (how far above the barrier the dynamic threshold sits).
    pub ratio_micro: Option<f64>,
    /// ε₅₀(flock) / static flock barrier.
    pub ratio_flock: Option<f64>,
    /// Topples by destination flock: (flock, type, count).
    pub destinations: Vec<(usize, Kind, u64)>,
    /// Dynamic class at ε* (None: the grid does not decide it).
    pub dynamic_class: Option<Class>,
}

/// No trial below a static barrier may cross it (energy never grows: the energy certificate,
/// `docs/methods.md`).
#[derive(Clone, Debug, Default, Serialize)]
pub struct BarrierCheck {
    /// Trials with ε below the basin barrier, and how many of them left the micro-equilibrium.
    pub below_basin: u64,
    /// Trials below the basin barrier that left the micro-equilibrium.
    pub basin_violations: u64,
    /// Trials with ε below the flock barrier, and how many of them left the flock.
    pub below_flock: u64,
    /// Trials below the flock barrier that left the flock.
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
    /// Statically regular, dynamically regular.
    pub regular_as_regular: u64,
    /// Statically regular, dynamically rocking.
    pub regular_as_rocking: u64,
    /// Statically rocking, dynamically regular.
    pub rocking_as_regular: u64,
    /// Statically rocking, dynamically rocking.
    pub rocking_as_rocking: u64,
    /// Equilibria the grid could not classify dynamically (or that do not stay at rest).
    pub undecided: u64,
}

impl Confusion {
    /// Count one equilibrium with static class `stat` and dynamic class `dynamic` (None: undecided).
    pub fn add(&mut self, stat: Class, dynamic: Option<Class>) {
        match (stat, dynamic) {
            (Class::Regular, Some(Class::Regular)) => self.regular_as_regular += 1,
            (Class::Regular, Some(Class::Rocking)) => self.regular_as_rocking += 1,
            (Class::Rocking, Some(Class::Regular)) => self.rocking_as_regular += 1,
            (Class::Rocking, Some(Class::Rocking)) => self.rocking_as_rocking += 1,
            (_, None) => self.undecided += 1,
        }
    }

    /// Add the counts of another matrix to this one.
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
    /// Simulation parameters.
    pub params: PerturbParams,
    /// Perturbation family (push or spin).
    pub family: Family,
    /// Increasing grid of ε.
    pub epsilons: Vec<f64>,
    /// Number of trials per equilibrium and ε.
    pub trials: u32,
    /// Seed of the random streams of the trials.
    pub seed: u64,
    /// ε* of the dynamic classification (None: the stone's ν).
    pub epsilon_star: Option<f64>,
}

impl PerturbConfig {
    /// Refuse invalid parameters, an empty, non-positive or non-increasing ε grid, or zero trials.
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
    /// Perturbation family (push or spin).
    pub family: Family,
    /// Seed of the random streams of the trials.
    pub seed: u64,
    /// Number of trials per equilibrium and ε.
    pub trials_per_point: u32,
    /// Increasing grid of ε.
    pub epsilons: Vec<f64>,
    /// Resolution ν of the flocks.
    pub nu: f64,
    /// ε* of the dynamic classification.
    pub epsilon_star: f64,
    /// Simulation parameters.
    pub params: PerturbParams,
    /// Real size of the stone, R_max in metres, and whether it was assumed (the mesh's unit
    /// neither given nor known): set by the command line and the Python binding
    /// ([`crate::dynamics::size::RealSize::resolve`]); absent when the caller set the
    /// parameters directly.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub r_max_m: Option<f64>,
    /// See `r_max_m`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub size_assumed: Option<bool>,
    /// Robustness of each stable micro-equilibrium.
    pub equilibria: Vec<Robustness>,
    /// Trials below a static barrier that crossed it (energy never grows, [`BarrierCheck`]).
    pub barrier_check: BarrierCheck,
    /// Static against dynamic class of the equilibria.
    pub confusion: Confusion,
    /// The deepest any hull corner went below the ground after any step or sub-step of any trial
    /// (R_max, [`crate::dynamics::engine::world::penetration`]).
    pub deepest_penetration: f64,
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
    let outcomes: Vec<(f64, Outcome, bool)> = trials.iter().map(|t| (t.epsilon, t.outcome, t.settled)).collect();
    let Curve { points: curve, leave50: eps50_micro, topple50: eps50_flock } =
        Curve::of(epsilons, rest.stays, &outcomes, true);
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
pub fn perturb_equilibria(stone: &Stone, starts: &[usize], cfg: &PerturbConfig) -> PerturbReport {
    match perturb_equilibria_monitored(stone, starts, cfg, &|| {}) {
        Ok(r) => r,
        Err(_) => unreachable!("a closure monitor never stops a run"),
    }
}

/// Number of trials a run of `cfg` on `n` equilibria makes (if all stay at rest).
pub fn task_count(n: usize, cfg: &PerturbConfig) -> u64 {
    n as u64 * cfg.epsilons.len() as u64 * cfg.trials as u64
}

/// [`perturb_equilibria`], telling `monitor` of every finished trial (from any thread); [`Error::Cancelled`] if
/// it stops the run.
pub fn perturb_equilibria_monitored(
    stone: &Stone,
    starts: &[usize],
    cfg: &PerturbConfig,
    monitor: &dyn Monitor,
) -> Result<PerturbReport> {
    let (checks, trials) =
        grid_trials(stone, starts, &cfg.params, cfg.epsilons.len(), cfg.trials, monitor, |s, i, k| {
            trial(stone, s, &cfg.params, cfg.family, cfg.epsilons[i], cfg.seed, k)
        })?;
    Ok(report(stone, starts, checks, trials, cfg))
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
        r_max_m: None,
        size_assumed: None,
        equilibria,
        barrier_check: BarrierCheck::of(&trials, stone),
        deepest_penetration: trials.iter().map(|t| t.deepest_penetration).fold(0.0, f64::max),
        confusion,
        trials,
    }
}
