//! Rational (NURBS) input for blending and hole filling: every patch and curve is handled as
//! its homogeneous B-spline, whose control points are `(w x, w y, w z, w)` (a polynomial one
//! has `w = 1`), and the control meshes carry the weights as [`VertexWeight`] tags, so that
//! non-uniform Catmull-Clark refines them in homogeneous coordinates as [`crate::nonuniform`]
//! does.
//!
//! # Why the methods carry over
//! A NURBS patch or curve is the central projection `(X, w) ↦ X / w` of its homogeneous
//! B-spline, and on a regular grid one NURSS step of homogeneous points is knot insertion
//! into that B-spline (Sederberg, Zheng, Sewell & Sabin, "Non-uniform recursive subdivision
//! surfaces", SIGGRAPH 1998, §3, applied coordinate by coordinate). So every statement the
//! methods prove for polynomial input holds for the homogeneous B-splines, and projection
//! keeps it: the blend's limit and the patch agree in position and first and second
//! derivatives in `R⁴` along the boundary, hence after projection (a smooth map where
//! `w > 0`); the fill's boundary row is the refined homogeneous control polygon of the
//! boundary curve, whose projection is the NURBS curve.
//!
//! # Points the constructions add
//! Control points taken from the input keep their homogeneous coordinates. A point that a
//! construction places (the blend's phantom row and gap columns, the fill's inner layers and
//! centre, the extension layer) is placed by the same formula as for polynomial input, on
//! the Cartesian points, and gets a positive weight: the mean of the weights of the points
//! the formula reads (blend), or the mean weight of the boundary's control points (fill).
//! Such points only shape the inside of the surface, never what is shared with the input;
//! with all weights 1 every weight is exactly 1 and the result is the polynomial one, bit for
//! bit.

use std::borrow::Cow;

use super::BlendError;
use crate::mesh::{PolyMesh, VertexWeight};
use crate::nurbs::{BSplineCurve, BSplineSurface, Curve, NurbsCurve, NurbsSurface, Surface};

/// A homogeneous point `(w x, w y, w z, w)`.
pub(crate) type H = [f64; 4];

/// The Cartesian point of a homogeneous one, `(x, y, z) / w` (exact for `w = 1`).
pub(crate) fn cart(p: &H) -> [f64; 3] {
    [p[0] / p[3], p[1] / p[3], p[2] / p[3]]
}

/// The homogeneous point of Cartesian `p` with weight `w`.
pub(crate) fn weighted(p: [f64; 3], w: f64) -> H {
    [w * p[0], w * p[1], w * p[2], w]
}

/// A bicubic patch as blending and hole filling read it: its homogeneous B-spline surface.
/// Implemented for polynomial patches ([`BSplineSurface<3>`], weights 1), rational ones
/// ([`NurbsSurface`]) and either ([`Surface`]).
pub trait Patch {
    /// The homogeneous B-spline surface `(w P, w)` (`w = 1` for a polynomial patch).
    fn homogeneous(&self) -> Cow<'_, BSplineSurface<4>>;
}

impl Patch for BSplineSurface<3> {
    fn homogeneous(&self) -> Cow<'_, BSplineSurface<4>> {
        let points = self.points().iter().map(|&p| weighted(p, 1.0)).collect();
        Cow::Owned(
            BSplineSurface::new(self.knots_u().clone(), self.knots_v().clone(), points)
                .expect("the same knots and as many points as a valid surface"),
        )
    }
}

impl Patch for NurbsSurface {
    fn homogeneous(&self) -> Cow<'_, BSplineSurface<4>> {
        Cow::Borrowed(NurbsSurface::homogeneous(self))
    }
}

impl Patch for Surface {
    fn homogeneous(&self) -> Cow<'_, BSplineSurface<4>> {
        match self {
            Surface::BSpline(s) => Patch::homogeneous(s),
            Surface::Nurbs(s) => Patch::homogeneous(s),
        }
    }
}

