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
//! rotational order, each edge leading the face after it, as the quad split does. Large
//! levels are refined in parallel over ranges of parent faces, edges and vertices, each
//! range writing its own part of every array (as [`super::topology`] does), so the result
//! is the same whatever the number of threads.

use std::ops::Range;

use super::topology::{
    append_edge_halves, child_edge_face_offset, child_topology, chunk_ranges, collect,
    edge_child_at, extend, filled, half_at_start, run, split_pieces, Appender, ChildFaces, Fresh,
    VertexRelations,
};
use crate::mesh::{Options, Topology};

/// Refines the triangle mesh `p` (complete, every face a triangle) one level: the child
/// topology, tags and sharpness; with `full == false` only what is needed to interpolate
/// into the child and to write it out (faces, edges' vertices, tags and sharpness), not the
/// relations needed to refine it further or to evaluate limit masks on it (edge → faces,
/// vertex → faces and edges), as the quad split's `refine_topology` does.
pub(crate) fn refine_tri_topology(p: &Topology, options: &Options, full: bool) -> Topology {
    debug_assert!(p.complete);
    debug_assert!((0..p.num_faces()).all(|f| p.face_vertices(f).len() == 3));
    let mut child = child_topology(p, options, 0, child_faces(p), full);
    if full {
        edge_faces(p, &mut child);
        vertex_relations(p, &mut child);
    }
    let max_edge_faces = (0..p.num_edges()).map(|e| p.edge_face_list(e).len()).max();
    child.max_valence = p
        .max_valence
        .max(2 + 2 * max_edge_faces.unwrap_or(0) as u32);
    child
}

/// The child faces (four per parent triangle), their edges and holes, and the child's
/// edge → vertices: the edges inside each parent face, then the halves of each parent edge.
fn child_faces(p: &Topology) -> ChildFaces {
    let nf = p.num_faces();
    let s = 3 * nf;
    let mut face_verts = Fresh::new(12 * nf);
    let mut face_edges = Fresh::new(12 * nf);
    let mut face_holes = Fresh::new(4 * nf);
    let mut edge_verts = Fresh::new(s + 2 * p.num_edges());
    let (inner, halves) = edge_verts.split_at(s);
    let ranges = chunk_ranges(nf);
    let fv = face_verts.all().pieces(&ranges, |f| 12 * f);
    let fe = face_edges.all().pieces(&ranges, |f| 12 * f);
    let fh = face_holes.all().pieces(&ranges, |f| 4 * f);
    let ev = inner.pieces(&ranges, |f| 3 * f);
    let items = (ranges.into_iter().zip(fv).zip(fe).zip(fh).zip(ev))
        .map(|((((r, fv), fe), fh), ev)| (r, [fv, fe], fh, ev))
        .collect();
    run(items, |(range, [mut fv, mut fe], mut fh, mut ev)| {
        fill_faces(p, range, [&mut fv, &mut fe], &mut fh, &mut ev)
    });
    append_edge_halves(p, p.num_vertices() as u32, halves);
    ChildFaces {
        face_offsets: collect(4 * nf + 1, |i| 3 * i as u32),
        face_verts: face_verts.finish(),
        face_edges: face_edges.finish(),
        face_holes: face_holes.finish(),
        edge_verts: edge_verts.finish(),
    }
}

