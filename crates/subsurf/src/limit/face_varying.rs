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
//!    [`BoundaryInterpolation::EdgeAndCorner`](crate::mesh::BoundaryInterpolation::EdgeAndCorner). Otherwise its sharpness is `v`'s explicit
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
//! # Schemes
//! NURSS: [`FaceVaryingSurface::nurss`], the same value mesh's non-uniform surface (built a
//! layer above, from [`NurssSurface`](crate::nonuniform::NurssSurface)). Loop
//! ([`FaceVaryingSurface::for_scheme`]): the value mesh's Loop limit ([`LoopSurface`]), each
//! face a triangle with the triangle's parameterisation; in the linear mode the value is
//! linear on each triangle, `(1 − u − v) a + u b + v c` (`Bfr::Surface`'s linear triangle). The adjustable scheme's limit is
//! the Catmull-Clark limit of its refined mesh, face-varying channels included: evaluate the
//! channel of the refined mesh ([`crate::MixedSurface::refined_point`] maps the points).

use std::sync::Arc;

use rayon::prelude::*;

use super::bilinear_surface::corner_weights;
use super::{Domain, EvalError, LimitSurface, LoopSurface, Order, Surface, SurfacePoint};
use crate::mesh::{
    FaceVarying, FaceVaryingInterpolation, MeshError, Options, PolyMesh, Topology, ValueMesh,
};
use crate::refine::nurss::NurssError;
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
    /// The channel's value mesh has bad knot tags or semi-sharp creases with NURSS
    /// ([`FaceVaryingSurface::nurss`]).
    #[error(transparent)]
    Nurss(#[from] NurssError),
    /// The scheme has no face-varying limit here.
    #[error("{}", unsupported(scheme))]
    Unsupported {
        /// The scheme's name.
        scheme: &'static str,
    },
}

/// The message of [`FaceVaryingError::Unsupported`].
fn unsupported(scheme: &str) -> String {
    if scheme == crate::scheme::Scheme::Nurss.name() {
        "the limit of face-varying data with the nurss scheme is FaceVaryingSurface::nurss's (it \
         reads the knot intervals)"
            .to_string()
    } else {
        format!("the limit of face-varying data is not available with the {scheme} scheme")
    }
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
    /// Loop: every face is one triangle, linear in `(u, v)`; else bilinear per (sub-)face.
    triangles: bool,
}

#[derive(Clone)]
enum Kind {
    /// [`FaceVaryingInterpolation::All`]: bilinear on every (sub-)face.
    Linear(Linear),
    /// The value mesh's limit surface, per 3 components: [`LimitSurface`]s, or the NURSS
    /// surfaces of [`FaceVaryingSurface::nurss`].
    Smooth(Vec<Arc<dyn Surface + Send + Sync>>),
}

