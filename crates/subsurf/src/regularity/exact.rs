//! Exact signs of the small polynomials the cone tests need, on the *exact* differences of
//! `f64` input points: `(a₁ − a₀) × (b₁ − b₀)` and `(a₁ − a₀) · (b₁ − b₀)` in the plane, and
//! `n · (q₁ − q₀)` in space.
//!
//! Each is evaluated first in `f64` with a forward error bound (a *filter*, as in Shewchuk's
//! adaptive predicates, "Adaptive precision floating-point arithmetic and fast robust
//! geometric predicates", DCG 18, 1997, §4: the bound `(3 + 16ε)ε·(|l| + |r|)` of
//! `orient2d` applies unchanged, since it already accounts for rounded differences); when
//! the filter cannot decide, the value is computed exactly as a floating-point *expansion*
//! (Shewchuk §2: `Two-Sum`, `Two-Product` with a fused multiply-add, `Grow-Expansion`),
//! whose most significant non-zero component has the sign of the exact value.
//!
//! `Two-Product` is exact only while the rounding error of a product is representable,
//! which holds when the product is at least `2⁻⁹⁰⁰` in magnitude (the error is a multiple
//! of `2^(eₐ+e_b)` and the product is below `2^(106+eₐ+e_b)`). Products that small (inputs
//! around `1e-135` and below) make the exact path give up: the predicates then return
//! `None`, which every caller treats as *undecided*, and an undecided comparison never
//! certifies anything.

/// The sign of an exactly evaluated quantity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sign {
    /// Strictly negative.
    Negative,
    /// Exactly zero.
    Zero,
    /// Strictly positive.
    Positive,
}

impl Sign {
    fn of(x: f64) -> Self {
        if x > 0.0 {
            Self::Positive
        } else if x < 0.0 {
            Self::Negative
        } else {
            Self::Zero
        }
    }
}

const EPS: f64 = f64::EPSILON / 2.0; // 2⁻⁵³, the unit roundoff
/// Shewchuk's `ccwerrboundA`.
const ERR_2X2: f64 = (3.0 + 16.0 * EPS) * EPS;
/// Bound for a 3-term dot product of rounded differences (`γ₄` rounded up generously).
const ERR_DOT3: f64 = 8.0 * EPS;
/// Below this a product's rounding error may not be representable (see the module docs).
const TINY: f64 = P100 * P100 * P100 * P100 * P100 * P100 * P100 * P100 * P100; // 2⁻⁹⁰⁰
/// `2⁻¹⁰⁰` (products of powers of two are exact).
const P100: f64 = 7.888_609_052_210_118e-31;

/// `a + b = s + e` exactly (Knuth's Two-Sum).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// A non-overlapping expansion, components in increasing magnitude (zeros dropped).
#[derive(Default)]
struct Expansion(Vec<f64>);

impl Expansion {
    /// Adds `b` exactly (Shewchuk's Grow-Expansion with zero elimination).
    fn grow(&mut self, b: f64) {
        let mut q = b;
        let mut out = Vec::with_capacity(self.0.len() + 1);
        for &e in &self.0 {
            let (s, h) = two_sum(q, e);
            if h != 0.0 {
                out.push(h);
            }
            q = s;
        }
        if q != 0.0 {
            out.push(q);
        }
        self.0 = out;
    }

    /// Adds the exact product `x·y`; `false` if it cannot be represented exactly.
    fn add_product(&mut self, x: f64, y: f64) -> bool {
        if x == 0.0 || y == 0.0 {
            return true;
        }
        let p = x * y;
        if !p.is_finite() || p.abs() < TINY {
            return false;
        }
        let e = x.mul_add(y, -p);
        self.grow(e);
        self.grow(p);
        true
    }

    fn sign(&self) -> Sign {
        self.0.last().map_or(Sign::Zero, |&x| Sign::of(x))
    }
}

/// The exact difference `a − b` as two components `(hi, lo)`.
#[inline]
fn diff(a: f64, b: f64) -> [f64; 2] {
    let (s, e) = two_sum(a, -b);
    [s, e]
}

