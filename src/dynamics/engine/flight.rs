//! Free flight between contacts, integrated outside rapier: a stone that does not
//! touch the ground moves as a free rigid body under gravity, and that motion needs no contact
//! pipeline at all.
//!
//! Measured (`results/drops_certificate/`): a thrown stone spends most of its simulated time in
//! the air — the release height and then the hops of a spinning body (the bundled stone's throw:
//! 3.7 of 4.3 s up to the certificate's decision) — and a rapier step of a body in flight still
//! costs 1.2 µs (broad phase, the half-space pair's manifold, the island and integration stages),
//! against 0.1 µs for a step of [`FreeBody`].
//!
//! # The motion
//!
//! With G the centre of mass, g = −9.81 ẑ, I the inertia about G in the body frame, q the
//! orientation (body → world) and ω the angular velocity in the body frame:
//!
//! ```text
//! x(t) = x₀ + v₀ t + ½ g t²,   v(t) = v₀ + g t                    (exact, per step)
//! I ω̇ = (I ω) × ω,   q̇ = ½ q ⊗ (0, ω)                            (Euler's equations)
//! ```
//!
//! Euler's equations are integrated with the classical Runge–Kutta method (RK4) on (q, ω), in
//! sub-steps that turn the body by at most [`MAX_SUBSTEP_ANGLE`] each, q renormalised after every
//! sub-step. Checked against what holds exactly (tests below): the kinetic energy and the world
//! angular momentum R(q) I ω are conserved to 10⁻⁶ relative over a second of a 50 rad/s tumble,
//! and the precession of a symmetric top has its closed-form rate. Rapier's own flight (f32,
//! one linearised gyroscopic step per sub-step) loses 0.5 % of the angular momentum and 1 % of
//! the energy over 1.5 s of a 40 rad/s tumble at dt = 1/240 s and converges to this flight as
//! its step shrinks (`tests/flight.rs`): the free flight is the same physics, more accurately.
//!
//! # When a stone is in flight, and the exact landing ([`FreeBody::fly`])
//!
//! The clearance is c(t) = z_G(t) − h(d(t)) (h the support function, d the body-frame down
//! direction): the height of the lowest hull point. A stone leaves rapier only after a step in
//! which the ground gave it no impulse and that ended with c > [`TAKE_OFF_CLEARANCE`]. In the
//! air, the landing is not looked for at the step boundaries: [`FreeBody::fly`] finds the first
//! time at which c falls to [`CONTACT_CLEARANCE`], by *conservative advancement* along the exact
//! trajectory. On any interval [t, t + τ] of the step,
//!
//! ```text
//! −dc/dt = −v_z − dh/dt ≤ max(0, −v_z(t)) + g τ + |ω_⊥| ρ  ≤  S,
//! ```
//!
//! because |dh/dt| = |∇h · ḋ| ≤ max|x − G| · |ω × d| and every hull point is within ρ = 1 R_max
//! of G, and |ω| ≤ √(2 T_rot / λ_min(I)) with T_rot the (conserved) rotational energy. So
//! advancing by τ = (c − c_contact)/S can never carry the clearance below c_contact; repeating
//! it converges to the first contact time from below, and never passes it. The stone is then
//! handed to rapier at clearance c ∈ [c_contact, c_contact + [`LANDING_TOLERANCE`]], inside
//! rapier's prediction distance (0.02 R_max, checked in `tests/flight.rs`): rapier's first step
//! already has the lowest corner as a speculative contact and the impact starts outside the
//! ground, never inside it. The stone lands part-way through a step; it re-enters rapier there
//! and goes on with whole steps from that instant (the ground is flat, fixed and the same at
//! every time, so the motion does not care), and its clock runs late by the unused part of the
//! step (≤ dt per landing, subtracted from the reported time).

use crate::dynamics::engine::params::{Flight, RunParams};
use crate::Vec3;
use nalgebra::{Matrix3, Quaternion, UnitQuaternion};

/// Largest rotation (rad) of one RK4 sub-step: local error ~ (0.2)⁵/120 ≈ 3·10⁻⁶ of the motion;
/// measured, the energy of a 50 rad/s tumble drifts by 4·10⁻⁸ and its angular momentum by 10⁻⁷
/// in a second (rapier's own flight: 10⁻² and 5·10⁻³), at two sub-steps per step of 1/240 s.
pub const MAX_SUBSTEP_ANGLE: f64 = 0.2;

