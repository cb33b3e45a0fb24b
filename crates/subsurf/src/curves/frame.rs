//! Side directions of a zone: the unit vector `u_i` at each middle-polygon point along which
//! the zone's side points are placed (`P_i ± W u_i`).
//!
//! - **Default: rotation-minimising frame** (double reflection, W. Wang, B. Jüttler,
//!   D. Zheng & Y. Liu, "Computation of rotation minimizing frames", ACM TOG 27(1), 2008),
//!   started from the polygon's plane normal (Newell's normal of the polygon, projected
//!   perpendicular to the first tangent; any perpendicular vector for a straight polygon).
//!   For a planar curve the frame is that plane's normal everywhere: the zone stands
//!   perpendicular to the curve's plane (a vase's profile curve gets a zone running around the
//!   vase, a rim circle a vertical band). On a closed polygon the frame's mismatch after one
//!   turn (its holonomy angle) is spread evenly over the points, so the frame closes.
//! - **A given side vector `s`**: `u_i = (s − (s·t_i) t_i) / |…|`, the vector projected
//!   perpendicular to the tangent.
//!
//! Tangents are `t_i = ê_{i−1} + ê_i` (unit edge directions; zero-length edges are
//! skipped), normalised; the tangent of an open end is its edge's direction.

use crate::geom::{cross, dot, norm, normalize_or_zero, sub, V3};

/// Unit tangents of a polygon (see the module documentation); `None` when all points
/// coincide.
pub fn tangents(points: &[V3], closed: bool) -> Option<Vec<V3>> {
    let n = points.len();
    let edge = |i: usize| normalize_or_zero(sub(&points[(i + 1) % n], &points[i]));
    let m = if closed { n } else { n - 1 };
    let dirs: Vec<V3> = (0..m).map(edge).collect();
    if dirs.iter().all(|d| norm(d) == 0.0) {
        return None;
    }
    // Nearest non-zero edge direction before point i (edges i − 1, i − 2, …) and after it
    // (edges i, i + 1, …), wrapping round a closed polygon: one sweep each way, two laps
    // when closed.
    let laps = if closed { 2 } else { 1 };
    let mut before: Vec<Option<V3>> = vec![None; n];
    let mut last: Option<V3> = None;
    for k in 0..laps * m {
        let e = k % m;
        if norm(&dirs[e]) > 0.0 {
            last = Some(dirs[e]);
        }
        // Edge e ends at point e + 1.
        let i = (e + 1) % n;
        if k + 1 >= (laps - 1) * m && (closed || e + 1 < n) {
            before[i] = last;
        }
    }
    let mut after: Vec<Option<V3>> = vec![None; n];
    let mut next: Option<V3> = None;
    for k in (0..laps * m).rev() {
        let e = k % m;
        if norm(&dirs[e]) > 0.0 {
            next = Some(dirs[e]);
        }
        // Edge e starts at point e.
        if k < m {
            after[e] = next;
        }
    }
    Some(
        (0..n)
            .map(|i| match (before[i], after[i]) {
                (Some(a), Some(b)) => {
                    let s = normalize_or_zero([a[0] + b[0], a[1] + b[1], a[2] + b[2]]);
                    if norm(&s) > 0.0 {
                        s
                    } else {
                        b
                    }
                }
                (Some(a), None) | (None, Some(a)) => a,
                (None, None) => [1.0, 0.0, 0.0],
            })
            .collect(),
    )
}

/// A unit vector perpendicular to `t` (the axis least aligned with it, projected).
fn any_perpendicular(t: &V3) -> V3 {
    let k = (0..3)
        .min_by(|&a, &b| t[a].abs().total_cmp(&t[b].abs()))
        .unwrap_or(0);
    let mut e = [0.0; 3];
    e[k] = 1.0;
    project_perpendicular(&e, t).unwrap_or([0.0, 0.0, 1.0])
}

