//! One drop of a pebble onto flat ground in rapier3d, from release to rest (SPEC §6).
//!
//! **Units.** The body is simulated in its own scaled frame: lengths divided by R_max (the
//! largest distance from G to a hull vertex) and mass normalised to 1, with g = 9.81. A drop is
//! then the same experiment for a mm pebble and a km asteroid: only dimensionless groups
//! (height/R_max, spin·√(R_max/g), friction, restitution) matter, and times are reported in
//! units of √(R_max/g)·... seconds of a 1 m body.
//!
//! **Body.** The collider is the convex hull; mass, G and the inertia tensor are the *solid's*
//! (computed in f64 by [`crate::solid`], converted once here to rapier's f32 glam types), set
//! as additional mass properties of a body whose collider has density 0.
//!
//! **Rest.** A drop has settled when its linear speed stays below `rest_linear_speed` and its
//! angular speed below `rest_angular_speed` for `rest_time` seconds in a row — the project's
//! own criterion, rapier's sleeping is disabled. The resting facet is the hull facet whose
//! outward normal is closest to the down direction; it is mapped to its micro-equilibrium
//! (if the facet is stable) and flock. A drop that ends on a non-stable facet, or is still
//! moving at `max_time`, is reported as such.

use crate::hull::Polyhedron;
use crate::{Point3, Vec3};
use nalgebra::{Matrix3, UnitQuaternion};
use rapier3d::prelude::*;
use serde::{Deserialize, Serialize};

/// Parameters of a drop, in the scaled frame (lengths in R_max, g = 9.81, mass 1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DropParams {
    /// Initial height of the lowest hull point above the ground, in units of R_max.
    pub height: f64,
    /// Initial angular speed (rad/s of the scaled body), random axis.
    pub spin: f64,
    /// Coulomb friction coefficient (rapier's combine rule: average).
    pub friction: f64,
    /// Restitution coefficient (rapier's combine rule: average).
    pub restitution: f64,
    /// Linear and angular velocity damping (1/s). Rapier has no rolling resistance: without
    /// some angular damping a smooth pebble rocks on its micro-facets for ever (measured: 199
    /// of 200 drops of an 800-vertex pebble still moving after 20 s with none, 0 of 200 with
    /// the default 1/s), so the default stands in for the rolling resistance of real ground.
    pub linear_damping: f64,
    pub angular_damping: f64,
    /// Time step (s).
    pub dt: f64,
    /// Give up after this long (s).
    pub max_time: f64,
    /// Rest: speeds below these thresholds (scaled units) for `rest_time` seconds.
    pub rest_linear_speed: f64,
    pub rest_angular_speed: f64,
    pub rest_time: f64,
}

impl Default for DropParams {
    fn default() -> Self {
        DropParams {
            height: 0.5,
            spin: 0.0,
            friction: 0.6,
            restitution: 0.2,
            linear_damping: 0.1,
            angular_damping: 1.0,
            dt: 1.0 / 240.0,
            max_time: 20.0,
            rest_linear_speed: 2e-3,
            rest_angular_speed: 5e-3,
            rest_time: 0.25,
        }
    }
}

impl DropParams {
    /// Refuse parameters that cannot describe a drop.
    pub fn check(&self) -> Result<(), String> {
        let positive = [("dt", self.dt), ("max time", self.max_time), ("rest time", self.rest_time)];
        if let Some((name, v)) = positive.iter().find(|(_, v)| !(*v > 0.0 && v.is_finite())) {
            return Err(format!("{name} must be positive, got {v}"));
        }
        let non_negative = [
            ("height", self.height),
            ("spin", self.spin),
            ("friction", self.friction),
            ("linear damping", self.linear_damping),
            ("angular damping", self.angular_damping),
        ];
        if let Some((name, v)) = non_negative.iter().find(|(_, v)| !(*v >= 0.0 && v.is_finite())) {
            return Err(format!("{name} must be ≥ 0, got {v}"));
        }
        if !(0.0..=1.0).contains(&self.restitution) {
            return Err(format!("restitution must be in [0, 1], got {}", self.restitution));
        }
        if self.dt > self.max_time {
            return Err(format!("dt ({}) is longer than the time cap ({})", self.dt, self.max_time));
        }
        Ok(())
    }
}

