//! [`PolyMesh`]: positions, faces (CSR) and tags, validated on construction.

use std::hash::BuildHasherDefault;

use super::{FaceGroups, FaceVarying, KnotTags, MeshError, Tags, TopologyWarning};
use crate::hash::FxHasher;

type BuildFx = BuildHasherDefault<FxHasher>;

/// Bound on coordinate magnitudes: a coordinate must be below it (`|x| < 1e75`; 1e75
/// itself is refused). Refinement averages and evaluation multiplies coordinates
/// (normals, tangent-plane projections and curvature multiply up to four of them), and
/// below 1e75 every such product stays finite.
pub const MAX_COORDINATE: f64 = 1e75;

/// A polygon mesh with faces of any size ≥ 3.
///
/// Memory layout (compressed sparse rows): face `f` has the vertices
/// `face_verts[face_offsets[f] .. face_offsets[f + 1]]`, in counter-clockwise order seen
/// from outside. Indices are `u32` (half the memory of `usize`; 4·10⁹ elements are enough
/// for any mesh that fits in memory at refinement time). Positions are `f64` triples.
///
/// ```
/// use subsurf::mesh::PolyMesh;
/// // A unit square as one quad.
/// let m = PolyMesh::from_faces(
///     vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
///     &[vec![0, 1, 2, 3]],
/// ).unwrap();
/// assert_eq!(m.num_faces(), 1);
/// assert_eq!(m.face(0), &[0, 1, 2, 3]);
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolyMesh {
    positions: Vec<[f64; 3]>,
    face_offsets: Vec<u32>,
    face_verts: Vec<u32>,
    /// Creases, corners and holes.
    pub tags: Tags,
    /// Knot intervals and rational weights for non-uniform Catmull-Clark subdivision
    /// ([`crate::nonuniform`]); Catmull-Clark ignores them. Checked by [`KnotTags::validate`].
    pub knots: KnotTags,
    /// Face-varying channels (texture coordinates and any other data per face corner),
    /// each with one index per face-vertex; the OBJ reader names its `vt` channel `"uv"`.
    /// Checked by [`validate`](Self::validate).
    pub face_varying: Vec<FaceVarying>,
    /// The object, group and material of each face and the material libraries (OBJ's
    /// `o`, `g`, `usemtl`, `mtllib`), carried to the children of each face by refinement.
    /// Checked by [`validate`](Self::validate).
    pub groups: FaceGroups,
}

/// A mesh lent: what [`LimitSurface::new`](crate::limit::LimitSurface::new) copies.
impl<'a> From<&'a PolyMesh> for std::borrow::Cow<'a, PolyMesh> {
    fn from(mesh: &'a PolyMesh) -> Self {
        std::borrow::Cow::Borrowed(mesh)
    }
}

/// A mesh given: what [`LimitSurface::new`](crate::limit::LimitSurface::new) takes apart
/// instead of copying.
impl From<PolyMesh> for std::borrow::Cow<'_, PolyMesh> {
    fn from(mesh: PolyMesh) -> Self {
        std::borrow::Cow::Owned(mesh)
    }
}

impl PolyMesh {
    /// Builds a mesh from positions and CSR faces (`face_offsets.len() == faces + 1`,
    /// `face_offsets[0] == 0`, last offset `== face_verts.len()`).
    ///
    /// A face may list a vertex more than once (a degenerate face); refinement treats it as
    /// OpenSubdiv does (its edges become non-manifold, hence infinitely sharp). Use
    /// [`check_strict`](Self::check_strict) to reject such faces.
    ///
    /// # Errors
    /// [`MeshError`] naming the first bad face or vertex: faces with fewer than 3
    /// vertices, out-of-range vertices, non-finite coordinates or coordinates of
    /// [`MAX_COORDINATE`] or more in magnitude.
    pub fn new(
        positions: Vec<[f64; 3]>,
        face_offsets: Vec<u32>,
        face_verts: Vec<u32>,
    ) -> Result<Self, MeshError> {
        let m = Self::new_unchecked(positions, face_offsets, face_verts);
        m.validate()?;
        Ok(m)
    }

    /// Builds a mesh from one vertex list per face. See [`new`](Self::new).
    pub fn from_faces<F: AsRef<[u32]>>(
        positions: Vec<[f64; 3]>,
        faces: &[F],
    ) -> Result<Self, MeshError> {
        let mut offsets = Vec::with_capacity(faces.len() + 1);
        let mut verts = Vec::new();
        offsets.push(0u32);
        for f in faces {
            verts.extend_from_slice(f.as_ref());
            let n = u32::try_from(verts.len()).map_err(|_| MeshError::TooLarge {
                what: "the face-vertex list".into(),
            })?;
            offsets.push(n);
        }
        Self::new(positions, offsets, verts)
    }

