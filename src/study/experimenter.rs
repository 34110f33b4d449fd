//! The dynamic synthetic hand experiment: a simulated person who sets the pebble down in random
//! orientations and notes the distinct stable flocks it comes to rest in.

use crate::analysis::Analysis;
use crate::dynamics::certificate::CertificateMode;
use crate::dynamics::drops::montecarlo::{run_and_summarize, RunHeader};
use crate::dynamics::drops::params::{DropParams, Preset};
use crate::dynamics::size::REFERENCE_R_MAX_M;
use crate::dynamics::size::{RealSize, Size};
use crate::dynamics::stone::Stone;
use crate::dynamics::surface::Surface;
use crate::equilibria::Kind;
use crate::Result;
use serde::Serialize;
use std::collections::BTreeSet;

/// The simulated hand experimenter of [`hand_experiment`].
#[derive(Clone, Debug, Serialize)]
pub struct Experimenter {
    /// Times the pebble is set down (a person's budget).
    pub trials: u64,
    /// Drop parameters; `height` (in R_max) is the small height it is let go from.
    pub params: DropParams,
    /// Seed of the experimenter's hands (mixed with each pebble's id).
    pub seed: u64,
    /// Metres per mesh unit of the pebbles: each is set down at its real size, the rolling
    /// resistance and torsional friction of `params` (set for R_max = [`REFERENCE_R_MAX_M`])
    /// rescaled to it through [`RealSize::resolve`]. None: every pebble is set down as a stone of
    /// R_max = [`REFERENCE_R_MAX_M`] whatever its mesh size (the size is then assumed, which the
    /// command line and the Python binding say).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub length_unit_m: Option<f64>,
}

/// Default budget of the simulated experimenter.
pub const DEFAULT_TRIALS: u64 = 20;
/// Default release height of the simulated experimenter, in R_max: a pebble put down by hand.
pub const DEFAULT_SET_DOWN_HEIGHT: f64 = 0.05;

/// The contact and launch of a pebble set down by hand: the [`Preset::Drop`] protocol (from rest,
/// no spin) on [`Surface::StoneOnStone`], released [`DEFAULT_SET_DOWN_HEIGHT`] above the ground.
pub fn set_down_params() -> DropParams {
    let mut p = Preset::Drop.params(Surface::StoneOnStone);
    p.launch.height = DEFAULT_SET_DOWN_HEIGHT;
    p
}

impl Default for Experimenter {
    fn default() -> Self {
        Experimenter { trials: DEFAULT_TRIALS, params: set_down_params(), seed: 1, length_unit_m: None }
    }
}

/// What the simulated experimenter found on one pebble.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DynamicCounts {
    /// Times the pebble was set down.
    pub trials: u64,
    /// Trials that came to rest (the others were still moving at the time cap).
    pub settled: u64,
    /// Distinct stable flocks found: the dynamic S.
    pub stable: usize,
    /// Distinct unstable or saddle flocks rested in (rocking equilibria found).
    pub rocking: usize,
    /// Ids of every flock found (flocks of G(ν)).
    pub found: Vec<usize>,
}

/// Set the analysed pebble down `exp.trials` times in uniformly random orientations from
/// `exp.params.height` (in R_max) and count the distinct flocks of G(ν) it rests in. Trial i
/// uses [`item_rng`](crate::rng::item_rng)`(seed, i)`. A trial settling on a facet that is not stable counts for the
/// flock its steepest descent drains to; a trial still moving at the time cap counts for nothing.
pub fn hand_experiment(a: &Analysis, nu: f64, exp: &Experimenter, seed: u64) -> Result<DynamicCounts> {
    let stone = Stone::new(a, nu)?;
    let mut params = exp.params.clone();
    if let Some(u) = exp.length_unit_m {
        let size = RealSize::resolve("", stone.body.r_max, Some(Size::Unit(u)))?;
        params.sim.contact.rolling_resistance *= REFERENCE_R_MAX_M / size.r_max_m;
        params.sim.contact.torsional_friction *= REFERENCE_R_MAX_M / size.r_max_m;
    }
    let header = RunHeader::of_params("", seed, exp.trials, params, CertificateMode::Flock);
    let (_, outcomes) = run_and_summarize(&stone, &header);
    let mut found = BTreeSet::new();
    let mut settled = 0;
    for o in outcomes.values().filter(|o| o.settled) {
        settled += 1;
        // Facets of outcomes are stable facets (the rule of `Stone::rest`).
        if let Some(k) = o.flock_in(&stone.facet_flock) {
            found.insert(k);
        }
    }
    let kinds = &stone.flock_kinds;
    let stable = found.iter().filter(|&&k| kinds[k] == Kind::Stable).count();
    Ok(DynamicCounts {
        trials: exp.trials,
        settled,
        stable,
        rocking: found.len() - stable,
        found: found.into_iter().collect(),
    })
}
