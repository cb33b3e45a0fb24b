//! Uniform refinement of a mesh's positions with every scheme whose levels are refined one
//! after the other from positions alone (all but NURSS, which carries knot intervals:
//! `refine::nurss`), to a mesh that carries the sharpness still left: the refinement under
//! [`subdivide`](fn@crate::subdivide), which adds the memory guard and the limit.

use super::loop_::{check_triangles, interpolate_loop};
use super::tri_topology::refine_tri_topology;
use super::{
    interpolate, interpolate_with, refine_topology, refine_topology_for_output, FaceVaryingRefiner,
};
use crate::mesh::{
    BoundaryInterpolation, Corner, Crease, FaceGroups, MeshError, Options, PolyMesh, Tags,
    Topology, TopologyWarning,
};
use crate::scheme::adjustable::Mixed;
use crate::scheme::bilinear::Bilinear;
use crate::scheme::catmark::CatmullClark;
use crate::scheme::loop_::Loop;
use crate::scheme::Scheme;

/// How each level of a uniform refinement is made: the schemes [`refine_uniform`] refines.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Steps {
    /// The Catmull-Clark split; the adjustable masks on the first `steps` levels, then
    /// Catmull-Clark's ([`Mixed::CATMULL_CLARK`]: Catmull-Clark throughout).
    Family(Mixed),
    /// The Catmull-Clark split with [`Bilinear`] masks.
    Bilinear,
    /// The triangle split with Loop's masks (`interpolate_loop`, and `FaceVaryingRefiner`
    /// for face-varying channels).
    Loop,
}

impl Steps {
    /// The steps of `scheme`, `None` for NURSS.
    pub(crate) fn of(scheme: Scheme) -> Option<Self> {
        match scheme {
            Scheme::CatmullClark => Some(Self::Family(Mixed::CATMULL_CLARK)),
            Scheme::Adjustable(m) => Some(Self::Family(m)),
            Scheme::Bilinear => Some(Self::Bilinear),
            Scheme::Loop => Some(Self::Loop),
            Scheme::Nurss => None,
        }
    }

    /// The options the topology is built with: bilinear makes no holes for boundary mode
    /// `None` ([`Bilinear::topology_options`]).
    pub(crate) fn topology_options(self, options: &Options) -> Options {
        match self {
            Self::Bilinear => Bilinear::topology_options(options),
            _ => *options,
        }
    }

    /// The next level of `p`: Loop's triangle split ([`refine_tri_topology`]), else the
    /// Catmull-Clark split ([`refine_topology`]), `full` as they say.
    pub(crate) fn refine(self, p: &Topology, options: &Options, full: bool) -> Topology {
        match self {
            Self::Loop => refine_tri_topology(p, options, full),
            _ => refine_topology(p, options, full),
        }
    }

    /// The steps that follow the first `k`: the adjusted steps of mixed subdivision count
    /// down ([`Mixed::after`]); Loop's and bilinear's are the same on every level.
    pub(crate) fn after(self, k: u32) -> Self {
        match self {
            Self::Family(m) => Self::Family(m.after(k)),
            other => other,
        }
    }
}

/// The last level of a uniform refinement and the positions of its vertices.
pub(crate) struct Uniform {
    /// The last level: complete (with its full adjacency) when asked for, else without
    /// edge vertices (`refine_topology_for_output`).
    pub(crate) level: Topology,
    /// The level before the last when the last is not complete: its edges give the
    /// output's creases.
    parent: Option<Topology>,
    /// The positions of the last level's vertices (OpenSubdiv's numbering).
    pub(crate) positions: Vec<[f64; 3]>,
    /// Warnings about the base mesh.
    pub(crate) warnings: Vec<TopologyWarning>,
    /// The face-varying channels, refined to the last level.
    face_varying: FaceVaryingRefiner,
    /// The base mesh's face groups, when it has any, for [`refined_groups`].
    groups: Option<BaseGroups>,
    boundary: BoundaryInterpolation,
}

