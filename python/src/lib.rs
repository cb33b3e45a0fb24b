//! The `subsurf` Python package's extension module (`subsurf._subsurf`): the library's
//! meshes, refinement, exact limit evaluation and tessellation with numpy arrays in and
//! out, in USD's vocabulary (`UsdGeomMesh`'s attribute names and tokens), and the paper
//! methods (curve interpolation, blending and hole filling, G2 caps, the sub-basis spline,
//! the regularity certificate).
//!
//! A thin shell, as the command-line tool is: arguments are checked and converted here,
//! every computation is one call of the `subsurf` crate, made with the interpreter's lock
//! released (so other Python threads run, and the library's own threads do the work).

mod arrays;
mod files;
mod mesh;
mod methods;
mod repose;
mod surface;
mod tokens;

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use files::{interpolate_curves, read};
use mesh::Mesh;
use methods::{blend, fill, BlendResult};
use repose::ReposerObject;
use surface::SurfaceObject;

create_exception!(
    subsurf,
    SubsurfError,
    PyValueError,
    "A mesh, its tags or an evaluation request that subsurf refuses; the message names the \
     face, vertex or point at fault."
);

/// The name of the face-varying channel of texture coordinates (the OBJ reader's `vt`).
pub(crate) const UV: &str = "uv";

pub(crate) fn error(e: impl std::fmt::Display) -> PyErr {
    SubsurfError::new_err(e.to_string())
}

#[pymodule]
fn _subsurf(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Mesh>()?;
    m.add_class::<SurfaceObject>()?;
    m.add_class::<ReposerObject>()?;
    m.add_class::<BlendResult>()?;
    m.add_function(wrap_pyfunction!(read, m)?)?;
    m.add_function(wrap_pyfunction!(interpolate_curves, m)?)?;
    m.add_function(wrap_pyfunction!(blend, m)?)?;
    m.add_function(wrap_pyfunction!(fill, m)?)?;
    m.add("SubsurfError", m.py().get_type::<SubsurfError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
