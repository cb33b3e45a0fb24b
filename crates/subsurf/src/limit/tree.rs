//! Configuration trees: the local refinement of an irregular face, computed once for all
//! faces with the same neighbourhood, as weights on the face's control points.
//!
//! The limit surface over an irregular face depends linearly on the vertices of its
//! 1-ring (see [`super::local`]), through the local refinement that
//! [`LimitSurface`](super::LimitSurface) descends: each level refines the cut-out,
//! regular children become bicubic patches, irregular children are cut out again. All of
//! that is decided by the cut-out's *topology* (adjacency, tags, sharpness) alone; the
//! positions only flow through it. So the work is split, as OpenSubdiv's `Bfr` splits it
//! (its `SurfaceFactoryCache` and `PatchTree`):
//!
//! - per **configuration** (one per distinct cut-out topology, found by
//!   [`Topology::structure_key`]; most meshes have a few dozen), a [`Tree`] built lazily, as
//!   deep as evaluated points need: for every node, the cut-out topology of the node and,
//!   for each of its children, either the 16 control points of its bicubic patch or the
//!   child's cut-out points, as sparse weights on the node's points; and at each corner
//!   where the limit is taken from the corner analysis ([`super::corner`]), that
//!   analysis's vectors as weights on the node's points;
//! - per **face**, only its cut-out's positions, which flow down the tree: a batch of points
//!   on one face computes each node's points once ([`Tree::eval`]).
//!
//! The weights are those of the very refinement and corner analysis that the
//! position-based path runs: the refinement's sparse masks (`refine::refinement_rows`,
//! which the `RefinePlan` uses too), and the corner analysis applied to unit control points
//! ("stencils by evaluation on a basis"; it is linear in the positions): so the tree gives
//! the same surface, to rounding. No topology is built while evaluating, and nothing is
//! allocated per point.

use super::bspline::{self, Derivatives, Order};
use super::corner::{corner_limit, is_limit_corner, CornerLimit, SectorCache};
use super::crease_patch::{single_crease, CreaseBasis, CreasePatch};
use super::local::{cut_out_unbounded, Local, Reach, Region, Shape};
use super::patch::{regular_patch_cells, Cell};
use super::surface::{quadrant, MAX_DEPTH};
use crate::hash::FxHasher;
use crate::mesh::{Options, Topology};
use crate::refine::{refine_topology, refinement_rows};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hash, Hasher};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

/// Sparse rows of weights on a node's points (CSR).
#[derive(Debug, Default)]
pub(super) struct Rows {
    offsets: Vec<u32>,
    cols: Vec<u32>,
    weights: Vec<f64>,
}

impl Rows {
    fn new() -> Self {
        Rows {
            offsets: vec![0],
            ..Rows::default()
        }
    }

    /// The refinement of `t` into `child` (its `refine_topology`): row `c` holds the
    /// weights of child vertex `c` on the vertices of `t` (sparse, from the refinement's
    /// masks: `O(weights)`, where interpolating unit vectors costs `O(vertices²)`, which
    /// dominated building the trees of faces next to vertices of high valence).
    fn refinement(t: &Topology, child: &Topology, options: &Options) -> Self {
        let mut rows = Rows::new();
        refinement_rows(t, child, options, |cols, weights| {
            for (&c, &w) in cols.iter().zip(weights) {
                if w != 0.0 {
                    rows.cols.push(c);
                    rows.weights.push(w);
                }
            }
            rows.offsets.push(rows.cols.len() as u32);
        });
        rows
    }

    /// The rows without the spare capacity of their growth (a tree keeps them; they were
    /// a quarter of a surface's memory on meshes of many configurations).
    fn shrunk(mut self) -> Self {
        self.offsets.shrink_to_fit();
        self.cols.shrink_to_fit();
        self.weights.shrink_to_fit();
        self
    }

    /// Adds `w ×` row `r` to `acc`.
    fn add_row_to(&self, r: usize, w: f64, acc: &mut Accumulator) {
        let (a, b) = (self.offsets[r] as usize, self.offsets[r + 1] as usize);
        for (&c, &x) in self.cols[a..b].iter().zip(&self.weights[a..b]) {
            acc.add(c, w * x);
        }
    }

    fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Row `r` applied to `pos`.
    #[inline]
    fn apply_row(&self, r: usize, pos: &[[f64; 3]]) -> [f64; 3] {
        let (a, b) = (self.offsets[r] as usize, self.offsets[r + 1] as usize);
        let mut acc = [0.0; 3];
        for (&c, &w) in self.cols[a..b].iter().zip(&self.weights[a..b]) {
            let p = &pos[c as usize];
            acc[0] += w * p[0];
            acc[1] += w * p[1];
            acc[2] += w * p[2];
        }
        acc
    }

    /// Every row applied to `pos`, into `out`.
    fn apply(&self, pos: &[[f64; 3]], out: &mut Vec<[f64; 3]>) {
        out.resize(self.len(), [0.0; 3]);
        self.apply_rows(pos, out);
    }

    /// The 16 rows of a patch applied to `pos`: `cp[i][j]` is row `4 i + j`.
    fn patch(&self, pos: &[[f64; 3]]) -> [[[f64; 3]; 4]; 4] {
        let mut cp = [[[0.0; 3]; 4]; 4];
        self.apply_rows(pos, cp.as_flattened_mut());
        cp
    }

    /// The first `out.len()` rows applied to `pos`, into `out`: with AVX2 and FMA where the
    /// processor has them (a point's three coordinates in one vector, one multiply-add per
    /// weight; the descent of a tree spends most of its time here), else
    /// [`apply_row`](Self::apply_row).
    fn apply_rows(&self, pos: &[[f64; 3]], out: &mut [[f64; 3]]) {
        #[cfg(target_arch = "x86_64")]
        if crate::cpu::has_avx2_fma() {
            // SAFETY: the features were just detected.
            unsafe { self.apply_rows_avx(pos, out) };
            return;
        }
        for (r, o) in out.iter_mut().enumerate() {
            *o = self.apply_row(r, pos);
        }
    }

    /// [`apply_rows`](Self::apply_rows) with AVX2 and FMA.
    ///
    /// # Safety
    /// The processor has AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn apply_rows_avx(&self, pos: &[[f64; 3]], out: &mut [[f64; 3]]) {
        use std::arch::x86_64::*;
        for (r, o) in out.iter_mut().enumerate() {
            let (a, b) = (self.offsets[r] as usize, self.offsets[r + 1] as usize);
            let mut acc = _mm256_setzero_pd();
            for (&c, &w) in self.cols[a..b].iter().zip(&self.weights[a..b]) {
                let p = &pos[c as usize];
                // SAFETY: `p` holds three `f64`: two loaded at its start, one at its end.
                let x = unsafe {
                    let xy = _mm_loadu_pd(p.as_ptr());
                    let z = _mm_load_sd(p.as_ptr().add(2));
                    _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(xy), z)
                };
                acc = _mm256_fmadd_pd(_mm256_set1_pd(w), x, acc);
            }
            let mut lanes = [0.0; 4];
            // SAFETY: `lanes` holds four `f64`.
            unsafe { _mm256_storeu_pd(lanes.as_mut_ptr(), acc) };
            *o = [lanes[0], lanes[1], lanes[2]];
        }
    }
}

/// A sparse row being summed: a dense array over the node's points, with the columns
/// touched, so that emptying it costs the row's length, not the node's size.
struct Accumulator {
    dense: Vec<f64>,
    /// Whether a column is in `touched`.
    seen: Vec<bool>,
    touched: Vec<u32>,
}

impl Accumulator {
    fn new(n: usize) -> Self {
        Accumulator {
            dense: vec![0.0; n],
            seen: vec![false; n],
            touched: Vec::new(),
        }
    }

    #[inline]
    fn add(&mut self, c: u32, w: f64) {
        if !std::mem::replace(&mut self.seen[c as usize], true) {
            self.touched.push(c);
        }
        self.dense[c as usize] += w;
    }

