//! Re-posing plans: the linear map from base positions to the positions of a refined level,
//! precomputed once so that moving the control points (animation, interactive editing,
//! fitting) costs one sparse matrix–vector product per level instead of a full refinement.
//!
//! Catmull-Clark refinement is linear in the vertex data: with the topology, tags and
//! options fixed, the positions of level `l + 1` are `S_l × positions of level l`, where
//! row `i` of `S_l` holds the weights of child vertex `i` on the parent vertices. A
//! [`RefinePlan`] stores that chain `S_0, …, S_{L-1}`, with the face points folded in (a
//! face point is the average of its face's vertices, so edge and vertex points depend on
//! parent vertices only), duplicate columns merged and zero weights dropped. Applying it
//! does no topology work and no mask computation. The last levels go further: over
//! regular quads refinement is uniform bicubic B-spline subdivision, so the plan stores
//! only the 16 control points of each such quad and computes the 81 vertices that three
//! more levels put on it with a fixed tensor-product kernel (see
//! `refine/plan_patches.rs`); any other face whose corners are manifold vertices
//! (extraordinary ones, triangles and n-gons of the base mesh, boundaries and sharp
//! features included) gets its vertices from a fixed matrix per shape and sharpness of
//! its 1-ring, on the points of that ring (`refine/plan_ring.rs`). Sparse rows cover the
//! rest: faces at non-manifold vertices, at semi-sharp edges under Chaikin's rule, at
//! valences above 16, and faces whose ring is shared by fewer than four faces.
//! BENCHMARKS.md ("Re-posing") has the speed against full refinement and OpenSubdiv.
//!
//! # Schemes
//! The shape-adjustable scheme with parameter `c` ([`crate::scheme::adjustable`], which
//! gives its source) changes weights only, never the topology, numbering or sharpness
//! decay, so its refinement is linear in the positions too. The plan of mixed subdivision
//! ([`Scheme::Adjustable`]: the adjustable masks on the first `k` levels, then
//! Catmull-Clark): its sparse rows take each level's masks from that level's
//! scheme. Its patches carry over as well: on a regular grid the adjustable masks are the
//! tensor product of the curve scheme `(c/4, 1 − c/2, c/4)`, `(½, ½)`, which has the cubic
//! B-spline's support, so a regular patch's kernel is the same `W P Wᵀ` with `W` computed
//! from that curve rule; the phantom points across sharp sides still give the crease rule,
//! `(1 − c/2) v + (c/4)(e_a + e_b)` along the side (derived in `refine/plan_patches.rs`);
//! and a ring's matrix is computed by refining its template with the same masks. A patch
//! composes the levels it spans, each with its own scheme's rules, so it may span the last
//! adjusted levels and the first Catmull-Clark ones.
//!
//! Non-uniform subdivision ([`Scheme::Nurss`], see [`crate::nonuniform`]) is
//! linear in the (homogeneous) points too: its weights depend on the knot intervals, which
//! refinement computes level by level from the base mesh's, never on the positions. Its
//! plan is sparse rows on every level, each the row of `refine::nurss`'s masks (the same
//! weights `refine::nurss::interpolate_nurss` applies, computed once per
//! level with face points and edge midpoints expanded into parent vertices). No patch
//! kernel applies: with unequal intervals the regular grid is a non-uniform B-spline, whose
//! weights vary from quad to quad.
//!
//! # Storage
//! Most rows share their weights with many others: every smooth edge point between two
//! quads has the same six weights, every smooth valence-4 vertex point the same nine. Each
//! distinct weight vector (a *class*) is stored once; a row is its class id and its columns:
//!
//! - per weight: one `u32` column (**4 bytes**);
//! - per row (child vertex): one `u32` class id (**4 bytes**);
//! - per block of 1024 rows: one `usize` (where the block's columns start);
//! - per class: its runs of equal weights, 16 bytes each (an `f64` and a count). Typical
//!   meshes have a few dozen classes per level; there are as many as rows only if no two
//!   rows share weights (say, with many distinct fractional sharpness values), and then a
//!   weight costs up to 20 bytes.
//!
//! A level of a quad mesh has about 6.2 weights per row (face points 4, smooth edge
//! points 6, valence-4 vertex points 9), i.e. about 29 bytes per vertex of each level.
//! A patch costs 64 bytes of control indices and 4 bytes per grid point (81 for a
//! depth-3 patch, of which it writes 64 on average), about 6 bytes per output vertex. A
//! patch with phantom points (at a boundary or crease) stores its 16 cells instead, 896
//! bytes; a ring patch 4 bytes per point of its ring (`2n + 8` for a quad with one corner
//! of valence `n`) and 4 bytes per vertex on it (81 on a quad at depth 3, padded to whole
//! groups of eight; 61 on a triangle, padded to 72 by fours of the faces that can own
//! them, see `refine/plan_ring.rs`, and 217 at depth 4); its ring's matrix is stored once.
//!
//! # Accuracy
//! The plan computes the same linear map as [`interpolate`](super::interpolate), but sums
//! in a different order (folded face points, merged columns), so its results agree with
//! [`subdivide`](fn@crate::subdivide) to rounding, not bit for bit: within 1e-14 of the size
//! of the mesh (its bounding-box diagonal) on all of OpenSubdiv's regression shapes at
//! levels 1–3 (`tests/integration/replay.rs`). Merged weights are summed with their
//! rounding errors, and each row adds its smallest terms first, so that a valence-360 pole
//! is as accurate as elsewhere. The patches' kernel rounds like a row of 16 terms (after
//! one more rounding for phantom points; dyadic weights, 8 multiply-adds per vertex), a
//! ring patch like a row of up to 64 terms (its matrix itself rounded once per entry);
//! multiply-adds are fused where the processor has FMA, so the last bits can differ
//! between processors with and without it. The result does not depend on the number of
//! threads.

use std::collections::HashMap;
use std::hash::BuildHasherDefault;

use crate::hash::FxHasher;
use std::ops::Range;

use rayon::prelude::*;

use super::loop_::check_triangles;
use super::nurss::{child_knots, NurssKnots, NurssMasks};
use super::plan_patches::{
    Claims, PatchLayer, BASE_RING_DEPTH, BILINEAR_DEPTH, LOOP_DEPTH, QUAD_DEPTH,
};
use super::topology::{refine_topology, run, split_pieces};
use super::uniform::{check_size, Steps};
use super::Error;
use crate::mesh::{
    MeshError, Options, PolyMesh, Rule, Topology, TopologyWarning, TriangleSubdivision,
};
use crate::scheme::adjustable::Mixed;
use crate::scheme::catmark::{self, VertexContext, VertexMask};
use crate::scheme::loop_::Loop;
use crate::scheme::{Bilinear, Rules, Scheme};

/// Rows per block: the unit of parallel work when applying a step, and of building it.
const BLOCK: usize = 1024;
/// Below this many rows a step is built and applied on the calling thread.
const PAR_MIN_ROWS: usize = 16 * 1024;

/// A precomputed map from base-level values (positions, or any `[f64; D]` primvar) to the
/// values at the vertices of uniform refinement level `levels`: a chain of sparse matrices,
/// one per level (see the module documentation for the layout).
///
/// ```
/// use subsurf::mesh::{Options, PolyMesh};
/// use subsurf::refine::RefinePlan;
/// use subsurf::{subdivide, Scheme, SubdivideOptions};
///
/// let mut quad = PolyMesh::from_faces(
///     vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
///     &[[0u32, 1, 2, 3]],
/// ).unwrap();
/// let plan = RefinePlan::new(&quad, Scheme::CatmullClark, Options::default(), 3).unwrap();
/// // Move a corner up: re-posing costs one sparse product per level.
/// quad.positions_mut()[2][2] = 1.0;
/// let moved = plan.apply(quad.positions());
/// let full = subdivide(&quad, &SubdivideOptions { levels: 3, ..Default::default() }).unwrap();
/// assert_eq!(moved.len(), plan.num_vertices());
/// for (a, b) in moved.iter().zip(full.mesh.positions()) {
///     assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-14));
/// }
/// ```
///
/// # Cost
/// Building a plan refines the topology once (as [`subdivide`](fn@crate::subdivide) does),
/// computes every mask of the sparse rows once, finds the patches and builds one matrix
/// per shape of ring: a few times the cost of one `subdivide`, in parallel like it.
/// Applying it does no topology work and no mask computation: the first levels are sparse
/// products, which read 4 bytes per weight and gather the parent values; the last two or
/// three levels are the patch kernels, which read 16 control points (or a face's ring) and
/// write the vertices on their face. Each output vertex is written once. BENCHMARKS.md
/// ("Re-posing") has the measured build and apply times against `subdivide` and
/// OpenSubdiv.
///
/// The plan covers positions of every vertex of the last level, in
/// [`subdivide`](fn@crate::subdivide)'s order (including vertices used only by hole faces);
/// it does not move them to the limit surface.
#[derive(Clone, Debug)]
pub struct RefinePlan {
    /// The levels computed in full, from the base on.
    steps: Vec<Step>,
    /// The last levels, by patches and sparse rows (see [`Tail`]).
    tail: Option<Tail>,
    num_base: usize,
    /// Refinement levels (`steps` and the tail's).
    levels: u32,
    warnings: Vec<TopologyWarning>,
}

