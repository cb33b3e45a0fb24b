//! The cubic curve to interpolate and its *middle polygon*: the control polygon with one
//! knot interval per edge, extended at an open end by a phantom control point when the
//! curve's end intervals need it.

use super::InterpolateError;
use crate::nurbs::Curve;

/// A cubic B-spline or NURBS curve, checked and in the form the zone builder needs.
///
/// # Which interval goes on which edge
/// A cubic control point `P_i` belongs to the basis function `N_{i,3}` on `t_i … t_{i+4}`,
/// centred on `t_{i+2}`; the edge `P_i P_{i+1}` carries `d_{i+2} = t_{i+3} − t_{i+2}`
/// (Sederberg, Zheng, Sewell & Sabin 1998; the same convention as
/// `crate::nurbs::mesh`), and `P_i` sits at the knot `t_{i+2}`. For a closed curve with
/// one period `u_0 … u_n` the edge `P_i P_{i+1}` carries `u_i − u_{i−1}` (indices mod `n`).
///
/// # Closed curves given open
/// A closed curve given in the unwrapped form CAD tools export (its first three control
/// points repeated at the end, its knot intervals periodic; openNURBS's `IsPeriodic`,
/// [`Curve::periodic_form`]) is taken as the closed curve: one zone round it, no seam.
///
/// # Closed clamped curves
/// A clamped curve (`t_1 = t_2 = t_3`, `t_n = t_{n+1} = t_{n+2}`) whose first and last
/// control points coincide is a closed curve with a `C⁰` point there: its zone is closed, the
/// two ends one vertex (two zones' end columns would cross at the seam). It is the closed
/// curve on `P_0 … P_{n−2}` with the period `u_i = t_{i+3}`, `0 ≤ i ≤ n − 1`: the edges at
/// `P_0` carry `d_2 = 0` and `d_n = 0`, a triple knot at the seam, and on every span the
/// closed curve's four control points and six knots are the clamped curve's (the knots
/// before `t_3` and after `t_n` that differ do not reach the domain), so it is the same
/// curve. The two points must have one weight.
///
/// # Open ends
/// On its domain `[t_3, t_n]` an open cubic with `n` points depends on the knots
/// `t_1 … t_{n+2}`: the `n − 1` edge intervals `d_2 … d_n` and two more, `d_1` before the
/// first edge and `d_{n+1}` after the last. The first edge point of the zone reads the
/// interval "before" `P_0` two steps around `P_0`; where `P_0` ends the zone the NURSS
/// boundary rule reads the mirror image, `d_2` (see `refine::nurss`). When
/// `d_1 = d_2` (every clamped curve, where both are 0, and every uniform one) that is already
/// right; otherwise the middle polygon gets a *phantom* point `P_{−1} = 2 P_0 − P_1` (weight
/// `w_0`) on an edge with interval `d_1`, so the rules read `d_1` at `P_0`. The phantom only
/// shapes the surface beyond the curve's end: the curve on its domain depends on
/// `P_0 … P_{n−1}` and `t_1 … t_{n+2}` alone. The same holds at the far end with `d_{n+1}`.
/// (Measured in `tests/integration/interpolate.rs`: for an unclamped non-uniform curve, leaving the
/// phantoms out puts the refined middle polygon 1.5e-2 of the curve's size off the knot-inserted
/// control polygon; with them the difference is 3e-16.)
#[derive(Clone, Debug, PartialEq)]
pub struct CubicCurve {
    /// Name for messages.
    pub label: String,
    /// Control points (Cartesian; for a closed curve the `n` distinct ones).
    pub points: Vec<[f64; 3]>,
    /// Rational weights, one per point (`None`: polynomial).
    pub weights: Option<Vec<f64>>,
    /// Closed (periodic) curve.
    pub closed: bool,
    /// Open: all knots `t_0 … t_{n+3}`; closed: one period `u_0 … u_n`.
    pub knots: Vec<f64>,
}

/// The middle polygon of a zone: the curve's control polygon (with phantom end points when
/// needed, see [`CubicCurve`]), its weights and its edge intervals.
#[derive(Clone, Debug, PartialEq)]
pub struct MiddlePolygon {
    /// Points, phantoms included.
    pub points: Vec<[f64; 3]>,
    /// Weight per point (1 for a polynomial curve).
    pub weights: Vec<f64>,
    /// Interval of edge `i` (from point `i` to `i + 1`, the last one wrapping for a closed
    /// curve): `points.len() − 1` values (open) or `points.len()` (closed).
    pub intervals: Vec<f64>,
    /// Closed polygon.
    pub closed: bool,
    /// The knot at point 0 (`t_2` of the curve, `t_1` with a phantom; for a closed curve
    /// `u_0 − (u_n − u_{n−1})`): the knot at point `j` is this plus the intervals of edges
    /// `0 … j − 1`.
    pub start_knot: f64,
    /// Index of the curve's control point 0 in `points` (1 with a phantom at the start).
    pub first: usize,
}

