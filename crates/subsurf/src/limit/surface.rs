//! [`LimitSurface`]: exact evaluation of the Catmull-Clark limit surface at any
//! `(face, u, v)`, with first and second derivatives.
//!
//! # Method
//! The limit surface over a *regular* quad is one bicubic B-spline patch
//! ([`crate::refine::patch`]), evaluated in closed form; so is a quad that is regular but for one
//! straight semi-sharp crease ([`super::crease_patch`]: the tensor product of the
//! B-spline basis along the crease and the crease curve scheme's limit functions across
//! it). Any other face (next to an extraordinary vertex, a dart, other semi-sharp
//! features, an n-gon, a non-manifold or irregular boundary vertex) is refined locally:
//! its 1-ring is cut out ([`super::local`]) and refined one level with the full
//! OpenSubdiv rules; each of its four children is again a patch or refined further.
//! Irregularities stay at the corners of sub-faces, so each level leaves at most one
//! irregular child per irregular corner, and a point at distance `d` from an irregular
//! corner is reached after about `log₂(1/d)` levels. A point exactly at an irregular
//! corner (or closer than `2^-MAX_DEPTH`) takes its position and tangent plane from the
//! corner's analysis ([`super::corner`]: OpenSubdiv's limit masks, or an eigen-analysis of
//! the corner's sector).
//!
//! The local refinement depends only on the cut-out's topology, so it is done once per
//! distinct neighbourhood (*configuration*), lazily, as deep as evaluated points need, as
//! weights on the cut-out's control points ([`super::tree`], as OpenSubdiv's `Bfr` caches
//! its patch trees); a face only stores its cut-out's positions, which flow down its
//! configuration's tree when points are evaluated. Cut-outs are compared up to where the
//! cycles around their interior vertices start (`Topology::subset_canonical`), so the faces
//! around a symmetric pole share one configuration. Faces whose 1-ring reaches a vertex of
//! more than [`HIGH_VALENCE`] faces (a quarter of that on a boundary or non-manifold
//! vertex, whose faces cannot share configurations that way: they would be as many as the
//! vertex's faces, each of size `O(valence)`) instead refine their positions directly, in
//! regions shared around the vertex ([`super::local`]).
//!
//! This is exact, not an approximation: the only truncation is at `2^-MAX_DEPTH ≈ 4e-15`
//! of a face, far below `f64` resolution of typical coordinates.
//!
//! # Cost
//! [`LimitSurface::new`] analyses every face (regular faces cost a few walks around their
//! corners) and finds each irregular face's configuration; the levels of a configuration's
//! tree are built the first time a point needs them (thread-safely, so batched parallel
//! evaluation shares them). [`LimitSurface::set_positions`] moves the control points and
//! keeps the trees, so re-evaluating an animated or optimised mesh costs only the per-face
//! work: a face that is one patch reads its control points from the surface's positions
//! when evaluated (a regular face whose control points are vertices: [`Node::Plain`],
//! made from the topology; at a boundary or single crease: [`Node::Net`], its net as
//! combinations of vertices), a tree face keeps how its nodes follow the control points
//! ([`Recipe`]: its cut-out's vertices) and is updated in place; faces in shared regions
//! keep the regions' shapes (`local::Shape`) and recompute only their points.
//! [`LimitSurface::eval_many`] evaluates the points of one face together, computing each
//! tree node's (or region's) points once, and the points of one patch four at a time on
//! vectors (`bspline::tensor_batch`). Measured against OpenSubdiv's `Bfr` in
//! `BENCHMARKS.md`.
//!
//! # Parametrisation
//! A quad `[v0 v1 v2 v3]` has `(0, 0)` at `v0`, `u` toward `v1`, `v` toward `v3` (as
//! OpenSubdiv's `Bfr`). An `n`-gon (`n ≠ 4`) is split into `n` quad sub-faces, the children
//! of one Catmull-Clark step: sub-face `j` has `(0, 0)` at the face's vertex `j`, `u` toward
//! the midpoint of edge `j` (toward vertex `j + 1`), `v` toward the midpoint of edge `j - 1`,
//! and `(1, 1)` at the face's centre.
//!
//! # At an irregular corner
//! The parametric derivatives of the limit surface are degenerate (zero or unbounded) at
//! an extraordinary vertex. There, [`LimitSurface::eval`] returns the exact limit
//! position, and as `du`, `dv` the limit *tangent vectors* of OpenSubdiv's tangent masks
//! oriented along the face's `u` and `v` edges: they span the exact tangent plane (their
//! cross product is the exact limit normal) but their lengths are not parametric
//! derivatives; second derivatives are zero.

use super::bspline::{self, Batch, Derivatives, Order, RegularBases};
use super::corner::{corner_limit, is_limit_corner, SectorCache};
use super::crease_patch::{single_crease, CreaseBasis, CreasePatch};
use super::local::{
    cut_out, own_cut, region_cut, FaceKind, LevelRef, Local, Reach, Region, RegionCache, Seed,
    ShapeCache, HIGH_VALENCE,
};
use super::memory::{Budget, BuildError};
use super::tree::{
    by_quadrant, scale_at, take_corners, Ctx, Kid, Leaf, Query, Scratch, Sink, Tree, TreeCache,
};
use crate::mesh::{MeshError, Options, PolyMesh, Topology};
use crate::refine::patch::{plain_net, regular_patch_cells, Net};
use rayon::prelude::*;
use std::borrow::Cow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

/// Deepest local refinement; a sub-face is then `2^-48` of its face.
pub const MAX_DEPTH: u32 = 48;

/// Where to evaluate: a face (and, for a non-quad, a sub-face) and a parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Base face.
    pub face: u32,
    /// Sub-face of an `n`-gon (0 for quads).
    pub subface: u32,
    /// Parameter along `u`, in `[0, 1]`.
    pub u: f64,
    /// Parameter along `v`, in `[0, 1]`.
    pub v: f64,
}

/// Errors of [`LimitSurface`] evaluation.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EvalError {
    /// The face index is out of range.
    #[error("face {face} does not exist (the mesh has {count} faces)")]
    NoSuchFace {
        /// Requested face.
        face: u32,
        /// Number of faces.
        count: usize,
    },
    /// The sub-face index is out of range for the face's size.
    #[error("face {face} has {size} sub-faces; sub-face {subface} does not exist")]
    NoSuchSubface {
        /// Face.
        face: u32,
        /// Requested sub-face.
        subface: u32,
        /// Face size (number of sub-faces; 1 for quads).
        size: usize,
    },
    /// The face was left out of the build ([`SurfaceBuilder::faces`]): no surface.
    ///
    /// [`SurfaceBuilder::faces`]: super::SurfaceBuilder::faces
    #[error("face {face} was not built (the surface was built for chosen faces only)")]
    NotBuilt {
        /// Face.
        face: u32,
    },
    /// The face is a hole (or excluded by `BoundaryInterpolation::None`): no surface.
    #[error("face {face} is a hole: it has no limit surface")]
    Hole {
        /// Face.
        face: u32,
    },
    /// The surface over the face has no exact evaluation (the NURSS surface near unequal
    /// knot intervals, see [`NurssSurface`](crate::nonuniform::NurssSurface)).
    #[error("face {face}: the surface has no exact evaluation here ({reason})")]
    NotExact {
        /// Face.
        face: u32,
        /// Why.
        reason: &'static str,
    },
    /// A parameter outside `[0, 1]` or not finite.
    #[error("parameter ({u}, {v}) is outside [0, 1]²")]
    BadParameter {
        /// `u`.
        u: f64,
        /// `v`.
        v: f64,
    },
    /// A parameter outside a triangle domain `u, v ≥ 0, u + v ≤ 1`
    /// ([`Domain::Triangle`](super::Domain::Triangle)) or not finite.
    #[error("parameter ({u}, {v}) is outside the triangle u, v ≥ 0, u + v ≤ 1")]
    OutsideTriangle {
        /// `u`.
        u: f64,
        /// `v`.
        v: f64,
    },
    /// The control points last written by [`LimitSurface::update_positions`] were not
    /// valid: the surface has no shape until valid ones are set.
    #[error(
        "control point {vertex} is not valid (not finite, or too large): set valid points first"
    )]
    InvalidPositions {
        /// The first bad vertex.
        vertex: usize,
    },
}

/// The limit surface of one face (or sub-face).
#[derive(Clone, Debug)]
pub(super) enum Node {
    Hole,
    /// A regular quad of the base mesh whose 16 control points are base vertices (every
    /// patch away from boundaries and creases): the face's index. Its net is gathered
    /// from the topology ([`plain_net`]) and its points from the surface's positions
    /// ([`Ctx::pos`]) when evaluated, so nothing is stored for it (the surface does not
    /// even keep the node: [`LimitSurface::faces`]), and nothing is updated when the mesh
    /// is re-posed.
    Plain(u32),
    /// A bicubic patch: its control points `cp[i][j]` (`i` along `u`).
    Regular(Box<[[[f64; 3]; 4]; 4]>),
    /// A quad of the base mesh that is one patch (regular, or with one straight semi-sharp
    /// crease) whose control points are combinations of base vertices (phantom points at
    /// a boundary or crease): its net, whose points are computed from the surface's
    /// positions ([`Ctx::pos`]) when evaluated, as a [`Node::Plain`]'s are, so nothing is
    /// updated when the mesh is re-posed (its control points, kept, took 384 bytes more:
    /// 0.8 MiB on `catmark_pawn` refined four times).
    Net(Box<PatchNet>),
    /// A regular face of a shared region ([`super::local`]): its net is the one the region
    /// keeps for the face, and its points are computed from the region's when evaluated
    /// (the region keeps both anyway; its control points, kept, took 384 bytes more: 1.9
    /// of the 14.6 MB of `catmark_nonman_quadpole360`'s heap).
    InRegion(Box<Local>),
    /// A quad that is regular but for one straight semi-sharp crease: closed form.
    Crease(Box<CreasePatch>),
    /// An irregular (sub-)face: the tree of its neighbourhood's configuration, shared
    /// with every face that has the same, and its cut-out's points.
    Tree(Box<TreeFace>),
    /// An irregular (sub-)face near a vertex of more than [`HIGH_VALENCE`] faces: its
    /// cut-out (or shared region), refined into four children the first time a point
    /// needs them.
    Lazy(Box<Lazy>),
}

