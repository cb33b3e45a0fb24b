//! Curve helpers shared by the curve-interpolation tests (`interpolate.rs`,
//! `interpolate_host.rs`): distances, de Boor evaluation, knots and control points of a
//! `Curve`, and blossoms (the independent reference for refined control points).
#![allow(dead_code)]

use subsurf::curves::Zone;
use subsurf::nonuniform::Nurss;
use subsurf::nurbs::{Curve, KnotVector};

pub type V3 = [f64; 3];

pub fn dist(a: &V3, b: &V3) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

pub fn knots(c: &Curve) -> &KnotVector {
    match c {
        Curve::BSpline(b) => b.knots(),
        Curve::Nurbs(b) => b.knots(),
    }
}

pub fn control_points(c: &Curve) -> Vec<V3> {
    match c {
        Curve::BSpline(b) => b.points().to_vec(),
        Curve::Nurbs(b) => b.points().to_vec(),
    }
}

pub fn eval(c: &Curve, t: f64) -> V3 {
    match c {
        Curve::BSpline(b) => b.eval(t).unwrap(),
        Curve::Nurbs(b) => b.eval(t).unwrap(),
    }
}

/// Homogeneous control points `(w x, w y, w z, w)`, unwrapped for a periodic curve (one per
/// basis function).
pub fn homogeneous(c: &Curve) -> Vec<[f64; 4]> {
    let (pts, w) = match c {
        Curve::BSpline(b) => (b.points().to_vec(), vec![1.0; b.points().len()]),
        Curve::Nurbs(b) => (b.points().to_vec(), b.weights()),
    };
    let n = pts.len();
    (0..knots(c).num_basis())
        .map(|i| {
            let (p, w) = (pts[i % n], w[i % n]);
            [w * p[0], w * p[1], w * p[2], w]
        })
        .collect()
}

/// The blossom `B(u_1, u_2, u_3)` of the piece of `c` on span `s` (`[t_s, t_{s+1}]`), in
/// homogeneous coordinates, projected.
pub fn blossom(c: &Curve, s: usize, u: [f64; 3]) -> V3 {
    let h = homogeneous(c);
    let t = knots(c).as_slice();
    let mut q: Vec<[f64; 4]> = (0..4).map(|i| h[s - 3 + i]).collect();
    for r in 1..=3 {
        for i in (r..=3).rev() {
            let gi = s - 3 + i;
            let den = t[gi + 4 - r] - t[gi];
            let a = if den > 0.0 {
                (u[r - 1] - t[gi]) / den
            } else {
                0.0
            };
            let prev = q[i - 1];
            for (x, y) in q[i].iter_mut().zip(prev) {
                *x = (1.0 - a) * y + a * *x;
            }
        }
    }
    let p = q[3];
    [p[0] / p[3], p[1] / p[3], p[2] / p[3]]
}

/// The diagonal of the bounding box of the control points: the scale errors are relative to.
pub fn size(c: &Curve) -> f64 {
    let pts = control_points(c);
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &pts {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    dist(&lo, &hi)
}

/// The knot at every point of the middle polygon at the current level.
pub fn middle_knots(s: &Nurss, ids: &[u32], z: &Zone) -> Vec<f64> {
    let t = s.topology();
    let d = s.intervals();
    let n = ids.len();
    let mut knots = vec![z.start_knot];
    let m = if z.closed { n } else { n - 1 };
    for i in 0..m {
        let e = t.find_edge(ids[i], ids[(i + 1) % n]).expect("middle edge") as usize;
        knots.push(knots[i] + d[e] / z.knot_scale);
    }
    knots
}

/// Checks every point of the middle polygon `ids` of `s` (at its current level) that
/// influences the curve's domain against the blossom; returns the number of points checked
/// and the largest error relative to the curve's size.
pub fn check_middle(curve: &Curve, s: &Nurss, ids: &[u32], z: &Zone) -> (usize, f64) {
    let kv = knots(curve);
    let (a, b) = kv.domain();
    let period = b - a;
    let sz = size(curve);
    let (mut checked, mut worst) = (0, 0.0f64);
    let pos = s.positions();
    let zk = middle_knots(s, ids, z);
    let n = ids.len();
    let knot = |j: isize| -> f64 {
        // Knot at point j (extended periodically for a closed polygon).
        if z.closed {
            let q = j.div_euclid(n as isize);
            zk[j.rem_euclid(n as isize) as usize] + q as f64 * period
        } else {
            zk[j as usize]
        }
    };
    let range: Vec<isize> = if z.closed {
        (0..n as isize).collect()
    } else {
        (2..n as isize - 2).collect()
    };
    for j in range {
        let tri = [knot(j - 1), knot(j), knot(j + 1)];
        // A non-empty span among the four the point influences, inside the domain.
        let span = (-2..2).find_map(|k| {
            let (lo, hi) = (knot(j + k), knot(j + k + 1));
            let x = 0.5 * (lo + hi);
            (hi > lo && (z.closed || (x > a && x < b))).then_some(x)
        });
        let Some(x) = span else { continue };
        let shift = if z.closed {
            ((x - a) / period).floor() * period
        } else {
            0.0
        };
        let s_idx = kv.span(x - shift).unwrap();
        let reference = blossom(curve, s_idx, tri.map(|t| t - shift));
        worst = worst.max(dist(&pos[ids[j as usize] as usize], &reference) / sz);
        checked += 1;
    }
    (checked, worst)
}
