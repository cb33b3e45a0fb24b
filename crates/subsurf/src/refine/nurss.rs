//! One step of non-uniform Catmull-Clark subdivision (NURSS) on a [`Topology`]: the
//! weights of [`crate::scheme::nurss`] applied to vertex data, and the knot intervals of the
//! child level. The child topology is Catmull-Clark's (`refine_topology`), so child
//! vertices, edges and faces are numbered exactly as for Catmull-Clark (OpenSubdiv's order).
//!
//! # How the rules read intervals
//! - *Side intervals.* Inside face `f`, edge `j` of the face reads [`NurssKnots::side`]: the
//!   auxiliary interval of that side when the level has them (the base mesh only, seed 001
//!   §2), else the edge's interval. An edge's *own* interval ([`NurssKnots::own`]) is the
//!   mean of its sides (seed 001: `d_ij = (d+_ij + d−_ij) / 2`), which is the edge's interval
//!   when no side is tagged.
//! - *Rotations.* `d±_X` for edge `k` around vertex `X` reads edge `k + 2` on the side of the
//!   face the rotation passes last (face `k + 1`) and edge `k − 2` on the side of face
//!   `k − 2`. The smooth vertex rule reads `h_{i±1}`, `h_{i±2}` the same way.
//! - *Boundaries.* At a boundary vertex a rotation that would leave the mesh reads the one
//!   met the other way round (`d± = 2 d+` or `2 d−`); if both leave, the edge's own interval
//!   (`d± = 2 d`): the intervals of a mirror image across the boundary. With these, a regular
//!   open grid refines exactly as the tensor-product B-spline of the grid extended by its
//!   mirror image (phantom points `2 P_0 − P_1`, mirrored intervals), and with equal intervals
//!   the rules are Catmull-Clark's.
//!
//! # Sharp edges and vertices
//! Boundary edges, non-manifold edges and infinitely sharp creases use the cubic B-spline
//! curve rules along the chain of sharp edges (the Catmull-Clark crease rule when all
//! intervals are equal): an edge point reads the intervals of the sharp edges continuing at
//! either end, a crease vertex (exactly two sharp edges) the curve vertex rule. Where the
//! chain ends (a corner, a dart, a vertex with three or more sharp edges) the missing
//! neighbour interval is the edge's own (mirror image: the chain's end point stays a control
//! point the curve ends at). Corner vertices (sharp, or more than two sharp edges, or
//! boundary corners in [`crate::mesh::BoundaryInterpolation::EdgeAndCorner`]) stay put.
//! Semi-sharp creases have no NURSS counterpart: callers reject them (see
//! [`crate::nurss::Nurss::new`]); zero intervals make sharp features instead.

use super::refine_topology;
use crate::mesh::{Options, Rule, Topology};
use crate::scheme::nurss::{
    curve_edge_weights, curve_vertex_weights, edge_weights, face_edge_interval, face_weights,
    midpoint_weights, vertex_weights, RingIntervals,
};

/// Knot intervals of one level.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NurssKnots {
    /// Interval of every edge (indexed like the level's edges).
    pub intervals: Vec<f64>,
    /// Auxiliary interval of every face side, indexed by face-vertex slot
    /// (`face_offsets[f] + j` is the side of face `f`'s edge `j`, from its vertex `j` to
    /// `j + 1`), or `None` (every side reads its edge's interval). Only base levels have them.
    pub sides: Option<Vec<f64>>,
}

impl NurssKnots {
    /// Interval of the side of face `f`'s edge `j` (`j` taken modulo the face size).
    #[inline]
    pub fn side(&self, t: &Topology, f: usize, j: usize) -> f64 {
        let o = t.face_offsets[f] as usize;
        let n = t.face_offsets[f + 1] as usize - o;
        let s = o + j % n;
        match &self.sides {
            Some(sides) => sides[s],
            None => self.intervals[t.face_edges[s] as usize],
        }
    }

