//! OBJ free-form geometry: B-spline and Bézier curves and surfaces, polynomial or rational.
//!
//! CAD tools (Rhino, Alias, Maya, openNURBS-based exporters) write NURBS into OBJ with the
//! free-form statements of the OBJ 3.0 specification (Wavefront, "Object Files (.obj)",
//! sections *Specifying free-form curves/surfaces*, *Elements* and *Free-form curve/surface
//! body statements*):
//!
//! ```text
//! v 0 0 0 1            # control points; the 4th number is the weight (default 1)
//! ...
//! cstype rat bspline   # rat = rational; bspline or bezier
//! deg 3 3              # degree in u (and v for surfaces)
//! surf 0 1 0 1  1 2 3 4 ... 16   # parameter range s0 s1 t0 t1, then control point indices
//! parm u 0 0 0 0 1 1 1 1          # knot vector in u
//! parm v 0 0 0 0 1 1 1 1
//! end
//! ```
//!
//! [`parse_obj_freeform`] reads every `curv` and `surf` element of a file into
//! [`nurbs::Geometry`](crate::nurbs::Geometry) values (the same types as the JSON reader),
//! and [`write_obj_freeform`] writes them back. The rules, and what is refused:
//!
//! - **Control points** are `v x y z [w]`; `w` is the weight of a rational (`rat`) element
//!   and is ignored otherwise (the specification's rule). A `v` line with six or seven
//!   numbers is a vertex with a colour: its weight is 1. Indices are 1-based, or negative
//!   (relative to the vertices defined before the element), as for faces; `v/vt/vn`
//!   references in `surf` use the `v` part.
//! - **Order of a surface's control points**: `u` varies fastest — the `k`-th index is
//!   `P_{i,j}` with `i = k mod N_u`, `j = k div N_u` (the specification's surface formula
//!   sums over `u` first; tinynurbs and Rhino's exporter use the same order).
//! - **B-spline knots** (`parm u` / `parm v`) are the whole knot vector, `N + p + 1` knots
//!   for `N` control points. openNURBS-style vectors without the two outermost knots
//!   (`N + p − 1`, whose end knots do not influence the curve) are accepted and completed
//!   by repeating the first and last knot.
//! - **Bézier** elements (`cstype bezier`): `parm` lists the `m + 1` breakpoints of `m`
//!   segments and there are `m p + 1` control points; they are read as the B-spline with
//!   every interior breakpoint repeated `p` times and the ends `p + 1` times, which is the
//!   same curve.
//! - The **parameter range** of `curv u0 u1` / `surf s0 s1 t0 t1` must be the knot
//!   vector's domain `[t_p, t_N]` (relative tolerance 1e-9): sub-ranges would need
//!   trimming of the element and are refused rather than silently ignored.
//! - **Refused** with an error naming the line: basis types other than `bspline` and
//!   `bezier` (`bmatrix`, `cardinal`, `taylor`), trimming and special curves/points
//!   (`trim`, `hole`, `scrv`, `sp`: the surface would be drawn untrimmed), an element
//!   without `cstype`, `deg` or `parm`, a body without `end`, and all the invalid knot
//!   vectors, counts and weights of the [`nurbs`](crate::nurbs) types.
//! - **Ignored**: polygons, lines and every non-free-form statement; 2-D parameter-space
//!   data (`vp`, `curv2`), connectivity (`con`), approximation techniques (`ctech`,
//!   `stech`), `step` and `bmat`.
//! - **Closed (periodic) elements**: OBJ has no periodic flag; CAD tools write a closed
//!   B-spline unwrapped, its first `p` control points repeated at the end and its knot
//!   intervals repeating with the period. An element in that form is read as the closed
//!   curve (or a surface as closed in that direction), the test openNURBS's
//!   `ON_NurbsCurve::IsPeriodic` makes ([`KnotVector::periodic_form`],
//!   [`BSplineCurve::periodic_form`]): the repeated points dropped, the knots one period.
//!   So a closed curve written by [`write_obj_freeform`] reads back closed.
//!
//! The name of each element is that of the last `o` (or, without one, `g`) statement.

use super::read::{line_data, PhysicalLines};
use super::ObjError;
use crate::mesh::MAX_COORDINATE;
use crate::nurbs::curve::coincident;
use crate::nurbs::{
    BSplineCurve, BSplineSurface, Curve, Geometry, KnotVector, NurbsCurve, NurbsSurface, Surface,
};
use std::fmt::Write as _;

