//! End-to-end tests of `subsurf limit` on faces that are not quads and on the other
//! surfaces (`--c`, knot tags and `--scheme`), each in its own temporary directory.

use crate::common;
use common::*;

use std::fs;

use subsurf::io::{parse_obj, write_obj, WriteOptions};
use subsurf::limit::{LimitSurface, Parameterization, SurfacePoint};
use subsurf::mesh::{Options, PolyMesh};

/// OpenSubdiv's `catmark_nonquads` (triangles, pentagons and hexagons among quads).
const NONQUADS: &str = include_str!("../../../subsurf/tests/shapes/osd/catmark_nonquads.obj");

/// The rows of a `limit` output: `face`, then the eleven numbers (and `s t` for a mesh with
/// texture coordinates).
fn rows(text: &str) -> Vec<(u32, Vec<f64>)> {
    text.lines()
        .map(|l| {
            let mut w = l.split_whitespace();
            let face = w.next().and_then(|x| x.parse().ok()).expect("face");
            let x: Vec<f64> = w.map(|t| t.parse().expect("number")).collect();
            assert!(x.len() == 11 || x.len() == 13, "{l}");
            (face, x)
        })
        .collect()
}

fn mesh_of(obj: &str) -> (PolyMesh, Options) {
    let f = parse_obj(obj.as_bytes(), "mesh.obj").expect("parse");
    let o = f.options.resolve(Options::default());
    (f.mesh, o)
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

/// Every face is sampled (triangles and `n`-gons wrote nothing before): a quad's grid as
/// `osd-oracle limit` prints it, each sub-face of another face in turn in `Bfr`'s `(u, v)`
/// of the face, with derivatives by those; the values are the library's at the sub-face's
/// `(s, t)`, the derivatives twice its.
#[test]
fn every_face_is_sampled_in_bfrs_parameterisation() {
    let dir = dir_with(&[("nonquads.obj", NONQUADS)]);
    let o = run_in(
        dir.path(),
        &["limit", "nonquads.obj", "--grid", "3", "-o", "out.tsv"],
    );
    assert_code(&o, 0);
    let out = rows(&fs::read_to_string(dir.path().join("out.tsv")).expect("out.tsv"));
    let (mesh, options) = mesh_of(NONQUADS);
    let surface = LimitSurface::new(&mesh, options).expect("surface");
    let mut expected = 0;
    let mut at = 0;
    for f in 0..mesh.num_faces() {
        let param = Parameterization::new(mesh.face(f).len());
        for sub in 0..param.num_subfaces() {
            for k in 0..9 {
                let (s, t) = ((k / 3) as f64 / 2.0, (k % 3) as f64 / 2.0);
                let (face, x) = &out[at];
                let (u, v) = param.to_face(sub, s, t);
                assert_eq!((*face as usize, x[0], x[1]), (f, u, v), "row {at}");
                let p = SurfacePoint {
                    face: f as u32,
                    subface: sub as u32,
                    u: s,
                    v: t,
                };
                let d = surface.eval_point(p).expect("eval");
                let k = param.derivative_scale();
                let want: Vec<f64> = (d.p.iter().copied())
                    .chain(d.du.iter().map(|x| k * x))
                    .chain(d.dv.iter().map(|x| k * x))
                    .collect();
                assert!(close(&x[2..], &want, 1e-12), "row {at}: {x:?} vs {want:?}");
                at += 1;
                expected += 1;
            }
        }
    }
    assert_eq!(out.len(), expected);
    // 9 triangles and n-gons among the faces: far more rows than the quads' alone.
    let quads = mesh.faces().filter(|f| f.len() == 4).count();
    assert!(out.len() > 9 * quads + 9 * 20, "{} rows", out.len());
}

/// A mesh of triangles only (a tetrahedron) writes 3 × N² rows per triangle: it wrote an
/// empty file with exit 0.
#[test]
fn triangles_are_sampled() {
    let tet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
    let dir = dir_with(&[("tet.obj", tet)]);
    let o = run_in(dir.path(), &["limit", "tet.obj", "--grid", "4", "-o", "-"]);
    assert_code(&o, 0);
    let out = rows(&stdout(&o));
    assert_eq!(out.len(), 4 * 3 * 16);
    // A triangle's tiles are two wide: sub-face 2 is in the second row.
    assert!(out.iter().any(|(_, x)| x[1] >= 1.0));
    assert!(out.iter().all(|(_, x)| x[0] <= 1.5 && x[1] <= 1.5));
}

/// A torus of 6 × 5 quads with knot intervals (every vertex regular, the intervals a
/// tensor product): the control mesh of a non-uniform periodic bicubic B-spline.
fn tagged_torus() -> String {
    let du = [1.0, 2.0, 1.0, 3.0, 1.5, 1.0];
    let dv = [1.0, 0.5, 2.0, 1.0, 1.0];
    let ku = subsurf::nurbs::KnotVector::periodic_from_intervals(3, &du).expect("knots");
    let kv = subsurf::nurbs::KnotVector::periodic_from_intervals(3, &dv).expect("knots");
    let mut points = Vec::new();
    for i in 0..du.len() {
        for j in 0..dv.len() {
            let (a, b) = (
                std::f64::consts::TAU * i as f64 / du.len() as f64,
                std::f64::consts::TAU * j as f64 / dv.len() as f64,
            );
            let r = 3.0 + b.cos();
            points.push([r * a.cos(), r * a.sin(), b.sin()]);
        }
    }
    let s = subsurf::nurbs::BSplineSurface::new(ku, kv, points).expect("spline");
    let mesh = s.control_mesh().expect("control mesh").mesh_with_knots();
    let mut text = Vec::new();
    write_obj(&mut text, &mesh, &WriteOptions::default()).expect("write");
    String::from_utf8(text).expect("utf-8")
}

/// Knot interval tags make `limit` sample the NURSS surface (it sampled Catmull-Clark's,
/// silently): with a note, as `tessellate` does; `--scheme nurss` is the same, `--scheme
/// catmull-clark` ignores the tags. The rows are the library's `NurssSurface`.
#[test]
fn knot_tags_and_scheme_choose_the_surface() {
    let torus = tagged_torus();
    assert!(torus.contains("t interval"), "{torus}");
    let dir = dir_with(&[("torus.obj", &torus)]);
    let run = |extra: &[&str]| {
        let mut args = vec!["limit", "torus.obj", "--grid", "3", "-o", "-"];
        args.extend_from_slice(extra);
        let o = run_in(dir.path(), &args);
        assert_code(&o, 0);
        (rows(&stdout(&o)), stderr(&o))
    };
    let (tagged, note) = run(&[]);
    assert!(note.contains("knot interval or weight tags"), "{note}");
    assert!(note.contains("NURSS"), "{note}");
    let (nurss, _) = run(&["--scheme", "nurss"]);
    let (cc, quiet) = run(&["--scheme", "catmull-clark"]);
    assert!(quiet.is_empty(), "{quiet}");
    assert_eq!(tagged, nurss);
    assert_eq!(tagged.len(), 30 * 9);
    let (mesh, options) = mesh_of(&torus);
    let reference = subsurf::nonuniform::NurssSurface::new(&mesh, &options).expect("nurss");
    let plain = LimitSurface::new(&mesh, options).expect("surface");
    let mut differ = 0.0f64;
    for ((face, x), (_, y)) in tagged.iter().zip(&cc) {
        let p = SurfacePoint {
            face: *face,
            subface: 0,
            u: x[0],
            v: x[1],
        };
        let d = reference.eval_point(p).expect("exact");
        let want: Vec<f64> = d.p.iter().chain(&d.du).chain(&d.dv).copied().collect();
        assert!(close(&x[2..], &want, 1e-12), "{x:?} vs {want:?}");
        let c = plain.eval_point(p).expect("cc");
        let want: Vec<f64> = c.p.iter().chain(&c.du).chain(&c.dv).copied().collect();
        assert!(close(&y[2..], &want, 1e-12), "{y:?} vs {want:?}");
        differ = differ.max((x[2] - y[2]).abs());
    }
    assert!(
        differ > 1e-3,
        "the NURSS and Catmull-Clark surfaces agree: {differ}"
    );
}

/// Where the NURSS surface has no closed form (here: unequal intervals at an
/// extraordinary vertex), `limit` says so, naming the face, and writes nothing: it gave
/// Catmull-Clark's numbers.
#[test]
fn nurss_faces_without_exact_evaluation_are_refused() {
    let mut obj = String::new();
    let (n, m) = (6u32, 6u32);
    for j in 0..m {
        for i in 0..n {
            let (a, b) = (
                std::f64::consts::TAU * f64::from(i) / f64::from(n),
                std::f64::consts::TAU * f64::from(j) / f64::from(m),
            );
            obj.push_str(&format!(
                "v {} {} {}\n",
                (3.0 + b.cos()) * a.cos(),
                (3.0 + b.cos()) * a.sin(),
                b.sin()
            ));
        }
    }
    let id = |i: u32, j: u32| (j % m) * n + i % n + 1;
    for j in 0..m {
        for i in 0..n {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if (i, j) == (0, 0) {
                obj.push_str(&format!(
                    "f {} {} {}\nf {} {} {}\n",
                    q[0], q[1], q[2], q[0], q[2], q[3]
                ));
            } else {
                obj.push_str(&format!("f {} {} {} {}\n", q[0], q[1], q[2], q[3]));
            }
        }
    }
    obj.push_str(&format!(
        "t interval 2/1/0 {} {} 3\n",
        id(0, 0) - 1,
        id(1, 0) - 1
    ));
    let dir = dir_with(&[("torus.obj", &obj)]);
    let o = run_in(dir.path(), &["limit", "torus.obj", "-o", "out.tsv"]);
    assert_code(&o, 1);
    let e = stderr(&o);
    assert!(
        e.contains("torus.obj: face 0: the non-uniform (NURSS) surface"),
        "{e}"
    );
    assert!(!dir.path().join("out.tsv").exists());
    // Catmull-Clark's surface of the same mesh is all there.
    let o = run_in(
        dir.path(),
        &[
            "limit",
            "torus.obj",
            "--scheme",
            "catmull-clark",
            "-o",
            "out.tsv",
        ],
    );
    assert_code(&o, 0);
}

/// `--c` samples the mixed (shape-adjustable) surface at the input's faces and
/// parameters, as `tessellate` and `render` do: the library's `MixedSurface`.
#[test]
fn c_samples_the_mixed_surface() {
    let dir = dir_with(&[("hut.obj", HUT)]);
    let o = run_in(
        dir.path(),
        &["limit", "hut.obj", "--grid", "3", "--c", "0.3", "-o", "-"],
    );
    assert_code(&o, 0);
    let out = rows(&stdout(&o));
    let (mesh, options) = mesh_of(HUT);
    let mixed = subsurf::MixedSurface::new(
        &mesh,
        options,
        subsurf::Mixed {
            scheme: subsurf::scheme::Adjustable::new(0.3).expect("c"),
            steps: 1,
        },
    )
    .expect("mixed");
    let cc = LimitSurface::new(&mesh, options).expect("surface");
    let mut at = 0;
    let mut differ = 0.0f64;
    for f in 0..mesh.num_faces() {
        let param = Parameterization::new(mesh.face(f).len());
        for sub in 0..param.num_subfaces() {
            for k in 0..9 {
                let (s, t) = ((k / 3) as f64 / 2.0, (k % 3) as f64 / 2.0);
                let p = SurfacePoint {
                    face: f as u32,
                    subface: sub as u32,
                    u: s,
                    v: t,
                };
                let d = mixed.eval_point(p).expect("mixed");
                let (_, x) = &out[at];
                assert!(close(&x[2..5], &d.p, 1e-12), "row {at}: {x:?} vs {:?}", d.p);
                differ = differ.max((x[2] - cc.eval_point(p).expect("cc").p[0]).abs());
                at += 1;
            }
        }
    }
    assert_eq!(out.len(), at);
    assert!(differ > 1e-3, "c = 0.3 gave Catmull-Clark's surface");
    let o = run_in(
        dir.path(),
        &[
            "limit", "hut.obj", "--c", "0.3", "--scheme", "nurss", "-o", "-",
        ],
    );
    assert_code(&o, 2);
}

/// OpenSubdiv's `catmark_fvar_bound1` (texture seams meeting at vertices of several values).
const FVAR_BOUND1: &str = include_str!("../../../subsurf/tests/shapes/osd/catmark_fvar_bound1.obj");

/// With texture coordinates every row ends with their limit `s t` (`osd-oracle limit`'s
/// layout), the library's `FaceVaryingSurface` in the `--fvar` mode (checked against
/// OpenSubdiv's `Bfr` by the library's `fvar_limit_golden` test); the modes differ.
#[test]
fn rows_end_with_the_limit_of_the_texture_coordinates() {
    use subsurf::limit::FaceVaryingSurface;
    use subsurf::mesh::FaceVaryingInterpolation;
    let dir = dir_with(&[("uv.obj", FVAR_BOUND1)]);
    let (mesh, options) = mesh_of(FVAR_BOUND1);
    let mut outputs = Vec::new();
    for mode in ["none", "corners-plus1", "all"] {
        let o = run_in(
            dir.path(),
            &[
                "limit", "uv.obj", "--grid", "3", "--fvar", mode, "-o", "out.tsv",
            ],
        );
        assert_code(&o, 0);
        let out = rows(&fs::read_to_string(dir.path().join("out.tsv")).expect("out.tsv"));
        let options = Options {
            face_varying: mode.parse::<FaceVaryingInterpolation>().expect("mode"),
            ..options
        };
        let uv = FaceVaryingSurface::new(&mesh, options, 0).expect("uv surface");
        assert_eq!(out.len(), 9 * mesh.num_faces(), "{mode}: one quad per face");
        for (face, x) in &out {
            assert_eq!(x.len(), 13, "{mode}: face {face}: s t at the end");
            let p = SurfacePoint {
                face: *face,
                subface: 0,
                u: x[0],
                v: x[1],
            };
            let st = uv.eval_point(p).expect("eval").value;
            assert!(
                close(&x[11..], &st, 1e-15),
                "{mode}: {face}: {:?} vs {st:?}",
                &x[11..]
            );
        }
        outputs.push(out);
    }
    assert!(
        outputs[0] != outputs[1] && outputs[1] != outputs[2],
        "the modes differ"
    );
}

/// The adjustable scheme at `c = ½` is Catmull-Clark: its rows, texture coordinates
/// included (evaluated on the refined mesh through the mapping of its points), are
/// Catmull-Clark's.
#[test]
fn adjustable_texture_coordinates_at_one_half_are_catmull_clarks() {
    let dir = dir_with(&[("uv.obj", FVAR_BOUND1)]);
    let run = |extra: &[&str], out: &str| {
        let mut args = vec![
            "limit", "uv.obj", "--grid", "3", "--fvar", "none", "-o", out,
        ];
        args.extend_from_slice(extra);
        assert_code(&run_in(dir.path(), &args), 0);
        rows(&fs::read_to_string(dir.path().join(out)).expect("out"))
    };
    let cc = run(&[], "cc.tsv");
    let adj = run(&["--c", "0.5", "--adjust-steps", "2"], "adj.tsv");
    assert_eq!(cc.len(), adj.len());
    for ((f, a), (g, b)) in cc.iter().zip(&adj) {
        assert_eq!(f, g);
        assert_eq!(b.len(), 13);
        assert!(close(&a[11..], &b[11..], 1e-12), "face {f}: {a:?} vs {b:?}");
    }
}

/// With NURSS the rows end with the texture coordinates' NURSS limit
/// (`FaceVaryingSurface::nurss`): with equal intervals (no knot tags, `--scheme nurss`)
/// Catmull-Clark's rows, `s t` included, in every mode.
#[test]
fn nurss_rows_end_with_texture_coordinates() {
    let dir = dir_with(&[("uv.obj", FVAR_BOUND1)]);
    let run = |extra: &[&str], out: &str| {
        let mut args = vec!["limit", "uv.obj", "--grid", "3", "-o", out];
        args.extend_from_slice(extra);
        let o = run_in(dir.path(), &args);
        assert_code(&o, 0);
        assert!(!stderr(&o).contains("texture"), "{}", stderr(&o));
        rows(&fs::read_to_string(dir.path().join(out)).expect("out"))
    };
    for mode in ["none", "corners-plus1", "all"] {
        let cc = run(&["--fvar", mode], "cc.tsv");
        let nurss = run(&["--fvar", mode, "--scheme", "nurss"], "nurss.tsv");
        assert_eq!(cc.len(), nurss.len());
        for ((f, a), (g, b)) in cc.iter().zip(&nurss) {
            assert_eq!((f, a.len(), b.len()), (g, 13, 13));
            assert!(close(a, b, 1e-12), "{mode}: face {f}: {a:?} vs {b:?}");
        }
    }
}

/// An 8 × 6 torus with unequal intervals in tensor-product layout (every face an exact NURSS
/// span) and texture coordinates `(i / 8, j / 6)` cut along the ring of column 0 (the faces
/// of the last column give it `s = 1`).
fn seam_torus() -> String {
    let (n, m) = (8u32, 6u32);
    let mut s = String::new();
    for j in 0..m {
        for i in 0..n {
            let (a, b) = (
                std::f64::consts::TAU * f64::from(i) / f64::from(n),
                std::f64::consts::TAU * f64::from(j) / f64::from(m),
            );
            let r = 2.0 + b.cos();
            s += &format!("v {} {} {}\n", r * a.cos(), r * a.sin(), b.sin());
        }
    }
    for j in 0..=m {
        for i in 0..=n {
            s += &format!(
                "vt {} {}\n",
                f64::from(i) / f64::from(n),
                f64::from(j) / f64::from(m)
            );
        }
    }
    let v = |i: u32, j: u32| (j % m) * n + i % n + 1;
    let t = |i: u32, j: u32| j * (n + 1) + i + 1;
    for j in 0..m {
        for i in 0..n {
            s += &format!(
                "f {}/{} {}/{} {}/{} {}/{}\n",
                v(i, j),
                t(i, j),
                v(i + 1, j),
                t(i + 1, j),
                v(i + 1, j + 1),
                t(i + 1, j + 1),
                v(i, j + 1),
                t(i, j + 1)
            );
        }
    }
    for j in 0..m {
        for i in 0..n {
            s += &format!(
                "t interval 2/1/0 {} {} {}\n",
                v(i, j) - 1,
                v(i + 1, j) - 1,
                1 + i % 3
            );
            s += &format!(
                "t interval 2/1/0 {} {} {}\n",
                v(i, j) - 1,
                v(i, j + 1) - 1,
                1 + j % 2
            );
        }
    }
    s
}

/// Where the texture coordinates' NURSS limit has no exact evaluation (next to a seam, with
/// unequal intervals) the command fails before writing, naming the face; the positions
/// alone are sampled (the file without `vt`).
#[test]
fn nurss_texture_coordinates_without_exact_evaluation_are_refused() {
    let torus = seam_torus();
    let no_uv: String = (torus.lines())
        .filter(|l| !l.starts_with("vt"))
        .map(|l| {
            let l = if l.starts_with("f ") {
                (l.split_whitespace())
                    .map(|w| w.split('/').next().unwrap_or(w))
                    .collect::<Vec<_>>()
                    .join(" ")
            } else {
                l.to_string()
            };
            l + "\n"
        })
        .collect();
    let dir = dir_with(&[("uv.obj", &torus), ("plain.obj", &no_uv)]);
    let args = [
        "limit", "uv.obj", "--grid", "2", "--fvar", "none", "-o", "out.tsv",
    ];
    let o = run_in(dir.path(), &args);
    assert_code(&o, 1);
    let err = stderr(&o);
    assert!(
        err.contains("uv.obj: texture coordinates: face 0: the surface has no exact evaluation"),
        "{err}"
    );
    assert!(!dir.path().join("out.tsv").exists());
    let o = run_in(
        dir.path(),
        &["limit", "plain.obj", "--grid", "2", "-o", "out.tsv"],
    );
    assert_code(&o, 0);
}

/// `osd-oracle refine catmark_fvar_bound1.obj 1 --limit --fvar none` (OpenSubdiv 3.5's
/// `PrimvarRefiner::LimitFaceVarying`): every ninth of its 97 `vt` values, by index, the
/// oracle's `%.17g` digits verbatim.
#[allow(clippy::excessive_precision)]
const ORACLE_LIMIT_VT: [(usize, [f64; 2]); 11] = [
    (0, [0.033333333333333333, 0.033333333333333333]),
    (9, [0.60000001788139334, 0.10833333656191826]),
    (18, [0.50000001490116119, 0.46666668057441718]),
    (27, [1.0, 0.80000000000000004]),
    (36, [0.70069444444444451, 0.074848090277777779]),
    (45, [0.87417534722222212, 0.69709201388888875]),
    (54, [0.29583333333333334, 0.0020833333333333333]),
    (63, [0.89999999999999991, 0.1980902777777778]),
    (72, [0.80000000000000004, 0.27934027777777781]),
    (81, [0.5, 0.58923611111111107]),
    (90, [0.44895834671333434, 0.83229169147089122]),
];

/// `subdivide --limit` moves the texture coordinates to their limit as OpenSubdiv's
/// `refine --limit` does (without `--limit` they are the refined values, which differ).
#[test]
fn subdivide_limit_moves_texture_coordinates_as_opensubdiv() {
    let dir = dir_with(&[("uv.obj", FVAR_BOUND1)]);
    let vt = |extra: &[&str], out: &str| -> Vec<[f64; 2]> {
        let mut args = vec![
            "subdivide",
            "uv.obj",
            "-l",
            "1",
            "--fvar",
            "none",
            "-o",
            out,
        ];
        args.extend_from_slice(extra);
        assert_code(&run_in(dir.path(), &args), 0);
        let text = fs::read_to_string(dir.path().join(out)).expect("out");
        (text.lines().filter_map(|l| l.strip_prefix("vt ")))
            .map(|l| {
                let x: Vec<f64> = l
                    .split_whitespace()
                    .map(|t| t.parse().expect("vt"))
                    .collect();
                [x[0], x[1]]
            })
            .collect()
    };
    let limit = vt(&["--limit"], "limit.obj");
    let refined = vt(&[], "refined.obj");
    assert_eq!(limit.len(), 97);
    for (i, st) in ORACLE_LIMIT_VT {
        assert!(
            close(&limit[i], &st, 1e-15),
            "vt {i}: {:?} vs {st:?}",
            limit[i]
        );
    }
    assert!(limit != refined, "--limit moved the values");
}

/// The rows of a golden file of the library's `tests/golden/bilinear_bfr/` (OpenSubdiv
/// `Bfr`'s, every face in `subsurf limit`'s layout; see the README there).
fn bilinear_golden(name: &str) -> Vec<(u32, Vec<f64>)> {
    use std::io::Read as _;
    let path = format!(
        "{}/../subsurf/tests/golden/bilinear_bfr/{name}.txt.gz",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut text = String::new();
    flate2::read::GzDecoder::new(fs::File::open(path).expect("golden file"))
        .read_to_string(&mut text)
        .expect("gzip");
    let data: String = (text.lines())
        .filter(|l| !l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect();
    rows(&data)
}

/// `limit --scheme bilinear --grid 4` writes OpenSubdiv `Bfr`'s rows: every face (quads,
/// and the sub-faces of triangles, pentagons and hexagons in `Bfr`'s `(u, v)` of the face),
/// positions, derivatives and texture coordinates to 1e-12, whatever the face-varying mode
/// (bilinear's is linear in all) and with boundary mode `none` (which leaves no bilinear face
/// out: `catmark_edgenone`'s tag).
#[test]
fn bilinear_rows_are_opensubdivs() {
    for (name, obj) in [
        (
            "bilinear_nonquads1",
            include_str!("../../../subsurf/tests/shapes/osd/bilinear_nonquads1.obj"),
        ),
        (
            "catmark_nonquads",
            include_str!("../../../subsurf/tests/shapes/osd/catmark_nonquads.obj"),
        ),
        (
            "catmark_edgenone",
            include_str!("../../../subsurf/tests/shapes/osd/catmark_edgenone.obj"),
        ),
    ] {
        let want = bilinear_golden(name);
        let dir = dir_with(&[("in.obj", obj)]);
        for fvar in ["all", "none"] {
            let o = run_in(
                dir.path(),
                &[
                    "limit", "in.obj", "--grid", "4", "--scheme", "bilinear", "--fvar", fvar, "-o",
                    "out.tsv",
                ],
            );
            assert_code(&o, 0);
            let got = rows(&fs::read_to_string(dir.path().join("out.tsv")).expect("out.tsv"));
            assert_eq!(got.len(), want.len(), "{name}");
            for (i, ((gf, g), (wf, w))) in got.iter().zip(&want).enumerate() {
                assert_eq!((gf, &g[..2]), (wf, &w[..2]), "{name} row {i}: face, u, v");
                assert_eq!(g.len(), 13, "{name} row {i}: s t at the end");
                assert!(
                    g.iter()
                        .zip(w)
                        .all(|(a, b)| (a - b).abs() <= 1e-12 * b.abs().max(1.0)),
                    "{name} {fvar} row {i}: {g:?} vs {w:?}"
                );
            }
        }
    }
}

/// `--c` belongs to the adjustable scheme: a usage error with `--scheme bilinear`.
#[test]
fn bilinear_refuses_c() {
    let dir = dir_with(&[("in.obj", NONQUADS)]);
    let o = run_in(
        dir.path(),
        &["limit", "in.obj", "--scheme", "bilinear", "--c", "0.3"],
    );
    assert_code(&o, 2);
    assert!(stderr(&o).contains("--c"), "{}", stderr(&o));
}
