//! N-sided hole filling with a corner-interpolating NURSS surface ([Jiang et al.] §3.2,
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
use super::homogeneous::{
    curve_of, mean, mesh_weights, weighted, weighted_mesh, BoundaryCurve, Patch,
};
use super::skirt::{merge_degenerate, nurss_refine_once, real_part, refine_with_skirt};
use super::BlendError;
use crate::mesh::PolyMesh;
use crate::nurbs::{BSplineCurve, BSplineSurface, Curve, KnotVector};

/// Fewest sides of a hole.
pub(crate) const MIN_SIDES: usize = 3;
/// Most sides of a hole.
pub(crate) const MAX_SIDES: usize = 8;

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

/// The boundary curve `S(u_3, v)` of a bicubic patch's first-row side, clamped. For a
/// homogeneous patch (`D = 4`, points `(w P, w)`) this is the homogeneous boundary curve,
/// whose projection is the NURBS boundary.
///
/// # Errors
/// [`BlendError::Degree`], [`BlendError::Unsupported`] naming patch `index`.
pub fn patch_boundary<const D: usize>(
    s: &BSplineSurface<D>,
    index: usize,
) -> Result<BSplineCurve<D>, BlendError> {
    super::patch::check_bicubic(s, index)?;
    let (nu, nv) = s.size();
    let u0 = s.domain().0 .0;
    let mut pts = Vec::with_capacity(nv);
    for j in 0..nv {
        let col: Vec<[f64; D]> = (0..nu).map(|i| s.points()[i * nv + j]).collect();
        let c = BSplineCurve::new(s.knots_u().clone(), col)?;
        pts.push(c.eval(u0)?);
    }
    clamp(&BSplineCurve::new(s.knots_v().clone(), pts)?)
}

/// [`patch_boundary`] of a polynomial or rational patch, as a polynomial or rational curve
/// (a NURBS patch's boundary is the projection of its homogeneous boundary curve).
///
/// # Errors
/// As [`patch_boundary`].
pub fn surface_boundary<P: Patch>(s: &P, index: usize) -> Result<Curve, BlendError> {
    curve_of(patch_boundary(&s.homogeneous(), index)?)
}

