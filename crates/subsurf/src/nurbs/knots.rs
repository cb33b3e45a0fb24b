//! [`KnotVector`]: validated knot vectors, open or periodic, and their knot intervals.
//!
//! # Conventions (The NURBS Book, Piegl & Tiller, 2nd ed., §2.2)
//! A B-spline of degree `p` with `N` basis functions `N_{0,p} … N_{N-1,p}` has the knots
//! `t_0 ≤ t_1 ≤ … ≤ t_{N+p}` (`N + p + 1` of them); `N_{i,p}` is supported on
//! `[t_i, t_{i+p+1}]`, and the curve is defined on the *domain* `[t_p, t_N]`, where `p + 1`
//! basis functions overlap everywhere. A knot may repeat at most `p + 1` times.
//!
//! The *knot intervals* are `d_i = t_{i+1} − t_i` (Sederberg, Zheng, Sewell & Sabin,
//! "Non-uniform recursive subdivision surfaces", SIGGRAPH 1998 — NURSS): a knot vector is its
//! first knot plus its intervals, and a multiple knot is a zero interval.
//!
//! # Periodic knot vectors
//! A closed curve with `n` distinct control points `P_0 … P_{n-1}` is given one period of
//! knots `u_0 ≤ u_1 ≤ … ≤ u_n` (period `T = u_n − u_0 > 0`, intervals `d_i = u_{i+1} − u_i`).
//! It is stored *unwrapped*, as the open B-spline with the `n + p` control points
//! `P_0 … P_{n-1}, P_0 … P_{p-1}` (indices mod `n`) and the `n + 2p + 1` knots
//! `t_{p+i} = u_i` (`0 ≤ i ≤ n`), extended periodically: `t_{p-k} = u_0 − (u_n − u_{n-k})` and
//! `t_{p+n+k} = u_n + (u_k − u_0)` for `1 ≤ k ≤ p` (so `t_{j+n} − t_j = T` and the interval
//! `t_{j+1} − t_j` is `d_{(j−p) mod n}`). The domain is then `[t_p, t_{p+n}] = [u_0, u_n]`,
//! and parameters outside it are wrapped into `[u_0, u_n)`. Point `P_i` belongs to the basis
//! function that starts at `t_i`; for a uniform cubic, `C(u_0) = (P_0 + 4 P_1 + P_2) / 6`.

use super::NurbsError;

/// The largest degree accepted. Every algorithm works for any degree; the bound only keeps
/// untrusted input (a JSON `degree`) from requesting absurd allocations (`O(p²)` scratch,
/// `2p` padding knots), far above any practical use (CAD systems stop at 25 or below).
pub const MAX_DEGREE: usize = 64;

/// A validated knot vector of a given degree: open (`t_0 … t_{N+p}`) or periodic (one period
/// `u_0 … u_n`, stored unwrapped; see the module documentation).
///
/// Invariants: degree `1 ≤ p ≤` [`MAX_DEGREE`]; knots finite and non-decreasing; no knot repeated more than
/// `p + 1` times; a non-empty domain; at least `p + 1` basis functions (open) or `max(p, 2)`
/// distinct control points (periodic).
///
/// ```
/// use subsurf::nurbs::KnotVector;
/// let k = KnotVector::new(3, vec![0.0, 0.0, 0.0, 0.0, 1.0, 3.0, 3.0, 3.0, 3.0])?;
/// assert_eq!(k.num_points(), 5);
/// assert_eq!(k.domain(), (0.0, 3.0));
/// assert_eq!(k.intervals(), vec![0.0, 0.0, 0.0, 1.0, 2.0, 0.0, 0.0, 0.0]);
/// assert!(k.is_clamped());
/// # Ok::<(), subsurf::nurbs::NurbsError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct KnotVector {
    degree: usize,
    knots: Vec<f64>,
    periodic: bool,
}

impl KnotVector {
    /// An open knot vector `t_0 … t_{N+p}` of degree `p` (for `N = knots.len() − p − 1`
    /// control points).
    ///
    /// # Errors
    /// [`NurbsError::BadDegree`] (`p = 0`), [`NurbsError::TooFewKnots`] (fewer than
    /// `2 (p + 1)`), [`NurbsError::NonFiniteKnot`], [`NurbsError::DecreasingKnots`],
    /// [`NurbsError::KnotMultiplicity`] (a knot repeated more than `p + 1` times),
    /// [`NurbsError::EmptyDomain`] (`t_p = t_N`).
    pub fn new(degree: usize, knots: Vec<f64>) -> Result<Self, NurbsError> {
        check_degree(degree)?;
        let min = 2 * (degree + 1);
        if knots.len() < min {
            return Err(NurbsError::TooFewKnots {
                degree,
                count: knots.len(),
                min,
            });
        }
        check_sorted(&knots)?;
        check_multiplicity(&knots, degree)?;
        let (start, end) = (knots[degree], knots[knots.len() - degree - 1]);
        if start >= end {
            return Err(NurbsError::EmptyDomain { start, end });
        }
        Ok(Self {
            degree,
            knots,
            periodic: false,
        })
    }

