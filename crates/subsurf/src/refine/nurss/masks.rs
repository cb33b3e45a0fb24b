//! One step of non-uniform Catmull-Clark subdivision (NURSS) on a [`Topology`]: the
//! weights of [`crate::scheme::nurss`] applied to vertex data, and the knot intervals of the
//! child level. The child topology is Catmull-Clark's (`refine_topology`), so child
//! vertices, edges and faces are numbered exactly as for Catmull-Clark (OpenSubdiv's order).
//!
//! A step's weights depend on the topology and the intervals only: `NurssMasks` computes
//! them once per level; [`interpolate_nurss`] applies them to data, and re-posing plans
//! ([`crate::refine::RefinePlan::new`] with [`Scheme::Nurss`](crate::Scheme::Nurss)) store them as rows.
//!
//! # How the rules read intervals
//! - *Side intervals.* Inside face `f`, edge `j` of the face reads [`NurssKnots::side`]: the
//!   auxiliary interval of that side when the level has them (the base mesh only, [JOS 2003]
//!   §2), else the edge's interval. An edge's *own* interval ([`NurssKnots::own`]) is the
//!   mean of its sides ([JOS 2003]: `d_ij = (d+_ij + d−_ij) / 2`), which is the edge's interval
//!   when no side is tagged.
//! - *Rotations.* `d±_X` for edge `k` around vertex `X` reads edge `k + 2` on the side of the
//!   face the rotation passes last (face `k + 1`) and edge `k − 2` on the side of face
//!   `k − 2`. The smooth vertex rule reads `h_{i±1}`, `h_{i±2}` the same way.
//! - *Boundaries.* At a boundary vertex a rotation that would leave the mesh reads the one
//!   met the other way round (`d± = 2 d+` or `2 d−`); if both leave, the edge's own interval
//!   (`d± = 2 d`): the intervals of a mirror image across the boundary. With these, a regular
//!   open grid with sharp corners ([`crate::mesh::BoundaryInterpolation::EdgeAndCorner`])
//!   refines exactly as the tensor-product B-spline of the grid extended by its mirror image
//!   (phantom points `2 P_0 − P_1`, mirrored intervals); with edge-only boundaries the
//!   boundary rules read the intervals round a corner instead, so next to the corners (the
//!   corner, its two boundary neighbours, its two boundary edges) the points differ.
//!   With equal intervals the rules are Catmull-Clark's.
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
//! [`crate::nonuniform::Nurss::new`]); zero intervals make sharp features instead.

use rayon::prelude::*;

use crate::mesh::{Options, Rule, Topology};
use crate::refine::refine_topology;
use crate::refine::topology::{chunk_ranges, collect, parallel, run, split_pieces, CHUNK};
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

/// The weight of each face-vertex slot of `t` in its face's point (NURSS face points),
/// with the effective `knots` and their values across `ac`.
fn face_masks(t: &Topology, knots: &NurssKnots, ac: &AcrossValues) -> Vec<f64> {
    let mut face = vec![0.0; t.face_verts.len()];
    let ranges = chunk_ranges(t.num_faces());
    let pieces = split_pieces(&mut face, &ranges, |f| t.face_offsets[f] as usize);
    run(ranges.into_iter().zip(pieces).collect(), |(r, piece)| {
        let base = t.face_offsets[r.start] as usize;
        let (mut d, mut a0, mut a1, mut w) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for f in r {
            let o = t.face_offsets[f] as usize;
            let n = t.face_offsets[f + 1] as usize - o;
            d.clear();
            a0.clear();
            a1.clear();
            for j in 0..n {
                d.push(knots.side(t, f, j));
                a0.push(ac.slot[o + j][0]);
                a1.push(ac.slot[o + (j + 1) % n][1]);
            }
            face_weights(&d, &a0, &a1, &mut w);
            piece[o - base..o - base + n].copy_from_slice(&w);
        }
    });
    face
}

