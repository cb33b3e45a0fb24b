//! [`BilinearSurface`]: exact evaluation of the limit of bilinear subdivision (OpenSubdiv's
//! `Sdc::SCHEME_BILINEAR`, [`scheme::Bilinear`](crate::scheme::Bilinear)) at any `(face, u, v)`, with first and
//! second derivatives, as OpenSubdiv's `Bfr::Surface` evaluates it.
//!
//! # The surface
//! Bilinear subdivision splits every face as Catmull-Clark does and places the new points at
//! the face's centroid, the edges' midpoints and the vertices themselves, whatever the
//! sharpness: each refined quad lies on the bilinear patch of its parent, so the limit over a
//! quad `[v₀ v₁ v₂ v₃]` is that patch,
//!
//! `S(u, v) = (1 − u)(1 − v) v₀ + u(1 − v) v₁ + uv v₂ + (1 − u)v v₃`,
//!
//! `(0, 0)` at `v₀`, `u` toward `v₁`, `v` toward `v₃`, with `S_u = (1 − v)(v₁ − v₀) +
//! v(v₂ − v₃)`, `S_v = (1 − u)(v₃ − v₀) + u(v₂ − v₁)`, the twist `S_uv = v₀ − v₁ + v₂ − v₃`,
//! and `S_uu = S_vv = 0`. A face of `n ≠ 4` vertices has no domain of its own: its first
//! step gives `n` quads, and its limit is their bilinear patches, addressed as
//! [`LimitSurface`](super::LimitSurface) addresses the sub-faces of an `n`-gon
//! ([`Parameterization`](super::Parameterization)): sub-face `j` is the quad
//! `[vⱼ, (vⱼ + vⱼ₊₁)/2, c, (vⱼ₋₁ + vⱼ)/2]`, `c = (v₀ + … + vₙ₋₁)/n` the centroid, in its own
//! `(s, t) ∈ [0, 1]²` (derivatives by `s` and `t`; by `Bfr`'s face coordinates they are twice
//! these, [`Parameterization::derivative_scale`](super::Parameterization::derivative_scale)).
//!
//! This is `Bfr`'s "linear" surface (OpenSubdiv 3.5, `bfr/surface.cpp`:
//! `evalMultiLinearDerivs`, the sub-face `[j, N + 1 + j, N, N + 1 + (j − 1)]` of the face's
//! points followed by its centroid `N` and edge midpoints; `SurfaceFactory::assignLinearSurface`
//! for every face, since the scheme's neighbourhood is the face itself), checked point for
//! point against it (`tests/golden/bilinear_bfr/`).
//!
//! # Which faces have a surface
//! Every face but the holes ([`Tags::holes`](crate::mesh::Tags::holes)). Creases, corners
//! and the boundary mode do not move bilinear points, and
//! [`BoundaryInterpolation::None`](crate::mesh::BoundaryInterpolation::None) makes no face a
//! hole for this scheme: OpenSubdiv tags boundary faces as holes only for schemes whose
//! points depend on a neighbourhood (`Bfr::SurfaceFactory` rejects smooth boundaries only
//! for non-linear schemes, `_rejectSmoothBoundariesForLimit`; [`Bilinear::topology_options`]).
//! Non-manifold edges and vertices and faces with a repeated vertex are evaluated by the
//! same formula (the patch of a degenerate face is degenerate, never an error).
//!
//! # Cost
//! Nothing is analysed: the surface keeps the face lists, the holes and the points; a point
//! costs one pass over its face's vertices.

use rayon::prelude::*;

use super::{copy_positions, Derivatives, EvalError, Order, SurfacePoint};
use crate::mesh::{MeshError, PolyMesh, Topology};
use crate::scheme::Bilinear;

/// The limit surface of bilinear subdivision (see the module docs): the bilinear patch of
/// every quad and of every sub-face of another face.
///
/// ```
/// use subsurf::limit::BilinearSurface;
/// use subsurf::mesh::PolyMesh;
/// let p = vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 2.0, 1.0], [0.0, 2.0, 0.0]];
/// let quad = PolyMesh::from_faces(p, &[[0u32, 1, 2, 3]]).unwrap();
/// let s = BilinearSurface::new(&quad).unwrap();
/// let d = s.eval(0, 0.5, 0.5).unwrap();
/// // The centre is the average of the corners; the twist is v0 - v1 + v2 - v3.
/// assert_eq!(d.p, [1.0, 1.0, 0.25]);
/// assert_eq!(d.duv, [0.0, 0.0, 1.0]);
/// ```
#[derive(Clone, Debug)]
pub struct BilinearSurface {
    face_offsets: Vec<u32>,
    face_verts: Vec<u32>,
    holes: Vec<bool>,
    pos: Vec<[f64; 3]>,
}

