//! [`Topology`]: the complete adjacency of one refinement level, with sharpness and rules.

use super::sharpness as crease;
use super::{Corner, Crease, MeshError, Options, PolyMesh, TopologyWarning};
use crate::hash::FxHasher;
use crate::mesh::options::BoundaryInterpolation;
use rayon::prelude::*;
use std::collections::HashMap;
use std::hash::BuildHasherDefault;

/// An invalid index.
pub const INVALID: u32 = u32::MAX;

/// The subdivision rule of a vertex, from its sharpness and its number of sharp edges
/// (OpenSubdiv's `Sdc::Crease::Rule`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Rule {
    /// No sharp edge, not sharp: the smooth Catmull-Clark vertex rule.
    #[default]
    Smooth,
    /// One sharp edge: treated as smooth.
    Dart,
    /// Two sharp edges: the cubic B-spline crease rule along them.
    Crease,
    /// A sharp vertex, or more than two sharp edges: the vertex stays put.
    Corner,
}

/// Per-vertex tags (OpenSubdiv's `Vtr::internal::Level::VTag`, the part that affects
/// refinement).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VertexTag {
    /// The subdivision rule.
    pub rule: Rule,
    /// On a boundary (has an edge with one face).
    pub boundary: bool,
    /// Non-manifold (more than one fan of faces, an incident non-manifold edge, or isolated).
    pub non_manifold: bool,
    /// A boundary vertex with a single face, made infinitely sharp by
    /// [`BoundaryInterpolation::EdgeAndCorner`].
    pub sharpened_corner: bool,
    /// Sharpness in (0, 10).
    pub semi_sharp: bool,
    /// Sharpness ≥ 10.
    pub inf_sharp: bool,
    /// Has an incident semi-sharp edge.
    pub semi_sharp_edges: bool,
    /// Has an incident infinitely sharp edge.
    pub inf_sharp_edges: bool,
}

/// Per-edge tags.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EdgeTag {
    /// Exactly one incident face.
    pub boundary: bool,
    /// More than two faces, or two faces that run it in the same direction.
    pub non_manifold: bool,
    /// Sharpness in (0, 10).
    pub semi_sharp: bool,
    /// Sharpness ≥ 10 (boundary and non-manifold edges always are).
    pub inf_sharp: bool,
}

/// An [`EdgeTag`] as a [`Topology`] stores it: its four flags in one byte (bits 0–3:
/// boundary, non-manifold, semi-sharp, infinitely sharp), a quarter of the struct's size,
/// which matters at 1–2 edges per refined vertex.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub(crate) struct PackedEdgeTag(u8);

impl PackedEdgeTag {
    /// The tag.
    #[inline]
    pub(crate) fn get(self) -> EdgeTag {
        let bit = |k: u8| self.0 >> k & 1 == 1;
        EdgeTag {
            boundary: bit(0),
            non_manifold: bit(1),
            semi_sharp: bit(2),
            inf_sharp: bit(3),
        }
    }

    /// The bits (for [`Topology::structure_key`]).
    pub(crate) fn bits(self) -> u32 {
        u32::from(self.0)
    }

    /// The tag whose [`bits`](Self::bits) are `bits` (`mesh::packed`).
    pub(crate) fn from_bits(bits: u32) -> Self {
        Self(bits as _)
    }
}

impl From<EdgeTag> for PackedEdgeTag {
    #[inline]
    fn from(t: EdgeTag) -> Self {
        PackedEdgeTag(
            t.boundary as u8
                | (t.non_manifold as u8) << 1
                | (t.semi_sharp as u8) << 2
                | (t.inf_sharp as u8) << 3,
        )
    }
}

/// A [`VertexTag`] as a [`Topology`] stores it, in two bytes (a quarter of the struct's
/// size): bits 0–1 the rule, 2–8 the flags in the struct's order.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub(crate) struct PackedVertexTag(u16);

impl PackedVertexTag {
    /// The tag.
    #[inline]
    pub(crate) fn get(self) -> VertexTag {
        let bit = |k: u16| self.0 >> k & 1 == 1;
        VertexTag {
            rule: match self.0 & 3 {
                0 => Rule::Smooth,
                1 => Rule::Dart,
                2 => Rule::Crease,
                _ => Rule::Corner,
            },
            boundary: bit(2),
            non_manifold: bit(3),
            sharpened_corner: bit(4),
            semi_sharp: bit(5),
            inf_sharp: bit(6),
            semi_sharp_edges: bit(7),
            inf_sharp_edges: bit(8),
        }
    }

    /// The bits (for [`Topology::structure_key`]).
    pub(crate) fn bits(self) -> u32 {
        u32::from(self.0)
    }

    /// The tag whose [`bits`](Self::bits) are `bits` (`mesh::packed`).
    pub(crate) fn from_bits(bits: u32) -> Self {
        Self(bits as _)
    }
}

impl From<VertexTag> for PackedVertexTag {
    #[inline]
    fn from(t: VertexTag) -> Self {
        let rule = match t.rule {
            Rule::Smooth => 0,
            Rule::Dart => 1,
            Rule::Crease => 2,
            Rule::Corner => 3,
        };
        PackedVertexTag(
            rule | (t.boundary as u16) << 2
                | (t.non_manifold as u16) << 3
                | (t.sharpened_corner as u16) << 4
                | (t.semi_sharp as u16) << 5
                | (t.inf_sharp as u16) << 6
                | (t.semi_sharp_edges as u16) << 7
                | (t.inf_sharp_edges as u16) << 8,
        )
    }
}

/// Complete adjacency, tags and sharpness of one level.
///
/// # Memory layout
/// All relations are flat arrays of `u32` indices in compressed-sparse-row form
/// (an `*_offsets` array of `count + 1` prefix sums and a member array):
///
/// | relation | members | parallel arrays |
/// |---|---|---|
/// | face → vertices | `face_verts` | `face_edges` (edge `i` runs from vertex `i` to `i + 1`) |
/// | edge → vertices | `edge_verts: [u32; 2]` | |
/// | edge → faces | `edge_faces` | `edge_face_local`: position of the edge in the face |
/// | vertex → faces | `vert_faces` | `vert_face_local`: position of the vertex in the face |
/// | vertex → edges | `vert_edges` | `vert_edge_local`: 0 or 1, which end of the edge |
///
/// Around a manifold vertex, faces and edges are in counter-clockwise order with face `i`
/// between edge `i` (leaving the vertex in face `i`) and edge `i + 1` (entering it); at a
/// boundary vertex edge 0 and the last edge are the two boundary edges. This is
/// OpenSubdiv's ordering (`Vtr::Level::orderVertexFacesAndEdges`), and limit tangents
/// depend on it.
///
/// Per element there are tags ([`EdgeTag`], [`VertexTag`], stored packed in 1 and 2 bytes;
/// a hole flag per face) and
/// `f32` sharpness values (see `crate::mesh::tags` for why `f32`).
///
/// # Construction
/// [`Topology::from_mesh`] builds the base level in O(n) expected time, with a fixed
/// number of allocations (none per element): edges are numbered in order of first
/// appearance while walking the faces, found in per-vertex buckets laid out in one
/// array; this reproduces OpenSubdiv's edge order exactly, so refined vertices come out
/// in OpenSubdiv's order too.
#[derive(Clone, Debug, Default)]
#[cfg_attr(test, derive(PartialEq))]
pub struct Topology {
    pub(crate) num_vertices: u32,
    pub(crate) face_offsets: Vec<u32>,
    pub(crate) face_verts: Vec<u32>,
    pub(crate) face_edges: Vec<u32>,
    pub(crate) face_holes: Vec<bool>,

    pub(crate) edge_verts: Vec<[u32; 2]>,
    pub(crate) edge_face_offsets: Vec<u32>,
    pub(crate) edge_faces: Vec<u32>,
    pub(crate) edge_face_local: Vec<u16>,

    pub(crate) vert_face_offsets: Vec<u32>,
    pub(crate) vert_faces: Vec<u32>,
    pub(crate) vert_face_local: Vec<u16>,
    pub(crate) vert_edge_offsets: Vec<u32>,
    pub(crate) vert_edges: Vec<u32>,
    pub(crate) vert_edge_local: Vec<u8>,

    pub(crate) edge_sharpness: Vec<f32>,
    pub(crate) vert_sharpness: Vec<f32>,
    pub(crate) edge_tags: Vec<PackedEdgeTag>,
    pub(crate) vert_tags: Vec<PackedVertexTag>,

    pub(crate) max_valence: u32,
    pub(crate) has_holes: bool,
    /// Whether the edge → faces and vertex → faces/edges relations (and face → edges) are
    /// present. The last level of a refinement that is only written out lacks them.
    pub(crate) complete: bool,
}

/// For each of `faces` of `t`, the corner its listing starts from in
/// [`Topology::subset_canonical`]: 0 for the first face; for each later face, its corner
/// that the faces before it (listed so) number first, the subset numbering its vertices in
/// order of first appearance. A face with no corner among those before keeps its own start
/// (the faces of a 1-ring all share a corner of the first). So the numbering does not
/// depend on where the level starts the faces' lists.
fn canonical_rotations(t: &Topology, faces: &[u32]) -> Vec<usize> {
    let mut number: HashMap<u32, u32, BuildHasherDefault<FxHasher>> = HashMap::default();
    let mut rotations = Vec::with_capacity(faces.len());
    for (i, &f) in faces.iter().enumerate() {
        let fv = t.face_vertices(f as usize);
        let r = if i == 0 {
            0
        } else {
            (0..fv.len())
                .filter_map(|k| number.get(&fv[k]).map(|&o| (o, k)))
                .min()
                .map_or(0, |(_, k)| k)
        };
        for k in 0..fv.len() {
            let next = number.len() as u32;
            number.entry(fv[(r + k) % fv.len()]).or_insert(next);
        }
        rotations.push(r);
    }
    rotations
}

/// Vertices per block of [`Topology::orient_vertices`]' parallel pass.
const VERTEX_BLOCK: usize = 4096;

/// The vertex relations of a block of [`VERTEX_BLOCK`] vertices from `first` on, as
/// [`Topology::orient_vertices`] fills them.
struct VertexBlock<'a> {
    first: usize,
    faces: &'a mut [u32],
    face_local: &'a mut [u16],
    /// The edges entering and leaving each vertex in each of its faces.
    corners: &'a mut [[u32; 2]],
    edges: &'a mut [u32],
    edge_local: &'a mut [u8],
    /// Which end of each of its edges each vertex is, in the order of `edges` as built.
    ends: &'a mut [u8],
    tags: &'a mut [PackedVertexTag],
}

/// Buffers reused from vertex to vertex by [`Topology::orient_vertices`].
#[derive(Default)]
struct OrientScratch {
    /// The vertex's faces, in counter-clockwise order.
    faces: Vec<u32>,
    /// The vertex's edges, in counter-clockwise order.
    edges: Vec<u32>,
    /// The counter-clockwise order (indices into the vertex's lists) from [`order_corners`].
    order: Vec<usize>,
    /// The vertex's positions in its faces, in that order.
    locals: Vec<u16>,
    /// Which end of each of its edges the vertex is, in that order.
    ends: Vec<u8>,
    /// The vertex's edges and ends, sorted by edge (around vertices of high valence).
    by_edge: Vec<(u32, u8)>,
}