/// A boundary curve as hole filling reads it: its homogeneous B-spline curve. Implemented
/// for [`BSplineCurve<3>`] (weights 1), [`NurbsCurve`] and [`Curve`].
pub trait BoundaryCurve {
    /// The homogeneous B-spline curve `(w P, w)` (`w = 1` for a polynomial curve).
    fn homogeneous(&self) -> Cow<'_, BSplineCurve<4>>;
}

impl BoundaryCurve for BSplineCurve<3> {
    fn homogeneous(&self) -> Cow<'_, BSplineCurve<4>> {
        let points = self.points().iter().map(|&p| weighted(p, 1.0)).collect();
        Cow::Owned(
            BSplineCurve::new(self.knots().clone(), points)
                .expect("the same knots and as many points as a valid curve"),
        )
    }
}

impl BoundaryCurve for NurbsCurve {
    fn homogeneous(&self) -> Cow<'_, BSplineCurve<4>> {
        Cow::Borrowed(NurbsCurve::homogeneous(self))
    }
}

impl BoundaryCurve for Curve {
    fn homogeneous(&self) -> Cow<'_, BSplineCurve<4>> {
        match self {
            Curve::BSpline(c) => BoundaryCurve::homogeneous(c),
            Curve::Nurbs(c) => BoundaryCurve::homogeneous(c),
        }
    }
}

/// The curve of homogeneous `c`: polynomial when every weight is 1, else rational.
///
/// # Errors
/// [`BlendError::Nurbs`] for a weight that is not positive (none from the methods).
pub(crate) fn curve_of(c: BSplineCurve<4>) -> Result<Curve, BlendError> {
    if c.points().iter().all(|p| p[3] == 1.0) {
        let points = c.points().iter().map(cart).collect();
        Ok(Curve::BSpline(BSplineCurve::new(
            c.knots().clone(),
            points,
        )?))
    } else {
        Ok(Curve::Nurbs(NurbsCurve::from_homogeneous(c)?))
    }
}

/// The surface of homogeneous `s`: polynomial when every weight is 1, else rational.
///
/// # Errors
/// [`BlendError::Nurbs`] for a weight that is not positive (none from the methods).
pub(crate) fn surface_of(s: BSplineSurface<4>) -> Result<Surface, BlendError> {
    if s.points().iter().all(|p| p[3] == 1.0) {
        let points = s.points().iter().map(cart).collect();
        let (u, v) = (s.knots_u().clone(), s.knots_v().clone());
        Ok(Surface::BSpline(BSplineSurface::new(u, v, points)?))
    } else {
        Ok(Surface::Nurbs(NurbsSurface::from_homogeneous(s)?))
    }
}

/// A mesh of `faces` on Cartesian `positions` with per-vertex `weights` (tagged only when
/// some weight is not 1).
///
/// # Errors
/// [`BlendError::Mesh`] for bad faces or coordinates.
pub(crate) fn weighted_mesh<F: AsRef<[u32]>>(
    positions: Vec<[f64; 3]>,
    weights: &[f64],
    faces: &[F],
) -> Result<PolyMesh, BlendError> {
    let mut mesh = PolyMesh::from_faces(positions, faces)?;
    mesh.knots.weights = VertexWeight::tags(weights);
    Ok(mesh)
}

/// The weight of every vertex of `mesh` (untagged: 1).
pub(crate) fn mesh_weights(mesh: &PolyMesh) -> Vec<f64> {
    crate::nonuniform::vertex_weights(mesh)
}

/// The mean of `weights` (their sum divided by their count: exactly 1 when all are 1).
pub(crate) fn mean(weights: impl IntoIterator<Item = f64>) -> f64 {
    let (sum, count) = weights
        .into_iter()
        .fold((0.0, 0usize), |(s, n), w| (s + w, n + 1));
    if count == 0 {
        1.0
    } else {
        sum / count as f64
    }
}
