//! The uniform bicubic B-spline patch: the Catmull-Clark limit surface of a regular quad
//! (all four corners of valence 4, no sharp features nearby), Catmull & Clark 1978.
//!
//! With the 4×4 control points `P[i][j]` (`i` along `u`, `j` along `v`; the face itself is
//! the middle cell, corners `P[1][1]`, `P[2][1]`, `P[2][2]`, `P[1][2]`),
//!
//! `S(u, v) = Σᵢ Σⱼ Bᵢ(u) Bⱼ(v) P[i][j]`, with the uniform cubic B-spline basis
//!
//! ```text
//! B₀(t) = (1 - t)³ / 6
//! B₁(t) = (3t³ - 6t² + 4) / 6
//! B₂(t) = (-3t³ + 3t² + 3t + 1) / 6
//! B₃(t) = t³ / 6
//! ```
//!
//! which is a partition of unity on `[0, 1]`.

/// Values and first and second derivatives of the four cubic B-spline basis functions at
/// `t`: `(B, B', B'')`.
#[inline]
pub fn basis(t: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    let t2 = t * t;
    let t3 = t2 * t;
    let b = [
        s * s * s / 6.0,
        (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
        (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
        t3 / 6.0,
    ];
    let d = [
        -0.5 * s * s,
        1.5 * t2 - 2.0 * t,
        -1.5 * t2 + t + 0.5,
        0.5 * t2,
    ];
    let dd = [s, 3.0 * t - 2.0, -3.0 * t + 1.0, t];
    (b, d, dd)
}

/// Position, first and second partial derivatives of a surface at one parameter.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Derivatives {
    /// Position `S`.
    pub p: [f64; 3],
    /// `∂S/∂u`.
    pub du: [f64; 3],
    /// `∂S/∂v`.
    pub dv: [f64; 3],
    /// `∂²S/∂u²`.
    pub duu: [f64; 3],
    /// `∂²S/∂u∂v`.
    pub duv: [f64; 3],
    /// `∂²S/∂v²`.
    pub dvv: [f64; 3],
}

impl Derivatives {
    /// The unit normal `Su × Sv / |Su × Sv|` (zero where the derivatives are parallel).
    pub fn normal(&self) -> [f64; 3] {
        crate::geom::unit_cross(&self.du, &self.dv)
    }

    /// The derivatives of `S(a·u + b, a·v + c)`: first derivatives times `a`, second
    /// times `a²` (used when a sub-patch covers a square of side `1/a` of its face).
    pub fn scaled(mut self, a: f64) -> Self {
        self.scale(a);
        self
    }

    /// [`scaled`](Self::scaled) in place.
    pub(crate) fn scale(&mut self, a: f64) {
        for k in 0..3 {
            self.du[k] *= a;
            self.dv[k] *= a;
            self.duu[k] *= a * a;
            self.duv[k] *= a * a;
            self.dvv[k] *= a * a;
        }
    }
}

/// Which derivatives an evaluation computes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Order {
    /// Position and first derivatives; the second derivatives are left zero (about 40 %
    /// less work per bicubic patch: what shading, tessellation and OpenSubdiv's
    /// `Bfr::Surface::Evaluate(uv, P, Du, Dv)` need).
    First,
    /// Position, first and second derivatives.
    #[default]
    Second,
}

/// Evaluates the bicubic B-spline patch with control points `cp[i][j]` (`i` along `u`) at
/// `(u, v)`.
#[inline]
pub fn eval(cp: &[[[f64; 3]; 4]; 4], u: f64, v: f64) -> Derivatives {
    tensor(cp, basis(u), basis(v), Order::Second)
}

/// [`eval`] computing the derivatives of `order` only.
#[inline]
pub fn eval_order(cp: &[[[f64; 3]; 4]; 4], u: f64, v: f64, order: Order) -> Derivatives {
    tensor(cp, basis(u), basis(v), order)
}

/// [`eval_order`] into `out` (see [`tensor_into`]).
#[inline]
pub(crate) fn eval_order_into(
    cp: &[[[f64; 3]; 4]; 4],
    u: f64,
    v: f64,
    order: Order,
    out: &mut Derivatives,
) {
    tensor_into(cp, basis(u), basis(v), order, out)
}

