//! End-to-end tests of `subsurf g2`, each in its own temporary directory.

use crate::common;
use common::*;

use std::fs;

/// The cube (8 vertices of valence 3, all capped) at rate 4: 6 × 16 quads on
/// 6 · 16 + 2 shared vertices — closed and watertight, with normals.
#[test]
fn writes_a_watertight_obj_with_normals() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["g2", "cube.obj", "-o", "out.obj", "--rate", "4"],
    );
    assert_code(&o, 0);
    let text = fs::read_to_string(dir.path().join("out.obj")).unwrap();
    assert_eq!(count_records(&text, "v"), 98);
    assert_eq!(count_records(&text, "vn"), 98);
    assert_eq!(count_records(&text, "f"), 96);
    assert!(text.contains("8 caps"), "{text}");
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));
}

/// JSON: every cap patch has 64 control points, its corner at (0, 0) is the same point
/// for all patches of a cap (the extraordinary vertex), and the bicubics cover the rest.
#[test]
fn json_lists_bi_septic_caps_and_bicubic_patches() {
    let dir = dir_with(&[("hut.obj", HUT)]);
    let o = run_in(dir.path(), &["g2", "hut.obj", "-o", "hut.json"]);
    assert_code(&o, 0);
    let text = fs::read_to_string(dir.path().join("hut.json")).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(doc["format"], "subsurf-g2");
    assert_eq!(doc["version"], 1);
    let caps = doc["caps"].as_array().unwrap();
    assert!(!caps.is_empty());
    for cap in caps {
        let patches = cap["patches"].as_array().unwrap();
        assert_eq!(patches.len() as u64, cap["valence"].as_u64().unwrap());
        let first = &patches[0]["points"][0];
        for p in patches {
            assert_eq!(p["degree"], 7);
            let pts = p["points"].as_array().unwrap();
            assert_eq!(pts.len(), 64);
            for k in 0..3 {
                let d = pts[0][k].as_f64().unwrap() - first[k].as_f64().unwrap();
                assert!(d.abs() < 1e-9);
            }
        }
    }
    let bicubic = doc["bicubic"].as_array().unwrap();
    assert!(!bicubic.is_empty());
    assert!(bicubic
        .iter()
        .all(|p| p["points"].as_array().unwrap().len() == 16));
}

/// IGES: fixed 80-column records, one rational B-spline surface entity (128) per patch of
/// the JSON output (caps and bicubics), and the terminate record's section counts.
#[test]
fn iges_has_one_entity_128_per_patch() {
    let dir = dir_with(&[("hut.obj", HUT)]);
    assert_code(&run_in(dir.path(), &["g2", "hut.obj", "-o", "hut.igs"]), 0);
    assert_code(&run_in(dir.path(), &["g2", "hut.obj", "-o", "hut.json"]), 0);
    let iges = fs::read_to_string(dir.path().join("hut.igs")).unwrap();
    let lines: Vec<&str> = iges.lines().collect();
    assert!(
        lines.iter().all(|l| l.len() == 80),
        "a record is not 80 columns"
    );
    // Directory entries come in pairs of 'D' records; the first field is the entity type.
    let entities: Vec<&str> = lines
        .iter()
        .filter(|l| l.as_bytes()[72] == b'D')
        .step_by(2)
        .map(|l| l[..8].trim())
        .collect();
    let doc: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.path().join("hut.json")).unwrap()).unwrap();
    let caps: usize = doc["caps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["patches"].as_array().unwrap().len())
        .sum();
    let bicubic = doc["bicubic"].as_array().unwrap().len();
    assert_eq!(entities.len(), caps + bicubic);
    assert!(entities.iter().all(|&e| e == "128"), "{entities:?}");
    let last = lines.last().unwrap();
    assert_eq!(last.as_bytes()[72], b'T');
    assert_eq!(&last[16..17], "D");
    let d_count: usize = last[17..24].trim().parse().unwrap();
    assert_eq!(d_count, 2 * entities.len());
}

/// `--report` prints the table: G2 rows tiny, Catmull-Clark's vertex row not.
#[test]
fn report_compares_with_catmull_clark() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["g2", "cube.obj", "-o", "out.obj", "--rate", "2", "--report"],
    );
    assert_code(&o, 0);
    let out = stdout(&o);
    assert!(out.contains("8 caps"), "{out}");
    let row = |name: &str, kind: &str| -> Vec<f64> {
        let line = out
            .lines()
            .find(|l| l.starts_with(name) && l.split_whitespace().any(|w| w == kind))
            .unwrap_or_else(|| panic!("no {name} {kind} row in {out}"));
        line.split_whitespace()
            .rev()
            .take(3)
            .map(|w| w.parse().unwrap())
            .collect()
    };
    for kind in ["inner", "outer", "vertex"] {
        let r = row("G2 caps", kind);
        assert!(r.iter().all(|&x| x < 1e-6), "{kind}: {r:?}");
    }
    let cc = row("Catmull-Clark", "vertex");
    assert!(cc[0] > 1e-2, "{cc:?}");
}

