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
//! - per **configuration** (one per distinct cut-out topology, found by its packed form,
//!   [`PackedTopology`]; most meshes have a few dozen), a [`Tree`] built lazily, as
//!   deep as evaluated points need: for every node, the cut-out topology of the node, the
//!   points of its refinement that its children read, as sparse weights on the node's
//!   points ([`Kids`]), and for each child either the net of its bicubic patch on those
//!   refined points or its own node, whose points are some of them; and at each corner
//!   where the limit is taken from the corner analysis ([`super::corner`]), that
//!   analysis's vectors as weights on the node's points;
//! - per **face**, only its cut-out's positions, which flow down the tree: a batch of points
//!   on one face computes each node's refined points once ([`Tree::eval`]).
//!
//! The weights are those of the very refinement and corner analysis that the
//! position-based path runs: the refinement's sparse masks (`refine::refinement_rows`,
//! which the `RefinePlan` uses too), and the corner analysis applied to unit control points
//! ("stencils by evaluation on a basis"; it is linear in the positions): so the tree gives
//! the same surface, to rounding. No topology is built while evaluating, and nothing is
//! allocated per point.

use super::bspline::{self, Derivatives, Order};
use super::configs::{Configs, Keyed};
use super::corner::{corner_limit, is_limit_corner, CornerLimit, SectorCache};
use super::crease_patch::{single_crease, CreaseBases, CreaseBasis, CreasePatch};
use super::local::{cut_out_unbounded, Local, Reach, Region, Shape};
use super::rows::{NodeRows, WeightPool};
use super::surface::{quadrant, MAX_DEPTH};
use super::Index;
use crate::mesh::{Options, PackedTopology, Topology};
use crate::refine::patch::{regular_patch_cells, Cell, Net};
use crate::refine::refine_topology;
use crate::scheme::adjustable::Adjustable;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

/// A child of a tree node, on its parent's refined points ([`Kids::rows`]).
#[derive(Debug)]
pub(super) enum Kid {
    /// No surface.
    Hole,
    /// A bicubic patch: its net on the refined points.
    Regular(KidNet),
    /// A single-crease patch ([`CreasePatch`]): its net on the refined points, its crease
    /// side and basis.
    Crease(KidNet, u8, Arc<CreaseBasis>),
    /// Irregular: the configuration of the child's cut-out and where its points are among
    /// the refined points, found when a point first reaches the child (see
    /// [`Tree::kids`]).
    Irregular(OnceLock<Sub>),
}

/// An irregular child: the tree of its cut-out's configuration, shared with every node
/// and face whose cut-out has the same (in canonical form, [`Topology::subset_canonical`]),
/// and where each of its cut-out's vertices is among its parent's refined points.
#[derive(Debug)]
pub(super) struct Sub {
    tree: Arc<Tree>,
    cols: Cols,
}

/// The net of a patch child: 8-bit indices of its parent's refined points, unless there
/// are more of those (a node holding a vertex of high valence). With 32-bit ones a child
/// took 96 bytes, and the children were 14 % of the heap of a grid with creases on a
/// tenth of its edges; with 16-bit ones 56, now 40.
#[derive(Debug)]
pub(super) enum KidNet {
    Narrow(Net<u8>),
    Wide(Box<Net>),
}

impl KidNet {
    fn new(net: Net) -> Self {
        match net.narrow() {
            Some(net) => KidNet::Narrow(net),
            None => KidNet::Wide(Box::new(net)),
        }
    }

    /// The control points for refined points `refined` (see [`Net::eval`]).
    fn eval(&self, refined: &[[f64; 3]]) -> [[[f64; 3]; 4]; 4] {
        let mut cp = [[[0.0; 3]; 4]; 4];
        self.eval_into(refined, &mut cp);
        cp
    }

    /// [`eval`](Self::eval) into `cp` (see [`Net::eval_into`]).
    fn eval_into(&self, refined: &[[f64; 3]], cp: &mut [[[f64; 3]; 4]; 4]) {
        match self {
            KidNet::Narrow(net) => net.eval_into(refined, cp),
            KidNet::Wide(net) => net.eval_into(refined, cp),
        }
    }

    /// The cells the net stands for.
    #[cfg(test)]
    fn cells(&self) -> [[Cell; 4]; 4] {
        match self {
            KidNet::Narrow(net) => net.cells(),
            KidNet::Wide(net) => net.cells(),
        }
    }
}

impl Kid {
    /// The control points of a regular kid whose parent's refined points are `refined`.
    pub(super) fn patch(&self, refined: &[[f64; 3]]) -> Option<[[[f64; 3]; 4]; 4]> {
        match self {
            Kid::Regular(net) => Some(net.eval(refined)),
            _ => None,
        }
    }

