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

use nalgebra::DMatrix;
use rayon::prelude::*;

use super::{project, Nurss};
use crate::mesh::{Rule, Topology};
use crate::refine::nurss::{across_values, effective_knots, refine_nurss_step, AcrossValues};
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

impl Nurss {
    /// The limit position of every vertex of the current level (one refinement step of the
    /// level is computed on the way, when it has smooth vertices; see the
    /// [module documentation](self) for how: closed form on creases and boundaries, iterated
    /// refinement of the vertex's quad fan for smooth vertices). Rational meshes are handled in
    /// homogeneous coordinates and projected at the end.
    pub fn limit_points(&self) -> Vec<[f64; 3]> {
        let t = &self.topology;
        let nv = t.num_vertices();
        let needs_fan =
            (0..nv).any(|v| matches!(t.vert_tags[v].get().rule, Rule::Smooth | Rule::Dart));
        let child =
            needs_fan.then(|| refine_nurss_step(t, &self.options, &self.knots, &self.points));
        let child_across = child
            .as_ref()
            .map(|(c, _, k)| across_values(c, &effective_knots(k)));
        let eff = effective_knots(&self.knots);
        let own: Vec<f64> = (0..t.num_edges()).map(|e| eff.own(t, e)).collect();
        // Every vertex on its own: in parallel over chunks (the same result on any number
        // of threads).
        let limit = |v: usize| {
            let p = self.points[v];
            if t.vertex_edges(v).is_empty() {
                return p;
            }
            match t.vert_tags[v].get().rule {
                Rule::Corner => p,
                Rule::Crease => crease_limit(t, &own, &self.points, v).unwrap_or(p),
                Rule::Smooth | Rule::Dart => match (&child, &child_across) {
                    (Some((c, pts, _)), Some(ac)) => {
                        Fan::gather(c, ac, pts, v).map_or(p, Fan::limit)
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

/// The two sharp edges of a crease vertex, their far ends and the intervals around them.
fn crease_limit(t: &Topology, own: &[f64], pts: &[[f64; 4]], v: usize) -> Option<[f64; 4]> {
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
    let partner = |q: usize, e: usize| {
        if t.vert_tags[q].get().rule != Rule::Crease {
            return own[e];
        }
        t.vertex_edges(q)
            .iter()
            .map(|&x| x as usize)
            .find(|&x| x != e && t.edge_sharpness[x] > 0.0)
            .map_or(own[e], |x| own[x])
    };
    let (q1, q2) = (other(e1), other(e2));
    let (a, b) = (own[e1], own[e2]);
    let (a2, b2) = (partner(q1, e1), partner(q2, e2));
    if a + b <= 0.0 {
        return Some(pts[v]);
    }
    let l = a2 + a + b;
    let r = a + b + b2;
    let (wl, wr) = (b / (a + b), a / (a + b));
    // Q1 = [b P_{i−1} + (a'+a) P_i] / l, Q2 = [(b+b') P_i + a P_{i+1}] / r.
    let mut c = [0.0; 4];
    for k in 0..4 {
        let q1p = if l > 0.0 {
            (b * pts[q1][k] + (a2 + a) * pts[v][k]) / l
        } else {
            pts[v][k]
        };
        let q2p = if r > 0.0 {
            ((b + b2) * pts[v][k] + a * pts[q2][k]) / r
        } else {
            pts[v][k]
        };
        c[k] = wl * q1p + wr * q2p;
    }
    Some(c)
}

/// The quad fan around a vertex after at least one step: centre `v`, edge neighbours `q_i`,
/// diagonal points `r_i` (face `i` is `v, q_i, r_i, q_{i+1}`), intervals and `d±` values.
#[derive(Clone)]
struct Fan {
    v: [f64; 4],
    q: Vec<[f64; 4]>,
    r: Vec<[f64; 4]>,
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
    /// Buffers reused by every step.
    scratch: FanScratch,
}

/// Work buffers of [`Fan::step`].
#[derive(Clone, Default)]
struct FanScratch {
    w: Vec<f64>,
    wm: Vec<f64>,
    wf: Vec<f64>,
    q: Vec<[f64; 4]>,
    r: Vec<[f64; 4]>,
    mids: Vec<[f64; 4]>,
    ring: Vec<RingIntervals>,
    ga: Vec<f64>,
    gb: Vec<f64>,
}

impl Fan {
    /// The fan of `v` in a level refined at least once (every face around `v` a quad).
    fn gather(t: &Topology, ac: &AcrossValues, pts: &[[f64; 4]], v: usize) -> Option<Fan> {
        let tag = t.vert_tags[v].get();
        let edges = t.vertex_edges(v);
        let faces = t.vertex_faces(v);
        let flocal = t.vertex_face_locals(v);
        let n = edges.len();
        if tag.boundary || tag.non_manifold || faces.len() != n || n < 2 {
            return None;
        }
        let mut fan = Fan {
            v: pts[v],
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
            scratch: FanScratch::default(),
        };
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
            fan.q.push(pts[fv[at(1)] as usize]);
            fan.r.push(pts[fv[at(2)] as usize]);
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
            let beyond = if sharp && t.vert_tags[q].get().rule == Rule::Crease {
                t.vertex_edges(q)
                    .iter()
                    .map(|&x| x as usize)
                    .find(|&x| x != e && t.edge_sharpness[x] > 0.0)
                    .map_or(fan.h[i], |x| ac.own[x])
            } else {
                fan.h[i]
            };
            fan.beyond.push(beyond);
            fan.slots.push([0, 1, 2, 3].map(|j| ac.slot[o + at(j)]));
        }
        Some(fan)
    }

    /// One NURSS step of the fan (buffers reused: no allocation after the first step).
    fn step(&mut self) {
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
        let mut v2 = [0.0; 4];
        for k in 0..4 {
            v2[k] = wv * self.v[k];
            for i in 0..n {
                v2[k] += sc.wm[i] * sc.mids[i][k] + sc.wf[i] * sc.r[i][k];
            }
        }
        self.v = v2;
        std::mem::swap(&mut self.q, &mut sc.q);
        std::mem::swap(&mut self.r, &mut sc.r);
        // New intervals and d± (see the module documentation): the face-interior edges
        // first (they read the old h), then the halves.
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
        // The rules are homogeneous of degree 0 in the intervals: keep them near 1 so that
        // hundreds of halvings cannot underflow.
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

    /// The limit of the centre under repeated refinement of the fan: iterated while it
    /// converges fast, else [`Fan::squared_limit`] (see the module documentation).
    fn limit(mut self) -> [f64; 4] {
        let scale = self.size() + self.v.iter().map(|c| c.abs()).fold(0.0, f64::max);
        for _ in 0..ITERATED_STEPS {
            let before = self.v;
            self.step();
            let moved = dist(&before, &self.v);
            if moved <= LIMIT_TOLERANCE * scale || !moved.is_finite() {
                return self.v;
            }
        }
        // Powers that do not converge: no limit exists; the last point iterated stands in.
        self.squared_limit().unwrap_or(self.v)
    }

    /// The fan's points in the order of [`Fan::step_matrix`]: `v`, the `q_i`, the `r_i`.
    fn points(&self) -> impl Iterator<Item = &[f64; 4]> {
        std::iter::once(&self.v).chain(&self.q).chain(&self.r)
    }

    /// The matrix `S` of one step of the fan in its current state, `(1 + 2n)²`, acting on
    /// the points `v, q_0 … q_{n−1}, r_0 … r_{n−1}`: computed by stepping copies of the
    /// fan whose points are unit vectors, four columns per copy (one per coordinate).
    fn step_matrix(&self) -> DMatrix<f64> {
        let n = self.h.len();
        let m = 1 + 2 * n;
        let mut s = DMatrix::zeros(m, m);
        for block in 0..m.div_ceil(4) {
            let mut unit = self.clone();
            let column = |j: usize| {
                let mut p = [0.0; 4];
                if j / 4 == block {
                    p[j % 4] = 1.0;
                }
                p
            };
            unit.v = column(0);
            for i in 0..n {
                unit.q[i] = column(1 + i);
                unit.r[i] = column(1 + n + i);
            }
            unit.step();
            for (row, p) in unit.points().enumerate() {
                for (k, &x) in p.iter().enumerate() {
                    let col = 4 * block + k;
                    if col < m {
                        s[(row, col)] = x;
                    }
                }
            }
        }
        s
    }

    /// `e_vᵀ S^∞ p`, the limit of the centre under the stationary step `S` =
    /// [`Fan::step_matrix`]: `S` squared until the centre's row stops changing (at most
    /// [`MAX_SQUARINGS`] times, `2^40` steps); `None` if it does not converge.
    ///
    /// Each squaring's rows are rescaled to sum to 1 (they do exactly; rounding would
    /// otherwise grow the eigenvalue 1 with the power). Not the left eigenvector of eigenvalue
    /// 1: next to zero intervals that eigenvalue can be double.
    fn squared_limit(&self) -> Option<[f64; 4]> {
        let mut power = self.step_matrix();
        let mut row = power.row(0).clone_owned();
        for _ in 0..MAX_SQUARINGS {
            power = &power * &power;
            for mut r in power.row_iter_mut() {
                let sum = r.sum();
                r /= sum;
            }
            let next = power.row(0);
            let change = (next - &row).amax();
            row.copy_from(&next);
            if !change.is_finite() {
                return None;
            }
            if change <= SQUARING_TOLERANCE {
                let mut c = [0.0; 4];
                for (w, p) in row.iter().zip(self.points()) {
                    for k in 0..4 {
                        c[k] += w * p[k];
                    }
                }
                return Some(c);
            }
        }
        None
    }
}

fn combine<const N: usize>(w: &[f64], p: &[&[f64; 4]; N]) -> [f64; 4] {
    let mut c = [0.0; 4];
    for (wi, pi) in w.iter().zip(p) {
        for k in 0..4 {
            c[k] += wi * pi[k];
        }
    }
    c
}

fn dist(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    (0..4).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::obj::read_obj;
    use crate::mesh::{EdgeInterval, Options};

    /// The fan of the pole of `catmark_pole{valence}` at level 1, with interval `zero` on one
    /// of the pole's edges and 1 elsewhere.
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
        Fan::gather(t, &ac, &s.points, pole).unwrap()
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
                    let x: f64 = (0..s.ncols()).map(|j| s[(row, j)] * before[j][k]).sum();
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
}
