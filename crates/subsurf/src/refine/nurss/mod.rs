//! The NURSS refiner: one level of non-uniform Catmull-Clark subdivision alive at a time
//! ([`Nurss`]), its knot intervals, its face-varying channels, and its re-posing plan. The
//! masks of a step are in `masks`, the channels' refinement in `face_varying`; the limit
//! (rows of weights per vertex) and evaluation are in [`crate::nonuniform`].

mod face_varying;
mod masks;

pub(crate) use face_varying::{NurssFaceVarying, ValueChannel};

pub(crate) use masks::{across_values, effective_knots, AcrossValues, NurssMasks};
pub(crate) use masks::{child_knots, refine_nurss_step, NurssKnots};

use crate::mesh::{
    Corner, Crease, EdgeInterval, KnotTagError, KnotTags, MeshError, Options, PolyMesh,
    SideInterval, Tags, Topology, TopologyWarning, VertexWeight,
};
use crate::refine::uniform::{check_size, Steps};
use crate::refine::RefinePlan;
use crate::scheme::adjustable::Mixed;

/// Errors of NURSS refinement.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NurssError {
    /// The mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// A knot interval, side interval or weight is invalid.
    #[error(transparent)]
    Knots(#[from] KnotTagError),
    /// A semi-sharp crease or vertex (see [`crate::nonuniform`]).
    #[error("{what} has sharpness {sharpness}: non-uniform (NURSS) subdivision supports only smooth (0) and infinitely sharp (≥ 10) creases and corners; use a zero knot interval for a sharp feature")]
    SemiSharp {
        /// The element (`"the crease on edge (3, 4)"`, `"vertex 7"`).
        what: String,
        /// Its sharpness.
        sharpness: f32,
    },
    /// Interval data of the wrong length for the topology.
    #[error("{what}: expected {expected} values, got {found}")]
    WrongLength {
        /// What was given.
        what: &'static str,
        /// Needed count.
        expected: usize,
        /// Given count.
        found: usize,
    },
    /// [`Nurss::from_knots`] was given a topology without its full adjacency.
    #[error("the topology lacks the adjacency that refinement needs (build it with Topology::from_mesh)")]
    IncompleteTopology,
    /// The refined mesh would exceed the index range.
    #[error("refining to level {level} would make {faces} faces, beyond the index range")]
    TooLarge {
        /// Requested level.
        level: u32,
        /// Face count.
        faces: u64,
    },
}

/// One level of a NURSS refinement: topology, homogeneous points, knot intervals and
/// face-varying channels.
#[derive(Clone, Debug)]
pub struct Nurss {
    pub(crate) options: Options,
    pub(crate) topology: Topology,
    pub(crate) points: Vec<[f64; 4]>,
    pub(crate) rational: bool,
    pub(crate) knots: NurssKnots,
    pub(crate) level: u32,
    pub(crate) warnings: Vec<TopologyWarning>,
    /// The mesh's face-varying channels at this level (`face_varying`'s docs).
    pub(crate) face_varying: NurssFaceVarying,
}

impl Nurss {
    /// The base level of `mesh` with its [`PolyMesh::knots`] (intervals, side intervals,
    /// weights; untagged edges have interval 1, untagged vertices weight 1) and its
    /// face-varying channels ([`PolyMesh::face_varying`], e.g. texture coordinates), which
    /// [`step`](Self::step) refines with the mesh and [`to_mesh`](Self::to_mesh) writes.
    ///
    /// A channel is refined as the NURSS refinement of its *value mesh* (the mesh's faces
    /// through one vertex per face-varying subset, seams made boundaries, tagged per
    /// [`Options::face_varying`] as [`FaceVaryingSurface`](crate::limit::FaceVaryingSurface)
    /// describes): each value-mesh edge carries the interval of the mesh edge it lies on,
    /// each value-mesh vertex the weight of its mesh vertex (values are refined as
    /// homogeneous coordinates, so a channel that is an affine function of the positions
    /// stays that function of the refined positions), and on every level these and the
    /// mode's corners are the refined mesh's, as the level is written (so refining `a` then
    /// `b` levels equals `a + b`). With all intervals equal and no weights this is the
    /// Catmull-Clark refinement of the value mesh, which equals OpenSubdiv's face-varying
    /// refinement in all six modes on its regression shapes; in mode `all` channels are
    /// refined linearly (centroids and midpoints), as for Catmull-Clark, whatever the
    /// intervals. Sources: Sederberg, Zheng, Sewell & Sabin, "Non-uniform recursive
    /// subdivision surfaces", SIGGRAPH 1998 (the rules); OpenSubdiv 3.6
    /// `Bfr::SurfaceFactory::InitFaceVaryingSurface` (the value mesh); docs/nurss.md,
    /// "Texture coordinates" (the derivation and the checks).
    ///
    /// # Errors
    /// [`NurssError::Knots`] for a bad tag (naming it), [`NurssError::SemiSharp`],
    /// [`NurssError::Mesh`] from [`Topology::from_mesh`] (of the mesh or of a channel's
    /// value mesh).
    pub fn new(mesh: &PolyMesh, options: &Options) -> Result<Self, NurssError> {
        let mut s = Self::vertices_only(mesh, options)?;
        let weights = vertex_weights(mesh);
        s.face_varying = NurssFaceVarying::new(mesh, &s, &weights)?;
        Ok(s)
    }

