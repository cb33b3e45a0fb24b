//! [`CapSolver`]: the constrained energy minimisation of a cap, precomputed per valence.
//!
//! Unknowns are the control points of the `n` bi-septic patches, `pᵢ,ₐᵦ` with the
//! extraordinary vertex at `(0, 0)` of every patch. The three rows of control points next
//! to the outer edges (`a ≥ 5` or `b ≥ 5`) are fixed by the outer G2 conditions
//! ([`super::outer_rows`]); the other `25n` (`a, b ≤ 4`) are free. The inner G2
//! conditions (position, first and second cross derivative of
//! [`Transitions::inner`](super::Transitions::inner)) are polynomial identities of degree
//! ≤ 9 along each inner edge; they are imposed exactly by collocation at
//! [`INNER_SAMPLES`] Chebyshev points (more than the degree, so the identity holds
//! everywhere), giving `A_free x_free + A_fixed x_fixed = 0` — the same matrix for the
//! three coordinates. Many rows are dependent (the cyclic conditions at the vertex, and
//! the oversampling), so the system is solved by the null-space method with an SVD:
//! `x_free = x_p + Z y`, `x_p = -A⁺ A_fixed x_fixed`, `Z` an orthonormal basis of
//! `ker A_free`, and `y` minimises the energy ([`super::energy`]):
//! `(Zᵀ H Z) y = -Zᵀ (H_ff x_p + H_fc x_fixed)`, solved by Cholesky (`ZᵀHZ` is positive
//! definite: the only bicubic in the null space would be `(1-u)³(1-v)³` on every patch,
//! which the first-order inner condition rules out for `c ≠ 1`). Everything is linear
//! in `x_fixed`, so the solver stores the matrix `x_free = M x_fixed`.
//!
//! The paper splits the system into `n` independent blocks by a discrete Fourier
//! transform over the patch index (the system is block-circulant); this implementation
//! solves the full system once per valence instead (at most `400` unknowns for
//! `n = 16`), which gives the same minimiser.

use super::bezier::BezierPatch;
use super::energy::patch_hessian;
use super::transition::Transitions;
use super::G2Error;
use nalgebra::DMatrix;
use std::f64::consts::PI;

/// Collocation points per inner edge (the inner G2 identities have degree ≤ 9).
pub const INNER_SAMPLES: usize = 24;

/// Control points per bi-septic patch.
const NP: usize = 64;

/// Whether control point `(a, b)` of a patch is free (not fixed by the outer rows).
fn is_free(a: usize, b: usize) -> bool {
    a <= 4 && b <= 4
}

/// Chebyshev points of `[0, 1]`.
pub(crate) fn chebyshev(m: usize, k: usize) -> f64 {
    0.5 - 0.5 * ((2 * k + 1) as f64 * PI / (2 * m) as f64).cos()
}

/// The inner G2 rows of one edge at parameter `t`, as weights over the `2 × 64` control
/// points of `(Pᵢ, Pᵢ₊₁)`, for the orders `k = 0, 1, 2`:
///
/// * `Pᵢ(0,t) - Pᵢ₊₁(t,0)`,
/// * `ρ'ᵤ ∂ᵤPᵢ + ρ'ᵥ ∂ᵥPᵢ - ∂ᵥPᵢ₊₁`,
/// * `ρ'ᵤ² ∂ᵤᵤPᵢ + 2ρ'ᵤρ'ᵥ ∂ᵤᵥPᵢ + ρ'ᵥ² ∂ᵥᵥPᵢ + ρ''ᵤ ∂ᵤPᵢ + ρ''ᵥ ∂ᵥPᵢ - ∂ᵥᵥPᵢ₊₁`
///
/// (the chain rule for `∂ₛᵏ [Pᵢ∘ρ]` at `s = 0`), all evaluated at `(0, t)` for `Pᵢ` and
/// `(t, 0)` for `Pᵢ₊₁`.
pub fn inner_rows(tr: &Transitions, t: f64) -> [Vec<f64>; 3] {
    let j = tr.inner(t);
    let [x1, y1] = j.first;
    let [x2, y2] = j.second;
    let w = |a, b| BezierPatch::weights(7, 0.0, t, a, b);
    let q = |b| BezierPatch::weights(7, t, 0.0, 0, b);
    let (p0, pu, pv, puu, puv, pvv) = (w(0, 0), w(1, 0), w(0, 1), w(2, 0), w(1, 1), w(0, 2));
    let mut rows = [vec![0.0; 2 * NP], vec![0.0; 2 * NP], vec![0.0; 2 * NP]];
    let (q0, q1, q2) = (q(0), q(1), q(2));
    for m in 0..NP {
        rows[0][m] = p0[m];
        rows[1][m] = x1 * pu[m] + y1 * pv[m];
        rows[2][m] =
            x1 * x1 * puu[m] + 2.0 * x1 * y1 * puv[m] + y1 * y1 * pvv[m] + x2 * pu[m] + y2 * pv[m];
        rows[0][NP + m] = -q0[m];
        rows[1][NP + m] = -q1[m];
        rows[2][NP + m] = -q2[m];
    }
    rows
}

