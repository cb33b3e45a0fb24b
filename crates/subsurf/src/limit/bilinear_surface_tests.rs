//! Tests of [`BilinearSurface`]: closed forms at the corners of sub-faces, derivatives
//! against finite differences, the refined mesh's points on the surface, watertightness,
//! re-posing and errors.

use super::*;
use crate::geom;
use crate::limit::Parameterization;
use crate::mesh::Tags;
use crate::scheme::Scheme;
use crate::{subdivide, SubdivideOptions};

type V3 = [f64; 3];

fn dist(a: V3, b: V3) -> f64 {
    geom::norm(&geom::sub(&a, &b))
}

fn lerp(a: V3, b: V3, t: f64) -> V3 {
    std::array::from_fn(|k| (1.0 - t) * a[k] + t * b[k])
}

/// A non-planar mesh of a triangle, a quad, a pentagon and a hexagon sharing edges (a fan
/// around vertex 0), with a bump so that no patch is flat.
fn mixed() -> PolyMesh {
    let mut p: Vec<V3> = (0..12)
        .map(|i| {
            let a = i as f64 * 0.7;
            [
                a.cos() * (1.0 + 0.1 * i as f64),
                a.sin(),
                0.3 * (i as f64 * 1.3).sin(),
            ]
        })
        .collect();
    p[0] = [0.1, -0.2, 0.9];
    let faces: Vec<Vec<u32>> = vec![
        vec![0, 1, 2],
        vec![0, 2, 3, 4],
        vec![0, 4, 5, 6, 7],
        vec![0, 7, 8, 9, 10, 11],
    ];
    PolyMesh::from_faces(p, &faces).expect("mesh")
}

fn points(s: &BilinearSurface, f: usize) -> Vec<V3> {
    s.face(f).iter().map(|&v| s.pos[v as usize]).collect()
}

fn at(s: &BilinearSurface, face: usize, sub: usize, u: f64, v: f64) -> Derivatives {
    s.eval_point(SurfacePoint {
        face: face as u32,
        subface: sub as u32,
        u,
        v,
    })
    .expect("eval")
}

/// A quad is the bilinear patch of its corners, with the formula's derivatives.
#[test]
fn a_quad_is_its_bilinear_patch() {
    let s = BilinearSurface::new(&mixed()).expect("surface");
    let q = points(&s, 1);
    for (u, v) in [
        (0.0, 0.0),
        (0.3, 0.7),
        (1.0, 0.25),
        (0.9, 1.0),
        (1.0 / 3.0, 0.1),
    ] {
        let d = at(&s, 1, 0, u, v);
        let want = lerp(lerp(q[0], q[1], u), lerp(q[3], q[2], u), v);
        assert!(dist(d.p, want) < 1e-15, "({u}, {v})");
        let du = lerp(geom::sub(&q[1], &q[0]), geom::sub(&q[2], &q[3]), v);
        let dv = lerp(geom::sub(&q[3], &q[0]), geom::sub(&q[2], &q[1]), u);
        let twist: V3 = std::array::from_fn(|k| q[0][k] - q[1][k] + q[2][k] - q[3][k]);
        assert!(dist(d.du, du) < 1e-15 && dist(d.dv, dv) < 1e-15);
        assert!(dist(d.duv, twist) < 1e-15);
        assert_eq!((d.duu, d.dvv), ([0.0; 3], [0.0; 3]));
    }
}