/// What happened to one drop.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DropOutcome {
    /// Index of the drop in its run (determines its random stream).
    pub index: u64,
    /// Whether the rest criterion was met (or a certificate decided the drop) before `max_time`.
    pub settled: bool,
    /// The hull facet facing down at the end (None when a flock-level certificate ended the
    /// drop before the facet was decided).
    pub facet: Option<u32>,
    /// The flock decided by a flock-level certificate (otherwise read it off `facet`).
    pub flock: Option<u32>,
    /// Simulated time (s) until rest / decision / the cap.
    pub time: f64,
    /// The drop was ended early by the energy certificate.
    pub certified: bool,
}

/// Conversions between the f64 nalgebra geometry and rapier's f32 glam types (the one boundary).
pub mod convert {
    use crate::Vec3;
    use nalgebra::{Matrix3, UnitQuaternion};
    use rapier3d::math::{Matrix, Rotation, Vector};

    pub fn vec(v: &Vec3) -> Vector {
        Vector::new(v.x as f32, v.y as f32, v.z as f32)
    }
    pub fn vec_back(v: Vector) -> Vec3 {
        Vec3::new(v.x as f64, v.y as f64, v.z as f64)
    }
    pub fn quat(q: &UnitQuaternion<f64>) -> Rotation {
        Rotation::from_xyzw(q.i as f32, q.j as f32, q.k as f32, q.w as f32).normalize()
    }
    pub fn quat_back(q: &Rotation) -> UnitQuaternion<f64> {
        UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q.w as f64, q.x as f64, q.y as f64, q.z as f64))
    }
    pub fn mat(m: &Matrix3<f64>) -> Matrix {
        Matrix::from_cols(
            Vector::new(m[(0, 0)] as f32, m[(1, 0)] as f32, m[(2, 0)] as f32),
            Vector::new(m[(0, 1)] as f32, m[(1, 1)] as f32, m[(2, 1)] as f32),
            Vector::new(m[(0, 2)] as f32, m[(1, 2)] as f32, m[(2, 2)] as f32),
        )
    }
}

/// Everything a drop needs about the body, prepared once per mesh (scaled frame, body origin
/// at G).
#[derive(Clone)]
pub struct DropBody {
    /// Hull corners relative to G, divided by R_max.
    pub corners: Vec<Vec3>,
    /// The collider: the project's own hull ([`super::hull_shape::HullShape`], exact facets,
    /// constant-time bounds), shared by all drops.
    pub shape: SharedShape,
    /// Outward unit normal of every facet (body frame).
    pub facet_normals: Vec<Vec3>,
    /// Inertia about G for unit mass, in the scaled frame.
    pub inertia: Matrix3<f64>,
    /// R_max in input units (the length scale).
    pub r_max: f64,
}

impl DropBody {
    /// Prepare the body from the hull, G and the solid's inertia tensor (density 1, input
    /// units) and volume.
    pub fn new(hull: &Polyhedron, g: &Point3, inertia: &Matrix3<f64>, volume: f64) -> Self {
        let r_max = hull.vertices.iter().map(|p| (p - g).norm()).fold(0.0, f64::max);
        let corners = hull.vertices.iter().map(|p| (p - g) / r_max).collect();
        let shape = SharedShape::new(super::hull_shape::HullShape::new(hull, g, 1.0 / r_max));
        let facet_normals = hull.facets.iter().map(|f| f.normal).collect();
        // I scales as L⁵ and mass as L³: unit mass in the scaled frame gives I / (V R_max²).
        let inertia = inertia / (volume * r_max * r_max);
        DropBody { corners, shape, facet_normals, inertia, r_max }
    }

    /// Height of G above the ground when the body touches it with down direction `d` (body
    /// frame): the support function h(d) = max (x − G)·d.
    pub fn support(&self, d: &Vec3) -> f64 {
        self.corners.iter().map(|c| c.dot(d)).fold(f64::NEG_INFINITY, f64::max)
    }