#[test]
fn bad_inputs_exit_1_usage_errors_exit_2() {
    let dir = dir_with(&[("cube.obj", CUBE), ("bad.obj", "v 0 0 0\nf 1 2 3\n")]);
    let o = run_in(dir.path(), &["g2", "cube.obj", "-o", "out.fbx"]);
    assert_code(&o, 2);
    assert!(stderr(&o).contains(".obj"), "{}", stderr(&o));
    let o = run_in(dir.path(), &["g2", "bad.obj", "-o", "out.obj"]);
    assert_code(&o, 1);
    assert!(stderr(&o).contains("bad.obj"), "{}", stderr(&o));
    let o = run_in(dir.path(), &["g2", "cube.obj"]);
    assert_code(&o, 2);
    let o = run_in(
        dir.path(),
        &["g2", "cube.obj", "-o", "x.obj", "--rate", "0"],
    );
    assert_code(&o, 2);
    // Nothing was written.
    assert!(!dir.path().join("out.obj").exists() && !dir.path().join("x.obj").exists());
}

/// The G2 surface's tessellation is written in every tessellation format (the one writer
/// of `subsurf tessellate`), and `subsurf spline` writes glTF with its patch colours.
#[test]
fn tessellations_in_every_format() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    for (file, magic) in [
        ("g.obj", &b"# written by subsurf"[..]),
        ("g.ply", b"ply\nformat binary_little_endian"),
        ("g.glb", b"glTF"),
    ] {
        let o = run_in(dir.path(), &["g2", "cube.obj", "--rate", "3", "-o", file]);
        assert_code(&o, 0);
        let bytes = std::fs::read(dir.path().join(file)).unwrap();
        assert!(bytes.starts_with(magic), "{file}");
    }
    // STL: an 80-byte header, the triangle count, 50 bytes per triangle: the cube's six
    // faces at rate 3 are 6 × 9 quads, two triangles each.
    let o = run_in(
        dir.path(),
        &["g2", "cube.obj", "--rate", "3", "-o", "g.stl"],
    );
    assert_code(&o, 0);
    let stl = std::fs::read(dir.path().join("g.stl")).unwrap();
    let count = u32::from_le_bytes(stl[80..84].try_into().unwrap());
    assert_eq!(count, 6 * 9 * 2);
    assert_eq!(stl.len(), 84 + 50 * count as usize);
    let o = run_in(
        dir.path(),
        &["spline", "cube.obj", "--colour-faces", "-o", "s.glb"],
    );
    assert_code(&o, 0);
    let glb = std::fs::read(dir.path().join("s.glb")).unwrap();
    assert!(glb.starts_with(b"glTF") && String::from_utf8_lossy(&glb).contains("COLOR_0"));
}

/// A .png output draws the G2 surface; --compare draws Catmull-Clark, which differs at the
/// caps; the picture options need a .png.
#[test]
fn png_pictures_of_the_caps_and_of_catmull_clark() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let args = [
        "g2",
        "cube.obj",
        "--rate",
        "8",
        "--curvature",
        "mean",
        "--view",
        "45,35",
    ];
    let o = run_in(dir.path(), &[&args[..], &["-o", "g2.png"]].concat());
    assert_code(&o, 0);
    let o = run_in(
        dir.path(),
        &[&args[..], &["-o", "cc.png", "--compare"]].concat(),
    );
    assert_code(&o, 0);
    let g2 = fs::read(dir.path().join("g2.png")).unwrap();
    let cc = fs::read(dir.path().join("cc.png")).unwrap();
    assert!(g2.starts_with(b"\x89PNG") && cc.starts_with(b"\x89PNG"));
    assert_ne!(g2, cc);
    let o = run_in(dir.path(), &["g2", "cube.obj", "-o", "x.obj", "--zebra"]);
    assert_code(&o, 1);
    assert!(stderr(&o).contains(".png"), "{}", stderr(&o));
}

fn vertex_lines(text: &str) -> Vec<&str> {
    text.lines().filter(|l| l.starts_with("v ")).collect()
}

