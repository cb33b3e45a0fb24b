//! [`SubBasis`]: one sub-basis function of class 1, 2 or 3 on the star of a vertex of
//! valence `n` ([Sub-basis splines], sections 1.2 and 2.2–2.3).
//!
//! # Domain
//! The `n` quads around a vertex map to `n` unit rhombi around the origin with angle
//! `θ = 2π/n` there; edge `k` points along `e_k = (cos kθ, sin kθ)` and rhombus `k` is spanned
//! by `e_k` and `e_{k+1}` with affine coordinates `(s, t) ∈ [0, 1]²` (point `s·e_k + t·e_{k+1}`;
//! the paper's `(β_l, α_l)` of eq. 13). The owner of the function lies on the local `u`-axis:
//! for class 2 it is the end of edge 0, for class 3 the far corner of rhombus 0 (the axis
//! bisects rhombus 0); class 1 is rotationally symmetric.
//!
//! # The function on one rhombus (eq. 14)
//! A bicubic Hermite patch whose data vanish at the three outer corners:
//!
//! ```text
//! w_k(s, t) = w·h0(s)h0(t) + D_k·h1(s)h0(t) + D_{k+1}·h0(s)h1(t) + A_k·h1(s)h1(t),
//! h0(x) = 2x³ − 3x² + 1 = (1 − x)²(1 + 2x),   h1(x) = x³ − 2x² + x = x(1 − x)²,
//! ```
//!
//! with the centre value `w`, the edge derivatives `D_k = ∇w · e_k` (eq. 17; the gradient is
//! `(g, 0)` in the local frame, so `D_k = g·cos(kθ)` for class 2 and `g·cos(kθ − θ/2)` for
//! class 3) and the twists `A_k`. Every piece is C1 across the outer boundary of the star
//! (value and both derivatives vanish there) and continuous across the inner edges.
//!
//! # Twists (eqs. 18–19, derived here because the extracted equation is damaged)
//! The paper asks for equal cross-boundary derivatives of rhombi `k − 1` and `k` at the
//! *midpoint* of their common edge `e_k`. Writing `e_{k+1} = −e_{k−1} + 2cosθ·e_k`, the
//! derivative along `e_{k+1}` at the edge point `x·e_k` is `D_{k+1}h0(x) + A_k h1(x)` in rhombus
//! `k` and `−(D_{k−1}h0(x) + A_{k−1}h1(x)) + 2cosθ·(w h0'(x) + D_k h1'(x))` in rhombus `k − 1`;
//! at `x = ½` (`h0 = ½`, `h1 = ⅛`, `h0' = −3/2`, `h1' = −¼`), with `D_{k−1} + D_{k+1} = 2cosθ·D_k`:
//!
//! ```text
//! A_{k−1} + A_k = −12 cosθ (2w + D_k),   k = 0, …, n − 1 (indices mod n).
//! ```
//!
//! (Along the whole edge the two derivatives differ by a multiple of `cosθ`, so the pieces
//! are C1 exactly only where `cosθ = 0`; the paper claims no more.) The cyclic matrix has
//! eigenvalues `1 + ω^j`: for odd `n` it is invertible,
//! `A_k = ½ Σ_{j<n} (−1)^j c_{k−j}`; for even `n` its kernel is the alternating vector
//! `(−1)^k`, the right-hand side is consistent (`Σ(−1)^k e_k = 0` for even `n ≥ 4`) and we take
//! the **minimum-norm solution** (the one orthogonal to `(−1)^k`) for every even `n ≠ 4`. For
//! `n = 6` this is the paper's choice for class 3 and coincides with its choices for classes 1
//! (all twists equal) and 2 (`A_5 = A_7`, i.e. symmetric about the axis): both pick the unique
//! solution that is symmetric about the `u`-axis, which the minimum-norm one is.
//! `n = 4` uses the exact B-spline pieces instead (their twists `±¼` of class 3 are another
//! solution of the same singular system).
//!
//! # Non-negativity, exactly
//! Since `h0(x) = (1 − x)²(1 + 2x)` and `h1(x) = x(1 − x)²`, a piece is
//! `(1 − s)²(1 − t)²·Q(s, t)` with the *bilinear* `Q = w(1+2s)(1+2t) + D_k s(1+2t) + D_{k+1}(1+2s)t
//! + A_k st`. A bilinear function is non-negative on `[0, 1]²` iff it is at its corners, so the
//! function is non-negative iff for every `k`
//!
//! ```text
//! Q(1,0) = 3w + D_k ≥ 0,   Q(1,1) = 9w + 3(D_k + D_{k+1}) + A_k ≥ 0     (w > 0 given).
//! ```
//!
//! These are also the piece's Bézier coefficients (`w`, `w + D_k/3`, `w + D_{k+1}/3`,
//! `w + (D_k + D_{k+1})/3 + A_k/9`; all others are 0), so here the Bernstein test is exact, not
//! just sufficient. `D_k` and `A_k` are linear in the slope `g`, so each condition is
//! `a + b·g ≥ 0` and the **largest admissible slope** is computed in closed form:
//! `g = min(g_regular, min_{b<0} −a/b)` (the paper reduces `∂w/∂u` "until the function is
//! non-negative"; its appendix lists the results for `n = 3, 5, 6, 7`). This reproduces the
//! appendix's `n = 3` values `5/27` (class 2) and `1/12` (class 3) and its `n = 6` class-2 value
//! `2/9` exactly (see the tests).
//!
//! # The `n = 6` class-3 value
//! The appendix's `n = 6` class-3 slope reads `√3/18` (the unreduced `1/(12 cos 30°)`). With the
//! twists above that function is negative inside the rhombus opposite its owner (`−1/1152` at
//! its centre), and no other solution `A + a·(−1)^k` of the singular twist system helps (the
//! opposite rhombus needs `a ≤ −7/12`, its neighbour `a ≥ −1/2`). We keep non-negativity: the
//! largest admissible slope is `√3/36`, half the value read from the damaged text (a test
//! proves the contradiction).
//!
//! # Valence 9 and more
//! For class 1 (`g = 0`) the twist is `A = −12 cosθ·w`, and `Q(1,1) = (9 − 12cosθ)w < 0` once
//! `cosθ > ¾`, i.e. for every `n ≥ 9`: the paper's construction cannot be both midpoint-C1 and
//! non-negative there. We keep non-negativity (a basis function must not be negative) and
//! damp the twist equation by `λ_n = min(1, 3/(4cosθ))` (right-hand side `λ_n·c_k`), the
//! largest factor that keeps class 1 non-negative. At `λ_n` the class-1 certificate `Q(1,1)` is
//! exactly 0, which would force the slope of classes 2 and 3 to 0 and leave the surface
//! without a tangent plane at the vertex (all centre derivatives vanish); so classes 2 and 3
//! use the damping `λ ∈ [0, λ_n]` (scanned in 400 steps) that admits the largest slope, ties
//! going to the larger `λ` (this turns out to be `λ = 0`, zero twists, for every `n ≥ 9` up to
//! at least 64; slopes ≈ 0.17 and 0.043, see `docs/sub-basis-spline.md`). For `n ≤ 8`, `λ = 1` and the
//! construction is the paper's.