/// The per-valence solver: the matrix from the fixed to the free control points.
#[derive(Clone, Debug)]
pub struct CapSolver {
    transitions: Transitions,
    /// Global indices (`patch·64 + a·8 + b`) of the free and the fixed control points.
    free: Vec<usize>,
    fixed: Vec<usize>,
    /// `x_free = m · x_fixed`.
    m: DMatrix<f64>,
    /// The constraint matrix over all `64n` control points (for the residual check).
    a: DMatrix<f64>,
}

impl CapSolver {
    /// Builds the solver for valence `n` (`3 ≤ n ≤ MAX_CAP_VALENCE`; `n = 4` is allowed
    /// and reproduces the bicubic B-spline).
    ///
    /// # Errors
    /// [`G2Error::Valence`] outside the supported range.
    pub fn new(n: usize) -> Result<Self, G2Error> {
        if !(3..=super::MAX_CAP_VALENCE).contains(&n) {
            return Err(G2Error::Valence {
                valence: n,
                max: super::MAX_CAP_VALENCE,
            });
        }
        let tr = Transitions::new(n);
        let total = NP * n;
        let mut free = Vec::new();
        let mut fixed = Vec::new();
        for p in 0..n {
            for a in 0..8 {
                for b in 0..8 {
                    let g = p * NP + a * 8 + b;
                    if is_free(a, b) {
                        free.push(g);
                    } else {
                        fixed.push(g);
                    }
                }
            }
        }
        let rows = 3 * INNER_SAMPLES * n;
        let mut a = DMatrix::<f64>::zeros(rows, total);
        for i in 0..n {
            let next = (i + 1) % n;
            for s in 0..INNER_SAMPLES {
                let t = chebyshev(INNER_SAMPLES, s);
                let r = inner_rows(&tr, t);
                for k in 0..3 {
                    let row = (i * INNER_SAMPLES + s) * 3 + k;
                    for m in 0..NP {
                        a[(row, i * NP + m)] += r[k][m];
                        a[(row, next * NP + m)] += r[k][NP + m];
                    }
                }
            }
        }
        // Scale every row to unit length: the same conditions, better conditioned (the
        // second-derivative rows carry weights ~10³).
        for mut row in a.row_iter_mut() {
            let norm = row.norm();
            if norm > 0.0 {
                row /= norm;
            }
        }
        let a_free = a.select_columns(free.iter());
        let a_fixed = a.select_columns(fixed.iter());
        // Hessian, block diagonal over the patches.
        let hp = patch_hessian(7);
        let mut h = DMatrix::<f64>::zeros(total, total);
        for p in 0..n {
            for x in 0..NP {
                for y in 0..NP {
                    h[(p * NP + x, p * NP + y)] = hp[x * NP + y];
                }
            }
        }
        let h_ff = h.select_rows(free.iter()).select_columns(free.iter());
        let h_fc = h.select_rows(free.iter()).select_columns(fixed.iter());

        let svd = a_free.clone().svd(true, true);
        let (u, vt) = match (svd.u, svd.v_t) {
            (Some(u), Some(vt)) => (u, vt),
            _ => {
                return Err(G2Error::Inconsistent {
                    valence: n,
                    residual: f64::NAN,
                })
            }
        };
        let sv = &svd.singular_values;
        let smax = sv.max();
        let nf = free.len();
        // Classify each singular triple (nalgebra does not promise an order).
        let keep: Vec<usize> = (0..sv.len()).filter(|&k| sv[k] > 1e-11 * smax).collect();
        let null: Vec<usize> = (0..nf).filter(|k| !keep.contains(k)).collect();
        // A⁺ = V Σ⁻¹ Uᵀ on the range.
        let mut pinv = DMatrix::<f64>::zeros(nf, rows);
        for &k in &keep {
            let vk = vt.row(k).transpose();
            let uk = u.column(k);
            pinv += (vk * uk.transpose()) / sv[k];
        }
        // Null space: the rows of Vᵀ (nf × nf, as rows ≥ nf) with zero singular value.
        let z = vt.select_rows(null.iter()).transpose();
        let p1 = -(&pinv * &a_fixed);
        let k = z.transpose() * &h_ff * &z;
        let chol = k.cholesky().ok_or(G2Error::Inconsistent {
            valence: n,
            residual: f64::NAN,
        })?;
        let rhs = z.transpose() * (&h_ff * &p1 + &h_fc);
        let y = -chol.solve(&rhs);
        let m = p1 + &z * y;
        Ok(Self {
            transitions: tr,
            free,
            fixed,
            m,
            a,
        })
    }

    /// The valence.
    pub fn valence(&self) -> usize {
        self.transitions.valence()
    }

