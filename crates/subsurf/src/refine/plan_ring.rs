//! Ring patches of a [`RefinePlan`]: the last levels of a face whose
//! corners are manifold vertices of any valence (inside or on a boundary, smooth or
//! sharp), computed from the points of its 1-ring by one fixed matrix per shape of ring
//! and sharpness, as regular patches are computed from 16 points by the bicubic kernel
//! (see `refine/plan_patches.rs`).
//!
//! # Why
//! Regular patches need four regular corners, so every face at an extraordinary vertex,
//! and every face that is not a quad, would be left to the plan's sparse rows, about ten
//! times dearer per vertex. On most quad meshes that is a few percent of the output; on
//! meshes dense in extraordinary vertices it is most of it: in an all-triangle mesh
//! (scans, CAD tessellations) every base face is a triangle, every quad of level 1 has two
//! extraordinary corners (an input vertex of valence about 6 and a face centre of valence
//! 3), and every quad of level 2 one.
//!
//! # Which faces
//! A face `f` (of any size) whose corners are manifold, of valence 3 to [`MAX_VALENCE`]
//! inside or 2 to [`MAX_VALENCE`] on a boundary, with manifold edges; with at most
//! [`MAX_POINTS`] points in its 1-ring (the faces that share a vertex with it), and no two
//! edges of the ring between the same two vertices. Corners and the edges at them may be
//! semi-sharp or infinitely sharp (their sharpness is part of the key, below), except for
//! semi-sharp edges under Chaikin's rule, whose children's sharpness reads edges beyond
//! the ring (test `ring_patches_with_random_creases`).
//!
//! The vertices that any number of levels put on the closed face depend only on its
//! 1-ring, through the masks of its corners, of the edges at its corners and of the faces
//! of the 1-ring: a level-`l + 1` vertex on `f` is a vertex, edge or face point of an
//! element of `f`, whose masks read the corners' fans; the child faces of `f` have as
//! corners children of `f`'s corners, of its edges and of `f` itself, whose fans lie in
//! the refined 1-ring of `f` and were computed by the masks of `f`'s corners, of the edges
//! at them and of the faces around them; and so on down. Every mask used is that of a
//! corner of `f` (smooth, of its valence), of an edge at a corner (smooth, between its
//! two faces; with OpenSubdiv's `smoothtriangles` rule, depending on their sizes) or of a
//! face of the 1-ring (the centroid). The other points of the 1-ring may be anything
//! (extraordinary, sharp, on a boundary): their own masks are never used. So the map from
//! the ring's points to the vertices that `d` levels put on `f` is one matrix for all
//! faces whose 1-rings have the same faces on the same points, once the points are
//! numbered the same way; on an all-triangle mesh, one per triple of corner valences.
//!
//! Boundaries and sharpness keep this true. A corner's whole fan is in the 1-ring, so in
//! the template (a mesh of the ring's faces, below) it has the same faces and the same
//! boundary edges; the key lists the sharpness of the corners and of every edge at them
//! ([`push_sharpness`]), which the template is given as tags and refined with the mesh's
//! options. So each corner has the same rule (smooth, dart, crease, corner, or a blend as
//! sharpness falls below 1) at every level, and the edges at it the same masks and the
//! same decay: uniform decay reads only the edge itself. Masks of points beyond the
//! corners, sharp or not, are never used.
//!
//! # The ring
//! [`ring_net`] lists the faces of the 1-ring from a corner `s` of `f`: `f` itself from
//! `s`, then for each corner in turn (`s`, `s + 1`, …) the faces around it that are not
//! listed yet, counter-clockwise from `f`, each from that corner. The points are numbered
//! in order of first appearance. This list (the ring's *key*) depends only on the shape of
//! the ring and on `s`. The corner is chosen by that shape alone, so that the same ring
//! listed from another corner shares the matrix: among the corners from which the
//! sequence of corner valences is least, the one whose key is least. Two points of the
//! ring may be the same vertex of the mesh (a small closed mesh): the key says so, and
//! the matrix is computed on exactly that. When a corner or an edge at one is sharp, the
//! key goes on with their sharpness values (`f32` bits, as refinement holds them).
//!
//! # The matrix
//! It is computed by refining the 1-ring itself: a mesh of the key's faces
//! ([`Kernel::new`]) refined `d` levels by a plan of sparse rows only (the masks of all
//! refinement, [`RefinePlan`] without patches; each level with the masks of its scheme,
//! Catmull-Clark's or the shape-adjustable one's), applied to the unit
//! vectors of its points; each row is then the refined value at one vertex on the
//! template's face 0 (rows grouped as [`Kernel::new`] says). No mask is written twice, so
//! the matrix cannot disagree with the rows. The template's own boundary rules act only
//! on points beyond the 1-ring's interior, which `f`'s vertices never read (above), and
//! at boundary corners of `f`, where the mesh has the same boundary. Zero entries are
//! dropped.
//!
//! # Which vertices
//! [`descendants`] lists the vertices that `d` levels put on a face, walking down the
//! child numbering of [`refine_topology`] from its corner `s` (child face `j` of a face
//! holds the child of its corner `j`; within a child, the walk starts from that corner):
//! the same list, in the same order, for the template's face 0 from its corner 0 and for
//! `f` from `s`. A vertex shared by two child faces is listed by each, the first time
//! counting; a patch is kept only if its list repeats exactly where the template's does.
//!
//! [`refine_topology`]: super::topology::refine_topology

use crate::mesh::{Corner, Crease, Options, PolyMesh, Topology};

use super::plan::RefinePlan;
use super::plan_patches::{grid_indices, prefetch_next, ring_span, Runs, SharedOut, NOT_OWNED};
use super::topology::rot;
use super::uniform::Steps;
#[cfg(target_arch = "x86_64")]
use crate::cpu::{has_avx2_fma, has_avx512f};
use std::collections::HashMap;

/// Largest valence of a corner of a ring patch. Higher valences are rare and stay with
/// the sparse rows.
pub(super) const MAX_VALENCE: usize = 16;

/// Largest number of points of a ring (held on the stack while a patch is computed): a
/// quad with one corner of valence 16 has 40, a triangle with corners of valence 6, 12.
/// A row of the matrix has up to as many terms.
pub(super) const MAX_POINTS: usize = 64;

/// The 1-ring of a face, read from one of its corners (module docs).
pub(super) struct RingNet {
    /// The ring's faces on the ring's points: for each face, its size then its points,
    /// face 0 being the patch's face from corner `start`; then, if any, the sharpness at
    /// its corners ([`push_sharpness`]). Equal keys, equal matrices.
    pub(super) key: Vec<u32>,
    /// The corner of the face the ring was read from.
    pub(super) start: usize,
    /// The mesh vertex of each point of the ring.
    pub(super) verts: Vec<u32>,
    /// The mesh faces of the ring, in the key's order.
    faces: Vec<u32>,
}

impl RingNet {
    /// A ring of face `f` read from its corner `start`, with no face listed yet.
    fn new(f: usize, start: usize) -> Self {
        RingNet {
            key: Vec::new(),
            start,
            verts: Vec::new(),
            faces: vec![f as u32],
        }
    }

    /// Appends a face to the key: its size, then its points, numbered in order of first
    /// appearance.
    fn push(&mut self, face: impl ExactSizeIterator<Item = u32>) {
        self.key.push(face.len() as u32);
        for v in face {
            let p = self.verts.iter().position(|&x| x == v).unwrap_or_else(|| {
                self.verts.push(v);
                self.verts.len() - 1
            });
            self.key.push(p as u32);
        }
    }
}

/// The "ring" of face `f` of `t` under bilinear subdivision: the face alone, on its
/// corners, read from corner 0 (`None` past [`MAX_POINTS`] corners). Bilinear face,
/// edge and vertex points are the centroid, the midpoint and the vertex itself whatever
/// the rule (smooth, crease, corner, boundary, non-manifold: `scheme::bilinear`), so every
/// vertex that any number of levels put on a face is a fixed combination of its corners:
/// one matrix per face size, whatever the mesh around it.
pub(super) fn face_net(t: &Topology, f: usize) -> Option<RingNet> {
    let fv = t.face_vertices(f);
    if fv.len() > MAX_POINTS {
        return None;
    }
    let mut ring = RingNet::new(f, 0);
    ring.push(fv.iter().copied());
    Some(ring)
}

/// Whether vertex `v` of `t` can be a corner of a ring patch (module docs): manifold, of
/// valence 3 to [`MAX_VALENCE`] inside and 2 to [`MAX_VALENCE`] on a boundary, and, with
/// Chaikin's crease rule, without semi-sharp edges (whose decay reads edges beyond the
/// ring). Its sharpness and that of its edges go into the ring's key.
fn ring_corner(t: &Topology, v: usize, chaikin: bool) -> bool {
    let tag = t.vertex_tag(v);
    let (edges, faces) = (t.vertex_edges(v), t.vertex_faces(v).len());
    let n = edges.len();
    let edges_ok = (edges.iter()).all(|&e| {
        let e = t.edge_tag(e as usize);
        !(e.non_manifold || (chaikin && e.semi_sharp))
    });
    !tag.non_manifold
        && edges_ok
        && n <= MAX_VALENCE
        && if tag.boundary {
            n >= 2 && faces + 1 == n
        } else {
            n >= 3 && faces == n
        }
}

