//! The symmetric zonal mesh: one column of three points `(P_i + o_i, P_i, P_i − o_i)` per
//! middle-polygon point and two quads per middle-polygon edge, with the knot intervals and
//! weights of [JOS 2003]'s Theorem 1. Points shared by zones (joint polygon groups, joins) are
//! one mesh vertex each, made once.
//!
//! # The conditions of Lemma 1 / Theorem 1, and how they are met
//! - *Symmetric polygon pairs*: the side points of each column are symmetric about the
//!   middle point, `T_i + B_i = 2 P_i`, in homogeneous coordinates too: a side point gets
//!   the weight of its middle point, so `w T_i + w B_i = 2 w P_i` (a rational curve's zone is
//!   symmetric exactly when this holds; then the middle polygon refines in homogeneous
//!   coordinates by the curve rules and the limit is the rational curve — a circle stays a
//!   circle).
//! - *Edges parallel to the middle polygon* (`T_i T_{i+1}`, `B_i B_{i+1}`) carry the middle
//!   edge's interval `d_i`.
//! - *Column edges* (`P_i T_i`, `P_i B_i`) all carry one interval `e` per zone: by default
//!   `e = W · Σ d_i / Σ |P_{i+1} − P_i|`, the same parameter speed across the zone as along
//!   it (any `e > 0` interpolates); at a joint polygon group, the other line's interval
//!   there; joined zones ([`super::crossing`]) share theirs.
//! - *Side offsets* `o_i` may point anywhere off the polygon: away from groups a
//!   rotation-minimising frame ([`super::frame`]); near a group the group's sheared offsets,
//!   kept (not turned across the polygon) so that the zones do not fold.
//! - *The second edge at a column's outer end*: the zone's sides are the mesh boundary, where
//!   NURSS reads the mirror image across the boundary (see `refine::nurss`): both
//!   sides of a column read the same values, so the condition holds.
//!
//! # Boundary: NURSS boundary rules, not skirt removal
//! The zone's border is an ordinary NURSS boundary (sharp B-spline curve rules, intervals
//! mirrored across it). The paper instead computes no new points on the zone's boundary
//! (skirt removal, [`crate::blend::skirt`]). Both keep the middle polygon exact, for the same reason: a middle point's
//! new position reads only its 1-ring and the intervals two steps around its neighbours, and
//! the boundary rules are mirror-symmetric across the middle polygon, so every refined zone is
//! again symmetric (`T' + B' = 2 P'`: the side rows refine by the same linear curve rules with
//! the same intervals as the middle row). Keeping the boundary keeps the whole zone as a
//! surface (the skirt-removed zone loses one ring per step) and needs no change to the
//! scheme; the ends of an open zone are handled by phantom points (see [`super::curve`]).

use super::crossing::{edge_interval, neighbour, Crossings, Group, Join, MIN_LINE_ANGLE};
use super::frame::{angle_about, rotate, side_directions, tangents};
use super::{CubicCurve, InterpolateError, MiddlePolygon, Zone};
use crate::geom::{dot, norm, sub, V3};
use crate::mesh::{EdgeInterval, KnotTags, PolyMesh, VertexWeight};
use std::collections::{HashMap, HashSet};

/// Mesh under construction.
#[derive(Default)]
pub(crate) struct Builder {
    positions: Vec<V3>,
    weights: Vec<f64>,
    faces: Vec<[u32; 4]>,
    face_keys: HashSet<[u32; 4]>,
    intervals: HashMap<(u32, u32), f64>,
}

impl Builder {
    fn vertex(&mut self, p: V3, w: f64) -> u32 {
        self.positions.push(p);
        self.weights.push(w);
        (self.positions.len() - 1) as u32
    }

    fn face(&mut self, f: [u32; 4]) {
        let mut k = f;
        k.sort_unstable();
        if self.face_keys.insert(k) {
            self.faces.push(f);
        }
    }

    fn interval(&mut self, a: u32, b: u32, d: f64) {
        self.intervals.entry((a.min(b), a.max(b))).or_insert(d);
    }

