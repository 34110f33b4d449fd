//! The planar pipeline in one call: polygon → micro-equilibria → checked hierarchy → flocks at
//! the macro scale ν, with the serialisable report (flock contents and rocking sides).

use super::{
    ellipse_polygon, hierarchy, PlanarEquilibria, PlanarEquilibrium, PlanarSite, Point2, Polygon, Sampling,
    DEFAULT_DEGENERACY_TOL,
};
use crate::hierarchy::{Counts, Flock, Flocks, Hierarchy, Kind, NuSource, Plateau, Step};
use crate::Result;
use serde::Serialize;

/// Polygon, micro-equilibria and hierarchy, in memory.
#[derive(Clone, Debug)]
pub struct PlanarAnalysis {
    /// The polygon.
    pub polygon: Polygon,
    /// Its micro-equilibria.
    pub equilibria: PlanarEquilibria,
    /// Cancellation hierarchy of the micro-equilibria over ν.
    pub hierarchy: Hierarchy,
}

/// The flock contents of a polygon with a stable/unstable macro pattern (e.g. the ellipse):
/// the (stable, unstable) counts of every stable and every unstable flock, in flock order.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct FlockContents {
    /// (stable, unstable) counts of every stable flock.
    pub stable_flocks: Vec<(usize, usize)>,
    /// (stable, unstable) counts of every unstable flock.
    pub unstable_flocks: Vec<(usize, usize)>,
}

impl FlockContents {
    /// Collect the contents of `flocks` by type.
    pub fn of(flocks: &[Flock]) -> Self {
        let mut c = FlockContents::default();
        for f in flocks {
            match f.kind {
                Kind::Stable => c.stable_flocks.push((f.stable, f.unstable)),
                _ => c.unstable_flocks.push((f.stable, f.unstable)),
            }
        }
        c
    }

    /// The common (stable, unstable) content of all stable flocks and of all unstable flocks,
    /// if every flock of a type has the same content.
    pub fn uniform(&self) -> Option<((usize, usize), (usize, usize))> {
        let same = |v: &[(usize, usize)]| v.first().filter(|f| v.iter().all(|x| x == *f)).copied();
        Some((same(&self.stable_flocks)?, same(&self.unstable_flocks)?))
    }
}

/// A rocking equilibrium of a polygon: a stable side in an unstable flock.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct RockingSide {
    /// Index into the micro-equilibria.
    pub index: usize,
    /// The stable side.
    pub side: u32,
    /// Contact point: the foot of G on the side.
    pub point: Point2,
    /// R = distance from G to the contact point.
    pub r: f64,
    /// Polar angle of the contact point seen from G, in (−π, π].
    pub phi: f64,
    /// Index of the (unstable) flock containing it.
    pub flock: usize,
}

impl RockingSide {
    /// Micro-equilibrium `index`, `p`, a rocking equilibrium in `flock`.
    fn of(index: usize, p: &PlanarEquilibrium, flock: usize) -> Self {
        let side = match p.site {
            PlanarSite::Side(s) => s,
            PlanarSite::Vertex(_) => unreachable!("rocking equilibria are stable"),
        };
        RockingSide { index, side, point: p.point, r: p.r, phi: p.phi, flock }
    }
}

/// The serialisable result of a planar analysis.
#[derive(Clone, Debug, Serialize)]
pub struct PlanarReport {
    /// Number of sides of the polygon.
    pub sides: usize,
    /// Area of the polygon.
    pub area: f64,
    /// G: the area centroid.
    pub centroid: Point2,
    /// Micro-equilibria.
    pub stable: usize,
    /// Number of unstable micro-equilibria (vertices).
    pub unstable: usize,
    /// R_min: smallest distance from G to a stable side.
    pub r_min: f64,
    /// R_max: largest distance from G to a vertex.
    pub r_max: f64,
    /// v_max = (R_max − R_min)/R_max: the largest cancellation level.
    pub v_max: f64,
    /// Number of signs decided within the tolerance τ = `tol_rel` · D.
    pub degenerate_decisions: usize,
    /// The macro scale used for flocks.
    pub nu: f64,
    /// Where ν came from.
    pub nu_source: NuSource,
    /// The longest step of n(ν), if any.
    pub plateau: Option<Plateau>,
    /// S(ν), U(ν).
    #[serde(rename = "macro")]
    pub macro_counts: Counts,
    /// Flocks at ν.
    pub flocks: Vec<Flock>,
    /// (stable, unstable) contents of the flocks by type.
    pub flock_contents: FlockContents,
    /// Stable sides in unstable flocks.
    pub rocking: Vec<RockingSide>,
    /// Every micro-equilibrium.
    pub micro: Vec<PlanarEquilibrium>,
    /// Staircase of the counts against ν.
    pub staircase: Vec<Step>,
}

impl PlanarAnalysis {
    /// Find the equilibria of `polygon` (signs within `tol_rel` · D decided symbolically), build and check the hierarchy.
    pub fn new(polygon: Polygon, tol_rel: f64) -> Result<Self> {
        let equilibria = PlanarEquilibria::new(&polygon, tol_rel)?;
        let hierarchy = hierarchy(&equilibria);
        hierarchy.check()?;
        Ok(PlanarAnalysis { polygon, equilibria, hierarchy })
    }

    /// The analysis of the ellipse 1 : a discretised into `sides` sides by `sampling`
    /// ([`ellipse_polygon`]), signs decided with the default tolerance [`DEFAULT_DEGENERACY_TOL`].
    pub fn of_ellipse(a: f64, sides: usize, sampling: Sampling) -> Result<Self> {
        PlanarAnalysis::new(ellipse_polygon(a, sides, sampling)?, DEFAULT_DEGENERACY_TOL)
    }

    /// The ν of the macro scale, by the rule of the 3D case ([`crate::hierarchy::macro_nu`]):
    /// the user's, else the midpoint of a clear plateau, else the paper's ν = 0.0035.
    pub fn macro_nu(&self, user: Option<f64>) -> (f64, NuSource) {
        crate::hierarchy::macro_nu(user, self.hierarchy.plateau())
    }

    /// The flocks at ν.
    pub fn flocks_at(&self, nu: f64) -> Flocks {
        self.hierarchy.flocks_at(nu)
    }

    /// The report at the user's ν, else at the automatic macro scale.
    pub fn report(&self, user_nu: Option<f64>) -> PlanarReport {
        let m = self.hierarchy.macro_scale(user_nu);
        let eq = &self.equilibria;
        let rocking = m.rocking.iter().map(|&i| RockingSide::of(i, &eq.points[i], m.flocks.membership[i])).collect();
        let (nu, nu_source, flocks) = (m.nu, m.source, m.flocks);
        PlanarReport {
            sides: self.polygon.len(),
            area: self.polygon.area,
            centroid: self.polygon.centroid,
            stable: eq.stable,
            unstable: eq.unstable,
            r_min: eq.r_min,
            r_max: eq.r_max,
            v_max: self.hierarchy.v_max(),
            degenerate_decisions: eq.degenerate_decisions,
            nu,
            nu_source,
            plateau: m.plateau,
            macro_counts: m.counts,
            flock_contents: FlockContents::of(&flocks.flocks),
            flocks: flocks.flocks,
            rocking,
            micro: eq.points.clone(),
            staircase: self.hierarchy.staircase(),
        }
    }
}
