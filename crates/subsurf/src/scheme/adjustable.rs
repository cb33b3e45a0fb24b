//! Masks of the shape-adjustable Catmull-Clark scheme with parameter `0 ≤ c ≤ 1`
//! ([Tang et al. 2017], "shape-adjustable Catmull-Clark"; docs/references.md).
//!
//! For a vertex `v` of valence `n` with far edge ends `eᵢ` and new face points `Fᵢ`:
//! - face point: `F = (1/m) Σ` of the face's `m` vertices (as Catmull-Clark);
//! - edge point: `E = c·(F₀ + F₁)/2 + (1 − c)·(v₀ + v₁)/2`;
//! - vertex point: `v' = (4c² Q + 8c(1−c) R + (n − 4c(2−c)) v) / n` with `Q` the average of
//!   the new face points around `v` and `R` the average of the midpoints of its edges.
//!   Expanded (`R = v/2 + Σeᵢ/(2n)`, `Q = ΣFᵢ/n`):
//!   `v' = (n − 4c)/n · v + 4c(1−c)/n² · Σ eᵢ + 4c²/n² · Σ Fᵢ`.
//!
//! The seed's text lost its exponents; this form is the one with all the properties the
//! seed states, each checked by a test below: the weights sum to 1 (affine invariance);
//! `c = ½` gives Catmull-Clark exactly (`(n−2)/n`, `1/n²`, `1/n²`, and the edge mask
//! `¼, ¼, ¼, ¼`; every weight is then bit for bit the [`CatmullClark`] one); `c = 0` leaves
//! every old vertex where it is (vertex weight 1, edge points are midpoints, face points
//! centroids: the bilinear refinement of the control mesh); and on a regular grid
//! (`n = 4`) the masks are the tensor product of the curve scheme
//! `p'₂ᵢ = (c/4) pᵢ₋₁ + (1 − c/2) pᵢ + (c/4) pᵢ₊₁`, `p'₂ᵢ₊₁ = (pᵢ + pᵢ₊₁)/2`
//! (`c = ½`: the cubic B-spline; `c = 0`: the control polygon).
//!
//! # Boundaries, creases, corners (derived here; the seed does not treat them)
//! A sharp edge is refined with the curve scheme along it, as Catmull-Clark uses the cubic
//! B-spline along it: the edge point is the midpoint (`p'₂ᵢ₊₁`) and a crease vertex with
//! sharp edges to `e_a`, `e_b` takes `(1 − c/2) v + (c/4)(e_a + e_b)` (`p'₂ᵢ`); corners stay
//! fixed. This is what the tensor-product structure gives on the boundary row of a regular
//! grid whose boundary is the limit of its own curve, and at `c = ½` it is OpenSubdiv's
//! crease rule `¾ v + ⅛ (e_a + e_b)`. Semi-sharp features are handled exactly as
//! OpenSubdiv handles them for Catmull-Clark (sharpness decays one per step, or by
//! Chaikin's rule; in the step where a feature becomes smooth, the edge mask is
//! `s·crease + (1 − s)·smooth` and the vertex mask blends the parent-rule and child-rule
//! masks by [`fractional_weight`](super::crease::fractional_weight)), with the `c` masks in place of the cubic ones.
//! Non-manifold edges with `m ≠ 2` faces give each face point `c/m` (Catmull-Clark: `½/m`).
//! With [`TriangleSubdivision::Smooth`] a triangle's face weight `f` (0.47 in
//! Catmull-Clark) scales with `2c`, as every face weight does: faces `2c·f`, ends
//! `½(1 − 4c·f)`.
//!
//! [`TriangleSubdivision::Smooth`]: crate::mesh::TriangleSubdivision::Smooth

use super::catmark::{CatmullClark, EdgeMask};
use super::Rules;
use crate::mesh::{Options, TriangleSubdivision};

/// The shape parameter `c` of the adjustable scheme, checked to lie in `[0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adjustable {
    c: f64,
}

/// An invalid shape parameter.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum AdjustableError {
    /// `c` is not a finite number in `[0, 1]`.
    #[error("shape parameter c = {c} is outside [0, 1]")]
    OutOfRange {
        /// The value given.
        c: f64,
    },
}

impl Adjustable {
    /// `c = ½`: Catmull-Clark.
    pub const CATMULL_CLARK: Adjustable = Adjustable { c: 0.5 };

    /// The scheme with parameter `c`.
    ///
    /// # Errors
    /// `AdjustableError::OutOfRange` unless `0 ≤ c ≤ 1`.
    pub fn new(c: f64) -> Result<Self, AdjustableError> {
        if (0.0..=1.0).contains(&c) {
            Ok(Self { c })
        } else {
            Err(AdjustableError::OutOfRange { c })
        }
    }