use std::f64::consts::PI;

/// Steps of the scan over the twist damping for valence ≥ 9.
const DAMPING_STEPS: usize = 400;

/// Bézier coefficients in `(−SNAP·w, 0)` are rounding residue of a tight bound: set to 0.
const SNAP: f64 = 1e-12;

/// The three classes of sub-basis functions ([Sub-basis splines], section 1.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Class {
    /// Class 1: the centre piece `w^{0,0}`, owned by the star's centre vertex; centre value
    /// `4/9`, gradient 0.
    Centre,
    /// Class 2: an edge piece `w^{0,±1}`, `w^{±1,0}`, owned by the end of a star edge; centre
    /// value `1/9`, slope toward the owner `1/3` (reduced for `n ≠ 4`).
    Edge,
    /// Class 3: a corner piece `w^{±1,±1}`, owned by the far corner of a star quad; centre
    /// value `1/36`, slope along the diagonal toward the owner `1/(12 cos(θ/2))` (reduced for
    /// `n ≠ 4`).
    Corner,
}

impl Class {
    /// All classes, in order 1, 2, 3.
    pub const ALL: [Class; 3] = [Class::Centre, Class::Edge, Class::Corner];

    /// The centre value of the uniform B-spline piece (eqs. 9–11): `(2/3)²`, `(2/3)(1/6)`,
    /// `(1/6)²`.
    pub fn value(self) -> f64 {
        match self {
            Class::Centre => 4.0 / 9.0,
            Class::Edge => 1.0 / 9.0,
            Class::Corner => 1.0 / 36.0,
        }
    }

