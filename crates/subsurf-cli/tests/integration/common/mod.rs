//! Helpers shared by the end-to-end tests: run the built `subsurf` binary in a temporary
//! directory and look at what it printed and wrote.
#![allow(dead_code)] // Each test file uses a different subset.

use std::fs;
use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};

/// The bundled cube (8 vertices, 6 quads).
pub const CUBE: &str = include_str!("../../../../../examples/meshes/cube.obj");
/// The bundled hut (a house with a pentagon and triangles).
pub const HUT: &str = include_str!("../../../../../examples/meshes/hut.obj");
/// The bundled 4 × 4 grid of quads.
pub const GRID: &str = include_str!("../../../../../examples/meshes/grid.obj");

/// The positions of the `v` lines of an OBJ text.
pub fn positions(obj: &str) -> Vec<[f64; 3]> {
    obj.lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|rest| {
            let c: Vec<f64> = rest
                .split_whitespace()
                .map(|t| t.parse().expect("coordinate"))
                .collect();
            [c[0], c[1], c[2]]
        })
        .collect()
}

/// Lines of `obj` whose first word is `prefix` (`v`, `vn`, `f`, ...).
pub fn count_records(obj: &str, prefix: &str) -> usize {
    obj.lines()
        .filter(|l| l.split_whitespace().next() == Some(prefix))
        .count()
}

pub fn run_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_subsurf"))
        .current_dir(dir)
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("cannot run subsurf")
}

pub fn run_with_stdin(dir: &Path, args: &[&str], input: &str) -> Output {
    run_with_bytes(dir, args, input.as_bytes())
}

/// Runs `subsurf args` in `dir` with `input` on standard input, written from a thread of
/// its own (the child may stop reading early: a broken pipe is not an error here).
pub fn run_with_bytes(dir: &Path, args: &[&str], input: &[u8]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_subsurf"))
        .current_dir(dir)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("cannot run subsurf");
    let mut stdin = child.stdin.take().expect("piped stdin");
    let input = input.to_vec();
    let feeder = std::thread::spawn(move || {
        let _ = stdin.write_all(&input);
    });
    let out = child.wait_with_output().expect("wait for subsurf");
    let _ = feeder.join();
    out
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts the exit code, showing stderr when it differs.
pub fn assert_code(o: &Output, code: i32) {
    assert_eq!(o.status.code(), Some(code), "stderr:\n{}", stderr(o));
}

/// A temporary directory holding `files`.
pub fn dir_with(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    for (name, text) in files {
        fs::write(dir.path().join(name), text).expect("write test file");
    }
    dir
}

/// File names in `dir`, sorted.
pub fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .expect("read dir")
        .map(|e| {
            e.expect("dir entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    names
}
