//! The hidden base: how a field rock's underside meets the ground, which no scan shows, drawn
//! anew by every member of an ensemble.
//!
//! # What is not known
//!
//! A rock standing on a pedestal or a table touches it at a few points of its underside: a
//! rigid body on a rigid plane is carried by three, and G must lie over the triangle they span,
//! or the rock would not stand. Which three is set by the microtopography of both surfaces. A
//! field scan does not see the underside at all (it is open there: [`crate::mesh::OpenScan`]); a
//! lab scan sees it to a few millimetres, as does the ground under it — and a rock set down again
//! after each test comes to rest on other corners. Moving the support triangle by millimetres
//! moves the rocking edges, and with them the static tipping threshold tan α = (distance from G's
//! foot to the nearest edge) / (height of G), several-fold both ways: smaller and larger supports,
//! offset from where the scan suggests.
//!
//! # What a member draws ([`HiddenBase::member`])
//!
//! The scan is read as an open scan whose rim is the lowest edge of what is trusted: a field
//! scan's own rim, or — for a closed scan — the section `band_m` above its lowest point (the
//! scan's last millimetres are as uncertain as the ground's). Below the rim the member draws:
//!
//! 1. **The region that carries the weight**: a disc of radius λ·min(ρ, q h) around a centre c,
//!    where ρ = √(A/π) is the footprint's radius (A the area the rim encloses), h G's height
//!    above the support, λ uniform in `region`, q = `reach`, and c uniform in the disc of that
//!    radius around G's foot (so G's foot lies in the region). The bound q h keeps the answer
//!    from depending on where a scan happens to stop: a scan cut higher has a wider rim, the
//!    rock under it is no wider.
//! 2. **The support triangle**: three points of the base grid ([`crate::mesh::BaseClosing`])
//!    inside the footprint and that disc, uniform among the triples whose triangle holds G's
//!    foot (rejection sampling; its tries are bounded) — or, when the rocking points were
//!    measured in the field (`rocking_points_m`), the grid points nearest them in every member.
//! 3. **The depth** d of the support below the rim's lowest point: uniform in `depth_m` when
//!    the user knows it, else in [0, D] with D = max(`walls` × E, `floor` × ρ), at most ρ, and
//!    for a closed scan (whose lowest point is seen) at most [`CLOSED_DEPTH`] bands. E is the depth at which the scan's walls,
//!    continued down at the rate they close just above the rim, would meet
//!    ([`HiddenBase::wall_depth`]): a scan whose section widens fast above its rim (a flat
//!    underside, seen nearly to the ground) hides a shallow base, one with steep walls a deep
//!    one.
//! 4. **The slope** κ, uniform in `slope`, at which the underside rises away from the support.
//!
//! The base closes the rim with a height field over the rim's plane. On the triangle it lies on
//! the horizontal support plane; at horizontal distance s from the triangle and r from the rim
//! it rises by max(κ s, w), where w = min(max(H − r E/ρ, 0), H s/(s + r)), H the
//! rim's height over the support there: the scan's walls continued down at the slope E/ρ they
//! have at the rim until they reach the support plane (never steeper than the straight way from
//! the triangle up to the rim), and beyond them the underside rises from the triangle at κ.
//! Tilted about a rocking edge by κ, the rock lands on the base beyond it. A closed scan is
//! treated exactly as a field scan cut at its band (its depth at most [`CLOSED_DEPTH`] bands):
//! in the calibration this scored better on the shake-table rock than keeping the band's
//! scanned shape with the support at the band's depth.
//!
//! Each member is its own closed solid — its own mass, G, inertia, hull, equilibria and flocks
//! (read at the scan's ν) — and must stand as scanned: the quasi-static descent from straight
//! down must reach the support (G's foot inside the triangle once the base's own mass is
//! counted), and put down with the runs' contact it must stay there; a member that would not is
//! drawn again (its tries are bounded and counted). A
//! member draws from its own stream (seed, member) after the other inputs' six uniforms, so it
//! is the same possible rock for every record and scale factor, thread count and ensemble size.
//!
//! The defaults ([`BaseUncertainty::calibrated`]) are calibrated on one real rock's shake-table
//! tests (`results/shake_table_sp1/`): in-sample, not a validation.

