//! The one-call facade: [`subdivide`] a [`PolyMesh`] to a level, optionally to the limit.

use crate::mesh::{MeshError, Options, PolyMesh, TopologyWarning};

/// What [`subdivide`] should do.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SubdivideOptions {
    /// Number of uniform refinement steps (0 leaves the mesh as it is).
    pub levels: u32,
    /// Scheme options (boundary interpolation, crease method, triangle rule).
    pub scheme: Options,
    /// Move the last level's vertices to their limit positions and compute limit normals.
    pub limit: bool,
    /// Keep hole faces in the output (tagged as holes) so that the result can be refined
    /// again with the same outcome; by default holes are left out, as OpenSubdiv does.
    pub keep_holes: bool,
    /// Refuse (with [`Error::TooLarge`]) when the estimated memory exceeds this many bytes.
    pub max_memory: Option<u64>,
}

/// The result of [`subdivide`].
#[derive(Clone, Debug, PartialEq)]
pub struct Subdivision {
    /// The refined mesh. Its tags carry the sharpness still left at the last level.
    pub mesh: PolyMesh,
    /// Unit limit normals per vertex, when [`SubdivideOptions::limit`] was set.
    pub normals: Option<Vec<[f64; 3]>>,
    /// Warnings about the input (ignored tags, non-manifold elements).
    pub warnings: Vec<TopologyWarning>,
}

/// Errors of [`subdivide`].
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Error {
    /// The input mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The requested level would need more memory than allowed.
    #[error("refining to level {levels} needs about {} MiB, more than the {} MiB allowed; use a lower level", estimate / (1 << 20), limit / (1 << 20))]
    TooLarge {
        /// Requested level.
        levels: u32,
        /// Estimated bytes.
        estimate: u64,
        /// Allowed bytes.
        limit: u64,
    },
}

/// Estimated peak memory in bytes of [`subdivide`] to `levels`.
pub fn estimate_memory(mesh: &PolyMesh, levels: u32) -> u64 {
    let _ = (mesh, levels);
    todo!()
}

/// Refines `mesh` uniformly with Catmull-Clark as OpenSubdiv does.
pub fn subdivide(mesh: &PolyMesh, opts: &SubdivideOptions) -> Result<Subdivision, Error> {
    subdivide_with_progress(mesh, opts, &mut |_, _| {})
}

/// [`subdivide`], calling `progress(level_done, levels)` after each level.
pub fn subdivide_with_progress(
    mesh: &PolyMesh,
    opts: &SubdivideOptions,
    progress: &mut dyn FnMut(u32, u32),
) -> Result<Subdivision, Error> {
    let _ = (mesh, opts, progress);
    todo!()
}
