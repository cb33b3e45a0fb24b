//! Helpers shared by the property tests of one scheme (`properties.rs`) and across schemes
//! (`cross_scheme.rs`): proptest settings and strategies, small 3x3 algebra, tolerances.
#![allow(dead_code)]

use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use subsurf::mesh::{BoundaryInterpolation, CreaseMethod, Options, TriangleSubdivision};

/// SplitMix64, for the many small details of a generated mesh (jitter, face edits, tag
/// placement) from a seed that proptest draws (and shrinks).
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [-1, 1).
    pub fn signed(&mut self) -> f64 {
        2.0 * self.unit() - 1.0
    }
}

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
        ..Options::default()
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
