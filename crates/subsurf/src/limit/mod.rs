//! Limit positions, tangents and normals of the vertices of a refined level, from
//! OpenSubdiv's limit masks (`crate::scheme::catmark::limit_position_mask`,
//! `crate::scheme::catmark::limit_tangent_masks`), as `PrimvarRefiner::Limit` does.
//!
//! The masks assume that every face around a vertex is a quad, which holds at every level
//! after the first. At a semi-sharp feature the mask of the vertex's *current* rule is
//! used (as in OpenSubdiv): the result is the limit of the surface in which the remaining
//! sharpness is infinite. Exact evaluation anywhere on the limit surface, with
//! derivatives, is [`LimitSurface`].

mod bilinear_surface;
mod box_spline;
pub mod bspline;
mod builder;
mod configs;
mod corner;
mod crease_patch;
mod eval;
mod face_varying;
mod local;
mod loop_surface;
mod loop_tree;
mod memory;
mod param;
mod rows;
mod stencil;
mod surface;
mod tessellate;
mod tessellate_fvar;
mod tree;
mod vertex_rows;

use crate::refine::patch::Index;

pub use bilinear_surface::BilinearSurface;
pub use bspline::{Derivatives, Order};
pub use builder::SurfaceBuilder;
pub use eval::{Domain, Surface};
pub use face_varying::{ChannelValues, FaceVaryingError, FaceVaryingSurface};
pub use loop_surface::LoopSurface;
pub use memory::BuildError;
pub use param::Parameterization;
pub use stencil::{LimitStencils, StencilError};
pub use surface::{EvalError, LimitSurface, SurfacePoint, MAX_DEPTH};
pub use tessellate::{
    tessellate, tessellate_mesh, TessellateError, Tessellation, MAX_TESSELLATION_VERTICES,
};
pub(crate) use vertex_rows::VertexLimitRows;

use crate::geom;
use crate::mesh::Topology;
use crate::scheme::catmark::{CatmullClark, VertexMask};
use crate::scheme::Rules;

/// Output buffers for the first and second limit tangents.
pub type Tangents<'a, const D: usize> = (&'a mut [[f64; D]], &'a mut [[f64; D]]);

/// Limit positions of the vertices of `level` (values `src`), and, when `tangents` is
/// given, the two limit tangents (see `catmark::limit_tangent_masks` for their
/// directions). Isolated vertices keep their position and get zero tangents.
pub fn limit_points<const D: usize>(
    level: &Topology,
    src: &[[f64; D]],
    pos: &mut [[f64; D]],
    tangents: Option<Tangents<'_, D>>,
) {
    limit_points_with(CatmullClark, level, src, pos, tangents);
}

/// [`limit_points`] with the limit masks of `rules` ([`Rules::limit_position_mask`],
/// [`Rules::limit_tangent_masks`]): Catmull-Clark's, Loop's or bilinear's.
pub(crate) fn limit_points_with<R: Rules, const D: usize>(
    rules: R,
    level: &Topology,
    src: &[[f64; D]],
    pos: &mut [[f64; D]],
    mut tangents: Option<Tangents<'_, D>>,
) {
    let mut masks = VertexMasks::default();
    for v in 0..level.num_vertices() {
        if !masks.load(rules, level, v, tangents.is_some()) {
            pos[v] = src[v];
            if let Some((t1, t2)) = tangents.as_mut() {
                t1[v] = [0.0; D];
                t2[v] = [0.0; D];
            }
            continue;
        }
        pos[v] = masks.apply(&masks.position, v, src);
        if let Some((t1, t2)) = tangents.as_mut() {
            t1[v] = masks.apply(&masks.tangents[0], v, src);
            t2[v] = masks.apply(&masks.tangents[1], v, src);
        }
    }
}

