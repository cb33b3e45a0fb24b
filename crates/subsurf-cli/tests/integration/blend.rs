//! End-to-end tests of `subsurf blend` and `subsurf fill`, each in its own temporary
//! directory, on the bundled examples.

use crate::common;
use common::*;

use std::fs;

const BLEND3: &str = include_str!("../../../../examples/patches/blend3.json");
const BLEND5: &str = include_str!("../../../../examples/patches/blend5.json");
const HOLE3: &str = include_str!("../../../../examples/patches/hole3.json");
const HOLE5: &str = include_str!("../../../../examples/patches/hole5.json");
const HOLE3_G1: &str = include_str!("../../../../examples/patches/hole3-g1.json");

/// Group names in order and the face count of each.
fn groups(text: &str) -> Vec<(String, usize)> {
    let mut out: Vec<(String, usize)> = Vec::new();
    for l in text.lines() {
        if let Some(name) = l.strip_prefix("g ") {
            out.push((name.to_string(), 0));
        } else if l.starts_with("f ") {
            if let Some(last) = out.last_mut() {
                last.1 += 1;
            }
        }
    }
    out
}

#[test]
fn blend_writes_the_base_patches_and_the_blend_as_groups() {
    for (file, text, n) in [("blend3.json", BLEND3, 3), ("blend5.json", BLEND5, 5)] {
        let dir = dir_with(&[(file, text)]);
        let o = run_in(
            dir.path(),
            &[
                "blend",
                file,
                "-o",
                "out.obj",
                "--levels",
                "3",
                "--control-mesh",
                "c.obj",
            ],
        );
        assert_code(&o, 0);
        let g = groups(&fs::read_to_string(dir.path().join("out.obj")).unwrap());
        assert_eq!(g.len(), n + 1);
        for (k, (name, faces)) in g.iter().take(n).enumerate() {
            assert_eq!(name, &format!("patch_{}", k + 1));
            assert!(*faces > 0);
        }
        assert_eq!(g[n].0, "blend");
        assert!(g[n].1 > 100);
        // The control mesh carries its knot intervals and reads back.
        let c = fs::read_to_string(dir.path().join("c.obj")).unwrap();
        assert!(c.contains("\nt interval 2/1/0 "));
        assert_code(&run_in(dir.path(), &["info", "c.obj"]), 0);
    }
}

#[test]
fn fill_writes_patches_curves_and_the_fill() {
    for (file, text, n) in [("hole3.json", HOLE3, 3), ("hole5.json", HOLE5, 5)] {
        let dir = dir_with(&[(file, text)]);
        let o = run_in(
            dir.path(),
            &[
                "fill", file, "-o", "out.obj", "--levels", "3", "--bulge", "-0.3",
            ],
        );
        assert_code(&o, 0);
        let out = fs::read_to_string(dir.path().join("out.obj")).unwrap();
        let g = groups(&out);
        assert_eq!(g.len(), 2 * n + 1);
        assert_eq!(g[n].0, "fill");
        assert!(g[n].1 > 100);
        assert_eq!(out.lines().filter(|l| l.starts_with("l ")).count(), n);
    }
}

#[test]
fn bad_inputs_exit_1_naming_the_item() {
    // Two curves are not a hole; a curve is not a patch to blend.
    let curves = r#"[
      {"type": "bspline-curve", "degree": 3, "knots": [0,0,0,0,1,1,1,1],
       "points": [[0,0,0],[1,0,0],[2,0,0],[3,0,0]]},
      {"type": "bspline-curve", "degree": 3, "knots": [0,0,0,0,1,1,1,1],
       "points": [[3,0,0],[3,1,0],[3,2,0],[3,3,0]]}
    ]"#;
    let dir = dir_with(&[("c.json", curves)]);
    let o = run_in(dir.path(), &["fill", "c.json", "-o", "out.obj"]);
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("sides of the hole: got 2"),
        "{}",
        stderr(&o)
    );
    let o = run_in(dir.path(), &["blend", "c.json", "-o", "out.obj"]);
    assert_code(&o, 1);
    assert!(stderr(&o).contains("c.json[0]: a curve"), "{}", stderr(&o));
    assert!(!dir.path().join("out.obj").exists());
    // Patches that do not share corners: the message names the patch.
    let moved = HOLE3.replacen("1.5,", "1.7,", 1);
    let dir = dir_with(&[("h.json", &moved)]);
    let o = run_in(dir.path(), &["fill", "h.json", "-o", "out.obj"]);
    assert_code(&o, 1);
    assert!(stderr(&o).contains("h.json["), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("does not share a corner"),
        "{}",
        stderr(&o)
    );
    // Usage errors exit 2.
    let o = run_in(
        dir.path(),
        &["fill", "h.json", "-o", "out.obj", "--levels", "99"],
    );
    assert_code(&o, 2);
}

#[test]
fn g1_fill_needs_patches_sharing_tangent_planes() {
    let dir = dir_with(&[("g1.json", HOLE3_G1), ("h.json", HOLE3)]);
    let o = run_in(
        dir.path(),
        &["fill", "g1.json", "-o", "out.obj", "--g1", "--levels", "3"],
    );
    assert_code(&o, 0);
    let g = groups(&fs::read_to_string(dir.path().join("out.obj")).unwrap());
    assert_eq!(g[3].0, "fill");
    assert!(g[3].1 > 100);
    // These patches were sampled from a height field: their tangent planes differ at the
    // corners, so no fill can meet them G1.
    let o = run_in(dir.path(), &["fill", "h.json", "-o", "out2.obj", "--g1"]);
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("do not share a tangent plane"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.path().join("out2.obj").exists());
}