/// A face evaluated through a configuration [`Tree`].
#[derive(Clone, Debug)]
pub(super) struct TreeFace {
    tree: Arc<Tree>,
    /// The points of the face's cut-out (the tree's root).
    points: CutPoints,
    /// The sub-face of an `n`-gon, `None` for a quad.
    sub: Option<usize>,
}

/// The points of a [`TreeFace`]'s cut-out.
#[derive(Clone, Debug)]
enum CutPoints {
    /// Vertices of the base mesh, whose positions are read from the control points when
    /// the face is evaluated ([`Ctx::pos`]): shared with the face's [`Recipe`], and
    /// nothing to update when the positions change. Kept as positions, they were 6 % of
    /// the heap of a grid with creases on a tenth of its edges.
    Base(Arc<[u32]>),
    /// Positions: a face of a refined cut-out or region, whose points only it holds.
    Own(Arc<[[f64; 3]]>),
}

impl TreeFace {
    /// Evaluates `qs` (see [`Tree::eval`]), the cut-out's points gathered into `scratch`
    /// if they are base vertices.
    fn eval(
        &self,
        qs: &mut [Query],
        depth: u32,
        scratch: &mut Scratch,
        ctx: Ctx<'_>,
        sink: &mut impl Sink,
    ) {
        match &self.points {
            CutPoints::Own(pos) => self.tree.eval(pos, self.sub, qs, depth, scratch, ctx, sink),
            CutPoints::Base(verts) => {
                let mut pos = scratch.take_cut();
                pos.clear();
                pos.extend(verts.iter().map(|&v| ctx.pos[v as usize]));
                self.tree
                    .eval(&pos, self.sub, qs, depth, scratch, ctx, sink);
                scratch.put_cut(pos);
            }
        }
    }
}

/// An irregular node: the cut-out around it and, once built, its children at the corners
/// 0, 1, 2, 3 (quadrants `[0,½]×[0,½]`, `[½,1]×[0,½]`, `[½,1]²`, `[0,½]×[½,1]`).
#[derive(Clone, Debug)]
pub(super) struct Lazy {
    local: Local,
    kids: OnceLock<Box<[Node; 4]>>,
}

impl Node {
    fn lazy(local: Local) -> Node {
        Node::Lazy(Box::new(Lazy {
            local,
            kids: OnceLock::new(),
        }))
    }

    /// The control points `cp[i][j]` of a bicubic patch: a [`Node::Regular`]'s, a
    /// [`Node::Plain`]'s `pos[net[4 i + j]]` (`net` from [`plain_net`] on the base
    /// topology, `pos` the base mesh's points), or those of the net of a [`Node::Net`]
    /// without a crease or a [`Node::InRegion`]; `None` for any other node.
    #[inline]
    fn bicubic(&self, ctx: Ctx<'_>) -> Option<Cow<'_, [[[f64; 3]; 4]; 4]>> {
        match self {
            Node::Plain(f) => {
                let Some(net) = plain_net(ctx.topo, *f as usize) else {
                    unreachable!("face {f} was made plain after its net was found")
                };
                // A loop of copies (nested `array::from_fn` stalled a store forward per
                // point, see `Net::eval`).
                let mut cp = [[[0.0; 3]; 4]; 4];
                for (c, &v) in cp.as_flattened_mut().iter_mut().zip(&net) {
                    *c = ctx.pos[v as usize];
                }
                Some(Cow::Owned(cp))
            }
            Node::Regular(cp) => Some(Cow::Borrowed(cp)),
            Node::Net(p) if p.crease.is_none() => Some(Cow::Owned(p.net.eval(ctx.pos))),
            Node::InRegion(l) => {
                let Some(net) = l.region.patch_net(l.face) else {
                    unreachable!(
                        "face {} of a region was made a patch after its net was found",
                        l.face
                    )
                };
                Some(Cow::Owned(net.eval(l.pos())))
            }
            _ => None,
        }
    }

    /// Evaluates `batch` (`depth` levels below the base face: derivatives scaled by
    /// `scale = 2^depth`) on a node that is one patch (plain, regular, single-crease or a
    /// base face's net); `false`, evaluating nothing, for any other node.
    fn eval_patch(&self, ctx: Ctx<'_>, scale: f64, batch: &mut impl Batch) -> bool {
        if let Some(cp) = self.bicubic(ctx) {
            bspline::tensor_batch(&cp, RegularBases, ctx.order, scale, batch);
        } else if let Some(p) = self.crease_patch(ctx) {
            p.eval_batch(ctx.order, scale, batch);
        } else {
            return false;
        }
        true
    }

    /// The single-crease patch of a [`Node::Crease`], or of a [`Node::Net`] with a crease
    /// (its control points from the base mesh's points `ctx.pos`); `None` for any other
    /// node.
    #[inline]
    fn crease_patch(&self, ctx: Ctx<'_>) -> Option<Cow<'_, CreasePatch>> {
        match self {
            Node::Crease(p) => Some(Cow::Borrowed(p)),
            Node::Net(p) => (p.crease.as_ref()).map(|(side, basis)| {
                Cow::Owned(CreasePatch::from_net(
                    &p.net.eval(ctx.pos),
                    *side,
                    basis.clone(),
                ))
            }),
            _ => None,
        }
    }
}

/// The nodes of one base face: one for a quad (kept inline), one per sub-face of an
/// `n`-gon.
#[derive(Clone, Debug)]
pub(super) enum FaceNodes {
    One(Node),
    Many(Box<[Node]>),
}

impl FaceNodes {
    pub(super) fn as_slice(&self) -> &[Node] {
        match self {
            FaceNodes::One(n) => std::slice::from_ref(n),
            FaceNodes::Many(ns) => ns,
        }
    }

    fn as_mut_slice(&mut self) -> &mut [Node] {
        match self {
            FaceNodes::One(n) => std::slice::from_mut(n),
            FaceNodes::Many(ns) => ns,
        }
    }
}

impl From<Vec<Node>> for FaceNodes {
    fn from(mut nodes: Vec<Node>) -> Self {
        match (nodes.pop(), nodes.is_empty()) {
            (Some(n), true) => FaceNodes::One(n),
            (Some(n), false) => {
                nodes.push(n);
                FaceNodes::Many(nodes.into_boxed_slice())
            }
            (None, _) => FaceNodes::Many(Box::new([])),
        }
    }
}

/// The exact Catmull-Clark limit surface of a mesh, evaluable anywhere. See the module
/// docs for the method and parametrisation.
///
/// ```
/// use subsurf::limit::LimitSurface;
/// use subsurf::mesh::{Options, PolyMesh};
/// // A cube: every vertex is extraordinary (valence 3).
/// let p = vec![
///     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
///     [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
/// ];
/// let f = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
/// let cube = PolyMesh::from_faces(p, &f).unwrap();
/// let s = LimitSurface::new(&cube, Options::default()).unwrap();
/// // By symmetry the centre of the top face lies above the cube's centre.
/// let d = s.eval(1, 0.5, 0.5).unwrap();
/// assert!((d.p[0] - 0.5).abs() < 1e-12 && (d.p[1] - 0.5).abs() < 1e-12);
/// // Its normal points up, out of the cube.
/// assert!(d.normal()[2] > 0.999_999);
/// ```
#[derive(Clone, Debug)]
pub struct LimitSurface {
    options: Options,
    /// The base level's topology (kept for [`Self::set_positions`]).
    base: Arc<Topology>,
    /// The control points (read by [`Node::Plain`] patches).
    pos: Vec<[f64; 3]>,
    /// The first bad vertex of `pos`, if [`LimitSurface::update_positions`] wrote one
    /// (evaluations then fail).
    invalid: Option<usize>,
    /// Valence above which faces share regions (see [`HIGH_VALENCE`]).
    high_valence: usize,
    /// What faces share: configuration trees and crease bases, kept when the positions
    /// change.
    shared: Arc<Shared>,
    /// Per base face, [`PLAIN`] if its surface is a [`Node::Plain`] patch (made from the
    /// face's index when needed: most faces of most meshes, for which the surface keeps
    /// these 4 bytes only), [`UNBUILT`] if it was left out of the build, else the index of
    /// its entry in `built`.
    faces: Vec<u32>,
    /// The faces that are not plain, in order: their nodes and how they follow the
    /// control points.
    built: Vec<BuiltFace>,
}

/// [`LimitSurface::faces`] of a face whose surface is a [`Node::Plain`] patch.
const PLAIN: u32 = u32::MAX;

/// [`LimitSurface::faces`] of a face left out of the build
/// ([`SurfaceBuilder::faces`](super::SurfaceBuilder::faces)).
const UNBUILT: u32 = u32::MAX - 1;

/// Which faces a build builds: called with a face's index and its vertices.
pub(super) type FaceSelect<'a> = dyn Fn(usize, &[u32]) -> bool + Sync + 'a;

/// A base face's nodes (one per sub-face; one for quads) and how they follow the control
/// points.
#[derive(Clone, Debug)]
struct BuiltFace {
    face: u32,
    nodes: FaceNodes,
    recipe: Recipe,
}

impl LimitSurface {
    /// Builds the surface of `mesh` with scheme `options`. Given the mesh itself (not a
    /// reference), the surface takes its points and face lists instead of copying them
    /// (28 bytes a vertex and 4 a face corner less at the peak of building, when the
    /// caller needs the mesh no more).
    ///
    /// # Errors
    /// [`MeshError`] if the mesh is invalid.
    pub fn new<'a>(
        mesh: impl Into<Cow<'a, PolyMesh>>,
        options: Options,
    ) -> Result<Self, MeshError> {
        Self::with_high_valence(mesh, options, HIGH_VALENCE, true)
    }

    /// [`LimitSurface::new`] of the faces `select` accepts, stopped (`TooLarge`) once the
    /// configurations found take the memory estimate over `budget` (see
    /// [`LimitSurface::builder`]).
    pub(super) fn build(
        mesh: Cow<'_, PolyMesh>,
        options: Options,
        budget: Option<Budget>,
        select: &FaceSelect<'_>,
    ) -> Result<Self, BuildError> {
        let mut surface = Self::unplaced(mesh, options, HIGH_VALENCE, true)?;
        let over = |configurations| budget.is_some_and(|b| b.exceeded_by(configurations));
        if surface.place_new(over, select) {
            return Err(BuildError::TooLarge {
                configurations: surface.num_configurations(),
                limit: budget.map_or(u64::MAX, |b| b.limit),
            });
        }
        Ok(surface)
    }

    /// [`LimitSurface::new`] with faces sharing regions around vertices of more than
    /// `high_valence` faces (`usize::MAX`: every face on its own, as tests compare), and
    /// single-crease faces in closed form or through the general local refinement.
    fn with_high_valence<'a>(
        mesh: impl Into<Cow<'a, PolyMesh>>,
        options: Options,
        high_valence: usize,
        crease_patches: bool,
    ) -> Result<Self, MeshError> {
        let mut surface = Self::unplaced(mesh.into(), options, high_valence, crease_patches)?;
        let stopped = surface.place_new(|_| false, &|_, _| true);
        debug_assert!(!stopped, "a build without a limit stopped");
        Ok(surface)
    }

