//! `subsurf bench`: time uniform refinement (topology + positions, no file output) the way
//! `osd-oracle bench` times OpenSubdiv, so the two can be compared on any mesh.

use std::time::Instant;

use anyhow::{Context, Result};
use subsurf::mesh::Options;
use subsurf::{subdivide, SubdivideOptions};

use crate::input::Input;
use crate::BenchArgs;

/// Runs `subsurf bench`.
pub fn run(args: &BenchArgs) -> Result<()> {
    let input = Input::read(&args.input)?;
    let opts = SubdivideOptions {
        levels: args.levels,
        scheme: args
            .scheme
            .over(input.obj.options)
            .resolve(Options::default()),
        ..SubdivideOptions::default()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads)
        .build()
        .context("cannot start the thread pool")?;
    let reps = args.reps.max(1);
    let mut times = Vec::with_capacity(reps);
    let mut verts = 0;
    for _ in 0..reps {
        let t0 = Instant::now();
        let sub = pool
            .install(|| subdivide(&input.obj.mesh, &opts))
            .with_context(|| input.name.clone())?;
        times.push(t0.elapsed().as_secs_f64());
        verts = sub.mesh.num_vertices();
    }
    times.sort_by(f64::total_cmp);
    println!(
        "subsurf refine level={} verts={} threads={} median_s={:.6} min_s={:.6}",
        args.levels,
        verts,
        pool.current_num_threads(),
        times[times.len() / 2],
        times[0]
    );
    Ok(())
}
