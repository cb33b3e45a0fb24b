//! Limit points of the vertices of a NURSS level.
//!
//! - **Corners** (and isolated vertices) stay put: the limit is the point itself.
//! - **Crease and boundary vertices** lie on the cubic B-spline curve of their chain of sharp
//!   edges: with `a = d_{i−1}`, `b = d_i` the intervals of the two sharp edges and `a'`, `b'`
//!   those beyond them (read as by the refinement rules), the point at the vertex's knot is the
//!   blossom `B(t, t, t)` of the span,
//!   `C = b/(a+b) · [b P_{i−1} + (a'+a) P_i]/(a'+a+b) + a/(a+b) · [(b+b') P_i + a P_{i+1}]/(a+b+b')`
//!   (closed form; `C = P_i` when `a + b = 0`).
//! - **Smooth vertices and darts**: one step of NURSS makes the 1-ring of every vertex a fan
//!   of quads whose next refinement depends only on the fan itself (its points, its intervals
//!   `h_i`, the intervals of the fan's outer edges, and `d±` values that, from the second step
//!   on, are functions of those intervals: at an edge point the halves of the split edge and the
//!   face-interior edges continue straight through, and in a quad opposite face-interior
//!   edges have equal intervals). The limit point is the limit of the vertex point under
//!   repeated refinement of this fan alone (`O(valence)` work per step). It is iterated
//!   until two successive vertex points differ by at most [`LIMIT_TOLERANCE`] times the fan's
//!   size (plus its distance to the origin), for at most 64 steps (`¼` per step on regular
//!   uniform grids: about 25 steps); a fan that has not converged by then is *slow*, and its
//!   limit is taken from the step's matrix `S` instead (below). On regular grids this
//!   equals the tensor-product B-spline evaluated at the vertex's knots (tested in
//!   `tests/integration/nurss.rs` against de Boor), and with equal intervals Catmull-Clark's
//!   limit position.
//!
//! # Slow fans
//! Next to small or zero intervals, NURSS converges slowly at extraordinary vertices: the
//! subdominant eigenvalue of a pole's fan with one zero interval on its edges is 0.93 at
//! valence 8, 0.9989 at valence 64 and 0.99996 at valence 360, and with an interval of 0.3
//! instead of 0 at valence 64, 0.78 (it varies continuously with the interval: 1e-2 gives
//! 0.987, 1e-8 the zero interval's value; a property of the seed's rules, not of the zero
//! stand-in). There the limit can lie far from the refined points of any level one would
//! compute — 0.15 from the valence-64 pole in a model of size 2 — and iterating does not
//! reach it. After 64 steps the fan's intervals have converged (relative to each other,
//! the face-interior intervals approach the split ones by half per step), so every further
//! step is the same matrix `S`, of size `(1 + 2n)²`, built by stepping copies of the fan on
//! unit points. The limit is the centre's row of `S^∞` applied to the fan's points, computed
//! by squaring `S` until that row changes by at most 8 ulp (`2^k` steps in `k` squarings;
//! each squaring's rows are rescaled to sum to 1, which keeps rounding from growing the
//! eigenvalue 1). Squaring, not the left eigenvector of eigenvalue 1: two zero intervals at
//! a vertex can make that eigenvalue double (the fan stops shrinking without becoming a
//! point, while its centre converges), where the eigenvector is not unique but the powers
//! still converge. Powers that do not converge within `2^40` steps mean the scheme has no
//! limit there; the point after 64 steps is returned. The cost is `O(n³)` per squaring,
//! for slow fans only (`subdivide --limit` of `catmark_pole360` with a zero interval at
//! its pole takes 0.35 s). A fan accepted by the
//! iteration is within `LIMIT_TOLERANCE / (1 − λ)` of its limit (`λ` its subdominant
//! eigenvalue), which only a slow mode left almost unexcited could make large. Levels
//! agree to 1e-14 where the 400 iterated steps used before had left points 1.1e-4 apart per
//! level at the valence-64 pole (tested in `tests/integration/nurss.rs`, and against
//! 60,000 iterated steps in this module's tests).
//!
//! # Settled fans
//! A step's weights depend only on the fan's intervals `h`, `ga`, `gb` (the others, `d±`
//! and the intervals beyond, are functions of them from the second step on; all are
//! rescaled each step, which the rules, homogeneous of degree 0, do not see). So when a step
//! leaves `h`, `ga`, `gb` exactly as they were, every further step is the same matrix `S`,
//! and the limit is taken from its powers at once, as for a slow fan. Fans settle wherever
//! the intervals are locally those of a tensor product (equal on opposite edges of each
//! quad, as in the control mesh of a B-spline surface): there the face-interior intervals
//! are already half the split ones, and the first step settles the fan. Such a fan costs
//! one step on unit points and a few squarings (about 5 at the rate `¼` of a regular grid)
//! instead of about 20 steps (BENCHMARKS.md has the effect on `subdivide --limit` and the
//! `Reposer`). Where opposite edges differ, the face-interior
//! intervals approach the split ones by half per step and never quite settle (with
//! random intervals on the same mesh, 4 % of the fans settle, and the times are unchanged).

use rayon::prelude::*;

