//! End-to-end tests of `subsurf repose BASE POSE... -o DIR`.

use crate::common;
use common::*;

use std::fs;

/// The bundled cube with creases (tags `t crease`).
const CUBE_CREASE: &str = include_str!("../../../../examples/meshes/cube-crease.obj");

/// `obj` with each vertex moved (a shear, a stretch and a wobble that depends on `t`):
/// every other line is kept as it is.
fn moved(obj: &str, t: f64) -> String {
    let mut i = 0;
    obj.lines()
        .map(|l| match l.strip_prefix("v ") {
            Some(rest) => {
                let c: Vec<f64> = rest
                    .split_whitespace()
                    .map(|t| t.parse().expect("coordinate"))
                    .collect();
                i += 1;
                let w = (1.3 * i as f64 + t).sin();
                format!(
                    "v {} {} {}\n",
                    c[0] + t * c[2],
                    (1.0 + t) * c[1] + 0.2 * w,
                    c[2] - 0.1 * w * w
                )
            }
            None => format!("{l}\n"),
        })
        .collect()
}

/// The `v` lines of `obj` only (a point cache).
fn points_only(obj: &str) -> String {
    obj.lines()
        .filter(|l| l.starts_with("v "))
        .map(|l| format!("{l}\n"))
        .collect()
}

/// The positions and the `f` lines of an OBJ text.
fn parse(obj: &str) -> (Vec<[f64; 3]>, Vec<&str>) {
    let faces = obj.lines().filter(|l| l.starts_with("f ")).collect();
    (positions(obj), faces)
}

/// Each refined pose is what `subsurf subdivide` writes for the pose with the base mesh's
/// tags: the same faces, the positions to rounding. The hut has a hexagon and triangles
/// (patches on rings), the cube semi-sharp creases that only the base mesh carries when
/// its poses are point caches.
#[test]
fn poses_are_what_subdivide_writes() {
    for (base, levels) in [(HUT, "3"), (CUBE_CREASE, "4"), (GRID, "2")] {
        let posed = [moved(base, 0.3), moved(base, 1.1)];
        let dir = dir_with(&[
            ("base.obj", base),
            ("a.obj", &posed[0]),
            ("b.obj", &points_only(&posed[1])),
            ("b-full.obj", &posed[1]),
        ]);
        fs::create_dir(dir.path().join("out")).expect("out dir");
        let o = run_in(
            dir.path(),
            &[
                "repose", "base.obj", "a.obj", "b.obj", "-o", "out", "-l", levels,
            ],
        );
        assert_code(&o, 0);
        assert!(o.stdout.is_empty(), "stdout: {}", stdout(&o));
        assert_eq!(listing(&dir.path().join("out")), ["a.obj", "b.obj"]);
        for (name, reference) in [("a.obj", "a.obj"), ("b.obj", "b-full.obj")] {
            let o = run_in(
                dir.path(),
                &["subdivide", reference, "-o", "full.obj", "-l", levels, "-q"],
            );
            assert_code(&o, 0);
            let full = fs::read_to_string(dir.path().join("full.obj")).expect("full");
            let repose = fs::read_to_string(dir.path().join("out").join(name)).expect("pose");
            let ((p, f), (q, g)) = (parse(&repose), parse(&full));
            assert_eq!(f, g, "{name}: faces");
            assert_eq!(p.len(), q.len(), "{name}: vertices");
            for (a, b) in p.iter().zip(&q) {
                assert!(
                    (0..3).all(|i| (a[i] - b[i]).abs() < 1e-13),
                    "{name}: {a:?} against {b:?}"
                );
            }
        }
    }
}

/// With `--limit`, the limit positions and normals `subsurf subdivide --limit` writes.
#[test]
fn limit_poses_are_what_subdivide_writes() {
    let pose = moved(HUT, 0.6);
    let dir = dir_with(&[("hut.obj", HUT), ("pose.obj", &pose)]);
    fs::create_dir(dir.path().join("out")).expect("out dir");
    let o = run_in(
        dir.path(),
        &[
            "repose", "hut.obj", "pose.obj", "-o", "out", "-l", "2", "--limit",
        ],
    );
    assert_code(&o, 0);
    let o = run_in(
        dir.path(),
        &[
            "subdivide",
            "pose.obj",
            "-o",
            "full.obj",
            "-l",
            "2",
            "--limit",
            "-q",
        ],
    );
    assert_code(&o, 0);
    let read = |p: &str| fs::read_to_string(dir.path().join(p)).expect("output");
    let (repose, full) = (read("out/pose.obj"), read("full.obj"));
    let normals = |obj: &str| -> Vec<[f64; 3]> {
        let vn: String = (obj.lines())
            .filter_map(|l| l.strip_prefix("vn "))
            .map(|l| format!("v {l}\n"))
            .collect();
        positions(&vn)
    };
    for (a, b) in [
        (positions(&repose), positions(&full)),
        (normals(&repose), normals(&full)),
    ] {
        assert_eq!(a.len(), b.len());
        assert!(!a.is_empty());
        for (p, q) in a.iter().zip(&b) {
            assert!(
                (0..3).all(|i| (p[i] - q[i]).abs() < 1e-12),
                "{p:?} against {q:?}"
            );
        }
    }
    assert_eq!(parse(&repose).1, parse(&full).1, "faces");
}

