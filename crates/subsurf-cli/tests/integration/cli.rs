//! End-to-end tests of the `subsurf` binary, each in its own temporary directory.

use crate::common;
use common::*;

use std::fs;
use std::path::Path;

/// The value on the `label:` line of `subsurf info` output.
fn info_value<'a>(text: &'a str, label: &str) -> Option<&'a str> {
    text.lines()
        .find_map(|l| l.strip_prefix(label)?.strip_prefix(':'))
        .map(str::trim)
}

// ---------------------------------------------------------------------------------------
// Argument parsing and exit codes

#[test]
fn help_exits_zero() {
    let dir = dir_with(&[]);
    let o = run_in(dir.path(), &["--help"]);
    assert_code(&o, 0);
    for cmd in ["subdivide", "info", "demo"] {
        assert!(stdout(&o).contains(cmd), "top-level help lacks {cmd}");
        let o = run_in(dir.path(), &[cmd, "--help"]);
        assert_code(&o, 0);
        let text = stdout(&o);
        assert!(text.contains("Usage: subsurf"), "{text}");
        assert!(
            text.contains("Examples:"),
            "{cmd} --help has no examples:\n{text}"
        );
    }
    let o = run_in(dir.path(), &["--version"]);
    assert_code(&o, 0);
    assert!(stdout(&o).starts_with("subsurf "));
}

#[test]
fn subdivide_help_lists_the_options() {
    let dir = dir_with(&[]);
    let o = run_in(dir.path(), &["subdivide", "--help"]);
    assert_code(&o, 0);
    let text = stdout(&o);
    for flag in [
        "--output",
        "--levels",
        "--boundary",
        "--crease-method",
        "--smooth-triangles",
        "--limit",
        "--keep-holes",
        "--max-memory",
        "--quiet",
        "edge-and-corner",
        "chaikin",
    ] {
        assert!(text.contains(flag), "subdivide --help lacks {flag}");
    }
}

#[test]
fn usage_errors_exit_two() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let cases: &[&[&str]] = &[
        &[],
        &["frobnicate"],
        &["subdivide", "cube.obj", "-o", "out.obj", "--bogus"],
        &["subdivide", "cube.obj"],
        &["subdivide", "-o", "out.obj"],
        &[
            "subdivide",
            "cube.obj",
            "-o",
            "out.obj",
            "--boundary",
            "sideways",
        ],
        &[
            "subdivide",
            "cube.obj",
            "-o",
            "out.obj",
            "--crease-method",
            "fancy",
        ],
        &["subdivide", "cube.obj", "-o", "out.obj", "-l", "-1"],
        &["subdivide", "cube.obj", "-o", "out.obj", "-l", "two"],
        &[
            "subdivide",
            "cube.obj",
            "-o",
            "out.obj",
            "--max-memory",
            "lots",
        ],
        &[
            "subdivide",
            "cube.obj",
            "-o",
            "out.obj",
            "--max-memory",
            "12X",
        ],
        &["info"],
        &["info", "cube.obj", "--boundary", "sideways"],
        &["demo", "--levels", "3"],
    ];
    for args in cases {
        let o = run_in(dir.path(), args);
        assert_eq!(
            o.status.code(),
            Some(2),
            "{args:?}: stderr:\n{}",
            stderr(&o)
        );
        assert!(!stderr(&o).is_empty(), "{args:?}: no message");
    }
    assert_eq!(
        listing(dir.path()),
        ["cube.obj"],
        "a usage error wrote something"
    );
}

#[test]
fn missing_input_exits_one_and_names_the_file() {
    let dir = dir_with(&[]);
    let o = run_in(dir.path(), &["subdivide", "missing.obj", "-o", "out.obj"]);
    assert_code(&o, 1);
    let err = stderr(&o);
    assert!(err.starts_with("error: "), "{err}");
    assert!(err.contains("missing.obj"), "{err}");
    assert!(o.stdout.is_empty());
    assert!(
        listing(dir.path()).is_empty(),
        "output written for a missing input"
    );

    let o = run_in(dir.path(), &["info", "missing.obj"]);
    assert_code(&o, 1);
    assert!(stderr(&o).contains("missing.obj"), "{}", stderr(&o));
}

