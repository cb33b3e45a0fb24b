//! The extension layer around an open quad mesh ([`add_extension_layer`]): one ring of new
//! faces outside the boundary, so that every old boundary vertex becomes a regular interior
//! vertex and skirt removal ([`super::skirt`]) can read the intervals beyond the boundary.

use std::collections::HashMap;

use super::grid::push_interval;
use super::skirt::boundary_vertices;
use super::BlendError;
use crate::mesh::PolyMesh;

/// Adds one ring of quads outside the boundary of `mesh` ([Jiang et al.], Algorithm 1 step 2):
/// - each boundary edge `a → b` gets the quad `(b, a, o_a, o_b)`; its edges leaving the old
///   boundary (`a`–`o_a`) get `interval`, the outer edge the boundary edge's own interval;
/// - a boundary vertex with two faces gets one outward vertex `2 v − w` (`w` the mean of its
///   interior neighbours); a corner (one face) gets one outward vertex per boundary edge
///   and a diagonal vertex with a corner quad, so that it becomes a regular valence-4
///   vertex.
///
/// The outer positions only shape the extension layer, which skirt removal drops.
///
/// # Errors
/// [`BlendError::BoundaryVertex`] for a boundary vertex with three or more faces;
/// [`BlendError::Mesh`].
pub(crate) fn add_extension_layer(mesh: &PolyMesh, interval: f64) -> Result<PolyMesh, BlendError> {
    let edges = BoundaryEdges::new(mesh);
    let mut outward = outward_vertices(mesh, &edges, interval)?;
    let (offsets, verts) = ring_faces(mesh, &edges, &mut outward, interval);
    let new_weights = extension_weights(mesh, &outward);
    let Outward {
        pos, new_intervals, ..
    } = outward;
    let mut out = PolyMesh::new(pos, offsets, verts)?;
    out.knots = mesh.knots.clone();
    if !new_weights.is_empty() {
        out.knots.weights = new_weights;
    }
    out.tags = mesh.tags.clone();
    for (a, b, d) in new_intervals {
        push_interval(&mut out, a, b, d);
    }
    // Outer edges with interval 1 were skipped by push_interval: nothing else to do.
    Ok(out)
}

/// The undirected key of edge `a`–`b`.
fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// The boundary of a mesh: every vertex's face count and interior neighbours, and the
/// directed boundary edges `a → b` (as their face runs them) by either end.
struct BoundaryEdges {
    faces_of: Vec<usize>,
    /// The neighbours of each vertex across interior edges (once per face corner).
    nbrs: Vec<Vec<u32>>,
    out_edge: HashMap<u32, u32>,
    in_edge: HashMap<u32, u32>,
}

impl BoundaryEdges {
    fn new(mesh: &PolyMesh) -> Self {
        let mut count: HashMap<(u32, u32), u32> = HashMap::new();
        for fv in mesh.faces() {
            for (i, &a) in fv.iter().enumerate() {
                *count.entry(key(a, fv[(i + 1) % fv.len()])).or_insert(0) += 1;
            }
        }
        let nv = mesh.num_vertices();
        let mut faces_of = vec![0usize; nv];
        let mut nbrs: Vec<Vec<u32>> = vec![Vec::new(); nv];
        // Directed boundary edges a → b (as their face runs them).
        let mut out_edge: HashMap<u32, u32> = HashMap::new();
        let mut in_edge: HashMap<u32, u32> = HashMap::new();
        for fv in mesh.faces() {
            for (i, &a) in fv.iter().enumerate() {
                faces_of[a as usize] += 1;
                let b = fv[(i + 1) % fv.len()];
                if count[&key(a, b)] == 1 {
                    out_edge.insert(a, b);
                    in_edge.insert(b, a);
                } else {
                    nbrs[a as usize].push(b);
                }
            }
        }
        Self {
            faces_of,
            nbrs,
            out_edge,
            in_edge,
        }
    }
}

/// The extension layer's new vertices and intervals.
struct Outward {
    /// The mesh's positions followed by the new vertices.
    pos: Vec<[f64; 3]>,
    /// Outward vertex of each boundary vertex for its incoming boundary edge.
    o_in: HashMap<u32, u32>,
    /// Outward vertex of each boundary vertex for its outgoing boundary edge.
    o_out: HashMap<u32, u32>,
    /// The quad `(v, a, d, b)` at each corner `v` (`d` its diagonal vertex).
    corner_faces: Vec<[u32; 4]>,
    /// Intervals to tag on the new edges.
    new_intervals: Vec<(u32, u32, f64)>,
}

