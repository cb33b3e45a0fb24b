//! A face-varying channel's *value mesh*: the mesh's faces through one vertex per
//! face-varying subset, seams made boundaries, tagged so that its Catmull-Clark surface is
//! the channel's (OpenSubdiv's `Bfr::SurfaceFactory::InitFaceVaryingSurface`, OpenSubdiv
//! 3.5/3.6, `bfr/faceSurface.cpp`, `bfr/faceVertex.cpp`).
//!
//! The construction and the vertex sharpness a subset takes in each linear-interpolation
//! mode are documented with the surface that evaluates it,
//! [`FaceVaryingSurface`](crate::limit::FaceVaryingSurface) ("Method: the channel's value
//! mesh", "Vertex sharpness of a subset"). NURSS refines and evaluates channels as the
//! non-uniform surface of the same mesh (`refine::nurss::face_varying`), which is why it
//! lives here, below both.
//!
//! Every value-mesh vertex belongs to one mesh vertex (a subset is a fan of faces around
//! it), so every value-mesh edge lies on one mesh edge; faces keep the mesh's numbering and
//! corner order, so face-vertex slots (and face sides) are the mesh's.

use std::collections::HashSet;

use super::{
    BoundaryInterpolation, Corner, Crease, FaceVarying, FaceVaryingInterpolation, MeshError,
    Options, PolyMesh, Tags, Topology, SHARPNESS_INFINITE,
};

/// A channel's value mesh (see the module docs): faces through one vertex per
/// face-varying subset, and its tags.
#[derive(Clone, Debug)]
pub(crate) struct ValueMesh {
    /// The mesh's face offsets.
    pub(crate) face_offsets: Vec<u32>,
    /// Per face-vertex slot: its value-mesh vertex.
    pub(crate) faces: Vec<u32>,
    /// Per value-mesh vertex: the channel's value index.
    pub(crate) value_of: Vec<u32>,
    /// Per value-mesh vertex: the mesh vertex it lies on.
    pub(crate) vertex_of: Vec<u32>,
    /// Holes (the mesh's), the mesh's sharp edges between value-mesh vertices, and each
    /// subset's vertex sharpness as corners.
    pub(crate) tags: Tags,
}

/// Union-find root of `x`, with path halving.
fn root(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let p = parent[parent[x as usize] as usize];
        parent[x as usize] = p;
        x = p;
    }
    x
}

/// What the subset rules read about the mesh and the channel.
struct Ctx<'a> {
    t: &'a Topology,
    indices: &'a [u32],
    /// Per face-vertex: its value-mesh vertex.
    vertex_of: Vec<u32>,
    /// Per edge: its two faces agree on the values at both ends (false for an edge
    /// without two faces).
    matched: Vec<bool>,
    /// Per mesh vertex: explicit (tagged) sharpness.
    explicit: Vec<f32>,
}

impl ValueMesh {
    /// The value mesh of the channel whose corner value indices are `indices`, on a mesh
    /// whose topology with `options` is `t` and whose vertices have the explicit (tagged)
    /// sharpness `explicit` ([`explicit_sharpness`](Self::explicit_sharpness)).
    pub(crate) fn build(
        t: &Topology,
        options: &Options,
        indices: &[u32],
        explicit: &[f32],
    ) -> Self {
        let (vertex_of, value_of, matched) = Self::subsets(t, indices);
        let explicit = explicit.to_vec();
        let ctx = Ctx {
            t,
            indices,
            vertex_of,
            matched,
            explicit,
        };
        let mut tags = Tags {
            holes: (0..t.num_faces() as u32)
                .filter(|&f| t.is_hole(f as usize))
                .collect(),
            ..Tags::default()
        };
        tags.creases = ctx.creases();
        tags.corners = ctx.corners(value_of.len(), options);
        let mut vertex_of = vec![0u32; value_of.len()];
        for (&w, &v) in ctx.vertex_of.iter().zip(&t.face_verts) {
            vertex_of[w as usize] = v;
        }
        ValueMesh {
            face_offsets: t.face_offsets.clone(),
            faces: ctx.vertex_of,
            value_of,
            vertex_of,
            tags,
        }
    }

    /// The explicit sharpness of every vertex of `mesh`: its corner tags (the last one of a
    /// vertex tagged twice), 0 elsewhere.
    pub(crate) fn explicit_sharpness(mesh: &PolyMesh) -> Vec<f32> {
        let mut explicit = vec![0.0f32; mesh.num_vertices()];
        for c in &mesh.tags.corners {
            if let Some(s) = explicit.get_mut(c.vertex as usize) {
                *s = c.sharpness;
            }
        }
        explicit
    }