/// The ring of face `f` of `t` read from the corner that the module docs say, if `f`
/// can be a ring patch.
pub(super) fn ring_net(t: &Topology, f: usize, chaikin: bool) -> Option<RingNet> {
    let fv = t.face_vertices(f);
    if !fv.iter().all(|&v| ring_corner(t, v as usize, chaikin)) {
        return None;
    }
    // The corners where the sequence of corner valences (from that corner on) is least,
    // and of their keys the least: a choice made by the shape of the ring alone, for
    // which most faces read one ring instead of one per corner.
    let n = fv.len();
    let valences = |s: usize| (0..n).map(move |j| t.vertex_edges(fv[(s + j) % n] as usize).len());
    let least = (0..n).min_by(|&a, &b| valences(a).cmp(valences(b)))?;
    let mut best: Option<RingNet> = None;
    for start in (0..n).filter(|&s| valences(s).eq(valences(least))) {
        let ring = read_ring(t, f, start)?;
        if best.as_ref().is_none_or(|b| ring.key < b.key) {
            best = Some(ring);
        }
    }
    let ring = best?;
    // The template finds its edges by their ends: so must the mesh, around this face
    // (two edges of the ring between the same two vertices would be one edge of the
    // template).
    let mut edges: Vec<([u32; 2], u32)> = Vec::new();
    for &g in &ring.faces {
        let (gv, ge) = (t.face_vertices(g as usize), t.face_edge_list(g as usize));
        for (k, &e) in ge.iter().enumerate() {
            let (a, b) = (gv[k], gv[(k + 1) % gv.len()]);
            edges.push(([a.min(b), a.max(b)], e));
        }
    }
    edges.sort_unstable();
    edges.dedup();
    edges.windows(2).all(|w| w[0].0 != w[1].0).then_some(ring)
}

/// The ring of face `f` of `t` read from its corner `start` (module docs), or `None`
/// if it has more than [`MAX_POINTS`] points.
fn read_ring(t: &Topology, f: usize, start: usize) -> Option<RingNet> {
    let fv = t.face_vertices(f);
    let n = fv.len();
    let mut ring = RingNet::new(f, start);
    ring.push((0..n).map(|j| fv[(start + j) % n]));
    for j in 0..n {
        let k = (start + j) % n;
        let v = fv[k] as usize;
        let (faces, locals) = (t.vertex_faces(v), t.vertex_face_locals(v));
        let m = faces.len();
        let i0 = (0..m).find(|&i| faces[i] as usize == f && locals[i] as usize == k)?;
        for s in 1..m {
            let g = faces[(i0 + s) % m];
            if ring.faces.contains(&g) {
                continue;
            }
            ring.faces.push(g);
            let gv = t.face_vertices(g as usize);
            let l = locals[(i0 + s) % m] as usize;
            ring.push((0..gv.len()).map(|q| gv[(l + q) % gv.len()]));
        }
        if ring.verts.len() > MAX_POINTS {
            return None;
        }
    }
    push_sharpness(t, &mut ring, n)?;
    Some(ring)
}

/// Marks the end of the faces of a key that goes on with sharpness (no face size or
/// point is this large).
const SHARP_KEY: u32 = u32::MAX;

/// Appends to the key of `ring`, if any corner of its face (its first `n` points) or any
/// edge at one is sharp: [`SHARP_KEY`], the number of such edges, `(point, point,
/// sharpness bits)` for each, sorted, then `(point, sharpness bits)` for each such
/// corner. These are all the sharpness values the face's refined vertices read (module
/// docs). Sharpness that the template would derive itself (boundary edges, a boundary
/// corner of one face in edge-and-corner mode) is listed too: given or derived, it is
/// the same. [`template`] reads it back. `None` if a sharp edge at a corner does not end
/// at ring points (it always does: it lies in a face at that corner).
fn push_sharpness(t: &Topology, ring: &mut RingNet, n: usize) -> Option<()> {
    let point = |v: u32| ring.verts.iter().position(|&x| x == v);
    let mut edges: Vec<[u32; 3]> = Vec::new();
    let mut corners: Vec<[u32; 2]> = Vec::new();
    for (p, &v) in ring.verts[..n].iter().enumerate() {
        let s = t.vertex_sharpness(v as usize);
        if s > 0.0 {
            corners.push([p as u32, s.to_bits()]);
        }
        for &e in t.vertex_edges(v as usize) {
            let s = t.edge_sharpness(e as usize);
            if s > 0.0 {
                let [a, b] = t.edge_vertices(e as usize).map(point);
                let (a, b) = (a? as u32, b? as u32);
                edges.push([a.min(b), a.max(b), s.to_bits()]);
            }
        }
    }
    if edges.is_empty() && corners.is_empty() {
        return Some(());
    }
    edges.sort_unstable();
    edges.dedup();
    ring.key.push(SHARP_KEY);
    ring.key.push(edges.len() as u32);
    ring.key.extend(edges.into_iter().flatten());
    ring.key.extend(corners.into_iter().flatten());
    Some(())
}

/// The template of ring `key`: a mesh of its faces on its points (at the origin), with
/// the sharpness of [`push_sharpness`] as tags. `None` if the key is malformed or its
/// faces are not a valid mesh.
fn template(key: &[u32]) -> Option<PolyMesh> {
    let mut faces = Vec::new();
    let mut rest = key;
    while let Some((&len, tail)) = rest.split_first() {
        if len == SHARP_KEY {
            break;
        }
        let (face, tail) = tail.split_at_checked(len as usize)?;
        faces.push(face);
        rest = tail;
    }
    let points = (faces.iter().copied().flatten().max()).map_or(0, |&m| m as usize + 1);
    let mut mesh = PolyMesh::from_faces(vec![[0.0; 3]; points], &faces).ok()?;
    if let [SHARP_KEY, count, sharp @ ..] = rest {
        let (edges, corners) = sharp.split_at_checked(3 * *count as usize)?;
        let (edges, corners) = (edges.chunks_exact(3), corners.chunks_exact(2));
        mesh.tags.creases = (edges.map(|e| Crease {
            v0: e[0],
            v1: e[1],
            sharpness: f32::from_bits(e[2]),
        }))
        .collect();
        mesh.tags.corners = (corners.map(|c| Corner {
            vertex: c[0],
            sharpness: f32::from_bits(c[1]),
        }))
        .collect();
    }
    Some(mesh)
}

/// Appends to `out` the vertices that `levels.len()` levels of `steps` put on the closed
/// face `f` of `levels[0]`, numbered in the level below the last of `levels`, walking from
/// corner `start` (module docs), with repetitions; `None` if a child face is not where
/// the numbering says.
pub(super) fn descendants(
    steps: Steps,
    levels: &[Topology],
    f: usize,
    start: usize,
    out: &mut Vec<u32>,
) -> Option<()> {
    match steps {
        Steps::Loop => tri_descendants(levels, f, start, out),
        Steps::Family(_) | Steps::Bilinear => quad_descendants(levels, f, start, out),
    }
}

/// [`descendants`] under the Catmull-Clark split ([`refine_topology`](super::topology::refine_topology)): child quad `k` of
/// a face holds the child of its corner `k`, at the quad's corner `rot(n, k)`; the last
/// level lists, from corner `start`, each corner and the child of the edge after it,
/// then the face's child.
fn quad_descendants(levels: &[Topology], f: usize, start: usize, out: &mut Vec<u32>) -> Option<()> {
    let t = &levels[0];
    let fv = t.face_vertices(f);
    let n = fv.len();
    if levels.len() == 1 {
        let fe = t.face_edge_list(f);
        let (nv, nf) = (t.num_vertices() as u32, t.num_faces() as u32);
        for j in 0..n {
            let k = (start + j) % n;
            out.extend([fv[k], nv + nf + fe[k]]);
        }
        out.push(nv + f as u32);
        return Some(());
    }
    let o = t.face_offsets[f] as usize;
    for j in 0..n {
        let k = (start + j) % n;
        let (g, r) = (o + k, rot(n, k));
        let cv = levels[1].face_vertices(g);
        if cv.len() != 4 || cv[r] != fv[k] {
            return None;
        }
        quad_descendants(&levels[1..], g, r, out)?;
    }
    Some(())
}

/// [`descendants`] under Loop's triangle split
/// ([`refine_tri_topology`](super::tri_topology::refine_tri_topology); no face children): triangle `f = [v₀ v₁ v₂]` with edge children `Eⱼ` (of edge `vⱼvⱼ₊₁`, vertex
/// `V + eⱼ`) has the corner children `4f + j = [.., vⱼ at corner j, ..]`, read from
/// corner `j` as `vⱼ, Eⱼ, Eⱼ₋₁`, and the middle one `4f + 3 = [E₁ E₂ E₀]`, which holds
/// `Eⱼ` at corner `j + 2`. From corner `s` the walk lists the corner children `s`, `s + 1`,
/// `s + 2`, each from its corner `j`, then the middle one from `Eₛ`: the same list for
/// every corner `s` read as corner 0, so the template's face 0 from corner 0 and `f`
/// from `s` list matching vertices in the same order. The last level lists each corner
/// and the child of the edge after it.
fn tri_descendants(levels: &[Topology], f: usize, start: usize, out: &mut Vec<u32>) -> Option<()> {
    let t = &levels[0];
    let (fv, fe) = (t.face_vertices(f), t.face_edge_list(f));
    if fv.len() != 3 {
        return None;
    }
    let nv = t.num_vertices() as u32;
    if levels.len() == 1 {
        for j in 0..3 {
            let k = (start + j) % 3;
            out.extend([fv[k], nv + fe[k]]);
        }
        return Some(());
    }
    let child = &levels[1];
    for j in 0..3 {
        let k = (start + j) % 3;
        let g = 4 * f + k;
        let cv = child.face_vertices(g);
        if cv.len() != 3 || cv[k] != fv[k] {
            return None;
        }
        tri_descendants(&levels[1..], g, k, out)?;
    }
    let (g, r) = (4 * f + 3, (start + 2) % 3);
    let cv = child.face_vertices(g);
    if cv.len() != 3 || cv[r] != nv + fe[start] {
        return None;
    }
    tri_descendants(&levels[1..], g, r, out)
}

