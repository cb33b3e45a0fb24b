//! `--scheme loop` and `--scheme bilinear`: refinement as the library's `subdivide` gives it
//! (with Loop, texture coordinates too), a quad for Loop refused naming the face, Loop's
//! and bilinear's limit surfaces tessellated and drawn, and `bench --scheme` timing the
//! scheme it names.

use crate::common;

use common::*;
use subsurf::io::parse_obj;
use subsurf::mesh::Options;
use subsurf::{Scheme, SubdivideOptions};

/// A square pyramid without its base, as four triangles, with a crease along one edge.
const TRIANGLES: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n\
                         f 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\nt crease 2/1/0 0 4 1.5\n";

/// The pyramid with texture coordinates: a seam along the edge 1-5 (its two faces give
/// vertex 1 the values 1 and 6), so the layout unfolds.
const TEXTURED: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n\
                        vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\nvt 0 0.2\n\
                        f 1/1 2/2 5/5\nf 2/2 3/3 5/5\nf 3/3 4/4 5/5\nf 4/4 1/6 5/5\n\
                        t crease 2/1/0 0 4 1.5\n";

/// The same with the last two triangles as one quad.
const WITH_QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n\
                         f 1 2 5\nf 2 3 5\nf 3 4 1 5\n";

fn library(scheme: Scheme, levels: u32) -> subsurf::mesh::PolyMesh {
    let input = parse_obj(TRIANGLES.as_bytes(), "tri.obj").expect("valid OBJ");
    let opts = SubdivideOptions {
        levels,
        scheme,
        options: input.options.resolve(Options::default()),
        ..Default::default()
    };
    subsurf::subdivide(&input.mesh, &opts)
        .expect("refines")
        .mesh
}

#[test]
fn loop_and_bilinear_refine_as_the_library() {
    let dir = dir_with(&[("tri.obj", TRIANGLES)]);
    for (name, scheme) in [("loop", Scheme::Loop), ("bilinear", Scheme::Bilinear)] {
        let out = format!("{name}.obj");
        let o = run_in(
            dir.path(),
            &[
                "subdivide",
                "tri.obj",
                "-o",
                &out,
                "-l",
                "2",
                "--scheme",
                name,
            ],
        );
        assert_code(&o, 0);
        let text = std::fs::read_to_string(dir.path().join(&out)).expect("output written");
        assert!(
            text.contains(&format!("--scheme {name}")),
            "the header names the scheme: {text:.300}"
        );
        let got = parse_obj(text.as_bytes(), &out).expect("valid output");
        let want = library(scheme, 2);
        assert_eq!(got.mesh.positions(), want.positions(), "{name}");
        assert_eq!(got.mesh.face_verts(), want.face_verts(), "{name}");
        let sizes: Vec<usize> = got.mesh.faces().map(<[u32]>::len).collect();
        let n = if scheme == Scheme::Loop { 3 } else { 4 };
        assert!(sizes.iter().all(|&s| s == n), "{name}: faces of {n}");
    }
    // Loop and Catmull-Clark differ: the scheme is not ignored.
    assert_ne!(
        library(Scheme::Loop, 1).positions(),
        library(Scheme::CatmullClark, 1).positions()
    );
}

/// Loop refines texture coordinates (face-varying data) as the library does and writes them
/// as `vt` lines and `f v/vt` faces, without a warning; with `--limit` it is refused as
/// without them.
#[test]
fn loop_writes_refined_texture_coordinates() {
    let dir = dir_with(&[("uv.obj", TEXTURED)]);
    let args = [
        "subdivide",
        "uv.obj",
        "-o",
        "out.obj",
        "-l",
        "2",
        "--scheme",
        "loop",
    ];
    let o = run_in(dir.path(), &args);
    assert_code(&o, 0);
    assert!(!stderr(&o).contains("texture"), "{}", stderr(&o));
    let text = std::fs::read_to_string(dir.path().join("out.obj")).expect("output written");
    let got = parse_obj(text.as_bytes(), "out.obj").expect("valid output");
    let input = parse_obj(TEXTURED.as_bytes(), "uv.obj").expect("valid OBJ");
    let opts = SubdivideOptions {
        levels: 2,
        scheme: Scheme::Loop,
        options: input.options.resolve(Options::default()),
        ..Default::default()
    };
    let want = subsurf::subdivide(&input.mesh, &opts)
        .expect("refines")
        .mesh;
    let (g, w) = (&got.mesh.face_varying, &want.face_varying);
    assert_eq!((g.len(), w.len()), (1, 1), "one uv channel");
    assert_eq!(g[0].indices(), w[0].indices());
    assert_eq!(g[0].values(), w[0].values());
    // The seam gives its vertices and the children of its edges two values each.
    assert!(count_records(&text, "vt") > got.mesh.num_vertices());
    assert!(text.lines().any(|l| l.starts_with("f ") && l.contains('/')));
    // With --limit the texture coordinates move to their limit too (checked against
    // OpenSubdiv by the library's `loop_limit_with_texture_coordinates_matches_opensubdiv`).
    let mut limit = args;
    limit[3] = "lim.obj";
    let o = run_in(dir.path(), &[&limit[..], &["--limit"]].concat());
    assert_code(&o, 0);
    let text = std::fs::read_to_string(dir.path().join("lim.obj")).expect("output written");
    let lim = parse_obj(text.as_bytes(), "lim.obj").expect("valid output");
    let linear = &lim.mesh.face_varying[0];
    assert_eq!(linear.indices(), w[0].indices());
    // In mode `all` (the default) they are linear: their limit is where they are.
    assert_eq!(linear.values(), w[0].values());
    assert_eq!(
        count_records(&text, "vn"),
        lim.mesh.num_vertices(),
        "limit normals"
    );
    limit[3] = "smooth.obj";
    let o = run_in(
        dir.path(),
        &[&limit[..], &["--limit", "--fvar", "none"]].concat(),
    );
    assert_code(&o, 0);
    let text = std::fs::read_to_string(dir.path().join("smooth.obj")).expect("output written");
    let smooth = parse_obj(text.as_bytes(), "smooth.obj").expect("valid output");
    assert_ne!(
        smooth.mesh.face_varying[0].values(),
        linear.values(),
        "mode none moves them"
    );
}