/// The rule of edge `e`'s point: the smooth rule on its midpoint and its two faces'
/// points for a smooth manifold edge between two faces, else the curve rule along the
/// crease or boundary.
fn edge_rule(t: &Topology, knots: &NurssKnots, ac: &AcrossValues, e: usize) -> EdgeRule {
    let [a, b] = t.edge_verts[e];
    let faces = t.edge_face_list(e);
    if faces.len() == 2 && t.edge_sharpness[e] <= 0.0 && !t.edge_tags[e].get().non_manifold {
        let locals = &t.edge_face_local[t.edge_face_offsets[e] as usize..];
        let sides = |i: usize| {
            let (f, l) = (faces[i] as usize, locals[i] as usize);
            let n = t.face_vertices(f).len();
            [knots.side(t, f, l + n - 1), knots.side(t, f, l + 1)]
        };
        let [m, l, r] = edge_weights(sides(0), sides(1));
        EdgeRule::Smooth { m, faces: [l, r] }
    } else {
        let d = ac.own[e];
        let before = crease_partner(t, a as usize, e).map_or(d, |x| ac.own[x]);
        let after = crease_partner(t, b as usize, e).map_or(d, |x| ac.own[x]);
        EdgeRule::Curve(curve_edge_weights(before, d, after))
    }
}

/// The rule of every vertex point of `t`, and the weights of the smooth ones on their
/// edges' midpoints and their faces' points (at the slots of `vert_edges` and
/// `vert_faces`, zero elsewhere).
fn vertex_masks(
    t: &Topology,
    knots: &NurssKnots,
    ac: &AcrossValues,
) -> (Vec<VertexRule>, Vec<f64>, Vec<f64>) {
    let mut vertex = vec![VertexRule::Keep; t.num_vertices()];
    let mut vert_mid = vec![0.0; t.vert_edges.len()];
    let mut vert_face = vec![0.0; t.vert_faces.len()];
    let ranges = chunk_ranges(t.num_vertices());
    let rules = split_pieces(&mut vertex, &ranges, |v| v);
    let mids = split_pieces(&mut vert_mid, &ranges, |v| t.vert_edge_offsets[v] as usize);
    let fws = split_pieces(&mut vert_face, &ranges, |v| t.vert_face_offsets[v] as usize);
    let items: Vec<_> = ranges.into_iter().zip(rules).zip(mids).zip(fws).collect();
    run(items, |(((r, rules), mids), fws)| {
        let (eb, fb) = (
            t.vert_edge_offsets[r.start] as usize,
            t.vert_face_offsets[r.start] as usize,
        );
        let (mut ring, mut wm, mut wf) = (Vec::new(), Vec::new(), Vec::new());
        for v in r.clone() {
            let edges = t.vertex_edges(v);
            let tag = t.vert_tags[v].get();
            rules[v - r.start] = match tag.rule {
                Rule::Corner => VertexRule::Keep,
                _ if edges.is_empty() => VertexRule::Keep,
                Rule::Crease => crease_vertex_rule(t, ac, v),
                Rule::Smooth | Rule::Dart if tag.boundary || !is_fan(t, v) => VertexRule::Keep,
                Rule::Smooth | Rule::Dart => {
                    let n = edges.len();
                    let wv = smooth_vertex_weights(t, knots, ac, v, &mut ring, (&mut wm, &mut wf));
                    let eo = t.vert_edge_offsets[v] as usize - eb;
                    let fo = t.vert_face_offsets[v] as usize - fb;
                    mids[eo..eo + n].copy_from_slice(&wm[..n]);
                    fws[fo..fo + n].copy_from_slice(&wf[..n]);
                    VertexRule::Smooth(wv)
                }
            };
        }
    });
    (vertex, vert_mid, vert_face)
}

/// The rule of crease vertex `v`: the curve rule along its two sharp edges (with the
/// intervals of the edges beyond them), else (not two sharp edges) kept.
fn crease_vertex_rule(t: &Topology, ac: &AcrossValues, v: usize) -> VertexRule {
    let mut sharp = (t.vertex_edges(v).iter())
        .map(|&e| e as usize)
        .filter(|&e| t.edge_sharpness[e] > 0.0);
    let (Some(e1), Some(e2), None) = (sharp.next(), sharp.next(), sharp.next()) else {
        return VertexRule::Keep;
    };
    let other = |e: usize| {
        let [x, y] = t.edge_verts[e];
        if x as usize == v {
            y
        } else {
            x
        }
    };
    let (q1, q2) = (other(e1), other(e2));
    let (d1, d2) = (ac.own[e1], ac.own[e2]);
    let d0 = crease_partner(t, q1 as usize, e1).map_or(d1, |x| ac.own[x]);
    let d3 = crease_partner(t, q2 as usize, e2).map_or(d2, |x| ac.own[x]);
    VertexRule::Curve {
        ends: [q1, q2],
        w: curve_vertex_weights([d0, d1, d2, d3]),
    }
}