    /// The surface of `mesh` without its nodes ([`Self::place_new`] builds them).
    fn unplaced(
        mesh: Cow<'_, PolyMesh>,
        options: Options,
        high_valence: usize,
        crease_patches: bool,
    ) -> Result<Self, MeshError> {
        mesh.validate()?;
        let (base, pos) = match mesh {
            Cow::Borrowed(mesh) => (
                Topology::from_mesh(mesh, &options)?.0,
                mesh.positions().to_vec(),
            ),
            Cow::Owned(mesh) => Topology::from_owned_mesh(mesh, &options)?,
        };
        let surface = LimitSurface {
            options,
            base: Arc::new(base),
            pos,
            invalid: None,
            high_valence,
            shared: Arc::new(Shared {
                trees: Arc::new(TreeCache::new(crease_patches)),
                ..Shared::default()
            }),
            faces: Vec::new(),
            built: Vec::new(),
        };
        Ok(surface)
    }

    /// Moves the control points to `positions` (one per vertex of the mesh the surface was
    /// built from), keeping everything that depends only on the topology: re-posing an
    /// animated or optimised mesh costs a fraction of [`Self::new`], as the local
    /// refinements of irregular faces (their configuration trees) are kept.
    ///
    /// ```
    /// use subsurf::limit::LimitSurface;
    /// use subsurf::mesh::{Options, PolyMesh};
    /// let p = vec![
    ///     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
    ///     [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
    /// ];
    /// let f = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
    /// let cube = PolyMesh::from_faces(p.clone(), &f).unwrap();
    /// let mut s = LimitSurface::new(&cube, Options::default()).unwrap();
    /// // Scale the cube by 2: the surface scales with it.
    /// let a = s.eval(1, 0.3, 0.6).unwrap().p;
    /// let doubled: Vec<[f64; 3]> = p.iter().map(|q| q.map(|x| 2.0 * x)).collect();
    /// s.set_positions(&doubled).unwrap();
    /// let b = s.eval(1, 0.3, 0.6).unwrap().p;
    /// assert!((0..3).all(|k| (b[k] - 2.0 * a[k]).abs() < 1e-12));
    /// ```
    ///
    /// # Errors
    /// [`MeshError::PositionCount`] if `positions` does not have one point per vertex,
    /// [`MeshError::NonFiniteCoordinate`] or [`MeshError::CoordinateTooLarge`] for a bad
    /// coordinate (as [`PolyMesh::validate`]).
    pub fn set_positions(&mut self, positions: &[[f64; 3]]) -> Result<(), MeshError> {
        let expected = self.base.num_vertices();
        if positions.len() != expected {
            return Err(MeshError::PositionCount {
                expected,
                found: positions.len(),
            });
        }
        crate::mesh::check_coordinates(positions)?;
        self.pos.copy_from_slice(positions);
        self.invalid = None;
        self.place();
        Ok(())
    }

    /// Moves the control points in place: `update` writes the new points over the
    /// surface's own ([`Self::positions`], one per vertex of the mesh the surface was built
    /// from), then the surface follows them as with [`Self::set_positions`]. An animation
    /// or an optimiser that keeps its points in the surface saves the second copy of them
    /// (24 bytes a vertex) that [`Self::set_positions`] reads from.
    ///
    /// ```
    /// use subsurf::limit::{EvalError, LimitSurface};
    /// use subsurf::mesh::{Options, PolyMesh};
    /// let p = vec![
    ///     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
    ///     [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
    /// ];
    /// let f = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
    /// // The surface takes the mesh (its points and faces are not copied).
    /// let mut s = LimitSurface::new(PolyMesh::from_faces(p, &f).unwrap(), Options::default())
    ///     .unwrap();
    /// let a = s.eval(1, 0.3, 0.6).unwrap().p;
    /// // Lift the cube by 1: the surface follows.
    /// s.update_positions(|pos| pos.iter_mut().for_each(|q| q[2] += 1.0)).unwrap();
    /// let b = s.eval(1, 0.3, 0.6).unwrap().p;
    /// assert!((b[2] - a[2] - 1.0).abs() < 1e-12);
    /// // A bad point: refused, and the surface has no shape until the points are valid.
    /// assert!(s.update_positions(|pos| pos[6][0] = f64::NAN).is_err());
    /// assert_eq!(s.eval(1, 0.3, 0.6), Err(EvalError::InvalidPositions { vertex: 6 }));
    /// s.update_positions(|pos| pos[6][0] = 1.0).unwrap();
    /// assert!((s.eval(1, 0.3, 0.6).unwrap().p[2] - b[2]).abs() < 1e-12);
    /// ```
    ///
    /// # Errors
    /// [`MeshError::NonFiniteCoordinate`] or [`MeshError::CoordinateTooLarge`] for a bad
    /// coordinate (as [`PolyMesh::validate`]). The points are then kept as written (the
    /// previous ones are gone), and every evaluation fails with
    /// [`EvalError::InvalidPositions`] until valid points are set by this method or
    /// [`Self::set_positions`].
    pub fn update_positions(
        &mut self,
        update: impl FnOnce(&mut [[f64; 3]]),
    ) -> Result<(), MeshError> {
        update(&mut self.pos);
        if let Err(e) = crate::mesh::check_coordinates(&self.pos) {
            self.invalid = Some(match e {
                MeshError::NonFiniteCoordinate { vertex, .. }
                | MeshError::CoordinateTooLarge { vertex, .. } => vertex,
                _ => 0,
            });
            return Err(e);
        }
        self.invalid = None;
        self.place();
        Ok(())
    }

