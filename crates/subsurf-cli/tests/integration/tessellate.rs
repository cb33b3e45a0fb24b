//! End-to-end tests of `subsurf tessellate`, each in its own temporary directory.

use crate::common;
use common::*;

use std::fs;

/// The cube at rate 3: 6 × 9 quads, 6 · 9 + 2 shared vertices (closed, genus 0).
const FACES: usize = 54;
const VERTS: usize = 56;

#[test]
fn writes_obj_with_normals() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["tessellate", "cube.obj", "-o", "out.obj", "--rate", "3"],
    );
    assert_code(&o, 0);
    let text = fs::read_to_string(dir.path().join("out.obj")).unwrap();
    assert_eq!(count_records(&text, "v"), VERTS);
    assert_eq!(count_records(&text, "vn"), VERTS);
    assert_eq!(count_records(&text, "f"), FACES);
    assert!(text.contains("# subsurf tessellate --rate 3"), "{text}");
    assert!(text
        .lines()
        .any(|l| l.starts_with("f ") && l.contains("//")));
    // Not a control cage: no scheme tags.
    assert_eq!(count_records(&text, "t"), 0);
    let o = run_in(
        dir.path(),
        &[
            "tessellate",
            "cube.obj",
            "-o",
            "tri.obj",
            "--rate",
            "3",
            "--triangles",
        ],
    );
    assert_code(&o, 0);
    let text = fs::read_to_string(dir.path().join("tri.obj")).unwrap();
    assert_eq!(count_records(&text, "f"), 2 * FACES);
    assert_eq!(count_records(&text, "v"), VERTS);
}

#[test]
fn writes_ply_of_the_expected_size() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["tessellate", "cube.obj", "-o", "out.PLY", "--rate", "3"],
    );
    assert_code(&o, 0);
    let bytes = fs::read(dir.path().join("out.PLY")).unwrap();
    let end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .expect("a PLY header")
        + 11;
    let header = std::str::from_utf8(&bytes[..end]).unwrap();
    assert!(header.starts_with("ply\nformat binary_little_endian 1.0\n"));
    assert!(header.contains(&format!("element vertex {VERTS}\n")));
    assert!(header.contains(&format!("element face {FACES}\n")));
    assert!(header.contains("property double nx\n"));
    // x y z nx ny nz as f64; per quad a u8 count and four i32.
    assert_eq!(bytes.len(), end + VERTS * 48 + FACES * 17);
    let ply = subsurf::io::read_ply(&bytes).unwrap();
    assert_eq!(ply.positions.len(), VERTS);
}

#[test]
fn writes_stl_of_the_expected_size() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    for extra in [&[][..], &["--triangles"][..]] {
        let mut args = vec!["tessellate", "cube.obj", "-o", "out.stl", "--rate", "3"];
        args.extend_from_slice(extra);
        let o = run_in(dir.path(), &args);
        assert_code(&o, 0);
        let bytes = fs::read(dir.path().join("out.stl")).unwrap();
        assert_eq!(bytes.len(), 84 + 50 * 2 * FACES);
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]);
        assert_eq!(count as usize, 2 * FACES);
        assert!(!bytes.starts_with(b"solid"));
    }
}

#[test]
fn dash_writes_obj_to_stdout() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["tessellate", "cube.obj", "-o", "-", "--rate", "2"],
    );
    assert_code(&o, 0);
    let text = String::from_utf8(o.stdout).unwrap();
    assert_eq!(count_records(&text, "f"), 6 * 4);
    assert_eq!(count_records(&text, "vn"), 6 * 4 + 2);
    assert_eq!(listing(dir.path()), ["cube.obj"]);
}

#[test]
fn unknown_extension_exits_one_and_writes_nothing() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    // An unknown extension is a usage error; no extension, the command's own refusal.
    for (out, code) in [("out.xyz", 2), ("out", 1)] {
        let o = run_in(
            dir.path(),
            &["tessellate", "cube.obj", "-o", out, "--rate", "2"],
        );
        assert_code(&o, code);
        let e = stderr(&o);
        assert!(e.contains(out) && e.contains(".obj, .ply"), "{e}");
        assert_eq!(listing(dir.path()), ["cube.obj"]);
    }
}

#[test]
fn bad_rates_are_usage_errors() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    for args in [
        &["tessellate", "cube.obj", "-o", "a.obj"][..],
        &["tessellate", "cube.obj", "-o", "a.obj", "--rate", "0"][..],
        &["tessellate", "cube.obj", "-o", "a.obj", "--rate", "x"][..],
    ] {
        let o = run_in(dir.path(), args);
        assert_code(&o, 2);
    }
    assert_eq!(listing(dir.path()), ["cube.obj"]);
}