/// The last `d` levels of a plan (`d` = [`QUAD_DEPTH`], or fewer for fewer levels;
/// [`BASE_RING_DEPTH`] for four levels of a mesh with faces that are not quads),
/// from the values of level `a = L − d` (the last fully computed one):
/// - [`PatchLayer`]s write the output vertices over the patches (regular and edge quads,
///   ring patches) of levels `a` (depth
///   `d`), `a + 1` (depth `d − 1`), … (depth ≥ 2), each output vertex at most once;
/// - the other output vertices are sparse rows on level `L − 1`, whose rows are needed
///   only at some of its vertices: `subsets[s − 1]` computes level `a + s` at the vertices
///   that later subsets and patches read (compact, in increasing order); the last one
///   computes the remaining output vertices `out_rows`.
#[derive(Clone, Debug)]
struct Tail {
    subsets: Vec<Step>,
    out_rows: Vec<u32>,
    layers: Vec<PatchLayer>,
    num_out: usize,
}

/// One level's sparse matrix: child vertex `i` = Σ weights × parent vertices.
#[derive(Clone, Debug)]
struct Step {
    /// Weight class of each row (child vertex).
    row_class: Vec<u32>,
    /// The parent vertex of each weight, row after row.
    cols: Vec<u32>,
    /// Index in `cols` of the first weight of each block of `BLOCK` rows, and the total.
    block_starts: Vec<usize>,
    /// The weights of class `c` are `class_groups[class_offsets[c]..class_offsets[c + 1]]`:
    /// runs of equal weights, each as (weight, number of columns), so that equal-weight
    /// parent values are summed first and multiplied once.
    class_offsets: Vec<u32>,
    class_groups: Vec<(f64, u32)>,
}

/// Scratch buffers for [`RefinePlan::apply_into`] (the intermediate levels), kept between
/// calls so that re-posing allocates nothing once they have grown.
#[derive(Clone, Debug, Default)]
pub struct PlanScratch<const D: usize = 3> {
    a: Vec<[f64; D]>,
    b: Vec<[f64; D]>,
    tail: Vec<Vec<[f64; D]>>,
}

impl RefinePlan {
    /// Builds the plan that maps the positions of `mesh` (or any values at its vertices)
    /// to those of its uniform refinement to `levels` with `scheme`, the rules' `options`
    /// and the mesh's tags, exactly as [`subdivide`](fn@crate::subdivide) would refine it
    /// (see "Schemes" in the module documentation for how each scheme is stored).
    ///
    /// With [`Scheme::Nurss`], a mesh with weights (`t weight` tags) is rational: NURSS
    /// refines its homogeneous points `(w x, w y, w z, w)`, and so must the plan; divide by
    /// the last coordinate after applying it ([`Reposer`](crate::Reposer) does both).
    ///
    /// ```
    /// use subsurf::mesh::{Options, PolyMesh};
    /// use subsurf::refine::RefinePlan;
    /// use subsurf::scheme::Adjustable;
    /// use subsurf::{subdivide, Mixed, Scheme, SubdivideOptions};
    ///
    /// let mut quad = PolyMesh::from_faces(
    ///     vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
    ///     &[[0u32, 1, 2, 3]],
    /// )?;
    /// // c = 0.3 for the first two of four levels, then Catmull-Clark.
    /// let scheme = Scheme::Adjustable(Mixed { scheme: Adjustable::new(0.3)?, steps: 2 });
    /// let plan = RefinePlan::new(&quad, scheme, Options::default(), 4)?;
    /// quad.positions_mut()[2][2] = 1.0;
    /// let moved = plan.apply(quad.positions());
    /// let opts = SubdivideOptions { levels: 4, scheme, ..Default::default() };
    /// let full = subdivide(&quad, &opts)?;
    /// for (a, b) in moved.iter().zip(full.mesh.positions()) {
    ///     assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-14));
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`Error::Mesh`] for an invalid mesh or tags, or when the last level would exceed
    /// 32-bit indices (and for a face that is not a triangle with Loop);
    /// [`Error::Nurss`] for bad knot tags or semi-sharp creases with NURSS.
    pub fn new(
        mesh: &PolyMesh,
        scheme: Scheme,
        options: Options,
        levels: u32,
    ) -> Result<Self, Error> {
        match Steps::of(scheme) {
            Some(steps) => Ok(Self::build(mesh, options, levels, u32::MAX, steps)?),
            None => Ok(super::nurss::plan(mesh, options, levels)?),
        }
    }

    /// The plan of NURSS refinement from the complete level `level` (the base level of a
    /// [`Nurss`](crate::nonuniform::Nurss), whose warnings are `warnings`) with the intervals
    /// `knots`, `levels` times: sparse rows of [`NurssMasks`] on every level
    /// ([`new`](Self::new) checks the mesh and reads its tags).
    pub(crate) fn from_nurss(
        mut level: Topology,
        mut knots: NurssKnots,
        options: Options,
        levels: u32,
        warnings: Vec<TopologyWarning>,
    ) -> Self {
        let num_base = level.num_vertices();
        let mut steps = Vec::with_capacity(levels as usize);
        for l in 1..=levels {
            let masks = NurssMasks::new(&level, &knots);
            // A vertex per parent vertex, face and edge (`refine_topology`'s numbering).
            let rows = level.num_vertices() + level.num_faces() + level.num_edges();
            let p = &level;
            steps.push(Step::from_rows(rows, None, |cv, s| {
                masks.row(p, cv, |v, w| s.row.add(v, w))
            }));
            drop(masks);
            if l < levels {
                knots = child_knots(&level, &knots);
                level = refine_topology(&level, &options, true);
            }
        }
        Self {
            steps,
            tail: None,
            num_base,
            levels,
            warnings,
        }
    }

    /// [`new`](Self::new) with patches of at most `max_depth` levels (none below 2; see
    /// [`tail_depth`] for each scheme's), refined with `steps` (the adjustable masks on the
    /// first levels that a [`Steps::Family`] says; Loop's on the triangle split; bilinear's
    /// with the topology options of [`Steps::topology_options`]).
    pub(super) fn build(
        mesh: &PolyMesh,
        options: Options,
        levels: u32,
        max_depth: u32,
        steps: Steps,
    ) -> Result<Self, MeshError> {
        if steps == Steps::Loop {
            check_triangles(mesh)?;
        }
        mesh.validate()?;
        check_size(mesh, steps, levels)?;
        let options = steps.topology_options(&options);
        let (mut level, warnings) = Topology::from_mesh(mesh, &options)?;
        let depth = tail_depth(mesh, steps, levels, max_depth);
        let full = levels - depth;
        let mut rows = Vec::with_capacity(full as usize);
        for l in 1..=full {
            let child = steps.refine(&level, &options, l < levels);
            rows.push(Step::of_steps(&level, &child, &options, None, steps, l));
            level = child;
        }
        let tail = (depth > 0).then(|| {
            let mut tops = vec![level];
            for l in full + 1..=levels {
                let child = steps.refine(&tops[tops.len() - 1], &options, l < levels);
                tops.push(child);
            }
            Tail::build(&tops, &options, steps.after(full))
        });
        Ok(Self {
            steps: rows,
            tail,
            num_base: mesh.num_vertices(),
            levels,
            warnings,
        })
    }

    /// Estimated peak memory in bytes of building a plan for `mesh` to `levels` with
    /// `scheme` and applying it once, saturating at `u64::MAX`: twice [`estimate_memory`]
    /// of that scheme's refinement to the same level (NURSS: Catmull-Clark's; building
    /// holds the last four levels at once; the measured peak of `subsurf bench --replay`
    /// on `catmark_bishop` to level 6 is ~120 bytes per output face, the estimate 320; a
    /// Loop or bilinear plan, sparse rows of about 5 weights on every level, holds about
    /// 30 bytes per output vertex). Check it before [`new`](Self::new) to refuse a level
    /// that would not fit instead of failing to allocate.
    ///
    /// [`estimate_memory`]: crate::estimate_memory
    pub fn estimate_memory(mesh: &PolyMesh, scheme: Scheme, levels: u32) -> u64 {
        let steps = Steps::of(scheme).unwrap_or(Steps::Family(Mixed::CATMULL_CLARK));
        super::uniform::estimate_uniform(mesh, steps, levels, false).saturating_mul(2)
    }

    /// Number of patches: faces whose last levels the plan computes by the bicubic kernel
    /// or by the matrix of their 1-ring (module docs).
    pub fn num_patches(&self) -> usize {
        self.tail
            .as_ref()
            .map_or(0, |t| t.layers.iter().map(PatchLayer::len).sum())
    }

    /// Number of base vertices the plan expects.
    pub fn num_base_vertices(&self) -> usize {
        self.num_base
    }

    /// Number of vertices it produces (all vertices of the last level).
    pub fn num_vertices(&self) -> usize {
        match (&self.tail, self.steps.last()) {
            (Some(tail), _) => tail.num_out,
            (None, Some(s)) => s.row_class.len(),
            (None, None) => self.num_base,
        }
    }

    /// Number of refinement levels.
    pub fn levels(&self) -> u32 {
        self.levels
    }

    /// Number of stored weights (columns) over all levels.
    pub fn num_weights(&self) -> usize {
        self.all_steps().map(|s| s.cols.len()).sum()
    }

    /// Bytes held by the plan's arrays.
    pub fn memory_bytes(&self) -> usize {
        let steps: usize = self.all_steps().map(Step::memory_bytes).sum();
        steps
            + self.tail.as_ref().map_or(0, |t| {
                4 * t.out_rows.len() + t.layers.iter().map(PatchLayer::memory_bytes).sum::<usize>()
            })
    }

    /// The sparse steps, full and subset.
    fn all_steps(&self) -> impl Iterator<Item = &Step> {
        self.steps
            .iter()
            .chain(self.tail.iter().flat_map(|t| &t.subsets))
    }

    /// Warnings about the base mesh (ignored tags, non-manifold elements).
    pub fn warnings(&self) -> &[TopologyWarning] {
        &self.warnings
    }

    /// The values at the last level's vertices, given those at the base vertices.
    ///
    /// # Panics
    /// If `base.len() != self.num_base_vertices()`.
    pub fn apply<const D: usize>(&self, base: &[[f64; D]]) -> Vec<[f64; D]> {
        let mut out = Vec::new();
        self.apply_into(base, &mut out, &mut PlanScratch::default());
        out
    }

    /// [`apply`](Self::apply) into `out` (resized to [`num_vertices`](Self::num_vertices)),
    /// with the intermediate levels in `scratch`: after the first call with the same
    /// `out` and `scratch`, nothing is allocated (`tests/plan_no_alloc.rs`).
    ///
    /// # Panics
    /// If `base.len() != self.num_base_vertices()`.
    pub fn apply_into<const D: usize>(
        &self,
        base: &[[f64; D]],
        out: &mut Vec<[f64; D]>,
        scratch: &mut PlanScratch<D>,
    ) {
        assert_eq!(
            base.len(),
            self.num_base,
            "the plan expects {} base values",
            self.num_base
        );
        let n = self.steps.len();
        if n == 0 && self.tail.is_none() {
            out.clear();
            out.extend_from_slice(base);
            return;
        }
        let (mut cur, mut spare) = (
            std::mem::take(&mut scratch.a),
            std::mem::take(&mut scratch.b),
        );
        // Both buffers take every level in turn: room for the largest from the first call
        // on, so that later calls allocate nothing (whatever the parity of the levels).
        let in_scratch = if self.tail.is_some() { n } else { n - 1 };
        let widest = self.steps[..in_scratch]
            .iter()
            .map(|s| s.row_class.len())
            .max();
        for v in [&mut cur, &mut spare] {
            v.reserve(widest.unwrap_or(0).saturating_sub(v.len()));
        }
        for (i, step) in self.steps.iter().enumerate() {
            let src: &[[f64; D]] = if i == 0 { base } else { &cur };
            let last = i + 1 == n && self.tail.is_none();
            let dst = if last { &mut *out } else { &mut spare };
            set_len(dst, step.row_class.len());
            step.apply(src, dst);
            if !last {
                std::mem::swap(&mut cur, &mut spare);
            }
        }
        if let Some(tail) = &self.tail {
            let src: &[[f64; D]] = if n == 0 { base } else { &cur };
            set_len(out, tail.num_out);
            tail.apply(src, out, &mut scratch.tail);
        }
        scratch.a = cur;
        scratch.b = spare;
    }
}