#[test]
fn missing_output_directory_exits_one() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["subdivide", "cube.obj", "-o", "no/such/dir/out.obj"],
    );
    assert_code(&o, 1);
    assert!(stderr(&o).contains("no/such/dir"), "{}", stderr(&o));
    assert_eq!(listing(dir.path()), ["cube.obj"]);
}

// ---------------------------------------------------------------------------------------
// Bad input: exit 1, `file:line`, no output file

const MALFORMED: &[(&str, &str, usize)] = &[
    (
        "face index out of range",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n",
        4,
    ),
    (
        "NaN coordinate",
        "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n",
        2,
    ),
    (
        "face of two vertices",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n",
        4,
    ),
    ("bad number", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n", 2),
];

/// A face that repeats a vertex is refined as OpenSubdiv refines it, with a warning;
/// `--strict` rejects it, naming the line, and writes nothing.
#[test]
fn repeated_vertex_warns_by_default_and_fails_with_strict() {
    let text = "# a comment\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\nf 2 2 4\n";
    let dir = dir_with(&[("deg.obj", text)]);
    let o = run_in(
        dir.path(),
        &["subdivide", "deg.obj", "-o", "out.obj", "-l", "1"],
    );
    assert_code(&o, 0);
    assert!(stderr(&o).contains("warning: deg.obj:"), "{}", stderr(&o));
    assert!(stderr(&o).contains("more than once"), "{}", stderr(&o));
    let o = run_in(
        dir.path(),
        &["subdivide", "deg.obj", "-o", "strict.obj", "--strict"],
    );
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("deg.obj:7: face 2 lists vertex 2 more than once"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.path().join("strict.obj").exists());
}

#[test]
fn malformed_obj_exits_one_names_the_line_and_writes_nothing() {
    for (what, text, line) in MALFORMED {
        let dir = dir_with(&[("bad.obj", text)]);
        let o = run_in(dir.path(), &["subdivide", "bad.obj", "-o", "out.obj"]);
        assert_code(&o, 1);
        let err = stderr(&o);
        assert!(err.starts_with("error: "), "{what}: {err}");
        assert!(err.contains(&format!("bad.obj:{line}:")), "{what}: {err}");
        assert_eq!(
            err.matches("bad.obj").count(),
            1,
            "{what}: file named twice: {err}"
        );
        assert_eq!(
            listing(dir.path()),
            ["bad.obj"],
            "{what}: output or temp file left"
        );
    }
}

#[test]
fn malformed_obj_keeps_an_existing_output_file() {
    let (_, text, _) = MALFORMED[0];
    let dir = dir_with(&[("bad.obj", text), ("out.obj", "previous contents\n")]);
    let o = run_in(dir.path(), &["subdivide", "bad.obj", "-o", "out.obj"]);
    assert_code(&o, 1);
    let kept = fs::read_to_string(dir.path().join("out.obj")).expect("out.obj");
    assert_eq!(kept, "previous contents\n");
    assert_eq!(listing(dir.path()), ["bad.obj", "out.obj"]);
}

#[test]
fn malformed_stdin_names_stdin_and_the_line() {
    let dir = dir_with(&[]);
    let (_, text, line) = MALFORMED[0];
    let o = run_with_stdin(dir.path(), &["subdivide", "-", "-o", "-"], text);
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains(&format!("<stdin>:{line}:")),
        "{}",
        stderr(&o)
    );
    assert!(o.stdout.is_empty(), "partial output on stdout");
}

#[test]
fn info_on_malformed_obj_exits_one() {
    let (_, text, line) = MALFORMED[1];
    let dir = dir_with(&[("bad.obj", text)]);
    let o = run_in(dir.path(), &["info", "bad.obj"]);
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains(&format!("bad.obj:{line}:")),
        "{}",
        stderr(&o)
    );
}

// ---------------------------------------------------------------------------------------
// subdivide