/// What [`refined_groups`] needs of a base mesh: its face groups, the size of each face
/// and whether it is a hole, the steps and levels of the refinement.
pub(crate) struct BaseGroups {
    groups: FaceGroups,
    sizes: Vec<u32>,
    holes: Vec<bool>,
    steps: Steps,
    levels: u32,
}

impl BaseGroups {
    /// The groups of `mesh`, whose base level is `level`, refined `levels` times with
    /// `steps`; `None` when it has none.
    pub(crate) fn new(
        mesh: &PolyMesh,
        level: &Topology,
        steps: Steps,
        levels: u32,
    ) -> Option<Self> {
        if mesh.groups.is_empty() {
            return None;
        }
        Some(Self {
            groups: mesh.groups.clone(),
            sizes: mesh.faces().map(|f| f.len() as u32).collect(),
            holes: (0..mesh.num_faces()).map(|f| level.is_hole(f)).collect(),
            steps,
            levels,
        })
    }
}

/// The face groups of `mesh` refined `levels` times with `steps` ([`refined_groups`]),
/// holes left out unless `keep_holes`, for the refinements that do not go through
/// [`refine_uniform`] (NURSS, whose faces are numbered as Catmull-Clark's): empty when
/// `mesh` has none.
///
/// # Errors
/// Those of [`Topology::from_mesh`] (which finds the holes).
pub(crate) fn groups_of_refined(
    mesh: &PolyMesh,
    options: &Options,
    steps: Steps,
    levels: u32,
    keep_holes: bool,
) -> Result<FaceGroups, MeshError> {
    if mesh.groups.is_empty() {
        return Ok(FaceGroups::default());
    }
    let (base, _) = Topology::from_mesh(mesh, options)?;
    Ok(BaseGroups::new(mesh, &base, steps, levels)
        .map(|g| refined_groups(&g, keep_holes))
        .unwrap_or_default())
}

/// The face groups of the refined mesh: each face's state given to all its descendants.
///
/// Refinement numbers the children of a face contiguously, in the order of their parents
/// (OpenSubdiv's `Vtr::Refinement`; `refine_topology`, `refine_tri_topology`): the quad
/// split gives face `f` of `n` corners the `n` child quads `S_f .. S_f + n` (one per
/// corner, `S_f` the corners of the faces before `f`), and every quad after the first
/// level its four `4g .. 4g + 4`; the triangle split gives triangle `t` its four
/// `4t .. 4t + 4`. So face `f` has `n·4^(L−1)` descendants at level `L ≥ 1` (the
/// triangle split: `4^L`), in one run, the runs in the order of the faces; the
/// descendants of a hole are holes, and are left out of the output unless `keep_holes`.
pub(crate) fn refined_groups(base: &BaseGroups, keep_holes: bool) -> FaceGroups {
    let l = base.levels;
    base.groups.for_children(|f| {
        if base.holes[f] && !keep_holes {
            return 0;
        }
        match (base.steps, l) {
            (_, 0) => 1,
            (Steps::Loop, _) => 1 << (2 * l),
            _ => (base.sizes[f] as usize) << (2 * (l - 1)),
        }
    })
}

/// Bytes per face of the last level held at once by [`refine_uniform`]: the child's faces, edge
/// vertices, tags and sharpness (~60 B), a quarter of a complete parent level (~50 B), two
/// position buffers (~30 B) and the output copy of the faces (16 B). Measured peaks are
/// ~130 B per output face (`BENCHMARKS.md`); the estimate errs high.
const BYTES_PER_FACE: u64 = 160;
/// Extra bytes per face when limit positions are requested: the last level's full
/// adjacency and three more position-sized buffers.
const LIMIT_BYTES_PER_FACE: u64 = 200;

/// Bytes per face of the last level for each number of a face-varying channel's values:
/// up to one value per face corner (a UV island per face, the worst layout) in the
/// output, a quarter as many in the parent level. Measured: 45 B per face for texture
/// coordinates (two numbers) at level 5 of `catmark_pawn`, whose every face is an island
/// of its own, 32 B with Loop on the all-triangle `catmark_bishop`; the estimate errs high.
const FVAR_BYTES_PER_FACE_PER_NUMBER: u64 = 32;
/// Bytes per face of the last level for each face-varying channel's indices: the child
/// faces' values (four per quad) and the child offsets.
const FVAR_INDEX_BYTES_PER_FACE: u64 = 16;
/// Extra bytes per face and number of a face-varying channel when the values are moved to
/// their limit (59 B per face measured on `catmark_pawn` level 5 with `--limit`, against
/// 45 B without).
const FVAR_LIMIT_BYTES_PER_FACE_PER_NUMBER: u64 = 16;