/// Levels of the tail of a plan of `levels` levels of `mesh` refined with `steps`, its
/// patches of at most `max_depth` levels (0: sparse rows only; never 1):
/// - the Catmull-Clark family: [`BASE_RING_DEPTH`] when the plan refines exactly that many
///   levels of a mesh with faces that are not quads, else at most [`QUAD_DEPTH`];
/// - Loop: at most [`LOOP_DEPTH`] (ring patches of triangles, `refine/plan_ring.rs`);
/// - bilinear: at most [`BILINEAR_DEPTH`] (a matrix per face size on the face's corners).
fn tail_depth(mesh: &PolyMesh, steps: Steps, levels: u32, max_depth: u32) -> u32 {
    if levels < 2 || max_depth < 2 {
        return 0;
    }
    let most = match steps {
        Steps::Family(_)
            if levels == BASE_RING_DEPTH
                && max_depth >= BASE_RING_DEPTH
                && (0..mesh.num_faces()).any(|f| mesh.face(f).len() != 4) =>
        {
            BASE_RING_DEPTH
        }
        Steps::Family(_) => QUAD_DEPTH,
        Steps::Loop => LOOP_DEPTH,
        Steps::Bilinear => BILINEAR_DEPTH,
    };
    most.min(max_depth).min(levels)
}

impl Tail {
    /// The tail that refines `tops[0]` to `tops[d]` (`d = tops.len() − 1 ≥ 2`), `tops`
    /// being consecutive levels, step `s` (from 1) with the masks of step `s` of `steps`.
    fn build(tops: &[Topology], options: &Options, steps: Steps) -> Tail {
        let d = tops.len() - 1;
        let mut claims = Claims::new(tops[d].num_vertices());
        let mut layers: Vec<PatchLayer> = (2..=d)
            .rev()
            .map(|depth| {
                let start = d - depth;
                let steps = steps.after(start as u32);
                PatchLayer::build(&tops[start..d], start, &mut claims, options, steps)
            })
            .collect();
        // From the last level down: the rows that are needed, and the vertices they read.
        let mut rows = claims.unclaimed();
        let out_rows = rows.clone();
        let mut subsets = Vec::with_capacity(d);
        for s in (1..=d).rev() {
            let (p, c) = (&tops[s - 1], &tops[s]);
            let mut step = Step::of_steps(p, c, options, Some(&rows), steps, s as u32);
            if s > 1 {
                let mut used = vec![false; p.num_vertices()];
                for &col in &step.cols {
                    used[col as usize] = true;
                }
                let readers = layers.iter().filter(|l| l.source == s - 1);
                for layer in readers {
                    for col in layer.control_vertices() {
                        used[col as usize] = true;
                    }
                }
                let mut map = vec![u32::MAX; used.len()];
                rows.clear();
                for (v, _) in used.iter().enumerate().filter(|&(_, &u)| u) {
                    map[v] = rows.len() as u32;
                    rows.push(v as u32);
                }
                step.remap_cols(&map);
                for layer in layers.iter_mut().filter(|l| l.source == s - 1) {
                    layer.remap(&map);
                }
            }
            subsets.push(step);
        }
        subsets.reverse();
        Tail {
            subsets,
            out_rows,
            layers,
            num_out: tops[d].num_vertices(),
        }
    }

    /// Writes the last level into `out` (of length `num_out`) from the values `src` of
    /// the first level of the tail, with the subset levels in `bufs`.
    fn apply<const D: usize>(
        &self,
        src: &[[f64; D]],
        out: &mut [[f64; D]],
        bufs: &mut Vec<Vec<[f64; D]>>,
    ) {
        bufs.resize_with(self.subsets.len(), Vec::new);
        for (s, step) in self.subsets.iter().enumerate() {
            let (done, rest) = bufs.split_at_mut(s);
            let from: &[[f64; D]] = if s == 0 { src } else { &done[s - 1] };
            set_len(&mut rest[0], step.row_class.len());
            step.apply(from, &mut rest[0]);
        }
        if let Some(last) = bufs.last() {
            for (&r, v) in self.out_rows.iter().zip(last) {
                out[r as usize] = *v;
            }
        }
        for layer in &self.layers {
            let from: &[[f64; D]] = if layer.source == 0 {
                src
            } else {
                &bufs[layer.source - 1]
            };
            layer.apply(from, out);
        }
    }
}

#[inline(always)]
fn add<const D: usize>(a: [f64; D], b: [f64; D]) -> [f64; D] {
    std::array::from_fn(|k| a[k] + b[k])
}

#[inline(always)]
fn scaled<const D: usize>(a: [f64; D], w: f64) -> [f64; D] {
    a.map(|x| w * x)
}

/// The sums of `src` over the next `lens[0]`, `lens[1]`, … columns from `*at` on.
#[inline(always)]
fn sums<const D: usize, const G: usize>(
    src: &[[f64; D]],
    cols: &[u32],
    at: &mut usize,
    lens: [usize; G],
) -> [[f64; D]; G] {
    let mut out = [[0.0; D]; G];
    for (o, n) in out.iter_mut().zip(lens) {
        let cs = &cols[*at..*at + n];
        *at += n;
        let mut sum = src[cs[0] as usize];
        for &c in &cs[1..] {
            sum = add(sum, src[c as usize]);
        }
        *o = sum;
    }
    out
}

/// Makes `v` hold `n` values (whatever they are: they are all overwritten), without
/// writing them when it has to grow (fresh zeroed memory is faulted in by the writers).
fn set_len<const D: usize>(v: &mut Vec<[f64; D]>, n: usize) {
    if v.len() != n {
        if v.capacity() >= n {
            v.resize(n, [0.0; D]);
        } else {
            *v = vec![[0.0; D]; n];
        }
    }
}