/// Exact sign of `Σₖ sₖ·xₖ·yₖ` where `xₖ = x₁ₖ − x₀ₖ` and `yₖ` are exact differences or plain
/// values (given as two-component expansions), and `sₖ = ±1`.
fn exact_sum_of_products(terms: &[([f64; 2], [f64; 2], bool)]) -> Option<Sign> {
    let mut acc = Expansion::default();
    for (x, y, negative) in terms {
        for &xi in x {
            for &yj in y {
                let xi = if *negative { -xi } else { xi };
                if !acc.add_product(xi, yj) {
                    return None;
                }
            }
        }
    }
    Some(acc.sign())
}

/// Sign of the cross product `(a₁ − a₀) × (b₁ − b₀)` of two plane vectors given by their
/// end points, exactly (see the module docs; `None` only for products below `2⁻⁹⁰⁰`).
pub(crate) fn cross2_sign(a0: [f64; 2], a1: [f64; 2], b0: [f64; 2], b1: [f64; 2]) -> Option<Sign> {
    let (ax, ay) = (a1[0] - a0[0], a1[1] - a0[1]);
    let (bx, by) = (b1[0] - b0[0], b1[1] - b0[1]);
    let (l, r) = (ax * by, ay * bx);
    let det = l - r;
    let mag = l.abs() + r.abs();
    if mag.is_finite() && mag > TINY * 4.0 && det.abs() > ERR_2X2 * mag {
        return Some(Sign::of(det));
    }
    exact_sum_of_products(&[
        (diff(a1[0], a0[0]), diff(b1[1], b0[1]), false),
        (diff(a1[1], a0[1]), diff(b1[0], b0[0]), true),
    ])
}

/// Sign of the dot product `(a₁ − a₀) · (b₁ − b₀)` of two plane vectors, exactly.
pub(crate) fn dot2_sign(a0: [f64; 2], a1: [f64; 2], b0: [f64; 2], b1: [f64; 2]) -> Option<Sign> {
    let (ax, ay) = (a1[0] - a0[0], a1[1] - a0[1]);
    let (bx, by) = (b1[0] - b0[0], b1[1] - b0[1]);
    let (l, r) = (ax * bx, ay * by);
    let dot = l + r;
    let mag = l.abs() + r.abs();
    if mag.is_finite() && mag > TINY * 4.0 && dot.abs() > ERR_2X2 * mag {
        return Some(Sign::of(dot));
    }
    exact_sum_of_products(&[
        (diff(a1[0], a0[0]), diff(b1[0], b0[0]), false),
        (diff(a1[1], a0[1]), diff(b1[1], b0[1]), false),
    ])
}

