//! `NurssSurface`: the exact non-uniform (NURSS) limit surface with derivatives, against
//! independent references: de Boor's algorithm on the bicubic B-spline (and NURBS) surface a
//! control mesh with knot intervals stands for (`nurbs::mesh`), the limit points of NURSS
//! refinement itself (`nurss::tessellate`), Catmull-Clark's `LimitSurface` where the
//! intervals are equal; and the refusal, naming the face, where there is no closed form.

use subsurf::limit::{LimitSurface, Order, SurfacePoint};
use subsurf::mesh::{EdgeInterval, Options, PolyMesh, VertexWeight};
use subsurf::nonuniform::{NurssEvalError, NurssSurface};
use subsurf::nurbs::{BSplineSurface, KnotVector, NurbsSurface};

type V3 = [f64; 3];

fn dist(a: V3, b: V3) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn norm(a: V3) -> f64 {
    dist(a, [0.0; 3])
}

/// A periodic bicubic B-spline surface (a wavy torus) with non-uniform knots in both
/// directions, and the weights `w` per control point for its rational version.
fn torus_spline(nu: usize, nv: usize) -> (BSplineSurface<3>, Vec<f64>) {
    let du: Vec<f64> = (0..nu).map(|i| 1.0 + 0.6 * ((i * 7) % 5) as f64).collect();
    let dv: Vec<f64> = (0..nv).map(|j| 0.5 + 0.5 * ((j * 3) % 4) as f64).collect();
    let ku = KnotVector::periodic_from_intervals(3, &du).expect("knots");
    let kv = KnotVector::periodic_from_intervals(3, &dv).expect("knots");
    let mut points = Vec::new();
    let mut weights = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let (a, b) = (
                std::f64::consts::TAU * i as f64 / nu as f64,
                std::f64::consts::TAU * j as f64 / nv as f64,
            );
            let r = 3.0 + (1.0 + 0.2 * (3.0 * a).sin()) * b.cos();
            points.push([r * a.cos(), r * a.sin(), b.sin() + 0.1 * (2.0 * a).cos()]);
            weights.push(1.0 + 0.5 * ((i + 2 * j) % 3) as f64);
        }
    }
    (
        BSplineSurface::new(ku, kv, points).expect("surface"),
        weights,
    )
}

/// The spline's point and derivatives by the face's `(u, v)` at `(u, v)` of face `f` of its
/// control mesh (parameter rectangle `r`).
fn spline_at(s: &NurbsSurface, r: [f64; 4], u: f64, v: f64) -> (V3, V3, V3) {
    let (a, b) = (r[1] - r[0], r[3] - r[2]);
    let d = s
        .eval_derivs(r[0] + u * a, r[2] + v * b, 1)
        .expect("inside the domain");
    (d[0][0], d[1][0].map(|x| a * x), d[0][1].map(|x| b * x))
}

const PARAMS: [f64; 5] = [0.0, 0.25, 0.5, 0.8, 1.0];

/// On a closed mesh of a non-uniform bicubic B-spline (every vertex regular, tensor-product
/// intervals), every face is that spline: positions and first derivatives by the face's
/// `(u, v)` (the span's length times those by the knot) to 1e-12, plain and rational (with
/// weight tags: the NURBS surface of the homogeneous points).
#[test]
fn regular_faces_are_the_bspline_and_nurbs_spans() {
    let (spline, weights) = torus_spline(7, 6);
    let cm = spline.control_mesh().expect("control mesh");
    for rational in [false, true] {
        let mut mesh = cm.mesh_with_knots();
        let reference = if rational {
            mesh.knots.weights = (0..weights.len())
                .map(|v| VertexWeight {
                    vertex: v as u32,
                    weight: weights[v],
                })
                .collect();
            let h: Vec<[f64; 4]> = (spline.points().iter().zip(&weights))
                .map(|(p, &w)| [w * p[0], w * p[1], w * p[2], w])
                .collect();
            let hs = BSplineSurface::new(spline.knots_u().clone(), spline.knots_v().clone(), h)
                .expect("homogeneous");
            NurbsSurface::from_homogeneous(hs).expect("nurbs")
        } else {
            let h: Vec<[f64; 4]> = (spline.points().iter())
                .map(|p| [p[0], p[1], p[2], 1.0])
                .collect();
            let hs = BSplineSurface::new(spline.knots_u().clone(), spline.knots_v().clone(), h)
                .expect("homogeneous");
            NurbsSurface::from_homogeneous(hs).expect("nurbs")
        };
        let s = NurssSurface::new(&mesh, &Options::default()).expect("surface");
        assert!(s.limit_surface().is_none(), "every face is a patch");
        for (f, &r) in cm.face_params.iter().enumerate() {
            for &u in &PARAMS {
                for &v in &PARAMS {
                    let p = SurfacePoint {
                        face: f as u32,
                        subface: 0,
                        u,
                        v,
                    };
                    let d = s.eval_point_order(p, Order::First).expect("exact");
                    let (x, xu, xv) = spline_at(&reference, r, u, v);
                    let what = format!("rational {rational}, face {f} at ({u}, {v})");
                    assert!(dist(d.p, x) < 1e-12 * norm(x), "{what}: {:?} vs {x:?}", d.p);
                    assert!(dist(d.du, xu) < 1e-11 * norm(xu).max(1.0), "{what}: du");
                    assert!(dist(d.dv, xv) < 1e-11 * norm(xv).max(1.0), "{what}: dv");
                }
            }
        }
    }
}