impl Step {
    /// `dst = S × src`.
    fn apply<const D: usize>(&self, src: &[[f64; D]], dst: &mut [[f64; D]]) {
        let body = |(b, out): (usize, &mut [[f64; D]])| {
            let mut at = self.block_starts[b];
            let classes = &self.row_class[b * BLOCK..b * BLOCK + out.len()];
            for (o, &c) in out.iter_mut().zip(classes) {
                let c = c as usize;
                let groups = &self.class_groups
                    [self.class_offsets[c] as usize..self.class_offsets[c + 1] as usize];
                // The shapes of almost all rows of quad meshes, unrolled: face points,
                // smooth edge points, regular vertex points.
                *o = match *groups {
                    [(w0, 4)] => {
                        let [s0] = sums(src, &self.cols, &mut at, [4]);
                        scaled(s0, w0)
                    }
                    [(w0, 4), (w1, 2)] => {
                        let [s0, s1] = sums(src, &self.cols, &mut at, [4, 2]);
                        add(scaled(s0, w0), scaled(s1, w1))
                    }
                    [(w0, 4), (w1, 4), (w2, 1)] => {
                        let [s0, s1, s2] = sums(src, &self.cols, &mut at, [4, 4, 1]);
                        add(add(scaled(s0, w0), scaled(s1, w1)), scaled(s2, w2))
                    }
                    _ => {
                        let mut acc = [0.0; D];
                        for &(w, n) in groups {
                            let cols = &self.cols[at..at + n as usize];
                            at += n as usize;
                            let mut sum = src[cols[0] as usize];
                            for &col in &cols[1..] {
                                sum = add(sum, src[col as usize]);
                            }
                            acc = add(acc, scaled(sum, w));
                        }
                        acc
                    }
                };
            }
        };
        if dst.len() < PAR_MIN_ROWS {
            dst.chunks_mut(BLOCK).enumerate().for_each(body);
        } else {
            dst.par_chunks_mut(BLOCK).enumerate().for_each(body);
        }
    }

    /// Bytes held.
    fn memory_bytes(&self) -> usize {
        4 * self.row_class.len()
            + 4 * self.cols.len()
            + std::mem::size_of::<usize>() * self.block_starts.len()
            + 4 * self.class_offsets.len()
            + 16 * self.class_groups.len()
    }

    /// Renumbers the columns through `map`.
    fn remap_cols(&mut self, map: &[u32]) {
        for c in &mut self.cols {
            *c = map[*c as usize];
        }
    }

    /// [`Step::build`] with the masks of step `s` (from 1) of `steps`.
    fn of_steps(
        p: &Topology,
        c: &Topology,
        options: &Options,
        only: Option<&[u32]>,
        steps: Steps,
        s: u32,
    ) -> Step {
        match steps {
            Steps::Family(mixed) => Step::build(p, c, options, only, mixed.step(s)),
            Steps::Loop => Step::build(p, c, options, only, Loop),
            Steps::Bilinear => Step::build(p, c, options, only, Bilinear),
        }
    }

    /// The weights of the vertices `only` of `c` (the refinement of `p`; all of them when
    /// `None`) on the vertices of `p`, one row per vertex in that order, with the masks of
    /// `rules` (Catmull-Clark's when it is [`Adjustable::CATMULL_CLARK`](crate::scheme::adjustable::Adjustable::CATMULL_CLARK); Loop's on the
    /// triangle split).
    fn build<R: Rules>(
        p: &Topology,
        c: &Topology,
        options: &Options,
        only: Option<&[u32]>,
        rules: R,
    ) -> Step {
        let rows = only.map_or(c.num_vertices(), <[u32]>::len);
        Step::from_rows(rows, only, |cv, scratch| {
            stencil(p, c, options, rules, cv, scratch)
        })
    }

    /// The step of `rows` child vertices (`only`, or `0..rows`), the row of child vertex
    /// `cv` added to `scratch.row` by `stencil(cv, scratch)`.
    fn from_rows(
        rows: usize,
        only: Option<&[u32]>,
        stencil: impl Fn(usize, &mut RowScratch) + Sync,
    ) -> Step {
        let nblocks = rows.div_ceil(BLOCK);
        let make = |scratch: &mut RowScratch, b: usize| {
            let mut block = Block::new(BLOCK.min(rows - b * BLOCK));
            for r in b * BLOCK..((b + 1) * BLOCK).min(rows) {
                let cv = only.map_or(r, |o| o[r] as usize);
                scratch.row.clear();
                stencil(cv, scratch);
                block.push(&scratch.row, &mut scratch.sorted, &mut scratch.bits);
            }
            block
        };
        let mut blocks: Vec<Block> = if rows < PAR_MIN_ROWS {
            let mut scratch = RowScratch::default();
            (0..nblocks).map(|b| make(&mut scratch, b)).collect()
        } else {
            (0..nblocks)
                .into_par_iter()
                .map_init(RowScratch::default, make)
                .collect()
        };

        // Number the classes of all blocks, in order, and renumber the rows.
        let mut ids = ClassIds::default();
        let mut class_offsets = vec![0u32];
        let mut class_groups: Vec<(f64, u32)> = Vec::new();
        let remaps: Vec<Vec<u32>> = blocks
            .iter_mut()
            .map(|block| {
                std::mem::take(&mut block.classes)
                    .into_iter()
                    .map(|bits| {
                        *ids.entry(bits).or_insert_with_key(|bits| {
                            push_groups(&mut class_groups, bits);
                            class_offsets.push(class_groups.len() as u32);
                            (class_offsets.len() - 2) as u32
                        })
                    })
                    .collect()
            })
            .collect();

        // Concatenate the blocks.
        let mut block_starts = Vec::with_capacity(nblocks + 1);
        block_starts.push(0);
        for block in &blocks {
            block_starts.push(block_starts.last().unwrap() + block.cols.len());
        }
        let mut row_class = vec![0u32; rows];
        let mut cols = vec![0u32; *block_starts.last().unwrap()];
        let ranges: Vec<Range<usize>> = if rows < PAR_MIN_ROWS {
            std::iter::once(0..nblocks).collect()
        } else {
            (0..nblocks).map(|b| b..b + 1).collect()
        };
        let rc = split_pieces(&mut row_class, &ranges, |b| b * BLOCK);
        let cs = split_pieces(&mut cols, &ranges, |b| block_starts[b]);
        let items: Vec<_> = ranges.into_iter().zip(rc).zip(cs).collect();
        run(items, |((range, rc), cs)| {
            let (mut r, mut k) = (0, 0);
            for b in range {
                let block = &blocks[b];
                for (o, &local) in rc[r..].iter_mut().zip(&block.row_class) {
                    *o = remaps[b][local as usize];
                }
                cs[k..k + block.cols.len()].copy_from_slice(&block.cols);
                r += block.row_class.len();
                k += block.cols.len();
            }
        });
        Step {
            row_class,
            cols,
            block_starts,
            class_offsets,
            class_groups,
        }
    }
}

/// Appends the runs of equal weights of `bits` (weights as bits) to `groups`.
fn push_groups(groups: &mut Vec<(f64, u32)>, bits: &[u64]) {
    let start = groups.len();
    for &b in bits {
        let len = groups.len();
        if len > start && groups[len - 1].0.to_bits() == b {
            groups[len - 1].1 += 1;
        } else {
            groups.push((f64::from_bits(b), 1));
        }
    }
}

/// The rows of one block, with classes numbered within the block.
struct Block {
    row_class: Vec<u32>,
    cols: Vec<u32>,
    /// Weights (as bits) of each local class.
    classes: Vec<Vec<u64>>,
    ids: ClassIds,
    /// The class of the previous row (the next one often has the same).
    last: u32,
}

impl Block {
    fn new(rows: usize) -> Self {
        Block {
            row_class: Vec::with_capacity(rows),
            cols: Vec::with_capacity(8 * rows),
            classes: Vec::new(),
            ids: ClassIds::default(),
            last: 0,
        }
    }

    /// Appends `row` (zero weights dropped, smallest weights first: the many small terms of
    /// a high-valence vertex are summed before its own large one is added, which keeps the
    /// rounding error of `apply` as small as that of `interpolate`).
    fn push(&mut self, row: &Row, scratch: &mut Vec<(f64, u32)>, bits: &mut Vec<u64>) {
        scratch.clear();
        scratch.extend(
            (0..row.cols.len())
                .map(|i| (row.weight(i), row.cols[i]))
                .filter(|&(w, _)| w != 0.0),
        );
        scratch.sort_by(|a, b| a.0.abs().total_cmp(&b.0.abs()));
        bits.clear();
        bits.extend(scratch.iter().map(|&(w, _)| w.to_bits()));
        self.cols.extend(scratch.iter().map(|&(_, c)| c));
        let id = match self.classes.get(self.last as usize) {
            Some(last) if last == bits => self.last,
            _ => match self.ids.get(bits.as_slice()) {
                Some(&id) => id,
                None => {
                    let id = self.classes.len() as u32;
                    self.classes.push(bits.clone());
                    self.ids.insert(bits.clone(), id);
                    id
                }
            },
        };
        self.last = id;
        self.row_class.push(id);
    }
}

/// Class numbers by weights (as bits).
type ClassIds = HashMap<Vec<u64>, u32, BuildHasherDefault<FxHasher>>;

/// A sparse row being built: weights on parent vertices, one entry per vertex. A weight
/// may be the sum of hundreds of contributions (the vertex itself in every face around a
/// pole), so each is accumulated with its rounding error (Knuth's two-sum) and rounded
/// once at the end.
#[derive(Default)]
struct Row {
    cols: Vec<u32>,
    ws: Vec<(f64, f64)>,
}

impl Row {
    fn clear(&mut self) {
        self.cols.clear();
        self.ws.clear();
    }

    #[inline]
    fn add(&mut self, col: u32, w: f64) {
        match self.cols.iter().position(|&c| c == col) {
            Some(i) => {
                let (a, err) = self.ws[i];
                let s = a + w;
                let bb = s - a;
                self.ws[i] = (s, err + ((a - (s - bb)) + (w - bb)));
            }
            None => {
                self.cols.push(col);
                self.ws.push((w, 0.0));
            }
        }
    }

