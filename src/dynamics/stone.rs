//! The one prepared stone of every dynamic run (drops, pushes, shaking, the simulated hand
//! experimenter), and the one rule that says where a stone came to rest.
//!
//! [`Stone::new`] turns an [`Analysis`] into everything the dynamics needs, once:
//!
//! * the rigid [`Body`] in the scaled frame ([`crate::dynamics::engine::body`]) (lengths / R_max, mass 1, g = 9.81 m/s²), with the
//!   hull as its collider and the solid's G and inertia;
//! * the merge tree of the support function h ([`MergeTree`]), which carries the
//!   quasi-static descent and the energy certificate;
//! * the maps facet → stable micro-equilibrium → flock at the chosen ν, and each flock's type;
//! * on demand, the quasi-static basin probabilities and every stable micro-equilibrium with its
//!   static barriers ([`Stone::stable`]).
//!
//! # Where did it come to rest ([`Stone::rest`])
//!
//! A body at rest with body-frame down direction d stands on the stable micro-equilibrium that
//! the quasi-static descent of h from d reaches (the gradient flow of the support function,
//! [`crate::basins::SupportFlow::settle`]) — never on "the facet whose normal is closest to d":
//! on scans, neighbouring facets differ by 10⁻⁴ rad, and the closest normal is then often a
//! non-stable facet next to the stable one. The rest is *on* that equilibrium when the height of
//! G above the ground, h(d), is within [`REST_TOLERANCE`] of R_F (the contact's soft penetration
//! and the tilt of a body resting on a micro-facet); otherwise the [`Rest`] says how far above it
//! the body stopped (a body that stopped on a slope by friction or rolling resistance, or that
//! hit the time cap).

use crate::analysis::Analysis;
use crate::basins::{MergeTree, QuasiStatic};
use crate::dynamics::engine::body::Body;
use crate::equilibria::{Kind, Site};
use crate::hull::Polyhedron;
use crate::rng::Stream;
use crate::{Error, Point3, Result, Vec3};
use nalgebra::UnitQuaternion;
use rand::RngExt;
use serde::{Deserialize, Serialize};
use std::sync::OnceLock;

/// How far above its stable facet's R_F (in R_max) the centre of mass of a resting body may be
/// and still count as resting on it: 10⁻³ R_max, the contact tolerance of the solver
/// ([`crate::dynamics::engine::world::ALLOWED_PENETRATION`]). The largest sink of a resting body measured on the
/// bundled stone is 1.3·10⁻⁴ R_max, and a tilt θ onto a neighbouring micro-facet raises G by
/// about R θ²/2 (10⁻⁹ R_max for the 5·10⁻⁵ rad between the facets of a scan).
pub const REST_TOLERANCE: f64 = 1e-3;

/// Where a stone came to rest, by the static theory ([`Stone::rest`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Rest {
    /// The stable facet the quasi-static descent from the final down direction reaches.
    pub facet: u32,
    /// Its stable micro-equilibrium (index into the analysis' equilibria) and flock.
    pub equilibrium: usize,
    /// Its flock.
    pub flock: usize,
    /// h(final down) − R_F in units of R_max: how far above its rest on the facet G stopped
    /// (≤ [`REST_TOLERANCE`] when the body rests on the equilibrium; the soft contact's sink
    /// makes it slightly negative).
    pub height_above: f64,
}

impl Rest {
    /// The body is on the equilibrium, within the contact tolerance.
    pub fn on_equilibrium(&self) -> bool {
        self.height_above <= REST_TOLERANCE
    }
}

/// Where the stone can leave a stable micro-equilibrium most cheaply, statically.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Exit {
    /// Barrier in units of m g R_max: (merge level − R_F)/R_max (∞, serialised as null, if
    /// there is no way out).
    pub epsilon: f64,
    /// The stable facet reached at that level (the cheapest one; ties: lowest index).
    pub facet: Option<u32>,
    /// Its micro-equilibrium.
    pub equilibrium: Option<usize>,
    /// Its flock.
    pub flock: Option<usize>,
}

/// Static class of a stable micro-equilibrium (paper §1.1, §4.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Class {
    /// In a stable flock.
    Regular,
    /// In an unstable or saddle flock.
    Rocking,
}

impl Class {
    /// The user-facing name.
    pub fn name(self) -> &'static str {
        match self {
            Class::Regular => "regular",
            Class::Rocking => "rocking",
        }
    }
}

