//! End-to-end tests of `subsurf interpolate --host`, each in its own temporary directory.

use crate::common;
use common::*;

use std::fs;

const HOST: &str = include_str!("../../examples/host-grid.obj");
const CURVE: &str = include_str!("../../examples/host-curve.json");

fn count(text: &str, prefix: &str) -> usize {
    text.lines().filter(|l| l.starts_with(prefix)).count()
}

#[test]
fn curve_is_embedded_in_the_bundled_host_and_the_result_refines_with_nurss() {
    let dir = dir_with(&[("host.obj", HOST), ("curve.json", CURVE)]);
    let o = run_in(
        dir.path(),
        &[
            "interpolate",
            "curve.json",
            "--host",
            "host.obj",
            "-o",
            "embedded.obj",
            "--curve-samples",
            "0",
        ],
    );
    assert_code(&o, 0);
    let text = fs::read_to_string(dir.path().join("embedded.obj")).unwrap();
    // The 10 × 8 grid (99 vertices, 80 quads) cut along 9 control points: 18 new vertices,
    // 2 zone faces on each of the 8 polygon edges and the 2 phantom host edges.
    assert_eq!(count(&text, "v "), 99 + 18);
    assert_eq!(count(&text, "f "), 80 + 20);
    assert!(count(&text, "t interval ") > 0);
    // The control mesh is a valid tagged OBJ that `subdivide` refines with NURSS.
    let o = run_in(
        dir.path(),
        &[
            "subdivide",
            "embedded.obj",
            "-o",
            "refined.obj",
            "--levels",
            "2",
        ],
    );
    assert_code(&o, 0);
    let refined = fs::read_to_string(dir.path().join("refined.obj")).unwrap();
    // 96 quads × 16 and the 4 phantom-edge triangles × 12 (3 quads, then 4 each).
    assert_eq!(count(&refined, "f "), 16 * 96 + 12 * 4);
}

#[test]
fn control_point_off_the_host_fails_with_exit_1_naming_it() {
    let moved = CURVE.replacen("[3.0, 4.0, ", "[3.0, 4.25, ", 1);
    assert_ne!(moved, CURVE);
    let dir = dir_with(&[("host.obj", HOST), ("curve.json", &moved)]);
    let o = run_in(
        dir.path(),
        &[
            "interpolate",
            "curve.json",
            "--host",
            "host.obj",
            "-o",
            "out.obj",
        ],
    );
    assert_code(&o, 1);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("control point 2"), "{err}");
    assert!(err.contains("no host vertex"), "{err}");
    assert!(!dir.path().join("out.obj").exists(), "no partial output");
}

#[test]
fn side_vector_with_a_host_is_a_usage_error() {
    let dir = dir_with(&[("host.obj", HOST), ("curve.json", CURVE)]);
    let o = run_in(
        dir.path(),
        &[
            "interpolate",
            "curve.json",
            "--host",
            "host.obj",
            "--side",
            "0,0,1",
            "-o",
            "out.obj",
        ],
    );
    assert_code(&o, 2);
}
