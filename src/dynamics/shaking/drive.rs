//! The ground driven by a [`Record`] under a stone that stands on it, and the shaken run that
//! both the fragility sweep ([`crate::dynamics::shaking::sweep`]) and field rocks ([`crate::dynamics::shaking::rock`]) make.
//!
//! # True size (Froude-exact scaled simulation)
//!
//! The stone is simulated in the scaled frame of [`crate::dynamics::drops::params`] (R_max = 1,
//! g = 9.81 m/s²) and the record — real time, m/s² — is converted exactly: with L = R_max in
//! metres, t_scaled = t/√L, accelerations unchanged, ground velocity / √L, displacement / L. The
//! rigid-body equations with Coulomb friction, Newton restitution and a rolling-resistance
//! *length* δ (given as δ/L by [`crate::dynamics::drops::params::Preset::params_at_size`]) are invariant
//! under this change of units, so the scaled run *is* the run at true size in which the numerical
//! parameters are converted the same way: time step dt·√L, contact natural frequency f/√L,
//! rapier's length unit L. Checked against Housner's rocking equation integrated at true size
//! ([`crate::dynamics::shaking::housner`], `tests/shake_rock.rs`, `results/fragility_surface/`).
//!
//! # Three components
//!
//! The kinematic ground gets the 3D velocity, advanced by the midpoint rule from the record's
//! acceleration at the middle of each step (exact ground displacement for piecewise-linear a(t));
//! rapier's contact solver uses the kinematic body's velocity, so a vertical ground acceleration
//! a_z changes the effective gravity to g + a_z. The record's horizontal axes are turned by the
//! azimuth in the world frame. When the record ends the ground keeps its final velocity — a
//! frame in uniform motion is inertial — and the stone is simulated until it rests *relative to
//! the ground*, by positions over windows ([`PositionRest`](crate::dynamics::engine::rest::PositionRest)).

use crate::dynamics::engine::rest::RestKind;
use crate::dynamics::engine::run::{run_to_end, Drive, NoCertificate, RunEnd};
use crate::dynamics::engine::simulation::Simulation;
use crate::dynamics::resting::RestingParams;
use crate::dynamics::stone::Stone;
use crate::ground_motion::Record;
use crate::Vec3;

/// The ground driven by a record in the scaled frame (module docs).
pub struct GroundDrive<'m> {
    record: &'m Record,
    /// Real seconds per scaled second, √(R_max / 1 m).
    time_factor: f64,
    /// cos and sin of the azimuth.
    rot: (f64, f64),
    dt: f64,
    v: Vec3,
    steps: u64,
}

impl<'m> GroundDrive<'m> {
    /// `record` (real time) under a stone of real size `r_max_m` metres, its x axis along
    /// `azimuth` (rad, world frame), simulated with the scaled time step `dt`.
    pub fn new(record: &'m Record, azimuth: f64, r_max_m: f64, dt: f64) -> Self {
        let time_factor = r_max_m.sqrt();
        let steps = (record.duration() / time_factor / dt).ceil() as u64;
        GroundDrive { record, time_factor, rot: (azimuth.cos(), azimuth.sin()), dt, v: Vec3::zeros(), steps }
    }

    /// Ground acceleration of the scaled frame at scaled time t: Froude scaling keeps
    /// accelerations (g is the same), so it is the real one at real time t·√L, its horizontal
    /// part turned by the azimuth.
    fn accel(&self, t: f64) -> Vec3 {
        let [x, y, z] = self.record.at(t * self.time_factor);
        let (c, s) = self.rot;
        Vec3::new(c * x - s * y, s * x + c * y, z)
    }
}

impl Drive for GroundDrive<'_> {
    fn before_step(&mut self, sim: &mut Simulation, step: u64) {
        let a = self.accel((step as f64 + 0.5) * self.dt);
        let v_new = self.v + a * self.dt;
        sim.set_ground_velocity(&((self.v + v_new) * 0.5));
        self.v = v_new;
    }
    fn ground_velocity(&self) -> Vec3 {
        self.v
    }
    fn active_steps(&self) -> u64 {
        self.steps
    }
}

/// A stone standing on the ground, settled, ready to be shaken.
pub struct Placed<'a> {
    /// The simulation, with the stone at rest.
    pub sim: Simulation<'a>,
    /// Position in [`Stone::stable`] of the micro-equilibrium it stands on.
    pub start: usize,
    /// Tilt (rad) of the body between where it was put down and where it came to rest.
    pub settling_tilt: f64,
}

impl<'a> Placed<'a> {
    /// The stone exactly at rest on stable micro-equilibrium `start` (position in
    /// [`Stone::stable`]), settled for `p.settle_time` ([`crate::dynamics::resting`]).
    pub fn on(stone: &'a Stone, start: usize, p: &RestingParams) -> Self {
        let sim = crate::dynamics::resting::resting_simulation(stone, start, p, p.settle_time);
        let n = stone.body.facet_normals[stone.stable()[start].facet as usize];
        let settling_tilt = n.dot(&sim.state().down).clamp(-1.0, 1.0).acos();
        Placed { sim, start, settling_tilt }
    }
}

/// How a shaken run went, in the scaled frame.
#[derive(Clone, Copy, Debug)]
pub struct Shaken {
    /// Position in [`Stone::stable`] of the micro-equilibrium the stone stood on.
    pub start: usize,
    /// Its tilt while it settled (rad).
    pub settling_tilt: f64,
    /// How the run ended.
    pub end: RunEnd,
    /// Largest tilt (rad) of the start facet's normal away from straight down.
    pub max_tilt: f64,
    /// Horizontal displacement of G relative to the ground from the start to the end (R_max).
    pub slide: f64,
    /// The deepest any hull corner went below the ground after any step or sub-step of the run
    /// (R_max, [`crate::dynamics::engine::world::penetration`]), the stone's settling included.
    pub deepest_penetration: f64,
}

/// Shake a placed stone with `record` (real time, SI, x axis along `azimuth` rad in the world
/// frame; the stone of real size `r_max_m` metres) until it rests relative to the ground (module
/// docs). No certificate: a driven system is not passive.
pub fn shake_placed(
    stone: &Stone,
    placed: Placed,
    p: &RestingParams,
    record: &Record,
    azimuth: f64,
    r_max_m: f64,
) -> Shaken {
    let Placed { mut sim, start, settling_tilt } = placed;
    let mut ground = GroundDrive::new(record, azimuth, r_max_m, p.sim.numerics.dt);
    let x0 = sim.ground_offset();
    let n = stone.body.facet_normals[stone.stable()[start].facet as usize];
    let mut max_tilt: f64 = 0.0;
    let end = run_to_end(&mut sim, &p.sim, &mut ground, &NoCertificate, RestKind::Positions, &mut |st| {
        max_tilt = max_tilt.max(n.dot(&st.down).clamp(-1.0, 1.0).acos())
    });
    Shaken {
        start,
        settling_tilt,
        end,
        max_tilt,
        slide: (sim.ground_offset() - x0).norm(),
        deepest_penetration: sim.deepest_penetration(),
    }
}
