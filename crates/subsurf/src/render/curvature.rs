//! Curvature of the exact limit surface, from its first and second derivatives, and the
//! colour maps that show it.
//!
//! With `S` the surface, `n = Sᵤ × Sᵥ / |Sᵤ × Sᵥ|` its unit normal (pointing outward for
//! faces counter-clockwise seen from outside), the first fundamental form
//! `E = Sᵤ·Sᵤ, F = Sᵤ·Sᵥ, G = Sᵥ·Sᵥ` and the second `L = Sᵤᵤ·n, M = Sᵤᵥ·n, N = Sᵥᵥ·n`:
//!
//! - Gaussian curvature `K = (LN − M²) / (EG − F²)` (positive on a sphere or the outside
//!   of a torus, negative on a saddle; independent of the normal's direction);
//! - mean curvature `H = −(EN − 2FM + GL) / (2(EG − F²))`, signed so that a convex
//!   surface (a sphere, seen from outside with outward normals) has `H > 0`;
//! - largest absolute principal curvature `κ = |H| + √(H² − K)` (≥ 0).
//!
//! The surface is C² except at irregular corners (extraordinary vertices, where the
//! evaluator returns tangents and no second derivatives): there the curvature is unknown
//! (and, for Catmull-Clark, unbounded or zero in the limit); pictures fill such vertices
//! from their neighbours and the automatic colour range ignores outliers.

use super::scene::LimitGrid;
use super::RenderError;
use crate::geom;
use crate::limit::{Derivatives, SurfacePoint};
use crate::mesh::{Options, PolyMesh};
use crate::scheme::Scheme;

/// Which curvature to show.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurvatureKind {
    /// Gaussian curvature `K` (diverging colour map, blue < 0 < red).
    Gauss,
    /// Mean curvature `H` (diverging colour map, blue < 0 < red).
    Mean,
    /// Largest absolute principal curvature (sequential colour map).
    Max,
}

impl CurvatureKind {
    /// The name shown above the colour bar.
    pub fn name(self) -> &'static str {
        match self {
            Self::Gauss => "gauss",
            Self::Mean => "mean",
            Self::Max => "max",
        }
    }
}

/// Curvatures at one point. See the module docs for the definitions and signs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Curvature {
    /// Gaussian curvature `K`.
    pub gauss: f64,
    /// Mean curvature `H` (positive where convex).
    pub mean: f64,
    /// Largest absolute principal curvature.
    pub max: f64,
}

impl Curvature {
    /// The curvatures from exact derivatives; `None` where the first fundamental form is
    /// (nearly) singular or a value is not finite.
    pub fn from_derivatives(d: &Derivatives) -> Option<Self> {
        let n = d.normal();
        if n == [0.0; 3] {
            return None;
        }
        let (e, f, g) = (
            geom::dot(&d.du, &d.du),
            geom::dot(&d.du, &d.dv),
            geom::dot(&d.dv, &d.dv),
        );
        let (l, m, nn) = (
            geom::dot(&d.duu, &n),
            geom::dot(&d.duv, &n),
            geom::dot(&d.dvv, &n),
        );
        let det = e * g - f * f;
        if det.is_nan() || det <= 1e-12 * e * g {
            return None;
        }
        let gauss = (l * nn - m * m) / det;
        let mean = -(e * nn - 2.0 * f * m + g * l) / (2.0 * det);
        let max = mean.abs() + (mean * mean - gauss).max(0.0).sqrt();
        [gauss, mean, max]
            .iter()
            .all(|x| x.is_finite())
            .then_some(Self { gauss, mean, max })
    }

    /// The value of `kind`.
    pub fn get(&self, kind: CurvatureKind) -> f64 {
        match kind {
            CurvatureKind::Gauss => self.gauss,
            CurvatureKind::Mean => self.mean,
            CurvatureKind::Max => self.max,
        }
    }
}

