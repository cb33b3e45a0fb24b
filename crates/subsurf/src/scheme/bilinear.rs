//! Bilinear subdivision (OpenSubdiv's `Sdc::Scheme<SCHEME_BILINEAR>`): the Catmull-Clark
//! topology split (an `n`-gon gives `n` quads), with face point = the centroid of the
//! face, edge point = the midpoint of the edge and vertex point = the vertex itself,
//! whatever the sharpness of edges and vertices. The refined meshes lie on the faces of
//! the input (piecewise bilinear for quads): OpenSubdiv's "no smoothing" refinement.

use super::catmark::{EdgeMask, VertexContext, VertexMask};
use super::Rules;
use crate::mesh::{CreaseMethod, Options, Rule};

/// The bilinear scheme's rules: every edge takes the crease (midpoint) mask and every
/// vertex the corner mask (OpenSubdiv's `ComputeEdgeVertexMask` and
/// `ComputeVertexVertexMask` for `SCHEME_BILINEAR`). Applied by
/// [`interpolate_with`](crate::refine::interpolate_with) on the Catmull-Clark topology.
///
/// With [`BoundaryInterpolation::None`](crate::mesh::BoundaryInterpolation::None)
/// OpenSubdiv makes no faces holes for this scheme (its neighbourhood is the face itself):
/// build its topology with [`Bilinear::topology_options`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Bilinear;

impl Bilinear {
    /// The options to build a bilinear level's topology with: `options`, with boundary
    /// mode `None` read as edge-only. The two differ only in the faces that `None` makes
    /// holes, which OpenSubdiv does only for schemes whose points depend on a
    /// neighbourhood of the face (`TopologyRefinerFactory`, `makeBoundaryFacesHoles`);
    /// boundary edges are infinitely sharp in both, and sharpness does not move bilinear
    /// points.
    pub fn topology_options(options: &Options) -> Options {
        let mut o = *options;
        if o.boundary == crate::mesh::BoundaryInterpolation::None {
            o.boundary = crate::mesh::BoundaryInterpolation::EdgeOnly;
        }
        o
    }
}

impl Rules for Bilinear {
    /// The midpoint: `½(v₀ + v₁)`.
    fn smooth_edge_mask(self, _: &Options, _: usize, _: [bool; 2]) -> EdgeMask {
        EdgeMask::CREASE
    }

    /// `(1, 0, 0)`: the vertex itself.
    fn smooth_vertex_weights(self, _: usize) -> (f64, f64, f64) {
        (1.0, 0.0, 0.0)
    }

    /// `(0, 1, 0)`: the vertex itself.
    fn crease_vertex_weights(self) -> [f64; 3] {
        [0.0, 1.0, 0.0]
    }

    /// `½(v₀ + v₁)`.
    #[inline]
    fn smooth_edge_point<const D: usize>(
        self,
        ends: [&[f64; D]; 2],
        _: [&[f64; D]; 2],
    ) -> [f64; D] {
        std::array::from_fn(|k| 0.5 * (ends[0][k] + ends[1][k]))
    }

    /// `v`.
    #[inline]
    fn smooth_vertex_point<'a, const D: usize>(
        self,
        _: usize,
        v: &[f64; D],
        _: impl Iterator<Item = &'a [f64; D]>,
        _: impl Iterator<Item = &'a [f64; D]>,
    ) -> [f64; D] {
        *v
    }

    /// The midpoint, whatever the sharpness.
    fn edge_mask(self, _: &Options, _: f32, _: Rule, _: usize, _: [bool; 2]) -> EdgeMask {
        EdgeMask::CREASE
    }

    /// The corner mask, whatever the rule.
    fn vertex_mask(
        self,
        _: CreaseMethod,
        ctx: &VertexContext,
        mask: &mut VertexMask,
        _: &mut VertexMask,
    ) {
        mask.set_corner(ctx.parent_edges.len(), ctx.num_faces);
    }

    /// The vertex itself: the bilinear limit surface passes through every vertex
    /// (OpenSubdiv's `assign*LimitMask` for `SCHEME_BILINEAR`).
    fn limit_position_mask(
        self,
        _: Rule,
        edge_sharpness: &[f32],
        num_faces: usize,
        m: &mut VertexMask,
    ) {
        m.set_corner(edge_sharpness.len(), num_faces);
    }

    /// Along the first two edges, `e₀ − v` and `e₁ − v` (ambiguous at every vertex of a
    /// piecewise bilinear surface; OpenSubdiv's choice).
    fn limit_tangent_masks(
        self,
        _: Rule,
        edge_sharpness: &[f32],
        num_faces: usize,
        t1: &mut VertexMask,
        t2: &mut VertexMask,
    ) {
        super::catmark::limit_tangent_masks(Rule::Corner, edge_sharpness, num_faces, t1, t2);
    }
}
