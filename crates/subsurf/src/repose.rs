//! Re-posing a subdivision: the refined mesh of a base mesh whose vertices move (animation
//! frames, interactive editing, fitting) while its faces and tags stay the same.
//!
//! [`Reposer`] refines the base mesh once with [`subdivide`] (the refined faces and tags,
//! which do not depend on the positions) and builds a [`RefinePlan`] (the linear map from
//! base positions to refined ones). Each new pose then costs one application of the plan,
//! 10–20× less than refining again (7.7–11× on one thread, 10–17× on two, on all-triangle
//! scans and random semi-sharp creases refined 2–3 levels; `BENCHMARKS.md`), and gives
//! the positions
//! [`subdivide`] would give on the moved mesh, to rounding (within 1e-14 of the mesh's
//! size; see the plan's accuracy notes), whatever the scheme: for non-uniform subdivision
//! ([`Scheme::Nurss`]) rational weights stay with their vertices from pose to pose.
//!
//! With [`SubdivideOptions::limit`], the limit positions and normals too: the limit masks
//! of the refined level ([`crate::limit::limit_points`], OpenSubdiv's
//! `PrimvarRefiner::Limit`) are linear in its positions, so they are stored as rows of
//! weights (position and two tangents per point, `limit::VertexLimitRows`) applied after
//! the plan, and each normal is
//! `t₁ × t₂ / |t₁ × t₂|` ([`crate::limit::normals`], with its fallback to the faces'
//! normals where the tangents are degenerate). NURSS limit points
//! ([`crate::nonuniform::Nurss::limit_points`]) are iterated on the data, but each is a linear
//! map of the level's points whose weights are found by iterating on unit points instead;
//! those rows are applied after the plan, in homogeneous points (positions only).

use crate::limit::{largest_coordinate, normals_into, VertexLimitRows};
use crate::mesh::{check_coordinates, MeshError, PolyMesh, Topology, TopologyWarning};
use crate::nonuniform::LimitRows;
use crate::refine::{refine_topology, Error, PlanScratch, RefinePlan, TopologyRefiner};
use crate::scheme::adjustable::Mixed;
use crate::scheme::Scheme;
use crate::subdivide::{estimate_memory, subdivide, SubdivideOptions, Subdivision};

/// A subdivision that can be re-posed: the refined mesh of a base mesh, recomputed for new
/// base positions with a [`RefinePlan`] instead of a full refinement.
///
/// ```
/// use subsurf::mesh::PolyMesh;
/// use subsurf::{subdivide, Reposer, SubdivideOptions};
///
/// // A cube: eight corners, six quads.
/// let corners: Vec<[f64; 3]> = (0..8)
///     .map(|i| [(i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2) as f64])
///     .collect();
/// let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
/// let cube = PolyMesh::from_faces(corners.clone(), &faces)?;
/// let opts = SubdivideOptions { levels: 3, ..Default::default() };
/// let mut reposer = Reposer::new(&cube, &opts)?;
///
/// // A new pose: the cube stretched along x.
/// let stretched: Vec<[f64; 3]> = corners.iter().map(|p| [2.0 * p[0], p[1], p[2]]).collect();
/// let posed = reposer.pose(&stretched)?.clone();
///
/// // The same mesh as refining the stretched cube, to rounding.
/// let full = subdivide(&PolyMesh::from_faces(stretched, &faces)?, &opts)?.mesh;
/// assert_eq!(posed.face_verts(), full.face_verts());
/// for (a, b) in posed.positions().iter().zip(full.positions()) {
///     assert!((0..3).all(|i| (a[i] - b[i]).abs() < 1e-14));
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct Reposer {
    /// The base mesh's faces, which a posed mesh must repeat ([`Reposer::pose_mesh`]).
    base_faces: Lists,
    /// The refined mesh, with the positions of the last pose.
    mesh: PolyMesh,
    plan: RefinePlan,
    scratch: PlanScratch<3>,
    warnings: Vec<TopologyWarning>,
    /// With [`SubdivideOptions::limit`]: the limit positions and normals.
    limit: Option<Box<LimitMap>>,
    /// For a rational NURSS mesh or the NURSS limit: the plan maps homogeneous points.
    homogeneous: Option<Box<Homogeneous>>,
}

