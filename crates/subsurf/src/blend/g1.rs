//! G1 N-sided hole filling ([Jiang et al.] §3.3, Algorithm 2): the fill interpolates the boundary
//! curves of N bicubic patches and meets every patch with a continuous normal.
//!
//! # Layout
//! Three parallel rings of control points and a middle:
//! - ring 1: the boundary curves' control points, one closed row; at a corner `c_k` the two
//!   curves meet with zero intervals on both sides (a triple knot: the row passes through
//!   `c_k` and may turn there);
//! - ring 2: `A_k = c_k + d_{c_k}` at each corner (the paper's `A_k`) and
//!   `B^k_j = p^k_j + d^k_j` opposite every other control point (the paper's `B^k_j`);
//! - ring 3: one point inward of each ring-2 point; the middle: a fan around a centre point
//!   (even count of more than 4) or one polygon.
//!
//! Intervals: along rings 1 and 2 the curves' spans, 0 across from ring 1 to ring 2 and on
//! the extension layer (corner interpolation, as in [`super::fill`](mod@super::fill)), 1 across from ring 2 to
//! ring 3 (the same for every ring-2 vertex, which is what keeps the refined outer rows
//! exact), the mean span along ring 3 and on the spokes.
//!
//! # The G1 construction
//! Near side `k` the limit is the tensor-product B-spline of rings 1 and 2 (cross knots
//! `0, 0, 0, 0, 1, …`), so its cross-boundary derivative is `D(t) ∝ Σ_j N_j(t) d_j`. With
//! `E(t) = ∂S_k/∂u` the base patch's cross derivative on the boundary and `T(t)` the
//! boundary's tangent, the fill meets the patch G1 where `D = −λ_k E + β_k T` with
//! `λ_k > 0` constant and `β_k` linear along the side (the G1 condition between adjacent
//! Bézier patches the paper uses): `D` is then a cubic on every span, and every span is a
//! Bézier segment once each interior knot of the boundary has multiplicity 3 (inserted;
//! the curves are unchanged), so the `d_j` are the Bézier coefficients of `D`, computed
//! exactly from four values per span. At corner `c_k` the two sides share `d_{c_k}`:
//! `−λ_k E_k(a) + x T_k(a) = −λ_{k−1} E_{k−1}(b) + y T_{k−1}(b)` is solved for
//! `x = β_k(a)`, `y = β_{k−1}(b)` (the paper's `x_k`, `y_k`); it has a solution exactly
//! when the two patches share the tangent plane at the corner (the paper's five
//! coplanar points), which is checked. `λ_k` scales `E` to the mean control-point spacing.
//!
//! The zero intervals of the tripled knots run across rings 1 and 2, so the fill has creases
//! near the boundary (visible in zebra pictures): it is G1 at the seams, not fair inside.

use std::collections::HashMap;

use super::extend::add_extension_layer;
use super::fill::{bulged_centre, chain_curves, patch_boundary, FillOptions};
use super::grid::{intervals, push_interval};
use super::homogeneous::{cart, Patch};
use super::skirt::{merge_degenerate, nurss_refine_once, real_part, refine_with_skirt};
use super::BlendError;
use crate::geom;
use crate::mesh::PolyMesh;
use crate::nurbs::{BSplineCurve, BSplineSurface, KnotVector};

use crate::geom::V3;

/// One side of the hole: the chained boundary curve (interior knots tripled) and the base
/// patch with the map from the curve's parameter to the patch's `v`.
struct Side<'a> {
    curve: BSplineCurve<3>,
    patch: &'a BSplineSurface<3>,
    reversed: bool,
}

impl Side<'_> {
    fn domain(&self) -> (f64, f64) {
        self.curve.domain()
    }
    /// The patch's `v` at curve parameter `t`.
    fn v(&self, t: f64) -> f64 {
        let (a, b) = self.domain();
        let t = t.clamp(a, b);
        if self.reversed {
            a + b - t
        } else {
            t
        }
    }
    /// `∂S/∂u` of the base patch on the boundary.
    fn cross(&self, t: f64) -> Result<V3, BlendError> {
        let u0 = self.patch.domain().0 .0;
        let (_, (v0, v1)) = self.patch.domain();
        let v = self.v(t).clamp(v0, v1);
        Ok(self.patch.eval_derivs(u0, v, 1)?[1][0])
    }
    fn tangent(&self, t: f64) -> Result<V3, BlendError> {
        let (a, b) = self.domain();
        Ok(self.curve.eval_derivs(t.clamp(a, b), 1)?[1])
    }
}

