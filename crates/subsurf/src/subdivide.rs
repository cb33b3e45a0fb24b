//! The one-call facade: [`subdivide`] a [`PolyMesh`] to a level, optionally to the limit.

use crate::limit;
use crate::mesh::{Corner, Crease, MeshError, Options, PolyMesh, Tags, Topology, TopologyWarning};
use crate::refine::interpolate;
use crate::refine::{
    interpolate_with, refine_topology, refine_topology_for_output, FaceVaryingRefiner,
};
use crate::scheme::adjustable::Mixed;
use crate::scheme::catmark::CatmullClark;

/// What [`subdivide`] should do.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SubdivideOptions {
    /// Number of uniform refinement steps (0 leaves the mesh as it is).
    pub levels: u32,
    /// The rules' options: boundary interpolation, crease method, triangle rule.
    pub options: Options,
    /// Move the last level's vertices to their limit positions and compute limit normals.
    /// Face-varying channels are refined to the last level but not moved to their limit.
    pub limit: bool,
    /// Keep hole faces in the output (tagged as holes) so that the result can be refined
    /// again with the same outcome; by default holes are left out, as OpenSubdiv does.
    pub keep_holes: bool,
    /// Refuse (with [`Error::TooLarge`]) when the estimated memory exceeds this many bytes.
    pub max_memory: Option<u64>,
}

/// The result of [`subdivide`].
#[derive(Clone, Debug, PartialEq)]
pub struct Subdivision {
    /// The refined mesh. Its tags carry the sharpness still left at the last level.
    pub mesh: PolyMesh,
    /// Unit limit normals per vertex, when [`SubdivideOptions::limit`] was set.
    pub normals: Option<Vec<[f64; 3]>>,
    /// Warnings about the input (ignored tags, non-manifold elements).
    pub warnings: Vec<TopologyWarning>,
}