/// Estimated peak memory in bytes of refining `mesh` `levels` times with `steps`, and of
/// moving the last level to the limit with `limit`, saturating at `u64::MAX`; its
/// face-varying channels are [`estimate_face_varying`]'s.
pub(crate) fn estimate_uniform(mesh: &PolyMesh, steps: Steps, levels: u32, limit: bool) -> u64 {
    let per_face = BYTES_PER_FACE + if limit { LIMIT_BYTES_PER_FACE } else { 0 };
    refined_faces(mesh, steps, levels)
        .saturating_mul(per_face)
        .saturating_add(mesh.num_vertices() as u64 * 64)
}

/// Estimated memory in bytes that refining the face-varying channels of `mesh` with it
/// adds to [`estimate_uniform`]'s, saturating at `u64::MAX`.
pub(crate) fn estimate_face_varying(
    mesh: &PolyMesh,
    steps: Steps,
    levels: u32,
    limit: bool,
) -> u64 {
    let per_number = FVAR_BYTES_PER_FACE_PER_NUMBER
        + if limit {
            FVAR_LIMIT_BYTES_PER_FACE_PER_NUMBER
        } else {
            0
        };
    let per_face: u64 = (mesh.face_varying.iter())
        .map(|c| FVAR_INDEX_BYTES_PER_FACE + c.dim() as u64 * per_number)
        .sum();
    refined_faces(mesh, steps, levels).saturating_mul(per_face)
}

/// Number of faces after `levels` uniform steps of `steps`: the first step makes the
/// face-vertex count `S` (every face of size `n` gives `n` quads), or four triangles per
/// triangle with Loop, then ×4 per step. Saturates.
pub(crate) fn refined_faces(mesh: &PolyMesh, steps: Steps, levels: u32) -> u64 {
    if levels == 0 {
        return mesh.num_faces() as u64;
    }
    let s = match steps {
        Steps::Loop => 4 * mesh.num_faces() as u64,
        _ => mesh.face_verts().len() as u64,
    };
    let shift = 2 * (levels as u64 - 1);
    if shift >= 64 {
        return if s == 0 { 0 } else { u64::MAX };
    }
    s.saturating_mul(1u64 << shift)
}

/// [`MeshError::TooLarge`] when `levels` steps of `steps` would take the last level of
/// `mesh` beyond 32-bit indices: its vertices are at most faces + edges + vertices, about
/// 4 × faces.
pub(crate) fn check_size(mesh: &PolyMesh, steps: Steps, levels: u32) -> Result<(), MeshError> {
    let faces = refined_faces(mesh, steps, levels);
    if faces
        .saturating_mul(4)
        .saturating_add(mesh.num_vertices() as u64)
        >= u32::MAX as u64
    {
        return Err(MeshError::TooLarge {
            what: format!("level {levels} ({faces} faces)"),
        });
    }
    Ok(())
}