use crate::mesh::{Rule, Topology};
use crate::refine::nurss::{
    across_values, child_knots, effective_knots, refine_nurss_step, AcrossValues, NurssMasks,
};
use crate::refine::nurss::{project, Nurss};
use crate::refine::refine_topology;
use crate::scheme::nurss::{
    curve_edge_weights, edge_weights, face_weights, midpoint_weights, vertex_weights, RingIntervals,
};

/// Relative tolerance of the fan iteration for smooth vertices: it stops when the vertex
/// point moves by less than this times the fan's diameter (plus its distance to the origin).
pub const LIMIT_TOLERANCE: f64 = 1e-15;

/// Steps of the fan iterated before its limit is taken from the powers of its step matrix
/// instead (by then its intervals have converged, so every further step is that matrix).
const ITERATED_STEPS: usize = 64;

/// The squared step matrix has converged when a squaring moves no weight of the centre's
/// row by more than this.
const SQUARING_TOLERANCE: f64 = 8.0 * f64::EPSILON;

/// Most squarings of the step matrix (`2^40` steps).
const MAX_SQUARINGS: usize = 40;

/// Unit vectors stepped together by [`Fan::limit_weights`] and [`Fan::step_matrix`]: the
/// points of a fan of valence up to 7 in one copy.
const UNIT_BLOCK: usize = 16;

impl Nurss {
    /// Whether the level has smooth vertices or darts, whose limits need the fans of one
    /// step more.
    fn has_fans(&self) -> bool {
        let t = &self.topology;
        (0..t.num_vertices())
            .any(|v| matches!(t.vert_tags[v].get().rule, Rule::Smooth | Rule::Dart))
    }

    /// Every edge's own interval as the rules read it ([`effective_knots`]): the crease
    /// limits' intervals.
    fn own_intervals(&self) -> Vec<f64> {
        let t = &self.topology;
        let eff = effective_knots(&self.knots);
        (0..t.num_edges()).map(|e| eff.own(t, e)).collect()
    }

    /// The limit position of every vertex of the current level (one refinement step of the
    /// level is computed on the way, when it has smooth vertices; see the
    /// module documentation for how: closed form on creases and boundaries, iterated
    /// refinement of the vertex's quad fan for smooth vertices). Rational meshes are handled in
    /// homogeneous coordinates and projected at the end.
    pub fn limit_points(&self) -> Vec<[f64; 3]> {
        let t = &self.topology;
        let nv = t.num_vertices();
        let child = self
            .has_fans()
            .then(|| refine_nurss_step(t, &self.options, &self.knots, &self.points));
        let child_across = child
            .as_ref()
            .map(|(c, _, k)| across_values(c, &effective_knots(k)));
        let own = self.own_intervals();
        // Every vertex on its own: in parallel over chunks (the same result on any number
        // of threads).
        let limit = |v: usize| {
            let p = self.points[v];
            if t.vertex_edges(v).is_empty() {
                return p;
            }
            match t.vert_tags[v].get().rule {
                Rule::Corner => p,
                Rule::Crease => crease_weights(t, &own, v)
                    .map_or(p, |w| weighted(w.map(|(q, x)| (x, &self.points[q])))),
                Rule::Smooth | Rule::Dart => match (&child, &child_across) {
                    (Some((c, pts, _)), Some(ac)) => {
                        Fan::gather(c, ac, v, |i| pts[i]).map_or(p, Fan::limit)
                    }
                    _ => p,
                },
            }
        };
        (0..nv)
            .into_par_iter()
            .with_min_len(1024)
            .map(|v| project(&limit(v), self.rational))
            .collect()
    }
}

/// The limit point of every vertex of a level as a row of weights on the level's points
/// (CSR): [`Nurss::limit_rows`], the rows of re-posing the limit
/// ([`crate::Reposer::new`] with [`Scheme::Nurss`](crate::Scheme::Nurss)).
#[derive(Clone, Debug, Default)]
pub(crate) struct LimitRows {
    offsets: Vec<u32>,
    cols: Vec<u32>,
    weights: Vec<f64>,
}

/// Vertices per block of [`Nurss::limit_rows`] and [`LimitRows::apply`].
const ROWS_BLOCK: usize = 1024;