/// Clearance (R_max) at which a landing stone is handed to rapier: half rapier's contact
/// prediction distance (module docs; checked against the world's own parameter in
/// `tests/flight.rs`), so that its first step in rapier already holds the contact.
pub const CONTACT_CLEARANCE: f64 = 0.01;

/// The landing is handed to rapier once the clearance is within this (R_max) above
/// [`CONTACT_CLEARANCE`].
pub const LANDING_TOLERANCE: f64 = 1e-4;

/// Most conservative-advancement moves in one step ([`FreeBody::fly`]); a stone that grazes the
/// ground without reaching it can need many. After them the stone lands where it is, still above
/// [`CONTACT_CLEARANCE`] (a move covers at least (c − c_contact)/S, so a stone more than
/// 0.01 R_max above it runs out of moves only at speeds S > 0.01 · 256 / dt ≈ 300 m/s, scaled).
pub const MAX_ADVANCES: usize = 256;

/// Rapier's contact prediction distance (R_max; rapier's default 0.02 × `length_unit` 1, which
/// [`crate::dynamics::engine::world::ground_world`] keeps): [`CONTACT_CLEARANCE`] is inside it.
pub const LANDING_CLEARANCE: f64 = 0.02;

/// Clearance (R_max) above which a stone that the ground did not push during the step leaves
/// rapier for free flight: eight times [`CONTACT_CLEARANCE`], so that a stone leaving the ground
/// does not come back at once.
pub const TAKE_OFF_CLEARANCE: f64 = 0.08;
const _: () = assert!(TAKE_OFF_CLEARANCE > LANDING_CLEARANCE && LANDING_CLEARANCE > CONTACT_CLEARANCE);

/// How a step of free flight ended ([`FreeBody::fly`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Flew {
    /// Still in the air at the end of the step.
    Airborne,
    /// Reached [`CONTACT_CLEARANCE`] after this much of the step (s).
    Landed(f64),
}

/// Gravity (m/s², scaled frame) — the world's.
use crate::GRAVITY as G;

/// Whether the runs of `p` fly outside rapier: [`Flight::Free`].
pub fn applies(p: &RunParams) -> bool {
    p.flight.mode == Flight::Free
}

/// Global velocity damping in flight (1/s): the `linear_damping` and `angular_damping` of a run
/// (rapier applies them in the air too). In free flight they act exactly: dv/dt = g − c v and
/// dω/dt = I⁻¹((Iω) × ω) − c_ω ω (rapier's own step is the implicit-Euler v ← v/(1 + c dt)).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Damping {
    /// Linear damping c (1/s).
    pub linear: f64,
    /// Angular damping c_ω (1/s).
    pub angular: f64,
}

impl Damping {
    /// The damping of `p`.
    pub fn of(p: &RunParams) -> Self {
        Damping { linear: p.contact.linear_damping, angular: p.contact.angular_damping }
    }
}

/// The inertia of a body in flight, with what every step needs of it computed once: the
/// inverse, and the smallest principal moment (which bounds |ω| by the rotational energy).
#[derive(Clone, Copy, Debug)]
pub struct Inertia {
    /// Inertia about G (unit mass, scaled frame, body axes).
    pub matrix: Matrix3<f64>,
    /// Its inverse (the identity if it has none).
    pub inverse: Matrix3<f64>,
    /// Its smallest eigenvalue λ_min.
    pub smallest: f64,
}

impl Inertia {
    /// The inertia `matrix`.
    pub fn new(matrix: Matrix3<f64>) -> Self {
        Inertia {
            matrix,
            inverse: matrix.try_inverse().unwrap_or_else(Matrix3::identity),
            smallest: matrix.symmetric_eigenvalues().min(),
        }
    }
}

/// A rigid body in free flight (scaled frame: unit mass, lengths / R_max). Horizontal position
/// is not kept: the ground is flat and unbounded, and the stones of a batch never meet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FreeBody {
    /// Height of G above the ground.
    pub z: f64,
    /// Velocity of G (world frame).
    pub linvel: Vec3,
    /// Orientation, body → world.
    pub orientation: UnitQuaternion<f64>,
    /// Angular velocity in the body frame.
    pub omega_body: Vec3,
}

