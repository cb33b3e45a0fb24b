//! [`CapSolver`]: the constrained energy minimisation of a cap, solved per Fourier
//! frequency of the sector index and precomputed per valence.
//!
//! # The system
//! Unknowns are the control points of the `n` bi-septic patches, `pᵢ,ₐᵦ` with the
//! extraordinary vertex at `(0, 0)` of every patch. The three rows of control points next
//! to the outer edges (`a ≥ 5` or `b ≥ 5`, 39 per patch) are fixed by the outer G2
//! conditions ([`super::cap::outer_rows`]); the other 25 per patch (`a, b ≤ 4`) are free.
//! The inner G2 conditions of edge `i` (position, first and second cross derivative of
//! [`Transitions::inner`](super::Transitions::inner), the rows of [`inner_rows`]) are
//! polynomial identities `Eₖ(t) = 0`, `k = 0, 1, 2`, of degree `dₖ` along the edge
//! ([`identity_degrees`]: 7, 7 and 9, or 10 for `n = 3`). They are imposed through their
//! Bernstein coefficients, `Eₖ = Σⱼ eₖⱼ Bᵈⱼ(t)` with `eₖⱼ` linear in the points of `Pᵢ`
//! and `Pᵢ₊₁` (computed by interpolation at `dₖ + 1` Chebyshev points, exact for degree
//! `dₖ`). Per edge this is `R₀ xᵢ + R₁ xᵢ₊₁ = 0` with the *same* `R₀, R₁` for every edge;
//! the energy ([`super::energy`]) is `Σᵢ xᵢᵀ H xᵢ`.
//!
//! # Fourier split ([Tang et al. 2017], §3.2; Loop & Schaefer 2008, §4)
//! The system commutes with the cyclic shift of the patches, so in the real discrete
//! Fourier basis of the sector index it is block diagonal. With `θ = 2πk/n` and
//! `xᵢ = a cos iθ + b sin iθ` (`a, b ∈ ℝ⁶⁴`, one frequency `k`),
//! `R₀ xᵢ + R₁ xᵢ₊₁ = cos iθ [(R₀ + cos θ R₁) a + sin θ R₁ b]
//!                    + sin iθ [-sin θ R₁ a + (R₀ + cos θ R₁) b]`
//! and `Σᵢ xᵢᵀ H xᵢ = n/2 (aᵀHa + bᵀHb)`, so frequency `k` (`0 < k < n/2`, covering `k` and
//! `n - k`) is the system `[[D, E], [-E, D]] (a, b) = 0`, `D = R₀ + cos θ R₁`,
//! `E = sin θ R₁`, with energy `aᵀHa + bᵀHb`: 50 free unknowns, 78 fixed. Frequencies
//! `k = 0` and `k = n/2` (`n` even) are real (`sin θ = 0`): `D a = 0`, 25 unknowns. That
//! the blocks between different frequencies of the actual all-sectors constraint matrix
//! (the reference solver's) and of the energy vanish is checked numerically (tests:
//! `≤ 10⁻¹⁴` of the largest entry, `n = 3..=16`).
//!
//! Each frequency is solved by the null-space method ([`constrained_minimiser`]): with the
//! SVD `B_free = U Σ Vᵀ`, `x_free = x_p + Z y`, `x_p = -B_free⁺ B_fixed x_fixed`, `Z` an
//! orthonormal basis of `ker B_free` (singular values below [`RANK_TOLERANCE`] of the
//! largest), and `y` minimises the energy: `(ZᵀHZ) y = -Zᵀ(H_ff x_p + H_fc x_fixed)`, by
//! Cholesky (`ZᵀHZ` is positive definite: the only bicubic in the null space would be
//! `(1-u)³(1-v)³` on every patch, which the first-order inner condition rules out for
//! `c ≠ 1`). The result is a matrix per frequency, applied to the discrete Fourier
//! coefficients of the fixed points; the free points are their inverse transform.
//!
//! # Conditioning
//! The free points enter every edge identity with a factor `(1-t)³` (their weights
//! `B⁷ᵦ(t)`, `b ≤ 4`, on `Pᵢ(0, t)` and `B⁷ₐ(t)`, `a ≤ 4`, on `Pᵢ₊₁(t, 0)` vanish to third
//! order at `t = 1`), so the last three Bernstein coefficients of every identity involve
//! fixed points only (tested). They are *consistency* conditions on the outer data — met
//! by construction (the transitions' derivation at `t = 1`), but by real data only to
//! rounding — that no choice of free points can change. The reference solver
//! ([`DenseCapSolver`](super::DenseCapSolver)) imposes the identities by sampled values,
//! where every sample near `t = 1` mixes these conditions with tiny multiples of the free
//! points: its constraint matrix has a graded spectrum down to `~4·10⁻⁶` of the largest
//! singular value, its map `x_fixed ↦ x_free` has a norm of `~1.6·10⁵`, and the data's
//! rounding-level inconsistency moved the caps by `~2·10⁻¹⁰` of their size under ulp
//! perturbations of the mesh (measured). Here:
//!
//! 1. the 9 consistency rows per edge are eliminated from the solve (exactly redundant for
//!    the free points), and each identity is used in its own degree (in a higher degree
//!    it would hide further fixed-only combinations);
//! 2. the remaining rows are equilibrated (unit length; the derivative orders carry
//!    weights `~1`, `~7`, `~50`), and each frequency block gets its own rank decision
//!    (kept singular values `≥ ~10⁻³` of the largest, dropped ones `≤ ~10⁻¹⁵`);
//! 3. the fixed data is first projected orthogonally onto the kernel of the consistency
//!    rows ([`CapSolver::consistency_projector`]; 9 per edge and frequency component,
//!    singular values `≥ 0.27` of the largest): the inconsistent rounding is removed
//!    instead of being amplified. Consistent data is unchanged, so the caps are the same
//!    minimisers.
//!
//! The map's norm drops to `~25`, the caps' response to perturbations of the mesh is
//! linear down to ulps (`~0.5` of the perturbation), and ulp perturbations move the caps
//! by `≤ 5·10⁻¹⁴` of their size (`tests/integration/g2cap.rs`). The two solvers agree to the
//! reference's rounding (`≤ 4·10⁻¹⁰` of the size; `~10⁻¹⁰` typically).

