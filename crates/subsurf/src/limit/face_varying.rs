//! [`FaceVaryingSurface`]: the exact limit of a face-varying channel (texture coordinates)
//! at any `(face, u, v)`, with first derivatives, as OpenSubdiv's `Bfr` evaluates
//! face-varying surfaces (`Bfr::SurfaceFactory::InitFaceVaryingSurface`, OpenSubdiv 3.5/3.6,
//! `bfr/faceSurface.cpp`, `bfr/faceVertex.cpp`; the rules are those of Pixar's OpenSubdiv
//! documentation, "Subdivision Surfaces", section "Face-varying Interpolation Rules").
//!
//! # Method: the channel's value mesh
//! A face-varying channel gives every face corner a value; around a vertex, faces that agree
//! on the values at both ends of the edge between them are *connected* (OpenSubdiv's
//! `FaceIndicesMatchAcrossEdge`), and an edge whose faces disagree is a seam. The faces
//! around a vertex connected that way form one *face-varying subset*
//! (`Bfr::FaceVertex::FindFaceVaryingSubset`): a fan of faces sharing one value. `Bfr`
//! evaluates the channel's limit on a face as the Catmull-Clark limit of a patch whose
//! control points are the values of its corners' subsets, each subset a vertex of its own,
//! bounded where its fan ends (a seam is a boundary, infinitely sharp as every boundary), with
//! the vertex mesh's edge sharpness inside the fans and a vertex sharpness that the
//! linear-interpolation mode sets per subset (below).
//!
//! That is exactly the Catmull-Clark limit of the channel's *value mesh*: one vertex per
//! subset (its position the value, padded to 3 components, 3 at a time for larger
//! channels), the mesh's faces through those vertices (so seams become boundaries), the
//! mesh's edge sharpness, holes and crease method, boundary interpolation edge-only and the
//! vertex sharpness below. The limit on a face depends only on its corners' fans and on
//! the rules at its corners, which the value mesh reproduces subset by subset; it is
//! evaluated with [`LimitSurface`] (exact, `Bfr`'s accuracy: see its docs).
//!
//! # Vertex sharpness of a subset (`Bfr::FaceSurface::sharpenBySdcFVarLinearInterpolation`)
//! Let `S` be a subset at vertex `v` (`|S|` faces of `v`'s `n`), *boundary* unless it is the
//! whole closed fan of an interior vertex with no seam.
//! 1. If `S` has the extent of `v`'s own faces (same count, same boundary status) it keeps
//!    `v`'s sharpness, including the corner sharpened by
//!    [`BoundaryInterpolation::EdgeAndCorner`]. Otherwise its sharpness is `v`'s explicit
//!    (tagged) sharpness, and it is infinitely sharp if it is a boundary with an infinitely
//!    sharp edge inside the fan.
//! 2. Infinitely sharp if `v` is non-manifold, or if `S`'s value occurs at `v` in faces
//!    outside `S` (a non-manifold value).
//! 3. A boundary subset not yet infinitely sharp is sharpened by the mode
//!    ([`FaceVaryingInterpolation`]): `none` never; `corners-only` if `|S| = 1`;
//!    `corners-plus1` if `|S| = 1` or `v` has more than two subsets (a third value, or the
//!    other value in more than one fan); `corners-plus2` as `plus1`, and also when `S` is all of
//!    an interior vertex's faces (a dart of the seams) or all but one; `boundaries` always.
//!    With `plus1` and `plus2`, a subset without sharp edges inside, at a vertex with sharp
//!    interior edges and at least two faces outside `S`, takes as vertex sharpness the
//!    largest sharpness of the interior edges outside it (but the two seams bounding it), if
//!    that exceeds `v`'s own ("dependent sharpness").
//!
//! [`FaceVaryingInterpolation::All`] (OpenSubdiv's default) is linear everywhere: the value
//! is the bilinear interpolation of the face's corner values on a quad, and on sub-face `j`
//! of an `n`-gon the bilinear interpolation of corner `j`, the midpoints of edges `j` and
//! `j − 1` and the centroid (`Bfr::Surface`'s linear patches).
//!
//! Not supported: Loop and NURSS (no face-varying limit: [`FaceVaryingError::Unsupported`]).
//! The adjustable scheme's limit is the Catmull-Clark limit of its refined mesh, face-varying
//! channels included: evaluate the channel of the refined mesh
//! ([`crate::MixedSurface::refined_point`] maps the points).

