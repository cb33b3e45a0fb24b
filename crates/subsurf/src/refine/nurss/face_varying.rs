//! Face-varying channels (texture coordinates) refined with NURSS, alongside the mesh's
//! [`Nurss`] levels.
//!
//! NURSS (Sederberg, Zheng, Sewell & Sabin, "Non-uniform recursive subdivision surfaces",
//! SIGGRAPH 1998: [Sederberg et al. 1998]) has no face-varying rules of its own, and
//! OpenSubdiv, which has no NURSS, none to compare with. The definition here extends the
//! one OpenSubdiv's `Bfr` uses for Catmull-Clark's limit (see
//! [`FaceVaryingSurface`](crate::limit::FaceVaryingSurface)): a channel is the surface of
//! its *value mesh* ([`ValueMesh`]: the mesh's faces through one vertex per face-varying
//! subset, seams made boundaries, vertex sharpness per linear-interpolation mode), and
//! under NURSS that surface is the value mesh's NURSS surface:
//!
//! - **Intervals.** Each value-mesh edge carries the knot interval of the mesh edge it lies
//!   on, each face side the mesh's side interval (the faces are the mesh's, slot for slot).
//! - **Rational weights.** Each value-mesh vertex carries the weight of the mesh vertex it
//!   lies on, and values are refined as homogeneous coordinates `(w s, w t, w)` and divided
//!   by the refined weight, as positions are. This is what keeps a channel that is an
//!   affine function of the positions (a planar projection `uv = A x + b`, laid out as the
//!   vertices) that function of the refined positions: one step makes
//!   `x' = Σ aᵢ wᵢ xᵢ / Σ aᵢ wᵢ`, and `A x' + b = Σ aᵢ wᵢ (A xᵢ + b) / Σ aᵢ wᵢ` is the
//!   weighted refinement of the values, not their unweighted `Σ aᵢ (A xᵢ + b)`. The channel
//!   is then, on a regular grid, a NURBS function with the surface's rational basis.
//! - **On every level.** A value level is the value mesh of the mesh level as it would be
//!   written and read back: after each step every value-mesh edge takes the refined
//!   interval of its mesh edge, every value its mesh vertex's refined weight (the
//!   homogeneous value rescaled, its Cartesian value unchanged), and every value-mesh
//!   vertex the sharpness the mode's rules give it on the refined level (on OpenSubdiv's
//!   regression shapes, the tags its face-varying refinement carries down). Where the
//!   value mesh's rules are the
//!   mesh's (no seam, no corner the mode sharpens) the refined intervals and weights are the
//!   same anyway. Elsewhere the value mesh alone would refine them otherwise (its boundary
//!   at a seam refines the weights along the seam alone, and on the first step halves its
//!   own side's interval where the mesh halves the mean of the two sides, [JOS 2003] §2),
//!   and a written level, which holds one interval per edge and one weight per vertex,
//!   could not carry that: reading the mesh's keeps refining `a` then `b` levels equal to
//!   refining `a + b` for the channels, in every mode. The limit of a level
//!   ([`crate::nonuniform`]) is the exact limit of its value mesh, which is the level's as
//!   written. The price: next to a seam or a sharpened corner of a rational mesh whose
//!   weights vary there, or a seam whose two sides carry different side intervals, the
//!   channel is not one fixed surface of the base value mesh, and the limits of successive
//!   levels differ there by a little, shrinking by about half per level (docs/nurss.md,
//!   "Texture coordinates", has the measure).
//! - **Linear channels** ([`FaceVaryingInterpolation::All`]) are refined as for
//!   Catmull-Clark ([`FaceVaryingRefiner`]: face points are centroids, edge points
//!   midpoints, vertices stay), unweighted. Midpoint knot insertion into a degree-1
//!   B-spline gives the midpoint whatever the intervals, so this is the non-uniform
//!   bilinear refinement; the value mesh cannot express it (its face points would read the
//!   intervals).
//!
//! With all intervals equal and no weights, NURSS is Catmull-Clark, and a channel's
//! refinement is the Catmull-Clark refinement of its value mesh.
//!
//! # Numbering
//! The value mesh's faces are the mesh's, so a value level's faces (children of a face in
//! its corner order, as `refine_topology` numbers them) are the mesh level's, face for
//! face and corner for corner: the refined channel's indices are the value level's face
//! vertices, and its values the value level's vertices (children of value-mesh vertices,
//! then of faces, then of edges), one per value-mesh vertex, but that a value the input
//! shares between two subsets of a vertex (a non-manifold value, which the rules keep a
//! corner) stays one value ([`ValueChannel::alias`]).