/// A vertex of the sampling grid that pictures are drawn from, with its curvature.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvatureSample {
    /// Where it was evaluated.
    pub point: SurfacePoint,
    /// Position on the limit surface.
    pub position: [f64; 3],
    /// Unit normal.
    pub normal: [f64; 3],
    /// Curvature (`None` at irregular corners, where it is not defined).
    pub curvature: Option<Curvature>,
}

/// The exact curvature of the limit surface of `mesh` under `scheme` (Catmull-Clark or
/// Loop, see [`Render::scheme`](super::Render::scheme)) at the vertices that
/// [`render`](super::render) colours with [`Paint::Curvature`](super::Paint::Curvature) at
/// `rate`: every (sub-)face's `rate × rate` grid (`rate/2` on sub-faces of `n`-gons; a
/// Loop triangle's points `(a, b) / rate`, `a + b ≤ rate`), evaluated from that face.
///
/// # Errors
/// As [`tessellate`](crate::limit::tessellate), an invalid mesh, or
/// [`RenderError::Scheme`] for another scheme.
pub fn sample_curvature(
    mesh: &PolyMesh,
    options: &Options,
    scheme: Scheme,
    rate: u32,
) -> Result<Vec<CurvatureSample>, RenderError> {
    let g = LimitGrid::sample_with(mesh, options, scheme, rate, true, None, None)?;
    let curv = g.curvature.unwrap_or_default();
    Ok(g.points
        .iter()
        .zip(&g.positions)
        .zip(&g.normals)
        .zip(curv)
        .map(
            |(((&point, &position), &normal), curvature)| CurvatureSample {
                point,
                position,
                normal,
                curvature,
            },
        )
        .collect())
}

/// The automatic colour range of `values` (NaN ignored), robust to outliers: a bound `m`
/// on the magnitude is the 98th percentile of `|value|`, but at most 4 × the 75th
/// percentile (or the 90th, if larger), so that the thin bands of very high curvature
/// along semi-sharp creases and around extraordinary vertices do not wash out the rest.
/// For Gaussian and mean curvature the range is `(−m, m)`, so that 0 is white; for the
/// largest curvature it is from the 2nd percentile to `m`. Never empty.
pub(crate) fn robust_range(values: &[f64], kind: CurvatureKind) -> (f64, f64) {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    let lo = match kind {
        CurvatureKind::Max => percentile(&mut v, 0.02).unwrap_or(0.0),
        _ => 0.0,
    };
    let mut mag: Vec<f64> = v.iter().map(|x| x.abs()).collect();
    let p98 = percentile(&mut mag, 0.98).unwrap_or(1.0);
    let p90 = percentile(&mut mag, 0.90).unwrap_or(1.0);
    let p75 = percentile(&mut mag, 0.75).unwrap_or(1.0);
    let knee = p98.min((4.0 * p75).max(p90));
    let m = [knee, p98, 1.0]
        .into_iter()
        .find(|&m| m > 0.0)
        .unwrap_or(1.0);
    match kind {
        CurvatureKind::Gauss | CurvatureKind::Mean => (-m, m),
        CurvatureKind::Max => {
            if m - lo > 1e-9 * m.abs().max(lo.abs()) && m > lo {
                (lo, m)
            } else {
                let pad = (0.05 * m.abs()).max(1e-12);
                (lo - pad, m + pad)
            }
        }
    }
}

/// The `p`-quantile of `v` (sorted in place), `None` when empty.
fn percentile(v: &mut [f64], p: f64) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_unstable_by(f64::total_cmp);
    let i = ((v.len() - 1) as f64 * p).round() as usize;
    Some(v[i.min(v.len() - 1)])
}

/// The colour (sRGB, 0–1) of `value` for `kind` within `range`: blue–white–red
/// symmetric around 0 (white at 0, full colour at `max(|min|, |max|)`) for Gaussian and
/// mean curvature, a sequential dark-blue–green–yellow map from `min` to `max` for the
/// largest curvature. NaN is grey.
pub(crate) fn colour(kind: CurvatureKind, range: (f64, f64), value: f64) -> [f64; 3] {
    if value.is_nan() {
        return [0.6, 0.6, 0.6];
    }
    match kind {
        CurvatureKind::Gauss | CurvatureKind::Mean => {
            let m = range.0.abs().max(range.1.abs());
            diverging(if m > 0.0 { value / m } else { 0.0 })
        }
        CurvatureKind::Max => {
            let t = (value - range.0) / (range.1 - range.0);
            sequential(if t.is_finite() { t } else { 0.5 })
        }
    }
}

