//! Loop subdivision of triangle meshes with OpenSubdiv's rules
//! (`Sdc::Scheme<SCHEME_LOOP>`).
//!
//! Every triangle splits into four (C. Loop, "Smooth Subdivision Surfaces Based on
//! Triangles", M.S. thesis, University of Utah, 1987, §3):
//! - edge point, smooth: `⅜(v₀ + v₁) + ⅛(o₀ + o₁)` with `oᵢ` the vertex opposite the edge
//!   in its two triangles (`¼/m` per opposite vertex on an edge with `m ≠ 2` faces, as
//!   OpenSubdiv keeps the ratio of the two parts); crease: `½(v₀ + v₁)`; a semi-sharp
//!   edge whose sharpness `s < 1` decays in the step blends the two with weight `s` on the
//!   crease mask;
//! - vertex point, smooth, valence `n`: `(1 − nβₙ) v + βₙ Σ eᵢ` with Loop's
//!   `βₙ = (⅝ − (⅜ + ¼ cos(2π/n))²)/n` (thesis §3.1; `β₆ = 1/16`); crease:
//!   `¾ v + ⅛(e_a + e_b)` along the two sharp edges; corner: `v`;
//! - the choice of mask and the blends during a step in which a semi-sharp feature decays
//!   are the rules of [`Rules`] (Hoppe et al., "Piecewise Smooth Surface Reconstruction",
//!   SIGGRAPH 1994, for the sharp masks; DeRose, Kass, Truong, "Subdivision Surfaces in
//!   Character Animation", SIGGRAPH 1998, §3, for semi-sharp creases), shared with the
//!   Catmull-Clark family.
//!
//! Loop has no face points: in the masks of this scheme the face weights of an
//! [`EdgeMask`] weigh the vertex of each incident triangle opposite the edge, and the
//! vertex masks have no face weights.

use super::catmark::{EdgeMask, VertexMask};
use super::{crease, Rules};
use crate::mesh::{Options, Rule};
use std::f64::consts::PI;

/// Loop's rules ([`Rules`]): OpenSubdiv's `Sdc::Scheme<SCHEME_LOOP>`. The refinement that
/// applies them is [`refine::TopologyRefiner`](crate::refine::TopologyRefiner) with [`Scheme::Loop`](crate::Scheme::Loop).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Loop;

/// Loop's `βₙ`, the weight of each neighbour of a smooth vertex of valence `n`:
/// `(⅝ − (⅜ + ¼ cos(2π/n))²)/n`, `1/16` at `n = 6` (computed as OpenSubdiv's
/// `assignSmoothMaskForVertex` does, in `f64`).
pub(crate) fn beta(n: usize) -> f64 {
    if n == 6 {
        return 0.0625;
    }
    let inv = 1.0 / n as f64;
    let b = 0.25 * (PI * 2.0 * inv).cos() + 0.375;
    (0.625 - b * b) * inv
}

impl Rules for Loop {
    /// `⅜` of each end and `⅛` of each opposite vertex; `¼/m` per opposite vertex on an
    /// edge with `m ≠ 2` faces (OpenSubdiv's `assignSmoothMaskForEdge`).
    fn smooth_edge_mask(self, _: &Options, num_faces: usize, _: [bool; 2]) -> EdgeMask {
        let f = if num_faces == 2 {
            0.125
        } else {
            0.125 * (2.0 / num_faces as f64)
        };
        EdgeMask {
            vertex: 0.375,
            faces: [f; 2],
            other_faces: f,
        }
    }

    /// `(1 − nβₙ, βₙ, 0)` with [`beta`].
    #[inline]
    fn smooth_vertex_weights(self, n: usize) -> (f64, f64, f64) {
        let b = beta(n);
        (1.0 - b * n as f64, b, 0.0)
    }

    /// `(⅛, ¾, ⅛)`: the cubic B-spline's even rule, as for Catmull-Clark.
    #[inline]
    fn crease_vertex_weights(self) -> [f64; 3] {
        [0.125, 0.75, 0.125]
    }