/// One stable micro-equilibrium with its static description.
#[derive(Clone, Debug, Serialize)]
pub struct StableEquilibrium {
    /// Index into the analysis' equilibria.
    pub index: usize,
    /// Its facet.
    pub facet: u32,
    /// R_F (input units).
    pub r: f64,
    /// R_F / R_max.
    pub r_normalised: f64,
    /// Its flock and the flock's type.
    pub flock: usize,
    /// Type of its flock.
    pub flock_kind: Kind,
    /// Regular or rocking.
    pub class: Class,
    /// Static barrier out of the micro-equilibrium's basin.
    pub basin_exit: Exit,
    /// Static barrier out of the flock.
    pub flock_exit: Exit,
    /// Quasi-static horizontal ground acceleration (in g) that lifts the stone off its facet in
    /// the most fragile direction: (distance from the stable point to the nearest side of F)
    /// / R_F (Housner's tan α for a block). Taken on the whole facet; the collider keeps at most
    /// four corners of a facet as its support polygon (the quadrilateral with the largest margin,
    /// see [`crate::dynamics::engine::hull_shape`]), so on facets with more corners the simulated stone
    /// can lift off a little earlier in some directions.
    pub uplift_acceleration: f64,
}

/// What the static theory says about each facet, to summarise runs against it (also rebuilt
/// from a checkpoint's stone for `rocking merge`).
#[derive(Clone, Debug)]
pub struct StaticModel {
    /// Outward unit normal of every hull facet (mesh frame).
    pub facet_normals: Vec<Vec3>,
    /// For every facet, its stable micro-equilibrium (None: not a stable facet).
    pub facet_equilibrium: Vec<Option<usize>>,
    /// For every facet, the flock of its stable micro-equilibrium.
    pub facet_flock: Vec<Option<usize>>,
    /// Type of every flock.
    pub flock_kinds: Vec<Kind>,
    /// Quasi-static resting probability of every facet (0 for non-stable ones).
    pub facet_probability: Vec<f64>,
    /// ν at which the flocks were read.
    pub nu: f64,
}

/// A stone prepared for every dynamic run: the body in the scaled frame, the merge tree of its
/// support function, its flocks at `nu`, and (on demand) its basins and stable equilibria.
#[derive(Clone)]
pub struct Stone {
    /// The rigid body.
    pub body: Body,
    /// Merge tree (and quasi-static flow) of the support function.
    pub tree: MergeTree,
    /// ν at which the flocks were read.
    pub nu: f64,
    /// R_F of every facet's stable micro-equilibrium (input units; NaN for non-stable facets).
    facet_r: Vec<f64>,
    /// For every facet: its stable micro-equilibrium.
    pub facet_equilibrium: Vec<Option<usize>>,
    /// For every facet: the flock of its stable micro-equilibrium.
    pub facet_flock: Vec<Option<usize>>,
    /// Flock of every micro-equilibrium.
    pub membership: Vec<usize>,
    /// Type of every flock.
    pub flock_kinds: Vec<Kind>,
    /// Surface triangles in the scaled body frame (relative to G) with their facet, and the
    /// cumulative areas, for sampling push points.
    triangles: Vec<(u32, [Vec3; 3])>,
    cumulative_area: Vec<f64>,
    hull: Polyhedron,
    g: Point3,
    equilibria: crate::equilibria::Equilibria,
    stable: OnceLock<Vec<StableEquilibrium>>,
    quasi_static: OnceLock<QuasiStatic>,
}