impl LimitRows {
    /// The number of rows (vertices).
    pub(crate) fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Each row applied to `src` (the level's values) into `dst`; in parallel over blocks of
    /// rows (the same result on any number of threads).
    ///
    /// # Panics
    /// If `dst` does not have one value per row.
    pub(crate) fn apply<const D: usize>(&self, src: &[[f64; D]], dst: &mut [[f64; D]]) {
        assert_eq!(dst.len(), self.len(), "one value per row");
        dst.par_chunks_mut(ROWS_BLOCK)
            .enumerate()
            .for_each(|(b, out)| {
                for (i, o) in out.iter_mut().enumerate() {
                    let v = b * ROWS_BLOCK + i;
                    let r = self.offsets[v] as usize..self.offsets[v + 1] as usize;
                    let (cols, weights) = (&self.cols[r.clone()], &self.weights[r]);
                    *o = weighted(
                        weights
                            .iter()
                            .zip(cols)
                            .map(|(&w, &c)| (w, &src[c as usize])),
                    );
                }
            });
    }
}

impl Nurss {
    /// The limit point of every vertex of the current level as weights on the level's
    /// points (homogeneous points for a rational mesh): corners and creases as
    /// [`limit_points`](Self::limit_points) computes them, and a smooth vertex's fan weights
    /// ([`Fan::limit_weights`]) composed with the rows of the step that made the fan. Agrees
    /// with [`limit_points`](Self::limit_points) within [`LIMIT_TOLERANCE`]` / (1 − λ)` of
    /// each fan's size.
    pub(crate) fn limit_rows(&self) -> LimitRows {
        let t = &self.topology;
        let nv = t.num_vertices();
        let child = self.has_fans().then(|| {
            let masks = NurssMasks::new(t, &self.knots);
            let c = refine_topology(t, &self.options, true);
            let ac = across_values(&c, &effective_knots(&child_knots(t, &self.knots)));
            (masks, c, ac)
        });
        let own = self.own_intervals();
        // Vertex `v`'s terms, a column possibly several times.
        let terms = |v: usize, out: &mut Vec<(u32, f64)>| {
            let keep = (v as u32, 1.0);
            if t.vertex_edges(v).is_empty() {
                return out.push(keep);
            }
            match t.vert_tags[v].get().rule {
                Rule::Corner => out.push(keep),
                Rule::Crease => match crease_weights(t, &own, v) {
                    Some(w) => out.extend(w.iter().map(|&(q, x)| (q as u32, x))),
                    None => out.push(keep),
                },
                Rule::Smooth | Rule::Dart => {
                    let fan = child
                        .as_ref()
                        .and_then(|(m, c, ac)| Some((m, Fan::gather(c, ac, v, |_| [0.0; 4])?)));
                    match fan {
                        Some((masks, fan)) => {
                            for (&id, w) in fan.ids.iter().zip(fan.limit_weights()) {
                                if w != 0.0 {
                                    masks.row(t, id as usize, |col, x| out.push((col, w * x)));
                                }
                            }
                        }
                        None => out.push(keep),
                    }
                }
            }
        };
        let blocks: Vec<LimitRows> = (0..nv.div_ceil(ROWS_BLOCK))
            .into_par_iter()
            .map(|b| {
                let mut rows = LimitRows::default();
                rows.offsets.push(0);
                let mut row = Vec::new();
                for v in b * ROWS_BLOCK..((b + 1) * ROWS_BLOCK).min(nv) {
                    row.clear();
                    terms(v, &mut row);
                    row.sort_unstable_by_key(|&(col, _)| col);
                    let start = rows.cols.len();
                    for &(col, w) in &row {
                        let last = rows.cols.len().wrapping_sub(1);
                        if rows.cols.len() > start && rows.cols[last] == col {
                            rows.weights[last] += w;
                        } else {
                            rows.cols.push(col);
                            rows.weights.push(w);
                        }
                    }
                    rows.offsets.push(rows.cols.len() as u32);
                }
                rows
            })
            .collect();
        let mut rows = LimitRows::default();
        rows.offsets.push(0);
        for b in blocks {
            let base = rows.cols.len() as u32;
            rows.offsets.extend(b.offsets[1..].iter().map(|o| base + o));
            rows.cols.extend(b.cols);
            rows.weights.extend(b.weights);
        }
        rows
    }
}

/// The interval of the sharp edge that continues sharp edge `e` beyond its end `q`, when
/// `q` is a crease vertex (the curve's next span); else `e`'s own: `own` holds every
/// edge's interval as the rules read it.
fn interval_beyond(t: &Topology, own: &[f64], q: usize, e: usize) -> f64 {
    if t.vert_tags[q].get().rule != Rule::Crease {
        return own[e];
    }
    t.vertex_edges(q)
        .iter()
        .map(|&x| x as usize)
        .find(|&x| x != e && t.edge_sharpness[x] > 0.0)
        .map_or(own[e], |x| own[x])
}

/// The weights of a crease vertex's limit point on itself and the far ends of its two sharp
/// edges (the closed form of the module documentation); `None` unless the vertex has exactly
/// two sharp edges.
fn crease_weights(t: &Topology, own: &[f64], v: usize) -> Option<[(usize, f64); 3]> {
    let sharp: Vec<usize> = t
        .vertex_edges(v)
        .iter()
        .map(|&e| e as usize)
        .filter(|&e| t.edge_sharpness[e] > 0.0)
        .collect();
    let [e1, e2] = sharp[..] else {
        return None;
    };
    let other = |e: usize| {
        let [x, y] = t.edge_verts[e];
        if x as usize == v {
            y as usize
        } else {
            x as usize
        }
    };
    let (q1, q2) = (other(e1), other(e2));
    let (a, b) = (own[e1], own[e2]);
    let (a2, b2) = (
        interval_beyond(t, own, q1, e1),
        interval_beyond(t, own, q2, e2),
    );
    if a + b <= 0.0 {
        return Some([(v, 1.0), (q1, 0.0), (q2, 0.0)]);
    }
    let l = a2 + a + b;
    let r = a + b + b2;
    let (wl, wr) = (b / (a + b), a / (a + b));
    // Q1 = [b P_{i−1} + (a'+a) P_i] / l, Q2 = [(b+b') P_i + a P_{i+1}] / r (P_i where the
    // sum vanishes), C = wl Q1 + wr Q2.
    let (q1_far, q1_v) = if l > 0.0 {
        (b / l, (a2 + a) / l)
    } else {
        (0.0, 1.0)
    };
    let (q2_v, q2_far) = if r > 0.0 {
        ((b + b2) / r, a / r)
    } else {
        (1.0, 0.0)
    };
    Some([
        (q1, wl * q1_far),
        (v, wl * q1_v + wr * q2_v),
        (q2, wr * q2_far),
    ])
}

/// The quad fan around a vertex after at least one step: centre `v`, edge neighbours `q_i`,
/// diagonal points `r_i` (face `i` is `v, q_i, r_i, q_{i+1}`), intervals and `d±` values.
#[derive(Clone)]
struct Fan<const D: usize = 4> {
    /// The level's vertices of the fan's points, in the order of [`Fan::points`].
    ids: Vec<u32>,
    v: [f64; D],
    q: Vec<[f64; D]>,
    r: Vec<[f64; D]>,
    /// Interval of edge `v q_i`.
    h: Vec<f64>,
    /// Interval of edge `q_i r_i` (in face `i`).
    ga: Vec<f64>,
    /// Interval of edge `r_i q_{i+1}`.
    gb: Vec<f64>,
    /// Whether edge `v q_i` is sharp (a dart's crease edge).
    sharp: Vec<bool>,
    /// Curve interval beyond `q_i` along a sharp edge `v q_i`.
    beyond: Vec<f64>,
    /// `d±` at `v` relative to edge `i`, at `q_i` relative to edge `v q_i`.
    av: Vec<f64>,
    aq: Vec<f64>,
    /// Per face `i`, `d±` at its corners `[v, q_i, r_i, q_{i+1}]` relative to the corner's
    /// leaving and entering edge.
    slots: Vec<[[f64; 2]; 4]>,
    /// Whether the last [`Fan::step`] left the intervals `h`, `ga`, `gb` (as normalized)
    /// exactly as it found them: every further step is then the same matrix (see the
    /// module documentation, "Settled fans").
    settled: bool,
    /// Buffers reused by every step.
    scratch: FanScratch<D>,
}

/// Work buffers of [`Fan::step`].
#[derive(Clone, Default)]
struct FanScratch<const D: usize> {
    /// The intervals `h` before the step.
    h: Vec<f64>,
    w: Vec<f64>,
    wm: Vec<f64>,
    wf: Vec<f64>,
    q: Vec<[f64; D]>,
    r: Vec<[f64; D]>,
    mids: Vec<[f64; D]>,
    ring: Vec<RingIntervals>,
    ga: Vec<f64>,
    gb: Vec<f64>,
}

impl<const D: usize> Fan<D> {
    /// The fan of `v` in a level refined at least once (every face around `v` a quad).
    /// `point(i)` gives the point of the level's vertex `i`.
    fn gather(
        t: &Topology,
        ac: &AcrossValues,
        v: usize,
        point: impl Fn(usize) -> [f64; D],
    ) -> Option<Self> {
        let tag = t.vert_tags[v].get();
        let edges = t.vertex_edges(v);
        let faces = t.vertex_faces(v);
        let flocal = t.vertex_face_locals(v);
        let n = edges.len();
        if tag.boundary || tag.non_manifold || faces.len() != n || n < 2 {
            return None;
        }
        let mut fan = Fan {
            v: point(v),
            ids: vec![v as u32],
            q: Vec::with_capacity(n),
            r: Vec::with_capacity(n),
            h: Vec::with_capacity(n),
            ga: Vec::with_capacity(n),
            gb: Vec::with_capacity(n),
            sharp: Vec::with_capacity(n),
            beyond: Vec::with_capacity(n),
            av: Vec::with_capacity(n),
            aq: Vec::with_capacity(n),
            slots: Vec::with_capacity(n),
            settled: false,
            scratch: FanScratch::default(),
        };
        let mut ring_ids = Vec::with_capacity(n);
        for i in 0..n {
            let e = edges[i] as usize;
            let f = faces[i] as usize;
            let fv = t.face_vertices(f);
            if fv.len() != 4 {
                return None;
            }
            let o = t.face_offsets[f] as usize;
            let l = flocal[i] as usize;
            let at = |j: usize| (l + j) % 4;
            fan.q.push(point(fv[at(1)] as usize));
            fan.r.push(point(fv[at(2)] as usize));
            fan.ids.push(fv[at(1)]);
            ring_ids.push(fv[at(2)]);
            fan.h.push(ac.own[e]);
            fan.ga.push(ac.own[t.face_edges[o + at(1)] as usize]);
            fan.gb.push(ac.own[t.face_edges[o + at(2)] as usize]);
            let [a, _] = t.edge_verts[e];
            let qend = usize::from(a as usize == v);
            fan.av.push(ac.edge[e][1 - qend]);
            fan.aq.push(ac.edge[e][qend]);
            let sharp = t.edge_sharpness[e] > 0.0;
            fan.sharp.push(sharp);
            let q = fv[at(1)] as usize;
            fan.beyond.push(if sharp {
                interval_beyond(t, &ac.own, q, e)
            } else {
                fan.h[i]
            });
            fan.slots.push([0, 1, 2, 3].map(|j| ac.slot[o + at(j)]));
        }
        fan.ids.extend(ring_ids);
        Some(fan)
    }

