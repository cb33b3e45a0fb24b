//! `subsurf fill`: fill an N-sided hole bounded by cubic B-spline curves or patches with a
//! corner-interpolating non-uniform Catmull-Clark (NURSS) surface ([Jiang et al.], Algorithm 1).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use subsurf::blend::{FillJob, FillJobOptions, FillOptions};
use subsurf::io::read_geometry;

use super::blend::{input_name, write, MEMORY_HINT};
use crate::output::Output;

/// Examples shown by `subsurf fill --help`.
pub const FILL_EXAMPLES: &str = "\
Input: 3 to 8 cubic B-spline or NURBS curves, or bicubic patches (their first-row boundary
u = u_3 is used), as JSON or OBJ free-form (see `subsurf nurbs`), meeting end to end around
the hole (in any direction). The fill interpolates every boundary curve and the corners
(NURBS input is filled in homogeneous coordinates and interpolated exactly; --g1 takes
polynomial patches, or NURBS patches with one weight each). --bulge B moves
the free inner control points along the boundary's normal by B times the hole's radius
(B > 0 convex, B < 0 concave). --g1 (patches only) makes the fill meet every patch with a
continuous normal (the paper's Algorithm 2; neighbouring patches must share the tangent plane
at their common corner). Output: OBJ with the base patches (`patch_1`, ...) when
patches were given, the boundary curves as polylines (`curve_1`, ...) and the fill (`fill`).

Examples:
  subsurf fill examples/patches/hole3.json -o hole3.obj
  subsurf fill examples/patches/hole5.json -o hole5.obj --bulge 0.4 --levels 5
  subsurf fill examples/patches/hole3.json -o hole3-g1.obj --g1";

/// Arguments of `subsurf fill`.
#[derive(Debug, Args)]
pub struct FillArgs {
    /// Input file: cubic curves or bicubic patches as JSON documents or OBJ free-form
    /// elements ('-' reads standard input).
    #[arg(value_name = "PATCHES")]
    pub input: PathBuf,
    /// Output OBJ file ('-' for standard output).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Skirt-removal refinement steps.
    #[arg(long, value_name = "L", default_value_t = 5, value_parser = clap::value_parser!(u32).range(0..=8))]
    pub levels: u32,
    /// Convex (> 0) or concave (< 0) fill: moves the free inner points along the normal.
    #[arg(
        long,
        value_name = "B",
        default_value_t = 0.0,
        allow_negative_numbers = true,
        value_parser = parse_bulge
    )]
    pub bulge: f64,
    /// Meet the base patches G1 (continuous normal; needs patches, not curves).
    #[arg(long)]
    pub g1: bool,
    /// Segments per knot span of the tessellated patches and curve polylines.
    #[arg(long, value_name = "N", default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=256))]
    pub samples: u32,
    /// Also write the fill control mesh (OBJ with `t interval` tags) here.
    #[arg(long, value_name = "OUT2")]
    pub control_mesh: Option<PathBuf>,
    /// Refuse to start when the estimated memory exceeds this (suffixes K, M, G, T: powers
    /// of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = crate::parse_bytes)]
    pub max_memory: Option<u64>,
}

/// Parses `--bulge B`: a finite number.
fn parse_bulge(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(b) if b.is_finite() => Ok(b),
        _ => Err(format!("'{s}' is not a finite number")),
    }
}

/// Runs `subsurf fill`.
pub fn run(args: &FillArgs) -> Result<()> {
    let out = Output::new(&args.output);
    out.check()?;
    let control_out = args.control_mesh.as_deref().map(Output::new);
    if let Some(c) = &control_out {
        c.check()?;
    }
    let name = input_name(&args.input);
    let items = read_geometry(&args.input)?;
    let options = FillJobOptions {
        levels: args.levels,
        samples: args.samples,
        fill: FillOptions {
            bulge: args.bulge,
            ..Default::default()
        },
        g1: args.g1,
    };
    // The control mesh first (no refinement): its size bounds the job's memory.
    let job = FillJob::new(&items, &name, &options)?;
    crate::memory::check(
        &name,
        &format!("filling with {} levels", args.levels),
        job.estimate_memory(),
        args.max_memory,
        MEMORY_HINT,
    )?;
    write(&job.run()?, &out, control_out)
}