#[test]
fn subdivide_writes_a_file() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["subdivide", "cube.obj", "-o", "out.obj", "-l", "2"],
    );
    assert_code(&o, 0);
    assert!(o.stdout.is_empty(), "stdout: {}", stdout(&o));
    assert!(o.stderr.is_empty(), "stderr: {}", stderr(&o));
    let out = fs::read_to_string(dir.path().join("out.obj")).expect("out.obj");
    // Catmull-Clark on a cube: F = 6·4^l, V = F + 2 (a closed genus-0 quad mesh).
    assert_eq!(count_records(&out, "f"), 96);
    assert_eq!(count_records(&out, "v"), 98);
    assert!(
        out.contains("subsurf subdivide -l 2"),
        "no command in the header"
    );
    assert_eq!(
        listing(dir.path()),
        ["cube.obj", "out.obj"],
        "temp file left"
    );
}

#[test]
fn default_level_is_two() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(dir.path(), &["subdivide", "cube.obj", "-o", "-"]);
    assert_code(&o, 0);
    assert_eq!(count_records(&stdout(&o), "f"), 96);
}

#[test]
fn dash_output_writes_obj_to_stdout() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(dir.path(), &["subdivide", "cube.obj", "-o", "-", "-l", "1"]);
    assert_code(&o, 0);
    let out = stdout(&o);
    assert_eq!(count_records(&out, "v"), 26);
    assert_eq!(count_records(&out, "f"), 24);
    assert_eq!(listing(dir.path()), ["cube.obj"], "a file was written");
}

/// Output to a device such as `/dev/null` goes into it: the atomic write (temporary file
/// renamed into place) must not replace the device by an ordinary file, which as root
/// would break every later process that reads or writes `/dev/null`.
#[cfg(target_os = "linux")]
#[test]
fn output_to_dev_null_leaves_the_device_alone() {
    use std::os::unix::fs::FileTypeExt;
    let is_device = || {
        fs::metadata("/dev/null")
            .map(|m| m.file_type().is_char_device())
            .unwrap_or(false)
    };
    if !is_device() {
        return; // nothing to protect on this system
    }
    let dir = dir_with(&[("grid.obj", GRID)]);
    let o = run_in(
        dir.path(),
        &["subdivide", "grid.obj", "-l", "1", "-o", "/dev/null"],
    );
    assert_code(&o, 0);
    assert!(is_device(), "/dev/null is no longer a device");
}

#[test]
fn dash_input_reads_stdin() {
    let dir = dir_with(&[]);
    let o = run_with_stdin(
        dir.path(),
        &["subdivide", "-", "-o", "out.obj", "-l", "1"],
        CUBE,
    );
    assert_code(&o, 0);
    let out = fs::read_to_string(dir.path().join("out.obj")).expect("out.obj");
    assert_eq!(count_records(&out, "f"), 24);
}

#[test]
fn level_zero_copies_the_mesh() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(dir.path(), &["subdivide", "cube.obj", "-o", "-", "-l", "0"]);
    assert_code(&o, 0);
    let out = stdout(&o);
    assert_eq!(count_records(&out, "v"), 8);
    assert_eq!(count_records(&out, "f"), 6);
}

#[test]
fn limit_writes_one_normal_per_vertex() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["subdivide", "cube.obj", "-o", "-", "-l", "1", "--limit"],
    );
    assert_code(&o, 0);
    let out = stdout(&o);
    assert_eq!(count_records(&out, "vn"), count_records(&out, "v"));
    assert!(out.contains("--limit"), "header comment lacks --limit");
}

/// The value of the `t interpolateboundary` tag in `obj`.
fn boundary_tag(obj: &str) -> Option<&str> {
    obj.lines()
        .find(|l| l.starts_with("t interpolateboundary"))
        .and_then(|l| l.split_whitespace().last())
}

/// `subsurf subdivide grid.obj -o - -l 1 EXTRA...` in `dir`: its standard output, after
/// checking that it succeeded.
fn grid_level_one(dir: &Path, extra: &[&str]) -> String {
    let mut args = vec!["subdivide", "grid.obj", "-o", "-", "-l", "1"];
    args.extend_from_slice(extra);
    let o = run_in(dir, &args);
    assert_code(&o, 0);
    stdout(&o)
}

