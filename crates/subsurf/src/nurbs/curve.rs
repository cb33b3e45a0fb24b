//! [`BSplineCurve`]: B-spline curves of any degree and dimension, open or closed.
//!
//! `C(t) = Σ_i N_{i,p}(t) P_i` (The NURBS Book eq. 3.1), evaluated by de Boor's algorithm,
//! differentiated with the basis derivatives (A3.2), refined by knot insertion (Boehm, A5.1,
//! A5.4). A closed curve has a periodic [`KnotVector`] and its control points wrap around
//! (see the [`knots`](super::knots) module for the convention).

use super::basis::ders_basis;
use super::insert::refine;
use super::vecn::{axpy, is_finite, lerp, with_scratch};
use super::{KnotVector, NurbsError};
use crate::mesh::MAX_COORDINATE;

/// A B-spline curve of degree `p ≥ 1` in `D` dimensions: knots and control points.
///
/// For an open knot vector there are `N = knots − p − 1` control points; for a periodic one
/// there are `n` distinct control points, used cyclically (`P_{i+n} = P_i`).
///
/// ```
/// use subsurf::nurbs::{BSplineCurve, KnotVector};
/// // A clamped cubic: interpolates its end points.
/// let k = KnotVector::new(3, vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0])?;
/// let c = BSplineCurve::new(k, vec![[0.0, 0.0], [1.0, 2.0], [2.0, 2.0], [3.0, 1.0], [4.0, 0.0]])?;
/// assert_eq!(c.eval(0.0)?, [0.0, 0.0]);
/// assert_eq!(c.eval(1.0)?, [4.0, 0.0]);
/// // Knot insertion does not change the curve.
/// let mut r = c.clone();
/// r.insert_knot(0.3)?;
/// assert_eq!(r.points().len(), 6);
/// let (a, b) = (c.eval(0.7)?, r.eval(0.7)?);
/// assert!((a[0] - b[0]).abs() < 1e-15 && (a[1] - b[1]).abs() < 1e-15);
/// # Ok::<(), subsurf::nurbs::NurbsError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct BSplineCurve<const D: usize> {
    knots: KnotVector,
    points: Vec<[f64; D]>,
}

impl<const D: usize> BSplineCurve<D> {
    /// A curve from its knots and its (distinct) control points.
    ///
    /// # Errors
    /// [`NurbsError::KnotCountMismatch`] unless `points.len()` is
    /// [`knots.num_points()`](KnotVector::num_points) (`knots − p − 1` for an open knot
    /// vector, `period knots − 1` for a periodic one); [`NurbsError::NonFinitePoint`];
    /// [`NurbsError::LargeCoordinate`] for a coordinate beyond 1e75 in magnitude.
    pub fn new(knots: KnotVector, points: Vec<[f64; D]>) -> Result<Self, NurbsError> {
        check_points(&knots, &points)?;
        Ok(Self { knots, points })
    }

    /// The clamped curve on `[0, 1]` with uniformly spaced interior knots
    /// ([`KnotVector::clamped_uniform`]).
    ///
    /// # Errors
    /// [`NurbsError::TooFewPoints`] when there are not more points than the degree, and the
    /// errors of [`new`](Self::new).
    pub fn clamped_uniform(degree: usize, points: Vec<[f64; D]>) -> Result<Self, NurbsError> {
        Self::new(KnotVector::clamped_uniform(degree, points.len())?, points)
    }

    /// The closed uniform curve (periodic knots `u_i = i`, domain `[0, n]`).
    ///
    /// # Errors
    /// [`NurbsError::TooFewKnots`] when there are fewer than `max(p, 2)` points, and the
    /// errors of [`new`](Self::new).
    pub fn closed_uniform(degree: usize, points: Vec<[f64; D]>) -> Result<Self, NurbsError> {
        Self::new(KnotVector::periodic_uniform(degree, points.len())?, points)
    }

    /// The Bézier curve of degree `points.len() − 1` on `[0, 1]` (clamped, no interior knot):
    /// `C(t) = Σ_i B_{i,p}(t) P_i` with the Bernstein polynomials
    /// `B_{i,p}(t) = C(p, i) tⁱ (1 − t)^{p−i}` (The NURBS Book §1.3 and §2.2).
    ///
    /// # Errors
    /// [`NurbsError::TooFewPoints`] for fewer than two points; [`NurbsError::BadDegree`]
    /// for more than [`MAX_DEGREE`](super::MAX_DEGREE)` + 1`; [`NurbsError::NonFinitePoint`].
    pub fn bezier(points: Vec<[f64; D]>) -> Result<Self, NurbsError> {
        if points.len() < 2 {
            return Err(NurbsError::TooFewPoints {
                count: points.len(),
                degree: 1,
                min: 2,
            });
        }
        let p = points.len() - 1;
        let mut k = vec![0.0; p + 1];
        k.extend(std::iter::repeat_n(1.0, p + 1));
        Self::new(KnotVector::new(p, k)?, points)
    }

