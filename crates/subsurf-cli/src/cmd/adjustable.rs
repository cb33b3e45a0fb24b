//! The shape-adjustable scheme's flags (`--scheme adjustable --c C [--adjust-steps K]`):
//! parsing, validation and the library's [`Mixed`] parameters.

use anyhow::{Context, Result};
use clap::error::ErrorKind;
use clap::CommandFactory;
use subsurf::mesh::{Options, PolyMesh};
use subsurf::scheme::Adjustable;
use subsurf::{subdivide, Mixed, Scheme, SubdivideOptions};

use crate::input::Input;
use crate::{AdjustArgs, SchemeKind};

/// Parses `--c`: a number in `[0, 1]` (clap turns the error into a usage error, exit 2).
pub fn parse_c(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(c) if (0.0..=1.0).contains(&c) => Ok(c),
        _ => Err(format!(
            "'{s}' is not a shape parameter in [0, 1] (0.5 is Catmull-Clark; smaller stays \
             closer to the control mesh)"
        )),
    }
}

/// The scheme of `subdivide`'s and `repose`'s flags. `--c` with another scheme than
/// `adjustable` is a usage error (exit 2).
pub fn for_subdivide(kind: SchemeKind, args: &AdjustArgs) -> Scheme {
    match (kind, args.c) {
        (SchemeKind::Adjustable, Some(c)) => Scheme::Adjustable(mixed(c, args.adjust_steps)),
        (SchemeKind::Adjustable, None) => usage_error("--scheme adjustable needs --c C"),
        (_, Some(_)) => usage_error("--c and --adjust-steps need --scheme adjustable"),
        (SchemeKind::Nurss, None) => Scheme::Nurss,
        (SchemeKind::CatmullClark, None) => Scheme::CatmullClark,
        (SchemeKind::Loop, None) => Scheme::Loop,
        (SchemeKind::Bilinear, None) => Scheme::Bilinear,
    }
}

/// The mixed-surface parameters of `tessellate`'s and `render`'s flags (`--c` selects the
/// adjustable scheme there; `--adjust-steps` defaults to 1).
pub fn for_surface(args: &AdjustArgs) -> Option<Mixed> {
    args.c
        .map(|c| mixed(c, Some(args.adjust_steps.unwrap_or(1))))
}

/// The surface that `tessellate` and `limit` sample: `--scheme` (`given`) when given, else
/// adjustable with `--c`, else NURSS for a file with knot interval or weight tags (with a
/// note on stderr unless `quiet`), else Catmull-Clark ([`check_surface_flags`] has refused
/// the contradictory combinations).
pub fn surface_kind(
    given: Option<SchemeKind>,
    args: &AdjustArgs,
    input: &Input,
    quiet: bool,
) -> SchemeKind {
    match given {
        Some(kind) => kind,
        None if args.c.is_some() => SchemeKind::Adjustable,
        None if subsurf::nonuniform::has_knots(&input.obj.mesh) => {
            if !quiet {
                crate::output::eprint_line(&format!(
                    "note: {} has knot interval or weight tags: sampling the non-uniform \
                     (NURSS) surface (--scheme catmull-clark ignores them)",
                    input.name
                ));
            }
            SchemeKind::Nurss
        }
        None => SchemeKind::CatmullClark,
    }
}

/// Usage errors (exit 2) of `--scheme` (`given`) with `--c` for the commands that sample a
/// surface ([`surface_kind`]), found before any input is read.
pub fn check_surface_flags(given: Option<SchemeKind>, args: &AdjustArgs) {
    let c = args.c.is_some();
    match given {
        Some(SchemeKind::Adjustable) if !c => usage_error("--scheme adjustable needs --c C"),
        Some(
            SchemeKind::Nurss | SchemeKind::CatmullClark | SchemeKind::Loop | SchemeKind::Bilinear,
        ) if c => usage_error("--c applies to --scheme adjustable only"),
        _ => {}
    }
}