impl OrientScratch {
    /// Reorders one vertex's lists (`faces`, `face_local`, `edges` and, from `ends`, the
    /// vertex's end of each edge into `edge_local`) by the order [`order_corners`] left in
    /// `self.order`: the walk's result, from the vertex's own `corners`.
    fn apply_corner_order(
        &mut self,
        faces: &mut [u32],
        face_local: &mut [u16],
        corners: &[[u32; 2]],
        edges: &mut [u32],
        edge_local: &mut [u8],
        ends: &[u8],
    ) {
        let order = &self.order;
        self.faces.clear();
        self.faces.extend(order.iter().map(|&k| faces[k]));
        self.locals.clear();
        self.locals.extend(order.iter().map(|&k| face_local[k]));
        self.edges.clear();
        self.edges.extend(order.iter().map(|&k| corners[k][1]));
        if edges.len() > faces.len() {
            self.edges.push(corners[order[order.len() - 1]][0]);
        }
        self.ends.clear();
        if edges.len() <= 16 {
            let es = &*edges;
            self.ends.extend(
                self.edges
                    .iter()
                    .map(|e| es.iter().position(|x| x == e).map_or(0, |p| ends[p])),
            );
        } else {
            // Around a vertex of high valence, by binary search (a scan per edge would
            // cost the square of the valence).
            let by_edge = &mut self.by_edge;
            by_edge.clear();
            by_edge.extend(edges.iter().copied().zip(ends.iter().copied()));
            by_edge.sort_unstable();
            self.ends.extend(self.edges.iter().map(|e| {
                let i = by_edge.partition_point(|&(x, _)| x < *e);
                by_edge
                    .get(i)
                    .filter(|&&(x, _)| x == *e)
                    .map_or(0, |&(_, n)| n)
            }));
        }
        faces.copy_from_slice(&self.faces);
        face_local.copy_from_slice(&self.locals);
        edges.copy_from_slice(&self.edges);
        edge_local.copy_from_slice(&self.ends);
    }
}

/// The counter-clockwise order of a vertex's faces (indices into its lists), found from
/// its corners alone when that is sure to be [`Topology::order_vertex`]'s order: `faces`
/// are the vertex's faces in face order, `corners` the edges entering and leaving it in
/// each, `edges` the number of its edges. So the order needs no reads of other faces
/// and edges, which on a large mesh lie anywhere in memory (the walk's cache misses were
/// most of the base level's topology: on a 1.2 M-quad scan, 39 % of a refinement to
/// level 1).
///
/// It is that order when no face holds the vertex twice, no edge enters it (or leaves
/// it) in two faces, and following each face's entering edge to the face that leaves by
/// it visits every face: from the first face for an interior vertex (as many edges as
/// faces), from the face whose leaving edge no face enters for a boundary one (one edge
/// more), whose last face's entering edge leaves no face. Then each edge at the vertex
/// has exactly the faces that enter or leave by it (one or two), as the walk finds them
/// through the edges' faces, and the walk starts from the same face (the one boundary
/// edge that leaves its only face). Otherwise `false`, and the walk decides.
fn order_corners(
    faces: &[u32],
    corners: &[[u32; 2]],
    edges: usize,
    order: &mut Vec<usize>,
) -> bool {
    let n = corners.len();
    let boundary = match edges {
        e if e == n && e >= 2 => false,
        e if e == n + 1 && n >= 1 => true,
        _ => return false,
    };
    if faces.windows(2).any(|w| w[0] == w[1]) {
        return false;
    }
    if corners.iter().any(|&[enter, leave]| enter == leave) {
        return false;
    }
    // The corner that leaves by edge `e`: a scan of the few corners of a usual vertex, a
    // binary search of them sorted by leaving edge around one of high valence (the walk
    // below asks once per corner, so scanning would cost `n²`).
    const SCAN: usize = 16;
    let (mut by_leave, mut enters) = (Vec::new(), Vec::new());
    if n > SCAN {
        by_leave.extend(corners.iter().enumerate().map(|(k, c)| (c[1], k)));
        by_leave.sort_unstable();
        enters.extend(corners.iter().map(|c| c[0]));
        enters.sort_unstable();
    }
    let leaves = |e: u32| -> Option<usize> {
        if n <= SCAN {
            corners.iter().position(|c| c[1] == e)
        } else {
            let i = by_leave.partition_point(|&(l, _)| l < e);
            by_leave.get(i).filter(|&&(l, _)| l == e).map(|&(_, k)| k)
        }
    };
    // No edge leaves (or enters) by two corners.
    let repeated = if n <= SCAN {
        corners.iter().enumerate().any(|(k, &[enter, leave])| {
            corners[k + 1..]
                .iter()
                .any(|c| c[0] == enter || c[1] == leave)
        })
    } else {
        enters.windows(2).any(|w| w[0] == w[1]) || by_leave.windows(2).any(|w| w[0].0 == w[1].0)
    };
    if repeated {
        return false;
    }
    let start = if boundary {
        // The corner whose leaving edge no corner enters: with distinct entering edges, the
        // one corner leaving by an edge that is not among them.
        let mut open = (0..n).filter(|&k| {
            let leave = corners[k][1];
            if n <= SCAN {
                !corners.iter().any(|c| c[0] == leave)
            } else {
                enters.binary_search(&leave).is_err()
            }
        });
        match (open.next(), open.next()) {
            (Some(k), None) => k,
            _ => return false,
        }
    } else {
        0
    };
    order.clear();
    order.push(start);
    let mut seen = vec![false; if n > SCAN { n } else { 0 }];
    if n > SCAN {
        seen[start] = true;
    }
    let mut at = start;
    for _ in 1..n {
        match leaves(corners[at][0]) {
            Some(k) if n > SCAN && !seen[k] => {
                seen[k] = true;
                order.push(k);
                at = k;
            }
            Some(k) if n <= SCAN && !order.contains(&k) => {
                order.push(k);
                at = k;
            }
            _ => return false,
        }
    }
    let last_enters = corners[at][0];
    if boundary {
        leaves(last_enters).is_none()
    } else {
        last_enters == corners[start][1]
    }
}

/// Whether `a` and `b` hold the same members, each as often.
fn same_members(a: &[u32], b: &[u32]) -> bool {
    let sorted = |x: &[u32]| {
        let mut v = x.to_vec();
        v.sort_unstable();
        v
    };
    a.len() == b.len() && sorted(a) == sorted(b)
}

/// `data`, a relation's members in CSR form with `offsets` over vertices, cut into the
/// members of each block of [`VERTEX_BLOCK`] vertices.
fn split_blocks<'a, T>(mut data: &'a mut [T], offsets: &[u32]) -> Vec<&'a mut [T]> {
    let nv = offsets.len() - 1;
    (0..nv.div_ceil(VERTEX_BLOCK))
        .map(|b| {
            let (start, end) = (b * VERTEX_BLOCK, ((b + 1) * VERTEX_BLOCK).min(nv));
            let len = (offsets[end] - offsets[start]) as usize;
            let (head, tail) = std::mem::take(&mut data).split_at_mut(len);
            data = tail;
            head
        })
        .collect()
}

#[inline]
fn range(offsets: &[u32], i: usize) -> std::ops::Range<usize> {
    offsets[i] as usize..offsets[i + 1] as usize
}

fn to_u32(n: usize, what: &str) -> Result<u32, MeshError> {
    u32::try_from(n)
        .ok()
        .filter(|&v| v != INVALID)
        .ok_or_else(|| MeshError::TooLarge { what: what.into() })
}

/// Checks that the vertex and face-vertex counts fit the 32-bit indices and every face the
/// 16-bit local indices.
fn check_sizes(nv: usize, face_offsets: &[u32], face_verts: &[u32]) -> Result<(), MeshError> {
    to_u32(nv, "the vertex count")?;
    to_u32(face_verts.len(), "the face-vertex count")?;
    for f in 0..face_offsets.len().saturating_sub(1) {
        if range(face_offsets, f).len() > u16::MAX as usize {
            return Err(MeshError::TooLarge {
                what: format!("face {f} has more than {} vertices", u16::MAX),
            });
        }
    }
    Ok(())
}

/// Per-vertex buckets of incident edges, sized by an upper bound (each face edge counted
/// at both ends), filled in creation order.
struct EdgeBuckets {
    /// Start of each vertex's bucket (`nv + 1` entries).
    start: Vec<u32>,
    /// Number of edges in each vertex's bucket.
    len: Vec<u32>,
    /// The edges, bucket after bucket.
    bucket: Vec<u32>,
    /// Which end of each bucket's edge its vertex is.
    end: Vec<u8>,
}

impl EdgeBuckets {
    /// Empty buckets for the faces `face_offsets`/`face_verts` on `nv` vertices.
    fn new(nv: usize, face_offsets: &[u32], face_verts: &[u32]) -> Self {
        let mut start = vec![0u32; nv + 1];
        for f in 0..face_offsets.len().saturating_sub(1) {
            let fv = &face_verts[range(face_offsets, f)];
            let n = fv.len();
            for i in 0..n {
                start[fv[i] as usize + 1] += 1;
                start[fv[(i + 1) % n] as usize + 1] += 1;
            }
        }
        for v in 0..nv {
            start[v + 1] += start[v];
        }
        let total = start[nv] as usize;
        EdgeBuckets {
            start,
            len: vec![0u32; nv],
            bucket: vec![0u32; total],
            end: vec![0u8; total],
        }
    }

    /// Vertex → edges (offsets, edges, which end of each edge the vertex is): the buckets
    /// compacted, each in creation order. The bucket array stays for reuse.
    fn compact(&mut self) -> (Vec<u32>, Vec<u32>, Vec<u8>) {
        let nv = self.len.len();
        let mut offsets = vec![0u32; nv + 1];
        for v in 0..nv {
            offsets[v + 1] = offsets[v] + self.len[v];
        }
        let mut edges = vec![0u32; offsets[nv] as usize];
        let mut ends = vec![0u8; edges.len()];
        for v in 0..nv {
            let b0 = self.start[v] as usize;
            let len = self.len[v] as usize;
            let o = offsets[v] as usize;
            edges[o..o + len].copy_from_slice(&self.bucket[b0..b0 + len]);
            ends[o..o + len].copy_from_slice(&self.end[b0..b0 + len]);
        }
        self.end = Vec::new();
        (offsets, edges, ends)
    }
}

/// The edges found from the faces by [`find_edges`].
struct FoundEdges {
    /// Face → edges, parallel to the face → vertices.
    face_edges: Vec<u32>,
    /// Each edge's vertices, in the direction of the face that created it.
    edge_verts: Vec<[u32; 2]>,
    /// Number of faces of each edge.
    nfaces: Vec<u32>,
    /// Whether each edge is non-manifold.
    nonman: Vec<bool>,
}

