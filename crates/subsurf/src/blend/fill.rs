//! N-sided hole filling with a corner-interpolating NURSS surface (seed 002 §3.2,
//! Algorithm 1).
//!
//! # Input
//! N = 3..=8 cubic B-spline boundary curves that meet end to end around the hole (each
//! curve's end is the next one's start, in either direction; they are oriented and chained
//! automatically), or the patches they bound: a patch contributes its first-row boundary
//! curve `S(u_3, v)`, whose control points are `Σ_i N_i(u_3) b_{i,j}`. Every curve is
//! clamped to its domain by knot insertion (so its first and last control points are its
//! ends, the hole's corners) and needs at least 4 control points.
//!
//! # The fill control mesh (Algorithm 1, steps 1–2)
//! The curves are first prepared by [`equalize_end_spans`] (knot insertion and an affine
//! reparametrization: the same point sets, every first and last span 1, at least 6 control
//! points). Then:
//! - Layer 1 (outermost): the curves' control points `p^k_0 … p^k_{M_k}`; `p^k_{M_k}` is
//!   `p^{k+1}_0`, the corner.
//! - Layer 2: one point `q^k_j` opposite each inner control point `p^k_j`
//!   (`j = 1 … M_k − 1`), where the points next to a corner are shared,
//!   `q^k_{M_k−1} = q^{k+1}_1 = Q_{k+1}`, so each corner has one regular corner quad
//!   `(c_k, p^k_1, Q_k, p^{k−1}_{M−1})` and the outer two layers are a regular grid.
//! - Layer 3: one point `r^k_j` opposite each `q^k_j` (`j = 2 … M_k − 2`), shared next to
//!   the corners (`R_k`), with the quad `(Q_k, q^k_2, R_k, q^{k−1}_{M−2})` at each corner:
//!   every non-corner layer-2 vertex is regular with one edge inwards.
//! - The middle, bounded by layer 3: a fan of quads around a centre point when the ring has
//!   an even count of more than 4 points (spokes to every second ring point), one polygon
//!   otherwise. (The paper's Fig. 5 instead adds one point opposite each side middle.)
//!
//! Default positions of the free points: `Q_k = p^k_1 + p^{k−1}_{M−1} − c_k` (completes
//! the corner parallelogram), `q^k_j = p^k_j + (G' − p^k_j) / 3`, `R_k = Q_k + (G' − Q_k) / 3`,
//! `r^k_j = p^k_j + 2 (G' − p^k_j) / 3` and the centre `G'`, with `G' = G + bulge · h · n`:
//! `G` the centroid of the boundary control points, `h` their mean distance from `G`, `n`
//! the unit Newell normal of the boundary control polygon (oriented by the curves'
//! direction). `bulge > 0` makes the fill convex along `n`, `< 0` concave (the paper's
//! Fig. 6 (a)/(b)).
//!
//! Knot intervals: along each side the clamped curve's spans (edge `p_j p_{j+1}` carries
//! `t_{j+3} − t_{j+2}`, so the first and last are 0) and the same on the parallel layer-2 and
//! layer-3 edges; 0 on the cross edges `p^k_j q^k_j` and on every extension edge (the
//! extension layer of [`super::extend`], step 2); 1 (the end span) on the cross edges
//! `q^k_j r^k_j`; the mean side interval on the fan's spokes.
//!
//! **Why the end spans must agree.** The new outer row's face points weigh `p^k_j` by
//! `(d_{j,j+1} + 2 d_{j+1,j+2}) · (0 + d±)` where `d±` is read beyond the second layer: at
//! `q^k_j` the inward edge, at the corner point `Q_k` the neighbouring side's layer-2 edge
//! (its end span, as at the corner of a tensor-product net). The row is the refined curve
//! only if all of them are equal, hence [`equalize_end_spans`]; without it the boundary
//! is off by up to 1e-2 of the hole's size (measured).
//!
//! # Why the limit interpolates the curves and corners
//! With zero first intervals and zero extension intervals, the NURSS face, edge and vertex
//! rules give zero weight to every point off the boundary in the new outer real row: its
//! face points are the curve's midpoint-insertion edge points, its edge points the curve's
//! vertex points, its corner the corner face's point `c_k`. The new intervals keep the
//! pattern (halves of zero are zero). So the real boundary row is always the refined,
//! clamped control polygon of the curves (step 3, with skirt removal), whose limit is the
//! curves themselves. [`Fill::boundary_curves`] reads that polygon back exactly.

