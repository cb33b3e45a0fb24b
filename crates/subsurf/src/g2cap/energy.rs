//! The fairness energy minimised by the caps:
//!
//! `E(P) = ∫₀¹∫₀¹ |∂⁴P/∂u⁴|² + |∂⁴P/∂v⁴|² du dv`,
//!
//! a quadratic form in the control points that is zero exactly when `P` has degree ≤ 3
//! in `u` and in `v`, i.e. for bicubic patches: this is the property Loop & Schaefer
//! (2008, §4) ask of their functional, so that valence 4 reproduces the bicubic B-spline.
//! With `∂⁴ᵤ Bᵈᵢ = d!/(d-4)! Σⱼ (-1)⁴⁻ʲ C(4, j) Bᵈ⁻⁴ᵢ₋ⱼ` and the exact Bernstein integrals
//! `∫₀¹ Bᵐᵢ Bᵐⱼ = C(m,i) C(m,j) / (C(2m, i+j) (2m+1))`, the Hessian of one degree-`d`
//! patch is `K ⊗ G + G ⊗ K` with `G` the Gram matrix of degree `d` and `K` that of the
//! fourth derivatives.

use super::bernstein::binomial;

/// Gram matrix `∫₀¹ Bᵐᵢ Bᵐⱼ` of the degree-`m` Bernstein basis.
fn gram(m: usize) -> Vec<Vec<f64>> {
    (0..=m)
        .map(|i| {
            (0..=m)
                .map(|j| {
                    binomial(m, i) * binomial(m, j) / (binomial(2 * m, i + j) * (2 * m + 1) as f64)
                })
                .collect()
        })
        .collect()
}

/// The Hessian (as a dense row-major `(d+1)² × (d+1)²` matrix, indices `i·(d+1) + j`) of
/// `E` for one patch of degree `d ≥ 4`: `E(P) = Σ pₐ·pᵦ Hₐᵦ` per coordinate.
pub(crate) fn patch_hessian(d: usize) -> Vec<f64> {
    assert!(d >= 4, "the energy needs degree ≥ 4");
    let g = gram(d);
    let g4 = gram(d - 4);
    let falling: f64 = (0..4).map(|j| (d - j) as f64).product();
    // D[i][a]: ∂⁴ Bᵈᵢ = Σₐ D[i][a] Bᵈ⁻⁴ₐ.
    let mut dm = vec![vec![0.0; d - 3]; d + 1];
    for i in 0..=d {
        for j in 0..=4usize {
            let a = i as isize - j as isize;
            if a >= 0 && (a as usize) <= d - 4 {
                let sign = if (4 - j) % 2 == 0 { 1.0 } else { -1.0 };
                dm[i][a as usize] += falling * sign * binomial(4, j);
            }
        }
    }
    let mut k = vec![vec![0.0; d + 1]; d + 1];
    for i in 0..=d {
        for l in 0..=d {
            let mut s = 0.0;
            for a in 0..=d - 4 {
                for b in 0..=d - 4 {
                    s += dm[i][a] * g4[a][b] * dm[l][b];
                }
            }
            k[i][l] = s;
        }
    }
    let n = d + 1;
    let mut h = vec![0.0; n * n * n * n];
    for i in 0..n {
        for j in 0..n {
            for a in 0..n {
                for b in 0..n {
                    h[(i * n + j) * n * n + a * n + b] = k[i][a] * g[j][b] + g[i][a] * k[j][b];
                }
            }
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::g2cap::BezierPatch;

    fn energy(h: &[f64], p: &[[f64; 3]]) -> f64 {
        let n = p.len();
        let mut e = 0.0;
        for a in 0..n {
            for b in 0..n {
                e += h[a * n + b] * (0..3).map(|k| p[a][k] * p[b][k]).sum::<f64>();
            }
        }
        e
    }

    /// Zero for every bicubic (here a random one, degree-elevated to 7).
    #[test]
    fn zero_for_bicubics() {
        let mut cp = [[[0.0; 3]; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                cp[i][j] = [(i * j) as f64, ((i + 2 * j) as f64).sin(), (i as f64).exp()];
            }
        }
        let p = BezierPatch::from_bicubic_bspline(&cp).elevated_to(7);
        let h = patch_hessian(7);
        assert!(energy(&h, p.points()).abs() < 1e-6);
    }

    /// `P = (u⁴, 0, 0)` has `∂⁴ᵤP = 24`, so `E = 24² = 576` (closed form).
    #[test]
    fn closed_form_for_u_to_the_fourth() {
        // Bézier coefficients of u⁴ in degree 7: C(i,4)/C(7,4).
        let pts: Vec<[f64; 3]> = (0..8)
            .flat_map(|i| (0..8).map(move |_| [binomial(i, 4) / binomial(7, 4), 0.0, 0.0]))
            .collect();
        let h = patch_hessian(7);
        assert!((energy(&h, &pts) - 576.0).abs() < 1e-8);
    }
}
