//! What the trials of one equilibrium say: its toppling curves and thresholds ε₅₀
//! ([`Robustness`], [`robustness`]), the check that no trial crossed a static barrier
//! ([`BarrierCheck`]), and the dynamic class against the static one ([`dynamic_class`],
//! [`Confusion`]).

use crate::dynamics::pushes::trial::Trial;
use crate::dynamics::resting::outcome::{Curve, CurvePoint, Outcome, Threshold};
use crate::dynamics::resting::SettleCheck;
use crate::dynamics::stone::{Class, StableEquilibrium, Stone};
use crate::equilibria::Kind;
use crate::stats::mann_whitney_auc;
use serde::Serialize;

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

    /// The matrix of `equilibria` with the dynamic class read at `epsilon_star`
    /// ([`dynamic_class`] of ε₅₀(flock)); an equilibrium the stone does not stay at rest on is
    /// undecided. At the run's own ε* it is the run's [`Confusion`]; at another one (10 ε*, say)
    /// it is how the classes agree under a coarser or finer experimenter.
    pub fn of<'a>(equilibria: impl IntoIterator<Item = &'a Robustness>, epsilon_star: f64) -> Confusion {
        let mut c = Confusion::default();
        for e in equilibria {
            c.add(e.equilibrium.class, if e.rest.stays { dynamic_class(e.eps50_flock, epsilon_star) } else { None });
        }
        c
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

/// How well ε₅₀(flock) separates the static classes, without a threshold ε*: the probability
/// that a random statically rocking equilibrium has a smaller ε₅₀(flock) than a random regular
/// one ([`mann_whitney_auc`], ties ½; a threshold above the grid, or none, ranks as ∞,
/// [`Threshold::rank`]), over the equilibria the stone stays at rest on; with the numbers of
/// rocking and regular equilibria it compared. 1: every rocking equilibrium topples more easily
/// than every regular one; ½: no separation; NaN if either class is empty.
pub fn rocking_auc<'a>(equilibria: impl IntoIterator<Item = &'a Robustness>) -> (f64, usize, usize) {
    let (mut rocking, mut regular) = (Vec::new(), Vec::new());
    for e in equilibria.into_iter().filter(|e| e.rest.stays) {
        match e.equilibrium.class {
            Class::Rocking => rocking.push(Threshold::rank(e.eps50_flock)),
            Class::Regular => regular.push(Threshold::rank(e.eps50_flock)),
        }
    }
    (mann_whitney_auc(&rocking, &regular), rocking.len(), regular.len())
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::stone::Exit;

    /// An equilibrium of static class `class` with ε₅₀(flock) `eps50`, at rest or not.
    fn robust(class: Class, eps50: Option<Threshold>, stays: bool) -> Robustness {
        let exit = Exit { epsilon: 1e-3, facet: None, equilibrium: None, flock: None };
        let equilibrium = StableEquilibrium {
            index: 0,
            facet: 0,
            r: 1.0,
            r_normalised: 1.0,
            flock: 0,
            flock_kind: Kind::Stable,
            class,
            basin_exit: exit,
            flock_exit: exit,
            uplift_acceleration: 0.5,
        };
        let rest = SettleCheck { stays, tilt: 0.0, sink: 0.0, speed: 0.0, angular_speed: 0.0, facet_reached: 0 };
        Robustness {
            equilibrium,
            rest,
            curve: vec![],
            eps50_micro: None,
            eps50_flock: eps50,
            first_leave: None,
            first_topple: None,
            ratio_micro: None,
            ratio_flock: None,
            destinations: vec![],
            dynamic_class: None,
        }
    }

    #[test]
    fn confusion_reads_the_dynamic_class_at_the_given_epsilon_star() {
        let (at, above) = (|x| Some(Threshold::At(x)), |x| Some(Threshold::Above(x)));
        let eqs = [
            robust(Class::Rocking, at(1e-4), true),
            robust(Class::Rocking, at(1e-2), true),
            robust(Class::Regular, above(1e-1), true),
            robust(Class::Regular, at(1e-4), false),
        ];
        // At ε* = 10⁻³: rocking→rocking, rocking→regular, regular→regular, one not at rest.
        let c = Confusion::of(&eqs, 1e-3);
        let counts = [c.rocking_as_rocking, c.rocking_as_regular, c.regular_as_regular, c.regular_as_rocking];
        assert_eq!((counts, c.undecided), ([1, 1, 1, 0], 1));
        // At ε* = 10⁻¹ both rocking ones topple below it; `Above(10⁻¹)` is still regular.
        let c = Confusion::of(&eqs, 1e-1);
        assert_eq!((c.rocking_as_rocking, c.rocking_as_regular, c.regular_as_regular), (2, 0, 1));
    }

    #[test]
    fn rocking_auc_compares_every_rocking_with_every_regular_equilibrium() {
        let at = |x| Some(Threshold::At(x));
        let eqs = [
            robust(Class::Rocking, at(1e-4), true),
            robust(Class::Rocking, Some(Threshold::Above(1.0)), true),
            robust(Class::Regular, at(1e-2), true),
            robust(Class::Regular, None, true),
            robust(Class::Regular, at(1e-6), false), // not at rest: left out
        ];
        // Rocking ranks (10⁻⁴, ∞) against regular (10⁻², ∞): 10⁻⁴ is below both (2), ∞ is above
        // 10⁻² (0) and ties ∞ (½): 2.5 / 4.
        assert_eq!(rocking_auc(&eqs), (0.625, 2, 2));
    }
}