use super::triangle::{distance_to_triangle, strictly_inside};
use crate::analysis::{Analysis, Options};
use crate::dynamics::resting::RestingParams;
use crate::dynamics::shaking::rock::{place, Pose};
use crate::dynamics::stone::Stone;
use crate::mesh::{BaseClosing, BasePoint, ClosedScan, OpenScan, RimChoice, Scan, TriMesh};
use crate::rng::item_rng;
use crate::tipping::TippingPolar;
use crate::{Error, Point3, Result, Vec3};
use rand::RngExt;
use serde::{Deserialize, Serialize};

/// What is not known of the hidden base, as ranges every member draws from (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BaseUncertainty {
    /// The rocking points measured in the field: the three points (x, y in metres, the scan's
    /// frame as scanned) the rock stands on. Given, every member stands on them (their nearest
    /// base grid points) and draws only the depth and the slope; None: drawn.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rocking_points_m: Option<[[f64; 2]; 3]>,
    /// Open scans: depth (m) of the support below the rim's lowest point, [low, high], low ≥ 0,
    /// as the user knows it. None: from 0 to `walls` × the depth at which the scan's walls,
    /// continued down, close ([`HiddenBase::wall_depth`]).
    pub depth_m: Option<[f64; 2]>,
    /// Open scans without a known depth: the deepest support as a multiple of the walls' depth
    /// ([`HiddenBase::wall_depth`])…
    #[serde(default = "default_walls")]
    pub walls: f64,
    /// … and at least this multiple of the footprint's radius ρ (a scan does not see the last
    /// millimetres under a wide base either).
    #[serde(default = "default_floor")]
    pub floor: f64,
    /// Closed scans: height (m) above the scan's lowest point up to which the scan is read as
    /// hidden (its base then drawn like an open scan's, at the depth of its scanned base); at
    /// most 1 % of R_max ([`BaseUncertainty::band_for`]).
    pub band_m: f64,
    /// Radius of the region that carries the weight, as a multiple λ of the footprint's radius
    /// √(A/π), [low, high].
    pub region: [f64; 2],
    /// Slope κ at which the underside rises away from its support triangle (height over
    /// horizontal distance), [low, high]: the tilt about a rocking edge at which the base beyond
    /// it next touches the ground.
    pub slope: [f64; 2],
    /// The region's radius is at most this multiple of G's height above the support: the
    /// weight is carried within the rock's proportions, not wherever the scan happens to stop
    /// (a scan cut higher has a wider rim; the rock under it is no wider).
    #[serde(default = "default_reach")]
    pub reach: f64,
}

fn default_reach() -> f64 {
    BaseUncertainty::calibrated().reach
}

fn default_walls() -> f64 {
    BaseUncertainty::calibrated().walls
}

fn default_floor() -> f64 {
    BaseUncertainty::calibrated().floor
}

impl BaseUncertainty {
    /// The defaults, calibrated on one real rock's shake-table tests (module docs): an open
    /// scan's depth from 0 to 0.6 × its walls' closing depth (at least 0.1 ρ), a 2 mm band for
    /// closed scans, λ from 0.1 to 1, κ from 0.005 to 0.03.
    pub fn calibrated() -> BaseUncertainty {
        BaseUncertainty {
            rocking_points_m: None,
            depth_m: None,
            walls: 0.6,
            floor: 0.1,
            band_m: 0.002,
            region: [0.1, 1.0],
            slope: [0.005, 0.03],
            reach: 0.25,
        }
    }

    /// The band (m) a closed scan of a rock of R_max `r_max_m` (m) is read as hidden up to:
    /// `band_m`, at most 1 % of R_max (a pebble's scan is not millimetres blind).
    pub fn band_for(&self, r_max_m: f64) -> f64 {
        self.band_m.min(0.01 * r_max_m)
    }

