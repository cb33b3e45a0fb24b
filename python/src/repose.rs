//! `subsurf.Reposer`: one refinement plan, many poses.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use subsurf::{Reposer, SubdivideOptions};

use crate::arrays::{asarray, float_grid, float_rows, rows_to_py};
use crate::error;
use crate::mesh::Mesh;

/// Refinement of one mesh in many poses (animation): the topology and the masks are
/// computed once (`subsurf::Reposer`, a `RefinePlan`), and each pose costs only the
/// interpolation of its points.
#[pyclass(module = "subsurf", name = "Reposer")]
pub(crate) struct ReposerObject {
    pub(crate) reposer: Reposer,
    pub(crate) base: Mesh,
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
    /// as an `(m, 3)` float64 array: what `Mesh.subdivide` gives for the moved mesh. Many
    /// poses at once: `points` of shape `(frames, n, 3)` gives `(frames, m, 3)`, each frame
    /// as if posed alone (and `mesh`, `normals` are then the last frame's).
    fn pose<'py>(
        &mut self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let ndim: usize = asarray(points, None)?.getattr("ndim")?.extract()?;
        if ndim != 3 {
            let positions = float_rows::<3>(points, "points")?;
            let reposer = &mut self.reposer;
            let refined = py
                .detach(|| reposer.pose(&positions).map(|m| m.positions().to_vec()))
                .map_err(error)?;
            return rows_to_py(py, &refined);
        }
        let (shape, values) = float_grid(points, "points")?;
        let &[frames, n, 3] = shape.as_slice() else {
            return Err(PyValueError::new_err(format!(
                "points must have shape (n, 3) or (frames, n, 3), not {shape:?}"
            )));
        };
        let reposer = &mut self.reposer;
        let m = reposer.mesh().num_vertices();
        let refined = py.detach(|| {
            let mut out: Vec<f64> = Vec::with_capacity(frames.saturating_mul(3 * m));
            for f in 0..frames {
                let frame = &values[f * 3 * n..(f + 1) * 3 * n];
                let rows: Vec<[f64; 3]> =
                    frame.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
                let posed = reposer
                    .pose(&rows)
                    .map_err(|e| error(format!("frame {f}: {e}")))?;
                out.extend(posed.positions().iter().flatten());
            }
            Ok::<_, PyErr>(out)
        })?;
        Ok(PyArray1::from_vec(py, refined)
            .reshape([frames, m, 3])?
            .into_any())
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
