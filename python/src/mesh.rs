//! `subsurf.Mesh`: a polygon mesh with its tags, texture coordinates and subdivision
//! options, in USD's vocabulary; refinement and conversions.

use std::io::Write as _;
use std::path::PathBuf;

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyImportError, PyValueError};
use pyo3::prelude::*;

use subsurf::io::{write_atomically, write_obj, write_ply, WriteOptions};
use subsurf::mesh::{
    Corner, Crease, CreaseMethod, EdgeInterval, FaceVarying, KnotTags, Options, PolyMesh, Tags,
    TriangleSubdivision, VertexWeight,
};
use subsurf::regularity::{
    check_regularity, plot_image, plot_svg, Dimension, Mode, RegularityOptions,
};
use subsurf::render::write_png;
use subsurf::{subdivide, Scheme, SubdivideOptions};

use crate::arrays::{
    asarray, float_array, float_rows, floats_to_py, index_array, indices_to_py, optional,
    rows_to_py,
};
use crate::surface::SurfaceObject;
use crate::tokens::{
    boundary_of, boundary_token, crease_method_of, fvar_of, fvar_token, scheme_of, scheme_token,
    triangle_rule_of,
};
use crate::{error, UV};

/// The sharp edges of USD's crease attributes: chains of `lengths[k]` vertices of `indices`,
/// with one sharpness per chain or one per edge.
pub(crate) fn usd_creases(
    indices: &[u32],
    lengths: &[u32],
    sharpnesses: &[f64],
) -> PyResult<Vec<Crease>> {
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
pub(crate) fn uv_channel(
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
pub(crate) struct Mesh {
    pub(crate) mesh: PolyMesh,
    pub(crate) scheme: Scheme,
    pub(crate) options: Options,
    /// Limit normals per point (`subdivide(limit=True)`, tessellations).
    pub(crate) normals: Option<Vec<[f64; 3]>>,
}

impl Mesh {
    pub(crate) fn uv(&self) -> Option<&FaceVarying> {
        self.mesh.face_varying.iter().find(|c| c.name() == UV)
    }

    pub(crate) fn derived(&self, mesh: PolyMesh, normals: Option<Vec<[f64; 3]>>) -> Self {
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
        floats_to_py(
            py,
            self.mesh
                .tags
                .creases
                .iter()
                .map(|c| f64::from(c.sharpness)),
        )
    }

    /// The sharp vertices (int32).
    #[getter]
    fn corner_indices<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        indices_to_py(py, self.mesh.tags.corners.iter().map(|c| c.vertex))
    }

    /// The sharpness of every sharp vertex (float64).
    #[getter]
    fn corner_sharpnesses<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        floats_to_py(
            py,
            self.mesh
                .tags
                .corners
                .iter()
                .map(|c| f64::from(c.sharpness)),
        )
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

    /// The regularity certificate of the Catmull-Clark limit surface of this quad net
    /// (Wang, Lin, Wang and Lu 2016, the repository's `docs/regularity.md`;
    /// `subsurf::regularity`), as `subsurf regularity --json` reports it: a dict with
    /// `certified` (every face certified by the chosen certificate and no sample
    /// contradicting it), the counts, the global cones per component and a verdict per face
    /// (`file` is `None`). `local` decides by each face's own patch neighbourhood instead of
    /// one cone pair per component; `sample` samples the limit surface `sample × sample`
    /// per face for the ground truth (0: off, else 2 to 1024); `planar` treats the net as
    /// planar (x, y) even where z is not 0; `plot` draws the net with its difference fans to
    /// an `.svg` or `.png` file.
    #[pyo3(signature = (*, local=false, sample=9, planar=false, plot=None))]
    fn regularity<'py>(
        &self,
        py: Python<'py>,
        local: bool,
        sample: u32,
        planar: bool,
        plot: Option<PathBuf>,
    ) -> PyResult<Bound<'py, PyAny>> {
        if self.scheme != Scheme::CatmullClark {
            return Err(error(format!(
                "the regularity certificate is for Catmull-Clark nets; the mesh's scheme is {:?}",
                scheme_token(self.scheme)
            )));
        }
        if sample == 1 || sample > 1024 {
            return Err(PyValueError::new_err(format!(
                "sample {sample}: 0 (no sampling) or 2 to 1024"
            )));
        }
        let png = match plot.as_ref().map(|p| {
            p.extension()
                .and_then(|e| e.to_str())
                .map(str::to_ascii_lowercase)
        }) {
            None => false,
            Some(Some(e)) if e == "svg" => false,
            Some(Some(e)) if e == "png" => true,
            Some(_) => {
                return Err(PyValueError::new_err(format!(
                    "{}: the plot is written as .svg or .png",
                    plot.as_deref()
                        .map_or(String::new(), |p| p.display().to_string())
                )))
            }
        };
        let options = RegularityOptions {
            scheme: self.options,
            dimension: planar.then_some(Dimension::Planar),
            samples: sample as usize,
        };
        let mode = if local { Mode::Local } else { Mode::Global };
        let json = py.detach(|| -> PyResult<String> {
            let report = check_regularity(&self.mesh, &options).map_err(error)?;
            if let Some(path) = &plot {
                if png {
                    let img = plot_image(&self.mesh, &report, mode);
                    write_atomically(path, |w| write_png(w, &img))?;
                } else {
                    let svg = plot_svg(&self.mesh, &report, mode);
                    write_atomically(path, |w| w.write_all(svg.as_bytes()))?;
                }
            }
            Ok(report.to_json(None, mode))
        })?;
        py.import("json")?.call_method1("loads", (json,))
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
        let faces = asarray(&mesh.getattr("faces")?, None)?;
        let shape: Vec<usize> = faces.getattr("shape")?.extract()?;
        let &[n, k] = shape.as_slice() else {
            return Err(PyValueError::new_err(format!(
                "the mesh's faces must have shape (n, k), not {shape:?}"
            )));
        };
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

pub(crate) fn corners(
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
pub(crate) fn knot_tags(
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
