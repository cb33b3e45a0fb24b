//! Refinement of face-varying data ([`FaceVarying`]: texture coordinates and any data per
//! face corner) alongside the vertex topology, as OpenSubdiv refines its face-varying
//! channels (`Vtr::internal::FVarLevel`, `FVarRefinement` and
//! `Far::PrimvarRefiner::InterpolateFaceVarying`).
//!
//! # The face-varying topology of a level ([`FvarLevel`])
//! Each vertex has one or more *values* (siblings): the distinct values its faces give it,
//! numbered in order of first appearance around the vertex. An edge whose two faces give
//! either end different values is *discontinuous* (a seam). A vertex whose values are
//! laid out as its vertex topology (one value, no seam, and not a boundary that the mode
//! makes linear) *matches*: its value is refined with the vertex masks of the scheme
//! ([`Rules`]), smooth, crease or corner as the vertex's sharpness says. The values of a
//! vertex that does not match each cover a span of its faces and are classified from
//! their span and the mode ([`FaceVaryingInterpolation`]):
//! - a *corner* (one face, or sharpened by the mode, an infinitely sharp edge inside the
//!   span, a non-manifold vertex or a disjoint span) keeps its value;
//! - a *crease* (a smooth face-varying boundary) takes the scheme's crease rule along the
//!   two boundary values at the ends of its span (`¾ v + ⅛ (a + b)` for Catmull-Clark
//!   and Loop);
//! - a *semi-sharp* value (a span with a semi-sharp edge, or a semi-sharp vertex) is a
//!   corner until the sharpness has decayed, then a crease, blended during the step it
//!   decays by OpenSubdiv's fractional weight.
//!
//! Face points are centroids of the face's values. A child of an edge takes the edge
//! mask of the scheme when the edge is continuous, else one value per face of the edge,
//! the midpoint of that face's two values.
//!
//! # Loop's triangle split
//! The same topology and classification serve Loop (C. Loop, "Smooth subdivision surfaces
//! based on triangles", M.S. thesis, University of Utah, 1987: [Loop 1987], with
//! OpenSubdiv's rules), whose split ([`super::tri_topology`]) makes no face points and
//! four triangles of each triangle: a continuous edge's child takes Loop's edge mask with
//! the values of the edge's ends and of each triangle's corner opposite the edge
//! (`⅜ (a + b) + ⅛ (o₀ + o₁)` when smooth); a vertex that matches takes Loop's vertex
//! mask on its value and its edges' far values (`(1 − nβₙ) v + βₙ Σ eᵢ` when smooth);
//! the rest is shared. A crease value at the child of a seam runs through the three
//! child triangles of one face of the edge (two quads with the quad split).
//!
//! # Numbering of child values (OpenSubdiv's)
//! Child values are numbered by child vertex (the children of vertices, then faces, then
//! edges, [`super::topology`]'s order; vertices then edges with the triangle split), each
//! child vertex's values in sibling order: a vertex's child has its parent's values in
//! the same order, a face's child one value, an edge's child one value, or one per face
//! of the edge (in the edge's face order) when the edge is discontinuous.

use std::ops::Range;

use rayon::prelude::*;

use super::primvar::{edge_mask_at, vertex_mask_at};
use super::topology::{
    append_pieces, chunk_ranges, collect, extend, rot, run, split_pieces, Appender, Fresh,
};
use crate::mesh::sharpness as sharp;
use crate::mesh::{
    BoundaryInterpolation, FaceVarying, FaceVaryingInterpolation, Options, Topology,
};
use crate::scheme::catmark::{self, CatmullClark, VertexMask};
use crate::scheme::loop_::Loop;
use crate::scheme::{crease, Rules};
use crate::scheme::{Bilinear, Scheme};

/// The classification of a face-varying value (OpenSubdiv's `FVarLevel::ValueTag`, the
/// part that refinement reads).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct ValueTag {
    /// The vertex's face-varying topology does not match its vertex topology.
    mismatch: bool,
    /// A smooth face-varying boundary (otherwise a corner).
    crease: bool,
    /// A corner that becomes a crease once its semi-sharp features have decayed.
    semi_sharp: bool,
    /// Semi-sharp because the vertex's other value is.
    dep_sharp: bool,
}

impl ValueTag {
    fn is_corner(self) -> bool {
        !self.crease
    }
}

/// Per edge: discontinuous (a seam), and linear (a boundary the mode makes linear).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct EdgeTag {
    mismatch: bool,
    linear: bool,
}

/// The faces of a vertex that one of its values covers, and the features inside
/// (OpenSubdiv's `FVarLevel::ValueSpan`).
#[derive(Clone, Copy, Debug, Default)]
struct Span {
    size: u16,
    start: u16,
    discts: u16,
    semi: u16,
    inf: u16,
}

/// The mode's consequences (OpenSubdiv's `completeTopologyFromFaceValues`).
#[derive(Clone, Copy, Debug)]
struct Mode {
    /// Everything linear.
    linear: bool,
    /// Face-varying boundaries linear.
    linear_boundaries: bool,
    /// A vertex's two values sharpen each other.
    dependent: bool,
    /// Single-face values are corners.
    corners_sharp: bool,
    /// Smooth corners of the vertex boundary become face-varying corners.
    sharpen_smooth_corners: bool,
    /// One corner sharpens both values of a vertex.
    sharpen_both: bool,
    /// Interior vertices with a single seam are corners.
    sharpen_darts: bool,
}

impl Mode {
    fn new(options: &Options) -> Self {
        use FaceVaryingInterpolation as F;
        let m = options.face_varying;
        let linear_boundaries = matches!(m, F::All | F::Boundaries);
        let corners_sharp = m != F::None;
        Self {
            linear: m == F::All,
            linear_boundaries,
            dependent: matches!(m, F::CornersPlus1 | F::CornersPlus2),
            corners_sharp,
            sharpen_smooth_corners: options.boundary != BoundaryInterpolation::EdgeAndCorner
                && corners_sharp,
            sharpen_both: m == F::CornersPlus2,
            sharpen_darts: m == F::CornersPlus2 || linear_boundaries,
        }
    }
}

/// The face-varying topology of one level of one channel. Values are addressed by *slot*
/// (`vert_offsets[v] + sibling`); at the base level `slot_values` maps a slot to the index
/// of its value in the user's value array, below it a slot is the index of its value.
///
/// A level refined onto a topology built for output only (not complete, so neither refined
/// further nor moved to the limit) is *not full*: it has no tags, crease ends or edge tags
/// ([`interpolate`] reads only its offsets, the parent's tags giving those of its vertex
/// children).
#[derive(Clone, Debug)]
pub(crate) struct FvarLevel {
    mode: Mode,
    /// Per face-vertex: the value index.
    face_values: Vec<u32>,
    /// Per face-vertex: which of its vertex's values it takes. The base level's only: below
    /// it a face-vertex's value is its slot, so its sibling is
    /// `face_values[i] - vert_offsets[v]`.
    face_siblings: Option<Vec<u16>>,
    /// Per vertex (`V + 1` prefix sums): its first slot.
    vert_offsets: Vec<u32>,
    /// Per slot: its value in the user's array (the base level's only).
    slot_values: Option<Vec<u32>>,
    /// Per slot (empty when not `full`): its class.
    tags: Vec<ValueTag>,
    /// Per slot (empty when not `full`): the vertex-face positions whose faces hold a
    /// crease's two end values.
    ends: Vec<[u16; 2]>,
    /// Per edge (empty when not `full`).
    edge_tags: Vec<EdgeTag>,
    /// Whether the level has everything refining it further and its limit read.
    full: bool,
}

