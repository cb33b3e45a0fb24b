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

#[test]
fn errors_name_the_input_file_or_standard_input() {
    let one_patch = {
        let v: serde_json::Value = serde_json::from_str(BLEND3).unwrap();
        serde_json::to_string(&serde_json::Value::Array(vec![v[0].clone()])).unwrap()
    };
    let two_curves = r#"[
      {"type": "bspline-curve", "degree": 3, "knots": [0,0,0,0,1,1,1,1],
       "points": [[0,0,0],[1,0,0],[2,0,0],[3,0,0]]},
      {"type": "bspline-curve", "degree": 3, "knots": [0,0,0,0,1,1,1,1],
       "points": [[3,0,0],[3,1,0],[3,2,0],[3,3,0]]}
    ]"#;
    let dir = dir_with(&[("c.json", two_curves), ("p.json", &one_patch)]);
    for (args, input, expected) in [
        (
            vec!["fill", "c.json"],
            None,
            "c.json: sides of the hole: got 2",
        ),
        (
            vec!["blend", "p.json"],
            None,
            "p.json: patches to blend: got 1",
        ),
        (
            vec!["fill", "-"],
            Some(two_curves),
            "<stdin>: sides of the hole: got 2",
        ),
        (
            vec!["blend", "-"],
            Some(one_patch.as_str()),
            "<stdin>: patches to blend: got 1",
        ),
        (vec!["blend", "-"], Some(two_curves), "<stdin>[0]: a curve"),
    ] {
        let mut all = args.clone();
        all.extend(["-o", "out.obj"]);
        let o = match input {
            Some(text) => run_with_stdin(dir.path(), &all, text),
            None => run_in(dir.path(), &all),
        };
        assert_code(&o, 1);
        assert!(
            stderr(&o).contains(&format!("error: {expected}")),
            "{args:?}: {}",
            stderr(&o)
        );
        assert!(!dir.path().join("out.obj").exists());
    }
}

#[test]
fn fill_refuses_a_bulge_that_would_overflow() {
    let dir = dir_with(&[("h.json", HOLE3)]);
    let o = run_in(
        dir.path(),
        &["fill", "h.json", "-o", "out.obj", "--bulge", "1e308"],
    );
    assert_code(&o, 1);
    let e = stderr(&o);
    assert!(
        e.starts_with("error: h.json: bulge 1e308 moves the fill's centre"),
        "{e}"
    );
    assert!(e.contains("use a smaller bulge"), "{e}");
    assert!(!dir.path().join("out.obj").exists());
    for bad in ["--bulge=inf", "--bulge=-inf", "--bulge=nan"] {
        let o = run_in(dir.path(), &["fill", "h.json", "-o", "out.obj", bad]);
        assert_code(&o, 2);
        assert!(
            stderr(&o).contains("is not a finite number"),
            "{}",
            stderr(&o)
        );
    }
    // Large but representable: accepted.
    let o = run_in(
        dir.path(),
        &[
            "fill", "h.json", "-o", "out.obj", "--bulge", "1e6", "--levels", "1",
        ],
    );
    assert_code(&o, 0);
}

/// `text` (a JSON array of patches) with `weights` added: `w(k, i, j)` for patch `k`.
fn with_weights(text: &str, w: impl Fn(usize, usize, usize) -> f64) -> String {
    let mut v: serde_json::Value = serde_json::from_str(text).unwrap();
    for (k, doc) in v.as_array_mut().unwrap().iter_mut().enumerate() {
        let rows = doc["points"].as_array().unwrap();
        let weights: Vec<Vec<f64>> = rows
            .iter()
            .enumerate()
            .map(|(i, row)| {
                (0..row.as_array().unwrap().len())
                    .map(|j| w(k, i, j))
                    .collect()
            })
            .collect();
        doc["weights"] = serde_json::json!(weights);
    }
    serde_json::to_string_pretty(&v).unwrap()
}

#[test]
fn nurbs_patches_are_blended_and_filled() {
    let ones = |_: usize, _: usize, _: usize| 1.0;
    let varied = |k: usize, i: usize, j: usize| 0.6 + 0.25 * ((k + 2 * i + 3 * j) % 4) as f64;
    for (cmd, text, extra) in [
        ("blend", BLEND3, vec![]),
        ("fill", HOLE3, vec![]),
        ("fill", HOLE3_G1, vec!["--g1"]),
    ] {
        let dir = dir_with(&[
            ("poly.json", text),
            ("ones.json", &with_weights(text, ones)),
            ("varied.json", &with_weights(text, varied)),
        ]);
        let run = |input: &str, out: &str| {
            let mut args = vec![cmd, input, "-o", out, "--levels", "2"];
            args.extend(&extra);
            run_in(dir.path(), &args)
        };
        assert_code(&run("poly.json", "poly.obj"), 0);
        // Weights 1: exactly the polynomial blend or fill (the tessellated base patches,
        // evaluated as NURBS, may differ in the last bits).
        assert_code(&run("ones.json", "ones.obj"), 0);
        let read = |f: &str| fs::read_to_string(dir.path().join(f)).unwrap();
        let group = |text: String| {
            let start = text
                .find(&format!("\ng {cmd}\n"))
                .expect("the method's group");
            let rest = &text[start + 1..];
            let end = rest[2..].find("\ng ").map_or(rest.len(), |e| e + 2);
            rest[..end].to_owned()
        };
        assert_eq!(
            group(read("ones.obj")),
            group(read("poly.obj")),
            "{cmd} {extra:?}"
        );
        let o = run("varied.json", "varied.obj");
        if extra.is_empty() {
            assert_code(&o, 0);
            assert_ne!(read("varied.obj"), read("poly.obj"));
        } else {
            // The G1 fill takes polynomial patches (or one weight per patch) only.
            assert_code(&o, 1);
            assert!(
                stderr(&o).contains("varied.json[0]: patch 0 is rational with unequal weights"),
                "{}",
                stderr(&o)
            );
        }
    }
}

#[test]
fn blend_and_fill_refuse_jobs_over_max_memory() {
    let dir = dir_with(&[("b.json", BLEND5), ("h.json", HOLE5)]);
    for args in [
        vec!["blend", "b.json", "--levels", "8"],
        vec!["fill", "h.json", "--levels", "8"],
        vec!["fill", "h.json", "--levels", "1", "--samples", "256"],
    ] {
        let mut all = args.clone();
        all.extend(["-o", "out.obj", "--max-memory", "32M"]);
        let o = run_in(dir.path(), &all);
        assert_code(&o, 1);
        let e = stderr(&o);
        let file = args[1];
        assert!(e.starts_with(&format!("error: {file}: ")), "{e}");
        assert!(
            e.contains("needs about")
                && e.contains("MiB, more than the limit of 32 MiB (--max-memory)"),
            "{e}"
        );
        assert!(!dir.path().join("out.obj").exists());
    }
}
