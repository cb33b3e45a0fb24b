//! Catmull-Clark masks with OpenSubdiv's rules (`Sdc::Scheme<SCHEME_CATMARK>`).
//!
//! Refinement masks (Catmull & Clark 1978; sharp rules: Hoppe et al. 1994, DeRose et
//! al. 1998):
//! - face point: the average of the face's `n` vertices;
//! - edge point, smooth: `¼(v₀ + v₁) + ¼(f₀ + f₁)` with `f` the new face points
//!   (`½/m` per face for `m ≠ 2` faces); crease: `½(v₀ + v₁)`; a semi-sharp edge whose
//!   sharpness `s < 1` decays this step blends the two with weight `s` on the crease mask;
//! - vertex point, smooth with valence `n`: `(n-2)/n · v + 1/n² Σ eᵢ + 1/n² Σ fᵢ`
//!   (`eᵢ` far ends of the edges, `fᵢ` new face points); crease: `¾ v + ⅛ (e_a + e_b)`
//!   along the two sharp edges; corner: `v`; on a change of rule during the step the
//!   parent-rule and child-rule masks are blended by [`crease::fractional_weight`].
//!
//! With [`TriangleSubdivision::Smooth`] the face weight of a triangle next to a smooth
//! edge is 0.47 instead of 0.25 (OpenSubdiv's `TRI_SUB_SMOOTH`).
//!
//! Limit masks (Halstead, Kass, DeRose 1993 for the smooth case; OpenSubdiv's
//! `assign*LimitMask` for creases and corners) weight the vertex, the far ends of its
//! edges and, for each incident quad, the vertex *opposite* in that quad.

use super::crease;
use super::Rules;
use crate::mesh::{Options, Rule, TriangleSubdivision};
use std::f64::consts::PI;

/// Weight of each of the `n` vertices in a face point: `1/n`.
#[inline]
pub(crate) fn face_point_weight(n: usize) -> f64 {
    1.0 / n as f64
}

/// Weights of an edge point: each end vertex gets `vertex`; the new face points of the
/// edge's faces get `faces[0]`, `faces[1]`, and `other_faces` each beyond the second.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeMask {
    /// Weight of each end vertex.
    pub vertex: f64,
    /// Weights of the first two faces' centres.
    pub faces: [f64; 2],
    /// Weight of every further face's centre (only on non-manifold edges).
    pub other_faces: f64,
}

impl EdgeMask {
    /// The crease (midpoint) mask.
    pub const CREASE: EdgeMask = EdgeMask {
        vertex: 0.5,
        faces: [0.0; 2],
        other_faces: 0.0,
    };

    /// Whether face weights are all zero (no face centres needed).
    pub fn is_crease(&self) -> bool {
        self.faces == [0.0; 2] && self.other_faces == 0.0
    }
}

/// Catmull-Clark's rules ([`Rules`]): OpenSubdiv's `Sdc::Scheme<SCHEME_CATMARK>`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct CatmullClark;

impl Rules for CatmullClark {
    /// `¼` of each end and each face point; `½/m` per face for `m ≠ 2` faces; with the
    /// smooth-triangle rule a triangle's face weight is 0.47 (OpenSubdiv's
    /// `assignSmoothMaskForEdge`).
    fn smooth_edge_mask(self, options: &Options, num_faces: usize, tri: [bool; 2]) -> EdgeMask {
        let use_tri = options.triangles == TriangleSubdivision::Smooth
            && num_faces == 2
            && (tri[0] || tri[1]);
        if !use_tri {
            if num_faces == 2 {
                EdgeMask {
                    vertex: 0.25,
                    faces: [0.25; 2],
                    other_faces: 0.0,
                }
            } else {
                let w = 0.5 / num_faces as f64;
                EdgeMask {
                    vertex: 0.25,
                    faces: [w; 2],
                    other_faces: w,
                }
            }
        } else {
            const TRI_EDGE_WEIGHT: f64 = 0.470;
            let f0 = if tri[0] { TRI_EDGE_WEIGHT } else { 0.25 };
            let f1 = if tri[1] { TRI_EDGE_WEIGHT } else { 0.25 };
            let f = 0.5 * (f0 + f1);
            EdgeMask {
                vertex: 0.5 * (1.0 - 2.0 * f),
                faces: [f; 2],
                other_faces: 0.0,
            }
        }
    }

    /// `((n − 2)/n, 1/n², 1/n²)`.
    #[inline]
    fn smooth_vertex_weights(self, n: usize) -> (f64, f64, f64) {
        let n = n as f64;
        let w = 1.0 / (n * n);
        ((n - 2.0) / n, w, w)
    }

