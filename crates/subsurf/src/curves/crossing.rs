//! Control points shared by several curves: *joint polygon groups* ([JOS 2003], §2 and
//! Corollary 1), and two curves ending at one point joined into one zone.
//!
//! # A joint polygon group
//! Four quads around a shared control point `X` with corners `X`, `X ± u`, `X ± v`,
//! `X ± u ± v`: two *lines* through `X`, along `u` and along `v`. Every curve at `X` runs
//! along one line, and each zone contains the group: the side points of a curve on the `u`
//! line are the `v` line's points (offset `±v`), those of a curve on the `v` line the `u`
//! line's (offset `∓u`, so that all zones orient the shared quads alike). The proof of
//! Corollary 1 needs, on each line, `P_1 + P_3 = 2 P_0` and equal intervals on opposite edges
//! (eq. 16); Theorem 1 needs every zone's column intervals equal, so a curve on the `u` line
//! gets the `v` line's interval at `X` as its column interval, and Lemma 1's second-edge
//! condition needs the intervals just beyond the line's neighbours to be that interval too.
//! Then the centre stays fixed under subdivision, every curve passes straight through it, and
//! the limit curves of opposite arms join `G2` (they are one cubic B-spline), those of
//! adjacent arms `G0`.
//!
//! Corollary 1 allows up to four zones to share a group (Fig. 13 b, c: three and four curves
//! through one point). A line holds
//! - one curve passing through `X` (both its neighbours are the line's points), or
//! - one curve *ending* at `X`, which gets a *phantom* end point `X − c` opposite its last
//!   edge `X + c` (see [`super::curve`]): the line's other point; or
//! - two curves ending at `X` from opposite sides, each the other's continuation: the
//!   neighbour of one is the phantom of the other (`P + Q = 2 X`), and so are the knot
//!   intervals of the shared edges.
//!
//! So two crossing curves fill a group, and so do one curve passing and one or two ending
//! (a T-junction, or a crossing whose second curve is given as two curves), or two, three or
//! four curves ending (Fig. 13 b, c). An ending curve's zone runs from the curve's end on to
//! `X` along the cubic B-spline of its control polygon extended by the phantom point
//! `2 X − P_{n−2}` with interval `d_{n+1}` (or, paired, along the other curve's polygon): on
//! `[t_n, t_{n+1}]` a span of that spline, `C²` with the curve at `C(t_n)`, reaching `X` (the
//! group's fixed centre) with zero curvature. This is not the curve's own polynomial
//! continued beyond `t_n` (that would need the phantom at a point fixed by the last span,
//! which a symmetric group cannot take). Why an end can sit in a group only this way:
//! Lemma 1's conclusion (iii) (`E_2 + E_4 = 2 V`, the group's centre fixed) needs every middle
//! polygon through `X` to have a neighbour on *both* sides, symmetric about `X` with equal
//! intervals; the curve on its domain `[t_3, t_n]` does not depend on where the phantom is,
//! only on `d_{n+1}` (see [`super::curve`]). The end needs `d_{n−1} = d_n = d_{n+1}` (an
//! unclamped end with equal last intervals; a clamped end has `d_{n+1} = 0`).
//!
//! # The angle between the lines
//! The group's quads are the parallelograms spanned by `u` and `v`, and a curve's column at
//! its neighbour `X + u` has the side points `X + u ± v`, which run nearly along the curve
//! when the lines are close: at a small angle the group is a sliver and the limit surface
//! folds (two curves crossing 21°–25° apart: 2–32 flipped face pairs at level 4; none from 30°
//! on, with the zones' side offsets kept sheared as [`super::zone`] does). Groups whose lines
//! are less than [`MIN_LINE_ANGLE`] apart are refused, naming the curves and the angle.
//!
//! # Two curves ending at one point, nearly opposite: one zone
//! Two curves that end at `X` and nothing else there, from directions more than
//! `180° − MIN_LINE_ANGLE` apart (as a group their lines would be too close: ends 170°–179°
//! apart in one plane folded the surface, 22–58 flipped face pairs at level 4), are not a
//! group: their zones are joined into one through `X` (each one's phantom end point is the
//! other's neighbour), a middle polygon that turns by less than [`MIN_LINE_ANGLE`] at `X` and
//! needs no symmetry there. Each curve on its domain depends on its own control points and on
//! the knot intervals up to the edge beyond `X` only, so both stay exact when the shared edges
//! carry both curves' intervals: the last edge of one must have the other's phantom interval
//! (`d_n = d'_1`) and the reverse (`d_{n+1} = d'_2`); the two zones share their columns and
//! their column interval. The limit then runs from one curve's end to the other's along one
//! cubic B-spline (through `X` only when the two polygons are symmetric there); no fold at
//! level 4 (tested from 170° to 179°).
//!
//! # What is refused
//! Reported naming the curves and the point: more than 4 branches at one point (a curve
//! passing through counts 2, one ending there 1); curves at one point that do not make two
//! lines; neighbours not symmetric about `X`; unequal intervals on the four edges around `X`
//! (`d_{k−2} = d_{k−1} = d_k = d_{k+1}` is needed: the other line's zones have column interval
//! `d_k`, and at the group's corners their column edges read `d_{k−2}` and `d_{k+1}` two steps
//! around — Lemma 1's second-edge condition; measured in `tests/integration/interpolate.rs`:
//! with intervals `0.6, 1, 1, 0.6` around `X` the other curve is missed by 2e-3 of its size);
//! lines closer than [`MIN_LINE_ANGLE`]; unequal weights around a rational crossing; joined
//! ends whose intervals do not continue each other; control polygons that cross without a
//! shared control point.
//!
//! Shared points and polygons passing near each other are found with a hash grid
//! (`interpolate/grid.rs`) in time linear in the number of control points.

