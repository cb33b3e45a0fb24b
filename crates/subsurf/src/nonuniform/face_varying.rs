//! The limit of face-varying channels (texture coordinates) under NURSS: at the vertices of
//! a refined level ([`Nurss::face_varying_limit`]) and anywhere on a face
//! ([`FaceVaryingSurface::nurss`]). A channel is the NURSS surface of its value mesh
//! (`refine::nurss::face_varying` has the definition and why), so its limit is that
//! surface's: limit points by [`Nurss::limit_points`] of the value level, evaluation by
//! [`NurssSurface`] of the value mesh.

use std::sync::Arc;

use super::{vertex_weights, Nurss, NurssSurface};
use crate::limit::{FaceVaryingError, FaceVaryingSurface, LimitSurface, Surface};
use crate::mesh::{FaceVarying, FaceVaryingInterpolation, Options, PolyMesh};
use crate::refine::nurss::ValueChannel;

impl Nurss {
    /// The face-varying channels of the current level moved to their limit, as
    /// [`to_mesh`](Self::to_mesh) writes them (faces written with `keep_holes`): a smooth
    /// channel's values are the limit points of its value level ([`Nurss::limit_points`],
    /// exact as there), a linear one's ([`FaceVaryingInterpolation::All`]) stay, as for
    /// Catmull-Clark (OpenSubdiv's `PrimvarRefiner::LimitFaceVarying`).
    pub(crate) fn face_varying_limit(&self, keep_holes: bool) -> Vec<FaceVarying> {
        let limit = |ch: &ValueChannel| {
            let mut chunks = vec![ch.level.limit_points()];
            for extra in &ch.extra {
                let mut level = ch.level.clone();
                level.points.clone_from(extra);
                chunks.push(level.limit_points());
            }
            ch.values(&chunks)
        };
        (self.face_varying).channels(&self.topology, keep_holes, Some(&limit))
    }
}

impl FaceVaryingSurface {
    /// The limit of channel `channel` of `mesh` under NURSS (non-uniform Catmull-Clark,
    /// Sederberg, Zheng, Sewell & Sabin, "Non-uniform recursive subdivision surfaces",
    /// SIGGRAPH 1998) with the mesh's knot tags ([`PolyMesh::knots`]) and `options` (whose
    /// [`Options::face_varying`] is the mode): the [`NurssSurface`] of the channel's value
    /// mesh (the value mesh of [`FaceVaryingSurface::new`], each edge with the interval of
    /// the mesh edge it lies on, each face side the mesh's, each vertex the weight of the
    /// mesh vertex it lies on; see docs/nurss.md, "Texture coordinates"). It is exact where
    /// that surface is: on faces whose value mesh around them is a regular grid with
    /// tensor-product intervals, and on faces with equal intervals and weights around them
    /// (Catmull-Clark's limit of the value mesh, which is [`FaceVaryingSurface::new`]'s).
    /// It is the surface of the channel as given: the limit points of the base level.
    /// (Refined levels take the mesh's weights on every level, see [`Nurss::new`]: next to a
    /// seam of a rational mesh whose weights vary there their limits differ from it a
    /// little.)
    /// Elsewhere — next to a seam, a boundary or an extraordinary vertex with unequal
    /// intervals — evaluation fails with [`EvalError::NotExact`](crate::limit::EvalError::NotExact)
    /// naming the face; the limit at the vertices of a refined level is exact everywhere
    /// ([`crate::subdivide`](fn@crate::subdivide) with `limit`). In mode `all` the channel is
    /// linear, as [`FaceVaryingSurface::new`]'s, whatever the intervals.
    ///
    /// # Errors
    /// [`FaceVaryingError::NoSuchChannel`]; [`FaceVaryingError::Nurss`] for bad knot tags or
    /// semi-sharp creases; [`FaceVaryingError::Mesh`] for an invalid mesh.
    ///
    /// ```
    /// use subsurf::limit::{FaceVaryingSurface, SurfacePoint};
    /// use subsurf::mesh::{EdgeInterval, FaceVarying, FaceVaryingInterpolation, Options, PolyMesh};
    /// // A 5 × 5 grid whose middle column of edges has interval 3, with uv = (x, y).
    /// let mut pos = Vec::new();
    /// for j in 0..6 { for i in 0..6 { pos.push([i as f64, j as f64, 0.0]); } }
    /// let mut faces = Vec::new();
    /// for j in 0..5u32 { for i in 0..5u32 { let v = 6 * j + i; faces.push([v, v + 1, v + 7, v + 6]); } }
    /// let mut m = PolyMesh::from_faces(pos.clone(), &faces)?;
    /// for j in 0..6u32 {
    ///     m.knots.intervals.push(EdgeInterval { v0: 6 * j + 2, v1: 6 * j + 3, interval: 3.0 });
    /// }
    /// let uv = pos.iter().flat_map(|p| [p[0], p[1]]).collect();
    /// m.face_varying.push(FaceVarying::new("uv", 2, uv, m.face_verts().to_vec())?);
    /// let o = Options { face_varying: FaceVaryingInterpolation::None, ..Options::default() };
    /// let s = FaceVaryingSurface::nurss(&m, o, 0)?;
    /// let x = s.eval_point(SurfacePoint { face: 12, subface: 0, u: 0.25, v: 0.5 })?;
    /// // The middle face is a span of a non-uniform B-spline: uv = (x, y) of the surface.
    /// let p = subsurf::nonuniform::NurssSurface::new(&m, &o)?
    ///     .eval_point(SurfacePoint { face: 12, subface: 0, u: 0.25, v: 0.5 })?.p;
    /// assert!((x.value[0] - p[0]).abs() < 1e-12 && (x.value[1] - p[1]).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn nurss(
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
        let base = Nurss::vertices_only(mesh, &options)?;
        if options.face_varying == FaceVaryingInterpolation::All {
            return Ok(Self::linear(base.topology(), ch));
        }
        let weights = vertex_weights(mesh);
        let (value, vm) = ValueChannel::new(mesh, &base, &weights, ch)?;
        let value_options = *value.level.options();
        let mut surfaces: Vec<Arc<dyn Surface + Send + Sync>> = Vec::new();
        for chunk in 0..ch.dim().div_ceil(3) {
            let mut level = value.level.clone();
            if chunk > 0 {
                level.points.clone_from(&value.extra[chunk - 1]);
            }
            let pm = vm.polymesh(vm.points(ch, chunk))?;
            let s = NurssSurface::from_level(&level, &pm, |m| {
                LimitSurface::new(m, value_options).map_err(FaceVaryingError::from)
            })?;
            surfaces.push(Arc::new(s));
        }
        Ok(Self::smooth(ch.dim(), surfaces))
    }
}
