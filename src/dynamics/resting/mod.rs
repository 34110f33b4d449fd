//! A stone put exactly at rest on one of its stable micro-equilibria — the start of every push,
//! spin and shaking run — and the parameters of those runs (pushes and shaking,
//! `docs/methods.md`); [`outcome`] says what became of it.
//!
//! The stone is placed with its facet F on the ground (the orientation maps F's outward normal
//! to −z, with no turn about the vertical), G at height R_F above the ground, zero velocity, and
//! left to settle for [`RestingParams::settle_time`] so that the soft contacts take their load
//! ([`resting_simulation`]). [`check_rest`] holds it there longer, undisturbed, and says whether
//! it stays.
//!
//! # One contact for every command
//!
//! Pushes, spins, ground shaking and field rocks run on the contact that drops were calibrated
//! and validated with ([`crate::dynamics::engine::contact`]): Coulomb friction and restitution of a surface pair
//! ([`Surface`]), and rolling resistance and torsional friction *through the contact* with the
//! pair's physical lever arm δ divided by the stone's real size R_max — no global damping, which
//! would also slow a stone that rocks freely or flies. [`RestingParams::on_surface`] builds them;
//! the size enters only through δ / R_max (every other group is Froude-invariant, see
//! [`crate::dynamics::engine::params`]). The overdamped contact the perturbation results were first computed with
//! (global angular damping 1 s⁻¹ on the scaled body, no rolling resistance) survives only as the
//! explicitly named reference [`RestingPreset::Damped`] ([`RestingParams::damped`]).

use crate::dynamics::certificate::CertificateMode;
use crate::dynamics::engine::params::{ContactParams, Flight, FlightParams, Numerics, RestParams, RunParams};
use crate::dynamics::engine::simulation::Simulation;
use crate::dynamics::stone::{resting_orientation, Class, StableEquilibrium, Stone};
use crate::dynamics::surface::Surface;
use crate::monitor::{self, Monitor};
use crate::{Error, Result, Vec3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// Default natural frequency (Hz) of the contacts of resting runs; see
/// [`RestingParams::contact_frequency`].
pub const CONTACT_FREQUENCY: f64 = 120.0;

/// Time step (s, of the scaled body) of every run that starts at rest: its own, not the drop
/// preset's, so that a change of the drops' numerics (e.g. a longer default step) cannot move a
/// push, a shaking run or a field rock. The contact at [`CONTACT_FREQUENCY`] and the rocking
/// thresholds of `results/fig11_rocking_vs_regular/` were measured with it.
pub const RESTING_DT: f64 = crate::dynamics::engine::params::REFERENCE_DT;

/// Which contact a run that starts at rest uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RestingPreset {
    /// The contact of a surface pair at the stone's real size ([`RestingParams::on_surface`]):
    /// the physics of drops and field rocks. The default.
    #[default]
    Surface,
    /// The overdamped reference ([`RestingParams::damped`]): friction 0.6, restitution 0.2,
    /// global damping 0.1 s⁻¹ linear and 1 s⁻¹ angular on the scaled body, no rolling
    /// resistance — what the perturbation and shaking results were computed with before they
    /// moved to the surface contact (`results/one_physics/`); kept to compare with them, never a
    /// default.
    Damped,
}

impl RestingPreset {
    /// Both presets.
    pub const ALL: [RestingPreset; 2] = [RestingPreset::Surface, RestingPreset::Damped];

    /// The user-facing name.
    pub fn name(self) -> &'static str {
        match self {
            RestingPreset::Surface => "surface",
            RestingPreset::Damped => "damped",
        }
    }
}

impl fmt::Display for RestingPreset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for RestingPreset {
    type Err = Error;
    fn from_str(s: &str) -> Result<RestingPreset> {
        RestingPreset::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| Error::unknown("contact model", s, &["surface", "damped"]))
    }
}