/// The weights of a NURSS base mesh (1 unless rational), the homogeneous points
/// `(w x, w y, w z, w)` of the base and refined levels, and with the limit, the rows that
/// map the refined level's to the limit's (buffers kept from pose to pose).
#[derive(Clone, Debug)]
struct Homogeneous {
    weights: Vec<f64>,
    base: Vec<[f64; 4]>,
    level: Vec<[f64; 4]>,
    scratch: PlanScratch<4>,
    limit: Option<(LimitRows, Vec<[f64; 4]>)>,
}

impl Homogeneous {
    /// Writes into `out` the positions of `plan` applied to the points `positions` with
    /// their weights: the homogeneous points refined (and mapped to the limit), then divided
    /// by their weight (as [`Nurss::positions`](crate::nonuniform::Nurss::positions)).
    fn apply(&mut self, plan: &RefinePlan, positions: &[[f64; 3]], out: &mut [[f64; 3]]) {
        self.base.clear();
        self.base.extend(
            positions
                .iter()
                .zip(&self.weights)
                .map(|(p, &w)| [w * p[0], w * p[1], w * p[2], w]),
        );
        plan.apply_into(&self.base, &mut self.level, &mut self.scratch);
        let points = match &mut self.limit {
            Some((rows, limit)) => {
                limit.resize(rows.len(), [0.0; 4]);
                rows.apply(&self.level, limit);
                limit
            }
            None => &self.level,
        };
        for (o, h) in out.iter_mut().zip(points) {
            *o = [h[0] / h[3], h[1] / h[3], h[2] / h[3]];
        }
    }
}

/// The limit positions and normals of a refined level as maps of the positions of the
/// plan's last level (the refined level itself, or, for a base mesh with faces other than
/// quads refined 0 levels, one level more, whose first vertices are the base mesh's; as
/// [`subdivide`]'s `limit_in_place`).
#[derive(Clone, Debug)]
struct LimitMap {
    /// Limit positions and tangents, one row per vertex of the refined mesh.
    rows: VertexLimitRows,
    /// The faces of each vertex of the refined level, holes included, and
    vertex_faces: Lists,
    /// the vertices of each face, for the normals at degenerate tangents.
    face_verts: Lists,
    /// The positions of the plan's last level, the tangents and the normals (buffers kept
    /// from pose to pose).
    level: Vec<[f64; 3]>,
    t: [Vec<[f64; 3]>; 2],
    normals: Vec<[f64; 3]>,
}

/// Lists of indices, one after the other (CSR).
#[derive(Clone, Debug)]
struct Lists {
    offsets: Vec<u32>,
    items: Vec<u32>,
}

impl Lists {
    /// The lists `list(0)`, …, `list(n − 1)`.
    fn new<'a>(n: usize, list: impl Fn(usize) -> &'a [u32]) -> Self {
        let mut offsets = Vec::with_capacity(n + 1);
        let mut items = Vec::new();
        offsets.push(0);
        for i in 0..n {
            items.extend_from_slice(list(i));
            offsets.push(items.len() as u32);
        }
        Lists { offsets, items }
    }

    /// The number of lists.
    fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// List `i`.
    fn get(&self, i: usize) -> &[u32] {
        &self.items[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }
}

impl LimitMap {
    /// The maps (`scheme`'s limit masks) of the first `n` vertices of `rows` (full
    /// adjacency), the normals' faces
    /// from `faces` (the refined level), and the current normals `normals`.
    fn new(scheme: Scheme, rows: &Topology, faces: &Topology, normals: Vec<[f64; 3]>) -> Self {
        let n = faces.num_vertices();
        LimitMap {
            rows: VertexLimitRows::new(scheme, rows, n),
            vertex_faces: Lists::new(n, |v| faces.vertex_faces(v)),
            face_verts: Lists::new(faces.num_faces(), |f| faces.face_vertices(f)),
            level: Vec::new(),
            t: [vec![[0.0; 3]; n], vec![[0.0; 3]; n]],
            normals,
        }
    }