impl FvarLevel {
    fn count(&self, v: usize) -> usize {
        (self.vert_offsets[v + 1] - self.vert_offsets[v]) as usize
    }

    fn slots(&self, v: usize) -> std::ops::Range<usize> {
        self.vert_offsets[v] as usize..self.vert_offsets[v + 1] as usize
    }

    /// Number of values of the level (beyond the base level: of the refined channel).
    pub(crate) fn num_slots(&self) -> usize {
        self.vert_offsets.last().copied().unwrap_or(0) as usize
    }

    /// The index of the value of `slot`.
    #[inline]
    fn slot_value(&self, slot: usize) -> u32 {
        match &self.slot_values {
            Some(values) => values[slot],
            None => slot as u32,
        }
    }

    /// The sibling of vertex `v` at face-vertex `at` (a corner of a face of `v`).
    #[inline]
    fn sibling(&self, at: usize, v: u32) -> u16 {
        match &self.face_siblings {
            Some(siblings) => siblings[at],
            None => (self.face_values[at] - self.vert_offsets[v as usize]) as u16,
        }
    }

    /// The sibling of vertex `v` in its `i`-th face.
    fn vertex_face_sibling(&self, t: &Topology, v: usize, i: usize) -> usize {
        let f = t.vertex_faces(v)[i] as usize;
        let at = t.face_offsets[f] as usize + t.vertex_face_locals(v)[i] as usize;
        self.sibling(at, v as u32) as usize
    }

    /// The value at corner `k` (taken cyclically) of face `f`.
    #[inline]
    fn face_value(&self, t: &Topology, f: usize, k: usize) -> u32 {
        let (a, b) = (t.face_offsets[f] as usize, t.face_offsets[f + 1] as usize);
        let n = b - a;
        // Callers step at most one turn past a corner: no division then.
        let k = if k < n {
            k
        } else if k - n < n {
            k - n
        } else {
            k % n
        };
        self.face_values[a + k]
    }

    /// The base level of a channel whose corner values are `indices` (OpenSubdiv's
    /// `FVarLevel::completeTopologyFromFaceValues`): seams, values per vertex, and the
    /// classification of the values of vertices that do not match.
    pub(crate) fn base(t: &Topology, indices: &[u32], options: &Options) -> Self {
        let nv = t.num_vertices();
        let mode = Mode::new(options);
        let mut l = Self {
            mode,
            face_values: indices.to_vec(),
            face_siblings: None,
            vert_offsets: Vec::with_capacity(nv + 1),
            slot_values: None,
            tags: Vec::new(),
            ends: Vec::new(),
            edge_tags: vec![EdgeTag::default(); t.num_edges()],
            full: true,
        };
        let mut slot_values = Vec::with_capacity(nv);
        let mut face_siblings = vec![0; indices.len()];
        let mut mismatch = vec![false; nv];
        l.vert_offsets.push(0);
        let mut vals = Vec::new();
        for v in 0..nv {
            let faces = t.vertex_faces(v);
            vals.clear();
            vals.extend(
                faces.iter().zip(t.vertex_face_locals(v)).map(|(&f, &k)| {
                    l.face_values[t.face_offsets[f as usize] as usize + k as usize]
                }),
            );
            l.mark_seams(t, v, &vals, &mut mismatch);
            // Distinct values in order of first appearance, and each face's sibling, found
            // as OpenSubdiv finds them: a value equal to the previous face's is that
            // sibling; otherwise, with two values so far, a value other than the first is
            // a new sibling even if it is the second (so A B A B gives three siblings, the
            // last B a value of its own), and beyond two values the list is searched.
            let first = slot_values.len();
            slot_values.push(vals.first().copied().unwrap_or(0));
            let mut prev_sib = 0;
            for (i, &x) in vals.iter().enumerate() {
                let unique = &slot_values[first..];
                let sib = if i == 0 || x == vals[i - 1] {
                    prev_sib
                } else if unique.len() == 1 || (unique.len() == 2 && unique[0] != x) {
                    slot_values.push(x);
                    slot_values.len() - 1 - first
                } else {
                    match unique.iter().position(|&y| y == x) {
                        Some(s) => s,
                        None => {
                            slot_values.push(x);
                            slot_values.len() - 1 - first
                        }
                    }
                };
                prev_sib = sib;
                let f = faces[i] as usize;
                let at = t.face_offsets[f] as usize + t.vertex_face_locals(v)[i] as usize;
                face_siblings[at] = sib as u16;
            }
            let count = slot_values.len() - first;
            if t.vert_tags[v].get().non_manifold && count > 1 {
                mismatch[v] = true;
            }
            l.vert_offsets.push(slot_values.len() as u32);
        }
        l.tags = vec![ValueTag::default(); slot_values.len()];
        l.ends = vec![[0, 0]; slot_values.len()];
        l.slot_values = Some(slot_values);
        l.face_siblings = Some(face_siblings);
        let mut spans = Vec::new();
        for v in (0..nv).filter(|&v| mismatch[v]) {
            l.classify(t, v, &mut spans);
        }
        l
    }

    /// Tags the seams at vertex `v` (its faces give `vals`) and the vertices they make
    /// mismatch, and the boundaries the mode makes linear.
    fn mark_seams(&mut self, t: &Topology, v: usize, vals: &[u32], mismatch: &mut [bool]) {
        let vtag = t.vert_tags[v].get();
        let (edges, nf) = (t.vertex_edges(v), vals.len());
        let linear = self.mode.linear_boundaries;
        let mut seams = Vec::new();
        if !vtag.non_manifold {
            for i in vtag.boundary as usize..nf {
                let prev = if i == 0 { nf - 1 } else { i - 1 };
                if vals[i] != vals[prev] {
                    seams.push(edges[i] as usize);
                }
            }
        } else if nf > 0 {
            for (&e, &end) in edges.iter().zip(t.vertex_edge_locals(v)) {
                let e = e as usize;
                let faces = t.edge_face_list(e);
                if faces.len() < 2 {
                    continue;
                }
                let locals = &t.edge_face_local[t.edge_face_offsets[e] as usize..];
                let value_in = |j: usize| {
                    let f = faces[j] as usize;
                    let k = locals[j] as usize;
                    let reversed = t.edge_verts[e][0] != t.face_vertices(f)[k];
                    self.face_value(t, f, k + ((end != 0) != reversed) as usize)
                };
                let v0 = value_in(0);
                if (1..faces.len()).any(|j| value_in(j) != v0) {
                    seams.push(e);
                }
            }
        }
        for e in seams {
            let [a, b] = t.edge_verts[e];
            mismatch[a as usize] = true;
            mismatch[b as usize] = true;
            self.edge_tags[e] = EdgeTag {
                mismatch: true,
                linear,
            };
        }
        if vtag.boundary && !mismatch[v] {
            if linear && nf > 0 {
                mismatch[v] = true;
                let boundary_edges: Vec<u32> = if !vtag.non_manifold {
                    vec![edges[0], edges[edges.len() - 1]]
                } else {
                    let tags = &t.edge_tags;
                    edges
                        .iter()
                        .copied()
                        .filter(|&e| tags[e as usize].get().boundary)
                        .collect()
                };
                for e in boundary_edges {
                    self.edge_tags[e as usize].linear = true;
                }
            } else if nf == 1 && self.mode.sharpen_smooth_corners {
                mismatch[v] = true;
            }
        }
    }

