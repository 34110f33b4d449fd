//! What is not known about a field rock ([`Uncertainty`]: base contact, azimuth, sign of the
//! record, friction, restitution, rolling resistance), and one member's draw of it ([`draw`]).

use crate::dynamics::shaking::ensemble::base::{BaseDraw, BaseUncertainty};
use crate::dynamics::shaking::rock::RockSetup;
use crate::dynamics::surface::Surface;
use crate::rng::item_rng;
use crate::{Error, Result};
use rand::RngExt;
use serde::{Deserialize, Serialize};

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
    /// How the hidden base meets the ground ([`super::base`]): every member draws its own base
    /// and stands on it as the scan stands. Absent: the scan's base (a field scan's nominal flat
    /// cap), in every member.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<BaseUncertainty>,
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
    /// units — base-contact tolerance and δ in mm, azimuth in degrees. Friction, restitution and
    /// δ not given range over `surface`'s ranges ([`Surface::ranges`]) unless `pinned` (the user
    /// set that value: friction, restitution, rolling resistance).
    pub fn stated(given: &Uncertainty, surface: Surface, pinned: [bool; 3]) -> Uncertainty {
        let r = surface.ranges();
        let or_surface = |x: Option<[f64; 2]>, pinned: bool, default: [f64; 2]| match x {
            Some(x) => Some(x),
            None if pinned => None,
            None => Some(default),
        };
        Uncertainty {
            contact_tolerance_m: given.contact_tolerance_m.map(|t| t.map(|x| x * 1e-3)),
            azimuth_deg: given.azimuth_deg,
            random_sign: given.random_sign,
            friction: or_surface(given.friction, pinned[0], r.friction),
            restitution: or_surface(given.restitution, pinned[1], r.restitution),
            rolling_resistance_m: or_surface(
                given.rolling_resistance_m.map(|d| d.map(|x| x * 1e-3)),
                pinned[2],
                r.rolling_resistance_m,
            ),
            base: given.base,
        }
    }

    /// Every range ordered, finite and physical (friction ≥ 0, restitution in [0, 1], lengths
    /// ≥ 0); else a parameter error naming it.
    pub fn check(&self) -> Result<()> {
        if let Some(b) = &self.base {
            b.check()?;
        }
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
            base: None,
        }
    }

    /// Whether the azimuth is unknown: it spans the whole circle.
    pub(crate) fn azimuth_unknown(&self) -> bool {
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
    /// The member's drawn base ([`super::base`]), if the base is uncertain.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<BaseDraw>,
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
        base: None,
    }
}
