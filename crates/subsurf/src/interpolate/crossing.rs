//! Crossings of curves: control points shared by two curves, checked against what a *joint
//! polygon group* needs (seed 001, §2 and Corollary 1).
//!
//! Where curve `A` (control point `k`, neighbours `A_{k±1} = X ± a`) and curve `B`
//! (control point `l`, neighbours `B_{l±1} = X ± b`) cross at `X`, the four quads around
//! `X` with corners `X`, `X ± a`, `X ± b`, `X ± a ± b` belong to both zones: `A`'s side
//! points at its three control points are `B`'s polygon (offset `±b`), and `B`'s are `A`'s
//! (offset `∓a`, so that both zones orient the shared quads alike). The proof of
//! Corollary 1 needs `P_1 + P_3 = 2 P_0` and equal intervals on opposite edges, for both
//! curves (eq. 16), and the theorem's conditions need `A`'s column intervals to be `B`'s
//! interval at `X` and vice versa. Then the group's centre stays fixed under subdivision and
//! each curve passes straight through it: the limit curves of opposite arms join with `G2`
//! (they are one cubic B-spline), those of adjacent arms with `G0`.
//!
//! A curve *ending* at a point another curve passes through (a T-junction, three branches)
//! gets a phantom end point `X − c` opposite its last edge `X + c` (see [`super::curve`]): the
//! group's fourth side point. Then it passes through the group like a crossing curve, and its
//! zone's limit runs from the curve's domain on to `X` (the group's fixed centre) along the
//! curve's natural extension; its end needs `d_1 = d_2` (an unclamped end: a clamped end has
//! zero intervals there, which a group cannot take).
//!
//! Two curves *both ending* at one point `X` (an L-shaped corner) are the same group once each
//! has its phantom end point: the phantoms fill the two free arms, each extended polygon passes
//! through `X`, and the pair is a crossing of the extended polygons. Why this is the only way
//! an end can sit in a group: Lemma 1's conclusion (iii) (`E_2 + E_4 = 2 V`, the group's
//! centre fixed) needs every middle polygon through `X` to have a neighbour on *both* sides,
//! symmetric about `X` with equal intervals — an end has one, and its phantom (`2X − P_{n−2}`,
//! interval `d_{n+1}`) is the other; and the curve on its domain `[t_3, t_n]` does not depend on
//! where the phantom is, only on `d_{n+1}` (see [`super::curve`]). So each curve at `X`, ending
//! or passing, takes one of the group's two lines, and the conditions are those of a crossing:
//! `d_{n−1} = d_n = d_{n+1}` at the end (an unclamped end with equal last intervals; a clamped
//! end has `d_{n+1} = 0`). A third curve would need a third line through `X` (a valence-6
//! centre), beyond Corollary 1: refused ([`InterpolateError::SharedPoint`]), as are two curves
//! ending at `X` in one line (their zones would overlap: join them into one curve).
//!
//! What the method cannot do is reported, naming the curve and the point: more than 4 branches
//! at one point (a curve passing through counts 2, one ending there 1); three or more curves at
//! one point; neighbours that are not
//! symmetric about `X`; unequal intervals on the four edges around `X`
//! (`d_{k−2} = d_{k−1} = d_k = d_{k+1}` is needed: the other curve's zone has column interval
//! `d_k`, and at the group's corners its column edges read `d_{k−2}` and `d_{k+1}` two steps
//! around — Lemma 1's second-edge condition; measured in `tests/integration/interpolate.rs`: with
//! intervals `0.6, 1, 1, 0.6` around `X` the other curve is missed by 2e-3 of its size); curves
//! tangent at `X`;
//! unequal weights around a rational crossing; control polygons that cross without a shared
//! control point.

use super::{CubicCurve, InterpolateError, MiddlePolygon};
use crate::geom::{cross, dot, norm, sub, V3};

