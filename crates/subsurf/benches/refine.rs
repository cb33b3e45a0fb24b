//! Criterion benches of uniform Catmull-Clark refinement (topology + positions, the same
//! work `subsurf bench` and `osd-oracle bench` time) and of exact limit evaluation (as
//! `subsurf bench --limit-grid 8` and `osd-oracle benchlimit`) on two OpenSubdiv test shapes.
//!
//! Run with `cargo bench -p subsurf` (or `cargo bench -p subsurf -- pawn` to filter).
//! The meshes are read at bench time from `tests/shapes/osd/`, with the scheme options of
//! their OBJ tags. See `BENCHMARKS.md` at the repository root for a comparison with
//! OpenSubdiv itself.

use std::path::PathBuf;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use subsurf::io::read_obj;
use subsurf::mesh::{Options, PolyMesh};
use subsurf::{subdivide, SubdivideOptions};

/// The allocator of the `subsurf` binary, so that the benches measure what `subsurf bench`
/// measures (see the crate docs, "Speed: choose the global allocator").
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

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
            options: scheme,
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
            options: scheme,
            limit: true,
            ..SubdivideOptions::default()
        };
        bench_one(&mut group, "threads1", shape, &mesh, &opts, &pool);
    }
    group.finish();
}

/// Exact limit evaluation, as `osd-oracle benchlimit IN 8` times `Bfr`: an 8×8 grid of
/// positions and first derivatives on every quad face, after `set_positions` on a surface
/// built once (`eval_grid8/threads1|2/<shape>`, throughput in points per second), and the
/// first build plus evaluation (`eval_grid8/cold/<shape>`).
fn limit_grid8(c: &mut Criterion) {
    use subsurf::limit::{LimitSurface, Order, SurfacePoint};
    let mut group = c.benchmark_group("eval_grid8");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    let grid = |s: &LimitSurface| -> Vec<SurfacePoint> {
        (0..s.num_faces())
            .filter(|&f| s.num_subfaces(f) == 1 && s.has_surface(f))
            .flat_map(|f| {
                (0..64).map(move |k| SurfacePoint {
                    face: f as u32,
                    subface: 0,
                    u: (k / 8) as f64 / 7.0,
                    v: (k % 8) as f64 / 7.0,
                })
            })
            .collect()
    };
    for shape in SHAPES {
        let (mesh, scheme) = load(shape);
        let mut surface = LimitSurface::new(&mesh, scheme).expect("surface");
        let points = grid(&surface);
        group.throughput(Throughput::Elements(points.len() as u64));
        let mut out = Vec::new();
        for threads in [1, 2] {
            let pool = pool(threads);
            group.bench_with_input(
                BenchmarkId::new(format!("threads{threads}"), shape),
                &points,
                |b, points| {
                    b.iter(|| {
                        pool.install(|| {
                            surface.set_positions(mesh.positions()).expect("positions");
                            surface.eval_many_into(points, Order::First, &mut out);
                        })
                    })
                },
            );
        }
        let pool = pool(1);
        group.bench_with_input(BenchmarkId::new("cold", shape), &points, |b, points| {
            b.iter(|| {
                pool.install(|| {
                    let s = LimitSurface::new(&mesh, scheme).expect("surface");
                    s.eval_many_into(points, Order::First, &mut out);
                })
            })
        });
    }
    group.finish();
}

criterion_group!(benches, refine_level5, limit_level3, limit_grid8);
criterion_main!(benches);