    /// A periodic knot vector of degree `p` from one period of knots `u_0 ≤ … ≤ u_n`, for a
    /// closed curve with `n` distinct control points (`n ≥ max(p, 2)`).
    ///
    /// Stored unwrapped, `t_{p+i} = u_i`, extended by translating the intervals across the
    /// seam (see the module documentation). `u_0` and `u_n` are the same knot (the
    /// seam): its multiplicity is the run `u_0 = u_1 = …` plus the run `… = u_{n-1} = u_n`,
    /// minus one.
    ///
    /// # Errors
    /// As [`new`](Self::new), with indices into `period_knots`; [`NurbsError::TooFewKnots`]
    /// when `n < max(p, 2)`; [`NurbsError::EmptyDomain`] when the period is zero.
    pub fn periodic(degree: usize, period_knots: &[f64]) -> Result<Self, NurbsError> {
        check_degree(degree)?;
        let min = degree.max(2) + 1;
        if period_knots.len() < min {
            return Err(NurbsError::TooFewKnots {
                degree,
                count: period_knots.len(),
                min,
            });
        }
        check_sorted(period_knots)?;
        let u = period_knots;
        let n = u.len() - 1;
        let (start, end) = (u[0], u[n]);
        if start >= end {
            return Err(NurbsError::EmptyDomain { start, end });
        }
        // Multiplicity, with the runs at both ends glued at the seam.
        check_multiplicity(&u[..n], degree)?;
        let head = u.iter().take_while(|&&x| x == start).count();
        let tail = u.iter().rev().take_while(|&&x| x == end).count();
        if head + tail - 1 > degree + 1 {
            return Err(NurbsError::KnotMultiplicity {
                knot: start,
                multiplicity: head + tail - 1,
                max: degree + 1,
            });
        }
        let p = degree;
        let mut knots = Vec::with_capacity(n + 2 * p + 1);
        knots.extend((1..=p).rev().map(|k| start - (end - u[n - k])));
        knots.extend_from_slice(u);
        knots.extend((1..=p).map(|k| end + (u[k] - start)));
        Ok(Self {
            degree,
            knots,
            periodic: true,
        })
    }

    /// The uniform open (unclamped) knot vector `t_i = i`, `0 ≤ i ≤ n + p`, for `n` control
    /// points; its domain is `[p, n]`. Uniform knots give the classic uniform B-splines (a
    /// uniform bicubic net is a regular Catmull-Clark mesh).
    ///
    /// # Errors
    /// [`NurbsError::BadDegree`], or [`NurbsError::TooFewPoints`] when `n ≤ p`.
    pub fn uniform(degree: usize, num_points: usize) -> Result<Self, NurbsError> {
        let len = num_points.saturating_add(degree).saturating_add(1);
        check_len_for_points(degree, num_points)?;
        Self::new(degree, (0..len).map(|i| i as f64).collect())
    }

    /// The clamped uniform knot vector on `[0, 1]` for `n ≥ p + 1` control points: `p + 1`
    /// zeros, the interior knots `k / (n − p)` for `1 ≤ k < n − p`, and `p + 1` ones (The
    /// NURBS Book eq. 2.13 with equally spaced interior knots). The curve interpolates its
    /// end points.
    ///
    /// # Errors
    /// [`NurbsError::BadDegree`], or [`NurbsError::TooFewPoints`] when `n ≤ p`.
    pub fn clamped_uniform(degree: usize, num_points: usize) -> Result<Self, NurbsError> {
        check_len_for_points(degree, num_points)?;
        let spans = num_points - degree;
        let mut k = vec![0.0; degree + 1];
        k.extend((1..spans).map(|i| i as f64 / spans as f64));
        k.extend(std::iter::repeat_n(1.0, degree + 1));
        Self::new(degree, k)
    }

    /// The uniform periodic knot vector `u_i = i`, `0 ≤ i ≤ n`, for a closed curve with `n`
    /// control points.
    ///
    /// # Errors
    /// As [`periodic`](Self::periodic).
    pub fn periodic_uniform(degree: usize, num_points: usize) -> Result<Self, NurbsError> {
        let u: Vec<f64> = (0..=num_points).map(|i| i as f64).collect();
        Self::periodic(degree, &u)
    }