impl FreeBody {
    /// The body with G at height `z`, orientation `q` and velocities `linvel`, `angvel` (both
    /// world frame).
    pub fn new(z: f64, linvel: Vec3, orientation: UnitQuaternion<f64>, angvel: &Vec3) -> Self {
        FreeBody { z, linvel, orientation, omega_body: orientation.inverse() * angvel }
    }

    /// Angular velocity in the world frame.
    pub fn angvel(&self) -> Vec3 {
        self.orientation * self.omega_body
    }

    /// Kinetic energy per unit mass: ½|v|² + ½ ωᵀIω.
    pub fn kinetic_energy(&self, inertia: &Matrix3<f64>) -> f64 {
        0.5 * self.linvel.norm_squared() + 0.5 * self.omega_body.dot(&(inertia * self.omega_body))
    }

    /// Angular momentum about G in the world frame, R(q) I ω.
    pub fn angular_momentum(&self, inertia: &Matrix3<f64>) -> Vec3 {
        self.orientation * (inertia * self.omega_body)
    }

    /// Advance the free motion by `dt` (module docs): G exactly, the rotation by RK4 sub-steps.
    pub fn step(&mut self, dt: f64, inertia: &Matrix3<f64>, inertia_inv: &Matrix3<f64>) {
        self.step_damped(dt, inertia, inertia_inv, Damping::default());
    }

    /// [`FreeBody::step`] under global damping ([`Damping`]): G exactly (an exponential
    /// approach to the terminal velocity −g/c), the rotation by RK4 sub-steps with the damping
    /// term. Without damping, exactly [`FreeBody::step`].
    pub fn step_damped(&mut self, dt: f64, inertia: &Matrix3<f64>, inertia_inv: &Matrix3<f64>, damping: Damping) {
        let c = damping.linear;
        if c > 0.0 {
            let decay = (-c * dt).exp();
            let terminal = -G / c;
            self.z += (self.linvel.z - terminal) * (1.0 - decay) / c + terminal * dt;
            self.linvel.z = terminal + (self.linvel.z - terminal) * decay;
            self.linvel.x *= decay;
            self.linvel.y *= decay;
        } else {
            self.z += self.linvel.z * dt - 0.5 * G * dt * dt;
            self.linvel.z -= G * dt;
        }
        let turn = self.omega_body.norm() * dt;
        let n = ((turn / MAX_SUBSTEP_ANGLE).ceil() as usize).max(1);
        let h = dt / n as f64;
        let mut q = *self.orientation.quaternion();
        let mut w = self.omega_body;
        for _ in 0..n {
            (q, w) = rk4(q, w, h, inertia, inertia_inv, damping.angular);
        }
        self.orientation = UnitQuaternion::new_normalize(q);
        self.omega_body = w;
    }
}

/// (q̇, ω̇) of Euler's equations with angular damping `c`.
fn rates(
    q: &Quaternion<f64>,
    w: &Vec3,
    inertia: &Matrix3<f64>,
    inertia_inv: &Matrix3<f64>,
    c: f64,
) -> (Quaternion<f64>, Vec3) {
    let qdot = q * Quaternion::from_imag(*w) * 0.5;
    let wdot = inertia_inv * (inertia * w).cross(w) - w * c;
    (qdot, wdot)
}

/// One classical Runge–Kutta step of length `h` (angular damping `c`); q renormalised.
fn rk4(
    q: Quaternion<f64>,
    w: Vec3,
    h: f64,
    inertia: &Matrix3<f64>,
    inertia_inv: &Matrix3<f64>,
    c: f64,
) -> (Quaternion<f64>, Vec3) {
    let (k1q, k1w) = rates(&q, &w, inertia, inertia_inv, c);
    let (k2q, k2w) = rates(&(q + k1q * (h / 2.0)), &(w + k1w * (h / 2.0)), inertia, inertia_inv, c);
    let (k3q, k3w) = rates(&(q + k2q * (h / 2.0)), &(w + k2w * (h / 2.0)), inertia, inertia_inv, c);
    let (k4q, k4w) = rates(&(q + k3q * h), &(w + k3w * h), inertia, inertia_inv, c);
    let q1 = q + (k1q + k2q * 2.0 + k3q * 2.0 + k4q) * (h / 6.0);
    let w1 = w + (k1w + k2w * 2.0 + k3w * 2.0 + k4w) * (h / 6.0);
    (q1.normalize(), w1)
}