/// A pose that does not match stops the run with an error naming it (and, for a face,
/// its line); the poses before it are written whole, nothing is written for it.
#[test]
fn a_pose_that_does_not_match_is_an_error() {
    let good = moved(HUT, 0.5);
    // Face 3 (line 20) turned: the same vertices, another first corner.
    let turned = good.replacen("f 2 3 9 8", "f 3 9 8 2", 1);
    assert_ne!(turned, good);
    let short = points_only(&good)
        .lines()
        .skip(1)
        .map(|l| format!("{l}\n"))
        .collect::<String>();
    let dir = dir_with(&[
        ("hut.obj", HUT),
        ("good.obj", &good),
        ("turned.obj", &turned),
        ("short.obj", &short),
    ]);
    fs::create_dir(dir.path().join("out")).expect("out dir");
    let o = run_in(
        dir.path(),
        &["repose", "hut.obj", "good.obj", "turned.obj", "-o", "out"],
    );
    assert_code(&o, 1);
    let err = stderr(&o);
    assert!(
        err.contains("turned.obj:20: face 3 is not the base mesh's face 3 (hut.obj:20)"),
        "{err}"
    );
    // All or nothing: the good pose before the bad one is not written either.
    assert_eq!(listing(&dir.path().join("out")), Vec::<String>::new());
    // A directory the run created is removed again when it fails.
    let o = run_in(
        dir.path(),
        &[
            "repose",
            "hut.obj",
            "good.obj",
            "turned.obj",
            "-o",
            "new/deeper",
        ],
    );
    assert_code(&o, 1);
    assert!(!dir.path().join("new").exists());
    let o = run_in(dir.path(), &["repose", "hut.obj", "short.obj", "-o", "out"]);
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("short.obj: the pose has 12 vertices, the base mesh 13"),
        "{}",
        stderr(&o)
    );
}

/// Mistakes in the command line fail before any work, naming what is wrong.
#[test]
fn outputs_that_cannot_be_written_are_refused_first() {
    let dir = dir_with(&[("hut.obj", HUT), ("a.obj", &moved(HUT, 0.2))]);
    fs::create_dir(dir.path().join("sub")).expect("sub dir");
    fs::write(dir.path().join("sub").join("a.obj"), moved(HUT, 0.4)).expect("second pose");
    for (args, message) in [
        (
            &["repose", "hut.obj", "a.obj", "-o", "hut.obj"][..],
            "cannot write to hut.obj: not a directory",
        ),
        (
            &["repose", "hut.obj", "a.obj", "sub/a.obj", "-o", "other"][..],
            "two poses would be written to other/a.obj",
        ),
        (
            &["repose", "hut.obj", "sub/a.obj", "-o", "sub"][..],
            "would replace an input",
        ),
        (
            &["repose", "hut.obj", "-", "-o", "sub"][..],
            "standard input ('-') can be the base mesh only",
        ),
    ] {
        let o = run_in(dir.path(), args);
        assert_code(&o, 1);
        assert!(stderr(&o).contains(message), "{args:?}: {}", stderr(&o));
    }
    assert_eq!(listing(dir.path()), ["a.obj", "hut.obj", "sub"]);
    assert_eq!(listing(&dir.path().join("sub")), ["a.obj"]);
}