    /// `(⅛, ¾, ⅛)`: the cubic B-spline's even rule.
    #[inline]
    fn crease_vertex_weights(self) -> [f64; 3] {
        [0.125, 0.75, 0.125]
    }

    /// `¼(v₀ + v₁ + f₀ + f₁)`, summed in that order.
    #[inline]
    fn smooth_edge_point<const D: usize>(
        self,
        ends: [&[f64; D]; 2],
        faces: [&[f64; D]; 2],
    ) -> [f64; D] {
        std::array::from_fn(|k| 0.25 * (ends[0][k] + ends[1][k] + faces[0][k] + faces[1][k]))
    }

    /// `(n − 2)/n · v + (Σ eᵢ + Σ fᵢ)/n²`, the far ends and face points summed in one
    /// running sum.
    #[inline]
    fn smooth_vertex_point<'a, const D: usize>(
        self,
        n: usize,
        v: &[f64; D],
        ends: impl Iterator<Item = &'a [f64; D]>,
        faces: impl Iterator<Item = &'a [f64; D]>,
    ) -> [f64; D] {
        let mut acc = [0.0; D];
        for x in ends.chain(faces) {
            for k in 0..D {
                acc[k] += x[k];
            }
        }
        let (vw, w, _) = self.smooth_vertex_weights(n);
        std::array::from_fn(|k| acc[k] * w + vw * v[k])
    }
}

/// A vertex mask being built: the vertex weight and, optionally, one weight per incident
/// edge (far end) and per incident face (its centre for refinement masks, its opposite
/// vertex for limit masks). Buffers are reused between vertices.
#[derive(Clone, Debug, Default)]
pub struct VertexMask {
    /// Weight of the vertex itself.
    pub vertex: f64,
    /// Weights of the edges' far ends (valid when `has_edges`).
    pub edges: Vec<f64>,
    /// Weights of the faces (valid when `has_faces`).
    pub faces: Vec<f64>,
    /// Whether `edges` is part of the mask.
    pub has_edges: bool,
    /// Whether `faces` is part of the mask.
    pub has_faces: bool,
}

impl VertexMask {
    /// All weights zero, with room for `num_edges` edges and `num_faces` faces.
    pub(crate) fn reset(&mut self, num_edges: usize, num_faces: usize) {
        self.vertex = 0.0;
        self.edges.clear();
        self.edges.resize(num_edges, 0.0);
        self.faces.clear();
        self.faces.resize(num_faces, 0.0);
        self.has_edges = false;
        self.has_faces = false;
    }

    /// The corner mask: the vertex itself.
    pub(crate) fn set_corner(&mut self, num_edges: usize, num_faces: usize) {
        self.reset(num_edges, num_faces);
        self.vertex = 1.0;
    }

    /// The crease mask `[end, centre, end]` along the sharp edges `ends`.
    pub(crate) fn set_crease(
        &mut self,
        num_edges: usize,
        num_faces: usize,
        ends: (usize, usize),
        [end, centre, _]: [f64; 3],
    ) {
        self.reset(num_edges, num_faces);
        self.vertex = centre;
        if num_edges > 0 {
            self.edges[ends.0] = end;
            self.edges[ends.1] = end;
        }
        self.has_edges = true;
    }

    /// The smooth mask of valence `valence` with weights `(vertex, each edge, each face)`.
    pub(crate) fn set_smooth(&mut self, valence: usize, (vw, ew, fw): (f64, f64, f64)) {
        self.reset(valence, valence);
        self.vertex = vw;
        self.edges.fill(ew);
        self.faces.fill(fw);
        self.has_edges = true;
        self.has_faces = true;
    }

    /// `self ← parent_w · self + (1 - parent_w) · child` (OpenSubdiv's
    /// `CombineVertexVertexMasks`).
    pub(crate) fn blend_with(&mut self, child: &VertexMask, parent_w: f64) {
        let child_w = 1.0 - parent_w;
        self.vertex = parent_w * self.vertex + child_w * child.vertex;
        if child.has_edges {
            if self.has_edges {
                for (d, s) in self.edges.iter_mut().zip(&child.edges) {
                    *d = parent_w * *d + child_w * s;
                }
            } else {
                for (d, s) in self.edges.iter_mut().zip(&child.edges) {
                    *d = child_w * s;
                }
                self.has_edges = true;
            }
        }
        if child.has_faces {
            if self.has_faces {
                for (d, s) in self.faces.iter_mut().zip(&child.faces) {
                    *d = parent_w * *d + child_w * s;
                }
            } else {
                for (d, s) in self.faces.iter_mut().zip(&child.faces) {
                    *d = child_w * s;
                }
                self.has_faces = true;
            }
        }
    }
}