    /// Classifies the values of a vertex that does not match (corner, crease or
    /// semi-sharp) and records the ends of its creases.
    fn classify(&mut self, t: &Topology, v: usize, spans: &mut Vec<Span>) {
        let vtag = t.vert_tags[v].get();
        let count = self.count(v);
        let nf = t.vertex_faces(v).len();
        let m = self.mode;
        let mut all_sharp = m.linear_boundaries
            || vtag.inf_sharp
            || vtag.non_manifold
            || (m.dependent && count > 2)
            || (m.sharpen_darts && count == 1 && !vtag.boundary);
        self.spans(t, v, spans);
        let mut dependent_to_sharpen = false;
        if !all_sharp && m.dependent && count == 2 {
            let (a, b) = (spans[0], spans[1]);
            all_sharp = a.inf > 0 || b.inf > 0 || a.discts > 0 || b.discts > 0;
            if m.sharpen_both {
                all_sharp |= a.size == 1 || b.size == 1;
            }
            dependent_to_sharpen = (a.semi > 0) != (b.semi > 0);
        }
        for (i, slot) in self.slots(v).enumerate() {
            let mut tag = ValueTag {
                mismatch: true,
                ..ValueTag::default()
            };
            let span = spans[i];
            if span.discts == 0 {
                let inf = all_sharp || span.inf > 0 || (span.size == 1 && m.corners_sharp);
                if !inf {
                    if span.semi > 0 || vtag.semi_sharp {
                        tag.semi_sharp = true;
                    } else if dependent_to_sharpen {
                        tag.semi_sharp = true;
                        tag.dep_sharp = true;
                    } else {
                        tag.crease = true;
                    }
                    if !m.linear_boundaries {
                        let last = span.start.wrapping_add(span.size).wrapping_sub(1);
                        let end = if i == 0 && span.start != 0 {
                            last.wrapping_sub(nf as u16)
                        } else {
                            last
                        };
                        self.ends[slot] = [span.start, end];
                    }
                }
            }
            self.tags[slot] = tag;
        }
    }

    /// The span of each value of vertex `v` into `out` (OpenSubdiv's
    /// `FVarLevel::gatherValueSpans`).
    fn spans(&self, t: &Topology, v: usize, out: &mut Vec<Span>) {
        let count = self.count(v);
        out.clear();
        out.resize(count, Span::default());
        let (edges, nf) = (t.vertex_edges(v), t.vertex_faces(v).len());
        let boundary = edges.len() > nf;
        let add = |span: &mut Span, e: u32| {
            let e = e as usize;
            let tag = t.edge_tags[e].get();
            if self.edge_tags[e].mismatch {
                span.discts += 1;
            } else if tag.inf_sharp {
                span.inf += 1;
            } else if tag.semi_sharp {
                span.semi += 1;
            }
        };
        if t.vert_tags[v].get().non_manifold {
            out.iter_mut().for_each(|s| s.discts = 1);
        } else if count == 1 && !boundary {
            // An interior vertex with one value: disjoint if more than one seam.
            let s = &mut out[0];
            for (i, &e) in edges.iter().enumerate() {
                if self.edge_tags[e as usize].mismatch {
                    if s.size > 0 {
                        s.discts = 1;
                        break;
                    }
                    s.size = nf as u16;
                    s.start = i as u16;
                } else {
                    add(s, e);
                }
            }
            s.size = nf as u16;
        } else {
            let sib = |i: usize| self.vertex_face_sibling(t, v, i);
            out[0].size = 1;
            let wraps = !boundary && sib(nf - 1) == 0;
            if wraps {
                add(&mut out[0], edges[0]);
            }
            for i in 1..nf {
                let s = &mut out[sib(i)];
                if sib(i) == sib(i - 1) {
                    add(s, edges[i]);
                } else {
                    if s.size > 0 {
                        s.discts += 1;
                    }
                    s.start = i as u16;
                }
                s.size += 1;
            }
            if wraps {
                out[0].discts = out[0].discts.wrapping_sub(1);
            }
        }
    }

    /// The values at the two ends of edge `e` in its `i`-th face (OpenSubdiv's
    /// `getEdgeFaceValues`; the order of the two does not matter to their users).
    fn edge_face_values(&self, t: &Topology, e: usize, i: usize) -> [u32; 2] {
        let [a, b] = t.edge_verts[e];
        if self.count(a as usize) + self.count(b as usize) > 2 {
            self.face_edge_values(t, e, i)
        } else {
            let at = |v: u32| self.slot_value(self.vert_offsets[v as usize] as usize);
            [at(a), at(b)]
        }
    }

    /// The values at the two ends of edge `e` in its `i`-th face, read from the face:
    /// [`edge_face_values`](Self::edge_face_values) of an edge with an end that has more
    /// than one value, as either end of a discontinuous edge has (its faces give an end
    /// different values).
    #[inline]
    fn face_edge_values(&self, t: &Topology, e: usize, i: usize) -> [u32; 2] {
        let at = t.edge_face_offsets[e] as usize + i;
        let (f, k) = (t.edge_faces[at] as usize, t.edge_face_local[at] as usize);
        [self.face_value(t, f, k), self.face_value(t, f, k + 1)]
    }

    /// The value of face `f` opposite its edge `e` (two corners after the first corner
    /// whose edge is `e`, as OpenSubdiv's `interpFVarFromEdges` finds it for Loop).
    fn opposite_value(&self, t: &Topology, f: usize, e: usize) -> u32 {
        let k = t.face_edge_list(f).iter().position(|&x| x as usize == e);
        self.face_value(t, f, k.unwrap_or(0) + 2)
    }

    /// The value at the far end of the `i`-th edge of vertex `v`, seen from the values of
    /// `v` (OpenSubdiv's `getVertexEdgeValues`, for a vertex that matches).
    fn vertex_edge_value(&self, t: &Topology, v: usize, i: usize) -> u32 {
        let e = t.vertex_edges(v)[i] as usize;
        let other = t.edge_verts[e][(t.vertex_edge_locals(v)[i] == 0) as usize] as usize;
        if self.count(other) == 1 {
            return self.slot_value(self.vert_offsets[other] as usize);
        }
        let vtag = t.vert_tags[v].get();
        let (faces, locals) = (t.vertex_faces(v), t.vertex_face_locals(v));
        if !vtag.non_manifold {
            if vtag.boundary && i == t.vertex_edges(v).len() - 1 {
                let f = faces[i - 1] as usize;
                let n = t.face_vertices(f).len();
                self.face_value(t, f, locals[i - 1] as usize + n - 1)
            } else {
                self.face_value(t, faces[i] as usize, locals[i] as usize + 1)
            }
        } else {
            let f = t.edge_face_list(e)[0] as usize;
            let k = t.edge_face_local[t.edge_face_offsets[e] as usize] as usize;
            if other as u32 == t.face_vertices(f)[k] {
                self.face_value(t, f, k)
            } else {
                self.face_value(t, f, k + 1)
            }
        }
    }

