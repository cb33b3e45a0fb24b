//! Wavefront OBJ with OpenSubdiv's `t` tags.
//!
//! Reading ([`parse_obj`], [`read_obj`]) accepts polygons (`f`, with every index form:
//! `v`, `v/vt`, `v//vn`, `v/vt/vn`, positive or negative), vertices (`v`, an optional `w`
//! or vertex colour is ignored), texture coordinates (`vt`) and normals (`vn`), LF, CRLF
//! and CR-only (old Mac OS) line ends, `\` line continuations and `#` comments. Objects,
//! groups and materials (`o`, `g`, `usemtl`, `mtllib`) are kept as the mesh's
//! [`FaceGroups`](crate::mesh::FaceGroups) (each face's state, and the libraries);
//! smoothing groups (`s`) are counted ([`ObjFile::smoothing_groups`]) and not kept.
//! Polyline, point and free-form statements are ignored, as are
//! unknown statements; but a line must start with something that looks like a keyword (a
//! letter, then letters, digits or `_`), and must be UTF-8 without control characters, so
//! that a binary or non-OBJ file fails on its first line instead of being read as an empty
//! mesh. Coordinates must be below 1e75 in magnitude
//! ([`MAX_COORDINATE`](crate::mesh::MAX_COORDINATE)).
//!
//! OpenSubdiv's tags (`t NAME ni/nf/ns ints... floats... strings...`, indices 0-based):
//!
//! | tag | meaning |
//! |-----|---------|
//! | `t crease 2/1/0 a b s` | edge `a`–`b` has sharpness `s`; `N/1/0` (one sharpness) or `N/(N-1)/0` (one per edge) tags the chain `v0 v1 ... vN-1`; `N/0/0` is infinitely sharp |
//! | `t corner N/1/0 v... s` | vertex sharpness (`N/N/0`: one each, `N/0/0`: infinitely sharp) |
//! | `t hole N/0/0 f...` | faces that are holes |
//! | `t interpolateboundary 1/0/0 k` | 0 none, 1 edge-and-corner, 2 edge-only |
//! | `t creasemethod 0/0/1 chaikin` | `chaikin` or `uniform` (`normal`) |
//! | `t smoothtriangles 0/0/1 smooth` | `smooth` or `catmark` |
//! | `t interval 2/1/0 a b d` | edge `a`–`b` has knot interval `d ≥ 0` (non-uniform Catmull-Clark, [`crate::nonuniform`]; untagged edges: 1) |
//! | `t sideinterval 3/1/0 f a b d` | the side of edge `a`–`b` in face `f` has auxiliary interval `d` (first step only) |
//! | `t weight 1/1/0 v w` | vertex `v` has rational weight `w > 0` (untagged: 1) |
//!
//! Free-form curves and surfaces (`cstype`, `deg`, `curv`, `surf`, `parm`, `end`) are
//! read separately, by [`parse_obj_freeform`].
//!
//! The knot tags are read into [`PolyMesh::knots`] and checked once the file is read: an
//! edge that no face has, a side whose face lacks the edge, a repeated vertex, a negative or
//! non-finite interval or a weight ≤ 0 is an error at the tag's line.
//!
//! Any other tag is recorded in [`ObjFile::unsupported_tags`], never dropped silently.
//!
//! Every problem is an [`ObjError`] that names the file and the 1-based line
//! (`model.obj:12: f: vertex index 0 is invalid: OBJ indices start at 1`). Out-of-range
//! vertex indices are checked once the whole file is read (OBJ allows faces to refer to
//! vertices defined further down) and reported at the line of the face, with the number of
//! vertices in the file. A face that lists a vertex twice is kept as written (a degenerate
//! face, which OpenSubdiv accepts).
//!
//! Writing ([`write_obj`]) prints every `f64` as the shortest decimal that reads back as
//! the same value, never in exponent form ([`push_decimal`](crate::io::push_decimal)), so
//! reading a written file gives bit-identical positions, and sharpness values as
//! round-trip exact `f32`.

use crate::mesh::{
    BoundaryInterpolation, CreaseMethod, FaceVaryingInterpolation, Options, PolyMesh,
    TriangleSubdivision,
};

mod describe;
pub(crate) mod freeform;
mod groups;
mod read;
mod write;

pub use freeform::{parse_obj_freeform, write_obj_freeform, FreeFormElement};
pub use groups::{write_groups_obj, write_method_obj};
pub(crate) use read::{first_non_text, non_text_message, parse_obj_within, PhysicalLines, Refusal};
pub use read::{parse_obj, read_obj};
pub use write::write_obj;

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
    /// The `s` statements that turn smoothing groups on (not `s off` or `s 0`): not kept,
    /// since a subdivision surface is smooth everywhere but at its creases.
    pub smoothing_groups: usize,
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
    /// `t facevaryinginterpolateboundary` (with `t facevaryingpropagatecorners` folded in).
    pub face_varying: Option<FaceVaryingInterpolation>,
}

impl FileOptions {
    /// These options over `defaults`.
    pub fn resolve(&self, defaults: Options) -> Options {
        Options {
            boundary: self.boundary.unwrap_or(defaults.boundary),
            crease_method: self.crease_method.unwrap_or(defaults.crease_method),
            triangles: self.triangles.unwrap_or(defaults.triangles),
            face_varying: self.face_varying.unwrap_or(defaults.face_varying),
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
