//! Parameters of a simulated run: the launch, the contact, the numerics — and the named presets
//! and surface pairs that set them (drops, `docs/methods.md`).
//!
//! **Units.** Every run is simulated in the stone's scaled frame: lengths in units of R_max (the
//! largest distance from G to a hull corner), mass 1, g = 9.81 m/s². Rigid-body dynamics with
//! Coulomb friction, restitution and a rolling-resistance *length* is invariant under Froude
//! scaling, so only dimensionless groups matter: height / R_max, speed / √(g R_max),
//! spin · √(R_max / g), δ / R_max. A number given here for the scaled body (R_max = 1 m) converts
//! to a real stone of size R_max = L (metres) as
//!
//! ```text
//! length_real = length · L,   speed_real = speed · √L,   spin_real = spin / √L,   time_real = time · √L
//! ```
//!
//! (e.g. a spin of 5 rad/s of the scaled body is 5/√0.01 = 50 rad/s for a die with R_max = 1 cm).
//! [`Surface::scaled`] turns the surface pair's physical rolling-resistance length into δ / R_max
//! for a stone of a given size.

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

/// Parameters of a run, in the scaled frame (see the module docs). Every field documents its
/// default, which is the calibrated [`Preset::Throw`] on [`Surface::SteelOnWood`] (see
/// `results/cuboid_dice/`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DropParams {
    /// Release height of the lowest hull point above the ground, in R_max. Default: the
    /// calibrated throw's.
    pub height: f64,
    /// Horizontal speed of G at release (m/s of the scaled body), along a uniformly random
    /// azimuth. Default: the calibrated throw's.
    pub horizontal_speed: f64,
    /// Angular speed at release (rad/s of the scaled body): exact or root-mean-square, see
    /// `spin_distribution`. Default: the calibrated throw's.
    pub spin: f64,
    /// Law of the release angular velocity. Default: [`SpinDistribution::Gaussian`].
    pub spin_distribution: SpinDistribution,
    /// Coulomb friction coefficient of the contact. Default 0.4 (steel on wood).
    pub friction: f64,
    /// Restitution coefficient of the contact. Default 0.5 (steel on wood).
    pub restitution: f64,
    /// Rolling-resistance length δ_r / R_max: the contact's rolling torque is at most δ_r N
    /// ([`crate::dynamics::engine::world`]). Default 0.02: steel on wood (δ = 0.2 mm) for R_max = 1 cm.
    pub rolling_resistance: f64,
    /// Torsional-friction length δ_t / R_max: on a single contact point the torque about the
    /// normal is at most δ_t N (on two or more points rapier's Coulomb twist friction acts instead,
    /// never both: [`crate::dynamics::engine::world`]). Default: equal to `rolling_resistance`.
    pub torsional_friction: f64,
    /// Global linear velocity damping (1/s). Default 0: it would slow a body in flight; kept
    /// for the overdamped [`Preset::QuasiStatic`] limit and for comparison with older runs.
    pub linear_damping: f64,
    /// Global angular velocity damping (1/s). Default 0 (see `linear_damping`).
    pub angular_damping: f64,
    /// Time step (s of the scaled body). Default [`Preset::largest_stable_dt`] = 1/120 s, checked
    /// against [`REFERENCE_DT`] = 1/240 s (`results/drops_dt/`, `results/cuboid_dice/`,
    /// `results/drops_vs_mujoco/`).
    pub dt: f64,
    /// Velocity iterations of rapier's contact solver per step. Default 4 (rapier's).
    pub solver_iterations: usize,
    /// Give up after this long (s of the scaled body). Default 60 s: with rolling resistance
    /// instead of global damping, a smooth pebble thrown onto a table rolls for 5–15 s (scaled)
    /// before it rests (measured on a 400-vertex pebble: mean 9 s at δ = 0.02 R_max).
    pub max_time: f64,
    /// Rest: linear speed below this (m/s, scaled) … Default 2·10⁻³.
    pub rest_linear_speed: f64,
    /// … and angular speed below this (rad/s, scaled) … Default 5·10⁻³.
    pub rest_angular_speed: f64,
    /// … for this long (s). Default 0.25 s.
    pub rest_time: f64,
    /// How a drop's flight between contacts is integrated, and how its impacts start. Default
    /// [`Flight::Free`]: exact landings and sub-stepped impacts ([`crate::dynamics::engine::impact`]), at which the
    /// throw is calibrated (`results/cuboid_dice/`).
    #[serde(default = "Flight::rapier")]
    pub flight: Flight,
    /// Strict impacts: read the sub-step bound of [`crate::dynamics::engine::impact`] again after every impact
    /// sub-step and cut the rest of the step finer where an impulse within the sub-step has turned
    /// the stone faster than the motion at the step's start allowed for (an impact can turn a
    /// spin about the vertical into a tumble). Default false: the count is read at the step's
    /// start, as the calibration and every result in `results/` were computed; with it, a box spun
    /// at 400 rad/s stays within [`crate::dynamics::engine::impact::DEPTH_BOUND`] (0.033 R_max deep without it,
    /// `tests/flight.rs`), and about one ordinary throw in a thousand ends elsewhere.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub strict_impacts: bool,
}

