//! Extraordinary patches of a [`RefinePlan`](super::RefinePlan): the last levels of a
//! quad with one extraordinary corner, computed from the `2n + 8` points of its 1-ring
//! by a fixed matrix per valence `n`, as regular patches are computed from 16 points by
//! the bicubic kernel (see `refine/plan_patches.rs`).
//!
//! # Why
//! Regular patches need four regular corners, so every quad at an extraordinary vertex is
//! left to the plan's sparse rows, about ten times dearer per vertex. On most meshes that
//! is a few percent of the output; on meshes dense in extraordinary vertices it is half
//! of it: refining an all-triangle mesh once makes every vertex and every face centre
//! extraordinary, and every quad of level 2 has one of them at a corner.
//!
//! # Which quads
//! A quad `f` whose corners are smooth interior vertices with no sharp or semi-sharp
//! edge, each surrounded by quads: three of valence 4 (the regular patches' test,
//! [`regular_corner`]) and one, `v`, of valence `n ≠ 4`, `3 ≤ n ≤` [`MAX_VALENCE`].
//! The vertices that any number of levels put on the closed quad depend only on its
//! 1-ring, the `n + 5` quads that share a vertex with it (`2n + 8` points: Stam 1998, §3),
//! through the smooth masks of its corners (valence `n` at `v`, 4 elsewhere), of the
//! smooth edges at them and of the faces of the 1-ring: a level-`l + 1` vertex on the
//! quad is a vertex, edge or face point of an element within half an edge of it, and the
//! masks of those elements reach no further than the 1-ring. The other points of the
//! 1-ring may be anything (extraordinary, sharp, on a boundary): their own masks are
//! never used. So the map from the `2n + 8` points to the `(2ᵈ + 1)²` vertices that `d`
//! levels put on the quad is one matrix `Mₙ` for all such quads, once the points are
//! numbered the same way.
//!
//! # The net
//! With the faces around `v` taken counter-clockwise from `f` (`g₀ = f, g₁, …, gₙ₋₁`,
//! `gᵢ = (v, aᵢ, bᵢ, aᵢ₊₁)`), the points are, in this order (Stam's numbering):
//!
//! ```text
//!   v, a₀, b₀, a₁, b₁, …, aₙ₋₁, bₙ₋₁,  then the seven beyond f:
//!
//!   c₆ ─ c₅ ─ c₄ ─ c₃        c₀ … c₆ at 4×4 grid cells (3,0) (3,1) (3,2) (3,3)
//!   │    │    │    │         (2,3) (1,3) (0,3), with v at (1,1), f = (1,1)–(2,2),
//!   b₁ ─ a₁ ─ b₀ ─ c₂        a₀ at (2,1), b₀ at (2,2), a₁ at (1,2), b₁ at (0,2),
//!   │    │ f  │    │         a₂ at (0,1), aₙ₋₁ at (1,0), bₙ₋₁ at (2,0)
//!   a₂ ─ v ─ a₀ ─ c₁
//!    ⋱   │    │    │
//!      aₙ₋₁─bₙ₋₁─ c₀
//! ```
//!
//! [`ev_net`] reads it off the mesh, and rejects the quad unless every point is read
//! consistently from every face that holds it and all `2n + 8` are distinct.
//!
//! # The matrix
//! `Mₙ` is computed by refining the 1-ring itself: a mesh of the `n + 5` quads of the
//! net ([`template_faces`]) refined `d` levels by a plan of sparse rows only (the masks
//! of all refinement, [`RefinePlan`](super::RefinePlan) without patches), applied to the
//! `2n + 8` unit vectors; row `k` of `Mₙ` is then the refined value at grid point `k` of
//! the quad `g₀`. The template's own boundary rules act only on points beyond the quad's
//! 1-ring, which the quad's vertices never read (above). Zero entries are dropped: a grid
//! point near `f`'s far corner does not depend on the whole ring.
//!
//! The grid is numbered in the frame of the net (`v` at grid point `(0, 0)`); a quad
//! whose extraordinary corner is its corner `k` has its grid turned `k` quarter turns
//! ([`rotate_grid`]), once, when the plan is built.