    /// The knot vector with the given knot intervals `d_i = t_{i+1} − t_i`, starting at 0
    /// (`t_0 = 0`, `t_{i+1} = t_i + d_i`, NURSS notation).
    ///
    /// With `clamped`, `intervals` are only the intervals of the domain (the `n − p` spans of
    /// a curve with `n` control points) and `p` zero intervals are added at each end, so that
    /// the first and last knots have multiplicity `p + 1`; otherwise `intervals` are all
    /// `n + p` intervals.
    ///
    /// # Errors
    /// [`NurbsError::NonFiniteKnot`] / [`NurbsError::DecreasingKnots`] for non-finite or
    /// negative intervals (indices of the resulting knots), and the errors of
    /// [`new`](Self::new).
    pub fn from_intervals(
        degree: usize,
        intervals: &[f64],
        clamped: bool,
    ) -> Result<Self, NurbsError> {
        check_degree(degree)?;
        let pad = if clamped { degree } else { 0 };
        let mut knots = Vec::with_capacity(intervals.len() + 1 + 2 * pad);
        knots.extend(std::iter::repeat_n(0.0, pad + 1));
        let mut t = 0.0;
        for &d in intervals {
            t += d;
            knots.push(t);
        }
        knots.extend(std::iter::repeat_n(t, pad));
        Self::new(degree, knots)
    }

    /// The periodic knot vector with the given knot intervals over one period
    /// (`u_0 = 0`, `u_{i+1} = u_i + d_i`, `n = intervals.len()` control points).
    ///
    /// # Errors
    /// As [`periodic`](Self::periodic).
    pub fn periodic_from_intervals(degree: usize, intervals: &[f64]) -> Result<Self, NurbsError> {
        let mut u = Vec::with_capacity(intervals.len() + 1);
        u.push(0.0);
        let mut t = 0.0;
        for &d in intervals {
            t += d;
            u.push(t);
        }
        Self::periodic(degree, &u)
    }

    /// The degree `p`.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// Whether the knot vector is periodic (a closed curve).
    pub fn is_periodic(&self) -> bool {
        self.periodic
    }

    /// All knots `t_0 … t_{N+p}` (unwrapped for a periodic knot vector).
    pub fn as_slice(&self) -> &[f64] {
        &self.knots
    }

    /// Number of knots `N + p + 1` (unwrapped for a periodic knot vector).
    pub fn num_knots(&self) -> usize {
        self.knots.len()
    }

    /// Number of basis functions `N = len − p − 1` (for a periodic knot vector, `n + p`: the
    /// unwrapped control points, the first `p` repeated).
    pub fn num_basis(&self) -> usize {
        self.knots.len() - self.degree - 1
    }

    /// Number of distinct control points a curve with these knots has: `N` for an open knot
    /// vector, `n` for a periodic one.
    pub fn num_points(&self) -> usize {
        if self.periodic {
            self.knots.len() - 2 * self.degree - 1
        } else {
            self.num_basis()
        }
    }

    /// One period of knots `u_0 … u_n` of a periodic knot vector.
    pub fn period_knots(&self) -> Option<&[f64]> {
        self.periodic
            .then(|| &self.knots[self.degree..self.knots.len() - self.degree])
    }