    /// The parameter `c`.
    pub fn c(self) -> f64 {
        self.c
    }

    /// The curve scheme's even rule `(c/4, 1 − c/2, c/4)`: weights of `pᵢ₋₁, pᵢ, pᵢ₊₁` in
    /// `p'₂ᵢ` (the odd rule is the midpoint).
    pub fn curve_even_weights(self) -> [f64; 3] {
        let c = self.c;
        [0.25 * c, 1.0 - 0.5 * c, 0.25 * c]
    }
}

/// The shape-adjustable masks (module docs); every weight at `c = ½` is Catmull-Clark's
/// bit for bit.
impl Rules for Adjustable {
    /// The smooth edge mask for an edge with `num_faces` faces, the first two of which are
    /// triangles as `tri` says: faces `c/m` each (`m = num_faces`), ends `(1 − c)/2` each;
    /// with the smooth-triangle rule the Catmull-Clark face weight `f` becomes `2c·f` and
    /// the ends `½(1 − 4c·f)`.
    fn smooth_edge_mask(self, options: &Options, num_faces: usize, tri: [bool; 2]) -> EdgeMask {
        let c = self.c;
        let use_tri = options.triangles == TriangleSubdivision::Smooth
            && num_faces == 2
            && (tri[0] || tri[1]);
        if use_tri {
            let m = CatmullClark.smooth_edge_mask(options, num_faces, tri);
            let f = 2.0 * c * m.faces[0];
            EdgeMask {
                vertex: 0.5 * (1.0 - 2.0 * f),
                faces: [f; 2],
                other_faces: 0.0,
            }
        } else {
            let w = if num_faces == 2 {
                0.5 * c
            } else {
                c / num_faces.max(1) as f64
            };
            EdgeMask {
                vertex: 0.5 * (1.0 - c),
                faces: [w; 2],
                other_faces: if num_faces == 2 { 0.0 } else { w },
            }
        }
    }

    /// Smooth vertex weights `(vertex, each edge end, each face point)` for valence `n`:
    /// `((n − 4c)/n, 4c(1−c)/n², 4c²/n²)`.
    #[inline]
    fn smooth_vertex_weights(self, n: usize) -> (f64, f64, f64) {
        let c = self.c;
        let n = n as f64;
        let nn = n * n;
        (
            (n - 4.0 * c) / n,
            4.0 * c * (1.0 - c) / nn,
            4.0 * c * c / nn,
        )
    }

    /// The curve scheme's even rule, [`curve_even_weights`](Adjustable::curve_even_weights).
    #[inline]
    fn crease_vertex_weights(self) -> [f64; 3] {
        self.curve_even_weights()
    }
}

impl Default for Adjustable {
    /// Catmull-Clark (`c = ½`).
    fn default() -> Self {
        Self::CATMULL_CLARK
    }
}

/// Parameters of mixed subdivision ([Tang et al. 2017]): the adjustable scheme on the first
/// `steps` refinement steps, then Catmull-Clark.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mixed {
    /// The shape-adjustable scheme (parameter `c`).
    pub scheme: Adjustable,
    /// Number of leading refinement steps that use `scheme`; later steps are
    /// Catmull-Clark. `u32::MAX`: every step.
    pub steps: u32,
}

impl Mixed {
    /// Catmull-Clark on every step (no adjusted step).
    pub(crate) const CATMULL_CLARK: Mixed = Mixed {
        scheme: Adjustable::CATMULL_CLARK,
        steps: 0,
    };

    /// Every refinement step uses `scheme`.
    pub fn all(scheme: Adjustable) -> Self {
        Self {
            scheme,
            steps: u32::MAX,
        }
    }

    /// The masks of step `l` (from 1): `scheme` on the first `steps`, then Catmull-Clark.
    pub(crate) fn step(self, l: u32) -> Adjustable {
        if l <= self.steps {
            self.scheme
        } else {
            Adjustable::CATMULL_CLARK
        }
    }

