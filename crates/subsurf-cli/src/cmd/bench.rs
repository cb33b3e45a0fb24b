//! `subsurf bench`: time uniform refinement (topology + positions, and the face-varying
//! channels such as texture coordinates, no file output) the way `osd-oracle bench` times
//! OpenSubdiv, so the two can be compared on any mesh; a mesh with face-varying channels is
//! timed once more without them, to give their share. With `--replay`, time re-posing
//! through a precomputed [`RefinePlan`] instead.

use std::time::Instant;

use anyhow::{Context, Result};
use subsurf::limit::{
    Derivatives, EvalError, LimitSurface, LoopSurface, Order, Surface, SurfacePoint,
};
use subsurf::mesh::{Options, PolyMesh};
use subsurf::refine::{PlanScratch, RefinePlan};
use subsurf::{subdivide, Scheme, SubdivideOptions};

use super::adjustable::usage_error;
use crate::input::Input;
use crate::{BenchArgs, SchemeKind};

/// Runs `subsurf bench` on `threads` worker threads (0: one per core).
pub fn run(args: &BenchArgs, threads: usize) -> Result<()> {
    let scheme = match args.scheme_kind {
        SchemeKind::CatmullClark => Scheme::CatmullClark,
        SchemeKind::Loop => Scheme::Loop,
        SchemeKind::Bilinear => Scheme::Bilinear,
        SchemeKind::Adjustable | SchemeKind::Nurss => usage_error(
            "bench times OpenSubdiv's schemes: --scheme catmull-clark, loop or bilinear",
        ),
    };
    if args.limit_grid.is_some() && scheme == Scheme::Bilinear {
        usage_error("--limit-grid times the Catmull-Clark and Loop limit surfaces");
    }
    let input = Input::read_surface(&args.input, args.max_memory)?;
    if !args.quiet {
        for w in input.warnings() {
            crate::output::eprint_line(&format!("warning: {w}"));
        }
        if subsurf::nonuniform::has_knots(&input.obj.mesh) {
            crate::output::eprint_line(&format!(
                "note: {} has knot interval or weight tags: bench times Catmull-Clark, as \
                 osd-oracle does, which ignores them",
                input.name
            ));
        }
    }
    let opts = SubdivideOptions {
        levels: args.levels,
        scheme,
        options: args
            .scheme
            .over(input.obj.options)
            .resolve(Options::default()),
        ..SubdivideOptions::default()
    };
    // This thread is the pool's first: one thread fewer (a small job's peak memory is
    // 0.2-0.5 MiB lower), and no hand-over to a worker before the repetitions.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .use_current_thread()
        .build()
        .context("cannot start the thread pool")?;
    let reps = args.reps as usize;
    let mesh = &input.obj.mesh;
    if let Some(n) = args.limit_grid {
        let name = input.name.clone();
        let guard = crate::memory::SurfaceGuard {
            name: &name,
            what: format!("evaluating a {n}×{n} grid per face"),
            max: args.max_memory,
            hint: "use a smaller --limit-grid",
            quads_only: true,
        };
        // Besides the surface, each thread's block of points and results.
        let blocks = (u64::from(n) * u64::from(n))
            .saturating_mul(POINT_BYTES * FACES_PER_BLOCK as u64)
            .saturating_mul(pool.current_num_threads() as u64);
        if scheme == Scheme::Loop {
            return bench_limit(input, opts.options, n, reps, &pool, |mesh, options| {
                LoopSurface::new(&mesh, options).with_context(|| name.clone())
            });
        }
        return bench_limit(input, opts.options, n, reps, &pool, |mesh, options| {
            guard.limit_surface(mesh, options, n, blocks)
        });
    }
    let (what, estimate) = if args.replay {
        (
            format!("building a re-posing plan to level {}", args.levels),
            RefinePlan::estimate_memory(mesh, scheme, args.levels),
        )
    } else {
        (
            format!("refining to level {}", args.levels),
            subsurf::estimate_memory(mesh, &opts),
        )
    };
    let hint = "use a lower level";
    crate::memory::check(&input.name, &what, estimate, args.max_memory, hint)?;
    crate::memory::for_refinement(estimate);
    if args.replay {
        return bench_replay(&input, &opts, reps, &pool);
    }
    bench_refine(&input, &opts, reps, &pool)
}