/// `--boundary edge` and `--boundary corner`, OpenSubdiv's and `osd-oracle`'s names, mean
/// `edge-only` and `edge-and-corner`.
#[test]
fn boundary_accepts_opensubdiv_names() {
    let dir = dir_with(&[("grid.obj", GRID)]);
    for (alias, name, tag) in [
        ("edge", "edge-only", "2"),
        ("corner", "edge-and-corner", "1"),
    ] {
        let out = grid_level_one(dir.path(), &["--boundary", alias]);
        assert_eq!(boundary_tag(&out), Some(tag), "{alias}");
        assert_eq!(
            out,
            grid_level_one(dir.path(), &["--boundary", name]),
            "{alias}"
        );
    }
}

#[test]
fn flags_override_file_tags_only_when_given() {
    // grid.obj says `t interpolateboundary 1/0/0 1` (edge-and-corner).
    let dir = dir_with(&[("grid.obj", GRID)]);
    assert_eq!(boundary_tag(&grid_level_one(dir.path(), &[])), Some("1"));
    let out = grid_level_one(dir.path(), &["--boundary", "none"]);
    assert_eq!(boundary_tag(&out), Some("0"));
    let out = grid_level_one(
        dir.path(),
        &["--crease-method", "chaikin", "--smooth-triangles"],
    );
    assert_eq!(boundary_tag(&out), Some("1"));
    assert!(out.contains("t creasemethod 0/0/1 chaikin"), "{out}");
    assert!(out.contains("t smoothtriangles 0/0/1 smooth"), "{out}");
}

#[test]
fn unsupported_tags_warn_unless_quiet() {
    let text = format!("{CUBE}t vertexedit 0/0/0\n");
    let line = text.lines().count();
    let dir = dir_with(&[("cube.obj", &text)]);
    let o = run_in(
        dir.path(),
        &["subdivide", "cube.obj", "-o", "out.obj", "-l", "1"],
    );
    assert_code(&o, 0);
    assert_eq!(
        stderr(&o).trim_end(),
        format!("warning: cube.obj:{line}: tag 'vertexedit' is not supported and was ignored")
    );
    let o = run_in(
        dir.path(),
        &[
            "subdivide",
            "cube.obj",
            "-o",
            "out.obj",
            "-l",
            "1",
            "--quiet",
        ],
    );
    assert_code(&o, 0);
    assert!(o.stderr.is_empty(), "{}", stderr(&o));
}

#[test]
fn too_large_exits_one_and_writes_nothing() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &[
            "subdivide",
            "cube.obj",
            "-o",
            "out.obj",
            "-l",
            "8",
            "--max-memory",
            "1K",
        ],
    );
    assert_code(&o, 1);
    let err = stderr(&o);
    assert!(err.starts_with("error: cube.obj: "), "{err}");
    assert_eq!(listing(dir.path()), ["cube.obj"]);
}

// ---------------------------------------------------------------------------------------
// info

#[test]
fn info_prints_counts_of_the_cube() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(dir.path(), &["info", "cube.obj"]);
    assert_code(&o, 0);
    let text = stdout(&o);
    assert_eq!(info_value(&text, "vertices"), Some("8"), "{text}");
    assert_eq!(info_value(&text, "edges"), Some("12"), "{text}");
    assert_eq!(info_value(&text, "faces"), Some("6"), "{text}");
    assert_eq!(info_value(&text, "manifold"), Some("yes"), "{text}");
    assert_eq!(
        info_value(&text, "euler characteristic"),
        Some("2"),
        "{text}"
    );
    assert_eq!(info_value(&text, "boundary edges"), Some("0"), "{text}");
    assert_eq!(
        info_value(&text, "extraordinary vertices"),
        Some("8"),
        "{text}"
    );
    assert_eq!(info_value(&text, "diagonal"), Some("3.464102"), "{text}");
}

