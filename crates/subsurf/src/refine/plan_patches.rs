//! Regular patches of a [`RefinePlan`](super::RefinePlan): the last levels of a quad
//! whose neighbourhood is a regular grid, computed from its 16 control points by a fixed
//! tensor-product kernel instead of one sparse row per refined vertex.
//!
//! # Why
//! Applying a plan level by level reads four bytes of stored column per weight (about 29
//! bytes per refined vertex) and sweeps over each parent level several times; at level 6
//! that memory traffic, not arithmetic, sets the time. Almost all of a refined mesh lies
//! over *regular* quads, where Catmull-Clark refinement is uniform bicubic B-spline
//! subdivision (Catmull & Clark 1978, §2; Stam 1998, §2): the `(2ᵈ + 1)²` vertices that
//! `d` more levels put on such a quad are the same fixed linear combinations of its 16
//! control points for every such quad. A patch therefore stores only its 16 control
//! indices and where its refined vertices go (about 5 bytes per output vertex at depth 3),
//! and computes them in registers.
//!
//! # The kernel
//! One level of uniform cubic B-spline subdivision of a sequence `pᵢ` gives the vertex
//! points `(pᵢ₋₁ + 6pᵢ + pᵢ₊₁)/8` and the edge points `(pᵢ + pᵢ₊₁)/2` (Lane & Riesenfeld
//! 1980). `d` such steps map the four control points at parameters `−1, 0, 1, 2` to the
//! points at `k/2ᵈ`, `k = 0..=2ᵈ`, of the span `[0, 1]`: an `(2ᵈ + 1) × 4` matrix `W`
//! of dyadic rationals (for `d = 2` the rows are `(5, 22, 5, 0)/32`, `(1, 10, 5, 0)/16`,
//! `(1, 31, 31, 1)/64` and their mirror images), computed exactly by [`weights`]. The
//! quad's refined vertices are `W P Wᵀ`, applied as two passes of `W` (along `u`, then
//! along `v`): 13 applications of `W` for the 81 vertices of depth 3.
//!
//! # Which quads
//! A quad is a patch when [`refinement_patch_cells`] finds its 4 × 4 net, with distinct
//! vertices (else it may be a ring patch; on holes too, whose vertices follow the same
//! rules): its four corners are
//! smooth valence-4 vertices with no sharp or semi-sharp edge, surrounded by quads, or
//! regular boundary, crease and corner vertices (see [`super::patch`]).
//! Refinement inside a smooth such quad only ever applies the
//! smooth regular masks: the vertices that level `l + 1` puts within half a parent edge of
//! the quad come from the masks of its corners, of the twelve edges at them and of the nine
//! faces around them (all regular), and every element derived from them is regular again.
//!
//! Across a boundary or an infinitely sharp crease the net has *phantom* points, `2 P₀ −
//! P₁` (and `4 P₀₀ − 2 P₁₀ − 2 P₀₁ + P₁₁` in a corner cell). They reproduce the crease rules
//! exactly: one step of the curve rules on a row `P₁, P₀, 2 P₀ − P₁` across the side gives
//! `P₀` at the side (the vertex rule `(P₁ + 6 P₀ + (2 P₀ − P₁))/8`) and the new phantom
//! `(3 P₀ − P₁)/2 = 2 P₀' − P₁'`, so the refined row has the same form; along the side the
//! tensor product then applies `(1, 6, 1)/8` and `(1, 1)/2` to the side's points, the crease
//! vertex and edge rules (Biermann, Levin & Zorin 2000, §3; OpenSubdiv's regular boundary
//! patches). A corner cell is fixed the same way in both directions (the corner rule). Such
//! patches ("edge patches" here) evaluate their phantom points into a local net first, then
//! run the same kernel.
//!
//! # The shape-adjustable scheme
//! With parameter `c` ([`crate::scheme::adjustable`]) the masks of a regular grid are the
//! tensor product of the curve rules `p'₂ᵢ = (c/4) pᵢ₋₁ + (1 − c/2) pᵢ + (c/4) pᵢ₊₁` and
//! `p'₂ᵢ₊₁ = (pᵢ + pᵢ₊₁)/2` (`c = ½`: the cubic B-spline), whose supports are the cubic
//! B-spline's: four control points still give the span's points at every level, and
//! [`weights`] computes `W` from these rules. The phantom points work for any `c`: on the
//! row `P₁, P₀, 2 P₀ − P₁` the vertex rule gives `(c/4) P₁ + (1 − c/2) P₀ + (c/4)(2 P₀ −
//! P₁) = P₀` and the edge rule the phantom `(3 P₀ − P₁)/2` as before, so along the side
//! the tensor product applies `(c/4, 1 − c/2, c/4)` and the midpoint, the adjustable
//! scheme's crease rules; its corners stay fixed. `tests/integration/replay.rs` compares
//! such plans with [`subdivide`](fn@crate::subdivide) with [`Scheme::Adjustable`](crate::Scheme::Adjustable) on every regression shape.
//!
//! A semi-sharp crease or corner is such a sharp side for the `d` levels of a patch when it
//! keeps the crease rules through all of them: with the uniform decay, sharpness at least
//! `d` ([`Sharp::for_levels`](crate::refine::patch::Sharp::for_levels) says why). The
//! sharpness-6 creases of `catmark_bishop` and `catmark_pawn` are patch sides from level 2
//! on.
//!
//! Any other face whose corners are manifold vertices (of any valence, inside or on a
//! boundary, smooth or sharp; a triangle or n-gon of the base mesh too) is a *ring patch*
//! instead: the same idea with a fixed
//! matrix per shape of 1-ring on the points of that ring (`refine/plan_ring.rs`).
//!
//! Each refined vertex is written by exactly one patch or by the plan's remaining sparse
//! rows (see [`Claims`]).
//!
//! # Order of work
//! A layer applies its patches by runs of [`RUN`] consecutive faces, each run all its
//! patches of every kind (plain, edge, ring) before the next, and runs in
//! parallel. The outputs of neighbouring quads share cache lines; one pass per kind would
//! load those lines from memory once per pass. Ring patches are applied by units of one
//! or more runs ([`ring_span`]), each key's patches of a unit together, so that a key's
//! matrix is read once for several patches: with many keys (110 on a 20 k-triangle scan
//! at depth 3) one run holds only two or three patches of each. The ring points
//! and grids of a layer's ring patches are stored in that order, unit by unit and
//! matrix by matrix within a unit ([`RingPatches`]), so that applying reads them as one
//! stream. At depth 2 a triangle's (any non-quad's) patch goes to a matrix of just the
//! rows it owns ([`RingGroups`]), so its groups of rows are full.
//!
//! # Numbering
//! Where a patch's refined vertices go follows from [`refine_topology`]'s child numbering
//! (the child of vertex `v` is `v`; of face `f` is `V + f`; of edge `e` is `V + F + e`;
//! child quad `j` of a quad keeps the parent's orientation, its corner `j` at the
//! parent's corner `j`): [`grid_indices`] walks the levels down and checks at every step
//! that the child quads are where the numbering says (a patch whose check fails is left
//! to the sparse rows).
//!
//! [`refine_topology`]: super::topology::refine_topology

