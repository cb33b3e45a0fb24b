//! [`FaceVarying`]: data per face corner with its own topology (texture coordinates).

use super::MeshError;

/// A face-varying channel: values of any dimension attached to face corners, as
/// OpenSubdiv's face-varying channels (`Far::TopologyDescriptor::FVarChannel`).
///
/// `indices` has one entry per face-vertex of the mesh, in the mesh's CSR order
/// ([`PolyMesh::face_verts`](super::PolyMesh::face_verts)): corner `i` of face `f` takes
/// value `indices[face_offsets[f] + i]`, whose `dim` components are
/// `values[dim * index ..][..dim]`. Faces that share a vertex may give it different values:
/// where two faces sharing an edge disagree at either end, the edge is a *seam* (a
/// face-varying boundary), interpolated by OpenSubdiv's rules for such boundaries
/// ([`FaceVaryingInterpolation`](super::FaceVaryingInterpolation)).
///
/// ```
/// use subsurf::mesh::{FaceVarying, PolyMesh};
/// let mut quad = PolyMesh::from_faces(
///     vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
///     &[[0u32, 1, 2, 3]],
/// ).unwrap();
/// let uv = FaceVarying::new("uv", 2, vec![0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0], vec![0, 1, 2, 3]).unwrap();
/// quad.face_varying.push(uv);
/// assert!(quad.validate().is_ok());
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct FaceVarying {
    name: String,
    dim: usize,
    values: Vec<f64>,
    indices: Vec<u32>,
}

impl FaceVarying {
    /// A channel named `name` (OBJ texture coordinates are named `"uv"`) of `dim`
    /// components per value.
    ///
    /// # Errors
    /// [`MeshError::BadFaceVarying`] when `dim` is 0, `values.len()` is not a multiple of
    /// `dim` or a value is not finite; [`MeshError::TooLarge`] beyond `u32::MAX` values.
    /// The indices are checked against a mesh by [`validate`](Self::validate) (which
    /// [`PolyMesh::validate`](super::PolyMesh::validate) calls), naming the face at fault.
    pub fn new(
        name: impl Into<String>,
        dim: usize,
        values: Vec<f64>,
        indices: Vec<u32>,
    ) -> Result<Self, MeshError> {
        let fv = Self {
            name: name.into(),
            dim,
            values,
            indices,
        };
        fv.check_values()?;
        Ok(fv)
    }

    /// Builds a channel without checks, for refinement (valid by construction).
    pub(crate) fn new_unchecked(
        name: String,
        dim: usize,
        values: Vec<f64>,
        indices: Vec<u32>,
    ) -> Self {
        Self {
            name,
            dim,
            values,
            indices,
        }
    }

    fn bad(&self, message: String) -> MeshError {
        MeshError::BadFaceVarying {
            channel: self.name.clone(),
            message,
        }
    }

    fn check_values(&self) -> Result<(), MeshError> {
        if self.dim == 0 {
            return Err(self.bad("its values have 0 components".into()));
        }
        if !self.values.len().is_multiple_of(self.dim) {
            return Err(self.bad(format!(
                "{} numbers do not make whole values of {} components",
                self.values.len(),
                self.dim
            )));
        }
        if u32::try_from(self.num_values()).is_err() {
            return Err(MeshError::TooLarge {
                what: format!("the values of face-varying channel '{}'", self.name),
            });
        }
        if let Some(i) = self.values.iter().position(|x| !x.is_finite()) {
            return Err(self.bad(format!(
                "value {} has a non-finite component ({})",
                i / self.dim,
                self.values[i]
            )));
        }
        Ok(())
    }

    /// Checks the channel against a mesh's faces (CSR offsets): values as in
    /// [`new`](Self::new), one index per face-vertex, every index in range.
    ///
    /// # Errors
    /// [`MeshError::BadFaceVarying`] or [`MeshError::FaceVaryingOutOfRange`] naming the
    /// first face at fault.
    pub fn validate(&self, face_offsets: &[u32]) -> Result<(), MeshError> {
        self.check_values()?;
        let corners = face_offsets.last().copied().unwrap_or(0) as usize;
        if self.indices.len() != corners {
            return Err(self.bad(format!(
                "it has {} face-corner indices, but the mesh has {corners} face-vertices",
                self.indices.len()
            )));
        }
        let n = self.num_values();
        for (f, w) in face_offsets.windows(2).enumerate() {
            for &i in &self.indices[w[0] as usize..w[1] as usize] {
                if i as usize >= n {
                    return Err(MeshError::FaceVaryingOutOfRange {
                        channel: self.name.clone(),
                        face: f,
                        index: i as u64,
                        count: n,
                    });
                }
            }
        }
        Ok(())
    }

    /// The channel's name (`"uv"` for OBJ texture coordinates).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Components per value.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of values.
    pub fn num_values(&self) -> usize {
        self.values.len() / self.dim.max(1)
    }

    /// Value `i` (its `dim` components).
    ///
    /// # Panics
    /// If `i >= num_values()`.
    pub fn value(&self, i: usize) -> &[f64] {
        &self.values[self.dim * i..self.dim * (i + 1)]
    }

    /// All values, `dim` numbers each.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The value index of every face corner, in the mesh's face-vertex order.
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }
}