    /// Limit positions into `pos` and the normals into `self.normals`, from the positions
    /// in `self.level`, those of the base mesh being `base` (which bound the level's).
    fn apply(&mut self, pos: &mut [[f64; 3]], base: &[[f64; 3]]) {
        let [t1, t2] = &mut self.t;
        self.rows.apply(&self.level, pos, t1, t2);
        let (vf, fv) = (&self.vertex_faces, &self.face_verts);
        normals_into(
            |v| vf.get(v),
            |f| fv.get(f),
            (pos, largest_coordinate(base)),
            &self.t[0],
            &self.t[1],
            &mut self.normals,
        );
    }
}

/// Why a pose was rejected by [`Reposer::pose`] or [`Reposer::pose_mesh`]. Faces and
/// vertices are numbered from 0.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PoseError {
    /// The pose has another number of vertices than the base mesh.
    #[error("the pose has {found} vertices, the base mesh {expected}")]
    VertexCount {
        /// The base mesh's vertices.
        expected: usize,
        /// The pose's.
        found: usize,
    },
    /// The posed mesh has faces, but not as many as the base mesh.
    #[error(
        "the pose has {found} faces, the base mesh {expected}: a pose repeats the base \
         mesh's faces or has none"
    )]
    FaceCount {
        /// The base mesh's faces.
        expected: usize,
        /// The pose's.
        found: usize,
    },
    /// A face of the posed mesh is not the base mesh's face of the same index.
    #[error(
        "face {face} is not the base mesh's face {face}: a pose repeats the base mesh's \
         faces, in the same order, or has none"
    )]
    Face {
        /// The first face that differs.
        face: usize,
    },
    /// A coordinate is not finite, or too large ([`MeshError::NonFiniteCoordinate`],
    /// [`MeshError::CoordinateTooLarge`]).
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