/// Blue (−1), white (0), red (+1), clamped; sRGB.
pub(crate) fn diverging(t: f64) -> [f64; 3] {
    const BLUE: [f64; 3] = [0.19, 0.32, 0.76];
    const WHITE: [f64; 3] = [0.97, 0.97, 0.97];
    const RED: [f64; 3] = [0.76, 0.11, 0.13];
    let t = t.clamp(-1.0, 1.0);
    let (end, s) = if t < 0.0 { (BLUE, -t) } else { (RED, t) };
    [0, 1, 2].map(|k| WHITE[k] + (end[k] - WHITE[k]) * s)
}

/// A perceptually ordered map from dark blue (0) through teal and green to yellow (1),
/// clamped (viridis' anchor colours); sRGB.
pub(crate) fn sequential(t: f64) -> [f64; 3] {
    const STOPS: [[f64; 3]; 6] = [
        [0.267, 0.005, 0.329],
        [0.231, 0.322, 0.545],
        [0.129, 0.569, 0.549],
        [0.369, 0.788, 0.384],
        [0.741, 0.875, 0.149],
        [0.993, 0.906, 0.144],
    ];
    let t = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let i = (t.floor() as usize).min(STOPS.len() - 2);
    let s = t - i as f64;
    [0, 1, 2].map(|k| STOPS[i][k] + (STOPS[i + 1][k] - STOPS[i][k]) * s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sphere of radius r parametrised by longitude/latitude, outward normal
    /// (u east, v north): K = 1/r², H = 1/r, κ = 1/r.
    #[test]
    fn sphere_curvatures() {
        let r: f64 = 2.0;
        let (u, v): (f64, f64) = (0.3, 0.2);
        let (cu, su, cv, sv) = (u.cos(), u.sin(), v.cos(), v.sin());
        let d = Derivatives {
            p: [r * cv * cu, r * cv * su, r * sv],
            du: [-r * cv * su, r * cv * cu, 0.0],
            dv: [-r * sv * cu, -r * sv * su, r * cv],
            duu: [-r * cv * cu, -r * cv * su, 0.0],
            duv: [r * sv * su, -r * sv * cu, 0.0],
            dvv: [-r * cv * cu, -r * cv * su, -r * sv],
        };
        // Outward: du × dv points along p.
        assert!(geom::dot(&d.normal(), &d.p) > 0.0);
        let c = Curvature::from_derivatives(&d).unwrap();
        assert!((c.gauss - 1.0 / (r * r)).abs() < 1e-12, "{c:?}");
        assert!((c.mean - 1.0 / r).abs() < 1e-12, "{c:?}");
        assert!((c.max - 1.0 / r).abs() < 1e-6, "{c:?}");
    }

    #[test]
    fn ranges_and_maps() {
        let v = [-3.0, -1.0, 0.0, 0.5, 2.0, f64::NAN];
        let (lo, hi) = robust_range(&v, CurvatureKind::Mean);
        assert_eq!(lo, -hi);
        assert!(hi > 0.0);
        let (lo, hi) = robust_range(&[1.0; 10], CurvatureKind::Max);
        assert!(lo < 1.0 && hi > 1.0);
        assert_eq!(diverging(0.0), [0.97; 3]);
        assert!(diverging(-1.0)[2] > diverging(-1.0)[0]);
        assert!(diverging(1.0)[0] > diverging(1.0)[2]);
        assert_eq!(
            colour(CurvatureKind::Gauss, (-1.0, 1.0), f64::NAN),
            [0.6; 3]
        );
        let dark = sequential(0.0).iter().sum::<f64>();
        let light = sequential(1.0).iter().sum::<f64>();
        assert!(dark < light);
    }
}