use crate::limit::patch::{closed_ring, net_cell, regular_corner, Corner, Sharp};
use crate::mesh::{Options, PolyMesh, Rule, Topology};

use super::plan::RefinePlan;
#[cfg(target_arch = "x86_64")]
use super::plan_patches::has_avx2_fma;
use super::plan_patches::{grid_indices, prefetch_next, Runs, SharedOut, NOT_OWNED};
use super::topology::refine_topology;

/// Largest valence of an extraordinary patch: a row of `Mₙ` has up to `2n + 8` terms (on
/// average 15 at valence 6 and 27 at valence 16, depth 3), and the control points are
/// held on the stack. Higher valences are rare and stay with the sparse rows.
pub(super) const MAX_VALENCE: usize = 16;

/// Largest number of control points of an extraordinary patch.
pub(super) const MAX_POINTS: usize = 2 * MAX_VALENCE + 8;

/// The net of an extraordinary patch: its valence, the corner of the quad that is
/// extraordinary, and the `2n + 8` control vertices in the order of the module docs.
pub(super) struct EvNet {
    pub(super) valence: usize,
    pub(super) corner: usize,
    pub(super) verts: Vec<u32>,
}

/// Number of control points of a net of valence `n`.
pub(super) fn net_len(n: usize) -> usize {
    2 * n + 8
}

/// The net of quad `f` of `t` if it is an extraordinary patch (module docs); `sharp` as
/// for regular patches (it only matters in that a sharp feature rules the quad out).
pub(super) fn ev_net(t: &Topology, f: usize, sharp: Sharp) -> Option<EvNet> {
    let fv = t.face_vertices(f);
    if fv.len() != 4 {
        return None;
    }
    let mut rings = [None; 4];
    let mut ev = None;
    for (k, ring) in rings.iter_mut().enumerate() {
        match regular_corner(t, f, k, sharp) {
            Some(Corner::Closed(r)) => *ring = Some(r),
            Some(Corner::Sector { .. }) => return None,
            None if ev.is_none() => ev = Some(k),
            None => return None,
        }
    }
    let k0 = ev?;
    let v = fv[k0] as usize;
    let n = t.vertex_edges(v).len();
    let tag = t.vertex_tag(v);
    let smooth = tag.rule == Rule::Smooth
        && !(tag.boundary
            || tag.non_manifold
            || tag.semi_sharp
            || tag.inf_sharp
            || tag.semi_sharp_edges
            || tag.inf_sharp_edges);
    if !smooth || !(3..=MAX_VALENCE).contains(&n) || n == 4 || t.vertex_faces(v).len() != n {
        return None;
    }
    // The fan around v, counter-clockwise from f: across the edge entering v in each face.
    let mut verts = Vec::with_capacity(net_len(n));
    verts.push(v as u32);
    let (mut g, mut m) = (f, k0);
    for i in 0..n {
        let gv = t.face_vertices(g);
        if gv.len() != 4 || (i > 0 && g == f) {
            return None;
        }
        verts.extend([gv[(m + 1) % 4], gv[(m + 2) % 4]]);
        let e = t.face_edge_list(g)[(m + 3) % 4] as usize;
        let ef = t.edge_face_list(e);
        if ef.len() != 2 {
            return None;
        }
        let next = if ef[0] as usize == g { ef[1] } else { ef[0] } as usize;
        let nv = t.face_vertices(next);
        let mn = nv.iter().position(|&x| x as usize == v)?;
        // Consistently oriented: the next face leaves v along the edge this one entered by.
        if nv.len() != 4 || nv[(mn + 1) % 4] != gv[(m + 3) % 4] {
            return None;
        }
        (g, m) = (next, mn);
    }
    if g != f {
        return None;
    }
    // The 4×4 cells in the frame of v (the quad turned so that v is its corner 0, at
    // (1,1)), from the three regular corners, as a regular net is read.
    let mut cells = [[u32::MAX; 4]; 4];
    let mut consistent = true;
    for j in 1..4 {
        let k = (k0 + j) % 4;
        let ring = rings[k]?;
        for (off, x) in std::iter::once(((0, 0), fv[k])).chain(closed_ring(t, &ring)) {
            let (i, l) = net_cell(j, off);
            consistent &= cells[i][l] == u32::MAX || cells[i][l] == x;
            cells[i][l] = x;
        }
    }
    // The cells that the fan also holds must agree with it.
    let a = |i: usize| verts[1 + 2 * (i % n)];
    let b = |i: usize| verts[2 + 2 * (i % n)];
    let fan = [
        ((2, 1), a(0)),
        ((2, 2), b(0)),
        ((1, 2), a(1)),
        ((0, 2), b(1)),
        ((0, 1), a(2)),
        ((1, 0), a(n - 1)),
        ((2, 0), b(n - 1)),
    ];
    if !consistent || fan.iter().any(|&((x, y), p)| cells[x][y] != p) {
        return None;
    }
    verts.extend(OUTER.iter().map(|&(x, y)| cells[x][y]));
    let mut sorted = verts.clone();
    sorted.sort_unstable();
    if sorted.windows(2).any(|w| w[0] == w[1]) {
        return None;
    }
    Some(EvNet {
        valence: n,
        corner: k0,
        verts,
    })
}

