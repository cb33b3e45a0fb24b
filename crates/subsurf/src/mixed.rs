//! Mixed subdivision ([Tang et al. 2017], "混合细分"): `k` steps of the shape-adjustable scheme with
//! parameter `c` ([`crate::scheme::adjustable`]), then Catmull-Clark to the limit.
//!
//! The limit of mixed subdivision is the Catmull-Clark limit surface of the control mesh
//! refined `k` times with `c`. [`MixedSurface`] builds exactly that — [`subdivide`](fn@crate::subdivide) with [`Scheme::Adjustable`](crate::Scheme::Adjustable)
//! to level `k`, then a [`LimitSurface`] on the result — so it is exact everywhere, and on
//! regular regions each patch is the bicubic B-spline patch of the `c`-refined net,
//! `P(u, v) = U·M·(S G Sᵀ)·Mᵀ·Vᵀ` with `M` the B-spline matrix and `S` the `c`-scheme's
//! local refinement matrix.
//!
//! # Faces of the input and faces of the refined mesh
//! Refinement numbers child faces from their parents (see `ARCHITECTURE.md`): after the
//! first step, corner `j` of input face `f` is face `o_f + j` (`o_f` the offset of `f` in
//! the input's face-vertex list); after that, corner `j` of face `g` (a quad) is face
//! `4g + j`, and corner `j` of a quad is its quadrant `j` in the `(u, v)` order
//! `[0,½]×[0,½]`, `[½,1]×[0,½]`, `[½,1]²`, `[0,½]×[½,1]`, with the parametric directions
//! kept. So a point `(u, v)` of an input quad lies, after `k` steps, in the refined face
//! reached by taking quadrants `k` times, at the parameter scaled by `2^k` (derivatives by
//! `2^k`, second derivatives by `4^k`); a sub-face `j` of an input `n`-gon (the
//! [`LimitSurface`] convention) is the level-1 face `o_f + j`, followed by `k − 1`
//! quadrant steps. [`MixedSurface::eval_point`] does this mapping
//! ([`MixedSurface::refined_point`] exposes it).

use crate::limit::{Derivatives, EvalError, LimitSurface, Order, SurfacePoint};
use crate::mesh::MeshError;
use crate::mesh::{Options, PolyMesh};
use crate::refine::uniform::{refine_mesh, Steps};
use crate::scheme::adjustable::Mixed;

/// The exact limit surface of mixed subdivision, evaluable at `(input face, u, v)` with
/// the parametrisation of [`LimitSurface`] on the *input* mesh (see the module docs).
///
/// ```
/// use subsurf::mesh::{Options, PolyMesh};
/// use subsurf::scheme::Adjustable;
/// use subsurf::{Mixed, MixedSurface};
///
/// let p = vec![
///     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
///     [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
/// ];
/// let f = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
/// let cube = PolyMesh::from_faces(p, &f)?;
/// let tight = Mixed { scheme: Adjustable::new(0.2)?, steps: 2 };
/// let s = MixedSurface::new(&cube, Options::default(), tight)?;
/// let top = s.eval(1, 0.5, 0.5)?;
/// // c < ½ keeps the surface closer to the control mesh than Catmull-Clark (z = 0.8333…).
/// assert!(top.p[2] > 0.84 && top.p[2] < 1.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct MixedSurface {
    mixed: Mixed,
    refined: PolyMesh,
    surface: LimitSurface,
    /// Input face-vertex offsets (the level-1 index of each face's first child).
    offsets: Vec<u32>,
}

impl MixedSurface {
    /// Refines `mesh` `mixed.steps` times with the adjustable scheme (holes kept, so that
    /// face numbers follow the rule of the module docs) and builds the Catmull-Clark limit
    /// surface of the result.
    ///
    /// # Errors
    /// [`MeshError`] for an invalid mesh, or when `mixed.steps` is so large (e.g.
    /// [`Mixed::all`]'s `u32::MAX`) that the refined mesh would not fit in 32-bit indices.
    pub fn new(mesh: &PolyMesh, options: Options, mixed: Mixed) -> Result<Self, MeshError> {
        let refined = refine_mesh(mesh, &options, Steps::Family(mixed), mixed.steps, true)?;
        let surface = LimitSurface::new(&refined, options)?;
        Ok(Self {
            mixed,
            refined,
            surface,
            offsets: mesh.face_offsets().to_vec(),
        })
    }