    /// One NURSS step of the fan (buffers reused: no allocation after the first step):
    /// its points, then its intervals; `settled` when the intervals no longer change.
    fn step(&mut self) {
        self.scratch.h.clear();
        self.scratch.h.extend_from_slice(&self.h);
        self.step_points();
        self.step_intervals();
        self.normalise_intervals();
        // The old `ga`, `gb` are in the scratch buffers since the swap.
        let sc = &self.scratch;
        self.settled = self.h == sc.h && self.ga == sc.ga && self.gb == sc.gb;
    }

    /// The fan's points one step on: its face points, midpoints and edge points, and the
    /// vertex point (a dart follows the smooth rule), from the current intervals.
    fn step_points(&mut self) {
        let n = self.h.len();
        let sc = &mut self.scratch;
        // Face points.
        sc.r.clear();
        for i in 0..n {
            let j = (i + 1) % n;
            let d = [self.h[i], self.ga[i], self.gb[i], self.h[j]];
            let s = &self.slots[i];
            let start = [s[0][0], s[1][0], s[2][0], s[3][0]];
            let end = [s[1][1], s[2][1], s[3][1], s[0][1]];
            face_weights(&d, &start, &end, &mut sc.w);
            let c = [&self.v, &self.q[i], &self.r[i], &self.q[j]];
            sc.r.push(combine(&sc.w, &c));
        }
        // Midpoints and edge points.
        sc.mids.clear();
        sc.q.clear();
        for i in 0..n {
            let p = (i + n - 1) % n;
            let m = midpoint_weights(self.h[i], self.av[i], self.aq[i]);
            let mp = combine(&m, &[&self.v, &self.q[i]]);
            sc.mids.push(mp);
            let e = if self.sharp[i] {
                let c = curve_edge_weights(self.h[i], self.h[i], self.beyond[i]);
                combine(&c, &[&self.v, &self.q[i]])
            } else {
                let left = [self.gb[p], self.h[p]];
                let right = [self.h[(i + 1) % n], self.ga[i]];
                let [a, b, c] = edge_weights(left, right);
                combine(&[a, b, c], &[&mp, &sc.r[p], &sc.r[i]])
            };
            sc.q.push(e);
        }
        // Vertex point (a dart follows the smooth rule).
        sc.ring.clear();
        sc.ring.extend((0..n).map(|i| RingIntervals {
            minus2: self.h[(i + n - 2) % n],
            minus1: self.h[(i + n - 1) % n],
            plus1: self.h[(i + 1) % n],
            plus2: self.h[(i + 2) % n],
        }));
        let wv = vertex_weights(&sc.ring, &mut sc.wm, &mut sc.wf);
        let mut v2 = [0.0; D];
        for k in 0..D {
            v2[k] = wv * self.v[k];
            for i in 0..n {
                v2[k] += sc.wm[i] * sc.mids[i][k] + sc.wf[i] * sc.r[i][k];
            }
        }
        self.v = v2;
        std::mem::swap(&mut self.q, &mut sc.q);
        std::mem::swap(&mut self.r, &mut sc.r);
    }