impl CubicCurve {
    /// Checks `curve` (cubic, finite, at least 4 control points open or 3 closed) and keeps
    /// its data; `label` names it in errors. A closed curve given in unwrapped form, and a
    /// clamped one whose ends coincide, are taken as closed (see the module
    /// documentation, "Closed curves given open").
    ///
    /// # Errors
    /// [`InterpolateError::Degree`] for a degree other than 3,
    /// [`InterpolateError::BadCurve`] for too few points or non-finite data, or ends that
    /// coincide with different weights.
    pub fn new(curve: &Curve, label: &str) -> Result<Self, InterpolateError> {
        let (knots, points, weights) = match curve {
            Curve::BSpline(c) => (c.knots(), c.points().to_vec(), None),
            Curve::Nurbs(c) => (c.knots(), c.points().to_vec(), Some(c.weights())),
        };
        if knots.degree() != 3 {
            return Err(InterpolateError::Degree {
                curve: label.to_string(),
                degree: knots.degree(),
            });
        }
        let bad = |reason: String| InterpolateError::BadCurve {
            curve: label.to_string(),
            reason,
        };
        // A closed curve given unwrapped, as CAD tools export one: closed.
        if let Some(periodic) = curve.periodic_form() {
            return Self::new(&periodic, label);
        }
        let closed = knots.is_periodic();
        let min = if closed { 3 } else { 4 };
        if points.len() < min {
            return Err(bad(format!(
                "{} control points; a zone needs at least {min}",
                points.len()
            )));
        }
        if let Some(i) = points.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(bad(format!("control point {i} is not finite")));
        }
        let knots = match knots.period_knots() {
            Some(u) => u.to_vec(),
            None => knots.as_slice().to_vec(),
        };
        let c = Self {
            label: label.to_string(),
            points,
            weights,
            closed,
            knots,
        };
        c.joined_ends()
    }

    /// A clamped curve whose first and last control points coincide (within 1e-9 of its
    /// size) as the closed curve it is: see [`CubicCurve`](CubicCurve#closed-clamped-curves).
    ///
    /// # Errors
    /// [`InterpolateError::BadCurve`] when the two points have different weights.
    fn joined_ends(self) -> Result<Self, InterpolateError> {
        let n = self.points.len();
        let t = &self.knots;
        let clamped = !self.closed && t[1] == t[3] && t[n] == t[n + 2];
        let size = super::zone::curve_size(&self.points);
        let meet = crate::geom::norm(&crate::geom::sub(&self.points[0], &self.points[n - 1]));
        if !clamped || n < 4 || meet > 1e-9 * size {
            return Ok(self);
        }
        let (w0, w1) = (self.weight(0), self.weight(n - 1));
        if w0 != w1 {
            return Err(InterpolateError::BadCurve {
                curve: self.label,
                reason: format!(
                    "its first and last control points coincide (a closed clamped curve) but their weights differ ({w0} and {w1}); one zone vertex joins both ends, so give them one weight"
                ),
            });
        }
        let period = t[3..=n + 2].to_vec();
        if crate::nurbs::KnotVector::periodic(3, &period).is_err() {
            return Ok(self);
        }
        let mut points = self.points;
        points.truncate(n - 1);
        let weights = self.weights.map(|mut w| {
            w.truncate(n - 1);
            w
        });
        Ok(Self {
            label: self.label,
            points,
            weights,
            closed: true,
            knots: period,
        })
    }

    /// Number of control points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether there are no control points (never, for a checked curve).
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Weight of control point `i` (1 for a polynomial curve).
    pub fn weight(&self, i: usize) -> f64 {
        self.weights.as_ref().map_or(1.0, |w| w[i])
    }

    /// The middle polygon (see [`CubicCurve`]).
    pub fn middle_polygon(&self) -> MiddlePolygon {
        self.middle_polygon_with(false, false)
    }

    /// The middle polygon, with a phantom point at the start / end of an open curve also
    /// where the end intervals would not need one (a curve ending at a crossing: the phantom
    /// is the joint polygon group's point opposite the curve's last edge).
    pub fn middle_polygon_with(&self, start_phantom: bool, end_phantom: bool) -> MiddlePolygon {
        let n = self.points.len();
        let k = &self.knots;
        let weights: Vec<f64> = (0..n).map(|i| self.weight(i)).collect();
        if self.closed {
            let d: Vec<f64> = k.windows(2).map(|w| w[1] - w[0]).collect();
            // Edge i carries u_i − u_{i−1}, i.e. d[(i − 1) mod n].
            let intervals = (0..n).map(|i| d[(i + n - 1) % n]).collect();
            return MiddlePolygon {
                points: self.points.clone(),
                weights,
                intervals,
                closed: true,
                start_knot: k[0] - d[n - 1],
                first: 0,
            };
        }
        let d: Vec<f64> = k.windows(2).map(|w| w[1] - w[0]).collect();
        let mut points = self.points.clone();
        let mut w = weights;
        let mut intervals: Vec<f64> = d[2..=n].to_vec();
        let mut start_knot = k[2];
        let mut first = 0;
        let reflect =
            |a: &[f64; 3], b: &[f64; 3]| [2.0 * a[0] - b[0], 2.0 * a[1] - b[1], 2.0 * a[2] - b[2]];
        if start_phantom || d[1] != d[2] {
            points.insert(0, reflect(&self.points[0], &self.points[1]));
            w.insert(0, w[0]);
            intervals.insert(0, d[1]);
            start_knot = k[1];
            first = 1;
        }
        if end_phantom || d[n + 1] != d[n] {
            points.push(reflect(&self.points[n - 1], &self.points[n - 2]));
            w.push(w[w.len() - 1]);
            intervals.push(d[n + 1]);
        }
        MiddlePolygon {
            points,
            weights: w,
            intervals,
            closed: false,
            start_knot,
            first,
        }
    }
}

impl MiddlePolygon {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether the polygon has no points.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Number of edges.
    pub fn num_edges(&self) -> usize {
        self.intervals.len()
    }
}