    fn finish(self) -> Result<PolyMesh, InterpolateError> {
        let mut mesh = PolyMesh::from_faces(self.positions, &self.faces)?;
        let mut intervals: Vec<EdgeInterval> = self
            .intervals
            .into_iter()
            .filter(|&(_, d)| d != 1.0)
            .map(|((v0, v1), interval)| EdgeInterval { v0, v1, interval })
            .collect();
        intervals.sort_by_key(|t| (t.v0, t.v1));
        let weights = VertexWeight::tags(&self.weights);
        mesh.knots = KnotTags {
            intervals,
            side_intervals: Vec::new(),
            weights,
        };
        Ok(mesh)
    }
}

/// Side vertices forced at a column by a group or a join.
#[derive(Clone, Copy)]
struct Forced {
    top: u32,
    bot: u32,
}

/// The zones under construction: mesh vertices of the middle polygons (`None` until made),
/// forced columns, and the column interval each curve must take.
struct Layout<'a> {
    curves: &'a [CubicCurve],
    middles: &'a [MiddlePolygon],
    mid: Vec<Vec<Option<u32>>>,
    forced: Vec<Vec<Option<Forced>>>,
    column: Vec<Option<f64>>,
}

impl Layout<'_> {
    fn error(&self, c: usize, j: usize, reason: String) -> InterpolateError {
        let m = &self.middles[c];
        let p = m.points[j];
        InterpolateError::Crossing {
            curve: self.curves[c].label.clone(),
            index: j.saturating_sub(m.first).min(self.curves[c].len() - 1),
            x: p[0],
            y: p[1],
            z: p[2],
            reason,
        }
    }

    fn near_two(&self, c: usize, j: usize) -> InterpolateError {
        self.error(
            c,
            j,
            "the control point is next to two crossings; leave at least two control points between crossings".into(),
        )
    }

    /// Middle point `j` of curve `c` is mesh vertex `v`.
    fn set_mid(&mut self, c: usize, j: usize, v: u32) -> Result<(), InterpolateError> {
        match self.mid[c][j] {
            Some(old) if old != v => Err(self.near_two(c, j)),
            _ => {
                self.mid[c][j] = Some(v);
                Ok(())
            }
        }
    }

    fn set_forced(&mut self, c: usize, j: usize, f: Forced) -> Result<(), InterpolateError> {
        if self.forced[c][j].is_some() {
            return Err(self.near_two(c, j));
        }
        self.forced[c][j] = Some(f);
        Ok(())
    }

    fn set_column(&mut self, c: usize, j: usize, e: f64) -> Result<(), InterpolateError> {
        match self.column[c] {
            Some(old) if (old - e).abs() > 1e-12 * old.abs().max(e.abs()) => Err(self.error(
                c,
                j,
                format!("all column edges of a zone need one knot interval (Theorem 1), but the curves it crosses have intervals {old} and {e} at their crossings"),
            )),
            _ => {
                self.column[c] = Some(e);
                Ok(())
            }
        }
    }
}

