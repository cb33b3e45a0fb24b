//! `subsurf blend`: join N bicubic B-spline or NURBS patches C2 with a non-uniform
//! Catmull-Clark (NURSS) blend surface refined with skirt removal ([Jiang et al.] §3.1).

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;
use subsurf::blend::{BlendJob, BlendJobOptions, MethodOutput};
use subsurf::io::read_geometry;
use subsurf::io::write_method_obj;
use subsurf::io::{write_obj, WriteOptions};

use crate::output::Output;

/// Examples shown by `subsurf blend --help`.
pub const BLEND_EXAMPLES: &str = "\
Input: N >= 2 bicubic B-spline or NURBS patches (JSON or OBJ free-form, see `subsurf nurbs`),
at least 4x4 control points, any knots, listed in order around the region to blend (NURBS
patches are blended in homogeneous coordinates: the blend joins them C2 too). Each patch is
blended along its first row (u = u_3); the end (last column) of each patch faces the start
(first column) of the next. Output: OBJ with one group per base patch (`patch_1`, ...) and the
blend surface (`blend`); --control-mesh writes the blend control mesh with its `t interval`
tags (its outer ring is the extension layer).

Examples:
  subsurf blend examples/patches/blend3.json -o blend3.obj
  subsurf blend examples/patches/blend5.json -o blend5.obj --levels 6 \\
      --control-mesh blend5-control.obj";

/// Arguments of `subsurf blend`.
#[derive(Debug, Args)]
pub struct BlendArgs {
    /// Input file: bicubic B-spline patches as JSON documents or OBJ free-form elements
    /// ('-' reads standard input).
    #[arg(value_name = "PATCHES")]
    pub input: PathBuf,
    /// Output OBJ file ('-' for standard output).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Skirt-removal refinement steps.
    #[arg(long, value_name = "L", default_value_t = 5, value_parser = clap::value_parser!(u32).range(0..=8))]
    pub levels: u32,
    /// Segments per knot span of the tessellated base patches.
    #[arg(long, value_name = "N", default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=256))]
    pub samples: u32,
    /// Also write the blend control mesh (OBJ with `t interval` tags) here.
    #[arg(long, value_name = "OUT2")]
    pub control_mesh: Option<PathBuf>,
    /// Refuse to start when the estimated memory exceeds this (suffixes K, M, G, T: powers
    /// of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = crate::parse_bytes)]
    pub max_memory: Option<u64>,
}

/// The name of the input in messages: the file name as given, or `<stdin>` for `-`.
pub fn input_name(path: &Path) -> String {
    if path == Path::new("-") {
        "<stdin>".to_owned()
    } else {
        path.display().to_string()
    }
}

/// Writes the output of `subsurf blend` or `subsurf fill`: the groups and polylines of
/// `result` to `out`, its control mesh to `control_out` when given.
pub fn write(result: &MethodOutput, out: &Output, control_out: Option<Output>) -> Result<()> {
    out.write(|w| write_method_obj(w, result))?;
    if let Some(c) = control_out {
        let comment = result.control_comment();
        let opts = WriteOptions {
            comment: Some(&comment),
            ..Default::default()
        };
        c.write(|mut w| write_obj(&mut w, &result.control, &opts))?;
    }
    Ok(())
}

/// Runs `subsurf blend`.
pub fn run(args: &BlendArgs) -> Result<()> {
    let out = Output::new(&args.output);
    out.check()?;
    let control_out = args.control_mesh.as_deref().map(Output::new);
    if let Some(c) = &control_out {
        c.check()?;
    }
    let name = input_name(&args.input);
    let items = read_geometry(&args.input)?;
    let options = BlendJobOptions {
        levels: args.levels,
        samples: args.samples,
    };
    let job = BlendJob::new(&items, &name, &options)?;
    crate::memory::check(
        &name,
        &format!("blending with {} levels", args.levels),
        job.estimate_memory(),
        args.max_memory,
        MEMORY_HINT,
    )?;
    write(&job.run()?, &out, control_out)
}

/// What to do about a blend or fill too large for the memory.
pub const MEMORY_HINT: &str = "use fewer --levels or --samples";
