//! Weights of non-uniform Catmull-Clark subdivision (NURSS): every edge carries a *knot
//! interval* `d ≥ 0`; the topology is Catmull-Clark's, only the weights depend on the
//! intervals.
//!
//! Source: T. Sederberg, J. Zheng, D. Sewell & M. Sabin, "Non-uniform recursive subdivision
//! surfaces", SIGGRAPH 1998, §3–4 (curve rules eq. 1–2, surface rules for face, edge and
//! vertex points); the degenerate cases (all-zero weights) are those of Wang, Zheng et al.'s
//! blending paper (plain average for face and edge "midpoints", `V' = V` for the vertex rule,
//! its eq. 1 and eq. 3).
//!
//! This module computes weights only; the caller reads the intervals around each element
//! (see `refine::nurss` for the walk, including *auxiliary* per-face-side
//! intervals). Notation: for a vertex `X` and one of its edges, `d±_X` is the sum of the
//! intervals of the edges met two steps counter-clockwise and two steps clockwise around `X`
//! from that edge (at a regular valence-4 vertex, twice the interval of the edge that
//! continues straight through `X`).
//!
//! Every rule reduces to Catmull-Clark when all intervals are equal and, on a regular grid,
//! to exact midpoint knot insertion into the tensor-product non-uniform cubic B-spline
//! (tested below and in `tests/integration/nurss.rs`). All weight sets sum to 1, so the rules are
//! affine invariant, and they are homogeneous of degree 0 in the intervals (scaling every interval
//! by a constant changes nothing).

/// Weights of the cubic B-spline *edge point* (midpoint knot insertion, Sederberg et al.
/// eq. 1): for the edge `P_i P_{i+1}` with interval `d` and neighbouring intervals `d_prev`
/// (edge `P_{i−1} P_i`) and `d_next` (edge `P_{i+1} P_{i+2}`),
///
/// `E = [(d + 2 d_next) P_i + (2 d_prev + d) P_{i+1}] / (2 (d_prev + d + d_next))`.
///
/// Returns `[w_i, w_{i+1}]`. If `d_prev + d + d_next = 0` the point is the midpoint.
#[inline]
pub(crate) fn curve_edge_weights(d_prev: f64, d: f64, d_next: f64) -> [f64; 2] {
    let s = d_prev + d + d_next;
    if s <= 0.0 {
        return [0.5, 0.5];
    }
    let a = (d + 2.0 * d_next) / (2.0 * s);
    [a, 1.0 - a]
}

/// Weights of the cubic B-spline *vertex point* (Sederberg et al. eq. 2):
///
/// `V_i = ½ P_i + ½ (d_i E_{i−1} + d_{i−1} E_i) / (d_{i−1} + d_i)`,
///
/// with `E_{i−1}`, `E_i` the [edge points](curve_edge_weights) of the two edges at `P_i`;
/// `d = [d_{i−2}, d_{i−1}, d_i, d_{i+1}]` are the intervals of the edges `P_{i−2}P_{i−1}`,
/// `P_{i−1}P_i`, `P_iP_{i+1}`, `P_{i+1}P_{i+2}`. Returns the weights of
/// `[P_{i−1}, P_i, P_{i+1}]`. If `d_{i−1} + d_i = 0` (a triple knot) `V_i = P_i`.
#[inline]
pub(crate) fn curve_vertex_weights(d: [f64; 4]) -> [f64; 3] {
    let [dm2, dm1, d0, dp1] = d;
    let s = dm1 + d0;
    if s <= 0.0 {
        return [0.0, 1.0, 0.0];
    }
    let el = curve_edge_weights(dm2, dm1, d0); // E_{i−1} on P_{i−1}, P_i
    let er = curve_edge_weights(dm1, d0, dp1); // E_i on P_i, P_{i+1}
    let (a, b) = (0.5 * d0 / s, 0.5 * dm1 / s);
    let wl = a * el[0];
    let wr = b * er[1];
    [wl, 1.0 - wl - wr, wr]
}