/// `(v − (v·t) t) / |…|`, or `None` when `v` is (nearly) parallel to `t`.
fn project_perpendicular(v: &V3, t: &V3) -> Option<V3> {
    let d = dot(v, t);
    let p = [v[0] - d * t[0], v[1] - d * t[1], v[2] - d * t[2]];
    let l = norm(&p);
    (l > 1e-9 * norm(v).max(f64::MIN_POSITIVE)).then(|| [p[0] / l, p[1] / l, p[2] / l])
}

/// Rotates `v` about the unit axis `t` by `angle` (Rodrigues).
pub(crate) fn rotate(v: &V3, t: &V3, angle: f64) -> V3 {
    let (s, c) = angle.sin_cos();
    let k = cross(t, v);
    let d = dot(t, v) * (1.0 - c);
    [
        v[0] * c + k[0] * s + t[0] * d,
        v[1] * c + k[1] * s + t[1] * d,
        v[2] * c + k[2] * s + t[2] * d,
    ]
}

/// Signed angle from `a` to `b` about the unit axis `t` (both perpendicular to `t`).
pub(crate) fn angle_about(a: &V3, b: &V3, t: &V3) -> f64 {
    dot(&cross(a, b), t).atan2(dot(a, b))
}

/// Side directions `u_i` of the polygon (see the module documentation): with `side`
/// the given vector projected perpendicular to each tangent, else a rotation-minimising
/// frame.
///
/// # Errors
/// The index of the first point where `side` is parallel to the tangent.
pub fn side_directions(
    points: &[V3],
    tangents: &[V3],
    closed: bool,
    side: Option<V3>,
) -> Result<Vec<V3>, usize> {
    let n = points.len();
    if let Some(s) = side {
        return tangents
            .iter()
            .enumerate()
            .map(|(i, t)| project_perpendicular(&s, t).ok_or(i))
            .collect();
    }
    // Plane normal of the polygon (Newell), as the start vector.
    let mut nrm = [0.0; 3];
    for i in 0..n {
        let (a, b) = (&points[i], &points[(i + 1) % n]);
        nrm[0] += (a[1] - b[1]) * (a[2] + b[2]);
        nrm[1] += (a[2] - b[2]) * (a[0] + b[0]);
        nrm[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    let mut r0 = if norm(&nrm) > 0.0 {
        project_perpendicular(&nrm, &tangents[0]).unwrap_or_else(|| any_perpendicular(&tangents[0]))
    } else {
        any_perpendicular(&tangents[0])
    };
    if norm(&r0) == 0.0 {
        r0 = any_perpendicular(&tangents[0]);
    }
    let steps = if closed { n } else { n - 1 };
    let mut frame = Vec::with_capacity(n + 1);
    frame.push(r0);
    for i in 0..steps {
        let (x0, x1) = (&points[i], &points[(i + 1) % n]);
        let (t0, t1) = (&tangents[i], &tangents[(i + 1) % n]);
        let r = frame[i];
        let v1 = sub(x1, x0);
        let c1 = dot(&v1, &v1);
        let (rl, tl) = if c1 > 0.0 {
            let f = 2.0 / c1;
            let (a, b) = (f * dot(&v1, &r), f * dot(&v1, t0));
            (
                [r[0] - a * v1[0], r[1] - a * v1[1], r[2] - a * v1[2]],
                [t0[0] - b * v1[0], t0[1] - b * v1[1], t0[2] - b * v1[2]],
            )
        } else {
            (r, *t0)
        };
        let v2 = sub(t1, &tl);
        let c2 = dot(&v2, &v2);
        let next = if c2 > 0.0 {
            let a = 2.0 / c2 * dot(&v2, &rl);
            [rl[0] - a * v2[0], rl[1] - a * v2[1], rl[2] - a * v2[2]]
        } else {
            rl
        };
        frame.push(project_perpendicular(&next, t1).unwrap_or_else(|| any_perpendicular(t1)));
    }
    if closed {
        // Spread the holonomy evenly over the points.
        let phi = angle_about(&frame[n], &frame[0], &tangents[0]);
        for (i, f) in frame.iter_mut().enumerate().take(n) {
            *f = rotate(f, &tangents[i], phi * i as f64 / n as f64);
        }
    }
    frame.truncate(n);
    Ok(frame)
}
