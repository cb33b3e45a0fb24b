//! Tests of [`LoopSurface`]: against the limit of Loop refinement, the refined mesh's own
//! surface, affine invariance and watertightness.

use super::*;
use crate::limit::limit_points_with;
use crate::mesh::{BoundaryInterpolation, Crease};
use crate::refine::TopologyRefiner;
use crate::scheme::Scheme;
use crate::{subdivide, SubdivideOptions};

type V3 = [f64; 3];

fn dist(a: V3, b: V3) -> f64 {
    geom::norm(&geom::sub(&a, &b))
}

fn angle(a: V3, b: V3) -> f64 {
    geom::norm(&geom::cross(&a, &b)).atan2(geom::dot(&a, &b))
}

fn diagonal(m: &PolyMesh) -> f64 {
    m.bounding_box().map_or(1.0, |(lo, hi)| dist(hi, lo))
}

/// A shape of OpenSubdiv's regression suite with the options of its tags.
fn shape(name: &str) -> (PolyMesh, Options) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/shapes/osd")
        .join(format!("{name}.obj"));
    let obj = crate::io::read_obj(&path).expect("shape");
    let options = obj.options.resolve(Options::default());
    (obj.mesh, options)
}

/// Shapes with extraordinary vertices, boundaries of both modes, infinitely sharp and
/// semi-sharp creases (both decay rules), corners, valence 2 and non-manifold features.
const SHAPES: &[&str] = &[
    "loop_icosahedron",
    "loop_tetrahedron",
    "loop_cube",
    "loop_cube_asymmetric",
    "loop_triangle_edgecorner",
    "loop_triangle_edgeonly",
    "loop_saddle_edgecorner",
    "loop_saddle_edgeonly",
    "loop_xord_boundary",
    "loop_cube_creases0",
    "loop_cube_creases1",
    "loop_chaikin0",
    "loop_chaikin1",
    "loop_cubes_infsharp",
    "loop_icos_infsharp",
    "loop_val2_interior",
    "loop_nonman_edges",
    "loop_nonman_verts",
    "loop_fvar_bound0",
    "loop_pole8",
];

/// A torus of `n × m` quads, each cut into two triangles along the same diagonal: every
/// vertex has valence 6.
fn torus(n: u32, m: u32) -> PolyMesh {
    let id = |i: u32, j: u32| (i % n) * m + (j % m);
    let mut pos = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let (a, b) = (
                std::f64::consts::TAU * f64::from(i) / f64::from(n),
                std::f64::consts::TAU * f64::from(j) / f64::from(m),
            );
            let r = 2.0 + 0.7 * b.cos() + 0.1 * (3.0 * a).sin();
            pos.push([r * a.cos(), r * a.sin(), 0.7 * b.sin()]);
        }
    }
    let mut faces = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            faces.push([a, b, c]);
            faces.push([a, c, d]);
        }
    }
    PolyMesh::from_faces(pos, &faces).expect("torus")
}

/// The child of a triangle holding `(u, v)` (any, on shared edges) and the point there.
fn child_of(u: f64, v: f64) -> (usize, f64, f64) {
    if u + v <= 0.5 {
        (0, 2.0 * u, 2.0 * v)
    } else if u >= 0.5 {
        (1, 2.0 * u - 1.0, 2.0 * v)
    } else if v >= 0.5 {
        (2, 2.0 * u, 2.0 * v - 1.0)
    } else {
        (3, 1.0 - 2.0 * u, 1.0 - 2.0 * v)
    }
}

/// The vertex of level `levels` of `r` at the dyadic point `(u, v)` of base face `f`.
fn level_vertex(r: &TopologyRefiner, f: usize, (mut u, mut v): (f64, f64), levels: usize) -> usize {
    let mut face = f;
    for _ in 0..levels {
        let (j, s, t) = child_of(u, v);
        (face, u, v) = (4 * face + j, s, t);
    }
    let k = match (u, v) {
        (0.0, 0.0) => 0,
        (1.0, 0.0) => 1,
        (0.0, 1.0) => 2,
        _ => panic!("({u}, {v}) is not a corner at level {levels}"),
    };
    r.level(levels).face_vertices(face)[k] as usize
}

/// The points `(i/4, j/4)`, `i + j ≤ 4`.
fn quarter_grid() -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for i in 0..=4 {
        for j in 0..=4 - i {
            out.push((f64::from(i) / 4.0, f64::from(j) / 4.0));
        }
    }
    out
}