    /// Appends the row (by column, zero weights dropped) to `rows` and empties it.
    fn push_into(&mut self, rows: &mut Rows) {
        self.touched.sort_unstable();
        for &c in &self.touched {
            self.seen[c as usize] = false;
            let w = std::mem::take(&mut self.dense[c as usize]);
            if w != 0.0 {
                rows.cols.push(c);
                rows.weights.push(w);
            }
        }
        self.touched.clear();
        rows.offsets.push(rows.cols.len() as u32);
    }
}

/// A child of a tree node.
#[derive(Debug)]
pub(super) enum Kid {
    /// No surface.
    Hole,
    /// A bicubic patch: its 16 control points as weights on the node's points.
    Regular(Rows),
    /// A single-crease patch ([`CreasePatch`]): its 16 control points as weights on the
    /// node's points, its crease side and basis.
    Crease(Rows, usize, Arc<CreaseBasis>),
    /// Irregular: the child's cut-out, built when a point first reaches the child (see
    /// [`TNode::kids`]).
    Irregular(OnceLock<Box<SubTree>>),
}

/// An irregular child: its cut-out points as weights on its parent's points, and its node.
#[derive(Debug)]
pub(super) struct SubTree {
    rows: Rows,
    node: TNode,
}

impl Kid {
    /// The control points of a regular kid whose node's points are `pos`.
    pub fn patch(&self, pos: &[[f64; 3]]) -> Option<[[[f64; 3]; 4]; 4]> {
        match self {
            Kid::Regular(rows) => Some(rows.patch(pos)),
            _ => None,
        }
    }

    /// The control net `cp[i][j]` of a crease kid whose node's points are `pos`.
    pub fn crease_net(&self, pos: &[[f64; 3]]) -> Option<[[[f64; 3]; 4]; 4]> {
        match self {
            Kid::Crease(rows, ..) => Some(rows.patch(pos)),
            _ => None,
        }
    }

    /// The single-crease patch of a crease kid whose node's points are `pos`.
    pub fn crease_patch(&self, pos: &[[f64; 3]]) -> Option<CreasePatch> {
        match self {
            Kid::Crease(rows, side, basis) => Some(CreasePatch::from_net(
                &rows.patch(pos),
                *side,
                basis.clone(),
            )),
            _ => None,
        }
    }
}

/// A node: an (irregular) face of a cut-out.
#[derive(Debug)]
pub(super) struct TNode {
    topo: Topology,
    face: usize,
    /// Whether single-crease children are [`Kid::Crease`] (else refined further).
    crease: bool,
    /// Corners where the limit comes from [`corner_limit`] ([`is_limit_corner`]).
    stop: [bool; 4],
    kids: OnceLock<Box<[Kid]>>,
    /// Boxed: most nodes never analyse a corner (only points exactly at one do), and the
    /// four inline took 640 of a node's 1,160 bytes (11 % of the surface on irregular
    /// triangulations, when nearly every triangle had a tree of its own).
    corners: [OnceLock<Box<CornerRows>>; 4],
}

/// A corner analysis as weights: for each node point, its weights in the five linear
/// vectors of [`CornerLimit`] (`p, a, b, t1, t2`).
#[derive(Debug)]
struct CornerRows {
    limit: CornerLimit,
    weights: Vec<[f64; 5]>,
}

impl CornerRows {
    fn eval(&self, pos: &[[f64; 3]]) -> Derivatives {
        let mut v = [[0.0; 3]; 5];
        for (w, p) in self.weights.iter().zip(pos) {
            for (vi, &wi) in v.iter_mut().zip(w) {
                if wi != 0.0 {
                    (0..3).for_each(|k| vi[k] += wi * p[k]);
                }
            }
        }
        self.limit.with_vectors(v).finish()
    }
}

/// The tree of one configuration: its root is the cut-out of a base face.
#[derive(Debug)]
pub(super) struct Tree {
    root: TNode,
}

/// Trees by a hash of their root's [`Topology::structure_key`], each bucket compared key
/// by key: the keys are not kept (up to a few KiB each, one per configuration: 10 % of the
/// surface when nearly every triangle of an irregular triangulation had a configuration of
/// its own, before faces listed from other corners shared them), a candidate's is computed
/// again from its root's topology.
type TreeMap = HashMap<u64, Vec<Arc<Tree>>, BuildHasherDefault<FxHasher>>;