use std::ops::Range;

use rayon::prelude::*;

use super::patch::{refinement_patch_cells, Cell, Sharp};
use super::plan_ring::{
    descendants, face_net, ring_net, subset_rows, Kernel, RingGroups, RingNet, RingPatches,
};
use super::uniform::Steps;
#[cfg(target_arch = "x86_64")]
use crate::cpu::{has_avx2_fma, has_avx512f};
use crate::mesh::{CreaseMethod, Options, Topology};
use crate::scheme::adjustable::Mixed;

/// Faces of a layer's level per run: the unit of parallel work. A run applies all its
/// patches, of every kind, before the next: neighbouring patches share cache lines of the
/// output, which a separate pass per kind would load again from memory.
const RUN: usize = 256;

/// Ring patches per key and unit of work that [`ring_span`] aims at.
const RING_PATCHES_PER_KEY: usize = 8;

/// Fewest units of work a layer is cut into when it has that many runs, whatever its ring
/// patches ask for ([`ring_span`]): the units are what the threads share.
///
/// Why: a layer's plain and edge patches are applied with its ring patches, unit by unit
/// (module docs), so the units a few ring patches ask for hold all the rest too. A regular
/// grid has four ring patches, at its corners (smooth valence-2 vertices), of one key;
/// eight per key would make the whole layer one unit, and two threads no faster than one.
/// Eight units keep both threads of a small machine busy and cost little where ring
/// matrices are many (BENCHMARKS.md, "Re-posing").
const MIN_UNITS: usize = 8;

/// Runs per unit of work of a layer with `runs` runs and `patches` ring patches of
/// `keys` keys (matrices: a key's, or one of the rows some of its patches own, see
/// [`RingGroups`]): enough for [`RING_PATCHES_PER_KEY`] patches of each key on average,
/// as long as that leaves [`MIN_UNITS`] units. A unit applies each key's patches
/// together, so that its matrix is read from memory once per unit; with many keys (an
/// all-triangle base mesh has one per triple of corner valences: 110 on a 20 k-triangle
/// scan, about 7 KiB each at depth 3) and runs of [`RUN`] faces, each key had two or
/// three patches per run and the matrices, together larger than the cache, were read
/// again for every few patches.
pub(super) fn ring_span(runs: usize, keys: usize, patches: usize) -> usize {
    (RING_PATCHES_PER_KEY * keys * runs)
        .div_ceil(patches.max(1))
        .min(runs / MIN_UNITS)
        .clamp(1, runs.max(1))
}

/// Fewest faces of a layer that share a ring (a key of `refine/plan_ring.rs`), each with
/// a vertex that no deeper layer wrote, for its matrix to be built: building one refines
/// its ring and applies the result to each of the ring's points, a thousand times the
/// cost of the sparse rows of a face. A mesh whose every face has its own ring (mixed face sizes around every
/// vertex) would otherwise build one matrix per face.
const MIN_RING_FACES: usize = 4;

/// The grid point for "written elsewhere".
pub(super) const NOT_OWNED: u32 = u32::MAX;

/// Deepest patches on quads: 3 gives 81 vertices per patch from 16 control points. (On
/// `catmark_bishop` 93 % of the quads of level 3 are patches, 97 % of level 4; deeper
/// patches would cover less and need more of the sparse rows.)
pub(super) const QUAD_DEPTH: u32 = 3;

/// Depth of the ring patches on the faces of the base mesh that are not quads (triangles,
/// n-gons) when a plan refines exactly this many levels; a layer of this depth holds
/// those patches only, and the quads go one level down (at most [`QUAD_DEPTH`]).
///
/// Why: at depth 3 on level 1, each of a triangle's three quads has a ring of its own
/// (18 points at valence 6, two of its corners being extraordinary), and its rows read
/// most of them; the triangle's own 1-ring has 12 points, which every row of a depth-4
/// matrix reads at most. On the all-triangle `cow` (5 804 triangles) an output vertex
/// costs 13.1 multiply-adds per component at depth 4 against 19.1 at depth 3 (counting
/// the zeros of the groups of eight rows). A quad's ring at an extraordinary corner is no smaller than its
/// children's, so quads keep [`QUAD_DEPTH`]. Five levels of a triangle would be 817 rows
/// per key (78 KiB at 12 points, about 80 keys on a scan), where depth 3 on level 2 finds
/// half of the quads regular, at 8 multiply-adds per vertex in the bicubic kernel.
pub(super) const BASE_RING_DEPTH: u32 = 4;

/// Deepest ring patches of Loop's triangles (`refine/plan_ring.rs`).
pub(super) const LOOP_DEPTH: u32 = 4;

/// Deepest patches of bilinear faces (a matrix per face size on its corners, [`face_net`]).
pub(super) const BILINEAR_DEPTH: u32 = 4;

/// All patches of one depth, on one level.
#[derive(Clone, Debug)]
pub(super) struct PatchLayer {
    /// Levels refined within each patch (2 or 3; [`BASE_RING_DEPTH`] for a layer of ring
    /// patches on the base mesh's faces that are not quads; up to [`LOOP_DEPTH`] and
    /// [`BILINEAR_DEPTH`] for Loop's and bilinear's, ring patches only).
    depth: u32,
    /// Which level's values the control indices refer to (see [`RefinePlan`]'s tail):
    /// 0 for the fully computed level, `s ≥ 1` for the `s`-th subset level.
    ///
    /// [`RefinePlan`]: super::RefinePlan
    pub(super) source: usize,
    /// Number of runs of [`RUN`] faces.
    runs: usize,
    /// Runs per unit of work (see [`ring_span`]): ring patches are indexed by units.
    span: usize,
    /// The 16 control vertices of each patch, `ctrl[4i + j]` at `(u, v)` cell `(i, j)`.
    ctrl: Vec<[u32; 16]>,
    /// Where the patches of each run start in `ctrl`.
    ctrl_runs: Runs,
    /// The output vertex of each of the `n²` grid points of each patch (`n = 2ᵈ + 1`,
    /// point `(x, y)` at `n x + y`, `x` along `u`), or [`NOT_OWNED`].
    out: Vec<u32>,
    /// The nets of the edge patches (with phantom points; module docs), as `ctrl`.
    pub(super) edge_nets: Vec<[Cell; 16]>,
    /// The grid points of the edge patches, as `out`.
    edge_out: Vec<u32>,
    /// Where the edge patches of each run start.
    edge_runs: Runs,
    /// The ring patches (`refine/plan_ring.rs`).
    pub(super) rings: RingPatches,
    /// The kernel's matrix `W`, one row of four weights per grid column.
    w: Vec<[f64; 4]>,
    /// One more than the largest control index, and than the largest output index.
    bounds: [usize; 2],
}

/// Where the patches of one kind start in each run of faces: run `r`'s are
/// `starts[r]..starts[r + 1]`.
#[derive(Clone, Debug, Default)]
pub(super) struct Runs(Vec<u32>);

