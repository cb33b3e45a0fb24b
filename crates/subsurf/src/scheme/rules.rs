//! The refinement rules of the Catmull-Clark family, written once: which mask a vertex or
//! edge takes (smooth, crease, corner, or a blend of two during the step in which a
//! semi-sharp feature decays), with each scheme giving only its smooth and crease weights,
//! as OpenSubdiv's `Sdc::Scheme<T>` specialises only `assignSmoothMaskForEdge`,
//! `assignCreaseMaskForVertex` and `assignSmoothMaskForVertex`.

use super::catmark::{EdgeMask, VertexContext, VertexMask};
use super::crease;
use crate::mesh::{CreaseMethod, Options, Rule};

/// A scheme of the Catmull-Clark family: face points are centroids, and the edge and
/// vertex points follow from the weights below by the shared rules of
/// [`edge_mask`](Rules::edge_mask) and [`vertex_mask`](Rules::vertex_mask). Loop
/// (`super::loop_::Loop`) shares the rules: it has no face points, and the face weights
/// of its edge masks weigh the vertex opposite the edge in each triangle.
pub trait Rules: Copy + Send + Sync {
    /// The mask of a smooth edge with `num_faces` faces, the first two of which are
    /// triangles as `tri` says.
    fn smooth_edge_mask(self, options: &Options, num_faces: usize, tri: [bool; 2]) -> EdgeMask;

    /// Smooth vertex weights `(vertex, each far edge end, each face point)` at valence `n`.
    fn smooth_vertex_weights(self, n: usize) -> (f64, f64, f64);

    /// The crease vertex weights `[end, centre, end]` along its two sharp edges (the even
    /// rule of the scheme's curve along a crease).
    fn crease_vertex_weights(self) -> [f64; 3];

    /// Whether the scheme splits every triangle into four triangles (Loop: OpenSubdiv's
    /// `Sdc::SPLIT_TO_TRIS`) rather than every face of `n` sides into `n` quads around a
    /// face point (`Sdc::SPLIT_TO_QUADS`, the default). With the triangle split there are
    /// no face points, and the face weights of an `EdgeMask` weigh the vertex opposite
    /// the edge in each triangle (OpenSubdiv's `Mask::AreFaceWeightsForFaceCenters()`
    /// false).
    #[inline]
    fn splits_triangles(self) -> bool {
        false
    }

    /// The point of a smooth edge between two faces (without the smooth-triangle rule):
    /// [`smooth_edge_mask`](Rules::smooth_edge_mask) applied to the two ends and the two
    /// new face points. Schemes may sum in an order of their own.
    #[inline]
    fn smooth_edge_point<const D: usize>(
        self,
        ends: [&[f64; D]; 2],
        faces: [&[f64; D]; 2],
    ) -> [f64; D] {
        let m = self.smooth_edge_mask(&Options::default(), 2, [false; 2]);
        std::array::from_fn(|k| {
            m.vertex * (ends[0][k] + ends[1][k])
                + m.faces[0] * faces[0][k]
                + m.faces[1] * faces[1][k]
        })
    }

