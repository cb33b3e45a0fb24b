//! One uniform triangle-split topology step (Loop): every triangle becomes four, the
//! child [`Topology`] derived directly from the parent's indices, with tags and sharpness
//! propagated as for the quad split ([`super::topology`]), as OpenSubdiv's
//! `Vtr::internal::TriRefinement` does.
//!
//! # Child numbering (OpenSubdiv's default order)
//! With `V`, `F`, `E` the parent's vertex, face and edge counts and `S = 3F`:
//! - vertices: the child of vertex `v` is `v`; of edge `e` is `V + e` (no face children);
//! - faces: parent triangle `f = [v₀ v₁ v₂]` with edges `eⱼ = vⱼvⱼ₊₁` and edge children
//!   `Eⱼ` gives `4f + j` at corner `j` and the middle one `4f + 3`:
//!   `[v₀, E₀, E₂]`, `[E₀, v₁, E₁]`, `[E₂, E₁, v₂]`, `[E₁, E₂, E₀]`;
//! - edges: `3f + j` joins `Eⱼ` and `Eⱼ₊₂` inside `f`; `S + 2e + k` joins the child of edge
//!   `e` and of its end `k`.
//!
//! The relations of the child (edge → faces, vertex → faces and edges) are built in
//! rotational order, each edge leading the face after it, as the quad split does.

use super::topology::{child_topology, edge_child_at, fill_edge_halves, half_at_start, ChildFaces};
use crate::mesh::{Options, Topology};

/// Refines the triangle mesh `p` (complete, every face a triangle) one level: the
/// complete child topology, tags and sharpness.
pub(crate) fn refine_tri_topology(p: &Topology, options: &Options) -> Topology {
    debug_assert!(p.complete);
    debug_assert!((0..p.num_faces()).all(|f| p.face_vertices(f).len() == 3));
    let nv = p.num_vertices();
    let nf = p.num_faces();
    let ne = p.num_edges();
    let s = 3 * nf;
    let su = s as u32;
    let ec0 = nv as u32;

    // Faces and the edges inside each parent face, then the halves of each parent edge.
    let mut face_verts = Vec::with_capacity(12 * nf);
    let mut face_edges = Vec::with_capacity(12 * nf);
    let mut face_holes = Vec::with_capacity(4 * nf);
    let mut edge_verts = Vec::with_capacity(s + 2 * ne);
    for f in 0..nf {
        let v = p.face_vertices(f);
        let pe = p.face_edge_list(f);
        let ce = [ec0 + pe[0], ec0 + pe[1], ec0 + pe[2]];
        face_verts.extend_from_slice(&[v[0], ce[0], ce[2], ce[0], v[1], ce[1]]);
        face_verts.extend_from_slice(&[ce[2], ce[1], v[2], ce[1], ce[2], ce[0]]);
        // Halves of edge j at its start (corner j) and at its end (corner j + 1).
        let start = |j: usize| edge_child_at(p, su, pe[j], v[j], true);
        let end = |j: usize| edge_child_at(p, su, pe[j], v[(j + 1) % 3], false);
        let inner = |j: usize| (3 * f + j) as u32;
        face_edges.extend_from_slice(&[start(0), inner(0), end(2)]);
        face_edges.extend_from_slice(&[end(0), start(1), inner(1)]);
        face_edges.extend_from_slice(&[inner(2), end(1), start(2)]);
        face_edges.extend_from_slice(&[inner(2), inner(0), inner(1)]);
        face_holes.extend_from_slice(&[p.face_holes[f]; 4]);
        edge_verts.extend_from_slice(&[[ce[0], ce[2]], [ce[1], ce[0]], [ce[2], ce[1]]]);
    }
    edge_verts.resize(s + 2 * ne, [0; 2]);
    fill_edge_halves(p, ec0, &mut edge_verts[s..]);

    let faces = ChildFaces {
        face_offsets: (0..=4 * nf as u32).map(|i| 3 * i).collect(),
        face_verts,
        face_edges,
        face_holes,
        edge_verts,
    };
    let mut child = child_topology(p, options, 0, faces, true);
    edge_faces(p, &mut child);
    vertex_relations(p, &mut child);
    let max_edge_faces = (0..ne).map(|e| p.edge_face_list(e).len()).max();
    child.max_valence = p
        .max_valence
        .max(2 + 2 * max_edge_faces.unwrap_or(0) as u32);
    child
}