impl Stone {
    /// Prepare an analysed stone with flocks read at `nu`.
    pub fn new(a: &Analysis, nu: f64) -> Result<Stone> {
        let g = a.mass.center_of_mass;
        let eq = &a.equilibria;
        let body = Body::new(&a.hull, &g, &a.mass.inertia, a.mass.volume);
        let tree = MergeTree::new(&a.hull, &g, eq);
        let flocks = a.hierarchy.flocks_at(nu);
        let facet_equilibrium: Vec<Option<usize>> = eq.at_facet.iter().map(|s| s.map(|s| s as usize)).collect();
        if facet_equilibrium.iter().all(Option::is_none) {
            return Err(Error::check("the hull has no stable facet"));
        }
        let facet_flock: Vec<Option<usize>> =
            facet_equilibrium.iter().map(|s| s.map(|s| flocks.membership[s])).collect();
        let facet_r = facet_equilibrium.iter().map(|s| s.map_or(f64::NAN, |s| eq.points[s].r)).collect();
        let flock_kinds: Vec<Kind> = flocks.flocks.iter().map(|f| f.kind).collect();
        let mut triangles = Vec::new();
        let mut cumulative_area = Vec::new();
        let mut total = 0.0;
        for (fi, facet) in a.hull.facets.iter().enumerate() {
            for t in &facet.triangles {
                let c = t.map(|v| body.corners[v as usize]);
                total += 0.5 * (c[1] - c[0]).cross(&(c[2] - c[0])).norm();
                triangles.push((fi as u32, c));
                cumulative_area.push(total);
            }
        }
        Ok(Stone {
            body,
            tree,
            nu,
            facet_r,
            facet_equilibrium,
            facet_flock,
            membership: flocks.membership,
            flock_kinds,
            triangles,
            cumulative_area,
            hull: a.hull.clone(),
            g,
            equilibria: eq.clone(),
            stable: OnceLock::new(),
            quasi_static: OnceLock::new(),
        })
    }

    /// Where a body with final body-frame down direction `down` rests (see the module docs).
    pub fn rest(&self, down: &Vec3) -> Rest {
        let f = self.tree.flow().settle(down).unwrap_or_else(|_| self.body.facet_towards(down));
        // `settle` ends on a stable facet by construction; the fallback (a zero or non-finite
        // direction) is the closest normal, mapped to the nearest stable facet by the flow.
        let f = if self.facet_equilibrium[f as usize].is_some() { f } else { self.nearest_stable(f) };
        let equilibrium = self.facet_equilibrium[f as usize].expect("a stable facet");
        let h = self.body.support(&down.normalize());
        Rest {
            facet: f,
            equilibrium,
            flock: self.membership[equilibrium],
            height_above: h - self.facet_r[f as usize] / self.body.r_max,
        }
    }

    fn nearest_stable(&self, f: u32) -> u32 {
        let n = self.body.facet_normals[f as usize];
        self.tree.flow().settle(&n).unwrap_or_else(|_| {
            (0..self.facet_equilibrium.len() as u32)
                .filter(|&s| self.facet_equilibrium[s as usize].is_some())
                .max_by(|&a, &b| {
                    let (na, nb) = (self.body.facet_normals[a as usize], self.body.facet_normals[b as usize]);
                    na.dot(&n).total_cmp(&nb.dot(&n))
                })
                .expect("a stone has a stable facet")
        })
    }

    /// This stone standing on `facet` with the corners within `tolerance` (R_max) of that
    /// facet's plane carrying load ([`Body::flattened`]); the static analysis is the scanned
    /// hull's. Tolerance 0: the stone itself.
    pub fn with_base_contact(&self, facet: u32, tolerance: f64) -> Result<Stone> {
        let n =
            *self.body.facet_normals.get(facet as usize).ok_or_else(|| Error::check(format!("no facet {facet}")))?;
        if !(tolerance >= 0.0 && tolerance.is_finite()) {
            return Err(Error::parameter("contact_tolerance", tolerance, "a finite length ≥ 0"));
        }
        let mut stone = self.clone();
        if tolerance > 0.0 {
            stone.body = self.body.flattened(&n, tolerance)?;
        }
        Ok(stone)
    }

    /// The flock where a stone at rest on `facet` lies: that of the facet's stable
    /// micro-equilibrium (None for a facet that is not stable, or not a facet of the hull).
    pub fn flock_of(&self, facet: u32) -> Option<usize> {
        self.facet_flock.get(facet as usize).copied().flatten()
    }

    /// R_F / R_max of a stable facet (NaN for a non-stable one).
    pub fn facet_height(&self, facet: u32) -> f64 {
        self.facet_r[facet as usize] / self.body.r_max
    }

    /// The quasi-static basin probabilities of the stable facets (computed once, on first use).
    pub fn quasi_static(&self) -> &QuasiStatic {
        self.quasi_static.get_or_init(|| crate::basins::basin_probabilities(&self.hull, &self.g, &self.equilibria))
    }

