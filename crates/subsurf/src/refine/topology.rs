//! One uniform Catmull-Clark topology step: the child [`Topology`] derived directly from
//! the parent's indices (no hashing), with tags and sharpness propagated as OpenSubdiv's
//! `Vtr::internal::Refinement` does.
//!
//! # Child numbering (OpenSubdiv's default order)
//! With `V`, `F`, `E` the parent's vertex, face and edge counts and `S` the total number
//! of face-vertices:
//! - vertices: the child of vertex `v` is `v`; of face `f` is `V + f`; of edge `e` is
//!   `V + F + e`;
//! - faces: the child of face `f` at its corner `j` is `face_offsets[f] + j`, a quad
//!   `[child of vertex j, child of edge j, child of f, child of edge j-1]`, rotated for
//!   parent quads so that its corner `j` is the vertex child (the parent's parametric
//!   orientation is kept);
//! - edges: `face_offsets[f] + j` joins the children of `f` and of its edge `j`;
//!   `S + 2e + k` joins the children of edge `e` and of its end `k`.

use std::mem::MaybeUninit;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

use crate::mesh::{
    CreaseMethod, Options, PackedEdgeTag, PackedVertexTag, Rule, Topology, VertexTag,
};
use crate::scheme::crease;

/// Rotation of the child quad at `corner` of a parent face of size `n`: child quads of
/// quads are rotated so that their corner `corner` is the parent vertex's child.
#[inline]
pub(super) fn rot(n: usize, corner: usize) -> usize {
    if n == 4 {
        corner
    } else {
        0
    }
}

/// Child edge of parent edge `e` at its end vertex `v`; `leaving` says whether a face
/// runs the edge away from `v` (which picks the child of a degenerate edge, whose two ends
/// are both `v`: the first child when leaving, the second when entering).
#[inline]
pub(super) fn edge_child_at(p: &Topology, s: u32, e: u32, v: u32, leaving: bool) -> u32 {
    let [a, b] = p.edge_verts[e as usize];
    let k = if a == b { !leaving } else { a != v };
    s + 2 * e + k as u32
}

// ---------------------------------------------------------------------------------------------
// Parallel passes
// ---------------------------------------------------------------------------------------------
//
// Every child element is a formula of parent indices, so each pass below runs over ranges of
// parent elements, and each range writes its own contiguous piece of every output array (the
// pieces are cut at the offsets that the formulas give). The result does not depend on how the
// ranges are cut or in which order they run: it is bit for bit the serial result. Small levels
// run on the calling thread.

/// Parent elements per parallel task.
pub(super) const CHUNK: usize = 4096;
/// Below this many elements a pass runs on the calling thread: sharing it would cost more
/// than it saves.
const PAR_MIN: usize = 16 * 1024;

/// Whether a pass over `n` elements should be shared between threads: when it is large
/// and the current rayon pool has more than one thread (with one, the serial loop is
/// cheaper than going through rayon).
pub(super) fn parallel(n: usize) -> bool {
    n >= PAR_MIN && rayon::current_num_threads() > 1
}

/// `0..n` cut into the ranges of parent elements that the tasks of a pass handle: `0..n`
/// itself when the pass is not [`parallel`], else ranges of `CHUNK`.
pub(super) fn chunk_ranges(n: usize) -> Vec<Range<usize>> {
    if !parallel(n) {
        std::iter::once(0..n).collect()
    } else {
        (0..n)
            .step_by(CHUNK)
            .map(|a| a..(a + CHUNK).min(n))
            .collect()
    }
}

/// Cuts `data` into consecutive pieces, one per range: piece `i` covers the output of
/// `ranges[i]`, which starts at `start(ranges[i].start)`; `data` starts at
/// `start(ranges[0].start)` and the last piece runs to its end.
pub(super) fn split_pieces<'a, T>(
    data: &'a mut [T],
    ranges: &[Range<usize>],
    start: impl Fn(usize) -> usize,
) -> Vec<&'a mut [T]> {
    let mut at = start(ranges[0].start);
    let mut rest = data;
    let mut pieces = Vec::with_capacity(ranges.len());
    for r in &ranges[1..] {
        let next = start(r.start);
        let (a, b) = std::mem::take(&mut rest).split_at_mut(next - at);
        pieces.push(a);
        rest = b;
        at = next;
    }
    pieces.push(rest);
    pieces
}

/// The next `len` elements of a vector, written in parallel pieces without being zeroed
/// first (zeroing an array that is written right after is a pass over memory as long as
/// the writing one) and then taken by the vector ([`finish`](Self::finish)).
///
/// The new elements are handed out once ([`all`](Self::all) or
/// [`split_at`](Self::split_at)) as [`Part`]s, each cut into [`Appender`]s
/// ([`Part::pieces`]), which pass the elements front to back. An appender dropped with its
/// piece written whole counts its length as written, so all `len` are written when the
/// count reaches `len`, which `finish` checks: a piece left short is a bug in the pass,
/// which panics there before the vector takes any new element.
pub(super) struct Fresh<T> {
    v: Vec<T>,
    len: usize,
    written: AtomicUsize,
    handed_out: bool,
}

/// A part of the elements of a [`Fresh`] vector.
pub(super) struct Part<'a, T> {
    buf: &'a mut [MaybeUninit<T>],
    written: &'a AtomicUsize,
}

/// A piece of a [`Part`], written front to back, one element after the other: what is
/// before its cursor is written.
pub(super) struct Appender<'a, T> {
    buf: &'a mut [MaybeUninit<T>],
    len: usize,
    written: &'a AtomicUsize,
}

impl<T: Copy> Fresh<T> {
    /// `len` new elements after those of `v`.
    pub(super) fn after(mut v: Vec<T>, len: usize) -> Self {
        v.reserve(len);
        Self {
            v,
            len,
            written: AtomicUsize::new(0),
            handed_out: false,
        }
    }

