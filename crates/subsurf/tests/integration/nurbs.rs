//! # B-splines and NURBS (`subsurf::nurbs`), as specifications
//!
//! Each test states a property of B-spline curves and surfaces and checks it against an
//! independent computation, on fixed examples and on random knot vectors (proptest):
//!
//! 1. **Basis functions** equal the textbook Cox–de Boor recursion, are non-negative and sum
//!    to one; their derivatives sum to zero.
//! 2. **Evaluation**: a B-spline built from the blossom of a polynomial *is* that polynomial,
//!    with the same derivatives; a Bézier curve equals de Casteljau's construction;
//!    derivatives match finite differences; closed curves are periodic; a tensor-product
//!    surface is a curve of curves, derivatives included.
//! 3. **Knot insertion** (open, clamped, periodic; degrees 1–5; single, many, midpoints)
//!    leaves the curve unchanged to 1e-12, and refinement in one pass equals insertions one
//!    at a time; likewise for surfaces along `u` and `v`.
//! 4. **Rational geometry is exact**: the NURBS circle, cylinder and torus evaluate to points
//!    on the exact circle, cylinder and torus (1e-14), before and after refinement.
//! 5. **Convergence**: after `k` midpoint steps the control polygon (net) is within
//!    `C · 4^-k` of the curve (surface).
//! 6. **Control mesh with knot intervals**: the NURSS convention (edge `P_i P_{i+1}` carries
//!    `t_{i+3} − t_{i+2}`), equal intervals for uniform knots, zero at clamped ends, face
//!    `(i, j)` ↔ span `[t_{i+2}, t_{i+3}] × [s_{j+2}, s_{j+3}]`; a uniform periodic bicubic
//!    surface is the Catmull-Clark limit surface of its control mesh.
//! 7. **JSON**: round trips are bit-exact; every malformed document names the bad field.
//! 8. **Bad input** gives typed errors.

// Geometry helpers walk parallel arrays with one index.
#![allow(clippy::needless_range_loop)]

use proptest::prelude::*;
use subsurf::limit::LimitSurface;
use subsurf::mesh::Options;
use subsurf::nurbs::{
    basis_derivatives, basis_functions, from_json_str, BSplineCurve, BSplineSurface, Curve,
    Geometry, KnotVector, NurbsCurve, NurbsError, NurbsSurface, Surface,
};

fn dist<const D: usize>(a: &[f64; D], b: &[f64; D]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// `n` parameters spread over `[a, b]`, both ends included.
fn params((a, b): (f64, f64), n: usize) -> impl Iterator<Item = f64> {
    (0..=n).map(move |i| {
        if i == n {
            b
        } else {
            a + (b - a) * i as f64 / n as f64
        }
    })
}

// ---------------------------------------------------------------------------------------
// Random knot vectors and curves.

/// Knot intervals: mostly positive and uneven, sometimes zero (multiple knots).
fn interval() -> impl Strategy<Value = f64> {
    prop_oneof![1 => Just(0.0), 5 => 0.05f64..2.0]
}

/// Kind of knot vector.
#[derive(Clone, Copy, Debug)]
enum Kind {
    Open,
    Clamped,
    Periodic,
}

/// A random valid knot vector of degree 1–5: open (unclamped), clamped, or periodic.
fn knot_vector() -> impl Strategy<Value = KnotVector> {
    knot_vector_of(&[Kind::Open, Kind::Clamped, Kind::Periodic])
}

/// A random valid knot vector of one of the given kinds.
fn knot_vector_of(kinds: &[Kind]) -> impl Strategy<Value = KnotVector> {
    (
        1usize..=5,
        0usize..=7,
        prop::sample::select(kinds.to_vec()),
        prop::collection::vec(interval(), 20),
        -3.0f64..3.0,
    )
        .prop_filter_map("invalid knot vector", |(p, extra, kind, d, shift)| {
            let k = match kind {
                Kind::Clamped => KnotVector::from_intervals(p, &d[..1 + extra], true),
                Kind::Open => KnotVector::from_intervals(p, &d[..2 * p + 1 + extra], false),
                Kind::Periodic => KnotVector::periodic_from_intervals(p, &d[..p.max(2) + extra]),
            }
            .ok()?;
            // Shift the parameter range away from 0.
            let shifted: Vec<f64> = match k.period_knots() {
                Some(u) => u.iter().map(|t| t + shift).collect(),
                None => k.as_slice().iter().map(|t| t + shift).collect(),
            };
            if k.is_periodic() {
                KnotVector::periodic(p, &shifted).ok()
            } else {
                KnotVector::new(p, shifted).ok()
            }
        })
}

fn point3() -> impl Strategy<Value = [f64; 3]> {
    [-5.0f64..5.0, -5.0f64..5.0, -5.0f64..5.0]
}

/// A random curve in 3D on a random knot vector.
fn curve() -> impl Strategy<Value = BSplineCurve<3>> {
    curve_of(&[Kind::Open, Kind::Clamped, Kind::Periodic])
}

/// A random curve in 3D on a random knot vector of one of the given kinds.
fn curve_of(kinds: &[Kind]) -> impl Strategy<Value = BSplineCurve<3>> {
    (knot_vector_of(kinds), prop::collection::vec(point3(), 20)).prop_map(|(k, pts)| {
        let n = k.num_points();
        BSplineCurve::new(k, pts[..n].to_vec()).expect("sizes match")
    })
}

/// A random NURBS curve (weights in [0.2, 5]).
fn nurbs_curve() -> impl Strategy<Value = NurbsCurve> {
    (
        knot_vector(),
        prop::collection::vec(point3(), 20),
        prop::collection::vec(0.2f64..5.0, 20),
    )
        .prop_map(|(k, pts, w)| {
            let n = k.num_points();
            NurbsCurve::new(k, pts[..n].to_vec(), w[..n].to_vec()).expect("valid")
        })
}

/// A parameter at fraction `s` of the domain.
fn at(k: &KnotVector, s: f64) -> f64 {
    let (a, b) = k.domain();
    (a + (b - a) * s).min(b)
}

// ---------------------------------------------------------------------------------------
// 1. Basis functions.

/// The Cox–de Boor recursion as in the textbook (eq. 2.5 of The NURBS Book), `0/0 = 0`;
/// degree-0 functions are the indicators of `[t_i, t_{i+1})`, except at the end `b` of the
/// domain, where the last non-empty span ending at `b` is taken as closed.
fn cox_de_boor(k: &[f64], i: usize, p: usize, t: f64, b: f64) -> f64 {
    if p == 0 {
        let inside = if t == b {
            k[i] < k[i + 1] && k[i + 1] == b
        } else {
            k[i] <= t && t < k[i + 1]
        };
        return if inside { 1.0 } else { 0.0 };
    }
    let mut s = 0.0;
    if k[i + p] > k[i] {
        s += (t - k[i]) / (k[i + p] - k[i]) * cox_de_boor(k, i, p - 1, t, b);
    }
    if k[i + p + 1] > k[i + 1] {
        s += (k[i + p + 1] - t) / (k[i + p + 1] - k[i + 1]) * cox_de_boor(k, i + 1, p - 1, t, b);
    }
    s
}

proptest! {
    #[test]
    fn basis_functions_are_cox_de_boor_nonnegative_and_a_partition_of_unity(
        k in knot_vector(), s in 0.0f64..=1.0,
    ) {
        let t = at(&k, s);
        let p = k.degree();
        let (span, n) = basis_functions(&k, t).unwrap();
        prop_assert_eq!(n.len(), p + 1);
        prop_assert!(n.iter().all(|&x| x >= 0.0), "{:?}", n);
        prop_assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        let b = k.domain().1;
        for i in 0..k.num_basis() {
            let expect = cox_de_boor(k.as_slice(), i, p, t, b);
            let got = if i + p >= span && i <= span { n[i + p - span] } else { 0.0 };
            prop_assert!((got - expect).abs() < 1e-12, "N_{},{}({}) = {} vs {}", i, p, t, got, expect);
        }
        let (span2, d) = basis_derivatives(&k, t, p + 1).unwrap();
        prop_assert_eq!(span2, span);
        for (j, row) in d.iter().enumerate() {
            let sum: f64 = row.iter().sum();
            let scale: f64 = row.iter().map(|x| x.abs()).sum::<f64>().max(1.0);
            if j == 0 {
                prop_assert!((sum - 1.0).abs() < 1e-14);
                prop_assert_eq!(row, &n);
            } else {
                prop_assert!(sum.abs() < 1e-11 * scale, "order {}: {:?}", j, row);
            }
        }
        prop_assert!(d[p + 1].iter().all(|&x| x == 0.0));
    }
}

#[test]
fn basis_derivatives_match_finite_differences() {
    let k = KnotVector::new(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.1, 2.5, 2.5, 2.5, 2.5],
    )
    .unwrap();
    let h = 1e-6;
    for t in [0.2, 0.7, 1.05, 1.8] {
        let (s, d) = basis_derivatives(&k, t, 2).unwrap();
        let (s1, n1) = basis_functions(&k, t + h).unwrap();
        let (s0, n0) = basis_functions(&k, t - h).unwrap();
        assert!(s == s1 && s == s0);
        for r in 0..4 {
            let fd = (n1[r] - n0[r]) / (2.0 * h);
            assert!((fd - d[1][r]).abs() < 1e-7, "{t} {r}: {fd} vs {}", d[1][r]);
            let fd2 = (n1[r] - 2.0 * d[0][r] + n0[r]) / (h * h);
            assert!(
                (fd2 - d[2][r]).abs() < 1e-3,
                "{t} {r}: {fd2} vs {}",
                d[2][r]
            );
        }
    }
}