use super::{Nurss, NurssError, NurssKnots, NurssMasks};
use crate::mesh::{
    FaceVarying, FaceVaryingInterpolation, MeshError, Options, PolyMesh, Topology, ValueMesh,
};
use crate::refine::{refine_topology, FaceVaryingRefiner};
use crate::scheme::catmark::CatmullClark;

/// The values a smooth channel is written with, from its value level (e.g. its limit).
pub(crate) type ChannelValues<'a> = dyn Fn(&ValueChannel) -> Vec<f64> + 'a;

/// The face-varying channels of a [`Nurss`] level (see the module docs).
#[derive(Clone, Debug, Default)]
pub(crate) enum NurssFaceVarying {
    /// No channels.
    #[default]
    None,
    /// Linear channels ([`FaceVaryingInterpolation::All`]), refined as for Catmull-Clark.
    Linear(FaceVaryingRefiner),
    /// One value level per channel.
    Smooth(Vec<ValueChannel>),
}

/// One channel's value mesh as a NURSS level.
#[derive(Clone, Debug)]
pub(crate) struct ValueChannel {
    /// The channel's name.
    pub(crate) name: String,
    /// Components per value.
    pub(crate) dim: usize,
    /// The value level: topology, intervals (read from the mesh's level), and as points the
    /// homogeneous values' first three components, `(w c₀, w c₁, w c₂, w)` (zero beyond
    /// `dim`).
    pub(crate) level: Nurss,
    /// The further components, three at a time, homogeneous as `level`'s points.
    pub(crate) extra: Vec<Vec<[f64; 4]>>,
    /// Per value-level vertex, the value it writes: itself, or for a vertex whose value
    /// the channel shares with another subset of the same mesh vertex (a non-manifold
    /// value, kept a corner by the mode's rules, so the two stay equal) the first such
    /// vertex, so that the written level shares it too, as the input did.
    pub(crate) alias: Vec<u32>,
}

impl ValueChannel {
    /// The value level of `ch`, a channel of `mesh` whose base NURSS level is `base` (its
    /// topology and knot intervals) and whose vertices have rational `weights`: the value
    /// mesh's topology with [`ValueMesh::options`], the mesh's intervals and side intervals
    /// on it, and the values weighted by the weights of the mesh vertices they lie on.
    ///
    /// # Errors
    /// [`NurssError::Mesh`] if the value mesh is invalid, or
    /// ([`MeshError::BadFaceVarying`]) a value
    /// beyond the `f64` range once weighted.
    pub(crate) fn new(
        mesh: &PolyMesh,
        base: &Nurss,
        weights: &[f64],
        ch: &FaceVarying,
    ) -> Result<(Self, ValueMesh), NurssError> {
        let t = &base.topology;
        let explicit = ValueMesh::explicit_sharpness(mesh);
        let vm = ValueMesh::build(t, &base.options, ch.indices(), &explicit);
        let options = ValueMesh::options(&base.options);
        let pm = vm.polymesh(vec![[0.0; 3]; vm.num_vertices()])?;
        let (vt, _) = Topology::from_mesh(&pm, &options)?;
        let knots = value_knots(t, &base.knots, &vt);
        let dim = ch.dim();
        let mut chunks = (0..dim.div_ceil(3)).map(|chunk| {
            (vm.points(ch, chunk).iter().zip(&vm.vertex_of))
                .map(|(p, &v)| {
                    let w = weights[v as usize];
                    [w * p[0], w * p[1], w * p[2], w]
                })
                .collect::<Vec<_>>()
        });
        let first = chunks.next().unwrap_or_default();
        let extra: Vec<_> = chunks.collect();
        let finite = |c: &Vec<[f64; 4]>| c.iter().flatten().all(|x| x.is_finite());
        if !(finite(&first) && extra.iter().all(finite)) {
            return Err(MeshError::BadFaceVarying {
                channel: ch.name().to_string(),
                message: "a value times its vertex's weight is beyond the f64 range".into(),
            }
            .into());
        }
        let mut level = Nurss::from_knots(vt, options, first, knots)?;
        level.rational = base.rational;
        let mut first_of = std::collections::HashMap::new();
        let alias = (vm.value_of.iter().zip(&vm.vertex_of).enumerate())
            .map(|(w, key)| *first_of.entry(key).or_insert(w as u32))
            .collect();
        let channel = ValueChannel {
            name: ch.name().to_string(),
            dim,
            level,
            extra,
            alias,
        };
        Ok((channel, vm))
    }

