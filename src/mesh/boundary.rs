//! Boundary loops of a welded triangle mesh: the edges used by exactly one triangle, chained
//! into closed loops.
//!
//! A surface with boundary is a 2-manifold with boundary when every edge is used by one or two
//! triangles, an edge of two triangles is traversed in opposite directions by them (consistent
//! orientation), and the triangles around every vertex form one fan: a closed cycle for an
//! interior vertex, one open fan for a vertex on the boundary. Then every boundary vertex has
//! exactly one outgoing and one incoming boundary edge, and the boundary edges, directed as their
//! one triangle traverses them, chain into disjoint closed loops. Each loop is reported in that
//! direction: for a surface oriented outwards (counter-clockwise seen from outside) a loop runs
//! counter-clockwise seen from the side the surface lies on, i.e. its vector area
//! ½ Σ pᵢ × pᵢ₊₁ points *into* the solid that a patch over the hole would close, and the patch's
//! triangles traverse each loop edge backwards.
//!
//! What is not such a surface is refused with [`Error::InvalidMesh`] naming the place: an edge
//! of three or more triangles, an edge traversed twice in the same direction, a vertex where two
//! fans of triangles meet (on two loops, or one loop passing through it twice).

use super::TriMesh;
use crate::{Error, Result};
use std::collections::HashMap;

/// One closed boundary loop: vertex indices, in the direction the mesh's triangles traverse its
/// edges (module docs); the last vertex joins the first.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BoundaryLoop {
    /// The loop's vertices in order (each once).
    pub vertices: Vec<u32>,
}

impl BoundaryLoop {
    /// The loop's points.
    pub fn points(&self, mesh: &TriMesh) -> Vec<crate::Point3> {
        self.vertices.iter().map(|&i| mesh.vertices[i as usize]).collect()
    }

    /// Number of edges (= vertices).
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    /// A loop has at least three vertices; this is never true for a loop found here.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }
}

/// The boundary loops of a welded mesh without zero-area triangles (module docs), ordered by
/// their smallest vertex index, each starting at it. Empty for a closed surface. Refuses a
/// surface that is not a 2-manifold with boundary or not consistently oriented.
pub fn boundary_loops(mesh: &TriMesh) -> Result<Vec<BoundaryLoop>> {
    let uses = mesh.edge_uses();
    let point = |i: u32| {
        let p = mesh.vertices[i as usize];
        format!("({}, {}, {})", p.x, p.y, p.z)
    };
    let mut worst: Option<((u32, u32), &str)> = None;
    for (&e, &(f, b)) in &uses {
        let problem = match f + b {
            n if n > 2 => "shared by more than two triangles",
            2 if f != 1 => "traversed in the same direction by both of its triangles (inconsistent orientation)",
            _ => continue,
        };
        // Deterministic report: the smallest such edge, three-triangle edges first.
        let key = (problem.starts_with("shared"), std::cmp::Reverse(e));
        if worst.is_none_or(|(w, p)| key > (p.starts_with("shared"), std::cmp::Reverse(w))) {
            worst = Some((e, problem));
        }
    }
    if let Some(((a, b), problem)) = worst {
        return Err(Error::invalid(format!("non-manifold: the edge from {} to {} is {problem}", point(a), point(b))));
    }
    check_fans(mesh, &point)?;
    // Boundary edges, directed as their one triangle runs them.
    let mut next: HashMap<u32, u32> = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if uses.get(&(a.min(b), a.max(b))).is_some_and(|&(f, r)| f + r == 1) && next.insert(a, b).is_some() {
                return Err(Error::invalid(format!(
                    "non-manifold boundary: the vertex at {} lies on two boundary loops (or one loop passes through it twice)",
                    point(a)
                )));
            }
        }
    }
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort_unstable();
    let mut seen: HashMap<u32, ()> = HashMap::with_capacity(next.len());
    let mut loops = Vec::new();
    for s in starts {
        if seen.contains_key(&s) {
            continue;
        }
        let mut vertices = vec![s];
        seen.insert(s, ());
        let mut cur = s;
        loop {
            // Every boundary vertex has one outgoing edge (above) and, its fan being one, one
            // incoming edge: the walk returns to its start.
            let Some(&n) = next.get(&cur) else {
                return Err(Error::check(format!("boundary loop from {} does not close", point(s))));
            };
            if n == s {
                break;
            }
            if seen.insert(n, ()).is_some() {
                return Err(Error::check(format!("boundary loop from {} runs into another", point(s))));
            }
            vertices.push(n);
            cur = n;
        }
        loops.push(BoundaryLoop { vertices });
    }
    Ok(loops)
}

