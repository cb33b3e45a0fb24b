//! [`NurbsCurve`]: rational B-spline curves in 3D, as B-splines in homogeneous coordinates.
//!
//! `C(t) = Σ_i N_{i,p}(t) w_i P_i / Σ_i N_{i,p}(t) w_i` (The NURBS Book eq. 4.1) is the
//! perspective image of the polynomial B-spline `C^w(t) = Σ_i N_{i,p}(t) (w_i P_i, w_i)` in
//! 4D (eq. 4.5). Everything linear — evaluation, knot insertion, refinement — is done on
//! `C^w` with the same code as polynomial curves, which is why refinement is exact for
//! rational curves too; positions are projected at the end, and derivatives follow from the
//! quotient rule `C^{(k)} = (A^{(k)} − Σ_{i=1}^{k} C(k, i) w^{(i)} C^{(k−i)}) / w` with
//! `C^w = (A, w)` (eq. 4.8, A4.2).

use super::curve::BSplineCurve;
use super::{KnotVector, NurbsError};
use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2, PI};

/// The control points `(x, y)` and weights of the unit circle as a clamped quadratic NURBS
/// with nine control points on the square `[−1, 1]²` (The NURBS Book §7.5, Fig. 7.16a):
/// corners have weight `cos 45° = √2/2`.
pub(crate) const UNIT_CIRCLE: [(f64, f64, f64); 9] = [
    (1.0, 0.0, 1.0),
    (1.0, 1.0, FRAC_1_SQRT_2),
    (0.0, 1.0, 1.0),
    (-1.0, 1.0, FRAC_1_SQRT_2),
    (-1.0, 0.0, 1.0),
    (-1.0, -1.0, FRAC_1_SQRT_2),
    (0.0, -1.0, 1.0),
    (1.0, -1.0, FRAC_1_SQRT_2),
    (1.0, 0.0, 1.0),
];

/// The knots of [`UNIT_CIRCLE`]: `0, 0, 0, ¼, ¼, ½, ½, ¾, ¾, 1, 1, 1`.
pub(crate) const UNIT_CIRCLE_KNOTS: [f64; 12] = [
    0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
];

/// A rational B-spline (NURBS) curve in 3D with positive weights, stored as the B-spline
/// `C^w` with homogeneous control points `(w x, w y, w z, w)`, together with the Cartesian
/// points `(x, y, z)` exactly as given (so that they read back bit for bit; after knot
/// insertion they are the projected new points, and `C^w` is recomputed from them).
///
/// ```
/// use subsurf::nurbs::NurbsCurve;
/// let c = NurbsCurve::circle([1.0, 2.0, 0.0], 3.0)?;
/// for i in 0..=100 {
///     let p = c.eval(i as f64 / 100.0)?;
///     let r = ((p[0] - 1.0).powi(2) + (p[1] - 2.0).powi(2)).sqrt();
///     assert!((r - 3.0).abs() < 1e-14);
/// }
/// # Ok::<(), subsurf::nurbs::NurbsError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct NurbsCurve {
    homogeneous: BSplineCurve<4>,
    points: Vec<[f64; 3]>,
}

impl NurbsCurve {
    /// A NURBS curve from knots, control points and weights (`P_i`, `w_i`).
    ///
    /// # Errors
    /// [`NurbsError::WeightCountMismatch`], [`NurbsError::NonPositiveWeight`], and the errors
    /// of [`BSplineCurve::new`].
    pub fn new(
        knots: KnotVector,
        points: Vec<[f64; 3]>,
        weights: Vec<f64>,
    ) -> Result<Self, NurbsError> {
        super::curve::check_magnitude(&points)?;
        let hw = homogenize(&points, &weights)?;
        Ok(Self {
            homogeneous: BSplineCurve::new(knots, hw)?,
            points,
        })
    }

    /// A NURBS curve from its homogeneous B-spline `C^w` (control points `(w P, w)`); the
    /// Cartesian points are their projections `P = (w P) / w`.
    ///
    /// # Errors
    /// [`NurbsError::NonPositiveWeight`] unless every `w > 0`.
    pub fn from_homogeneous(curve: BSplineCurve<4>) -> Result<Self, NurbsError> {
        check_weights(curve.points().iter().map(|p| p[3]))?;
        let points = curve.points().iter().map(project).collect();
        let weights: Vec<f64> = curve.points().iter().map(|p| p[3]).collect();
        Self::new(curve.knots().clone(), points, weights)
    }

