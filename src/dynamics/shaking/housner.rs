//! Housner's rigid block: the closed forms and the rocking equation the engine is checked
//! against, and the two measurements that compare them with rapier — the validation module the
//! tests (`tests/perturb.rs`, `tests/shake_rock.rs`) and experiments (`housner_block`,
//! `fragility_surface`, `ensemble_fragility`) share.
//!
//! A block of half-width b and half-height h (tan α = b/h, R = √(b² + h²)) on a rigid ground with
//! enough friction:
//!
//! * under a horizontal ground acceleration a it stays in full contact as long as a < g tan α
//!   and starts to tip when a exceeds it ([`ramp_tipping`] measures it with a slowly rising a);
//! * rocking freely, its angular velocity drops at every impact by the factor
//!   r = 1 − (3/2) sin² α (conservation of angular momentum about the impacting corner, with a
//!   perfectly plastic impact at that corner alone, [`housner_ratio`]) — [`free_rocking`]
//!   measures the ratio of the impact angular velocities of successive half-cycles;
//! * under any ground motion its rocking follows Housner's equation ([`housner_overturns`]),
//!   integrated here independently of rapier: for one block ([`HousnerBlock::overturns_along`]),
//!   for the members of an ensemble ([`HousnerBlock::overturns_drawn`],
//!   [`HousnerBlock::overturns_oriented`]), its fragility read in Housner's dimensionless
//!   variables ([`HousnerBlock::dimensionless_pga_at`]).

use crate::analysis::{Analysis, Options};
use crate::dynamics::engine::convert;
use crate::dynamics::engine::run::Drive;
use crate::dynamics::engine::simulation::Simulation;
use crate::dynamics::resting::{resting_simulation, RestingParams};
use crate::dynamics::shaking::drive::GroundDrive;
use crate::dynamics::shaking::ensemble::Draw;
use crate::dynamics::stone::{resting_orientation, Stone};
use crate::ground_motion::fragility::FragilitySurface;
use crate::ground_motion::Record;
use crate::rng::item_rng;
use crate::{Error, Result, Vec3, GRAVITY};
use nalgebra::UnitQuaternion;
use rand::RngExt;
use serde::Serialize;

/// A rectangular block of half-width `b` (x), half-depth `d` (y) and half-height `h` (z), in
/// input units ([`crate::generate::cuboid`] of 2b × 2d × 2h), as a stone with its flocks at `nu`
/// (its macro ν if None), and the position in [`Stone::stable`] of its rest on the face with
/// normal −z: the block of [`ramp_tipping`] and [`free_rocking`], rocking in the x–z plane with
/// tan α = b/h.
pub fn block_stone(b: f64, d: f64, h: f64, nu: Option<f64>) -> Result<(Stone, usize)> {
    if ![b, d, h].iter().all(|x| *x > 0.0 && x.is_finite()) {
        return Err(Error::parameter("block", format!("{b} × {d} × {h}"), "positive half-lengths b × d × h"));
    }
    let (mesh, repairs) = crate::generate::cuboid(2.0 * b, 2.0 * d, 2.0 * h).into_solid_boundary()?;
    let stone = super::rock::stone_of(&Analysis::of_solid(mesh, repairs, &Options::default())?, nu)?;
    let bottom = stone.stable().iter().position(|e| stone.body.facet_normals[e.facet as usize].z < -0.999);
    let what = "the block has no stable rest on its bottom face";
    let bottom =
        bottom.ok_or_else(|| Error::Pose { pose: "on the face with normal −z".into(), what: what.into() })?;
    Ok((stone, bottom))
}

