//! B-spline basis functions and their derivatives by the Cox–de Boor recursion.
//!
//! `N_{i,0}(t) = 1` on `[t_i, t_{i+1})`, else 0, and
//! `N_{i,p}(t) = (t − t_i) / (t_{i+p} − t_i) · N_{i,p−1}(t)
//!            + (t_{i+p+1} − t) / (t_{i+p+1} − t_{i+1}) · N_{i+1,p−1}(t)`
//! (The NURBS Book, eq. 2.5). On the span `[t_k, t_{k+1})` only `N_{k−p,p} … N_{k,p}` are
//! non-zero; they are computed together, without divisions by zero, by The NURBS Book
//! algorithm A2.2 (values) and A2.3 (derivatives, eq. 2.10). They are non-negative and sum
//! to one (partition of unity, P2.4 and P2.5).
//!
//! ```
//! use subsurf::nurbs::{basis_functions, KnotVector};
//! let k = KnotVector::new(3, vec![0.0, 0.0, 0.0, 0.0, 0.3, 1.0, 2.5, 2.5, 2.5, 2.5])?;
//! for t in [0.0, 0.1, 0.3, 0.7, 1.9, 2.5] {
//!     let (span, n) = basis_functions(&k, t)?;
//!     assert!(n.iter().all(|&x| x >= 0.0));
//!     assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-15);
//!     assert!(span >= 3 && span < 6);
//! }
//! # Ok::<(), subsurf::nurbs::NurbsError>(())
//! ```

use super::{KnotVector, NurbsError};

/// The `p + 1` basis functions that are non-zero at `t`: returns the span `k` and
/// `[N_{k−p,p}(t), …, N_{k,p}(t)]` (The NURBS Book A2.2). For a periodic knot vector `t` is
/// first wrapped into the period.
///
/// # Errors
/// [`NurbsError::ParameterOutOfDomain`] (see [`KnotVector::parameter`]).
pub fn basis_functions(knots: &KnotVector, t: f64) -> Result<(usize, Vec<f64>), NurbsError> {
    let t = knots.parameter(t)?;
    let span = knots.span_in_domain(t);
    let p = knots.degree();
    let mut n = vec![0.0; p + 1];
    let mut left = vec![0.0; p + 1];
    let mut right = vec![0.0; p + 1];
    basis_into(knots.as_slice(), p, span, t, &mut n, &mut left, &mut right);
    Ok((span, n))
}

/// The basis functions non-zero at `t` and their derivatives up to `order`: returns the span
/// `k` and `ders` with `ders[j][r] = d^j/dt^j N_{k−p+r,p}(t)` for `0 ≤ j ≤ order` (The NURBS
/// Book A2.3, eq. 2.10); derivatives of order above `p` are zero. The derivatives of the
/// basis sum to zero (differentiate the partition of unity).
///
/// # Errors
/// [`NurbsError::ParameterOutOfDomain`] (see [`KnotVector::parameter`]).
pub fn basis_derivatives(
    knots: &KnotVector,
    t: f64,
    order: usize,
) -> Result<(usize, Vec<Vec<f64>>), NurbsError> {
    let t = knots.parameter(t)?;
    let span = knots.span_in_domain(t);
    let p = knots.degree();
    let flat = ders_basis(knots.as_slice(), p, span, t, order);
    let mut ders: Vec<Vec<f64>> = flat.chunks(p + 1).map(<[f64]>::to_vec).collect();
    ders.resize(order.saturating_add(1), vec![0.0; p + 1]);
    Ok((span, ders))
}

/// A2.2: `n[r] = N_{span−p+r,p}(t)`; `left`, `right` are scratch of length `p + 1`. Needs a
/// non-empty span (`knots[span] < knots[span + 1]`), which makes every denominator positive.
pub(crate) fn basis_into(
    knots: &[f64],
    p: usize,
    span: usize,
    t: f64,
    n: &mut [f64],
    left: &mut [f64],
    right: &mut [f64],
) {
    n[0] = 1.0;
    for j in 1..=p {
        left[j] = t - knots[span + 1 - j];
        right[j] = knots[span + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            let temp = n[r] / (right[r + 1] + left[j - r]);
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
    }
}

/// A2.3, flattened: entry `j (p + 1) + r` is `d^j/dt^j N_{span−p+r,p}(t)`,
/// `0 ≤ j ≤ min(order, p)` (higher derivatives vanish and are not stored).
pub(crate) fn ders_basis(knots: &[f64], p: usize, span: usize, t: f64, order: usize) -> Vec<f64> {
    let w = p + 1;
    let top = order.min(p);
    let mut ders = vec![0.0; (top + 1) * w];
    // ndu[j][r] (row-major w × w): upper triangle basis values of all degrees, lower
    // triangle knot differences.
    let mut ndu = vec![0.0; w * w];
    let mut left = vec![0.0; w];
    let mut right = vec![0.0; w];
    ndu[0] = 1.0;
    for j in 1..=p {
        left[j] = t - knots[span + 1 - j];
        right[j] = knots[span + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j * w + r] = right[r + 1] + left[j - r];
            let temp = ndu[r * w + j - 1] / ndu[j * w + r];
            ndu[r * w + j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j * w + j] = saved;
    }
    for r in 0..=p {
        ders[r] = ndu[r * w + p];
    }
    let mut a = vec![0.0; 2 * w];
    for r in 0..=p {
        let (mut s1, mut s2) = (0, w);
        a[0] = 1.0;
        for k in 1..=top {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if r >= k {
                let rk = rk as usize;
                a[s2] = a[s1] / ndu[(pk + 1) * w + rk];
                d = a[s2] * ndu[rk * w + pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if r <= pk + 1 { k - 1 } else { p - r };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2 + j] = (a[s1 + j] - a[s1 + j - 1]) / ndu[(pk + 1) * w + idx];
                d += a[s2 + j] * ndu[idx * w + pk];
            }
            if r <= pk {
                a[s2 + k] = -a[s1 + k - 1] / ndu[(pk + 1) * w + r];
                d += a[s2 + k] * ndu[r * w + pk];
            }
            ders[k * w + r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut f = p as f64;
    for k in 1..=top {
        for r in 0..=p {
            ders[k * w + r] *= f;
        }
        f *= (p - k) as f64;
    }
    ders
}