    /// The degree `p`.
    pub fn degree(&self) -> usize {
        self.knots.degree()
    }

    /// The knot vector.
    pub fn knots(&self) -> &KnotVector {
        &self.knots
    }

    /// The distinct control points.
    pub fn points(&self) -> &[[f64; D]] {
        &self.points
    }

    /// Whether the curve is closed (periodic knots, wrapped control points).
    pub fn is_closed(&self) -> bool {
        self.knots.is_periodic()
    }

    /// The parameter domain `[t_p, t_N]` (one period for a closed curve).
    pub fn domain(&self) -> (f64, f64) {
        self.knots.domain()
    }

    /// The position `C(t)` by de Boor's algorithm (de Boor, "On calculating with B-splines",
    /// J. Approx. Theory 6, 1972; The NURBS Book §5.2, repeated knot insertion):
    /// with `k` the span of `t`, start from `d_j = P_{k−p+j}` and for `r = 1 … p` replace
    /// `d_j ← (1 − α) d_{j−1} + α d_j`, `α = (t − t_i) / (t_{i+p+1−r} − t_i)`,
    /// `i = k − p + j`, for `j = p … r`; then `C(t) = d_p`. Every step is a convex combination,
    /// so the result is as accurate as the control points.
    ///
    /// # Errors
    /// [`NurbsError::ParameterOutOfDomain`] for an open curve and `t` outside
    /// [`domain`](Self::domain) (a closed curve wraps `t`), or `t` not finite.
    pub fn eval(&self, t: f64) -> Result<[f64; D], NurbsError> {
        let t = self.knots.parameter(t)?;
        Ok(self.eval_in_domain(t))
    }

    /// [`eval`](Self::eval) for `t` in the domain.
    pub(crate) fn eval_in_domain(&self, t: f64) -> [f64; D] {
        let p = self.degree();
        let k = self.knots.span_in_domain(t);
        let u = self.knots.as_slice();
        with_scratch(p + 1, [0.0; D], |d| {
            for (j, dj) in d.iter_mut().enumerate() {
                *dj = self.point(k - p + j);
            }
            for r in 1..=p {
                for j in (r..=p).rev() {
                    let i = k - p + j;
                    let a = (t - u[i]) / (u[i + p + 1 - r] - u[i]);
                    d[j] = lerp(&d[j - 1], &d[j], a);
                }
            }
            d[p]
        })
    }

    /// The position and derivatives `[C(t), C'(t), …, C^{(order)}(t)]`:
    /// `C^{(j)}(t) = Σ_r N^{(j)}_{k−p+r,p}(t) P_{k−p+r}` (The NURBS Book A3.2 with the basis
    /// derivatives of A2.3); derivatives above the degree are zero. At a knot the derivatives
    /// are those of the span that starts there (right derivatives), except at the end of an
    /// open domain (left derivatives).
    ///
    /// # Errors
    /// As [`eval`](Self::eval).
    pub fn eval_derivs(&self, t: f64, order: usize) -> Result<Vec<[f64; D]>, NurbsError> {
        let t = self.knots.parameter(t)?;
        let p = self.degree();
        let k = self.knots.span_in_domain(t);
        let ders = ders_basis(self.knots.as_slice(), p, k, t, order);
        let mut out = vec![[0.0; D]; order + 1];
        for (j, o) in out.iter_mut().enumerate().take(order.min(p) + 1) {
            for r in 0..=p {
                axpy(o, ders[j * (p + 1) + r], &self.point(k - p + r));
            }
        }
        Ok(out)
    }

    /// Inserts the knot `t` once (Boehm's algorithm, The NURBS Book A5.1; see the
    /// [formula](super#knot-insertion)): one more control point, the same curve.
    /// On a closed curve `t` is wrapped into the period and inserted periodically.
    ///
    /// # Errors
    /// [`NurbsError::ParameterOutOfDomain`], or [`NurbsError::KnotMultiplicity`] when `t`
    /// already has multiplicity `p + 1`; the curve is then unchanged.
    pub fn insert_knot(&mut self, t: f64) -> Result<(), NurbsError> {
        self.insert_knots(&[t])
    }