use std::collections::HashSet;

use rayon::prelude::*;

use super::{EvalError, LimitSurface, Order, SurfacePoint};
use crate::mesh::{
    BoundaryInterpolation, Corner, Crease, FaceVarying, FaceVaryingInterpolation, MeshError,
    Options, PolyMesh, Tags, Topology,
};
use crate::scheme::crease::SHARPNESS_INFINITE;
use crate::scheme::Scheme;

/// Errors of building a [`FaceVaryingSurface`].
#[derive(Debug, thiserror::Error)]
pub enum FaceVaryingError {
    /// The mesh (or the channel's value mesh) is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// There is no channel of that index.
    #[error("face-varying channel {channel} does not exist (the mesh has {count})")]
    NoSuchChannel {
        /// Requested channel.
        channel: usize,
        /// Number of channels.
        count: usize,
    },
    /// The scheme has no face-varying limit here.
    #[error("the limit of face-varying data is not available with the {scheme} scheme")]
    Unsupported {
        /// The scheme's name.
        scheme: &'static str,
    },
}

/// A channel's limit at points: `dim` numbers per point for the value and each first
/// derivative (by the face's, or sub-face's, `u` and `v`, as [`LimitSurface`]'s).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ChannelValues {
    /// Components per value.
    pub dim: usize,
    /// Values, `dim` numbers per point.
    pub value: Vec<f64>,
    /// Derivatives by `u`, `dim` numbers per point.
    pub du: Vec<f64>,
    /// Derivatives by `v`, `dim` numbers per point.
    pub dv: Vec<f64>,
}

impl ChannelValues {
    fn zeros(dim: usize, n: usize) -> Self {
        Self {
            dim,
            value: vec![0.0; dim * n],
            du: vec![0.0; dim * n],
            dv: vec![0.0; dim * n],
        }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.value.len() / self.dim.max(1)
    }

    /// Whether there are no points.
    pub fn is_empty(&self) -> bool {
        self.value.is_empty()
    }

    /// The value at point `i`.
    pub fn value_at(&self, i: usize) -> &[f64] {
        &self.value[self.dim * i..self.dim * (i + 1)]
    }
}

/// The limit surface of one face-varying channel of a mesh (see the module docs).
///
/// ```
/// use subsurf::limit::{FaceVaryingSurface, SurfacePoint};
/// use subsurf::mesh::{FaceVarying, FaceVaryingInterpolation, Options, PolyMesh};
/// // Two quads side by side whose texture coordinates are cut along their shared edge.
/// let p = vec![
///     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0],
///     [0.0, 1.0, 0.0], [1.0, 1.0, 0.0], [2.0, 1.0, 0.0],
/// ];
/// let mut m = PolyMesh::from_faces(p, &[[0u32, 1, 4, 3], [1, 2, 5, 4]]).unwrap();
/// let uv = vec![0.0, 0.0, 0.5, 0.0, 0.5, 1.0, 0.0, 1.0, 0.6, 0.0, 1.0, 0.0, 1.0, 1.0, 0.6, 1.0];
/// m.face_varying.push(FaceVarying::new("uv", 2, uv, vec![0, 1, 2, 3, 4, 5, 6, 7]).unwrap());
/// let options = Options { face_varying: FaceVaryingInterpolation::CornersOnly, ..Options::default() };
/// let s = FaceVaryingSurface::new(&m, options, 0).unwrap();
/// // Each face is its own island: the seam is a boundary of both, straight between the
/// // islands' corners, which this mode keeps.
/// let at = |face, u| s.eval_point(SurfacePoint { face, subface: 0, u, v: 0.5 }).unwrap().value;
/// assert!((at(0, 1.0)[0] - 0.5).abs() < 1e-12 && (at(1, 0.0)[0] - 0.6).abs() < 1e-12);
/// ```
#[derive(Clone, Debug)]
pub struct FaceVaryingSurface {
    dim: usize,
    kind: Kind,
}