/// Parameters of runs that start at rest on a stable micro-equilibrium: pushes, spins, ground
/// shaking and field rocks. Every field documents its default, which is
/// [`RestingParams::on_surface`]`(`[`Surface::StoneOnStone`]`, 1 m)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RestingParams {
    /// The surface pair whose contact `sim` holds (None: the damped reference, or parameters
    /// made by hand). Said by the summaries; absent from files of earlier versions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<Surface>,
    /// Contact, time step, time cap, rest thresholds and flight. Default: the surface pair's
    /// contact at the stone's real size (friction, restitution, rolling resistance and torsional
    /// friction δ / R_max, no global damping, as a drop's), dt 1/240 s, 4 solver iterations, a
    /// cap of 20 s (scaled) after the perturbation or the motion, rest by the drops' speeds held
    /// for 0.5 s, impacts sub-stepped.
    pub sim: RunParams,
    /// Settling time (s, scaled) on the equilibrium before the perturbation. Default 0.25 s.
    pub settle_time: f64,
    /// Extra time (s, scaled) of undisturbed rest in the check that the stone stays on its
    /// equilibrium. Default 1 s.
    pub hold_time: f64,
    /// Natural frequency (Hz, scaled) of rapier's soft contact constraints (rapier's default:
    /// 30 Hz against moving bodies, which the kinematic ground is, 60 Hz against fixed ones;
    /// both are set to this). Default 120 Hz. A stone on a micro-facet a hundredth of R_max
    /// wide stands on a spring foundation whose rotational stiffness must beat the overturning
    /// m g R_F θ: at 30 Hz it does not for the shallowest facets. Measured on the bundled stone
    /// (15 stable micro-equilibria, damped contact): 8 stay at rest at 30 Hz, 11 at 60 Hz, 14 at
    /// 120 and 240 Hz (the last one's G is 0.0013 R_F from its facet's edge), and only 8 at
    /// 480 Hz, where the stiff contact starts to jitter at dt = 1/240 s.
    pub contact_frequency: f64,
    /// End a trial early by the energy certificate: [`CertificateMode::Facet`] once the final
    /// facet is certain or a flock other than the start's is, [`CertificateMode::Flock`] only
    /// once a flock other than the start's is certain (a trial that stays in its flock runs on
    /// to rest, so that same equilibrium and neighbour are still told apart). Default
    /// [`CertificateMode::None`]: the check that no trial crosses a static barrier is only
    /// meaningful without it. Written `false` / `true` / `"flock"` (files of earlier versions
    /// have the two booleans).
    #[serde(with = "certificate_field")]
    pub certificate: CertificateMode,
}

pub mod outcome;

/// [`RestingParams::certificate`] as files write it: `false` (none), `true` (facet) or
/// `"flock"`.
mod certificate_field {
    use crate::dynamics::certificate::CertificateMode;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Serialize, Deserialize)]
    #[serde(untagged)]
    enum Field {
        Bool(bool),
        Name(CertificateMode),
    }

    pub fn serialize<S: Serializer>(m: &CertificateMode, s: S) -> Result<S::Ok, S::Error> {
        match m {
            CertificateMode::None => Field::Bool(false),
            CertificateMode::Facet => Field::Bool(true),
            CertificateMode::Flock => Field::Name(CertificateMode::Flock),
        }
        .serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<CertificateMode, D::Error> {
        Ok(match Field::deserialize(d)? {
            Field::Bool(false) => CertificateMode::None,
            Field::Bool(true) => CertificateMode::Facet,
            Field::Name(m) => m,
        })
    }
}

/// Time cap (s, scaled) after a perturbation or a ground motion.
pub const RESTING_MAX_TIME: f64 = 20.0;

/// Rest window (s, scaled) of runs that start at rest: the speeds (pushes) or positions (shaking,
/// field rocks) must stay still this long.
pub const RESTING_REST_TIME: f64 = 0.5;

impl Default for RestingParams {
    fn default() -> Self {
        Self::on_surface(Surface::StoneOnStone, 1.0).expect("1 m is a valid size")
    }
}

impl RestingParams {
    /// The contact of `surface` for a stone of real size R_max = `r_max_m` metres (module docs):
    /// the pair's contact at that size, as a drop's
    /// ([`crate::dynamics::surface::Surface::scaled`], no global damping), with the numerics of
    /// resting runs
    /// ([`RESTING_DT`], impacts sub-stepped: [`Flight::Free`]), a cap of [`RESTING_MAX_TIME`],
    /// rest held for [`RESTING_REST_TIME`], contacts at [`CONTACT_FREQUENCY`]. A size that is not
    /// a positive finite length is refused.
    pub fn on_surface(surface: Surface, r_max_m: f64) -> Result<RestingParams> {
        if !(r_max_m > 0.0 && r_max_m.is_finite()) {
            return Err(Error::parameter("size", r_max_m, "a positive length in metres (R_max)"));
        }
        let mut contact = ContactParams::default();
        surface.scaled(&mut contact, r_max_m);
        let sim = RunParams {
            contact,
            numerics: Numerics { dt: RESTING_DT, max_time: RESTING_MAX_TIME, ..Numerics::default() },
            rest: RestParams { rest_time: RESTING_REST_TIME, ..RestParams::default() },
            flight: FlightParams { mode: Flight::Free, strict_impacts: false },
        };
        Ok(RestingParams {
            surface: Some(surface),
            sim,
            settle_time: 0.25,
            hold_time: 1.0,
            contact_frequency: CONTACT_FREQUENCY,
            certificate: CertificateMode::None,
        })
    }

