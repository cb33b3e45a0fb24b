//! Non-uniform Catmull-Clark subdivision (NURSS; Sederberg, Zheng, Sewell & Sabin,
//! "Non-uniform recursive subdivision surfaces", SIGGRAPH 1998): Catmull-Clark topology with
//! a *knot interval* on every edge, which reproduces non-uniform cubic B-spline surfaces on
//! regular grids (one step = midpoint knot insertion in every span) and extends them to any
//! topology; optional rational weights (refined in homogeneous coordinates, so NURBS nets of
//! cylinders and tori stay exact) and auxiliary per-face-side intervals on the base mesh
//! ([JOS 2003] §2).
//!
//! # API
//! - [`Nurss`]: one level alive at a time. [`Nurss::new`] reads a [`PolyMesh`] and its
//!   [`PolyMesh::knots`] ([`KnotTags`](crate::mesh::KnotTags): intervals, side intervals, weights);
//!   [`Nurss::from_knots`] takes a per-edge interval array for a [`Topology`](crate::mesh::Topology) directly.
//!   [`Nurss::step`] refines one level, [`Nurss::refine`] several; the current level is read
//!   with [`Nurss::topology`], [`Nurss::intervals`], [`Nurss::positions`],
//!   [`Nurss::homogeneous`], and written out with [`Nurss::to_mesh`] (intervals and weights
//!   as [`KnotTags`](crate::mesh::KnotTags), so refining `a` then `b` levels equals refining `a + b`).
//! - [`Nurss::limit_points`]: the limit position of every vertex of the current level.
//! - [`crate::subdivide`](fn@crate::subdivide) with [`Scheme::Nurss`](crate::Scheme::Nurss):
//!   the one-call facade.
//! - [`tessellate`](fn@tessellate): a watertight sampling of the limit surface through refinement (limit
//!   points of level `L` for rate `2^L`), with mesh normals.
//! - [`NurssSurface`]: exact evaluation with derivatives at any `(face, u, v)` where the
//!   surface has a closed form (regular tensor-product faces, and faces with equal
//!   intervals around them, which are Catmull-Clark's), an error naming the face elsewhere.
//! - Face-varying channels (texture coordinates): [`Nurss`] refines them with the mesh as
//!   their value meshes (see [`Nurss::new`]), [`subdivide`](fn@crate::subdivide) and
//!   [`tessellate`](fn@tessellate) write them (at the limit with `limit`), and
//!   [`FaceVaryingSurface::nurss`](crate::limit::FaceVaryingSurface::nurss) evaluates their
//!   exact limit where [`NurssSurface`] has one.
//! - Re-posing (new positions of the same mesh, refined without refining again, or moved to
//!   the limit): [`crate::Reposer::new`] with [`Scheme::Nurss`](crate::Scheme::Nurss), and
//!   the plan underneath, [`crate::refine::RefinePlan::new`].
//!
//! The weights are in `crate::scheme::nurss`, the application to a level in
//! `refine::nurss` (which documents how intervals are read, boundaries and sharp
//! features). Child vertices, faces and edges are numbered as Catmull-Clark's (OpenSubdiv's
//! order), and with all intervals equal the result is Catmull-Clark's.
//!
//! # Boundaries, creases, corners, holes
//! Boundary edges follow the cubic B-spline curve rule with the boundary's own intervals
//! (Catmull-Clark's boundary rule when the intervals are equal); boundary interpolation
//! modes, infinitely sharp creases, corners and holes are honoured as in Catmull-Clark.
//! Semi-sharp creases and vertices (sharpness strictly between 0 and 10) are rejected with
//! [`NurssError::SemiSharp`]: their fractional rules have no non-uniform counterpart; use a
//! zero knot interval (a sharp feature) or infinite sharpness instead.
//!
//! ```
//! use subsurf::mesh::{EdgeInterval, Options, PolyMesh};
//! use subsurf::nonuniform::Nurss;
//!
//! // A 4×4 grid whose middle column of edges carries interval 3.
//! let mut pos = Vec::new();
//! for j in 0..4 { for i in 0..4 { pos.push([i as f64, j as f64, 0.0]); } }
//! let mut faces = Vec::new();
//! for j in 0..3u32 { for i in 0..3u32 { let v = 4 * j + i; faces.push([v, v + 1, v + 5, v + 4]); } }
//! let mut grid = PolyMesh::from_faces(pos, &faces).unwrap();
//! for j in 0..4u32 {
//!     grid.knots.intervals.push(EdgeInterval { v0: 4 * j + 1, v1: 4 * j + 2, interval: 3.0 });
//! }
//! let mut s = Nurss::new(&grid, &Options::default()).unwrap();
//! s.refine(2);
//! assert_eq!(s.topology().num_faces(), 9 * 16);
//! let out = s.to_mesh(false);
//! // The refined intervals travel with the mesh: two steps quarter them (edges of
//! // interval 1 would not be listed).
//! let iv: Vec<f64> = out.knots.intervals.iter().map(|t| t.interval).collect();
//! assert!(iv.iter().all(|&d| d == 0.25 || d == 0.75) && iv.contains(&0.75));
//! ```