    /// The schemes of the steps after the first `k`.
    pub(crate) fn after(self, k: u32) -> Mixed {
        Mixed {
            steps: self.steps.saturating_sub(k),
            ..self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{CreaseMethod, Rule};
    use crate::scheme::catmark::{VertexContext, VertexMask};

    fn sum(m: &VertexMask) -> f64 {
        m.vertex
            + if m.has_edges {
                m.edges.iter().sum()
            } else {
                0.0
            }
            + if m.has_faces {
                m.faces.iter().sum()
            } else {
                0.0
            }
    }

    fn cs() -> impl Iterator<Item = Adjustable> {
        [0.0, 0.1, 0.25, 0.5, 0.7, 0.9, 1.0]
            .into_iter()
            .map(|c| Adjustable::new(c).expect("c in [0, 1]"))
    }

    const RULES: [Rule; 4] = [Rule::Smooth, Rule::Dart, Rule::Crease, Rule::Corner];

    /// Every rule change a vertex can undergo (sharpness only decays), with the context
    /// that triggers it.
    fn contexts<'a>(pe: &'a [f32], ce: &'a [f32], num_faces: usize) -> Vec<VertexContext<'a>> {
        let mut out = Vec::new();
        for (i, &p) in RULES.iter().enumerate() {
            for &c in &RULES[..=i] {
                out.push(VertexContext {
                    parent_rule: p,
                    child_rule: c,
                    parent_sharpness: 0.4,
                    child_sharpness: 0.0,
                    parent_edges: pe,
                    child_edges: ce,
                    num_faces,
                });
            }
        }
        out
    }

    #[test]
    fn c_must_lie_in_the_unit_interval() {
        for c in [-1e-300, 1.0 + 1e-15, f64::NAN, f64::INFINITY] {
            assert!(Adjustable::new(c).is_err(), "{c}");
        }
        assert_eq!(Adjustable::new(0.5), Ok(Adjustable::CATMULL_CLARK));
        assert_eq!(Adjustable::default().c(), 0.5);
    }

    #[test]
    fn every_mask_sums_to_one() {
        let pe = [0.5f32, 0.0, 0.8, 0.0, 0.0];
        // Child edges: the same two edges stay sharp, so crease masks find their ends.
        let ce = [0.25f32, 0.0, 0.5, 0.0, 0.0];
        let tri = Options {
            triangles: TriangleSubdivision::Smooth,
            ..Options::default()
        };
        for a in cs() {
            for o in [Options::default(), tri] {
                for s in [0.0f32, 0.3, 1.0, 10.0] {
                    for rule in [Rule::Smooth, Rule::Crease] {
                        for (nf, t) in [(2, [false; 2]), (2, [true, false]), (3, [false; 2])] {
                            let m = a.edge_mask(&o, s, rule, nf, t);
                            let total = 2.0 * m.vertex
                                + m.faces[..nf.min(2)].iter().sum::<f64>()
                                + m.other_faces * nf.saturating_sub(2) as f64;
                            assert!((total - 1.0).abs() < 1e-14, "c={} {total}", a.c());
                        }
                    }
                }
            }
            for n in 1..12 {
                let (v, e, f) = a.smooth_vertex_weights(n);
                let nf = n as f64;
                assert!((v + nf * (e + f) - 1.0).abs() < 1e-14);
            }
            let (mut m, mut child) = (VertexMask::default(), VertexMask::default());
            for method in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
                for ctx in contexts(&pe, &ce, 5) {
                    a.vertex_mask(method, &ctx, &mut m, &mut child);
                    assert!((sum(&m) - 1.0).abs() < 1e-14, "{ctx:?}");
                }
            }
        }
    }

    /// `c = ½` is Catmull-Clark: every mask equals OpenSubdiv's, bit for bit.
    #[test]
    fn one_half_is_catmull_clark_exactly() {
        let a = Adjustable::CATMULL_CLARK;
        let tri = Options {
            triangles: TriangleSubdivision::Smooth,
            ..Options::default()
        };
        for o in [Options::default(), tri] {
            for s in [0.0f32, 0.25, 0.7, 1.0, 3.0, 10.0] {
                for rule in RULES {
                    for nf in 1..6 {
                        for t in [[false; 2], [true, false], [false, true], [true, true]] {
                            assert_eq!(
                                a.edge_mask(&o, s, rule, nf, t),
                                CatmullClark.edge_mask(&o, s, rule, nf, t),
                                "s={s} {rule:?} faces={nf} tri={t:?}"
                            );
                        }
                    }
                }
            }
        }
        let pe = [0.5f32, 0.0, 0.8, 0.0, 2.0, 0.0];
        let ce = [0.25f32, 0.0, 0.0, 0.0, 1.0, 0.0];
        let (mut m, mut child) = (VertexMask::default(), VertexMask::default());
        let mut cc = VertexMask::default();
        let mut scratch = VertexMask::default();
        for method in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
            for ctx in contexts(&pe, &ce, 6)
                .into_iter()
                .chain(contexts(&pe[..4], &ce[..4], 3))
            {
                a.vertex_mask(method, &ctx, &mut m, &mut child);
                CatmullClark.vertex_mask(method, &ctx, &mut cc, &mut scratch);
                assert_eq!(m.vertex, cc.vertex, "{ctx:?}");
                assert_eq!(m.has_edges, cc.has_edges);
                assert_eq!(m.has_faces, cc.has_faces);
                if m.has_edges {
                    assert_eq!(m.edges, cc.edges, "{ctx:?}");
                }
                if m.has_faces {
                    assert_eq!(m.faces, cc.faces, "{ctx:?}");
                }
            }
        }
    }

