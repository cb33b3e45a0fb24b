//! The `subsurf` Python package's extension module (`subsurf._subsurf`): the library's
//! meshes, refinement, exact limit evaluation and tessellation with numpy arrays in and
//! out, in USD's vocabulary (`UsdGeomMesh`'s attribute names and tokens).
//!
//! A thin shell, as the command-line tool is: arguments are checked and converted here,
//! every computation is one call of the `subsurf` crate, made with the interpreter's lock
//! released (so other Python threads run, and the library's own threads do the work).

use std::path::PathBuf;

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::create_exception;
use pyo3::exceptions::{PyImportError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use subsurf::curves::{embed_geometry, interpolate_geometry, HostOptions, InterpolateOptions};
use subsurf::g2cap::{G2Surface, G2SurfaceOptions};
use subsurf::io::{read_geometry, read_mesh, write_atomically, write_obj, write_ply, WriteOptions};
use subsurf::limit::{
    tessellate, BilinearSurface, Derivatives, EvalError, FaceVaryingSurface, LimitSurface,
    LoopSurface, Order, Surface, SurfacePoint,
};
use subsurf::mesh::{
    BoundaryInterpolation, Corner, Crease, CreaseMethod, EdgeInterval, FaceVarying,
    FaceVaryingInterpolation, KnotTags, Options, PolyMesh, Tags, TriangleSubdivision, VertexWeight,
};
use subsurf::nonuniform::{tessellate as nonuniform_tessellate, NurssSurface};
use subsurf::scheme::Adjustable;
use subsurf::spline::{QuadSpline, SubBasisSurface};
use subsurf::{subdivide, Mixed, MixedSurface, Reposer, Scheme, SubdivideOptions};

create_exception!(
    subsurf,
    SubsurfError,
    PyValueError,
    "A mesh, its tags or an evaluation request that subsurf refuses; the message names the \
     face, vertex or point at fault."
);

/// The name of the face-varying channel of texture coordinates (the OBJ reader's `vt`).
const UV: &str = "uv";

fn error(e: impl std::fmt::Display) -> PyErr {
    SubsurfError::new_err(e.to_string())
}

// ---------------------------------------------------------------------------------------
// Tokens (USD's, where USD has the attribute).

/// The scheme of a token: USD's three, and subsurf's shape-adjustable Catmull-Clark
/// (`"adjustable"`: `c` for the first `adjust_steps` levels, then Catmull-Clark) and
/// non-uniform Catmull-Clark (`"nurss"`, with knot intervals).
fn scheme_of(token: &str, c: f64, adjust_steps: u32) -> PyResult<Scheme> {
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

fn scheme_token(scheme: Scheme) -> &'static str {
    match scheme {
        Scheme::Loop => "loop",
        Scheme::Bilinear => "bilinear",
        Scheme::Adjustable(_) => "adjustable",
        Scheme::Nurss => "nurss",
        _ => "catmullClark",
    }
}

fn boundary_of(token: &str) -> PyResult<BoundaryInterpolation> {
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

fn boundary_token(b: BoundaryInterpolation) -> &'static str {
    match b {
        BoundaryInterpolation::None => "none",
        BoundaryInterpolation::EdgeOnly => "edgeOnly",
        BoundaryInterpolation::EdgeAndCorner => "edgeAndCorner",
    }
}

const FVAR_TOKENS: [(&str, FaceVaryingInterpolation); 6] = [
    ("none", FaceVaryingInterpolation::None),
    ("cornersOnly", FaceVaryingInterpolation::CornersOnly),
    ("cornersPlus1", FaceVaryingInterpolation::CornersPlus1),
    ("cornersPlus2", FaceVaryingInterpolation::CornersPlus2),
    ("boundaries", FaceVaryingInterpolation::Boundaries),
    ("all", FaceVaryingInterpolation::All),
];

fn fvar_of(token: &str) -> PyResult<FaceVaryingInterpolation> {
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

fn fvar_token(m: FaceVaryingInterpolation) -> &'static str {
    FVAR_TOKENS
        .iter()
        .find(|(_, x)| *x == m)
        .map_or("all", |&(t, _)| t)
}

fn crease_method_of(token: &str) -> PyResult<CreaseMethod> {
    match token {
        "uniform" => Ok(CreaseMethod::Uniform),
        "chaikin" => Ok(CreaseMethod::Chaikin),
        _ => Err(PyValueError::new_err(format!(
            "crease_method must be \"uniform\" or \"chaikin\", not {token:?}"
        ))),
    }
}

fn triangle_rule_of(token: &str) -> PyResult<TriangleSubdivision> {
    match token {
        "catmullClark" => Ok(TriangleSubdivision::Catmark),
        "smooth" => Ok(TriangleSubdivision::Smooth),
        _ => Err(PyValueError::new_err(format!(
            "triangle_subdivision_rule must be \"catmullClark\" or \"smooth\", not {token:?}"
        ))),
    }
}

// ---------------------------------------------------------------------------------------
// Arrays.

/// `obj` as a C-contiguous numpy array (`numpy.asarray`, with `dtype` when given).
fn asarray<'py>(obj: &Bound<'py, PyAny>, dtype: Option<&str>) -> PyResult<Bound<'py, PyAny>> {
    let np = obj.py().import("numpy")?;
    match dtype {
        Some(d) => np.call_method1("ascontiguousarray", (obj, d)),
        None => np.call_method1("ascontiguousarray", (obj,)),
    }
}