/// A linear channel: the mesh's faces, the channel's corner indices and values.
#[derive(Clone, Debug)]
struct Linear {
    dim: usize,
    face_offsets: Vec<u32>,
    indices: Vec<u32>,
    values: Vec<f64>,
    holes: Vec<bool>,
}

#[derive(Clone, Debug)]
enum Kind {
    /// [`FaceVaryingInterpolation::All`]: bilinear on every (sub-)face.
    Linear(Linear),
    /// The value mesh's limit surface, per 3 components.
    Smooth(Vec<LimitSurface>),
}

impl FaceVaryingSurface {
    /// The limit of channel `channel` of `mesh` under Catmull-Clark with `options` (whose
    /// [`Options::face_varying`] is the mode).
    ///
    /// # Errors
    /// [`FaceVaryingError::NoSuchChannel`], or [`FaceVaryingError::Mesh`] for an invalid
    /// mesh.
    pub fn new(
        mesh: &PolyMesh,
        options: Options,
        channel: usize,
    ) -> Result<Self, FaceVaryingError> {
        mesh.validate()?;
        let ch = mesh
            .face_varying
            .get(channel)
            .ok_or(FaceVaryingError::NoSuchChannel {
                channel,
                count: mesh.face_varying.len(),
            })?;
        let (t, _) = Topology::from_mesh(mesh, &options)?;
        if options.face_varying == FaceVaryingInterpolation::All {
            return Ok(Self::linear(&t, ch));
        }
        let vm = ValueMesh::build(mesh, &t, &options, ch.indices());
        let dim = ch.dim();
        let value_options = Options {
            boundary: BoundaryInterpolation::EdgeOnly,
            ..options
        };
        let mut surfaces = Vec::new();
        for chunk in 0..dim.div_ceil(3) {
            let points = vm.points(ch, chunk);
            match surfaces.first() {
                None => {
                    let mut m = PolyMesh::new(points, vm.face_offsets.clone(), vm.faces.clone())?;
                    m.tags = vm.tags.clone();
                    surfaces.push(LimitSurface::new(m, value_options)?);
                }
                Some(first) => {
                    let mut s: LimitSurface = first.clone();
                    s.set_positions(&points)?;
                    surfaces.push(s);
                }
            }
        }
        Ok(Self {
            dim,
            kind: Kind::Smooth(surfaces),
        })
    }

    /// [`FaceVaryingSurface::new`] for `scheme`: Catmull-Clark, and bilinear (whose
    /// face-varying limit is linear in every mode, as OpenSubdiv's); the adjustable scheme
    /// through its refined mesh (see the module docs).
    ///
    /// # Errors
    /// [`FaceVaryingError::Unsupported`] for Loop, NURSS and the adjustable scheme (whose
    /// channels are evaluated on the refined mesh), else as [`FaceVaryingSurface::new`].
    pub fn for_scheme(
        mesh: &PolyMesh,
        scheme: Scheme,
        options: Options,
        channel: usize,
    ) -> Result<Self, FaceVaryingError> {
        match scheme {
            Scheme::CatmullClark => Self::new(mesh, options, channel),
            Scheme::Bilinear => {
                let linear = Options {
                    face_varying: FaceVaryingInterpolation::All,
                    ..options
                };
                Self::new(mesh, linear, channel)
            }
            _ => Err(FaceVaryingError::Unsupported {
                scheme: scheme.name(),
            }),
        }
    }

    fn linear(t: &Topology, ch: &FaceVarying) -> Self {
        Self {
            dim: ch.dim(),
            kind: Kind::Linear(Linear {
                dim: ch.dim(),
                face_offsets: t.face_offsets.clone(),
                indices: ch.indices().to_vec(),
                values: ch.values().to_vec(),
                holes: (0..t.num_faces()).map(|f| t.is_hole(f)).collect(),
            }),
        }
    }

    /// Components per value.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The value and first derivatives at `p`.
    ///
    /// # Errors
    /// As [`LimitSurface::eval_point`]: no such face or sub-face, a hole, a parameter
    /// outside `[0, 1]`.
    pub fn eval_point(&self, p: SurfacePoint) -> Result<ChannelValues, EvalError> {
        self.eval_many(&[p])
    }