/// The cells of the seven points beyond the quad, in net order (module docs).
const OUTER: [(usize, usize); 7] = [(3, 0), (3, 1), (3, 2), (3, 3), (2, 3), (1, 3), (0, 3)];

/// The `n + 5` quads of the 1-ring of a net of valence `n`, on its points numbered as in
/// the module docs: the fan `gᵢ = (v, aᵢ, bᵢ, aᵢ₊₁)` (`g₀` is the patch's quad, face 0)
/// and the five quads beyond it, oriented as the fan.
pub(super) fn template_faces(n: usize) -> Vec<[u32; 4]> {
    let (a, b) = (
        |i: usize| (1 + 2 * (i % n)) as u32,
        |i: usize| (2 + 2 * i) as u32,
    );
    let cell = |(x, y): (usize, usize)| -> u32 {
        match (x, y) {
            (1, 1) => 0,
            (2, 1) => a(0),
            (2, 2) => b(0),
            (1, 2) => a(1),
            (0, 2) => b(1),
            (1, 0) => a(n - 1),
            (2, 0) => b(n - 1),
            _ => (2 * n + 1 + OUTER.iter().position(|&c| c == (x, y)).expect("outer cell")) as u32,
        }
    };
    let mut faces: Vec<[u32; 4]> = (0..n).map(|i| [0, a(i), b(i), a(i + 1)]).collect();
    for (x, y) in [(2, 0), (2, 1), (2, 2), (1, 2), (0, 2)] {
        faces.push([(x, y), (x + 1, y), (x + 1, y + 1), (x, y + 1)].map(cell));
    }
    faces
}

/// Rows of `Mₙ` computed together: enough independent sums to keep the multiply-add
/// units busy (a single row's sum waits on each addition in turn, four cycles each), and
/// two 256-bit vectors of weights per control point.
const LANES: usize = 8;

/// The matrix `Mₙ` of depth `d` (module docs), by groups of [`LANES`] rows (grid points):
/// each group lists the control points that any of its rows depends on, with the
/// [`LANES`] weights of its rows on each (0 where a row does not depend on it), in grid
/// order, padded with empty rows to whole groups. (Grouping rows greedily by their
/// supports saves under 2 % of the terms: neighbouring grid points depend on nearly the
/// same control points.)
#[derive(Clone, Debug)]
pub(super) struct Kernel {
    /// Number of rows: the grid points, and the padding to a multiple of [`LANES`].
    rows: usize,
    /// Group `g`'s terms are `starts[g]..starts[g + 1]`.
    starts: Vec<u32>,
    /// The weights of each term, one per row of its group.
    weights: Vec<[f64; LANES]>,
    /// The control point (net slot) of each term.
    slots: Vec<u32>,
}