    /// `len` elements of a new vector.
    pub(super) fn new(len: usize) -> Self {
        Self::after(Vec::new(), len)
    }

    /// The new elements, all of them.
    pub(super) fn all(&mut self) -> Part<'_, T> {
        assert!(!self.handed_out, "the elements are handed out once");
        self.handed_out = true;
        Part {
            buf: &mut self.v.spare_capacity_mut()[..self.len],
            written: &self.written,
        }
    }

    /// The new elements, cut at `mid`.
    pub(super) fn split_at(&mut self, mid: usize) -> (Part<'_, T>, Part<'_, T>) {
        let Part { buf, written } = self.all();
        let (a, b) = buf.split_at_mut(mid);
        (Part { buf: a, written }, Part { buf: b, written })
    }

    /// The vector with its new elements, every piece of every part having been written
    /// whole.
    pub(super) fn finish(mut self) -> Vec<T> {
        assert_eq!(
            *self.written.get_mut(),
            self.len,
            "a piece of a pass was left short"
        );
        // SAFETY: the parts are disjoint (one `all` or `split_at` of the `len` elements
        // after the end of `v`, within the capacity reserved), their pieces disjoint
        // (`Part::pieces` consumes the part), and each piece added its length to `written`
        // only once written whole: a sum of `len` means all `len` are initialised.
        unsafe { self.v.set_len(self.v.len() + self.len) };
        self.v
    }
}

impl<'a, T> Part<'a, T> {
    /// The part cut into consecutive pieces, one per range ([`split_pieces`]: the piece
    /// of `ranges[i]` from `start(ranges[i].start) - start(ranges[0].start)` on, the last
    /// one to the end of the part).
    pub(super) fn pieces(
        self,
        ranges: &[Range<usize>],
        start: impl Fn(usize) -> usize,
    ) -> Vec<Appender<'a, T>> {
        let written = self.written;
        split_pieces(self.buf, ranges, start)
            .into_iter()
            .map(|buf| Appender {
                buf,
                len: 0,
                written,
            })
            .collect()
    }
}

impl<T: Copy> Appender<'_, T> {
    /// Writes `x` at the cursor, which moves on by one.
    #[inline(always)]
    pub(super) fn push(&mut self, x: T) {
        self.buf[self.len].write(x);
        self.len += 1;
    }

    /// Writes `xs` at the cursor, which moves on by their number.
    #[inline(always)]
    pub(super) fn push_slice(&mut self, xs: &[T]) {
        let out = &mut self.buf[self.len..self.len + xs.len()];
        for (o, &x) in out.iter_mut().zip(xs) {
            o.write(x);
        }
        self.len += xs.len();
    }
}

impl<T> Drop for Appender<'_, T> {
    fn drop(&mut self) {
        if self.len == self.buf.len() {
            self.written.fetch_add(self.len, Ordering::Relaxed);
        }
    }
}

/// Appends `len` elements to `v` ([`Fresh`]): cut into the pieces of the ranges of `0..n`
/// ([`Part::pieces`] with `start`), each written by `f(range, piece)`, in parallel when
/// large.
pub(super) fn append_pieces<T: Copy + Send + Sync>(
    v: &mut Vec<T>,
    len: usize,
    n: usize,
    start: impl Fn(usize) -> usize,
    f: impl Fn(Range<usize>, &mut Appender<'_, T>) + Sync + Send,
) {
    let mut fresh = Fresh::after(std::mem::take(v), len);
    let ranges = chunk_ranges(n);
    let pieces = fresh.all().pieces(&ranges, start);
    run(ranges.into_iter().zip(pieces).collect(), |(r, mut out)| {
        f(r, &mut out)
    });
    *v = fresh.finish();
}

/// Runs `f` on every item, in parallel when there is more than one.
pub(super) fn run<I: Send>(items: Vec<I>, f: impl Fn(I) + Sync + Send) {
    if items.len() <= 1 {
        items.into_iter().for_each(f);
    } else {
        items.into_par_iter().for_each(f);
    }
}

/// `(0..n).map(f).collect()`, in parallel when large (writing straight into the vector).
pub(super) fn collect<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
    if !parallel(n) {
        (0..n).map(f).collect()
    } else {
        (0..n).into_par_iter().with_min_len(CHUNK).map(f).collect()
    }
}

/// `v.extend((0..n).map(f))`, in parallel when large (writing straight into the vector).
pub(super) fn extend<T: Send>(v: &mut Vec<T>, n: usize, f: impl Fn(usize) -> T + Sync + Send) {
    if !parallel(n) {
        v.extend((0..n).map(f));
    } else {
        v.par_extend((0..n).into_par_iter().with_min_len(CHUNK).map(f));
    }
}

/// `vec![value; n]`, written in parallel when large.
pub(super) fn filled<T: Copy + Send + Sync>(n: usize, value: T) -> Vec<T> {
    if !parallel(n) {
        vec![value; n]
    } else {
        (0..n)
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|_| value)
            .collect()
    }
}

/// `(0..n).map(f).max()` (0 when empty), in parallel when large.
fn max_of(n: usize, f: impl Fn(usize) -> usize + Sync + Send) -> usize {
    if !parallel(n) {
        (0..n).map(f).max().unwrap_or(0)
    } else {
        (0..n)
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(f)
            .max()
            .unwrap_or(0)
    }
}

// ---------------------------------------------------------------------------------------------
// Refinement
// ---------------------------------------------------------------------------------------------

