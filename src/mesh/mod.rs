//! Triangle meshes of scanned stones: reading and writing ([`io`]), welding, and the checks that
//! make a triangle soup into the boundary of a solid (closed, manifold, consistently oriented).

pub mod base;
pub mod boundary;
pub mod cut;
pub mod intersect;
pub mod io;
pub mod open_scan;
pub mod plane;
pub mod polygon;
pub mod unit;

pub use base::{BaseClosing, BasePoint, ClosedScan};
pub use boundary::{boundary_loops, BoundaryLoop};
pub use cut::{cut_base, cut_open, stand_on};
pub use open_scan::{OpenScan, OpenScanSummary, Opening, RimChoice, Scan};
pub use plane::Plane;

use crate::{Error, Point3, Result, Vec3};
use std::collections::HashMap;

/// An indexed triangle mesh in f64. Triangles are counter-clockwise seen from outside once
/// [`TriMesh::into_solid_boundary`] has accepted them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub vertices: Vec<Point3>,
    /// Triangles as triples of vertex indices.
    pub triangles: Vec<[u32; 3]>,
}

/// What [`TriMesh::into_solid_boundary`] changed to make the mesh usable, for the report.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Repairs {
    /// Vertices merged into an earlier vertex at exactly the same position.
    pub welded_vertices: usize,
    /// Vertices referenced by no triangle (dropped: they are not part of the stone).
    pub unreferenced_vertices: usize,
    /// Triangles with a repeated vertex after welding (zero area, dropped).
    pub degenerate_triangles: usize,
    /// The whole surface was oriented inwards (negative volume) and was flipped.
    pub flipped: bool,
    /// Pairs of triangles that cross each other, all shallower than
    /// [`SHALLOW_CROSSING_DEPTH`] × the size and no more than [`SHALLOW_CROSSING_PAIRS`] × the
    /// number of triangles (hair-thin overlaps of decimated or stitched scans): accepted as they
    /// are, and said. Deeper or more numerous crossings are refused.
    pub shallow_crossings: usize,
    /// The deepest of those crossings ([`intersect::depth`]) divided by the bounding-box diagonal;
    /// 0 without crossings.
    pub crossing_depth: f64,
}

/// Self-intersections deeper ([`intersect::depth`]) than this fraction of the bounding-box
/// diagonal are refused ([`Error::SelfIntersecting`]); shallower ones are accepted and counted in
/// [`Repairs`]. Of the 39 scans of `data/meshes` three cross themselves: Arrokoth 1.4·10⁻³ and Phobos
/// 2.6·10⁻⁴ of their size deep (seams), the 500-facet decimation of stone A0 1.4·10⁻² (a fold of
/// a fifth of a facet). A vertex pulled through the body or a coordinate read from the wrong
/// column crosses by a sizeable fraction of the size.
pub const SHALLOW_CROSSING_DEPTH: f64 = 2e-2;

/// At most this fraction of the triangles may be involved in accepted crossings (counted as
/// pairs): local defects are few (16 pairs in the 32 070 triangles of Phobos, 3 in the 500 of a 500-facet decimation), while a surface read
/// with the wrong coordinate columns crosses itself everywhere (5802 pairs in 11 918).
pub const SHALLOW_CROSSING_PAIRS: f64 = 1e-2;

/// x · 2^k, exact unless the result leaves the normal range of f64 (computed in steps so that
/// 2^k itself never overflows).
pub fn ldexp(mut x: f64, mut k: i32) -> f64 {
    let pow2 = |e: i32| f64::from_bits(((e + 1023) as u64) << 52);
    while k > 1000 {
        x *= pow2(1000);
        k -= 1000;
    }
    while k < -1000 {
        x *= pow2(-1000);
        k += 1000;
    }
    x * pow2(k)
}

/// A point with every coordinate multiplied by 2^k ([`ldexp`]).
pub fn scale_point(p: &Point3, k: i32) -> Point3 {
    p.map(|x| ldexp(x, k))
}

/// The binary exponent e of a positive finite x: x = f · 2^e with f in [0.5, 1).
fn exponent(x: f64) -> i32 {
    if x < f64::MIN_POSITIVE {
        return exponent(x * ldexp(1.0, 600)) - 600;
    }
    ((x.to_bits() >> 52) & 0x7ff) as i32 - 1022
}