    /// The values and first derivatives at `points`, evaluated in parallel (list the points
    /// face by face for speed, as for [`LimitSurface::eval_many`]).
    ///
    /// # Errors
    /// The first point's error, as [`FaceVaryingSurface::eval_point`].
    pub fn eval_many(&self, points: &[SurfacePoint]) -> Result<ChannelValues, EvalError> {
        let dim = self.dim;
        let mut out = ChannelValues::zeros(dim, points.len());
        match &self.kind {
            Kind::Linear(linear) => {
                const CHUNK: usize = 1024;
                (points.par_chunks(CHUNK))
                    .zip(out.value.par_chunks_mut(dim * CHUNK))
                    .zip(out.du.par_chunks_mut(dim * CHUNK))
                    .zip(out.dv.par_chunks_mut(dim * CHUNK))
                    .try_for_each(|(((ps, val), du), dv)| {
                        for (i, &p) in ps.iter().enumerate() {
                            let r = dim * i..dim * (i + 1);
                            linear.eval(p, &mut val[r.clone()], &mut du[r.clone()], &mut dv[r])?;
                        }
                        Ok(())
                    })?;
            }
            Kind::Smooth(surfaces) => {
                let mut res = Vec::new();
                for (chunk, s) in surfaces.iter().enumerate() {
                    s.eval_many_into(points, Order::First, &mut res);
                    for (i, r) in res.iter().enumerate() {
                        let d = r.as_ref().map_err(Clone::clone)?;
                        for k in 0..3.min(dim - 3 * chunk) {
                            let at = dim * i + 3 * chunk + k;
                            out.value[at] = d.p[k];
                            out.du[at] = d.du[k];
                            out.dv[at] = d.dv[k];
                        }
                    }
                }
            }
        }
        Ok(out)
    }
}

impl Linear {
    /// The linear (bilinear per sub-face) value and derivatives at `p`.
    fn eval(
        &self,
        p: SurfacePoint,
        val: &mut [f64],
        du: &mut [f64],
        dv: &mut [f64],
    ) -> Result<(), EvalError> {
        let Linear {
            dim,
            face_offsets,
            indices,
            values,
            holes,
        } = self;
        let (f, dim) = (p.face as usize, *dim);
        if f + 1 >= face_offsets.len() {
            return Err(EvalError::NoSuchFace {
                face: p.face,
                count: face_offsets.len() - 1,
            });
        }
        let corners = &indices[face_offsets[f] as usize..face_offsets[f + 1] as usize];
        let n = corners.len();
        let subs = if n == 4 { 1 } else { n };
        if p.subface as usize >= subs {
            return Err(EvalError::NoSuchSubface {
                face: p.face,
                subface: p.subface,
                size: subs,
            });
        }
        if !(0.0..=1.0).contains(&p.u) || !(0.0..=1.0).contains(&p.v) {
            return Err(EvalError::BadParameter { u: p.u, v: p.v });
        }
        if holes[f] {
            return Err(EvalError::Hole { face: p.face });
        }
        let value = |c: usize| &values[dim * corners[c] as usize..][..dim];
        // The four corners of the bilinear patch, (0,0), (1,0), (1,1), (0,1), as weights
        // on the face's corners: the face's own for a quad; for sub-face `j` of an n-gon,
        // corner `j`, the midpoint of edge `j`, the centroid, the midpoint of edge `j - 1`.
        let mut w = vec![[0.0; 4]; n];
        if n == 4 {
            (0..4).for_each(|c| w[c][c] = 1.0);
        } else {
            let j = p.subface as usize;
            let (next, prev) = ((j + 1) % n, (j + n - 1) % n);
            w[j][0] = 1.0;
            w[j][1] += 0.5;
            w[next][1] += 0.5;
            (0..n).for_each(|c| w[c][2] = 1.0 / n as f64);
            w[j][3] += 0.5;
            w[prev][3] += 0.5;
        }
        let (u, v) = (p.u, p.v);
        // Bilinear weights of the patch corners and their derivatives.
        let b = [(1.0 - u) * (1.0 - v), u * (1.0 - v), u * v, (1.0 - u) * v];
        let bu = [-(1.0 - v), 1.0 - v, v, -v];
        let bv = [-(1.0 - u), -u, u, 1.0 - u];
        val.fill(0.0);
        du.fill(0.0);
        dv.fill(0.0);
        for (c, wc) in w.iter().enumerate() {
            let (a, au, av) = (0..4).fold((0.0, 0.0, 0.0), |(a, au, av), k| {
                (a + wc[k] * b[k], au + wc[k] * bu[k], av + wc[k] * bv[k])
            });
            for (k, &x) in value(c).iter().enumerate() {
                val[k] += a * x;
                du[k] += au * x;
                dv[k] += av * x;
            }
        }
        Ok(())
    }
}