    /// The control net `cp[i][j]` of a crease kid whose parent's refined points are
    /// `refined`.
    pub(super) fn crease_net(&self, refined: &[[f64; 3]]) -> Option<[[[f64; 3]; 4]; 4]> {
        match self {
            Kid::Crease(net, ..) => Some(net.eval(refined)),
            _ => None,
        }
    }

    /// The single-crease patch of a crease kid whose parent's refined points are
    /// `refined`.
    pub(super) fn crease_patch(&self, refined: &[[f64; 3]]) -> Option<CreasePatch> {
        match self {
            Kid::Crease(net, side, basis) => Some(CreasePatch::from_net(
                &net.eval(refined),
                usize::from(*side),
                basis.clone(),
            )),
            _ => None,
        }
    }
}

/// A node's children and the refined points they read.
///
/// The points of the node's refinement that any child reads (the vertices of a patch's
/// net, of an irregular child's cut-out) are computed once per evaluation, as sparse rows
/// on the node's points; the children read them by index (a patch's cells) or as they are
/// (an irregular child's points gathered through [`Sub::cols`]). Composing each child's
/// rows with the refinement instead would repeat the refinement of the points that
/// neighbouring children share: about twice the weights to keep and to apply (see
/// `BENCHMARKS.md`, "Meshes with many creases").
///
/// The vertices of the node's refinement that the children read (`needed`, increasing:
/// [`Tree::find_kids`]) are not kept: a child reads its `k`th refined point as slot `k`,
/// and a child found later finds them again as it refines the node again
/// ([`Tree::build_sub`]). Kept, they were 8 % of the heap of a grid with creases on a
/// tenth of its edges.
#[derive(Debug)]
pub(super) struct Kids {
    /// Row `k`: refined vertex `needed[k]` as weights on the node's cut-out's points.
    rows: NodeRows,
    /// The children, by sub-face.
    kids: Box<[Kid]>,
}

impl Kids {
    /// The children.
    pub(super) fn kids(&self) -> &[Kid] {
        &self.kids
    }

    /// The refined points of a node evaluated on `pos`, into `out`.
    pub(super) fn refine_into(&self, pos: &[[f64; 3]], out: &mut Vec<[f64; 3]>) {
        self.rows.apply(pos, out);
    }

    /// The refined points of a node evaluated on `pos`.
    pub(super) fn refine(&self, pos: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let mut out = Vec::new();
        self.refine_into(pos, &mut out);
        out
    }
}

/// Where vertex `v` is in `needed` (increasing): a tree lists every vertex its children
/// read when it builds them, so a missing one is a broken invariant.
fn slot_of(needed: &[u32], v: u32) -> u32 {
    match needed.binary_search(&v) {
        Ok(k) => k as u32,
        Err(_) => unreachable!("a tree child reads a refined vertex its node does not compute"),
    }
}

/// [`Sub::cols`]: 16-bit positions when they fit (with 32-bit ones they were a tenth of
/// the heap of a grid with creases on a tenth of its edges).
#[derive(Debug)]
enum Cols {
    Narrow(Box<[u16]>),
    Wide(Box<[u32]>),
}

impl Cols {
    fn new(cols: Vec<u32>) -> Self {
        match cols.iter().map(|&c| u16::narrow(c)).collect() {
            Some(narrow) => Cols::Narrow(narrow),
            None => Cols::Wide(cols.into()),
        }
    }

    /// Where vertex `i` is.
    #[cfg(test)]
    fn get(&self, i: u32) -> u32 {
        match self {
            Cols::Narrow(c) => u32::from(c[i as usize]),
            Cols::Wide(c) => c[i as usize],
        }
    }

    /// The points at these positions of `refined`, into `out`.
    fn gather(&self, refined: &[[f64; 3]], out: &mut Vec<[f64; 3]>) {
        out.clear();
        match self {
            Cols::Narrow(c) => out.extend(c.iter().map(|&i| refined[usize::from(i)])),
            Cols::Wide(c) => out.extend(c.iter().map(|&i| refined[i as usize])),
        }
    }

    #[cfg(test)]
    fn len(&self) -> usize {
        match self {
            Cols::Narrow(c) => c.len(),
            Cols::Wide(c) => c.len(),
        }
    }
}

/// A corner analysis as weights: the five linear vectors of [`CornerLimit`]
/// (`p, a, b, t1, t2`) as sparse weights on the points the node is evaluated on. Sparse,
/// as the corner's limit reads only the points near it: stored for every vertex of the
/// cut-out, the weights were a tenth of the heap of a grid with creases on a tenth of its
/// edges.
#[derive(Debug)]
struct CornerRows {
    limit: CornerLimit,
    /// The points read (the cut-out's vertices with a nonzero weight).
    cols: Box<[u32]>,
    /// Their weights in the five vectors.
    weights: Box<[[f64; 5]]>,
}