#[test]
fn info_reports_boundary_and_scheme_of_the_grid() {
    let dir = dir_with(&[("grid.obj", GRID)]);
    let o = run_in(dir.path(), &["info", "grid.obj"]);
    assert_code(&o, 0);
    let text = stdout(&o);
    assert_eq!(info_value(&text, "vertices"), Some("25"), "{text}");
    assert_eq!(info_value(&text, "edges"), Some("40"), "{text}");
    assert_eq!(info_value(&text, "faces"), Some("16"), "{text}");
    assert_eq!(info_value(&text, "boundary loops"), Some("1"), "{text}");
    assert_eq!(info_value(&text, "boundary edges"), Some("16"), "{text}");
    assert_eq!(
        info_value(&text, "euler characteristic"),
        Some("1"),
        "{text}"
    );
    assert_eq!(
        info_value(&text, "boundary interpolation"),
        Some("edge-and-corner (file)")
    );
    let o = run_in(dir.path(), &["info", "grid.obj", "--boundary", "edge-only"]);
    assert_code(&o, 0);
    let text = stdout(&o);
    assert_eq!(
        info_value(&text, "boundary interpolation"),
        Some("edge-only (--boundary)")
    );
}

#[test]
fn info_json_is_valid_json() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(dir.path(), &["info", "cube.obj", "--json"]);
    assert_code(&o, 0);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("valid JSON");
    assert_eq!(v["file"], "cube.obj");
    assert_eq!(v["vertices"], 8);
    assert_eq!(v["edges"], 12);
    assert_eq!(v["faces"], 6);
    assert_eq!(
        v["face_sizes"],
        serde_json::json!([{"size": 4, "count": 6}])
    );
    assert_eq!(
        v["valences"],
        serde_json::json!([{"valence": 3, "count": 8}])
    );
    assert_eq!(v["manifold"], true);
    assert_eq!(v["euler_characteristic"], 2);
    assert_eq!(
        v["bounding_box"]["min"],
        serde_json::json!([-1.0, -1.0, -1.0])
    );
    assert_eq!(v["scheme"]["boundary"], "edge-only");
    assert!(v["file_scheme"]["boundary"].is_null());
    assert_eq!(v["suggested_scheme"], "catmull-clark");
}

/// `info` suggests Loop for a mesh of triangles only, and Catmull-Clark as soon as one
/// face is not a triangle.
#[test]
fn info_suggests_loop_for_triangle_meshes() {
    let tris = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";
    let mixed = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nf 1 2 3 4\nf 2 5 3\n";
    let dir = dir_with(&[("tris.obj", tris), ("mixed.obj", mixed)]);
    for (file, want) in [("tris.obj", "loop"), ("mixed.obj", "catmull-clark")] {
        let o = run_in(dir.path(), &["info", file]);
        assert_code(&o, 0);
        let text = stdout(&o);
        let line = info_value(&text, "suggested scheme").expect("a suggestion");
        assert!(line.starts_with(want), "{file}: {line}");
        let o = run_in(dir.path(), &["info", file, "--json"]);
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("valid JSON");
        assert_eq!(v["suggested_scheme"], want, "{file}");
    }
}

#[test]
fn info_reads_stdin() {
    let dir = dir_with(&[]);
    let o = run_with_stdin(dir.path(), &["info", "-"], CUBE);
    assert_code(&o, 0);
    assert_eq!(info_value(&stdout(&o), "faces"), Some("6"));
}

// ---------------------------------------------------------------------------------------
// demo