/// `Σᵢ Σⱼ Aᵢ(u) Bⱼ(v) P[i][j]` with its first and (for [`Order::Second`]) second
/// derivatives, for bases given as `(values, first, second derivatives)` at the point: a
/// tensor-product surface of any two bases of four functions. Contracts `v` first (two or
/// three sums of four per column), then `u`.
#[inline]
pub fn tensor(
    cp: &[[[f64; 3]; 4]; 4],
    a: ([f64; 4], [f64; 4], [f64; 4]),
    b: ([f64; 4], [f64; 4], [f64; 4]),
    order: Order,
) -> Derivatives {
    let mut r = Derivatives::default();
    tensor_into(cp, a, b, order, &mut r);
    r
}

/// [`tensor`] written into `out` in place. The evaluators use this form: a
/// [`Derivatives`] is 144 bytes, and each move of one through a temporary compiles to a
/// `memcpy` call (9 % of the time of a grid of limit evaluations before this).
#[inline]
pub(crate) fn tensor_into(
    cp: &[[[f64; 3]; 4]; 4],
    a: ([f64; 4], [f64; 4], [f64; 4]),
    b: ([f64; 4], [f64; 4], [f64; 4]),
    order: Order,
    out: &mut Derivatives,
) {
    match order {
        Order::First => tensor_to::<false>(cp, a, b, out),
        Order::Second => tensor_to::<true>(cp, a, b, out),
    }
}

/// [`tensor_into`], with second derivatives when `SECOND` (a constant, so each instance
/// has only the sums it needs).
#[inline(always)]
fn tensor_to<const SECOND: bool>(
    cp: &[[[f64; 3]; 4]; 4],
    (a, da, dda): ([f64; 4], [f64; 4], [f64; 4]),
    (b, db, ddb): ([f64; 4], [f64; 4], [f64; 4]),
    r: &mut Derivatives,
) {
    // q[i] = (Σⱼ Bⱼ P, Σⱼ B'ⱼ P, Σⱼ B''ⱼ P) for column i.
    let mut q = [[[0.0; 3]; 3]; 4];
    for (qi, col) in q.iter_mut().zip(cp) {
        for (j, p) in col.iter().enumerate() {
            for k in 0..3 {
                qi[0][k] += b[j] * p[k];
                qi[1][k] += db[j] * p[k];
                if SECOND {
                    qi[2][k] += ddb[j] * p[k];
                }
            }
        }
    }
    *r = Derivatives::default();
    for i in 0..4 {
        for k in 0..3 {
            r.p[k] += a[i] * q[i][0][k];
            r.du[k] += da[i] * q[i][0][k];
            r.dv[k] += a[i] * q[i][1][k];
            if SECOND {
                r.duu[k] += dda[i] * q[i][0][k];
                r.duv[k] += da[i] * q[i][1][k];
                r.dvv[k] += a[i] * q[i][2][k];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_a_partition_of_unity_with_zero_derivative_sums() {
        for i in 0..=20 {
            let t = i as f64 / 20.0;
            let (b, d, dd) = basis(t);
            assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            assert!(d.iter().sum::<f64>().abs() < 1e-15);
            assert!(dd.iter().sum::<f64>().abs() < 1e-15);
            assert!(b.iter().all(|&x| x >= 0.0));
        }
    }

    /// Derivatives agree with central finite differences of the values.
    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-5;
        for i in 1..10 {
            let t = i as f64 / 10.0;
            let (b0, d, dd) = basis(t);
            let (bp, dp, _) = basis(t + h);
            let (bm, dm, _) = basis(t - h);
            for k in 0..4 {
                assert!(((bp[k] - bm[k]) / (2.0 * h) - d[k]).abs() < 1e-9);
                assert!(((dp[k] - dm[k]) / (2.0 * h) - dd[k]).abs() < 1e-9);
                assert!(b0[k].is_finite());
            }
        }
    }

    /// A control net sampled from a bilinear function is reproduced exactly (B-splines
    /// reproduce linear functions): S(u, v) at the face equals the function.
    #[test]
    fn linear_precision() {
        let f = |x: f64, y: f64| [2.0 * x + 0.5 * y + 1.0, -x + 3.0 * y, 0.25 * x];
        let mut cp = [[[0.0; 3]; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                cp[i][j] = f(i as f64 - 1.0, j as f64 - 1.0);
            }
        }
        let r = eval(&cp, 0.3, 0.8);
        let e = f(0.3, 0.8);
        for k in 0..3 {
            assert!((r.p[k] - e[k]).abs() < 1e-14);
        }
        assert!((r.du[0] - 2.0).abs() < 1e-14 && (r.dv[1] - 3.0).abs() < 1e-14);
        assert!(r
            .duu
            .iter()
            .chain(&r.duv)
            .chain(&r.dvv)
            .all(|x| x.abs() < 1e-13));
    }
}
