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

/// The bases of a [`tensor_batch`] at four parameters `(u, v)`: along the first index of
/// the net, then the second. A trait rather than a closure so that the bicubic B-spline's
/// ([`RegularBases`]) are compiled into the vectorised batch: passed as a function, they
/// stayed a call compiled without AVX (a tenth of the evaluation of a tree-heavy mesh).
pub(crate) trait Bases {
    fn at(&self, u: Lanes, v: Lanes) -> (BasisLanes, BasisLanes);
}

/// The bases of the bicubic B-spline patch: [`basis`] lane by lane (the same formulas, on
/// vectors).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RegularBases;

impl Bases for RegularBases {
    #[inline(always)]
    fn at(&self, u: Lanes, v: Lanes) -> (BasisLanes, BasisLanes) {
        (basis_lanes(u), basis_lanes(v))
    }
}

impl<F: Fn(Lanes, Lanes) -> (BasisLanes, BasisLanes)> Bases for F {
    #[inline(always)]
    fn at(&self, u: Lanes, v: Lanes) -> (BasisLanes, BasisLanes) {
        self(u, v)
    }
}

/// [`basis`] at four parameters: `[B, B′, B″][i][lane]`. The same formulas, written again
/// lane by lane so that they compile to vector operations (the scalar [`basis`] per lane
/// and a transposition cost 51 instructions per point, this 11); test
/// `batch_without_fma_is_tensor_into_bit_for_bit` checks that both give the same bits.
#[inline(always)]
fn basis_lanes(t: Lanes) -> BasisLanes {
    let mut r: BasisLanes = Default::default();
    for l in 0..LANES {
        let t = t[l];
        let s = 1.0 - t;
        let t2 = t * t;
        let t3 = t2 * t;
        r[0][0][l] = s * s * s / 6.0;
        r[0][1][l] = (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0;
        r[0][2][l] = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0;
        r[0][3][l] = t3 / 6.0;
        r[1][0][l] = -0.5 * s * s;
        r[1][1][l] = 1.5 * t2 - 2.0 * t;
        r[1][2][l] = -1.5 * t2 + t + 0.5;
        r[1][3][l] = 0.5 * t2;
        r[2][0][l] = s;
        r[2][1][l] = 3.0 * t - 2.0;
        r[2][2][l] = -3.0 * t + 1.0;
        r[2][3][l] = t;
    }
    r
}

/// The bases of four points, given as one [`Basis`] per point, by lane.
#[inline(always)]
pub(crate) fn transpose_bases(per_lane: [Basis; LANES]) -> BasisLanes {
    let mut r: BasisLanes = Default::default();
    for (l, (b, d, dd)) in per_lane.iter().enumerate() {
        for i in 0..4 {
            (r[0][i][l], r[1][i][l], r[2][i][l]) = (b[i], d[i], dd[i]);
        }
    }
    r
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

/// Values and first and second derivatives of four basis functions at one parameter
/// (as [`basis`] returns them).
pub(crate) type Basis = ([f64; 4], [f64; 4], [f64; 4]);

/// The points of a batch evaluation of one patch ([`tensor_batch`]): the parameter of
/// point `i`, and where its result goes.
pub(crate) trait Batch {
    /// Number of points.
    fn len(&self) -> usize;
    /// The parameter `(u, v)` of point `i`.
    fn uv(&self, i: usize) -> (f64, f64);
    /// Where point `i`'s derivatives are written (every field is overwritten).
    fn out(&mut self, i: usize) -> &mut Derivatives;
}

/// Points evaluated together by [`tensor_batch`]: one 256-bit vector of `f64` per value.
pub(crate) const LANES: usize = 4;

/// One value per lane.
pub(crate) type Lanes = [f64; LANES];

/// Four basis functions and their first and second derivatives at [`LANES`] parameters:
/// `[values, first, second][function][lane]`.
pub(crate) type BasisLanes = [[Lanes; 4]; 3];

/// [`tensor_into`] at every point of `batch`, with the bases `bases(u, v)` (along the first
/// and the second index of `cp`, at four points at a time), the first derivatives
/// multiplied by `scale` and the second by `scale²` (a sub-patch of side `1/scale`).
///
/// The points are evaluated four at a time, one per lane of a vector: each control point
/// is loaded once per four points, and the sums of [`tensor_into`] (the same ones, in the
/// same order) run on vectors. Where the processor has FMA (detected at run time), the
/// multiply-adds are fused, so the last bits may differ from [`tensor_into`]'s; on a given
/// processor a point's result does not depend on the other points of its batch. On an 8×8
/// grid on every face of a 15 k-quad mesh (957 k points, position and first derivatives,
/// one thread), with the nets kept across re-posing (`surface.rs`), this takes about a
/// third of the instructions per point of one point at a time (`BENCHMARKS.md`).
pub(crate) fn tensor_batch(
    cp: &[[[f64; 3]; 4]; 4],
    bases: impl Bases,
    order: Order,
    scale: f64,
    batch: &mut impl Batch,
) {
    #[cfg(target_arch = "x86_64")]
    if crate::cpu::has_avx2_fma() {
        // SAFETY: the features were just detected.
        unsafe { tensor_batch_avx(cp, bases, order, scale, batch) };
        return;
    }
    match order {
        Order::First => tensor_lanes::<false, false>(cp, bases, scale, batch),
        Order::Second => tensor_lanes::<true, false>(cp, bases, scale, batch),
    }
}

/// [`tensor_batch`] compiled with AVX2 and FMA.
///
/// # Safety
/// The processor has AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn tensor_batch_avx(
    cp: &[[[f64; 3]; 4]; 4],
    bases: impl Bases,
    order: Order,
    scale: f64,
    batch: &mut impl Batch,
) {
    // SAFETY (both): the processor has AVX2 and FMA (this function's contract).
    match (order, batch.len()) {
        (Order::First, 1) => unsafe { tensor_one_avx::<false>(cp, bases, scale, batch) },
        (Order::Second, 1) => unsafe { tensor_one_avx::<true>(cp, bases, scale, batch) },
        (Order::First, _) => tensor_lanes::<false, true>(cp, bases, scale, batch),
        (Order::Second, _) => tensor_lanes::<true, true>(cp, bases, scale, batch),
    }
}

/// [`tensor_batch_avx`] for a batch of one point, by point: each control point's three
/// coordinates in one vector, so a column sum is four multiply-adds per value, not twelve
/// (one per coordinate) on vectors of which one lane of four is the point. The sums of
/// [`tensor_lanes`] at its first lane, in the same order: the same bits.
///
/// Deep in a configuration tree a patch child mostly holds one point (`catmark_chaikin1`:
/// 680 of 856 patch batches a repetition).
///
/// # Safety
/// The processor has AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn tensor_one_avx<const SECOND: bool>(
    cp: &[[[f64; 3]; 4]; 4],
    bases: impl Bases,
    scale: f64,
    batch: &mut impl Batch,
) {
    use crate::cpu::{load3, store3};
    use std::arch::x86_64::*;
    let (u, v) = batch.uv(0);
    // All four lanes at the point, as `tensor_lanes` fills a batch of one.
    let (a, b) = bases.at([u; LANES], [v; LANES]);
    let at = |x: f64| _mm256_set1_pd(x);
    let zero = _mm256_setzero_pd();
    let mut r = [zero; 6];
    for (i, col) in cp.iter().enumerate() {
        let mut q = [zero; 3];
        for (j, p) in col.iter().enumerate() {
            // SAFETY: `p` is three `f64`; the processor has AVX.
            let p = unsafe { load3(p.as_ptr()) };
            q[0] = _mm256_fmadd_pd(at(b[0][j][0]), p, q[0]);
            q[1] = _mm256_fmadd_pd(at(b[1][j][0]), p, q[1]);
            if SECOND {
                q[2] = _mm256_fmadd_pd(at(b[2][j][0]), p, q[2]);
            }
        }
        let (ai, dai, ddai) = (at(a[0][i][0]), at(a[1][i][0]), at(a[2][i][0]));
        r[0] = _mm256_fmadd_pd(ai, q[0], r[0]);
        r[1] = _mm256_fmadd_pd(dai, q[0], r[1]);
        r[2] = _mm256_fmadd_pd(ai, q[1], r[2]);
        if SECOND {
            r[3] = _mm256_fmadd_pd(ddai, q[0], r[3]);
            r[4] = _mm256_fmadd_pd(dai, q[1], r[4]);
            r[5] = _mm256_fmadd_pd(ai, q[2], r[5]);
        }
    }
    let (s, s2) = (at(scale), at(scale * scale));
    let d = batch.out(0);
    // SAFETY (all): each is three `f64`; the processor has AVX.
    unsafe {
        store3(d.p.as_mut_ptr(), r[0]);
        store3(d.du.as_mut_ptr(), _mm256_mul_pd(r[1], s));
        store3(d.dv.as_mut_ptr(), _mm256_mul_pd(r[2], s));
    }
    if SECOND {
        // SAFETY: as above.
        unsafe {
            store3(d.duu.as_mut_ptr(), _mm256_mul_pd(r[3], s2));
            store3(d.duv.as_mut_ptr(), _mm256_mul_pd(r[4], s2));
            store3(d.dvv.as_mut_ptr(), _mm256_mul_pd(r[5], s2));
        }
    } else {
        (d.duu, d.duv, d.dvv) = ([0.0; 3], [0.0; 3], [0.0; 3]);
    }
}

