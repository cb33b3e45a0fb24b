//! End-to-end tests of `subsurf spline`, each in its own temporary directory.

use crate::common;
use common::*;

use std::fs;

/// The cube at rate 3: 6 × 9 quads on 6 · 9 + 2 shared vertices (closed, watertight).
#[test]
fn writes_a_watertight_obj_with_normals() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["spline", "cube.obj", "-o", "out.obj", "--rate", "3"],
    );
    assert_code(&o, 0);
    let text = fs::read_to_string(dir.path().join("out.obj")).unwrap();
    assert_eq!(count_records(&text, "v"), 56);
    assert_eq!(count_records(&text, "vn"), 56);
    assert_eq!(count_records(&text, "f"), 54);
    assert!(text.contains("# subsurf spline --rate 3"), "{text}");
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));
}

#[test]
fn non_quad_input_is_subdivided_once_and_says_so() {
    let dir = dir_with(&[("hut.obj", HUT)]);
    let o = run_in(
        dir.path(),
        &["spline", "hut.obj", "-o", "hut.ply", "--rate", "2"],
    );
    assert_code(&o, 0);
    assert!(
        stderr(&o).contains("one Catmull-Clark step"),
        "{}",
        stderr(&o)
    );
    let bytes = fs::read(dir.path().join("hut.ply")).unwrap();
    assert!(bytes.starts_with(b"ply\nformat binary_little_endian 1.0\n"));
}

#[test]
fn open_meshes_leave_out_faces_at_the_boundary() {
    let dir = dir_with(&[("grid.obj", GRID)]);
    let o = run_in(
        dir.path(),
        &["spline", "grid.obj", "-o", "g.obj", "--rate", "2"],
    );
    assert_code(&o, 0);
    // 4 × 4 faces, only the 2 × 2 inner ones have all corners interior.
    assert!(
        stderr(&o).contains("12 of 16 faces have no surface"),
        "{}",
        stderr(&o)
    );
    let text = fs::read_to_string(dir.path().join("g.obj")).unwrap();
    assert_eq!(count_records(&text, "f"), 4 * 4);
}

#[test]
fn colour_faces_writes_vertex_colours_in_obj_and_face_colours_in_ply() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &[
            "spline",
            "cube.obj",
            "-o",
            "c.obj",
            "--rate",
            "2",
            "--colour-faces",
        ],
    );
    assert_code(&o, 0);
    let text = fs::read_to_string(dir.path().join("c.obj")).unwrap();
    // Each patch has its own 3 × 3 vertices, each `v x y z r g b`.
    assert_eq!(count_records(&text, "v"), 6 * 9);
    assert!(text
        .lines()
        .filter(|l| l.starts_with("v "))
        .all(|l| l.split_whitespace().count() == 7));
    // Neighbouring patches differ: more than one colour.
    let colours: std::collections::HashSet<String> = text
        .lines()
        .filter(|l| l.starts_with("v "))
        .map(|l| l.split_whitespace().skip(4).collect::<Vec<_>>().join(" "))
        .collect();
    assert!(colours.len() >= 3, "{colours:?}");
    let o = run_in(
        dir.path(),
        &[
            "spline",
            "cube.obj",
            "-o",
            "c.ply",
            "--rate",
            "2",
            "--color-faces",
        ],
    );
    assert_code(&o, 0);
    let bytes = fs::read(dir.path().join("c.ply")).unwrap();
    let header = String::from_utf8_lossy(&bytes[..400]);
    assert!(
        header.contains(
            "element face 24\nproperty list uchar int vertex_indices\nproperty uchar red"
        ),
        "{header}"
    );
}

#[test]
fn basis_exports_one_basis_function_as_a_scalar() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &[
            "spline", "cube.obj", "-o", "b.ply", "--rate", "4", "--basis", "0",
        ],
    );
    assert_code(&o, 0);
    let bytes = fs::read(dir.path().join("b.ply")).unwrap();
    let end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let header = String::from_utf8_lossy(&bytes[..end]);
    assert!(header.contains("property double basis"), "{header}");
    // Vertex record: 6 doubles, 3 colour bytes, the scalar; cube rate 4: 98 vertices.
    let rec = 6 * 8 + 3 + 8;
    let mut max: f64 = 0.0;
    for i in 0..98 {
        let at = end + i * rec + 51;
        let x = f64::from_le_bytes(bytes[at..at + 8].try_into().unwrap());
        assert!((0.0..=1.0).contains(&x), "{x}");
        max = max.max(x);
    }
    // At its own corner the cube's vertex weighs most but is not interpolated.
    assert!(max > 0.2 && max < 1.0, "{max}");
    let o = run_in(
        dir.path(),
        &["spline", "cube.obj", "-o", "b.obj", "--basis", "8"],
    );
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("only 8 control points"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.path().join("b.obj").exists());
}

#[test]
fn report_prints_distance_and_normal_jumps() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &[
            "spline", "cube.obj", "-o", "r.obj", "--rate", "4", "--report",
        ],
    );
    assert_code(&o, 0);
    let out = stdout(&o);
    assert!(out.contains("distance at equal parameters: max"), "{out}");
    assert!(
        out.contains("normal jumps across edges at irregular vertices (12 edges)"),
        "{out}"
    );
}

