//! Subdivision weights (masks) only: no topology, no positions.
//!
//! - `crease`: sharpness arithmetic and vertex rules (OpenSubdiv's `Sdc::Crease`),
//!   in `f32` as OpenSubdiv computes them.
//! - `catmark`: Catmull-Clark face, edge and vertex masks, with OpenSubdiv's rules for
//!   creases, corners, transitions between them, and triangles; limit position and
//!   tangent masks.
//! - `adjustable`: the shape-adjustable Catmull-Clark scheme with parameter `c`
//!   (`c = ½` is Catmull-Clark).
//! - `bilinear`: OpenSubdiv's bilinear scheme (midpoints and centroids, any polygons).
//! - `loop_`: Loop's triangle scheme with OpenSubdiv's rules for creases and corners.
//! - `nurss`: non-uniform Catmull-Clark (knot intervals on edges, Sederberg et al. 1998).
//! - [`Rules`]: the rules that pick a vertex's or edge's mask, written once for the
//!   Catmull-Clark family and shared by Loop; `catmark::CatmullClark`,
//!   [`adjustable::Adjustable`], [`bilinear::Bilinear`] and `loop_::Loop` give their weights.
//!
//! A mask is a set of weights on the parent's vertex, the far ends of its edges, and
//! its faces' centres (refinement) or the vertices opposite in its faces (limit masks).

pub(crate) mod adjustable;
pub(crate) mod bilinear;
pub(crate) mod catmark;
pub(crate) mod crease;
pub(crate) mod kind;
pub(crate) mod loop_;
pub(crate) mod nurss;
mod rules;

pub use adjustable::Adjustable;
pub use bilinear::Bilinear;
pub(crate) use kind::Scheme;
pub use rules::Rules;
