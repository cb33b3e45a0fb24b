//! Sharpness tags: edge creases, vertex corners and holes.
//!
//! Sharpness is stored as `f32` on purpose: OpenSubdiv stores and decays sharpness in
//! single precision and computes its transitional (fractional) weights from those `f32`
//! values. Holding the same `f32` values is what makes our refined positions agree with
//! OpenSubdiv's to 1e-12 instead of 1e-8 on fractional creases.

/// Sharpness at or above which an edge or vertex is infinitely sharp (OpenSubdiv's
/// `Sdc::Crease::SHARPNESS_INFINITE`).
pub const SHARPNESS_INFINITE: f32 = 10.0;

/// A sharp edge between two vertices (OBJ `t crease 2/1/0 v0 v1 s`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crease {
    /// First end vertex (0-based).
    pub v0: u32,
    /// Second end vertex (0-based).
    pub v1: u32,
    /// Sharpness: 0 smooth, in (0, 10) semi-sharp (decays by one per level),
    /// ≥ 10 infinitely sharp.
    pub sharpness: f32,
}

/// A sharp vertex (OBJ `t corner 1/1/0 v s`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Corner {
    /// The vertex (0-based).
    pub vertex: u32,
    /// Sharpness, as for [`Crease::sharpness`].
    pub sharpness: f32,
}

/// Sharpness and hole tags of a mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tags {
    /// Sharp edges. An edge listed twice takes the last value (as in OpenSubdiv).
    pub creases: Vec<Crease>,
    /// Sharp vertices. A vertex listed twice takes the last value.
    pub corners: Vec<Corner>,
    /// Faces that are holes: they shape their neighbours but are not part of the surface.
    pub holes: Vec<u32>,
}

impl Tags {
    /// True when there are no creases, corners or holes.
    pub fn is_empty(&self) -> bool {
        self.creases.is_empty() && self.corners.is_empty() && self.holes.is_empty()
    }
}

/// A knot interval on an edge (OBJ `t interval 2/1/0 v0 v1 d`): the input of non-uniform
/// Catmull-Clark subdivision ([`crate::nonuniform`]). Edges without one have interval 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeInterval {
    /// One end vertex (0-based).
    pub v0: u32,
    /// The other end vertex (0-based); the order does not matter.
    pub v1: u32,
    /// The knot interval, finite and ≥ 0 (0 makes a sharp feature / multiple knot).
    pub interval: f64,
}

/// An *auxiliary* knot interval on one side of an edge (OBJ `t sideinterval 3/1/0 f v0 v1
/// d`): the interval of edge `v0`–`v1` as read from inside face `face` on the first
/// subdivision step ([JOS 2003] §2, "auxiliary intervals"); sides without one read the edge's
/// interval. Only the base mesh has them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SideInterval {
    /// The face (0-based) whose side of the edge this is.
    pub face: u32,
    /// One end vertex of the edge (0-based).
    pub v0: u32,
    /// The other end vertex; the order does not matter.
    pub v1: u32,
    /// The knot interval, finite and ≥ 0.
    pub interval: f64,
}

/// A rational weight on a vertex (OBJ `t weight 1/1/0 v w`): the mesh is refined in
/// homogeneous coordinates `(w x, w y, w z, w)`. Vertices without one have weight 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexWeight {
    /// The vertex (0-based).
    pub vertex: u32,
    /// The weight, finite and > 0.
    pub weight: f64,
}

impl VertexWeight {
    /// The tags of per-vertex weights `weights` (vertex `i` has `weights[i]`): none when all
    /// are 1 (the mesh is then polynomial), else one per vertex.
    pub fn tags(weights: &[f64]) -> Vec<VertexWeight> {
        if weights.iter().all(|&w| w == 1.0) {
            return Vec::new();
        }
        weights
            .iter()
            .enumerate()
            .map(|(v, &weight)| VertexWeight {
                vertex: v as u32,
                weight,
            })
            .collect()
    }
}

/// Knot intervals and rational weights of a mesh for non-uniform Catmull-Clark subdivision
/// (NURSS). Entries listed twice take the last value. Catmull-Clark ignores them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct KnotTags {
    /// Per-edge knot intervals (untagged edges: 1).
    pub intervals: Vec<EdgeInterval>,
    /// Per-face-side auxiliary intervals (untagged sides: the edge's interval).
    pub side_intervals: Vec<SideInterval>,
    /// Per-vertex rational weights (untagged vertices: 1).
    pub weights: Vec<VertexWeight>,
}

