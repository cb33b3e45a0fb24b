//! The rows of a configuration-tree node: each refined point its children read, as sparse
//! weights on the points the node is evaluated on ([`NodeRows`]), and the pool that keeps
//! each distinct set of weights once per surface ([`WeightPool`]).
//!
//! A node's refined points are face, edge and vertex points, smooth or sharp, whose
//! weights are one of a few vectors (four quarters, the six of a smooth edge point, the
//! nine of a smooth vertex point of valence 4, the blends of a semi-sharp crease, ...). So
//! the rows are kept by the node's *classes*, the distinct vectors (each row its slot and
//! columns, in the group of its class), and nodes whose classes are the same share one
//! array of them. On a
//! grid with creases on a tenth of its edges (6,835 configurations, 20,312 nodes) the
//! weights stored with every term were two thirds of the rows and the rows 43 % of the
//! heap; stored once per node, still 3.6 MB (a seventh of the heap); shared, six arrays
//! and the pool's map, under 2 KB.

use super::Index;
use crate::hash::FxHasher;
use crate::mesh::{Options, Topology};
use crate::refine::refinement_rows;
use crate::scheme::Rules;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::{Arc, Mutex};

/// The rows of a node's refined points, with the narrowest indices that hold them.
///
/// The indices (the groups' headers, the rows' slots and columns) are 8-bit when they
/// fit, as they do on nearly every node (a cut-out of a few dozen points, its refinement
/// read through a couple of hundred terms: on a grid with creases on a tenth of its
/// edges, at most 24 columns and 140 terms), else 16-bit unless the node's cut-out holds
/// a face or vertex of thousands of sides. 32-bit, they were half of the rows; 16-bit,
/// still two thirds of the rows and a sixth of the heap of that grid.
#[derive(Debug)]
pub(super) enum NodeRows {
    Tiny(RowsOf<u8>),
    Narrow(RowsOf<u16>),
    Wide(RowsOf<u32>),
}

/// [`NodeRows`] with indices of type `I`.
///
/// The rows are kept by *group*: the rows that read the same weights (one class: smooth
/// edge points, face points of quads, ...) one after the other, each as the slot of the
/// point it computes and its columns. Within a group every row has the same length and
/// the same weights, so the kernel ([`group_avx`]) keeps the weights in registers and
/// runs a loop of a length known when it is compiled: per term, one load and one
/// multiply-add. Row by row, each term also loaded its weight and counted, and the loop
/// over a row's terms ended at a different length from one row to the next.
#[derive(Debug)]
pub(super) struct RowsOf<I> {
    /// Number of rows, `n`: the points computed.
    len: u32,
    /// One past the last `f64` the rows read: three times the fewest points they read.
    reach: u32,
    /// In one allocation (three took a fifth more memory than the indices themselves):
    /// the number of groups `g`; per group its row length `l` and its number of rows;
    /// then the rows of each group in turn, each as `l + 1` indices: the slot it
    /// computes, then its columns. Group `k` reads class `k`. Slots and columns are
    /// offsets in `f64`, three times the point's index, which the kernel adds to the
    /// points' address as they are (a multiply by three per term less: 4 % of
    /// `catmark_chaikin1`); no node of the grids with creases needs wider indices for it.
    index: Box<[I]>,
    /// The node's classes, one after the other, from [`WeightPool::intern`]: every class
    /// a row of the node reads, so the groups' lengths say where each starts.
    weights: Arc<[f64]>,
}