/// At the vertices of a refined level whose rule is final, Loop's limit masks are the exact
/// limit: the surface there equals them (positions to 1e-12 of the diagonal, normals to
/// 1e-8 rad), on every face of every shape, at every quarter point.
#[test]
fn equals_the_limit_masks_of_refinement() {
    const LEVELS: usize = 6;
    for name in SHAPES {
        let (mesh, options) = shape(name);
        let s = LoopSurface::new(&mesh, options).expect("surface");
        let mut r = TopologyRefiner::new(&mesh, Scheme::Loop, options).expect("refiner");
        r.refine_uniform(LEVELS as u32);
        let pts = r.interpolate_all(mesh.positions());
        let level = r.level(LEVELS);
        let n = level.num_vertices();
        let (mut lim, mut t1, mut t2) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
        limit_points_with(Loop, level, &pts, &mut lim, Some((&mut t1, &mut t2)));
        let diag = diagonal(&mesh);
        let (mut worst_p, mut worst_n) = (0.0f64, 0.0f64);
        for f in (0..mesh.num_faces()).filter(|&f| s.has_surface(f)) {
            for (u, v) in quarter_grid() {
                let x = level_vertex(&r, f, (u, v), LEVELS);
                let tag = level.vertex_tag(x);
                // Masks are exact where the rule no longer changes; a dart's are not.
                if tag.semi_sharp || tag.semi_sharp_edges || tag.rule == Rule::Dart {
                    continue;
                }
                let d = s.eval(f as u32, u, v).expect("eval");
                let e = dist(d.p, lim[x]) / diag;
                assert!(e < 1e-12, "{name}: face {f} ({u}, {v}): {e:e}");
                worst_p = worst_p.max(e);
                let smooth_interior =
                    tag.rule == Rule::Smooth && !tag.boundary && !tag.non_manifold;
                // `loop_val2_interior`'s two-triangle pillows collapse: no tangent plane.
                // Nor do faces with a repeated vertex (`loop_nonman_edges`).
                let pillow = *name == "loop_val2_interior";
                let fv = mesh.face(f);
                let degenerate = fv[0] == fv[1] || fv[1] == fv[2] || fv[2] == fv[0];
                if smooth_interior && level.vertex_faces(x).len() >= 3 && !pillow && !degenerate {
                    let (a, b) = (d.normal(), geom::unit_cross(&t1[x], &t2[x]));
                    let e = angle(a, b).min(angle(a, b.map(|c| -c)));
                    assert!(
                        e < 1e-8,
                        "{name}: face {f} ({u}, {v}): normal {e:e} rad {a:?} {b:?}"
                    );
                    assert!(
                        geom::norm(&a) > 0.5,
                        "{name}: face {f} ({u}, {v}): no normal {d:?}"
                    );
                    worst_n = worst_n.max(e);
                }
            }
        }
        eprintln!("{name}: positions {worst_p:.1e}, normals {worst_n:.1e} rad");
    }
}

/// The derivatives of a point of child `j` as the parent's (`(u, v) = φⱼ(s, t)`): halved,
/// doubled,
/// and negated through the middle child; second ones times 4.
fn to_parent(j: usize, d: Derivatives) -> Derivatives {
    d.scaled(if j == 3 { -2.0 } else { 2.0 })
}

/// `(u, v)` of the parent at `(s, t)` of child `j`.
fn parent_param(j: usize, s: f64, t: f64) -> (f64, f64) {
    match j {
        0 => (s / 2.0, t / 2.0),
        1 => ((s + 1.0) / 2.0, t / 2.0),
        2 => (s / 2.0, (t + 1.0) / 2.0),
        _ => ((1.0 - s) / 2.0, (1.0 - t) / 2.0),
    }
}

/// Interior points of a triangle, and points on its sides.
const POINTS: [(f64, f64); 7] = [
    (0.2, 0.3),
    (0.6, 0.1),
    (0.1, 0.7),
    (1.0 / 3.0, 1.0 / 3.0),
    (0.5, 0.0),
    (0.3, 0.7),
    (0.0, 0.45),
];

/// `a` and `b` agree: positions to `tol · diag`, first and second derivatives relative to
/// their size (floor `diag`).
fn assert_same(a: &Derivatives, b: &Derivatives, diag: f64, tol: f64, what: &str) {
    assert!(
        dist(a.p, b.p) < tol * diag,
        "{what}: position {:e}",
        dist(a.p, b.p) / diag
    );
    let pairs = [
        (a.du, b.du),
        (a.dv, b.dv),
        (a.duu, b.duu),
        (a.duv, b.duv),
        (a.dvv, b.dvv),
    ];
    for (k, (x, y)) in pairs.into_iter().enumerate() {
        let scale = geom::norm(&y).max(diag);
        assert!(
            dist(x, y) < 1e3 * tol * scale,
            "{what}: derivative {k} {:e}",
            dist(x, y) / scale
        );
    }
}

