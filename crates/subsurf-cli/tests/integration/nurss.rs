//! End-to-end tests of non-uniform Catmull-Clark on the command line: `--scheme nurss`, its
//! default for files with knot tags, refined intervals in the output, `--limit`, `info`, and
//! errors naming `file:line` for bad `t interval` / `t sideinterval` / `t weight` tags.

use crate::common;

use common::*;
use subsurf::io::parse_obj;
use subsurf::mesh::Options;
use subsurf::nonuniform::Nurss;
use subsurf::{Scheme, SubdivideOptions};

/// The bundled example: a 5×5 grid with intervals 3 and 0.
const GRID: &str = include_str!("../../../../examples/meshes/nurss-grid.obj");

fn read(dir: &std::path::Path, name: &str) -> subsurf::io::ObjFile {
    let text = std::fs::read(dir.join(name)).expect("output written");
    parse_obj(&text, name).expect("output reads back")
}

#[test]
fn knot_tags_select_nurss_with_a_note() {
    let dir = dir_with(&[("grid.obj", GRID)]);
    let o = run_in(
        dir.path(),
        &["subdivide", "grid.obj", "-o", "out.obj", "-l", "2"],
    );
    assert_code(&o, 0);
    assert!(
        stderr(&o).contains("note: grid.obj has knot interval or weight tags"),
        "{}",
        stderr(&o)
    );
    // Same result as the library's NURSS, and the refined intervals are in the output.
    let out = read(dir.path(), "out.obj");
    let input = parse_obj(GRID.as_bytes(), "grid.obj").unwrap();
    let opts = SubdivideOptions {
        levels: 2,
        scheme: Scheme::Nurss,
        options: input.options.resolve(Options::default()),
        ..Default::default()
    };
    let lib = subsurf::subdivide(&input.mesh, &opts).unwrap();
    assert_eq!(out.mesh.positions(), lib.mesh.positions());
    assert_eq!(out.mesh.knots, lib.mesh.knots);
    assert!(out.mesh.knots.intervals.iter().any(|t| t.interval == 0.75));
    // --quiet silences the note; --scheme catmull-clark ignores the tags (another surface).
    let o = run_in(
        dir.path(),
        &["subdivide", "grid.obj", "-o", "q.obj", "-l", "2", "-q"],
    );
    assert_code(&o, 0);
    assert_eq!(stderr(&o), "");
    let o = run_in(
        dir.path(),
        &[
            "subdivide",
            "grid.obj",
            "-o",
            "cc.obj",
            "-l",
            "2",
            "--scheme",
            "catmull-clark",
        ],
    );
    assert_code(&o, 0);
    assert!(!stderr(&o).contains("note:"));
    let cc = read(dir.path(), "cc.obj");
    assert!(cc.mesh.knots.is_empty());
    assert_ne!(cc.mesh.positions(), out.mesh.positions());
    // `bench` times Catmull-Clark (as `osd-oracle bench`), and says so.
    for extra in [&[][..], &["--replay"][..]] {
        let mut args = vec!["bench", "grid.obj", "-l", "2", "--reps", "1"];
        args.extend_from_slice(extra);
        let o = run_in(dir.path(), &args);
        assert_code(&o, 0);
        assert!(
            stderr(&o).contains(
                "note: grid.obj has knot interval or weight tags: bench times Catmull-Clark"
            ),
            "{}",
            stderr(&o)
        );
    }
}