    /// The fan's intervals and `d±` one step on (see the module documentation): the
    /// face-interior edges first (they read the old `h`), then the halves. The old `ga`,
    /// `gb` go to the scratch buffers.
    fn step_intervals(&mut self) {
        let n = self.h.len();
        let sc = &mut self.scratch;
        sc.ga.clear();
        sc.ga
            .extend((0..n).map(|i| 0.25 * (self.h[(i + 1) % n] + self.ga[i])));
        sc.gb.clear();
        sc.gb
            .extend((0..n).map(|i| 0.25 * (self.gb[i] + self.h[i])));
        std::mem::swap(&mut self.ga, &mut sc.ga);
        std::mem::swap(&mut self.gb, &mut sc.gb);
        for i in 0..n {
            self.aq[i] = self.h[i];
            self.h[i] *= 0.5;
        }
        for i in 0..n {
            self.av[i] = self.h[(i + 2) % n] + self.h[(i + n - 2) % n];
            self.beyond[i] = self.h[i];
        }
        for i in 0..n {
            let j = (i + 1) % n;
            let p = (i + n - 1) % n;
            self.slots[i] = [
                [self.av[i], self.av[j]],
                [2.0 * self.gb[p], self.aq[i]],
                [2.0 * self.gb[i], 2.0 * self.ga[i]],
                [self.aq[j], 2.0 * self.ga[j]],
            ];
        }
    }

    /// Scales the intervals to a largest of 1: the rules are homogeneous of degree 0 in
    /// them, and near 1 hundreds of halvings cannot underflow.
    fn normalise_intervals(&mut self) {
        let max = self
            .h
            .iter()
            .chain(&self.ga)
            .chain(&self.gb)
            .fold(0.0f64, |m, &d| m.max(d));
        if max > 0.0 && max.is_finite() {
            let s = 1.0 / max;
            for x in self
                .h
                .iter_mut()
                .chain(&mut self.ga)
                .chain(&mut self.gb)
                .chain(&mut self.beyond)
                .chain(&mut self.av)
                .chain(&mut self.aq)
            {
                *x *= s;
            }
            for face in &mut self.slots {
                for c in face.iter_mut() {
                    c[0] *= s;
                    c[1] *= s;
                }
            }
        }
    }