impl CornerRows {
    /// The limit at the corner of a node evaluated on `pos`.
    fn eval(&self, pos: &[[f64; 3]]) -> Derivatives {
        let mut v = [[0.0; 3]; 5];
        for (w, &c) in self.weights.iter().zip(&*self.cols) {
            let p = pos[c as usize];
            for (vi, &wi) in v.iter_mut().zip(w) {
                if wi != 0.0 {
                    (0..3).for_each(|k| vi[k] += wi * p[k]);
                }
            }
        }
        self.limit.with_vectors(v).finish()
    }
}

/// The tree of one configuration: face 0 of cut-out `topo`, irregular, evaluated on the
/// cut-out's points in order. Its irregular children are trees too, shared with every
/// node and face whose cut-out has the same configuration ([`TreeCache`]): the nodes along
/// a semi-sharp crease that ends at an extraordinary vertex, say, are the same few
/// configurations for every face around that vertex, however its other corners look.
#[derive(Debug)]
pub(super) struct Tree {
    /// The cut-out, packed: the configuration's key, unpacked when the node is refined
    /// (its children built, a corner analysed, a child built after its siblings). As a
    /// [`Topology`], the roots' cut-outs were 30 % of the heap of a grid with creases on
    /// a tenth of its edges (6,800 configurations); packed, they take a fifth of that.
    topo: PackedTopology,
    /// Corners where the limit comes from [`corner_limit`] ([`is_limit_corner`]).
    stop: [bool; 4],
    kids: OnceLock<Kids>,
    /// Made when a corner is first analysed: most nodes never analyse one (only points
    /// exactly at a corner where the limit is taken do). Inline, the four took 640 of a
    /// node's 1,160 bytes (11 % of the surface on irregular triangulations, when nearly
    /// every triangle had a tree of its own); each boxed, still 64 of 136.
    corners: OnceLock<Box<[OnceLock<CornerRows>; 4]>>,
    /// What it shares with the other trees of its surface.
    pools: Arc<Pools>,
    /// Whether a face has this configuration (else only nodes below faces' configurations
    /// do): [`TreeCache::len`] counts the faces' configurations.
    face: AtomicBool,
}

/// What the trees of one surface share.
#[derive(Debug, Default)]
pub(super) struct Pools {
    /// The crease bases of crease patches, one per sharpness (made per patch, they were
    /// 6 % of the heap of a grid with random sharpness on a tenth of its edges); the
    /// surface's own crease faces use them too.
    pub bases: CreaseBases,
    /// The weights of the nodes' rows.
    weights: WeightPool,
    /// Refine single-crease faces further instead of using [`CreasePatch`] (tests compare).
    pub no_crease_patches: bool,
}

/// Configurations of one surface, by their cut-outs (packed): the faces' trees and the
/// nodes below them.
#[derive(Debug, Default)]
pub(super) struct TreeCache {
    trees: Configs<Tree>,
    /// Number of faces' configurations, distinct (read while a surface is built, to stop
    /// a build over its memory limit).
    count: AtomicUsize,
    /// What the trees share (the surface's faces use its crease bases too).
    pub pools: Arc<Pools>,
}

impl Keyed for Tree {
    fn key(&self) -> &PackedTopology {
        &self.topo
    }
}

impl TreeCache {
    /// An empty cache; with `crease_patches` false, single-crease faces are refined
    /// further like any irregular face instead of becoming [`CreasePatch`]es.
    pub(super) fn new(crease_patches: bool) -> Self {
        TreeCache {
            pools: Arc::new(Pools {
                no_crease_patches: !crease_patches,
                ..Pools::default()
            }),
            ..TreeCache::default()
        }
    }

    /// Whether single-crease faces are refined further ([`TreeCache::new`]).
    pub(super) fn no_crease_patches(&self) -> bool {
        self.pools.no_crease_patches
    }

    /// The tree of the configuration whose cut-out is `topo` (face 0), found by a face,
    /// built the first time.
    pub(super) fn get(&self, topo: Topology) -> Arc<Tree> {
        self.find(topo, true)
    }

    /// The tree of `topo`, counted as a face's configuration if `face`.
    fn find(&self, topo: Topology, face: bool) -> Arc<Tree> {
        let tree = self
            .trees
            .find(topo, |t, packed| Tree::new(t, packed, self.pools.clone()));
        if face && !tree.face.swap(true, Ordering::Relaxed) {
            self.count.fetch_add(1, Ordering::Relaxed);
        }
        tree
    }

