//! The paper methods on patches and curves: blending and N-sided hole filling
//! ([Jiang et al.], `subsurf::blend`), as `subsurf blend` and `subsurf fill` run them.

use std::path::PathBuf;

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use subsurf::blend::{BlendJob, BlendJobOptions, FillJob, FillJobOptions, FillOptions};
use subsurf::blend::{JobError, MethodOutput};
use subsurf::io::{read_geometry, write_atomically, write_method_obj};
use subsurf::mesh::Options;
use subsurf::nurbs::{
    BSplineCurve, BSplineSurface, Curve, Geometry, KnotVector, NurbsCurve, NurbsSurface,
    SourcedGeometry, Surface,
};
use subsurf::Scheme;

use crate::arrays::{float_grid, rows_to_py};
use crate::error;
use crate::mesh::Mesh;

/// The knot vector of `count` control points given `knots` (`field` in messages): its
/// degree is what the number of knots implies, `len(knots) − count − 1`.
fn knot_vector(
    knots: &Bound<'_, PyAny>,
    count: usize,
    at: &str,
    field: &str,
) -> PyResult<KnotVector> {
    let (_, knots) = float_grid(knots, &format!("{at}: {field}"))?;
    let Some(degree) = knots.len().checked_sub(count + 1).filter(|&p| p > 0) else {
        return Err(error(format!(
            "{at}: {field} has {} knots for {count} control points; a B-spline of degree p \
             needs {count} + p + 1",
            knots.len()
        )));
    };
    KnotVector::new(degree, knots).map_err(|e| error(format!("{at}: {field}: {e}")))
}

/// The control points of an item, `axes` axes of `(x, y, z)` or homogeneous
/// `(w x, w y, w z, w)` rows: the shape without its last axis, the values, and the length
/// of the last axis (3 or 4).
fn net(
    points: &Bound<'_, PyAny>,
    at: &str,
    axes: usize,
) -> PyResult<(Vec<usize>, Vec<f64>, usize)> {
    let (shape, values) = float_grid(points, &format!("{at}: points"))?;
    match shape.split_last() {
        Some((&d @ (3 | 4), lead)) if lead.len() == axes => Ok((lead.to_vec(), values, d)),
        _ => {
            let what = if axes == 1 {
                "a curve (points, knots) has points of shape (n, 3) or (n, 4)"
            } else {
                "a patch (points, knots_u, knots_v) has points of shape (m, n, 3) or (m, n, 4)"
            };
            Err(PyValueError::new_err(format!(
                "{at}: {what}, not {shape:?}"
            )))
        }
    }
}

/// A curve `(points, knots)` or a patch `(points, knots_u, knots_v)` of a list given to
/// `blend` or `fill`, labelled `at`.
fn item(obj: &Bound<'_, PyAny>, at: String) -> PyResult<SourcedGeometry> {
    let parts: Vec<Bound<'_, PyAny>> = obj.extract().map_err(|_| shape_error(&at))?;
    let rows3 =
        |v: &[f64]| -> Vec<[f64; 3]> { v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect() };
    let rows4 = |v: &[f64]| -> Vec<[f64; 4]> {
        v.chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect()
    };
    let fail = |e: subsurf::nurbs::NurbsError| error(format!("{at}: {e}"));
    let geometry = match parts.as_slice() {
        [points, knots] => {
            let (lead, values, d) = net(points, &at, 1)?;
            let k = knot_vector(knots, lead[0], &at, "knots")?;
            Geometry::Curve(if d == 3 {
                Curve::BSpline(BSplineCurve::new(k, rows3(&values)).map_err(fail)?)
            } else {
                let h = BSplineCurve::new(k, rows4(&values)).map_err(fail)?;
                Curve::Nurbs(NurbsCurve::from_homogeneous(h).map_err(fail)?)
            })
        }
        [points, knots_u, knots_v] => {
            let (lead, values, d) = net(points, &at, 2)?;
            let ku = knot_vector(knots_u, lead[0], &at, "knots_u")?;
            let kv = knot_vector(knots_v, lead[1], &at, "knots_v")?;
            Geometry::Surface(if d == 3 {
                Surface::BSpline(BSplineSurface::new(ku, kv, rows3(&values)).map_err(fail)?)
            } else {
                let h = BSplineSurface::new(ku, kv, rows4(&values)).map_err(fail)?;
                Surface::Nurbs(NurbsSurface::from_homogeneous(h).map_err(fail)?)
            })
        }
        _ => return Err(shape_error(&at)),
    };
    Ok(SourcedGeometry {
        geometry,
        name: None,
        origin: at,
    })
}

fn shape_error(at: &str) -> PyErr {
    PyTypeError::new_err(format!(
        "{at} must be (points, knots) for a curve or (points, knots_u, knots_v) for a patch"
    ))
}

/// The items of `arg`: the curves and patches of a file (a path: JSON documents or OBJ
/// free-form elements, as the command-line tool reads them), or a sequence of curves and
/// patches as arrays, labelled `what[k]` in messages. Also the input's name for messages.
fn items(
    py: Python<'_>,
    arg: &Bound<'_, PyAny>,
    what: &str,
) -> PyResult<(Vec<SourcedGeometry>, String)> {
    if let Ok(path) = arg.extract::<PathBuf>() {
        let items = py.detach(|| read_geometry(&path)).map_err(error)?;
        return Ok((items, path.display().to_string()));
    }
    let list = arg.try_iter().map_err(|_| {
        PyTypeError::new_err(format!(
            "{what} must be a path or a sequence of (points, knots[, knots_v]) tuples"
        ))
    })?;
    let mut out = Vec::new();
    for (k, obj) in list.enumerate() {
        out.push(item(&obj?, format!("{what}[{k}]"))?);
    }
    Ok((out, what.to_owned()))
}