/// How the flight of a dropped stone between contacts is integrated ([`crate::dynamics::engine::flight`]), and
/// with it how impacts start ([`crate::dynamics::engine::impact`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Flight {
    /// Every step in rapier's pipeline, in the air as on the ground: contacts are found only at
    /// the step boundaries, so an impact can start 0.1–0.2 R_max inside the ground in a throw
    /// (`results/drops_impacts/`). The former reference numerics, kept to compare.
    Rapier,
    /// The default. Out of rapier while the stone is clear of the ground: G on its parabola and
    /// the rotation by Euler's equations ([`crate::dynamics::engine::flight`]), handed to rapier at the exact
    /// instant its lowest point comes within [`crate::dynamics::engine::flight::CONTACT_CLEARANCE`] of the ground;
    /// in contact, a step that could bring a hull point down by more than
    /// [`crate::dynamics::engine::impact::IMPACT_APPROACH`] is sub-stepped ([`crate::dynamics::engine::impact`]). Impacts start
    /// outside the ground (deepest compression 9.9·10⁻³ R_max, under the bound of 10⁻², over
    /// 7 200 drops and throws at 1/240 and 1/120 s, `results/drops_impacts/`). Runs that start at rest (pushes, shaking)
    /// sub-step their impacts the same way and keep their flight in rapier. Global damping
    /// (`--linear-damping`, `--angular-damping`) acts in free flight too, exactly
    /// ([`crate::dynamics::engine::flight::Damping`]).
    #[default]
    Free,
}

impl Flight {
    /// Every mode.
    pub const ALL: [Flight; 2] = [Flight::Rapier, Flight::Free];

    /// [`Flight::Rapier`]: what a checkpoint written before the field existed ran with.
    pub fn rapier() -> Flight {
        Flight::Rapier
    }

    /// The user-facing name (as `--flight` takes it).
    pub fn name(self) -> &'static str {
        match self {
            Flight::Rapier => "rapier",
            Flight::Free => "free",
        }
    }
}

impl fmt::Display for Flight {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Flight {
    type Err = Error;
    fn from_str(s: &str) -> Result<Flight> {
        Flight::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| Error::Usage(format!("unknown flight mode {s:?}: expected rapier or free")))
    }
}

impl Default for DropParams {
    fn default() -> Self {
        Preset::Throw.params(Surface::SteelOnWood)
    }
}