/// Sign of `n · (q₁ − q₀)` for an `f64` vector `n`, exactly.
pub(crate) fn dot3_sign(n: [f64; 3], q0: [f64; 3], q1: [f64; 3]) -> Option<Sign> {
    let mut dot = 0.0;
    let mut mag = 0.0;
    for k in 0..3 {
        let p = n[k] * (q1[k] - q0[k]);
        dot += p;
        mag += p.abs();
    }
    if mag.is_finite() && mag > TINY * 8.0 && dot.abs() > ERR_DOT3 * mag {
        return Some(Sign::of(dot));
    }
    let terms: Vec<([f64; 2], [f64; 2], bool)> = (0..3)
        .map(|k| ([n[k], 0.0], diff(q1[k], q0[k]), false))
        .collect();
    exact_sum_of_products(&terms)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference: integer coordinates make every quantity an exact `i128`.
    fn cross_i(a0: [i64; 2], a1: [i64; 2], b0: [i64; 2], b1: [i64; 2]) -> i128 {
        let ax = (a1[0] - a0[0]) as i128;
        let ay = (a1[1] - a0[1]) as i128;
        let bx = (b1[0] - b0[0]) as i128;
        let by = (b1[1] - b0[1]) as i128;
        ax * by - ay * bx
    }

    fn sign_i(x: i128) -> Sign {
        Sign::of(x as f64)
    }

    fn f(p: [i64; 2], scale: f64) -> [f64; 2] {
        [p[0] as f64 * scale, p[1] as f64 * scale]
    }

    #[test]
    fn tiny_is_two_to_the_minus_900() {
        assert_eq!(TINY, 2f64.powi(-900));
    }

    #[test]
    fn cross_sign_matches_integer_arithmetic_on_huge_integers() {
        // 2⁵² + small offsets: the f64 differences are exact but the products are not.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % 2001) as i64 - 1000
        };
        let big = 1i64 << 52;
        for _ in 0..20000 {
            let a0 = [big + next(), big + next()];
            let a1 = [big + next(), big + next()];
            // b nearly parallel to a: scaled copies of a plus tiny noise.
            let k = next().signum().max(1) * 3;
            let b0 = [big + next(), big + next()];
            let d = [(a1[0] - a0[0]) * k, (a1[1] - a0[1]) * k];
            let b1 = [b0[0] + d[0] + next() % 2, b0[1] + d[1] + next() % 2];
            let want = sign_i(cross_i(a0, a1, b0, b1));
            for scale in [1.0, 2f64.powi(-300), 2f64.powi(150)] {
                let got = cross2_sign(f(a0, scale), f(a1, scale), f(b0, scale), f(b1, scale));
                assert_eq!(got, Some(want), "{a0:?} {a1:?} {b0:?} {b1:?} × {scale}");
            }
        }
    }

    #[test]
    fn exactly_parallel_and_antiparallel_vectors_have_zero_cross_product() {
        let a0 = [0.1, 0.7];
        let a1 = [0.3, 1.3];
        // 0.1 + 0.2 ≠ 0.3 in binary: use exactly representable multiples instead.
        let b0 = [1.5, -2.25];
        let b1 = [1.5 + 0.5, -2.25 + 1.5];
        let c0 = [0.25, 0.5];
        let c1 = [0.25 - 0.125, 0.5 - 0.375];
        let a = [a1[0] - a0[0], a1[1] - a0[1]];
        // a is not exactly (0.2, 0.6): its exact cross product with (1, 3) decides.
        let exact = cross2_sign(a0, a1, [0.0, 0.0], [1.0, 3.0]);
        assert!(exact.is_some());
        assert_eq!(cross2_sign(b0, b1, c0, c1), Some(Sign::Zero));
        assert_eq!(dot2_sign(b0, b1, c0, c1), Some(Sign::Negative));
        assert_eq!(dot2_sign(b0, b1, b0, b1), Some(Sign::Positive));
        assert!(a[0] > 0.0);
    }

    #[test]
    fn sign_of_rounded_cross_product_is_corrected() {
        // (1 + 2⁻⁵²)·(1 − 2⁻⁵³)… built so that the f64 evaluation rounds to 0.
        let e = f64::EPSILON;
        let a0 = [0.0, 0.0];
        let a1 = [1.0 + e, 1.0];
        let b0 = [0.0, 0.0];
        let b1 = [1.0, 1.0 - e];
        // Exact: (1+e)(1−e) − 1 = −e² < 0.
        let naive = (a1[0] * b1[1]) - (a1[1] * b1[0]);
        assert_eq!(naive, 0.0, "the naive value rounds away the sign");
        assert_eq!(cross2_sign(a0, a1, b0, b1), Some(Sign::Negative));
    }

    #[test]
    fn dot3_sign_is_exact_near_zero() {
        let e = f64::EPSILON;
        let n = [1.0 + e, -1.0, 0.0];
        let q0 = [0.0, 0.0, 5.0];
        let q1 = [1.0, 1.0 + e, 7.0];
        // (1+e) − (1+e) = 0 exactly.
        assert_eq!(dot3_sign(n, q0, q1), Some(Sign::Zero));
        let q1 = [1.0 - e / 2.0, 1.0 - e / 2.0, 7.0];
        // (1+e)(1−e/2) − (1−e/2) = e(1 − e/2) > 0
        assert_eq!(dot3_sign(n, q0, q1), Some(Sign::Positive));
        assert_eq!(dot3_sign([0.0; 3], q0, q1), Some(Sign::Zero));
    }

    #[test]
    fn products_below_the_exact_range_are_undecided_not_guessed() {
        let t = 1e-200;
        assert_eq!(
            cross2_sign(
                [0.0, 0.0],
                [t, t],
                [0.0, 0.0],
                [t, t * (1.0 + f64::EPSILON)]
            ),
            None
        );
        // A clear-cut sign is still decided by the filter.
        assert_eq!(
            cross2_sign([0.0, 0.0], [1.0, 0.0], [0.0, 0.0], [0.0, 1.0]),
            Some(Sign::Positive)
        );
    }
}