/// Copies the control points `src` over `dst` (a surface's `set_positions`).
///
/// # Errors
/// [`EvalError::InvalidPositions`]: naming the first point that is not finite, or, when the
/// counts differ, the smaller of the two counts.
pub(crate) fn copy_positions(dst: &mut [[f64; 3]], src: &[[f64; 3]]) -> Result<(), EvalError> {
    if src.len() != dst.len() {
        return Err(EvalError::InvalidPositions {
            vertex: src.len().min(dst.len()),
        });
    }
    if let Some(v) = src.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
        return Err(EvalError::InvalidPositions { vertex: v });
    }
    dst.copy_from_slice(src);
    Ok(())
}

/// The limit masks of one vertex ([`Rules::limit_position_mask`],
/// [`Rules::limit_tangent_masks`]) and the points they weigh: the vertex, the far ends of
/// its edges and the corners of its faces opposite it.
#[derive(Default)]
pub(crate) struct VertexMasks {
    /// The limit position's mask.
    position: VertexMask,
    /// The two limit tangents' masks (loaded with `tangents`).
    tangents: [VertexMask; 2],
    sharp: Vec<f32>,
    ends: Vec<u32>,
    opposite: Vec<u32>,
}

impl VertexMasks {
    /// Loads the masks of vertex `v` of `level` (the tangents' too with `tangents`);
    /// `false` for an isolated vertex, which has none (its limit is itself).
    pub(crate) fn load<R: Rules>(
        &mut self,
        rules: R,
        level: &Topology,
        v: usize,
        tangents: bool,
    ) -> bool {
        self.load_for_face(rules, level, v, tangents, None)
    }

    /// [`load`](Self::load), with the tangents of the sector of face `face` (one of `v`'s)
    /// when given. At an interior crease vertex the crease's two sharp edges split the faces
    /// into two sectors, each with its own tangent plane (the surface has a sharp crease
    /// there); the crease tangent masks (`Rules::limit_tangent_masks`, OpenSubdiv's
    /// `assignCreaseLimitTangentMasks`) span the plane of the sector that runs from the
    /// first sharp edge to the next, so the vertex's edges and faces are listed from the
    /// sharp edge that begins `face`'s sector. OpenSubdiv's `Bfr` evaluates a face's corner
    /// in its own sector in the same way.
    pub(crate) fn load_for_face<R: Rules>(
        &mut self,
        rules: R,
        level: &Topology,
        v: usize,
        tangents: bool,
        face: Option<usize>,
    ) -> bool {
        let edges = level.vertex_edges(v);
        if edges.is_empty() {
            return false;
        }
        let faces = level.vertex_faces(v);
        let tag = level.vertex_tag(v);
        let rule = tag.rule;
        self.sharp.clear();
        (self.sharp).extend(edges.iter().map(|&e| level.edge_sharpness(e as usize)));
        self.ends.clear();
        self.ends.extend(level.vertex_neighbours(v));
        self.opposite.clear();
        self.opposite.extend(
            (faces.iter())
                .zip(level.vertex_face_locals(v))
                .map(|(&f, &l)| {
                    let fv = level.face_vertices(f as usize);
                    fv[(l as usize + 2) % fv.len()]
                }),
        );
        // Face i lies between edges i and i + 1 of a manifold interior vertex.
        let interior = !tag.boundary && !tag.non_manifold && faces.len() == edges.len();
        let local = face.and_then(|f| faces.iter().position(|&x| x as usize == f));
        if let (crate::mesh::Rule::Crease, true, Some(k)) = (rule, interior, local) {
            let n = edges.len();
            let sharp = |i: usize| crate::mesh::sharpness::is_sharp(self.sharp[i % n]);
            if let Some(back) = (0..n).find(|&b| sharp(k + n - b)) {
                let first = (k + n - back) % n;
                self.sharp.rotate_left(first);
                self.ends.rotate_left(first);
                self.opposite.rotate_left(first);
            }
        }
        rules.limit_position_mask(rule, &self.sharp, faces.len(), &mut self.position);
        if tangents {
            let [t1, t2] = &mut self.tangents;
            rules.limit_tangent_masks(rule, &self.sharp, faces.len(), t1, t2);
        }
        true
    }