    /// Number of configurations.
    pub(super) fn len(&self) -> usize {
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
    /// The surface's configurations, where a node finds its irregular children's.
    pub trees: &'a TreeCache,
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
    /// The refined points of the node at each depth.
    levels: Vec<Vec<[f64; 3]>>,
    /// The points of the irregular child at each depth, gathered from its parent's
    /// refined points.
    gathered: Vec<Vec<[f64; 3]>>,
    /// The refined points of an `n`-gon root (whose sub-faces start at depth 0).
    root: Vec<[f64; 3]>,
    /// The points of a base face's cut-out.
    cut: Vec<[f64; 3]>,
}

impl Scratch {
    /// The buffer of the refined points at `depth`, taken out (put it back with
    /// [`put`](Self::put)).
    fn take(&mut self, depth: u32) -> Vec<[f64; 3]> {
        take_at(&mut self.levels, depth)
    }

    fn put(&mut self, depth: u32, buffer: Vec<[f64; 3]>) {
        self.levels[depth as usize] = buffer;
    }

    /// The buffer of an irregular child's points at `depth`, taken out (put it back with
    /// [`put_gathered`](Self::put_gathered)).
    fn take_gathered(&mut self, depth: u32) -> Vec<[f64; 3]> {
        take_at(&mut self.gathered, depth)
    }

    fn put_gathered(&mut self, depth: u32, buffer: Vec<[f64; 3]>) {
        self.gathered[depth as usize] = buffer;
    }

    /// The buffer of a cut-out's points, taken out (put it back with
    /// [`put_cut`](Self::put_cut)).
    pub(super) fn take_cut(&mut self) -> Vec<[f64; 3]> {
        std::mem::take(&mut self.cut)
    }

    /// Puts back the buffer [`take_cut`](Self::take_cut) took out.
    pub(super) fn put_cut(&mut self, buffer: Vec<[f64; 3]>) {
        self.cut = buffer;
    }
}

/// Buffer `depth` of `buffers`, taken out (made if there is none yet).
fn take_at(buffers: &mut Vec<Vec<[f64; 3]>>, depth: u32) -> Vec<[f64; 3]> {
    let d = depth as usize;
    if buffers.len() <= d {
        buffers.resize_with(d + 1, Vec::new);
    }
    std::mem::take(&mut buffers[d])
}

impl Tree {
    /// The children (sub-faces of an `n`-gon; quadrants of a quad), which read the
    /// refined points of the cut-out ([`Kids::refine`]); irregular ones found later.
    pub(super) fn root_kids(&self, options: &Options) -> &Kids {
        self.kids(options, |_| false, None)
    }