/// `obj` as rows of `N` floats: an `(n, N)` array-like of numbers (any real dtype).
fn float_rows<const N: usize>(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<[f64; N]>> {
    let a = asarray(obj, None)?;
    let kind: String = a.getattr("dtype")?.getattr("kind")?.extract()?;
    let size: usize = a.getattr("size")?.extract()?;
    if size > 0 && !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(PyTypeError::new_err(format!(
            "{name} must hold real numbers, not dtype {}",
            a.getattr("dtype")?.str()?
        )));
    }
    let shape: Vec<usize> = a.getattr("shape")?.extract()?;
    let a = if size == 0 && shape.len() == 1 {
        a.call_method1("reshape", (0, N))?
    } else {
        a
    };
    let shape: Vec<usize> = a.getattr("shape")?.extract()?;
    if shape.len() != 2 || shape[1] != N {
        return Err(PyValueError::new_err(format!(
            "{name} must have shape (n, {N}), not {shape:?}"
        )));
    }
    let a = asarray(&a, Some("float64"))?;
    let a: PyReadonlyArray2<'_, f64> = a.extract()?;
    let flat = a.as_slice()?;
    let rows: Vec<[f64; N]> = flat
        .chunks_exact(N)
        .map(|c| std::array::from_fn(|k| c[k]))
        .collect();
    if let Some(i) = flat.iter().position(|x| !x.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "{name}[{}] has a value that is not finite ({})",
            i / N,
            flat[i]
        )));
    }
    Ok(rows)
}

/// `obj` as a flat array of floats (any real dtype, any shape flattened).
fn float_array(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    let a = asarray(obj, None)?;
    let kind: String = a.getattr("dtype")?.getattr("kind")?.extract()?;
    let size: usize = a.getattr("size")?.extract()?;
    if size > 0 && !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(PyTypeError::new_err(format!(
            "{name} must hold real numbers, not dtype {}",
            a.getattr("dtype")?.str()?
        )));
    }
    let a = asarray(&a.call_method0("ravel")?, Some("float64"))?;
    let a: PyReadonlyArray1<'_, f64> = a.extract()?;
    Ok(a.as_slice()?.to_vec())
}

/// `obj` as a flat array of indices (integers from 0 to `u32::MAX - 1`; any integer dtype).
fn index_array(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<u32>> {
    let a = asarray(obj, None)?;
    let kind: String = a.getattr("dtype")?.getattr("kind")?.extract()?;
    let size: usize = a.getattr("size")?.extract()?;
    if size > 0 && !matches!(kind.as_str(), "i" | "u") {
        return Err(PyTypeError::new_err(format!(
            "{name} must hold integers, not dtype {}",
            a.getattr("dtype")?.str()?
        )));
    }
    let a = asarray(&a.call_method0("ravel")?, Some("int64"))?;
    let a: PyReadonlyArray1<'_, i64> = a.extract()?;
    a.as_slice()?
        .iter()
        .enumerate()
        .map(|(i, &x)| {
            u32::try_from(x)
                .ok()
                .filter(|&x| x != u32::MAX)
                .ok_or_else(|| {
                    PyValueError::new_err(format!("{name}[{i}] = {x} is not a valid index"))
                })
        })
        .collect()
}

fn optional<T>(
    obj: Option<&Bound<'_, PyAny>>,
    read: impl FnOnce(&Bound<'_, PyAny>) -> PyResult<T>,
) -> PyResult<Option<T>> {
    match obj {
        Some(o) if !o.is_none() => read(o).map(Some),
        _ => Ok(None),
    }
}

/// `rows` as an `(n, N)` float64 array (the vector's buffer handed to numpy, reshaped).
fn rows_to_py<'py, const N: usize>(
    py: Python<'py>,
    rows: &[[f64; N]],
) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([rows.len(), N])?
        .into_any())
}

fn indices_to_py<'py>(py: Python<'py>, v: impl Iterator<Item = u32>) -> Bound<'py, PyAny> {
    let v: Vec<i32> = v.map(|x| x as i32).collect();
    PyArray1::from_vec(py, v).into_any()
}

// ---------------------------------------------------------------------------------------
// Meshes.

/// The sharp edges of USD's crease attributes: chains of `lengths[k]` vertices of `indices`,
/// with one sharpness per chain or one per edge.
fn usd_creases(indices: &[u32], lengths: &[u32], sharpnesses: &[f64]) -> PyResult<Vec<Crease>> {
    let total: u64 = lengths.iter().map(|&l| u64::from(l)).sum();
    if total != indices.len() as u64 {
        return Err(PyValueError::new_err(format!(
            "crease_lengths sum to {total}, but crease_indices has {} entries",
            indices.len()
        )));
    }
    if let Some(k) = lengths.iter().position(|&l| l < 2) {
        return Err(PyValueError::new_err(format!(
            "crease_lengths[{k}] = {}: a crease runs through at least 2 vertices",
            lengths[k]
        )));
    }
    let edges = indices.len() - lengths.len();
    let per_edge = sharpnesses.len() == edges && edges != lengths.len();
    if sharpnesses.len() != lengths.len() && !per_edge {
        return Err(PyValueError::new_err(format!(
            "crease_sharpnesses has {} values: one per crease ({}) or one per crease edge ({edges})",
            sharpnesses.len(),
            lengths.len()
        )));
    }
    let mut creases = Vec::with_capacity(edges);
    let mut start = 0;
    for (k, &len) in lengths.iter().enumerate() {
        let chain = &indices[start..start + len as usize];
        for (e, pair) in chain.windows(2).enumerate() {
            let s = if per_edge {
                sharpnesses[creases.len()]
            } else {
                sharpnesses[k]
            };
            if s.is_nan() || s < 0.0 {
                return Err(PyValueError::new_err(format!(
                    "crease {k}, edge {e}: sharpness {s} is not a non-negative number"
                )));
            }
            creases.push(Crease {
                v0: pair[0],
                v1: pair[1],
                sharpness: s as f32,
            });
        }
        start += len as usize;
    }
    Ok(creases)
}

/// The texture-coordinate channel: `uvs` indexed by `uv_indices` (one per face corner), or
/// without indices one value per vertex (vertex-varying) or per face corner.
fn uv_channel(
    uvs: Vec<[f64; 2]>,
    uv_indices: Option<Vec<u32>>,
    face_verts: &[u32],
    num_points: usize,
) -> PyResult<FaceVarying> {
    let indices = match uv_indices {
        Some(i) => i,
        None if uvs.len() == face_verts.len() => (0..face_verts.len() as u32).collect(),
        None if uvs.len() == num_points => face_verts.to_vec(),
        None => {
            return Err(PyValueError::new_err(format!(
                "uvs has {} rows but no uv_indices: give one per face corner ({}) or per point \
                 ({num_points}), or give uv_indices",
                uvs.len(),
                face_verts.len()
            )))
        }
    };
    let values = uvs.into_iter().flatten().collect();
    FaceVarying::new(UV, 2, values, indices).map_err(error)
}