impl Reposer {
    /// Refines `base` with `opts` (as [`subdivide`], with `opts.scheme`) and builds the plan
    /// that re-poses the result. The base mesh's tags (creases, corners, holes; knot
    /// intervals and weights with [`Scheme::Nurss`]) and `opts.options` hold for every pose.
    ///
    /// With `opts.limit`, each pose gives the limit positions and the limit normals
    /// ([`normals`](Self::normals)), as [`subdivide`] does; building then refines the
    /// topology once more, with the last level's full adjacency, for its limit masks.
    /// NURSS gives limit positions only ([`crate::nonuniform::Nurss::limit_points`], within
    /// 1e-14 of the size: rows of weights on the refined level, applied after the plan).
    ///
    /// A rational NURSS base mesh (weight tags) keeps its weights: a pose moves the points,
    /// each keeps the weight of its vertex; the refined mesh keeps the refined intervals and
    /// weights as tags ([`PolyMesh::knots`]).
    ///
    /// ```
    /// use subsurf::mesh::{EdgeInterval, PolyMesh};
    /// use subsurf::{subdivide, Reposer, Scheme, SubdivideOptions};
    ///
    /// let corners: Vec<[f64; 3]> = (0..8)
    ///     .map(|i| [(i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2) as f64])
    ///     .collect();
    /// let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    /// let mut cube = PolyMesh::from_faces(corners.clone(), &faces)?;
    /// // Non-uniform: edges along x three times as long in parameter as the others.
    /// for [a, b] in [[0, 1], [2, 3], [4, 5], [6, 7]] {
    ///     cube.knots.intervals.push(EdgeInterval { v0: a, v1: b, interval: 3.0 });
    /// }
    /// let opts = SubdivideOptions { levels: 3, scheme: Scheme::Nurss, ..Default::default() };
    /// let mut reposer = Reposer::new(&cube, &opts)?;
    ///
    /// let stretched: Vec<[f64; 3]> = corners.iter().map(|p| [2.0 * p[0], p[1], p[2]]).collect();
    /// let posed = reposer.pose(&stretched)?.clone();
    /// let mut moved = cube.clone();
    /// moved.positions_mut().copy_from_slice(&stretched);
    /// let full = subdivide(&moved, &opts)?.mesh;
    /// for (a, b) in posed.positions().iter().zip(full.positions()) {
    ///     assert!((0..3).all(|i| (a[i] - b[i]).abs() < 1e-14));
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// As [`subdivide`] ([`Error::Mesh`], [`Error::Nurss`]), the memory estimate
    /// ([`Error::TooLarge`]) counting the plan too ([`Reposer::estimate_memory`]).
    pub fn new(base: &PolyMesh, opts: &SubdivideOptions) -> Result<Self, Error> {
        let scheme = opts.scheme;
        if let Some(limit) = opts.max_memory {
            let estimate = Self::estimate_memory(base, opts);
            if estimate > limit {
                return Err(Error::TooLarge {
                    levels: opts.levels,
                    estimate,
                    limit,
                });
            }
        }
        let mut nurss_limit = None;
        let sub = match scheme {
            Scheme::Nurss => {
                // The limit positions come from the rows below, as every pose's.
                let s =
                    crate::nonuniform::refined(base, &opts.options, opts.levels, &mut |_, _| {})?;
                nurss_limit = opts.limit.then(|| s.limit_rows());
                let mut mesh = crate::subdivide::nurss_output(base, &s, opts, false)?;
                if opts.limit {
                    // The face-varying channels are the same in every pose.
                    mesh.face_varying = s.face_varying_limit(opts.keep_holes);
                }
                Subdivision {
                    mesh,
                    warnings: s.warnings().to_vec(),
                    normals: None,
                }
            }
            _ => subdivide(base, opts)?,
        };
        // Limit masks need quads around each vertex: on a base mesh with other faces,
        // refined 0 levels, they are taken one level further down (as `subdivide` does).
        // (NURSS limit rows map the level itself; Loop's masks need triangles, which it has.)
        let ngons = (0..base.num_faces()).any(|f| base.face(f).len() != 4);
        let own_rows = matches!(scheme, Scheme::Nurss | Scheme::Loop);
        let plan_levels = if opts.limit && opts.levels == 0 && ngons && !own_rows {
            1
        } else {
            opts.levels
        };
        // The level that limit masks may add is Catmull-Clark's, as in `subdivide`.
        let plan_scheme = match scheme {
            Scheme::Adjustable(m) => Scheme::Adjustable(Mixed {
                steps: m.steps.min(opts.levels),
                ..m
            }),
            s => s,
        };
        let plan = RefinePlan::new(base, plan_scheme, opts.options, plan_levels)?;
        // NURSS in homogeneous points when rational or mapped to the limit (whose rows map
        // homogeneous points).
        let nurss = scheme == Scheme::Nurss;
        let mut homogeneous = (nurss && (!base.knots.weights.is_empty() || nurss_limit.is_some()))
            .then(|| {
                Box::new(Homogeneous {
                    weights: crate::nonuniform::vertex_weights(base),
                    base: Vec::new(),
                    level: Vec::new(),
                    scratch: PlanScratch::default(),
                    limit: nurss_limit.map(|rows| (rows, Vec::new())),
                })
            });
        let mut mesh = sub.mesh;
        if let Some(h) = homogeneous.as_mut().filter(|h| h.limit.is_some()) {
            h.apply(&plan, base.positions(), mesh.positions_mut());
        }
        let limit = match sub.normals {
            Some(normals) => {
                let refiner = TopologyRefiner::new(base, scheme, opts.options)?;
                let topology_options = *refiner.options();
                let level = refiner.into_level(opts.levels);
                let map = if plan_levels > opts.levels {
                    let rows = refine_topology(&level, &topology_options, true);
                    LimitMap::new(scheme, &rows, &level, normals)
                } else {
                    LimitMap::new(scheme, &level, &level, normals)
                };
                Some(Box::new(map))
            }
            None => None,
        };
        Ok(Self {
            base_faces: Lists::new(base.num_faces(), |f| base.face(f)),
            mesh,
            plan,
            scratch: PlanScratch::default(),
            warnings: sub.warnings,
            limit,
            homogeneous,
        })
    }

