//! Cost that grows linearly with the size of the input, shown by counting work rather than
//! by timing it (tests run on busy machines): a counting global allocator records how many
//! blocks and bytes a job allocates and its peak of live bytes, and each job runs at two
//! sizes, `n` and `2 n`. Linear cost doubles every count; the quadratic costs these tests
//! guard against (every face around a vertex cutting out the whole fan, a linear search of
//! a vertex's edges per edge) quadruple them. The bound, 2.3, leaves room for the
//! constant part of a job and for growth steps of vectors landing differently at the two
//! sizes.
//!
//! One job at a time (the tests of this file take turns) on one thread (a pool of one), so
//! that nothing else in the process allocates meanwhile.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use subsurf::limit::{tessellate_mesh, LimitSurface, SurfacePoint};
use subsurf::mesh::{Options, PolyMesh, Topology};
use subsurf::{subdivide, SubdivideOptions};

/// The system allocator, counting blocks, bytes and the peak of live bytes.
struct Counting;

static BLOCKS: AtomicUsize = AtomicUsize::new(0);
static BYTES: AtomicUsize = AtomicUsize::new(0);
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(bytes: usize) {
    BLOCKS.fetch_add(1, Ordering::Relaxed);
    BYTES.fetch_add(bytes, Ordering::Relaxed);
    let live = LIVE.fetch_add(bytes, Ordering::Relaxed) + bytes;
    PEAK.fetch_max(live, Ordering::Relaxed);
}

// SAFETY: forwards to `System`; the counters have no effect on the memory.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        grew(layout.size());
        System.alloc(layout)
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        System.dealloc(ptr, layout)
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        grew(new_size);
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// What a job allocated: blocks, bytes in all, and the peak of live bytes above the live
/// bytes at its start.
#[derive(Debug, Clone, Copy)]
struct Work {
    blocks: usize,
    bytes: usize,
    peak: usize,
}

/// Taken while a job is counted: the counters are the whole process's.
static TURN: Mutex<()> = Mutex::new(());

/// Runs `job` on a pool of one thread and counts what it allocates.
fn count(job: impl FnOnce() + Send) -> Work {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("thread pool");
    pool.install(|| {
        let (blocks, bytes, live) = (
            BLOCKS.load(Ordering::SeqCst),
            BYTES.load(Ordering::SeqCst),
            LIVE.load(Ordering::SeqCst),
        );
        PEAK.store(live, Ordering::SeqCst);
        job();
        Work {
            blocks: BLOCKS.load(Ordering::SeqCst) - blocks,
            bytes: BYTES.load(Ordering::SeqCst) - bytes,
            peak: PEAK.load(Ordering::SeqCst) - live,
        }
    })
}

/// A fan of `n` triangles (or quads, with an outer ring) around vertex 0: one vertex of
/// valence `n`, the others of valence 3 or 4.
fn fan(n: usize, quads: bool) -> PolyMesh {
    let mut p = vec![[0.0, 0.0, 0.0]];
    for i in 0..n {
        let a = i as f64 / n as f64 * std::f64::consts::TAU;
        p.push([a.cos(), a.sin(), 0.1 * (3.0 * a).sin()]);
    }
    if quads {
        for i in 0..n {
            let a = (i as f64 + 0.5) / n as f64 * std::f64::consts::TAU;
            p.push([2.0 * a.cos(), 2.0 * a.sin(), 0.0]);
        }
    }
    let faces: Vec<Vec<u32>> = (0..n)
        .map(|i| {
            let (a, b) = (i as u32 + 1, ((i + 1) % n) as u32 + 1);
            if quads {
                vec![0, a, (n + 1 + i) as u32, b]
            } else {
                vec![0, a, b]
            }
        })
        .collect();
    PolyMesh::from_faces(p, &faces).expect("valid fan")
}

/// Asserts that every count of `job` at size `2 n` is at most 2.6 times its count at `n`.
fn assert_linear(what: &str, n: usize, job: impl Fn(usize) + Sync) {
    // A first run at each size warms up what is allocated once per process.
    count(|| job(n));
    let small = count(|| job(n));
    let large = count(|| job(2 * n));
    for (name, a, b) in [
        ("blocks", small.blocks, large.blocks),
        ("bytes", small.bytes, large.bytes),
        ("peak bytes", small.peak, large.peak),
    ] {
        let ratio = b as f64 / a.max(1) as f64;
        assert!(
            ratio <= 2.3,
            "{what}: {name} grew {ratio:.2}× from size {n} to {} ({a} → {b}): not linear",
            2 * n
        );
    }
}