/// Housner's ramp: the stone at rest on `start`, the ground accelerating along `azimuth` with
/// a(t) = `rate`·t (g per scaled second) up to `a_max` (g). Returns the ground acceleration
/// (g) at which the resting facet's tilt first exceeds `tilt` (rad), or None.
///
/// The detection lags the true onset: past the threshold a_c the overturning moment grows
/// like m h (a − a_c), so the tilt grows like (t − t_c)³ and the reading is late by about
/// (6 I_O tilt / (m h g rate))^(1/3)·rate (in g); keep `rate` and `tilt` small.
pub fn ramp_tipping(
    stone: &Stone,
    start: usize,
    p: &RestingParams,
    azimuth: f64,
    rate: f64,
    tilt: f64,
    a_max: f64,
) -> Option<f64> {
    let s = &stone.stable()[start];
    let dt = p.sim.numerics.dt;
    let mut sim = resting_simulation(stone, start, p, p.settle_time);
    let n = stone.body.facet_normals[s.facet as usize];
    // The tilt of the settled, unloaded stone is the reference.
    let tilt0 = n.dot(&sim.state().down).clamp(-1.0, 1.0).acos();
    let ramp = ramp_record(rate, a_max).ok()?;
    // The scaled body itself (R_max = 1 m): the record's time is the scaled time.
    let mut ground = GroundDrive::new(&ramp, azimuth, 1.0, dt);
    for step in 0..ground.active_steps() {
        ground.before_step(&mut sim, step);
        sim.step();
        if n.dot(&sim.state().down).clamp(-1.0, 1.0).acos() - tilt0 > tilt {
            return Some(ramp.at((step + 1) as f64 * dt)[0] / GRAVITY);
        }
    }
    None
}

/// The detection lag (g) of [`ramp_tipping`] on a block of half-width `b` and half-height `h`
/// (scaled lengths, R_max = 1) at ramp `rate` (g per scaled s) and detection `tilt` (rad):
/// rate·(6 I_O tilt / (h rate g))^(1/3), I_O = (4/3)(b² + h²) the block's moment of inertia
/// about its bottom edge (unit mass).
pub fn ramp_lag(b: f64, h: f64, rate: f64, tilt: f64) -> f64 {
    let i_o = 4.0 / 3.0 * (b * b + h * h);
    rate * (6.0 * i_o * tilt / (h * rate * GRAVITY)).cbrt()
}

/// The ground acceleration a(t) = `rate`·t along x (g per s) up to `a_max` (g), in m/s².
pub fn ramp_record(rate: f64, a_max: f64) -> Result<Record> {
    if !(rate > 0.0 && a_max > 0.0 && rate.is_finite() && a_max.is_finite()) {
        return Err(Error::motion("ramp", format!("needs a positive rate and peak, got {rate} g/s up to {a_max} g")));
    }
    Record::new("ramp", a_max / rate, vec![[0.0; 3], [a_max * GRAVITY, 0.0, 0.0]])
}

/// One free-rocking half-cycle of a block (between two impacts).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct HalfCycle {
    /// Start and end time (s, scaled).
    pub t0: f64,
    /// End time (s, scaled).
    pub t1: f64,
    /// Largest |θ| in the half-cycle (rad).
    pub amplitude: f64,
    /// Angular velocity the block has at θ = 0 on the corner it rocks on in this half-cycle:
    /// the median over the half-cycle's samples (|θ| ≥ 0.2 amplitude) of
    /// √(ω² + (2 m g R / I_O)(cos(α − |θ|) − cos α)), which is constant for a rigid rotation about
    /// the corner (energy conservation), so it measures the impact velocities without reading
    /// the few steps the soft contact takes to turn the block over.
    pub omega0: f64,
}