/// Which [`KnotTags`] entry is wrong, and why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum KnotTagError {
    /// An interval or side interval names the same vertex twice.
    #[error("{what} {index}: the edge's two vertices are both {vertex}")]
    SameVertex {
        /// `"interval"` or `"side interval"`.
        what: &'static str,
        /// Index of the entry in its list.
        index: usize,
        /// The vertex.
        vertex: u32,
    },
    /// A vertex or face index beyond the mesh.
    #[error("{what} {index}: {kind} {value} is out of range: the mesh has {count} {kind}s")]
    OutOfRange {
        /// `"interval"`, `"side interval"` or `"weight"`.
        what: &'static str,
        /// Index of the entry in its list.
        index: usize,
        /// `"vertex"` or `"face"`.
        kind: &'static str,
        /// The bad index.
        value: u32,
        /// Number of vertices or faces.
        count: usize,
    },
    /// No face has the edge.
    #[error("{what} {index}: the mesh has no edge between vertices {v0} and {v1}")]
    UnknownEdge {
        /// `"interval"` or `"side interval"`.
        what: &'static str,
        /// Index of the entry in its list.
        index: usize,
        /// One end.
        v0: u32,
        /// The other end.
        v1: u32,
    },
    /// A side interval names a face that does not have the edge.
    #[error("side interval {index}: face {face} has no edge between vertices {v0} and {v1}")]
    EdgeNotInFace {
        /// Index of the entry.
        index: usize,
        /// The face.
        face: u32,
        /// One end.
        v0: u32,
        /// The other end.
        v1: u32,
    },
    /// A negative or non-finite interval.
    #[error("{what} {index}: knot interval {value} must be a finite number ≥ 0")]
    BadInterval {
        /// `"interval"` or `"side interval"`.
        what: &'static str,
        /// Index of the entry in its list.
        index: usize,
        /// The value.
        value: f64,
    },
    /// A zero, negative or non-finite weight.
    #[error(
        "weight {index}: rational weight {value} of vertex {vertex} must be a finite number > 0"
    )]
    BadWeight {
        /// Index of the entry.
        index: usize,
        /// The vertex.
        vertex: u32,
        /// The value.
        value: f64,
    },
}

impl KnotTagError {
    /// Which list the bad entry is in (`"interval"`, `"side interval"`, `"weight"`) and its
    /// index there: lets a reader point at the source line of the entry.
    pub fn entry(&self) -> (&'static str, usize) {
        match *self {
            Self::SameVertex { what, index, .. }
            | Self::OutOfRange { what, index, .. }
            | Self::UnknownEdge { what, index, .. }
            | Self::BadInterval { what, index, .. } => (what, index),
            Self::EdgeNotInFace { index, .. } => ("side interval", index),
            Self::BadWeight { index, .. } => ("weight", index),
        }
    }
}

impl KnotTags {
    /// True when there are no intervals, side intervals or weights.
    pub fn is_empty(&self) -> bool {
        self.intervals.is_empty() && self.side_intervals.is_empty() && self.weights.is_empty()
    }

    /// Checks every entry against `mesh`: indices in range, two distinct vertices that are an
    /// edge of the mesh (of face `face` for a side interval), intervals finite and ≥ 0,
    /// weights finite and > 0. Reports the first bad entry (intervals, then side intervals,
    /// then weights).
    pub fn validate(&self, mesh: &super::PolyMesh) -> Result<(), KnotTagError> {
        use std::collections::HashSet;
        let nv = mesh.num_vertices();
        let nf = mesh.num_faces();
        let key = |a: u32, b: u32| (a.min(b), a.max(b));
        let check_pair = |what, index, v0: u32, v1: u32| {
            for v in [v0, v1] {
                if v as usize >= nv {
                    return Err(KnotTagError::OutOfRange {
                        what,
                        index,
                        kind: "vertex",
                        value: v,
                        count: nv,
                    });
                }
            }
            if v0 == v1 {
                return Err(KnotTagError::SameVertex {
                    what,
                    index,
                    vertex: v0,
                });
            }
            Ok(())
        };
        let check_value = |what, index, value: f64| {
            if value.is_finite() && value >= 0.0 {
                Ok(())
            } else {
                Err(KnotTagError::BadInterval { what, index, value })
            }
        };
        if !self.intervals.is_empty() {
            let mut edges = HashSet::with_capacity(mesh.face_verts().len());
            for fv in mesh.faces() {
                for (i, &a) in fv.iter().enumerate() {
                    edges.insert(key(a, fv[(i + 1) % fv.len()]));
                }
            }
            for (index, t) in self.intervals.iter().enumerate() {
                check_pair("interval", index, t.v0, t.v1)?;
                if !edges.contains(&key(t.v0, t.v1)) {
                    return Err(KnotTagError::UnknownEdge {
                        what: "interval",
                        index,
                        v0: t.v0,
                        v1: t.v1,
                    });
                }
                check_value("interval", index, t.interval)?;
            }
        }
        for (index, t) in self.side_intervals.iter().enumerate() {
            if t.face as usize >= nf {
                return Err(KnotTagError::OutOfRange {
                    what: "side interval",
                    index,
                    kind: "face",
                    value: t.face,
                    count: nf,
                });
            }
            check_pair("side interval", index, t.v0, t.v1)?;
            let fv = mesh.face(t.face as usize);
            let has = (0..fv.len()).any(|i| key(fv[i], fv[(i + 1) % fv.len()]) == key(t.v0, t.v1));
            if !has {
                return Err(KnotTagError::EdgeNotInFace {
                    index,
                    face: t.face,
                    v0: t.v0,
                    v1: t.v1,
                });
            }
            check_value("side interval", index, t.interval)?;
        }
        for (index, w) in self.weights.iter().enumerate() {
            if w.vertex as usize >= nv {
                return Err(KnotTagError::OutOfRange {
                    what: "weight",
                    index,
                    kind: "vertex",
                    value: w.vertex,
                    count: nv,
                });
            }
            if !(w.weight.is_finite() && w.weight > 0.0) {
                return Err(KnotTagError::BadWeight {
                    index,
                    vertex: w.vertex,
                    value: w.weight,
                });
            }
        }
        Ok(())
    }
}