    /// The control points, one per vertex of the mesh the surface was built from.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.pos
    }

    /// Builds the per-face nodes (keeping none for plain faces); `true` if it stopped as
    /// soon as `over(configurations found)`, the faces not built by then left plain (the
    /// caller then drops the surface).
    fn place_new(&mut self, over: impl Fn(usize) -> bool + Sync, select: &FaceSelect<'_>) -> bool {
        let cache = RegionCache::default();
        let reach = Reach::with_high_valence(&self.options, self.high_valence);
        let level = LevelRef::new(&self.base, &self.pos, &self.shared, &cache, reach);
        let (shared, options) = (&*self.shared, &self.options);
        let stop = AtomicBool::new(false);
        let base = &*self.base;
        let chosen: Vec<bool> = (0..base.num_faces())
            .into_par_iter()
            .map(|f| select(f, base.face_vertices(f)))
            .collect();
        self.built = (0..base.num_faces())
            .into_par_iter()
            .filter_map(|f| {
                if stop.load(Ordering::Relaxed) || !chosen[f] {
                    return None;
                }
                let (nodes, recipe) = build_face(level, shared, f, options);
                if matches!(recipe, Recipe::Tree(..)) && over(shared.trees.len()) {
                    stop.store(true, Ordering::Relaxed);
                }
                let face = f as u32;
                (!matches!(nodes[..], [Node::Plain(_)])).then(|| BuiltFace {
                    face,
                    nodes: nodes.into(),
                    recipe,
                })
            })
            .collect();
        // A stopped build leaves the faces it did not reach plain; the surface is dropped
        // with its error.
        self.faces = (chosen.into_iter())
            .map(|c| if c { PLAIN } else { UNBUILT })
            .collect();
        for (i, b) in self.built.iter().enumerate() {
            self.faces[b.face as usize] = i as u32;
        }
        stop.into_inner()
    }

    /// Re-poses the per-face nodes to the control points `self.pos`.
    fn place(&mut self) {
        let pos = &self.pos[..];
        let cache = RegionCache::default();
        let reach = Reach::with_high_valence(&self.options, self.high_valence);
        let level = LevelRef::new(&self.base, pos, &self.shared, &cache, reach);
        let (shared, options) = (&*self.shared, &self.options);
        // Re-posing: plain patches read the new positions as they are; other patches
        // evaluate their nets again and trees take the new points of their cut-outs, in
        // place; the rest (position-based local refinement) is built again, on the kept
        // shapes of the shared regions.
        self.built.par_iter_mut().for_each(|b| {
            let f = b.face as usize;
            if let Recipe::Region(w) = b.recipe {
                b.nodes = region_nodes(level, f, w, options).into();
            } else if !b.recipe.update(b.nodes.as_mut_slice(), pos, options) {
                let (fresh, r) = build_face(level, shared, f, options);
                (b.nodes, b.recipe) = (fresh.into(), r);
            }
        });
    }

    /// Number of distinct neighbourhoods ("configurations") of the irregular faces whose
    /// local refinement is shared (see the module docs): a measure of how much work
    /// [`Self::new`] and the first evaluations near irregular features do.
    pub fn num_configurations(&self) -> usize {
        self.shared.trees.len()
    }

    /// Number of faces in the shared region of a vertex of high valence (see
    /// [`super::local::HIGH_VALENCE`]), refined from the region's points as evaluation
    /// needs.
    pub(super) fn num_region_faces(&self) -> usize {
        (self.built.iter())
            .filter(|b| matches!(b.recipe, Recipe::Region(Seed::Vertex(_))))
            .count()
    }

    /// Number of nodes (sub-faces, or the face itself for a quad) of the faces in the
    /// shared regions of large faces (see [`super::local::LARGE_FACE`]): the face's own
    /// `n` sub-faces and the faces that share a vertex with it.
    pub(super) fn num_large_face_nodes(&self) -> usize {
        (self.built.iter())
            .filter(|b| matches!(b.recipe, Recipe::Region(Seed::Face(_))))
            .map(|b| b.nodes.as_slice().len())
            .sum()
    }

    /// The base faces' vertex lists.
    pub(super) fn base_faces(&self) -> impl Iterator<Item = &[u32]> + '_ {
        (0..self.base.num_faces()).map(|f| self.base.face_vertices(f))
    }

    /// Number of control points (the vertices of the mesh the surface was built from).
    pub fn num_vertices(&self) -> usize {
        self.pos.len()
    }

    /// Number of base faces.
    pub fn num_faces(&self) -> usize {
        self.faces.len()
    }

    /// The nodes of face `f` (one per sub-face), if there is such a face and it was built.
    fn face_nodes(&self, f: usize) -> Result<Cow<'_, FaceNodes>, EvalError> {
        let face = f as u32;
        Ok(match self.faces.get(f) {
            None => {
                return Err(EvalError::NoSuchFace {
                    face,
                    count: self.faces.len(),
                })
            }
            Some(&UNBUILT) => return Err(EvalError::NotBuilt { face }),
            Some(&PLAIN) => Cow::Owned(FaceNodes::One(Node::Plain(face))),
            Some(&i) => Cow::Borrowed(&self.built[i as usize].nodes),
        })
    }

    /// Number of sub-faces of face `f` (1 for a quad, `n` for an `n`-gon; 0 if there is
    /// no such face).
    pub fn num_subfaces(&self, f: usize) -> usize {
        if f >= self.faces.len() {
            return 0;
        }
        match self.base.face_vertices(f).len() {
            4 => 1,
            n => n,
        }
    }

    /// Whether face `f` has a surface: it exists, is not a hole and was built (see
    /// [`LimitSurface::builder`]).
    pub fn has_surface(&self, f: usize) -> bool {
        self.face_nodes(f)
            .is_ok_and(|n| !matches!(n.as_slice().first(), Some(Node::Hole) | None))
    }

    /// Position and first and second derivatives at `(u, v)` of quad `face` (sub-face 0
    /// of a non-quad).
    pub fn eval(&self, face: u32, u: f64, v: f64) -> Result<Derivatives, EvalError> {
        self.eval_point(SurfacePoint {
            face,
            subface: 0,
            u,
            v,
        })
    }

    /// Evaluates at a [`SurfacePoint`].
    pub fn eval_point(&self, p: SurfacePoint) -> Result<Derivatives, EvalError> {
        self.eval_point_order(p, Order::Second)
    }

    /// [`Self::eval_point`] computing the derivatives of `order` only.
    pub fn eval_point_order(
        &self,
        p: SurfacePoint,
        order: Order,
    ) -> Result<Derivatives, EvalError> {
        let mut out = Ok(Derivatives::default());
        self.eval_point_into(p, order, &mut out);
        out
    }

    /// [`eval_point_order`](Self::eval_point_order) into `out`, in place: the derivatives
    /// (144 bytes) are written where they end up, not moved through temporaries (each
    /// move of that size was a `memcpy` call, 9 % of the time of a grid evaluation).
    fn eval_point_into(
        &self,
        p: SurfacePoint,
        order: Order,
        out: &mut Result<Derivatives, EvalError>,
    ) {
        match self.node(p) {
            Err(e) => *out = Err(e),
            Ok(node) => {
                if out.is_err() {
                    *out = Ok(Derivatives::default());
                }
                if let Ok(d) = out {
                    if !eval_node(&node, p.u, p.v, self.ctx(order), d) {
                        *out = Err(EvalError::Hole { face: p.face });
                    }
                }
            }
        }
    }

    fn ctx(&self, order: Order) -> Ctx<'_> {
        Ctx {
            options: &self.options,
            order,
            pos: &self.pos,
            topo: &self.base,
            sectors: &self.shared.sectors,
            trees: &self.shared.trees,
        }
    }

    /// The node of `p`'s face and sub-face, after checking `p` (made for a plain face,
    /// borrowed for any other).
    fn node(&self, p: SurfacePoint) -> Result<Cow<'_, Node>, EvalError> {
        if let Some(vertex) = self.invalid {
            return Err(EvalError::InvalidPositions { vertex });
        }
        let nodes = self.face_nodes(p.face as usize)?;
        let sub = p.subface as usize;
        let size = nodes.as_slice().len();
        if sub >= size {
            return Err(EvalError::NoSuchSubface {
                face: p.face,
                subface: p.subface,
                size,
            });
        }
        if !(0.0..=1.0).contains(&p.u) || !(0.0..=1.0).contains(&p.v) {
            return Err(EvalError::BadParameter { u: p.u, v: p.v });
        }
        Ok(match nodes {
            Cow::Borrowed(nodes) => Cow::Borrowed(&nodes.as_slice()[sub]),
            Cow::Owned(nodes) => Cow::Owned(nodes.as_slice()[sub].clone()),
        })
    }

    /// Evaluates many points in parallel; results in the same order.
    ///
    /// Consecutive points on the same face (and sub-face) are evaluated together: the
    /// points of each node of an irregular face's tree are computed once for all of them,
    /// so listing points face by face (as a grid or tessellation does) is much faster than
    /// calling [`Self::eval_point`] for each.
    pub fn eval_many(&self, points: &[SurfacePoint]) -> Vec<Result<Derivatives, EvalError>> {
        let mut out = Vec::new();
        self.eval_many_into(points, Order::Second, &mut out);
        out
    }

    /// [`Self::eval_many`] computing the derivatives of `order` only, into `out` (resized to
    /// `points.len()`): reusing the buffer from one call to the next (re-posing,
    /// animation) saves allocating and clearing it.
    pub fn eval_many_into(
        &self,
        points: &[SurfacePoint],
        order: Order,
        out: &mut Vec<Result<Derivatives, EvalError>>,
    ) {
        out.resize(points.len(), Ok(Derivatives::default()));
        self.eval_many_to(points, order, out);
    }

    /// [`Self::eval_many_into`] into a slice of the same length as `points` (every entry
    /// is overwritten): a buffer kept at the largest size of a series of calls with
    /// different numbers of points is not filled again when a call needs more than the
    /// last.
    ///
    /// # Panics
    /// If `out.len() != points.len()`.
    pub fn eval_many_to(
        &self,
        points: &[SurfacePoint],
        order: Order,
        out: &mut [Result<Derivatives, EvalError>],
    ) {
        /// Points per parallel task.
        const CHUNK: usize = 256;
        assert_eq!(out.len(), points.len(), "one result per point");
        out.par_chunks_mut(CHUNK)
            .zip(points.par_chunks(CHUNK))
            .for_each_init(Buffers::default, |bufs, (out, points)| {
                self.eval_chunk(points, out, bufs, order)
            });
    }

    /// [`Self::eval_many`] on one chunk, face run by face run.
    fn eval_chunk(
        &self,
        points: &[SurfacePoint],
        out: &mut [Result<Derivatives, EvalError>],
        bufs: &mut Buffers,
        order: Order,
    ) {
        let mut i = 0;
        while i < points.len() {
            let p = points[i];
            let run = points[i..]
                .iter()
                .take_while(|q| (q.face, q.subface) == (p.face, p.subface))
                .count();
            let in_domain =
                |q: &SurfacePoint| (0.0..=1.0).contains(&q.u) && (0.0..=1.0).contains(&q.v);
            let node = self.node(p).ok();
            let node = node.as_deref();
            // A patch: all the run's points together, four at a time.
            let run_points = &points[i..i + run];
            let all_in = || run_points.iter().all(in_domain);
            if let Some(n) = node.filter(|_| all_in()) {
                let batch = &mut RunBatch {
                    points: run_points,
                    out: &mut out[i..i + run],
                };
                if n.eval_patch(self.ctx(order), 1.0, batch) {
                    i += run;
                    continue;
                }
            }
            let Some(node) = node.filter(|n| matches!(n, Node::Tree(_) | Node::Lazy(_))) else {
                for k in i..i + run {
                    self.eval_point_into(points[k], order, &mut out[k]);
                }
                i += run;
                continue;
            };
            bufs.queries.clear();
            for (k, q) in points[i..i + run].iter().enumerate() {
                if in_domain(q) {
                    bufs.queries.push(Query {
                        u: q.u,
                        v: q.v,
                        out: k as u32,
                    });
                } else {
                    out[i + k] = Err(EvalError::BadParameter { u: q.u, v: q.v });
                }
            }
            let sink = &mut RunSink {
                out: &mut out[i..i + run],
                face: p.face,
            };
            let ctx = self.ctx(order);
            eval_queries(node, &mut bufs.queries, 0, &mut bufs.scratch, ctx, sink);
            i += run;
        }
    }
}