/// Free rocking of a box resting on its face with normal −z (a [`crate::generate::cuboid`] of
/// full lengths 2b × 2d × 2h along x, y, z, in input units), released from rest tilted by
/// `theta0` (rad) about its +x bottom edge (rotation about y), simulated for `duration` scaled
/// seconds. Returns the half-cycles between zero crossings of θ, the rotation about y.
pub fn free_rocking(
    stone: &Stone,
    start: usize,
    p: &RestingParams,
    b: f64,
    h: f64,
    theta0: f64,
    duration: f64,
) -> Vec<HalfCycle> {
    let s = &stone.stable()[start];
    let q0 = resting_orientation(&stone.body.facet_normals[s.facet as usize]);
    let q = UnitQuaternion::from_axis_angle(&Vec3::y_axis(), theta0) * q0;
    let down = q.inverse() * -Vec3::z();
    let z = stone.body.support(&down);
    let mut sim = Simulation::new(&stone.body, &p.sim, &q, z, &Vec3::zeros(), &Vec3::zeros());
    sim.set_contact_frequency(p.contact_frequency);
    let dt = p.sim.numerics.dt;
    let r_max = stone.body.r_max;
    let (b, h) = (b / r_max, h / r_max);
    let big_r = (b * b + h * h).sqrt();
    let alpha = b.atan2(h);
    // I_O = I_G + m R² for rotation about the bottom edge (unit mass, scaled); I_G from the body.
    let i_o = stone.body.inertia[(1, 1)] + big_r * big_r;
    let k = 2.0 * GRAVITY * big_r / i_o;
    let steps = (duration / dt).ceil() as u64;
    let mut samples: Vec<(f64, f64, f64)> = Vec::with_capacity(steps as usize);
    for step in 1..=steps {
        sim.step();
        let rb = &sim.world.bodies[sim.body_handle];
        let rot = convert::quat_back(rb.rotation()) * q0.inverse();
        let x = rot * Vec3::x();
        let theta = (-x.z).atan2(x.x);
        let omega = convert::vec_back(rb.angvel()).y;
        samples.push((step as f64 * dt, theta, omega));
    }
    let mut cycles = Vec::new();
    let mut begin = 0;
    for i in 1..=samples.len() {
        let end = i == samples.len() || samples[i].1.signum() != samples[i - 1].1.signum();
        if !end {
            continue;
        }
        let part = &samples[begin..i];
        begin = i;
        let amplitude = part.iter().fold(0.0f64, |m, s| m.max(s.1.abs()));
        let mut inv: Vec<f64> = part
            .iter()
            .filter(|s| s.1.abs() >= 0.2 * amplitude)
            .map(|s| (s.2 * s.2 + k * ((alpha - s.1.abs()).cos() - alpha.cos())).max(0.0).sqrt())
            .collect();
        if inv.is_empty() {
            continue;
        }
        inv.sort_by(f64::total_cmp);
        cycles.push(HalfCycle { t0: part[0].0, t1: part[part.len() - 1].0, amplitude, omega0: inv[inv.len() / 2] });
    }
    cycles
}

/// The impacts of free rocking ([`free_rocking`]'s half-cycles), until the rocking has died out:
/// for each half-cycle after the first, its amplitude (rad) and the ratio ω₀(it)/ω₀(the one
/// before) of the impact that began it, up to the first half-cycle of amplitude `floor` (rad) or
/// less.
pub fn impact_ratios(cycles: &[HalfCycle], floor: f64) -> Vec<(f64, f64)> {
    let impacts = cycles.windows(2).take_while(|w| w[1].amplitude > floor);
    impacts.map(|w| (w[1].amplitude, w[1].omega0 / w[0].omega0)).collect()
}

/// The mean ratio of the first (up to) `count` `impacts` ([`impact_ratios`]) whose amplitude
/// after the impact exceeds `amplitude` (rad): impacts small enough for the contact's
/// compliance to matter left out. None if there is none.
pub fn mean_impact_ratio(impacts: &[(f64, f64)], amplitude: f64, count: usize) -> Option<f64> {
    let large: Vec<f64> = impacts.iter().filter(|i| i.0 > amplitude).take(count).map(|i| i.1).collect();
    (!large.is_empty()).then(|| large.iter().sum::<f64>() / large.len() as f64)
}

/// Housner's ratio of angular velocities after / before an impact of a rocking block,
/// 1 − (3/2) sin² α, tan α = b/h.
pub fn housner_ratio(b: f64, h: f64) -> f64 {
    let a = b.atan2(h);
    1.0 - 1.5 * a.sin().powi(2)
}

/// A freestanding rectangular block for Housner's rocking equation: its slenderness tan α = b/h
/// (half-width over half-height) and the semi-diagonal R = √(b² + h²) (m) of its rocking plane.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct HousnerBlock {
    /// tan α = b/h.
    pub tan_alpha: f64,
    /// R (m).
    pub r_m: f64,
}

impl HousnerBlock {
    /// Housner's frequency parameter p = √(3g/4R) (rad/s).
    pub fn p(&self) -> f64 {
        (3.0 * GRAVITY / (4.0 * self.r_m)).sqrt()
    }