#[test]
fn too_large_exits_one_with_the_estimate() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["tessellate", "cube.obj", "-o", "a.ply", "--rate", "100000"],
    );
    assert_code(&o, 1);
    let e = stderr(&o);
    assert!(
        e.contains("60000000002 vertices") && e.contains("lower the rate"),
        "{e}"
    );
    assert_eq!(listing(dir.path()), ["cube.obj"]);
}

#[test]
fn odd_rates_round_up_with_non_quads() {
    let dir = dir_with(&[("hut.obj", HUT)]);
    let o = run_in(
        dir.path(),
        &["tessellate", "hut.obj", "-o", "hut.obj.obj", "--rate", "3"],
    );
    assert_code(&o, 0);
    assert!(
        stderr(&o).contains("rate 3 rounded up to 4"),
        "{}",
        stderr(&o)
    );
    let text = fs::read_to_string(dir.path().join("hut.obj.obj")).unwrap();
    // Six quads of 4 × 4, a hexagon and six triangles of 2 × 2 per corner.
    assert_eq!(count_records(&text, "f"), 6 * 16 + 6 * 4 + 6 * 3 * 4);
    let o = run_in(
        dir.path(),
        &["tessellate", "hut.obj", "-o", "q.obj", "--rate", "3", "-q"],
    );
    assert_code(&o, 0);
    assert_eq!(stderr(&o), "");
}

#[test]
fn help_shows_examples() {
    let dir = dir_with(&[]);
    let o = run_in(dir.path(), &["tessellate", "--help"]);
    assert_code(&o, 0);
    let text = String::from_utf8_lossy(&o.stdout);
    for s in [
        "--rate",
        "--triangles",
        "--boundary",
        "--crease-method",
        "Examples:",
        ".stl",
    ] {
        assert!(text.contains(s), "{s} missing from:\n{text}");
    }
}

/// A cube of side 9e74 (coordinates may be up to 1e75) tessellates to OBJ and PLY, which
/// keep double precision; STL and glTF keep single precision and cannot store it: the
/// error names the input, its face and line, not the output (it said `cannot write
/// out.stl: vertex 0 (...) cannot be stored as f32`), and nothing is written.
#[test]
fn single_precision_formats_refuse_huge_coordinates_naming_the_input() {
    let big: String = CUBE
        .lines()
        .map(|l| match l.strip_prefix("v ") {
            Some(rest) => {
                let c: Vec<String> = (rest.split_whitespace())
                    .map(|x| format!("{}e74", 9.0 * x.parse::<f64>().expect("coordinate")))
                    .collect();
                format!("v {}\n", c.join(" "))
            }
            None => format!("{l}\n"),
        })
        .collect();
    let dir = dir_with(&[("big.obj", &big)]);
    for out in ["out.obj", "out.ply"] {
        let o = run_in(
            dir.path(),
            &["tessellate", "big.obj", "-o", out, "--rate", "2"],
        );
        assert_code(&o, 0);
    }
    let line = 1 + big
        .lines()
        .position(|l| l.starts_with("f "))
        .expect("a face");
    for out in ["out.stl", "out.glb"] {
        let o = run_in(
            dir.path(),
            &["tessellate", "big.obj", "-o", out, "--rate", "2"],
        );
        assert_code(&o, 1);
        let e = stderr(&o);
        assert!(
            e.contains(&format!(
                "big.obj:{line}: face 1: the limit surface reaches"
            )),
            "{e}"
        );
        assert!(!e.contains("cannot write"), "{e}");
        assert!(!dir.path().join(out).exists(), "{out} written");
    }
}

/// OpenSubdiv's `catmark_fvar_bound1` (texture seams meeting at vertices of several values).
const FVAR_BOUND1: &str = include_str!("../../../subsurf/tests/shapes/osd/catmark_fvar_bound1.obj");

/// Positions, texture coordinates and faces (`v/vt` per corner, 0-based) of an OBJ.
#[allow(clippy::type_complexity)]
fn obj_with_uvs(text: &str) -> (Vec<[f64; 3]>, Vec<[f64; 2]>, Vec<Vec<(usize, usize)>>) {
    let nums = |l: &str| -> Vec<f64> {
        l.split_whitespace()
            .skip(1)
            .map(|x| x.parse().expect("number"))
            .collect()
    };
    let (mut v, mut vt, mut f) = (Vec::new(), Vec::new(), Vec::new());
    for l in text.lines() {
        if l.starts_with("v ") {
            let x = nums(l);
            v.push([x[0], x[1], x[2]]);
        } else if l.starts_with("vt ") {
            let x = nums(l);
            vt.push([x[0], x[1]]);
        } else if l.starts_with("f ") {
            f.push(
                (l.split_whitespace().skip(1))
                    .map(|c| {
                        let mut k = c.split('/').map(|x| x.parse::<usize>().expect("index") - 1);
                        (k.next().expect("v"), k.next().expect("vt"))
                    })
                    .collect(),
            );
        }
    }
    (v, vt, f)
}

