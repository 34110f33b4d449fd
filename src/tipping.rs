//! The quasi-static tipping acceleration of a stone standing on flat ground, against azimuth
//! (the quasi-static side of a field rock): what a field geologist checks first.
//!
//! A rigid stone with centre of mass G stands on the plane with body-frame down direction d.
//! Its *support polygon* P is the convex hull of the hull corners that touch the ground,
//! projected into the ground plane, with G's projection as origin. A horizontal ground
//! acceleration of magnitude a, pointing along −u, acts on the stone (in the ground's frame) as a
//! force m a u at G, at height h above the ground; the stone starts to lift about the side of P
//! that supports it in direction u once the moment of that force exceeds the moment of its weight:
//!
//! ```text
//! m a h > m g s_P(u)   ⇔   a / g > tan α(u) = s_P(u) / h,     s_P(u) = max_{p ∈ P} p·u
//! ```
//!
//! (Housner's tan α for a block, in every direction). Over all directions the smallest is the
//! distance from G's projection to the nearest side of P, divided by h: the minimum quasi-static
//! tipping acceleration. Exact for a rigid stone on a rigid plane; a dynamic ground motion needs
//! more than this to overturn the stone (Housner's rocking), never less to lift it.
//!
//! **Which corners touch (the contact tolerance).** A scan resolves the base to a few mm, and a
//! broad, nearly flat base has many corners within that of the lowest plane. A corner whose
//! height above the lowest corner (along d) is at most the tolerance τ is counted as touching:
//! physically, τ is how far the ground's or the rock's surface may deviate from the scanned
//! planes — soil, a thin layer of debris, the scan's own error — so that those corners can carry
//! load. The pose itself is unchanged (the rock is not re-seated); only its support polygon
//! grows with τ, and with it the tipping acceleration in the directions where new corners lie.
//!
//! **Azimuths.** (e₁, e₂) is an orthonormal basis of the ground plane in the body frame
//! ([`TippingPolar::basis`]); azimuth θ is measured from e₁ towards e₂, and direction θ is
//! u(θ) = cos θ e₁ + sin θ e₂. tan α(θ) is the ground acceleration (in g) that tips the stone
//! about its side in direction u(θ); that acceleration points along −u(θ).
//! [`TippingSummary`] carries the curve, its minimum and the basis, in metres and degrees.

use crate::{Error, Point3, Result, Vec3};
use serde::{Deserialize, Serialize};

/// The support polygon of a pose and the tipping acceleration it gives in every direction.
#[derive(Clone, Debug)]
pub struct TippingPolar {
    /// Height of G above the ground (input units).
    pub height: f64,
    /// Orthonormal basis (e₁, e₂) of the ground plane in the body frame: azimuth θ is measured
    /// from e₁ towards e₂, and direction θ is u(θ) = cos θ e₁ + sin θ e₂.
    pub basis: [Vec3; 2],
    /// The support polygon, counter-clockwise, in the basis coordinates relative to G's
    /// projection (input units). Fewer than three corners: the stone touches along an edge or
    /// at a point.
    pub polygon: Vec<[f64; 2]>,
}