/// A curve or surface read from an OBJ file, with where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct FreeFormElement {
    /// The curve or surface.
    pub geometry: Geometry,
    /// The name of the enclosing `o` (or `g`) statement, if any.
    pub name: Option<String>,
    /// 1-based line of the `curv` or `surf` statement.
    pub line: usize,
}

/// Parses the free-form curves and surfaces of OBJ bytes, in file order; `source_name` is
/// used in errors.
///
/// # Errors
/// The first problem, as an [`ObjError`] naming `source_name` and the 1-based line (see the
/// module documentation for what is refused).
///
/// ```
/// use subsurf::io::parse_obj_freeform;
/// use subsurf::nurbs::{Curve, Geometry};
/// let text = "v 0 0 0\nv 1 2 0\nv 3 2 0\nv 4 0 0\n\
///             cstype bspline\ndeg 3\ncurv 0 1 1 2 3 4\nparm u 0 0 0 0 1 1 1 1\nend\n";
/// let elements = parse_obj_freeform(text.as_bytes(), "bezier.obj")?;
/// let Geometry::Curve(Curve::BSpline(c)) = &elements[0].geometry else { panic!() };
/// assert_eq!(c.eval(0.5)?, [2.0, 1.5, 0.0]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn parse_obj_freeform(
    bytes: &[u8],
    source_name: &str,
) -> Result<Vec<FreeFormElement>, ObjError> {
    let err = |line: usize, message: String| ObjError {
        source_name: source_name.to_owned(),
        line: Some(line),
        message,
    };
    let mut reader = Reader::default();
    let mut lines = PhysicalLines {
        rest: bytes,
        line: 0,
    };
    let mut joined = String::new();
    while let Some((first, raw)) = lines.next() {
        let (data, mut continues) = line_data(raw, first).map_err(|m| err(first, m))?;
        joined.clear();
        joined.push_str(data);
        while continues {
            let Some((no, raw)) = lines.next() else { break };
            let (data, more) = line_data(raw, no).map_err(|m| err(no, m))?;
            joined.push(' ');
            joined.push_str(data);
            continues = more;
        }
        reader
            .statement(&joined, first)
            .map_err(|m| err(reader.element_error_line.take().unwrap_or(first), m))?;
    }
    if let Some(open) = &reader.open {
        return Err(err(
            open.line,
            format!("{} has no `end` statement", open.keyword()),
        ));
    }
    Ok(reader.elements)
}

/// The basis type of `cstype`.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Basis {
    BSpline,
    Bezier,
}

/// An element whose body (`parm` statements) is being read.
struct Open {
    line: usize,
    /// `None` for a curve, `Some` for a surface.
    surface: bool,
    /// Parameter range `[u0, u1]` or `[s0, s1, t0, t1]`.
    range: Vec<f64>,
    /// Resolved 0-based control point indices.
    indices: Vec<usize>,
    parm_u: Option<Vec<f64>>,
    parm_v: Option<Vec<f64>>,
    rational: bool,
    basis: Basis,
    degree: (usize, usize),
    name: Option<String>,
}

impl Open {
    fn keyword(&self) -> &'static str {
        if self.surface {
            "surf"
        } else {
            "curv"
        }
    }
}

#[derive(Default)]
struct Reader {
    /// `x, y, z, w` of every `v` so far.
    vertices: Vec<[f64; 4]>,
    /// `(rational, basis)` of the last `cstype`.
    cstype: Option<(bool, Basis)>,
    /// The last `deg`.
    degree: Option<(usize, Option<usize>)>,
    object: Option<String>,
    group: Option<String>,
    open: Option<Open>,
    elements: Vec<FreeFormElement>,
    /// Set when an element fails to build at its `end`: the error belongs to the element's
    /// `curv`/`surf` line.
    element_error_line: Option<usize>,
}

