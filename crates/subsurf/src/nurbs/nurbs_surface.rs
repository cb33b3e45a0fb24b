//! [`NurbsSurface`]: rational tensor-product surfaces in 3D, as B-spline surfaces in
//! homogeneous coordinates, with the exact cylinder and torus.
//!
//! `S(u, v) = Σ N_{i,p}(u) N_{j,q}(v) w_{i,j} P_{i,j} / Σ N_{i,p}(u) N_{j,q}(v) w_{i,j}`
//! (The NURBS Book eq. 4.15) is the projection of the 4D B-spline surface `S^w = (A, w)`
//! with control points `(w P, w)`; its derivatives follow from the quotient rule (eq. 4.20,
//! A4.4):
//! `S_{k,l} = (A_{k,l} − Σ_{j=1}^{l} C(l,j) w_{0,j} S_{k,l−j}
//!            − Σ_{i=1}^{k} C(k,i) w_{i,0} S_{k−i,l}
//!            − Σ_{i=1}^{k} C(k,i) Σ_{j=1}^{l} C(l,j) w_{i,j} S_{k−i,l−j}) / w`.

use super::nurbs_curve::{check_radius, check_weights, homogenize, project};
use super::nurbs_curve::{UNIT_CIRCLE, UNIT_CIRCLE_KNOTS};
use super::surface::{BSplineSurface, SurfaceDerivs};
use super::{KnotVector, NurbsError};

/// A rational tensor-product B-spline (NURBS) surface in 3D with positive weights, stored as
/// its homogeneous B-spline surface (control points `(w x, w y, w z, w)`, row by row
/// `i · nv + j` as in [`BSplineSurface`]) together with the Cartesian points as given (see
/// [`NurbsCurve`](super::NurbsCurve)).
///
/// ```
/// use subsurf::nurbs::NurbsSurface;
/// let torus = NurbsSurface::torus([0.0, 0.0, 0.0], 3.0, 1.0)?;
/// let p = torus.eval(0.3, 0.8)?;
/// let rho = (p[0] * p[0] + p[1] * p[1]).sqrt();
/// assert!(((rho - 3.0).powi(2) + p[2] * p[2] - 1.0).abs() < 1e-14);
/// # Ok::<(), subsurf::nurbs::NurbsError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct NurbsSurface {
    homogeneous: BSplineSurface<4>,
    points: Vec<[f64; 3]>,
}

impl NurbsSurface {
    /// A NURBS surface from knots, control net and weights (both `[i · nv + j]`).
    ///
    /// # Errors
    /// [`NurbsError::WeightCountMismatch`], [`NurbsError::NonPositiveWeight`], and the errors
    /// of [`BSplineSurface::new`].
    pub fn new(
        u: KnotVector,
        v: KnotVector,
        points: Vec<[f64; 3]>,
        weights: Vec<f64>,
    ) -> Result<Self, NurbsError> {
        super::curve::check_magnitude(&points)?;
        let hw = homogenize(&points, &weights)?;
        Ok(Self {
            homogeneous: BSplineSurface::new(u, v, hw)?,
            points,
        })
    }

    /// A NURBS surface from its homogeneous B-spline surface (Cartesian points projected).
    ///
    /// # Errors
    /// [`NurbsError::NonPositiveWeight`] unless every `w > 0`.
    pub fn from_homogeneous(surface: BSplineSurface<4>) -> Result<Self, NurbsError> {
        check_weights(surface.points().iter().map(|p| p[3]))?;
        let points = surface.points().iter().map(project).collect();
        let weights: Vec<f64> = surface.points().iter().map(|p| p[3]).collect();
        let (u, v) = (surface.knots_u().clone(), surface.knots_v().clone());
        Self::new(u, v, points, weights)
    }