impl TippingPolar {
    /// The support polygon of the stone with hull `corners` and centre of mass `g`, standing
    /// with body-frame down direction `down`, counting the corners within `tolerance` (input
    /// units, ≥ 0) of the lowest as touching (plus 10⁻¹² of the hull's size from G, so that the
    /// corners of the facet the stone rests on touch at τ = 0 despite rounding).
    pub fn new(corners: &[Point3], g: &Point3, down: &Vec3, tolerance: f64) -> Result<Self> {
        let n = down
            .try_normalize(1e-12)
            .ok_or_else(|| Error::parameter("down", format!("{down:?}"), "a non-zero direction"))?;
        if !(tolerance >= 0.0 && tolerance.is_finite()) {
            return Err(Error::parameter("tolerance", tolerance, "a finite length ≥ 0"));
        }
        if corners.is_empty() {
            return Err(Error::check("the hull has no corners"));
        }
        let depth = |p: &Point3| (p - g).dot(&n);
        let lowest = corners.iter().map(depth).fold(f64::NEG_INFINITY, f64::max);
        // Rounding: the corners of the facet a stone rests on differ in depth by ~10⁻¹⁶ of its
        // size; they all touch at τ = 0.
        let slack = 1e-12 * corners.iter().map(|p| (p - g).norm()).fold(0.0, f64::max);
        let e1 = n.cross(&if n.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() }).normalize();
        let e2 = n.cross(&e1);
        let touching: Vec<[f64; 2]> = corners
            .iter()
            .filter(|p| lowest - depth(p) <= tolerance + slack)
            .map(|p| {
                let r = p - g;
                [r.dot(&e1), r.dot(&e2)]
            })
            .collect();
        Ok(TippingPolar { height: lowest, basis: [e1, e2], polygon: convex_hull(touching) })
    }

    /// Whether G's projection lies inside the support polygon (on its boundary counts): the
    /// pose can stand at all.
    pub fn stands(&self) -> bool {
        self.polygon.len() >= 3 && self.sides().all(|(a, b)| cross(a, b) >= 0.0)
    }

    /// tan α in direction `azimuth` (rad): the ground acceleration (in g), pointing the other
    /// way, that starts to lift the stone about its support in that direction (module docs).
    /// Negative when G's projection is outside the polygon on that side.
    pub fn acceleration(&self, azimuth: f64) -> f64 {
        let u = [azimuth.cos(), azimuth.sin()];
        let s = self.polygon.iter().map(|p| p[0] * u[0] + p[1] * u[1]).fold(f64::NEG_INFINITY, f64::max);
        s / self.height
    }

    /// The smallest tipping acceleration over all directions (in g) and its azimuth (rad): the
    /// distance from G's projection to the nearest side of the support polygon over h, along
    /// that side's outward normal. 0 (azimuth of the contact's normal, or 0) for a stone that
    /// touches along an edge or at a point; negative if it cannot stand.
    pub fn minimum(&self) -> (f64, f64) {
        if self.polygon.len() < 3 {
            return (0.0, 0.0);
        }
        self.sides()
            .map(|(a, b)| {
                let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                let len = (dx * dx + dy * dy).sqrt();
                // Outward normal of a counter-clockwise side, and the signed distance of the
                // origin (G's projection) inside it.
                let normal = [dy / len, -dx / len];
                (cross(a, b) / len / self.height, normal[1].atan2(normal[0]))
            })
            .fold((f64::INFINITY, 0.0), |best, x| if x.0 < best.0 { x } else { best })
    }

    /// The smallest tilt of the ground, in degrees, that tips the stone: tilting the ground by β
    /// loads the stone as a horizontal acceleration g tan β does, so it is atan of the minimum
    /// tan α ([`TippingPolar::minimum`]) — the tilt that brings G's vertical over the nearest
    /// side of the support polygon.
    pub fn tipping_tilt_deg(&self) -> f64 {
        self.minimum().0.atan().to_degrees()
    }

    /// The polar as data (module docs): tolerance, height and support polygon in metres
    /// (lengths × `metres_per_unit`, the size of one input unit in metres, > 0), the minimum
    /// tan α (dimensionless, in g) with its azimuth in degrees in [0, 360), and the curve
    /// tan α(θ) sampled at θ = 0°, 1°, …, 359°. `tolerance_m` is the contact tolerance this
    /// polar was built with, in metres (recorded as given).
    pub fn summary(&self, tolerance_m: f64, metres_per_unit: f64) -> TippingSummary {
        let (minimum_g, azimuth) = self.minimum();
        let curve = (0..360).map(|k| [k as f64, self.acceleration((k as f64).to_radians())]).collect();
        let vec = |v: &Vec3| [v.x, v.y, v.z];
        TippingSummary {
            tolerance_m,
            height_m: self.height * metres_per_unit,
            stands: self.stands(),
            minimum_g,
            minimum_azimuth_deg: degrees_0_360(azimuth),
            support_polygon_m: self.polygon.iter().map(|p| [p[0] * metres_per_unit, p[1] * metres_per_unit]).collect(),
            curve,
            basis: [vec(&self.basis[0]), vec(&self.basis[1])],
        }
    }

    fn sides(&self) -> impl Iterator<Item = ([f64; 2], [f64; 2])> + '_ {
        let k = self.polygon.len();
        (0..k).map(move |i| (self.polygon[i], self.polygon[(i + 1) % k]))
    }
}

