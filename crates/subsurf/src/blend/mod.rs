//! [Jiang et al.] (docs/references.md: NURBS patch blending and N-sided hole filling):
//! skirt-removal refinement for open meshes, corner interpolation with zero knot intervals,
//! C2 blending of bicubic B-spline patches and N-sided hole filling with non-uniform
//! Catmull-Clark (NURSS, [`crate::nonuniform`]).
//!
//! - `skirt`: skirt removal for any scheme (`skirt::skirt_step`, [`skirt::nurss_step`],
//!   [`skirt::catmark_step`], [`skirt::refine_with_skirt`]).
//! - `extend`: the extension layer around an open mesh.
//! - `grid`: vertex grids carried through refinement and the exact limit (de Boor) over a
//!   regular part.
//! - `patch`: a clamped patch as a corner-interpolating control mesh.
//! - `join`: C2 blending of N bicubic patches ([`blend()`]).
//! - `fill`: N-sided hole filling (Algorithm 1, corner interpolating).
//! - `g1`: N-sided hole filling, G1 (Algorithm 2).
//! - `job`: blending and filling the patches and curves of a file as `subsurf blend` and
//!   `subsurf fill` do ([`BlendJob`], [`FillJob`]: the input checked, the memory estimated,
//!   the output assembled).
//!
//! Patches and curves may be rational (NURBS): the methods run on their homogeneous
//! B-splines, which non-uniform Catmull-Clark refines as it refines rational meshes
//! (`homogeneous`).

mod error;

pub(crate) mod extend;
pub(crate) mod fill;
pub(crate) mod g1;
pub(crate) mod grid;
pub(crate) mod homogeneous;
pub(crate) mod job;
pub(crate) mod join;
pub(crate) mod patch;
pub(crate) mod skirt;

pub use error::BlendError;
pub use fill::{fill, Fill, FillOptions};
pub use fill::{patch_boundary, reversed, reweight_ends, surface_boundary};
pub use g1::fill_g1;
pub use grid::grid_mesh;
pub use homogeneous::{BoundaryCurve, Patch};
pub use job::{
    BlendJob, BlendJobOptions, FillJob, FillJobOptions, JobError, MethodOutput, MAX_LEVELS,
    MAX_SAMPLES,
};
pub use join::{blend, blend_control_mesh, Blend, BlendMesh};
pub use patch::corner_interpolating_mesh;
pub use skirt::{
    catmark_refine_once, catmark_step, nurss_refine_once, nurss_step, real_part, refine_with_skirt,
};