#[test]
fn demo_creates_the_files_it_lists() {
    let dir = dir_with(&[]);
    let o = run_in(dir.path(), &["demo", "-o", "out/demo"]);
    assert_code(&o, 0);
    let text = stdout(&o);
    let mut listed = Vec::new();
    for line in text.lines() {
        // `PATH  V vertices, F faces (what)`
        let mut words = line.split_whitespace();
        let path = words.next().expect("a path");
        if !path.ends_with(".obj") {
            // Pictures, glTF and the gallery page: `PATH  (what)` (checked in demo.rs).
            let len = fs::metadata(dir.path().join(path)).map_or(0, |m| m.len());
            assert!(len > 0, "{path} missing or empty");
            listed.push(
                Path::new(path)
                    .file_name()
                    .expect("file name")
                    .to_string_lossy()
                    .into_owned(),
            );
            continue;
        }
        let v: usize = words
            .next()
            .and_then(|w| w.parse().ok())
            .expect("vertex count");
        assert_eq!(words.next(), Some("vertices,"), "{line}");
        let f: usize = words
            .next()
            .and_then(|w| w.parse().ok())
            .expect("face count");
        let obj =
            fs::read_to_string(dir.path().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"));
        assert_eq!(count_records(&obj, "v"), v, "{path}");
        assert_eq!(count_records(&obj, "f"), f, "{path}");
        listed.push(
            Path::new(path)
                .file_name()
                .expect("file name")
                .to_string_lossy()
                .into_owned(),
        );
    }
    listed.sort();
    assert_eq!(
        listing(&dir.path().join("out/demo")),
        listed,
        "files written but not listed"
    );
    for name in [
        "cube.obj",
        "cube-l3.obj",
        "torus-l3-limit.obj",
        "catmark_pawn.obj",
        "catmark_pawn-l3.obj",
    ] {
        assert!(listed.iter().any(|l| l == name), "{name} not written");
    }
    let cube = fs::read_to_string(dir.path().join("out/demo/cube-l3.obj")).expect("cube-l3.obj");
    assert_eq!(count_records(&cube, "f"), 6 * 64);
    let limit = fs::read_to_string(dir.path().join("out/demo/torus-l3-limit.obj")).expect("limit");
    assert_eq!(count_records(&limit, "vn"), count_records(&limit, "v"));
}

#[test]
fn demo_defaults_to_subsurf_demo() {
    let dir = dir_with(&[]);
    let o = run_in(dir.path(), &["demo"]);
    assert_code(&o, 0);
    assert!(dir.path().join("subsurf-demo/cube-l3.obj").is_file());
}

#[test]
fn demo_fails_when_the_directory_is_a_file() {
    let dir = dir_with(&[("taken", "not a directory\n")]);
    let o = run_in(dir.path(), &["demo", "-o", "taken"]);
    assert_code(&o, 1);
    assert!(stderr(&o).contains("taken"), "{}", stderr(&o));
}

/// `limit` evaluates and writes its rows in blocks of faces: on a mesh of several blocks
/// (144 faces, 81 points each: three blocks), the file and standard output hold every
/// face's grid once, in face order and `osd-oracle limit`'s layout, at the library's
/// limit points and derivatives.
#[test]
fn limit_rows_of_every_block_in_face_order() {
    let n = 12;
    let mut obj = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (f64::from(i), f64::from(j));
            obj.push_str(&format!(
                "v {x} {y} {}\n",
                (0.7 * x).sin() * (0.4 * y).cos()
            ));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            obj.push_str(&format!("f {a} {} {} {}\n", a + 1, a + n + 2, a + n + 1));
        }
    }
    let dir = dir_with(&[("wavy.obj", &obj)]);
    let o = run_in(
        dir.path(),
        &["limit", "wavy.obj", "--grid", "9", "-o", "out.tsv"],
    );
    assert_code(&o, 0);
    let file = fs::read_to_string(dir.path().join("out.tsv")).expect("out.tsv");
    let o = run_in(dir.path(), &["limit", "wavy.obj", "--grid", "9", "-o", "-"]);
    assert_code(&o, 0);
    assert_eq!(stdout(&o), file, "standard output and the file differ");

    let mesh = subsurf::io::parse_obj(obj.as_bytes(), "wavy.obj")
        .expect("parse")
        .mesh;
    let surface = subsurf::limit::LimitSurface::new(&mesh, subsurf::mesh::Options::default())
        .expect("surface");
    let rows: Vec<&str> = file.lines().collect();
    assert_eq!(rows.len(), 144 * 81);
    for (r, row) in rows.iter().enumerate() {
        let x: Vec<f64> = row
            .split_whitespace()
            .map(|t| t.parse().expect("number"))
            .collect();
        let (face, k) = ((r / 81) as u32, r % 81);
        let (u, v) = ((k / 9) as f64 / 8.0, (k % 9) as f64 / 8.0);
        assert_eq!(x[..3], [f64::from(face), u, v], "row {r}");
        let d = surface.eval(face, u, v).expect("eval");
        let want = d.p.iter().chain(&d.du).chain(&d.dv);
        for (got, want) in x[3..].iter().zip(want) {
            assert!((got - want).abs() <= 1e-12, "row {r}: {got} against {want}");
        }
        assert_eq!(x.len(), 12, "row {r}");
    }
}