impl Reader {
    fn statement(&mut self, text: &str, line: usize) -> Result<(), String> {
        let mut tokens = text.split_ascii_whitespace();
        let Some(keyword) = tokens.next() else {
            return Ok(());
        };
        let args: Vec<&str> = tokens.collect();
        if let Some(open) = &self.open {
            if !matches!(keyword, "parm" | "end" | "trim" | "hole" | "scrv" | "sp") {
                return Err(format!(
                    "`{keyword}` inside the body of the {} at line {} (missing `end`?)",
                    open.keyword(),
                    open.line
                ));
            }
        }
        match keyword {
            "v" => self.vertex(&args),
            "o" => {
                self.object = Some(args.join(" "));
                Ok(())
            }
            "g" => {
                self.group = Some(args.join(" "));
                Ok(())
            }
            "cstype" => self.cstype(&args),
            "deg" => self.deg(&args),
            "curv" => self.element(&args, line, false),
            "surf" => self.element(&args, line, true),
            "parm" => self.parm(&args),
            "end" => self.end(),
            "trim" | "hole" | "scrv" | "sp" => Err(format!(
                "`{keyword}` (trimming curves and special curves or points) is not supported: \
                 the surface would be used untrimmed"
            )),
            _ => Ok(()),
        }
    }

    fn vertex(&mut self, args: &[&str]) -> Result<(), String> {
        let numbers = args
            .iter()
            .map(|t| number(t, "v"))
            .collect::<Result<Vec<_>, _>>()?;
        if let Some(c) = numbers.iter().take(3).find(|c| c.abs() > MAX_COORDINATE) {
            return Err(format!(
                "v: the coordinate {c:e} is too large; coordinates must be below 1e75 in magnitude"
            ));
        }
        let w = match numbers.len() {
            3 | 6 | 7 => 1.0,
            4 => numbers[3],
            n => return Err(format!("v: expected x y z [w], got {n} numbers")),
        };
        self.vertices.push([numbers[0], numbers[1], numbers[2], w]);
        Ok(())
    }

    fn cstype(&mut self, args: &[&str]) -> Result<(), String> {
        let (rational, kind) = match args {
            ["rat", kind] => (true, *kind),
            [kind] => (false, *kind),
            _ => return Err("cstype: expected `[rat] bspline` or `[rat] bezier`".into()),
        };
        let basis = match kind {
            "bspline" => Basis::BSpline,
            "bezier" => Basis::Bezier,
            "bmatrix" | "cardinal" | "taylor" => {
                return Err(format!(
                    "cstype {kind} is not supported (bspline and bezier are)"
                ))
            }
            other => return Err(format!("cstype: unknown basis type {other:?}")),
        };
        self.cstype = Some((rational, basis));
        Ok(())
    }

    fn deg(&mut self, args: &[&str]) -> Result<(), String> {
        let parse = |t: &str| -> Result<usize, String> {
            match t.parse::<usize>() {
                Ok(d) if d >= 1 => Ok(d),
                _ => Err(format!("deg: {t:?} is not a degree (an integer ≥ 1)")),
            }
        };
        self.degree = match args {
            [u] => Some((parse(u)?, None)),
            [u, v] => Some((parse(u)?, Some(parse(v)?))),
            _ => return Err("deg: expected `deg degu [degv]`".into()),
        };
        Ok(())
    }

    fn element(&mut self, args: &[&str], line: usize, surface: bool) -> Result<(), String> {
        let keyword = if surface { "surf" } else { "curv" };
        let (rational, basis) = self
            .cstype
            .ok_or_else(|| format!("{keyword} before any `cstype` statement"))?;
        let (du, dv) = self
            .degree
            .ok_or_else(|| format!("{keyword} before any `deg` statement"))?;
        let degree = if surface {
            let dv = dv.ok_or_else(|| {
                "surf needs two degrees: the last `deg` statement gives one".to_string()
            })?;
            (du, dv)
        } else {
            (du, 0)
        };
        let nrange = if surface { 4 } else { 2 };
        if args.len() < nrange + 2 {
            return Err(format!(
                "{keyword}: expected {} parameter values and at least two control points",
                nrange
            ));
        }
        let range = args[..nrange]
            .iter()
            .map(|t| number(t, keyword))
            .collect::<Result<Vec<_>, _>>()?;
        let count = self.vertices.len();
        let indices = args[nrange..]
            .iter()
            .map(|t| vertex_index(t, count, keyword))
            .collect::<Result<Vec<_>, _>>()?;
        self.open = Some(Open {
            line,
            surface,
            range,
            indices,
            parm_u: None,
            parm_v: None,
            rational,
            basis,
            degree,
            name: self.object.clone().or_else(|| self.group.clone()),
        });
        Ok(())
    }

