//! Placeholder: replaced by the OBJ reader/writer.
use crate::mesh::{BoundaryInterpolation, CreaseMethod, Options, PolyMesh, TriangleSubdivision};
use std::path::Path;

/// A parsed OBJ file.
#[derive(Clone, Debug, Default)]
pub struct ObjFile {
    /// The polygon mesh (0-based vertex indices) with creases, corners and holes.
    pub mesh: PolyMesh,
    /// `vt` records (u, v, w; w = 0 when absent).
    pub texcoords: Vec<[f64; 3]>,
    /// `vn` records.
    pub normals: Vec<[f64; 3]>,
    /// Texture index per face corner (parallel to the face-vertex list), when every corner has one.
    pub face_texcoords: Option<Vec<u32>>,
    /// Normal index per face corner, when every corner has one.
    pub face_normals: Option<Vec<u32>>,
    /// 1-based source line of each face.
    pub face_lines: Vec<u32>,
    /// Scheme options set by tags.
    pub options: FileOptions,
    /// Tags read but not (yet) honoured.
    pub unsupported_tags: Vec<UnsupportedTag>,
}

/// Scheme options read from `t interpolateboundary`, `t creasemethod`, `t smoothtriangles`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FileOptions {
    /// `t interpolateboundary`.
    pub boundary: Option<BoundaryInterpolation>,
    /// `t creasemethod`.
    pub crease_method: Option<CreaseMethod>,
    /// `t smoothtriangles`.
    pub triangles: Option<TriangleSubdivision>,
}

impl FileOptions {
    /// These options over `defaults`.
    pub fn resolve(&self, defaults: Options) -> Options {
        Options {
            boundary: self.boundary.unwrap_or(defaults.boundary),
            crease_method: self.crease_method.unwrap_or(defaults.crease_method),
            triangles: self.triangles.unwrap_or(defaults.triangles),
        }
    }
}

/// A tag that was read but is not honoured.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnsupportedTag {
    /// 1-based line.
    pub line: usize,
    /// Tag name (`vertexedit`, ...).
    pub name: String,
}

/// An error reading OBJ: file, line and what is wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{source_name}{}: {message}", line.map(|l| format!(":{l}")).unwrap_or_default())]
pub struct ObjError {
    /// File name as given (or `<stdin>`).
    pub source_name: String,
    /// 1-based line, when the error belongs to one.
    pub line: Option<usize>,
    /// What is wrong.
    pub message: String,
}

/// Reads an OBJ file.
pub fn read_obj(path: &Path) -> Result<ObjFile, ObjError> {
    let _ = path;
    todo!()
}

/// Parses OBJ bytes; `source_name` is used in errors.
pub fn parse_obj(bytes: &[u8], source_name: &str) -> Result<ObjFile, ObjError> {
    let _ = (bytes, source_name);
    todo!()
}

/// What to write besides positions and faces.
#[derive(Clone, Copy, Debug, Default)]
pub struct WriteOptions<'a> {
    /// Per-vertex normals, written as `vn` with faces as `v//vn`.
    pub normals: Option<&'a [[f64; 3]]>,
    /// Scheme options to record as tags (`interpolateboundary`, `creasemethod`, `smoothtriangles`).
    pub scheme: Option<Options>,
    /// A comment line for the header.
    pub comment: Option<&'a str>,
}

/// Writes `mesh` (with its tags) as OBJ.
pub fn write_obj<W: std::io::Write>(w: &mut W, mesh: &PolyMesh, opts: &WriteOptions) -> std::io::Result<()> {
    let _ = (w, mesh, opts);
    todo!()
}