/// Weights of the *face point* of an `n`-gon `P_0 … P_{n−1}` (Sederberg et al. §4):
/// `F = Σ w_i P_i / Σ w_i` with
///
/// `w_i = (d_i + d±_{P_{i+1}}) · (d_{i−1} + d±_{P_{i−1}})`,
///
/// where `d[i]` is the interval of the face's edge `P_i P_{i+1}`, `across_end[i]` is
/// `d±` at its end `P_{i+1}` (relative to that edge) and `across_start[i]` is `d±` at its
/// start `P_i`. On a regular grid `w = (d_0 + 2 d_1)(e_0 + 2 e_1)`, the tensor product of
/// the curve rule. If `Σ w_i = 0` the face point is the centroid (blending paper, eq. 1).
///
/// Writes the normalised weights to `out` (cleared first).
///
/// # Panics
/// If the three slices differ in length.
pub(crate) fn face_weights(
    d: &[f64],
    across_start: &[f64],
    across_end: &[f64],
    out: &mut Vec<f64>,
) {
    let n = d.len();
    assert!(across_start.len() == n && across_end.len() == n);
    out.clear();
    let mut sum = 0.0;
    for i in 0..n {
        let ip = if i == 0 { n - 1 } else { i - 1 };
        let w = (d[i] + across_end[i]) * (d[ip] + across_start[ip]);
        sum += w;
        out.push(w);
    }
    if sum > 0.0 {
        for w in out.iter_mut() {
            *w /= sum;
        }
    } else {
        out.fill(1.0 / n as f64);
    }
}

/// Weights `[w_P, w_Q]` of the *edge midpoint* `M` of an edge `PQ` with interval `d`
/// (Sederberg et al. §4; each end weighted by the intervals around the *other* end):
///
/// `M = [(d + d±_Q) P + (d + d±_P) Q] / (2d + d±_P + d±_Q)`.
///
/// On a regular grid this is the curve edge point along the edge. If the denominator is 0,
/// `M` is the midpoint (blending paper, eq. 1).
#[inline]
pub(crate) fn midpoint_weights(d: f64, across_p: f64, across_q: f64) -> [f64; 2] {
    let s = 2.0 * d + across_p + across_q;
    if s <= 0.0 {
        return [0.5, 0.5];
    }
    let a = (d + across_q) / s;
    [a, 1.0 - a]
}

/// Weights of a smooth *edge point* `E = w_m M + w_l F_l + w_r F_r` of an edge between two
/// faces (Sederberg et al. §4), given the side intervals of each face: `left = [a, b]` are
/// the intervals of the left face's two edges next to this edge (at its two ends), and
/// `right` likewise. Each face's weight is the sum of the *other* face's side intervals over
/// twice the sum of all four:
///
/// `α_l = (r_0 + r_1) / (2 (l_0 + l_1 + r_0 + r_1))`, `α_r = (l_0 + l_1) / (2 (…))`,
/// `w_m = 1 − α_l − α_r = ½`.
///
/// With opposite edges equal this is `E = ½ M + ½ (e_r F_l + e_l F_r) / (e_l + e_r)`, the
/// tensor product of the curve edge rule and the curve vertex rule. If all four intervals
/// are 0 the faces get ¼ each. Returns `[w_m, α_l, α_r]`.
#[inline]
pub(crate) fn edge_weights(left: [f64; 2], right: [f64; 2]) -> [f64; 3] {
    let l = left[0] + left[1];
    let r = right[0] + right[1];
    let s = l + r;
    if s <= 0.0 {
        return [0.5, 0.25, 0.25];
    }
    let al = r / (2.0 * s);
    let ar = l / (2.0 * s);
    [1.0 - al - ar, al, ar]
}