    /// Builds a mesh without validation, for callers that produce valid meshes by
    /// construction (refinement); [`validate`](Self::validate) checks them later if needed.
    pub(crate) fn new_unchecked(
        positions: Vec<[f64; 3]>,
        face_offsets: Vec<u32>,
        face_verts: Vec<u32>,
    ) -> Self {
        Self {
            positions,
            face_offsets,
            face_verts,
            tags: Tags::default(),
            knots: KnotTags::default(),
            face_varying: Vec::new(),
            groups: FaceGroups::default(),
        }
    }

    /// Checks every invariant that [`new`](Self::new) promises, plus the tag indices.
    pub fn validate(&self) -> Result<(), MeshError> {
        let nv = self.positions.len();
        if u32::try_from(nv).is_err() {
            return Err(MeshError::TooLarge {
                what: "the vertex count".into(),
            });
        }
        check_coordinates(&self.positions)?;
        let offs = &self.face_offsets;
        if offs.first() != Some(&0) {
            return Err(MeshError::BadFaceOffsets(
                "the first offset must be 0".into(),
            ));
        }
        if *offs.last().unwrap_or(&0) as usize != self.face_verts.len() {
            return Err(MeshError::BadFaceOffsets(
                "the last offset must equal the number of face-vertices".into(),
            ));
        }
        for f in 0..offs.len() - 1 {
            let (a, b) = (offs[f], offs[f + 1]);
            if b < a {
                return Err(MeshError::BadFaceOffsets(format!(
                    "offset of face {f} decreases"
                )));
            }
            let fv = &self.face_verts[a as usize..b as usize];
            if fv.len() < 3 {
                return Err(MeshError::FaceTooSmall {
                    face: f,
                    count: fv.len(),
                });
            }
            for &v in fv {
                if v as usize >= nv {
                    return Err(MeshError::VertexOutOfRange {
                        face: f,
                        index: v as u64,
                        count: nv,
                    });
                }
            }
        }
        self.validate_tags()?;
        for channel in &self.face_varying {
            channel.validate(&self.face_offsets)?;
        }
        self.groups.validate(self.num_faces())
    }

    /// The first face that lists a vertex more than once, as an error.
    pub fn check_repeated_vertices(&self) -> Result<(), MeshError> {
        for (f, fv) in self.faces().enumerate() {
            if let Some(v) = repeated_vertex(fv) {
                return Err(MeshError::RepeatedVertex { face: f, vertex: v });
            }
        }
        Ok(())
    }

    /// The warnings about this mesh that need no topology: faces that list a vertex more
    /// than once ([`TopologyWarning::DegenerateFaces`]) and creases whose two vertices
    /// share no edge ([`TopologyWarning::CreaseEdgeMissing`], one per such crease). The
    /// same warnings as [`Topology::from_mesh`](super::Topology::from_mesh) gives about
    /// them, in one pass over the faces: for the jobs that build no topology of their
    /// own before they evaluate.
    pub fn warnings(&self) -> Vec<TopologyWarning> {
        let mut warnings = Vec::new();
        let mut degenerate = self
            .faces()
            .enumerate()
            .filter(|(_, fv)| repeated_vertex(fv).is_some());
        if let Some((first, _)) = degenerate.next() {
            warnings.push(TopologyWarning::DegenerateFaces {
                count: 1 + degenerate.count(),
                first: first as u32,
            });
        }
        let creases = &self.tags.creases;
        if creases.is_empty() {
            return warnings;
        }
        let key = |a: u32, b: u32| (a.min(b), a.max(b));
        let mut missing: std::collections::HashSet<(u32, u32), BuildFx> =
            creases.iter().map(|c| key(c.v0, c.v1)).collect();
        for fv in self.faces() {
            for (i, &a) in fv.iter().enumerate() {
                missing.remove(&key(a, fv[(i + 1) % fv.len()]));
            }
            if missing.is_empty() {
                return warnings;
            }
        }
        warnings.extend(creases.iter().enumerate().filter_map(|(i, c)| {
            missing
                .contains(&key(c.v0, c.v1))
                .then_some(TopologyWarning::CreaseEdgeMissing {
                    crease: i,
                    v0: c.v0,
                    v1: c.v1,
                })
        }));
        warnings
    }

    /// Strict validation: no face repeats a vertex, and the topology is manifold and
    /// consistently oriented (see [`crate::mesh::Topology::check_manifold`]).
    pub fn check_strict(&self) -> Result<(), MeshError> {
        self.check_repeated_vertices()?;
        let (t, _) = super::Topology::from_mesh(self, &super::Options::default())?;
        t.check_manifold()
    }

