//! End-to-end tests of `subsurf render`, each in its own temporary directory.

use crate::common;
use common::*;

use std::fs;

const TORUS: &str = include_str!("../../../../examples/meshes/torus.obj");

/// Width and height from a PNG's IHDR chunk (panics if `bytes` is not a PNG).
#[track_caller]
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert!(bytes.len() > 24, "too short for a PNG");
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |b: &[u8]| u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
    (be(&bytes[16..20]), be(&bytes[20..24]))
}

#[test]
fn writes_a_png_of_the_requested_size() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["render", "cube.obj", "-o", "out.png", "--size", "200x150"],
    );
    assert_code(&o, 0);
    let bytes = fs::read(dir.path().join("out.png")).unwrap();
    assert_eq!(png_size(&bytes), (200, 150));
    // Deterministic: the same command writes the same bytes.
    let o = run_in(
        dir.path(),
        &["render", "cube.obj", "-o", "again.png", "--size", "200x150"],
    );
    assert_code(&o, 0);
    assert_eq!(bytes, fs::read(dir.path().join("again.png")).unwrap());
    // The default size.
    let o = run_in(dir.path(), &["render", "cube.obj", "-o", "big.PNG"]);
    assert_code(&o, 0);
    assert_eq!(
        png_size(&fs::read(dir.path().join("big.PNG")).unwrap()),
        (800, 600)
    );
}

#[test]
fn modes_work_and_differ() {
    let dir = dir_with(&[("cube.obj", CUBE), ("torus.obj", TORUS)]);
    let runs: &[&[&str]] = &[
        &["cube.obj", "-o", "plain.png"],
        &["cube.obj", "-o", "zebra.png", "--zebra"],
        &["cube.obj", "-o", "mean.png", "--curvature", "mean"],
        &[
            "torus.obj",
            "-o",
            "gauss.png",
            "--curvature",
            "gauss",
            "--range=-2,2",
        ],
        &[
            "cube.obj",
            "-o",
            "max.png",
            "--curvature",
            "max",
            "--view",
            "45,35",
        ],
        &["cube.obj", "-o", "cage.png", "--control-mesh"],
        &["cube.obj", "-o", "faces.png", "--faces", "--up", "y"],
        &[
            "cube.obj", "-o", "l2.png", "--level", "2", "--shade", "flat",
        ],
        &[
            "cube.obj",
            "-o",
            "rate.png",
            "--limit-rate",
            "3",
            "--view",
            "-30,-10",
        ],
        &["cube.obj", "-o", "zoom.png", "--zoom", "2"],
    ];
    let mut seen = Vec::new();
    for args in runs {
        let mut all = vec!["render"];
        all.extend_from_slice(args);
        all.extend_from_slice(&["--size", "120x90"]);
        let o = run_in(dir.path(), &all);
        assert_code(&o, 0);
        let bytes = fs::read(dir.path().join(args[2])).unwrap();
        assert_eq!(png_size(&bytes), (120, 90), "{args:?}");
        assert!(
            !seen.contains(&bytes),
            "{args:?} drew the same as another mode"
        );
        seen.push(bytes);
    }
    // Curvature reports its colour range.
    let o = run_in(
        dir.path(),
        &["render", "cube.obj", "-o", "m.png", "--curvature", "mean"],
    );
    assert_code(&o, 0);
    assert!(
        stderr(&o).contains("mean curvature colour range"),
        "{}",
        stderr(&o)
    );
    let o = run_in(
        dir.path(),
        &[
            "render",
            "cube.obj",
            "-o",
            "q.png",
            "--curvature",
            "mean",
            "-q",
        ],
    );
    assert_code(&o, 0);
    assert_eq!(stderr(&o), "");
}

#[test]
fn writes_to_standard_output_and_reads_standard_input() {
    let dir = dir_with(&[]);
    let o = run_with_stdin(
        dir.path(),
        &["render", "-", "-o", "-", "--size", "64x48"],
        CUBE,
    );
    assert_code(&o, 0);
    assert_eq!(png_size(&o.stdout), (64, 48));
    assert!(listing(dir.path()).is_empty());
}

#[test]
fn bad_extension_fails_without_writing() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    // An unknown extension is a usage error; a name without one is a PNG.
    let o = run_in(dir.path(), &["render", "cube.obj", "-o", "out.jpg"]);
    assert_code(&o, 2);
    assert!(stderr(&o).contains(".png"), "{}", stderr(&o));
    assert_eq!(listing(dir.path()), ["cube.obj"]);
    let o = run_in(
        dir.path(),
        &["render", "cube.obj", "-o", "out", "--size", "64x48"],
    );
    assert_code(&o, 0);
    assert!(fs::read(dir.path().join("out"))
        .unwrap()
        .starts_with(b"\x89PNG"));
}