    fn parm(&mut self, args: &[&str]) -> Result<(), String> {
        let open = self
            .open
            .as_mut()
            .ok_or("parm outside the body of a curv or surf element")?;
        let (dir, values) = args
            .split_first()
            .ok_or("parm: expected `parm u|v values`")?;
        let values = values
            .iter()
            .map(|t| number(t, "parm"))
            .collect::<Result<Vec<_>, _>>()?;
        let slot = match (*dir, open.surface) {
            ("u", _) => &mut open.parm_u,
            ("v", true) => &mut open.parm_v,
            ("v", false) => return Err("parm v in the body of a curve (curves have only u)".into()),
            (other, _) => return Err(format!("parm: unknown direction {other:?}")),
        };
        if slot.is_some() {
            return Err(format!("parm {dir} given twice"));
        }
        *slot = Some(values);
        Ok(())
    }

    fn end(&mut self) -> Result<(), String> {
        let open = self
            .open
            .take()
            .ok_or("end without a curv or surf element")?;
        let line = open.line;
        let name = open.name.clone();
        let geometry = build(open, &self.vertices).inspect_err(|_| {
            self.element_error_line = Some(line);
        })?;
        self.elements.push(FreeFormElement {
            geometry,
            name,
            line,
        });
        Ok(())
    }
}

/// A finite number.
fn number(t: &str, keyword: &str) -> Result<f64, String> {
    // A long token is shown by its first characters.
    let shown = || match t.char_indices().nth(40) {
        Some((end, _)) => format!("{:?}…", &t[..end]),
        None => format!("{t:?}"),
    };
    match t.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(format!("{keyword}: {} is not finite", shown())),
        Err(_) => Err(format!("{keyword}: {} is not a number", shown())),
    }
}

/// A 0-based vertex index from `v`, `v/vt` or `v/vt/vn`, 1-based or negative (relative to
/// the `count` vertices defined so far).
fn vertex_index(t: &str, count: usize, keyword: &str) -> Result<usize, String> {
    let v = t.split('/').next().unwrap_or(t);
    let bad = || format!("{keyword}: {t:?} is not a vertex index");
    let out_of_range = || {
        format!(
            "{keyword}: vertex index {v} is out of range: {count} vertices are defined before it"
        )
    };
    if let Some(rel) = v.strip_prefix('-') {
        let k: usize = rel.parse().map_err(|_| bad())?;
        if k == 0 || k > count {
            return Err(out_of_range());
        }
        Ok(count - k)
    } else {
        let k: usize = v.parse().map_err(|_| bad())?;
        if k == 0 {
            return Err(format!(
                "{keyword}: vertex index 0 is invalid: OBJ indices start at 1"
            ));
        }
        if k > count {
            return Err(out_of_range());
        }
        Ok(k - 1)
    }
}

/// The knot vector of one direction with `n` control points.
fn knots(
    parm: Option<Vec<f64>>,
    basis: Basis,
    degree: usize,
    n: usize,
    dir: &str,
) -> Result<KnotVector, String> {
    let parm = parm.ok_or_else(|| format!("no `parm {dir}` statement in the element's body"))?;
    let knots = match basis {
        Basis::BSpline => {
            if parm.len() + 2 == n + degree + 1 {
                // openNURBS style: the two outermost knots are implied.
                let mut k = Vec::with_capacity(parm.len() + 2);
                k.push(parm[0]);
                k.extend_from_slice(&parm);
                k.push(parm[parm.len() - 1]);
                k
            } else if parm.len() == n + degree + 1 {
                parm
            } else {
                return Err(format!(
                    "parm {dir}: {n} control points of degree {degree} need {} knots, got {}",
                    n + degree + 1,
                    parm.len()
                ));
            }
        }
        Basis::Bezier => {
            let segments = parm.len().saturating_sub(1);
            if segments == 0 || n != segments * degree + 1 {
                return Err(format!(
                    "parm {dir}: a Bézier element with {} breakpoints of degree {degree} needs {} \
                     control points, got {n}",
                    parm.len(),
                    segments * degree + 1
                ));
            }
            let mut k = Vec::with_capacity(n + degree + 1);
            for (i, &b) in parm.iter().enumerate() {
                let times = if i == 0 || i == segments {
                    degree + 1
                } else {
                    degree
                };
                k.extend(std::iter::repeat_n(b, times));
            }
            k
        }
    };
    KnotVector::new(degree, knots).map_err(|e| format!("parm {dir}: {e}"))
}