// ---------------------------------------------------------------------------------------
// 2. Evaluation.

/// The control points of the polynomial `f(t) = Σ_k a_k t^k` (degree ≤ p) as a B-spline on
/// the knots `k`: the blossom `P_i = F(t_{i+1}, …, t_{i+p})`, where the blossom of `t^k` is
/// the elementary symmetric polynomial `e_k` divided by `C(p, k)` (de Boor–Fix / Ramshaw).
fn blossom_points(k: &KnotVector, coeffs: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let p = k.degree();
    let t = k.as_slice();
    (0..k.num_points())
        .map(|i| {
            let args = &t[i + 1..=i + p];
            // e[j] = elementary symmetric polynomial of degree j of args.
            let mut e = vec![0.0; p + 1];
            e[0] = 1.0;
            for &x in args {
                for j in (1..=p).rev() {
                    e[j] += x * e[j - 1];
                }
            }
            let mut out = [0.0; 3];
            let mut binom = 1.0; // C(p, j)
            for (j, a) in coeffs.iter().enumerate() {
                if j > 0 {
                    binom = binom * (p + 1 - j) as f64 / j as f64;
                }
                for c in 0..3 {
                    out[c] += a[c] * e[j] / binom;
                }
            }
            out
        })
        .collect()
}

/// `d^r/dt^r Σ_k a_k t^k`.
fn poly_deriv(coeffs: &[[f64; 3]], t: f64, r: usize) -> [f64; 3] {
    let mut out = [0.0; 3];
    for (k, a) in coeffs.iter().enumerate().skip(r) {
        let falling: f64 = (k + 1 - r..=k).map(|x| x as f64).product();
        for c in 0..3 {
            out[c] += a[c] * falling * t.powi((k - r) as i32);
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn a_blossomed_polynomial_is_that_polynomial_with_its_derivatives(
        // A polynomial is not periodic.
        k in knot_vector_of(&[Kind::Open, Kind::Clamped]),
        coeffs in prop::collection::vec([-2.0f64..2.0, -2.0f64..2.0, -2.0f64..2.0], 6),
    ) {
        let p = k.degree();
        let coeffs = &coeffs[..=p];
        let c = BSplineCurve::new(k.clone(), blossom_points(&k, coeffs)).unwrap();
        let scale = 1.0 + k.as_slice().iter().fold(0.0f64, |m, t| m.max(t.abs())).powi(p as i32);
        for t in params(k.domain(), 17) {
            let d = c.eval_derivs(t, p + 1).unwrap();
            prop_assert!(dist(&c.eval(t).unwrap(), &d[0]) < 1e-12 * scale * 10.0);
            for r in 0..=p + 1 {
                let exact = poly_deriv(coeffs, t, r);
                let tol = 1e-9 * scale * (1.0 + 10f64.powi(r as i32));
                prop_assert!(dist(&d[r], &exact) < tol, "t {} order {}: {:?} vs {:?}", t, r, d[r], exact);
            }
        }
    }

    #[test]
    fn a_bezier_curve_is_de_casteljau(
        pts in prop::collection::vec(point3(), 2..10), s in 0.0f64..=1.0,
    ) {
        let c = BSplineCurve::bezier(pts.clone()).unwrap();
        let mut q = pts.clone();
        for r in 1..q.len() {
            for i in 0..q.len() - r {
                for d in 0..3 {
                    q[i][d] = (1.0 - s) * q[i][d] + s * q[i + 1][d];
                }
            }
        }
        prop_assert!(dist(&c.eval(s).unwrap(), &q[0]) < 1e-13);
    }

    #[test]
    fn derivatives_match_finite_differences(c in curve(), s in 0.05f64..0.95) {
        let t = at(c.knots(), s);
        let k = c.knots().as_slice();
        let span = c.knots().span(t).unwrap();
        let h = 1e-6;
        // Stay inside one polynomial piece.
        prop_assume!(t - h > k[span] && t + h < k[span + 1]);
        let d = c.eval_derivs(t, 2).unwrap();
        let (a, b) = (c.eval(t - h).unwrap(), c.eval(t + h).unwrap());
        let scale = 1.0 + d[1].iter().map(|x| x.abs()).sum::<f64>() + d[2].iter().map(|x| x.abs()).sum::<f64>();
        for i in 0..3 {
            let fd = (b[i] - a[i]) / (2.0 * h);
            prop_assert!((fd - d[1][i]).abs() < 1e-6 * scale, "{} vs {}", fd, d[1][i]);
        }
    }

    #[test]
    fn a_closed_curve_is_periodic(c in curve_of(&[Kind::Periodic]), s in 0.0f64..1.0) {
        prop_assert!(c.is_closed());
        let (a, b) = c.domain();
        let t = at(c.knots(), s);
        let p0 = c.eval(t).unwrap();
        for shift in [-2.0, -1.0, 1.0, 3.0] {
            prop_assert!(dist(&p0, &c.eval(t + shift * (b - a)).unwrap()) < 1e-11);
        }
        // The seam: C(u_0) = C(u_n).
        prop_assert!(dist(&c.eval(a).unwrap(), &c.eval(b).unwrap()) < 1e-12);
    }
}

/// A random surface on two random knot vectors (each open, clamped or periodic).
fn surface() -> impl Strategy<Value = BSplineSurface<3>> {
    (
        knot_vector(),
        knot_vector(),
        prop::collection::vec(point3(), 400),
    )
        .prop_map(|(u, v, p)| {
            let n = u.num_points() * v.num_points();
            BSplineSurface::new(u, v, p[..n].to_vec()).expect("sizes match")
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn a_surface_is_a_curve_of_curves(s in surface(), a in 0.0f64..=1.0, b in 0.0f64..=1.0) {
        // S(u, v) = Σ_i N_i(u) C_i(v), C_i the curve through row i: evaluate the rows along
        // v, then the resulting curve along u, with the same derivatives.
        let (u, v) = (at(s.knots_u(), a), at(s.knots_v(), b));
        let (nu, nv) = s.size();
        let rows: Vec<Vec<[f64; 3]>> = (0..nu)
            .map(|i| {
                let row = (0..nv).map(|j| *s.point(i, j).unwrap()).collect();
                BSplineCurve::new(s.knots_v().clone(), row).unwrap().eval_derivs(v, 1).unwrap()
            })
            .collect();
        let along = |k: usize| {
            let pts = rows.iter().map(|r| r[k]).collect();
            BSplineCurve::new(s.knots_u().clone(), pts).unwrap().eval_derivs(u, 1).unwrap()
        };
        let (c0, c1) = (along(0), along(1));
        let d = s.eval_derivs(u, v, 2).unwrap();
        let tol = |x: &[f64; 3]| 1e-10 * (1.0 + x.iter().map(|c| c.abs()).sum::<f64>());
        prop_assert!(dist(&s.eval(u, v).unwrap(), &c0[0]) < tol(&c0[0]));
        prop_assert!(dist(&d[0][0], &c0[0]) < tol(&c0[0]));
        prop_assert!(dist(&d[1][0], &c0[1]) < tol(&c0[1]));
        prop_assert!(dist(&d[0][1], &c1[0]) < tol(&c1[0]));
        prop_assert!(dist(&d[1][1], &c1[1]) < tol(&c1[1]));
    }

    #[test]
    fn surface_knot_insertion_leaves_the_surface_unchanged(
        s in surface(), a in 0.0f64..=1.0, b in 0.0f64..=1.0,
    ) {
        let mut r = s.clone();
        if r.insert_knots_u(&[at(s.knots_u(), a)]).is_err() {
            prop_assert_eq!(&r, &s);
        }
        let _ = r.insert_knots_v(&[at(s.knots_v(), b)]);
        r.insert_midpoints().unwrap();
        prop_assert_eq!(r.is_closed(), s.is_closed());
        for x in params(s.knots_u().domain(), 9) {
            for y in params(s.knots_v().domain(), 9) {
                prop_assert!(dist(&s.eval(x, y).unwrap(), &r.eval(x, y).unwrap()) < 1e-11);
            }
        }
    }
}

#[test]
fn a_closed_uniform_cubic_starts_at_its_documented_point() {
    let pts = vec![
        [0.0, 0.0, 0.0],
        [6.0, 0.0, 0.0],
        [6.0, 6.0, 0.0],
        [0.0, 6.0, 3.0],
        [-3.0, 3.0, 0.0],
    ];
    let c = BSplineCurve::closed_uniform(3, pts.clone()).unwrap();
    assert_eq!(c.domain(), (0.0, 5.0));
    // C(u_0) = (P_0 + 4 P_1 + P_2) / 6, C(u_1) = (P_1 + 4 P_2 + P_3) / 6, ...
    for i in 0..5 {
        let e: [f64; 3] = std::array::from_fn(|d| {
            (pts[i][d] + 4.0 * pts[(i + 1) % 5][d] + pts[(i + 2) % 5][d]) / 6.0
        });
        assert!(dist(&c.eval(i as f64).unwrap(), &e) < 1e-14);
    }
    // C² everywhere, including across the seam.
    let l = c.eval_derivs(5.0 - 1e-9, 2).unwrap();
    let r = c.eval_derivs(0.0, 2).unwrap();
    assert!(dist(&l[1], &r[1]) < 1e-7 && dist(&l[2], &r[2]) < 1e-6);
}

#[test]
fn a_clamped_curve_interpolates_its_end_points_and_end_tangents() {
    let pts = vec![
        [0.0, 0.0, 0.0],
        [1.0, 2.0, 0.0],
        [3.0, 2.0, 1.0],
        [4.0, 0.0, 0.0],
    ];
    let c = BSplineCurve::clamped_uniform(2, pts.clone()).unwrap();
    assert!(c.knots().is_clamped());
    assert_eq!(c.eval(0.0).unwrap(), pts[0]);
    assert_eq!(c.eval(1.0).unwrap(), pts[3]);
    // C'(0) = p / (t_{p+1} − t_1) (P_1 − P_0) (The NURBS Book eq. 3.7).
    let d = c.eval_derivs(0.0, 1).unwrap();
    let f = 2.0 / 0.5;
    assert!(dist(&d[1], &[f * 1.0, f * 2.0, 0.0]) < 1e-13);
}

// ---------------------------------------------------------------------------------------
// 3. Knot insertion.

proptest! {
    #[test]
    fn knot_insertion_leaves_the_curve_unchanged(c in curve(), s in 0.0f64..=1.0) {
        let t = at(c.knots(), s);
        let mut r = c.clone();
        match r.insert_knot(t) {
            Err(NurbsError::KnotMultiplicity { .. }) => {
                prop_assert_eq!(&r, &c); // unchanged on error
                return Ok(());
            }
            other => prop_assert!(other.is_ok(), "{:?}", other),
        }
        prop_assert_eq!(r.points().len(), c.points().len() + 1);
        prop_assert_eq!(r.knots().multiplicity(t), c.knots().multiplicity(t) + 1);
        prop_assert_eq!(r.domain(), c.domain());
        for x in params(c.domain(), 50) {
            let (a, b) = (c.eval(x).unwrap(), r.eval(x).unwrap());
            prop_assert!(dist(&a, &b) < 1e-12, "at {}: {:?} vs {:?}", x, a, b);
        }
    }

    #[test]
    fn refinement_in_one_pass_equals_insertions_one_at_a_time(
        c in curve(), ss in prop::collection::vec(0.0f64..=1.0, 1..6),
    ) {
        let ts: Vec<f64> = ss.iter().map(|&s| at(c.knots(), s)).collect();
        let mut once = c.clone();
        let res = once.insert_knots(&ts);
        let mut seq = c.clone();
        let res_seq = ts.iter().try_for_each(|&t| seq.insert_knot(t));
        prop_assert_eq!(res.is_ok(), res_seq.is_ok());
        if res.is_err() {
            prop_assert_eq!(&once, &c);
            return Ok(());
        }
        prop_assert_eq!(once.knots(), seq.knots());
        for (a, b) in once.points().iter().zip(seq.points()) {
            prop_assert!(dist(a, b) < 1e-12);
        }
        for x in params(c.domain(), 40) {
            prop_assert!(dist(&c.eval(x).unwrap(), &once.eval(x).unwrap()) < 1e-12);
        }
    }

    #[test]
    fn midpoint_insertion_halves_every_interval_and_keeps_the_curve(c in curve()) {
        let mut r = c.clone();
        r.insert_midpoints().unwrap();
        let before: Vec<f64> = c.knots().domain_intervals().into_iter().filter(|&d| d > 0.0).collect();
        let after: Vec<f64> = r.knots().domain_intervals().into_iter().filter(|&d| d > 0.0).collect();
        prop_assert_eq!(after.len(), 2 * before.len());
        for (i, d) in before.iter().enumerate() {
            prop_assert!((after[2 * i] + after[2 * i + 1] - d).abs() < 1e-14 * (1.0 + d));
            prop_assert!((after[2 * i] - after[2 * i + 1]).abs() < 1e-14 * (1.0 + d));
        }
        for x in params(c.domain(), 40) {
            prop_assert!(dist(&c.eval(x).unwrap(), &r.eval(x).unwrap()) < 1e-12);
        }
    }

    #[test]
    fn rational_knot_insertion_leaves_the_curve_unchanged(c in nurbs_curve(), s in 0.0f64..=1.0) {
        let mut r = c.clone();
        if r.insert_knot(at(c.knots(), s)).is_err() {
            return Ok(());
        }
        r.insert_midpoints().unwrap();
        for x in params(c.domain(), 40) {
            let (a, b) = (c.eval(x).unwrap(), r.eval(x).unwrap());
            prop_assert!(dist(&a, &b) < 1e-11, "{:?} vs {:?}", a, b);
            let (da, db) = (c.eval_derivs(x, 1).unwrap(), r.eval_derivs(x, 1).unwrap());
            let scale = 1.0 + da[1].iter().map(|v| v.abs()).sum::<f64>();
            prop_assert!(dist(&da[1], &db[1]) < 1e-9 * scale);
        }
    }
}

#[test]
fn insertion_of_a_full_multiplicity_knot_is_refused() {
    let mut c = BSplineCurve::clamped_uniform(3, vec![[0.0; 2]; 5]).unwrap();
    let before = c.clone();
    assert!(matches!(
        c.insert_knot(0.0),
        Err(NurbsError::KnotMultiplicity {
            multiplicity: 5,
            max: 4,
            ..
        })
    ));
    assert_eq!(c, before);
    assert!(matches!(
        c.insert_knot(1.5),
        Err(NurbsError::ParameterOutOfDomain { .. })
    ));
    // Up to multiplicity p + 1 in the interior: the curve gets a corner there.
    c.insert_knots(&[0.5, 0.5, 0.5]).unwrap();
    assert_eq!(c.knots().multiplicity(0.5), 4);
    assert!(c.insert_knot(0.5).is_err());
}

// ---------------------------------------------------------------------------------------
// 4. Exact rational geometry.

fn on_circle(p: &[f64; 3], c: &[f64; 3], r: f64) -> f64 {
    ((p[0] - c[0]).hypot(p[1] - c[1]) - r)
        .abs()
        .max((p[2] - c[2]).abs())
}

#[test]
fn the_nurbs_circle_is_exact_before_and_after_refinement() {
    let (c, r) = ([0.5, -1.25, 2.0], 1.75);
    let mut circle = NurbsCurve::circle(c, r).unwrap();
    let original = circle.clone();
    for step in 0..4 {
        for t in params(circle.domain(), 1000) {
            let p = circle.eval(t).unwrap();
            assert!(
                on_circle(&p, &c, r) < 1e-14 * r.max(1.0) * 2.0,
                "step {step} t {t}"
            );
            assert!(dist(&p, &original.eval(t).unwrap()) < 1e-14 * 4.0);
            // The tangent is perpendicular to the radius, for any parametrisation.
            let d = circle.eval_derivs(t, 1).unwrap();
            let dot = (p[0] - c[0]) * d[1][0] + (p[1] - c[1]) * d[1][1];
            assert!(dot.abs() < 1e-12 * (1.0 + d[1][0].abs() + d[1][1].abs()));
        }
        circle.insert_midpoints().unwrap();
        circle.insert_knot(0.3 + 0.01 * step as f64).unwrap();
    }
    // Full circle and the seam.
    assert!(dist(&circle.eval(0.0).unwrap(), &[c[0] + r, c[1], c[2]]) < 1e-15);
    assert!(dist(&circle.eval(0.5).unwrap(), &[c[0] - r, c[1], c[2]]) < 1e-14);
}

#[test]
fn nurbs_arcs_are_exact() {
    for (a, b) in [
        (0.0, 0.3),
        (1.0, 2.5),
        (-0.5, 3.0),
        (0.2, 4.5),
        (0.0, std::f64::consts::TAU),
    ] {
        let arc = NurbsCurve::arc([1.0, 2.0, 3.0], 2.0, a, b).unwrap();
        let start = arc.eval(0.0).unwrap();
        let end = arc.eval(1.0).unwrap();
        assert!(dist(&start, &[1.0 + 2.0 * a.cos(), 2.0 + 2.0 * a.sin(), 3.0]) < 1e-14);
        assert!(dist(&end, &[1.0 + 2.0 * b.cos(), 2.0 + 2.0 * b.sin(), 3.0]) < 1e-14);
        for t in params(arc.domain(), 200) {
            assert!(on_circle(&arc.eval(t).unwrap(), &[1.0, 2.0, 3.0], 2.0) < 1e-14 * 4.0);
        }
    }
    assert!(NurbsCurve::arc([0.0; 3], 1.0, 0.0, 7.0).is_err());
    assert!(NurbsCurve::arc([0.0; 3], -1.0, 0.0, 1.0).is_err());
}

/// Distance of `p` from the torus of the given radii around the `z` axis through `c`.
fn off_torus(p: &[f64; 3], c: &[f64; 3], big: f64, small: f64) -> f64 {
    let (x, y, z) = (p[0] - c[0], p[1] - c[1], p[2] - c[2]);
    ((x.hypot(y) - big).hypot(z) - small).abs()
}

#[test]
fn the_nurbs_cylinder_is_exact_before_and_after_refinement() {
    let (base, r, h) = ([1.0, 2.0, -1.0], 0.75, 3.0);
    let mut cyl = NurbsSurface::cylinder(base, r, h).unwrap();
    let original = cyl.clone();
    for _ in 0..3 {
        for u in params((0.0, 1.0), 40) {
            for v in params((0.0, 1.0), 7) {
                let p = cyl.eval(u, v).unwrap();
                assert!(((p[0] - base[0]).hypot(p[1] - base[1]) - r).abs() < 1e-14);
                assert!((p[2] - (base[2] + v * h)).abs() < 1e-14 * 8.0);
                assert!(dist(&p, &original.eval(u, v).unwrap()) < 1e-14 * 8.0);
            }
        }
        cyl.insert_midpoints().unwrap();
        cyl.insert_knots_u(&[0.123]).unwrap();
    }
}

#[test]
fn the_nurbs_torus_is_exact_before_and_after_refinement() {
    let (c, big, small) = ([0.5, -0.25, 1.0], 3.0, 1.25);
    let mut torus = NurbsSurface::torus(c, big, small).unwrap();
    let original = torus.clone();
    for step in 0..3 {
        for u in params((0.0, 1.0), 37) {
            for v in params((0.0, 1.0), 29) {
                let p = torus.eval(u, v).unwrap();
                assert!(off_torus(&p, &c, big, small) < 1e-14 * 4.0, "step {step}");
                assert!(dist(&p, &original.eval(u, v).unwrap()) < 1e-14 * 8.0);
                // Both tangents are perpendicular to the tube's radius.
                let d = torus.eval_second(u, v).unwrap();
                let rho = (p[0] - c[0]).hypot(p[1] - c[1]);
                let axis = [
                    c[0] + big * (p[0] - c[0]) / rho,
                    c[1] + big * (p[1] - c[1]) / rho,
                    c[2],
                ];
                let n: [f64; 3] = std::array::from_fn(|i| p[i] - axis[i]);
                for t in [d.du, d.dv] {
                    let dot: f64 = (0..3).map(|i| n[i] * t[i]).sum();
                    let len = t.iter().map(|x| x * x).sum::<f64>().sqrt();
                    assert!(dot.abs() < 1e-12 * (1.0 + len));
                }
            }
        }
        torus.insert_midpoints().unwrap();
        torus.insert_knots_v(&[0.01 * (step + 1) as f64]).unwrap();
    }
}

#[test]
fn rational_surface_derivatives_match_finite_differences() {
    let torus = NurbsSurface::torus([0.0; 3], 2.0, 0.7).unwrap();
    let h = 1e-5;
    for (u, v) in [(0.1, 0.2), (0.33, 0.61), (0.8, 0.9), (0.55, 0.05)] {
        let d = torus.eval_second(u, v).unwrap();
        let f = |a: f64, b: f64| torus.eval(a, b).unwrap();
        for i in 0..3 {
            let du = (f(u + h, v)[i] - f(u - h, v)[i]) / (2.0 * h);
            let dv = (f(u, v + h)[i] - f(u, v - h)[i]) / (2.0 * h);
            let duu = (f(u + h, v)[i] - 2.0 * d.p[i] + f(u - h, v)[i]) / (h * h);
            let dvv = (f(u, v + h)[i] - 2.0 * d.p[i] + f(u, v - h)[i]) / (h * h);
            let duv = (f(u + h, v + h)[i] - f(u + h, v - h)[i] - f(u - h, v + h)[i]
                + f(u - h, v - h)[i])
                / (4.0 * h * h);
            assert!((du - d.du[i]).abs() < 1e-6 * (1.0 + d.du[i].abs()));
            assert!((dv - d.dv[i]).abs() < 1e-6 * (1.0 + d.dv[i].abs()));
            assert!((duu - d.duu[i]).abs() < 1e-3 * (1.0 + d.duu[i].abs()));
            assert!((dvv - d.dvv[i]).abs() < 1e-3 * (1.0 + d.dvv[i].abs()));
            assert!((duv - d.duv[i]).abs() < 1e-3 * (1.0 + d.duv[i].abs()));
        }
    }
}

// ---------------------------------------------------------------------------------------
// 5. Convergence of the control polygon under midpoint insertion.

/// max |P_i − C(ξ_i)| over the control points, `ξ_i` the Greville abscissae.
fn polygon_error(c: &BSplineCurve<3>) -> f64 {
    let g = c.knots().greville();
    let (a, b) = c.domain();
    c.points()
        .iter()
        .zip(g)
        .map(|(p, x)| {
            let x = if c.is_closed() { x } else { x.clamp(a, b) };
            dist(p, &c.eval(x).unwrap())
        })
        .fold(0.0, f64::max)
}

#[test]
fn midpoint_insertion_converges_like_four_to_the_minus_k() {
    let pts = vec![
        [0.0, 0.0, 0.0],
        [1.0, 3.0, 0.5],
        [2.5, -1.0, 1.0],
        [4.0, 2.0, -1.0],
        [5.0, 0.0, 0.0],
        [6.5, 4.0, 2.0],
    ];
    let open = BSplineCurve::new(
        KnotVector::from_intervals(3, &[0.5, 1.5, 0.25], true).unwrap(),
        pts.clone(),
    )
    .unwrap();
    let closed = BSplineCurve::new(
        KnotVector::periodic_from_intervals(3, &[1.0, 0.3, 2.0, 0.7, 1.0, 0.5]).unwrap(),
        pts,
    )
    .unwrap();
    for mut c in [open, closed] {
        let mut errs = vec![polygon_error(&c)];
        for _ in 0..7 {
            c.insert_midpoints().unwrap();
            errs.push(polygon_error(&c));
        }
        // C = 4 · err_0 (err_k · 4^k increases towards about 2.6 · err_0 here).
        for (k, e) in errs.iter().enumerate() {
            assert!(*e <= 4.0 * errs[0] * 0.25f64.powi(k as i32), "{errs:?}");
        }
        // And not faster: the rate is really 4 (ratio between 3.5 and 4.5 asymptotically).
        let ratio = errs[6] / errs[7];
        assert!((3.5..4.5).contains(&ratio), "{errs:?}");
    }
}

#[test]
fn the_refined_torus_net_converges_to_the_torus() {
    let (big, small) = (2.0, 0.5);
    let mut torus = NurbsSurface::torus([0.0; 3], big, small).unwrap();
    let mut errs = vec![];
    for _ in 0..5 {
        torus.insert_midpoints().unwrap();
        let e = torus
            .points()
            .iter()
            .map(|p| off_torus(p, &[0.0; 3], big, small))
            .fold(0.0, f64::max);
        errs.push(e);
    }
    for k in 1..errs.len() {
        assert!(
            errs[k] <= 2.0 * errs[0] * 0.25f64.powi(k as i32),
            "{errs:?}"
        );
    }
    let ratio = errs[3] / errs[4];
    assert!((3.5..4.5).contains(&ratio), "{errs:?}");
    assert!(errs[4] < 1e-3, "{errs:?}");
}

// ---------------------------------------------------------------------------------------
// 6. Control mesh with knot intervals.

fn grid_surface(u: KnotVector, v: KnotVector) -> BSplineSurface<3> {
    let (nu, nv) = (u.num_points(), v.num_points());
    let mut pts = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let (x, y) = (i as f64, j as f64);
            pts.push([x, y, (0.7 * x).sin() * (1.3 * y).cos() + 0.1 * x * y]);
        }
    }
    BSplineSurface::new(u, v, pts).unwrap()
}

#[test]
fn uniform_knots_give_equal_intervals_and_clamped_ends_give_zero() {
    let s = grid_surface(
        KnotVector::uniform(3, 7).unwrap(),
        KnotVector::uniform(3, 5).unwrap(),
    );
    let m = s.control_mesh().unwrap();
    assert_eq!(m.mesh.num_vertices(), 35);
    assert_eq!(m.mesh.num_faces(), 6 * 4);
    assert_eq!(m.u_edges.len(), 6 * 5);
    assert_eq!(m.v_edges.len(), 7 * 4);
    assert!(m
        .u_edges
        .iter()
        .chain(&m.v_edges)
        .all(|e| e.interval == 1.0));

    let c = grid_surface(
        KnotVector::from_intervals(3, &[1.0, 2.0, 0.5], true).unwrap(),
        KnotVector::clamped_uniform(3, 4).unwrap(),
    );
    let m = c.control_mesh().unwrap();
    // u: 6 points, edges 0..5 carry d_2 … d_6 of [0,0,0,0,1,3,3.5,3.5,3.5,3.5]: 0, 1, 2, 0.5, 0.
    let per_i: Vec<f64> = (0..5).map(|i| m.u_edges[i * 4].interval).collect();
    assert_eq!(per_i, vec![0.0, 1.0, 2.0, 0.5, 0.0]);
    for e in &m.u_edges {
        assert_eq!(e.v1, e.v0 + 4); // P_{i,j} → P_{i+1,j}
    }
    let per_j: Vec<f64> = (0..3).map(|j| m.v_edges[j].interval).collect();
    assert_eq!(per_j, vec![0.0, 1.0, 0.0]);
}

#[test]
fn face_i_j_is_the_span_whose_control_points_surround_it() {
    let u = KnotVector::new(
        3,
        vec![0.0, 0.5, 1.5, 1.75, 3.0, 3.25, 4.5, 5.0, 6.5, 7.0, 8.0],
    )
    .unwrap(); // 7 points, non-uniform
    let v =
        KnotVector::from_intervals(3, &[0.3, 1.1, 0.6, 0.9, 1.4, 0.2, 0.8, 1.0], false).unwrap(); // 5 points
    let s = grid_surface(u.clone(), v.clone());
    let m = s.control_mesh().unwrap();
    let t = u.as_slice();
    let (nu, nv) = s.size();
    assert_eq!(m.face_params.len(), (nu - 1) * (nv - 1));
    for (idx, e) in m.u_edges.iter().enumerate() {
        let i = idx / nv;
        assert_eq!(e.interval, t[i + 3] - t[i + 2]);
    }
    // An interior face: its rectangle is a span of the domain, and the surface there depends
    // on P_{i-1..=i+2, j-1..=j+2} and on nothing else.
    let (i, j) = (2, 1);
    let f = i * (nv - 1) + j;
    let [u0, u1, v0, v1] = m.face_params[f];
    assert_eq!([u0, u1], [t[i + 2], t[i + 3]]);
    assert_eq!(
        m.mesh.face(f),
        &[
            (i * nv + j) as u32,
            ((i + 1) * nv + j) as u32,
            ((i + 1) * nv + j + 1) as u32,
            (i * nv + j + 1) as u32
        ]
    );
    let um = 0.5 * (u0 + u1);
    let vm = 0.5 * (v0 + v1);
    let base = s.eval(um, vm).unwrap();
    for a in 0..nu {
        for b in 0..nv {
            let mut pts = s.points().to_vec();
            pts[a * nv + b][2] += 1.0;
            let moved = BSplineSurface::new(u.clone(), v.clone(), pts).unwrap();
            let changed = dist(&moved.eval(um, vm).unwrap(), &base) > 0.0;
            let inside = (i - 1..=i + 2).contains(&a) && (j.saturating_sub(1)..=j + 2).contains(&b);
            assert_eq!(changed, inside, "P_{a},{b}");
        }
    }
}

#[test]
fn a_uniform_periodic_bicubic_is_the_catmull_clark_limit_of_its_control_mesh() {
    let (nu, nv) = (6, 5);
    let u = KnotVector::periodic_uniform(3, nu).unwrap();
    let v = KnotVector::periodic_uniform(3, nv).unwrap();
    // A bumpy torus.
    let mut pts = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let a = std::f64::consts::TAU * i as f64 / nu as f64;
            let b = std::f64::consts::TAU * j as f64 / nv as f64;
            let rho = 3.0 + (1.0 + 0.2 * ((i * j) % 3) as f64) * b.cos();
            pts.push([rho * a.cos(), rho * a.sin(), b.sin() + 0.1 * i as f64]);
        }
    }
    let s = BSplineSurface::new(u, v, pts).unwrap();
    let m = s.control_mesh().unwrap();
    assert_eq!(m.mesh.num_faces(), nu * nv);
    assert!(m
        .u_edges
        .iter()
        .chain(&m.v_edges)
        .all(|e| e.interval == 1.0));
    let limit = LimitSurface::new(&m.mesh, Options::default()).unwrap();
    for (f, r) in m.face_params.iter().enumerate() {
        for (a, b) in [(0.0, 0.0), (0.25, 0.5), (0.9, 0.1), (1.0, 1.0)] {
            let d = limit.eval(f as u32, a, b).unwrap();
            let e = s
                .eval_second(r[0] + a * (r[1] - r[0]), r[2] + b * (r[3] - r[2]))
                .unwrap();
            assert!(dist(&d.p, &e.p) < 1e-12, "face {f} ({a}, {b})");
            assert!(dist(&d.du, &e.du) < 1e-11 && dist(&d.dv, &e.dv) < 1e-11);
        }
    }
}

