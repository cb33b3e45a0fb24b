//! Conversion of a bicubic B-spline surface to a control mesh with knot intervals: the input
//! of non-uniform Catmull-Clark subdivision (NURSS).
//!
//! # The mapping
//! The control net `P_{i,j}` becomes a quad mesh: vertex `i · nv + j` is `P_{i,j}`, and face
//! `(i, j)` is `[P_{i,j}, P_{i+1,j}, P_{i+1,j+1}, P_{i,j+1}]` (so its `u` runs along `i`, its
//! `v` along `j`, and its normal is `S_u × S_v`), for `0 ≤ i < nu − 1` (or `< nu`, wrapping,
//! in a closed direction) and likewise for `j`.
//!
//! Each edge carries a *knot interval* (Sederberg, Zheng, Sewell & Sabin, "Non-uniform
//! recursive subdivision surfaces", SIGGRAPH 1998, §2–3). For a cubic, the basis function
//! `N_{i,3}` is supported on the five knots `t_i … t_{i+4}` and is centred on `t_{i+2}`
//! (its Greville abscissa for uniform knots, its maximum for symmetric spacing); in NURSS the
//! control point `P_i` is associated with that central knot, so the edge `P_i P_{i+1}` spans
//! the parameter interval between the central knots of `N_i` and `N_{i+1}`:
//!
//! > the edge `P_{i,j} P_{i+1,j}` carries `d_{i+2} = t_{i+3} − t_{i+2}` of the `u` knots, and
//! > the edge `P_{i,j} P_{i,j+1}` carries `d_{j+2}` of the `v` knots,
//!
//! indices of the unwrapped knot vector; for a periodic direction this is the period interval
//! `u_{m+1} − u_m`, `m = (i + 2 − p) mod n = (i − 1) mod n`. Consequences: uniform knots
//! give equal intervals everywhere (the regular Catmull-Clark case); a clamped end (`p + 1`
//! equal knots) gives zero intervals on the edges of the first and last rows; and face
//! `(i, j)`, whose 4×4 neighbourhood `P_{i−1…i+2, j−1…j+2}` is exactly the set of control
//! points of the span `[t_{i+2}, t_{i+3}] × [s_{j+2}, s_{j+3}]`, is the image of that
//! parameter rectangle (recorded in [`ControlMesh::face_params`]). For uniform knots the
//! bicubic B-spline is the Catmull-Clark limit surface of this mesh away from its border.

use super::{BSplineSurface, KnotVector, NurbsError};
use crate::mesh::{EdgeInterval, KnotTags, PolyMesh};

/// A mesh edge with the knot interval it carries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KnotEdge {
    /// First end vertex (`P_{i,j}`).
    pub v0: u32,
    /// Second end vertex (`P_{i+1,j}` for a `u` edge, `P_{i,j+1}` for a `v` edge).
    pub v1: u32,
    /// The knot interval `d ≥ 0` of the edge.
    pub interval: f64,
}

/// The control mesh of a bicubic B-spline surface with its knot intervals (see the
/// module documentation for the conventions).
#[derive(Clone, Debug, PartialEq)]
pub struct ControlMesh {
    /// Quads over the control net; vertex `i · nv + j` is `P_{i,j}`.
    pub mesh: PolyMesh,
    /// Edges along `u`, `P_{i,j} → P_{i+1,j}`, with the `u` knot interval `d_{i+2}`.
    pub u_edges: Vec<KnotEdge>,
    /// Edges along `v`, `P_{i,j} → P_{i,j+1}`, with the `v` knot interval `d_{j+2}`.
    pub v_edges: Vec<KnotEdge>,
    /// Per face, the parameter rectangle `[u0, u1, v0, v1] = [t_{i+2}, t_{i+3}, s_{j+2},
    /// s_{j+3}]` of the spline it stands for (possibly outside the domain, or empty, for
    /// border faces of an open net; in a closed direction it may precede the period start,
    /// which evaluation wraps).
    pub face_params: Vec<[f64; 4]>,
}

