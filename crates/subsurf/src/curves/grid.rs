//! A uniform hash grid over 3-D points and segments: the near-neighbour searches of curve
//! interpolation (control points shared by curves, control polygons passing near each other,
//! control points matched to host vertices) in time linear in the input for inputs whose
//! points are spread out (each cell holds a bounded number of them), where comparing every
//! pair was quadratic.
//!
//! Cells are cubes of side `h` keyed by `⌊(p − origin) / h⌋` (saturating); a point within
//! `h` of `p` is in one of the 27 cells around `p`'s cell. A segment is entered in the cells
//! around points sampled along it at most `h / 2` apart, so that every point within `h / 4` of
//! the segment lies in a cell that holds it ([`Grid::insert_segment`]).

use crate::geom::{norm, sub, V3};
use crate::hash::FxHasher;
use std::collections::HashMap;
use std::hash::BuildHasherDefault;

type Key = [i64; 3];

/// A uniform hash grid of ids (see the [module documentation](self)).
pub(crate) struct Grid {
    cell: f64,
    origin: V3,
    cells: HashMap<Key, Vec<u32>, BuildHasherDefault<FxHasher>>,
}

impl Grid {
    /// An empty grid of cubes of side `cell` (finite, > 0) anchored at `origin`.
    pub(crate) fn new(cell: f64, origin: V3) -> Self {
        Self {
            cell,
            origin,
            cells: HashMap::default(),
        }
    }

    fn key(&self, p: &V3) -> Key {
        // `as` saturates: points far outside the grid's range share its outermost cells.
        [0, 1, 2].map(|k| ((p[k] - self.origin[k]) / self.cell).floor() as i64)
    }

    fn add(&mut self, key: Key, id: u32) {
        let ids = self.cells.entry(key).or_default();
        if ids.last() != Some(&id) {
            ids.push(id);
        }
    }

    /// Enters `id` at point `p`.
    pub(crate) fn insert_point(&mut self, p: &V3, id: u32) {
        let k = self.key(p);
        self.add(k, id);
    }

    /// Enters `id` for the segment `p q` in the cells around points sampled along it at most
    /// half a cell apart; returns the number of cells entered (the work done). Every point
    /// within a quarter cell of the segment is in a cell that holds `id`.
    pub(crate) fn insert_segment(&mut self, p: &V3, q: &V3, id: u32) -> u64 {
        let d = sub(q, p);
        let steps = (2.0 * norm(&d) / self.cell).ceil().clamp(1.0, 1e9) as usize;
        let mut work = 0;
        let mut last = None;
        for s in 0..=steps {
            let t = s as f64 / steps as f64;
            let k = self.key(&[p[0] + t * d[0], p[1] + t * d[1], p[2] + t * d[2]]);
            if last == Some(k) {
                continue;
            }
            last = Some(k);
            for n in neighbours(k) {
                self.add(n, id);
                work += 1;
            }
        }
        work
    }

    /// The ids entered in the 27 cells around `p`'s cell, by cell (an id entered in several
    /// of them is given once per cell).
    pub(crate) fn near(&self, p: &V3, mut f: impl FnMut(u32)) {
        for n in neighbours(self.key(p)) {
            if let Some(ids) = self.cells.get(&n) {
                ids.iter().for_each(|&id| f(id));
            }
        }
    }

    /// The ids of every non-empty cell, in no particular order.
    pub(crate) fn cells(&self) -> impl Iterator<Item = &[u32]> {
        self.cells.values().map(Vec::as_slice)
    }
}

/// The 27 keys around `k` (itself included).
fn neighbours(k: Key) -> impl Iterator<Item = Key> {
    (0..27).map(move |i: i64| {
        [
            k[0].saturating_add(i % 3 - 1),
            k[1].saturating_add((i / 3) % 3 - 1),
            k[2].saturating_add(i / 9 - 1),
        ]
    })
}

/// The smallest corner of the bounding box of `points` (the origin when there are none).
pub(crate) fn lower_corner<'a>(points: impl Iterator<Item = &'a V3>) -> V3 {
    let mut lo = [f64::INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
        }
    }
    if lo.iter().all(|x| x.is_finite()) {
        lo
    } else {
        [0.0; 3]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn near_points_are_found_and_far_ones_are_not() {
        let mut g = Grid::new(0.5, [0.0; 3]);
        g.insert_point(&[0.1, 0.1, 0.1], 1);
        g.insert_point(&[0.6, 0.1, 0.1], 2);
        g.insert_point(&[3.0, 0.1, 0.1], 3);
        let mut found = Vec::new();
        g.near(&[0.45, 0.1, 0.1], |id| found.push(id));
        found.sort_unstable();
        assert_eq!(found, [1, 2]);
    }

    #[test]
    fn a_segment_is_in_every_cell_near_it() {
        let mut g = Grid::new(0.25, [0.0; 3]);
        let (p, q) = ([0.0, 0.0, 0.0], [3.0, 2.0, 1.0]);
        g.insert_segment(&p, &q, 7);
        for i in 0..=100 {
            let t = i as f64 / 100.0;
            // Points a little off the segment (< a quarter cell).
            let x = [3.0 * t + 0.05, 2.0 * t - 0.04, t + 0.03];
            let hit = g.cells.get(&g.key(&x)).is_some_and(|ids| ids.contains(&7));
            assert!(hit, "{x:?}");
        }
    }
}
