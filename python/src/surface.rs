//! `subsurf.Surface`: the limit, G2-capped and sub-basis spline surfaces of a mesh.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use subsurf::g2cap::{G2Surface, G2SurfaceOptions};
use subsurf::limit::{
    tessellate, BilinearSurface, Derivatives, EvalError, FaceVaryingSurface, LimitSurface,
    LoopSurface, Order, Surface, SurfacePoint,
};
use subsurf::nonuniform::{tessellate as nonuniform_tessellate, NurssSurface};
use subsurf::spline::{QuadSpline, SubBasisSurface};
use subsurf::{MixedSurface, Scheme};

use crate::arrays::{float_array, index_array, optional, rows_to_py};
use crate::mesh::Mesh;
use crate::{error, UV};

/// The limit surface of one scheme.
pub(crate) enum AnySurface {
    CatmullClark(LimitSurface),
    Loop(Box<LoopSurface>),
    Bilinear(BilinearSurface),
    Mixed(Box<MixedSurface>),
    Nurss(Box<NurssSurface>),
    G2(Box<G2Surface>),
    Spline(Box<SubBasisSurface>),
}

impl AnySurface {
    pub(crate) fn as_dyn(&self) -> &dyn Surface {
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
pub(crate) struct SurfaceObject {
    pub(crate) surface: AnySurface,
    /// The texture coordinates' limit, or why there is none (raised when asked for).
    pub(crate) uv: Result<Option<FaceVaryingSurface>, String>,
    /// The mesh whose faces the surface is parametrised over.
    pub(crate) base: Mesh,
    pub(crate) kind: &'static str,
}

impl SurfaceObject {
    pub(crate) fn limit(m: &Mesh) -> Result<Self, String> {
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

    pub(crate) fn g2(m: &Mesh, levels: Option<u32>) -> Result<Self, String> {
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

    pub(crate) fn spline(m: &Mesh) -> Result<Self, String> {
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
    pub(crate) fn tessellation(&self, rate: u32, triangles: bool) -> Result<Mesh, String> {
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
pub(crate) const NO_UV: &str = "texture coordinates are evaluated on the limit surface only \
                     (Mesh.limit_surface())";

/// The points `(face, subface, u, v)` of the arrays given to `evaluate`.
pub(crate) fn surface_points(
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

pub(crate) fn point_error(i: usize, p: SurfacePoint, e: &EvalError) -> PyErr {
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
