//! `subsurf demo`: the bundled example meshes, refined, written to a directory.

use std::fs;
use std::path::Path;

use anyhow::{Context, Result};
use subsurf::io::obj::parse_obj;
use subsurf::mesh::{Options, PolyMesh};
use subsurf::SubdivideOptions;

use super::subdivide::{command_line, refine, write};
use crate::input::Input;
use crate::output::Output;
use crate::progress::Progress;
use crate::DemoArgs;

/// A bundled example mesh (from `examples/meshes/` at the repository root).
struct Example {
    name: &'static str,
    obj: &'static str,
    /// Also refine to the limit surface, with normals.
    limit: bool,
}

macro_rules! example {
    ($name:literal, $limit:expr) => {
        Example {
            name: $name,
            obj: include_str!(concat!("../../../../examples/meshes/", $name, ".obj")),
            limit: $limit,
        }
    };
}

const EXAMPLES: &[Example] = &[
    example!("cube", false),
    example!("cube-crease", false),
    example!("grid", false),
    example!("hut", false),
    example!("torus", true),
    example!("catmark_pawn", false),
];

/// Refinement level of the demo.
const LEVELS: u32 = 3;

/// Runs `subsurf demo`.
pub fn run(args: &DemoArgs) -> Result<()> {
    let dir = &args.output;
    fs::create_dir_all(dir)
        .with_context(|| format!("cannot create directory {}", dir.display()))?;
    let mut stdout = std::io::stdout().lock();
    for ex in EXAMPLES {
        let name = format!("{}.obj", ex.name);
        let input = Input {
            obj: parse_obj(ex.obj.as_bytes(), &name)?,
            name,
        };

        let path = dir.join(&input.name);
        Output::File(path.clone()).write(|w| w.write_all(ex.obj.as_bytes()))?;
        report(&mut stdout, &path, &input.obj.mesh, "input")?;

        let scheme = input.obj.options.resolve(Options::default());
        for limit in [false, true].into_iter().filter(|&l| !l || ex.limit) {
            let opts = SubdivideOptions {
                levels: LEVELS,
                scheme,
                limit,
                ..Default::default()
            };
            let suffix = if limit { "-limit" } else { "" };
            let path = dir.join(format!("{}-l{LEVELS}{suffix}.obj", ex.name));
            let progress = Progress::new(LEVELS, false);
            let sub = refine(&input, &opts, &progress, false)?;
            let comment = command_line(&opts, &input.name);
            write(
                &Output::File(path.clone()),
                &sub,
                &opts,
                &comment,
                &progress,
            )?;
            drop(progress);
            let what = if limit {
                "level 3, limit positions and normals"
            } else {
                "level 3"
            };
            report(&mut stdout, &path, &sub.mesh, what)?;
        }
    }
    Ok(())
}

/// One line per written file: path, counts, what it is.
fn report(out: &mut impl std::io::Write, path: &Path, mesh: &PolyMesh, what: &str) -> Result<()> {
    writeln!(
        out,
        "{}  {} vertices, {} faces ({what})",
        path.display(),
        mesh.num_vertices(),
        mesh.num_faces()
    )
    .context("cannot write to standard output")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn examples_are_small_and_tagged() {
        let total: usize = EXAMPLES.iter().map(|e| e.obj.len()).sum();
        assert!(total < 100_000, "bundled examples take {total} bytes");
        for e in EXAMPLES {
            assert!(e.obj.starts_with('#'), "{} has no header comment", e.name);
        }
        assert!(EXAMPLES.iter().any(|e| e.limit));
    }
}