/// On sub-face `j` of an `n`-gon the corners are vertex `j`, the midpoint of edge `j`, the
/// centroid and the midpoint of edge `j − 1`, and the sides are straight between them.
#[test]
fn subface_corners_are_vertex_midpoints_and_centroid() {
    let s = BilinearSurface::new(&mixed()).expect("surface");
    for f in [0, 2, 3] {
        let c = points(&s, f);
        let n = c.len();
        assert_eq!(s.num_subfaces(f), n);
        let centroid: V3 = std::array::from_fn(|k| c.iter().map(|p| p[k]).sum::<f64>() / n as f64);
        for j in 0..n {
            let next = lerp(c[j], c[(j + 1) % n], 0.5);
            let prev = lerp(c[(j + n - 1) % n], c[j], 0.5);
            let corners = [
                (0.0, 0.0, c[j]),
                (1.0, 0.0, next),
                (1.0, 1.0, centroid),
                (0.0, 1.0, prev),
            ];
            for (u, v, want) in corners {
                let got = at(&s, f, j, u, v).p;
                assert!(dist(got, want) < 1e-15, "face {f} sub {j} ({u}, {v})");
            }
            // Straight sides: the bilinear patch of the four corners.
            let (u, v) = (0.3, 0.8);
            let want = lerp(lerp(c[j], next, u), lerp(prev, centroid, u), v);
            assert!(dist(at(&s, f, j, u, v).p, want) < 1e-15);
        }
    }
}

/// First derivatives and the twist equal central differences of the positions (exact for a
/// bilinear patch up to rounding); the second derivatives along `u` and `v` are zero.
#[test]
fn derivatives_are_the_differences_of_positions() {
    let s = BilinearSurface::new(&mixed()).expect("surface");
    let h = 1e-3;
    for f in 0..s.num_faces() {
        for j in 0..s.num_subfaces(f) {
            for (u, v) in [(0.5, 0.5), (0.2, 0.9), (0.01, 0.99)] {
                let d = at(&s, f, j, u, v);
                let p = |du: f64, dv: f64| at(&s, f, j, u + du, v + dv).p;
                let fd_u: V3 = std::array::from_fn(|k| (p(h, 0.0)[k] - p(-h, 0.0)[k]) / (2.0 * h));
                let fd_v: V3 = std::array::from_fn(|k| (p(0.0, h)[k] - p(0.0, -h)[k]) / (2.0 * h));
                let fd_uv: V3 = std::array::from_fn(|k| {
                    (p(h, h)[k] - p(h, -h)[k] - p(-h, h)[k] + p(-h, -h)[k]) / (4.0 * h * h)
                });
                let what = format!("face {f} sub {j} ({u}, {v})");
                assert!(dist(d.du, fd_u) < 1e-10, "{what}: du");
                assert!(dist(d.dv, fd_v) < 1e-10, "{what}: dv");
                assert!(dist(d.duv, fd_uv) < 1e-7, "{what}: duv");
                assert_eq!((d.duu, d.dvv), ([0.0; 3], [0.0; 3]), "{what}");
            }
        }
    }
}

/// Every vertex of the mesh refined twice by bilinear subdivision lies on the surface at
/// its dyadic parameter: the surface's points at `(i/4, j/4)` of every quad and `(i/2, j/2)`
/// of every sub-face of another face and the refined vertices are the same set.
#[test]
fn the_refined_points_lie_on_the_surface() {
    let mesh = mixed();
    let s = BilinearSurface::new(&mesh).expect("surface");
    let opts = SubdivideOptions {
        levels: 2,
        scheme: Scheme::Bilinear,
        ..SubdivideOptions::default()
    };
    let refined = subdivide(&mesh, &opts).expect("refines").mesh;
    let mut samples = Vec::new();
    for f in 0..s.num_faces() {
        // A quad's second level is its 4 × 4 grid; an n-gon's first level is its sub-faces,
        // so its second is their 2 × 2 grids.
        let m = if s.num_subfaces(f) == 1 { 4 } else { 2 };
        for j in 0..s.num_subfaces(f) {
            for k in 0..(m + 1) * (m + 1) {
                let (u, v) = ((k / (m + 1)) as f64, (k % (m + 1)) as f64);
                samples.push(at(&s, f, j, u / m as f64, v / m as f64).p);
            }
        }
    }
    let near = |p: &V3, set: &[V3]| set.iter().any(|q| dist(*p, *q) < 1e-14);
    assert!(refined.positions().iter().all(|p| near(p, &samples)));
    assert!(samples.iter().all(|p| near(p, refined.positions())));
}