impl DropParams {
    /// Refuse parameters that cannot describe a run, naming the parameter (its field name,
    /// [`Error::Parameter`]) and the value.
    pub fn check(&self) -> Result<()> {
        let positive = [("dt", self.dt), ("max_time", self.max_time), ("rest_time", self.rest_time)];
        if let Some((name, v)) = positive.iter().find(|(_, v)| !(*v > 0.0 && v.is_finite())) {
            return Err(Error::parameter(name, v, "positive and finite"));
        }
        let non_negative = [
            ("height", self.height),
            ("horizontal_speed", self.horizontal_speed),
            ("spin", self.spin),
            ("friction", self.friction),
            ("rolling_resistance", self.rolling_resistance),
            ("torsional_friction", self.torsional_friction),
            ("linear_damping", self.linear_damping),
            ("angular_damping", self.angular_damping),
            ("rest_linear_speed", self.rest_linear_speed),
            ("rest_angular_speed", self.rest_angular_speed),
        ];
        if let Some((name, v)) = non_negative.iter().find(|(_, v)| !(*v >= 0.0 && v.is_finite())) {
            return Err(Error::parameter(name, v, "≥ 0 and finite"));
        }
        if !(0.0..=1.0).contains(&self.restitution) {
            return Err(Error::parameter("restitution", self.restitution, "in [0, 1]"));
        }
        if self.solver_iterations == 0 || self.solver_iterations > 1000 {
            return Err(Error::parameter("solver_iterations", self.solver_iterations, "in 1..=1000"));
        }
        if self.dt > self.max_time {
            return Err(Error::parameter(
                "dt",
                self.dt,
                format!("at most the time cap max_time ({} s)", self.max_time),
            ));
        }
        // Contact stability: rapier's soft contacts (30–60 Hz) need several steps per
        // oscillation, and a body must not fall through more than a fraction of itself per step.
        if self.dt > MAX_STABLE_DT {
            return Err(Error::parameter(
                "dt",
                self.dt,
                format!(
                    "at most {MAX_STABLE_DT} s of the scaled body for the contact solver (the soft contacts oscillate \
                     at 30–60 Hz and need ≥ 4 steps per period; the drop presets take this longest step, runs from \
                     rest 1/240 s)"
                ),
            ));
        }
        if self.max_time / self.dt > 1e8 {
            return Err(Error::parameter(
                "max_time",
                self.max_time,
                format!("at most 10⁸ steps of dt = {} s", self.dt),
            ));
        }
        Ok(())
    }

    /// Speed of G when the body first touches the ground (m/s, scaled): √(v_h² + 2 g h).
    pub fn impact_speed(&self) -> f64 {
        (self.horizontal_speed.powi(2) + 2.0 * crate::GRAVITY * self.height).sqrt()
    }
}

/// The longest time step (s, scaled) a run accepts: 1/120 s, four steps per period of the
/// stiffest default contact (30 Hz). Measured: at 1/120 s the cube still lands 1/6 on each face;
/// at dt = 1 s 4 of 5 drops never settle.
pub const MAX_STABLE_DT: f64 = 1.0 / 120.0;

/// The reference time step (s, scaled): the step the presets' default
/// ([`Preset::largest_stable_dt`]) and every longer one are checked against
/// (`results/drops_dt/`, `results/drops_settling/`), `rocking drop --reference`'s, and the step
/// of runs that start at rest ([`crate::dynamics::resting::RESTING_DT`]).
pub const REFERENCE_DT: f64 = 1.0 / 240.0;

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
    /// (`dynamics::hull_shape`, `dynamics::world`).
    pub fn reference(self, p: &mut DropParams) {
        p.flight = Flight::Free;
        p.dt = REFERENCE_DT;
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
        let c = surface.contact();
        let base = DropParams {
            height: 1.0,
            horizontal_speed: 0.0,
            spin: 0.0,
            spin_distribution: SpinDistribution::Gaussian,
            friction: c.friction,
            restitution: c.restitution,
            rolling_resistance: c.rolling_resistance_m / r_max_m,
            torsional_friction: c.rolling_resistance_m / r_max_m,
            linear_damping: 0.0,
            angular_damping: 0.0,
            dt: self.largest_stable_dt(),
            solver_iterations: 4,
            max_time: 60.0,
            rest_linear_speed: 2e-3,
            rest_angular_speed: 5e-3,
            rest_time: 0.25,
            flight: Flight::Free,
            strict_impacts: false,
        };
        match self {
            Preset::QuasiStatic => {
                DropParams { height: 1e-3, restitution: 0.0, linear_damping: 10.0, angular_damping: 10.0, ..base }
            }
            Preset::Drop => base,
            Preset::Throw => {
                DropParams { height: THROW_HEIGHT, horizontal_speed: THROW_HORIZONTAL_SPEED, spin: THROW_SPIN, ..base }
            }
        }
    }
}