/// The base level's topology around a vertex of valence 10 000 and 20 000.
#[test]
fn topology_is_linear_in_the_valence() {
    for quads in [false, true] {
        assert_linear("Topology::from_mesh", 10_000, |n| {
            let mesh = fan(n, quads);
            Topology::from_mesh(&mesh, &Options::default()).expect("topology");
        });
    }
}

/// One level of refinement around a vertex of valence 10 000 and 20 000.
#[test]
fn refinement_is_linear_in_the_valence() {
    assert_linear("subdivide", 10_000, |n| {
        let opts = SubdivideOptions {
            levels: 1,
            ..SubdivideOptions::default()
        };
        subdivide(&fan(n, false), &opts).expect("refinement");
    });
}

/// The limit surface around a vertex of valence 400 and 800 (above `HIGH_VALENCE`), built and evaluated at the
/// corners and the centre of every face (the grid of `subsurf limit --grid 2` plus the
/// centres), and its tessellation at rate 2 (`subsurf tessellate --rate 2`).
#[test]
fn limit_surface_is_linear_in_the_valence() {
    for quads in [false, true] {
        assert_linear("LimitSurface", 400, |n| {
            let mesh = fan(n, quads);
            let surface = LimitSurface::new(&mesh, Options::default()).expect("surface");
            let mut points = Vec::new();
            for (face, corners) in mesh.faces().enumerate() {
                // A quad is one sub-face; an n-gon has n (see `SurfacePoint`).
                let subfaces = if corners.len() == 4 { 1 } else { corners.len() };
                for subface in 0..subfaces as u32 {
                    for (u, v) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.5, 0.5)] {
                        points.push(SurfacePoint {
                            face: face as u32,
                            subface,
                            u,
                            v,
                        });
                    }
                }
            }
            for r in surface.eval_many(&points) {
                r.expect("evaluation");
            }
        });
        assert_linear("tessellate", 400, |n| {
            tessellate_mesh(&fan(n, quads), &Options::default(), 2, false).expect("tessellation");
        });
    }
}

/// The memory estimates that `--max-memory` is checked against bound the peak of live bytes
/// that refinement and re-posing (building the plan, then one pose) allocate, around
/// vertices of valence 4000 (triangles, quads, at a boundary), levels 1 and 2, with and
/// without limit positions.
#[test]
fn memory_estimates_bound_the_peak() {
    use subsurf::Reposer;
    let half_fan = {
        let n = 4000;
        let mut p = vec![[0.0, 0.0, 0.0]];
        for i in 0..=n {
            let a = i as f64 / n as f64 * std::f64::consts::PI;
            p.push([a.cos(), a.sin(), 0.1 * (3.0 * a).sin()]);
        }
        let faces: Vec<[u32; 3]> = (0..n as u32).map(|i| [0, i + 1, i + 2]).collect();
        PolyMesh::from_faces(p, &faces).expect("valid half fan")
    };
    for (name, mesh) in [
        ("triangle fan", fan(4000, false)),
        ("quad fan", fan(4000, true)),
        ("fan at a boundary", half_fan),
    ] {
        for levels in [1, 2] {
            for limit in [false, true] {
                let opts = SubdivideOptions {
                    levels,
                    limit,
                    ..SubdivideOptions::default()
                };
                let what = format!("{name}, level {levels}, limit {limit}");
                let used = count(|| {
                    subdivide(&mesh, &opts).expect("refinement");
                });
                let estimate = subsurf::estimate_memory(&mesh, &opts);
                assert!(
                    used.peak as u64 <= estimate,
                    "subdivide of the {what}: peak {} bytes, estimate {estimate}",
                    used.peak
                );
                let used = count(|| {
                    let mut reposer = Reposer::new(&mesh, &opts).expect("plan");
                    reposer.pose(mesh.positions()).expect("pose");
                });
                let estimate = Reposer::estimate_memory(&mesh, &opts);
                assert!(
                    used.peak as u64 <= estimate,
                    "re-posing the {what}: peak {} bytes, estimate {estimate}",
                    used.peak
                );
            }
        }
    }
}