/// The quasi-static tipping of one pose as data, for JSON and plots: [`TippingPolar::summary`].
/// Azimuths as in the module docs: θ from e₁ towards e₂ (`basis`), u(θ) = cos θ e₁ + sin θ e₂;
/// tan α(θ) is the ground acceleration (in g), pointing along −u(θ), that tips the stone about
/// its side in direction u(θ).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TippingSummary {
    /// The contact tolerance τ (m).
    pub tolerance_m: f64,
    /// Height h of G above the ground (m).
    pub height_m: f64,
    /// Whether G's projection lies in the support polygon: the pose can stand.
    pub stands: bool,
    /// The smallest tan α over all azimuths (in g): the distance from G's projection to the
    /// nearest side of the support polygon over h. Negative if the pose cannot stand.
    pub minimum_g: f64,
    /// Azimuth of the minimum (degrees, in [0, 360)).
    pub minimum_azimuth_deg: f64,
    /// The support polygon, counter-clockwise, in the (e₁, e₂) coordinates relative to G's
    /// projection (m).
    pub support_polygon_m: Vec<[f64; 2]>,
    /// [θ (degrees), tan α(θ) (in g)] at θ = 0°, 1°, …, 359° (360 points).
    pub curve: Vec<[f64; 2]>,
    /// e₁ and e₂ in the body (mesh) frame: azimuth 0° is e₁, azimuth 90° is e₂.
    pub basis: [[f64; 3]; 2],
}

/// One [`TippingPolar`] per contact tolerance in `tolerances` (input units, each ≥ 0), for the
/// stone with hull `corners` and centre of mass `g` standing with body-frame down direction
/// `down` ([`TippingPolar::new`]). The support polygon, hence every tan α(θ), grows with τ.
pub fn tipping_polars(corners: &[Point3], g: &Point3, down: &Vec3, tolerances: &[f64]) -> Result<Vec<TippingPolar>> {
    tolerances.iter().map(|&tol| TippingPolar::new(corners, g, down, tol)).collect()
}

/// An angle in radians as degrees in [0, 360) (`rem_euclid` may round −0 or a tiny negative
/// angle up to 360 itself).
fn degrees_0_360(radians: f64) -> f64 {
    let d = radians.to_degrees().rem_euclid(360.0);
    if d >= 360.0 {
        0.0
    } else {
        d
    }
}