/// `a × b + c`, fused when `FMA` (a constant: only where the processor has it, else a
/// fused multiply-add is a slow library call).
#[inline(always)]
fn madd<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// The body of [`tensor_batch`]: second derivatives when `SECOND`, fused multiply-adds
/// when `FMA`.
#[inline(always)]
fn tensor_lanes<const SECOND: bool, const FMA: bool>(
    cp: &[[[f64; 3]; 4]; 4],
    bases: impl Bases,
    scale: f64,
    batch: &mut impl Batch,
) {
    let n = batch.len();
    let mut start = 0;
    while start < n {
        let count = LANES.min(n - start);
        // The parameters by lane (the lanes past the end repeat the last point), and the
        // bases: `a[d][i][lane]` (d: value, first, second derivative).
        let (mut u, mut v) = ([0.0; LANES], [0.0; LANES]);
        for l in 0..LANES {
            (u[l], v[l]) = batch.uv(start + l.min(count - 1));
        }
        let (a, b) = bases.at(u, v);
        // As `tensor_to`: column sums along the second index, then along the first.
        // r[0] = S, r[1] = Su, r[2] = Sv, r[3] = Suu, r[4] = Suv, r[5] = Svv.
        let mut r: [[Lanes; 3]; 6] = Default::default();
        for (i, col) in cp.iter().enumerate() {
            let mut q: [[Lanes; 3]; 3] = Default::default();
            for (j, p) in col.iter().enumerate() {
                for k in 0..3 {
                    for l in 0..LANES {
                        q[0][k][l] = madd::<FMA>(b[0][j][l], p[k], q[0][k][l]);
                        q[1][k][l] = madd::<FMA>(b[1][j][l], p[k], q[1][k][l]);
                        if SECOND {
                            q[2][k][l] = madd::<FMA>(b[2][j][l], p[k], q[2][k][l]);
                        }
                    }
                }
            }
            for k in 0..3 {
                for l in 0..LANES {
                    let (ai, dai, ddai) = (a[0][i][l], a[1][i][l], a[2][i][l]);
                    r[0][k][l] = madd::<FMA>(ai, q[0][k][l], r[0][k][l]);
                    r[1][k][l] = madd::<FMA>(dai, q[0][k][l], r[1][k][l]);
                    r[2][k][l] = madd::<FMA>(ai, q[1][k][l], r[2][k][l]);
                    if SECOND {
                        r[3][k][l] = madd::<FMA>(ddai, q[0][k][l], r[3][k][l]);
                        r[4][k][l] = madd::<FMA>(dai, q[1][k][l], r[4][k][l]);
                        r[5][k][l] = madd::<FMA>(ai, q[2][k][l], r[5][k][l]);
                    }
                }
            }
        }
        let s2 = scale * scale;
        for l in 0..count {
            let d = batch.out(start + l);
            let at = |m: usize, f: f64| [r[m][0][l] * f, r[m][1][l] * f, r[m][2][l] * f];
            d.p = at(0, 1.0);
            d.du = at(1, scale);
            d.dv = at(2, scale);
            (d.duu, d.duv, d.dvv) = if SECOND {
                (at(3, s2), at(4, s2), at(5, s2))
            } else {
                ([0.0; 3], [0.0; 3], [0.0; 3])
            };
        }
        start += count;
    }
}