#[test]
fn refining_a_then_b_levels_equals_a_plus_b() {
    let dir = dir_with(&[("grid.obj", GRID)]);
    for (args, _) in [
        (
            vec!["subdivide", "grid.obj", "-o", "l3.obj", "-l", "3", "-q"],
            0,
        ),
        (
            vec!["subdivide", "grid.obj", "-o", "l1.obj", "-l", "1", "-q"],
            0,
        ),
        (
            vec!["subdivide", "l1.obj", "-o", "l12.obj", "-l", "2", "-q"],
            0,
        ),
    ] {
        assert_code(&run_in(dir.path(), &args), 0);
    }
    let (a, b) = (read(dir.path(), "l3.obj"), read(dir.path(), "l12.obj"));
    assert_eq!(a.mesh.num_faces(), b.mesh.num_faces());
    // Edge points are numbered by the edges of the file read, so compare faces' corners.
    for (fa, fb) in a.mesh.faces().zip(b.mesh.faces()) {
        for (&va, &vb) in fa.iter().zip(fb) {
            let (p, q) = (
                a.mesh.positions()[va as usize],
                b.mesh.positions()[vb as usize],
            );
            assert!((0..3).all(|k| (p[k] - q[k]).abs() < 1e-13), "{p:?} {q:?}");
        }
    }
}

#[test]
fn limit_moves_to_the_nurss_limit_points() {
    let dir = dir_with(&[("grid.obj", GRID)]);
    let o = run_in(
        dir.path(),
        &[
            "subdivide",
            "grid.obj",
            "-o",
            "lim.obj",
            "-l",
            "1",
            "--limit",
            "-q",
        ],
    );
    assert_code(&o, 0);
    let out = read(dir.path(), "lim.obj");
    let input = parse_obj(GRID.as_bytes(), "grid.obj").unwrap();
    let mut s = Nurss::new(&input.mesh, &input.options.resolve(Options::default())).unwrap();
    s.step();
    assert_eq!(out.mesh.positions(), &s.limit_points()[..]);
}

#[test]
fn info_shows_knot_statistics() {
    let dir = dir_with(&[("grid.obj", GRID)]);
    let o = run_in(dir.path(), &["info", "grid.obj"]);
    assert_code(&o, 0);
    let text = stdout(&o);
    assert!(
        text.contains("15 tagged edges, from 0 to 3, 5 zero"),
        "{text}"
    );
    let o = run_in(dir.path(), &["info", "grid.obj", "--json"]);
    assert_code(&o, 0);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["knots"]["tagged_edges"], 15);
    assert_eq!(v["knots"]["zero_interval_edges"], 5);
    assert_eq!(v["knots"]["max_interval"], 3.0);
    assert_eq!(v["knots"]["weighted_vertices"], 0);
}

const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

#[test]
fn bad_knot_tags_name_file_and_line() {
    let cases = [
        (
            "t interval 2/1/0 0 2 1\n",
            "bad.obj:6: t interval: the mesh has no edge between vertices 0 and 2",
        ),
        (
            "t interval 2/1/0 0 1 -1\n",
            "bad.obj:6: t interval: knot interval '-1' must be a finite number ≥ 0",
        ),
        (
            "t interval 2/1/0 0 1 inf\n",
            "bad.obj:6: t interval: knot interval 'inf'",
        ),
        (
            "t interval 2/1/0 1 1 2\n",
            "bad.obj:6: t interval: an edge needs two different vertices",
        ),
        (
            "t interval 2/1/0 0 9 2\n",
            "bad.obj:6: t interval: vertex index 9 is out of range",
        ),
        (
            "t sideinterval 3/1/0 0 0 2 1\n",
            "bad.obj:6: t sideinterval: face 0 has no edge between vertices 0 and 2",
        ),
        (
            "t sideinterval 3/1/0 3 0 1 1\n",
            "bad.obj:6: t sideinterval: face index 3 is out of range",
        ),
        (
            "t weight 1/1/0 2 0\n",
            "bad.obj:6: t weight: rational weight '0' must be a finite number > 0",
        ),
        (
            "t weight 1/1/0 2 nan\n",
            "bad.obj:6: t weight: rational weight 'nan'",
        ),
        (
            "t interval 3/1/0 0 1 2 1\n",
            "bad.obj:6: t interval: unexpected counts 3/1/0",
        ),
    ];
    for (tag, expected) in cases {
        let text = format!("{QUAD}{tag}");
        let dir = dir_with(&[("bad.obj", &text)]);
        let o = run_in(dir.path(), &["subdivide", "bad.obj", "-o", "out.obj"]);
        assert_code(&o, 1);
        assert!(stderr(&o).contains(expected), "{tag}: {}", stderr(&o));
        assert_eq!(listing(dir.path()), vec!["bad.obj"], "no output on error");
    }
}