impl Runs {
    /// From the run of each patch (in increasing order), with `runs` runs.
    pub(super) fn new(run_of: &[u32], runs: usize) -> Self {
        let mut starts = Vec::with_capacity(runs + 1);
        let mut at = 0;
        for r in 0..=runs as u32 {
            while at < run_of.len() && run_of[at] < r {
                at += 1;
            }
            starts.push(at as u32);
        }
        Runs(starts)
    }

    /// The patches of run `r`.
    pub(super) fn range(&self, r: usize) -> Range<usize> {
        self.0[r] as usize..self.0[r + 1] as usize
    }

    /// Bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        4 * self.0.len()
    }
}

/// Which output vertices are already written by a patch.
pub(super) struct Claims(Vec<bool>);

impl Claims {
    pub(super) fn new(n: usize) -> Self {
        Claims(vec![false; n])
    }

    /// The output vertices no patch writes, in increasing order.
    pub(super) fn unclaimed(&self) -> Vec<u32> {
        (0..self.0.len() as u32)
            .filter(|&i| !self.0[i as usize])
            .collect()
    }
}

/// The matrix `W` of depth `d` (module docs): row `k` holds the weights of the point at
/// parameter `k/2ᵈ` on the control points at `−1, 0, 1, 2`, step `s` (from 1) with the
/// curve rules of `mixed.step(s)` (vertex points `(c/4) pᵢ₋₁ + (1 − c/2) pᵢ + (c/4) pᵢ₊₁`,
/// edge points `(pᵢ + pᵢ₊₁)/2`; the cubic B-spline's `(1, 6, 1)/8` for Catmull-Clark,
/// `c = ½`).
pub(super) fn weights(d: u32, mixed: Mixed) -> Vec<[f64; 4]> {
    // Points as (parameter × 2^d, weights); for Catmull-Clark all values are exact dyadic
    // rationals.
    let scale = 1i64 << d;
    let mut pts: Vec<(i64, [f64; 4])> = (0..4)
        .map(|k| {
            let mut w = [0.0; 4];
            w[k] = 1.0;
            ((k as i64 - 1) * scale, w)
        })
        .collect();
    let lerp = |a: &[f64; 4], b: &[f64; 4], wa: f64, wb: f64| -> [f64; 4] {
        std::array::from_fn(|k| wa * a[k] + wb * b[k])
    };
    for step in 1..=d {
        let [side, centre, _] = mixed.step(step).curve_even_weights();
        let mut next = Vec::with_capacity(2 * pts.len());
        for i in 0..pts.len() {
            if i > 0 && i + 1 < pts.len() {
                let (x, ref p) = pts[i];
                let side = lerp(&pts[i - 1].1, &pts[i + 1].1, side, side);
                next.push((x, lerp(p, &side, centre, 1.0)));
            }
            if i + 1 < pts.len() {
                let x = (pts[i].0 + pts[i + 1].0) / 2;
                next.push((x, lerp(&pts[i].1, &pts[i + 1].1, 0.5, 0.5)));
            }
        }
        pts = next;
    }
    pts.into_iter()
        .filter(|&(x, _)| (0..=scale).contains(&x))
        .map(|(_, w)| w)
        .collect()
}

/// The output vertices (numbered in the level `d` below `levels[0]`) of the
/// `(2ᵈ + 1)²` grid points of quad `f` of `levels[0]`, where `levels` holds the `d` levels
/// from that of `f` on (`d = levels.len()`), or `None` when the numbering does not give a
/// consistent grid (see the module docs).
pub(super) fn grid_indices(levels: &[Topology], f: usize) -> Option<Vec<u32>> {
    let d = levels.len();
    let n = (1usize << d) + 1;
    let mut grid = vec![NOT_OWNED; n * n];
    fill(levels, f, (0, 0), 1 << d, n, &mut grid)?;
    grid.iter().all(|&g| g != NOT_OWNED).then_some(grid)
}

/// Corner `j` of a quad of side `h`, as an offset from its corner 0.
fn corner(j: usize, h: usize) -> (usize, usize) {
    [(0, 0), (h, 0), (h, h), (0, h)][j]
}

/// Fills the grid points of quad `f` of `levels[0]`, whose corner 0 is at `origin` and
/// whose side is `h` grid steps.
fn fill(
    levels: &[Topology],
    f: usize,
    origin: (usize, usize),
    h: usize,
    n: usize,
    grid: &mut [u32],
) -> Option<()> {
    let t = &levels[0];
    let fv = t.face_vertices(f);
    if fv.len() != 4 {
        return None;
    }
    let mut put = |(x, y): (usize, usize), v: u32| -> Option<()> {
        let g = &mut grid[(origin.0 + x) * n + origin.1 + y];
        if *g != NOT_OWNED && *g != v {
            return None;
        }
        *g = v;
        Some(())
    };
    if levels.len() == 1 {
        // The last step: the children of this quad's vertices, edges and of itself.
        let fe = t.face_edge_list(f);
        let (nv, nf) = (t.num_vertices() as u32, t.num_faces() as u32);
        for j in 0..4 {
            let (a, b) = (fv[j], fv[(j + 1) % 4]);
            let ev = t.edge_vertices(fe[j] as usize);
            if ev != [a, b] && ev != [b, a] {
                return None;
            }
            let (c0, c1) = (corner(j, h), corner((j + 1) % 4, h));
            put(c0, a)?;
            put(((c0.0 + c1.0) / 2, (c0.1 + c1.1) / 2), nv + nf + fe[j])?;
        }
        return put((h / 2, h / 2), nv + f as u32);
    }
    // Child quad `j` sits in the quadrant of corner `j`, in the same orientation, with
    // the child of vertex `j` (the same index) at its corner `j`.
    let o = t.face_offsets[f] as usize;
    let child = &levels[1];
    for j in 0..4 {
        let g = o + j;
        let cv = child.face_vertices(g);
        if cv.len() != 4 || cv[j] != fv[j] {
            return None;
        }
        let q = corner(j, h / 2);
        fill(
            &levels[1..],
            g,
            (origin.0 + q.0, origin.1 + q.1),
            h / 2,
            n,
            grid,
        )?;
    }
    Some(())
}

/// The control net of a patch.
enum Net {
    /// 16 vertices of the level.
    Plain([u32; 16]),
    /// With phantom points (boxed: 14 times the size of a plain net, and rarer).
    Edge(Box<[Cell; 16]>),
    /// The 1-ring of a face with manifold corners (`refine/plan_ring.rs`).
    Ring(RingNet),
}

/// The control net of face `f` if it can be a patch (module docs), with the edges and
/// vertices that `sharp` takes as infinitely sharp: its 16 cells, whose vertices (those
/// that are not phantoms) must be distinct; or else its 1-ring.
fn patch_controls(t: &Topology, f: usize, sharp: Sharp, chaikin: bool) -> Option<Net> {
    let Some(cells) = refinement_patch_cells(t, f, sharp) else {
        return ring_net(t, f, chaikin).map(Net::Ring);
    };
    let cells: [Cell; 16] = std::array::from_fn(|k| cells[k / 4][k % 4]);
    let plain = cells.iter().all(|c| c.len == 1 && c.weights[0] == 1.0);
    let mut verts: Vec<u32> = (cells.iter())
        .filter(|c| c.len == 1)
        .map(|c| c.verts[0])
        .collect();
    verts.sort_unstable();
    if verts.windows(2).any(|w| w[0] == w[1]) {
        return ring_net(t, f, chaikin).map(Net::Ring);
    }
    Some(if plain {
        Net::Plain(cells.map(|c| c.verts[0]))
    } else {
        Net::Edge(Box::new(cells))
    })
}