    /// Every range ordered, finite and physical; else a parameter error naming it.
    pub fn check(&self) -> Result<()> {
        if let Some(p) = self.rocking_points_m {
            if !p.iter().flatten().all(|x| x.is_finite()) {
                return Err(Error::parameter("rocking_points", format!("{p:?}"), "three finite points x, y"));
            }
        }
        if let Some([d0, d1]) = self.depth_m {
            if !(d0.is_finite() && d1.is_finite() && 0.0 <= d0 && d0 <= d1) {
                return Err(Error::parameter(
                    "base_depth",
                    format!("{d0},{d1}"),
                    "a range LOW,HIGH with 0 ≤ LOW ≤ HIGH",
                ));
            }
        }
        if !(self.walls > 0.0 && self.walls.is_finite()) {
            return Err(Error::parameter("base_walls", self.walls, "a positive multiple of the walls' depth"));
        }
        if !(0.0..=1.0).contains(&self.floor) {
            return Err(Error::parameter("base_floor", self.floor, "a multiple of the footprint's radius in [0, 1]"));
        }
        if !(self.band_m > 0.0 && self.band_m.is_finite()) {
            return Err(Error::parameter("base_band", self.band_m, "a positive length"));
        }
        let [l0, l1] = self.region;
        if !(l0.is_finite() && l1.is_finite() && 0.0 < l0 && l0 <= l1) {
            return Err(Error::parameter("base_region", format!("{l0},{l1}"), "a range LOW,HIGH with 0 < LOW ≤ HIGH"));
        }
        let [k0, k1] = self.slope;
        if !(k0.is_finite() && k1.is_finite() && 0.0 <= k0 && k0 <= k1) {
            return Err(Error::parameter("base_slope", format!("{k0},{k1}"), "a range LOW,HIGH with 0 ≤ LOW ≤ HIGH"));
        }
        if !(self.reach > 0.0) {
            return Err(Error::parameter("base_reach", self.reach, "a positive multiple of G's height"));
        }
        Ok(())
    }
}

/// One member's base (real units, mesh frame).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BaseDraw {
    /// Depth (m) of the support below the rim's lowest point.
    pub depth_m: f64,
    /// λ: the region's radius over the footprint's.
    pub region: f64,
    /// κ: the slope at which the underside rises away from the support.
    pub slope: f64,
    /// The support triangle's corners (x, y in metres, mesh frame).
    pub support_m: [[f64; 2]; 3],
    /// The member's quasi-static tipping threshold: the smallest horizontal ground acceleration
    /// (g) that lifts it off its support, over all azimuths ([`TippingPolar::minimum`]).
    pub tan_alpha: f64,
    /// Draws it took to find a base the rock stands on as scanned (1: the first).
    pub tries: u32,
}

/// A closed scan's hidden base lies at most this many bands below the band's rim: its lowest
/// point is seen, to within the scan's last millimetres and the ground's unevenness.
pub const CLOSED_DEPTH: f64 = 3.0;

/// Tries of the support triangle per drawn region before a new region is drawn.
const TRIANGLE_TRIES: usize = 20_000;

/// Draws of a whole base (region, triangle, depth) before a member is given up.
const BASE_TRIES: u32 = 50;

/// Where the hidden base's rim comes from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BaseSource {
    /// A field scan's own rim.
    OpenScan,
    /// A closed scan cut open this high (m) above its lowest point.
    ClosedScan {
        /// The band's height (m).
        band_m: f64,
    },
}

/// A scan ready to be closed by drawn bases (module docs), standing as it stands: +z up.
#[derive(Clone, Debug)]
pub struct HiddenBase {
    closing: BaseClosing,
    source: BaseSource,
    /// Metres per mesh unit.
    unit: f64,
    /// G of the scan closed flat (mesh units), the foot the support must hold.
    g: Point3,
    /// The rim's lowest height (mesh units).
    z_low: f64,
    /// √(A/π) of the footprint (mesh units).
    radius: f64,
    /// The largest distance from G's foot to a base grid point (mesh units).
    extent: f64,
    /// The depth (mesh units) below the rim at which the scan's walls, continued down, close
    /// (open scans; [`HiddenBase::wall_depth`]).
    walls: Option<f64>,
    /// Every base grid point's (x, y).
    grid: Vec<[f64; 2]>,
    /// How the scan was turned and shifted to stand (scan frame → this frame).
    frame: (nalgebra::Rotation3<f64>, Vec3),
}