/// Times `reps` refinements of `input` with `opts` and prints their median and minimum;
/// with face-varying channels, also the same refinement without them and their share.
fn bench_refine(
    input: &Input,
    opts: &SubdivideOptions,
    reps: usize,
    pool: &rayon::ThreadPool,
) -> Result<()> {
    let mesh = &input.obj.mesh;
    let mut verts = 0;
    let times = time_reps(pool, reps, || {
        let sub = subdivide(mesh, opts).with_context(|| input.name.clone())?;
        verts = sub.mesh.num_vertices();
        Ok(sub)
    })?;
    let median = times[times.len() / 2];
    let mut line = format!(
        "subsurf refine level={} verts={} threads={} median_s={median:.6} min_s={:.6}",
        opts.levels,
        verts,
        pool.current_num_threads(),
        times[0]
    );
    if !mesh.face_varying.is_empty() {
        // The face-varying channels' share: the same refinement without them.
        let mut plain = mesh.clone();
        plain.face_varying.clear();
        let vertices = time_reps(pool, reps, || {
            subdivide(&plain, opts).with_context(|| input.name.clone())
        })?;
        let vertices = vertices[vertices.len() / 2];
        let pct = 100.0 * (median / vertices - 1.0);
        line.push_str(&format!(
            " channels={} vertices_s={vertices:.6} fvar_pct={pct:.0}",
            mesh.face_varying.len()
        ));
    }
    crate::output::print(&format!("{line}\n"))?;
    Ok(())
}

/// Builds a [`RefinePlan`] once (timed separately) and times applying it to the base
/// positions `reps` times, into buffers kept from one repetition to the next (as an
/// animation would re-pose frame after frame), allocated once the memory the build freed
/// is returned ([`crate::memory::return_freed_memory`]).
fn bench_replay(
    input: &Input,
    opts: &SubdivideOptions,
    reps: usize,
    pool: &rayon::ThreadPool,
) -> Result<()> {
    let mesh = &input.obj.mesh;
    let levels = opts.levels;
    let t0 = Instant::now();
    let plan = pool
        .install(|| RefinePlan::new(mesh, opts.scheme, opts.options, levels))
        .with_context(|| input.name.clone())?;
    let build = t0.elapsed().as_secs_f64();
    // The build's temporaries go back to the system before the buffers are allocated.
    crate::memory::return_freed_memory();
    let mut out = Vec::new();
    let mut scratch = PlanScratch::default();
    let times = time_reps(pool, reps, || {
        plan.apply_into(mesh.positions(), &mut out, &mut scratch);
        Ok(())
    })?;
    crate::output::print(&format!("{}\n", format_args!(
        "subsurf replay level={levels} verts={} threads={} median_s={:.6} min_s={:.6} (plan built in {build:.6}s) weights={} patches={} plan_mib={}",
        out.len(),
        pool.current_num_threads(),
        times[times.len() / 2],
        times[0],
        plan.num_weights(),
        plan.num_patches(),
        plan.memory_bytes() >> 20,
    )))?;
    Ok(())
}

/// The points of a block of faces and their results.
type Block = (Vec<SurfacePoint>, Vec<Result<Derivatives, EvalError>>);

thread_local! {
    /// Each pool thread's [`Block`], kept from one repetition to the next (as an
    /// animation evaluating frame after frame would keep it), so that a repetition times
    /// the evaluation, not allocating and filling the block anew.
    static BLOCK: std::cell::RefCell<Block> = const { std::cell::RefCell::new((Vec::new(), Vec::new())) };
}