impl BSplineSurface<3> {
    /// The control mesh of a bicubic surface with per-edge knot intervals (NURSS, see the
    /// module documentation).
    ///
    /// # Errors
    /// [`NurbsError::BadDegree`] unless both degrees are 3; [`NurbsError::TooFewPoints`] for
    /// a closed direction with fewer than 3 points (its faces would repeat);
    /// [`NurbsError::TooLarge`] beyond `u32` vertex indices.
    pub fn control_mesh(&self) -> Result<ControlMesh, NurbsError> {
        for d in [self.knots_u().degree(), self.knots_v().degree()] {
            if d != 3 {
                return Err(NurbsError::BadDegree {
                    degree: d,
                    reason: "a control mesh with knot intervals needs a bicubic surface",
                });
            }
        }
        let (nu, nv) = self.size();
        let (cu, cv) = self.is_closed();
        for (n, closed) in [(nu, cu), (nv, cv)] {
            if closed && n < 3 {
                return Err(NurbsError::TooFewPoints {
                    count: n,
                    degree: 3,
                    min: 3,
                });
            }
        }
        if u32::try_from(nu * nv).is_err() {
            return Err(NurbsError::TooLarge { count: nu * nv });
        }
        let id = |i: usize, j: usize| ((i % nu) * nv + (j % nv)) as u32;
        let du = edge_intervals(self.knots_u());
        let dv = edge_intervals(self.knots_v());
        let (eu, ev) = (if cu { nu } else { nu - 1 }, if cv { nv } else { nv - 1 });
        let mut u_edges = Vec::with_capacity(eu * nv);
        for i in 0..eu {
            for j in 0..nv {
                u_edges.push(KnotEdge {
                    v0: id(i, j),
                    v1: id(i + 1, j),
                    interval: du[i],
                });
            }
        }
        let mut v_edges = Vec::with_capacity(nu * ev);
        for i in 0..nu {
            for j in 0..ev {
                v_edges.push(KnotEdge {
                    v0: id(i, j),
                    v1: id(i, j + 1),
                    interval: dv[j],
                });
            }
        }
        let (tu, tv) = (self.knots_u().as_slice(), self.knots_v().as_slice());
        let mut faces = Vec::with_capacity(eu * ev);
        let mut face_params = Vec::with_capacity(eu * ev);
        for i in 0..eu {
            for j in 0..ev {
                faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
                face_params.push([tu[i + 2], tu[i + 3], tv[j + 2], tv[j + 3]]);
            }
        }
        let mesh = PolyMesh::from_faces(self.points().to_vec(), &faces)?;
        Ok(ControlMesh {
            mesh,
            u_edges,
            v_edges,
            face_params,
        })
    }
}

/// The interval of edge `i → i + 1` of a cubic direction: `t_{i+3} − t_{i+2}` (open), or
/// the period interval `d_{(i−1) mod n}` (periodic), for every edge of the direction.
fn edge_intervals(k: &KnotVector) -> Vec<f64> {
    let t = k.as_slice();
    match k.period_knots() {
        Some(_) => {
            let d = k.intervals();
            let n = d.len();
            (0..n).map(|i| d[(i + n - 1) % n]).collect()
        }
        None => (0..k.num_points() - 1)
            .map(|i| t[i + 3] - t[i + 2])
            .collect(),
    }
}

impl ControlMesh {
    /// The knot intervals of every edge as [`KnotTags`] (`u` edges, then `v` edges), ready
    /// for [`crate::nonuniform::Nurss`].
    pub fn knot_tags(&self) -> KnotTags {
        KnotTags {
            intervals: self
                .u_edges
                .iter()
                .chain(&self.v_edges)
                .map(|e| EdgeInterval {
                    v0: e.v0,
                    v1: e.v1,
                    interval: e.interval,
                })
                .collect(),
            ..KnotTags::default()
        }
    }

    /// The control mesh with its knot intervals in [`PolyMesh::knots`].
    pub fn mesh_with_knots(&self) -> PolyMesh {
        let mut m = self.mesh.clone();
        m.knots = self.knot_tags();
        m
    }
}