/// `mesh` turned to stand as `pose` stands (+z up, the facet of an equilibrium down), and the
/// rotation and shift that did it.
fn standing(mesh: &TriMesh, pose: &Pose, stone: &Stone) -> Result<(TriMesh, (nalgebra::Rotation3<f64>, Vec3))> {
    let rotation = match pose.resolved(stone)? {
        Pose::Equilibrium { id } => {
            let facet = stone.stable()[stone.position(id).ok_or_else(|| Error::check("a resolved pose"))?].facet;
            let down = stone.body.facet_normals[facet as usize];
            nalgebra::Rotation3::rotation_between(&down, &-Vec3::z())
                .unwrap_or_else(|| nalgebra::Rotation3::from_axis_angle(&Vec3::x_axis(), std::f64::consts::PI))
        }
        p => p.orientation().ok_or_else(|| Error::check("a resolved pose"))?.to_rotation_matrix(),
    };
    let turned = mesh.transformed(&rotation, 1.0, &Vec3::zeros());
    Ok((turned, (rotation, Vec3::zeros())))
}

impl HiddenBase {
    /// The hidden base of a field scan standing as scanned (+z up), `unit` metres per mesh unit.
    pub fn of_open_scan(scan: OpenScan, unit: f64) -> Result<HiddenBase> {
        HiddenBase::new(BaseClosing::new(scan)?, BaseSource::OpenScan, unit)
    }

    /// The hidden base of a closed scan standing as scanned (+z up): cut open `band_m` above its
    /// lowest point ([`crate::mesh::cut_base`]).
    pub fn of_closed_scan(mesh: &TriMesh, band_m: f64, unit: f64) -> Result<HiddenBase> {
        let open = crate::mesh::cut_base(mesh, band_m / unit)?;
        let scan = OpenScan::new(open, &RimChoice::Lowest)?;
        HiddenBase::new(BaseClosing::new(scan)?, BaseSource::ClosedScan { band_m }, unit)
    }

    /// The hidden base of the scan `mesh` (as read, open or closed) of the rock `stone` standing
    /// in `pose`: the scan turned to stand as the pose stands (as scanned; the quaternion; the
    /// equilibrium's facet down), then read as a field scan (its rim chosen by `rim`) or cut open
    /// `band_m` above its lowest point. A field scan must stand as scanned. A known centre of
    /// mass in `opts` is carried into that frame ([`HiddenBase::options`]).
    pub fn of_scan(
        mesh: TriMesh,
        pose: &Pose,
        stone: &Stone,
        band_m: f64,
        unit: f64,
        rim: &RimChoice,
    ) -> Result<HiddenBase> {
        match mesh.into_scan(rim)? {
            Scan::Open(scan) => match pose.resolved(stone)? {
                Pose::AsScanned => HiddenBase::of_open_scan(*scan, unit),
                p => Err(Error::Pose {
                    pose: p.to_string(),
                    what:
                        "a field scan's hidden base is drawn under the rock as scanned: give the pose as-scanned, or \
                           no base uncertainty"
                            .into(),
                }),
            },
            Scan::Closed(mesh, _) => {
                let (turned, frame) = standing(&mesh, pose, stone)?;
                let mut hidden = HiddenBase::of_closed_scan(&turned, band_m, unit)?;
                hidden.frame = frame;
                Ok(hidden)
            }
        }
    }

    /// `opts` for the members' solids: a known centre of mass turned into the frame the base
    /// stands in.
    pub fn options(&self, opts: &Options) -> Options {
        let (rotation, shift) = self.frame;
        Options { center_of_mass: opts.center_of_mass.map(|c| rotation * c + shift), ..opts.clone() }
    }