/// Neighbouring faces and sub-faces agree along their shared edges.
#[test]
fn watertight_along_shared_edges() {
    let s = BilinearSurface::new(&mixed()).expect("surface");
    let ts = [0.0, 0.125, 1.0 / 3.0, 0.7, 1.0];
    // Inside each n-gon: sub-face j's side u = 1 is sub-face j + 1's side v = 1, bit for bit.
    for f in [0, 2, 3] {
        let n = s.num_subfaces(f);
        for j in 0..n {
            for &t in &ts {
                assert_eq!(at(&s, f, j, 1.0, t).p, at(&s, f, (j + 1) % n, t, 1.0).p);
            }
        }
    }
    // Across faces: face f + 1's edge 0 runs from vertex 0 (the fan's centre) to the
    // vertex it shares with face f, whose last edge, n − 1, runs into vertex 0. At a
    // fraction t ≤ ½ from vertex 0 along it: on a quad (t, 0) and (0, t); on an n-gon,
    // sub-face 0 (whose u runs to the midpoint of edge 0, v to that of edge n − 1),
    // (2t, 0) and (0, 2t).
    let scale = |f: usize| if s.face(f).len() == 4 { 1.0 } else { 2.0 };
    for f in 0..3 {
        for &t in &[0.0, 0.1, 0.25, 0.4, 0.5] {
            let a = at(&s, f + 1, 0, scale(f + 1) * t, 0.0).p;
            let b = at(&s, f, 0, 0.0, scale(f) * t).p;
            assert!(
                dist(a, b) < 1e-15,
                "faces {f} and {}: t = {t}: {a:?} {b:?}",
                f + 1
            );
        }
    }
}

/// The weights on a face's corners sum to 1 for the position and to 0 for each derivative.
#[test]
fn corner_weights_are_a_partition_of_unity() {
    for n in [3, 4, 5, 6, 9] {
        for sub in 0..Parameterization::new(n).num_subfaces() {
            for (u, v) in [(0.0, 0.0), (0.3, 0.6), (1.0, 1.0)] {
                let mut sum = [0.0; 4];
                let mut seen = 0;
                corner_weights(n, sub, u, v, |c, w| {
                    assert_eq!(c, seen);
                    seen += 1;
                    (0..4).for_each(|k| sum[k] += w[k]);
                });
                assert_eq!(seen, n);
                assert!((sum[0] - 1.0).abs() < 1e-15, "{n} {sub}: {sum:?}");
                assert!(
                    sum[1..].iter().all(|x| x.abs() < 1e-15),
                    "{n} {sub}: {sum:?}"
                );
            }
        }
    }
}

/// Re-posing gives the surface of the moved mesh; bad points are refused naming the vertex.
#[test]
fn set_positions_reposes() {
    let mesh = mixed();
    let mut s = BilinearSurface::new(&mesh).expect("surface");
    let moved: Vec<V3> = (mesh.positions().iter())
        .map(|p| [2.0 * p[0] + p[2], p[1] - 1.0, p[2] * p[2]])
        .collect();
    let mut other = mesh.clone();
    other.positions_mut().copy_from_slice(&moved);
    let fresh = BilinearSurface::new(&other).expect("surface");
    s.set_positions(&moved).expect("valid");
    for f in 0..s.num_faces() {
        for j in 0..s.num_subfaces(f) {
            assert_eq!(at(&s, f, j, 0.3, 0.7), at(&fresh, f, j, 0.3, 0.7));
        }
    }
    assert_eq!(
        s.set_positions(&moved[1..]),
        Err(EvalError::InvalidPositions { vertex: 11 })
    );
    let mut bad = moved.clone();
    bad[5][1] = f64::INFINITY;
    assert_eq!(
        s.set_positions(&bad),
        Err(EvalError::InvalidPositions { vertex: 5 })
    );
    assert_eq!(s.positions(), &moved[..], "a refused pose changes nothing");
}

