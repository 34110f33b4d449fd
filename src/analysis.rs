//! The static pipeline, mesh → solid → hull → equilibria → Morse–Smale graph → hierarchy →
//! flocks, and [`Report`], the one serialisable result the CLI, plots and experiments read.

use crate::equilibria::{Equilibria, Kind, Signs, Site, DEFAULT_DEGENERACY_TOL};
use crate::hierarchy::cancellation_hierarchy;
use crate::hierarchy::{Counts, Flock, Hierarchy, Plateau, Step};
use crate::hull::{Polyhedron, DEFAULT_COPLANAR_TOL};
use crate::mesh::{ldexp, scale_point, BaseClosing, ClosedScan, OpenScanSummary, Repairs, RimChoice, Scan, TriMesh};
use crate::morse_smale::MorseSmaleGraph;
use crate::shape::{describe, ShapeDescriptors};
use crate::solid::MassProperties;
use crate::{Error, Point3, Result};
use serde::Serialize;
use std::path::Path;

pub use crate::hierarchy::{NuSource, PAPER_NU};
pub use hidden_base::{DependentCounts, HiddenBase, OpenScanReport, FLAT_CAP};

mod hidden_base;

/// Tolerances and choices of a static analysis.
#[derive(Clone, Debug)]
pub struct Options {
    /// Relative coplanarity tolerance of the facet merge (× bounding-box diagonal).
    pub coplanar_tol: f64,
    /// Relative tolerance of degenerate equilibrium predicates (× hull diameter).
    pub degeneracy_tol: f64,
    /// Fixed ν for the macro scale; `None` = the automatic plateau (or [`PAPER_NU`] if none).
    pub nu: Option<f64>,
    /// A known centre of mass (input frame and units) overriding the homogeneous solid's G:
    /// a weighted die, a hollow print, a scan of only the hull. The inertia is then taken about
    /// it ([`MassProperties::about`]). `None`: the solid's G.
    pub center_of_mass: Option<Point3>,
    /// Which opening of an open scan is the rim of its hidden base ([`Analysis::of_scan`]).
    pub rim: RimChoice,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            coplanar_tol: DEFAULT_COPLANAR_TOL,
            degeneracy_tol: DEFAULT_DEGENERACY_TOL,
            nu: None,
            center_of_mass: None,
            rim: RimChoice::Lowest,
        }
    }
}

/// Every intermediate object of the static analysis, in memory.
pub struct Analysis {
    /// The input triangle mesh after repairs.
    pub mesh: TriMesh,
    /// Repairs applied to the input mesh.
    pub repairs: Repairs,
    /// Volume, centre of mass and inertia of the solid.
    pub mass: MassProperties,
    /// Convex hull with coplanar triangles merged into facets.
    pub hull: Polyhedron,
    /// Micro-equilibria on the hull (stable, saddle, unstable).
    pub equilibria: Equilibria,
    /// Morse–Smale graph of the distance function from G.
    pub graph: MorseSmaleGraph,
    /// Cancellation hierarchy of the equilibria over ν.
    pub hierarchy: Hierarchy,
    /// Shape descriptors (axis ratios, Zingg class).
    pub shape: ShapeDescriptors,
    /// The shared signs of the equilibrium predicates (reused by the tracer).
    pub signs: Signs,
    /// For an open scan: the base that closed it ([`Analysis::of_closed_scan`]); `None` for a
    /// closed stone.
    pub hidden_base: Option<HiddenBase>,
}