/// The intervals a smooth vertex rule reads for one edge `i` around the vertex: the edges met
/// one and two steps clockwise (`minus1`, `minus2`) and counter-clockwise (`plus1`,
/// `plus2`) from edge `i`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct RingIntervals {
    /// `h_{i−2}`.
    pub minus2: f64,
    /// `h_{i−1}`.
    pub minus1: f64,
    /// `h_{i+1}`.
    pub plus1: f64,
    /// `h_{i+2}`.
    pub plus2: f64,
}

/// Weights of the smooth *vertex point* of a vertex `V` of valence `n` (Sederberg et al.
/// §4; the blending paper's eq. 3 writes the same rule with `c = n(n − 3)`):
///
/// `V' = (n − 3)/n · V + 3 Σ_i (m_i M_i + f_i F_i) / (n Σ_i (m_i + f_i))`,
///
/// `m_i = (h_{i−1} + h_{i+1})(h_{i−2} + h_{i+2}) / 2`, `f_i = h_{i−1} · h_{i+2}`,
///
/// where `M_i` is the [edge midpoint](midpoint_weights) of edge `i` and `F_i` the face point
/// of the face between edges `i` and `i + 1`; `ring[i]` holds the intervals edge `i` reads.
/// If `Σ (m_i + f_i) = 0` the vertex stays put, `V' = V` (blending paper, eq. 3).
///
/// Writes the weights of the `M_i` to `mids` and of the `F_i` to `faces` (both cleared) and
/// returns the weight of `V`.
pub(crate) fn vertex_weights(
    ring: &[RingIntervals],
    mids: &mut Vec<f64>,
    faces: &mut Vec<f64>,
) -> f64 {
    let n = ring.len();
    mids.clear();
    faces.clear();
    let mut sum = 0.0;
    for r in ring {
        let m = 0.5 * (r.minus1 + r.plus1) * (r.minus2 + r.plus2);
        let f = r.minus1 * r.plus2;
        sum += m + f;
        mids.push(m);
        faces.push(f);
    }
    if n == 0 || sum <= 0.0 {
        mids.fill(0.0);
        faces.fill(0.0);
        return 1.0;
    }
    let nf = n as f64;
    let scale = 3.0 / (nf * sum);
    for w in mids.iter_mut().chain(faces.iter_mut()) {
        *w *= scale;
    }
    (nf - 3.0) / nf
}

