//! How much memory a [`LimitSurface`] takes: bounds to check before building one and
//! before evaluating it, and a build that stops at a limit.
//!
//! A surface holds a node per face (a regular quad's is 16 vertex indices) and, for its
//! irregular faces, one configuration tree per distinct neighbourhood ([`super::tree`]),
//! which evaluation deepens a level per halving of the spacing of the points evaluated.
//! How many configurations a mesh has is known only once they are found, which is most of
//! building the surface: refined meshes and scans have a few hundred (`rocker-arm`, 20 088
//! triangles: 376; `nefertiti`, 99 938: 967), a mesh whose irregular faces all differ (say,
//! by their crease sharpness) one per irregular face. So the bound is taken in two steps:
//!
//! 1. before building: [`LimitSurface::estimate_build_memory`], everything but the
//!    configurations (per vertex and per face); [`LimitSurface::new_within`] then builds
//!    while charging each configuration as it is found, and stops with
//!    [`BuildError::TooLarge`] at the limit instead of running out of memory;
//! 2. before evaluating: [`LimitSurface::estimate_memory`], the built surface with its
//!    configurations deepened as far as the points need.
//!
//! The constants are upper bounds of peaks measured (`/proc/self/status` `VmHWM` around
//! [`LimitSurface::new`] and around evaluating every face, mimalloc as in the binary, one
//! and two threads) on the 81 OpenSubdiv regression shapes, the repository's examples and
//! eleven public scans and their triangulations (`BENCHMARKS.md`, "Memory of limit
//! surfaces"); on meshes of more than 5 000 faces the estimates were 1.7–6.6× the
//! surface's measured peak, the most on large quad meshes (charged per vertex and face as
//! much as triangulations, which take four times more). Since plain faces keep nothing
//! and the freed memory of the build is returned at once, large quad meshes take less
//! still: `catmark_bishop` refined four times (240 k quads) is estimated at 409 MiB for an
//! 8 × 8 grid per face and peaks at 61 MiB in `bench --limit-grid 8` (6.7×; the constants
//! were not lowered, as triangulations still need them).

use super::LimitSurface;
use crate::mesh::{MeshError, PolyMesh};
use std::borrow::Cow;

/// Bytes taken whatever the mesh: the worker threads' stacks and the allocator's arenas,
/// which grow in steps of 2–4 MiB (measured: 2.6–4.7 MiB to build the smallest shapes,
/// up to 11 MiB with points evaluated 1/32 apart), and the program's own pages (the
/// `subsurf` binary: 8–13 MiB resident before it reads its input).
const FIXED_BYTES: u64 = 24 << 20;

/// Bytes per vertex and per face of the mesh, configurations apart: the surface's copy of
/// the positions, the base level's topology, a node per face (but plain ones) and, for an
/// irregular face, its cut-out's vertices and points (measured: 0.12 KiB on the 240 k quads of
/// `catmark_bishop` refined four times, 0.3–0.4 KiB on quad meshes refined twice, up to
/// 0.55 KiB on triangulations).
const ELEMENT_BYTES: u64 = 768;

/// Bytes per configuration and per level of it: charged twice when it is built and first
/// evaluated (its root cut-out's topology, refinement weights, children and corner
/// analyses: 60–130 KiB measured on meshes of more than a thousand faces), and once more
/// per level evaluated (up to 65 KiB measured, on triangulations).
const CONFIGURATION_LEVEL_BYTES: u64 = 80 << 10;

/// Bytes per face in the shared region of a vertex of high valence (see
/// [`super::local::HIGH_VALENCE`]) and per level evaluated: such faces are refined on
/// their own, from the region's points, as deep as the points need (measured: 32 KiB at
/// `catmark_nonman_quadpole64`, 41 KiB at `catmark_nonman_quadpole360`), and two levels
/// more for the region's first refinements.
const REGION_FACE_LEVEL_BYTES: u64 = 48 << 10;

/// Bytes per corner of a face of more than [`super::local::LARGE_FACE`] corners when the
/// surface is built: the face's shared region and its first refinement, in which the
/// face's `n` sub-faces share the region of its centre (measured: up to 3.3 KiB, a lone
/// 65 535-gon).
const LARGE_FACE_CORNER_BYTES: u64 = 4 << 10;

/// Bytes per node in the shared region of a large face (its sub-faces, and the faces
/// that share a vertex with it) and per level evaluated, and one level more: each level
/// refines the region of the face's centre once and splits each node (measured: up to
/// 7.4 KiB per node and level, on a prism over a 16 000-gon at rate 32).
const LARGE_FACE_NODE_LEVEL_BYTES: u64 = 8 << 10;