impl Analysis {
    /// Run the static pipeline on a closed, checked mesh (see [`TriMesh::into_solid_boundary`]).
    ///
    /// Everything is computed on the mesh scaled by the exact power of two 2^k that brings its
    /// largest extent into [1, 2) ([`TriMesh::unit_exponent`]) and scaled back, so any finite
    /// coordinates give the same counts, ν and hierarchy as the unscaled mesh (for ordinary sizes
    /// bit for bit the numbers of computing in input units). Lengths, areas, volumes and moments
    /// are reported in input units; one that does not fit in f64 there (the volume of a
    /// 10³⁰⁰-unit stone) is reported as infinite, honestly, rather than refused.
    pub fn of_solid(mesh: TriMesh, repairs: Repairs, opts: &Options) -> Result<Self> {
        let k = mesh.unit_exponent();
        let unit = mesh.scaled_pow2(k);
        let mut unit_mass = MassProperties::of_unscaled(&unit)?;
        if let Some(c) = opts.center_of_mass {
            if !c.coords.iter().all(|x| x.is_finite()) {
                return Err(Error::parameter("center_of_mass", c, "three finite numbers"));
            }
            unit_mass = unit_mass.about(&crate::mesh::scale_point(&c, k));
        }
        let mass = unit_mass.scaled_pow2(-k);
        Self::normalised(mesh, unit, k, repairs, mass, unit_mass, opts)
    }

    /// As [`Analysis::of_solid`] but with given mass properties (e.g. a G that is not the
    /// homogeneous solid's, for a stone with a heavy inclusion), in input units.
    pub fn with_center_of_mass(mesh: TriMesh, repairs: Repairs, mass: MassProperties, opts: &Options) -> Result<Self> {
        let k = mesh.unit_exponent();
        let unit = mesh.scaled_pow2(k);
        let unit_mass = mass.scaled_pow2(k);
        Self::normalised(mesh, unit, k, repairs, mass, unit_mass, opts)
    }

    /// The pipeline on `unit` = `mesh` × 2^k, results scaled back by 2^−k.
    fn normalised(
        mesh: TriMesh,
        unit: TriMesh,
        k: i32,
        repairs: Repairs,
        mass: MassProperties,
        unit_mass: MassProperties,
        opts: &Options,
    ) -> Result<Self> {
        opts.check()?;
        let hull = Polyhedron::new(&unit.vertices, opts.coplanar_tol)?;
        let g = unit_mass.center_of_mass;
        centre_inside(&hull, &g, opts.degeneracy_tol, &mass.center_of_mass)?;
        let signs = Signs::new(&hull, &g, opts.degeneracy_tol);
        let equilibria = Equilibria::from_signs(&hull, &g, &signs)?;
        let mut graph = MorseSmaleGraph::trace(&hull, &equilibria, &g, &signs)?;
        let mut hierarchy = cancellation_hierarchy(&equilibria, &graph)?;
        let mut shape = describe(&unit, &unit_mass);
        // Back to input units.
        let hull = hull.scaled_pow2(-k);
        let equilibria = equilibria.scaled_pow2(-k);
        graph.arcs.iter_mut().flat_map(|a| a.path.iter_mut()).for_each(|p| *p = scale_point(p, -k));
        hierarchy.nodes.iter_mut().for_each(|n| n.r = ldexp(n.r, -k));
        hierarchy.r_max = ldexp(hierarchy.r_max, -k);
        for x in [&mut shape.a, &mut shape.b, &mut shape.c] {
            *x = ldexp(*x, -k);
        }
        shape.volume = ldexp(shape.volume, -3 * k);
        shape.area = ldexp(shape.area, -2 * k);
        Ok(Analysis { mesh, repairs, mass, hull, equilibria, graph, hierarchy, shape, signs, hidden_base: None })
    }

    /// Load, check and analyse a mesh file, closed or open ([`Analysis::of_scan`]); every error
    /// names the file.
    pub fn of_file(path: &Path, opts: &Options) -> Result<Self> {
        let mesh = crate::mesh::io::read(path)?;
        Self::of_scan(mesh, opts).map_err(|e| e.with_path(path))
    }

    /// Check and analyse a scan as read ([`TriMesh::into_scan`]): a closed surface exactly as
    /// [`TriMesh::into_solid_boundary`] and [`Analysis::of_solid`] do; an open one (a field
    /// scan, its rim chosen by `opts.rim`) closed with the flat cap, the nominal base
    /// ([`BaseClosing::flat`]), its micro-equilibria marked where they depend on that base
    /// ([`HiddenBase`]).
    pub fn of_scan(mesh: TriMesh, opts: &Options) -> Result<Self> {
        match mesh.into_scan(&opts.rim)? {
            Scan::Closed(mesh, repairs) => Self::of_solid(mesh, repairs, opts),
            Scan::Open(scan) => {
                let summary = scan.summary().clone();
                let closed = BaseClosing::new(*scan)?.flat()?;
                Self::of_closed_scan(closed, summary, FLAT_CAP, opts)
            }
        }
    }

