//! Criterion benches of uniform Catmull-Clark refinement (topology + positions, the same
//! work `subsurf bench` and `osd-oracle bench` time) on two OpenSubdiv test shapes.
//!
//! Run with `cargo bench -p subsurf` (or `cargo bench -p subsurf -- pawn` to filter).
//! The meshes are read at bench time from `tests/shapes/osd/`, with the scheme options of
//! their OBJ tags. See `BENCHMARKS.md` at the repository root for a comparison with
//! OpenSubdiv itself.

use std::path::PathBuf;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use subsurf::io::obj::read_obj;
use subsurf::mesh::{Options, PolyMesh};
use subsurf::{subdivide, SubdivideOptions};

/// As in the `subsurf` binary: transparent huge pages for large buffers, so that the benches
/// measure what `subsurf bench` measures (see `subsurf::alloc`).
#[global_allocator]
static GLOBAL: subsurf::alloc::HugePageAlloc = subsurf::alloc::HugePageAlloc;

/// The shapes benched, from `crates/subsurf/tests/shapes/osd/`.
const SHAPES: [&str; 2] = ["catmark_bishop", "catmark_pawn"];

/// Reads `tests/shapes/osd/<name>.obj` and the scheme options of its tags.
fn load(name: &str) -> (PolyMesh, Options) {
    let path: PathBuf = [
        env!("CARGO_MANIFEST_DIR"),
        "tests",
        "shapes",
        "osd",
        &format!("{name}.obj"),
    ]
    .iter()
    .collect();
    let obj = read_obj(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let options = obj.options.resolve(Options::default());
    (obj.mesh, options)
}

/// A rayon pool with `n` workers; refinement run inside it uses at most `n` threads.
fn pool(n: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .expect("cannot start a rayon thread pool")
}

/// Benches `subdivide(mesh, opts)` inside `pool`, under `group/<id>/<shape>`, with the
/// output vertex count as throughput (elements/s = output vertices per second).
fn bench_one(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    id: &str,
    shape: &str,
    mesh: &PolyMesh,
    opts: &SubdivideOptions,
    pool: &rayon::ThreadPool,
) {
    let verts = pool
        .install(|| subdivide(mesh, opts))
        .expect("subdivide failed")
        .mesh
        .num_vertices();
    group.throughput(Throughput::Elements(verts as u64));
    group.bench_with_input(BenchmarkId::new(id, shape), mesh, |b, mesh| {
        b.iter(|| {
            pool.install(|| subdivide(mesh, opts))
                .expect("subdivide failed")
        })
    });
}

/// Uniform refinement to level 5 with one and with two threads.
fn refine_level5(c: &mut Criterion) {
    let mut group = c.benchmark_group("refine_l5");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    let pools = [(1, pool(1)), (2, pool(2))];
    for shape in SHAPES {
        let (mesh, scheme) = load(shape);
        let opts = SubdivideOptions {
            levels: 5,
            scheme,
            ..SubdivideOptions::default()
        };
        for (n, pool) in &pools {
            bench_one(
                &mut group,
                &format!("threads{n}"),
                shape,
                &mesh,
                &opts,
                pool,
            );
        }
    }
    group.finish();
}

/// Refinement to level 3 followed by limit positions and normals, one thread.
fn limit_level3(c: &mut Criterion) {
    let mut group = c.benchmark_group("limit_l3");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    let pool = pool(1);
    for shape in SHAPES {
        let (mesh, scheme) = load(shape);
        let opts = SubdivideOptions {
            levels: 3,
            scheme,
            limit: true,
            ..SubdivideOptions::default()
        };
        bench_one(&mut group, "threads1", shape, &mesh, &opts, &pool);
    }
    group.finish();
}

criterion_group!(benches, refine_level5, limit_level3);
criterion_main!(benches);