use std::collections::HashMap;

use super::extend::add_extension_layer;
use super::grid::{intervals, push_interval};
use super::skirt::{nurss_refine_once, real_part, refine_with_skirt};
use super::BlendError;
use crate::mesh::PolyMesh;
use crate::nurbs::{BSplineCurve, BSplineSurface, KnotVector};

/// Fewest sides of a hole.
pub const MIN_SIDES: usize = 3;
/// Most sides of a hole.
pub const MAX_SIDES: usize = 8;

/// Options of [`fill`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FillOptions {
    /// Moves the free inner points along the boundary's normal by `bulge` times the hole's
    /// mean radius (0: flat default, > 0 convex, < 0 concave).
    pub bulge: f64,
    /// Relative tolerance (times the boundary's size) within which curve ends count as a
    /// shared corner; such ends are snapped to their mean.
    pub corner_tolerance: f64,
}

impl Default for FillOptions {
    fn default() -> Self {
        Self {
            bulge: 0.0,
            corner_tolerance: 1e-6,
        }
    }
}

/// The boundary curve `S(u_3, v)` of a bicubic patch's first-row side, clamped.
///
/// # Errors
/// [`BlendError::Degree`], [`BlendError::Unsupported`] naming patch `index`.
pub fn patch_boundary(s: &BSplineSurface<3>, index: usize) -> Result<BSplineCurve<3>, BlendError> {
    super::patch::check_bicubic(s, index)?;
    let (nu, nv) = s.size();
    let u0 = s.domain().0 .0;
    let mut pts = Vec::with_capacity(nv);
    for j in 0..nv {
        let col: Vec<[f64; 3]> = (0..nu).map(|i| s.points()[i * nv + j]).collect();
        let c = BSplineCurve::new(s.knots_u().clone(), col)?;
        pts.push(c.eval(u0)?);
    }
    clamp(&BSplineCurve::new(s.knots_v().clone(), pts)?)
}

/// The same cubic curve on its domain with clamped knots (end knots of multiplicity 4), by
/// knot insertion: after inserting the domain ends `a`, `b` up to multiplicity 3 (at
/// least), with `k`, `l` their first indices and `s = k + mult(a) − 4`, the curve on
/// `[a, b]` has control points `P_s … P_{l−1}` and knots `a, t_{s+1} … t_{l+2}, b` (the
/// B-spline `N_{k−1}` is the only one not vanishing at a knot of multiplicity 3).
///
/// # Errors
/// [`BlendError::Degree`] unless cubic; [`BlendError::Unsupported`] if closed.
pub fn clamp(c: &BSplineCurve<3>) -> Result<BSplineCurve<3>, BlendError> {
    check_curve(c, 0)?;
    let (a, b) = c.domain();
    let mut c = c.clone();
    for t in [a, b] {
        let m = c.knots().multiplicity(t);
        if m < 3 {
            c.insert_knots(&vec![t; 3 - m])?;
        }
    }
    let t = c.knots().as_slice();
    let k = t.iter().position(|&x| x == a).unwrap_or(0);
    let s = (k + c.knots().multiplicity(a).min(4)).saturating_sub(4);
    let l = t.iter().position(|&x| x == b).unwrap_or(t.len() - 4);
    let points = c.points()[s..l].to_vec();
    let mut knots = t[s..=l + 3].to_vec();
    knots[0] = a;
    let e = knots.len() - 1;
    knots[e] = b;
    Ok(BSplineCurve::new(KnotVector::new(3, knots)?, points)?)
}

fn check_curve(c: &BSplineCurve<3>, index: usize) -> Result<(), BlendError> {
    if c.degree() != 3 {
        return Err(BlendError::Degree {
            what: "curve",
            index,
            degree: c.degree(),
        });
    }
    if c.is_closed() {
        return Err(BlendError::Unsupported {
            what: "curve",
            index,
            kind: "closed",
        });
    }
    Ok(())
}