    /// The parameter domain `[t_p, t_N]` (for a periodic knot vector, one period
    /// `[u_0, u_n]`).
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.num_basis()])
    }

    /// The parameter `t` checked against the domain: unchanged if `t_p ≤ t ≤ t_N`; for a
    /// periodic knot vector any finite `t` is wrapped into `[u_0, u_n)`,
    /// `u_0 + (t − u_0) mod T`.
    ///
    /// # Errors
    /// [`NurbsError::ParameterOutOfDomain`] for NaN, infinite, or (open) out-of-domain `t`.
    pub fn parameter(&self, t: f64) -> Result<f64, NurbsError> {
        let (start, end) = self.domain();
        if self.periodic && t.is_finite() {
            if (start..end).contains(&t) {
                return Ok(t);
            }
            let w = start + (t - start).rem_euclid(end - start);
            return Ok(if w < end { w } else { start });
        }
        if t >= start && t <= end {
            Ok(t)
        } else {
            Err(NurbsError::ParameterOutOfDomain { t, start, end })
        }
    }

    /// The knot span of `t` (after [`parameter`](Self::parameter)): the index `k`,
    /// `p ≤ k < N`, with `t_k ≤ t < t_{k+1}`, found by binary search (The NURBS Book A2.1); at
    /// the end of the domain, `t = t_N`, the last non-empty span.
    ///
    /// ```
    /// use subsurf::nurbs::KnotVector;
    /// let k = KnotVector::new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 2.0])?;
    /// assert_eq!(k.span(0.5)?, 2);
    /// assert_eq!(k.span(1.0)?, 4);
    /// assert_eq!(k.span(2.0)?, 4);
    /// # Ok::<(), subsurf::nurbs::NurbsError>(())
    /// ```
    ///
    /// # Errors
    /// As [`parameter`](Self::parameter).
    pub fn span(&self, t: f64) -> Result<usize, NurbsError> {
        let t = self.parameter(t)?;
        Ok(self.span_in_domain(t))
    }

    /// [`span`](Self::span) for a parameter already in the domain.
    pub(crate) fn span_in_domain(&self, t: f64) -> usize {
        let (p, n) = (self.degree, self.num_basis());
        let k = &self.knots;
        if t >= k[n] {
            let mut s = n - 1;
            while s > p && k[s] == k[s + 1] {
                s -= 1;
            }
            return s;
        }
        // Number of knots among t_p … t_{n-1} that are ≤ t (at least one: t ≥ t_p).
        let c = k[p..n].partition_point(|&x| x <= t);
        p + c.max(1) - 1
    }

    /// How many times the value `t` occurs as a knot (for a periodic knot vector, within one
    /// period, the seam counted once).
    pub fn multiplicity(&self, t: f64) -> usize {
        match self.period_knots() {
            Some(u) => {
                let n = u.len() - 1;
                if t == u[0] || t == u[n] {
                    let head = u.iter().take_while(|&&x| x == u[0]).count();
                    let tail = u.iter().rev().take_while(|&&x| x == u[n]).count();
                    head + tail - 1
                } else {
                    u.iter().filter(|&&x| x == t).count()
                }
            }
            None => self.knots.iter().filter(|&&x| x == t).count(),
        }
    }

    /// The knot intervals `d_i = t_{i+1} − t_i`: all `N + p` of them for an open knot vector,
    /// the `n` intervals of one period `u_{i+1} − u_i` for a periodic one (the inverse of
    /// [`from_intervals`](Self::from_intervals) /
    /// [`periodic_from_intervals`](Self::periodic_from_intervals) up to the first knot).
    pub fn intervals(&self) -> Vec<f64> {
        let s = self.period_knots().unwrap_or(&self.knots);
        s.windows(2).map(|w| w[1] - w[0]).collect()
    }

    /// The intervals of the domain, `t_{i+1} − t_i` for `p ≤ i < N` (one period for a
    /// periodic knot vector).
    pub fn domain_intervals(&self) -> Vec<f64> {
        self.knots[self.degree..=self.num_basis()]
            .windows(2)
            .map(|w| w[1] - w[0])
            .collect()
    }

    /// Whether the knot vector is open and clamped: `t_0 = … = t_p` and
    /// `t_N = … = t_{N+p}`, so that the curve interpolates its end control points.
    pub fn is_clamped(&self) -> bool {
        let (p, k) = (self.degree, &self.knots);
        !self.periodic
            && k[..=p].iter().all(|&x| x == k[0])
            && k[k.len() - p - 1..].iter().all(|&x| x == k[k.len() - 1])
    }

    /// The periodic knot vector that this open one is the unwrapped form of, if it is one:
    /// the form CAD tools export a closed curve in (see [`BSplineCurve::periodic_form`]
    /// for the control points). With `N` basis functions and `n = N − p` it needs degree
    /// `p ≥ 2`, `N ≥ p + 3` (`p ≤ 3`) or `N ≥ 2p` (`p ≥ 4`), and the intervals `d_j =
    /// t_{j+1} − t_j` to repeat with period `n` for `1 ≤ j ≤ 2p − 2`, within `√ε` (1.49e-8)
    /// times the larger of `t_{p+1} − t_{p−1}` and the domain's length: openNURBS's
    /// `ON_IsKnotVectorPeriodic` (the two outermost knots, which openNURBS does not store,
    /// do not influence the curve). The result has the period `u_i = t_{p+i}`, `0 ≤ i ≤ n`:
    /// the same knots on the domain and the periodic extension outside it.
    ///
    /// [`BSplineCurve::periodic_form`]: super::BSplineCurve::periodic_form
    pub fn periodic_form(&self) -> Option<Self> {
        const SQRT_EPSILON: f64 = 1.490116119385e-8;
        let (p, t) = (self.degree, &self.knots);
        let big = self.num_basis();
        let enough = if p <= 3 { big >= p + 3 } else { big >= 2 * p };
        if self.periodic || p < 2 || !enough {
            return None;
        }
        let n = big - p;
        let (start, end) = self.domain();
        let tol = SQRT_EPSILON * (t[p + 1] - t[p - 1]).abs().max(end - start);
        let d = |j: usize| t[j + 1] - t[j];
        if (1..=2 * p - 2).any(|j| (d(j) - d(j + n)).abs() > tol) {
            return None;
        }
        Self::periodic(p, &t[p..=p + n]).ok()
    }

    /// The same knot vector mapped affinely so that the domain becomes `[0, 1]`:
    /// `t ↦ (t − t_p) / (t_N − t_p)` (the end knots map to exactly 0 and 1; the order of the
    /// knots is kept, since rounding is monotonic).
    pub fn normalized(&self) -> Self {
        let (a, b) = self.domain();
        let map = |t: f64| (t - a) / (b - a);
        match self.period_knots() {
            Some(u) => {
                let u: Vec<f64> = u.iter().map(|&t| map(t)).collect();
                // A monotonic affine image of a valid period is valid.
                Self::periodic(self.degree, &u).unwrap_or_else(|_| self.clone())
            }
            None => Self {
                degree: self.degree,
                knots: self.knots.iter().map(|&t| map(t)).collect(),
                periodic: false,
            },
        }
    }

    /// The Greville abscissae `ξ_i = (t_{i+1} + … + t_{i+p}) / p`, one per distinct control
    /// point (de Boor, *A Practical Guide to Splines*): the parameter a control point is
    /// "attached to"; the control polygon lies within `O(h²)` of the curve at these
    /// parameters, `h` the largest knot interval. For a periodic knot vector they may lie before
    /// `u_0` (wrap them with [`parameter`](Self::parameter)).
    pub fn greville(&self) -> Vec<f64> {
        let p = self.degree;
        (0..self.num_points())
            .map(|i| self.knots[i + 1..=i + p].iter().sum::<f64>() / p as f64)
            .collect()
    }

    /// The midpoints `(t_i + t_{i+1}) / 2` of the non-zero intervals of the domain (of one
    /// period): the knots one step of non-uniform (NURSS) subdivision inserts.
    pub fn midpoints(&self) -> Vec<f64> {
        self.knots[self.degree..=self.num_basis()]
            .windows(2)
            .filter(|w| w[1] > w[0])
            .map(|w| w[0] + 0.5 * (w[1] - w[0]))
            .collect()
    }
}

