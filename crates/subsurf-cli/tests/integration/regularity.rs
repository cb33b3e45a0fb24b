//! End-to-end tests of `subsurf regularity`, each in its own temporary directory.

use crate::common;
use common::*;

use std::fs;

const GEAR: &str = include_str!("../../../../examples/meshes/regularity-gear.obj");
const DOLPHIN: &str = include_str!("../../../../examples/meshes/regularity-dolphin.obj");
const BUTTERFLY: &str = include_str!("../../../../examples/meshes/regularity-butterfly.obj");

/// A 5×2 planar grid whose columns 2 and 3 swap places: the net and its limit fold.
fn folded() -> String {
    let xs = [0.0, 1.0, 3.5, 2.5, 4.0, 5.0];
    let mut s = String::from("t interpolateboundary 1/0/0 1\n");
    for j in 0..3 {
        for x in xs {
            s += &format!("v {x} {j} 0\n");
        }
    }
    for j in 0..2 {
        for i in 0..5 {
            let a = j * 6 + i + 1;
            s += &format!("f {} {} {} {}\n", a, a + 1, a + 7, a + 6);
        }
    }
    s
}

#[test]
fn the_papers_kind_of_examples_are_certified_locally() {
    let dir = dir_with(&[
        ("gear.obj", GEAR),
        ("dolphin.obj", DOLPHIN),
        ("butterfly.obj", BUTTERFLY),
    ]);
    for name in ["gear.obj", "dolphin.obj", "butterfly.obj"] {
        let o = run_in(dir.path(), &["regularity", name, "--local"]);
        assert_code(&o, 0);
        let out = stdout(&o);
        assert!(out.contains("planar net"), "{out}");
        assert!(
            out.contains("verdict (local certificate): the limit surface is regular"),
            "{out}"
        );
        assert!(out.contains(" 0 not regular"), "{out}");
    }
}

#[test]
fn a_ring_is_not_certified_globally_exit_3() {
    let dir = dir_with(&[("gear.obj", GEAR), ("butterfly.obj", BUTTERFLY)]);
    let o = run_in(dir.path(), &["regularity", "gear.obj"]);
    assert_code(&o, 3);
    let out = stdout(&o);
    assert!(
        out.contains("verdict (global certificate): not certified"),
        "{out}"
    );
    assert!(
        out.contains("local certificate succeeds where the global one fails: 144 faces"),
        "{out}"
    );
    // The butterfly's two fans are disjoint: certified by Theorem 3 itself.
    let o = run_in(dir.path(), &["regularity", "butterfly.obj"]);
    assert_code(&o, 0);
}

#[test]
fn a_folded_net_is_refused_with_the_face_named() {
    let dir = dir_with(&[("folded.obj", &folded())]);
    let o = run_in(dir.path(), &["regularity", "folded.obj", "--local"]);
    assert_code(&o, 3);
    let out = stdout(&o);
    assert!(out.contains("face 2: refused"), "{out}");
    assert!(out.contains("sampled NOT regular"), "{out}");
}

#[test]
fn json_report_has_the_documented_fields() {
    let dir = dir_with(&[("folded.obj", &folded())]);
    let o = run_in(
        dir.path(),
        &[
            "regularity",
            "folded.obj",
            "--local",
            "--json",
            "--sample",
            "5",
        ],
    );
    assert_code(&o, 3);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    assert_eq!(v["file"], "folded.obj");
    assert_eq!(v["dimension"], "planar");
    assert_eq!(v["orientation"], 1);
    assert_eq!(v["mode"], "local");
    assert_eq!(v["certified"], false);
    assert_eq!(v["samples"], 5);
    assert_eq!(v["counts"]["faces"], 10);
    let faces = v["faces"].as_array().expect("faces");
    assert_eq!(faces.len(), 10);
    let f2 = &faces[2];
    assert_eq!(f2["face"], 2);
    assert_eq!(f2["local"], "refused");
    assert!(f2["local_reason"].as_str().is_some());
    assert_eq!(f2["class"], "not-regular");
    assert!(f2["worst_sample"]["value"].as_f64().expect("value") <= 0.0);
    let c = &v["counts"];
    let sum = ["certified", "refused", "not_applicable"]
        .iter()
        .map(|k| c[k].as_u64().expect("count"))
        .sum::<u64>();
    assert_eq!(sum, 10);
    assert!(v["components"].as_array().is_some());
}