/// A G1-filled hole.
#[derive(Clone, Debug, PartialEq)]
pub struct G1Fill {
    /// The boundary curves, clamped, chained and with interior knots of multiplicity 3.
    pub curves: Vec<BSplineCurve<3>>,
    /// The control mesh with its extension layer.
    pub control: PolyMesh,
    /// The refined mesh, extension layer included.
    pub refined: PolyMesh,
}

/// The limit's outer two rows along one side: the boundary as a clamped B-spline and the
/// cross-boundary derivative direction `D(t) = Σ N_j(t) (row2_j − row1_j)` on the same knots.
#[derive(Clone, Debug, PartialEq)]
pub struct BoundaryRows {
    /// The limit boundary curve.
    pub boundary: BSplineCurve<3>,
    /// The cross-boundary derivative (up to a positive factor), pointing into the fill.
    pub cross: BSplineCurve<3>,
}

impl G1Fill {
    /// The fill surface: the real part of the refined mesh, with the vertices that the
    /// tripled knots make coincide merged ([`super::skirt::merge_degenerate`]: the quads
    /// between them have zero area; merged, the mesh keeps every other face and vertex and
    /// stays watertight).
    ///
    /// # Errors
    /// None in practice.
    pub fn surface(&self) -> Result<PolyMesh, BlendError> {
        merge_degenerate(&real_part(&self.refined)?)
    }

    /// The exact limit boundary and cross-boundary derivative of every side, read from the
    /// refined mesh's outer two real rows (see [`BoundaryRows`]), side `k` from corner `k`
    /// to corner `k + 1` in the parameter of [`curves`](Self::curves)`[k]`.
    ///
    /// # Errors
    /// [`BlendError::Grid`] if the real boundary is not one loop through the corners.
    pub fn boundary_rows(&self) -> Result<Vec<BoundaryRows>, BlendError> {
        let real = real_part(&self.refined)?;
        let iv = intervals(&real);
        let d = |a: u32, b: u32| iv.get(&(a.min(b), a.max(b))).copied().unwrap_or(1.0);
        let lp = BoundaryLoop::new(&real)?;
        let l = lp.verts.len();
        let pos = |v: u32| real.positions()[v as usize];
        let n = self.curves.len();
        let mut corner_at = Vec::with_capacity(n);
        for c in &self.curves {
            let target = c.points()[0];
            let i = (0..l)
                .min_by(|&a, &b| {
                    geom::norm(&geom::sub(&pos(lp.verts[a]), &target))
                        .total_cmp(&geom::norm(&geom::sub(&pos(lp.verts[b]), &target)))
                })
                .ok_or_else(|| bad_boundary("empty loop"))?;
            corner_at.push(i);
        }
        let mut out = Vec::with_capacity(n);
        for s in 0..n {
            let (i0, i1) = (corner_at[s], corner_at[(s + 1) % n]);
            let len = (i1 + l - i0) % l;
            let mut idx: Vec<usize> = (0..=len).map(|t| (i0 + t) % l).collect();
            let mut ivs: Vec<f64> = idx
                .windows(2)
                .map(|w| d(lp.verts[w[0]], lp.verts[w[1]]))
                .collect();
            trim_zero_runs(&mut idx, &mut ivs);
            let t0 = self.curves[s].knots().as_slice()[0];
            let mut knots = vec![t0, t0, t0];
            for &x in &ivs {
                let last = knots[knots.len() - 1];
                knots.push(last + x);
            }
            let last = knots[knots.len() - 1];
            knots.extend([last, last]);
            let kv = KnotVector::new(3, knots)?;
            let row0: Vec<V3> = idx.iter().map(|&i| pos(lp.verts[i])).collect();
            let mut diffs = Vec::with_capacity(idx.len());
            for &i in &idx {
                diffs.push(geom::sub(&pos(lp.inward(i)?), &pos(lp.verts[i])));
            }
            out.push(BoundaryRows {
                boundary: BSplineCurve::new(kv.clone(), row0)?,
                cross: BSplineCurve::new(kv, diffs)?,
            });
        }
        Ok(out)
    }
}