use super::bernstein::bernstein;
use super::bezier::BezierPatch;
use super::energy::patch_hessian;
use super::transition::Transitions;
use super::G2Error;
use nalgebra::DMatrix;
use std::f64::consts::PI;

/// Degrees (in the parameter `t` along the edge) of the inner G2 identities of orders
/// 0, 1, 2 at valence `n`: `Pᵢ(0, t) - Pᵢ₊₁(t, 0)` has degree 7; the first-order row adds
/// `α(t) ∂ᵥPᵢ(0, t)`, `1 + 6 = 7`; the second-order row has `r₁(t) ∂ᵤPᵢ(0, t)`, `2 + 7 = 9`
/// (`3 + 7 = 10` for `n = 3`, whose `r₁, r₂` have the cubic resonance correction). Tested:
/// the Bernstein rows of these degrees reproduce [`inner_rows`] everywhere.
pub(crate) fn identity_degrees(n: usize) -> [usize; 3] {
    [7, 7, if n == 3 { 10 } else { 9 }]
}

/// Of an identity of degree `d`, the Bernstein coefficients `j ≤ d - 3` involve free points;
/// the last three (`j > d - 3`) only fixed ones (module docs).
const CONSISTENCY_ROWS: usize = 3;

/// Singular values below this fraction of the largest count as zero (null space of a
/// constraint block, rank of the consistency rows). Measured for `n = 3..=16`: per
/// frequency the kept singular values are `≥ 9·10⁻⁴` of the largest and the others
/// `≤ 2·10⁻¹⁶` (the cyclic conditions at the vertex); the all-sectors reference solver's
/// are `≥ 4·10⁻⁶` and `≤ 4·10⁻¹⁶`; the consistency rows have full rank (`≥ 0.27`).
pub(crate) const RANK_TOLERANCE: f64 = 1e-9;

/// Control points per bi-septic patch.
pub(crate) const NP: usize = 64;

/// Whether control point `(a, b)` of a patch is free (not fixed by the outer rows).
fn is_free(a: usize, b: usize) -> bool {
    a <= 4 && b <= 4
}

/// Local indices (`a·8 + b`) of the free and of the fixed control points of one patch.
fn local_indices() -> (Vec<usize>, Vec<usize>) {
    (0..NP).partition(|&m| is_free(m / 8, m % 8))
}

