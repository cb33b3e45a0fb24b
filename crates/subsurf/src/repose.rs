//! Re-posing a subdivision: the refined mesh of a base mesh whose vertices move (animation
//! frames, interactive editing, fitting) while its faces and tags stay the same.
//!
//! [`Reposer`] refines the base mesh once with [`subdivide`] (the refined faces and tags,
//! which do not depend on the positions) and builds a [`RefinePlan`] (the linear map from
//! base positions to refined ones). Each new pose then costs one application of the plan,
//! 10–20× less than refining again (`BENCHMARKS.md`), and gives the positions
//! [`subdivide`] would give on the moved mesh, to rounding (within 1e-14 of the mesh's
//! size; see the plan's accuracy notes).

use crate::mesh::{check_coordinates, MeshError, PolyMesh, TopologyWarning};
use crate::refine::{PlanScratch, RefinePlan};
use crate::subdivide::{estimate_memory, subdivide, Error, SubdivideOptions};

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
    /// The base mesh's faces (CSR), which a posed mesh must repeat ([`Reposer::pose_mesh`]).
    base_offsets: Vec<u32>,
    base_verts: Vec<u32>,
    /// The refined mesh, with the positions of the last pose.
    mesh: PolyMesh,
    plan: RefinePlan,
    scratch: PlanScratch<3>,
    warnings: Vec<TopologyWarning>,
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
    /// Refines `base` with `opts` (as [`subdivide`]) and builds the plan that re-poses the
    /// result. The base mesh's tags (creases, corners, holes) and `opts.scheme` hold for
    /// every pose.
    ///
    /// # Errors
    /// As [`subdivide`], the memory estimate ([`Error::TooLarge`]) counting the plan too
    /// ([`RefinePlan::estimate_memory`]); [`Error::LimitNotReposable`] when `opts.limit` is
    /// set (the plan computes refined positions, not limit positions and normals).
    pub fn new(base: &PolyMesh, opts: &SubdivideOptions) -> Result<Self, Error> {
        if opts.limit {
            return Err(Error::LimitNotReposable);
        }
        if let Some(limit) = opts.max_memory {
            let estimate = estimate_memory(base, opts)
                .saturating_add(RefinePlan::estimate_memory(base, opts.levels));
            if estimate > limit {
                return Err(Error::TooLarge {
                    levels: opts.levels,
                    estimate,
                    limit,
                });
            }
        }
        let sub = subdivide(base, opts)?;
        let plan = RefinePlan::new(base, opts.scheme, opts.levels)?;
        debug_assert_eq!(plan.num_vertices(), sub.mesh.num_vertices());
        Ok(Self {
            base_offsets: base.face_offsets().to_vec(),
            base_verts: base.face_verts().to_vec(),
            mesh: sub.mesh,
            plan,
            scratch: PlanScratch::default(),
            warnings: sub.warnings,
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
        self.plan
            .apply_into(positions, self.mesh.positions_vec_mut(), &mut self.scratch);
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
            let expected = self.base_offsets.len() - 1;
            if posed.num_faces() != expected {
                return Err(PoseError::FaceCount {
                    expected,
                    found: posed.num_faces(),
                });
            }
            let base = |f: usize| {
                &self.base_verts[self.base_offsets[f] as usize..self.base_offsets[f + 1] as usize]
            };
            if let Some(face) = (0..expected).find(|&f| posed.face(f) != base(f)) {
                return Err(PoseError::Face { face });
            }
        }
        self.pose(posed.positions())
    }

    /// The refined mesh, with the positions of the last pose (at first, the base mesh's).
    pub fn mesh(&self) -> &PolyMesh {
        &self.mesh
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
                scheme: Options::default(),
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

    #[test]
    fn limit_and_memory_are_refused() {
        let base = grid();
        let limit = SubdivideOptions {
            levels: 2,
            limit: true,
            ..Default::default()
        };
        assert_eq!(
            Reposer::new(&base, &limit).unwrap_err(),
            Error::LimitNotReposable
        );
        let small = SubdivideOptions {
            levels: 4,
            max_memory: Some(1000),
            ..Default::default()
        };
        assert!(matches!(
            Reposer::new(&base, &small),
            Err(Error::TooLarge { levels: 4, .. })
        ));
    }
}