/// [`BlendError::Grid`] for a fill whose real boundary is not as [`G1Fill::boundary_rows`]
/// needs it.
fn bad_boundary(m: &str) -> BlendError {
    BlendError::Grid(format!("fill boundary: {m}"))
}

/// The boundary loop of a mesh (edges with one face), from its lowest vertex in face order,
/// with every vertex's neighbours.
struct BoundaryLoop {
    verts: Vec<u32>,
    nbrs: HashMap<u32, Vec<u32>>,
}

impl BoundaryLoop {
    /// The boundary loop of `real`; fails when there is none or it is not one closed loop.
    fn new(real: &PolyMesh) -> Result<Self, BlendError> {
        let mut count: HashMap<(u32, u32), u32> = HashMap::new();
        for fv in real.faces() {
            for (i, &a) in fv.iter().enumerate() {
                let b = fv[(i + 1) % fv.len()];
                *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        let mut next: HashMap<u32, u32> = HashMap::new();
        let mut nbrs: HashMap<u32, Vec<u32>> = HashMap::new();
        for fv in real.faces() {
            for (i, &a) in fv.iter().enumerate() {
                let b = fv[(i + 1) % fv.len()];
                if count[&(a.min(b), a.max(b))] == 1 {
                    next.insert(a, b);
                }
                nbrs.entry(a).or_default().push(b);
                nbrs.entry(b).or_default().push(a);
            }
        }
        let start = *next
            .keys()
            .min()
            .ok_or_else(|| bad_boundary("no boundary"))?;
        let mut lp = vec![start];
        let mut v = next[&start];
        while v != start {
            lp.push(v);
            v = *next.get(&v).ok_or_else(|| bad_boundary("open boundary"))?;
            if lp.len() > next.len() {
                return Err(bad_boundary("not one loop"));
            }
        }
        Ok(Self { verts: lp, nbrs })
    }

    /// The inward neighbour of loop vertex `i`: its one neighbour off the loop.
    fn inward(&self, i: usize) -> Result<u32, BlendError> {
        let (lp, l) = (&self.verts, self.verts.len());
        let (p, n) = (lp[(i + l - 1) % l], lp[(i + 1) % l]);
        let mut c: Vec<u32> = self.nbrs[&lp[i]]
            .iter()
            .copied()
            .filter(|&w| w != p && w != n)
            .collect();
        c.sort_unstable();
        c.dedup();
        match c.as_slice() {
            [w] => Ok(*w),
            _ => Err(bad_boundary(
                "a boundary vertex without one inward neighbour",
            )),
        }
    }
}

/// Trims the zero intervals `ivs` between the loop points `idx` of one side to valid knots.
/// Zero intervals double in number each step: a knot of multiplicity 3 (a corner or a
/// tripled interior knot) becomes a run of zero edges whose inner points all equal the curve
/// point there (inserting a knot that already has multiplicity 3 repeats that point). Keeps
/// one zero edge at each end (clamped) and two in each interior run (multiplicity 3): the
/// same curve, valid knots.
fn trim_zero_runs(idx: &mut Vec<usize>, ivs: &mut Vec<f64>) {
    while idx.len() > 3 && ivs[0] == 0.0 && ivs[1] == 0.0 {
        idx.remove(0);
        ivs.remove(0);
    }
    while idx.len() > 3 && ivs[ivs.len() - 1] == 0.0 && ivs[ivs.len() - 2] == 0.0 {
        idx.pop();
        ivs.pop();
    }
    let mut e = 0;
    while e + 2 < ivs.len() {
        if ivs[e] == 0.0 && ivs[e + 1] == 0.0 && ivs[e + 2] == 0.0 {
            // Drop the point between edges e + 1 and e + 2 (merging two zeros).
            idx.remove(e + 2);
            ivs.remove(e + 2);
        } else {
            e += 1;
        }
    }
}

/// The polynomial patch of homogeneous `s` (patch `index`) whose weights are all equal
/// (a NURBS patch with one weight is that polynomial patch).
///
/// # Errors
/// [`BlendError::RationalG1`] for unequal weights: the G1 construction above is for
/// polynomial patches.
fn polynomial(s: &BSplineSurface<4>, index: usize) -> Result<BSplineSurface<3>, BlendError> {
    let w0 = s.points()[0][3];
    if s.points().iter().any(|p| p[3] != w0) {
        return Err(BlendError::RationalG1 { index });
    }
    let points = s.points().iter().map(cart).collect();
    Ok(BSplineSurface::new(
        s.knots_u().clone(),
        s.knots_v().clone(),
        points,
    )?)
}

/// Inserts every interior knot of `c` up to multiplicity 3 (a piecewise Bézier curve).
fn triple_interior_knots(c: &BSplineCurve<3>) -> Result<BSplineCurve<3>, BlendError> {
    let (a, b) = c.domain();
    let mut values: Vec<f64> = c
        .knots()
        .as_slice()
        .iter()
        .copied()
        .filter(|&t| t > a && t < b)
        .collect();
    values.dedup();
    let mut c = c.clone();
    for t in values {
        let m = c.knots().multiplicity(t);
        if m < 3 {
            c.insert_knots(&vec![t; 3 - m])?;
        }
    }
    Ok(c)
}

/// Fills the hole bounded by the first-row boundaries of `patches` G1 (Algorithm 2): the
/// limit interpolates the boundary curves and corners and has the base patches' normal
/// along every boundary (see the module documentation). The patches are polynomial,
/// or rational with one weight each (which are polynomial patches).
///
/// # Errors
/// As [`super::fill::fill`] for the boundary curves; [`BlendError::TangentPlane`] when two
/// patches do not share the tangent plane at their common corner;
/// [`BlendError::RationalG1`] for a patch with unequal weights.
pub fn fill_g1<P: Patch>(
    patches: &[P],
    levels: u32,
    opts: &FillOptions,
) -> Result<G1Fill, BlendError> {
    if !opts.bulge.is_finite() {
        return Err(BlendError::Option(format!(
            "bulge {} must be a finite number",
            opts.bulge
        )));
    }
    let patches = patches
        .iter()
        .enumerate()
        .map(|(k, p)| polynomial(&p.homogeneous(), k))
        .collect::<Result<Vec<_>, _>>()?;
    let sides = hole_sides(&patches, opts)?;
    let (spacing, lambda) = cross_scales(&sides)?;
    let (beta, corner_d) = corner_cross_vectors(&sides, &lambda, spacing)?;
    let mut ds: Vec<Vec<V3>> = Vec::with_capacity(sides.len());
    for (k, s) in sides.iter().enumerate() {
        ds.push(side_cross_coefficients(s, k, lambda[k], beta[k])?);
    }
    let mesh = g1_control_mesh(&sides, &corner_d, &ds, opts.bulge)?;
    let control = add_extension_layer(&mesh, 0.0)?;
    let refined = refine_with_skirt(&control, levels, &mut [], nurss_refine_once)?;
    Ok(G1Fill {
        curves: sides.into_iter().map(|s| s.curve).collect(),
        control,
        refined,
    })
}

/// The hole's sides: the patches' boundary curves chained into a loop
/// ([`chain_curves`]), each with its interior knots tripled and its patch, noting which
/// curves the chaining reversed.
fn hole_sides<'a>(
    patches: &'a [BSplineSurface<3>],
    opts: &FillOptions,
) -> Result<Vec<Side<'a>>, BlendError> {
    let curves = patches
        .iter()
        .enumerate()
        .map(|(k, s)| patch_boundary(s, k))
        .collect::<Result<Vec<_>, _>>()?;
    let chained = chain_curves(&curves, opts.corner_tolerance)?;
    let mut sides = Vec::with_capacity(chained.len());
    for (k, c) in chained.iter().enumerate() {
        let start = c.points()[0];
        let orig = &curves[k];
        let reversed = geom::norm(&geom::sub(&start, &orig.points()[0]))
            > geom::norm(&geom::sub(&start, &orig.points()[orig.points().len() - 1]));
        sides.push(Side {
            curve: triple_interior_knots(c)?,
            patch: &patches[k],
            reversed,
        });
    }
    Ok(sides)
}

