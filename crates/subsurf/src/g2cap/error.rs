//! Typed errors of the G2 cap construction.

use crate::limit::EvalError;
use crate::mesh::MeshError;

/// Why a G2 cap or surface could not be built or evaluated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum G2Error {
    /// The input mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Evaluation of the Catmull-Clark surface failed (or a point is outside the domain).
    #[error(transparent)]
    Eval(#[from] EvalError),
    /// G2 caps are built on the Catmull-Clark surface or the adjustable scheme's
    /// ([`G2SurfaceOptions::scheme`](super::G2SurfaceOptions::scheme)), not on this one.
    #[error("G2 caps are built on catmull-clark or adjustable surfaces, not on {0} ones")]
    Scheme(&'static str),
    /// A cap needs at least 3 patches and at most [`super::MAX_CAP_VALENCE`].
    #[error("valence {valence} is outside the supported range 3..={max}")]
    Valence {
        /// The requested valence.
        valence: usize,
        /// The largest supported valence.
        max: usize,
    },
    /// The outer data of a cap does not have one entry per patch.
    #[error("a cap of valence {valence} needs {valence} outer patch pairs, got {got}")]
    OuterCount {
        /// Valence.
        valence: usize,
        /// Number of entries given.
        got: usize,
    },
    /// A patch next to the cap of `vertex` is not a single bicubic polynomial (the
    /// extraordinary vertex is not isolated, or a crease or boundary is too close).
    #[error("the surface next to the cap of vertex {vertex} (face {face}) is not bicubic: fit error {error:e}")]
    NotBicubic {
        /// The extraordinary vertex (or face, for the centre of an n-gon: see `face`).
        vertex: usize,
        /// The input face holding the neighbour patch.
        face: usize,
        /// Largest misfit of the bicubic interpolant, relative to the patch size.
        error: f64,
    },
    /// The linear G2 constraints could not be met (should not happen: the transitions are
    /// consistent by construction; reported rather than returning a non-G2 surface).
    #[error(
        "the G2 constraints of a valence-{valence} cap are inconsistent (residual {residual:e})"
    )]
    Inconsistent {
        /// Valence.
        valence: usize,
        /// Largest constraint residual, relative to the size of the control net.
        residual: f64,
    },
    /// A cap patch index is out of range.
    #[error("cap {cap} has no patch {patch}")]
    NoSuchPatch {
        /// Cap index.
        cap: usize,
        /// Patch index.
        patch: usize,
    },
    /// The limit surface would exceed the memory limit of
    /// [`G2Surface::new`](super::G2Surface::new) with [`G2SurfaceOptions::max_memory`](super::G2SurfaceOptions::max_memory).
    #[error(transparent)]
    TooLarge(crate::limit::BuildError),
    /// A tessellation rate of 0, or one whose output would not fit 32-bit indices.
    #[error("cannot tessellate at rate {rate}: {reason}")]
    Rate {
        /// The requested rate.
        rate: u32,
        /// Why.
        reason: &'static str,
    },
}
