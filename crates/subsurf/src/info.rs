//! [`mesh_info`]: a summary of a mesh for `subsurf info`.

use crate::mesh::{Options, PolyMesh};
use crate::subdivide::Error;

/// Counts and classification of a mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshInfo {
    /// Vertices.
    pub vertices: usize,
    /// Edges.
    pub edges: usize,
    /// Faces.
    pub faces: usize,
    /// `(face size, count)`, ascending.
    pub face_sizes: Vec<(usize, usize)>,
    /// `(valence, count)` over vertices with faces, ascending.
    pub valences: Vec<(usize, usize)>,
    /// Vertices whose valence is not regular (4 inside, 3 on a boundary; corners excluded).
    pub extraordinary_vertices: usize,
    /// Isolated vertices (no face).
    pub isolated_vertices: usize,
    /// Number of closed boundary loops.
    pub boundary_loops: usize,
    /// Boundary edges.
    pub boundary_edges: usize,
    /// Non-manifold edges.
    pub non_manifold_edges: usize,
    /// Non-manifold vertices (isolated vertices excluded).
    pub non_manifold_vertices: usize,
    /// Euler characteristic V - E + F.
    pub euler_characteristic: i64,
    /// Semi-sharp edges, infinitely sharp edges (tags), sharp vertices, holes.
    pub creases: usize,
    /// Tagged corner vertices.
    pub corners: usize,
    /// Hole faces.
    pub holes: usize,
    /// Bounding box.
    pub bounding_box: Option<([f64; 3], [f64; 3])>,
}

/// Summarises `mesh` (topology built with `options`).
pub fn mesh_info(mesh: &PolyMesh, options: &Options) -> Result<MeshInfo, Error> {
    let _ = (mesh, options);
    todo!()
}