/// The mean control-point spacing of the sides (the scale of the cross vectors) and every
/// side's `λ_k`: the spacing over `|E|` at the middle of the side (1 where `E` vanishes).
fn cross_scales(sides: &[Side]) -> Result<(f64, Vec<f64>), BlendError> {
    let (mut sum, mut cnt) = (0.0, 0usize);
    for s in sides {
        for w in s.curve.points().windows(2) {
            sum += geom::norm(&geom::sub(&w[1], &w[0]));
            cnt += 1;
        }
    }
    let spacing = if cnt > 0 { sum / cnt as f64 } else { 1.0 };
    let mut lambda = Vec::with_capacity(sides.len());
    for s in sides {
        let (a, b) = s.domain();
        let e = geom::norm(&s.cross(0.5 * (a + b))?);
        lambda.push(if e > 0.0 { spacing / e } else { 1.0 });
    }
    Ok((spacing, lambda))
}

/// At every corner `k` ([Jiang et al.] §3.3, Algorithm 2, the paper's `x_k`, `y_k`): solves
/// `−λ_k E_k(a) + x T_k(a) = −λ_{k−1} E_{k−1}(b) + y T_{k−1}(b)` by least squares and checks
/// the residual (the two patches share the tangent plane). Returns `β` at the start and end
/// of every side and the shared cross vector `d_{c_k}` at every corner.
///
/// # Errors
/// [`BlendError::TangentPlane`] when the tangents are parallel or the residual is not small.
fn corner_cross_vectors(
    sides: &[Side],
    lambda: &[f64],
    spacing: f64,
) -> Result<(Vec<[f64; 2]>, Vec<V3>), BlendError> {
    let n = sides.len();
    let mut beta = vec![[0.0f64; 2]; n];
    let mut corner_d = vec![[0.0f64; 3]; n];
    for k in 0..n {
        let p = (k + n - 1) % n;
        let (a, _) = sides[k].domain();
        let (_, b) = sides[p].domain();
        let (tk, tp) = (sides[k].tangent(a)?, sides[p].tangent(b)?);
        let rhs = geom::sub(
            &geom::scale(&sides[k].cross(a)?, lambda[k]),
            &geom::scale(&sides[p].cross(b)?, lambda[p]),
        );
        // x tk − y tp = rhs, least squares.
        let (m11, m12, m22) = (
            geom::dot(&tk, &tk),
            -geom::dot(&tk, &tp),
            geom::dot(&tp, &tp),
        );
        let (r1, r2) = (geom::dot(&tk, &rhs), -geom::dot(&tp, &rhs));
        let det = m11 * m22 - m12 * m12;
        if det.abs() <= 1e-12 * m11 * m22 {
            return Err(BlendError::TangentPlane {
                index: k,
                previous: p,
                residual: f64::INFINITY,
            });
        }
        let x = (r1 * m22 - r2 * m12) / det;
        let y = (m11 * r2 - m12 * r1) / det;
        let res = geom::norm(&geom::sub(
            &geom::sub(&geom::scale(&tk, x), &geom::scale(&tp, y)),
            &rhs,
        ));
        if res > 1e-7 * geom::norm(&rhs).max(spacing) {
            return Err(BlendError::TangentPlane {
                index: k,
                previous: p,
                residual: res / spacing,
            });
        }
        beta[k][0] = x;
        beta[p][1] = y;
        corner_d[k] = geom::add(
            &geom::scale(&sides[k].cross(a)?, -lambda[k]),
            &geom::scale(&tk, x),
        );
    }
    Ok((beta, corner_d))
}

