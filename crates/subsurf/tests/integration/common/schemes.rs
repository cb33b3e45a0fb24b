//! Helpers shared by the property tests of one scheme (`properties.rs`) and across schemes
//! (`cross_scheme.rs`): proptest settings and strategies, small 3x3 algebra, tolerances.
#![allow(dead_code)]

use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use subsurf::mesh::{BoundaryInterpolation, CreaseMethod, Options, TriangleSubdivision};

pub type P3 = [f64; 3];
pub type Mat3 = [[f64; 3]; 3];

pub fn options_strategy() -> impl Strategy<Value = Options> {
    (0..3usize, any::<bool>(), any::<bool>()).prop_map(|(b, chaikin, smooth)| Options {
        boundary: [
            BoundaryInterpolation::None,
            BoundaryInterpolation::EdgeAndCorner,
            BoundaryInterpolation::EdgeOnly,
        ][b],
        crease_method: if chaikin {
            CreaseMethod::Chaikin
        } else {
            CreaseMethod::Uniform
        },
        triangles: if smooth {
            TriangleSubdivision::Smooth
        } else {
            TriangleSubdivision::Catmark
        },
    })
}

/// Proptest settings: `cases` random cases (`PROPTEST_CASES` overrides it), failures not
/// persisted to files.
pub fn config(cases: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(cases);
    ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

pub fn fail(msg: String) -> TestCaseError {
    TestCaseError::fail(msg)
}

pub fn mat_vec(a: &Mat3, x: &P3) -> P3 {
    let mut y = [0.0; 3];
    for r in 0..3 {
        y[r] = a[r][0] * x[0] + a[r][1] * x[1] + a[r][2] * x[2];
    }
    y
}

/// The size of a point set for relative tolerances: its largest coordinate magnitude (≥ 1).
pub fn scale_of(pts: &[P3]) -> f64 {
    pts.iter()
        .flat_map(|p| p.iter())
        .fold(1.0, |m: f64, c| m.max(c.abs()))
}