/// Refines `mesh` uniformly `levels` times with `steps` as OpenSubdiv refines it (same
/// rules for boundaries, creases, corners, holes, triangles and non-manifold topology; same
/// vertex and face order). Only the last two levels are kept in memory. With `complete`,
/// the last level has its full adjacency (for limit masks; Loop's levels always have it).
/// `progress(level_done, levels)` is called after each level. `mesh` has been validated
/// ([`PolyMesh::validate`]).
///
/// # Errors
/// [`MeshError`] for invalid tags; [`MeshError::NotTriangle`] naming the first face of
/// `mesh` that is not a triangle, with Loop; [`MeshError::TooLarge`] when the last level
/// would exceed 32-bit indices.
pub(crate) fn refine_uniform(
    mesh: &PolyMesh,
    options: &Options,
    steps: Steps,
    levels: u32,
    complete: bool,
    progress: &mut dyn FnMut(u32, u32),
) -> Result<Uniform, MeshError> {
    if steps == Steps::Loop {
        check_triangles(mesh)?;
    }
    check_size(mesh, steps, levels)?;
    let options = &steps.topology_options(options);
    let (mut level, warnings) = Topology::from_mesh(mesh, options)?;
    let mut pos = mesh.positions().to_vec();
    let mut fvar = FaceVaryingRefiner::new(&level, &mesh.face_varying, options);
    let groups = BaseGroups::new(mesh, &level, steps, levels);
    let mut parent = None;
    for l in 1..=levels {
        // The last level needs its full adjacency only for limit masks, and its edge
        // vertices only for the output's creases, which are read from its parent.
        let for_output = l == levels && !complete;
        let child = match steps {
            Steps::Family(_) | Steps::Bilinear if for_output => {
                refine_topology_for_output(&level, options)
            }
            _ => steps.refine(&level, options, !for_output),
        };
        let mut next = vec![[0.0; 3]; child.num_vertices()];
        match steps {
            Steps::Family(m) if l <= m.steps => {
                interpolate_with(&level, &child, options, m.scheme, &pos, &mut next);
                fvar.refine(&level, &child, options, m.scheme);
            }
            Steps::Family(_) => {
                interpolate(&level, &child, options, &pos, &mut next);
                fvar.refine(&level, &child, options, CatmullClark);
            }
            Steps::Bilinear => {
                interpolate_with(&level, &child, options, Bilinear, &pos, &mut next);
                fvar.refine(&level, &child, options, Bilinear);
            }
            Steps::Loop => {
                interpolate_loop(&level, &child, options, &pos, &mut next);
                fvar.refine(&level, &child, options, Loop);
            }
        }
        let p = std::mem::replace(&mut level, child);
        // The triangle split writes the child's edge vertices in any case.
        if for_output && steps != Steps::Loop {
            parent = Some(p);
        }
        pos = next;
        progress(l, levels);
    }
    Ok(Uniform {
        level,
        parent,
        positions: pos,
        warnings,
        face_varying: fvar,
        groups,
        boundary: options.boundary,
    })
}

/// `mesh` refined `levels` times with `steps` ([`refine_uniform`]) as a mesh, holes kept
/// (tagged) with `keep_holes`: what the paper methods refine control meshes with, and what
/// rendering draws a level of.
///
/// # Errors
/// [`MeshError`] for an invalid mesh, and as [`refine_uniform`].
pub(crate) fn refine_mesh(
    mesh: &PolyMesh,
    options: &Options,
    steps: Steps,
    levels: u32,
    keep_holes: bool,
) -> Result<PolyMesh, MeshError> {
    mesh.validate()?;
    let u = refine_uniform(mesh, options, steps, levels, false, &mut |_, _| {})?;
    Ok(u.into_mesh(keep_holes))
}

impl Uniform {
    /// Moves the face-varying channels of the last level (complete: refined with
    /// `complete`) to their limit ([`FaceVaryingRefiner::limit`]).
    pub(crate) fn limit_face_varying(&mut self, scheme: Scheme, options: &Options) {
        self.face_varying.limit(scheme, &self.level, options);
    }

    /// The refined mesh ([`output_mesh`]) with its face-varying channels and face groups
    /// ([`refined_groups`]), holes kept (tagged) with `keep_holes`.
    pub(crate) fn into_mesh(self, keep_holes: bool) -> PolyMesh {
        let face_varying = self.face_varying.finish(&self.level, keep_holes);
        let groups = (self.groups.as_ref()).map(|g| refined_groups(g, keep_holes));
        let mut m = output_mesh(
            self.level,
            self.parent.as_ref(),
            self.boundary == BoundaryInterpolation::None,
            self.positions,
            keep_holes,
        );
        m.face_varying = face_varying;
        if let Some(groups) = groups {
            debug_assert!(groups.validate(m.num_faces()).is_ok());
            m.groups = groups;
        }
        m
    }
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