impl NodeRows {
    /// The rows of the refinement of `t` into `child` by `rules` (see
    /// [`refinement_rows`]) for the child vertices `verts`, with each column `c` (a vertex
    /// of `t`) mapped to `cols(c)`, the point the node is evaluated on; zero weights left
    /// out. The weights are interned in `pool`.
    pub(super) fn refinement<R: Rules>(
        t: &Topology,
        child: &Topology,
        options: &Options,
        rules: R,
        verts: &[u32],
        cols: impl Fn(u32) -> u32,
        pool: &WeightPool,
    ) -> Self {
        let mut starts = vec![0];
        let (mut all_cols, mut class_of) = (vec![], vec![]);
        // The distinct weight vectors so far, `(start, length)` in `found`: a node has a
        // few dozen at most, so a scan finds a row's (a map allocated a key per row).
        let mut found: Vec<f64> = Vec::new();
        let mut classes: Vec<(u32, u32)> = Vec::new();
        let mut row = Vec::new();
        refinement_rows(t, child, options, rules, verts.iter().copied(), |cs, ws| {
            row.clear();
            for (&c, &w) in cs.iter().zip(ws).filter(|&(_, &w)| w != 0.0) {
                all_cols.push(cols(c));
                row.push(w);
            }
            starts.push(all_cols.len() as u32);
            let same = |&(start, len): &(u32, u32)| {
                bits_equal(&found[start as usize..(start + len) as usize], &row)
            };
            let class = classes.iter().position(same).unwrap_or_else(|| {
                classes.push((found.len() as u32, row.len() as u32));
                found.extend_from_slice(&row);
                classes.len() - 1
            });
            class_of.push(class as u32);
        });
        // The classes in a canonical order (by their bits), so that nodes with the same
        // classes share one array whatever order their rows met them in.
        let class = |k: usize| {
            let (start, len) = classes[k];
            &found[start as usize..(start + len) as usize]
        };
        let mut order: Vec<usize> = (0..classes.len()).collect();
        order.sort_unstable_by(|&a, &b| {
            let bits = |k| class(k).iter().map(|w| w.to_bits());
            bits(a).cmp(bits(b))
        });
        let mut weights = Vec::with_capacity(found.len());
        let mut rank = vec![0; classes.len()];
        for (i, &k) in order.iter().enumerate() {
            rank[k] = i as u32;
            weights.extend_from_slice(class(k));
        }
        let class_of: Vec<u32> = class_of.iter().map(|&k| rank[k as usize]).collect();
        let lengths: Vec<u32> = order.iter().map(|&k| classes[k].1).collect();
        NodeRows::new(
            &starts,
            &all_cols,
            &class_of,
            &lengths,
            pool.intern(&weights),
        )
    }

    /// The rows of `starts`, `cols`, `class` and `weights`, with the narrowest indices
    /// they all fit: row `r` computes slot `r` from columns `cols[starts[r]..starts[r +
    /// 1]]` with the weights of class `class[r]`. The classes are `weights` one after the
    /// other, class `k` of length `lengths[k]`.
    pub(super) fn new(
        starts: &[u32],
        cols: &[u32],
        class: &[u32],
        lengths: &[u32],
        weights: Arc<[f64]>,
    ) -> Self {
        let index = grouped(starts, cols, class, lengths);
        let len = class.len() as u32;
        if let Some(rows) = RowsOf::new(len, &index, &weights) {
            NodeRows::Tiny(rows)
        } else if let Some(rows) = RowsOf::new(len, &index, &weights) {
            NodeRows::Narrow(rows)
        } else {
            NodeRows::Wide(
                RowsOf::new(len, &index, &weights)
                    .unwrap_or_else(|| unreachable!("32-bit indices fit")),
            )
        }
    }

    /// Number of rows.
    pub(super) fn len(&self) -> usize {
        match self {
            NodeRows::Tiny(r) => r.len as usize,
            NodeRows::Narrow(r) => r.len as usize,
            NodeRows::Wide(r) => r.len as usize,
        }
    }

    /// Every row applied to `pos`, into `out`.
    ///
    /// # Panics
    /// If `pos` holds fewer points than the rows read.
    pub(super) fn apply(&self, pos: &[[f64; 3]], out: &mut Vec<[f64; 3]>) {
        out.resize(self.len(), [0.0; 3]);
        match self {
            NodeRows::Tiny(r) => r.apply(pos, out),
            NodeRows::Narrow(r) => r.apply(pos, out),
            NodeRows::Wide(r) => r.apply(pos, out),
        }
    }

    /// The weights the rows read (shared with the nodes that have the same classes).
    #[cfg(test)]
    pub(super) fn weights(&self) -> &Arc<[f64]> {
        match self {
            NodeRows::Tiny(r) => &r.weights,
            NodeRows::Narrow(r) => &r.weights,
            NodeRows::Wide(r) => &r.weights,
        }
    }
}

