//! Bernstein polynomials `Bⁿᵢ(t) = C(n, i) tⁱ (1 - t)ⁿ⁻ⁱ` and their derivatives (Farin,
//! *Curves and Surfaces for CAGD*, 5th ed., §5.3):
//!
//! `dᵏ/dtᵏ Bⁿᵢ(t) = n!/(n-k)! · Σⱼ₌₀..ₖ (-1)ᵏ⁻ʲ C(k, j) Bⁿ⁻ᵏᵢ₋ⱼ(t)`.

/// The binomial coefficient `C(n, k)` (0 when `k > n`).
pub(super) fn binomial(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    let mut r = 1.0;
    for j in 0..k.min(n - k) {
        r = r * (n - j) as f64 / (j + 1) as f64;
    }
    r
}

/// `Bⁿᵢ(t)`, zero for `i` outside `0..=n`.
pub(super) fn bernstein(n: usize, i: isize, t: f64) -> f64 {
    if i < 0 || i as usize > n {
        return 0.0;
    }
    let i = i as usize;
    binomial(n, i) * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32)
}

/// The `k`-th derivative of `Bⁿᵢ` at `t` (zero for `k > n`).
pub(super) fn bernstein_derivative(n: usize, i: usize, t: f64, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    let falling: f64 = (0..k).map(|j| (n - j) as f64).product();
    let mut s = 0.0;
    for j in 0..=k {
        let sign = if (k - j).is_multiple_of(2) { 1.0 } else { -1.0 };
        s += sign * binomial(k, j) * bernstein(n - k, i as isize - j as isize, t);
    }
    falling * s
}

/// All `n + 1` values of the `k`-th derivative of the degree-`n` Bernstein basis at `t`.
pub(super) fn basis_derivatives(n: usize, t: f64, k: usize) -> Vec<f64> {
    (0..=n).map(|i| bernstein_derivative(n, i, t, k)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bernstein_basis_is_a_partition_of_unity() {
        for n in 0..9 {
            for s in 0..=10 {
                let t = s as f64 / 10.0;
                let sum: f64 = (0..=n as isize).map(|i| bernstein(n, i, t)).sum();
                assert!((sum - 1.0).abs() < 1e-14);
            }
        }
    }

    /// Derivatives agree with central differences of the next lower derivative.
    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-6;
        for n in [3, 7] {
            for i in 0..=n {
                for k in 1..4 {
                    for s in 1..10 {
                        let t = s as f64 / 10.0;
                        let fd = (bernstein_derivative(n, i, t + h, k - 1)
                            - bernstein_derivative(n, i, t - h, k - 1))
                            / (2.0 * h);
                        let d = bernstein_derivative(n, i, t, k);
                        assert!((fd - d).abs() < 1e-5 * (1.0 + d.abs()), "n {n} i {i} k {k}");
                    }
                }
            }
        }
    }
}