    /// Whether Housner's equation ([`housner_overturns`]), with Housner's impact ratio
    /// ([`housner_ratio`]), overturns the block under the ground acceleration `accel(t)` in its
    /// rocking plane (m/s²) within `duration` s.
    pub fn overturns(&self, accel: &dyn Fn(f64) -> f64, duration: f64) -> bool {
        housner_overturns(self.tan_alpha.atan(), self.p(), accel, duration, housner_ratio(self.tan_alpha, 1.0))
    }

    /// Whether Housner's equation overturns the block under the horizontal components of
    /// `record` times `k` (a scale factor, its sign included), its rocking plane at `theta` (rad)
    /// from the record's x axis: ü_g(t) = k (cos θ a_x(t) + sin θ a_y(t)) over the record
    /// ([`HousnerBlock::overturns`]).
    pub fn overturns_along(&self, record: &Record, k: f64, theta: f64) -> bool {
        let (s, c) = theta.sin_cos();
        let accel = |t: f64| {
            let a = record.at(t);
            k * (c * a[0] + s * a[1])
        };
        self.overturns(&accel, record.duration())
    }

    /// The contour P = `prob` of a fitted fragility `surface` in the block's dimensionless
    /// variables: PGA/(g tan α) at τ = p·PGV/PGA (the surface's [`FragilitySurface::pga_at`] at
    /// PGV/PGA = τ/p); None where the surface has no such contour ([`FragilitySurface::pga_at`]).
    pub fn dimensionless_pga_at(&self, surface: &FragilitySurface, prob: f64, tau: f64) -> Option<f64> {
        surface.pga_at(prob, tau / self.p()).map(|pga| pga / self.tan_alpha)
    }

    /// The band of that contour ([`FragilitySurface::pga_band_at`], `z` standard errors) in the
    /// same variables over the τ of `taus`, as a polygon: its low-PGA edge along `taus`, then its
    /// high-PGA edge back, at the τ where both edges are found.
    pub fn dimensionless_band(&self, surface: &FragilitySurface, prob: f64, taus: &[f64], z: f64) -> Vec<(f64, f64)> {
        let edges = |&t: &f64| {
            let [lo, _, hi] = surface.pga_band_at(prob, t / self.p(), z)?;
            Some(((t, lo? / self.tan_alpha), (t, hi? / self.tan_alpha)))
        };
        let band: Vec<_> = taus.iter().filter_map(edges).collect();
        band.iter().map(|e| e.0).chain(band.iter().rev().map(|e| e.1)).collect()
    }

    /// Housner's equation on the members `draws` of an ensemble under `record` × `scale`: a
    /// member's record has its x axis at the draw's azimuth φ from the rocking plane (as
    /// [`Record::rotated`] puts it) and the draw's sign, so the plane is at −φ from the record's
    /// x axis ([`HousnerBlock::overturns_along`] with k = scale × sign). One outcome per draw, the
    /// draws run in parallel.
    pub fn overturns_drawn(&self, record: &Record, scale: f64, draws: &[Draw]) -> Vec<bool> {
        use rayon::prelude::*;
        let along = |d: &Draw| self.overturns_along(record, scale * d.sign, -d.azimuth_deg.to_radians());
        draws.par_iter().map(along).collect()
    }

    /// Housner's equation on `members` random orientations of the block under each case
    /// (record, scale factor) of `cases`: member m draws from stream m of `seed` ([`item_rng`])
    /// the angle θ of its rocking plane from the records' x axis, uniform in [0, 2π), then its
    /// sign, −1 or +1 with probability ½ each. Entry [m][k] says whether case k overturns member m
    /// ([`HousnerBlock::overturns_along`] with k = scale × sign). The members run in parallel.
    pub fn overturns_oriented(&self, cases: &[(&Record, f64)], members: u64, seed: u64) -> Vec<Vec<bool>> {
        use rayon::prelude::*;
        let member = |m: u64| -> Vec<bool> {
            let mut rng = item_rng(seed, m);
            let theta = rng.random_range(0.0..std::f64::consts::TAU);
            let sign = if rng.random::<f64>() < 0.5 { -1.0 } else { 1.0 };
            cases.iter().map(|&(record, scale)| self.overturns_along(record, scale * sign, theta)).collect()
        };
        (0..members).into_par_iter().map(member).collect()
    }
}