/// Checks that the element's parameter range is its knot vector's domain.
fn check_range(range: &[f64], k: &KnotVector, dir: &str) -> Result<(), String> {
    let (a, b) = k.domain();
    let tol = 1e-9 * (b - a).abs().max(a.abs()).max(b.abs()).max(1e-300);
    if (range[0] - a).abs() > tol || (range[1] - b).abs() > tol {
        return Err(format!(
            "the {dir} parameter range [{}, {}] is not the knot domain [{a}, {b}]; \
             sub-ranges (trimmed elements) are not supported",
            range[0], range[1]
        ));
    }
    Ok(())
}

/// The possible numbers of control points in one direction for a `parm` list: the full
/// knot vector's, then the openNURBS form's (B-spline); the breakpoints' (Bézier).
fn counts(parm: &[f64], basis: Basis, degree: usize) -> Vec<usize> {
    match basis {
        Basis::BSpline => [parm.len() + 2, parm.len()]
            .iter()
            .filter_map(|&k| k.checked_sub(degree + 1))
            .filter(|&c| c > 0)
            .rev()
            .collect(),
        Basis::Bezier => vec![parm.len().saturating_sub(1) * degree + 1],
    }
}

/// `(N_u, N_v)` of a surface element with `n` control points, from its `parm` lists.
fn net_size(open: &Open, n: usize) -> Result<(usize, usize), String> {
    let (Some(pu), Some(pv)) = (&open.parm_u, &open.parm_v) else {
        let dir = if open.parm_u.is_none() { "u" } else { "v" };
        return Err(format!("no `parm {dir}` statement in the element's body"));
    };
    let cu = counts(pu, open.basis, open.degree.0);
    let cv = counts(pv, open.basis, open.degree.1);
    for &nu in &cu {
        for &nv in &cv {
            if nu.checked_mul(nv) == Some(n) {
                return Ok((nu, nv));
            }
        }
    }
    Err(format!(
        "surf: {n} control points do not match the knot vectors: `parm u` ({} values, degree \
         {}) and `parm v` ({} values, degree {}) give a net of {} x {}",
        pu.len(),
        open.degree.0,
        pv.len(),
        open.degree.1,
        cu.first().copied().unwrap_or(0),
        cv.first().copied().unwrap_or(0)
    ))
}

/// Builds the curve or surface of a finished element.
fn build(open: Open, vertices: &[[f64; 4]]) -> Result<Geometry, String> {
    let points: Vec<[f64; 3]> = open
        .indices
        .iter()
        .map(|&i| [vertices[i][0], vertices[i][1], vertices[i][2]])
        .collect();
    let weights: Vec<f64> = open.indices.iter().map(|&i| vertices[i][3]).collect();
    if !open.surface {
        let k = knots(open.parm_u, open.basis, open.degree.0, points.len(), "u")?;
        check_range(&open.range, &k, "u")?;
        let (k, n) = periodic(k, points.len(), |i, j| {
            coincident(&points[i], &points[j]) && coincident(&[weights[i]], &[weights[j]])
        });
        let (points, weights) = (points[..n].to_vec(), weights[..n].to_vec());
        let curve = if open.rational {
            NurbsCurve::new(k, points, weights).map(Curve::Nurbs)
        } else {
            BSplineCurve::new(k, points).map(Curve::BSpline)
        };
        return curve.map(Geometry::Curve).map_err(|e| format!("curv: {e}"));
    }
    // u varies fastest in the file; the library stores P_{i,j} at i · nv + j.
    let n = points.len();
    let (nu, nv) = net_size(&open, n)?;
    let ku = knots(open.parm_u, open.basis, open.degree.0, nu, "u")?;
    let kv = knots(open.parm_v, open.basis, open.degree.1, nv, "v")?;
    check_range(&open.range[..2], &ku, "u")?;
    check_range(&open.range[2..], &kv, "v")?;
    let reorder = |k: usize| (k % nv) * nu + k / nv;
    let net: Vec<[f64; 3]> = (0..n).map(|k| points[reorder(k)]).collect();
    let w: Vec<f64> = (0..n).map(|k| weights[reorder(k)]).collect();
    let same = |a: usize, b: usize| coincident(&net[a], &net[b]) && coincident(&[w[a]], &[w[b]]);
    let (ku, nu2) = periodic(ku, nu, |i, j| (0..nv).all(|c| same(i * nv + c, j * nv + c)));
    let (kv, nv2) = periodic(kv, nv, |i, j| {
        (0..nu2).all(|r| same(r * nv + i, r * nv + j))
    });
    let keep = |k: usize| k / nv < nu2 && k % nv < nv2;
    let net: Vec<[f64; 3]> = (0..n).filter(|&k| keep(k)).map(|k| net[k]).collect();
    let w: Vec<f64> = (0..n).filter(|&k| keep(k)).map(|k| w[k]).collect();
    let surface = if open.rational {
        NurbsSurface::new(ku, kv, net, w).map(Surface::Nurbs)
    } else {
        BSplineSurface::new(ku, kv, net).map(Surface::BSpline)
    };
    surface
        .map(Geometry::Surface)
        .map_err(|e| format!("surf: {e}"))
}