/// Lays out one joint polygon group (see [`super::crossing`]): its centre, the points of
/// its two lines, its four corners, every curve's three columns there and column interval.
fn lay_group(b: &mut Builder, l: &mut Layout<'_>, g: &Group) -> Result<(), InterpolateError> {
    let m0 = &l.middles[g.lines[0][0].curve];
    let xp = m0.points[g.lines[0][0].index];
    let wx = m0.weights[g.lines[0][0].index];
    let x = b.vertex(xp, wx);
    // Per line: direction, the points at ±direction, the interval at the centre.
    let mut dirs = [[0.0; 3]; 2];
    let mut ends = [[0u32; 2]; 2];
    let mut at = [0.0; 2];
    for (k, line) in g.lines.iter().enumerate() {
        let r = line[0];
        let m = &l.middles[r.curve];
        let Some(next) = neighbour(m, r.index, 1) else {
            return Err(l.error(r.curve, r.index, "no neighbour on one side".into()));
        };
        dirs[k] = sub(&m.points[next], &xp);
        at[k] = edge_interval(m, r.index, 1);
        for (e, s) in [(0usize, -1.0), (1, 1.0)] {
            // The line's point at s · direction: a control point of a curve when one has
            // it, else the phantom of the first curve.
            let mut best: Option<(V3, f64)> = None;
            for &a in line {
                let ma = &l.middles[a.curve];
                let sigma = sign(&sub(&arm_next(ma, a.index), &xp), &dirs[k]);
                if let Some(j) = neighbour(ma, a.index, (s * sigma) as isize) {
                    let real = j >= ma.first && j < ma.first + l.curves[a.curve].len();
                    if real || best.is_none() {
                        best = Some((ma.points[j], ma.weights[j]));
                    }
                }
            }
            let (p, w) = best.unwrap_or((xp, wx));
            ends[k][e] = b.vertex(p, w);
        }
    }
    let (u, v) = (dirs[0], dirs[1]);
    let mut corner = [[0u32; 2]; 2];
    for (i, su) in [-1.0, 1.0].iter().enumerate() {
        for (k, sv) in [-1.0, 1.0].iter().enumerate() {
            corner[i][k] = b.vertex([0, 1, 2].map(|c| xp[c] + su * u[c] + sv * v[c]), wx);
        }
    }
    // corner(s, t) = X + s u + t v; end(line, s) = X + s · direction.
    let cr = |s: f64, t: f64| corner[usize::from(s > 0.0)][usize::from(t > 0.0)];
    let end = |k: usize, s: f64| ends[k][usize::from(s > 0.0)];
    for (k, line) in g.lines.iter().enumerate() {
        for &a in line {
            let ma = &l.middles[a.curve];
            let s = sign(&sub(&arm_next(ma, a.index), &xp), &dirs[k]);
            let (Some(prev), Some(next)) = (neighbour(ma, a.index, -1), neighbour(ma, a.index, 1))
            else {
                return Err(l.error(a.curve, a.index, "no neighbour on one side".into()));
            };
            l.set_mid(a.curve, a.index, x)?;
            l.set_mid(a.curve, prev, end(k, -s))?;
            l.set_mid(a.curve, next, end(k, s))?;
            // Line 0: side points offset s·v on top; line 1: −s·u (module docs of crossing).
            let (columns, top_at_x, bot_at_x) = if k == 0 {
                (
                    [(prev, cr(-s, s), cr(-s, -s)), (next, cr(s, s), cr(s, -s))],
                    end(1, s),
                    end(1, -s),
                )
            } else {
                (
                    [(prev, cr(-s, -s), cr(s, -s)), (next, cr(-s, s), cr(s, s))],
                    end(0, -s),
                    end(0, s),
                )
            };
            for (j, top, bot) in columns {
                l.set_forced(a.curve, j, Forced { top, bot })?;
            }
            let f = Forced {
                top: top_at_x,
                bot: bot_at_x,
            };
            l.set_forced(a.curve, a.index, f)?;
            l.set_column(a.curve, a.index, at[1 - k])?;
        }
    }
    Ok(())
}

/// The middle point after `j` (itself at an open end).
fn arm_next(m: &MiddlePolygon, j: usize) -> V3 {
    m.points[neighbour(m, j, 1).unwrap_or(j)]
}

/// `+1` when `a` points along `d`, else `−1`.
fn sign(a: &V3, d: &V3) -> f64 {
    if dot(a, d) >= 0.0 {
        1.0
    } else {
        -1.0
    }
}

/// Shares the middle points of a join (see [`super::crossing`]): the common end point, and
/// each curve's phantom as the other's neighbour. Returns, for curve `a`'s middle indices
/// around the point, the matching indices of `b` and whether `b` runs the other way.
fn lay_join(
    b: &mut Builder,
    l: &mut Layout<'_>,
    jn: &Join,
) -> Result<([usize; 3], [usize; 3], bool), InterpolateError> {
    let (ma, mb) = (&l.middles[jn.a.curve], &l.middles[jn.b.curve]);
    let (a, bb) = (jn.a, jn.b);
    let around = |m: &MiddlePolygon, j: usize| match (neighbour(m, j, -1), neighbour(m, j, 1)) {
        (Some(p), Some(n)) => Some([p, j, n]),
        _ => None,
    };
    let (Some(ia), Some(ib)) = (around(ma, a.index), around(mb, bb.index)) else {
        return Err(l.error(a.curve, a.index, "no neighbour on one side".into()));
    };
    let x = ma.points[a.index];
    // b runs with a when b's next point is a's next point.
    let same_way = dot(
        &sub(&arm_next(ma, a.index), &x),
        &sub(&arm_next(mb, bb.index), &x),
    ) > 0.0;
    let ib = if same_way { ib } else { [ib[2], ib[1], ib[0]] };
    for k in 0..3 {
        // A control point of either curve (the other's phantom is there).
        let real_a = ia[k] >= ma.first && ia[k] < ma.first + l.curves[a.curve].len();
        let (p, w) = if real_a {
            (ma.points[ia[k]], ma.weights[ia[k]])
        } else {
            (mb.points[ib[k]], mb.weights[ib[k]])
        };
        let v = b.vertex(p, w);
        l.set_mid(a.curve, ia[k], v)?;
        l.set_mid(bb.curve, ib[k], v)?;
    }
    Ok((ia, ib, !same_way))
}