    /// Analyse an open scan closed by a base ([`BaseClosing::close`]), found as `scan` says and
    /// named `base` in reports, as [`Analysis::of_solid`] does, keeping which vertices are the
    /// base's ([`Analysis::hidden_base`]).
    pub fn of_closed_scan(closed: ClosedScan, scan: OpenScanSummary, base: &str, opts: &Options) -> Result<Self> {
        let hidden = HiddenBase::of(&closed, scan, base);
        let mut a = Self::of_solid(closed.mesh, closed.repairs, opts)?;
        a.hidden_base = Some(hidden);
        Ok(a)
    }

    /// For every micro-equilibrium: whether it depends on an open scan's hidden base
    /// ([`HiddenBase::dependent`]); all false for a closed stone.
    pub fn on_hidden_base(&self) -> Vec<bool> {
        match &self.hidden_base {
            Some(h) => h.dependent(&self.hull, &self.equilibria),
            None => vec![false; self.equilibria.points.len()],
        }
    }

    /// The scan as read: the analysed mesh, less the base that closed a field scan's rim (the
    /// scan's own triangles, its gaps' patches included; unreferenced points are dropped when it
    /// is read again). A closed scan is its mesh.
    pub fn scan_mesh(&self) -> TriMesh {
        match &self.hidden_base {
            Some(h) => TriMesh::new(self.mesh.vertices.clone(), self.mesh.triangles[..h.first_base_triangle].to_vec()),
            None => self.mesh.clone(),
        }
    }

    /// For each hull facet, the stable micro-equilibrium its steepest descent reaches.
    pub fn basins(&self) -> Vec<Option<usize>> {
        MorseSmaleGraph::facet_basins(&self.hull, &self.equilibria, &self.mass.center_of_mass, &self.signs)
    }

    /// The ν of the macro scale: the user's, else the plateau's, else the paper's.
    pub fn macro_nu(&self, opts: &Options) -> (f64, NuSource) {
        crate::hierarchy::macro_nu(opts.nu, self.hierarchy.plateau())
    }

    /// The serialisable summary of the analysis.
    pub fn report(&self, file: &str, opts: &Options) -> Report {
        self.report_with(file, opts, true)
    }

    /// [`Analysis::report`] without the quasi-static basin probabilities: `stable_facets` is
    /// empty. For field studies, which count equilibria and never read the basins: the exact basin
    /// areas (a descent of the support function per stable facet) are most of the time of a
    /// 2000-point pebble's report.
    pub fn report_without_basins(&self, file: &str, opts: &Options) -> Report {
        self.report_with(file, opts, false)
    }