    /// Size of the fan: its largest distance from the centre (in homogeneous coordinates).
    fn size(&self) -> f64 {
        self.q
            .iter()
            .chain(&self.r)
            .map(|p| dist(p, &self.v))
            .fold(0.0, f64::max)
    }

    /// The fan's points in the order of [`Fan::step_matrix`]: `v`, the `q_i`, the `r_i`.
    fn points(&self) -> impl Iterator<Item = &[f64; D]> {
        std::iter::once(&self.v).chain(&self.q).chain(&self.r)
    }

    /// A copy of the fan (its intervals and state) with the points `point(j)`, `j` in the
    /// order of [`Fan::points`].
    fn with_points<const E: usize>(&self, point: impl Fn(usize) -> [f64; E]) -> Fan<E> {
        let n = self.h.len();
        Fan {
            ids: self.ids.clone(),
            v: point(0),
            q: (0..n).map(|i| point(1 + i)).collect(),
            r: (0..n).map(|i| point(1 + n + i)).collect(),
            h: self.h.clone(),
            ga: self.ga.clone(),
            gb: self.gb.clone(),
            sharp: self.sharp.clone(),
            beyond: self.beyond.clone(),
            av: self.av.clone(),
            aq: self.aq.clone(),
            slots: self.slots.clone(),
            settled: self.settled,
            scratch: FanScratch::default(),
        }
    }

    /// A copy of the fan whose points are the unit vectors `W block … W block + W − 1`, one
    /// per coordinate (zero where the index is beyond the fan's points).
    fn unit_copy<const W: usize>(&self, block: usize) -> Fan<W> {
        self.with_points(|j| {
            let mut p = [0.0; W];
            if j / W == block {
                p[j % W] = 1.0;
            }
            p
        })
    }

    /// The matrix `S` of one step of the fan in its current state, `(1 + 2n)²`, acting on
    /// the points `v, q_0 … q_{n−1}, r_0 … r_{n−1}`: computed by stepping copies of the
    /// fan whose points are unit vectors, [`UNIT_BLOCK`] columns per copy (one per
    /// coordinate).
    fn step_matrix(&self) -> Square {
        let m = self.ids.len();
        let mut s = Square::zeros(m);
        for block in 0..m.div_ceil(UNIT_BLOCK) {
            let mut unit = self.unit_copy::<UNIT_BLOCK>(block);
            unit.step();
            for (row, p) in unit.points().enumerate() {
                for (k, &x) in p.iter().enumerate() {
                    let col = UNIT_BLOCK * block + k;
                    if col < m {
                        s.a[row * m + col] = x;
                    }
                }
            }
        }
        s
    }

    /// The centre's row of `S^∞`, the limit of the centre under the stationary step `S` =
    /// [`Fan::step_matrix`] being that row times the fan's points: `S` squared until the row
    /// stops changing (at most [`MAX_SQUARINGS`] times, `2^40` steps); `None` if it does not
    /// converge.
    ///
    /// Each squaring's rows are rescaled to sum to 1 (they do exactly; rounding would
    /// otherwise grow the eigenvalue 1 with the power). Not the left eigenvector of eigenvalue
    /// 1: next to zero intervals that eigenvalue can be double.
    fn squared_row(&self) -> Option<Vec<f64>> {
        let mut power = self.step_matrix();
        let mut row = power.row(0).to_vec();
        for _ in 0..MAX_SQUARINGS {
            power = power.squared();
            for r in power.a.chunks_exact_mut(power.n) {
                let sum: f64 = r.iter().sum();
                r.iter_mut().for_each(|x| *x /= sum);
            }
            let next = power.row(0);
            let change = (next.iter().zip(&row))
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            row.copy_from_slice(next);
            if !change.is_finite() {
                return None;
            }
            if change <= SQUARING_TOLERANCE {
                return Some(row);
            }
        }
        None
    }
}

impl Fan {
    /// The limit of the centre under repeated refinement of the fan: iterated while it
    /// converges fast, from the powers of its step matrix ([`Fan::squared_row`]) once it
    /// has settled or if it is slow (see the module documentation).
    fn limit(mut self) -> [f64; 4] {
        let scale = self.size() + self.v.iter().map(|c| c.abs()).fold(0.0, f64::max);
        for _ in 0..ITERATED_STEPS {
            let before = self.v;
            self.step();
            let moved = dist(&before, &self.v);
            if moved <= LIMIT_TOLERANCE * scale || !moved.is_finite() {
                return self.v;
            }
            if self.settled {
                break;
            }
        }
        // Powers that do not converge: no limit exists; the last point iterated stands in.
        match self.squared_row() {
            Some(row) => weighted(row.iter().copied().zip(self.points())),
            None => self.v,
        }
    }

