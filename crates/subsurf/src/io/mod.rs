//! File input and output.
//!
//! - `obj`: Wavefront OBJ with OpenSubdiv's `t` tags (creases, corners, holes, scheme
//!   options), read with errors that name file and line, written with round-trip exact
//!   `f64` values.
//! - `ply`: PLY, read (ASCII and binary) and written (binary).
//! - `gltf`, `gltf_read`: glTF 2.0, written (`.glb`) and read (`.gltf`, `.glb`: welded
//!   triangles and `TEXCOORD_0`), with the `gltf` feature.
//! - `input`: a polygon mesh from a file or stream in any format read (OBJ, PLY, glTF),
//!   told apart by content, read in blocks that are checked as they arrive, within a memory
//!   limit.
//! - `geometry`: files of NURBS curves and surfaces, JSON or OBJ free-form.
//! - [`push_decimal`]: the shortest decimal that reads back as the same `f64`, fast.
//! - [`write_atomically`]: every output file is written to a temporary file in the same
//!   directory and renamed into place, so a failed run never leaves a partial file;
//!   [`PendingFile`] does the same for several files that appear together or not at all,
//!   and [`remove_temporary_files`] cleans up after a signal.

mod atomic;
mod decimal;
pub(crate) mod geometry;
#[cfg(feature = "gltf")]
pub(crate) mod gltf;
#[cfg(feature = "gltf")]
mod gltf_read;
pub(crate) mod input;
pub(crate) mod obj;
pub(crate) mod ply;
pub(crate) mod stl;
mod tessellation;
mod up;

pub use atomic::{remove_temporary_files, write_atomically, Finished, PendingFile};
pub use decimal::push_decimal;
pub use geometry::{geometry_to_string, parse_geometry, read_geometry, GeometryFormat};
#[cfg(feature = "gltf")]
pub use gltf::{face_edges, to_gltf_frame, write_glb, GlbLines, GlbMesh, CHUNK_BIN, CHUNK_JSON};
#[cfg(feature = "gltf")]
pub use gltf_read::{from_gltf_frame, parse_gltf, GltfError, GltfFile};
pub use input::{parse_mesh, read_mesh, read_mesh_from, MeshFormat, ReadMeshError, BLOCK};
pub use obj::{
    parse_obj, parse_obj_freeform, read_obj, write_groups_obj, write_method_obj, write_obj,
    write_obj_freeform, FileOptions, FreeFormElement, ObjError, ObjFile, UnsupportedTag,
    WriteOptions,
};
pub use ply::{parse_ply, read_ply, write_ply, PlyEncoding, PlyError, PlyFile, MAX_HEADER};
pub use stl::{read_stl, write_stl};
pub use tessellation::{write_tessellation, Colours, TessellationFormat, TessellationWriteOptions};
pub use up::Up;