/// Refines `p` one level: the child's topology, tags and sharpness. With `full == false`
/// only what is needed to interpolate into the child and to write it out is built (faces,
/// edges' vertices, tags and sharpness), not the relations needed to refine it further or
/// to evaluate limit masks on it (face → edges, edge → faces, vertex → faces and edges);
/// OpenSubdiv skips the same work for the last level.
///
/// Large levels are refined in parallel (on the current rayon pool) over ranges of parent
/// faces, edges and vertices; the result is identical whatever the number of threads.
pub(crate) fn refine_topology(p: &Topology, options: &Options, full: bool) -> Topology {
    refine(p, options, full, true)
}

/// [`refine_topology`] with `full == false` and without the child's edge → vertices
/// relation (`edge_verts` is left empty, so `num_edges()` is 0, while edge tags and
/// sharpness are there): for the last level of [`subdivide`](fn@crate::subdivide), whose only
/// use of child edge vertices is the output's crease tags, which it reads from the parent
/// (the child edge `S + 2e + k` joins `V + F + e` and the end `k` of parent edge `e`;
/// the edges inside parent faces are never sharp). This saves 8 bytes per child edge
/// (61 MB at level 6 of `catmark_bishop`), written to fresh memory.
pub(crate) fn refine_topology_for_output(p: &Topology, options: &Options) -> Topology {
    refine(p, options, false, false)
}

/// [`refine_topology`], with or without `edge_verts`.
fn refine(p: &Topology, options: &Options, full: bool, with_edge_verts: bool) -> Topology {
    let faces = child_faces(p, full, with_edge_verts);
    let mut child = child_topology(p, options, p.num_faces(), faces, full);
    if full {
        build_relations(p, &mut child);
    }
    child
}

/// The arrays of a child topology that a split computes itself (the tags, sharpness and
/// relations follow from them and the parent): face → vertices and face → edges (empty when
/// not built), face holes and edge → vertices (empty when not built).
pub(super) struct ChildFaces {
    pub(super) face_offsets: Vec<u32>,
    pub(super) face_verts: Vec<u32>,
    pub(super) face_edges: Vec<u32>,
    pub(super) face_holes: Vec<bool>,
    pub(super) edge_verts: Vec<[u32; 2]>,
}

/// The child [`Topology`] of `p` with the split's `faces`: tags and sharpness propagated
/// ([`child_edge_tags`], [`child_vertex_tags`]), relations not built. `face_children` is
/// the number of face children (`F` for the quad split, 0 for the triangle split), which
/// come between the vertex and the edge children; `complete` says whether the caller
/// builds the relations.
pub(super) fn child_topology(
    p: &Topology,
    options: &Options,
    face_children: usize,
    faces: ChildFaces,
    complete: bool,
) -> Topology {
    let (edge_tags, edge_sharpness) = child_edge_tags(p, options.crease_method);
    let (vert_tags, vert_sharpness) = child_vertex_tags(p, &edge_tags, face_children);
    Topology {
        num_vertices: (p.num_vertices() + face_children + p.num_edges()) as u32,
        face_offsets: faces.face_offsets,
        face_verts: faces.face_verts,
        face_edges: faces.face_edges,
        face_holes: faces.face_holes,
        edge_verts: faces.edge_verts,
        edge_sharpness,
        vert_sharpness,
        edge_tags,
        vert_tags,
        has_holes: p.has_holes,
        complete,
        ..Topology::default()
    }
}

/// The child faces of the quad split (every child is a quad), their holes, and when asked
/// their edges (`full`) and the child's edge → vertices (`with_edge_verts`): the edges
/// inside each parent face, then the two halves of each parent edge.
fn child_faces(p: &Topology, full: bool, with_edge_verts: bool) -> ChildFaces {
    let nf = p.num_faces();
    let s = p.face_verts.len();
    let cne = s + 2 * p.num_edges();
    let fo = |f: usize| p.face_offsets[f] as usize;
    // An array that is not built has empty pieces.
    let fo_if = |built: bool| move |f: usize| if built { fo(f) } else { 0 };

    let face_offsets = collect(s + 1, |i| 4 * i as u32);
    let mut face_verts = Fresh::new(4 * s);
    let mut face_edges = Fresh::new(if full { 4 * s } else { 0 });
    let mut face_holes = Fresh::new(s);
    let mut edge_verts = Fresh::new(if with_edge_verts { cne } else { 0 });
    let (ev_faces, ev_edges) = edge_verts.split_at(if with_edge_verts { s } else { 0 });
    let ranges = chunk_ranges(nf);
    let fv = face_verts.all().pieces(&ranges, |f| 4 * fo(f));
    let fe = face_edges.all().pieces(&ranges, |f| 4 * fo_if(full)(f));
    let fh = face_holes.all().pieces(&ranges, fo);
    let ev = ev_faces.pieces(&ranges, fo_if(with_edge_verts));
    let items: Vec<_> = ranges
        .into_iter()
        .zip(fv)
        .zip(fe)
        .zip(fh)
        .zip(ev)
        .map(|((((r, verts), edges), holes), edge_verts)| {
            let out = FacePiece {
                verts,
                edges,
                holes,
                edge_verts,
            };
            (r, out)
        })
        .collect();
    run(items, |(range, out)| {
        fill_face_children(p, range, out, full, with_edge_verts)
    });
    if with_edge_verts {
        append_edge_halves(p, (p.num_vertices() + nf) as u32, ev_edges);
    }
    ChildFaces {
        face_offsets,
        face_verts: face_verts.finish(),
        face_edges: face_edges.finish(),
        face_holes: face_holes.finish(),
        edge_verts: edge_verts.finish(),
    }
}

/// The pieces of the child's face arrays that one range of parent faces writes.
struct FacePiece<'a> {
    verts: Appender<'a, u32>,
    edges: Appender<'a, u32>,
    holes: Appender<'a, bool>,
    edge_verts: Appender<'a, [u32; 2]>,
}