    /// The explicit sharpness of every vertex of a refined level `t`, as the level written
    /// to a file tags it (its vertex sharpness, but on non-manifold vertices and on the
    /// corners that edge-and-corner boundaries sharpen, which reading sharpens again).
    pub(crate) fn written_sharpness(t: &Topology) -> Vec<f32> {
        (0..t.num_vertices())
            .map(|v| {
                let tag = t.vertex_tag(v);
                if tag.non_manifold || tag.sharpened_corner {
                    0.0
                } else {
                    t.vertex_sharpness(v)
                }
            })
            .collect()
    }

    /// The sharpness of every value-mesh vertex (its corner tag, or 0).
    pub(crate) fn vertex_sharpness(&self) -> Vec<f32> {
        let mut s = vec![0.0f32; self.num_vertices()];
        for c in &self.tags.corners {
            s[c.vertex as usize] = c.sharpness;
        }
        s
    }

    /// The options of the value mesh: the mesh's, with edge-only boundary interpolation
    /// (the sharp corners are tagged, [`BoundaryInterpolation::EdgeAndCorner`]'s
    /// included).
    pub(crate) fn options(options: &Options) -> Options {
        Options {
            boundary: BoundaryInterpolation::EdgeOnly,
            ..*options
        }
    }

    /// Number of value-mesh vertices.
    pub(crate) fn num_vertices(&self) -> usize {
        self.value_of.len()
    }

    /// The value mesh with `points` at its vertices, and its tags.
    ///
    /// # Errors
    /// [`MeshError`] if `points` does not have one point per value-mesh vertex, or a
    /// coordinate is not finite.
    pub(crate) fn polymesh(&self, points: Vec<[f64; 3]>) -> Result<PolyMesh, MeshError> {
        let mut m = PolyMesh::new(points, self.face_offsets.clone(), self.faces.clone())?;
        m.tags = self.tags.clone();
        Ok(m)
    }

    /// The subsets: per face-vertex its value-mesh vertex, per value-mesh vertex its
    /// value, and per edge whether its faces agree.
    fn subsets(t: &Topology, indices: &[u32]) -> (Vec<u32>, Vec<u32>, Vec<bool>) {
        let mut parent: Vec<u32> = (0..indices.len() as u32).collect();
        let mut matched = vec![false; t.num_edges()];
        let mut ends = Vec::new();
        for (e, m) in matched.iter_mut().enumerate() {
            let faces = t.edge_face_list(e);
            if faces.len() < 2 {
                continue;
            }
            let a = t.edge_verts[e][0];
            ends.clear();
            for (i, &f) in faces.iter().enumerate() {
                let f = f as usize;
                let k = t.edge_face_local[t.edge_face_offsets[e] as usize + i] as usize;
                let (o, n) = (t.face_offsets[f] as usize, t.face_vertices(f).len());
                let (c0, c1) = (o + k, o + (k + 1) % n);
                ends.push(if t.face_verts[c0] == a {
                    (c0, c1)
                } else {
                    (c1, c0)
                });
            }
            let mut all = true;
            for i in 0..ends.len() {
                for j in i + 1..ends.len() {
                    let ((a0, b0), (a1, b1)) = (ends[i], ends[j]);
                    if indices[a0] == indices[a1] && indices[b0] == indices[b1] {
                        for (x, y) in [(a0, a1), (b0, b1)] {
                            let (rx, ry) =
                                (root(&mut parent, x as u32), root(&mut parent, y as u32));
                            parent[rx as usize] = ry;
                        }
                    } else {
                        all = false;
                    }
                }
            }
            *m = all && faces.len() == 2;
        }
        let mut id = vec![u32::MAX; indices.len()];
        let mut vertex_of = vec![0u32; indices.len()];
        let mut value_of = Vec::new();
        for c in 0..indices.len() {
            let r = root(&mut parent, c as u32) as usize;
            if id[r] == u32::MAX {
                id[r] = value_of.len() as u32;
                value_of.push(indices[r]);
            }
            vertex_of[c] = id[r];
        }
        (vertex_of, value_of, matched)
    }

    /// Component `chunk` (3 components from `3 chunk`, zero beyond the channel's) of the
    /// values of the value-mesh vertices.
    pub(crate) fn points(&self, ch: &FaceVarying, chunk: usize) -> Vec<[f64; 3]> {
        (self.value_of.iter())
            .map(|&x| {
                let v = ch.value(x as usize);
                std::array::from_fn(|k| v.get(3 * chunk + k).copied().unwrap_or(0.0))
            })
            .collect()
    }
}