/// Rows of a ring matrix computed together: enough independent sums to keep the
/// multiply-add units busy (a single row's sum waits on each addition in turn, four cycles
/// each), and two 256-bit vectors of weights per control point (one 512-bit vector with
/// AVX-512).
const LANES: usize = 8;

/// The matrix of a ring key for `d` levels (module docs), by groups of [`LANES`] rows (the
/// vertices on the face, grouped as [`Kernel::new`] says): each group lists the ring
/// points that any of its rows depends on, with the [`LANES`] weights of its rows on each
/// (0 where a row does not depend on it), padded with empty rows to whole groups.
#[derive(Clone, Debug)]
pub(super) struct Kernel {
    /// Number of points of the ring.
    points: usize,
    /// Number of rows: the vertices on the face, and the padding (to fours per class of
    /// owners on a non-quad, see [`by_owner`], and to a multiple of [`LANES`]).
    rows: usize,
    /// For each entry of [`descendants`] (with repetitions), its row (empty in a
    /// [`Kernel::subset`]).
    row_of: Vec<u16>,
    /// Whether the rows are grouped by owners ([`Kernel::by_owner`]).
    by_owner: bool,
    /// Group `g`'s terms are `starts[g]..starts[g + 1]`.
    starts: Vec<u32>,
    /// The weights of each term, one per row of its group.
    weights: Vec<[f64; LANES]>,
    /// The ring point of each term.
    slots: Vec<u32>,
}

impl Kernel {
    /// The matrix of ring `key` for `depth` levels, refined with `options`, step `s` with
    /// the split and masks of step `s` of `steps` (module docs). `None` if the template cannot be built
    /// or refined as a mesh of its own (the faces are then left to the sparse rows).
    pub(super) fn new(key: &[u32], depth: u32, options: &Options, steps: Steps) -> Option<Kernel> {
        let mesh = template(key)?;
        let points = mesh.num_vertices();
        let plan = RefinePlan::build(&mesh, *options, depth, 0, steps).ok()?;
        let (mut level, _) = Topology::from_mesh(&mesh, options).ok()?;
        let mut levels = Vec::with_capacity(depth as usize);
        for _ in 1..depth {
            let child = steps.refine(&level, options, true);
            levels.push(std::mem::replace(&mut level, child));
        }
        levels.push(level);
        let mut walk = Vec::new();
        descendants(steps, &levels, 0, 0, &mut walk)?;
        let columns: Vec<Vec<[f64; 1]>> = (0..points)
            .map(|s| {
                let unit: Vec<[f64; 1]> =
                    (0..points).map(|i| [f64::from(u8::from(i == s))]).collect();
                plan.apply(&unit)
            })
            .collect();
        // The rows, in groups of `LANES` that depend on few ring points together. On a
        // quad, the grid's rows (`x` along the side from corner 0): measured 5 % faster
        // than any grouping below, with as few terms (137 against 138 at valence 3, depth
        // 3), and faster than the classes below (the sides and corners of a grid are
        // already its first and last rows and the ends of the others). Elsewhere the rows
        // by which faces can own them (`by_owner`), each class in half groups of
        // `LANES / 2` rows (the kernel skips a half group none of whose rows its face
        // owns), and within a class groups grown greedily from the vertex that depends on
        // the fewest ring points by the vertex that adds the fewest.
        let owners = mesh.face(0).len() != 4;
        let mut rows: Vec<Option<u32>> = if !owners {
            grid_indices(&levels, 0)?.into_iter().map(Some).collect()
        } else {
            let support = |v: u32| {
                (0..points)
                    .filter(|&s| columns[s][v as usize][0] != 0.0)
                    .fold(0u64, |m, s| m | 1 << s)
            };
            let mut rows = Vec::new();
            for class in by_owner(steps, &levels, &walk) {
                rows.extend(greedy_groups(
                    class.into_iter().map(|v| (v, support(v))).collect(),
                ));
                rows.resize(rows.len().next_multiple_of(LANES / 2), None);
            }
            rows
        };
        rows.resize(rows.len().next_multiple_of(LANES), None);
        let row_of = (walk.iter())
            .map(|&v| u16::try_from(rows.iter().position(|&x| x == Some(v))?).ok())
            .collect::<Option<Vec<u16>>>()?;
        let mut kernel = Kernel {
            points,
            rows: rows.len(),
            row_of,
            by_owner: owners,
            starts: vec![0],
            weights: Vec::new(),
            slots: Vec::new(),
        };
        kernel.push_groups(&rows, |g, s| {
            g.map_or(0.0, |g| columns[s as usize][g as usize][0])
        });
        Some(kernel)
    }

    /// Appends the groups of `rows` ([`LANES`] at a time, the last one shorter if so),
    /// row `r`'s weight on ring point `s` being `weight(r, s)`: each group's terms are
    /// the ring points, in order, on which any of its rows has a weight other than zero.
    fn push_groups<R: Copy>(&mut self, rows: &[R], weight: impl Fn(R, u32) -> f64) {
        for group in rows.chunks(LANES) {
            for s in 0..self.points as u32 {
                let mut w = [0.0; LANES];
                for (w, &r) in w.iter_mut().zip(group) {
                    *w = weight(r, s);
                }
                if w.iter().any(|&w| w != 0.0) {
                    self.weights.push(w);
                    self.slots.push(s);
                }
            }
            self.starts.push(self.weights.len() as u32);
        }
    }

    /// The output vertex of each row, padded with [`NOT_OWNED`], of a face with ring
    /// points `verts` from its [`descendants`] `walk` (with repetitions); `None` unless
    /// the ring has the template's points and the walk repeats exactly where the
    /// template's does.
    pub(super) fn grid(&self, verts: &[u32], walk: &[u32]) -> Option<Vec<u32>> {
        if verts.len() != self.points || walk.len() != self.row_of.len() {
            return None;
        }
        let mut grid = vec![NOT_OWNED; self.rows];
        for (&v, &r) in walk.iter().zip(&self.row_of) {
            let g = &mut grid[r as usize];
            if *g != NOT_OWNED && *g != v {
                return None;
            }
            *g = v;
        }
        let mut sorted: Vec<u32> = grid.iter().copied().filter(|&g| g != NOT_OWNED).collect();
        sorted.sort_unstable();
        sorted.windows(2).all(|w| w[0] != w[1]).then_some(grid)
    }

    /// Whether the rows are grouped by the faces that can own them ([`by_owner`]: the
    /// kernel of a face that is not a quad), so that a face's rows are worth packing
    /// into a kernel of their own ([`Kernel::subset`]).
    pub(super) fn by_owner(&self) -> bool {
        self.by_owner
    }

    /// The kernel of rows `rows` of this one only (in that order, by groups of
    /// [`LANES`], the last padded with empty rows), for the faces that own just those
    /// ([`RingGroups`]).
    ///
    /// Each row keeps its nonzero terms in the same order (of ring points); its group may
    /// add others of weight zero, which leave a finite sum as it is (test
    /// `owned_rows_give_the_same_points`).
    pub(super) fn subset(&self, rows: &[u16]) -> Kernel {
        let mut kernel = Kernel {
            points: self.points,
            rows: rows.len().next_multiple_of(LANES),
            row_of: Vec::new(),
            by_owner: self.by_owner,
            starts: vec![0],
            weights: Vec::new(),
            slots: Vec::new(),
        };
        // Row `r`'s weight on ring point `s`: its lane of its group's term on `s`.
        let weight = |r: u16, s: u32| {
            let (g, lane) = (usize::from(r) / LANES, usize::from(r) % LANES);
            let terms = self.starts[g] as usize..self.starts[g + 1] as usize;
            (self.slots[terms.clone()].binary_search(&s))
                .map_or(0.0, |t| self.weights[terms.start + t][lane])
        };
        kernel.push_groups(rows, weight);
        kernel
    }

    /// The nonzero entries `(ring point, weight)` of row `r`.
    #[cfg(test)]
    fn row(&self, r: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let (g, lane) = (r / LANES, r % LANES);
        let terms = self.starts[g] as usize..self.starts[g + 1] as usize;
        (self.slots[terms.clone()].iter().zip(&self.weights[terms]))
            .map(move |(&s, w)| (s as usize, w[lane]))
            .filter(|&(_, w)| w != 0.0)
    }

    /// Bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        4 * self.starts.len() + 2 * self.row_of.len() + (8 * LANES + 4) * self.weights.len()
    }
}

