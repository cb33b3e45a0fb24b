//! End-to-end tests of the shape-adjustable scheme's flags: `subdivide --scheme adjustable
//! --c C [--adjust-steps K]`, and `--c`/`--adjust-steps` on `tessellate` and `render`.

use crate::common;
use common::*;

use std::fs;
use std::path::Path;

/// The `v` lines of an OBJ file, parsed.
fn vertices(path: &Path) -> Vec<[f64; 3]> {
    positions(&fs::read_to_string(path).expect("output written"))
}

fn max_diff(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .flat_map(|(p, q)| (0..3).map(move |k| (p[k] - q[k]).abs()))
        .fold(0.0, f64::max)
}

#[test]
fn one_half_is_catmull_clark() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["subdivide", "cube.obj", "-o", "cc.obj", "-l", "3"],
    );
    assert_code(&o, 0);
    let o = run_in(
        dir.path(),
        &[
            "subdivide",
            "cube.obj",
            "-o",
            "half.obj",
            "-l",
            "3",
            "--scheme",
            "adjustable",
            "--c",
            "0.5",
        ],
    );
    assert_code(&o, 0);
    let (cc, half) = (
        vertices(&dir.path().join("cc.obj")),
        vertices(&dir.path().join("half.obj")),
    );
    assert_eq!(cc.len(), 386);
    assert!(max_diff(&cc, &half) < 1e-12);
    // The header records the command line that reproduces the output.
    let text = fs::read_to_string(dir.path().join("half.obj")).unwrap();
    assert!(
        text.contains("--scheme adjustable --c 0.5 cube.obj"),
        "{text:.300}"
    );
    // The explicit default scheme is accepted too.
    let o = run_in(
        dir.path(),
        &[
            "subdivide",
            "cube.obj",
            "-o",
            "cc2.obj",
            "-l",
            "3",
            "--scheme",
            "catmull-clark",
        ],
    );
    assert_code(&o, 0);
    assert_eq!(
        fs::read(dir.path().join("cc.obj")).unwrap(),
        fs::read(dir.path().join("cc2.obj")).unwrap()
    );
}

#[test]
fn zero_keeps_the_control_points_and_c_changes_the_shape() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let input = vertices(&dir.path().join("cube.obj"));
    let run = |c: &str, out: &str, extra: &[&str]| {
        let mut args = vec!["subdivide", "cube.obj", "-o", out, "-l", "2", "--scheme"];
        args.extend(["adjustable", "--c", c]);
        args.extend(extra);
        assert_code(&run_in(dir.path(), &args), 0);
        vertices(&dir.path().join(out))
    };
    let zero = run("0", "zero.obj", &[]);
    assert_eq!(&zero[..8], &input[..], "c = 0 moved a control point");
    // Larger c moves the cube's corners further in (Catmull-Clark: c = 0.5).
    let r = |p: &[[f64; 3]]| p[0].iter().map(|x| x * x).sum::<f64>().sqrt();
    let (low, high) = (run("0.2", "low.obj", &[]), run("0.9", "high.obj", &[]));
    assert!(
        r(&input) > r(&low) && r(&low) > r(&high),
        "{} {} {}",
        r(&input),
        r(&low),
        r(&high)
    );
    // Mixed: one adjustable step, then Catmull-Clark: neither of the two pure schemes.
    let mixed = run("0.2", "mixed.obj", &["--adjust-steps", "1"]);
    let text = fs::read_to_string(dir.path().join("mixed.obj")).unwrap();
    assert!(text.contains("--c 0.2 --adjust-steps 1 cube.obj"));
    assert!(max_diff(&mixed, &low) > 1e-3);
}

#[test]
fn bad_parameters_are_usage_errors() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    for (args, msg) in [
        (&["--scheme", "adjustable", "--c", "1.5"][..], "[0, 1]"),
        (&["--scheme", "adjustable", "--c", "-0.1"][..], "[0, 1]"),
        (&["--scheme", "adjustable", "--c", "nan"][..], "[0, 1]"),
        (&["--scheme", "adjustable"][..], "--c"),
        (&["--c", "0.3"][..], "--scheme adjustable"),
        (
            &["--scheme", "catmull-clark", "--c", "0.3"][..],
            "--scheme adjustable",
        ),
        (
            &["--scheme", "adjustable", "--adjust-steps", "1"][..],
            "--c",
        ),
        (
            &["--scheme", "loop", "--c", "0.3"][..],
            "--scheme adjustable",
        ),
        (&["--scheme", "doo-sabin", "--c", "0.3"][..], "doo-sabin"),
    ] {
        let mut all = vec!["subdivide", "cube.obj", "-o", "out.obj"];
        all.extend(args);
        let o = run_in(dir.path(), &all);
        assert_code(&o, 2);
        assert!(stderr(&o).contains(msg), "{args:?}: {}", stderr(&o));
        assert!(!dir.path().join("out.obj").exists());
    }
    let o = run_in(
        dir.path(),
        &[
            "render", "cube.obj", "-o", "x.png", "--c", "0.3", "--level", "1",
        ],
    );
    assert_code(&o, 2);
    let o = run_in(
        dir.path(),
        &[
            "tessellate",
            "cube.obj",
            "-o",
            "x.obj",
            "--rate",
            "2",
            "--c",
            "2",
        ],
    );
    assert_code(&o, 2);
}

#[test]
fn tessellate_and_render_draw_the_mixed_surface() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let tess = |out: &str, extra: &[&str]| {
        let mut args = vec!["tessellate", "cube.obj", "-o", out, "--rate", "8"];
        args.extend(extra);
        assert_code(&run_in(dir.path(), &args), 0);
        vertices(&dir.path().join(out))
    };
    let cc = tess("cc.obj", &[]);
    // c = ½ with two adjustable steps: the same surface, sampled at the same points
    // (numbered differently).
    let half = tess("half.obj", &["--c", "0.5", "--adjust-steps", "2"]);
    assert_eq!(cc.len(), half.len());
    let bbox = |p: &[[f64; 3]]| {
        p.iter().fold([f64::MAX, f64::MIN], |b, q| {
            [b[0].min(q[0]), b[1].max(q[0])]
        })
    };
    let (a, b) = (bbox(&cc), bbox(&half));
    assert!((a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12);
    // c = 0.1 stays closer to the cube (corner at ±1) than Catmull-Clark.
    let tight = tess("tight.obj", &["--c", "0.1"]);
    assert!(bbox(&tight)[1] > bbox(&cc)[1] + 0.01);

    let o = run_in(
        dir.path(),
        &[
            "render", "cube.obj", "-o", "r.png", "--size", "64x48", "--c", "0.1", "--zebra",
        ],
    );
    assert_code(&o, 0);
    let png = fs::read(dir.path().join("r.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
}