/// The vertices a cell combines.
fn cell_verts(c: &Cell) -> &[u32] {
    &c.verts[..c.len]
}

/// The faces of `levels[0]` that can be patches of depth `levels.len()` refined with
/// `steps` and would write an output vertex not yet in `claims`: each with its net, and
/// its grid of output vertices (regular and edge patches) or its `descendants` (ring
/// patches, whose grids come once the matrix of their key says which vertices repeat).
/// Not the faces whose every vertex a deeper layer claimed (at level 4 of a triangle
/// mesh, every quad of level 1). Which faces are patches ([`face_patch`]) depends on the
/// scheme.
fn find_patches(
    levels: &[Topology],
    claims: &Claims,
    crease_method: CreaseMethod,
    steps: Steps,
) -> Vec<(u32, Net, Vec<u32>)> {
    let depth = levels.len() as u32;
    let sharp = Sharp::for_levels(depth, crease_method);
    let chaikin = crease_method == CreaseMethod::Chaikin;
    let t = &levels[0];
    let seen = &claims.0;
    (0..t.num_faces())
        .into_par_iter()
        .with_min_len(RUN)
        .filter_map(|f| {
            let net = face_patch(t, f, depth, steps, sharp, chaikin)?;
            let verts = match &net {
                Net::Ring(ring) => {
                    let mut walk = Vec::new();
                    descendants(steps, levels, f, ring.start, &mut walk)?;
                    walk
                }
                _ => grid_indices(levels, f)?,
            };
            let open = verts.iter().any(|&v| !seen[v as usize]);
            open.then_some((f as u32, net, verts))
        })
        .collect()
}

/// The net of face `f` of `t` if it can be a patch of depth `depth` refined with `steps`:
/// - the Catmull-Clark family: a regular or edge patch, or else a ring patch
///   ([`patch_controls`]); past [`QUAD_DEPTH`], only faces that are not quads;
/// - Loop: a ring patch of the triangle (`refine/plan_ring.rs`): its 1-ring plays the part
///   it plays for Catmull-Clark, the masks of Loop's triangle split reading no further;
/// - bilinear: every face, its "ring" its corners alone ([`face_net`]): bilinear points
///   are averages of the face's own corners at every level.
fn face_patch(
    t: &Topology,
    f: usize,
    depth: u32,
    steps: Steps,
    sharp: Sharp,
    chaikin: bool,
) -> Option<Net> {
    match steps {
        Steps::Family(_) if depth > QUAD_DEPTH && t.face_vertices(f).len() == 4 => None,
        Steps::Family(_) => patch_controls(t, f, sharp, chaikin),
        Steps::Loop => ring_net(t, f, chaikin).map(Net::Ring),
        Steps::Bilinear => face_net(t, f).map(Net::Ring),
    }
}

/// The patches `found` with their grids and (ring patches) the index of their key, and
/// the kernel of each key: one matrix per key found on at least `MIN_RING_FACES` faces
/// (in parallel: an all-triangle base mesh has one per triple of valences). The ring
/// patches of other keys, and of a key whose matrix could not be built, are dropped:
/// they are left to the rows.
#[allow(clippy::type_complexity)]
fn with_ring_grids(
    found: Vec<(u32, Net, Vec<u32>)>,
    depth: u32,
    options: &Options,
    steps: Steps,
) -> (Vec<(u32, Net, Vec<u32>, usize)>, Vec<Option<Kernel>>) {
    let mut keys: Vec<&[u32]> = (found.iter())
        .filter_map(|(_, net, _)| match net {
            Net::Ring(ring) => Some(ring.key.as_slice()),
            _ => None,
        })
        .collect();
    keys.sort_unstable();
    let counts: Vec<usize> = keys.chunk_by(|a, b| a == b).map(<[_]>::len).collect();
    keys.dedup();
    let kernels: Vec<Option<Kernel>> = (keys.par_iter().zip(counts))
        .map(|(key, n)| (n >= MIN_RING_FACES).then(|| Kernel::new(key, depth, options, steps))?)
        .collect();
    let ring_grids: Vec<Option<(usize, Vec<u32>)>> = (found.par_iter())
        .with_min_len(RUN)
        .map(|(_, net, walk)| {
            let Net::Ring(ring) = net else { return None };
            let k = keys.binary_search(&ring.key.as_slice()).ok()?;
            Some((k, kernels[k].as_ref()?.grid(&ring.verts, walk)?))
        })
        .collect();
    let found = (found.into_iter().zip(ring_grids))
        .filter_map(|((f, net, grid), ring)| match (net, ring) {
            (Net::Ring(_), None) => None,
            (net @ Net::Ring(_), Some((k, grid))) => Some((f, net, grid, k)),
            (net, _) => Some((f, net, grid, 0)),
        })
        .collect();
    (found, kernels)
}

/// The patches of a layer sorted by kind, by [`claim_patches`].
struct ClaimedPatches {
    /// Regular patches: control vertices, output grids, run of each.
    ctrl: Vec<[u32; 16]>,
    out: Vec<u32>,
    ctrl_run: Vec<u32>,
    /// Edge patches: nets, output grids, run of each.
    edge_nets: Vec<[Cell; 16]>,
    edge_out: Vec<u32>,
    edge_run: Vec<u32>,
    /// Ring patches, grouped by matrix, and their span.
    rings: RingPatches,
    span: usize,
}

/// Claims, in face order, the output vertices of the patches `found` that no earlier
/// patch (or deeper layer) claimed (the others' grid entries become [`NOT_OWNED`]), and
/// sorts the patches that claim at least one by kind; `kernels` are the ring keys'
/// matrices, `runs` the number of runs of faces, `subset_rows` says which ring patches
/// are packed ([`RingGroups`]).
fn claim_patches(
    found: Vec<(u32, Net, Vec<u32>, usize)>,
    claims: &mut Claims,
    kernels: &[Option<Kernel>],
    runs: usize,
    subset_rows: usize,
) -> ClaimedPatches {
    let mut ctrl = Vec::with_capacity(found.len());
    let mut out = Vec::with_capacity(found.iter().map(|(_, _, g, _)| g.len()).sum());
    let (mut edge_nets, mut edge_out) = (Vec::new(), Vec::new());
    let (mut ctrl_run, mut edge_run) = (Vec::new(), Vec::new());
    let mut ring_groups = RingGroups::new(kernels, subset_rows);
    for (f, net, mut grid, key) in found {
        let run = f / RUN as u32;
        let mut any = false;
        for g in grid.iter_mut().filter(|g| **g != NOT_OWNED) {
            let seen = &mut claims.0[*g as usize];
            if *seen {
                *g = NOT_OWNED;
            } else {
                *seen = true;
                any = true;
            }
        }
        match net {
            _ if !any => {}
            Net::Ring(ring) => ring_groups.push(key, run, ring.verts, grid),
            Net::Plain(c) => {
                ctrl.push(c);
                out.extend_from_slice(&grid);
                ctrl_run.push(run);
            }
            Net::Edge(c) => {
                edge_nets.push(*c);
                edge_out.extend_from_slice(&grid);
                edge_run.push(run);
            }
        }
    }
    let (rings, span) = ring_groups.finish(runs);
    ClaimedPatches {
        ctrl,
        out,
        ctrl_run,
        edge_nets,
        edge_out,
        edge_run,
        rings,
        span,
    }
}