/// The index of [`RowsOf`] for the rows of [`NodeRows::new`].
fn grouped(starts: &[u32], cols: &[u32], class: &[u32], lengths: &[u32]) -> Vec<u32> {
    debug_assert_eq!(
        starts.len(),
        class.len() + 1,
        "a start per row and one past"
    );
    let cols_of = |r: usize| &cols[starts[r] as usize..starts[r + 1] as usize];
    let mut index = vec![lengths.len() as u32];
    index.extend(lengths.iter().flat_map(|&l| [l, 0]));
    // The rows by class, in order within each.
    let mut rows: Vec<u32> = (0..class.len() as u32).collect();
    rows.sort_by_key(|&r| class[r as usize]);
    for r in rows.into_iter().map(|r| r as usize) {
        let k = class[r] as usize;
        debug_assert_eq!(cols_of(r).len(), lengths[k] as usize, "row {r}'s length");
        index[2 + 2 * k] += 1;
        index.push(3 * r as u32);
        index.extend(cols_of(r).iter().map(|&c| 3 * c));
    }
    index
}

impl<I: Index> RowsOf<I> {
    /// The rows of `index` (see [`RowsOf::index`]) computing `len` points, if every index
    /// fits in `I`.
    ///
    /// # Panics
    /// If `index` is not rows of `len` slots and classes that are `weights` (what the
    /// kernel's unchecked reads rely on).
    fn new(len: u32, index: &[u32], weights: &Arc<[f64]>) -> Option<Self> {
        let narrow = index.iter().map(|&x| I::narrow(x)).collect::<Option<_>>()?;
        let mut rows = RowsOf {
            len,
            reach: 0,
            index: narrow,
            weights: weights.clone(),
        };
        let (mut terms, mut reach) = (0, 0);
        for (w, l, these) in rows.groups() {
            terms += w.len();
            for row in these.chunks_exact(l + 1) {
                assert!(row[0].get() + 3 <= 3 * len as usize, "a slot past the rows");
                reach = (row[1..].iter()).fold(reach, |r, c| r.max(c.get() + 3));
            }
        }
        let groups = rows.index[0].get();
        let counted: usize = (rows.index[1..1 + 2 * groups].chunks_exact(2))
            .map(|h| h[1].get() * (h[0].get() + 1))
            .sum();
        assert!(
            terms == weights.len() && 1 + 2 * groups + counted == index.len(),
            "rows that are not whole groups of the weights"
        );
        rows.reach = reach as u32;
        Some(rows)
    }

    /// The groups: each one's weights, row length and rows.
    fn groups(&self) -> impl Iterator<Item = (&[f64], usize, &[I])> {
        let g = self.index[0].get();
        let (heads, mut rows) = self.index[1..].split_at(2 * g);
        let mut weights = &self.weights[..];
        heads.chunks_exact(2).map(move |h| {
            let (l, n) = (h[0].get(), h[1].get());
            let (w, these);
            (w, weights) = weights.split_at(l);
            (these, rows) = rows.split_at(n * (l + 1));
            (w, l, these)
        })
    }

    /// Every row applied to `pos`, into `out` (one point per row): with AVX2 and FMA
    /// where the processor has them (a point's three coordinates in one vector, one
    /// multiply-add per weight; the descent of a tree spends most of its time here).
    ///
    /// # Panics
    /// If `pos` holds fewer points than the rows read, or `out` is not one per row.
    pub(super) fn apply(&self, pos: &[[f64; 3]], out: &mut [[f64; 3]]) {
        assert!(
            self.reach as usize <= 3 * pos.len() && out.len() == self.len as usize,
            "rows applied to too few points, or into the wrong number"
        );
        #[cfg(target_arch = "x86_64")]
        if crate::cpu::has_avx2_fma() {
            for (w, l, rows) in self.groups() {
                // SAFETY: the features were just detected; every column's three `f64`
                // are below `reach`, every slot's below `3 len` (both checked above and
                // in `new`).
                unsafe { group_avx(w, l, rows, pos, out) };
            }
            return;
        }
        self.apply_portable(pos, out);
    }

