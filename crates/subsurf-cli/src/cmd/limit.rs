//! `subsurf limit`: sample the exact limit surface on an N×N grid per quad face, in the
//! column layout and order of `osd-oracle limit`.

use anyhow::{Context, Result};
use subsurf::limit::{LimitSurface, Order, SurfacePoint};
use subsurf::mesh::Options;

use crate::input::Input;
use crate::output::Output;
use crate::LimitArgs;

/// Bytes per output row held until the file is written (measured: 214 at 6 million rows).
const BYTES_PER_ROW: u64 = 256;

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
    let out = Output::new(&args.output);
    out.check()?;
    let input = Input::read_surface(&args.input)?;
    if !args.quiet {
        for w in input.unsupported_tag_warnings() {
            eprintln!("warning: {w}");
        }
    }
    let options = args
        .scheme
        .over(input.obj.options)
        .resolve(Options::default());
    // Memory: the surface, then every row as text until all are written.
    let surface = crate::memory::SurfaceGuard {
        name: &input.name,
        what: format!("sampling a {0}×{0} grid per face", args.grid),
        max: args.max_memory,
        hint: "use a smaller --grid",
        quads_only: true,
    }
    .limit_surface(
        &input.obj.mesh,
        options,
        args.grid,
        crate::memory::grid_samples(&input.obj.mesh, args.grid).saturating_mul(BYTES_PER_ROW),
    )?;
    let n = args.grid as usize;
    // One face's rows at a time, in parallel over faces, written in face order: the face's
    // points evaluated together (`eval_many_into`, which computes each tree node's points
    // once and a patch's four points at a time), position and first derivatives only.
    let faces = grid_faces(&surface);
    let rows: Vec<Result<String>> = {
        use rayon::prelude::*;
        faces
            .par_iter()
            .map_init(
                || (Vec::new(), Vec::new()),
                |(points, results), &f| {
                    points.clear();
                    points.extend(grid(f, n));
                    surface.eval_many_into(points, Order::First, results);
                    let mut s = String::new();
                    for (p, d) in points.iter().zip(results.iter()) {
                        let d = d
                            .as_ref()
                            .map_err(Clone::clone)
                            .with_context(|| format!("{}: face {f}", input.name))?;
                        use std::fmt::Write as _;
                        let _ = write!(s, "{f} {} {}", p.u, p.v);
                        for x in d.p.iter().chain(&d.du).chain(&d.dv) {
                            let _ = write!(s, " {x}");
                        }
                        s.push('\n');
                    }
                    Ok(s)
                },
            )
            .collect()
    };
    out.write(|w| {
        for r in &rows {
            match r {
                Ok(s) => w.write_all(s.as_bytes())?,
                Err(e) => return Err(std::io::Error::other(format!("{e:#}"))),
            }
        }
        Ok(())
    })
}
