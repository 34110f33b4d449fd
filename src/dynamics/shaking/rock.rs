//! Field rocks: a rock at its true size, in a physical pose, under a recorded three-component
//! ground motion, one record at a time ([`crate::dynamics::shaking::records::run_record`]) or every
//! record × scale factor of a batch with its fragility surface ([`crate::dynamics::shaking::records::run_batch`]).
//!
//! * **Pose** ([`Pose`], [`place`]): as scanned (mesh frame = world frame, +z up, put down under
//!   its lowest point and settled; refused unless it rests on the stable micro-equilibrium of the
//!   quasi-static descent from the as-scanned down direction), a stable micro-equilibrium, or a
//!   quaternion.
//! * **True size and motion**: the Froude-exact scaled run of [`crate::dynamics::shaking::drive`].
//! * **Contact** from the surface pairs of [`Surface`] at the rock's real size ([`rock_params`],
//!   the contact of every resting run; rock on concrete by default on the command line).
//! * **Outcome** ([`RockRun`]): overturned = rests on a stable micro-equilibrium of another flock;
//!   the largest tilt; the residual slide relative to the ground.
//! * Records × scale factors, with or without an ensemble, and their fragility surface:
//!   [`crate::dynamics::shaking::records`].

use crate::analysis::{Analysis, Options};
use crate::dynamics::engine::rest::RestKind;
use crate::dynamics::engine::run::{run_to_end, NoCertificate, Passive};
use crate::dynamics::engine::simulation::Simulation;
use crate::dynamics::resting::outcome::{classify, Outcome};
use crate::dynamics::resting::RestingParams;
use crate::dynamics::shaking::drive::{shake_placed, Placed};
use crate::dynamics::stone::Stone;
use crate::dynamics::surface::Surface;
use crate::ground_motion::{Measures, Record};
use crate::{Error, Result, Vec3};
use nalgebra::UnitQuaternion;
use serde::{Deserialize, Serialize};

/// How the rock stands on the ground before the motion starts.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Pose {
    /// The mesh frame is the world frame (+z up, as field scans are stored): the rock is put
    /// down on a horizontal ground under its lowest point and settles under gravity. It must come
    /// to rest on the stable micro-equilibrium of the quasi-static descent from the as-scanned
    /// down direction −z ([`Stone::rest`]).
    AsScanned,
    /// Exactly at rest on this stable micro-equilibrium (its index among the analysis'
    /// micro-equilibria, as `analyze` prints it), as for pushes; written `equilibrium:ID`. Files
    /// written before hull facets could be named call it `facet` (then `facet:ID` named an
    /// equilibrium), which is read as this.
    #[serde(alias = "facet")]
    Equilibrium {
        /// Analysis index of the stable micro-equilibrium.
        id: usize,
    },
    /// At rest on the stable micro-equilibrium of this hull facet (the facet number `analyze`
    /// prints beside each equilibrium); written `facet:F`. [`Pose::resolved`] turns it into the
    /// [`Pose::Equilibrium`] it names.
    HullFacet {
        /// The hull facet's number.
        facet: usize,
    },
    /// The mesh rotated by this unit quaternion (w, x, y, z; mesh → world), put down and settled
    /// as for [`Pose::AsScanned`].
    Quat {
        /// Components w, x, y, z (normalised on use).
        q: [f64; 4],
    },
}

impl std::fmt::Display for Pose {
    /// The command line's spelling (`as-scanned`, `equilibrium:ID`, `facet:F`, `quat:w,x,y,z`),
    /// which [`Pose::from_str`](std::str::FromStr) reads back.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Pose::AsScanned => write!(f, "as-scanned"),
            Pose::Equilibrium { id } => write!(f, "equilibrium:{id}"),
            Pose::HullFacet { facet } => write!(f, "facet:{facet}"),
            Pose::Quat { q } => write!(f, "quat:{},{},{},{}", q[0], q[1], q[2], q[3]),
        }
    }
}