/// A polygon mesh with its subdivision options, as `UsdGeomMesh` holds one: points, faces,
/// creases, corners, holes, texture coordinates and the scheme's settings.
#[pyclass(module = "subsurf", name = "Mesh", frozen)]
struct Mesh {
    mesh: PolyMesh,
    scheme: Scheme,
    options: Options,
    /// Limit normals per point (`subdivide(limit=True)`, tessellations).
    normals: Option<Vec<[f64; 3]>>,
}

impl Mesh {
    fn uv(&self) -> Option<&FaceVarying> {
        self.mesh.face_varying.iter().find(|c| c.name() == UV)
    }

    fn derived(&self, mesh: PolyMesh, normals: Option<Vec<[f64; 3]>>) -> Self {
        Self {
            mesh,
            scheme: self.scheme,
            options: self.options,
            normals,
        }
    }
}

#[pymethods]
impl Mesh {
    #[new]
    #[pyo3(signature = (
        points, face_vertex_counts, face_vertex_indices, *,
        crease_indices=None, crease_lengths=None, crease_sharpnesses=None,
        corner_indices=None, corner_sharpnesses=None, hole_indices=None,
        interpolate_boundary="edgeOnly", scheme="catmullClark",
        uvs=None, uv_indices=None, face_varying_linear_interpolation="all",
        crease_method="uniform", triangle_subdivision_rule="catmullClark",
        c=0.5, adjust_steps=1, knot_interval_indices=None, knot_intervals=None, weights=None,
    ))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        points: &Bound<'_, PyAny>,
        face_vertex_counts: &Bound<'_, PyAny>,
        face_vertex_indices: &Bound<'_, PyAny>,
        crease_indices: Option<&Bound<'_, PyAny>>,
        crease_lengths: Option<&Bound<'_, PyAny>>,
        crease_sharpnesses: Option<&Bound<'_, PyAny>>,
        corner_indices: Option<&Bound<'_, PyAny>>,
        corner_sharpnesses: Option<&Bound<'_, PyAny>>,
        hole_indices: Option<&Bound<'_, PyAny>>,
        interpolate_boundary: &str,
        scheme: &str,
        uvs: Option<&Bound<'_, PyAny>>,
        uv_indices: Option<&Bound<'_, PyAny>>,
        face_varying_linear_interpolation: &str,
        crease_method: &str,
        triangle_subdivision_rule: &str,
        c: f64,
        adjust_steps: u32,
        knot_interval_indices: Option<&Bound<'_, PyAny>>,
        knot_intervals: Option<&Bound<'_, PyAny>>,
        weights: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let scheme = scheme_of(scheme, c, adjust_steps)?;
        let options = Options {
            boundary: boundary_of(interpolate_boundary)?,
            crease_method: crease_method_of(crease_method)?,
            triangles: triangle_rule_of(triangle_subdivision_rule)?,
            face_varying: fvar_of(face_varying_linear_interpolation)?,
        };
        let positions = float_rows::<3>(points, "points")?;
        let counts = index_array(face_vertex_counts, "face_vertex_counts")?;
        let face_verts = index_array(face_vertex_indices, "face_vertex_indices")?;
        let mut offsets = Vec::with_capacity(counts.len() + 1);
        offsets.push(0u32);
        let mut total = 0u64;
        for &c in &counts {
            total += u64::from(c);
            offsets.push(u32::try_from(total).map_err(|_| error("too many face vertices"))?);
        }
        if total != face_verts.len() as u64 {
            return Err(PyValueError::new_err(format!(
                "face_vertex_counts sum to {total}, but face_vertex_indices has {} entries",
                face_verts.len()
            )));
        }
        let num_points = positions.len();
        let mut mesh = PolyMesh::new(positions, offsets, face_verts).map_err(error)?;
        mesh.tags = Tags {
            creases: match optional(crease_indices, |o| index_array(o, "crease_indices"))? {
                None => Vec::new(),
                Some(ci) => {
                    let lengths = optional(crease_lengths, |o| index_array(o, "crease_lengths"))?
                        .ok_or_else(|| {
                        PyValueError::new_err("crease_indices need crease_lengths")
                    })?;
                    let sharp =
                        optional(crease_sharpnesses, |o| float_array(o, "crease_sharpnesses"))?
                            .ok_or_else(|| {
                                PyValueError::new_err("crease_indices need crease_sharpnesses")
                            })?;
                    usd_creases(&ci, &lengths, &sharp)?
                }
            },
            corners: corners(corner_indices, corner_sharpnesses)?,
            holes: optional(hole_indices, |o| index_array(o, "hole_indices"))?.unwrap_or_default(),
        };
        if let Some(uvs) = optional(uvs, |o| float_rows::<2>(o, "uvs"))? {
            let indices = optional(uv_indices, |o| index_array(o, "uv_indices"))?;
            let channel = uv_channel(uvs, indices, mesh.face_verts(), num_points)?;
            mesh.face_varying.push(channel);
        } else if optional(uv_indices, |_| Ok(()))?.is_some() {
            return Err(PyValueError::new_err("uv_indices given without uvs"));
        }
        mesh.knots = knot_tags(knot_interval_indices, knot_intervals, weights)?;
        if !mesh.knots.is_empty() && scheme != Scheme::Nurss {
            return Err(PyValueError::new_err(
                "knot intervals and weights are the input of scheme=\"nurss\" only",
            ));
        }
        mesh.validate().map_err(error)?;
        Ok(Self {
            mesh,
            scheme,
            options,
            normals: None,
        })
    }

    /// The points, an `(n, 3)` float64 array (a copy).
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        rows_to_py(py, self.mesh.positions())
    }

    /// The number of corners of each face (int32).
    #[getter]
    fn face_vertex_counts<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        indices_to_py(py, self.mesh.face_offsets().windows(2).map(|w| w[1] - w[0]))
    }

    /// The corners of every face, face after face (int32).
    #[getter]
    fn face_vertex_indices<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        indices_to_py(py, self.mesh.face_verts().iter().copied())
    }

    /// The sharp edges' vertices, two per edge (each crease of `crease_lengths` is one edge).
    #[getter]
    fn crease_indices<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let c = &self.mesh.tags.creases;
        indices_to_py(py, c.iter().flat_map(|c| [c.v0, c.v1]))
    }

    /// 2 for every sharp edge.
    #[getter]
    fn crease_lengths<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        indices_to_py(py, self.mesh.tags.creases.iter().map(|_| 2))
    }

    /// The sharpness of every sharp edge (float64).
    #[getter]
    fn crease_sharpnesses<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let s = self
            .mesh
            .tags
            .creases
            .iter()
            .map(|c| f64::from(c.sharpness));
        PyArray1::from_vec(py, s.collect()).into_any()
    }

    /// The sharp vertices (int32).
    #[getter]
    fn corner_indices<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        indices_to_py(py, self.mesh.tags.corners.iter().map(|c| c.vertex))
    }

    /// The sharpness of every sharp vertex (float64).
    #[getter]
    fn corner_sharpnesses<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let s = self
            .mesh
            .tags
            .corners
            .iter()
            .map(|c| f64::from(c.sharpness));
        PyArray1::from_vec(py, s.collect()).into_any()
    }

    /// The faces that are holes (int32).
    #[getter]
    fn hole_indices<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        indices_to_py(py, self.mesh.tags.holes.iter().copied())
    }

    /// The texture coordinates' values, an `(m, 2)` float64 array, or `None`.
    #[getter]
    fn uvs<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let Some(c) = self.uv() else { return Ok(None) };
        let rows: Vec<[f64; 2]> = c
            .values()
            .chunks_exact(c.dim())
            .map(|x| [x[0], x.get(1).copied().unwrap_or(0.0)])
            .collect();
        rows_to_py(py, &rows).map(Some)
    }

    /// The texture coordinate of every face corner (indices into `uvs`, int32), or `None`.
    #[getter]
    fn uv_indices<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyAny>> {
        self.uv()
            .map(|c| indices_to_py(py, c.indices().iter().copied()))
    }

    /// Unit limit normals per point (`subdivide(limit=True)` and `tessellate`), or `None`.
    #[getter]
    fn normals<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.normals
            .as_deref()
            .map(|n| rows_to_py(py, n))
            .transpose()
    }

    /// `"catmullClark"`, `"loop"` or `"bilinear"`.
    #[getter]
    fn scheme(&self) -> &'static str {
        scheme_token(self.scheme)
    }

    /// The shape parameter `c` of the adjustable scheme, or `None`.
    #[getter]
    fn c(&self) -> Option<f64> {
        match self.scheme {
            Scheme::Adjustable(m) => Some(m.scheme.c()),
            _ => None,
        }
    }

    /// The levels refined by the adjustable scheme before Catmull-Clark, or `None`.
    #[getter]
    fn adjust_steps(&self) -> Option<u32> {
        match self.scheme {
            Scheme::Adjustable(m) => Some(m.steps),
            _ => None,
        }
    }

    /// `"none"`, `"edgeOnly"` or `"edgeAndCorner"`.
    #[getter]
    fn interpolate_boundary(&self) -> &'static str {
        boundary_token(self.options.boundary)
    }

    /// One of `"none"`, `"cornersOnly"`, `"cornersPlus1"`, `"cornersPlus2"`,
    /// `"boundaries"`, `"all"`.
    #[getter]
    fn face_varying_linear_interpolation(&self) -> &'static str {
        fvar_token(self.options.face_varying)
    }

    /// `"uniform"` or `"chaikin"`.
    #[getter]
    fn crease_method(&self) -> &'static str {
        match self.options.crease_method {
            CreaseMethod::Uniform => "uniform",
            CreaseMethod::Chaikin => "chaikin",
        }
    }

    /// `"catmullClark"` or `"smooth"`.
    #[getter]
    fn triangle_subdivision_rule(&self) -> &'static str {
        match self.options.triangles {
            TriangleSubdivision::Catmark => "catmullClark",
            TriangleSubdivision::Smooth => "smooth",
        }
    }

    /// The number of points.
    #[getter]
    fn num_points(&self) -> usize {
        self.mesh.num_vertices()
    }

    /// The number of faces.
    #[getter]
    fn num_faces(&self) -> usize {
        self.mesh.num_faces()
    }

    fn __repr__(&self) -> String {
        format!(
            "subsurf.Mesh({} points, {} faces, scheme={:?}{})",
            self.mesh.num_vertices(),
            self.mesh.num_faces(),
            scheme_token(self.scheme),
            if self.uv().is_some() { ", uvs" } else { "" }
        )
    }

    /// Refines the mesh `levels` times with its scheme, exactly as OpenSubdiv's
    /// `Far::TopologyRefiner::RefineUniform` and `PrimvarRefiner` number and compute it.
    /// With `limit`, the last level's points (and texture coordinates) move to their limit
    /// and `normals` holds the limit normals.
    #[pyo3(signature = (levels, *, limit=false))]
    fn subdivide(&self, py: Python<'_>, levels: u32, limit: bool) -> PyResult<Self> {
        let opts = SubdivideOptions {
            levels,
            scheme: self.scheme,
            options: self.options,
            limit,
            ..SubdivideOptions::default()
        };
        let sub = py.detach(|| subdivide(&self.mesh, &opts)).map_err(error)?;
        Ok(self.derived(sub.mesh, sub.normals))
    }

    /// The exact limit surface of the mesh under its scheme (and of its texture
    /// coordinates), to evaluate at any `(face, u, v)`.
    fn limit_surface(&self, py: Python<'_>) -> PyResult<SurfaceObject> {
        py.detach(|| SurfaceObject::limit(self)).map_err(error)
    }

    /// The surface with G2 caps at the extraordinary vertices (Tang, Li, Liu and Gu, "Smooth
    /// Connection near Singular Points on Subdivision Surfaces", Advances in Applied
    /// Mathematics 6(9), 2017; `subsurf::g2cap`): the limit
    /// surface of the Catmull-Clark (or adjustable) scheme with the neighbourhood of each
    /// extraordinary vertex, after `levels` isolation levels (default 2, or 3 with non-quad
    /// faces), replaced by bi-septic patches that are curvature continuous.
    #[pyo3(signature = (levels=None))]
    fn g2_surface(&self, py: Python<'_>, levels: Option<u32>) -> PyResult<SurfaceObject> {
        py.detach(|| SurfaceObject::g2(self, levels)).map_err(error)
    }

    /// The rational bicubic spline surface of the sub-basis functions ([Sub-basis splines]
    /// in the repository's `docs/references.md`: the uniform bicubic B-spline basis split
    /// into sub-basis functions, rebuilt at irregular vertices; `subsurf::spline`): over
    /// the mesh's faces, or over those of its first Catmull-Clark level when it has faces
    /// that are not quads (`Surface.mesh`).
    fn spline_surface(&self, py: Python<'_>) -> PyResult<SurfaceObject> {
        py.detach(|| SurfaceObject::spline(self)).map_err(error)
    }

    /// A watertight tessellation of the limit surface (`limit_surface().tessellate`; NURSS
    /// faces without an exact evaluation sampled through refinement).
    #[pyo3(signature = (rate=8, *, triangles=false))]
    fn tessellate(&self, py: Python<'_>, rate: u32, triangles: bool) -> PyResult<Self> {
        py.detach(|| SurfaceObject::limit(self)?.tessellation(rate, triangles))
            .map_err(error)
    }

    /// Writes the mesh to `path`: OBJ (`.obj`, with its tags, texture coordinates and
    /// normals) or PLY (`.ply`, points, normals and faces; a mesh with texture coordinates
    /// or tags is refused, as PLY would drop them). The file appears only once complete.
    fn write(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("obj") => {
                let opts = WriteOptions {
                    normals: self.normals.as_deref(),
                    scheme: Some(self.options),
                    comment: Some("written by subsurf (Python)"),
                };
                py.detach(|| write_atomically(&path, |w| write_obj(w, &self.mesh, &opts)))?;
            }
            Some("ply") => {
                if self.uv().is_some() || !self.mesh.tags.is_empty() {
                    return Err(error(format!(
                        "{}: PLY would drop the mesh's texture coordinates or tags; write .obj",
                        path.display()
                    )));
                }
                let m = &self.mesh;
                py.detach(|| {
                    write_atomically(&path, |w| {
                        let n = self.normals.as_deref();
                        write_ply(w, m.positions(), n, m.face_offsets(), m.face_verts())
                    })
                })?;
            }
            _ => {
                return Err(PyValueError::new_err(format!(
                    "{}: write .obj or .ply",
                    path.display()
                )))
            }
        }
        Ok(())
    }

    /// A mesh from a `trimesh.Trimesh` (its `vertices` and `faces`; any object with those
    /// attributes), with the given scheme (`"loop"` suits triangle meshes).
    #[staticmethod]
    #[pyo3(signature = (mesh, *, scheme="loop"))]
    fn from_trimesh(mesh: &Bound<'_, PyAny>, scheme: &str) -> PyResult<Self> {
        let py = mesh.py();
        let faces = asarray(&mesh.getattr("faces")?, Some("int64"))?;
        let n: usize = faces.getattr("shape")?.get_item(0)?.extract()?;
        let k: usize = faces.getattr("shape")?.get_item(1)?.extract()?;
        let counts = PyArray1::from_vec(py, vec![k as i64; n]);
        let kwargs = pyo3::types::PyDict::new(py);
        kwargs.set_item("scheme", scheme)?;
        let cls = py.get_type::<Mesh>();
        cls.call((mesh.getattr("vertices")?, counts, faces), Some(&kwargs))?
            .extract::<Mesh>()
    }

    /// The mesh as a `trimesh.Trimesh` (faces split into triangles as fans from their first
    /// corner; `process=False`, so nothing is merged or reordered). Needs trimesh.
    fn to_trimesh<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let trimesh = py.import("trimesh").map_err(|e| {
            PyImportError::new_err(format!("to_trimesh needs the trimesh package: {e}"))
        })?;
        let mut tris: Vec<i64> = Vec::new();
        for f in self.mesh.faces() {
            for i in 1..f.len() - 1 {
                tris.extend([f[0], f[i], f[i + 1]].map(i64::from));
            }
        }
        let n = tris.len() / 3;
        let faces = PyArray1::from_vec(py, tris).reshape([n, 3])?;
        let kwargs = pyo3::types::PyDict::new(py);
        kwargs.set_item("vertices", self.points(py)?)?;
        kwargs.set_item("faces", faces)?;
        kwargs.set_item("process", false)?;
        trimesh.getattr("Trimesh")?.call((), Some(&kwargs))
    }
}