/// The same surface is the limit of NURSS refinement itself: the limit points of its
/// vertices after two steps (`nurss::tessellate` at rate 4, an independent computation
/// from the NURSS rules), rational too, are the surface's points at `(i/4, j/4)` of every
/// face.
#[test]
fn regular_faces_are_the_limit_of_nurss_refinement() {
    let (spline, weights) = torus_spline(6, 5);
    let cm = spline.control_mesh().expect("control mesh");
    for rational in [false, true] {
        let mut mesh = cm.mesh_with_knots();
        if rational {
            mesh.knots.weights = (0..weights.len())
                .map(|v| VertexWeight {
                    vertex: v as u32,
                    weight: weights[v],
                })
                .collect();
        }
        let o = Options::default();
        let t = subsurf::nonuniform::tessellate(&mesh, &o, 4, false).expect("refinement");
        let s = NurssSurface::new(&mesh, &o).expect("surface");
        for f in 0..mesh.num_faces() {
            for i in 0..=4 {
                for j in 0..=4 {
                    let (u, v) = (f64::from(i) / 4.0, f64::from(j) / 4.0);
                    let p = SurfacePoint {
                        face: f as u32,
                        subface: 0,
                        u,
                        v,
                    };
                    let x = s.eval_point(p).expect("exact").p;
                    let nearest = (t.positions.iter())
                        .map(|&q| dist(q, x))
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        nearest < 1e-11 * norm(x),
                        "rational {rational}, face {f} at ({u}, {v}): {nearest:e} from refinement"
                    );
                }
            }
        }
    }
}

/// A cube (every vertex extraordinary) with a pyramid of triangles on top, every edge of
/// interval 2: with equal intervals everywhere the NURSS surface is Catmull-Clark's,
/// evaluated exactly anywhere (`LimitSurface`, bit for bit), triangles and extraordinary
/// vertices included.
#[test]
fn equal_intervals_give_catmull_clarks_surface() {
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
        [0.5, 0.5, 1.5],
    ];
    let faces: Vec<Vec<u32>> = vec![
        vec![0, 3, 2, 1],
        vec![0, 1, 5, 4],
        vec![1, 2, 6, 5],
        vec![2, 3, 7, 6],
        vec![3, 0, 4, 7],
        vec![4, 5, 8],
        vec![5, 6, 8],
        vec![6, 7, 8],
        vec![7, 4, 8],
    ];
    let mut mesh = PolyMesh::from_faces(p, &faces).expect("mesh");
    for f in &faces {
        for k in 0..f.len() {
            let (v0, v1) = (f[k], f[(k + 1) % f.len()]);
            if v0 < v1 {
                mesh.knots.intervals.push(EdgeInterval {
                    v0,
                    v1,
                    interval: 2.0,
                });
            }
        }
    }
    let o = Options::default();
    let s = NurssSurface::new(&mesh, &o).expect("surface");
    let cc = LimitSurface::new(&mesh, o).expect("surface");
    for f in 0..mesh.num_faces() {
        for sub in 0..cc.num_subfaces(f) {
            for &u in &PARAMS {
                for &v in &PARAMS {
                    let p = SurfacePoint {
                        face: f as u32,
                        subface: sub as u32,
                        u,
                        v,
                    };
                    assert_eq!(s.eval_point(p), Ok(cc.eval_point(p).expect("cc")), "{p:?}");
                }
            }
        }
    }
}

/// Where neither holds (an extraordinary vertex with unequal intervals around it) the
/// surface has no closed form: an error naming the face and why, never other numbers; the
/// faces away from it keep their exact evaluation.
#[test]
fn other_faces_are_refused_naming_the_face() {
    // An 8 × 8 torus of quads, one of them split into two triangles (two vertices of
    // valence 5).
    let (n, m) = (8u32, 8u32);
    let id = |i: u32, j: u32| (j % m) * n + i % n;
    let mut p = Vec::new();
    for j in 0..m {
        for i in 0..n {
            let (a, b) = (
                std::f64::consts::TAU * f64::from(i) / f64::from(n),
                std::f64::consts::TAU * f64::from(j) / f64::from(m),
            );
            p.push([
                (3.0 + b.cos()) * a.cos(),
                (3.0 + b.cos()) * a.sin(),
                b.sin(),
            ]);
        }
    }
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for j in 0..m {
        for i in 0..n {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if (i, j) == (0, 0) {
                faces.push(vec![q[0], q[1], q[2]]);
                faces.push(vec![q[0], q[2], q[3]]);
            } else {
                faces.push(q.to_vec());
            }
        }
    }
    let mut mesh = PolyMesh::from_faces(p, &faces).expect("torus");
    // Interval 3 on one ring of edges through the triangles' corner.
    for j in 0..m {
        mesh.knots.intervals.push(EdgeInterval {
            v0: id(0, j),
            v1: id(1, j),
            interval: 3.0,
        });
    }
    let s = NurssSurface::new(&mesh, &Options::default()).expect("surface");
    let at = |f: usize| SurfacePoint {
        face: f as u32,
        subface: 0,
        u: 0.5,
        v: 0.5,
    };
    // The two triangles (faces 0 and 1) and the quads around their corners are refused.
    for f in [0, 1, 2] {
        match s.eval_point(at(f)) {
            Err(NurssEvalError::NotExact { face, reason }) => {
                assert_eq!(face, f as u32);
                assert!(!reason.is_empty());
                let msg = s.eval_point(at(f)).unwrap_err().to_string();
                assert!(msg.starts_with(&format!("face {f}: ")), "{msg}");
            }
            other => panic!("face {f}: {other:?}"),
        }
        assert!(s.check_face(f).is_err(), "face {f}");
    }
    // Far from them, the torus is a regular tensor-product grid.
    let far = faces.len() / 2 + 3;
    assert!(s.eval_point(at(far)).is_ok(), "face {far}");
    assert!(s.check_face(far).is_ok());
}
