//! # subsurf
//!
//! Smooth surfaces on arbitrary polygon meshes: Catmull-Clark subdivision that agrees with
//! OpenSubdiv (Pixar's reference implementation) to 1e-12 — boundaries, semi-sharp creases,
//! corners, holes, n-gons, non-manifold topology — and limit positions and normals.
//!
//! ```
//! use subsurf::mesh::{Options, PolyMesh};
//! use subsurf::{subdivide, SubdivideOptions};
//!
//! // A cube, refined twice.
//! let p = vec![
//!     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
//!     [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
//! ];
//! let faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
//! let cube = PolyMesh::from_faces(p, &faces).unwrap();
//! let out = subdivide(&cube, &SubdivideOptions { levels: 2, ..Default::default() }).unwrap();
//! assert_eq!(out.mesh.num_faces(), 6 * 16);
//! // Catmull-Clark shrinks the cube towards its centre but keeps its symmetry.
//! let c = out.mesh.positions().iter().fold([0.0; 3], |a, p| [a[0] + p[0], a[1] + p[1], a[2] + p[2]]);
//! let n = out.mesh.num_vertices() as f64;
//! assert!((c[0] / n - 0.5).abs() < 1e-12);
//! ```
//!
//! The scheme is a parameter ([`Scheme`]: Catmull-Clark, the shape-adjustable scheme,
//! non-uniform Catmull-Clark with knot intervals, Loop, bilinear) of every operation:
//! [`subdivide`](fn@subdivide), [`estimate_memory`], [`refine::RefinePlan::new`],
//! [`Reposer::new`]. Face-varying data (texture coordinates, [`mesh::FaceVarying`]) is
//! refined with the positions.
//!
//! Layers, bottom-up (see `ARCHITECTURE.md`): [`mesh`] (polygon meshes and their adjacency),
//! [`scheme`] (subdivision weights only), [`refine`] (topology refinement once, then fast
//! application to any primvar), [`limit`] (exact limit evaluation), the paper methods,
//! [`io`] (files), [`render`], and the one-call facade [`subdivide`](fn@subdivide).
//!
//! # Speed: choose the global allocator
//! Refinement writes every byte of a few fresh buffers (about 100 bytes per output vertex)
//! and frees the previous level's. With glibc's `malloc`, large blocks are mapped and
//! unmapped per call, so every 4 KiB page is faulted in and zeroed by the kernel again, at
//! about the cost of the refinement itself. An allocator that keeps its memory and reuses
//! it removes that cost. The `subsurf` binary uses
//! [mimalloc](https://crates.io/crates/mimalloc), and applications that refine large
//! meshes should consider doing the same (BENCHMARKS.md has the figures):
//!
//! ```ignore
//! #[global_allocator]
//! static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;
//! ```
#![warn(missing_docs)]
#![warn(unreachable_pub)]
// Geometry kernels walk several parallel arrays with one index; iterator chains would hide that.
#![allow(clippy::needless_range_loop)]

pub mod blend;
pub mod curves;
#[cfg(feature = "g2")]
pub mod g2cap;
pub mod io;
pub mod limit;
pub mod mesh;
pub mod nonuniform;
pub mod nurbs;
pub mod refine;
pub mod regularity;
#[cfg(feature = "render")]
pub mod render;
pub mod scheme;
pub mod spline;

mod cpu;
mod geom;
mod hash;
mod info;
mod json;
mod mixed;
mod repose;
mod subdivide;

/// The README's examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
struct ReadmeDoctests;

/// The examples of the pages in `docs/`, compiled and run as doc tests (one item per page).
#[cfg(doctest)]
mod docs_doctests {
    #[doc = include_str!("../../../docs/library.md")]
    struct Library;
    #[doc = include_str!("../../../docs/catmull-clark.md")]
    struct CatmullClark;
    #[doc = include_str!("../../../docs/nurss.md")]
    struct Nurss;
    #[doc = include_str!("../../../docs/curve-interpolation.md")]
    struct CurveInterpolation;
    #[doc = include_str!("../../../docs/blend.md")]
    struct Blend;
    #[doc = include_str!("../../../docs/adjustable-g2.md")]
    struct AdjustableG2;
    #[doc = include_str!("../../../docs/sub-basis-spline.md")]
    struct SubBasisSpline;
    #[doc = include_str!("../../../docs/regularity.md")]
    struct Regularity;
}

pub use info::{mesh_info, MeshInfo};
pub use mixed::MixedSurface;
pub use refine::error::Error;
pub use repose::{PoseError, Reposer};
pub use scheme::adjustable::Mixed;
pub use scheme::kind::Scheme;
pub use subdivide::{
    estimate_memory, subdivide, subdivide_with_progress, SubdivideOptions, Subdivision,
};