    fn new(closing: BaseClosing, source: BaseSource, unit: f64) -> Result<HiddenBase> {
        let flat = closing.flat()?;
        let g = crate::solid::MassProperties::of(&flat.mesh)?.center_of_mass;
        let rim: Vec<Point3> = closing.scan().rim().iter().flat_map(|l| l.points(closing.scan().mesh())).collect();
        let z_low = rim.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
        let n = closing.plane().normal;
        if n.z > -1e-6 {
            return Err(Error::check("the rim of the hidden base does not face down"));
        }
        let grid: Vec<[f64; 2]> = closing.points().iter().map(|p| [p.point.x, p.point.y]).collect();
        let extent = grid.iter().map(|[x, y]| (x - g.x).hypot(y - g.y)).fold(0.0, f64::max);
        let radius = (closing.scan().summary().rim.area / std::f64::consts::PI).sqrt();
        let frame = (nalgebra::Rotation3::identity(), Vec3::zeros());
        let walls = closing_depth(closing.scan(), radius);
        Ok(HiddenBase { closing, source, unit, g, z_low, radius, extent, walls, grid, frame })
    }

    /// The depth (m) below the rim's lowest point at which the scan's walls, continued down at
    /// the rate they close just above the rim, would meet: E = ρ δ / (ρ(δ) − ρ), with ρ(δ) the
    /// footprint radius of the section δ = ρ/20 above the rim's plane. A scan whose section
    /// widens slowly above its rim (steep walls) hides a deep base; one that widens fast (a flat
    /// underside) a shallow one. None for a closed scan, or where the section cannot be read or
    /// does not widen (then the range is 0 to the footprint's radius).
    pub fn wall_depth(&self) -> Option<f64> {
        self.walls.map(|e| e * self.unit)
    }

    /// Where the rim came from.
    pub fn source(&self) -> BaseSource {
        self.source
    }

    /// Member `member` of seed `seed` under `u`: its closed solid analysed with `opts`, its stone
    /// with flocks at `nu`, and what it drew (module docs). Refused when no drawn base lets the
    /// rock stand as scanned.
    pub fn member(
        &self,
        u: &BaseUncertainty,
        seed: u64,
        member: u64,
        opts: &Options,
        nu: f64,
        params: &RestingParams,
    ) -> Result<(Stone, BaseDraw)> {
        u.check()?;
        let given = u.rocking_points_m.map(|p| self.rocking_points(p)).transpose()?;
        let mut rng = item_rng(seed, member);
        // The six uniforms of the other inputs come first (`super::uncertainty::draw`).
        for _ in 0..6 {
            let _: f64 = rng.random_range(0.0..1.0);
        }
        // Why the last draws failed, for the refusal.
        let (mut no_triangle, mut unreadable, mut elsewhere, mut unsteady) = (0, 0, 0, 0);
        let ([d0, d1], summary) = (self.depth_range(u), self.closing.scan().summary());
        for tries in 1..=BASE_TRIES {
            let region = u.region[0] + (u.region[1] - u.region[0]) * rng.random_range(0.0..1.0);
            let depth = d0 + (d1 - d0) * rng.random_range(0.0..1.0);
            let slope = u.slope[0] + (u.slope[1] - u.slope[0]) * rng.random_range(0.0..1.0);
            let height = self.g.z - (self.z_low - depth / self.unit);
            // The drawn region, widened (×1.5 at a time, up to the whole footprint) while no
            // triangle of grid points in it holds G's foot: a rim of separate islands (a rock
            // resting on a few bumps) has its weight carried across them.
            let mut r = region * self.radius.min(u.reach * height);
            let triangle = match given {
                Some(t) => Some(t),
                None => loop {
                    match self.support(r, &mut rng) {
                        Some(t) => break Some(t),
                        None if r < self.extent => r = (1.5 * r).min(self.extent),
                        None => break None,
                    }
                },
            };
            let Some(triangle) = triangle else {
                no_triangle += 1;
                continue;
            };
            // A drawn base whose solid cannot be analysed (a hull too degenerate to read) is
            // drawn again, like one the rock does not stand on.
            let analysed = self
                .closed(&triangle, depth / self.unit, slope)
                .and_then(|closed| Analysis::of_closed_scan(closed, summary.clone(), "drawn base", opts))
                .and_then(|a| Stone::new(&a, nu).map(|s| (a, s)));
            let Ok((a, stone)) = analysed else {
                unreadable += 1;
                continue;
            };
            let down = -Vec3::z();
            let rest = stone.rest(&down);
            if stone.body.facet_normals[rest.facet as usize].dot(&down) < 1.0 - 1e-9 {
                elsewhere += 1;
                continue;
            }
            // Put down with the runs' contact, it must stay (a support whose edge passes within
            // the soft contact's give of G's foot does not).
            if place(&stone, &Pose::AsScanned, params).is_err() {
                unsteady += 1;
                continue;
            }
            let corners: Vec<Point3> = a.hull.vertices.clone();
            let polar = TippingPolar::new(&corners, &a.mass.center_of_mass, &down, 0.0)?;
            let support_m = triangle.map(|k| self.grid[k].map(|x| x * self.unit));
            let draw = BaseDraw { depth_m: depth, region, slope, support_m, tan_alpha: polar.minimum().0, tries };
            return Ok((stone, draw));
        }
        Err(Error::Pose {
            pose: "as-scanned".into(),
            what: format!(
                "ensemble member {member}: none of {BASE_TRIES} drawn bases lets the rock stand as scanned (G's foot \
                 must lie over the support: {no_triangle} found no support triangle around it, {elsewhere} rested \
                 elsewhere, {unsteady} did not stay put, {unreadable} gave no readable solid); check that the scan \
                 stands as it was scanned (+z up, the open rim at the bottom), give the hidden base's depth as \
                 measured, or run without base uncertainty (the scan's own base)"
            ),
        })
    }

