//! Errors of the regularity check.

use crate::limit::EvalError;
use crate::mesh::MeshError;

/// Errors of [`check_regularity`](super::check_regularity).
#[derive(Debug, thiserror::Error)]
pub enum RegularityError {
    /// The mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The limit surface could not be evaluated at a sample.
    #[error("sampling the limit surface: {0}")]
    Eval(#[from] EvalError),
}