    /// The regular (unreduced) centre slope toward the owner for angle `θ` at the centre:
    /// `0`, `1/3`, `1/(12 cos(θ/2))` (eqs. 9–11).
    pub fn regular_slope(self, theta: f64) -> f64 {
        match self {
            Class::Centre => 0.0,
            Class::Edge => 1.0 / 3.0,
            Class::Corner => 1.0 / (12.0 * (0.5 * theta).cos()),
        }
    }

    /// Angle of the owner direction from edge 0: 0 for classes 1 and 2, `θ/2` for class 3.
    fn axis_offset(self, theta: f64) -> f64 {
        match self {
            Class::Corner => 0.5 * theta,
            _ => 0.0,
        }
    }
}

/// One sub-basis function on the star of a vertex of valence `n` (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct SubBasis {
    /// Valence of the star's centre.
    pub valence: usize,
    /// Class.
    pub class: Class,
    /// Centre value `w`.
    pub value: f64,
    /// Slope `∂w/∂u` toward the owner actually used (reduced for non-negativity).
    pub slope: f64,
    /// The regular slope of [`Class::regular_slope`] before reduction.
    pub regular_slope: f64,
    /// Damping factor `λ_n` of the twist equation (1 for `n ≤ 8`).
    pub twist_damping: f64,
    /// Edge derivatives `D_k = ∇w · e_k`, `k = 0..n`.
    pub edge_derivatives: Vec<f64>,
    /// Twists `A_k` of rhombus `k`, `k = 0..n`.
    pub twists: Vec<f64>,
}

/// `(h0, h1)` and their first and second derivatives at `x`.
#[inline]
pub(crate) fn hermite(x: f64) -> ([f64; 2], [f64; 2], [f64; 2]) {
    let x2 = x * x;
    (
        [2.0 * x2 * x - 3.0 * x2 + 1.0, x2 * x - 2.0 * x2 + x],
        [6.0 * x2 - 6.0 * x, 3.0 * x2 - 4.0 * x + 1.0],
        [12.0 * x - 6.0, 6.0 * x - 4.0],
    )
}

/// Solves the cyclic system `A_{k−1} + A_k = c_k` (indices mod `n`): the unique solution for
/// odd `n`, the minimum-norm one for even `n` (see the module docs).
pub(crate) fn solve_cyclic(c: &[f64]) -> Vec<f64> {
    let n = c.len();
    if n % 2 == 1 {
        (0..n)
            .map(|k| {
                0.5 * (0..n)
                    .map(|j| {
                        let s = if j % 2 == 0 { 1.0 } else { -1.0 };
                        s * c[(k + n - j) % n]
                    })
                    .sum::<f64>()
            })
            .collect()
    } else {
        let mut a = vec![0.0; n];
        for k in 1..n {
            a[k] = c[k] - a[k - 1];
        }
        let alt = |k: usize| if k.is_multiple_of(2) { 1.0 } else { -1.0 };
        let m = (0..n).map(|k| alt(k) * a[k]).sum::<f64>() / n as f64;
        for k in 0..n {
            a[k] -= m * alt(k);
        }
        a
    }
}

/// Twist damping `λ_n = min(1, 3/(4 cos(2π/n)))` (see the module docs).
pub(crate) fn twist_damping(n: usize) -> f64 {
    let c = (2.0 * PI / n as f64).cos();
    if c <= 0.75 {
        1.0
    } else {
        0.75 / c
    }
}

/// The construction of one class and valence as an affine function of the slope `g`:
/// `D_k = g·dir_k`, `A = a0 + g·a1`.
struct Linear {
    n: usize,
    class: Class,
    lambda: f64,
    regular_slope: f64,
    dir: Vec<f64>,
    a0: Vec<f64>,
    a1: Vec<f64>,
}

impl Linear {
    fn new(n: usize, class: Class, lambda: f64) -> Self {
        let theta = 2.0 * PI / n as f64;
        let w = class.value();
        let off = class.axis_offset(theta);
        let dir: Vec<f64> = (0..n).map(|k| (k as f64 * theta - off).cos()).collect();
        let ct = theta.cos();
        let a0 = solve_cyclic(&vec![-12.0 * ct * 2.0 * w * lambda; n]);
        let a1 = solve_cyclic(
            &dir.iter()
                .map(|d| -12.0 * ct * d * lambda)
                .collect::<Vec<_>>(),
        );
        Self {
            n,
            class,
            lambda,
            regular_slope: class.regular_slope(theta),
            dir,
            a0,
            a1,
        }
    }

