//! The parameters of a drop: its [`Launch`] and the engine's [`RunParams`] — and the named
//! presets that set both (drops, `docs/methods.md`). The units are the scaled frame's
//! ([`crate::dynamics::engine::params`]); the contact comes from a surface pair
//! ([`crate::dynamics::surface::Surface`]).

use crate::dynamics::engine::params::{
    ContactParams, Flight, FlightParams, Numerics, RestParams, RunParams, MAX_STABLE_DT, REFERENCE_DT,
};
use crate::dynamics::size::REFERENCE_R_MAX_M;
use crate::dynamics::surface::Surface;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// How the angular velocity of a launch is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SpinDistribution {
    /// |ω| = `spin` exactly, about a uniformly random axis.
    Fixed,
    /// ω isotropic Gaussian: each component normal with mean 0 and standard deviation
    /// `spin`/√3, so the root-mean-square |ω| is `spin` (|ω| has a Maxwell distribution). A hand
    /// throw does not give every die the same spin; this is the maximum-entropy law with a given
    /// mean rotational energy.
    Gaussian,
}

/// How a drop starts: the release above the ground (scaled frame). Every field documents its
/// default, the calibrated [`Preset::Throw`] (`results/cuboid_dice/`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Launch {
    /// Release height of the lowest hull point above the ground, in R_max. Default: the
    /// calibrated throw's, [`THROW_HEIGHT`] = 2.
    pub height: f64,
    /// Horizontal speed of G at release (m/s of the scaled body), along a uniformly random
    /// azimuth. Default: the calibrated throw's, [`THROW_HORIZONTAL_SPEED`] = 4.
    pub horizontal_speed: f64,
    /// Angular speed at release (rad/s of the scaled body): exact or root-mean-square, see
    /// `spin_distribution`. Default: the calibrated throw's, [`THROW_SPIN`] = 25.
    pub spin: f64,
    /// Law of the release angular velocity. Default: [`SpinDistribution::Gaussian`].
    pub spin_distribution: SpinDistribution,
}

impl Default for Launch {
    fn default() -> Self {
        Launch {
            height: THROW_HEIGHT,
            horizontal_speed: THROW_HORIZONTAL_SPEED,
            spin: THROW_SPIN,
            spin_distribution: SpinDistribution::Gaussian,
        }
    }
}

impl Launch {
    /// Released at rest (no speed, no spin) with the lowest hull point `height` R_max above the
    /// ground.
    pub fn at_rest(height: f64) -> Launch {
        Launch { height, horizontal_speed: 0.0, spin: 0.0, spin_distribution: SpinDistribution::Fixed }
    }

    /// Refuse a launch that cannot describe a release, naming the parameter.
    pub fn check(&self) -> Result<()> {
        let non_negative = [("height", self.height), ("horizontal_speed", self.horizontal_speed), ("spin", self.spin)];
        if let Some((name, v)) = non_negative.iter().find(|(_, v)| !(*v >= 0.0 && v.is_finite())) {
            return Err(Error::parameter(name, v, "≥ 0 and finite"));
        }
        Ok(())
    }
}

/// Parameters of a drop: its launch and the run of the engine (scaled frame; both serialised at
/// one level, as every report and checkpoint writes them). The default is the calibrated
/// [`Preset::Throw`] on steel on wood for a stone of R_max = 1 cm, which is also each group's
/// own default.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DropParams {
    /// How the stone is released.
    #[serde(flatten)]
    pub launch: Launch,
    /// Contact, numerics, rest rule and flight of the run.
    #[serde(flatten)]
    pub sim: RunParams,
}

impl Default for DropParams {
    fn default() -> Self {
        Preset::Throw.params(Surface::SteelOnWood)
    }
}

impl DropParams {
    /// Refuse parameters that cannot describe a drop, naming the parameter (its field name,
    /// [`Error::Parameter`]) and the value.
    pub fn check(&self) -> Result<()> {
        self.sim.check()?;
        self.launch.check()
    }
}

/// Named, documented launch protocols (drops, `docs/methods.md`). Each sets the launch and the
/// numerics; the contact comes from a [`Surface`]. Every field can still be overridden.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Preset {
    /// The overdamped limit of the quasi-static basins: released at rest touching the ground
    /// (height 10⁻³ R_max), no restitution, strong global damping 10 s⁻¹ (linear and angular) so
    /// the body creeps down the support function. Drops under it converge to the basin
    /// probabilities (measured in `results/drops_quasistatic_limit/`: micro-facet KL 0.008 at
    /// 10 s⁻¹).
    QuasiStatic,
    /// Released from rest (no spin, no horizontal speed) with the lowest point 1 R_max above the
    /// ground: a stone let fall from the hand.
    Drop,
    /// A hand throw onto a table: released 2 R_max above it with 4 m/s (scaled) of horizontal
    /// speed and a Gaussian angular velocity of 25 rad/s rms (scaled): fitted to the seven measured
    /// dice of `data/cuboid_dice_throws.csv` with exact landings ([`Flight::Free`]), and inside the
    /// calibration's Monte Carlo noise band with the default numerics of every later change
    /// (`results/cuboid_dice/`, which lists the grid points within the band; a point within it is
    /// not moved to the grid's best, that would fit noise). For a 16 mm die:
    /// 2.8 cm, 0.5 m/s, 34 turns/s. (With rapier's own flight the same fit gave H 5, Ω 35: its
    /// impacts, which started inside the table, took energy the launch had to make up.)
    Throw,
}

