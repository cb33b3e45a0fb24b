//! The errors of refinement, whatever the scheme.

use crate::mesh::MeshError;
use crate::refine::nurss::NurssError;

/// Errors of refinement: [`subdivide`](fn@crate::subdivide),
/// [`RefinePlan::new`](super::RefinePlan::new), [`Reposer::new`](crate::Reposer::new).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Error {
    /// The input mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The requested level would need more memory than allowed.
    #[error("refining to level {levels} needs about {}, more than the limit of {}; use a lower level", ByteSize(*estimate), ByteSize(*limit))]
    TooLarge {
        /// Requested level.
        levels: u32,
        /// Estimated bytes.
        estimate: u64,
        /// Allowed bytes.
        limit: u64,
    },
    /// Non-uniform refinement ([`Scheme::Nurss`](crate::scheme::Scheme::Nurss)) of the mesh failed: a bad knot tag, a
    /// semi-sharp crease.
    #[error(transparent)]
    Nurss(#[from] NurssError),
    /// The operation is not available for this scheme (e.g. moving to the limit with Loop).
    #[error("{what} is not available for the {scheme} scheme")]
    Unsupported {
        /// The operation (`"moving to the limit"`, `"building a re-posing plan"`).
        what: &'static str,
        /// The scheme's name ([`Scheme::name`](crate::scheme::Scheme::name)).
        scheme: &'static str,
    },
}

/// A byte count as messages give it: MiB rounded up, or KiB (rounded up) below 1 MiB.
struct ByteSize(u64);

impl std::fmt::Display for ByteSize {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.0 < 1 << 20 {
            write!(f, "{} KiB", self.0.div_ceil(1 << 10))
        } else {
            write!(f, "{} MiB", self.0.div_ceil(1 << 20))
        }
    }
}