/// Calibrated release height of [`Preset::Throw`] (R_max), see `results/cuboid_dice/`.
pub const THROW_HEIGHT: f64 = 2.0;
/// Calibrated horizontal speed of [`Preset::Throw`] (m/s of the scaled body), see `results/cuboid_dice/`.
pub const THROW_HORIZONTAL_SPEED: f64 = 4.0;
/// Calibrated rms spin of [`Preset::Throw`] (rad/s of the scaled body), see `results/cuboid_dice/`.
pub const THROW_SPIN: f64 = 25.0;

/// The size at which a surface's physical rolling-resistance length is turned into δ / R_max by
/// the presets when the stone's real size is not given: R_max = 1 cm (a die, a pebble).
pub const REFERENCE_R_MAX_M: f64 = 0.01;

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
            .ok_or_else(|| Error::Usage(format!("unknown preset {s:?}: expected one of quasi-static, drop, throw")))
    }
}

/// The physical contact of a surface pair.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Contact {
    /// Coulomb friction coefficient.
    pub friction: f64,
    /// Coefficient of restitution of a normal impact.
    pub restitution: f64,
    /// Rolling-resistance length δ (metres): the lever arm of the normal force that resists
    /// rolling, M_r ≤ δ N.
    pub rolling_resistance_m: f64,
}

/// The range of each contact parameter of a surface pair (low, high): what an ensemble of field
/// runs draws from when the surface is only known by its kind ([`Surface::ranges`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactRanges {
    /// Coulomb friction coefficient.
    pub friction: [f64; 2],
    /// Coefficient of restitution.
    pub restitution: [f64; 2],
    /// Rolling-resistance length δ (metres).
    pub rolling_resistance_m: [f64; 2],
}

/// Named surface pairs, with friction, restitution and rolling resistance inside published
/// ranges (each variant cites them).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Surface {
    /// Steel dice on a wooden table: μ = 0.4 (dry steel on wood 0.2–0.6 in the friction
    /// tables of Marks' Standard Handbook for Mechanical Engineers), e = 0.5 (steel ball on hardwood
    /// 0.4–0.6), δ = 0.2 mm (rolling-friction lever arm of steel on wood, 0.05–0.5 mm in
    /// handbook tables; the geometric middle of that range).
    SteelOnWood,
    /// A stone on a rock surface: μ = 0.6 (Byerlee 1978: 0.6–0.85 for rock on rock), e = 0.3
    /// (normal restitution of rock on bedrock 0.2–0.5 in rockfall back-analyses, e.g. Giani 1992;
    /// Asteriou et al. 2012), δ = 0.1 mm.
    StoneOnStone,
    /// A rock on a concrete slab or shake table: μ = 0.6 (0.5–0.7), e = 0.3, δ = 0.1 mm.
    RockOnConcrete,
    /// A rock on a steel plate: μ = 0.45 (0.3–0.6 for dry rock on steel), e = 0.4, δ = 0.05 mm.
    RockOnSteel,
}

impl Surface {
    /// Every surface pair.
    pub const ALL: [Surface; 4] =
        [Surface::SteelOnWood, Surface::StoneOnStone, Surface::RockOnConcrete, Surface::RockOnSteel];