/// Errors of [`subdivide`].
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Error {
    /// The input mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The requested level would need more memory than allowed.
    #[error("refining to level {levels} needs about {}, more than the limit of {}; use a lower level", ByteSize(*estimate), ByteSize(*limit))]
    TooLarge {
        /// Requested level.
        levels: u32,
        /// Estimated bytes.
        estimate: u64,
        /// Allowed bytes.
        limit: u64,
    },
    /// Non-uniform (NURSS) refinement of the mesh failed: a bad knot tag, a semi-sharp
    /// crease ([`Reposer::new_nurss`](crate::Reposer::new_nurss)).
    #[error(transparent)]
    Nurss(#[from] crate::nurss::NurssError),
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

/// A byte count as messages give it: MiB rounded up, or KiB (rounded up) below 1 MiB.
struct ByteSize(u64);

impl std::fmt::Display for ByteSize {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.0 < 1 << 20 {
            write!(f, "{} KiB", self.0.div_ceil(1 << 10))
        } else {
            write!(f, "{} MiB", self.0.div_ceil(1 << 20))
        }
    }
}

/// Bytes per face of the last level held at once by [`subdivide`]: the child's faces, edge
/// vertices, tags and sharpness (~60 B), a quarter of a complete parent level (~50 B), two
/// position buffers (~30 B) and the output copy of the faces (16 B). Measured peaks are
/// ~130 B per output face (`BENCHMARKS.md`); the estimate errs high.
const BYTES_PER_FACE: u64 = 160;
/// Extra bytes per face when limit positions are requested: the last level's full
/// adjacency and three more position-sized buffers.
const LIMIT_BYTES_PER_FACE: u64 = 200;

/// Number of faces after `levels` uniform steps: the face-vertex count `S` for the first
/// step (every face of size `n` gives `n` quads), then ×4 per step. Saturates.
fn refined_faces(mesh: &PolyMesh, levels: u32) -> u64 {
    if levels == 0 {
        return mesh.num_faces() as u64;
    }
    let s = mesh.face_verts().len() as u64;
    let shift = 2 * (levels as u64 - 1);
    if shift >= 64 {
        return if s == 0 { 0 } else { u64::MAX };
    }
    s.saturating_mul(1u64 << shift)
}

/// Estimated peak memory in bytes of [`subdivide`] with `opts` (the levels, and whether
/// limit positions are computed), saturating at `u64::MAX`.
pub fn estimate_memory(mesh: &PolyMesh, opts: &SubdivideOptions) -> u64 {
    let per_face = BYTES_PER_FACE + if opts.limit { LIMIT_BYTES_PER_FACE } else { 0 };
    refined_faces(mesh, opts.levels)
        .saturating_mul(per_face)
        .saturating_add(mesh.num_vertices() as u64 * 64)
}

/// Refines `mesh` uniformly `opts.levels` times with Catmull-Clark as OpenSubdiv does
/// (same rules for boundaries, creases, corners, holes, triangles and non-manifold
/// topology; same vertex and face order), optionally moving the result to the limit.
///
/// Only the last two levels are kept in memory while refining.
///
/// # Errors
/// [`Error::Mesh`] for an invalid mesh or tags; [`Error::TooLarge`] when the estimated
/// memory exceeds `opts.max_memory` or the result would exceed 32-bit indices.
pub fn subdivide(mesh: &PolyMesh, opts: &SubdivideOptions) -> Result<Subdivision, Error> {
    subdivide_with_progress(mesh, opts, &mut |_, _| {})
}

/// [`subdivide`], calling `progress(level_done, levels)` after each level.
pub fn subdivide_with_progress(
    mesh: &PolyMesh,
    opts: &SubdivideOptions,
    progress: &mut dyn FnMut(u32, u32),
) -> Result<Subdivision, Error> {
    subdivide_steps(mesh, opts, None, progress)
}

/// Mixed subdivision: like [`subdivide`], but the first `mixed.steps` levels use the
/// shape-adjustable masks with parameter `mixed.scheme` ([`crate::scheme::adjustable`]),
/// the remaining levels Catmull-Clark. Topology, numbering, tags and sharpness decay are
/// those of [`subdivide`]; with `c = ½` the result is [`subdivide`]'s (to rounding).
///
/// With `opts.limit` the last level is moved to its Catmull-Clark limit: the limit of the
/// mixed scheme with `min(mixed.steps, opts.levels)` adjustable steps (see
/// [`MixedSurface`](crate::MixedSurface) for evaluation anywhere on it).
///
/// # Errors
/// As [`subdivide`].
pub fn subdivide_mixed(
    mesh: &PolyMesh,
    opts: &SubdivideOptions,
    mixed: Mixed,
) -> Result<Subdivision, Error> {
    subdivide_steps(mesh, opts, Some(mixed), &mut |_, _| {})
}

/// [`subdivide_mixed`], calling `progress(level_done, levels)` after each level.
pub fn subdivide_mixed_with_progress(
    mesh: &PolyMesh,
    opts: &SubdivideOptions,
    mixed: Mixed,
    progress: &mut dyn FnMut(u32, u32),
) -> Result<Subdivision, Error> {
    subdivide_steps(mesh, opts, Some(mixed), progress)
}

/// The refinement loop of [`subdivide`] and [`subdivide_mixed`]: level `l` uses the
/// adjustable masks when `l <= mixed.steps`, Catmull-Clark otherwise.
fn subdivide_steps(
    mesh: &PolyMesh,
    opts: &SubdivideOptions,
    mixed: Option<Mixed>,
    progress: &mut dyn FnMut(u32, u32),
) -> Result<Subdivision, Error> {
    mesh.validate()?;
    let estimate = estimate_memory(mesh, opts);
    if let Some(limit) = opts.max_memory {
        if estimate > limit {
            return Err(Error::TooLarge {
                levels: opts.levels,
                estimate,
                limit,
            });
        }
    }
    // Vertices of the last level ≤ faces + edges + vertices ≤ ~4 × faces: keep that in u32.
    let faces = refined_faces(mesh, opts.levels);
    if faces
        .saturating_mul(4)
        .saturating_add(mesh.num_vertices() as u64)
        >= u32::MAX as u64
    {
        return Err(Error::Mesh(MeshError::TooLarge {
            what: format!("level {} ({faces} faces)", opts.levels),
        }));
    }

    let (mut level, warnings) = Topology::from_mesh(mesh, &opts.options)?;
    let mut pos = mesh.positions().to_vec();
    let mut fvar = FaceVaryingRefiner::new(&level, &mesh.face_varying, &opts.options);
    // The parent of the last level, when that level is built without edge vertices.
    let mut parent = None;
    for l in 1..=opts.levels {
        let last = l == opts.levels;
        // The last level needs its full adjacency only for limit masks, and its edge
        // vertices only for the output's creases, which are read from its parent.
        let child = if last && !opts.limit {
            refine_topology_for_output(&level, &opts.options)
        } else {
            refine_topology(&level, &opts.options, true)
        };
        let mut next = vec![[0.0; 3]; child.num_vertices()];
        match mixed {
            Some(m) if l <= m.steps => {
                interpolate_with(&level, &child, &opts.options, m.scheme, &pos, &mut next);
                fvar.refine(&level, &child, &opts.options, m.scheme);
            }
            _ => {
                interpolate(&level, &child, &opts.options, &pos, &mut next);
                fvar.refine(&level, &child, &opts.options, CatmullClark);
            }
        }
        let p = std::mem::replace(&mut level, child);
        if last && !opts.limit {
            parent = Some(p);
        }
        pos = next;
        progress(l, opts.levels);
    }

    let normals = if opts.limit {
        Some(limit_in_place(&level, &opts.options, &mut pos))
    } else {
        None
    };
    let face_varying = fvar.finish(&level, opts.keep_holes);
    let mut out = output_mesh(
        level,
        parent.as_ref(),
        opts.options.boundary == crate::mesh::BoundaryInterpolation::None,
        pos,
        opts.keep_holes,
    );
    out.face_varying = face_varying;
    Ok(Subdivision {
        mesh: out,
        normals,
        warnings,
    })
}

/// Moves `pos` (values at the vertices of `level`) to their limit positions and returns
/// unit limit normals. Limit masks need quads around each vertex; where a vertex touches
/// an n-gon (only possible at the base level) the masks are applied one level further
/// down, whose vertex `v` is the child of `v` and has the same limit.
fn limit_in_place(level: &Topology, options: &Options, pos: &mut [[f64; 3]]) -> Vec<[f64; 3]> {
    let nv = level.num_vertices();
    let all_quads = (0..level.num_faces()).all(|f| level.face_vertices(f).len() == 4);
    let (lim, t1, t2) = if all_quads {
        let mut lim = vec![[0.0; 3]; nv];
        let (mut t1, mut t2) = (vec![[0.0; 3]; nv], vec![[0.0; 3]; nv]);
        limit::limit_points(level, pos, &mut lim, Some((&mut t1, &mut t2)));
        (lim, t1, t2)
    } else {
        let child = refine_topology(level, options, true);
        let mut cpos = vec![[0.0; 3]; child.num_vertices()];
        interpolate(level, &child, options, pos, &mut cpos);
        let n = child.num_vertices();
        let mut lim = vec![[0.0; 3]; n];
        let (mut t1, mut t2) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
        limit::limit_points(&child, &cpos, &mut lim, Some((&mut t1, &mut t2)));
        lim.truncate(nv);
        t1.truncate(nv);
        t2.truncate(nv);
        (lim, t1, t2)
    };
    pos.copy_from_slice(&lim);
    limit::normals(level, pos, &t1, &t2)
}

/// The output mesh of a refined level: all vertices (OpenSubdiv's numbering), the faces
/// that are not holes (all of them, holes tagged, with `keep_holes`), and the sharpness
/// still left, as tags — so that refining the output `b` more levels gives the same
/// result as refining the input `a + b` levels. Sharpness that the next run re-derives
/// by itself (boundary and non-manifold edges, sharpened corners and non-manifold
/// vertices) is not written.
///
/// `parent` is given when `level` was built by `refine_topology_for_output`, without edge
/// vertices: the crease tags then come from the parent's edges.
///
/// The level is consumed: when every face is kept (no holes, or `keep_holes`) its face
/// arrays become the mesh's without a copy (at level 6 of `catmark_bishop`, 76 MB that
/// would otherwise be allocated, faulted in and copied), and the scans for remaining
/// sharpness run in parallel on large levels.
fn output_mesh(
    mut level: Topology,
    parent: Option<&Topology>,
    explicit_boundary: bool,
    pos: Vec<[f64; 3]>,
    keep_holes: bool,
) -> PolyMesh {
    let nf = level.num_faces();
    let holes: Vec<u32> = if keep_holes && level.has_holes() {
        (0..nf as u32)
            .filter(|&f| level.is_hole(f as usize))
            .collect()
    } else {
        Vec::new()
    };
    let drop_holes = !keep_holes && level.has_holes() && (0..nf).any(|f| level.is_hole(f));
    // Boundary edges are sharpened again when the output is read back, except that with
    // `BoundaryInterpolation::None` their explicit sharpness decides which faces are
    // holes: there, write them all (the holes themselves are tagged).
    let crease = |e: usize, [v0, v1]: [u32; 2]| {
        let t = level.edge_tag(e);
        let s = level.edge_sharpness(e);
        let keep = !t.non_manifold && (!t.boundary || explicit_boundary);
        (s > 0.0 && keep).then_some(Crease {
            v0,
            v1,
            sharpness: s,
        })
    };
    let corner = |v: usize| {
        let s = level.vertex_sharpness(v);
        let t = level.vertex_tag(v);
        (s > 0.0 && !t.non_manifold && !t.sharpened_corner).then_some(Corner {
            vertex: v as u32,
            sharpness: s,
        })
    };
    let creases = || match parent {
        None => filter_map_indices(level.num_edges(), |e| crease(e, level.edge_vertices(e))),
        Some(p) => {
            // Child edges `0..S` lie inside parent faces and are never sharp; `S + 2e + k`
            // joins the child of parent edge `e` to the end `k` of that edge.
            let s = p.face_verts().len();
            debug_assert!((0..s).all(|e| level.edge_sharpness(e) == 0.0));
            let ec0 = (p.num_vertices() + p.num_faces()) as u32;
            filter_map_indices(2 * p.num_edges(), |i| {
                let e = i / 2;
                crease(s + i, [ec0 + e as u32, p.edge_vertices(e)[i % 2]])
            })
        }
    };
    let (creases, corners) =
        rayon::join(creases, || filter_map_indices(level.num_vertices(), corner));
    let tags = Tags {
        holes,
        creases,
        corners,
    };
    let (offsets, verts) = if drop_holes {
        let mut offsets = Vec::with_capacity(nf + 1);
        let mut verts = Vec::with_capacity(level.face_verts().len());
        offsets.push(0u32);
        for f in 0..nf {
            if !level.is_hole(f) {
                verts.extend_from_slice(level.face_vertices(f));
                offsets.push(verts.len() as u32);
            }
        }
        (offsets, verts)
    } else {
        (
            std::mem::take(&mut level.face_offsets),
            std::mem::take(&mut level.face_verts),
        )
    };
    drop(level);
    let mut m = PolyMesh::new_unchecked(pos, offsets, verts);
    m.tags = tags;
    m
}

/// `(0..n).filter_map(f).collect()`, in parallel (keeping the order) when `n` is large.
fn filter_map_indices<T: Send>(n: usize, f: impl Fn(usize) -> Option<T> + Sync + Send) -> Vec<T> {
    use rayon::prelude::*;
    if n < 64 * 1024 {
        (0..n).filter_map(f).collect()
    } else {
        (0..n)
            .into_par_iter()
            .with_min_len(16 * 1024)
            .filter_map(f)
            .collect()
    }
}