#[test]
fn plots_are_written_as_svg_or_png() {
    let dir = dir_with(&[("dolphin.obj", DOLPHIN)]);
    let o = run_in(
        dir.path(),
        &[
            "regularity",
            "dolphin.obj",
            "--local",
            "--plot",
            "fans.svg",
            "--sample",
            "0",
        ],
    );
    assert_code(&o, 0);
    let svg = fs::read_to_string(dir.path().join("fans.svg")).expect("svg written");
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(
        svg.contains("#2850dc") && svg.contains("#d72828"),
        "blue u and red v lines"
    );
    let o = run_in(
        dir.path(),
        &["regularity", "dolphin.obj", "--plot", "fans.png"],
    );
    assert_code(&o, 3); // not certified globally, but the picture is drawn
    let png = fs::read(dir.path().join("fans.png")).expect("png written");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
}

#[test]
fn bad_input_exits_1_and_usage_errors_2() {
    let dir = dir_with(&[("bad.obj", "v 0 0 0\nf 1 2 3\n"), ("ok.obj", BUTTERFLY)]);
    assert_code(&run_in(dir.path(), &["regularity", "missing.obj"]), 1);
    let o = run_in(dir.path(), &["regularity", "bad.obj"]);
    assert_code(&o, 1);
    assert!(stderr(&o).contains("bad.obj"), "{}", stderr(&o));
    assert_code(
        &run_in(dir.path(), &["regularity", "ok.obj", "--sample", "1"]),
        2,
    );
    assert_code(
        &run_in(dir.path(), &["regularity", "ok.obj", "--plot", "x.gif"]),
        2,
    );
    // A plot into a missing directory fails before any work, with exit 1.
    assert_code(
        &run_in(
            dir.path(),
            &["regularity", "ok.obj", "--plot", "no/such/x.svg"],
        ),
        1,
    );
}

#[test]
fn reads_standard_input_and_forces_planar() {
    let dir = dir_with(&[]);
    // The butterfly lifted to z = 1: spatial by default, planar with --planar.
    let lifted = BUTTERFLY.replace(" 0\n", " 1\n");
    let o = run_with_stdin(
        dir.path(),
        &["regularity", "-", "--json", "--sample", "3"],
        &lifted,
    );
    assert_code(&o, 0);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    assert_eq!(v["dimension"], "spatial");
    assert_eq!(v["file"], "<stdin>");
    let o = run_with_stdin(
        dir.path(),
        &["regularity", "-", "--json", "--planar"],
        &lifted,
    );
    assert_code(&o, 0);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    assert_eq!(v["dimension"], "planar");
}

/// Sampling and plotting are refused up front above --max-memory (exit 1, no plot).
#[test]
fn jobs_over_max_memory_are_refused_up_front() {
    let dir = dir_with(&[("gear.obj", GEAR)]);
    for args in [
        vec!["--sample", "1024"],
        vec!["--sample", "0", "--plot", "fans.svg"],
    ] {
        let mut all = vec!["regularity", "gear.obj", "--max-memory", "100K"];
        all.extend(&args);
        let o = run_in(dir.path(), &all);
        assert_code(&o, 1);
        let e = stderr(&o);
        assert!(e.starts_with("error: gear.obj: "), "{e}");
        assert!(
            e.contains("more than the limit of 100 KiB (--max-memory)"),
            "{e}"
        );
        assert!(!dir.path().join("fans.svg").exists());
    }
    let o = run_in(
        dir.path(),
        &["regularity", "gear.obj", "--local", "--max-memory", "256M"],
    );
    assert_code(&o, 0);
}