/// The edges of the faces `face_offsets`/`face_verts`, numbered in the order the faces
/// first run them, and which are non-manifold (degenerate, twice in one face, in more than
/// two faces or run the same way by two); `buckets` gets each vertex's edges.
fn find_edges(
    face_offsets: &[u32],
    face_verts: &[u32],
    buckets: &mut EdgeBuckets,
) -> Result<FoundEdges, MeshError> {
    let nf = face_offsets.len().saturating_sub(1);
    let cap = face_verts.len() / 2 + 4;
    let mut face_edges = vec![0u32; face_verts.len()];
    let mut edge_verts: Vec<[u32; 2]> = Vec::with_capacity(cap);
    // Number of faces seen per edge, whether it became non-manifold, and its last face.
    let mut edge_nfaces: Vec<u32> = Vec::with_capacity(cap);
    let mut edge_nonman: Vec<bool> = Vec::with_capacity(cap);
    let mut edge_last_face: Vec<u32> = Vec::with_capacity(cap);
    let bucket_start: &[u32] = &buckets.start;
    let bucket_len: &mut [u32] = &mut buckets.len;
    let bucket: &mut [u32] = &mut buckets.bucket;
    let bucket_end: &mut [u8] = &mut buckets.end;

    for f in 0..nf {
        let r = range(face_offsets, f);
        let n = r.len();
        for i in 0..n {
            let v0 = face_verts[r.start + i];
            let v1 = face_verts[r.start + (i + 1) % n];
            // An edge is in the buckets of both its ends, in creation order: search
            // the shorter one, so that a vertex of high valence costs its neighbours
            // nothing (a fan of n faces: O(n) in all, not O(n²)).
            let (near, far) = if bucket_len[v1 as usize] < bucket_len[v0 as usize] {
                (v1, v0)
            } else {
                (v0, v1)
            };
            let b0 = bucket_start[near as usize] as usize;
            // A degenerate edge (a vertex repeated consecutively) is always new.
            let mut found = if v0 == v1 {
                None
            } else {
                bucket[b0..b0 + bucket_len[near as usize] as usize]
                    .iter()
                    .copied()
                    .find(|&e| {
                        let ev = edge_verts[e as usize];
                        ev[0] == far || ev[1] == far
                    })
            };
            let mut twice_in_face = false;
            if let Some(e) = found {
                let eu = e as usize;
                if edge_last_face[eu] == f as u32 {
                    twice_in_face = true;
                    // The edge occurs twice in this face: a new instance, and both
                    // are non-manifold.
                    edge_nonman[eu] = true;
                    found = None;
                } else if edge_nfaces[eu] > 1 || edge_verts[eu][0] == v0 {
                    // A third face, or a second face running the edge the same way.
                    edge_nonman[eu] = true;
                }
            }
            let e = match found {
                Some(e) => {
                    edge_nfaces[e as usize] += 1;
                    edge_last_face[e as usize] = f as u32;
                    e
                }
                None => {
                    let e = to_u32(edge_verts.len(), "the edge count")?;
                    edge_verts.push([v0, v1]);
                    edge_nfaces.push(1);
                    edge_last_face.push(f as u32);
                    edge_nonman.push(v0 == v1 || twice_in_face);
                    for (end, v) in [v0, v1].into_iter().enumerate() {
                        let at = bucket_start[v as usize] + bucket_len[v as usize];
                        bucket[at as usize] = e;
                        bucket_end[at as usize] = end as u8;
                        bucket_len[v as usize] += 1;
                    }
                    e
                }
            };
            face_edges[r.start + i] = e;
        }
    }
    Ok(FoundEdges {
        face_edges,
        edge_verts,
        nfaces: edge_nfaces,
        nonman: edge_nonman,
    })
}

/// Edge → faces (offsets, faces, the edge's position in each face), in face order, from
/// the faces' edges and each edge's face count.
fn edge_faces_in_order(
    face_offsets: &[u32],
    face_edges: &[u32],
    nfaces: &[u32],
) -> (Vec<u32>, Vec<u32>, Vec<u16>) {
    let ne = nfaces.len();
    let mut offsets = vec![0u32; ne + 1];
    for e in 0..ne {
        offsets[e + 1] = offsets[e] + nfaces[e];
    }
    let mut faces = vec![0u32; face_edges.len()];
    let mut local = vec![0u16; face_edges.len()];
    let mut fill = offsets[..ne].to_vec();
    for f in 0..face_offsets.len().saturating_sub(1) {
        let r = range(face_offsets, f);
        for (i, &e) in face_edges[r].iter().enumerate() {
            let at = fill[e as usize] as usize;
            faces[at] = f as u32;
            local[at] = i as u16;
            fill[e as usize] += 1;
        }
    }
    (offsets, faces, local)
}

/// Vertex → faces (offsets, faces, the vertex's position in each face), in face order;
/// `corners` gets, parallel to the faces, the edges entering and leaving the vertex in
/// each.
fn vertex_faces_in_order(
    nv: usize,
    face_offsets: &[u32],
    face_verts: &[u32],
    face_edges: &[u32],
    corners: &mut [[u32; 2]],
) -> (Vec<u32>, Vec<u32>, Vec<u16>) {
    let mut offsets = vec![0u32; nv + 1];
    for &v in face_verts {
        offsets[v as usize + 1] += 1;
    }
    for v in 0..nv {
        offsets[v + 1] += offsets[v];
    }
    let mut faces = vec![0u32; face_verts.len()];
    let mut local = vec![0u16; face_verts.len()];
    let mut fill = offsets[..nv].to_vec();
    for f in 0..face_offsets.len().saturating_sub(1) {
        let r = range(face_offsets, f);
        let fe = &face_edges[r.clone()];
        let n = fe.len();
        for (i, &v) in face_verts[r].iter().enumerate() {
            let at = fill[v as usize] as usize;
            faces[at] = f as u32;
            local[at] = i as u16;
            corners[at] = [fe[(i + n - 1) % n], fe[i]];
            fill[v as usize] += 1;
        }
    }
    (offsets, faces, local)
}

impl Topology {
    /// Builds the base level of `mesh`: edges, adjacency in rotational order, manifold and
    /// boundary classification, then the tags and sharpness that `options` and
    /// `mesh.tags` imply (OpenSubdiv's `TopologyRefinerFactory` rules: boundary edges and
    /// non-manifold edges infinitely sharp; corners sharpened in
    /// [`BoundaryInterpolation::EdgeAndCorner`]; non-manifold vertices sharpened except
    /// along an interior non-manifold crease; faces at unsharpened boundaries become holes
    /// in [`BoundaryInterpolation::None`]).
    ///
    /// Non-manifold input is accepted and handled as OpenSubdiv handles it; use
    /// [`check_manifold`](Self::check_manifold) to reject it instead.
    ///
    /// # Errors
    /// [`MeshError::TooLarge`] when counts exceed the index range, or a face has more
    /// than 65535 vertices. (A [`PolyMesh`] is otherwise valid by construction.)
    pub fn from_mesh(
        mesh: &PolyMesh,
        options: &Options,
    ) -> Result<(Self, Vec<TopologyWarning>), MeshError> {
        let (offsets, verts) = (mesh.face_offsets().to_vec(), mesh.face_verts().to_vec());
        Self::from_faces(mesh.num_vertices(), offsets, verts)?.tagged(&mesh.tags, options)
    }

    /// [`Self::from_mesh`] taking the mesh: its face lists become the topology's (no copy),
    /// and its positions are returned (the warnings are not).
    pub(crate) fn from_owned_mesh(
        mesh: PolyMesh,
        options: &Options,
    ) -> Result<(Self, Vec<[f64; 3]>), MeshError> {
        let nv = mesh.num_vertices();
        let (positions, face_offsets, face_verts, tags) = mesh.into_parts();
        let (t, _) = Self::from_faces(nv, face_offsets, face_verts)?.tagged(&tags, options)?;
        Ok((t, positions))
    }

    /// The adjacency `self` with `tags` applied, sharpness and rules prepared, and the
    /// warnings about its faces, edges and vertices.
    fn tagged(
        mut self,
        tags: &super::Tags,
        options: &Options,
    ) -> Result<(Self, Vec<TopologyWarning>), MeshError> {
        let t = &mut self;
        let mut warnings = Vec::new();
        t.assign_tags(&tags.creases, &tags.corners, &tags.holes, &mut warnings);
        t.prepare_tags_and_sharpness(options);
        let degenerate: Vec<usize> = (0..t.num_faces())
            .filter(|&f| super::polymesh::repeated_vertex(t.face_vertices(f)).is_some())
            .collect();
        if let Some(&f) = degenerate.first() {
            warnings.push(TopologyWarning::DegenerateFaces {
                count: degenerate.len(),
                first: f as u32,
            });
        }
        let nm_edges: Vec<usize> = (0..t.num_edges())
            .filter(|&e| t.edge_tags[e].get().non_manifold)
            .collect();
        if let Some(&e) = nm_edges.first() {
            let [a, b] = t.edge_verts[e];
            warnings.push(TopologyWarning::NonManifoldEdges {
                count: nm_edges.len(),
                first: (a, b),
            });
        }
        let nm_verts: Vec<usize> = (0..t.num_vertices())
            .filter(|&v| t.vert_tags[v].get().non_manifold && !t.vertex_faces(v).is_empty())
            .collect();
        if let Some(&v) = nm_verts.first() {
            warnings.push(TopologyWarning::NonManifoldVertices {
                count: nm_verts.len(),
                first: v as u32,
            });
        }
        Ok((self, warnings))
    }

    /// Adjacency only (no tags applied yet), OpenSubdiv's
    /// `Level::completeTopologyFromFaceVertices`, on the faces `offsets` and `verts` (CSR),
    /// which become the topology's.
    fn from_faces(
        num_vertices: usize,
        offsets: Vec<u32>,
        verts: Vec<u32>,
    ) -> Result<Self, MeshError> {
        let nv = num_vertices;
        let nf = offsets.len().saturating_sub(1);
        check_sizes(nv, &offsets, &verts)?;
        let mut buckets = EdgeBuckets::new(nv, &offsets, &verts);
        let edges = find_edges(&offsets, &verts, &mut buckets)?;
        let ne = edges.edge_verts.len();
        let (vert_edge_offsets, vert_edges, edge_ends) = buckets.compact();
        let (edge_face_offsets, edge_faces, edge_face_local) =
            edge_faces_in_order(&offsets, &edges.face_edges, &edges.nfaces);
        // The edges entering and leaving each vertex in each of its faces, for
        // `orient_vertices` (read here in face order, not there face by face), in the
        // buckets' array: two entries per face-vertex, as many as it has.
        let (corners, _) = buckets.bucket.as_chunks_mut::<2>();
        debug_assert_eq!(corners.len(), verts.len());
        let (vert_face_offsets, vert_faces, vert_face_local) =
            vertex_faces_in_order(nv, &offsets, &verts, &edges.face_edges, corners);

        let mut t = Topology {
            num_vertices: nv as u32,
            face_offsets: offsets,
            face_verts: verts,
            face_edges: edges.face_edges,
            face_holes: vec![false; nf],
            edge_verts: edges.edge_verts,
            edge_face_offsets,
            edge_faces,
            edge_face_local,
            vert_face_offsets,
            vert_faces,
            vert_face_local,
            vert_edge_offsets,
            vert_edges,
            vert_edge_local: Vec::new(),
            edge_sharpness: vec![0.0; ne],
            vert_sharpness: vec![0.0; nv],
            edge_tags: vec![PackedEdgeTag::default(); ne],
            vert_tags: vec![PackedVertexTag::default(); nv],
            max_valence: 0,
            has_holes: false,
            complete: true,
        };
        t.tag_non_manifold_edges(&edges.nonman);
        t.orient_vertices(corners, edge_ends);
        Ok(t)
    }