impl<'py> FromPyObject<'_, 'py> for Mesh {
    type Error = PyErr;
    fn extract(obj: Borrowed<'_, 'py, PyAny>) -> PyResult<Self> {
        let m = obj.cast::<Mesh>()?.get();
        Ok(Self {
            mesh: m.mesh.clone(),
            scheme: m.scheme,
            options: m.options,
            normals: m.normals.clone(),
        })
    }
}

fn corners(
    indices: Option<&Bound<'_, PyAny>>,
    sharpnesses: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<Corner>> {
    let Some(ci) = optional(indices, |o| index_array(o, "corner_indices"))? else {
        return Ok(Vec::new());
    };
    let cs = optional(sharpnesses, |o| float_array(o, "corner_sharpnesses"))?
        .ok_or_else(|| PyValueError::new_err("corner_indices need corner_sharpnesses"))?;
    if cs.len() != ci.len() {
        return Err(PyValueError::new_err(format!(
            "corner_sharpnesses has {} values for {} corner_indices",
            cs.len(),
            ci.len()
        )));
    }
    ci.iter()
        .zip(&cs)
        .enumerate()
        .map(|(k, (&vertex, &s))| {
            if s.is_nan() || s < 0.0 {
                return Err(PyValueError::new_err(format!(
                    "corner_sharpnesses[{k}] = {s} is not a non-negative number"
                )));
            }
            Ok(Corner {
                vertex,
                sharpness: s as f32,
            })
        })
        .collect()
}

/// NURSS's knot tags: an interval per edge of `(k, 2)` `indices`, and one rational weight
/// per point (all 1 when absent).
fn knot_tags(
    indices: Option<&Bound<'_, PyAny>>,
    intervals: Option<&Bound<'_, PyAny>>,
    weights: Option<&Bound<'_, PyAny>>,
) -> PyResult<KnotTags> {
    let mut tags = KnotTags::default();
    if let Some(edges) = optional(indices, |o| index_array(o, "knot_interval_indices"))? {
        let values = optional(intervals, |o| float_array(o, "knot_intervals"))?
            .ok_or_else(|| PyValueError::new_err("knot_interval_indices need knot_intervals"))?;
        if edges.len() != 2 * values.len() {
            return Err(PyValueError::new_err(format!(
                "knot_interval_indices has {} entries for {} knot_intervals (two per edge)",
                edges.len(),
                values.len()
            )));
        }
        tags.intervals = edges
            .chunks_exact(2)
            .zip(values)
            .map(|(e, interval)| EdgeInterval {
                v0: e[0],
                v1: e[1],
                interval,
            })
            .collect();
    }
    if let Some(w) = optional(weights, |o| float_array(o, "weights"))? {
        tags.weights = VertexWeight::tags(&w);
    }
    Ok(tags)
}

// ---------------------------------------------------------------------------------------
// Limit surfaces.

/// The limit surface of one scheme.
enum AnySurface {
    CatmullClark(LimitSurface),
    Loop(Box<LoopSurface>),
    Bilinear(BilinearSurface),
    Mixed(Box<MixedSurface>),
    Nurss(Box<NurssSurface>),
    G2(Box<G2Surface>),
    Spline(Box<SubBasisSurface>),
}

impl AnySurface {
    fn as_dyn(&self) -> &dyn Surface {
        match self {
            Self::CatmullClark(s) => s,
            Self::Loop(s) => &**s,
            Self::Bilinear(s) => s,
            Self::Mixed(s) => &**s,
            Self::Nurss(s) => &**s,
            Self::G2(s) => &**s,
            Self::Spline(s) => &**s,
        }
    }
}

/// A smooth surface over the faces of a mesh: its exact limit surface
/// (`Mesh.limit_surface()`, as OpenSubdiv's `Bfr::Surface` evaluates it, with the limit of
/// its texture coordinates), its G2-capped surface or its sub-basis spline surface.
#[pyclass(module = "subsurf", name = "Surface", frozen)]
struct SurfaceObject {
    surface: AnySurface,
    /// The texture coordinates' limit, or why there is none (raised when asked for).
    uv: Result<Option<FaceVaryingSurface>, String>,
    /// The mesh whose faces the surface is parametrised over.
    base: Mesh,
    kind: &'static str,
}

impl SurfaceObject {
    fn limit(m: &Mesh) -> Result<Self, String> {
        let s = |e: &dyn std::fmt::Display| e.to_string();
        let surface = match m.scheme {
            Scheme::Loop => AnySurface::Loop(Box::new(
                LoopSurface::new(&m.mesh, m.options).map_err(|e| s(&e))?,
            )),
            Scheme::Bilinear => {
                AnySurface::Bilinear(BilinearSurface::new(&m.mesh).map_err(|e| s(&e))?)
            }
            Scheme::Adjustable(mixed) => AnySurface::Mixed(Box::new(
                MixedSurface::new(&m.mesh, m.options, mixed).map_err(|e| s(&e))?,
            )),
            Scheme::Nurss => AnySurface::Nurss(Box::new(
                NurssSurface::new(&m.mesh, &m.options).map_err(|e| s(&e))?,
            )),
            _ => {
                AnySurface::CatmullClark(LimitSurface::new(&m.mesh, m.options).map_err(|e| s(&e))?)
            }
        };
        let uv = match m.mesh.face_varying.iter().position(|c| c.name() == UV) {
            Some(c) => FaceVaryingSurface::for_scheme(&m.mesh, m.scheme, m.options, c)
                .map(Some)
                .map_err(|e| format!("texture coordinates: {e}")),
            None => Ok(None),
        };
        Ok(Self {
            surface,
            uv,
            base: m.derived(m.mesh.clone(), None),
            kind: "limit",
        })
    }

    fn g2(m: &Mesh, levels: Option<u32>) -> Result<Self, String> {
        let opts = G2SurfaceOptions {
            scheme: m.scheme,
            options: m.options,
            levels,
            ..G2SurfaceOptions::default()
        };
        let surface = G2Surface::new(&m.mesh, &opts).map_err(|e| e.to_string())?;
        Ok(Self {
            surface: AnySurface::G2(Box::new(surface)),
            uv: Err(NO_UV.to_owned()),
            base: m.derived(m.mesh.clone(), None),
            kind: "g2",
        })
    }

    fn spline(m: &Mesh) -> Result<Self, String> {
        let q = QuadSpline::new(&m.mesh).map_err(|e| e.to_string())?;
        Ok(Self {
            surface: AnySurface::Spline(Box::new(q.surface)),
            uv: Err(NO_UV.to_owned()),
            base: m.derived(q.control, None),
            kind: "spline",
        })
    }

    /// The tessellation of the surface at `rate` as a mesh (scheme `"bilinear"`: it is a
    /// surface already) with normals and, for a limit surface, texture coordinates.
    fn tessellation(&self, rate: u32, triangles: bool) -> Result<Mesh, String> {
        let m = &self.base;
        let t = if let AnySurface::Nurss(_) = self.surface {
            // NURSS faces without an exact evaluation are sampled through refinement (the
            // tessellation's texture coordinates included).
            nonuniform_tessellate(&m.mesh, &m.options, rate, triangles)
                .map_err(|e| e.to_string())?
        } else {
            let mut t = tessellate(self.surface.as_dyn(), &m.mesh, rate, triangles)
                .map_err(|e| e.to_string())?;
            if let Ok(Some(uv)) = &self.uv {
                let channel = t
                    .evaluate_face_varying(&m.mesh, uv, UV)
                    .map_err(|e| e.to_string())?;
                t.face_varying.push(channel);
            } else if let (Err(e), Some(_)) = (&self.uv, m.uv()) {
                return Err(format!("{e}; tessellate the limit surface to keep them"));
            }
            t
        };
        Ok(Mesh {
            mesh: t.to_polymesh().map_err(|e| e.to_string())?,
            scheme: Scheme::Bilinear,
            options: m.options,
            normals: Some(t.normals),
        })
    }
}

/// Why a G2 or spline surface has no texture coordinates.
const NO_UV: &str = "texture coordinates are evaluated on the limit surface only \
                     (Mesh.limit_surface())";

/// The points `(face, subface, u, v)` of the arrays given to `evaluate`.
fn surface_points(
    face_ids: &Bound<'_, PyAny>,
    u: &Bound<'_, PyAny>,
    v: &Bound<'_, PyAny>,
    subfaces: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<SurfacePoint>> {
    let faces = index_array(face_ids, "face_ids")?;
    let u = float_array(u, "u")?;
    let v = float_array(v, "v")?;
    let subs = optional(subfaces, |o| index_array(o, "subfaces"))?;
    let n = faces.len();
    if u.len() != n || v.len() != n || subs.as_ref().is_some_and(|s| s.len() != n) {
        return Err(PyValueError::new_err(format!(
            "face_ids, u, v (and subfaces) must have one entry per point: {n}, {}, {}{}",
            u.len(),
            v.len(),
            subs.as_ref()
                .map_or(String::new(), |s| format!(", {}", s.len()))
        )));
    }
    Ok((0..n)
        .map(|i| SurfacePoint {
            face: faces[i],
            subface: subs.as_ref().map_or(0, |s| s[i]),
            u: u[i],
            v: v[i],
        })
        .collect())
}

fn point_error(i: usize, p: SurfacePoint, e: &EvalError) -> PyErr {
    error(format!(
        "point {i} (face {}, subface {}, u {}, v {}): {e}",
        p.face, p.subface, p.u, p.v
    ))
}

#[pymethods]
impl SurfaceObject {
    /// Position and first derivatives (and with `second`, the second derivatives `duu`,
    /// `duv`, `dvv`) at every point `(face_ids[i], u[i], v[i])`, as `(n, 3)` float64 arrays.
    /// Quads and Loop triangles are one parameter domain each (a triangle's is
    /// `u, v ≥ 0, u + v ≤ 1`); an `n`-gon has `n` quad sub-faces, chosen by `subfaces`.
    #[pyo3(signature = (face_ids, u, v, *, subfaces=None, second=false))]
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        face_ids: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        subfaces: Option<&Bound<'py, PyAny>>,
        second: bool,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let points = surface_points(face_ids, u, v, subfaces)?;
        let order = if second { Order::Second } else { Order::First };
        let results = py.detach(|| {
            let mut out = vec![Ok(Derivatives::default()); points.len()];
            self.surface
                .as_dyn()
                .evaluate_many(&points, order, &mut out);
            out
        });
        let mut d = Vec::with_capacity(results.len());
        for (i, r) in results.into_iter().enumerate() {
            d.push(r.map_err(|e| point_error(i, points[i], &e))?);
        }
        let field =
            |f: fn(&Derivatives) -> [f64; 3]| rows_to_py(py, &d.iter().map(f).collect::<Vec<_>>());
        let mut out = vec![field(|d| d.p)?, field(|d| d.du)?, field(|d| d.dv)?];
        if second {
            out.extend([field(|d| d.duu)?, field(|d| d.duv)?, field(|d| d.dvv)?]);
        }
        PyTuple::new(py, out)
    }

    /// The limit of the texture coordinates at every point, an `(n, 2)` float64 array
    /// (the mesh's `face_varying_linear_interpolation` applies).
    #[pyo3(signature = (face_ids, u, v, *, subfaces=None))]
    fn evaluate_uv<'py>(
        &self,
        py: Python<'py>,
        face_ids: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        subfaces: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let Some(uv) = self.uv.as_ref().map_err(error)? else {
            return Err(error("the mesh has no texture coordinates (uvs)"));
        };
        let points = surface_points(face_ids, u, v, subfaces)?;
        let values = py.detach(|| {
            points
                .iter()
                .enumerate()
                .map(|(i, &p)| {
                    uv.eval_point(p)
                        .map(|c| [c.value[0], c.value.get(1).copied().unwrap_or(0.0)])
                        .map_err(|e| (i, p, e))
                })
                .collect::<Result<Vec<[f64; 2]>, _>>()
        });
        let values = values.map_err(|(i, p, e)| point_error(i, p, &e))?;
        rows_to_py(py, &values)
    }

    /// The number of faces of the control mesh.
    #[getter]
    fn num_faces(&self) -> usize {
        self.surface.as_dyn().num_faces()
    }

    /// `"limit"`, `"g2"` or `"spline"`.
    #[getter]
    fn kind(&self) -> &'static str {
        self.kind
    }

    /// The mesh whose faces `evaluate` takes: the mesh itself, or for a spline surface of a
    /// mesh with non-quad faces, its first Catmull-Clark level.
    #[getter]
    fn mesh(&self) -> Mesh {
        self.base.derived(self.base.mesh.clone(), None)
    }

    /// A watertight tessellation: each quad face (each sub-face of other polygons) becomes
    /// `rate × rate` quads, each Loop triangle `rate²` triangles (quads split into triangles
    /// with `triangles`), with the surface's normals and, on a limit surface, the limit of
    /// the texture coordinates. The result's scheme is `"bilinear"`: it is a surface
    /// already.
    #[pyo3(signature = (rate=8, *, triangles=false))]
    fn tessellate(&self, py: Python<'_>, rate: u32, triangles: bool) -> PyResult<Mesh> {
        py.detach(|| self.tessellation(rate, triangles))
            .map_err(error)
    }
}