    /// The two boundary values next to the crease value `sibling` of vertex `v`: the
    /// value after `v` in the span's first face and before it in its last (OpenSubdiv's
    /// `getVertexCreaseEndValues`).
    fn crease_end_values(&self, t: &Topology, v: usize, sibling: usize) -> [u32; 2] {
        let [s, e] = self.ends[self.vert_offsets[v] as usize + sibling];
        let (faces, locals) = (t.vertex_faces(v), t.vertex_face_locals(v));
        let f0 = faces[s as usize] as usize;
        let f1 = faces[e as usize] as usize;
        let n1 = t.face_vertices(f1).len();
        [
            self.face_value(t, f0, locals[s as usize] as usize + 1),
            self.face_value(t, f1, locals[e as usize] as usize + n1 - 1),
        ]
    }

    /// The sharpness of the edges inside the span of crease value `slot` of vertex `v`
    /// (between its first and last face), before (`p`) and after (`c`) the step.
    fn span_sharpness(
        &self,
        p: &Topology,
        c: &Topology,
        v: usize,
        slot: usize,
        out: &mut (Vec<f32>, Vec<f32>),
    ) {
        let [s, e] = self.ends[slot].map(usize::from);
        let edges = p.vertex_edges(v);
        let locals = p.vertex_edge_locals(v);
        let k0 = p.face_verts.len();
        // The edges after the first face up to the last, around the vertex.
        let n = edges.len();
        let inside = if e >= s { e - s } else { n - s + e };
        out.0.clear();
        out.1.clear();
        for k in (1..=inside).map(|i| (s + i) % n) {
            let pe = edges[k] as usize;
            out.0.push(p.edge_sharpness[pe]);
            out.1
                .push(c.edge_sharpness[k0 + 2 * pe + locals[k] as usize]);
        }
    }

    /// OpenSubdiv's `FVarRefinement::getFractionalWeight`: the weight of the corner rule
    /// for semi-sharp value `slot` of vertex `v` during the step from `p` to `c`.
    fn fractional_weight(
        &self,
        p: &Topology,
        c: &Topology,
        options: &Options,
        v: usize,
        slot: usize,
        sharpness: &mut (Vec<f32>, Vec<f32>),
    ) -> f64 {
        self.span_sharpness(p, c, v, slot, sharpness);
        crease::fractional_weight(
            options.crease_method,
            p.vert_sharpness[v],
            c.vert_sharpness[v],
            &sharpness.0,
            &sharpness.1,
        ) as f64
    }
}

impl FvarLevel {
    /// The face-varying topology of `c`, the refinement of `p` by the quad split or, with
    /// `triangles`, the triangle split (OpenSubdiv's `FVarRefinement::applyRefinement`):
    /// child values numbered as the module docs say, tags inherited (a discontinuous or
    /// linear edge's child values are creases, or corners when boundaries are linear),
    /// crease ends carried down, and semi-sharp values that have decayed reclassified as
    /// creases. Reads of `c` are limited to its sharpness, its vertex tags and whether it
    /// is complete: a level built for output only gives a level that is not full (see
    /// [`FvarLevel`]). Large levels are refined in parallel over ranges of parent
    /// vertices, faces and edges, each writing its own part of every array, so the result
    /// does not depend on the number of threads.
    pub(crate) fn refine(&self, p: &Topology, c: &Topology, triangles: bool) -> Self {
        debug_assert!(self.full, "a level built for output only is not refined");
        let nf = face_children(p, triangles);
        let full = c.is_complete();
        let vert_offsets = self.child_offsets(p, nf);
        let (tags, ends) = self.child_tags(p, c, triangles, &vert_offsets, full);
        let face_values = self.child_face_values(p, triangles, &vert_offsets);
        // Both splits make `2E` halves of edges after `S` edges inside the faces (the quad
        // split one per face-vertex, the triangle split three per triangle).
        let edge_tags = if full {
            let s = p.face_verts.len();
            collect(s + 2 * p.num_edges(), |i| {
                if i < s {
                    EdgeTag::default()
                } else {
                    self.edge_tags[(i - s) / 2]
                }
            })
        } else {
            Vec::new()
        };
        Self {
            mode: self.mode,
            face_values,
            face_siblings: None,
            vert_offsets,
            slot_values: None,
            tags,
            ends,
            edge_tags,
            full,
        }
    }

    /// The child's first slot per child vertex (prefix sums): a vertex's child has its
    /// parent's values (so the first `V + 1` offsets are the parent's), a face's child
    /// (`nf` of them) one value, an edge's child one, or one per face of the edge when the
    /// edge is discontinuous.
    fn child_offsets(&self, p: &Topology, nf: usize) -> Vec<u32> {
        let (nv, ne) = (p.num_vertices(), p.num_edges());
        let values = |e: usize| -> u32 {
            if self.edge_tags[e].mismatch {
                p.edge_face_list(e).len() as u32
            } else {
                1
            }
        };
        let mut offsets = Vec::with_capacity(nv + nf + ne + 1);
        offsets.extend_from_slice(&self.vert_offsets[..=nv]);
        let faces0 = offsets[nv];
        extend(&mut offsets, nf, |f| faces0 + f as u32 + 1);
        // Each range of edges starts after the values of the ranges before it.
        let ranges = chunk_ranges(ne);
        let counts = map_ranges(&ranges, |r| r.map(values).sum::<u32>());
        let mut at = faces0 + nf as u32;
        let starts = counts.iter().map(|&n| {
            at += n;
            at - n
        });
        let mut fresh = Fresh::after(offsets, ne);
        let pieces = fresh.all().pieces(&ranges, |e| e);
        let items = ranges.iter().cloned().zip(starts).zip(pieces);
        run(items.collect(), |((r, mut at), mut out)| {
            for e in r {
                at += values(e);
                out.push(at);
            }
        });
        fresh.finish()
    }

    /// The tags and crease ends of the child's values (`offsets` its first slots) when
    /// `full` (else none): a vertex's child has its parent's values' (semi-sharp values
    /// whose sharpness has decayed becoming creases,
    /// [`child_vertex_tags`](Self::child_vertex_tags)), a face's child a matching
    /// value, a discontinuous or linear edge's child values are creases (corners when
    /// boundaries are linear) each running through the child faces of one face of the
    /// edge: the two quads of the face on each side, or the triangle split's two corner
    /// triangles and the middle one (`super::tri_topology` orders them).
    fn child_tags(
        &self,
        p: &Topology,
        c: &Topology,
        triangles: bool,
        offsets: &[u32],
        full: bool,
    ) -> (Vec<ValueTag>, Vec<[u16; 2]>) {
        if !full {
            return (Vec::new(), Vec::new());
        }
        let nv = p.num_vertices();
        let vert_slots = offsets[nv] as usize;
        let total = offsets[offsets.len() - 1] as usize;
        let mut tags = Vec::with_capacity(total);
        extend(&mut tags, vert_slots, |i| self.tags[i]);
        if !self.mode.linear_boundaries {
            for_pieces(
                nv,
                &mut tags,
                |v| offsets[v] as usize,
                |r, tags| {
                    let first = offsets[r.start] as usize;
                    for v in r {
                        let slots = offsets[v] as usize - first..offsets[v + 1] as usize - first;
                        self.child_vertex_tags(p, c, v, &mut tags[slots]);
                    }
                },
            );
        }
        let mut ends = Vec::with_capacity(total);
        extend(&mut ends, vert_slots, |i| self.ends[i]);
        tags.resize(total, ValueTag::default());
        ends.resize(total, [0, 0]);
        let split = ValueTag {
            mismatch: true,
            crease: !self.mode.linear_boundaries,
            ..ValueTag::default()
        };
        let per_face: u16 = if triangles { 3 } else { 2 };
        let edge_offsets = &offsets[nv + face_children(p, triangles)..];
        let start = |e: usize| edge_offsets[e] as usize;
        let ranges = chunk_ranges(p.num_edges());
        let tag_pieces = split_pieces(&mut tags[start(0)..], &ranges, start);
        let end_pieces = split_pieces(&mut ends[start(0)..], &ranges, start);
        let items = ranges
            .into_iter()
            .zip(tag_pieces.into_iter().zip(end_pieces));
        run(items.collect(), |(r, (tags, ends))| {
            let first = start(r.start);
            for e in r {
                let et = self.edge_tags[e];
                if !et.mismatch && !et.linear {
                    continue;
                }
                for (i, slot) in (start(e) - first..start(e + 1) - first).enumerate() {
                    tags[slot] = split;
                    let first = per_face * i as u16;
                    ends[slot] = [first, first + per_face - 1];
                }
            }
        });
        (tags, ends)
    }