    /// The overdamped reference contact ([`RestingPreset::Damped`]): friction 0.6, restitution
    /// 0.2, global damping 0.1 s⁻¹ linear and 1 s⁻¹ angular standing in for rolling resistance,
    /// no rolling resistance, dt 1/240 s, cap 20 s, rest by speeds held 0.25 s. Independent of
    /// size (the damping rates are those of the scaled body).
    pub fn damped() -> RestingParams {
        let defaults = RunParams::default();
        let sim = RunParams {
            contact: ContactParams {
                friction: 0.6,
                restitution: 0.2,
                rolling_resistance: 0.0,
                torsional_friction: 0.0,
                linear_damping: 0.1,
                angular_damping: 1.0,
            },
            numerics: Numerics { max_time: RESTING_MAX_TIME, dt: RESTING_DT, ..defaults.numerics },
            rest: defaults.rest,
            // The old numerics with the old contact: rapier's own steps, impacts not sub-stepped.
            flight: FlightParams { mode: Flight::Rapier, ..defaults.flight },
        };
        RestingParams {
            surface: None,
            sim,
            settle_time: 0.25,
            hold_time: 1.0,
            contact_frequency: CONTACT_FREQUENCY,
            certificate: CertificateMode::None,
        }
    }

    /// The parameters of `preset`: [`RestingParams::on_surface`] or [`RestingParams::damped`]
    /// (which ignores the surface and the size).
    pub fn of(preset: RestingPreset, surface: Surface, r_max_m: f64) -> Result<RestingParams> {
        match preset {
            RestingPreset::Surface => Self::on_surface(surface, r_max_m),
            RestingPreset::Damped => Ok(Self::damped()),
        }
    }

    /// Refuse parameters that cannot describe a run.
    pub fn check(&self) -> Result<()> {
        self.sim.check()?;
        if !(self.settle_time >= 0.0 && self.settle_time.is_finite()) {
            return Err(Error::parameter("settle_time", self.settle_time, "≥ 0 and finite"));
        }
        if !(self.contact_frequency > 0.0 && self.contact_frequency.is_finite()) {
            return Err(Error::parameter("contact_frequency", self.contact_frequency, "positive and finite"));
        }
        if !(self.hold_time >= 0.0 && self.hold_time.is_finite()) {
            return Err(Error::parameter("hold_time", self.hold_time, "≥ 0 and finite"));
        }
        Ok(())
    }
}

/// A regular and a rocking stable micro-equilibrium to compare (positions in
/// [`Stone::stable`]): the regular one with the smallest R (the deepest rest of the stone),
/// and the rocking one with the highest barrier out of its basin (the most convincingly
/// balanced rocking position), each among those that stay at rest (checked with `p`). Either
/// may be missing.
pub fn default_pair(stone: &Stone, p: &RestingParams) -> (Option<usize>, Option<usize>) {
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
pub fn resting_simulation<'a>(stone: &'a Stone, eq: usize, p: &RestingParams, time: f64) -> Simulation<'a> {
    let s = &stone.stable()[eq];
    let q = resting_orientation(&stone.body.facet_normals[s.facet as usize]);
    let mut sim = Simulation::new(&stone.body, &p.sim, &q, s.r_normalised, &Vec3::zeros(), &Vec3::zeros());
    sim.set_contact_frequency(p.contact_frequency);
    sim.advance((time / p.sim.numerics.dt).round() as u64);
    sim
}

/// Put the stone on `eq`, let it settle and hold, and check that it stays.
pub fn check_rest(stone: &Stone, eq: usize, p: &RestingParams) -> SettleCheck {
    let s = &stone.stable()[eq];
    let sim = resting_simulation(stone, eq, p, p.settle_time + p.hold_time);
    let st = sim.state();
    let n = stone.body.facet_normals[s.facet as usize];
    let facet_reached = stone.rest(&st.down).facet;
    let (speed, angular_speed) = (st.linvel.norm(), st.angvel.norm());
    SettleCheck {
        stays: facet_reached == s.facet
            && speed < p.sim.rest.rest_linear_speed
            && angular_speed < p.sim.rest.rest_angular_speed,
        tilt: n.dot(&st.down).clamp(-1.0, 1.0).acos(),
        sink: s.r_normalised - st.z,
        speed,
        angular_speed,
        facet_reached,
    }
}

/// The grid of trials of a perturbation or shaking run: check that the stone stays at rest on
/// every start (in parallel), then run `trial(start, point, k)` for every start that stays, every
/// grid point and every trial number, in parallel, in a fixed order (so the result does not
/// depend on the thread count), telling `monitor` of each; [`Error::Cancelled`] if it stops the
/// run.
pub fn grid_trials<T: Send>(
    stone: &Stone,
    starts: &[usize],
    p: &RestingParams,
    points: usize,
    trials: u32,
    monitor: &dyn Monitor,
    trial: impl Fn(usize, usize, u32) -> T + Sync,
) -> Result<(Vec<SettleCheck>, Vec<T>)> {
    let checks: Vec<SettleCheck> = starts.par_iter().map(|&s| check_rest(stone, s, p)).collect();
    let tasks: Vec<(usize, usize, u32)> = starts
        .iter()
        .zip(&checks)
        .filter(|(_, c)| c.stays)
        .flat_map(|(&s, _)| (0..points).flat_map(move |i| (0..trials).map(move |k| (s, i, k))))
        .collect();
    let out = tasks.par_iter().map(|&(s, i, k)| monitor::item(monitor, || trial(s, i, k))).collect();
    Ok((checks, monitor::all(out)?))
}
