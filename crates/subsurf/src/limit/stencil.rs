//! [`LimitStencils`]: a precomputed table that maps control points to a fixed set of limit
//! samples, so that re-evaluating after the control points move (animation, shape
//! optimisation) is a sparse matrix-vector product.
//!
//! The limit surface is linear in the control points: each sample's position and first
//! derivatives are weighted sums `Σ wᵢ Pᵢ` over the control points of the sample's face's
//! 1-ring. The weights are found by evaluating the same exact evaluator as
//! [`LimitSurface`](super::LimitSurface) on unit control points (three at a time, one per
//! coordinate), so the table reproduces `LimitSurface::eval` to rounding.
//!
//! At an irregular corner that is not a smooth vertex (crease, corner, dart, non-manifold;
//! see [`LimitSurface`](super::LimitSurface)), the evaluator's tangent directions depend
//! on the geometry, not linearly on the control points; there the table's derivative
//! weights are not meaningful (positions are exact everywhere).

use super::bspline::{Derivatives, Order};
use super::local::{LevelRef, Reach, RegionCache};
use super::surface::{build_face, eval_node, EvalError, Shared, SurfacePoint};
use super::tree::Ctx;
use crate::mesh::{MeshError, Options, PolyMesh, Topology};
use rayon::prelude::*;

/// One sample's stencil: `(control vertex, [w_position, w_du, w_dv])` entries.
type Row = Vec<(u32, [f64; 3])>;
/// Stencils of one face's samples, by sample index.
type FaceRows = Vec<(usize, Row)>;

/// Errors of [`LimitStencils::new`].
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StencilError {
    /// The mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// A sample point is invalid (no such face, a hole, a parameter out of range).
    #[error("sample {index}: {error}")]
    Point {
        /// Index of the sample.
        index: usize,
        /// What is wrong with it.
        error: EvalError,
    },
}

/// Weights of limit samples on control points (CSR: sample `s` has the entries
/// `offsets[s] .. offsets[s + 1]`), each entry `(vertex, [w_position, w_du, w_dv])`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LimitStencils {
    offsets: Vec<u32>,
    vertices: Vec<u32>,
    weights: Vec<[f64; 3]>,
    num_control: usize,
}

impl LimitStencils {
    /// Computes the stencils of `points` on the limit surface of `mesh`.
    ///
    /// # Errors
    /// [`StencilError`] for an invalid mesh or sample point.
    pub fn new(
        mesh: &PolyMesh,
        options: Options,
        points: &[SurfacePoint],
    ) -> Result<Self, StencilError> {
        mesh.validate()?;
        let (base, _) = Topology::from_mesh(mesh, &options)?;
        // Group the samples by face.
        let mut order: Vec<usize> = (0..points.len()).collect();
        order.sort_by_key(|&i| (points[i].face, points[i].subface));
        let mut groups: Vec<&[usize]> = Vec::new();
        let mut start = 0;
        for i in 1..=order.len() {
            if i == order.len() || points[order[i]].face != points[order[start]].face {
                if i > start {
                    groups.push(&order[start..i]);
                }
                start = i;
            }
        }
        let nv = mesh.num_vertices();
        // Faces with the same neighbourhood share their configuration tree.
        let shared = Shared::default();
        let per_group: Vec<Result<FaceRows, StencilError>> = groups
            .par_iter()
            .map_init(
                || vec![[0.0; 3]; nv],
                |unit, group| face_stencils(&base, &shared, unit, group, points, &options),
            )
            .collect();
        let mut rows: Vec<Row> = vec![Vec::new(); points.len()];
        for g in per_group {
            for (i, row) in g? {
                rows[i] = row;
            }
        }
        let mut t = LimitStencils {
            offsets: vec![0],
            num_control: nv,
            ..Default::default()
        };
        for row in rows {
            for (v, w) in row {
                t.vertices.push(v);
                t.weights.push(w);
            }
            t.offsets.push(t.vertices.len() as u32);
        }
        Ok(t)
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Number of stored weights (non-zeros).
    pub fn num_weights(&self) -> usize {
        self.weights.len()
    }

    /// The entries of sample `s`: `(control vertex, [w_position, w_du, w_dv])`.
    pub fn stencil(&self, s: usize) -> impl Iterator<Item = (u32, [f64; 3])> + '_ {
        let r = self.offsets[s] as usize..self.offsets[s + 1] as usize;
        self.vertices[r.clone()]
            .iter()
            .copied()
            .zip(self.weights[r].iter().copied())
    }

