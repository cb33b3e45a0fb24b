//! Applying the masks of a scheme of the Catmull-Clark family ([`crate::scheme::Rules`]) to
//! vertex data ("primvars": positions, colours, any `[f64; D]`), one level at a time, in
//! the order OpenSubdiv's `PrimvarRefiner::Interpolate` uses: face points, then edge
//! points and vertex points (which read the new face points).
//!
//! The three passes are data-parallel; each is split across threads with rayon once a
//! level is large enough to pay for it.

use crate::mesh::{Options, Rule, Topology};
use crate::scheme::catmark::{self, CatmullClark, VertexContext, VertexMask};
use crate::scheme::Rules;
use rayon::prelude::*;

/// Elements per parallel task; below `2 * CHUNK` elements a pass runs on one thread.
pub(super) const CHUNK: usize = 8192;

#[inline]
pub(super) fn axpy<const D: usize>(acc: &mut [f64; D], w: f64, x: &[f64; D]) {
    for k in 0..D {
        acc[k] += w * x[k];
    }
}

/// Interpolates `src` (values at the vertices of `parent`) to `dst` (values at the
/// vertices of `child`, the refinement of `parent`) with Catmull-Clark's masks:
/// [`interpolate_with`] and `CatmullClark`.
///
/// # Panics
/// If `src.len() != parent.num_vertices()` or `dst.len() != child.num_vertices()`.
pub fn interpolate<const D: usize>(
    parent: &Topology,
    child: &Topology,
    options: &Options,
    src: &[[f64; D]],
    dst: &mut [[f64; D]],
) {
    interpolate_with(parent, child, options, CatmullClark, src, dst);
}

/// Interpolates `src` (values at the vertices of `parent`) to `dst` (values at the
/// vertices of `child`, the refinement of `parent`) with the masks of `rules`: the face
/// points (centroids) first, then the edge and vertex points, which read them. Every
/// scheme of the Catmull-Clark family refines the same topology, so the scheme changes the
/// weights only.
///
/// # Panics
/// If `src.len() != parent.num_vertices()` or `dst.len() != child.num_vertices()`.
pub fn interpolate_with<R: Rules, const D: usize>(
    parent: &Topology,
    child: &Topology,
    options: &Options,
    rules: R,
    src: &[[f64; D]],
    dst: &mut [[f64; D]],
) {
    let nv = parent.num_vertices();
    let nf = parent.num_faces();
    assert_eq!(src.len(), nv, "source has the wrong number of values");
    assert_eq!(
        dst.len(),
        child.num_vertices(),
        "destination has the wrong number of values"
    );
    let (vert_pts, rest) = dst.split_at_mut(nv);
    let (face_pts, edge_pts) = rest.split_at_mut(nf);

    // Face points.
    face_points(parent, src, face_pts);
    let face_pts: &[[f64; D]] = face_pts;

    // Edge points.
    let tri_option = options.triangles == crate::mesh::TriangleSubdivision::Smooth;
    let edge_pass = |(start, out): (usize, &mut [[f64; D]])| {
        for (i, o) in out.iter_mut().enumerate() {
            let e = start + i;
            let [a, b] = parent.edge_verts[e];
            let faces = parent.edge_face_list(e);
            let sharp = parent.edge_sharpness[e];
            let (pa, pb) = (&src[a as usize], &src[b as usize]);
            if sharp <= 0.0 && faces.len() == 2 && !tri_option {
                let (f0, f1) = (&face_pts[faces[0] as usize], &face_pts[faces[1] as usize]);
                *o = rules.smooth_edge_point([pa, pb], [f0, f1]);
                continue;
            }
            let m = edge_mask_at(parent, child, options, rules, e);
            let mut acc = [0.0; D];
            for k in 0..D {
                acc[k] = m.vertex * (pa[k] + pb[k]);
            }
            if !m.is_crease() {
                for (j, &f) in faces.iter().enumerate() {
                    let w = if j < 2 { m.faces[j] } else { m.other_faces };
                    axpy(&mut acc, w, &face_pts[f as usize]);
                }
            }
            *o = acc;
        }
    };

    // Vertex points.
    let vertex_pass = |chunk: (usize, &mut [[f64; D]])| {
        vertex_points(parent, child, options, rules, src, Some(face_pts), chunk)
    };
    rayon::join(
        || run_chunks(edge_pts, edge_pass),
        || run_chunks(vert_pts, vertex_pass),
    );
}