// ---------------------------------------------------------------------------------------
// Re-posing.

/// Refinement of one mesh in many poses (animation): the topology and the masks are
/// computed once (`subsurf::Reposer`, a `RefinePlan`), and each pose costs only the
/// interpolation of its points.
#[pyclass(module = "subsurf", name = "Reposer")]
struct ReposerObject {
    reposer: Reposer,
    base: Mesh,
}

#[pymethods]
impl ReposerObject {
    /// The re-posing of `mesh` refined `levels` times; with `limit`, each pose's points
    /// move to their limit and `normals` holds the limit normals.
    #[new]
    #[pyo3(signature = (mesh, levels, *, limit=false))]
    fn new(py: Python<'_>, mesh: &Mesh, levels: u32, limit: bool) -> PyResult<Self> {
        let opts = SubdivideOptions {
            levels,
            scheme: mesh.scheme,
            options: mesh.options,
            limit,
            ..SubdivideOptions::default()
        };
        let reposer = py
            .detach(|| Reposer::new(&mesh.mesh, &opts))
            .map_err(error)?;
        let base = mesh.derived(mesh.mesh.clone(), None);
        Ok(Self { reposer, base })
    }

    /// The refined points of the pose `points` (the base mesh's points moved, `(n, 3)`),
    /// as an `(m, 3)` float64 array: what `Mesh.subdivide` gives for the moved mesh.
    fn pose<'py>(
        &mut self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let positions = float_rows::<3>(points, "points")?;
        let reposer = &mut self.reposer;
        let refined = py
            .detach(|| reposer.pose(&positions).map(|m| m.positions().to_vec()))
            .map_err(error)?;
        rows_to_py(py, &refined)
    }

    /// The refined mesh in the last pose (the first: the base mesh's own points), with its
    /// texture coordinates and, with `limit`, its normals.
    #[getter]
    fn mesh(&self) -> Mesh {
        let normals = self.reposer.normals().map(<[_]>::to_vec);
        self.base.derived(self.reposer.mesh().clone(), normals)
    }

    /// The limit normals of the last pose (`limit=True`), or `None`.
    #[getter]
    fn normals<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.reposer
            .normals()
            .map(|n| rows_to_py(py, n))
            .transpose()
    }
}