/// Everything the vertex-point mask of one vertex depends on.
#[derive(Clone, Copy, Debug)]
pub struct VertexContext<'a> {
    /// Rule of the vertex before the step.
    pub parent_rule: Rule,
    /// Rule of its child vertex after the step.
    pub child_rule: Rule,
    /// Vertex sharpness before the step.
    pub parent_sharpness: f32,
    /// Vertex sharpness after the step.
    pub child_sharpness: f32,
    /// Sharpness of each incident edge before the step (rotational order).
    pub parent_edges: &'a [f32],
    /// Sharpness of each incident edge's child at this vertex after the step.
    pub child_edges: &'a [f32],
    /// Number of incident faces.
    pub num_faces: usize,
}

/// Limit position mask of a vertex with rule `rule`, incident edge sharpness
/// `edge_sharpness` (rotational order) and `num_faces` faces, all quads
/// (OpenSubdiv's `ComputeVertexLimitMask`):
/// - smooth, valence `n ≠ 2`: `v·(1 - n(4w + w)) + 4w Σ eᵢ + w Σ dᵢ` with
///   `w = 1/(n(n+5))` (`dᵢ` the vertex opposite in face `i`); `n = 4`: 4/9, 1/9, 1/36;
/// - crease: `⅔ v + ⅙ (e_a + e_b)`; corner (and smooth valence 2): `v`.
pub(crate) fn limit_position_mask(
    rule: Rule,
    edge_sharpness: &[f32],
    num_faces: usize,
    m: &mut VertexMask,
) {
    let ne = edge_sharpness.len();
    match rule {
        Rule::Smooth | Rule::Dart => {
            let n = num_faces;
            if n == 2 {
                m.set_corner(ne, num_faces);
                return;
            }
            m.reset(ne, num_faces);
            m.has_edges = true;
            m.has_faces = true;
            if n == 4 {
                m.vertex = 4.0 / 9.0;
                m.edges.fill(1.0 / 9.0);
                m.faces.fill(1.0 / 36.0);
            } else {
                let nn = n as f64;
                let fw = 1.0 / (nn * (nn + 5.0));
                let ew = 4.0 * fw;
                m.vertex = 1.0 - nn * (ew + fw);
                m.edges.fill(ew);
                m.faces.fill(fw);
            }
        }
        Rule::Crease => {
            let (a, b) = crease::crease_ends(edge_sharpness);
            m.reset(ne, num_faces);
            m.has_edges = true;
            m.vertex = 2.0 / 3.0;
            m.edges[a] = 1.0 / 6.0;
            m.edges[b] = 1.0 / 6.0;
        }
        Rule::Corner => m.set_corner(ne, num_faces),
    }
}

/// Limit tangent masks (first and second tangent) of a vertex, as
/// [`limit_position_mask`] (OpenSubdiv's `assign*LimitTangentMasks`):
/// - smooth, valence `n`: `t₁ = Σ 4cos(iθ) eᵢ + Σ (cos iθ + cos (i+1)θ)/(4λ-1) dᵢ`,
///   `θ = 2π/n`, `λ = 5/16 + (cos θ + cos(θ/2)·√(2(9 + cos θ)))/16` the subdominant
///   eigenvalue; `t₂` is `t₁` rotated by one edge;
/// - crease: `t₁ = ½(e_a - e_b)` along the crease, `t₂` across it into the faces between
///   the two crease edges (Biermann et al. 2000 boundary tangent);
/// - corner: `t₁ = e₀ - v`, `t₂ = e₁ - v`.
///
/// `t₁ × t₂` points to the side the faces are counter-clockwise on.
pub(crate) fn limit_tangent_masks(
    rule: Rule,
    edge_sharpness: &[f32],
    num_faces: usize,
    t1: &mut VertexMask,
    t2: &mut VertexMask,
) {
    let ne = edge_sharpness.len();
    match rule {
        Rule::Smooth | Rule::Dart => smooth_tangents(ne, num_faces, t1, t2),
        Rule::Crease => crease_tangents(edge_sharpness, num_faces, t1, t2),
        Rule::Corner => corner_tangents(ne, num_faces, t1, t2),
    }
}