/// Configurations of one surface, by [`Topology::structure_key`].
#[derive(Debug, Default)]
pub(super) struct TreeCache {
    trees: Mutex<TreeMap>,
    /// Number of trees in `trees` (read without the lock while a surface is built, to stop
    /// a build over its memory limit).
    count: AtomicUsize,
    /// Refine single-crease faces further instead of using [`CreasePatch`] (tests compare).
    pub no_crease_patches: bool,
}

impl TreeCache {
    /// An empty cache; with `crease_patches` false, single-crease faces are refined
    /// further like any irregular face instead of becoming [`CreasePatch`]es.
    pub fn new(crease_patches: bool) -> Self {
        TreeCache {
            no_crease_patches: !crease_patches,
            ..TreeCache::default()
        }
    }

    /// The tree of the configuration whose root cut-out is `topo` (face 0), built the
    /// first time.
    pub fn get(&self, topo: Topology) -> Arc<Tree> {
        let mut key = Vec::new();
        topo.structure_key(&mut key);
        let hash = {
            let mut h = FxHasher::default();
            key.hash(&mut h);
            h.finish()
        };
        let lock = || match self.trees.lock() {
            Ok(m) => m,
            Err(poisoned) => poisoned.into_inner(),
        };
        // The candidates' keys are computed without the lock (other threads look up
        // meanwhile); a tree added since is looked for again under it.
        let seen = lock().get(&hash).cloned().unwrap_or_default();
        let mut other = Vec::new();
        let same = |tree: &Arc<Tree>, other: &mut Vec<u32>| {
            other.clear();
            tree.root.topo.structure_key(other);
            *other == key
        };
        if let Some(tree) = seen.iter().find(|t| same(t, &mut other)) {
            return tree.clone();
        }
        let mut map = lock();
        let bucket = map.entry(hash).or_default();
        if let Some(tree) = bucket[seen.len()..].iter().find(|t| same(t, &mut other)) {
            return tree.clone();
        }
        let tree = Arc::new(Tree {
            root: TNode::new(topo, 0, !self.no_crease_patches),
        });
        bucket.push(tree.clone());
        self.count.fetch_add(1, Ordering::Relaxed);
        tree
    }

    /// Number of configurations.
    pub fn len(&self) -> usize {
        self.count.load(Ordering::Relaxed)
    }
}

/// What an evaluation needs besides the points: the scheme options (to build tree levels)
/// and the derivatives to compute.
#[derive(Clone, Copy, Debug)]
pub(super) struct Ctx<'a> {
    /// Scheme options.
    pub options: &'a Options,
    /// Derivatives to compute.
    pub order: Order,
    /// The base mesh's control points, which [`Node::Plain`](super::surface::Node) patches
    /// (base faces only) gather theirs from.
    pub pos: &'a [[f64; 3]],
    /// The base mesh's topology, from which those patches find their nets.
    pub topo: &'a Topology,
    /// The surface's eigen-analyses of corner sectors.
    pub sectors: &'a SectorCache,
}

/// One point to evaluate: its parameter in the current node, and where its result goes.
#[derive(Clone, Copy, Debug)]
pub(super) struct Query {
    /// Parameter along `u`.
    pub u: f64,
    /// Parameter along `v`.
    pub v: f64,
    /// Index of the result.
    pub out: u32,
}

/// Buffers reused from one evaluation to the next: the points of each level of the
/// descent.
#[derive(Debug, Default)]
pub(super) struct Scratch {
    levels: Vec<Vec<[f64; 3]>>,
}

impl Tree {
    /// The root's children (sub-faces of an `n`-gon root; quadrants of a quad).
    pub fn root_kids(&self, options: &Options) -> &[Kid] {
        self.root.kids(options, |_| false)
    }

