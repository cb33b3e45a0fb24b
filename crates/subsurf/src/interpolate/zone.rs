//! The symmetric zonal mesh: one column of three points `(P_i + o_i, P_i, P_i − o_i)` per
//! middle-polygon point and two quads per middle-polygon edge, with the knot intervals and
//! weights of seed 001's Theorem 1.
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
//!   it (any `e > 0` interpolates); at a crossing, the other curve's interval there.
//! - *The second edge at a column's outer end*: the zone's sides are the mesh boundary, where
//!   NURSS reads the mirror image across the boundary (see [`crate::refine::nurss`]): both
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

use super::crossing::{edge_interval, neighbour, Crossing};
use super::frame::{angle_about, rotate, side_directions, tangents};
use super::{CubicCurve, InterpolateError, MiddlePolygon, Zone};
use crate::geom::{norm, sub, V3};
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

/// Side offsets and vertex ids forced at a column by a crossing.
#[derive(Clone, Copy)]
struct Forced {
    top: u32,
    bot: u32,
}

/// Builds the zones of all curves, sharing the joint polygon groups of `crossings`.
pub(crate) fn build(
    curves: &[CubicCurve],
    middles: &[MiddlePolygon],
    crossings: &[Crossing],
    width: f64,
    side: Option<V3>,
) -> Result<(PolyMesh, Vec<Zone>), InterpolateError> {
    let mut b = Builder::default();
    // Middle points (shared at crossings).
    let mut mid: Vec<Vec<u32>> = middles
        .iter()
        .map(|m| {
            m.points
                .iter()
                .zip(&m.weights)
                .map(|(&p, &w)| b.vertex(p, w))
                .collect()
        })
        .collect();
    for x in crossings {
        mid[x.b.curve][x.b.index] = mid[x.a.curve][x.a.index];
    }
    // Forced columns and column intervals.
    let mut forced: Vec<Vec<Option<Forced>>> =
        middles.iter().map(|m| vec![None; m.len()]).collect();
    let mut column_interval: Vec<Option<f64>> = vec![None; curves.len()];
    for x in crossings {
        let (a, bb) = (x.a, x.b);
        let (ma, mb) = (&middles[a.curve], &middles[bb.curve]);
        let (Some(ka0), Some(ka1)) = (neighbour(ma, a.index, -1), neighbour(ma, a.index, 1)) else {
            continue;
        };
        let (Some(lb0), Some(lb1)) = (neighbour(mb, bb.index, -1), neighbour(mb, bb.index, 1))
        else {
            continue;
        };
        let xp = ma.points[a.index];
        let av = sub(&ma.points[ka1], &xp);
        let bv = sub(&mb.points[lb1], &xp);
        let w = ma.weights[a.index];
        let corner = |b: &mut Builder, sa: f64, sb: f64| {
            b.vertex(
                [
                    xp[0] + sa * av[0] + sb * bv[0],
                    xp[1] + sa * av[1] + sb * bv[1],
                    xp[2] + sa * av[2] + sb * bv[2],
                ],
                w,
            )
        };
        let (cpp, cpm, cmp, cmm) = (
            corner(&mut b, 1.0, 1.0),
            corner(&mut b, 1.0, -1.0),
            corner(&mut b, -1.0, 1.0),
            corner(&mut b, -1.0, -1.0),
        );
        let (xa0, xa1) = (mid[a.curve][ka0], mid[a.curve][ka1]);
        let (xb0, xb1) = (mid[bb.curve][lb0], mid[bb.curve][lb1]);
        let set = |forced: &mut Vec<Vec<Option<Forced>>>, c: usize, j: usize, f: Forced| {
            if forced[c][j].is_some() {
                let m = &middles[c];
                let p = m.points[j];
                return Err(InterpolateError::Crossing {
                    curve: curves[c].label.clone(),
                    index: j.saturating_sub(m.first),
                    x: p[0],
                    y: p[1],
                    z: p[2],
                    reason: "the control point is next to two crossings; leave at least two control points between crossings".into(),
                });
            }
            forced[c][j] = Some(f);
            Ok(())
        };
        // A's columns: offset +b on top.
        set(&mut forced, a.curve, ka0, Forced { top: cmp, bot: cmm })?;
        set(&mut forced, a.curve, a.index, Forced { top: xb1, bot: xb0 })?;
        set(&mut forced, a.curve, ka1, Forced { top: cpp, bot: cpm })?;
        // B's columns: offset −a on top.
        set(&mut forced, bb.curve, lb0, Forced { top: cmm, bot: cpm })?;
        set(
            &mut forced,
            bb.curve,
            bb.index,
            Forced { top: xa0, bot: xa1 },
        )?;
        set(&mut forced, bb.curve, lb1, Forced { top: cmp, bot: cpp })?;
        for (c, other, arm) in [(a.curve, mb, bb), (bb.curve, ma, a)] {
            let e = edge_interval(other, arm.index, 1);
            match column_interval[c] {
                Some(old) if (old - e).abs() > 1e-12 * old.abs().max(e.abs()) => {
                    let m = &middles[c];
                    let p = other.points[arm.index];
                    return Err(InterpolateError::Crossing {
                        curve: curves[c].label.clone(),
                        index: (if c == a.curve { a.index } else { bb.index })
                            .saturating_sub(m.first),
                        x: p[0],
                        y: p[1],
                        z: p[2],
                        reason: format!(
                            "all column edges of a zone need one knot interval (Theorem 1), but the curves it crosses have intervals {old} and {e} at their crossings"
                        ),
                    });
                }
                _ => column_interval[c] = Some(e),
            }
        }
    }
    let mut zones = Vec::with_capacity(curves.len());
    for (c, m) in middles.iter().enumerate() {
        let label = &curves[c].label;
        let bad = |reason: String| InterpolateError::BadCurve {
            curve: label.clone(),
            reason,
        };
        let tan = tangents(&m.points, m.closed)
            .ok_or_else(|| bad("all control points coincide".into()))?;
        let u = side_directions(&m.points, &tan, m.closed, side).map_err(|i| {
            let what = if i < m.first || i >= m.first + curves[c].len() {
                "the phantom point beyond the curve's end".to_string()
            } else {
                format!("control point {}", i - m.first)
            };
            bad(format!(
                "the side vector is parallel to the curve's tangent at {what}"
            ))
        })?;
        let size = curve_size(&curves[c].points);
        let w_abs = width * size;
        // Angle and width at forced columns, interpolated between them.
        let n = m.len();
        let mut anchors: Vec<(usize, f64, f64)> = Vec::new();
        for j in 0..n {
            if let Some(f) = forced[c][j] {
                let o = sub(&b.positions[f.top as usize], &m.points[j]);
                let d = crate::geom::dot(&o, &tan[j]);
                let perp = [
                    o[0] - d * tan[j][0],
                    o[1] - d * tan[j][1],
                    o[2] - d * tan[j][2],
                ];
                anchors.push((j, angle_about(&u[j], &perp, &tan[j]), norm(&o)));
            }
        }
        let mut top = Vec::with_capacity(n);
        let mut bot = Vec::with_capacity(n);
        for j in 0..n {
            if let Some(f) = forced[c][j] {
                top.push(f.top);
                bot.push(f.bot);
                continue;
            }
            let (phi, wj) = blend(&anchors, j, n, m.closed, w_abs);
            let o = rotate(&u[j], &tan[j], phi);
            let p = m.points[j];
            let wt = m.weights[j];
            top.push(b.vertex([p[0] + wj * o[0], p[1] + wj * o[1], p[2] + wj * o[2]], wt));
            bot.push(b.vertex([p[0] - wj * o[0], p[1] - wj * o[1], p[2] - wj * o[2]], wt));
        }
        let e = column_interval[c].unwrap_or_else(|| {
            let len: f64 = (0..m.num_edges())
                .map(|i| norm(&sub(&m.points[(i + 1) % n], &m.points[i])))
                .sum();
            let par: f64 = m.intervals.iter().sum();
            if len > 0.0 && par > 0.0 {
                w_abs * par / len
            } else {
                1.0
            }
        });
        let ids = &mid[c];
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
            label: label.clone(),
            middle: ids.clone(),
            closed: m.closed,
            start_knot: m.start_knot,
            first: m.first,
            count: curves[c].len(),
            knot_scale: 1.0,
        });
    }
    Ok((b.finish()?, zones))
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