    /// An edge's own interval: the mean of its face sides, or its interval without sides.
    pub fn own(&self, t: &Topology, e: usize) -> f64 {
        match &self.sides {
            None => self.intervals[e],
            Some(sides) => {
                let faces = t.edge_face_list(e);
                if faces.is_empty() {
                    return self.intervals[e];
                }
                let locals = &t.edge_face_local[t.edge_face_offsets[e] as usize..];
                let sum: f64 = faces
                    .iter()
                    .zip(locals)
                    .map(|(&f, &l)| sides[t.face_offsets[f as usize] as usize + l as usize])
                    .sum();
                sum / faces.len() as f64
            }
        }
    }
}

/// The stand-in for a zero interval, relative to the level's largest interval.
const ZERO_INTERVAL: f64 = 1e-100;

/// The intervals the weights are computed from: every interval divided by the level's largest
/// (the rules are homogeneous of degree 0, so this changes nothing but the range), and every
/// zero interval replaced by [`ZERO_INTERVAL`].
///
/// Why: the rules divide by sums of products of intervals, which vanish in cases that are not
/// degenerate at all — at a vertex on a column of two zero intervals (a triple knot), every
/// `m_i` and `f_i` of the vertex rule is 0, although the tensor-product spline refines that
/// vertex by the curve rule along the column; a face spanning a zero interval in one direction
/// has all-zero weights although the spline gives the curve rule in the other direction. The
/// rules' limits as the zero intervals tend to 0 together are the exact answers (they are the
/// knot-insertion results of the multiple knots; `tests/integration/nurss.rs` checks them), and
/// with a stand-in 10⁻¹⁰⁰ times the largest interval the computed weights *are* those limits to
/// `f64` precision (the perturbation is far below one ulp). Where every interval around an
/// element is zero the limit is the uniform rule's, except that a vertex whose edge
/// midpoints and face points all coincide with it stays put — the blending paper's
/// corner-interpolation case (its eq. 3, `V' = V`) is reproduced. A level whose intervals are
/// all zero uses the degenerate fallbacks of [`crate::scheme::nurss`].
pub(crate) fn effective_knots(k: &NurssKnots) -> NurssKnots {
    let max = k
        .intervals
        .iter()
        .chain(k.sides.iter().flatten())
        .fold(0.0f64, |m, &d| m.max(d));
    if max <= 0.0 || !max.is_finite() {
        return k.clone();
    }
    let map = |d: &f64| {
        if *d > 0.0 {
            d / max
        } else {
            ZERO_INTERVAL
        }
    };
    NurssKnots {
        intervals: k.intervals.iter().map(map).collect(),
        sides: k.sides.as_ref().map(|s| s.iter().map(map).collect()),
    }
}

/// `d±` around every vertex, precomputed once per level.
pub(crate) struct AcrossValues {
    /// Per edge, `d±` at its end 0 and end 1 (relative to the edge).
    pub(crate) edge: Vec<[f64; 2]>,
    /// Per face-vertex slot (vertex `j` of face `f`): `d±` at that vertex relative to the
    /// face's edge `j` (leaving it) and edge `j − 1` (entering it).
    pub(crate) slot: Vec<[f64; 2]>,
    /// Own interval per edge.
    pub(crate) own: Vec<f64>,
}

/// Position of `(f, local)` in `v`'s face list.
#[inline]
fn side_slot(t: &Topology, f: u32, local: u16, entering: bool) -> usize {
    let o = t.face_offsets[f as usize] as usize;
    let n = t.face_offsets[f as usize + 1] as usize - o;
    let l = local as usize;
    o + if entering { (l + n - 1) % n } else { l }
}

fn read_side(t: &Topology, k: &NurssKnots, own: &[f64], slot: usize) -> f64 {
    match &k.sides {
        Some(s) => s[slot],
        None => own[t.face_edges[slot] as usize],
    }
}

