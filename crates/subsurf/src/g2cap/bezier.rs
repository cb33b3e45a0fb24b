//! [`BezierPatch`]: a tensor-product Bézier patch of equal degree `d` in `u` and `v`,
//! `P(u, v) = Σᵢ Σⱼ Bᵈᵢ(u) Bᵈⱼ(v) pᵢⱼ` (Farin, *Curves and Surfaces for CAGD*, ch. 16),
//! with exact evaluation of all partial derivatives, conversion from the uniform bicubic
//! B-spline and degree elevation. The caps are bi-septic (`d = 7`, 8×8 control points);
//! the Catmull-Clark patches around them are bicubic (`d = 3`).

use super::bernstein::basis_derivatives;
use crate::limit::Derivatives;

/// A tensor-product Bézier patch of degree `d × d` with control points `pᵢⱼ` stored
/// row-major, `i` along `u`: `points[i * (d + 1) + j]`.
#[derive(Clone, Debug, PartialEq)]
pub struct BezierPatch {
    degree: usize,
    points: Vec<[f64; 3]>,
}

impl BezierPatch {
    /// A patch of degree `degree` from its `(degree + 1)²` control points (row-major, `i`
    /// along `u`). Returns `None` when the count does not match.
    pub fn new(degree: usize, points: Vec<[f64; 3]>) -> Option<Self> {
        (points.len() == (degree + 1) * (degree + 1)).then_some(Self { degree, points })
    }

    /// The bicubic Bézier form of the uniform bicubic B-spline patch with control points
    /// `cp[i][j]` (`i` along `u`, the layout of [`crate::limit::bspline::eval`]). Per
    /// direction the B-spline segment `(p₀, p₁, p₂, p₃)` has the Bézier points
    /// `((p₀+4p₁+p₂)/6, (4p₁+2p₂)/6, (2p₁+4p₂)/6, (p₁+4p₂+p₃)/6)` (the
    /// B-spline-to-Bézier conversion of the uniform cubic B-spline, Farin ch. 7).
    pub fn from_bicubic_bspline(cp: &[[[f64; 3]; 4]; 4]) -> Self {
        const M: [[f64; 4]; 4] = [
            [1.0, 4.0, 1.0, 0.0],
            [0.0, 4.0, 2.0, 0.0],
            [0.0, 2.0, 4.0, 0.0],
            [0.0, 1.0, 4.0, 1.0],
        ];
        let mut points = vec![[0.0; 3]; 16];
        for a in 0..4 {
            for b in 0..4 {
                let mut p = [0.0; 3];
                for i in 0..4 {
                    for j in 0..4 {
                        let w = M[a][i] * M[b][j] / 36.0;
                        if w != 0.0 {
                            for k in 0..3 {
                                p[k] += w * cp[i][j][k];
                            }
                        }
                    }
                }
                points[a * 4 + b] = p;
            }
        }
        Self { degree: 3, points }
    }

    /// The degree-`degree` patch interpolating `f` at the tensor grid of `degree + 1`
    /// Chebyshev points of `[0, 1]` in each direction: exact (up to rounding) when `f` is a
    /// polynomial of that degree in each variable. Returns `None` if `degree > 20`.
    pub fn interpolate(degree: usize, mut f: impl FnMut(f64, f64) -> [f64; 3]) -> Option<Self> {
        if degree > 20 {
            return None;
        }
        let n = degree + 1;
        let node = |k: usize| super::solver::chebyshev(n, k);
        let c = nalgebra::DMatrix::from_fn(n, n, |m, a| {
            super::bernstein::bernstein(degree, a as isize, node(m))
        });
        let inv = c.try_inverse()?;
        let samples: Vec<[f64; 3]> = (0..n * n).map(|g| f(node(g / n), node(g % n))).collect();
        let mut points = vec![[0.0; 3]; n * n];
        for k in 0..3 {
            let vals = nalgebra::DMatrix::from_fn(n, n, |i, j| samples[i * n + j][k]);
            let cp = &inv * vals * inv.transpose();
            for i in 0..n {
                for j in 0..n {
                    points[i * n + j][k] = cp[(i, j)];
                }
            }
        }
        Some(Self { degree, points })
    }

    /// Degree `d`.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The control points, row-major (`i` along `u`).
    pub fn points(&self) -> &[[f64; 3]] {
        &self.points
    }

    /// Control point `pᵢⱼ`.
    pub fn point(&self, i: usize, j: usize) -> [f64; 3] {
        self.points[i * (self.degree + 1) + j]
    }

    /// The same surface as a patch of degree `d + 1` in both directions:
    /// `p'ᵢ = i/(d+1) pᵢ₋₁ + (1 - i/(d+1)) pᵢ` per direction (Farin §5.1).
    pub fn elevated(&self) -> Self {
        let d = self.degree;
        let e = d + 1;
        // Elevate along v (within rows), then along u.
        let mut rows = vec![[0.0; 3]; (d + 1) * (e + 1)];
        for i in 0..=d {
            for j in 0..=e {
                let a = j as f64 / e as f64;
                let mut p = [0.0; 3];
                for k in 0..3 {
                    let lo = if j > 0 { self.point(i, j - 1)[k] } else { 0.0 };
                    let hi = if j <= d { self.point(i, j)[k] } else { 0.0 };
                    p[k] = a * lo + (1.0 - a) * hi;
                }
                rows[i * (e + 1) + j] = p;
            }
        }
        let mut points = vec![[0.0; 3]; (e + 1) * (e + 1)];
        for i in 0..=e {
            let a = i as f64 / e as f64;
            for j in 0..=e {
                let mut p = [0.0; 3];
                for k in 0..3 {
                    let lo = if i > 0 {
                        rows[(i - 1) * (e + 1) + j][k]
                    } else {
                        0.0
                    };
                    let hi = if i <= d {
                        rows[i * (e + 1) + j][k]
                    } else {
                        0.0
                    };
                    p[k] = a * lo + (1.0 - a) * hi;
                }
                points[i * (e + 1) + j] = p;
            }
        }
        Self { degree: e, points }
    }