impl PatchLayer {
    /// The patches of depth `levels.len()` on the faces of `levels[0]` (refined with
    /// `options`, step `s` from `levels[0]` with the masks of step `s` of `steps`): every
    /// face that can be one ([`face_patch`]) and writes at least one output vertex not yet
    /// in `claims` (which it then claims).
    pub(super) fn build(
        levels: &[Topology],
        source: usize,
        claims: &mut Claims,
        options: &Options,
        steps: Steps,
    ) -> Self {
        let depth = levels.len() as u32;
        let runs = levels[0].num_faces().div_ceil(RUN);
        let found = find_patches(levels, claims, options.crease_method, steps);
        let (found, kernels) = with_ring_grids(found, depth, options, steps);
        let sorted = claim_patches(found, claims, &kernels, runs, subset_rows(steps));
        let mut layer = PatchLayer {
            depth,
            source,
            runs,
            span: sorted.span,
            ctrl: sorted.ctrl,
            ctrl_runs: Runs::new(&sorted.ctrl_run, runs),
            out: sorted.out,
            edge_nets: sorted.edge_nets,
            edge_out: sorted.edge_out,
            edge_runs: Runs::new(&sorted.edge_run, runs),
            rings: sorted.rings,
            // The bicubic kernel's, for the regular patches of the Catmull-Clark family.
            w: match steps {
                Steps::Family(mixed) if depth <= QUAD_DEPTH => weights(depth, mixed),
                _ => Vec::new(),
            },
            bounds: [0, 0],
        };
        layer.set_bounds();
        layer
    }

    fn set_bounds(&mut self) {
        let end = |i: u32| i as usize + 1;
        self.bounds = [
            self.control_vertices().map(end).max().unwrap_or(0),
            (self.out.iter().chain(&self.edge_out))
                .chain(&self.rings.out)
                .filter(|&&o| o != NOT_OWNED)
                .map(|&o| end(o))
                .max()
                .unwrap_or(0),
        ];
    }

    /// Levels refined within each patch.
    #[cfg(test)]
    pub(super) fn depth(&self) -> u32 {
        self.depth
    }

    /// Every source vertex that the patches read (with repetitions).
    pub(super) fn control_vertices(&self) -> impl Iterator<Item = u32> + '_ {
        let edge = self.edge_nets.iter().flatten().flat_map(cell_verts);
        let rings = &self.rings.ctrl;
        self.ctrl.iter().flatten().chain(edge).chain(rings).copied()
    }

    /// Number of patches.
    pub(super) fn len(&self) -> usize {
        self.ctrl.len() + self.edge_nets.len() + self.rings.len()
    }

    /// Bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        64 * self.ctrl.len()
            + 4 * self.out.len()
            + self.ctrl_runs.memory_bytes()
            + self.edge_runs.memory_bytes()
            + std::mem::size_of::<[Cell; 16]>() * self.edge_nets.len()
            + 4 * self.edge_out.len()
            + self.rings.memory_bytes()
            + 32 * self.w.len()
    }

    /// Renumbers the control vertices through `map` (the position of each vertex in the
    /// subset level that holds it).
    pub(super) fn remap(&mut self, map: &[u32]) {
        for c in self.ctrl.iter_mut().flatten() {
            *c = map[*c as usize];
        }
        for c in self.edge_nets.iter_mut().flatten() {
            for v in &mut c.verts[..c.len] {
                *v = map[*v as usize];
            }
        }
        for c in &mut self.rings.ctrl {
            *c = map[*c as usize];
        }
        self.set_bounds();
    }

    /// Writes every owned grid point of every patch into `out`, from the values `src`
    /// of the patches' level.
    pub(super) fn apply<const D: usize>(&self, src: &[[f64; D]], out: &mut [[f64; D]]) {
        // Every index the kernels use is in bounds (they do not check each one).
        assert!(self.bounds[0] <= src.len() && self.bounds[1] <= out.len());
        let dst = SharedOut(out.as_mut_ptr());
        let rings_only = self.ctrl.is_empty() && self.edge_nets.is_empty();
        match self.depth {
            // Ring patches only: every layer of Loop and bilinear, and a Catmull-Clark
            // layer past `QUAD_DEPTH` (`face_patch`).
            _ if rings_only => self.run(src, &dst, |_| {}),
            2 => self.run(src, &dst, |r| self.plain_and_edge::<5, 25, D>(r, src, &dst)),
            3 => self.run(src, &dst, |r| self.plain_and_edge::<9, 81, D>(r, src, &dst)),
            d => unreachable!("regular patches of depth {d}"),
        }
    }

    /// Runs `plain` on every run of faces and the ring patches of each unit of work.
    fn run<const D: usize>(
        &self,
        src: &[[f64; D]],
        dst: &SharedOut<[f64; D]>,
        plain: impl Fn(usize) + Sync,
    ) {
        let body = |unit: usize| {
            for r in unit * self.span..((unit + 1) * self.span).min(self.runs) {
                plain(r);
            }
            // SAFETY: indices checked by `apply`; each output written once (`SharedOut`).
            unsafe { self.rings.apply(unit, src, dst) };
        };
        let units = self.runs.div_ceil(self.span);
        if units <= 1 || rayon::current_num_threads() == 1 {
            (0..units).for_each(body);
        } else {
            (0..units).into_par_iter().for_each(body);
        }
    }

    /// The plain and edge patches of run `r`.
    fn plain_and_edge<const N: usize, const NN: usize, const D: usize>(
        &self,
        r: usize,
        src: &[[f64; D]],
        dst: &SharedOut<[f64; D]>,
    ) {
        let w: &[[f64; 4]; N] = self.w.as_slice().try_into().expect("kernel size");
        let run = self.ctrl_runs.range(r);
        let (ctrl, grids) = (
            &self.ctrl[run.clone()],
            &self.out[run.start * NN..run.end * NN],
        );
        // SAFETY: indices checked by `apply`; each output written once (`SharedOut`).
        unsafe { patches::<N, NN, D>(w, src, ctrl, grids, dst) };
        // Edge patches: the nets of up to `LOCAL` patches evaluated into an array on
        // the stack (nothing is allocated), then the same kernel over it.
        let run = self.edge_runs.range(r);
        let nets = &self.edge_nets[run.clone()];
        let grids = &self.edge_out[run.start * NN..run.end * NN];
        for (nets, grids) in nets.chunks(LOCAL).zip(grids.chunks(LOCAL * NN)) {
            let mut local = [[[0.0; D]; 16]; LOCAL];
            for (l, net) in local.iter_mut().zip(nets) {
                *l = net.each_ref().map(|c| c.eval(src));
            }
            let local = local.as_flattened();
            // SAFETY: `LOCAL_CTRL` indexes `local`; outputs as above.
            unsafe { patches::<N, NN, D>(w, local, &LOCAL_CTRL[..nets.len()], grids, dst) };
        }
    }
}