impl Kernel {
    /// `Mₙ` for `depth` levels, refined with `options` (module docs). `None` only if the
    /// template could not be built, which would be a defect (the quads are then left to
    /// the sparse rows).
    pub(super) fn new(n: usize, depth: u32, options: &Options) -> Option<Kernel> {
        let faces = template_faces(n);
        let points = net_len(n);
        let mesh = PolyMesh::from_faces(vec![[0.0; 3]; points], &faces).ok()?;
        let plan = RefinePlan::build(&mesh, *options, depth, 0).ok()?;
        let (mut level, _) = Topology::from_mesh(&mesh, options).ok()?;
        let mut levels = Vec::with_capacity(depth as usize);
        for _ in 1..depth {
            let child = refine_topology(&level, options, true);
            levels.push(std::mem::replace(&mut level, child));
        }
        levels.push(level);
        let grid = grid_indices(&levels, 0)?;
        let columns: Vec<Vec<[f64; 1]>> = (0..points)
            .map(|s| {
                let unit: Vec<[f64; 1]> =
                    (0..points).map(|i| [f64::from(u8::from(i == s))]).collect();
                plan.apply(&unit)
            })
            .collect();
        let mut kernel = Kernel {
            rows: grid.len().next_multiple_of(LANES),
            starts: vec![0],
            weights: Vec::new(),
            slots: Vec::new(),
        };
        for group in grid.chunks(LANES) {
            for (s, column) in columns.iter().enumerate() {
                let mut w = [0.0; LANES];
                for (w, &g) in w.iter_mut().zip(group) {
                    *w = column[g as usize][0];
                }
                if w.iter().any(|&w| w != 0.0) {
                    kernel.weights.push(w);
                    kernel.slots.push(s as u32);
                }
            }
            kernel.starts.push(kernel.weights.len() as u32);
        }
        Some(kernel)
    }

    /// The nonzero entries `(control point, weight)` of row `r`.
    #[cfg(test)]
    fn row(&self, r: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let (g, lane) = (r / LANES, r % LANES);
        let terms = self.starts[g] as usize..self.starts[g + 1] as usize;
        (self.slots[terms.clone()].iter().zip(&self.weights[terms]))
            .map(move |(&s, w)| (s as usize, w[lane]))
            .filter(|&(_, w)| w != 0.0)
    }

    /// Bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        4 * self.starts.len() + (8 * LANES + 4) * self.weights.len()
    }
}

/// The extraordinary patches of one valence in one [`PatchLayer`](super::plan_patches::PatchLayer).
#[derive(Clone, Debug)]
pub(super) struct EvGroup {
    pub(super) valence: usize,
    kernel: Kernel,
    /// The `2n + 8` control vertices of each patch, in net order.
    pub(super) ctrl: Vec<u32>,
    /// The output vertex of each grid point of each patch, in the net's frame, or
    /// [`NOT_OWNED`].
    pub(super) out: Vec<u32>,
    /// The run of faces of each patch, while the layer is built.
    run_of: Vec<u32>,
    /// Where the patches of each run start.
    runs: Runs,
}

impl EvGroup {
    pub(super) fn new(valence: usize, kernel: Kernel) -> Self {
        EvGroup {
            valence,
            kernel,
            ctrl: Vec::new(),
            out: Vec::new(),
            run_of: Vec::new(),
            runs: Runs::default(),
        }
    }

    /// Adds a patch of run `run` (not before those already added) with control vertices
    /// `verts` and grid `grid` (in the net's frame), padded as the kernel's rows.
    pub(super) fn push(&mut self, run: u32, verts: &[u32], grid: &[u32]) {
        self.ctrl.extend_from_slice(verts);
        self.out.extend_from_slice(grid);
        let pad = self.kernel.rows - grid.len();
        self.out.resize(self.out.len() + pad, NOT_OWNED);
        self.run_of.push(run);
    }

