//! Single-crease patches: the exact limit surface, in closed form, of a quad that would be a
//! regular bicubic patch but for one straight semi-sharp crease along one of its sides.
//!
//! # Where it applies
//! Quad `f` whose four corners are smooth interior vertices of four quads (vertex
//! sharpness 0, no infinitely sharp edge), and whose only sharp edges at those corners are
//! the three edges of one grid line of its 4×4 control net through one of its sides (the
//! side and its two straight extensions), all with the same semi-sharp sharpness `s`, with
//! [`CreaseMethod::Uniform`]. (Edges further out do not
//! shape `f`'s surface; see [`super::local`].) OpenSubdiv's regression shapes
//! `catmark_pawn` and `catmark_bishop` are mostly such faces (sharpness-6 rings).
//!
//! # Why the surface is a tensor product
//! Across a straight crease line of a regular grid every Catmull-Clark rule that applies
//! factors into a rule along the crease times a rule across it (weights `[¼ ¾ ¼]/…`
//! written per direction):
//! - smooth vertices, face points and smooth edge points are the tensor products of the
//!   cubic B-spline rules `[⅛ ¾ ⅛]` (at old points) and `[½ ½]` (between them);
//! - a vertex on the crease is `[⅛ ¾ ⅛]` along it times the identity across it when sharp,
//!   `[⅛ ¾ ⅛]` across when smooth; an edge point on the crease is `[½ ½]` along it times
//!   the same two choices across; when the sharpness `σ` of a step is in `(0, 1)` both are
//!   blended with weight `σ` on the sharp rule ([`crate::scheme::crease::fractional_weight`],
//!   [`crate::scheme::Rules::edge_mask`]: the same weight for vertices and edges, as both
//!   crease edges at a crease vertex carry the same `σ`).
//!
//! So along the crease every step is the uniform cubic B-spline rule, and across it a
//! level-dependent curve scheme: at step `k` the crease point is blended between itself
//! (weight `w_k = min(σ_k, 1)`, `σ_k = s − k` while positive) and `[⅛ ¾ ⅛]`. The limit is
//! `S(x, y) = Σₐ Σₘ Nₐ(x) Φₘ(y) P[a][m]` with `N` the uniform cubic B-spline basis along
//! the crease and `Φ` the limit functions of the curve scheme across it (`y` the distance
//! from the crease, rows `m = −1, 0, 1, 2` at `y = m`, the crease at `m = 0`).
//!
//! # The curve scheme's limit functions
//! After `L` sharp steps (`σ_L = 0`) the curve is the uniform B-spline of its level-`L`
//! points. A segment `[h, 2h]` (`h = 2^-l`, `1 ≤ l ≤ L`) is the B-spline segment of the
//! level-`l` points at `y = 0, h, 2h, 3h` (its later refinement never uses the crease
//! point's rule: the points it needs are the new point between `0` and `h`, `[½ ½]`, and
//! old points other than the crease); the segment `[0, 2^-L]` is that of the level-`L`
//! points at `y = −h, 0, h, 2h`. [`CreaseBasis`] holds these points as weights on the
//! four rows, by running the curve scheme on unit rows; the level-`l + 1` points at
//! `m = −1..3` need only the level-`l` points at `m = −1..3`, so each level costs 20
//! weights. This is the construction of Nießner, Loop, Greiner, "Efficient Evaluation of
//! Semi-Smooth Creases in Catmull-Clark Subdivision Surfaces" (Eurographics 2012), which
//! OpenSubdiv's adaptive patches use for the same faces.
//!
//! Checked against the general local refinement (configuration trees) for sharpness
//! 0.3 to 9.7 and every side, and against OpenSubdiv's `Bfr` on the regression shapes.

use super::bspline::{basis, tensor_batch, transpose_bases, Batch, Lanes, Order, LANES};
use crate::mesh::{CreaseMethod, Options, Topology};
use crate::refine::patch::{patch_cells, walk, Cell, Corner, Sharp};
use crate::scheme::crease;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// The limit functions of the curve scheme across a crease of sharpness `s` (see the
/// module docs).
#[derive(Debug)]
pub(super) struct CreaseBasis {
    /// `segs[l - 1][b]`: level-`l` point `m = b` (`0..=3`) as weights on rows `−1..=2`.
    segs: Vec<[[f64; 4]; 4]>,
    /// Level-`L` points `m = −1..=2`.
    last: [[f64; 4]; 4],
}

