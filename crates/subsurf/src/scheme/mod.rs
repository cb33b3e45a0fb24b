//! Subdivision weights (masks) only: no topology, no positions.
//!
//! - [`crease`]: sharpness arithmetic and vertex rules (OpenSubdiv's `Sdc::Crease`),
//!   in `f32` as OpenSubdiv computes them.
//! - [`catmark`]: Catmull-Clark face, edge and vertex masks, with OpenSubdiv's rules for
//!   creases, corners, transitions between them, and triangles; limit position and
//!   tangent masks.
//! - [`adjustable`]: the shape-adjustable Catmull-Clark scheme with parameter `c`
//!   (`c = ½` is Catmull-Clark).
//! - [`nurss`]: non-uniform Catmull-Clark (knot intervals on edges, Sederberg et al. 1998).
//! - [`Rules`]: the rules that pick a vertex's or edge's mask, written once for the
//!   Catmull-Clark family; [`catmark::CatmullClark`] and [`adjustable::Adjustable`] give
//!   their weights.
//!
//! A mask is a set of weights on the parent's vertex, the far ends of its edges, and
//! its faces' centres (refinement) or the vertices opposite in its faces (limit masks).

pub mod adjustable;
pub mod catmark;
pub mod crease;
mod kind;
pub mod nurss;
mod rules;

pub use kind::Scheme;
pub use rules::Rules;