/// Poses in PLY are written as OBJ under their names with the extension `.obj`; a PLY and
/// an OBJ pose of one name are refused, as their outputs would be one file.
#[test]
fn ply_poses_are_written_as_obj() {
    let pose = moved(HUT, 0.2);
    let ply = crate::input_formats::ply(&pose, "binary_little_endian");
    let dir = dir_with(&[("hut.obj", HUT), ("a.obj", &pose)]);
    fs::write(dir.path().join("b.ply"), &ply).expect("PLY pose");
    let o = run_in(
        dir.path(),
        &[
            "repose", "hut.obj", "a.obj", "b.ply", "-o", "out", "-l", "1",
        ],
    );
    assert_code(&o, 0);
    assert_eq!(listing(&dir.path().join("out")), ["a.obj", "b.obj"]);
    let read = |n: &str| fs::read_to_string(dir.path().join("out").join(n)).expect("output");
    assert_eq!(positions(&read("a.obj")), positions(&read("b.obj")));
    fs::write(dir.path().join("a.ply"), &ply).expect("PLY pose");
    let o = run_in(
        dir.path(),
        &["repose", "hut.obj", "a.obj", "a.ply", "-o", "two"],
    );
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("two poses would be written to two/a.obj"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.path().join("two").exists());
}

/// A missing output directory is created, with its parents.
#[test]
fn a_missing_output_directory_is_created() {
    let dir = dir_with(&[("hut.obj", HUT), ("a.obj", &moved(HUT, 0.2))]);
    let o = run_in(dir.path(), &["repose", "hut.obj", "a.obj", "-o", "out/l2"]);
    assert_code(&o, 0);
    assert_eq!(listing(&dir.path().join("out/l2")), ["a.obj"]);
}