/// Rotation angle and width at column `j`: linear in the column index between the nearest
/// forced columns (constant beyond the outermost ones; around a closed polygon, cyclically).
fn blend(anchors: &[(usize, f64, f64)], j: usize, n: usize, closed: bool, w: f64) -> (f64, f64) {
    if anchors.is_empty() {
        return (0.0, w);
    }
    let dist = |from: usize, to: usize| -> Option<usize> {
        if to >= from {
            Some(to - from)
        } else if closed {
            Some(to + n - from)
        } else {
            None
        }
    };
    // Nearest anchor before (distance from it to j) and after (from j to it).
    let prev = anchors
        .iter()
        .filter_map(|a| dist(a.0, j).map(|d| (d, a)))
        .min_by_key(|x| x.0);
    let next = anchors
        .iter()
        .filter_map(|a| dist(j, a.0).map(|d| (d, a)))
        .min_by_key(|x| x.0);
    match (prev, next) {
        (Some((dp, a)), Some((dn, b))) if dp + dn > 0 => {
            let t = dp as f64 / (dp + dn) as f64;
            let mut delta = b.1 - a.1;
            while delta > std::f64::consts::PI {
                delta -= 2.0 * std::f64::consts::PI;
            }
            while delta < -std::f64::consts::PI {
                delta += 2.0 * std::f64::consts::PI;
            }
            (a.1 + t * delta, a.2 + t * (b.2 - a.2))
        }
        (Some((_, a)), _) | (None, Some((_, a))) => (a.1, a.2),
        (None, None) => (0.0, w),
    }
}