    /// The range (m) the support's depth below the rim is drawn from (module docs): the depth
    /// given, else 0 to D = max(`walls` × [`HiddenBase::wall_depth`], `floor` × ρ), at most ρ —
    /// and for a closed scan, whose lowest point is seen, at most [`CLOSED_DEPTH`] bands.
    pub fn depth_range(&self, u: &BaseUncertainty) -> [f64; 2] {
        if let Some(d) = u.depth_m {
            return d;
        }
        let d =
            self.walls.map_or(self.radius, |e| (u.walls * e).max(u.floor * self.radius).min(self.radius)) * self.unit;
        match self.source {
            BaseSource::OpenScan => [0.0, d],
            BaseSource::ClosedScan { band_m } => [0.0, d.min(CLOSED_DEPTH * band_m)],
        }
    }

    /// The base grid points nearest the rocking points `p` (metres, mesh frame); refused when two
    /// are the same point or their triangle does not hold G's foot (the rock could not stand
    /// on them).
    fn rocking_points(&self, p: [[f64; 2]; 3]) -> Result<[usize; 3]> {
        if self.frame.0 != nalgebra::Rotation3::identity() {
            return Err(Error::parameter(
                "rocking_points",
                format!("{p:?}"),
                "points in the scan's frame as scanned: the rock standing as scanned",
            ));
        }
        let nearest = |q: [f64; 2]| {
            let (x, y) = (q[0] / self.unit, q[1] / self.unit);
            let d = |k: usize| (self.grid[k][0] - x).hypot(self.grid[k][1] - y);
            (0..self.grid.len()).min_by(|&a, &b| d(a).total_cmp(&d(b))).unwrap_or(0)
        };
        let t = p.map(nearest);
        let (gx, gy) = (self.g.x, self.g.y);
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || !strictly_inside(&t.map(|k| self.grid[k]), [gx, gy]) {
            return Err(Error::parameter(
                "rocking_points",
                format!("{p:?}"),
                format!(
                    "three distinct points inside the rim around G's foot at ({:.4}, {:.4}) m, or the rock could not \
                     stand on them",
                    gx * self.unit,
                    gy * self.unit
                ),
            ));
        }
        Ok(t)
    }