    /// [`new`](Self::new) without the face-varying channels (for the surface and the
    /// re-posing plan, which do not read them).
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub(crate) fn vertices_only(mesh: &PolyMesh, options: &Options) -> Result<Self, NurssError> {
        mesh.knots.validate(mesh)?;
        let (topology, warnings) = Topology::from_mesh(mesh, options)?;
        let mut intervals = vec![1.0; topology.num_edges()];
        for t in &mesh.knots.intervals {
            // Every edge between the two vertices (non-manifold input can have several).
            let v0 = t.v0 as usize;
            for (&e, &l) in topology
                .vertex_edges(v0)
                .iter()
                .zip(topology.vertex_edge_locals(v0))
            {
                if topology.edge_vertices(e as usize)[1 - l as usize] == t.v1 {
                    intervals[e as usize] = t.interval;
                }
            }
        }
        let sides = if mesh.knots.side_intervals.is_empty() {
            None
        } else {
            let mut sides: Vec<f64> = topology
                .face_edges
                .iter()
                .map(|&e| intervals[e as usize])
                .collect();
            for t in &mesh.knots.side_intervals {
                let f = t.face as usize;
                let fv = topology.face_vertices(f);
                let n = fv.len();
                let o = topology.face_offsets[f] as usize;
                for j in 0..n {
                    let (a, b) = (fv[j], fv[(j + 1) % n]);
                    if (a, b) == (t.v0, t.v1) || (a, b) == (t.v1, t.v0) {
                        sides[o + j] = t.interval;
                    }
                }
            }
            Some(sides)
        };
        let weights = vertex_weights(mesh);
        let rational = !mesh.knots.weights.is_empty();
        let points = mesh
            .positions()
            .iter()
            .zip(&weights)
            .map(|(p, &w)| [w * p[0], w * p[1], w * p[2], w])
            .collect();
        let mut s = Self::from_knots(topology, *options, points, NurssKnots { intervals, sides })?;
        s.rational = rational;
        s.warnings = warnings;
        Ok(s)
    }

    /// A level from its parts: a complete `topology` (from [`Topology::from_mesh`]),
    /// homogeneous points `(w x, w y, w z, w)` per vertex (`w = 1`: not rational), and knot
    /// intervals per edge (and optional side intervals per face-vertex slot, see
    /// `NurssKnots`).
    ///
    /// # Errors
    /// [`NurssError::IncompleteTopology`], [`NurssError::WrongLength`],
    /// [`NurssError::SemiSharp`], and
    /// [`NurssError::Knots`] for a negative or non-finite interval or a weight ≤ 0.
    pub fn from_knots(
        topology: Topology,
        options: Options,
        points: Vec<[f64; 4]>,
        knots: NurssKnots,
    ) -> Result<Self, NurssError> {
        let t = &topology;
        if !t.is_complete() {
            return Err(NurssError::IncompleteTopology);
        }
        let check = |what, expected, found| {
            if expected == found {
                Ok(())
            } else {
                Err(NurssError::WrongLength {
                    what,
                    expected,
                    found,
                })
            }
        };
        check("points", t.num_vertices(), points.len())?;
        check("intervals", t.num_edges(), knots.intervals.len())?;
        if let Some(s) = &knots.sides {
            check("side intervals", t.face_verts.len(), s.len())?;
        }
        let all = knots
            .intervals
            .iter()
            .chain(knots.sides.iter().flatten())
            .enumerate();
        for (index, &value) in all {
            if !(value.is_finite() && value >= 0.0) {
                let what = if index < knots.intervals.len() {
                    "interval"
                } else {
                    "side interval"
                };
                return Err(KnotTagError::BadInterval { what, index, value }.into());
            }
        }
        for (index, p) in points.iter().enumerate() {
            if !(p[3].is_finite() && p[3] > 0.0) {
                return Err(KnotTagError::BadWeight {
                    index,
                    vertex: index as u32,
                    value: p[3],
                }
                .into());
            }
        }
        for e in 0..t.num_edges() {
            let s = t.edge_sharpness(e);
            if s > 0.0 && s < crate::mesh::SHARPNESS_INFINITE {
                let [a, b] = t.edge_vertices(e);
                return Err(NurssError::SemiSharp {
                    what: format!("the crease on edge ({a}, {b})"),
                    sharpness: s,
                });
            }
        }
        for v in 0..t.num_vertices() {
            let s = t.vertex_sharpness(v);
            if s > 0.0 && s < crate::mesh::SHARPNESS_INFINITE {
                return Err(NurssError::SemiSharp {
                    what: format!("vertex {v}"),
                    sharpness: s,
                });
            }
        }
        let rational = points.iter().any(|p| p[3] != 1.0);
        Ok(Self {
            options,
            topology,
            points,
            rational,
            knots,
            level: 0,
            warnings: Vec::new(),
            face_varying: NurssFaceVarying::None,
        })
    }