/// `r`'s derivatives, after making it `Ok` if it was not (their values are then to be
/// overwritten).
fn ok_slot(r: &mut Result<Derivatives, EvalError>) -> &mut Derivatives {
    if r.is_err() {
        *r = Ok(Derivatives::default());
    }
    match r {
        Ok(d) => d,
        Err(_) => unreachable!("set to Ok above"),
    }
}

/// The points of one face run of [`LimitSurface::eval_many`] on a patch.
struct RunBatch<'a> {
    points: &'a [SurfacePoint],
    out: &'a mut [Result<Derivatives, EvalError>],
}

impl Batch for RunBatch<'_> {
    fn len(&self) -> usize {
        self.points.len()
    }
    fn uv(&self, i: usize) -> (f64, f64) {
        (self.points[i].u, self.points[i].v)
    }
    fn out(&mut self, i: usize) -> &mut Derivatives {
        ok_slot(&mut self.out[i])
    }
}

/// The results of one face run of [`LimitSurface::eval_many`] through a tree.
struct RunSink<'a> {
    out: &'a mut [Result<Derivatives, EvalError>],
    face: u32,
}

impl Sink for RunSink<'_> {
    fn slot(&mut self, k: u32) -> &mut Derivatives {
        ok_slot(&mut self.out[k as usize])
    }
    fn hole(&mut self, k: u32) {
        self.out[k as usize] = Err(EvalError::Hole { face: self.face });
    }
}

/// The result of one point evaluated through a tree.
struct OneSink<'a> {
    out: &'a mut Derivatives,
    found: bool,
}

impl Sink for OneSink<'_> {
    fn slot(&mut self, _: u32) -> &mut Derivatives {
        self.found = true;
        self.out
    }
    fn hole(&mut self, _: u32) {}
}

/// Buffers of one [`LimitSurface::eval_many`] task.
#[derive(Default)]
struct Buffers {
    queries: Vec<Query>,
    scratch: Scratch,
}

/// What the faces of one surface share.
#[derive(Debug, Default)]
pub(super) struct Shared {
    /// Configuration trees of irregular faces (also those inside shared regions, see
    /// [`super::local::FaceKind::Tree`]).
    pub trees: Arc<TreeCache>,
    /// Shapes of the base level's shared regions (see [`super::local::Shape`]).
    pub regions: ShapeCache,
    /// Eigen-analyses of corner sectors (see [`SectorCache`]).
    pub sectors: SectorCache,
}

/// The nodes of face `f` of `level` (one per sub-face): a regular patch, a single-crease
/// patch, else the face's configuration tree from `shared` (unless the 1-ring reaches a
/// vertex of more than `level.reach.high_valence` faces: then the position-based local
/// refinement).
pub(super) fn build_face(
    level: LevelRef<'_>,
    shared: &Shared,
    f: usize,
    options: &Options,
) -> (Vec<Node>, Recipe) {
    let base = level.topo;
    let n = base.face_vertices(f).len();
    if base.is_hole(f) {
        return (vec![Node::Hole; if n == 4 { 1 } else { n }], Recipe::Fixed);
    }
    if let Some(patch) = PatchNet::new(base, f, shared, options) {
        if let (Net::Plain(verts), None) = (&patch.net, &patch.crease) {
            if plain_net(base, f).as_ref() == Some(verts) {
                return (vec![Node::Plain(f as u32)], Recipe::Fixed);
            }
        }
        return (vec![Node::Net(Box::new(patch))], Recipe::Fixed);
    }
    match cut_out(base, f, level.reach) {
        Ok(faces) => {
            let (sub, verts) = base.subset_canonical(&faces);
            let tree = shared.trees.get(sub);
            let verts: Arc<[u32]> = verts.into();
            let nodes = tree_nodes(
                &tree,
                &verts,
                level.pos,
                if n == 4 { 1 } else { n },
                options,
            );
            (nodes, Recipe::Tree(tree, verts))
        }
        Err(seed) => (region_nodes(level, f, seed, options), Recipe::Region(seed)),
    }
}

/// The nodes of face `f` of `level`, irregular, in the shared region of `seed`: the face
/// itself, or the children of an `n`-gon after one step (unrotated for `n ≠ 4`).
fn region_nodes(level: LevelRef<'_>, f: usize, seed: Seed, options: &Options) -> Vec<Node> {
    let local = region_cut(level, f, seed);
    let n = level.topo.face_vertices(f).len();
    if n == 4 {
        return vec![Node::lazy(local)];
    }
    let child = local.region.refined(options);
    let first = local.child_face(0);
    (0..n).map(|j| node_for(&child, first + j)).collect()
}

/// How the nodes of a base face follow its control points, so that
/// [`LimitSurface::set_positions`] updates them in place (without walking the topology,
/// and allocating only a tree face's new cut-out points).
#[derive(Clone, Debug)]
pub(super) enum Recipe {
    /// Nothing to update: a hole, or a [`Node::Plain`] or [`Node::Net`] patch (which read
    /// the positions when evaluated).
    Fixed,
    /// Through a configuration tree, with the vertices of the face's cut-out.
    Tree(Arc<Tree>, Arc<[u32]>),
    /// Position-based local refinement in the shared region of this vertex or face: built
    /// again (without looking at the face's topology), on the region's kept shape.
    Region(Seed),
}

impl Recipe {
    /// Sets `nodes` (built with this recipe) to base positions `pos`; `false` if they
    /// must be built again.
    fn update(&self, nodes: &mut [Node], pos: &[[f64; 3]], options: &Options) -> bool {
        match (self, nodes) {
            (Recipe::Fixed, _) => true,
            (Recipe::Tree(tree, verts), nodes) => {
                let kids = tree.root_kids(options);
                // The root's refined points, for the patches of an n-gon's sub-faces.
                let patches = nodes
                    .iter()
                    .any(|n| matches!(n, Node::Regular(_) | Node::Crease(_)));
                let refined = if patches {
                    let points: Vec<[f64; 3]> = verts.iter().map(|&v| pos[v as usize]).collect();
                    kids.refine(&points)
                } else {
                    Vec::new()
                };
                let kids = kids.kids();
                for (j, node) in nodes.iter_mut().enumerate() {
                    match node {
                        // Reads its points from the control points.
                        Node::Tree(t) if matches!(t.points, CutPoints::Base(_)) => {}
                        Node::Tree(_) => return false,
                        Node::Regular(cp) => match kids.get(j).and_then(|k| k.patch(&refined)) {
                            Some(p) => **cp = p,
                            None => return false,
                        },
                        Node::Crease(c) => match kids.get(j).and_then(|k| k.crease_net(&refined)) {
                            Some(p) => c.set_net(&p),
                            None => return false,
                        },
                        Node::Hole => {}
                        Node::Plain(_) | Node::Net(_) | Node::InRegion(_) | Node::Lazy(_) => {
                            return false
                        }
                    }
                }
                true
            }
            _ => false,
        }
    }
}

/// A base face whose surface is one patch (regular, or with one semi-sharp crease): its
/// control net as combinations of base vertices ([`Node::Net`]), kept so that evaluation
/// computes the control points from the positions without walking the topology (about
/// 3 000 instructions per face).
#[derive(Clone, Debug)]
pub(super) struct PatchNet {
    net: Net,
    /// The crease side and basis of a single-crease patch.
    crease: Option<(usize, Arc<CreaseBasis>)>,
}

impl PatchNet {
    /// The net of face `f` of `t`, if it is a regular or (unless `shared` says not) a
    /// single-crease quad.
    fn new(t: &Topology, f: usize, shared: &Shared, options: &Options) -> Option<Self> {
        if t.face_vertices(f).len() != 4 || t.is_hole(f) {
            return None;
        }
        if let Some(cells) = regular_patch_cells(t, f) {
            let net = Net::new(cells);
            return Some(PatchNet { net, crease: None });
        }
        if shared.trees.no_crease_patches() {
            return None;
        }
        let (cells, side, s) = single_crease(t, f, options)?;
        let crease = Some((side, shared.trees.pools.bases.get(s)));
        Some(PatchNet {
            net: Net::new(cells),
            crease,
        })
    }
}

/// The `count` nodes of a base face evaluated through `tree` (one for a quad, one per
/// sub-face of an `n`-gon), whose cut-out has the base vertices `verts`, at positions
/// `pos` (those the surface is evaluated with, [`Ctx::pos`]).
fn tree_nodes(
    tree: &Arc<Tree>,
    verts: &Arc<[u32]>,
    pos: &[[f64; 3]],
    count: usize,
    options: &Options,
) -> Vec<Node> {
    let node = |sub: Option<usize>| {
        Node::Tree(Box::new(TreeFace {
            tree: tree.clone(),
            points: CutPoints::Base(verts.clone()),
            sub,
        }))
    };
    if count == 1 {
        return vec![node(None)];
    }
    let kids = tree.root_kids(options);
    let pos: Vec<[f64; 3]> = verts.iter().map(|&v| pos[v as usize]).collect();
    let refined = kids.refine(&pos);
    kids.kids()
        .iter()
        .enumerate()
        .map(|(j, kid)| match kid {
            Kid::Hole => Node::Hole,
            Kid::Regular(_) => match kid.patch(&refined) {
                Some(cp) => Node::Regular(Box::new(cp)),
                None => node(Some(j)),
            },
            Kid::Crease(..) => match kid.crease_patch(&refined) {
                Some(p) => Node::Crease(Box::new(p)),
                None => node(Some(j)),
            },
            Kid::Irregular(..) => node(Some(j)),
        })
        .collect()
}

