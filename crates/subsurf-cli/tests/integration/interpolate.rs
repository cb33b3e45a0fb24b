//! End-to-end tests of `subsurf interpolate`, each in its own temporary directory.

use crate::common;
use common::*;

use std::fs;

const VASE: &str = include_str!("../../../../examples/curves/vase.json");
const DOLPHIN: &str = include_str!("../../../../examples/curves/dolphin.json");

/// `v` lines of the mesh (before `g curves`) and of the curves, and the `l` lines.
fn parse(text: &str) -> (Vec<[f64; 3]>, Vec<[f64; 3]>, usize, usize) {
    let (mut mesh, mut curves, mut faces, mut lines) = (Vec::new(), Vec::new(), 0, 0);
    let mut in_curves = false;
    for l in text.lines() {
        let mut t = l.split_whitespace();
        match t.next() {
            Some("g") => in_curves = t.next() == Some("curves"),
            Some("v") => {
                let p: Vec<f64> = t.map(|x| x.parse().unwrap()).collect();
                let p = [p[0], p[1], p[2]];
                if in_curves {
                    curves.push(p)
                } else {
                    mesh.push(p)
                }
            }
            Some("f") => faces += 1,
            Some("l") => lines += 1,
            _ => {}
        }
    }
    (mesh, curves, faces, lines)
}

