//! Sampling curves and surfaces for display and checking: polylines and quad grids with a
//! fixed number of segments per knot span, so that sharp points (multiple knots) and span
//! boundaries are always samples.

use super::{Curve, KnotVector, NurbsError, Surface};
use crate::mesh::PolyMesh;

/// Parameters `t` that split every non-empty knot span of the domain into `per_span`
/// equal steps: the distinct knots in the domain `[t_p, t_N]` and the points between them,
/// in increasing order, both ends included.
///
/// ```
/// use subsurf::nurbs::{sample_parameters, KnotVector};
/// let k = KnotVector::new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 3.0, 3.0, 3.0])?;
/// assert_eq!(sample_parameters(&k, 2), vec![0.0, 0.5, 1.0, 2.0, 3.0]);
/// # Ok::<(), subsurf::nurbs::NurbsError>(())
/// ```
pub fn sample_parameters(knots: &KnotVector, per_span: usize) -> Vec<f64> {
    let per_span = per_span.max(1);
    let (a, b) = knots.domain();
    let mut breaks: Vec<f64> = knots
        .as_slice()
        .iter()
        .copied()
        .filter(|&t| t >= a && t <= b)
        .collect();
    breaks.dedup();
    let mut out = Vec::with_capacity((breaks.len().max(2) - 1) * per_span + 1);
    for w in breaks.windows(2) {
        for k in 0..per_span {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / per_span as f64);
        }
    }
    out.push(b);
    out
}

/// The number of [`sample_parameters`] of `knots` with `per_span` segments per knot span,
/// `(spans) · per_span + 1`, without making them (saturating).
pub fn sample_count(knots: &KnotVector, per_span: usize) -> u64 {
    let (a, b) = knots.domain();
    let mut spans = 0u64;
    let mut last = None;
    for &t in knots.as_slice().iter().filter(|&&t| t >= a && t <= b) {
        if last.is_some_and(|x| x != t) {
            spans += 1;
        }
        last = Some(t);
    }
    spans
        .max(1)
        .saturating_mul(per_span.max(1) as u64)
        .saturating_add(1)
}

impl Curve {
    /// The knot vector.
    pub fn knots(&self) -> &KnotVector {
        match self {
            Curve::BSpline(c) => c.knots(),
            Curve::Nurbs(c) => c.knots(),
        }
    }

    /// The parameter domain `[t_p, t_N]`.
    pub fn domain(&self) -> (f64, f64) {
        match self {
            Curve::BSpline(c) => c.domain(),
            Curve::Nurbs(c) => c.domain(),
        }
    }

    /// The Cartesian control points (of a NURBS curve: as given, without weights).
    pub fn points(&self) -> &[[f64; 3]] {
        match self {
            Curve::BSpline(c) => c.points(),
            Curve::Nurbs(c) => c.points(),
        }
    }

    /// The point at `t` (de Boor; rational: the projection of the homogeneous curve).
    ///
    /// # Errors
    /// [`NurbsError::ParameterOutOfDomain`] outside the domain.
    pub fn eval(&self, t: f64) -> Result<[f64; 3], NurbsError> {
        match self {
            Curve::BSpline(c) => c.eval(t),
            Curve::Nurbs(c) => c.eval(t),
        }
    }

    /// Points on the curve at [`sample_parameters`] (`per_span` segments per knot span).
    ///
    /// # Errors
    /// None in practice (parameters are in the domain); evaluation errors are passed on.
    pub fn polyline(&self, per_span: usize) -> Result<Vec<[f64; 3]>, NurbsError> {
        let knots = match self {
            Curve::BSpline(c) => c.knots(),
            Curve::Nurbs(c) => c.knots(),
        };
        sample_parameters(knots, per_span)
            .into_iter()
            .map(|t| match self {
                Curve::BSpline(c) => c.eval(t),
                Curve::Nurbs(c) => c.eval(t),
            })
            .collect()
    }
}

impl Surface {
    /// A quad grid on the surface at [`sample_parameters`] in both directions (`per_span`
    /// segments per knot span): vertex `i · n_v + j` is `S(u_i, v_j)`, and the quads are
    /// oriented so that their normal is `S_u × S_v`.
    ///
    /// # Errors
    /// Evaluation errors (none in practice).
    pub fn grid(&self, per_span: usize) -> Result<PolyMesh, NurbsError> {
        let (ku, kv) = match self {
            Surface::BSpline(s) => (s.knots_u(), s.knots_v()),
            Surface::Nurbs(s) => (s.knots_u(), s.knots_v()),
        };
        let (us, vs) = (
            sample_parameters(ku, per_span),
            sample_parameters(kv, per_span),
        );
        let mut positions = Vec::with_capacity(us.len() * vs.len());
        for &u in &us {
            for &v in &vs {
                positions.push(match self {
                    Surface::BSpline(s) => s.eval(u, v)?,
                    Surface::Nurbs(s) => s.eval(u, v)?,
                });
            }
        }
        let nv = vs.len() as u32;
        let mut faces = Vec::with_capacity((us.len() - 1) * (vs.len() - 1));
        for i in 0..us.len() as u32 - 1 {
            for j in 0..nv - 1 {
                let at = |i: u32, j: u32| i * nv + j;
                faces.push(vec![at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        PolyMesh::from_faces(positions, &faces).map_err(NurbsError::from)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::{BSplineSurface, NurbsCurve};

    #[test]
    fn a_circle_polyline_lies_on_the_circle() {
        let c = Curve::Nurbs(NurbsCurve::circle([0.0, 0.0, 0.0], 2.0).unwrap());
        let pts = c.polyline(8).unwrap();
        assert!(pts.len() > 8);
        for p in pts {
            assert!(((p[0] * p[0] + p[1] * p[1]).sqrt() - 2.0).abs() < 1e-14);
        }
    }

    #[test]
    fn a_bilinear_grid_has_the_corners_and_the_orientation() {
        let s = Surface::BSpline(
            BSplineSurface::new(
                KnotVector::new(1, vec![0.0, 0.0, 1.0, 1.0]).unwrap(),
                KnotVector::new(1, vec![0.0, 0.0, 1.0, 1.0]).unwrap(),
                vec![
                    [0.0, 0.0, 0.0],
                    [0.0, 1.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [1.0, 1.0, 0.0],
                ],
            )
            .unwrap(),
        );
        let m = s.grid(2).unwrap();
        assert_eq!(m.num_vertices(), 9);
        assert_eq!(m.num_faces(), 4);
        // First face (0,0) → (u+, 0) → (u+, v+) → (0, v+): counter-clockwise seen from +z.
        let f = m.face(0);
        let p = |k: usize| m.positions()[f[k] as usize];
        let (a, b, c) = (p(0), p(1), p(2));
        let cross_z = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        assert!(cross_z > 0.0);
    }
}