impl CreaseBasis {
    /// The basis for sharpness `s` (semi-sharp: `0 < s < 10`).
    pub(super) fn new(s: f32) -> Self {
        // Level points m = -1..=3 (index m + 1) as weights on the rows m = -1..=2.
        let mut pts = [[0.0; 4]; 5];
        for (m, p) in pts.iter_mut().take(4).enumerate() {
            p[m] = 1.0;
        }
        let mut segs = Vec::new();
        let mut sigma = s;
        while crease::is_sharp(sigma) && segs.len() < 16 {
            let w = f64::from(sigma.min(1.0));
            let at = |m: i32| pts[(m + 1) as usize];
            let lerp = |a: [f64; 4], b: [f64; 4], t: f64| {
                std::array::from_fn(|i| a[i] + t * (b[i] - a[i]))
            };
            let vertex = |c: i32| {
                let (a, p, b) = (at(c - 1), at(c), at(c + 1));
                let smooth: [f64; 4] = std::array::from_fn(|i| 0.125 * (a[i] + b[i]) + 0.75 * p[i]);
                if c == 0 {
                    lerp(smooth, p, w)
                } else {
                    smooth
                }
            };
            let mid = |c: i32| -> [f64; 4] {
                let (a, b) = (at(c), at(c + 1));
                std::array::from_fn(|i| 0.5 * (a[i] + b[i]))
            };
            // New m = -1 (between -1 and 0), 0, 1, 2, 3 (between 1 and 2).
            pts = [mid(-1), vertex(0), mid(0), vertex(1), mid(1)];
            segs.push([pts[1], pts[2], pts[3], pts[4]]);
            sigma = crease::decrement(sigma);
        }
        let last = [pts[0], pts[1], pts[2], pts[3]];
        CreaseBasis { segs, last }
    }

    /// `Φₘ(y)` and its first and second derivatives, for `y` in `[0, 1]`.
    fn eval(&self, y: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
        let levels = self.segs.len();
        let mut h = 0.5;
        let mut l = 1;
        while y < h && l < levels {
            h *= 0.5;
            l += 1;
        }
        let (m, t) = if y >= h {
            (&self.segs[l - 1], y / h - 1.0)
        } else {
            (&self.last, y / h)
        };
        let (b, d, dd) = basis(t);
        // `h` is a power of two: multiplying by its inverse is dividing by it, bit for
        // bit, without a division per term.
        let (inv, inv2) = (1.0 / h, 1.0 / (h * h));
        let mut out = ([0.0; 4], [0.0; 4], [0.0; 4]);
        for (k, row) in m.iter().enumerate() {
            for r in 0..4 {
                out.0[r] += b[k] * row[r];
                out.1[r] += d[k] * row[r] * inv;
                out.2[r] += dd[k] * row[r] * inv2;
            }
        }
        out
    }
}

/// Crease bases by sharpness (bits), shared by the faces of one surface.
#[derive(Debug, Default)]
pub(super) struct CreaseBases(Mutex<HashMap<u32, Arc<CreaseBasis>>>);

impl CreaseBases {
    pub(super) fn get(&self, s: f32) -> Arc<CreaseBasis> {
        super::lock(&self.0)
            .entry(s.to_bits())
            .or_insert_with(|| Arc::new(CreaseBasis::new(s)))
            .clone()
    }
}

/// A single-crease patch (see the module docs).
#[derive(Clone, Debug)]
pub(super) struct CreasePatch {
    /// The control net in the crease's frame: `net[a][m]`, `a` along the crease (the
    /// face's own direction), `m` across it from row `−1` (`m = 0`) to `2` (`m = 3`).
    net: [[[f64; 3]; 4]; 4],
    /// The face's side on the crease (0: `v = 0`, 1: `u = 1`, 2: `v = 1`, 3: `u = 0`).
    side: usize,
    basis: Arc<CreaseBasis>,
}

impl CreasePatch {
    /// The patch with control net `cp[i][j]` (`i` along `u`), crease side `side` and
    /// basis `basis`.
    pub(super) fn from_net(cp: &[[[f64; 3]; 4]; 4], side: usize, basis: Arc<CreaseBasis>) -> Self {
        let mut patch = CreasePatch {
            net: Default::default(),
            side,
            basis,
        };
        patch.set_net(cp);
        patch
    }

    /// Sets the control net `cp[i][j]` (`i` along `u`), keeping the side and the basis.
    pub(super) fn set_net(&mut self, cp: &[[[f64; 3]; 4]; 4]) {
        // cp[i][j]: i along u, j along v. Map to net[a][m].
        // Plain loops of copies: nested `array::from_fn` built each point in a temporary
        // and read it back across two stores (a stalled store forward per point).
        for (a, row) in self.net.iter_mut().enumerate() {
            for (m, p) in row.iter_mut().enumerate() {
                *p = match self.side {
                    0 => cp[a][m],
                    2 => cp[a][3 - m],
                    3 => cp[m][a],
                    _ => cp[3 - m][a],
                };
            }
        }
    }

