//! [`BlendError`]: why a mesh, patch or curve does not fit skirt removal, blending or hole
//! filling.

use crate::mesh::MeshError;
use crate::nonuniform::NurssError;
use crate::nurbs::NurbsError;

/// Errors of skirt-removal refinement, patch blending and hole filling. Errors about an
/// input patch or curve name it by its index in the input list (`patch 2`); the CLI replaces
/// the index by the file position and name.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BlendError {
    /// A mesh could not be built or refined.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Non-uniform refinement failed.
    #[error(transparent)]
    Nurss(#[from] NurssError),
    /// Catmull-Clark refinement failed.
    #[error("Catmull-Clark refinement failed: {0}")]
    Subdivide(String),
    /// A spline operation failed.
    #[error(transparent)]
    Nurbs(#[from] NurbsError),
    /// The refined mesh is not the one-step Catmull-Clark refinement of the parent.
    #[error("the refined mesh has {found} faces; a one-step refinement of the parent has {expected} (one per face corner)")]
    NotARefinement {
        /// Faces of a one-step refinement.
        expected: usize,
        /// Faces given.
        found: usize,
    },
    /// Skirt removal does not handle meshes with holes.
    #[error("skirt removal does not support hole faces (face {face} is a hole)")]
    Holes {
        /// The first hole face.
        face: u32,
    },
    /// Every face of the mesh is in its outer ring: nothing would be left.
    #[error("every face of the mesh touches its boundary: skirt removal would leave nothing")]
    NoInterior,
    /// A boundary vertex the extension layer cannot be built around.
    #[error("vertex {vertex} is on the boundary with {faces} faces; the extension layer needs boundary vertices with one face (a corner) or two")]
    BoundaryVertex {
        /// The vertex.
        vertex: u32,
        /// Its number of faces.
        faces: usize,
    },
    /// A tracked vertex grid left the mesh or stopped being a quad grid.
    #[error("vertex grid: {0}")]
    Grid(String),
    /// An input patch or curve has the wrong degree.
    #[error("{what} {index}: degree {degree} where the method needs bicubic / cubic (degree 3)")]
    Degree {
        /// `"patch"` or `"curve"`.
        what: &'static str,
        /// Index in the input list.
        index: usize,
        /// The degree found (the larger one if the two directions differ).
        degree: usize,
    },
    /// An input patch has too few rows or columns.
    #[error("patch {index}: {rows}×{columns} control points; blending needs at least 4×4 (three rows are shared with the blend mesh, the fourth is its extension layer)")]
    TooSmall {
        /// Index in the input list.
        index: usize,
        /// Rows (along `u`).
        rows: usize,
        /// Columns (along `v`).
        columns: usize,
    },
    /// A boundary curve with too few control points.
    #[error("curve {index}: {points} control points; a side of the hole needs at least 4")]
    ShortCurve {
        /// Index in the input list.
        index: usize,
        /// Its number of control points.
        points: usize,
    },
    /// A closed (periodic) or rational input, which the methods do not take.
    #[error("{what} {index} is {kind}: the method takes open, non-rational B-splines")]
    Unsupported {
        /// `"patch"` or `"curve"`.
        what: &'static str,
        /// Index in the input list.
        index: usize,
        /// `"closed"` or `"rational"`.
        kind: &'static str,
    },
    /// The knot vectors of a patch are not clamped where the method needs it.
    #[error("patch {index}: its {direction} knots are not clamped (end knots of multiplicity 4)")]
    NotClamped {
        /// Index in the input list.
        index: usize,
        /// `"u"` or `"v"`.
        direction: &'static str,
    },
    /// Too few patches or curves.
    #[error("{what}: got {found}, need {min} to {max}")]
    Count {
        /// What is counted.
        what: &'static str,
        /// Given.
        found: usize,
        /// Minimum.
        min: usize,
        /// Maximum.
        max: usize,
    },
    /// The boundary curves do not share corners.
    #[error("curve {index} does not share a corner with curve {next}: the nearest ends are {distance:.3e} apart (tolerance {tolerance:.1e})")]
    Corner {
        /// The curve (index in the input list).
        index: usize,
        /// The curve that should follow it around the hole.
        next: usize,
        /// Distance between the nearest end points.
        distance: f64,
        /// Allowed distance.
        tolerance: f64,
    },
    /// Two patches do not share the tangent plane at their common corner (needed for G1).
    #[error("patch {index} and patch {previous} do not share a tangent plane at their common corner (misfit {residual:.2e} of the control-point spacing), so no fill can meet both G1")]
    TangentPlane {
        /// The patch starting at the corner.
        index: usize,
        /// The patch ending there.
        previous: usize,
        /// How far from coplanar (relative).
        residual: f64,
    },
    /// A rational patch with unequal weights given to the G1 fill, whose construction
    /// ([Jiang et al.], Algorithm 2: the G1 conditions between adjacent Bézier patches) is for
    /// polynomial patches.
    #[error("patch {index} is rational with unequal weights: the G1 fill meets polynomial patches only (the fill without G1 takes rational patches)")]
    RationalG1 {
        /// Index in the input list.
        index: usize,
    },
    /// A bad option value.
    #[error("{0}")]
    Option(String),
}

impl BlendError {
    /// The index of the input patch or curve the error is about, if any.
    pub fn input_index(&self) -> Option<usize> {
        match *self {
            Self::Degree { index, .. }
            | Self::TooSmall { index, .. }
            | Self::ShortCurve { index, .. }
            | Self::Unsupported { index, .. }
            | Self::NotClamped { index, .. }
            | Self::Corner { index, .. }
            | Self::TangentPlane { index, .. }
            | Self::RationalG1 { index } => Some(index),
            _ => None,
        }
    }
}
