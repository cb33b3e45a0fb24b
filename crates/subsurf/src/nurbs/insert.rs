//! Knot insertion (Boehm 1980) and knot refinement, for open and periodic knot vectors,
//! applied to any number of rows of control points at once (a curve is one row; a surface
//! refined along `u` has one row per `v` index).
//!
//! Inserting `x ∈ [t_k, t_{k+1})` into a degree-`p` B-spline replaces the control points
//! `P_{k−p+1} … P_{k−1}` by the `p` points
//! `Q_i = (1 − α_i) P_{i−1} + α_i P_i`, `α_i = (x − t_i) / (t_{i+p} − t_i)`,
//! `k − p + 1 ≤ i ≤ k`, keeps `Q_i = P_i` before and `Q_i = P_{i−1}` after (Boehm,
//! "Inserting new knots into B-spline curves", CAD 12(4), 1980; The NURBS Book eq. 5.15,
//! A5.1). The curve is unchanged: the new basis spans the old one. Several knots are inserted
//! in one pass by The NURBS Book A5.4 (knot refinement), `O((n + m) p)` for `m` knots.
//!
//! For a periodic knot vector the same formula is applied cyclically: `x` and all its
//! translates `x + kT` are inserted, the `n + 1` new distinct points are
//! `Q_{j mod (n+1)}` for `k − p + 1 ≤ j ≤ k − p + 1 + n` (indices of `P` mod `n`), one knot
//! at a time (`O(m (n + p))` for `m` knots).

use super::vecn::lerp;
use super::{KnotVector, NurbsError};

/// Rows of control points (each row: the distinct control points of one curve).
pub(crate) type Rows<const D: usize> = Vec<Vec<[f64; D]>>;

/// Inserts the knots `xs` (any order; each in the domain, or any finite value for a periodic
/// knot vector, wrapped) into every row. Returns the new knot vector and rows; on error,
/// nothing has been computed.
pub(crate) fn refine<const D: usize>(
    knots: &KnotVector,
    xs: &[f64],
    rows: Rows<D>,
) -> Result<(KnotVector, Rows<D>), NurbsError> {
    let mut xs = xs
        .iter()
        .map(|&x| knots.parameter(x))
        .collect::<Result<Vec<f64>, _>>()?;
    if xs.is_empty() {
        return Ok((knots.clone(), rows));
    }
    xs.sort_by(f64::total_cmp);
    let p = knots.degree();
    match knots.period_knots() {
        None => {
            let merged = merge(knots.as_slice(), &xs);
            let new = KnotVector::new(p, merged)?;
            let rows = rows
                .iter()
                .map(|r| refine_open(knots.as_slice(), p, r, &xs))
                .collect();
            Ok((new, rows))
        }
        Some(u) => {
            // Validate the final knot vector first, so that no step can fail.
            let new = KnotVector::periodic(p, &merge(u, &xs))?;
            let mut cur = knots.clone();
            let mut rows = rows;
            for &x in &xs {
                let Some(u) = cur.period_knots() else { break };
                let next = KnotVector::periodic(p, &merge(u, &[x]))?;
                for r in rows.iter_mut() {
                    *r = insert_periodic(&cur, r, x);
                }
                cur = next;
            }
            debug_assert_eq!(cur, new);
            Ok((new, rows))
        }
    }
}

/// `a` and sorted `b` merged, each element of `b` after the elements of `a` equal to it.
fn merge(a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let mut i = 0;
    for &x in b {
        while i < a.len() && a[i] <= x {
            out.push(a[i]);
            i += 1;
        }
        out.push(x);
    }
    out.extend_from_slice(&a[i..]);
    out
}

/// The span of `x` as The NURBS Book A2.1 finds it (`nb` = last control point index): the
/// last `s ≤ nb` with `t_s ≤ x`, and `nb` at the end of the domain.
fn span_a21(u: &[f64], p: usize, nb: usize, x: f64) -> usize {
    if x >= u[nb + 1] {
        return nb;
    }
    let c = u[p..=nb].partition_point(|&t| t <= x);
    p + c.max(1) - 1
}

/// The NURBS Book A5.4 (RefineKnotVectCurve): the control points after inserting the sorted
/// knots `x` (all in the domain) into the open knot vector `u` of degree `p`.
fn refine_open<const D: usize>(u: &[f64], p: usize, pw: &[[f64; D]], x: &[f64]) -> Vec<[f64; D]> {
    let nb = pw.len() - 1;
    let r = x.len() - 1;
    let a = span_a21(u, p, nb, x[0]);
    let b = span_a21(u, p, nb, x[r]) + 1;
    let mut ubar = vec![0.0; u.len() + r + 1];
    let mut qw = vec![[0.0; D]; nb + r + 2];
    qw[..=a - p].copy_from_slice(&pw[..=a - p]);
    for j in b - 1..=nb {
        qw[j + r + 1] = pw[j];
    }
    ubar[..=a].copy_from_slice(&u[..=a]);
    for j in b + p..u.len() {
        ubar[j + r + 1] = u[j];
    }
    let mut i = b + p - 1;
    let mut k = b + p + r;
    for j in (0..=r).rev() {
        while x[j] <= u[i] && i > a {
            qw[k - p - 1] = pw[i - p - 1];
            ubar[k] = u[i];
            k -= 1;
            i -= 1;
        }
        qw[k - p - 1] = qw[k - p];
        for l in 1..=p {
            let ind = k - p + l;
            let alfa = ubar[k + l] - x[j];
            if alfa == 0.0 {
                qw[ind - 1] = qw[ind];
            } else {
                let alfa = alfa / (ubar[k + l] - u[i - p + l]);
                // alfa · Q[ind−1] + (1 − alfa) · Q[ind]
                qw[ind - 1] = lerp(&qw[ind], &qw[ind - 1], alfa);
            }
        }
        ubar[k] = x[j];
        k -= 1;
    }
    qw
}

/// One cyclic Boehm insertion of `x ∈ [u_0, u_n)` into the closed curve with periodic knots
/// `knots` and distinct points `pts` (`n` of them); returns the `n + 1` new points.
fn insert_periodic<const D: usize>(knots: &KnotVector, pts: &[[f64; D]], x: f64) -> Vec<[f64; D]> {
    let n = pts.len();
    let p = knots.degree();
    let t = knots.as_slice();
    let k = knots.span_in_domain(x);
    let mut out = vec![[0.0; D]; n + 1];
    for j in k + 1 - p..=k {
        let a = (x - t[j]) / (t[j + p] - t[j]);
        out[j % (n + 1)] = lerp(&pts[(j - 1) % n], &pts[j % n], a);
    }
    for j in k + 1..=k + 1 + n - p {
        out[j % (n + 1)] = pts[(j - 1) % n];
    }
    out
}
