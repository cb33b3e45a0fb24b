//! [`continuity_report`]: how well the patches of a surface join across their
//! boundaries — position gap, normal angle and jump in normal curvature — for the G2
//! caps of a [`G2Surface`] and, on the same boundaries, for plain Catmull-Clark.
//!
//! At each sample point of a boundary both sides are evaluated with first and second
//! derivatives. The normal curvature across the boundary is taken in the geometric
//! direction `w = n × T` (unit; `T` the side's tangent along the boundary, `n` its unit
//! normal), so both sides use the same direction in space whatever their
//! parametrisations: with `w = a Sᵤ + b Sᵥ`, `κ = a² L + 2ab M + b² N` (`L = Sᵤᵤ·n`,
//! `M = Sᵤᵥ·n`, `N = Sᵥᵥ·n`; do Carmo §3-2). The relative jump is
//! `|κ₁ - κ₂| / max(|κ₁|, |κ₂|, 1/size)`, `size` the diagonal of the mesh's bounding box
//! (so that nearly flat regions are judged against the curvature of the whole object).
//! Sample points are `tₖ = (k + ½)/m`, `k = 0..m`, avoiding the end points (where
//! Catmull-Clark's derivatives are degenerate at the extraordinary vertex).
//!
//! Catmull-Clark is C2 across these edges away from the vertex; its defect is *at* the
//! vertex, where the curvature depends on the direction of approach (it diverges or
//! vanishes, Peters & Reif 2008, ch. 6). The *vertex* rows compare the second fundamental
//! forms of the `n` patches at the vertex, expressed in one orthonormal tangent frame: for
//! the caps exactly at the vertex (G2 means one common form), for Catmull-Clark at the
//! cap coordinates `(10⁻³, 10⁻³)` of each patch (it has no second derivatives at the
//! vertex itself); the jump is relative to the largest entry (or `1/size`).

use super::surface::{G2Surface, PatchRef};
use super::G2Error;
use crate::geom;
use crate::limit::Derivatives;

/// Which boundaries a [`BoundaryStats`] covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoundaryKind {
    /// Between consecutive patches at an extraordinary vertex (edges at the EV).
    Inner,
    /// Between a cap patch and a surrounding bicubic patch.
    Outer,
    /// At the extraordinary vertex itself, between all `n` patches meeting there.
    Vertex,
}

/// Which surface a [`BoundaryStats`] measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The G2 surface (caps).
    G2,
    /// Plain Catmull-Clark on the same boundaries (the mixed surface without caps, for
    /// [`G2Surface::new`](super::G2Surface::new) with [`Scheme::Adjustable`](crate::Scheme::Adjustable)).
    CatmullClark,
}

/// Maxima over all sample points of one kind of boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryStats {
    /// Surface measured.
    pub surface: Side,
    /// Boundaries measured.
    pub kind: BoundaryKind,
    /// Number of boundaries (edges).
    pub boundaries: usize,
    /// Sample points per boundary.
    pub samples: usize,
    /// Largest distance between the two sides' positions.
    pub max_gap: f64,
    /// Largest angle between the two sides' unit normals (radians).
    pub max_normal_angle: f64,
    /// Largest relative jump of the normal curvature across the boundary.
    pub max_curvature_jump: f64,
}

impl BoundaryStats {
    fn new(surface: Side, kind: BoundaryKind, samples: usize) -> Self {
        Self {
            surface,
            kind,
            boundaries: 0,
            samples,
            max_gap: 0.0,
            max_normal_angle: 0.0,
            max_curvature_jump: 0.0,
        }
    }

    fn add(&mut self, a: &Derivatives, ta: [f64; 3], b: &Derivatives, tb: [f64; 3], size: f64) {
        let gap = geom::norm(&geom::sub(&a.p, &b.p));
        let (na, nb) = (a.normal(), b.normal());
        let angle = geom::norm(&geom::cross(&na, &nb)).atan2(geom::dot(&na, &nb));
        let ka = cross_curvature(a, ta);
        let kb = cross_curvature(b, tb);
        let jump = (ka - kb).abs() / ka.abs().max(kb.abs()).max(1.0 / size);
        self.max_gap = self.max_gap.max(gap);
        self.max_normal_angle = self.max_normal_angle.max(angle);
        self.max_curvature_jump = self.max_curvature_jump.max(jump);
        if !(gap.is_finite() && angle.is_finite() && jump.is_finite()) {
            self.max_gap = f64::NAN;
        }
    }
}