    /// The transition maps used.
    pub fn transitions(&self) -> &Transitions {
        &self.transitions
    }

    /// Completes `n` bi-septic patches whose outer rows (`a ≥ 5` or `b ≥ 5`) are set:
    /// fills in the free control points (the energy minimiser under the inner G2
    /// constraints) and checks the constraint residual.
    ///
    /// # Errors
    /// [`G2Error::Inconsistent`] if the constraints are not met to `1e-7` of the net's
    /// size (never expected).
    pub fn complete(&self, points: &mut [[f64; 3]]) -> Result<(), G2Error> {
        let n = self.valence();
        debug_assert_eq!(points.len(), NP * n);
        // Solve for the offsets from the centroid of the fixed points (the solution is
        // affine invariant): keeps the rounding relative to the cap's size, not to its
        // distance from the origin.
        let mut centre = [0.0; 3];
        for &g in &self.fixed {
            for c in 0..3 {
                centre[c] += points[g][c] / self.fixed.len() as f64;
            }
        }
        let xf = DMatrix::from_fn(self.fixed.len(), 3, |r, c| {
            points[self.fixed[r]][c] - centre[c]
        });
        let x = &self.m * xf;
        for (r, &g) in self.free.iter().enumerate() {
            for c in 0..3 {
                points[g][c] = x[(r, c)] + centre[c];
            }
        }
        let all = DMatrix::from_fn(points.len(), 3, |r, c| points[r][c]);
        let res = (&self.a * &all).amax();
        let scale = all.amax().max(1e-300);
        let (lo, hi) = bounds(points);
        let size = (0..3)
            .map(|k| hi[k] - lo[k])
            .fold(0.0, f64::max)
            .max(scale * 1e-12);
        // Rows are derivative identities with weights up to ~7² · 8; compare to the size.
        let rel = res / size;
        if rel.is_nan() || rel > 1e-7 {
            return Err(G2Error::Inconsistent {
                valence: n,
                residual: rel,
            });
        }
        Ok(())
    }
}

/// Componentwise bounds of a point set.
fn bounds(points: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The inner rows are the chain rule of `∂ₛᵏ [Pᵢ∘ρ]`: for patches related exactly by a
    /// map with that jet, `Pᵢ₊₁ := Pᵢ∘ρ` (computed by finite differences of the
    /// composition), every row vanishes.
    #[test]
    fn inner_rows_are_the_chain_rule_of_the_composition() {
        let tr = Transitions::new(5);
        // A random bi-septic Pᵢ.
        let pts: Vec<[f64; 3]> = (0..64)
            .map(|k| {
                let x = k as f64;
                [(0.7 * x).sin(), (1.3 * x).cos(), (0.1 * x * x).sin()]
            })
            .collect();
        let p = BezierPatch::new(7, pts).unwrap();
        let t = 0.37;
        let j = tr.inner(t);
        let rho = |s: f64| {
            (
                j.first[0] * s + 0.5 * j.second[0] * s * s,
                t + j.first[1] * s + 0.5 * j.second[1] * s * s,
            )
        };
        let q = |s: f64| {
            let (u, v) = rho(s);
            p.derivative(u, v, 0, 0)
        };
        let h = 1e-4;
        let (q0, qp, qm) = (q(0.0), q(h), q(-h));
        let d1: Vec<f64> = (0..3).map(|k| (qp[k] - qm[k]) / (2.0 * h)).collect();
        let d2: Vec<f64> = (0..3)
            .map(|k| (qp[k] - 2.0 * q0[k] + qm[k]) / (h * h))
            .collect();
        let rows = inner_rows(&tr, t);
        for (order, expect) in [(1usize, &d1), (2, &d2)] {
            for k in 0..3 {
                // Row applied to (Pᵢ, 0) gives ∂ₛᵏ[Pᵢ∘ρ]; the Pᵢ₊₁ part is -∂ᵥᵏ Pᵢ₊₁.
                let got: f64 = (0..NP).map(|m| rows[order][m] * p.points()[m][k]).sum();
                assert!(
                    (got - expect[k]).abs() < 1e-5 * (1.0 + got.abs()),
                    "order {order}"
                );
            }
        }
        let got: f64 = (0..NP).map(|m| rows[0][m] * p.points()[m][0]).sum();
        assert!((got - q0[0]).abs() < 1e-12);
    }

    /// The reduced Hessian is positive definite for every valence (unique minimiser),
    /// i.e. the solver builds.
    #[test]
    fn solvers_build_for_every_supported_valence() {
        for n in 3..=MAX_TEST_VALENCE {
            assert!(CapSolver::new(n).is_ok(), "valence {n}");
        }
        assert!(CapSolver::new(2).is_err());
        assert!(CapSolver::new(super::super::MAX_CAP_VALENCE + 1).is_err());
    }

    const MAX_TEST_VALENCE: usize = 10;
}