/// `--c C [--adjust-steps K]`: the G2 surface of the mixed surface. `--c 0.5` is
/// Catmull-Clark (the same vertices), `--c 0.3` pulls the surface toward the cube and its
/// report still shows G2 caps; the JSON records the parameters; bad values are usage
/// errors (exit 2), as for `subdivide`, `tessellate` and `render`.
#[test]
fn shape_parameter_gives_the_g2_surface_of_the_mixed_surface() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let plain = ["g2", "cube.obj", "--rate", "4", "-o"];
    assert_code(&run_in(dir.path(), &[&plain[..], &["cc.obj"]].concat()), 0);
    let o = run_in(
        dir.path(),
        &[&plain[..], &["half.obj", "--c", "0.5"]].concat(),
    );
    assert_code(&o, 0);
    let o = run_in(
        dir.path(),
        &[&plain[..], &["tight.obj", "--c", "0.3", "--report"]].concat(),
    );
    assert_code(&o, 0);
    let read = |f: &str| fs::read_to_string(dir.path().join(f)).unwrap();
    let (cc, half, tight) = (read("cc.obj"), read("half.obj"), read("tight.obj"));
    assert_eq!(vertex_lines(&cc), vertex_lines(&half));
    assert!(tight.contains("--c 0.3 --adjust-steps 1"), "{tight}");
    // The centre of a face: Catmull-Clark's cube reaches 5/6 of the half width; c = 0.3
    // stays closer to the control mesh (it is bicubic there, far from the caps).
    let max_x = |t: &str| {
        vertex_lines(t)
            .iter()
            .map(|l| l.split_whitespace().nth(1).unwrap().parse::<f64>().unwrap())
            .fold(f64::MIN, f64::max)
    };
    assert!(
        max_x(&tight) > max_x(&cc) + 1e-3,
        "{} vs {}",
        max_x(&tight),
        max_x(&cc)
    );
    let out = stdout(&o);
    assert!(
        out.contains("8 caps") && out.contains("mixed surface"),
        "{out}"
    );
    for line in out.lines().filter(|l| l.starts_with("G2 caps")) {
        let worst = line
            .split_whitespace()
            .rev()
            .take(3)
            .map(|w| w.parse::<f64>().unwrap())
            .fold(0.0, f64::max);
        assert!(worst < 1e-6, "{line}");
    }
    let o = run_in(
        dir.path(),
        &[
            "g2",
            "cube.obj",
            "-o",
            "m.json",
            "--c",
            "0.7",
            "--adjust-steps",
            "2",
        ],
    );
    assert_code(&o, 0);
    let doc: serde_json::Value = serde_json::from_str(&read("m.json")).unwrap();
    assert_eq!(doc["mixed"]["c"], 0.7);
    assert_eq!(doc["mixed"]["adjust_steps"], 2);
    assert_eq!(doc["levels"], 3);
    assert_eq!(doc["caps"].as_array().unwrap().len(), 8);
    for bad in [
        &["--c", "1.5"][..],
        &["--c", "-0.1"],
        &["--c", "x"],
        &["--adjust-steps", "2"],
    ] {
        let o = run_in(
            dir.path(),
            &[&["g2", "cube.obj", "-o", "bad.obj"][..], bad].concat(),
        );
        assert_code(&o, 2);
    }
    assert!(stderr(&run_in(
        dir.path(),
        &["g2", "cube.obj", "-o", "b.obj", "--c", "2"]
    ))
    .contains("shape parameter in [0, 1]"));
    assert!(!dir.path().join("bad.obj").exists() && !dir.path().join("b.obj").exists());
}

/// With `--c`, a .png draws the mixed G2 surface, and `--compare` the mixed surface
/// without caps (not plain Catmull-Clark, which `--c 0.5 --compare` draws).
#[test]
fn png_with_shape_parameter_compares_with_the_mixed_surface() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let base = ["g2", "cube.obj", "--rate", "4", "--zebra"];
    let runs: [(&str, &[&str]); 3] = [
        ("g2.png", &["--c", "0.3"]),
        ("mixed.png", &["--c", "0.3", "--compare"]),
        ("cc.png", &["--c", "0.5", "--compare"]),
    ];
    for (out, extra) in runs {
        let args = [&base[..], extra, &["-o", out]].concat();
        assert_code(&run_in(dir.path(), &args), 0);
    }
    let read = |f: &str| fs::read(dir.path().join(f)).unwrap();
    let (g2, mixed, cc) = (read("g2.png"), read("mixed.png"), read("cc.png"));
    assert!(g2.starts_with(b"\x89PNG"));
    assert_ne!(g2, mixed);
    assert_ne!(mixed, cc);
}

/// `--rate` sizes the tessellation and the picture: refused up front above --max-memory
/// (exit 1, nothing written); JSON output does not depend on the rate.
#[test]
fn large_rates_are_refused_up_front() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    for (out, what) in [("out.obj", "tessellating"), ("out.png", "drawing")] {
        let o = run_in(
            dir.path(),
            &[
                "g2",
                "cube.obj",
                "-o",
                out,
                "--rate",
                "4096",
                "--max-memory",
                "1G",
            ],
        );
        assert_code(&o, 1);
        let e = stderr(&o);
        let prefix = format!("error: cube.obj: {what} the G2 surface at rate 4096 needs about ");
        assert!(e.starts_with(&prefix), "{e}");
        assert!(e.contains("(--max-memory); use a lower --rate"), "{e}");
        assert!(!dir.path().join(out).exists());
    }
    let o = run_in(
        dir.path(),
        &[
            "g2",
            "cube.obj",
            "-o",
            "out.json",
            "--rate",
            "4096",
            "--max-memory",
            "64M",
        ],
    );
    assert_code(&o, 0);
}
