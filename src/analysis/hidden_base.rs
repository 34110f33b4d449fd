//! An open scan's hidden base in the static analysis: what was closed, and which
//! micro-equilibria depend on it.
//!
//! A micro-equilibrium depends on the hidden base when its site on the hull — the stable
//! facet, the saddle edge, the unstable vertex — has a corner on the base: a rim vertex or an
//! interior point of the surface that closed the rim ([`ClosedScan::on_base`]). Another base
//! (one that bulges, or is recessed) moves or removes exactly these; the others are the scan's
//! own, as long as the base stays within the hull they span.

use crate::equilibria::{Equilibria, Kind, Site};
use crate::hull::Polyhedron;
use crate::mesh::{ClosedScan, OpenScanSummary};
use serde::Serialize;

/// The base an open scan was closed with, for the analysis and its report.
#[derive(Clone, Debug)]
pub struct HiddenBase {
    /// What was found in the scan (rim, gaps closed).
    pub scan: OpenScanSummary,
    /// The base that closed the rim, in words (`flat cap` for the nominal closing).
    pub base: String,
    /// For every vertex of the analysed mesh: whether it belongs to the base.
    pub on_base: Vec<bool>,
    /// Index of the base's first triangle in the analysed mesh: the triangles before it are the
    /// scan's (its gaps' patches included).
    pub first_base_triangle: usize,
}

/// How the nominal closing of an open scan is named in reports.
pub const FLAT_CAP: &str = "flat cap";

impl HiddenBase {
    /// The hidden base of `closed`, found as `scan` says, closed by `base`.
    pub fn of(closed: &ClosedScan, scan: OpenScanSummary, base: &str) -> HiddenBase {
        HiddenBase {
            scan,
            base: base.to_string(),
            on_base: closed.on_base.clone(),
            first_base_triangle: closed.first_base_triangle,
        }
    }

    /// For every micro-equilibrium of `eq` (on `hull`, whose corners come from the analysed
    /// mesh's vertices): whether its site has a corner on the base (module docs).
    pub fn dependent(&self, hull: &Polyhedron, eq: &Equilibria) -> Vec<bool> {
        let on = |corner: u32| {
            hull.source.get(corner as usize).is_some_and(|&v| self.on_base.get(v as usize).copied().unwrap_or(false))
        };
        eq.points
            .iter()
            .map(|p| match p.site {
                Site::Facet(f) => hull.facets[f as usize].vertices.iter().any(|&c| on(c)),
                Site::Edge(e) => hull.edges[e as usize].vertices.iter().any(|&c| on(c)),
                Site::Vertex(v) => on(v),
            })
            .collect()
    }

    /// The report's section: what was found, the base, and how many micro-equilibria of each
    /// kind depend on it (`dependent` from [`HiddenBase::dependent`]).
    pub fn report(&self, eq: &Equilibria, dependent: &[bool]) -> OpenScanReport {
        let count = |k: Kind| eq.points.iter().zip(dependent).filter(|(p, d)| **d && p.kind == k).count();
        OpenScanReport {
            scan: self.scan.clone(),
            base: self.base.clone(),
            on_hidden_base: DependentCounts {
                stable: count(Kind::Stable),
                unstable: count(Kind::Unstable),
                saddle: count(Kind::Saddle),
            },
        }
    }
}

/// Numbers of micro-equilibria that depend on the hidden base.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct DependentCounts {
    /// Stable ones (a hull facet with a corner on the base).
    pub stable: usize,
    /// Unstable ones (a hull vertex on the base).
    pub unstable: usize,
    /// Saddles (a hull edge with an end on the base).
    pub saddle: usize,
}

/// The report's section on an open scan (mesh units).
#[derive(Clone, Debug, Serialize)]
pub struct OpenScanReport {
    /// What was found: the rim, the gaps closed, the flaps trimmed.
    #[serde(flatten)]
    pub scan: OpenScanSummary,
    /// The base that closed the rim.
    pub base: String,
    /// Micro-equilibria whose site touches the base.
    pub on_hidden_base: DependentCounts,
}
