//! [`BSplineSurface`]: tensor-product B-spline surfaces of any degrees, each direction open
//! or closed.
//!
//! `S(u, v) = Σ_i Σ_j N_{i,p}(u) N_{j,q}(v) P_{i,j}` (The NURBS Book eq. 3.11), evaluated
//! with A3.5, differentiated with A3.6 (`∂^{k+l} S / ∂u^k ∂v^l = Σ_i Σ_j N^{(k)}_{i,p}(u)
//! N^{(l)}_{j,q}(v) P_{i,j}`, eq. 3.17), refined by knot insertion along `u` (every column
//! `P_{·,j}` is a curve) or `v` (every row `P_{i,·}`), §5.3.

use super::basis::{basis_into, ders_basis};
use super::insert::refine;
use super::vecn::{axpy, is_finite, with_scratch};
use super::{KnotVector, NurbsError};

/// A tensor-product B-spline surface in `D` dimensions: knots along `u` (degree `p`, `nu`
/// distinct control points) and `v` (degree `q`, `nv` points), and the control net
/// `P_{i,j}` stored row by row, `points[i · nv + j]` (`i` along `u`, `j` along `v`). A
/// direction with periodic knots is closed: its indices wrap around.
///
/// ```
/// use subsurf::nurbs::{BSplineSurface, KnotVector};
/// // A bilinear patch.
/// let k = KnotVector::new(1, vec![0.0, 0.0, 1.0, 1.0])?;
/// let s = BSplineSurface::new(k.clone(), k, vec![[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 1.0]])?;
/// assert_eq!(s.eval(0.5, 0.5)?, [0.5, 0.5, 0.25]);
/// let d = s.eval_second(0.5, 0.5)?;
/// assert_eq!(d.duv, [0.0, 0.0, 1.0]);
/// # Ok::<(), subsurf::nurbs::NurbsError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct BSplineSurface<const D: usize> {
    u: KnotVector,
    v: KnotVector,
    points: Vec<[f64; D]>,
}

/// A surface point with its first and second partial derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceDerivs<const D: usize> {
    /// Position `S`.
    pub p: [f64; D],
    /// `∂S/∂u`.
    pub du: [f64; D],
    /// `∂S/∂v`.
    pub dv: [f64; D],
    /// `∂²S/∂u²`.
    pub duu: [f64; D],
    /// `∂²S/∂u∂v`.
    pub duv: [f64; D],
    /// `∂²S/∂v²`.
    pub dvv: [f64; D],
}

impl<const D: usize> SurfaceDerivs<D> {
    /// Picks the entries of a table `skl[k][l] = ∂^{k+l}S/∂u^k∂v^l` with `k + l ≤ 2`.
    pub(crate) fn from_table(skl: &[Vec<[f64; D]>]) -> Self {
        Self {
            p: skl[0][0],
            du: skl[1][0],
            dv: skl[0][1],
            duu: skl[2][0],
            duv: skl[1][1],
            dvv: skl[0][2],
        }
    }
}

impl<const D: usize> BSplineSurface<D> {
    /// A surface from its knot vectors and control net (`points[i · nv + j]`).
    ///
    /// # Errors
    /// [`NurbsError::NetSizeMismatch`] unless there are
    /// `u.num_points() × v.num_points()` points; [`NurbsError::NonFinitePoint`],
    /// [`NurbsError::LargeCoordinate`] (flat index).
    pub fn new(u: KnotVector, v: KnotVector, points: Vec<[f64; D]>) -> Result<Self, NurbsError> {
        let (rows, columns) = (u.num_points(), v.num_points());
        if rows.checked_mul(columns) != Some(points.len()) {
            return Err(NurbsError::NetSizeMismatch {
                count: points.len(),
                rows,
                columns,
            });
        }
        if let Some(index) = points.iter().position(|p| !is_finite(p)) {
            return Err(NurbsError::NonFinitePoint { index });
        }
        super::curve::check_magnitude(&points)?;
        Ok(Self { u, v, points })
    }

