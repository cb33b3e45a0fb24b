//! JSON input and output of curves and surfaces.
//!
//! # Schema
//! A curve (B-spline, or NURBS when `weights` is present):
//!
//! ```json
//! {
//!   "type": "bspline-curve",
//!   "degree": 3,
//!   "knots": [0, 0, 0, 0, 0.5, 1, 1, 1, 1],
//!   "points": [[0, 0, 0], [1, 2, 0], [2, 2, 0], [3, 1, 0], [4, 0, 0]],
//!   "weights": [1, 0.5, 1, 2, 1],
//!   "closed": false
//! }
//! ```
//!
//! | field | type | meaning |
//! |---|---|---|
//! | `type` | string | `"bspline-curve"` |
//! | `degree` | integer ≥ 1 | the degree `p` |
//! | `knots` | numbers, non-decreasing | open: all `n + p + 1` knots `t_0 … t_{n+p}`; closed: one period `u_0 … u_n` (`n + 1` knots, see [`KnotVector::periodic`]) |
//! | `points` | `[x, y, z]` arrays | the `n` (distinct) control points |
//! | `weights` | positive numbers, optional | one per point; present ⇒ rational (NURBS) |
//! | `closed` | boolean, optional (false) | periodic knots, points wrap around |
//!
//! A surface (tensor product; `i` along `u`, `j` along `v`):
//!
//! ```json
//! {
//!   "type": "bspline-surface",
//!   "degree_u": 1, "degree_v": 1,
//!   "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
//!   "points": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]],
//!   "weights": [[1, 1], [1, 2]],
//!   "closed_u": false, "closed_v": false
//! }
//! ```
//!
//! `points[i][j]` is `P_{i,j}` (`nu` rows of `nv` points), `weights[i][j]` its weight
//! (optional); `degree_*`, `knots_*`, `closed_*` are as for a curve, per direction.
//!
//! Unknown and duplicate fields are errors. Every error names the field (for example
//! `knots[4]` or `points[2][1]`) and, when reading text, its line and column
//! ([`NurbsError::Json`]); malformed JSON gives [`NurbsError::JsonSyntax`].
//!
//! # Exactness
//! [`Curve::from_json_str`] / [`Surface::from_json_str`] read numbers with a correctly
//! rounding parser, and [`Curve::to_json_string`] / [`Surface::to_json_string`] write the
//! shortest representation that reads back to the same `f64`, so a round trip is exact.
//! The text is compact and is what `serde_json` writes for the same fields, so documents
//! embed in other JSON tools; note that `serde_json`'s own float parser (without its
//! `float_roundtrip` feature) may be off by one unit in the last place.
//!
//! ```
//! use subsurf::nurbs::{Curve, NurbsCurve};
//! let c = Curve::Nurbs(NurbsCurve::circle([0.0, 0.0, 0.0], 2.0)?);
//! let text = c.to_json_string();
//! assert_eq!(Curve::from_json_str(&text)?, c);
//! let bad = text.replace("\"degree\":2", "\"degree\":-2");
//! let err = Curve::from_json_str(&bad).unwrap_err().to_string();
//! assert!(err.contains("`degree`"), "{err}");
//! # Ok::<(), subsurf::nurbs::NurbsError>(())
//! ```

use super::json_reader::{line_col, parse, Node, Value};
use super::{BSplineCurve, BSplineSurface, KnotVector, NurbsCurve, NurbsError, NurbsSurface};
use crate::json::{object, ToJson};

/// The `type` of a curve document.
pub const CURVE_TYPE: &str = "bspline-curve";
/// The `type` of a surface document.
pub const SURFACE_TYPE: &str = "bspline-surface";

/// A curve document (see the schema).
#[derive(Clone, Debug, PartialEq)]
pub struct CurveJson {
    /// The member `type`: always [`CURVE_TYPE`].
    pub kind: String,
    /// The degree `p`.
    pub degree: usize,
    /// All knots (open) or one period of knots (closed).
    pub knots: Vec<f64>,
    /// The distinct control points.
    pub points: Vec<[f64; 3]>,
    /// The weights, for a rational curve.
    pub weights: Option<Vec<f64>>,
    /// Whether the knots are periodic.
    pub closed: bool,
}