/// Errors of [`LimitSurface::new_within`] and [`SurfaceBuilder::build`](super::SurfaceBuilder::build).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BuildError {
    /// The mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Building the surface would take more memory than allowed.
    #[error(
        "the limit surface needs more than {} MiB (found {configurations} distinct \
         neighbourhoods of irregular faces so far, about {} KiB each)",
        limit >> 20,
        (2 * CONFIGURATION_LEVEL_BYTES) >> 10
    )]
    TooLarge {
        /// Configurations found when the build stopped.
        configurations: usize,
        /// Allowed bytes.
        limit: u64,
    },
}

/// The memory limit of a build: the bytes of everything but the configurations, and the
/// limit.
#[derive(Clone, Copy, Debug)]
pub(super) struct Budget {
    pub fixed: u64,
    pub limit: u64,
}

impl Budget {
    /// Whether `configurations` configurations take the build over its limit.
    pub(super) fn exceeded_by(self, configurations: usize) -> bool {
        self.fixed
            .saturating_add(configuration_bytes(configurations, 2))
            > self.limit
    }
}

/// [`LimitSurface::estimate_build_memory`] of a mesh of `vertices` vertices and `faces`
/// faces, `large_corners` of them corners of large faces.
fn build_bytes(vertices: usize, faces: usize, large_corners: u64) -> u64 {
    let elements = (vertices as u64).saturating_add(faces as u64);
    FIXED_BYTES
        .saturating_add(elements.saturating_mul(ELEMENT_BYTES))
        .saturating_add(large_corners.saturating_mul(LARGE_FACE_CORNER_BYTES))
}

/// The corners of `mesh`'s faces of more than [`super::local::LARGE_FACE`] corners.
fn large_face_corners<'a>(faces: impl Iterator<Item = &'a [u32]>) -> u64 {
    faces
        .map(|f| f.len())
        .filter(|&n| n > super::local::LARGE_FACE)
        .map(|n| n as u64)
        .sum()
}

/// Bytes of `n` configurations at `levels` levels.
fn configuration_bytes(n: usize, levels: u64) -> u64 {
    (n as u64)
        .saturating_mul(levels)
        .saturating_mul(CONFIGURATION_LEVEL_BYTES)
}

/// Levels of refinement that evaluating points `1 / divisions` apart needs near an
/// extraordinary vertex: `ceil(log2 divisions)` (at most 32, below
/// [`super::MAX_DEPTH`]).
fn levels_for(divisions: u32) -> u64 {
    u64::from(u32::BITS - (divisions.max(1) - 1).leading_zeros())
}

impl LimitSurface {
    /// Estimated bytes of building the surface of `mesh` ([`LimitSurface::new`]), apart
    /// from its configurations: `24 MiB + 768 B × (vertices + faces)`, and `4 KiB` per
    /// corner of each face of more than `LARGE_FACE` corners
    /// (its shared region, refined once).
    ///
    /// A surface's irregular faces take one configuration tree per distinct
    /// neighbourhood, most of the memory of a surface that has many, and their number is
    /// known only once they are found (refined meshes and scans have a few hundred, a mesh
    /// whose irregular faces all differ one per face). So a job checks this before
    /// building, builds with [`LimitSurface::new_within`], which charges each
    /// configuration as it is found, and checks [`LimitSurface::estimate_memory`] before
    /// evaluating. The constants bound the peaks measured on the OpenSubdiv shapes and
    /// public scans (`BENCHMARKS.md`, "Memory of limit surfaces").
    ///
    /// ```
    /// use subsurf::limit::LimitSurface;
    /// use subsurf::mesh::PolyMesh;
    /// let quad = PolyMesh::from_faces(
    ///     vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
    ///     &[[0, 1, 2, 3]],
    /// ).unwrap();
    /// assert_eq!(LimitSurface::estimate_build_memory(&quad), (24 << 20) + 5 * 768);
    /// ```
    pub fn estimate_build_memory(mesh: &PolyMesh) -> u64 {
        let large = large_face_corners(mesh.faces());
        build_bytes(mesh.num_vertices(), mesh.num_faces(), large)
    }