/// The surface of the refined mesh (its tags carry the sharpness left) on child `j` of a
/// face is the base surface on that quarter, derivatives included: on the regular torus,
/// where every face is one box-spline patch, this is the box spline's refinement relation
/// checked against Loop's rules as the project refines; on the shapes it checks the
/// recursion, the child numbering and the middle child's turned parameterisation.
#[test]
fn the_refined_mesh_has_the_same_surface() {
    let mut cases: Vec<(String, PolyMesh, Options)> =
        vec![("torus".into(), torus(6, 5), Options::default())];
    // Not `loop_val2_interior`: its level 1 read back as a mesh does not refine as level 1
    // does (its two-triangle pillows; `subdivide` of the output differs from two levels).
    for name in SHAPES
        .iter()
        .filter(|&&n| n != "loop_val2_interior" && n != "loop_nonman_edges")
    {
        let (m, o) = shape(name);
        cases.push((name.to_string(), m, o));
    }
    for (name, mesh, options) in cases {
        let s0 = LoopSurface::new(&mesh, options).expect("surface");
        if name == "torus" {
            assert!((0..mesh.num_faces()).all(|f| box_net(&s0.topo, f).is_some()));
        }
        let sub = SubdivideOptions {
            levels: 1,
            scheme: Scheme::Loop,
            options,
            keep_holes: true,
            ..SubdivideOptions::default()
        };
        let refined = subdivide(&mesh, &sub).expect("subdivide").mesh;
        let s1 = LoopSurface::new(&refined, options).expect("refined surface");
        let diag = diagonal(&mesh);
        for f in (0..mesh.num_faces()).filter(|&f| s0.has_surface(f)) {
            for j in 0..4 {
                for &(s, t) in &POINTS {
                    let child = s1.eval((4 * f + j) as u32, s, t).expect("child");
                    let (u, v) = parent_param(j, s, t);
                    let parent = s0.eval(f as u32, u, v).expect("parent");
                    let what = format!("{name}: face {f} child {j} ({s}, {t})");
                    assert_same(&to_parent(j, child), &parent, diag, 1e-12, &what);
                }
            }
        }
    }
}

/// An affine map of the control points maps the limit surface by the same map (positions)
/// and its derivatives by its linear part; a planar mesh stays in its plane.
#[test]
fn affine_invariance_and_planarity() {
    let a = [[1.2, 0.3, -0.4], [0.1, 0.9, 0.5], [-0.2, 0.4, 1.1]];
    let shift = [0.5, -2.0, 3.0];
    let apply = |p: &V3, b: f64| -> V3 {
        std::array::from_fn(|i| (0..3).map(|k| a[i][k] * p[k]).sum::<f64>() + b * shift[i])
    };
    for name in [
        "loop_xord_boundary",
        "loop_cube_creases1",
        "loop_chaikin0",
        "loop_nonman_verts",
    ] {
        let (mut mesh, options) = shape(name);
        let s = LoopSurface::new(&mesh, options).expect("surface");
        mesh.positions_mut()
            .iter_mut()
            .for_each(|p| *p = apply(p, 1.0));
        let t = LoopSurface::new(&mesh, options).expect("surface");
        let diag = diagonal(&mesh);
        let pts: Vec<SurfacePoint> = (0..mesh.num_faces() as u32)
            .filter(|&f| s.has_surface(f as usize))
            .flat_map(|f| {
                quarter_grid().into_iter().map(move |(u, v)| SurfacePoint {
                    face: f,
                    subface: 0,
                    u,
                    v,
                })
            })
            .collect();
        let (d0, d1) = (
            s.eval_many(&pts, Order::Second),
            t.eval_many(&pts, Order::Second),
        );
        for (p, (x, y)) in pts.iter().zip(d0.iter().zip(&d1)) {
            let (x, y) = (x.as_ref().expect("eval"), y.as_ref().expect("eval"));
            let want = Derivatives {
                p: apply(&x.p, 1.0),
                du: apply(&x.du, 0.0),
                dv: apply(&x.dv, 0.0),
                duu: apply(&x.duu, 0.0),
                duv: apply(&x.duv, 0.0),
                dvv: apply(&x.dvv, 0.0),
            };
            // At an irregular corner the tangents are not parametric derivatives (they are
            // chords projected onto the tangent plane): positions only.
            let corner = matches!((p.u, p.v), (0.0, 0.0) | (1.0, 0.0) | (0.0, 1.0));
            if corner {
                assert!(dist(y.p, want.p) < 1e-12 * diag, "{name}: {p:?}");
            } else {
                assert_same(y, &want, diag, 1e-12, &format!("{name}: {p:?}"));
            }
        }
    }
    // Planar: a triangulated square with a crease and a corner stays in z = 0.
    let (mut mesh, options) = shape("loop_saddle_edgecorner");
    mesh.positions_mut().iter_mut().for_each(|p| p[2] = 0.0);
    mesh.tags.creases.push(Crease {
        v0: mesh.face(0)[0],
        v1: mesh.face(0)[1],
        sharpness: 1.5,
    });
    let s = LoopSurface::new(&mesh, options).expect("surface");
    for f in 0..mesh.num_faces() as u32 {
        for (u, v) in quarter_grid() {
            let d = s.eval(f, u, v).expect("eval");
            assert!(d.p[2].abs() < 1e-15 && d.du[2].abs() < 1e-14 && d.dv[2].abs() < 1e-14);
        }
    }
}

