//! Reading meshes and interpolating the curves of a file.

use std::path::PathBuf;

use pyo3::prelude::*;

use subsurf::curves::{embed_geometry, interpolate_geometry, HostOptions, InterpolateOptions};
use subsurf::io::{read_geometry, read_mesh};
use subsurf::mesh::Options;
use subsurf::Scheme;

use crate::error;
use crate::mesh::Mesh;
use crate::tokens::{scheme_of, scheme_token};

/// Reads a mesh from an OBJ, PLY or glTF file, with the subdivision options its tags set
/// (OBJ's `t interpolateboundary`, `t creasemethod`, …) and its texture coordinates. What the
/// file holds and the mesh cannot (normals, other properties) is reported as a warning.
#[pyfunction]
#[pyo3(signature = (path, *, scheme="catmullClark", c=0.5, adjust_steps=1))]
pub(crate) fn read(
    py: Python<'_>,
    path: PathBuf,
    scheme: &str,
    c: f64,
    adjust_steps: u32,
) -> PyResult<Mesh> {
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
pub(crate) fn interpolate_curves(
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
