//! Mesh errors and warnings told in the terms of the OBJ file they came from.
//!
//! [`MeshError`] and [`TopologyWarning`] number faces and vertices from 0, as the library
//! does. In a message about a file, the numbers should be the file's: OBJ counts vertices
//! from 1 (as `f` statements refer to them), and faces are counted here from 1 too, in the
//! order of their `f` statements, with the line of the statement. (Tag indices, as in
//! `t hole 1/0/0 0`, stay 0-based, as OpenSubdiv's tags are; messages about tags keep the
//! library's numbering.) A mesh read from PLY, whose vertex lists count from 0, is
//! described from 0 ([`ObjFile::describe_error_from`]).

use super::ObjFile;
use crate::mesh::{MeshError, TopologyWarning};

impl ObjFile {
    /// The line of face `f`'s `f` statement (1-based), if the face came from this file.
    pub fn face_line(&self, f: usize) -> Option<usize> {
        self.face_lines.get(f).map(|&l| l as usize)
    }

    /// The line of the first face that uses vertex `v`.
    fn vertex_line(&self, v: u32) -> Option<usize> {
        let f = self.mesh.faces().position(|fv| fv.contains(&v))?;
        self.face_line(f)
    }

    /// The line of the first face with an edge `a`–`b`.
    fn edge_line(&self, a: u32, b: u32) -> Option<usize> {
        let f = self.mesh.faces().position(|fv| {
            (0..fv.len()).any(|i| {
                let (x, y) = (fv[i], fv[(i + 1) % fv.len()]);
                (x, y) == (a, b) || (x, y) == (b, a)
            })
        })?;
        self.face_line(f)
    }

    /// `e` in the file's terms: the line it concerns (a face's `f` line; for a vertex, the
    /// first face using it) and the message with faces and vertices numbered from 1 (module
    /// docs). Errors that concern no face or vertex of the file keep their text.
    pub fn describe_error(&self, e: &MeshError) -> (Option<usize>, String) {
        self.describe_error_from(e, 1)
    }

    /// [`describe_error`](Self::describe_error) with faces and vertices numbered from
    /// `first` (1 for OBJ, 0 for PLY; [`MeshFormat::first_index`](crate::io::input::MeshFormat::first_index)).
    pub fn describe_error_from(&self, e: &MeshError, first: u64) -> (Option<usize>, String) {
        let n = |i: u64| i + first;
        match *e {
            MeshError::RepeatedVertex { face, vertex } => (
                self.face_line(face),
                format!(
                    "face {} lists vertex {} more than once",
                    n(face as u64),
                    n(u64::from(vertex))
                ),
            ),
            MeshError::NonManifoldEdge {
                v0,
                v1,
                faces,
                first,
                second,
            } => (
                self.face_line(second as usize),
                format!(
                    "edge {}-{} is shared by {faces} faces (non-manifold); faces {} and {} are \
                     two of them",
                    n(u64::from(v0)),
                    n(u64::from(v1)),
                    n(u64::from(first)),
                    n(u64::from(second))
                ),
            ),
            MeshError::InconsistentOrientation { f0, f1, v0, v1 } => (
                self.face_line(f1 as usize),
                format!(
                    "faces {} and {} are oriented inconsistently: both run edge {}-{} in the \
                     same direction",
                    n(u64::from(f0)),
                    n(u64::from(f1)),
                    n(u64::from(v0)),
                    n(u64::from(v1))
                ),
            ),
            MeshError::NonManifoldVertex { vertex, faces } => (
                self.vertex_line(vertex),
                format!(
                    "vertex {} is non-manifold: its {faces} faces do not form a single fan",
                    n(u64::from(vertex))
                ),
            ),
            _ => (None, e.to_string()),
        }
    }

    /// `w` in the file's terms, as [`ObjFile::describe_error`] (the line of the first
    /// element concerned).
    pub fn describe_warning(&self, w: &TopologyWarning) -> (Option<usize>, String) {
        self.describe_warning_from(w, 1)
    }

    /// [`describe_warning`](Self::describe_warning) with faces and vertices numbered from
    /// `first`, as [`describe_error_from`](Self::describe_error_from).
    pub fn describe_warning_from(
        &self,
        w: &TopologyWarning,
        first: u64,
    ) -> (Option<usize>, String) {
        let n = |i: u64| i + first;
        let then = w.consequence();
        match *w {
            TopologyWarning::DegenerateFaces { count, first } => (
                self.face_line(first as usize),
                format!(
                    "{count} face(s) (first: face {}) list a vertex more than once; {then}",
                    n(u64::from(first))
                ),
            ),
            TopologyWarning::NonManifoldEdges { count, first } => (
                self.edge_line(first.0, first.1),
                format!(
                    "{count} non-manifold edge(s) (first: {}-{}) {then}",
                    n(u64::from(first.0)),
                    n(u64::from(first.1))
                ),
            ),
            TopologyWarning::NonManifoldVertices { count, first } => (
                self.vertex_line(first),
                format!(
                    "{count} non-manifold vertex/vertices (first: {}) {then}",
                    n(u64::from(first))
                ),
            ),
            _ => (None, w.to_string()),
        }
    }
}