impl BilinearSurface {
    /// The bilinear limit surface of `mesh`. No subdivision option changes it (module docs);
    /// the mesh's hole tags make faces without a surface.
    ///
    /// # Errors
    /// Any error of [`PolyMesh::validate`] or [`Topology::from_mesh`].
    pub fn new(mesh: &PolyMesh) -> Result<Self, MeshError> {
        mesh.validate()?;
        // The holes as refinement makes them for this scheme (only the tagged ones).
        let options = Bilinear::topology_options(&crate::mesh::Options::default());
        let (topo, _) = Topology::from_mesh(mesh, &options)?;
        Ok(Self {
            face_offsets: mesh.face_offsets().to_vec(),
            face_verts: mesh.face_verts().to_vec(),
            holes: (0..topo.num_faces()).map(|f| topo.is_hole(f)).collect(),
            pos: mesh.positions().to_vec(),
        })
    }

    /// Number of faces of the control mesh.
    pub fn num_faces(&self) -> usize {
        self.holes.len()
    }

    /// The vertices of face `f` (which must exist).
    fn face(&self, f: usize) -> &[u32] {
        &self.face_verts[self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize]
    }

    /// Number of sub-faces of face `f`: 1 for a quad, `n` for an `n`-gon, 0 if there is no
    /// such face (as [`LimitSurface::num_subfaces`](super::LimitSurface::num_subfaces)).
    pub fn num_subfaces(&self, f: usize) -> usize {
        match self.face_offsets.get(f + 1) {
            Some(_) => match self.face(f).len() {
                4 => 1,
                n => n,
            },
            None => 0,
        }
    }

    /// Whether face `f` exists and is not a hole.
    pub fn has_surface(&self, f: usize) -> bool {
        f < self.num_faces() && !self.holes[f]
    }

    /// The control points.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.pos
    }

    /// Replaces the control points (the same number, finite); nothing else is kept that
    /// depends on them, so re-posing costs the copy.
    ///
    /// # Errors
    /// [`EvalError::InvalidPositions`]: naming the first vertex that is not finite, or, when
    /// the number of points differs from the mesh's, the smaller of the two counts.
    pub fn set_positions(&mut self, pos: &[[f64; 3]]) -> Result<(), EvalError> {
        copy_positions(&mut self.pos, pos)
    }

    /// Position and first and second derivatives at `(u, v)` of quad `face` (sub-face 0 of
    /// a non-quad).
    ///
    /// # Errors
    /// As [`BilinearSurface::eval_point`].
    pub fn eval(&self, face: u32, u: f64, v: f64) -> Result<Derivatives, EvalError> {
        self.eval_point(SurfacePoint {
            face,
            subface: 0,
            u,
            v,
        })
    }

    /// Position and first and second derivatives at `p` (see the module docs).
    ///
    /// # Errors
    /// [`EvalError::NoSuchFace`], [`EvalError::NoSuchSubface`], [`EvalError::BadParameter`]
    /// for `(u, v)` outside `[0, 1]²` (or not finite), [`EvalError::Hole`].
    pub fn eval_point(&self, p: SurfacePoint) -> Result<Derivatives, EvalError> {
        self.check(p)?;
        let fv = self.face(p.face as usize);
        let mut d = Derivatives::default();
        corner_weights(fv.len(), p.subface as usize, p.u, p.v, |c, w| {
            let x = &self.pos[fv[c] as usize];
            for k in 0..3 {
                d.p[k] += w[0] * x[k];
                d.du[k] += w[1] * x[k];
                d.dv[k] += w[2] * x[k];
                d.duv[k] += w[3] * x[k];
            }
        });
        Ok(d)
    }

    /// [`eval_point`](Self::eval_point) at every point, in parallel; `order` is accepted
    /// for the [`Surface`](super::Surface) interface (the twist is always computed).
    pub fn eval_many(
        &self,
        points: &[SurfacePoint],
        order: Order,
    ) -> Vec<Result<Derivatives, EvalError>> {
        let mut out = vec![Ok(Derivatives::default()); points.len()];
        self.eval_many_to(points, order, &mut out);
        out
    }

    /// [`eval_many`](Self::eval_many) into `out` (one result per point).
    ///
    /// # Panics
    /// If `out.len() != points.len()`.
    pub fn eval_many_to(
        &self,
        points: &[SurfacePoint],
        _order: Order,
        out: &mut [Result<Derivatives, EvalError>],
    ) {
        assert_eq!(out.len(), points.len(), "one result per point");
        out.par_iter_mut()
            .zip(points.par_iter())
            .with_min_len(1024)
            .for_each(|(o, &p)| *o = self.eval_point(p));
    }

    /// The errors of point `p` (see [`eval_point`](Self::eval_point)), in
    /// [`LimitSurface`](super::LimitSurface)'s order.
    fn check(&self, p: SurfacePoint) -> Result<(), EvalError> {
        let f = p.face as usize;
        if f >= self.num_faces() {
            return Err(EvalError::NoSuchFace {
                face: p.face,
                count: self.num_faces(),
            });
        }
        let size = self.num_subfaces(f);
        if p.subface as usize >= size {
            return Err(EvalError::NoSuchSubface {
                face: p.face,
                subface: p.subface,
                size,
            });
        }
        if !(0.0..=1.0).contains(&p.u) || !(0.0..=1.0).contains(&p.v) {
            return Err(EvalError::BadParameter { u: p.u, v: p.v });
        }
        if self.holes[f] {
            return Err(EvalError::Hole { face: p.face });
        }
        Ok(())
    }
}