impl std::fmt::Debug for Kind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Kind::Linear(l) => f.debug_tuple("Linear").field(l).finish(),
            Kind::Smooth(s) => write!(f, "Smooth({} surfaces)", s.len()),
        }
    }
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
        Self::build(mesh, options, channel, false)
    }

    /// [`new`](Self::new) with Catmull-Clark's surface of the value mesh, or with `triangles`
    /// Loop's ([`LoopSurface`]; every face must be a triangle).
    fn build(
        mesh: &PolyMesh,
        options: Options,
        channel: usize,
        triangles: bool,
    ) -> Result<Self, FaceVaryingError> {
        mesh.validate()?;
        if triangles {
            crate::refine::check_triangles(mesh)?;
        }
        let ch = mesh
            .face_varying
            .get(channel)
            .ok_or(FaceVaryingError::NoSuchChannel {
                channel,
                count: mesh.face_varying.len(),
            })?;
        let (t, _) = Topology::from_mesh(mesh, &options)?;
        if options.face_varying == FaceVaryingInterpolation::All {
            let mut linear = Self::linear(&t, ch);
            if let Kind::Linear(l) = &mut linear.kind {
                l.triangles = triangles;
            }
            return Ok(linear);
        }
        let explicit = ValueMesh::explicit_sharpness(mesh);
        let vm = ValueMesh::build(&t, &options, ch.indices(), &explicit);
        let dim = ch.dim();
        let value_options = ValueMesh::options(&options);
        if triangles {
            let surfaces = (0..dim.div_ceil(3))
                .map(|chunk| {
                    let m = vm.polymesh(vm.points(ch, chunk))?;
                    let s = LoopSurface::new(&m, value_options)?;
                    Ok(Arc::new(s) as Arc<dyn Surface + Send + Sync>)
                })
                .collect::<Result<_, FaceVaryingError>>()?;
            return Ok(Self::smooth(dim, surfaces));
        }
        let mut surfaces = Vec::new();
        for chunk in 0..dim.div_ceil(3) {
            let points = vm.points(ch, chunk);
            match surfaces.first() {
                None => {
                    surfaces.push(LimitSurface::new(vm.polymesh(points)?, value_options)?);
                }
                Some(first) => {
                    let mut s: LimitSurface = first.clone();
                    s.set_positions(&points)?;
                    surfaces.push(s);
                }
            }
        }
        let surfaces = (surfaces.into_iter())
            .map(|s| Arc::new(s) as Arc<dyn Surface + Send + Sync>)
            .collect();
        Ok(Self::smooth(dim, surfaces))
    }

    /// A channel of `dim` components whose value mesh's surfaces are `surfaces`, one per
    /// 3 components (the last one's extra components ignored).
    pub(crate) fn smooth(dim: usize, surfaces: Vec<Arc<dyn Surface + Send + Sync>>) -> Self {
        Self {
            dim,
            kind: Kind::Smooth(surfaces),
        }
    }

    /// [`FaceVaryingSurface::new`] for `scheme`: Catmull-Clark, Loop (the value mesh's
    /// [`LoopSurface`], see the module docs), and bilinear (whose face-varying limit is
    /// linear in every mode, as OpenSubdiv's, on every face of
    /// [`BilinearSurface`](super::BilinearSurface): boundary mode `None` makes no holes for
    /// this scheme); the adjustable scheme through its refined mesh (see the module docs);
    /// NURSS with [`FaceVaryingSurface::nurss`].
    ///
    /// # Errors
    /// [`FaceVaryingError::Unsupported`] for NURSS (built a layer above, its message says by
    /// what) and the adjustable scheme (whose channels are evaluated on the refined mesh),
    /// [`FaceVaryingError::Mesh`] naming a face that is not a triangle with Loop, else as
    /// [`FaceVaryingSurface::new`].
    pub fn for_scheme(
        mesh: &PolyMesh,
        scheme: Scheme,
        options: Options,
        channel: usize,
    ) -> Result<Self, FaceVaryingError> {
        match scheme {
            Scheme::CatmullClark => Self::new(mesh, options, channel),
            Scheme::Loop => Self::build(mesh, options, channel, true),
            Scheme::Bilinear => {
                // Linear, with the scheme's holes: the tagged ones only, boundary mode
                // `None` making none (as `BilinearSurface`).
                let linear = Options {
                    face_varying: FaceVaryingInterpolation::All,
                    ..crate::scheme::Bilinear::topology_options(&options)
                };
                Self::new(mesh, linear, channel)
            }
            _ => Err(FaceVaryingError::Unsupported {
                scheme: scheme.name(),
            }),
        }
    }

    /// The linear channel `ch` ([`FaceVaryingInterpolation::All`]) of a mesh of topology
    /// `t`: bilinear on every (sub-)face.
    pub(crate) fn linear(t: &Topology, ch: &FaceVarying) -> Self {
        Self {
            dim: ch.dim(),
            kind: Kind::Linear(Linear {
                dim: ch.dim(),
                face_offsets: t.face_offsets.clone(),
                indices: ch.indices().to_vec(),
                values: ch.values().to_vec(),
                holes: (0..t.num_faces()).map(|f| t.is_hole(f)).collect(),
                triangles: false,
            }),
        }
    }

    /// Components per value.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The parameter domain of face `f` (see [`Surface::domain`]): a triangle with Loop,
    /// else the unit square.
    pub fn domain(&self, f: usize) -> Domain {
        match &self.kind {
            Kind::Linear(l) if l.triangles => Domain::Triangle,
            Kind::Linear(_) => Domain::Quad,
            Kind::Smooth(s) => s.first().map_or(Domain::Quad, |s| s.domain(f)),
        }
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
                let mut res = vec![Ok(super::Derivatives::default()); points.len()];
                for (chunk, s) in surfaces.iter().enumerate() {
                    s.evaluate_many(points, Order::First, &mut res);
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
            triangles,
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
        if *triangles {
            return self.eval_triangle(p, corners, (val, du, dv));
        }
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
        // The bilinear patch of the quad, or of sub-face `j` of an n-gon (corner `j`, the
        // midpoints of edges `j` and `j - 1`, the centroid), as weights on the corners.
        val.fill(0.0);
        du.fill(0.0);
        dv.fill(0.0);
        corner_weights(n, p.subface as usize, p.u, p.v, |c, w| {
            for (k, &x) in value(c).iter().enumerate() {
                val[k] += w[0] * x;
                du[k] += w[1] * x;
                dv[k] += w[2] * x;
            }
        });
        Ok(())
    }

    /// The linear value on a triangle `corners` (Loop): `(1 − u − v) a + u b + v c`.
    fn eval_triangle(
        &self,
        p: SurfacePoint,
        corners: &[u32],
        (val, du, dv): (&mut [f64], &mut [f64], &mut [f64]),
    ) -> Result<(), EvalError> {
        if p.subface != 0 {
            return Err(EvalError::NoSuchSubface {
                face: p.face,
                subface: p.subface,
                size: 1,
            });
        }
        if !super::loop_surface::in_triangle(p.u, p.v) {
            return Err(EvalError::OutsideTriangle { u: p.u, v: p.v });
        }
        if self.holes[p.face as usize] {
            return Err(EvalError::Hole { face: p.face });
        }
        let dim = self.dim;
        let value = |c: usize| &self.values[dim * corners[c] as usize..][..dim];
        let (a, b, c) = (value(0), value(1), value(2));
        for k in 0..dim {
            val[k] = (1.0 - p.u - p.v) * a[k] + p.u * b[k] + p.v * c[k];
            du[k] = b[k] - a[k];
            dv[k] = c[k] - a[k];
        }
        Ok(())
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

    /// NURSS's face-varying limit is built a layer above ([`FaceVaryingSurface::nurss`]);
    /// Loop's needs triangles; a missing channel is named.
    #[test]
    fn unsupported_schemes_and_missing_channels_are_errors() {
        let m = grid(3);
        let e = FaceVaryingSurface::for_scheme(&m, Scheme::Nurss, Options::default(), 0);
        assert!(matches!(e, Err(FaceVaryingError::Unsupported { .. })));
        let e = FaceVaryingSurface::for_scheme(&m, Scheme::Loop, Options::default(), 0);
        assert!(matches!(
            e,
            Err(FaceVaryingError::Mesh(MeshError::NotTriangle {
                face: 0,
                ..
            }))
        ));
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