/// The node of face `f` of a refined cut-out or region.
fn node_for(region: &Arc<Region>, f: usize) -> Node {
    let level = region.level();
    let fresh;
    let kind = match level.kinds.get(f) {
        Some(kind) => kind.get_or_init(|| Box::new(FaceKind::find(level, f))),
        None => {
            fresh = FaceKind::find(level, f);
            &fresh
        }
    };
    match kind {
        FaceKind::Hole => Node::Hole,
        FaceKind::Patch(_) if region.is_shared() => Node::InRegion(Box::new(Local {
            region: region.clone(),
            face: f,
        })),
        FaceKind::Patch(net) => Node::Regular(Box::new(net.eval(level.pos))),
        FaceKind::Region(seed) => Node::lazy(region_cut(level, f, *seed)),
        FaceKind::Own(faces) => Node::lazy(own_cut(level, faces)),
        FaceKind::Tree(tree, verts) => Node::Tree(Box::new(TreeFace {
            tree: tree.clone(),
            points: CutPoints::Own(verts.iter().map(|&v| level.pos[v as usize]).collect()),
            sub: None,
        })),
    }
}

/// The four children of an irregular node.
fn split(l: &Local, options: &Options) -> Box<[Node; 4]> {
    let child = l.region.refined(options);
    let first = l.child_face(0);
    Box::new([0, 1, 2, 3].map(|j| node_for(&child, first + j)))
}

/// Evaluates `qs` on `node`, `depth` levels below its base face (derivatives are scaled
/// by `2^depth` to the base face's parameters), all queries together: a tree's descent, or
/// a lazy node's with its patches' points four at a time. Writes each result into `sink`;
/// reorders `qs`.
fn eval_queries(
    node: &Node,
    qs: &mut [Query],
    depth: u32,
    scratch: &mut Scratch,
    ctx: Ctx<'_>,
    sink: &mut impl Sink,
) {
    let scale = scale_at(depth);
    match node {
        Node::Hole => qs.iter().for_each(|q| sink.hole(q.out)),
        Node::Plain(_) | Node::Regular(_) | Node::InRegion(_) | Node::Crease(_) | Node::Net(_) => {
            node.eval_patch(ctx, scale, &mut Leaf { qs, sink });
        }
        Node::Tree(t) => t.eval(qs, depth, scratch, ctx, sink),
        Node::Lazy(lz) => {
            // Limit masks give the limit only once no semi-sharp feature is left at the
            // corner (sharpness still to decay changes the rules of later levels). A
            // regular corner (one that only an irregularity elsewhere on the face keeps from
            // being a patch corner) is reached by refining further, where the patch gives
            // exact parametric derivatives.
            let stop = |k| is_limit_corner(lz.local.topo(), lz.local.face, k);
            let rest = take_corners(qs, depth, stop, |k, out| {
                *sink.slot(out) = corner_limit(&lz.local, k, ctx.options, ctx.sectors).finish();
            });
            let qs = &mut qs[..rest];
            if qs.is_empty() {
                return;
            }
            let kids = lz.kids.get_or_init(|| split(&lz.local, ctx.options));
            for (kid, qs) in kids.iter().zip(by_quadrant(qs)) {
                if !qs.is_empty() {
                    eval_queries(kid, qs, depth + 1, scratch, ctx, sink);
                }
            }
        }
    }
}

/// Quadrant of `(u, v)` and the parameter within it.
#[inline]
pub(super) fn quadrant(u: f64, v: f64) -> (usize, f64, f64) {
    match (u >= 0.5, v >= 0.5) {
        (false, false) => (0, 2.0 * u, 2.0 * v),
        (true, false) => (1, 2.0 * u - 1.0, 2.0 * v),
        (true, true) => (2, 2.0 * u - 1.0, 2.0 * v - 1.0),
        (false, true) => (3, 2.0 * u, 2.0 * v - 1.0),
    }
}