/// Edge patches evaluated together into one local array.
const LOCAL: usize = 16;

/// The control indices of the local patches: patch `p`'s net at `16 p .. 16 p + 16`.
const LOCAL_CTRL: [[u32; 16]; LOCAL] = {
    let mut ctrl = [[0u32; 16]; LOCAL];
    let mut i = 0;
    while i < 16 * LOCAL {
        ctrl[i / 16][i % 16] = i as u32;
        i += 1;
    }
    ctrl
};

/// The output array, written by several patches at once at distinct indices.
pub(super) struct SharedOut<T>(pub(super) *mut T);

// SAFETY: every output index appears at most once over all patches of a plan (they are
// claimed in `PatchLayer::build`), so concurrent writers never touch the same element.
unsafe impl<T: Send> Sync for SharedOut<T> {}

/// Runs the kernel on a run of patches: for positions, [`patches_avx512`] when the
/// processor has AVX-512F, else [`patches_avx`] when it has AVX2 and FMA (detected at run
/// time: the default x86-64 target has none of them); else [`kernel`].
///
/// # Safety
/// Every control index is in bounds of `src`, every grid index is [`NOT_OWNED`] or in
/// bounds of `out`, and no other thread writes the same output indices.
unsafe fn patches<const N: usize, const NN: usize, const D: usize>(
    w: &[[f64; 4]; N],
    src: &[[f64; D]],
    ctrl: &[[u32; 16]],
    grids: &[u32],
    out: &SharedOut<[f64; D]>,
) {
    #[cfg(target_arch = "x86_64")]
    if D == 3 && has_avx2_fma() {
        // SAFETY: the features were just detected; `D == 3`; the caller's bounds.
        unsafe {
            if has_avx512f() {
                patches_avx512::<N, NN>(w, src.as_ptr().cast(), ctrl, grids, out.0.cast());
            } else {
                patches_avx::<N, NN>(w, src.as_ptr().cast(), ctrl, grids, out.0.cast());
            }
        }
        return;
    }
    for (k, (c, g)) in ctrl.iter().zip(grids.chunks_exact(NN)).enumerate() {
        // SAFETY: the caller's.
        unsafe {
            prefetch_next::<D>(grids, k, NN, out.0.cast());
            kernel::<N, NN, D>(w, src, c, g.try_into().expect("grid size"), out);
        }
    }
}

/// Asks the processor to start loading the cache lines that patch `k + 1` of `grids` (`nn`
/// points per patch) will write (its owned points in `out`, `D` doubles each), while
/// patch `k` is computed.
///
/// The outputs of one patch lie in a few dozen separate runs of the output array (the
/// child numbering puts vertex, face and edge children of each level apart), too many
/// streams for the hardware prefetcher, so without this each patch waits on its stores'
/// cache misses (BENCHMARKS.md, "Re-posing", has the gain); prefetching two patches
/// ahead is slower. A hint only: it never faults, and on other
/// processors than x86-64 it is nothing.
///
/// # Safety
/// Every grid index is [`NOT_OWNED`] or in bounds of `out` (as [`patches`]).
#[inline(always)]
pub(super) unsafe fn prefetch_next<const D: usize>(
    grids: &[u32],
    k: usize,
    nn: usize,
    out: *mut f64,
) {
    #[cfg(target_arch = "x86_64")]
    if let Some(next) = grids.get((k + 1) * nn..(k + 2) * nn) {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        for &o in next {
            // Without a branch (which the pattern of owned points would mispredict):
            // points not owned prefetch the start of `out` instead.
            let o = if o == NOT_OWNED { 0 } else { o as usize };
            // SAFETY: `o` is 0 or in bounds of `out` (the caller's); SSE is part of x86-64.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(out.add(D * o).cast()) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (grids, k, nn, out);
}

/// The kernel for positions (three components, each point one 256-bit vector with a
/// zero fourth lane) with fused multiply-adds: about 15 % faster than [`kernel`]
/// compiled for the default target, and it keeps the 16 control points in registers.
///
/// # Safety
/// As [`patches`], with `src` and `out` pointing at `[f64; 3]` values; the processor
/// has AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn patches_avx<const N: usize, const NN: usize>(
    w: &[[f64; 4]; N],
    src: *const f64,
    ctrl: &[[u32; 16]],
    grids: &[u32],
    out: *mut f64,
) {
    use std::arch::x86_64::*;
    // SAFETY (whole body): the caller's bounds.
    unsafe {
        for (k, (c, g)) in ctrl.iter().zip(grids.chunks_exact(NN)).enumerate() {
            prefetch_next::<3>(grids, k, NN, out);
            prefetch_ctrl(ctrl, k, src);
            // Along u, one column of control points at a time.
            let mut t = [[_mm256_setzero_pd(); N]; 4];
            for (j, tj) in t.iter_mut().enumerate() {
                let q = [0, 1, 2, 3].map(|i| load_point(src, c[4 * i + j]));
                for (x, txj) in tj.iter_mut().enumerate() {
                    *txj = combine(&w[x], q);
                }
            }
            // Along v, for the owned points only.
            for x in 0..N {
                let col = [t[0][x], t[1][x], t[2][x], t[3][x]];
                for y in 0..N {
                    let o = g[x * N + y];
                    if o != NOT_OWNED {
                        store_point(out, o, combine(&w[y], col));
                    }
                }
            }
        }
    }
}

/// Asks the processor to start loading the control points of patch `k + 2` of `ctrl`
/// (in `src`, `[f64; 3]` values): they lie anywhere in the level's positions, and
/// without this the kernels wait on their loads (BENCHMARKS.md, "Re-posing"); one patch
/// ahead is too late to help.
///
/// # Safety
/// Every control index is in bounds of `src` (a hint only: it never faults).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn prefetch_ctrl(ctrl: &[[u32; 16]], k: usize, src: *const f64) {
    use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
    if let Some(next) = ctrl.get(k + 2) {
        for &i in next {
            // SAFETY: `i` is in bounds of `src` (the caller's); SSE is part of x86-64.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(src.add(3 * i as usize).cast()) };
        }
    }
}

/// Point `c` of `src` (`[f64; 3]` values) in the low lanes of a 256-bit vector, the
/// fourth zero, read without touching the next point: two loads and an insert, not
/// [`crate::cpu::load3`]'s masked load, which is slower here (the tree rows of limit
/// evaluation are faster with it).
///
/// # Safety
/// `c` is in bounds of `src`; the processor has AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
unsafe fn load_point(src: *const f64, c: u32) -> std::arch::x86_64::__m256d {
    use std::arch::x86_64::*;
    // SAFETY: three doubles in bounds (the caller's).
    unsafe {
        let p = src.add(3 * c as usize);
        _mm256_insertf128_pd::<1>(
            _mm256_castpd128_pd256(_mm_loadu_pd(p)),
            _mm_load_sd(p.add(2)),
        )
    }
}