    /// Evaluates `queries` on the face whose cut-out points are `pos` — on sub-face `sub`
    /// of an `n`-gon, or on the quad itself (`None`, then `depth` levels below the base
    /// face whose parameters the derivatives are scaled to) — writing each result into
    /// `sink`. Reorders `queries`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn eval(
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
            None => descend(self, pos, queries, depth, scratch, ctx, sink),
            Some(j) => {
                let kids = self.kids(ctx.options, |k| k == j, Some(ctx.trees));
                let mut refined = std::mem::take(&mut scratch.root);
                kids.refine_into(pos, &mut refined);
                // The sub-face is its own parameter domain: depth 0, no rescaling.
                let kid = kids.kids.get(j).map(|kid| (kid, self, j));
                kid_eval(kid, &refined, queries, 0, scratch, ctx, sink);
                scratch.root = refined;
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

/// Evaluates `qs` on `node` (at `depth`, evaluated on points `pos`).
fn descend(
    node: &Tree,
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
            let corner = node.corner(k, ctx.options, ctx.sectors);
            *sink.slot(out) = corner.eval(pos);
        },
    );
    let qs = &mut qs[..rest];
    if qs.is_empty() {
        return;
    }
    let quadrants = by_quadrant(qs);
    let wanted = |k: usize| !quadrants[k].is_empty();
    let kids = node.kids(ctx.options, wanted, Some(ctx.trees));
    let mut refined = scratch.take(depth);
    kids.refine_into(pos, &mut refined);
    for (k, qs) in quadrants.into_iter().enumerate() {
        if !qs.is_empty() {
            let kid = kids.kids.get(k).map(|kid| (kid, node, k));
            kid_eval(kid, &refined, qs, depth + 1, scratch, ctx, sink);
        }
    }
    scratch.put(depth, refined);
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
/// partitions, in linear time (a sort would cost `n log n` on every node of every batch).
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
/// of a node whose refined points are `refined`: `(kid, its parent, the kid's index
/// there)`.
fn kid_eval(
    kid: Option<(&Kid, &Tree, usize)>,
    refined: &[[f64; 3]],
    qs: &mut [Query],
    depth: u32,
    scratch: &mut Scratch,
    ctx: Ctx<'_>,
    sink: &mut impl Sink,
) {
    match kid {
        None | Some((Kid::Hole, ..)) => qs.iter().for_each(|q| sink.hole(q.out)),
        Some((Kid::Regular(net), ..)) => {
            let mut cp = [[[0.0; 3]; 4]; 4];
            net.eval_into(refined, &mut cp);
            let scale = scale_at(depth);
            let leaf = &mut Leaf { qs, sink };
            bspline::tensor_batch(&cp, bspline::RegularBases, ctx.order, scale, leaf);
        }
        Some((kid @ Kid::Crease(..), ..)) => {
            if let Some(patch) = kid.crease_patch(refined) {
                let scale = scale_at(depth);
                patch.eval_batch(ctx.order, scale, &mut Leaf { qs, sink });
            }
        }
        Some((Kid::Irregular(sub), parent, j)) => {
            let sub = sub.get_or_init(|| parent.build_sub(j, ctx.options, ctx.trees));
            let mut pos = scratch.take_gathered(depth);
            sub.cols.gather(refined, &mut pos);
            descend(&sub.tree, &pos, qs, depth, scratch, ctx, sink);
            scratch.put_gathered(depth, pos);
        }
    }
}

/// `2^depth`, the scale of the derivatives of a sub-patch `depth` levels below its face,
/// exactly (`depth ≤ MAX_DEPTH < 64`); without a call (`powi` is one to a library
/// routine, 0.75 % of `catmark_chaikin1`'s evaluation).
pub(super) fn scale_at(depth: u32) -> f64 {
    debug_assert!(depth < 64);
    (1u64 << depth) as f64
}

/// What [`Tree::build_kids`] found a child to be, before the refined points are chosen
/// (a few at a time, while a node is built: not worth boxing the cells).
#[allow(clippy::large_enum_variant)]
enum Found {
    Hole,
    /// A patch's cells, and a crease patch's side and sharpness.
    Patch([[Cell; 4]; 4], Option<(usize, f32)>),
    /// An irregular child's cut-out (faces of the refinement).
    Irregular(Vec<u32>),
}

impl Tree {
    /// The tree of face 0 of `topo`, packed as `packed`.
    fn new(topo: &Topology, packed: PackedTopology, pools: Arc<Pools>) -> Self {
        let stop = std::array::from_fn(|k| {
            topo.face_vertices(0).len() == 4 && is_limit_corner(topo, 0, k)
        });
        Tree {
            topo: packed,
            stop,
            kids: OnceLock::new(),
            corners: Default::default(),
            pools,
            face: AtomicBool::new(false),
        }
    }

    /// The children (built the first time). Of the irregular ones, only those for which
    /// `wanted(k)` holds are found now (in `trees`), the others when a point first
    /// reaches them ([`Self::build_sub`], which refines this node again): a grid's points
    /// reach the quadrants they reach every time, and on a face with an irregular corner
    /// the deepest corner child holds none of them (its corner's point is the parent's).
    fn kids(
        &self,
        options: &Options,
        wanted: impl Fn(usize) -> bool,
        trees: Option<&TreeCache>,
    ) -> &Kids {
        self.kids
            .get_or_init(|| self.build_kids(&self.topo.unpack(), options, wanted, trees))
    }

    /// Whether sharp rules reach as far as Chaikin's rule lets them (the cut-outs of
    /// children).
    fn chaikin(options: &Options) -> bool {
        Reach::new(options).chaikin
    }

    /// Irregular child `j`, found after its siblings were built (refines this node again,
    /// and finds again the refined points its children read).
    #[cold]
    #[inline(never)]
    fn build_sub(&self, j: usize, options: &Options, trees: &TreeCache) -> Sub {
        let t = self.topo.unpack();
        let child = refine_topology(&t, options, true);
        let (found, needed) = self.find_kids(&t, &child, options);
        match &found[j] {
            Found::Irregular(faces) => Self::sub(&child, faces, &needed, trees),
            _ => unreachable!("child {j} was irregular when its siblings were built"),
        }
    }

    /// The child whose cut-out is `faces` of `child`, this node's refinement, whose
    /// points are the refined vertices `needed`.
    fn sub(child: &Topology, faces: &[u32], needed: &[u32], trees: &TreeCache) -> Sub {
        let (sub, verts) = child.subset_canonical(faces);
        Sub {
            tree: trees.find(sub, false),
            cols: Cols::new(verts.iter().map(|&v| slot_of(needed, v)).collect()),
        }
    }

