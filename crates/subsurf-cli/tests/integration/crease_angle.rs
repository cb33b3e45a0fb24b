//! End-to-end tests of `subsurf subdivide --crease-angle DEG [--sharpness S]`.

use crate::common;
use common::*;

use std::fs;

/// The cube's corners, as in `examples/meshes/cube.obj` (vertices 0..8).
const CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// Runs `subsurf subdivide cube.obj -o out.obj <extra>` on `input`, expecting success, and
/// returns the output file's text.
fn subdivide(input: &str, extra: &[&str]) -> String {
    let dir = dir_with(&[("cube.obj", input)]);
    let mut args = vec!["subdivide", "cube.obj", "-o", "out.obj"];
    args.extend_from_slice(extra);
    let o = run_in(dir.path(), &args);
    assert_code(&o, 0);
    assert!(
        o.stdout.is_empty(),
        "unexpected stdout: {}",
        String::from_utf8_lossy(&o.stdout)
    );
    fs::read_to_string(dir.path().join("out.obj")).expect("output written")
}

#[test]
fn creased_cube_keeps_its_corners() {
    let out = subdivide(CUBE, &["-l", "2", "--crease-angle", "60"]);
    let p = positions(&out);
    assert_eq!(p.len(), 98, "a cube at level 2 has 98 vertices");
    // Three infinitely sharp edges at each corner: the corner rule keeps it in place.
    for c in CORNERS {
        assert!(p.contains(&c), "corner {c:?} moved:\n{out}");
    }
    // Every vertex stays on the cube's surface: edges are straight, faces flat.
    for v in &p {
        assert!(v.iter().all(|x| x.abs() <= 1.0), "{v:?}");
        assert!(v.iter().any(|x| x.abs() == 1.0), "{v:?} is off the surface");
    }
    assert!(
        out.contains("--crease-angle 60 --sharpness 10"),
        "the header comment records the flags:\n{out}"
    );
}

#[test]
fn smooth_cube_moves_its_corners() {
    // Without the flag (or with a threshold above 90°) the cube is rounded.
    for extra in [&["-l", "2"][..], &["-l", "2", "--crease-angle", "100"]] {
        let p = positions(&subdivide(CUBE, extra));
        assert_eq!(p.len(), 98);
        assert!(CORNERS.iter().all(|c| !p.contains(c)), "{extra:?}");
    }
    let plain = positions(&subdivide(CUBE, &["-l", "2"]));
    let high = positions(&subdivide(CUBE, &["-l", "2", "--crease-angle", "100"]));
    assert_eq!(plain, high);
}

#[test]
fn sharpness_sets_the_crease_value() {
    // Semi-sharp creases (sharpness 1) decay after one level: the corners move, but less
    // than on the smooth cube.
    let smooth = positions(&subdivide(CUBE, &["-l", "2"]));
    let semi = positions(&subdivide(
        CUBE,
        &["-l", "2", "--crease-angle", "45", "--sharpness", "1"],
    ));
    assert!(CORNERS.iter().all(|c| !semi.contains(c)));
    // Output vertex 0 is the child of corner 0 (vertex children come first).
    let dist = |p: [f64; 3]| {
        (0..3)
            .map(|k| (p[k] - CORNERS[0][k]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    assert!(
        dist(semi[0]) < dist(smooth[0]),
        "{:?} {:?}",
        semi[0],
        smooth[0]
    );
    // Sharpness 0: creases that do nothing.
    let zero = positions(&subdivide(
        CUBE,
        &["-l", "2", "--crease-angle", "45", "--sharpness", "0"],
    ));
    assert_eq!(zero, smooth);
}

#[test]
fn file_creases_override_automatic_ones() {
    // An explicit smooth crease on edge 0–1 (0-based) wins over the automatic one: corners
    // 0 and 1 keep only two sharp edges, so the crease rule moves them; the other six keep
    // three and stay put.
    let input = format!("{CUBE}t crease 2/1/0 0 1 0\n");
    let p = positions(&subdivide(&input, &["-l", "2", "--crease-angle", "60"]));
    for (i, c) in CORNERS.iter().enumerate() {
        assert_eq!(p.contains(c), i >= 2, "corner {i} at {c:?}");
    }
}

#[test]
fn sharpness_without_crease_angle_is_a_usage_error() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["subdivide", "cube.obj", "-o", "out.obj", "--sharpness", "3"],
    );
    assert_code(&o, 2);
    assert!(stderr(&o).contains("--crease-angle"), "{}", stderr(&o));
    assert!(!dir.path().join("out.obj").exists());
}

#[test]
fn out_of_range_values_are_usage_errors() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    for (flags, needle) in [
        (&["--crease-angle", "200"][..], "between 0 and 180"),
        (&["--crease-angle", "-5"], "between 0 and 180"),
        (&["--crease-angle", "nan"], "between 0 and 180"),
        (&["--crease-angle", "steep"], "between 0 and 180"),
        (&["--crease-angle", "30", "--sharpness", "-1"], "sharpness"),
        (&["--crease-angle", "30", "--sharpness", "inf"], "sharpness"),
    ] {
        let mut args = vec!["subdivide", "cube.obj", "-o", "out.obj"];
        args.extend_from_slice(flags);
        let o = run_in(dir.path(), &args);
        assert_code(&o, 2);
        let err = stderr(&o);
        assert!(err.contains(needle), "{flags:?}: {err}");
        assert!(!dir.path().join("out.obj").exists());
    }
}