/// The tessellation's texture coordinates are the exact limit at every corner, seen from
/// the corner's own face: each row of `subsurf limit` (at the same `(u, v)`, its `s t`
/// checked against OpenSubdiv `Bfr`) is found at its vertex, with its face's value, on both
/// sides of every seam; every format but STL carries them.
#[test]
fn texture_coordinates_are_the_limit_at_every_corner() {
    let dir = dir_with(&[("uv.obj", FVAR_BOUND1)]);
    for mode in ["none", "corners-plus1", "all"] {
        let tess = [
            "tessellate",
            "uv.obj",
            "--rate",
            "2",
            "--fvar",
            mode,
            "-o",
            "out.obj",
        ];
        assert_code(&run_in(dir.path(), &tess), 0);
        let limit = [
            "limit", "uv.obj", "--grid", "3", "--fvar", mode, "-o", "rows.tsv",
        ];
        assert_code(&run_in(dir.path(), &limit), 0);
        let (v, vt, faces) = obj_with_uvs(&fs::read_to_string(dir.path().join("out.obj")).unwrap());
        let rows = fs::read_to_string(dir.path().join("rows.tsv")).unwrap();
        // (vertex, texture coordinate) pairs of every corner.
        let corners: Vec<(usize, usize)> = faces.iter().flatten().copied().collect();
        assert!(vt.len() > v.len(), "{mode}: seams add values");
        for row in rows.lines() {
            let x: Vec<f64> = row.split_whitespace().map(|t| t.parse().unwrap()).collect();
            let near = |p: &[f64; 3]| (0..3).all(|k| (p[k] - x[3 + k]).abs() < 1e-12);
            let at = v
                .iter()
                .position(near)
                .expect("the sample is an output vertex");
            let found = (corners.iter()).filter(|&&(p, _)| p == at).any(|&(_, t)| {
                (vt[t][0] - x[12]).abs() < 1e-12 && (vt[t][1] - x[13]).abs() < 1e-12
            });
            assert!(
                found,
                "{mode}: row {row}: no corner of vertex {at} has its s t"
            );
        }
    }
    // PLY: `s t` per vertex, a vertex per (position, texture coordinate).
    let o = run_in(
        dir.path(),
        &["tessellate", "uv.obj", "--rate", "2", "-o", "out.ply"],
    );
    assert_code(&o, 0);
    let bytes = fs::read(dir.path().join("out.ply")).unwrap();
    let end = bytes.windows(10).position(|w| w == b"end_header").unwrap();
    let header = String::from_utf8_lossy(&bytes[..end]).to_string();
    assert!(
        header.contains("property double s\nproperty double t\n"),
        "{header}"
    );
    // glTF: TEXCOORD_0, flipped to glTF's top-left origin.
    let o = run_in(
        dir.path(),
        &["tessellate", "uv.obj", "--rate", "2", "-o", "out.glb"],
    );
    assert_code(&o, 0);
    let glb = gltf::Gltf::from_slice(&fs::read(dir.path().join("out.glb")).unwrap())
        .expect("a valid glb");
    let blob = glb.blob.as_deref().expect("a BIN chunk");
    let prim = glb.meshes().next().unwrap().primitives().next().unwrap();
    let reader = prim.reader(|_| Some(blob));
    let tex: Vec<[f32; 2]> = reader
        .read_tex_coords(0)
        .expect("TEXCOORD_0")
        .into_f32()
        .collect();
    assert_eq!(tex.len(), reader.read_positions().unwrap().count());
    let (_, vt, _) = obj_with_uvs(&fs::read_to_string(dir.path().join("out.obj")).unwrap());
    for t in &tex {
        let near = |u: &[f64; 2]| {
            (u[0] - f64::from(t[0])).abs() < 1e-6 && (1.0 - u[1] - f64::from(t[1])).abs() < 1e-6
        };
        assert!(
            vt.iter().any(near),
            "{t:?} is no texture coordinate of the OBJ"
        );
    }
    // STL cannot store them: a note says so.
    let o = run_in(
        dir.path(),
        &["tessellate", "uv.obj", "--rate", "2", "-o", "out.stl"],
    );
    assert_code(&o, 0);
    assert!(
        stderr(&o).contains("STL stores no texture coordinates"),
        "{}",
        stderr(&o)
    );
}
