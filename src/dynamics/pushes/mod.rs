//! Perturbation robustness of stable micro-equilibria (paper §3, §4.1 and Figure 11).
//!
//! A stone is put **exactly at rest** on one stable micro-equilibrium — its facet F on the
//! ground (the orientation maps F's outward normal to −z, with no turn about the vertical), G at
//! height R_F above the ground, zero velocity — and left to settle for
//! [`RestingParams::settle_time`] so that the soft contacts take their load. It is then
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
//! [`crate::dynamics::resting::outcome::Outcome::Same`] (back on F), [`crate::dynamics::resting::outcome::Outcome::SameFlock`] (rocked onto another stable
//! micro-equilibrium of F's flock) or [`crate::dynamics::resting::outcome::Outcome::Toppled`] (left the flock), with the final
//! facet, equilibrium and flock ("where to").
//!
//! Before any trial, [`crate::dynamics::resting::check_rest`] holds the stone on the equilibrium for
//! `settle_time + hold_time` without perturbation. Equilibria whose G is too close to the edge of
//! a tiny facet for the soft contact (see [`RestingParams::contact_frequency`]) tip off by
//! themselves; they are reported as not staying at rest and get no curve.
//!
//! With [`RestingParams::certificate`] a trial ends as soon as the merge-tree certificate of
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
//! Trial k of equilibrium i uses the random stream [`crate::rng::item_rng`]`(seed, stream)` with
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
//! log ε between grid points, [`crate::dynamics::resting::outcome::Threshold`]) sit above them because part of the energy goes
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

pub mod kick;
pub mod robustness;
pub mod trial;

pub use kick::{kick, Family};
pub use robustness::{dynamic_class, robustness, rocking_auc, BarrierCheck, Confusion, Robustness};
pub use trial::{stream_index, trial, Trial};

use crate::dynamics::resting::{grid_trials, RestingParams, SettleCheck};
use crate::dynamics::stone::Stone;
use crate::monitor::Monitor;
use crate::{Error, Result};
use serde::Serialize;

/// What a perturbation run is.
#[derive(Clone, Debug, Serialize)]
pub struct PerturbConfig {
    /// Simulation parameters.
    pub params: RestingParams,
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
            return Err(Error::parameter("epsilons", format!("{:?}", self.epsilons), "a non-empty grid of positive ε"));
        }
        if self.epsilons.windows(2).any(|w| w[1] <= w[0]) {
            return Err(Error::parameter("epsilons", format!("{:?}", self.epsilons), "an increasing grid"));
        }
        if self.trials == 0 {
            return Err(Error::parameter("trials", 0, "at least 1 per ε"));
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
    pub params: RestingParams,
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
    let equilibria: Vec<Robustness> = starts
        .iter()
        .zip(checks)
        .map(|(&s, c)| {
            let mine: Vec<Trial> = trials.iter().filter(|t| t.start == s).copied().collect();
            robustness(stone, s, c, &cfg.epsilons, &mine, epsilon_star)
        })
        .collect();
    let confusion = Confusion::of(&equilibria, epsilon_star);
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