    /// [`apply`](Self::apply) without vector instructions.
    pub(super) fn apply_portable(&self, pos: &[[f64; 3]], out: &mut [[f64; 3]]) {
        let (pos, out) = (pos.as_flattened(), out.as_flattened_mut());
        for (w, l, rows) in self.groups() {
            for row in rows.chunks_exact(l + 1) {
                let mut acc = [0.0; 3];
                for (&c, &w) in row[1..].iter().zip(w) {
                    let p = &pos[c.get()..c.get() + 3];
                    (0..3).for_each(|k| acc[k] += w * p[k]);
                }
                out[row[0].get()..row[0].get() + 3].copy_from_slice(&acc);
            }
        }
    }
}

/// The rows of one group, each of length `l` with weights `w`, applied to `pos` into
/// `out`: for the lengths that occur (up to 17 terms, a smooth vertex point of valence
/// 8), in a loop of that length ([`group_of`]).
///
/// # Safety
/// The processor has AVX2 and FMA; `rows` holds rows of `l + 1` offsets ([`RowsOf::index`]),
/// the slot first (of a point of `out`), then the columns (of points of `pos`); `w` holds
/// `l` weights.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn group_avx<I: Index>(
    w: &[f64],
    l: usize,
    rows: &[I],
    pos: &[[f64; 3]],
    out: &mut [[f64; 3]],
) {
    macro_rules! by_length {
        ($($l:literal)*) => {
            match l {
                // SAFETY: as for this function, with `l` weights.
                $($l => unsafe { group_of::<I, $l>(w, rows, pos, out) },)*
                // SAFETY: as for this function.
                _ => unsafe { group_any(w, rows, pos, out) },
            }
        };
    }
    by_length!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17)
}

/// [`group_avx`] for rows of `L` terms.
///
/// # Safety
/// As [`group_avx`], with `w.len() == L`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn group_of<I: Index, const L: usize>(
    w: &[f64],
    rows: &[I],
    pos: &[[f64; 3]],
    out: &mut [[f64; 3]],
) {
    use crate::cpu::{load3, store3};
    use std::arch::x86_64::*;
    let mut ws = [_mm256_setzero_pd(); L];
    for (v, &w) in ws.iter_mut().zip(w) {
        *v = _mm256_set1_pd(w);
    }
    let (pos, out) = (
        pos.as_flattened().as_ptr(),
        out.as_flattened_mut().as_mut_ptr(),
    );
    for row in rows.chunks_exact(L + 1) {
        let mut acc = _mm256_setzero_pd();
        for (k, &w) in ws.iter().enumerate() {
            // SAFETY: the row has `L + 1` indices; its columns are points of `pos`.
            let x = unsafe { load3(pos.add(row.get_unchecked(k + 1).get())) };
            acc = _mm256_fmadd_pd(w, x, acc);
        }
        // SAFETY: the slot is a point of `out`.
        unsafe { store3(out.add(row.get_unchecked(0).get()), acc) };
    }
}

/// [`group_avx`] for rows of any length.
///
/// # Safety
/// As [`group_avx`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn group_any<I: Index>(w: &[f64], rows: &[I], pos: &[[f64; 3]], out: &mut [[f64; 3]]) {
    use crate::cpu::{load3, store3};
    use std::arch::x86_64::*;
    let (pos, out) = (
        pos.as_flattened().as_ptr(),
        out.as_flattened_mut().as_mut_ptr(),
    );
    for row in rows.chunks_exact(w.len() + 1) {
        let mut acc = _mm256_setzero_pd();
        for (&c, &w) in row[1..].iter().zip(w) {
            // SAFETY: the columns are points of `pos`.
            let x = unsafe { load3(pos.add(c.get())) };
            acc = _mm256_fmadd_pd(_mm256_set1_pd(w), x, acc);
        }
        // SAFETY: the slot is a point of `out`.
        unsafe { store3(out.add(row[0].get()), acc) };
    }
}