/// The clearance c = z_G − h(d) of a body at height `z` whose support in its down direction is
/// `support` (module docs).
pub fn clearance(z: f64, support: f64) -> f64 {
    z - support
}

/// Whether a stone in rapier whose step ended with clearance `c` may leave it for free flight.
pub fn may_take_off(c: f64) -> bool {
    c > TAKE_OFF_CLEARANCE
}

/// Whether a stone released (or found) at clearance `c` starts in the air rather than in rapier.
pub fn airborne(c: f64) -> bool {
    c > CONTACT_CLEARANCE + LANDING_TOLERANCE
}

impl FreeBody {
    /// Down direction in the body frame.
    pub fn down(&self) -> Vec3 {
        self.orientation.inverse() * -Vec3::z()
    }

    /// Fly for at most `dt` under `damping`, stopping at the first instant the clearance falls
    /// to [`CONTACT_CLEARANCE`] (conservative advancement, module docs). `support` is the support
    /// function h of the body frame. The speed bound holds with damping too: damping only
    /// lowers |v| towards the terminal velocity, and the rotational energy.
    pub fn fly(&mut self, dt: f64, inertia: &Inertia, damping: Damping, support: &dyn Fn(&Vec3) -> f64) -> Flew {
        // |ω| ≤ √(2 T_rot / λ_min): T_rot is constant in free flight (it only falls with damping).
        let t_rot = self.omega_body.dot(&(inertia.matrix * self.omega_body));
        let omega_max = (t_rot / inertia.smallest).sqrt();
        let mut t = 0.0;
        for _ in 0..MAX_ADVANCES {
            // h ≤ 1 in every direction: high up, the support need not be asked.
            let gap = if self.z - 1.0 > TAKE_OFF_CLEARANCE {
                self.z - 1.0 - CONTACT_CLEARANCE
            } else {
                clearance(self.z, support(&self.down())) - CONTACT_CLEARANCE
            };
            if gap <= LANDING_TOLERANCE {
                return Flew::Landed(t);
            }
            let left = dt - t;
            if left <= 0.0 {
                return Flew::Airborne;
            }
            let speed = (-self.linvel.z).max(0.0) + G * left + omega_max;
            let tau = (gap / speed).min(left);
            self.step_damped(tau, &inertia.matrix, &inertia.inverse, damping);
            t = if tau == left { dt } else { t + tau };
        }
        // Out of moves (a graze, or a speed bound ≫ 100 m/s): land where it is, still above
        // CONTACT_CLEARANCE.
        Flew::Landed(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tumbling() -> FreeBody {
        let q = UnitQuaternion::from_euler_angles(0.3, -1.1, 2.0);
        FreeBody::new(3.0, Vec3::new(1.0, -2.0, 0.5), q, &Vec3::new(30.0, -25.0, 33.0))
    }

    #[test]
    fn energy_and_angular_momentum_are_conserved_in_a_tumble() {
        // An asymmetric body (principal moments 0.1, 0.2, 0.25, rotated off the axes), tumbling
        // near its unstable middle axis at ≈ 50 rad/s for 1 s: the hardest case for an integrator.
        let r = nalgebra::Rotation3::from_euler_angles(0.4, 0.2, -0.7);
        let inertia = r.matrix() * Matrix3::from_diagonal(&Vec3::new(0.1, 0.2, 0.25)) * r.matrix().transpose();
        let inv = inertia.try_inverse().unwrap();
        let mut b = tumbling();
        let (e0, l0) = (b.omega_body.dot(&(inertia * b.omega_body)), b.angular_momentum(&inertia));
        let vz0 = b.linvel.z;
        let dt = 1.0 / 240.0;
        for _ in 0..240 {
            b.step(dt, &inertia, &inv);
        }
        let e1 = b.omega_body.dot(&(inertia * b.omega_body));
        assert!(((e1 - e0) / e0).abs() < 1e-6, "rotational energy drifts by {:e}", (e1 - e0) / e0);
        let dl = (b.angular_momentum(&inertia) - l0).norm() / l0.norm();
        assert!(dl < 1e-6, "angular momentum drifts by {dl:e}");
        // G exactly on its parabola.
        assert!((b.z - (3.0 + vz0 - 0.5 * G)).abs() < 1e-12);
        assert!((b.linvel.z - (vz0 - G)).abs() < 1e-12);
        // Not vacuous: the body did turn, and the body-frame ω moved (it is not a steady spin).
        assert!(b.orientation.angle_to(&tumbling().orientation) > 0.1);
        assert!((b.omega_body - tumbling().omega_body).norm() > 1.0);
    }

    #[test]
    fn damped_flight_has_its_closed_form() {
        // dv/dt = g − c v: v_z(t) = −g/c + (v₀ + g/c) e^{−ct}, z(t) = z₀ + (v₀ + g/c)(1 − e^{−ct})/c
        // − g t/c; v_x decays as e^{−ct}. For an isotropic body (Iω × ω = 0) ω(t) = ω₀ e^{−c_ω t}.
        let inertia = Matrix3::identity() * 0.4;
        let inv = inertia.try_inverse().unwrap();
        let damping = Damping { linear: 0.1, angular: 1.0 };
        let (v0, w0) = (Vec3::new(2.0, 0.0, 3.0), Vec3::new(5.0, -3.0, 1.0));
        let mut b = FreeBody::new(2.0, v0, UnitQuaternion::identity(), &w0);
        let (dt, steps) = (1.0 / 240.0, 360);
        for _ in 0..steps {
            b.step_damped(dt, &inertia, &inv, damping);
        }
        let t = dt * steps as f64;
        let (c, e) = (damping.linear, (-damping.linear * t).exp());
        let vz = -G / c + (v0.z + G / c) * e;
        let z = 2.0 + (v0.z + G / c) * (1.0 - e) / c - G * t / c;
        assert!((b.linvel.z - vz).abs() < 1e-10 && (b.z - z).abs() < 1e-10, "{} {vz}, {} {z}", b.linvel.z, b.z);
        assert!((b.linvel.x - v0.x * e).abs() < 1e-12);
        let w = w0 * (-damping.angular * t).exp();
        assert!((b.angvel() - w).norm() < 1e-8, "{:?} vs {w:?}", b.angvel());
        // Not vacuous: without damping the same flight ends elsewhere.
        let mut free = FreeBody::new(2.0, v0, UnitQuaternion::identity(), &w0);
        for _ in 0..steps {
            free.step(dt, &inertia, &inv);
        }
        assert!((free.z - b.z).abs() > 0.01 && (free.angvel() - w).norm() > 1.0);
    }

    #[test]
    fn symmetric_top_precesses_at_its_closed_form_rate() {
        // I = diag(a, a, c): in the body frame ω precesses about the symmetry axis at
        // Ω = (c − a)/a · ω₃, with ω₃ and |ω⊥| constant.
        let (a, c) = (0.2, 0.35);
        let inertia = Matrix3::from_diagonal(&Vec3::new(a, a, c));
        let inv = inertia.try_inverse().unwrap();
        let (w_perp, w3) = (4.0, 20.0);
        let mut b = FreeBody::new(0.0, Vec3::zeros(), UnitQuaternion::identity(), &Vec3::new(w_perp, 0.0, w3));
        let t = 0.7;
        let n = 700;
        for _ in 0..n {
            b.step(t / n as f64, &inertia, &inv);
        }
        let omega = (c - a) / a * w3;
        // Body-frame ω̇ = I⁻¹(Iω × ω): ω̇₁ = −Ω ω₂, ω̇₂ = Ω ω₁, so (ω₁, ω₂) turns by +Ω t.
        let expect = Vec3::new(w_perp * (omega * t).cos(), w_perp * (omega * t).sin(), w3);
        assert!((b.omega_body - expect).norm() < 1e-7, "{:?} vs {:?}", b.omega_body, expect);
    }
}