/// A surface document (see the schema).
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceJson {
    /// The member `type`: always [`SURFACE_TYPE`].
    pub kind: String,
    /// The degree along `u`.
    pub degree_u: usize,
    /// The degree along `v`.
    pub degree_v: usize,
    /// The knots along `u` (one period if closed).
    pub knots_u: Vec<f64>,
    /// The knots along `v` (one period if closed).
    pub knots_v: Vec<f64>,
    /// `points[i][j] = P_{i,j}`.
    pub points: Vec<Vec<[f64; 3]>>,
    /// `weights[i][j] = w_{i,j}`, for a rational surface.
    pub weights: Option<Vec<Vec<f64>>>,
    /// Whether the `u` knots are periodic.
    pub closed_u: bool,
    /// Whether the `v` knots are periodic.
    pub closed_v: bool,
}

/// A 3D curve read from or written to JSON: polynomial or rational.
#[derive(Clone, Debug, PartialEq)]
pub enum Curve {
    /// A B-spline curve (no `weights`).
    BSpline(BSplineCurve<3>),
    /// A NURBS curve (`weights` given).
    Nurbs(NurbsCurve),
}

/// A 3D tensor-product surface read from or written to JSON: polynomial or rational.
#[derive(Clone, Debug, PartialEq)]
pub enum Surface {
    /// A B-spline surface (no `weights`).
    BSpline(BSplineSurface<3>),
    /// A NURBS surface (`weights` given).
    Nurbs(NurbsSurface),
}

/// A curve or a surface, by the document's `type`.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// A `"bspline-curve"` document.
    Curve(Curve),
    /// A `"bspline-surface"` document.
    Surface(Surface),
}

/// A curve or surface read from a file, with a description of where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct SourcedGeometry {
    /// The curve or surface.
    pub geometry: Geometry,
    /// Its name (the OBJ `o`/`g` statement before it), if any.
    pub name: Option<String>,
    /// Where it is in the file, for messages: `curves.obj:12` (the `curv`/`surf` line) or
    /// `curves.json[2]` (the index in the JSON array; `[0]` for a single document).
    pub origin: String,
}

impl SourcedGeometry {
    /// `origin` and, when there is one, the name in quotes: `curves.obj:12 ("rim")`.
    pub fn label(&self) -> String {
        match &self.name {
            Some(n) if !n.is_empty() => format!("{} ({n:?})", self.origin),
            _ => self.origin.clone(),
        }
    }
}

/// Reads a curve or surface document, dispatching on its `type`.
///
/// # Errors
/// [`NurbsError::JsonSyntax`] or [`NurbsError::Json`] naming the field.
pub fn from_json_str(text: &str) -> Result<Geometry, NurbsError> {
    let root = parse(text)?;
    geometry_from_node(&Reader { text, root: &root })
}

/// Reads a file of several documents: either one curve or surface document, or an array
/// of them (`[{"type": "bspline-curve", ...}, {"type": "bspline-surface", ...}]`), as
/// written by [`to_json_string_all`]. The inputs of curve interpolation and patch blending
/// are such lists.
///
/// # Errors
/// [`NurbsError::JsonSyntax`] for malformed JSON; [`NurbsError::Json`] naming the field,
/// prefixed by the document's index in the array (for example `[2].knots[4]`).
pub fn from_json_str_all(text: &str) -> Result<Vec<Geometry>, NurbsError> {
    let root = parse(text)?;
    let items: Vec<&Node> = match &root.value {
        Value::Arr(items) => items.iter().collect(),
        _ => return geometry_from_node(&Reader { text, root: &root }).map(|g| vec![g]),
    };
    items
        .into_iter()
        .enumerate()
        .map(|(i, item)| {
            geometry_from_node(&Reader { text, root: item }).map_err(|e| match e {
                NurbsError::Json { field, message } => NurbsError::Json {
                    field: if field.is_empty() || field.starts_with('[') {
                        format!("[{i}]{field}")
                    } else {
                        format!("[{i}].{field}")
                    },
                    message,
                },
                other => other,
            })
        })
        .collect()
}

/// Writes several curves and surfaces as one JSON array (read back exactly by
/// [`from_json_str_all`]).
pub fn to_json_string_all(items: &[Geometry]) -> String {
    let parts: Vec<String> = items
        .iter()
        .map(|g| match g {
            Geometry::Curve(c) => c.to_json_string(),
            Geometry::Surface(s) => s.to_json_string(),
        })
        .collect();
    format!("[\n{}\n]\n", parts.join(",\n"))
}