    /// What each child of this node (face 0 of cut-out `t`) is in `t`'s refinement
    /// `child`, and the refined vertices the children read, in increasing order (the
    /// node's refined points, [`Kids`]).
    fn find_kids(
        &self,
        t: &Topology,
        child: &Topology,
        options: &Options,
    ) -> (Vec<Found>, Vec<u32>) {
        // Face 0's children are the first faces of its refinement.
        let size = t.face_vertices(0).len();
        let crease = !self.pools.no_crease_patches;
        let found: Vec<Found> = (0..size)
            .map(|f| {
                if child.is_hole(f) {
                    Found::Hole
                } else if let Some(cells) = regular_patch_cells(child, f) {
                    Found::Patch(cells, None)
                } else if let Some((cells, side, s)) =
                    single_crease(child, f, options).filter(|_| crease)
                {
                    Found::Patch(cells, Some((side, s)))
                } else {
                    Found::Irregular(cut_out_unbounded(child, f, Self::chaikin(options)))
                }
            })
            .collect();
        let mut needed = Vec::new();
        for kid in &found {
            match kid {
                Found::Hole => {}
                Found::Patch(cells, _) => needed.extend(
                    (cells.iter().flatten()).flat_map(|c| c.verts[..c.len].iter().copied()),
                ),
                Found::Irregular(faces) => needed.extend(
                    (faces.iter()).flat_map(|&g| child.face_vertices(g as usize).iter().copied()),
                ),
            }
        }
        needed.sort_unstable();
        needed.dedup();
        (found, needed)
    }

    /// The children of this node, whose cut-out is `t`; the irregular ones for which
    /// `wanted` holds found in `trees` (if given).
    fn build_kids(
        &self,
        t: &Topology,
        options: &Options,
        wanted: impl Fn(usize) -> bool,
        trees: Option<&TreeCache>,
    ) -> Kids {
        let child = refine_topology(t, options, true);
        let (found, needed) = self.find_kids(t, &child, options);
        let pools = &self.pools;
        let cc = Adjustable::CATMULL_CLARK;
        let rows = NodeRows::refinement(t, &child, options, cc, &needed, |c| c, &pools.weights);
        let kids = (found.into_iter().enumerate())
            .map(|(j, kid)| {
                // The net on the refined points.
                let net = |cells: [[Cell; 4]; 4]| {
                    KidNet::new(Net::new(cells.map(|row| {
                        row.map(|mut c| {
                            (c.verts.iter_mut().take(c.len))
                                .for_each(|v| *v = slot_of(&needed, *v));
                            c
                        })
                    })))
                };
                match kid {
                    Found::Hole => Kid::Hole,
                    Found::Patch(cells, None) => Kid::Regular(net(cells)),
                    Found::Patch(cells, Some((side, s))) => {
                        Kid::Crease(net(cells), side as u8, pools.bases.get(s))
                    }
                    Found::Irregular(faces) => {
                        let sub = OnceLock::new();
                        if let Some(trees) = trees.filter(|_| wanted(j)) {
                            let _ = sub.set(Self::sub(&child, &faces, &needed, trees));
                        }
                        Kid::Irregular(sub)
                    }
                }
            })
            .collect();
        Kids { rows, kids }
    }