/// `w[0] q[0] + w[1] q[1] + w[2] q[2] + w[3] q[3]`, summed in that order with fused
/// multiply-adds (the first a product).
///
/// # Safety
/// The processor has AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn combine(w: &[f64; 4], q: [std::arch::x86_64::__m256d; 4]) -> std::arch::x86_64::__m256d {
    use std::arch::x86_64::*;
    let a = _mm256_mul_pd(_mm256_broadcast_sd(&w[0]), q[0]);
    let a = _mm256_fmadd_pd(_mm256_broadcast_sd(&w[1]), q[1], a);
    let a = _mm256_fmadd_pd(_mm256_broadcast_sd(&w[2]), q[2], a);
    _mm256_fmadd_pd(_mm256_broadcast_sd(&w[3]), q[3], a)
}

/// Writes the low three lanes of `v` to point `o` of `out` (`[f64; 3]` values).
///
/// # Safety
/// `o` is in bounds of `out`; the processor has AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
unsafe fn store_point(out: *mut f64, o: u32, v: std::arch::x86_64::__m256d) {
    // SAFETY: three doubles in bounds (the caller's).
    unsafe { crate::cpu::store3(out.add(3 * o as usize), v) }
}

/// [`patches_avx`] with AVX-512, by component: lane `x` of a 512-bit vector holds grid
/// row `x < 8`, so the pass along `u` is four multiply-adds per column of control points
/// and component for eight rows at once, and the pass along `v` four per grid column and
/// component, each broadcasting its scalar (a control point's component, a weight)
/// straight from memory. Row 8 (at depth 3) is computed as in [`patches_avx`]. The sums
/// are the same, in the same order: the results are bit for bit those of [`patches_avx`]
/// (test `avx_kernel_agrees`).
///
/// [`patches_avx`] holds one point per 256-bit vector (a lane of four unused), and its
/// pass along `v` broadcasts four weights and does four multiply-adds per point; here it
/// is twelve multiply-adds (with their broadcasts folded in) per eight points, 8–16 %
/// less apply time (BENCHMARKS.md, "Re-posing"). Compiling [`patches_avx`] itself with
/// AVX-512 enabled (32 registers, broadcasts folded into the multiply-adds) was slower:
/// the compiler kept the 36 weights in registers and spilled the sums instead.
///
/// # Safety
/// As [`patches_avx`]; the processor has AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2,fma")]
unsafe fn patches_avx512<const N: usize, const NN: usize>(
    w: &[[f64; 4]; N],
    src: *const f64,
    ctrl: &[[u32; 16]],
    grids: &[u32],
    out: *mut f64,
) {
    use super::plan_ring::{any_owned, store_eight};
    use std::arch::x86_64::*;
    const LANES: usize = 8;
    let rows = N.min(LANES);
    let mut scratch = [0.0f64; 3];
    // SAFETY (whole body): the caller's bounds.
    unsafe {
        // Column i of W over the rows x < 8 (zero past N).
        let wcol: [__m512d; 4] = std::array::from_fn(|i| {
            let mut a = [0.0; LANES];
            for (a, w) in a.iter_mut().zip(w) {
                *a = w[i];
            }
            _mm512_loadu_pd(a.as_ptr())
        });
        for (k, (c, g)) in ctrl.iter().zip(grids.chunks_exact(NN)).enumerate() {
            prefetch_next::<3>(grids, k, NN, out);
            prefetch_ctrl(ctrl, k, src);
            // Along u: t[j][l], component l of column j over the rows x < 8.
            let mut t = [[_mm512_setzero_pd(); 3]; 4];
            for (j, tj) in t.iter_mut().enumerate() {
                let q = [0, 1, 2, 3].map(|i| src.add(3 * c[4 * i + j] as usize));
                for (l, tjl) in tj.iter_mut().enumerate() {
                    let a = _mm512_mul_pd(wcol[0], _mm512_set1_pd(*q[0].add(l)));
                    let a = _mm512_fmadd_pd(wcol[1], _mm512_set1_pd(*q[1].add(l)), a);
                    let a = _mm512_fmadd_pd(wcol[2], _mm512_set1_pd(*q[2].add(l)), a);
                    *tjl = _mm512_fmadd_pd(wcol[3], _mm512_set1_pd(*q[3].add(l)), a);
                }
            }
            // Along v, one grid column y at a time, its rows x < 8 together; a half
            // (four rows) none of whose points the patch owns is not written.
            for (y, wy) in w.iter().enumerate() {
                let mut to = [NOT_OWNED; LANES];
                for (x, to) in to.iter_mut().enumerate().take(rows) {
                    *to = g[x * N + y];
                }
                let (low, high) = (any_owned(&to[..4]), any_owned(&to[4..]));
                if !(low || high) {
                    continue;
                }
                let [vx, vy, vz] = [0, 1, 2].map(|l| {
                    let a = _mm512_mul_pd(_mm512_set1_pd(wy[0]), t[0][l]);
                    let a = _mm512_fmadd_pd(_mm512_set1_pd(wy[1]), t[1][l], a);
                    let a = _mm512_fmadd_pd(_mm512_set1_pd(wy[2]), t[2][l], a);
                    _mm512_fmadd_pd(_mm512_set1_pd(wy[3]), t[3][l], a)
                });
                store_eight(vx, vy, vz, &to, [low, high], out, &mut scratch);
            }
            // Row 8 (depth 3), one point at a time as in `patches_avx`.
            for x in LANES..N {
                let col: [__m256d; 4] = std::array::from_fn(|j| {
                    combine(&w[x], [0, 1, 2, 3].map(|i| load_point(src, c[4 * i + j])))
                });
                for (y, wy) in w.iter().enumerate() {
                    let o = g[x * N + y];
                    if o != NOT_OWNED {
                        store_point(out, o, combine(wy, col));
                    }
                }
            }
        }
    }
}