/// The vertices that `levels.len()` levels put on the closed face 0 of `levels[0]`
/// (`walk`, the [`descendants`] from its corner 0) in classes of the faces that may hold
/// them too, so that a face's rows not written by it (claimed by an earlier face, see
/// `PatchLayer::build`) come together and are skipped: first those only the face holds
/// (inside it, or on a side without a neighbour), then for each side shared with another
/// face the vertices on it, then the corners. Each side is claimed whole by one of its two
/// faces and each corner by one of its faces, so on an all-triangle mesh a face writes
/// its inside, half of its sides and a sixth of its corners on average: 12 of its 19
/// vertices at depth 2, where its rows in groups by support alone (owned and not owned
/// mixed) made it compute nearly all.
fn by_owner(steps: Steps, levels: &[Topology], walk: &[u32]) -> Vec<Vec<u32>> {
    let t = &levels[0];
    let (fv, fe) = (t.face_vertices(0), t.face_edge_list(0));
    // The vertices of the face across each side (empty without one).
    let across: Vec<Vec<u32>> = (fe.iter())
        .map(|&e| {
            let mut d = Vec::new();
            if let Some(&g) = t.edge_face_list(e as usize).iter().find(|&&g| g != 0) {
                if descendants(steps, levels, g as usize, 0, &mut d).is_none() {
                    d.clear();
                }
            }
            d.sort_unstable();
            d
        })
        .collect();
    let mut verts = walk.to_vec();
    verts.sort_unstable();
    verts.dedup();
    let n = fv.len();
    let mut classes = vec![Vec::new(); n + 2];
    for v in verts {
        // A corner's children keep its index (vertex points come first at each level).
        let class = if fv.contains(&v) {
            n + 1
        } else {
            (across.iter())
                .position(|d| d.binary_search(&v).is_ok())
                .map_or(0, |k| k + 1)
        };
        classes[class].push(v);
    }
    classes
}

/// Rows `(vertex, bit set of the ring points it depends on)` in groups of [`LANES`], each
/// grown from the row that depends on the fewest points by the row that adds the fewest,
/// every group but the last full.
fn greedy_groups(mut left: Vec<(u32, u64)>) -> Vec<Option<u32>> {
    let mut rows = Vec::with_capacity(left.len().next_multiple_of(LANES));
    while let Some(seed) = (0..left.len()).min_by_key(|&i| left[i].1.count_ones()) {
        let (v, mut union) = left.remove(seed);
        rows.push(Some(v));
        for _ in 1..LANES {
            let Some((i, _)) = (left.iter().enumerate())
                .min_by_key(|(_, (_, s))| ((union | s).count_ones(), s.count_ones()))
            else {
                break;
            };
            let (v, s) = left.remove(i);
            union |= s;
            rows.push(Some(v));
        }
    }
    rows
}

/// Most rows of a Catmull-Clark kernel whose patches get kernels of the rows they own
/// ([`RingGroups`]): 24 at depth 2 on a triangle. Past that (depth 3 and more), packing
/// a patch's rows saves a smaller share of its groups, and the more numerous matrices
/// cost more than that saves (`catmark_bishop_l2_tri` at level 3, 6–10 % slower).
const SUBSET_ROWS: usize = 4 * LANES;

/// [`SUBSET_ROWS`] for Loop's triangles: their kernels at depth 3 (56 rows: 45 vertices
/// in fours by owners) too. A triangle there owns 32 of its 45 vertices on average,
/// which its key's groups spread over about five groups of eight and a kernel of its own
/// packs into four: on the scan-like torus at level 3, 10–20 % less time and a plan of
/// 19 MiB instead of 26 (BENCHMARKS.md, "Loop and bilinear"). At depth 4 (160 rows)
/// packing was slower, as for Catmull-Clark at depth 3.
const LOOP_SUBSET_ROWS: usize = 8 * LANES;

/// The most rows of a kernel whose patches [`RingGroups`] packs into kernels of the rows
/// they own, with `steps`.
pub(super) fn subset_rows(steps: Steps) -> usize {
    match steps {
        Steps::Loop => LOOP_SUBSET_ROWS,
        Steps::Family(_) | Steps::Bilinear => SUBSET_ROWS,
    }
}

/// The ring patches of a layer as they are claimed, each with its matrix, until they are
/// laid out ([`RingGroups::finish`]). A patch whose key's kernel is grouped by owners and
/// has at most [`subset_rows`] rows goes to the kernel of the rows it owns
/// ([`Kernel::subset`]), made once per key and set of rows, its grid those rows'
/// vertices; the others to their key's kernel.
///
/// On an all-triangle mesh at depth 2 a face owns its inside, the sides it claims and the
/// corners it claims, 12 of its 24 rows on average, which its key's groups of owners
/// spread over 2.4 groups of eight and a kernel of their own packs into 2.1, fewer
/// partly empty groups (BENCHMARKS.md, "Re-posing").
pub(super) struct RingGroups<'a> {
    /// The kernel of each key (`None`: the key's faces are left to the rows).
    kernels: &'a [Option<Kernel>],
    /// The most rows of a kernel whose patches are packed ([`subset_rows`]).
    subset_rows: usize,
    /// The matrix of each key and set of owned rows (empty: the key's kernel).
    index: HashMap<(usize, Vec<u16>), usize>,
    /// The matrices.
    matrices: Vec<Kernel>,
    /// The patches, in the order they were claimed.
    patches: Vec<Claimed>,
}

/// A ring patch as [`RingGroups`] holds it until the layer's patches are laid out.
struct Claimed {
    /// Its matrix, in [`RingGroups::matrices`].
    matrix: u32,
    /// Its run of faces.
    run: u32,
    /// Its ring points.
    verts: Vec<u32>,
    /// The output vertex of each row of its matrix, or [`NOT_OWNED`].
    grid: Vec<u32>,
}

impl<'a> RingGroups<'a> {
    /// The ring patches of matrices `kernels` (by key), those of at most `subset_rows`
    /// rows packed.
    pub(super) fn new(kernels: &'a [Option<Kernel>], subset_rows: usize) -> Self {
        RingGroups {
            kernels,
            subset_rows,
            index: HashMap::new(),
            matrices: Vec::new(),
            patches: Vec::new(),
        }
    }

    /// Adds a patch of key `k` in run `run` (not before those already added) with ring
    /// points `verts` and grid `grid` (its [`Kernel::grid`], the rows it does not own set
    /// to [`NOT_OWNED`]).
    pub(super) fn push(&mut self, k: usize, run: u32, verts: Vec<u32>, grid: Vec<u32>) {
        let Some(kernel) = &self.kernels[k] else {
            return;
        };
        let rows: Vec<u16> = if kernel.by_owner() && kernel.rows <= self.subset_rows {
            (0..grid.len() as u16)
                .filter(|&r| grid[usize::from(r)] != NOT_OWNED)
                .collect()
        } else {
            Vec::new()
        };
        // The grid of the rows the patch owns, if they get a kernel of their own.
        let grid = if rows.is_empty() {
            grid
        } else {
            let mut owned: Vec<u32> = rows.iter().map(|&r| grid[usize::from(r)]).collect();
            owned.resize(rows.len().next_multiple_of(LANES), NOT_OWNED);
            owned
        };
        let matrices = &mut self.matrices;
        let m = *self.index.entry((k, rows)).or_insert_with_key(|(_, rows)| {
            matrices.push(if rows.is_empty() {
                kernel.clone()
            } else {
                kernel.subset(rows)
            });
            matrices.len() - 1
        });
        self.patches.push(Claimed {
            matrix: m as u32,
            run,
            verts,
            grid,
        });
    }

    /// The ring patches of a layer of `runs` runs, laid out by unit of work, and the runs
    /// per unit ([`ring_span`]).
    pub(super) fn finish(self, runs: usize) -> (RingPatches, usize) {
        let RingGroups {
            matrices,
            mut patches,
            ..
        } = self;
        let span = ring_span(runs, matrices.len(), patches.len());
        let units = runs.div_ceil(span);
        // By unit, then by matrix, each matrix's patches in the order they were claimed.
        let segment = |p: &Claimed| (p.run / span as u32, p.matrix);
        patches.sort_by_key(segment);
        let ctrl = patches.iter().map(|p| p.verts.len()).sum();
        let out = patches.iter().map(|p| p.grid.len()).sum();
        let mut laid = RingPatches {
            kernels: matrices,
            ctrl: Vec::with_capacity(ctrl),
            out: Vec::with_capacity(out),
            segments: Vec::new(),
            units: Runs::default(),
        };
        let mut unit_of = Vec::new();
        for same in patches.chunk_by(|a, b| segment(a) == segment(b)) {
            let (unit, matrix) = segment(&same[0]);
            laid.segments.push(Segment {
                kernel: matrix,
                patches: same.len() as u32,
                ctrl: laid.ctrl.len(),
                out: laid.out.len(),
            });
            unit_of.push(unit);
            for p in same {
                laid.ctrl.extend_from_slice(&p.verts);
                laid.out.extend_from_slice(&p.grid);
            }
        }
        laid.units = Runs::new(&unit_of, units);
        (laid, span)
    }
}

/// The patches of one matrix in one unit of work of a [`RingPatches`].
#[derive(Clone, Copy, Debug)]
struct Segment {
    /// The matrix, in [`RingPatches::kernels`].
    kernel: u32,
    /// Number of patches.
    patches: u32,
    /// Where their ring points start in [`RingPatches::ctrl`].
    ctrl: usize,
    /// Where their grids start in [`RingPatches::out`].
    out: usize,
}

/// The ring patches of one [`PatchLayer`](super::plan_patches::PatchLayer), in the order
/// they are applied: by unit of work ([`ring_span`]), within a unit by matrix, each
/// matrix's patches in the order they were claimed (the order of the faces).
///
/// Why one array in that order rather than one per matrix: applying reads the ring
/// points and grids of the patches once each, and read in order they come in as the
/// processor's prefetchers fetch a stream. One array per matrix had a unit jump from
/// matrix to matrix, a new stream every few patches; on a scan with corners of many
/// valences (`nefertiti`, 100 k triangles, 2 752 matrices at level 2) the first lines of
/// each were missed, and a re-posing took twice as long per output vertex as on a scan
/// with few matrices (`ogre`); in this order, 14 % less on one thread and 20 % less on
/// two (`BENCHMARKS.md`, "Ring patches stored in the order they are applied").
#[derive(Clone, Debug, Default)]
pub(super) struct RingPatches {
    /// The matrices.
    kernels: Vec<Kernel>,
    /// The ring points of each patch, in its key's order.
    pub(super) ctrl: Vec<u32>,
    /// The output vertex of each row of each patch, or [`NOT_OWNED`].
    pub(super) out: Vec<u32>,
    /// The patches of one matrix and unit each, by unit.
    segments: Vec<Segment>,
    /// Where the segments of each unit start.
    units: Runs,
}