    /// The largest slope in `[0, regular]` with all certificates `a + b·g ≥ 0` (class 1: 0).
    fn max_slope(&self) -> f64 {
        if self.class == Class::Centre {
            return 0.0;
        }
        let n = self.n;
        let w = self.class.value();
        let mut g = self.regular_slope;
        let mut bound = |a: f64, b: f64| {
            if b < 0.0 {
                g = g.min((-a / b).max(0.0));
            }
        };
        for k in 0..n {
            let k1 = (k + 1) % n;
            bound(3.0 * w, self.dir[k]);
            bound(
                9.0 * w + self.a0[k],
                3.0 * (self.dir[k] + self.dir[k1]) + self.a1[k],
            );
        }
        g
    }

    fn at(&self, g: f64) -> SubBasis {
        SubBasis {
            valence: self.n,
            class: self.class,
            value: self.class.value(),
            slope: g,
            regular_slope: self.regular_slope,
            twist_damping: self.lambda,
            edge_derivatives: self.dir.iter().map(|d| g * d).collect(),
            twists: (0..self.n).map(|k| self.a0[k] + g * self.a1[k]).collect(),
        }
    }
}

impl SubBasis {
    /// Builds the sub-basis function of `class` for valence `n ≥ 3`: the exact B-spline
    /// piece for `n = 4`, otherwise the Hermite construction with twists from the cyclic
    /// system and the largest non-negative slope (module docs).
    ///
    /// # Panics
    /// If `n < 3` (no star of rhombi exists; callers check the valence first).
    pub fn new(n: usize, class: Class) -> Self {
        assert!(n >= 3, "sub-basis functions need valence ≥ 3, got {n}");
        if n == 4 {
            return Self::regular(class);
        }
        let lambda_n = twist_damping(n);
        let lin = if class == Class::Centre || lambda_n == 1.0 {
            Linear::new(n, class, lambda_n)
        } else {
            // n ≥ 9: the damping λ ∈ [0, λ_n] that admits the largest slope (ties: larger λ).
            let mut best = Linear::new(n, class, lambda_n);
            let mut best_g = best.max_slope();
            for i in (0..DAMPING_STEPS).rev() {
                let lin = Linear::new(n, class, lambda_n * i as f64 / DAMPING_STEPS as f64);
                let g = lin.max_slope();
                if g > best_g * (1.0 + 1e-12) {
                    best = lin;
                    best_g = g;
                }
            }
            best
        };
        lin.at(lin.max_slope())
    }

    /// The Hermite construction of `class` for valence `n ≥ 3`, `n ≠ 4`, with the given
    /// centre slope `g` instead of the largest non-negative one (for experiments and
    /// tests: a slope above [`new`](Self::new)'s makes the function negative somewhere).
    ///
    /// # Panics
    /// If `n < 3` or `n == 4`.
    pub fn with_slope(n: usize, class: Class, g: f64) -> Self {
        assert!(
            n >= 3 && n != 4,
            "the Hermite construction needs n ≥ 3, n ≠ 4"
        );
        Linear::new(n, class, twist_damping(n)).at(g)
    }

    /// The exact uniform B-spline pieces (`n = 4`): tensor products of the 1D pieces
    /// `B⁰ = (2/3)h0` and `B^{±1} = (1/6)h0 ± (1/2)h1` (derivative `1/2` toward the owner).
    fn regular(class: Class) -> Self {
        let (slope, d, a): (f64, [f64; 4], [f64; 4]) = match class {
            Class::Centre => (0.0, [0.0; 4], [0.0; 4]),
            Class::Edge => (1.0 / 3.0, [1.0 / 3.0, 0.0, -1.0 / 3.0, 0.0], [0.0; 4]),
            Class::Corner => (
                std::f64::consts::SQRT_2 / 12.0,
                [1.0 / 12.0, 1.0 / 12.0, -1.0 / 12.0, -1.0 / 12.0],
                [0.25, -0.25, 0.25, -0.25],
            ),
        };
        Self {
            valence: 4,
            class,
            value: class.value(),
            slope,
            regular_slope: slope,
            twist_damping: 1.0,
            edge_derivatives: d.to_vec(),
            twists: a.to_vec(),
        }
    }