    fn report_with(&self, file: &str, opts: &Options, basins: bool) -> Report {
        let m = self.hierarchy.macro_scale(opts.nu);
        let (nu, nu_source, flocks) = (m.nu, m.source, m.flocks);
        let eq = &self.equilibria;
        let on_base = self.on_hidden_base();
        let rocking = m
            .rocking
            .into_iter()
            .map(|i| {
                let p = &eq.points[i];
                let flock = flocks.membership[i];
                RockingEquilibrium {
                    index: i,
                    facet: match p.site {
                        Site::Facet(f) => f,
                        _ => u32::MAX,
                    },
                    point: p.point,
                    r: p.r,
                    r_normalised: p.r / eq.r_max,
                    flock,
                    flock_type: flocks.flocks[flock].kind,
                    hidden_base: on_base[i],
                }
            })
            .collect();
        let micro_list = eq
            .points
            .iter()
            .enumerate()
            .map(|(i, p)| MicroEquilibrium {
                index: i,
                kind: p.kind,
                site: p.site,
                point: p.point,
                r: p.r,
                flock: flocks.membership[i],
                hidden_base: on_base[i],
            })
            .collect();
        // On the normalised hull (exact power-of-two scaling, as the pipeline): probabilities
        // are scale-free, and no product overflows at extreme scales.
        let k = self.mesh.unit_exponent();
        let quasi_static = basins.then(|| {
            crate::basins::basin_probabilities(
                &self.hull.clone().scaled_pow2(k),
                &crate::mesh::scale_point(&self.mass.center_of_mass, k),
                &eq.clone().scaled_pow2(k),
            )
        });
        let stable_facets = quasi_static.map_or_else(Vec::new, |quasi_static| {
            eq.at_facet
                .iter()
                .enumerate()
                .filter_map(|(f, s)| {
                    let s = (*s)? as usize;
                    Some(StableFacet {
                        facet: f as u32,
                        equilibrium: s,
                        normal: self.hull.facets[f].normal,
                        r: eq.points[s].r,
                        basin_probability: quasi_static.facet_probability[f],
                        flock: flocks.membership[s],
                        hidden_base: on_base[s],
                    })
                })
                .collect()
        });
        let macro_counts = m.counts;
        Report {
            file: file.to_string(),
            repairs: self.repairs.clone(),
            open_scan: self.hidden_base.as_ref().map(|h| h.report(eq, &on_base)),
            mesh: MeshSummary { vertices: self.mesh.vertices.len(), triangles: self.mesh.triangles.len() },
            solid: SolidSummary {
                volume: self.mass.volume,
                center_of_mass: self.mass.center_of_mass,
                principal_moments: self.mass.principal_moments,
                area: self.mesh.area(),
            },
            hull: HullSummary {
                facets: self.hull.facets.len(),
                edges: self.hull.edges.len(),
                vertices: self.hull.vertices.len(),
                triangles: self.hull.hull_triangles,
                coplanar_tol: self.hull.coplanar_tol,
                volume: self.hull.volume(),
                area: self.hull.area(),
            },
            micro: MicroSummary {
                stable: eq.stable,
                unstable: eq.unstable,
                saddle: eq.saddle,
                r_min: eq.r_min,
                r_max: eq.r_max,
                degenerate_decisions: eq.degenerate_decisions,
            },
            shape: self.shape.clone(),
            r#macro: MacroSummary {
                nu,
                nu_source,
                stable: macro_counts.stable,
                unstable: macro_counts.unstable,
                saddle: macro_counts.saddle,
            },
            plateau: m.plateau,
            flocks: flocks.flocks,
            rocking,
            staircase: self.hierarchy.staircase(),
            equilibria: micro_list,
            stable_facets,
        }
    }
}

#[derive(Clone, Debug, Serialize)]
/// Size of the input mesh.
pub struct MeshSummary {
    /// Number of mesh vertices.
    pub vertices: usize,
    /// Number of mesh triangles.
    pub triangles: usize,
}

#[derive(Clone, Debug, Serialize)]
/// Mass properties of the solid (uniform density).
pub struct SolidSummary {
    /// Volume of the solid (input units³).
    pub volume: f64,
    /// Centre of mass G (input units).
    pub center_of_mass: Point3,
    /// Principal moments of inertia about G.
    pub principal_moments: [f64; 3],
    /// Surface area of the mesh (input units²).
    pub area: f64,
}

#[derive(Clone, Debug, Serialize)]
/// Size and measures of the convex hull.
pub struct HullSummary {
    /// Number of hull facets (after the coplanar merge).
    pub facets: usize,
    /// Number of hull edges.
    pub edges: usize,
    /// Number of hull vertices.
    pub vertices: usize,
    /// Hull triangles before the coplanar merge.
    pub triangles: usize,
    /// Absolute coplanarity tolerance used (input units).
    pub coplanar_tol: f64,
    /// Volume of the hull (input units³).
    pub volume: f64,
    /// Surface area of the hull (input units²).
    pub area: f64,
}