impl RingPatches {
    /// Number of patches.
    pub(super) fn len(&self) -> usize {
        self.segments.iter().map(|s| s.patches as usize).sum()
    }

    /// Bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        self.kernels.iter().map(Kernel::memory_bytes).sum::<usize>()
            + 4 * (self.ctrl.len() + self.out.len())
            + std::mem::size_of::<Segment>() * self.segments.len()
            + self.units.memory_bytes()
    }

    /// Writes the owned grid points of the patches of unit `unit` into `out`, from the
    /// values `src` of the patches' level.
    ///
    /// # Safety
    /// As [`Kernel::apply`].
    pub(super) unsafe fn apply<const D: usize>(
        &self,
        unit: usize,
        src: &[[f64; D]],
        out: &SharedOut<[f64; D]>,
    ) {
        for s in &self.segments[self.units.range(unit)] {
            let k = &self.kernels[s.kernel as usize];
            let n = s.patches as usize;
            let ctrl = &self.ctrl[s.ctrl..s.ctrl + n * k.points];
            let grids = &self.out[s.out..s.out + n * k.rows];
            // SAFETY: the caller's.
            unsafe { k.apply(src, ctrl, grids, out) };
        }
    }
}

impl Kernel {
    /// Writes the owned grid points of the patches with ring points `ctrl` (the kernel's
    /// number of points each) and grids `grids` (its number of rows each) into `out`,
    /// from the values `src` of the patches' level.
    ///
    /// # Safety
    /// Every control index is in bounds of `src`, every grid index is [`NOT_OWNED`] or in
    /// bounds of `out`, and no other thread writes the same output indices.
    pub(super) unsafe fn apply<const D: usize>(
        &self,
        src: &[[f64; D]],
        ctrl: &[u32],
        grids: &[u32],
        out: &SharedOut<[f64; D]>,
    ) {
        let (points, nn) = (self.points, self.rows);
        #[cfg(target_arch = "x86_64")]
        if D == 3 && has_avx512f() {
            let src = src.as_ptr().cast();
            // SAFETY: the features were just detected; `D == 3`; the caller's bounds.
            unsafe { ring_patches_avx512(self, src, ctrl, grids, out.0.cast()) };
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if D == 3 && has_avx2_fma() {
            let src = src.as_ptr().cast();
            // SAFETY: the features were just detected; `D == 3`; the caller's bounds.
            unsafe { ring_patches_avx(self, src, ctrl, grids, out.0.cast()) };
            return;
        }
        let k = self;
        // The control points by component: `local[c][s]`.
        let mut local = [[0.0; MAX_POINTS]; D];
        for (p, (c, g)) in ctrl
            .chunks_exact(points)
            .zip(grids.chunks_exact(nn))
            .enumerate()
        {
            // SAFETY: the caller's.
            unsafe { prefetch_next::<D>(grids, p, nn, out.0.cast()) };
            for (s, &v) in c.iter().enumerate() {
                (0..D).for_each(|i| local[i][s] = src[v as usize][i]);
            }
            for (group, rows) in g.chunks(LANES).enumerate() {
                if rows.iter().all(|&o| o == NOT_OWNED) {
                    continue;
                }
                let mut acc = [[0.0; LANES]; D];
                let terms = k.starts[group] as usize..k.starts[group + 1] as usize;
                for (w, &s) in k.weights[terms.clone()].iter().zip(&k.slots[terms]) {
                    for (acc, local) in acc.iter_mut().zip(&local) {
                        let x = local[s as usize];
                        (0..LANES).for_each(|l| acc[l] += w[l] * x);
                    }
                }
                for (l, &o) in rows.iter().enumerate() {
                    if o != NOT_OWNED {
                        // SAFETY: the caller's.
                        unsafe {
                            out.0
                                .add(o as usize)
                                .write(std::array::from_fn(|i| acc[i][l]))
                        };
                    }
                }
            }
        }
    }
}

/// [`Kernel::apply`] for positions, with AVX2 and FMA (as the regular patches'
/// `patches_avx`): two patches at a time, so that each term's two vectors of weights
/// (a group of [`LANES`] rows) are loaded once for both, and twelve independent sums
/// (two patches × two vectors of rows × three components) keep the multiply-adds busy;
/// each broadcasts its ring point's components straight from `src`. Where both patches
/// own rows of one half of the group only (patches of a matrix of the rows they own,
/// [`RingGroups`], own the same rows), that half of both. A group whose halves the two
/// patches own differently, and the last patch of an odd number, are computed one patch
/// at a time ([`ring_group_avx`]). Each row's sum is the same, in the same
/// order, as with one patch at a time, and as [`ring_patches_avx512`]'s: bit for bit
/// (test `vector_kernels_agree`).
///
/// Why two patches: one patch's group did six multiply-adds per term on six sums, each
/// waiting on the previous term's; with the two loads of weights and three broadcasts a
/// term cost about eight cycles. Two patches at once were 10–25 % faster on Loop's
/// triangles and no slower on Catmull-Clark's ring patches (BENCHMARKS.md, "Loop and
/// bilinear"). The ring is no longer copied to the stack by component first (a fifth of
/// the kernel's samples when it was measured; reading it from `src` was faster at depth
/// 2 and slower at depth 3 for one patch at a time).
///
/// # Safety
/// As [`Kernel::apply`], with `src` and `out` pointing at `[f64; 3]` values; the
/// processor has AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn ring_patches_avx(
    k: &Kernel,
    src: *const f64,
    ctrl: &[u32],
    grids: &[u32],
    out: *mut f64,
) {
    use std::arch::x86_64::*;
    let (points, nn) = (k.points, k.rows);
    let groups = k.starts.len() - 1;
    let mut scratch = [0.0f64; 3];
    let pairs = ctrl
        .chunks_exact(2 * points)
        .zip(grids.chunks_exact(2 * nn));
    // SAFETY (whole body): the caller's bounds; slots are below `points`.
    unsafe {
        for (p, (c, g)) in pairs.enumerate() {
            // The two patches of the next pair.
            prefetch_next::<3>(grids, 2 * p + 1, nn, out);
            prefetch_next::<3>(grids, 2 * p + 2, nn, out);
            let (c0, c1) = c.split_at(points);
            let (g0, g1) = g.split_at(nn);
            for group in 0..groups {
                let rows = LANES * group..LANES * (group + 1);
                let (r0, r1) = (&g0[rows.clone()], &g1[rows]);
                let owned = [r0, r1].map(|r| [any_owned(&r[..4]), any_owned(&r[4..])]);
                let terms = k.starts[group] as usize..k.starts[group + 1] as usize;
                let terms = k.weights[terms.clone()].iter().zip(&k.slots[terms]);
                if owned[0] != owned[1] || owned[0] == [false; 2] {
                    // (Rare: patches of one matrix mostly own the same rows.)
                    ring_group_avx(k, group, src, c0, r0, out, &mut scratch);
                    ring_group_avx(k, group, src, c1, r1, out, &mut scratch);
                    continue;
                }
                if owned[0] != [true; 2] {
                    // Both own rows of the same half only: that half of both.
                    let h = usize::from(owned[0][1]);
                    let mut acc = [[_mm256_setzero_pd(); 3]; 2];
                    for (w, &s) in terms {
                        let w = _mm256_loadu_pd(w.as_ptr().add(4 * h));
                        let q =
                            [c0, c1].map(|c| src.add(3 * *c.get_unchecked(s as usize) as usize));
                        for i in 0..3 {
                            for (acc, q) in acc.iter_mut().zip(q) {
                                let x = _mm256_broadcast_sd(&*q.add(i));
                                acc[i] = _mm256_fmadd_pd(w, x, acc[i]);
                            }
                        }
                    }
                    for (acc, r) in acc.iter().zip([r0, r1]) {
                        let [x, y, z] = *acc;
                        store_four(x, y, z, &r[4 * h..4 * h + 4], out, &mut scratch);
                    }
                    continue;
                }
                let mut acc = [[[_mm256_setzero_pd(); 2]; 3]; 2];
                for (w, &s) in terms {
                    let w = [
                        _mm256_loadu_pd(w.as_ptr()),
                        _mm256_loadu_pd(w.as_ptr().add(4)),
                    ];
                    let q = [c0, c1].map(|c| src.add(3 * *c.get_unchecked(s as usize) as usize));
                    for i in 0..3 {
                        for (acc, q) in acc.iter_mut().zip(q) {
                            let x = _mm256_broadcast_sd(&*q.add(i));
                            acc[i][0] = _mm256_fmadd_pd(w[0], x, acc[i][0]);
                            acc[i][1] = _mm256_fmadd_pd(w[1], x, acc[i][1]);
                        }
                    }
                }
                for (acc, r) in acc.iter().zip([r0, r1]) {
                    for (half, rows) in r.chunks(4).enumerate() {
                        let [x, y, z] = acc.map(|a| a[half]);
                        store_four(x, y, z, rows, out, &mut scratch);
                    }
                }
            }
        }
        let done = ctrl.len() / (2 * points) * 2;
        if done * points < ctrl.len() {
            // (Prefetched with the last pair, if any.)
            let (c, g) = (&ctrl[done * points..], &grids[done * nn..]);
            for group in 0..groups {
                let rows = &g[LANES * group..LANES * (group + 1)];
                ring_group_avx(k, group, src, c, rows, out, &mut scratch);
            }
        }
    }
}