/// The child quads of the parent faces `range` (vertices, edges when `full`, holes) and the
/// child edges inside them (edge → vertices when `with_edge_verts`), appended to `out`.
fn fill_face_children(
    p: &Topology,
    range: Range<usize>,
    mut out: FacePiece<'_>,
    full: bool,
    with_edge_verts: bool,
) {
    let s = p.face_verts.len();
    let nv = p.num_vertices();
    let (fc0, ec0) = (nv as u32, (nv + p.num_faces()) as u32);
    for f in range {
        let o = p.face_offsets[f] as usize;
        let pfv = p.face_vertices(f);
        let pfe = p.face_edge_list(f);
        let n = pfv.len();
        let hole = p.face_holes[f];
        for j in 0..n {
            let jp = if j == 0 { n - 1 } else { j - 1 };
            let v = pfv[j];
            // Corner `k` goes to `(k + rot) % 4`.
            let r = 4 - rot(n, j);
            let verts = [v, ec0 + pfe[j], fc0 + f as u32, ec0 + pfe[jp]];
            out.verts
                .push_slice(&[0, 1, 2, 3].map(|i| verts[(i + r) % 4]));
            if full {
                let edges = [
                    edge_child_at(p, s as u32, pfe[j], v, true),
                    (o + j) as u32,
                    (o + jp) as u32,
                    edge_child_at(p, s as u32, pfe[jp], v, false),
                ];
                out.edges
                    .push_slice(&[0, 1, 2, 3].map(|i| edges[(i + r) % 4]));
            }
            out.holes.push(hole);
            if with_edge_verts {
                out.edge_verts.push([fc0 + f as u32, ec0 + pfe[j]]);
            }
        }
    }
}

/// Edge → vertices of the two halves of every parent edge `e` (child edges `S + 2e + k`,
/// joining the child of `e`, numbered `ec0 + e`, and the child of its end `k`), written into
/// `out` (`2E` entries).
pub(super) fn append_edge_halves(p: &Topology, ec0: u32, out: Part<'_, [u32; 2]>) {
    let ranges = chunk_ranges(p.num_edges());
    let pieces = out.pieces(&ranges, |e| 2 * e);
    run(
        ranges.into_iter().zip(pieces).collect(),
        |(range, mut out)| {
            for e in range {
                let [a, b] = p.edge_verts[e];
                out.push_slice(&[[ec0 + e as u32, a], [ec0 + e as u32, b]]);
            }
        },
    );
}

/// Tags and sharpness of the child edges (OpenSubdiv's `propagateComponentTags` and
/// `subdivideEdgeSharpness`): edges inside parent faces are smooth; the halves of a parent
/// edge inherit its tag, and semi-sharp ones decay.
pub(super) fn child_edge_tags(
    p: &Topology,
    method: CreaseMethod,
) -> (Vec<PackedEdgeTag>, Vec<f32>) {
    let s = p.face_verts.len();
    let ne = p.num_edges();
    let mut tags = filled(s + 2 * ne, PackedEdgeTag::default());
    let mut sharpness = vec![0.0f32; s + 2 * ne];
    let ranges = chunk_ranges(ne);
    let t = split_pieces(&mut tags[s..], &ranges, |e| 2 * e);
    let sh = split_pieces(&mut sharpness[s..], &ranges, |e| 2 * e);
    run(
        ranges.into_iter().zip(t).zip(sh).collect(),
        |((range, t), sh)| {
            let mut incident = Vec::new();
            let base = range.start;
            for e in range {
                if p.edge_tags[e] == PackedEdgeTag::default() {
                    // Smooth, manifold and interior: so are both halves.
                    continue;
                }
                let tag = p.edge_tags[e].get();
                let ps = p.edge_sharpness[e];
                for k in 0..2 {
                    let mut ctag = tag;
                    let cs = if tag.inf_sharp {
                        crease::SHARPNESS_INFINITE
                    } else if tag.semi_sharp {
                        let cs = if method == CreaseMethod::Uniform {
                            crease::decrement(ps)
                        } else {
                            let v = p.edge_verts[e][k] as usize;
                            incident.clear();
                            incident.extend(
                                p.vertex_edges(v)
                                    .iter()
                                    .map(|&x| p.edge_sharpness[x as usize]),
                            );
                            crease::subdivide_edge_sharpness(method, ps, &incident)
                        };
                        if !crease::is_sharp(cs) {
                            ctag.semi_sharp = false;
                        }
                        cs
                    } else {
                        0.0
                    };
                    let i = 2 * (e - base) + k;
                    t[i] = ctag.into();
                    sh[i] = cs;
                }
            }
        },
    );
    (tags, sharpness)
}