/// A join's columns: curve `a`'s zone gives its three columns around the shared point
/// (middle indices `ia`) to curve `other` (indices `ib`, top and bottom swapped when `other`
/// runs the other way).
#[derive(Clone, Copy)]
struct JoinedColumns {
    other: usize,
    ia: [usize; 3],
    ib: [usize; 3],
    reversed: bool,
}

/// Union-find root of curve `c` (curves that share their column interval).
fn find(root: &mut [usize], c: usize) -> usize {
    let mut r = c;
    while root[r] != r {
        r = root[r];
    }
    root[c] = r;
    r
}

/// Builds the zones of all curves, sharing the joint polygon groups and joins of `cr`;
/// `work` counts the columns and anchors visited.
pub(crate) fn build(
    curves: &[CubicCurve],
    cr: &Crossings,
    width: f64,
    side: Option<V3>,
    work: &mut u64,
) -> Result<(PolyMesh, Vec<Zone>), InterpolateError> {
    let middles = &cr.middles;
    let mut b = Builder::default();
    let mut l = Layout {
        curves,
        middles,
        mid: middles.iter().map(|m| vec![None; m.len()]).collect(),
        forced: middles.iter().map(|m| vec![None; m.len()]).collect(),
        column: vec![None; curves.len()],
    };
    for g in &cr.groups {
        lay_group(&mut b, &mut l, g)?;
    }
    // Joined curves share their column interval.
    let mut root: Vec<usize> = (0..curves.len()).collect();
    let mut joined: Vec<Vec<JoinedColumns>> = vec![Vec::new(); curves.len()];
    for jn in &cr.joins {
        let (ia, ib, reversed) = lay_join(&mut b, &mut l, jn)?;
        joined[jn.a.curve].push(JoinedColumns {
            other: jn.b.curve,
            ia,
            ib,
            reversed,
        });
        let (ra, rb) = (find(&mut root, jn.a.curve), find(&mut root, jn.b.curve));
        root[ra.max(rb)] = ra.min(rb);
    }
    for c in 0..curves.len() {
        let r = find(&mut root, c);
        if let Some(e) = l.column[c] {
            l.set_column(r, middles[c].first, e)?;
        }
    }
    for (c, m) in middles.iter().enumerate() {
        for j in 0..m.len() {
            if l.mid[c][j].is_none() {
                l.mid[c][j] = Some(b.vertex(m.points[j], m.weights[j]));
            }
        }
    }
    let mut zones = Vec::with_capacity(curves.len());
    for c in 0..middles.len() {
        let ids: Vec<u32> = l.mid[c].iter().map(|v| v.unwrap_or(0)).collect();
        let w_abs = width * curve_size(&curves[c].points);
        let (top, bot) = lay_columns(&mut b, &l, c, &ids, side, w_abs, work)?;
        for jc in &joined[c] {
            for k in 0..3 {
                let (t, bo) = (top[jc.ia[k]], bot[jc.ia[k]]);
                let f = if jc.reversed {
                    Forced { top: bo, bot: t }
                } else {
                    Forced { top: t, bot: bo }
                };
                l.set_forced(jc.other, jc.ib[k], f)?;
            }
        }
        let r = find(&mut root, c);
        let m = &middles[c];
        let e = *l.column[r].get_or_insert_with(|| {
            let pts: Vec<V3> = ids.iter().map(|&v| b.positions[v as usize]).collect();
            default_column_interval(&pts, m, w_abs)
        });
        let n = m.len();
        for i in 0..m.num_edges() {
            let j = (i + 1) % n;
            b.face([ids[i], ids[j], top[j], top[i]]);
            b.face([ids[i], bot[i], bot[j], ids[j]]);
            let d = m.intervals[i];
            b.interval(ids[i], ids[j], d);
            b.interval(top[i], top[j], d);
            b.interval(bot[i], bot[j], d);
        }
        for j in 0..n {
            b.interval(ids[j], top[j], e);
            b.interval(ids[j], bot[j], e);
        }
        zones.push(Zone {
            label: curves[c].label.clone(),
            middle: ids,
            closed: m.closed,
            start_knot: m.start_knot,
            first: m.first,
            count: curves[c].len(),
            knot_scale: 1.0,
        });
    }
    Ok((b.finish()?, zones))
}