    /// The mixed surface of `mesh` from its control mesh `refined`, refined as
    /// [`new`](Self::new) refines it (`mixed.steps` adjustable steps, holes kept: e.g. by
    /// [`subdivide`](fn@crate::subdivide) with [`Scheme::Adjustable`](crate::Scheme::Adjustable)), and `surface`, the Catmull-Clark limit surface of `refined`
    /// (built by the caller, e.g. within a memory limit:
    /// [`LimitSurface::builder`](crate::limit::LimitSurface::builder)).
    ///
    /// # Errors
    /// [`MeshError::NotRefined`] when `refined` or `surface` has another number of faces than
    /// `mixed.steps` steps of `mesh` make.
    pub fn from_refined(
        mesh: &PolyMesh,
        refined: PolyMesh,
        surface: LimitSurface,
        mixed: Mixed,
    ) -> Result<Self, MeshError> {
        let expected = match mixed.steps {
            0 => mesh.num_faces() as u64,
            k => (mesh.face_verts().len() as u64)
                .checked_shl(2 * (k - 1))
                .unwrap_or(u64::MAX),
        };
        for found in [refined.num_faces(), surface.num_faces()] {
            if found as u64 != expected {
                return Err(MeshError::NotRefined { expected, found });
            }
        }
        Ok(Self {
            mixed,
            refined,
            surface,
            offsets: mesh.face_offsets().to_vec(),
        })
    }

    /// The parameters.
    pub fn mixed(&self) -> Mixed {
        self.mixed
    }

    /// The control mesh after the adjustable steps (holes included, tagged).
    pub fn refined_mesh(&self) -> &PolyMesh {
        &self.refined
    }

    /// The Catmull-Clark limit surface of [`refined_mesh`](Self::refined_mesh).
    pub fn limit_surface(&self) -> &LimitSurface {
        &self.surface
    }

