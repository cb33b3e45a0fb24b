//! Following a polyline of mesh vertices through refinement.
//!
//! Catmull-Clark and NURSS number child vertices from parent indices (see
//! [`crate::refine`]): vertex `v` stays `v`, the point of edge `e` is `V + F + e`. A
//! polyline of vertices `v_0, v_1, …` joined by edges therefore becomes
//! `v_0, E(v_0 v_1), v_1, E(v_1 v_2), …` one level down. This is how the middle polygon of a
//! zone is found at any level.

use crate::mesh::Topology;

/// The child polyline of `poly` (vertices of `parent`, consecutive ones joined by edges;
/// the last joined to the first when `closed`), or `None` when two consecutive vertices are
/// not joined by an edge of `parent`.
pub fn refine_polyline(parent: &Topology, poly: &[u32], closed: bool) -> Option<Vec<u32>> {
    let base = (parent.num_vertices() + parent.num_faces()) as u32;
    let n = poly.len();
    let m = if closed { n } else { n.saturating_sub(1) };
    let mut out = Vec::with_capacity(n + m);
    for i in 0..n {
        out.push(poly[i]);
        if i < m {
            let e = parent.find_edge(poly[i], poly[(i + 1) % n])?;
            out.push(base + e);
        }
    }
    Some(out)
}