/// The derivatives of the surface of base node `node` at `(u, v)`, written into `out`;
/// false (and `out` unspecified) where `node` is a hole. One point through
/// [`eval_queries`].
pub(super) fn eval_node(node: &Node, u: f64, v: f64, ctx: Ctx<'_>, out: &mut Derivatives) -> bool {
    let mut sink = OneSink { out, found: false };
    let query = &mut [Query { u, v, out: 0 }];
    eval_queries(node, query, 0, &mut Scratch::default(), ctx, &mut sink);
    sink.found
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom;
    use crate::mesh::{BoundaryInterpolation, Corner, Crease, Options};

    /// A fan of `n` faces around vertex 0 (quads, or triangles when `tri`), closed or open
    /// (one gap), on a wavy surface so that nothing is planar or symmetric.
    fn fan(n: usize, tri: bool, closed: bool) -> PolyMesh {
        let mut p = vec![[0.0, 0.0, 0.1]];
        let wave = |a: f64| 0.2 * (3.0 * a).sin() + 0.05 * (7.0 * a).cos();
        for i in 0..n {
            let a = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
            p.push([a.cos(), a.sin(), wave(a)]);
        }
        if !tri {
            for i in 0..n {
                let a = 2.0 * std::f64::consts::PI * (i as f64 + 0.5) / n as f64;
                p.push([2.0 * a.cos(), 2.0 * a.sin(), wave(a + 1.0)]);
            }
        }
        let m = if closed { n } else { n - 1 };
        let faces: Vec<Vec<u32>> = (0..m)
            .map(|i| {
                let (a, b) = (1 + i as u32, 1 + ((i + 1) % n) as u32);
                if tri {
                    vec![0, a, b]
                } else {
                    vec![0, a, 1 + (n + i) as u32, b]
                }
            })
            .collect();
        PolyMesh::from_faces(p, &faces).expect("valid fan")
    }

    /// An `n × m` torus of quads, each face listed from one of its four corners, with the
    /// quad at `(0, 0)` split into two triangles: the faces that touch them are not plain,
    /// all the others are.
    fn rotated_torus(n: u32, m: u32) -> PolyMesh {
        let mut p = Vec::new();
        for j in 0..m {
            for i in 0..n {
                let (a, b) = (
                    std::f64::consts::TAU * i as f64 / n as f64,
                    std::f64::consts::TAU * j as f64 / m as f64,
                );
                let r = 2.0 + (0.5 + 0.05 * (3.0 * a).sin()) * b.cos();
                p.push([r * a.cos(), r * a.sin(), 0.5 * b.sin()]);
            }
        }
        let id = |i: u32, j: u32| (j % m) * n + i % n;
        let mut faces: Vec<Vec<u32>> = Vec::new();
        for j in 0..m {
            for i in 0..n {
                let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
                if (i, j) == (0, 0) {
                    faces.push(vec![q[0], q[1], q[2]]);
                    faces.push(vec![q[0], q[2], q[3]]);
                } else {
                    let r = ((i + 2 * j) % 4) as usize;
                    faces.push((0..4).map(|k| q[(k + r) % 4]).collect());
                }
            }
        }
        PolyMesh::from_faces(p, &faces).expect("torus")
    }

    /// A plain face's net read from the topology ([`plain_net`]) is the one the corner
    /// walks find ([`regular_patch_cells`]) on every face that has one, listed from any
    /// corner; the surface keeps nothing for those faces, and evaluates them as before
    /// (the same points as through their stored control points).
    #[test]
    fn plain_faces_are_found_from_the_topology_and_not_stored() {
        let mesh = rotated_torus(9, 7);
        let o = Options::default();
        let (topo, _) = Topology::from_mesh(&mesh, &o).expect("topology");
        let mut plain = 0;
        for f in 0..topo.num_faces() {
            let walked = regular_patch_cells(&topo, f).map(Net::new);
            match (&walked, plain_net(&topo, f)) {
                (Some(Net::Plain(w)), Some(t)) => {
                    assert_eq!(*w, t, "face {f}");
                    plain += 1;
                }
                (Some(Net::Plain(_)), None) => panic!("face {f}: plain net not found"),
                _ => {}
            }
        }
        // 62 quads; the two triangles and the 8 quads at their corners are not plain.
        assert_eq!(plain, topo.num_faces() - 2 - 8);
        let surface = LimitSurface::new(&mesh, o).expect("surface");
        assert_eq!(surface.built.len(), 10);
        assert_eq!(surface.faces.iter().filter(|&&i| i == PLAIN).count(), plain);
        for f in 0..surface.num_faces() {
            let Some(Net::Plain(net)) = regular_patch_cells(&topo, f).map(Net::new) else {
                continue;
            };
            let cp: [[[f64; 3]; 4]; 4] = std::array::from_fn(|i| {
                std::array::from_fn(|j| mesh.positions()[net[4 * i + j] as usize])
            });
            for (u, v) in [(0.0, 0.0), (0.3, 0.8), (1.0, 0.5), (0.61, 0.07)] {
                let a = surface.eval(f as u32, u, v).expect("eval");
                let mut b = Derivatives::default();
                let node = Node::Regular(Box::new(cp));
                assert!(eval_node(&node, u, v, surface.ctx(Order::Second), &mut b));
                for (x, y) in [(a.p, b.p), (a.du, b.du), (a.dv, b.dv), (a.duv, b.duv)] {
                    assert!(
                        (0..3).all(|k| (x[k] - y[k]).abs() < 1e-14),
                        "face {f} at {u}, {v}"
                    );
                }
            }
        }
    }

    /// A surface built from the mesh itself (which it takes apart) is the one built from a
    /// reference to it (which it copies), tags included; re-posed in place it is the one
    /// re-posed from the caller's points.
    #[test]
    fn a_surface_takes_its_mesh_or_copies_it_to_the_same_effect() {
        let meshes = [
            creased_grid(2.5, false),
            creased_grid(0.3, true),
            rotated_torus(6, 5),
            fan(7, true, false),
        ];
        for (k, mesh) in meshes.into_iter().enumerate() {
            let o = Options::default();
            let lent = LimitSurface::new(&mesh, o).expect("surface");
            let moved = mesh
                .positions()
                .iter()
                .map(|p| [p[0], p[2], -p[1]])
                .collect::<Vec<_>>();
            let mut given = LimitSurface::new(mesh, o).expect("surface");
            let mut lent_moved = lent.clone();
            lent_moved.set_positions(&moved).expect("points");
            assert_eq!(lent.faces, given.faces, "mesh {k}");
            assert_eq!(
                lent.num_configurations(),
                given.num_configurations(),
                "mesh {k}"
            );
            let check = |a: &LimitSurface, b: &LimitSurface| {
                for f in 0..a.num_faces() as u32 {
                    for (u, v) in [(0.0, 0.0), (0.3, 0.8), (1.0, 0.5), (0.61, 0.07)] {
                        assert_eq!(a.eval(f, u, v), b.eval(f, u, v), "mesh {k}, face {f}");
                    }
                }
            };
            check(&lent, &given);
            given
                .update_positions(|p| p.iter_mut().for_each(|q| *q = [q[0], q[2], -q[1]]))
                .expect("points");
            check(&lent_moved, &given);
        }
    }

    /// A wavy 7×7 grid of quads with a crease of sharpness `s` along the grid line
    /// `x = 3` (`vertical`) or `y = 3`, stopping short of the border.
    fn creased_grid(s: f32, vertical: bool) -> PolyMesh {
        let n = 8u32;
        let mut mesh = crate::mesh::test_grid(n - 1, n - 1, |x, y| {
            [
                x + 0.1 * y.sin(),
                y + 0.07 * (1.3 * x).cos(),
                0.3 * (0.7 * x + 0.4 * y).sin(),
            ]
        });
        for k in 1..n - 2 {
            let (a, b) = if vertical {
                (k * n + 3, (k + 1) * n + 3)
            } else {
                (3 * n + k, 3 * n + k + 1)
            };
            mesh.tags.creases.push(crate::mesh::Crease {
                v0: a,
                v1: b,
                sharpness: s,
            });
        }
        mesh
    }

    /// Single-crease faces in closed form ([`CreasePatch`]) equal the general local
    /// refinement, with second derivatives, at every side, for integer and fractional
    /// sharpness, down to `2⁻¹²` from the crease.
    #[test]
    fn crease_patches_equal_local_refinement() {
        let params = [
            0.0,
            1.0 / 4096.0,
            0.001,
            0.03,
            0.25,
            1.0 / 3.0,
            0.5,
            0.77,
            1.0,
        ];
        for s in [0.3f32, 1.0, 2.5, 6.0, 9.7] {
            for vertical in [false, true] {
                let mesh = creased_grid(s, vertical);
                let o = Options::default();
                let fast =
                    LimitSurface::with_high_valence(&mesh, o, HIGH_VALENCE, true).expect("surface");
                let slow = LimitSurface::with_high_valence(&mesh, o, HIGH_VALENCE, false)
                    .expect("surface");
                let creased = (0..fast.num_faces())
                    .filter(|&f| {
                        let nodes = fast.face_nodes(f).expect("a face");
                        matches!(&nodes.as_slice()[0], Node::Net(p) if p.crease.is_some())
                    })
                    .count();
                assert!(creased >= 4, "s = {s}: only {creased} single-crease faces");
                for f in 0..fast.num_faces() {
                    for &u in &params {
                        for &v in &params {
                            let a = fast.eval(f as u32, u, v).expect("eval");
                            let b = slow.eval(f as u32, u, v).expect("eval");
                            let pairs = [
                                (a.p, b.p),
                                (a.du, b.du),
                                (a.dv, b.dv),
                                (a.duu, b.duu),
                                (a.duv, b.duv),
                                (a.dvv, b.dvv),
                            ];
                            for (i, (x, y)) in pairs.into_iter().enumerate() {
                                let d = geom::norm(&geom::sub(&x, &y));
                                // The local refinement descends up to ten levels here;
                                // its second derivatives, scaled by 4 per level, keep
                                // only ~1e-10 of their precision.
                                let tol = if i < 3 { 1e-10 } else { 1e-8 };
                                assert!(
                                    d <= tol * (1.0 + geom::norm(&y)),
                                    "s = {s}, vertical {vertical}, face {f} ({u}, {v}), \
                                     derivative {i}: {x:?} vs {y:?}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    /// Asserts that `a` and `b` give the same position and first derivatives (within
    /// `tol × max(scale, |value|)`), or both no surface, on every `step`-th face (all its
    /// sub-faces) at `params × params`; returns the number of points compared.
    fn assert_agree(
        a: &LimitSurface,
        b: &LimitSurface,
        (params, step): (&[f64], usize),
        (tol, scale): (f64, f64),
        what: &str,
    ) -> usize {
        let mut compared = 0;
        for f in (0..a.num_faces()).step_by(step) {
            for sub in 0..a.num_subfaces(f) {
                for &u in params {
                    for &v in params {
                        let p = SurfacePoint {
                            face: f as u32,
                            subface: sub as u32,
                            u,
                            v,
                        };
                        let (x, y) = (a.eval_point(p), b.eval_point(p));
                        assert_eq!(x.is_ok(), y.is_ok(), "{what}: face {f}/{sub}");
                        let (Ok(x), Ok(y)) = (x, y) else {
                            continue;
                        };
                        for (x, y) in [(x.p, y.p), (x.du, y.du), (x.dv, y.dv)] {
                            let d = geom::norm(&geom::sub(&x, &y));
                            assert!(
                                d <= tol * scale.max(geom::norm(&y)),
                                "{what}: face {f}/{sub} at ({u}, {v}): {x:?} vs {y:?}"
                            );
                        }
                        compared += 1;
                    }
                }
            }
        }
        compared
    }

    /// `tests/shapes/osd/<name>.obj`, its scheme options and its bounding-box diagonal.
    fn shape(path: &std::path::Path) -> (PolyMesh, Options, f64) {
        let obj = crate::io::obj::read_obj(path).expect("shape");
        let o = obj.options.resolve(Options::default());
        let (lo, hi) = obj.mesh.bounding_box().expect("box");
        (obj.mesh, o, geom::norm(&geom::sub(&hi, &lo)))
    }

    /// The same inside configuration trees, where single-crease children of faces next to
    /// extraordinary vertices become crease patches: OpenSubdiv's bishop and pawn, whose
    /// sharpness-6 rings pass next to extraordinary vertices, evaluated with and without
    /// crease patches.
    #[test]
    fn crease_kids_equal_local_refinement() {
        let params = [0.0, 0.01, 0.2, 0.5, 0.93, 1.0];
        for name in ["catmark_bishop", "catmark_pawn"] {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join(format!("tests/shapes/osd/{name}.obj"));
            let (mesh, o, diag) = shape(&path);
            let fast = LimitSurface::with_high_valence(&mesh, o, HIGH_VALENCE, true);
            let slow = LimitSurface::with_high_valence(&mesh, o, HIGH_VALENCE, false);
            let (fast, slow) = (fast.expect("surface"), slow.expect("surface"));
            assert_agree(&fast, &slow, (&params, 1), (1e-12, diag), name);
        }
    }

    /// Every OpenSubdiv regression shape gives the same surface through configuration
    /// trees and crease patches (the default) as through the position-based local
    /// refinement of shared regions (`high_valence` 0 puts every face in a region): a check
    /// that faces sharing a tree really have the same neighbourhood, and that weights and
    /// positions flow through the same refinement.
    #[test]
    fn trees_equal_position_based_refinement_on_every_shape() {
        // Every third face, at its corner (0, 0) and two inner points: ~8 s in the test
        // profile, most of it in the position-based refinement.
        let params = [0.0, 0.3, 0.71];
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/shapes/osd");
        let mut shapes = 0;
        for entry in std::fs::read_dir(&dir).expect("shapes") {
            let path = entry.expect("entry").path();
            if path.extension().is_none_or(|e| e != "obj") {
                continue;
            }
            let (mesh, o, diag) = shape(&path);
            let trees = LimitSurface::new(&mesh, o).expect("surface");
            let regions = LimitSurface::with_high_valence(&mesh, o, 0, false).expect("surface");
            let what = path.display().to_string();
            assert_agree(&trees, &regions, (&params, 3), (1e-11, diag), &what);
            shapes += 1;
        }
        assert!(shapes > 50, "only {shapes} shapes");
    }

    /// Faces that share a region (around a vertex of more faces than [`HIGH_VALENCE`], or
    /// a quarter of that on a boundary, refined with positions) give the same surface as
    /// faces cut out on their own (and evaluated through configuration trees, as weights):
    /// to rounding, `1e-12` of the values' size, everywhere including the high-valence
    /// vertex itself.
    #[test]
    fn shared_regions_equal_own_cut_outs() {
        let params = [0.0, 0.25, 0.5, 1.0 / 3.0, 0.9, 1.0];
        let (interior, boundary) = (HIGH_VALENCE + 7, HIGH_VALENCE / 4 + 3);
        let cases = [
            (fan(interior, false, true), "closed quad fan"),
            (fan(interior, true, true), "closed triangle fan"),
            (fan(boundary, false, false), "open quad fan"),
            (fan(boundary, true, false), "open triangle fan"),
        ];
        for (mesh, what) in &cases {
            for boundary in [
                BoundaryInterpolation::EdgeOnly,
                BoundaryInterpolation::EdgeAndCorner,
            ] {
                let options = Options {
                    boundary,
                    ..Options::default()
                };
                let shared = LimitSurface::new(mesh, options).expect("surface");
                let alone = LimitSurface::with_high_valence(mesh, options, usize::MAX, true)
                    .expect("surface");
                let what = format!("{what}, {boundary:?}");
                let compared = assert_agree(&shared, &alone, (&params, 1), (1e-12, 1.0), &what);
                assert!(compared > 500, "{what}: only {compared} points");
            }
        }
    }

    /// A prism over an `n`-gon (its two caps, `n` side quads), off the cylinder so that
    /// nothing is symmetric; with `cap_only`, the top cap alone (every vertex on its
    /// boundary).
    fn prism(n: usize, cap_only: bool) -> PolyMesh {
        let mut p = Vec::new();
        for z in [0.0, 1.0] {
            for k in 0..n {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                let r = 1.0 + 0.1 * (3.0 * a).sin() + 0.05 * (5.0 * a + z).cos();
                p.push([r * a.cos(), r * a.sin(), z + 0.1 * (2.0 * a).cos()]);
            }
        }
        let n32 = n as u32;
        let top: Vec<u32> = (0..n32).map(|k| n32 + k).collect();
        let mut faces = vec![top];
        if !cap_only {
            faces.push((0..n32).rev().collect());
            for k in 0..n32 {
                let j = (k + 1) % n32;
                faces.push(vec![k, j, n32 + j, n32 + k]);
            }
        }
        PolyMesh::from_faces(p, &faces).expect("prism")
    }

    /// Faces of more than `LARGE_FACE` corners, and the faces whose 1-ring holds one, in
    /// shared regions (refined with positions, the sub-faces sharing their centre's region)
    /// give the surface of own cut-outs and configuration trees: to rounding, everywhere,
    /// the sub-faces' corners (the face's centre, of valence `n`) included; on a prism, a
    /// lone face (boundary creases at every corner), and with creases around the face
    /// (Chaikin's rule, whose regions reach one ring further).
    #[test]
    fn large_faces_in_shared_regions_equal_own_cut_outs() {
        use super::super::local::LARGE_FACE;
        let params = [0.0, 0.25, 0.5, 1.0 / 3.0, 0.9, 1.0];
        let n = LARGE_FACE + 3;
        let mut creased = prism(n, false);
        for k in 0..n as u32 {
            let sharpness = 0.5 + (k % 3) as f32;
            let j = (k + 1) % n as u32;
            creased.tags.creases.push(Crease {
                v0: k,
                v1: j,
                sharpness,
            });
        }
        let chaikin = Options {
            crease_method: crate::mesh::CreaseMethod::Chaikin,
            ..Options::default()
        };
        let cases = [
            (prism(n, false), Options::default(), "prism"),
            (prism(n, true), Options::default(), "lone face"),
            (creased, chaikin, "prism with Chaikin creases"),
        ];
        for (mesh, options, what) in &cases {
            let shared = LimitSurface::new(mesh, *options).expect("surface");
            assert!(shared.num_large_face_nodes() >= n, "{what}: no region");
            let alone =
                LimitSurface::with_high_valence(mesh, *options, usize::MAX, true).expect("surface");
            assert_eq!(alone.num_large_face_nodes(), 0, "{what}");
            let compared = assert_agree(&shared, &alone, (&params, 1), (1e-12, 1.0), what);
            assert!(compared > 500, "{what}: only {compared} points");
        }
    }

    /// At an infinitely sharp vertex a face's cut-out holds only its own sector (the faces
    /// between infinitely sharp edges): around a corner of `HIGH_VALENCE + 7` quads split
    /// by sharp spokes into sectors of five, with a triangle in one sector, every face
    /// gets a small cut-out, and the surface equals that of shared regions refined with
    /// positions (which hold every face of the corner), corners included. A semi-sharp
    /// spoke (whose decay reads every edge at the vertex) puts the faces back in a region.
    #[test]
    fn sectors_at_sharp_corners_equal_shared_regions() {
        let n = HIGH_VALENCE + 7;
        let params = [0.0, 0.25, 0.5, 0.9, 1.0];
        let mut mesh = fan(n, false, true);
        // One face of the fan becomes a triangle (its outer vertex dropped).
        let mut faces: Vec<Vec<u32>> = mesh.faces().map(|f| f.to_vec()).collect();
        faces[2].remove(2);
        mesh = PolyMesh::from_faces(mesh.positions().to_vec(), &faces).expect("fan");
        mesh.tags.corners.push(Corner {
            vertex: 0,
            sharpness: 10.0,
        });
        for i in (0..n as u32).step_by(5) {
            mesh.tags.creases.push(Crease {
                v0: 0,
                v1: 1 + i,
                sharpness: 10.0,
            });
        }
        let o = Options::default();
        let (t, _) = Topology::from_mesh(&mesh, &o).expect("topology");
        for f in 0..n {
            let faces = cut_out(&t, f, Reach::new(&o)).expect("a cut-out of its own");
            // Its sector at the centre (five faces), and up to three faces around each
            // of its other corners.
            assert!(faces.len() <= 9, "face {f}: {} faces", faces.len());
        }
        let sectors = LimitSurface::new(&mesh, o).expect("surface");
        let regions = LimitSurface::with_high_valence(&mesh, o, 0, false).expect("surface");
        let compared = assert_agree(&sectors, &regions, (&params, 1), (1e-12, 1.0), "sectors");
        assert!(compared > 3000, "only {compared} points");

        mesh.tags.creases[1].sharpness = 2.5;
        let (t, _) = Topology::from_mesh(&mesh, &o).expect("topology");
        assert_eq!(cut_out(&t, 0, Reach::new(&o)), Err(Seed::Vertex(0)));
    }

    /// Re-posing keeps what depends on the topology alone (configuration trees, the shapes
    /// of shared regions and what their faces are, patch nets) and recomputes the rest:
    /// after [`LimitSurface::set_positions`] (and evaluations at the old positions, which
    /// fill the caches), every point equals, bit for bit, that of a surface built afresh
    /// at the new positions; and points evaluated together ([`LimitSurface::eval_many`])
    /// equal points evaluated one by one, also on a surface that meets them one by one
    /// from the last, whose trees build the children near a face's first corner only when
    /// a later point reaches them.
    #[test]
    fn re_posing_equals_a_fresh_surface() {
        let params = [0.0, 0.1, 0.25, 1.0 / 3.0, 0.5, 0.9, 1.0];
        let cases = [
            (
                fan(HIGH_VALENCE + 7, false, true),
                "closed quad fan (shared region)",
            ),
            (
                fan(HIGH_VALENCE / 4 + 3, true, false),
                "open triangle fan (shared region)",
            ),
            (fan(9, false, false), "open quad fan (trees)"),
            (crate::mesh::test_cube(), "cube (trees)"),
            (creased_grid(2.5, true), "creased grid (crease patches)"),
        ];
        for (mesh, what) in &cases {
            let o = Options::default();
            let moved: Vec<[f64; 3]> = (mesh.positions().iter())
                .map(|p| {
                    [
                        p[0] + 0.1 * p[1].sin(),
                        p[1] * 1.2,
                        p[2] + 0.05 * p[0] * p[1],
                    ]
                })
                .collect();
            let mut points = Vec::new();
            let mut s = LimitSurface::new(mesh, o).expect("surface");
            for f in 0..s.num_faces() {
                for sub in 0..s.num_subfaces(f) {
                    for &u in &params {
                        for &v in &params {
                            let (face, subface) = (f as u32, sub as u32);
                            points.push(SurfacePoint {
                                face,
                                subface,
                                u,
                                v,
                            });
                        }
                    }
                }
            }
            let before = s.eval_many(&points);
            s.set_positions(&moved).expect("positions");
            let mut fresh_mesh = mesh.clone();
            fresh_mesh.positions_mut().copy_from_slice(&moved);
            let fresh = LimitSurface::new(&fresh_mesh, o).expect("surface");
            let (a, b) = (s.eval_many(&points), fresh.eval_many(&points));
            let late = LimitSurface::new(&fresh_mesh, o).expect("surface");
            let mut c: Vec<_> = points.iter().rev().map(|&p| late.eval_point(p)).collect();
            c.reverse();
            // Into a slice of a longer buffer holding other results: every entry replaced.
            let stale = Err(EvalError::BadParameter { u: 2.0, v: -1.0 });
            let mut kept = vec![stale; points.len() + 5];
            s.eval_many_to(&points, Order::Second, &mut kept[..points.len()]);
            assert_eq!(kept[..points.len()], a[..], "{what}: into a slice");
            let mut moved_points = 0;
            for (k, p) in points.iter().enumerate() {
                assert_eq!(a[k], b[k], "{what}: re-posed vs fresh at {p:?}");
                assert_eq!(c[k], b[k], "{what}: one by one from the last at {p:?}");
                assert_eq!(a[k], s.eval_point(*p), "{what}: together vs alone at {p:?}");
                if let (Ok(x), Ok(y)) = (&a[k], &before[k]) {
                    moved_points += usize::from(x.p != y.p);
                }
            }
            assert!(
                moved_points > points.len() / 2,
                "{what}: the surface did not move"
            );
        }
    }

    /// `eval_many_to` wants one result per point.
    #[test]
    #[should_panic(expected = "one result per point")]
    fn eval_many_to_checks_its_slice() {
        let s = LimitSurface::new(crate::mesh::test_cube(), Options::default()).expect("cube");
        let p = SurfacePoint {
            face: 0,
            subface: 0,
            u: 0.5,
            v: 0.5,
        };
        s.eval_many_to(&[p, p], Order::First, &mut [Ok(Derivatives::default())]);
    }

    /// The faces around a pole whose neighbourhoods differ only by where the pole's cycle
    /// of faces starts, and by the direction of edges, share one configuration (the
    /// fan's faces all start at the pole); faces around a boundary vertex do not.
    #[test]
    fn faces_around_a_symmetric_pole_share_one_configuration() {
        for tri in [false, true] {
            let closed = fan(40, tri, true);
            let s = LimitSurface::new(&closed, Options::default()).expect("surface");
            assert_eq!(s.num_configurations(), 1, "closed fan, triangles: {tri}");
            let open = fan(12, tri, false);
            let s = LimitSurface::new(&open, Options::default()).expect("surface");
            assert!(s.num_configurations() > 1, "open fan, triangles: {tri}");
        }
    }
}
