//! The transition maps (reparametrisations) that define G2 continuity across the
//! boundaries of a cap; the derivation is in the [module docs](super).
//!
//! Only the 2-jet of a transition across its edge matters for G2, so a transition is
//! stored as its first and second derivative across the edge, as functions of the
//! parameter along the edge:
//!
//! * **inner** edge between cap patches `Pᵢ` and `Pᵢ₊₁` (`Pᵢ(0, t) = Pᵢ₊₁(t, 0)`):
//!   `ρ(t, s) = (0, t) + s·(-1, α(t)) + s²/2·(r₁(t), r₂(t))` maps the coordinates
//!   `(t, s)` of `Pᵢ₊₁` (`s` across the edge) into those of `Pᵢ`, and G2 means
//!   `∂ˢₖ [Pᵢ∘ρ](t, 0) = ∂ᵛₖ Pᵢ₊₁(t, 0)` for `k = 0, 1, 2`, with (`c = cos 2π/n`)
//!   `α = 2c(1-t)`, `r₁ = 4c(1-c)(1-t) - 4c²(1-c)(1-t)²`,
//!   `r₂ = -4c²(1-t) - 4c²(1-c)(1-t)²`, plus `(5/2, 1/2)·(1-t)³` for `n = 3`;
//! * **outer** edge `v = 1` of a cap patch, against the bicubic patch `B` across it (or
//!   any polynomial sharing its 2-jet along the edge):
//!   `σ(x, s) = (x, 1) + s·(β(x), γ(x)) + s²/2·(δ(x), ε(x))` and G2 means
//!   `∂ᵛₖ P(x, 1) = ∂ˢₖ [B∘σ](x, 0)`, with `β = -c x(1-x)`, `γ = 1 - c x(1-x)`,
//!   `δ = ε = -2c x³(1-x)`; the edge `u = 1` is the mirror image (`u ↔ v`).
//!
//! For `n = 4` (`c = 0`) every transition is the identity of a regular grid, so G2 is C2.

use std::f64::consts::PI;

/// The first and second derivative of a transition map across its edge at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jet {
    /// `∂ₛ` of the map (a vector of the other patch's parameter plane).
    pub first: [f64; 2],
    /// `∂ₛ²` of the map.
    pub second: [f64; 2],
}

/// The transition maps of a cap around a vertex of valence `n`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transitions {
    valence: usize,
    c: f64,
}

impl Transitions {
    /// The transitions for valence `n` (`n ≥ 3`).
    pub fn new(valence: usize) -> Self {
        let c = if valence == 4 {
            0.0
        } else {
            (2.0 * PI / valence as f64).cos()
        };
        Self { valence, c }
    }

    /// The valence `n`.
    pub fn valence(&self) -> usize {
        self.valence
    }

    /// `c = cos(2π/n)` (exactly 0 for `n = 4`).
    pub fn cos(&self) -> f64 {
        self.c
    }

    /// The inner transition `ρ` at parameter `t` along the edge (`t = 0` at the
    /// extraordinary vertex): `∂ₛρ = (-1, α(t))`, `∂ₛ²ρ = (r₁(t), r₂(t))`.
    pub fn inner(&self, t: f64) -> Jet {
        let c = self.c;
        let s = 1.0 - t;
        let alpha = 2.0 * c * s;
        let q = -4.0 * c * c * (1.0 - c) * s * s;
        // Valence 3 only: the resonance correction (module docs), zero to third order at
        // t = 1 so the conditions there are unchanged.
        let (e1, e2) = if self.valence == 3 {
            (2.5 * s * s * s, 0.5 * s * s * s)
        } else {
            (0.0, 0.0)
        };
        Jet {
            first: [-1.0, alpha],
            second: [4.0 * c * (1.0 - c) * s + q + e1, -4.0 * c * c * s + q + e2],
        }
    }