/// Tags and sharpness of the child vertices, given the child edges' tags (OpenSubdiv's
/// `propagateComponentTags`, `subdivideVertexSharpness`, `reclassifySemisharpVertices`):
/// vertex children inherit and decay, and are re-classified where sharp features decayed;
/// face children are smooth; edge children are creases where the edge was sharp.
/// `nf` is the number of face children, which come between the vertex and the edge
/// children: one per parent face for quad splits, none for triangle splits.
pub(super) fn child_vertex_tags(
    p: &Topology,
    edge_tags: &[PackedEdgeTag],
    nf: usize,
) -> (Vec<PackedVertexTag>, Vec<f32>) {
    let nv = p.num_vertices();
    let ne = p.num_edges();
    let s = p.face_verts.len();
    let mut tags = filled(nv + nf + ne, PackedVertexTag::default());
    let mut sharpness = vec![0.0f32; nv + nf + ne];
    let (of_verts, rest) = tags.split_at_mut(nv);
    let of_edges = &mut rest[nf..];

    // Children of vertices.
    let ranges = chunk_ranges(nv);
    let t = split_pieces(of_verts, &ranges, |v| v);
    let sh = split_pieces(&mut sharpness[..nv], &ranges, |v| v);
    run(
        ranges.into_iter().zip(t).zip(sh).collect(),
        |((range, t), sh)| {
            let base = range.start;
            for v in range {
                if p.vert_tags[v] == PackedVertexTag::default() {
                    continue;
                }
                let pt = p.vert_tags[v].get();
                let mut tag = pt;
                let cs = if pt.inf_sharp {
                    crease::SHARPNESS_INFINITE
                } else if pt.semi_sharp {
                    let cs = crease::decrement(p.vert_sharpness[v]);
                    if !crease::is_sharp(cs) {
                        tag.semi_sharp = false;
                    }
                    cs
                } else {
                    0.0
                };
                // Re-classify vertex children whose sharp features decayed.
                let decayed = pt.semi_sharp && !tag.semi_sharp;
                if pt.semi_sharp_edges || decayed {
                    let (mut inf, mut semi) = (0, 0);
                    for (&pe, &l) in p.vertex_edges(v).iter().zip(p.vertex_edge_locals(v)) {
                        let t = edge_tags[s + 2 * pe as usize + l as usize].get();
                        inf += t.inf_sharp as usize;
                        semi += t.semi_sharp as usize;
                    }
                    tag.semi_sharp_edges = semi > 0;
                    if !tag.semi_sharp && !tag.inf_sharp {
                        tag.rule = crease::vertex_rule(0.0, inf + semi);
                    }
                }
                t[v - base] = tag.into();
                sh[v - base] = cs;
            }
        },
    );

    // Children of faces are smooth (the default); children of edges are creases where the
    // edge was sharp.
    let ranges = chunk_ranges(ne);
    let t = split_pieces(of_edges, &ranges, |e| e);
    run(ranges.into_iter().zip(t).collect(), |(range, t)| {
        let base = range.start;
        for e in range {
            if p.edge_tags[e] == PackedEdgeTag::default() {
                continue;
            }
            let et = p.edge_tags[e].get();
            let mut tag = VertexTag {
                non_manifold: et.non_manifold,
                boundary: et.boundary,
                semi_sharp_edges: et.semi_sharp,
                inf_sharp_edges: et.inf_sharp,
                rule: if et.semi_sharp || et.inf_sharp {
                    Rule::Crease
                } else {
                    Rule::Smooth
                },
                ..VertexTag::default()
            };
            if tag.semi_sharp_edges {
                let count = edge_tags[s + 2 * e].get().semi_sharp as usize
                    + edge_tags[s + 2 * e + 1].get().semi_sharp as usize;
                tag.semi_sharp_edges = count > 0;
                tag.rule = crease::vertex_rule(0.0, count);
            }
            t[e - base] = tag.into();
        }
    });
    (tags, sharpness)
}

/// The child's edge → faces and vertex → faces/edges relations, in rotational order, and
/// its maximum valence.
fn build_relations(p: &Topology, c: &mut Topology) {
    debug_assert!(
        p.edge_face_offsets[0] == 0 && p.vert_face_offsets[0] == 0 && p.vert_edge_offsets[0] == 0
    );
    let (edge_face_offsets, edge_faces, edge_face_local) = child_edge_faces(p);
    c.edge_face_offsets = edge_face_offsets;
    c.edge_faces = edge_faces;
    c.edge_face_local = edge_face_local;
    child_vertex_relations(p, c);
    c.max_valence = child_max_valence(p);
}

/// Start of child edge `ce`'s faces in the child's edge → faces relation, with `S` face
/// corners in the parent: the child edge `ce < S` inside a parent face lies in two child
/// faces; each half `S + 2e + k` of parent edge `e` in as many as `e` has faces.
#[inline]
pub(super) fn child_edge_face_offset(pef: &[u32], s: usize, ce: usize) -> u32 {
    if ce <= s {
        2 * ce as u32
    } else {
        let i = ce - s;
        let e = i / 2;
        if i.is_multiple_of(2) {
            2 * s as u32 + 2 * pef[e]
        } else {
            2 * s as u32 + pef[e] + pef[e + 1]
        }
    }
}

/// The child's edge → faces relation (offsets, faces, and the edge's position in each
/// face): the edges inside parent faces, then the halves of parent edges.
fn child_edge_faces(p: &Topology) -> (Vec<u32>, Vec<u32>, Vec<u16>) {
    let ne = p.num_edges();
    let s = p.face_verts.len();
    let pef = &p.edge_face_offsets;
    let mut offsets = Vec::with_capacity(s + 2 * ne + 1);
    extend(&mut offsets, s + 1, |ce| 2 * ce as u32);
    extend(&mut offsets, 2 * ne, |i| {
        child_edge_face_offset(pef, s, s + 1 + i)
    });
    let nef = offsets[s + 2 * ne] as usize;
    let mut faces = vec![0u32; nef];
    let mut local = vec![0u16; nef];
    let (ef_in, ef_halves) = faces.split_at_mut(2 * s);
    let (efl_in, efl_halves) = local.split_at_mut(2 * s);

    let fo = |f: usize| 2 * p.face_offsets[f] as usize;
    let ranges = chunk_ranges(p.num_faces());
    let a = split_pieces(ef_in, &ranges, fo);
    let b = split_pieces(efl_in, &ranges, fo);
    run(
        ranges.into_iter().zip(a).zip(b).collect(),
        |((range, ef), efl)| fill_inner_edge_faces(p, range, ef, efl),
    );

    let ranges = chunk_ranges(ne);
    let a = split_pieces(ef_halves, &ranges, |e| 2 * pef[e] as usize);
    let b = split_pieces(efl_halves, &ranges, |e| 2 * pef[e] as usize);
    run(
        ranges.into_iter().zip(a).zip(b).collect(),
        |((range, ef), efl)| fill_half_edge_faces(p, range, ef, efl),
    );
    (offsets, faces, local)
}