/// Every vertex is surrounded by one fan of triangles: its link (the edge a → b of every triangle
/// (v, a, b)) is one cycle or one path. Consistent orientation, checked before, makes each link
/// vertex's successor and predecessor unique, so the link is a union of disjoint paths and
/// cycles, and one component is what is left to check.
fn check_fans(mesh: &TriMesh, point: &dyn Fn(u32) -> String) -> Result<()> {
    let nv = mesh.vertices.len();
    let mut start = vec![0usize; nv + 1];
    mesh.triangles.iter().flatten().for_each(|&i| start[i as usize + 1] += 1);
    for i in 0..nv {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut link = vec![(0u32, 0u32); start[nv]];
    for t in &mesh.triangles {
        for k in 0..3 {
            let v = t[k] as usize;
            link[fill[v]] = (t[(k + 1) % 3], t[(k + 2) % 3]);
            fill[v] += 1;
        }
    }
    for v in 0..nv {
        let edges = &link[start[v]..start[v + 1]];
        if edges.is_empty() {
            continue;
        }
        let next: HashMap<u32, u32> = edges.iter().copied().collect();
        let has_pred: std::collections::HashSet<u32> = edges.iter().map(|e| e.1).collect();
        let path_start = edges.iter().map(|e| e.0).find(|a| !has_pred.contains(a));
        let first = path_start.unwrap_or(edges[0].0);
        let (mut cur, mut steps) = (first, 0);
        while let Some(&n) = next.get(&cur) {
            steps += 1;
            cur = n;
            if cur == first || steps > edges.len() {
                break;
            }
        }
        if steps != edges.len() {
            return Err(Error::invalid(match path_start {
                Some(_) => format!(
                    "non-manifold boundary: the vertex at {} joins separate fans of triangles: it lies on two boundary loops (or one loop passes through it twice)",
                    point(v as u32)
                ),
                None => format!(
                    "non-manifold vertex at {}: two or more separate fans of triangles meet there",
                    point(v as u32)
                ),
            }));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Point3;

    /// A 3 × 3 grid of vertices, 8 triangles, counter-clockwise seen from +z.
    fn square() -> TriMesh {
        let v = (0..9).map(|i| Point3::new((i % 3) as f64, (i / 3) as f64, 0.0)).collect();
        let mut t = vec![];
        for y in 0..2u32 {
            for x in 0..2u32 {
                let a = y * 3 + x;
                t.push([a, a + 1, a + 4]);
                t.push([a, a + 4, a + 3]);
            }
        }
        TriMesh::new(v, t)
    }

    #[test]
    fn a_square_patch_has_one_loop_counter_clockwise_seen_from_its_front() {
        let loops = boundary_loops(&square()).unwrap();
        assert_eq!(loops.len(), 1);
        assert_eq!(loops[0].vertices, vec![0, 1, 2, 5, 8, 7, 6, 3]);
    }

    #[test]
    fn a_bow_tie_boundary_vertex_is_refused() {
        // Two triangles touching at one vertex only.
        let v = vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(-1.0, 0.0, 0.0),
            Point3::new(-1.0, -1.0, 0.0),
        ];
        let e = boundary_loops(&TriMesh::new(v, vec![[0, 1, 2], [0, 3, 4]])).unwrap_err().to_string();
        assert!(
            e.contains("non-manifold boundary: the vertex at (0, 0, 0)") && e.contains("two boundary loops"),
            "{e}"
        );
    }

    #[test]
    fn three_triangles_on_an_edge_and_a_flipped_triangle_are_refused() {
        let mut m = square();
        m.vertices.push(Point3::new(0.5, 0.5, 1.0));
        m.triangles.push([0, 4, 9]);
        let e = boundary_loops(&m).unwrap_err().to_string();
        assert!(e.contains("non-manifold: the edge from (0, 0, 0) to (1, 1, 0) is shared by more than two"), "{e}");
        let mut m = square();
        m.triangles[1] = [0, 3, 4];
        let e = boundary_loops(&m).unwrap_err().to_string();
        assert!(e.contains("inconsistent orientation"), "{e}");
    }
}