/// Errors in `LimitSurface`'s order: face, sub-face, parameter, hole; `eval_many` gives
/// each point its own result.
#[test]
fn errors_name_the_face_and_the_parameter() {
    let mut mesh = mixed();
    mesh.tags = Tags {
        holes: vec![2],
        ..Tags::default()
    };
    let s = BilinearSurface::new(&mesh).expect("surface");
    let p = |face: u32, subface: u32, u: f64, v: f64| SurfacePoint {
        face,
        subface,
        u,
        v,
    };
    let cases = [
        (
            p(4, 0, 0.5, 0.5),
            Err(EvalError::NoSuchFace { face: 4, count: 4 }),
        ),
        (
            p(1, 1, 0.5, 0.5),
            Err(EvalError::NoSuchSubface {
                face: 1,
                subface: 1,
                size: 1,
            }),
        ),
        (
            p(0, 3, 0.5, 0.5),
            Err(EvalError::NoSuchSubface {
                face: 0,
                subface: 3,
                size: 3,
            }),
        ),
        (
            p(0, 0, -0.1, 0.5),
            Err(EvalError::BadParameter { u: -0.1, v: 0.5 }),
        ),
        (
            p(3, 5, 0.5, 1.5),
            Err(EvalError::BadParameter { u: 0.5, v: 1.5 }),
        ),
        (p(2, 1, 0.5, 0.5), Err(EvalError::Hole { face: 2 })),
    ];
    let points: Vec<SurfacePoint> = cases.iter().map(|c| c.0).collect();
    let many = s.eval_many(&points, Order::First);
    for ((q, want), got) in cases.iter().zip(&many) {
        assert_eq!(&s.eval_point(*q), want);
        assert_eq!(got, want);
    }
    let nan = s.eval(0, f64::NAN, 0.5);
    assert!(
        matches!(nan, Err(EvalError::BadParameter { .. })),
        "{nan:?}"
    );
    assert!(!s.has_surface(2) && s.has_surface(3) && !s.has_surface(4));
    assert_eq!(
        (s.num_subfaces(0), s.num_subfaces(1), s.num_subfaces(4)),
        (3, 1, 0)
    );
    // Many points, in parallel, in order.
    let grid: Vec<SurfacePoint> = (0..s.num_faces() as u32)
        .flat_map(|f| (0..4000).map(move |k| p(f, 0, (k % 63) as f64 / 62.0, 0.25)))
        .collect();
    for (q, r) in grid.iter().zip(s.eval_many(&grid, Order::Second)) {
        assert_eq!(r, s.eval_point(*q));
    }
}

/// Non-manifold edges, a face with a repeated vertex and a boundary-only mesh evaluate to
/// finite points (a degenerate face has a degenerate patch) without an error.
#[test]
fn degenerate_and_non_manifold_faces_evaluate() {
    let p: Vec<V3> = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
    ];
    // Three faces on edge 0-1; a quad with vertex 2 twice.
    let faces: Vec<Vec<u32>> = vec![
        vec![0, 1, 2],
        vec![1, 0, 3],
        vec![0, 1, 4],
        vec![2, 5, 2, 4],
    ];
    let mesh = PolyMesh::from_faces(p, &faces).expect("mesh");
    let s = BilinearSurface::new(&mesh).expect("surface");
    for f in 0..s.num_faces() {
        for j in 0..s.num_subfaces(f) {
            for (u, v) in [(0.0, 0.0), (0.5, 0.5), (1.0, 1.0), (1.0, 0.0)] {
                let d = at(&s, f, j, u, v);
                assert!(d.p.iter().chain(&d.du).chain(&d.dv).all(|x| x.is_finite()));
            }
        }
    }
    // The degenerate quad [2 5 2 4]: its corners (0, 0) and (1, 1) are both vertex 2.
    assert_eq!(at(&s, 3, 0, 0.0, 0.0).p, [0.0, 1.0, 0.0]);
    assert_eq!(at(&s, 3, 0, 1.0, 1.0).p, [0.0, 1.0, 0.0]);
}