/// The tangent masks at a corner (and at a smooth vertex of two faces): the differences
/// toward the far ends of the first two edges.
fn corner_tangents(ne: usize, nf: usize, t1: &mut VertexMask, t2: &mut VertexMask) {
    t1.reset(ne, nf);
    t2.reset(ne, nf);
    t1.has_edges = true;
    t2.has_edges = true;
    t1.vertex = -1.0;
    t2.vertex = -1.0;
    if ne > 0 {
        t1.edges[0] = 1.0;
    }
    if ne > 1 {
        t2.edges[1] = 1.0;
    }
}

/// The tangent masks at a smooth (or dart) vertex of `nf` faces: the cosine-weighted
/// edge and face sums of the subdominant eigenvectors, the second rotated by one face.
fn smooth_tangents(ne: usize, nf: usize, t1: &mut VertexMask, t2: &mut VertexMask) {
    let n = nf;
    if n == 2 {
        corner_tangents(ne, nf, t1, t2);
        return;
    }
    t1.reset(ne, nf);
    t2.reset(ne, nf);
    for t in [&mut *t1, &mut *t2] {
        t.has_edges = true;
        t.has_faces = true;
    }
    if n == 4 {
        t1.edges.copy_from_slice(&[4.0, 0.0, -4.0, 0.0]);
        t1.faces.copy_from_slice(&[1.0, -1.0, -1.0, 1.0]);
        t2.edges.copy_from_slice(&[0.0, 4.0, 0.0, -4.0]);
        t2.faces.copy_from_slice(&[1.0, 1.0, -1.0, -1.0]);
    } else {
        let theta = 2.0 * PI / n as f64;
        let (c, ch) = (theta.cos(), (0.5 * theta).cos());
        let lambda = 5.0 / 16.0 + (c + ch * (2.0 * (9.0 + c)).sqrt()) / 16.0;
        let fscale = 1.0 / (4.0 * lambda - 1.0);
        for i in 0..n {
            let ci = (i as f64 * theta).cos();
            let ci1 = ((i + 1) as f64 * theta).cos();
            t1.edges[i] = 4.0 * ci;
            t1.faces[i] = fscale * (ci + ci1);
        }
        for i in 0..n {
            let j = (i + n - 1) % n;
            t2.edges[i] = t1.edges[j];
            t2.faces[i] = t1.faces[j];
        }
    }
}

