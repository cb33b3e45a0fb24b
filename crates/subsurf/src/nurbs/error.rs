//! [`NurbsError`]: every way a knot vector, curve, surface or JSON document can be invalid.

use crate::mesh::MeshError;

/// An invalid knot vector, control polygon or net, weight, parameter or JSON document.
///
/// Every variant names the offending index or value, so that a message can point at the
/// input; errors found while reading JSON are wrapped in [`NurbsError::Json`], which adds the
/// field (for example `knots_u[4]`).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NurbsError {
    /// The degree is not usable for the requested operation.
    #[error("degree {degree} is not allowed: {reason}")]
    BadDegree {
        /// The degree given.
        degree: usize,
        /// What was expected.
        reason: &'static str,
    },
    /// Fewer knots than a B-spline of this degree needs (`2 (p + 1)` for an open knot
    /// vector, two for a periodic one).
    #[error("{count} knots are too few for degree {degree}: at least {min} are needed")]
    TooFewKnots {
        /// The degree.
        degree: usize,
        /// Number of knots given.
        count: usize,
        /// Smallest valid number.
        min: usize,
    },
    /// A knot is NaN or infinite.
    #[error("knot {index} is not finite ({value})")]
    NonFiniteKnot {
        /// Index of the knot.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// Knot `index` is smaller than knot `index - 1`.
    #[error("knots decrease at index {index}: {previous} is followed by {value}")]
    DecreasingKnots {
        /// Index of the smaller knot.
        index: usize,
        /// The knot before it.
        previous: f64,
        /// The knot itself.
        value: f64,
    },
    /// A knot repeats more than `p + 1` times (a basis function would vanish).
    #[error("knot {knot} has multiplicity {multiplicity}, more than degree + 1 = {max}")]
    KnotMultiplicity {
        /// The repeated knot value.
        knot: f64,
        /// How often it occurs.
        multiplicity: usize,
        /// The largest multiplicity allowed (`p + 1`).
        max: usize,
    },
    /// The parameter domain `[t_p, t_n]` (or the period) has zero length.
    #[error("the parameter domain [{start}, {end}] is empty")]
    EmptyDomain {
        /// First knot of the domain.
        start: f64,
        /// Last knot of the domain.
        end: f64,
    },
    /// The number of knots does not match the number of control points: an open curve of
    /// degree `p` with `n` control points needs `n + p + 1` knots, a periodic one `n + 1`.
    #[error(
        "{points} control points of degree {degree} need {expected} knots, but {knots} were given"
    )]
    KnotCountMismatch {
        /// Number of knots given.
        knots: usize,
        /// Number of control points given.
        points: usize,
        /// The degree.
        degree: usize,
        /// Number of knots expected.
        expected: usize,
    },
    /// Fewer control points than the degree allows (at least `p + 1` for an open curve,
    /// `max(p, 2)` for a closed one), including an empty control polygon.
    #[error("{count} control points are too few: degree {degree} needs at least {min}")]
    TooFewPoints {
        /// Number of control points given.
        count: usize,
        /// The degree.
        degree: usize,
        /// Smallest valid number.
        min: usize,
    },
    /// The control net does not have `rows × columns` points.
    #[error(
        "a control net of {rows} × {columns} points was expected, but {count} points were given"
    )]
    NetSizeMismatch {
        /// Number of points given.
        count: usize,
        /// Points along `u`.
        rows: usize,
        /// Points along `v`.
        columns: usize,
    },
    /// A control point has a NaN or infinite coordinate.
    #[error("control point {index} has a non-finite coordinate")]
    NonFinitePoint {
        /// Index of the control point.
        index: usize,
    },
    /// A control point has a coordinate beyond [`crate::mesh::MAX_COORDINATE`] (1e75) in
    /// magnitude, the bound of every mesh (refinement and evaluation multiply coordinates).
    #[error("control point {index} has the coordinate {value:e}; coordinates must be below 1e75 in magnitude")]
    LargeCoordinate {
        /// Index of the control point.
        index: usize,
        /// The coordinate.
        value: f64,
    },
    /// A weight is zero, negative, NaN or infinite (rational curves need positive weights).
    #[error("weight {index} is {weight}; weights must be positive and finite")]
    NonPositiveWeight {
        /// Index of the weight.
        index: usize,
        /// Its value.
        weight: f64,
    },
    /// The number of weights differs from the number of control points.
    #[error("{weights} weights were given for {points} control points")]
    WeightCountMismatch {
        /// Number of weights.
        weights: usize,
        /// Number of control points.
        points: usize,
    },
    /// The parameter is NaN or outside the domain `[start, end]` of an open curve.
    #[error("parameter {t} is outside the domain [{start}, {end}]")]
    ParameterOutOfDomain {
        /// The parameter.
        t: f64,
        /// Start of the domain.
        start: f64,
        /// End of the domain.
        end: f64,
    },
    /// A geometric argument (a radius, a height, an angle) is out of range.
    #[error("{name} = {value} is not allowed: {reason}")]
    InvalidArgument {
        /// Name of the argument.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What was expected.
        reason: &'static str,
    },
    /// The control net is too large for `u32` mesh indices.
    #[error("the control net has {count} points, more than a mesh can index")]
    TooLarge {
        /// Number of control points.
        count: usize,
    },
    /// Building the control mesh failed (cannot happen for valid nets; kept for safety).
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The JSON text is not well-formed JSON.
    #[error("JSON syntax error at line {line}, column {column}: {message}")]
    JsonSyntax {
        /// 1-based line.
        line: usize,
        /// 1-based column (in characters).
        column: usize,
        /// What was wrong.
        message: String,
    },
    /// A JSON field is missing, has the wrong type, or holds an invalid value.
    #[error("JSON field `{field}`: {message}")]
    Json {
        /// Path of the field, for example `points[3][1]` or `knots_v`.
        field: String,
        /// What is wrong with it.
        message: String,
    },
}