/// Global indices (`patch·64 + a·8 + b`) of the free and of the fixed control points of
/// `n` patches, patch by patch.
pub(crate) fn patch_indices(n: usize) -> (Vec<usize>, Vec<usize>) {
    (0..NP * n).partition(|&g| is_free((g % NP) / 8, g % 8))
}

/// [`G2Error::Valence`] unless `3 ≤ n ≤ MAX_CAP_VALENCE`.
pub(crate) fn check_valence(n: usize) -> Result<(), G2Error> {
    if (3..=super::MAX_CAP_VALENCE).contains(&n) {
        Ok(())
    } else {
        Err(G2Error::Valence {
            valence: n,
            max: super::MAX_CAP_VALENCE,
        })
    }
}

/// [`G2Error::OuterCount`] unless `points` holds the `64n` control points of `n` patches.
pub(crate) fn check_count(points: &[[f64; 3]], n: usize) -> Result<(), G2Error> {
    if points.len() != NP * n {
        return Err(G2Error::OuterCount {
            valence: n,
            got: points.len() / NP,
        });
    }
    Ok(())
}

/// The centroid of the points at `indices`.
pub(crate) fn centroid(points: &[[f64; 3]], indices: &[usize]) -> [f64; 3] {
    let mut centre = [0.0; 3];
    for &g in indices {
        for c in 0..3 {
            centre[c] += points[g][c];
        }
    }
    centre.map(|x| x / indices.len().max(1) as f64)
}

/// The null-space method for `min xᵀHx` subject to `B_free x_free + B_fixed x_fixed = 0`
/// (least squares where inconsistent): returns `W` with `x_free = W x_fixed`, or `None` if
/// the SVD fails or the reduced Hessian is not positive definite. Singular values below
/// [`RANK_TOLERANCE`] of the largest count as zero.
pub(crate) fn constrained_minimiser(
    b_free: &DMatrix<f64>,
    b_fixed: &DMatrix<f64>,
    h_ff: &DMatrix<f64>,
    h_fc: &DMatrix<f64>,
) -> Option<DMatrix<f64>> {
    let nf = b_free.ncols();
    // Pad with zero rows so that Vᵀ is square (nalgebra's thin SVD).
    let rows = b_free.nrows().max(nf);
    let mut padded = DMatrix::<f64>::zeros(rows, nf);
    padded
        .view_mut((0, 0), (b_free.nrows(), nf))
        .copy_from(b_free);
    let svd = padded.svd(true, true);
    let (u, vt) = (svd.u?, svd.v_t?);
    let sv = &svd.singular_values;
    let smax = sv.max();
    // Classify each singular triple (nalgebra does not promise an order).
    let keep: Vec<usize> = (0..sv.len())
        .filter(|&k| sv[k] > RANK_TOLERANCE * smax)
        .collect();
    let null: Vec<usize> = (0..nf).filter(|k| !keep.contains(k)).collect();
    // x_p = -V Σ⁻¹ Uᵀ B_fixed x_fixed on the range.
    let ub = u.transpose();
    let mut p1 = DMatrix::<f64>::zeros(nf, b_fixed.ncols());
    for &k in &keep {
        let coeff = ub.row(k).columns(0, b_free.nrows()) * b_fixed / sv[k];
        p1 -= vt.row(k).transpose() * coeff;
    }
    let z = vt.select_rows(null.iter()).transpose();
    if z.ncols() == 0 {
        return Some(p1);
    }
    let k = z.transpose() * h_ff * &z;
    let chol = k.cholesky()?;
    let rhs = z.transpose() * (h_ff * &p1 + h_fc);
    let y = -chol.solve(&rhs);
    Some(p1 + &z * y)
}

/// The inner G2 identities of one edge in Bernstein form.
#[derive(Clone, Debug)]
pub(crate) struct EdgeRows {
    /// Weights over the control points of `Pᵢ` (`r0`) and of `Pᵢ₊₁` (`r1`); one row per
    /// Bernstein coefficient `eₖⱼ`, order by order (`j = 0..=dₖ`).
    pub r0: DMatrix<f64>,
    pub r1: DMatrix<f64>,
    /// The rows that involve free points (all but the last three of every order).
    pub kept: Vec<usize>,
}