/// The outward vertices of every boundary vertex ([Jiang et al.], Algorithm 1 step 2):
/// `2 v − w` (`w` the mean of its interior
/// neighbours, or of its two boundary neighbours when it has none) for a vertex with two
/// faces; for a corner (one face) one per boundary edge and a diagonal vertex, with the
/// corner quad and its two `interval` edges.
///
/// # Errors
/// [`BlendError::BoundaryVertex`] for a boundary vertex with three or more faces (or not on
/// one boundary edge each way).
fn outward_vertices(
    mesh: &PolyMesh,
    edges: &BoundaryEdges,
    interval: f64,
) -> Result<Outward, BlendError> {
    let bnd = boundary_vertices(mesh);
    let nv = mesh.num_vertices();
    let mut pos = mesh.positions().to_vec();
    let p = |v: u32| mesh.positions()[v as usize];
    let lin = |a: [f64; 3], s: f64, b: [f64; 3], t: f64| {
        [
            s * a[0] + t * b[0],
            s * a[1] + t * b[1],
            s * a[2] + t * b[2],
        ]
    };
    let mut o_in: HashMap<u32, u32> = HashMap::new();
    let mut o_out: HashMap<u32, u32> = HashMap::new();
    let mut corner_faces = Vec::new();
    let mut new_intervals = Vec::new();
    for v in 0..nv as u32 {
        if !bnd[v as usize] {
            continue;
        }
        let (Some(&x), Some(&y)) = (edges.in_edge.get(&v), edges.out_edge.get(&v)) else {
            return Err(BlendError::BoundaryVertex {
                vertex: v,
                faces: edges.faces_of[v as usize],
            });
        };
        match edges.faces_of[v as usize] {
            2 => {
                let inner = &edges.nbrs[v as usize];
                let w = if inner.is_empty() {
                    lin(p(x), 0.5, p(y), 0.5)
                } else {
                    let mut s = [0.0; 3];
                    for &n in inner {
                        s = lin(s, 1.0, p(n), 1.0 / inner.len() as f64);
                    }
                    s
                };
                let o = pos.len() as u32;
                pos.push(lin(p(v), 2.0, w, -1.0));
                o_in.insert(v, o);
                o_out.insert(v, o);
            }
            1 => {
                // Corner: the face runs x → v → y; away from y for the incoming edge, away
                // from x for the outgoing one, and the diagonal.
                let a = pos.len() as u32;
                pos.push(lin(p(v), 2.0, p(y), -1.0));
                let b = pos.len() as u32;
                pos.push(lin(p(v), 2.0, p(x), -1.0));
                let d = pos.len() as u32;
                pos.push([
                    3.0 * p(v)[0] - p(x)[0] - p(y)[0],
                    3.0 * p(v)[1] - p(x)[1] - p(y)[1],
                    3.0 * p(v)[2] - p(x)[2] - p(y)[2],
                ]);
                o_in.insert(v, a);
                o_out.insert(v, b);
                corner_faces.push([v, a, d, b]);
                new_intervals.push((a, d, interval));
                new_intervals.push((d, b, interval));
            }
            n => {
                return Err(BlendError::BoundaryVertex {
                    vertex: v,
                    faces: n,
                })
            }
        }
    }
    Ok(Outward {
        pos,
        o_in,
        o_out,
        corner_faces,
        new_intervals,
    })
}

/// The faces of `mesh` followed by the extension ring (CSR offsets and vertices): the quad
/// `(b, a, o_a, o_b)` on every boundary edge `a → b` (its outer edge with the boundary
/// edge's own interval), then the corner quads; adds `interval` on the edges leaving the old
/// boundary.
fn ring_faces(
    mesh: &PolyMesh,
    edges: &BoundaryEdges,
    outward: &mut Outward,
    interval: f64,
) -> (Vec<u32>, Vec<u32>) {
    let own = super::grid::intervals(mesh);
    let mut offsets = mesh.face_offsets().to_vec();
    let mut verts = mesh.face_verts().to_vec();
    let push = |f: &[u32], offsets: &mut Vec<u32>, verts: &mut Vec<u32>| {
        verts.extend_from_slice(f);
        offsets.push(verts.len() as u32);
    };
    let (o_in, o_out) = (&outward.o_in, &outward.o_out);
    let new_intervals = &mut outward.new_intervals;
    // In the order of the boundary edges' first vertices, so that the output does not
    // depend on the hash map's order (the same input gives the same mesh).
    let mut boundary_edges: Vec<(u32, u32)> =
        edges.out_edge.iter().map(|(&a, &b)| (a, b)).collect();
    boundary_edges.sort_unstable();
    for (a, b) in boundary_edges {
        let (oa, ob) = (o_out[&a], o_in[&b]);
        push(&[b, a, oa, ob], &mut offsets, &mut verts);
        let d = own.get(&key(a, b)).copied().unwrap_or(1.0);
        new_intervals.push((oa, ob, d));
    }
    for f in &outward.corner_faces {
        push(f, &mut offsets, &mut verts);
    }
    for v in 0..mesh.num_vertices() as u32 {
        if let Some(&o) = o_in.get(&v) {
            new_intervals.push((v, o, interval));
        }
        if let (Some(&a), Some(&b)) = (o_in.get(&v), o_out.get(&v)) {
            if a != b {
                new_intervals.push((v, b, interval));
            }
        }
    }
    (offsets, verts)
}

/// The weight tags of the extended mesh (none when `mesh` has none): each new vertex has the
/// weight of the boundary vertex it was made from (its position and weight never reach the
/// surface, but must be valid).
fn extension_weights(mesh: &PolyMesh, outward: &Outward) -> Vec<crate::mesh::VertexWeight> {
    if mesh.knots.weights.is_empty() {
        Vec::new()
    } else {
        let w = super::homogeneous::mesh_weights(mesh);
        let mut all = w.clone();
        all.resize(outward.pos.len(), 1.0);
        for (&v, &o) in outward.o_in.iter().chain(&outward.o_out) {
            all[o as usize] = w[v as usize];
        }
        for f in &outward.corner_faces {
            all[f[2] as usize] = w[f[0] as usize];
        }
        crate::mesh::VertexWeight::tags(&all)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blend::skirt::outer_ring;

    #[test]
    fn a_quad_gets_a_regular_ring_of_eight_faces() {
        let m = PolyMesh::from_faces(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            &[[0u32, 1, 2, 3]],
        )
        .unwrap();
        let e = add_extension_layer(&m, 0.0).unwrap();
        assert_eq!(e.num_faces(), 9);
        assert_eq!(e.num_vertices(), 16);
        // The old face is the only real face; the old vertices are interior.
        assert_eq!(outer_ring(&e).iter().filter(|&&r| !r).count(), 1);
        crate::mesh::Topology::from_mesh(&e, &Default::default()).unwrap();
        // Edges leaving the old boundary carry the extension interval.
        assert!(e.knots.intervals.iter().any(|t| t.interval == 0.0));
    }
}
