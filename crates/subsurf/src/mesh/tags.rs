//! Sharpness tags: edge creases, vertex corners and holes.
//!
//! Sharpness is stored as `f32` on purpose: OpenSubdiv stores and decays sharpness in
//! single precision and computes its transitional (fractional) weights from those `f32`
//! values. Holding the same `f32` values is what makes our refined positions agree with
//! OpenSubdiv's to 1e-12 instead of 1e-8 on fractional creases.

/// Sharpness at or above which an edge or vertex is infinitely sharp (OpenSubdiv's
/// `Sdc::Crease::SHARPNESS_INFINITE`).
pub const SHARPNESS_INFINITE: f32 = 10.0;

/// A sharp edge between two vertices (OBJ `t crease 2/1/0 v0 v1 s`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crease {
    /// First end vertex (0-based).
    pub v0: u32,
    /// Second end vertex (0-based).
    pub v1: u32,
    /// Sharpness: 0 smooth, in (0, 10) semi-sharp (decays by one per level),
    /// ≥ 10 infinitely sharp.
    pub sharpness: f32,
}

/// A sharp vertex (OBJ `t corner 1/1/0 v s`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Corner {
    /// The vertex (0-based).
    pub vertex: u32,
    /// Sharpness, as for [`Crease::sharpness`].
    pub sharpness: f32,
}

/// Sharpness and hole tags of a mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tags {
    /// Sharp edges. An edge listed twice takes the last value (as in OpenSubdiv).
    pub creases: Vec<Crease>,
    /// Sharp vertices. A vertex listed twice takes the last value.
    pub corners: Vec<Corner>,
    /// Faces that are holes: they shape their neighbours but are not part of the surface.
    pub holes: Vec<u32>,
}

impl Tags {
    /// True when there are no creases, corners or holes.
    pub fn is_empty(&self) -> bool {
        self.creases.is_empty() && self.corners.is_empty() && self.holes.is_empty()
    }
}