    /// Evaluates `queries` on the face whose cut-out points are `pos` — on sub-face `sub`
    /// of an `n`-gon, or on the quad itself (`None`, then `depth` levels below the base
    /// face whose parameters the derivatives are scaled to) — writing each result into
    /// `sink`. Reorders `queries`.
    #[allow(clippy::too_many_arguments)]
    pub fn eval(
        &self,
        pos: &[[f64; 3]],
        sub: Option<usize>,
        queries: &mut [Query],
        depth: u32,
        scratch: &mut Scratch,
        ctx: Ctx<'_>,
        sink: &mut impl Sink,
    ) {
        match sub {
            None => descend(&self.root, pos, queries, depth, scratch, ctx, sink),
            Some(j) => {
                let kids = self.root.kids(ctx.options, |k| k == j);
                // The sub-face is its own parameter domain: depth 0, no rescaling.
                let kid = kids.get(j).map(|kid| (kid, &self.root, j));
                kid_eval(kid, pos, queries, 0, scratch, ctx, sink);
            }
        }
    }
}

/// Where [`Tree::eval`] writes the result of each query (by its `out`).
pub(super) trait Sink {
    /// Where the derivatives of query `k` go (every field is overwritten).
    fn slot(&mut self, k: u32) -> &mut Derivatives;
    /// Query `k` has no surface (it lies on a hole).
    fn hole(&mut self, k: u32);
}

/// The queries of one patch, as a [`bspline::Batch`] writing into a [`Sink`].
pub(super) struct Leaf<'a, S> {
    /// The queries.
    pub qs: &'a [Query],
    /// Where their results go.
    pub sink: &'a mut S,
}

impl<S: Sink> bspline::Batch for Leaf<'_, S> {
    fn len(&self) -> usize {
        self.qs.len()
    }
    fn uv(&self, i: usize) -> (f64, f64) {
        (self.qs[i].u, self.qs[i].v)
    }
    fn out(&mut self, i: usize) -> &mut Derivatives {
        self.sink.slot(self.qs[i].out)
    }
}

/// Evaluates `qs` on `node` (at `depth`, points `pos`).
fn descend(
    node: &TNode,
    pos: &[[f64; 3]],
    qs: &mut [Query],
    depth: u32,
    scratch: &mut Scratch,
    ctx: Ctx<'_>,
    sink: &mut impl Sink,
) {
    // Points at a corner where the limit is known: the corner analysis.
    let rest = take_corners(
        qs,
        depth,
        |k| node.stop[k],
        |k, out| {
            *sink.slot(out) = node.corner(k, ctx.options, ctx.sectors).eval(pos);
        },
    );
    let qs = &mut qs[..rest];
    if qs.is_empty() {
        return;
    }
    let quadrants = by_quadrant(qs);
    let kids = node.kids(ctx.options, |k| !quadrants[k].is_empty());
    for (k, qs) in quadrants.into_iter().enumerate() {
        if !qs.is_empty() {
            let kid = kids.get(k).map(|kid| (kid, node, k));
            kid_eval(kid, pos, qs, depth + 1, scratch, ctx, sink);
        }
    }
}

/// The corner of a node, `depth` levels below its base face, whose limit analysis gives its
/// surface at `(u, v)`, if any: `(u, v)` is that corner and `stop` says the limit is known
/// there, or `MAX_DEPTH` is reached (then the corner of `(u, v)`'s quadrant).
fn corner_query(u: f64, v: f64, depth: u32, stop: impl Fn(usize) -> bool) -> Option<usize> {
    let corner = match (u, v) {
        (0.0, 0.0) => Some(0),
        (1.0, 0.0) => Some(1),
        (1.0, 1.0) => Some(2),
        (0.0, 1.0) => Some(3),
        _ if depth >= MAX_DEPTH => Some(quadrant(u, v).0),
        _ => None,
    };
    corner.filter(|&k| depth >= MAX_DEPTH || stop(k))
}

/// Answers each query of `qs` at a corner ([`corner_query`]) by `at(corner, query.out)` and
/// moves the others to the front, in order; returns how many those are.
pub(super) fn take_corners(
    qs: &mut [Query],
    depth: u32,
    stop: impl Fn(usize) -> bool,
    mut at: impl FnMut(usize, u32),
) -> usize {
    let mut rest = 0;
    for i in 0..qs.len() {
        let q = qs[i];
        match corner_query(q.u, q.v, depth, &stop) {
            Some(k) => at(k, q.out),
            None => {
                qs[rest] = q;
                rest += 1;
            }
        }
    }
    rest
}