/// The orthogonal projector `I - D⁺D` onto the kernel of `d` (the fixed data that meets
/// the consistency rows `d`), with `D⁺D = Σ vⱼvⱼᵀ` over the right singular vectors of
/// singular values above [`RANK_TOLERANCE`] of the largest; `None` if the SVD fails.
pub(crate) fn kernel_projector(d: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let nx = d.ncols();
    let mut p = DMatrix::<f64>::identity(nx, nx);
    let svd = d.clone().svd(false, true);
    let vt = svd.v_t?;
    let s = &svd.singular_values;
    let smax = s.max();
    for j in 0..s.len() {
        if s[j] > RANK_TOLERANCE * smax {
            let vj = vt.row(j).transpose();
            p -= &vj * vj.transpose();
        }
    }
    Some(p)
}

/// The Bernstein coefficients of the inner G2 identities of one edge, `Eₖ = Σⱼ eₖⱼ Bᵈⱼ(t)`
/// with `d = dₖ` of [`identity_degrees`], as weights over the control points of `Pᵢ` and
/// `Pᵢ₊₁`: computed by interpolating the rows of [`inner_rows`] at `dₖ + 1` Chebyshev
/// points (exact for polynomials of degree `dₖ`).
pub(crate) fn edge_coefficients(tr: &Transitions) -> EdgeRows {
    let degrees = identity_degrees(tr.valence());
    let total: usize = degrees.iter().map(|d| d + 1).sum();
    let mut r0 = DMatrix::zeros(total, NP);
    let mut r1 = DMatrix::zeros(total, NP);
    let mut kept = Vec::new();
    let mut offset = 0;
    for (k, &d) in degrees.iter().enumerate() {
        let c = DMatrix::from_fn(d + 1, d + 1, |m, j| {
            bernstein(d, j as isize, chebyshev(d + 1, m))
        });
        let inv = c
            .try_inverse()
            .unwrap_or_else(|| DMatrix::identity(d + 1, d + 1));
        let values: Vec<[Vec<f64>; 3]> = (0..=d)
            .map(|m| inner_rows(tr, chebyshev(d + 1, m)))
            .collect();
        for j in 0..=d {
            for (m, v) in values.iter().enumerate() {
                let w = inv[(j, m)];
                for q in 0..NP {
                    r0[(offset + j, q)] += w * v[k][q];
                    r1[(offset + j, q)] += w * v[k][NP + q];
                }
            }
        }
        kept.extend(offset..offset + d + 1 - CONSISTENCY_ROWS);
        offset += d + 1;
    }
    EdgeRows { r0, r1, kept }
}

/// The real Fourier basis over the sector index: for frequency `k` (`0 ≤ k ≤ n/2`) its
/// components (`cos`, and `sin` for `0 < k < n/2`) as functions of the sector `i`.
#[derive(Clone, Debug)]
struct Fourier {
    n: usize,
    /// `[k][component][i]`.
    basis: Vec<Vec<Vec<f64>>>,
    /// Analysis weights: coefficient = `weight · Σᵢ basis(i) xᵢ` (`1/n` or `2/n`).
    weight: Vec<f64>,
}

impl Fourier {
    fn new(n: usize) -> Self {
        let mut basis = Vec::new();
        let mut weight = Vec::new();
        for k in 0..=n / 2 {
            // Reduce i·k mod n first: the angles are exact multiples of 2π/n.
            let angle = |i: usize| 2.0 * PI * ((i * k) % n) as f64 / n as f64;
            let cos: Vec<f64> = (0..n).map(|i| angle(i).cos()).collect();
            if k == 0 || 2 * k == n {
                basis.push(vec![cos]);
                weight.push(1.0 / n as f64);
            } else {
                let sin = (0..n).map(|i| angle(i).sin()).collect();
                basis.push(vec![cos, sin]);
                weight.push(2.0 / n as f64);
            }
        }
        Self { n, basis, weight }
    }

    /// The block-circulant matrix over all sectors (blocks `rows × cols` per pair of
    /// sectors) whose frequency-`k` block is `blocks[k]` (stacked by component).
    fn assemble(&self, blocks: &[DMatrix<f64>], rows: usize, cols: usize) -> DMatrix<f64> {
        let n = self.n;
        let mut w = DMatrix::zeros(rows * n, cols * n);
        for (k, m) in blocks.iter().enumerate() {
            let basis = &self.basis[k];
            for i in 0..n {
                for j in 0..n {
                    let mut block = w.view_mut((i * rows, j * cols), (rows, cols));
                    for (ci, bi) in basis.iter().enumerate() {
                        for (cj, bj) in basis.iter().enumerate() {
                            let f = self.weight[k] * bi[i] * bj[j];
                            block += m.view((ci * rows, cj * cols), (rows, cols)) * f;
                        }
                    }
                }
            }
        }
        w
    }