/// The curve traversed backwards (`t ↦ a + b − t`).
pub fn reversed(c: &BSplineCurve<3>) -> Result<BSplineCurve<3>, BlendError> {
    let t = c.knots().as_slice();
    let (lo, hi) = (t[0], t[t.len() - 1]);
    let knots: Vec<f64> = t.iter().rev().map(|&x| lo + hi - x).collect();
    let pts: Vec<[f64; 3]> = c.points().iter().rev().copied().collect();
    Ok(BSplineCurve::new(KnotVector::new(c.degree(), knots)?, pts)?)
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Clamps, orients and chains `curves` into a closed loop (curve `k` ends where curve
/// `k + 1` starts), snapping shared corners to the mean of the two ends.
///
/// # Errors
/// [`BlendError::Count`], [`BlendError::Degree`], [`BlendError::Unsupported`],
/// [`BlendError::ShortCurve`], [`BlendError::Corner`] naming the curve.
pub fn chain_curves(
    curves: &[BSplineCurve<3>],
    tolerance: f64,
) -> Result<Vec<BSplineCurve<3>>, BlendError> {
    let n = curves.len();
    if !(MIN_SIDES..=MAX_SIDES).contains(&n) {
        return Err(BlendError::Count {
            what: "sides of the hole",
            found: n,
            min: MIN_SIDES,
            max: MAX_SIDES,
        });
    }
    let mut cs = Vec::with_capacity(n);
    for (k, c) in curves.iter().enumerate() {
        check_curve(c, k)?;
        let c = clamp(c).map_err(|e| match e {
            BlendError::Degree { degree, .. } => BlendError::Degree {
                what: "curve",
                index: k,
                degree,
            },
            e => e,
        })?;
        if c.points().len() < 4 {
            return Err(BlendError::ShortCurve {
                index: k,
                points: c.points().len(),
            });
        }
        cs.push(c);
    }
    let ends = |c: &BSplineCurve<3>| (c.points()[0], c.points()[c.points().len() - 1]);
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for c in &cs {
        for p in c.points() {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    let tol = tolerance * dist(lo, hi).max(f64::MIN_POSITIVE);
    // Orient curve 0 so that curve 1 continues it, then each next curve.
    let (s0, e0) = ends(&cs[0]);
    let (s1, e1) = ends(&cs[1]);
    if dist(e0, s1).min(dist(e0, e1)) > dist(s0, s1).min(dist(s0, e1)) {
        cs[0] = reversed(&cs[0])?;
    }
    for k in 1..n {
        let end = ends(&cs[k - 1]).1;
        let (s, e) = ends(&cs[k]);
        if dist(end, e) < dist(end, s) {
            cs[k] = reversed(&cs[k])?;
        }
    }
    let mut out = cs;
    for k in 0..n {
        let next = (k + 1) % n;
        let a = ends(&out[k]).1;
        let b = ends(&out[next]).0;
        let d = dist(a, b);
        if d > tol {
            return Err(BlendError::Corner {
                index: k,
                next,
                distance: d,
                tolerance: tol,
            });
        }
        let m = [
            0.5 * (a[0] + b[0]),
            0.5 * (a[1] + b[1]),
            0.5 * (a[2] + b[2]),
        ];
        for (idx, last) in [(k, true), (next, false)] {
            let c = &out[idx];
            let mut pts = c.points().to_vec();
            let i = if last { pts.len() - 1 } else { 0 };
            pts[i] = m;
            out[idx] = BSplineCurve::new(c.knots().clone(), pts)?;
        }
    }
    Ok(out)
}

/// Prepares chained clamped curves for the fill mesh without changing them as point sets:
/// inserts the knots `a + δ` and `b − δ` (`δ` a third of the shorter end span) so that
/// the first and last spans are equal, then scales the parameter (`t ↦ a + (t − a) / δ`)
/// so that they are 1. The fill mesh needs this: at a corner of the hole the interval
/// beyond the second layer of one side is the end span of the neighbouring side's curve
/// (as at the corner of a tensor-product net), and every second-layer vertex of a side must
/// see the same such interval for the new outer row to be exactly the refined curve.
///
/// # Errors
/// [`BlendError::Nurbs`] (none in practice for valid curves).
pub fn equalize_end_spans(curves: &[BSplineCurve<3>]) -> Result<Vec<BSplineCurve<3>>, BlendError> {
    curves
        .iter()
        .map(|c| {
            let t = c.knots().as_slice();
            let (a, b) = c.domain();
            let first = t.iter().copied().find(|&x| x > a).unwrap_or(b) - a;
            let last = b - t.iter().rev().copied().find(|&x| x < b).unwrap_or(a);
            let delta = first.min(last) / 3.0;
            let mut c = c.clone();
            c.insert_knots(&[a + delta, b - delta])?;
            let knots: Vec<f64> = c
                .knots()
                .as_slice()
                .iter()
                .map(|&x| a + (x - a) / delta)
                .collect();
            Ok(BSplineCurve::new(
                KnotVector::new(3, knots)?,
                c.points().to_vec(),
            )?)
        })
        .collect()
}

/// The fill control mesh of a chained loop of clamped curves (from [`chain_curves`] and
/// [`equalize_end_spans`]), with its extension layer (see the
/// [module documentation](self)).
///
/// # Errors
/// [`BlendError::Option`] for a non-finite bulge, [`BlendError::ShortCurve`] for a curve
/// with fewer than 6 control points (equalized curves have at least 6);
/// [`BlendError::Mesh`].
pub fn fill_control_mesh(curves: &[BSplineCurve<3>], bulge: f64) -> Result<PolyMesh, BlendError> {
    if !bulge.is_finite() {
        return Err(BlendError::Option(format!(
            "bulge {bulge} must be a finite number"
        )));
    }
    let n = curves.len();
    for (index, c) in curves.iter().enumerate() {
        if c.points().len() < 6 {
            return Err(BlendError::ShortCurve {
                index,
                points: c.points().len(),
            });
        }
    }
    let m: Vec<usize> = curves.iter().map(|c| c.points().len() - 1).collect();
    let mut pos: Vec<[f64; 3]> = Vec::new();
    // Layer 1: corner k, then the inner points of side k.
    let mut corner = vec![0u32; n];
    let mut inner_p = vec![Vec::new(); n];
    for k in 0..n {
        corner[k] = pos.len() as u32;
        pos.push(curves[k].points()[0]);
        for j in 1..m[k] {
            inner_p[k].push(pos.len() as u32);
            pos.push(curves[k].points()[j]);
        }
    }
    let p = |k: usize, j: usize| -> u32 {
        if j == 0 {
            corner[k]
        } else if j == m[k] {
            corner[(k + 1) % n]
        } else {
            inner_p[k][j - 1]
        }
    };
    let boundary: Vec<[f64; 3]> = (0..n)
        .flat_map(|k| (0..m[k]).map(move |j| (k, j)))
        .map(|(k, j)| pos[p(k, j) as usize])
        .collect();
    let nb = boundary.len() as f64;
    let mut g = [0.0; 3];
    for q in &boundary {
        for k in 0..3 {
            g[k] += q[k] / nb;
        }
    }
    let h = boundary.iter().map(|&q| dist(q, g)).sum::<f64>() / nb;
    let mut normal = [0.0; 3];
    for (i, a) in boundary.iter().enumerate() {
        let b = boundary[(i + 1) % boundary.len()];
        normal[0] += (a[1] - b[1]) * (a[2] + b[2]);
        normal[1] += (a[2] - b[2]) * (a[0] + b[0]);
        normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    let len = dist(normal, [0.0; 3]);
    if len > 0.0 {
        normal = normal.map(|x| x / len);
    }
    let gp = [
        g[0] + bulge * h * normal[0],
        g[1] + bulge * h * normal[1],
        g[2] + bulge * h * normal[2],
    ];
    let toward = |a: [f64; 3], f: f64| {
        [
            a[0] + (gp[0] - a[0]) * f,
            a[1] + (gp[1] - a[1]) * f,
            a[2] + (gp[2] - a[2]) * f,
        ]
    };
    // Layer 2: Q_k near corner k (completing the corner parallelogram), then q^k_j for
    // j = 2 … M_k − 2.
    let mut qc = vec![0u32; n];
    for k in 0..n {
        let prev = (k + n - 1) % n;
        let (a, b, c) = (
            pos[p(k, 1) as usize],
            pos[p(prev, m[prev] - 1) as usize],
            pos[corner[k] as usize],
        );
        qc[k] = pos.len() as u32;
        pos.push([a[0] + b[0] - c[0], a[1] + b[1] - c[1], a[2] + b[2] - c[2]]);
    }
    let mut inner_q = vec![Vec::new(); n];
    for k in 0..n {
        for j in 2..m[k] - 1 {
            inner_q[k].push(pos.len() as u32);
            let a = pos[p(k, j) as usize];
            pos.push(toward(a, 1.0 / 3.0));
        }
    }
    let q = |k: usize, j: usize| -> u32 {
        if j == 1 {
            qc[k]
        } else if j == m[k] - 1 {
            qc[(k + 1) % n]
        } else {
            inner_q[k][j - 2]
        }
    };
    // Layer 3: R_k opposite Q_k, then r^k_j for j = 3 … M_k − 3.
    let mut rc = vec![0u32; n];
    for k in 0..n {
        rc[k] = pos.len() as u32;
        let a = pos[qc[k] as usize];
        pos.push(toward(a, 1.0 / 3.0));
    }
    let mut inner_r = vec![Vec::new(); n];
    for k in 0..n {
        for j in 3..m[k] - 2 {
            inner_r[k].push(pos.len() as u32);
            let a = pos[p(k, j) as usize];
            pos.push(toward(a, 2.0 / 3.0));
        }
    }
    let r = |k: usize, j: usize| -> u32 {
        if j == 2 {
            rc[k]
        } else if j == m[k] - 2 {
            rc[(k + 1) % n]
        } else {
            inner_r[k][j - 3]
        }
    };
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for k in 0..n {
        let prev = (k + n - 1) % n;
        faces.push(vec![corner[k], p(k, 1), qc[k], p(prev, m[prev] - 1)]);
        faces.push(vec![qc[k], q(k, 2), rc[k], q(prev, m[prev] - 2)]);
        for j in 1..m[k] - 1 {
            faces.push(vec![p(k, j), p(k, j + 1), q(k, j + 1), q(k, j)]);
        }
        for j in 2..m[k] - 2 {
            faces.push(vec![q(k, j), q(k, j + 1), r(k, j + 1), r(k, j)]);
        }
    }
    let ring: Vec<u32> = (0..n)
        .flat_map(|k| (2..m[k] - 2).map(move |j| (k, j)))
        .map(|(k, j)| r(k, j))
        .collect();
    let len = ring.len();
    let mut spokes = Vec::new();
    if len.is_multiple_of(2) && len > 4 {
        let c = pos.len() as u32;
        pos.push(gp);
        for i in (1..len).step_by(2) {
            faces.push(vec![c, ring[i], ring[(i + 1) % len], ring[(i + 2) % len]]);
            spokes.push((c, ring[i]));
        }
    } else {
        faces.push(ring);
    }
    let mut mesh = PolyMesh::from_faces(pos, &faces)?;
    let mut side_sum = 0.0;
    let mut side_count = 0usize;
    for k in 0..n {
        let t = curves[k].knots().as_slice();
        for j in 0..m[k] {
            let d = t[j + 3] - t[j + 2];
            push_interval(&mut mesh, p(k, j), p(k, j + 1), d);
            if j >= 1 && j + 1 < m[k] {
                push_interval(&mut mesh, q(k, j), q(k, j + 1), d);
            }
            if j >= 2 && j + 2 < m[k] {
                push_interval(&mut mesh, r(k, j), r(k, j + 1), d);
            }
            if d > 0.0 {
                side_sum += d;
                side_count += 1;
            }
        }
        for j in 1..m[k] {
            push_interval(&mut mesh, p(k, j), q(k, j), 0.0);
        }
        // Beyond the second layer: the end span of the neighbouring curves (1 after
        // equalize_end_spans), the same for every second-layer vertex of the side.
        let beyond = t[4] - t[3];
        for j in 2..m[k] - 1 {
            push_interval(&mut mesh, q(k, j), r(k, j), beyond);
        }
    }
    let spoke = if side_count > 0 {
        side_sum / side_count as f64
    } else {
        1.0
    };
    for (a, b) in spokes {
        push_interval(&mut mesh, a, b, spoke);
    }
    add_extension_layer(&mesh, 0.0)
}

/// A filled hole.
#[derive(Clone, Debug, PartialEq)]
pub struct Fill {
    /// The boundary curves, clamped, oriented, chained and with equalized end spans
    /// ([`equalize_end_spans`]): the input curves as point sets, reparametrized affinely.
    pub curves: Vec<BSplineCurve<3>>,
    /// The fill control mesh with its extension layer.
    pub control: PolyMesh,
    /// The refined mesh, extension layer included.
    pub refined: PolyMesh,
}

impl Fill {
    /// The fill surface: the real part of the refined mesh (its control points).
    ///
    /// # Errors
    /// None in practice.
    pub fn surface(&self) -> Result<PolyMesh, BlendError> {
        real_part(&self.refined)
    }

    /// The limit of the fill along its boundary, exactly: the refined mesh's real boundary
    /// loop, cut at the corners (vertices whose two loop edges both have interval 0) into
    /// one clamped cubic B-spline per side (control points along the loop, knots from the
    /// loop's intervals, starting at the input curve's first knot). Side `k` runs from
    /// corner `k` to corner `k + 1` like [`curves`](Self::curves)`[k]`.
    ///
    /// # Errors
    /// [`BlendError::Grid`] if the loop does not have one corner per side (also when a
    /// curve has an interior knot of multiplicity 3, which looks like a corner).
    pub fn boundary_curves(&self) -> Result<Vec<BSplineCurve<3>>, BlendError> {
        let real = real_part(&self.refined)?;
        let iv = intervals(&real);
        let d = |a: u32, b: u32| iv.get(&(a.min(b), a.max(b))).copied().unwrap_or(1.0);
        let mut count: HashMap<(u32, u32), u32> = HashMap::new();
        for fv in real.faces() {
            for (i, &a) in fv.iter().enumerate() {
                let b = fv[(i + 1) % fv.len()];
                *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        let mut next: HashMap<u32, u32> = HashMap::new();
        for fv in real.faces() {
            for (i, &a) in fv.iter().enumerate() {
                let b = fv[(i + 1) % fv.len()];
                if count[&(a.min(b), a.max(b))] == 1 {
                    next.insert(a, b);
                }
            }
        }
        let bad = |m: &str| BlendError::Grid(format!("fill boundary: {m}"));
        let start = *next.keys().min().ok_or_else(|| bad("no boundary"))?;
        let mut lp = vec![start];
        let mut v = next[&start];
        while v != start {
            lp.push(v);
            v = *next.get(&v).ok_or_else(|| bad("open boundary"))?;
            if lp.len() > next.len() {
                return Err(bad("not one loop"));
            }
        }
        let l = lp.len();
        let is_corner =
            |i: usize| d(lp[(i + l - 1) % l], lp[i]) == 0.0 && d(lp[i], lp[(i + 1) % l]) == 0.0;
        let corners: Vec<usize> = (0..l).filter(|&i| is_corner(i)).collect();
        let n = self.curves.len();
        if corners.len() != n {
            return Err(bad(&format!("{} corners for {n} sides", corners.len())));
        }
        // Match corner 0 of the input.
        let c0 = self.curves[0].points()[0];
        let first = (0..n)
            .min_by(|&a, &b| {
                let pa = real.positions()[lp[corners[a]] as usize];
                let pb = real.positions()[lp[corners[b]] as usize];
                dist(pa, c0).total_cmp(&dist(pb, c0))
            })
            .unwrap_or(0);
        let mut out = Vec::with_capacity(n);
        for s in 0..n {
            let (i0, i1) = (corners[(first + s) % n], corners[(first + s + 1) % n]);
            let len = (i1 + l - i0) % l;
            let ids: Vec<u32> = (0..=len).map(|t| lp[(i0 + t) % l]).collect();
            let pts: Vec<[f64; 3]> = ids.iter().map(|&v| real.positions()[v as usize]).collect();
            let t0 = self.curves[s].knots().as_slice()[0];
            let mut knots = vec![t0, t0, t0];
            for w in ids.windows(2) {
                let last = knots[knots.len() - 1];
                knots.push(last + d(w[0], w[1]));
            }
            let last = knots[knots.len() - 1];
            knots.extend([last, last]);
            out.push(BSplineCurve::new(KnotVector::new(3, knots)?, pts)?);
        }
        Ok(out)
    }
}

/// Fills the hole bounded by `curves` (Algorithm 1): chains them ([`chain_curves`]), builds
/// [`fill_control_mesh`] and refines it `levels` times with NURSS and skirt removal.
///
/// # Errors
/// As [`chain_curves`] and [`fill_control_mesh`]; NURSS errors.
pub fn fill(
    curves: &[BSplineCurve<3>],
    levels: u32,
    opts: &FillOptions,
) -> Result<Fill, BlendError> {
    let curves = equalize_end_spans(&chain_curves(curves, opts.corner_tolerance)?)?;
    let control = fill_control_mesh(&curves, opts.bulge)?;
    let refined = refine_with_skirt(&control, levels, &mut [], nurss_refine_once)?;
    Ok(Fill {
        curves,
        control,
        refined,
    })
}
