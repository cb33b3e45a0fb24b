//! [`G2Cap`]: the `n` bi-septic patches around one extraordinary vertex, from the bicubic
//! patches around them ([`OuterPatches`]).

use super::bernstein::bernstein;
use super::bezier::BezierPatch;
use super::solver::{chebyshev, CapSolver};
use super::transition::Transitions;
use super::G2Error;
use nalgebra::{DMatrix, Matrix3xX};

/// The two bicubic patches next to one cap patch, as degree-3 [`BezierPatch`]es in the cap
/// patch's own coordinates shifted onto `[0, 1]²`: `across_v(x, s)` is the surface at cap
/// coordinates `(x, 1 + s)` (the neighbour across the edge `v = 1`), `across_u(s, y)` the
/// surface at `(1 + s, y)` (across `u = 1`). Only their 2-jets along the shared edges
/// matter, so any polynomial with the same 2-jet (e.g. the bicubic of the cap face itself,
/// which joins them C2) gives the same cap.
#[derive(Clone, Debug, PartialEq)]
pub struct OuterPatches {
    /// The patch across `v = 1`, in coordinates `(u, v - 1)`.
    pub across_v: BezierPatch,
    /// The patch across `u = 1`, in coordinates `(u - 1, v)`.
    pub across_u: BezierPatch,
}

/// Sets the three outer rows of control points of one bi-septic patch (`b ≥ 5` from the
/// edge `v = 1`, `a ≥ 5` from `u = 1`; the corner block `a, b ≥ 5` from both, averaged)
/// from the outer G2 conditions `∂ᵛₖ P(x, 1) = ∂ˢₖ [B∘σ](x, 0)` (`k = 0, 1, 2`) of
/// [`Transitions::outer`]:
///
/// `F₀ = B`, `F₁ = β Bᵤ + γ Bᵥ`, `F₂ = β² Bᵤᵤ + 2βγ Bᵤᵥ + γ² Bᵥᵥ + δ Bᵤ + ε Bᵥ`,
///
/// polynomials of degree ≤ 7 in `x` (B bicubic, β, γ quadratic, δ, ε quartic), converted
/// to Bézier form by interpolation at 8 Chebyshev points; then with `Fₖ = Σ qₖ,ₐ B⁷ₐ`:
/// `pₐ₇ = q₀,ₐ`, `pₐ₆ = pₐ₇ - q₁,ₐ/7`, `pₐ₅ = q₂,ₐ/42 - pₐ₇ + 2pₐ₆`.
/// Returns the largest disagreement of the two edges on the corner block (zero up to
/// rounding: the transitions agree at the outer corner to second order).
pub(crate) fn outer_rows(tr: &Transitions, outer: &OuterPatches, points: &mut [[f64; 3]]) -> f64 {
    // Interpolation matrix at Chebyshev points; its inverse maps values to Bézier points.
    let c = DMatrix::from_fn(8, 8, |m, a| bernstein(7, a as isize, chebyshev(8, m)));
    let inv = c.try_inverse().unwrap_or_else(|| DMatrix::identity(8, 8));
    let mut from_v = [[[0.0; 3]; 3]; 8]; // [a][row 5,6,7 → 0,1,2]
    let mut from_u = [[[0.0; 3]; 3]; 8]; // [b][col 5,6,7]
    for side in 0..2 {
        let mut f = [
            Matrix3xX::<f64>::zeros(8),
            Matrix3xX::zeros(8),
            Matrix3xX::zeros(8),
        ];
        for m in 0..8 {
            let x = chebyshev(8, m);
            let j = tr.outer(x);
            // (along, across) derivatives of the neighbour at the edge point.
            let (b, d) = if side == 0 {
                let n = &outer.across_v;
                let g = |a, b| n.derivative(x, 0.0, a, b);
                (j, [g(0, 0), g(1, 0), g(0, 1), g(2, 0), g(1, 1), g(0, 2)])
            } else {
                let n = &outer.across_u;
                let g = |a, b| n.derivative(0.0, x, a, b);
                // Mirror: the roles of u and v swap.
                (j, [g(0, 0), g(0, 1), g(1, 0), g(0, 2), g(1, 1), g(2, 0)])
            };
            let [be, ga] = b.first;
            let [de, ep] = b.second;
            let [p, bu, bv, buu, buv, bvv] = d;
            for k in 0..3 {
                f[0][(k, m)] = p[k];
                f[1][(k, m)] = be * bu[k] + ga * bv[k];
                f[2][(k, m)] = be * be * buu[k]
                    + 2.0 * be * ga * buv[k]
                    + ga * ga * bvv[k]
                    + de * bu[k]
                    + ep * bv[k];
            }
        }
        let q: Vec<Matrix3xX<f64>> = f.iter().map(|fk| fk * inv.transpose()).collect();
        let target = if side == 0 { &mut from_v } else { &mut from_u };
        for a in 0..8 {
            for k in 0..3 {
                let p7 = q[0][(k, a)];
                let p6 = p7 - q[1][(k, a)] / 7.0;
                let p5 = q[2][(k, a)] / 42.0 - p7 + 2.0 * p6;
                target[a][2][k] = p7;
                target[a][1][k] = p6;
                target[a][0][k] = p5;
            }
        }
    }
    let mut mismatch = 0.0f64;
    for a in 0..8 {
        for r in 0..3 {
            let b = 5 + r;
            // Edge v = 1 sets p[a][b]; edge u = 1 sets p[b][a].
            points[a * 8 + b] = from_v[a][r];
        }
    }
    for b in 0..8 {
        for r in 0..3 {
            let a = 5 + r;
            let idx = a * 8 + b;
            if b >= 5 {
                let v = from_v[a][b - 5];
                let u = from_u[b][r];
                for k in 0..3 {
                    mismatch = mismatch.max((v[k] - u[k]).abs());
                    points[idx][k] = 0.5 * (v[k] + u[k]);
                }
            } else {
                points[idx] = from_u[b][r];
            }
        }
    }
    mismatch
}