/// Group `group` of the patch with ring points `c` and output rows `rows` (its
/// [`LANES`] rows of the grid), for [`ring_patches_avx`]: nothing if the patch owns none
/// of them, half the work if it owns rows of one half only.
///
/// # Safety
/// As [`ring_patches_avx`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn ring_group_avx(
    k: &Kernel,
    group: usize,
    src: *const f64,
    c: &[u32],
    rows: &[u32],
    out: *mut f64,
    scratch: &mut [f64; 3],
) {
    use std::arch::x86_64::*;
    let (low, high) = (any_owned(&rows[..4]), any_owned(&rows[4..]));
    if !(low || high) {
        return;
    }
    let mut acc = [[_mm256_setzero_pd(); 2]; 3];
    let terms = k.starts[group] as usize..k.starts[group + 1] as usize;
    let terms = k.weights[terms.clone()].iter().zip(&k.slots[terms]);
    // SAFETY (whole body): the caller's bounds; slots are below `points`.
    unsafe {
        if low && high {
            for (w, &s) in terms {
                let w = [
                    _mm256_loadu_pd(w.as_ptr()),
                    _mm256_loadu_pd(w.as_ptr().add(4)),
                ];
                let q = src.add(3 * *c.get_unchecked(s as usize) as usize);
                for (i, acc) in acc.iter_mut().enumerate() {
                    let x = _mm256_broadcast_sd(&*q.add(i));
                    acc[0] = _mm256_fmadd_pd(w[0], x, acc[0]);
                    acc[1] = _mm256_fmadd_pd(w[1], x, acc[1]);
                }
            }
        } else {
            // Only one half of the rows is written: half the work.
            let h = usize::from(high);
            for (w, &s) in terms {
                let w = _mm256_loadu_pd(w.as_ptr().add(4 * h));
                let q = src.add(3 * *c.get_unchecked(s as usize) as usize);
                for (i, acc) in acc.iter_mut().enumerate() {
                    let x = _mm256_broadcast_sd(&*q.add(i));
                    acc[h] = _mm256_fmadd_pd(w, x, acc[h]);
                }
            }
        }
        for (half, rows) in rows.chunks(4).enumerate() {
            let [x, y, z] = acc.map(|a| a[half]);
            store_four(x, y, z, rows, out, scratch);
        }
    }
}

/// Whether any of the four rows `r` is owned (all bits of their `&` are set only if none
/// is), without a branch per row.
#[inline]
pub(super) fn any_owned(r: &[u32]) -> bool {
    r[0] & r[1] & r[2] & r[3] != NOT_OWNED
}

/// Writes eight rows of `(x, y, z)` (one row per lane of 512-bit vectors) with
/// [`store_four`], each half of four rows where `halves` says.
///
/// # Safety
/// As [`store_four`]; the processor has AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
pub(super) unsafe fn store_eight(
    x: std::arch::x86_64::__m512d,
    y: std::arch::x86_64::__m512d,
    z: std::arch::x86_64::__m512d,
    rows: &[u32],
    halves: [bool; 2],
    out: *mut f64,
    scratch: &mut [f64; 3],
) {
    use std::arch::x86_64::*;
    let split = |v: __m512d| [_mm512_castpd512_pd256(v), _mm512_extractf64x4_pd::<1>(v)];
    let (x, y, z) = (split(x), split(y), split(z));
    for h in 0..2 {
        if halves[h] {
            // SAFETY: the caller's.
            unsafe { store_four(x[h], y[h], z[h], &rows[4 * h..4 * h + 4], out, scratch) };
        }
    }
}

/// Writes four rows of `(x, y, z)` (one row per lane) to their output vertices `rows`,
/// rows not owned to `scratch`: from (x, y, z) by row to rows of (x, y), (z).
///
/// # Safety
/// Every entry of `rows` is [`NOT_OWNED`] or in bounds of `out` (`[f64; 3]` values); the
/// processor has AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
unsafe fn store_four(
    x: std::arch::x86_64::__m256d,
    y: std::arch::x86_64::__m256d,
    z: std::arch::x86_64::__m256d,
    rows: &[u32],
    out: *mut f64,
    scratch: &mut [f64; 3],
) {
    use std::arch::x86_64::*;
    let (xy02, xy13) = (_mm256_unpacklo_pd(x, y), _mm256_unpackhi_pd(x, y));
    let (zlo, zhi) = (_mm256_castpd256_pd128(z), _mm256_extractf128_pd::<1>(z));
    let xy = [
        _mm256_castpd256_pd128(xy02),
        _mm256_castpd256_pd128(xy13),
        _mm256_extractf128_pd::<1>(xy02),
        _mm256_extractf128_pd::<1>(xy13),
    ];
    for (l, &o) in rows.iter().enumerate() {
        // Points not owned are written to `scratch`, a select of the address. The
        // compiler, which sees that `scratch` is never read, may still branch around a
        // store instead: measured, that is faster than forcing the selects (4–25 %, see
        // `BENCHMARKS.md`, "Regular patches with AVX-512"); the pattern of owned points
        // is predicted well.
        let q = if o == NOT_OWNED {
            scratch.as_mut_ptr()
        } else {
            out.wrapping_add(3 * o as usize)
        };
        // SAFETY: `q` is `scratch` or an owned vertex in bounds (the caller's).
        unsafe {
            _mm_storeu_pd(q, xy[l]);
            let z = if l < 2 { zlo } else { zhi };
            if l % 2 == 0 {
                _mm_store_sd(q.add(2), z);
            } else {
                _mm_storeh_pd(q.add(2), z);
            }
        }
    }
}

