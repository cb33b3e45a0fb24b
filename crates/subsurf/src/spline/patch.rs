//! [`RationalPatch`]: the surface over one quad as a rational bicubic Bézier patch.
//!
//! Over face `[p0 p1 p2 p3]` (`u` toward `p1`, `v` toward `p3`) the sub-basis functions
//! centred at corner `p_j` are bicubic in that corner's rhombus coordinates `(s, t)`, which
//! are affine in `(u, v)`: corner 0 `(s, t) = (u, v)`, corner 1 `(v, 1 − u)`, corner 2
//! `(1 − u, 1 − v)`, corner 3 `(1 − v, u)`. Each has Bézier coefficients only at the indices
//! `{0, 1}²` of its own corner (see [`super::subbasis`]), so the four corners fill the four
//! disjoint 2×2 corner blocks of one 4×4 net. The numerator `Σ W_i P_i` and the denominator
//! `Σ W_i` of eq. 12 are therefore one homogeneous bicubic Bézier patch with points
//! `(Σ c·P, Σ c)`, and `P = N / D` is evaluated like any rational Bézier patch, as cheaply as
//! a polynomial bicubic patch (section 2.4's claim).

use crate::limit::Derivatives;

/// Net index `(i, j)` (`i` along `u`) of Bézier coefficient `(a, b)` (`a` along `s`) of a
/// sub-basis piece centred at corner `j` of the face.
#[inline]
pub(crate) fn net_index(corner: usize, a: usize, b: usize) -> (usize, usize) {
    match corner {
        0 => (a, b),
        1 => (3 - b, a),
        2 => (3 - a, 3 - b),
        _ => (b, 3 - a),
    }
}

/// The four coefficient indices `(a, b)` in the order of [`super::SubBasis::bezier`].
pub(crate) const AB: [(usize, usize); 4] = [(0, 0), (1, 0), (0, 1), (1, 1)];

/// Cubic Bernstein polynomials and their first and second derivatives at `t`.
#[inline]
pub(crate) fn bernstein(t: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    (
        [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t],
        [
            -3.0 * s * s,
            3.0 * s * (1.0 - 3.0 * t),
            3.0 * t * (2.0 - 3.0 * t),
            3.0 * t * t,
        ],
        [6.0 * s, 18.0 * t - 12.0, 6.0 - 18.0 * t, 6.0 * t],
    )
}

/// A rational bicubic Bézier patch: homogeneous points `(w·P, w)`, `net[i][j]`, `i` along `u`.
#[derive(Clone, Debug, PartialEq)]
pub struct RationalPatch {
    /// Homogeneous control points `[x·w, y·w, z·w, w]`.
    pub net: [[[f64; 4]; 4]; 4],
}

impl RationalPatch {
    /// Position and first and second derivatives of `N/D` at `(u, v)` (quotient rule:
    /// `P_u = (N_u − P D_u)/D`, `P_uv = (N_uv − P_u D_v − P_v D_u − P D_uv)/D`, …).
    #[inline]
    pub fn eval(&self, u: f64, v: f64) -> Derivatives {
        let (bu, du, ddu) = bernstein(u);
        let (bv, dv, ddv) = bernstein(v);
        // h[q] for q = value, u, v, uu, uv, vv: homogeneous 4-vectors.
        let mut h = [[0.0f64; 4]; 6];
        for i in 0..4 {
            // Contract along v first.
            let mut r = [[0.0f64; 4]; 3];
            for j in 0..4 {
                let p = &self.net[i][j];
                for c in 0..4 {
                    r[0][c] += bv[j] * p[c];
                    r[1][c] += dv[j] * p[c];
                    r[2][c] += ddv[j] * p[c];
                }
            }
            for c in 0..4 {
                h[0][c] += bu[i] * r[0][c];
                h[1][c] += du[i] * r[0][c];
                h[2][c] += bu[i] * r[1][c];
                h[3][c] += ddu[i] * r[0][c];
                h[4][c] += du[i] * r[1][c];
                h[5][c] += bu[i] * r[2][c];
            }
        }
        let d = h[0][3];
        let inv = 1.0 / d;
        let mut out = Derivatives::default();
        for c in 0..3 {
            let p = h[0][c] * inv;
            let pu = (h[1][c] - p * h[1][3]) * inv;
            let pv = (h[2][c] - p * h[2][3]) * inv;
            out.p[c] = p;
            out.du[c] = pu;
            out.dv[c] = pv;
            out.duu[c] = (h[3][c] - 2.0 * pu * h[1][3] - p * h[3][3]) * inv;
            out.duv[c] = (h[4][c] - pu * h[2][3] - pv * h[1][3] - p * h[4][3]) * inv;
            out.dvv[c] = (h[5][c] - 2.0 * pv * h[2][3] - p * h[5][3]) * inv;
        }
        out
    }

    /// Position only (cheaper than [`eval`](Self::eval)).
    #[inline]
    pub fn position(&self, u: f64, v: f64) -> [f64; 3] {
        let (bu, _, _) = bernstein(u);
        let (bv, _, _) = bernstein(v);
        let mut h = [0.0f64; 4];
        for i in 0..4 {
            for j in 0..4 {
                let b = bu[i] * bv[j];
                let p = &self.net[i][j];
                for c in 0..4 {
                    h[c] += b * p[c];
                }
            }
        }
        [h[0] / h[3], h[1] / h[3], h[2] / h[3]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Derivatives of a genuinely rational patch agree with central differences.
    #[test]
    fn rational_derivatives_match_finite_differences() {
        let mut net = [[[0.0; 4]; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                let w = 1.0 + 0.3 * ((i * 3 + j) as f64).sin().abs();
                let p = [
                    i as f64 + 0.1 * j as f64,
                    j as f64 - 0.2 * (i * j) as f64,
                    ((i + 2 * j) as f64).cos(),
                ];
                net[i][j] = [p[0] * w, p[1] * w, p[2] * w, w];
            }
        }
        let patch = RationalPatch { net };
        let (u, v, e) = (0.37, 0.61, 1e-5);
        let d = patch.eval(u, v);
        let f = |u, v| patch.eval(u, v);
        for c in 0..3 {
            let fd = |a: f64, b: f64| (a - b) / (2.0 * e);
            assert!((fd(f(u + e, v).p[c], f(u - e, v).p[c]) - d.du[c]).abs() < 1e-8);
            assert!((fd(f(u, v + e).p[c], f(u, v - e).p[c]) - d.dv[c]).abs() < 1e-8);
            assert!((fd(f(u + e, v).du[c], f(u - e, v).du[c]) - d.duu[c]).abs() < 1e-7);
            assert!((fd(f(u, v + e).du[c], f(u, v - e).du[c]) - d.duv[c]).abs() < 1e-7);
            assert!((fd(f(u, v + e).dv[c], f(u, v - e).dv[c]) - d.dvv[c]).abs() < 1e-7);
            assert!((patch.position(u, v)[c] - d.p[c]).abs() < 1e-14);
        }
    }
}
