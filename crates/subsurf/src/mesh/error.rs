//! Typed errors and warnings of the mesh layer. Every variant names the element at fault
//! (0-based face, vertex or edge end indices); readers that know source lines (the OBJ
//! reader) add them on top.

/// An invalid mesh.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// A face with fewer than three vertices.
    #[error("face {face} has {count} vertices; a face needs at least 3")]
    FaceTooSmall {
        /// Face index.
        face: usize,
        /// Its vertex count.
        count: usize,
    },
    /// A face that is not a triangle given to a scheme that refines triangles only (Loop).
    #[error("face {face} has {count} vertices; Loop subdivision needs a mesh of triangles only")]
    NotTriangle {
        /// Face index.
        face: usize,
        /// Its vertex count.
        count: usize,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {index}, but the mesh has {count} vertices")]
    VertexOutOfRange {
        /// Face index.
        face: usize,
        /// The bad vertex index.
        index: u64,
        /// Number of vertices.
        count: usize,
    },
    /// A face lists the same vertex twice.
    #[error("face {face} lists vertex {vertex} more than once")]
    RepeatedVertex {
        /// Face index.
        face: usize,
        /// The repeated vertex.
        vertex: u32,
    },
    /// A coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate ({value})")]
    NonFiniteCoordinate {
        /// Vertex index.
        vertex: usize,
        /// The offending value.
        value: f64,
    },
    /// A coordinate too large for the geometry that follows (normals and curvature multiply
    /// coordinates; 1e75 keeps every product finite).
    #[error(
        "vertex {vertex} has the coordinate {value}; coordinates must be below 1e75 in magnitude"
    )]
    CoordinateTooLarge {
        /// Vertex index.
        vertex: usize,
        /// The offending value.
        value: f64,
    },
    /// New positions for a mesh (or a structure built from one) do not have one point per
    /// vertex.
    #[error("expected {expected} positions (one per vertex), got {found}")]
    PositionCount {
        /// Number of vertices.
        expected: usize,
        /// Number of positions given.
        found: usize,
    },
    /// A face-varying channel is malformed (its values, or its index count against the
    /// mesh's face-vertices).
    #[error("face-varying channel '{channel}': {message}")]
    BadFaceVarying {
        /// The channel's name.
        channel: String,
        /// What is wrong.
        message: String,
    },
    /// A face grouping that does not fit the mesh ([`FaceGroups::validate`](super::FaceGroups::validate)).
    #[error("face groups: {message}")]
    BadFaceGroups {
        /// What is wrong.
        message: String,
    },
    /// A face refers to a face-varying value that does not exist.
    #[error("face {face} refers to value {index} of face-varying channel '{channel}', which has {count} values")]
    FaceVaryingOutOfRange {
        /// The channel's name.
        channel: String,
        /// Face index.
        face: usize,
        /// The bad value index.
        index: u64,
        /// Number of values of the channel.
        count: usize,
    },
    /// The face offsets of a CSR face list are not a valid prefix sum.
    #[error("face offsets are malformed: {0}")]
    BadFaceOffsets(String),
    /// An edge shared by more than two faces (rejected only by [`crate::mesh::Topology::check_manifold`]).
    #[error("edge ({v0}, {v1}) is shared by {faces} faces (non-manifold); faces {first} and {second} are two of them")]
    NonManifoldEdge {
        /// End vertex.
        v0: u32,
        /// End vertex.
        v1: u32,
        /// Number of faces on the edge.
        faces: usize,
        /// One face on the edge.
        first: u32,
        /// Another face on the edge.
        second: u32,
    },
    /// Two faces traverse their common edge in the same direction.
    #[error("faces {f0} and {f1} are oriented inconsistently: both run edge ({v0}, {v1}) in the same direction")]
    InconsistentOrientation {
        /// First face.
        f0: u32,
        /// Second face.
        f1: u32,
        /// Edge start, as both faces run it.
        v0: u32,
        /// Edge end.
        v1: u32,
    },
    /// A vertex whose faces do not form a single fan.
    #[error("vertex {vertex} is non-manifold: its {faces} faces do not form a single fan")]
    NonManifoldVertex {
        /// Vertex index.
        vertex: u32,
        /// Number of incident faces.
        faces: usize,
    },
    /// A crease or corner sharpness that is NaN or negative.
    #[error(
        "{what} has sharpness {value}; sharpness must be a number ≥ 0 (≥ 10 is infinitely sharp)"
    )]
    BadSharpness {
        /// Description of the tagged element.
        what: String,
        /// The value.
        value: f32,
    },
    /// A tag refers to a vertex or face that does not exist.
    #[error("{what} refers to {kind} {index}, but the mesh has {count}")]
    TagOutOfRange {
        /// Which tag.
        what: &'static str,
        /// "vertex" or "face".
        kind: &'static str,
        /// The bad index.
        index: u64,
        /// Number of such elements.
        count: usize,
    },
    /// More elements than 32-bit indices can address.
    #[error("the mesh is too large: {what} would exceed the 32-bit index range")]
    TooLarge {
        /// What overflowed.
        what: String,
    },
    /// A refined mesh (or its limit surface) given with its input has another number of
    /// faces than the refinement makes
    /// ([`MixedSurface::from_refined`](crate::MixedSurface::from_refined)).
    #[error(
        "the refined mesh has {found} faces, not the {expected} that refining the input makes"
    )]
    NotRefined {
        /// Faces the refinement makes.
        expected: u64,
        /// Faces given.
        found: usize,
    },
}