    /// [`LimitSurface::new`], stopping with [`BuildError::TooLarge`] as soon as the
    /// configurations found would take the estimate over `max_bytes`:
    /// [`LimitSurface::estimate_build_memory`] plus 160 KiB per configuration (built and
    /// first evaluated). Nothing is kept of a stopped build. Like [`LimitSurface::new`],
    /// it takes the mesh or a reference to it.
    ///
    /// # Errors
    /// [`BuildError::Mesh`] if the mesh is invalid, [`BuildError::TooLarge`] over the limit.
    pub fn new_within<'a>(
        mesh: impl Into<Cow<'a, PolyMesh>>,
        options: crate::mesh::Options,
        max_bytes: u64,
    ) -> Result<Self, BuildError> {
        Self::builder(mesh, options).max_bytes(max_bytes).build()
    }

    /// Estimated bytes of this surface once points `1 / divisions` of a face's side apart
    /// have been evaluated (an `n`×`n` grid or a tessellation at rate `n`: `n`), input
    /// mesh included: [`LimitSurface::estimate_build_memory`], plus per configuration
    /// `80 KiB × (l + 2)`, per face in the shared region of a vertex of high valence
    /// `48 KiB × (l + 2)` and per node in the shared region of a large face (its `n`
    /// sub-faces and each face sharing a vertex with it) `8 KiB × (l + 1)`, with
    /// `l = ceil(log2 divisions)` levels. Every configuration is charged as if it were
    /// evaluated.
    ///
    /// Measured on faces of 4 000 to 65 535 vertices (alone, and as the caps of prisms), at
    /// rates 2 to 32 (`subsurf tessellate`, peak RSS of the release build): the job's
    /// estimate (this and 128 bytes per output vertex) was 1.4–5.9 times the peak, the
    /// most at rate 2 (`BENCHMARKS.md`, "Memory of limit surfaces").
    ///
    /// ```
    /// use subsurf::limit::LimitSurface;
    /// use subsurf::mesh::{Options, PolyMesh};
    /// // A cube: its six faces, each with four corners of valence 3, share one
    /// // configuration.
    /// let p = vec![
    ///     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
    ///     [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
    /// ];
    /// let f = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
    /// let cube = PolyMesh::from_faces(p, &f).unwrap();
    /// let s = LimitSurface::new(&cube, Options::default()).unwrap();
    /// assert_eq!(s.num_configurations(), 1);
    /// let built = LimitSurface::estimate_build_memory(&cube);
    /// assert_eq!(s.estimate_memory(1), built + 2 * (80 << 10));
    /// assert_eq!(s.estimate_memory(16), built + 6 * (80 << 10));
    /// ```
    pub fn estimate_memory(&self, divisions: u32) -> u64 {
        let levels = levels_for(divisions);
        let regions = self.num_region_faces() as u64;
        let large = large_face_corners(self.base_faces());
        let large_nodes = self.num_large_face_nodes() as u64;
        build_bytes(self.num_vertices(), self.num_faces(), large)
            .saturating_add(configuration_bytes(self.num_configurations(), levels + 2))
            .saturating_add(
                regions
                    .saturating_mul(levels + 2)
                    .saturating_mul(REGION_FACE_LEVEL_BYTES),
            )
            .saturating_add(
                large_nodes
                    .saturating_mul(levels + 1)
                    .saturating_mul(LARGE_FACE_NODE_LEVEL_BYTES),
            )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Crease, Options};

    /// An `n`×`n` grid of squares split into triangles, with a crease of its own sharpness
    /// on every horizontal interior edge: no two triangles away from the border share a
    /// neighbourhood.
    fn creased_triangles(n: u32) -> PolyMesh {
        let w = n + 1;
        let p = (0..w * w)
            .map(|i| [f64::from(i % w), f64::from(i / w), 0.0])
            .collect();
        let mut faces = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let a = j * w + i;
                faces.push(vec![a, a + 1, a + w + 1]);
                faces.push(vec![a, a + w + 1, a + w]);
            }
        }
        let mut mesh = PolyMesh::from_faces(p, &faces).expect("valid mesh");
        for j in 1..n {
            for i in 0..n {
                let v0 = j * w + i;
                mesh.tags.creases.push(Crease {
                    v0,
                    v1: v0 + 1,
                    sharpness: 0.5 + (j * n + i) as f32 / 64.0,
                });
            }
        }
        mesh
    }

    /// `new_within` builds the surface `new` builds when its configurations fit, and
    /// stops as soon as they do not: with room for ten, after finding the eleventh.
    #[test]
    fn a_build_within_a_limit_stops_at_the_configurations_that_do_not_fit() {
        let mesh = creased_triangles(8);
        let options = Options::default();
        let whole = LimitSurface::new(&mesh, options).expect("surface");
        let n = whole.num_configurations();
        assert!(n > 40, "{n} configurations");
        let fixed = LimitSurface::estimate_build_memory(&mesh);
        let room = |k: usize| fixed + configuration_bytes(k, 2);
        let within = LimitSurface::new_within(&mesh, options, room(n)).expect("fits");
        assert_eq!(within.num_configurations(), n);
        for f in 0..mesh.num_faces() as u32 {
            let (a, b) = (whole.eval(f, 0.3, 0.6), within.eval(f, 0.3, 0.6));
            assert_eq!(a.expect("point").p, b.expect("point").p, "face {f}");
        }
        match LimitSurface::new_within(&mesh, options, room(10)) {
            Err(BuildError::TooLarge {
                configurations,
                limit,
            }) => {
                assert!((11..n).contains(&configurations), "{configurations}");
                assert_eq!(limit, room(10));
            }
            other => panic!("not stopped: {other:?}"),
        }
        assert!(matches!(
            LimitSurface::new_within(&mesh, options, fixed - 1),
            Err(BuildError::TooLarge {
                configurations: 0,
                ..
            })
        ));
    }

    /// Faces of more than `LARGE_FACE` corners are charged per corner when built, and per
    /// node of their shared regions (their sub-faces, and the faces that share a vertex
    /// with them) and level evaluated, plus one.
    #[test]
    fn the_estimate_charges_large_faces_per_corner_and_region_node() {
        let n = super::super::local::LARGE_FACE as u32 + 4;
        let p: Vec<[f64; 3]> = (0..2 * n)
            .map(|i| {
                let a = std::f64::consts::TAU * f64::from(i % n) / f64::from(n);
                [a.cos(), a.sin(), f64::from(i / n) + 0.1 * (3.0 * a).sin()]
            })
            .collect();
        let mut faces = vec![(n..2 * n).collect::<Vec<u32>>(), (0..n).rev().collect()];
        for k in 0..n {
            let j = (k + 1) % n;
            faces.push(vec![k, j, n + j, n + k]);
        }
        let prism = PolyMesh::from_faces(p, &faces).expect("prism");
        let plain = FIXED_BYTES + u64::from(2 * n + n + 2) * ELEMENT_BYTES;
        let built = LimitSurface::estimate_build_memory(&prism);
        assert_eq!(built, plain + u64::from(2 * n) * LARGE_FACE_CORNER_BYTES);
        let s = LimitSurface::new(&prism, Options::default()).expect("surface");
        // Both caps' sub-faces and the side quads, which share a vertex with them.
        let nodes = s.num_large_face_nodes() as u64;
        assert_eq!(nodes, u64::from(3 * n));
        let c = s.num_configurations() as u64;
        for (divisions, levels) in [(1, 0), (4, 2), (32, 5)] {
            assert_eq!(
                s.estimate_memory(divisions),
                built
                    + c * (levels + 2) * CONFIGURATION_LEVEL_BYTES
                    + nodes * (levels + 1) * LARGE_FACE_NODE_LEVEL_BYTES,
                "{divisions}"
            );
        }
    }

    /// The estimate after building charges each configuration two levels and one per
    /// level evaluated, and each face in the region of a vertex of high valence one per
    /// level and two more.
    #[test]
    fn the_estimate_charges_configurations_and_region_faces_per_level() {
        // A fan of 150 triangles around a vertex of valence 150, and the quad strip around
        // it (150 quads): the faces next to the centre are in its region.
        let k = 150u32;
        let mut p = vec![[0.0, 0.0, 0.0]];
        for ring in 1..=2 {
            for i in 0..k {
                let a = std::f64::consts::TAU * f64::from(i) / f64::from(k);
                p.push([f64::from(ring) * a.cos(), f64::from(ring) * a.sin(), 0.0]);
            }
        }
        let mut faces = Vec::new();
        for i in 0..k {
            let (a, b) = (1 + i, 1 + (i + 1) % k);
            faces.push(vec![0, a, b]);
            faces.push(vec![a, a + k, b + k, b]);
        }
        let mesh = PolyMesh::from_faces(p, &faces).expect("valid mesh");
        let s = LimitSurface::new(&mesh, Options::default()).expect("surface");
        let (c, r) = (s.num_configurations() as u64, s.num_region_faces() as u64);
        assert!(r >= u64::from(k), "{r} region faces");
        let fixed = LimitSurface::estimate_build_memory(&mesh);
        assert_eq!(
            fixed,
            FIXED_BYTES + (2 * u64::from(k) + 1 + 2 * u64::from(k)) * ELEMENT_BYTES
        );
        let at = |levels: u64| {
            fixed
                + c * (levels + 2) * CONFIGURATION_LEVEL_BYTES
                + r * (levels + 2) * REGION_FACE_LEVEL_BYTES
        };
        assert_eq!(s.estimate_memory(0), at(0));
        assert_eq!(s.estimate_memory(1), at(0));
        assert_eq!(s.estimate_memory(2), at(1));
        assert_eq!(s.estimate_memory(16), at(4));
        assert_eq!(s.estimate_memory(17), at(5));
        assert_eq!(s.estimate_memory(u32::MAX), at(32));
    }
}