/// The periodic knot vector and the number of distinct control points (rows) of a
/// direction with `count` of them, when it is the unwrapped form of a closed one: its knots'
/// [`KnotVector::periodic_form`] with period `n`, and `same(i, i + n)` for the first `p` (the
/// repeated control points coincide); else the knots and `count` unchanged.
fn periodic(
    k: KnotVector,
    count: usize,
    same: impl Fn(usize, usize) -> bool,
) -> (KnotVector, usize) {
    match k.periodic_form() {
        Some(pk) => {
            let n = pk.num_points();
            if (0..pk.degree()).all(|i| same(i, i + n)) {
                (pk, n)
            } else {
                (k, count)
            }
        }
        None => (k, count),
    }
}

/// Writes curves and surfaces as OBJ free-form elements (`cstype [rat] bspline`), read back
/// exactly by [`parse_obj_freeform`]: the control points of each element as `v x y z w`
/// lines (weight 1 for polynomial ones), then the element with its full knot vectors.
/// Periodic (closed) elements are written unwrapped, with their first `p` control points
/// repeated, which is the same curve, as CAD tools write them; read back they are closed
/// again. Numbers use Rust's shortest round-trip form.
pub fn write_obj_freeform(items: &[Geometry]) -> String {
    let mut out = String::from("# subsurf: free-form curves and surfaces\n");
    let mut base = 0usize;
    for (n, item) in items.iter().enumerate() {
        let _ = writeln!(out, "o element{}", n + 1);
        match item {
            Geometry::Curve(c) => {
                let (k, pts, w, rat) = match c {
                    Curve::BSpline(c) => (c.knots(), c.points().to_vec(), None, false),
                    Curve::Nurbs(c) => (c.knots(), c.points().to_vec(), Some(c.weights()), true),
                };
                let count = k.num_basis();
                for i in 0..count {
                    let j = i % pts.len();
                    write_vertex(&mut out, pts[j], w.as_ref().map_or(1.0, |w| w[j]));
                }
                let (a, b) = k.domain();
                let _ = writeln!(out, "cstype {}bspline", if rat { "rat " } else { "" });
                let _ = writeln!(out, "deg {}", k.degree());
                let _ = write!(out, "curv {a:?} {b:?}");
                for i in 0..count {
                    let _ = write!(out, " {}", base + i + 1);
                }
                let _ = write!(out, "\nparm u");
                write_knots(&mut out, k);
                out.push_str("end\n");
                base += count;
            }
            Geometry::Surface(s) => {
                let (ku, kv, pts, w, rat, (nu0, nv0)) = match s {
                    Surface::BSpline(s) => (
                        s.knots_u(),
                        s.knots_v(),
                        s.points().to_vec(),
                        None,
                        false,
                        s.size(),
                    ),
                    Surface::Nurbs(s) => (
                        s.knots_u(),
                        s.knots_v(),
                        s.points().to_vec(),
                        Some(s.weights()),
                        true,
                        s.size(),
                    ),
                };
                let (nu, nv) = (ku.num_basis(), kv.num_basis());
                for j in 0..nv {
                    for i in 0..nu {
                        let at = (i % nu0) * nv0 + j % nv0;
                        write_vertex(&mut out, pts[at], w.as_ref().map_or(1.0, |w| w[at]));
                    }
                }
                let ((a, b), (c, d)) = (ku.domain(), kv.domain());
                let _ = writeln!(out, "cstype {}bspline", if rat { "rat " } else { "" });
                let _ = writeln!(out, "deg {} {}", ku.degree(), kv.degree());
                let _ = write!(out, "surf {a:?} {b:?} {c:?} {d:?}");
                for i in 0..nu * nv {
                    let _ = write!(out, " {}", base + i + 1);
                }
                let _ = write!(out, "\nparm u");
                write_knots(&mut out, ku);
                out.push_str("parm v");
                write_knots(&mut out, kv);
                out.push_str("end\n");
                base += nu * nv;
            }
        }
    }
    out
}

