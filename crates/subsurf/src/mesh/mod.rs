//! Polygon meshes: the exchange type [`PolyMesh`], its sharpness [`Tags`], the scheme
//! [`Options`], and the adjacency [`Topology`] that refinement works on.
//!
//! Two layers live here:
//! - [`PolyMesh`] is what a user builds or reads: positions, faces in CSR form and tags.
//!   It is validated on construction ([`PolyMesh::new`]), so every face has at least three
//!   distinct, in-range vertices and every coordinate is finite.
//! - [`Topology`] is the complete, index-based adjacency of one refinement level (edges,
//!   vertex → edges/faces in rotational order, boundary and manifold classification,
//!   sharpness and vertex rules), built from a [`PolyMesh`] in O(n).

mod crease_angle;
mod error;
mod face_varying;
mod groups;
mod options;
mod packed;
mod polymesh;
pub(crate) mod sharpness;
mod tags;
mod topology;
mod value_mesh;

pub use crease_angle::{crease_by_angle, CreaseAngleError};
pub use error::{MeshError, TopologyWarning};
pub use face_varying::FaceVarying;
pub use groups::{FaceGroups, GroupState};
pub use options::{
    BoundaryInterpolation, CreaseMethod, FaceVaryingInterpolation, Options, TriangleSubdivision,
};
pub(crate) use packed::PackedTopology;
pub(crate) use polymesh::check_coordinates;
pub use polymesh::{PolyMesh, MAX_COORDINATE};
pub use tags::{
    Corner, Crease, EdgeInterval, KnotTagError, KnotTags, SideInterval, Tags, VertexWeight,
    SHARPNESS_INFINITE,
};
pub use topology::{EdgeTag, Rule, Topology, VertexTag, INVALID};
pub(crate) use topology::{PackedEdgeTag, PackedVertexTag};
pub(crate) use value_mesh::ValueMesh;

/// An `n × m` grid of unit quads in the plane z = 0, vertex `(i, j)` at index
/// `j * (n + 1) + i`, mapped through `f`. Shared by the unit tests of several layers.
#[cfg(test)]
pub(crate) fn test_grid(n: u32, m: u32, f: impl Fn(f64, f64) -> [f64; 3]) -> PolyMesh {
    let p = (0..=m)
        .flat_map(|j| (0..=n).map(move |i| (i as f64, j as f64)))
        .map(|(x, y)| f(x, y))
        .collect();
    let idx = |i: u32, j: u32| j * (n + 1) + i;
    let faces: Vec<[u32; 4]> = (0..m)
        .flat_map(|j| (0..n).map(move |i| (i, j)))
        .map(|(i, j)| [idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)])
        .collect();
    PolyMesh::from_faces(p, &faces).expect("a grid is a valid mesh")
}

/// The unit cube `[0, 1]³`, six quads oriented outwards: every vertex extraordinary
/// (valence 3). Shared by the unit tests of several layers.
#[cfg(test)]
pub(crate) fn test_cube() -> PolyMesh {
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    let f = [
        [0, 3, 2, 1],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ];
    PolyMesh::from_faces(p, &f).expect("a valid cube")
}