    /// The knot vector along `u`.
    pub fn knots_u(&self) -> &KnotVector {
        &self.u
    }

    /// The knot vector along `v`.
    pub fn knots_v(&self) -> &KnotVector {
        &self.v
    }

    /// The degrees `(p, q)`.
    pub fn degrees(&self) -> (usize, usize) {
        (self.u.degree(), self.v.degree())
    }

    /// The numbers of distinct control points `(nu, nv)`.
    pub fn size(&self) -> (usize, usize) {
        (self.u.num_points(), self.v.num_points())
    }

    /// The control net, `points[i · nv + j] = P_{i,j}`.
    pub fn points(&self) -> &[[f64; D]] {
        &self.points
    }

    /// The control point `P_{i,j}`, if it exists.
    pub fn point(&self, i: usize, j: usize) -> Option<&[f64; D]> {
        let (nu, nv) = self.size();
        (i < nu && j < nv).then(|| &self.points[i * nv + j])
    }

    /// The parameter domains `([u_start, u_end], [v_start, v_end])`.
    pub fn domain(&self) -> ((f64, f64), (f64, f64)) {
        (self.u.domain(), self.v.domain())
    }

    /// Whether the surface is closed along `u` and along `v` (periodic knots).
    pub fn is_closed(&self) -> (bool, bool) {
        (self.u.is_periodic(), self.v.is_periodic())
    }

    /// The position `S(u, v) = Σ_k N_{ku−p+k,p}(u) Σ_l N_{kv−q+l,q}(v) P_{ku−p+k, kv−q+l}`
    /// over the spans `ku`, `kv` (The NURBS Book A3.5).
    ///
    /// # Errors
    /// [`NurbsError::ParameterOutOfDomain`] for a parameter outside the domain of an open
    /// direction (closed directions wrap), or not finite.
    pub fn eval(&self, u: f64, v: f64) -> Result<[f64; D], NurbsError> {
        let (u, v) = (self.u.parameter(u)?, self.v.parameter(v)?);
        let (p, q) = self.degrees();
        let (ku, kv) = (self.u.span_in_domain(u), self.v.span_in_domain(v));
        Ok(with_scratch(3 * (p + 1), 0.0, |bu| {
            let (nu, rest) = bu.split_at_mut(p + 1);
            let (l, r) = rest.split_at_mut(p + 1);
            basis_into(self.u.as_slice(), p, ku, u, nu, l, r);
            with_scratch(3 * (q + 1), 0.0, |bv| {
                let (nv, rest) = bv.split_at_mut(q + 1);
                let (l, r) = rest.split_at_mut(q + 1);
                basis_into(self.v.as_slice(), q, kv, v, nv, l, r);
                let mut s = [0.0; D];
                for (a, &na) in nu.iter().enumerate() {
                    let mut row = [0.0; D];
                    for (b, &nb) in nv.iter().enumerate() {
                        axpy(&mut row, nb, &self.net(ku - p + a, kv - q + b));
                    }
                    axpy(&mut s, na, &row);
                }
                s
            })
        }))
    }

