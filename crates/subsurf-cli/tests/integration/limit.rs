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

/// The rows of a `limit` output: `face`, then the eleven numbers.
fn rows(text: &str) -> Vec<(u32, Vec<f64>)> {
    text.lines()
        .map(|l| {
            let mut w = l.split_whitespace();
            let face = w.next().and_then(|x| x.parse().ok()).expect("face");
            let x: Vec<f64> = w.map(|t| t.parse().expect("number")).collect();
            assert_eq!(x.len(), 11, "{l}");
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