fn dist(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[test]
fn vase_control_mesh_has_interval_tags_and_the_curves_as_polylines() {
    let dir = dir_with(&[("vase.json", VASE)]);
    let o = run_in(dir.path(), &["interpolate", "vase.json", "-o", "vase.obj"]);
    assert_code(&o, 0);
    let text = fs::read_to_string(dir.path().join("vase.obj")).unwrap();
    let (_, curves, faces, lines) = parse(&text);
    // 4 profiles × 10 edges × 2 + 2 sections × 16 edges × 2 − 8 shared groups × 4 quads.
    assert_eq!(faces, 80 + 64 - 32);
    assert_eq!(lines, 6);
    assert!(!curves.is_empty());
    assert!(text.contains("\nt interval 2/1/0 "), "no interval tags");
    // The control mesh reads back and refines (it is a valid tagged OBJ).
    let o = run_in(dir.path(), &["info", "vase.obj"]);
    assert_code(&o, 0);
}

#[test]
fn tessellated_limit_surface_passes_through_the_curves() {
    // At level 2 the middle polygons' limit points sit at every quarter of each (uniform)
    // knot span, which is where 4 samples per span put the polyline's vertices: every curve
    // sample must be a vertex of the limit surface.
    for (name, text) in [("vase.json", VASE), ("dolphin.json", DOLPHIN)] {
        let dir = dir_with(&[(name, text)]);
        let o = run_in(
            dir.path(),
            &[
                "interpolate",
                name,
                "-o",
                "out.obj",
                "--levels",
                "2",
                "--tessellate",
                "--curve-samples",
                "4",
            ],
        );
        assert_code(&o, 0);
        let out = fs::read_to_string(dir.path().join("out.obj")).unwrap();
        let (mesh, curves, _, _) = parse(&out);
        let mut worst = 0.0f64;
        for p in &curves {
            let d = mesh
                .iter()
                .map(|q| dist(p, q))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
        // Sizes are about 10; the limit points are exact to rounding.
        assert!(
            worst < 1e-9,
            "{name}: a curve sample is {worst:e} from the surface"
        );
    }
}

#[test]
fn writes_to_standard_output() {
    let dir = dir_with(&[("d.json", DOLPHIN)]);
    let o = run_in(
        dir.path(),
        &[
            "interpolate",
            "d.json",
            "-o",
            "-",
            "--curve-samples",
            "0",
            "--width",
            "0.08",
        ],
    );
    assert_code(&o, 0);
    let (_, curves, faces, lines) = parse(&stdout(&o));
    assert_eq!((curves.len(), lines), (0, 0));
    // Silhouette 24 edges, sections 3 × 8, both sides; 6 groups of 4 shared quads.
    assert_eq!(faces, 2 * 24 + 2 * 24 - 24);
}

const QUADRATIC: &str = r#"{"type": "bspline-curve", "degree": 2, "knots": [0, 0, 0, 1, 2, 2, 2],
 "points": [[0, 0, 0], [1, 1, 0], [2, 0, 0], [3, 1, 0]]}"#;

#[test]
fn a_quadratic_curve_is_refused_naming_it() {
    let dir = dir_with(&[("q.json", QUADRATIC)]);
    let o = run_in(dir.path(), &["interpolate", "q.json", "-o", "out.obj"]);
    assert_code(&o, 1);
    let e = stderr(&o);
    assert!(e.contains("q.json[0]") && e.contains("degree 2"), "{e}");
    assert!(!dir.path().join("out.obj").exists());
}

#[test]
fn three_curves_through_one_point_are_refused() {
    let line = |a: [f64; 3]| {
        format!(
            r#"{{"type": "bspline-curve", "degree": 3, "knots": [0, 0, 0, 0, 1, 2, 2, 2, 2], "points": [[{}, {}, {}], [{}, {}, {}], [0, 0, 0], [{}, {}, {}], [{}, {}, {}]]}}"#,
            -2.0 * a[0],
            -2.0 * a[1],
            -2.0 * a[2],
            -a[0],
            -a[1],
            -a[2],
            a[0],
            a[1],
            a[2],
            2.0 * a[0],
            2.0 * a[1],
            2.0 * a[2]
        )
    };
    let text = format!(
        "[{}, {}, {}]",
        line([1.0, 0.0, 0.0]),
        line([0.0, 1.0, 0.0]),
        line([1.0, 1.0, 0.3])
    );
    let dir = dir_with(&[("star.json", &text)]);
    let o = run_in(dir.path(), &["interpolate", "star.json", "-o", "out.obj"]);
    assert_code(&o, 1);
    let e = stderr(&o);
    assert!(
        e.contains("6 curve branches meet at (0, 0, 0)") && e.contains("star.json[2] point 2"),
        "{e}"
    );
}

#[test]
fn bad_width_and_side_are_refused() {
    let dir = dir_with(&[("v.json", VASE)]);
    let o = run_in(
        dir.path(),
        &["interpolate", "v.json", "-o", "out.obj", "--width", "-1"],
    );
    assert_code(&o, 1);
    assert!(stderr(&o).contains("width"), "{}", stderr(&o));
    let o = run_in(
        dir.path(),
        &["interpolate", "v.json", "-o", "out.obj", "--side", "0,0"],
    );
    assert_code(&o, 2);
    let o = run_in(
        dir.path(),
        &["interpolate", "v.json", "-o", "out.obj", "--side", "0,0,0"],
    );
    assert_code(&o, 1);
    assert!(!dir.path().join("out.obj").exists());
}

#[test]
fn refining_beyond_the_memory_limit_is_refused_up_front() {
    let dir = dir_with(&[("vase.json", VASE)]);
    for (input, name) in [("vase.json", "vase.json"), ("-", "<stdin>")] {
        let args = [
            "interpolate",
            input,
            "-o",
            "out.obj",
            "--levels",
            "8",
            "--tessellate",
            "--max-memory",
            "64M",
        ];
        let o = if input == "-" {
            run_with_stdin(dir.path(), &args, VASE)
        } else {
            run_in(dir.path(), &args)
        };
        assert_code(&o, 1);
        let e = stderr(&o);
        assert!(
            e.contains(&format!(
                "{name}: refining the zones to level 8 and moving them to the limit needs about "
            )) && e.contains(
                "MiB, more than the limit of 64 MiB (--max-memory); use a lower --levels"
            ),
            "{e}"
        );
        assert!(!dir.path().join("out.obj").exists());
    }
    let o = run_in(
        dir.path(),
        &[
            "interpolate",
            "vase.json",
            "-o",
            "out.obj",
            "--levels",
            "1",
            "--max-memory",
            "64M",
        ],
    );
    assert_code(&o, 0);
}

#[test]
fn curve_errors_on_standard_input_name_stdin() {
    let dir = dir_with(&[]);
    let o = run_with_stdin(
        dir.path(),
        &["interpolate", "-", "-o", "out.obj"],
        QUADRATIC,
    );
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("<stdin>[0]: degree 2"),
        "{}",
        stderr(&o)
    );
}
