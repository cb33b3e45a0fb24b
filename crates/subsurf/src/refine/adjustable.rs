//! Applying the masks of the shape-adjustable scheme ([`crate::scheme::adjustable`]) to
//! vertex data, one level at a time, on the same child topology as Catmull-Clark (the
//! scheme changes weights only, never connectivity, numbering or sharpness decay).
//!
//! The passes and their order are those of [`super::interpolate`] (face points, then edge
//! and vertex points, which read the new face points); this is a separate function so
//! that the Catmull-Clark path keeps its fixed-weight fast paths untouched.

use super::primvar::{axpy, face_points, run_chunks};
use crate::mesh::{Options, Rule, Topology, TriangleSubdivision};
use crate::scheme::adjustable::Adjustable;
use crate::scheme::catmark::{VertexContext, VertexMask};

/// Interpolates `src` (values at the vertices of `parent`) to `dst` (values at the
/// vertices of `child`, the refinement of `parent`) with the adjustable scheme `scheme`.
/// With [`Adjustable::CATMULL_CLARK`] the masks are Catmull-Clark's bit for bit and the
/// result equals [`super::interpolate`]'s up to the order of floating-point additions.
///
/// # Panics
/// If `src.len() != parent.num_vertices()` or `dst.len() != child.num_vertices()`.
pub fn interpolate_adjustable<const D: usize>(
    parent: &Topology,
    child: &Topology,
    options: &Options,
    scheme: Adjustable,
    src: &[[f64; D]],
    dst: &mut [[f64; D]],
) {
    let nv = parent.num_vertices();
    let nf = parent.num_faces();
    // Child edge `s + 2e + k` is the half of parent edge `e` at its end `k`.
    let s = parent.face_verts.len();
    assert_eq!(src.len(), nv, "source has the wrong number of values");
    assert_eq!(
        dst.len(),
        child.num_vertices(),
        "destination has the wrong number of values"
    );
    let (vert_pts, rest) = dst.split_at_mut(nv);
    let (face_pts, edge_pts) = rest.split_at_mut(nf);

    // Face points: centroids, whatever c is.
    face_points(parent, src, face_pts);
    let face_pts: &[[f64; D]] = face_pts;

    let tri_option = options.triangles == TriangleSubdivision::Smooth;
    let is_tri = |f: Option<&u32>| f.is_some_and(|&f| parent.face_vertices(f as usize).len() == 3);
    let edge_pass = |(start, out): (usize, &mut [[f64; D]])| {
        for (i, o) in out.iter_mut().enumerate() {
            let e = start + i;
            let [a, b] = parent.edge_verts[e];
            let faces = parent.edge_face_list(e);
            let tri = if tri_option {
                [is_tri(faces.first()), is_tri(faces.get(1))]
            } else {
                [false; 2]
            };
            let child_rule = child.vert_tags[nv + nf + e].get().rule;
            let m = scheme.edge_mask(
                options,
                parent.edge_sharpness[e],
                child_rule,
                faces.len(),
                tri,
            );
            let (pa, pb) = (&src[a as usize], &src[b as usize]);
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

    let vertex_pass = |(start, out): (usize, &mut [[f64; D]])| {
        let mut mask = VertexMask::default();
        let mut scratch = VertexMask::default();
        let mut pe = Vec::new();
        let mut ce = Vec::new();
        for (i, o) in out.iter_mut().enumerate() {
            let v = start + i;
            let edges = parent.vertex_edges(v);
            let faces = parent.vertex_faces(v);
            let ptag = parent.vert_tags[v].get();
            let p = &src[v];
            if edges.is_empty() {
                *o = *p;
                continue;
            }
            let mut acc = [0.0; D];
            if matches!(ptag.rule, Rule::Smooth | Rule::Dart) {
                let (vw, ew, fw) = scheme.smooth_vertex_weights(edges.len());
                let mut se = [0.0; D];
                for x in parent.vertex_neighbours(v) {
                    for k in 0..D {
                        se[k] += src[x as usize][k];
                    }
                }
                let mut sf = [0.0; D];
                for &f in faces {
                    for k in 0..D {
                        sf[k] += face_pts[f as usize][k];
                    }
                }
                for k in 0..D {
                    acc[k] = ew * se[k] + fw * sf[k] + vw * p[k];
                }
                *o = acc;
                continue;
            }
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
                parent_rule: ptag.rule,
                child_rule: child.vert_tags[v].get().rule,
                parent_sharpness: parent.vert_sharpness[v],
                child_sharpness: child.vert_sharpness[v],
                parent_edges: &pe,
                child_edges: &ce,
                num_faces: faces.len(),
            };
            scheme.vertex_mask(options.crease_method, &ctx, &mut mask, &mut scratch);
            if mask.has_faces {
                for (&f, &w) in faces.iter().zip(&mask.faces) {
                    axpy(&mut acc, w, &face_pts[f as usize]);
                }
            }
            if mask.has_edges {
                for (x, &w) in parent.vertex_neighbours(v).zip(&mask.edges) {
                    axpy(&mut acc, w, &src[x as usize]);
                }
            }
            axpy(&mut acc, mask.vertex, p);
            *o = acc;
        }
    };
    rayon::join(
        || run_chunks(edge_pts, edge_pass),
        || run_chunks(vert_pts, vertex_pass),
    );
}