impl std::str::FromStr for Pose {
    type Err = Error;
    fn from_str(s: &str) -> Result<Pose> {
        let bad = || {
            Error::parameter(
                "pose",
                format!("{s:?}"),
                "as-scanned, equilibrium:ID (a stable micro-equilibrium, as analyze numbers them), facet:F (the \
                 hull facet it rests on) or quat:w,x,y,z",
            )
        };
        let number = |t: &str| t.trim().parse::<usize>().map_err(|_| bad());
        if s == "as-scanned" {
            return Ok(Pose::AsScanned);
        }
        if let Some(id) = s.strip_prefix("equilibrium:") {
            return Ok(Pose::Equilibrium { id: number(id)? });
        }
        if let Some(facet) = s.strip_prefix("facet:") {
            return Ok(Pose::HullFacet { facet: number(facet)? });
        }
        if let Some(q) = s.strip_prefix("quat:") {
            let v: Vec<f64> = q
                .split(',')
                .map(|x| x.trim().parse::<f64>())
                .collect::<std::result::Result<_, _>>()
                .map_err(|_| bad())?;
            let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            if v.len() != 4 || !(n > 0.0 && n.is_finite()) {
                return Err(Error::parameter(
                    "pose",
                    format!("{s:?}"),
                    "a quaternion of four finite numbers, not all zero",
                ));
            }
            return Ok(Pose::Quat { q: [v[0], v[1], v[2], v[3]] });
        }
        Err(bad())
    }
}

impl Pose {
    /// This pose on `stone`, a hull facet turned into the stable micro-equilibrium it holds; an
    /// equilibrium index that is not a stable one's, or a facet that holds none, is refused with
    /// the ids that are. `facet:F` named an equilibrium index before it named a hull facet; where
    /// F could be read both ways and the two differ, it is refused with both readings rather than
    /// read one way silently.
    pub fn resolved(self, stone: &Stone) -> Result<Pose> {
        let stable: Vec<(usize, usize)> = stone.stable().iter().map(|s| (s.index, s.facet as usize)).collect();
        self.resolved_among(&stable, &|id| stone.facet_hint(id))
    }

    /// [`Pose::resolved`] among the stable micro-equilibria `stable` (analysis index, hull
    /// facet), `hint` saying what an index that is not a stable one's is.
    fn resolved_among(self, stable: &[(usize, usize)], hint: &dyn Fn(usize) -> String) -> Result<Pose> {
        let list = || {
            let ids: Vec<String> = stable.iter().map(|(index, facet)| format!("{index} (facet {facet})")).collect();
            ids.join(", ")
        };
        let refuse = |what: String| Error::Pose { pose: self.to_string(), what };
        match self {
            Pose::Equilibrium { id } if !stable.iter().any(|s| s.0 == id) => Err(refuse(format!(
                "not the index of a stable micro-equilibrium{}; stable ones (with their hull facets): {}",
                hint(id),
                list()
            ))),
            Pose::HullFacet { facet } => {
                let on = stable.iter().find(|s| s.1 == facet);
                let old = stable.iter().find(|s| s.0 == facet);
                match (on, old) {
                    (Some(&(e, _)), Some(&(_, old_facet))) if e != facet => Err(refuse(format!(
                        "ambiguous: hull facet {facet} holds stable micro-equilibrium {e}, and equilibrium {facet} \
                         (what facet:{facet} meant in earlier versions) rests on hull facet {old_facet}; write \
                         equilibrium:{e} for the first, equilibrium:{facet} for the second"
                    ))),
                    (Some(&(e, _)), _) => Ok(Pose::Equilibrium { id: e }),
                    (None, old) => {
                        let was = old.map_or(String::new(), |&(_, old_facet)| {
                            format!(
                                "; facet:{facet} meant equilibrium {facet} in earlier versions: write equilibrium:{facet} \
                                 for it (it rests on hull facet {old_facet})"
                            )
                        });
                        Err(refuse(format!(
                            "hull facet {facet} holds no stable micro-equilibrium{was}; stable ones (with their hull \
                             facets): {}",
                            list()
                        )))
                    }
                }
            }
            p => Ok(p),
        }
    }