/// The child faces of the parent triangles `range` (their vertices and edges, 12 each per
/// parent), their holes (4 per parent) and the edges inside them (3 per parent), appended
/// to the pieces of the range.
fn fill_faces(
    p: &Topology,
    range: Range<usize>,
    [fv_out, fe_out]: [&mut Appender<'_, u32>; 2],
    holes: &mut Appender<'_, bool>,
    inner_edges: &mut Appender<'_, [u32; 2]>,
) {
    let su = 3 * p.num_faces() as u32;
    let ec0 = p.num_vertices() as u32;
    for f in range {
        let v = p.face_vertices(f);
        let pe = p.face_edge_list(f);
        let ce = [ec0 + pe[0], ec0 + pe[1], ec0 + pe[2]];
        fv_out.push_slice(&[
            v[0], ce[0], ce[2], ce[0], v[1], ce[1], ce[2], ce[1], v[2], ce[1], ce[2], ce[0],
        ]);
        // Halves of edge j at its start (corner j) and at its end (corner j + 1).
        let start = |j: usize| edge_child_at(p, su, pe[j], v[j], true);
        let end = |j: usize| edge_child_at(p, su, pe[j], v[(j + 1) % 3], false);
        let inner = |j: usize| (3 * f + j) as u32;
        fe_out.push_slice(&[
            start(0),
            inner(0),
            end(2),
            end(0),
            start(1),
            inner(1),
            inner(2),
            end(1),
            start(2),
            inner(2),
            inner(0),
            inner(1),
        ]);
        holes.push_slice(&[p.face_holes[f]; 4]);
        inner_edges.push_slice(&[[ce[0], ce[2]], [ce[1], ce[0]], [ce[2], ce[1]]]);
    }
}

/// The child's edge → faces relation: an edge inside parent face `f` lies in its corner
/// triangle and the middle one; each half of a parent edge in one corner triangle per
/// face of the parent edge, in the parent's order (with the edge's position in each child
/// face). The offsets are the quad split's (two faces per inner edge, a parent edge's
/// face count per half).
fn edge_faces(p: &Topology, c: &mut Topology) {
    let (nf, ne) = (p.num_faces(), p.num_edges());
    let s = 3 * nf;
    let pef = &p.edge_face_offsets;
    let mut offsets = Vec::with_capacity(s + 2 * ne + 1);
    extend(&mut offsets, s + 2 * ne + 1, |ce| {
        child_edge_face_offset(pef, s, ce)
    });
    let total = offsets[s + 2 * ne] as usize;
    let mut faces = filled(total, 0u32);
    let mut local = filled(total, 0u16);
    let (f_in, f_halves) = faces.split_at_mut(2 * s);
    let (l_in, l_halves) = local.split_at_mut(2 * s);

    let ranges = chunk_ranges(nf);
    let a = split_pieces(f_in, &ranges, |f| 6 * f);
    let b = split_pieces(l_in, &ranges, |f| 6 * f);
    run(
        ranges.into_iter().zip(a).zip(b).collect(),
        |((r, ef), efl)| {
            for (at, f) in r.enumerate() {
                for j in 0..3 {
                    // Inner edge j: edge (j + 1) % 3 of corner triangle j and of the middle one.
                    let k = 6 * at + 2 * j;
                    ef[k..k + 2].copy_from_slice(&[4 * f as u32 + j as u32, 4 * f as u32 + 3]);
                    efl[k..k + 2].fill(((j + 1) % 3) as u16);
                }
            }
        },
    );

    let ranges = chunk_ranges(ne);
    let a = split_pieces(f_halves, &ranges, |e| 2 * pef[e] as usize);
    let b = split_pieces(l_halves, &ranges, |e| 2 * pef[e] as usize);
    run(
        ranges.into_iter().zip(a).zip(b).collect(),
        |((r, ef), efl)| fill_half_edge_faces(p, r, ef, efl),
    );
    c.edge_face_offsets = offsets;
    c.edge_faces = faces;
    c.edge_face_local = local;
}

/// Edge → faces of the halves of the parent edges `range`, written into `ef`/`efl`,
/// which start at the first of them: the half at the start of parent edge `i` of a face is
/// edge `i` of corner triangle `i`; the half at its end, edge `i` of corner triangle `i + 1`.
fn fill_half_edge_faces(p: &Topology, range: Range<usize>, ef: &mut [u32], efl: &mut [u16]) {
    let pef = &p.edge_face_offsets;
    let mut at = 0;
    for e in range {
        let ev = p.edge_verts[e];
        let pl = &p.edge_face_local[pef[e] as usize..];
        for k in 0..2 {
            for (&pf, &i) in p.edge_face_list(e).iter().zip(pl) {
                let fv = p.face_vertices(pf as usize);
                let i = i as usize;
                let corner = if half_at_start(ev, fv, i, k) {
                    i
                } else {
                    (i + 1) % 3
                };
                ef[at] = 4 * pf + corner as u32;
                efl[at] = i as u16;
                at += 1;
            }
        }
    }
}

/// The child's vertex → faces and vertex → edges relations in rotational order (each
/// edge leading the face after it). Vertex children keep their parent's order. Around
/// the child `Eᵢ` of edge `i` of a parent triangle (running `vᵢ → vᵢ₊₁`): the half toward
/// `vᵢ₊₁`, corner triangle `i + 1`, inner edge `i + 1`, the middle triangle, inner edge
/// `i`, corner triangle `i`, the half toward `vᵢ`; then the same in the next parent face.
/// On non-manifold edges the two halves come first, then each face's inner edges. So the
/// child of an edge with `n` faces has `3n` faces and `2n + 2` edges.
fn vertex_relations(p: &Topology, c: &mut Topology) {
    let (nv, ne) = (p.num_vertices(), p.num_edges());
    let (pvf, pve, pef) = (
        &p.vert_face_offsets,
        &p.vert_edge_offsets,
        &p.edge_face_offsets,
    );
    let (vf_all, ve_all) = (pvf[nv], pve[nv]);
    let mut fo = Vec::with_capacity(nv + ne + 1);
    extend(&mut fo, nv + 1, |v| pvf[v]);
    extend(&mut fo, ne, |e| vf_all + 3 * pef[e + 1]);
    let mut eo = Vec::with_capacity(nv + ne + 1);
    extend(&mut eo, nv + 1, |v| pve[v]);
    extend(&mut eo, ne, |e| {
        ve_all + 2 * pef[e + 1] + 2 * (e + 1) as u32
    });
    let mut vf = filled(fo[nv + ne] as usize, 0u32);
    let mut vfl = filled(vf.len(), 0u16);
    let mut ve = filled(eo[nv + ne] as usize, 0u32);
    let mut vel = filled(ve.len(), 0u8);
    let all = VertexRelations {
        faces: &mut vf,
        face_local: &mut vfl,
        edges: &mut ve,
        edge_local: &mut vel,
    };
    let (of_vertices, of_edges) = all.split_at(vf_all as usize, ve_all as usize);
    let items = of_vertices.pieces(chunk_ranges(nv), |v| pvf[v] as usize, |v| pve[v] as usize);
    run(items, |(range, out)| fill_vertex_children(p, range, out));
    let items = of_edges.pieces(
        chunk_ranges(ne),
        |e| 3 * pef[e] as usize,
        |e| 2 * pef[e] as usize + 2 * e,
    );
    run(items, |(range, out)| fill_edge_children(p, range, out));
    c.vert_face_offsets = fo;
    c.vert_faces = vf;
    c.vert_face_local = vfl;
    c.vert_edge_offsets = eo;
    c.vert_edges = ve;
    c.vert_edge_local = vel;
}

/// Faces and edges around the children of the parent vertices `range` (the corner
/// triangles and edge halves at the vertex, in the parent's order), written into `out`,
/// which starts at the first of them.
fn fill_vertex_children(p: &Topology, range: Range<usize>, out: VertexRelations<'_>) {
    let su = p.face_verts.len() as u32;
    let (mut f_at, mut e_at) = (0, 0);
    for v in range {
        for (&pf, &j) in p.vertex_faces(v).iter().zip(p.vertex_face_locals(v)) {
            out.faces[f_at] = 4 * pf + j as u32;
            out.face_local[f_at] = j;
            f_at += 1;
        }
        for (&pe, &l) in p.vertex_edges(v).iter().zip(p.vertex_edge_locals(v)) {
            out.edges[e_at] = su + 2 * pe + l as u32;
            out.edge_local[e_at] = 1;
            e_at += 1;
        }
    }
}

/// Faces and edges around the children of the parent edges `range` ([`vertex_relations`]
/// gives the order), written into `out`, which starts at the first of them.
fn fill_edge_children(p: &Topology, range: Range<usize>, out: VertexRelations<'_>) {
    let su = p.face_verts.len() as u32;
    let (mut f_at, mut e_at) = (0, 0);
    let mut push_edge = |out: &mut VertexRelations<'_>, e: u32, l: u8| {
        out.edges[e_at] = e;
        out.edge_local[e_at] = l;
        e_at += 1;
    };
    let mut out = out;
    for e in range {
        let pfaces = p.edge_face_list(e);
        let pl = &p.edge_face_local[p.edge_face_offsets[e] as usize..];
        let manifold = !p.edge_tags[e].get().non_manifold && pfaces.len() <= 2;
        if !manifold {
            push_edge(&mut out, su + 2 * e as u32, 0);
            push_edge(&mut out, su + 2 * e as u32 + 1, 0);
        }
        for (n, (&pf, &i)) in pfaces.iter().zip(pl).enumerate() {
            let i = i as u32;
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            out.faces[f_at..f_at + 3].copy_from_slice(&[4 * pf + i1, 4 * pf + 3, 4 * pf + i]);
            out.face_local[f_at..f_at + 3].copy_from_slice(&[i as u16, i2 as u16, i1 as u16]);
            f_at += 3;
            let fv = p.face_vertices(pf as usize);
            let (a, b) = (fv[i as usize], fv[i1 as usize]);
            if manifold && n == 0 {
                push_edge(&mut out, edge_child_at(p, su, e as u32, b, false), 0);
            }
            push_edge(&mut out, 3 * pf + i1, 1);
            push_edge(&mut out, 3 * pf + i, 0);
            if manifold && n == 0 {
                push_edge(&mut out, edge_child_at(p, su, e as u32, a, true), 0);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Crease, PolyMesh};
    use crate::refine::loop_::tests::tri_grid;

    /// A triangulated `n × n` grid (`loop_`'s test grid) with a fin (a triangle on an
    /// interior edge, making it non-manifold) and creases: every pass is parallel from
    /// level 0 when `n ≥ 100`.
    fn big_mesh(n: u32) -> PolyMesh {
        let grid = tri_grid(n, |i, j| ((i * 7 + j * 3) % 5) as f64 * 0.1);
        let id = |i: u32, j: u32| i * (n + 1) + j;
        let mut pos = grid.positions().to_vec();
        let mut faces: Vec<Vec<u32>> = grid.faces().map(<[u32]>::to_vec).collect();
        pos.push([5.0, 5.0, 3.0]);
        faces.push(vec![id(5, 5), id(5, 6), pos.len() as u32 - 1]);
        let mut m = PolyMesh::from_faces(pos, &faces).expect("valid grid");
        m.tags.creases = (0..n / 2)
            .map(|j| Crease {
                v0: id(n / 3, j),
                v1: id(n / 3, j + 1),
                sharpness: 0.5 + j as f32 * 0.1,
            })
            .collect();
        m
    }

    /// The triangle split gives the same topology, array for array, with one thread (one
    /// range per pass) and with two (ranges of `CHUNK` elements written in parallel).
    #[test]
    fn parallel_split_equals_serial() {
        let mesh = big_mesh(100);
        let options = Options::default();
        let (base, _) = Topology::from_mesh(&mesh, &options).expect("valid mesh");
        assert!(base.num_faces() >= 20_000 && base.num_vertices() >= 10_000);
        let two_levels = || {
            let l1 = refine_tri_topology(&base, &options, true);
            let l2 = refine_tri_topology(&l1, &options, true);
            (l1, l2)
        };
        let pool = |n| rayon::ThreadPoolBuilder::new().num_threads(n).build();
        let serial = pool(1).expect("pool").install(two_levels);
        let parallel = pool(2).expect("pool").install(two_levels);
        assert!(
            serial == parallel,
            "the split depends on the number of threads"
        );
        // The non-manifold edge's child has 3 faces × 3 and 2 + 2 × 3 edges.
        let l1 = &serial.0;
        let most = (0..l1.num_vertices())
            .map(|v| l1.vertex_faces(v).len())
            .max();
        assert_eq!(most, Some(9));
    }
}