/// The tangent masks at a crease vertex: along the crease, the difference of its two
/// ends; across it, the sine-weighted sum over the edges and faces between them (one
/// edge between them, or none, have their own closed forms).
fn crease_tangents(edge_sharpness: &[f32], nf: usize, t1: &mut VertexMask, t2: &mut VertexMask) {
    let ne = edge_sharpness.len();
    let (a, b) = crease::crease_ends(edge_sharpness);
    t1.reset(ne, nf);
    t1.has_edges = true;
    t1.has_faces = true;
    t1.edges[a] = 0.5;
    t1.edges[b] = -0.5;
    t2.reset(ne, nf);
    t2.has_edges = true;
    t2.has_faces = true;
    let interior = b.saturating_sub(a).saturating_sub(1);
    if interior == 1 {
        t2.vertex = -4.0 / 6.0;
        t2.edges[a] = -1.0 / 6.0;
        t2.edges[a + 1] = 4.0 / 6.0;
        t2.edges[b] = -1.0 / 6.0;
        t2.faces[a] = 1.0 / 6.0;
        t2.faces[a + 1] = 1.0 / 6.0;
    } else if interior > 1 {
        let k = (interior + 1) as f64;
        let theta = PI / k;
        let (c, s) = (theta.cos(), theta.sin());
        let denom = 1.0 / (k * (3.0 + c));
        let r = (c + 1.0) / s;
        t2.vertex = 4.0 * r * (c - 1.0) * denom;
        t2.edges[a] = -r * (1.0 + 2.0 * c) * denom;
        t2.edges[b] = -r * (1.0 + 2.0 * c) * denom;
        t2.faces[a] = s * denom;
        let mut s_next = s;
        for i in 1..=interior {
            let s_i = s_next;
            s_next = ((i + 1) as f64 * theta).sin();
            t2.edges[a + i] = 4.0 * s_i * denom;
            t2.faces[a + i] = (s_i + s_next) * denom;
        }
    } else {
        t2.vertex = -6.0;
        t2.edges[a] = 3.0;
        t2.edges[b] = 3.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::CreaseMethod;

    fn sum(m: &VertexMask) -> f64 {
        m.vertex
            + m.edges.iter().sum::<f64>() * m.has_edges as u8 as f64
            + m.faces.iter().sum::<f64>() * m.has_faces as u8 as f64
    }

    #[test]
    fn edge_masks_sum_to_one() {
        let o = Options::default();
        for s in [0.0f32, 0.3, 0.7, 1.0, 2.0, 10.0] {
            for rule in [Rule::Smooth, Rule::Crease] {
                let m = CatmullClark.edge_mask(&o, s, rule, 2, [false; 2]);
                assert!((2.0 * m.vertex + m.faces[0] + m.faces[1] - 1.0).abs() < 1e-15);
            }
        }
        let tri = Options {
            triangles: TriangleSubdivision::Smooth,
            ..o
        };
        let m = CatmullClark.smooth_edge_mask(&tri, 2, [true, false]);
        assert!((2.0 * m.vertex + 2.0 * m.faces[0] - 1.0).abs() < 1e-15);
        assert!((m.faces[0] - 0.36).abs() < 1e-15);
    }

    #[test]
    fn transitional_edge_mask_blends_by_sharpness() {
        let o = Options::default();
        let m = CatmullClark.edge_mask(&o, 0.25, Rule::Smooth, 2, [false; 2]);
        assert!((m.vertex - (0.25 * 0.5 + 0.75 * 0.25)).abs() < 1e-15);
        assert!((m.faces[0] - 0.75 * 0.25).abs() < 1e-15);
    }

    #[test]
    fn vertex_masks_sum_to_one_for_every_possible_rule_change() {
        let rules = [Rule::Smooth, Rule::Dart, Rule::Crease, Rule::Corner];
        let mut m = VertexMask::default();
        let mut s = VertexMask::default();
        let pe = [0.5f32, 0.0, 0.8, 0.0, 0.0];
        // Child edges: the same two edges stay sharp, so crease masks find their ends.
        let ce = [0.25f32, 0.0, 0.5, 0.0, 0.0];
        // Sharpness only decays, so a child's rule is never sharper than its parent's
        // (OpenSubdiv's mask blending relies on that too).
        for (i, &p) in rules.iter().enumerate() {
            for &c in &rules[..=i] {
                let ctx = VertexContext {
                    parent_rule: p,
                    child_rule: c,
                    parent_sharpness: 0.4,
                    child_sharpness: 0.0,
                    parent_edges: &pe,
                    child_edges: &ce,
                    num_faces: 5,
                };
                CatmullClark.vertex_mask(CreaseMethod::Uniform, &ctx, &mut m, &mut s);
                assert!((sum(&m) - 1.0).abs() < 1e-14, "{p:?}->{c:?}: {}", sum(&m));
            }
        }
    }

    #[test]
    fn limit_masks_sum_to_one_and_tangents_to_zero() {
        let mut m = VertexMask::default();
        let (mut t1, mut t2) = (VertexMask::default(), VertexMask::default());
        for n in 3..12 {
            let es = vec![0.0f32; n];
            limit_position_mask(Rule::Smooth, &es, n, &mut m);
            assert!((sum(&m) - 1.0).abs() < 1e-14);
            limit_tangent_masks(Rule::Smooth, &es, n, &mut t1, &mut t2);
            assert!(sum(&t1).abs() < 1e-12 && sum(&t2).abs() < 1e-12, "n={n}");
        }
        for n in 2..8 {
            // Boundary vertex: n edges, n-1 faces, crease along the first and last.
            let mut es = vec![0.0f32; n];
            es[0] = 10.0;
            es[n - 1] = 10.0;
            limit_position_mask(Rule::Crease, &es, n - 1, &mut m);
            assert!((sum(&m) - 1.0).abs() < 1e-14);
            limit_tangent_masks(Rule::Crease, &es, n - 1, &mut t1, &mut t2);
            assert!(sum(&t1).abs() < 1e-12 && sum(&t2).abs() < 1e-12, "n={n}");
        }
    }

    /// The valence-4 smooth limit mask is the bicubic B-spline's value at a knot:
    /// (1/6, 4/6, 1/6) ⊗ (1/6, 4/6, 1/6).
    #[test]
    fn regular_limit_mask_is_tensor_bspline() {
        let mut m = VertexMask::default();
        limit_position_mask(Rule::Smooth, &[0.0; 4], 4, &mut m);
        assert!((m.vertex - (4.0 / 6.0) * (4.0 / 6.0)).abs() < 1e-15);
        assert!((m.edges[0] - (1.0 / 6.0) * (4.0 / 6.0)).abs() < 1e-15);
        assert!((m.faces[0] - (1.0 / 6.0) * (1.0 / 6.0)).abs() < 1e-15);
    }
}