    /// Tags the edges flagged in `nonman`, and their ends, non-manifold (every tag is
    /// still the default: the flag is set by replacing it).
    fn tag_non_manifold_edges(&mut self, nonman: &[bool]) {
        let non_manifold_edge = PackedEdgeTag::from(EdgeTag {
            non_manifold: true,
            ..EdgeTag::default()
        });
        let non_manifold_vertex = PackedVertexTag::from(VertexTag {
            non_manifold: true,
            ..VertexTag::default()
        });
        for (e, &nm) in nonman.iter().enumerate() {
            if nm {
                self.edge_tags[e] = non_manifold_edge;
                for v in self.edge_verts[e] {
                    self.vert_tags[v as usize] = non_manifold_vertex;
                }
            }
        }
    }

    /// Orders the faces and edges of every manifold vertex counter-clockwise; a vertex
    /// that cannot be ordered (more than one fan, isolated) is non-manifold. Then the
    /// position of each vertex in each of its faces and which end of each of its edges it
    /// is.
    ///
    /// In parallel over blocks of [`VERTEX_BLOCK`] vertices, each block writing its own
    /// ranges of the vertex relations: every refinement, limit surface and plan builds the
    /// base level's topology first, on large scans a good part of the whole job.
    ///
    /// Most vertices are ordered from `corners` (the edges entering and leaving each
    /// vertex in each of its faces, listed by [`from_faces`](Self::from_faces) in face
    /// order) with [`order_corners`], and their edges' ends come from `ends` (which end
    /// of each edge the vertex is, in the order the edges were found); the others by the
    /// walk of [`order_vertex`](Self::order_vertex). The walk reads faces and edges
    /// anywhere in memory, where the corners are read in order: on large meshes the walk
    /// everywhere would make this pass most of a level-1 refinement.
    fn orient_vertices(&mut self, corners: &mut [[u32; 2]], mut ends: Vec<u8>) {
        let nv = self.num_vertices as usize;
        let mut faces = std::mem::take(&mut self.vert_faces);
        let mut face_local = std::mem::take(&mut self.vert_face_local);
        let mut edges = std::mem::take(&mut self.vert_edges);
        let mut edge_local = vec![0u8; edges.len()];
        let mut tags = std::mem::take(&mut self.vert_tags);
        let this = &*self;
        let (fo, eo) = (&this.vert_face_offsets, &this.vert_edge_offsets);
        let blocks: Vec<VertexBlock> = (split_blocks(&mut faces, fo).into_iter())
            .zip(split_blocks(&mut face_local, fo))
            .zip(split_blocks(corners, fo))
            .zip(split_blocks(&mut edges, eo))
            .zip(split_blocks(&mut edge_local, eo))
            .zip(split_blocks(&mut ends, eo))
            .zip(tags.chunks_mut(VERTEX_BLOCK))
            .enumerate()
            .map(
                |(b, ((((((faces, face_local), corners), edges), edge_local), ends), tags))| {
                    VertexBlock {
                        first: b * VERTEX_BLOCK,
                        faces,
                        face_local,
                        corners,
                        edges,
                        edge_local,
                        ends,
                        tags,
                    }
                },
            )
            .collect();
        if nv < 2 * VERTEX_BLOCK {
            blocks.into_iter().for_each(|b| this.orient_block(b));
        } else {
            blocks.into_par_iter().for_each(|b| this.orient_block(b));
        }
        self.vert_faces = faces;
        self.vert_face_local = face_local;
        self.vert_edges = edges;
        self.vert_edge_local = edge_local;
        self.vert_tags = tags;
        self.max_valence = self.largest_valence();
    }

    /// Orients the vertices of one block (see [`orient_vertices`](Self::orient_vertices)):
    /// each manifold vertex from its corners where [`order_corners`] can, else by the walk
    /// of [`order_vertex`](Self::order_vertex), which tags the vertex non-manifold when it
    /// fails; then which end of each of its edges each vertex is.
    fn orient_block(&self, block: VertexBlock<'_>) {
        let VertexBlock {
            first: v0,
            faces,
            face_local,
            corners,
            edges,
            edge_local,
            ends,
            tags,
        } = block;
        let (fo, eo) = (&self.vert_face_offsets, &self.vert_edge_offsets);
        let mut s = OrientScratch::default();
        let (f0, e0) = (fo[v0] as usize, eo[v0] as usize);
        for (i, tag) in tags.iter_mut().enumerate() {
            let v = v0 + i;
            let fr = fo[v] as usize - f0..fo[v + 1] as usize - f0;
            let er = eo[v] as usize - e0..eo[v + 1] as usize - e0;
            let manifold = !tag.get().non_manifold;
            if manifold
                && order_corners(
                    &faces[fr.clone()],
                    &corners[fr.clone()],
                    er.len(),
                    &mut s.order,
                )
            {
                s.apply_corner_order(
                    &mut faces[fr.clone()],
                    &mut face_local[fr.clone()],
                    &corners[fr],
                    &mut edges[er.clone()],
                    &mut edge_local[er.clone()],
                    &ends[er],
                );
                continue;
            }
            if manifold {
                let ordered = self.order_vertex(
                    v,
                    (&faces[fr.clone()], &edges[er.clone()]),
                    &mut s.faces,
                    &mut s.edges,
                );
                if ordered {
                    faces[fr.clone()].copy_from_slice(&s.faces);
                    edges[er.clone()].copy_from_slice(&s.edges);
                    // Faces were reordered around manifold vertices only, where
                    // each face occurs once; around the others, the positions
                    // recorded in face order are still right (a face that repeats
                    // a vertex occurs once per corner there).
                    for (l, &f) in face_local[fr].iter_mut().zip(&s.faces) {
                        let fv = self.face_vertices(f as usize);
                        *l = fv.iter().position(|&x| x as usize == v).unwrap_or(0) as u16;
                    }
                } else {
                    let mut t = tag.get();
                    t.non_manifold = true;
                    *tag = t.into();
                }
            }
            for i in er.clone() {
                let e = edges[i] as usize;
                let [a, b] = self.edge_verts[e];
                edge_local[i] = if a == b {
                    // A degenerate edge is listed twice: first as its end 0, then
                    // as end 1.
                    (i > er.start && edges[i - 1] as usize == e) as u8
                } else {
                    (b as usize == v) as u8
                };
            }
        }
    }

    /// Walks around `v` from a starting face (the first face if interior, the face of the
    /// boundary edge that leaves `v` if on a boundary), crossing to the neighbour face over
    /// the edge that enters `v`. Fails if the walk does not visit every face and edge
    /// exactly once (OpenSubdiv's `orderVertexFacesAndEdges`).
    fn order_vertex(
        &self,
        v: usize,
        (vfaces, vedges): (&[u32], &[u32]),
        faces: &mut Vec<u32>,
        edges: &mut Vec<u32>,
    ) -> bool {
        let (nf, ne) = (vfaces.len(), vedges.len());
        if nf == 0 || ne < 2 || ne > nf + 1 {
            return false;
        }
        faces.clear();
        edges.clear();
        let local_of_vertex = |f: u32| -> usize {
            self.face_vertices(f as usize)
                .iter()
                .position(|&x| x as usize == v)
                .unwrap_or(0)
        };
        let (mut f, mut fv, mut e);
        if ne == nf {
            f = vfaces[0];
            fv = local_of_vertex(f);
            e = self.face_edge_list(f as usize)[fv];
        } else {
            f = INVALID;
            fv = 0;
            e = INVALID;
            for &cand in vedges {
                let ef = self.edge_face_list(cand as usize);
                if ef.len() == 1 {
                    e = cand;
                    f = ef[0];
                    fv = local_of_vertex(f);
                    if self.face_edge_list(f as usize)[fv] == e {
                        break;
                    }
                }
            }
            if e == INVALID {
                return false;
            }
        }
        faces.push(f);
        edges.push(e);
        let first = e;
        while edges.len() < ne {
            let fe = self.face_edge_list(f as usize);
            let prev = if fv == 0 { fe.len() - 1 } else { fv - 1 };
            let next = fe[prev];
            if next == e || next == first {
                return false;
            }
            edges.push(next);
            if faces.len() < nf {
                let ef = self.edge_face_list(next as usize);
                if ef.is_empty() || (ef.len() == 1 && ef[0] == f) {
                    return false;
                }
                f = if ef[0] == f { ef[1] } else { ef[0] };
                let Some(pos) = self
                    .face_edge_list(f as usize)
                    .iter()
                    .position(|&x| x == next)
                else {
                    return false;
                };
                fv = pos;
                faces.push(f);
            }
            e = next;
        }
        // Around a vertex that a face holds twice, the walk can list an edge twice and miss
        // another (OpenSubdiv's walk does the same, and its result then depends on the
        // corner a face starts from): the vertex is non-manifold unless the walk visited
        // each of its edges once and each of its faces as often as they hold it.
        faces.len() == nf && same_members(edges, vedges) && same_members(faces, vfaces)
    }

    /// Applies creases, corners and holes (OpenSubdiv's `assignComponentTags`).
    fn assign_tags(
        &mut self,
        creases: &[Crease],
        corners: &[Corner],
        holes: &[u32],
        warnings: &mut Vec<TopologyWarning>,
    ) {
        for (i, c) in creases.iter().enumerate() {
            match self.find_edge(c.v0, c.v1) {
                Some(e) => self.edge_sharpness[e as usize] = c.sharpness,
                None => warnings.push(TopologyWarning::CreaseEdgeMissing {
                    crease: i,
                    v0: c.v0,
                    v1: c.v1,
                }),
            }
        }
        for c in corners {
            if let Some(s) = self.vert_sharpness.get_mut(c.vertex as usize) {
                *s = c.sharpness;
            }
        }
        for &h in holes {
            if let Some(x) = self.face_holes.get_mut(h as usize) {
                *x = true;
                self.has_holes = true;
            }
        }
    }