    /// The value each face corner of the value level writes ([`alias`](Self::alias)).
    pub(crate) fn corner_values(&self) -> Vec<u32> {
        let vt = &self.level.topology;
        (vt.face_verts.iter())
            .map(|&w| self.alias[w as usize])
            .collect()
    }

    /// The channel's values, `dim` numbers per value-level vertex, from `chunks`: the
    /// value level's points, then the further components, three at a time (Cartesian).
    pub(crate) fn values(&self, chunks: &[Vec<[f64; 3]>]) -> Vec<f64> {
        let n = self.level.points.len();
        let mut out = vec![0.0; self.dim * n];
        for (c, pts) in chunks.iter().enumerate() {
            for (v, p) in pts.iter().enumerate() {
                for k in 0..3.min(self.dim - 3 * c) {
                    out[self.dim * v + 3 * c + k] = p[k];
                }
            }
        }
        out
    }

    /// The refined values, `dim` numbers per value-level vertex (homogeneous values
    /// divided by their weights).
    fn refined_values(&self) -> Vec<f64> {
        let rational = self.level.rational;
        let chunks: Vec<Vec<[f64; 3]>> = std::iter::once(&self.level.points)
            .chain(&self.extra)
            .map(|c| c.iter().map(|p| super::project(p, rational)).collect())
            .collect();
        self.values(&chunks)
    }

    /// Refines the channel one step, `child` and `knots` being the mesh's next level and
    /// its intervals, and `points` its homogeneous points if the mesh is rational (module
    /// docs, "On every level").
    fn step(&mut self, child: &Topology, knots: &NurssKnots, points: Option<&[[f64; 4]]>) {
        let level = &mut self.level;
        let t = &level.topology;
        let masks = NurssMasks::new(t, &level.knots);
        let n = t.num_vertices() + t.num_faces() + t.num_edges();
        for pts in std::iter::once(&mut level.points).chain(self.extra.iter_mut()) {
            let mut dst = vec![[0.0; 4]; n];
            masks.apply(t, pts, &mut dst);
            *pts = dst;
        }
        drop(masks);
        let mut vt = refine_topology(t, &level.options, true);
        // Children of vertices keep their parents' numbers (and aliases); the rest are new.
        self.alias
            .extend(self.alias.len() as u32..vt.num_vertices() as u32);
        retag(child, &mut vt, &self.alias, &level.options);
        level.knots = value_knots(child, knots, &vt);
        if let Some(points) = points {
            let chunks = std::iter::once(&mut level.points).chain(self.extra.iter_mut());
            reweight(child, points, &vt, chunks);
        }
        level.topology = vt;
        level.level += 1;
    }
}

/// Gives every vertex of the value level `vt` (a refined value level) the sharpness that
/// the value mesh of the mesh level `t` gives it ([`ValueMesh::build`] with the values
/// the corners write, `alias` of `vt`'s vertices, and the sharpness `t` is written with):
/// the mode's rules applied to the refined level, as reading it back from a file applies
/// them.
fn retag(t: &Topology, vt: &mut Topology, alias: &[u32], options: &Options) {
    let explicit = ValueMesh::written_sharpness(t);
    let indices: Vec<u32> = vt.face_verts.iter().map(|&w| alias[w as usize]).collect();
    let vm = ValueMesh::build(t, options, &indices, &explicit);
    let sharp = vm.vertex_sharpness();
    let mut s = vec![0.0f32; vt.num_vertices()];
    for (&w, &x) in vm.faces.iter().zip(&vt.face_verts) {
        s[x as usize] = s[x as usize].max(sharp[w as usize]);
    }
    for (v, &s) in s.iter().enumerate() {
        if s != vt.vertex_sharpness(v) {
            vt.set_vertex_sharpness(v, s);
        }
    }
}