/// Times evaluating an `n`×`n` grid on every quad face (a triangular grid of `n` points a
/// side on every triangle of a Loop surface), as `osd-oracle benchlimit` times OpenSubdiv's
/// `Bfr`: the surface of the quads is built once (as `Bfr`'s factory and its
/// cache of irregular configurations are; other faces are not evaluated, so not built), and each repetition re-poses it and evaluates every
/// point's position and first derivatives
/// ([`LimitSurface::update_positions`](subsurf::limit::LimitSurface::update_positions),
/// [`LimitSurface::eval_many_into`](subsurf::limit::LimitSurface::eval_many_into) with
/// [`Order::First`](subsurf::limit::Order::First), as `Bfr::Surface::Evaluate`). The first build
/// plus evaluation (nothing cached) is reported as `cold_s`. A [`LoopSurface`] builds its
/// configurations as its faces are first evaluated, and keeps them.
///
/// Like `benchlimit`, which evaluates point after point and keeps only a running sum, the
/// points are streamed: blocks of [`FACES_PER_BLOCK`] faces are listed and evaluated into
/// buffers each thread keeps, so the job holds no array of all points or results (168 bytes
/// a point). The surface keeps the control points and is re-posed in place, so the mesh is
/// dropped once it is built: the job's memory is the surface's, the list of quads and one
/// block per thread. `build` builds the surface (within the job's memory limit).
fn bench_limit<S: Timed>(
    input: Input,
    options: Options,
    n: u32,
    reps: usize,
    pool: &rayon::ThreadPool,
    build: impl FnOnce(PolyMesh, Options) -> Result<S> + Send,
) -> Result<()> {
    use rayon::prelude::*;
    let Input { name, obj, .. } = input;
    let mesh = obj.mesh;
    let n = n as usize;
    // The sum of the `x` of every point evaluated on `faces` (so that nothing is optimised
    // away).
    let eval_all = |surface: &S, faces: &[u32]| -> f64 {
        faces
            .par_chunks(FACES_PER_BLOCK)
            .map(|block| {
                BLOCK.with_borrow_mut(|(points, out)| {
                    points.clear();
                    points.extend(block.iter().flat_map(|&face| {
                        super::limit::grid(face, n, surface.domain(face as usize))
                    }));
                    // Kept at the largest block's size (the last block is smaller).
                    if out.len() < points.len() {
                        out.resize(points.len(), Ok(Derivatives::default()));
                    }
                    let out = &mut out[..points.len()];
                    // Position and first derivatives, as `Bfr::Surface::Evaluate(uv, P, Du, Dv)`.
                    surface.evaluate_many(points, Order::First, out);
                    out.iter()
                        .filter_map(|r| r.as_ref().ok())
                        .map(|d| d.p[0])
                        .sum::<f64>()
                })
            })
            .sum()
    };
    let t0 = Instant::now();
    let (mut surface, faces, mut sink) = pool.install(|| {
        // The surface takes the mesh's points and faces: it is re-posed in place below.
        let surface = build(mesh, options)?;
        let faces = super::limit::grid_faces(&surface);
        let sink = eval_all(&surface, &faces);
        anyhow::Ok((surface, faces, sink))
    })?;
    let cold = t0.elapsed().as_secs_f64();
    let points = (faces.iter())
        .map(|&f| super::limit::grid(f, n, surface.domain(f as usize)).count() as u64)
        .sum::<u64>();
    // Built: from here on each repetition frees and allocates the same blocks again (the
    // nodes of faces in the shared regions of high-valence vertices, rebuilt when
    // re-posed), which kept memory serves without faulting pages in again, at the same
    // peak (BENCHMARKS.md, "Allocator settings, kept buffers and memory estimates").
    crate::memory::keep_freed_memory(true);
    let times = time_reps(pool, reps, || {
        // Re-posed in place, to the same points (as an animation writing its next frame
        // into the surface would).
        surface.repose().with_context(|| name.clone())?;
        sink += eval_all(&surface, &faces);
        Ok(())
    })?;
    crate::output::print(&format!("{}\n", format_args!(
        "subsurf limit points={} threads={} median_s={:.6} min_s={:.6} cold_s={cold:.6} configurations={} (sink {sink:.3})",
        points,
        pool.current_num_threads(),
        times[times.len() / 2],
        times[0],
        surface.configurations(),
    )))?;
    Ok(())
}

/// A surface `bench --limit-grid` times: built once, then re-posed in place and evaluated
/// again each repetition.
trait Timed: Surface + Send {
    /// Sets the control points again, to the same points (as an animation writing its
    /// next frame into the surface would).
    fn repose(&mut self) -> Result<()>;
    /// The number of distinct irregular neighbourhoods built.
    fn configurations(&self) -> usize;
}

impl Timed for LimitSurface {
    fn repose(&mut self) -> Result<()> {
        Ok(self.update_positions(|_| {})?)
    }

    fn configurations(&self) -> usize {
        self.num_configurations()
    }
}

impl Timed for LoopSurface {
    fn repose(&mut self) -> Result<()> {
        let pos = self.positions().to_vec();
        Ok(self.set_positions(&pos)?)
    }

    fn configurations(&self) -> usize {
        self.num_configurations()
    }
}

/// The seconds of `reps` runs of `rep`, sorted, each result dropped after its time is
/// taken. All run inside `pool`, whose first thread is the caller's: handed over to a
/// worker one by one, the times would include waking it, which takes longer than the whole
/// work of a small mesh's limit grid.
fn time_reps<T>(
    pool: &rayon::ThreadPool,
    reps: usize,
    mut rep: impl FnMut() -> Result<T> + Send,
) -> Result<Vec<f64>> {
    pool.install(|| {
        let mut times = Vec::with_capacity(reps);
        for _ in 0..reps {
            let t0 = Instant::now();
            let result = rep()?;
            times.push(t0.elapsed().as_secs_f64());
            drop(result);
        }
        times.sort_by(f64::total_cmp);
        Ok(times)
    })
}

/// Bytes per point of [`bench_limit`]'s blocks: the point and its result.
const POINT_BYTES: u64 = (std::mem::size_of::<subsurf::limit::SurfacePoint>()
    + std::mem::size_of::<Result<subsurf::limit::Derivatives, subsurf::limit::EvalError>>())
    as u64;

/// Faces per block of [`bench_limit`]'s streamed evaluation: 16 faces of an 8×8 grid are
/// 1,024 points (four of `eval_many_into`'s parallel chunks).
const FACES_PER_BLOCK: usize = 16;