    /// The weights of mask `m` (one of this vertex `v`'s), as `add(point, weight)`: the
    /// faces' opposite corners, the edges' far ends, then the vertex.
    fn weights(&self, m: &VertexMask, v: usize, mut add: impl FnMut(u32, f64)) {
        if m.has_faces {
            for (&x, &w) in self.opposite.iter().zip(&m.faces) {
                add(x, w);
            }
        }
        if m.has_edges {
            for (&x, &w) in self.ends.iter().zip(&m.edges) {
                add(x, w);
            }
        }
        add(v as u32, m.vertex);
    }

    /// The points of vertex `v` in the order of [`weights`](Self::weights), each with its
    /// weights in the position's mask and the two tangents' (0 where a mask does not weigh
    /// the point), as `add(point, [position, t₁, t₂])`. The masks must have been loaded
    /// for `v` with `tangents` (else the tangents' are another vertex's).
    pub(crate) fn terms(&self, v: usize, mut add: impl FnMut(u32, [f64; 3])) {
        debug_assert_eq!(self.tangents[0].edges.len(), self.ends.len());
        let [p, t1, t2] = [&self.position, &self.tangents[0], &self.tangents[1]];
        let face = |m: &VertexMask, i: usize| if m.has_faces { m.faces[i] } else { 0.0 };
        let edge = |m: &VertexMask, i: usize| if m.has_edges { m.edges[i] } else { 0.0 };
        for (i, &x) in self.opposite.iter().enumerate() {
            add(x, [face(p, i), face(t1, i), face(t2, i)]);
        }
        for (i, &x) in self.ends.iter().enumerate() {
            add(x, [edge(p, i), edge(t1, i), edge(t2, i)]);
        }
        add(v as u32, [p.vertex, t1.vertex, t2.vertex]);
    }

    /// Mask `m` of vertex `v` applied to the values `src` (the [`weights`](Self::weights)
    /// in their order).
    fn apply<const D: usize>(&self, m: &VertexMask, v: usize, src: &[[f64; D]]) -> [f64; D] {
        let mut acc = [0.0; D];
        self.weights(m, v, |x, w| {
            for k in 0..D {
                acc[k] += w * src[x as usize][k];
            }
        });
        acc
    }
}

/// Unit normals `t₁ × t₂ / |t₁ × t₂|`. Where the tangents are degenerate (a vertex whose
/// limit tangent plane the masks cannot give, e.g. a crease folded back on itself), the
/// normal of the vertex's faces at this level (sum of their Newell normals) is used; an
/// isolated vertex gets `[0, 0, 0]`, and so does a vertex whose faces' normals cancel
/// (faces back to back).
///
/// Degenerate means parallel to within rounding, not only exactly: the masks' terms
/// cancel (to zero, or to tangents that are parallel, on exact positions), and what is
/// left is noise of about 1e-16 of the largest coordinate `c` of `pos`. So the tangents
/// are taken for parallel when the sine of their angle is under 1e-12, or under 1e-12 `c`
/// over the length of either (each tangent's direction is known to no better). Among the
/// faces, those whose Newell normal is shorter than 1e-12 `c²` (no area) are left out,
/// and faces' normals whose sum is under 1e-12 of the sum of their lengths give none. So
/// positions that differ by rounding (a re-posing plan's and a refinement's,
/// [`crate::Reposer`]) give the same normals; with exact tests, the noise of cancelled
/// tangents gave normals in any direction.
pub fn normals(
    level: &Topology,
    pos: &[[f64; 3]],
    t1: &[[f64; 3]],
    t2: &[[f64; 3]],
) -> Vec<[f64; 3]> {
    let mut out = vec![[0.0; 3]; level.num_vertices()];
    normals_into(
        |v| level.vertex_faces(v),
        |f| level.face_vertices(f),
        (pos, largest_coordinate(pos)),
        t1,
        t2,
        &mut out,
    );
    out
}

/// The largest magnitude of a coordinate of `points` (0 for none).
pub(crate) fn largest_coordinate(points: &[[f64; 3]]) -> f64 {
    (points.iter()).fold(0.0f64, |m, p| {
        m.max(p[0].abs()).max(p[1].abs()).max(p[2].abs())
    })
}