/// `qs` split by quadrant ([`quadrant`]'s numbering: v < ½ with u < ½ then u ≥ ½, then
/// v ≥ ½ with u ≥ ½ then u < ½), each query's parameter mapped to its quadrant's. By three
/// partitions: linear, where a sort was 10 % of the evaluation of a cube's grid.
pub(super) fn by_quadrant(qs: &mut [Query]) -> [&mut [Query]; 4] {
    let low_v = partition(qs, |q| q.v < 0.5);
    let (low, high) = qs.split_at_mut(low_v);
    let low_u = partition(low, |q| q.u < 0.5);
    let high_u = partition(high, |q| q.u >= 0.5);
    let (q0, q1) = low.split_at_mut(low_u);
    let (q2, q3) = high.split_at_mut(high_u);
    let mut quadrants = [q0, q1, q2, q3];
    for q in quadrants.iter_mut().flat_map(|qs| qs.iter_mut()) {
        let (_, s, t) = quadrant(q.u, q.v);
        (q.u, q.v) = (s, t);
    }
    quadrants
}

/// Moves the elements of `s` for which `first` holds before the others (in no particular
/// order); returns how many there are.
fn partition<T>(s: &mut [T], first: impl Fn(&T) -> bool) -> usize {
    let mut n = 0;
    for i in 0..s.len() {
        if first(&s[i]) {
            s.swap(n, i);
            n += 1;
        }
    }
    n
}

/// Evaluates `qs` (parameters already in the kid's domain) on `kid`, a child at `depth`
/// of a node with points `pos`: `(kid, its parent, its index there)`.
fn kid_eval(
    kid: Option<(&Kid, &TNode, usize)>,
    pos: &[[f64; 3]],
    qs: &mut [Query],
    depth: u32,
    scratch: &mut Scratch,
    ctx: Ctx<'_>,
    sink: &mut impl Sink,
) {
    match kid {
        None | Some((Kid::Hole, ..)) => qs.iter().for_each(|q| sink.hole(q.out)),
        Some((Kid::Regular(rows), ..)) => {
            let cp = rows.patch(pos);
            let scale = 2f64.powi(depth as i32);
            let leaf = &mut Leaf { qs, sink };
            bspline::tensor_batch(&cp, bspline::regular_bases, ctx.order, scale, leaf);
        }
        Some((kid @ Kid::Crease(..), ..)) => {
            if let Some(patch) = kid.crease_patch(pos) {
                let scale = 2f64.powi(depth as i32);
                patch.eval_batch(ctx.order, scale, &mut Leaf { qs, sink });
            }
        }
        Some((Kid::Irregular(sub), parent, j)) => {
            let SubTree { rows, node } = &**sub.get_or_init(|| parent.build_sub(j, ctx.options));
            let d = depth as usize;
            if scratch.levels.len() <= d {
                scratch.levels.resize_with(d + 1, Vec::new);
            }
            let mut kpos = std::mem::take(&mut scratch.levels[d]);
            rows.apply(pos, &mut kpos);
            descend(node, &kpos, qs, depth, scratch, ctx, sink);
            scratch.levels[d] = kpos;
        }
    }
}

impl TNode {
    fn new(topo: Topology, face: usize, crease: bool) -> Self {
        let stop = std::array::from_fn(|k| {
            topo.face_vertices(face).len() == 4 && is_limit_corner(&topo, face, k)
        });
        TNode {
            topo,
            face,
            crease,
            stop,
            kids: OnceLock::new(),
            corners: Default::default(),
        }
    }

    /// The children (built the first time). Of the irregular ones, only those for which
    /// `wanted(k)` holds get their sub-tree now, the others when a point first reaches
    /// them ([`Self::build_sub`], which refines this node again): a grid's points
    /// reach the quadrants they reach every time, and on a face with an irregular corner
    /// the deepest corner child holds none of them (its corner's point is the parent's).
    /// Building it anyway took a fifth of the memory of the trees of meshes whose faces
    /// nearly all have configurations of their own.
    fn kids(&self, options: &Options, wanted: impl Fn(usize) -> bool) -> &[Kid] {
        self.kids.get_or_init(|| self.build_kids(options, wanted))
    }