// ---------------------------------------------------------------------------------------
// Files.

/// Reads a mesh from an OBJ, PLY or glTF file, with the subdivision options its tags set
/// (OBJ's `t interpolateboundary`, `t creasemethod`, …) and its texture coordinates. What the
/// file holds and the mesh cannot (normals, other properties) is reported as a warning.
#[pyfunction]
#[pyo3(signature = (path, *, scheme="catmullClark", c=0.5, adjust_steps=1))]
fn read(py: Python<'_>, path: PathBuf, scheme: &str, c: f64, adjust_steps: u32) -> PyResult<Mesh> {
    let scheme = scheme_of(scheme, c, adjust_steps)?;
    let file = py.detach(|| read_mesh(&path, None)).map_err(error)?;
    let name = path.display().to_string();
    // The file's own notes (what it holds that the mesh leaves out: `vn`, other PLY
    // properties, glTF's other content) and the tags read but not honoured.
    let mut notes = file.ignored.clone();
    for t in &file.obj.unsupported_tags {
        notes.push(format!("tag not supported: {t:?}"));
    }
    if !file.obj.mesh.knots.is_empty() && scheme != Scheme::Nurss {
        notes.push(format!(
            "knot interval or weight tags: the {} scheme ignores them (scheme=\"nurss\" reads them)",
            scheme_token(scheme)
        ));
    }
    let warnings = py.import("warnings")?;
    for note in notes {
        warnings.call_method1("warn", (format!("{name}: {note}"),))?;
    }
    let options = file.obj.options.resolve(Options::default());
    file.obj
        .mesh
        .validate()
        .map_err(|e| error(format!("{name}: {e}")))?;
    Ok(Mesh {
        mesh: file.obj.mesh,
        scheme,
        options,
        normals: None,
    })
}