    /// The user-facing name (as `--surface` takes it).
    pub fn name(self) -> &'static str {
        match self {
            Surface::SteelOnWood => "steel-on-wood",
            Surface::StoneOnStone => "stone-on-stone",
            Surface::RockOnConcrete => "rock-on-concrete",
            Surface::RockOnSteel => "rock-on-steel",
        }
    }

    /// The contact of this pair.
    pub fn contact(self) -> Contact {
        let (friction, restitution, rolling_resistance_m) = match self {
            Surface::SteelOnWood => (0.4, 0.5, 2e-4),
            Surface::StoneOnStone => (0.6, 0.3, 1e-4),
            Surface::RockOnConcrete => (0.6, 0.3, 1e-4),
            Surface::RockOnSteel => (0.45, 0.4, 5e-5),
        };
        Contact { friction, restitution, rolling_resistance_m }
    }

    /// The ranges each contact parameter of this pair may take, around [`Surface::contact`]
    /// (which lies inside them). Cited, as in the variants' docs: steel on wood μ 0.2–0.6,
    /// e 0.4–0.6, δ 0.05–0.5 mm (Marks' handbook tables); rock on rock μ 0.6–0.85 (Byerlee 1978)
    /// and e 0.2–0.5 (rockfall back-analyses); rock on concrete μ 0.5–0.7; rock on steel μ
    /// 0.3–0.6. Not cited, this project's assumption, said where it is used: e 0.2–0.5 on
    /// concrete (as on bedrock), e 0.3–0.5 on steel, and δ a factor 2 either side of the
    /// nominal value for the three rock pairs (no published range found).
    pub fn ranges(self) -> ContactRanges {
        let c = self.contact();
        let (friction, restitution, rolling_resistance_m) = match self {
            Surface::SteelOnWood => ([0.2, 0.6], [0.4, 0.6], [5e-5, 5e-4]),
            Surface::StoneOnStone => {
                ([0.6, 0.85], [0.2, 0.5], [0.5 * c.rolling_resistance_m, 2.0 * c.rolling_resistance_m])
            }
            Surface::RockOnConcrete => {
                ([0.5, 0.7], [0.2, 0.5], [0.5 * c.rolling_resistance_m, 2.0 * c.rolling_resistance_m])
            }
            Surface::RockOnSteel => {
                ([0.3, 0.6], [0.3, 0.5], [0.5 * c.rolling_resistance_m, 2.0 * c.rolling_resistance_m])
            }
        };
        ContactRanges { friction, restitution, rolling_resistance_m }
    }

    /// Set the contact of `p` to this pair's, for a stone of real size R_max = `r_max_m` metres.
    pub fn scaled(self, p: &mut DropParams, r_max_m: f64) {
        let c = self.contact();
        p.friction = c.friction;
        p.restitution = c.restitution;
        p.rolling_resistance = c.rolling_resistance_m / r_max_m;
        p.torsional_friction = c.rolling_resistance_m / r_max_m;
    }
}

impl fmt::Display for Surface {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Surface {
    type Err = Error;
    fn from_str(s: &str) -> Result<Surface> {
        Surface::ALL.into_iter().find(|p| p.name() == s).ok_or_else(|| {
            let names: Vec<&str> = Surface::ALL.iter().map(|s| s.name()).collect();
            Error::Usage(format!("unknown surface {s:?}: expected one of {}", names.join(", ")))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_and_surfaces_parse_their_names_and_pass_the_check() {
        for p in Preset::ALL {
            assert_eq!(p.name().parse::<Preset>().unwrap(), p);
            for s in Surface::ALL {
                assert_eq!(s.name().parse::<Surface>().unwrap(), s);
                p.params(s).check().unwrap();
                // The nominal contact lies inside its ranges.
                let (c, r) = (s.contact(), s.ranges());
                for (x, [lo, hi]) in [
                    (c.friction, r.friction),
                    (c.restitution, r.restitution),
                    (c.rolling_resistance_m, r.rolling_resistance_m),
                ] {
                    assert!(lo < hi && (lo..=hi).contains(&x), "{s}: {x} outside [{lo}, {hi}]");
                }
            }
        }
        assert!("fling".parse::<Preset>().is_err());
        // No global damping except in the overdamped limit.
        assert_eq!(DropParams::default().angular_damping, 0.0);
        assert!(Preset::QuasiStatic.params(Surface::StoneOnStone).angular_damping > 0.0);
    }

    #[test]
    fn nonsense_parameters_are_refused_with_their_name() {
        let name = |p: DropParams| match p.check().unwrap_err() {
            Error::Parameter { name, .. } => name,
            e => panic!("not a parameter error: {e}"),
        };
        assert_eq!(name(DropParams { dt: 1.0, ..DropParams::default() }), "dt");
        assert_eq!(name(DropParams { friction: f64::NAN, ..DropParams::default() }), "friction");
        assert_eq!(name(DropParams { restitution: 1.5, ..DropParams::default() }), "restitution");
        assert_eq!(name(DropParams { max_time: 1e-3, dt: 1e-2, ..DropParams::default() }), "dt");
        let e = DropParams { restitution: 1.5, ..DropParams::default() }.check().unwrap_err();
        assert_eq!(e.to_string(), "restitution must be in [0, 1], got 1.5");
        assert_eq!(e.spelled(&|n| format!("{n}=")), "restitution= must be in [0, 1], got 1.5");
    }
}