    /// The refined mesh for the base positions `positions` (one per base vertex): the
    /// plan applied to them. Nothing is allocated after the first pose.
    ///
    /// # Errors
    /// [`PoseError::VertexCount`] unless there is one position per base vertex;
    /// [`PoseError::Mesh`] for a coordinate that is not finite or too large. The mesh then
    /// keeps its previous positions.
    pub fn pose(&mut self, positions: &[[f64; 3]]) -> Result<&PolyMesh, PoseError> {
        let expected = self.plan.num_base_vertices();
        if positions.len() != expected {
            return Err(PoseError::VertexCount {
                expected,
                found: positions.len(),
            });
        }
        check_coordinates(positions)?;
        match (&mut self.limit, &mut self.homogeneous) {
            (None, None) => {
                (self.plan).apply_into(positions, self.mesh.positions_vec_mut(), &mut self.scratch)
            }
            (None, Some(h)) => h.apply(&self.plan, positions, self.mesh.positions_mut()),
            (Some(limit), _) => {
                (self.plan).apply_into(positions, &mut limit.level, &mut self.scratch);
                limit.apply(self.mesh.positions_mut(), positions);
            }
        }
        Ok(&self.mesh)
    }

    /// [`pose`](Self::pose) with the positions of `posed`, a mesh that either has the base
    /// mesh's faces (the same vertices in the same order; its tags are not read) or none
    /// (positions only, as a point cache).
    ///
    /// # Errors
    /// [`PoseError::FaceCount`] or [`PoseError::Face`] (the first face that differs) when
    /// its faces are not the base mesh's; as [`pose`](Self::pose).
    pub fn pose_mesh(&mut self, posed: &PolyMesh) -> Result<&PolyMesh, PoseError> {
        if posed.num_faces() > 0 {
            let expected = self.base_faces.len();
            if posed.num_faces() != expected {
                return Err(PoseError::FaceCount {
                    expected,
                    found: posed.num_faces(),
                });
            }
            let base = &self.base_faces;
            if let Some(face) = (0..expected).find(|&f| posed.face(f) != base.get(f)) {
                return Err(PoseError::Face { face });
            }
        }
        self.pose(posed.positions())
    }

    /// Estimated peak memory in bytes of [`new`](Self::new) and the first pose, saturating
    /// at `u64::MAX`: [`estimate_memory`] of the refinement plus
    /// [`RefinePlan::estimate_memory`]. `new` refuses to start above
    /// [`SubdivideOptions::max_memory`]; check it first to say so in your own terms.
    ///
    /// NURSS refinement keeps every level complete and refines homogeneous points (twice
    /// [`estimate_memory`] of Catmull-Clark's), and the plan is sparse rows on every level
    /// ([`RefinePlan::estimate_memory`] covers them). Its limit refines the last level's
    /// topology once more (its vertices' fans) while the last level is kept complete with
    /// its masks: three times Catmull-Clark's estimate of one level more (the measured
    /// peaks it covers are in BENCHMARKS.md, "Allocator settings, kept buffers and memory
    /// estimates"). Each face-varying channel, refined as a value mesh of its own, adds
    /// twice that estimate.
    pub fn estimate_memory(base: &PolyMesh, opts: &SubdivideOptions) -> u64 {
        let plan = RefinePlan::estimate_memory(base, opts.scheme, opts.levels);
        if opts.scheme != Scheme::Nurss {
            return estimate_memory(base, opts).saturating_add(plan);
        }
        let refined = SubdivideOptions {
            levels: opts.levels.saturating_add(u32::from(opts.limit)),
            limit: false,
            scheme: Scheme::CatmullClark,
            ..opts.clone()
        };
        // Each face-varying channel is a value mesh refined as the mesh (a level of its own).
        let copies = u64::from(2 + u8::from(opts.limit)) + 2 * base.face_varying.len() as u64;
        (estimate_memory(base, &refined).saturating_mul(copies)).saturating_add(plan)
    }