/// A channel's value mesh (see the module docs): faces through one vertex per
/// face-varying subset, and its tags.
struct ValueMesh {
    face_offsets: Vec<u32>,
    faces: Vec<u32>,
    /// Per value-mesh vertex: the channel's value index.
    value_of: Vec<u32>,
    tags: Tags,
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
    fn build(mesh: &PolyMesh, t: &Topology, options: &Options, indices: &[u32]) -> Self {
        let (vertex_of, value_of, matched) = Self::subsets(t, indices);
        let mut explicit = vec![0.0f32; t.num_vertices()];
        for c in &mesh.tags.corners {
            if let Some(s) = explicit.get_mut(c.vertex as usize) {
                *s = c.sharpness;
            }
        }
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
        ValueMesh {
            face_offsets: t.face_offsets.clone(),
            faces: ctx.vertex_of,
            value_of,
            tags,
        }
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
    fn points(&self, ch: &FaceVarying, chunk: usize) -> Vec<[f64; 3]> {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 3 grid of quads whose last quad is split into two triangles (16 vertices), its
    /// positions as a channel of `dim` components (`dim ≥ 3`, the rest a function of them).
    fn grid(dim: usize) -> PolyMesh {
        let mut p = Vec::new();
        for j in 0..4 {
            for i in 0..4 {
                p.push([i as f64, j as f64, 0.1 * ((i * j) % 3) as f64]);
            }
        }
        let v = |i: u32, j: u32| j * 4 + i;
        let mut faces: Vec<Vec<u32>> = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                faces.push(vec![v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)]);
            }
        }
        let last = faces.pop().unwrap_or_default();
        faces.push(vec![last[0], last[1], last[2]]);
        faces.push(vec![last[0], last[2], last[3]]);
        let mut m = PolyMesh::from_faces(p.clone(), &faces).unwrap();
        let values: Vec<f64> = (p.iter())
            .flat_map(|q| (0..dim).map(move |k| if k < 3 { q[k] } else { q[0] * q[1] + k as f64 }))
            .collect();
        let indices = m.face_verts().to_vec();
        m.face_varying
            .push(FaceVarying::new("data", dim, values, indices).unwrap());
        m
    }

    fn points(m: &PolyMesh) -> Vec<SurfacePoint> {
        let mut out = Vec::new();
        for f in 0..m.num_faces() as u32 {
            let subs = if m.face(f as usize).len() == 4 {
                1
            } else {
                m.face(f as usize).len()
            };
            for subface in 0..subs as u32 {
                for (u, v) in [(0.0, 0.0), (0.3, 0.7), (1.0, 0.5), (0.5, 1.0)] {
                    out.push(SurfacePoint {
                        face: f,
                        subface,
                        u,
                        v,
                    });
                }
            }
        }
        out
    }

    /// A channel laid out as the vertices (no seam) in mode `none` is the vertex limit
    /// surface of its values: here the positions themselves, so it is `LimitSurface`'s.
    #[test]
    fn a_channel_without_seams_is_the_vertex_limit() {
        let m = grid(3);
        let options = Options {
            face_varying: FaceVaryingInterpolation::None,
            ..Options::default()
        };
        let uv = FaceVaryingSurface::new(&m, options, 0).unwrap();
        let s = LimitSurface::new(&m, options).unwrap();
        let ps = points(&m);
        let got = uv.eval_many(&ps).unwrap();
        for (i, p) in ps.iter().enumerate() {
            let d = s.eval_point(*p).unwrap();
            for k in 0..3 {
                assert!((got.value[3 * i + k] - d.p[k]).abs() < 1e-14, "{p:?}");
                assert!((got.du[3 * i + k] - d.du[k]).abs() < 1e-12, "{p:?}");
                assert!((got.dv[3 * i + k] - d.dv[k]).abs() < 1e-12, "{p:?}");
            }
        }
    }

    /// A channel of 5 components is evaluated 3 at a time: each component is the same as
    /// in a channel of its own.
    #[test]
    fn wide_channels_are_their_components() {
        let m = grid(5);
        let options = Options {
            face_varying: FaceVaryingInterpolation::CornersOnly,
            ..Options::default()
        };
        let wide = FaceVaryingSurface::new(&m, options, 0).unwrap();
        assert_eq!(wide.dim(), 5);
        let ps = points(&m);
        let all = wide.eval_many(&ps).unwrap();
        for k in 0..5 {
            let ch = &m.face_varying[0];
            let values = (0..ch.num_values()).map(|i| ch.value(i)[k]).collect();
            let mut one = m.clone();
            one.face_varying =
                vec![FaceVarying::new("c", 1, values, ch.indices().to_vec()).unwrap()];
            let single = FaceVaryingSurface::new(&one, options, 0)
                .unwrap()
                .eval_many(&ps)
                .unwrap();
            for i in 0..ps.len() {
                assert!((all.value[5 * i + k] - single.value[i]).abs() < 1e-14);
                assert!((all.du[5 * i + k] - single.du[i]).abs() < 1e-12);
            }
        }
    }

    /// Mode `all` is bilinear per (sub-)face: on sub-face `j` of the triangle, corner `j`
    /// at `(0, 0)`, the midpoint of edge `j` at `(1, 0)`, the centroid at `(1, 1)`; its
    /// derivatives are finite differences of its values.
    #[test]
    fn linear_channels_are_bilinear_per_subface() {
        let m = grid(3);
        let options = Options::default();
        assert_eq!(options.face_varying, FaceVaryingInterpolation::All);
        let uv = FaceVaryingSurface::new(&m, options, 0).unwrap();
        let tri = m.num_faces() as u32 - 2;
        let c = m.face(tri as usize).to_vec();
        let pos = |i: u32| m.positions()[i as usize];
        for j in 0..3u32 {
            let at = |u: f64, v: f64| {
                let p = SurfacePoint {
                    face: tri,
                    subface: j,
                    u,
                    v,
                };
                uv.eval_point(p).unwrap()
            };
            let (a, b) = (pos(c[j as usize]), pos(c[(j as usize + 1) % 3]));
            let centre: Vec<f64> = (0..3)
                .map(|k| c.iter().map(|&i| pos(i)[k]).sum::<f64>() / 3.0)
                .collect();
            for k in 0..3 {
                assert!((at(0.0, 0.0).value[k] - a[k]).abs() < 1e-15);
                assert!((at(1.0, 0.0).value[k] - 0.5 * (a[k] + b[k])).abs() < 1e-15);
                assert!((at(1.0, 1.0).value[k] - centre[k]).abs() < 1e-15);
            }
            let (h, x) = (1e-6, at(0.4, 0.3));
            let (xu, xv) = (at(0.4 + h, 0.3), at(0.4, 0.3 + h));
            for k in 0..3 {
                assert!(((xu.value[k] - x.value[k]) / h - x.du[k]).abs() < 1e-6);
                assert!(((xv.value[k] - x.value[k]) / h - x.dv[k]).abs() < 1e-6);
            }
        }
    }

    /// Loop and NURSS have no face-varying limit here; a missing channel is named.
    #[test]
    fn unsupported_schemes_and_missing_channels_are_errors() {
        let m = grid(3);
        for scheme in [Scheme::Loop, Scheme::Nurss] {
            let e = FaceVaryingSurface::for_scheme(&m, scheme, Options::default(), 0);
            assert!(matches!(e, Err(FaceVaryingError::Unsupported { .. })));
        }
        let e = FaceVaryingSurface::new(&m, Options::default(), 1);
        assert!(matches!(
            e,
            Err(FaceVaryingError::NoSuchChannel {
                channel: 1,
                count: 1
            })
        ));
    }
}