#[test]
fn bad_input_and_usage_errors() {
    let dir = dir_with(&[("cube.obj", CUBE), ("bad.obj", "v 0 0 0\nf 1 2 3\n")]);
    let o = run_in(dir.path(), &["render", "bad.obj", "-o", "out.png"]);
    assert_code(&o, 1);
    assert!(stderr(&o).contains("bad.obj"), "{}", stderr(&o));
    let o = run_in(dir.path(), &["render", "missing.obj", "-o", "out.png"]);
    assert_code(&o, 1);
    assert!(stderr(&o).contains("missing.obj"), "{}", stderr(&o));
    // Every face a hole: nothing to draw.
    let holes = format!("{CUBE}t hole 6/0/0 0 1 2 3 4 5\n");
    fs::write(dir.path().join("holes.obj"), holes).unwrap();
    let o = run_in(dir.path(), &["render", "holes.obj", "-o", "out.png"]);
    assert_code(&o, 1);
    assert!(stderr(&o).contains("nothing to draw"), "{}", stderr(&o));
    // Usage errors exit with 2.
    for args in [
        &["--size", "10x10"][..],
        &["--size", "800"],
        &["--view", "30"],
        &["--curvature", "mean", "--level", "1"],
        &["--zebra", "--faces"],
        &["--curvature", "gauss", "--zebra"],
        &["--range=-1,1"],
        &["--shade", "phong"],
        &["--level", "1", "--limit-rate", "4"],
        &["--zoom", "0"],
    ] {
        let mut all = vec!["render", "cube.obj", "-o", "out.png"];
        all.extend_from_slice(args);
        let o = run_in(dir.path(), &all);
        assert_code(&o, 2);
    }
    let o = run_in(
        dir.path(),
        &[
            "render",
            "cube.obj",
            "-o",
            "out.png",
            "--curvature",
            "mean",
            "--range",
            "1,1",
        ],
    );
    assert_code(&o, 1);
    assert!(stderr(&o).contains("range"), "{}", stderr(&o));
    assert_eq!(listing(dir.path()), ["bad.obj", "cube.obj", "holes.obj"]);
}

/// A refusal quotes the limit the user gave, at every stage (before the surface is built,
/// while it is built, before it is evaluated), and names what to reduce: the picture's
/// size when the picture is most of the memory.
#[test]
fn memory_refusals_quote_the_given_limit_and_what_to_reduce() {
    let pawn = include_str!("../../../../examples/meshes/catmark_pawn.obj");
    let dir = dir_with(&[("pawn.obj", pawn), ("cube.obj", CUBE)]);
    let mut refused = 0;
    for mib in (20..=80).step_by(4) {
        let limit = format!("{mib}M");
        let o = run_in(
            dir.path(),
            &[
                "render",
                "pawn.obj",
                "-o",
                "p.png",
                "--limit-rate",
                "8",
                "--max-memory",
                &limit,
            ],
        );
        if o.status.code() == Some(1) {
            refused += 1;
            let e = stderr(&o);
            assert!(
                e.contains(&format!(
                    "more than the limit of {mib} MiB (--max-memory); use a lower --limit-rate"
                )),
                "{limit}: {e}"
            );
        } else {
            assert_code(&o, 0);
        }
    }
    assert!(refused > 0);
    let o = run_in(
        dir.path(),
        &[
            "render",
            "cube.obj",
            "-o",
            "c.png",
            "--size",
            "6000x6000",
            "--max-memory",
            "100M",
        ],
    );
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("use a smaller --size"),
        "{}",
        stderr(&o)
    );
}

/// A cube with a cross-shaped texture layout (14 `vt`, seams on 7 edges).
const TEXTURED_CUBE: &str = include_str!("../../../subsurf/tests/golden/fvar/textured_cube.obj");

/// `--texture checker` draws through the texture coordinates (their limit in the `--fvar`
/// mode, or a level's); a mesh without them is an error naming it, and the texture's
/// flags need `--texture`.
#[test]
fn texture_checker_through_the_texture_coordinates() {
    let dir = dir_with(&[("uv.obj", TEXTURED_CUBE), ("cube.obj", CUBE)]);
    let draw = |extra: &[&str], out: &str| {
        let mut args = vec![
            "render",
            "uv.obj",
            "--size",
            "120x90",
            "-o",
            out,
            "--texture",
            "checker",
        ];
        args.extend_from_slice(extra);
        assert_code(&run_in(dir.path(), &args), 0);
        fs::read(dir.path().join(out)).unwrap()
    };
    let all = draw(&["--fvar", "all"], "all.png");
    let none = draw(&["--fvar", "none", "--squares", "4"], "none.png");
    let level = draw(&["--level", "1"], "level.png");
    assert!(all != none && all != level);
    let o = run_in(
        dir.path(),
        &["render", "cube.obj", "-o", "x.png", "--texture", "checker"],
    );
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("cube.obj") && stderr(&o).contains("no texture coordinates"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.path().join("x.png").exists());
    let o = run_in(
        dir.path(),
        &["render", "uv.obj", "-o", "x.png", "--squares", "4"],
    );
    assert_code(&o, 2);
    let o = run_in(
        dir.path(),
        &[
            "render",
            "uv.obj",
            "-o",
            "x.png",
            "--texture",
            "checker",
            "--zebra",
        ],
    );
    assert_code(&o, 2);
}