fn job_error(e: JobError) -> PyErr {
    match e {
        JobError::Option(m) => PyValueError::new_err(m),
        e => error(e),
    }
}

/// A blend or fill: the surface, the base patches and boundary curves around it, and the
/// control mesh (`subsurf.blend`, `subsurf.fill`).
#[pyclass(module = "subsurf", name = "BlendResult", frozen)]
pub(crate) struct BlendResult {
    output: MethodOutput,
}

/// `m` as a mesh of `scheme` (the library's default options).
fn mesh_of(m: &subsurf::mesh::PolyMesh, scheme: Scheme) -> Mesh {
    Mesh {
        mesh: m.clone(),
        scheme,
        options: Options::default(),
        normals: None,
    }
}

#[pymethods]
impl BlendResult {
    /// `"blend"` or `"fill"`.
    #[getter]
    fn method(&self) -> &'static str {
        self.output.method
    }

    /// The blend or fill surface: the control mesh refined `levels` times with skirt
    /// removal (scheme `"bilinear"`: it is a surface already).
    #[getter]
    fn surface(&self) -> Mesh {
        mesh_of(&self.output.surface, Scheme::Bilinear)
    }

    /// The control mesh (scheme `"nurss"`, with its knot intervals; its outer ring is the
    /// extension layer).
    #[getter]
    fn control(&self) -> Mesh {
        mesh_of(&self.output.control, Scheme::Nurss)
    }

    /// The base patches tessellated at `samples` segments per knot span (none for a hole
    /// given by curves).
    #[getter]
    fn patches(&self) -> Vec<Mesh> {
        self.output
            .patches
            .iter()
            .map(|m| mesh_of(m, Scheme::Bilinear))
            .collect()
    }

    /// Fill: the boundary curves as `(k, 3)` polylines at `samples` segments per knot span;
    /// blend: an empty list.
    #[getter]
    fn curves<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyAny>>> {
        self.output
            .curves
            .iter()
            .map(|c| rows_to_py(py, c))
            .collect()
    }

    /// A one-line description (the first line of the written file).
    #[getter]
    fn comment(&self) -> &str {
        &self.output.comment
    }

    /// Writes the OBJ file `subsurf blend` / `subsurf fill` writes: the base patches
    /// (`patch_1`, …), the surface (`blend` or `fill`) and the boundary polylines
    /// (`curve_1`, …) as groups. The file appears only once complete.
    fn write(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| write_atomically(&path, |w| write_method_obj(w, &self.output)))?;
        Ok(())
    }

    fn __repr__(&self) -> String {
        format!(
            "<subsurf.BlendResult {}: {} faces, {} base patches, {} curves>",
            self.output.method,
            self.output.surface.num_faces(),
            self.output.patches.len(),
            self.output.curves.len()
        )
    }
}

/// Joins N ≥ 2 bicubic B-spline or NURBS patches C2 with a non-uniform Catmull-Clark
/// (NURSS) surface refined with skirt removal ([Jiang et al.] §3.1, the repository's
/// `docs/references.md`), as `subsurf blend` does. `patches`: a JSON or OBJ free-form file,
/// or a sequence of `(points, knots_u, knots_v)` with `points` `(m, n, 3)` or homogeneous
/// `(m, n, 4)` (`(w x, w y, w z, w)`, NURBS) and full knot vectors (`m + 4`, `n + 4` knots
/// for degree 3), listed in order around the region; each is blended along its first row.
#[pyfunction]
#[pyo3(signature = (patches, *, levels=5, samples=8))]
pub(crate) fn blend(
    py: Python<'_>,
    patches: &Bound<'_, PyAny>,
    levels: u32,
    samples: u32,
) -> PyResult<BlendResult> {
    let (items, name) = items(py, patches, "patches")?;
    let options = BlendJobOptions { levels, samples };
    let output = py
        .detach(|| BlendJob::new(&items, &name, &options)?.run())
        .map_err(job_error)?;
    Ok(BlendResult { output })
}

/// Fills the hole bounded by 3 to 8 cubic B-spline or NURBS curves, or bicubic patches
/// (their first-row boundary), meeting end to end, with a corner-interpolating NURSS
/// surface ([Jiang et al.] Algorithm 1; with `g1`, Algorithm 2: the fill meets the patches
/// with a continuous normal), as `subsurf fill` does. `boundary`: a file, or a sequence of
/// curves `(points, knots)` (`points` `(n, 3)` or homogeneous `(n, 4)`) and patches
/// `(points, knots_u, knots_v)`. `bulge` moves the free inner control points along the
/// boundary's normal by `bulge` times the hole's radius (> 0 convex, < 0 concave).
#[pyfunction]
#[pyo3(signature = (boundary, *, levels=5, bulge=0.0, g1=false, samples=8))]
pub(crate) fn fill(
    py: Python<'_>,
    boundary: &Bound<'_, PyAny>,
    levels: u32,
    bulge: f64,
    g1: bool,
    samples: u32,
) -> PyResult<BlendResult> {
    if !bulge.is_finite() {
        return Err(PyValueError::new_err(format!(
            "bulge {bulge} is not a finite number"
        )));
    }
    let (items, name) = items(py, boundary, "boundary")?;
    let options = FillJobOptions {
        levels,
        samples,
        fill: FillOptions {
            bulge,
            ..FillOptions::default()
        },
        g1,
    };
    let output = py
        .detach(|| FillJob::new(&items, &name, &options)?.run())
        .map_err(job_error)?;
    Ok(BlendResult { output })
}