/// The control mesh whose Catmull-Clark limit surface is the mixed surface of `mixed`:
/// the input refined `mixed.steps` times with the adjustable scheme (holes kept).
pub fn refined_mesh(input: &Input, options: Options, mixed: Mixed) -> Result<PolyMesh> {
    let opts = SubdivideOptions {
        levels: mixed.steps,
        scheme: Scheme::Adjustable(mixed),
        options,
        keep_holes: true,
        max_memory: crate::memory::available(),
        ..SubdivideOptions::default()
    };
    let sub = subdivide(&input.obj.mesh, &opts)
        .with_context(|| format!("{}: --adjust-steps {}", input.name, mixed.steps))?;
    Ok(sub.mesh)
}

/// Samples per edge of the refined mesh that give at least `rate` per input edge after
/// `steps` steps: `⌈rate / 2^steps⌉`.
pub fn refined_rate(rate: u32, steps: u32) -> u32 {
    let div = 1u64 << steps.min(32);
    (u64::from(rate).div_ceil(div)).max(1) as u32
}

fn mixed(c: f64, steps: Option<u32>) -> Mixed {
    // `parse_c` accepted only values in [0, 1].
    let scheme = Adjustable::new(c).unwrap_or_else(|e| usage_error(&e.to_string()));
    Mixed {
        scheme,
        steps: steps.unwrap_or(u32::MAX),
    }
}

/// The flags that reproduce `mixed` with `levels` levels, for output headers.
pub fn flags(mixed: Mixed, levels: u32) -> String {
    let mut s = format!("--scheme adjustable --c {}", mixed.scheme.c());
    if mixed.steps < levels {
        s.push_str(&format!(" --adjust-steps {}", mixed.steps));
    }
    s
}

/// Exits with clap's usage error (status 2).
pub fn usage_error(msg: &str) -> ! {
    crate::Cli::command()
        .error(ErrorKind::ArgumentConflict, msg)
        .exit()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn c_values() {
        assert_eq!(parse_c("0"), Ok(0.0));
        assert_eq!(parse_c("0.25"), Ok(0.25));
        assert_eq!(parse_c("1"), Ok(1.0));
        for bad in ["-0.1", "1.01", "nan", "inf", "", "x"] {
            assert!(parse_c(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn flags_reproduce_the_parameters() {
        let m = Mixed {
            scheme: Adjustable::new(0.3).expect("valid"),
            steps: 2,
        };
        assert_eq!(flags(m, 4), "--scheme adjustable --c 0.3 --adjust-steps 2");
        assert_eq!(flags(m, 2), "--scheme adjustable --c 0.3");
        let all = Mixed::all(Adjustable::CATMULL_CLARK);
        assert_eq!(flags(all, 3), "--scheme adjustable --c 0.5");
        let args = AdjustArgs {
            c: Some(0.2),
            adjust_steps: None,
        };
        assert_eq!(
            for_subdivide(SchemeKind::Adjustable, &args),
            Scheme::Adjustable(Mixed {
                scheme: Adjustable::new(0.2).expect("valid"),
                steps: u32::MAX
            })
        );
        assert_eq!(for_surface(&args).map(|m| m.steps), Some(1));
        let none = AdjustArgs {
            c: None,
            adjust_steps: None,
        };
        assert_eq!(
            for_subdivide(SchemeKind::CatmullClark, &none),
            Scheme::CatmullClark
        );
        assert_eq!(for_subdivide(SchemeKind::Nurss, &none), Scheme::Nurss);
        assert_eq!(for_surface(&none), None);
    }

    #[test]
    fn refined_rates_round_up() {
        assert_eq!(refined_rate(16, 2), 4);
        assert_eq!(refined_rate(10, 2), 3);
        assert_eq!(refined_rate(1, 3), 1);
        assert_eq!(refined_rate(8, 0), 8);
        assert_eq!(refined_rate(8, 40), 1);
    }
}