mod face_varying;
pub(crate) mod limit;
pub(crate) mod surface;
pub(crate) mod tessellate;

use crate::mesh::PolyMesh;
pub(crate) use crate::refine::nurss::vertex_weights;
pub use crate::refine::nurss::{Nurss, NurssError};

pub(crate) use limit::LimitRows;
pub use limit::LIMIT_TOLERANCE;
pub use surface::{NurssEvalError, NurssSurface};
pub use tessellate::tessellate;

/// `mesh` (with its [`PolyMesh::knots`]) refined `levels` times with NURSS, as
/// [`subdivide`](fn@crate::subdivide) with [`Scheme::Nurss`](crate::Scheme::Nurss) refines it,
/// calling `progress(level_done, levels)` after each level.
///
/// # Errors
/// As [`Nurss::new`]; [`MeshError::TooLarge`](crate::mesh::MeshError::TooLarge) (in
/// [`NurssError::Mesh`]) beyond the `u32` index range, as every uniform refinement
/// ([`check_size`](crate::refine::uniform::check_size)).
pub(crate) fn refined(
    mesh: &PolyMesh,
    options: &crate::mesh::Options,
    levels: u32,
    progress: &mut dyn FnMut(u32, u32),
) -> Result<Nurss, NurssError> {
    use crate::refine::uniform::{check_size, Steps};
    check_size(
        mesh,
        Steps::Family(crate::scheme::adjustable::Mixed::CATMULL_CLARK),
        levels,
    )?;
    let mut s = Nurss::new(mesh, options)?;
    for l in 1..=levels {
        s.step();
        progress(l, levels);
    }
    Ok(s)
}

impl Nurss {
    /// The current level as [`subdivide`](fn@crate::subdivide) writes it: holes kept
    /// (tagged) with `keep_holes`, and moved to the limit with `limit` (positions by
    /// [`Nurss::limit_points`], face-varying channels by
    /// [`face_varying_limit`](Nurss::face_varying_limit)).
    pub(crate) fn output_mesh(&self, keep_holes: bool, limit: bool) -> PolyMesh {
        let mut out = self.to_mesh(keep_holes);
        if limit {
            let lp = self.limit_points();
            out.positions_mut().copy_from_slice(&lp);
            out.face_varying = self.face_varying_limit(keep_holes);
        }
        out
    }
}

/// Whether `mesh` has knot intervals, side intervals or weights: the CLI then defaults to
/// NURSS.
pub fn has_knots(mesh: &PolyMesh) -> bool {
    !mesh.knots.is_empty()
}

/// Statistics of a mesh's knot tags (for `subsurf info`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct KnotSummary {
    /// Distinct edges with a `t interval` tag (a later tag on the same edge wins).
    pub tagged_edges: usize,
    /// Smallest and largest tagged interval.
    pub interval_range: Option<(f64, f64)>,
    /// Tagged edges whose interval is 0.
    pub zero_interval_edges: usize,
    /// `t sideinterval` entries.
    pub side_intervals: usize,
    /// Distinct vertices with a `t weight` tag.
    pub weighted_vertices: usize,
    /// Smallest and largest weight.
    pub weight_range: Option<(f64, f64)>,
}

/// The [`KnotSummary`] of `mesh.knots`.
pub fn knot_summary(mesh: &PolyMesh) -> KnotSummary {
    use std::collections::HashMap;
    let mut edges: HashMap<(u32, u32), f64> = HashMap::new();
    for t in &mesh.knots.intervals {
        edges.insert((t.v0.min(t.v1), t.v0.max(t.v1)), t.interval);
    }
    let mut weights: HashMap<u32, f64> = HashMap::new();
    for w in &mesh.knots.weights {
        weights.insert(w.vertex, w.weight);
    }
    let range = |it: &mut dyn Iterator<Item = f64>| {
        it.fold(None, |r: Option<(f64, f64)>, x| {
            Some(r.map_or((x, x), |(a, b)| (a.min(x), b.max(x))))
        })
    };
    KnotSummary {
        tagged_edges: edges.len(),
        interval_range: range(&mut edges.values().copied()),
        zero_interval_edges: edges.values().filter(|&&d| d == 0.0).count(),
        side_intervals: mesh.knots.side_intervals.len(),
        weighted_vertices: weights.len(),
        weight_range: range(&mut weights.values().copied()),
    }
}
