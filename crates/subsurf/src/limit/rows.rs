//! The rows of a configuration-tree node: each refined point its children read, as sparse
//! weights on the points the node is evaluated on ([`NodeRows`]), and the pool that keeps
//! each distinct set of weights once per surface ([`WeightPool`]).
//!
//! A node's refined points are face, edge and vertex points, smooth or sharp, whose
//! weights are one of a few vectors (four quarters, the six of a smooth edge point, the
//! nine of a smooth vertex point of valence 4, the blends of a semi-sharp crease, ...). So
//! each row keeps its columns and where its weights start in the node's *classes*, the
//! distinct vectors, and nodes whose classes are the same share one array of them. On a
//! grid with creases on a tenth of its edges (6,835 configurations, 20,312 nodes) the
//! weights stored with every term were two thirds of the rows and the rows 43 % of the
//! heap; stored once per node, still 3.6 MB (a seventh of the heap); shared, six arrays
//! and the pool's map, under 2 KB.

use super::Index;
use crate::hash::FxHasher;
use crate::mesh::{Options, Topology};
use crate::refine::refinement_rows;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::{Arc, Mutex};

/// The rows of a node's refined points, with the narrowest indices that hold them.
///
/// The indices (where rows start, where their weights start, the columns) are 8-bit when
/// they fit, as they do on nearly every node (a cut-out of a few dozen points, its
/// refinement read through a couple of hundred terms: on a grid with creases on a tenth
/// of its edges, at most 24 columns and 140 terms), else 16-bit unless the node's cut-out
/// holds a face or vertex of thousands of sides. 32-bit, they were half of the rows;
/// 16-bit, still two thirds of the rows and a sixth of the heap of that grid.
#[derive(Debug)]
pub(super) enum NodeRows {
    Tiny(RowsOf<u8>),
    Narrow(RowsOf<u16>),
    Wide(RowsOf<u32>),
}

/// [`NodeRows`] with indices of type `I`.
#[derive(Debug)]
pub(super) struct RowsOf<I> {
    /// Number of rows, `n`.
    len: u32,
    /// In one allocation (three took a fifth more memory than the indices themselves):
    /// `n + 1` row starts, then `n` weight starts, then the columns. Row `r`'s columns
    /// are `cols[starts[r]..starts[r + 1]]`, its weights as many from `weights[first[r]]`.
    index: Box<[I]>,
    /// The node's classes, one after the other, from [`WeightPool::intern`].
    weights: Arc<[f64]>,
}