    /// What the static theory says about each facet, for summaries.
    pub fn model(&self) -> StaticModel {
        StaticModel {
            facet_normals: self.body.facet_normals.clone(),
            facet_equilibrium: self.facet_equilibrium.clone(),
            facet_flock: self.facet_flock.clone(),
            flock_kinds: self.flock_kinds.clone(),
            facet_probability: self.quasi_static().facet_probability.clone(),
            nu: self.nu,
        }
    }

    /// The stable micro-equilibria (in the analysis' order) with their static barriers
    /// (computed once, on first use).
    pub fn stable(&self) -> &[StableEquilibrium] {
        self.stable.get_or_init(|| self.stable_equilibria())
    }

    /// Positions in [`Stone::stable`] of the stable micro-equilibria asked for: those of flock
    /// `flock`, else the analysis indices `equilibria`, else all. A flock that does not exist or
    /// holds no stable micro-equilibrium, or an index that is not a stable micro-equilibrium, is
    /// refused with the list of the stable ones.
    pub fn select(&self, equilibria: &[usize], flock: Option<usize>) -> crate::Result<Vec<usize>> {
        let list =
            || self.stable().iter().map(|s| format!("{} (flock {})", s.index, s.flock)).collect::<Vec<_>>().join(", ");
        if let Some(k) = flock {
            if k >= self.flock_kinds.len() {
                return Err(crate::Error::parameter(
                    "flock",
                    k,
                    format!("a flock of the stone: it has {} flocks at ν = {:.3e}", self.flock_kinds.len(), self.nu),
                ));
            }
            let v: Vec<usize> = (0..self.stable().len()).filter(|&i| self.stable()[i].flock == k).collect();
            if v.is_empty() {
                return Err(crate::Error::parameter(
                    "flock",
                    k,
                    format!("a flock with a stable micro-equilibrium; stable ones: {}", list()),
                ));
            }
            return Ok(v);
        }
        if equilibria.is_empty() {
            return Ok((0..self.stable().len()).collect());
        }
        equilibria
            .iter()
            .map(|&id| {
                self.position(id).ok_or_else(|| {
                    crate::Error::parameter(
                        "equilibrium",
                        id,
                        format!(
                            "the index of a stable micro-equilibrium{}; stable ones: {}",
                            self.facet_hint(id),
                            list()
                        ),
                    )
                })
            })
            .collect()
    }

    /// What to say of an id that is not a stable micro-equilibrium's index when it is the number
    /// of a hull facet a stable micro-equilibrium rests on (the analysis summary prints both):
    /// "; hull facet 174 holds stable micro-equilibrium 3", else "".
    pub fn facet_hint(&self, id: usize) -> String {
        let on: Vec<String> =
            self.stable().iter().filter(|s| s.facet as usize == id).map(|s| s.index.to_string()).collect();
        match on.len() {
            0 => String::new(),
            1 => format!("; hull facet {id} holds stable micro-equilibrium {}", on[0]),
            _ => format!("; hull facet {id} holds stable micro-equilibria {}", on.join(", ")),
        }
    }

    /// The position in [`Stone::stable`] of micro-equilibrium `index` (an index into the
    /// analysis' equilibria), if it is a stable one.
    pub fn position(&self, index: usize) -> Option<usize> {
        self.stable().iter().position(|s| s.index == index)
    }

    /// The first stable micro-equilibrium whose resting facet faces `normal` (a unit vector in
    /// the body frame): its outward facet normal n has n · `normal` > 0.999 (within 2.6°). With
    /// `normal` = −z, the rest of a block generated standing on its bottom face.
    pub fn stable_facing(&self, normal: &Vec3) -> Option<&StableEquilibrium> {
        self.stable().iter().find(|e| self.body.facet_normals[e.facet as usize].dot(normal) > 0.999)
    }