/// `--threads N` is taken by every command; more than 4 per core is a usage error (a
/// request for 100 000 threads started them all).
#[test]
fn threads_on_every_command_and_bounded() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    for args in [
        &["info", "cube.obj", "--threads", "1"][..],
        &["subdivide", "cube.obj", "-o", "out.obj", "--threads", "2"],
        &[
            "--threads",
            "1",
            "limit",
            "cube.obj",
            "--grid",
            "2",
            "-o",
            "out.tsv",
        ],
        &[
            "bench",
            "cube.obj",
            "-l",
            "1",
            "--reps",
            "1",
            "--threads",
            "1",
        ],
    ] {
        assert_code(&run_in(dir.path(), args), 0);
    }
    let o = run_in(dir.path(), &["info", "cube.obj", "--threads", "100000"]);
    assert_code(&o, 2);
    assert!(
        stderr(&o).contains("more than 4 per core"),
        "{}",
        stderr(&o)
    );
}

// ---------------------------------------------------------------------------------------
// Output names

/// An output extension no writer of the command knows is a usage error (exit 2) naming
/// the extensions the command writes, and nothing is written.
#[test]
fn unknown_output_extensions_are_usage_errors() {
    let patches = include_str!("../../../../examples/patches/blend3.json");
    let dir = dir_with(&[("cube.obj", CUBE), ("p.json", patches)]);
    for (args, writes) in [
        (&["subdivide", "cube.obj"][..], ".obj"),
        (&["limit", "cube.obj"], ".txt, .tsv or .dat"),
        (
            &["tessellate", "cube.obj", "--rate", "2"],
            ".obj, .ply, .stl or .glb",
        ),
        (&["render", "cube.obj"], ".png"),
        (&["spline", "cube.obj"], ".obj, .ply, .stl or .glb"),
        (
            &["g2", "cube.obj"],
            ".obj, .ply, .stl, .glb, .json, .igs, .iges or .png",
        ),
        (&["nurbs", "p.json"], ".json or .obj"),
        (&["blend", "p.json"], ".obj"),
    ] {
        let mut args = args.to_vec();
        args.extend(["-o", "out.fbx"]);
        let o = run_in(dir.path(), &args);
        assert_code(&o, 2);
        let err = stderr(&o);
        assert!(
            err.contains("'.fbx' is not a format this command writes")
                && err.contains(&format!("it writes {writes}")),
            "{args:?}: {err}"
        );
        assert_eq!(listing(dir.path()), ["cube.obj", "p.json"], "{args:?}");
    }
    let o = run_in(dir.path(), &["regularity", "cube.obj", "--plot", "r.pdf"]);
    assert_code(&o, 2);
    // Any case; a name without an extension is the command's first format.
    let o = run_in(dir.path(), &["subdivide", "cube.obj", "-o", "OUT.OBJ"]);
    assert_code(&o, 0);
    let o = run_in(dir.path(), &["subdivide", "cube.obj", "-o", "plain"]);
    assert_code(&o, 0);
    assert!(fs::read_to_string(dir.path().join("plain"))
        .unwrap()
        .contains("\nf "));
}

