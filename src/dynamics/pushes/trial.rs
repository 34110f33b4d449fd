//! One trial: a stone placed at rest on a stable micro-equilibrium, kicked with energy ε and run
//! to rest ([`trial`]), on its own random stream ([`stream_index`]).

use crate::dynamics::certificate::{CertificateMode, EnergyCertificate};
use crate::dynamics::engine::rest::RestKind;
use crate::dynamics::engine::run::{run_to_end, Certificate, Decided, Passive};
use crate::dynamics::pushes::kick::{kick, Family};
use crate::dynamics::resting::outcome::{classify, Outcome};
use crate::dynamics::resting::{resting_simulation, RestingParams};
use crate::dynamics::stone::Stone;
use crate::rng::item_rng;
use serde::Serialize;

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
    /// Decide the final facet too ([`CertificateMode::Facet`]), not only a flock left.
    facet: bool,
}

impl Certificate for TrialCertificate<'_> {
    fn decided(&self, s: &crate::dynamics::engine::world::BodyState) -> Option<Decided> {
        if let Some(f) = self.energy.facet(s).filter(|_| self.facet) {
            return Some(Decided::Facet(f));
        }
        self.energy.flock(s).filter(|&k| k != self.start_flock).map(|k| Decided::Flock(k as u32))
    }
}

/// Run one trial: rest on `start`, kick, simulate to rest.
pub fn trial(stone: &Stone, start: usize, p: &RestingParams, family: Family, epsilon: f64, seed: u64, k: u32) -> Trial {
    let s = &stone.stable()[start];
    let mut rng = item_rng(seed, stream_index(family, start, k));
    let mut sim = resting_simulation(stone, start, p, p.settle_time);
    let (q, z) = sim.pose();
    let (v, w, _) = kick(stone, s.facet, &q, z, family, epsilon, &mut rng);
    sim.set_velocity(&v, &w);
    let level0 = sim.state().level;
    let mut max_rise: f64 = 0.0;
    let energy = EnergyCertificate::new(stone, CertificateMode::Facet).expect("a facet certificate");
    let cert = TrialCertificate { energy, start_flock: s.flock, facet: p.certificate == CertificateMode::Facet };
    let none = crate::dynamics::engine::run::NoCertificate;
    let cert: &dyn Certificate = if p.certificate == CertificateMode::None { &none } else { &cert };
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