    /// The outer transition `σ` across the edge `v = 1` at parameter `x` along it (`x = 0`
    /// at the corner next to the extraordinary vertex): `∂ₛσ = (β, γ)`, `∂ₛ²σ = (δ, ε)`.
    /// Across `u = 1` use the mirror image: `(γ, β)` and `(ε, δ)` at `y = v`.
    pub fn outer(&self, x: f64) -> Jet {
        let c = self.c;
        let b = -c * x * (1.0 - x);
        let d = -2.0 * c * x * x * x * (1.0 - x);
        Jet {
            first: [b, 1.0 + b],
            second: [d, d],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Valence 4: every transition is the identity of the regular grid (C2).
    #[test]
    fn valence_four_is_the_regular_grid() {
        let t = Transitions::new(4);
        for k in 0..=10 {
            let x = k as f64 / 10.0;
            assert_eq!(t.inner(x).first, [-1.0, 0.0]);
            assert_eq!(t.inner(x).second, [0.0, 0.0]);
            assert_eq!(t.outer(x).first, [0.0, 1.0]);
            assert_eq!(t.outer(x).second, [0.0, 0.0]);
        }
    }

    /// At the extraordinary vertex the inner transition's linear part
    /// `L = [[0, -1], [1, 2c]]` (columns: images of the edge and cross directions) has
    /// `Lⁿ = I`: going once around the vertex returns to the start (the cyclic
    /// condition, first order).
    #[test]
    fn linear_part_at_the_vertex_is_cyclic() {
        for n in 3..=16 {
            let tr = Transitions::new(n);
            let j = tr.inner(0.0);
            // ρ(t, s) ≈ (-s, t + α s): the matrix acting on (t, s).
            let l = [[0.0, j.first[0]], [1.0, j.first[1]]];
            let mut m = [[1.0, 0.0], [0.0, 1.0]];
            for _ in 0..n {
                let mut r = [[0.0; 2]; 2];
                for a in 0..2 {
                    for b in 0..2 {
                        r[a][b] = l[a][0] * m[0][b] + l[a][1] * m[1][b];
                    }
                }
                m = r;
            }
            for a in 0..2 {
                for b in 0..2 {
                    let e = if a == b { 1.0 } else { 0.0 };
                    assert!((m[a][b] - e).abs() < 1e-12, "valence {n}");
                }
            }
        }
    }

    /// Valence 3: the quadratic part `Q(t, s) = (r₁(0) s²/2, α'(0) t s + r₂(0) s²/2)` of the
    /// inner transition has no resonant term: with `w = (1, -λ)` the eigenvector of `L` for
    /// `λ = e^{2πi/3}` and `ℓ = (1, λ)` its left eigenvector, `ℓ · B(w̄, w̄) = 0` (`B` the
    /// symmetric bilinear form of `Q`), so the transitions compose to the identity to
    /// second order around the vertex.
    #[test]
    fn valence_three_has_no_second_order_resonance() {
        let tr = Transitions::new(3);
        let j0 = tr.inner(0.0);
        let h = 1e-6;
        let alpha_prime = (tr.inner(h).first[1] - tr.inner(0.0).first[1]) / h;
        let (r1, r2) = (j0.second[0], j0.second[1]);
        assert!((r1 + 2.0).abs() < 1e-12 && (r2 + 2.0).abs() < 1e-12);
        // Complex numbers as (re, im).
        let mul = |a: (f64, f64), b: (f64, f64)| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
        let lam = (-0.5, 3f64.sqrt() / 2.0);
        let lam_bar = (lam.0, -lam.1);
        // w̄ = (t̄, s̄) = (1, -λ̄).
        let (tb, sb) = ((1.0, 0.0), (-lam_bar.0, -lam_bar.1));
        let s2 = mul(sb, sb);
        let ts = mul(tb, sb);
        let b1 = (0.5 * r1 * s2.0, 0.5 * r1 * s2.1);
        let b2 = (
            alpha_prime * ts.0 + 0.5 * r2 * s2.0,
            alpha_prime * ts.1 + 0.5 * r2 * s2.1,
        );
        let res = {
            let a = b1;
            let b = mul(lam, b2);
            (a.0 + b.0, a.1 + b.1)
        };
        assert!(res.0.abs() < 1e-5 && res.1.abs() < 1e-5, "{res:?}");
    }

    /// Away from the extraordinary vertex (`t = 1`, and the far end `x = 1` of an outer
    /// edge) the transitions are those of the regular grid to the orders the
    /// surrounding C2 bicubics fix: `α`, `r₁`, `r₂` vanish at `t = 1`; `β(0) = β(1) = 0`,
    /// `γ(0) = γ(1) = 1`, and `δ`, `ε` vanish to third order at `x = 0`.
    #[test]
    fn regular_at_the_ends_of_the_edges() {
        for n in [3, 5, 6, 7, 8, 12] {
            let tr = Transitions::new(n);
            let j = tr.inner(1.0);
            assert_eq!(j.first, [-1.0, 0.0]);
            assert!(j.second[0].abs() < 1e-15 && j.second[1].abs() < 1e-15);
            for x in [0.0, 1.0] {
                let o = tr.outer(x);
                assert!(o.first[0].abs() < 1e-15 && (o.first[1] - 1.0).abs() < 1e-15);
            }
            assert!(tr.outer(1e-3).second[0].abs() < 1e-8);
        }
    }
}