    /// All partial derivatives up to total order `order`: `skl[k][l] = ∂^{k+l}S/∂u^k∂v^l`
    /// for `k + l ≤ order` (entries with `k + l > order`, and derivatives above the degree,
    /// are zero), by The NURBS Book A3.6 with the basis derivatives of A2.3. At a knot the
    /// derivatives are those of the span starting there.
    ///
    /// # Errors
    /// As [`eval`](Self::eval).
    pub fn eval_derivs(
        &self,
        u: f64,
        v: f64,
        order: usize,
    ) -> Result<Vec<Vec<[f64; D]>>, NurbsError> {
        let (u, v) = (self.u.parameter(u)?, self.v.parameter(v)?);
        let (p, q) = self.degrees();
        let (ku, kv) = (self.u.span_in_domain(u), self.v.span_in_domain(v));
        let du = ders_basis(self.u.as_slice(), p, ku, u, order);
        let dv = ders_basis(self.v.as_slice(), q, kv, v, order);
        let mut skl = vec![vec![[0.0; D]; order + 1]; order + 1];
        let mut temp = vec![[0.0; D]; q + 1];
        for k in 0..=order.min(p) {
            for (s, t) in temp.iter_mut().enumerate() {
                *t = [0.0; D];
                for r in 0..=p {
                    axpy(t, du[k * (p + 1) + r], &self.net(ku - p + r, kv - q + s));
                }
            }
            for l in 0..=(order - k).min(q) {
                for (s, t) in temp.iter().enumerate() {
                    axpy(&mut skl[k][l], dv[l * (q + 1) + s], t);
                }
            }
        }
        Ok(skl)
    }

    /// The position with first and second partial derivatives
    /// ([`eval_derivs`](Self::eval_derivs) of order 2).
    ///
    /// # Errors
    /// As [`eval`](Self::eval).
    pub fn eval_second(&self, u: f64, v: f64) -> Result<SurfaceDerivs<D>, NurbsError> {
        Ok(SurfaceDerivs::from_table(&self.eval_derivs(u, v, 2)?))
    }

    /// Inserts the knots `ts` along `u` into every column `P_{·,j}` (knot refinement, The
    /// NURBS Book A5.4/A5.5); the surface is unchanged.
    ///
    /// # Errors
    /// [`NurbsError::ParameterOutOfDomain`], [`NurbsError::KnotMultiplicity`]; the surface is
    /// then unchanged.
    pub fn insert_knots_u(&mut self, ts: &[f64]) -> Result<(), NurbsError> {
        let (nu, nv) = self.size();
        let cols = (0..nv)
            .map(|j| (0..nu).map(|i| self.points[i * nv + j]).collect())
            .collect();
        let (knots, cols) = refine(&self.u, ts, cols)?;
        let nu2 = knots.num_points();
        let mut points = vec![[0.0; D]; nu2 * nv];
        for (j, col) in cols.iter().enumerate() {
            for (i, p) in col.iter().enumerate() {
                points[i * nv + j] = *p;
            }
        }
        self.u = knots;
        self.points = points;
        Ok(())
    }

    /// Inserts the knots `ts` along `v` into every row `P_{i,·}`; the surface is unchanged.
    ///
    /// # Errors
    /// As [`insert_knots_u`](Self::insert_knots_u).
    pub fn insert_knots_v(&mut self, ts: &[f64]) -> Result<(), NurbsError> {
        let nv = self.v.num_points();
        let rows = self.points.chunks(nv).map(<[_]>::to_vec).collect();
        let (knots, rows) = refine(&self.v, ts, rows)?;
        self.v = knots;
        self.points = rows.concat();
        Ok(())
    }

    /// Inserts the midpoint of every non-zero knot interval of both domains (one step of
    /// non-uniform subdivision of the control net; see [`KnotVector::midpoints`]).
    ///
    /// # Errors
    /// None in practice (see [`BSplineCurve::insert_midpoints`](super::BSplineCurve::insert_midpoints)).
    pub fn insert_midpoints(&mut self) -> Result<(), NurbsError> {
        let (mu, mv) = (self.u.midpoints(), self.v.midpoints());
        self.insert_knots_u(&mu)?;
        self.insert_knots_v(&mv)
    }

    /// Control point `(a, b)` of the unwrapped net (indices mod `nu`, `nv` in closed
    /// directions).
    #[inline]
    fn net(&self, a: usize, b: usize) -> [f64; D] {
        let (nu, nv) = self.size();
        let i = if a >= nu { a - nu } else { a };
        let j = if b >= nv { b - nv } else { b };
        self.points[i * nv + j]
    }
}
