//! Named surface pairs: the friction, restitution and rolling-resistance length of a stone on a
//! kind of ground, inside published ranges, and the ranges an ensemble draws from.

use crate::dynamics::engine::params::ContactParams;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

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

    /// What the pair stands for, and so which kind of run takes it by default: "dice thrown on
    /// a wooden table, where the throw is calibrated" (drops), "a stone resting on rock" (pushes
    /// and shaking sweeps), "a rock on a shake table's concrete" (field rocks).
    pub fn stands_for(self) -> &'static str {
        match self {
            Surface::SteelOnWood => "dice thrown on a wooden table, where the throw is calibrated",
            Surface::StoneOnStone => "a stone resting on rock",
            Surface::RockOnConcrete => "a rock on a shake table's concrete",
            Surface::RockOnSteel => "a rock on a steel plate",
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

    /// Set the contact of `c` to this pair's, for a stone of real size R_max = `r_max_m` metres
    /// (δ / R_max for both the rolling resistance and the torsional friction; the damping is left
    /// as it is).
    pub fn scaled(self, c: &mut ContactParams, r_max_m: f64) {
        let pair = self.contact();
        c.friction = pair.friction;
        c.restitution = pair.restitution;
        c.rolling_resistance = pair.rolling_resistance_m / r_max_m;
        c.torsional_friction = pair.rolling_resistance_m / r_max_m;
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
            Error::unknown("surface", s, &names)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn surfaces_parse_their_names_and_hold_their_nominal_contact_inside_its_ranges() {
        for s in Surface::ALL {
            assert_eq!(s.name().parse::<Surface>().unwrap(), s);
            let (c, r) = (s.contact(), s.ranges());
            for (x, [lo, hi]) in [
                (c.friction, r.friction),
                (c.restitution, r.restitution),
                (c.rolling_resistance_m, r.rolling_resistance_m),
            ] {
                assert!(lo < hi && (lo..=hi).contains(&x), "{s}: {x} outside [{lo}, {hi}]");
            }
        }
        assert!("ice-on-ice".parse::<Surface>().is_err());
    }
}