/// The top and bottom side vertices of every column of curve `c`'s zone (middle vertices
/// `ids`): the forced ones, and new ones at the [`side_offsets`] of the others.
fn lay_columns(
    b: &mut Builder,
    l: &Layout<'_>,
    c: usize,
    ids: &[u32],
    side: Option<V3>,
    w_abs: f64,
    work: &mut u64,
) -> Result<(Vec<u32>, Vec<u32>), InterpolateError> {
    let m = &l.middles[c];
    let curve = &l.curves[c];
    let bad = |reason: String| InterpolateError::BadCurve {
        curve: curve.label.clone(),
        reason,
    };
    let pts: Vec<V3> = ids.iter().map(|&v| b.positions[v as usize]).collect();
    let tan = tangents(&pts, m.closed).ok_or_else(|| bad("all control points coincide".into()))?;
    let u = side_directions(&pts, &tan, m.closed, side).map_err(|i| {
        let what = if i < m.first || i >= m.first + curve.len() {
            "the phantom point beyond the curve's end".to_string()
        } else {
            format!("control point {}", i - m.first)
        };
        bad(format!(
            "the side vector is parallel to the curve's tangent at {what}"
        ))
    })?;
    let anchors: Vec<Anchor> = (0..m.len())
        .filter_map(|j| {
            let f = l.forced[c][j]?;
            let o = sub(&b.positions[f.top as usize], &pts[j]);
            let along = dot(&o, &tan[j]);
            let perp = [0, 1, 2].map(|k| o[k] - along * tan[j][k]);
            Some(Anchor {
                j,
                angle: angle_about(&u[j], &perp, &tan[j]),
                len: norm(&o),
                along,
            })
        })
        .collect();
    let offsets = side_offsets(&tan, &u, &anchors, m.closed, w_abs, work);
    let mut top = Vec::with_capacity(m.len());
    let mut bot = Vec::with_capacity(m.len());
    for (j, o) in offsets.iter().enumerate() {
        if let Some(f) = l.forced[c][j] {
            top.push(f.top);
            bot.push(f.bot);
            continue;
        }
        let (p, wt) = (pts[j], m.weights[j]);
        top.push(b.vertex([0, 1, 2].map(|k| p[k] + o[k]), wt));
        bot.push(b.vertex([0, 1, 2].map(|k| p[k] - o[k]), wt));
    }
    Ok((top, bot))
}

/// The column interval of a zone not constrained by a group: `W · Σ d_i / Σ |P_{i+1} − P_i|`,
/// the same parameter speed across the zone as along it (1 for a degenerate polygon).
fn default_column_interval(pts: &[V3], m: &MiddlePolygon, w_abs: f64) -> f64 {
    let n = pts.len();
    let len: f64 = (0..m.num_edges())
        .map(|i| norm(&sub(&pts[(i + 1) % n], &pts[i])))
        .sum();
    let par: f64 = m.intervals.iter().sum();
    if len > 0.0 && par > 0.0 {
        w_abs * par / len
    } else {
        1.0
    }
}

/// A column whose side points are given: its index, and its offset `o` (top minus middle
/// point) as the angle of `o`'s part across the polygon about the tangent (from the frame's
/// `u_j`), `|o|`, and `o`'s part along the tangent.
#[derive(Clone, Copy, Debug)]
struct Anchor {
    j: usize,
    angle: f64,
    len: f64,
    along: f64,
}