/// One document, dispatching on its `type`.
fn geometry_from_node(r: &Reader<'_>) -> Result<Geometry, NurbsError> {
    let obj = r.object(r.root, "")?;
    match r.string(obj, "type")?.as_str() {
        CURVE_TYPE => Curve::from_node(r).map(Geometry::Curve),
        SURFACE_TYPE => Surface::from_node(r).map(Geometry::Surface),
        other => Err(r.error(
            "type",
            format!("expected \"{CURVE_TYPE}\" or \"{SURFACE_TYPE}\", got {other:?}"),
        )),
    }
}

impl Curve {
    /// The closed (periodic) curve that this open one is the unwrapped form of, if it is
    /// ([`BSplineCurve::periodic_form`], [`NurbsCurve::periodic_form`]).
    pub fn periodic_form(&self) -> Option<Self> {
        match self {
            Curve::BSpline(c) => c.periodic_form().map(Curve::BSpline),
            Curve::Nurbs(c) => c.periodic_form().map(Curve::Nurbs),
        }
    }

    /// Reads a curve document (see the schema); numbers are read exactly.
    ///
    /// # Errors
    /// [`NurbsError::JsonSyntax`] for malformed JSON; [`NurbsError::Json`] naming the field
    /// (and its line) for a missing, mistyped, unknown or invalid field.
    pub fn from_json_str(text: &str) -> Result<Self, NurbsError> {
        let root = parse(text)?;
        Self::from_node(&Reader { text, root: &root })
    }

    fn from_node(r: &Reader<'_>) -> Result<Self, NurbsError> {
        let obj = r.object(r.root, "")?;
        r.allow_only(
            obj,
            &["type", "degree", "knots", "points", "weights", "closed"],
        )?;
        let json = CurveJson {
            kind: r.string(obj, "type")?,
            degree: r.usize(obj, "degree")?,
            knots: r.numbers(r.get(obj, "knots")?, "knots")?,
            points: r.points(r.get(obj, "points")?, "points")?,
            weights: match r.find(obj, "weights") {
                Some(n) => Some(r.numbers(n, "weights")?),
                None => None,
            },
            closed: r.bool(obj, "closed")?,
        };
        Self::from_json(&json).map_err(|e| r.locate(e))
    }

    /// Builds the curve a [`CurveJson`] describes.
    ///
    /// # Errors
    /// [`NurbsError::Json`] naming the invalid field.
    pub fn from_json(j: &CurveJson) -> Result<Self, NurbsError> {
        if j.kind != CURVE_TYPE {
            return Err(json_error(
                "type",
                format!("expected \"{CURVE_TYPE}\", got {:?}", j.kind),
            ));
        }
        let knots = knot_vector(j.degree, &j.knots, j.closed)
            .map_err(|e| knot_error(e, "degree", "knots"))?;
        let flat = |i: usize| format!("[{i}]");
        match &j.weights {
            None => BSplineCurve::new(knots, j.points.clone()).map(Curve::BSpline),
            Some(w) => NurbsCurve::new(knots, j.points.clone(), w.clone()).map(Curve::Nurbs),
        }
        .map_err(|e| point_error(e, "knots", &flat))
    }

    /// The document describing this curve.
    pub fn to_json(&self) -> CurveJson {
        let (knots, points, weights) = match self {
            Curve::BSpline(c) => (c.knots(), c.points().to_vec(), None),
            Curve::Nurbs(c) => (c.knots(), c.points().to_vec(), Some(c.weights())),
        };
        CurveJson {
            kind: CURVE_TYPE.into(),
            degree: knots.degree(),
            knots: knots.period_knots().unwrap_or(knots.as_slice()).to_vec(),
            points,
            weights,
            closed: knots.is_periodic(),
        }
    }

    /// The curve as compact JSON text (exact: [`from_json_str`](Self::from_json_str) reads
    /// back an equal curve).
    pub fn to_json_string(&self) -> String {
        crate::json::to_string(&self.to_json())
    }
}

impl Surface {
    /// Reads a surface document (see the schema); numbers are read exactly.
    ///
    /// # Errors
    /// As [`Curve::from_json_str`].
    pub fn from_json_str(text: &str) -> Result<Self, NurbsError> {
        let root = parse(text)?;
        Self::from_node(&Reader { text, root: &root })
    }