    /// The values of the child faces (`offsets` the child's first slots), in parallel over
    /// ranges of parent faces ([`fill_child_faces`](Self::fill_child_faces)).
    fn child_face_values(&self, p: &Topology, triangles: bool, offsets: &[u32]) -> Vec<u32> {
        let mut values = Vec::new();
        let start = |f: usize| 4 * p.face_offsets[f] as usize;
        append_pieces(
            &mut values,
            start(p.num_faces()),
            p.num_faces(),
            start,
            |r, out| self.fill_child_faces(p, triangles, offsets, r, out),
        );
        values
    }

    /// The values of the children of the parent faces `range`, appended to `out`. With
    /// the quad split the child of face `f` at corner `j` is the quad `[child of vertex j,
    /// child of edge j, child of f, child of edge j-1]` (rotated for quads, as
    /// [`super::topology`] lays it out); with the triangle split (`triangles`) triangle
    /// `[v₀ v₁ v₂]` with edge children `E₀ E₁ E₂` gives `[v₀ E₀ E₂]`, `[E₀ v₁ E₁]`,
    /// `[E₂ E₁ v₂]`, `[E₁ E₂ E₀]` ([`super::tri_topology`]).
    /// A vertex's child takes the sibling of its parent in `f`, an edge's child with one
    /// value per face the position of `f` among the edge's faces (the last, if `f` is
    /// there twice, as OpenSubdiv's `populateChildValuesForEdgeVertex` finds it).
    fn fill_child_faces(
        &self,
        p: &Topology,
        triangles: bool,
        offsets: &[u32],
        range: Range<usize>,
        out: &mut Appender<'_, u32>,
    ) {
        let nv = p.num_vertices();
        let edge0 = nv + face_children(p, triangles);
        let edge_child = |e: u32, f: usize| -> u32 {
            let cv = edge0 + e as usize;
            let first = offsets[cv];
            // A discontinuous edge's child has a value per face of the edge.
            if offsets[cv + 1] - first == 1 {
                return first;
            }
            let faces = p.edge_face_list(e as usize);
            first + faces.iter().rposition(|&g| g as usize == f).unwrap_or(0) as u32
        };
        for f in range {
            let o = p.face_offsets[f] as usize;
            let (fv, fe) = (p.face_vertices(f), p.face_edge_list(f));
            // Below the base level a face-vertex's value is its slot, which is the slot of
            // the vertex's child (the child of a vertex has its parent's slots).
            let vert = |j: usize| match &self.face_siblings {
                Some(siblings) => offsets[fv[j] as usize] + siblings[o + j] as u32,
                None => self.face_values[o + j],
            };
            let edge = |j: usize| edge_child(fe[j], f);
            if triangles {
                let (e0, e1, e2) = (edge(0), edge(1), edge(2));
                let corners = [
                    vert(0),
                    e0,
                    e2, //
                    e0,
                    vert(1),
                    e1, //
                    e2,
                    e1,
                    vert(2), //
                    e1,
                    e2,
                    e0,
                ];
                out.push_slice(&corners);
                continue;
            }
            let n = fv.len();
            let centre = offsets[nv + f];
            let mut before = edge(n - 1);
            for j in 0..n {
                let after = edge(j);
                let corners = [vert(j), after, centre, before];
                before = after;
                // Corner `k` goes to `(k + rot) % 4`.
                let r = 4 - rot(n, j);
                out.push_slice(&[0, 1, 2, 3].map(|i| corners[(i + r) % 4]));
            }
        }
    }

    /// The tags of the values of the child of vertex `v` into `tags` (one per value):
    /// this level's, the semi-sharp ones whose sharpness has decayed in the step from `p`
    /// to `c` become creases (OpenSubdiv's `FVarRefinement::reclassifySemisharpValues`,
    /// with smooth face-varying boundaries; with linear ones they are corners and stay).
    fn child_vertex_tags(&self, p: &Topology, c: &Topology, v: usize, tags: &mut [ValueTag]) {
        let slots = self.slots(v);
        tags.copy_from_slice(&self.tags[slots.clone()]);
        if self.mode.linear_boundaries || !tags[0].mismatch {
            return;
        }
        let (pt, ct) = (p.vert_tags[v].get(), c.vert_tags[v].get());
        if (!pt.semi_sharp && !pt.semi_sharp_edges) || ct.semi_sharp || ct.inf_sharp {
            return;
        }
        let to_crease = |t: &mut ValueTag| {
            t.semi_sharp = false;
            t.dep_sharp = false;
            t.crease = true;
        };
        if !ct.semi_sharp_edges {
            for t in tags.iter_mut() {
                if t.semi_sharp {
                    to_crease(t);
                }
            }
            return;
        }
        let s = p.face_verts.len();
        let (edges, locals) = (p.vertex_edges(v), p.vertex_edge_locals(v));
        let child_semi = |k: usize| {
            sharp::is_semi_sharp(c.edge_sharpness[s + 2 * edges[k] as usize + locals[k] as usize])
        };
        for (t, &ends) in tags.iter_mut().zip(&self.ends[slots]) {
            if !t.semi_sharp || t.dep_sharp {
                continue;
            }
            let [a, b] = ends.map(usize::from);
            let still = if b > a {
                (a + 1..=b).any(child_semi)
            } else if a > b {
                (a + 1..edges.len()).chain(0..=b).any(child_semi)
            } else {
                false
            };
            if !still {
                to_crease(t);
            }
        }
        if tags.len() == 2 && self.mode.dependent {
            if tags[0].dep_sharp && !tags[1].semi_sharp {
                tags[0].dep_sharp = false;
            } else if tags[1].dep_sharp && !tags[0].semi_sharp {
                tags[1].dep_sharp = false;
            }
        }
    }
}

/// Runs `f(range, piece)` over `0..n` cut into ranges ([`chunk_ranges`]), `out` cut into
/// the pieces that the ranges write ([`split_pieces`]: piece of `range` from
/// `start(range.start)` on), in parallel when large.
fn for_pieces<T: Send>(
    n: usize,
    out: &mut [T],
    start: impl Fn(usize) -> usize,
    f: impl Fn(Range<usize>, &mut [T]) + Sync + Send,
) {
    let ranges = chunk_ranges(n);
    let pieces = split_pieces(out, &ranges, start);
    run(ranges.into_iter().zip(pieces).collect(), |(r, piece)| {
        f(r, piece)
    });
}