    /// The Bézier coefficients `[b00, b10, b01, b11]` of the piece on rhombus `k` in the
    /// Bernstein basis of `(s, t)` (indices ≥ 2 are zero): `h0 = B0 + B1`, `h1 = B1/3`.
    pub fn bezier(&self, k: usize) -> [f64; 4] {
        let n = self.valence;
        let (dk, dk1, a) = (
            self.edge_derivatives[k % n],
            self.edge_derivatives[(k + 1) % n],
            self.twists[k % n],
        );
        let w = self.value;
        // Where the slope bound is tight a coefficient is 0 up to rounding; snap that residue.
        let snap = |b: f64| if b < 0.0 && b > -SNAP * w { 0.0 } else { b };
        [
            w,
            snap(w + dk / 3.0),
            snap(w + dk1 / 3.0),
            snap(w + (dk + dk1) / 3.0 + a / 9.0),
        ]
    }

    /// Value and first partial derivatives `(w, ∂w/∂s, ∂w/∂t)` on rhombus `k` at `(s, t)`
    /// (eq. 14).
    pub fn eval(&self, k: usize, s: f64, t: f64) -> [f64; 3] {
        let n = self.valence;
        let (dk, dk1, a) = (
            self.edge_derivatives[k % n],
            self.edge_derivatives[(k + 1) % n],
            self.twists[k % n],
        );
        let (hs, ds, _) = hermite(s);
        let (ht, dt, _) = hermite(t);
        let c = [[self.value, dk1], [dk, a]]; // c[i][j]: h_i(s) h_j(t)
        let mut r = [0.0; 3];
        for i in 0..2 {
            for j in 0..2 {
                r[0] += c[i][j] * hs[i] * ht[j];
                r[1] += c[i][j] * ds[i] * ht[j];
                r[2] += c[i][j] * hs[i] * dt[j];
            }
        }
        r
    }

    /// The smallest of the non-negativity certificates `Q(1,0) = 3w + D_k` and
    /// `Q(1,1) = 9w + 3(D_k + D_{k+1}) + A_k` over all rhombi (with `Q(0,0) = w`): the
    /// function is non-negative iff this is `≥ 0` (module docs).
    pub fn certificate(&self) -> f64 {
        (0..self.valence)
            .flat_map(|k| {
                let b = self.bezier(k);
                [b[0], 3.0 * b[1], 3.0 * b[2], 9.0 * b[3]]
            })
            .fold(f64::INFINITY, f64::min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cyclic_solutions_satisfy_the_system() {
        for n in 3..=12 {
            let c: Vec<f64> = (0..n)
                .map(|k| (0.7 * k as f64).sin() + if n % 2 == 0 { 0.0 } else { 0.3 })
                .collect();
            // Make even right-hand sides consistent (alternating sum 0).
            let mut c = c;
            if n % 2 == 0 {
                let m: f64 = c
                    .iter()
                    .enumerate()
                    .map(|(k, x)| if k % 2 == 0 { *x } else { -*x })
                    .sum::<f64>()
                    / n as f64;
                for (k, x) in c.iter_mut().enumerate() {
                    *x -= if k % 2 == 0 { m } else { -m };
                }
            }
            let a = solve_cyclic(&c);
            for k in 0..n {
                assert!((a[(k + n - 1) % n] + a[k] - c[k]).abs() < 1e-12, "n = {n}");
            }
            if n % 2 == 0 {
                let alt: f64 = a
                    .iter()
                    .enumerate()
                    .map(|(k, x)| if k % 2 == 0 { *x } else { -*x })
                    .sum();
                assert!(alt.abs() < 1e-12, "minimum norm: orthogonal to the kernel");
            }
        }
    }

    #[test]
    fn hermite_basis_matches_its_factored_form() {
        for i in 0..=10 {
            let x = i as f64 / 10.0;
            let (h, _, _) = hermite(x);
            assert!((h[0] - (1.0 - x).powi(2) * (1.0 + 2.0 * x)).abs() < 1e-15);
            assert!((h[1] - x * (1.0 - x).powi(2)).abs() < 1e-15);
        }
    }
}