    /// The topology, knot intervals and base-mesh warnings of the current level.
    pub(crate) fn into_parts(self) -> (Topology, NurssKnots, Vec<TopologyWarning>) {
        (self.topology, self.knots, self.warnings)
    }

    /// Refines one level, face-varying channels included (auxiliary side intervals are
    /// used, then dropped).
    pub fn step(&mut self) {
        let (child, points, knots) =
            refine_nurss_step(&self.topology, &self.options, &self.knots, &self.points);
        let rational = self.rational.then_some(points.as_slice());
        (self.face_varying).step((&self.topology, &child), &knots, rational, &self.options);
        self.topology = child;
        self.points = points;
        self.knots = knots;
        self.level += 1;
    }

    /// Refines `levels` more levels.
    pub fn refine(&mut self, levels: u32) {
        for _ in 0..levels {
            self.step();
        }
    }

    /// Number of steps taken since the base level.
    pub fn level(&self) -> u32 {
        self.level
    }

    /// Topology of the current level.
    pub fn topology(&self) -> &Topology {
        &self.topology
    }

    /// Scheme options.
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// Warnings about the base mesh.
    pub fn warnings(&self) -> &[TopologyWarning] {
        &self.warnings
    }

    /// Knot intervals (and side intervals, on the base level) of the current level.
    pub fn knots(&self) -> &NurssKnots {
        &self.knots
    }

    /// Knot interval of every edge of the current level.
    pub fn intervals(&self) -> &[f64] {
        &self.knots.intervals
    }

    /// Homogeneous points `(w x, w y, w z, w)` of the current level.
    pub fn homogeneous(&self) -> &[[f64; 4]] {
        &self.points
    }

    /// Whether the mesh has rational weights.
    pub fn is_rational(&self) -> bool {
        self.rational
    }

    /// Cartesian positions of the current level (homogeneous points divided by their weight).
    pub fn positions(&self) -> Vec<[f64; 3]> {
        self.points
            .iter()
            .map(|p| project(p, self.rational))
            .collect()
    }

    /// The current level as a [`PolyMesh`]: hole faces left out unless `keep_holes` (then
    /// tagged), remaining sharpness as crease and corner tags (as [`crate::subdivide`](fn@crate::subdivide)
    /// writes them), [`PolyMesh::knots`] holding every interval that is not 1 (of edges of
    /// written faces) and, for a rational mesh, every weight, and the refined face-varying
    /// channels (their corners those of the written faces).
    pub fn to_mesh(&self, keep_holes: bool) -> PolyMesh {
        let level = &self.topology;
        let explicit_boundary = self.options.boundary == crate::mesh::BoundaryInterpolation::None;
        let mut offsets = Vec::with_capacity(level.num_faces() + 1);
        let mut verts = Vec::with_capacity(level.face_verts().len());
        let mut holes = Vec::new();
        offsets.push(0u32);
        // Index of each written face in the output.
        let mut written = vec![u32::MAX; level.num_faces()];
        for f in 0..level.num_faces() {
            let hole = level.is_hole(f);
            if hole && !keep_holes {
                continue;
            }
            written[f] = (offsets.len() - 1) as u32;
            if hole {
                holes.push((offsets.len() - 1) as u32);
            }
            verts.extend_from_slice(level.face_vertices(f));
            offsets.push(verts.len() as u32);
        }
        let mut tags = Tags {
            holes,
            ..Tags::default()
        };
        let mut knots = KnotTags::default();
        for e in 0..level.num_edges() {
            let t = level.edge_tag(e);
            let s = level.edge_sharpness(e);
            let [v0, v1] = level.edge_vertices(e);
            let keep = !t.non_manifold && (!t.boundary || explicit_boundary);
            if s > 0.0 && keep {
                tags.creases.push(Crease {
                    v0,
                    v1,
                    sharpness: s,
                });
            }
            let d = self.knots.own(level, e);
            let written = keep_holes
                || !level.has_holes()
                || level
                    .edge_face_list(e)
                    .iter()
                    .any(|&f| !level.is_hole(f as usize));
            if d != 1.0 && written && v0 != v1 {
                knots.intervals.push(EdgeInterval {
                    v0,
                    v1,
                    interval: d,
                });
            }
        }
        knots.side_intervals = self.side_intervals(&written);
        tags.corners = corner_tags(level);
        if self.rational {
            knots.weights = self
                .points
                .iter()
                .enumerate()
                .map(|(v, p)| VertexWeight {
                    vertex: v as u32,
                    weight: p[3],
                })
                .collect();
        }
        let mut m = PolyMesh::new_unchecked(self.positions(), offsets, verts);
        m.tags = tags;
        m.knots = knots;
        m.face_varying = self.face_varying.channels(level, keep_holes, None);
        m
    }