#[test]
fn bad_usage_and_inputs_fail_cleanly() {
    let dir = dir_with(&[("cube.obj", CUBE), ("bad.obj", "v 0 0 0\nf 1 2 3\n")]);
    let o = run_in(
        dir.path(),
        &["spline", "cube.obj", "-o", "x.stl", "--colour-faces"],
    );
    assert_code(&o, 1);
    assert!(stderr(&o).contains("STL has no colours"));
    let o = run_in(
        dir.path(),
        &["spline", "cube.obj", "-o", "x.obj", "--rate", "0"],
    );
    assert_code(&o, 2);
    let o = run_in(
        dir.path(),
        &[
            "spline",
            "cube.obj",
            "-o",
            "x.obj",
            "--colour-faces",
            "--basis",
            "1",
        ],
    );
    assert_code(&o, 2);
    let o = run_in(dir.path(), &["spline", "cube.obj", "-o", "-", "--report"]);
    assert_code(&o, 1);
    let o = run_in(dir.path(), &["spline", "bad.obj", "-o", "x.obj"]);
    assert_code(&o, 1);
    assert!(stderr(&o).contains("bad.obj"), "{}", stderr(&o));
    assert_eq!(listing(dir.path()), ["bad.obj", "cube.obj"]);
}

#[test]
fn stl_output_has_two_triangles_per_quad() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["spline", "cube.obj", "-o", "c.stl", "--rate", "2"],
    );
    assert_code(&o, 0);
    let bytes = fs::read(dir.path().join("c.stl")).unwrap();
    assert_eq!(bytes.len(), 84 + 50 * 2 * 24);
}

#[test]
fn tags_are_ignored_with_a_note() {
    let creased = format!("{CUBE}\nt crease 2/1/0 1 2 10\n");
    let dir = dir_with(&[("c.obj", &creased)]);
    let o = run_in(
        dir.path(),
        &["spline", "c.obj", "-o", "c.obj.out.obj", "--rate", "1"],
    );
    assert_code(&o, 0);
    assert!(stderr(&o).contains("tags are ignored"), "{}", stderr(&o));
    let o = run_in(
        dir.path(),
        &["spline", "c.obj", "-o", "q.obj", "--rate", "1", "-q"],
    );
    assert_code(&o, 0);
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));
}

/// A closed quad mesh with two poles of valence `n`: pole, a ring of `2n` points joined to
/// it by `n` quads, a second ring, the other pole.
fn two_poles(n: usize) -> String {
    let mut text = String::from("v 0 0 1\n");
    for ring in [0.7, -0.7] {
        for j in 0..2 * n {
            let a = std::f64::consts::PI * j as f64 / n as f64;
            text += &format!("v {} {} {ring}\n", 0.5 * a.cos(), 0.5 * a.sin());
        }
    }
    text += "v 0 0 -1\n";
    let a = |j: usize| 2 + j % (2 * n);
    let b = |j: usize| 2 + 2 * n + j % (2 * n);
    let q = 4 * n + 2;
    for i in 0..n {
        text += &format!("f 1 {} {} {}\n", a(2 * i), a(2 * i + 1), a(2 * i + 2));
        text += &format!("f {q} {} {} {}\n", b(2 * i + 2), b(2 * i + 1), b(2 * i));
    }
    for j in 0..2 * n {
        text += &format!("f {} {} {} {}\n", a(j), b(j), b(j + 1), a(j + 1));
    }
    text
}

/// The rate and the poles' valence size the job: both are refused up front when the
/// estimate exceeds --max-memory (exit 1, nothing written), in the form of `tessellate`.
#[test]
fn large_rates_and_poles_are_refused_up_front() {
    let dir = dir_with(&[("cube.obj", CUBE), ("pole.obj", &two_poles(4000))]);
    for (file, rate, limit, hint) in [
        ("cube.obj", "4096", "1G", "use a lower --rate"),
        (
            "pole.obj",
            "1",
            "512M",
            "the mesh is too large (a vertex of valence n",
        ),
    ] {
        let o = run_in(
            dir.path(),
            &[
                "spline",
                file,
                "-o",
                "out.obj",
                "--rate",
                rate,
                "--max-memory",
                limit,
            ],
        );
        assert_code(&o, 1);
        let e = stderr(&o);
        let prefix = format!("error: {file}: the spline surface at rate {rate} needs about ");
        assert!(e.starts_with(&prefix), "{e}");
        assert!(e.contains(&format!("(--max-memory); {hint}")), "{e}");
        assert!(!dir.path().join("out.obj").exists());
    }
    // Within the limit, the same jobs at a low rate run.
    let o = run_in(
        dir.path(),
        &[
            "spline",
            "cube.obj",
            "-o",
            "out.obj",
            "--rate",
            "4",
            "--max-memory",
            "64M",
        ],
    );
    assert_code(&o, 0);
}