/// One curve passing through a crossing: curve index and middle-polygon index of `X`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arm {
    /// Curve index.
    pub curve: usize,
    /// Index of the crossing point in the curve's middle polygon.
    pub index: usize,
}

/// Two curves crossing at a shared control point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// The first curve (the lower index).
    pub a: Arm,
    /// The second curve.
    pub b: Arm,
}

fn crossing_error(c: &CubicCurve, m: &MiddlePolygon, j: usize, reason: String) -> InterpolateError {
    let p = m.points[j];
    InterpolateError::Crossing {
        curve: c.label.clone(),
        index: j - m.first,
        x: p[0],
        y: p[1],
        z: p[2],
        reason,
    }
}

/// Index of the neighbour `j + s` (`s = ±1`) in a middle polygon, wrapping when closed.
pub(crate) fn neighbour(m: &MiddlePolygon, j: usize, s: isize) -> Option<usize> {
    let n = m.len() as isize;
    let i = j as isize + s;
    if m.closed {
        Some(i.rem_euclid(n) as usize)
    } else if (0..n).contains(&i) {
        Some(i as usize)
    } else {
        None
    }
}

/// Interval of the edge from `j` to `j + s` (`s = ±1`; the edge must exist).
pub(crate) fn edge_interval(m: &MiddlePolygon, j: usize, s: isize) -> f64 {
    let n = m.len();
    if s > 0 {
        m.intervals[j]
    } else {
        m.intervals[(j + n - 1) % n]
    }
}

/// Finds the crossings of `curves` (control points of different curves within `tol` of each
/// other) and checks each (see the [module documentation](self)).
///
/// # Errors
/// [`InterpolateError::TooManyCurves`], [`InterpolateError::Crossing`],
/// [`InterpolateError::UnsharedCrossing`].
pub fn find_crossings(
    curves: &[CubicCurve],
    tol: f64,
) -> Result<(Vec<MiddlePolygon>, Vec<Crossing>), InterpolateError> {
    // Groups of coincident control points of different curves (user indices).
    let mut groups: Vec<(V3, Vec<Arm>)> = Vec::new();
    for (c, curve) in curves.iter().enumerate() {
        for i in 0..curve.len() {
            let p = curve.points[i];
            let arm = Arm { curve: c, index: i };
            match groups
                .iter_mut()
                .find(|(q, arms)| norm(&sub(q, &p)) <= tol && arms.iter().all(|a| a.curve != c))
            {
                Some((_, arms)) => arms.push(arm),
                None => groups.push((p, vec![arm])),
            }
        }
    }
    groups.retain(|(_, a)| a.len() > 1);
    let is_end = |a: &Arm| {
        let c = &curves[a.curve];
        !c.closed && (a.index == 0 || a.index + 1 == c.len())
    };
    let mut phantoms = vec![(false, false); curves.len()];
    for (x, arms) in &groups {
        let branches: usize = arms.iter().map(|a| if is_end(a) { 1 } else { 2 }).sum();
        if branches > 4 {
            let names: Vec<String> = arms
                .iter()
                .map(|a| format!("{} point {}", curves[a.curve].label, a.index))
                .collect();
            return Err(InterpolateError::TooManyCurves {
                branches,
                curves: names.join(", "),
                x: x[0],
                y: x[1],
                z: x[2],
            });
        }
        if arms.len() > 2 {
            let names: Vec<String> = arms
                .iter()
                .map(|a| {
                    let how = if is_end(a) { "ends" } else { "passes" };
                    format!("{} {how} at its point {}", curves[a.curve].label, a.index)
                })
                .collect();
            return Err(InterpolateError::SharedPoint {
                count: arms.len(),
                curves: names.join(", "),
                x: x[0],
                y: x[1],
                z: x[2],
            });
        }
        for a in arms.iter().filter(|a| is_end(a)) {
            if a.index == 0 {
                phantoms[a.curve].0 = true;
            } else {
                phantoms[a.curve].1 = true;
            }
        }
    }
    let middles: Vec<MiddlePolygon> = curves
        .iter()
        .zip(&phantoms)
        .map(|(c, &(s, e))| c.middle_polygon_with(s, e))
        .collect();
    let mut out = Vec::new();
    for (_, arms) in groups {
        let arms: Vec<Arm> = arms
            .iter()
            .map(|a| Arm {
                curve: a.curve,
                index: a.index + middles[a.curve].first,
            })
            .collect();
        let (a, b) = (arms[0], arms[1]);
        let user = |arm: Arm| Arm {
            curve: arm.curve,
            index: arm.index - middles[arm.curve].first,
        };
        check_arm(curves, &middles, a, tol)?;
        check_arm(curves, &middles, b, tol)?;
        let dir = |arm: Arm| {
            let m = &middles[arm.curve];
            let j = neighbour(m, arm.index, 1).unwrap_or(arm.index);
            sub(&m.points[j], &m.points[arm.index])
        };
        let (da, db) = (dir(a), dir(b));
        if norm(&cross(&da, &db)) <= 1e-6 * norm(&da) * norm(&db) {
            let other = &curves[a.curve].label;
            let reason = if is_end(&user(a)) && is_end(&user(b)) {
                format!("the curve ends where {other} ends, in the same line; join the two curves into one (their zones would overlap)")
            } else {
                format!("the control polygon is parallel to that of {other} here; crossing curves must meet at an angle")
            };
            return Err(crossing_error(
                &curves[b.curve],
                &middles[b.curve],
                b.index,
                reason,
            ));
        }
        let w = |arm: Arm, s: isize| {
            let m = &middles[arm.curve];
            neighbour(m, arm.index, s).map_or(1.0, |j| m.weights[j])
        };
        let wx = w(a, 0);
        for arm in [a, b] {
            for s in -1..=1 {
                if (w(arm, s) - wx).abs() > 1e-12 * wx {
                    return Err(crossing_error(
                        &curves[arm.curve],
                        &middles[arm.curve],
                        arm.index,
                        "the weights of both curves at the crossing point and its neighbours must be equal (a joint polygon group is symmetric in homogeneous coordinates)".into(),
                    ));
                }
            }
        }
        out.push(Crossing { a, b });
    }
    check_unshared(curves, &middles, tol)?;
    Ok((middles, out))
}