/// The `n` bi-septic patches of a G2 cap. Patch `i` has the extraordinary vertex at
/// `(0, 0)` and shares its edge `u = 0` with the edge `v = 0` of patch `i + 1`:
/// `Pᵢ(0, t) = Pᵢ₊₁(t, 0)`.
#[derive(Clone, Debug, PartialEq)]
pub struct G2Cap {
    patches: Vec<BezierPatch>,
    corner_mismatch: f64,
}

impl G2Cap {
    /// Builds the cap from the bicubic neighbours of its patches (one [`OuterPatches`]
    /// per patch, in order), with a solver for their valence.
    ///
    /// # Errors
    /// [`G2Error::OuterCount`] if `outer.len()` differs from the solver's valence;
    /// [`G2Error::Inconsistent`] if the constraints cannot be met.
    pub fn with_solver(solver: &CapSolver, outer: &[OuterPatches]) -> Result<Self, G2Error> {
        let n = solver.valence();
        if outer.len() != n {
            return Err(G2Error::OuterCount {
                valence: n,
                got: outer.len(),
            });
        }
        let mut points = vec![[0.0; 3]; 64 * n];
        let mut corner_mismatch = 0.0f64;
        for (i, o) in outer.iter().enumerate() {
            let m = outer_rows(solver.transitions(), o, &mut points[64 * i..64 * (i + 1)]);
            corner_mismatch = corner_mismatch.max(m);
        }
        solver.complete(&mut points)?;
        let patches = points
            .chunks(64)
            .filter_map(|c| BezierPatch::new(7, c.to_vec()))
            .collect();
        Ok(Self {
            patches,
            corner_mismatch,
        })
    }

    /// As [`with_solver`](Self::with_solver), building the solver for `outer.len()`.
    ///
    /// # Errors
    /// As [`CapSolver::new`] and [`with_solver`](Self::with_solver).
    pub fn new(outer: &[OuterPatches]) -> Result<Self, G2Error> {
        Self::with_solver(&CapSolver::new(outer.len())?, outer)
    }

    /// The valence `n` (number of patches).
    pub fn valence(&self) -> usize {
        self.patches.len()
    }

    /// The bi-septic patches, in order around the vertex.
    pub fn patches(&self) -> &[BezierPatch] {
        &self.patches
    }

    /// Largest disagreement between the two outer edges of a patch on their shared 3×3
    /// corner block of control points (a consistency diagnostic of the outer transitions;
    /// zero up to rounding).
    pub fn corner_mismatch(&self) -> f64 {
        self.corner_mismatch
    }
}