/// Computes the grid points of one patch (`W P Wᵀ`) and writes those it owns.
///
/// # Safety
/// As [`patches`].
#[inline(always)]
unsafe fn kernel<const N: usize, const NN: usize, const D: usize>(
    w: &[[f64; 4]; N],
    src: &[[f64; D]],
    ctrl: &[u32; 16],
    grid: &[u32; NN],
    out: &SharedOut<[f64; D]>,
) {
    let mix = |w: &[f64; 4], x: [&[f64; D]; 4]| -> [f64; D] {
        std::array::from_fn(|l| w[0] * x[0][l] + w[1] * x[1][l] + w[2] * x[2][l] + w[3] * x[3][l])
    };
    // Along u: t[j][x] = Σᵢ W[x][i] p[i][j].
    let t: [[[f64; D]; N]; 4] = std::array::from_fn(|j| {
        let q = [0, 1, 2, 3].map(|i| &src[ctrl[4 * i + j] as usize]);
        std::array::from_fn(|x| mix(&w[x], q))
    });
    // Along v, for the owned points only.
    for x in 0..N {
        for y in 0..N {
            let o = grid[x * N + y];
            if o != NOT_OWNED {
                let v = mix(&w[y], [&t[0][x], &t[1][x], &t[2][x], &t[3][x]]);
                // SAFETY: the caller's.
                unsafe { out.0.add(o as usize).write(v) };
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Units of work hold at least `RING_PATCHES_PER_KEY` ring patches per key on
    /// average (but the last, which may be shorter), unless that would leave fewer than
    /// `MIN_UNITS` units; never fewer than one run or more than all.
    #[test]
    fn ring_units_hold_several_patches_per_key() {
        // 20 k triangles in 79 runs: 110 keys need 4 runs per unit, 10 keys one.
        assert_eq!(ring_span(79, 110, 20_000), 4);
        assert_eq!(ring_span(79, 10, 20_000), 1);
        assert_eq!(ring_span(3, 500, 700), 1);
        assert_eq!(ring_span(0, 0, 0), 1);
        // A regular grid of 63 × 63 quads with four ring patches at its corners, and
        // a scan with a matrix for every 36 faces: 8 and 9 units.
        assert_eq!(ring_span(16, 1, 4), 2);
        assert_eq!(ring_span(391, 2752, 99_938), 48);
        for (runs, keys, patches) in [
            (79, 110, 20_000),
            (1000, 37, 250_000),
            (18, 218, 4608),
            (16, 1, 4),
            (391, 2752, 99_938),
            (3, 500, 700),
        ] {
            let span = ring_span(runs, keys, patches);
            // Per key and unit of `span` full runs (the last unit may be shorter).
            let per_key = patches as f64 / keys as f64 * span as f64 / runs as f64;
            let units = runs.div_ceil(span);
            let capped = span == (runs / MIN_UNITS).max(1);
            assert!(
                per_key >= RING_PATCHES_PER_KEY as f64 || capped,
                "{per_key}"
            );
            assert!(units >= MIN_UNITS.min(runs), "{units}");
        }
    }

    /// The kernel rows of depth 2 are the composed subdivision masks worked out by hand.
    #[test]
    fn depth_two_weights() {
        let w = weights(2, Mixed::CATMULL_CLARK);
        let expect = [
            [5.0 / 32.0, 22.0 / 32.0, 5.0 / 32.0, 0.0],
            [1.0 / 16.0, 10.0 / 16.0, 5.0 / 16.0, 0.0],
            [1.0 / 64.0, 31.0 / 64.0, 31.0 / 64.0, 1.0 / 64.0],
            [0.0, 5.0 / 16.0, 10.0 / 16.0, 1.0 / 16.0],
            [0.0, 5.0 / 32.0, 22.0 / 32.0, 5.0 / 32.0],
        ];
        assert_eq!(w, expect);
    }

    /// The AVX2 kernel for positions computes the portable kernel's sums within rounding
    /// (it fuses multiply-adds, the portable one does not), at depths 2 and 3, writing
    /// exactly the owned points (a point is owned unless its index plus the patch's
    /// number is a multiple of 3, 5 or 7, by patch); the AVX-512 kernel writes the AVX2
    /// kernel's values bit for bit (NaN where nothing is written).
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn avx_kernel_agrees() {
        fn check<const N: usize, const NN: usize>(depth: u32) {
            let w: [[f64; 4]; N] = weights(depth, Mixed::CATMULL_CLARK).try_into().unwrap();
            let src: Vec<[f64; 3]> = (0..64)
                .map(|i| {
                    let x = f64::from(i);
                    [
                        (0.9 * x).sin() * 2.5,
                        (0.4 * x).cos() - 0.05 * x,
                        1.0 / (2.0 + x),
                    ]
                })
                .collect();
            let ctrl: Vec<[u32; 16]> = (0..6u32)
                .map(|p| std::array::from_fn(|i| (7 * p + 5 * i as u32) % 64))
                .collect();
            let grids: Vec<u32> = (0..ctrl.len() * NN)
                .map(|i| {
                    let (p, j) = (i / NN, i % NN);
                    let skip = [3, 5, 7][p % 3];
                    if (j + p) % skip == 0 {
                        NOT_OWNED
                    } else {
                        i as u32
                    }
                })
                .collect();
            let n_out = ctrl.len() * NN;
            let run = |which: u8| {
                let mut out = vec![[f64::NAN; 3]; n_out];
                let dst = SharedOut(out.as_mut_ptr());
                let (s, o) = (src.as_ptr().cast(), dst.0.cast());
                // SAFETY: indices in bounds; the AVX2 kernel only where the processor has
                // its features.
                unsafe {
                    match which {
                        0 => {
                            for (c, g) in ctrl.iter().zip(grids.chunks_exact(NN)) {
                                kernel::<N, NN, 3>(&w, &src, c, g.try_into().unwrap(), &dst);
                            }
                        }
                        1 => patches_avx::<N, NN>(&w, s, &ctrl, &grids, o),
                        _ => patches_avx512::<N, NN>(&w, s, &ctrl, &grids, o),
                    }
                }
                out
            };
            let portable = run(0);
            let owned = grids.iter().filter(|&&o| o != NOT_OWNED).count();
            assert_eq!(portable.iter().filter(|p| !p[0].is_nan()).count(), owned);
            if !has_avx2_fma() {
                return;
            }
            let avx = run(1);
            for (i, (a, b)) in avx.iter().zip(&portable).enumerate() {
                for c in 0..3 {
                    let same = a[c].is_nan() && b[c].is_nan() || (a[c] - b[c]).abs() < 1e-14;
                    assert!(same, "depth {depth} point {i}: {a:?} against {b:?}");
                }
            }
            if !has_avx512f() {
                return;
            }
            let bits = |p: &Vec<[f64; 3]>| -> Vec<[u64; 3]> {
                p.iter().map(|x| x.map(f64::to_bits)).collect()
            };
            assert_eq!(bits(&run(2)), bits(&avx), "depth {depth}");
        }
        check::<5, 25>(2);
        check::<9, 81>(3);
    }

    /// Every row is a partition of unity and reproduces the parameter of its point (cubic
    /// B-splines reproduce linear functions, and so does the adjustable scheme's curve
    /// rule for any `c`): exactly for Catmull-Clark (dyadic weights), to rounding
    /// otherwise. `c = 0` is the control polygon: the points of the span lie on `p₀p₁`.
    #[test]
    fn weights_reproduce_linear_functions() {
        for c in [0.5, 0.0, 0.3, 0.8] {
            let scheme = Mixed::all(crate::scheme::adjustable::Adjustable::new(c).unwrap());
            let tol = if c == 0.5 { 0.0 } else { 1e-15 };
            for d in 1..=4 {
                let w = weights(d, scheme);
                assert_eq!(w.len(), (1 << d) + 1);
                for (k, row) in w.iter().enumerate() {
                    assert!((row.iter().sum::<f64>() - 1.0).abs() <= tol, "c {c}");
                    let t: f64 = row
                        .iter()
                        .zip([-1.0, 0.0, 1.0, 2.0])
                        .map(|(w, x)| w * x)
                        .sum();
                    assert!((t - k as f64 / (1 << d) as f64).abs() <= tol, "c {c}");
                    if c == 0.0 {
                        assert_eq!([row[0], row[3]], [0.0, 0.0], "c 0, depth {d}");
                    }
                }
            }
        }
    }
}