/// [`ring_patches_avx`] with AVX-512: a group of [`LANES`] rows is one 512-bit vector per
/// component, so a term is one load of weights and three multiply-adds that broadcast
/// their ring point's components straight from `src` (against two loads, three
/// broadcasts and six multiply-adds, after copying the ring to the stack by component).
/// The sums are the same, in the same order, as [`ring_patches_avx`]'s: the results are
/// the same, bit for bit.
///
/// Reading the ring straight from `src` (no copy to the stack) is most of its gain over
/// [`ring_patches_avx`] (BENCHMARKS.md, "Re-posing", has the figures and the variants
/// tried: two sets of sums, whose kernel is not bound by multiply-add latency; all groups'
/// sums at once for small matrices, faster on small meshes and slower on large ones; the
/// AVX2 kernel reading from `src`, faster at depth 2 and slower deeper, so it keeps its
/// copy).
///
/// # Safety
/// As [`ring_patches_avx`]; the processor has AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2,fma")]
unsafe fn ring_patches_avx512(
    k: &Kernel,
    src: *const f64,
    ctrl: &[u32],
    grids: &[u32],
    out: *mut f64,
) {
    use std::arch::x86_64::*;
    let (points, nn) = (k.points, k.rows);
    let mut scratch = [0.0f64; 3];
    // SAFETY (whole body): the caller's bounds; slots are below `points ≤ MAX_POINTS`.
    unsafe {
        for (p, (c, g)) in ctrl
            .chunks_exact(points)
            .zip(grids.chunks_exact(nn))
            .enumerate()
        {
            prefetch_next::<3>(grids, p, nn, out);
            for (group, rows) in g.chunks(LANES).enumerate() {
                if rows.iter().fold(NOT_OWNED, |a, &r| a & r) == NOT_OWNED {
                    continue;
                }
                let mut acc = [_mm512_setzero_pd(); 3];
                let terms = k.starts[group] as usize..k.starts[group + 1] as usize;
                for (w, &s) in k.weights[terms.clone()].iter().zip(&k.slots[terms]) {
                    let w = _mm512_loadu_pd(w.as_ptr());
                    let q = src.add(3 * *c.get_unchecked(s as usize) as usize);
                    for (i, acc) in acc.iter_mut().enumerate() {
                        let x = _mm512_set1_pd(*q.add(i));
                        *acc = _mm512_fmadd_pd(w, x, *acc);
                    }
                }
                let [x, y, z] = acc;
                store_eight(x, y, z, rows, [true; 2], out, &mut scratch);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scheme::adjustable::Mixed;

    /// Catmull-Clark's steps.
    const CC: Steps = Steps::Family(Mixed::CATMULL_CLARK);

    /// The `n + 5` quads of the 1-ring of a quad with one corner of valence `n` (vertex 0)
    /// and three regular ones: the fan `(0, aᵢ, bᵢ, aᵢ₊₁)` with `aᵢ = 1 + 2i`,
    /// `bᵢ = 2 + 2i`, its face 0 being the patch's quad, and five quads beyond.
    fn one_ev_ring(n: usize) -> Vec<[u32; 4]> {
        let a = |i: usize| (1 + 2 * (i % n)) as u32;
        let b = |i: usize| (2 + 2 * i) as u32;
        let c = |k: u32| 2 * n as u32 + 1 + k;
        let mut faces: Vec<[u32; 4]> = (0..n).map(|i| [0, a(i), b(i), a(i + 1)]).collect();
        faces.extend([
            [b(n - 1), c(0), c(1), a(0)],
            [a(0), c(1), c(2), b(0)],
            [b(0), c(2), c(3), c(4)],
            [a(1), b(0), c(4), c(5)],
            [b(1), a(1), c(5), c(6)],
        ]);
        faces
    }

    /// An octahedron: four triangles around each vertex.
    const OCTAHEDRON: [[u32; 3]; 8] = [
        [0, 1, 2],
        [0, 2, 3],
        [0, 3, 4],
        [0, 4, 1],
        [5, 2, 1],
        [5, 3, 2],
        [5, 4, 3],
        [5, 1, 4],
    ];

    fn topology(faces: &[impl AsRef<[u32]>], options: &Options) -> Topology {
        let points = faces.iter().flat_map(|f| f.as_ref()).max().unwrap() + 1;
        let mesh = PolyMesh::from_faces(vec![[0.0; 3]; points as usize], faces).unwrap();
        Topology::from_mesh(&mesh, options).unwrap().0
    }

    /// The key and points of a ring do not depend on the corner a face is listed from,
    /// and the key lists the ring's faces on its own points.
    #[test]
    fn ring_does_not_depend_on_listing() {
        let options = Options::default();
        let rings = [one_ev_ring(3), one_ev_ring(6)];
        let octa: Vec<Vec<u32>> = OCTAHEDRON.iter().map(|f| f.to_vec()).collect();
        let mut cases: Vec<Vec<Vec<u32>>> = rings
            .iter()
            .map(|r| r.iter().map(|f| f.to_vec()).collect())
            .collect();
        cases.push(octa);
        for faces in cases {
            let t = topology(&faces, &options);
            let ring = ring_net(&t, 0, false).expect("face 0 is a ring patch");
            // The key's faces are the mesh's faces around face 0, renumbered.
            let listed = template(&ring.key).expect("a valid key").num_faces();
            let mut around: Vec<u32> = (t.face_vertices(0).iter())
                .flat_map(|&v| t.vertex_faces(v as usize).to_vec())
                .collect();
            around.sort_unstable();
            around.dedup();
            assert_eq!(listed, around.len());
            for k in 1..faces[0].len() {
                let mut turned = faces.clone();
                turned[0].rotate_left(k);
                // The same least key (from any corner that gives it, when the ring is
                // symmetric), and the same points read from the same corner.
                let t = topology(&turned, &options);
                assert_eq!(
                    ring_net(&t, 0, false).unwrap().key,
                    ring.key,
                    "turned by {k}"
                );
                let n = faces[0].len();
                let u = read_ring(&t, 0, (ring.start + n - k) % n).unwrap();
                assert_eq!(
                    (&u.key, &u.verts),
                    (&ring.key, &ring.verts),
                    "turned by {k}"
                );
            }
        }
    }

    /// Each row is a partition of unity (refinement is affine invariant), and the row of
    /// the vertex at a corner of valence `n` is `d` steps of the smooth vertex rule,
    /// worked out in closed form: with that corner at 1 and every other point at 0, its fan
    /// stays rotationally symmetric, so one value for it, one for all its neighbours `a`
    /// and one for all the opposite corners `b` of its faces follow each step (face point
    /// `(v + 2a + b)/4`, the new `b`; edge point `(v + a + 2 face)/4`, the new `a`; vertex
    /// point `(n − 2)/n v + (a + face)/n`).
    #[test]
    fn rows_are_affine_and_corner_is_vertex_rule() {
        let options = Options::default();
        for n in [3, 5, 6, 8] {
            let faces = one_ev_ring(n);
            let t = topology(&faces, &options);
            let ring = ring_net(&t, 0, false).unwrap();
            for depth in [2u32, 3, 4] {
                let k = Kernel::new(&ring.key, depth, &options, CC).unwrap();
                assert_eq!(k.points, 2 * n + 8);
                let side = (1usize << depth) + 1;
                assert_eq!(k.rows, (side * side).next_multiple_of(LANES));
                for r in 0..side * side {
                    let sum: f64 = k.row(r).map(|(_, w)| w).sum();
                    assert!((sum - 1.0).abs() < 1e-14, "n {n} depth {depth} row {r}");
                }
                // The patch's own vertices: vertex 0 keeps its index in every level.
                let mut levels = vec![t.clone()];
                for _ in 1..depth {
                    let child = CC.refine(&levels[levels.len() - 1], &options, true);
                    levels.push(child);
                }
                let mut walk = Vec::new();
                descendants(CC, &levels, 0, ring.start, &mut walk).unwrap();
                let grid = k.grid(&ring.verts, &walk).unwrap();
                let row = grid.iter().position(|&g| g == 0).unwrap();
                let slot = ring.verts.iter().position(|&v| v == 0).unwrap();
                let nf = n as f64;
                let (mut v, mut a, mut b) = (1.0, 0.0, 0.0);
                for _ in 0..depth {
                    let face = (v + 2.0 * a + b) / 4.0;
                    let edge = (v + a + 2.0 * face) / 4.0;
                    (v, a, b) = ((nf - 2.0) / nf * v + (a + face) / nf, edge, face);
                }
                let got: f64 = k.row(row).filter(|&(s, _)| s == slot).map(|(_, w)| w).sum();
                assert!(
                    (got - v).abs() < 1e-15,
                    "n {n} depth {depth}: {got} against {v}"
                );
            }
        }
    }

    /// A cube (corners 0–7) with its top split in two triangles and one side in four
    /// around a centre (8).
    fn cube_with_triangles() -> Vec<Vec<u32>> {
        vec![
            vec![0, 3, 2, 1],
            vec![4, 5, 6],
            vec![4, 6, 7],
            vec![0, 1, 8],
            vec![1, 5, 8],
            vec![5, 4, 8],
            vec![4, 0, 8],
            vec![1, 2, 6, 5],
            vec![2, 3, 7, 6],
            vec![3, 0, 4, 7],
        ]
    }

    /// A ring patch of a test mesh: its depth, the number of vertices of the level it
    /// writes, its face, ring, key's kernel and grid.
    struct TestPatch {
        depth: u32,
        n_out: usize,
        f: usize,
        ring: RingNet,
        kernel: Kernel,
        grid: Vec<u32>,
    }

    /// Every ring patch of `t` at depths 2 and 3 whose walk repeats where its key's does.
    fn ring_patches(t: &Topology, options: &Options) -> Vec<TestPatch> {
        let mut patches = Vec::new();
        for depth in [2u32, 3, 4] {
            let mut levels = vec![t.clone()];
            while levels.len() < depth as usize + 1 {
                let child = CC.refine(&levels[levels.len() - 1], options, true);
                levels.push(child);
            }
            let n_out = levels[depth as usize].num_vertices();
            for f in 0..t.num_faces() {
                let Some(ring) = ring_net(t, f, false) else {
                    continue;
                };
                let kernel = Kernel::new(&ring.key, depth, options, CC).unwrap();
                let mut walk = Vec::new();
                descendants(CC, &levels[..depth as usize], f, ring.start, &mut walk).unwrap();
                if let Some(grid) = kernel.grid(&ring.verts, &walk) {
                    patches.push(TestPatch {
                        depth,
                        n_out,
                        f,
                        ring,
                        kernel,
                        grid,
                    });
                }
            }
        }
        patches
    }

    /// A triangle that owns only some of its rows gets a kernel of those rows at depth 2
    /// (`RingGroups`, `Kernel::subset`), which writes the very bits its key's kernel
    /// writes at those vertices, and nothing else; a quad, and a triangle at depth 3,
    /// keep their key's kernel.
    #[test]
    fn owned_rows_give_the_same_points() {
        let options = Options::default();
        let t = topology(&cube_with_triangles(), &options);
        let base: Vec<[f64; 3]> = (0..t.num_vertices())
            .map(|i| {
                let x = i as f64;
                [
                    (0.7 * x).sin() * 3.1 + 5.0,
                    (1.3 * x).cos() + 0.1 * x + 2.0,
                    1.0 / (1.0 + x),
                ]
            })
            .collect();
        let mut subsets = 0;
        for p in ring_patches(&t, &options) {
            let (f, grid) = (p.f, &p.grid);
            let run = |apply: &dyn Fn(&SharedOut<[f64; 3]>)| {
                let mut out = vec![[f64::NAN; 3]; p.n_out];
                apply(&SharedOut(out.as_mut_ptr()));
                out.iter().map(|p| p.map(f64::to_bits)).collect::<Vec<_>>()
            };
            assert_eq!(
                p.kernel.by_owner(),
                t.face_vertices(f).len() != 4,
                "face {f}"
            );
            let packs = p.kernel.by_owner() && grid.len() <= SUBSET_ROWS;
            let kernels = [Some(p.kernel)];
            // The key's kernel itself, every row it owns.
            let full = kernels[0].as_ref().unwrap();
            // SAFETY: the grid's indices are in bounds of the refined level.
            let want = run(&|out| unsafe { full.apply(&base, &p.ring.verts, grid, out) });
            // Every third owned row, then all but the first eleven.
            let owned: Vec<usize> = (0..grid.len()).filter(|&r| grid[r] != NOT_OWNED).collect();
            let keep: [&dyn Fn(usize) -> bool; 2] = [&|i| i % 3 == 0, &|i| i >= 11];
            for keep in keep {
                let mut part = grid.clone();
                for (i, &r) in owned.iter().enumerate() {
                    if !keep(i) {
                        part[r] = NOT_OWNED;
                    }
                }
                let kept = part.iter().filter(|&&o| o != NOT_OWNED).count();
                let mut groups = RingGroups::new(&kernels, SUBSET_ROWS);
                groups.push(0, 0, p.ring.verts.clone(), part.clone());
                let (patches, _) = groups.finish(1);
                assert_eq!((patches.kernels.len(), patches.len()), (1, 1));
                if packs {
                    assert_eq!(patches.kernels[0].rows, kept.next_multiple_of(LANES));
                    subsets += 1;
                } else {
                    assert_eq!(patches.kernels[0].rows, grid.len());
                }
                // SAFETY: as above.
                let got = run(&|out| unsafe { patches.apply(0, &base, out) });
                let unwritten = [f64::NAN.to_bits(); 3];
                for (v, (g, w)) in got.iter().zip(&want).enumerate() {
                    let mine = part.contains(&(v as u32));
                    let depth = p.depth;
                    let want = if mine { *w } else { unwritten };
                    assert_eq!(*g, want, "face {f} depth {depth} vertex {v}");
                }
            }
        }
        assert!(subsets >= 12, "{subsets} subsets");
    }

    /// The vector kernels compute the portable loop's sums: AVX2 and AVX-512 bit for bit
    /// alike (same terms in the same order, each fused), and both within rounding of the
    /// portable loop (which does not fuse), on every ring patch of two meshes: a closed
    /// one of quads and triangles with corners of valence 3 to 6, and an open one with a
    /// pentagon and corners on its boundary.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn vector_kernels_agree() {
        let options = Options::default();
        let closed = cube_with_triangles();
        let mut open: Vec<Vec<u32>> = one_ev_ring(5)
            .iter()
            .enumerate()
            .flat_map(|(i, q)| match i % 3 {
                0 => vec![vec![q[0], q[1], q[2]], vec![q[0], q[2], q[3]]],
                _ => vec![q.to_vec()],
            })
            .collect();
        open.push(vec![open[0][1], 99, 98, 97, open[0][0]]);
        let open: Vec<Vec<u32>> = {
            // Number the vertices densely.
            let mut ids: Vec<u32> = open.iter().flatten().copied().collect();
            ids.sort_unstable();
            ids.dedup();
            let id = |v: &u32| ids.binary_search(v).unwrap() as u32;
            open.iter().map(|f| f.iter().map(id).collect()).collect()
        };
        let mut patches = 0;
        for faces in [closed, open] {
            let t = topology(&faces, &options);
            let base: Vec<[f64; 3]> = (0..t.num_vertices())
                .map(|i| {
                    let x = i as f64;
                    [
                        (0.7 * x).sin() * 3.1,
                        (1.3 * x).cos() + 0.1 * x,
                        1.0 / (1.0 + x),
                    ]
                })
                .collect();
            for p in ring_patches(&t, &options) {
                let (depth, n_out, f, ring, grid) = (p.depth, p.n_out, p.f, &p.ring, &p.grid);
                let k = &p.kernel;
                let run = |out: &mut Vec<[f64; 3]>, kernel: u8| {
                    let shared = SharedOut(out.as_mut_ptr());
                    let (src, o) = (base.as_ptr().cast(), shared.0.cast());
                    let (ctrl, g) = (&ring.verts[..], &grid[..]);
                    // SAFETY: the grid's indices are in bounds of the refined level; the
                    // vector kernels only where the processor has their features.
                    unsafe {
                        match kernel {
                            0 => {
                                // The portable loop, one component at a time.
                                for c in 0..3 {
                                    let one: Vec<[f64; 1]> = base.iter().map(|p| [p[c]]).collect();
                                    let mut res = vec![[f64::NAN]; n_out];
                                    k.apply(&one, ctrl, g, &SharedOut(res.as_mut_ptr()));
                                    for (o, r) in out.iter_mut().zip(&res) {
                                        o[c] = r[0];
                                    }
                                }
                            }
                            1 => ring_patches_avx(k, src, ctrl, g, o),
                            _ => ring_patches_avx512(k, src, ctrl, g, o),
                        }
                    }
                };
                let mut portable = vec![[f64::NAN; 3]; n_out];
                run(&mut portable, 0);
                let written = portable.iter().filter(|p| !p[0].is_nan()).count();
                assert!(written > 0, "face {f} depth {depth}");
                patches += 1;
                if !has_avx2_fma() {
                    continue;
                }
                let mut avx = vec![[f64::NAN; 3]; n_out];
                run(&mut avx, 1);
                for (i, (a, b)) in avx.iter().zip(&portable).enumerate() {
                    for c in 0..3 {
                        assert!(
                            a[c].to_bits() == b[c].to_bits() || (a[c] - b[c]).abs() < 1e-14,
                            "face {f} depth {depth} vertex {i}: {a:?} against {b:?}"
                        );
                    }
                }
                if has_avx512f() {
                    let mut avx512 = vec![[f64::NAN; 3]; n_out];
                    run(&mut avx512, 2);
                    let bits = |v: &Vec<[f64; 3]>| -> Vec<[u64; 3]> {
                        v.iter().map(|p| p.map(f64::to_bits)).collect()
                    };
                    assert_eq!(bits(&avx512), bits(&avx), "face {f} depth {depth}");
                }
            }
        }
        assert!(patches >= 20, "{patches} ring patches");
    }

    /// The AVX2 kernel computes two patches at a time: three copies of each ring patch of
    /// a closed mesh of quads and triangles (depths 2 to 4), each reading its own points
    /// (moved differently) and writing its own vertices, computed together (a pair, then
    /// the last alone) give bit for bit what each gives alone, with all its rows owned,
    /// with every third row owned by another face, and with every third half group of
    /// four rows owned by another face (halves computed for both patches at once).
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn avx_pairs_agree() {
        if !has_avx2_fma() {
            return;
        }
        let options = Options::default();
        let t = topology(&cube_with_triangles(), &options);
        let (nv, copies) = (t.num_vertices(), 3);
        // Copy `i` reads its ring's vertex `v` at `i nv + v`.
        let base: Vec<[f64; 3]> = (0..copies * nv)
            .map(|i| {
                let x = i as f64;
                [
                    (0.7 * x).sin() * 3.1,
                    (1.3 * x).cos() + 0.1 * x,
                    1.0 / (1.0 + x),
                ]
            })
            .collect();
        let bits =
            |v: &[[f64; 3]]| -> Vec<[u64; 3]> { v.iter().map(|p| p.map(f64::to_bits)).collect() };
        let mut pairs = 0;
        for p in ring_patches(&t, &options) {
            let (points, nn, n_out) = (p.kernel.points, p.kernel.rows, p.n_out);
            let keep: [&dyn Fn(usize) -> bool; 3] =
                [&|_| true, &|r| r % 3 != 1, &|r| r / 4 % 3 != 1];
            for keep in keep {
                let (mut ctrl, mut grids) = (Vec::new(), Vec::new());
                for i in 0..copies {
                    ctrl.extend(p.ring.verts.iter().map(|&v| v + (i * nv) as u32));
                    grids.extend(p.grid.iter().enumerate().map(|(r, &o)| {
                        if o == NOT_OWNED || !keep(r) {
                            NOT_OWNED
                        } else {
                            o + (i * n_out) as u32
                        }
                    }));
                }
                let src = base.as_ptr().cast();
                let mut together = vec![[f64::NAN; 3]; copies * n_out];
                let mut alone = together.clone();
                // SAFETY: every grid index is in bounds of its copy's part of the output,
                // every ring point of the base; the processor has AVX2 and FMA.
                unsafe {
                    ring_patches_avx(&p.kernel, src, &ctrl, &grids, together.as_mut_ptr().cast());
                    for i in 0..copies {
                        let (c, g) = (&ctrl[i * points..][..points], &grids[i * nn..][..nn]);
                        ring_patches_avx(&p.kernel, src, c, g, alone.as_mut_ptr().cast());
                    }
                }
                let (b, a) = (bits(&together), bits(&alone));
                let differs = (0..a.len()).find(|&i| b[i] != a[i]);
                let (f, depth) = (p.f, p.depth);
                assert!(differs.is_none(), "face {f} depth {depth}: {differs:?}");
                // The copies read different points: their vertices differ.
                let j = (0..n_out)
                    .find(|&j| !alone[j][0].is_nan())
                    .expect("a vertex");
                assert_ne!(alone[j], alone[n_out + j], "face {f}");
                pairs += 1;
            }
        }
        assert!(pairs >= 60, "{pairs} pairs");
    }

    /// A triangle's vertices: three child quads of `(2ᵈ⁻¹ + 1)²` points sharing their
    /// sides from the centre, every row a partition of unity; a face with a corner of
    /// valence above [`MAX_VALENCE`] is not a ring patch.
    #[test]
    fn triangle_rows_and_limits() {
        let options = Options::default();
        let t = topology(&OCTAHEDRON, &options);
        let ring = ring_net(&t, 0, false).unwrap();
        assert_eq!(ring.verts.len(), 6);
        for depth in [2u32, 3, 4] {
            let k = Kernel::new(&ring.key, depth, &options, CC).unwrap();
            let h = 1usize << (depth - 1);
            let rows = 3 * (h + 1) * (h + 1) - 3 * (h + 1) + 1;
            assert_eq!(
                (0..k.rows).filter(|&r| k.row(r).next().is_some()).count(),
                rows
            );
            for r in 0..k.rows {
                let sum: f64 = k.row(r).map(|(_, w)| w).sum();
                assert!(
                    sum == 0.0 || (sum - 1.0).abs() < 1e-14,
                    "depth {depth} row {r}"
                );
            }
        }
        // A fan of 17 triangles around vertex 0.
        let fan: Vec<[u32; 3]> = (0..17u32).map(|i| [0, 1 + i, 1 + (i + 1) % 17]).collect();
        let mut closed = fan.clone();
        closed.extend((0..17u32).map(|i| [18, 1 + (i + 1) % 17, 1 + i]));
        assert!(ring_net(&topology(&closed, &options), 0, false).is_none());
    }
}
