//! Building a [`LimitSurface`] with choices beyond the scheme: a memory limit, and which
//! faces to build.
//!
//! [`LimitSurface::new`] builds every face. A job that evaluates some faces only (the
//! quads of a mixed mesh, as OpenSubdiv's `Bfr` benchmarks and `subsurf limit --grid` do;
//! a region being edited; the faces in view) can build those alone: the surface keeps
//! nothing for the others and refuses to evaluate them ([`EvalError::NotBuilt`]). On an
//! all-triangle scan, whose every face is irregular, a surface of no faces takes a fifth
//! of the memory of a full one (BENCHMARKS.md; `subsurf bench --limit-grid 8` evaluates
//! quads only).
//!
//! The surface of a face does not depend on which other faces are built: each face's
//! nodes are computed from the control points and topology around it (its 1-ring, or its
//! cut-out), which the surface holds in full.
//!
//! [`EvalError::NotBuilt`]: super::EvalError::NotBuilt

use std::borrow::Cow;

use super::memory::Budget;
use super::surface::FaceSelect;
use super::{BuildError, LimitSurface};
use crate::mesh::{Options, PolyMesh};

/// A [`LimitSurface`] to build ([`LimitSurface::builder`]): the mesh and scheme, and
/// optionally a memory limit ([`Self::max_bytes`]) and the faces to build
/// ([`Self::faces`]).
///
/// ```
/// use subsurf::limit::{EvalError, LimitSurface};
/// use subsurf::mesh::{Options, PolyMesh};
/// // A quad and a triangle sharing an edge.
/// let mesh = PolyMesh::from_faces(
///     vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [2.0, 0.5, 0.0]],
///     &[vec![0u32, 1, 2, 3], vec![1, 4, 2]],
/// )
/// .unwrap();
/// let quads = LimitSurface::builder(&mesh, Options::default())
///     .faces(|_, verts| verts.len() == 4)
///     .build()
///     .unwrap();
/// let all = LimitSurface::new(&mesh, Options::default()).unwrap();
/// // The quad's surface is the same as in a surface of every face…
/// assert_eq!(quads.eval(0, 0.3, 0.7).unwrap().p, all.eval(0, 0.3, 0.7).unwrap().p);
/// // …and the triangle has none.
/// assert!(!quads.has_surface(1) && all.has_surface(1));
/// assert_eq!(quads.eval(1, 0.5, 0.5), Err(EvalError::NotBuilt { face: 1 }));
/// ```
#[must_use = "a builder does nothing until `build` is called"]
pub struct SurfaceBuilder<'a> {
    mesh: Cow<'a, PolyMesh>,
    options: Options,
    max_bytes: Option<u64>,
    faces: Option<Box<FaceSelect<'a>>>,
}

impl std::fmt::Debug for SurfaceBuilder<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SurfaceBuilder")
            .field("faces", &self.mesh.num_faces())
            .field("options", &self.options)
            .field("max_bytes", &self.max_bytes)
            .field("some_faces", &self.faces.is_some())
            .finish()
    }
}

impl LimitSurface {
    /// A builder of the surface of `mesh` with scheme `options`, which takes the mesh or a
    /// reference to it as [`LimitSurface::new`] does. Without further choices its
    /// [`build`](SurfaceBuilder::build) is [`LimitSurface::new`].
    pub fn builder<'a>(mesh: impl Into<Cow<'a, PolyMesh>>, options: Options) -> SurfaceBuilder<'a> {
        SurfaceBuilder {
            mesh: mesh.into(),
            options,
            max_bytes: None,
            faces: None,
        }
    }
}

impl<'a> SurfaceBuilder<'a> {
    /// Stops the build with [`BuildError::TooLarge`] once the configurations found would
    /// take the estimate over `max_bytes`, as [`LimitSurface::new_within`] does (which is
    /// this builder with this limit).
    pub fn max_bytes(mut self, max_bytes: u64) -> Self {
        self.max_bytes = Some(max_bytes);
        self
    }

    /// Builds only the faces for which `select(face, its vertices)` is true (by default
    /// every face). The surface of a face built is the same as in a surface of every
    /// face; the others have no surface ([`LimitSurface::has_surface`] is false, and
    /// evaluating them is [`EvalError::NotBuilt`](super::EvalError::NotBuilt)) and cost 4
    /// bytes each; [`tessellate`](fn@super::tessellate) leaves them out as it leaves holes.
    /// `select` is called once per face, from several threads.
    pub fn faces(mut self, select: impl Fn(usize, &[u32]) -> bool + Sync + 'a) -> Self {
        self.faces = Some(Box::new(select));
        self
    }

    /// Builds the surface.
    ///
    /// # Errors
    /// [`BuildError::Mesh`] if the mesh is invalid; [`BuildError::TooLarge`] if a memory
    /// limit was set and the surface would exceed it (before anything is built if the
    /// mesh alone does, by [`LimitSurface::estimate_build_memory`]).
    pub fn build(self) -> Result<LimitSurface, BuildError> {
        let budget = self.max_bytes.map(|limit| Budget {
            fixed: LimitSurface::estimate_build_memory(&self.mesh),
            limit,
        });
        if let Some(budget) = budget.filter(|b| b.exceeded_by(0)) {
            return Err(BuildError::TooLarge {
                configurations: 0,
                limit: budget.limit,
            });
        }
        let all = |_: usize, _: &[u32]| true;
        let select = self.faces.as_deref().unwrap_or(&all);
        LimitSurface::build(self.mesh, self.options, budget, select)
    }
}
