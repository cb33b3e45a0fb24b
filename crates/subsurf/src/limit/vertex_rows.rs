//! The limit position and tangents of every vertex of a refined level as fixed weights on
//! the level's positions ([`VertexLimitRows`]), for re-posing (`crate::repose`).

use std::collections::HashMap;
use std::hash::BuildHasherDefault;

use rayon::prelude::*;

use super::VertexMasks;
use crate::hash::FxHasher;
use crate::mesh::Topology;
use crate::scheme::catmark::CatmullClark;
use crate::scheme::loop_::Loop;
use crate::scheme::{Bilinear, Rules, Scheme};

/// Rows applied per task of [`VertexLimitRows::apply`].
const BLOCK: usize = 4096;

/// How many rows ahead [`VertexLimitRows::apply`] asks for the points of a row: a row's
/// points lie in separate runs of the level (the children of faces, edges and vertices
/// are numbered apart), so without it each row waits on its points' cache misses.
const AHEAD: usize = 8;

/// The limit masks ([`super::limit_points`]) of the first vertices of a level, as rows:
/// each vertex's points (its faces' opposite corners, its edges' far ends, itself; the
/// order of [`VertexMasks::weights`]) with three weights each, for the limit position and
/// the two limit tangents, so that one pass over the points gives all three. The weights
/// are stored once per distinct row shape (a *class*: every smooth valence-4 vertex has the
/// same), 4 bytes per point and row otherwise.
///
/// Applied, each sum runs in the order of [`super::limit_points`] (faces, edges, vertex),
/// so on the same level positions the results are its own: a point that one mask does not
/// weigh adds a zero term to that mask's sum, which leaves it as it is.
#[derive(Clone, Debug)]
pub(crate) struct VertexLimitRows {
    /// Row `r`'s points are `cols[offsets[r]..offsets[r + 1]]`.
    offsets: Vec<u32>,
    cols: Vec<u32>,
    /// The class of each row; class `c`'s weights are
    /// `weights[class_offsets[c]..class_offsets[c + 1]]`, one `[position, t₁, t₂]` per point.
    class: Vec<u32>,
    class_offsets: Vec<u32>,
    weights: Vec<[f64; 3]>,
}

impl VertexLimitRows {
    /// The rows of vertices `0..n` of `level` (with full adjacency), with the limit masks
    /// of `scheme` (Catmull-Clark's for the Catmull-Clark family, Loop's, bilinear's; as
    /// `subdivide` moves a level to its limit). An isolated vertex's limit is itself, with
    /// zero tangents.
    ///
    /// # Panics
    /// With [`Scheme::Nurss`], whose limit rows are `nonuniform::LimitRows`.
    pub(crate) fn new(scheme: Scheme, level: &Topology, n: usize) -> Self {
        match scheme {
            Scheme::Loop => Self::with(Loop, level, n),
            Scheme::Bilinear => Self::with(Bilinear, level, n),
            Scheme::CatmullClark | Scheme::Adjustable(_) => Self::with(CatmullClark, level, n),
            Scheme::Nurss => panic!("NURSS limit rows are nonuniform::LimitRows"),
        }
    }

    /// [`new`](Self::new) with the masks of `rules`.
    fn with<R: Rules>(rules: R, level: &Topology, n: usize) -> Self {
        let mut masks = VertexMasks::default();
        let mut ids: HashMap<Vec<u64>, u32, BuildHasherDefault<FxHasher>> = HashMap::default();
        let mut rows = VertexLimitRows {
            offsets: Vec::with_capacity(n + 1),
            cols: Vec::new(),
            class: Vec::with_capacity(n),
            class_offsets: vec![0],
            weights: Vec::new(),
        };
        rows.offsets.push(0);
        let (mut row, mut bits) = (Vec::new(), Vec::new());
        for v in 0..n {
            row.clear();
            if masks.load(rules, level, v, true) {
                masks.terms(v, |x, w| row.push((x, w)));
            } else {
                row.push((v as u32, [1.0, 0.0, 0.0]));
            }
            row.retain(|(_, w)| w.iter().any(|&w| w != 0.0));
            bits.clear();
            bits.extend(row.iter().flat_map(|(_, w)| w.map(f64::to_bits)));
            // Most rows repeat a class already seen: look it up without copying the key.
            let class = match ids.get(&bits) {
                Some(&class) => class,
                None => {
                    rows.weights.extend(row.iter().map(|&(_, w)| w));
                    rows.class_offsets.push(rows.weights.len() as u32);
                    let class = (rows.class_offsets.len() - 2) as u32;
                    ids.insert(bits.clone(), class);
                    class
                }
            };
            rows.class.push(class);
            rows.cols.extend(row.iter().map(|&(x, _)| x));
            rows.offsets.push(rows.cols.len() as u32);
        }
        rows
    }

    /// Asks the processor to start loading the points of row `r` (if there is one) from
    /// `src`. A hint only: it never faults, and on other processors than x86-64 it is
    /// nothing.
    #[inline(always)]
    fn prefetch(&self, src: &[[f64; 3]], r: usize) {
        #[cfg(target_arch = "x86_64")]
        if r + 1 < self.offsets.len() {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            for &x in &self.cols[self.offsets[r] as usize..self.offsets[r + 1] as usize] {
                if let Some(q) = src.get(x as usize) {
                    // SAFETY: `q` is a reference into `src`; SSE is part of x86-64.
                    unsafe { _mm_prefetch::<_MM_HINT_T0>(q.as_ptr().cast()) };
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = (src, r);
    }

    /// Limit positions into `pos` and tangents into `t1`, `t2` (one per row), from the
    /// level's positions `src`, in parallel over blocks of rows.
    ///
    /// # Panics
    /// If the outputs do not have one value per row, or a point is out of bounds of `src`.
    pub(crate) fn apply(
        &self,
        src: &[[f64; 3]],
        pos: &mut [[f64; 3]],
        t1: &mut [[f64; 3]],
        t2: &mut [[f64; 3]],
    ) {
        let n = self.class.len();
        assert!(
            pos.len() == n && t1.len() == n && t2.len() == n,
            "one value per row"
        );
        if n <= BLOCK || rayon::current_num_threads() == 1 {
            self.block(src, 0, pos, t1, t2);
        } else {
            (pos.par_chunks_mut(BLOCK).zip(t1.par_chunks_mut(BLOCK)))
                .zip(t2.par_chunks_mut(BLOCK))
                .enumerate()
                .for_each(|(b, ((pos, t1), t2))| self.block(src, b * BLOCK, pos, t1, t2));
        }
    }

    /// [`apply`](Self::apply) to the rows from `first` on, as many as `pos` holds.
    fn block(
        &self,
        src: &[[f64; 3]],
        first: usize,
        pos: &mut [[f64; 3]],
        t1: &mut [[f64; 3]],
        t2: &mut [[f64; 3]],
    ) {
        for (i, ((p, a), c)) in pos.iter_mut().zip(t1).zip(t2).enumerate() {
            let r = first + i;
            self.prefetch(src, r + AHEAD);
            let cols = &self.cols[self.offsets[r] as usize..self.offsets[r + 1] as usize];
            let k = self.class[r] as usize;
            let ws = &self.weights[self.class_offsets[k] as usize..];
            let mut acc = [[0.0; 3]; 3];
            for (&x, w) in cols.iter().zip(ws) {
                let q = src[x as usize];
                for (acc, w) in acc.iter_mut().zip(w) {
                    for j in 0..3 {
                        acc[j] += w * q[j];
                    }
                }
            }
            [*p, *a, *c] = acc;
        }
    }
}
