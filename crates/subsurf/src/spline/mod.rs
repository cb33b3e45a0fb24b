//! A rational bicubic spline surface on irregular quad meshes from sub-basis functions
//! ([Sub-basis splines]: "a B-spline method on irregular meshes by decomposition and classification of
//! the uniform bicubic B-spline basis function").
//!
//! The uniform cubic B-spline `N_i` splits into three C1 pieces `B^{-1}, B^0, B^1`, each living on
//! two knot intervals; the tensor product `N_i(u)N_j(v)` splits into nine *sub-basis functions*,
//! each living on the four quads around one grid vertex: class 1 (centre), class 2 (edge) and
//! class 3 (corner). On a vertex of valence `n ≠ 4` each class is rebuilt as piecewise bicubic
//! Hermite patches on a star of `n` unit rhombi (`subbasis`), tabulated once per valence
//! (`table`). Each control point's basis function `W_i` is the sum of its `2n + 1` pieces, and
//! the surface `P = Σ (W_i / Σ W_j) P_i` ([`SubBasisSurface`]) is one rational bicubic patch per
//! face (`patch`); on a regular mesh it is the uniform bicubic B-spline.
//!
//! Non-quad input gets one Catmull-Clark step first ([`quad_control_mesh`]). Faces with a
//! corner on the boundary get no surface. [`SubBasisSurface`] is a
//! [`Surface`](crate::limit::Surface): [`limit::tessellate`](crate::limit::tessellate)
//! samples it on a watertight grid; [`compare_with_limit`] measures it against the
//! Catmull-Clark limit surface; [`face_colours`] and [`scalar_colours`] colour pictures.

pub(crate) mod colour;
pub(crate) mod compare;
mod error;
pub(crate) mod patch;
pub(crate) mod subbasis;
mod surface;
pub(crate) mod table;

pub use colour::{face_colours, scalar_colours, PALETTE};
pub use compare::{compare_with_limit, Comparison};
pub use error::SplineError;
pub use patch::RationalPatch;
pub use subbasis::{Class, SubBasis};
pub use surface::{quad_control_mesh, Piece, QuadSpline, SubBasisSurface};
pub use table::{valence_table, ValenceTable, EAGER_MAX_VALENCE};
