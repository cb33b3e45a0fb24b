//! `subsurf nurbs`: NURBS curves and surfaces from JSON or OBJ free-form files.

use crate::common;
use common::*;

const FREEFORM: &str = include_str!("../../../../examples/nurbs/freeform.obj");

#[test]
fn summary_names_every_element_with_its_line() {
    let dir = dir_with(&[("ff.obj", FREEFORM)]);
    let o = run_in(dir.path(), &["nurbs", "ff.obj"]);
    assert_code(&o, 0);
    let out = stdout(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out}");
    assert!(lines[0].starts_with("ff.obj:15 (\"profile\"): curve: degree 3, 8 control points"));
    assert!(lines[1].contains("(\"rim\"): curve: rational, degree 2, 9 control points"));
    assert!(lines[2].contains("(\"patch\"): surface: degree 3 x 3, 4 x 4 control points"));
}

#[test]
fn obj_to_json_to_obj_keeps_every_number() {
    let dir = dir_with(&[("ff.obj", FREEFORM)]);
    assert_code(&run_in(dir.path(), &["nurbs", "ff.obj", "-o", "a.json"]), 0);
    assert_code(&run_in(dir.path(), &["nurbs", "a.json", "-o", "b.obj"]), 0);
    assert_code(&run_in(dir.path(), &["nurbs", "b.obj", "-o", "c.json"]), 0);
    let a = std::fs::read_to_string(dir.path().join("a.json")).unwrap();
    let c = std::fs::read_to_string(dir.path().join("c.json")).unwrap();
    assert_eq!(a, c);
    // The JSON on standard output is the same text.
    let o = run_in(dir.path(), &["nurbs", "b.obj", "-o", "-"]);
    assert_eq!(stdout(&o), a);
}

#[test]
fn samples_are_polylines_and_quads_on_the_geometry() {
    let dir = dir_with(&[("ff.obj", FREEFORM)]);
    let o = run_in(
        dir.path(),
        &["nurbs", "ff.obj", "-o", "s.obj", "--sample", "4"],
    );
    assert_code(&o, 0);
    let text = std::fs::read_to_string(dir.path().join("s.obj")).unwrap();
    let v: Vec<[f64; 3]> = text
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let n: Vec<f64> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
            [n[0], n[1], n[2]]
        })
        .collect();
    let groups: Vec<&str> = text.lines().filter(|l| l.starts_with("g ")).collect();
    // Surfaces first, then curves, each group named after its element.
    assert_eq!(groups, ["g patch", "g profile", "g rim"]);
    // The rim is a circle of radius 1.1 at height 2.8: 4 spans x 4 segments + 1 points.
    let rim = text.lines().filter(|l| l.starts_with("l ")).nth(1).unwrap();
    let ids: Vec<usize> = rim[2..].split(' ').map(|t| t.parse().unwrap()).collect();
    assert_eq!(ids.len(), 17);
    for i in ids {
        let p = v[i - 1];
        assert!(
            ((p[0] * p[0] + p[1] * p[1]).sqrt() - 1.1).abs() < 1e-14,
            "{p:?}"
        );
        assert!((p[2] - 2.8).abs() < 1e-15);
    }
    // The Bézier patch: 4 x 4 segments.
    assert_eq!(text.lines().filter(|l| l.starts_with("f ")).count(), 16);
}

#[test]
fn bad_input_exits_one_with_the_line_and_writes_nothing() {
    let broken = FREEFORM.replace(
        "parm u 0 0 0 0 0.5 1.5 3 4 5 5 5 5",
        "parm u 0 0 0 0 0.5 1.5 3 4 5 5 5",
    );
    let dir = dir_with(&[
        ("bad.obj", &broken),
        ("bad.json", "[{\"type\": \"bspline-curve\", \"degree\": 3}]"),
    ]);
    let o = run_in(dir.path(), &["nurbs", "bad.obj", "-o", "out.json"]);
    assert_code(&o, 1);
    assert!(
        stderr(&o)
            .contains("bad.obj:15: parm u: 8 control points of degree 3 need 12 knots, got 11"),
        "{}",
        stderr(&o)
    );
    let o = run_in(dir.path(), &["nurbs", "bad.json", "-o", "out.json"]);
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("bad.json: JSON field `[0]"),
        "{}",
        stderr(&o)
    );
    let o = run_in(dir.path(), &["nurbs", "bad.json", "-o", "out.ply"]);
    assert_code(&o, 2);
    assert!(stderr(&o).contains(".json or .obj"), "{}", stderr(&o));
    assert!(!dir.path().join("out.json").exists());
    assert!(!dir.path().join("out.ply").exists());
}