/// The neighbours of the crossing point are symmetric about it, with equal intervals.
fn check_arm(
    curves: &[CubicCurve],
    middles: &[MiddlePolygon],
    arm: Arm,
    tol: f64,
) -> Result<(), InterpolateError> {
    let m = &middles[arm.curve];
    let c = &curves[arm.curve];
    let j = arm.index;
    let (Some(jm), Some(jp)) = (neighbour(m, j, -1), neighbour(m, j, 1)) else {
        return Err(crossing_error(c, m, j, "no neighbour on one side".into()));
    };
    let x = m.points[j];
    let s = [
        m.points[jm][0] + m.points[jp][0] - 2.0 * x[0],
        m.points[jm][1] + m.points[jp][1] - 2.0 * x[1],
        m.points[jm][2] + m.points[jp][2] - 2.0 * x[2],
    ];
    if norm(&s) > tol {
        return Err(crossing_error(
            c,
            m,
            j,
            format!(
                "a joint polygon group needs the neighbouring control points symmetric about the crossing point (P[{}] + P[{}] = 2 P[{}]), off by {:e}",
                jm - m.first.min(jm),
                jp - m.first.min(jp),
                j - m.first,
                norm(&s)
            ),
        ));
    }
    let (d0, d1) = (edge_interval(m, j, -1), edge_interval(m, j, 1));
    if (d0 - d1).abs() > 1e-12 * d0.abs().max(d1.abs()) || d0 <= 0.0 {
        return Err(crossing_error(
            c,
            m,
            j,
            format!("a joint polygon group needs equal non-zero knot intervals on both edges at the crossing point, got {d0} and {d1}"),
        ));
    }
    // Lemma 1's second-edge condition for the *other* curve's zone: its column edges at the
    // group's corners (interval `d0`, this curve's interval at X) read this curve's intervals
    // one edge beyond the group, on both sides, and those must equal the column interval
    // (where the polygon ends there, the boundary rule reads the edge's own interval).
    let beyond = |s: isize, near: usize| match neighbour(m, near, s) {
        Some(_) => edge_interval(m, near, s),
        None => edge_interval(m, j, s),
    };
    let (c0, c1) = (beyond(-1, jm), beyond(1, jp));
    if [c0, c1]
        .iter()
        .any(|&c| (c - d0).abs() > 1e-12 * c.abs().max(d0.abs()))
    {
        return Err(crossing_error(
            c,
            m,
            j,
            format!("the crossing curve's zone needs the two edges just beyond the crossing's neighbours to have the same knot interval as the edges at the crossing (Lemma 1, second-edge condition): got {c0}, {d0}, {d1}, {c1}"),
        ));
    }
    if norm(&sub(&m.points[jp], &x)) <= tol {
        return Err(crossing_error(
            c,
            m,
            j,
            "the neighbouring control points coincide with the crossing point".into(),
        ));
    }
    Ok(())
}

