//! File input and output.
//!
//! - [`obj`]: Wavefront OBJ with OpenSubdiv's `t` tags (creases, corners, holes, scheme
//!   options), read with errors that name file and line, written with round-trip exact
//!   `f64` values.
//! - [`ply`]: PLY, read (ASCII and binary) and written (binary).
//! - [`input`]: a polygon mesh from a file or stream in any format read (OBJ, PLY), told
//!   apart by content, read in blocks that are checked as they arrive, within a memory
//!   limit.
//! - [`geometry`]: files of NURBS curves and surfaces, JSON or OBJ free-form.
//! - [`push_decimal`]: the shortest decimal that reads back as the same `f64`, fast.
//! - [`write_atomically`]: every output file is written to a temporary file in the same
//!   directory and renamed into place, so a failed run never leaves a partial file;
//!   [`PendingFile`] does the same for several files that appear together or not at all,
//!   and [`remove_temporary_files`] cleans up after a signal.

mod atomic;
mod decimal;
pub mod geometry;
pub mod gltf;
pub mod input;
pub mod obj;
pub mod ply;
pub mod stl;

pub use atomic::{remove_temporary_files, write_atomically, Finished, PendingFile};
pub use decimal::push_decimal;
