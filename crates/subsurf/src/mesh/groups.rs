//! [`FaceGroups`]: the object, group and material of each face, as OBJ's `o`, `g`,
//! `usemtl` and `mtllib` statements give them.

use super::MeshError;

/// The object (`o`), group (`g`) and material (`usemtl`) that a face was read under: the
/// text after the keyword (several group names as written, separated by single spaces),
/// `None` before the file's first such statement.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct GroupState {
    /// `o NAME`.
    pub object: Option<String>,
    /// `g NAME...`.
    pub group: Option<String>,
    /// `usemtl NAME`.
    pub material: Option<String>,
}

/// The grouping of a mesh's faces, compactly: the distinct [`GroupState`]s and the index
/// of each face's, plus the material libraries (`mtllib`). OBJ files carry it
/// ([`crate::io::parse_obj`] reads it, [`crate::io::write_obj`] writes it); refinement
/// gives every child face its parent's state, so a subdivided textured model keeps its
/// materials; other operations that make new faces (tessellation, the paper methods) do
/// not carry it.
///
/// Empty (the [`Default`]) when no face is grouped and no library named.
///
/// ```
/// use subsurf::mesh::{FaceGroups, GroupState};
/// let red = GroupState { material: Some("red".into()), ..GroupState::default() };
/// let groups = FaceGroups {
///     material_libraries: vec!["colours.mtl".into()],
///     states: vec![GroupState::default(), red],
///     face_states: vec![0, 1, 1],
/// };
/// assert!(groups.validate(3).is_ok());
/// assert_eq!(groups.state(2).and_then(|s| s.material.as_deref()), Some("red"));
/// ```
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FaceGroups {
    /// The arguments of the `mtllib` statements, in the order read.
    pub material_libraries: Vec<String>,
    /// The distinct states, in the order of their first face.
    pub states: Vec<GroupState>,
    /// The index in `states` of each face's state: one per face, or empty when no face is
    /// grouped.
    pub face_states: Vec<u32>,
}

impl FaceGroups {
    /// Whether there is nothing to carry: no face grouped, no library.
    pub fn is_empty(&self) -> bool {
        self.face_states.is_empty() && self.material_libraries.is_empty()
    }

    /// The state of face `f`, if faces are grouped.
    pub fn state(&self, f: usize) -> Option<&GroupState> {
        let &s = self.face_states.get(f)?;
        self.states.get(s as usize)
    }

    /// Checks the grouping against a mesh of `faces` faces: `face_states` empty or one per
    /// face, each in range.
    ///
    /// # Errors
    /// [`MeshError::BadFaceGroups`] naming the first face at fault.
    pub fn validate(&self, faces: usize) -> Result<(), MeshError> {
        let bad = |message: String| Err(MeshError::BadFaceGroups { message });
        if !self.face_states.is_empty() && self.face_states.len() != faces {
            return bad(format!(
                "{} face states for a mesh of {faces} faces",
                self.face_states.len()
            ));
        }
        match (self.face_states.iter()).position(|&s| s as usize >= self.states.len()) {
            Some(f) => bad(format!(
                "face {f} has state {}, but there are {} states",
                self.face_states[f],
                self.states.len()
            )),
            None => Ok(()),
        }
    }

    /// The grouping of a mesh whose faces are, in order, `children(f)` faces for each face
    /// `f` of this one (its children, contiguous, as refinement numbers them), each in its
    /// parent's state.
    pub(crate) fn for_children(&self, children: impl Fn(usize) -> usize) -> Self {
        let mut face_states = Vec::new();
        for (f, &s) in self.face_states.iter().enumerate() {
            face_states.extend(std::iter::repeat_n(s, children(f)));
        }
        Self {
            material_libraries: self.material_libraries.clone(),
            states: self.states.clone(),
            face_states,
        }
    }
}