/// Housner's rocking equation for a rigid rectangular block (Housner 1963; the form integrated by
/// Makris & Roussos 2000 and Zhang & Makris 2001), integrated independently of rapier — the
/// reference the rapier block is checked against (`tests/shake_rock.rs`,
/// `experiments/fragility_surface.rs`). `alpha` = atan(b/h), `p` = √(3g/4R) (rad/s), `accel` the
/// ground acceleration ü_g(t) (m/s²) for 0 ≤ t ≤ `duration` (s), `r` the impact ratio. Returns
/// whether the block overturns:
///
/// θ̈ = −p² [sin(α sgn θ − θ) + (ü_g/g) cos(α sgn θ − θ)],   p² = 3g/(4R),
///
/// rocking starts when |ü_g| > g tan α (θ takes the sign of −ü_g), at every impact (θ crossing 0)
/// the angular velocity is multiplied by r = 1 − (3/2) sin² α, and the block returns to rest when
/// an impact leaves it slower than 10⁻⁶ p while |ü_g| ≤ g tan α. It overturns when |θ| passes
/// π/2, or passes α after the ground motion has ended (gravity alone then tips it over).
/// RK4 with 4000 steps per 2π/p.
pub fn housner_overturns(alpha: f64, p: f64, accel: &dyn Fn(f64) -> f64, duration: f64, r: f64) -> bool {
    let g = GRAVITY;
    let h = 2.0 * std::f64::consts::PI / p / 4000.0;
    let rhs = |t: f64, th: f64, side: f64| {
        let a = if t <= duration { accel(t) } else { 0.0 };
        -p * p * ((alpha * side - th).sin() + a / g * (alpha * side - th).cos())
    };
    let (mut t, mut th, mut w, mut side, mut resting) = (0.0f64, 0.0f64, 0.0f64, 1.0f64, true);
    let t_end = duration + 40.0 / p;
    while t < t_end {
        let a = if t <= duration { accel(t) } else { 0.0 };
        if resting {
            if a.abs() > g * alpha.tan() {
                resting = false;
                side = -a.signum();
            } else {
                t += h;
                continue;
            }
        }
        // RK4 on (θ, ω) on the current corner.
        let k1 = (w, rhs(t, th, side));
        let k2 = (w + 0.5 * h * k1.1, rhs(t + 0.5 * h, th + 0.5 * h * k1.0, side));
        let k3 = (w + 0.5 * h * k2.1, rhs(t + 0.5 * h, th + 0.5 * h * k2.0, side));
        let k4 = (w + h * k3.1, rhs(t + h, th + h * k3.0, side));
        let th_new = th + h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        let w_new = w + h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        t += h;
        if th_new * side < 0.0 {
            // Impact: onto the other corner, angular velocity × r.
            th = 0.0;
            w = r * w_new;
            side = -side;
            let a = if t <= duration { accel(t) } else { 0.0 };
            if w.abs() < 1e-6 * p && a.abs() <= g * alpha.tan() {
                resting = true;
                w = 0.0;
            }
            continue;
        }
        th = th_new;
        w = w_new;
        if th.abs() > std::f64::consts::FRAC_PI_2 || (t > duration && th.abs() > alpha) {
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_housner_block_rocks_above_g_tan_alpha_only() {
        // p = √(3g/4R): R = 3/4 m gives p = √g.
        let block = HousnerBlock { tan_alpha: 0.25, r_m: 0.75 };
        assert!((block.p() - GRAVITY.sqrt()).abs() < 1e-12);
        // A constant ground acceleration below g tan α never lifts the block; one held above it
        // pushes it over (the overturning moment grows as the block tips).
        let a_c = GRAVITY * block.tan_alpha;
        assert!(!block.overturns(&|_| 0.98 * a_c, 5.0));
        assert!(!block.overturns(&|_| -0.98 * a_c, 5.0));
        assert!(block.overturns(&|_| 1.5 * a_c, 5.0));
        assert!(block.overturns(&|_| -1.5 * a_c, 5.0));
    }

    #[test]
    fn a_housner_block_feels_the_record_along_its_rocking_plane() {
        // A record of constant 1.5 g tan α along y (10 s): the block overturns with its plane
        // along y, either sign, but not along x, nor at 60° from y (cos 60° · 1.5 = 0.75 < 1).
        let block = HousnerBlock { tan_alpha: 0.25, r_m: 0.75 };
        let a = 1.5 * GRAVITY * block.tan_alpha;
        let record = Record::new("y", 0.01, vec![[0.0, a, 0.0]; 1001]).unwrap();
        let half_pi = std::f64::consts::FRAC_PI_2;
        assert!(block.overturns_along(&record, 1.0, half_pi) && block.overturns_along(&record, -1.0, half_pi));
        assert!(!block.overturns_along(&record, 1.0, 0.0));
        assert!(!block.overturns_along(&record, 1.0, half_pi / 3.0));
        // Scaled by 2, 60° from y is 1.5 g tan α again.
        assert!(block.overturns_along(&record, 2.0, half_pi / 3.0));
    }

    #[test]
    fn the_ramp_lag_grows_as_the_rate_to_two_thirds() {
        // b = 1/2, h = 1: I_O = 5/3, and at tilt 10⁻³ 6 I_O tilt = 10⁻², so at rate 10⁻² g/s
        // the lag is 10⁻² g^(−1/3); eight times the rate, four times the lag.
        let lag = ramp_lag(0.5, 1.0, 0.01, 1e-3);
        assert!((lag - 0.01 / GRAVITY.cbrt()).abs() < 1e-15, "{lag}");
        assert!((ramp_lag(0.5, 1.0, 0.08, 1e-3) / lag - 4.0).abs() < 1e-12);
    }

    #[test]
    fn impacts_are_ratios_of_successive_half_cycles_until_the_rocking_dies() {
        let cycle = |amplitude: f64, omega0: f64| HalfCycle { t0: 0.0, t1: 0.0, amplitude, omega0 };
        let cycles = [cycle(0.1, 2.0), cycle(0.05, 1.0), cycle(0.01, 0.8), cycle(1e-6, 0.1), cycle(0.03, 0.3)];
        // Everything from the first amplitude at or below 10⁻⁵ rad on is contact noise.
        let impacts = impact_ratios(&cycles, 1e-5);
        assert_eq!(impacts, vec![(0.05, 0.5), (0.01, 0.8)]);
        // Only impacts that leave more than 0.02 rad count: the first one; at most one: the first.
        assert_eq!(mean_impact_ratio(&impacts, 0.02, 4), Some(0.5));
        assert!((mean_impact_ratio(&impacts, 0.0, 4).unwrap() - 0.65).abs() < 1e-15);
        assert_eq!(mean_impact_ratio(&impacts, 0.0, 1), Some(0.5));
        assert_eq!(mean_impact_ratio(&impacts, 0.1, 4), None);
    }

    #[test]
    fn oriented_members_overturn_where_their_plane_sees_enough_of_the_record() {
        // A constant 3 g tan α along x: a member overturns where |cos θ| > 1/3 (θ uniform), a
        // share 2 acos(1/3)/π = 0.784 of the members; 400 members: a binomial standard error of
        // 0.021. The same record at scale 0.3 (0.9 g tan α) overturns none.
        let block = HousnerBlock { tan_alpha: 0.25, r_m: 0.75 };
        let record = Record::new("x", 0.01, vec![[3.0 * GRAVITY * block.tan_alpha, 0.0, 0.0]; 501]).unwrap();
        let outcome = block.overturns_oriented(&[(&record, 1.0), (&record, 0.3)], 400, 7);
        let share = outcome.iter().filter(|o| o[0]).count() as f64 / 400.0;
        let expected = 2.0 * (1.0f64 / 3.0).acos() / std::f64::consts::PI;
        assert!((share - expected).abs() < 0.07, "{share} vs {expected}");
        assert!(outcome.iter().all(|o| !o[1]));
        assert_eq!(outcome, block.overturns_oriented(&[(&record, 1.0), (&record, 0.3)], 400, 7));
    }

    #[test]
    fn a_surface_reads_in_housner_s_dimensionless_variables() {
        // R = 3/4 m: p = √g. A surface with β = (0, 1, 0) has PGA₅₀ = 1 g at every PGV/PGA, so
        // PGA₅₀/(g tan α) = 4 at tan α = 0.25; with β₂ = 1 too, PGA₅₀ = 1/(PGV/PGA) = p/τ.
        let block = HousnerBlock { tan_alpha: 0.25, r_m: 0.75 };
        let flat = FragilitySurface::exact([0.0, 1.0, 0.0]);
        assert!((block.dimensionless_pga_at(&flat, 0.5, 2.0).unwrap() - 4.0).abs() < 1e-12);
        let sloped = FragilitySurface::exact([0.0, 1.0, 1.0]);
        let at = block.dimensionless_pga_at(&sloped, 0.5, 2.0).unwrap();
        assert!((at - 4.0 * GRAVITY.sqrt() / 2.0).abs() < 1e-12, "{at}");
        // A band ±1.96 on β₀ (variance 1): ln PGA ± 1.96 about the contour, within the grid's step.
        let fit = FragilitySurface { covariance: [[1.0, 0.0, 0.0], [0.0; 3], [0.0; 3]], ..flat };
        let band = block.dimensionless_band(&fit, 0.5, &[1.0, 2.0, 3.0], 1.96);
        assert_eq!(band.iter().map(|p| p.0).collect::<Vec<_>>(), [1.0, 2.0, 3.0, 3.0, 2.0, 1.0]);
        let step = 12.0 / 4000.0;
        assert!(band[..3].iter().all(|p| ((p.1 / 4.0).ln() + 1.96).abs() <= step), "{band:?}");
        assert!(band[3..].iter().all(|p| ((p.1 / 4.0).ln() - 1.96).abs() <= step), "{band:?}");
        // No band where the fit has no contour.
        assert!(block.dimensionless_band(&FragilitySurface::exact([0.0, -1.0, 0.0]), 0.5, &[1.0], 1.96).is_empty());
    }

    #[test]
    fn a_block_stone_rests_on_its_bottom_face() {
        // b = 0.25, d = 0.3, h = 1: the rest on the face −z lies h = 1 below the centre of mass.
        let (stone, k) = block_stone(0.25, 0.3, 1.0, Some(0.01)).unwrap();
        let rest = &stone.stable()[k];
        assert!(stone.body.facet_normals[rest.facet as usize].z < -0.999);
        assert!((rest.r - 1.0).abs() < 1e-9, "{}", rest.r);
        assert_eq!(stone.nu, 0.01);
        assert!(block_stone(0.25, 0.3, 0.0, None).is_err());
    }

    #[test]
    fn a_drawn_member_sees_the_record_turned_by_its_azimuth() {
        // A constant 1.5 g tan α along y: a member whose record's x axis is at 90° from the
        // rocking plane has the record's y axis along −x, in the plane: it overturns, either sign.
        // At 0° (y across the plane) and at 30° (y at 60° from the plane: cos 60° · 1.5 < 1) it
        // stands; at 30° and scale 2, 1.5 g tan α again, it overturns.
        let block = HousnerBlock { tan_alpha: 0.25, r_m: 0.75 };
        let record = Record::new("y", 0.01, vec![[0.0, 1.5 * GRAVITY * block.tan_alpha, 0.0]; 501]).unwrap();
        let draw = |azimuth_deg: f64, sign: f64| Draw {
            member: 0,
            contact_tolerance_m: 0.0,
            azimuth_deg,
            sign,
            friction: 0.6,
            restitution: 0.3,
            rolling_resistance_m: 0.0,
            base: None,
        };
        let draws = [draw(90.0, 1.0), draw(90.0, -1.0), draw(0.0, 1.0), draw(30.0, 1.0)];
        assert_eq!(block.overturns_drawn(&record, 1.0, &draws), [true, true, false, false]);
        assert_eq!(block.overturns_drawn(&record, 2.0, &draws[3..]), [true]);
    }
}