    /// Sharpens boundaries and non-manifold features and derives edge and vertex tags and
    /// rules (OpenSubdiv's `prepareComponentTagsAndSharpness`).
    fn prepare_tags_and_sharpness(&mut self, options: &Options) {
        let nv = self.num_vertices as usize;
        if options.boundary == BoundaryInterpolation::None {
            for v in 0..nv {
                let ve = self.vertex_edges(v);
                let interior_manifold =
                    ve.len() == self.vertex_faces(v).len() && !self.vert_tags[v].get().non_manifold;
                if interior_manifold {
                    continue;
                }
                let exclude = ve.iter().any(|&e| {
                    self.edge_face_list(e as usize).len() == 1
                        && !crease::is_infinite(self.edge_sharpness[e as usize])
                });
                if exclude {
                    for i in range(&self.vert_face_offsets, v) {
                        self.face_holes[self.vert_faces[i] as usize] = true;
                    }
                    self.has_holes = true;
                }
            }
        }
        for e in 0..self.num_edges() {
            let mut tag = self.edge_tags[e].get();
            tag.boundary = self.edge_face_offsets[e + 1] - self.edge_face_offsets[e] < 2;
            if tag.boundary || tag.non_manifold {
                self.edge_sharpness[e] = crease::SHARPNESS_INFINITE;
            }
            let s = self.edge_sharpness[e];
            tag.inf_sharp = crease::is_infinite(s);
            tag.semi_sharp = crease::is_sharp(s) && !tag.inf_sharp;
            self.edge_tags[e] = tag.into();
        }
        let sharpen_corners = options.boundary == BoundaryInterpolation::EdgeAndCorner;
        for v in 0..nv {
            let (mut boundary, mut inf, mut semi, mut nonman) = (0, 0, 0, 0);
            for &e in self.vertex_edges(v) {
                let t = self.edge_tags[e as usize].get();
                boundary += t.boundary as usize;
                inf += t.inf_sharp as usize;
                semi += t.semi_sharp as usize;
                nonman += t.non_manifold as usize;
            }
            let nfaces = self.vertex_faces(v).len();
            let nedges = self.vertex_edges(v).len();
            let topological_corner = nfaces == 1 && nedges == 2;
            let mut tag = self.vert_tags[v].get();
            if topological_corner && sharpen_corners {
                self.vert_sharpness[v] = crease::SHARPNESS_INFINITE;
                tag.sharpened_corner = true;
            } else if tag.non_manifold {
                // Not on an interior non-manifold crease (two non-manifold edges, more faces
                // than edges, no boundary): sharpen.
                if !(nonman == 2 && boundary == 0 && nfaces > nedges) {
                    self.vert_sharpness[v] = crease::SHARPNESS_INFINITE;
                }
            }
            let s = self.vert_sharpness[v];
            tag.inf_sharp = crease::is_infinite(s);
            tag.semi_sharp = crease::is_semi_sharp(s);
            tag.semi_sharp_edges = semi > 0;
            tag.inf_sharp_edges = inf > 0;
            tag.boundary = boundary > 0;
            tag.rule = crease::vertex_rule(s, inf + semi);
            self.vert_tags[v] = tag.into();
        }
    }

    /// Sets vertex `v`'s sharpness to `s` and derives its tag and rule again from it and its
    /// edges' tags, as [`Topology::from_mesh`] does (for a vertex that the boundary option
    /// does not sharpen): a refined level re-tagged as reading it back from a file tags it.
    pub(crate) fn set_vertex_sharpness(&mut self, v: usize, s: f32) {
        let (mut inf, mut semi) = (0, 0);
        for &e in self.vertex_edges(v) {
            let t = self.edge_tags[e as usize].get();
            inf += t.inf_sharp as usize;
            semi += t.semi_sharp as usize;
        }
        self.vert_sharpness[v] = s;
        let mut tag = self.vert_tags[v].get();
        tag.inf_sharp = crease::is_infinite(s);
        tag.semi_sharp = crease::is_semi_sharp(s);
        tag.rule = crease::vertex_rule(s, inf + semi);
        self.vert_tags[v] = tag.into();
    }

    /// Rejects non-manifold topology with an error naming the first offending element:
    /// an edge with more than two faces, two faces running an edge the same way, or a
    /// vertex whose faces form more than one fan.
    pub fn check_manifold(&self) -> Result<(), MeshError> {
        for e in 0..self.num_edges() {
            if !self.edge_tags[e].get().non_manifold {
                continue;
            }
            let ef = self.edge_face_list(e);
            let [v0, v1] = self.edge_verts[e];
            if ef.len() > 2 {
                return Err(MeshError::NonManifoldEdge {
                    v0,
                    v1,
                    faces: ef.len(),
                    first: ef[0],
                    second: ef[1],
                });
            }
            if ef.len() == 2 {
                return Err(MeshError::InconsistentOrientation {
                    f0: ef[0],
                    f1: ef[1],
                    v0,
                    v1,
                });
            }
        }
        for v in 0..self.num_vertices() {
            let nf = self.vertex_faces(v).len();
            if self.vert_tags[v].get().non_manifold && nf > 0 {
                return Err(MeshError::NonManifoldVertex {
                    vertex: v as u32,
                    faces: nf,
                });
            }
        }
        Ok(())
    }

    /// The edge between `v0` and `v1`, if any.
    pub fn find_edge(&self, v0: u32, v1: u32) -> Option<u32> {
        if v0 == v1 || v0 >= self.num_vertices || v1 >= self.num_vertices {
            return None;
        }
        self.vertex_edges(v0 as usize).iter().copied().find(|&e| {
            let ev = self.edge_verts[e as usize];
            ev[0] == v1 || ev[1] == v1
        })
    }

    /// Number of vertices.
    #[inline]
    pub fn num_vertices(&self) -> usize {
        self.num_vertices as usize
    }
    /// Number of edges.
    #[inline]
    pub fn num_edges(&self) -> usize {
        self.edge_verts.len()
    }
    /// Number of faces.
    #[inline]
    pub fn num_faces(&self) -> usize {
        self.face_offsets.len() - 1
    }
    /// Largest number of edges or faces at a vertex.
    pub fn max_valence(&self) -> usize {
        self.max_valence as usize
    }
    /// Vertices of face `f`, counter-clockwise.
    #[inline]
    pub fn face_vertices(&self, f: usize) -> &[u32] {
        &self.face_verts[range(&self.face_offsets, f)]
    }
    /// Edges of face `f`; edge `i` joins vertex `i` and `i + 1`.
    #[inline]
    pub fn face_edge_list(&self, f: usize) -> &[u32] {
        &self.face_edges[range(&self.face_offsets, f)]
    }
    /// Whether face `f` is a hole.
    #[inline]
    pub fn is_hole(&self, f: usize) -> bool {
        self.face_holes[f]
    }
    /// End vertices of edge `e`.
    #[inline]
    pub fn edge_vertices(&self, e: usize) -> [u32; 2] {
        self.edge_verts[e]
    }
    /// Faces of edge `e`, in face order.
    #[inline]
    pub fn edge_face_list(&self, e: usize) -> &[u32] {
        &self.edge_faces[range(&self.edge_face_offsets, e)]
    }
    /// Faces around vertex `v` (counter-clockwise if manifold).
    #[inline]
    pub fn vertex_faces(&self, v: usize) -> &[u32] {
        &self.vert_faces[range(&self.vert_face_offsets, v)]
    }
    /// Position of `v` in each of [`vertex_faces`](Self::vertex_faces).
    #[inline]
    pub fn vertex_face_locals(&self, v: usize) -> &[u16] {
        &self.vert_face_local[range(&self.vert_face_offsets, v)]
    }
    /// Edges around vertex `v` (counter-clockwise if manifold).
    #[inline]
    pub fn vertex_edges(&self, v: usize) -> &[u32] {
        &self.vert_edges[range(&self.vert_edge_offsets, v)]
    }
    /// Which end (0 or 1) of each of [`vertex_edges`](Self::vertex_edges) `v` is.
    #[inline]
    pub fn vertex_edge_locals(&self, v: usize) -> &[u8] {
        &self.vert_edge_local[range(&self.vert_edge_offsets, v)]
    }
    /// The vertex at the other end of each edge around `v`.
    pub fn vertex_neighbours(&self, v: usize) -> impl Iterator<Item = u32> + '_ {
        self.vertex_edges(v)
            .iter()
            .zip(self.vertex_edge_locals(v))
            .map(move |(&e, &l)| self.edge_verts[e as usize][1 - l as usize])
    }
    /// Sharpness of edge `e` (boundary and non-manifold edges: 10, infinitely sharp).
    #[inline]
    pub fn edge_sharpness(&self, e: usize) -> f32 {
        self.edge_sharpness[e]
    }
    /// Sharpness of vertex `v`.
    #[inline]
    pub fn vertex_sharpness(&self, v: usize) -> f32 {
        self.vert_sharpness[v]
    }
    /// Tags of edge `e`.
    #[inline]
    pub fn edge_tag(&self, e: usize) -> EdgeTag {
        self.edge_tags[e].get()
    }
    /// Tags of vertex `v`.
    #[inline]
    pub fn vertex_tag(&self, v: usize) -> VertexTag {
        self.vert_tags[v].get()
    }
    /// Whether the adjacency beyond faces and edge vertices is present (see
    /// [`crate::refine::TopologyRefiner`]; always true for levels it returns).
    pub fn is_complete(&self) -> bool {
        self.complete
    }
    /// Whether any face is a hole.
    pub fn has_holes(&self) -> bool {
        self.has_holes
    }
    /// CSR face offsets.
    pub fn face_offsets(&self) -> &[u32] {
        &self.face_offsets
    }
    /// CSR face-vertex indices.
    pub fn face_verts(&self) -> &[u32] {
        &self.face_verts
    }
}

impl Topology {
    /// Appends to `out` everything of this topology that refinement and the limit surface
    /// read — sizes, every relation in its order, tags and sharpness — so that two
    /// topologies with equal keys refine identically, level after level. Used to share the
    /// local refinement of one neighbourhood between all faces that have the same one.
    pub(crate) fn structure_key(&self, out: &mut Vec<u32>) {
        self.structure_key_with(out, |_| true, |_| true);
    }

    /// [`structure_key`](Self::structure_key) with the tags and sharpness of vertex `c`
    /// and of its edges only (every other vertex's and edge's written as zeros): of the
    /// faces around a vertex `c` whose edges are not semi-sharp, all that decides one
    /// step's children of `c`, of its edges and of its faces, the points of a corner's
    /// eigen-analysis; the rules of the other vertices and edges decide only points
    /// farther out. (A semi-sharp edge at `c` would not do: under Chaikin's rule its
    /// midpoint's rule depends on the edges at its far end. Corners are analysed only once
    /// no semi-sharp edge is left at them, `limit::corner::is_limit_corner`, or 48 levels
    /// down, where none is left either.)
    pub(crate) fn corner_structure_key(&self, c: usize, out: &mut Vec<u32>) {
        let edges = self.vertex_edges(c);
        self.structure_key_with(out, |v| v == c, |e| edges.contains(&(e as u32)));
    }

    fn structure_key_with(
        &self,
        out: &mut Vec<u32>,
        vertex: impl Fn(usize) -> bool,
        edge: impl Fn(usize) -> bool,
    ) {
        fn list(out: &mut Vec<u32>, xs: impl ExactSizeIterator<Item = u32>) {
            out.push(xs.len() as u32);
            out.extend(xs);
        }
        let kept = |keep: bool, x: u32| if keep { x } else { 0 };
        out.push(self.num_vertices);
        list(out, self.face_offsets.iter().copied());
        list(out, self.face_verts.iter().copied());
        list(out, self.face_edges.iter().copied());
        list(out, self.face_holes.iter().map(|&h| h as u32));
        list(out, self.edge_verts.as_flattened().iter().copied());
        list(out, self.edge_face_offsets.iter().copied());
        list(out, self.edge_faces.iter().copied());
        list(out, self.edge_face_local.iter().map(|&x| x as u32));
        list(out, self.vert_face_offsets.iter().copied());
        list(out, self.vert_faces.iter().copied());
        list(out, self.vert_face_local.iter().map(|&x| x as u32));
        list(out, self.vert_edge_offsets.iter().copied());
        list(out, self.vert_edges.iter().copied());
        list(out, self.vert_edge_local.iter().map(|&x| x as u32));
        let edges = self.edge_sharpness.iter().zip(&self.edge_tags).enumerate();
        list(
            out,
            edges.clone().map(|(e, (x, _))| kept(edge(e), x.to_bits())),
        );
        let verts = self.vert_sharpness.iter().zip(&self.vert_tags).enumerate();
        list(
            out,
            verts
                .clone()
                .map(|(v, (x, _))| kept(vertex(v), x.to_bits())),
        );
        list(out, edges.map(|(e, (_, t))| kept(edge(e), t.bits())));
        list(out, verts.map(|(v, (_, t))| kept(vertex(v), t.bits())));
        out.extend([
            self.max_valence,
            self.has_holes as u32,
            self.complete as u32,
        ]);
    }

