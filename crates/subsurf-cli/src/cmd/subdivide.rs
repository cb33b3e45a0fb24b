//! `subsurf subdivide`: read OBJ, refine, write OBJ.

use anyhow::{Context, Result};
use subsurf::io::{write_obj, FileOptions, WriteOptions};
use subsurf::mesh::{crease_by_angle, Options, TriangleSubdivision};
use subsurf::{subdivide_with_progress, Scheme, SubdivideOptions, Subdivision};

use crate::input::Input;
use crate::output::Output;
use crate::progress::Progress;
use crate::{SchemeKind, SubdivideArgs};

/// Runs `subsurf subdivide`.
pub fn run(args: &SubdivideArgs) -> Result<()> {
    let out = Output::new(&args.output);
    out.check()?;
    let progress = Progress::new(args.levels, args.quiet);
    progress.set_message(format!("reading {}", args.input.display()));
    let mut input = Input::read_surface(&args.input, args.max_memory)?;
    if args.strict {
        input.check_strict()?;
    }
    if !args.quiet {
        for w in input.warnings() {
            progress.warn(&w);
        }
    }
    let kind = scheme_kind(args.scheme_kind, &input, &progress, args.quiet);
    let opts = SubdivideOptions {
        levels: args.levels,
        scheme: super::adjustable::for_subdivide(kind, &args.adjust),
        options: FileOptions {
            face_varying: args.fvar.or(input.obj.options.face_varying),
            ..args.scheme.over(input.obj.options)
        }
        .resolve(Options::default()),
        limit: args.limit,
        keep_holes: args.keep_holes,
        max_memory: args.max_memory.or_else(crate::memory::available),
    };
    crate::memory::for_refinement(subsurf::estimate_memory(&input.obj.mesh, &opts));
    let mut flags = scheme_flags(opts.scheme, opts.levels);
    if let Some(angle) = args.crease_angle {
        add_angle_creases(&mut input, &opts.options, angle, args.sharpness)?;
        let angle = format!("--crease-angle {angle} --sharpness {}", args.sharpness);
        flags = [flags, angle].join(" ").trim().to_owned();
    }
    let sub = refine(&input, &opts, &progress, args.quiet)?;
    let comment = command_line_with(&opts, &flags, &args.input.display().to_string());
    write(&out, &sub, &opts, &comment, &progress)
}

/// The flags that select `scheme` (refining `levels` levels), for output headers: none for
/// Catmull-Clark.
pub fn scheme_flags(scheme: Scheme, levels: u32) -> String {
    match scheme {
        Scheme::Adjustable(m) => super::adjustable::flags(m, levels),
        Scheme::CatmullClark => String::new(),
        other => format!("--scheme {}", other.name()),
    }
}

/// The scheme: `--scheme` (`given`) when given, else NURSS for a file with knot tags (with
/// a note on stderr unless `quiet`), else Catmull-Clark.
pub fn scheme_kind(
    given: Option<SchemeKind>,
    input: &Input,
    progress: &Progress,
    quiet: bool,
) -> SchemeKind {
    match given {
        Some(kind) => kind,
        None if subsurf::nonuniform::has_knots(&input.obj.mesh) => {
            if !quiet {
                progress.note(&format!(
                    "{} has knot interval or weight tags: refining with --scheme nurss \
                     (--scheme catmull-clark ignores them)",
                    input.name
                ));
            }
            SchemeKind::Nurss
        }
        None => SchemeKind::CatmullClark,
    }
}

/// Puts a crease of `sharpness` on every edge of `input` whose dihedral angle exceeds
/// `angle` degrees, *before* the file's own creases so that those win on the same edge.
fn add_angle_creases(
    input: &mut Input,
    scheme: &Options,
    angle: f64,
    sharpness: f32,
) -> Result<()> {
    let mesh = &mut input.obj.mesh;
    let mut creases = crease_by_angle(mesh, scheme, angle, sharpness)
        .with_context(|| format!("{}: --crease-angle", input.name))?;
    creases.append(&mut mesh.tags.creases);
    mesh.tags.creases = creases;
    Ok(())
}