#[test]
fn semi_sharp_creases_are_a_clear_error_with_nurss() {
    let text = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nf 1 2 5 4\nf 2 3 6 5\n\
                t crease 2/1/0 1 4 2.5\nt interval 2/1/0 0 1 2\n";
    let dir = dir_with(&[("c.obj", text)]);
    let o = run_in(dir.path(), &["subdivide", "c.obj", "-o", "out.obj", "-q"]);
    assert_code(&o, 1);
    assert!(stderr(&o).contains("sharpness 2.5"), "{}", stderr(&o));
    assert!(stderr(&o).contains("NURSS"), "{}", stderr(&o));
}

#[test]
fn unknown_scheme_is_a_usage_error() {
    let dir = dir_with(&[("grid.obj", GRID)]);
    let o = run_in(
        dir.path(),
        &[
            "subdivide",
            "grid.obj",
            "-o",
            "x.obj",
            "--scheme",
            "doo-sabin",
        ],
    );
    assert_code(&o, 2);
    assert!(stderr(&o).contains("nurss"), "{}", stderr(&o));
    // --c belongs to the adjustable scheme only.
    let o = run_in(
        dir.path(),
        &[
            "subdivide",
            "grid.obj",
            "-o",
            "x.obj",
            "--scheme",
            "nurss",
            "--c",
            "0.3",
        ],
    );
    assert_code(&o, 2);
}

#[test]
fn tessellate_samples_the_nurss_limit_through_refinement() {
    let dir = dir_with(&[("grid.obj", GRID)]);
    let o = run_in(
        dir.path(),
        &["tessellate", "grid.obj", "-o", "t.obj", "--rate", "3"],
    );
    assert_code(&o, 0);
    let err = stderr(&o);
    assert!(
        err.contains("sampling the non-uniform (NURSS) surface"),
        "{err}"
    );
    assert!(err.contains("rate 3 rounded up to 4"), "{err}");
    // Every sample is a NURSS limit point of level 2 (what subdivide --limit -l 2 writes).
    let o = run_in(
        dir.path(),
        &[
            "subdivide",
            "grid.obj",
            "-o",
            "l2.obj",
            "-l",
            "2",
            "--limit",
            "-q",
        ],
    );
    assert_code(&o, 0);
    let t = read(dir.path(), "t.obj");
    let l2 = read(dir.path(), "l2.obj");
    assert_eq!(t.mesh.num_vertices(), l2.mesh.num_vertices());
    for p in t.mesh.positions() {
        assert!(
            l2.mesh.positions().contains(p),
            "{p:?} is not a limit point"
        );
    }
    assert_eq!(t.normals.len(), t.mesh.num_vertices());
    // --scheme catmull-clark samples the other surface; --c with nurss is a usage error.
    let o = run_in(
        dir.path(),
        &[
            "tessellate",
            "grid.obj",
            "-o",
            "cc.obj",
            "--rate",
            "4",
            "--scheme",
            "catmull-clark",
        ],
    );
    assert_code(&o, 0);
    assert_ne!(
        read(dir.path(), "cc.obj").mesh.positions(),
        t.mesh.positions()
    );
    let o = run_in(
        dir.path(),
        &[
            "tessellate",
            "grid.obj",
            "-o",
            "x.obj",
            "--rate",
            "4",
            "--scheme",
            "nurss",
            "--c",
            "0.3",
        ],
    );
    assert_code(&o, 2);
}

