//! G2 caps at extraordinary vertices: around every interior extraordinary vertex of a
//! Catmull-Clark surface, the `n` patches at the vertex are replaced by `n` bi-septic
//! (degree 7×7) Bézier patches that join each other and the surrounding bicubic
//! B-spline patches with curvature continuity (G2). After Loop & Schaefer, *G2 tensor
//! product splines over extraordinary vertices*, SGP 2008, as [Tang et al. 2017] uses them
//! (§3.2), with the transition maps re-derived (the seed's formulas are damaged).
//!
//! # Layout
//! Refinement isolates each extraordinary vertex (EV): after `L` Catmull-Clark steps its
//! 2-ring is regular apart from the centre, so the patches around the `n` faces at the
//! EV — the *outer* patches — are bicubic. Cap patch `Pᵢ(u, v)`, `i = 0..n`, has the EV at
//! `(0, 0)`; its edge `u = 0` is the edge `v = 0` of `Pᵢ₊₁` (`Pᵢ(0, t) = Pᵢ₊₁(t, 0)`, the
//! *inner* boundaries), and its edges `u = 1`, `v = 1` border bicubic patches (the
//! *outer* boundaries). `c = cos(2π/n)`.
//!
//! # G2 and transition maps
//! Two patches `P` and `Q` sharing an edge join G2 when there is a reparametrisation `ρ`
//! of a neighbourhood of the edge, fixing it pointwise, with `Q` and `P∘ρ` in C2 contact:
//! `∂ₛᵏ Q(t, 0) = ∂ₛᵏ [P∘ρ](t, 0)` for `k = 0, 1, 2` (`s` across the edge; seed
//! Definition 1). Only the 2-jet of `ρ` across the edge enters, by the chain rule:
//!
//! * `k = 1`: `Qₛ = ρ'ᵤ Pᵤ + ρ'ᵥ Pᵥ`,
//! * `k = 2`: `Qₛₛ = ρ'ᵤ² Pᵤᵤ + 2ρ'ᵤρ'ᵥ Pᵤᵥ + ρ'ᵥ² Pᵥᵥ + ρ''ᵤ Pᵤ + ρ''ᵥ Pᵥ`,
//!
//! so for fixed `ρ` the conditions are *linear* in the control points. The whole
//! difficulty is choosing the jets of `ρ` so that the conditions are solvable with
//! degree 7 for all data. We derive them from three requirements:
//!
//! 1. **Degree.** Each condition must be a polynomial identity in `t` that bi-septic
//!    patches can satisfy. With `ρ' = (-1, α)` on inner edges (the symmetric form of the
//!    seed's Eq. (3)), `α` must be linear; the second-order terms `r₁ Pᵤ`, `r₂ Pᵥ` may be
//!    quadratic (they raise the identity to degree 9, which only removes freedom).
//! 2. **The EV** (`t = 0`): the tangent plane must be well defined, i.e. going around the
//!    vertex the linear parts `[[0, -1], [1, α(0)]]` must compose to the identity. Their
//!    eigenvalues are `e^{±2πi/n}` iff `α(0) = 2c` (tested in `transition`).
//! 3. **The other end** (`t = 1`, a regular vertex `V` where cap patches `i`, `i+1` and
//!    two bicubics meet). The outer conditions fix the 2-jets of the caps along the outer
//!    edges, hence all derivatives `∂ᵤᵃ∂ᵥᵇ` with `b ≤ 2` of `Pᵢ` at `V` (and `a ≤ 2` of
//!    `Pᵢ₊₁`). Differentiating the inner conditions along the edge at `t = 1` gives
//!    identities between these fixed quantities, which must hold for all data. Writing
//!    `G` for the common regular (C2) bicubic near `V` (`Pᵢ ≈ G(u, v)`,
//!    `Pᵢ₊₁(t, s) ≈ G(-s, t)`), the outer transition across `v = 1`,
//!    `σ(x, s) = (x, 1) + s(β, γ) + s²/2 (δ, ε)`, enters through the chain rule.
//!    The order-0 and order-1 derivatives of the first-order identity at `V` give
//!    `β(0) = 0`, `γ(0) = 1`, `2γ'(0) = -2c` (the `α'(1) = -2c` of the linear `α` must be
//!    absorbed by the outer edges: with a plain C2 outer boundary, `α` would need a triple
//!    root at `t = 1`, impossible in degree 7). At the far corner `x = 1` (valence 4, all
//!    neighbours bicubic) both outer edges must prescribe the same mixed derivatives:
//!    `β'(1) = γ'(1)`, `β(1) = 0`, `γ(1) = 1`. Degree 7 allows quadratic `β, γ` (they
//!    enter squared next to the cubic `Bᵤᵤ`), so `β = -c x(1-x)`, `γ = 1 - c x(1-x)`.
//!    The second-order identities at `V` (orders 0, 1, 2 along the edge) then determine
//!    `r₁(1) = r₂(1) = 0`, `r₁'(1) = 4c² - 4c`, `r₂'(1) = 4c²`, `r₁''(1) = r₂''(1) =
//!    8c³ - 8c²`, and the corner condition on the 3×3 block of control points shared by
//!    the two outer edges gives `δ = ε = -2c x³(1-x)`:
//!
//!    `α = 2c(1-t)`, `r₁ = 4c(1-c)(1-t) - 4c²(1-c)(1-t)²`,
//!    `r₂ = -4c²(1-t) - 4c²(1-c)(1-t)²`.
//!
//! 4. **Cyclic condition at second order** (the EV again). Going around the vertex, the
//!    transitions must compose to the identity also in their quadratic terms, or the
//!    constraints force the tangents at the EV to vanish (a singular point). Writing the
//!    composition in the eigen-coordinates `z, z̄` of `L` (eigenvalues `λ = e^{±2πi/n}`), a
//!    quadratic term `z̄²` in the `z` component can be removed by a change of coordinates
//!    unless `λ = λ̄²`, i.e. `n = 3`: for every other valence any quadratic part is harmless
//!    (it is `L q - q∘L` for some quadratic `q`, so the maps are conjugate to rotations to
//!    second order). For `n = 3` the resonant coefficient of the quadratic part
//!    `(r₁(0) s²/2, α'(0) t s + r₂(0) s²/2)` must vanish; with `α'(0) = 1`, `λ = e^{2πi/3}`
//!    this is `(r₁(0) λ + r₂(0) λ̄)/2 = 1`, so `r₁(0) = r₂(0) = -2`, reached by adding
//!    `(5/2, 1/2)·(1-t)³` to `(r₁, r₂)` (which changes nothing at `t = 1`). Without it the
//!    valence-3 caps come out with zero tangents at the vertex (tested).
//!
//! For `n = 4` all of this is the identity of the regular grid. The derivation is checked
//! numerically: for random 2-rings of every valence 3..=16 the constraint system is
//! consistent to rounding (`solver` tests, `tests/integration/g2cap.rs`), the corner blocks from
//! the two outer edges agree, and the resulting surfaces have position, normal and normal
//! curvature continuous across every boundary at 1e-10 ([`continuity_report`]).
//!
//! # Construction
//! The outer rows of control points (three per outer edge) follow explicitly from the
//! bicubic neighbours (`cap::outer_rows`); the inner `5×5` blocks minimise the energy of
//! `energy` (zero exactly for bicubics, so valence 4 gives back the B-spline patches)
//! under the inner G2 conditions. The system commutes with the rotation of the sectors,
//! so [`CapSolver`] solves it per Fourier frequency of the sector index (`⌊n/2⌋ + 1`
//! systems of at most 50 unknowns, once per valence), after eliminating the rows that
//! involve outer data only and projecting the data onto the consistent subspace: the
//! caps are a well-conditioned function of the mesh (ulp perturbations move them by
//! `≲ 5·10⁻¹⁴` of their size). [`DenseCapSolver`], the direct solve over all sectors, is
//! kept as the reference (same caps to its own rounding, `~10⁻¹⁰`).
//! [`G2Surface`] does this for every interior smooth EV of a mesh (valence 3..=16, also
//! the centres of n-gons); vertices on boundaries or creases, or next to them, keep the
//! Catmull-Clark surface. [`G2Surface::new`] with [`Scheme::Adjustable`](crate::Scheme::Adjustable) does the same for the mixed
//! (shape-adjustable) surface of [Tang et al. 2017]: only the surrounding bicubics change (those of
//! the `c`-refined net), and with them the outer rows of the caps.

mod bernstein;
mod bezier;
pub(crate) mod cap;
mod dense;
pub(crate) mod energy;
mod error;
pub(crate) mod export;
mod iges;
mod report;
mod solver;
pub(crate) mod surface;
pub(crate) mod transition;

pub use bezier::BezierPatch;
pub use cap::{G2Cap, OuterPatches};
pub use dense::{DenseCapSolver, INNER_SAMPLES};
pub use error::G2Error;
pub use export::{patches_json, CapJson, MixedJson, PatchJson, SurfaceJson};
pub use iges::to_iges;
pub use report::{continuity_report, BoundaryKind, BoundaryStats, ContinuityReport, Side};
pub use solver::{inner_rows, CapSolver};
pub use surface::{CapInfo, G2Surface, G2SurfaceOptions, PatchRef, Uncapped};
pub use transition::{Jet, Transitions};

/// The largest valence capped (higher-valence vertices keep the Catmull-Clark surface).
pub const MAX_CAP_VALENCE: usize = 16;