#[test]
fn loop_refuses_a_quad_naming_it() {
    let dir = dir_with(&[("quad.obj", WITH_QUAD)]);
    let o = run_in(
        dir.path(),
        &["subdivide", "quad.obj", "-o", "out.obj", "--scheme", "loop"],
    );
    assert_code(&o, 1);
    let err = stderr(&o);
    assert!(err.contains("quad.obj") && err.contains("face"), "{err}");
    assert!(!dir.path().join("out.obj").exists());
}

/// `tessellate --scheme bilinear` writes the library's tessellation of the bilinear limit
/// surface (the control mesh itself, n-gons through their sub-faces); `render --scheme
/// bilinear` draws it; `--c` is refused.
#[test]
fn bilinear_tessellates_and_renders_its_limit_surface() {
    use subsurf::limit::{tessellate, BilinearSurface};
    let dir = dir_with(&[("mixed.obj", WITH_QUAD)]);
    let args = ["tessellate", "mixed.obj", "-o", "t.obj", "--rate", "2"];
    let o = run_in(dir.path(), &[&args[..], &["--scheme", "bilinear"]].concat());
    assert_code(&o, 0);
    let text = std::fs::read_to_string(dir.path().join("t.obj")).expect("output written");
    assert!(
        text.contains("subsurf tessellate --scheme bilinear"),
        "{text:.300}"
    );
    let got = parse_obj(text.as_bytes(), "t.obj").expect("valid output");
    let input = parse_obj(WITH_QUAD.as_bytes(), "mixed.obj").expect("valid OBJ");
    let surface = BilinearSurface::new(&input.mesh).expect("a bilinear surface");
    let want = tessellate(&surface, &input.mesh, 2, false).expect("tessellates");
    assert_eq!(got.mesh.face_verts(), &want.face_verts[..]);
    assert_eq!(got.mesh.positions(), &want.positions[..]);
    // Two triangles (three sub-faces each) and a quad, at rate 2.
    assert_eq!(got.mesh.num_faces(), 2 * 3 + 4);
    for (extra, code) in [(&[][..], 0), (&["--c", "0.3"][..], 2)] {
        let args = [
            &["render", "mixed.obj", "-o", "b.png", "--scheme", "bilinear"][..],
            extra,
        ];
        let o = run_in(dir.path(), &args.concat());
        assert_code(&o, code);
        assert_eq!(dir.path().join("b.png").exists(), code == 0, "{extra:?}");
        let _ = std::fs::remove_file(dir.path().join("b.png"));
    }
}