    fn validate_tags(&self) -> Result<(), MeshError> {
        let nv = self.positions.len();
        let nf = self.num_faces();
        for c in &self.tags.creases {
            for v in [c.v0, c.v1] {
                if v as usize >= nv {
                    return Err(MeshError::TagOutOfRange {
                        what: "a crease",
                        kind: "vertex",
                        index: v as u64,
                        count: nv,
                    });
                }
            }
            if c.sharpness.is_nan() || c.sharpness < 0.0 {
                return Err(MeshError::BadSharpness {
                    what: format!("the crease on edge ({}, {})", c.v0, c.v1),
                    value: c.sharpness,
                });
            }
        }
        for c in &self.tags.corners {
            if c.vertex as usize >= nv {
                return Err(MeshError::TagOutOfRange {
                    what: "a corner",
                    kind: "vertex",
                    index: c.vertex as u64,
                    count: nv,
                });
            }
            if c.sharpness.is_nan() || c.sharpness < 0.0 {
                return Err(MeshError::BadSharpness {
                    what: format!("the corner at vertex {}", c.vertex),
                    value: c.sharpness,
                });
            }
        }
        for &h in &self.tags.holes {
            if h as usize >= nf {
                return Err(MeshError::TagOutOfRange {
                    what: "a hole",
                    kind: "face",
                    index: h as u64,
                    count: nf,
                });
            }
        }
        Ok(())
    }

    /// The mesh's positions, face offsets and face vertices (CSR) and tags, taken apart
    /// (the knot tags, face-varying channels and face groups are dropped).
    pub(crate) fn into_parts(self) -> (Vec<[f64; 3]>, Vec<u32>, Vec<u32>, Tags) {
        (
            self.positions,
            self.face_offsets,
            self.face_verts,
            self.tags,
        )
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }

    /// The position buffer itself, for writers that fill it whole
    /// ([`RefinePlan::apply_into`](crate::refine::RefinePlan::apply_into)); its length must
    /// stay the number of vertices.
    pub(crate) fn positions_vec_mut(&mut self) -> &mut Vec<[f64; 3]> {
        &mut self.positions
    }

    /// Mutable vertex positions (topology stays fixed).
    pub fn positions_mut(&mut self) -> &mut [[f64; 3]] {
        &mut self.positions
    }

    /// Number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.positions.len()
    }

    /// Number of faces.
    pub fn num_faces(&self) -> usize {
        self.face_offsets.len().saturating_sub(1)
    }

    /// The vertices of face `f`.
    ///
    /// # Panics
    /// If `f >= num_faces()`.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.face_verts[self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize]
    }

    /// Iterator over all faces' vertex lists.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = &[u32]> + '_ {
        self.face_offsets
            .windows(2)
            .map(move |w| &self.face_verts[w[0] as usize..w[1] as usize])
    }

    /// CSR offsets (`num_faces() + 1` entries).
    pub fn face_offsets(&self) -> &[u32] {
        &self.face_offsets
    }

    /// CSR face-vertex indices.
    pub fn face_verts(&self) -> &[u32] {
        &self.face_verts
    }

    /// Axis-aligned bounding box `(min, max)`, or `None` for a mesh without vertices.
    pub fn bounding_box(&self) -> Option<([f64; 3], [f64; 3])> {
        let first = *self.positions.first()?;
        let mut lo = first;
        let mut hi = first;
        for p in &self.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        Some((lo, hi))
    }
}

/// A vertex that `face` lists more than once, if any (quadratic for small faces, sorting
/// for large ones).
pub(crate) fn repeated_vertex(face: &[u32]) -> Option<u32> {
    if face.len() <= 32 {
        face.iter()
            .enumerate()
            .find(|&(i, v)| face[..i].contains(v))
            .map(|(_, &v)| v)
    } else {
        let mut sorted = face.to_vec();
        sorted.sort_unstable();
        sorted.windows(2).find(|w| w[0] == w[1]).map(|w| w[0])
    }
}

/// Checks that every coordinate is finite and below [`MAX_COORDINATE`] in magnitude
/// (`|x| < 1e75`).
///
/// # Errors
/// [`MeshError::NonFiniteCoordinate`] or [`MeshError::CoordinateTooLarge`], naming the
/// first vertex at fault.
pub(crate) fn check_coordinates(positions: &[[f64; 3]]) -> Result<(), MeshError> {
    for (v, p) in positions.iter().enumerate() {
        for &c in p {
            if !c.is_finite() {
                return Err(MeshError::NonFiniteCoordinate {
                    vertex: v,
                    value: c,
                });
            }
            if c.abs() >= MAX_COORDINATE {
                return Err(MeshError::CoordinateTooLarge {
                    vertex: v,
                    value: c,
                });
            }
        }
    }
    Ok(())
}