    /// `c = 0` keeps every old vertex, makes edge points midpoints; face points are
    /// centroids for every `c`.
    #[test]
    fn zero_keeps_the_control_points() {
        let a = Adjustable::new(0.0).expect("valid");
        let pe = [0.5f32, 0.0, 0.8, 0.0, 0.0];
        let ce = [0.25f32, 0.0, 0.5, 0.0, 0.0];
        let (mut m, mut child) = (VertexMask::default(), VertexMask::default());
        for ctx in contexts(&pe, &ce, 5) {
            a.vertex_mask(CreaseMethod::Uniform, &ctx, &mut m, &mut child);
            assert_eq!(m.vertex, 1.0, "{ctx:?}");
            assert!(m.edges.iter().chain(&m.faces).all(|&w| w == 0.0));
        }
        for s in [0.0f32, 0.5, 10.0] {
            for nf in 1..5 {
                let e = a.edge_mask(&Options::default(), s, Rule::Smooth, nf, [false; 2]);
                assert_eq!((e.vertex, e.faces, e.other_faces), (0.5, [0.0; 2], 0.0));
            }
        }
        assert_eq!(crate::scheme::catmark::face_point_weight(5), 0.2);
    }

    /// On a regular grid the vertex and edge masks, written on the 3×3 (resp. 2×3)
    /// neighbourhood of control points (a face point is the average of its quad), are the
    /// tensor products of the curve rules `(c/4, 1 − c/2, c/4)` and `(½, ½)`.
    #[test]
    fn regular_masks_are_tensor_products_of_the_curve_scheme() {
        for a in cs() {
            let even = a.curve_even_weights();
            let odd = [0.5, 0.5];
            // Vertex at grid (1, 1); edges to (2,1), (1,2), (0,1), (1,0) in that order; face i
            // between edges i and i+1 has the diagonal corner.
            let (vw, ew, fw) = a.smooth_vertex_weights(4);
            let mut g = [[0.0; 3]; 3];
            g[1][1] += vw;
            let ends = [(2, 1), (1, 2), (0, 1), (1, 0)];
            for (i, &(x, y)) in ends.iter().enumerate() {
                g[x][y] += ew;
                let (x1, y1) = ends[(i + 1) % 4];
                let diag = (x + x1 - 1, y + y1 - 1);
                for p in [(1, 1), (x, y), (x1, y1), diag] {
                    g[p.0][p.1] += fw / 4.0;
                }
            }
            for x in 0..3 {
                for y in 0..3 {
                    let want = even[x] * even[y];
                    assert!((g[x][y] - want).abs() < 1e-15, "c={} ({x},{y})", a.c());
                }
            }
            // Edge from (0, 1) to (1, 1) with faces below (y 0..1) and above (y 1..2).
            let e = a.edge_mask(&Options::default(), 0.0, Rule::Smooth, 2, [false; 2]);
            let mut h = [[0.0; 3]; 2];
            for x in 0..2 {
                h[x][1] += e.vertex;
                for (j, y) in [(0, 0), (1, 2)] {
                    h[x][1] += e.faces[j] / 4.0;
                    h[x][y] += e.faces[j] / 4.0;
                }
            }
            for x in 0..2 {
                for y in 0..3 {
                    assert!((h[x][y] - odd[x] * even[y]).abs() < 1e-15, "c={}", a.c());
                }
            }
        }
    }

    /// The crease mask is the curve scheme's even rule along the two sharp edges.
    #[test]
    fn crease_vertices_follow_the_curve_scheme() {
        for a in cs() {
            let pe = [10.0f32, 0.0, 0.0, 10.0];
            let ctx = VertexContext {
                parent_rule: Rule::Crease,
                child_rule: Rule::Crease,
                parent_sharpness: 0.0,
                child_sharpness: 0.0,
                parent_edges: &pe,
                child_edges: &pe,
                num_faces: 3,
            };
            let (mut m, mut child) = (VertexMask::default(), VertexMask::default());
            a.vertex_mask(CreaseMethod::Uniform, &ctx, &mut m, &mut child);
            let [w, centre, _] = a.curve_even_weights();
            assert_eq!(m.vertex, centre);
            assert_eq!(m.edges, vec![w, 0.0, 0.0, w]);
            assert!(!m.has_faces);
        }
    }
}