/// Whether the star of `v` is one consistently ordered fan (interior: as many faces as
/// edges; boundary: one fewer).
#[inline]
fn is_fan(t: &Topology, v: usize) -> bool {
    let tag = t.vert_tags[v].get();
    let (ne, nf) = (t.vertex_edges(v).len(), t.vertex_faces(v).len());
    !tag.non_manifold
        && if tag.boundary {
            nf + 1 == ne && ne >= 2
        } else {
            nf == ne && ne >= 2
        }
}

/// [`AcrossValues`] of a complete level.
pub(crate) fn across_values(t: &Topology, k: &NurssKnots) -> AcrossValues {
    let own: Vec<f64> = (0..t.num_edges()).map(|e| k.own(t, e)).collect();
    let mut edge = vec![[0.0; 2]; t.num_edges()];
    let mut slot = vec![[0.0; 2]; t.face_verts.len()];
    let mut a = Vec::new();
    for v in 0..t.num_vertices() {
        let edges = t.vertex_edges(v);
        let elocal = t.vertex_edge_locals(v);
        let faces = t.vertex_faces(v);
        let flocal = t.vertex_face_locals(v);
        let n = edges.len();
        if !is_fan(t, v) {
            // No rotational order: every rotation reads the mirror image.
            for (&e, &l) in edges.iter().zip(elocal) {
                edge[e as usize][l as usize] = 2.0 * own[e as usize];
            }
            for (&f, &l) in faces.iter().zip(flocal) {
                let s = side_slot(t, f, l, false);
                let sp = side_slot(t, f, l, true);
                slot[s] = [
                    2.0 * own[t.face_edges[s] as usize],
                    2.0 * own[t.face_edges[sp] as usize],
                ];
            }
            continue;
        }
        let interior = faces.len() == n;
        a.clear();
        for i in 0..n {
            let plus = if interior || i + 2 < n {
                let f = (i + 1) % n;
                Some(read_side(
                    t,
                    k,
                    &own,
                    side_slot(t, faces[f], flocal[f], true),
                ))
            } else {
                None
            };
            let minus = if interior || i >= 2 {
                let f = (i + n - 2) % n;
                Some(read_side(
                    t,
                    k,
                    &own,
                    side_slot(t, faces[f], flocal[f], false),
                ))
            } else {
                None
            };
            a.push(match (plus, minus) {
                (Some(p), Some(m)) => p + m,
                (Some(x), None) | (None, Some(x)) => 2.0 * x,
                (None, None) => 2.0 * own[edges[i] as usize],
            });
        }
        for i in 0..n {
            edge[edges[i] as usize][elocal[i] as usize] = a[i];
        }
        for (i, (&f, &l)) in faces.iter().zip(flocal).enumerate() {
            let s = side_slot(t, f, l, false);
            slot[s] = [a[i], a[(i + 1) % n]];
        }
    }
    AcrossValues { edge, slot, own }
}

/// The sharp edge at `v` other than `e`, if `v` follows the crease rule.
fn crease_partner(t: &Topology, v: usize, e: usize) -> Option<usize> {
    if t.vert_tags[v].get().rule != Rule::Crease {
        return None;
    }
    t.vertex_edges(v)
        .iter()
        .map(|&x| x as usize)
        .find(|&x| x != e && t.edge_sharpness[x] > 0.0)
}

#[inline]
fn axpy<const D: usize>(acc: &mut [f64; D], w: f64, x: &[f64; D]) {
    for c in 0..D {
        acc[c] += w * x[c];
    }
}