    /// The weight of entry `i`.
    #[inline]
    fn weight(&self, i: usize) -> f64 {
        self.ws[i].0 + self.ws[i].1
    }

    /// Adds `w ×` the face point of `f`, its vertices taken from corner `start` on (so that
    /// rows of the same shape list their weights in the same order).
    fn add_face(&mut self, p: &Topology, f: usize, start: usize, w: f64) {
        let fv = p.face_vertices(f);
        let n = fv.len();
        let wf = w * catmark::face_point_weight(n);
        for k in 0..n {
            self.add(fv[(start + k) % n], wf);
        }
    }
}

#[derive(Default)]
struct RowScratch {
    row: Row,
    sorted: Vec<(f64, u32)>,
    bits: Vec<u64>,
    mask: VertexMask,
    /// The child-rule mask of blends.
    child_mask: VertexMask,
    pe: Vec<f32>,
    ce: Vec<f32>,
}

/// Rows of the refinement of `p` into `c` by `rules` (`c` is [`refine_topology`]'s
/// refinement of `p` for the Catmull-Clark family, [`refine_tri_topology`]'s triangle split
/// for Loop) as sparse weights: for each vertex of `verts` (vertices of `c`) in order,
/// `row(cols, weights)` with its weights on the vertices of `p`, each vertex once, zero
/// weights included. These are the masks [`interpolate`](super::interpolate) (with Loop,
/// [`interpolate_loop`](super::interpolate_loop)) applies (each weight summed with its
/// rounding error carried, as [`RefinePlan`] does), so applying them gives its values to
/// rounding, in `O(weights)` time where interpolating unit vectors would take
/// `O(vertices²)`.
///
/// [`refine_tri_topology`]: super::refine_tri_topology
pub(crate) fn refinement_rows<R: Rules>(
    p: &Topology,
    c: &Topology,
    options: &Options,
    rules: R,
    verts: impl IntoIterator<Item = u32>,
    mut row: impl FnMut(&[u32], &[f64]),
) {
    let mut scratch = RowScratch::default();
    let mut weights = Vec::new();
    for cv in verts {
        scratch.row.clear();
        stencil(p, c, options, rules, cv as usize, &mut scratch);
        let r = &scratch.row;
        weights.clear();
        weights.extend((0..r.cols.len()).map(|i| r.weight(i)));
        row(&r.cols, &weights);
    }
}

/// The row of child vertex `cv`: the masks of [`interpolate_with`](super::interpolate_with)
/// with `rules` ([`Adjustable::CATMULL_CLARK`](crate::scheme::adjustable::Adjustable::CATMULL_CLARK)'s are Catmull-Clark's bit for bit), with
/// face points expanded into their vertices; with a scheme that splits triangles (Loop,
/// `c` the triangle split of `p`), those of `interpolate_loop`: no face points, an edge
/// point's face weights on the vertices opposite the edge.
fn stencil<R: Rules>(
    p: &Topology,
    c: &Topology,
    options: &Options,
    rules: R,
    cv: usize,
    scratch: &mut RowScratch,
) {
    let nv = p.num_vertices();
    let nf = if rules.splits_triangles() {
        0
    } else {
        p.num_faces()
    };
    let row = &mut scratch.row;
    if cv < nv {
        vertex_stencil(p, c, options, rules, cv, scratch);
    } else if cv < nv + nf {
        row.add_face(p, cv - nv, 0, 1.0);
    } else {
        let e = cv - nv - nf;
        let [a, b] = p.edge_verts[e];
        let faces = p.edge_face_list(e);
        let locals = &p.edge_face_local[p.edge_face_offsets[e] as usize..];
        let sharp = p.edge_sharpness[e];
        // The edge's share of face `f` (the face's local edge `i`): its face point, or
        // with Loop the vertex opposite the edge.
        let add_face = |row: &mut Row, f: u32, i: u16, w: f64| {
            if rules.splits_triangles() {
                row.add(p.face_vertices(f as usize)[(i as usize + 2) % 3], w);
            } else {
                row.add_face(p, f as usize, i as usize, w);
            }
        };
        let tri_option =
            options.triangles == TriangleSubdivision::Smooth && !rules.splits_triangles();
        if sharp <= 0.0 && faces.len() == 2 && !tri_option {
            let m = rules.smooth_edge_mask(options, 2, [false; 2]);
            row.add(a, m.vertex);
            row.add(b, m.vertex);
            for ((&f, &i), &w) in faces.iter().zip(locals).zip(&m.faces) {
                add_face(row, f, i, w);
            }
        } else {
            let tri = [0, 1].map(|j| {
                tri_option
                    && faces
                        .get(j)
                        .is_some_and(|&f| p.face_vertices(f as usize).len() == 3)
            });
            let child_rule = c.vert_tags[cv].get().rule;
            let m = rules.edge_mask(options, sharp, child_rule, faces.len(), tri);
            row.add(a, m.vertex);
            row.add(b, m.vertex);
            if !m.is_crease() {
                for (j, (&f, &i)) in faces.iter().zip(locals).enumerate() {
                    let w = if j < 2 { m.faces[j] } else { m.other_faces };
                    add_face(row, f, i, w);
                }
            }
        }
    }
}