    /// The corner analysis at corner `k` as weights (computed the first time).
    fn corner(&self, k: usize, options: &Options, sectors: &SectorCache) -> &CornerRows {
        self.corners.get_or_init(Box::default)[k].get_or_init(|| {
            // Three unit control points at a time, one per coordinate: coordinate `c` of
            // each output vector is the weight of the point set to `e_c`.
            // The probes share one shape, which analyses the corner's sector (and refines
            // it, where that takes further levels) once for all of them.
            let topo = self.topo.unpack();
            let n = topo.num_vertices();
            let shape = Shape::probed(topo);
            let mut weights = vec![[0.0; 5]; n];
            let mut limit = CornerLimit::default();
            for c0 in (0..n).step_by(3) {
                let mut pos = vec![[0.0; 3]; n];
                for c in 0..3.min(n - c0) {
                    pos[c0 + c][c] = 1.0;
                }
                let local = Local {
                    region: Arc::new(Region::new(shape.clone(), pos)),
                    face: 0,
                };
                limit = corner_limit(&local, k, options, sectors);
                let vs = limit.vectors();
                for c in 0..3.min(n - c0) {
                    weights[c0 + c] = vs.map(|v| v[c]);
                }
            }
            let (cols, weights): (Vec<u32>, Vec<[f64; 5]>) = (0..n as u32)
                .zip(weights)
                .filter(|(_, w)| w.iter().any(|&w| w != 0.0))
                .unzip();
            CornerRows {
                limit,
                cols: cols.into(),
                weights: weights.into(),
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Crease;

    /// A 6 × 6 grid with creases that end inside it or change sharpness (infinitely sharp,
    /// then 2; 3, then 1), and a cube: faces with patch, crease-patch and irregular
    /// children.
    fn creased_grid_and_cube() -> [crate::mesh::PolyMesh; 2] {
        let n = 7u32;
        let mut grid = crate::mesh::test_grid(n - 1, n - 1, |x, y| [x, y, 0.1 * x * y]);
        let v = |i: u32, j: u32| j * n + i;
        for (v0, v1, sharpness) in [
            (v(1, 1), v(2, 1), 10.0),
            (v(2, 1), v(3, 1), 10.0),
            (v(3, 1), v(4, 1), 2.0),
            (v(4, 1), v(5, 1), 2.0),
            (v(1, 4), v(2, 4), 3.0),
            (v(2, 4), v(3, 4), 1.0),
            (v(3, 4), v(4, 4), 1.0),
        ] {
            grid.tags.creases.push(Crease { v0, v1, sharpness });
        }
        [grid, crate::mesh::test_cube()]
    }

    /// The refined points a node keeps rows for, and each child's reads of them, on every
    /// face of a grid with creases that end inside it or change sharpness (patches, crease
    /// patches and irregular children) and on a cube (irregular children only), two
    /// levels down: every refined point is computed once (`needed` increasing) and read
    /// by some child, and no child reads past them.
    #[test]
    fn children_read_each_refined_point_of_their_node() {
        let options = Options::default();
        let trees = TreeCache::new(true);
        let mut checked = [0; 3];
        for mesh in creased_grid_and_cube() {
            let t = Topology::from_mesh(&mesh, &options).expect("topology").0;
            for f in 0..t.num_faces() {
                let Ok(faces) = super::super::local::cut_out(&t, f, Reach::new(&options)) else {
                    unreachable!("no high valence here");
                };
                let tree = trees.get(t.subset_canonical(&faces).0);
                check_node(&tree, 2, &options, &trees, &mut checked);
            }
        }
        let [patches, creases, irregular] = checked;
        assert!(patches > 0 && creases > 0 && irregular > 0, "{checked:?}");
    }

    /// A child found after its siblings were built (by a point that reaches it later) is
    /// the child found with them: the same configuration, on the same refined points. On
    /// every face of a grid with creases that end inside it or change sharpness, and of a
    /// cube.
    #[test]
    fn children_built_later_are_those_built_with_their_siblings() {
        let options = Options::default();
        let (now, later) = (TreeCache::new(true), TreeCache::new(true));
        let (mut compared, mut seen) = (0, std::collections::HashSet::new());
        for mesh in creased_grid_and_cube() {
            let t = Topology::from_mesh(&mesh, &options).expect("topology").0;
            for f in 0..t.num_faces() {
                let faces = super::super::local::cut_out(&t, f, Reach::new(&options))
                    .expect("no high valence here");
                let (a, b) = (
                    now.get(t.subset_canonical(&faces).0),
                    later.get(t.subset_canonical(&faces).0),
                );
                if !seen.insert(Arc::as_ptr(&b)) {
                    continue; // A configuration met before.
                }
                let kids_a = a.kids(&options, |_| true, Some(&now));
                let kids_b = b.kids(&options, |_| false, Some(&later));
                for (j, (ka, kb)) in kids_a.kids().iter().zip(kids_b.kids()).enumerate() {
                    let (Kid::Irregular(sa), Kid::Irregular(sb)) = (ka, kb) else {
                        continue;
                    };
                    assert!(
                        sb.get().is_none(),
                        "face {f}: child {j} built with its siblings"
                    );
                    let na = sa.get().expect("built with its siblings");
                    let nb = sb.get_or_init(|| b.build_sub(j, &options, &later));
                    let cols = |n: &Sub| {
                        (0..n.cols.len() as u32)
                            .map(|i| n.cols.get(i))
                            .collect::<Vec<_>>()
                    };
                    assert_eq!(cols(na), cols(nb), "face {f}, child {j}");
                    assert!(na.tree.topo == nb.tree.topo, "face {f}, child {j}");
                    assert_eq!(na.tree.stop, nb.tree.stop, "face {f}, child {j}");
                    compared += 1;
                }
            }
        }
        assert!(compared >= 10, "{compared} children compared");
    }

    /// Nodes below the faces' configurations are shared: around the creases of a grid,
    /// that end inside it or change sharpness, the faces' trees two levels deep hold
    /// fewer distinct nodes than they reach, and each node found twice is one tree.
    #[test]
    fn nodes_with_the_same_cut_out_are_one_tree() {
        let options = Options::default();
        let trees = TreeCache::new(true);
        let [grid, _] = creased_grid_and_cube();
        let t = Topology::from_mesh(&grid, &options).expect("topology").0;
        let mut reached = 0;
        let mut distinct = std::collections::HashSet::new();
        for f in 0..t.num_faces() {
            let faces = super::super::local::cut_out(&t, f, Reach::new(&options))
                .expect("no high valence here");
            let root = trees.get(t.subset_canonical(&faces).0);
            let mut level = vec![root];
            for _ in 0..2 {
                let mut next = Vec::new();
                for node in &level {
                    for kid in node.kids(&options, |_| true, Some(&trees)).kids() {
                        if let Kid::Irregular(sub) = kid {
                            let sub = sub.get().expect("wanted");
                            reached += 1;
                            distinct.insert(Arc::as_ptr(&sub.tree));
                            next.push(sub.tree.clone());
                        }
                    }
                }
                level = next;
            }
        }
        assert!(reached > 0);
        assert!(distinct.len() < reached, "{} of {reached}", distinct.len());
    }

    /// A node of a grid keeps rows with 8-bit indices, and nodes with the same classes
    /// of weights share them: the cut-outs of every interior face of a 6 × 6 grid, and of
    /// the faces next to a crease, make a handful of distinct arrays of weights.
    #[test]
    fn grid_nodes_keep_tiny_rows_and_share_weights() {
        let mut grid = crate::mesh::test_grid(6, 6, |x, y| [x, y, 0.0]);
        grid.tags.creases.push(Crease {
            v0: 8,
            v1: 9,
            sharpness: 2.5,
        });
        let options = Options::default();
        let t = Topology::from_mesh(&grid, &options).expect("topology").0;
        let trees = TreeCache::new(true);
        let mut arrays = Vec::new();
        for f in [7, 8, 9, 14, 15, 16, 21] {
            let faces = super::super::local::cut_out(&t, f, Reach::new(&options)).expect("cut-out");
            let tree = trees.get(t.subset_canonical(&faces).0);
            let kids = tree.root_kids(&options);
            assert!(matches!(kids.rows, NodeRows::Tiny(_)));
            arrays.push(kids.rows.weights().clone());
        }
        let pool = &trees.pools.weights;
        assert!(
            pool.len() < arrays.len(),
            "{} arrays for {} nodes",
            pool.len(),
            arrays.len()
        );
        let distinct: std::collections::HashSet<*const f64> =
            arrays.iter().map(|a| a.as_ptr()).collect();
        assert_eq!(distinct.len(), pool.len());
    }

    /// A patch child's net keeps 8-bit indices when its parent has at most 256 refined
    /// points, else 32-bit ones, to the same control points.
    #[test]
    fn kid_nets_of_both_widths_agree() {
        let refined: Vec<[f64; 3]> = (0..400)
            .map(|i| [f64::from(i), f64::from(i % 7), 1.0])
            .collect();
        for top in [255, 399] {
            let verts: [u32; 16] = std::array::from_fn(|k| top - 3 * k as u32);
            let net = Net::Plain(verts);
            let want = net.eval(&refined);
            let kid = KidNet::new(net);
            assert_eq!(matches!(kid, KidNet::Wide(_)), top > 255);
            assert_eq!(kid.eval(&refined), want);
        }
    }

    fn check_node(
        node: &Tree,
        levels: u32,
        options: &Options,
        trees: &TreeCache,
        checked: &mut [usize; 3],
    ) {
        let kids = node.kids(options, |_| true, Some(trees));
        let t = node.topo.unpack();
        let quad = t.face_vertices(0).len() == 4;
        for k in 0..4 {
            assert_eq!(quad && is_limit_corner(&t, 0, k), node.stop[k]);
        }
        let needed = node
            .find_kids(&t, &refine_topology(&t, options, true), options)
            .1;
        assert!(needed.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(kids.rows.len(), needed.len());
        let mut read = vec![false; needed.len()];
        for kid in kids.kids() {
            let slots: Vec<u32> = match kid {
                Kid::Hole => Vec::new(),
                Kid::Regular(net) | Kid::Crease(net, ..) => {
                    checked[usize::from(matches!(kid, Kid::Crease(..)))] += 1;
                    (net.cells().iter().flatten())
                        .flat_map(|c| c.verts[..c.len].to_vec())
                        .collect()
                }
                Kid::Irregular(sub) => {
                    checked[2] += 1;
                    let sub = sub.get().expect("built, as every child was wanted");
                    assert_eq!(sub.tree.topo.unpack().num_vertices(), sub.cols.len());
                    if levels > 1 {
                        check_node(&sub.tree, levels - 1, options, trees, checked);
                    }
                    (0..sub.cols.len() as u32)
                        .map(|i| sub.cols.get(i))
                        .collect()
                }
            };
            for s in slots {
                read[s as usize] = true;
            }
        }
        assert!(read.iter().all(|&r| r), "a refined point no child reads");
    }
}