#[test]
fn a_control_mesh_needs_a_bicubic() {
    let k = KnotVector::uniform(2, 4).unwrap();
    let s = grid_surface(k.clone(), k);
    assert!(matches!(
        s.control_mesh(),
        Err(NurbsError::BadDegree { degree: 2, .. })
    ));
}

// ---------------------------------------------------------------------------------------
// 7. JSON.

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn json_round_trips_are_exact(c in curve(), r in nurbs_curve()) {
        for g in [Curve::BSpline(c), Curve::Nurbs(r)] {
            let text = g.to_json_string();
            let back = Curve::from_json_str(&text).unwrap();
            prop_assert_eq!(&back, &g);
            prop_assert_eq!(back.to_json_string(), text.clone());
            // An independent parser reads the same document, number for number.
            let doc = g.to_json();
            let v: serde_json::Value = serde_json::from_str(&text).unwrap();
            let numbers = |v: &serde_json::Value| -> Vec<f64> {
                let mut out = Vec::new();
                let mut stack = vec![v];
                while let Some(v) = stack.pop() {
                    match v {
                        serde_json::Value::Array(items) => stack.extend(items.iter().rev()),
                        other => out.push(other.as_f64().unwrap()),
                    }
                }
                out
            };
            prop_assert_eq!(v["type"].as_str(), Some(doc.kind.as_str()));
            prop_assert_eq!(v["degree"].as_u64(), Some(doc.degree as u64));
            prop_assert_eq!(numbers(&v["knots"]), doc.knots.clone());
            prop_assert_eq!(numbers(&v["points"]), doc.points.concat());
            prop_assert_eq!(v.get("weights").map(numbers), doc.weights.clone());
            prop_assert_eq!(v["closed"].as_bool(), Some(doc.closed));
            prop_assert_eq!(v.as_object().unwrap().len(), 5 + usize::from(doc.weights.is_some()));
        }
    }

    #[test]
    fn surface_json_round_trips_are_exact(
        u in knot_vector(), v in knot_vector(),
        pts in prop::collection::vec(point3(), 400),
        w in prop::collection::vec(0.1f64..10.0, 400),
    ) {
        let n = u.num_points() * v.num_points();
        let s = BSplineSurface::new(u.clone(), v.clone(), pts[..n].to_vec()).unwrap();
        let r = NurbsSurface::new(u, v, pts[..n].to_vec(), w[..n].to_vec()).unwrap();
        for g in [Surface::BSpline(s), Surface::Nurbs(r)] {
            let text = g.to_json_string();
            prop_assert_eq!(Surface::from_json_str(&text).unwrap(), g.clone());
            prop_assert_eq!(from_json_str(&text).unwrap(), Geometry::Surface(g));
        }
    }
}