impl BoundaryStats {
    /// One vertex: the `n` patches' positions, normals and second fundamental forms
    /// (as symmetric 2×2 matrices in a common orthonormal tangent frame) compared pairwise.
    fn add_vertex(&mut self, patches: &[Derivatives], size: f64) {
        self.boundaries += 1;
        let Some(first) = patches.first() else {
            return;
        };
        let n0 = first.normal();
        let e1 = geom::normalize_or_zero(first.du);
        let e2 = geom::cross(&n0, &e1);
        let forms: Vec<[f64; 3]> = patches.iter().map(|d| second_form(d, n0, e1, e2)).collect();
        let scale = forms
            .iter()
            .flat_map(|f| f.iter().map(|x| x.abs()))
            .fold(1.0 / size, f64::max);
        for (a, fa) in patches.iter().zip(&forms) {
            for (b, fb) in patches.iter().zip(&forms) {
                let gap = geom::norm(&geom::sub(&a.p, &b.p));
                let (na, nb) = (a.normal(), b.normal());
                let angle = geom::norm(&geom::cross(&na, &nb)).atan2(geom::dot(&na, &nb));
                let jump = (0..3).map(|k| (fa[k] - fb[k]).abs()).fold(0.0, f64::max) / scale;
                self.max_gap = self.max_gap.max(gap);
                self.max_normal_angle = self.max_normal_angle.max(angle);
                self.max_curvature_jump = self.max_curvature_jump.max(jump);
            }
        }
    }
}

/// The second fundamental form of `d` (normal `n`) in the orthonormal tangent frame
/// `(e1, e2)`: `(II(e1,e1), II(e1,e2), II(e2,e2))`, from `II = Kᵀ [[L, M], [M, N]] K` with
/// `K` the inverse of the frame coordinates of `(Sᵤ, Sᵥ)`.
fn second_form(d: &Derivatives, n: [f64; 3], e1: [f64; 3], e2: [f64; 3]) -> [f64; 3] {
    let (a, b, c, e) = (
        geom::dot(&d.du, &e1),
        geom::dot(&d.dv, &e1),
        geom::dot(&d.du, &e2),
        geom::dot(&d.dv, &e2),
    );
    let det = a * e - b * c;
    // K = J⁻¹, J = [[a, b], [c, e]] maps (∂u, ∂v) coefficients to frame coordinates.
    let k = [[e / det, -b / det], [-c / det, a / det]];
    let (l, m, nn) = (
        geom::dot(&d.duu, &n),
        geom::dot(&d.duv, &n),
        geom::dot(&d.dvv, &n),
    );
    let h = [[l, m], [m, nn]];
    let mut s = [[0.0; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            for p in 0..2 {
                for q in 0..2 {
                    s[i][j] += k[p][i] * h[p][q] * k[q][j];
                }
            }
        }
    }
    [s[0][0], s[0][1], s[1][1]]
}

/// Normal curvature of `d` in the direction `n × t` (see the module docs).
pub(crate) fn cross_curvature(d: &Derivatives, t: [f64; 3]) -> f64 {
    let n = d.normal();
    let w = geom::normalize_or_zero(geom::cross(&n, &t));
    // Solve w = a Su + b Sv in the least-squares sense (exact in the tangent plane).
    let (e, f, g) = (
        geom::dot(&d.du, &d.du),
        geom::dot(&d.du, &d.dv),
        geom::dot(&d.dv, &d.dv),
    );
    let (p, q) = (geom::dot(&w, &d.du), geom::dot(&w, &d.dv));
    let det = e * g - f * f;
    let a = (g * p - f * q) / det;
    let b = (e * q - f * p) / det;
    a * a * geom::dot(&d.duu, &n)
        + 2.0 * a * b * geom::dot(&d.duv, &n)
        + b * b * geom::dot(&d.dvv, &n)
}

/// The report of [`continuity_report`]: the G2 caps' inner and outer boundaries, and
/// Catmull-Clark across the inner ones.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContinuityReport {
    /// Caps, between consecutive cap patches.
    pub g2_inner: BoundaryStats,
    /// Caps, between cap patches and the surrounding bicubics.
    pub g2_outer: BoundaryStats,
    /// Catmull-Clark across the same inner boundaries (edges at the extraordinary vertices).
    pub cc_inner: BoundaryStats,
    /// Caps at the extraordinary vertices: the second fundamental forms of the `n` patches
    /// there (see [`continuity_report`]).
    pub g2_vertex: BoundaryStats,
    /// Catmull-Clark next to the extraordinary vertices (at distance `10⁻³` of a patch).
    pub cc_vertex: BoundaryStats,
    /// Number of caps measured.
    pub caps: usize,
}

impl ContinuityReport {
    /// The five rows in order.
    pub fn rows(&self) -> [&BoundaryStats; 5] {
        [
            &self.g2_inner,
            &self.g2_outer,
            &self.cc_inner,
            &self.g2_vertex,
            &self.cc_vertex,
        ]
    }
}

