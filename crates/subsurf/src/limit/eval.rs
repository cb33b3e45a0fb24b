//! One vocabulary for every surface over the faces of a control mesh: the exact limit
//! surface, the mixed (shape-adjustable) surface, the G2 surface, the sub-basis spline and
//! the NURSS surface are evaluated the same way, so that drawing, tessellating
//! ([`tessellate`](super::tessellate())) and comparing take any of them.

use super::{
    BilinearSurface, Derivatives, EvalError, LimitSurface, LoopSurface, Order, SurfacePoint,
};
use rayon::prelude::*;

/// The parameter domain of a face (of each of its sub-faces).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Domain {
    /// The unit square `(u, v) ∈ [0, 1]²` (Catmull-Clark and its relatives).
    #[default]
    Quad,
    /// The triangle `u, v ≥ 0, u + v ≤ 1`, `(0, 0)` at the face's first vertex, `u` toward
    /// the second, `v` toward the third (Loop; OpenSubdiv's `Bfr` parameterisation of a
    /// triangle).
    Triangle,
}

/// A parametric surface over the faces of a control mesh, addressed as
/// [`LimitSurface`] addresses its own: a point is a face (a sub-face of a non-quad, see
/// [`Parameterization`](super::Parameterization)) and `(u, v)` in its
/// [`domain`](Surface::domain), `[0, 1]²` or a triangle.
pub trait Surface: Sync {
    /// Number of faces of the control mesh.
    fn num_faces(&self) -> usize;

    /// Number of sub-faces of face `f`: 1 for a quad, `n` for an `n`-gon, 0 if there is no
    /// such face (see [`Parameterization`](super::Parameterization)).
    fn num_subfaces(&self, f: usize) -> usize;

    /// Whether face `f` exists and has a surface (it is not a hole, and not a face the
    /// surface leaves out).
    fn has_surface(&self, f: usize) -> bool;

    /// The parameter domain of face `f`'s sub-faces: the unit square unless the surface says
    /// otherwise ([`LoopSurface`]'s triangles, which [`tessellate`](super::tessellate())
    /// samples on triangular grids).
    fn domain(&self, f: usize) -> Domain {
        let _ = f;
        Domain::Quad
    }

    /// Position and first and second derivatives at `p`.
    ///
    /// # Errors
    /// As [`LimitSurface::eval_point`]: a face that does not exist, a parameter outside
    /// the face's [`domain`](Self::domain), a face without a surface (a hole).
    fn evaluate(&self, p: SurfacePoint) -> Result<Derivatives, EvalError>;

    /// [`evaluate`](Self::evaluate) at every point of `points` into `out` (one result per
    /// point), in parallel; `order` says which derivatives are needed (an implementation
    /// may compute more). The default evaluates each point on its own.
    ///
    /// # Panics
    /// If `out.len() != points.len()`.
    fn evaluate_many(
        &self,
        points: &[SurfacePoint],
        order: Order,
        out: &mut [Result<Derivatives, EvalError>],
    ) {
        let _ = order;
        assert_eq!(out.len(), points.len(), "one result per point");
        out.par_iter_mut()
            .zip(points.par_iter())
            .with_min_len(64)
            .for_each(|(o, &p)| *o = self.evaluate(p));
    }
}

/// The [`Surface`] methods that forward to a surface type's own of the same name.
macro_rules! forward_surface {
    ($t:ty) => {
        fn num_faces(&self) -> usize {
            <$t>::num_faces(self)
        }

        fn has_surface(&self, f: usize) -> bool {
            <$t>::has_surface(self, f)
        }

        fn evaluate(&self, p: SurfacePoint) -> Result<Derivatives, EvalError> {
            self.eval_point(p)
        }

        fn evaluate_many(
            &self,
            points: &[SurfacePoint],
            order: Order,
            out: &mut [Result<Derivatives, EvalError>],
        ) {
            self.eval_many_to(points, order, out);
        }
    };
}

impl Surface for LimitSurface {
    forward_surface!(LimitSurface);

    fn num_subfaces(&self, f: usize) -> usize {
        LimitSurface::num_subfaces(self, f)
    }
}

impl Surface for LoopSurface {
    forward_surface!(LoopSurface);

    /// 1 for every face (each triangle is one domain), 0 if there is no such face.
    fn num_subfaces(&self, f: usize) -> usize {
        usize::from(f < LoopSurface::num_faces(self))
    }

    fn domain(&self, _: usize) -> Domain {
        Domain::Triangle
    }
}

impl Surface for BilinearSurface {
    forward_surface!(BilinearSurface);

    fn num_subfaces(&self, f: usize) -> usize {
        BilinearSurface::num_subfaces(self, f)
    }
}