/// Parses `--crease-angle`: degrees, a finite number in [0, 180].
pub fn parse_crease_angle(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(a) if (0.0..=180.0).contains(&a) => Ok(a),
        _ => Err(format!(
            "'{s}' is not an angle in degrees between 0 and 180 (e.g. 30; a cube's edges are at 90)"
        )),
    }
}

/// Parses `--sharpness`: a finite number ≥ 0 (10 or more is infinitely sharp).
pub fn parse_sharpness(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!(
            "'{s}' is not a sharpness: expected a number ≥ 0 (10 or more is infinitely sharp)"
        )),
    }
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
    let mut report = |done, levels| progress.level_done(done, levels);
    let sub = subdivide_with_progress(&input.obj.mesh, opts, &mut report)
        .with_context(|| input.name.clone())?;
    if !quiet {
        for w in sub
            .warnings
            .iter()
            .filter_map(|w| input.topology_warning(w))
        {
            progress.warn(&w);
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
        scheme: Some(opts.options),
        comment: Some(comment),
    };
    out.write(|mut w| write_obj(&mut w, &sub.mesh, &write_opts))
}

/// The command line that reproduces `opts` on `input`, for the output's header comment.
pub fn command_line(opts: &SubdivideOptions, input: &str) -> String {
    command_line_with(opts, "", input)
}

/// [`command_line`] with `flags` (if not empty) before the input.
fn command_line_with(opts: &SubdivideOptions, flags: &str, input: &str) -> String {
    command_line_of("subdivide", opts, flags, input)
}

/// The command line of subcommand `command` that refines `inputs` with `opts` (levels,
/// scheme, `--limit`, `--keep-holes`), `flags` (if not empty) before the inputs.
pub fn command_line_of(
    command: &str,
    opts: &SubdivideOptions,
    flags: &str,
    inputs: &str,
) -> String {
    let s = &opts.options;
    let mut line = format!(
        "subsurf {command} -l {} --boundary {} --crease-method {}",
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
    if !flags.is_empty() {
        line.push(' ');
        line.push_str(flags);
    }
    line.push(' ');
    line.push_str(inputs);
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
            options: Options {
                boundary: BoundaryInterpolation::EdgeAndCorner,
                crease_method: CreaseMethod::Chaikin,
                triangles: TriangleSubdivision::Smooth,
                ..Options::default()
            },
            limit: true,
            keep_holes: false,
            max_memory: None,
            scheme: Scheme::CatmullClark,
        };
        assert_eq!(
            command_line(&opts, "in.obj"),
            "subsurf subdivide -l 3 --boundary edge-and-corner --crease-method chaikin \
             --smooth-triangles --limit in.obj"
        );
        assert_eq!(
            command_line_with(&opts, "--crease-angle 30 --sharpness 10", "in.obj"),
            "subsurf subdivide -l 3 --boundary edge-and-corner --crease-method chaikin \
             --smooth-triangles --limit --crease-angle 30 --sharpness 10 in.obj"
        );
    }

    #[test]
    fn crease_angle_and_sharpness_values() {
        assert_eq!(parse_crease_angle("30"), Ok(30.0));
        assert_eq!(parse_crease_angle("0"), Ok(0.0));
        assert_eq!(parse_crease_angle("180"), Ok(180.0));
        for bad in ["-1", "180.01", "200", "nan", "inf", "", "x"] {
            assert!(parse_crease_angle(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_sharpness("2.5"), Ok(2.5));
        assert_eq!(parse_sharpness("0"), Ok(0.0));
        for bad in ["-0.5", "nan", "inf", "", "x"] {
            assert!(parse_sharpness(bad).is_err(), "{bad}");
        }
    }
}