/// `tessellate --scheme loop` writes the library's tessellation of the Loop limit surface
/// (`rate²` triangles per triangle, texture coordinates at their limit, the scheme in the
/// header); `render --scheme loop` draws it, differently from Catmull-Clark's surface of
/// the same triangles; NURSS, `--c` and quads are refused.
#[test]
fn loop_tessellates_and_renders_its_limit_surface() {
    use subsurf::limit::{tessellate, LoopSurface};
    let dir = dir_with(&[("uv.obj", TEXTURED), ("quad.obj", WITH_QUAD)]);
    let o = run_in(
        dir.path(),
        &[
            "tessellate",
            "uv.obj",
            "-o",
            "t.obj",
            "--rate",
            "4",
            "--scheme",
            "loop",
        ],
    );
    assert_code(&o, 0);
    let text = std::fs::read_to_string(dir.path().join("t.obj")).expect("output written");
    assert!(
        text.contains("subsurf tessellate --scheme loop --rate 4"),
        "{text:.300}"
    );
    let got = parse_obj(text.as_bytes(), "t.obj").expect("valid output");
    let input = parse_obj(TEXTURED.as_bytes(), "uv.obj").expect("valid OBJ");
    let options = input.options.resolve(Options::default());
    let surface = LoopSurface::new(&input.mesh, options).expect("a Loop surface");
    let want = tessellate(&surface, &input.mesh, 4, false).expect("tessellates");
    assert_eq!(got.mesh.num_faces(), 4 * 16);
    assert_eq!(got.mesh.face_verts(), &want.face_verts[..]);
    assert_eq!(got.mesh.positions(), &want.positions[..]);
    // The seam along edge 1-5 gives vertex 1 and the 3 samples inside the edge a texture
    // coordinate per side (the apex has one).
    let uv = &got.mesh.face_varying[0];
    assert_eq!(uv.num_values(), want.num_vertices() + 4);

    let render = |extra: &[&str]| {
        let args = [
            &[
                "render", "uv.obj", "-o", "z.png", "--zebra", "--size", "64x48",
            ],
            extra,
        ];
        let o = run_in(dir.path(), &args.concat());
        let png = std::fs::read(dir.path().join("z.png")).ok();
        let _ = std::fs::remove_file(dir.path().join("z.png"));
        (o, png)
    };
    let (o, loop_png) = render(&["--scheme", "loop"]);
    assert_code(&o, 0);
    let (o, cc_png) = render(&[]);
    assert_code(&o, 0);
    assert!(loop_png.is_some() && loop_png != cc_png);
    for (extra, code) in [
        (&["--scheme", "nurss"][..], 2),
        (&["--scheme", "loop", "--c", "0.3"][..], 2),
    ] {
        let (o, png) = render(extra);
        assert_code(&o, code);
        assert!(png.is_none(), "{extra:?}");
    }
    let o = run_in(
        dir.path(),
        &["render", "quad.obj", "-o", "q.png", "--scheme", "loop"],
    );
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("quad.obj") && stderr(&o).contains("face"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.path().join("q.png").exists());
}

/// `bench --scheme loop|bilinear` refines (and with `--replay` re-poses) with that scheme:
/// the vertex count it prints is the scheme's; the schemes OpenSubdiv does not have are
/// usage errors.
#[test]
fn bench_times_the_scheme_it_names() {
    let dir = dir_with(&[("tri.obj", TRIANGLES)]);
    for (name, scheme) in [("loop", Scheme::Loop), ("bilinear", Scheme::Bilinear)] {
        let verts = library(scheme, 2).num_vertices();
        for replay in [false, true] {
            let mut args = vec![
                "bench", "tri.obj", "-l", "2", "--reps", "1", "--scheme", name,
            ];
            if replay {
                args.push("--replay");
            }
            let o = run_in(dir.path(), &args);
            assert_code(&o, 0);
            let out = stdout(&o);
            assert!(out.contains(&format!("verts={verts} ")), "{args:?}: {out}");
        }
    }
    let o = run_in(dir.path(), &["bench", "tri.obj", "--scheme", "nurss"]);
    assert_code(&o, 2);
    assert!(
        stderr(&o).contains("OpenSubdiv's schemes"),
        "{}",
        stderr(&o)
    );
}

/// `bench --scheme loop --limit-grid N` times the Loop limit surface on the triangular
/// grid of `N` points a side on every triangle (as `osd-oracle benchlimit --scheme loop`):
/// `N (N + 1) / 2` points a face, cold and warm times; bilinear has no limit to time.
#[test]
fn bench_times_the_loop_limit_on_triangular_grids() {
    let dir = dir_with(&[("tri.obj", TRIANGLES)]);
    let faces = count_records(TRIANGLES, "f");
    let o = run_in(
        dir.path(),
        &[
            "bench",
            "tri.obj",
            "--scheme",
            "loop",
            "--limit-grid",
            "4",
            "--reps",
            "2",
        ],
    );
    assert_code(&o, 0);
    let out = stdout(&o);
    assert!(out.contains(&format!("points={} ", faces * 10)), "{out}");
    for field in ["cold_s=", "median_s=", "min_s="] {
        assert!(out.contains(field), "{out}");
    }
    let o = run_in(
        dir.path(),
        &[
            "bench",
            "tri.obj",
            "--scheme",
            "bilinear",
            "--limit-grid",
            "4",
        ],
    );
    assert_code(&o, 2);
    assert!(
        stderr(&o).contains("Catmull-Clark and Loop"),
        "{}",
        stderr(&o)
    );
}