    fn from_node(r: &Reader<'_>) -> Result<Self, NurbsError> {
        let obj = r.object(r.root, "")?;
        r.allow_only(
            obj,
            &[
                "type", "degree_u", "degree_v", "knots_u", "knots_v", "points", "weights",
                "closed_u", "closed_v",
            ],
        )?;
        let rows = r.array(r.get(obj, "points")?, "points")?;
        let mut points = Vec::with_capacity(rows.len());
        for (i, row) in rows.iter().enumerate() {
            let row = r.points(row, &format!("points[{i}]"))?;
            if i > 0 && row.len() != points.first().map_or(0, Vec::len) {
                return Err(r.error(
                    &format!("points[{i}]"),
                    format!(
                        "expected {} points, as in points[0], got {}",
                        points.first().map_or(0, Vec::len),
                        row.len()
                    ),
                ));
            }
            points.push(row);
        }
        let weights = match r.find(obj, "weights") {
            None => None,
            Some(n) => {
                let rows = r.array(n, "weights")?;
                let mut w = Vec::with_capacity(rows.len());
                for (i, row) in rows.iter().enumerate() {
                    w.push(r.numbers(row, &format!("weights[{i}]"))?);
                }
                Some(w)
            }
        };
        let json = SurfaceJson {
            kind: r.string(obj, "type")?,
            degree_u: r.usize(obj, "degree_u")?,
            degree_v: r.usize(obj, "degree_v")?,
            knots_u: r.numbers(r.get(obj, "knots_u")?, "knots_u")?,
            knots_v: r.numbers(r.get(obj, "knots_v")?, "knots_v")?,
            points,
            weights,
            closed_u: r.bool(obj, "closed_u")?,
            closed_v: r.bool(obj, "closed_v")?,
        };
        Self::from_json(&json).map_err(|e| r.locate(e))
    }

    /// Builds the surface a [`SurfaceJson`] describes.
    ///
    /// # Errors
    /// [`NurbsError::Json`] naming the invalid field.
    pub fn from_json(j: &SurfaceJson) -> Result<Self, NurbsError> {
        if j.kind != SURFACE_TYPE {
            return Err(json_error(
                "type",
                format!("expected \"{SURFACE_TYPE}\", got {:?}", j.kind),
            ));
        }
        let u = knot_vector(j.degree_u, &j.knots_u, j.closed_u)
            .map_err(|e| knot_error(e, "degree_u", "knots_u"))?;
        let v = knot_vector(j.degree_v, &j.knots_v, j.closed_v)
            .map_err(|e| knot_error(e, "degree_v", "knots_v"))?;
        let nv = j.points.first().map_or(0, Vec::len);
        if let Some(i) = j.points.iter().position(|r| r.len() != nv) {
            return Err(json_error(
                &format!("points[{i}]"),
                format!("expected {nv} points, as in points[0]"),
            ));
        }
        let (nu_k, nv_k) = (u.num_points(), v.num_points());
        if j.points.len() != nu_k || nv != nv_k {
            return Err(json_error(
                "points",
                format!(
                    "the knots need {nu_k} × {nv_k} control points, but {} × {nv} were given",
                    j.points.len()
                ),
            ));
        }
        let points = j.points.concat();
        let grid = |k: usize| format!("[{}][{}]", k / nv.max(1), k % nv.max(1));
        match &j.weights {
            None => BSplineSurface::new(u, v, points).map(Surface::BSpline),
            Some(w) => {
                if let Some(i) = (0..nu_k).find(|&i| w.get(i).map(Vec::len) != Some(nv)) {
                    return Err(json_error(
                        &if i < w.len() {
                            format!("weights[{i}]")
                        } else {
                            "weights".into()
                        },
                        format!("expected {nu_k} rows of {nv} weights, like the points"),
                    ));
                }
                if w.len() != nu_k {
                    return Err(json_error(
                        "weights",
                        format!("expected {nu_k} rows of weights, got {}", w.len()),
                    ));
                }
                NurbsSurface::new(u, v, points, w.concat()).map(Surface::Nurbs)
            }
        }
        .map_err(|e| point_error(e, "points", &grid))
    }