    /// Loop splits triangles: no face points; edge masks weigh the opposite vertices.
    #[inline]
    fn splits_triangles(self) -> bool {
        true
    }

    /// Loop's limit positions (OpenSubdiv's `assign*LimitMask` for `SCHEME_LOOP`):
    /// - smooth (and dart), valence `n`: `(1 − nε) v + ε Σ eᵢ` with
    ///   `ε = 1/(n + 3/(8βₙ))` and Loop's [`beta`] (Loop 1987, §3.2, the left eigenvector of
    ///   the subdivision matrix; `½ v + 1/12 Σ eᵢ` at `n = 6`), at every valence;
    /// - crease: `⅔ v + ⅙(e_a + e_b)` along the two sharp edges (the cubic B-spline's limit,
    ///   whatever the valence);
    /// - corner: `v`.
    fn limit_position_mask(
        self,
        rule: Rule,
        edge_sharpness: &[f32],
        num_faces: usize,
        m: &mut VertexMask,
    ) {
        let ne = edge_sharpness.len();
        match rule {
            Rule::Smooth | Rule::Dart if num_faces == 6 => {
                m.reset(ne, num_faces);
                m.has_edges = true;
                m.vertex = 0.5;
                m.edges.fill(1.0 / 12.0);
            }
            Rule::Smooth | Rule::Dart => {
                // OpenSubdiv's order of operations, in f64.
                let n = num_faces as f64;
                let inv = 1.0 / n;
                let b = 0.25 * (PI * 2.0 * inv).cos() + 0.375;
                let gamma = (0.625 - b * b) * inv;
                let e = 1.0 / (n + 3.0 / (8.0 * gamma));
                m.reset(ne, num_faces);
                m.has_edges = true;
                m.vertex = 1.0 - e * n;
                m.edges.fill(e);
            }
            Rule::Crease => {
                let (a, b) = crease::crease_ends(edge_sharpness);
                m.reset(ne, num_faces);
                m.has_edges = true;
                m.vertex = 4.0 / 6.0;
                m.edges[a] = 1.0 / 6.0;
                m.edges[b] = 1.0 / 6.0;
            }
            Rule::Corner => m.set_corner(ne, num_faces),
        }
    }

    /// Loop's limit tangents (OpenSubdiv's `assign*LimitTangentMasks` for `SCHEME_LOOP`,
    /// scaled as it scales them so that tangents of a regular mesh are alike in size):
    /// smooth, valence `n > 2`: `t₁ = Σ cos(2πi/n) eᵢ`, `t₂ = Σ sin(2πi/n) eᵢ` (at valence 2,
    /// where these are parallel, the corner's, so that the normal is the two faces'); crease:
    /// `t₁ = 3/2 (e_a − e_b)` along it and `t₂` across the faces between its edges (closed
    /// forms for 0, 1 and 2 edges between them, else sine weights over them); corner:
    /// `3(e₀ − v)` and `3(e₁ − v)`.
    fn limit_tangent_masks(
        self,
        rule: Rule,
        edge_sharpness: &[f32],
        num_faces: usize,
        t1: &mut VertexMask,
        t2: &mut VertexMask,
    ) {
        let ne = edge_sharpness.len();
        for t in [&mut *t1, &mut *t2] {
            t.reset(ne, num_faces);
            t.has_edges = true;
        }
        match rule {
            Rule::Smooth | Rule::Dart if num_faces != 2 => {
                let alpha = 2.0 * PI / num_faces as f64;
                for i in 0..ne.min(num_faces) {
                    t1.edges[i] = (alpha * i as f64).cos();
                    t2.edges[i] = (alpha * i as f64).sin();
                }
            }
            Rule::Crease => crease_tangents(edge_sharpness, t1, t2),
            _ => {
                t1.vertex = -3.0;
                t2.vertex = -3.0;
                if ne > 0 {
                    t1.edges[0] = 3.0;
                }
                if ne > 1 {
                    t2.edges[1] = 3.0;
                }
            }
        }
    }