#[test]
fn json_documents_read_as_documented() {
    let text = r#"{
        "type": "bspline-curve",
        "degree": 2,
        "knots": [0, 1, 2, 3],
        "points": [[1, 0, 0], [0, 1, 0], [-1, 0, 0]],
        "weights": [1, 0.5, 1],
        "closed": true
    }"#;
    let Curve::Nurbs(c) = Curve::from_json_str(text).unwrap() else {
        panic!("weights make a NURBS curve")
    };
    assert!(c.is_closed());
    assert_eq!(c.domain(), (0.0, 3.0));
    assert_eq!(c.weights(), vec![1.0, 0.5, 1.0]);
    let s = r#"{"type": "bspline-surface", "degree_u": 1, "degree_v": 1,
        "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
        "points": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]}"#;
    let Surface::BSpline(s) = Surface::from_json_str(s).unwrap() else {
        panic!("no weights: polynomial")
    };
    assert_eq!(s.point(1, 0), Some(&[1.0, 0.0, 0.0]));
    assert_eq!(s.eval(1.0, 1.0).unwrap(), [1.0, 1.0, 1.0]);
}

#[test]
fn malformed_json_names_the_field() {
    let good = r#"{"type":"bspline-curve","degree":2,"knots":[0,0,0,1,1,1],"points":[[0,0,0],[1,1,0],[2,0,0]],"weights":[1,2,1]}"#;
    assert!(Curve::from_json_str(good).is_ok());
    let cases = [
        (r#""degree":2"#, r#""degree":"2""#, "degree"),
        (r#""degree":2"#, r#""degree":0"#, "degree"),
        (r#""degree":2"#, r#""degree":2.5"#, "degree"),
        (
            r#""knots":[0,0,0,1,1,1]"#,
            r#""knots":[0,0,0,1,1]"#,
            "knots",
        ),
        (
            r#""knots":[0,0,0,1,1,1]"#,
            r#""knots":[0,0,0,1,0.5,1]"#,
            "knots[4]",
        ),
        (
            r#""knots":[0,0,0,1,1,1]"#,
            r#""knots":[0,0,0,1,"x",1]"#,
            "knots[4]",
        ),
        (
            r#""knots":[0,0,0,1,1,1]"#,
            r#""knots":[0,0,0,0,1,1]"#,
            "knots",
        ),
        (
            r#""knots":[0,0,0,1,1,1]"#,
            r#""knots":[0,0,0,1e999,1e999,1e999]"#,
            "knots[3]",
        ),
        (r#"[1,1,0]"#, r#"[1,1]"#, "points[1]"),
        (r#"[1,1,0]"#, r#"[1,null,0]"#, "points[1][1]"),
        (
            r#""weights":[1,2,1]"#,
            r#""weights":[1,-2,1]"#,
            "weights[1]",
        ),
        (r#""weights":[1,2,1]"#, r#""weights":[1,2]"#, "weights"),
        (r#""type":"bspline-curve""#, r#""type":"bspline""#, "type"),
        (r#""type":"bspline-curve","#, "", "type"),
        (
            r#","weights":[1,2,1]"#,
            r#","weights":[1,2,1],"wieghts":1"#,
            "wieghts",
        ),
        (
            r#","weights":[1,2,1]"#,
            r#","weights":[1,2,1],"closed":"yes""#,
            "closed",
        ),
        (
            r#","weights":[1,2,1]"#,
            r#","weights":[1,2,1],"degree":3"#,
            "degree",
        ),
        (r#""degree":2"#, r#""degree":65"#, "degree"),
        (
            r#""degree":2"#,
            r#""degree":18446744073709551616"#,
            "degree",
        ),
        (r#""degree":2"#, r#""degree":1e30"#, "degree"),
    ];
    for (from, to, field) in cases {
        assert!(good.contains(from), "{from}");
        let bad = good.replacen(from, to, 1);
        match Curve::from_json_str(&bad) {
            Err(NurbsError::Json { field: f, message }) => {
                assert_eq!(f, field, "{bad}: {message}")
            }
            other => panic!("{bad}: {other:?}"),
        }
    }
    let surface = r#"{"type":"bspline-surface","degree_u":1,"degree_v":1,"knots_u":[0,0,1,1],"knots_v":[0,0,1,1],"points":[[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]],"weights":[[1,1],[1,2]]}"#;
    assert!(Surface::from_json_str(surface).is_ok());
    for (from, to, field) in [
        ("[[1,0,0],[1,1,1]]", "[[1,0,0]]", "points[1]"),
        (
            "[[1,0,0],[1,1,1]]",
            "[[1,0,0],[1,1,1e400]]",
            "points[1][1][2]",
        ),
        ("[[1,1],[1,2]]", "[[1,1],[1,0]]", "weights[1][1]"),
        ("[[1,1],[1,2]]", "[[1,1],[1]]", "weights[1]"),
        (
            r#""knots_v":[0,0,1,1]"#,
            r#""knots_v":[0,0,0.5,1,1]"#,
            "points",
        ),
        (
            r#""knots_v":[0,0,1,1]"#,
            r#""knots_v":[0,0,1,1,1]"#,
            "knots_v",
        ),
        (
            r#""knots_u":[0,0,1,1]"#,
            r#""knots_u":[1,0,1,1]"#,
            "knots_u[1]",
        ),
        (r#""degree_v":1"#, r#""degree_v":0"#, "degree_v"),
    ] {
        assert!(surface.contains(from), "{from}");
        let bad = surface.replacen(from, to, 1);
        match Surface::from_json_str(&bad) {
            Err(NurbsError::Json { field: f, message }) => {
                assert_eq!(f, field, "{bad}: {message}")
            }
            other => panic!("{bad}: {other:?}"),
        }
    }
    // Syntax errors give the line and column.
    match Curve::from_json_str("{\"type\":\n  \"bspline-curve\",,}") {
        Err(NurbsError::JsonSyntax { line, column, .. }) => assert_eq!((line, column), (2, 19)),
        other => panic!("{other:?}"),
    }
    // Field errors in text carry the line too.
    let err = Curve::from_json_str(&good.replace(r#""degree":2"#, "\n\"degree\":-1"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("`degree`") && err.contains("line 2"), "{err}");
}

// ---------------------------------------------------------------------------------------
// 8. Knot vectors and bad input.

proptest! {
    #[test]
    fn knot_intervals_round_trip(k in knot_vector()) {
        let d = k.intervals();
        let again = if k.is_periodic() {
            KnotVector::periodic_from_intervals(k.degree(), &d).unwrap()
        } else {
            KnotVector::from_intervals(k.degree(), &d, false).unwrap()
        };
        let first = k.period_knots().unwrap_or(k.as_slice())[0];
        let (a, b) = (again.as_slice(), k.as_slice());
        for (x, y) in a.iter().zip(b) {
            prop_assert!((x + first - y).abs() < 1e-12);
        }
        // Normalised: domain [0, 1], same shape.
        let nk = k.normalized();
        prop_assert_eq!(nk.domain(), (0.0, 1.0));
        prop_assert_eq!(nk.num_knots(), k.num_knots());
    }
}

#[test]
fn knot_vectors_and_curves_reject_bad_input_with_typed_errors() {
    use NurbsError as E;
    assert!(matches!(
        KnotVector::new(0, vec![0.0, 1.0]),
        Err(E::BadDegree { .. })
    ));
    assert!(matches!(
        KnotVector::new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0]),
        Err(E::TooFewKnots { min: 6, .. })
    ));
    assert!(matches!(
        KnotVector::new(1, vec![0.0, 1.0, 0.5, 2.0]),
        Err(E::DecreasingKnots { index: 2, .. })
    ));
    assert!(matches!(
        KnotVector::new(1, vec![0.0, f64::NAN, 1.0, 2.0]),
        Err(E::NonFiniteKnot { index: 1, .. })
    ));
    assert!(matches!(
        KnotVector::new(1, vec![0.0, 1.0, 1.0, 1.0, 2.0]),
        Err(E::KnotMultiplicity {
            multiplicity: 3,
            max: 2,
            ..
        })
    ));
    assert!(matches!(
        KnotVector::new(1, vec![0.0, 1.0, 1.0, 2.0]),
        Err(E::EmptyDomain { .. })
    ));
    assert!(KnotVector::new(1, vec![0.0, 1.0, 1.0, 2.0, 3.0]).is_ok());
    assert!(matches!(
        KnotVector::new(2, vec![0.0, 1.0, 1.0, 1.0, 1.0, 2.0]),
        Err(E::KnotMultiplicity { .. })
    ));
    assert!(matches!(
        KnotVector::new(1, vec![0.0, 1.0, 1.0, 2.0, 3.0]).map(|k| k.span(2.5)),
        Ok(Err(E::ParameterOutOfDomain { .. }))
    ));
    assert!(matches!(
        KnotVector::periodic(3, &[0.0, 1.0, 2.0]),
        Err(E::TooFewKnots { .. })
    ));
    assert!(matches!(
        KnotVector::periodic(2, &[1.0, 1.0, 1.0, 1.0]),
        Err(E::EmptyDomain { .. })
    ));
    // Seam multiplicity: u_0 = u_1 and u_{n-1} = u_n glue to multiplicity 3 at the seam.
    let k = KnotVector::periodic(2, &[0.0, 0.0, 1.0, 2.0, 2.0]).unwrap();
    assert_eq!(k.multiplicity(0.0), 3);
    assert_eq!(k.multiplicity(2.0), 3);
    assert!(matches!(
        KnotVector::periodic(1, &[0.0, 0.0, 1.0, 2.0, 2.0]),
        Err(E::KnotMultiplicity {
            multiplicity: 3,
            ..
        })
    ));

    let k = KnotVector::clamped_uniform(2, 4).unwrap();
    assert!(matches!(
        BSplineCurve::new(k.clone(), vec![[0.0; 3]; 5]),
        Err(E::KnotCountMismatch {
            knots: 7,
            points: 5,
            expected: 8,
            ..
        })
    ));
    assert!(matches!(
        BSplineCurve::new(k.clone(), vec![[0.0, 0.0, f64::INFINITY]; 4]),
        Err(E::NonFinitePoint { index: 0 })
    ));
    assert!(matches!(
        BSplineCurve::<3>::bezier(vec![]),
        Err(E::TooFewPoints { .. })
    ));
    assert!(matches!(
        NurbsCurve::new(k.clone(), vec![[0.0; 3]; 4], vec![1.0, 0.0, 1.0, 1.0]),
        Err(E::NonPositiveWeight { index: 1, .. })
    ));
    assert!(matches!(
        NurbsCurve::new(k.clone(), vec![[0.0; 3]; 4], vec![1.0; 3]),
        Err(E::WeightCountMismatch { .. })
    ));
    let c = BSplineCurve::new(k.clone(), vec![[0.0; 3]; 4]).unwrap();
    assert!(matches!(c.eval(1.5), Err(E::ParameterOutOfDomain { .. })));
    assert!(matches!(
        c.eval(f64::NAN),
        Err(E::ParameterOutOfDomain { .. })
    ));
    assert!(matches!(
        BSplineSurface::new(k.clone(), k, vec![[0.0; 3]; 15]),
        Err(E::NetSizeMismatch {
            rows: 4,
            columns: 4,
            ..
        })
    ));
    assert!(matches!(
        NurbsSurface::torus([0.0; 3], 1.0, f64::NAN),
        Err(E::InvalidArgument { .. })
    ));
}