    /// The orientation (mesh → world) of a pose that is put down and settled: as scanned (the
    /// identity) or the quaternion, normalised; None for a pose that names an equilibrium.
    pub fn orientation(&self) -> Option<UnitQuaternion<f64>> {
        match *self {
            Pose::AsScanned => Some(UnitQuaternion::identity()),
            Pose::Quat { q } => {
                Some(UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3])))
            }
            Pose::Equilibrium { .. } | Pose::HullFacet { .. } => None,
        }
    }
}

/// Rest criterion for placement: the pose's expected micro-equilibrium, else a usage error that
/// says where the rock went instead.
fn refuse_pose(stone: &Stone, pose: &Pose, down: &Vec3, expected: u32, got: u32, settled: bool) -> Error {
    let eq = |f: u32| stone.facet_equilibrium[f as usize].map_or("?".to_string(), |e| e.to_string());
    let off = stone.body.facet_normals[expected as usize].dot(down).clamp(-1.0, 1.0).acos().to_degrees();
    if !settled {
        return Error::Pose {
            pose: pose.to_string(),
            what: "the rock did not come to rest after it was put down (it is still moving at the time cap)".into(),
        };
    }
    let what = format!(
        "put down on the ground, the rock does not rest on the stable micro-equilibrium under it \
         ({} by the quasi-static descent, whose facet is {off:.2}° from the given down direction) but rolled \
         to {}: the rock does not stand still in this pose (a scan made standing should be within a fraction of a \
         degree of its resting facet); choose a pose that stands: facet:ID of a stable equilibrium, or a quat:",
        eq(expected),
        eq(got)
    );
    Error::Pose { pose: pose.to_string(), what }
}

/// Put the rock down in `pose` and let it settle under gravity (module docs of the field-rock
/// docs).
///
/// * `Equilibrium` (or `HullFacet`, [`Pose::resolved`]): exactly at rest on its facet, settled for
///   `p.settle_time` (as for pushes).
/// * `AsScanned` / `Quat`: the body orientation is the pose, G above the ground by the support
///   function h(d) of the down direction d (the lowest point touches), zero velocity; simulated
///   without motion until it rests ([`PositionRest`](crate::dynamics::engine::rest::PositionRest) of `p.sim`, at most
///   `p.sim.max_time`). It must rest on the micro-equilibrium the quasi-static descent of h from
///   d reaches ([`Stone::rest`]), else the pose is refused.
pub fn place<'a>(stone: &'a Stone, pose: &Pose, p: &RestingParams) -> Result<Placed<'a>> {
    let q = match pose.resolved(stone)? {
        Pose::Equilibrium { id } => {
            let start = stone.position(id).expect("a resolved pose names a stable micro-equilibrium");
            return Ok(Placed::on(stone, start, p));
        }
        resolved => resolved.orientation().ok_or_else(|| Error::check(format!("pose {pose} did not resolve")))?,
    };
    let down0 = q.inverse() * -Vec3::z();
    let expected = stone.rest(&down0);
    let z = stone.body.support(&down0);
    let mut sim = Simulation::new(&stone.body, &p.sim, &q, z, &Vec3::zeros(), &Vec3::zeros());
    sim.set_contact_frequency(p.contact_frequency);
    sim.advance((p.settle_time / p.sim.numerics.dt).round() as u64);
    let end = run_to_end(&mut sim, &p.sim, &mut Passive, &NoCertificate, RestKind::Positions, &mut |_| {});
    let rest = stone.rest(&end.state.down);
    if !end.settled || rest.facet != expected.facet {
        return Err(refuse_pose(stone, pose, &down0, expected.facet, rest.facet, end.settled));
    }
    let start = stone.position(rest.equilibrium).expect("a stable micro-equilibrium");
    Ok(Placed { sim, start, settling_tilt: down0.dot(&end.state.down).clamp(-1.0, 1.0).acos() })
}