/// `f` of every range, in parallel when there is more than one.
fn map_ranges<T: Send>(
    ranges: &[Range<usize>],
    f: impl Fn(Range<usize>) -> T + Sync + Send,
) -> Vec<T> {
    if ranges.len() <= 1 {
        ranges.iter().cloned().map(f).collect()
    } else {
        ranges.par_iter().cloned().map(f).collect()
    }
}

/// The weight of each end value in the limit of a face-varying crease value: OpenSubdiv's
/// `PrimvarRefiner::LimitFaceVarying` writes the literal `1.0f/6.0f`, a single-precision ⅙
/// (`0.1666666716…`), and `2.0f/3.0f` for the value itself, so its weights sum to
/// `1 + 2.98e-8`, not 1. They are used as they are, so that `subdivide`'s limit of
/// face-varying values is OpenSubdiv's to rounding (tests/golden/fvar_limit); the exact
/// crease limit (weights ⅙, ⅔) differs from it by up to 3e-8 of the values' size.
/// [`crate::limit::FaceVaryingSurface`] evaluates the exact limit.
const CREASE_LIMIT_END: f64 = (1.0f32 / 6.0f32) as f64;
/// The weight of the value itself in the limit of a face-varying crease value: OpenSubdiv's
/// single-precision `2.0f/3.0f` (see [`CREASE_LIMIT_END`]).
const CREASE_LIMIT_CENTRE: f64 = (2.0f32 / 3.0f32) as f64;

impl FvarLevel {
    /// The limit of the values `src` (`dim` numbers each, indexed as this level indexes
    /// them) into `dst` (a copy of `src` on entry), by OpenSubdiv's
    /// `PrimvarRefiner::LimitFaceVarying`: values of a linear channel, and of isolated
    /// vertices, stay; a vertex whose values match its vertex topology takes the scheme's
    /// limit mask of its vertex rule ([`catmark::limit_position_mask`]: the faces' opposite
    /// values, the edges' far values, the value itself); otherwise each of its values is a
    /// corner, which stays, or a crease, whose limit is `⅔ v + ⅙ (a + b)` with `a`, `b` the
    /// boundary values next to it (the crease's B-spline limit), with OpenSubdiv's single
    /// precision weights ([`CREASE_LIMIT_END`]). `t` is the level's topology, complete, with
    /// quads around every vertex (every level after the first).
    fn limit<R: Rules>(&self, rules: R, t: &Topology, dim: usize, src: &[f64], dst: &mut [f64]) {
        let val = |i: u32| &src[dim * i as usize..dim * (i as usize + 1)];
        let (mut mask, mut sharp) = (VertexMask::default(), Vec::new());
        for v in 0..t.num_vertices() {
            let slots = self.slots(v);
            if self.mode.linear || t.vertex_edges(v).is_empty() {
                continue;
            }
            if !self.tags[slots.start].mismatch {
                let x = self.slot_value(slots.start) as usize;
                let mut out = vec![0.0; dim];
                sharp.clear();
                sharp.extend(
                    t.vertex_edges(v)
                        .iter()
                        .map(|&e| t.edge_sharpness[e as usize]),
                );
                let faces = t.vertex_faces(v);
                let rule = t.vertex_tag(v).rule;
                rules.limit_position_mask(rule, &sharp, faces.len(), &mut mask);
                if mask.has_faces {
                    let locals = t.vertex_face_locals(v);
                    for ((&f, &l), &w) in faces.iter().zip(locals).zip(&mask.faces) {
                        axpy(
                            &mut out,
                            w,
                            val(self.face_value(t, f as usize, l as usize + 2)),
                        );
                    }
                }
                if mask.has_edges {
                    for (i, &w) in mask.edges.iter().enumerate() {
                        axpy(&mut out, w, val(self.vertex_edge_value(t, v, i)));
                    }
                }
                axpy(&mut out, mask.vertex, val(x as u32));
                dst[dim * x..dim * (x + 1)].copy_from_slice(&out);
                continue;
            }
            for (k, slot) in slots.enumerate() {
                if self.tags[slot].is_corner() {
                    continue;
                }
                let x = self.slot_value(slot) as usize;
                let [a, b] = self.crease_end_values(t, v, k);
                let out = &mut dst[dim * x..dim * (x + 1)];
                out.fill(0.0);
                axpy(out, CREASE_LIMIT_END, val(a));
                axpy(out, CREASE_LIMIT_END, val(b));
                axpy(out, CREASE_LIMIT_CENTRE, val(x as u32));
            }
        }
    }
}

/// The number of child vertices of the faces of `p`: one per face with the quad split,
/// none with the triangle split.
fn face_children(p: &Topology, triangles: bool) -> usize {
    if triangles {
        0
    } else {
        p.num_faces()
    }
}

/// `acc += w · x` over `dim` components.
#[inline(always)]
fn axpy(acc: &mut [f64], w: f64, x: &[f64]) {
    for (a, &b) in acc.iter_mut().zip(x) {
        *a += w * b;
    }
}

/// Refines the values `src` (`dim` numbers each, indexed as level `pf` of topology `p`
/// indexes them) to the values of `cf`, the refinement of `pf` onto `c` (the refinement
/// of `p`), returned (`dim · cf.num_slots()` numbers): OpenSubdiv's
/// `PrimvarRefiner::InterpolateFaceVarying` with the masks of `rules` (face points, then
/// edge and vertex points, which read them). With a scheme that splits triangles (Loop,
/// [`Rules::splits_triangles`]) there are no face points, and the face weights of an edge
/// mask weigh each triangle's value opposite the edge. Large levels are interpolated in
/// parallel over ranges of faces, edges and vertices (each value is computed by the same
/// operations whatever the ranges).
#[allow(clippy::too_many_arguments)]
pub(crate) fn interpolate<R: Rules>(
    p: &Topology,
    c: &Topology,
    pf: &FvarLevel,
    cf: &FvarLevel,
    options: &Options,
    rules: R,
    dim: usize,
    src: &[f64],
) -> Vec<f64> {
    // Values of one to three numbers (texture coordinates, colours) have their size
    // known to the compiler.
    macro_rules! pass {
        ($d:literal) => {
            FvarPass::<R, $d> {
                p,
                c,
                pf,
                cf,
                options,
                rules,
                dim,
                src,
            }
            .run()
        };
    }
    match dim {
        1 => pass!(1),
        2 => pass!(2),
        3 => pass!(3),
        _ => pass!(0),
    }
}

/// Scratch space of [`FvarPass::split_vertex_points`]: the child's tags of a vertex's
/// values, and the sharpness of the edges of a crease span before and after the step.
#[derive(Default)]
struct SplitScratch {
    tags: Vec<ValueTag>,
    sharpness: (Vec<f32>, Vec<f32>),
}

/// What every pass of [`interpolate`] reads: the parent and child topologies and
/// face-varying levels, the options, the scheme's rules, and the parent's values
/// (`dim` numbers each; `D` is `dim` when not 0).
struct FvarPass<'a, R, const D: usize> {
    p: &'a Topology,
    c: &'a Topology,
    pf: &'a FvarLevel,
    cf: &'a FvarLevel,
    options: &'a Options,
    rules: R,
    dim: usize,
    src: &'a [f64],
}