/// The `d_j` of side `k` ([Jiang et al.] §3.3, Algorithm 2): the Bézier coefficients of the
/// cubic `D = −λ E + β T` (`β` linear from `beta[0]` to `beta[1]`) on every span, exact from
/// its values at the span's ends and thirds; one per control point of the side's curve.
fn side_cross_coefficients(
    s: &Side,
    k: usize,
    lambda: f64,
    beta: [f64; 2],
) -> Result<Vec<V3>, BlendError> {
    let (a, b) = s.domain();
    let mut spans: Vec<f64> = s
        .curve
        .knots()
        .as_slice()
        .iter()
        .copied()
        .filter(|&t| t >= a && t <= b)
        .collect();
    spans.dedup();
    let target = |t: f64| -> Result<V3, BlendError> {
        let bt = beta[0] + (beta[1] - beta[0]) * (t - a) / (b - a);
        Ok(geom::add(
            &geom::scale(&s.cross(t)?, -lambda),
            &geom::scale(&s.tangent(t)?, bt),
        ))
    };
    let mut d = Vec::new();
    for w in spans.windows(2) {
        let (s0, s1) = (w[0], w[1]);
        let c0 = target(s0)?;
        let c3 = target(s1)?;
        let f1 = target(s0 + (s1 - s0) / 3.0)?;
        let f2 = target(s0 + 2.0 * (s1 - s0) / 3.0)?;
        let aa = geom::sub(
            &geom::sub(&geom::scale(&f1, 27.0), &geom::scale(&c0, 8.0)),
            &c3,
        );
        let bb = geom::sub(
            &geom::sub(&geom::scale(&f2, 27.0), &c0),
            &geom::scale(&c3, 8.0),
        );
        let c1 = geom::scale(&geom::sub(&geom::scale(&aa, 2.0), &bb), 1.0 / 18.0);
        let c2 = geom::scale(&geom::sub(&geom::scale(&bb, 2.0), &aa), 1.0 / 18.0);
        if d.is_empty() {
            d.push(c0);
        }
        d.extend([c1, c2, c3]);
    }
    if d.len() != s.curve.points().len() {
        return Err(BlendError::Grid(format!(
            "side {k}: {} Bézier coefficients for {} control points",
            d.len(),
            s.curve.points().len()
        )));
    }
    Ok(d)
}