/// Something accepted but worth telling the user (OpenSubdiv reports these too).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TopologyWarning {
    /// A crease tag names two vertices that share no edge; the tag is ignored.
    CreaseEdgeMissing {
        /// Index of the crease in [`crate::mesh::Tags::creases`].
        crease: usize,
        /// End vertex.
        v0: u32,
        /// End vertex.
        v1: u32,
    },
    /// Faces that list a vertex more than once; their repeated edges are non-manifold
    /// (sharp), as in OpenSubdiv, and so is a vertex whose faces cannot be walked around
    /// in one order.
    DegenerateFaces {
        /// How many.
        count: usize,
        /// The first one.
        first: u32,
    },
    /// Non-manifold edges were found; they are treated as infinitely sharp.
    NonManifoldEdges {
        /// How many.
        count: usize,
        /// The first one's end vertices.
        first: (u32, u32),
    },
    /// Non-manifold vertices were found; they are treated as infinitely sharp corners
    /// (or as crease vertices on an interior non-manifold crease).
    NonManifoldVertices {
        /// How many (isolated vertices excluded).
        count: usize,
        /// The first one.
        first: u32,
    },
}

impl TopologyWarning {
    /// What is done about the elements the warning names (the part of its message after
    /// them, shared by [`Display`](std::fmt::Display) and messages that number elements
    /// in a file's terms).
    pub fn consequence(&self) -> &'static str {
        match self {
            Self::CreaseEdgeMissing { .. } => "the crease is ignored",
            Self::DegenerateFaces { .. } => {
                "they have no well-defined surface there: refined as degenerate faces, with \
                 the vertex sharp where the faces around it cannot be ordered (OpenSubdiv then \
                 gives a result that depends on the corner a face starts from); --strict \
                 refuses them"
            }
            Self::NonManifoldEdges { .. } => "are treated as infinitely sharp, as OpenSubdiv does",
            Self::NonManifoldVertices { .. } => "are treated as sharp, as OpenSubdiv does",
        }
    }
}

impl std::fmt::Display for TopologyWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let then = self.consequence();
        match self {
            Self::CreaseEdgeMissing { crease, v0, v1 } => {
                write!(
                    f,
                    "crease {crease}: vertices {v0} and {v1} share no edge; {then}"
                )
            }
            Self::DegenerateFaces { count, first } => write!(
                f,
                "{count} face(s) (first: face {first}) list a vertex more than once; {then}"
            ),
            Self::NonManifoldEdges { count, first } => write!(
                f,
                "{count} non-manifold edge(s) (first: {}-{}) {then}",
                first.0, first.1
            ),
            Self::NonManifoldVertices { count, first } => write!(
                f,
                "{count} non-manifold vertex/vertices (first: {first}) {then}"
            ),
        }
    }
}