    /// Position and derivatives (of `order`) at every point of `batch`, the derivatives
    /// multiplied as [`tensor_batch`] says.
    pub(crate) fn eval_batch(&self, order: Order, scale: f64, batch: &mut impl Batch) {
        // x along the crease, y across it (distance from the crease).
        let side = self.side;
        let frame = |u: f64, v: f64| match side {
            0 => (u, v),
            2 => (u, 1.0 - v),
            3 => (v, u),
            _ => (v, 1.0 - u),
        };
        let bases = |u: Lanes, v: Lanes| {
            let xy: [(f64, f64); LANES] = std::array::from_fn(|l| frame(u[l], v[l]));
            (
                transpose_bases(xy.map(|(x, _)| basis(x))),
                transpose_bases(xy.map(|(_, y)| self.basis.eval(y))),
            )
        };
        tensor_batch(&self.net, bases, order, scale, batch);
        if side == 0 {
            return;
        }
        // From (x, y) derivatives to (u, v) ones.
        let neg = |x: [f64; 3]| x.map(|c| -c);
        for i in 0..batch.len() {
            let d = batch.out(i);
            match side {
                2 => (d.dv, d.duv) = (neg(d.dv), neg(d.duv)),
                3 => (d.du, d.dv, d.duu, d.dvv) = (d.dv, d.du, d.dvv, d.duu),
                _ => {
                    (d.du, d.dv, d.duu, d.duv, d.dvv) = (neg(d.dv), d.du, d.dvv, neg(d.duv), d.duu)
                }
            }
        }
    }
}

/// The control net (no phantoms), the crease side and the sharpness of quad `f` if it is a
/// single-crease face (see the module docs).
pub(super) fn single_crease(
    t: &Topology,
    f: usize,
    options: &Options,
) -> Option<([[Cell; 4]; 4], usize, f32)> {
    if options.crease_method != CreaseMethod::Uniform {
        return None;
    }
    let fv = t.face_vertices(f);
    if fv.len() != 4 || t.is_hole(f) {
        return None;
    }
    // Smooth interior valence-4 corners of quads, semi-sharp edges allowed.
    let closed = |k: usize| -> Option<Corner> {
        let c = fv[k] as usize;
        let tag = t.vertex_tag(c);
        if tag.boundary || tag.non_manifold || tag.inf_sharp_edges || tag.semi_sharp {
            return None;
        }
        if t.vertex_sharpness(c) != 0.0 || t.vertex_edges(c).len() != 4 {
            return None;
        }
        let (ring, closed) = walk(t, f, c, true, Sharp::LIMIT);
        let quads = ring.iter().all(|&(g, _)| t.face_vertices(g).len() == 4);
        (closed && ring.len() == 3 && quads).then(|| Corner::Closed([ring[0], ring[1], ring[2]]))
    };
    let cells = patch_cells(t, f, closed, Sharp::LIMIT)?;
    let net = cells.map(|col| col.map(|c| c.verts[0]));
    // The sharp edges at the corners, as vertex pairs.
    let mut sharp: Vec<([u32; 2], f32)> = Vec::with_capacity(4);
    for &c in fv {
        for &e in t.vertex_edges(c as usize) {
            let s = t.edge_sharpness(e as usize);
            if s > 0.0 {
                let mut ends = t.edge_vertices(e as usize);
                ends.sort_unstable();
                if !sharp.iter().any(|(x, _)| *x == ends) {
                    sharp.push((ends, s));
                }
            }
        }
    }
    if sharp.len() != 3 {
        return None;
    }
    let s = sharp[0].1;
    if !crease::is_semi_sharp(s) || sharp.iter().any(|&(_, x)| x != s) {
        return None;
    }
    for side in 0..4 {
        let line: [(usize, usize); 4] = match side {
            0 => [(0, 1), (1, 1), (2, 1), (3, 1)],
            1 => [(2, 0), (2, 1), (2, 2), (2, 3)],
            2 => [(0, 2), (1, 2), (2, 2), (3, 2)],
            _ => [(1, 0), (1, 1), (1, 2), (1, 3)],
        };
        let on_line = (0..3).all(|i| {
            let (a, b) = (line[i], line[i + 1]);
            let mut ends = [net[a.0][a.1], net[b.0][b.1]];
            ends.sort_unstable();
            sharp.iter().any(|(x, _)| *x == ends)
        });
        if on_line {
            return Some((cells, side, s));
        }
    }
    None
}