#[derive(Clone, Debug, Serialize)]
/// Counts and extremes of the micro-equilibria.
pub struct MicroSummary {
    /// Number of stable micro-equilibria (S).
    pub stable: usize,
    /// Number of unstable micro-equilibria (U).
    pub unstable: usize,
    /// Number of saddle micro-equilibria (H).
    pub saddle: usize,
    /// R_min: smallest distance from G to a stable equilibrium (input units).
    pub r_min: f64,
    /// R_max: largest distance from G to a hull vertex (input units).
    pub r_max: f64,
    /// Number of predicate signs decided by the symbolic perturbation (0 for generic input).
    pub degenerate_decisions: usize,
}

#[derive(Clone, Debug, Serialize)]
/// Macro-equilibrium counts at the chosen ν.
pub struct MacroSummary {
    /// Resolution ν at which the flocks are counted.
    pub nu: f64,
    /// Where ν came from (user, plateau, …).
    pub nu_source: NuSource,
    /// Number of stable flocks.
    pub stable: usize,
    /// Number of unstable flocks.
    pub unstable: usize,
    /// Number of saddle flocks.
    pub saddle: usize,
}

/// A stable micro-equilibrium inside an unstable or saddle flock (paper §1.1, §4.1).
#[derive(Clone, Debug, Serialize)]
pub struct RockingEquilibrium {
    /// Index into `equilibria`.
    pub index: usize,
    /// Hull facet the stone rests on.
    pub facet: u32,
    /// Foot point of the equilibrium on the facet.
    pub point: Point3,
    /// Distance from G to the equilibrium (input units).
    pub r: f64,
    /// Distance from G divided by the largest equilibrium distance `r_max`.
    pub r_normalised: f64,
    /// Index of the flock containing it.
    pub flock: usize,
    /// Type of that flock (unstable or saddle).
    pub flock_type: Kind,
    /// Its facet has a corner on an open scan's hidden base ([`HiddenBase::dependent`]);
    /// written only when true.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub hidden_base: bool,
}

/// One micro-equilibrium with its flock at the report's ν.
#[derive(Clone, Debug, Serialize)]
pub struct MicroEquilibrium {
    /// Index into the equilibria list.
    pub index: usize,
    /// Stable, saddle or unstable.
    pub kind: Kind,
    /// Hull facet, edge or vertex where it lies.
    pub site: Site,
    /// Position of the equilibrium point (input units).
    pub point: Point3,
    /// Distance from G to the equilibrium (input units).
    pub r: f64,
    /// Index of its flock at the report's ν.
    pub flock: usize,
    /// Its site has a corner on an open scan's hidden base ([`HiddenBase::dependent`]); written
    /// only when true.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub hidden_base: bool,
}

/// A stable facet as another engine or an experiment needs it: which way it faces and how often
/// the quasi-static theory rests on it, so that their outcomes can be mapped onto it.
#[derive(Clone, Debug, Serialize)]
pub struct StableFacet {
    /// Hull facet index.
    pub facet: u32,
    /// Its stable micro-equilibrium (index into `equilibria`).
    pub equilibrium: usize,
    /// Outward unit normal (mesh frame): the stone rests on the facet when this points down.
    pub normal: crate::Vec3,
    /// Distance from G to the facet's plane (input units).
    pub r: f64,
    /// Quasi-static resting probability: the facet's basin area on the sphere of down
    /// directions / 4π ([`crate::basins::basin_probabilities`]).
    pub basin_probability: f64,
    /// Flock at the macro ν.
    pub flock: usize,
    /// The facet has a corner on an open scan's hidden base; written only when true.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub hidden_base: bool,
}

