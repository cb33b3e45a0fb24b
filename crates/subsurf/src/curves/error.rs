//! Errors of curve interpolation.

/// What keeps a set of curves from being interpolated by symmetric zonal meshes. Every
/// variant names the curve (its [`label`](crate::nurbs::SourcedGeometry::label) or
/// `curve N`) and, where there is one, the control point.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum InterpolateError {
    /// No curve was given.
    #[error("no curves to interpolate")]
    NoCurves,
    /// The curve is not cubic (the method interpolates cubic B-spline / NURBS curves only).
    #[error("{curve}: degree {degree}; curve interpolation by symmetric zonal meshes needs cubic curves (degree 3)")]
    Degree {
        /// The curve.
        curve: String,
        /// Its degree.
        degree: usize,
    },
    /// A non-finite coordinate, or a curve too short for a zone.
    #[error("{curve}: {reason}")]
    BadCurve {
        /// The curve.
        curve: String,
        /// What is wrong.
        reason: String,
    },
    /// A bad option (width, side vector).
    #[error("{0}")]
    BadOption(String),
    /// More curve branches meet at one point than a joint polygon group can take.
    #[error("{branches} curve branches meet at ({x}, {y}, {z}) ({curves}); a joint polygon group takes at most 4 (two curves crossing, or up to four ending there), as in the paper's Corollary 1")]
    TooManyCurves {
        /// Number of branches (2 per curve passing through, 1 per curve ending there).
        branches: usize,
        /// The curves and control points.
        curves: String,
        /// The point.
        x: f64,
        /// The point.
        y: f64,
        /// The point.
        z: f64,
    },
    /// The curves sharing one control point do not make the two lines of a joint polygon
    /// group (Corollary 1): each line holds one curve passing through the point, or one or two
    /// ending there (two from opposite sides when each is the other's continuation, their
    /// neighbours symmetric about the point); see `super::crossing`.
    #[error("{count} curves share the point ({x}, {y}, {z}) ({curves}) and need {lines} lines through it; a joint polygon group has two (Corollary 1): each holds one curve passing through the point, or one or two ending there (two only from opposite sides, each continuing the other: neighbours symmetric about the point)")]
    SharedPoint {
        /// Number of curves.
        count: usize,
        /// Number of lines they need.
        lines: usize,
        /// The curves, how they meet the point, and their control points.
        curves: String,
        /// The point.
        x: f64,
        /// The point.
        y: f64,
        /// The point.
        z: f64,
    },
    /// A control point is not a vertex of the host mesh.
    #[error("{curve}, control point {index} at ({x}, {y}, {z}): no host vertex within {tol:e} of it; with a host mesh every control point must be a host vertex")]
    HostVertex {
        /// The curve.
        curve: String,
        /// The control point.
        index: usize,
        /// Its position.
        x: f64,
        /// Its position.
        y: f64,
        /// Its position.
        z: f64,
        /// The matching tolerance (a fraction of the host's size, see
        /// `super::host::HOST_TOLERANCE`).
        tol: f64,
    },
    /// The host mesh around a control point does not have the shape the embedding needs.
    #[error("{curve}, control point {index} at ({x}, {y}, {z}): {reason}")]
    Host {
        /// The curve.
        curve: String,
        /// The control point.
        index: usize,
        /// Its position.
        x: f64,
        /// Its position.
        y: f64,
        /// Its position.
        z: f64,
        /// What is wrong.
        reason: String,
    },
    /// The host mesh as a whole cannot take zones.
    #[error("host mesh: {0}")]
    HostMesh(String),
    /// The crossing does not have the shape a joint polygon group needs.
    #[error("{curve}, control point {index} at ({x}, {y}, {z}): {reason}")]
    Crossing {
        /// The curve.
        curve: String,
        /// The control point.
        index: usize,
        /// Its position.
        x: f64,
        /// Its position.
        y: f64,
        /// Its position.
        z: f64,
        /// What is wrong.
        reason: String,
    },
    /// The zones do not form a valid mesh (not expected for checked curves).
    #[error("the zone mesh is invalid: {0}")]
    Mesh(#[from] crate::mesh::MeshError),
    /// Two control polygons cross without sharing a control point there.
    #[error("{a} (edge {edge_a}) and {b} (edge {edge_b}) cross near ({x}, {y}, {z}) without a shared control point; curves may only cross at a control point of both (joint polygon group)")]
    UnsharedCrossing {
        /// One curve.
        a: String,
        /// Its control-polygon edge (from control point `edge_a` to `edge_a + 1`).
        edge_a: usize,
        /// The other curve.
        b: String,
        /// Its edge.
        edge_b: usize,
        /// Where.
        x: f64,
        /// Where.
        y: f64,
        /// Where.
        z: f64,
    },
}