    /// Inserts all the knots `ts` (any order, repetitions allowed) in one pass (knot
    /// refinement, The NURBS Book A5.4). The curve is unchanged.
    ///
    /// # Errors
    /// As [`insert_knot`](Self::insert_knot); on error the curve is unchanged.
    pub fn insert_knots(&mut self, ts: &[f64]) -> Result<(), NurbsError> {
        let (knots, mut rows) = refine(&self.knots, ts, vec![self.points.clone()])?;
        if let Some(points) = rows.pop() {
            self.knots = knots;
            self.points = points;
        }
        Ok(())
    }

    /// Inserts the midpoint of every non-zero knot interval of the domain (of the period),
    /// [`KnotVector::midpoints`]: the knots one step of non-uniform subdivision (NURSS)
    /// inserts; every interval is halved. After `s` steps the control polygon is within
    /// `O(4^{−s})` of the curve (at the Greville abscissae).
    ///
    /// # Errors
    /// None in practice (midpoints of non-empty intervals are new knots); kept for the
    /// signature of [`insert_knots`](Self::insert_knots).
    pub fn insert_midpoints(&mut self) -> Result<(), NurbsError> {
        let m = self.knots.midpoints();
        self.insert_knots(&m)
    }

    /// The closed (periodic) curve that this open one is the unwrapped form of, if it is:
    /// its knot vector's [`KnotVector::periodic_form`] and its first `p` control points
    /// coinciding with its last `p` (`P_i` and `P_{i+n}`, each coordinate within 2⁻³² or
    /// 2⁻⁴² of the sum of their magnitudes: openNURBS's `ON_NurbsCurve::IsPeriodic` and
    /// `ON_PointsAreCoincident`). The result keeps `P_0 … P_{n−1}`: the same curve, now
    /// closed (CAD tools write closed curves to OBJ free-form this way).
    pub fn periodic_form(&self) -> Option<Self> {
        let k = self.knots.periodic_form()?;
        let n = k.num_points();
        let p = k.degree();
        (0..p)
            .all(|i| coincident(&self.points[i], &self.points[i + n]))
            .then(|| Self {
                knots: k,
                points: self.points[..n].to_vec(),
            })
    }

    /// Control point `a` of the unwrapped sequence (`a mod n` for a closed curve).
    #[inline]
    pub(crate) fn point(&self, a: usize) -> [f64; D] {
        let n = self.points.len();
        self.points[if a >= n { a - n } else { a }]
    }
}

/// Number of points matches the knots, all finite.
pub(crate) fn check_points<const D: usize>(
    knots: &KnotVector,
    points: &[[f64; D]],
) -> Result<(), NurbsError> {
    let expected_points = knots.num_points();
    if points.len() != expected_points {
        let (given, expected) = match knots.period_knots() {
            Some(u) => (u.len(), points.len() + 1),
            None => (knots.num_knots(), points.len() + knots.degree() + 1),
        };
        return Err(NurbsError::KnotCountMismatch {
            knots: given,
            points: points.len(),
            degree: knots.degree(),
            expected,
        });
    }
    if let Some(index) = points.iter().position(|p| !is_finite(p)) {
        return Err(NurbsError::NonFinitePoint { index });
    }
    check_magnitude(points)
}

/// Every coordinate of Cartesian points (`D ≤ 3`) at most [`MAX_COORDINATE`] in magnitude,
/// the bound every mesh is held to (refinement and evaluation multiply coordinates; see
/// [`crate::mesh::MAX_COORDINATE`]). Homogeneous points (`D = 4`) are not checked here: the
/// rational types check their Cartesian points.
pub(crate) fn check_magnitude<const D: usize>(points: &[[f64; D]]) -> Result<(), NurbsError> {
    if D > 3 {
        return Ok(());
    }
    for (index, p) in points.iter().enumerate() {
        if let Some(&value) = p.iter().find(|c| c.abs() > MAX_COORDINATE) {
            return Err(NurbsError::LargeCoordinate { index, value });
        }
    }
    Ok(())
}

/// Whether two points coincide in openNURBS's sense (`ON_PointsAreCoincident`): each
/// coordinate pair within `ON_ZERO_TOLERANCE = 2⁻³²`, or within `ON_RELATIVE_TOLERANCE =
/// 2⁻⁴²` times the sum of their magnitudes.
pub(crate) fn coincident<const D: usize>(a: &[f64; D], b: &[f64; D]) -> bool {
    const ZERO_TOLERANCE: f64 = 2.328_306_436_538_696_3e-10;
    const RELATIVE_TOLERANCE: f64 = 2.273_736_754_432_320_6e-13;
    a.iter().zip(b).all(|(&x, &y)| {
        let d = (x - y).abs();
        d <= ZERO_TOLERANCE || d <= (x.abs() + y.abs()) * RELATIVE_TOLERANCE
    })
}