/// The outcome of one rock under one ground motion ([`shake_record`]), real units.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct RockRun {
    /// Overturned: came to rest on a stable micro-equilibrium of another flock than the one it
    /// stood on ([`Outcome::Toppled`]; a run still moving at the time cap is classified by the
    /// quasi-static descent from its last down direction, and `settled` is false).
    pub overturned: bool,
    /// Same micro-equilibrium, another one of the same flock (it rocked to a neighbour), or
    /// overturned.
    pub outcome: Outcome,
    /// Largest tilt (degrees) of the start facet's normal away from straight down.
    pub max_tilt_deg: f64,
    /// Residual sliding (m): horizontal displacement of G relative to the ground between the start
    /// and the end of the run (includes the travel of an overturn).
    pub slide_m: f64,
    /// Tilt (degrees) of the body while it settled after being put down.
    pub settling_tilt_deg: f64,
    /// Analysis index of the stable micro-equilibrium it stood on, and its flock.
    pub start_equilibrium: usize,
    /// Flock it stood on.
    pub start_flock: usize,
    /// Analysis index of the stable micro-equilibrium it ended on.
    pub final_equilibrium: usize,
    /// Flock it ended in.
    pub final_flock: usize,
    /// Came to rest (relative to the ground) before the time cap.
    pub settled: bool,
    /// Azimuth of the record's x axis (degrees, counter-clockwise from the x axis of the rock as
    /// it stands: the mesh's own as scanned, or turned by the smallest rotation that brings its
    /// facet down when it stands on an equilibrium).
    pub azimuth_deg: f64,
    /// The surface pair the contact started from ([`RestingParams::surface`]; absent: the damped
    /// reference or parameters made by hand, and files of earlier versions).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<Surface>,
    /// Real R_max of the rock (m).
    pub r_max_m: f64,
    /// Whether that size was assumed, the mesh's unit being neither given nor known
    /// ([`crate::dynamics::size`]); set from [`RockSetup::size_assumed`] by the runs that have a
    /// setup, absent when the caller gave the unit as a bare number.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size_assumed: Option<bool>,
    /// Real time simulated from the start of the motion (s).
    pub time_s: f64,
    /// Steps simulated (placement excluded).
    pub steps: u64,
    /// The deepest any hull corner went below the ground after any step or sub-step of the run
    /// (in units of the rock's R_max, [`crate::dynamics::engine::world::penetration`]), the stone's settling included.
    #[serde(default)]
    pub deepest_penetration: f64,
}

/// Shake a placed rock with `record` (real time, SI, x axis turned by `azimuth` rad in the world
/// frame), the rock of real size `r_max_m` metres, until it rests relative to the ground
/// ([`shake_placed`]; true size by the Froude-exact scaled run of [`crate::dynamics::shaking::drive`]).
pub fn shake_record(
    stone: &Stone,
    placed: Placed,
    p: &RestingParams,
    record: &Record,
    azimuth: f64,
    r_max_m: f64,
) -> RockRun {
    let run = shake_placed(stone, placed, p, record, azimuth, r_max_m);
    let s = &stone.stable()[run.start];
    let rest = stone.rest(&run.end.state.down);
    let outcome = classify(stone, run.start, Some(rest.facet), rest.flock);
    RockRun {
        overturned: outcome == Outcome::Toppled,
        outcome,
        max_tilt_deg: run.max_tilt.to_degrees(),
        slide_m: run.slide * r_max_m,
        settling_tilt_deg: run.settling_tilt.to_degrees(),
        start_equilibrium: s.index,
        start_flock: s.flock,
        final_equilibrium: rest.equilibrium,
        final_flock: rest.flock,
        settled: run.end.settled,
        azimuth_deg: azimuth.to_degrees(),
        surface: p.surface,
        r_max_m,
        size_assumed: None,
        time_s: run.end.steps as f64 * p.sim.numerics.dt * r_max_m.sqrt(),
        steps: run.end.steps,
        deepest_penetration: run.deepest_penetration,
    }
}