/// Relative size under which [`normals`] takes a tangent, an angle or a sum of face normals
/// for cancelled.
const CANCELLED: f64 = 1e-12;

/// [`normals`] into `out` (one per vertex), the faces of vertex `v` being `vertex_faces(v)`
/// and the vertices of face `f` `face_vertices(f)`; `(pos, largest)` the positions and
/// their [`largest_coordinate`], or any bound above it not much larger (the base mesh's:
/// refinement and limits are convex combinations of its points).
pub(crate) fn normals_into<'a>(
    vertex_faces: impl Fn(usize) -> &'a [u32] + Sync,
    face_vertices: impl Fn(usize) -> &'a [u32] + Sync,
    (pos, largest): (&[[f64; 3]], f64),
    t1: &[[f64; 3]],
    t2: &[[f64; 3]],
    out: &mut [[f64; 3]],
) {
    let small = CANCELLED * largest * largest;
    // `2 (C c)²`, `C` = [`CANCELLED`]: see the angle test below.
    let noise = 2.0 * (CANCELLED * largest).powi(2);
    let normal = |(v, n): (usize, &mut [f64; 3])| {
        let (a, b) = (t1[v], t2[v]);
        let (aa, bb) = (geom::dot(&a, &a), geom::dot(&b, &b));
        if (1e-150..1e150).contains(&aa) && (1e-150..1e150).contains(&bb) {
            // Tangents of moderate length (nearly all; their squares neither overflow nor
            // underflow here): `sin θ = |a × b| / (|a| |b|)`. A tangent's direction is
            // known to about `C c / |t|` (its terms cancel down to it), so the tangents
            // span a plane when `sin θ > C` and `sin θ > C c (1/|a| + 1/|b|)`, the second
            // tested through its bound `|a × b|² > 2 (C c)² (|a|² + |b|²)`. One square root
            // and one division, where the scaled path below takes three and a dozen (45 %
            // of re-posing's limit pass).
            let c = geom::cross(&a, &b);
            let cc = geom::dot(&c, &c);
            if cc > CANCELLED * CANCELLED * aa * bb && cc > noise * (aa + bb) {
                let s = 1.0 / cc.sqrt();
                *n = [c[0] * s, c[1] * s, c[2] * s];
                return;
            }
        } else {
            // Tiny or huge tangents (a mesh at 1e-200 or 1e200): scaled first.
            let (a, b) = (geom::normalize_or_zero(a), geom::normalize_or_zero(b));
            if geom::norm(&geom::cross(&a, &b)) > CANCELLED {
                *n = geom::unit_cross(&a, &b);
                return;
            }
        }
        // Tangents that are (nearly) parallel or cancelled give no plane: the faces'.
        let (mut acc, mut lengths) = ([0.0; 3], 0.0);
        for &f in vertex_faces(v) {
            let n = geom::newell_normal(pos, face_vertices(f as usize));
            let length = geom::norm(&n);
            // A face of no area (its limit points on a line) has a normal of noise.
            if length > small {
                (0..3).for_each(|k| acc[k] += n[k]);
                lengths += length;
            }
        }
        *n = if geom::norm(&acc) > CANCELLED * lengths {
            geom::normalize_or_zero(acc)
        } else {
            [0.0; 3]
        };
    };
    if out.len() < 16 * 1024 || rayon::current_num_threads() == 1 {
        out.iter_mut().enumerate().for_each(normal);
    } else {
        use rayon::prelude::*;
        out.par_iter_mut()
            .enumerate()
            .with_min_len(4096)
            .for_each(normal);
    }
}

/// `m` locked, also if a thread panicked while holding it: the limit layer's caches and
/// cells are only ever filled whole (an entry inserted, a value set), so what a panicking
/// thread left is consistent.
fn lock<T>(m: &std::sync::Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    match m.lock() {
        Ok(g) => g,
        Err(poisoned) => poisoned.into_inner(),
    }
}