/// A 4 × 4 grid of quads with unequal intervals along one column and texture coordinates
/// cut along the column `x = 2` (the right island's values shifted by `(0.05, 0)`).
fn seam_grid() -> String {
    let mut s = String::new();
    for j in 0..5 {
        for i in 0..5 {
            s += &format!("v {i} {j} {}\n", 0.1 * f64::from((i * j) % 3));
        }
    }
    for (shift, columns) in [(0.0, 0..3), (0.05, 2..5)] {
        for j in 0..5 {
            for i in columns.clone() {
                s += &format!("vt {} {}\n", f64::from(i) / 4.0 + shift, f64::from(j) / 4.0);
            }
        }
    }
    // Left island: vt 3 j + i + 1 (i ≤ 2); right island: 16 + 3 j + (i − 2).
    let vt = |i: u32, j: u32, right: bool| {
        if right {
            16 + 3 * j + (i - 2)
        } else {
            3 * j + i + 1
        }
    };
    for j in 0..4 {
        for i in 0..4 {
            let right = i >= 2;
            let c = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let corners: Vec<String> = (c.iter())
                .map(|&(a, b)| format!("{}/{}", 5 * b + a + 1, vt(a, b, right)))
                .collect();
            s += &format!("f {}\n", corners.join(" "));
        }
    }
    for j in 0..5 {
        s += &format!("t interval 2/1/0 {} {} 3\n", 5 * j + 1, 5 * j + 2);
    }
    s + "t facevaryinginterpolateboundary 1/0/0 0\n"
}

/// Texture coordinates are refined with NURSS as the library refines them and written as
/// `vt` lines and `f v/vt` faces consistent with the `f` lines (the seam keeps two values
/// per vertex), without a warning; `--limit` moves them to the library's limit.
#[test]
fn texture_coordinates_are_refined_and_written() {
    let text = seam_grid();
    let dir = dir_with(&[("uv.obj", &text)]);
    let input = parse_obj(text.as_bytes(), "uv.obj").unwrap();
    for limit in [false, true] {
        let mut args = vec!["subdivide", "uv.obj", "-o", "out.obj", "-l", "2"];
        if limit {
            args.push("--limit");
        }
        let o = run_in(dir.path(), &args);
        assert_code(&o, 0);
        assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
        let out = read(dir.path(), "out.obj");
        let opts = SubdivideOptions {
            levels: 2,
            scheme: Scheme::Nurss,
            options: input.options.resolve(Options::default()),
            limit,
            ..Default::default()
        };
        let lib = subsurf::subdivide(&input.mesh, &opts).unwrap().mesh;
        assert_eq!(out.mesh.face_verts(), lib.face_verts());
        let (g, w) = (&out.mesh.face_varying, &lib.face_varying);
        assert_eq!((g.len(), w.len()), (1, 1), "one uv channel");
        assert_eq!(g[0].indices(), w[0].indices());
        assert_eq!(g[0].values(), w[0].values());
        // 17 × 17 vertices, and a second value on each of the seam's 17.
        assert_eq!(g[0].num_values(), 17 * 17 + 17);
    }
}

/// `tessellate` writes the NURSS limit of the texture coordinates at the samples (the
/// library's `nonuniform::tessellate`), no note.
#[test]
fn tessellate_writes_nurss_texture_coordinates() {
    let text = seam_grid();
    let dir = dir_with(&[("uv.obj", &text)]);
    let o = run_in(
        dir.path(),
        &["tessellate", "uv.obj", "-o", "t.obj", "--rate", "4"],
    );
    assert_code(&o, 0);
    assert!(!stderr(&o).contains("texture"), "{}", stderr(&o));
    let t = read(dir.path(), "t.obj");
    let input = parse_obj(text.as_bytes(), "uv.obj").unwrap();
    let options = input.options.resolve(Options::default());
    let lib = subsurf::nonuniform::tessellate(&input.mesh, &options, 4, false).unwrap();
    assert_eq!(t.mesh.face_verts(), &lib.face_verts[..]);
    let (g, w) = (&t.mesh.face_varying[0], &lib.face_varying[0]);
    assert_eq!(g.indices(), w.indices());
    assert_eq!(g.values(), w.values());
    assert_eq!(g.num_values(), 17 * 17 + 17);
}