    /// Indexes the patches by run, once all are added.
    pub(super) fn set_runs(&mut self, runs: usize) {
        self.runs = Runs::new(&std::mem::take(&mut self.run_of), runs);
    }

    /// Number of patches.
    pub(super) fn len(&self) -> usize {
        self.ctrl.len() / net_len(self.valence)
    }

    /// Bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        self.kernel.memory_bytes()
            + 4 * self.ctrl.len()
            + 4 * self.out.len()
            + self.runs.memory_bytes()
    }

    /// Writes the owned grid points of the patches of run `r` into `out`, from the values
    /// `src` of the patches' level.
    ///
    /// # Safety
    /// Every control index is in bounds of `src`, every grid index is [`NOT_OWNED`] or in
    /// bounds of `out`, and no other thread writes the same output indices.
    pub(super) unsafe fn apply<const D: usize>(
        &self,
        r: usize,
        src: &[[f64; D]],
        out: &SharedOut<[f64; D]>,
    ) {
        let (points, nn) = (net_len(self.valence), self.kernel.rows);
        let run = self.runs.range(r);
        let ctrl = &self.ctrl[run.start * points..run.end * points];
        let grids = &self.out[run.start * nn..run.end * nn];
        #[cfg(target_arch = "x86_64")]
        if D == 3 && has_avx2_fma() {
            let src = src.as_ptr().cast();
            // SAFETY: the features were just detected; `D == 3`; the caller's bounds.
            unsafe { ev_patches_avx(&self.kernel, points, src, ctrl, grids, out.0.cast()) };
            return;
        }
        let k = &self.kernel;
        // The control points by component: `local[c][s]`.
        let mut local = [[0.0; MAX_POINTS]; D];
        for (p, (c, g)) in ctrl
            .chunks_exact(points)
            .zip(grids.chunks_exact(nn))
            .enumerate()
        {
            // SAFETY: the caller's.
            unsafe { prefetch_next::<D>(grids, p, nn, out.0.cast()) };
            for (s, &v) in c.iter().enumerate() {
                (0..D).for_each(|i| local[i][s] = src[v as usize][i]);
            }
            for (group, rows) in g.chunks(LANES).enumerate() {
                if rows.iter().all(|&o| o == NOT_OWNED) {
                    continue;
                }
                let mut acc = [[0.0; LANES]; D];
                let terms = k.starts[group] as usize..k.starts[group + 1] as usize;
                for (w, &s) in k.weights[terms.clone()].iter().zip(&k.slots[terms]) {
                    for (acc, local) in acc.iter_mut().zip(&local) {
                        let x = local[s as usize];
                        (0..LANES).for_each(|l| acc[l] += w[l] * x);
                    }
                }
                for (l, &o) in rows.iter().enumerate() {
                    if o != NOT_OWNED {
                        // SAFETY: the caller's.
                        unsafe {
                            out.0
                                .add(o as usize)
                                .write(std::array::from_fn(|i| acc[i][l]))
                        };
                    }
                }
            }
        }
    }
}