/// The control mesh whose non-uniform (NURSS) limit surface interpolates the cubic B-spline
/// and NURBS curves of the file `path` (JSON documents or OBJ free-form curves), by the
/// symmetric zonal meshes of [JOS 2003] (the repository's `docs/references.md`;
/// `subsurf::curves`): a mesh with scheme `"nurss"` and its knot intervals, to refine or
/// evaluate. `width` is the zone's half-width relative to each curve's size and `side` a
/// direction for the zones' sides (default: a rotation-minimising frame). With `host`, the
/// curves' control polygons run along edges of that mesh and the zones are embedded in it
/// (`width` then a fraction of the shortest host edge at each point, in `(0, 1)`).
#[pyfunction]
#[pyo3(signature = (path, *, width=None, side=None, host=None))]
fn interpolate_curves(
    py: Python<'_>,
    path: PathBuf,
    width: Option<f64>,
    side: Option<[f64; 3]>,
    host: Option<&Mesh>,
) -> PyResult<Mesh> {
    let name = path.display().to_string();
    let items = py.detach(|| read_geometry(&path)).map_err(error)?;
    let interpolation = py.detach(|| match host {
        Some(h) => {
            if side.is_some() {
                return Err("side applies to curves without a host".to_owned());
            }
            let mut opts = HostOptions::default();
            if let Some(w) = width {
                opts.width = w;
            }
            embed_geometry(&h.mesh, &items, &opts).map_err(|e| e.to_string())
        }
        None => {
            let mut opts = InterpolateOptions {
                side,
                ..InterpolateOptions::default()
            };
            if let Some(w) = width {
                opts.width = w;
            }
            interpolate_geometry(&items, &opts).map_err(|e| e.to_string())
        }
    });
    let interpolation = interpolation.map_err(|e| error(format!("{name}: {e}")))?;
    Ok(Mesh {
        mesh: interpolation.mesh,
        scheme: Scheme::Nurss,
        options: host.map_or_else(Options::default, |h| h.options),
        normals: None,
    })
}

#[pymodule]
fn _subsurf(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Mesh>()?;
    m.add_class::<SurfaceObject>()?;
    m.add_class::<ReposerObject>()?;
    m.add_function(wrap_pyfunction!(read, m)?)?;
    m.add_function(wrap_pyfunction!(interpolate_curves, m)?)?;
    m.add("SubsurfError", m.py().get_type::<SubsurfError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