/// The row of the child of parent vertex `v` ([`stencil`]).
fn vertex_stencil<R: Rules>(
    p: &Topology,
    c: &Topology,
    options: &Options,
    rules: R,
    v: usize,
    s: &mut RowScratch,
) {
    let edges = p.vertex_edges(v);
    let faces = p.vertex_faces(v);
    let corners = p.vertex_face_locals(v);
    let ptag = p.vert_tags[v].get();
    let row = &mut s.row;
    if edges.is_empty() {
        row.add(v as u32, 1.0);
        return;
    }
    if matches!(ptag.rule, Rule::Smooth | Rule::Dart) {
        // Loop's valence is the face count (`vertex_points`), the same at the manifold
        // interior vertices that smooth rules apply to.
        let n = if rules.splits_triangles() {
            faces.len()
        } else {
            edges.len()
        };
        let (vw, ew, fw) = rules.smooth_vertex_weights(n);
        row.add(v as u32, vw);
        for x in p.vertex_neighbours(v).take(n) {
            row.add(x, ew);
        }
        if !rules.splits_triangles() {
            for (&f, &j) in faces.iter().zip(corners) {
                row.add_face(p, f as usize, j as usize, fw);
            }
        }
        return;
    }
    let sp = p.face_verts.len();
    s.pe.clear();
    s.pe.extend(edges.iter().map(|&e| p.edge_sharpness[e as usize]));
    s.ce.clear();
    s.ce.extend(
        edges
            .iter()
            .zip(p.vertex_edge_locals(v))
            .map(|(&e, &l)| c.edge_sharpness[sp + 2 * e as usize + l as usize]),
    );
    let ctx = VertexContext {
        parent_rule: ptag.rule,
        child_rule: c.vert_tags[v].get().rule,
        parent_sharpness: p.vert_sharpness[v],
        child_sharpness: c.vert_sharpness[v],
        parent_edges: &s.pe,
        child_edges: &s.ce,
        num_faces: faces.len(),
    };
    rules.vertex_mask(options.crease_method, &ctx, &mut s.mask, &mut s.child_mask);
    let mask = &s.mask;
    row.add(v as u32, mask.vertex);
    if mask.has_edges {
        for (x, &w) in p.vertex_neighbours(v).zip(&mask.edges) {
            row.add(x, w);
        }
    }
    if mask.has_faces && !rules.splits_triangles() {
        for ((&f, &j), &w) in faces.iter().zip(corners).zip(&mask.faces) {
            row.add_face(p, f as usize, j as usize, w);
        }
    }
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{BoundaryInterpolation, Corner, Crease, CreaseMethod};

    /// Catmull-Clark's steps.
    const CC: Steps = Steps::Family(Mixed::CATMULL_CLARK);

    /// `a + b` as a double-double (Knuth's two-sum).
    fn two_sum(a: f64, b: f64) -> (f64, f64) {
        let s = a + b;
        let bb = s - a;
        (s, (a - (s - bb)) + (b - bb))
    }

    fn dd_add(x: (f64, f64), y: (f64, f64)) -> (f64, f64) {
        let (s, e) = two_sum(x.0, y.0);
        two_sum(s, e + x.1 + y.1)
    }

    fn dd_mul(x: (f64, f64), w: f64) -> (f64, f64) {
        let p = x.0 * w;
        two_sum(p, x.0.mul_add(w, -p) + x.1 * w)
    }

    /// The plan applied in double-double arithmetic (its stored weights, exact sums).
    fn apply_dd(plan: &RefinePlan, base: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let mut cur: Vec<[(f64, f64); 3]> = base.iter().map(|p| p.map(|x| (x, 0.0))).collect();
        for st in &plan.steps {
            let mut at = 0;
            cur = st
                .row_class
                .iter()
                .map(|&c| {
                    let groups = &st.class_groups[st.class_offsets[c as usize] as usize
                        ..st.class_offsets[c as usize + 1] as usize];
                    let mut acc = [(0.0, 0.0); 3];
                    for &(w, n) in groups {
                        for &col in &st.cols[at..at + n as usize] {
                            for k in 0..3 {
                                acc[k] = dd_add(acc[k], dd_mul(cur[col as usize][k], w));
                            }
                        }
                        at += n as usize;
                    }
                    acc
                })
                .collect();
        }
        cur.iter().map(|p| p.map(|(hi, lo)| hi + lo)).collect()
    }

    /// Around a valence-360 pole a row has hundreds of small weights and one large one:
    /// the weights (accumulated exactly) and `apply` (small terms first) are accurate to
    /// an ulp or two, as `subdivide` is.
    #[test]
    fn high_valence_rows_are_accurate() {
        let (obj, options) = shape("catmark_pole360");
        for levels in 1..=3 {
            // Sparse rows only (patches are not near the pole; see `patches_match_rows`).
            let plan = RefinePlan::build(&obj.mesh, options, levels, 0, CC).unwrap();
            let exact = apply_dd(&plan, obj.mesh.positions());
            let got = plan.apply(obj.mesh.positions());
            let opts = crate::SubdivideOptions {
                levels,
                options,
                ..Default::default()
            };
            let sub = crate::subdivide(&obj.mesh, &opts).unwrap();
            for (i, ((a, b), c)) in got.iter().zip(sub.mesh.positions()).zip(&exact).enumerate() {
                for k in 0..3 {
                    assert!(
                        (a[k] - c[k]).abs() <= 1e-15,
                        "plan, level {levels}, vertex {i}"
                    );
                    assert!(
                        (b[k] - c[k]).abs() <= 1e-15,
                        "subdivide, level {levels}, vertex {i}"
                    );
                }
            }
        }
    }

    /// Regression shape `name` and the options of its tags.
    fn shape(name: &str) -> (crate::io::obj::ObjFile, Options) {
        let path = format!("{}/tests/shapes/osd/{name}.obj", env!("CARGO_MANIFEST_DIR"));
        let obj = crate::io::obj::read_obj(std::path::Path::new(&path)).unwrap();
        let options = obj.options.resolve(Options::default());
        (obj, options)
    }

    /// Builds plans of regression shape `name` to levels 2..=4 with patches of depth 2, 3
    /// and 4 (see [`check_mesh_patches`]).
    fn check_patches(name: &str) -> (usize, usize) {
        let (obj, options) = shape(name);
        check_mesh_patches(&obj.mesh, options, name)
    }

    /// Builds plans of `mesh` to levels 2..=4 with patches of depth 2, 3 and 4 (ring
    /// patches on the base mesh's faces that are not quads, at level 4), checks that they
    /// compute the same vertices as plans of sparse rows only (to rounding), and returns
    /// the numbers of patches with phantom points (edge patches) and of ring patches over
    /// all of them.
    fn check_mesh_patches(mesh: &PolyMesh, options: Options, name: &str) -> (usize, usize) {
        check_steps_patches(mesh, options, CC, 4, name)
    }

    /// [`check_mesh_patches`] with `steps`, to levels 2..=`max_level`, with patches of
    /// at most every depth from 2 to the deepest of any scheme ([`tail_depth`]).
    fn check_steps_patches(
        mesh: &PolyMesh,
        options: Options,
        steps: Steps,
        max_level: u32,
        name: &str,
    ) -> (usize, usize) {
        let pos = mesh.positions();
        let (lo, hi) = mesh.bounding_box().unwrap();
        let size = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
        let (mut edge_patches, mut ring_patches) = (0, 0);
        let deepest = BASE_RING_DEPTH.max(LOOP_DEPTH).max(BILINEAR_DEPTH);
        for levels in 2..=max_level {
            let rows = RefinePlan::build(mesh, options, levels, 0, steps).unwrap();
            let want = rows.apply(pos);
            for depth in 2..=deepest {
                let plan = RefinePlan::build(mesh, options, levels, depth, steps).unwrap();
                // (A face is a patch once its corners are smooth or regular: on every
                // level of a mesh without sharp features.)
                assert!(
                    levels < 4 || plan.num_patches() > 0,
                    "{name} level {levels} depth {depth}"
                );
                for layer in plan.tail.iter().flat_map(|t| &t.layers) {
                    edge_patches += layer.edge_nets.len();
                    ring_patches += layer.rings.len();
                }
                let got = plan.apply(pos);
                assert_eq!(got.len(), want.len());
                for (i, (a, b)) in got.iter().zip(&want).enumerate() {
                    let err = (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max);
                    // Both sides round differently (16-term kernel, or up to 64 terms of
                    // a ring patch, against folded sparse rows): measured at most 2.4e-15
                    // of the size (pawn, level 4).
                    assert!(
                        err <= 4e-15 * size,
                        "{name} level {levels} depth {depth} vertex {i}: {err:e}"
                    );
                }
            }
        }
        (edge_patches, ring_patches)
    }

    /// Patches compute the same vertices as the sparse rows, to rounding, at every depth,
    /// and cover most of a mesh with few extraordinary vertices.
    #[test]
    fn patches_match_rows() {
        for name in ["catmark_pawn", "catmark_torus_creases0", "catmark_bishop"] {
            check_patches(name);
            let (obj, options) = shape(name);
            let plan = RefinePlan::new(&obj.mesh, Scheme::CatmullClark, options, 4).unwrap();
            let tail = plan.tail.as_ref().unwrap();
            let rows = tail.out_rows.len() as f64 / tail.num_out as f64;
            // Measured: 9 % (pawn), 11 % (torus_creases0), 14 % (bishop) of level 4.
            assert!(rows < 0.2, "{name}: {rows} of the output in sparse rows");
        }
    }

    /// Patches with phantom points across boundaries (every boundary mode), infinitely
    /// sharp creases and corners reproduce the crease rules: the same vertices as the
    /// sparse rows.
    #[test]
    fn edge_patches_match_rows() {
        for name in [
            "catmark_edgeonly",
            "catmark_edgecorner",
            "catmark_edgenone",
            "catmark_quadstrips",
            "catmark_inf_crease1",
            "catmark_hole_test3",
        ] {
            assert!(check_patches(name).0 > 0, "{name}: no edge patches");
        }
    }

    /// Semi-sharp creases and corners that stay sharp through a patch's levels (uniform
    /// decay, sharpness at least the depth; `catmark_single_crease` has sharpness exactly
    /// 1, 2 and 5, where the last step is OpenSubdiv's transitional rule at full weight)
    /// are taken as infinitely sharp: the same vertices as the sparse rows.
    #[test]
    fn semi_sharp_patches_match_rows() {
        for name in [
            "catmark_torus_creases0",
            "catmark_single_crease",
            "catmark_cube_creases1",
            "catmark_cubes_semisharp",
        ] {
            let (edge, _) = check_patches(name);
            assert!(edge > 0, "{name}: no edge patches");
        }
        // The torus has no boundary and no infinitely sharp edge: its edge patches are
        // at the semi-sharp creases. With Chaikin's decay they are not patches.
        let (obj, options) = shape("catmark_torus_creases0");
        let plan = RefinePlan::new(&obj.mesh, Scheme::CatmullClark, options, 4).unwrap();
        assert!(plan
            .tail
            .iter()
            .flat_map(|t| &t.layers)
            .any(|l| !l.edge_nets.is_empty()));
        let chaikin = Options {
            crease_method: crate::mesh::CreaseMethod::Chaikin,
            ..options
        };
        let plan = RefinePlan::new(&obj.mesh, Scheme::CatmullClark, chaikin, 4).unwrap();
        assert!(plan
            .tail
            .iter()
            .flat_map(|t| &t.layers)
            .all(|l| l.edge_nets.is_empty()));
    }

    /// Faces with smooth corners of any valence (3 to 8 here; triangles and n-gons of the
    /// base meshes, quads of level 1 with two extraordinary corners, quads of level 2
    /// with one), with boundary corners (edge-only, edge-and-corner and none) and with
    /// sharp corners and edges, computed by their ring's matrix give the same vertices as
    /// the sparse rows; `catmark_smoothtris0` with OpenSubdiv's `smoothtriangles` rule.
    #[test]
    fn ring_patches_match_rows() {
        for name in [
            "catmark_cube",
            "catmark_pyramid",
            "catmark_toroidal_tet",
            "catmark_nonquads",
            "catmark_smoothtris0",
            "catmark_pole8",
            "catmark_gregory_test6",
            "catmark_val2_foldover",
            // Boundary corners, in each boundary mode.
            "catmark_edgeonly",
            "catmark_edgenone",
            "catmark_flap",
            "catmark_flap2",
            "catmark_quadstrips",
            "catmark_tent",
            "catmark_val2_interior",
            // Semi-sharp and infinitely sharp creases and corners at the corners (their
            // sharpness is part of the key), with Chaikin's rule too.
            "catmark_pyramid_creases0",
            "catmark_pyramid_creases1",
            "catmark_single_crease",
            "catmark_tent_creases0",
            "catmark_dart_edgeonly",
            "catmark_chaikin0",
        ] {
            assert!(check_patches(name).1 > 0, "{name}: no ring patches");
        }
    }

    /// Ring patches at sharp corners and edges give the vertices of the sparse rows:
    /// `catmark_smoothtris0` with random tags (semi-sharp creases from 0.23 to 3.9,
    /// infinitely sharp ones, a corner, holes), with uniform decay and with Chaikin's
    /// rule. Chaikin's rule makes a semi-sharp edge's children depend on edges beyond
    /// the ring, so corners with one are left to the rows (allowing them makes this
    /// test fail: an error of 4e-7 at level 3).
    #[test]
    fn ring_patches_with_random_creases() {
        const TAGS: &str = "t crease 2/1/0 10 40 1\n\
            t crease 2/1/0 18 37 3.6\n\
            t crease 2/1/0 30 31 0.557\n\
            t crease 2/1/0 3 4 0.99\n\
            t crease 2/1/0 0 1 2.0001\n\
            t crease 2/1/0 9 29 0.99\n\
            t crease 2/1/0 16 36 2.891\n\
            t crease 2/1/0 28 41 2.793\n\
            t crease 2/1/0 18 19 0.373\n\
            t crease 2/1/0 10 29 1.5\n\
            t crease 2/1/0 9 10 0.6\n\
            t crease 2/1/0 4 40 10\n\
            t crease 2/1/0 39 41 3.9\n\
            t crease 2/1/0 5 6 0.5\n\
            t crease 2/1/0 27 41 0.611\n\
            t crease 2/1/0 4 23 0.557\n\
            t crease 2/1/0 2 40 1.276\n\
            t crease 2/1/0 21 41 1.516\n\
            t crease 2/1/0 12 31 10\n\
            t crease 2/1/0 33 34 10\n\
            t crease 2/1/0 32 41 0.229\n\
            t crease 2/1/0 13 33 0.920\n\
            t crease 2/1/0 19 39 1.953\n\
            t crease 2/1/0 12 13 1.5\n\
            t crease 2/1/0 14 33 1\n\
            t crease 2/1/0 15 35 2.0001\n\
            t crease 2/1/0 22 41 1.309\n\
            t crease 2/1/0 7 8 0.261\n\
            t crease 2/1/0 24 41 0.859\n\
            t crease 2/1/0 5 25 3.8\n\
            t crease 2/1/0 28 29 1.5\n\
            t crease 2/1/0 36 41 2.991\n\
            t crease 2/1/0 36 37 3.1\n\
            t crease 2/1/0 7 40 4.3\n\
            t crease 2/1/0 1 21 3.4\n\
            t crease 2/1/0 10 11 2.0001\n\
            t corner 1/1/0 9 1.733\n\
            t hole 4/0/0 41 30 44 46\n\
            t creasemethod 0/0/1 chaikin\n\
            t interpolateboundary 1/0/0 2\n";
        let path = format!(
            "{}/tests/shapes/osd/catmark_smoothtris0.obj",
            env!("CARGO_MANIFEST_DIR")
        );
        let text = std::fs::read_to_string(path).unwrap() + TAGS;
        let obj = crate::io::obj::parse_obj(text.as_bytes(), "tagged").unwrap();
        let options = obj.options.resolve(Options::default());
        assert_eq!(options.crease_method, crate::mesh::CreaseMethod::Chaikin);
        for crease_method in [crate::mesh::CreaseMethod::Uniform, options.crease_method] {
            let options = Options {
                crease_method,
                ..options
            };
            let (_, rings) = check_mesh_patches(&obj.mesh, options, "tagged smoothtris0");
            assert!(rings > 0);
        }
    }

    /// A ring shared by fewer than `MIN_RING_FACES` faces of a level gets no matrix:
    /// `catmark_pyramid`'s four triangles share one ring and are patches from the base
    /// level (in groups by the rows each owns), its square base (the only face with its
    /// ring) is left to the rows.
    #[test]
    fn rare_rings_are_rows() {
        let (obj, options) = shape("catmark_pyramid");
        let plan = RefinePlan::new(&obj.mesh, Scheme::CatmullClark, options, 2).unwrap();
        let layers = &plan.tail.as_ref().unwrap().layers;
        assert_eq!(layers.len(), 1);
        assert_eq!(layers[0].rings.len(), 4);
    }

    /// An all-triangle mesh (`catmark_bishop` with each quad split in two, and its
    /// creases and holes dropped) is covered by ring patches at every level: its
    /// triangles from the base level on (four levels deep when the plan refines four),
    /// the quads of level 1 with two extraordinary corners, those of level 2 with one.
    /// Few vertices are left to the rows.
    #[test]
    fn triangle_meshes_are_ring_patches() {
        let (obj, _) = shape("catmark_bishop");
        let mesh = &obj.mesh;
        let mut tris: Vec<[u32; 3]> = Vec::new();
        for f in 0..mesh.num_faces() {
            let v = mesh.face(f);
            for k in 1..v.len() - 1 {
                tris.push([v[0], v[k], v[k + 1]]);
            }
        }
        let tri = PolyMesh::from_faces(mesh.positions().to_vec(), &tris).unwrap();
        let (_, rings) = check_mesh_patches(&tri, Options::default(), "bishop_tri");
        assert!(rings > 0);
        for levels in 2..=5 {
            let plan =
                RefinePlan::new(&tri, Scheme::CatmullClark, Options::default(), levels).unwrap();
            let tail = plan.tail.as_ref().unwrap();
            let depths: Vec<u32> = tail.layers.iter().map(|l| l.depth()).collect();
            let first = levels.min(3) + u32::from(levels == 4);
            assert_eq!(
                depths,
                (2..=first).rev().collect::<Vec<_>>(),
                "level {levels}"
            );
            let rows = tail.out_rows.len() as f64 / tail.num_out as f64;
            // Measured: 8.9 %, 2.5 %, 0.6 %, 0.15 % at levels 2 to 5 (the faces at the
            // poles of valence above 16 and their children, and at level 2 the triangles
            // whose ring is shared by fewer than `MIN_RING_FACES`), where every vertex was
            // a row at levels 2 and 3 before ring patches.
            assert!(
                rows < 0.1,
                "level {levels}: {rows} of the output in sparse rows"
            );
        }
    }

    /// An open all-triangle mesh (the triangles of [`triangle_meshes_are_ring_patches`]
    /// below a cut, so that its boundary runs along the cut) is covered by ring patches up
    /// to its boundary: faces with boundary corners are ring patches too, their template
    /// having the same boundary.
    #[test]
    fn open_triangle_meshes_are_ring_patches() {
        let (obj, _) = shape("catmark_bishop");
        let mesh = &obj.mesh;
        let pos = mesh.positions();
        let mut tris: Vec<[u32; 3]> = Vec::new();
        for f in 0..mesh.num_faces() {
            let v = mesh.face(f);
            for k in 1..v.len() - 1 {
                let t = [v[0], v[k], v[k + 1]];
                if t.iter().map(|&i| pos[i as usize][2]).sum::<f64>() < 3.0 * 0.6 {
                    tris.push(t);
                }
            }
        }
        let open = PolyMesh::from_faces(pos.to_vec(), &tris).unwrap();
        for boundary in [
            BoundaryInterpolation::EdgeOnly,
            BoundaryInterpolation::EdgeAndCorner,
            BoundaryInterpolation::None,
        ] {
            let options = Options {
                boundary,
                ..Options::default()
            };
            let (_, rings) = check_mesh_patches(&open, options, "bishop_tri_open");
            assert!(rings > 0);
            // Ring patches at boundary corners too leave 5.5 %, 1.2 % and 0.28 % of the
            // output (measured in each mode) to sparse rows at levels 2 to 4.
            for (levels, bound) in [(2, 0.07), (3, 0.02), (4, 0.005)] {
                let plan = RefinePlan::new(&open, Scheme::CatmullClark, options, levels).unwrap();
                let tail = plan.tail.as_ref().unwrap();
                let rows = tail.out_rows.len() as f64 / tail.num_out as f64;
                assert!(
                    rows < bound,
                    "{boundary:?} level {levels}: {rows} of the output in sparse rows"
                );
            }
        }
    }

    /// Every vertex of the smooth regular part shares a handful of classes.
    #[test]
    fn classes_are_shared() {
        let (obj, _) = shape("catmark_torus");
        let plan = RefinePlan::build(&obj.mesh, Options::default(), 3, 0, CC).unwrap();
        let last = plan.steps.last().unwrap();
        // Regular quads: face points, smooth edge points and valence-4 vertex points.
        assert_eq!(last.class_offsets.len() - 1, 3);
        assert_eq!(
            plan.num_weights(),
            plan.steps.iter().map(|s| s.cols.len()).sum::<usize>()
        );
    }

    /// The triangles of `catmark_bishop` (each face split into a fan from its corner 0):
    /// corners of valence 3 to 12, and the two poles of valence 20.
    fn bishop_triangles() -> PolyMesh {
        let (obj, _) = shape("catmark_bishop");
        let mesh = &obj.mesh;
        let mut tris: Vec<[u32; 3]> = Vec::new();
        for f in 0..mesh.num_faces() {
            let v = mesh.face(f);
            for k in 1..v.len() - 1 {
                tris.push([v[0], v[k], v[k + 1]]);
            }
        }
        PolyMesh::from_faces(mesh.positions().to_vec(), &tris).unwrap()
    }

    /// A closed torus of `n × m` squares, each cut into two triangles along the same
    /// diagonal: every vertex has valence 6.
    fn regular_tri_torus(n: u32, m: u32) -> PolyMesh {
        let id = |i: u32, j: u32| (i % n) * m + j % m;
        let mut pos = Vec::new();
        for i in 0..n {
            for j in 0..m {
                let (u, v) = (
                    std::f64::consts::TAU * f64::from(i) / f64::from(n),
                    std::f64::consts::TAU * f64::from(j) / f64::from(m),
                );
                let r = 1.0 + 0.4 * v.cos();
                pos.push([r * u.cos(), r * u.sin(), 0.4 * v.sin()]);
            }
        }
        let mut faces = Vec::new();
        for i in 0..n {
            for j in 0..m {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                faces.extend([[a, b, c], [a, c, d]]);
            }
        }
        PolyMesh::from_faces(pos, &faces).unwrap()
    }

    /// `mesh` with pseudo-random tags (a linear congruential sequence from `seed`): about
    /// a third of its edges semi-sharp (0.23 to 3.9, some at whole values, where the
    /// rules change at the last step) or infinitely sharp, three semi-sharp or
    /// infinitely sharp corners, and two holes.
    fn with_random_tags(mut mesh: PolyMesh, seed: u64) -> PolyMesh {
        let mut state = seed;
        let mut next = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 33) as u32
        };
        const SHARPNESS: [f32; 10] = [0.23, 0.557, 0.99, 1.0, 1.5, 2.0001, 2.891, 3.0, 3.9, 10.0];
        let mut edges: Vec<[u32; 2]> = mesh
            .faces()
            .flat_map(|f| (0..f.len()).map(move |k| [f[k], f[(k + 1) % f.len()]]))
            .map(|[a, b]| [a.min(b), a.max(b)])
            .collect();
        edges.sort_unstable();
        edges.dedup();
        for [v0, v1] in edges {
            if next() % 3 == 0 {
                let sharpness = SHARPNESS[next() as usize % SHARPNESS.len()];
                mesh.tags.creases.push(Crease { v0, v1, sharpness });
            }
        }
        let (nv, nf) = (mesh.num_vertices() as u32, mesh.num_faces() as u32);
        for sharpness in [0.7, 2.5, 10.0] {
            let vertex = next() % nv;
            mesh.tags.corners.push(Corner { vertex, sharpness });
        }
        mesh.tags.holes = vec![next() % nf, next() % nf];
        mesh
    }

    /// Ring patches of Loop's triangles compute the vertices of the sparse rows, to
    /// rounding, at every depth, on every Loop regression shape: corners of valence 3
    /// (`loop_tetrahedron`) to 8 (`loop_pole8`), boundaries in each mode
    /// (`loop_triangle_edge*`, the saddles), infinitely sharp and semi-sharp creases and
    /// corners (with Chaikin's rule in `loop_chaikin*`), non-manifold edges and vertices
    /// (their faces left to the rows) and a pole of valence 360 (beyond `MAX_VALENCE`:
    /// rows).
    #[test]
    fn loop_ring_patches_match_rows() {
        for name in [
            "loop_chaikin0",
            "loop_chaikin1",
            "loop_cube",
            "loop_cube_asymmetric",
            "loop_cube_creases0",
            "loop_cube_creases1",
            "loop_cubes_infsharp",
            "loop_fvar_bound0",
            "loop_icos_infsharp",
            "loop_icosahedron",
            "loop_nonman_edge100",
            "loop_nonman_edges",
            "loop_nonman_verts",
            "loop_pole360",
            "loop_pole8",
            "loop_saddle_edgecorner",
            "loop_saddle_edgeonly",
            "loop_tetrahedron",
            "loop_triangle_edgecorner",
            "loop_triangle_edgenone",
            "loop_triangle_edgeonly",
            "loop_val2_interior",
            "loop_xord_boundary",
        ] {
            let (obj, options) = shape(name);
            let levels = if name == "loop_pole360" { 3 } else { 4 };
            let (_, rings) = check_steps_patches(&obj.mesh, options, Steps::Loop, levels, name);
            assert!(rings > 0, "{name}: no ring patches");
        }
    }

    /// Loop ring patches whose corners and the edges at them carry random sharpness
    /// (part of the key), with holes, in each boundary mode, with uniform decay and with
    /// Chaikin's rule (semi-sharp edges at a corner then leave the face to the rows):
    /// the vertices of the sparse rows, on a closed mesh (`loop_icosahedron` refined
    /// once, so that the tags fall on corners of valence 5 and 6) and an open one (the
    /// all-triangle bishop below a cut).
    #[test]
    fn loop_ring_patches_with_random_tags() {
        let (ico, _) = shape("loop_icosahedron");
        let ico = crate::subdivide(
            &ico.mesh,
            &crate::SubdivideOptions {
                levels: 1,
                scheme: Scheme::Loop,
                ..Default::default()
            },
        )
        .unwrap()
        .mesh;
        let bishop = bishop_triangles();
        let pos = bishop.positions();
        let below: Vec<Vec<u32>> = (bishop.faces())
            .filter(|f| f.iter().map(|&v| pos[v as usize][2]).sum::<f64>() < 3.0 * 0.6)
            .map(<[u32]>::to_vec)
            .collect();
        let open = PolyMesh::from_faces(pos.to_vec(), &below).unwrap();
        for (name, mesh, seed) in [("icosahedron", ico, 7), ("open bishop", open, 11)] {
            let mesh = with_random_tags(mesh, seed);
            for boundary in [
                BoundaryInterpolation::EdgeOnly,
                BoundaryInterpolation::EdgeAndCorner,
                BoundaryInterpolation::None,
            ] {
                for crease_method in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
                    let options = Options {
                        boundary,
                        crease_method,
                        ..Options::default()
                    };
                    let what = format!("{name} {boundary:?} {crease_method:?}");
                    let (_, rings) = check_steps_patches(&mesh, options, Steps::Loop, 3, &what);
                    assert!(rings > 0, "{what}: no ring patches");
                }
            }
        }
    }

    /// A regular all-triangle torus (every vertex of valence 6) is covered by Loop ring
    /// patches of one ring shape: every face of the level `LOOP_DEPTH` above the output
    /// is a patch, no vertex is left to the rows, and the plan stores no weight when it
    /// refines at most `LOOP_DEPTH` levels; the all-triangle bishop (corners of valence 3
    /// to 12, two poles of valence 20 whose faces are rows on every level) leaves few.
    #[test]
    fn loop_kernels_cover_triangle_meshes() {
        let torus = regular_tri_torus(12, 8);
        let faces = torus.num_faces();
        for levels in 2..=LOOP_DEPTH + 1 {
            let plan = RefinePlan::new(&torus, Scheme::Loop, Options::default(), levels).unwrap();
            let tail = plan.tail.as_ref().unwrap();
            let depth = levels.min(LOOP_DEPTH);
            assert!(tail.out_rows.is_empty(), "level {levels}");
            assert_eq!(tail.layers.len(), depth as usize - 1);
            assert_eq!(plan.num_patches(), faces << (2 * (levels - depth)));
            let first = &tail.layers[0];
            assert_eq!((first.depth(), first.len()), (depth, plan.num_patches()));
            if levels <= LOOP_DEPTH {
                assert_eq!(plan.num_weights(), 0, "level {levels}");
            }
        }
        // Measured: 6.4 %, 1.0 %, 0.26 %, 0.065 % of the output at levels 2 to 5 (the
        // faces at the poles and their children, and at level 2 the triangles whose
        // ring is shared by fewer than `MIN_RING_FACES`), where every vertex was a row
        // before Loop's ring patches.
        let bishop = bishop_triangles();
        for (levels, bound) in [(2, 0.08), (3, 0.015), (4, 0.004), (5, 0.001)] {
            let plan = RefinePlan::new(&bishop, Scheme::Loop, Options::default(), levels).unwrap();
            let tail = plan.tail.as_ref().unwrap();
            let rows = tail.out_rows.len() as f64 / tail.num_out as f64;
            assert!(
                rows < bound,
                "level {levels}: {rows} of the output in sparse rows"
            );
        }
    }

    /// Bilinear plans compute every vertex on a face from its corners by one matrix per
    /// face size: the same vertices as the sparse rows, to rounding, on quads, triangles
    /// and n-gons, at boundaries in each mode, creases, holes and non-manifold edges and
    /// vertices (which do not change bilinear points), every vertex on a face written by
    /// a patch.
    #[test]
    fn bilinear_face_patches_match_rows() {
        for name in [
            "bilinear_cube",
            "bilinear_nonquads0",
            "bilinear_nonquads1",
            "catmark_nonquads",
            "catmark_hole_test3",
            "catmark_nonman_edges",
            "catmark_nonman_verts",
            "catmark_nonman_quadpole64",
            "catmark_edgenone",
            "catmark_cube_creases1",
            "catmark_val2_foldover",
        ] {
            let (obj, options) = shape(name);
            let (_, rings) = check_steps_patches(&obj.mesh, options, Steps::Bilinear, 4, name);
            assert!(rings > 0, "{name}: no patches");
            for levels in 2..=BILINEAR_DEPTH {
                let plan = RefinePlan::new(&obj.mesh, Scheme::Bilinear, options, levels).unwrap();
                let tail = plan.tail.as_ref().unwrap();
                // Faces whose size has fewer than `MIN_RING_FACES` faces are rows.
                let sizes = |n: usize| obj.mesh.faces().filter(|f| f.len() == n).count();
                if obj.mesh.faces().all(|f| sizes(f.len()) >= 4) {
                    assert!(tail.out_rows.is_empty(), "{name} level {levels}");
                    assert_eq!(plan.num_weights(), 0, "{name} level {levels}");
                }
            }
        }
    }
}