impl Preset {
    /// Every preset, in the order of the documentation.
    pub const ALL: [Preset; 3] = [Preset::QuasiStatic, Preset::Drop, Preset::Throw];

    /// The user-facing name (as `--preset` takes it).
    pub fn name(self) -> &'static str {
        match self {
            Preset::QuasiStatic => "quasi-static",
            Preset::Drop => "drop",
            Preset::Throw => "throw",
        }
    }

    /// The default time step of this preset: the longest at which its statistics are those of the
    /// reference step [`REFERENCE_DT`] (1/240 s), measured in `results/drops_dt/` on three bodies:
    /// per-flock χ² homogeneity against 1/240 s (as many tests below 0.05 up to 1/80 s as chance
    /// gives), every drop settled, the contact's
    /// compression at rest and the energy rise where the certificate decides under its margin.
    /// All three presets pass up to 1/80 s; the step is capped at the longest the contact check
    /// accepts, [`MAX_STABLE_DT`] = 1/120 s.
    pub fn largest_stable_dt(self) -> f64 {
        match self {
            Preset::QuasiStatic | Preset::Drop | Preset::Throw => MAX_STABLE_DT,
        }
    }

    /// The reference numerics of this preset (`rocking drop --reference`): free flight
    /// ([`Flight::Free`]) at [`REFERENCE_DT`] = 1/240 s, the step its default
    /// ([`Preset::largest_stable_dt`], 1/120 s, the former `--fast` before it became the default)
    /// is checked against: per-flock statistics the same on independent samples
    /// (`results/cuboid_dice/`) and drop by drop (the paired test on the same releases,
    /// `results/drops_vs_mujoco/`); every throw of every mesh of `data/meshes` and of the bundled
    /// stone settles at both steps (`results/drops_settling/`) since a stone resting on a stable
    /// facet is carried by it and rolling resistance turns it about its contact
    /// (`dynamics::engine::hull_shape`, `dynamics::engine::contact`).
    pub fn reference(self, p: &mut DropParams) {
        p.sim.flight.mode = Flight::Free;
        p.sim.numerics.dt = REFERENCE_DT;
    }

    /// The parameters of this preset on `surface`, for a stone of the reference size
    /// [`REFERENCE_R_MAX_M`].
    pub fn params(self, surface: Surface) -> DropParams {
        self.params_for_size(surface, REFERENCE_R_MAX_M)
    }

    /// The parameters of this preset on `surface` for a stone of real size R_max = `size` metres
    /// when it is given, else of the reference size [`REFERENCE_R_MAX_M`] (what `rocking drop
    /// --preset P --surface S [--size L]` starts from).
    pub fn params_for(self, surface: Surface, size: Option<f64>) -> Result<DropParams> {
        match size {
            Some(r) => self.params_at_size(surface, r),
            None => Ok(self.params(surface)),
        }
    }

    /// The parameters of this preset on `surface` for a stone of real size R_max = `r_max_m`
    /// metres (the surface's rolling-resistance length is divided by it); a size that is not a
    /// positive finite length is a usage error.
    pub fn params_at_size(self, surface: Surface, r_max_m: f64) -> Result<DropParams> {
        if !(r_max_m > 0.0 && r_max_m.is_finite()) {
            return Err(Error::parameter("size", r_max_m, "a positive length in metres (R_max)"));
        }
        Ok(self.params_for_size(surface, r_max_m))
    }

    fn params_for_size(self, surface: Surface, r_max_m: f64) -> DropParams {
        let mut contact = ContactParams::default();
        surface.scaled(&mut contact, r_max_m);
        let sim = RunParams {
            contact,
            numerics: Numerics { dt: self.largest_stable_dt(), ..Numerics::default() },
            rest: RestParams::default(),
            flight: FlightParams { mode: Flight::Free, strict_impacts: false },
        };
        let still =
            Launch { height: 1.0, horizontal_speed: 0.0, spin: 0.0, spin_distribution: SpinDistribution::Gaussian };
        match self {
            Preset::QuasiStatic => {
                let mut p = DropParams { launch: Launch { height: 1e-3, ..still }, sim };
                let c = &mut p.sim.contact;
                (c.restitution, c.linear_damping, c.angular_damping) = (0.0, 10.0, 10.0);
                p
            }
            Preset::Drop => DropParams { launch: still, sim },
            Preset::Throw => DropParams { launch: Launch::default(), sim },
        }
    }
}

