//! [`DenseCapSolver`]: the cap's constrained energy minimisation solved as one system over
//! all `n` patches — the direct formulation, kept as the independent reference that the
//! production per-frequency solver ([`CapSolver`](super::CapSolver)) is tested and
//! benchmarked against.
//!
//! The inner G2 conditions are imposed by collocation: the three rows of [`inner_rows`]
//! at [`INNER_SAMPLES`] Chebyshev points of every inner edge (more than the degree ≤ 10
//! of the identities, so they hold everywhere), each row scaled to unit length. This
//! gives `A_free x_free + A_fixed x_fixed = 0` over all `64n` control points, solved by
//! the null-space method of [`constrained_minimiser`] on the full system (`25n` unknowns,
//! `72n` rows). It is slower (one SVD of a `72n × 25n` matrix, `O(n³)`, against
//! `⌊n/2⌋ + 1` SVDs of at most `34 × 50`) and worse conditioned than
//! [`CapSolver`](super::CapSolver): sampled values of the identities, rather than their
//! Bernstein coefficients, mix the rows that only involve fixed points with the others,
//! and the data's rounding reaches the solution amplified by `~10⁵` (see the `solver`
//! module docs). On consistent data both give the same caps, to this solver's rounding.

use super::energy::patch_hessian;
use super::solver::{chebyshev, constrained_minimiser, inner_rows, patch_indices, NP};
use super::transition::Transitions;
use super::G2Error;
use nalgebra::DMatrix;

/// Collocation points per inner edge of the reference solver.
pub const INNER_SAMPLES: usize = 24;

/// The inner G2 conditions of a valence-`n` cap sampled at [`INNER_SAMPLES`] Chebyshev
/// points of every inner edge, over all `64n` control points (row `(i·INNER_SAMPLES + s)·3
/// + k`: edge `i`, sample `s`, order `k`), each row scaled to unit length.
pub(crate) fn sampled_rows(tr: &Transitions) -> DMatrix<f64> {
    let n = tr.valence();
    let mut a = DMatrix::<f64>::zeros(3 * INNER_SAMPLES * n, NP * n);
    for i in 0..n {
        let next = (i + 1) % n;
        for s in 0..INNER_SAMPLES {
            let r = inner_rows(tr, chebyshev(INNER_SAMPLES, s));
            for k in 0..3 {
                let row = (i * INNER_SAMPLES + s) * 3 + k;
                for m in 0..NP {
                    a[(row, i * NP + m)] += r[k][m];
                    a[(row, next * NP + m)] += r[k][NP + m];
                }
            }
        }
    }
    for mut row in a.row_iter_mut() {
        let norm = row.norm();
        if norm > 0.0 {
            row /= norm;
        }
    }
    a
}

/// The all-sectors reference solver of one valence: `x_free = W x_fixed`.
#[derive(Clone, Debug)]
pub struct DenseCapSolver {
    transitions: Transitions,
    free: Vec<usize>,
    fixed: Vec<usize>,
    w: DMatrix<f64>,
}

impl DenseCapSolver {
    /// Builds the reference solver for valence `n` (`3 ≤ n ≤ MAX_CAP_VALENCE`).
    ///
    /// # Errors
    /// [`G2Error::Valence`] outside the supported range; [`G2Error::Inconsistent`] if the
    /// reduced energy is not positive definite (not expected).
    pub fn new(n: usize) -> Result<Self, G2Error> {
        super::solver::check_valence(n)?;
        let tr = Transitions::new(n);
        let (free, fixed) = patch_indices(n);
        let a = sampled_rows(&tr);
        let hp = patch_hessian(7);
        let total = NP * n;
        let h = DMatrix::from_fn(total, total, |r, c| {
            if r / NP == c / NP {
                hp[(r % NP) * NP + c % NP]
            } else {
                0.0
            }
        });
        let h_ff = h.select_rows(free.iter()).select_columns(free.iter());
        let h_fc = h.select_rows(free.iter()).select_columns(fixed.iter());
        let a_free = a.select_columns(free.iter());
        let a_fixed = a.select_columns(fixed.iter());
        let w = constrained_minimiser(&a_free, &a_fixed, &h_ff, &h_fc).ok_or(
            G2Error::Inconsistent {
                valence: n,
                residual: f64::NAN,
            },
        )?;
        Ok(Self {
            transitions: tr,
            free,
            fixed,
            w,
        })
    }

    /// The valence.
    pub fn valence(&self) -> usize {
        self.transitions.valence()
    }

    /// The matrix `W` with `x_free = W x_fixed` (rows: the free control points, columns:
    /// the fixed ones, both in the order of [`CapSolver::weights`](super::CapSolver::weights)).
    pub fn weights(&self) -> &DMatrix<f64> {
        &self.w
    }

    /// Completes `n` bi-septic patches (`64n` points) whose outer rows are set, as
    /// [`CapSolver::complete`](super::CapSolver::complete) (without the residual check).
    ///
    /// # Errors
    /// [`G2Error::OuterCount`] if `points.len() != 64n`.
    pub fn complete(&self, points: &mut [[f64; 3]]) -> Result<(), G2Error> {
        let n = self.valence();
        super::solver::check_count(points, n)?;
        let centre = super::solver::centroid(points, &self.fixed);
        let xf = DMatrix::from_fn(self.fixed.len(), 3, |r, c| {
            points[self.fixed[r]][c] - centre[c]
        });
        let x = &self.w * xf;
        for (r, &g) in self.free.iter().enumerate() {
            for c in 0..3 {
                points[g][c] = x[(r, c)] + centre[c];
            }
        }
        Ok(())
    }
}
