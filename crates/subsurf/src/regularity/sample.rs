//! Ground truth: the exact limit surface ([`LimitSurface`]) sampled densely, per face.
//!
//! Face `f` is sampled at `u = i/(N−1)`, `v = j/(N−1)` (`i, j = 0 … N−1`, corners and
//! edges included). The measured value at a sample is the *sine of the angle* between the
//! tangents, `s = (S_u × S_v) / (|S_u| |S_v|)`: planar, the signed determinant times the
//! mesh's orientation sign (so a fold is negative); spatial, the length of the normalised
//! cross product. A sample is **not regular** when `s ≤` [`SINE_TOLERANCE`] or a tangent
//! is shorter than [`LENGTH_TOLERANCE`] times the bounding-box diagonal (it vanishes up to
//! rounding). Exactly at an irregular corner (extraordinary, or an irregular boundary
//! vertex) the evaluator returns tangent directions rather than parametric derivatives:
//! that sample measures the tangent plane (geometric regularity), not the parametric
//! Jacobian, which may tend to zero there (at an edge-only corner it does, linearly).

use rayon::prelude::*;

use super::cone::Dimension;
use super::exact::Sign;
use crate::limit::{EvalError, LimitSurface};

/// A sample whose tangents make an angle with sine at most this is counted as singular.
pub(crate) const SINE_TOLERANCE: f64 = 1e-10;
/// A tangent shorter than this times the bounding-box diagonal is counted as zero.
pub(crate) const LENGTH_TOLERANCE: f64 = 1e-12;

/// One sample of the limit surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Face.
    pub face: u32,
    /// Parameter `u`.
    pub u: f64,
    /// Parameter `v`.
    pub v: f64,
    /// The sine measure of the module docs (negative: a fold, in the plane).
    pub value: f64,
}

/// The sampled verdict on one face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sampled {
    /// Every sample is regular; `min` is the one with the smallest value.
    Regular {
        /// The least regular sample.
        min: Sample,
    },
    /// A sample is singular (or, in the plane, folded): the least regular one.
    NotRegular {
        /// The offending sample.
        at: Sample,
    },
}

impl Sampled {
    /// Whether every sample was regular.
    pub fn is_regular(&self) -> bool {
        matches!(self, Self::Regular { .. })
    }

    /// The least regular sample.
    pub fn worst(&self) -> Sample {
        match *self {
            Self::Regular { min } | Self::NotRegular { at: min } => min,
        }
    }
}

/// The sine measure at one point from the tangents `du`, `dv`; `scale` is the bounding-box
/// diagonal and `orientation` the planar mesh's sign.
pub(crate) fn measure(
    du: &[f64; 3],
    dv: &[f64; 3],
    dim: Dimension,
    orientation: Sign,
    scale: f64,
) -> (f64, bool) {
    let len = |a: &[f64; 3]| match dim {
        Dimension::Planar => a[0].hypot(a[1]),
        Dimension::Spatial => a[0].hypot(a[1]).hypot(a[2]),
    };
    let (lu, lv) = (len(du), len(dv));
    if lu == 0.0 || lv == 0.0 {
        return (0.0, false);
    }
    let a = [du[0] / lu, du[1] / lu, du[2] / lu];
    let b = [dv[0] / lv, dv[1] / lv, dv[2] / lv];
    let s = match dim {
        Dimension::Planar => {
            let det = a[0] * b[1] - a[1] * b[0];
            if orientation == Sign::Negative {
                -det
            } else {
                det
            }
        }
        Dimension::Spatial => {
            let c = [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ];
            c[0].hypot(c[1]).hypot(c[2])
        }
    };
    let tiny = LENGTH_TOLERANCE * scale;
    (s, s > SINE_TOLERANCE && lu > tiny && lv > tiny)
}

/// Samples `faces` of `surface` on an `n × n` grid each (`n ≥ 2`); `None` for faces
/// without a surface (holes) or that are not quads.
pub(crate) fn sample_faces(
    surface: &LimitSurface,
    faces: &[u32],
    n: usize,
    dim: Dimension,
    orientation: Sign,
    scale: f64,
) -> Result<Vec<Option<Sampled>>, EvalError> {
    let n = n.max(2);
    faces
        .par_iter()
        .map(|&f| {
            let fi = f as usize;
            if surface.num_subfaces(fi) != 1 || !surface.has_surface(fi) {
                return Ok(None);
            }
            let mut worst: Option<(Sample, bool)> = None;
            for i in 0..n {
                for j in 0..n {
                    let (u, v) = (i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64);
                    let d = surface.eval(f, u, v)?;
                    let (value, ok) = measure(&d.du, &d.dv, dim, orientation, scale);
                    let s = Sample {
                        face: f,
                        u,
                        v,
                        value,
                    };
                    let replace = match worst {
                        None => true,
                        Some((w, wok)) => (wok && !ok) || (wok == ok && value < w.value),
                    };
                    if replace {
                        worst = Some((s, ok));
                    }
                }
            }
            Ok(worst.map(|(s, ok)| {
                if ok {
                    Sampled::Regular { min: s }
                } else {
                    Sampled::NotRegular { at: s }
                }
            }))
        })
        .collect()
}