/// Gives every value of the value level `vt` the weight of the mesh vertex it lies on
/// (`points`, the homogeneous points of the mesh level `t`), rescaling its homogeneous
/// `chunks` (their Cartesian values unchanged).
fn reweight<'a>(
    t: &Topology,
    points: &[[f64; 4]],
    vt: &Topology,
    chunks: impl Iterator<Item = &'a mut Vec<[f64; 4]>>,
) {
    let mut weight = vec![0.0; vt.num_vertices()];
    for (&w, &v) in vt.face_verts.iter().zip(&t.face_verts) {
        weight[w as usize] = points[v as usize][3];
    }
    for chunk in chunks {
        for (p, &w) in chunk.iter_mut().zip(&weight) {
            let s = w / p[3];
            *p = p.map(|x| x * s);
            p[3] = w;
        }
    }
}

/// The knot intervals of the value level `vt` of a mesh level `t` with `knots`: each value
/// edge the interval of the mesh edge it lies on (found through the face sides, which the
/// two levels share), each face side the mesh's.
fn value_knots(t: &Topology, knots: &NurssKnots, vt: &Topology) -> NurssKnots {
    let mut intervals = vec![1.0; vt.num_edges()];
    for (&ve, &e) in vt.face_edges.iter().zip(&t.face_edges) {
        intervals[ve as usize] = knots.intervals[e as usize];
    }
    NurssKnots {
        intervals,
        sides: knots.sides.clone(),
    }
}

impl NurssFaceVarying {
    /// The channels of `mesh` at its base level `base` (vertex `weights`), refined as the
    /// module docs say.
    ///
    /// # Errors
    /// As [`ValueChannel::new`].
    pub(crate) fn new(mesh: &PolyMesh, base: &Nurss, weights: &[f64]) -> Result<Self, NurssError> {
        if mesh.face_varying.is_empty() {
            return Ok(Self::None);
        }
        if base.options.face_varying == FaceVaryingInterpolation::All {
            let r = FaceVaryingRefiner::new(&base.topology, &mesh.face_varying, &base.options);
            return Ok(Self::Linear(r));
        }
        let channels = (mesh.face_varying.iter())
            .map(|ch| Ok(ValueChannel::new(mesh, base, weights, ch)?.0))
            .collect::<Result<_, NurssError>>()?;
        Ok(Self::Smooth(channels))
    }

    /// Refines every channel one step: `p` is the mesh's level, `c` its child with the
    /// intervals `knots` and, if the mesh is rational, the homogeneous points `points`.
    pub(crate) fn step(
        &mut self,
        (p, c): (&Topology, &Topology),
        knots: &NurssKnots,
        points: Option<&[[f64; 4]]>,
        options: &Options,
    ) {
        match self {
            Self::None => {}
            Self::Linear(r) => r.refine(p, c, options, CatmullClark),
            Self::Smooth(channels) => {
                (channels.iter_mut()).for_each(|ch| ch.step(c, knots, points));
            }
        }
    }

    /// The channels of the mesh level `last` as [`FaceVarying`]s, their faces those that
    /// are written (all with `keep_holes`, else those that are not holes), their values
    /// the refined ones or, when `values` is given, `values(channel)` for each smooth
    /// channel (e.g. its limit).
    pub(crate) fn channels(
        &self,
        last: &Topology,
        keep_holes: bool,
        values: Option<&ChannelValues<'_>>,
    ) -> Vec<FaceVarying> {
        match self {
            Self::None => Vec::new(),
            Self::Linear(r) => r.clone().finish(last, keep_holes),
            Self::Smooth(channels) => (channels.iter())
                .map(|ch| {
                    let values = match values {
                        Some(f) => f(ch),
                        None => ch.refined_values(),
                    };
                    let vt = &ch.level.topology;
                    let corners = ch.corner_values();
                    let indices = if keep_holes || !last.has_holes() {
                        corners
                    } else {
                        (0..last.num_faces())
                            .filter(|&f| !last.is_hole(f))
                            .flat_map(|f| {
                                let o = vt.face_offsets[f] as usize;
                                corners[o..vt.face_offsets[f + 1] as usize].to_vec()
                            })
                            .collect()
                    };
                    FaceVarying::new_unchecked(ch.name.clone(), ch.dim, values, indices)
                })
                .collect(),
        }
    }
}