/// No output may be an input or another output, however the paths are spelt.
#[test]
fn outputs_never_replace_inputs_or_each_other() {
    let patches = include_str!("../../../../examples/patches/blend3.json");
    let dir = dir_with(&[("cube.obj", CUBE), ("p.json", patches)]);
    fs::create_dir(dir.path().join("sub")).unwrap();
    for args in [
        &["subdivide", "cube.obj", "-o", "sub/../cube.obj"][..],
        &["tessellate", "cube.obj", "--rate", "2", "-o", "./cube.obj"],
        &["nurbs", "p.json", "-o", "p.json"],
        &[
            "blend",
            "p.json",
            "-o",
            "b.obj",
            "--control-mesh",
            "./b.obj",
        ],
        &["interpolate", "p.json", "-o", "h.obj", "--host", "h.obj"],
    ] {
        let o = run_in(dir.path(), args);
        assert_code(&o, 2);
        let err = stderr(&o);
        assert!(
            err.contains("would replace the input") || err.contains("would replace the other"),
            "{args:?}: {err}"
        );
        assert_eq!(
            listing(dir.path()),
            ["cube.obj", "p.json", "sub"],
            "{args:?}"
        );
        assert_eq!(
            fs::read_to_string(dir.path().join("cube.obj")).unwrap(),
            CUBE
        );
    }
}

/// `subsurf ... -o - | head`: a reader that goes away is not a failure (exit 0, nothing on
/// stderr), for every command that writes to standard output, pictures included.
#[test]
fn a_closed_pipe_on_standard_output_exits_zero() {
    use std::process::{Command, Stdio};
    let dir = dir_with(&[("cube.obj", CUBE)]);
    for args in [
        &["subdivide", "cube.obj", "-l", "2", "-o", "-"][..],
        &["limit", "cube.obj", "--grid", "8", "-o", "-"],
        &["tessellate", "cube.obj", "--rate", "8", "-o", "-"],
        // A picture larger than the output buffer: the encoder meets the closed pipe.
        &[
            "render", "cube.obj", "--zebra", "--size", "1200x900", "-o", "-",
        ],
        &["g2", "cube.obj", "-o", "-"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_subsurf"))
            .current_dir(dir.path())
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("cannot run subsurf");
        // Close the reading end before anything is written.
        drop(child.stdout.take());
        let o = child.wait_with_output().expect("subsurf did not finish");
        assert_code(&o, 0);
        assert_eq!(stderr(&o), "", "{args:?}");
    }
}

/// A full disk on standard output is an error (exit 1, a message on stderr), never a
/// panic, for every command that prints, and a full standard error does not panic either.
#[cfg(target_os = "linux")]
#[test]
fn a_full_standard_output_is_an_error_not_a_panic() {
    use std::process::{Command, Stdio};
    let patches = include_str!("../../../../examples/patches/blend3.json");
    let dir = dir_with(&[("cube.obj", CUBE), ("p.json", patches)]);
    let full = || {
        fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .expect("/dev/full")
    };
    for args in [
        &["info", "cube.obj"][..],
        &["info", "cube.obj", "--json"],
        &["bench", "cube.obj", "-l", "1", "--reps", "1"],
        &["nurbs", "p.json"],
        &["spline", "cube.obj", "-o", "s.obj", "--report"],
        &["g2", "cube.obj", "-o", "g.obj", "--report"],
        &["regularity", "cube.obj"],
        &["subdivide", "cube.obj", "-o", "-"],
        &["limit", "cube.obj", "--grid", "2", "-o", "-"],
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_subsurf"))
            .current_dir(dir.path())
            .args(args)
            .stdin(Stdio::null())
            .stdout(full())
            .output()
            .expect("cannot run subsurf");
        let err = stderr(&o);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_code(&o, 1);
        assert!(err.contains("No space left on device"), "{args:?}: {err}");
    }
    // An error to a full standard error: still exit 1, not a panic (exit 101).
    let o = Command::new(env!("CARGO_BIN_EXE_subsurf"))
        .current_dir(dir.path())
        .args(["subdivide", "missing.obj", "-o", "x.obj"])
        .stdin(Stdio::null())
        .stderr(full())
        .output()
        .expect("cannot run subsurf");
    assert_code(&o, 1);
}