/// The fill's control mesh before its extension layer ([Jiang et al.] §3.3, Algorithm 2; see
/// the module documentation's layout): ring 1 the sides' control points, ring 2 ring 1 plus the cross vectors `ds`
/// (`d_{c_k}`, the mean of the two sides' at a corner), ring 3 a third of the way to the
/// bulged centre, and the middle; with the intervals of the layout.
fn g1_control_mesh(
    sides: &[Side],
    corner_d: &[V3],
    ds: &[Vec<V3>],
    bulge: f64,
) -> Result<PolyMesh, BlendError> {
    let n = sides.len();
    let mut ring1: Vec<V3> = Vec::new();
    let mut ring2: Vec<V3> = Vec::new();
    let mut spans1: Vec<f64> = Vec::new();
    for (k, s) in sides.iter().enumerate() {
        let pts = s.curve.points();
        let t = s.curve.knots().as_slice();
        let p = (k + n - 1) % n;
        let dc = geom::scale(&geom::add(&corner_d[k], &ds[p][ds[p].len() - 1]), 0.5);
        for j in 0..pts.len() - 1 {
            ring1.push(pts[j]);
            ring2.push(if j == 0 {
                geom::add(&pts[0], &dc)
            } else {
                geom::add(&pts[j], &ds[k][j])
            });
            spans1.push(t[j + 3] - t[j + 2]);
        }
    }
    let m = ring1.len();
    let gp = bulged_centre(&ring1, bulge)?;
    let ring3: Vec<V3> = ring2
        .iter()
        .map(|&q| geom::add(&q, &geom::scale(&geom::sub(&gp, &q), 1.0 / 3.0)))
        .collect();
    let mut pos: Vec<V3> = Vec::with_capacity(3 * m + 1);
    pos.extend_from_slice(&ring1);
    pos.extend_from_slice(&ring2);
    pos.extend_from_slice(&ring3);
    let id = |r: usize, i: usize| (r * m + i % m) as u32;
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for r in 0..2 {
        for i in 0..m {
            faces.push(vec![id(r, i), id(r, i + 1), id(r + 1, i + 1), id(r + 1, i)]);
        }
    }
    let mut spokes = Vec::new();
    if m.is_multiple_of(2) && m > 4 {
        let c = pos.len() as u32;
        pos.push(gp);
        for i in (0..m).step_by(2) {
            faces.push(vec![c, id(2, i), id(2, i + 1), id(2, i + 2)]);
            spokes.push((c, id(2, i)));
        }
    } else {
        faces.push((0..m).map(|i| id(2, i)).collect());
    }
    let mut mesh = PolyMesh::from_faces(pos, &faces)?;
    let positive: Vec<f64> = spans1.iter().copied().filter(|&x| x > 0.0).collect();
    let mean = if positive.is_empty() {
        1.0
    } else {
        positive.iter().sum::<f64>() / positive.len() as f64
    };
    for i in 0..m {
        push_interval(&mut mesh, id(0, i), id(0, i + 1), spans1[i]);
        push_interval(&mut mesh, id(1, i), id(1, i + 1), spans1[i]);
        push_interval(&mut mesh, id(2, i), id(2, i + 1), mean);
        push_interval(&mut mesh, id(0, i), id(1, i), 0.0);
        push_interval(&mut mesh, id(1, i), id(2, i), 1.0);
    }
    for (a, b) in spokes {
        push_interval(&mut mesh, a, b, mean);
    }
    Ok(mesh)
}