/// The smooth rule at interior fan vertex `v`: its own weight, returned, and its weights
/// on its edges' midpoints and its faces' points, into `wm` and `wf` (in the order of its
/// edges and faces), from the intervals around it gathered in `ring`.
fn smooth_vertex_weights(
    t: &Topology,
    knots: &NurssKnots,
    ac: &AcrossValues,
    v: usize,
    ring: &mut Vec<RingIntervals>,
    (wm, wf): (&mut Vec<f64>, &mut Vec<f64>),
) -> f64 {
    let faces = t.vertex_faces(v);
    let flocal = t.vertex_face_locals(v);
    let n = t.vertex_edges(v).len();
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
    vertex_weights(ring, wm, wf)
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

/// `f(i, &mut out[i])` for every `i`, in parallel over chunks when `out` is large.
fn fill<T: Send>(out: &mut [T], f: impl Fn(usize, &mut T) + Sync + Send) {
    if parallel(out.len()) {
        (out.par_iter_mut().with_min_len(CHUNK).enumerate()).for_each(|(i, o)| f(i, o));
    } else {
        out.iter_mut().enumerate().for_each(|(i, o)| f(i, o));
    }
}

#[inline]
fn axpy<const D: usize>(acc: &mut [f64; D], w: f64, x: &[f64; D]) {
    for c in 0..D {
        acc[c] += w * x[c];
    }
}

/// The rule of an edge point.
#[derive(Clone, Copy, Debug)]
enum EdgeRule {
    /// `m M + f₀ F₀ + f₁ F₁`: the edge's midpoint `M` (its weights in `NurssMasks::mid`) and
    /// the points of its two faces (Sederberg et al. §4, the edge point of a smooth edge).
    Smooth { m: f64, faces: [f64; 2] },
    /// `c₀ A + c₁ B` on the edge's ends: the cubic B-spline curve's edge point along a
    /// chain of sharp edges (boundary, non-manifold or infinitely sharp).
    Curve([f64; 2]),
}

/// The rule of a vertex point.
#[derive(Clone, Copy, Debug)]
enum VertexRule {
    /// The vertex stays (a corner, an isolated or boundary vertex, a vertex whose star is
    /// not one fan, a crease vertex without exactly two sharp edges).
    Keep,
    /// `c₀ Q₀ + c₁ V + c₂ Q₁` along a crease, `Q₀` and `Q₁` the far ends of its two sharp
    /// edges (the curve's vertex point).
    Curve { ends: [u32; 2], w: [f64; 3] },
    /// `w V + Σᵢ mᵢ Mᵢ + fᵢ Fᵢ` over its edges' midpoints and its faces' points, the `mᵢ`
    /// and `fᵢ` in [`NurssMasks`]' `vert_mid` and `vert_face` at the vertex's edge and face
    /// slots (Sederberg et al. §4, the vertex point).
    Smooth(f64),
}

/// Every weight of one NURSS step on a level: what [`interpolate_nurss`] applies to vertex
/// data, computed once from the level's topology and knot intervals (and nothing else:
/// the step is linear in the data). [`apply`](Self::apply) refines data with them;
/// [`row`](Self::row) gives one child vertex's weights on the parent vertices, the rows of
/// a re-posing plan ([`crate::refine::RefinePlan::new`]).
///
/// The rules are those of the [module documentation](self), with the weights of
/// [`crate::scheme::nurss`]: face points on their face's vertices; edge midpoints `M` on
/// the edge's ends; edge points on `M` and their faces' points (or the curve rule);
/// vertex points on themselves, their edges' `M` and their faces' points (or the curve
/// rule, or the vertex itself).
pub(crate) struct NurssMasks {
    /// The weight of each face-vertex slot in its face's point.
    face: Vec<f64>,
    /// The weights of each edge's midpoint `M` on its two ends.
    mid: Vec<[f64; 2]>,
    edge: Vec<EdgeRule>,
    vertex: Vec<VertexRule>,
    /// The weights of [`VertexRule::Smooth`] on the midpoints of the vertex's edges, at
    /// their slots of `vert_edges` (zero elsewhere).
    vert_mid: Vec<f64>,
    /// The same on the points of its faces, at their slots of `vert_faces`.
    vert_face: Vec<f64>,
}

impl NurssMasks {
    /// The masks of refining `parent` (complete, without semi-sharp edges or vertices)
    /// with the intervals `knots`. In parallel over blocks of faces, edges and vertices
    /// when the level is large (the same weights on any number of threads).
    pub(crate) fn new(parent: &Topology, knots: &NurssKnots) -> Self {
        let t = parent;
        let eff = effective_knots(knots);
        let knots = &eff;
        let ac = across_values(t, knots);
        let face = face_masks(t, knots, &ac);
        let mid = collect(t.num_edges(), |e| {
            midpoint_weights(ac.own[e], ac.edge[e][0], ac.edge[e][1])
        });
        let edge = collect(t.num_edges(), |e| edge_rule(t, knots, &ac, e));
        let (vertex, vert_mid, vert_face) = vertex_masks(t, knots, &ac);
        NurssMasks {
            face,
            mid,
            edge,
            vertex,
            vert_mid,
            vert_face,
        }
    }

    /// Refines `src` (values at the vertices of `t`, the level of [`new`](Self::new)) into
    /// `dst` (the child's vertices), as [`interpolate_nurss`] describes; in parallel over
    /// blocks when large (each value computed as on one thread).
    pub(crate) fn apply<const D: usize>(
        &self,
        t: &Topology,
        src: &[[f64; D]],
        dst: &mut [[f64; D]],
    ) {
        let (nv, nf, ne) = (t.num_vertices(), t.num_faces(), t.num_edges());
        let (vert_pts, rest) = dst.split_at_mut(nv);
        let (face_pts, edge_pts) = rest.split_at_mut(nf);

        fill(face_pts, |f, out| {
            let r = t.face_offsets[f] as usize..t.face_offsets[f + 1] as usize;
            let mut acc = [0.0; D];
            for (&v, &w) in t.face_verts[r.clone()].iter().zip(&self.face[r]) {
                axpy(&mut acc, w, &src[v as usize]);
            }
            *out = acc;
        });
        let face_pts: &[[f64; D]] = face_pts;

        // Edge midpoints M (read by edge and vertex points), then edge points.
        let mut mids = vec![[0.0; D]; ne];
        fill(&mut mids, |e, out| {
            let [a, b] = t.edge_verts[e];
            let [m0, m1] = self.mid[e];
            let mut mp = [0.0; D];
            axpy(&mut mp, m0, &src[a as usize]);
            axpy(&mut mp, m1, &src[b as usize]);
            *out = mp;
        });
        fill(edge_pts, |e, out| {
            let mut acc = [0.0; D];
            match self.edge[e] {
                EdgeRule::Smooth { m, faces: [l, r] } => {
                    let faces = t.edge_face_list(e);
                    axpy(&mut acc, m, &mids[e]);
                    axpy(&mut acc, l, &face_pts[faces[0] as usize]);
                    axpy(&mut acc, r, &face_pts[faces[1] as usize]);
                }
                EdgeRule::Curve([c0, c1]) => {
                    let [a, b] = t.edge_verts[e];
                    axpy(&mut acc, c0, &src[a as usize]);
                    axpy(&mut acc, c1, &src[b as usize]);
                }
            }
            *out = acc;
        });

        fill(vert_pts, |v, out| {
            let p = &src[v];
            *out = match self.vertex[v] {
                VertexRule::Keep => *p,
                VertexRule::Curve { ends: [q1, q2], w } => {
                    let mut acc = [0.0; D];
                    axpy(&mut acc, w[0], &src[q1 as usize]);
                    axpy(&mut acc, w[1], p);
                    axpy(&mut acc, w[2], &src[q2 as usize]);
                    acc
                }
                VertexRule::Smooth(wv) => {
                    let (eo, fo) = (
                        t.vert_edge_offsets[v] as usize,
                        t.vert_face_offsets[v] as usize,
                    );
                    let faces = t.vertex_faces(v);
                    let mut acc = [0.0; D];
                    axpy(&mut acc, wv, p);
                    for (i, &e) in t.vertex_edges(v).iter().enumerate() {
                        axpy(&mut acc, self.vert_mid[eo + i], &mids[e as usize]);
                        axpy(
                            &mut acc,
                            self.vert_face[fo + i],
                            &face_pts[faces[i] as usize],
                        );
                    }
                    acc
                }
            };
        });
    }

    /// The weights of child vertex `cv` (numbered as [`interpolate_nurss`]'s `dst`) on the
    /// vertices of `t`, face points and midpoints expanded: `add(vertex, weight)` for each
    /// term, a vertex possibly several times (the caller sums them).
    pub(crate) fn row(&self, t: &Topology, cv: usize, mut add: impl FnMut(u32, f64)) {
        let (nv, nf) = (t.num_vertices(), t.num_faces());
        let face = |add: &mut dyn FnMut(u32, f64), f: usize, w: f64| {
            let r = t.face_offsets[f] as usize..t.face_offsets[f + 1] as usize;
            for (&v, &wv) in t.face_verts[r.clone()].iter().zip(&self.face[r]) {
                add(v, w * wv);
            }
        };
        let mid = |add: &mut dyn FnMut(u32, f64), e: usize, w: f64| {
            let ([a, b], [m0, m1]) = (t.edge_verts[e], self.mid[e]);
            add(a, w * m0);
            add(b, w * m1);
        };
        if cv < nv {
            let v = cv;
            match self.vertex[v] {
                VertexRule::Keep => add(v as u32, 1.0),
                VertexRule::Curve { ends: [q1, q2], w } => {
                    add(q1, w[0]);
                    add(v as u32, w[1]);
                    add(q2, w[2]);
                }
                VertexRule::Smooth(wv) => {
                    let (eo, fo) = (
                        t.vert_edge_offsets[v] as usize,
                        t.vert_face_offsets[v] as usize,
                    );
                    let faces = t.vertex_faces(v);
                    add(v as u32, wv);
                    for (i, &e) in t.vertex_edges(v).iter().enumerate() {
                        mid(&mut add, e as usize, self.vert_mid[eo + i]);
                        face(&mut add, faces[i] as usize, self.vert_face[fo + i]);
                    }
                }
            }
        } else if cv < nv + nf {
            face(&mut add, cv - nv, 1.0);
        } else {
            let e = cv - nv - nf;
            match self.edge[e] {
                EdgeRule::Smooth { m, faces: [l, r] } => {
                    let faces = t.edge_face_list(e);
                    mid(&mut add, e, m);
                    face(&mut add, faces[0] as usize, l);
                    face(&mut add, faces[1] as usize, r);
                }
                EdgeRule::Curve([c0, c1]) => {
                    let [a, b] = t.edge_verts[e];
                    add(a, c0);
                    add(b, c1);
                }
            }
        }
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
pub(super) fn interpolate_nurss<const D: usize>(
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
    NurssMasks::new(t, knots).apply(t, src, dst);
}

/// The knot intervals of the child of `parent` (no side intervals: they exist on the base
/// level only): the halves of edge `e` (child edges `S + 2e + k`) get `d_e / 2` (its own
/// interval); the edge from the point of face `f` to the point of its edge `j` (child edge
/// `face_offsets[f] + j`) gets `(d_{j−1} + d_{j+1}) / 4`, the side intervals of the face's
/// edges on either side (Sederberg et al., Fig. 6).
pub(crate) fn child_knots(parent: &Topology, knots: &NurssKnots) -> NurssKnots {
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
pub(crate) fn refine_nurss_step<const D: usize>(
    parent: &Topology,
    options: &Options,
    knots: &NurssKnots,
    src: &[[f64; D]],
) -> (Topology, Vec<[f64; D]>, NurssKnots) {
    // The values first: their masks are freed before the child topology is built, so they
    // do not add to the peak.
    let t = parent;
    let mut dst = vec![[0.0; D]; t.num_vertices() + t.num_faces() + t.num_edges()];
    interpolate_nurss(parent, knots, src, &mut dst);
    let child = refine_topology(parent, options, true);
    debug_assert_eq!(child.num_vertices(), dst.len());
    let k = child_knots(parent, knots);
    (child, dst, k)
}