/// Refines `src` (values at the vertices of `parent`, e.g. positions, or homogeneous
/// `(w x, w y, w z, w)` for a rational mesh) one NURSS step into `dst` (values at the
/// vertices of the Catmull-Clark child of `parent`: vertex points first, then face points,
/// then edge points; see [`crate::refine`]'s numbering).
///
/// `parent` must be complete (built by [`Topology::from_mesh`] or refined with all
/// relations), and have no semi-sharp edges or vertices (they are read as infinitely sharp).
///
/// # Panics
/// If the lengths of `src`, `dst` or `knots` do not match `parent`.
pub fn interpolate_nurss<const D: usize>(
    parent: &Topology,
    knots: &NurssKnots,
    src: &[[f64; D]],
    dst: &mut [[f64; D]],
) {
    let t = parent;
    let (nv, nf, ne) = (t.num_vertices(), t.num_faces(), t.num_edges());
    assert_eq!(src.len(), nv, "source has the wrong number of values");
    assert_eq!(dst.len(), nv + nf + ne, "destination has the wrong size");
    assert_eq!(knots.intervals.len(), ne, "one interval per edge is needed");
    if let Some(s) = &knots.sides {
        assert_eq!(
            s.len(),
            t.face_verts.len(),
            "one side interval per face side"
        );
    }
    let eff = effective_knots(knots);
    let knots = &eff;
    let ac = across_values(t, knots);
    let (vert_pts, rest) = dst.split_at_mut(nv);
    let (face_pts, edge_pts) = rest.split_at_mut(nf);

    // Face points.
    let (mut d, mut a0, mut a1, mut w) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (f, out) in face_pts.iter_mut().enumerate() {
        let fv = t.face_vertices(f);
        let o = t.face_offsets[f] as usize;
        let n = fv.len();
        d.clear();
        a0.clear();
        a1.clear();
        for j in 0..n {
            d.push(knots.side(t, f, j));
            a0.push(ac.slot[o + j][0]);
            a1.push(ac.slot[o + (j + 1) % n][1]);
        }
        face_weights(&d, &a0, &a1, &mut w);
        let mut acc = [0.0; D];
        for (&v, &wi) in fv.iter().zip(&w) {
            axpy(&mut acc, wi, &src[v as usize]);
        }
        *out = acc;
    }
    let face_pts: &[[f64; D]] = face_pts;

    // Edge midpoints M (read by edge and vertex points) and edge points.
    let mut mids = vec![[0.0; D]; ne];
    for e in 0..ne {
        let [a, b] = t.edge_verts[e];
        let (pa, pb) = (&src[a as usize], &src[b as usize]);
        let m = midpoint_weights(ac.own[e], ac.edge[e][0], ac.edge[e][1]);
        let mut mp = [0.0; D];
        axpy(&mut mp, m[0], pa);
        axpy(&mut mp, m[1], pb);
        mids[e] = mp;
        let faces = t.edge_face_list(e);
        let mut acc = [0.0; D];
        if faces.len() == 2 && t.edge_sharpness[e] <= 0.0 && !t.edge_tags[e].get().non_manifold {
            let locals = &t.edge_face_local[t.edge_face_offsets[e] as usize..];
            let sides = |i: usize| {
                let (f, l) = (faces[i] as usize, locals[i] as usize);
                let n = t.face_vertices(f).len();
                [knots.side(t, f, l + n - 1), knots.side(t, f, l + 1)]
            };
            let [wm, wl, wr] = edge_weights(sides(0), sides(1));
            axpy(&mut acc, wm, &mp);
            axpy(&mut acc, wl, &face_pts[faces[0] as usize]);
            axpy(&mut acc, wr, &face_pts[faces[1] as usize]);
        } else {
            let d = ac.own[e];
            let before = crease_partner(t, a as usize, e).map_or(d, |x| ac.own[x]);
            let after = crease_partner(t, b as usize, e).map_or(d, |x| ac.own[x]);
            let c = curve_edge_weights(before, d, after);
            axpy(&mut acc, c[0], pa);
            axpy(&mut acc, c[1], pb);
        }
        edge_pts[e] = acc;
    }

    // Vertex points.
    let (mut ring, mut wm, mut wf) = (Vec::new(), Vec::new(), Vec::new());
    for (v, out) in vert_pts.iter_mut().enumerate() {
        let p = &src[v];
        let edges = t.vertex_edges(v);
        let tag = t.vert_tags[v].get();
        *out = *p;
        match tag.rule {
            Rule::Corner => {}
            _ if edges.is_empty() => {}
            Rule::Crease => {
                let sharp: Vec<usize> = edges
                    .iter()
                    .map(|&e| e as usize)
                    .filter(|&e| t.edge_sharpness[e] > 0.0)
                    .collect();
                let [e1, e2] = match sharp[..] {
                    [x, y] => [x, y],
                    _ => continue,
                };
                let other = |e: usize| {
                    let [x, y] = t.edge_verts[e];
                    if x as usize == v {
                        y as usize
                    } else {
                        x as usize
                    }
                };
                let (q1, q2) = (other(e1), other(e2));
                let (d1, d2) = (ac.own[e1], ac.own[e2]);
                let d0 = crease_partner(t, q1, e1).map_or(d1, |x| ac.own[x]);
                let d3 = crease_partner(t, q2, e2).map_or(d2, |x| ac.own[x]);
                let c = curve_vertex_weights([d0, d1, d2, d3]);
                let mut acc = [0.0; D];
                axpy(&mut acc, c[0], &src[q1]);
                axpy(&mut acc, c[1], p);
                axpy(&mut acc, c[2], &src[q2]);
                *out = acc;
            }
            Rule::Smooth | Rule::Dart => {
                let faces = t.vertex_faces(v);
                let flocal = t.vertex_face_locals(v);
                let n = edges.len();
                if tag.boundary || !is_fan(t, v) {
                    continue;
                }
                let side = |f: usize, entering: bool| {
                    read_side(
                        t,
                        knots,
                        &ac.own,
                        side_slot(t, faces[f], flocal[f], entering),
                    )
                };
                ring.clear();
                for i in 0..n {
                    ring.push(RingIntervals {
                        minus2: side((i + n - 2) % n, false),
                        minus1: side((i + n - 1) % n, false),
                        plus1: side(i, true),
                        plus2: side((i + 1) % n, true),
                    });
                }
                let wv = vertex_weights(&ring, &mut wm, &mut wf);
                let mut acc = [0.0; D];
                axpy(&mut acc, wv, p);
                for i in 0..n {
                    axpy(&mut acc, wm[i], &mids[edges[i] as usize]);
                    axpy(&mut acc, wf[i], &face_pts[faces[i] as usize]);
                }
                *out = acc;
            }
        }
    }
}

