//! [`SplineError`]: errors of the sub-basis spline surface.

use crate::mesh::MeshError;

/// Errors of [`super::SubBasisSurface`] construction, evaluation and tessellation.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SplineError {
    /// The mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// A face is not a quad (use [`super::quad_control_mesh`] first).
    #[error(
        "face {face} has {size} vertices; the sub-basis spline needs a quad mesh \
         (apply one Catmull-Clark step first)"
    )]
    NotQuad {
        /// Face.
        face: usize,
        /// Its number of vertices.
        size: usize,
    },
    /// The Catmull-Clark step that turns a non-quad mesh into quads failed.
    #[error("the Catmull-Clark step to a quad mesh failed: {0}")]
    Subdivide(String),
    /// The face index is out of range.
    #[error("face {face} does not exist (the mesh has {count} faces)")]
    NoSuchFace {
        /// Requested face.
        face: u32,
        /// Number of faces.
        count: usize,
    },
    /// The face has no surface: a corner's sub-basis functions are incomplete.
    #[error(
        "face {face} has no spline surface: its corner vertex {vertex} is on a boundary, \
         non-manifold or of valence below 3, so its sub-basis functions are incomplete"
    )]
    NoSurface {
        /// Face.
        face: u32,
        /// The first corner vertex whose star is incomplete.
        vertex: u32,
    },
    /// The vertex index is out of range.
    #[error("vertex {vertex} does not exist (the mesh has {count} vertices)")]
    NoSuchVertex {
        /// Requested vertex.
        vertex: u32,
        /// Number of vertices.
        count: usize,
    },
    /// A parameter outside `[0, 1]` or not finite.
    #[error("parameter ({u}, {v}) is outside [0, 1]²")]
    BadParameter {
        /// `u`.
        u: f64,
        /// `v`.
        v: f64,
    },
    /// The surface was not built from this mesh.
    #[error(
        "the spline surface does not belong to the mesh ({surface_faces} faces and \
         {surface_vertices} control points in the surface, {mesh_faces} and {mesh_vertices} \
         in the mesh)"
    )]
    Mismatch {
        /// Faces of the surface.
        surface_faces: usize,
        /// Control points of the surface.
        surface_vertices: usize,
        /// Faces of the mesh.
        mesh_faces: usize,
        /// Vertices of the mesh.
        mesh_vertices: usize,
    },
}