    /// The weights of [`Fan::limit`] on the fan's points (in the order of [`Fan::points`]),
    /// whatever they are: the same steps on copies of the fan whose points are unit vectors,
    /// [`UNIT_BLOCK`] per copy (one per coordinate: the step's weights are computed once
    /// for all of them), iterated until no weight moves by more than [`LIMIT_TOLERANCE`] in
    /// a step, for at most the same 64 steps; a slow or settled fan's weights are the
    /// centre's row of `S^∞` times the product of the steps so far. [`Fan::limit`] on data,
    /// which stops on the data instead, agrees within `LIMIT_TOLERANCE / (1 − λ)` of the
    /// fan's size.
    fn limit_weights(&self) -> Vec<f64> {
        const W: usize = UNIT_BLOCK;
        let m = self.ids.len();
        let mut units: Vec<Fan<W>> = (0..m.div_ceil(W)).map(|b| self.unit_copy(b)).collect();
        // The weights on the fan's points of the copies' centres.
        let weights =
            |units: &[Fan<W>]| -> Vec<f64> { (0..m).map(|j| units[j / W].v[j % W]).collect() };
        for _ in 0..ITERATED_STEPS {
            let mut moved = 0.0f64;
            for u in &mut units {
                let before = u.v;
                u.step();
                for k in 0..W {
                    moved = moved.max((u.v[k] - before[k]).abs());
                }
            }
            if moved <= LIMIT_TOLERANCE || !moved.is_finite() {
                return weights(&units);
            }
            if units[0].settled {
                break;
            }
        }
        let Some(row) = units[0].squared_row() else {
            return weights(&units);
        };
        // (row · P)_j, where P, the product of the steps so far, maps unit vector j to
        // copy j / W's points in coordinate j % W.
        (0..m)
            .map(|j| {
                let u = &units[j / W];
                row.iter().zip(u.points()).map(|(w, p)| w * p[j % W]).sum()
            })
            .collect()
    }
}

/// A dense square matrix, row-major: the step matrix of a fan, `(1 + 2n)²`, and its powers.
struct Square {
    /// Size.
    n: usize,
    /// Entries, row `i` at `a[i n .. (i + 1) n]`.
    a: Vec<f64>,
}

impl Square {
    fn zeros(n: usize) -> Self {
        Self {
            n,
            a: vec![0.0; n * n],
        }
    }

    fn row(&self, i: usize) -> &[f64] {
        &self.a[i * self.n..(i + 1) * self.n]
    }

    /// `self²`, row by row (each row of the product is a combination of the rows of
    /// `self`, summed in order of the columns).
    fn squared(&self) -> Self {
        let n = self.n;
        let mut out = Self::zeros(n);
        for (i, o) in out.a.chunks_exact_mut(n).enumerate() {
            for (k, &x) in self.row(i).iter().enumerate() {
                if x != 0.0 {
                    o.iter_mut()
                        .zip(self.row(k))
                        .for_each(|(o, &y)| *o += x * y);
                }
            }
        }
        out
    }
}

fn combine<const N: usize, const D: usize>(w: &[f64], p: &[&[f64; D]; N]) -> [f64; D] {
    let mut c = [0.0; D];
    for (wi, pi) in w.iter().zip(p) {
        for k in 0..D {
            c[k] += wi * pi[k];
        }
    }
    c
}

/// `Σ w_j p_j`.
fn weighted<'a, const D: usize>(terms: impl IntoIterator<Item = (f64, &'a [f64; D])>) -> [f64; D] {
    let mut c = [0.0; D];
    for (w, p) in terms {
        for k in 0..D {
            c[k] += w * p[k];
        }
    }
    c
}