/// The knot intervals of the child of `parent` (no side intervals: they exist on the base
/// level only): the halves of edge `e` (child edges `S + 2e + k`) get `d_e / 2` (its own
/// interval); the edge from the point of face `f` to the point of its edge `j` (child edge
/// `face_offsets[f] + j`) gets `(d_{j−1} + d_{j+1}) / 4`, the side intervals of the face's
/// edges on either side (Sederberg et al., Fig. 6).
pub fn child_knots(parent: &Topology, knots: &NurssKnots) -> NurssKnots {
    let t = parent;
    let s = t.face_verts.len();
    let mut intervals = vec![0.0; s + 2 * t.num_edges()];
    for f in 0..t.num_faces() {
        let o = t.face_offsets[f] as usize;
        let n = t.face_vertices(f).len();
        for j in 0..n {
            intervals[o + j] =
                face_edge_interval(knots.side(t, f, j + n - 1), knots.side(t, f, j + 1));
        }
    }
    for e in 0..t.num_edges() {
        let h = 0.5 * knots.own(t, e);
        intervals[s + 2 * e] = h;
        intervals[s + 2 * e + 1] = h;
    }
    NurssKnots {
        intervals,
        sides: None,
    }
}

/// One complete NURSS step: the child topology (Catmull-Clark's, with every relation, so it
/// can be refined again), the child values and the child intervals.
pub fn refine_nurss_step<const D: usize>(
    parent: &Topology,
    options: &Options,
    knots: &NurssKnots,
    src: &[[f64; D]],
) -> (Topology, Vec<[f64; D]>, NurssKnots) {
    let child = refine_topology(parent, options, true);
    let mut dst = vec![[0.0; D]; child.num_vertices()];
    interpolate_nurss(parent, knots, src, &mut dst);
    let k = child_knots(parent, knots);
    (child, dst, k)
}
