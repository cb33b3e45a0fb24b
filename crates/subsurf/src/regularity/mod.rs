//! A certificate of regularity of Catmull-Clark limit surfaces read off the control net's
//! difference vectors (Wang, Lin, Wang, Lu, *On Regularity of Catmull-Clark Subdivision
//! Surfaces*, Journal of Computer-Aided Design & Computer Graphics, 2016), for quad nets
//! whose interior vertices all have valence 4; planar nets (the Jacobian of the map
//! `(u, v) ↦ (x, y)` must not vanish or change sign: no fold) and spatial ones (the normal
//! `S_u × S_v` must not vanish).
//!
//! # The paper
//! §1.1.1 defines the forward differences `Δu(p_ij) = p_i,j+1 − p_ij` and
//! `Δv(p_ij) = p_i+1,j − p_ij`. §1.1.2 shows that one Catmull-Clark step maps the six
//! u-differences of rows 1–3 of a 3×3 block linearly to the new ones with non-negative
//! rows `ξ₁ … ξ₆` (face→edge `(3, 1, 3, 1, 0, 0)/16`, edge→face `(1, 3, 1, 3, 0, 0)/16`,
//! edge→vertex `(3, 1, 18, 6, 3, 1)/64`, vertex→edge `(1, 3, 6, 18, 1, 3)/64`); §1.2 builds
//! the 9×9 matrix `S` of the central differences (`2S` has eigenvalues
//! `1, 5/8, 1/2, 1/2, 1/4, 1/4, 1/4, 1/8, 1/8`) whose powers converge to a non-negative
//! matrix. Theorems 1 and 2: the limit tangents are combinations with weights in `[0, 1]` of
//! the control net's forward differences. Theorem 3: if the cone spanned by all
//! u-differences and the cone spanned by all v-differences meet only at the origin, the
//! limit surface is regular. Its examples (§2, Figs. 5–7) are planar nets whose cones are
//! fans (angular sectors).
//!
//! # What the cones are, exactly
//! On a face whose limit surface is one bicubic B-spline patch with control points
//! `P[i][j]` (`i` along `u`), differentiating the cubic B-spline basis gives the quadratic
//! one on the differences:
//!
//! `S_u(u, v) = Σ_{i=0..2} Σ_{j=0..3} N²ᵢ(u) N³ⱼ(v) (P[i+1][j] − P[i][j])`
//!
//! (and the same for `S_v`), with non-negative weights: this is Theorem 1 made local and
//! explicit. So the tangents of face `f` depend only on the **12 u- and 12 v-differences of
//! its 4×4 patch neighbourhood** (`neighbourhood`); these are the *local cones*.
//! Across a boundary (or infinitely sharp crease) the patch uses phantom points
//! `P₋₁ = 2P₀ − P₁`. A phantom column's u-difference equals a real one
//! (`P₀ − P₋₁ = P₁ − P₀`); a phantom row's u-differences are `2Δ₀ − Δ₁`, and absorbing them
//! leaves the weights `N³₁ + 2N³₀ ≥ 0` and `N³₂ − N³₀ = v(3 − v²)/3 ≥ 0` on the real rows (with
//! phantom rows on both sides: `1 − v` and `v`). So **only the real differences of the
//! block are needed**, still with non-negative weights: the boundary handling of the paper,
//! made exact. The *global cones* of Theorem 3 are all u- and v-differences of the net
//! under a global `(i, j)` labelling (`frame`); every face's local differences are among
//! them, so the global certificate implies the local one on every face it covers.
//!
//! # A correction to Theorem 3
//! "The cones meet only at the origin" does not exclude `S_u` and `S_v` pointing in
//! *opposite* directions (u-differences along `+x`, v-differences along `−x`: the cones
//! meet only at the origin, yet every normal is zero), nor a cone that holds a line (two
//! opposite u-differences, whose combination can vanish). The test used here
//! (`cone`) asks that the u-cone meet neither the v-cone nor its opposite except at the
//! origin, with both cones pointed: planar, every `Δu × Δv` has one strict sign; spatial,
//! two separating planes exist. Then `S_u × S_v ≠ 0` wherever some weight on a non-zero
//! difference of each direction is positive — which holds everywhere on the face when its
//! own four edges are non-zero, since the quadratic weight `N²₁ ≥ 1/2` and the cubic
//! weights `N³₁, N³₂ ≥ 1/6` of the face's own edges never vanish on `[0, 1]` (with two
//! phantom rows, `1 − v` and `v` never vanish together). A face with a zero-length edge is
//! refused.
//!
//! # What is certified
//! - **Planar** (all `z = 0`, or forced): on a certified face `det(S_u, S_v)` has the
//!   strict sign of the mesh's orientation (the sign of its total signed area): the map
//!   does not fold there. Not certified: global injectivity (distant parts may overlap).
//! - **Spatial**: on a certified face `S_u × S_v ≠ 0`: the surface is regular, with a
//!   continuous unit normal. The condition says nothing about the normal's *direction* (it
//!   may turn arbitrarily; there is no cone of normals) or about self-intersections.
//!
//! # Not applicable
//! Faces at an interior extraordinary vertex (outside the paper's setting), and faces at a
//! boundary vertex that is not a regular boundary or corner vertex: the paper allows
//! irregular boundary vertices, but its derivation covers only the regular 3×3 blocks, and
//! OpenSubdiv's boundary rules mix the directions with negative weights (at a smooth
//! corner with edge points `(C+A)/2`, `(C+B)/2` and vertex point `(A + 6C + B)/8`, the new
//! u-difference is `(3Δu − Δv)/8`). Worse, at an edge-only corner (one face, boundary not
//! sharpened) the limit boundary is smooth, so `S_u ∥ S_v` at the corner whatever the
//! cones: such corners must be tagged (`t interpolateboundary 1/0/0 1`, edge-and-corner)
//! to be certified. Those faces are reported with the vertex ([`Inapplicable`]).
//!
//! # Exactness
//! Signs are decided exactly on the exact differences of the `f64` input (`exact`): a
//! zero difference is exactly zero (and left out of the cones), collinear differences are
//! recognised as such, and near-collinear ones get their true sign. In space the
//! separating planes are searched numerically and verified exactly (`separation`), so
//! the spatial test may refuse cones separable only by a margin below rounding (it never
//! certifies wrongly). A sign that cannot be computed exactly (products below `2⁻⁹⁰⁰`)
//! refuses.
//!
//! # Ground truth
//! `sample` samples the exact limit surface densely and classifies each face:
//! certified, regular but not certified, or not regular (with the failing sample).

pub(crate) mod cone;
pub(crate) mod exact;
pub(crate) mod frame;
pub(crate) mod neighbourhood;
pub(crate) mod plot;
pub(crate) mod sample;
pub(crate) mod sector;
pub(crate) mod separation;

mod error;
mod report;
mod summary;

pub use cone::{ConeTest, Difference, Dimension, Direction, Obstruction, Witness};
pub use error::RegularityError;
pub use exact::Sign;
pub use frame::{Frames, NoFrame};
pub use neighbourhood::block;
pub use neighbourhood::{Block, Inapplicable};
#[cfg(feature = "render")]
pub use plot::plot_image;
pub use plot::{plot_svg, PLOT_HEIGHT, PLOT_WIDTH};
pub use report::{
    check_regularity, check_regularity_with, Certificate, Class, ComponentCones, Counts,
    FaceReport, Mode, Refusal, RegularityOptions, RegularityReport,
};
pub use sample::{Sample, Sampled};