/// Shaking parameters of a rock at true size R_max = `r_max_m` on `surface`: the contact of every
/// resting run, [`RestingParams::on_surface`] (the surface pair's friction, restitution and
/// rolling-resistance length at that size, 120 Hz contacts, dt 1/240 s, a 20 s cap after the
/// motion, rest windows of 0.5 s).
pub fn rock_params(surface: Surface, r_max_m: f64) -> Result<RestingParams> {
    RestingParams::on_surface(surface, r_max_m)
}

/// The stone of the analysis `a` with its flocks at `nu`, or at the analysis' macro ν
/// ([`Analysis::macro_nu`]) if None.
pub fn stone_of(a: &Analysis, nu: Option<f64>) -> Result<Stone> {
    Stone::new(a, nu.unwrap_or_else(|| a.macro_nu(&Options::default()).0))
}

/// The default poses of `stone` as a rock of R_max `r_max_m` on concrete: the equilibrium
/// indices of its regular and its rocking default equilibrium
/// ([`crate::dynamics::resting::default_pair`] with [`rock_params`] of
/// [`Surface::RockOnConcrete`]), either None when the stone has none that stays at rest.
pub fn default_poses(stone: &Stone, r_max_m: f64) -> Result<(Option<usize>, Option<usize>)> {
    let p = rock_params(Surface::RockOnConcrete, r_max_m)?;
    let (regular, rocking) = crate::dynamics::resting::default_pair(stone, &p);
    let index = |k: Option<usize>| k.map(|k| stone.stable()[k].index);
    Ok((index(regular), index(rocking)))
}

/// A field rock and how it is shaken: everything of a run but the record.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RockSetup {
    /// The pose it stands in.
    pub pose: Pose,
    /// Metres per mesh unit.
    pub length_unit_m: f64,
    /// Real R_max of the rock (m): the body's R_max (mesh units) times `length_unit_m`.
    pub r_max_m: f64,
    /// Whether that size was assumed, the mesh's unit being neither given nor known: set by the
    /// command line and the Python binding, which decide the size with
    /// [`crate::dynamics::size::RealSize::resolve`]; absent when the unit was given as a number.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size_assumed: Option<bool>,
    /// Azimuth (rad, world frame) of the records' x axis.
    pub azimuth: f64,
    /// Simulation parameters (scaled frame, see [`shake_record`]).
    pub params: RestingParams,
}

impl RockSetup {
    /// The setup of `stone` in `pose` with mesh unit `length_unit_m` metres on `surface`.
    pub fn new(stone: &Stone, pose: Pose, length_unit_m: f64, surface: Surface, azimuth: f64) -> Result<RockSetup> {
        let r_max_m = stone.body.r_max * length_unit_m;
        Ok(RockSetup {
            pose,
            length_unit_m,
            r_max_m,
            size_assumed: None,
            azimuth,
            params: rock_params(surface, r_max_m)?,
        })
    }

    /// The setup of `stone` in `pose` with mesh unit `length_unit_m` metres and the simulation
    /// parameters `params` (e.g. [`rock_params`] with overrides).
    pub fn with_params(
        stone: &Stone,
        pose: Pose,
        length_unit_m: f64,
        azimuth: f64,
        params: RestingParams,
    ) -> RockSetup {
        let r_max_m = stone.body.r_max * length_unit_m;
        RockSetup { pose, length_unit_m, r_max_m, size_assumed: None, azimuth, params }
    }

    /// Real time step of the simulation (s): dt·√(R_max / 1 m).
    pub fn real_dt(&self) -> f64 {
        self.params.sim.numerics.dt * self.r_max_m.sqrt()
    }
}

/// `record` × `scale` (≥ 0, else a usage error) as the rock of `setup` is driven by it: the
/// scaled record's intensity measures (on the record as given) and the motion of the run
/// ([`driven`] to the setup's real step).
pub fn scaled_motion(record: &Record, scale: f64, setup: &RockSetup) -> Result<(Measures, Record)> {
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(Error::parameter("scale", scale, "≥ 0"));
    }
    let scaled = record.scaled(scale);
    Ok((scaled.measures(), driven(&scaled, setup.real_dt())?))
}