/// The OBJ texts of `base` moved (`moved(base, 0.7)`) and refined `levels` times with
/// `flags`, by `repose` (with `base` as the base mesh) and by `subdivide`.
fn repose_and_subdivide(
    base: &str,
    levels: &'static str,
    flags: &[&'static str],
) -> (String, String) {
    let pose = moved(base, 0.7);
    let dir = dir_with(&[("base.obj", base), ("pose.obj", &pose)]);
    fs::create_dir(dir.path().join("out")).expect("out dir");
    let with = |args: &[&'static str]| -> Vec<&str> {
        let mut v = args.to_vec();
        v.extend_from_slice(&["-l", levels]);
        v.extend_from_slice(flags);
        v
    };
    let o = run_in(
        dir.path(),
        &with(&["repose", "base.obj", "pose.obj", "-o", "out"]),
    );
    assert_code(&o, 0);
    let o = run_in(
        dir.path(),
        &with(&["subdivide", "pose.obj", "-o", "full.obj", "-q"]),
    );
    assert_code(&o, 0);
    let read = |p: &str| fs::read_to_string(dir.path().join(p)).expect("output");
    (read("out/pose.obj"), read("full.obj"))
}

/// `p` and `q` have as many positions, each within 1e-13 of the other's.
fn assert_same_positions(p: &[[f64; 3]], q: &[[f64; 3]], flags: &[&str]) {
    assert_eq!(p.len(), q.len(), "{flags:?}: vertices");
    for (a, b) in p.iter().zip(q) {
        assert!(
            (0..3).all(|i| (a[i] - b[i]).abs() < 1e-13),
            "{flags:?}: {a:?} against {b:?}"
        );
    }
}

/// With the adjustable scheme (`--scheme adjustable --c C [--adjust-steps K]`), each
/// refined pose is what `subsurf subdivide` writes with the same flags: every level
/// adjusted, the first one only (Catmull-Clark's patches after it), and with `--limit`.
#[test]
fn adjustable_poses_are_what_subdivide_writes() {
    let flag_sets: [&[&str]; 3] = [
        &["--scheme", "adjustable", "--c", "0.3"],
        &[
            "--scheme",
            "adjustable",
            "--c",
            "0.8",
            "--adjust-steps",
            "1",
        ],
        &["--scheme", "adjustable", "--c", "0.2", "--limit"],
    ];
    for (base, levels) in [(HUT, "3"), (CUBE_CREASE, "4")] {
        for flags in flag_sets {
            let (repose, full) = repose_and_subdivide(base, levels, flags);
            let ((p, f), (q, g)) = (parse(&repose), parse(&full));
            assert_eq!(f, g, "{flags:?}: faces");
            assert_same_positions(&p, &q, flags);
            // The header says how the pose was refined.
            assert!(
                repose.contains(&flags[..4].join(" ")),
                "{flags:?}: {repose:.300}"
            );
        }
    }
}

/// NURSS (`--scheme nurss`, and the default for a base mesh with knot tags): each refined
/// pose is what `subsurf subdivide` writes for the pose with the base mesh's knot
/// intervals, faces and tags alike, positions to rounding; with rational weights too
/// (`t weight`, which stay with their vertices), and with `--limit` (no normals).
#[test]
fn nurss_poses_are_what_subdivide_writes() {
    let knots = include_str!("../../../../examples/meshes/nurss-grid.obj");
    let rational = format!("{knots}t weight 1/1/0 12 2.5\nt weight 1/1/0 6 0.5\n");
    for (base, flags) in [
        (knots, &[][..]),
        (knots, &["--scheme", "nurss"][..]),
        (&rational[..], &[][..]),
        (knots, &["--limit"][..]),
        (&rational[..], &["--limit"][..]),
    ] {
        let (repose, full) = repose_and_subdivide(base, "3", flags);
        let ((p, _), (q, _)) = (parse(&repose), parse(&full));
        // Faces and tags (the refined intervals and weights) are the same lines.
        let not_v = |t: &str| -> Vec<String> {
            (t.lines())
                .filter(|l| !l.starts_with("v ") && !l.starts_with('#'))
                .map(str::to_owned)
                .collect()
        };
        assert_eq!(not_v(&repose), not_v(&full), "{flags:?}: faces and tags");
        assert!(repose.contains("t interval"), "{flags:?}: no intervals");
        assert_same_positions(&p, &q, flags);
        assert!(repose.contains("--scheme nurss"), "{repose:.300}");
    }
}

/// Loop (a triangle mesh with a semi-sharp crease and a boundary) and bilinear (the hut,
/// with n-gons): each refined pose is what `subsurf subdivide` writes with the same
/// scheme, faces alike and positions to rounding, with and without `--limit`.
#[test]
fn loop_and_bilinear_poses_are_what_subdivide_writes() {
    let triangles = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\nv 0.5 -0.5 0.3\n\
                     f 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\nf 1 6 2\nt crease 2/1/0 0 4 1.5\n";
    for (base, scheme) in [(triangles, "loop"), (HUT, "bilinear")] {
        for limit in [false, true] {
            let mut flags = vec!["--scheme", scheme];
            if limit {
                flags.push("--limit");
            }
            let (repose, full) = repose_and_subdivide(base, "3", &flags);
            let ((p, f), (q, g)) = (parse(&repose), parse(&full));
            assert_eq!(f, g, "{flags:?}: faces");
            assert_same_positions(&p, &q, &flags);
            let header = repose.lines().nth(1).unwrap_or_default();
            assert!(
                header.contains(&flags[..2].join(" ")) && header.contains("--limit") == limit,
                "{flags:?}: {header}"
            );
        }
    }
}

/// What cannot be re-posed is an error that says what to do: a semi-sharp crease under
/// NURSS; `--c` needs `--scheme adjustable` (a usage error).
#[test]
fn schemes_that_are_not_reposed_are_refused() {
    let knots = include_str!("../../../../examples/meshes/nurss-grid.obj");
    let dir = dir_with(&[
        ("hut.obj", HUT),
        ("a.obj", &moved(HUT, 0.2)),
        ("cube.obj", CUBE_CREASE),
        ("knots.obj", knots),
    ]);
    fs::create_dir(dir.path().join("out")).expect("out dir");
    for (args, code, message) in [
        (
            &[
                "repose", "cube.obj", "cube.obj", "-o", "out", "--scheme", "nurss",
            ][..],
            1,
            "cube.obj: the crease on edge",
        ),
        (
            &["repose", "hut.obj", "a.obj", "-o", "out", "--c", "0.3"][..],
            2,
            "--c and --adjust-steps need --scheme adjustable",
        ),
        (
            &[
                "repose",
                "hut.obj",
                "a.obj",
                "-o",
                "out",
                "--scheme",
                "adjustable",
            ][..],
            2,
            "--scheme adjustable needs --c C",
        ),
    ] {
        let o = run_in(dir.path(), args);
        assert_code(&o, code);
        assert!(stderr(&o).contains(message), "{args:?}: {}", stderr(&o));
    }
    assert!(listing(&dir.path().join("out")).is_empty());
    // With --scheme catmull-clark the knot tags are ignored, as `subdivide` ignores them.
    let o = run_in(
        dir.path(),
        &[
            "repose",
            "knots.obj",
            "knots.obj",
            "-o",
            "out",
            "--scheme",
            "catmull-clark",
            "-q",
        ],
    );
    assert_code(&o, 0);
    assert_eq!(listing(&dir.path().join("out")), ["knots.obj"]);
}