/// Whether `a` and `b` hold the same bits.
fn bits_equal(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// The weights of the nodes' rows of one surface, each distinct array kept once.
///
/// Nodes of different configurations mostly have the same classes (on a grid with creases
/// of sharpness 1, 2 or 3 on a tenth of its edges, 20,312 nodes have six distinct arrays),
/// so each node's array is looked up here when the node is built and shared. Equal means
/// the same bits, so a shared array gives every node the very weights it computed.
#[derive(Debug, Default)]
pub(super) struct WeightPool(Mutex<WeightMap>);

/// Arrays by a hash of their bits, each bucket compared array by array.
type WeightMap = HashMap<u64, Vec<Arc<[f64]>>, BuildHasherDefault<FxHasher>>;

impl WeightPool {
    /// The pool's array equal to `weights`, added the first time.
    pub(super) fn intern(&self, weights: &[f64]) -> Arc<[f64]> {
        let hash = {
            let mut h = FxHasher::default();
            weights.iter().for_each(|w| h.write_u64(w.to_bits()));
            h.finish()
        };
        let mut map = super::lock(&self.0);
        let bucket = map.entry(hash).or_default();
        if let Some(shared) = bucket.iter().find(|s| bits_equal(s, weights)) {
            return shared.clone();
        }
        let shared: Arc<[f64]> = weights.into();
        bucket.push(shared.clone());
        shared
    }

    /// Number of distinct arrays.
    #[cfg(test)]
    pub(super) fn len(&self) -> usize {
        super::lock(&self.0).values().map(Vec::len).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows with 8-bit and 16-bit indices give the points the same rows give with 32-bit
    /// ones, each into its own slot whatever group it is computed in, and the vector path
    /// gives those of the portable one (to the rounding of its fused multiply-adds); a
    /// node reading a point past 8 or 16 bits keeps wider ones.
    #[test]
    fn rows_of_every_width_agree() {
        // A face point, an edge point, and a second face point sharing the first's weights.
        let starts = [0, 4, 6, 10];
        let cols = [0, 1, 2, 3, 4, 1, 4, 5, 6, 7];
        let (class, lengths) = ([0, 1, 0], [4, 2]);
        let weights: Arc<[f64]> = vec![0.25, 0.25, 0.25, 0.25, 0.5, 0.5].into();
        let pos = points(8);
        let expect = |vs: &[usize], w: f64| -> [f64; 3] {
            std::array::from_fn(|k| vs.iter().map(|&v| w * pos[v][k]).sum())
        };
        let wanted = [
            expect(&[0, 1, 2, 3], 0.25),
            expect(&[4, 1], 0.5),
            expect(&[4, 5, 6, 7], 0.25),
        ];
        let index = grouped(&starts, &cols, &class, &lengths);
        let tiny = RowsOf::<u8>::new(3, &index, &weights).expect("fits");
        let narrow = RowsOf::<u16>::new(3, &index, &weights).expect("fits");
        let wide = RowsOf::<u32>::new(3, &index, &weights).expect("fits");
        let (mut a, mut b, mut c) = ([[0.0; 3]; 3], [[0.0; 3]; 3], [[0.0; 3]; 3]);
        let mut d = a;
        narrow.apply(&pos, &mut a);
        wide.apply(&pos, &mut b);
        narrow.apply_portable(&pos, &mut c);
        tiny.apply(&pos, &mut d);
        assert_eq!(a, b);
        assert_eq!(a, d);
        for (got, want) in [a, c].iter().flatten().zip(wanted.iter().chain(&wanted)) {
            for k in 0..3 {
                assert!((got[k] - want[k]).abs() <= 1e-15 * want[k].abs().max(1.0));
            }
        }

        // A column past 8 bits keeps 16-bit indices, one past 16 bits 32-bit ones.
        for far_col in [300, 70_000] {
            let mut far = pos.clone();
            far.resize(far_col + 1, [0.0; 3]);
            far[far_col] = [1.0, 2.0, 3.0];
            let half: Arc<[f64]> = vec![0.5, 0.5].into();
            let rows = NodeRows::new(&[0, 2], &[3, far_col as u32], &[0], &[2], half);
            let wide = matches!(rows, NodeRows::Wide(_));
            assert_eq!(wide, far_col > 65_535, "column {far_col}");
            assert!(!matches!(rows, NodeRows::Tiny(_)), "column {far_col}");
            let mut out = Vec::new();
            rows.apply(&far, &mut out);
            for k in 0..3 {
                assert!((out[0][k] - 0.5 * (pos[3][k] + far[far_col][k])).abs() < 1e-15);
            }
        }
    }

    /// `n` points with distinct, unround coordinates.
    fn points(n: usize) -> Vec<[f64; 3]> {
        (0..n)
            .map(|i| {
                let x = i as f64;
                [x, x * x / 7.0, 1.0 / (x + 1.0)]
            })
            .collect()
    }

    /// Rows of every length from 0 to 20 terms (each length a kernel of its own up to
    /// 17, the loop of any length past it), interleaved among groups, give the very sums
    /// of fused multiply-adds in the order of their terms, each in its slot.
    #[test]
    fn every_row_length_gives_its_sums() {
        let pos = points(40);
        let lengths: Vec<u32> = (0..=20).collect();
        let weights: Vec<f64> = (lengths.iter())
            .flat_map(|&l| (0..l).map(move |k| f64::from(k + 1) / f64::from(l + 3) - 0.1))
            .collect();
        let (mut starts, mut cols, mut class) = (vec![0], vec![], vec![]);
        // Two rows of each length, the second group's rows between the first's.
        for (r, l) in (0..2).flat_map(|r| lengths.iter().map(move |&l| (r, l))) {
            cols.extend((0..l).map(|k| (7 * k + 3 * l + r) % 40));
            starts.push(cols.len() as u32);
            class.push(l);
        }
        let rows = NodeRows::new(&starts, &cols, &class, &lengths, weights.clone().into());
        let mut out = Vec::new();
        rows.apply(&pos, &mut out);
        let mut first = vec![0];
        for &l in &lengths {
            first.push(first.last().copied().unwrap_or(0) + l as usize);
        }
        for (r, got) in out.iter().enumerate() {
            let (l, cs) = (
                class[r] as usize,
                &cols[starts[r] as usize..starts[r + 1] as usize],
            );
            let want: [f64; 3] = std::array::from_fn(|k| {
                (cs.iter().zip(&weights[first[l]..]))
                    .fold(0.0, |acc: f64, (&c, &w)| w.mul_add(pos[c as usize][k], acc))
            });
            if crate::cpu::has_avx2_fma() {
                assert_eq!(*got, want, "row {r} of {l} terms");
            }
            for k in 0..3 {
                assert!((got[k] - want[k]).abs() <= 1e-14, "row {r} of {l} terms");
            }
        }
    }

    /// Rows that read past the points they are given panic rather than read past them.
    #[test]
    #[should_panic(expected = "too few points")]
    fn rows_check_their_points() {
        let half: Arc<[f64]> = vec![0.5, 0.5].into();
        let rows = NodeRows::new(&[0, 2], &[0, 5], &[0], &[2], half);
        rows.apply(&points(5), &mut Vec::new());
    }

    /// The pool keeps one array per distinct bits: equal arrays come back shared, arrays
    /// that differ in one bit (or in length) do not.
    #[test]
    fn pool_shares_equal_weights_only() {
        let pool = WeightPool::default();
        let a = pool.intern(&[0.25, 0.25, 0.5]);
        let b = pool.intern(&[0.25, 0.25, 0.5]);
        let c = pool.intern(&[0.25, 0.25, f64::from_bits(0.5f64.to_bits() + 1)]);
        let d = pool.intern(&[0.25, 0.25]);
        assert!(Arc::ptr_eq(&a, &b));
        assert!(!Arc::ptr_eq(&a, &c) && !Arc::ptr_eq(&a, &d));
        assert_eq!((&c[..2], c[2].to_bits()), (&a[..2], a[2].to_bits() + 1));
        assert_eq!(pool.len(), 3);
    }
}
