//! Criterion benches of re-posing: applying a precomputed [`RefinePlan`] to the base
//! positions against a full [`subdivide`] of the same mesh to the same level
//! (`catmark_bishop`, level 5, one thread).
//!
//! Run with `cargo bench -p subsurf --bench replay`. Throughput is in output vertices per
//! second. Building the plan is benched too (`replay_l5/build`), since it is paid once per
//! topology. `replay_mixed_l5` does the same for mixed subdivision against
//! [`subdivide_mixed`]: the shape-adjustable scheme with `c = 0.3` on every level, on the
//! first level only, and on the first four, then Catmull-Clark.

use std::path::PathBuf;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use subsurf::io::obj::read_obj;
use subsurf::mesh::{Options, PolyMesh};
use subsurf::refine::{PlanScratch, RefinePlan};
use subsurf::scheme::adjustable::Adjustable;
use subsurf::{subdivide, subdivide_mixed, Mixed, SubdivideOptions};

/// The allocator of the `subsurf` binary, so that the full refinement compared with is the
/// one `subsurf bench` measures (see the crate docs, "Speed: choose the global allocator").
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

const SHAPE: &str = "catmark_bishop";
const LEVELS: u32 = 5;

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

/// A one-thread pool, [`SHAPE`] with its scheme options, and the options of its
/// refinement to [`LEVELS`].
fn setup() -> (rayon::ThreadPool, PolyMesh, Options, SubdivideOptions) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("cannot start a rayon thread pool");
    let (mesh, scheme) = load(SHAPE);
    let opts = SubdivideOptions {
        levels: LEVELS,
        scheme,
        ..SubdivideOptions::default()
    };
    (pool, mesh, scheme, opts)
}

fn replay_level5(c: &mut Criterion) {
    let (pool, mesh, scheme, opts) = setup();
    let plan = pool
        .install(|| RefinePlan::new(&mesh, scheme, LEVELS))
        .expect("plan failed");

    let mut group = c.benchmark_group("replay_l5");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5))
        .throughput(Throughput::Elements(plan.num_vertices() as u64));

    let mut out = Vec::new();
    let mut scratch = PlanScratch::default();
    group.bench_function(format!("apply/{SHAPE}"), |b| {
        b.iter(|| pool.install(|| plan.apply_into(mesh.positions(), &mut out, &mut scratch)))
    });
    group.bench_function(format!("subdivide/{SHAPE}"), |b| {
        b.iter(|| {
            pool.install(|| subdivide(&mesh, &opts))
                .expect("subdivide failed")
        })
    });
    group.bench_function(format!("build/{SHAPE}"), |b| {
        b.iter(|| {
            pool.install(|| RefinePlan::new(&mesh, scheme, LEVELS))
                .expect("plan failed")
        })
    });
    group.finish();
}

fn replay_mixed_level5(c: &mut Criterion) {
    let (pool, mesh, scheme, opts) = setup();
    let adjustable = Adjustable::new(0.3).expect("c in [0, 1]");
    let mut group = c.benchmark_group("replay_mixed_l5");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    for (what, steps) in [
        ("every_level", u32::MAX),
        ("first_level", 1),
        ("four_levels", 4),
    ] {
        let mixed = Mixed {
            scheme: adjustable,
            steps,
        };
        let plan = pool
            .install(|| RefinePlan::new_mixed(&mesh, scheme, LEVELS, mixed))
            .expect("plan failed");
        group.throughput(Throughput::Elements(plan.num_vertices() as u64));
        let mut out = Vec::new();
        let mut scratch = PlanScratch::default();
        group.bench_function(format!("apply/{what}/{SHAPE}"), |b| {
            b.iter(|| pool.install(|| plan.apply_into(mesh.positions(), &mut out, &mut scratch)))
        });
        group.bench_function(format!("subdivide/{what}/{SHAPE}"), |b| {
            b.iter(|| {
                pool.install(|| subdivide_mixed(&mesh, &opts, mixed))
                    .expect("subdivide failed")
            })
        });
    }
    group.finish();
}

criterion_group!(benches, replay_level5, replay_mixed_level5);
criterion_main!(benches);