    /// The document describing this surface.
    pub fn to_json(&self) -> SurfaceJson {
        let (ku, kv, flat, weights) = match self {
            Surface::BSpline(s) => (s.knots_u(), s.knots_v(), s.points().to_vec(), None),
            Surface::Nurbs(s) => (
                s.knots_u(),
                s.knots_v(),
                s.points().to_vec(),
                Some(s.weights()),
            ),
        };
        let nv = kv.num_points();
        SurfaceJson {
            kind: SURFACE_TYPE.into(),
            degree_u: ku.degree(),
            degree_v: kv.degree(),
            knots_u: ku.period_knots().unwrap_or(ku.as_slice()).to_vec(),
            knots_v: kv.period_knots().unwrap_or(kv.as_slice()).to_vec(),
            points: flat.chunks(nv).map(<[_]>::to_vec).collect(),
            weights: weights.map(|w| w.chunks(nv).map(<[_]>::to_vec).collect()),
            closed_u: ku.is_periodic(),
            closed_v: kv.is_periodic(),
        }
    }

    /// The surface as compact JSON text (exact, see [`Curve::to_json_string`]).
    pub fn to_json_string(&self) -> String {
        crate::json::to_string(&self.to_json())
    }
}

impl ToJson for CurveJson {
    fn write_json(&self, out: &mut String) {
        object(out, |o| {
            o.field("type", &self.kind);
            o.field("degree", &self.degree);
            o.field("knots", &self.knots);
            o.field("points", &self.points);
            o.field_if_some("weights", &self.weights);
            o.field("closed", &self.closed);
        });
    }
}

impl ToJson for SurfaceJson {
    fn write_json(&self, out: &mut String) {
        object(out, |o| {
            o.field("type", &self.kind);
            o.field("degree_u", &self.degree_u);
            o.field("degree_v", &self.degree_v);
            o.field("knots_u", &self.knots_u);
            o.field("knots_v", &self.knots_v);
            o.field("points", &self.points);
            o.field_if_some("weights", &self.weights);
            o.field("closed_u", &self.closed_u);
            o.field("closed_v", &self.closed_v);
        });
    }
}

/// The open or periodic knot vector of a document.
fn knot_vector(degree: usize, knots: &[f64], closed: bool) -> Result<KnotVector, NurbsError> {
    if closed {
        KnotVector::periodic(degree, knots)
    } else {
        KnotVector::new(degree, knots.to_vec())
    }
}

fn json_error(field: &str, message: String) -> NurbsError {
    NurbsError::Json {
        field: field.into(),
        message,
    }
}

/// A knot-vector error, attributed to the degree or knots field.
fn knot_error(e: NurbsError, degree: &str, knots: &str) -> NurbsError {
    let field = match &e {
        NurbsError::BadDegree { .. } => degree.to_string(),
        NurbsError::NonFiniteKnot { index, .. } | NurbsError::DecreasingKnots { index, .. } => {
            format!("{knots}[{index}]")
        }
        _ => knots.to_string(),
    };
    json_error(&field, e.to_string())
}

/// A curve or surface error, attributed to the points, weights or knots field; `index`
/// turns a flat point index into a field suffix.
fn point_error(e: NurbsError, count_field: &str, index: &dyn Fn(usize) -> String) -> NurbsError {
    let field = match &e {
        NurbsError::NonFinitePoint { index: i } | NurbsError::LargeCoordinate { index: i, .. } => {
            format!("points{}", index(*i))
        }
        NurbsError::NonPositiveWeight { index: i, .. } => format!("weights{}", index(*i)),
        NurbsError::WeightCountMismatch { .. } => "weights".into(),
        NurbsError::KnotCountMismatch { .. } => count_field.into(),
        _ => "points".into(),
    };
    json_error(&field, e.to_string())
}

/// Typed access to the parsed document, with field paths in errors.
struct Reader<'a> {
    text: &'a str,
    root: &'a Node,
}

type Members = [(String, Node)];

impl<'a> Reader<'a> {
    /// An error at `field`, with its line and column when the field exists.
    fn error(&self, field: &str, message: String) -> NurbsError {
        match self.position(field) {
            Some(pos) => {
                let (line, column) = line_col(self.text, pos);
                json_error(field, format!("{message} (line {line}, column {column})"))
            }
            None => json_error(field, message),
        }
    }

