//! The files a command line names, checked before anything runs: every output's extension
//! must be one its command writes, and no output may be an input or another output.
//!
//! A failed check is a usage error (exit 2) and nothing is read or written: `-o out.fbx`
//! must not silently write OBJ, and `fill h.json -o h.json` must not replace its input.

use std::path::{Path, PathBuf};

use crate::output::{check_extension, formats, Format};
use crate::Command;

/// An output a command writes: its flag, its path and the formats it may be written in.
struct Out<'a> {
    flag: &'static str,
    path: &'a Path,
    formats: &'static [Format],
}

/// The inputs and outputs of `command` (`repose` checks its own: its output names are
/// made from the poses' names).
fn files(command: &Command) -> (Vec<&Path>, Vec<Out<'_>>) {
    use Format::*;
    fn out<'a>(flag: &'static str, path: &'a Path, formats: &'static [Format]) -> Out<'a> {
        Out {
            flag,
            path,
            formats,
        }
    }
    let mut inputs: Vec<&Path> = Vec::new();
    let mut outputs = Vec::new();
    match command {
        Command::Subdivide(a) => {
            inputs.push(&a.input);
            outputs.push(out("--output", &a.output, &[Obj]));
        }
        Command::Limit(a) => {
            inputs.push(&a.input);
            outputs.push(out("--output", &a.output, &[Text]));
        }
        Command::Tessellate(a) => {
            inputs.push(&a.input);
            outputs.push(out("--output", &a.output, formats::TESSELLATE));
        }
        Command::Render(a) => {
            inputs.push(&a.input);
            outputs.push(out("--output", &a.output, &[Png]));
        }
        Command::Nurbs(a) => {
            inputs.push(&a.input);
            if let Some(o) = &a.output {
                outputs.push(out("--output", o, &[Json, Obj]));
            }
        }
        Command::Interpolate(a) => {
            inputs.push(&a.input);
            inputs.extend(a.host.as_deref());
            outputs.push(out("--output", &a.output, &[Obj]));
        }
        Command::Spline(a) => {
            inputs.push(&a.input);
            outputs.push(out("--output", &a.output, formats::SPLINE));
        }
        Command::Regularity(a) => {
            inputs.push(&a.input);
            if let Some(p) = &a.plot {
                outputs.push(out("--plot", p, &[Svg, Png]));
            }
        }
        Command::G2(a) => {
            inputs.push(&a.input);
            outputs.push(out("--output", &a.output, formats::G2));
        }
        Command::Blend(a) => {
            inputs.push(&a.input);
            outputs.push(out("--output", &a.output, &[Obj]));
            if let Some(c) = &a.control_mesh {
                outputs.push(out("--control-mesh", c, &[Obj]));
            }
        }
        Command::Fill(a) => {
            inputs.push(&a.input);
            outputs.push(out("--output", &a.output, &[Obj]));
            if let Some(c) = &a.control_mesh {
                outputs.push(out("--control-mesh", c, &[Obj]));
            }
        }
        Command::Info(_) | Command::Demo(_) | Command::Repose(_) | Command::Bench(_) => {}
    }
    (inputs, outputs)
}

/// Checks the files `command` names (see the module docs); the error is the message of a
/// usage error.
pub fn check(command: &Command) -> Result<(), String> {
    let (inputs, outputs) = files(command);
    for o in &outputs {
        check_extension(o.path, o.formats)
            .map_err(|e| format!("{} {}: {e}", o.flag, o.path.display()))?;
    }
    for (k, o) in outputs.iter().enumerate() {
        if let Some(input) = inputs.iter().find(|i| same_file(i, o.path)) {
            return Err(format!(
                "{} {} would replace the input {}: write the output elsewhere",
                o.flag,
                o.path.display(),
                input.display()
            ));
        }
        if let Some(other) = outputs[..k].iter().find(|p| same_file(p.path, o.path)) {
            return Err(format!(
                "{} and {} both name {}: one output would replace the other",
                other.flag,
                o.flag,
                o.path.display()
            ));
        }
    }
    Ok(())
}

/// Whether `a` and `b` name one file: the same file, through links and relative paths,
/// if it exists, else the same name in the same directory. Standard input and output
/// (`-`) are no file.
fn same_file(a: &Path, b: &Path) -> bool {
    if a == Path::new("-") || b == Path::new("-") {
        return false;
    }
    match (identity(a), identity(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

/// The canonical path of `p`, or of its directory joined with its name when `p` does not
/// exist yet.
fn identity(p: &Path) -> Option<PathBuf> {
    if let Ok(c) = p.canonicalize() {
        return Some(c);
    }
    let name = p.file_name()?;
    let dir = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Some(dir.canonicalize().ok()?.join(name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_file_through_relative_paths() {
        let dir = std::env::temp_dir().join(format!("subsurf-paths-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let f = dir.join("a.obj");
        std::fs::write(&f, "").unwrap();
        assert!(same_file(&f, &dir.join("sub/../a.obj")));
        assert!(same_file(&dir.join("new.obj"), &dir.join("sub/../new.obj")));
        assert!(!same_file(&f, &dir.join("b.obj")));
        assert!(!same_file(Path::new("-"), Path::new("-")));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
