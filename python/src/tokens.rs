//! USD's tokens for the scheme and its options (and subsurf's own schemes), both ways.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use subsurf::mesh::{
    BoundaryInterpolation, CreaseMethod, FaceVaryingInterpolation, TriangleSubdivision,
};
use subsurf::scheme::Adjustable;
use subsurf::{Mixed, Scheme};

use crate::error;

/// The scheme of a token: USD's three, and subsurf's shape-adjustable Catmull-Clark
/// (`"adjustable"`: `c` for the first `adjust_steps` levels, then Catmull-Clark) and
/// non-uniform Catmull-Clark (`"nurss"`, with knot intervals).
pub(crate) fn scheme_of(token: &str, c: f64, adjust_steps: u32) -> PyResult<Scheme> {
    match token {
        "catmullClark" => Ok(Scheme::CatmullClark),
        "loop" => Ok(Scheme::Loop),
        "bilinear" => Ok(Scheme::Bilinear),
        "adjustable" => Ok(Scheme::Adjustable(Mixed {
            scheme: Adjustable::new(c).map_err(error)?,
            steps: adjust_steps,
        })),
        "nurss" => Ok(Scheme::Nurss),
        _ => Err(PyValueError::new_err(format!(
            "scheme must be \"catmullClark\", \"loop\", \"bilinear\", \"adjustable\" or \
             \"nurss\", not {token:?}"
        ))),
    }
}

pub(crate) fn scheme_token(scheme: Scheme) -> &'static str {
    match scheme {
        Scheme::Loop => "loop",
        Scheme::Bilinear => "bilinear",
        Scheme::Adjustable(_) => "adjustable",
        Scheme::Nurss => "nurss",
        _ => "catmullClark",
    }
}

pub(crate) fn boundary_of(token: &str) -> PyResult<BoundaryInterpolation> {
    match token {
        "none" => Ok(BoundaryInterpolation::None),
        "edgeOnly" => Ok(BoundaryInterpolation::EdgeOnly),
        "edgeAndCorner" => Ok(BoundaryInterpolation::EdgeAndCorner),
        _ => Err(PyValueError::new_err(format!(
            "interpolate_boundary must be \"none\", \"edgeOnly\" or \"edgeAndCorner\", not \
             {token:?}"
        ))),
    }
}

pub(crate) fn boundary_token(b: BoundaryInterpolation) -> &'static str {
    match b {
        BoundaryInterpolation::None => "none",
        BoundaryInterpolation::EdgeOnly => "edgeOnly",
        BoundaryInterpolation::EdgeAndCorner => "edgeAndCorner",
    }
}

pub(crate) const FVAR_TOKENS: [(&str, FaceVaryingInterpolation); 6] = [
    ("none", FaceVaryingInterpolation::None),
    ("cornersOnly", FaceVaryingInterpolation::CornersOnly),
    ("cornersPlus1", FaceVaryingInterpolation::CornersPlus1),
    ("cornersPlus2", FaceVaryingInterpolation::CornersPlus2),
    ("boundaries", FaceVaryingInterpolation::Boundaries),
    ("all", FaceVaryingInterpolation::All),
];

pub(crate) fn fvar_of(token: &str) -> PyResult<FaceVaryingInterpolation> {
    FVAR_TOKENS
        .iter()
        .find(|(t, _)| *t == token)
        .map(|&(_, m)| m)
        .ok_or_else(|| {
            PyValueError::new_err(format!(
                "face_varying_linear_interpolation must be one of \"none\", \"cornersOnly\", \
                 \"cornersPlus1\", \"cornersPlus2\", \"boundaries\", \"all\", not {token:?}"
            ))
        })
}

pub(crate) fn fvar_token(m: FaceVaryingInterpolation) -> &'static str {
    FVAR_TOKENS
        .iter()
        .find(|(_, x)| *x == m)
        .map_or("all", |&(t, _)| t)
}

pub(crate) fn crease_method_of(token: &str) -> PyResult<CreaseMethod> {
    match token {
        "uniform" => Ok(CreaseMethod::Uniform),
        "chaikin" => Ok(CreaseMethod::Chaikin),
        _ => Err(PyValueError::new_err(format!(
            "crease_method must be \"uniform\" or \"chaikin\", not {token:?}"
        ))),
    }
}

pub(crate) fn triangle_rule_of(token: &str) -> PyResult<TriangleSubdivision> {
    match token {
        "catmullClark" => Ok(TriangleSubdivision::Catmark),
        "smooth" => Ok(TriangleSubdivision::Smooth),
        _ => Err(PyValueError::new_err(format!(
            "triangle_subdivision_rule must be \"catmullClark\" or \"smooth\", not {token:?}"
        ))),
    }
}