/// Edge → faces of the child edges inside the parent faces `range` (each in the child
/// faces at its two ends), written into `ef`/`efl`, which start at the first of them.
fn fill_inner_edge_faces(p: &Topology, range: Range<usize>, ef: &mut [u32], efl: &mut [u16]) {
    let fo = |f: usize| p.face_offsets[f] as usize;
    let base = 2 * fo(range.start);
    for f in range {
        let o = fo(f);
        let n = p.face_vertices(f).len();
        for j in 0..n {
            let ce = o + j;
            let jn = if j + 1 == n { 0 } else { j + 1 };
            let at = 2 * ce - base;
            ef[at] = ce as u32;
            efl[at] = ((1 + rot(n, j)) % 4) as u16;
            ef[at + 1] = (o + jn) as u32;
            efl[at + 1] = ((2 + rot(n, jn)) % 4) as u16;
        }
    }
}

/// Whether the half `k` of parent edge `ev` (its end `k`) lies at the start of the edge
/// in the parent face `fv`, where the edge is the face's edge `i` (a degenerate edge, both
/// ends the same vertex: its first half is at the start).
#[inline]
pub(super) fn half_at_start(ev: [u32; 2], fv: &[u32], i: usize, k: usize) -> bool {
    if ev[0] == ev[1] {
        k == 0
    } else {
        fv[i] == ev[k]
    }
}

/// Edge → faces of the halves of the parent edges `range` (each half in the child face
/// at its end in every face of the parent edge), written into `ef`/`efl`, which start at
/// the first of them.
fn fill_half_edge_faces(p: &Topology, range: Range<usize>, ef: &mut [u32], efl: &mut [u16]) {
    let s = p.face_verts.len();
    let pef = &p.edge_face_offsets;
    let base = child_edge_face_offset(pef, s, s + 2 * range.start) as usize;
    for e in range {
        let ev = p.edge_verts[e];
        let pfaces = p.edge_face_list(e);
        let plocal = &p.edge_face_local[pef[e] as usize..];
        for k in 0..2 {
            let first = child_edge_face_offset(pef, s, s + 2 * e + k) as usize - base;
            for (at, (pf, &i)) in (first..).zip(pfaces.iter().zip(plocal)) {
                let pf = *pf as usize;
                let fv = p.face_vertices(pf);
                let n = fv.len();
                let i = i as usize;
                let (corner, pos) = if half_at_start(ev, fv, i, k) {
                    (i, 0)
                } else {
                    ((i + 1) % n, 3)
                };
                ef[at] = p.face_offsets[pf] + corner as u32;
                efl[at] = ((pos + rot(n, corner)) % 4) as u16;
            }
        }
    }
}

/// Offsets of the child's vertex → faces and vertex → edges relations. Vertex children
/// keep their parent's counts, face children have the face's size, and edge children have
/// two faces per parent face and one edge per parent face plus two.
fn child_vertex_offsets(p: &Topology) -> (Vec<u32>, Vec<u32>) {
    let nv = p.num_vertices();
    let nf = p.num_faces();
    let ne = p.num_edges();
    let cnv = nv + nf + ne;
    let su = p.face_verts.len() as u32;
    let pef = &p.edge_face_offsets;
    let (pvf, pve) = (&p.vert_face_offsets, &p.vert_edge_offsets);
    let (vf_all, ve_all) = (pvf[nv], pve[nv]);
    // One group of children after the other (without branching per child).
    let mut vert_face_offsets = Vec::with_capacity(cnv + 1);
    extend(&mut vert_face_offsets, nv + 1, |v| pvf[v]);
    extend(&mut vert_face_offsets, nf, |f| {
        vf_all + p.face_offsets[f + 1]
    });
    extend(&mut vert_face_offsets, ne, |e| vf_all + su + 2 * pef[e + 1]);
    let mut vert_edge_offsets = Vec::with_capacity(cnv + 1);
    extend(&mut vert_edge_offsets, nv + 1, |v| pve[v]);
    extend(&mut vert_edge_offsets, nf, |f| {
        ve_all + p.face_offsets[f + 1]
    });
    extend(&mut vert_edge_offsets, ne, |e| {
        ve_all + su + pef[e + 1] + 2 * (e + 1) as u32
    });
    #[cfg(debug_assertions)]
    {
        // The same offsets, child by child.
        let vfo = |cv: usize| -> u32 {
            if cv <= nv {
                pvf[cv]
            } else if cv <= nv + nf {
                vf_all + p.face_offsets[cv - nv]
            } else {
                vf_all + su + 2 * pef[cv - nv - nf]
            }
        };
        let veo = |cv: usize| -> u32 {
            if cv <= nv {
                pve[cv]
            } else if cv <= nv + nf {
                ve_all + p.face_offsets[cv - nv]
            } else {
                let e = cv - nv - nf;
                ve_all + su + pef[e] + 2 * e as u32
            }
        };
        debug_assert!((0..=cnv).all(|cv| vert_face_offsets[cv] == vfo(cv)));
        debug_assert!((0..=cnv).all(|cv| vert_edge_offsets[cv] == veo(cv)));
    }
    (vert_face_offsets, vert_edge_offsets)
}

/// A piece of the child's vertex → faces and vertex → edges arrays, with the vertex's
/// position in each face and edge.
pub(super) struct VertexRelations<'a> {
    pub(super) faces: &'a mut [u32],
    pub(super) face_local: &'a mut [u16],
    pub(super) edges: &'a mut [u32],
    pub(super) edge_local: &'a mut [u8],
}

