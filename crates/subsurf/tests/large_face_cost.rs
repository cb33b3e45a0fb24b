//! The cost of the limit surface over a face of `n` vertices is linear in `n`: building it,
//! tessellating it and evaluating a grid on each of its `n` sub-faces (whose corners all meet
//! at the face's centre, a vertex of valence `n`) allocate `O(n)` bytes in `O(n)` blocks.
//! Counted with a counting global allocator (a binary of its own, so that no other test
//! allocates meanwhile) at two sizes, four times apart: a linear cost grows four times, a
//! quadratic one sixteen. Before faces of many vertices shared regions, a face was the root
//! of a configuration tree whose refinement rows read all `n` corners from each of its
//! `O(n)` refined points, and each of its sub-faces cut out the `n` faces around the centre.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use subsurf::limit::{tessellate, LimitSurface, Order, SurfacePoint};
use subsurf::mesh::{Options, PolyMesh};

/// The system allocator, counting allocations and the bytes they ask for.
struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);
static BYTES: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to `System`; the counters have no effect on the memory.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        BYTES.fetch_add(layout.size(), Ordering::Relaxed);
        System.alloc(layout)
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        BYTES.fetch_add(new_size, Ordering::Relaxed);
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// A prism over an `n`-gon (two caps, `n` side quads), or its top cap alone: a lone face,
/// every vertex a boundary crease vertex. Off the cylinder, so that no two corners are
/// alike.
fn prism(n: usize, cap_only: bool) -> PolyMesh {
    let mut p = Vec::new();
    for z in [0.0, 1.0] {
        for k in 0..n {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            let r = 1.0 + 0.1 * (3.0 * a).sin() + 0.05 * (7.0 * a + z).cos();
            p.push([r * a.cos(), r * a.sin(), z + 0.1 * (5.0 * a).cos()]);
        }
    }
    let m = n as u32;
    let mut faces = vec![(0..m).map(|k| m + k).collect::<Vec<u32>>()];
    if !cap_only {
        faces.push((0..m).rev().collect());
        for k in 0..m {
            let j = (k + 1) % m;
            faces.push(vec![k, j, m + j, m + k]);
        }
    }
    PolyMesh::from_faces(p, &faces).expect("prism")
}

/// Allocations and bytes of building the surface of `mesh`, tessellating it at rate 4 and
/// evaluating a 5 × 5 grid on every sub-face (as `subsurf limit --grid 5` does), positions
/// and first derivatives.
fn cost(mesh: &PolyMesh) -> (usize, usize) {
    let o = Options::default();
    let (a0, b0) = (
        ALLOCATIONS.load(Ordering::Relaxed),
        BYTES.load(Ordering::Relaxed),
    );
    let surface = LimitSurface::new(mesh, o).expect("surface");
    let t = tessellate(&surface, mesh, 4, false).expect("tessellation");
    assert!(t.num_faces() > 0);
    let mut points = Vec::new();
    for f in 0..surface.num_faces() {
        for sub in 0..surface.num_subfaces(f) {
            for k in 0..25 {
                points.push(SurfacePoint {
                    face: f as u32,
                    subface: sub as u32,
                    u: (k / 5) as f64 / 4.0,
                    v: (k % 5) as f64 / 4.0,
                });
            }
        }
    }
    let mut out = Vec::new();
    surface.eval_many_into(&points, Order::First, &mut out);
    assert!(out.iter().all(Result::is_ok));
    drop((surface, t, points, out));
    (
        ALLOCATIONS.load(Ordering::Relaxed) - a0,
        BYTES.load(Ordering::Relaxed) - b0,
    )
}

#[test]
fn large_faces_cost_linear_allocations() {
    // One thread: the counts do not depend on how work is split.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    for cap_only in [true, false] {
        let what = if cap_only { "lone face" } else { "prism" };
        let (n, big) = (64, 256);
        let (small, large) =
            pool.install(|| (cost(&prism(n, cap_only)), cost(&prism(big, cap_only))));
        let ratio = |a: usize, b: usize| b as f64 / a as f64;
        let (count, bytes) = (ratio(small.0, large.0), ratio(small.1, large.1));
        // Four times the corners: four times the work, with a margin for the logarithms
        // of hash maps growing and the output's fixed part.
        assert!(
            count < 5.0 && bytes < 5.0,
            "{what}: {n} → {big} vertices: {count:.1}× the allocations ({} → {}), \
             {bytes:.1}× the bytes ({} → {})",
            small.0,
            large.0,
            small.1,
            large.1
        );
    }
}