    fn frequencies(&self) -> usize {
        self.basis.len()
    }

    /// `cos θ`, `sin θ` of frequency `k` (`θ = 2πk/n`).
    fn angle(&self, k: usize) -> (f64, f64) {
        let c = self.basis[k][0][1 % self.n];
        let s = self.basis[k].get(1).map_or(0.0, |b| b[1 % self.n]);
        (c, s)
    }
}

/// The constraint block of frequency `k` of the edge rows `(R₀, R₁)` (columns restricted
/// to one patch's `cols`): `D = R₀ + cos θ R₁` for a real frequency, else
/// `[[D, E], [-E, D]]` with `E = sin θ R₁` (module docs).
fn frequency_block(
    r0: &DMatrix<f64>,
    r1: &DMatrix<f64>,
    cos: f64,
    sin: f64,
    width: usize,
) -> DMatrix<f64> {
    let d = r0 + r1 * cos;
    if width == 1 {
        return d;
    }
    let e = r1 * sin;
    let (m, f) = d.shape();
    let mut b = DMatrix::zeros(2 * m, 2 * f);
    b.view_mut((0, 0), (m, f)).copy_from(&d);
    b.view_mut((0, f), (m, f)).copy_from(&e);
    b.view_mut((m, 0), (m, f)).copy_from(&(-&e));
    b.view_mut((m, f), (m, f)).copy_from(&d);
    b
}