fn write_vertex(out: &mut String, p: [f64; 3], w: f64) {
    let _ = writeln!(out, "v {:?} {:?} {:?} {w:?}", p[0], p[1], p[2]);
}

fn write_knots(out: &mut String, k: &KnotVector) {
    for t in k.as_slice() {
        let _ = write!(out, " {t:?}");
    }
    out.push('\n');
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::NurbsCurve;

    fn parse(text: &str) -> Result<Vec<FreeFormElement>, ObjError> {
        parse_obj_freeform(text.as_bytes(), "t.obj")
    }

    fn err(text: &str) -> String {
        parse(text).unwrap_err().to_string()
    }

    const CUBIC: &str = "v 0 0 0\nv 1 2 0\nv 3 2 0\nv 4 0 0\nv 5 1 1\n\
        cstype bspline\ndeg 3\ncurv 0 2 1 2 3 4 5\nparm u 0 0 0 0 1 2 2 2 2\nend\n";

    #[test]
    fn reads_a_clamped_cubic_curve() {
        let e = parse(CUBIC).unwrap();
        assert_eq!(e.len(), 1);
        assert_eq!(e[0].line, 8);
        let Geometry::Curve(Curve::BSpline(c)) = &e[0].geometry else {
            panic!("{:?}", e[0].geometry)
        };
        assert_eq!(c.points().len(), 5);
        assert_eq!(c.eval(0.0).unwrap(), [0.0, 0.0, 0.0]);
        assert_eq!(c.eval(2.0).unwrap(), [5.0, 1.0, 1.0]);
    }

    #[test]
    fn opennurbs_knot_vectors_without_end_knots_are_completed() {
        let short = CUBIC.replace("parm u 0 0 0 0 1 2 2 2 2", "parm u 0 0 0 1 2 2 2");
        assert_eq!(parse(&short).unwrap(), parse(CUBIC).unwrap());
    }

    #[test]
    fn negative_indices_and_continuation_lines() {
        let text = CUBIC.replace("curv 0 2 1 2 3 4 5", "curv 0 2 -5 -4 \\\n -3 -2 -1");
        assert_eq!(
            parse(&text).unwrap()[0].geometry,
            parse(CUBIC).unwrap()[0].geometry
        );
    }

    #[test]
    fn a_rational_circle_round_trips_exactly() {
        let circle = Geometry::Curve(Curve::Nurbs(
            NurbsCurve::circle([1.0, 2.0, 3.0], 2.5).unwrap(),
        ));
        let text = write_obj_freeform(std::slice::from_ref(&circle));
        let back = parse(&text).unwrap();
        assert_eq!(back.len(), 1);
        assert_eq!(back[0].name.as_deref(), Some("element1"));
        let Geometry::Curve(Curve::Nurbs(c)) = &back[0].geometry else {
            panic!()
        };
        for k in 0..=40 {
            let (a, b) = c.domain();
            let t = a + (b - a) * k as f64 / 40.0;
            let p = c.eval(t).unwrap();
            let r = ((p[0] - 1.0).powi(2) + (p[1] - 2.0).powi(2)).sqrt();
            assert!((r - 2.5).abs() < 1e-14 && (p[2] - 3.0).abs() < 1e-15);
        }
        assert_eq!(back[0].geometry, circle);
    }

    #[test]
    fn surfaces_list_u_fastest() {
        // A bilinear patch: P(i, j) = (i, j, i * j) with 2 x 3 points.
        let mut text = String::new();
        for j in 0..3 {
            for i in 0..2 {
                text += &format!("v {i} {j} {}\n", i * j);
            }
        }
        text += "cstype bspline\ndeg 1 1\nsurf 0 1 0 2 1 2 3 4 5 6\n\
                 parm u 0 0 1 1\nparm v 0 0 1 2 2\nend\n";
        let e = parse(&text).unwrap();
        let Geometry::Surface(Surface::BSpline(s)) = &e[0].geometry else {
            panic!()
        };
        assert_eq!(s.size(), (2, 3));
        assert_eq!(s.points()[3 + 2], [1.0, 2.0, 2.0]); // P_{1,2}
        let back = parse(&write_obj_freeform(&[e[0].geometry.clone()])).unwrap();
        assert_eq!(back[0].geometry, e[0].geometry);
    }

    #[test]
    fn a_bezier_curve_is_its_bspline() {
        let text = "v 0 0 0\nv 1 1 0\nv 2 1 0\nv 3 0 0\nv 4 -1 0\nv 5 -1 0\nv 6 0 0\n\
                    cstype bezier\ndeg 3\ncurv 0 2 1 2 3 4 5 6 7\nparm u 0 1 2\nend\n";
        let e = parse(text).unwrap();
        let Geometry::Curve(Curve::BSpline(c)) = &e[0].geometry else {
            panic!()
        };
        assert_eq!(
            c.knots().as_slice(),
            &[0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 2.0]
        );
        // First segment at t = 0.5: de Casteljau of (0,0), (1,1), (2,1), (3,0).
        assert_eq!(c.eval(0.5).unwrap(), [1.5, 0.75, 0.0]);
    }

    #[test]
    fn refusals_name_the_line() {
        let cases: &[(String, &str)] = &[
            (
                CUBIC.replace("cstype bspline", "cstype cardinal"),
                "t.obj:6: cstype cardinal is not supported",
            ),
            (
                CUBIC.replace("end\n", ""),
                "t.obj:8: curv has no `end` statement",
            ),
            (
                CUBIC.replace("end\n", "trim 0 1 1\nend\n"),
                "t.obj:10: `trim`",
            ),
            (
                CUBIC.replace("curv 0 2", "curv 0 1.5"),
                "t.obj:8: the u parameter range [0, 1.5] is not the knot domain [0, 2]",
            ),
            (
                CUBIC.replace("parm u 0 0 0 0 1 2 2 2 2", "parm u 0 0 0 0 2 2 2 2"),
                "t.obj:8: parm u: 5 control points of degree 3 need 9 knots, got 8",
            ),
            (
                CUBIC.replace("parm u 0 0 0 0 1 2 2 2 2", "parm u 0 0 0 0 3 2 2 2 2"),
                "t.obj:8: parm u: knots decrease",
            ),
            (
                CUBIC.replace("curv 0 2 1 2 3 4 5", "curv 0 2 1 2 3 4 9"),
                "t.obj:8: curv: vertex index 9 is out of range: 5 vertices",
            ),
            (
                CUBIC.replace("curv 0 2 1 2 3 4 5", "curv 0 2 0 2 3 4 5"),
                "t.obj:8: curv: vertex index 0 is invalid",
            ),
            (
                CUBIC.replace("deg 3\n", ""),
                "t.obj:7: curv before any `deg` statement",
            ),
            (
                CUBIC.replace("v 1 2 0\n", "v 1 nan 0\n"),
                "t.obj:2: v: \"nan\" is not finite",
            ),
            (
                CUBIC
                    .replace("cstype bspline", "cstype rat bspline")
                    .replace("v 3 2 0", "v 3 2 0 -1"),
                "t.obj:8: curv: ",
            ),
            (
                CUBIC.replace("parm u", "f 1 2 3\nparm u"),
                "t.obj:9: `f` inside the body of the curv at line 8",
            ),
        ];
        for (text, want) in cases {
            let got = err(text);
            assert!(got.starts_with(want), "want {want:?}\n got {got:?}");
        }
    }

    #[test]
    fn polygons_are_ignored() {
        let text = format!(
            "v 9 9 9\nf 1 1 1\n{}",
            CUBIC.replace("curv 0 2 1 2 3 4 5", "curv 0 2 2 3 4 5 6")
        )
        .replacen("v 0 0 0", "v 0 0 0", 1);
        let e = parse(&text).unwrap();
        assert_eq!(e[0].geometry, parse(CUBIC).unwrap()[0].geometry);
        assert!(parse("v 1 2 3\nf 1 1 1\n").unwrap().is_empty());
    }
}