/// [`EvGroup::apply`] for positions, with AVX2 and FMA (as the regular patches'
/// `patches_avx`): the control points split by component, and for each group of
/// [`LANES`] rows six independent sums (two vectors of rows × three components).
///
/// # Safety
/// As [`EvGroup::apply`], with `src` and `out` pointing at `[f64; 3]` values; the
/// processor has AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn ev_patches_avx(
    k: &Kernel,
    points: usize,
    src: *const f64,
    ctrl: &[u32],
    grids: &[u32],
    out: *mut f64,
) {
    use std::arch::x86_64::*;
    let nn = k.rows;
    let mut local = [[0.0; MAX_POINTS]; 3];
    // SAFETY (whole body): the caller's bounds; slots are below `points ≤ MAX_POINTS`.
    unsafe {
        for (p, (c, g)) in ctrl
            .chunks_exact(points)
            .zip(grids.chunks_exact(nn))
            .enumerate()
        {
            prefetch_next::<3>(grids, p, nn, out);
            for (s, &v) in c.iter().enumerate() {
                let q = src.add(3 * v as usize);
                local[0][s] = *q;
                local[1][s] = *q.add(1);
                local[2][s] = *q.add(2);
            }
            for (group, rows) in g.chunks(LANES).enumerate() {
                let owned = |rows: &[u32]| rows.iter().any(|&o| o != NOT_OWNED);
                let (low, high) = (owned(&rows[..4]), owned(&rows[4..]));
                if !(low || high) {
                    continue;
                }
                let mut acc = [[_mm256_setzero_pd(); 2]; 3];
                let terms = k.starts[group] as usize..k.starts[group + 1] as usize;
                let terms = k.weights[terms.clone()].iter().zip(&k.slots[terms]);
                if low && high {
                    for (w, &s) in terms {
                        let w = [
                            _mm256_loadu_pd(w.as_ptr()),
                            _mm256_loadu_pd(w.as_ptr().add(4)),
                        ];
                        for (acc, local) in acc.iter_mut().zip(&local) {
                            let x = _mm256_broadcast_sd(local.get_unchecked(s as usize));
                            acc[0] = _mm256_fmadd_pd(w[0], x, acc[0]);
                            acc[1] = _mm256_fmadd_pd(w[1], x, acc[1]);
                        }
                    }
                } else {
                    // Only one half of the rows is written: half the work.
                    let h = usize::from(high);
                    for (w, &s) in terms {
                        let w = _mm256_loadu_pd(w.as_ptr().add(4 * h));
                        for (acc, local) in acc.iter_mut().zip(&local) {
                            let x = _mm256_broadcast_sd(local.get_unchecked(s as usize));
                            acc[h] = _mm256_fmadd_pd(w, x, acc[h]);
                        }
                    }
                }
                // Four rows at a time from (x, y, z) by row to rows of (x, y), (z).
                for (half, rows) in rows.chunks(4).enumerate() {
                    let [x, y, z] = acc.map(|a| a[half]);
                    let (xy02, xy13) = (_mm256_unpacklo_pd(x, y), _mm256_unpackhi_pd(x, y));
                    let (zlo, zhi) = (_mm256_castpd256_pd128(z), _mm256_extractf128_pd::<1>(z));
                    let xy = [
                        _mm256_castpd256_pd128(xy02),
                        _mm256_castpd256_pd128(xy13),
                        _mm256_extractf128_pd::<1>(xy02),
                        _mm256_extractf128_pd::<1>(xy13),
                    ];
                    for (l, &o) in rows.iter().enumerate() {
                        if o == NOT_OWNED {
                            continue;
                        }
                        let q = out.add(3 * o as usize);
                        _mm_storeu_pd(q, xy[l]);
                        let z = if l < 2 { zlo } else { zhi };
                        if l % 2 == 0 {
                            _mm_store_sd(q.add(2), z);
                        } else {
                            _mm_storeh_pd(q.add(2), z);
                        }
                    }
                }
            }
        }
    }
}

/// `grid` (`side × side` points of a quad, point `(x, y)` at `side x + y`, corner 0 at
/// `(0, 0)`) renumbered in the frame where the quad's corner `k` is corner 0.
pub(super) fn rotate_grid(grid: &[u32], side: usize, k: usize) -> Vec<u32> {
    let h = side - 1;
    let mut cur = grid.to_vec();
    for _ in 0..k {
        // Corner 1 at (h, 0) goes to (0, 0): (x, y) → (y, h − x).
        let mut next = vec![NOT_OWNED; cur.len()];
        for x in 0..side {
            for y in 0..side {
                next[y * side + h - x] = cur[x * side + y];
            }
        }
        cur = next;
    }
    cur
}