    /// The base level's auxiliary intervals where they differ from the edge's own, on the
    /// faces written (`written[f]`: face `f`'s index in the output, `u32::MAX` if dropped).
    fn side_intervals(&self, written: &[u32]) -> Vec<SideInterval> {
        let level = &self.topology;
        let mut out = Vec::new();
        let Some(sides) = &self.knots.sides else {
            return out;
        };
        for f in 0..level.num_faces() {
            if written[f] == u32::MAX {
                continue;
            }
            let fv = level.face_vertices(f);
            let o = level.face_offsets[f] as usize;
            for j in 0..fv.len() {
                let e = level.face_edges[o + j] as usize;
                let d = sides[o + j];
                if d != self.knots.own(level, e) {
                    out.push(SideInterval {
                        face: written[f],
                        v0: fv[j],
                        v1: fv[(j + 1) % fv.len()],
                        interval: d,
                    });
                }
            }
        }
        out
    }
}

/// The corner tags of `level`'s sharp vertices: not the non-manifold ones, nor the
/// boundary vertices of a single face that edge-and-corner interpolation makes sharp (the
/// written boundary option does that again).
fn corner_tags(level: &Topology) -> Vec<Corner> {
    let mut corners = Vec::new();
    for v in 0..level.num_vertices() {
        let s = level.vertex_sharpness(v);
        let t = level.vertex_tag(v);
        if s > 0.0 && !t.non_manifold && !t.sharpened_corner {
            corners.push(Corner {
                vertex: v as u32,
                sharpness: s,
            });
        }
    }
    corners
}

/// The plan of non-uniform Catmull-Clark subdivision (NURSS, [JOS 2003]) of `mesh` to
/// `levels`, with its knot intervals ([`PolyMesh::knots`]), as [`Nurss`] refines it: every
/// level is sparse rows, as their weights depend on the intervals and no fixed kernel
/// applies (see "Schemes" in [`crate::refine::plan`]).
///
/// # Errors
/// As [`Nurss::new`] (bad knot tags, semi-sharp creases, an invalid mesh), and
/// [`MeshError::TooLarge`] (in [`NurssError::Mesh`]) when the last level would exceed
/// 32-bit indices.
pub(crate) fn plan(
    mesh: &PolyMesh,
    options: Options,
    levels: u32,
) -> Result<RefinePlan, NurssError> {
    mesh.validate()?;
    check_size(mesh, Steps::Family(Mixed::CATMULL_CLARK), levels)?;
    let (level, knots, warnings) = Nurss::vertices_only(mesh, &options)?.into_parts();
    Ok(RefinePlan::from_nurss(
        level, knots, options, levels, warnings,
    ))
}

/// The weight of every vertex of `mesh`: its `t weight` tag (the last one, if several),
/// else 1.
pub(crate) fn vertex_weights(mesh: &PolyMesh) -> Vec<f64> {
    let mut weights = vec![1.0; mesh.num_vertices()];
    for w in &mesh.knots.weights {
        weights[w.vertex as usize] = w.weight;
    }
    weights
}

#[inline]
pub(crate) fn project(p: &[f64; 4], rational: bool) -> [f64; 3] {
    if rational {
        [p[0] / p[3], p[1] / p[3], p[2] / p[3]]
    } else {
        [p[0], p[1], p[2]]
    }
}