/// The side offset `o_j` of every column (`P_j ± o_j`): without anchors `w · u_j`; else
/// interpolated between the nearest anchors before and after (linearly in the column index;
/// around a closed polygon cyclically; beyond the outermost anchors of an open one, the
/// nearest): the angle about the tangent, the shear `o · t / |o|` (kept at most
/// `cos MIN_LINE_ANGLE`, so the offset stays that far off the tangent) and `|o|`, whose
/// excess over `w` is halved at every column away from an anchor (a group's offsets are the
/// other line's edges, often far wider than the zone: kept wide, a bending zone folded, e.g.
/// ends 40° apart whose edges differ 2:1).
///
/// A group's columns are sheared: their side points `X ± u ± v` lie along the other line,
/// not across their own. Free columns keep that shear rather than turning the offset across
/// the polygon at the next column: then a zone near a straight arm is the strip of the
/// group's parallelograms (`X + s u + t v`, `s ≥ 1`, `0 ≤ t ≤ 1`), which the zones of the
/// other line (`t ≥ 1`, `0 ≤ s ≤ 1`) do not overlap at any angle between the lines (nor when it
/// narrows, `0 ≤ t ≤ λ ≤ 1`); turned
/// across, the zones of two lines overlap in the acute wedge between them and a zone whose
/// side points jump from along to across folds (measured at level 4: crossings at 45°, and
/// ends 60°–175° apart with unequal edge lengths, had 5–43 flipped face pairs; kept, none
/// from 30° on). Theorem 1 needs only `T_j + B_j = 2 P_j`, any offset direction. Linear in
/// the columns: the nearest anchors come from one sweep each way; `work` counts the columns
/// visited.
fn side_offsets(
    tan: &[V3],
    u: &[V3],
    anchors: &[Anchor],
    closed: bool,
    w: f64,
    work: &mut u64,
) -> Vec<V3> {
    let n = tan.len();
    *work += 2 * n as u64 + anchors.len() as u64;
    if anchors.is_empty() {
        return u.iter().map(|d| d.map(|x| w * x)).collect();
    }
    let mut at: Vec<Option<usize>> = vec![None; n];
    for (i, a) in anchors.iter().enumerate() {
        at[a.j] = Some(i);
    }
    // Nearest anchor at or before / at or after each column (cyclic when closed).
    let mut before: Vec<Option<usize>> = vec![None; n];
    let mut cur = if closed {
        anchors.len().checked_sub(1)
    } else {
        None
    };
    for j in 0..n {
        cur = at[j].or(cur);
        before[j] = cur;
    }
    let mut after: Vec<Option<usize>> = vec![None; n];
    let mut cur = if closed { Some(0) } else { None };
    for j in (0..n).rev() {
        cur = at[j].or(cur);
        after[j] = cur;
    }
    // Columns from column `from` forward to column `to`.
    let forward = |from: usize, to: usize| if to >= from { to - from } else { to + n - from };
    let max_along = MIN_LINE_ANGLE.to_radians().cos();
    // |o| `k` columns away from anchor `a`: its excess over `w` halved at every column.
    let shrink = |a: &Anchor, k: usize| {
        if a.len > w {
            w + (a.len - w) * 0.5f64.powi(k.min(1000) as i32)
        } else {
            a.len
        }
    };
    let shear = |a: &Anchor| if a.len > 0.0 { a.along / a.len } else { 0.0 };
    (0..n)
        .map(|j| {
            let (angle, len, ratio) = match (before[j], after[j]) {
                (Some(p), Some(q)) if p != q || anchors[p].j != j => {
                    let (a, bq) = (&anchors[p], &anchors[q]);
                    let (cp, cq) = (forward(a.j, j), forward(j, bq.j));
                    let t = cp as f64 / (cp + cq).max(1) as f64;
                    let mut delta = bq.angle - a.angle;
                    delta -= std::f64::consts::TAU * (delta / std::f64::consts::TAU).round();
                    let len = (a.len + t * (bq.len - a.len)).min(shrink(a, cp).max(shrink(bq, cq)));
                    let ratio = shear(a) + t * (shear(bq) - shear(a));
                    (a.angle + t * delta, len, ratio)
                }
                (Some(p), _) | (None, Some(p)) => {
                    let a = &anchors[p];
                    (a.angle, shrink(a, a.j.abs_diff(j)), shear(a))
                }
                (None, None) => (0.0, w, 0.0),
            };
            let along = ratio * len;
            let along = along.clamp(-max_along * len, max_along * len);
            let across = (len * len - along * along).max(0.0).sqrt();
            let r = rotate(&u[j], &tan[j], angle);
            [0, 1, 2].map(|k| along * tan[j][k] + across * r[k])
        })
        .collect()
}

/// Diagonal of the bounding box of `points` (1 when they all coincide).
pub(crate) fn curve_size(points: &[V3]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let d = norm(&sub(&hi, &lo));
    if d > 0.0 && d.is_finite() {
        d
    } else {
        1.0
    }
}