#[cfg(test)]
mod tests {

    use super::*;

    /// The template is a valid mesh whose first face has the extraordinary corner, and
    /// `ev_net` reads it back in the same order from any corner numbering of the quad.
    #[test]
    fn net_reads_the_template() {
        for n in [3, 5, 6, 7, 12] {
            let faces = template_faces(n);
            assert_eq!(faces.len(), n + 5);
            let mesh = PolyMesh::from_faces(vec![[0.0; 3]; net_len(n)], &faces).unwrap();
            let (t, _) = Topology::from_mesh(&mesh, &Options::default()).unwrap();
            assert_eq!(t.vertex_edges(0).len(), n);
            let net =
                ev_net(&t, 0, Sharp::LIMIT).expect("the template's quad is an extraordinary patch");
            assert_eq!((net.valence, net.corner), (n, 0));
            assert_eq!(net.verts, (0..net_len(n) as u32).collect::<Vec<_>>());
            // The same quad listed from another corner.
            for k in 1..4 {
                let mut turned = faces.clone();
                turned[0].rotate_left(k);
                let mesh = PolyMesh::from_faces(vec![[0.0; 3]; net_len(n)], &turned).unwrap();
                let (t, _) = Topology::from_mesh(&mesh, &Options::default()).unwrap();
                let net = ev_net(&t, 0, Sharp::LIMIT).unwrap();
                assert_eq!(net.corner, (4 - k) % 4);
                assert_eq!(net.verts, (0..net_len(n) as u32).collect::<Vec<_>>());
            }
        }
    }

    /// Each row of `Mₙ` is a partition of unity (refinement is affine invariant), and the
    /// grid point at the extraordinary vertex is `d` steps of the smooth vertex rule of
    /// valence `n`, worked out in closed form: with `v = 1` and every other point 0, the
    /// fan stays rotationally symmetric, so one value for `v`, one for all `aᵢ` and one for
    /// all `bᵢ` follow each step (face point `(v + 2a + b)/4`, which becomes the new `b`;
    /// edge point `(v + a + 2 face)/4`, the new `a`; vertex point
    /// `(n − 2)/n v + (a + face)/n`).
    #[test]
    fn kernel_rows_are_affine_and_corner_is_vertex_rule() {
        for n in [3, 5, 6, 8] {
            for depth in [2, 3] {
                let k = Kernel::new(n, depth, &Options::default()).unwrap();
                let points: usize = ((1 << depth) + 1) * ((1 << depth) + 1);
                assert_eq!(k.rows, points.next_multiple_of(LANES));
                for r in 0..points {
                    let sum: f64 = k.row(r).map(|(_, w)| w).sum();
                    assert!((sum - 1.0).abs() < 1e-14, "n {n} depth {depth} row {r}");
                }
                let nf = n as f64;
                let (mut v, mut a, mut b) = (1.0, 0.0, 0.0);
                for _ in 0..depth {
                    let face = (v + 2.0 * a + b) / 4.0;
                    let edge = (v + a + 2.0 * face) / 4.0;
                    (v, a, b) = ((nf - 2.0) / nf * v + (a + face) / nf, edge, face);
                }
                let got: f64 = k.row(0).filter(|&(s, _)| s == 0).map(|(_, w)| w).sum();
                assert!(
                    (got - v).abs() < 1e-15,
                    "n {n} depth {depth}: {got} against {v}"
                );
            }
        }
    }

    /// Turning a grid four times gives it back; once moves corner 1 to corner 0.
    #[test]
    fn rotation() {
        let side = 5;
        let grid: Vec<u32> = (0..25).collect();
        assert_eq!(rotate_grid(&grid, side, 4), grid);
        let once = rotate_grid(&grid, side, 1);
        assert_eq!(once[0], grid[4 * side]);
        assert_eq!(once[4 * side], grid[4 * side + 4]);
    }
}