    /// The facet whose outward normal is closest to the down direction `d` (body frame).
    pub fn facet_towards(&self, d: &Vec3) -> u32 {
        let mut best = (f64::NEG_INFINITY, 0u32);
        for (i, n) in self.facet_normals.iter().enumerate() {
            let c = n.dot(d);
            if c > best.0 {
                best = (c, i as u32);
            }
        }
        best.1
    }
}

/// Initial state of a drop: orientation (body → world) and angular velocity (world).
#[derive(Clone, Copy, Debug)]
pub struct Release {
    pub orientation: UnitQuaternion<f64>,
    pub angvel: Vec3,
}

/// What a certificate has proved about the end of a drop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Decided {
    /// The drop will end on this facet.
    Facet(u32),
    /// The drop will end in this flock.
    Flock(u32),
}

/// A certificate that may end a drop early: given the body-frame down direction and the energy
/// level L = E/(m g) in the scaled frame (a height of G over R_max), what is already certain.
pub trait Certificate {
    fn decided(&self, down: &Vec3, level: f64) -> Option<Decided>;
}

/// No early termination.
pub struct NoCertificate;
impl Certificate for NoCertificate {
    fn decided(&self, _: &Vec3, _: f64) -> Option<Decided> {
        None
    }
}

const GRAVITY: f64 = 9.81;

/// Penetration the contact solver allows, in units of R_max.
pub const ALLOWED_PENETRATION: f64 = 1e-3;

/// The state of the body that the rest criterion and the certificate read (scaled frame).
#[derive(Clone, Copy, Debug)]
pub struct BodyState {
    /// Down direction in the body frame.
    pub down: Vec3,
    /// Height of G above the ground.
    pub z: f64,
    /// Linear and angular velocity (world frame).
    pub linvel: Vec3,
    pub angvel: Vec3,
    /// Energy level L = E/(m g) = z_G + kinetic energy/(m g): a bound on h(down) for the rest of
    /// a passive motion.
    pub level: f64,
}

/// A rapier world with the ground (a half-space z ≤ 0 on a kinematic body, so that it can be
/// shaken) and the pebble, in the scaled frame. Drops ([`simulate`]), pushes and ground shaking
/// all run on it.
pub struct Simulation<'a> {
    pub world: PhysicsWorld,
    pub body_handle: RigidBodyHandle,
    pub ground_handle: RigidBodyHandle,
    body: &'a DropBody,
}