/// Two faces sharing an edge agree along it: positions to 1e-12 of the diagonal and, where
/// the edge is smooth, the normals to 1e-8 rad.
#[test]
fn watertight_along_shared_edges() {
    let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)];
    for name in SHAPES {
        let (mesh, options) = shape(name);
        let s = LoopSurface::new(&mesh, options).expect("surface");
        let t = &s.topo;
        let diag = diagonal(&mesh);
        for e in 0..t.num_edges() {
            let faces = t.edge_face_list(e);
            if faces.len() != 2 || faces.iter().any(|&f| !s.has_surface(f as usize)) {
                continue;
            }
            let [a, _] = t.edge_vertices(e);
            // The faces of a two-triangle pillow face opposite ways: their normals too.
            let pillow = faces[0] != faces[1] && {
                let mut a = t.face_vertices(faces[0] as usize).to_vec();
                let mut b = t.face_vertices(faces[1] as usize).to_vec();
                a.sort_unstable();
                b.sort_unstable();
                a == b
            };
            let smooth = t.edge_sharpness(e) == 0.0 && !pillow;
            for x in [0.2, 0.5, 0.85] {
                let mut seen: Vec<Derivatives> = Vec::new();
                for &f in faces {
                    let fe = t.face_edge_list(f as usize);
                    let Some(j) = fe.iter().position(|&g| g as usize == e) else {
                        continue;
                    };
                    // Parameter `x` from the edge's first vertex.
                    let from_a = t.face_vertices(f as usize)[j] == a;
                    let w = if from_a { x } else { 1.0 - x };
                    let (p, q) = (corners[j], corners[(j + 1) % 3]);
                    let (u, v) = (p.0 + w * (q.0 - p.0), p.1 + w * (q.1 - p.1));
                    seen.push(s.eval(f, u, v).expect("eval"));
                }
                if let [d0, d1] = seen.as_slice() {
                    let what = format!("{name}: edge {e} at {x}");
                    assert!(dist(d0.p, d1.p) < 1e-12 * diag, "{what}: positions");
                    if smooth {
                        let ang = angle(d0.normal(), d1.normal());
                        assert!(ang < 1e-8, "{what}: normals {ang:e} rad");
                    }
                }
            }
        }
    }
}

#[test]
fn errors_name_the_face_and_the_parameter() {
    let (mesh, options) = shape("loop_icosahedron");
    let s = LoopSurface::new(&mesh, options).expect("surface");
    for (u, v) in [(0.7, 0.4), (-0.1, 0.4), (f64::NAN, 0.4)] {
        let e = s.eval(0, u, v).unwrap_err();
        assert!(matches!(e, EvalError::OutsideTriangle { .. }), "{e}");
        assert!(e.to_string().contains("u + v ≤ 1"), "{e}");
    }
    assert!(s.eval(0, 0.5, 0.5).is_ok());
    let n = mesh.num_faces() as u32;
    assert!(matches!(
        s.eval(n, 0.1, 0.1),
        Err(EvalError::NoSuchFace { .. })
    ));
    let p = SurfacePoint {
        face: 0,
        subface: 1,
        u: 0.1,
        v: 0.1,
    };
    assert!(matches!(
        s.eval_point(p),
        Err(EvalError::NoSuchSubface { .. })
    ));
    let quad = PolyMesh::from_faces(
        vec![
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0, 0.0, 0.0],
        ],
        &[vec![1u32, 4, 2], vec![0, 1, 2, 3]],
    )
    .expect("mesh");
    let e = LoopSurface::new(&quad, Options::default()).unwrap_err();
    assert_eq!(e, MeshError::NotTriangle { face: 1, count: 4 });
    // Boundary interpolation `none`: the faces at the boundary have no surface.
    let (mesh, _) = shape("loop_triangle_edgenone");
    let o = Options {
        boundary: BoundaryInterpolation::None,
        ..Options::default()
    };
    let s = LoopSurface::new(&mesh, o).expect("surface");
    let hole = (0..mesh.num_faces())
        .find(|&f| !s.has_surface(f))
        .expect("a hole");
    assert!(matches!(
        s.eval(hole as u32, 0.2, 0.2),
        Err(EvalError::Hole { .. })
    ));
}
