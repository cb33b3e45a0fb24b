//! `subsurf limit`: sample the exact limit surface on an N×N grid per quad face, in the
//! column layout and order of `osd-oracle limit`.

use anyhow::{Context, Result};
use subsurf::limit::{LimitSurface, Order, SurfacePoint};
use subsurf::mesh::Options;

use crate::input::Input;
use crate::output::Output;
use crate::LimitArgs;

/// Bytes per output row held until its block is written (measured: 214 at 6 million rows).
const BYTES_PER_ROW: u64 = 256;

/// Bytes of the shortest output row (`0 0 0 0 0 0 0 0 0 0 0 0`): a file of fewer bytes per
/// row than this cannot be, so a job whose rows times this exceed the free space is refused.
const MIN_BYTES_PER_ROW: u64 = 24;

/// Grid points per block of faces evaluated together (in parallel) and then written: only
/// one block's rows are held as text (about 1 MiB), where holding all of them made
/// `catmark_pawn` with `--grid 5` peak at 9.9 MiB (`osd-oracle limit`: 6.6).
const POINTS_PER_BLOCK: usize = 4096;

/// The faces a grid is sampled on, in order: every quad with a surface (not a hole), as
/// `osd-oracle limit` and `benchlimit` sample.
pub fn grid_faces(surface: &LimitSurface) -> Vec<u32> {
    (0..surface.num_faces())
        .filter(|&f| surface.num_subfaces(f) == 1 && surface.has_surface(f))
        .map(|f| f as u32)
        .collect()
}

/// The `n`×`n` grid on quad `face`, in `osd-oracle limit`'s order: `u = i / (n − 1)` outer,
/// `v = j / (n − 1)` inner (the centre for `n = 1`).
pub fn grid(face: u32, n: usize) -> impl Iterator<Item = SurfacePoint> {
    let param = move |i: usize| {
        if n == 1 {
            0.5
        } else {
            i as f64 / (n - 1) as f64
        }
    };
    (0..n * n).map(move |k| SurfacePoint {
        face,
        subface: 0,
        u: param(k / n),
        v: param(k % n),
    })
}

/// Runs `subsurf limit`.
pub fn run(args: &LimitArgs) -> Result<()> {
    // Every block is evaluated in parallel: this thread is the first of rayon's global
    // pool, one thread fewer than a pool beside it (`catmark_pawn --grid 5` 7.0 -> 6.4
    // MiB). Commands that may not use the pool at all leave it to start on first use.
    // If it cannot be built so, rayon builds its default one then.
    let _ = rayon::ThreadPoolBuilder::new()
        .use_current_thread()
        .build_global();
    let out = Output::new(&args.output);
    out.check()?;
    let input = Input::read_surface(&args.input, args.max_memory)?;
    if !args.quiet {
        for w in input.warnings() {
            eprintln!("warning: {w}");
        }
    }
    let options = args
        .scheme
        .over(input.obj.options)
        .resolve(Options::default());
    let n = args.grid as usize;
    let faces_per_block = (POINTS_PER_BLOCK / (n * n)).max(1);
    let what = format!("sampling a {0}×{0} grid per face", args.grid);
    let hint = "use a smaller --grid";
    // The rows are streamed: neither memory nor the whole output bounds them, the disk does.
    let samples = crate::memory::grid_samples(&input.obj.mesh, args.grid);
    out.check_space(
        &input.name,
        &what,
        samples.saturating_mul(MIN_BYTES_PER_ROW),
        hint,
    )?;
    // Memory: the surface, then one block's rows as text.
    let held = samples
        .min((faces_per_block * n * n) as u64)
        .saturating_mul(BYTES_PER_ROW);
    let surface = crate::memory::SurfaceGuard {
        name: &input.name,
        what,
        max: args.max_memory,
        hint,
        quads_only: true,
    }
    .limit_surface(&input.obj.mesh, options, args.grid, held)?;
    // One face's rows at a time, in parallel over the faces of a block, written in face
    // order: the face's points evaluated together (`eval_many_into`, which computes each
    // tree node's points once and a patch's four points at a time), position and first
    // derivatives only. An error stops the output at its block: a file is then not
    // written at all, standard output has the blocks before it.
    let faces = grid_faces(&surface);
    let face_rows = |points: &mut Vec<SurfacePoint>, results: &mut Vec<_>, f: u32| {
        points.clear();
        points.extend(grid(f, n));
        surface.eval_many_into(points, Order::First, results);
        let mut s = Vec::new();
        for (p, d) in points.iter().zip(results.iter()) {
            let d = d
                .as_ref()
                .map_err(Clone::clone)
                .with_context(|| format!("{}: face {f}", input.name))?;
            use std::io::Write as _;
            let _ = write!(s, "{f}");
            for x in [p.u, p.v].iter().chain(&d.p).chain(&d.du).chain(&d.dv) {
                s.push(b' ');
                subsurf::io::push_decimal(&mut s, *x);
            }
            s.push(b'\n');
        }
        Ok::<_, anyhow::Error>(s)
    };
    out.write(|w| {
        use rayon::prelude::*;
        let mut rows = Vec::new();
        for block in faces.chunks(faces_per_block) {
            block
                .par_iter()
                .map_init(
                    || (Vec::new(), Vec::new()),
                    |(points, results), &f| face_rows(points, results, f),
                )
                .collect_into_vec(&mut rows);
            for r in &rows {
                match r {
                    Ok(s) => w.write_all(s)?,
                    Err(e) => return Err(std::io::Error::other(format!("{e:#}"))),
                }
            }
        }
        Ok(())
    })
}