impl NodeRows {
    /// The rows of the refinement of `t` into `child` (its `refine_topology`) for the
    /// child vertices `verts`, with each column `c` (a vertex of `t`) mapped to `cols(c)`,
    /// the point the node is evaluated on; zero weights left out. The weights are
    /// interned in `pool`.
    pub fn refinement(
        t: &Topology,
        child: &Topology,
        options: &Options,
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
        refinement_rows(t, child, options, verts.iter().copied(), |cs, ws| {
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
        let mut start_of = vec![0; classes.len()];
        for &k in &order {
            start_of[k] = weights.len() as u32;
            weights.extend_from_slice(class(k));
        }
        let first: Vec<u32> = class_of.iter().map(|&k| start_of[k as usize]).collect();
        NodeRows::new(&starts, &all_cols, &first, pool.intern(&weights))
    }

    /// The rows of `starts`, `cols`, `first` (see [`RowsOf::index`]) and `weights`, with
    /// the narrowest indices they all fit.
    pub fn new(starts: &[u32], cols: &[u32], first: &[u32], weights: Arc<[f64]>) -> Self {
        if let Some(rows) = RowsOf::new(starts, cols, first, &weights) {
            NodeRows::Tiny(rows)
        } else if let Some(rows) = RowsOf::new(starts, cols, first, &weights) {
            NodeRows::Narrow(rows)
        } else {
            NodeRows::Wide(
                RowsOf::new(starts, cols, first, &weights)
                    .unwrap_or_else(|| unreachable!("32-bit indices fit")),
            )
        }
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        match self {
            NodeRows::Tiny(r) => r.len as usize,
            NodeRows::Narrow(r) => r.len as usize,
            NodeRows::Wide(r) => r.len as usize,
        }
    }

    /// Every row applied to `pos`, into `out`.
    pub fn apply(&self, pos: &[[f64; 3]], out: &mut Vec<[f64; 3]>) {
        out.resize(self.len(), [0.0; 3]);
        match self {
            NodeRows::Tiny(r) => r.apply(pos, out),
            NodeRows::Narrow(r) => r.apply(pos, out),
            NodeRows::Wide(r) => r.apply(pos, out),
        }
    }

    /// The weights the rows read (shared with the nodes that have the same classes).
    #[cfg(test)]
    pub fn weights(&self) -> &Arc<[f64]> {
        match self {
            NodeRows::Tiny(r) => &r.weights,
            NodeRows::Narrow(r) => &r.weights,
            NodeRows::Wide(r) => &r.weights,
        }
    }
}

impl<I: Index> RowsOf<I> {
    /// The rows of `starts`, `cols`, `first` (see [`RowsOf::index`]) and `weights`, if
    /// the indices fit in `I`.
    pub fn new(starts: &[u32], cols: &[u32], first: &[u32], weights: &Arc<[f64]>) -> Option<Self> {
        debug_assert_eq!(
            starts.len(),
            first.len() + 1,
            "a start per row and one past"
        );
        let index = (starts.iter().chain(first).chain(cols))
            .map(|&x| I::narrow(x))
            .collect::<Option<_>>()?;
        Some(RowsOf {
            len: first.len() as u32,
            index,
            weights: weights.clone(),
        })
    }

    /// The row starts (`n + 1`), the weight starts (`n`) and the columns.
    #[inline(always)]
    fn parts(&self) -> (&[I], &[I], &[I]) {
        let n = self.len as usize;
        let (starts, rest) = self.index.split_at(n + 1);
        let (first, cols) = rest.split_at(n);
        (starts, first, cols)
    }

    /// Every row applied to `pos`, into `out` (one point per row): with AVX2 and FMA
    /// where the processor has them (a point's three coordinates in one vector, one
    /// multiply-add per weight; the descent of a tree spends most of its time here).
    pub fn apply(&self, pos: &[[f64; 3]], out: &mut [[f64; 3]]) {
        #[cfg(target_arch = "x86_64")]
        if crate::cpu::has_avx2_fma() {
            // SAFETY: the features were just detected.
            unsafe { self.apply_avx(pos, out) };
            return;
        }
        self.apply_portable(pos, out);
    }

    /// [`apply`](Self::apply) without vector instructions.
    pub fn apply_portable(&self, pos: &[[f64; 3]], out: &mut [[f64; 3]]) {
        let (starts, first, cols) = self.parts();
        for (r, o) in out.iter_mut().enumerate() {
            let (a, b, w) = (starts[r].get(), starts[r + 1].get(), first[r].get());
            let mut acc = [0.0; 3];
            for (&c, &w) in cols[a..b].iter().zip(&self.weights[w..w + (b - a)]) {
                let p = &pos[c.get()];
                (0..3).for_each(|k| acc[k] += w * p[k]);
            }
            *o = acc;
        }
    }

    /// [`apply`](Self::apply) with AVX2 and FMA.
    ///
    /// # Safety
    /// The processor has AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn apply_avx(&self, pos: &[[f64; 3]], out: &mut [[f64; 3]]) {
        use std::arch::x86_64::*;
        let (starts, first, cols) = self.parts();
        // The three coordinates of a point in one masked load (the fourth lane zero, and
        // never read from memory).
        let xyz = _mm256_setr_epi64x(-1, -1, -1, 0);
        for (r, o) in out.iter_mut().enumerate() {
            let (a, b, w) = (starts[r].get(), starts[r + 1].get(), first[r].get());
            let mut acc = _mm256_setzero_pd();
            for (&c, &w) in cols[a..b].iter().zip(&self.weights[w..w + (b - a)]) {
                let p = &pos[c.get()];
                // SAFETY: `p` holds three `f64`, the lanes the mask loads.
                let x = unsafe { _mm256_maskload_pd(p.as_ptr(), xyz) };
                acc = _mm256_fmadd_pd(_mm256_set1_pd(w), x, acc);
            }
            // Straight from the register to the point: through an array on the stack, the
            // next row's loads could wait on that store wherever a point's address had
            // the same low 12 bits as the array's (4K aliasing), so the time depended on
            // where the stack happened to lie (`catmark_chaikin1`, address randomisation
            // off: 0.16 or 0.26 ms a repetition, by the size of the environment).
            // SAFETY: `o` holds three `f64`: two stored, then the third.
            unsafe {
                _mm_storeu_pd(o.as_mut_ptr(), _mm256_castpd256_pd128(acc));
                _mm_store_sd(o.as_mut_ptr().add(2), _mm256_extractf128_pd::<1>(acc));
            }
        }
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
    pub fn intern(&self, weights: &[f64]) -> Arc<[f64]> {
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
    pub fn len(&self) -> usize {
        super::lock(&self.0).values().map(Vec::len).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows with 8-bit and 16-bit indices give the points the same rows give with 32-bit
    /// ones, and the vector path gives those of the portable one (to the rounding of its
    /// fused multiply-adds); a node reading a point past 8 or 16 bits keeps wider ones.
    #[test]
    fn rows_of_every_width_agree() {
        // A face point, an edge point, and a second face point sharing the first's weights.
        let starts = [0, 4, 6, 10];
        let cols = [0, 1, 2, 3, 4, 1, 4, 5, 6, 7];
        let first = [0, 4, 0];
        let weights: Arc<[f64]> = vec![0.25, 0.25, 0.25, 0.25, 0.5, 0.5].into();
        let pos: Vec<[f64; 3]> = (0..8)
            .map(|i| {
                let x = f64::from(i);
                [x, x * x / 7.0, 1.0 / (x + 1.0)]
            })
            .collect();
        let expect = |vs: &[usize], w: f64| -> [f64; 3] {
            std::array::from_fn(|k| vs.iter().map(|&v| w * pos[v][k]).sum())
        };
        let wanted = [
            expect(&[0, 1, 2, 3], 0.25),
            expect(&[4, 1], 0.5),
            expect(&[4, 5, 6, 7], 0.25),
        ];
        let tiny = RowsOf::<u8>::new(&starts, &cols, &first, &weights).expect("fits");
        let narrow = RowsOf::<u16>::new(&starts, &cols, &first, &weights).expect("fits");
        let wide = RowsOf::<u32>::new(&starts, &cols, &first, &weights).expect("fits");
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
            let rows = NodeRows::new(&[0, 2], &[3, far_col as u32], &[0], half);
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