/// `width` copies of `m` on the diagonal.
fn block_diagonal(m: &DMatrix<f64>, width: usize) -> DMatrix<f64> {
    let (r, c) = m.shape();
    let mut b = DMatrix::zeros(r * width, c * width);
    for w in 0..width {
        b.view_mut((w * r, w * c), (r, c)).copy_from(m);
    }
    b
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

/// The per-valence solver: one matrix per Fourier frequency from the fixed to the free
/// control points (module docs).
#[derive(Clone, Debug)]
pub struct CapSolver {
    transitions: Transitions,
    fourier: Fourier,
    /// Local indices of the free (25) and fixed (39) control points of a patch.
    free: Vec<usize>,
    fixed: Vec<usize>,
    /// Per frequency: free coefficients = `maps[k]` · fixed coefficients, both stacked by
    /// component (`cos`, then `sin`).
    maps: Vec<DMatrix<f64>>,
    /// Per frequency: the projector onto the consistent fixed coefficients.
    projectors: Vec<DMatrix<f64>>,
    /// All Bernstein-coefficient rows of an edge (for the residual check).
    r0: DMatrix<f64>,
    r1: DMatrix<f64>,
}

impl CapSolver {
    /// Builds the solver for valence `n` (`3 ≤ n ≤ MAX_CAP_VALENCE`; `n = 4` is allowed
    /// and reproduces the bicubic B-spline).
    ///
    /// # Errors
    /// [`G2Error::Valence`] outside the supported range; [`G2Error::Inconsistent`] if a
    /// frequency's reduced energy is not positive definite (not expected).
    pub fn new(n: usize) -> Result<Self, G2Error> {
        check_valence(n)?;
        let tr = Transitions::new(n);
        let (free, fixed) = local_indices();
        let EdgeRows { r0, r1, kept } = edge_coefficients(&tr);
        // Equilibration: every row scaled to unit length over both patches (the same
        // factor for every edge, so the system stays block circulant).
        let (mut e0, mut e1) = (r0.clone(), r1.clone());
        for r in 0..e0.nrows() {
            let norm = (e0.row(r).norm_squared() + e1.row(r).norm_squared()).sqrt();
            if norm > 0.0 {
                e0.row_mut(r).scale_mut(1.0 / norm);
                e1.row_mut(r).scale_mut(1.0 / norm);
            }
        }
        let columns = |m: &DMatrix<f64>, rows: &[usize], cols: &[usize]| {
            m.select_rows(rows.iter()).select_columns(cols.iter())
        };
        let dropped: Vec<usize> = (0..e0.nrows()).filter(|r| !kept.contains(r)).collect();
        // The solve uses the rows that involve free points; the projector the others.
        let (e0f, e1f) = (columns(&e0, &kept, &free), columns(&e1, &kept, &free));
        let (e0x, e1x) = (columns(&e0, &kept, &fixed), columns(&e1, &kept, &fixed));
        let (d0x, d1x) = (
            columns(&e0, &dropped, &fixed),
            columns(&e1, &dropped, &fixed),
        );
        let hp = DMatrix::from_row_slice(NP, NP, &patch_hessian(7));
        let h_ff = hp.select_rows(free.iter()).select_columns(free.iter());
        let h_fc = hp.select_rows(free.iter()).select_columns(fixed.iter());
        let fourier = Fourier::new(n);
        let mut maps = Vec::with_capacity(fourier.frequencies());
        let mut projectors = Vec::with_capacity(fourier.frequencies());
        for k in 0..fourier.frequencies() {
            let (cos, sin) = fourier.angle(k);
            let width = fourier.basis[k].len();
            let b_free = frequency_block(&e0f, &e1f, cos, sin, width);
            let b_fixed = frequency_block(&e0x, &e1x, cos, sin, width);
            let m = constrained_minimiser(
                &b_free,
                &b_fixed,
                &block_diagonal(&h_ff, width),
                &block_diagonal(&h_fc, width),
            )
            .ok_or(G2Error::Inconsistent {
                valence: n,
                residual: f64::NAN,
            })?;
            // Project the fixed data onto the consistent subspace first (module docs).
            let p = kernel_projector(&frequency_block(&d0x, &d1x, cos, sin, width)).ok_or(
                G2Error::Inconsistent {
                    valence: n,
                    residual: f64::NAN,
                },
            )?;
            maps.push(m * &p);
            projectors.push(p);
        }
        Ok(Self {
            transitions: tr,
            fourier,
            free,
            fixed,
            maps,
            projectors,
            r0,
            r1,
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

    /// The whole linear map `x_free = W x_fixed` over all patches, assembled from the
    /// per-frequency matrices: row `25i + l` is the `l`-th free control point (in the order
    /// `a·8 + b`) of patch `i`, column `39j + l` the `l`-th fixed one of patch `j`. `W` is
    /// block circulant (`W` depends on `j - i` only); it is what [`complete`](Self::complete)
    /// applies, and what the reference solver computes directly
    /// ([`DenseCapSolver::weights`](super::DenseCapSolver::weights)).
    pub fn weights(&self) -> DMatrix<f64> {
        self.fourier
            .assemble(&self.maps, self.free.len(), self.fixed.len())
    }

    /// The orthogonal projector `P` (`39n × 39n`, order as the columns of
    /// [`weights`](Self::weights)) onto the *consistent* fixed data: the outer rows that
    /// meet the consistency conditions (the last three Bernstein coefficients of every
    /// inner identity, which involve fixed points only; module docs). Outer rows from
    /// C2 bicubic neighbours are consistent (`P x = x` up to rounding), and
    /// `weights() = weights() · P`: the rounding-level inconsistency of real data is
    /// projected away instead of amplified.
    pub fn consistency_projector(&self) -> DMatrix<f64> {
        self.fourier
            .assemble(&self.projectors, self.fixed.len(), self.fixed.len())
    }

    /// Completes `n` bi-septic patches (`64n` points, patch by patch) whose outer rows
    /// (`a ≥ 5` or `b ≥ 5`) are set: fills in the free control points (the energy
    /// minimiser under the inner G2 constraints) and checks the constraint residual.
    /// Per frequency `k`, the Fourier coefficients of the fixed points (relative to their
    /// centroid: the solution is affine invariant, and this keeps the rounding relative to
    /// the cap's size) are mapped to those of the free points, which are then summed back.
    ///
    /// # Errors
    /// [`G2Error::OuterCount`] if `points.len() != 64n`; [`G2Error::Inconsistent`] if the
    /// constraints are not met to `1e-7` of the net's size (never expected).
    pub fn complete(&self, points: &mut [[f64; 3]]) -> Result<(), G2Error> {
        let n = self.valence();
        check_count(points, n)?;
        let fixed_global: Vec<usize> = (0..n)
            .flat_map(|i| self.fixed.iter().map(move |&l| i * NP + l))
            .collect();
        let centre = centroid(points, &fixed_global);
        for (g, p) in points.iter_mut().enumerate() {
            if is_free((g % NP) / 8, g % 8) {
                *p = centre;
            }
        }
        let (nf, nx) = (self.free.len(), self.fixed.len());
        for (k, m) in self.maps.iter().enumerate() {
            let basis = &self.fourier.basis[k];
            let scale = self.fourier.weight[k];
            let mut g = DMatrix::<f64>::zeros(nx * basis.len(), 3);
            for (cj, b) in basis.iter().enumerate() {
                for (i, &bi) in b.iter().enumerate() {
                    for (l, &m) in self.fixed.iter().enumerate() {
                        let p = points[i * NP + m];
                        for c in 0..3 {
                            g[(cj * nx + l, c)] += scale * bi * (p[c] - centre[c]);
                        }
                    }
                }
            }
            let f = m * g;
            for (ci, b) in basis.iter().enumerate() {
                for (i, &bi) in b.iter().enumerate() {
                    for (l, &m) in self.free.iter().enumerate() {
                        for c in 0..3 {
                            points[i * NP + m][c] += bi * f[(ci * nf + l, c)];
                        }
                    }
                }
            }
        }
        self.check(points)
    }

    /// The largest Bernstein coefficient of the inner G2 identities over all edges (all
    /// 33 per edge, including the consistency rows), relative to the net's size.
    fn check(&self, points: &[[f64; 3]]) -> Result<(), G2Error> {
        let n = self.valence();
        let (lo, hi) = bounds(points);
        let scale = (0..3).fold(0.0f64, |m, k| m.max(lo[k].abs()).max(hi[k].abs()));
        let size = (0..3)
            .map(|k| hi[k] - lo[k])
            .fold(0.0, f64::max)
            .max(scale * 1e-12)
            .max(f64::MIN_POSITIVE);
        let patch = |i: usize| DMatrix::from_fn(NP, 3, |r, c| points[i * NP + r][c] - lo[c]);
        let mut res = 0.0f64;
        for i in 0..n {
            let e = &self.r0 * patch(i) + &self.r1 * patch((i + 1) % n);
            res = res.max(e.amax());
        }
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

    /// The Bernstein rows of [`edge_coefficients`] are the identities themselves: summed
    /// against `Bᵈⱼ(t)` they give [`inner_rows`] at any `t` (so the degrees of
    /// [`identity_degrees`] are high enough).
    #[test]
    fn bernstein_rows_reproduce_the_identities_along_the_edge() {
        for n in [3, 4, 5, 6, 8, 11, 16] {
            let tr = Transitions::new(n);
            let rows = edge_coefficients(&tr);
            for t in [0.0, 0.013, 0.29, 0.5, 0.77, 0.999, 1.0] {
                let direct = inner_rows(&tr, t);
                let mut offset = 0;
                for (k, &d) in identity_degrees(n).iter().enumerate() {
                    for q in 0..NP {
                        let (mut a, mut b) = (0.0, 0.0);
                        for j in 0..=d {
                            let w = bernstein(d, j as isize, t);
                            a += w * rows.r0[(offset + j, q)];
                            b += w * rows.r1[(offset + j, q)];
                        }
                        let scale = 1.0 + direct[k][q].abs() + direct[k][NP + q].abs();
                        assert!(
                            (a - direct[k][q]).abs() < 1e-11 * scale,
                            "n {n} t {t} k {k}"
                        );
                        assert!(
                            (b - direct[k][NP + q]).abs() < 1e-11 * scale,
                            "n {n} t {t} k {k}"
                        );
                    }
                    offset += d + 1;
                }
            }
        }
    }

    /// The last three Bernstein coefficients of every identity involve fixed points only
    /// (their free weights vanish to rounding), and every other row involves free points.
    #[test]
    fn consistency_rows_involve_fixed_points_only() {
        let (free, _) = local_indices();
        for n in 3..=MAX_TEST_VALENCE {
            let rows = edge_coefficients(&Transitions::new(n));
            let largest = rows.r0.amax().max(rows.r1.amax());
            for r in 0..rows.r0.nrows() {
                let on_free = free
                    .iter()
                    .map(|&q| rows.r0[(r, q)].abs().max(rows.r1[(r, q)].abs()))
                    .fold(0.0, f64::max);
                if rows.kept.contains(&r) {
                    assert!(on_free > 1e-6 * largest, "n {n} row {r}: {on_free:e}");
                } else {
                    assert!(on_free < 1e-13 * largest, "n {n} row {r}: {on_free:e}");
                }
            }
            assert_eq!(rows.r0.nrows() - rows.kept.len(), 9);
        }
    }

    /// The orthonormal real Fourier matrix over the sectors (rows: frequency components
    /// in the order of [`Fourier`]), and the frequency of each row.
    fn fourier_matrix(n: usize) -> (DMatrix<f64>, Vec<usize>) {
        let f = Fourier::new(n);
        let mut q = DMatrix::zeros(n, n);
        let mut freq = Vec::new();
        let mut r = 0;
        for k in 0..f.frequencies() {
            for b in &f.basis[k] {
                let norm = b.iter().map(|x| x * x).sum::<f64>().sqrt();
                for i in 0..n {
                    q[(r, i)] = b[i] / norm;
                }
                freq.push(k);
                r += 1;
            }
        }
        (q, freq)
    }

    /// `(Q ⊗ I) A (Q ⊗ I)ᵀ` for a matrix of `n × n` blocks of size `rows × cols`.
    fn transform(a: &DMatrix<f64>, q: &DMatrix<f64>, rows: usize, cols: usize) -> DMatrix<f64> {
        let n = q.nrows();
        let mut t = DMatrix::zeros(n * rows, n * cols);
        for p in 0..n {
            for s in 0..n {
                let mut block = t.view_mut((p * rows, s * cols), (rows, cols));
                for i in 0..n {
                    for j in 0..n {
                        let f = q[(p, i)] * q[(s, j)];
                        if f != 0.0 {
                            block += a.view((i * rows, j * cols), (rows, cols)) * f;
                        }
                    }
                }
            }
        }
        t
    }

    /// The actual all-sectors constraint matrix (the reference solver's sampled rows) and
    /// the energy are block diagonal in the real Fourier basis of the sector index: every
    /// block between different frequencies vanishes to rounding. This is what the
    /// per-frequency solve relies on.
    #[test]
    fn constraints_and_energy_are_block_diagonal_per_frequency() {
        for n in [3, 4, 5, 6, 7, 8, 12, 16] {
            let tr = Transitions::new(n);
            let (q, freq) = fourier_matrix(n);
            let a = super::super::dense::sampled_rows(&tr);
            let rows = a.nrows() / n;
            let hp = DMatrix::from_row_slice(NP, NP, &patch_hessian(7));
            let h = DMatrix::from_fn(NP * n, NP * n, |r, c| {
                if r / NP == c / NP {
                    hp[(r % NP, c % NP)]
                } else {
                    0.0
                }
            });
            for (m, rows) in [(a, rows), (h, NP)] {
                let t = transform(&m, &q, rows, NP);
                let largest = t.amax();
                let mut off = 0.0f64;
                let mut on = 0.0f64;
                for p in 0..n {
                    for s in 0..n {
                        let block = t.view((p * rows, s * NP), (rows, NP)).amax();
                        if freq[p] == freq[s] {
                            on = on.max(block);
                        } else {
                            off = off.max(block);
                        }
                    }
                }
                assert!(
                    off <= 1e-14 * largest,
                    "n {n}: off-diagonal {off:e} of {largest:e}"
                );
                assert!(on > 0.1 * largest, "n {n}");
            }
        }
    }

    /// The per-frequency solution is the all-sectors one: on consistent data (the range
    /// of the projector) the reference solver's weights equal the per-frequency weights,
    /// `W_dense P = W` to `1e-9` of their size (the reference's own rounding is
    /// `~1e-10`), and `W P = W`.
    #[test]
    fn per_frequency_weights_are_the_all_sectors_weights() {
        for n in [3, 4, 5, 7, 8] {
            let s = CapSolver::new(n).unwrap();
            let d = super::super::DenseCapSolver::new(n).unwrap();
            let (w, p) = (s.weights(), s.consistency_projector());
            let scale = w.amax();
            let e = (d.weights() * &p - &w).amax();
            assert!(e <= 1e-9 * scale, "n {n}: {e:e} of {scale:e}");
            assert!((&w * &p - &w).amax() <= 1e-12 * scale, "n {n}");
            // P is an orthogonal projector.
            assert!((&p * &p - &p).amax() < 1e-12 && (p.transpose() - &p).amax() < 1e-12);
        }
    }
}
