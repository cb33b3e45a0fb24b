//! Criterion benches of re-posing: applying a precomputed [`RefinePlan`] to the base
//! positions against a full [`subdivide`] of the same mesh to the same level
//! (`catmark_bishop`, level 5, one thread).
//!
//! Run with `cargo bench -p subsurf --bench replay`. Throughput is in output vertices per
//! second. Building the plan is benched too (`replay_l5/build`), since it is paid once per
//! topology. `replay_mixed_l5` does the same for mixed subdivision against
//! [`subdivide`] with `Scheme::Adjustable`: the shape-adjustable scheme with `c = 0.3` on every level, on the
//! first level only, and on the first four, then Catmull-Clark. `replay_nurss_l5` does it
//! for non-uniform subdivision against [`subdivide`] with `Scheme::Nurss`: the bishop with its creases
//! infinitely sharp and an interval of 1–3 on every edge; `replay_nurss_limit_l4` poses
//! its limit positions (`Reposer::new` with `Scheme::Nurss` and `limit`) against `subdivide` with
//! the limit, at level 4.

use std::path::PathBuf;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use subsurf::io::read_obj;
use subsurf::mesh::{EdgeInterval, Options, PolyMesh, SHARPNESS_INFINITE};
use subsurf::refine::{PlanScratch, RefinePlan};
use subsurf::scheme::Adjustable;
use subsurf::{subdivide, Mixed, Reposer, Scheme, SubdivideOptions};

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
        options: scheme,
        ..SubdivideOptions::default()
    };
    (pool, mesh, scheme, opts)
}

/// The group `name`: applying the plan that `build` makes to the positions of `mesh`
/// (`apply`), a full refinement by `full` (`subdivide`), and `build` itself (`build`), in
/// `pool`.
fn apply_full_build<T: Send, P: std::fmt::Debug + Send>(
    c: &mut Criterion,
    pool: &rayon::ThreadPool,
    name: &str,
    mesh: &PolyMesh,
    build: impl Fn() -> Result<RefinePlan, P> + Sync,
    full: impl Fn() -> T + Sync,
) {
    let plan = pool.install(&build).expect("plan failed");
    let mut group = c.benchmark_group(name);
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
        b.iter(|| pool.install(&full))
    });
    group.bench_function(format!("build/{SHAPE}"), |b| {
        b.iter(|| pool.install(&build).expect("plan failed"))
    });
    group.finish();
}

fn replay_level5(c: &mut Criterion) {
    let (pool, mesh, scheme, opts) = setup();
    apply_full_build(
        c,
        &pool,
        "replay_l5",
        &mesh,
        || RefinePlan::new(&mesh, Scheme::CatmullClark, scheme, LEVELS),
        || subdivide(&mesh, &opts).expect("subdivide failed"),
    );
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
            .install(|| RefinePlan::new(&mesh, Scheme::Adjustable(mixed), scheme, LEVELS))
            .expect("plan failed");
        group.throughput(Throughput::Elements(plan.num_vertices() as u64));
        let mut out = Vec::new();
        let mut scratch = PlanScratch::default();
        group.bench_function(format!("apply/{what}/{SHAPE}"), |b| {
            b.iter(|| pool.install(|| plan.apply_into(mesh.positions(), &mut out, &mut scratch)))
        });
        group.bench_function(format!("subdivide/{what}/{SHAPE}"), |b| {
            b.iter(|| {
                pool.install(|| {
                    subdivide(
                        &mesh,
                        &SubdivideOptions {
                            scheme: Scheme::Adjustable(mixed),
                            ..opts.clone()
                        },
                    )
                })
                .expect("subdivide failed")
            })
        });
    }
    group.finish();
}

/// `catmark_bishop` for non-uniform subdivision: its creases infinitely sharp (NURSS has
/// no semi-sharp rule) and a knot interval on every edge, 1, 1.5, 2, 2.5 or 3 by the
/// edge's ends.
fn nurss_bishop(mesh: &PolyMesh) -> PolyMesh {
    let mut m = mesh.clone();
    for c in &mut m.tags.creases {
        c.sharpness = SHARPNESS_INFINITE;
    }
    let faces: Vec<Vec<u32>> = m.faces().map(<[u32]>::to_vec).collect();
    for f in &faces {
        for i in 0..f.len() {
            let (v0, v1) = (f[i], f[(i + 1) % f.len()]);
            let interval = 1.0 + 0.5 * ((7 * v0.min(v1) + 13 * v0.max(v1)) % 5) as f64;
            m.knots.intervals.push(EdgeInterval { v0, v1, interval });
        }
    }
    m
}

fn replay_nurss_level5(c: &mut Criterion) {
    let (pool, mesh, scheme, _) = setup();
    let mesh = nurss_bishop(&mesh);
    let opts = SubdivideOptions {
        scheme: Scheme::Nurss,
        levels: LEVELS,
        options: scheme,
        ..Default::default()
    };
    apply_full_build(
        c,
        &pool,
        "replay_nurss_l5",
        &mesh,
        || RefinePlan::new(&mesh, Scheme::Nurss, scheme, LEVELS),
        || subdivide(&mesh, &opts).expect("subdivide failed"),
    );
}

fn replay_nurss_limit_level4(c: &mut Criterion) {
    const LIMIT_LEVELS: u32 = 4;
    let (pool, mesh, scheme, _) = setup();
    let mesh = nurss_bishop(&mesh);
    let nurss_opts = SubdivideOptions {
        scheme: Scheme::Nurss,
        levels: LIMIT_LEVELS,
        options: scheme,
        limit: true,
        ..Default::default()
    };
    let build = || Reposer::new(&mesh, &nurss_opts).expect("reposer failed");
    let mut reposer = pool.install(build);
    let mut group = c.benchmark_group("replay_nurss_limit_l4");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5))
        .throughput(Throughput::Elements(reposer.mesh().num_vertices() as u64));
    group.bench_function(format!("pose/{SHAPE}"), |b| {
        b.iter(|| {
            pool.install(|| {
                reposer
                    .pose(mesh.positions())
                    .map(|_| ())
                    .expect("pose failed")
            })
        })
    });
    group.bench_function(format!("subdivide/{SHAPE}"), |b| {
        b.iter(|| pool.install(|| subdivide(&mesh, &nurss_opts).expect("subdivide failed")))
    });
    group.bench_function(format!("build/{SHAPE}"), |b| b.iter(|| pool.install(build)));
    group.finish();
}

criterion_group!(
    benches,
    replay_level5,
    replay_mixed_level5,
    replay_nurss_level5,
    replay_nurss_limit_level4
);
criterion_main!(benches);
