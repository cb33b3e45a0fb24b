//! B-spline and NURBS curves and tensor-product surfaces of any degree: knot vectors and
//! knot intervals, evaluation with derivatives, exact knot insertion, closed (periodic) and
//! clamped curves, rational geometry in homogeneous coordinates, JSON input/output, and the
//! conversion of a bicubic surface to a control mesh with knot intervals (the input of
//! non-uniform Catmull-Clark subdivision, NURSS).
//!
//! | module | concept |
//! |---|---|
//! | `knots` | [`KnotVector`]: validated open and periodic knot vectors, spans, multiplicities, knot intervals |
//! | `basis` | Cox–de Boor basis functions and derivatives (The NURBS Book A2.2, A2.3) |
//! | [knot insertion](self#knot-insertion) | Boehm's knot insertion and knot refinement (A5.1, A5.4), cyclic for periodic knots |
//! | `curve` | [`BSplineCurve`], `Σ N_{i,p}(t) P_i` over `[f64; D]` points: de Boor, derivatives, insertion |
//! | `nurbs_curve` | [`NurbsCurve`], rational curves as 4D B-splines; the exact circle (§7.5) |
//! | `surface` | [`BSplineSurface`], tensor-product surfaces, partial derivatives, insertion along `u` / `v` |
//! | `nurbs_surface` | [`NurbsSurface`], rational surfaces; the exact cylinder and torus |
//! | `mesh` | [`ControlMesh`]: bicubic surface → quad mesh + per-edge knot intervals |
//! | `json` | [`Curve`], [`Surface`]: JSON schema, exact reading and writing |
//!
//! References: L. Piegl & W. Tiller, *The NURBS Book*, 2nd ed., Springer 1997 (algorithm and
//! equation numbers below are theirs); W. Boehm, "Inserting new knots into B-spline curves",
//! CAD 12(4), 1980; T. Sederberg, J. Zheng, D. Sewell & M. Sabin, "Non-uniform recursive
//! subdivision surfaces", SIGGRAPH 1998.
//!
//! ```
//! use subsurf::nurbs::NurbsSurface;
//! // A torus refined by one step of midpoint knot insertion stays exactly a torus.
//! let mut torus = NurbsSurface::torus([0.0; 3], 2.0, 0.5)?;
//! let before = torus.eval(0.3, 0.7)?;
//! torus.insert_midpoints()?;
//! assert_eq!(torus.size(), (13, 13)); // 9 + 4 midpoints each way
//! let after = torus.eval(0.3, 0.7)?;
//! assert!((0..3).all(|c| (before[c] - after[c]).abs() < 1e-14));
//! # Ok::<(), subsurf::nurbs::NurbsError>(())
//! ```
//!
//! # Knot insertion
//! Inserting `x ∈ [t_k, t_{k+1})` replaces `P_{k−p+1} … P_{k−1}` by the `p` points
//! `Q_i = (1 − α_i) P_{i−1} + α_i P_i`, `α_i = (x − t_i) / (t_{i+p} − t_i)` (Boehm 1980;
//! The NURBS Book eq. 5.15). Many knots go in one pass (A5.4). For periodic knots `x` and all
//! its translates by the period are inserted, cyclically. Rational curves and surfaces are
//! refined in homogeneous coordinates, so a refined circle, cylinder or torus is still exact.
//!
//! # Why not a crate
//! [`curvo`](https://crates.io/crates/curvo) (0.3) is the most complete NURBS crate; we read
//! it and chose to write this module instead, because:
//! - **periodicity is not kept**: its closed curves are unwrapped open curves
//!   (`try_periodic`), and knot refinement does not insert the periodic translates, so a
//!   refined closed curve is no longer periodic — but non-uniform subdivision of closed
//!   nets needs exactly that (and knot-interval bookkeeping per edge, which no crate has);
//! - **errors are `anyhow::Result`**, not typed (this crate's rule: typed `thiserror` errors
//!   that name the faulty input);
//! - **weight**: it depends on `nalgebra`, `simba`, `argmin`, `geo`, `spade`, `robust`,
//!   `hashbrown`, `itertools`, `ordered-float`, `gauss-quad`, `anyhow` — far more than
//!   evaluation and refinement need, for a library whose other layers use plain `[f64; D]`;
//! - **control over numerics**: we want the exact algorithms of The NURBS Book (de Boor as
//!   convex combinations, A5.4 refinement) on `f64` arrays, allocation-free evaluation for
//!   ordinary degrees, and bit-exact JSON round trips.
//!
//! The module is small (a few hundred lines of algorithms), and every algorithm is checked in
//! `tests/integration/nurbs.rs` against an independent computation (de Casteljau, polynomial
//! blossoms, finite differences, exact circles and tori, repeated single insertions).

pub(crate) mod basis;
pub(crate) mod curve;
pub(crate) mod error;
mod insert;
pub(crate) mod json;
mod json_reader;
pub(crate) mod knots;
pub(crate) mod mesh;
pub(crate) mod nurbs_curve;
pub(crate) mod nurbs_surface;
pub(crate) mod sample;
pub(crate) mod surface;
mod vecn;

pub use basis::{basis_derivatives, basis_functions};
pub use curve::BSplineCurve;
pub use error::NurbsError;
pub use json::{
    from_json_str, from_json_str_all, to_json_string_all, Curve, CurveJson, Geometry,
    SourcedGeometry, Surface, SurfaceJson, CURVE_TYPE, SURFACE_TYPE,
};
pub use knots::{KnotVector, MAX_DEGREE};
pub use mesh::{ControlMesh, KnotEdge};
pub use nurbs_curve::NurbsCurve;
pub use nurbs_surface::NurbsSurface;
pub use sample::{sample_count, sample_parameters};
pub use surface::{BSplineSurface, SurfaceDerivs};