impl std::fmt::Display for ContinuityReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "{:<15} {:<6} {:>10} {:>8} {:>12} {:>14} {:>16}",
            "surface", "edges", "boundaries", "samples", "max gap", "max normal ∠", "max rel. Δκ"
        )?;
        for r in self.rows() {
            writeln!(
                f,
                "{:<15} {:<6} {:>10} {:>8} {:>12.3e} {:>14.3e} {:>16.3e}",
                match r.surface {
                    Side::G2 => "G2 caps",
                    Side::CatmullClark => "Catmull-Clark",
                },
                match r.kind {
                    BoundaryKind::Inner => "inner",
                    BoundaryKind::Outer => "outer",
                    BoundaryKind::Vertex => "vertex",
                },
                r.boundaries,
                r.samples,
                r.max_gap,
                r.max_normal_angle,
                r.max_curvature_jump
            )?;
        }
        Ok(())
    }
}

/// Measures every boundary of every cap of `surface` at `samples` points (at least 1):
/// inner boundaries (patch `i` at `(0, t)` against patch `i+1` at `(t, 0)`), outer
/// boundaries (cap patch at `(x, 1)` and `(1, y)` against the Catmull-Clark surface, which
/// is the bicubic neighbour there and C2 across that edge), and, for comparison, the
/// Catmull-Clark surface ([`G2Surface::eval_uncapped`]: the mixed surface for
/// [`G2Surface::new`] with [`Scheme::Adjustable`](crate::Scheme::Adjustable)) across the same inner boundaries (its outer boundaries are
/// C2). Derivatives are compared in cap coordinates.
///
/// # Errors
/// [`G2Error::Eval`] if the Catmull-Clark surface cannot be evaluated (not expected).
pub fn continuity_report(surface: &G2Surface, samples: usize) -> Result<ContinuityReport, G2Error> {
    let m = samples.max(1);
    let size = surface.size();
    let mut r = ContinuityReport {
        g2_inner: BoundaryStats::new(Side::G2, BoundaryKind::Inner, m),
        g2_outer: BoundaryStats::new(Side::G2, BoundaryKind::Outer, m),
        cc_inner: BoundaryStats::new(Side::CatmullClark, BoundaryKind::Inner, m),
        g2_vertex: BoundaryStats::new(Side::G2, BoundaryKind::Vertex, 1),
        cc_vertex: BoundaryStats::new(Side::CatmullClark, BoundaryKind::Vertex, 1),
        caps: surface.caps().len(),
    };
    let cc = |slot: &PatchRef, s: f64, t: f64| -> Result<Derivatives, G2Error> {
        let (u, v) = slot.to_face(s, t);
        let d = surface.eval_uncapped(crate::limit::SurfacePoint {
            face: slot.face,
            subface: slot.subface,
            u: u.clamp(0.0, 1.0),
            v: v.clamp(0.0, 1.0),
        })?;
        Ok(slot.face_to_cap(&d))
    };
    for cap in surface.caps() {
        let n = cap.slots.len();
        let patches = cap.cap.patches();
        let at_g2: Vec<Derivatives> = patches.iter().map(|p| p.eval(0.0, 0.0)).collect();
        r.g2_vertex.add_vertex(&at_g2, size);
        let delta = 1e-3;
        let at_cc: Vec<Derivatives> = cap
            .slots
            .iter()
            .map(|s| cc(s, delta, delta))
            .collect::<Result<_, _>>()?;
        r.cc_vertex.add_vertex(&at_cc, size);
        for i in 0..n {
            let j = (i + 1) % n;
            r.g2_inner.boundaries += 1;
            r.cc_inner.boundaries += 1;
            r.g2_outer.boundaries += 2;
            for k in 0..m {
                let t = (k as f64 + 0.5) / m as f64;
                // Inner: Pᵢ(0, t) (along: ∂ᵥ) against Pⱼ(t, 0) (along: ∂ᵤ).
                let a = patches[i].eval(0.0, t);
                let b = patches[j].eval(t, 0.0);
                r.g2_inner.add(&a, a.dv, &b, b.du, size);
                let a = cc(&cap.slots[i], 0.0, t)?;
                let b = cc(&cap.slots[j], t, 0.0)?;
                r.cc_inner.add(&a, a.dv, &b, b.du, size);
                // Outer: v = 1 (along ∂ᵤ) and u = 1 (along ∂ᵥ) against Catmull-Clark there.
                for (s, tt, along_u) in [(t, 1.0, true), (1.0, t, false)] {
                    let a = patches[i].eval(s, tt);
                    let b = cc(&cap.slots[i], s, tt)?;
                    let (ta, tb) = if along_u { (a.du, b.du) } else { (a.dv, b.dv) };
                    r.g2_outer.add(&a, ta, &b, tb, size);
                }
            }
        }
    }
    Ok(r)
}