    /// Position and first derivatives of every sample for control points `control`
    /// (second derivatives are not tabulated and are zero), in parallel.
    ///
    /// # Panics
    /// If `control` does not have one point per control vertex of the mesh.
    pub fn apply(&self, control: &[[f64; 3]]) -> Vec<Derivatives> {
        assert_eq!(
            control.len(),
            self.num_control,
            "one control point per mesh vertex"
        );
        (0..self.len())
            .into_par_iter()
            .with_min_len(1024)
            .map(|s| {
                let mut d = Derivatives::default();
                for (v, w) in self.stencil(s) {
                    let p = &control[v as usize];
                    for k in 0..3 {
                        d.p[k] += w[0] * p[k];
                        d.du[k] += w[1] * p[k];
                        d.dv[k] += w[2] * p[k];
                    }
                }
                d
            })
            .collect()
    }
}

/// The vertices of the 1-ring of face `f` (the faces around its vertices): everything the
/// face's surface can depend on (see `local`), in order of first appearance.
fn one_ring(base: &Topology, f: usize) -> Vec<u32> {
    let mut faces: Vec<u32> = vec![f as u32];
    for &v in base.face_vertices(f) {
        for &g in base.vertex_faces(v as usize) {
            if !faces.contains(&g) {
                faces.push(g);
            }
        }
    }
    let mut ring: Vec<u32> = Vec::new();
    for &g in &faces {
        for &w in base.face_vertices(g as usize) {
            if !ring.contains(&w) {
                ring.push(w);
            }
        }
    }
    ring
}

/// Stencils of the samples `group` (indices into `points`, all on one face): evaluate the
/// face's surface built on unit control points, three vertices at a time (one per
/// coordinate), over the vertices of the face's 1-ring. `unit` is all zeros on entry and
/// on exit.
fn face_stencils(
    base: &Topology,
    shared: &Shared,
    unit: &mut [[f64; 3]],
    group: &[usize],
    points: &[SurfacePoint],
    options: &Options,
) -> Result<FaceRows, StencilError> {
    let f = points[group[0]].face as usize;
    let err = |index: usize, error: EvalError| StencilError::Point { index, error };
    if f >= base.num_faces() {
        let e = EvalError::NoSuchFace {
            face: f as u32,
            count: base.num_faces(),
        };
        return Err(err(group[0], e));
    }
    for &i in group {
        let p = points[i];
        if !(0.0..=1.0).contains(&p.u) || !(0.0..=1.0).contains(&p.v) {
            return Err(err(i, EvalError::BadParameter { u: p.u, v: p.v }));
        }
    }
    let ring = one_ring(base, f);
    let mut rows: FaceRows = group.iter().map(|&i| (i, Vec::new())).collect();
    for chunk in ring.chunks(3) {
        for (k, &v) in chunk.iter().enumerate() {
            unit[v as usize][k] = 1.0;
        }
        let cache = RegionCache::default();
        let level = LevelRef::new(base, unit, shared, &cache, Reach::new(options));
        let (nodes, _) = build_face(level, shared, f, options);
        for (row, &i) in rows.iter_mut().zip(group) {
            let p = points[i];
            let node = nodes.get(p.subface as usize).ok_or_else(|| {
                err(
                    i,
                    EvalError::NoSuchSubface {
                        face: p.face,
                        subface: p.subface,
                        size: nodes.len(),
                    },
                )
            });
            let d = match node {
                Ok(n) => {
                    let ctx = Ctx {
                        options,
                        order: Order::First,
                        pos: unit,
                        topo: base,
                        sectors: &shared.sectors,
                        trees: &shared.trees,
                    };
                    let mut d = Derivatives::default();
                    if eval_node(n, p.u, p.v, ctx, &mut d) {
                        Ok(d)
                    } else {
                        Err(err(i, EvalError::Hole { face: p.face }))
                    }
                }
                Err(e) => Err(e),
            };
            let d = match d {
                Ok(d) => d,
                Err(e) => {
                    for &v in chunk {
                        unit[v as usize] = [0.0; 3];
                    }
                    return Err(e);
                }
            };
            for (k, &v) in chunk.iter().enumerate() {
                let w = [d.p[k], d.du[k], d.dv[k]];
                if w != [0.0; 3] {
                    row.1.push((v, w));
                }
            }
        }
        for &v in chunk {
            unit[v as usize] = [0.0; 3];
        }
    }
    for row in &mut rows {
        row.1.sort_unstable_by_key(|e| e.0);
    }
    Ok(rows)
}