fn dist<const D: usize>(a: &[f64; D], b: &[f64; D]) -> f64 {
    (0..D).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::obj::read_obj;
    use crate::mesh::{EdgeInterval, Options};

    /// The fan of the pole of `catmark_pole{valence}` at level 1, with `interval` on one of
    /// the pole's edges and 1 elsewhere.
    fn pole_fan(valence: usize, interval: f64) -> Fan {
        let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join(format!("tests/shapes/osd/catmark_pole{valence}.obj"));
        let mut mesh = read_obj(&path).unwrap().mesh;
        mesh.tags = Default::default();
        let (t, _) = Topology::from_mesh(&mesh, &Options::default()).unwrap();
        let pole = (0..t.num_vertices())
            .max_by_key(|&v| t.vertex_edges(v).len())
            .unwrap();
        assert_eq!(t.vertex_edges(pole).len(), valence);
        let [v0, v1] = t.edge_vertices(t.vertex_edges(pole)[0] as usize);
        mesh.knots.intervals.push(EdgeInterval { v0, v1, interval });
        let mut s = Nurss::new(&mesh, &Options::default()).unwrap();
        s.step();
        let t = &s.topology;
        let ac = across_values(t, &effective_knots(&s.knots));
        // A vertex's child keeps its index.
        Fan::gather(t, &ac, pole, |i| s.points[i]).unwrap()
    }

    #[test]
    fn square_matrix_squares() {
        let m = Square {
            n: 2,
            a: vec![1.0, 2.0, 3.0, 4.0],
        };
        assert_eq!(m.squared().a, vec![7.0, 10.0, 15.0, 22.0]);
    }

    /// The step matrix maps the fan's points as a step does.
    #[test]
    fn step_matrix_is_one_step() {
        let mut fan = pole_fan(8, 0.0);
        for _ in 0..3 {
            let s = fan.step_matrix();
            let before: Vec<[f64; 4]> = fan.points().copied().collect();
            fan.step();
            for (row, p) in fan.points().enumerate() {
                for k in 0..4 {
                    let x: f64 = (0..s.n).map(|j| s.row(row)[j] * before[j][k]).sum();
                    assert!((x - p[k]).abs() < 1e-15, "row {row}: {x} vs {}", p[k]);
                }
            }
        }
    }

    /// Next to a small or zero interval, a pole's fan converges slowly (subdominant
    /// eigenvalue 0.93 at valence 8 with a zero interval, 0.78 at valence 64 with an interval
    /// of 0.3, 0.9989 at valence 64 with a zero one): its limit, taken
    /// from the powers of its step matrix after 64 steps, is where thousands of steps take it.
    /// The 400 iterated steps used before stopped 0.1 short of it at valence 64 (in a model
    /// of size 2).
    #[test]
    fn slowly_converging_fans_reach_their_limit() {
        for (valence, interval, steps) in [(8, 0.0, 2_000), (64, 0.3, 1_000), (64, 0.0, 60_000)] {
            let fan = pole_fan(valence, interval);
            let mut iterated = fan.clone();
            for _ in 0..steps {
                iterated.step();
            }
            let limit = fan.limit();
            let gap = dist(&limit, &iterated.v);
            assert!(
                gap < 1e-12,
                "valence {valence}, interval {interval}: {gap:e}"
            );
        }
        // What 400 steps give at valence 64 with a zero interval.
        let mut fan = pole_fan(64, 0.0);
        let limit = fan.clone().limit();
        for _ in 0..400 {
            fan.step();
        }
        assert!(dist(&limit, &fan.v) > 0.05);
    }

    /// With equal intervals a fan settles after its first step (the second leaves its
    /// intervals as they were), and its limit, from the powers of its step matrix, is
    /// Catmull-Clark's limit position `(n² v + 4 Σ q_i + Σ r_i) / (n (n + 5))`, to which NURSS
    /// reduces there; a fan next to a zero interval does not settle.
    #[test]
    fn fans_with_equal_intervals_settle_on_catmull_clarks_limit() {
        for valence in [8, 64] {
            let fan = pole_fan(valence, 1.0);
            let mut stepped = fan.clone();
            stepped.step();
            stepped.step();
            assert!(stepped.settled, "valence {valence}");
            let n = valence as f64;
            let cc: [f64; 4] = std::array::from_fn(|k| {
                let q: f64 = fan.q.iter().map(|p| p[k]).sum();
                let r: f64 = fan.r.iter().map(|p| p[k]).sum();
                (n * n * fan.v[k] + 4.0 * q + r) / (n * (n + 5.0))
            });
            let gap = dist(&fan.clone().limit(), &cc);
            assert!(gap < 1e-14 * fan.size(), "valence {valence}: {gap:e}");
        }
        let mut slow = pole_fan(8, 0.0);
        for _ in 0..8 {
            slow.step();
            assert!(!slow.settled);
        }
    }

    /// The limit rows applied to a level's points are its limit points: on the regression
    /// shapes with random intervals (a tenth of them zero) at levels 0 and 1, rational on
    /// every other shape.
    #[test]
    fn limit_rows_give_the_limit_points() {
        let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/shapes/osd");
        let mut names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "obj"))
            .collect();
        names.sort();
        let mut seed = 7u64;
        let mut rand = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut worst = 0.0f64;
        let mut shapes = 0;
        for (i, path) in names.iter().enumerate() {
            // The malformed shapes of the corpus are for other tests.
            let Ok(obj) = read_obj(path) else { continue };
            let mut mesh = obj.mesh;
            mesh.tags.creases.retain(|c| c.sharpness >= 10.0);
            mesh.tags.corners.retain(|c| c.sharpness >= 10.0);
            let faces: Vec<Vec<u32>> = mesh.faces().map(|f| f.to_vec()).collect();
            for f in &faces {
                for j in 0..f.len() {
                    let interval = if rand() < 0.1 {
                        0.0
                    } else {
                        0.5 + 2.5 * rand()
                    };
                    mesh.knots.intervals.push(EdgeInterval {
                        v0: f[j],
                        v1: f[(j + 1) % f.len()],
                        interval,
                    });
                }
            }
            if i % 2 == 1 {
                mesh.knots.weights = (0..mesh.num_vertices() as u32)
                    .map(|vertex| crate::mesh::VertexWeight {
                        vertex,
                        weight: 0.5 + 2.0 * rand(),
                    })
                    .collect();
            }
            let Ok(mut s) = Nurss::new(&mesh, &Options::default()) else {
                continue;
            };
            shapes += 1;
            let scale = mesh
                .positions()
                .iter()
                .flatten()
                .fold(1.0f64, |m, c| m.max(c.abs()));
            for level in 0..2 {
                if level > 0 {
                    s.step();
                }
                let rows = s.limit_rows();
                let mut hom = vec![[0.0; 4]; rows.len()];
                rows.apply(&s.points, &mut hom);
                for (v, (h, p)) in hom.iter().zip(s.limit_points()).enumerate() {
                    let q = project(h, s.rational);
                    let gap = (0..3).map(|k| (q[k] - p[k]).abs()).fold(0.0, f64::max);
                    worst = worst.max(gap / scale);
                    assert!(
                        gap < 1e-12 * scale,
                        "{path:?} level {level} vertex {v}: {q:?} vs {p:?}"
                    );
                }
            }
        }
        assert!(shapes >= 80, "{shapes} shapes");
        eprintln!("worst {worst:e}");
    }
}