/// Control-polygon edges of different curves that pass within `tol` of each other away from
/// shared control points.
fn check_unshared(
    curves: &[CubicCurve],
    middles: &[MiddlePolygon],
    tol: f64,
) -> Result<(), InterpolateError> {
    let edges = |c: usize| {
        let curve = &curves[c];
        let n = curve.len();
        let m = if curve.closed { n } else { n - 1 };
        (0..m).map(move |i| (i, curve.points[i], curve.points[(i + 1) % n]))
    };
    for a in 0..curves.len() {
        for b in a + 1..curves.len() {
            for (i, p0, p1) in edges(a) {
                for (j, q0, q1) in edges(b) {
                    let shared = [p0, p1]
                        .iter()
                        .any(|p| [q0, q1].iter().any(|q| norm(&sub(p, q)) <= tol));
                    if shared {
                        continue;
                    }
                    if let Some(x) = segments_meet(&p0, &p1, &q0, &q1, tol) {
                        let _ = middles;
                        return Err(InterpolateError::UnsharedCrossing {
                            a: curves[a].label.clone(),
                            edge_a: i,
                            b: curves[b].label.clone(),
                            edge_b: j,
                            x: x[0],
                            y: x[1],
                            z: x[2],
                        });
                    }
                }
            }
        }
    }
    Ok(())
}

/// The midpoint of the closest points of two segments when they are within `tol`.
fn segments_meet(p0: &V3, p1: &V3, q0: &V3, q1: &V3, tol: f64) -> Option<V3> {
    let d1 = sub(p1, p0);
    let d2 = sub(q1, q0);
    let r = sub(p0, q0);
    let (a, e, f) = (dot(&d1, &d1), dot(&d2, &d2), dot(&d2, &r));
    let (s, t) = if a <= 0.0 && e <= 0.0 {
        (0.0, 0.0)
    } else if a <= 0.0 {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = dot(&d1, &r);
        if e <= 0.0 {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = dot(&d1, &d2);
            let den = a * e - b * b;
            let mut s = if den > 0.0 {
                ((b * f - c * e) / den).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            }
            (s, t)
        }
    };
    let cp = [p0[0] + s * d1[0], p0[1] + s * d1[1], p0[2] + s * d1[2]];
    let cq = [q0[0] + t * d2[0], q0[1] + t * d2[1], q0[2] + t * d2[2]];
    (norm(&sub(&cp, &cq)) <= tol).then(|| {
        [
            0.5 * (cp[0] + cq[0]),
            0.5 * (cp[1] + cq[1]),
            0.5 * (cp[2] + cq[2]),
        ]
    })
}