#[test]
fn a_300_digit_coordinate_is_refused_naming_the_file_and_line() {
    let big = "9".repeat(300);
    let json = format!(
        "[{{\"type\": \"bspline-curve\", \"degree\": 3, \"knots\": [0, 0, 0, 0, 1, 1, 1, 1],\n \"points\": [[0, 0, 0], [1, {big}, 0], [2, 0, 0], [3, 1, 0]]}}]\n"
    );
    let obj = format!(
        "v 0 0 0\nv 1 {big} 0\nv 2 0 0\nv 3 1 0\ncstype bspline\ndeg 3\ncurv 0 1 1 2 3 4\nparm u 0 0 0 0 1 1 1 1\nend\n"
    );
    let dir = dir_with(&[("big.json", &json), ("big.obj", &obj)]);
    for (name, want) in [
        (
            "big.json",
            "big.json: JSON field `[0].points[1]`: control point 1 has the coordinate 1e300",
        ),
        ("big.obj", "big.obj:2: v: the coordinate 1e300 is too large"),
    ] {
        for args in [
            vec!["nurbs", name],
            vec!["nurbs", name, "-o", "out.obj", "--sample", "4"],
        ] {
            let o = run_in(dir.path(), &args);
            assert_code(&o, 1);
            assert!(stderr(&o).contains(want), "{}", stderr(&o));
        }
        if name.ends_with(".json") {
            assert!(stderr(&run_in(dir.path(), &["nurbs", name])).contains("(line 2, column"));
        }
    }
    // Standard input is named <stdin>.
    let o = run_with_stdin(dir.path(), &["nurbs", "-"], &obj);
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("<stdin>:2: v: the coordinate 1e300"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.path().join("out.obj").exists());
}

#[test]
fn sampling_beyond_the_memory_limit_is_refused_up_front() {
    let dir = dir_with(&[("ff.obj", FREEFORM)]);
    for input in ["ff.obj", "-"] {
        let args = [
            "nurbs",
            input,
            "-o",
            "s.obj",
            "--sample",
            "10000",
            "--max-memory",
            "64M",
        ];
        let o = if input == "-" {
            run_with_stdin(dir.path(), &args, FREEFORM)
        } else {
            run_in(dir.path(), &args)
        };
        assert_code(&o, 1);
        let name = if input == "-" { "<stdin>" } else { "ff.obj" };
        let e = stderr(&o);
        assert!(
            e.contains(&format!(
                "{name}: sampling at 10000 segments per knot span needs about "
            )) && e.contains(
                "MiB, more than the limit of 64 MiB (--max-memory); use a lower --sample"
            ),
            "{e}"
        );
        assert!(!dir.path().join("s.obj").exists());
    }
    // Within the limit it runs.
    let o = run_in(
        dir.path(),
        &[
            "nurbs",
            "ff.obj",
            "-o",
            "s.obj",
            "--sample",
            "8",
            "--max-memory",
            "64M",
        ],
    );
    assert_code(&o, 0);
}

#[test]
fn closed_curves_survive_json_to_obj_to_json() {
    let json = r#"[{"type": "bspline-curve", "degree": 3, "knots": [0, 1, 1.5, 3, 4, 4.2, 5, 6.5], "closed": true,
  "points": [[2, 0, 0], [1.2, 1, 0.3], [-0.4, 1.3, -0.3], [-1.8, 0.6, 0.3], [-1.8, -0.6, -0.3], [-0.4, -1.3, 0.3], [1.2, -1, -0.3]]},
 {"type": "bspline-surface", "degree_u": 2, "degree_v": 1, "knots_u": [0, 1, 2, 3, 4], "knots_v": [0, 0, 1, 1], "closed_u": true,
  "points": [[[0, 0, 0], [0, 0, 1]], [[1, 0, 0], [1, 0, 1]], [[1, 1, 0], [1, 1, 1]], [[0, 1, 0], [0, 1, 1]]]}]"#;
    let dir = dir_with(&[("c.json", json)]);
    assert_code(&run_in(dir.path(), &["nurbs", "c.json", "-o", "a.json"]), 0);
    assert_code(&run_in(dir.path(), &["nurbs", "a.json", "-o", "b.obj"]), 0);
    assert_code(&run_in(dir.path(), &["nurbs", "b.obj", "-o", "c2.json"]), 0);
    let a = std::fs::read_to_string(dir.path().join("a.json")).unwrap();
    let c = std::fs::read_to_string(dir.path().join("c2.json")).unwrap();
    assert!(
        a.contains("\"closed\":true") && a.contains("\"closed_u\":true"),
        "{a}"
    );
    assert_eq!(a, c);
}