    /// The part of this level made of `faces` (each listed once), with every relation,
    /// tag and sharpness copied rather than re-derived: edges keep their identity (two
    /// edges between the same vertices stay two, as around degenerate faces), rules and
    /// sharpness stay those of the whole level, and faces and edges around each vertex keep
    /// their order, restricted to the subset. Elements on the subset's rim have incomplete
    /// neighbourhoods (refining them gives meaningless values, which callers must not use);
    /// around such a vertex of many faces of which the subset holds few, those are listed
    /// in the subset's order instead ([`rim_corners`]).
    ///
    /// Returns the subset and, for each of its vertices, the vertex of `self`.
    pub(crate) fn subset(&self, faces: &[u32]) -> (Topology, Vec<u32>) {
        self.subset_with(faces, false)
    }

    /// [`subset`](Self::subset) in a form that does not depend on where this level starts
    /// the cyclic lists of faces and edges around its interior manifold vertices, nor on the
    /// direction of its edges or the order of an edge's faces, nor on which corner the
    /// faces after the first are listed from: around each such vertex, both lists start at
    /// its face listed first in `faces` (for a vertex on the subset's rim, the parts of the
    /// lists in the subset), each edge runs from its lower-numbered end, and its faces are
    /// in the subset's order; every face but the first is listed from its corner that
    /// comes first in the subset's numbering of the faces before it
    /// ([`canonical_rotations`]). The Catmull-Clark rules depend on none of these, so the
    /// surface is the same (to rounding: sums run in another order), and faces whose
    /// neighbourhoods differ only by them get the same
    /// [`structure_key`](Self::structure_key): around a symmetric pole of valence `n`, one
    /// configuration instead of `n`; on a scanned triangulation, whose triangles are
    /// listed from arbitrary corners, one per shape of 1-ring and corner of the face
    /// instead of one per face. The first face keeps its corners' order (its parameter
    /// domain).
    pub(crate) fn subset_canonical(&self, faces: &[u32]) -> (Topology, Vec<u32>) {
        self.subset_with(faces, true)
    }

    /// Whether refining vertex `v` sums three or more semi-sharp values in `f32`, in the
    /// order of its edges: Chaikin's average of its semi-sharp edges
    /// ([`subdivide_edge_sharpness`](crate::scheme::crease::subdivide_edge_sharpness)) and
    /// the fractional weight of a change of rule
    /// ([`fractional_weight`](crate::scheme::crease::fractional_weight)), as OpenSubdiv
    /// sums them. Such a sum of values like 0.3, 0.7 and 3.7 depends on the order in its
    /// last bit (a limit point 8e-9 off the limit of refinement when the cycle started
    /// elsewhere), and under Chaikin's rule a bit can become a whole step, as a child edge
    /// of sharpness `1e-7` instead of 0 is semi-sharp and enters its neighbours' average
    /// the next level (OpenSubdiv's `Bfr`, which orders such sums its own way, is 4e-3 off
    /// OpenSubdiv's own refinement on that example). So
    /// [`subset_canonical`](Self::subset_canonical) keeps the level's own order around
    /// such a vertex, the order the whole mesh refines in.
    fn sharpness_sums_depend_on_order(&self, v: u32) -> bool {
        let edges = self.vertex_edges(v as usize);
        let semi = |s: f32| crease::is_semi_sharp(s) as usize;
        let n = semi(self.vert_sharpness[v as usize])
            + edges
                .iter()
                .map(|&e| semi(self.edge_sharpness[e as usize]))
                .sum::<usize>();
        n >= 3
    }

    fn subset_with(&self, faces: &[u32], canonical: bool) -> (Topology, Vec<u32>) {
        let sub = Subset::new(self, faces, canonical);
        let (face_offsets, face_verts, face_edges) = sub.face_lists();
        let mut t = Topology {
            num_vertices: sub.verts.len() as u32,
            face_offsets,
            face_verts,
            face_edges,
            face_holes: faces.iter().map(|&f| self.face_holes[f as usize]).collect(),
            has_holes: self.has_holes,
            complete: true,
            ..Topology::default()
        };
        sub.fill_edges(&mut t);
        sub.fill_vertices(&mut t, canonical);
        if canonical {
            canonical_edge_order(&mut t);
        }
        t.max_valence = t.largest_valence();
        (t, sub.verts)
    }

    /// The largest number of edges or faces around a vertex.
    fn largest_valence(&self) -> u32 {
        (0..self.num_vertices())
            .map(|v| self.vertex_edges(v).len().max(self.vertex_faces(v).len()) as u32)
            .max()
            .unwrap_or(0)
    }
}

/// The corners (vertex, edge) of face `f` of `level`, listed from its corner `r` on.
#[inline]
fn rotated_corners(level: &Topology, f: u32, r: usize) -> impl Iterator<Item = (u32, u32)> + '_ {
    let f = f as usize;
    let (fv, fe) = (level.face_vertices(f), level.face_edge_list(f));
    let n = fv.len();
    // `r + k` wraps once at most (without a division: this runs for every corner).
    (0..n).map(move |k| {
        let j = if r + k < n { r + k } else { r + k - n };
        (fv[j], fe[j])
    })
}

/// A subset of a level's faces as [`Topology::subset_with`] builds it: the faces, where
/// each one's listing starts, and the subset's numbering of the level's vertices, edges
/// and faces (in order of first appearance).
struct Subset<'a> {
    level: &'a Topology,
    faces: &'a [u32],
    rotations: Vec<usize>,
    vmap: SubsetMap,
    emap: SubsetMap,
    fmap: SubsetMap,
    /// The level's vertices in the subset, by their number there.
    verts: Vec<u32>,
    /// The level's edges in the subset, by their number there.
    edges: Vec<u32>,
}

impl<'a> Subset<'a> {
    /// The numbering of the subset `faces` of `level`, each face listed from its first
    /// corner, or (`canonical`) from the corner [`canonical_rotations`] picks.
    fn new(level: &'a Topology, faces: &'a [u32], canonical: bool) -> Self {
        let rotations = if canonical {
            canonical_rotations(level, faces)
        } else {
            vec![0; faces.len()]
        };
        let n = faces.len();
        let corners =
            || (faces.iter().zip(&rotations)).flat_map(|(&f, &r)| rotated_corners(level, f, r));
        let m = (faces.iter())
            .map(|&f| level.face_vertices(f as usize).len())
            .sum();
        let (vmap, verts) =
            SubsetMap::numbering(corners().map(|(v, _)| v), m, level.num_vertices(), n);
        let (emap, edges) =
            SubsetMap::numbering(corners().map(|(_, e)| e), m, level.edge_verts.len(), n);
        let (fmap, _) = SubsetMap::numbering(faces.iter().copied(), n, level.num_faces(), n);
        Subset {
            level,
            faces,
            rotations,
            vmap,
            emap,
            fmap,
            verts,
            edges,
        }
    }

    /// The corners of the subset's face `i`, from its rotation on.
    #[inline]
    fn corners(&self, i: usize) -> impl Iterator<Item = (u32, u32)> + '_ {
        rotated_corners(self.level, self.faces[i], self.rotations[i])
    }

    /// The position in the subset's face `lf` of the corner at position `k` in the level's.
    #[inline]
    fn local(&self, lf: u32, k: u16) -> u16 {
        let r = self.rotations[lf as usize];
        if r == 0 {
            return k;
        }
        let n = self
            .level
            .face_vertices(self.faces[lf as usize] as usize)
            .len();
        let j = k as usize + n - r;
        (if j < n { j } else { j - n }) as u16
    }

    /// The subset's face → vertices and face → edges (offsets, vertices, edges).
    fn face_lists(&self) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
        let mut face_offsets = Vec::with_capacity(self.faces.len() + 1);
        face_offsets.push(0u32);
        let mut face_verts = Vec::new();
        let mut face_edges = Vec::new();
        for i in 0..self.faces.len() {
            for (v, e) in self.corners(i) {
                face_verts.push(self.vmap.get(v).unwrap_or(0));
                face_edges.push(self.emap.get(e).unwrap_or(0));
            }
            face_offsets.push(face_verts.len() as u32);
        }
        (face_offsets, face_verts, face_edges)
    }

    /// The subset's edges in `t`: their vertices, sharpness, tags, and faces (those in the
    /// subset, in the level's order).
    fn fill_edges(&self, t: &mut Topology) {
        let level = self.level;
        let edges = &self.edges;
        t.edge_verts = edges
            .iter()
            .map(|&e| level.edge_verts[e as usize].map(|v| self.vmap.get(v).unwrap_or(0)))
            .collect();
        t.edge_sharpness = edges
            .iter()
            .map(|&e| level.edge_sharpness[e as usize])
            .collect();
        t.edge_tags = edges.iter().map(|&e| level.edge_tags[e as usize]).collect();
        t.edge_face_offsets.push(0);
        for &e in edges {
            for i in range(&level.edge_face_offsets, e as usize) {
                if let Some(lf) = self.fmap.get(level.edge_faces[i]) {
                    t.edge_faces.push(lf);
                    t.edge_face_local
                        .push(self.local(lf, level.edge_face_local[i]));
                }
            }
            t.edge_face_offsets.push(t.edge_faces.len() as u32);
        }
    }

    /// The subset's vertices in `t`: their sharpness, tags, and faces and edges (those in
    /// the subset, in the level's rotational order, or listed from the subset's faces
    /// around vertices of too many faces to walk, see [`rim_corners`]).
    fn fill_vertices(&self, t: &mut Topology, canonical: bool) {
        let level = self.level;
        t.vert_sharpness = (self.verts.iter())
            .map(|&v| level.vert_sharpness[v as usize])
            .collect();
        t.vert_tags = (self.verts.iter())
            .map(|&v| level.vert_tags[v as usize])
            .collect();
        t.vert_face_offsets.push(0);
        t.vert_edge_offsets.push(0);
        let rim = rim_corners(level, self.faces, &self.verts, &self.vmap, &self.rotations);
        for (i, &v) in self.verts.iter().enumerate() {
            match rim.get(&(i as u32)) {
                Some(corners) => push_rim_vertex(t, i as u32, corners),
                None => self.push_vertex(t, v, canonical),
            }
        }
    }

    /// Appends the faces and edges of the level's vertex `v` that are in the subset to
    /// `t`'s vertex relations. They start at the level's own start, or (`canonical`,
    /// around an interior manifold vertex, whose face `k` and edge `k` go together,
    /// unless the order of its sums of sharpness matters) at the subset's first face
    /// around `v`.
    fn push_vertex(&self, t: &mut Topology, v: u32, canonical: bool) {
        let level = self.level;
        let faces_v = range(&level.vert_face_offsets, v as usize);
        let edges_v = range(&level.vert_edge_offsets, v as usize);
        let tag = level.vert_tags[v as usize].get();
        let cyclic = !tag.boundary && !tag.non_manifold && faces_v.len() == edges_v.len();
        let start = if canonical && cyclic && !level.sharpness_sums_depend_on_order(v) {
            faces_v
                .clone()
                .filter_map(|i| self.fmap.get(level.vert_faces[i]).map(|lf| (lf, i)))
                .min()
                .map_or(0, |(_, i)| i - faces_v.start)
        } else {
            0
        };
        let from = |r: &std::ops::Range<usize>| {
            // `start` is 0 unless the two lists have the same length.
            let a = r.start + start;
            (a..r.end).chain(r.start..a)
        };
        for i in from(&faces_v) {
            if let Some(lf) = self.fmap.get(level.vert_faces[i]) {
                t.vert_faces.push(lf);
                t.vert_face_local
                    .push(self.local(lf, level.vert_face_local[i]));
            }
        }
        t.vert_face_offsets.push(t.vert_faces.len() as u32);
        for i in from(&edges_v) {
            if let Some(le) = self.emap.get(level.vert_edges[i]) {
                t.vert_edges.push(le);
                t.vert_edge_local.push(level.vert_edge_local[i]);
            }
        }
        t.vert_edge_offsets.push(t.vert_edges.len() as u32);
    }
}