/// The same cubic curve on its domain with clamped knots (end knots of multiplicity 4), by
/// knot insertion: after inserting the domain ends `a`, `b` up to multiplicity 3 (at
/// least), with `k`, `l` their first indices and `s = k + mult(a) − 4`, the curve on
/// `[a, b]` has control points `P_s … P_{l−1}` and knots `a, t_{s+1} … t_{l+2}, b` (the
/// B-spline `N_{k−1}` is the only one not vanishing at a knot of multiplicity 3).
///
/// # Errors
/// [`BlendError::Degree`] unless cubic; [`BlendError::Unsupported`] if closed.
pub(crate) fn clamp<const D: usize>(c: &BSplineCurve<D>) -> Result<BSplineCurve<D>, BlendError> {
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

fn check_curve<const D: usize>(c: &BSplineCurve<D>, index: usize) -> Result<(), BlendError> {
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
pub fn reversed<const D: usize>(c: &BSplineCurve<D>) -> Result<BSplineCurve<D>, BlendError> {
    let t = c.knots().as_slice();
    let (lo, hi) = (t[0], t[t.len() - 1]);
    let knots: Vec<f64> = t.iter().rev().map(|&x| lo + hi - x).collect();
    let pts: Vec<[f64; D]> = c.points().iter().rev().copied().collect();
    Ok(BSplineCurve::new(KnotVector::new(c.degree(), knots)?, pts)?)
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The weight of a control point: `p[3]` of a homogeneous point (`D = 4`), else 1.
fn weight_of<const D: usize>(p: &[f64; D]) -> f64 {
    if D == 4 {
        p[D - 1]
    } else {
        1.0
    }
}

/// The Cartesian point of a control point: `(x, y, z) / w` of a homogeneous point (`D = 4`),
/// else the point.
fn cart_of<const D: usize>(p: &[f64; D]) -> [f64; 3] {
    let w = weight_of(p);
    [p[0] / w, p[1] / w, p[2] / w]
}

/// The control point of Cartesian `c` with the weight of `p`.
fn with_cart<const D: usize>(p: &[f64; D], c: [f64; 3]) -> [f64; D] {
    let w = weight_of(p);
    let mut out = *p;
    for k in 0..3 {
        out[k] = w * c[k];
    }
    out
}

/// Clamps, orients and chains `curves` into a closed loop (curve `k` ends where curve
/// `k + 1` starts), snapping shared corners to the mean of the two ends.
///
/// # Errors
/// [`BlendError::Count`], [`BlendError::Degree`], [`BlendError::Unsupported`],
/// [`BlendError::ShortCurve`], [`BlendError::Corner`] naming the curve.
pub(crate) fn chain_curves<const D: usize>(
    curves: &[BSplineCurve<D>],
    tolerance: f64,
) -> Result<Vec<BSplineCurve<D>>, BlendError> {
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
    let ends = |c: &BSplineCurve<D>| {
        let p = c.points();
        (cart_of(&p[0]), cart_of(&p[p.len() - 1]))
    };
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for c in &cs {
        for p in c.points().iter().map(cart_of) {
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
            pts[i] = with_cart(&pts[i], m);
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
pub(crate) fn equalize_end_spans<const D: usize>(
    curves: &[BSplineCurve<D>],
) -> Result<Vec<BSplineCurve<D>>, BlendError> {
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
/// [module documentation](self)). Homogeneous curves (`D = 4`, points `(w P, w)`, from
/// NURBS curves whose weights agree at the shared corners) give a rational mesh: layer 1
/// keeps the curves' weights, every other point gets their mean (see
/// [`super::homogeneous`]).
///
/// # Errors
/// [`BlendError::Option`] for a non-finite bulge or one that moves the centre beyond
/// [`crate::mesh::MAX_COORDINATE`], [`BlendError::ShortCurve`] for a curve with fewer than 6
/// control points (equalized curves have at least 6); [`BlendError::Mesh`].
pub(crate) fn fill_control_mesh<const D: usize>(
    curves: &[BSplineCurve<D>],
    bulge: f64,
) -> Result<PolyMesh, BlendError> {
    for (index, c) in curves.iter().enumerate() {
        if c.points().len() < 6 {
            return Err(BlendError::ShortCurve {
                index,
                points: c.points().len(),
            });
        }
    }
    let mut pos: Vec<[f64; 3]> = Vec::new();
    let mut weights: Vec<f64> = Vec::new();
    let mut layers = FillLayers::first(curves, &mut pos, &mut weights);
    let gp = bulged_centre(&pos, bulge)?;
    layers.add_inner(&mut pos, gp);
    let (faces, spokes) = layers.faces(&mut pos, gp);
    let free = mean(weights.iter().copied());
    weights.resize(pos.len(), free);
    let mut mesh = weighted_mesh(pos, &weights, &faces)?;
    layers.set_intervals(&mut mesh, curves, spokes);
    add_extension_layer(&mesh, 0.0)
}

/// The vertices of the fill control mesh's three layers ([Jiang et al.] §3.2, Algorithm 1
/// step 1; see the module documentation):
/// layer 1 `p^k_j` (the curves' control points), layer 2 `q^k_j` with the corner points
/// `Q_k`, layer 3 `r^k_j` with `R_k`.
struct FillLayers {
    /// `M_k`: the last control point index of curve `k`.
    m: Vec<usize>,
    corner: Vec<u32>,
    inner_p: Vec<Vec<u32>>,
    qc: Vec<u32>,
    inner_q: Vec<Vec<u32>>,
    rc: Vec<u32>,
    inner_r: Vec<Vec<u32>>,
}

impl FillLayers {
    /// Layer 1: corner `k`, then the inner points of side `k`, pushed onto `pos` (Cartesian)
    /// and `weights`.
    fn first<const D: usize>(
        curves: &[BSplineCurve<D>],
        pos: &mut Vec<[f64; 3]>,
        weights: &mut Vec<f64>,
    ) -> Self {
        let n = curves.len();
        let m: Vec<usize> = curves.iter().map(|c| c.points().len() - 1).collect();
        let mut corner = vec![0u32; n];
        let mut inner_p = vec![Vec::new(); n];
        for k in 0..n {
            corner[k] = pos.len() as u32;
            for j in 0..m[k] {
                if j > 0 {
                    inner_p[k].push(pos.len() as u32);
                }
                let q = &curves[k].points()[j];
                pos.push(cart_of(q));
                weights.push(weight_of(q));
            }
        }
        Self {
            m,
            corner,
            inner_p,
            qc: Vec::new(),
            inner_q: vec![Vec::new(); n],
            rc: Vec::new(),
            inner_r: vec![Vec::new(); n],
        }
    }

    /// Layers 2 and 3, pushed onto `pos`: `Q_k` near corner `k` (completing the corner
    /// parallelogram), `q^k_j` (`j = 2 … M_k − 2`) a third of the way from `p^k_j` to the
    /// centre `gp`; `R_k` a third of the way from `Q_k` to `gp`, `r^k_j` (`j = 3 … M_k − 3`)
    /// two thirds of the way from `p^k_j`.
    fn add_inner(&mut self, pos: &mut Vec<[f64; 3]>, gp: [f64; 3]) {
        let (n, m) = (self.m.len(), self.m.clone());
        let toward = |a: [f64; 3], f: f64| {
            [
                a[0] + (gp[0] - a[0]) * f,
                a[1] + (gp[1] - a[1]) * f,
                a[2] + (gp[2] - a[2]) * f,
            ]
        };
        let mut qc = vec![0u32; n];
        for k in 0..n {
            let prev = (k + n - 1) % n;
            let (a, b, c) = (
                pos[self.p(k, 1) as usize],
                pos[self.p(prev, m[prev] - 1) as usize],
                pos[self.corner[k] as usize],
            );
            qc[k] = pos.len() as u32;
            pos.push([a[0] + b[0] - c[0], a[1] + b[1] - c[1], a[2] + b[2] - c[2]]);
        }
        for k in 0..n {
            for j in 2..m[k] - 1 {
                self.inner_q[k].push(pos.len() as u32);
                let a = pos[self.p(k, j) as usize];
                pos.push(toward(a, 1.0 / 3.0));
            }
        }
        let mut rc = vec![0u32; n];
        for k in 0..n {
            rc[k] = pos.len() as u32;
            let a = pos[qc[k] as usize];
            pos.push(toward(a, 1.0 / 3.0));
        }
        for k in 0..n {
            for j in 3..m[k] - 2 {
                self.inner_r[k].push(pos.len() as u32);
                let a = pos[self.p(k, j) as usize];
                pos.push(toward(a, 2.0 / 3.0));
            }
        }
        self.qc = qc;
        self.rc = rc;
    }

    /// `p^k_j`, `j = 0 … M_k` (the corners at both ends).
    fn p(&self, k: usize, j: usize) -> u32 {
        let n = self.m.len();
        if j == 0 {
            self.corner[k]
        } else if j == self.m[k] {
            self.corner[(k + 1) % n]
        } else {
            self.inner_p[k][j - 1]
        }
    }

    /// `q^k_j`, `j = 1 … M_k − 1` (`Q_k`, `Q_{k+1}` at the ends).
    fn q(&self, k: usize, j: usize) -> u32 {
        let n = self.m.len();
        if j == 1 {
            self.qc[k]
        } else if j == self.m[k] - 1 {
            self.qc[(k + 1) % n]
        } else {
            self.inner_q[k][j - 2]
        }
    }

    /// `r^k_j`, `j = 2 … M_k − 2` (`R_k`, `R_{k+1}` at the ends).
    fn r(&self, k: usize, j: usize) -> u32 {
        let n = self.m.len();
        if j == 2 {
            self.rc[k]
        } else if j == self.m[k] - 2 {
            self.rc[(k + 1) % n]
        } else {
            self.inner_r[k][j - 3]
        }
    }

    /// The quads between the layers and the middle bounded by layer 3: a fan around the
    /// centre `gp` (pushed onto `pos`; an even ring of more than 4 points, its spokes
    /// returned), else one polygon.
    fn faces(&self, pos: &mut Vec<[f64; 3]>, gp: [f64; 3]) -> (Vec<Vec<u32>>, Vec<(u32, u32)>) {
        let (n, m) = (self.m.len(), &self.m);
        let mut faces: Vec<Vec<u32>> = Vec::new();
        for k in 0..n {
            let prev = (k + n - 1) % n;
            faces.push(vec![
                self.corner[k],
                self.p(k, 1),
                self.qc[k],
                self.p(prev, m[prev] - 1),
            ]);
            faces.push(vec![
                self.qc[k],
                self.q(k, 2),
                self.rc[k],
                self.q(prev, m[prev] - 2),
            ]);
            for j in 1..m[k] - 1 {
                faces.push(vec![
                    self.p(k, j),
                    self.p(k, j + 1),
                    self.q(k, j + 1),
                    self.q(k, j),
                ]);
            }
            for j in 2..m[k] - 2 {
                faces.push(vec![
                    self.q(k, j),
                    self.q(k, j + 1),
                    self.r(k, j + 1),
                    self.r(k, j),
                ]);
            }
        }
        let ring: Vec<u32> = (0..n)
            .flat_map(|k| (2..m[k] - 2).map(move |j| (k, j)))
            .map(|(k, j)| self.r(k, j))
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
        (faces, spokes)
    }

    /// Tags the intervals of the module documentation: the curves' spans along the three
    /// layers, 0 from layer 1 to 2, the neighbouring curves' end span from layer 2 to 3, and
    /// the mean positive span on the `spokes`.
    fn set_intervals<const D: usize>(
        &self,
        mesh: &mut PolyMesh,
        curves: &[BSplineCurve<D>],
        spokes: Vec<(u32, u32)>,
    ) {
        let (n, m) = (self.m.len(), &self.m);
        let mut side_sum = 0.0;
        let mut side_count = 0usize;
        for k in 0..n {
            let t = curves[k].knots().as_slice();
            for j in 0..m[k] {
                let d = t[j + 3] - t[j + 2];
                push_interval(mesh, self.p(k, j), self.p(k, j + 1), d);
                if j >= 1 && j + 1 < m[k] {
                    push_interval(mesh, self.q(k, j), self.q(k, j + 1), d);
                }
                if j >= 2 && j + 2 < m[k] {
                    push_interval(mesh, self.r(k, j), self.r(k, j + 1), d);
                }
                if d > 0.0 {
                    side_sum += d;
                    side_count += 1;
                }
            }
            for j in 1..m[k] {
                push_interval(mesh, self.p(k, j), self.q(k, j), 0.0);
            }
            // Beyond the second layer: the end span of the neighbouring curves (1 after
            // equalize_end_spans), the same for every second-layer vertex of the side.
            let beyond = t[4] - t[3];
            for j in 2..m[k] - 1 {
                push_interval(mesh, self.q(k, j), self.r(k, j), beyond);
            }
        }
        let spoke = if side_count > 0 {
            side_sum / side_count as f64
        } else {
            1.0
        };
        for (a, b) in spokes {
            push_interval(mesh, a, b, spoke);
        }
    }
}

/// The fill's centre `G' = G + bulge · h · n` of the closed boundary polygon `boundary`:
/// `G` the centroid of its points, `h` their mean distance from `G`, `n` the unit Newell
/// normal (oriented by the polygon's direction).
///
/// # Errors
/// [`BlendError::Option`] for a non-finite `bulge`, or one that puts `G'` beyond
/// [`crate::mesh::MAX_COORDINATE`] in a coordinate (refinement multiplies coordinates; below
/// that bound every product is finite).
pub(crate) fn bulged_centre(boundary: &[[f64; 3]], bulge: f64) -> Result<[f64; 3], BlendError> {
    if !bulge.is_finite() {
        return Err(BlendError::Option(format!(
            "bulge {bulge} must be a finite number"
        )));
    }
    let nb = boundary.len() as f64;
    let mut g = [0.0; 3];
    for q in boundary {
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
    if gp
        .iter()
        .any(|c| !c.is_finite() || c.abs() > crate::mesh::MAX_COORDINATE)
    {
        return Err(BlendError::Option(format!(
            "bulge {bulge:e} moves the fill's centre {:.3e} away from the boundary (the bulge \
             times the hole's mean radius {h:.3e}); coordinates must stay below 1e75 in \
             magnitude: use a smaller bulge",
            (bulge * h).abs()
        )));
    }
    Ok(gp)
}

/// A filled hole.
#[derive(Clone, Debug, PartialEq)]
pub struct Fill {
    /// The boundary curves, clamped, oriented, chained and with equalized end spans
    /// (`equalize_end_spans`): the input curves as point sets, reparametrized affinely
    /// (rational curves whose weights disagree at the corners also by
    /// `match_corner_weights`).
    pub curves: Vec<Curve>,
    /// The fill control mesh with its extension layer.
    pub control: PolyMesh,
    /// The refined mesh, extension layer included.
    pub refined: PolyMesh,
}

impl Fill {
    /// The fill surface: the real part of the refined mesh (its control points), with the
    /// vertices that zero knot intervals make coincide merged
    /// (`super::skirt::merge_degenerate`).
    ///
    /// # Errors
    /// None in practice.
    pub fn surface(&self) -> Result<PolyMesh, BlendError> {
        merge_degenerate(&real_part(&self.refined)?)
    }

    /// The limit of the fill along its boundary, exactly: the refined mesh's real boundary
    /// loop, cut at the corners (vertices whose two loop edges both have interval 0) into
    /// one clamped cubic B-spline per side (control points along the loop, knots from the
    /// loop's intervals, starting at the input curve's first knot; rational, with the
    /// mesh's weights, when the fill is). Side `k` runs from corner `k` to corner `k + 1`
    /// like [`curves`](Self::curves)`[k]`.
    ///
    /// # Errors
    /// [`BlendError::Grid`] if the loop does not have one corner per side (also when a
    /// curve has an interior knot of multiplicity 3, which looks like a corner).
    pub fn boundary_curves(&self) -> Result<Vec<Curve>, BlendError> {
        let real = real_part(&self.refined)?;
        let w = mesh_weights(&real);
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
            let pts: Vec<[f64; 4]> = ids
                .iter()
                .map(|&v| weighted(real.positions()[v as usize], w[v as usize]))
                .collect();
            let t0 = self.curves[s].knots().as_slice()[0];
            let mut knots = vec![t0, t0, t0];
            for w in ids.windows(2) {
                let last = knots[knots.len() - 1];
                knots.push(last + d(w[0], w[1]));
            }
            let last = knots[knots.len() - 1];
            knots.extend([last, last]);
            out.push(curve_of(BSplineCurve::new(
                KnotVector::new(3, knots)?,
                pts,
            )?)?);
        }
        Ok(out)
    }
}

/// Fills the hole bounded by `curves` (Algorithm 1), polynomial ([`BSplineCurve<3>`]),
/// rational ([`NurbsCurve`](crate::nurbs::NurbsCurve)) or either ([`Curve`]): chains them
/// (`chain_curves`), matches rational curves' weights at the corners
/// (`match_corner_weights`), builds `fill_control_mesh` and refines it `levels` times
/// with NURSS (in homogeneous coordinates when rational) and skirt removal.
///
/// # Errors
/// As `chain_curves` and `fill_control_mesh`; NURSS errors.
pub fn fill<C: BoundaryCurve>(
    curves: &[C],
    levels: u32,
    opts: &FillOptions,
) -> Result<Fill, BlendError> {
    let homogeneous: Vec<BSplineCurve<4>> = curves
        .iter()
        .map(|c| c.homogeneous().into_owned())
        .collect();
    let chained = match_corner_weights(chain_curves(&homogeneous, opts.corner_tolerance)?)?;
    let prepared = equalize_end_spans(&chained)?;
    let control = fill_control_mesh(&prepared, opts.bulge)?;
    let refined = refine_with_skirt(&control, levels, &mut [], nurss_refine_once)?;
    Ok(Fill {
        curves: prepared
            .into_iter()
            .map(curve_of)
            .collect::<Result<_, _>>()?,
        control,
        refined,
    })
}

/// Rational curves chained around a hole (from [`chain_curves`]: clamped, curve `k` ending
/// where curve `k + 1` starts) with one weight at each shared corner, as the fill mesh
/// needs (a corner is one vertex of both sides), the curves unchanged as point sets.
///
/// Two changes keep a NURBS curve as a point set: multiplying all its homogeneous points by
/// a constant, and a rational linear (Möbius) reparametrization, which also changes the
/// ratio of its end weights (see [`reweight_ends`]). Corner `k` needs
/// `λ_{k−1} e_{k−1} = λ_k s_k` (`s_k`, `e_k` the first and last weight of curve `k`, `λ_k`
/// its constant), solvable around the loop exactly when `Π s_k / e_k = 1`. So each curve's
/// ratio `e_k / s_k` is first multiplied by `φ = (Π s_k / e_k)^{1/N}` (a Möbius
/// reparametrization, shared equally by the `N` curves), then `λ_0 = 1`,
/// `λ_k = λ_{k−1} e_{k−1} / s_k`. Curves whose weights are all 1 (polynomial) are returned
/// as they are.
///
/// # Errors
/// [`BlendError::Nurbs`] (none in practice for valid curves).
pub(crate) fn match_corner_weights(
    curves: Vec<BSplineCurve<4>>,
) -> Result<Vec<BSplineCurve<4>>, BlendError> {
    if curves
        .iter()
        .all(|c| c.points().iter().all(|p| p[3] == 1.0))
    {
        return Ok(curves);
    }
    let ends = |c: &BSplineCurve<4>| {
        let p = c.points();
        (p[0][3], p[p.len() - 1][3])
    };
    let n = curves.len() as f64;
    let log_ratio: f64 = curves
        .iter()
        .map(|c| {
            let (s, e) = ends(c);
            s.ln() - e.ln()
        })
        .sum::<f64>();
    let phi = (log_ratio / n).exp();
    let mut out = Vec::with_capacity(curves.len());
    for c in &curves {
        let c = if phi == 1.0 {
            c.clone()
        } else {
            reweight_ends(c, phi)?
        };
        let lambda = match out.last() {
            None => 1.0,
            Some(prev) => ends(prev).1 / ends(&c).0,
        };
        let pts = c.points().iter().map(|p| p.map(|x| x * lambda)).collect();
        out.push(BSplineCurve::new(c.knots().clone(), pts)?);
    }
    Ok(out)
}

/// The clamped cubic homogeneous curve `c` on the same domain `[a, b]` reparametrized by a
/// rational linear map that fixes `a` and `b`, so that the ratio of its last weight to its
/// first is multiplied by `phi > 0`; the projected curve is the same point set.
///
/// With `y = (t − a) / (b − a)` the old parameter and `x` the new one, normalized,
/// `y = g(x) = x / (ρ + (1 − ρ) x)` (`ρ > 0`, increasing, `g(0) = 0`, `g(1) = 1`). Each
/// B-spline `N_{i,p}(g(x))` is a spline in `x` of degree `p` over `(ρ + (1 − ρ) x)^p`,
/// supported on the mapped knots `x_j = g⁻¹(y_j) = ρ y_j / (1 − y_j + ρ y_j)`, so it is
/// `κ_i N'_{i,p}(x) / (ρ + (1 − ρ) x)^p` with `κ_i = Π_{j=1..p} (ρ + (1 − ρ) x_{i+j})` (for
/// `p = 1` directly from `N_{i,1}`; for higher degrees by the recurrence; Lee & Lucian,
/// "Möbius reparametrizations of rational B-splines", CAGD 8(3), 1991; The NURBS Book
/// §6.4). The common denominator cancels in the rational curve, so the curve in `x` has the
/// knots `x_j` and the homogeneous points `κ_i P^w_i`. Clamped ends give `κ_0 = ρ^p`,
/// `κ_n = 1`: the end-weight ratio is multiplied by `ρ^{−p}`, hence `ρ = phi^{−1/p}`.
///
/// # Errors
/// [`BlendError::Nurbs`] for an unclamped curve's knots (none for `clamp`ed curves).
pub fn reweight_ends(c: &BSplineCurve<4>, phi: f64) -> Result<BSplineCurve<4>, BlendError> {
    let p = c.degree();
    let rho = phi.powf(-1.0 / p as f64);
    let (a, b) = c.domain();
    let t = c.knots().as_slice();
    let last = t.len() - 1;
    let x: Vec<f64> = t
        .iter()
        .enumerate()
        .map(|(j, &tj)| {
            let y = ((tj - a) / (b - a)).clamp(0.0, 1.0);
            if j <= p || tj <= a {
                0.0
            } else if j >= last - p || tj >= b {
                1.0
            } else {
                rho * y / (1.0 - y + rho * y)
            }
        })
        .collect();
    let knots: Vec<f64> = x
        .iter()
        .map(|&xj| if xj == 1.0 { b } else { a + (b - a) * xj })
        .collect();
    let points = c
        .points()
        .iter()
        .enumerate()
        .map(|(i, q)| {
            let kappa: f64 = (1..=p).map(|j| rho + (1.0 - rho) * x[i + j]).product();
            q.map(|v| v * kappa)
        })
        .collect();
    Ok(BSplineCurve::new(KnotVector::new(p, knots)?, points)?)
}