/// `record` as a run with real time step `real_dt` (s) is driven by it: resampled without aliasing
/// to the step when it is sampled finer ([`Record::resampled`]), as it is otherwise.
pub fn driven(record: &Record, real_dt: f64) -> Result<Record> {
    if record.dt < real_dt {
        record.resampled(real_dt)
    } else {
        Ok(record.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_facet_pose_is_read_as_the_hull_facet_and_never_silently_as_an_old_equilibrium_id() {
        // Stable micro-equilibria (index, hull facet): 0 on facet 3, 1 on facet 7, 3 on facet 0.
        let stable = [(0, 3), (1, 7), (3, 0)];
        let none = |_: usize| String::new();
        let pose = |s: &str| s.parse::<Pose>().unwrap().resolved_among(&stable, &none);
        // A facet that holds an equilibrium and is no equilibrium's index: that equilibrium.
        assert_eq!(pose("facet:7").unwrap(), Pose::Equilibrium { id: 1 });
        // The same equilibrium either way (facet 0 holds equilibrium 3... and equilibrium 0 is on
        // facet 3): facet:3 holds equilibrium 0 but names equilibrium 3 of old, on facet 0.
        let e = pose("facet:3").unwrap_err().to_string();
        assert!(e.contains("ambiguous: hull facet 3 holds stable micro-equilibrium 0, and equilibrium 3"), "{e}");
        assert!(e.contains("write equilibrium:0 for the first, equilibrium:3 for the second"), "{e}");
        // A facet holding no equilibrium whose number is an old equilibrium id: refused, pointing
        // to equilibrium:ID.
        let e = pose("facet:1").unwrap_err().to_string();
        assert!(e.contains("hull facet 1 holds no stable micro-equilibrium; facet:1 meant equilibrium 1"), "{e}");
        assert!(e.contains("write equilibrium:1 for it (it rests on hull facet 7)"), "{e}");
        // Neither reading: the list of what there is.
        let e = pose("facet:9").unwrap_err().to_string();
        assert!(e.contains("stable ones (with their hull facets): 0 (facet 3), 1 (facet 7), 3 (facet 0)"), "{e}");
        // Equilibrium ids are taken as they are, or refused.
        assert_eq!(pose("equilibrium:3").unwrap(), Pose::Equilibrium { id: 3 });
        assert!(pose("equilibrium:2").is_err());
        // Where both readings name the same equilibrium (a box: equilibrium k on facet k), it is
        // that one.
        let same = [(0, 0), (1, 1)];
        assert_eq!(
            "facet:1".parse::<Pose>().unwrap().resolved_among(&same, &none).unwrap(),
            Pose::Equilibrium { id: 1 }
        );
        assert_eq!(Pose::AsScanned.resolved_among(&stable, &none).unwrap(), Pose::AsScanned);
    }

    #[test]
    fn a_box_is_a_stone_at_its_nu_resting_by_default_on_its_largest_face() {
        // A 2 × 1.2 × 0.6 box: its stable equilibria are its six faces, the deepest (R = 0.3)
        // the two of normal ±z; a box has no rocking equilibrium.
        let (mesh, repairs) = crate::generate::cuboid(2.0, 1.2, 0.6).into_solid_boundary().unwrap();
        let a = Analysis::of_solid(mesh, repairs, &Options::default()).unwrap();
        let stone = stone_of(&a, Some(0.01)).unwrap();
        assert_eq!(stone.nu, 0.01);
        assert_eq!(stone_of(&a, None).unwrap().nu, a.macro_nu(&Options::default()).0);
        let (regular, rocking) = default_poses(&stone, 1.0).unwrap();
        let k = stone.position(regular.expect("a regular pose")).unwrap();
        let q = &stone.stable()[k];
        assert!(stone.body.facet_normals[q.facet as usize].z.abs() > 0.999);
        assert!((q.r - 0.3).abs() < 1e-9, "{}", q.r);
        assert_eq!(rocking, None);
        assert!(default_poses(&stone, -1.0).is_err());
    }
}