/// Appends the faces and edges of the subset's vertex `i` to `t`'s vertex relations from
/// its `corners` (face, position) in the subset's faces ([`rim_corners`]): the faces in
/// that order, each face's edges into and out of the vertex once.
fn push_rim_vertex(t: &mut Topology, i: u32, corners: &[(u32, u16)]) {
    for &(lf, k) in corners {
        t.vert_faces.push(lf);
        t.vert_face_local.push(k);
    }
    t.vert_face_offsets.push(t.vert_faces.len() as u32);
    let first = t.vert_edges.len();
    for &(lf, k) in corners {
        let fe = t.face_edge_list(lf as usize);
        let n = fe.len();
        for le in [fe[(k as usize + n - 1) % n], fe[k as usize]] {
            if !t.vert_edges[first..].contains(&le) {
                t.vert_edges.push(le);
                let end = (t.edge_verts[le as usize][0] != i) as u8;
                t.vert_edge_local.push(end);
            }
        }
    }
    t.vert_edge_offsets.push(t.vert_edges.len() as u32);
}

/// Puts a canonical subset's edges in an order independent of how the level was built:
/// each edge from its lower-numbered end (the subset numbers its vertices in the order of
/// its faces), and the faces of each edge in the subset's order.
fn canonical_edge_order(t: &mut Topology) {
    let flip: Vec<bool> = t.edge_verts.iter().map(|&[a, b]| a > b).collect();
    for (ev, &f) in t.edge_verts.iter_mut().zip(&flip) {
        if f {
            ev.swap(0, 1);
        }
    }
    for (&e, end) in t.vert_edges.iter().zip(&mut t.vert_edge_local) {
        if flip[e as usize] {
            *end = 1 - *end;
        }
    }
    let mut pairs: Vec<(u32, u16)> = Vec::new();
    for e in 0..t.edge_verts.len() {
        let r = range(&t.edge_face_offsets, e);
        pairs.clear();
        pairs.extend(
            t.edge_faces[r.clone()]
                .iter()
                .copied()
                .zip(t.edge_face_local[r.clone()].iter().copied()),
        );
        pairs.sort_unstable();
        for (i, &(f, l)) in r.zip(&pairs) {
            (t.edge_faces[i], t.edge_face_local[i]) = (f, l);
        }
    }
}

/// Vertices of a level with more faces than this may be listed from the subset's faces
/// rather than walked (see [`rim_corners`]).
const RIM_VALENCE: usize = 128;

/// For each vertex of a subset (by its number there) that has more than [`RIM_VALENCE`]
/// faces in the level and more than eight times as many as the subset has faces, the
/// subset's faces that have it as a corner, as `(face, corner)` in the subset, in the
/// subset's order. Such a vertex lies on the subset's rim (the subset does not hold most
/// of its faces), where the order of its faces and edges is read by nobody (its
/// neighbourhood is incomplete, so nothing is evaluated there), so [`Topology::subset`]
/// lists them so instead of walking the vertex's faces in the level: the few faces around
/// a corner next to the centre of a face of thousands of vertices (an `n`-gon's sub-faces
/// after a step, whose corners are analysed one by one) walked all of the centre's, which
/// made analysing them all `O(n²)`.
fn rim_corners(
    level: &Topology,
    faces: &[u32],
    verts: &[u32],
    vmap: &SubsetMap,
    rotations: &[usize],
) -> HashMap<u32, Vec<(u32, u16)>> {
    let limit = RIM_VALENCE.max(8 * faces.len());
    let mut rim: HashMap<u32, Vec<(u32, u16)>> = HashMap::new();
    if !verts
        .iter()
        .any(|&v| level.vertex_faces(v as usize).len() > limit)
    {
        return rim;
    }
    for (lf, &f) in faces.iter().enumerate() {
        let fv = level.face_vertices(f as usize);
        let (n, r) = (fv.len(), rotations[lf]);
        for (k, &v) in fv.iter().enumerate() {
            if level.vertex_faces(v as usize).len() <= limit {
                continue;
            }
            let Some(lv) = vmap.get(v) else { continue };
            // The corner's place in the face after its rotation (see `subset_with`).
            let local = (k + n - r) % n;
            rim.entry(lv).or_default().push((lf as u32, local as u16));
        }
    }
    rim
}

/// Indices of a level numbered in a subset ([`Topology::subset`]): a table over the
/// level's indices when the level is not much larger than the subset (the refinement of a
/// cut-out, which the configuration trees subset at every node), else a small hash table
/// of the subset's own (a base mesh, of which a cut-out is a few dozen faces, cut out for
/// every irregular face). The table over the level is the faster where it is small enough
/// to fill.
enum SubsetMap {
    /// `table[x]` is `x`'s number, `u32::MAX` if `x` is not in the subset.
    Table(Vec<u32>),
    /// Open addressing with linear probing: `(x, number)` at the first free slot from
    /// `x`'s hash on, `x = u32::MAX` in a free slot; at most half the slots are taken.
    Hashed(Vec<(u32, u32)>),
}

impl SubsetMap {
    /// The numbering of `items` (`count` of them at most, indices below `size`, of a
    /// subset of `faces` faces) in order of first appearance, and the distinct items in
    /// that order: by a table if `size` is at most 64 times `faces` (a tree node's level
    /// has about ten times as many elements as its cut-out has faces).
    fn numbering(
        items: impl Iterator<Item = u32>,
        count: usize,
        size: usize,
        faces: usize,
    ) -> (Self, Vec<u32>) {
        Self::numbering_by(items, count, size, size <= 64 * faces)
    }

    /// [`numbering`](Self::numbering) by a table over the level or by hashing.
    fn numbering_by(
        items: impl Iterator<Item = u32>,
        count: usize,
        size: usize,
        table: bool,
    ) -> (Self, Vec<u32>) {
        let mut distinct = Vec::with_capacity(count);
        if table {
            let mut table = vec![u32::MAX; size];
            for x in items {
                let slot = &mut table[x as usize];
                if *slot == u32::MAX {
                    *slot = distinct.len() as u32;
                    distinct.push(x);
                }
            }
            return (SubsetMap::Table(table), distinct);
        }
        let mut slots = vec![(u32::MAX, 0); (2 * count).next_power_of_two().max(8)];
        for x in items {
            let i = Self::probe(&slots, x);
            if slots[i].0 == u32::MAX {
                slots[i] = (x, distinct.len() as u32);
                distinct.push(x);
            }
        }
        (SubsetMap::Hashed(slots), distinct)
    }

    /// The slot of `x` in `slots`, or the free one where it would go (Fibonacci hashing:
    /// the high bits of `x` times 2³²/φ pick the first slot).
    #[inline]
    fn probe(slots: &[(u32, u32)], x: u32) -> usize {
        let mask = slots.len() - 1;
        let mut i = Self::home(x, slots.len());
        loop {
            let k = slots[i].0;
            if k == x || k == u32::MAX {
                return i;
            }
            i = (i + 1) & mask;
        }
    }

    /// The first slot tried for `x` in `len` slots (a power of two, `2^k` with
    /// `3 ≤ k ≤ 32`): the top `k` bits of `x` times `2³²/φ`.
    #[inline]
    fn home(x: u32, len: usize) -> usize {
        (x.wrapping_mul(0x9E37_79B9) >> (32 - len.trailing_zeros())) as usize
    }