    fn stable_equilibria(&self) -> Vec<StableEquilibrium> {
        let eq = &self.equilibria;
        let r_max = eq.r_max;
        let stable_facets: Vec<u32> =
            (0..self.hull.facets.len() as u32).filter(|&f| self.facet_equilibrium[f as usize].is_some()).collect();
        let mut stable = Vec::new();
        for (i, p) in eq.points.iter().enumerate() {
            let (Kind::Stable, Site::Facet(f)) = (p.kind, p.site) else { continue };
            let flock = self.membership[i];
            let flock_kind = self.flock_kinds[flock];
            let exit = |pred: &dyn Fn(u32) -> bool| {
                let mut best: (f64, Option<u32>) = (f64::INFINITY, None);
                for &s in stable_facets.iter().filter(|&&s| s != f && pred(s)) {
                    let level = self.tree.entry_barrier(f, s);
                    if level < best.0 {
                        best = (level, Some(s));
                    }
                }
                let equilibrium = best.1.and_then(|s| self.facet_equilibrium[s as usize]);
                Exit {
                    epsilon: (best.0 - p.r) / r_max,
                    facet: best.1,
                    equilibrium,
                    flock: equilibrium.map(|e| self.membership[e]),
                }
            };
            let basin_exit = exit(&|_| true);
            let flock_exit = exit(&|s| self.facet_flock[s as usize] != Some(flock));
            let facet = &self.hull.facets[f as usize];
            let n = facet.vertices.len();
            let margin = (0..n)
                .map(|k| {
                    let (u, v) = (
                        self.hull.vertices[facet.vertices[k] as usize],
                        self.hull.vertices[facet.vertices[(k + 1) % n] as usize],
                    );
                    let e = v - u;
                    e.cross(&(p.point - u)).norm() / e.norm()
                })
                .fold(f64::INFINITY, f64::min);
            stable.push(StableEquilibrium {
                index: i,
                facet: f,
                r: p.r,
                r_normalised: p.r / r_max,
                flock,
                flock_kind,
                class: if flock_kind == Kind::Stable { Class::Regular } else { Class::Rocking },
                basin_exit,
                flock_exit,
                uplift_acceleration: margin / p.r,
            });
        }
        stable
    }

    /// A point uniformly distributed on the hull surface outside facet `exclude` (scaled body
    /// frame, relative to G) and the outward normal of its facet.
    pub fn surface_point(&self, rng: &mut Stream, exclude: u32) -> (Vec3, Vec3) {
        let total = *self.cumulative_area.last().expect("a hull has facets");
        for _ in 0..1000 {
            let x = rng.random_range(0.0..total);
            let k = self.cumulative_area.partition_point(|&c| c <= x).min(self.triangles.len() - 1);
            let (f, [a, b, c]) = self.triangles[k];
            if f == exclude {
                continue;
            }
            let (s, t): (f64, f64) = (rng.random(), rng.random());
            let s = s.sqrt();
            let p = a * (1.0 - s) + b * (s * (1.0 - t)) + c * (s * t);
            return (p, self.body.facet_normals[f as usize]);
        }
        // Only reachable if the resting facet is (almost) the whole surface.
        (self.body.corners[0], self.body.corners[0].normalize())
    }
}

/// The orientation (body → world) that puts the outward normal `n` (body frame) straight down.
pub fn resting_orientation(n: &Vec3) -> UnitQuaternion<f64> {
    UnitQuaternion::rotation_between(n, &-Vec3::z())
        .unwrap_or_else(|| UnitQuaternion::from_axis_angle(&Vec3::x_axis(), std::f64::consts::PI))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::Options;

    #[test]
    fn a_box_rests_on_each_of_its_faces() {
        // A 2 × 3 × 4 box: its six faces are its stable rests, one facing each of ±x, ±y, ±z.
        let (mesh, rep) = crate::generate::cuboid(2.0, 3.0, 4.0).into_solid_boundary().unwrap();
        let a = Analysis::of_solid(mesh, rep, &Options::default()).unwrap();
        let stone = Stone::new(&a, 0.01).unwrap();
        let mut found = Vec::new();
        for axis in [Vec3::x(), Vec3::y(), Vec3::z()] {
            for normal in [axis, -axis] {
                let e = stone.stable_facing(&normal).expect("a face");
                assert!((stone.body.facet_normals[e.facet as usize] - normal).norm() < 1e-9);
                // At rest on the face: in the flock of the face's stable equilibrium.
                assert_eq!(stone.flock_of(e.facet), Some(e.flock));
                found.push(e.index);
            }
        }
        found.sort();
        found.dedup();
        assert_eq!(found.len(), 6);
        // Between two faces there is none.
        assert!(stone.stable_facing(&Vec3::new(1.0, 1.0, 0.0).normalize()).is_none());
        // Past the hull's facets, no flock.
        assert_eq!(stone.flock_of(stone.body.facet_normals.len() as u32), None);
    }
}