    /// This node's refinement: the refined cut-out and the weights of its points on this
    /// node's.
    fn refine(&self, options: &Options) -> (Topology, Rows) {
        let child = refine_topology(&self.topo, options, true);
        let refinement = Rows::refinement(&self.topo, &child, options);
        (child, refinement)
    }

    /// The sub-tree of irregular child `j`.
    #[cold]
    #[inline(never)]
    fn build_sub(&self, j: usize, options: &Options) -> Box<SubTree> {
        let (child, refinement) = self.refine(options);
        let f = self.topo.face_offsets()[self.face] as usize + j;
        let mut acc = Accumulator::new(self.topo.num_vertices());
        self.sub_tree(&child, &refinement, f, &mut acc, options)
    }

    /// The sub-tree of face `f` of `child`, this node's refinement.
    fn sub_tree(
        &self,
        child: &Topology,
        refinement: &Rows,
        f: usize,
        acc: &mut Accumulator,
        options: &Options,
    ) -> Box<SubTree> {
        let faces = cut_out_unbounded(child, f, Reach::new(options).chaikin);
        let (sub, verts) = child.subset(&faces);
        let mut rows = Rows::new();
        for &v in &verts {
            refinement.add_row_to(v as usize, 1.0, acc);
            acc.push_into(&mut rows);
        }
        Box::new(SubTree {
            rows: rows.shrunk(),
            node: TNode::new(sub, 0, self.crease),
        })
    }

    fn build_kids(&self, options: &Options, wanted: impl Fn(usize) -> bool) -> Box<[Kid]> {
        let t = &self.topo;
        let (child, refinement) = self.refine(options);
        let first = t.face_offsets()[self.face] as usize;
        let size = t.face_vertices(self.face).len();
        let mut acc = Accumulator::new(t.num_vertices());
        (first..first + size)
            .map(|f| {
                if child.is_hole(f) {
                    return Kid::Hole;
                }
                let mut patch_rows = |cells: &[[Cell; 4]; 4]| {
                    let mut rows = Rows::new();
                    for cell in cells.iter().flatten() {
                        for (&v, &w) in cell.verts.iter().zip(&cell.weights).take(cell.len) {
                            refinement.add_row_to(v as usize, w, &mut acc);
                        }
                        acc.push_into(&mut rows);
                    }
                    rows.shrunk()
                };
                if let Some(cells) = regular_patch_cells(&child, f) {
                    return Kid::Regular(patch_rows(&cells));
                }
                if let Some((cells, side, s)) =
                    single_crease(&child, f, options).filter(|_| self.crease)
                {
                    return Kid::Crease(patch_rows(&cells), side, Arc::new(CreaseBasis::new(s)));
                }
                let sub = OnceLock::new();
                if wanted(f - first) {
                    let _ = sub.set(self.sub_tree(&child, &refinement, f, &mut acc, options));
                }
                Kid::Irregular(sub)
            })
            .collect()
    }

    /// The corner analysis at corner `k` as weights (computed the first time).
    fn corner(&self, k: usize, options: &Options, sectors: &SectorCache) -> &CornerRows {
        self.corners[k].get_or_init(|| {
            // Three unit control points at a time, one per coordinate: coordinate `c` of
            // each output vector is the weight of the point set to `e_c`.
            // The probes share one shape, which analyses the corner's sector (and refines
            // it, where that takes further levels) once for all of them.
            let n = self.topo.num_vertices();
            let shape = Shape::probed(self.topo.clone());
            let mut weights = vec![[0.0; 5]; n];
            let mut limit = CornerLimit::default();
            for c0 in (0..n).step_by(3) {
                let mut pos = vec![[0.0; 3]; n];
                for c in 0..3.min(n - c0) {
                    pos[c0 + c][c] = 1.0;
                }
                let local = Local {
                    region: Arc::new(Region::new(shape.clone(), pos)),
                    face: self.face,
                };
                limit = corner_limit(&local, k, options, sectors);
                let vs = limit.vectors();
                for c in 0..3.min(n - c0) {
                    weights[c0 + c] = vs.map(|v| v[c]);
                }
            }
            Box::new(CornerRows { limit, weights })
        })
    }
}