impl<R: Rules, const D: usize> FvarPass<'_, R, D> {
    /// The numbers per value.
    #[inline(always)]
    fn d(&self) -> usize {
        if D == 0 {
            self.dim
        } else {
            D
        }
    }

    /// The parent's value `i`.
    #[inline(always)]
    fn val(&self, i: u32) -> &[f64] {
        let d = self.d();
        &self.src[d * i as usize..][..d]
    }

    /// The child values, in their order: the vertex points, the face points and the edge
    /// points, each appended as it is computed ([`append_pieces`]: no array is zeroed
    /// first). The others read the face points (unless the channel is linear), which are
    /// then computed first, aside. The vertex children of a linear channel below the base
    /// level keep their parent's values, slot for slot, and are copied.
    fn run(&self) -> Vec<f64> {
        let (p, pf, d) = (self.p, self.pf, self.d());
        let offsets = &self.cf.vert_offsets;
        let (nv, ne) = (p.num_vertices(), p.num_edges());
        let nf = face_children(p, self.rules.splits_triangles());
        let face0 = offsets[nv] as usize;
        let edge0 = offsets[nv + nf] as usize;
        let total = d * self.cf.num_slots();
        let face_points = |out: &mut Vec<f64>| {
            append_pieces(
                out,
                d * nf,
                nf,
                |f| d * f,
                |r, out| self.face_points(r, out),
            )
        };
        let linear = pf.mode.linear;
        let mut faces = Vec::new();
        if !linear {
            face_points(&mut faces);
        }
        let mut dst = Vec::with_capacity(total);
        if linear && pf.slot_values.is_none() {
            debug_assert_eq!(pf.num_slots(), face0);
            dst.extend_from_slice(&self.src[..d * face0]);
        } else {
            let start = |v: usize| d * offsets[v] as usize;
            append_pieces(&mut dst, d * face0, nv, start, |r, out| {
                self.vertex_points(&faces, r, out)
            });
        }
        if linear {
            face_points(&mut dst);
        } else {
            dst.extend_from_slice(&faces);
        }
        let start = |e: usize| d * offsets[nv + nf + e] as usize;
        append_pieces(&mut dst, total - d * edge0, ne, start, |r, out| {
            self.edge_points(&faces, r, out)
        });
        dst
    }

    /// An accumulator of one value (`d` numbers, the first `d` of `buf`, whose length is
    /// then known to the compiler when `D` is).
    #[inline(always)]
    fn acc<'b>(&self, buf: &'b mut Vec<f64>) -> &'b mut [f64] {
        buf.resize(self.d(), 0.0);
        &mut buf[..self.d()]
    }

    /// The child values of the parent faces `range` (one per face; none with the triangle
    /// split), appended to `out`: the average of the face's values.
    fn face_points(&self, range: Range<usize>, out: &mut Appender<'_, f64>) {
        let p = self.p;
        let mut buf = Vec::new();
        let acc = self.acc(&mut buf);
        for f in range {
            acc.fill(0.0);
            let w = catmark::face_point_weight(p.face_vertices(f).len());
            let o = p.face_offsets[f] as usize..p.face_offsets[f + 1] as usize;
            for &x in &self.pf.face_values[o] {
                axpy(acc, 1.0, self.val(x));
            }
            acc.iter_mut().for_each(|x| *x *= w);
            out.push_slice(acc);
        }
    }

    /// The child values of the parent edges `range`, appended to `out`, given the face
    /// points `face_out`: the edge mask where the edge's values match across it, else
    /// (and for linear channels) each side's midpoint. The mask's face weights weigh the
    /// face points, or with the triangle split each triangle's value opposite the edge.
    fn edge_points(&self, face_out: &[f64], range: Range<usize>, out: &mut Appender<'_, f64>) {
        let (p, pf, d) = (self.p, self.pf, self.d());
        let triangles = self.rules.splits_triangles();
        let child0 = p.num_vertices() + face_children(p, triangles);
        let face_pt = |f: u32| &face_out[d * f as usize..][..d];
        let mut buf = Vec::new();
        let acc = self.acc(&mut buf);
        for e in range {
            // The child's values are split (`refine`'s tags).
            let et = pf.edge_tags[e];
            if et.mismatch || et.linear {
                debug_assert!(
                    !et.mismatch || {
                        let [a, b] = p.edge_verts[e].map(|v| pf.count(v as usize));
                        a + b > 2
                    }
                );
                for i in 0..self.cf.count(child0 + e) {
                    let [a, b] = if et.mismatch {
                        pf.face_edge_values(p, e, i)
                    } else {
                        pf.edge_face_values(p, e, i)
                    };
                    acc.fill(0.0);
                    axpy(acc, 0.5, self.val(a));
                    axpy(acc, 0.5, self.val(b));
                    out.push_slice(acc);
                }
                continue;
            }
            // A continuous edge's child has one value.
            acc.fill(0.0);
            let [a, b] = pf.edge_face_values(p, e, 0);
            if pf.mode.linear {
                axpy(acc, 0.5, self.val(a));
                axpy(acc, 0.5, self.val(b));
                out.push_slice(acc);
                continue;
            }
            let m = edge_mask_at(p, self.c, self.options, self.rules, e);
            axpy(acc, m.vertex, self.val(a));
            axpy(acc, m.vertex, self.val(b));
            if !m.is_crease() {
                for (j, &f) in p.edge_face_list(e).iter().enumerate() {
                    let w = if j < 2 { m.faces[j] } else { m.other_faces };
                    if triangles {
                        axpy(acc, w, self.val(pf.opposite_value(p, f as usize, e)));
                    } else {
                        axpy(acc, w, face_pt(f));
                    }
                }
            }
            out.push_slice(acc);
        }
    }

    /// The child values of the parent vertices `range`, appended to `out`, given the face
    /// points `face_out`: the vertex mask where the vertex's values match around it (one
    /// value), else [`split_vertex_points`](Self::split_vertex_points).
    fn vertex_points(&self, face_out: &[f64], range: Range<usize>, out: &mut Appender<'_, f64>) {
        let (p, pf, d) = (self.p, self.pf, self.d());
        let face_pt = |f: u32| &face_out[d * f as usize..][..d];
        let (mut mask, mut cmask) = (VertexMask::default(), VertexMask::default());
        let (mut pe, mut ce) = (Vec::new(), Vec::new());
        let mut scratch = SplitScratch::default();
        let mut buf = Vec::new();
        let acc = self.acc(&mut buf);
        for v in range {
            // The child of a vertex has its parent's values and their tags' `mismatch`.
            if pf.tags[pf.vert_offsets[v] as usize].mismatch {
                self.split_vertex_points(v, acc, out, &mut scratch);
                continue;
            }
            let pv = self.val(pf.slot_value(pf.slots(v).start));
            if pf.mode.linear || p.vertex_edges(v).is_empty() {
                out.push_slice(pv);
                continue;
            }
            acc.fill(0.0);
            let scratch = (&mut pe, &mut ce, &mut cmask);
            vertex_mask_at(p, self.c, self.options, self.rules, v, &mut mask, scratch);
            // Loop's vertex masks have no face weights (zero if set), and no face points.
            if mask.has_faces && !self.rules.splits_triangles() {
                for (&f, &w) in p.vertex_faces(v).iter().zip(&mask.faces) {
                    axpy(acc, w, face_pt(f));
                }
            }
            if mask.has_edges {
                for (i, &w) in mask.edges.iter().enumerate() {
                    axpy(acc, w, self.val(pf.vertex_edge_value(p, v, i)));
                }
            }
            axpy(acc, mask.vertex, pv);
            out.push_slice(acc);
        }
    }

    /// The child values of vertex `v`, whose values differ around it (one per value,
    /// appended to `out`; `acc` holds one value): each value a corner (kept) or a crease
    /// point between the values at the ends of its crease, semi-sharp ones blended toward
    /// the corner by the fractional weight.
    fn split_vertex_points(
        &self,
        v: usize,
        acc: &mut [f64],
        out: &mut Appender<'_, f64>,
        scratch: &mut SplitScratch,
    ) {
        let (p, pf) = (self.p, self.pf);
        let ps = pf.slots(v);
        let [end_w, centre_w, _] = self.rules.crease_vertex_weights();
        let child_tags = &mut scratch.tags;
        if !pf.mode.linear {
            child_tags.resize(ps.len(), ValueTag::default());
            pf.child_vertex_tags(p, self.c, v, child_tags);
        }
        for (k, pslot) in ps.clone().enumerate() {
            let pv = self.val(pf.slot_value(pslot));
            if pf.mode.linear || child_tags[k].is_corner() {
                out.push_slice(pv);
                continue;
            }
            let [a, b] = pf.crease_end_values(p, v, k);
            let (mut ew, mut vw) = (end_w, centre_w);
            let pt = pf.tags[pslot];
            if pt.semi_sharp {
                // A value sharpened by the other one decays with it.
                let from = if pt.dep_sharp {
                    ps.start + (1 - k)
                } else {
                    pslot
                };
                let sharpness = &mut scratch.sharpness;
                let corner = pf.fractional_weight(p, self.c, self.options, v, from, sharpness);
                vw = (1.0 - corner) * centre_w + corner;
                ew = (1.0 - corner) * end_w;
            }
            acc.fill(0.0);
            axpy(acc, ew, self.val(a));
            axpy(acc, ew, self.val(b));
            axpy(acc, vw, pv);
            out.push_slice(acc);
        }
    }
}