    /// The point of a smooth vertex `v` of valence `n`: the weights of
    /// [`smooth_vertex_weights`](Rules::smooth_vertex_weights) on `v`, the far ends of its
    /// edges and its new face points. Schemes may sum in an order of their own.
    #[inline]
    fn smooth_vertex_point<'a, const D: usize>(
        self,
        n: usize,
        v: &[f64; D],
        ends: impl Iterator<Item = &'a [f64; D]>,
        faces: impl Iterator<Item = &'a [f64; D]>,
    ) -> [f64; D] {
        let (vw, ew, fw) = self.smooth_vertex_weights(n);
        let (mut se, mut sf) = ([0.0; D], [0.0; D]);
        for x in ends {
            for k in 0..D {
                se[k] += x[k];
            }
        }
        for x in faces {
            for k in 0..D {
                sf[k] += x[k];
            }
        }
        std::array::from_fn(|k| ew * se[k] + fw * sf[k] + vw * v[k])
    }

    /// The edge-point mask of an edge with sharpness `sharpness` whose new vertex gets
    /// rule `child_rule` (OpenSubdiv's `ComputeEdgeVertexMask`): smooth if the edge is
    /// smooth, the midpoint if the child is a crease vertex, otherwise the transitional
    /// step of a decaying crease, `s · midpoint + (1 − s) · smooth`.
    fn edge_mask(
        self,
        options: &Options,
        sharpness: f32,
        child_rule: Rule,
        num_faces: usize,
        tri: [bool; 2],
    ) -> EdgeMask {
        if !crease::is_sharp(sharpness) {
            return self.smooth_edge_mask(options, num_faces, tri);
        }
        if child_rule == Rule::Crease {
            return EdgeMask::CREASE;
        }
        let m = self.smooth_edge_mask(options, num_faces, tri);
        let p = sharpness as f64;
        let q = 1.0 - p;
        EdgeMask {
            vertex: p * 0.5 + q * m.vertex,
            faces: [m.faces[0] * q, m.faces[1] * q],
            other_faces: m.other_faces * q,
        }
    }

    /// The vertex-point mask into `mask` (OpenSubdiv's `ComputeVertexVertexMask`): smooth
    /// and dart vertices take the smooth mask; otherwise the parent rule's mask (crease
    /// along the two sharp edges, or corner), and if the rule changes during the step, that
    /// mask blended with the child rule's (computed in `child`) with weight
    /// `crease::fractional_weight` on the parent's.
    fn vertex_mask(
        self,
        method: CreaseMethod,
        ctx: &VertexContext,
        mask: &mut VertexMask,
        child: &mut VertexMask,
    ) {
        let valence = ctx.parent_edges.len();
        let set = |m: &mut VertexMask, rule: Rule, edges: &[f32]| match rule {
            Rule::Smooth | Rule::Dart => m.set_smooth(valence, self.smooth_vertex_weights(valence)),
            Rule::Crease => m.set_crease(
                valence,
                ctx.num_faces,
                crease::crease_ends(edges),
                self.crease_vertex_weights(),
            ),
            Rule::Corner => m.set_corner(valence, ctx.num_faces),
        };
        set(mask, ctx.parent_rule, ctx.parent_edges);
        if matches!(ctx.parent_rule, Rule::Smooth | Rule::Dart) || ctx.child_rule == ctx.parent_rule
        {
            return;
        }
        set(child, ctx.child_rule, ctx.child_edges);
        let w = crease::fractional_weight(
            method,
            ctx.parent_sharpness,
            ctx.child_sharpness,
            ctx.parent_edges,
            ctx.child_edges,
        ) as f64;
        mask.blend_with(child, w);
    }

    /// The limit position mask of a vertex of rule `rule` (at the last level) with the
    /// sharpness of its edges `edge_sharpness` (in its edge order) and `num_faces` faces
    /// (OpenSubdiv's `Sdc::Scheme::ComputeVertexLimitMask`). The default is Catmull-Clark's
    /// (see `catmark::limit_position_mask`).
    #[inline]
    fn limit_position_mask(
        self,
        rule: Rule,
        edge_sharpness: &[f32],
        num_faces: usize,
        m: &mut VertexMask,
    ) {
        super::catmark::limit_position_mask(rule, edge_sharpness, num_faces, m);
    }

    /// The two limit tangent masks of a vertex, as
    /// [`limit_position_mask`](Rules::limit_position_mask) (their cross product is the
    /// limit normal's direction). The default is Catmull-Clark's (see
    /// `catmark::limit_tangent_masks`).
    #[inline]
    fn limit_tangent_masks(
        self,
        rule: Rule,
        edge_sharpness: &[f32],
        num_faces: usize,
        t1: &mut VertexMask,
        t2: &mut VertexMask,
    ) {
        super::catmark::limit_tangent_masks(rule, edge_sharpness, num_faces, t1, t2);
    }
}