/// Everything a run of `rocking analyze` says about one stone.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// Name of the analysed mesh file.
    pub file: String,
    /// Repairs applied to the input mesh.
    pub repairs: Repairs,
    /// For an open scan: what was found and closed, and how many micro-equilibria depend on the
    /// hidden base (absent for a closed stone).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub open_scan: Option<OpenScanReport>,
    /// Size of the input mesh.
    pub mesh: MeshSummary,
    /// Mass properties of the solid.
    pub solid: SolidSummary,
    /// Size and measures of the convex hull.
    pub hull: HullSummary,
    /// Micro-equilibrium counts.
    pub micro: MicroSummary,
    /// Shape descriptors (axis ratios, Zingg class).
    pub shape: ShapeDescriptors,
    /// Macro-equilibrium (flock) counts at ν.
    pub r#macro: MacroSummary,
    /// Plateau of the count staircase from which ν was chosen, if any.
    pub plateau: Option<Plateau>,
    /// Flocks of equilibria at ν.
    pub flocks: Vec<Flock>,
    /// Stable micro-equilibria inside unstable or saddle flocks.
    pub rocking: Vec<RockingEquilibrium>,
    /// Staircase of flock counts against ν.
    pub staircase: Vec<Step>,
    /// Every micro-equilibrium with its flock.
    pub equilibria: Vec<MicroEquilibrium>,
    /// Every stable facet with its outward normal and quasi-static basin probability (empty in a
    /// report made without the basins, [`Analysis::report_without_basins`]).
    pub stable_facets: Vec<StableFacet>,
}

impl Report {
    /// Macro counts as a [`Counts`].
    pub fn macro_counts(&self) -> Counts {
        Counts { stable: self.r#macro.stable, unstable: self.r#macro.unstable, saddle: self.r#macro.saddle }
    }
}

/// Largest accepted relative coplanarity tolerance: beyond it merged facets bend visibly and
/// the micro scale the analysis is about is erased.
pub const MAX_COPLANAR_TOL: f64 = 1e-3;

/// Largest accepted relative degeneracy tolerance of the equilibrium predicates.
pub const MAX_DEGENERACY_TOL: f64 = 1e-3;

impl Options {
    /// Refuse tolerances that are not finite, not positive or too large (see [`check_coplanar_tol`])
    /// and a ν outside (0, 1], each with its own message.
    pub fn check(&self) -> Result<()> {
        check_coplanar_tol(self.coplanar_tol)?;
        check_tolerance("degeneracy_tol", self.degeneracy_tol, MAX_DEGENERACY_TOL)?;
        if let Some(nu) = self.nu {
            check_nu(nu)?;
        }
        Ok(())
    }
}

/// Refuse a relative coplanarity tolerance that is not in (0, [`MAX_COPLANAR_TOL`]].
pub fn check_coplanar_tol(tol: f64) -> Result<f64> {
    check_tolerance("coplanar_tol", tol, MAX_COPLANAR_TOL)
}

fn check_tolerance(name: &str, tol: f64, max: f64) -> Result<f64> {
    if tol.is_finite() && tol > 0.0 && tol <= max {
        Ok(tol)
    } else {
        Err(Error::parameter(name, tol, format!("a finite number in (0, {max:e}] (relative to the stone's size)")))
    }
}

/// G must lie inside the hull by more than the degeneracy tolerance τ = `tol_rel` × diameter of
/// every facet plane; otherwise no micro-equilibrium set exists (the stone could not rest) and
/// [`Error::CentreOutsideHull`] says by how much and at which facet. `g_input` is G in input
/// units, for the message.
fn centre_inside(hull: &Polyhedron, g: &Point3, tol_rel: f64, g_input: &Point3) -> Result<()> {
    let tau = tol_rel * hull.diameter;
    let worst = hull
        .facets
        .iter()
        .enumerate()
        .map(|(i, f)| (i, f.offset - f.normal.dot(&g.coords)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    match worst {
        Some((f, depth)) if !(depth > tau) => {
            let what = if depth < 0.0 {
                format!(
                    "{:.3e} of the stone's size beyond the plane of hull facet {f}; the surface does not bound a solid (it may intersect itself) or the given G is wrong",
                    -depth / hull.diameter
                )
            } else {
                format!("on the hull's surface, within {:.0e} of its size of hull facet {f}'s plane", tol_rel)
            };
            Err(Error::CentreOutsideHull { path: crate::error::MEMORY.into(), g: g_input.coords.into(), what })
        }
        _ => Ok(()),
    }
}

/// Refuse a ν outside (0, 1].
pub fn check_nu(nu: f64) -> Result<f64> {
    if nu.is_finite() && nu > 0.0 && nu <= 1.0 {
        Ok(nu)
    } else {
        Err(Error::parameter("nu", nu, "in (0, 1]"))
    }
}
