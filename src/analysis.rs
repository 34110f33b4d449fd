//! The static pipeline, mesh → solid → hull → equilibria → Morse–Smale graph → hierarchy →
//! flocks, and [`Report`], the one serialisable result the CLI, plots and experiments read.

use crate::equilibria::{Equilibria, Kind, Signs, Site, DEFAULT_DEGENERACY_TOL};
use crate::hierarchy::{Counts, Flock, Hierarchy, Plateau, Step};
use crate::hull::{Polyhedron, DEFAULT_COPLANAR_TOL};
use crate::mesh::{Repairs, TriMesh};
use crate::morse_smale::{cancellation_hierarchy, MorseSmaleGraph};
use crate::shape::{describe, ShapeDescriptors};
use crate::solid::MassProperties;
use crate::{Error, Point3, Result};
use serde::Serialize;
use std::path::Path;

pub use crate::hierarchy::{NuSource, PAPER_NU};

/// Tolerances and choices of a static analysis.
#[derive(Clone, Debug)]
pub struct Options {
    /// Relative coplanarity tolerance of the facet merge (× bounding-box diagonal).
    pub coplanar_tol: f64,
    /// Relative tolerance of degenerate equilibrium predicates (× hull diameter).
    pub degeneracy_tol: f64,
    /// Fixed ν for the macro scale; `None` = the automatic plateau (or [`PAPER_NU`] if none).
    pub nu: Option<f64>,
}

impl Default for Options {
    fn default() -> Self {
        Options { coplanar_tol: DEFAULT_COPLANAR_TOL, degeneracy_tol: DEFAULT_DEGENERACY_TOL, nu: None }
    }
}

/// Every intermediate object of the static analysis, in memory.
pub struct Analysis {
    pub mesh: TriMesh,
    pub repairs: Repairs,
    pub mass: MassProperties,
    pub hull: Polyhedron,
    pub equilibria: Equilibria,
    pub graph: MorseSmaleGraph,
    pub hierarchy: Hierarchy,
    pub shape: ShapeDescriptors,
    /// The shared signs of the equilibrium predicates (reused by the tracer).
    pub signs: Signs,
}

impl Analysis {
    /// Run the static pipeline on a closed, checked mesh (see [`TriMesh::into_solid_boundary`]).
    pub fn of_solid(mesh: TriMesh, repairs: Repairs, opts: &Options) -> Result<Self> {
        let mass = MassProperties::of(&mesh)?;
        Self::with_center_of_mass(mesh, repairs, mass, opts)
    }

    /// As [`Analysis::of_solid`] but with given mass properties (e.g. a G that is not the
    /// homogeneous solid's, for a stone with a heavy inclusion).
    pub fn with_center_of_mass(mesh: TriMesh, repairs: Repairs, mass: MassProperties, opts: &Options) -> Result<Self> {
        let hull = Polyhedron::new(&mesh.vertices, opts.coplanar_tol)?;
        let g = mass.center_of_mass;
        let signs = Signs::new(&hull, &g, opts.degeneracy_tol);
        let equilibria = Equilibria::from_signs(&hull, &g, &signs)?;
        let graph = MorseSmaleGraph::trace(&hull, &equilibria, &g, &signs)?;
        let hierarchy = cancellation_hierarchy(&equilibria, &graph)?;
        let shape = describe(&mesh, &mass);
        Ok(Analysis { mesh, repairs, mass, hull, equilibria, graph, hierarchy, shape, signs })
    }

    /// Load, check and analyse a mesh file; every error names the file.
    pub fn of_file(path: &Path, opts: &Options) -> Result<Self> {
        let (mesh, repairs) = crate::mesh::io::load_solid(path)?;
        Self::of_solid(mesh, repairs, opts).map_err(|e| e.with_path(path))
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
        let m = self.hierarchy.macro_scale(opts.nu);
        let (nu, nu_source, flocks) = (m.nu, m.source, m.flocks);
        let eq = &self.equilibria;
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
            })
            .collect();
        let macro_counts = m.counts;
        Report {
            file: file.to_string(),
            repairs: self.repairs.clone(),
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
        }
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct MeshSummary {
    pub vertices: usize,
    pub triangles: usize,
}

#[derive(Clone, Debug, Serialize)]
pub struct SolidSummary {
    pub volume: f64,
    pub center_of_mass: Point3,
    pub principal_moments: [f64; 3],
    pub area: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct HullSummary {
    pub facets: usize,
    pub edges: usize,
    pub vertices: usize,
    /// Hull triangles before the coplanar merge.
    pub triangles: usize,
    /// Absolute coplanarity tolerance used (input units).
    pub coplanar_tol: f64,
    pub volume: f64,
    pub area: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct MicroSummary {
    pub stable: usize,
    pub unstable: usize,
    pub saddle: usize,
    pub r_min: f64,
    pub r_max: f64,
    pub degenerate_decisions: usize,
}

#[derive(Clone, Debug, Serialize)]
pub struct MacroSummary {
    pub nu: f64,
    pub nu_source: NuSource,
    pub stable: usize,
    pub unstable: usize,
    pub saddle: usize,
}

/// A stable micro-equilibrium inside an unstable or saddle flock (paper §1.1, §4.1).
#[derive(Clone, Debug, Serialize)]
pub struct RockingEquilibrium {
    /// Index into `equilibria`.
    pub index: usize,
    /// Hull facet the stone rests on.
    pub facet: u32,
    pub point: Point3,
    pub r: f64,
    pub r_normalised: f64,
    pub flock: usize,
    pub flock_type: Kind,
}

/// One micro-equilibrium with its flock at the report's ν.
#[derive(Clone, Debug, Serialize)]
pub struct MicroEquilibrium {
    pub index: usize,
    pub kind: Kind,
    pub site: Site,
    pub point: Point3,
    pub r: f64,
    pub flock: usize,
}

/// Everything a run of `rocking analyze` says about one stone.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub file: String,
    pub repairs: Repairs,
    pub mesh: MeshSummary,
    pub solid: SolidSummary,
    pub hull: HullSummary,
    pub micro: MicroSummary,
    pub shape: ShapeDescriptors,
    pub r#macro: MacroSummary,
    pub plateau: Option<Plateau>,
    pub flocks: Vec<Flock>,
    pub rocking: Vec<RockingEquilibrium>,
    pub staircase: Vec<Step>,
    pub equilibria: Vec<MicroEquilibrium>,
}

impl Report {
    /// Macro counts as a [`Counts`].
    pub fn macro_counts(&self) -> Counts {
        Counts { stable: self.r#macro.stable, unstable: self.r#macro.unstable, saddle: self.r#macro.saddle }
    }
}

/// Refuse a ν outside (0, 1].
pub fn check_nu(nu: f64) -> Result<f64> {
    if nu.is_finite() && nu > 0.0 && nu <= 1.0 {
        Ok(nu)
    } else {
        Err(Error::Usage(format!("ν must be in (0, 1], got {nu}")))
    }
}