    /// The circular cylinder of axis `z` through `base` (the centre of its bottom circle),
    /// radius `r` and height `h`: the nine-point NURBS circle
    /// ([`NurbsCurve::circle`](super::NurbsCurve::circle)) along `u ∈ [0, 1]` swept linearly
    /// along `v ∈ [0, 1]` (degrees 2 × 1; The NURBS Book §8.3, general cylinder):
    /// `P_{i,j} = base + (r X_i, r Y_i, j h)`, `w_{i,j} = w_i`.
    ///
    /// # Errors
    /// [`NurbsError::InvalidArgument`] unless `r` and `h` are positive and finite.
    pub fn cylinder(base: [f64; 3], radius: f64, height: f64) -> Result<Self, NurbsError> {
        check_radius("radius", radius)?;
        check_radius("height", height)?;
        let mut points = Vec::with_capacity(18);
        let mut weights = Vec::with_capacity(18);
        for &(x, y, w) in &UNIT_CIRCLE {
            for j in 0..2 {
                points.push([
                    base[0] + radius * x,
                    base[1] + radius * y,
                    base[2] + j as f64 * height,
                ]);
                weights.push(w);
            }
        }
        let u = KnotVector::new(2, UNIT_CIRCLE_KNOTS.to_vec())?;
        let v = KnotVector::new(1, vec![0.0, 0.0, 1.0, 1.0])?;
        Self::new(u, v, points, weights)
    }

    /// The torus around the `z` axis through `center`, of major radius `R` (centre of the
    /// tube) and minor radius `r` (the tube): the surface of revolution (The NURBS Book §8.5,
    /// A8.1) of the NURBS circle of radius `r` centred at distance `R`, i.e.
    /// `P_{i,j} = center + ((R + r X_j) X_i, (R + r X_j) Y_i, r Y_j)`, `w_{i,j} = w_i w_j`
    /// with `(X, Y, w)` the unit circle's control points; `u ∈ [0, 1]` goes around the axis,
    /// `v ∈ [0, 1]` around the tube. Every point satisfies
    /// `(√(x² + y²) − R)² + z² = r²` (relative to the centre).
    ///
    /// # Errors
    /// [`NurbsError::InvalidArgument`] unless both radii are positive and finite.
    pub fn torus(center: [f64; 3], major: f64, minor: f64) -> Result<Self, NurbsError> {
        check_radius("major radius", major)?;
        check_radius("minor radius", minor)?;
        let mut points = Vec::with_capacity(81);
        let mut weights = Vec::with_capacity(81);
        for &(xi, yi, wi) in &UNIT_CIRCLE {
            for &(xj, yj, wj) in &UNIT_CIRCLE {
                let rho = major + minor * xj;
                points.push([
                    center[0] + rho * xi,
                    center[1] + rho * yi,
                    center[2] + minor * yj,
                ]);
                weights.push(wi * wj);
            }
        }
        let k = KnotVector::new(2, UNIT_CIRCLE_KNOTS.to_vec())?;
        Self::new(k.clone(), k, points, weights)
    }

    /// The homogeneous B-spline surface `S^w`.
    pub fn homogeneous(&self) -> &BSplineSurface<4> {
        &self.homogeneous
    }

    /// The knot vector along `u`.
    pub fn knots_u(&self) -> &KnotVector {
        self.homogeneous.knots_u()
    }

    /// The knot vector along `v`.
    pub fn knots_v(&self) -> &KnotVector {
        self.homogeneous.knots_v()
    }

    /// The degrees `(p, q)`.
    pub fn degrees(&self) -> (usize, usize) {
        self.homogeneous.degrees()
    }

    /// The numbers of distinct control points `(nu, nv)`.
    pub fn size(&self) -> (usize, usize) {
        self.homogeneous.size()
    }

    /// The parameter domains.
    pub fn domain(&self) -> ((f64, f64), (f64, f64)) {
        self.homogeneous.domain()
    }

    /// The Cartesian control points `P_{i,j}` (`[i · nv + j]`).
    pub fn points(&self) -> &[[f64; 3]] {
        &self.points
    }

    /// The weights `w_{i,j}` (`[i · nv + j]`).
    pub fn weights(&self) -> Vec<f64> {
        self.homogeneous.points().iter().map(|p| p[3]).collect()
    }