    /// The refined mesh, with the positions of the last pose (at first, the base mesh's).
    pub fn mesh(&self) -> &PolyMesh {
        &self.mesh
    }

    /// The limit normals of the last pose, one per vertex of [`mesh`](Self::mesh), when
    /// the options asked for the limit ([`SubdivideOptions::limit`]; not for NURSS, whose
    /// limit has no normals, as in [`subdivide`]).
    pub fn normals(&self) -> Option<&[[f64; 3]]> {
        self.limit.as_ref().map(|l| l.normals.as_slice())
    }

    /// The plan applied to each pose.
    pub fn plan(&self) -> &RefinePlan {
        &self.plan
    }

    /// Warnings about the base mesh (ignored tags, non-manifold elements), as
    /// [`Subdivision::warnings`](crate::Subdivision::warnings).
    pub fn warnings(&self) -> &[TopologyWarning] {
        &self.warnings
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Options;

    /// A 3×3 grid of quads with a hole in the middle and a crease across it.
    fn grid() -> PolyMesh {
        let positions: Vec<[f64; 3]> = (0..16)
            .map(|i| [(i % 4) as f64, (i / 4) as f64, ((i * 7) % 5) as f64 * 0.1])
            .collect();
        let faces: Vec<[u32; 4]> = (0..9)
            .map(|f| {
                let (x, y) = (f % 3, f / 3);
                let v = 4 * y + x;
                [v, v + 1, v + 5, v + 4]
            })
            .collect();
        let mut mesh = PolyMesh::from_faces(positions, &faces).unwrap();
        mesh.tags.holes.push(4);
        mesh.tags.creases.push(crate::mesh::Crease {
            v0: 4,
            v1: 5,
            sharpness: 1.5,
        });
        mesh
    }

    fn moved(mesh: &PolyMesh, t: f64) -> Vec<[f64; 3]> {
        (mesh.positions().iter().enumerate())
            .map(|(i, p)| {
                let w = (i as f64 * 1.7 + t).sin();
                [p[0] + 0.3 * w, 2.0 * p[1] - t, p[2] + w * w]
            })
            .collect()
    }

    /// Each pose gives what refining the moved mesh gives: the same faces and tags, the
    /// positions to rounding; holes are left out as `subdivide` leaves them out.
    #[test]
    fn poses_match_subdivide() {
        let base = grid();
        for keep_holes in [false, true] {
            let opts = SubdivideOptions {
                levels: 3,
                options: Options::default(),
                keep_holes,
                ..Default::default()
            };
            let mut reposer = Reposer::new(&base, &opts).unwrap();
            assert_eq!(reposer.mesh(), &subdivide(&base, &opts).unwrap().mesh);
            for t in [0.0, 0.5, 2.0] {
                let mut mesh = base.clone();
                mesh.positions_mut().copy_from_slice(&moved(&base, t));
                let full = subdivide(&mesh, &opts).unwrap().mesh;
                let posed = reposer.pose_mesh(&mesh).unwrap();
                assert_eq!(posed.face_offsets(), full.face_offsets());
                assert_eq!(posed.face_verts(), full.face_verts());
                assert_eq!(posed.tags, full.tags);
                for (a, b) in posed.positions().iter().zip(full.positions()) {
                    assert!((0..3).all(|i| (a[i] - b[i]).abs() < 1e-13), "{a:?} {b:?}");
                }
            }
        }
    }

    #[test]
    fn bad_poses_are_rejected_and_leave_the_mesh_as_it_was() {
        let base = grid();
        let opts = SubdivideOptions {
            levels: 2,
            ..Default::default()
        };
        let mut reposer = Reposer::new(&base, &opts).unwrap();
        let before = reposer.mesh().clone();
        let n = base.num_vertices();
        assert_eq!(
            reposer.pose(&base.positions()[1..]).unwrap_err(),
            PoseError::VertexCount {
                expected: n,
                found: n - 1
            }
        );
        let mut nan = base.positions().to_vec();
        nan[5][1] = f64::NAN;
        assert!(matches!(
            reposer.pose(&nan),
            Err(PoseError::Mesh(MeshError::NonFiniteCoordinate {
                vertex: 5,
                ..
            }))
        ));
        // Faces other than the base mesh's: fewer, or one turned.
        let faces: Vec<&[u32]> = base.faces().take(8).collect();
        let fewer = PolyMesh::from_faces(base.positions().to_vec(), &faces).unwrap();
        assert_eq!(
            reposer.pose_mesh(&fewer).unwrap_err(),
            PoseError::FaceCount {
                expected: 9,
                found: 8
            }
        );
        let mut faces: Vec<Vec<u32>> = base.faces().map(<[u32]>::to_vec).collect();
        faces[6].rotate_left(1);
        let turned = PolyMesh::from_faces(base.positions().to_vec(), &faces).unwrap();
        assert_eq!(
            reposer.pose_mesh(&turned).unwrap_err(),
            PoseError::Face { face: 6 }
        );
        assert_eq!(reposer.mesh(), &before);
        // Positions only: accepted.
        let points = PolyMesh::from_faces(moved(&base, 1.0), &[] as &[[u32; 4]]).unwrap();
        let posed = reposer.pose_mesh(&points).unwrap().clone();
        assert_eq!(
            posed.positions(),
            reposer.pose(&moved(&base, 1.0)).unwrap().positions()
        );
    }

    /// With `limit`, each pose gives `subdivide`'s limit positions and normals: on the grid
    /// (a hole, a semi-sharp crease), a hexagonal hut with triangles at levels 0 (its limit
    /// masks one level down) and 2, and at two poses each.
    #[test]
    fn limit_poses_match_subdivide() {
        let hut = {
            let mut p: Vec<[f64; 3]> = (0..6)
                .map(|i| {
                    let a = i as f64 * std::f64::consts::FRAC_PI_3;
                    [a.cos(), a.sin(), 0.0]
                })
                .collect();
            let top: Vec<[f64; 3]> = p.iter().map(|q| [q[0], q[1], 1.0]).collect();
            p.extend(top);
            p.push([0.0, 0.0, 1.8]);
            let mut faces: Vec<Vec<u32>> = vec![(0..6).rev().collect()];
            for i in 0..6u32 {
                let j = (i + 1) % 6;
                faces.push(vec![i, j, j + 6, i + 6]);
                faces.push(vec![i + 6, j + 6, 12]);
            }
            PolyMesh::from_faces(p, &faces).unwrap()
        };
        for (base, levels) in [(grid(), 2), (grid(), 3), (hut.clone(), 0), (hut, 2)] {
            let opts = SubdivideOptions {
                levels,
                limit: true,
                ..Default::default()
            };
            let mut reposer = Reposer::new(&base, &opts).unwrap();
            for t in [0.7, 1.9] {
                let mut mesh = base.clone();
                mesh.positions_mut().copy_from_slice(&moved(&base, t));
                let full = subdivide(&mesh, &opts).unwrap();
                let posed = reposer.pose(mesh.positions()).unwrap();
                assert_eq!(posed.face_verts(), full.mesh.face_verts());
                for (a, b) in posed.positions().iter().zip(full.mesh.positions()) {
                    assert!((0..3).all(|i| (a[i] - b[i]).abs() < 1e-13), "{a:?} {b:?}");
                }
                let normals = reposer.normals().unwrap();
                let expected = full.normals.unwrap();
                assert_eq!(normals.len(), expected.len());
                for (a, b) in normals.iter().zip(&expected) {
                    assert!((0..3).all(|i| (a[i] - b[i]).abs() < 1e-12), "{a:?} {b:?}");
                }
            }
        }
    }

    #[test]
    fn memory_is_refused() {
        let small = SubdivideOptions {
            levels: 4,
            max_memory: Some(1000),
            ..Default::default()
        };
        assert!(matches!(
            Reposer::new(&grid(), &small),
            Err(Error::TooLarge { levels: 4, .. })
        ));
        let plain = Reposer::new(&grid(), &SubdivideOptions::default()).unwrap();
        assert!(plain.normals().is_none());
    }
}