    /// Adds the line and column to a [`NurbsError::Json`].
    fn locate(&self, e: NurbsError) -> NurbsError {
        match e {
            NurbsError::Json { field, message } => self.error(&field, message),
            other => other,
        }
    }

    /// Byte offset of the value at a path like `points[2][1]`.
    fn position(&self, path: &str) -> Option<usize> {
        let mut node = self.root;
        let (name, mut rest) = path.split_at(path.find('[').unwrap_or(path.len()));
        if !name.is_empty() {
            let Value::Obj(m) = &node.value else {
                return None;
            };
            node = &m.iter().find(|(k, _)| k == name)?.1;
        }
        while let Some(r) = rest.strip_prefix('[') {
            let end = r.find(']')?;
            let i: usize = r[..end].parse().ok()?;
            let Value::Arr(a) = &node.value else {
                return None;
            };
            node = a.get(i)?;
            rest = &r[end + 1..];
        }
        Some(node.pos)
    }

    fn object(&self, n: &'a Node, field: &str) -> Result<&'a Members, NurbsError> {
        match &n.value {
            Value::Obj(m) => Ok(m),
            _ => Err(self.error(field, "expected an object".into())),
        }
    }

    fn array(&self, n: &'a Node, field: &str) -> Result<&'a [Node], NurbsError> {
        match &n.value {
            Value::Arr(a) => Ok(a),
            _ => Err(self.error(field, "expected an array".into())),
        }
    }

    fn allow_only(&self, obj: &Members, names: &[&str]) -> Result<(), NurbsError> {
        for (k, (name, _)) in obj.iter().enumerate() {
            if !names.contains(&name.as_str()) {
                return Err(self.error(name, format!("unknown field; expected one of {names:?}")));
            }
            if obj[..k].iter().any(|(n, _)| n == name) {
                return Err(json_error(name, "duplicate field".into()));
            }
        }
        Ok(())
    }

    fn find(&self, obj: &'a Members, name: &str) -> Option<&'a Node> {
        obj.iter().find(|(k, _)| k == name).map(|(_, n)| n)
    }

    fn get(&self, obj: &'a Members, name: &str) -> Result<&'a Node, NurbsError> {
        self.find(obj, name)
            .ok_or_else(|| json_error(name, "missing field".into()))
    }

    fn string(&self, obj: &Members, name: &str) -> Result<String, NurbsError> {
        match &self.get(obj, name)?.value {
            Value::Str(s) => Ok(s.clone()),
            _ => Err(self.error(name, "expected a string".into())),
        }
    }

    fn usize(&self, obj: &Members, name: &str) -> Result<usize, NurbsError> {
        match &self.get(obj, name)?.value {
            Value::Num(_, Some(k)) => {
                usize::try_from(*k).map_err(|_| self.error(name, format!("{k} is too large")))
            }
            Value::Num(x, None) if *x >= 0.0 && x.fract() == 0.0 => {
                Err(self.error(name, format!("{x} is too large")))
            }
            _ => Err(self.error(name, "expected a non-negative integer".into())),
        }
    }

    fn bool(&self, obj: &Members, name: &str) -> Result<bool, NurbsError> {
        match self.find(obj, name).map(|n| &n.value) {
            None => Ok(false),
            Some(Value::Bool(b)) => Ok(*b),
            Some(_) => Err(self.error(name, "expected true or false".into())),
        }
    }

    fn number(&self, n: &Node, field: &str) -> Result<f64, NurbsError> {
        match n.value {
            Value::Num(x, _) if x.is_finite() => Ok(x),
            Value::Num(..) => Err(self.error(field, "the number is out of range".into())),
            _ => Err(self.error(field, "expected a number".into())),
        }
    }

    fn numbers(&self, n: &Node, field: &str) -> Result<Vec<f64>, NurbsError> {
        self.array(n, field)?
            .iter()
            .enumerate()
            .map(|(i, x)| self.number(x, &format!("{field}[{i}]")))
            .collect()
    }

    fn points(&self, n: &Node, field: &str) -> Result<Vec<[f64; 3]>, NurbsError> {
        self.array(n, field)?
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let f = format!("{field}[{i}]");
                let c = self.numbers(p, &f)?;
                <[f64; 3]>::try_from(c.as_slice()).map_err(|_| {
                    self.error(
                        &f,
                        format!("expected 3 coordinates [x, y, z], got {}", c.len()),
                    )
                })
            })
            .collect()
    }
}