use super::grid::{lower_corner, Grid};
use super::{CubicCurve, InterpolateError, MiddlePolygon};
use crate::geom::{dot, norm, sub, V3};
use std::collections::HashSet;

/// The smallest angle, in degrees, between the two lines of a joint polygon group (see the
/// [module documentation](self#the-angle-between-the-lines)).
pub(crate) const MIN_LINE_ANGLE: f64 = 30.0;

/// One curve at a shared point: curve index and middle-polygon index of the point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Arm {
    /// Curve index.
    pub curve: usize,
    /// Index of the shared point in the curve's middle polygon.
    pub index: usize,
}

/// A joint polygon group: the curves on each of its two lines (one passing through the
/// point, or one or two ending there; see the [module documentation](self)).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Group {
    /// The curves of each line; the first of a line sets its direction (from the point to
    /// that curve's next middle-polygon point).
    pub lines: [Vec<Arm>; 2],
}

/// Two curves ending at one point from nearly opposite directions, joined into one zone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Join {
    /// The curve of the lower index (its zone is built first; the other takes its columns).
    pub a: Arm,
    /// The other curve.
    pub b: Arm,
}

/// The middle polygons of all curves (phantom end points included) and how they share
/// points.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Crossings {
    /// One per curve, in input order.
    pub middles: Vec<MiddlePolygon>,
    /// Joint polygon groups.
    pub groups: Vec<Group>,
    /// Ends joined into one zone.
    pub joins: Vec<Join>,
}