    /// The closed curve that this open one is the unwrapped form of, if it is: as
    /// [`BSplineCurve::periodic_form`] on the homogeneous points (so the weights of the
    /// repeated control points coincide too).
    pub fn periodic_form(&self) -> Option<Self> {
        let h = self.homogeneous.periodic_form()?;
        let n = h.points().len();
        let coincide =
            (0..h.degree()).all(|i| super::curve::coincident(&self.points[i], &self.points[i + n]));
        coincide.then(|| Self {
            homogeneous: h,
            points: self.points[..n].to_vec(),
        })
    }

    /// The full circle of the given centre and radius in the plane `z = centre.z`, starting
    /// at `centre + (r, 0, 0)` and running counter-clockwise for `t ∈ [0, 1]`: the nine-point
    /// quadratic NURBS of The NURBS Book §7.5 (four 90° arcs, corner weights `√2/2`, knots
    /// `0, 0, 0, ¼, ¼, ½, ½, ¾, ¾, 1, 1, 1`). Points on it are exactly on the circle up to
    /// rounding; it is not uniformly parametrised.
    ///
    /// # Errors
    /// [`NurbsError::InvalidArgument`] unless the radius is positive and finite;
    /// [`NurbsError::NonFinitePoint`] for a non-finite centre.
    pub fn circle(center: [f64; 3], radius: f64) -> Result<Self, NurbsError> {
        check_radius("radius", radius)?;
        let points = UNIT_CIRCLE
            .iter()
            .map(|&(x, y, _)| [center[0] + radius * x, center[1] + radius * y, center[2]])
            .collect();
        let weights = UNIT_CIRCLE.iter().map(|&(_, _, w)| w).collect();
        let knots = KnotVector::new(2, UNIT_CIRCLE_KNOTS.to_vec())?;
        Self::new(knots, points, weights)
    }

    /// The circular arc of the given centre and radius in the plane `z = centre.z` from angle
    /// `start` to angle `end` (radians, counter-clockwise, `0 < end − start ≤ 2π`), as The
    /// NURBS Book A7.1 builds it: `k = ⌈(end − start) / 90°⌉` quadratic arcs of sweep `Δ`,
    /// end points on the circle with weight 1, middle points at distance `r / cos(Δ/2)` on
    /// the bisector with weight `cos(Δ/2)`, double interior knots at `i / k`; domain `[0, 1]`.
    ///
    /// # Errors
    /// [`NurbsError::InvalidArgument`] for a bad radius or sweep.
    pub fn arc(center: [f64; 3], radius: f64, start: f64, end: f64) -> Result<Self, NurbsError> {
        check_radius("radius", radius)?;
        let sweep = end - start;
        if !(sweep > 0.0 && sweep <= 2.0 * PI && start.is_finite()) {
            return Err(NurbsError::InvalidArgument {
                name: "end - start",
                value: sweep,
                reason: "the sweep must be in (0, 2π]",
            });
        }
        let arcs = [FRAC_PI_2, PI, 1.5 * PI]
            .iter()
            .position(|&a| sweep <= a)
            .map_or(4, |i| i + 1);
        let delta = sweep / arcs as f64;
        let w1 = (0.5 * delta).cos();
        let at = |a: f64, r: f64| [center[0] + r * a.cos(), center[1] + r * a.sin(), center[2]];
        let mut points = vec![at(start, radius)];
        let mut weights = vec![1.0];
        let mut knots = vec![0.0; 3];
        for i in 1..=arcs {
            let a0 = start + (i - 1) as f64 * delta;
            points.push(at(a0 + 0.5 * delta, radius / w1));
            weights.push(w1);
            points.push(at(if i == arcs { end } else { a0 + delta }, radius));
            weights.push(1.0);
            if i < arcs {
                let k = i as f64 / arcs as f64;
                knots.extend([k, k]);
            }
        }
        knots.extend([1.0; 3]);
        Self::new(KnotVector::new(2, knots)?, points, weights)
    }

    /// The homogeneous B-spline `C^w`.
    pub fn homogeneous(&self) -> &BSplineCurve<4> {
        &self.homogeneous
    }

    /// The degree `p`.
    pub fn degree(&self) -> usize {
        self.homogeneous.degree()
    }

    /// The knot vector.
    pub fn knots(&self) -> &KnotVector {
        self.homogeneous.knots()
    }

    /// The parameter domain.
    pub fn domain(&self) -> (f64, f64) {
        self.homogeneous.domain()
    }

    /// Whether the curve is closed (periodic knots).
    pub fn is_closed(&self) -> bool {
        self.homogeneous.is_closed()
    }

    /// The (Cartesian) control points `P_i`.
    pub fn points(&self) -> &[[f64; 3]] {
        &self.points
    }