/// The bilinear patch at `(u, v)` of sub-face `sub` of a face of `n` corners (the face itself
/// when `n = 4`) as weights on the face's corners: `add(c, [w, w_u, w_v, w_uv])` for every
/// corner `c` in order, the weights of the position, its first derivatives and the twist
/// (module docs; `w_uu = w_vv = 0`).
///
/// The patch's corners `q₀ … q₃` have the bilinear weights `b = ((1 − u)(1 − v), u(1 − v),
/// uv, (1 − u)v)`; on a sub-face they are `q₀ = vⱼ`, `q₁ = (vⱼ + vⱼ₊₁)/2`, `q₂` the centroid
/// and `q₃ = (vⱼ₋₁ + vⱼ)/2`, so corner `j` weighs `b₀ + b₁/2 + b₃/2 + b₂/n`, corner `j + 1`
/// `b₁/2 + b₂/n`, corner `j − 1` `b₃/2 + b₂/n` and every other `b₂/n` (`Bfr`'s
/// `transformLinearQuadWeightsToStencil`, OpenSubdiv 3.5 `bfr/surface.cpp`). Shared by
/// [`BilinearSurface`] and the linear face-varying channels
/// ([`FaceVaryingSurface`](super::FaceVaryingSurface)).
pub(super) fn corner_weights(
    n: usize,
    sub: usize,
    u: f64,
    v: f64,
    mut add: impl FnMut(usize, [f64; 4]),
) {
    // Per patch corner: the weights of the position, `∂/∂u`, `∂/∂v` and `∂²/∂u∂v`.
    let q = [
        [(1.0 - u) * (1.0 - v), -(1.0 - v), -(1.0 - u), 1.0],
        [u * (1.0 - v), 1.0 - v, -u, -1.0],
        [u * v, v, u, 1.0],
        [(1.0 - u) * v, -v, 1.0 - u, -1.0],
    ];
    if n == 4 {
        q.iter().enumerate().for_each(|(c, &w)| add(c, w));
        return;
    }
    let inv_n = 1.0 / n as f64;
    let role = |f: fn(&[[f64; 4]; 4], usize, f64) -> f64| -> [f64; 4] {
        std::array::from_fn(|k| f(&q, k, inv_n))
    };
    // The weights of the four roles a corner plays: the sub-face's own, the next, the
    // previous, any other (contributing to the centroid only).
    let own = role(|q, k, i| q[0][k] + 0.5 * q[1][k] + 0.5 * q[3][k] + i * q[2][k]);
    let next = role(|q, k, i| 0.5 * q[1][k] + i * q[2][k]);
    let prev = role(|q, k, i| 0.5 * q[3][k] + i * q[2][k]);
    let other = role(|q, k, i| i * q[2][k]);
    let (after, before) = ((sub + 1) % n, (sub + n - 1) % n);
    for c in 0..n {
        add(
            c,
            if c == sub {
                own
            } else if c == after {
                next
            } else if c == before {
                prev
            } else {
                other
            },
        );
    }
}

#[cfg(test)]
#[path = "bilinear_surface_tests.rs"]
mod tests;
