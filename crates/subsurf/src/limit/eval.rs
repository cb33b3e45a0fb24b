//! One vocabulary for every surface over the faces of a control mesh: the exact limit
//! surface, the mixed (shape-adjustable) surface and the G2 surface are evaluated the
//! same way, so that drawing, tessellating and comparing take any of them.

use super::{Derivatives, EvalError, LimitSurface, SurfacePoint};

/// A parametric surface over the faces of a control mesh, addressed as
/// [`LimitSurface`] addresses its own: a point is a face (a sub-face of a non-quad, see
/// [`Parameterization`](super::Parameterization)) and `(u, v)` in `[0, 1]²`.
pub trait Surface: Sync {
    /// Position and first and second derivatives at `p`.
    ///
    /// # Errors
    /// As [`LimitSurface::eval_point`]: a face that does not exist, a parameter outside
    /// `[0, 1]²`, a face without a surface (a hole).
    fn evaluate(&self, p: SurfacePoint) -> Result<Derivatives, EvalError>;
}

impl Surface for LimitSurface {
    fn evaluate(&self, p: SurfacePoint) -> Result<Derivatives, EvalError> {
        self.eval_point(p)
    }
}