/// The child's edge → faces relation: an edge inside parent face `f` lies in its corner
/// triangle and the middle one; each half of a parent edge in one corner triangle per
/// face of the parent edge, in the parent's order (with the edge's position in each child
/// face).
fn edge_faces(p: &Topology, c: &mut Topology) {
    let nf = p.num_faces();
    let s = 3 * nf;
    let mut offsets = Vec::with_capacity(c.edge_verts.len() + 1);
    let mut faces = Vec::with_capacity(2 * s + 2 * p.edge_faces.len());
    let mut local = Vec::with_capacity(faces.capacity());
    offsets.push(0u32);
    for f in 0..nf as u32 {
        for j in 0..3u32 {
            // Inner edge j: edge (j + 1) % 3 of corner triangle j and of the middle one.
            faces.extend_from_slice(&[4 * f + j, 4 * f + 3]);
            local.extend_from_slice(&[((j + 1) % 3) as u16; 2]);
            offsets.push(faces.len() as u32);
        }
    }
    for e in 0..p.num_edges() {
        let ev = p.edge_verts[e];
        let pl = &p.edge_face_local[p.edge_face_offsets[e] as usize..];
        for k in 0..2 {
            for (&pf, &i) in p.edge_face_list(e).iter().zip(pl) {
                let fv = p.face_vertices(pf as usize);
                let i = i as usize;
                let corner = if half_at_start(ev, fv, i, k) {
                    i
                } else {
                    (i + 1) % 3
                };
                // The half at the start of parent edge i is edge i of corner triangle i;
                // the half at its end, edge i of corner triangle i + 1.
                faces.push(4 * pf + corner as u32);
                local.push(i as u16);
            }
            offsets.push(faces.len() as u32);
        }
    }
    c.edge_face_offsets = offsets;
    c.edge_faces = faces;
    c.edge_face_local = local;
}

/// The child's vertex → faces and vertex → edges relations in rotational order (each
/// edge leading the face after it). Vertex children keep their parent's order. Around
/// the child `Eᵢ` of edge `i` of a parent triangle (running `vᵢ → vᵢ₊₁`): the half toward
/// `vᵢ₊₁`, corner triangle `i + 1`, inner edge `i + 1`, the middle triangle, inner edge
/// `i`, corner triangle `i`, the half toward `vᵢ`; then the same in the next parent face.
/// On non-manifold edges the two halves come first, then each face's inner edges.
fn vertex_relations(p: &Topology, c: &mut Topology) {
    let nv = p.num_vertices();
    let ne = p.num_edges();
    let su = p.face_verts.len() as u32;
    let mut fo = Vec::with_capacity(nv + ne + 1);
    let mut eo = Vec::with_capacity(nv + ne + 1);
    let mut vf = Vec::with_capacity(c.face_verts.len());
    let mut vfl = Vec::with_capacity(c.face_verts.len());
    let mut ve = Vec::with_capacity(2 * c.edge_verts.len());
    let mut vel = Vec::with_capacity(2 * c.edge_verts.len());
    fo.push(0u32);
    eo.push(0u32);
    for v in 0..nv {
        for (&pf, &j) in p.vertex_faces(v).iter().zip(p.vertex_face_locals(v)) {
            vf.push(4 * pf + j as u32);
            vfl.push(j);
        }
        for (&pe, &l) in p.vertex_edges(v).iter().zip(p.vertex_edge_locals(v)) {
            ve.push(su + 2 * pe + l as u32);
            vel.push(1u8);
        }
        fo.push(vf.len() as u32);
        eo.push(ve.len() as u32);
    }
    for e in 0..ne {
        let pfaces = p.edge_face_list(e);
        let pl = &p.edge_face_local[p.edge_face_offsets[e] as usize..];
        let manifold = !p.edge_tags[e].get().non_manifold && pfaces.len() <= 2;
        if !manifold {
            ve.extend_from_slice(&[su + 2 * e as u32, su + 2 * e as u32 + 1]);
            vel.extend_from_slice(&[0, 0]);
        }
        for (n, (&pf, &i)) in pfaces.iter().zip(pl).enumerate() {
            let i = i as u32;
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            vf.extend_from_slice(&[4 * pf + i1, 4 * pf + 3, 4 * pf + i]);
            vfl.extend_from_slice(&[i as u16, i2 as u16, i1 as u16]);
            let fv = p.face_vertices(pf as usize);
            let (a, b) = (fv[i as usize], fv[i1 as usize]);
            if manifold && n == 0 {
                ve.push(edge_child_at(p, su, e as u32, b, false));
                vel.push(0);
            }
            ve.extend_from_slice(&[3 * pf + i1, 3 * pf + i]);
            vel.extend_from_slice(&[1, 0]);
            if manifold && n == 0 {
                ve.push(edge_child_at(p, su, e as u32, a, true));
                vel.push(0);
            }
        }
        fo.push(vf.len() as u32);
        eo.push(ve.len() as u32);
    }
    c.vert_face_offsets = fo;
    c.vert_faces = vf;
    c.vert_face_local = vfl;
    c.vert_edge_offsets = eo;
    c.vert_edges = ve;
    c.vert_edge_local = vel;
}