impl TriMesh {
    /// A mesh from vertices and triangles, unchecked.
    pub fn new(vertices: Vec<Point3>, triangles: Vec<[u32; 3]>) -> Self {
        TriMesh { vertices, triangles }
    }

    /// Axis-aligned bounding box `(min, max)` of the vertices; `None` when empty.
    pub fn bounding_box(&self) -> Option<(Point3, Point3)> {
        let first = *self.vertices.first()?;
        Some(self.vertices.iter().fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p))))
    }

    /// Length of the bounding-box diagonal: the length scale of every tolerance.
    pub fn diameter(&self) -> f64 {
        self.bounding_box().map_or(0.0, |(lo, hi)| (hi - lo).norm())
    }

    /// Signed volume by the divergence theorem (positive for outward orientation).
    pub fn signed_volume(&self) -> f64 {
        let o = self.vertices.first().map_or(Vec3::zeros(), |p| p.coords);
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i as usize].coords - o);
                a.dot(&b.cross(&c))
            })
            .sum::<f64>()
            / 6.0
    }

    /// Surface area.
    pub fn area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i as usize]);
                (b - a).cross(&(c - a)).norm() / 2.0
            })
            .sum()
    }

    /// The exponent k such that the mesh scaled by 2^k ([`TriMesh::scaled_pow2`]) has its largest
    /// bounding-box extent in [1, 2): the normalisation every computation runs in. Scaling by a
    /// power of two is exact in f64 (away from the subnormal range), so results scaled back by 2^−k
    /// are bit for bit those of the unscaled arithmetic whenever that did not overflow or
    /// underflow. The extent is formed from halved coordinates, so it never overflows; 0 for a
    /// mesh without extent or without vertices.
    pub fn unit_exponent(&self) -> i32 {
        let Some((lo, hi)) = self.bounding_box() else { return 0 };
        let half = (0..3).map(|i| hi[i] * 0.5 - lo[i] * 0.5).fold(0.0, f64::max);
        if !(half > 0.0 && half.is_finite()) {
            return 0;
        }
        -exponent(half)
    }

    /// This mesh with every coordinate multiplied by 2^k (exact, see [`ldexp`]).
    pub fn scaled_pow2(&self, k: i32) -> TriMesh {
        TriMesh {
            vertices: self.vertices.iter().map(|p| scale_point(p, k)).collect(),
            triangles: self.triangles.clone(),
        }
    }

    /// Rigid motion and uniform scaling `x ↦ s·R·x + t`, for invariance checks and generators.
    pub fn transformed(&self, rotation: &nalgebra::Rotation3<f64>, scale: f64, t: &Vec3) -> Self {
        TriMesh {
            vertices: self.vertices.iter().map(|p| Point3::from(rotation * p.coords * scale + t)).collect(),
            triangles: self.triangles.clone(),
        }
    }

    /// Weld exactly coincident vertices (bitwise equal coordinates, −0 = +0) and drop vertices no
    /// triangle uses. Returns (welded, unreferenced).
    pub fn weld(&mut self) -> (usize, usize) {
        let key = |p: &Point3| p.coords.map(|x| if x == 0.0 { 0u64 } else { x.to_bits() });
        let mut first: HashMap<[u64; 3], u32> = HashMap::with_capacity(self.vertices.len());
        let mut remap = Vec::with_capacity(self.vertices.len());
        let mut welded = 0;
        for (i, p) in self.vertices.iter().enumerate() {
            let k = key(p);
            let j = *first.entry([k.x, k.y, k.z]).or_insert(i as u32);
            welded += usize::from(j != i as u32);
            remap.push(j);
        }
        for t in &mut self.triangles {
            *t = t.map(|i| remap[i as usize]);
        }
        // Compact: keep referenced vertices only, in their original order.
        let mut used = vec![false; self.vertices.len()];
        self.triangles.iter().flatten().for_each(|&i| used[i as usize] = true);
        let mut new_index = vec![u32::MAX; self.vertices.len()];
        let mut kept = Vec::new();
        for (i, p) in self.vertices.iter().enumerate() {
            if used[i] {
                new_index[i] = kept.len() as u32;
                kept.push(*p);
            }
        }
        let unreferenced = self.vertices.len() - kept.len() - welded;
        self.vertices = kept;
        for t in &mut self.triangles {
            *t = t.map(|i| new_index[i as usize]);
        }
        (welded, unreferenced)
    }

    /// Make this mesh the boundary of a solid or say precisely why it is not one.
    ///
    /// Checks, in order: non-empty; finite coordinates; indices in range; after welding and
    /// dropping zero-area (repeated-index) triangles: no two triangles on the same three vertices,
    /// every edge shared by exactly two triangles (edge-manifold, closed), traversed in opposite
    /// directions (consistently oriented), every vertex a single fan (vertex-manifold), one
    /// connected shell, non-zero volume, and no two triangles crossing each other deeper than
    /// [`SHALLOW_CROSSING_DEPTH`] of the size (nor more pairs than [`SHALLOW_CROSSING_PAIRS`] of
    /// the triangles) ([`intersect::find_self_intersection`], exact;
    /// [`Error::SelfIntersecting`] names the deepest pair by their numbers in the input; shallow
    /// crossings are counted in [`Repairs`]). Volume and crossings are evaluated on the mesh
    /// scaled by 2^[`TriMesh::unit_exponent`], so that any finite coordinates work. A surface that
    /// is consistently oriented *inwards* (negative volume) is flipped and reported in [`Repairs`].
    pub fn into_solid_boundary(self) -> Result<(TriMesh, Repairs)> {
        let (mesh, rep, original) = self.prepared()?;
        mesh.solid_checks(rep, &original)
    }

    /// Read a scan: a closed surface as [`TriMesh::into_solid_boundary`] does (the same checks,
    /// messages and result), an open one (with edges of one triangle, none of three or more) as
    /// an [`OpenScan`] whose rim is chosen by `rim` ([`OpenScan::from_prepared`]).
    pub fn into_scan(self, rim: &RimChoice) -> Result<Scan> {
        let (mesh, rep, original) = self.prepared()?;
        let (mut open, mut fans) = (false, false);
        for &(f, b) in mesh.edge_uses().values() {
            open |= f + b == 1;
            fans |= f + b > 2;
        }
        if open && !fans {
            Ok(Scan::Open(Box::new(OpenScan::from_prepared(mesh, rep, &original, rim)?)))
        } else {
            let (mesh, rep) = mesh.solid_checks(rep, &original)?;
            Ok(Scan::Closed(mesh, rep))
        }
    }

    /// What every reading shares, closed stone or open scan: non-empty, finite, indices in range;
    /// welded; zero-area (repeated-index) triangles dropped; no duplicate triangles. Returns the
    /// mesh, its repairs so far and the input number of every kept triangle (for messages).
    fn prepared(mut self) -> Result<(TriMesh, Repairs, Vec<usize>)> {
        if self.vertices.is_empty() || self.triangles.is_empty() {
            return Err(Error::invalid(format!(
                "empty mesh ({} vertices, {} triangles)",
                self.vertices.len(),
                self.triangles.len()
            )));
        }
        if let Some((i, p)) = self.vertices.iter().enumerate().find(|(_, p)| !p.coords.iter().all(|x| x.is_finite())) {
            return Err(Error::invalid(format!("vertex {i} has a non-finite coordinate ({}, {}, {})", p.x, p.y, p.z)));
        }
        let n = self.vertices.len() as u32;
        if let Some((k, t)) = self.triangles.iter().enumerate().find(|(_, t)| t.iter().any(|&i| i >= n)) {
            return Err(Error::invalid(format!("triangle {k} refers to vertex {t:?} but there are only {n} vertices")));
        }
        let mut rep = Repairs::default();
        (rep.welded_vertices, rep.unreferenced_vertices) = self.weld();
        let before = self.triangles.len();
        // Numbers of the kept triangles in the input, for messages.
        let original: Vec<usize> = (0..before)
            .filter(|&k| {
                let t = self.triangles[k];
                t[0] != t[1] && t[1] != t[2] && t[2] != t[0]
            })
            .collect();
        self.triangles.retain(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0]);
        rep.degenerate_triangles = before - self.triangles.len();
        if self.triangles.is_empty() {
            return Err(Error::invalid("every triangle is degenerate (repeated vertices)"));
        }
        self.check_duplicates(&original)?;
        Ok((self, rep, original))
    }

    /// The checks of a closed solid after [`TriMesh::prepared`] (see
    /// [`TriMesh::into_solid_boundary`]).
    fn solid_checks(mut self, mut rep: Repairs, original: &[usize]) -> Result<(TriMesh, Repairs)> {
        self.check_edges()?;
        self.check_vertex_fans()?;
        self.check_single_shell()?;
        // Volume and self-intersections in normalised coordinates (exact power-of-two scaling),
        // so that no product over- or underflows whatever the units.
        let k = self.unit_exponent();
        let unit = self.scaled_pow2(k);
        let v = unit.signed_volume();
        let d = unit.diameter();
        if !(v.abs() > 1e-12 * d * d * d) {
            return Err(Error::degenerate(format!(
                "the surface encloses no volume (|V| = {:.3e} for a size of {:.3e}): flat or collapsed",
                ldexp(v.abs(), -3 * k),
                ldexp(d, -k)
            )));
        }
        unit.check_crossings(k, &mut rep, original)?;
        if v < 0.0 {
            rep.flipped = true;
            self.triangles.iter_mut().for_each(|t| t.swap(1, 2));
        }
        Ok((self, rep))
    }

    /// Self-intersections of this mesh, normalised by 2^`k` ([`TriMesh::unit_exponent`]): shallow
    /// and few ones counted in `rep`, others refused ([`Error::SelfIntersecting`], triangles
    /// named by `original`, their numbers in the input; a triangle past its end is named by its
    /// own number).
    pub(crate) fn check_crossings(&self, k: i32, rep: &mut Repairs, original: &[usize]) -> Result<()> {
        let d = self.diameter();
        let Some(c) = intersect::find_self_intersection(&self.vertices, &self.triangles) else { return Ok(()) };
        let few = c.pairs as f64 <= SHALLOW_CROSSING_PAIRS * self.triangles.len() as f64;
        if few && c.depth <= SHALLOW_CROSSING_DEPTH * d {
            rep.shallow_crossings = c.pairs;
            rep.crossing_depth = c.depth / d;
            return Ok(());
        }
        let name = |t: usize| original.get(t).copied().unwrap_or(t);
        Err(Error::SelfIntersecting {
            path: crate::error::MEMORY.into(),
            first: name(c.first),
            second: name(c.second),
            pairs: c.pairs,
            depth: ldexp(c.depth, -k),
            relative_depth: c.depth / d,
            near: Some(scale_point(&c.near, -k).coords.into()),
        })
    }

    pub(crate) fn edge_uses(&self) -> HashMap<(u32, u32), (u32, u32)> {
        // undirected edge (lo, hi) -> (uses as lo->hi, uses as hi->lo)
        let mut uses: HashMap<(u32, u32), (u32, u32)> = HashMap::with_capacity(self.triangles.len() * 3 / 2);
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let e = uses.entry((a.min(b), a.max(b))).or_default();
                if a < b {
                    e.0 += 1
                } else {
                    e.1 += 1
                }
            }
        }
        uses
    }

    /// Two triangles on the same three vertices (in either orientation) are a duplicate, not a
    /// surface; `original` gives the input number of each triangle.
    fn check_duplicates(&self, original: &[usize]) -> Result<()> {
        let mut seen: HashMap<[u32; 3], usize> = HashMap::with_capacity(self.triangles.len());
        for (k, t) in self.triangles.iter().enumerate() {
            let mut key = *t;
            key.sort_unstable();
            if let Some(&first) = seen.get(&key) {
                let same = self.triangles[first] == *t
                    || self.triangles[first] == [t[1], t[2], t[0]]
                    || self.triangles[first] == [t[2], t[0], t[1]];
                let p = key.map(|i| self.vertices[i as usize]);
                return Err(Error::invalid(format!(
                    "duplicate triangle: triangles {} and {} join the same three vertices ({}, {}, {}), ({}, {}, {}), ({}, {}, {}){}",
                    original[first],
                    original[k],
                    p[0].x,
                    p[0].y,
                    p[0].z,
                    p[1].x,
                    p[1].y,
                    p[1].z,
                    p[2].x,
                    p[2].y,
                    p[2].z,
                    if same { "" } else { " with opposite orientations" }
                )));
            }
            seen.insert(key, k);
        }
        Ok(())
    }

    fn check_edges(&self) -> Result<()> {
        let uses = self.edge_uses();
        let (mut open, mut nonmanifold, mut misoriented) = (vec![], vec![], vec![]);
        for (&e, &(f, b)) in &uses {
            match f + b {
                1 => open.push(e),
                2 if f != 1 => misoriented.push(e),
                2 => {}
                _ => nonmanifold.push(e),
            }
        }
        let at = |list: &mut Vec<(u32, u32)>| {
            list.sort_unstable();
            let (a, b) = list[0];
            let (pa, pb) = (self.vertices[a as usize], self.vertices[b as usize]);
            format!("e.g. the edge from ({}, {}, {}) to ({}, {}, {})", pa.x, pa.y, pa.z, pb.x, pb.y, pb.z)
        };
        // Edges with three or more triangles first: a fin or flap attached to the surface also
        // leaves open edges, but the extra triangles are the cause.
        if !nonmanifold.is_empty() {
            let also_open = if open.is_empty() {
                String::new()
            } else {
                format!(
                    "; {} other edge(s) belong to only one triangle, as along a fin sticking out of the surface",
                    open.len()
                )
            };
            return Err(Error::invalid(format!(
                "non-manifold: {} edge(s) are shared by more than two triangles ({}){also_open}",
                nonmanifold.len(),
                at(&mut nonmanifold)
            )));
        }
        if !open.is_empty() {
            return Err(Error::invalid(format!(
                "the surface is open: {} edge(s) belong to only one triangle ({}); a stone must be a closed surface",
                open.len(),
                at(&mut open)
            )));
        }
        if !misoriented.is_empty() {
            return Err(Error::invalid(format!(
                "inconsistent orientation: {} edge(s) are traversed in the same direction by both of their triangles ({}); some triangles are flipped relative to their neighbours",
                misoriented.len(),
                at(&mut misoriented)
            )));
        }
        Ok(())
    }

    /// Every vertex must be surrounded by a single cycle of triangles (no "bow-tie" vertices).
    fn check_vertex_fans(&self) -> Result<()> {
        // For vertex v, each triangle (v, a, b) gives a link edge a -> b; the link must be one cycle.
        let nv = self.vertices.len();
        let mut start = vec![0usize; nv + 1];
        self.triangles.iter().flatten().for_each(|&i| start[i as usize + 1] += 1);
        for i in 0..nv {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut link = vec![(0u32, 0u32); start[nv]];
        for t in &self.triangles {
            for k in 0..3 {
                let v = t[k] as usize;
                link[fill[v]] = (t[(k + 1) % 3], t[(k + 2) % 3]);
                fill[v] += 1;
            }
        }
        for v in 0..nv {
            let edges = &link[start[v]..start[v + 1]];
            let next: HashMap<u32, u32> = edges.iter().copied().collect();
            let (first, _) = edges[0];
            let (mut cur, mut steps) = (first, 0);
            loop {
                cur = next[&cur]; // closed & oriented: every link vertex has a successor
                steps += 1;
                if cur == first || steps > edges.len() {
                    break;
                }
            }
            if steps != edges.len() {
                let p = self.vertices[v];
                return Err(Error::invalid(format!(
                    "non-manifold vertex at ({}, {}, {}): two or more separate fans of triangles meet there",
                    p.x, p.y, p.z
                )));
            }
        }
        Ok(())
    }

    fn check_single_shell(&self) -> Result<()> {
        let shells = self.pieces();
        if shells > 1 {
            return Err(Error::invalid(format!(
                "the mesh has {shells} separate closed shells; a stone must be a single closed surface"
            )));
        }
        Ok(())
    }

    /// Number of connected pieces (triangles joined through shared vertices; every vertex is
    /// assumed used by a triangle).
    pub(crate) fn pieces(&self) -> usize {
        self.piece_labels().iter().enumerate().filter(|&(i, &p)| p as usize == i).count()
    }

    /// For every vertex, the piece it belongs to (triangles joined through shared vertices), named
    /// by one of its vertices (union–find).
    pub(crate) fn piece_labels(&self) -> Vec<u32> {
        let mut parent: Vec<u32> = (0..self.vertices.len() as u32).collect();
        fn find(p: &mut [u32], mut x: u32) -> u32 {
            while p[x as usize] != x {
                p[x as usize] = p[p[x as usize] as usize];
                x = p[x as usize];
            }
            x
        }
        for t in &self.triangles {
            for k in 0..2 {
                let (a, b) = (find(&mut parent, t[k]), find(&mut parent, t[k + 1]));
                parent[a as usize] = b;
            }
        }
        (0..self.vertices.len() as u32).map(|i| find(&mut parent, i)).collect()
    }
}