    /// Three grid points inside a region of radius `r` (mesh units) around a centre drawn within
    /// that distance of G's foot, whose triangle holds the foot; None if none was found.
    fn support(&self, r: f64, rng: &mut impl rand::Rng) -> Option<[usize; 3]> {
        let (gx, gy) = (self.g.x, self.g.y);
        let (a, t) = (rng.random_range(0.0..std::f64::consts::TAU), rng.random_range(0.0f64..1.0).sqrt() * r);
        let (cx, cy) = (gx + t * a.cos(), gy + t * a.sin());
        let inside: Vec<usize> = (0..self.grid.len())
            .filter(|&k| {
                let [x, y] = self.grid[k];
                (x - cx).powi(2) + (y - cy).powi(2) <= r * r
            })
            .collect();
        if inside.len() < 3 {
            return None;
        }
        let holds = |k: [usize; 3]| strictly_inside(&k.map(|i| self.grid[inside[i]]), [gx, gy]);
        for _ in 0..TRIANGLE_TRIES {
            let k = [0, 1, 2].map(|_| rng.random_range(0..inside.len()));
            if k[0] != k[1] && k[1] != k[2] && k[0] != k[2] && holds(k) {
                return Some(k.map(|i| inside[i]));
            }
        }
        None
    }

    /// The scan closed by a base whose support is `triangle` (grid indices) at `depth` (mesh
    /// units) below the rim's lowest point (module docs).
    fn closed(&self, triangle: &[usize; 3], depth: f64, slope: f64) -> Result<ClosedScan> {
        let corners = triangle.map(|k| self.grid[k]);
        let (n_z, support) = (-self.closing.plane().normal.z, self.z_low - depth);
        // The walls' slope at the rim (height per horizontal distance): vertical when they do
        // not close.
        let wall = self.walls.map_or(f64::INFINITY, |e| e / self.radius);
        self.closing.close(|p: &BasePoint| {
            // Down to the support plane on the triangle; away from it the underside rises at the
            // slope κ at least, and reaches the rim the way the walls come down to it: the rim's
            // height over the support H, less the walls' slope times the distance r from the
            // rim, but never steeper than H s/(s + r) (s the distance from the triangle).
            let full = p.point.z - support;
            let s = distance_to_triangle([p.point.x, p.point.y], &corners);
            let r = p.rim_distance;
            let walls = if s > 0.0 { (full - wall * r).max(0.0).min(full * s / (s + r)) } else { 0.0 };
            let rise = (slope * s).max(walls);
            ((full - rise) / n_z).max(0.0)
        })
    }

    /// The lowest height of the rim (mesh units).
    pub fn rim_height(&self) -> f64 {
        self.z_low
    }
}

/// The walls' closing depth of `scan` (mesh units, [`HiddenBase::wall_depth`]): the area its
/// section δ = ρ/20 above the rim's plane encloses (the boundary loops lying in that plane, each
/// counted with its orientation, so pockets subtract); None if it does not widen.
fn closing_depth(scan: &OpenScan, radius: f64) -> Option<f64> {
    let rim = scan.rim_plane();
    let delta = radius / 20.0;
    let up = -rim.normal;
    let plane = crate::mesh::Plane::new(rim.point + up * delta, up)?;
    let above = crate::mesh::cut_open(scan.mesh(), &plane).ok()?;
    let loops = crate::mesh::boundary_loops(&above).ok()?;
    let area: f64 = loops
        .iter()
        .map(|l| l.points(&above))
        .filter(|p| p.iter().all(|x| plane.distance(x).abs() <= 1e-9 * radius))
        .map(|p| crate::mesh::plane::vector_area(&p).dot(&up))
        .sum();
    let wider = (area.max(0.0) / std::f64::consts::PI).sqrt();
    (wider > radius * (1.0 + 1e-6)).then(|| radius * delta / (wider - radius))
}