/// The interval of the new edge from the face point of a face to the edge point of its edge
/// `i`: `(d_{i−1} + d_{i+1}) / 4`, with `d_{i±1}` the intervals of the face's edges on either
/// side of edge `i` (Sederberg et al. Fig. 6). The two halves of an old edge get `d / 2`.
#[inline]
pub(crate) fn face_edge_interval(d_prev: f64, d_next: f64) -> f64 {
    0.25 * (d_prev + d_next)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64) / ((1u64 << 53) as f64)
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-14
    }

    #[test]
    fn weights_sum_to_one_for_random_intervals() {
        let mut s = 7;
        let (mut out, mut mids, mut faces) = (Vec::new(), Vec::new(), Vec::new());
        for n in 3..9 {
            let d: Vec<f64> = (0..n).map(|_| lcg(&mut s) * 3.0).collect();
            let a: Vec<f64> = (0..n).map(|_| lcg(&mut s) * 3.0).collect();
            let b: Vec<f64> = (0..n).map(|_| lcg(&mut s) * 3.0).collect();
            face_weights(&d, &a, &b, &mut out);
            assert!(close(out.iter().sum(), 1.0));
            let ring: Vec<RingIntervals> = (0..n)
                .map(|_| RingIntervals {
                    minus2: lcg(&mut s),
                    minus1: lcg(&mut s),
                    plus1: lcg(&mut s),
                    plus2: lcg(&mut s),
                })
                .collect();
            let v = vertex_weights(&ring, &mut mids, &mut faces);
            let total = v + mids.iter().sum::<f64>() + faces.iter().sum::<f64>();
            assert!(close(total, 1.0), "valence {n}: {total}");
        }
        let c = curve_vertex_weights([0.3, 1.7, 0.2, 2.5]);
        assert!(close(c.iter().sum(), 1.0));
        let e = edge_weights([0.1, 0.7], [2.0, 0.4]);
        assert!(close(e.iter().sum(), 1.0));
        assert!(close(midpoint_weights(0.5, 1.0, 3.0).iter().sum(), 1.0));
    }

    #[test]
    fn equal_intervals_give_catmull_clark_weights() {
        let h = 0.37;
        // Curve rules: midpoint, and (1/8, 3/4, 1/8).
        assert_eq!(curve_edge_weights(h, h, h), [0.5, 0.5]);
        let c = curve_vertex_weights([h; 4]);
        assert!(close(c[0], 0.125) && close(c[1], 0.75) && close(c[2], 0.125));
        // Face point: the centroid.
        let mut out = Vec::new();
        face_weights(&[h; 5], &[2.0 * h; 5], &[2.0 * h; 5], &mut out);
        assert!(out.iter().all(|&w| close(w, 0.2)));
        // Edge point: ¼ of each end and each face point.
        let m = midpoint_weights(h, 2.0 * h, 2.0 * h);
        let e = edge_weights([h, h], [h, h]);
        assert!(close(e[0] * m[0], 0.25) && close(e[0] * m[1], 0.25));
        assert!(close(e[1], 0.25) && close(e[2], 0.25));
        // Vertex point: (n − 2)/n V + 1/n² Σ Q_i + 1/n² Σ F_i for every valence.
        for n in 3..10 {
            let ring = vec![
                RingIntervals {
                    minus2: h,
                    minus1: h,
                    plus1: h,
                    plus2: h
                };
                n
            ];
            let (mut mids, mut faces) = (Vec::new(), Vec::new());
            let v = vertex_weights(&ring, &mut mids, &mut faces);
            let nf = n as f64;
            // M_i = (V + Q_i) / 2 when all intervals are equal.
            let wv = v + 0.5 * mids.iter().sum::<f64>();
            assert!(close(wv, (nf - 2.0) / nf), "valence {n}");
            assert!(mids.iter().all(|&m| close(0.5 * m, 1.0 / (nf * nf))));
            assert!(faces.iter().all(|&f| close(f, 1.0 / (nf * nf))));
        }
    }

    /// On a regular grid with intervals `d0, d1, d2` along `u` (the face spans `d1`) and
    /// `e0, e1, e2` along `v`, the face point is the tensor product of two curve edge points.
    #[test]
    fn regular_face_point_is_tensor_product_of_curve_edge_points() {
        let (d0, d1, d2, e0, e1, e2) = (0.3, 1.1, 0.7, 2.0, 0.4, 0.9);
        // Corners P00, P10, P11, P01 (counter-clockwise); edges 0: u (d1), 1: v (e1),
        // 2: u (d1), 3: v (e1). d± at an end = twice the interval continuing through it.
        let d = [d1, e1, d1, e1];
        let across_start = [2.0 * d0, 2.0 * e0, 2.0 * d2, 2.0 * e2];
        let across_end = [2.0 * d2, 2.0 * e2, 2.0 * d0, 2.0 * e0];
        let mut w = Vec::new();
        face_weights(&d, &across_start, &across_end, &mut w);
        let cu = curve_edge_weights(d0, d1, d2);
        let cv = curve_edge_weights(e0, e1, e2);
        let expected = [cu[0] * cv[0], cu[1] * cv[0], cu[1] * cv[1], cu[0] * cv[1]];
        for k in 0..4 {
            assert!(close(w[k], expected[k]), "{w:?} vs {expected:?}");
        }
    }

    /// The curve vertex rule reproduces exact midpoint knot insertion: blossom check with the
    /// cubic `t³` (control points are its blossom values at consecutive knot triples).
    #[test]
    fn curve_rules_are_midpoint_knot_insertion() {
        // Knots t_0..t_7 from intervals; control point P_i = blossom(t_{i+1}, t_{i+2}, t_{i+3}).
        let iv = [0.5, 1.3, 0.2, 0.9, 2.1, 0.6, 1.0];
        let mut t = vec![0.0];
        for d in iv {
            t.push(t.last().copied().unwrap_or(0.0) + d);
        }
        let blossom = |a: f64, b: f64, c: f64| a * b * c; // of t³
        let p: Vec<f64> = (0..t.len() - 3)
            .map(|i| blossom(t[i + 1], t[i + 2], t[i + 3]))
            .collect();
        // Edge P_i P_{i+1} spans [t_{i+2}, t_{i+3}] (interval iv[i+2]).
        let mid = |k: usize| 0.5 * (t[k] + t[k + 1]);
        for i in 1..p.len() - 2 {
            let w = curve_edge_weights(iv[i + 1], iv[i + 2], iv[i + 3]);
            let e = w[0] * p[i] + w[1] * p[i + 1];
            let exact = blossom(t[i + 2], mid(i + 2), t[i + 3]);
            assert!((e - exact).abs() < 1e-12, "edge {i}: {e} vs {exact}");
        }
        for i in 2..p.len() - 2 {
            let w = curve_vertex_weights([iv[i], iv[i + 1], iv[i + 2], iv[i + 3]]);
            let v = w[0] * p[i - 1] + w[1] * p[i] + w[2] * p[i + 1];
            let exact = blossom(mid(i + 1), t[i + 2], mid(i + 2));
            assert!((v - exact).abs() < 1e-12, "vertex {i}: {v} vs {exact}");
        }
    }

    #[test]
    fn degenerate_weights() {
        let mut out = Vec::new();
        face_weights(&[0.0; 4], &[0.0; 4], &[0.0; 4], &mut out);
        assert_eq!(out, vec![0.25; 4]);
        assert_eq!(midpoint_weights(0.0, 0.0, 0.0), [0.5, 0.5]);
        assert_eq!(edge_weights([0.0; 2], [0.0; 2]), [0.5, 0.25, 0.25]);
        let (mut m, mut f) = (Vec::new(), Vec::new());
        assert_eq!(
            vertex_weights(&[RingIntervals::default(); 5], &mut m, &mut f),
            1.0
        );
        assert!(m.iter().chain(&f).all(|&w| w == 0.0));
        assert_eq!(curve_vertex_weights([1.0, 0.0, 0.0, 1.0]), [0.0, 1.0, 0.0]);
        // A zero interval next to P_i: the edge point on the other side ends at P_i's side.
        let e = curve_edge_weights(1.0, 1.0, 0.0);
        assert!(close(e[0], 1.0 / 4.0));
    }

    #[test]
    fn scaling_intervals_changes_nothing() {
        let k = 3.7;
        let ring = [
            RingIntervals {
                minus2: 0.2,
                minus1: 1.5,
                plus1: 0.3,
                plus2: 0.8,
            },
            RingIntervals {
                minus2: 1.2,
                minus1: 0.5,
                plus1: 0.9,
                plus2: 0.1,
            },
            RingIntervals {
                minus2: 0.6,
                minus1: 0.4,
                plus1: 2.0,
                plus2: 1.0,
            },
        ];
        let scaled: Vec<RingIntervals> = ring
            .iter()
            .map(|r| RingIntervals {
                minus2: k * r.minus2,
                minus1: k * r.minus1,
                plus1: k * r.plus1,
                plus2: k * r.plus2,
            })
            .collect();
        let (mut m1, mut f1, mut m2, mut f2) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let v1 = vertex_weights(&ring, &mut m1, &mut f1);
        let v2 = vertex_weights(&scaled, &mut m2, &mut f2);
        assert!(close(v1, v2));
        for (a, b) in m1.iter().chain(&f1).zip(m2.iter().chain(&f2)) {
            assert!(close(*a, *b));
        }
    }
}