impl<'a> VertexRelations<'a> {
    /// `self` cut after its first `faces` face entries and `edges` edge entries.
    pub(super) fn split_at(self, faces: usize, edges: usize) -> (Self, Self) {
        let (f0, f1) = self.faces.split_at_mut(faces);
        let (fl0, fl1) = self.face_local.split_at_mut(faces);
        let (e0, e1) = self.edges.split_at_mut(edges);
        let (el0, el1) = self.edge_local.split_at_mut(edges);
        (
            VertexRelations {
                faces: f0,
                face_local: fl0,
                edges: e0,
                edge_local: el0,
            },
            VertexRelations {
                faces: f1,
                face_local: fl1,
                edges: e1,
                edge_local: el1,
            },
        )
    }

    /// `self` cut into one piece per range (as [`split_pieces`]): the piece of range `r`
    /// starts at face entry `face_start(r.start)` and edge entry `edge_start(r.start)`;
    /// each piece comes with its range.
    pub(super) fn pieces(
        self,
        ranges: Vec<Range<usize>>,
        face_start: impl Fn(usize) -> usize,
        edge_start: impl Fn(usize) -> usize,
    ) -> Vec<(Range<usize>, Self)> {
        let a = split_pieces(self.faces, &ranges, &face_start);
        let b = split_pieces(self.face_local, &ranges, &face_start);
        let c = split_pieces(self.edges, &ranges, &edge_start);
        let d = split_pieces(self.edge_local, &ranges, &edge_start);
        ranges
            .into_iter()
            .zip(a)
            .zip(b)
            .zip(c)
            .zip(d)
            .map(|((((r, faces), face_local), edges), edge_local)| {
                let piece = VertexRelations {
                    faces,
                    face_local,
                    edges,
                    edge_local,
                };
                (r, piece)
            })
            .collect()
    }
}

/// The child's vertex → faces and vertex → edges relations, in rotational order: the
/// children of vertices, then of faces, then of edges.
fn child_vertex_relations(p: &Topology, c: &mut Topology) {
    let nv = p.num_vertices();
    let s = p.face_verts.len();
    let (vert_face_offsets, vert_edge_offsets) = child_vertex_offsets(p);
    let cnv = vert_face_offsets.len() - 1;
    let mut vert_faces = vec![0u32; vert_face_offsets[cnv] as usize];
    let mut vert_face_local = vec![0u16; vert_faces.len()];
    let mut vert_edges = vec![0u32; vert_edge_offsets[cnv] as usize];
    let mut vert_edge_local = vec![0u8; vert_edges.len()];
    let all = VertexRelations {
        faces: &mut vert_faces,
        face_local: &mut vert_face_local,
        edges: &mut vert_edges,
        edge_local: &mut vert_edge_local,
    };
    let (pvf, pve) = (&p.vert_face_offsets, &p.vert_edge_offsets);
    let (of_vertices, rest) = all.split_at(pvf[nv] as usize, pve[nv] as usize);
    let (of_faces, of_edges) = rest.split_at(s, s);

    let items = of_vertices.pieces(chunk_ranges(nv), |v| pvf[v] as usize, |v| pve[v] as usize);
    run(items, |(range, out)| fill_vertex_children(p, range, out));
    let fo = |f: usize| p.face_offsets[f] as usize;
    let items = of_faces.pieces(chunk_ranges(p.num_faces()), fo, fo);
    run(items, |(range, out)| {
        fill_face_child_relations(p, range, out)
    });
    let pef = &p.edge_face_offsets;
    let items = of_edges.pieces(
        chunk_ranges(p.num_edges()),
        |e| 2 * pef[e] as usize,
        |e| pef[e] as usize + 2 * e,
    );
    run(items, |(range, out)| fill_edge_children(p, range, out));

    c.vert_face_offsets = vert_face_offsets;
    c.vert_faces = vert_faces;
    c.vert_face_local = vert_face_local;
    c.vert_edge_offsets = vert_edge_offsets;
    c.vert_edges = vert_edges;
    c.vert_edge_local = vert_edge_local;
}

/// Faces and edges around the children of the parent vertices `range`: the children of
/// the parent's faces and edges around it, in the parent's order, written into `out`,
/// which starts at the first of them.
fn fill_vertex_children(p: &Topology, range: Range<usize>, out: VertexRelations<'_>) {
    let su = p.face_verts.len() as u32;
    let vf_start = |v: usize| p.vert_face_offsets[v] as usize;
    let ve_start = |v: usize| p.vert_edge_offsets[v] as usize;
    let (fbase, ebase) = (vf_start(range.start), ve_start(range.start));
    for v in range {
        let fo = vf_start(v) - fbase;
        for (k, (&pf, &j)) in p
            .vertex_faces(v)
            .iter()
            .zip(p.vertex_face_locals(v))
            .enumerate()
        {
            let n = p.face_vertices(pf as usize).len();
            out.faces[fo + k] = p.face_offsets[pf as usize] + j as u32;
            out.face_local[fo + k] = rot(n, j as usize) as u16;
        }
        let eo = ve_start(v) - ebase;
        for (k, (&pe, &l)) in p
            .vertex_edges(v)
            .iter()
            .zip(p.vertex_edge_locals(v))
            .enumerate()
        {
            out.edges[eo + k] = su + 2 * pe + l as u32;
            out.edge_local[eo + k] = 1;
        }
    }
}

/// Faces and edges around the children of the parent faces `range`: the face's child
/// quads and the child edges inside it, written into `out`, which starts at the first of
/// them.
fn fill_face_child_relations(p: &Topology, range: Range<usize>, out: VertexRelations<'_>) {
    let fo = |f: usize| p.face_offsets[f] as usize;
    let base = fo(range.start);
    for f in range {
        let o = fo(f);
        let n = p.face_vertices(f).len();
        let at = o - base;
        for i in 0..n {
            out.faces[at + i] = (o + i) as u32;
            out.face_local[at + i] = ((2 + rot(n, i)) % 4) as u16;
            out.edges[at + i] = (o + (i + n - 1) % n) as u32;
            out.edge_local[at + i] = 0;
        }
    }
}