    /// The number of `x`, if it is in the subset.
    #[inline]
    fn get(&self, x: u32) -> Option<u32> {
        match self {
            SubsetMap::Table(table) => Some(table[x as usize]).filter(|&n| n != u32::MAX),
            SubsetMap::Hashed(slots) => {
                let (k, n) = slots[Self::probe(slots, x)];
                (k == x).then_some(n)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A subset numbers a level's indices the same by a table and by hashing: in order
    /// of first appearance, absent ones absent; also when they all start at one slot of
    /// the hash table (40 distinct items, 43 with repeats: 128 slots).
    #[test]
    fn subset_maps_number_alike() {
        let same_home: Vec<u32> = (1..)
            .filter(|&x| SubsetMap::home(x, 128) == SubsetMap::home(1, 128))
            .take(40)
            .collect();
        assert_eq!((2 * 43usize).next_power_of_two(), 128);
        let colliding: Vec<u32> = same_home
            .iter()
            .copied()
            .chain([same_home[3], 1, 7])
            .collect();
        let few = vec![7u32, 3, 7, 0, 9, 3, 12, 0, 5];
        for items in [few, colliding] {
            let size = *items.iter().max().unwrap() as usize + 2;
            let n = items.len();
            let (table, a) = SubsetMap::numbering_by(items.iter().copied(), n, size, true);
            let (hashed, b) = SubsetMap::numbering_by(items.iter().copied(), n, size, false);
            assert_eq!(a, b);
            // Every item, and others of the level around them that are absent.
            let probes = items.iter().flat_map(|&x| [x, x + 1]).chain(0..size as u32);
            for x in probes.filter(|&x| (x as usize) < size) {
                let want = a.iter().position(|&y| y == x).map(|i| i as u32);
                assert_eq!(table.get(x), want, "{x}");
                assert_eq!(hashed.get(x), want, "{x}");
            }
        }
        let (_, a) = SubsetMap::numbering_by([7u32, 3, 7, 0, 9].into_iter(), 5, 10, false);
        assert_eq!(a, [7, 3, 0, 9]);
    }

    /// On every vertex of `t` where the order follows from the corners ([`order_corners`],
    /// given the vertex's corners in face order as `from_faces` lists them), checks that
    /// it is the walk's ([`Topology::order_vertex`]); returns on how many of them it does.
    fn check_corner_order(t: &Topology, name: &str) -> usize {
        let mut order = Vec::new();
        let mut by_corners = 0;
        for v in 0..t.num_vertices() {
            let mut records: Vec<(u32, u16)> = (t.vertex_faces(v).iter().copied())
                .zip(t.vertex_face_locals(v).iter().copied())
                .collect();
            records.sort_unstable();
            let faces: Vec<u32> = records.iter().map(|r| r.0).collect();
            let corners: Vec<[u32; 2]> = (records.iter())
                .map(|&(f, l)| {
                    let fe = t.face_edge_list(f as usize);
                    let (n, l) = (fe.len(), usize::from(l));
                    [fe[(l + n - 1) % n], fe[l]]
                })
                .collect();
            let ne = t.vertex_edges(v).len();
            if !order_corners(&faces, &corners, ne, &mut order) {
                continue;
            }
            by_corners += 1;
            let (mut walk_faces, mut walk_edges) = (Vec::new(), Vec::new());
            let lists = (faces.as_slice(), t.vertex_edges(v));
            assert!(
                t.order_vertex(v, lists, &mut walk_faces, &mut walk_edges),
                "{name} vertex {v}"
            );
            let mut edges: Vec<u32> = order.iter().map(|&k| corners[k][1]).collect();
            if ne > faces.len() {
                edges.push(corners[order[order.len() - 1]][0]);
            }
            let ordered: Vec<u32> = order.iter().map(|&k| faces[k]).collect();
            assert_eq!(
                (ordered, edges),
                (walk_faces, walk_edges),
                "{name} vertex {v}"
            );
        }
        by_corners
    }

    /// Where a vertex's order follows from its corners ([`order_corners`]), it is the
    /// walk's ([`Topology::order_vertex`]), on every vertex of every regression shape
    /// (boundaries, holes, n-gons, non-manifold fins, bowties, faces that repeat a vertex)
    /// and of a mesh with faces turned against their neighbours; and it is taken on most
    /// vertices.
    #[test]
    fn corner_order_is_the_walks() {
        let dir = format!("{}/tests/shapes/osd", env!("CARGO_MANIFEST_DIR"));
        let mut meshes: Vec<(String, PolyMesh)> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "obj"))
            .map(|p| {
                let mesh = crate::io::obj::read_obj(&p).unwrap().mesh;
                (p.display().to_string(), mesh)
            })
            .collect();
        // A 4 × 4 grid of quads, two of them turned the other way round.
        let at = |i: u32, j: u32| 5 * j + i;
        let grid: Vec<Vec<u32>> = (0..16)
            .map(|q| {
                let (i, j) = (q % 4, q / 4);
                let f = vec![at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                if q == 5 || q == 10 {
                    f.into_iter().rev().collect()
                } else {
                    f
                }
            })
            .collect();
        let turned = PolyMesh::from_faces(vec![[0.0; 3]; 25], &grid).unwrap();
        meshes.push(("turned".into(), turned));
        // Fans of 40 faces around vertex 0 (past the scan of `order_corners`): closed, open,
        // of quads, and closed with one face turned.
        for (name, n, closed, quads) in [
            ("closed fan", 40u32, true, false),
            ("open fan", 40, false, false),
            ("quad fan", 40, true, true),
            ("turned fan", 41, true, false),
        ] {
            let rim = |i: u32| 1 + i % n;
            let faces: Vec<Vec<u32>> = (0..if closed { n } else { n - 1 })
                .map(|i| {
                    let f = if quads {
                        vec![0, rim(i), n + 1 + i, rim(i + 1)]
                    } else {
                        vec![0, rim(i), rim(i + 1)]
                    };
                    if name == "turned fan" && i == 7 {
                        f.into_iter().rev().collect()
                    } else {
                        f
                    }
                })
                .collect();
            let mesh = PolyMesh::from_faces(vec![[0.0; 3]; 2 * n as usize + 1], &faces).unwrap();
            meshes.push((name.into(), mesh));
        }
        assert!(meshes.len() > 80);
        let (mut by_corners, mut vertices) = (0, 0);
        for (name, mesh) in &meshes {
            let t = Topology::from_mesh(mesh, &Options::default()).unwrap().0;
            by_corners += check_corner_order(&t, name);
            vertices += t.num_vertices();
        }
        assert!(by_corners * 10 > vertices * 9, "{by_corners} of {vertices}");
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig {
            failure_persistence: None,
            ..proptest::prelude::ProptestConfig::default()
        })]
        /// The same on random meshes of a few faces over a few vertices: faces of 3 to 5
        /// corners on any vertices (repeated ones too), so that edges with three or more
        /// faces, bowties, faces turned against their neighbours and faces that repeat a
        /// vertex are common.
        #[test]
        fn corner_order_is_the_walks_on_random_meshes(
            faces in proptest::collection::vec(
                proptest::collection::vec(0u32..7, 3..=5), 1..10)
        ) {
            let mesh = PolyMesh::from_faces(vec![[0.0; 3]; 7], &faces).unwrap();
            if let Ok((t, _)) = Topology::from_mesh(&mesh, &Options::default()) {
                check_corner_order(&t, &format!("{faces:?}"));
            }
        }

        /// The same around one vertex of high valence (so that `order_corners` sorts
        /// instead of scanning): a fan of 17 to 40 triangles around vertex 0, some of them
        /// turned, some left out (open fans, split fans), some repeated.
        #[test]
        fn corner_order_is_the_walks_at_high_valence(
            change in proptest::collection::vec(0u8..12, 17..40)
        ) {
            let n = change.len() as u32;
            let rim = |i: u32| 1 + i % n;
            let mut faces: Vec<Vec<u32>> = Vec::new();
            for (i, &c) in (0..n).zip(&change) {
                let f = vec![0, rim(i), rim(i + 1)];
                match c {
                    0 => {}
                    1 => faces.push(f.into_iter().rev().collect()),
                    2 => {
                        faces.push(f.clone());
                        faces.push(f);
                    }
                    _ => faces.push(f),
                }
            }
            if let Ok(mesh) = PolyMesh::from_faces(vec![[0.0; 3]; n as usize + 1], &faces) {
                if let Ok((t, _)) = Topology::from_mesh(&mesh, &Options::default()) {
                    check_corner_order(&t, &format!("{change:?}"));
                }
            }
        }
    }

    /// The base level's vertex relations, built in blocks of vertices, are those that
    /// refinement builds by its own rules: a mesh with a boundary, a hole's rim,
    /// triangles, a pentagon and a non-manifold fin, refined five levels (22 k
    /// vertices, several blocks), then read back as a base mesh. Around each vertex the
    /// same faces and neighbours in the same counter-clockwise order (from the same first
    /// face on a boundary; interior fans may start anywhere), the same positions in them,
    /// and the same manifold, boundary and valence.
    #[test]
    fn base_vertex_relations_match_refinement() {
        // A 6 × 5 grid of vertices with quad (1, 1) left out, quad (3, 2) split into
        // two triangles, a pentagon over the top row, and a fin on the edge 0-1.
        let at = |i: u32, j: u32| 6 * j + i;
        let mut faces: Vec<Vec<u32>> = Vec::new();
        for j in 0..4 {
            for i in 0..5 {
                let q = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                match (i, j) {
                    (1, 1) => {}
                    (3, 2) => {
                        faces.push(vec![q[0], q[1], q[2]]);
                        faces.push(vec![q[0], q[2], q[3]]);
                    }
                    _ => faces.push(q.to_vec()),
                }
            }
        }
        faces.push(vec![at(0, 4), at(1, 4), at(2, 4), 31, 30]);
        faces.push(vec![at(1, 0), at(0, 0), 32]);
        let mesh = PolyMesh::from_faces(vec![[0.0; 3]; 33], &faces).unwrap();
        let options = Options::default();
        let mut level = Topology::from_mesh(&mesh, &options).unwrap().0;
        for _ in 0..5 {
            level = crate::refine::refine_topology(&level, &options, true);
        }
        let nv = level.num_vertices();
        assert!(nv > 5 * VERTEX_BLOCK, "{nv} vertices");
        let refined = (0..level.num_faces())
            .map(|f| level.face_vertices(f).to_vec())
            .collect::<Vec<_>>();
        let mesh = PolyMesh::from_faces(vec![[0.0; 3]; nv], &refined).unwrap();
        let base = Topology::from_mesh(&mesh, &options).unwrap().0;
        let (mut manifold, mut boundary) = (0, 0);
        for v in 0..nv {
            let (a, b) = (level.vertex_tag(v), base.vertex_tag(v));
            assert_eq!(
                (a.non_manifold, a.boundary),
                (b.non_manifold, b.boundary),
                "vertex {v}"
            );
            // Each face and edge by its vertices (the two levels number edges apart).
            let around = |t: &Topology| {
                let faces = t.vertex_faces(v).to_vec();
                let locals = t.vertex_face_locals(v).to_vec();
                let far: Vec<u32> = (t.vertex_edges(v).iter())
                    .zip(t.vertex_edge_locals(v))
                    .map(|(&e, &l)| {
                        let ends = t.edge_vertices(e as usize);
                        assert_eq!(ends[usize::from(l)] as usize, v, "vertex {v}");
                        ends[1 - usize::from(l)]
                    })
                    .collect();
                for (&f, &l) in faces.iter().zip(&locals) {
                    assert_eq!(t.face_vertices(f as usize)[usize::from(l)] as usize, v);
                }
                (faces, locals, far)
            };
            let (want, got) = (around(&level), around(&base));
            if a.non_manifold {
                continue;
            }
            manifold += 1;
            boundary += usize::from(a.boundary);
            let n = want.0.len();
            // The rotation that puts the base level's first face first.
            let k = if a.boundary || n == 0 {
                0
            } else {
                want.0
                    .iter()
                    .position(|&f| f == got.0[0])
                    .expect("same faces")
            };
            let turn = |x: &[u32]| [&x[k..], &x[..k]].concat();
            let turn16 = |x: &[u16]| [&x[k..], &x[..k]].concat();
            assert_eq!(turn(&want.0), got.0, "faces of vertex {v}");
            assert_eq!(turn16(&want.1), got.1, "positions at vertex {v}");
            assert_eq!(turn(&want.2), got.2, "neighbours of vertex {v}");
        }
        assert_eq!(base.max_valence(), level.max_valence());
        assert!(
            manifold > nv - 100 && boundary > 500,
            "{manifold} {boundary}"
        );
    }

    /// Every edge and vertex tag survives being stored packed, and distinct tags are
    /// stored distinctly.
    #[test]
    fn packed_tags_round_trip() {
        let mut seen = std::collections::HashSet::new();
        for bits in 0u32..16 {
            let b = |k: u32| bits >> k & 1 == 1;
            let t = EdgeTag {
                boundary: b(0),
                non_manifold: b(1),
                semi_sharp: b(2),
                inf_sharp: b(3),
            };
            let packed = PackedEdgeTag::from(t);
            assert_eq!(packed.get(), t);
            assert!(seen.insert(packed.bits()));
        }
        seen.clear();
        for rule in [Rule::Smooth, Rule::Dart, Rule::Crease, Rule::Corner] {
            for bits in 0u32..128 {
                let b = |k: u32| bits >> k & 1 == 1;
                let t = VertexTag {
                    rule,
                    boundary: b(0),
                    non_manifold: b(1),
                    sharpened_corner: b(2),
                    semi_sharp: b(3),
                    inf_sharp: b(4),
                    semi_sharp_edges: b(5),
                    inf_sharp_edges: b(6),
                };
                let packed = PackedVertexTag::from(t);
                assert_eq!(packed.get(), t);
                assert!(seen.insert(packed.bits()));
            }
        }
        assert_eq!(PackedVertexTag::default().get(), VertexTag::default());
        assert_eq!(PackedEdgeTag::default().get(), EdgeTag::default());
    }
}