    /// Number of input faces.
    pub fn num_faces(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// The point of the refined mesh's surface that is `p` of the input, and the factor
    /// `2^d` by which its first derivatives are scaled back (`d` the number of quadrant
    /// steps taken).
    ///
    /// # Errors
    /// [`EvalError::NoSuchFace`], [`EvalError::NoSuchSubface`] or
    /// [`EvalError::BadParameter`] for a point that is not on the input mesh.
    pub fn refined_point(&self, p: SurfacePoint) -> Result<(SurfacePoint, f64), EvalError> {
        let f = p.face as usize;
        if f >= self.num_faces() {
            return Err(EvalError::NoSuchFace {
                face: p.face,
                count: self.num_faces(),
            });
        }
        let size = (self.offsets[f + 1] - self.offsets[f]) as usize;
        let subfaces = if size == 4 { 1 } else { size };
        if p.subface as usize >= subfaces {
            return Err(EvalError::NoSuchSubface {
                face: p.face,
                subface: p.subface,
                size: subfaces,
            });
        }
        if !(0.0..=1.0).contains(&p.u) || !(0.0..=1.0).contains(&p.v) {
            return Err(EvalError::BadParameter { u: p.u, v: p.v });
        }
        if self.mixed.steps == 0 {
            return Ok((p, 1.0));
        }
        let (mut u, mut v) = (p.u, p.v);
        let mut scale = 1.0;
        let mut face = if size == 4 {
            let (q, s, t) = quadrant(u, v);
            (u, v, scale) = (s, t, 2.0);
            self.offsets[f] as u64 + q as u64
        } else {
            self.offsets[f] as u64 + p.subface as u64
        };
        for _ in 1..self.mixed.steps {
            let (q, s, t) = quadrant(u, v);
            (u, v) = (s, t);
            scale *= 2.0;
            face = 4 * face + q as u64;
        }
        // The face exists: `new` built the refined mesh, whose face count bounds it.
        Ok((
            SurfacePoint {
                face: face as u32,
                subface: 0,
                u,
                v,
            },
            scale,
        ))
    }

    /// Position and first and second derivatives with respect to the input face's
    /// `(u, v)` at `p`. At an extraordinary vertex `du`, `dv` are tangent directions, as in
    /// [`LimitSurface`].
    ///
    /// # Errors
    /// As [`refined_point`](Self::refined_point), and [`EvalError::Hole`] on a hole.
    pub fn eval_point(&self, p: SurfacePoint) -> Result<Derivatives, EvalError> {
        let (q, scale) = self.refined_point(p)?;
        match self.surface.eval_point(q) {
            Ok(d) => Ok(d.scaled(scale)),
            Err(EvalError::Hole { .. }) => Err(EvalError::Hole { face: p.face }),
            Err(e) => Err(e),
        }
    }

    /// [`eval_point`](Self::eval_point) of many points, computing the derivatives of
    /// `order` only, into `out` (resized to `points.len()`): the points mapped to the
    /// refined mesh's surface ([`refined_point`](Self::refined_point)) and evaluated there
    /// together ([`LimitSurface::eval_many_into`], which shares the work of consecutive
    /// points on one face).
    pub fn eval_many_into(
        &self,
        points: &[SurfacePoint],
        order: Order,
        out: &mut Vec<Result<Derivatives, EvalError>>,
    ) {
        let mapped: Vec<Result<(SurfacePoint, f64), EvalError>> =
            points.iter().map(|&p| self.refined_point(p)).collect();
        // Points not on the input mesh stand in as the first face's corner; their results
        // are replaced by their errors below.
        let stand_in = SurfacePoint {
            face: 0,
            subface: 0,
            u: 0.0,
            v: 0.0,
        };
        let refined: Vec<SurfacePoint> = (mapped.iter())
            .map(|m| m.as_ref().map_or(stand_in, |&(q, _)| q))
            .collect();
        self.surface.eval_many_into(&refined, order, out);
        for ((r, m), p) in out.iter_mut().zip(&mapped).zip(points) {
            match (m, r.as_mut()) {
                (Err(e), _) => *r = Err(e.clone()),
                (Ok((_, scale)), Ok(d)) => d.scale(*scale),
                (Ok(_), Err(EvalError::Hole { .. })) => *r = Err(EvalError::Hole { face: p.face }),
                (Ok(_), Err(_)) => {}
            }
        }
    }

    /// [`eval_point`](Self::eval_point) at `(u, v)` of quad `face` (sub-face 0 of a
    /// non-quad).
    pub fn eval(&self, face: u32, u: f64, v: f64) -> Result<Derivatives, EvalError> {
        self.eval_point(SurfacePoint {
            face,
            subface: 0,
            u,
            v,
        })
    }
}

/// Quadrant of `(u, v)` (0: `[0,½)×[0,½)`, 1: `[½,1]×[0,½)`, 2: `[½,1]²`,
/// 3: `[0,½)×[½,1]`) and the parameter within it.
fn quadrant(u: f64, v: f64) -> (usize, f64, f64) {
    match (u >= 0.5, v >= 0.5) {
        (false, false) => (0, 2.0 * u, 2.0 * v),
        (true, false) => (1, 2.0 * u - 1.0, 2.0 * v),
        (true, true) => (2, 2.0 * u - 1.0, 2.0 * v - 1.0),
        (false, true) => (3, 2.0 * u, 2.0 * v - 1.0),
    }
}

impl crate::limit::Surface for MixedSurface {
    fn num_faces(&self) -> usize {
        MixedSurface::num_faces(self)
    }

    fn num_subfaces(&self, f: usize) -> usize {
        match self.offsets.get(f..f + 2) {
            Some(&[a, b]) if b - a == 4 => 1,
            Some(&[a, b]) => (b - a) as usize,
            _ => 0,
        }
    }

    /// Whether the refined faces over face `f` have a surface: holes and the faces a
    /// boundary rule leaves out stay so through refinement, all children alike.
    fn has_surface(&self, f: usize) -> bool {
        let centre = SurfacePoint {
            face: f as u32,
            subface: 0,
            u: 0.5,
            v: 0.5,
        };
        self.refined_point(centre)
            .is_ok_and(|(q, _)| self.surface.has_surface(q.face as usize))
    }

    fn evaluate(&self, p: SurfacePoint) -> Result<Derivatives, EvalError> {
        self.eval_point(p)
    }
}