impl<'a> Simulation<'a> {
    /// The pebble with orientation `orientation` (body → world), G at height `z`, and the
    /// given velocities, above a flat ground.
    pub fn new(
        body: &'a DropBody,
        p: &DropParams,
        orientation: &UnitQuaternion<f64>,
        z: f64,
        linvel: &Vec3,
        angvel: &Vec3,
    ) -> Self {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, -GRAVITY as f32);
        world.integration_parameters.dt = p.dt as f32;
        world.integration_parameters.length_unit = 1.0;
        // Rapier's allowed linear error, in R_max (default 0.005). Note: in rapier 0.36.1 it is
        // read only by continuous collision detection; the penetration the certificate's margin
        // must cover is bounded by measurement instead (≤ 8·10⁻⁴ R_max, see CERTIFICATE_MARGIN).
        world.integration_parameters.normalized_allowed_linear_error = ALLOWED_PENETRATION as f32;
        let ground_handle = world.bodies.insert(RigidBodyBuilder::kinematic_velocity_based().build());
        let ground = ColliderBuilder::new(SharedShape::halfspace(Vector::Z))
            .friction(p.friction as f32)
            .restitution(p.restitution as f32)
            .build();
        world.colliders.insert_with_parent(ground, ground_handle, &mut world.bodies);
        let mass = MassProperties::with_inertia_matrix(Vector::ZERO, 1.0, convert::mat(&body.inertia));
        let rb = RigidBodyBuilder::dynamic()
            .pose(Pose::from_parts(Vector::new(0.0, 0.0, z as f32), convert::quat(orientation)))
            .linvel(convert::vec(linvel))
            .angvel(convert::vec(angvel))
            .linear_damping(p.linear_damping as f32)
            .angular_damping(p.angular_damping as f32)
            .additional_mass_properties(mass)
            .gyroscopic_forces_enabled(true)
            .can_sleep(false)
            .build();
        let body_handle = world.bodies.insert(rb);
        let collider = ColliderBuilder::new(body.shape.clone())
            .density(0.0)
            .friction(p.friction as f32)
            .restitution(p.restitution as f32)
            .build();
        world.colliders.insert_with_parent(collider, body_handle, &mut world.bodies);
        Simulation { world, body_handle, ground_handle, body }
    }

    /// Advance one time step.
    pub fn step(&mut self) {
        self.world.step();
    }

    /// Set the ground's horizontal velocity (world frame) for the next steps.
    pub fn set_ground_velocity(&mut self, v: &Vec3) {
        self.world.bodies[self.ground_handle].set_linvel(convert::vec(v), true);
    }

    /// The pebble's current state.
    pub fn state(&self) -> BodyState {
        let rb = &self.world.bodies[self.body_handle];
        let q = convert::quat_back(rb.rotation());
        let down = q.inverse() * -Vec3::z();
        let linvel = convert::vec_back(rb.linvel());
        let angvel = convert::vec_back(rb.angvel());
        let w_body = q.inverse() * angvel;
        let kinetic = 0.5 * linvel.norm_squared() + 0.5 * w_body.dot(&(self.body.inertia * w_body));
        let z = rb.translation().z as f64;
        BodyState { down, z, linvel, angvel, level: z + kinetic / GRAVITY }
    }
}

/// Counts consecutive calm steps (speeds under the rest thresholds) until `rest_time`.
pub struct RestDetector {
    calm: u64,
    needed: u64,
    linear: f64,
    angular: f64,
}

impl RestDetector {
    pub fn new(p: &DropParams) -> Self {
        RestDetector {
            calm: 0,
            needed: (p.rest_time / p.dt).ceil() as u64,
            linear: p.rest_linear_speed,
            angular: p.rest_angular_speed,
        }
    }

    /// Feed the velocities relative to the ground; true once the body has been calm long enough.
    pub fn at_rest(&mut self, linvel: &Vec3, angvel: &Vec3) -> bool {
        if linvel.norm() < self.linear && angvel.norm() < self.angular {
            self.calm += 1;
        } else {
            self.calm = 0;
        }
        self.calm >= self.needed
    }
}

/// Simulate one drop to rest (or to the certificate, or to the time cap).
pub fn simulate(body: &DropBody, p: &DropParams, release: &Release, index: u64, cert: &dyn Certificate) -> DropOutcome {
    let down_body = release.orientation.inverse() * -Vec3::z();
    let z0 = p.height + body.support(&down_body);
    let mut sim = Simulation::new(body, p, &release.orientation, z0, &Vec3::zeros(), &release.angvel);
    let mut rest = RestDetector::new(p);
    let steps_max = (p.max_time / p.dt).ceil() as u64;
    for step in 1..=steps_max {
        sim.step();
        let s = sim.state();
        let t = step as f64 * p.dt;
        if step % 4 == 0 {
            match cert.decided(&s.down, s.level) {
                Some(Decided::Facet(f)) => {
                    return DropOutcome { index, settled: true, facet: Some(f), flock: None, time: t, certified: true }
                }
                Some(Decided::Flock(k)) => {
                    return DropOutcome { index, settled: true, facet: None, flock: Some(k), time: t, certified: true }
                }
                None => {}
            }
        }
        if rest.at_rest(&s.linvel, &s.angvel) {
            let facet = Some(body.facet_towards(&s.down));
            return DropOutcome { index, settled: true, facet, flock: None, time: t, certified: false };
        }
    }
    let facet = Some(body.facet_towards(&sim.state().down));
    DropOutcome { index, settled: false, facet, flock: None, time: p.max_time, certified: false }
}