    /// The weights `w_i`.
    pub fn weights(&self) -> Vec<f64> {
        self.homogeneous.points().iter().map(|p| p[3]).collect()
    }

    /// The position `C(t) = A(t) / w(t)` with `C^w(t) = (A(t), w(t))` evaluated by de Boor's
    /// algorithm in 4D.
    ///
    /// # Errors
    /// As [`BSplineCurve::eval`].
    pub fn eval(&self, t: f64) -> Result<[f64; 3], NurbsError> {
        Ok(project(&self.homogeneous.eval(t)?))
    }

    /// The position and derivatives `[C, C', …, C^{(order)}]` by the quotient rule
    /// `C^{(k)} = (A^{(k)} − Σ_{i=1}^{k} C(k, i) w^{(i)} C^{(k−i)}) / w` (The NURBS Book eq.
    /// 4.8, A4.2).
    ///
    /// # Errors
    /// As [`BSplineCurve::eval`].
    pub fn eval_derivs(&self, t: f64, order: usize) -> Result<Vec<[f64; 3]>, NurbsError> {
        let h = self.homogeneous.eval_derivs(t, order)?;
        Ok(rational_derivs(&h))
    }

    /// Inserts the knot `t` into `C^w` (see [`BSplineCurve::insert_knot`]); the curve, and
    /// therefore every point on a circle or conic, is unchanged.
    ///
    /// # Errors
    /// As [`BSplineCurve::insert_knot`].
    pub fn insert_knot(&mut self, t: f64) -> Result<(), NurbsError> {
        self.insert_knots(&[t])
    }

    /// Inserts all the knots `ts` (see [`BSplineCurve::insert_knots`]).
    ///
    /// # Errors
    /// As [`BSplineCurve::insert_knots`].
    pub fn insert_knots(&mut self, ts: &[f64]) -> Result<(), NurbsError> {
        let mut h = self.homogeneous.clone();
        h.insert_knots(ts)?;
        *self = Self::from_homogeneous(h)?;
        Ok(())
    }

    /// Inserts the midpoint of every non-zero knot interval of the domain (see
    /// [`BSplineCurve::insert_midpoints`]).
    ///
    /// # Errors
    /// As [`BSplineCurve::insert_midpoints`].
    pub fn insert_midpoints(&mut self) -> Result<(), NurbsError> {
        let m = self.knots().midpoints();
        self.insert_knots(&m)
    }
}

/// `(x, y, z, w) ↦ (x / w, y / w, z / w)`.
#[inline]
pub(crate) fn project(p: &[f64; 4]) -> [f64; 3] {
    [p[0] / p[3], p[1] / p[3], p[2] / p[3]]
}

/// `[(w P_i, w_i)]`, validating counts and weights.
pub(crate) fn homogenize(
    points: &[[f64; 3]],
    weights: &[f64],
) -> Result<Vec<[f64; 4]>, NurbsError> {
    if points.len() != weights.len() {
        return Err(NurbsError::WeightCountMismatch {
            weights: weights.len(),
            points: points.len(),
        });
    }
    check_weights(weights.iter().copied())?;
    Ok(points
        .iter()
        .zip(weights)
        .map(|(p, &w)| [w * p[0], w * p[1], w * p[2], w])
        .collect())
}

/// Every weight positive and finite.
pub(crate) fn check_weights(weights: impl Iterator<Item = f64>) -> Result<(), NurbsError> {
    for (index, weight) in weights.enumerate() {
        if !(weight > 0.0 && weight.is_finite()) {
            return Err(NurbsError::NonPositiveWeight { index, weight });
        }
    }
    Ok(())
}

/// A positive finite length.
pub(crate) fn check_radius(name: &'static str, value: f64) -> Result<(), NurbsError> {
    if value > 0.0 && value.is_finite() {
        Ok(())
    } else {
        Err(NurbsError::InvalidArgument {
            name,
            value,
            reason: "must be positive and finite",
        })
    }
}

/// A4.2: Cartesian derivatives from homogeneous ones.
fn rational_derivs(h: &[[f64; 4]]) -> Vec<[f64; 3]> {
    let w0 = h[0][3];
    let mut ck: Vec<[f64; 3]> = Vec::with_capacity(h.len());
    for k in 0..h.len() {
        let mut v = [h[k][0], h[k][1], h[k][2]];
        let mut bin = 1.0; // C(k, i)
        for i in 1..=k {
            bin = bin * (k + 1 - i) as f64 / i as f64;
            let s = bin * h[i][3];
            for c in 0..3 {
                v[c] -= s * ck[k - i][c];
            }
        }
        ck.push([v[0] / w0, v[1] / w0, v[2] / w0]);
    }
    ck
}