fn crossing_error(c: &CubicCurve, m: &MiddlePolygon, j: usize, reason: String) -> InterpolateError {
    let p = m.points[j];
    InterpolateError::Crossing {
        curve: c.label.clone(),
        index: j.saturating_sub(m.first),
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

/// Whether middle-polygon point `j` is a phantom (not one of the curve's control points).
fn is_phantom(m: &MiddlePolygon, count: usize, j: usize) -> bool {
    j < m.first || j >= m.first + count
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * a.abs().max(b.abs())
}

/// Finds the control points shared by curves (within `tol` of each other), arranges each
/// into a joint polygon group or a join, and checks them (see the [module
/// documentation](self)).
///
/// Adds to `work` the candidates it compares (shared points and polygon edges), a
/// measure of its running time.
///
/// # Errors
/// [`InterpolateError::TooManyCurves`], [`InterpolateError::SharedPoint`],
/// [`InterpolateError::Crossing`], [`InterpolateError::UnsharedCrossing`].
pub(crate) fn find_crossings_counted(
    curves: &[CubicCurve],
    tol: f64,
    work: &mut u64,
) -> Result<Crossings, InterpolateError> {
    let points = shared_points(curves, tol, work);
    let is_end = |a: &Arm| {
        let c = &curves[a.curve];
        !c.closed && (a.index == 0 || a.index + 1 == c.len())
    };
    let mut phantoms = vec![(false, false); curves.len()];
    for (x, arms) in &points {
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
        for a in arms.iter().filter(|a| is_end(a)) {
            if a.index == 0 {
                phantoms[a.curve].0 = true;
            } else {
                phantoms[a.curve].1 = true;
            }
        }
    }
    let mut middles: Vec<MiddlePolygon> = curves
        .iter()
        .zip(&phantoms)
        .map(|(c, &(s, e))| c.middle_polygon_with(s, e))
        .collect();
    let (mut groups, mut joins) = (Vec::new(), Vec::new());
    for (x, arms) in &points {
        let arms: Vec<Arm> = arms
            .iter()
            .map(|a| Arm {
                curve: a.curve,
                index: a.index + middles[a.curve].first,
            })
            .collect();
        match arrange(curves, &mut middles, &arms, x, tol)? {
            Arrangement::Group(g) => groups.push(g),
            Arrangement::Join(j) => joins.push(j),
        }
    }
    check_unshared(curves, tol, work)?;
    Ok(Crossings {
        middles,
        groups,
        joins,
    })
}

/// Groups of control points of different curves within `tol` of each other (user indices),
/// those with more than one curve. A point joins the first group (in order of creation)
/// whose first point is within `tol` and which has no point of its curve yet.
fn shared_points(curves: &[CubicCurve], tol: f64, work: &mut u64) -> Vec<(V3, Vec<Arm>)> {
    let origin = lower_corner(curves.iter().flat_map(|c| c.points.iter()));
    let mut grid = Grid::new((2.0 * tol).max(f64::MIN_POSITIVE), origin);
    let mut groups: Vec<(V3, Vec<Arm>)> = Vec::new();
    for (c, curve) in curves.iter().enumerate() {
        for (i, p) in curve.points.iter().enumerate() {
            let mut best: Option<u32> = None;
            grid.near(p, |g| {
                *work += 1;
                let (q, arms) = &groups[g as usize];
                if norm(&sub(q, p)) <= tol
                    && arms.iter().all(|a| a.curve != c)
                    && best.is_none_or(|b| g < b)
                {
                    best = Some(g);
                }
            });
            let arm = Arm { curve: c, index: i };
            match best {
                Some(g) => groups[g as usize].1.push(arm),
                None => {
                    grid.insert_point(p, groups.len() as u32);
                    groups.push((*p, vec![arm]));
                }
            }
        }
    }
    groups.retain(|(_, a)| a.len() > 1);
    groups
}

enum Arrangement {
    Group(Group),
    Join(Join),
}

/// An arm's curve ends at the shared point: its real neighbour's side (`+1`: the next
/// middle-polygon point, `−1`: the previous one), or `None` when it passes through.
fn end_side(curves: &[CubicCurve], middles: &[MiddlePolygon], a: Arm) -> Option<isize> {
    let (c, m) = (&curves[a.curve], &middles[a.curve]);
    if c.closed {
        return None;
    }
    let prev = neighbour(m, a.index, -1).is_some_and(|j| !is_phantom(m, c.len(), j));
    let next = neighbour(m, a.index, 1).is_some_and(|j| !is_phantom(m, c.len(), j));
    match (prev, next) {
        (true, true) => None,
        (true, false) => Some(-1),
        _ => Some(1),
    }
}

/// The vector from the shared point to the arm's neighbour on side `s`.
fn arm_dir(middles: &[MiddlePolygon], a: Arm, s: isize) -> V3 {
    let m = &middles[a.curve];
    let j = neighbour(m, a.index, s).unwrap_or(a.index);
    sub(&m.points[j], &m.points[a.index])
}

/// Angle in degrees between two vectors (0 when one is zero).
fn angle_deg(a: &V3, b: &V3) -> f64 {
    let (la, lb) = (norm(a), norm(b));
    if la == 0.0 || lb == 0.0 {
        return 0.0;
    }
    (dot(a, b) / (la * lb)).clamp(-1.0, 1.0).acos().to_degrees()
}

/// How `arm` meets the point, for messages: "a passes at its point 3", "b ends at its point 0".
fn describe(curves: &[CubicCurve], middles: &[MiddlePolygon], a: Arm) -> String {
    let how = if end_side(curves, middles, a).is_some() {
        "ends"
    } else {
        "passes"
    };
    let m = &middles[a.curve];
    format!(
        "{} {how} at its point {}",
        curves[a.curve].label,
        a.index - m.first
    )
}

/// Arranges the curves at one shared point `x` into a group's two lines or a join, and
/// checks them.
fn arrange(
    curves: &[CubicCurve],
    middles: &mut [MiddlePolygon],
    arms: &[Arm],
    x: &V3,
    tol: f64,
) -> Result<Arrangement, InterpolateError> {
    let ends: Vec<Option<isize>> = arms.iter().map(|&a| end_side(curves, middles, a)).collect();
    if let ([a, b], [Some(sa), Some(sb)]) = (arms, ends.as_slice()) {
        let angle = angle_deg(&arm_dir(middles, *a, *sa), &arm_dir(middles, *b, *sb));
        if angle > 180.0 - MIN_LINE_ANGLE + 1e-9 {
            return join(curves, middles, [*a, *b], [*sa, *sb], angle);
        }
    }
    // Passing curves take a line each; ending ones pair up when each is the other's
    // continuation (neighbours symmetric about the point), else take a line each.
    let mut lines: Vec<Vec<Arm>> = Vec::new();
    let mut paired = vec![false; arms.len()];
    for i in 0..arms.len() {
        if paired[i] {
            continue;
        }
        let Some(si) = ends[i] else {
            lines.push(vec![arms[i]]);
            continue;
        };
        let di = arm_dir(middles, arms[i], si);
        let partner = (i + 1..arms.len()).find(|&j| {
            !paired[j]
                && ends[j].is_some_and(|sj| {
                    let dj = arm_dir(middles, arms[j], sj);
                    norm(&[di[0] + dj[0], di[1] + dj[1], di[2] + dj[2]]) <= tol
                })
        });
        match partner {
            Some(j) => {
                paired[j] = true;
                let sj = ends[j].unwrap_or(1);
                continue_into(middles, arms[i], si, arms[j], sj);
                lines.push(vec![arms[i], arms[j]]);
            }
            None => lines.push(vec![arms[i]]),
        }
    }
    if lines.len() != 2 {
        let names: Vec<String> = arms.iter().map(|&a| describe(curves, middles, a)).collect();
        return Err(InterpolateError::SharedPoint {
            count: arms.len(),
            lines: lines.len(),
            curves: names.join(", "),
            x: x[0],
            y: x[1],
            z: x[2],
        });
    }
    let lines = [lines[0].clone(), lines[1].clone()];
    for line in &lines {
        for &a in line {
            check_arm(curves, middles, a, tol)?;
        }
        check_line(curves, middles, line)?;
    }
    check_angle(curves, middles, &lines)?;
    check_weights(curves, middles, &lines)?;
    Ok(Arrangement::Group(Group { lines }))
}

/// Makes each of two curves ending at one point continue into the other: `a`'s phantom
/// (opposite its real neighbour on side `sa`) becomes `b`'s real neighbour (position and
/// weight), and the reverse. Each curve on its domain does not depend on its phantom point.
fn continue_into(middles: &mut [MiddlePolygon], a: Arm, sa: isize, b: Arm, sb: isize) {
    let real = |m: &MiddlePolygon, arm: Arm, s: isize| {
        let j = neighbour(m, arm.index, s).unwrap_or(arm.index);
        (m.points[j], m.weights[j])
    };
    let (pa, wa) = real(&middles[a.curve], a, sa);
    let (pb, wb) = real(&middles[b.curve], b, sb);
    for (arm, s, p, w) in [(a, -sa, pb, wb), (b, -sb, pa, wa)] {
        let m = &mut middles[arm.curve];
        if let Some(j) = neighbour(m, arm.index, s) {
            m.points[j] = p;
            m.weights[j] = w;
        }
    }
}

/// Two curves ending at one point from nearly opposite directions (`angle` apart), joined
/// into one zone (see the [module documentation](self#two-curves-ending-at-one-point-nearly-opposite-one-zone)).
fn join(
    curves: &[CubicCurve],
    middles: &mut [MiddlePolygon],
    arms: [Arm; 2],
    sides: [isize; 2],
    angle: f64,
) -> Result<Arrangement, InterpolateError> {
    let [a, b] = if arms[0].curve < arms[1].curve {
        arms
    } else {
        [arms[1], arms[0]]
    };
    let [sa, sb] = if arms[0].curve < arms[1].curve {
        sides
    } else {
        [sides[1], sides[0]]
    };
    let (ma, mb) = (&middles[a.curve], &middles[b.curve]);
    // The edge to a's real neighbour is b's phantom edge, and the reverse.
    let (ra, pa) = (
        edge_interval(ma, a.index, sa),
        edge_interval(ma, a.index, -sa),
    );
    let (rb, pb) = (
        edge_interval(mb, b.index, sb),
        edge_interval(mb, b.index, -sb),
    );
    let (wa, wb) = (ma.weights[a.index], mb.weights[b.index]);
    let name = |arm: Arm| describe(curves, middles, arm);
    let reason = if !(same(ra, pb) && same(rb, pa)) {
        Some(format!(
            "{} and {}, their last edges {angle:.1}° apart: nearly opposite ends are joined into one zone through the point, whose shared edges need the knot intervals of both curves: the edge to {}'s neighbour has interval {ra} in it and {pb} beyond {}'s end, the edge to {}'s neighbour {rb} and {pa}; give the curves matching end intervals (or join them into one curve)",
            name(a), name(b), curves[a.curve].label, curves[b.curve].label, curves[b.curve].label
        ))
    } else if !same(wa, wb) {
        Some(format!(
            "{} and {} are joined into one zone through the point, which needs one weight there: got {wa} and {wb}",
            name(a),
            name(b)
        ))
    } else {
        None
    };
    if let Some(reason) = reason {
        return Err(crossing_error(&curves[b.curve], mb, b.index, reason));
    }
    continue_into(middles, a, sa, b, sb);
    Ok(Arrangement::Join(Join { a, b }))
}

/// The neighbours of the shared point are symmetric about it and do not coincide with it.
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
    let s = [0, 1, 2].map(|k| m.points[jm][k] + m.points[jp][k] - 2.0 * x[k]);
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

/// The intervals along one line of a group: one value on both edges at the point (every
/// curve on the line agreeing) and, Lemma 1's second-edge condition, on the edges just beyond
/// the neighbours (where a neighbour ends its polygon, the boundary rule reads the edge's
/// own interval; where it is a phantom of a paired curve, the other curve's edge is there).
fn check_line(
    curves: &[CubicCurve],
    middles: &[MiddlePolygon],
    line: &[Arm],
) -> Result<(), InterpolateError> {
    let first = line[0];
    let dir = arm_dir(middles, first, 1);
    let err = |arm: Arm, reason: String| {
        crossing_error(&curves[arm.curve], &middles[arm.curve], arm.index, reason)
    };
    // at[0], at[1]: the edges at the point towards −dir and +dir; beyond likewise.
    let mut at: [Option<f64>; 2] = [None, None];
    let mut beyond: [Option<f64>; 2] = [None, None];
    for &arm in line {
        let m = &middles[arm.curve];
        let count = curves[arm.curve].len();
        let sigma = if dot(&arm_dir(middles, arm, 1), &dir) >= 0.0 {
            1
        } else {
            -1
        };
        for (k, side) in [(0usize, -1isize), (1, 1)] {
            let s = side * sigma;
            let d = edge_interval(m, arm.index, s);
            match at[k] {
                Some(old) if !same(old, d) => {
                    return Err(err(
                        arm,
                        format!("the curves ending here from opposite sides continue each other (Corollary 1): the edge they share needs one knot interval, got {old} and {d}"),
                    ))
                }
                _ => at[k] = Some(d),
            }
            let Some(jn) = neighbour(m, arm.index, s) else {
                continue;
            };
            if is_phantom(m, count, jn) && line.len() > 1 {
                continue; // the paired curve's edge is beyond
            }
            beyond[k] = Some(match neighbour(m, jn, s) {
                Some(_) if !is_phantom(m, count, jn) => edge_interval(m, jn, s),
                _ => d,
            });
        }
    }
    let (d0, d1) = (at[0].unwrap_or(0.0), at[1].unwrap_or(0.0));
    if !same(d0, d1) || d0 <= 0.0 {
        return Err(err(
            first,
            format!("a joint polygon group needs equal non-zero knot intervals on both edges at the crossing point, got {d0} and {d1}"),
        ));
    }
    let (c0, c1) = (beyond[0].unwrap_or(d0), beyond[1].unwrap_or(d0));
    if !(same(c0, d0) && same(c1, d0)) {
        return Err(err(
            first,
            format!("the crossing curve's zone needs the two edges just beyond the crossing's neighbours to have the same knot interval as the edges at the crossing (Lemma 1, second-edge condition): got {c0}, {d0}, {d1}, {c1}"),
        ));
    }
    Ok(())
}

/// The group's two lines are at least [`MIN_LINE_ANGLE`] apart.
fn check_angle(
    curves: &[CubicCurve],
    middles: &[MiddlePolygon],
    lines: &[Vec<Arm>; 2],
) -> Result<(), InterpolateError> {
    let (u, v) = (
        arm_dir(middles, lines[0][0], 1),
        arm_dir(middles, lines[1][0], 1),
    );
    let a = angle_deg(&u, &v);
    let apart = a.min(180.0 - a);
    // Rounding of the angle's cosine must not refuse lines exactly MIN_LINE_ANGLE apart.
    if apart >= MIN_LINE_ANGLE - 1e-9 {
        return Ok(());
    }
    let names: Vec<String> = lines
        .iter()
        .flatten()
        .map(|&arm| describe(curves, middles, arm))
        .collect();
    // For two ending curves, also the angle between their last edges.
    let ends = match (lines[0].as_slice(), lines[1].as_slice()) {
        ([a], [b]) => match (end_side(curves, middles, *a), end_side(curves, middles, *b)) {
            (Some(sa), Some(sb)) => format!(
                ", their last edges {:.1}° apart",
                angle_deg(&arm_dir(middles, *a, sa), &arm_dir(middles, *b, sb))
            ),
            _ => String::new(),
        },
        _ => String::new(),
    };
    let b = lines[1][0];
    Err(crossing_error(
        &curves[b.curve],
        &middles[b.curve],
        b.index,
        format!(
            "{}: the control polygons meet at {apart:.1}°{ends}; a joint polygon group needs its two lines at least {MIN_LINE_ANGLE}° apart (closer, its quads are slivers and the limit surface folds)",
            names.join(", ")
        ),
    ))
}

/// Every curve of the group has one weight at the point and its neighbours (the group is
/// symmetric in homogeneous coordinates only then).
fn check_weights(
    curves: &[CubicCurve],
    middles: &[MiddlePolygon],
    lines: &[Vec<Arm>; 2],
) -> Result<(), InterpolateError> {
    let first = lines[0][0];
    let wx = middles[first.curve].weights[first.index];
    for &arm in lines.iter().flatten() {
        let m = &middles[arm.curve];
        for s in -1..=1 {
            let w = neighbour(m, arm.index, s).map_or(wx, |j| m.weights[j]);
            if (w - wx).abs() > 1e-12 * wx {
                return Err(crossing_error(
                    &curves[arm.curve],
                    m,
                    arm.index,
                    "the weights of both curves at the crossing point and its neighbours must be equal (a joint polygon group is symmetric in homogeneous coordinates)".into(),
                ));
            }
        }
    }
    Ok(())
}

/// Control-polygon edges of different curves that pass within `tol` of each other away from
/// shared control points; the first such pair in the order (curve, other curve, edge, other
/// edge). Edges are entered in a hash grid ([`super::grid`]) of cells as long as the mean
/// edge, and only edges of different curves sharing a cell are compared.
fn check_unshared(curves: &[CubicCurve], tol: f64, work: &mut u64) -> Result<(), InterpolateError> {
    // (curve, edge, p0, p1) of every polygon edge, curve by curve.
    let mut segs: Vec<(usize, usize, V3, V3)> = Vec::new();
    for (c, curve) in curves.iter().enumerate() {
        let n = curve.len();
        let m = if curve.closed { n } else { n - 1 };
        segs.extend((0..m).map(|i| (c, i, curve.points[i], curve.points[(i + 1) % n])));
    }
    if curves.len() < 2 || segs.is_empty() {
        return Ok(());
    }
    let mean = segs.iter().map(|s| norm(&sub(&s.3, &s.2))).sum::<f64>() / segs.len() as f64;
    let cell = if mean.is_finite() && mean > 0.0 {
        mean.max(8.0 * tol)
    } else {
        (8.0 * tol).max(1.0)
    };
    let mut grid = Grid::new(cell, lower_corner(segs.iter().map(|s| &s.2)));
    for (id, s) in segs.iter().enumerate() {
        *work += grid.insert_segment(&s.2, &s.3, id as u32);
    }
    let mut tested: HashSet<(u32, u32)> = HashSet::new();
    let mut first: Option<(usize, usize, usize, usize, V3)> = None;
    for ids in grid.cells() {
        // Ids are ascending, so one curve's edges are consecutive.
        for (k, &s) in ids.iter().enumerate() {
            let (ca, ia, p0, p1) = segs[s as usize];
            let others = ids[k + 1..]
                .iter()
                .skip_while(|&&t| segs[t as usize].0 == ca);
            for &t in others {
                *work += 1;
                if !tested.insert((s, t)) {
                    continue;
                }
                let (cb, ib, q0, q1) = segs[t as usize];
                let shared = [p0, p1]
                    .iter()
                    .any(|p| [q0, q1].iter().any(|q| norm(&sub(p, q)) <= tol));
                if shared {
                    continue;
                }
                if let Some(x) = segments_meet(&p0, &p1, &q0, &q1, tol) {
                    let key = (ca, cb, ia, ib, x);
                    if first.is_none_or(|f| (ca, cb, ia, ib) < (f.0, f.1, f.2, f.3)) {
                        first = Some(key);
                    }
                }
            }
        }
    }
    match first {
        Some((a, b, edge_a, edge_b, x)) => Err(InterpolateError::UnsharedCrossing {
            a: curves[a].label.clone(),
            edge_a,
            b: curves[b].label.clone(),
            edge_b,
            x: x[0],
            y: x[1],
            z: x[2],
        }),
        None => Ok(()),
    }
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
