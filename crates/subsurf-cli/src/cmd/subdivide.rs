//! `subsurf subdivide`: read OBJ, refine, write OBJ.

use anyhow::{Context, Result};
use subsurf::io::obj::{write_obj, WriteOptions};
use subsurf::mesh::{Options, TriangleSubdivision};
use subsurf::{subdivide_with_progress, SubdivideOptions, Subdivision};

use crate::input::Input;
use crate::output::Output;
use crate::progress::Progress;
use crate::SubdivideArgs;

/// Runs `subsurf subdivide`.
pub fn run(args: &SubdivideArgs) -> Result<()> {
    let out = Output::new(&args.output);
    out.check()?;
    let progress = Progress::new(args.levels, args.quiet);
    progress.set_message(format!("reading {}", args.input.display()));
    let input = Input::read(&args.input)?;
    if args.strict {
        input.check_strict()?;
    }
    if !args.quiet {
        for w in input.unsupported_tag_warnings() {
            progress.warn(&w);
        }
    }
    let opts = SubdivideOptions {
        levels: args.levels,
        scheme: args
            .scheme
            .over(input.obj.options)
            .resolve(Options::default()),
        limit: args.limit,
        keep_holes: args.keep_holes,
        max_memory: args.max_memory,
    };
    let sub = refine(&input, &opts, &progress, args.quiet)?;
    let comment = command_line(&opts, &args.input.display().to_string());
    write(&out, &sub, &opts, &comment, &progress)
}

/// Refines `input` with `opts`, reporting levels to `progress` and the library's warnings
/// (unless `quiet`). Errors name the input.
pub fn refine(
    input: &Input,
    opts: &SubdivideOptions,
    progress: &Progress,
    quiet: bool,
) -> Result<Subdivision> {
    progress.set_message(format!("refining {}", input.name));
    let sub = subdivide_with_progress(&input.obj.mesh, opts, &mut |done, levels| {
        progress.level_done(done, levels)
    })
    .with_context(|| input.name.clone())?;
    if !quiet {
        for w in &sub.warnings {
            progress.warn(&format!("{}: {w}", input.name));
        }
    }
    Ok(sub)
}

/// Writes the refined mesh (and its limit normals, if any) as OBJ to `out`.
pub fn write(
    out: &Output,
    sub: &Subdivision,
    opts: &SubdivideOptions,
    comment: &str,
    progress: &Progress,
) -> Result<()> {
    progress.set_message(format!("writing {}", out.name()));
    let write_opts = WriteOptions {
        normals: sub.normals.as_deref(),
        scheme: Some(opts.scheme),
        comment: Some(comment),
    };
    out.write(|mut w| write_obj(&mut w, &sub.mesh, &write_opts))
}

/// The command line that reproduces `opts` on `input`, for the output's header comment.
pub fn command_line(opts: &SubdivideOptions, input: &str) -> String {
    let s = &opts.scheme;
    let mut line = format!(
        "subsurf subdivide -l {} --boundary {} --crease-method {}",
        opts.levels, s.boundary, s.crease_method
    );
    if s.triangles == TriangleSubdivision::Smooth {
        line.push_str(" --smooth-triangles");
    }
    if opts.limit {
        line.push_str(" --limit");
    }
    if opts.keep_holes {
        line.push_str(" --keep-holes");
    }
    line.push(' ');
    line.push_str(input);
    line
}

#[cfg(test)]
mod tests {
    use super::*;
    use subsurf::mesh::{BoundaryInterpolation, CreaseMethod};

    #[test]
    fn command_line_lists_effective_options() {
        let opts = SubdivideOptions {
            levels: 3,
            scheme: Options {
                boundary: BoundaryInterpolation::EdgeAndCorner,
                crease_method: CreaseMethod::Chaikin,
                triangles: TriangleSubdivision::Smooth,
            },
            limit: true,
            keep_holes: false,
            max_memory: None,
        };
        assert_eq!(
            command_line(&opts, "in.obj"),
            "subsurf subdivide -l 3 --boundary edge-and-corner --crease-method chaikin \
             --smooth-triangles --limit in.obj"
        );
    }
}