/// `1 ≤ degree ≤ MAX_DEGREE`.
fn check_degree(degree: usize) -> Result<(), NurbsError> {
    if degree == 0 {
        return Err(NurbsError::BadDegree {
            degree,
            reason: "the degree must be at least 1",
        });
    }
    if degree > MAX_DEGREE {
        return Err(NurbsError::BadDegree {
            degree,
            reason: "the degree must be at most MAX_DEGREE = 64",
        });
    }
    Ok(())
}

/// Enough points for a degree (n ≥ p + 1), as a knot-count error.
fn check_len_for_points(degree: usize, num_points: usize) -> Result<(), NurbsError> {
    check_degree(degree)?;
    if num_points <= degree {
        return Err(NurbsError::TooFewPoints {
            count: num_points,
            degree,
            min: degree + 1,
        });
    }
    Ok(())
}

/// Finite and non-decreasing.
fn check_sorted(knots: &[f64]) -> Result<(), NurbsError> {
    for (index, &value) in knots.iter().enumerate() {
        if !value.is_finite() {
            return Err(NurbsError::NonFiniteKnot { index, value });
        }
        if index > 0 && value < knots[index - 1] {
            return Err(NurbsError::DecreasingKnots {
                index,
                previous: knots[index - 1],
                value,
            });
        }
    }
    Ok(())
}

/// No run of equal knots longer than `p + 1` (knots sorted).
fn check_multiplicity(knots: &[f64], degree: usize) -> Result<(), NurbsError> {
    let mut run = 0;
    for (i, &t) in knots.iter().enumerate() {
        run = if i > 0 && t == knots[i - 1] {
            run + 1
        } else {
            1
        };
        if run > degree + 1 {
            let multiplicity = knots.iter().filter(|&&x| x == t).count();
            return Err(NurbsError::KnotMultiplicity {
                knot: t,
                multiplicity,
                max: degree + 1,
            });
        }
    }
    Ok(())
}