    /// The same surface raised to degree `degree` (≥ the current degree).
    pub fn elevated_to(&self, degree: usize) -> Self {
        let mut p = self.clone();
        while p.degree < degree {
            p = p.elevated();
        }
        p
    }

    /// The weights `∂ᵃᵤ ∂ᵇᵥ [Bᵈᵢ(u) Bᵈⱼ(v)]` of every control point, row-major, so that
    /// `∂ᵃᵤ ∂ᵇᵥ P(u, v) = Σ weightsᵢⱼ pᵢⱼ`. Valid for any `(u, v)`, also outside `[0, 1]²`
    /// (the polynomial continued).
    pub fn weights(degree: usize, u: f64, v: f64, a: usize, b: usize) -> Vec<f64> {
        let bu = basis_derivatives(degree, u, a);
        let bv = basis_derivatives(degree, v, b);
        let mut w = Vec::with_capacity((degree + 1) * (degree + 1));
        for x in &bu {
            for y in &bv {
                w.push(x * y);
            }
        }
        w
    }

    /// The partial derivative `∂ᵃᵤ ∂ᵇᵥ P(u, v)` (`a = b = 0`: the position).
    pub fn derivative(&self, u: f64, v: f64, a: usize, b: usize) -> [f64; 3] {
        let bu = basis_derivatives(self.degree, u, a);
        let bv = basis_derivatives(self.degree, v, b);
        let n = self.degree + 1;
        let mut r = [0.0; 3];
        for i in 0..n {
            // Inner sum first: fewer multiplications, same result.
            let mut row = [0.0; 3];
            for j in 0..n {
                let p = &self.points[i * n + j];
                for k in 0..3 {
                    row[k] += bv[j] * p[k];
                }
            }
            for k in 0..3 {
                r[k] += bu[i] * row[k];
            }
        }
        r
    }

    /// Position and first and second partial derivatives at `(u, v)`.
    pub fn eval(&self, u: f64, v: f64) -> Derivatives {
        Derivatives {
            p: self.derivative(u, v, 0, 0),
            du: self.derivative(u, v, 1, 0),
            dv: self.derivative(u, v, 0, 1),
            duu: self.derivative(u, v, 2, 0),
            duv: self.derivative(u, v, 1, 1),
            dvv: self.derivative(u, v, 0, 2),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::limit::bspline;

    fn net() -> [[[f64; 3]; 4]; 4] {
        let mut cp = [[[0.0; 3]; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                let (x, y) = (i as f64, j as f64);
                cp[i][j] = [
                    x + 0.1 * y * y,
                    y - 0.2 * x * y,
                    (x * 1.3).sin() + (y * 0.7).cos(),
                ];
            }
        }
        cp
    }

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() <= tol)
    }

    /// The Bézier form of a bicubic B-spline patch is the same surface, with the same
    /// derivatives, as the B-spline evaluator of the limit module.
    #[test]
    fn bspline_conversion_reproduces_the_bspline_patch() {
        let cp = net();
        let b = BezierPatch::from_bicubic_bspline(&cp);
        for &(u, v) in &[(0.0, 0.0), (0.3, 0.7), (1.0, 0.25), (0.5, 1.0)] {
            let e = bspline::eval(&cp, u, v);
            let d = b.eval(u, v);
            for (x, y) in [(d.p, e.p), (d.du, e.du), (d.dv, e.dv), (d.duu, e.duu)] {
                assert!(close(x, y, 1e-13));
            }
            assert!(close(d.duv, e.duv, 1e-13) && close(d.dvv, e.dvv, 1e-13));
        }
    }

    /// Degree elevation changes the representation, not the surface.
    #[test]
    fn elevation_keeps_the_surface() {
        let b = BezierPatch::from_bicubic_bspline(&net());
        let e = b.elevated_to(7);
        assert_eq!(e.degree(), 7);
        assert_eq!(e.points().len(), 64);
        for &(u, v) in &[(0.0, 0.0), (0.2, 0.9), (0.61, 0.33), (1.0, 1.0)] {
            for (a, c) in [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2), (3, 2)] {
                let (x, y) = (e.derivative(u, v, a, c), b.derivative(u, v, a, c));
                // Relative: high derivatives of the degree-7 form sum large weights.
                let scale = 1.0 + y.iter().fold(0.0f64, |m, z| m.max(z.abs()));
                assert!(
                    close(x, y, 1e-9 * scale),
                    "{a} {c} at ({u}, {v}): {x:?} vs {y:?}"
                );
            }
        }
    }

    /// The weights reproduce `derivative`.
    #[test]
    fn weights_agree_with_derivative() {
        let e = BezierPatch::from_bicubic_bspline(&net()).elevated_to(7);
        let w = BezierPatch::weights(7, 0.3, 0.8, 1, 2);
        let mut p = [0.0; 3];
        for (x, q) in w.iter().zip(e.points()) {
            for k in 0..3 {
                p[k] += x * q[k];
            }
        }
        assert!(close(p, e.derivative(0.3, 0.8, 1, 2), 1e-12));
    }
}