/// Calibrated release height of [`Preset::Throw`] (R_max), see `results/cuboid_dice/`.
pub const THROW_HEIGHT: f64 = 2.0;
/// Calibrated horizontal speed of [`Preset::Throw`] (m/s of the scaled body), see `results/cuboid_dice/`.
pub const THROW_HORIZONTAL_SPEED: f64 = 4.0;
/// Calibrated rms spin of [`Preset::Throw`] (rad/s of the scaled body), see `results/cuboid_dice/`.
pub const THROW_SPIN: f64 = 25.0;

impl fmt::Display for Preset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Preset {
    type Err = Error;
    fn from_str(s: &str) -> Result<Preset> {
        Preset::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| Error::unknown("preset", s, &["quasi-static", "drop", "throw"]))
    }
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_parse_their_names_and_pass_the_check() {
        for p in Preset::ALL {
            assert_eq!(p.name().parse::<Preset>().unwrap(), p);
            for s in Surface::ALL {
                p.params(s).check().unwrap();
            }
        }
        assert!("fling".parse::<Preset>().is_err());
        // No global damping except in the overdamped limit.
        assert_eq!(DropParams::default().sim.contact.angular_damping, 0.0);
        assert!(Preset::QuasiStatic.params(Surface::StoneOnStone).sim.contact.angular_damping > 0.0);
    }

    #[test]
    fn the_default_of_every_group_is_the_calibrated_throw_on_steel_on_wood() {
        let groups = DropParams { launch: Launch::default(), sim: RunParams::default() };
        assert_eq!(groups, Preset::Throw.params(Surface::SteelOnWood));
        assert_eq!(DropParams::default(), Preset::Throw.params(Surface::SteelOnWood));
        // The groups are not all alike: a drop from rest is not the default launch.
        assert_ne!(Preset::Drop.params(Surface::SteelOnWood).launch, Launch::default());
    }

    #[test]
    fn the_serialised_form_is_flat_and_in_the_order_of_the_fields_before_the_split() {
        let json = serde_json::to_string(&DropParams::default()).unwrap();
        let keys: Vec<&str> = json.split('"').skip(1).step_by(2).filter(|k| !k.is_empty()).collect();
        let expected = [
            "height",
            "horizontal_speed",
            "spin",
            "spin_distribution",
            "gaussian",
            "friction",
            "restitution",
            "rolling_resistance",
            "torsional_friction",
            "linear_damping",
            "angular_damping",
            "dt",
            "solver_iterations",
            "max_time",
            "rest_linear_speed",
            "rest_angular_speed",
            "rest_time",
            "flight",
            "free",
        ];
        assert_eq!(keys, expected);
        let back: DropParams = serde_json::from_str(&json).unwrap();
        assert_eq!(back, DropParams::default());
        // A checkpoint written before the flight mode existed ran rapier's flight.
        let old = json.replace(",\"flight\":\"free\"", "");
        assert_eq!(serde_json::from_str::<DropParams>(&old).unwrap().sim.flight.mode, Flight::Rapier);
    }

    #[test]
    fn a_run_from_rest_has_the_contact_of_a_drop_and_its_own_numerics() {
        use crate::dynamics::resting::{RestingParams, RESTING_DT};
        for s in Surface::ALL {
            let (drop, rest) =
                (Preset::Drop.params_at_size(s, 0.3).unwrap(), RestingParams::on_surface(s, 0.3).unwrap());
            assert_eq!(rest.sim.contact, drop.sim.contact);
            assert_eq!(rest.sim.numerics.solver_iterations, drop.sim.numerics.solver_iterations);
            assert_eq!(rest.sim.numerics.dt, RESTING_DT);
            assert_ne!(rest.sim.numerics.dt, drop.sim.numerics.dt);
        }
        assert!(RestingParams::on_surface(Surface::StoneOnStone, -1.0).is_err());
    }

    #[test]
    fn nonsense_parameters_are_refused_with_their_name() {
        let name = |f: &dyn Fn(&mut DropParams)| {
            let mut p = DropParams::default();
            f(&mut p);
            match p.check().unwrap_err() {
                Error::Parameter { name, .. } => name,
                e => panic!("not a parameter error: {e}"),
            }
        };
        assert_eq!(name(&|p| p.sim.numerics.dt = 1.0), "dt");
        assert_eq!(name(&|p| p.sim.contact.friction = f64::NAN), "friction");
        assert_eq!(name(&|p| p.sim.contact.restitution = 1.5), "restitution");
        assert_eq!(name(&|p| p.launch.spin = -1.0), "spin");
        assert_eq!(name(&|p| (p.sim.numerics.max_time, p.sim.numerics.dt) = (1e-3, 1e-2)), "dt");
        let mut p = DropParams::default();
        p.sim.contact.restitution = 1.5;
        let e = p.check().unwrap_err();
        assert_eq!(e.to_string(), "restitution must be in [0, 1], got 1.5");
        assert_eq!(e.spelled(&|n| format!("{n}=")), "restitution= must be in [0, 1], got 1.5");
    }
}