    /// The position `S(u, v) = A(u, v) / w(u, v)`.
    ///
    /// # Errors
    /// As [`BSplineSurface::eval`].
    pub fn eval(&self, u: f64, v: f64) -> Result<[f64; 3], NurbsError> {
        Ok(project(&self.homogeneous.eval(u, v)?))
    }

    /// All partial derivatives up to total order `order`, `skl[k][l] = ∂^{k+l}S/∂u^k∂v^l`
    /// (`k + l ≤ order`, zero otherwise), by the quotient rule of The NURBS Book A4.4 (see
    /// the module documentation).
    ///
    /// # Errors
    /// As [`BSplineSurface::eval`].
    pub fn eval_derivs(
        &self,
        u: f64,
        v: f64,
        order: usize,
    ) -> Result<Vec<Vec<[f64; 3]>>, NurbsError> {
        let h = self.homogeneous.eval_derivs(u, v, order)?;
        let bin = binomials(order);
        let w = h[0][0][3];
        let mut skl = vec![vec![[0.0; 3]; order + 1]; order + 1];
        for k in 0..=order {
            for l in 0..=order - k {
                let mut v = [h[k][l][0], h[k][l][1], h[k][l][2]];
                let mut sub = |s: f64, p: [f64; 3]| {
                    for c in 0..3 {
                        v[c] -= s * p[c];
                    }
                };
                for j in 1..=l {
                    sub(bin[l][j] * h[0][j][3], skl[k][l - j]);
                }
                for i in 1..=k {
                    sub(bin[k][i] * h[i][0][3], skl[k - i][l]);
                    for j in 1..=l {
                        sub(bin[k][i] * bin[l][j] * h[i][j][3], skl[k - i][l - j]);
                    }
                }
                skl[k][l] = [v[0] / w, v[1] / w, v[2] / w];
            }
        }
        Ok(skl)
    }

    /// The position with first and second partial derivatives.
    ///
    /// # Errors
    /// As [`BSplineSurface::eval`].
    pub fn eval_second(&self, u: f64, v: f64) -> Result<SurfaceDerivs<3>, NurbsError> {
        Ok(SurfaceDerivs::from_table(&self.eval_derivs(u, v, 2)?))
    }

    /// Inserts knots along `u` (see [`BSplineSurface::insert_knots_u`]); the surface is
    /// unchanged.
    ///
    /// # Errors
    /// As [`BSplineSurface::insert_knots_u`].
    pub fn insert_knots_u(&mut self, ts: &[f64]) -> Result<(), NurbsError> {
        let mut h = self.homogeneous.clone();
        h.insert_knots_u(ts)?;
        *self = Self::from_homogeneous(h)?;
        Ok(())
    }

    /// Inserts knots along `v` (see [`BSplineSurface::insert_knots_v`]).
    ///
    /// # Errors
    /// As [`BSplineSurface::insert_knots_v`].
    pub fn insert_knots_v(&mut self, ts: &[f64]) -> Result<(), NurbsError> {
        let mut h = self.homogeneous.clone();
        h.insert_knots_v(ts)?;
        *self = Self::from_homogeneous(h)?;
        Ok(())
    }

    /// Inserts the midpoint of every non-zero knot interval in both directions (see
    /// [`BSplineSurface::insert_midpoints`]).
    ///
    /// # Errors
    /// As [`BSplineSurface::insert_midpoints`].
    pub fn insert_midpoints(&mut self) -> Result<(), NurbsError> {
        let mut h = self.homogeneous.clone();
        h.insert_midpoints()?;
        *self = Self::from_homogeneous(h)?;
        Ok(())
    }
}

/// Pascal's triangle `bin[n][k] = C(n, k)`, `0 ≤ k ≤ n ≤ order`.
fn binomials(order: usize) -> Vec<Vec<f64>> {
    let mut bin = vec![vec![0.0; order + 1]; order + 1];
    for n in 0..=order {
        bin[n][0] = 1.0;
        for k in 1..=n {
            bin[n][k] = bin[n - 1][k - 1] + if k < n { bin[n - 1][k] } else { 0.0 };
        }
    }
    bin
}