/// The face-varying channels of a mesh refined level by level next to its vertex
/// topology: each channel's current level (`FvarLevel`) and values.
#[derive(Clone, Debug)]
pub struct FaceVaryingRefiner {
    channels: Vec<(FvarLevel, Vec<f64>)>,
    names: Vec<(String, usize)>,
}

impl FaceVaryingRefiner {
    /// The base level of every channel of a mesh whose base topology is `base`.
    pub fn new(base: &Topology, channels: &[FaceVarying], options: &Options) -> Self {
        Self {
            channels: channels
                .iter()
                .map(|ch| {
                    (
                        FvarLevel::base(base, ch.indices(), options),
                        ch.values().to_vec(),
                    )
                })
                .collect(),
            names: channels
                .iter()
                .map(|ch| (ch.name().to_string(), ch.dim()))
                .collect(),
        }
    }

    /// Whether there are no channels.
    pub fn is_empty(&self) -> bool {
        self.channels.is_empty()
    }

    /// Refines every channel from `p` to `c` (the refinement of `p`, possibly built for
    /// output only) with the masks of `rules`: OpenSubdiv's
    /// `Far::PrimvarRefiner::InterpolateFaceVarying` (see the module docs). `c` is the
    /// quad split of `p` ([`crate::refine::TopologyRefiner`] with a scheme of the
    /// Catmull-Clark family or bilinear), or its triangle split when `rules` splits
    /// triangles (Loop, [`Rules::splits_triangles`]).
    ///
    /// # Panics
    /// If `c` does not have the vertex count of that split of `p` (`V + F + E`, or
    /// `V + E` for the triangle split).
    pub fn refine<R: Rules>(&mut self, p: &Topology, c: &Topology, options: &Options, rules: R) {
        let triangles = rules.splits_triangles();
        assert_eq!(
            c.num_vertices(),
            p.num_vertices() + face_children(p, triangles) + p.num_edges(),
            "the child level is not the refinement of the parent by the scheme's split"
        );
        for ((level, values), (_, dim)) in self.channels.iter_mut().zip(&self.names) {
            let child = level.refine(p, c, triangles);
            *values = interpolate(p, c, level, &child, options, rules, *dim, values);
            *level = child;
        }
    }

    /// Moves every channel's values to their limit (OpenSubdiv's
    /// `PrimvarRefiner::LimitFaceVarying`, see `FvarLevel::limit`), the channels being at
    /// level `last`, complete (built with its full adjacency). Where `last` has a face that
    /// is not a quad (the base level only), the limit masks, which assume quads, are
    /// applied one Catmull-Clark level further down, whose vertices' values are the
    /// children of `last`'s and have the same limit. The masks are `scheme`'s
    /// ([`Rules::limit_position_mask`]): Catmull-Clark's for the Catmull-Clark family
    /// (the adjustable scheme's limit is the Catmull-Clark limit of its last level), Loop's
    /// (on triangles, which need no further level) and bilinear's (the values themselves).
    ///
    /// # Panics
    /// With [`Scheme::Nurss`], which has no face-varying channels to move.
    pub fn limit(&mut self, scheme: Scheme, last: &Topology, options: &Options) {
        match scheme {
            Scheme::Loop => self.limit_with(Loop, last, options),
            Scheme::Bilinear => self.limit_with(Bilinear, last, options),
            Scheme::CatmullClark | Scheme::Adjustable(_) => {
                self.limit_with(CatmullClark, last, options)
            }
            Scheme::Nurss => panic!("NURSS has no face-varying limit masks"),
        }
    }

    /// [`limit`](Self::limit) with `rules`' masks.
    fn limit_with<R: Rules>(&mut self, rules: R, last: &Topology, options: &Options) {
        let all_quads = rules.splits_triangles()
            || (0..last.num_faces()).all(|f| last.face_vertices(f).len() == 4);
        let child = (!all_quads).then(|| super::refine_topology(last, options, true));
        for ((level, values), (_, dim)) in self.channels.iter_mut().zip(&self.names) {
            let dim = *dim;
            match &child {
                None => {
                    let mut lim = values.clone();
                    level.limit(rules, last, dim, values, &mut lim);
                    *values = lim;
                }
                Some(c) => {
                    let cl = level.refine(last, c, false);
                    let cv = interpolate(last, c, level, &cl, options, rules, dim, values);
                    let mut lim = cv.clone();
                    cl.limit(rules, c, dim, &cv, &mut lim);
                    // The first slots of the child level are the children of `last`'s
                    // vertices' values, in the same order.
                    for slot in 0..level.num_slots() {
                        let x = level.slot_value(slot) as usize;
                        values[dim * x..dim * (x + 1)]
                            .copy_from_slice(&lim[dim * slot..dim * (slot + 1)]);
                    }
                }
            }
        }
    }

    /// The channels of the last level `last`, their faces those of `last` that are kept:
    /// all of them with `keep_holes`, else those that are not holes (as the output mesh
    /// of [`crate::subdivide()`] keeps them).
    pub fn finish(self, last: &Topology, keep_holes: bool) -> Vec<FaceVarying> {
        self.channels
            .into_iter()
            .zip(self.names)
            .map(|((level, values), (name, dim))| {
                let indices = if keep_holes || !last.has_holes() {
                    level.face_values
                } else {
                    (0..last.num_faces())
                        .filter(|&f| !last.is_hole(f))
                        .flat_map(|f| {
                            let o =
                                last.face_offsets[f] as usize..last.face_offsets[f + 1] as usize;
                            level.face_values[o].iter().copied()
                        })
                        .collect()
                };
                FaceVarying::new_unchecked(name, dim, values, indices)
            })
            .collect()
    }
}