/// The vertex points of `parent` refined into `child` with `rules`, for the values `src`
/// at `parent`'s vertices, into `out` (the points of vertices `start..start + out.len()`):
/// a vertex without edges is kept, a smooth or dart vertex gets the scheme's smooth
/// point, any other the weights of its mask ([`vertex_mask_at`]) on itself, the far ends
/// of its edges and its faces' points. `face_pts` are the new face points of the
/// Catmull-Clark family, where a smooth vertex's valence is its edge count; Loop has none
/// (`None`): its valence is the face count, as in OpenSubdiv (the same at the manifold
/// interior vertices that smooth rules apply to), and its masks have no face weights.
pub(super) fn vertex_points<R: Rules, const D: usize>(
    parent: &Topology,
    child: &Topology,
    options: &Options,
    rules: R,
    src: &[[f64; D]],
    face_pts: Option<&[[f64; D]]>,
    (start, out): (usize, &mut [[f64; D]]),
) {
    let (mut mask, mut child_mask) = (VertexMask::default(), VertexMask::default());
    let mut pe = Vec::new();
    let mut ce = Vec::new();
    for (i, o) in out.iter_mut().enumerate() {
        let v = start + i;
        let edges = parent.vertex_edges(v);
        let faces = parent.vertex_faces(v);
        let p = &src[v];
        if edges.is_empty() {
            *o = *p;
            continue;
        }
        if matches!(parent.vert_tags[v].get().rule, Rule::Smooth | Rule::Dart) {
            let ends = parent.vertex_neighbours(v);
            *o = match face_pts {
                Some(fp) => rules.smooth_vertex_point(
                    edges.len(),
                    p,
                    ends.map(|x| &src[x as usize]),
                    faces.iter().map(|&f| &fp[f as usize]),
                ),
                None => rules.smooth_vertex_point(
                    faces.len(),
                    p,
                    ends.take(faces.len()).map(|x| &src[x as usize]),
                    std::iter::empty(),
                ),
            };
            continue;
        }
        let scratch = (&mut pe, &mut ce, &mut child_mask);
        vertex_mask_at(parent, child, options, rules, v, &mut mask, scratch);
        let mut acc = [0.0; D];
        match face_pts {
            Some(fp) if mask.has_faces => {
                for (&f, &w) in faces.iter().zip(&mask.faces) {
                    axpy(&mut acc, w, &fp[f as usize]);
                }
            }
            Some(_) => {}
            None => debug_assert!(!mask.has_faces || mask.faces.iter().all(|&w| w == 0.0)),
        }
        if mask.has_edges {
            for (x, &w) in parent.vertex_neighbours(v).zip(&mask.edges) {
                axpy(&mut acc, w, &src[x as usize]);
            }
        }
        axpy(&mut acc, mask.vertex, p);
        *o = acc;
    }
}

/// Runs `f(start, chunk)` over `out` in chunks, in parallel when large.
pub(super) fn run_chunks<T: Send, F>(out: &mut [T], f: F)
where
    F: Fn((usize, &mut [T])) + Sync + Send,
{
    if out.len() < 2 * CHUNK {
        f((0, out));
    } else {
        out.par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(i, c)| f((i * CHUNK, c)));
    }
}

/// The face points of `parent` (centroids of the face vertices, the same in every scheme
/// that changes only edge and vertex weights) into `face_pts`, one per face.
pub(super) fn face_points<const D: usize>(
    parent: &Topology,
    src: &[[f64; D]],
    face_pts: &mut [[f64; D]],
) {
    let face_pass = |(start, out): (usize, &mut [[f64; D]])| {
        for (i, o) in out.iter_mut().enumerate() {
            let fv = parent.face_vertices(start + i);
            let mut acc = [0.0; D];
            for &v in fv {
                for k in 0..D {
                    acc[k] += src[v as usize][k];
                }
            }
            let w = catmark::face_point_weight(fv.len());
            for k in 0..D {
                acc[k] *= w;
            }
            *o = acc;
        }
    };
    run_chunks(face_pts, face_pass);
}

/// The mask of parent edge `e`'s child vertex (OpenSubdiv's `ComputeEdgeVertexMask`): the
/// scheme's [`Rules::edge_mask`] for the edge's sharpness, its faces (and which of the first
/// two are triangles) and the rule of its child vertex in `child` (`V + F + e` with the
/// quad split, `V + e` with the triangle split, [`Rules::splits_triangles`]).
pub(super) fn edge_mask_at<R: Rules>(
    parent: &Topology,
    child: &Topology,
    options: &Options,
    rules: R,
    e: usize,
) -> catmark::EdgeMask {
    let faces = parent.edge_face_list(e);
    let is_tri = |f: Option<&u32>| f.is_some_and(|&f| parent.face_vertices(f as usize).len() == 3);
    let tri = [is_tri(faces.first()), is_tri(faces.get(1))];
    let face_children = if rules.splits_triangles() {
        0
    } else {
        parent.num_faces()
    };
    let child_rule = child.vert_tags[parent.num_vertices() + face_children + e]
        .get()
        .rule;
    rules.edge_mask(
        options,
        parent.edge_sharpness[e],
        child_rule,
        faces.len(),
        tri,
    )
}

/// The mask of parent vertex `v`'s child vertex into `mask` (OpenSubdiv's
/// `ComputeVertexVertexMask`): the scheme's [`Rules::vertex_mask`] for the parent and
/// child rules and sharpness of `v` and of its edges (the child edge `S + 2e + k` is the
/// half of parent edge `e` at its end `k`, `S` the parent's face-vertex count). `scratch`
/// holds the two sharpness lists and the child rule's mask.
pub(super) fn vertex_mask_at<R: Rules>(
    parent: &Topology,
    child: &Topology,
    options: &Options,
    rules: R,
    v: usize,
    mask: &mut VertexMask,
    (pe, ce, child_mask): (&mut Vec<f32>, &mut Vec<f32>, &mut VertexMask),
) {
    let s = parent.face_verts.len();
    let edges = parent.vertex_edges(v);
    pe.clear();
    pe.extend(edges.iter().map(|&e| parent.edge_sharpness[e as usize]));
    ce.clear();
    ce.extend(
        edges
            .iter()
            .zip(parent.vertex_edge_locals(v))
            .map(|(&e, &l)| child.edge_sharpness[s + 2 * e as usize + l as usize]),
    );
    let ctx = VertexContext {
        parent_rule: parent.vert_tags[v].get().rule,
        child_rule: child.vert_tags[v].get().rule,
        parent_sharpness: parent.vert_sharpness[v],
        child_sharpness: child.vert_sharpness[v],
        parent_edges: pe,
        child_edges: ce,
        num_faces: parent.vertex_faces(v).len(),
    };
    rules.vertex_mask(options.crease_method, &ctx, mask, child_mask);
}