/// Faces and edges around the children of the parent edges `range`, written into `out`,
/// which starts at the first of them: two child faces per parent face (the one at the
/// edge's second vertex in that face first); on manifold edges the edges in
/// counter-clockwise order, on others the two halves, then one inner edge per face.
fn fill_edge_children(p: &Topology, range: Range<usize>, out: VertexRelations<'_>) {
    let su = p.face_verts.len() as u32;
    let pef = &p.edge_face_offsets;
    let vf_start = |e: usize| 2 * pef[e] as usize;
    let ve_start = |e: usize| pef[e] as usize + 2 * e;
    let (vf, vfl, ve, vel) = (out.faces, out.face_local, out.edges, out.edge_local);
    let (fbase, ebase) = (vf_start(range.start), ve_start(range.start));
    for e in range {
        let pfaces = p.edge_face_list(e);
        let plocal = &p.edge_face_local[pef[e] as usize..];
        let mut fo = vf_start(e) - fbase;
        let eo = ve_start(e) - ebase;
        let manifold = !p.edge_tags[e].get().non_manifold && pfaces.len() <= 2;
        for (&pf, &i) in pfaces.iter().zip(plocal) {
            let pfu = pf as usize;
            let n = p.face_vertices(pfu).len();
            let (c0, c1) = (i as usize, (i as usize + 1) % n);
            let base = p.face_offsets[pfu];
            vf[fo] = base + c1 as u32;
            vfl[fo] = ((3 + rot(n, c1)) % 4) as u16;
            vf[fo + 1] = base + c0 as u32;
            vfl[fo + 1] = ((1 + rot(n, c0)) % 4) as u16;
            fo += 2;
        }
        if manifold {
            // Counter-clockwise: [edge child toward the first face's second vertex,
            // interior edge of face 0, edge child toward its first vertex, interior edge
            // of face 1].
            let pf0 = pfaces[0] as usize;
            let i0 = plocal[0] as usize;
            let fv = p.face_vertices(pf0);
            let (a, b) = (fv[i0], fv[(i0 + 1) % fv.len()]);
            ve[eo] = edge_child_at(p, su, e as u32, b, false);
            ve[eo + 1] = p.face_offsets[pf0] + i0 as u32;
            ve[eo + 2] = edge_child_at(p, su, e as u32, a, true);
            vel[eo] = 0;
            vel[eo + 1] = 1;
            vel[eo + 2] = 0;
            if pfaces.len() == 2 {
                ve[eo + 3] = p.face_offsets[pfaces[1] as usize] + plocal[1] as u32;
                vel[eo + 3] = 1;
            }
        } else {
            ve[eo] = su + 2 * e as u32;
            ve[eo + 1] = su + 2 * e as u32 + 1;
            vel[eo] = 0;
            vel[eo + 1] = 0;
            for (k, (&pf, &i)) in pfaces.iter().zip(plocal).enumerate() {
                ve[eo + 2 + k] = p.face_offsets[pf as usize] + i as u32;
                vel[eo + 2 + k] = 1;
            }
        }
    }
}

/// The child's maximum valence. Valence never shrinks: vertex children keep theirs, face
/// children have the face size, edge children 2 + the edge's face count (twice its face
/// count when it has more than two).
fn child_max_valence(p: &Topology) -> u32 {
    let max_face = max_of(p.num_faces(), |f| p.face_vertices(f).len());
    let max_edge_faces = max_of(p.num_edges(), |e| p.edge_face_list(e).len());
    let max_edge_valence = max_edge_faces + max_edge_faces.max(2);
    p.max_valence
        .max(max_face as u32)
        .max(max_edge_valence as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pieces of two parts written front to back give the vector the values written, with
    /// one thread or several (the pieces are then written in parallel).
    #[test]
    fn fresh_elements_are_the_ones_written() {
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a thread pool");
            let v = pool.install(|| {
                let n = 3 * PAR_MIN;
                let mut fresh = Fresh::after(vec![7u32], 2 * n);
                let (a, b) = fresh.split_at(n);
                let ranges = chunk_ranges(n);
                for (part, offset) in [(a, 0), (b, n)] {
                    let pieces = part.pieces(&ranges, |i| i);
                    run(
                        ranges.iter().cloned().zip(pieces).collect(),
                        |(r, mut out)| {
                            for i in r {
                                out.push((offset + i) as u32);
                            }
                        },
                    );
                }
                fresh.finish()
            });
            assert_eq!(v.len(), 1 + 6 * PAR_MIN);
            assert_eq!(v[0], 7);
            assert!(v[1..].iter().enumerate().all(|(i, &x)| x == i as u32));
        }
    }

    /// A piece left short is caught before the vector takes the new elements.
    #[test]
    #[should_panic(expected = "left short")]
    fn fresh_refuses_a_piece_left_short() {
        let mut fresh = Fresh::<f64>::new(4);
        let mut pieces = fresh.all().pieces(&[0..2, 2..4], |i| i);
        pieces[0].push_slice(&[1.0, 2.0]);
        pieces[1].push(3.0);
        drop(pieces);
        fresh.finish();
    }

    /// A part handed out twice would let one piece be counted twice.
    #[test]
    #[should_panic(expected = "handed out once")]
    fn fresh_hands_its_elements_out_once() {
        let mut fresh = Fresh::<u8>::new(2);
        let _ = fresh.all();
        let _ = fresh.split_at(1);
    }
}