/// a × b (z component).
fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Convex hull of points in the plane, counter-clockwise, collinear points dropped (Andrew's
/// monotone chain).
fn convex_hull(mut p: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let turn = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = hull.len();
        let points: Box<dyn Iterator<Item = &[f64; 2]>> =
            if pass == 0 { Box::new(p.iter()) } else { Box::new(p.iter().rev()) };
        for &q in points {
            while hull.len() >= start + 2 && turn(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0 {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Corners of a box with half-sides a, b, c about the origin.
    fn block(a: f64, b: f64, c: f64) -> Vec<Point3> {
        (0..8)
            .map(|s| {
                let f = |k: usize, h: f64| if s >> k & 1 == 1 { -h } else { h };
                Point3::new(f(0, a), f(1, b), f(2, c))
            })
            .collect()
    }

    #[test]
    fn a_cube_tips_over_at_a_tilt_of_45_degrees() {
        let cube = TippingPolar::new(&block(1.0, 1.0, 1.0), &Point3::origin(), &-Vec3::z(), 0.0).unwrap();
        assert!((cube.tipping_tilt_deg() - 45.0).abs() < 1e-12);
        // A block twice as tall as wide: tan β = ½.
        let tall = TippingPolar::new(&block(0.5, 0.8, 1.0), &Point3::origin(), &-Vec3::z(), 0.0).unwrap();
        assert!((tall.tipping_tilt_deg() - 0.5f64.atan().to_degrees()).abs() < 1e-12);
    }

    #[test]
    fn a_block_tips_at_housners_tan_alpha_in_every_direction() {
        // A block 2a × 2b × 2c on its base: s(θ) = a|cos θ'| + b|sin θ'| in the block's axes, so
        // tan α = s / c; the minimum is min(a, b)/c, across the nearer side.
        let (a, b, c) = (0.3, 0.5, 1.2);
        let t = TippingPolar::new(&block(a, b, c), &Point3::origin(), &-Vec3::z(), 0.0).unwrap();
        assert!((t.height - c).abs() < 1e-12 && t.polygon.len() == 4 && t.stands());
        let x = t.basis[0];
        for k in 0..24 {
            let theta = k as f64 * std::f64::consts::TAU / 24.0;
            // The block's axes in the polar's basis: θ' = θ + (angle of e₁ from the block's x).
            let phi = x.y.atan2(x.x);
            let exact = (a * (theta + phi).cos().abs() + b * (theta + phi).sin().abs()) / c;
            assert!((t.acceleration(theta) - exact).abs() < 1e-12, "θ = {theta}");
        }
        let (min, azimuth) = t.minimum();
        assert!((min - a / c).abs() < 1e-12, "{min} vs {}", a / c);
        // Across the x sides: the direction of the minimum is ±x in the body frame.
        let u = t.basis[0] * azimuth.cos() + t.basis[1] * azimuth.sin();
        assert!(u.x.abs() > 1.0 - 1e-12, "{u:?}");
    }

    #[test]
    fn the_contact_tolerance_decides_which_corners_carry_the_stone() {
        // One base corner of the block raised by 2 mm (a scanned base that is not quite flat):
        // with a tolerance below 2 mm it does not touch and the support is the triangle of the
        // other three; from 2 mm on the full rectangle supports the stone again.
        let (a, b, c) = (0.3, 0.5, 1.2);
        let mut corners = block(a, b, c);
        let raised = corners.iter().position(|p| p.x > 0.0 && p.y > 0.0 && p.z < 0.0).unwrap();
        corners[raised].z += 0.002;
        let min = |tol: f64| TippingPolar::new(&corners, &Point3::origin(), &-Vec3::z(), tol).unwrap().minimum().0;
        let triangle = min(0.001);
        let rectangle = min(0.0025);
        assert!((rectangle - a / c).abs() < 1e-12, "{rectangle}");
        // G's projection (the origin) lies on the triangle's diagonal: the stone can just stand,
        // and the smallest acceleration that lifts it is 0.
        assert!(triangle.abs() < 1e-12, "{triangle}");
        // A less symmetric case: G moved off the diagonal towards the kept corners.
        let g = Point3::new(-0.05, -0.05, 0.0);
        let t = TippingPolar::new(&corners, &g, &-Vec3::z(), 0.001).unwrap();
        assert_eq!(t.polygon.len(), 3);
        let (m, _) = t.minimum();
        // Distance from (0.05, 0.05) (G in the triangle's frame, relative to G) to the diagonal
        // from (a, −b) to (−a, b): |b·0.05 + a·0.05| / √(a² + b²), over the height c.
        let d = (b * 0.05 + a * 0.05) / (a * a + b * b).sqrt() / c;
        assert!((m - d).abs() < 1e-9, "{m} vs {d}");
    }

    #[test]
    fn the_summary_of_a_block_holds_housners_minimum_and_its_curve() {
        // Block 2a × 2b × 2c, a < b: min tan α = a/c across the nearer sides (±x in the body).
        let (a, b, c) = (0.3, 0.5, 1.2);
        let t = TippingPolar::new(&block(a, b, c), &Point3::origin(), &-Vec3::z(), 0.0).unwrap();
        let s = t.summary(0.0, 1.0);
        assert!(s.stands && (s.minimum_g - a / c).abs() < 1e-12, "{}", s.minimum_g);
        assert!((0.0..360.0).contains(&s.minimum_azimuth_deg), "{}", s.minimum_azimuth_deg);
        assert_eq!(s.curve.len(), 360);
        assert!(s.curve.iter().enumerate().all(|(k, p)| p[0] == k as f64));
        let sampled = s.curve.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        assert!((sampled - s.minimum_g).abs() <= 1e-3 * s.minimum_g, "{sampled} vs {}", s.minimum_g);
        // The minimum's azimuth points along ±x in the body frame.
        let th = s.minimum_azimuth_deg.to_radians();
        let ux = s.basis[0][0] * th.cos() + s.basis[1][0] * th.sin();
        assert!(ux.abs() > 1.0 - 1e-12, "{ux}");
        let json = serde_json::to_string(&s).unwrap();
        assert_eq!(serde_json::from_str::<TippingSummary>(&json).unwrap(), s);
    }

    #[test]
    fn summary_lengths_scale_with_the_unit_and_tan_alpha_does_not() {
        // The same block in mm (0.001 m per unit) and m: lengths scale, tan α does not.
        let (a, b, c) = (300.0, 500.0, 1200.0);
        let polars = tipping_polars(&block(a, b, c), &Point3::new(20.0, -10.0, 0.0), &-Vec3::z(), &[0.0, 2.0]).unwrap();
        assert_eq!(polars.len(), 2);
        let mm = polars[0].summary(0.0, 1e-3);
        let unit = polars[0].summary(0.0, 1.0);
        assert!((mm.height_m - 1.2).abs() < 1e-12 && (unit.height_m - c).abs() < 1e-9);
        for (p, q) in mm.support_polygon_m.iter().zip(&unit.support_polygon_m) {
            assert!((p[0] - q[0] * 1e-3).abs() < 1e-12 && (p[1] - q[1] * 1e-3).abs() < 1e-12);
        }
        assert_eq!(
            (mm.minimum_g, mm.minimum_azimuth_deg, &mm.curve),
            (unit.minimum_g, unit.minimum_azimuth_deg, &unit.curve)
        );
        // G moved 20 towards +x: the nearest side is now +x, at (a − 20)/c.
        assert!((mm.minimum_g - (a - 20.0) / c).abs() < 1e-12, "{}", mm.minimum_g);
        assert!((0.0..360.0).contains(&mm.minimum_azimuth_deg));
    }

    #[test]
    fn azimuths_are_reported_in_0_to_360_degrees() {
        assert_eq!(degrees_0_360(0.0), 0.0);
        assert_eq!(degrees_0_360(-0.0), 0.0);
        assert_eq!(degrees_0_360(-1e-17), 0.0);
        assert!((degrees_0_360(-std::f64::consts::FRAC_PI_2) - 270.0).abs() < 1e-12);
        assert!((degrees_0_360(std::f64::consts::PI) - 180.0).abs() < 1e-12);
    }

    #[test]
    fn tilted_blocks_on_their_face_touch_at_all_four_base_corners_at_zero_tolerance() {
        // Rotated about oblique axes, the base corners' depths along the rotated down direction
        // differ by rounding only: all four touch at τ = 0 and the block stands.
        let (a, b, c) = (0.3, 0.5, 1.2);
        for k in 0..40 {
            let axis = nalgebra::Unit::new_normalize(Vec3::new(0.3 + 0.1 * k as f64, -0.7, 0.5 - 0.05 * k as f64));
            let r = nalgebra::Rotation3::from_axis_angle(&axis, 0.1 + 0.15 * k as f64);
            let corners: Vec<Point3> = block(a, b, c).iter().map(|p| r * p).collect();
            let t = TippingPolar::new(&corners, &Point3::origin(), &(r * -Vec3::z()), 0.0).unwrap();
            assert_eq!(t.polygon.len(), 4, "rotation {k}");
            assert!(t.stands() && (t.minimum().0 - a / c).abs() < 1e-12, "rotation {k}: {:?}", t.minimum());
        }
    }

    #[test]
    fn bad_input_is_refused_with_its_name() {
        let e = TippingPolar::new(&block(1.0, 1.0, 1.0), &Point3::origin(), &Vec3::zeros(), 0.0).unwrap_err();
        assert!(e.to_string().contains("down"), "{e}");
        let e = TippingPolar::new(&block(1.0, 1.0, 1.0), &Point3::origin(), &-Vec3::z(), -1.0).unwrap_err();
        assert!(e.to_string().contains("tolerance"), "{e}");
    }
}