/// A batch of one point, written into `out` (for tests).
#[cfg(test)]
pub(crate) struct One<'a> {
    pub u: f64,
    pub v: f64,
    pub out: &'a mut Derivatives,
}

#[cfg(test)]
impl Batch for One<'_> {
    fn len(&self) -> usize {
        1
    }
    fn uv(&self, _: usize) -> (f64, f64) {
        (self.u, self.v)
    }
    fn out(&mut self, _: usize) -> &mut Derivatives {
        self.out
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

    /// A batch of points given as a list, written into a list.
    struct List {
        uv: Vec<(f64, f64)>,
        out: Vec<Derivatives>,
    }

    impl Batch for List {
        fn len(&self) -> usize {
            self.uv.len()
        }
        fn uv(&self, i: usize) -> (f64, f64) {
            self.uv[i]
        }
        fn out(&mut self, i: usize) -> &mut Derivatives {
            &mut self.out[i]
        }
    }

    /// A wavy, asymmetric net and `n` parameters spread over the patch.
    fn net_and_points(n: usize) -> ([[[f64; 3]; 4]; 4], List) {
        let cp = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let (x, y) = (i as f64, j as f64);
                [
                    x + 0.1 * y * y,
                    y - 0.2 * x,
                    (1.3 * x).sin() * (0.7 * y + 0.4).cos(),
                ]
            })
        });
        let uv = (0..n)
            .map(|k| {
                let t = k as f64 / n.max(2) as f64;
                (t, (0.37 + 0.61 * t) % 1.0)
            })
            .collect();
        let out = vec![Derivatives::default(); n];
        (cp, List { uv, out })
    }

    /// Without FMA the batch runs the very sums of `tensor_into`, in the same order: the
    /// same bits, for every batch size (full and partial groups of lanes) and order.
    #[test]
    fn batch_without_fma_is_tensor_into_bit_for_bit() {
        for n in 1..=9 {
            for order in [Order::First, Order::Second] {
                let (cp, mut list) = net_and_points(n);
                match order {
                    Order::First => tensor_lanes::<false, false>(&cp, RegularBases, 2.0, &mut list),
                    Order::Second => tensor_lanes::<true, false>(&cp, RegularBases, 2.0, &mut list),
                }
                for (&(u, v), got) in list.uv.iter().zip(&list.out) {
                    let mut want = Derivatives::default();
                    tensor_into(&cp, basis(u), basis(v), order, &mut want);
                    assert_eq!(*got, want.scaled(2.0), "n {n} {order:?} at ({u}, {v})");
                }
            }
        }
    }

    /// With whatever the processor has (fused multiply-adds or not), the batch agrees
    /// with `tensor_into` to rounding, and a point's result does not depend on the other
    /// points of its batch: a batch of one (a kernel of its own with AVX2) gives the bits
    /// of the same point in a batch of eleven, for either order.
    #[test]
    fn batch_agrees_with_single_points() {
        for order in [Order::First, Order::Second] {
            let (cp, mut all) = net_and_points(11);
            tensor_batch(&cp, RegularBases, order, 2.0, &mut all);
            for (&(u, v), got) in all.uv.iter().zip(&all.out) {
                let mut alone = Derivatives::default();
                let one = &mut One {
                    u,
                    v,
                    out: &mut alone,
                };
                tensor_batch(&cp, RegularBases, order, 2.0, one);
                assert_eq!(*got, alone, "{order:?} at ({u}, {v})");
                let mut want = Derivatives::default();
                tensor_into(&cp, basis(u), basis(v), order, &mut want);
                let want = want.scaled(2.0);
                let fields = |d: &Derivatives| [d.p, d.du, d.dv, d.duu, d.duv, d.dvv];
                for (a, b) in fields(got).iter().zip(&fields(&want)) {
                    for k in 0..3 {
                        assert!((a[k] - b[k]).abs() < 1e-14, "({u}, {v}): {a:?} vs {b:?}");
                    }
                }
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