impl Ctx<'_> {
    /// The value-mesh vertex at the corner of `v`'s `i`-th face.
    fn at(&self, v: usize, i: usize) -> u32 {
        let f = self.t.vertex_faces(v)[i] as usize;
        self.vertex_of[self.t.face_offsets[f] as usize + self.t.vertex_face_locals(v)[i] as usize]
    }

    /// The channel's value at the corner of `v`'s `i`-th face.
    fn value_at(&self, v: usize, i: usize) -> u32 {
        let f = self.t.vertex_faces(v)[i] as usize;
        self.indices[self.t.face_offsets[f] as usize + self.t.vertex_face_locals(v)[i] as usize]
    }

    /// The mesh's sharp edges (explicit creases, and the implicit ones of non-manifold
    /// edges) between the value-mesh vertices of their faces.
    fn creases(&self) -> Vec<Crease> {
        let t = self.t;
        let mut seen = HashSet::new();
        let mut out = Vec::new();
        for e in 0..t.num_edges() {
            let s = t.edge_sharpness[e];
            let faces = t.edge_face_list(e);
            if s <= 0.0 || faces.len() < 2 {
                continue;
            }
            for (i, &f) in faces.iter().enumerate() {
                let f = f as usize;
                let k = t.edge_face_local[t.edge_face_offsets[e] as usize + i] as usize;
                let (o, n) = (t.face_offsets[f] as usize, t.face_vertices(f).len());
                let (a, b) = (self.vertex_of[o + k], self.vertex_of[o + (k + 1) % n]);
                if seen.insert((a.min(b), a.max(b))) {
                    out.push(Crease {
                        v0: a,
                        v1: b,
                        sharpness: s,
                    });
                }
            }
        }
        out
    }

    /// The sharpness of every value-mesh vertex (module docs, "Vertex sharpness of a
    /// subset"), as corner tags.
    fn corners(&self, count: usize, options: &Options) -> Vec<Corner> {
        let mut sharp = vec![0.0f32; count];
        for v in 0..self.t.num_vertices() {
            let nf = self.t.vertex_faces(v).len();
            let mut done = Vec::new();
            for i in 0..nf {
                let w = self.at(v, i);
                if !done.contains(&w) {
                    done.push(w);
                    sharp[w as usize] = self.subset_sharpness(v, w, options);
                }
            }
        }
        (sharp.into_iter().enumerate())
            .filter(|&(_, s)| s > 0.0)
            .map(|(w, sharpness)| Corner {
                vertex: w as u32,
                sharpness,
            })
            .collect()
    }

    /// The sharpness of subset `w` of vertex `v`.
    fn subset_sharpness(&self, v: usize, w: u32, options: &Options) -> f32 {
        let t = self.t;
        let vtag = t.vert_tags[v].get();
        if vtag.non_manifold {
            return SHARPNESS_INFINITE;
        }
        let nf = t.vertex_faces(v).len();
        let size = (0..nf).filter(|&i| self.at(v, i) == w).count();
        let edges = t.vertex_edges(v);
        // Interior edges of the subset: between two of its faces, agreeing.
        let inside = |i: usize| {
            let e = edges[i] as usize;
            self.matched[e] && {
                let prev = if i == 0 { nf - 1 } else { i - 1 };
                i < nf && self.at(v, prev) == w && self.at(v, i) == w
            }
        };
        let closed = !vtag.boundary
            && size == nf
            && (0..edges.len()).all(|i| self.matched[edges[i] as usize]);
        let boundary = !closed;
        let mut s = if size == nf && boundary == vtag.boundary {
            // The vertex's own sharpness (with the corner that edge-and-corner sharpens).
            t.vert_sharpness[v]
        } else {
            let inf_inside = (0..edges.len())
                .any(|i| inside(i) && t.edge_sharpness[edges[i] as usize] >= SHARPNESS_INFINITE);
            if boundary && inf_inside {
                SHARPNESS_INFINITE
            } else {
                self.explicit[v]
            }
        };
        if s < SHARPNESS_INFINITE && size < nf {
            let x = (0..nf)
                .find(|&i| self.at(v, i) == w)
                .map(|i| self.value_at(v, i));
            if (0..nf).filter(|&i| Some(self.value_at(v, i)) == x).count() > size {
                s = SHARPNESS_INFINITE;
            }
        }
        if boundary && s < SHARPNESS_INFINITE {
            s = self.by_mode(v, w, size, s, &inside, options.face_varying);
        }
        s
    }

    /// Rule 3 of the module docs: the sharpness `s` of boundary subset `w` (of `size`
    /// faces) of vertex `v` under `mode`; `inside(i)`: `v`'s edge `i` is inside the subset.
    fn by_mode(
        &self,
        v: usize,
        w: u32,
        size: usize,
        s: f32,
        inside: &dyn Fn(usize) -> bool,
        mode: FaceVaryingInterpolation,
    ) -> f32 {
        use FaceVaryingInterpolation as F;
        let t = self.t;
        let nf = t.vertex_faces(v).len();
        // `plus1` and `plus2`: corners and vertices of more than two subsets.
        let plus = || (size == 1 || self.more_than_two_subsets(v, w)).then_some(SHARPNESS_INFINITE);
        let dependent = |s: f32| -> f32 {
            let edges = t.vertex_edges(v);
            let sharp_edges = |e: &u32| {
                t.edge_face_list(*e as usize).len() == 2 && t.edge_sharpness[*e as usize] > 0.0
            };
            let has = nf - size > 1
                && edges.iter().any(sharp_edges)
                && !(0..edges.len())
                    .any(|i| inside(i) && t.edge_sharpness[edges[i] as usize] > 0.0);
            if !has {
                return s;
            }
            let dep = self.dependent_sharpness(v, w);
            if dep > self.explicit[v] {
                dep
            } else {
                s
            }
        };
        match mode {
            F::None => s,
            F::CornersOnly => {
                if size == 1 {
                    SHARPNESS_INFINITE
                } else {
                    s
                }
            }
            F::CornersPlus1 => plus().unwrap_or_else(|| dependent(s)),
            F::CornersPlus2 => plus().unwrap_or_else(|| match nf - size {
                0 if !t.vert_tags[v].get().boundary => SHARPNESS_INFINITE,
                0 => s,
                1 => SHARPNESS_INFINITE,
                _ => dependent(s),
            }),
            F::Boundaries | F::All => SHARPNESS_INFINITE,
        }
    }

    /// Whether vertex `v` has a value other than subset `w`'s and its own, or the one other
    /// value in more than one fan (`Bfr`'s `hasMoreThanTwoFVarSubsets`).
    fn more_than_two_subsets(&self, v: usize, w: u32) -> bool {
        let t = self.t;
        let nf = t.vertex_faces(v).len();
        let boundary = t.vert_tags[v].get().boundary;
        let edges = t.vertex_edges(v);
        let corner = (0..nf)
            .find(|&i| self.at(v, i) == w)
            .map(|i| self.value_at(v, i));
        let mut other = None;
        let mut discts = 1;
        for i in 0..nf {
            let x = Some(self.value_at(v, i));
            if x == corner {
                continue;
            }
            if other.is_some() && x != other {
                return true;
            }
            other = x;
            // The edge to the next face: edge `i + 1` (edge `i` lies between faces `i - 1`
            // and `i`).
            let next_edge = if boundary {
                (i + 1 < nf).then_some(i + 1)
            } else {
                Some((i + 1) % nf)
            };
            discts += next_edge.is_none_or(|k| !self.matched[edges[k] as usize]) as u32;
            if discts > 2 {
                return true;
            }
        }
        false
    }

    /// The largest sharpness of `v`'s interior edges but the two bounding subset `w` (a fan
    /// that is not all of `v`'s faces).
    fn dependent_sharpness(&self, v: usize, w: u32) -> f32 {
        let t = self.t;
        let nf = t.vertex_faces(v).len();
        let boundary = t.vert_tags[v].get().boundary;
        let edges = t.vertex_edges(v);
        let ins = |i: usize| self.at(v, i) == w;
        let prev = |i: usize| {
            if i == 0 {
                (!boundary).then_some(nf - 1)
            } else {
                Some(i - 1)
            }
        };
        let next = |i: usize| {
            if i + 1 == nf {
                (!boundary).then_some(0)
            } else {
                Some(i + 1)
            }
        };
        // The edge before the fan's first face and the one after its last (edge `i` lies
        // before face `i`).
        let first = (0..nf).find(|&i| ins(i) && prev(i).is_none_or(|p| !ins(p)));
        let last = (0..nf).find(|&i| ins(i) && next(i).is_none_or(|n| !ins(n)));
        let skip_a = first.filter(|&i| prev(i).is_some());
        let skip_b = last.and_then(next);
        let mut sharp = 0.0f32;
        for (i, &e) in edges.iter().enumerate().take(nf) {
            if prev(i).is_none() || Some(i) == skip_a || Some(i) == skip_b {
                continue;
            }
            sharp = sharp.max(t.edge_sharpness[e as usize]);
        }
        sharp
    }
}