    /// `⅜(v₀ + v₁) + ⅛(o₀ + o₁)`; `faces` are the two opposite vertices.
    #[inline]
    fn smooth_edge_point<const D: usize>(
        self,
        ends: [&[f64; D]; 2],
        opposite: [&[f64; D]; 2],
    ) -> [f64; D] {
        std::array::from_fn(|k| {
            0.375 * (ends[0][k] + ends[1][k]) + 0.125 * (opposite[0][k] + opposite[1][k])
        })
    }
}

/// Loop's crease tangents (see [`Loop::limit_tangent_masks`]): along the crease from its
/// trailing sharp edge to its leading one, and across the faces between them, into the
/// surface (OpenSubdiv's `assignCreaseLimitTangentMasks`).
fn crease_tangents(edge_sharpness: &[f32], t1: &mut VertexMask, t2: &mut VertexMask) {
    let (a, b) = crease::crease_ends(edge_sharpness);
    t1.edges[a] = 1.5;
    t1.edges[b] = -1.5;
    let interior = b.saturating_sub(a).saturating_sub(1);
    match interior {
        0 => {
            t2.vertex = -6.0;
            t2.edges[a] = 3.0;
            t2.edges[b] = 3.0;
        }
        1 => {
            t2.vertex = -3.0;
            t2.edges[a + 1] = 3.0;
        }
        2 => {
            let root3 = 3f64.sqrt();
            t2.vertex = -root3;
            t2.edges[a] = -0.5 * root3;
            t2.edges[b] = -0.5 * root3;
            t2.edges[a + 1] = root3;
            t2.edges[a + 2] = root3;
        }
        _ => {
            let theta = PI / (interior + 1) as f64;
            let c = -3.0 * theta.sin();
            t2.edges[a] = c;
            t2.edges[b] = c;
            let e = -3.0 * 2.0 * (theta.cos() - 1.0);
            for i in 1..=interior {
                t2.edges[a + i] = e * (i as f64 * theta).sin();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{CreaseMethod, Rule};
    use crate::scheme::catmark::{VertexContext, VertexMask};

    #[test]
    fn beta_is_loops() {
        // Loop's thesis: β₃ = 3/16, β₆ = 1/16; n → ∞: nβₙ → ⅝ − (⅝)² = 15/64 (not
        // Warren's 3/8, which OpenSubdiv does not use).
        assert!((beta(3) - 3.0 / 16.0).abs() < 1e-15);
        assert!((beta(6) - 1.0 / 16.0).abs() < 1e-15);
        assert!((beta(1000) * 1000.0 - 15.0 / 64.0).abs() < 1e-5);
        // The formula at n = 6 agrees with the special case to rounding.
        let b = 0.25 * (PI / 3.0).cos() + 0.375;
        assert!(((0.625 - b * b) / 6.0 - 0.0625).abs() < 1e-16);
    }

    #[test]
    fn masks_sum_to_one() {
        let o = Options::default();
        for m in [2usize, 1, 3, 4] {
            let e = Loop.smooth_edge_mask(&o, m, [false; 2]);
            let total = 2.0 * e.vertex
                + if m >= 2 {
                    e.faces[0] + e.faces[1] + (m - 2) as f64 * e.other_faces
                } else {
                    e.faces[0]
                };
            // One face: ¾ + ¼ = 1 too (⅜ + ⅜ + ¼).
            assert!((total - 1.0).abs() < 1e-15, "m={m}: {total}");
        }
        let mut mask = VertexMask::default();
        let mut child = VertexMask::default();
        for n in 2..20 {
            let pe = vec![0.0f32; n];
            let ctx = VertexContext {
                parent_rule: Rule::Smooth,
                child_rule: Rule::Smooth,
                parent_sharpness: 0.0,
                child_sharpness: 0.0,
                parent_edges: &pe,
                child_edges: &pe,
                num_faces: n,
            };
            Loop.vertex_mask(CreaseMethod::Uniform, &ctx, &mut mask, &mut child);
            let s = mask.vertex + mask.edges.iter().sum::<f64>();
            assert!((s - 1.0).abs() < 1e-14);
            assert!(mask.faces.iter().all(|&w| w == 0.0));
        }
    }
}
